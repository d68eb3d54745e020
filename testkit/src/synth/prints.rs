//! Synthetic fingerprint-like ridge fields. A smooth phase function `phase(x, y)` (a whorl, loop,
//! arch or spiral term, warped, plus point dislocations) defines the ridges as the level sets
//! `phase = 2 pi k`. They are traced with marching squares on a half-pixel grid, where each grid
//! edge compares its two phases modulo 2 pi (the phase jumps by 2 pi across the branch cuts of
//! the dislocation and spiral terms, but never changes by more than pi along one edge away from
//! them). A dislocation is where one extra ridge starts: a ridge ending, or, joined to its
//! neighbour, a bifurcation. The traced polylines are the truth and the image is rendered from
//! them, so the truth lies on the ridges by construction.

use super::{render, Case, SplitMix64, Stroke};
use std::f64::consts::{PI, TAU};

/// Marching-squares grid spacing, px: the traced points are at most `GRID * sqrt(2)` apart.
const GRID: f64 = 0.5;

/// Cells within this distance of a singular point are not traced: the phase turns too fast there
/// to compare modulo 2 pi. The ridge is continued straight to the point (it is a ray up close).
/// The value of [`print_cases`]; see [`Field::core`].
const CORE: f64 = 1.5;

/// The large-scale ridge flow.
#[derive(Clone, Copy, Debug)]
enum Pattern {
    /// Closed rings around a center (ellipses, axis ratio `squash`).
    Whorl { squash: f64 },
    /// Ridges recurving around a core: distance to a ray leaving the core at `angle` radians.
    Loop { angle: f64 },
    /// Ridges across the finger, bulging up by `height` px over a bump of width `spread`.
    Arch { height: f64, spread: f64 },
    /// `arms` spiral ridges out of the center.
    Spiral { arms: f64 },
}

/// One ridge field.
#[derive(Clone, Debug)]
struct Field {
    pattern: Pattern,
    center: [f64; 2],
    /// Ridge period, px.
    period: f64,
    /// Warp amplitude, px, wavelengths, px, and phases.
    warp: [f64; 5],
    /// Dislocations: position, sign (which side gains the ridge) and whether the new ridge is
    /// joined to its neighbour (a bifurcation) rather than left as an ending.
    dislocations: Vec<([f64; 2], f64, bool)>,
    /// Radius of the untraced disk around each singular point, px ([`CORE`]). Below
    /// `period / 2 pi` only the ridge that ends at the point reaches the disk; above it, a
    /// neighbouring ridge can graze the disk and be cut there (three ends at one dislocation).
    core: f64,
    /// Distance added to a loop's, in periods. With 0 the ray from the core is a level the
    /// phase only touches, so a loop's innermost valley is two periods wide along it; with 1/2
    /// that line is the middle of an ordinary valley and the innermost ridge recurves around the
    /// core, as in a real loop.
    loop_offset: f64,
}

impl Field {
    /// The phase, radians; ridges are where it is a multiple of 2 pi.
    fn phase(&self, x: f64, y: f64) -> f64 {
        let [a, l1, l2, f1, f2] = self.warp;
        // A smooth warp of the coordinates keeps |grad F| within about 15% of 1, so the local
        // period stays within 15% of `period`.
        let u = x + a * (y / l1 + f1).sin() - self.center[0];
        let v = y + a * (x / l2 + f2).sin() - self.center[1];
        let distance = match self.pattern {
            Pattern::Whorl { squash } => (u * u / squash + v * v * squash).sqrt(),
            Pattern::Loop { angle } => {
                let (s, c) = angle.sin_cos();
                let along = u * c + v * s;
                let d = if along <= 0.0 {
                    u.hypot(v)
                } else {
                    (v * c - u * s).abs()
                };
                d + self.loop_offset * self.period
            }
            Pattern::Arch { height, spread } => {
                v + height * (-(u * u) / (2.0 * spread * spread)).exp()
            }
            Pattern::Spiral { .. } => u.hypot(v),
        };
        let mut phase = TAU * distance / self.period;
        if let Pattern::Spiral { arms } = self.pattern {
            phase += arms * (y - self.center[1]).atan2(x - self.center[0]);
        }
        for &(p, sign, _) in &self.dislocations {
            phase += sign * (y - p[1]).atan2(x - p[0]);
        }
        phase
    }

