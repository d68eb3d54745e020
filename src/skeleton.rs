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

use kiddo::{ImmutableKdTree, SquaredEuclidean};

use crate::geometry::{dist, tangents};
use crate::mask::ink_distances;
use crate::point_set::{Grid, PointSet};
use crate::{Binary, Edge, StrokeGraph, Vertex};

/// Strokes at least this wide (px, the legs' median skeleton width) can show a bold corner
/// ([`Work::dissolve_corners`]): below it the skeleton's widths, known to a pixel, do not tell
/// ink where two strokes merge from one stroke.
const BOLD_CORNER_WIDTH: f64 = 5.0;

/// A corner's leg, its points listed from the junction outwards, and the first and last index
/// of the stretch that gives its line.
type LegStretch<'a> = (&'a [[f64; 2]], (usize, usize));

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
    // A copy with a one-pixel background border, so every neighbour is an index offset.
    let pw = width + 2;
    let mut padded = vec![false; pw * (height + 2)];
    for y in 0..height {
        padded[(y + 1) * pw + 1..(y + 1) * pw + 1 + width]
            .copy_from_slice(&ink[y * width..(y + 1) * width]);
    }
    let pw = pw as isize;
    let offsets: [isize; 8] = RING.map(|(dx, dy)| dy as isize * pw + dx as isize);
    // The 8 neighbours as the bits of a byte (bit k: RING[k]), and for each sub-iteration a
    // table of the neighbourhoods whose center goes.
    let bits = |grid: &[bool], i: usize| -> u8 {
        (0..8).fold(0u8, |b, k| {
            b | (u8::from(grid[(i as isize + offsets[k]) as usize]) << k)
        })
    };
    let table: [[bool; 256]; 2] = std::array::from_fn(|step| {
        std::array::from_fn(|n| {
            let p: [bool; 8] = std::array::from_fn(|k| n & (1 << k) != 0);
            let b = p.iter().filter(|&&v| v).count();
            let a = (0..8).filter(|&k| !p[k] && p[(k + 1) % 8]).count();
            let keep = if step == 0 {
                p[2] && p[4] && (p[0] || p[6])
            } else {
                p[0] && p[6] && (p[2] || p[4])
            };
            (2..=6).contains(&b) && a == 1 && !keep
        })
    });
    // Only a pixel with a background neighbour can go; after a sub-iteration only the
    // neighbours of what went can newly have one. Checking just those gives the same result as
    // checking every ink pixel each time, in a time that grows with the ink, not with the ink
    // times the stroke width.
    // A pixel whose neighbourhood has not changed since both sub-iterations checked it cannot
    // go until a neighbour goes: `since` is the sub-iteration it was (re)queued in.
    let mut queued = vec![false; padded.len()];
    let mut since = vec![0u32; padded.len()];
    let mut candidates: Vec<usize> = padded
        .iter()
        .enumerate()
        .filter_map(|(i, &on)| on.then_some(i))
        .filter(|&i| bits(&padded, i) != u8::MAX)
        .collect();
    for &i in &candidates {
        queued[i] = true;
    }
    let mut marked = Vec::new();
    let mut idle = 0;
    let mut step = 0;
    let mut t = 0u32;
    // Stable when two sub-iterations in a row delete nothing.
    while idle < 2 {
        marked.clear();
        marked.extend(
            candidates
                .iter()
                .copied()
                .filter(|&i| table[step][bits(&padded, i) as usize]),
        );
        for &i in &marked {
            padded[i] = false;
            queued[i] = false;
        }
        idle = if marked.is_empty() { idle + 1 } else { 0 };
        // The next candidates: those checked once since their neighbourhood last changed (the
        // other sub-iteration may delete them) and the ink neighbours of every deleted pixel.
        candidates.retain(|&i| {
            let keep = padded[i] && since[i] == t;
            if !keep {
                queued[i] = false;
            }
            keep
        });
        for &i in &marked {
            for offset in offsets {
                let j = (i as isize + offset) as usize;
                if padded[j] {
                    since[j] = t + 1;
                    if !queued[j] {
                        queued[j] = true;
                        candidates.push(j);
                    }
                }
            }
        }
        step = 1 - step;
        t += 1;
    }
    let mut thin = vec![false; width * height];
    for y in 0..height {
        thin[y * width..(y + 1) * width]
            .copy_from_slice(&padded[(y + 1) * pw as usize + 1..(y + 1) * pw as usize + 1 + width]);
    }
    thin
}

