//! Spurs: the arms test (§3.1's idea applied to the skeleton) decides which terminal branches
//! are the boundary's bumps and go ([`Work::prune_spurs`], [`spur_reach`]). docs/design.md,
//! "Skeleton-carried geometry".
//!
//! The experiment `decide_by_ink` (`ExperimentParams::decide_by_ink`) decides instead by which
//! of two drawings explains the ink ([`ink_only_arm`]): the junction's strokes with the branch
//! (the arm kept) or without it (the arm cut), each drawn with a round pen of each edge's
//! measured (median) width; the arm is kept when the ink only it explains, less the background it covers, outweighs
//! the cost of one more part, [`PART_COST`] squared widths.

use std::cmp::Ordering;

use crate::geometry::{cmp_dist, dist, dist_bounds, unit};

use super::crossings::arm_point;
use super::work::{median, Ink, Work};
use super::{disk_radius, MIN_WIDTH_PX};

/// A branch whose tip lies farther than this many stroke widths (plus [`SPUR_TIP_MARGIN_PX`])
/// from its junction is an arm: the envelope reaches at most about 4 widths from the junction.
const SPUR_TIP_REACH: f64 = 5.0;

/// See [`SPUR_TIP_REACH`] (px): a hairline's junction disk and a pixel of its tip.
const SPUR_TIP_MARGIN_PX: f64 = 2.0;

/// The envelope a branch is measured against holds the junction's other edges' points within
/// this many stroke widths of it: the strokes the branch leaves, not their far ends.
const ENVELOPE_REACH: f64 = 3.0;

/// A spur reaches at most this many stroke widths beyond the envelope (a sharp corner's branch
/// reaches about `0.2 w`); an arm half a width long or more reaches beyond it.
const SPUR_REACH: f64 = 0.4;

/// See [`SPUR_REACH`] (px): a bump of the boundary reaches about a pixel.
const SPUR_REACH_PX: f64 = 1.5;

/// The cost of one more part (an arm and its end), in squared stroke widths, against which the
/// ink only the arm explains is weighed (`decide_by_ink`): half a square of the stroke's width.
/// A round pen's cap is `pi / 8 = 0.39` squared widths: an end's cap sticking out of the
/// stroke it leaves is no evidence of an arm; an arm half a width longer than its cap is.
pub(super) const PART_COST: f64 = 0.5;

