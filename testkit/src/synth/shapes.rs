//! The hard cases: the shapes where stroke extraction usually fails (shallow crossings, junctions
//! of many arms, loops with tails, near misses, thick-thin strokes, broken ink), each in an image
//! just big enough to hold it with a margin of at least two stroke widths.

use super::{dropout, frame, sample_curve, Case, Stroke};
use std::f64::consts::PI;

/// Default width of the single shapes, px.
const W: f64 = 5.0;

/// Truth curves are sampled at least this densely, px.
const SPACING: f64 = 1.0;

/// Unit vector at `degrees` (image coordinates: y down, so positive angles turn clockwise).
fn dir(degrees: f64) -> [f64; 2] {
    let a = degrees.to_radians();
    [a.cos(), a.sin()]
}

fn at(c: [f64; 2], d: [f64; 2], s: f64) -> [f64; 2] {
    [c[0] + d[0] * s, c[1] + d[1] * s]
}

/// Frames a hard case with a margin of two widths plus one pixel.
fn hard(name: String, strokes: Vec<Stroke>) -> Case {
    let w = strokes.iter().map(Stroke::max_width).fold(0.0, f64::max);
    frame(&name, "hard", strokes, 2.0 * w + 1.0)
}

/// A closed curve sampled over `[0, 2 pi]`, its first point repeated exactly at the end.
fn closed(f: impl Fn(f64) -> [f64; 2]) -> Vec<[f64; 2]> {
    let mut points = sample_curve(f, 0.0, 2.0 * PI, SPACING);
    if let Some(&first) = points.first() {
        if let Some(last) = points.last_mut() {
            *last = first;
        }
    }
    points
}

fn circle(c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    closed(|t| [c[0] + r * t.cos(), c[1] + r * t.sin()])
}

