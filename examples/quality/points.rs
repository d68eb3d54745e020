//! The point-set group: unorganized strip-shaped point sets, the paper's own input (§3), generated
//! by the test kit with known curves (`ridgeline_testkit::synth::strip_cases`) and traced with
//! `ridgeline::trace_points`, by default and with `Params::paper()`.
//!
//! Scores are in units of the strip's own width `w` (the truth's local full width), so the scaled
//! copies of a case score the same when the graph is the same, scaled:
//! - junctions: predicted vertices of degree 3 or more, matched one to one to true junctions
//!   within the case's largest width, their degree compared; ends (degree 1) alike;
//! - components and independent cycles of the predicted graph;
//! - exactly right: every true junction matched by one of the same degree, every true end matched,
//!   none left over, components and cycles exact;
//! - centerline F1 within a quarter of the local width (both curves sampled every `w / 20`);
//! - mean distance of the predicted centerline to the truth, in local widths;
//! - width: the median of the predicted widths over the median true width (1 is right).
//!
//! Beside them, what a user without a point-cloud tool does with a 2D set (`raster+thinning`):
//! rasterize it at its own point spacing (one pixel per spacing, the spacing `1 / sqrt(density)`
//! estimated as twice the median distance to the nearest other point, as for random points),
//! close the gaps between the points (a closing by a 5 x 5 square: gaps of up to two spacings;
//! at half the spacing or with a 3 x 3 closing it makes a mesh of every case), thin and extract the
//! pixel graph as the thinning baseline does, pruning terminal branches shorter than the stroke
//! width, and map the graph back to the set's units. There is no such baseline in space (no voxel
//! thinning here).

use std::time::Instant;

use image::Luma;
use imageproc::distance_transform::Norm;
use ridgeline::{Binary, GrayImage, Params, StrokeGraph};
use ridgeline_testkit::synth::{strip_cases, tube_cases, StripCase, TubeCase};
use serde::Serialize;

use crate::thinning;

/// One method on one point-set case.
#[derive(Serialize)]
pub struct PointOutcome {
    case: String,
    method: String,
    time_ms: f64,
    failure: Option<String>,
    true_junctions: Vec<usize>,
    predicted_junctions: Vec<usize>,
    junctions_right: bool,
    true_ends: usize,
    predicted_ends: usize,
    ends_right: bool,
    components: [usize; 2],
    cycles: [usize; 2],
    exactly_right: bool,
    f1: f64,
    mean_distance_widths: f64,
    width_ratio: f64,
    warnings: Vec<String>,
}

/// The methods compared.
const METHODS: [&str; 2] = ["ridgeline", "paper"];

/// The rasterize-and-thin baseline of the plane (module docs).
const RASTER: &str = "raster+thinning";

fn params(method: &str) -> Params {
    match method {
        "paper" => Params::paper(),
        _ => Params::default(),
    }
}

/// Runs the group, the plane's cases then those in space (one case when `only` names it), prints
/// their tables and returns the outcomes.
pub fn run(only: Option<&str>, verbose: bool) -> Vec<PointOutcome> {
    let mut outcomes = run_plane(only, verbose);
    outcomes.extend(run_3d(only, verbose));
    outcomes
}

/// The plane's cases.
fn run_plane(only: Option<&str>, verbose: bool) -> Vec<PointOutcome> {
    let cases: Vec<StripCase> = strip_cases()
        .into_iter()
        .filter(|c| only.is_none_or(|n| n == c.name))
        .collect();
    if cases.is_empty() {
        return Vec::new();
    }
    let started = Instant::now();
    let mut outcomes = Vec::new();
    for case in &cases {
        for method in METHODS {
            outcomes.push(run_one(case, method));
        }
        outcomes.push(run_raster(case));
    }
    println!("\n## points ({} cases)\n", cases.len());
    println!(
        "Random points in strips around known curves (band 8 units wide unless named); scores in \
         units of the local width w.\n"
    );
    print_tables(&outcomes, verbose);
    println!("\npoints: {:.1} s", started.elapsed().as_secs_f64());
    outcomes
}

