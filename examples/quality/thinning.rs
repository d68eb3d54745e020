//! The thinning baseline of the quality benchmark (not part of the product): Zhang-Suen thinning of
//! the foreground, then the pixel-graph extraction thinning tools use (skan, OpenCV-based
//! pipelines): skeleton pixels with more than two skeleton neighbours are junction pixels, clustered
//! 8-connected into one vertex each; pixels with one neighbour are ends; the pixel paths between
//! them are edges; skeleton cycles without any junction become loops. Coordinates are pixel centers.
//!
//! [`trace_pruned`] adds the pruning a careful user of thinning adds: terminal branches (a
//! junction to an end) shorter than the local stroke width removed, the same rule as ridgeline's
//! own cleanup (docs/design.md, adaptation 10), in one pass.

use ridgeline::geometry::tangents;
use ridgeline::{Binary, Edge, StrokeGraph};

/// Zhang-Suen thinning followed by pixel-graph extraction (the library's, [`ridgeline::thin`],
/// whose skeleton the default skeleton-carried tracing builds on). An empty graph for a mask that
/// is not `width x height` pixels (the test kit's never are).
pub fn trace(binary: &Binary) -> StrokeGraph {
    ridgeline::thin(binary).unwrap_or_default()
}

/// [`trace`], then terminal branches shorter than the stroke width at their junction removed
/// ([`prune`]).
pub fn trace_pruned(binary: &Binary) -> StrokeGraph {
    prune(trace(binary))
}

/// Removes every edge from a junction (degree 3 or more) to an end (degree 1) that is shorter than
/// the junction's stroke width, with its end, in one pass, then joins the two edges left at each
/// vertex of degree 2. A junction whose every branch goes stays as a dot.
pub fn prune(mut graph: StrokeGraph) -> StrokeGraph {
    let mut alive = vec![true; graph.vertices.len()];
    let degree = degrees(&graph);
    let vertices = &graph.vertices;
    graph.edges.retain(|e| {
        let (junction, end) = match (degree[e.from], degree[e.to]) {
            (1, d) if d >= 3 => (e.to, e.from),
            (d, 1) if d >= 3 => (e.from, e.to),
            _ => return true,
        };
        if e.length() >= vertices[junction].width {
            return true;
        }
        alive[end] = false;
        false
    });
    dissolve(&mut graph, &mut alive);
    // Drop the vertices removed or joined away, renumbering the edges' ends.
    let mut index = vec![usize::MAX; graph.vertices.len()];
    let mut kept = Vec::new();
    for (v, vertex) in graph.vertices.iter().enumerate() {
        if alive[v] {
            index[v] = kept.len();
            kept.push(vertex.clone());
        }
    }
    for e in &mut graph.edges {
        e.from = index[e.from];
        e.to = index[e.to];
    }
    graph.vertices = kept;
    let degree = degrees(&graph);
    for (v, vertex) in graph.vertices.iter_mut().enumerate() {
        vertex.degree = degree[v];
    }
    graph
}

fn degrees(graph: &StrokeGraph) -> Vec<usize> {
    let mut degree = vec![0; graph.vertices.len()];
    for e in &graph.edges {
        degree[e.from] += 1;
        degree[e.to] += 1;
    }
    degree
}

/// Joins the two edges at every live vertex with exactly two edge ends from two different edges
/// into one, marking the vertex dead.
fn dissolve(graph: &mut StrokeGraph, alive: &mut [bool]) {
    loop {
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); graph.vertices.len()];
        for (i, e) in graph.edges.iter().enumerate() {
            incident[e.from].push(i);
            incident[e.to].push(i);
        }
        let Some(v) = (0..graph.vertices.len())
            .find(|&v| alive[v] && incident[v].len() == 2 && incident[v][0] != incident[v][1])
        else {
            return;
        };
        let (a, b) = (incident[v][0], incident[v][1]);
        let mut second = graph.edges[b].clone();
        let first = &mut graph.edges[a];
        if first.to != v {
            reverse(first);
        }
        if second.from != v {
            reverse(&mut second);
        }
        first.points.extend_from_slice(&second.points[1..]);
        first.widths.extend_from_slice(&second.widths[1..]);
        first.to = second.to;
        first.directions = tangents(&first.points);
        graph.edges.remove(b);
        alive[v] = false;
    }
}

fn reverse(e: &mut Edge) {
    std::mem::swap(&mut e.from, &mut e.to);
    e.points.reverse();
    e.widths.reverse();
    e.directions = tangents(&e.points);
}

/// Euclidean distance from each pixel center to the nearest background pixel center (outside the
/// image counts as background): Felzenszwalb & Huttenlocher's separable squared transform.
pub fn distance_to_background(binary: &Binary) -> Vec<f64> {
    let (w, h) = (binary.width as usize, binary.height as usize);
    // Distances to the border (the background beyond the image) bound everything from the start.
    let mut d2: Vec<f64> = (0..w * h)
        .map(|i| {
            if !binary.ink[i] {
                return 0.0;
            }
            let (x, y) = (i % w, i / w);
            let edge = (x + 1).min(w - x).min(y + 1).min(h - y) as f64;
            edge * edge
        })
        .collect();
    let mut line = Vec::new();
    let mut out = Vec::new();
    for x in 0..w {
        line.clear();
        line.extend((0..h).map(|y| d2[y * w + x]));
        lower_envelope(&line, &mut out);
        for y in 0..h {
            d2[y * w + x] = out[y];
        }
    }
    for y in 0..h {
        line.clear();
        line.extend_from_slice(&d2[y * w..(y + 1) * w]);
        lower_envelope(&line, &mut out);
        d2[y * w..(y + 1) * w].copy_from_slice(&out);
    }
    d2.into_iter().map(f64::sqrt).collect()
}

/// One dimension of the squared distance transform: `out[q] = min_p f[p] + (q - p)^2`.
fn lower_envelope(f: &[f64], out: &mut Vec<f64>) {
    let n = f.len();
    out.clear();
    out.resize(n, 0.0);
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    let mut k = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let parabola_cut = |q: usize, p: usize| {
        ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * q as f64 - 2.0 * p as f64)
    };
    for q in 1..n {
        let mut s = parabola_cut(q, v[k]);
        while s <= z[k] {
            k -= 1;
            s = parabola_cut(q, v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let d = q as f64 - v[k] as f64;
        *o = d * d + f[v[k]];
    }
}
