//! Smooth centerlines: every skeleton edge fitted to its own ink ([`Work::smooth_edges`]), the
//! last step of the reconciliation (docs/design.md, "Skeleton-carried geometry").
//!
//! A one-pixel skeleton is a staircase of pixel centers, half a pixel off the stroke's middle
//! where the stroke is an even number of pixels wide. Each edge is resampled every pixel, each
//! sample moved to the middle of the ink's cross-section along its normal (the medial point),
//! and the polyline that stays closest to the medial points while bending least is solved for:
//! §3.4's least squares (Eq. (4)), data term and smoothness term, with the second difference as
//! the smoothness (a straight run costs nothing, so straight strokes stay straight and ends are
//! not pulled in). A run that one line explains within the pixel grid's own scatter (the
//! staircase moves a straight stroke's medial points by up to two thirds of a pixel at its own
//! period, which the smoothing cannot tell from a bend) is held on the least-squares line of its
//! medial points ([`straight_runs`]; docs/quality.md, eighth session of 2026-12-06). The
//! smoothing's reach is in units of the stroke's width; it is cut at the
//! edge's corners, so a corner stays sharp; a point the fit would move off the ink keeps its
//! skeleton place. Last, the polyline keeps only the points its shape needs: every dropped
//! point lies within [`SIMPLIFY_PX`] of the line kept, and every segment kept lies on the ink.
//! The ends stay exactly at their vertices, and the graph does not change.
//!
//! The method's lines that the skeleton adopted ([`super::adopt`]) are fitted the same way: §3.4's
//! nodes lie a stroke width apart and their L1 medians wander by a few tenths of a pixel. A moved
//! edge that would cross or touch another edge (or itself) away from their vertices keeps its
//! path from before, so the geometry never adds a crossing to the graph.

use crate::geometry::{
    arc_lengths, bounds, crossing_paths, hypot, principal, segment_dist, segment_dist2, ArcWalk,
};
use crate::stroke_graph::Edge;

use super::work::{median, Ink, Work};
use super::{disk_radius, MIN_WIDTH_PX};

/// The spacing of the fit's samples along an edge (px): about the skeleton's own, one per pixel.
const SAMPLE_PX: f64 = 1.0;

/// A dropped point lies within this of the simplified polyline (px).
pub(super) const SIMPLIFY_PX: f64 = 0.1;

/// The smoothing passes shapes longer than this many stroke widths and flattens shorter
/// wiggles (the wavelength at which Eq. (4)'s second-difference term halves an oscillation):
/// the pixel staircase is finer than a stroke is wide, the bends of a letter are coarser.
const CUTOFF_WIDTHS: f64 = 2.0;

/// See [`CUTOFF_WIDTHS`] (px): on a hairline the staircase still has steps of a few pixels.
const MIN_CUTOFF_PX: f64 = 4.0;

/// A corner turns by more than this (degrees) over a stroke width either side of it, and more
/// than its neighbours do: the smoothing does not reach across it.
const CORNER_DEG: f64 = 35.0;

/// A medial point lies at most this far from the skeleton (px): the skeleton is within a pixel
/// of the middle; a cross-section that says otherwise runs along another stroke.
const MAX_SHIFT_PX: f64 = 0.75;

/// A cross-section is the stroke's own when it is at most this many local widths long (plus a
/// pixel): longer, it runs into another stroke where two meet or crowd.
const CROWDED_WIDTHS: f64 = 1.5;

/// The ink is sampled along a cross-section every quarter pixel (px).
const SECTION_STEP_PX: f64 = 0.25;

/// Halvings of the step in which a cross-section leaves the ink (to 1/64 px).
const BISECTIONS: usize = 4;

/// The data weight of an edge's two ends: they stay at their vertices.
const END_WEIGHT: f64 = 1e8;

/// A run of medial points is straight when the parabola of least squares through them bends
/// off its chord by at most this (px): a curve that bends less is drawn by its line within it.
const BEND_PX: f64 = 0.25;

/// ... and none lies farther than this from its line (px): the pixel grid moves each of a
/// cross-section's two boundaries by up to half a pixel, and its middle as far, along the
/// diagonal half a pixel's diagonal.
const SCATTER_PX: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// A run within an edge is held on its line when it is at least this many stroke widths long
/// (and twice [`MIN_CUTOFF_PX`]): twice the smoothing's cutoff, below which Eq. (4) flattens it.
const LINE_WIDTHS: f64 = 2.0 * CUTOFF_WIDTHS;

/// The fewest measured medial points a line is fitted to.
const MIN_LINE_POINTS: usize = 4;

impl Work {
    /// Fits every skeleton edge to its ink and simplifies every edge (see the module's text).
    ///
    /// With `lines`, a stretch the pixel grid cannot tell from straight is one line
    /// ([`straight_runs`]); off for a print's ridges, whose minutiae were measured without.
    pub(super) fn smooth_edges(&mut self, lines: bool) {
        let degree = self.degrees();
        let clear = |v: usize| -> f64 {
            if degree[v] >= 3 {
                disk_radius(self.vertices[v].width)
            } else {
                0.0
            }
        };
        let clears: Vec<f64> = (0..self.vertices.len()).map(clear).collect();
        let originals = self.edges.clone();
        // Edges that cross or touch another (or themselves) away from a vertex keep their
        // geometry: moving them could remove a crossing as well as add one.
        let all = vec![true; self.edges.len()];
        let mut moved = vec![false; self.edges.len()];
        let crossing = crossing_edges(&originals, &all);
        for (e, edge) in self.edges.iter_mut().enumerate() {
            let Some(edge) = edge else { continue };
            if crossing.binary_search(&e).is_ok() {
                continue;
            }
            let clear = [clears[edge.from], clears[edge.to]];
            // A closed curve's vertex is only where the loop was cut: it moves with the fit.
            let closed = edge.from == edge.to && degree[edge.from] == 2;
            if fit_edge(edge, &self.ink, clear, lines, closed) {
                // The fitted polyline's tangents are written by `finish`.
                edge.directions.clear();
            }
            simplify_edge(edge, &self.ink);
            moved[e] = originals[e]
                .as_ref()
                .is_some_and(|o| o.points != edge.points);
        }
        // A moved edge that now crosses or touches another edge, or itself, away from their
        // shared vertices, or that comes within a pixel of another edge's end (where the end
        // would read as touching it), takes back its path from before: the graph's topology
        // is the reconciliation's, and the geometry must not change what it shows.
        let ends: Vec<([f64; 2], usize)> = self
            .edges
            .iter()
            .enumerate()
            .filter_map(|(e, edge)| edge.as_ref().map(|edge| (e, edge)))
            .flat_map(|(e, edge)| [(edge.from, e), (edge.to, e)])
            .filter(|&(v, _)| degree[v] == 1)
            .map(|(v, e)| (self.vertices[v].pos, e))
            .collect();
        //
        // After the first round only the edges taken back have changed: an edge still moved
        // kept its path, which met neither itself nor any other edge as it was, and its
        // distance to the ends does not depend on the other edges; so the next round asks
        // only whether it meets an edge just taken back, among the moved edges whose boxes
        // come near one (two segments under one cell lie less than a cell apart).
        let mut back = crossing_edges(&self.edges, &moved);
        back.extend(edges_near_ends(&self.edges, &originals, &moved, &ends));
        let mut boxes = Vec::new();
        while !back.is_empty() {
            for &e in &back {
                self.edges[e].clone_from(&originals[e]);
                moved[e] = false;
            }
            if boxes.is_empty() {
                boxes = self
                    .edges
                    .iter()
                    .map(|edge| edge.as_ref().map(|edge| bounds(&edge.points)))
                    .collect();
            }
            let taken: Vec<([f64; 2], [f64; 2])> = back
                .iter()
                .filter_map(|&e| self.edges[e].as_ref().map(|edge| bounds(&edge.points)))
                .collect();
            let apart = |(lo, hi): ([f64; 2], [f64; 2]), (a, b): ([f64; 2], [f64; 2])| {
                lo[0] - b[0] > NEAR_CELL_PX
                    || a[0] - hi[0] > NEAR_CELL_PX
                    || lo[1] - b[1] > NEAR_CELL_PX
                    || a[1] - hi[1] > NEAR_CELL_PX
            };
            let paths: Vec<Option<&[[f64; 2]]>> = self
                .edges
                .iter()
                .enumerate()
                .map(|(e, edge)| {
                    let edge = edge.as_ref()?;
                    let near = back.contains(&e)
                        || (moved[e]
                            && boxes[e].is_some_and(|own| taken.iter().any(|&t| !apart(own, t))));
                    near.then_some(edge.points.as_slice())
                })
                .collect();
            back = crossing_paths(&paths, &moved);
        }
        for edge in self.edges.iter().flatten() {
            if edge.from == edge.to && degree[edge.from] == 2 {
                self.vertices[edge.from].pos = edge.points[0];
            }
        }
    }
}