fn run_one(case: &StripCase, method: &str) -> PointOutcome {
    let start = Instant::now();
    let result = ridgeline::trace_points(&case.points, &params(method));
    let time_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut outcome = run_one_empty(case, method);
    outcome.time_ms = time_ms;
    match result {
        Err(e) => outcome.failure = Some(e.to_string()),
        Ok(trace) => {
            outcome.warnings = trace.warnings.iter().map(|w| w.code.to_string()).collect();
            score(case, &trace.graph, &mut outcome);
        }
    }
    outcome
}

/// The outcome of `method` on `case` before it is scored.
fn run_one_empty(case: &StripCase, method: &str) -> PointOutcome {
    PointOutcome {
        case: case.name.clone(),
        method: method.to_string(),
        time_ms: 0.0,
        failure: None,
        true_junctions: case.junctions.iter().map(|j| j.1).collect(),
        predicted_junctions: Vec::new(),
        junctions_right: false,
        true_ends: case.ends.len(),
        predicted_ends: 0,
        ends_right: false,
        components: [case.components, 0],
        cycles: [case.cycles, 0],
        exactly_right: false,
        f1: 0.0,
        mean_distance_widths: f64::NAN,
        width_ratio: f64::NAN,
        warnings: Vec::new(),
    }
}

/// The rasterize-and-thin baseline on one case (module docs).
fn run_raster(case: &StripCase) -> PointOutcome {
    let start = Instant::now();
    let graph = raster_thinning(&case.points);
    let mut outcome = run_one_empty(case, RASTER);
    outcome.time_ms = start.elapsed().as_secs_f64() * 1e3;
    score(case, &graph, &mut outcome);
    outcome
}

/// Rasterizes `points` at their own spacing, closes the gaps, thins, prunes and maps the graph
/// back to the points' units.
fn raster_thinning(points: &[[f64; 2]]) -> StrokeGraph {
    let Some(nearest) = nearest_spacing(points) else {
        return StrokeGraph::default();
    };
    let spacing = 2.0 * nearest;
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // A margin of three pixels keeps the closing off the image's edge.
    let pad = 3.0;
    let side = |k: usize| ((hi[k] - lo[k]) / spacing).floor() as u32 + 1 + 2 * pad as u32;
    let (width, height) = (side(0), side(1));
    if u64::from(width) * u64::from(height) > 64_000_000 {
        return StrokeGraph::default();
    }
    let mut binary = Binary::new(width, height);
    for p in points {
        let x = ((p[0] - lo[0]) / spacing).floor() + pad;
        let y = ((p[1] - lo[1]) / spacing).floor() + pad;
        binary.set(x as i64, y as i64, true);
    }
    // The closing by a 5 x 5 square: imageproc's, on the mask as a gray image.
    let image = GrayImage::from_fn(width, height, |x, y| {
        Luma([if binary.get(x.into(), y.into()) {
            255
        } else {
            0
        }])
    });
    let image = imageproc::morphology::close(&image, Norm::LInf, 2);
    let mut closed = Binary::new(width, height);
    for (x, y, pixel) in image.enumerate_pixels() {
        closed.set(x.into(), y.into(), pixel[0] > 0);
    }
    let mut graph = thinning::trace_pruned(&closed);
    let to_units = |q: [f64; 2]| {
        [
            lo[0] + (q[0] - pad) * spacing,
            lo[1] + (q[1] - pad) * spacing,
        ]
    };
    for v in &mut graph.vertices {
        v.pos = to_units(v.pos);
        v.width *= spacing;
    }
    for e in &mut graph.edges {
        for q in &mut e.points {
            *q = to_units(*q);
        }
        for w in &mut e.widths {
            *w *= spacing;
        }
    }
    graph
}