/// Every hard case (group `hard`), in a fixed order.
pub fn hard_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    // Centers on a pixel center, so axis-aligned strokes render symmetrically.
    let c = [0.5, 0.5];

    // X crossings: two long straight strokes crossing at their middles. The arms must be long
    // enough to separate (their ink parts where d sin(angle) > width), or there is no crossing
    // to see, so the half length grows as the angle closes.
    for angle in [15.0, 30.0, 45.0, 60.0, 90.0] {
        for w in [3.0f64, 5.0, 8.0, 14.0] {
            let half = (3.0 * w / f64::sin(f64::to_radians(angle))).max(40.0);
            let (d1, d2) = (dir(10.0), dir(10.0 + angle));
            let strokes = vec![
                Stroke::new(vec![at(c, d1, -half), at(c, d1, half)], w),
                Stroke::new(vec![at(c, d2, -half), at(c, d2, half)], w),
            ];
            cases.push(hard(format!("x{angle}_w{w}"), strokes));
        }
    }

    // Junctions: strokes meeting at one point.
    for w in [3.0f64, 8.0] {
        let a = (6.0 * w).max(30.0);
        // T: the stem starts on the bar's centerline.
        let t = vec![
            Stroke::new(vec![[c[0] - a, c[1]], [c[0] + a, c[1]]], w),
            Stroke::new(vec![c, [c[0], c[1] + 1.5 * a]], w),
        ];
        cases.push(hard(format!("t_w{w}"), t));
        // Y: written as upper-left arm down the stem, then the upper-right arm to the center.
        let y = vec![
            Stroke::new(vec![at(c, dir(-150.0), a), c, at(c, dir(90.0), a)], w),
            Stroke::new(vec![at(c, dir(-30.0), a), c], w),
        ];
        cases.push(hard(format!("y_w{w}"), y));
        // K: two arms leave the stem's middle.
        let k = vec![
            Stroke::new(vec![[c[0], c[1] - a], [c[0], c[1] + a]], w),
            Stroke::new(vec![at(c, dir(-50.0), a * 1.2), c], w),
            Stroke::new(vec![c, at(c, dir(50.0), a * 1.2)], w),
        ];
        cases.push(hard(format!("k_w{w}"), k));
        // Six-way star: three lines through one point.
        let star = (0..3)
            .map(|i| {
                let d = dir(15.0 + 60.0 * i as f64);
                Stroke::new(vec![at(c, d, -a), at(c, d, a)], w)
            })
            .collect();
        cases.push(hard(format!("star_w{w}"), star));
    }

    // '#': two horizontal and two vertical bars.
    let (s, g) = (45.0, 15.0);
    let hash = vec![
        Stroke::new(vec![[-s + c[0], -g + c[1]], [s + c[0], -g + c[1]]], W),
        Stroke::new(vec![[-s + c[0], g + c[1]], [s + c[0], g + c[1]]], W),
        Stroke::new(vec![[-g + c[0], -s + c[1]], [-g + c[0], s + c[1]]], W),
        Stroke::new(vec![[g + c[0], -s + c[1]], [g + c[0], s + c[1]]], W),
    ];
    cases.push(hard("hash".into(), hash));

    // A circle with a cross through it: four T-like meetings plus a crossing at the center.
    let r = 40.0;
    let ring = vec![
        Stroke::new(circle(c, r), W),
        Stroke::new(vec![[c[0] - 1.4 * r, c[1]], [c[0] + 1.4 * r, c[1]]], W),
        Stroke::new(vec![[c[0], c[1] - 1.4 * r], [c[0], c[1] + 1.4 * r]], W),
    ];
    cases.push(hard("circle".into(), ring));

    // 'e': the bar, then the bowl from the bar's right end up, around and out into a tail; the
    // bowl passes through the bar's left end.
    let r = 25.0;
    let mut e = vec![[c[0] - r, c[1]]];
    e.extend(sample_curve(
        |t| [c[0] + r * t.cos(), c[1] - r * t.sin()],
        0.0,
        310f64.to_radians(),
        SPACING,
    ));
    cases.push(hard("e_loop".into(), vec![Stroke::new(e, W)]));

    // Alpha: a nodal cubic, the loop on the left, its two tails crossing at 67 degrees.
    let s = 40.0;
    let alpha = sample_curve(
        |t| [c[0] - s * (1.0 - t * t), c[1] + 1.5 * s * t * (1.0 - t * t)],
        -1.3,
        1.3,
        SPACING,
    );
    cases.push(hard("alpha".into(), vec![Stroke::new(alpha, W)]));

    // Figure-8: one closed stroke crossing itself at right angles (lemniscate of Gerono).
    let a = 50.0;
    let eight = closed(|t| [c[0] + a * t.sin() * t.cos(), c[1] + a * t.sin()]);
    cases.push(hard("figure8".into(), vec![Stroke::new(eight, W)]));

    // Archimedean spiral r = b theta, turns 4 widths apart.
    let b = 4.0 * W / (2.0 * PI);
    let spiral = sample_curve(
        |t| [c[0] + b * t * t.cos(), c[1] + b * t * t.sin()],
        PI,
        5.0 * PI,
        SPACING,
    );
    cases.push(hard("spiral".into(), vec![Stroke::new(spiral, W)]));

    // Closed outlines with sharp corners; they start and end at a corner.
    let q = 80.0;
    let square = vec![
        c,
        [c[0] + q, c[1]],
        [c[0] + q, c[1] + q],
        [c[0], c[1] + q],
        c,
    ];
    cases.push(hard("square".into(), vec![Stroke::new(square, W)]));
    let q = 90.0;
    let triangle = vec![
        c,
        [c[0] + q, c[1]],
        [c[0] + q / 2.0, c[1] - q * 0.75f64.sqrt()],
        c,
    ];
    cases.push(hard("triangle".into(), vec![Stroke::new(triangle, W)]));

    // An acute V of 20 degrees: the arms share ink for about 3 widths from the apex.
    let l = 100.0;
    let v = vec![at(c, dir(-80.0), l), c, at(c, dir(-100.0), l)];
    cases.push(hard("v20".into(), vec![Stroke::new(v, W)]));

    // Two strokes that nearly touch: a stem ending 2 px of background below a bar (centerlines
    // on pixel centers, so the gap is exactly two pixel rows).
    let near = vec![
        Stroke::new(vec![[c[0] - 40.0, c[1]], [c[0] + 40.0, c[1]]], W),
        Stroke::new(vec![[c[0], c[1] + W + 2.0], [c[0], c[1] + 60.0]], W),
    ];
    cases.push(hard("near_touch".into(), near));

    // Parallel strokes with 2, 3 and 4 background rows between their ink.
    for gap in [2.0, 3.0, 4.0] {
        let d = W + gap;
        let strokes = (0..3)
            .map(|i| {
                let y = c[1] + d * i as f64;
                Stroke::new(vec![[c[0], y], [c[0] + 120.0, y]], W)
            })
            .collect();
        cases.push(hard(format!("parallel{gap}"), strokes));
    }

    // A stroke whose width grows threefold along a gentle arc.
    let points = sample_curve(
        |t| [c[0] + t, c[1] - 12.0 * (PI * t / 150.0).sin()],
        0.0,
        150.0,
        SPACING,
    );
    let widths = arc_fractions(&points)
        .iter()
        .map(|f| 3.0 + 6.0 * f)
        .collect();
    cases.push(hard("width3x".into(), vec![Stroke { points, widths }]));

    // Dropout on the middle third of a wavy stroke.
    for (percent, seed) in [(30u32, 30u64), (60, 60)] {
        let w = 7.0;
        let points = sample_curve(
            |t| [c[0] + t, c[1] + 12.0 * (2.0 * PI * t / 180.0).sin()],
            0.0,
            180.0,
            SPACING,
        );
        let mut case = hard(format!("dropout{percent}"), vec![Stroke::new(points, w)]);
        let x0 = case.strokes[0].points[0][0];
        let region = [
            (x0 + 60.0) as u32,
            0,
            (x0 + 120.0) as u32,
            case.binary.height,
        ];
        dropout(&mut case.binary, region, percent as f64 / 100.0, seed);
        cases.push(case);
    }

    // A line of solid text and, below it, a wavy stroke with 30% of its ink knocked out: dropout
    // mode belongs to the broken stroke only (docs/design.md, "The front end").
    {
        let w = 5.0;
        let mut strokes = super::text_line("line", "whom", 40.0, w).strokes;
        let bottom = strokes
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p[1]))
            .fold(0.0f64, f64::max);
        let wave = sample_curve(
            |t| [20.0 + t, bottom + 30.0 + 8.0 * (2.0 * PI * t / 120.0).sin()],
            0.0,
            160.0,
            SPACING,
        );
        strokes.push(Stroke::new(wave, 7.0));
        let mut case = hard("dropout_below_text".into(), strokes);
        let wave_top = case.strokes.last().map_or(0.0, |s| s.points[0][1]) - 14.0;
        let region = [0, wave_top as u32, case.binary.width, case.binary.height];
        dropout(&mut case.binary, region, 0.3, 40);
        cases.push(case);
    }

    // A gentle S curve.
    let s_curve = sample_curve(
        |t| [c[0] + 25.0 * (2.0 * PI * t / 120.0).sin(), c[1] + t],
        0.0,
        120.0,
        SPACING,
    );
    cases.push(hard("s_curve".into(), vec![Stroke::new(s_curve, W)]));

    // Several separate parts: a line, a ring, a V and an arc, well apart.
    let parts = vec![
        Stroke::new(vec![c, [c[0] + 50.0, c[1] + 20.0]], W),
        Stroke::new(circle([c[0] + 100.0, c[1] + 10.0], 18.0), W),
        Stroke::new(
            vec![
                [c[0] + 140.0, c[1] - 10.0],
                [c[0] + 155.0, c[1] + 25.0],
                [c[0] + 170.0, c[1] - 10.0],
            ],
            W,
        ),
        Stroke::new(
            sample_curve(
                |t| [c[0] + 60.0 + 30.0 * t.cos(), c[1] + 40.0 + 30.0 * t.sin()],
                0.3,
                2.8,
                SPACING,
            ),
            W,
        ),
    ];
    cases.push(hard("parts".into(), parts));
    cases
}

/// Arc length fraction (0 at the start, 1 at the end) at each point of a polyline.
fn arc_fractions(points: &[[f64; 2]]) -> Vec<f64> {
    let mut acc = vec![0.0];
    for s in points.windows(2) {
        let step = (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1]);
        acc.push(acc.last().copied().unwrap_or(0.0) + step);
    }
    let total = acc.last().copied().unwrap_or(0.0).max(f64::MIN_POSITIVE);
    acc.iter().map(|a| a / total).collect()
}
