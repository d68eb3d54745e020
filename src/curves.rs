//! Smooth curves: cubic Béziers fitted to centerline polylines, for SVG paths that are smaller and
//! smoother than polylines (docs/design.md, "Beyond the paper").
//!
//! Schneider's algorithm ("An Algorithm for Automatically Fitting Digitized Curves", Graphics
//! Gems, 1990): split the polyline at corners (turning angle above a threshold), then for each
//! piece fit one cubic by least squares with fixed end tangents under chord-length
//! parameterization, improve the parameters by Newton steps, and when the largest distance from a
//! point to the curve still exceeds the tolerance, split at that point (with a shared tangent, so
//! the pieces join smoothly) and fit both halves.
//!
//! Input: a polyline (image coordinates). Output: `Vec<CubicBezier>`, joined end to start; every
//! input point lies within the tolerance of the curve at its parameter. Deterministic.

use crate::geometry::hypot;
use crate::stroke_graph::StrokeGraph;
use serde::Serialize;

/// One cubic Bézier segment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CubicBezier {
    /// Start point.
    pub p0: [f64; 2],
    /// First control point.
    pub p1: [f64; 2],
    /// Second control point.
    pub p2: [f64; 2],
    /// End point.
    pub p3: [f64; 2],
}

impl CubicBezier {
    /// The point at parameter `t` in `[0, 1]`.
    pub fn eval(&self, t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let (b0, b1, b2, b3) = (s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
        [
            b0 * self.p0[0] + b1 * self.p1[0] + b2 * self.p2[0] + b3 * self.p3[0],
            b0 * self.p0[1] + b1 * self.p1[1] + b2 * self.p2[1] + b3 * self.p3[1],
        ]
    }

    /// First derivative at `t`.
    fn derivative(&self, t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let d = |k: usize| {
            3.0 * (s * s * (self.p1[k] - self.p0[k])
                + 2.0 * s * t * (self.p2[k] - self.p1[k])
                + t * t * (self.p3[k] - self.p2[k]))
        };
        [d(0), d(1)]
    }

    /// Second derivative at `t`.
    fn second_derivative(&self, t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let d = |k: usize| {
            6.0 * (s * (self.p2[k] - 2.0 * self.p1[k] + self.p0[k])
                + t * (self.p3[k] - 2.0 * self.p2[k] + self.p1[k]))
        };
        [d(0), d(1)]
    }
}

/// Options for [`fit_edges`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CurveOptions {
    /// Largest distance from a polyline point to the fitted curve, px. Default value: 0.5.
    pub tolerance: f64,
    /// A polyline point where the direction turns by more than this many degrees is a corner: the
    /// curve passes through it with a break in tangent. Default value: 60.
    pub corner_angle_deg: f64,
}

impl Default for CurveOptions {
    fn default() -> Self {
        CurveOptions {
            tolerance: 0.5,
            corner_angle_deg: 60.0,
        }
    }
}

/// Fits each edge polyline of `graph`: one list of segments per edge, in edge order.
pub fn fit_edges(graph: &StrokeGraph, options: &CurveOptions) -> Vec<Vec<CubicBezier>> {
    graph
        .edges
        .iter()
        .map(|e| fit_beziers(&e.points, options.tolerance, options.corner_angle_deg))
        .collect()
}

/// Newton reparameterization rounds per piece before it is split (Schneider uses 4).
const MAX_ITERATIONS: usize = 8;

type Point = [f64; 2];

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}
fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}
fn scale(a: Point, s: f64) -> Point {
    [a[0] * s, a[1] * s]
}
fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn norm(a: Point) -> f64 {
    hypot(a[0], a[1])
}
fn normalize(a: Point) -> Point {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0, 0.0]
    }
}