    /// Points where the phase is singular (the ends of extra ridges).
    fn singular_points(&self) -> Vec<[f64; 2]> {
        let mut points: Vec<[f64; 2]> = self.dislocations.iter().map(|d| d.0).collect();
        if let Pattern::Spiral { .. } = self.pattern {
            points.push(self.center);
        }
        points
    }
}

/// Wraps an angle difference into (-pi, pi].
fn wrap(d: f64) -> f64 {
    d - TAU * ((d + PI) / TAU).ceil() + TAU
}

/// Traces the level sets `phase = 2 pi k` over `[0, width] x [0, height]`. Returns polylines
/// (closed ones repeat their first point) and, for each, which ends reached a singular point
/// (those ends are continued to the point itself).
fn trace(field: &Field, width: u32, height: u32) -> Vec<(Vec<[f64; 2]>, [bool; 2])> {
    let nx = (width as f64 / GRID) as usize + 1;
    let ny = (height as f64 / GRID) as usize + 1;
    let pos = |i: usize, j: usize| [i as f64 * GRID, j as f64 * GRID];
    let mut phase = vec![0.0; nx * ny];
    for j in 0..ny {
        for i in 0..nx {
            let p = pos(i, j);
            phase[j * nx + i] = field.phase(p[0], p[1]);
        }
    }
    // One crossing node per grid edge at most: along an edge the phase changes by less than pi,
    // so at most one multiple of 2 pi lies between its ends.
    let horizontal = ny * (nx - 1);
    let mut edge_node = vec![u32::MAX; horizontal + nx * (ny - 1)];
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    let mut crossing = |e: usize, a: usize, b: usize, pa: [f64; 2], pb: [f64; 2]| {
        let delta = wrap(phase[b] - phase[a]);
        let (ka, kb) = ((phase[a] / TAU).floor(), ((phase[a] + delta) / TAU).floor());
        if ka != kb {
            let level = TAU * ka.max(kb);
            let t = ((level - phase[a]) / delta).clamp(0.0, 1.0);
            edge_node[e] = nodes.len() as u32;
            nodes.push([pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])]);
        }
    };
    for j in 0..ny {
        for i in 0..nx - 1 {
            crossing(
                j * (nx - 1) + i,
                j * nx + i,
                j * nx + i + 1,
                pos(i, j),
                pos(i + 1, j),
            );
        }
    }
    for j in 0..ny - 1 {
        for i in 0..nx {
            crossing(
                horizontal + j * nx + i,
                j * nx + i,
                (j + 1) * nx + i,
                pos(i, j),
                pos(i, j + 1),
            );
        }
    }

    let singular = field.singular_points();
    let mut links: Vec<[u32; 2]> = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let center = [(i as f64 + 0.5) * GRID, (j as f64 + 0.5) * GRID];
            if singular
                .iter()
                .any(|s| (s[0] - center[0]).hypot(s[1] - center[1]) < field.core)
            {
                continue;
            }
            // Edges e0 top, e1 right, e2 bottom, e3 left; corners c0 top-left, clockwise.
            let e = [
                j * (nx - 1) + i,
                horizontal + j * nx + i + 1,
                (j + 1) * (nx - 1) + i,
                horizontal + j * nx + i,
            ];
            let n = e.map(|e| edge_node[e]);
            let present: Vec<u32> = n.iter().copied().filter(|&k| k != u32::MAX).collect();
            match present.len() {
                2 => links.push([present[0], present[1]]),
                4 => {
                    // Saddle: unwrap the corners along the cell boundary and ask the phase at the
                    // center which diagonal pair of corners is connected.
                    let c = [
                        j * nx + i,
                        j * nx + i + 1,
                        (j + 1) * nx + i + 1,
                        (j + 1) * nx + i,
                    ];
                    let c0 = phase[c[0]];
                    let c1 = c0 + wrap(phase[c[1]] - c0);
                    let level = TAU * (c0 / TAU).floor().max((c1 / TAU).floor());
                    let mid = c0 + wrap(field.phase(center[0], center[1]) - c0);
                    if (mid >= level) == (c0 >= level) {
                        links.push([n[0], n[1]]);
                        links.push([n[2], n[3]]);
                    } else {
                        links.push([n[0], n[3]]);
                        links.push([n[1], n[2]]);
                    }
                }
                // Odd counts only occur next to a singular point, which is excluded above.
                _ => {}
            }
        }
    }
    chains(&nodes, &links, &singular, field.core)
}

