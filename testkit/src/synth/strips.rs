//! Strip-shaped point sets, the paper's own input (§3, Figs. 1, 6, 8): random points drawn
//! uniformly in bands around known curves, with the truth as a graph of centerlines, junctions with
//! their degree, ends, components and cycles.
//!
//! A band is the set of points within half its local width of a centerline, measured along the
//! curve's normal; its ends are cut square at the curve's ends, so a true end is the curve's end.
//! Points are drawn with a density proportional to `density * width` per unit of length (uniform
//! per unit of area, times `density`), so a case's weights and widths may vary along a curve.

use super::rng::SplitMix64;

/// One centerline of a strip case: a polyline sampled finely, with the band's full width and the
/// relative sampling density at each point.
#[derive(Clone, Debug)]
pub struct StripCurve {
    /// Centerline points.
    pub points: Vec<[f64; 2]>,
    /// Full band width at each point (the truth the width output is measured against).
    pub widths: Vec<f64>,
    /// Relative point density per unit of area at each point.
    pub density: Vec<f64>,
}

/// A point-set case with its truth.
#[derive(Clone, Debug)]
pub struct StripCase {
    /// Unique name, e.g. `figure8`.
    pub name: String,
    /// The points (unorganized, in the order drawn).
    pub points: Vec<[f64; 2]>,
    /// The true centerlines.
    pub curves: Vec<StripCurve>,
    /// True junctions: position and degree.
    pub junctions: Vec<([f64; 2], usize)>,
    /// True ends.
    pub ends: Vec<[f64; 2]>,
    /// Connected components of the truth.
    pub components: usize,
    /// Independent cycles of the truth.
    pub cycles: usize,
    /// The band's typical full width (the unit of the scores).
    pub width: f64,
}

impl StripCase {
    /// The same case with every coordinate (points and truth) multiplied by `factor`.
    pub fn scaled(&self, name: &str, factor: f64) -> StripCase {
        let s = |p: [f64; 2]| [p[0] * factor, p[1] * factor];
        StripCase {
            name: name.to_string(),
            points: self.points.iter().map(|&p| s(p)).collect(),
            curves: self
                .curves
                .iter()
                .map(|c| StripCurve {
                    points: c.points.iter().map(|&p| s(p)).collect(),
                    widths: c.widths.iter().map(|w| w * factor).collect(),
                    density: c.density.clone(),
                })
                .collect(),
            junctions: self.junctions.iter().map(|&(p, d)| (s(p), d)).collect(),
            ends: self.ends.iter().map(|&p| s(p)).collect(),
            components: self.components,
            cycles: self.cycles,
            width: self.width * factor,
        }
    }
}

/// A curve `f(t)` for `t` in `[t0, t1]`, sampled at `n + 1` points, with constant width and
/// density.
fn curve(f: impl Fn(f64) -> [f64; 2], t0: f64, t1: f64, n: usize, width: f64) -> StripCurve {
    let points: Vec<[f64; 2]> = (0..=n)
        .map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64))
        .collect();
    StripCurve {
        widths: vec![width; points.len()],
        density: vec![1.0; points.len()],
        points,
    }
}

/// A straight segment from `a` to `b`.
fn segment(a: [f64; 2], b: [f64; 2], width: f64) -> StripCurve {
    let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / 2.0).ceil().max(1.0) as usize;
    curve(
        |t| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t],
        0.0,
        1.0,
        n,
        width,
    )
}

/// A circle of radius `r` around `c`, closed (first point repeated at the end).
fn circle(c: [f64; 2], r: f64, width: f64) -> StripCurve {
    let n = (r * std::f64::consts::TAU / 2.0).ceil() as usize;
    curve(
        |t| [c[0] + r * t.cos(), c[1] + r * t.sin()],
        0.0,
        std::f64::consts::TAU,
        n,
        width,
    )
}