/// Zhang-Suen can leave runs two pixels thick (a 45 degree staircase, an L-shaped step) whose
/// pixels all have three or more skeleton neighbours, so the graph would make one junction of the
/// whole run. Removes, in raster order until none is left, every skeleton pixel that is simple
/// (its removal changes neither the skeleton's 8-connectivity nor its holes: Yokoi's
/// 8-connectivity number is 1) and is no tip: it has three or more skeleton neighbours, or two
/// that make it the inner corner of an L. Ends, the middle pixels of one-pixel lines and the
/// centers of real junctions are not simple.
pub fn one_pixel_thick(skeleton: &mut [bool], width: usize, height: usize) {
    let (w, h) = (width as i64, height as i64);
    let on =
        |s: &[bool], x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && s[(y * w + x) as usize];
    // Neighbours counter-clockwise from east: E, NE, N, NW, W, SW, S, SE.
    const AROUND: [(i64, i64); 8] = [
        (1, 0),
        (1, -1),
        (0, -1),
        (-1, -1),
        (-1, 0),
        (-1, 1),
        (0, 1),
        (1, 1),
    ];
    let mut candidates: Vec<usize> = skeleton
        .iter()
        .enumerate()
        .filter_map(|(i, &on)| on.then_some(i))
        .collect();
    loop {
        let mut changed = false;
        for &i in &candidates {
            if !skeleton[i] {
                continue;
            }
            let (x, y) = ((i as i64) % w, (i as i64) / w);
            let n: [bool; 8] =
                std::array::from_fn(|k| on(skeleton, x + AROUND[k].0, y + AROUND[k].1));
            // Two neighbours: only the inner corner of an L step (both of them 4-neighbours)
            // goes; two neighbours side by side are the tip of a run, which removing would
            // shorten (the run would be eaten away from its end).
            match n.iter().filter(|&&v| v).count() {
                0 | 1 => continue,
                2 if (0..8).step_by(2).filter(|&k| n[k]).count() != 2 => continue,
                _ => {}
            }
            // Yokoi: C8 = sum over k in {0, 2, 4, 6} of x'k - x'k x'k+1 x'k+2, x' = not x.
            let c8: i32 = (0..4)
                .map(|j| {
                    let k = 2 * j;
                    let (a, b, c) = (!n[k], !n[k + 1], !n[(k + 2) % 8]);
                    i32::from(a) - i32::from(a && b && c)
                })
                .sum();
            if c8 == 1 {
                skeleton[i] = false;
                changed = true;
            }
        }
        if !changed {
            return;
        }
        candidates.retain(|&i| skeleton[i]);
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
    half_width: &[f32],
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
        (2.0 * f64::from(half_width[(y * w + x) as usize]) - 1.0).max(1.0)
    };
    // Neighbour counts (at most 8) and vertex ids, kept small: the window can be a whole page.
    // The skeleton's pixels, in raster order: every pass below walks these, not the window.
    let pixels: Vec<usize> = skeleton
        .iter()
        .enumerate()
        .filter_map(|(i, &on)| on.then_some(i))
        .collect();
    let mut count = vec![0u8; skeleton.len()];
    for &i in &pixels {
        count[i] = neighbours(i).count() as u8;
    }

    const NONE: u32 = u32::MAX;
    let mut vertex_of = vec![NONE; skeleton.len()];
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut stack = Vec::new();
    for &i in &pixels {
        if vertex_of[i] != NONE || count[i] == 2 {
            continue;
        }
        let id = vertices.len();
        let mut sum = [0.0, 0.0];
        let mut members = 0.0;
        if count[i] > 2 {
            stack.push(i);
            vertex_of[i] = id as u32;
            while let Some(j) = stack.pop() {
                let c = center(j);
                sum = [sum[0] + c[0], sum[1] + c[1]];
                members += 1.0;
                for k in neighbours(j) {
                    if count[k] > 2 && vertex_of[k] == NONE {
                        vertex_of[k] = id as u32;
                        stack.push(k);
                    }
                }
            }
        } else {
            vertex_of[i] = id as u32;
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
    for &a in pixels.iter().filter(|&&i| vertex_of[i] != NONE) {
        let from = vertex_of[a] as usize;
        for u in neighbours(a) {
            if vertex_of[u] != NONE {
                if vertex_of[u] as usize != from && a < u {
                    let points = vec![vertices[from].pos, vertices[vertex_of[u] as usize].pos];
                    make_edge(from, vertex_of[u] as usize, points, &mut edges);
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
                    Some(k) if vertex_of[k] != NONE => break Some(vertex_of[k] as usize),
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
    for &s in pixels.iter().filter(|&&i| count[i] == 2) {
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

/// Zhang-Suen thinning of `binary` (whose size [`Binary::check_size`] has checked) and the
/// [`pixel_graph`] of its skeleton, half-widths from the exact distance transform of the ink: what
/// thinning tools give, without any decision of the method.
pub(crate) fn thin(binary: &Binary) -> StrokeGraph {
    let (w, h) = (binary.width as usize, binary.height as usize);
    if w == 0 || h == 0 {
        return StrokeGraph {
            width: binary.width,
            height: binary.height,
            ..StrokeGraph::default()
        };
    }
    let skeleton = zhang_suen(&binary.ink, w, h);
    let mut half = vec![0f32; w * h];
    let ink_pixels = (0..w * h).filter(|&i| binary.ink[i]);
    for (i, d) in ink_pixels.zip(ink_distances(&binary.ink, w, h)) {
        half[i] = d;
    }
    pixel_graph(w, h, &skeleton, &half)
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
    let half: Vec<f32> = grid
        .index
        .iter()
        .map(|&i| match i {
            Grid::NONE => 0.0,
            i => points.half_width[i as usize],
        })
        .collect();
    let mut ink = ink;
    fill_specks(&mut ink, w, h);
    let mut skeleton = zhang_suen(&ink, w, h);
    one_pixel_thick(&mut skeleton, w, h);
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
    let ink = Ink {
        mask: ink,
        width: w,
        height: h,
        origin: [x0, y0],
    };
    let mut work = Work::new(s, ink);
    work.prune_spurs();
    work.join_degree_two();
    work.contract_short_links();
    work.merge_crossings(method);
    work.prune_spurs();
    // A dissolved corner lengthens its neighbours' legs (the corners of a small `w` share them):
    // repeated until none is left.
    while work.dissolve_corners() {
        work.join_degree_two();
    }
    work.join_degree_two();
    work.collapse_dots();
    work.extend_ends();
    work.straighten_junctions();
    work.adopt_method_geometry(method);
    work.finish(method.width, method.height)
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
fn keep_every_component(ink: &[bool], half: &[f32], w: usize, h: usize, skeleton: &mut [bool]) {
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

/// An ink mask over a window of the image.
struct Ink {
    mask: Vec<bool>,
    width: usize,
    height: usize,
    /// The image coordinates of the window's corner.
    origin: [f64; 2],
}

impl Ink {
    fn at(&self, p: [f64; 2]) -> bool {
        let (x, y) = (
            (p[0] - self.origin[0]).floor(),
            (p[1] - self.origin[1]).floor(),
        );
        x >= 0.0
            && y >= 0.0
            && (x as usize) < self.width
            && (y as usize) < self.height
            && self.mask[y as usize * self.width + x as usize]
    }

    /// How far the ink goes on from `from` along the unit vector `u`: the first sample, every
    /// half pixel from half a pixel on, that is off the ink or beyond `limit`.
    fn exit(&self, from: [f64; 2], u: [f64; 2], limit: f64) -> f64 {
        let mut t = 0.5;
        while t <= limit && self.at([from[0] + t * u[0], from[1] + t * u[1]]) {
            t += 0.5;
        }
        t
    }

    /// Whether the segment `a`-`b` lies on the ink, sampled every half pixel.
    fn holds(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let n = (dist(a, b) * 2.0).ceil().max(1.0) as usize;
        (0..=n).all(|i| {
            let t = i as f64 / n as f64;
            self.at([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
        })
    }
}

/// The skeleton graph being edited: removed edges are `None`, removed vertices `alive == false`.
struct Work {
    /// The ink the skeleton was thinned from, to keep every straightened line on it.
    ink: Ink,
    vertices: Vec<Vertex>,
    alive: Vec<bool>,
    /// Vertices that were dots (no edge) from the start: kept with degree 0.
    dot: Vec<bool>,
    edges: Vec<Option<Edge>>,
}

impl Work {
    fn new(graph: StrokeGraph, ink: Ink) -> Work {
        let n = graph.vertices.len();
        let dot = graph.vertices.iter().map(|v| v.degree == 0).collect();
        Work {
            ink,
            vertices: graph.vertices,
            alive: vec![true; n],
            dot,
            // Tangents are written by `finish`, once the polylines are final.
            edges: graph
                .edges
                .into_iter()
                .map(|mut e| {
                    e.directions.clear();
                    Some(e)
                })
                .collect(),
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
    /// nearer to it than to any other of the method's junctions and within 5 of its widths,
    /// linked by short skeleton edges (at most that radius) that form a tree (no hole among
    /// them), and leaving by exactly as many arms as the crossing has, become one vertex at the
    /// crossing. A long edge between two of them (the loop of an `8` closing on its waist)
    /// becomes a loop at the crossing. Each arm is cut where it leaves the merged junctions'
    /// reach and joined straight to the crossing.
    fn merge_crossings(&mut self, method: &StrokeGraph) {
        let junctions: Vec<&Vertex> = method.vertices.iter().filter(|v| v.degree >= 3).collect();
        if !junctions.iter().any(|v| v.degree >= 4) {
            return;
        }
        let positions: Vec<[f64; 2]> = junctions.iter().map(|v| v.pos).collect();
        let Ok(tree) = ImmutableKdTree::<f64, 2>::new_from_slice(&positions) else {
            return;
        };
        let mut degree = self.degrees();
        let mut at = self.incidence();
        // The skeleton junctions each crossing owns (its nearest method junction is the crossing).
        let mut owned: Vec<Vec<usize>> = vec![Vec::new(); junctions.len()];
        for i in (0..self.vertices.len()).filter(|&i| self.alive[i] && degree[i] >= 3) {
            let nearest = tree
                .query(&self.vertices[i].pos)
                .nearest_one::<SquaredEuclidean<f64>>()
                .execute();
            let owner = nearest.item as usize;
            let c = junctions[owner];
            // The Y's of an acute crossing lie about (w / 2) / sin(theta / 2) from it, 3.8 w at
            // 15 degrees, and the method's width at a crossing can be a little less than the
            // strokes': 5 widths.
            if c.degree >= 4 && dist(self.vertices[i].pos, c.pos) <= 5.0 * c.width.max(2.0) {
                owned[owner].push(i);
            }
        }
        let mut mark = vec![usize::MAX; self.vertices.len()];
        let length = Edge::length;
        for (owner, near) in owned.iter().enumerate() {
            if near.len() < 2 {
                continue;
            }
            let c = junctions[owner];
            let radius = 5.0 * c.width.max(2.0);
            for &i in near {
                mark[i] = owner;
            }
            let Some(&seed) = near.iter().min_by(|&&a, &&b| {
                dist(self.vertices[a].pos, c.pos)
                    .total_cmp(&dist(self.vertices[b].pos, c.pos))
                    .then(a.cmp(&b))
            }) else {
                continue;
            };
            // The skeleton junctions linked to the one nearest the crossing by edges among them
            // (at most 2 radii long: two junctions within the radius), and the links.
            let mut group = vec![seed];
            let mut links: Vec<usize> = Vec::new();
            let mut next = 0;
            while next < group.len() {
                let g = group[next];
                next += 1;
                for &e in &at[g] {
                    let Some(edge) = &self.edges[e] else { continue };
                    let other = if edge.from == g { edge.to } else { edge.from };
                    if other == g || mark[other] != owner || length(edge) > 2.0 * radius {
                        continue;
                    }
                    if !links.contains(&e) {
                        links.push(e);
                    }
                    if !group.contains(&other) {
                        group.push(other);
                    }
                }
            }
            for &i in near {
                mark[i] = usize::MAX;
            }
            if group.len() < 2 {
                continue;
            }
            // The shortest links that join the group (Kruskal) are merged away. A link that
            // would close a cycle goes round a hole among the junctions (a cell of a grid): then
            // they are not one crossing. (A longer edge between two of them, the loop of an `8`,
            // is no link and stays, as a loop at the crossing.)
            links.sort_by(|&a, &b| {
                let (la, lb) = (
                    self.edges[a].as_ref().map_or(0.0, length),
                    self.edges[b].as_ref().map_or(0.0, length),
                );
                la.total_cmp(&lb).then(a.cmp(&b))
            });
            let mut root: Vec<usize> = (0..group.len()).collect();
            fn find(root: &mut [usize], mut i: usize) -> usize {
                while root[i] != i {
                    root[i] = root[root[i]];
                    i = root[i];
                }
                i
            }
            let slot = |v: usize| group.iter().position(|&g| g == v).unwrap_or(0);
            let mut internal = Vec::new();
            for &e in &links {
                let Some(edge) = &self.edges[e] else { continue };
                let (ra, rb) = (
                    find(&mut root, slot(edge.from)),
                    find(&mut root, slot(edge.to)),
                );
                if ra != rb {
                    root[ra] = rb;
                    internal.push(e);
                }
            }
            if internal.len() != links.len() {
                continue;
            }
            let arms: usize = group.iter().map(|&i| degree[i]).sum::<usize>() - 2 * internal.len();
            if arms != c.degree {
                continue;
            }
            // The arms bend towards the skeleton's Y's within about half a width of them: they
            // are cut beyond that and run straight to the crossing, or just beyond the Y's
            // where that line would leave the ink; where both would, this is no crossing.
            let spread = group
                .iter()
                .map(|&i| dist(self.vertices[i].pos, c.pos))
                .fold(0.0f64, f64::max);
            let arms_hold = |reach: f64| {
                group.iter().all(|&i| {
                    at[i].iter().all(|&e| {
                        let Some(edge) = self.edges[e].as_ref() else {
                            return true;
                        };
                        if internal.contains(&e) {
                            return true;
                        }
                        let ends = [edge.from == i, edge.to == i];
                        ends.iter().enumerate().all(|(end, &here)| {
                            if !here {
                                return true;
                            }
                            self.ink
                                .holds(c.pos, cut_point(edge, end == 0, c.pos, reach))
                        })
                    })
                })
            };
            let Some(reach) = [spread + 0.5 * c.width, spread]
                .into_iter()
                .find(|&r| arms_hold(r))
            else {
                continue;
            };
            for &e in &internal {
                self.edges[e] = None;
            }
            let hub = group[0];
            self.vertices[hub].pos = c.pos;
            self.vertices[hub].width = c.width;
            let mut hub_edges = Vec::new();
            for &i in &group {
                if i != hub {
                    self.alive[i] = false;
                }
                for &e in &at[i] {
                    let Some(edge) = self.edges[e].as_mut() else {
                        continue;
                    };
                    if hub_edges.contains(&e) {
                        continue;
                    }
                    hub_edges.push(e);
                    for end in 0..2 {
                        let at_end = if end == 0 { edge.from } else { edge.to };
                        if !group.contains(&at_end) {
                            continue;
                        }
                        if end == 0 {
                            edge.from = hub;
                        } else {
                            edge.to = hub;
                        }
                        cut_arm(edge, end == 0, c.pos, reach);
                    }
                }
                if i != hub {
                    at[i].clear();
                    degree[i] = 0;
                }
            }
            degree[hub] = arms;
            at[hub] = hub_edges;
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
            // The envelope reaches at most about 4 widths from the junction: a branch whose tip
            // lies beyond 5 reaches beyond it.
            let tip_pos = self.vertices[tip].pos;
            if dist(tip_pos, j.pos) > 5.0 * stroke.max(1.0) + 2.0 {
                continue;
            }
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
    /// within the stroke's half-width of `v`, plus the uncertainty of `v` and a tenth of the
    /// width: no ink reaches beyond the corner the two legs make by themselves. Then the stub and the
    /// junction go, and both legs run straight to `v`, the bend.
    ///
    /// A bold corner (strokes of at least [`BOLD_CORNER_WIDTH`], both legs much wider at the
    /// junction than a stroke: their inks merge over a length of about `w / (2 tan(θ / 2))`)
    /// may leave no straight leg beyond the stub's reach; its legs' lines are then taken where
    /// each leg is one stroke wide again, and the bend is placed no deeper than half a width
    /// inside the ink's end along the bisector (a round corner's centre; the lines of a mitred
    /// corner meet before that). docs/quality.md, "Bold corners".
    fn dissolve_corners(&mut self) -> bool {
        let mut changed = false;
        let at = self.incidence();
        let degree = self.degrees();
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
            // Every edge's points and widths listed from the junction outwards.
            let outwards = |e: usize| -> (Vec<[f64; 2]>, Vec<f64>) {
                let edge = self.edges[e].as_ref().expect("live edge");
                let (mut points, mut widths) = (edge.points.clone(), edge.widths.clone());
                if edge.from != j {
                    points.reverse();
                    widths.reverse();
                }
                (points, widths)
            };
            let (stub_points, _) = outwards(stub);
            let (jp, tip) = (self.vertices[j].pos, stub_points[stub_points.len() - 1]);
            let stroke = legs
                .iter()
                .filter_map(|&e| self.edges[e].as_ref())
                .map(|e| median(&e.widths))
                .fold(f64::INFINITY, f64::min);
            let half = (stroke + 1.0) / 2.0;
            let reach = dist(jp, tip);
            let (leg_a, leg_b) = (outwards(legs[0]), outwards(legs[1]));
            let bold = stroke >= BOLD_CORNER_WIDTH
                && [&leg_a, &leg_b]
                    .iter()
                    .all(|(_, widths)| widths[0] > 1.25 * stroke + 1.0);
            // Each leg's stretch for its line, pointing towards the corner: from `reach` to
            // `reach + 2 w` from the junction (where it no longer bends towards the other leg);
            // for a bold corner whose leg is still wider than a stroke there, from where it is
            // one stroke wide again, up to `2 w` long.
            let beyond_reach = |points: &[[f64; 2]]| -> Option<(usize, usize)> {
                let near = points.iter().position(|&p| dist(p, jp) >= reach)?;
                let far = points
                    .iter()
                    .position(|&p| dist(p, jp) >= reach + 2.0 * stroke)
                    .unwrap_or(points.len() - 1);
                Some((near, far))
            };
            let one_stroke = |(points, widths): &(Vec<[f64; 2]>, Vec<f64>),
                              reached: (usize, usize)| {
                let single = |i: usize| widths[i] <= stroke + 1.0;
                if (reached.0..=reached.1).all(single) {
                    return Some(reached);
                }
                let start =
                    (0..points.len()).find(|&i| single(i) && dist(points[i], jp) >= half)?;
                let mut end = start;
                while end + 1 < points.len()
                    && single(end + 1)
                    && dist(points[end + 1], points[start]) <= 2.0 * stroke
                {
                    end += 1;
                }
                (dist(points[start], points[end]) >= (0.5 * stroke).max(3.0))
                    .then_some((start, end))
            };
            let (Some(reached_a), Some(reached_b)) =
                (beyond_reach(&leg_a.0), beyond_reach(&leg_b.0))
            else {
                continue;
            };
            let corner = |sa: (usize, usize), sb: (usize, usize)| {
                self.corner_of(
                    jp,
                    tip,
                    &stub_points,
                    stroke,
                    bold,
                    [(&leg_a.0[..], sa), (&leg_b.0[..], sb)],
                )
            };
            // A bold corner tries the one-stroke stretches first, then (where they differ) the
            // stretches beyond the stub's reach, as every other corner.
            let first = if bold {
                one_stroke(&leg_a, reached_a).zip(one_stroke(&leg_b, reached_b))
            } else {
                None
            };
            let found = match first {
                Some((sa, sb)) if (sa, sb) != (reached_a, reached_b) => {
                    corner(sa, sb).or_else(|| corner(reached_a, reached_b))
                }
                _ => corner(reached_a, reached_b),
            };
            let Some((v, cut_a, cut_b)) = found else {
                continue;
            };
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

    /// The bend of a corner at the junction `jp` whose stub ends at `tip` (see
    /// [`Work::dissolve_corners`]), from its two legs' points listed outwards and the stretch of
    /// each that gives its line: the bend and, per leg, how many points it loses.
    fn corner_of(
        &self,
        jp: [f64; 2],
        tip: [f64; 2],
        stub_points: &[[f64; 2]],
        stroke: f64,
        bold: bool,
        legs: [LegStretch; 2],
    ) -> Option<([f64; 2], usize, usize)> {
        let half = (stroke + 1.0) / 2.0;
        let reach = dist(jp, tip);
        let line = |(points, (near, far)): LegStretch| {
            let (a, b) = (points[near], points[far]);
            let d = [a[0] - b[0], a[1] - b[1]];
            let n = d[0].hypot(d[1]);
            (n >= 1.0).then(|| (a, [d[0] / n, d[1] / n], near))
        };
        let ((a, ua, cut_a), (b, ub, cut_b)) = (line(legs[0])?, line(legs[1])?);
        // The legs leave the corner at less than 120 degrees: -ua . -ub > cos 120.
        let cross = ua[0] * ub[1] - ua[1] * ub[0];
        if ua[0] * ub[0] + ua[1] * ub[1] <= (120f64).to_radians().cos() || cross.abs() < 1e-6 {
            return None;
        }
        // a + s ua = b + t ub.
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let (s, t) = (
            (dx * ub[1] - dy * ub[0]) / cross,
            (dx * ua[1] - dy * ua[0]) / cross,
        );
        if s < 0.0 || t < 0.0 {
            return None;
        }
        let v = [a[0] + s * ua[0], a[1] + s * ua[1]];
        // The legs' lines are known to about a pixel across, which moves where they meet by
        // 1 / sin(theta / 2) along the bisector (theta the corner's angle); beyond that, the
        // ink may stick out by a tenth of the width before it is an end of its own (a brush's
        // overshoot at the corner of a box).
        let half_angle = (ua[0] * ub[0] + ua[1] * ub[1]).clamp(-1.0, 1.0).acos() / 2.0;
        let margin = 0.1 * stroke + 1.0 / half_angle.sin().max(0.1);
        let on_stub = stub_points
            .iter()
            .map(|&p| dist(p, v))
            .fold(f64::INFINITY, f64::min)
            <= half + margin;
        if !on_stub || dist(v, tip) > half + margin {
            return None;
        }
        let along = dist(jp, v);
        let v = if bold && along > 0.0 {
            // No deeper than half a width inside the ink's end along the bisector.
            let u = [(v[0] - jp[0]) / along, (v[1] - jp[1]) / along];
            let inside = (self.ink.exit(jp, u, along + stroke) - half).max(0.0);
            if along > inside {
                [jp[0] + inside * u[0], jp[1] + inside * u[1]]
            } else {
                v
            }
        } else if along > reach {
            // Where the legs' lines meet beyond the stub's tip, the bend is the tip (on the ink).
            tip
        } else {
            v
        };
        (self.ink.holds(v, a) && self.ink.holds(v, b)).then_some((v, cut_a, cut_b))
    }

    /// Two skeleton junctions closer than the ink can show apart (a link of at most
    /// `max(3 px, w / 2)`, `w` its median width): thinning splits a crossing of thin strokes
    /// into two Y's a pixel or two apart. The link is contracted to its middle; a second edge
    /// between the two becomes a loop, so no cycle is lost.
    fn contract_short_links(&mut self) {
        let mut degree = self.degrees();
        let mut at = self.incidence();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            let (a, b) = (edge.from, edge.to);
            if a == b || degree[a] < 3 || degree[b] < 3 {
                continue;
            }
            let length = edge.length();
            if length > (0.5 * median(&edge.widths)).max(3.0) {
                continue;
            }
            let middle = {
                let (p, q) = (self.vertices[a].pos, self.vertices[b].pos);
                [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]
            };
            self.edges[e] = None;
            let moved: Vec<usize> = at[b].clone();
            for &o in &moved {
                let Some(other) = self.edges[o].as_mut() else {
                    continue;
                };
                if other.from == b {
                    other.from = a;
                }
                if other.to == b {
                    other.to = a;
                }
            }
            for &o in at[a].iter().chain(&moved) {
                let Some(other) = self.edges[o].as_mut() else {
                    continue;
                };
                if other.from == a {
                    other.points[0] = middle;
                }
                if other.to == a {
                    let last = other.points.len() - 1;
                    other.points[last] = middle;
                }
            }
            let width = self.vertices[a].width.max(self.vertices[b].width);
            self.vertices[a].pos = middle;
            self.vertices[a].width = width;
            self.alive[b] = false;
            degree[a] = degree[a] + degree[b] - 2;
            degree[b] = 0;
            let mut joined = std::mem::take(&mut at[a]);
            joined.extend(moved);
            joined.retain(|&o| o != e);
            joined.sort_unstable();
            joined.dedup();
            at[a] = joined;
            at[b].clear();
        }
    }

    /// Thinning erodes a stroke's end, most along a diagonal: each end is carried on along its
    /// own direction (taken over the last two widths) to where the ink ends, less the stroke's
    /// half-width, the centre of its cap. Ends are only ever lengthened.
    fn extend_ends(&mut self) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            for at_start in [true, false] {
                let Some(edge) = &self.edges[e] else { break };
                let v = if at_start { edge.from } else { edge.to };
                if degree[v] != 1 || edge.from == edge.to || edge.points.len() < 2 {
                    continue;
                }
                let stroke = median(&edge.widths);
                let half = (stroke + 1.0) / 2.0;
                let mut inwards: Vec<[f64; 2]> = edge.points.clone();
                if !at_start {
                    inwards.reverse();
                }
                let tip = inwards[0];
                let back = inwards
                    .iter()
                    .find(|&&p| dist(p, tip) >= 2.0 * stroke.max(1.5))
                    .copied()
                    .unwrap_or(inwards[inwards.len() - 1]);
                let d = [tip[0] - back[0], tip[1] - back[1]];
                let n = d[0].hypot(d[1]);
                if n < 1.0 {
                    continue;
                }
                let u = [d[0] / n, d[1] / n];
                // Where the ink ends ahead of the tip (at most a few widths on).
                let reach = self.ink.exit(tip, u, 2.0 * stroke + 4.0) - half;
                if reach < 1.0 {
                    continue;
                }
                let end = [tip[0] + reach * u[0], tip[1] + reach * u[1]];
                let width = edge.widths[if at_start { 0 } else { edge.widths.len() - 1 }];
                let edge = self.edges[e].as_mut().expect("live edge");
                if at_start {
                    edge.points.insert(0, end);
                    edge.widths.insert(0, width);
                } else {
                    edge.points.push(end);
                    edge.widths.push(width);
                }
                self.vertices[v].pos = end;
            }
        }
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
            let length = edge.length();
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
        let degree = self.degrees();
        let mut at = self.incidence();
        for v in 0..self.vertices.len() {
            if !self.alive[v] || degree[v] != 2 {
                continue;
            }
            let incident: Vec<usize> = at[v]
                .iter()
                .copied()
                .filter(|&e| self.edges[e].is_some())
                .collect();
            let [a, b] = incident[..] else { continue };
            let is_loop = |e: usize| self.edges[e].as_ref().is_some_and(|x| x.from == x.to);
            if a == b || is_loop(a) || is_loop(b) {
                continue;
            }
            let (Some(mut first), Some(mut second)) = (self.edges[a].take(), self.edges[b].take())
            else {
                continue;
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
            let far = first.to;
            self.alive[v] = false;
            self.edges[a] = Some(first);
            at[v].clear();
            for e in &mut at[far] {
                if *e == b {
                    *e = a;
                }
            }
            at[far].sort_unstable();
            at[far].dedup();
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
                if (edge.from == edge.to || edge.points.len() > 2)
                    && self.ink.holds(hub, cut_point(edge, at_start, hub, reach))
                {
                    cut_arm(edge, at_start, hub, reach);
                }
            }
        }
    }

    /// Geometry where the method is right (§3.4's fitted polylines, smooth and centred below
    /// a pixel): a skeleton vertex is matched to the nearest of the method's vertices of the
    /// same kind (an end to an end, a junction to a junction of the same degree) within
    /// `max(2 px, w)`, and a skeleton edge between two matched vertices takes the polyline of
    /// the method's edge between their partners when the two lie within `max(1.5 px, w / 2)`
    /// of each other everywhere (so the method's line keeps to this stroke's ink). The
    /// skeleton keeps its own paths wherever the method's graph differs: chords, fused
    /// junctions, lost arms and loops (docs/quality.md, "Fidelity directions").
    fn adopt_method_geometry(&mut self, method: &StrokeGraph) {
        if method.vertices.is_empty() {
            return;
        }
        let positions: Vec<[f64; 2]> = method.vertices.iter().map(|v| v.pos).collect();
        let Ok(tree) = ImmutableKdTree::<f64, 2>::new_from_slice(&positions) else {
            return;
        };
        let mut method_at = vec![Vec::new(); method.vertices.len()];
        for (f, edge) in method.edges.iter().enumerate() {
            method_at[edge.from].push(f);
            if edge.to != edge.from {
                method_at[edge.to].push(f);
            }
        }
        let degree = self.degrees();
        let at = self.incidence();
        // The stroke width at a vertex: the widest median of its edges.
        let stroke_at = |v: usize| {
            at[v]
                .iter()
                .filter_map(|&e| self.edges[e].as_ref())
                .map(|e| median(&e.widths))
                .fold(1.0f64, f64::max)
        };
        let mut partner = vec![usize::MAX; self.vertices.len()];
        let mut taken = vec![false; method.vertices.len()];
        let mut order: Vec<(f64, usize, usize)> = Vec::new();
        for v in (0..self.vertices.len()).filter(|&v| self.alive[v] && degree[v] != 2) {
            if degree[v] == 0 {
                continue;
            }
            let reach = stroke_at(v).max(2.0);
            let pos = self.vertices[v].pos;
            for found in tree
                .query(&pos)
                .within::<SquaredEuclidean<f64>>(reach * reach)
                .execute()
            {
                let m = found.item as usize;
                let dm = method.vertices[m].degree;
                if (degree[v] == 1 && dm == 1) || (degree[v] >= 3 && dm == degree[v]) {
                    order.push((found.distance, v, m));
                }
            }
        }
        // Nearest pairs first, each vertex matched once.
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        for (_, v, m) in order {
            if partner[v] == usize::MAX && !taken[m] {
                partner[v] = m;
                taken[m] = true;
            }
        }
        let mut used = vec![false; method.edges.len()];
        let mut moved = vec![false; self.vertices.len()];
        let bbox = |points: &[[f64; 2]]| {
            points.iter().fold(
                [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ],
                |b, p| {
                    [
                        b[0].min(p[0]),
                        b[1].min(p[1]),
                        b[2].max(p[0]),
                        b[3].max(p[1]),
                    ]
                },
            )
        };
        // The method's closed curves without a junction (a ring, a closed ridge).
        let method_rings: Vec<(usize, [f64; 4])> = method
            .edges
            .iter()
            .enumerate()
            .filter(|(_, f)| f.from == f.to && method.vertices[f.from].degree == 2)
            .map(|(f, edge)| (f, bbox(&edge.points)))
            .collect();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            let loose = (0.5 * median(&edge.widths)).max(1.0);
            let ring = edge.from == edge.to && degree[edge.from] == 2;
            let candidates: Vec<(usize, bool)> = if ring {
                let b = bbox(&edge.points);
                method_rings
                    .iter()
                    .filter(|(_, r)| {
                        r[0] <= b[2] + loose
                            && b[0] <= r[2] + loose
                            && r[1] <= b[3] + loose
                            && b[1] <= r[3] + loose
                    })
                    .map(|&(f, _)| (f, true))
                    .collect()
            } else {
                let (a, b) = (partner[edge.from], partner[edge.to]);
                if a == usize::MAX || b == usize::MAX {
                    continue;
                }
                method_at[a]
                    .iter()
                    .map(|&f| (f, &method.edges[f]))
                    .filter(|(_, c)| (c.from == a && c.to == b) || (c.from == b && c.to == a))
                    .map(|(f, c)| (f, c.from == a && c.to == b))
                    .collect()
            };
            let mut best: Option<(f64, usize, bool)> = None;
            for (f, forward) in candidates {
                if used[f] {
                    continue;
                }
                let line = &method.edges[f].points;
                if !line.windows(2).all(|s| self.ink.holds(s[0], s[1])) {
                    continue;
                }
                if let Some(gap) = follows(&edge.points, line, 1.0, loose) {
                    if best.is_none_or(|(g, ..)| gap < g) {
                        best = Some((gap, f, forward));
                    }
                }
            }
            if ring {
                if let Some((_, f, _)) = best {
                    partner[edge.from] = method.edges[f].from;
                }
            }
            let Some((_, f, forward)) = best else {
                continue;
            };
            used[f] = true;
            let source = &method.edges[f];
            let mut points = source.points.clone();
            let mut widths = source.widths.clone();
            let mut directions = source.directions.clone();
            if !forward {
                points.reverse();
                widths.reverse();
                directions.reverse();
                for d in &mut directions {
                    *d = [-d[0], -d[1]];
                }
            }
            let edge = self.edges[e].as_mut().expect("live edge");
            edge.points = points;
            edge.widths = widths;
            edge.directions = directions;
            for v in [edge.from, edge.to] {
                moved[v] = true;
            }
        }
        // The vertices whose edges took the method's lines sit where the method put them; the
        // skeleton edges that meet them there are joined to the new position.
        for v in (0..self.vertices.len()).filter(|&v| moved[v]) {
            let pos = method.vertices[partner[v]].pos;
            self.vertices[v].pos = pos;
            for &e in &at[v] {
                let Some(edge) = self.edges[e].as_mut() else {
                    continue;
                };
                if edge.from == v {
                    edge.points[0] = pos;
                }
                if edge.to == v {
                    let last = edge.points.len() - 1;
                    edge.points[last] = pos;
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
                // The method's lines keep their fitted tangents; the skeleton's get theirs.
                if e.directions.len() != e.points.len() {
                    e.directions = tangents(&e.points);
                }
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

/// How closely two polylines follow each other: `None` when a point of either lies farther than
/// `loose` from the other, or when more than a tenth of either's points lie farther than
/// `tight`; else the largest distance.
fn follows(p: &[[f64; 2]], q: &[[f64; 2]], tight: f64, loose: f64) -> Option<f64> {
    // Squared distances, compared with squared bounds.
    let (tight2, loose2) = (tight * tight, loose * loose);
    // The segments of `to` bucketed in square cells at least `2 loose` across, so a point only
    // looks at the segments of the (at most four) cells within `loose` of it: linear in the
    // points, however long the lines (a page-long stroke has tens of thousands).
    let cell = (2.0 * loose).max(4.0);
    let key = |v: f64| (v / cell).floor() as i64;
    let directed = |from: &[[f64; 2]], to: &[[f64; 2]]| -> Option<f64> {
        let segments: Vec<([f64; 2], [f64; 2])> = match to {
            [only] => vec![(*only, *only)],
            _ => to.windows(2).map(|s| (s[0], s[1])).collect(),
        };
        let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>> =
            std::collections::HashMap::new();
        for (k, &(a, b)) in segments.iter().enumerate() {
            for cx in key(a[0].min(b[0]))..=key(a[0].max(b[0])) {
                for cy in key(a[1].min(b[1]))..=key(a[1].max(b[1])) {
                    buckets.entry((cx, cy)).or_default().push(k);
                }
            }
        }
        let mut worst = 0.0f64;
        let mut off = 0;
        for &x in from {
            let mut d2 = f64::INFINITY;
            for cx in key(x[0] - loose)..=key(x[0] + loose) {
                for cy in key(x[1] - loose)..=key(x[1] + loose) {
                    for &k in buckets.get(&(cx, cy)).map_or(&[][..], Vec::as_slice) {
                        let (a, b) = segments[k];
                        d2 = d2.min(crate::geometry::segment_dist2(x, a, b));
                    }
                }
            }
            if d2 > loose2 {
                return None;
            }
            if d2 > tight2 {
                off += 1;
            }
            worst = worst.max(d2);
        }
        (off * 10 <= from.len()).then_some(worst.sqrt())
    };
    if p.is_empty() || q.is_empty() {
        return None;
    }
    Some(directed(p, q)?.max(directed(q, p)?))
}

/// The median of a polyline's widths (1 for none): the stroke's width, unmoved by the wider
/// pixels where it meets another.
fn median(widths: &[f64]) -> f64 {
    let mut sorted = widths.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(1.0)
}

fn reverse(edge: &mut Edge) {
    std::mem::swap(&mut edge.from, &mut edge.to);
    edge.points.reverse();
    edge.widths.reverse();
}

/// The index of the point where an arm first leaves the disk of radius `reach` around `hub`,
/// walking from its start when `at_start`, else from its end; the far end when it never does.
fn cut_index(points: &[[f64; 2]], at_start: bool, hub: [f64; 2], reach: f64) -> usize {
    let n = points.len();
    let beyond = |i: &usize| dist(points[*i], hub) > reach;
    if at_start {
        (0..n).find(beyond).unwrap_or(n - 1)
    } else {
        (0..n).rev().find(beyond).unwrap_or(0)
    }
}

/// Where [`cut_arm`] would cut.
fn cut_point(edge: &Edge, at_start: bool, hub: [f64; 2], reach: f64) -> [f64; 2] {
    edge.points[cut_index(&edge.points, at_start, hub, reach)]
}

/// Cuts an arm's polyline where it first leaves the disk of radius `reach` around `hub` (from its
/// start when `at_start`, else from its end) and joins it straight to `hub`.
fn cut_arm(edge: &mut Edge, at_start: bool, hub: [f64; 2], reach: f64) {
    let cut = cut_index(&edge.points, at_start, hub, reach);
    if at_start {
        let width = edge.widths.first().copied().unwrap_or(1.0);
        edge.points.drain(..cut);
        edge.widths.drain(..cut);
        edge.points.insert(0, hub);
        edge.widths.insert(0, width);
    } else {
        let width = edge.widths.last().copied().unwrap_or(1.0);
        edge.points.truncate(cut + 1);
        edge.widths.truncate(cut + 1);
        edge.points.push(hub);
        edge.widths.push(width);
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

    fn traced(strokes: &[Stroke], w: u32, h: u32) -> (crate::Binary, StrokeGraph) {
        let binary = render(strokes, w, h);
        let graph = crate::trace_binary(&binary, &skeleton_params())
            .expect("trace")
            .graph;
        graph.validate().expect("valid graph");
        (binary, graph)
    }

    /// The distance from `p` to the nearest point of the graph's polylines.
    fn nearest_point(graph: &StrokeGraph, p: [f64; 2]) -> f64 {
        graph
            .edges
            .iter()
            .flat_map(|e| e.points.iter())
            .map(|&q| dist(q, p))
            .fold(f64::INFINITY, f64::min)
    }

    fn assert_on_ink(binary: &crate::Binary, graph: &StrokeGraph) {
        for edge in &graph.edges {
            for s in edge.points.windows(2) {
                for k in 0..=8 {
                    let t = k as f64 / 8.0;
                    let p = [
                        s[0][0] + t * (s[1][0] - s[0][0]),
                        s[0][1] + t * (s[1][1] - s[0][1]),
                    ];
                    assert!(
                        binary.get(p[0].floor() as i64, p[1].floor() as i64),
                        "{p:?} is off the ink"
                    );
                }
            }
        }
    }

    #[test]
    fn a_thick_staircase_thins_to_one_pixel_and_a_ring_stays_a_cycle() {
        // A 2-pixel-thick 45 degree staircase: every pixel has three neighbours.
        let (w, h) = (12, 12);
        let mut skeleton = vec![false; w * h];
        for i in 1..10 {
            skeleton[i * w + i] = true;
            skeleton[i * w + i + 1] = true;
        }
        one_pixel_thick(&mut skeleton, w, h);
        let on = |x: usize, y: usize| skeleton[y * w + x];
        let neighbours = |x: usize, y: usize| {
            RING.iter()
                .filter(|&&(dx, dy)| {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    nx >= 0
                        && ny >= 0
                        && (nx as usize) < w
                        && (ny as usize) < h
                        && on(nx as usize, ny as usize)
                })
                .count()
        };
        let pixels: Vec<(usize, usize)> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| on(x, y))
            .collect();
        assert!(pixels.len() >= 9, "{pixels:?}");
        assert!(
            pixels.iter().all(|&(x, y)| neighbours(x, y) <= 2),
            "{pixels:?}"
        );
        // A ring of ink keeps its hole: one cycle, no end.
        let (_, ring) = traced(
            &[Stroke::new(
                (0..=64)
                    .map(|k| {
                        let a = k as f64 / 64.0 * std::f64::consts::TAU;
                        [40.0 + 20.0 * a.cos(), 40.0 + 20.0 * a.sin()]
                    })
                    .collect(),
                5.0,
            )],
            80,
            80,
        );
        assert_eq!(ring.edges.len() + 1, ring.vertices.len() + 1, "one loop");
        assert_eq!(ring.endpoints().count(), 0);
    }

    #[test]
    fn a_sharp_corner_is_a_bend_at_the_corner_not_a_junction() {
        // Two legs of width 6 meeting at 30 degrees at (50, 90).
        let corner = [50.0, 90.0];
        let a = 15f64.to_radians();
        let legs = Stroke::new(
            vec![
                [50.0 - 70.0 * a.sin(), 90.0 - 70.0 * a.cos()],
                corner,
                [50.0 + 70.0 * a.sin(), 90.0 - 70.0 * a.cos()],
            ],
            6.0,
        );
        let (binary, graph) = traced(&[legs], 100, 110);
        assert!(
            graph.vertices.iter().all(|v| v.degree < 3),
            "{:?}",
            graph.vertices
        );
        assert_eq!(graph.endpoints().count(), 2);
        let nearest = nearest_point(&graph, corner);
        assert!(
            nearest <= 3.0,
            "the bend is {nearest:.1} px from the corner"
        );
        assert_on_ink(&binary, &graph);
    }

    #[test]
    fn a_bold_acute_zigzag_bends_at_its_corners() {
        // Strokes 12 px wide meeting under 30-36 degrees, legs under six widths long: their inks
        // merge for about two widths from each corner, so the skeleton's legs bend together far
        // from it, and thinning makes each corner a Y with its junction deep in the merged ink.
        let corners = [[30.0, 110.0], [50.0, 30.0], [70.0, 110.0], [92.0, 35.0]];
        let (binary, graph) = traced(&[Stroke::new(corners.to_vec(), 12.0)], 125, 140);
        assert!(
            graph.vertices.iter().all(|v| v.degree < 3),
            "{:?}",
            graph.vertices
        );
        assert_eq!(graph.endpoints().count(), 2);
        for corner in &corners[1..3] {
            let nearest = nearest_point(&graph, *corner);
            assert!(
                nearest <= 2.0,
                "the bend is {nearest:.1} px from the corner {corner:?}"
            );
        }
        assert_on_ink(&binary, &graph);
    }

    #[test]
    fn cells_finer_than_a_stroke_stay_cycles() {
        // A box of 2 x 2 cells, each 5 px across, strokes 8 px wide (cells 0.6 widths).
        let (x0, y0, c, w) = (10.0, 10.0, 13.0, 8.0);
        let strokes: Vec<Stroke> = (0..3)
            .flat_map(|k| {
                let t = k as f64 * c;
                [
                    Stroke::new(vec![[x0, y0 + t], [x0 + 2.0 * c, y0 + t]], w),
                    Stroke::new(vec![[x0 + t, y0], [x0 + t, y0 + 2.0 * c]], w),
                ]
            })
            .collect();
        let (binary, graph) = traced(&strokes, 56, 56);
        let cycles = graph.edges.len() + 1 - graph.vertices.len();
        assert_eq!(cycles, 4, "every cell a cycle");
        assert_eq!(graph.endpoints().count(), 0, "no spur");
        assert_on_ink(&binary, &graph);
    }

    #[test]
    fn a_dot_is_one_vertex_and_an_end_reaches_its_cap() {
        let dot = Stroke::new(vec![[20.0, 20.0], [21.0, 20.5]], 5.0);
        let diagonal = Stroke::new(vec![[40.0, 10.0], [90.0, 60.0]], 3.0);
        let (_, graph) = traced(&[dot, diagonal], 100, 70);
        let dots: Vec<&Vertex> = graph.vertices.iter().filter(|v| v.degree == 0).collect();
        assert_eq!(dots.len(), 1, "{:?}", graph.vertices);
        assert!(dist(dots[0].pos, [20.5, 20.25]) <= 1.5);
        for end in [[40.0, 10.0], [90.0, 60.0]] {
            let nearest = graph
                .endpoints()
                .map(|v| dist(graph.vertices[v].pos, end))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest <= 1.5, "an end {nearest:.1} px from {end:?}");
        }
    }
}