/// Joins crossing nodes into polylines. A node has at most two links (one per cell it borders).
fn chains(
    nodes: &[[f64; 2]],
    links: &[[u32; 2]],
    singular: &[[f64; 2]],
    core: f64,
) -> Vec<(Vec<[f64; 2]>, [bool; 2])> {
    let mut adjacent = vec![[u32::MAX; 2]; nodes.len()];
    for (l, link) in links.iter().enumerate() {
        for &n in link {
            let slot = &mut adjacent[n as usize];
            if slot[0] == u32::MAX {
                slot[0] = l as u32;
            } else if slot[1] == u32::MAX {
                slot[1] = l as u32;
            }
        }
    }
    let degree = |n: usize| adjacent[n].iter().filter(|&&l| l != u32::MAX).count();
    let mut used = vec![false; links.len()];
    let walk = |start: usize, used: &mut Vec<bool>| -> Option<Vec<usize>> {
        let mut path = vec![start];
        let mut at = start;
        loop {
            let next_link = adjacent[at]
                .iter()
                .copied()
                .find(|&l| l != u32::MAX && !used[l as usize])?;
            used[next_link as usize] = true;
            let [a, b] = links[next_link as usize];
            at = if a as usize == at {
                b as usize
            } else {
                a as usize
            };
            path.push(at);
            if at == start || degree(at) < 2 {
                return Some(path);
            }
            if adjacent[at]
                .iter()
                .all(|&l| l == u32::MAX || used[l as usize])
            {
                return Some(path);
            }
        }
    };
    let mut paths = Vec::new();
    // Open chains first, from their ends, then the closed loops left over.
    for n in 0..nodes.len() {
        if degree(n) == 1 {
            if let Some(path) = walk(n, &mut used) {
                paths.push(path);
            }
        }
    }
    for n in 0..nodes.len() {
        while let Some(path) = walk(n, &mut used) {
            paths.push(path);
        }
    }
    let near_singular = |p: [f64; 2]| {
        singular
            .iter()
            .copied()
            .find(|s| (s[0] - p[0]).hypot(s[1] - p[1]) < core + 1.5 * GRID)
    };
    // Crumbs from the cells around an excluded core are not ridges.
    let in_core = |n: &usize| {
        singular
            .iter()
            .any(|s| (s[0] - nodes[*n][0]).hypot(s[1] - nodes[*n][1]) < core + 2.5 * GRID)
    };
    paths
        .into_iter()
        .filter(|path| path.len() >= 2 && !path.iter().all(in_core))
        .map(|path| {
            let mut points: Vec<[f64; 2]> = path.iter().map(|&n| nodes[n]).collect();
            let mut ends = [false; 2];
            if path.first() != path.last() {
                if let Some(s) = near_singular(points[0]) {
                    points.insert(0, s);
                    ends[0] = true;
                }
                if let Some(s) = points.last().copied().and_then(near_singular) {
                    points.push(s);
                    ends[1] = true;
                }
            }
            (points, ends)
        })
        .collect()
}

fn length(points: &[[f64; 2]]) -> f64 {
    points
        .windows(2)
        .map(|s| (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1]))
        .sum()
}

