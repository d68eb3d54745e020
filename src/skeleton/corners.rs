//! Corners: the Y that thinning makes of a sharp bend is a bend ([`Work::dissolve_corners`]).
//! docs/design.md, "Skeleton-carried geometry"; docs/quality.md, "Bold corners".

use std::cmp::Ordering;

use crate::geometry::{cmp_dist, dist, hypot, unit};

use super::spurs::{worse_by, PART_COST};
use super::work::{median, sampled, Work};
use super::{disk_radius, MIN_LINE_PX, MIN_WIDTH_PX};

/// Strokes at least this wide (px, the legs' median skeleton width) can show a bold corner
/// ([`Work::dissolve_corners`]): below it the skeleton's widths, known to a pixel, do not tell
/// ink where two strokes merge from one stroke.
const BOLD_CORNER_WIDTH: f64 = 5.0;

/// A bold corner's legs are both wider at the junction than this many stroke widths (plus
/// [`WIDTH_UNCERTAINTY_PX`]): their inks merge there.
const BOLD_LEG_WIDENING: f64 = 1.25;

/// The skeleton's widths are known to a pixel (px): a point of a leg is one stroke wide when
/// its width exceeds the stroke's by at most this.
const WIDTH_UNCERTAINTY_PX: f64 = 1.0;

/// A leg's line is taken over this many stroke widths: beyond where it bends towards the other
/// leg, short enough to be straight.
const LEG_LINE: f64 = 2.0;

/// A bold corner's one-stroke stretch gives a line when at least this many stroke widths long
/// (and [`MIN_LEG_LINE_PX`]).
const MIN_LEG_LINE: f64 = 0.5;

/// See [`MIN_LEG_LINE`] (px): a line through fewer pixels points anywhere.
const MIN_LEG_LINE_PX: f64 = 3.0;

/// A corner's legs leave it at less than this (degrees): a wider bend thins to a bend, not a Y.
const MAX_CORNER_ANGLE_DEG: f64 = 120.0;

/// Legs whose unit directions' cross product is below this are parallel: their lines meet
/// nowhere.
const PARALLEL_SINE: f64 = 1e-6;

/// The ink may stick out beyond the corner by this many stroke widths before it is an end of
/// its own (a brush's overshoot at the corner of a box).
const OVERSHOOT: f64 = 0.1;

/// The legs' lines are known to about a pixel across (px), which moves where they meet by
/// `1 / sin(θ / 2)` along the bisector.
const LINE_UNCERTAINTY_PX: f64 = 1.0;

/// The smallest `sin(θ / 2)` that uncertainty is divided by: at most 10 px for a corner that
/// nearly closes.
const MIN_HALF_ANGLE_SINE: f64 = 0.1;

/// A cusp's stub is at most this many stroke widths long ([`Work::cusp_at`]): the wedge where
/// two legs meeting under 20 degrees or more merge.
const CUSP_STUB: f64 = 3.0;

/// A cusp's legs both leave it away from its stub: each leg's direction from the junction (to
/// its point as far away as the stub's tip) is more than this (degrees) from the stub's. A leg
/// that carries on the stub's line (a stem running a little past a bar, a box corner's ear)
/// is no cusp's; at 105 degrees such ends were taken (docs/quality.md, "Session of 2026-12-07,
/// sixteenth").
const CUSP_AWAY_DEG: f64 = 120.0;

/// Cusps are looked for on strokes at least this wide (px, the legs' median skeleton width):
/// on strokes one or two pixels wide a stub's and its legs' directions over a pixel or two are
/// the grid's, and the drawings differ by a pixel or two, less than a part's cost (the pages of
/// the quality benchmark lost junctions: docs/quality.md, "Session of 2026-12-07, sixteenth").
const CUSP_MIN_WIDTH_PX: f64 = 2.5;

/// A cusp's legs are drawn straight to its tip from where they are this many stroke widths from
/// the junction ([`Work::cusp_at`]): beyond the wedge, where each leg is on its own stroke's
/// middle again; the nearer and the farther are both tried.
const CUSP_LEG: [f64; 2] = [1.0, 2.0];