impl Work {
    /// Spurs: terminal branches whose ink does not reach beyond their junction's disk by more
    /// than `max(1.5 px, 0.4 w)` ([`SPUR_REACH_PX`], [`SPUR_REACH`]) are removed, least reaching first, while
    /// their junction keeps three edges (of the two stubs of a forked stroke end, the longer
    /// one stays as the stroke's end). A sharp corner's branch reaches about `0.2 w`, a boundary
    /// bump about a pixel; an arm half a width long or more is kept. Two short branches of one
    /// junction that line up are one stroke crossing the others and are judged together
    /// ([`judge_crossbars`]).
    ///
    /// With `strokes` (not a print's ridges), a branch's reach counts the ink its line runs on
    /// beyond its tip, up to half a width: thinning erodes a branch's tip by about that, most
    /// along a diagonal (an arm a width long at 45° kept its junction's disk and little more).
    /// And it is measured from where the lines it leaves pass ([`undipped`]) at every width:
    /// thinning bends a line a pixel into a branch that leaves it square whatever the width,
    /// and at three or four pixels that pixel is a third of the width (the teeth of a comb a
    /// width long were cut). On ridges, only on one-pixel lines, as the minutiae were measured.
    ///
    /// With `by_ink` (the experiment `decide_by_ink`), a branch is a spur when the ink only it
    /// explains ([`ink_only_arm`]) is at most [`PART_COST`] squared stroke widths; least first.
    pub(super) fn prune_spurs(&mut self, by_ink: bool, strokes: bool) {
        let mut degree = self.degrees();
        let at = self.incident();
        // The stroke width an arm leaves: the narrowest median width of the junction's other
        // edges (the width at the junction itself is inflated where strokes meet).
        let mut spurs = Vec::new();
        let mut twins = Vec::new();
        // The reach rule's branches: how far each reaches past its limit, and its direction.
        let mut branches = Vec::new();
        for (e, edge) in self.edges.iter().enumerate() {
            let Some(edge) = edge else { continue };
            let (junction, tip, forward) = match (degree[edge.from], degree[edge.to]) {
                (1, d) if d >= 3 => (edge.to, edge.from, false),
                (d, 1) if d >= 3 => (edge.from, edge.to, true),
                _ => continue,
            };
            let others = || {
                at.row(junction)
                    .iter()
                    .filter(move |&&o| o != e)
                    .filter_map(|&o| self.edges[o].as_ref())
            };
            let stroke = others()
                .map(|other| median(&other.widths))
                .fold(f64::INFINITY, f64::min);
            let j = &self.vertices[junction];
            let stroke = if stroke.is_finite() { stroke } else { j.width };
            let tip_pos = self.vertices[tip].pos;
            if dist(tip_pos, j.pos) > SPUR_TIP_REACH * stroke.max(MIN_WIDTH_PX) + SPUR_TIP_MARGIN_PX
            {
                continue;
            }
            let mut points = edge.points.clone();
            let mut widths = edge.widths.clone();
            if !forward {
                points.reverse();
                widths.reverse();
            }
            if by_ink {
                // Each hypothesis is drawn with a round pen of each edge's own width (its median):
                // the disks the skeleton measures near a junction are inflated by the very ink in
                // question. The cut hypothesis draws the junction with the narrowest of its
                // strokes and the other edges' points that can reach the branch's disks.
                let pen = median(&widths);
                let reach = dist(tip_pos, j.pos) + disk_radius(pen) + 2.0 * disk_radius(stroke);
                let mut drawn = vec![(j.pos, stroke)];
                for other in others() {
                    let own = median(&other.widths);
                    drawn.extend(
                        other
                            .points
                            .iter()
                            .filter(|&&q| dist(q, j.pos) <= reach)
                            .map(|&q| (q, own)),
                    );
                }
                let arm = vec![pen; points.len()];
                let gain = ink_only_arm(&self.ink, &points, &arm, &drawn);
                let w = stroke.max(MIN_WIDTH_PX);
                if gain <= PART_COST * w * w {
                    spurs.push((gain, e, junction, tip));
                }
                continue;
            }
            // The envelope: the junction, put back where the lines it leaves pass
            // ([`undipped`]), and its other edges' points near it.
            let centre = if strokes || stroke <= MIN_WIDTH_PX {
                undipped(j.pos, &points, others().map(|o| first_step(o, junction)))
            } else {
                j.pos
            };
            let mut envelope = vec![(centre, j.width)];
            for other in others() {
                envelope.extend(
                    other
                        .points
                        .iter()
                        .copied()
                        .zip(other.widths.iter().copied())
                        .filter(|&(q, _)| {
                            cmp_dist(q, j.pos, ENVELOPE_REACH * stroke).is_some_and(Ordering::is_le)
                        })
                        .filter(|&(q, _)| centre == j.pos || q != j.pos),
                );
            }
            // Thinning erodes a branch's tip, most along a diagonal (about half its width, the
            // same erosion [`Work::extend_ends`] makes up for): the ink the branch's own line
            // runs on beyond its tip is the branch's too, the farthest point of it a disk of
            // half a pixel.
            let (tip_at, back) = (points[points.len() - 1], points[0]);
            let axis = unit([tip_at[0] - back[0], tip_at[1] - back[1]]).filter(|_| strokes);
            if let Some(axis) = axis {
                let on = (self.ink.exit(tip_at, axis, 2.0 * stroke + 4.0) - 0.5)
                    .min(disk_radius(stroke));
                if on > 0.0 {
                    points.push([tip_at[0] + on * axis[0], tip_at[1] + on * axis[1]]);
                    widths.push(0.0);
                }
            }
            let mut reach = spur_reach(&points, &widths, &envelope);
            let limit = (SPUR_REACH * stroke).max(SPUR_REACH_PX);
            if strokes && reach <= limit {
                let row = at.row(junction);
                if let Some(twin) = self.lost_twin(junction, centre, row, e, limit) {
                    reach = f64::INFINITY;
                    twins.push((junction, twin, self.vertices[tip].width));
                } else if row.len() == 4 {
                    // A twin restored (or kept by thinning): the bar and, opposite, another
                    // short branch.
                    let others: Vec<usize> = row.iter().copied().filter(|&o| o != e).collect();
                    let short = |o: usize| {
                        self.edges[o].as_ref().is_some_and(|x| {
                            let far = if x.from == junction { x.to } else { x.from };
                            degree[far] == 1
                                && dist(self.vertices[far].pos, j.pos)
                                    <= SPUR_TIP_REACH * stroke.max(MIN_WIDTH_PX)
                                        + SPUR_TIP_MARGIN_PX
                        })
                    };
                    let crossing = (0..3).any(|k| {
                        let bar = [others[(k + 1) % 3], others[(k + 2) % 3]];
                        short(others[k]) && self.crosses_bar(junction, centre, bar, e, limit)
                    });
                    if crossing {
                        reach = f64::INFINITY;
                    }
                }
            }
            let away = unit([tip_pos[0] - j.pos[0], tip_pos[1] - j.pos[1]]);
            branches.push(Branch {
                reach,
                limit,
                stroke,
                edge: e,
                junction,
                tip,
                away,
            });
        }
        let verdicts = judge_crossbars(&branches, &degree);
        spurs.extend(
            branches
                .iter()
                .zip(verdicts)
                .filter(|(b, spur)| spur.unwrap_or(b.reach <= b.limit))
                .map(|(b, _)| (b.reach, b.edge, b.junction, b.tip)),
        );
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
        for (v, (points, widths), width) in twins {
            let end = self.vertices.len();
            self.vertices.push(crate::stroke_graph::Vertex {
                pos: points[points.len() - 1],
                degree: 1,
                width,
            });
            self.alive.push(true);
            self.dot.push(false);
            self.edges.push(Some(crate::stroke_graph::Edge {
                from: v,
                to: end,
                points,
                widths,
                directions: Vec::new(),
            }));
        }
    }
}

