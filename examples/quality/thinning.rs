//! The thinning baseline of the quality benchmark (not part of the product): Zhang-Suen thinning of
//! the foreground, then the pixel-graph extraction thinning tools use (skan, OpenCV-based
//! pipelines): skeleton pixels with more than two skeleton neighbours are junction pixels, clustered
//! 8-connected into one vertex each; pixels with one neighbour are ends; the pixel paths between
//! them are edges; skeleton cycles without any junction become loops. Coordinates are pixel centers.
//!
//! [`trace_pruned`] adds the pruning a careful user of thinning adds: terminal branches (a
//! junction to an end) shorter than the local stroke width removed, the same rule as ridgeline's
//! own cleanup (DESIGN.md change 8), in one pass.

use ridgeline::{Binary, Edge, StrokeGraph, Vertex};

/// Zhang-Suen thinning followed by pixel-graph extraction.
pub fn trace(binary: &Binary) -> StrokeGraph {
    let skeleton = zhang_suen(binary);
    let half_width = distance_to_background(binary);
    pixel_graph(binary.width, binary.height, &skeleton, &half_width)
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

/// Offsets of the 8 neighbours in the order P2..P9 of Zhang and Suen (N, NE, E, SE, S, SW, W, NW).
const RING: [(i64, i64); 8] = [
    (0, -1),
    (1, -1),
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
];

/// Zhang & Suen (1984), "A fast parallel algorithm for thinning digital patterns": two
/// sub-iterations, each deleting in parallel the boundary pixels with 2-6 neighbours, one 0->1
/// transition around them, and (south-east | north-west) boundary conditions, until stable.
fn zhang_suen(binary: &Binary) -> Vec<bool> {
    let (w, h) = (binary.width as i64, binary.height as i64);
    let mut ink = binary.ink.clone();
    let mut alive: Vec<usize> = (0..ink.len()).filter(|&i| ink[i]).collect();
    let get = |ink: &[bool], x: i64, y: i64| {
        x >= 0 && y >= 0 && x < w && y < h && ink[(y * w + x) as usize]
    };
    let mut marked = Vec::new();
    loop {
        let mut changed = false;
        for step in 0..2 {
            marked.clear();
            for &i in &alive {
                let (x, y) = ((i as i64) % w, (i as i64) / w);
                let p: [bool; 8] = std::array::from_fn(|k| get(&ink, x + RING[k].0, y + RING[k].1));
                let b = p.iter().filter(|&&v| v).count();
                if !(2..=6).contains(&b) {
                    continue;
                }
                let a = (0..8).filter(|&k| !p[k] && p[(k + 1) % 8]).count();
                if a != 1 {
                    continue;
                }
                // p[0] = P2 (N), p[2] = P4 (E), p[4] = P6 (S), p[6] = P8 (W). The first pass
                // deletes unless P2.P4.P6 or P4.P6.P8 is set, the second unless P2.P4.P8 or P2.P6.P8.
                let keep = if step == 0 {
                    p[2] && p[4] && (p[0] || p[6])
                } else {
                    p[0] && p[6] && (p[2] || p[4])
                };
                if !keep {
                    marked.push(i);
                }
            }
            for &i in &marked {
                ink[i] = false;
            }
            changed |= !marked.is_empty();
            alive.retain(|&i| ink[i]);
        }
        if !changed {
            return ink;
        }
    }
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

/// The graph of a one-pixel skeleton.
fn pixel_graph(width: u32, height: u32, skeleton: &[bool], half_width: &[f64]) -> StrokeGraph {
    let (w, h) = (width as i64, height as i64);
    let on = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && skeleton[(y * w + x) as usize];
    let neighbours = |i: usize| {
        let (x, y) = ((i as i64) % w, (i as i64) / w);
        RING.iter()
            .filter(move |&&(dx, dy)| on(x + dx, y + dy))
            .map(move |&(dx, dy)| ((y + dy) * w + x + dx) as usize)
    };
    let center = |i: usize| [(i as i64 % w) as f64 + 0.5, (i as i64 / w) as f64 + 0.5];
    // Stroke width at a pixel: 2 x distance to the background, less the pixel itself.
    let width_at = |p: [f64; 2]| {
        let (x, y) = (
            (p[0].floor() as i64).clamp(0, w - 1),
            (p[1].floor() as i64).clamp(0, h - 1),
        );
        (2.0 * half_width[(y * w + x) as usize] - 1.0).max(1.0)
    };
    let count: Vec<usize> = (0..skeleton.len())
        .map(|i| {
            if skeleton[i] {
                neighbours(i).count()
            } else {
                0
            }
        })
        .collect();

    // Vertices: junction clusters, ends, isolated pixels.
    const NONE: usize = usize::MAX;
    let mut vertex_of = vec![NONE; skeleton.len()];
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut stack = Vec::new();
    for i in (0..skeleton.len()).filter(|&i| skeleton[i]) {
        if vertex_of[i] != NONE || count[i] == 2 {
            continue;
        }
        let id = vertices.len();
        let mut sum = [0.0, 0.0];
        let mut members = 0.0;
        if count[i] > 2 {
            stack.push(i);
            vertex_of[i] = id;
            while let Some(j) = stack.pop() {
                let c = center(j);
                sum = [sum[0] + c[0], sum[1] + c[1]];
                members += 1.0;
                for k in neighbours(j) {
                    if count[k] > 2 && vertex_of[k] == NONE {
                        vertex_of[k] = id;
                        stack.push(k);
                    }
                }
            }
        } else {
            vertex_of[i] = id;
            sum = center(i);
            members = 1.0;
        }
        let pos = [sum[0] / members, sum[1] / members];
        vertices.push(Vertex {
            pos,
            degree: 0,
            width: width_at(pos),
        });
    }

    // Edges: walk from every vertex pixel along pixels with two neighbours.
    let mut edges: Vec<Edge> = Vec::new();
    let mut visited = vec![false; skeleton.len()];
    let make_edge = |from: usize, to: usize, points: Vec<[f64; 2]>, edges: &mut Vec<Edge>| {
        let widths = points.iter().map(|&p| width_at(p)).collect();
        let directions = tangents(&points);
        edges.push(Edge {
            from,
            to,
            points,
            widths,
            directions,
        });
    };
    for a in (0..skeleton.len()).filter(|&i| skeleton[i] && vertex_of[i] != NONE) {
        let from = vertex_of[a];
        for u in neighbours(a) {
            if vertex_of[u] != NONE {
                // Two vertex pixels side by side (an end next to a junction, a 2-pixel stroke).
                if vertex_of[u] != from && a < u {
                    let points = vec![vertices[from].pos, vertices[vertex_of[u]].pos];
                    make_edge(from, vertex_of[u], points, &mut edges);
                }
                continue;
            }
            if visited[u] {
                continue;
            }
            let mut points = vec![vertices[from].pos];
            let (mut prev, mut cur) = (a, u);
            let to = loop {
                visited[cur] = true;
                points.push(center(cur));
                let next = neighbours(cur).find(|&k| k != prev);
                match next {
                    Some(k) if vertex_of[k] != NONE => break Some(vertex_of[k]),
                    Some(k) if !visited[k] => {
                        prev = cur;
                        cur = k;
                    }
                    _ => break None,
                }
            };
            let Some(to) = to else { continue };
            // A pixel tucked into a junction cluster is not a loop.
            if to == from && points.len() <= 3 {
                continue;
            }
            points.push(vertices[to].pos);
            make_edge(from, to, points, &mut edges);
        }
    }
    // Cycles with no junction: a loop anchored at their first pixel.
    for s in (0..skeleton.len()).filter(|&i| skeleton[i] && count[i] == 2) {
        if visited[s] {
            continue;
        }
        let id = vertices.len();
        vertices.push(Vertex {
            pos: center(s),
            degree: 0,
            width: width_at(center(s)),
        });
        let mut points = vec![center(s)];
        visited[s] = true;
        let (mut prev, mut cur) = (s, neighbours(s).next().unwrap_or(s));
        while cur != s && !visited[cur] {
            visited[cur] = true;
            points.push(center(cur));
            match neighbours(cur).find(|&k| k != prev) {
                Some(k) => {
                    prev = cur;
                    cur = k;
                }
                None => break,
            }
        }
        points.push(center(s));
        make_edge(id, id, points, &mut edges);
    }
    for e in &edges {
        vertices[e.from].degree += 1;
        vertices[e.to].degree += 1;
    }
    StrokeGraph {
        width,
        height,
        vertices,
        edges,
    }
}

fn tangents(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i.saturating_sub(1)], points[(i + 1).min(n - 1)]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len = d[0].hypot(d[1]);
            if len > 0.0 {
                [d[0] / len, d[1] / len]
            } else {
                [1.0, 0.0]
            }
        })
        .collect()
}