/// The ink ahead of a cusp's stub is followed at most this many stroke widths (plus
/// [`CUSP_SEARCH_PX`]) to its cap, as an end's is.
const CUSP_SEARCH: f64 = 2.0;

/// See [`CUSP_SEARCH`] (px).
const CUSP_SEARCH_PX: f64 = 4.0;

/// A corner's leg, its points listed from the junction outwards, and the first and last index
/// of the stretch that gives its line.
type LegStretch<'a> = (&'a [[f64; 2]], (usize, usize));

/// A corner found at a junction: its stub (and the stub's far vertex), each leg with how many
/// of its points (from the junction) it loses, the bend and the stroke's width.
struct Corner {
    stub: usize,
    tip_vertex: Option<usize>,
    legs: [(usize, usize); 2],
    bend: [f64; 2],
    stroke: f64,
}

impl Work {
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
    ///
    /// With `cusps`, a Y that is no such corner is still a bend when the ink says so
    /// ([`Work::cusp_at`]).
    pub(super) fn dissolve_corners(&mut self, cusps: bool) -> bool {
        let mut changed = false;
        let at = self.incident();
        let degree = self.degrees();
        for j in 0..self.vertices.len() {
            if !self.alive[j] || degree[j] != 3 || at.row(j).len() != 3 {
                continue;
            }
            let corner = self
                .corner_at(j, at.row(j), &degree)
                .or_else(|| cusps.then(|| self.cusp_at(j, at.row(j), &degree)).flatten());
            if let Some(corner) = corner {
                self.bend(j, corner);
                changed = true;
            }
        }
        changed
    }

    /// The degree-3 junction `j`'s (its edges `at`) stub, the shortest terminal edge (a leg may
    /// end too, at the stroke's end), with the stub's far vertex, and its two legs; `None` when
    /// an edge is a loop or none ends.
    fn stub_and_legs(
        &self,
        j: usize,
        at: &[usize],
        degree: &[usize],
    ) -> Option<(usize, Option<usize>, Vec<usize>)> {
        let far = |e: usize| {
            self.edges[e]
                .as_ref()
                .map(|x| if x.from == j { x.to } else { x.from })
        };
        if at.iter().any(|&e| far(e).is_none_or(|f| f == j)) {
            return None;
        }
        let stub = at
            .iter()
            .copied()
            .filter(|&e| far(e).is_some_and(|f| degree[f] == 1))
            .min_by_key(|&e| (self.edges[e].as_ref().map_or(0, |x| x.points.len()), e))?;
        let legs = at.iter().copied().filter(|&e| e != stub).collect();
        Some((stub, far(stub), legs))
    }