impl Work {
    /// The lost half of a short stroke crossing another. Thinning a `+` whose arms are about a
    /// width long may keep one arm's branch, a pixel or two long, and erode the other's into the
    /// bar (Zhang-Suen's passes are not symmetric), the bar's line a pixel off its middle: a T
    /// whose one short branch reaches no farther than a bump, though the ink shows a cross.
    /// Where the degree-3 junction `v`'s edges other than its terminal branch `e` run straight
    /// through it ([`Work::straight_through`]) and the branch leaves them at more than
    /// [`TWIN_ACROSS_DEG`], the ink along the branch's line is measured on both sides of the
    /// bar's ink (the bar's edges found where the bar is clear of the crossing): where it
    /// reaches beyond both by more than `limit` (a spur's reach, as [`Work::prune_spurs`]), the
    /// branch is an arm and its mirror image through the junction, on the ink all along, is its
    /// lost twin: returned as the twin's points and widths, listed from the junction.
    fn lost_twin(
        &self,
        v: usize,
        jp: [f64; 2],
        at: &[usize],
        e: usize,
        limit: f64,
    ) -> Option<Twin> {
        let edge = self.edges[e].as_ref()?;
        // Only a T has lost a twin; a junction of degree four is judged by its branches.
        let [a, b] = at.iter().copied().filter(|&o| o != e).collect::<Vec<_>>()[..] else {
            return None;
        };
        if !self.crosses_bar(v, jp, [a, b], e, limit) {
            return None;
        }
        let forward = edge.from == v;
        let mut points: Vec<[f64; 2]> = edge
            .points
            .iter()
            .map(|&p| [2.0 * jp[0] - p[0], 2.0 * jp[1] - p[1]])
            .collect();
        let mut widths = edge.widths.clone();
        if !forward {
            points.reverse();
            widths.reverse();
        }
        // The twin starts at the junction itself, wherever thinning left it.
        points[0] = self.vertices[v].pos;
        points
            .iter()
            .all(|&p| self.ink.at(p))
            .then_some((points, widths))
    }

    /// Whether the terminal branch `e` of the junction `v` (put back at `jp`) crosses the bar
    /// its edges `bar` make (straight through `jp`, [`Work::straight_through`]) at more than
    /// [`TWIN_ACROSS_DEG`], its ink reaching beyond both of the bar's ink edges along its line
    /// by more than `limit` (see [`Work::lost_twin`]).
    fn crosses_bar(&self, v: usize, jp: [f64; 2], bar: [usize; 2], e: usize, limit: f64) -> bool {
        let measured = || -> Option<bool> {
            // The junction put on the bar's line (thinning may leave it a pixel into the
            // branch: [`Work::undip_junctions`] comes later).
            let [pa, pb] = [bar[0], bar[1]].map(|o| {
                self.edges[o]
                    .as_ref()
                    .map(|x| arm_point(x, x.from == v, jp, median(&x.widths).max(2.0)))
            });
            let (pa, pb) = (pa?, pb?);
            let d = unit([pb[0] - pa[0], pb[1] - pa[1]])?;
            let t = (jp[0] - pa[0]) * d[0] + (jp[1] - pa[1]) * d[1];
            let jp = [pa[0] + t * d[0], pa[1] + t * d[1]];
            if !self.straight_through(v, bar, jp) {
                return Some(false);
            }
            let edge = self.edges[e].as_ref()?;
            let tip = if edge.from == v {
                edge.points[edge.points.len() - 1]
            } else {
                edge.points[0]
            };
            let b = unit([tip[0] - jp[0], tip[1] - jp[1]])?;
            let stroke = median(&edge.widths).max(MIN_WIDTH_PX);
            let bar_edge = self.edges[bar[0]].as_ref()?;
            let bar_width = median(&bar_edge.widths).max(MIN_WIDTH_PX);
            let far = arm_point(bar_edge, bar_edge.from == v, jp, bar_width.max(2.0));
            let u = unit([far[0] - jp[0], far[1] - jp[1]])?;
            let sine = u[0] * b[1] - u[1] * b[0];
            if sine.abs() < TWIN_ACROSS_DEG.to_radians().sin() {
                return Some(false);
            }
            // The bar's normal on the branch's side, and its two ink edges measured on each
            // side of the crossing, clear of the crossing stroke's ink.
            let n = if sine > 0.0 {
                [-u[1], u[0]]
            } else {
                [u[1], -u[0]]
            };
            let clear = stroke + bar_width + 2.0;
            let mut edges = [0.0, 0.0];
            for &o in &bar {
                let other = self.edges[o].as_ref()?;
                let q = arm_point(other, other.from == v, jp, clear);
                if dist(q, jp) < clear - 1.0 {
                    return Some(false);
                }
                let across = 2.0 * bar_width + 4.0;
                edges[0] += (self.ink.exit(q, n, across) - INK_EDGE_PX) / 2.0;
                edges[1] += (self.ink.exit(q, [-n[0], -n[1]], across) - INK_EDGE_PX) / 2.0;
            }
            let reach = 4.0 * stroke + 4.0 + bar_width;
            let own = (self.ink.exit(jp, b, reach) - INK_EDGE_PX) * sine.abs() - edges[0];
            let twin =
                (self.ink.exit(jp, [-b[0], -b[1]], reach) - INK_EDGE_PX) * sine.abs() - edges[1];
            // One stroke crossing the bar reaches alike either side, within half a width (a
            // branch thinning did not make needs more than [`judge_crossbars`]' one width): a
            // long arm does not vouch for a bump opposite it.
            let alike =
                (own - twin).abs() <= (TWIN_REACH_DIFF * stroke).max(CROSSBAR_REACH_DIFF_PX);
            Some(alike && own.min(twin) > limit)
        };
        measured().unwrap_or(false)
    }
}

