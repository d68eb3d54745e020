//! Ends and dots: an end carried on to the centre of its cap ([`Work::extend_ends`]); a blob no
//! longer than wide is a dot ([`Work::collapse_dots`]). docs/design.md, "Skeleton-carried
//! geometry".

use std::cmp::Ordering;

use crate::geometry::{cmp_dist, dist, hypot};

use super::work::{median, Clearance, Work};
use super::{disk_radius, MIN_LINE_PX, MIN_WIDTH_PX};

/// An end's direction is taken over this many stroke widths from its tip: beyond the cap that
/// thinning rounds.
const END_DIRECTION: f64 = 2.0;

/// The narrowest width (px) [`END_DIRECTION`] is measured in: a hairline's direction over at
/// least 3 px.
const END_DIRECTION_MIN_WIDTH_PX: f64 = 1.5;

/// The ink ahead of an end is followed at most this many stroke widths (plus
/// [`END_SEARCH_PX`]): thinning erodes an end by about a half-width, more along a diagonal.
const END_SEARCH: f64 = 2.0;

/// See [`END_SEARCH`] (px).
const END_SEARCH_PX: f64 = 4.0;

/// The cap's centre is looked for along the end's line every this many px
/// ([`Work::cap_centre`]).
const CAP_STEP_PX: f64 = 0.5;

/// The disks of the end's line that reach this near (px) to the farthest reach as far: the
/// ink's edge is known to a pixel ([`Work::cap_centre`]).
const CAP_REACH_PX: f64 = 1.0;

/// A cap's centre lies on the stroke's middle: the ink either side of it, across the end's line,
/// differs by at most this many stroke widths (a tail that curves away from the end's line is
/// still followed)...
const CAP_CENTRED: f64 = 0.25;

/// ...and at least this (px): a pixel either side.
const CAP_CENTRED_PX: f64 = 1.0;

/// An end is carried on by at least this (px), or stays: less is within its own pixel.
const MIN_EXTENSION_PX: f64 = 1.0;

/// The walk along the ink's middle beyond an end ([`Work::walk_middle`]) steps this far (px).
const WALK_STEP_PX: f64 = 0.5;

/// At each step the walk turns by at most this (degrees) either side, in steps of a third of it:
/// a terminal that curls (a `c`, the foot of a `3`) or a flag that leaves a stem at a slant.
const WALK_TURN_DEG: f64 = 30.0;

/// ...and by at most this (degrees) in all from the end's own direction: a stroke's terminal,
/// not a stroke of its own that meets it.
const WALK_TOTAL_TURN_DEG: f64 = 90.0;

/// The walk bounds a step's clearance by this many of the background centres it found last
/// (those of the steps before it and of the same step's other turns): a few, each one a
/// squared distance.
const WALK_KNOWN_BACKGROUND: usize = 8;