/// Shortens ridges that end at a singular point until their end is `clearance` px from every
/// other ridge (and from its own far parts), so the ink shows an ending and not a merge. An end
/// moves at most `reach` px.
fn trim_ends(ridges: &mut [(Vec<[f64; 2]>, [bool; 2])], clearance: f64, reach: f64) {
    let distance = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    for r in 0..ridges.len() {
        for side in 0..2 {
            if !ridges[r].1[side] {
                continue;
            }
            if side == 0 {
                ridges[r].0.reverse();
            }
            let Some(&start) = ridges[r].0.last() else {
                continue;
            };
            // Only points near the original end can ever be too close: collect them once.
            let radius = reach + clearance;
            let others: Vec<[f64; 2]> = ridges
                .iter()
                .enumerate()
                .filter(|(o, _)| *o != r)
                .flat_map(|(_, ridge)| {
                    ridge
                        .0
                        .iter()
                        .copied()
                        .filter(|&q| distance(q, start) < radius)
                })
                .collect();
            let own = &ridges[r].0;
            let mut arc = vec![0.0; own.len()];
            for k in 1..own.len() {
                arc[k] = arc[k - 1] + distance(own[k], own[k - 1]);
            }
            let near_own: Vec<usize> = (0..own.len())
                .filter(|&k| distance(own[k], start) < radius)
                .collect();
            loop {
                let own = &ridges[r].0;
                let last = own.len() - 1;
                let end = own[last];
                if own.len() < 3 || distance(end, start) > reach {
                    break;
                }
                // Own points far along the ridge count as other ridges (a spiral's next turn).
                let own_close = near_own.iter().any(|&k| {
                    k < last
                        && arc[last] - arc[k] > 3.0 * clearance
                        && distance(own[k], end) < clearance
                });
                let other_close = others.iter().any(|&q| distance(q, end) < clearance);
                if !(own_close || other_close) {
                    break;
                }
                ridges[r].0.pop();
            }
            if side == 0 {
                ridges[r].0.reverse();
            }
        }
    }
}