/// A lost twin arm's points and widths ([`Work::lost_twin`]).
type Twin = (Vec<[f64; 2]>, Vec<f64>);

/// A junction's short branch and the bar it leaves cross at more than this (degrees) for the
/// branch's lost twin to be looked for ([`Work::lost_twin`]).
const TWIN_ACROSS_DEG: f64 = 60.0;

/// How much farther (stroke widths) the ink on one side of a bar may reach than on the other for
/// the two to be one stroke crossing it ([`Work::crosses_bar`]).
const TWIN_REACH_DIFF: f64 = 0.5;

/// Where the ink ends along a line, before the first sample off it (px): half a sample step.
const INK_EDGE_PX: f64 = 0.25;

impl Work {
    /// Junctions put back where the lines pass. Making the skeleton one pixel thick
    /// removes a straight line's pixel beside a branch that leaves it square (the line's two
    /// pixels either side stay 8-connected through the branch's first pixel: docs/design.md,
    /// "Skeleton-carried geometry", the skeleton made one pixel thick), so the line dips a pixel
    /// into the branch and the junction sits on the branch. On lines one pixel wide that pixel
    /// is a whole width: measured from there, a branch two pixels long reaches no farther than
    /// a boundary bump (and [`Work::prune_spurs`] would cut it), and the line's fit sags off the
    /// ink (docs/quality.md, "Thin drawings (issue 31)"); on wider strokes the junction and
    /// its T's bar sit a pixel off the bar's middle (docs/quality.md, "seventeenth: arms
    /// measured from the line"). Where a degree-3 junction's two other edges leave it through
    /// its diagonal neighbours two pixels apart on one row or column, and the third leaves it
    /// straight away from their middle, the junction moves to that middle (the removed pixel,
    /// on the ink) and the third edge starts there: on lines of median width one pixel
    /// always; with `strokes` (not a print's ridges), on wider lines that run straight through
    /// ([`Work::straight_through`]).
    pub(super) fn undip_junctions(&mut self, strokes: bool) {
        let degree = self.degrees();
        let at = self.incident();
        for (v, &d) in degree.iter().enumerate() {
            if !self.alive[v] || d != 3 || at.row(v).len() != 3 {
                continue;
            }
            let j = self.vertices[v].pos;
            let steps: Vec<Option<[f64; 2]>> = at
                .row(v)
                .iter()
                .map(|&e| self.edges[e].as_ref().and_then(|edge| first_step(edge, v)))
                .collect();
            let Some(steps) = steps.into_iter().collect::<Option<Vec<_>>>() else {
                continue;
            };
            for k in 0..3 {
                let (a, b, next) = (steps[(k + 1) % 3], steps[(k + 2) % 3], steps[k]);
                let Some(middle) = dip_middle(j, a, b) else {
                    continue;
                };
                // The branch leaves straight away from the middle: its first step is the
                // junction's 4-neighbour opposite the middle.
                let away = [2.0 * j[0] - middle[0], 2.0 * j[1] - middle[1]];
                let line_width = |e: usize| {
                    self.edges[e]
                        .as_ref()
                        .map_or(f64::INFINITY, |edge| median(&edge.widths))
                };
                let (branch, lines) = (
                    at.row(v)[k],
                    [at.row(v)[(k + 1) % 3], at.row(v)[(k + 2) % 3]],
                );
                // On one-pixel lines always; on wider strokes (not a print's ridges, whose
                // minutiae were measured without) where the line runs straight through.
                let thin = lines.iter().all(|&e| line_width(e) <= MIN_WIDTH_PX);
                if next != away || !(thin || strokes && self.straight_through(v, lines, middle)) {
                    continue;
                }
                for e in lines {
                    if let Some(edge) = self.edges[e].as_mut() {
                        set_end(edge, v, middle);
                    }
                }
                if let Some(edge) = self.edges[branch].as_mut() {
                    let width = edge.widths.first().copied().unwrap_or(MIN_WIDTH_PX);
                    extend_end(edge, edge.from == v, middle, width);
                }
                self.vertices[v].pos = middle;
                break;
            }
        }
    }
}

impl Work {
    /// Whether the edges `lines` of the junction `v` are one straight line through `middle`:
    /// their points a width (two pixels at least) from the junction lie on opposite sides of
    /// it within [`STRAIGHT_THROUGH_DEG`]. A T's bar; not a stroke that leaves a stem at a
    /// shallow angle (the shoulder of an `h`), where the junction stays where thinning put it.
    fn straight_through(&self, v: usize, lines: [usize; 2], middle: [f64; 2]) -> bool {
        let j = self.vertices[v].pos;
        let mut far = lines.iter().filter_map(|&e| {
            let edge = self.edges[e].as_ref()?;
            let p = arm_point(edge, edge.from == v, j, median(&edge.widths).max(2.0));
            unit([p[0] - middle[0], p[1] - middle[1]])
        });
        let (Some(u), Some(t)) = (far.next(), far.next()) else {
            return false;
        };
        u[0] * t[0] + u[1] * t[1] < -STRAIGHT_THROUGH_DEG.to_radians().cos()
    }
}

/// A line is straight through a junction when its two sides leave it within this angle
/// (degrees) of opposite directions ([`Work::straight_through`]).
const STRAIGHT_THROUGH_DEG: f64 = 18.0;