/// Draws `count` points uniformly in the bands of `curves` (density-weighted).
fn draw_points(curves: &[StripCurve], count: usize, rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    // Cumulative weight of every piece: length x mean width x mean density.
    let mut pieces = Vec::new();
    let mut cumulative = Vec::new();
    let mut total = 0.0;
    for (c, curve) in curves.iter().enumerate() {
        for i in 1..curve.points.len() {
            let (a, b) = (curve.points[i - 1], curve.points[i]);
            let length = (b[0] - a[0]).hypot(b[1] - a[1]);
            let w = 0.5 * (curve.widths[i - 1] + curve.widths[i]);
            let d = 0.5 * (curve.density[i - 1] + curve.density[i]);
            total += length * w * d;
            pieces.push((c, i));
            cumulative.push(total);
        }
    }
    let mut points = Vec::with_capacity(count);
    while points.len() < count {
        let pick = rng.next_f64() * total;
        let k = cumulative
            .partition_point(|&x| x < pick)
            .min(pieces.len() - 1);
        let (c, i) = pieces[k];
        let curve = &curves[c];
        let (a, b) = (curve.points[i - 1], curve.points[i]);
        let t = rng.next_f64();
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        if length == 0.0 {
            continue;
        }
        let w = curve.widths[i - 1] + (curve.widths[i] - curve.widths[i - 1]) * t;
        let normal = [-(b[1] - a[1]) / length, (b[0] - a[0]) / length];
        let offset = rng.range(-0.5, 0.5) * w;
        points.push([
            a[0] + (b[0] - a[0]) * t + normal[0] * offset,
            a[1] + (b[1] - a[1]) * t + normal[1] * offset,
        ]);
    }
    points
}

/// Builds a case: `count` points in the bands of `curves`.
#[allow(clippy::too_many_arguments)]
fn case(
    name: &str,
    curves: Vec<StripCurve>,
    count: usize,
    junctions: Vec<([f64; 2], usize)>,
    ends: Vec<[f64; 2]>,
    components: usize,
    cycles: usize,
    seed: u64,
) -> StripCase {
    let mut rng = SplitMix64::new(seed);
    let points = draw_points(&curves, count, &mut rng);
    let width = curves.first().map_or(1.0, |c| c.widths[0]);
    StripCase {
        name: name.to_string(),
        points,
        curves,
        junctions,
        ends,
        components,
        cycles,
        width,
    }
}

/// Band width of the cases, in their units.
pub const STRIP_WIDTH: f64 = 8.0;

/// Points per unit of band area in the cases (the figure 8's 10,000 points over its band).
const DENSITY: f64 = 10_000.0 / (FIGURE8_LENGTH * STRIP_WIDTH);

/// Centerline length of the figure 8 ([`figure8`] with `a = 100`), to two decimals.
const FIGURE8_LENGTH: f64 = 609.72;

/// Points for a band of `length` x `width` at [`DENSITY`].
fn count_for(length: f64, width: f64) -> usize {
    (length * width * DENSITY).round() as usize
}

/// The figure 8 (lemniscate of Gerono, `x = a sin t`, `y = a sin t cos t`): one crossing at 90
/// degrees at the origin, two loops.
fn figure8(width: f64) -> StripCurve {
    curve(
        |t| [100.0 * t.sin(), 100.0 * t.sin() * t.cos()],
        0.0,
        std::f64::consts::TAU,
        1200,
        width,
    )
}

/// Two segments of length 240 crossing at their middles at `angle` degrees, widths `w1`, `w2`.
fn crossing(name: &str, angle: f64, w1: f64, w2: f64, seed: u64) -> StripCase {
    let (s, c) = angle.to_radians().sin_cos();
    let a = segment([-120.0, 0.0], [120.0, 0.0], w1);
    let b = segment([-120.0 * c, -120.0 * s], [120.0 * c, 120.0 * s], w2);
    case(
        name,
        vec![a, b],
        count_for(240.0, w1) + count_for(240.0, w2),
        vec![([0.0, 0.0], 4)],
        vec![
            [-120.0, 0.0],
            [120.0, 0.0],
            [-120.0 * c, -120.0 * s],
            [120.0 * c, 120.0 * s],
        ],
        1,
        0,
        seed,
    )
}

/// Segments of length 100 from the origin in `directions` (degrees).
fn star(name: &str, directions: &[f64], seed: u64) -> StripCase {
    let ends: Vec<[f64; 2]> = directions
        .iter()
        .map(|d| {
            let (s, c) = d.to_radians().sin_cos();
            [100.0 * c, 100.0 * s]
        })
        .collect();
    let curves = ends
        .iter()
        .map(|&e| segment([0.0, 0.0], e, STRIP_WIDTH))
        .collect();
    case(
        name,
        curves,
        count_for(100.0 * ends.len() as f64, STRIP_WIDTH),
        vec![([0.0, 0.0], ends.len())],
        ends,
        1,
        0,
        seed,
    )
}

