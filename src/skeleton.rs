//! Skeleton-carried geometry, method-decided topology (an experiment, `Params::skeleton`; see the
//! fidelity notes in `docs/quality.md`): a topology-preserving pixel skeleton of the ink carries the
//! geometry and every hole, and the stroke graph of the paper's method (§3.1-§3.4) decides what
//! the pixels alone cannot:
//!
//! - **crossings**: skeleton junctions around one of the method's crossings (degree >= 4), joined
//!   by short skeleton edges that enclose no hole and leaving it by as many arms as the crossing
//!   has, are one vertex at the method's crossing (thinning splits an X into two Y's);
//! - **spurs**: a terminal skeleton branch is kept when its ink reaches beyond the junction's own
//!   disk by more than a boundary bump ([`spur_reach`]), or when the method has a stroke end there.
//!
//! - **corners**: where the method sees no junction, the Y that thinning makes of a sharp bend
//!   (two legs and a stub into the corner) is a bend.
//!
//! In: the method's [`StrokeGraph`] and the [`PointSet`] with its pixel grid. Out: a
//! [`StrokeGraph`] whose polylines are the skeleton's pixel paths (smoothing them, even over 3
//! pixels, measured worse at 1 px tolerance). Point lists and
//! dropout mode (broken strokes, whose skeleton is not the stroke's) keep the method's graph.