/// The point after `junction` on `edge` (its pixel next to the junction's), if any.
fn first_step(edge: &crate::stroke_graph::Edge, junction: usize) -> Option<[f64; 2]> {
    let n = edge.points.len();
    if n < 2 || edge.from == edge.to {
        return None;
    }
    Some(if edge.from == junction {
        edge.points[1]
    } else {
        edge.points[n - 2]
    })
}

/// Adds `point` (of width `width`) to `edge`, before its first point when `at_start`, else after
/// its last: the edge carried on past its end.
pub(super) fn extend_end(
    edge: &mut crate::stroke_graph::Edge,
    at_start: bool,
    point: [f64; 2],
    width: f64,
) {
    if at_start {
        edge.points.insert(0, point);
        edge.widths.insert(0, width);
    } else {
        edge.points.push(point);
        edge.widths.push(width);
    }
}

/// Moves `edge`'s end at `junction` to `to`.
fn set_end(edge: &mut crate::stroke_graph::Edge, junction: usize, to: [f64; 2]) {
    let n = edge.points.len();
    if edge.from == junction {
        edge.points[0] = to;
    } else {
        edge.points[n - 1] = to;
    }
}

/// The pixel thinning removed beside the junction `j` of a line that dips into a branch: the
/// middle of `a` and `b`, the line's pixels next to `j`, when both are diagonal neighbours of
/// `j` two pixels apart on one row or column ([`undipped`], [`Work::undip_junctions`]).
fn dip_middle(j: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    let diagonal = |p: [f64; 2]| (p[0] - j[0]).abs() == 1.0 && (p[1] - j[1]).abs() == 1.0;
    let apart = [(a[0] - b[0]).abs(), (a[1] - b[1]).abs()];
    (diagonal(a) && diagonal(b) && (apart == [2.0, 0.0] || apart == [0.0, 2.0]))
        .then(|| [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0])
}

/// Where the strokes a branch leaves pass its junction `j`. Thinning bends a straight line a
/// pixel into a branch that leaves it square (the line's pixel beside the branch is not needed
/// for its 8-connectivity, so it goes: docs/design.md, "Skeleton-carried geometry", the
/// skeleton made one pixel thick), and the junction with it: measured from there, a branch a
/// pixel longer than a boundary bump reaches as far as one, which at one to four pixels of
/// width is a real arm (docs/quality.md, "Thin drawings (issue 31)" and "seventeenth: arms
/// measured from the line"). When the two other edges'
/// pixels next to the junction are its diagonal neighbours on one row or column, two pixels
/// apart, and the branch leaves the junction away from them, the line passes through their
/// middle; else through the junction itself.
fn undipped(
    j: [f64; 2],
    branch: &[[f64; 2]],
    mut steps: impl Iterator<Item = Option<[f64; 2]>>,
) -> [f64; 2] {
    let (Some(Some(a)), Some(Some(b)), None) = (steps.next(), steps.next(), steps.next()) else {
        return j;
    };
    let Some(&next) = branch.get(1) else {
        return j;
    };
    let Some(middle) = dip_middle(j, a, b) else {
        return j;
    };
    let out = [j[0] - middle[0], j[1] - middle[1]];
    let towards = [next[0] - j[0], next[1] - j[1]];
    if out[0] * towards[0] + out[1] * towards[1] > 0.0 {
        middle
    } else {
        j
    }
}

/// Branches that leave a junction in opposite directions within this angle (degrees) line up:
/// the two halves of one stroke crossing the junction's others.
const CROSSBAR_ANGLE_DEG: f64 = 30.0;

/// The most two halves of one bar across a stroke differ in reach is the crossed stroke's width
/// (the skeleton's junction lies up to half of it off the stroke's middle, which one half gains
/// and the other loses), and at least this (px): a pixel either way on hairlines.
const CROSSBAR_REACH_DIFF_PX: f64 = 2.0;

/// A terminal branch the reach rule judges ([`Work::prune_spurs`]).
struct Branch {
    /// How far its ink reaches beyond the envelope ([`spur_reach`]), px.
    reach: f64,
    /// The most a spur reaches: `max(1.5 px, 0.4 w)`.
    limit: f64,
    /// The width `w` of the strokes it leaves (the narrowest), px.
    stroke: f64,
    edge: usize,
    junction: usize,
    tip: usize,
    /// The unit direction from the junction to the tip.
    away: Option<[f64; 2]>,
}