/// The 2D strip cases: lines, circles, the figure 8 (10,000 points, band 8 wide), crossings at 20,
/// 45 and 90 degrees, crossing strips of widths 4 and 12, T, Y, a six-arm star, a spiral, parallel
/// strips one width apart, three parts, density falling tenfold along a strip, width growing
/// threefold, 2 % outliers, a sparse figure 8 (2,500 points) and the figure 8 scaled by 0.001 and
/// by 1000. Deterministic.
pub fn strip_cases() -> Vec<StripCase> {
    let w = STRIP_WIDTH;
    let mut cases = Vec::new();
    cases.push(case(
        "line",
        vec![segment([0.0, 0.0], [300.0, 0.0], w)],
        count_for(300.0, w),
        vec![],
        vec![[0.0, 0.0], [300.0, 0.0]],
        1,
        0,
        1,
    ));
    let r = 80.0;
    cases.push(case(
        "circle",
        vec![circle([0.0, 0.0], r, w)],
        count_for(std::f64::consts::TAU * r, w),
        vec![],
        vec![],
        1,
        1,
        2,
    ));
    let sine = curve(|t| [t, 40.0 * (t / 40.0).sin()], 0.0, 300.0, 600, w);
    let sine_length = polyline_length(&sine.points);
    cases.push(case(
        "sine",
        vec![sine],
        count_for(sine_length, w),
        vec![],
        vec![[0.0, 0.0], [300.0, 40.0 * (300.0f64 / 40.0).sin()]],
        1,
        0,
        3,
    ));
    let eight = || figure8(w);
    let figure8_case = case(
        "figure8",
        vec![eight()],
        10_000,
        vec![([0.0, 0.0], 4)],
        vec![],
        1,
        2,
        4,
    );
    cases.push(figure8_case.clone());
    cases.push(crossing("cross20", 20.0, w, w, 5));
    cases.push(crossing("cross45", 45.0, w, w, 6));
    cases.push(crossing("cross90", 90.0, w, w, 7));
    cases.push(crossing("cross_w4_w12", 90.0, 4.0, 12.0, 8));
    cases.push(case(
        "T",
        vec![
            segment([-100.0, 0.0], [100.0, 0.0], w),
            segment([0.0, 0.0], [0.0, -120.0], w),
        ],
        count_for(320.0, w),
        vec![([0.0, 0.0], 3)],
        vec![[-100.0, 0.0], [100.0, 0.0], [0.0, -120.0]],
        1,
        0,
        9,
    ));
    cases.push(star("Y", &[90.0, 210.0, 330.0], 10));
    cases.push(star("star6", &[0.0, 60.0, 120.0, 180.0, 240.0, 300.0], 11));
    // Archimedean spiral, turns 6 widths apart, three turns.
    let spiral = curve(
        |t| {
            let r = 20.0 + 6.0 * w * t / std::f64::consts::TAU;
            [r * t.cos(), r * t.sin()]
        },
        0.0,
        3.0 * std::f64::consts::TAU,
        2000,
        w,
    );
    let spiral_length = polyline_length(&spiral.points);
    let spiral_ends = vec![spiral.points[0], spiral.points[spiral.points.len() - 1]];
    cases.push(case(
        "spiral",
        vec![spiral],
        count_for(spiral_length, w),
        vec![],
        spiral_ends,
        1,
        0,
        12,
    ));
    // Two strips with a gap of one width between them.
    cases.push(case(
        "parallel",
        vec![
            segment([0.0, 0.0], [240.0, 0.0], w),
            segment([0.0, 2.0 * w], [240.0, 2.0 * w], w),
        ],
        count_for(480.0, w),
        vec![],
        vec![[0.0, 0.0], [240.0, 0.0], [0.0, 2.0 * w], [240.0, 2.0 * w]],
        2,
        0,
        13,
    ));
    cases.push(case(
        "three_parts",
        vec![
            segment([0.0, 0.0], [200.0, 0.0], w),
            circle([100.0, 100.0], 50.0, w),
            curve(
                |t| [250.0 + 60.0 * t.cos(), 100.0 + 60.0 * t.sin()],
                -1.2,
                1.2,
                200,
                w,
            ),
        ],
        count_for(200.0 + std::f64::consts::TAU * 50.0 + 2.4 * 60.0, w),
        vec![],
        vec![
            [0.0, 0.0],
            [200.0, 0.0],
            [
                250.0 + 60.0 * (-1.2f64).cos(),
                100.0 + 60.0 * (-1.2f64).sin(),
            ],
            [250.0 + 60.0 * 1.2f64.cos(), 100.0 + 60.0 * 1.2f64.sin()],
        ],
        3,
        1,
        14,
    ));
    // Density falling tenfold from one end to the other (the mean density is the others').
    let mut falling = segment([0.0, 0.0], [300.0, 0.0], w);
    let n = falling.points.len() - 1;
    falling.density = (0..=n)
        .map(|i| 10f64.powf(-(i as f64) / n as f64))
        .collect();
    let mean: f64 = falling.density.iter().sum::<f64>() / falling.density.len() as f64;
    cases.push(case(
        "density_falling",
        vec![falling],
        (count_for(300.0, w) as f64 * mean * 1.5) as usize,
        vec![],
        vec![[0.0, 0.0], [300.0, 0.0]],
        1,
        0,
        15,
    ));
    // Width growing threefold, 5 to 15.
    let mut growing = segment([0.0, 0.0], [300.0, 0.0], w);
    let n = growing.points.len() - 1;
    growing.widths = (0..=n).map(|i| 5.0 + 10.0 * i as f64 / n as f64).collect();
    cases.push(case(
        "width_growing",
        vec![growing],
        count_for(300.0, 10.0),
        vec![],
        vec![[0.0, 0.0], [300.0, 0.0]],
        1,
        0,
        16,
    ));
    // 2 % outliers, uniform over the figure 8's bounding box grown by 10 widths.
    let mut outliers = figure8_case.clone();
    outliers.name = "outliers2pct".to_string();
    let mut rng = SplitMix64::new(17);
    let extra = outliers.points.len() / 50;
    for _ in 0..extra {
        outliers
            .points
            .push([rng.range(-180.0, 180.0), rng.range(-130.0, 130.0)]);
    }
    cases.push(outliers);
    cases.push(case(
        "sparse_figure8",
        vec![eight()],
        2_500,
        vec![([0.0, 0.0], 4)],
        vec![],
        1,
        2,
        18,
    ));
    cases.push(figure8_case.scaled("figure8_x0.001", 0.001));
    cases.push(figure8_case.scaled("figure8_x1000", 1000.0));
    cases
}