/// Joins the end of ridge `r` (its last point) to the nearest other ridge ahead of it with a
/// smooth quadratic curve: the ink then shows a bifurcation.
fn join_ahead(ridges: &mut [(Vec<[f64; 2]>, [bool; 2])], r: usize, period: f64) {
    let own = &ridges[r].0;
    if own.len() < 8 {
        return;
    }
    let end = own[own.len() - 1];
    let back = own[own.len() - 7];
    let d = [end[0] - back[0], end[1] - back[1]];
    let norm = d[0].hypot(d[1]);
    if norm == 0.0 {
        return;
    }
    let d = [d[0] / norm, d[1] / norm];
    let target = [end[0] + d[0] * 0.8 * period, end[1] + d[1] * 0.8 * period];
    let mut best: Option<([f64; 2], f64)> = None;
    for (o, ridge) in ridges.iter().enumerate() {
        if o == r {
            continue;
        }
        for q in &ridge.0 {
            let dist = (q[0] - target[0]).hypot(q[1] - target[1]);
            if best.is_none_or(|b| dist < b.1) {
                best = Some((*q, dist));
            }
        }
    }
    let Some((foot, _)) = best else { return };
    let reach = (foot[0] - end[0]).hypot(foot[1] - end[1]);
    if reach > 1.5 * period {
        return;
    }
    let control = [end[0] + d[0] * reach * 0.5, end[1] + d[1] * reach * 0.5];
    let steps = (reach / (0.5 * GRID)).ceil().max(2.0) as usize;
    for s in 1..=steps {
        let t = s as f64 / steps as f64;
        let (a, b, c) = ((1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t);
        ridges[r].0.push([
            a * end[0] + b * control[0] + c * foot[0],
            a * end[1] + b * control[1] + c * foot[1],
        ]);
    }
    ridges[r].1[1] = false;
}

/// Cuts polylines to the inside of an ellipse (the finger's contact area), splitting where they
/// leave it; the crossing points are found by bisection.
fn clip_to_ellipse(points: &[[f64; 2]], center: [f64; 2], axes: [f64; 2]) -> Vec<Vec<[f64; 2]>> {
    let inside = |p: [f64; 2]| {
        let (u, v) = ((p[0] - center[0]) / axes[0], (p[1] - center[1]) / axes[1]);
        u * u + v * v <= 1.0
    };
    let boundary = |a: [f64; 2], b: [f64; 2]| {
        // `a` inside, `b` outside.
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if inside([a[0] + mid * (b[0] - a[0]), a[1] + mid * (b[1] - a[1])]) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        [a[0] + lo * (b[0] - a[0]), a[1] + lo * (b[1] - a[1])]
    };
    let mut ring: Vec<[f64; 2]> = points.to_vec();
    let closed = ring.len() > 2 && ring.first() == ring.last();
    if closed {
        // Start a closed ridge outside the ellipse, so no piece is split at its seam.
        match ring.iter().position(|&p| !inside(p)) {
            None => return vec![ring],
            Some(k) => {
                ring.pop();
                ring.rotate_left(k);
                let first = ring[0];
                ring.push(first);
            }
        }
    }
    let mut pieces = Vec::new();
    let mut current: Vec<[f64; 2]> = Vec::new();
    for (k, &p) in ring.iter().enumerate() {
        if inside(p) {
            if current.is_empty() && k > 0 {
                current.push(boundary(p, ring[k - 1]));
            }
            current.push(p);
        } else if !current.is_empty() {
            current.push(boundary(ring[k - 1], p));
            pieces.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        pieces.push(current);
    }
    pieces
}

/// One print: trace, trim and join at the dislocations, clip to the finger area, render.
fn print_case(name: &str, group: &str, field: &Field, width: f64, size: u32) -> Case {
    let mut ridges = trace(field, size, size);
    // Ink gap of 2 px or more between the end of a new ridge and its neighbours.
    trim_ends(&mut ridges, width + 2.5, 4.0 * field.period);
    for (p, _, bifurcation) in &field.dislocations {
        if !bifurcation {
            continue;
        }
        // The trimmed end of this dislocation's ridge: the nearest end that reached a singular
        // point (with many dislocations, another one's end may also be within reach).
        let mut nearest: Option<(usize, usize, f64)> = None;
        for (k, r) in ridges.iter().enumerate() {
            for (side, end) in [(0, r.0.first()), (1, r.0.last())] {
                let Some(e) = end else { continue };
                let d = (e[0] - p[0]).hypot(e[1] - p[1]);
                if r.1[side] && d < 4.0 * width + 10.0 && nearest.is_none_or(|n| d < n.2) {
                    nearest = Some((k, side, d));
                }
            }
        }
        if let Some((r, side, _)) = nearest {
            if side == 0 {
                // The end is at the start of the polyline: turn it around first.
                ridges[r].0.reverse();
                ridges[r].1 = [ridges[r].1[1], ridges[r].1[0]];
            }
            join_ahead(&mut ridges, r, field.period);
        }
    }
    let (center, axes) = finger_area(size);
    let mut strokes = Vec::new();
    for (points, _) in &ridges {
        for piece in clip_to_ellipse(points, center, axes) {
            let closed = piece.len() > 2 && piece.first() == piece.last();
            // Drop crumbs at the rim and rings too small to keep a hole in their ink.
            let min_length = if closed { TAU * width } else { field.period };
            if length(&piece) >= min_length {
                strokes.push(Stroke::new(piece, width));
            }
        }
    }
    let binary = render(&strokes, size, size);
    // The full square image: the finger area sits inside it with a margin.
    Case {
        name: name.to_string(),
        group: group.into(),
        binary,
        strokes,
    }
}

/// The finger area of a print image of side `size`: the centre and the half-axes of the ellipse
/// its ridges are clipped to. A true ridge that ends on this outline was cut there (the finger's
/// edge), not at a minutia.
pub fn finger_area(size: u32) -> ([f64; 2], [f64; 2]) {
    let s = f64::from(size);
    ([s / 2.0, s / 2.0], [0.42 * s, 0.47 * s])
}

/// A dislocation placed as fractions of the image size: x, y, sign, and whether it is joined
/// (a bifurcation).
type Dislocation = (f64, f64, f64, bool);

/// Every print case (group `prints`): 10 ridge fields of 200 x 200 px, ridge width 3-5 px, period
/// 8-11 px: whorls, loops, arches and spirals, some with a ridge ending or a bifurcation.
pub fn print_cases() -> Vec<Case> {
    let size = 200u32;
    let s = size as f64;
    let kinds: [(&str, u8, &[Dislocation]); 10] = [
        ("whorl", 0, &[]),
        ("whorl_ending", 0, &[(0.62, 0.28, 1.0, false)]),
        ("loop", 1, &[]),
        ("loop_tilted", 1, &[]),
        ("arch", 2, &[]),
        (
            "arch_minutiae",
            2,
            &[(0.35, 0.4, 1.0, false), (0.66, 0.62, -1.0, true)],
        ),
        ("spiral", 3, &[]),
        ("spiral2", 4, &[]),
        ("whorl_bifurcation", 0, &[(0.3, 0.7, -1.0, true)]),
        ("arch_ending", 2, &[(0.55, 0.72, 1.0, false)]),
    ];
    let mut cases = Vec::new();
    for (index, (name, kind, dislocations)) in kinds.iter().enumerate() {
        let mut rng = SplitMix64::new(0x5EED_0000 + index as u64);
        let (mut field, width) = random_field(*kind, &mut rng, s);
        // Off-grid positions, so no grid line runs through a singular point.
        field.dislocations = dislocations
            .iter()
            .map(|&(x, y, sign, join)| ([x * s + 0.123, y * s + 0.377], sign, join))
            .collect();
        cases.push(print_case(
            &format!("print{index}_{name}"),
            "prints",
            &field,
            width,
            size,
        ));
    }
    cases
}

/// A ridge field of pattern `kind` (0 whorl, 1 loop, 2 arch, 3 and 4 spirals of one and two
/// arms) for a square image of side `s`, without dislocations, and its ridge width: period
/// 8-11 px, width 3-5 px and at most 45 % of the period.
fn random_field(kind: u8, rng: &mut SplitMix64, s: f64) -> (Field, f64) {
    let period = rng.range(8.0, 11.0);
    // Ridges at most 45% of the period wide: ink gaps stay >= 3 px where the warp compresses.
    let widths: Vec<f64> = [3.0, 4.0, 5.0]
        .into_iter()
        .filter(|w| *w <= 0.45 * period)
        .collect();
    let width = widths.get(rng.below(widths.len())).copied().unwrap_or(3.0);
    let pattern = match kind {
        0 => Pattern::Whorl {
            squash: rng.range(1.0, 1.3),
        },
        1 => Pattern::Loop {
            angle: PI / 2.0 + rng.range(-0.5, 0.5),
        },
        2 => Pattern::Arch {
            height: rng.range(15.0, 35.0),
            spread: rng.range(35.0, 55.0),
        },
        3 => Pattern::Spiral { arms: 1.0 },
        _ => Pattern::Spiral { arms: 2.0 },
    };
    let center = match kind {
        1 => [s * rng.range(0.45, 0.55), s * rng.range(0.3, 0.4)],
        2 => [s * 0.5, s * rng.range(0.55, 0.65)],
        _ => [s * rng.range(0.45, 0.55), s * rng.range(0.45, 0.55)],
    };
    let warp = [
        rng.range(2.0, 4.0),
        rng.range(25.0, 40.0),
        rng.range(25.0, 40.0),
        rng.range(0.0, TAU),
        rng.range(0.0, TAU),
    ];
    let field = Field {
        pattern,
        center,
        period,
        warp,
        dislocations: Vec::new(),
        core: CORE,
        loop_offset: 0.0,
    };
    (field, width)
}

/// Side of the [`dense_print_cases`] images, px.
pub const DENSE_PRINT_SIZE: u32 = 320;

/// Prints with the minutia density of a real capture (group `fingerprints`): 10 ridge fields of
/// 320 x 320 px (the finger area about 270 x 300 px, 13 x 15 mm at 500 ppi), patterns and ridges
/// as in [`print_cases`], each with 28-41 dislocations spread over the print. A 500 ppi print
/// has roughly 30-80 minutiae over a whole finger (docs/fingerprints.md, "Benchmark"); here the dislocations are at least 3
/// periods apart and 2.5 periods from the pattern's core, their signs balanced (so the flow far
/// from them is the pattern's), 55 % endings and 45 % bifurcations. Some land near the rim and are
/// clipped away; the rest are the truth.
pub fn dense_print_cases() -> Vec<Case> {
    let size = DENSE_PRINT_SIZE;
    let s = size as f64;
    let names = ["whorl", "loop", "arch", "spiral", "spiral2"];
    let mut cases = Vec::new();
    for index in 0..10u64 {
        let kind = (index % 5) as u8;
        let mut rng = SplitMix64::new(0xF1A6_0000 + index);
        let (mut field, width) = random_field(kind, &mut rng, s);
        // Every dislocation ends one ridge only (see `Field::core`).
        field.core = 0.1 * field.period;
        field.loop_offset = 0.5;
        let target = 28 + rng.below(14);
        let spacing = 3.0 * field.period;
        let core_point = match field.pattern {
            Pattern::Arch { .. } => None,
            _ => Some(field.center),
        };
        let (cx, cy) = (s / 2.0, s / 2.0);
        // Within the finger's ellipse (0.42 s x 0.47 s), a little inside its rim.
        let (ax, ay) = (0.40 * s, 0.45 * s);
        let mut placed: Vec<[f64; 2]> = Vec::new();
        for _ in 0..20_000 {
            if placed.len() == target {
                break;
            }
            let p = [rng.range(cx - ax, cx + ax), rng.range(cy - ay, cy + ay)];
            let (u, v) = ((p[0] - cx) / ax, (p[1] - cy) / ay);
            let far = |q: [f64; 2], d: f64| (q[0] - p[0]).hypot(q[1] - p[1]) >= d;
            // A loop's ridges fold back along the ray from its core (the phase has a crease
            // there): a dislocation near the fold would not end one ridge.
            let off_fold = match field.pattern {
                Pattern::Loop { angle } => {
                    let (sin, cos) = angle.sin_cos();
                    let (du, dv) = (p[0] - field.center[0], p[1] - field.center[1]);
                    du * cos + dv * sin < -field.period
                        || (dv * cos - du * sin).abs() > 2.0 * field.period
                }
                _ => true,
            };
            if u * u + v * v <= 1.0
                && off_fold
                && core_point.is_none_or(|c| far(c, 2.5 * field.period))
                && placed.iter().all(|&q| far(q, spacing))
            {
                placed.push(p);
            }
        }
        field.dislocations = placed
            .iter()
            .enumerate()
            .map(|(k, &p)| {
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                (p, sign, rng.next_f64() < 0.45)
            })
            .collect();
        cases.push(print_case(
            &format!("dense{index}_{}", names[kind as usize]),
            "fingerprints",
            &field,
            width,
            size,
        ));
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense prints have a realistic number of free ridge ends well inside the finger.
    #[test]
    fn dense_prints_have_many_minutiae() {
        for case in dense_print_cases() {
            let s = f64::from(case.binary.width);
            let ends = case
                .strokes
                .iter()
                .flat_map(|st| [st.points[0], st.points[st.points.len() - 1]])
                .filter(|p| {
                    let (u, v) = ((p[0] - s / 2.0) / (0.36 * s), (p[1] - s / 2.0) / (0.41 * s));
                    u * u + v * v <= 1.0
                })
                .count();
            eprintln!(
                "{}: {} strokes, {ends} ends inside",
                case.name,
                case.strokes.len()
            );
            assert!((20..=90).contains(&ends), "{}: {ends} ends", case.name);
        }
    }

    #[test]
    fn wrap_range() {
        for d in [-7.0, -PI, -1.0, 0.0, 1.0, PI, 4.0, 10.0] {
            let w = wrap(d);
            assert!(w > -PI - 1e-12 && w <= PI + 1e-12, "{d} -> {w}");
            assert!(((d - w) / TAU - ((d - w) / TAU).round()).abs() < 1e-9);
        }
    }

    /// The traced points satisfy the level-set equation: phase within a small error of 2 pi k.
    #[test]
    fn traced_points_are_on_level_sets() {
        let field = Field {
            pattern: Pattern::Whorl { squash: 1.2 },
            center: [60.0, 60.0],
            period: 9.0,
            warp: [3.0, 30.0, 35.0, 0.4, 1.1],
            dislocations: vec![([30.3, 80.7], 1.0, false)],
            core: CORE,
            loop_offset: 0.0,
        };
        let ridges = trace(&field, 120, 120);
        assert!(ridges.len() > 5);
        let mut ends_at_dislocation = 0;
        for (points, ends) in &ridges {
            ends_at_dislocation += ends.iter().filter(|&&e| e).count();
            let skip = [ends[0] as usize, ends[1] as usize];
            for p in &points[skip[0]..points.len() - skip[1]] {
                let phase = field.phase(p[0], p[1]);
                let off = (phase / TAU - (phase / TAU).round()).abs() * field.period;
                // Linear interpolation over a half-pixel edge: error well under 0.1 px.
                assert!(off < 0.1, "{p:?} is {off} px off its level set");
            }
        }
        // A dislocation starts exactly one extra ridge.
        assert_eq!(ends_at_dislocation, 1);
    }

    /// Separate ridges stay apart in the ink, except where a bifurcation joins them.
    #[test]
    fn ridges_do_not_merge() {
        for case in print_cases().into_iter().chain(dense_print_cases()) {
            let w = case.strokes[0].widths[0];
            let ends: Vec<[f64; 2]> = case
                .strokes
                .iter()
                .flat_map(|s| [s.points[0], s.points[s.points.len() - 1]])
                .collect();
            let junction_near = |p: [f64; 2]| {
                ends.iter()
                    .any(|e| (e[0] - p[0]).hypot(e[1] - p[1]) < 2.0 * w + 3.0)
            };
            // Bucket the points on a coarse grid for the neighbour search.
            let cell = 8.0;
            let n = (f64::from(case.binary.width) / cell) as usize + 1;
            let mut buckets = vec![Vec::new(); n * n];
            for (si, s) in case.strokes.iter().enumerate() {
                for (pi, p) in s.points.iter().enumerate() {
                    // Every point lies in the image (the bucket index assumes it).
                    assert!(p[0] >= 0.0 && p[1] >= 0.0, "{}: {p:?}", case.name);
                    let (bx, by) = ((p[0] / cell) as usize, (p[1] / cell) as usize);
                    buckets[by.min(n - 1) * n + bx.min(n - 1)].push((si, pi));
                }
            }
            for (si, s) in case.strokes.iter().enumerate() {
                for p in &s.points {
                    if junction_near(*p) {
                        continue;
                    }
                    let (bx, by) = ((p[0] / cell) as i64, (p[1] / cell) as i64);
                    for y in by - 1..=by + 1 {
                        for x in bx - 1..=bx + 1 {
                            if x < 0 || y < 0 || x >= n as i64 || y >= n as i64 {
                                continue;
                            }
                            for &(sj, pj) in &buckets[y as usize * n + x as usize] {
                                if sj == si {
                                    continue;
                                }
                                let q = case.strokes[sj].points[pj];
                                let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                                assert!(
                                    d >= w + 1.5,
                                    "{}: ridges {si} and {sj} {d:.2} px apart at {p:?}",
                                    case.name
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