use crate::point_set::{Grid, PointSet};
use crate::{dist, Edge, StrokeGraph, Vertex};

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
/// transition around them, and (south-east | north-west) boundary conditions, until stable. The
/// skeleton keeps the ink's connectivity and holes.
pub fn zhang_suen(ink: &[bool], width: usize, height: usize) -> Vec<bool> {
    let (w, h) = (width as i64, height as i64);
    let mut ink = ink.to_vec();
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

/// The graph of a one-pixel skeleton in a `width` x `height` window: skeleton pixels with more
/// than two skeleton neighbours are junction pixels, clustered 8-connected into one vertex each;
/// pixels with one neighbour are ends, with none dots; the pixel paths between them are edges;
/// skeleton cycles without a junction become loops. Coordinates are pixel centers of the window;
/// widths are `2 half_width - 1` (the pixel itself not counted).
pub fn pixel_graph(
    width: usize,
    height: usize,
    skeleton: &[bool],
    half_width: &[f64],
) -> StrokeGraph {
    let (w, h) = (width as i64, height as i64);
    let on = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && skeleton[(y * w + x) as usize];
    let neighbours = |i: usize| {
        let (x, y) = ((i as i64) % w, (i as i64) / w);
        RING.iter()
            .filter(move |&&(dx, dy)| on(x + dx, y + dy))
            .map(move |&(dx, dy)| ((y + dy) * w + x + dx) as usize)
    };
    let center = |i: usize| [(i as i64 % w) as f64 + 0.5, (i as i64 / w) as f64 + 0.5];
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

    let mut edges: Vec<Edge> = Vec::new();
    let mut visited = vec![false; skeleton.len()];
    let make_edge = |from: usize, to: usize, points: Vec<[f64; 2]>, edges: &mut Vec<Edge>| {
        let widths = points.iter().map(|&p| width_at(p)).collect();
        edges.push(Edge {
            from,
            to,
            points,
            widths,
            directions: Vec::new(),
        });
    };
    for a in (0..skeleton.len()).filter(|&i| skeleton[i] && vertex_of[i] != NONE) {
        let from = vertex_of[a];
        for u in neighbours(a) {
            if vertex_of[u] != NONE {
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
            if to == from && points.len() <= 3 {
                continue;
            }
            points.push(vertices[to].pos);
            make_edge(from, to, points, &mut edges);
        }
    }
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
    let mut graph = StrokeGraph {
        width: width as u32,
        height: height as u32,
        vertices,
        edges,
    };
    set_directions(&mut graph);
    graph
}

/// Unit tangents of a polyline by central differences, as the fit writes them.
pub fn tangents(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
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

fn set_directions(graph: &mut StrokeGraph) {
    for edge in &mut graph.edges {
        edge.directions = tangents(&edge.points);
    }
}

/// How far the ink of a terminal branch reaches beyond the envelope of the strokes it leaves:
/// for each of its points `p` (with `r(p)` the half-width there), how far its disk sticks out of
/// the nearest-fitting disk `(q, r(q))` among `envelope` (the junction and the points of its
/// other edges), `min_q |p - q| + r(p) - r(q)`; the largest over the branch. A spur, a bump of
/// the boundary or the branch into a rounded corner, reaches about a pixel; an arm's ink sticks
/// out by its length. Widths are full widths (`r = (w + 1) / 2`, the pixel itself counted).
pub fn spur_reach(points: &[[f64; 2]], widths: &[f64], envelope: &[([f64; 2], f64)]) -> f64 {
    points
        .iter()
        .zip(widths)
        .map(|(&p, &w)| {
            let r = (w + 1.0) / 2.0;
            envelope
                .iter()
                .map(|&(q, wq)| dist(p, q) + r - (wq + 1.0) / 2.0)
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|e| e.is_finite())
        .fold(0.0f64, f64::max)
}

/// The skeleton-carried graph of `points`' ink with the topology decisions of `method` (see the
/// module doc). Returns `method` unchanged for point lists and in dropout mode.
pub fn carry(method: &StrokeGraph, points: &PointSet) -> StrokeGraph {
    let Some(grid) = &points.grid else {
        return method.clone();
    };
    if points.dropout || grid.index.is_empty() {
        return method.clone();
    }
    let (w, h) = (grid.width as usize, grid.height as usize);
    let ink: Vec<bool> = grid.index.iter().map(|&i| i != Grid::NONE).collect();
    let half: Vec<f64> = grid
        .index
        .iter()
        .map(|&i| match i {
            Grid::NONE => 0.0,
            i => f64::from(points.half_width[i as usize]),
        })
        .collect();
    let mut ink = ink;
    fill_specks(&mut ink, w, h);
    let mut skeleton = zhang_suen(&ink, w, h);
    keep_every_component(&ink, &half, w, h, &mut skeleton);
    let mut s = pixel_graph(w, h, &skeleton, &half);
    let (x0, y0) = (grid.x0 as f64, grid.y0 as f64);
    for v in &mut s.vertices {
        v.pos = [v.pos[0] + x0, v.pos[1] + y0];
    }
    for e in &mut s.edges {
        for p in &mut e.points {
            *p = [p[0] + x0, p[1] + y0];
        }
    }
    let mut work = Work::new(s);
    work.prune_spurs();
    work.join_degree_two();
    work.merge_crossings(method);
    work.prune_spurs();
    // A dissolved corner lengthens its neighbours' legs (the corners of a small `w` share them):
    // repeated until none is left.
    while work.dissolve_corners() {
        work.join_degree_two();
    }
    work.join_degree_two();
    work.collapse_dots();
    work.straighten_junctions();
    let mut graph = work.finish(method.width, method.height);
    set_directions(&mut graph);
    graph
}

/// Background specks of at most 3 pixels enclosed by ink (a sharp meeting of two strokes or a
/// rendering gap; the noise the dropout test counts, `mask::tiny_hole`) are not holes: filled,
/// so the skeleton makes no cycle around them.
fn fill_specks(ink: &mut [bool], w: usize, h: usize) {
    if w < 3 || h < 3 {
        return;
    }
    let mut specks = Vec::new();
    for i in w..ink.len() - w {
        if !ink[i] && ink[i - 1] && crate::mask::tiny_hole(ink, w, h, i).is_some() {
            specks.push(i);
        }
    }
    for start in specks {
        let mut stack = vec![start];
        while let Some(p) = stack.pop() {
            if ink[p] {
                continue;
            }
            ink[p] = true;
            stack.extend([p - 1, p + 1, p - w, p + w]);
        }
    }
}

/// Zhang-Suen thinning erases some small blobs whole (a 2 x 2 block, a short 2-pixel-thick
/// diagonal): every component of the ink that lost all its pixels gets back its deepest one, a
/// dot.
fn keep_every_component(ink: &[bool], half: &[f64], w: usize, h: usize, skeleton: &mut [bool]) {
    let mut seen = vec![false; ink.len()];
    let mut stack = Vec::new();
    let mut members = Vec::new();
    for start in 0..ink.len() {
        if !ink[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        members.clear();
        while let Some(i) = stack.pop() {
            members.push(i);
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for (dx, dy) in RING {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if ink[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if members.iter().any(|&i| skeleton[i]) {
            continue;
        }
        if let Some(&deepest) = members
            .iter()
            .max_by(|&&a, &&b| half[a].total_cmp(&half[b]).then(b.cmp(&a)))
        {
            skeleton[deepest] = true;
        }
    }
}

/// The skeleton graph being edited: removed edges are `None`, removed vertices `alive == false`.
struct Work {
    vertices: Vec<Vertex>,
    alive: Vec<bool>,
    /// Vertices that were dots (no edge) from the start: kept with degree 0.
    dot: Vec<bool>,
    edges: Vec<Option<Edge>>,
}

impl Work {
    fn new(graph: StrokeGraph) -> Work {
        let n = graph.vertices.len();
        let dot = graph.vertices.iter().map(|v| v.degree == 0).collect();
        Work {
            vertices: graph.vertices,
            alive: vec![true; n],
            dot,
            edges: graph.edges.into_iter().map(Some).collect(),
        }
    }

    fn degrees(&self) -> Vec<usize> {
        let mut degree = vec![0; self.vertices.len()];
        for e in self.edges.iter().flatten() {
            degree[e.from] += 1;
            degree[e.to] += 1;
        }
        degree
    }

    /// Crossings: around each of the method's vertices of degree >= 4, the skeleton junctions
    /// nearer to it than to any other of the method's junctions (and within 4 of its widths), joined by skeleton edges among themselves that form a tree (no
    /// hole inside) and leaving by exactly as many arms as the crossing has, become one vertex at
    /// the crossing; each arm is cut where it leaves the merged junctions' reach and joined
    /// straight to it.
    fn merge_crossings(&mut self, method: &StrokeGraph) {
        let mut claimed = vec![false; self.vertices.len()];
        let junctions: Vec<[f64; 2]> = method
            .vertices
            .iter()
            .filter(|v| v.degree >= 3)
            .map(|v| v.pos)
            .collect();
        // The method's junction nearest to a point: every skeleton junction belongs to one.
        let nearest_junction = |p: [f64; 2]| {
            junctions
                .iter()
                .copied()
                .min_by(|a, b| dist(*a, p).total_cmp(&dist(*b, p)))
        };
        for v in method.vertices.iter().filter(|v| v.degree >= 4) {
            let degree = self.degrees();
            // The Y's of an acute crossing lie about (w / 2) / sin(theta / 2) from it, 3.8 w at
            // 15 degrees: search within 4 widths, among the skeleton junctions whose nearest
            // method junction is this one.
            let radius = 4.0 * v.width.max(2.0);
            let near: Vec<usize> = (0..self.vertices.len())
                .filter(|&i| self.alive[i] && !claimed[i] && degree[i] >= 3)
                .filter(|&i| dist(self.vertices[i].pos, v.pos) <= radius)
                .filter(|&i| nearest_junction(self.vertices[i].pos) == Some(v.pos))
                .collect();
            if near.len() < 2 {
                continue;
            }
            // The connected group of `near` (through edges between members) nearest the crossing.
            let Some(&seed) = near.iter().min_by(|&&a, &&b| {
                dist(self.vertices[a].pos, v.pos).total_cmp(&dist(self.vertices[b].pos, v.pos))
            }) else {
                continue;
            };
            let mut group = vec![seed];
            let mut internal = Vec::new();
            let mut grew = true;
            while grew {
                grew = false;
                for (e, edge) in self.edges.iter().enumerate() {
                    let Some(edge) = edge else { continue };
                    if internal.contains(&e) {
                        continue;
                    }
                    let (a, b) = (edge.from, edge.to);
                    let (in_a, in_b) = (group.contains(&a), group.contains(&b));
                    if (in_a || in_b) && near.contains(&a) && near.contains(&b) {
                        internal.push(e);
                        if !in_a {
                            group.push(a);
                        }
                        if !in_b {
                            group.push(b);
                        }
                        grew = true;
                    }
                }
            }
            // A cycle among the group would be a hole in the ink: never merged away.
            if group.len() < 2 || internal.len() != group.len() - 1 {
                continue;
            }
            let arms: usize = group.iter().map(|&i| degree[i]).sum::<usize>() - 2 * internal.len();
            if arms != v.degree {
                continue;
            }
            let reach = group
                .iter()
                .map(|&i| dist(self.vertices[i].pos, v.pos))
                .fold(0.0f64, f64::max);
            for &e in &internal {
                self.edges[e] = None;
            }
            let hub = group[0];
            self.vertices[hub].pos = v.pos;
            self.vertices[hub].width = v.width;
            for &i in &group {
                claimed[i] = true;
                if i != hub {
                    self.alive[i] = false;
                }
            }
            for edge in self.edges.iter_mut().flatten() {
                for end in 0..2 {
                    let at = if end == 0 { edge.from } else { edge.to };
                    if !group.contains(&at) {
                        continue;
                    }
                    if end == 0 {
                        edge.from = hub;
                    } else {
                        edge.to = hub;
                    }
                    cut_arm(edge, end == 0, v.pos, reach);
                }
            }
        }
    }

    /// The edges at each vertex (a loop listed once).
    fn incidence(&self) -> Vec<Vec<usize>> {
        let mut at = vec![Vec::new(); self.vertices.len()];
        for (e, edge) in self.edges.iter().enumerate() {
            let Some(edge) = edge else { continue };
            at[edge.from].push(e);
            if edge.to != edge.from {
                at[edge.to].push(e);
            }
        }
        at
    }

    /// Spurs: terminal branches whose ink does not reach beyond their junction's disk by more
    /// than `max(1.5 px, 0.4 x` the stroke width`)` are removed, least reaching first, while
    /// their junction keeps three edges (of the two stubs of a forked stroke end, the longer
    /// one stays as the stroke's end). A sharp corner's branch reaches about `0.2 w`, a boundary
    /// bump about a pixel; an arm half a width long or more is kept.
    fn prune_spurs(&mut self) {
        let mut degree = self.degrees();
        let at = self.incidence();
        // The stroke width an arm leaves: the narrowest median width of the junction's other
        // edges (the width at the junction itself is inflated where strokes meet).
        let median = |widths: &[f64]| {
            let mut sorted = widths.to_vec();
            sorted.sort_by(f64::total_cmp);
            sorted.get(sorted.len() / 2).copied().unwrap_or(1.0)
        };
        let mut spurs = Vec::new();
        for (e, edge) in self.edges.iter().enumerate() {
            let Some(edge) = edge else { continue };
            let (junction, tip, forward) = match (degree[edge.from], degree[edge.to]) {
                (1, d) if d >= 3 => (edge.to, edge.from, false),
                (d, 1) if d >= 3 => (edge.from, edge.to, true),
                _ => continue,
            };
            let others = || {
                at[junction]
                    .iter()
                    .filter(move |&&o| o != e)
                    .filter_map(|&o| self.edges[o].as_ref())
            };
            let stroke = others()
                .map(|other| median(&other.widths))
                .fold(f64::INFINITY, f64::min);
            let j = &self.vertices[junction];
            let stroke = if stroke.is_finite() { stroke } else { j.width };
            let mut points = edge.points.clone();
            let mut widths = edge.widths.clone();
            if !forward {
                points.reverse();
                widths.reverse();
            }
            // The envelope: the junction and its other edges' points within 3 stroke widths.
            let mut envelope = vec![(j.pos, j.width)];
            for other in others() {
                envelope.extend(
                    other
                        .points
                        .iter()
                        .copied()
                        .zip(other.widths.iter().copied())
                        .filter(|&(q, _)| dist(q, j.pos) <= 3.0 * stroke),
                );
            }
            let reach = spur_reach(&points, &widths, &envelope);
            if reach <= (0.4 * stroke).max(1.5) {
                spurs.push((reach, e, junction, tip));
            }
        }
        spurs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (_, e, junction, tip) in spurs {
            if degree[junction] < 3 {
                continue;
            }
            degree[junction] -= 1;
            degree[tip] -= 1;
            self.edges[e] = None;
            self.alive[tip] = false;
        }
    }

    /// Corners: thinning turns a sharp bend into a Y, the two legs bending together above the
    /// corner and a stub running on into the corner's tip. A degree-3 skeleton junction with one
    /// terminal stub is such a corner when its two legs, followed straight beyond where they
    /// bend, meet under less than 120 degrees at a point `v` on the stub, and the stub's ink ends
    /// within the stroke's half-width (plus the spur margin of [`Self::prune_spurs`]) of `v`: no
    /// ink reaches beyond the corner the two legs make by themselves. Then the stub and the
    /// junction go, and both legs run straight to `v`, the bend.
    fn dissolve_corners(&mut self) -> bool {
        let mut changed = false;
        let at = self.incidence();
        let degree = self.degrees();
        let median = |widths: &[f64]| {
            let mut sorted = widths.to_vec();
            sorted.sort_by(f64::total_cmp);
            sorted.get(sorted.len() / 2).copied().unwrap_or(1.0)
        };
        for j in 0..self.vertices.len() {
            if !self.alive[j] || degree[j] != 3 || at[j].len() != 3 {
                continue;
            }
            let far = |e: usize| {
                self.edges[e]
                    .as_ref()
                    .map(|x| if x.from == j { x.to } else { x.from })
            };
            if at[j].iter().any(|&e| far(e).is_none_or(|f| f == j)) {
                continue;
            }
            // The stub: the shortest terminal edge (a leg may end too, at the stroke's end).
            let Some(stub) = at[j]
                .iter()
                .copied()
                .filter(|&e| far(e).is_some_and(|f| degree[f] == 1))
                .min_by_key(|&e| (self.edges[e].as_ref().map_or(0, |x| x.points.len()), e))
            else {
                continue;
            };
            let legs: Vec<usize> = at[j].iter().copied().filter(|&e| e != stub).collect();
            // Every edge's points listed from the junction outwards.
            let outwards = |e: usize| -> Vec<[f64; 2]> {
                let edge = self.edges[e].as_ref().expect("live edge");
                let mut points = edge.points.clone();
                if edge.from != j {
                    points.reverse();
                }
                points
            };
            let stub_points = outwards(stub);
            let (jp, tip) = (self.vertices[j].pos, stub_points[stub_points.len() - 1]);
            let stroke = legs
                .iter()
                .filter_map(|&e| self.edges[e].as_ref())
                .map(|e| median(&e.widths))
                .fold(f64::INFINITY, f64::min);
            let half = (stroke + 1.0) / 2.0;
            let reach = dist(jp, tip);
            // Each leg's line: through its points at `reach` and `reach + 2 w` from the junction
            // (where it no longer bends towards the other leg), pointing towards the corner.
            let line = |points: &[[f64; 2]]| -> Option<([f64; 2], [f64; 2], usize)> {
                let near = points.iter().position(|&p| dist(p, jp) >= reach)?;
                let far = points
                    .iter()
                    .position(|&p| dist(p, jp) >= reach + 2.0 * stroke)
                    .unwrap_or(points.len() - 1);
                let (a, b) = (points[near], points[far]);
                let d = [a[0] - b[0], a[1] - b[1]];
                let n = d[0].hypot(d[1]);
                (n >= 1.0).then(|| (a, [d[0] / n, d[1] / n], near))
            };
            let (leg_a, leg_b) = (outwards(legs[0]), outwards(legs[1]));
            let (Some((a, ua, cut_a)), Some((b, ub, cut_b))) = (line(&leg_a), line(&leg_b)) else {
                continue;
            };
            // The legs leave the corner at less than 120 degrees: -ua . -ub > cos 120.
            let cross = ua[0] * ub[1] - ua[1] * ub[0];
            if ua[0] * ub[0] + ua[1] * ub[1] <= (120f64).to_radians().cos() || cross.abs() < 1e-6 {
                continue;
            }
            // a + s ua = b + t ub.
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let (s, t) = (
                (dx * ub[1] - dy * ub[0]) / cross,
                (dx * ua[1] - dy * ua[0]) / cross,
            );
            if s < 0.0 || t < 0.0 {
                continue;
            }
            let v = [a[0] + s * ua[0], a[1] + s * ua[1]];
            let margin = (0.4 * stroke).max(1.5);
            let on_stub = stub_points
                .iter()
                .map(|&p| dist(p, v))
                .fold(f64::INFINITY, f64::min)
                <= half + margin;
            if !on_stub || dist(v, tip) > half + margin {
                continue;
            }
            // Where the legs' lines meet beyond the stub's tip, the bend is the tip (on the ink).
            let v = if dist(jp, v) > reach { tip } else { v };
            let tip_vertex = far(stub);
            for (e, cut) in [(legs[0], cut_a), (legs[1], cut_b)] {
                let edge = self.edges[e].as_mut().expect("live edge");
                let forward = edge.from == j;
                if !forward {
                    edge.points.reverse();
                    edge.widths.reverse();
                }
                edge.points.drain(..cut);
                edge.widths.drain(..cut);
                edge.points.insert(0, v);
                edge.widths.insert(0, stroke);
                if !forward {
                    edge.points.reverse();
                    edge.widths.reverse();
                }
            }
            if let Some(tip_vertex) = tip_vertex {
                self.alive[tip_vertex] = false;
            }
            self.edges[stub] = None;
            self.vertices[j].pos = v;
            self.vertices[j].width = stroke;
            changed = true;
        }
        changed
    }

    /// A blob of ink no longer than it is wide (the dot of an `i`, a full stop) thins to a short
    /// segment between two ends: it is a dot, one vertex of degree 0 at the segment's middle.
    fn collapse_dots(&mut self) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            if edge.from == edge.to || degree[edge.from] != 1 || degree[edge.to] != 1 {
                continue;
            }
            let length: f64 = edge.points.windows(2).map(|p| dist(p[0], p[1])).sum();
            let width = edge.widths.iter().copied().fold(1.0f64, f64::max);
            if length > width {
                continue;
            }
            let (a, b) = (edge.points[0], edge.points[edge.points.len() - 1]);
            let (keep, gone) = (edge.from, edge.to);
            self.vertices[keep].pos = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            self.vertices[keep].width = width;
            self.dot[keep] = true;
            self.alive[gone] = false;
            self.edges[e] = None;
        }
    }

    /// Vertices left with two edge ends (after pruning) are not junctions: their two edges
    /// become one.
    fn join_degree_two(&mut self) {
        loop {
            let degree = self.degrees();
            let Some(v) = (0..self.vertices.len()).find(|&i| {
                self.alive[i]
                    && degree[i] == 2
                    && self
                        .edges
                        .iter()
                        .flatten()
                        .all(|e| !(e.from == i && e.to == i))
            }) else {
                return;
            };
            let incident: Vec<usize> = (0..self.edges.len())
                .filter(|&e| {
                    self.edges[e]
                        .as_ref()
                        .is_some_and(|edge| edge.from == v || edge.to == v)
                })
                .collect();
            let [a, b] = incident[..] else { return };
            let (Some(mut first), Some(mut second)) = (self.edges[a].take(), self.edges[b].take())
            else {
                return;
            };
            if first.to != v {
                reverse(&mut first);
            }
            if second.from != v {
                reverse(&mut second);
            }
            first.points.pop();
            first.widths.pop();
            first.points.extend(second.points);
            first.widths.extend(second.widths);
            first.to = second.to;
            self.alive[v] = false;
            self.edges[a] = Some(first);
        }
    }

    /// Inside a junction's own disk the skeleton's pixel paths bend towards whichever junction
    /// pixel they touch, so arms can cross there: each arm is cut where it leaves the disk (radius
    /// the half-width at the junction) and joined straight to the junction.
    fn straighten_junctions(&mut self) {
        let degree = self.degrees();
        for edge in self.edges.iter_mut().flatten() {
            for at_start in [true, false] {
                let v = if at_start { edge.from } else { edge.to };
                if degree[v] < 3 {
                    continue;
                }
                let hub = self.vertices[v].pos;
                let reach = (self.vertices[v].width + 1.0) / 2.0;
                if edge.from == edge.to || edge.points.len() > 2 {
                    cut_arm(edge, at_start, hub, reach);
                }
            }
        }
    }

    fn finish(self, width: u32, height: u32) -> StrokeGraph {
        let degree = self.degrees();
        let mut index = vec![usize::MAX; self.vertices.len()];
        let mut vertices = Vec::new();
        for (i, v) in self.vertices.into_iter().enumerate() {
            if self.alive[i] && (degree[i] > 0 || self.dot[i]) {
                index[i] = vertices.len();
                vertices.push(Vertex {
                    degree: degree[i],
                    ..v
                });
            }
        }
        let edges = self
            .edges
            .into_iter()
            .flatten()
            .map(|mut e| {
                e.from = index[e.from];
                e.to = index[e.to];
                e
            })
            .collect();
        StrokeGraph {
            width,
            height,
            vertices,
            edges,
        }
    }
}

fn reverse(edge: &mut Edge) {
    std::mem::swap(&mut edge.from, &mut edge.to);
    edge.points.reverse();
    edge.widths.reverse();
}

/// Cuts an arm's polyline where it first leaves the disk of radius `reach` around `hub` (from its
/// start when `at_start`, else from its end) and joins it straight to `hub`.
fn cut_arm(edge: &mut Edge, at_start: bool, hub: [f64; 2], reach: f64) {
    if !at_start {
        edge.points.reverse();
        edge.widths.reverse();
    }
    let keep_from = edge
        .points
        .iter()
        .position(|&p| dist(p, hub) > reach)
        .unwrap_or(edge.points.len() - 1)
        .min(edge.points.len() - 1);
    let width = edge.widths.first().copied().unwrap_or(1.0);
    edge.points.drain(..keep_from);
    edge.widths.drain(..keep_from);
    edge.points.insert(0, hub);
    edge.widths.insert(0, width);
    if !at_start {
        edge.points.reverse();
        edge.widths.reverse();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{render, Stroke};
    use crate::Params;

    fn skeleton_params() -> Params {
        Params {
            skeleton: true,
            ..Params::default()
        }
    }

    #[test]
    fn an_x_is_one_crossing_and_every_polyline_stays_on_the_ink() {
        let x = render(
            &[
                Stroke::new(vec![[10.0, 10.0], [90.0, 90.0]], 8.0),
                Stroke::new(vec![[10.0, 90.0], [90.0, 10.0]], 8.0),
            ],
            100,
            100,
        );
        let graph = crate::trace_binary(&x, &skeleton_params())
            .expect("trace")
            .graph;
        graph.validate().expect("valid graph");
        let degrees: Vec<usize> = graph.vertices.iter().map(|v| v.degree).collect();
        assert_eq!(
            degrees.iter().filter(|&&d| d == 4).count(),
            1,
            "{degrees:?}"
        );
        assert_eq!(
            degrees.iter().filter(|&&d| d == 1).count(),
            4,
            "{degrees:?}"
        );
        for edge in &graph.edges {
            for p in &edge.points {
                assert!(
                    x.get(p[0].floor() as i64, p[1].floor() as i64),
                    "{p:?} is off the ink"
                );
            }
        }
    }

    #[test]
    fn a_short_arm_reaches_beyond_its_junction_and_a_bump_does_not() {
        // A junction of width 8 (radius 4.5 with the pixel); a bump ends 3 px out, where the
        // stroke's edge is; an arm of 1.5 widths ends 12 px out with its full width.
        let junction = [0.0, 0.0];
        let envelope = [(junction, 8.0), ([4.0, 0.0], 8.0), ([-4.0, 0.0], 8.0)];
        let bump = spur_reach(&[[0.0, 1.0], [0.0, 3.0]], &[7.0, 1.0], &envelope);
        let arm = spur_reach(&[[0.0, 4.0], [0.0, 12.0]], &[8.0, 6.0], &envelope);
        assert!(bump < 1.0, "{bump}");
        assert!(arm > 0.5 * 8.0, "{arm}");
    }
}