/// A uniform cloud of `count` points in a square of side `side`: no strip at all.
pub fn uniform_cloud(count: usize, side: f64, seed: u64) -> Vec<[f64; 2]> {
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| [rng.range(0.0, side), rng.range(0.0, side)])
        .collect()
}

fn polyline_length(points: &[[f64; 2]]) -> f64 {
    points
        .windows(2)
        .map(|p| (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cases_are_deterministic_and_inside_their_bands() {
        let a = strip_cases();
        let b = strip_cases();
        assert_eq!(a.len(), 20);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.points, y.points);
        }
        let eight = a.iter().find(|c| c.name == "figure8").expect("figure8");
        assert_eq!(eight.points.len(), 10_000);
        // Every point lies within half a width (and a sampling step) of the centerline.
        for p in eight.points.iter().step_by(37) {
            let d = eight.curves[0]
                .points
                .iter()
                .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.5 * STRIP_WIDTH + 0.6, "{p:?} at {d}");
        }
        let length = polyline_length(&eight.curves[0].points);
        assert!((length - FIGURE8_LENGTH).abs() < 0.5, "{length}");
    }
}

/// One centerline of a tube case in space: a polyline sampled finely, with the tube's diameter.
#[derive(Clone, Debug)]
pub struct TubeCurve {
    /// Centerline points.
    pub points: Vec<[f64; 3]>,
    /// Tube diameter at each point (the truth the width output is measured against).
    pub widths: Vec<f64>,
}

/// A 3D point-set case (the paper's Fig. 7): random points filling tubes around known space
/// curves, with the truth.
#[derive(Clone, Debug)]
pub struct TubeCase {
    /// Unique name, e.g. `helix`.
    pub name: String,
    /// The points (unorganized, in the order drawn).
    pub points: Vec<[f64; 3]>,
    /// The true centerlines.
    pub curves: Vec<TubeCurve>,
    /// True junctions: position and degree.
    pub junctions: Vec<([f64; 3], usize)>,
    /// True ends.
    pub ends: Vec<[f64; 3]>,
    /// Connected components of the truth.
    pub components: usize,
    /// Independent cycles of the truth.
    pub cycles: usize,
    /// The tube's diameter (the unit of the scores).
    pub width: f64,
}