impl Work {
    /// Thinning erodes a stroke's end, most along a diagonal: each end is carried on along its
    /// own direction (taken over the last two widths) to where the ink ends, less the stroke's
    /// half-width, the centre of its cap; with `tails`, a stroke that narrows to its end is
    /// carried on to the centre of its own, narrower cap ([`Work::cap_centre`]), and a terminal
    /// that curls away from the end's line (a `c`, an `e`, the flag of a blackletter stem) along
    /// the ink's middle to its cap ([`Work::walk_middle`]) when that goes on farther. Ends are
    /// only ever lengthened.
    pub(super) fn extend_ends(&mut self, tails: bool) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            for at_start in [true, false] {
                let Some(edge) = &self.edges[e] else { break };
                let v = if at_start { edge.from } else { edge.to };
                if degree[v] != 1 || edge.from == edge.to || edge.points.len() < 2 {
                    continue;
                }
                let stroke = median(&edge.widths);
                let half = disk_radius(stroke);
                let mut inwards: Vec<[f64; 2]> = edge.points.clone();
                if !at_start {
                    inwards.reverse();
                }
                let tip = inwards[0];
                let back = inwards
                    .iter()
                    .find(|&&p| {
                        dist(p, tip) >= END_DIRECTION * stroke.max(END_DIRECTION_MIN_WIDTH_PX)
                    })
                    .copied()
                    .unwrap_or(inwards[inwards.len() - 1]);
                let d = [tip[0] - back[0], tip[1] - back[1]];
                let n = hypot(d[0], d[1]);
                if n < MIN_LINE_PX {
                    continue;
                }
                let u = [d[0] / n, d[1] / n];
                // Where the ink ends ahead of the tip (at most a few widths on).
                let exit = self.ink.exit(tip, u, END_SEARCH * stroke + END_SEARCH_PX);
                let reach = exit - half;
                // A stroke that narrows to its end (a brush's tail) ends at the centre of its
                // own cap, nearer the tip than the stroke's half-width.
                let cap = tails
                    .then(|| self.cap_centre(tip, u, exit, stroke))
                    .flatten();
                let reach = match cap {
                    Some(cap) if cap >= reach + MIN_EXTENSION_PX => cap,
                    _ => reach,
                };
                // A terminal that bends away from the end's line (thinning erodes a curling
                // tip most) is followed along the ink's middle instead, when that goes on
                // farther.
                let walk = tails
                    .then(|| {
                        self.walk_middle(&inwards, u, stroke, END_SEARCH * stroke + END_SEARCH_PX)
                    })
                    .flatten()
                    .filter(|(_, walked)| *walked >= reach.max(0.0) + MIN_EXTENSION_PX);
                let path = match walk {
                    Some((path, _)) => path,
                    None if reach >= MIN_EXTENSION_PX => {
                        vec![[tip[0] + reach * u[0], tip[1] + reach * u[1]]]
                    }
                    None => continue,
                };
                let width = edge.widths[if at_start { 0 } else { edge.widths.len() - 1 }];
                let edge = self.edges[e].as_mut().expect("live edge");
                // The walk's points in one splice: each inserted at the start on its own would
                // shift the whole edge once per point.
                let n = path.len();
                if at_start {
                    edge.points.splice(0..0, path.iter().rev().copied());
                    edge.widths.splice(0..0, std::iter::repeat_n(width, n));
                } else {
                    edge.points.extend_from_slice(&path);
                    edge.widths.extend(std::iter::repeat_n(width, n));
                }
                self.vertices[v].pos = path[path.len() - 1];
            }
        }
    }

    /// The centre of the cap of an end at `tip` going along `u`, whose ink ends `exit` px on:
    /// of the disks on the ink centred on the end's line (each as wide as the distance to the
    /// background, measured as the widths are), the nearest to the tip among those that reach
    /// as far ahead as any, within a pixel ([`CAP_REACH_PX`]). A round pen's cap is reached
    /// by every disk from its centre on, so that is the cap's centre (`exit` less the stroke's
    /// half-width, as before); where the stroke narrows to its end (a brush's tail), the disks
    /// reach farther the nearer the tip they lie, and the end is the centre of the narrower
    /// cap (docs/design.md, adaptation 13). Only on the stroke's middle ([`CAP_CENTRED_PX`]).
    fn cap_centre(&self, tip: [f64; 2], u: [f64; 2], exit: f64, stroke: f64) -> Option<f64> {
        let at = |t: f64| [tip[0] + t * u[0], tip[1] + t * u[1]];
        let mut reaches = Vec::new();
        let mut t = 0.0;
        while t < exit {
            reaches.push((t, t + self.ink.clearance(at(t), exit - t + 1.0)));
            t += CAP_STEP_PX;
        }
        let farthest = reaches
            .iter()
            .map(|r| r.1)
            .fold(f64::NEG_INFINITY, f64::max);
        let &(t, _) = reaches.iter().find(|r| r.1 >= farthest - CAP_REACH_PX)?;
        let (across, back) = ([-u[1], u[0]], [u[1], -u[0]]);
        let (a, b) = (
            self.ink.exit(at(t), across, exit),
            self.ink.exit(at(t), back, exit),
        );
        ((a - b).abs() <= (CAP_CENTRED * stroke).max(CAP_CENTRED_PX)).then_some(t)
    }

    /// The ink's middle followed on from the end of the edge whose points from its tip are
    /// `inwards`, going along `u`, at most `limit` px: every [`WALK_STEP_PX`] the step, of those
    /// turning at most [`WALK_TURN_DEG`] (and [`WALK_TOTAL_TURN_DEG`] from `u`), whose point
    /// lies farthest from the background (the straightest of equals): a medial-axis walk, into
    /// ink no wider than the stroke and never back along the edge. A point is an end where the
    /// ink ahead of it along its step goes on by at least the stroke's half-width: the centre of
    /// its cap, as [`Work::extend_ends`] finds it on a straight line. The walk's points to its
    /// last end (the smoothing fits the edge to its ink and keeps only the points its shape
    /// needs) and the length walked; `None` when no point is an end.
    fn walk_middle(
        &self,
        inwards: &[[f64; 2]],
        u: [f64; 2],
        stroke: f64,
        limit: f64,
    ) -> Option<(Vec<[f64; 2]>, f64)> {
        let tip = inwards[0];
        let half = disk_radius(stroke);
        // The edge's own points the walk could come back to: it goes on from the tip, never
        // back along the edge (a step whose point lies nearer one of them than the tip).
        let behind: Vec<[f64; 2]> = inwards[1..]
            .iter()
            .copied()
            .take_while(|&p| cmp_dist(p, tip, limit + 1.0).is_some_and(Ordering::is_le))
            .collect();
        let squared = |a: [f64; 2], b: [f64; 2]| {
            let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
            dx * dx + dy * dy
        };
        let widest = half + 1.0;
        let turn = WALK_TURN_DEG.to_radians();
        let cos_total = WALK_TOTAL_TURN_DEG.to_radians().cos();
        let (mut p, mut d) = (tip, u);
        let mut walked = 0.0;
        let mut path = Vec::new();
        let mut end = None;
        // The background centres nearest the points looked at so far (the last
        // [`WALK_KNOWN_BACKGROUND`] of them bound a step's clearances).
        let mut background: Vec<[f64; 2]> = Vec::new();
        // The seven turns' sines and cosines, the same at every step (worked out once: the
        // library's `sin_cos` per turn per step was most of the walk's arithmetic).
        let turns = [0.0, -1.0, 1.0, -2.0, 2.0, -3.0, 3.0].map(|k: f64| (k * turn / 3.0).sin_cos());
        while walked + WALK_STEP_PX <= limit {
            let mut best: Option<([f64; 2], [f64; 2], Clearance)> = None;
            for (s, c) in turns {
                let r = [d[0] * c - d[1] * s, d[0] * s + d[1] * c];
                // (A rounding's worth below: three turns of a third make the whole turn.)
                if r[0] * u[0] + r[1] * u[1] < cos_total - 1e-9 {
                    continue;
                }
                let q = [p[0] + WALK_STEP_PX * r[0], p[1] + WALK_STEP_PX * r[1]];
                if !self.ink.at(q) {
                    continue;
                }
                // A step no farther from a background centre already found than the best step
                // is from its nearest is not clearer (the best is kept among equals), so its
                // clearance is not needed: the same squared distances, compared as they are
                // found (`Ink::squared_to_centre`).
                if let Some((_, _, b)) = best {
                    if b.pixel.is_some()
                        && background
                            .iter()
                            .rev()
                            .take(WALK_KNOWN_BACKGROUND)
                            .any(|&c| self.ink.squared_to_centre(q, c) <= b.squared)
                    {
                        continue;
                    }
                }
                let to_tip = squared(q, tip);
                if behind.iter().any(|&b| squared(q, b) < to_tip) {
                    continue;
                }
                let clear = self.ink.nearest_background(q, widest);
                background.extend(clear.pixel);
                if best.is_none_or(|b| clear.clearance > b.2.clearance) {
                    best = Some((q, r, clear));
                }
            }
            let Some((q, r, clear)) = best else { break };
            let clear = clear.clearance;
            if clear > widest {
                break;
            }
            (p, d) = (q, r);
            walked += WALK_STEP_PX;
            path.push(p);
            if self.ink.exit(p, d, half + 1.0) > half {
                end = Some((path.len(), walked));
            }
        }
        let (n, walked) = end?;
        path.truncate(n);
        Some((path, walked))
    }

    /// A blob of ink no longer than it is wide (the dot of an `i`, a full stop) thins to a short
    /// segment between two ends: it is a dot, one vertex of degree 0 at the segment's middle.
    pub(super) fn collapse_dots(&mut self) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            if edge.from == edge.to || degree[edge.from] != 1 || degree[edge.to] != 1 {
                continue;
            }
            let length = edge.length();
            let width = edge.widths.iter().copied().fold(MIN_WIDTH_PX, f64::max);
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
}