/// The median distance from a point to its nearest other point (None for fewer than two distinct
/// points), found through a grid of cells about one spacing wide.
fn nearest_spacing(points: &[[f64; 2]]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let area = ((hi[0] - lo[0]) * (hi[1] - lo[1])).max(f64::MIN_POSITIVE);
    let cell = (area / points.len() as f64).sqrt().max(1e-12);
    let cols = ((hi[0] - lo[0]) / cell) as usize + 1;
    let key = |p: [f64; 2]| {
        (
            ((p[0] - lo[0]) / cell) as usize,
            ((p[1] - lo[1]) / cell) as usize,
        )
    };
    let mut grid: std::collections::HashMap<usize, Vec<usize>> = Default::default();
    for (i, &p) in points.iter().enumerate() {
        let (cx, cy) = key(p);
        grid.entry(cy * cols + cx).or_default().push(i);
    }
    let mut nearest = Vec::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        let (cx, cy) = key(p);
        // Widen the search ring until a neighbour is found and the ring is past it.
        let mut best = f64::INFINITY;
        for ring in 1usize.. {
            for y in cy.saturating_sub(ring)..=cy + ring {
                for x in cx.saturating_sub(ring)..=(cx + ring).min(cols - 1) {
                    for &j in grid.get(&(y * cols + x)).into_iter().flatten() {
                        let d = (points[j][0] - p[0]).hypot(points[j][1] - p[1]);
                        if j != i && d > 0.0 {
                            best = best.min(d);
                        }
                    }
                }
            }
            if best <= (ring as f64) * cell || ring > cols.max(points.len()) {
                break;
            }
        }
        if best.is_finite() {
            nearest.push(best);
        }
    }
    nearest.sort_by(f64::total_cmp);
    nearest.get(nearest.len() / 2).copied()
}

/// A centerline sampled every `step`: positions, and for the truth the local width.
fn resample(points: &[[f64; 2]], widths: &[f64], step: f64, out: &mut Vec<([f64; 2], f64)>) {
    for i in 1..points.len() {
        let (a, b) = (points[i - 1], points[i]);
        let length = ridgeline::dist(a, b);
        let n = (length / step).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            let w = widths.get(i - 1).copied().unwrap_or(0.0) * (1.0 - t)
                + widths.get(i).copied().unwrap_or(0.0) * t;
            out.push(([a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t], w));
        }
    }
    if let Some(&last) = points.last() {
        out.push((last, widths.last().copied().unwrap_or(0.0)));
    }
}

/// Index of the nearest of `targets` to `p` and its distance (brute force; the sets are small).
fn nearest(p: [f64; 2], targets: &[([f64; 2], f64)]) -> (usize, f64) {
    let mut best = (0, f64::INFINITY);
    for (i, t) in targets.iter().enumerate() {
        let d = ridgeline::dist(p, t.0);
        if d < best.1 {
            best = (i, d);
        }
    }
    best
}

