//! §3.4 in space: the refined graph's chains resampled to an even node spacing, each point given
//! to its nearest node (of its own part), the nodes moved to minimize Eq. (4),
//! `sum |q_i - q'_i|^2 + w |L Q|^2`, with `q'_i` the L1 median of node `i`'s points, solved for
//! the three coordinates at once from one factorization. As in the plane (docs/design.md,
//! adaptations 12 and 13): with the held Laplacian only nodes inside a chain are smoothed and
//! vertices weigh `anchor_weight`; ends move out to where their points end. The tube's diameter
//! at each node comes from the points of its cell around the fitted line (a filled disk of
//! radius `R` has a mean squared distance `R^2 / 2` from its center).

use std::collections::HashSet;
use std::num::NonZero;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use sprs::{FillInReduction, SymmetryCheck, TriMat};
use sprs_ldl::Ldl;

use super::math::{add, dist2, dot, norm, scale, sub, V3};
use super::points::Cloud;
use super::refine::Refined;
use crate::curve3d::{CurveGraph3d, Edge3d, Vertex3d};
use crate::median::upper_median;
use crate::params::{LaplacianRule, Params};

/// Fewest points in a node's cell for it to measure the diameter itself.
const WIDTH_MIN_POINTS: usize = 6;

/// A chain of the refined graph between two vertices (the same one for a closed curve).
struct Chain {
    from: usize,
    to: usize,
    /// Refined nodes from `from`'s node to `to`'s node, both included.
    nodes: Vec<u32>,
}