/// A space curve `f(t)` for `t` in `[t0, t1]`, sampled at `n + 1` points, of constant diameter.
fn tube(f: impl Fn(f64) -> [f64; 3], t0: f64, t1: f64, n: usize, width: f64) -> TubeCurve {
    let points: Vec<[f64; 3]> = (0..=n)
        .map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64))
        .collect();
    TubeCurve {
        widths: vec![width; points.len()],
        points,
    }
}

/// A straight tube from `a` to `b`.
fn tube_segment(a: [f64; 3], b: [f64; 3], width: f64) -> TubeCurve {
    tube(
        |t| {
            [
                a[0] + (b[0] - a[0]) * t,
                a[1] + (b[1] - a[1]) * t,
                a[2] + (b[2] - a[2]) * t,
            ]
        },
        0.0,
        1.0,
        64,
        width,
    )
}

fn length3(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
}

/// Draws `count` points uniformly in the solid tubes of `curves`: a piece chosen with probability
/// proportional to its volume, a point along it, and a point uniform in the disk of the tube's
/// cross-section there; the tubes are cut square at their ends.
fn draw_tube_points(curves: &[TubeCurve], count: usize, rng: &mut SplitMix64) -> Vec<[f64; 3]> {
    let mut pieces = Vec::new();
    let mut cumulative = Vec::new();
    let mut total = 0.0;
    for (c, curve) in curves.iter().enumerate() {
        for i in 1..curve.points.len() {
            let w = 0.5 * (curve.widths[i - 1] + curve.widths[i]);
            total += length3(curve.points[i - 1], curve.points[i]) * w * w;
            pieces.push((c, i));
            cumulative.push(total);
        }
    }
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let pick = rng.next_f64() * total;
        let k = cumulative
            .partition_point(|&c| c < pick)
            .min(pieces.len() - 1);
        let (c, i) = pieces[k];
        let curve = &curves[c];
        let (a, b) = (curve.points[i - 1], curve.points[i]);
        let t = rng.next_f64();
        let center = [
            a[0] + (b[0] - a[0]) * t,
            a[1] + (b[1] - a[1]) * t,
            a[2] + (b[2] - a[2]) * t,
        ];
        let width = curve.widths[i - 1] + (curve.widths[i] - curve.widths[i - 1]) * t;
        let l = length3(a, b).max(1e-12);
        let u = [(b[0] - a[0]) / l, (b[1] - a[1]) / l, (b[2] - a[2]) / l];
        // Two unit vectors across the tangent.
        let helper = if u[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let cross = |p: [f64; 3], q: [f64; 3]| {
            [
                p[1] * q[2] - p[2] * q[1],
                p[2] * q[0] - p[0] * q[2],
                p[0] * q[1] - p[1] * q[0],
            ]
        };
        let v = cross(u, helper);
        let vn = length3([0.0; 3], v);
        let v = [v[0] / vn, v[1] / vn, v[2] / vn];
        let n = cross(u, v);
        let radius = 0.5 * width * rng.next_f64().sqrt();
        let angle = rng.range(0.0, std::f64::consts::TAU);
        let (x, y) = (radius * angle.cos(), radius * angle.sin());
        out.push([
            center[0] + x * v[0] + y * n[0],
            center[1] + x * v[1] + y * n[1],
            center[2] + x * v[2] + y * n[2],
        ]);
    }
    out
}

/// The tube diameter of the 3D cases.
pub const TUBE_WIDTH: f64 = 8.0;