/// Matches `predicted` to `truth` one to one within `radius`, closest pairs first; returns the
/// pairs (truth index, predicted index).
fn match_points(truth: &[[f64; 2]], predicted: &[[f64; 2]], radius: f64) -> Vec<(usize, usize)> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, t) in truth.iter().enumerate() {
        for (j, p) in predicted.iter().enumerate() {
            let d = ridgeline::dist(*t, *p);
            if d <= radius {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut used_t, mut used_p) = (vec![false; truth.len()], vec![false; predicted.len()]);
    let mut matched = Vec::new();
    for (_, i, j) in pairs {
        if !used_t[i] && !used_p[j] {
            used_t[i] = true;
            used_p[j] = true;
            matched.push((i, j));
        }
    }
    matched
}

fn score(case: &StripCase, graph: &StrokeGraph, o: &mut PointOutcome) {
    let radius = case
        .curves
        .iter()
        .flat_map(|c| c.widths.iter().copied())
        .fold(case.width, f64::max);
    // Junctions.
    let junctions: Vec<usize> = graph.junctions().collect();
    let predicted: Vec<[f64; 2]> = junctions.iter().map(|&v| graph.vertices[v].pos).collect();
    let truth: Vec<[f64; 2]> = case.junctions.iter().map(|j| j.0).collect();
    let matched = match_points(&truth, &predicted, radius);
    o.predicted_junctions = junctions
        .iter()
        .map(|&v| graph.vertices[v].degree)
        .collect();
    o.junctions_right = matched.len() == truth.len()
        && predicted.len() == truth.len()
        && matched
            .iter()
            .all(|&(i, j)| case.junctions[i].1 == graph.vertices[junctions[j]].degree);
    // Ends.
    let ends: Vec<[f64; 2]> = graph.endpoints().map(|v| graph.vertices[v].pos).collect();
    o.predicted_ends = ends.len();
    let matched = match_points(&case.ends, &ends, radius);
    o.ends_right = matched.len() == case.ends.len() && ends.len() == case.ends.len();
    o.components[1] = graph.components();
    o.cycles[1] = graph.cycles();
    o.exactly_right = o.junctions_right
        && o.ends_right
        && o.components[0] == o.components[1]
        && o.cycles[0] == o.cycles[1];
    // Centerlines.
    let step = case.width / 20.0;
    let mut truth_samples = Vec::new();
    for c in &case.curves {
        resample(&c.points, &c.widths, step, &mut truth_samples);
    }
    let mut predicted_samples = Vec::new();
    for e in &graph.edges {
        resample(&e.points, &e.widths, step, &mut predicted_samples);
    }
    if predicted_samples.is_empty() {
        return;
    }
    let mut close = 0;
    let mut distance = 0.0;
    let mut ratios = Vec::new();
    for &(p, w) in &predicted_samples {
        let (i, d) = nearest(p, &truth_samples);
        let local = truth_samples[i].1;
        if d <= 0.25 * local {
            close += 1;
            ratios.push(w / local);
        }
        distance += d / local;
    }
    let precision = close as f64 / predicted_samples.len() as f64;
    let found = truth_samples
        .iter()
        .filter(|&&(t, w)| nearest(t, &predicted_samples).1 <= 0.25 * w)
        .count();
    let recall = found as f64 / truth_samples.len().max(1) as f64;
    o.f1 = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    o.mean_distance_widths = distance / predicted_samples.len() as f64;
    ratios.sort_by(f64::total_cmp);
    o.width_ratio = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
}

/// The 3D cases (`ridgeline_testkit::synth::tube_cases`), traced with `ridgeline::trace_points3d`
/// by default and with the paper's preset, scored as the plane's cases are: junctions and ends
/// matched within the tube's diameter, F1 within a quarter diameter, mean distance in diameters,
/// width: the median predicted diameter over the true one.
fn run_3d(only: Option<&str>, verbose: bool) -> Vec<PointOutcome> {
    let cases: Vec<TubeCase> = tube_cases()
        .into_iter()
        .filter(|c| only.is_none_or(|n| n == format!("3d_{}", c.name)))
        .collect();
    if cases.is_empty() {
        return Vec::new();
    }
    let started = Instant::now();
    let mut outcomes = Vec::new();
    for case in &cases {
        for method in METHODS {
            outcomes.push(run_one_3d(case, method));
        }
    }
    println!("\n## points in space ({} cases)\n", cases.len());
    println!(
        "Random points filling tubes 8 units in diameter around known space curves; scores in \
         diameters.\n"
    );
    print_tables(&outcomes, verbose);
    println!(
        "\npoints in space: {:.1} s",
        started.elapsed().as_secs_f64()
    );
    outcomes
}

fn run_one_3d(case: &TubeCase, method: &str) -> PointOutcome {
    let start = Instant::now();
    let result = ridgeline::trace_points3d(&case.points, &params(method));
    let time_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut o = PointOutcome {
        case: format!("3d_{}", case.name),
        method: method.to_string(),
        time_ms,
        failure: None,
        true_junctions: case.junctions.iter().map(|j| j.1).collect(),
        predicted_junctions: Vec::new(),
        junctions_right: false,
        true_ends: case.ends.len(),
        predicted_ends: 0,
        ends_right: false,
        components: [case.components, 0],
        cycles: [case.cycles, 0],
        exactly_right: false,
        f1: 0.0,
        mean_distance_widths: f64::NAN,
        width_ratio: f64::NAN,
        warnings: Vec::new(),
    };
    let trace = match result {
        Err(e) => {
            o.failure = Some(e.to_string());
            return o;
        }
        Ok(trace) => trace,
    };
    o.warnings = trace.warnings.iter().map(|w| w.code.to_string()).collect();
    let graph = &trace.graph;
    let radius = case.width;
    let junctions: Vec<usize> = graph.junctions().collect();
    let predicted: Vec<[f64; 3]> = junctions.iter().map(|&v| graph.vertices[v].pos).collect();
    let truth: Vec<[f64; 3]> = case.junctions.iter().map(|j| j.0).collect();
    let matched = match_points3(&truth, &predicted, radius);
    o.predicted_junctions = junctions
        .iter()
        .map(|&v| graph.vertices[v].degree)
        .collect();
    o.junctions_right = matched.len() == truth.len()
        && predicted.len() == truth.len()
        && matched
            .iter()
            .all(|&(i, j)| case.junctions[i].1 == graph.vertices[junctions[j]].degree);
    let ends: Vec<[f64; 3]> = graph.endpoints().map(|v| graph.vertices[v].pos).collect();
    o.predicted_ends = ends.len();
    let matched = match_points3(&case.ends, &ends, radius);
    o.ends_right = matched.len() == case.ends.len() && ends.len() == case.ends.len();
    o.components[1] = graph.components();
    o.cycles[1] = graph.cycles();
    o.exactly_right = o.junctions_right
        && o.ends_right
        && o.components[0] == o.components[1]
        && o.cycles[0] == o.cycles[1];
    let step = case.width / 20.0;
    let mut truth_samples = Vec::new();
    for c in &case.curves {
        resample3(&c.points, &c.widths, step, &mut truth_samples);
    }
    let mut predicted_samples = Vec::new();
    for e in &graph.edges {
        resample3(&e.points, &e.widths, step, &mut predicted_samples);
    }
    if predicted_samples.is_empty() {
        return o;
    }
    let truth_points: Vec<[f64; 3]> = truth_samples.iter().map(|s| s.0).collect();
    let predicted_points: Vec<[f64; 3]> = predicted_samples.iter().map(|s| s.0).collect();
    let mut close = 0;
    let mut distance = 0.0;
    let mut ratios = Vec::new();
    for &(p, w) in &predicted_samples {
        let (i, d) = nearest3(p, &truth_points);
        let local = truth_samples[i].1;
        if d <= 0.25 * local {
            close += 1;
            ratios.push(w / local);
        }
        distance += d / local;
    }
    let precision = close as f64 / predicted_samples.len() as f64;
    let found = truth_samples
        .iter()
        .filter(|&&(t, w)| nearest3(t, &predicted_points).1 <= 0.25 * w)
        .count();
    let recall = found as f64 / truth_samples.len().max(1) as f64;
    o.f1 = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    o.mean_distance_widths = distance / predicted_samples.len() as f64;
    ratios.sort_by(f64::total_cmp);
    o.width_ratio = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    o
}

fn resample3(points: &[[f64; 3]], widths: &[f64], step: f64, out: &mut Vec<([f64; 3], f64)>) {
    for i in 1..points.len() {
        let (a, b) = (points[i - 1], points[i]);
        let n = (ridgeline::dist3(a, b) / step).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            let w = widths[i - 1] * (1.0 - t) + widths[i] * t;
            out.push((
                [
                    a[0] + (b[0] - a[0]) * t,
                    a[1] + (b[1] - a[1]) * t,
                    a[2] + (b[2] - a[2]) * t,
                ],
                w,
            ));
        }
    }
    if let (Some(&last), Some(&w)) = (points.last(), widths.last()) {
        out.push((last, w));
    }
}