pub(super) fn fit(cloud: &Cloud, refined: &Refined, params: &Params) -> CurveGraph3d {
    let count = refined.pos.len();
    if count == 0 {
        return CurveGraph3d::default();
    }
    let degree = |i: usize| refined.adj[i].len();
    // Vertices: nodes of degree other than 2, and one node of each closed curve.
    let mut vertex_of = vec![usize::MAX; count];
    let mut vertex_nodes: Vec<u32> = Vec::new();
    for (i, slot) in vertex_of.iter_mut().enumerate() {
        if degree(i) != 2 {
            *slot = vertex_nodes.len();
            vertex_nodes.push(i as u32);
        }
    }
    let mut seen_edge: HashSet<(u32, u32)> = HashSet::new();
    let mut chains: Vec<Chain> = Vec::new();
    let walk = |start: u32,
                vertex_of: &Vec<usize>,
                chains: &mut Vec<Chain>,
                seen_edge: &mut HashSet<(u32, u32)>| {
        for &first in &refined.adj[start as usize] {
            let edge = (start.min(first), start.max(first));
            if seen_edge.contains(&edge) {
                continue;
            }
            seen_edge.insert(edge);
            let mut nodes = vec![start, first];
            let (mut prev, mut at) = (start, first);
            while vertex_of[at as usize] == usize::MAX {
                let next = refined.adj[at as usize]
                    .iter()
                    .copied()
                    .find(|&x| x != prev)
                    .unwrap_or(prev);
                seen_edge.insert((at.min(next), at.max(next)));
                prev = at;
                at = next;
                nodes.push(at);
            }
            chains.push(Chain {
                from: vertex_of[start as usize],
                to: vertex_of[at as usize],
                nodes,
            });
        }
    };
    for &start in &vertex_nodes {
        walk(start, &vertex_of, &mut chains, &mut seen_edge);
    }
    // Closed curves: every node of degree 2, none visited yet.
    for i in 0..count as u32 {
        let visited = refined.adj[i as usize]
            .iter()
            .any(|&j| seen_edge.contains(&(i.min(j), i.max(j))));
        if vertex_of[i as usize] == usize::MAX && !visited {
            vertex_of[i as usize] = vertex_nodes.len();
            vertex_nodes.push(i);
            walk(i, &vertex_of, &mut chains, &mut seen_edge);
        }
    }

    // Even spacing: `h = max(3 Dis_ave, median diameter)` (adaptation 12).
    let mut widths = refined.width.clone();
    let median_width = upper_median(&mut widths).unwrap_or(1.0);
    let h = (3.0 * cloud.spacing).max(params.fit.spacing_factor * median_width);
    // Fit nodes: the vertices, then each chain's interior nodes in order.
    let mut pos: Vec<V3> = vertex_nodes
        .iter()
        .map(|&i| refined.pos[i as usize])
        .collect();
    let mut fallback_width: Vec<f64> = vertex_nodes
        .iter()
        .map(|&i| refined.width[i as usize])
        .collect();
    let mut runs: Vec<Vec<u32>> = Vec::new();
    for chain in &chains {
        let line: Vec<V3> = chain
            .nodes
            .iter()
            .map(|&i| refined.pos[i as usize])
            .collect();
        let node_widths: Vec<f64> = chain
            .nodes
            .iter()
            .map(|&i| refined.width[i as usize])
            .collect();
        let length: f64 = line.windows(2).map(|w| dist2(w[0], w[1]).sqrt()).sum();
        let minimum = if chain.from == chain.to { 3 } else { 1 };
        let segments = ((length / h).round() as usize).max(minimum);
        let mut run = vec![chain.from as u32];
        let targets: Vec<f64> = (1..segments)
            .map(|s| length * s as f64 / segments as f64)
            .collect();
        for (p, w) in along(&line, &node_widths, &targets) {
            run.push(pos.len() as u32);
            pos.push(p);
            fallback_width.push(w);
        }
        run.push(chain.to as u32);
        runs.push(run);
    }
    let fit_count = pos.len();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); fit_count];
    for run in &runs {
        for w in run.windows(2) {
            neighbours[w[0] as usize].push(w[1]);
            neighbours[w[1] as usize].push(w[0]);
        }
    }
    // Parts: a vertex's from its refined node's points; a chain's interior from its start.
    let mut part = vec![u32::MAX; fit_count];
    for (p, &o) in refined.owner.iter().enumerate() {
        if o != u32::MAX {
            let v = vertex_of[o as usize];
            if v != usize::MAX && part[v] == u32::MAX {
                part[v] = cloud.part[p];
            }
        }
    }
    for run in &runs {
        let from = part[run[0] as usize];
        for &i in &run[1..run.len() - 1] {
            part[i as usize] = from;
        }
    }
    let cells = assign(cloud, &pos, &part);
    let medians: Vec<Option<V3>> = cells
        .par_iter()
        .map(|cell| weiszfeld(cloud, cell, params.fit.weiszfeld_iterations))
        .collect();
    let vertex_count = vertex_nodes.len();
    let held = params.fit.laplacian == LaplacianRule::Held;
    let mut weights = vec![1.0; fit_count];
    let mut targets = pos.clone();
    for i in 0..fit_count {
        match medians[i] {
            Some(m) => targets[i] = m,
            None => weights[i] = 1e-3,
        }
        if held && i < vertex_count {
            weights[i] *= params.fit.anchor_weight;
        }
    }
    let rows: Vec<(usize, Vec<u32>)> = (0..fit_count)
        .filter(|&i| !neighbours[i].is_empty() && (!held || neighbours[i].len() == 2))
        .filter(|&i| !(held && i < vertex_count))
        .map(|i| (i, neighbours[i].clone()))
        .collect();
    let mut solved = solve(&targets, &weights, &rows, params.fit.smoothness).unwrap_or(targets);
    // Ends where the points end (adaptation 13): out along the edge to the farthest point of the
    // end's cell and its neighbour's.
    for v in 0..vertex_count {
        if neighbours[v].len() != 1 {
            continue;
        }
        let inner = neighbours[v][0] as usize;
        let axis = sub(solved[v], solved[inner]);
        let length = norm(axis);
        if length <= 0.0 {
            continue;
        }
        let u = scale(axis, 1.0 / length);
        let reach = cells[v]
            .iter()
            .chain(&cells[inner])
            .map(|&p| dot(sub(cloud.points[p as usize], solved[v]), u))
            .fold(0.0f64, f64::max);
        solved[v] = add(solved[v], scale(u, reach));
    }
    // Diameters from each cell around the fitted line.
    let mut diameter = vec![f64::NAN; fit_count];
    for i in 0..fit_count {
        if neighbours[i].len() != 2 || cells[i].len() < WIDTH_MIN_POINTS {
            continue;
        }
        let (a, b) = (
            solved[neighbours[i][0] as usize],
            solved[neighbours[i][1] as usize],
        );
        let t = sub(b, a);
        let tn = norm(t);
        if tn <= 0.0 {
            continue;
        }
        let t = scale(t, 1.0 / tn);
        let mean_square = cells[i]
            .iter()
            .map(|&p| {
                let d = sub(cloud.points[p as usize], solved[i]);
                (dot(d, d) - dot(d, t).powi(2)).max(0.0)
            })
            .sum::<f64>()
            / cells[i].len() as f64;
        diameter[i] = 2.0 * (2.0 * mean_square).sqrt();
    }
    let diameter: Vec<f64> = (0..fit_count)
        .map(|i| {
            if diameter[i].is_finite() {
                return diameter[i];
            }
            let around: Vec<f64> = neighbours[i]
                .iter()
                .map(|&j| diameter[j as usize])
                .filter(|d| d.is_finite())
                .collect();
            if around.is_empty() {
                fallback_width[i]
            } else {
                around.iter().sum::<f64>() / around.len() as f64
            }
        })
        .collect();
    let mut graph = CurveGraph3d {
        vertices: (0..vertex_count)
            .map(|v| Vertex3d {
                pos: solved[v],
                degree: 0,
                width: diameter[v],
            })
            .collect(),
        edges: Vec::with_capacity(runs.len()),
    };
    for (run, chain) in runs.iter().zip(&chains) {
        graph.vertices[chain.from].degree += 1;
        graph.vertices[chain.to].degree += 1;
        graph.edges.push(Edge3d {
            from: chain.from,
            to: chain.to,
            points: run.iter().map(|&i| solved[i as usize]).collect(),
            widths: run.iter().map(|&i| diameter[i as usize]).collect(),
        });
    }
    graph
}