#[cfg(test)]
mod tests {
    use crate::geometry::dist;
    use crate::params::Params;
    use crate::synth::{render, Stroke};

    /// The ends of a bar drawn from `(20.5, 40.5)` to `(110.5, 40.5)`, `start` px wide at its
    /// left end and `end` px wide at its right (each end a round cap of that width).
    fn bar_ends(start: f64, end: f64) -> Vec<[f64; 2]> {
        let n = 10;
        let points: Vec<[f64; 2]> = (0..=n).map(|i| [20.5 + 9.0 * i as f64, 40.5]).collect();
        let widths = (0..=n)
            .map(|i| start + (end - start) * i as f64 / n as f64)
            .collect();
        let binary = render(&[Stroke { points, widths }], 130, 80);
        let mut params = Params::default();
        params.finish.skeleton = true;
        let graph = crate::trace_binary(&binary, &params).expect("trace").graph;
        graph.endpoints().map(|v| graph.vertices[v].pos).collect()
    }

    #[test]
    fn a_stroke_that_narrows_ends_at_the_centre_of_its_own_cap() {
        // A brush's tail: 20 px wide narrowing to 5. The stroke's median half-width (about
        // 6 px) from the ink's end put the end about 4 px short of the narrow cap's centre.
        for (start, end) in [(20.0, 5.0), (16.0, 6.0)] {
            let ends = bar_ends(start, end);
            assert_eq!(ends.len(), 2, "{ends:?}");
            let tail = [110.5, 40.5];
            let nearest = ends
                .iter()
                .map(|&p| dist(p, tail))
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest <= 1.5,
                "{start} -> {end} px: ends {ends:?}, the tail's cap centre {tail:?}"
            );
        }
        // A stroke of one width keeps its end at its cap's centre.
        let ends = bar_ends(9.0, 9.0);
        for cap in [[20.5, 40.5], [110.5, 40.5]] {
            assert!(
                ends.iter().any(|&p| dist(p, cap) <= 1.0),
                "ends {ends:?}, cap centre {cap:?}"
            );
        }
    }
}