/// Fits cubic Béziers to the polyline `points` so that every point lies within `tolerance` (px) of
/// the curve, breaking the tangent at corners (points where the polyline turns by more than
/// `corner_angle_deg`). A closed polyline (last point equal to the first) without a corner there
/// gets one tangent at its start and end, so the curve closes smoothly. Non-finite points and
/// repeated points are skipped; fewer than two distinct points give no segment. A non-positive
/// tolerance is treated as 0.01 px.
pub fn fit_beziers(points: &[[f64; 2]], tolerance: f64, corner_angle_deg: f64) -> Vec<CubicBezier> {
    let mut clean: Vec<Point> = Vec::with_capacity(points.len());
    for &p in points {
        if !(p[0].is_finite() && p[1].is_finite()) {
            continue;
        }
        if clean.last().is_none_or(|&q| norm(sub(p, q)) > 1e-9) {
            clean.push(p);
        }
    }
    if clean.len() < 2 {
        return Vec::new();
    }
    let tolerance = if tolerance > 0.0 && tolerance.is_finite() {
        tolerance
    } else {
        0.01
    };
    let corner_cos = corner_angle_deg.to_radians().cos();
    let n = clean.len();
    let turns_sharply = |before: Point, at: Point, after: Point| {
        let (a, b) = (normalize(sub(at, before)), normalize(sub(after, at)));
        dot(a, b) < corner_cos
    };
    // Corners split the polyline into pieces fitted independently.
    let mut breaks = vec![0];
    for i in 1..n - 1 {
        if turns_sharply(clean[i - 1], clean[i], clean[i + 1]) {
            breaks.push(i);
        }
    }
    breaks.push(n - 1);
    let closed = n > 3 && norm(sub(clean[0], clean[n - 1])) <= 1e-9;
    let smooth_closure = closed && !turns_sharply(clean[n - 2], clean[0], clean[1]);
    let mut out = Vec::new();
    for (k, piece) in breaks.windows(2).enumerate() {
        let (first, last) = (piece[0], piece[1]);
        let mut start_tangent = normalize(sub(clean[first + 1], clean[first]));
        let mut end_tangent = normalize(sub(clean[last - 1], clean[last]));
        if smooth_closure && k == 0 {
            start_tangent = normalize(sub(clean[1], clean[n - 2]));
        }
        if smooth_closure && k == breaks.len() - 2 {
            end_tangent = normalize(sub(clean[n - 2], clean[1]));
        }
        fit_piece(
            &clean[first..=last],
            start_tangent,
            end_tangent,
            tolerance,
            &mut out,
        );
    }
    out
}

/// Schneider's `FitCubic` on one corner-free piece, with an explicit stack (long polylines must not
/// recurse deeply). Segments are appended in order.
fn fit_piece(
    d: &[Point],
    start_tangent: Point,
    end_tangent: Point,
    tolerance: f64,
    out: &mut Vec<CubicBezier>,
) {
    // (first, last, tangent at first, tangent at last); popped left half first.
    let mut stack = vec![(0usize, d.len() - 1, start_tangent, end_tangent)];
    let mut u: Vec<f64> = Vec::new();
    while let Some((first, last, t1, t2)) = stack.pop() {
        let piece = &d[first..=last];
        if piece.len() == 2 {
            // Two points: Schneider's heuristic, control points a third of the chord along the tangents.
            let third = norm(sub(piece[1], piece[0])) / 3.0;
            out.push(CubicBezier {
                p0: piece[0],
                p1: add(piece[0], scale(t1, third)),
                p2: add(piece[1], scale(t2, third)),
                p3: piece[1],
            });
            continue;
        }
        chord_length_parameters(piece, &mut u);
        let mut curve = generate_bezier(piece, &u, t1, t2);
        let (mut error, mut split) = max_error(piece, &curve, &u);
        // Within a few tolerances, Newton steps on the parameters usually reach the tolerance.
        if error > tolerance && error < 4.0 * tolerance {
            for _ in 0..MAX_ITERATIONS {
                reparameterize(piece, &curve, &mut u);
                curve = generate_bezier(piece, &u, t1, t2);
                (error, split) = max_error(piece, &curve, &u);
                if error <= tolerance {
                    break;
                }
            }
        }
        if error <= tolerance {
            out.push(curve);
            continue;
        }
        // Split at the worst point with a shared tangent (Schneider's `ComputeCenterTangent`).
        let split = split.clamp(1, piece.len() - 2);
        let mut center = normalize(sub(piece[split - 1], piece[split + 1]));
        if norm(center) == 0.0 {
            center = normalize(sub(piece[split - 1], piece[split]));
        }
        stack.push((first + split, last, scale(center, -1.0), t2));
        stack.push((first, first + split, t1, center));
    }
}