/// The points at the rising arc lengths `targets` along `line`, and the widths there, in one
/// walk along it.
fn along(line: &[V3], widths: &[f64], targets: &[f64]) -> Vec<(V3, f64)> {
    let mut out = Vec::with_capacity(targets.len());
    let mut walked = 0.0;
    let mut i = 0;
    for &s in targets {
        while i + 1 < line.len() {
            let step = dist2(line[i], line[i + 1]).sqrt();
            if walked + step >= s && step > 0.0 {
                break;
            }
            walked += step;
            i += 1;
        }
        if i + 1 >= line.len() {
            out.push((line[line.len() - 1], widths[widths.len() - 1]));
            continue;
        }
        let step = dist2(line[i], line[i + 1]).sqrt();
        let t = ((s - walked) / step).clamp(0.0, 1.0);
        out.push((
            add(line[i], scale(sub(line[i + 1], line[i]), t)),
            widths[i] + t * (widths[i + 1] - widths[i]),
        ));
    }
    out
}

/// Each point's nearest fit node of its own part (any part when none is among its few nearest).
fn assign(cloud: &Cloud, pos: &[V3], part: &[u32]) -> Vec<Vec<u32>> {
    let mut cells = vec![Vec::new(); pos.len()];
    let Ok(tree) = ImmutableKdTree::<f64, 3>::new_from_slice(pos) else {
        return cells;
    };
    let wanted = NonZero::new(8.min(pos.len())).unwrap_or(NonZero::<usize>::MIN);
    let nearest: Vec<u32> = (0..cloud.len())
        .into_par_iter()
        .map(|p| {
            let mut found = tree
                .query(&cloud.points[p])
                .nearest_n::<SquaredEuclidean<f64>>(wanted)
                .execute();
            found.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.item.cmp(&b.item)));
            found
                .iter()
                .find(|r| part[r.item as usize] == cloud.part[p])
                .or(found.first())
                .map_or(0, |r| r.item)
        })
        .collect();
    for (p, &node) in nearest.iter().enumerate() {
        cells[node as usize].push(p as u32);
    }
    cells
}

/// The L1 median of a cell's points by Weiszfeld's iteration from their mean.
fn weiszfeld(cloud: &Cloud, cell: &[u32], iterations: usize) -> Option<V3> {
    if cell.is_empty() {
        return None;
    }
    let points = || cell.iter().map(|&p| cloud.points[p as usize]);
    let mut m = scale(points().fold([0.0; 3], add), 1.0 / cell.len() as f64);
    for _ in 0..iterations {
        let mut sum = [0.0; 3];
        let mut total = 0.0;
        for p in points() {
            let d = dist2(p, m).sqrt().max(1e-9);
            sum = add(sum, scale(p, 1.0 / d));
            total += 1.0 / d;
        }
        let next = scale(sum, 1.0 / total);
        let moved = dist2(next, m);
        m = next;
        if moved < 1e-18 {
            break;
        }
    }
    Some(m)
}

/// Solves `(W + w L^T L) Q = W Q'` (Eq. (4)); each row of `L` is `q_i - mean(neighbours)`.
fn solve(targets: &[V3], weights: &[f64], rows: &[(usize, Vec<u32>)], w: f64) -> Option<Vec<V3>> {
    let n = targets.len();
    if w == 0.0 || rows.is_empty() {
        return Some(targets.to_vec());
    }
    let mut matrix = TriMat::new((n, n));
    for (i, &weight) in weights.iter().enumerate() {
        matrix.add_triplet(i, i, weight);
    }
    for (center, around) in rows {
        let share = 1.0 / around.len() as f64;
        let mut row: Vec<(usize, f64)> = vec![(*center, 1.0)];
        row.extend(around.iter().map(|&j| (j as usize, -share)));
        for &(a, x) in &row {
            for &(b, y) in &row {
                matrix.add_triplet(a, b, w * x * y);
            }
        }
    }
    let matrix = matrix.to_csc::<usize>();
    let ldl = Ldl::new()
        .fill_in_reduction(FillInReduction::ReverseCuthillMcKee)
        .check_symmetry(SymmetryCheck::DontCheckSymmetry)
        .numeric(matrix.view())
        .ok()?;
    let mut out = vec![[0.0; 3]; n];
    for k in 0..3 {
        let b: Vec<f64> = (0..n).map(|i| weights[i] * targets[i][k]).collect();
        let x = ldl.solve(&b);
        for (o, v) in out.iter_mut().zip(x) {
            o[k] = v;
        }
    }
    out.iter()
        .all(|p| p.iter().all(|c| c.is_finite()))
        .then_some(out)
}