/// The 3D cases (the paper's Fig. 7): a helix, a trefoil knot (one closed tube, no junction), two
/// tubes crossing, a Y in space and two parallel tubes one diameter apart, each 8 units in
/// diameter and filled with random points about a tenth of the diameter apart (`Dis_ave` about 0.7).
pub fn tube_cases() -> Vec<TubeCase> {
    use std::f64::consts::{PI, TAU};
    let w = TUBE_WIDTH;
    let mut cases = Vec::new();
    let mut add = |name: &str,
                   curves: Vec<TubeCurve>,
                   junctions: Vec<([f64; 3], usize)>,
                   ends: Vec<[f64; 3]>,
                   components: usize,
                   cycles: usize,
                   seed: u64| {
        let volume: f64 = curves
            .iter()
            .map(|c| {
                c.points
                    .windows(2)
                    .map(|p| length3(p[0], p[1]))
                    .sum::<f64>()
                    * PI
                    * w
                    * w
                    / 4.0
            })
            .sum();
        // Half a point per cubic unit: neighbours about 0.7 units apart in tubes 8 wide.
        let count = (0.5 * volume) as usize;
        let mut rng = SplitMix64::new(seed);
        let points = draw_tube_points(&curves, count, &mut rng);
        cases.push(TubeCase {
            name: name.to_string(),
            points,
            curves,
            junctions,
            ends,
            components,
            cycles,
            width: w,
        });
    };
    let helix = tube(
        |t| [60.0 * t.cos(), 60.0 * t.sin(), 80.0 * t / TAU],
        0.0,
        2.0 * TAU,
        800,
        w,
    );
    let ends = vec![helix.points[0], helix.points[helix.points.len() - 1]];
    add("helix", vec![helix], vec![], ends, 1, 0, 31);
    let trefoil = tube(
        |t| {
            [
                20.0 * (t.sin() + 2.0 * (2.0 * t).sin()),
                20.0 * (t.cos() - 2.0 * (2.0 * t).cos()),
                -20.0 * (3.0 * t).sin(),
            ]
        },
        0.0,
        TAU,
        1200,
        w,
    );
    add("trefoil", vec![trefoil], vec![], vec![], 1, 1, 32);
    let (c60, s60) = ((PI / 3.0).cos(), (PI / 3.0).sin());
    let a = tube_segment([-60.0, 0.0, 0.0], [60.0, 0.0, 0.0], w);
    let b = tube_segment(
        [-60.0 * c60, -60.0 * s60, -20.0],
        [60.0 * c60, 60.0 * s60, 20.0],
        w,
    );
    let ends = vec![a.points[0], a.points[64], b.points[0], b.points[64]];
    add(
        "crossing_tubes",
        vec![a, b],
        vec![([0.0; 3], 4)],
        ends,
        1,
        0,
        33,
    );
    let arms: Vec<TubeCurve> = [0.0f64, TAU / 3.0, 2.0 * TAU / 3.0]
        .iter()
        .map(|&angle| tube_segment([0.0; 3], [60.0 * angle.cos(), 60.0 * angle.sin(), 25.0], w))
        .collect();
    let ends = arms.iter().map(|c| c.points[64]).collect();
    add("y_3d", arms, vec![([0.0; 3], 3)], ends, 1, 0, 34);
    let parallel: Vec<TubeCurve> = [0.0, 2.0 * w]
        .iter()
        .map(|&y| {
            tube(
                move |t| [t, y, 12.0 * (t / 25.0).sin()],
                -80.0,
                80.0,
                400,
                w,
            )
        })
        .collect();
    let ends = parallel
        .iter()
        .flat_map(|c| [c.points[0], c.points[c.points.len() - 1]])
        .collect();
    add("parallel_tubes", parallel, vec![], ends, 2, 0, 35);
    cases
}

/// `count` random points in a band [`STRIP_WIDTH`] wide around a sine wave whose length grows
/// with `count`, at the density of the plane's cases: the speed benchmark's strips of any size.
pub fn sine_strip(count: usize, seed: u64) -> Vec<[f64; 2]> {
    let w = STRIP_WIDTH;
    let length = count as f64 / (w * DENSITY);
    let n = (length / 2.0).ceil().max(2.0) as usize;
    let wave = curve(|t| [t, 40.0 * (t / 60.0).sin()], 0.0, length, n, w);
    let mut rng = SplitMix64::new(seed);
    draw_points(&[wave], count, &mut rng)
}

/// `count` random points filling a helix tube [`TUBE_WIDTH`] across, as many turns as the density
/// of the 3D cases asks: the speed benchmark's tubes of any size.
pub fn helix_tube(count: usize, seed: u64) -> Vec<[f64; 3]> {
    use std::f64::consts::{PI, TAU};
    let w = TUBE_WIDTH;
    let turn = (TAU * 60.0f64).hypot(80.0);
    let length = count as f64 / (0.5 * PI * w * w / 4.0);
    let turns = length / turn;
    let n = (length / 2.0).ceil().max(2.0) as usize;
    let helix = tube(
        |t| [60.0 * t.cos(), 60.0 * t.sin(), 80.0 * t / TAU],
        0.0,
        turns * TAU,
        n,
        w,
    );
    let mut rng = SplitMix64::new(seed);
    draw_tube_points(&[helix], count, &mut rng)
}