/// More than a cell of [`crossing_paths`] (4 px): boxes this far apart hold no two segments
/// under one cell.
const NEAR_CELL_PX: f64 = 8.0;

/// The moved edges that come within [`MIN_WIDTH_PX`] of the end of another edge (`ends`: each
/// end's position and its own edge) nearer than their path from before did.
fn edges_near_ends(
    edges: &[Option<Edge>],
    originals: &[Option<Edge>],
    moved: &[bool],
    ends: &[([f64; 2], usize)],
) -> Vec<usize> {
    let nearest = |edge: &Edge, p: [f64; 2]| {
        edge.points
            .windows(2)
            .map(|s| segment_dist(p, s[0], s[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut near = Vec::new();
    for (e, edge) in edges.iter().enumerate() {
        let (Some(edge), Some(original)) = (edge, &originals[e]) else {
            continue;
        };
        if !moved[e] {
            continue;
        }
        let (lo, hi) = bounds(&edge.points);
        let close = ends.iter().any(|&(p, own)| {
            own != e
                && p[0] >= lo[0] - MIN_WIDTH_PX
                && p[0] <= hi[0] + MIN_WIDTH_PX
                && p[1] >= lo[1] - MIN_WIDTH_PX
                && p[1] <= hi[1] + MIN_WIDTH_PX
                && {
                    let d = nearest(edge, p);
                    d < MIN_WIDTH_PX && d < nearest(original, p)
                }
        });
        if close {
            near.push(e);
        }
    }
    near
}

/// The edges among those `moved` whose polylines cross or touch another edge's polyline, or
/// their own, other than where two segments share an end point; in rising order.
fn crossing_edges(edges: &[Option<Edge>], moved: &[bool]) -> Vec<usize> {
    let paths: Vec<Option<&[[f64; 2]]>> = edges
        .iter()
        .map(|edge| edge.as_ref().map(|edge| edge.points.as_slice()))
        .collect();
    crossing_paths(&paths, moved)
}

/// Fits one skeleton edge to the medial points of its ink: resampled, moved, solved (see the
/// module's text). `clear` is the radius around each end's junction within which the arm is
/// the straight join [`super::work::cut_arm`] made, kept as it is. With `lines`, the straight
/// runs of the medial points ([`straight_runs`]) are held on their lines. The two ends of a
/// `closed` curve (its vertex joins nothing else) move together to the medial point where the
/// loop was cut.
fn fit_edge(edge: &mut Edge, ink: &Ink, clear: [f64; 2], lines: bool, closed: bool) -> bool {
    let s = arc_lengths(&edge.points);
    let total = s[s.len() - 1];
    let m = (total / SAMPLE_PX).round() as usize;
    if edge.points.len() < 3 || m < 3 {
        return false;
    }
    let step = total / m as f64;
    let width = median(&edge.widths);
    let mut samples = Vec::with_capacity(m + 1);
    let mut widths = Vec::with_capacity(m + 1);
    let mut walk = ArcWalk::new(&edge.points, &s);
    for j in 0..=m {
        let (p, k) = walk.at(j as f64 * step);
        let (a, b) = (
            edge.widths[k],
            edge.widths[(k + 1).min(edge.widths.len() - 1)],
        );
        let len = s[(k + 1).min(s.len() - 1)] - s[k];
        let f = if len > 0.0 {
            ((j as f64 * step - s[k]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        samples.push(p);
        widths.push(a + f * (b - a));
    }
    samples[0] = edge.points[0];
    samples[m] = edge.points[edge.points.len() - 1];

    // Half a stroke width either side: the chord that gives a sample's direction, and the
    // reach of the corner test.
    let half = ((width / 2.0 / step).round() as usize).max(1);
    let reach = ((width / step).round() as usize).max(2);
    let chord = |j: usize, k: usize| {
        let (a, b) = (samples[j.saturating_sub(k)], samples[(j + k).min(m)]);
        unit([b[0] - a[0], b[1] - a[1]])
    };
    // The middle of the ink's cross-section through `p` across the unit vector `u`, and the
    // section's length; `None` where the section is longer than the stroke is wide (it runs
    // into another stroke or along this one) or its middle too far off.
    let section_at = |p: [f64; 2], u: [f64; 2], width: f64| {
        let normal = [-u[1], u[0]];
        let limit = CROWDED_WIDTHS * width + 1.0;
        let (plus, minus) = (
            section_exit(ink, p, normal, limit),
            section_exit(ink, p, [-normal[0], -normal[1]], limit),
        );
        let shift = (plus - minus) / 2.0;
        if plus + minus >= limit || shift.abs() > MAX_SHIFT_PX {
            return None;
        }
        Some((
            [p[0] + shift * normal[0], p[1] + shift * normal[1]],
            plus + minus,
        ))
    };
    // Where a closed curve was cut, the middle of its section across the cut, on the ink.
    let cut = if closed && m > 2 * half {
        let (a, b) = (samples[m - half], samples[half]);
        unit([b[0] - a[0], b[1] - a[1]])
            .and_then(|u| section_at(samples[0], u, widths[0]))
            .map(|(q, _)| q)
            .filter(|&q| ink.at(q))
    } else {
        None
    };
    let mut measured = vec![false; m + 1];
    let mut sections = vec![0.0; m + 1];
    let mut medial: Vec<[f64; 2]> = (0..=m)
        .map(|j| {
            let p = samples[j];
            let t = j as f64 * step;
            if j == 0 || j == m || t < clear[0] || total - t < clear[1] {
                return p;
            }
            let Some(u) = chord(j, half) else { return p };
            let Some((q, section)) = section_at(p, u, widths[j]) else {
                return p;
            };
            measured[j] = true;
            sections[j] = section;
            q
        })
        .collect();
    if let Some(q) = cut {
        (medial[0], medial[m]) = (q, q);
    }

    // Corners: the turn between the chords before and after a sample, over a stroke width,
    // above CORNER_DEG and the largest within that width. The chord after sample `j` is the
    // chord before sample `j + reach`: each is measured once (`ahead[i]`, from `i` to
    // `i + reach`), where one is needed at all (no sample has both when `m < 2 reach`).
    let corner_cos = CORNER_DEG.to_radians().cos();
    let ahead: Vec<Option<[f64; 2]>> = if m >= 2 * reach {
        (0..=m - reach)
            .map(|i| {
                let (p, b) = (samples[i], samples[i + reach]);
                unit([b[0] - p[0], b[1] - p[1]])
            })
            .collect()
    } else {
        Vec::new()
    };
    let turn: Vec<f64> = (0..=m)
        .map(|j| {
            if j < reach || j + reach > m {
                return 1.0;
            }
            match (ahead[j - reach], ahead[j]) {
                (Some(x), Some(y)) => x[0] * y[0] + x[1] * y[1],
                _ => 1.0,
            }
        })
        .collect();
    let corner: Vec<bool> = (0..=m)
        .map(|j| {
            turn[j] < corner_cos
                && (j.saturating_sub(reach)..=(j + reach).min(m))
                    .all(|i| turn[i] > turn[j] || (turn[i] == turn[j] && i >= j))
        })
        .collect();

    // Eq. (4): min Σ a_j |q_j - medial_j|² + λ Σ |q_{j-1} - 2 q_j + q_{j+1}|², the second
    // difference left out at corners; λ from the cutoff wavelength L in samples, the
    // smoothing's response 1 / (1 + λ (2 sin(π / L))⁴) being 1/2 there.
    let cutoff = (CUTOFF_WIDTHS * width).max(MIN_CUTOFF_PX) / step;
    let lambda = 1.0 / (2.0 * (std::f64::consts::PI / cutoff).sin()).powi(4);
    let mut data: Vec<f64> = (0..=m)
        .map(|j| {
            if j == 0 || j == m || corner[j] {
                END_WEIGHT
            } else {
                1.0
            }
        })
        .collect();
    let smooth: Vec<bool> = (0..=m).map(|j| j > 0 && j < m && !corner[j]).collect();
    let mut target = medial.clone();
    if lines {
        // The stroke's own cross-sections, no longer than their median and the half pixel's
        // diagonal by which the grid may move each of their two boundaries: where another
        // stroke's ink joins this one (the inside of a corner, a fork) or the stroke swells (a
        // serif, a blot), the middle of the section is not this stroke's line.
        // The test of straightness reads every medial point (a brush stroke's bend is where it
        // swells), the line is fitted to the stroke's own sections only.
        let lengths: Vec<f64> = (0..=m)
            .filter(|&j| measured[j])
            .map(|j| sections[j])
            .collect();
        let own = median(&lengths) + std::f64::consts::SQRT_2;
        let mut clean = measured.clone();
        for j in 0..=m {
            clean[j] &= sections[j] <= own;
        }
        // A corner's medial points are the round pen's cut, a stroke width either side.
        for j in (0..=m).filter(|&j| corner[j]) {
            for flag in &mut measured[j.saturating_sub(reach)..=(j + reach).min(m)] {
                *flag = false;
            }
            for flag in &mut clean[j.saturating_sub(reach)..=(j + reach).min(m)] {
                *flag = false;
            }
        }
        // A straight run is held on its line, but for half a width at an end or a corner,
        // where the fit joins it to the vertex or bends into the next stretch.
        let min_run = ((LINE_WIDTHS * width).max(2.0 * MIN_CUTOFF_PX) / step).round() as usize;
        let breaks: Vec<usize> = (0..=m).filter(|&j| j == 0 || j == m || corner[j]).collect();
        for stretch in breaks.windows(2) {
            let (a, b) = (stretch[0], stretch[1]);
            // Towards a junction or a corner the line runs on under the other strokes' ink,
            // which hides it; towards an end it stops where it was last measured: beyond is the
            // stroke's own cap, a blot, a hook.
            let hidden =
                |j: usize| corner[j] || (j == 0 && clear[0] > 0.0) || (j == m && clear[1] > 0.0);
            for ((first, last), line) in straight_runs(&medial, &measured, &clean, a, b, min_run) {
                // Under the ink of a junction or a corner, by at most two widths: a line
                // measured farther away does not speak for the stroke there.
                let hides = 2 * reach;
                let mut measured_from = (first..=last).find(|&j| clean[j]).unwrap_or(last);
                let mut measured_to = (first..=last).rev().find(|&j| clean[j]).unwrap_or(first);
                if first == a && hidden(a) {
                    measured_from = measured_from.saturating_sub(hides);
                }
                if last == b && hidden(b) {
                    measured_to += hides;
                }
                let (first, last) = (first.max(measured_from), last.min(measured_to));
                for j in first.max(a + half)..=last.min(b.saturating_sub(half)) {
                    target[j] = line.project(medial[j]);
                    data[j] = END_WEIGHT;
                }
            }
        }
    }
    let fitted = solve_banded(&target, &data, &smooth, lambda);
    let mut points = Vec::with_capacity(m + 1);
    for j in 0..=m {
        let q = fitted[j];
        points.push(if j == 0 || j == m {
            medial[j]
        } else if !ink.at(q) {
            samples[j]
        } else {
            q
        });
    }
    edge.points = points;
    edge.widths = widths;
    true
}

/// A line through `centre` along the unit vector `along`.
#[derive(Clone, Copy, Debug)]
struct Line {
    centre: [f64; 2],
    along: [f64; 2],
}

impl Line {
    /// The point of the line nearest `p`.
    fn project(&self, p: [f64; 2]) -> [f64; 2] {
        let t = (p[0] - self.centre[0]) * self.along[0] + (p[1] - self.centre[1]) * self.along[1];
        [
            self.centre[0] + t * self.along[0],
            self.centre[1] + t * self.along[1],
        ]
    }
}

/// The line of least squares through the `measured` points of `points[a..=b]` when one line
/// explains them within the pixel grid's own scatter: the points bend off it by at most
/// [`BEND_PX`] (the sagitta of the parabola of least squares through their offsets, which the
/// staircase's sawtooth barely moves while a curve moves it by its own sagitta), and none lies
/// farther than [`SCATTER_PX`] from it. `None` with fewer than [`MIN_LINE_POINTS`] measured.
///
/// `scratch` holds the measured points, then their places in the line's frame: one walk over
/// the stretch, then over the points alone, and the walk that measures the scatter stops at the
/// first point too far (the same sums in the same order as before, so the same bits).
fn straight_line(
    points: &[[f64; 2]],
    measured: &[bool],
    a: usize,
    b: usize,
    scratch: &mut Vec<[f64; 2]>,
) -> Option<Line> {
    scratch.clear();
    let (mut first, mut last) = (usize::MAX, 0);
    let mut centre = [0.0; 2];
    for j in a..=b {
        if measured[j] {
            let p = points[j];
            first = first.min(j);
            last = j;
            centre = [centre[0] + p[0], centre[1] + p[1]];
            scratch.push(p);
        }
    }
    let n = scratch.len();
    // Measured along most of their span: a few points do not speak for a stretch between.
    let span = if n > 0 { last - first + 1 } else { 0 };
    if n < MIN_LINE_POINTS || 2 * n < span {
        return None;
    }
    let centre = [centre[0] / n as f64, centre[1] / n as f64];
    let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
    for p in scratch.iter() {
        let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
        cxx += dx * dx;
        cxy += dx * dy;
        cyy += dy * dy;
    }
    let (_, along) = principal(cxx, cxy, cyy);
    let normal = [-along[1], along[0]];
    // Offsets r across the line against positions t along it, t scaled to [-1, 1].
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in scratch.iter_mut() {
        let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
        let (t, r) = (
            dx * along[0] + dy * along[1],
            dx * normal[0] + dy * normal[1],
        );
        if r.abs() > SCATTER_PX {
            return None;
        }
        lo = lo.min(t);
        hi = hi.max(t);
        *p = [t, r];
    }
    if hi - lo < 1.0 {
        return None;
    }
    let bend = parabola_bend(scratch.iter().map(|&[t, r]| (t, r)), lo, hi)?;
    (bend.abs() <= BEND_PX).then_some(Line { centre, along })
}

/// The coefficient of u² of the parabola of least squares r = c0 + c1 u + c2 u² through the
/// offsets `(t, r)`, u = t scaled from [`lo`, `hi`] to [-1, 1]: the parabola's sagitta over
/// its chord (the normal equations, solved by Cramer's rule). `None` when they are singular.
fn parabola_bend(offsets: impl Iterator<Item = (f64, f64)>, lo: f64, hi: f64) -> Option<f64> {
    let (mid, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    let mut s = [0.0; 5];
    let mut y = [0.0; 3];
    for (t, r) in offsets {
        let u = (t - mid) / half;
        let mut power = 1.0;
        for (k, sk) in s.iter_mut().enumerate() {
            *sk += power;
            if k < 3 {
                y[k] += power * r;
            }
            power *= u;
        }
    }
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let normal_matrix = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let det = det3(normal_matrix);
    if det.abs() < 1e-12 {
        return None;
    }
    let mut with_y = normal_matrix;
    for (row, &yk) in with_y.iter_mut().zip(&y) {
        row[2] = yk;
    }
    Some(det3(with_y) / det)
}

/// The margin by which [`Moments::surely_not_straight`] clears a bound before it answers: its
/// sums and [`straight_line`]'s, taken in different orders and about different origins, differ
/// by rounding only (well below 1e-9 of a bound at the conditioning it asks for).
const SURE: f64 = 1e-3;

/// Running sums of the measured points of a window `first..=last` of a stretch (Σ xᵃ yᵇ for
/// a + b ≤ 4, x and y about an origin near the window, kept there by summing afresh once
/// four window lengths of samples have entered and left since): a window grows, shrinks or
/// slides by a sample in constant time, and [`Moments::surely_not_straight`] tells from the sums alone, without a
/// walk over the window, most windows that [`straight_line`] would refuse.
struct Moments<'a> {
    points: &'a [[f64; 2]],
    measured: &'a [bool],
    origin: [f64; 2],
    /// Σ xᵃ yᵇ over the window's measured points, in the order of [`Moments::terms`].
    sums: [f64; 15],
    /// The window summed; none before the first.
    window: Option<(usize, usize)>,
    /// Samples added or removed since the sums were taken afresh.
    moves: usize,
}

impl<'a> Moments<'a> {
    fn new(points: &'a [[f64; 2]], measured: &'a [bool]) -> Self {
        Self {
            points,
            measured,
            origin: [0.0; 2],
            sums: [0.0; 15],
            window: None,
            moves: 0,
        }
    }

    /// xᵃ yᵇ for a + b ≤ 4: 1; x, y; x², xy, y²; x³, x²y, xy², y³; x⁴, x³y, x²y², xy³, y⁴.
    #[inline]
    fn terms(x: f64, y: f64) -> [f64; 15] {
        let (xx, xy, yy) = (x * x, x * y, y * y);
        [
            1.0,
            x,
            y,
            xx,
            xy,
            yy,
            xx * x,
            xx * y,
            x * yy,
            yy * y,
            xx * xx,
            xx * xy,
            xx * yy,
            xy * yy,
            yy * yy,
        ]
    }

    /// Adds (`sign` 1) or removes (`sign` -1) sample `j` when it is measured.
    #[inline]
    fn add(&mut self, j: usize, sign: f64) {
        if !self.measured[j] {
            return;
        }
        let p = self.points[j];
        let terms = Self::terms(p[0] - self.origin[0], p[1] - self.origin[1]);
        for (sum, term) in self.sums.iter_mut().zip(terms) {
            *sum += sign * term;
        }
        self.moves += 1;
    }

    /// Makes the sums those of `first..=last` (`first <= last`): by the samples that entered
    /// and left, or afresh when that would take as long or the origin is left behind.
    fn set(&mut self, first: usize, last: usize) {
        let len = last + 1 - first;
        let moved = match self.window {
            Some((f, l)) if first <= l && f <= last => {
                let step = first.abs_diff(f) + last.abs_diff(l);
                (step < len && self.moves + step <= 4 * len).then_some((f, l))
            }
            _ => None,
        };
        self.window = Some((first, last));
        let Some((f, l)) = moved else {
            self.origin = self.points[first];
            self.sums = [0.0; 15];
            for j in first..=last {
                self.add(j, 1.0);
            }
            self.moves = 0;
            return;
        };
        for j in f..first {
            self.add(j, -1.0);
        }
        for j in first..f {
            self.add(j, 1.0);
        }
        for j in last + 1..=l {
            self.add(j, -1.0);
        }
        for j in l + 1..=last {
            self.add(j, 1.0);
        }
    }

    /// Whether [`straight_line`] surely refuses the window's measured points, `ends` the first
    /// and last of them: the sum of their squared offsets from their line of least squares
    /// (the scatter matrix's smaller eigenvalue) is above what [`SCATTER_PX`] allows each, or
    /// the parabola of least squares through their offsets bends by more than [`BEND_PX`] over
    /// the span between the two ends (which the span between the farthest points, where
    /// [`straight_line`] measures the bend, can only exceed). Both by a margin of [`SURE`] and
    /// only where the sums are well conditioned (a clear axis, positions along it not bunched
    /// at two places): else `false`, and the full test decides.
    fn surely_not_straight(&self, ends: [[f64; 2]; 2]) -> bool {
        let [n, sx, sy, sxx, sxy, syy, sx3, sx2y, sxy2, sy3, sx4, sx3y, sx2y2, sxy3, sy4] =
            self.sums;
        if n < MIN_LINE_POINTS as f64 {
            return false;
        }
        // The scatter matrix about the centroid, its eigenvalues and the larger one's axis,
        // from the better-conditioned row.
        let c = [sx / n, sy / n];
        let (cxx, cxy, cyy) = (sxx - c[0] * sx, sxy - c[0] * sy, syy - c[1] * sy);
        let half_diff = (cxx - cyy) / 2.0;
        let root = (half_diff * half_diff + cxy * cxy).sqrt();
        let mean = (cxx + cyy) / 2.0;
        let (larger, smaller) = (mean + root, mean - root);
        if root.is_nan() || root <= SURE * larger {
            return false;
        }
        if smaller > n * SCATTER_PX * SCATTER_PX * (1.0 + SURE) {
            return true;
        }
        let v = if half_diff >= 0.0 {
            [larger - cyy, cxy]
        } else {
            [cxy, larger - cxx]
        };
        let norm = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let (ax, ay) = (v[0] / norm, v[1] / norm);
        // Positions t along the axis and offsets r across it, about the origin: their sums
        // Σ t, Σ r, Σ t², Σ t³, Σ t⁴, Σ t r, Σ t² r.
        let (ax2, ay2, axy) = (ax * ax, ay * ay, ax * ay);
        let t1 = ax * sx + ay * sy;
        let r1 = ax * sy - ay * sx;
        let t2 = ax2 * sxx + 2.0 * axy * sxy + ay2 * syy;
        let t3 = ax2 * ax * sx3 + 3.0 * ax2 * ay * sx2y + 3.0 * ax * ay2 * sxy2 + ay2 * ay * sy3;
        let t4 = ax2 * ax2 * sx4
            + 4.0 * ax2 * axy * sx3y
            + 6.0 * ax2 * ay2 * sx2y2
            + 4.0 * axy * ay2 * sxy3
            + ay2 * ay2 * sy4;
        let tr = -axy * sxx + (ax2 - ay2) * sxy + axy * syy;
        let t2r = -ax2 * ay * sx3
            + (ax2 - 2.0 * ay2) * ax * sx2y
            + (2.0 * ax2 - ay2) * ay * sxy2
            + axy * ay * sy3;
        // ... about the centroid.
        let mut along = [n, t1, t2, t3, t4];
        let (tc, rc) = (t1 / n, r1 / n);
        shift_moments(&mut along, tc);
        let [_, _, t2, t3, t4] = along;
        let t2r = t2r - 2.0 * tc * tr + tc * tc * r1 - rc * t2;
        // r = d0 + d1 t + d2 t² with Σ t = Σ r = Σ t r = 0 (the centroid, the axes): the
        // normal equations leave d2 = Σ t² r / (Σ t⁴ - (Σ t²)² / n - (Σ t³)² / Σ t²).
        let spread = t4 - t2 * t2 / n - t3 * t3 / t2;
        if spread.is_nan() || spread <= SURE * t4 {
            return false;
        }
        let d = [ends[1][0] - ends[0][0], ends[1][1] - ends[0][1]];
        let half = (d[0] * ax + d[1] * ay).abs() / 2.0;
        (t2r / spread).abs() * half * half > BEND_PX * (1.0 + SURE)
    }
}

/// Power sums Σ xᵏ (k = 0, 1, ...) made Σ (x - c)ᵏ: the binomial expansion, in place.
fn shift_moments(sums: &mut [f64], c: f64) {
    for k in 0..sums.len() {
        for i in (k + 1..sums.len()).rev() {
            sums[i] -= c * sums[i - 1];
        }
    }
}

/// The straight runs of the stretch `a..=b` of `medial` (between an edge's ends and corners),
/// each its first and last sample and its line ([`straight_line`] of the `measured` points and
/// of the `clean` ones, the line of the latter): the whole stretch when one line explains it, else
/// the longest runs of at least `min_run` samples found from its start onwards, each grown
/// while one line explains it.
///
/// A window is first put to the tests that need no walk over it: its count of measured points
/// and their span, then [`Moments::surely_not_straight`] on its running sums; only a window
/// that passes them is fitted (most windows slid along a curve do not).
fn straight_runs(
    medial: &[[f64; 2]],
    measured: &[bool],
    clean: &[bool],
    a: usize,
    b: usize,
    min_run: usize,
) -> Vec<((usize, usize), Line)> {
    // Every fit below reads points of the stretch only: room for all of them at once, where
    // growing it push by push reallocated a few times per stretch.
    let mut scratch = Vec::with_capacity(b + 1 - a);
    // The clean points' line only where the measured ones are straight.
    let mut fit = |first: usize, last: usize| {
        straight_line(medial, measured, first, last, &mut scratch)
            .and_then(|_| straight_line(medial, clean, first, last, &mut scratch))
    };
    if let Some(line) = fit(a, b) {
        return vec![((a, b), line)];
    }
    // The measured samples of the stretch: how many before each sample, the first at or after
    // it, the last at or before it.
    let len = b + 1 - a;
    let mut before = vec![0; len + 1];
    let mut next = vec![usize::MAX; len + 1];
    let mut previous = vec![usize::MAX; len];
    for k in 0..len {
        before[k + 1] = before[k] + measured[a + k] as usize;
        previous[k] = if measured[a + k] {
            a + k
        } else if k > 0 {
            previous[k - 1]
        } else {
            usize::MAX
        };
    }
    for k in (0..len).rev() {
        next[k] = if measured[a + k] { a + k } else { next[k + 1] };
    }
    let mut moments = Moments::new(medial, measured);
    let mut straight = |first: usize, last: usize| {
        // `straight_line`'s count and span, exactly.
        let n = before[last + 1 - a] - before[first - a];
        if n < MIN_LINE_POINTS {
            return None;
        }
        let (from, to) = (next[first - a], previous[last - a]);
        if 2 * n < to + 1 - from {
            return None;
        }
        moments.set(first, last);
        if moments.surely_not_straight([medial[from], medial[to]]) {
            return None;
        }
        fit(first, last)
    };
    let mut runs = Vec::new();
    let mut start = a;
    while start + min_run <= b {
        let Some(mut line) = straight(start, start + min_run) else {
            start += 1;
            continue;
        };
        // Grown by a quarter of its length while straight, then the last step halved.
        let (mut good, mut step) = (start + min_run, (min_run / 4).max(1));
        loop {
            let next = (good + step).min(b);
            if next == good {
                break;
            }
            match straight(start, next) {
                Some(grown) => {
                    (good, line) = (next, grown);
                    step = ((good - start) / 4).max(1);
                }
                None if step > 1 => step /= 2,
                None => break,
            }
        }
        runs.push(((start, good), line));
        start = good;
    }
    runs
}

/// Where the ink ends going from `from` along the unit vector `u`: the first quarter-pixel
/// sample off the ink, then halved down to 1/64 px (so a sample on a pixel's edge, which the
/// floor puts on one side, moves the answer by no more than that); `limit` when the ink has not
/// ended by then.
///
/// The halvings need not read the mask when the first sample off the ink left the last one's
/// pixel across one edge only: each coordinate of `x0 + t u` moves one way only as `t` grows (a
/// rounded product and a rounded sum are monotone) and by at most a quarter pixel between the
/// two samples, so every point between them lies in one of their two pixels, and the side of
/// that edge (an integer, held exactly) says which: the same answers as reading the mask.
fn section_exit(ink: &Ink, from: [f64; 2], u: [f64; 2], limit: f64) -> f64 {
    // `Ink::at` without its floors (a call each on the baseline x86-64): a window coordinate
    // that is not negative truncates to its floor.
    let (x0, y0) = (from[0] - ink.origin[0], from[1] - ink.origin[1]);
    let point = |t: f64| (x0 + t * u[0], y0 + t * u[1]);
    // When the first sample and the point at `limit` lie in the window, every sample between
    // does (each coordinate moves one way only): the walk reads the mask without the window's
    // bounds (most of a lookup's instructions).
    let in_window =
        |(x, y): (f64, f64)| x >= 0.0 && y >= 0.0 && x < ink.width as f64 && y < ink.height as f64;
    let in_bounds =
        limit > SECTION_STEP_PX && in_window(point(SECTION_STEP_PX)) && in_window(point(limit));
    let mut t = SECTION_STEP_PX;
    while t < limit {
        let (x, y) = point(t);
        let on = if in_bounds {
            // SAFETY: `(x, y)` lies between the first sample and the point at `limit`, both
            // in the window: a rounded product and a rounded sum are monotone, so each
            // coordinate of `point(t)` is monotone in `t` for `SECTION_STEP_PX <= t <= limit`.
            unsafe { ink.at_inside(x, y) }
        } else {
            ink.at_window(x, y)
        };
        if !on {
            let (mut inside, mut outside) = (t - SECTION_STEP_PX, t);
            // The column or row of the last sample on the ink (none before the first sample)
            // that this one stayed in, when it left the other: the axis, the pixel edge it
            // crossed, and whether it crossed it rising. Between the two samples the coordinate
            // stays on the last one's side of the pixel's other edge (it moves one way only),
            // so the side of the crossed edge alone says whether a point is in that pixel.
            let mut across = None;
            if inside > 0.0 {
                let (xi, yi) = point(inside);
                let (cx, cy) = (window_floor(xi), window_floor(yi));
                let same_column = x >= cx && x < cx + 1.0;
                let same_row = y >= cy && y < cy + 1.0;
                across = match (same_column, same_row) {
                    (false, true) if x >= cx => Some((0, cx + 1.0, true)),
                    (false, true) => Some((0, cx, false)),
                    (true, false) if y >= cy => Some((1, cy + 1.0, true)),
                    (true, false) => Some((1, cy, false)),
                    _ => None,
                };
            }
            for _ in 0..BISECTIONS {
                let mid = (inside + outside) / 2.0;
                let (xm, ym) = point(mid);
                let on = match across {
                    Some((0, edge, rising)) => (xm < edge) == rising,
                    Some((_, edge, rising)) => (ym < edge) == rising,
                    None => ink.at_window(xm, ym),
                };
                if on {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            return (inside + outside) / 2.0;
        }
        t += SECTION_STEP_PX;
    }
    limit
}

/// The floor of a coordinate of a point on the ink (so inside the window: not negative, and
/// below 2^53), held exactly.
#[inline]
fn window_floor(v: f64) -> f64 {
    if v < 4_294_967_296.0 {
        f64::from(v as u32)
    } else {
        v as i64 as f64
    }
}

fn unit(d: [f64; 2]) -> Option<[f64; 2]> {
    let len = hypot(d[0], d[1]);
    (len > 1e-9).then(|| [d[0] / len, d[1] / len])
}

/// Solves `(A + λ DᵀD) q = A target` per coordinate, `A` the diagonal of `data`, `D` the second
/// differences at the samples where `smooth` holds: a symmetric positive definite matrix with
/// two bands either side of the diagonal, by its banded Cholesky factorization (linear in the
/// samples).
fn solve_banded(target: &[[f64; 2]], data: &[f64], smooth: &[bool], lambda: f64) -> Vec<[f64; 2]> {
    let n = target.len();
    // The matrix's bands: diagonal, first and second off-diagonal.
    let mut d0 = data.to_vec();
    let mut d1 = vec![0.0; n];
    let mut d2 = vec![0.0; n];
    for j in (1..n.saturating_sub(1)).filter(|&j| smooth[j]) {
        // The row (1, -2, 1) at j-1, j, j+1: its outer product, scaled by λ.
        let c = [1.0, -2.0, 1.0];
        for a in 0..3 {
            d0[j - 1 + a] += lambda * c[a] * c[a];
            if a < 2 {
                d1[j - 1 + a] += lambda * c[a] * c[a + 1];
            }
        }
        d2[j - 1] += lambda * c[0] * c[2];
    }
    // Banded Cholesky, L with the same bands: l0 diagonal, l1 and l2 below it, each written
    // over its band of the matrix (every entry of a band is read once, just before its own
    // entry of L is written).
    let (mut l0, mut l1, mut l2) = (d0, d1, d2);
    for i in 0..n {
        if i >= 2 {
            l2[i - 2] /= l0[i - 2];
        }
        if i >= 1 {
            let back = if i >= 2 { l2[i - 2] * l1[i - 2] } else { 0.0 };
            l1[i - 1] = (l1[i - 1] - back) / l0[i - 1];
        }
        let mut diag = l0[i];
        if i >= 1 {
            diag -= l1[i - 1] * l1[i - 1];
        }
        if i >= 2 {
            diag -= l2[i - 2] * l2[i - 2];
        }
        l0[i] = diag.max(1e-12).sqrt();
    }
    // Both coordinates in one sweep each way (the same operations on each as two solves).
    let mut out = vec![[0.0; 2]; n];
    for i in 0..n {
        let mut v = [data[i] * target[i][0], data[i] * target[i][1]];
        if i >= 1 {
            let y = out[i - 1];
            v = [v[0] - l1[i - 1] * y[0], v[1] - l1[i - 1] * y[1]];
        }
        if i >= 2 {
            let y = out[i - 2];
            v = [v[0] - l2[i - 2] * y[0], v[1] - l2[i - 2] * y[1]];
        }
        out[i] = [v[0] / l0[i], v[1] / l0[i]];
    }
    // Back substitution in place: `out[i]` still holds the forward sweep's value.
    for i in (0..n).rev() {
        let mut v = out[i];
        if i + 1 < n {
            let q = out[i + 1];
            v = [v[0] - l1[i] * q[0], v[1] - l1[i] * q[1]];
        }
        if i + 2 < n {
            let q = out[i + 2];
            v = [v[0] - l2[i] * q[0], v[1] - l2[i] * q[1]];
        }
        out[i] = [v[0] / l0[i], v[1] / l0[i]];
    }
    out
}

/// Keeps only the points an edge's shape needs: Douglas-Peucker at [`SIMPLIFY_PX`], a segment
/// kept only when it lies on the ink; widths and directions (when the edge has them) follow
/// their points.
fn simplify_edge(edge: &mut Edge, ink: &Ink) {
    let n = edge.points.len();
    if n < 3 {
        return;
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0usize, n - 1)];
    let mut squares = Vec::new();
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (pa, pb) = (edge.points[a], edge.points[b]);
        // The farthest point by its squared distance, then the distance itself (`hypot`) only
        // for the points whose squares come within rounding of the largest: the same point (the
        // first of the farthest) and the same distance as measuring every point, at one square
        // root per candidate instead of per point.
        squares.clear();
        squares.extend((a + 1..b).map(|i| segment_dist2(edge.points[i], pa, pb)));
        let near_far2 = squares.iter().copied().fold(0.0, f64::max) * (1.0 - 1e-9);
        let (mut worst, mut at) = (-1.0, a + 1);
        for (i, &d2) in (a + 1..b).zip(&squares) {
            if d2 < near_far2 {
                continue;
            }
            let d = segment_dist(edge.points[i], pa, pb);
            if d > worst {
                (worst, at) = (d, i);
            }
        }
        if worst > SIMPLIFY_PX || !ink.holds(pa, pb) {
            keep[at] = true;
            stack.push((at, b));
            stack.push((a, at));
        }
    }
    retain_kept(&mut edge.points, &keep);
    retain_kept(&mut edge.widths, &keep);
    if edge.directions.len() == n {
        retain_kept(&mut edge.directions, &keep);
    }
}

/// Keeps the items whose `keep` flag is set.
fn retain_kept<T>(items: &mut Vec<T>, keep: &[bool]) {
    let mut flags = keep.iter();
    items.retain(|_| flags.next().copied().unwrap_or(true));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::point_at;
    use crate::params::Params;
    use crate::synth::{render, Stroke};

    /// [`section_exit`] as it was: every sample looked up in the mask.
    fn section_exit_looked_up(ink: &Ink, from: [f64; 2], u: [f64; 2], limit: f64) -> f64 {
        let (x0, y0) = (from[0] - ink.origin[0], from[1] - ink.origin[1]);
        let on = |t: f64| ink.at_window(x0 + t * u[0], y0 + t * u[1]);
        let mut t = SECTION_STEP_PX;
        while t < limit {
            if !on(t) {
                let (mut inside, mut outside) = (t - SECTION_STEP_PX, t);
                for _ in 0..BISECTIONS {
                    let mid = (inside + outside) / 2.0;
                    if on(mid) {
                        inside = mid;
                    } else {
                        outside = mid;
                    }
                }
                return (inside + outside) / 2.0;
            }
            t += SECTION_STEP_PX;
        }
        limit
    }

    /// [`straight_line`] as it was: five walks over the stretch.
    fn straight_line_five_walks(
        points: &[[f64; 2]],
        measured: &[bool],
        a: usize,
        b: usize,
    ) -> Option<Line> {
        let on = || (a..=b).filter(|&j| measured[j]).map(|j| points[j]);
        let n = on().count();
        // Measured along most of their span: a few points do not speak for a stretch between.
        let span = match (
            (a..=b).find(|&j| measured[j]),
            (a..=b).rev().find(|&j| measured[j]),
        ) {
            (Some(first), Some(last)) => last - first + 1,
            _ => 0,
        };
        if n < MIN_LINE_POINTS || 2 * n < span {
            return None;
        }
        let centre = on().fold([0.0; 2], |c, p| [c[0] + p[0], c[1] + p[1]]);
        let centre = [centre[0] / n as f64, centre[1] / n as f64];
        let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
        for p in on() {
            let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
            cxx += dx * dx;
            cxy += dx * dy;
            cyy += dy * dy;
        }
        let (_, along) = principal(cxx, cxy, cyy);
        let normal = [-along[1], along[0]];
        // Offsets r across the line against positions t along it, t scaled to [-1, 1].
        let frame = |p: [f64; 2]| {
            let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
            (
                dx * along[0] + dy * along[1],
                dx * normal[0] + dy * normal[1],
            )
        };
        let (mut lo, mut hi, mut worst) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for p in on() {
            let (t, r) = frame(p);
            lo = lo.min(t);
            hi = hi.max(t);
            worst = worst.max(r.abs());
        }
        if worst > SCATTER_PX || hi - lo < 1.0 {
            return None;
        }
        let bend = parabola_bend(on().map(frame), lo, hi)?;
        (bend.abs() <= BEND_PX).then_some(Line { centre, along })
    }

    /// [`straight_runs`] as it was: every window fitted from scratch.
    fn straight_runs_refitted(
        medial: &[[f64; 2]],
        measured: &[bool],
        clean: &[bool],
        a: usize,
        b: usize,
        min_run: usize,
    ) -> Vec<((usize, usize), Line)> {
        let straight_line = |medial: &[[f64; 2]], _: &[bool], a: usize, b: usize| {
            // The clean points' line only where the measured ones are straight (most windows on
            // a curve are not): the same answer, without the second fit.
            straight_line_five_walks(medial, measured, a, b)
                .and_then(|_| straight_line_five_walks(medial, clean, a, b))
        };
        if let Some(line) = straight_line(medial, measured, a, b) {
            return vec![((a, b), line)];
        }
        let mut runs = Vec::new();
        let mut start = a;
        while start + min_run <= b {
            let Some(mut line) = straight_line(medial, measured, start, start + min_run) else {
                start += 1;
                continue;
            };
            // Grown by a quarter of its length while straight, then the last step halved.
            let (mut good, mut step) = (start + min_run, (min_run / 4).max(1));
            loop {
                let next = (good + step).min(b);
                if next == good {
                    break;
                }
                match straight_line(medial, measured, start, next) {
                    Some(grown) => {
                        (good, line) = (next, grown);
                        step = ((good - start) / 4).max(1);
                    }
                    None if step > 1 => step /= 2,
                    None => break,
                }
            }
            runs.push(((start, good), line));
            start = good;
        }
        runs
    }

    #[test]
    fn power_sums_shifted_are_the_centred_ones() {
        let xs: [f64; 6] = [3.0, -1.5, 7.25, 0.5, 2.0, 11.0];
        let c = 2.75;
        let mut sums: Vec<f64> = (0..5)
            .map(|k| xs.iter().map(|x: &f64| x.powi(k)).sum())
            .collect();
        shift_moments(&mut sums, c);
        for (k, &sum) in sums.iter().enumerate() {
            let direct: f64 = xs.iter().map(|x| (x - c).powi(k as i32)).sum();
            assert!(
                (sum - direct).abs() <= 1e-9 * direct.abs().max(1.0),
                "{k}: {sum} {direct}"
            );
        }
    }

    /// A stretch's medial points, which of them were measured, which are clean.
    type Stretch = (Vec<[f64; 2]>, Vec<bool>, Vec<bool>);

    /// Medial points of random strokes (lines, arcs, waves, sampled every pixel, moved by the
    /// pixel grid's scatter), with random samples left unmeasured or unclean.
    fn random_stretches() -> Vec<Stretch> {
        let mut next = crate::synth::lcg(3333u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let mut stretches = Vec::new();
        for case in 0..600 {
            let len = 10 + (unit() * 150.0) as usize;
            let (x0, y0) = (unit() * 3000.0, unit() * 3000.0);
            let angle = unit() * std::f64::consts::TAU;
            let radius = 3.0 * (unit() * 8.0).exp();
            let wave = (unit() * 3.0, 10.0 + unit() * 60.0);
            let scatter = [0.0, 0.2, 0.45][case % 3];
            let points: Vec<[f64; 2]> = (0..len)
                .map(|j| {
                    let s = j as f64;
                    let (u, v) = match case % 4 {
                        0 => (s, 0.0),
                        1 | 2 => {
                            let a = s / radius;
                            (radius * a.sin(), radius * (1.0 - a.cos()))
                        }
                        _ => (s, wave.0 * (s / wave.1 * std::f64::consts::TAU).sin()),
                    };
                    let (c, d) = (angle.cos(), angle.sin());
                    [
                        x0 + u * c - v * d + scatter * (unit() - 0.5),
                        y0 + u * d + v * c + scatter * (unit() - 0.5),
                    ]
                })
                .collect();
            let gaps = [0.0, 0.05, 0.3][case % 3];
            let measured: Vec<bool> = (0..len).map(|_| unit() >= gaps).collect();
            let clean: Vec<bool> = measured.iter().map(|&m| m && unit() >= gaps).collect();
            stretches.push((points, measured, clean));
        }
        stretches
    }

    #[test]
    fn a_window_refused_from_its_sums_is_one_the_fit_refuses() {
        // Every window of every random stretch (its sums moved to it as the search moves
        // them, grown, shrunk and slid): where the sums say surely not straight, the fit as it
        // was says the same. Both answers well represented.
        let (mut refused, mut fitted, mut straight) = (0, 0, 0);
        for (points, measured, _) in random_stretches() {
            let len = points.len();
            let mut moments = Moments::new(&points, &measured);
            for first in 0..len {
                for last in first..len.min(first + 60) {
                    let n = (first..=last).filter(|&j| measured[j]).count();
                    if n < MIN_LINE_POINTS {
                        continue;
                    }
                    let from = (first..=last).find(|&j| measured[j]).unwrap();
                    let to = (first..=last).rev().find(|&j| measured[j]).unwrap();
                    moments.set(first, last);
                    let exact = straight_line_five_walks(&points, &measured, first, last);
                    if moments.surely_not_straight([points[from], points[to]]) {
                        assert!(exact.is_none(), "{first} {last}: {points:?} {measured:?}");
                        refused += 1;
                    } else {
                        fitted += 1;
                        straight += exact.is_some() as usize;
                    }
                }
            }
        }
        assert!(
            refused > 100_000 && straight > 50_000 && fitted > straight + 1_000,
            "{refused} {fitted} {straight}"
        );
    }

    #[test]
    fn the_straight_runs_from_running_sums_are_the_runs_refitted() {
        // The same runs and the same lines, bit for bit, as fitting every window afresh.
        let mut runs = 0;
        for (case, (points, measured, clean)) in random_stretches().into_iter().enumerate() {
            let b = points.len() - 1;
            for min_run in [4, 9, 16, 33] {
                let a = case % 3;
                let new = straight_runs(&points, &measured, &clean, a, b, min_run);
                let old = straight_runs_refitted(&points, &measured, &clean, a, b, min_run);
                assert_eq!(new.len(), old.len(), "{case} {min_run}");
                for (n, o) in new.iter().zip(&old) {
                    assert_eq!(n.0, o.0, "{case} {min_run}");
                    let bits = |l: &Line| {
                        [l.centre[0], l.centre[1], l.along[0], l.along[1]].map(f64::to_bits)
                    };
                    assert_eq!(bits(&n.1), bits(&o.1), "{case} {min_run}");
                }
                runs += new.len();
            }
        }
        assert!(runs > 1000, "{runs}");
    }

    #[test]
    fn a_cross_section_reading_each_pixel_once_ends_where_it_did() {
        // Random windows of blobs and specks, sections from inside and outside them (on pixel
        // corners and edges too), along random directions and along the axes and diagonals
        // (zeros of both signs), limits short and long: the same bits as looking up every sample.
        let mut next = crate::synth::lcg(4242u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let special = [
            [1.0, 0.0],
            [-1.0, 0.0],
            [0.0, 1.0],
            [0.0, -1.0],
            [-0.0, 1.0],
            [1.0, -0.0],
            [h, h],
            [-h, h],
            [h, -h],
            [-h, -h],
        ];
        let (mut exits, mut limits) = (0, 0);
        for case in 0..300 {
            let width = 1 + (unit() * 40.0) as usize;
            let height = 1 + (unit() * 40.0) as usize;
            let fill = unit();
            let mut mask: Vec<bool> = (0..width * height).map(|_| unit() < fill).collect();
            // Solid discs, so that sections run through several ink pixels.
            for _ in 0..(unit() * 4.0) as usize {
                let (cx, cy, r) = (unit() * width as f64, unit() * height as f64, unit() * 10.0);
                for y in 0..height {
                    for x in 0..width {
                        let (dx, dy) = (x as f64 + 0.5 - cx, y as f64 + 0.5 - cy);
                        if dx * dx + dy * dy <= r * r {
                            mask[y * width + x] = true;
                        }
                    }
                }
            }
            let origin = if case % 3 == 0 {
                [0.0, 0.0]
            } else {
                [
                    (unit() * 2000.0).floor() - 1000.0,
                    (unit() * 2000.0).floor() + 0.5,
                ]
            };
            let ink = Ink {
                mask,
                width,
                height,
                origin,
            };
            for k in 0..200 {
                let mut p = [
                    unit() * (width as f64 + 4.0) - 2.0,
                    unit() * (height as f64 + 4.0) - 2.0,
                ];
                match k % 4 {
                    0 => p = [p[0].floor() + 0.5, p[1].floor() + 0.5],
                    1 => p = [p[0].floor(), p[1].floor()],
                    _ => {}
                }
                let from = [p[0] + origin[0], p[1] + origin[1]];
                let u = if k % 5 == 0 {
                    special[(unit() * special.len() as f64) as usize % special.len()]
                } else {
                    let a = unit() * std::f64::consts::TAU;
                    [a.cos(), a.sin()]
                };
                let limit = if k % 7 == 0 {
                    unit() * 2.0
                } else {
                    unit() * 30.0
                };
                let (new, old) = (
                    section_exit(&ink, from, u, limit),
                    section_exit_looked_up(&ink, from, u, limit),
                );
                assert_eq!(
                    new.to_bits(),
                    old.to_bits(),
                    "{case} {k}: {from:?} {u:?} {limit}"
                );
                if old == limit {
                    limits += 1;
                } else {
                    exits += 1;
                }
            }
        }
        // Both outcomes well represented.
        assert!(exits > 10_000 && limits > 5_000, "{exits} {limits}");
    }

    #[test]
    fn the_ink_lookup_is_the_one_through_usize() {
        // `Ink::at_window` as it was: the coordinates cast to `usize` directly.
        let through_usize = |ink: &Ink, x: f64, y: f64| {
            x >= 0.0
                && y >= 0.0
                && (x as usize) < ink.width
                && (y as usize) < ink.height
                && ink.mask[y as usize * ink.width + x as usize]
        };
        let (width, height) = (7, 5);
        let ink = Ink {
            mask: (0..width * height).map(|i| i % 3 != 1).collect(),
            width,
            height,
            origin: [0.0; 2],
        };
        let values = [
            f64::NAN,
            f64::NEG_INFINITY,
            -1e300,
            -1.0,
            -0.5,
            -0.0,
            0.0,
            0.25,
            0.999,
            1.0,
            3.5,
            4.999_999_999,
            5.0,
            6.5,
            7.0,
            9.2e18,
            // 2⁶³ less one step of `f64`, and 2⁶³ itself (`Ink::at_window`'s bound).
            9_223_372_036_854_774_784.0,
            9_223_372_036_854_775_808.0,
            1.9e19,
            1e300,
            f64::INFINITY,
        ];
        for &x in &values {
            for &y in &values {
                assert_eq!(ink.at_window(x, y), through_usize(&ink, x, y), "{x} {y}");
            }
        }
    }

    #[test]
    // A dense reference solve reads clearest with its indices.
    #[allow(clippy::needless_range_loop)]
    fn the_banded_solve_matches_a_dense_one() {
        // A zigzag target, a corner in the middle: (A + λ DᵀD) q = A t solved densely by
        // Gaussian elimination gives the same q.
        let n = 9;
        let target: Vec<[f64; 2]> = (0..n)
            .map(|i| [i as f64, if i % 2 == 0 { 0.5 } else { -0.5 }])
            .collect();
        let data: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 * 0.25).collect();
        let smooth: Vec<bool> = (0..n).map(|i| i > 0 && i < n - 1 && i != 4).collect();
        let lambda = 3.0;
        let banded = solve_banded(&target, &data, &smooth, lambda);
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            a[i][i] = data[i];
        }
        for j in (1..n - 1).filter(|&j| smooth[j]) {
            let row = [(j - 1, 1.0), (j, -2.0), (j + 1, 1.0)];
            for &(r, x) in &row {
                for &(c, y) in &row {
                    a[r][c] += lambda * x * y;
                }
            }
        }
        for k in 0..2 {
            let mut m = a.clone();
            let mut b: Vec<f64> = (0..n).map(|i| data[i] * target[i][k]).collect();
            for i in 0..n {
                for r in i + 1..n {
                    let f = m[r][i] / m[i][i];
                    for c in i..n {
                        m[r][c] -= f * m[i][c];
                    }
                    b[r] -= f * b[i];
                }
            }
            let mut x = vec![0.0; n];
            for i in (0..n).rev() {
                let s: f64 = (i + 1..n).map(|c| m[i][c] * x[c]).sum();
                x[i] = (b[i] - s) / m[i][i];
            }
            for i in 0..n {
                assert!(
                    (x[i] - banded[i][k]).abs() < 1e-9,
                    "{k} {i}: {x:?} {banded:?}"
                );
            }
        }
    }

    fn traced(strokes: &[Stroke], w: u32, h: u32) -> (crate::binary::Binary, StrokeGraph) {
        let binary = render(strokes, w, h);
        let graph = crate::trace_binary(&binary, &Params::default())
            .expect("trace")
            .graph;
        super::super::validate(&graph).expect("valid skeleton graph");
        (binary, graph)
    }

    use crate::stroke_graph::StrokeGraph;

    /// The mean and largest distance from a graph's polylines, sampled every quarter pixel, to
    /// the polyline `truth`, leaving out `skip` px at each end of each edge.
    fn distance_to(graph: &StrokeGraph, truth: &[[f64; 2]], skip: f64) -> (f64, f64) {
        let (mut sum, mut count, mut worst) = (0.0, 0usize, 0.0f64);
        for edge in &graph.edges {
            let s = arc_lengths(&edge.points);
            let total = s[s.len() - 1];
            let mut t = skip;
            while t <= total - skip {
                let (p, _) = point_at(&edge.points, &s, t);
                let d = truth
                    .windows(2)
                    .map(|w| segment_dist(p, w[0], w[1]))
                    .fold(f64::INFINITY, f64::min);
                sum += d;
                count += 1;
                worst = worst.max(d);
                t += 0.25;
            }
        }
        (sum / count.max(1) as f64, worst)
    }

    #[test]
    fn a_slanted_stroke_of_even_width_is_one_straight_centred_line() {
        // 4 px wide, a slope of 1 in 5: the skeleton is a staircase half a pixel to one side.
        let line = vec![[10.0, 20.0], [110.0, 40.0]];
        let (binary, graph) = traced(&[Stroke::new(line.clone(), 4.0)], 120, 60);
        assert_eq!(graph.edges.len(), 1);
        let (mean, worst) = distance_to(&graph, &line, 4.0);
        assert!(mean <= 0.2, "mean {mean:.3} px from the true centerline");
        assert!(worst <= 0.5, "worst {worst:.3} px");
        // A straight stroke needs few points.
        let points = graph.edges[0].points.len();
        assert!(points <= 12, "{points} points for a straight stroke");
        for s in graph.edges[0].points.windows(2) {
            for k in 0..=8 {
                let t = k as f64 / 8.0;
                let p = [
                    s[0][0] + t * (s[1][0] - s[0][0]),
                    s[0][1] + t * (s[1][1] - s[0][1]),
                ];
                assert!(binary.get(p[0].floor() as i64, p[1].floor() as i64));
            }
        }
    }

    /// The skeleton's graph of `strokes` with no decision of the method's (an empty method
    /// graph: no crossing merged, no line adopted), so that the smoothing alone places it.
    fn skeleton_alone(strokes: &[Stroke], w: u32, h: u32) -> StrokeGraph {
        let binary = render(strokes, w, h);
        let params = Params::default();
        let points = crate::raster::points(&binary, &params).expect("points");
        let method = StrokeGraph {
            width: w,
            height: h,
            ..StrokeGraph::default()
        };
        let graph = super::super::prepare(&points, &params.experiments, false, None)
            .expect("a skeleton")
            .carry(&method, &params.experiments);
        super::super::validate(&graph).expect("valid skeleton graph");
        graph
    }

    #[test]
    fn slanted_straight_strokes_are_straight_and_centred_without_the_methods_lines() {
        // Slopes from 1 in 2 to 1 in 20, even and odd widths: the medial points scatter at the
        // staircase's period, the line through them is the stroke's middle (within the tenth
        // of a pixel by which a slope of a whole ratio leaves the image unchanged).
        let mut report = Vec::new();
        let mut failed = false;
        for &(rise, width) in &[
            (50.0, 4.0),
            (20.0, 4.0),
            (10.0, 4.0),
            (5.0, 4.0),
            (20.0, 5.0),
            (5.0, 5.0),
            (30.0, 3.0),
            (12.0, 6.0),
            (40.0, 7.0),
            (8.0, 8.0),
        ] {
            let line = vec![[10.0, 20.0], [110.0, 20.0 + rise]];
            let graph = skeleton_alone(&[Stroke::new(line.clone(), width)], 120, 80);
            assert_eq!(graph.edges.len(), 1);
            let (mean, worst) = distance_to(&graph, &line, width);
            let points = graph.edges[0].points.len();
            report.push(format!(
                "rise {rise} width {width}: mean {mean:.3} worst {worst:.3} points {points}"
            ));
            failed |= mean > 0.15 || worst > 0.3 || points > 5;
        }
        assert!(!failed, "{report:#?}");
    }

    #[test]
    fn a_right_angle_stays_sharp_and_a_circle_round() {
        let corner = [80.0, 20.0];
        let l = vec![[15.0, 20.0], corner, [80.0, 85.0]];
        let (_, graph) = traced(&[Stroke::new(l.clone(), 5.0)], 100, 100);
        assert_eq!(graph.edges.len(), 1);
        let (mean, _) = distance_to(&graph, &l, 4.0);
        assert!(mean <= 0.25, "mean {mean:.3} px from the L");
        // A round pen's corner is cut by the skeleton; the fit does not cut it further.
        let nearest = graph.edges[0]
            .points
            .windows(2)
            .map(|s| segment_dist(corner, s[0], s[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= 3.0,
            "the corner is {nearest:.2} px from the line"
        );

        let ring: Vec<[f64; 2]> = (0..=96)
            .map(|k| {
                let a = k as f64 / 96.0 * std::f64::consts::TAU;
                [50.0 + 30.0 * a.cos(), 50.0 + 30.0 * a.sin()]
            })
            .collect();
        let (_, graph) = traced(&[Stroke::new(ring.clone(), 6.0)], 100, 100);
        let (mean, worst) = distance_to(&graph, &ring, 0.0);
        assert!(mean <= 0.2, "mean {mean:.3} px from the circle");
        assert!(worst <= 0.6, "worst {worst:.3} px from the circle");
    }
}