    /// Step 1 of [`Work::dissolve_corners`]: whether the degree-3 junction `j` (its edges `at`)
    /// is a corner, and if so its bend.
    fn corner_at(&self, j: usize, at: &[usize], degree: &[usize]) -> Option<Corner> {
        let (stub, tip_vertex, legs) = self.stub_and_legs(j, at, degree)?;
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
        let half = disk_radius(stroke);
        let reach = dist(jp, tip);
        let (leg_a, leg_b) = (outwards(legs[0]), outwards(legs[1]));
        let bold = stroke >= BOLD_CORNER_WIDTH
            && [&leg_a, &leg_b]
                .iter()
                .all(|(_, widths)| widths[0] > BOLD_LEG_WIDENING * stroke + WIDTH_UNCERTAINTY_PX);
        // Each leg's stretch for its line, pointing towards the corner: from `reach` to
        // `reach + 2 w` from the junction (where it no longer bends towards the other leg);
        // for a bold corner whose leg is still wider than a stroke there, from where it is
        // one stroke wide again, up to `2 w` long.
        let beyond_reach = |points: &[[f64; 2]]| -> Option<(usize, usize)> {
            let near = points
                .iter()
                .position(|&p| cmp_dist(p, jp, reach).is_some_and(Ordering::is_ge))?;
            let far = points
                .iter()
                .position(|&p| {
                    cmp_dist(p, jp, reach + LEG_LINE * stroke).is_some_and(Ordering::is_ge)
                })
                .unwrap_or(points.len() - 1);
            Some((near, far))
        };
        let one_stroke = |(points, widths): &(Vec<[f64; 2]>, Vec<f64>), reached: (usize, usize)| {
            let single = |i: usize| widths[i] <= stroke + WIDTH_UNCERTAINTY_PX;
            if (reached.0..=reached.1).all(single) {
                return Some(reached);
            }
            let start = (0..points.len()).find(|&i| single(i) && dist(points[i], jp) >= half)?;
            let mut end = start;
            while end + 1 < points.len()
                && single(end + 1)
                && dist(points[end + 1], points[start]) <= LEG_LINE * stroke
            {
                end += 1;
            }
            (dist(points[start], points[end]) >= (MIN_LEG_LINE * stroke).max(MIN_LEG_LINE_PX))
                .then_some((start, end))
        };
        let (Some(reached_a), Some(reached_b)) = (beyond_reach(&leg_a.0), beyond_reach(&leg_b.0))
        else {
            return None;
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
        let (v, cut_a, cut_b) = found?;
        Some(Corner {
            stub,
            tip_vertex,
            legs: [(legs[0], cut_a), (legs[1], cut_b)],
            bend: v,
            stroke,
        })
    }

    /// A cusp: where a stroke turns back (a script join's peak, a blackletter point), its two
    /// legs' inks merge into a wedge and thinning makes a Y of it, a short stub running into the
    /// cusp's tip. Where the legs curve away from each other beyond the stub (as script strokes
    /// do), their lines do not meet on the stub and the corner rule keeps the Y; the direction
    /// of the legs does not tell such a wedge from a short arm leaving a curve either
    /// (docs/quality.md, "Cusps: measured, not kept"). The ink does: two drawings are compared,
    /// each with a round pen of each edge's median width, as spurs are decided by the ink
    /// (docs/quality.md, "Deciding spurs by the ink"): the Y as it is (the stub carried on to
    /// the centre of its cap, as its end will be), and the cusp, both legs running straight
    /// from one or two widths out ([`CUSP_LEG`]) to that centre, the stub gone. The cusp is
    /// taken when its drawing's error (ink left uncovered plus background covered) is worse than
    /// the Y's by at most the cost of the part it saves ([`PART_COST`] squared widths), for a
    /// stub at most [`CUSP_STUB`] widths long whose straight legs stay on the ink.
    fn cusp_at(&self, j: usize, at: &[usize], degree: &[usize]) -> Option<Corner> {
        let (stub, tip_vertex, legs) = self.stub_and_legs(j, at, degree)?;
        let outwards = |e: usize| -> Vec<[f64; 2]> {
            let edge = self.edges[e].as_ref().expect("live edge");
            let mut points = edge.points.clone();
            if edge.from != j {
                points.reverse();
            }
            points
        };
        let width_of = |e: usize| {
            self.edges[e]
                .as_ref()
                .map_or(MIN_WIDTH_PX, |x| median(&x.widths))
        };
        let pens = [width_of(legs[0]), width_of(legs[1])];
        let stroke = pens[0].min(pens[1]);
        // The stub's own width, at most the legs': a short stub's measured widths are inflated
        // by the very blob of ink in question (a box corner's ear, the wedge).
        let stub_pen = width_of(stub).min(stroke);
        let w = stroke.max(MIN_WIDTH_PX);
        let stub_points = outwards(stub);
        let (jp, tip) = (self.vertices[j].pos, stub_points[stub_points.len() - 1]);
        if stroke < CUSP_MIN_WIDTH_PX
            || dist(jp, tip) > CUSP_STUB * w
            || dist(jp, tip) < MIN_LINE_PX
        {
            return None;
        }
        let reach = dist(jp, tip);
        let leg_points = [outwards(legs[0]), outwards(legs[1])];
        let along = unit([tip[0] - jp[0], tip[1] - jp[1]])?;
        let away = CUSP_AWAY_DEG.to_radians().cos();
        for points in &leg_points {
            let p = points
                .iter()
                .find(|&&p| dist(p, jp) >= reach)
                .unwrap_or(&points[points.len() - 1]);
            let d = unit([p[0] - jp[0], p[1] - jp[1]])?;
            if d[0] * along[0] + d[1] * along[1] >= away {
                return None;
            }
        }
        // The stub carried on to the centre of its cap, along its line over its last width.
        let back = stub_points
            .iter()
            .rev()
            .find(|&&p| dist(p, tip) >= w)
            .copied()
            .unwrap_or(jp);
        let u = unit([tip[0] - back[0], tip[1] - back[1]])?;
        let on = (self.ink.exit(tip, u, CUSP_SEARCH * w + CUSP_SEARCH_PX) - disk_radius(stroke))
            .max(0.0);
        let v = [tip[0] + on * u[0], tip[1] + on * u[1]];
        // The window both drawings differ in reaches the legs this far from the junction.
        let window = dist(jp, v) + (CUSP_LEG[1] + 1.0) * w + disk_radius(stroke);
        let mut best: Option<(f64, [usize; 2])> = None;
        for k in CUSP_LEG {
            let cuts = [0, 1].map(|i| leg_points[i].iter().position(|&p| dist(p, jp) >= k * w));
            let [Some(cut_a), Some(cut_b)] = cuts else {
                continue;
            };
            let cuts = [cut_a, cut_b];
            if (0..2).any(|i| !self.ink.holds_thin(leg_points[i][cuts[i]], v, stroke)) {
                continue;
            }
            let mut with_stub: Vec<([f64; 2], f64)> = stub_points
                .iter()
                .chain(std::iter::once(&v))
                .map(|&p| (p, stub_pen))
                .collect();
            let (mut cusp, mut common) = (Vec::new(), Vec::new());
            for i in 0..2 {
                let points = &leg_points[i];
                with_stub.extend(points[..cuts[i]].iter().map(|&p| (p, pens[i])));
                common.extend(
                    points[cuts[i]..]
                        .iter()
                        .take_while(|&&p| dist(p, jp) <= window)
                        .map(|&p| (p, pens[i])),
                );
                // The leg's straight line to the tip, every half pixel (as the ink is tested
                // along a line), the tip itself drawn once below with the narrower pen.
                let line: Vec<[f64; 2]> = sampled(points[cuts[i]], v).collect();
                cusp.extend(line[..line.len() - 1].iter().map(|&p| (p, pens[i])));
            }
            cusp.push((v, stroke));
            let worse = worse_by(&self.ink, &with_stub, &cusp, &common);
            if best.is_none_or(|(b, _)| worse < b) {
                best = Some((worse, cuts));
            }
        }
        let (worse, [cut_a, cut_b]) = best?;
        (worse <= PART_COST * w * w).then(|| Corner {
            stub,
            tip_vertex,
            legs: [(legs[0], cut_a), (legs[1], cut_b)],
            bend: v,
            stroke,
        })
    }

    /// Step 2 of [`Work::dissolve_corners`]: the stub and the junction go, and both legs run
    /// straight to the bend.
    fn bend(&mut self, j: usize, corner: Corner) {
        let Corner {
            stub,
            tip_vertex,
            legs,
            bend: v,
            stroke,
        } = corner;
        for (e, cut) in legs {
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
        let half = disk_radius(stroke);
        let reach = dist(jp, tip);
        let line = |(points, (near, far)): LegStretch| {
            let (a, b) = (points[near], points[far]);
            let d = [a[0] - b[0], a[1] - b[1]];
            let n = hypot(d[0], d[1]);
            (n >= MIN_LINE_PX).then(|| (a, [d[0] / n, d[1] / n], near))
        };
        let ((a, ua, cut_a), (b, ub, cut_b)) = (line(legs[0])?, line(legs[1])?);
        // The legs leave the corner at less than 120 degrees: -ua . -ub > cos 120.
        let cross = ua[0] * ub[1] - ua[1] * ub[0];
        if ua[0] * ub[0] + ua[1] * ub[1] <= MAX_CORNER_ANGLE_DEG.to_radians().cos()
            || cross.abs() < PARALLEL_SINE
        {
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
        let margin =
            OVERSHOOT * stroke + LINE_UNCERTAINTY_PX / half_angle.sin().max(MIN_HALF_ANGLE_SINE);
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
}
