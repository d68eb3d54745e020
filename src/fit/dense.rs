//! §3.4 dense re-fit ([`crate::ExperimentParams::dense_fit`]): every edge re-fitted from the pixels
//! it owns, one point every [`crate::DENSE_SPACING`] `Dis_ave`.
//!
//! The least-squares fit of Eq. (4) places one node per `h` (about one stroke width), so a
//! curve tighter than that is cut by chords. Here each edge's own points (the Voronoi cells of its
//! interior nodes) are projected onto its fitted polyline and binned by arc length; each bin
//! gives a point at the median of its points' offsets across the polyline, i.e. the middle of
//! that slice of the stroke. A 1-D median per slice, not a Voronoi partition at the fine
//! spacing: the geodesic distance of the assignment is octagonal, and between sites 2 px apart
//! its bisectors bend across a wide stroke, which made the slices' medians zig-zag.
//!
//! Within one stroke width of a junction a slice of one arm also holds the other arms' ink, so no
//! point is taken there: the edge runs straight into the junction placed by `place`.

use super::assign::Groups;
use crate::geometry::{arc_lengths, point_at};
use crate::point_set::PointSet;

/// Fewest points a slice needs for its median to count.
const MIN_SLICE_POINTS: usize = 2;

/// One edge to re-fit: its unknowns (vertex to vertex) and the arc length to leave out at each
/// end (one stroke width at a junction, none elsewhere).
pub struct EdgeSpan<'a> {
    /// The edge's unknowns, rewritten in place.
    pub ids: &'a mut Vec<u32>,
    /// The coarse unknowns whose cells hold the edge's points: those the layout put on it, both
    /// vertices included (the placement may have dropped some from `ids`).
    pub owners: Vec<u32>,
    /// Arc length left out after the first vertex and before the last.
    pub skip: [f64; 2],
}

/// Re-fits `edges` from the cells of their interior unknowns. New points are appended to
/// `positions`; `parent[i]` is the coarse unknown each new point stands for (its cell and width).
pub fn refit(
    edges: Vec<EdgeSpan<'_>>,
    positions: &mut Vec<[f64; 2]>,
    parent: &mut Vec<u32>,
    cells: &Groups,
    points: &PointSet,
    spacing: f64,
) {
    let mut samples: Vec<(u32, f64)> = Vec::new();
    let mut offsets: Vec<f64> = Vec::new();
    for edge in edges {
        let ids = edge.ids;
        if ids.len() < 3 {
            continue;
        }
        let line: Vec<[f64; 2]> = ids.iter().map(|&i| positions[i as usize]).collect();
        let s = arc_lengths(&line);
        let length = s[s.len() - 1];
        let (from, to) = (edge.skip[0], length - edge.skip[1]);
        if to - from < 2.0 * spacing {
            continue;
        }
        samples.clear();
        for &coarse in &edge.owners {
            // A cell lies around its unknown: the segments next to it (its place on the line, or
            // the segment nearest it when the placement dropped it).
            let hint = match ids.iter().position(|&i| i == coarse) {
                Some(k) => k.min(line.len() - 2),
                None => nearest_segment(&line, positions[coarse as usize]),
            };
            for &p in cells.of(coarse as usize) {
                let q = points.points[p as usize];
                let mut best: Option<(f64, f64, f64)> = None;
                for k in hint.saturating_sub(2)..(hint + 3).min(line.len() - 1) {
                    let (a, b) = (line[k], line[k + 1]);
                    let d = [b[0] - a[0], b[1] - a[1]];
                    let len2 = d[0] * d[0] + d[1] * d[1];
                    if len2 <= 1e-12 {
                        continue;
                    }
                    let t = (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0);
                    let foot = [a[0] + t * d[0], a[1] + t * d[1]];
                    let gap = crate::geometry::dist(q, foot);
                    if best.is_none_or(|(g, _, _)| gap < g) {
                        let len = len2.sqrt();
                        let across = ((q[0] - a[0]) * d[1] - (q[1] - a[1]) * d[0]) / len;
                        best = Some((gap, s[k] + t * len, across));
                    }
                }
                // A vertex's cell also holds other arms' ink: only what lies beside this edge
                // (projected inside it, not past an end) counts.
                if let Some((_, along, across)) = best {
                    if along > from.max(1e-9) && along < to.min(length - 1e-9) {
                        samples.push((((along - from) / spacing) as u32, across));
                    }
                }
            }
        }
        samples.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        // (bin, median offset) per slice with enough points.
        let mut slices: Vec<(u32, f64)> = Vec::new();
        for run in samples.chunk_by(|a, b| a.0 == b.0) {
            if run.len() < MIN_SLICE_POINTS {
                continue;
            }
            offsets.clear();
            offsets.extend(run.iter().map(|x| x.1));
            let m = offsets.len() / 2;
            let median = if offsets.len() % 2 == 1 {
                offsets[m]
            } else {
                0.5 * (offsets[m - 1] + offsets[m])
            };
            slices.push((run[0].0, median));
        }
        // Half a pixel of jitter from the pixel grid: a [1 2 1] / 4 pass between adjacent slices.
        let smoothed: Vec<f64> = (0..slices.len())
            .map(|i| {
                let here = slices[i];
                let prev = i
                    .checked_sub(1)
                    .map(|k| slices[k])
                    .filter(|x| x.0 + 1 == here.0);
                let next = slices.get(i + 1).copied().filter(|x| x.0 == here.0 + 1);
                match (prev, next) {
                    (Some(a), Some(b)) => 0.25 * a.1 + 0.5 * here.1 + 0.25 * b.1,
                    _ => here.1,
                }
            })
            .collect();
        let keep = if ids[0] == ids[ids.len() - 1] { 2 } else { 1 };
        if slices.len() < keep.max(ids.len().min(3) - 2) {
            continue;
        }
        let mut rewritten = Vec::with_capacity(slices.len() + 2);
        rewritten.push(ids[0]);
        for (&(bin, _), &offset) in slices.iter().zip(&smoothed) {
            let along = from + (bin as f64 + 0.5) * spacing;
            let (base, k) = point_at(&line, &s, along.min(to));
            let (a, b) = (line[k], line[k + 1]);
            let len = crate::geometry::dist(a, b).max(1e-12);
            // `across` was measured as d × (q - a): positive to the right of the direction.
            let normal = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len];
            positions.push([base[0] + offset * normal[0], base[1] + offset * normal[1]]);
            parent.push(parent[ids[k.clamp(1, ids.len() - 2)] as usize]);
            rewritten.push((positions.len() - 1) as u32);
        }
        rewritten.push(ids[ids.len() - 1]);
        *ids = rewritten;
    }
}

/// Index of the polyline segment nearest to `p`.
fn nearest_segment(line: &[[f64; 2]], p: [f64; 2]) -> usize {
    let mut best = (f64::INFINITY, 0);
    for k in 0..line.len() - 1 {
        let (a, b) = (line[k], line[k + 1]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = (d[0] * d[0] + d[1] * d[1]).max(1e-12);
        let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0);
        let gap = crate::geometry::dist(p, [a[0] + t * d[0], a[1] + t * d[1]]);
        if gap < best.0 {
            best = (gap, k);
        }
    }
    best.1
}