/// Index of the nearest of `targets` to `p` and its distance (brute force; the sets are small).
fn nearest3(p: [f64; 3], targets: &[[f64; 3]]) -> (usize, f64) {
    let mut best = (0, f64::INFINITY);
    for (i, &t) in targets.iter().enumerate() {
        let d = ridgeline::dist3(p, t);
        if d < best.1 {
            best = (i, d);
        }
    }
    best
}

fn match_points3(truth: &[[f64; 3]], predicted: &[[f64; 3]], radius: f64) -> Vec<(usize, usize)> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, &t) in truth.iter().enumerate() {
        for (j, &p) in predicted.iter().enumerate() {
            let d = ridgeline::dist3(t, p);
            if d <= radius {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut used_t, mut used_p) = (vec![false; truth.len()], vec![false; predicted.len()]);
    let mut matched = Vec::new();
    for (_, i, j) in pairs {
        if !used_t[i] && !used_p[j] {
            used_t[i] = true;
            used_p[j] = true;
            matched.push((i, j));
        }
    }
    matched
}

/// The group's summary table per method and, with `verbose`, one row per case.
fn print_tables(outcomes: &[PointOutcome], verbose: bool) {
    println!(
        "| method | exactly right | junctions right | ends right | components | cycles | F1 @ w/4 | mean dist / w | width ratio | mean time ms | warned |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for method in METHODS.into_iter().chain([RASTER]) {
        let mine: Vec<&PointOutcome> = outcomes.iter().filter(|o| o.method == method).collect();
        let n = mine.len();
        if n == 0 {
            continue;
        }
        let count = |f: &dyn Fn(&PointOutcome) -> bool| mine.iter().filter(|o| f(o)).count();
        let mean = |f: &dyn Fn(&PointOutcome) -> f64| {
            let v: Vec<f64> = mine
                .iter()
                .filter(|o| o.failure.is_none())
                .map(|o| f(o))
                .filter(|x| x.is_finite())
                .collect();
            v.iter().sum::<f64>() / v.len().max(1) as f64
        };
        println!(
            "| {method} | {}/{n} | {}/{n} | {}/{n} | {}/{n} | {}/{n} | {:.3} | {:.3} | {:.2} | {:.1} | {}/{n} |",
            count(&|o| o.exactly_right),
            count(&|o| o.junctions_right),
            count(&|o| o.ends_right),
            count(&|o| o.components[0] == o.components[1]),
            count(&|o| o.cycles[0] == o.cycles[1]),
            mean(&|o| o.f1),
            mean(&|o| o.mean_distance_widths),
            mean(&|o| o.width_ratio),
            mean(&|o| o.time_ms),
            count(&|o| !o.warnings.is_empty()),
        );
    }
    if verbose {
        println!(
            "\n| case | method | exact | junctions (true / predicted degrees) | ends t/p | comp t/p | cycles t/p | F1 | dist/w | width | ms | warnings |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
        for o in outcomes {
            if let Some(f) = &o.failure {
                println!("| {} | {} | failed: {f} |", o.case, o.method);
                continue;
            }
            let degrees = |d: &[usize]| {
                if d.len() > 6 {
                    format!("{} junctions", d.len())
                } else {
                    format!("{d:?}")
                }
            };
            println!(
                "| {} | {} | {} | {} / {} | {}/{} | {}/{} | {}/{} | {:.3} | {:.3} | {:.2} | {:.1} | {} |",
                o.case,
                o.method,
                if o.exactly_right { "yes" } else { "no" },
                degrees(&o.true_junctions),
                degrees(&o.predicted_junctions),
                o.true_ends,
                o.predicted_ends,
                o.components[0],
                o.components[1],
                o.cycles[0],
                o.cycles[1],
                o.f1,
                o.mean_distance_widths,
                o.width_ratio,
                o.time_ms,
                o.warnings.join(" "),
            );
        }
    }
}