/// Chord-length parameterization: `u[i]` is the polyline length up to point `i` over the total.
fn chord_length_parameters(d: &[Point], u: &mut Vec<f64>) {
    u.clear();
    u.push(0.0);
    let mut length = 0.0;
    for w in d.windows(2) {
        length += norm(sub(w[1], w[0]));
        u.push(length);
    }
    if length > 0.0 {
        u.iter_mut().for_each(|x| *x /= length);
    }
}

/// Least-squares cubic with end points fixed and end tangents `t1`, `t2` fixed in direction:
/// solves the 2x2 normal equations for the two tangent lengths (Schneider's `GenerateBezier`),
/// falling back to a third of the chord when they are degenerate or not positive.
fn generate_bezier(d: &[Point], u: &[f64], t1: Point, t2: Point) -> CubicBezier {
    let (p0, p3) = (d[0], d[d.len() - 1]);
    let mut c = [[0.0; 2]; 2];
    let mut x = [0.0; 2];
    for (&p, &t) in d.iter().zip(u) {
        let s = 1.0 - t;
        let (b0, b1, b2, b3) = (s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
        let a1 = scale(t1, b1);
        let a2 = scale(t2, b2);
        c[0][0] += dot(a1, a1);
        c[0][1] += dot(a1, a2);
        c[1][1] += dot(a2, a2);
        let rest = sub(p, add(scale(p0, b0 + b1), scale(p3, b2 + b3)));
        x[0] += dot(a1, rest);
        x[1] += dot(a2, rest);
    }
    c[1][0] = c[0][1];
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    let (alpha1, alpha2) = if det.abs() > 1e-12 {
        (
            (x[0] * c[1][1] - c[0][1] * x[1]) / det,
            (c[0][0] * x[1] - c[1][0] * x[0]) / det,
        )
    } else {
        (0.0, 0.0)
    };
    let chord = norm(sub(p3, p0));
    let epsilon = 1e-6 * chord;
    // Tangent lengths must be positive and finite, else Schneider's fallback: a third of the chord.
    let usable = |alpha: f64| alpha > epsilon && alpha.is_finite();
    let (alpha1, alpha2) = if usable(alpha1) && usable(alpha2) {
        (alpha1, alpha2)
    } else {
        (chord / 3.0, chord / 3.0)
    };
    CubicBezier {
        p0,
        p1: add(p0, scale(t1, alpha1)),
        p2: add(p3, scale(t2, alpha2)),
        p3,
    }
}

/// Largest distance from a point to the curve at its parameter, and that point's index.
fn max_error(d: &[Point], curve: &CubicBezier, u: &[f64]) -> (f64, usize) {
    let mut worst = (0.0, d.len() / 2);
    for i in 1..d.len() - 1 {
        let e = norm(sub(curve.eval(u[i]), d[i]));
        if e > worst.0 {
            worst = (e, i);
        }
    }
    worst
}

/// One Newton-Raphson step per point on `f(t) = (Q(t) - P) · Q'(t)`, the condition for `Q(t)` to be
/// the nearest curve point to `P` (Schneider's `NewtonRaphsonRootFind`).
fn reparameterize(d: &[Point], curve: &CubicBezier, u: &mut [f64]) {
    for (p, t) in d.iter().zip(u.iter_mut()) {
        let q = curve.eval(*t);
        let q1 = curve.derivative(*t);
        let q2 = curve.second_derivative(*t);
        let diff = sub(q, *p);
        let numerator = dot(diff, q1);
        let denominator = dot(q1, q1) + dot(diff, q2);
        if denominator.abs() > 1e-12 {
            let next = *t - numerator / denominator;
            if next.is_finite() {
                *t = next.clamp(0.0, 1.0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest distance from any input point to the curve, by dense sampling.
    fn deviation(points: &[Point], segments: &[CubicBezier]) -> f64 {
        let samples: Vec<Point> = segments
            .iter()
            .flat_map(|s| (0..=400).map(move |k| s.eval(k as f64 / 400.0)))
            .collect();
        points
            .iter()
            .map(|&p| {
                samples
                    .iter()
                    .map(|&q| norm(sub(p, q)))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    fn joined(segments: &[CubicBezier]) -> bool {
        segments
            .windows(2)
            .all(|w| norm(sub(w[0].p3, w[1].p0)) < 1e-9)
    }

    #[test]
    fn circle_fits_within_tolerance_with_few_segments() {
        let points: Vec<Point> = (0..=120)
            .map(|k| {
                let a = k as f64 / 120.0 * std::f64::consts::TAU;
                [100.0 + 40.0 * a.cos(), 100.0 + 40.0 * a.sin()]
            })
            .collect();
        let segments = fit_beziers(&points, 0.5, 60.0);
        assert!(
            !segments.is_empty() && segments.len() <= 8,
            "{} segments",
            segments.len()
        );
        assert!(joined(&segments));
        assert!(deviation(&points, &segments) <= 0.5);
        // Between the samples too, the curve stays on the circle.
        for s in &segments {
            for k in 0..=100 {
                let r = norm(sub(s.eval(k as f64 / 100.0), [100.0, 100.0]));
                assert!((r - 40.0).abs() <= 0.5, "radius {r}");
            }
        }
        // Closed and smooth: the end tangent continues the start tangent.
        let (first, last) = (segments[0], segments[segments.len() - 1]);
        let (a, b) = (
            normalize(sub(first.p1, first.p0)),
            normalize(sub(last.p3, last.p2)),
        );
        assert!(dot(a, b) > 0.999, "{a:?} {b:?}");
    }

    #[test]
    fn square_keeps_its_corners() {
        let mut points = Vec::new();
        let corners = [
            [10.0, 10.0],
            [60.0, 10.0],
            [60.0, 60.0],
            [10.0, 60.0],
            [10.0, 10.0],
        ];
        for w in corners.windows(2) {
            for k in 0..10 {
                let t = k as f64 / 10.0;
                points.push([
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ]);
            }
        }
        points.push(corners[4]);
        let segments = fit_beziers(&points, 0.5, 60.0);
        assert_eq!(segments.len(), 4);
        for (s, c) in segments.iter().zip(corners.iter()) {
            assert!(norm(sub(s.p0, *c)) < 1e-9, "segment starts at a corner");
        }
        assert!(deviation(&points, &segments) <= 0.5);
        // Straight sides: control points on the side.
        for s in &segments {
            let side = normalize(sub(s.p3, s.p0));
            for p in [s.p1, s.p2] {
                let off = sub(p, s.p0);
                assert!((off[0] * side[1] - off[1] * side[0]).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn straight_line_is_one_segment() {
        let points: Vec<Point> = (0..50)
            .map(|k| [k as f64 * 1.3, 5.0 + k as f64 * 0.7])
            .collect();
        let segments = fit_beziers(&points, 0.5, 60.0);
        assert_eq!(segments.len(), 1);
        assert!(deviation(&points, &segments) <= 0.1);
    }

    #[test]
    fn wiggly_pixel_curve_stays_within_tolerance() {
        // A sine with pixel-rounded samples: noise forces splits; every point stays within tolerance.
        let points: Vec<Point> = (0..300)
            .map(|k| {
                let x = k as f64 * 0.7;
                [
                    x,
                    (50.0 + 20.0 * (x / 15.0).sin() + 3.0 * (x / 4.0).cos()).round() + 0.5,
                ]
            })
            .collect();
        for tolerance in [0.3, 0.5, 1.0] {
            let segments = fit_beziers(&points, tolerance, 60.0);
            assert!(joined(&segments));
            assert!(deviation(&points, &segments) <= tolerance + 1e-9);
            assert!(segments.len() < points.len() / 2);
        }
    }

    #[test]
    fn degenerate_input_gives_no_segment_and_no_panic() {
        assert!(fit_beziers(&[], 0.5, 60.0).is_empty());
        assert!(fit_beziers(&[[1.0, 1.0]], 0.5, 60.0).is_empty());
        assert!(fit_beziers(&[[1.0, 1.0], [1.0, 1.0], [f64::NAN, 2.0]], 0.5, 60.0).is_empty());
        let two = fit_beziers(&[[0.0, 0.0], [3.0, 4.0]], 0.0, 60.0);
        assert_eq!(two.len(), 1);
    }
}
