//! Shallow T's: where an arm meets a stroke at a shallow angle (a bowl closing on a stem, an
//! `e`'s loop closing on its entry stroke, a connector leaving a stem), the two strokes' inks stay
//! one blob past the point where their centerlines meet, and thinning forks where the inks part,
//! one to three widths down the stroke. Along the shared stretch the ink is wider than either
//! stroke; where the centerlines meet it is one stroke's width again. [`Work::place_shallow_tees`]
//! moves the junction back to there. docs/design.md, "Skeleton-carried geometry"; docs/quality.md,
//! "Session of 2026-12-06, seventh: junctions in script (issue 31)".

use std::cmp::Ordering;

use crate::geometry::{cmp_dist, dist};
use crate::stroke_graph::Edge;

use super::work::{median, points_outwards, Work};

/// The fork of a shallow T: its two arms (the T's arm and the stroke's other half) leave the
/// junction less than this far apart (cosine of 75 degrees; measured over [`ARM_SPAN`], so a
/// curved arm's direction is its chord's: measured at 60, 75 and 90 degrees in docs/quality.md).
const FORK_COS: f64 = 0.26;

/// Arms' directions are measured to their point this many of their widths from the junction.
const ARM_SPAN: f64 = 2.0;

/// One stroke's ink: the skeleton's width (px) at most this much over the wider fork arm's
/// median width (the skeleton's widths are odd pixel counts of the distance transform, so a
/// pixel's rounding either way).
const ONE_STROKE_PX: f64 = 1.0;

/// The stroke beyond the new junction must be one stroke's ink for this many widths (the middle
/// of a shallow X's lens is one stroke's width too, for a point).
const ONE_STROKE_RUN: f64 = 1.0;

/// A move of less than this many widths is not made (a T at a right angle forks where its
/// centerlines meet, give or take the junction's disk).
const MIN_MOVE: f64 = 0.5;

/// A move of more than this many widths is not made: an arm at 20 degrees parts from the
/// stroke `w / sin 20° ≈ 3 w` past the meeting point.
const MAX_MOVE: f64 = 3.0;

/// The fork's arms are joined to the new junction from their point this many of their widths
/// from the old one (past the junction's disk, where their own path is the stroke's).
const ARM_JOIN: f64 = 1.0;

impl Work {
    /// Junctions of shallow T's moved to where the strokes' centerlines meet: at a degree-3
    /// junction whose two arms leave it as a narrow fork (within 75 degrees of each other, both
    /// away from the third edge), the third edge, the stroke the arm joins, carries both strokes'
    /// ink as long as its skeleton width exceeds the wider fork arm's by more than a pixel; the
    /// junction moves along it to the first point where the ink is one stroke's again, and stays
    /// so for a width on (not within a width of a junction at the edge's other end, whose own
    /// ink is wide), when that is between half a width and three widths from the fork. The two
    /// fork arms are joined straight to it from a width out, on the ink. One edge at most may be
    /// the shared stretch; otherwise nothing moves. Strokes under two pixels' skeleton width are
    /// left: a pixel's rounding is half their width.
    pub(super) fn place_shallow_tees(&mut self) {
        let degree = self.degrees();
        let at = self.incident();
        for v in 0..self.vertices.len() {
            if !self.alive[v] || degree[v] != 3 {
                continue;
            }
            // The three edge ends at the junction: a loop's two ends are two of them (the bowl
            // of a `6` or `9` closing on its own stem).
            let ends: Vec<End> = at
                .row(v)
                .iter()
                .flat_map(|&e| {
                    let edge = self.edges[e].as_ref();
                    let from = edge.is_some_and(|x| x.from == v);
                    let to = edge.is_some_and(|x| x.to == v);
                    [(from, (e, true)), (to, (e, false))]
                        .into_iter()
                        .filter_map(|(here, end)| here.then_some(end))
                })
                .collect();
            if ends.len() != 3 {
                continue;
            }
            let jp = self.vertices[v].pos;
            let edge = |(e, _): End| self.edges[e].as_ref().expect("live edge");
            let moves: Vec<(usize, usize, [f64; 2])> = (0..3)
                .filter_map(|k| {
                    let stem = ends[k];
                    let fork = [ends[(k + 1) % 3], ends[(k + 2) % 3]];
                    let stem_edge = edge(stem);
                    let other = if stem.1 { stem_edge.to } else { stem_edge.from };
                    // A loop's other end is this junction: the one-stroke run is looked for
                    // along the loop, far from its return.
                    let far_junction =
                        (other != v && degree[other] >= 3).then_some(self.vertices[other].pos);
                    shallow_tee_point(
                        jp,
                        (stem_edge, stem.1),
                        fork.map(|f| (edge(f), f.1)),
                        far_junction,
                    )
                    .map(|(i, q)| (k, i, q))
                })
                .collect();
            let [(k, i, q)] = moves[..] else {
                continue;
            };
            let stem = ends[k];
            let fork = [ends[(k + 1) % 3], ends[(k + 2) % 3]];
            // Each fork arm from a width out, joined straight to the new junction.
            let joins: Option<Vec<usize>> = fork
                .iter()
                .map(|&(e, at_start)| {
                    let edge = self.edges[e].as_ref()?;
                    let w = median(&edge.widths);
                    let outwards = points_outwards(edge, at_start);
                    let cut = outwards.iter().position(|&p| dist(p, jp) >= ARM_JOIN * w)?;
                    self.ink.holds(q, outwards[cut]).then_some(cut)
                })
                .collect();
            let Some(joins) = joins else { continue };
            // A loop cut at both its ends keeps points between them.
            let cuts = [i, joins[0], joins[1]];
            let ends_cut = [stem, fork[0], fork[1]];
            let short_loop = (0..3).any(|a| {
                (a + 1..3).any(|b| {
                    ends_cut[a].0 == ends_cut[b].0
                        && self.edges[ends_cut[a].0]
                            .as_ref()
                            .is_none_or(|x| cuts[a] + cuts[b] + 2 > x.points.len())
                })
            });
            if short_loop {
                continue;
            }
            for (&(e, at_start), &cut) in fork.iter().zip(&joins) {
                let Some(edge) = self.edges[e].as_mut() else {
                    continue;
                };
                rejoin(edge, at_start, cut, q);
            }
            if let Some(edge) = self.edges[stem.0].as_mut() {
                trim_start(edge, stem.1, i);
            }
            self.vertices[v].pos = q;
        }
    }
}

