//! Corners: the Y that thinning makes of a sharp bend is a bend ([`Work::dissolve_corners`]).
//! docs/design.md, "Skeleton-carried geometry"; docs/quality.md, "Bold corners".

use crate::geometry::{dist, hypot};

use super::work::{median, Work};
use super::{disk_radius, MIN_LINE_PX};

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
    pub(super) fn dissolve_corners(&mut self) -> bool {
        let mut changed = false;
        let at = self.incidence();
        let degree = self.degrees();
        for j in 0..self.vertices.len() {
            if !self.alive[j] || degree[j] != 3 || at[j].len() != 3 {
                continue;
            }
            if let Some(corner) = self.corner_at(j, &at[j], &degree) {
                self.bend(j, corner);
                changed = true;
            }
        }
        changed
    }

    /// Step 1 of [`Work::dissolve_corners`]: whether the degree-3 junction `j` (its edges `at`)
    /// is a corner, and if so its bend.
    fn corner_at(&self, j: usize, at: &[usize], degree: &[usize]) -> Option<Corner> {
        let far = |e: usize| {
            self.edges[e]
                .as_ref()
                .map(|x| if x.from == j { x.to } else { x.from })
        };
        if at.iter().any(|&e| far(e).is_none_or(|f| f == j)) {
            return None;
        }
        // The stub: the shortest terminal edge (a leg may end too, at the stroke's end).
        let stub = at
            .iter()
            .copied()
            .filter(|&e| far(e).is_some_and(|f| degree[f] == 1))
            .min_by_key(|&e| (self.edges[e].as_ref().map_or(0, |x| x.points.len()), e))?;
        let legs: Vec<usize> = at.iter().copied().filter(|&e| e != stub).collect();
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
            let near = points.iter().position(|&p| dist(p, jp) >= reach)?;
            let far = points
                .iter()
                .position(|&p| dist(p, jp) >= reach + LEG_LINE * stroke)
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
            tip_vertex: far(stub),
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