/// A short stroke crossing another (the bar of a `t` or an `f`, a `+`) leaves the skeleton two
/// short branches at one junction, one either side, whose reaches differ by the pixel grid: the
/// junction lies off the crossed stroke's middle, which one branch gains and the other loses.
/// Judged one by one, the longer can be kept and the shorter cut, and a symmetric cross comes out
/// as a T. So where two branches of a junction of degree four or more leave it in opposite
/// directions (within [`CROSSBAR_ANGLE_DEG`]) and reach alike (within a stroke width,
/// [`CROSSBAR_REACH_DIFF_PX`] at least: a long arm does not vouch for a bump opposite it), they
/// are one stroke and share one verdict: an arm when either reaches past its limit (the ink
/// shows the bar runs past the stroke), spurs when neither does. Each branch pairs at most once,
/// the most nearly opposite pairs first. Returns, per branch, the pair's verdict (`Some(true)`:
/// a spur), `None` for a branch judged alone.
fn judge_crossbars(branches: &[Branch], degree: &[usize]) -> Vec<Option<bool>> {
    let opposite = -CROSSBAR_ANGLE_DEG.to_radians().cos();
    // Pairs only within a junction: the branches grouped by junction (stable, so each group's
    // pairs come in rising order), never all pairs of the chunk.
    let mut by_junction: Vec<usize> = (0..branches.len()).collect();
    by_junction.sort_by_key(|&i| branches[i].junction);
    let mut pairs = Vec::new();
    for group in by_junction.chunk_by(|&i, &k| branches[i].junction == branches[k].junction) {
        if degree[branches[group[0]].junction] < 4 {
            continue;
        }
        for (n, &i) in group.iter().enumerate() {
            for &k in &group[n + 1..] {
                let (a, b) = (&branches[i], &branches[k]);
                if (a.reach - b.reach).abs() > a.stroke.min(b.stroke).max(CROSSBAR_REACH_DIFF_PX) {
                    continue;
                }
                let (Some(u), Some(v)) = (a.away, b.away) else {
                    continue;
                };
                let c = u[0] * v[0] + u[1] * v[1];
                if c <= opposite {
                    pairs.push((c, i, k));
                }
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut verdicts = vec![None; branches.len()];
    for (_, i, k) in pairs {
        if verdicts[i].is_some() || verdicts[k].is_some() {
            continue;
        }
        let (a, b) = (&branches[i], &branches[k]);
        let spur = a.reach <= a.limit && b.reach <= b.limit;
        verdicts[i] = Some(spur);
        verdicts[k] = Some(spur);
    }
    verdicts
}

/// How far the ink of a terminal branch reaches beyond the envelope of the strokes it leaves:
/// for each of its points `p` (with `r(p)` the half-width there), how far its disk sticks out of
/// the nearest-fitting disk `(q, r(q))` among `envelope` (the junction and the points of its
/// other edges), `min_q |p - q| + r(p) - r(q)`; the largest over the branch. A spur, a bump of
/// the boundary or the branch into a rounded corner, reaches about a pixel; an arm's ink sticks
/// out by its length. Widths are full widths (`r = (w + 1) / 2`, the pixel itself counted).
pub(super) fn spur_reach(points: &[[f64; 2]], widths: &[f64], envelope: &[([f64; 2], f64)]) -> f64 {
    points
        .iter()
        .zip(widths)
        .map(|(&p, &w)| {
            let r = disk_radius(w);
            // The least excess; a disk whose excess from the distance's lower bound is already
            // more than the least so far leaves it (rounding keeps the order of the sums).
            envelope.iter().fold(f64::INFINITY, |least, &(q, wq)| {
                let rq = disk_radius(wq);
                if dist_bounds(p, q).is_some_and(|(low, _)| low + r - rq > least) {
                    least
                } else {
                    least.min(dist(p, q) + r - rq)
                }
            })
        })
        .filter(|e| e.is_finite())
        .fold(0.0f64, f64::max)
}

/// Whether pixel center `c` lies inside the round pen's disk of full width `w` (the pixel itself
/// counted, as the widths are) at `p`: a skeleton pixel's disk holds exactly the ink pixels
/// closer to it than the nearest background pixel.
fn in_disk(c: [f64; 2], p: [f64; 2], w: f64) -> bool {
    cmp_dist(c, p, disk_radius(w)).is_some_and(Ordering::is_lt)
}

/// How much better the drawing with the arm explains the ink than the drawing without it, px:
/// over the pixels that the branch's disks (`points`, `widths`) cover and none of `drawn`'s (the
/// junction and its other edges) does, the ink pixels (ink only the arm explains) less the
/// background pixels (what the arm draws where there is none). Elsewhere the two drawings agree,
/// so this is the difference of their errors (ink not covered plus covered background).
pub(super) fn ink_only_arm(
    ink: &Ink,
    points: &[[f64; 2]],
    widths: &[f64],
    drawn: &[([f64; 2], f64)],
) -> f64 {
    let arm: Vec<([f64; 2], f64)> = points.iter().copied().zip(widths.iter().copied()).collect();
    worse_by(ink, &arm, &[], drawn)
}

/// How much worse the drawing `common` + `second` explains the ink than `common` + `first`, px:
/// each drawn with round pens (a disk of its full width at each point), the error of a drawing
/// is the ink it leaves uncovered plus the background it covers. The two agree outside the
/// disks of `first` and `second` and wherever `common` covers, so the difference is counted over
/// the other pixels of their disks alone: an ink pixel only `first` covers, or a background pixel
/// only `second` covers, counts one against `second`; the reverse, one for it.
pub(super) fn worse_by(
    ink: &Ink,
    first: &[([f64; 2], f64)],
    second: &[([f64; 2], f64)],
    common: &[([f64; 2], f64)],
) -> f64 {
    let mut min = [f64::INFINITY; 2];
    let mut max = [f64::NEG_INFINITY; 2];
    for &(p, w) in first.iter().chain(second) {
        let r = disk_radius(w);
        for k in 0..2 {
            min[k] = min[k].min(p[k] - r);
            max[k] = max[k].max(p[k] + r);
        }
    }
    if !min[0].is_finite() {
        return 0.0;
    }
    let covers =
        |drawing: &[([f64; 2], f64)], c: [f64; 2]| drawing.iter().any(|&(p, w)| in_disk(c, p, w));
    // Pixel centers of the window, in image coordinates (pixel `x` of the ink's window covers
    // `origin + [x, x + 1)`).
    let to_index = |v: f64, k: usize| (v - ink.origin[k] - 0.5).ceil() as i64;
    let mut worse = 0.0;
    for y in to_index(min[1], 1)..=to_index(max[1], 1) {
        for x in to_index(min[0], 0)..=to_index(max[0], 0) {
            let c = [
                ink.origin[0] + x as f64 + 0.5,
                ink.origin[1] + y as f64 + 0.5,
            ];
            let (a, b) = (covers(first, c), covers(second, c));
            if a == b || covers(common, c) {
                continue;
            }
            // Only one of the two drawings covers this pixel: right on ink, wrong off it.
            worse += if ink.at(c) == a { 1.0 } else { -1.0 };
        }
    }
    worse
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::params::Params;
    use crate::synth::{drawn, render, Stroke};

    /// Junction degrees and the number of ends of the traced stem-on-bar: a bar 8 px wide
    /// across, a stem from below running `over` px past the bar's centerline, by the ink.
    fn tee(over: f64) -> (Vec<usize>, usize) {
        let (w, c) = (8.0, [60.5, 40.5]);
        let strokes = [
            Stroke::new(vec![[c[0] - 45.0, c[1]], [c[0] + 45.0, c[1]]], w),
            Stroke::new(vec![[c[0], c[1] + 35.0], [c[0], c[1] - over]], w),
        ];
        let mut params = Params::default();
        params.experiments.decide_by_ink = true;
        shape(&render(&strokes, 121, 90), &params)
    }

    /// Junction degrees and the number of ends of `binary` traced with `params`.
    fn shape(binary: &crate::binary::Binary, params: &Params) -> (Vec<usize>, usize) {
        let graph = crate::trace_binary(binary, params).expect("trace").graph;
        let junctions = graph
            .junctions()
            .map(|v| graph.vertices[v].degree)
            .collect();
        (junctions, graph.endpoints().count())
    }

    #[test]
    fn by_the_ink_a_long_overhang_is_an_arm_and_a_short_one_is_not() {
        // Two widths past the bar: a crossing with four arms.
        assert_eq!(tee(16.0), (vec![4], 4));
        // A quarter width: the stem's cap inside the bar's ink, a T.
        assert_eq!(tee(2.0), (vec![3], 3));
    }

    #[test]
    fn the_ink_only_an_arm_explains_is_its_area_beyond_the_drawn_disks() {
        // Ink: a 9 px wide bar (rows 10-18) and a 5 px wide stub above it (rows 4-9). The
        // drawing without the arm covers the bar; the arm's disks cover the stub.
        let (width, height) = (40, 30);
        let mask: Vec<bool> = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                (10..19).contains(&y) || ((18..23).contains(&x) && (4..10).contains(&y))
            })
            .collect();
        let ink = Ink {
            mask,
            width,
            height,
            origin: [0.0, 0.0],
        };
        let drawn: Vec<([f64; 2], f64)> = (0..40).map(|x| ([x as f64 + 0.5, 14.5], 9.0)).collect();
        let arm = [[20.5, 10.5], [20.5, 8.5], [20.5, 6.5]];
        let gain = ink_only_arm(&ink, &arm, &[5.0, 5.0, 5.0], &drawn);
        // The stub's 30 pixels, less the few its round disks miss at the corners; no
        // background is covered (each disk holds only pixels nearer than its width says).
        assert!((20.0..=30.0).contains(&gain), "{gain}");
        assert_eq!(ink_only_arm(&ink, &[[20.5, 14.5]], &[9.0], &drawn), 0.0);
        // Two drawings compared: swapped, the difference changes sign; a drawing of the stub
        // against one that paints the background beside it instead.
        let stub: Vec<([f64; 2], f64)> = arm.iter().map(|&p| (p, 5.0)).collect();
        let beside: Vec<([f64; 2], f64)> = arm.iter().map(|&p| ([p[0] + 8.0, p[1]], 5.0)).collect();
        let worse = worse_by(&ink, &stub, &beside, &drawn);
        assert!(worse > 2.0 * 20.0, "{worse}");
        assert_eq!(worse_by(&ink, &beside, &stub, &drawn), -worse);
    }

    /// Junction degrees and the number of ends of a drawn `t`: a stem `w` px wide, 120 px
    /// tall, crossed 36 px below its top by a bar `w` px thick that runs `over` px past the
    /// stem's sides on both sides, square-ended, as fonts draw it.
    fn cross_bar(w: usize, over: usize) -> (Vec<usize>, usize) {
        let (width, height) = (80, 140);
        let (x0, y0) = (37, 10);
        let ink = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let stem = (x0..x0 + w).contains(&x) && (y0..y0 + 120).contains(&y);
                let bar =
                    (x0 - over..x0 + w + over).contains(&x) && (y0 + 36..y0 + 36 + w).contains(&y);
                stem || bar
            })
            .collect();
        let binary = crate::binary::Binary {
            width: width as u32,
            height: height as u32,
            ink,
        };
        shape(&binary, &Params::default())
    }

    #[test]
    fn a_short_bar_across_a_stroke_is_kept_or_cut_whole() {
        // At every width, as the bar runs farther past the stem, the skeleton goes from no arm
        // to a crossing, never through a T: the two halves' reaches differ by the pixel grid,
        // and judged one by one the shorter half went first (a T at 0.6-0.8 widths).
        for w in 3..=10 {
            let mut crossing = false;
            for over in 1..=w + 1 {
                let got = cross_bar(w, over);
                if got == (vec![4], 4) {
                    crossing = true;
                } else {
                    assert!(
                        !crossing && got == (vec![], 2),
                        "w {w}, over {over}: {got:?}"
                    );
                }
            }
            assert!(crossing, "w {w}: no crossing even a width past the stem");
        }
    }

    #[test]
    fn a_cross_thinned_into_a_tee_keeps_both_arms() {
        // A bar five pixels wide and a stroke as wide crossing it, a width past each edge with
        // a round cap, as a 4 px `+` rasterizes. Thinning keeps a one-pixel branch on one side
        // only and the bar's line a pixel off its middle: measured alone, that branch reached
        // no farther than a bump and the cross came out a bare line. The ink along the branch's
        // line reaches a width beyond both of the bar's edges: one crossing, four ends.
        let cap = |w: usize| {
            let pad = (5 - w) / 2;
            format!(
                "{}{}{}",
                ".".repeat(28 + pad),
                "#".repeat(w),
                ".".repeat(28 + pad)
            )
        };
        let bar = |inset: usize| {
            format!(
                "{}{}{}",
                ".".repeat(2 + inset),
                "#".repeat(57 - 2 * inset),
                ".".repeat(2 + inset)
            )
        };
        let mut rows = vec![String::new(), String::new(), cap(1), cap(3), cap(5), cap(5)];
        rows.extend([bar(2), bar(1), bar(0), bar(1), bar(2)]);
        rows.extend([cap(5), cap(5), cap(3), cap(1), String::new(), String::new()]);
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        assert_eq!(shape(&drawn(&rows), &Params::default()), (vec![4], 4));
        // The same stroke on one side only is no cross: no twin is made up for it. (Its one
        // arm, a width past the edge of a 5 px bar, is still lost: thinning leaves no branch.)
        let tee: Vec<&str> = [&rows[..11], &rows[15..]].concat();
        let (junctions, ends) = shape(&drawn(&tee), &Params::default());
        assert!(!junctions.contains(&4) && ends <= 3, "{junctions:?} {ends}");
        // A bump of a pixel on each side, mirrored alike: no arm either side.
        let bumps: Vec<&str> = [&rows[..2], &rows[5..12], &rows[15..]].concat();
        assert_eq!(shape(&drawn(&bumps), &Params::default()), (vec![], 2));
    }

    #[test]
    fn the_teeth_of_a_comb_a_width_long_are_arms() {
        // A bar three pixels wide and seven teeth three pixels wide running a width (three
        // rows) past its edge, the last row a pixel, as a 2 px comb rasterizes. Thinning bends
        // the bar a pixel into each tooth: measured from that pixel the teeth reached 0.4 w and
        // were cut; measured from where the bar passes, each is a width long and kept.
        let bar = "....#################################################.....";
        let rows = [
            "",
            "",
            bar,
            "...###################################################....",
            bar,
            ".........###...###...###...###...###...###...###..........",
            ".........###...###...###...###...###...###...###..........",
            "..........#.....#.....#.....#.....#.....#.....#...........",
            "",
            "",
        ];
        assert_eq!(
            shape(&drawn(&rows), &Params::default()),
            (vec![3; 7], 9),
            "every tooth a T and an end"
        );
        // Each T on the bar's middle row (y = 3.5), not on the pixel thinning bent into the
        // tooth.
        let graph = crate::trace_binary(&drawn(&rows), &Params::default())
            .expect("trace")
            .graph;
        for v in graph.junctions() {
            assert_eq!(graph.vertices[v].pos[1], 3.5, "{:?}", graph.vertices[v].pos);
        }
        // One row past the edge, a bump of the boundary: no arm.
        let one = [&rows[..5], &rows[7..]].concat();
        assert_eq!(shape(&drawn(&one), &Params::default()), (vec![], 2));
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

    #[test]
    fn an_arm_that_thinning_shortens_along_a_diagonal_is_kept() {
        // A bar and an arm at 45 degrees whose ink reaches one width beyond the bar's edge:
        // thinning erodes the arm's tip by about half a width, leaving a branch that by its own
        // disks reaches less than `0.4 w` past the junction's; the ink its line runs on beyond
        // the tip is the arm's. At every width the arm is kept: one junction, three ends.
        for w in [8.0f64, 12.0] {
            let c = [70.5, 50.5];
            let length = w + w / 2.0 * (std::f64::consts::SQRT_2 - 1.0);
            let d = std::f64::consts::FRAC_1_SQRT_2;
            let strokes = [
                Stroke::new(vec![[c[0] - 60.0, c[1]], [c[0] + 60.0, c[1]]], w),
                Stroke::new(vec![c, [c[0] + length * d, c[1] - length * d]], w),
            ];
            let shape = shape(&render(&strokes, 141, 80), &Params::default());
            assert_eq!(shape, (vec![3], 3), "w {w}");
        }
        // A bump of the bar's edge, a pixel and a half high and a width long, is no arm.
        let strokes = [
            Stroke::new(vec![[10.5, 40.5], [130.5, 40.5]], 8.0),
            Stroke::new(vec![[66.5, 39.0], [74.5, 39.0]], 8.0),
        ];
        assert_eq!(
            shape(&render(&strokes, 141, 80), &Params::default()),
            (vec![], 2)
        );
    }
}