/// An edge's end at a junction: the edge, and whether it is its start.
type End = (usize, bool);

/// Where the junction at `jp` of a shallow T belongs on `stem` (an edge and whether its start
/// is the junction's end; the index of that point on `stem` counted from the junction, and the
/// point), when `fork`'s two arms leave it as an acute fork away from `stem` and `stem`'s ink
/// is two strokes' wide up to there ([`Work::place_shallow_tees`]).
fn shallow_tee_point(
    jp: [f64; 2],
    stem: (&Edge, bool),
    fork: [(&Edge, bool); 2],
    far_junction: Option<[f64; 2]>,
) -> Option<(usize, [f64; 2])> {
    let direction = |(edge, at_start): (&Edge, bool)| {
        let w = median(&edge.widths);
        let outwards = points_outwards(edge, at_start);
        let p = outwards
            .iter()
            .copied()
            .find(|&p| cmp_dist(p, jp, ARM_SPAN * w).is_some_and(Ordering::is_ge))
            .unwrap_or(outwards[outwards.len() - 1]);
        let d = dist(p, jp);
        (d > 0.0).then(|| [(p[0] - jp[0]) / d, (p[1] - jp[1]) / d])
    };
    let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
    let (a, b, c) = (direction(fork[0])?, direction(fork[1])?, direction(stem)?);
    if dot(a, b) < FORK_COS || dot(a, c) >= 0.0 || dot(b, c) >= 0.0 {
        return None;
    }
    let one_stroke = median(&fork[0].0.widths).max(median(&fork[1].0.widths));
    // A pixel's rounding is half the stroke or more: the ink cannot show where two strokes
    // become one (lines one or two pixels wide).
    if one_stroke < 2.0 * ONE_STROKE_PX {
        return None;
    }
    let limit = one_stroke + ONE_STROKE_PX;
    let (points, widths) = outwards_with_widths(stem.0, stem.1);
    let mut along = 0.0;
    let mut start = None;
    for i in 1..points.len() {
        along += dist(points[i - 1], points[i]);
        if widths[i] <= limit {
            start = Some((i, along));
            break;
        }
    }
    let (i, moved) = start?;
    if moved < MIN_MOVE * one_stroke || moved > MAX_MOVE * one_stroke {
        return None;
    }
    // One stroke's ink for a width on.
    let mut run = 0.0;
    for j in i + 1..points.len() {
        run += dist(points[j - 1], points[j]);
        let near_junction = far_junction.is_some_and(|f| dist(points[j], f) < one_stroke);
        if widths[j] > limit || near_junction {
            return None;
        }
        if run >= ONE_STROKE_RUN * one_stroke {
            return Some((i, points[i]));
        }
    }
    None
}

/// The points and widths of `edge` listed outwards from its start (`at_start`) or its end.
fn outwards_with_widths(edge: &Edge, at_start: bool) -> (Vec<[f64; 2]>, Vec<f64>) {
    if at_start {
        (edge.points.clone(), edge.widths.clone())
    } else {
        (
            edge.points.iter().rev().copied().collect(),
            edge.widths.iter().rev().copied().collect(),
        )
    }
}

/// Drops the first `cut` points of `edge` counted from its start (`at_start`) or its end, and
/// starts (ends) it at `q`.
fn rejoin(edge: &mut Edge, at_start: bool, cut: usize, q: [f64; 2]) {
    let n = edge.points.len();
    if at_start {
        let width = edge.widths[0];
        edge.points.drain(..cut);
        edge.widths.drain(..cut);
        edge.points.insert(0, q);
        edge.widths.insert(0, width);
    } else {
        let width = edge.widths[n - 1];
        edge.points.truncate(n - cut);
        edge.widths.truncate(n - cut);
        edge.points.push(q);
        edge.widths.push(width);
    }
}

/// Drops the `i` points of `edge` before its `i`-th counted from its start (`at_start`) or its
/// end, which becomes that end.
fn trim_start(edge: &mut Edge, at_start: bool, i: usize) {
    let n = edge.points.len();
    if at_start {
        edge.points.drain(..i);
        edge.widths.drain(..i);
    } else {
        edge.points.truncate(n - i);
        edge.widths.truncate(n - i);
    }
}
