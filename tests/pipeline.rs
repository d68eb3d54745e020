//! End-to-end: render known centerlines thickly, trace, and compare topology and geometry with the
//! truth. Nothing here is special-cased in the pipeline: the shapes are only drawn here.

use ridgeline::geometry::segment_dist;
use ridgeline::{trace_binary, Binary, Params, StrokeGraph};
use ridgeline_testkit::synth::{render, Stroke};

fn line(a: [f64; 2], b: [f64; 2], width: f64) -> Stroke {
    Stroke::new(vec![a, b], width)
}

/// A stroke through `center` at `angle_deg`, `half_length` each way.
fn through(center: [f64; 2], angle_deg: f64, half_length: f64, width: f64) -> Stroke {
    let (s, c) = angle_deg.to_radians().sin_cos();
    line(
        [center[0] - half_length * c, center[1] - half_length * s],
        [center[0] + half_length * c, center[1] + half_length * s],
        width,
    )
}

fn circle(center: [f64; 2], radius: f64, width: f64) -> Stroke {
    let n = (radius * 2.0 * std::f64::consts::PI).ceil() as usize;
    let points = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64 * 2.0 * std::f64::consts::PI;
            [center[0] + radius * t.cos(), center[1] + radius * t.sin()]
        })
        .collect();
    Stroke::new(points, width)
}

fn trace(binary: &Binary) -> StrokeGraph {
    let trace = trace_binary(binary, &Params::default()).expect("trace succeeds");
    trace.graph.validate().expect("stroke graph is valid");
    trace.graph
}

fn degrees(graph: &StrokeGraph) -> Vec<usize> {
    let mut d: Vec<usize> = graph.vertices.iter().map(|v| v.degree).collect();
    d.sort_unstable();
    d
}

/// Distance from `p` to the nearest point of the truth polylines.
fn distance_to_truth(p: [f64; 2], strokes: &[Stroke]) -> f64 {
    let mut best = f64::INFINITY;
    for s in strokes {
        for w in s.points.windows(2) {
            best = best.min(segment_dist(p, w[0], w[1]));
        }
        if s.points.len() == 1 {
            best = best.min(ridgeline::dist(p, s.points[0]));
        }
    }
    best
}

fn distance_to_graph(p: [f64; 2], graph: &StrokeGraph) -> f64 {
    let mut best = f64::INFINITY;
    for e in &graph.edges {
        for w in e.points.windows(2) {
            best = best.min(segment_dist(p, w[0], w[1]));
        }
    }
    for v in &graph.vertices {
        best = best.min(ridgeline::dist(p, v.pos));
    }
    best
}

/// Every output point within `max(2, w/2)` of the truth, and every truth point (sampled every
/// 0.5 px) within the same bound of the output.
fn assert_geometry(graph: &StrokeGraph, strokes: &[Stroke]) {
    let max_width = strokes
        .iter()
        .flat_map(|s| s.widths.iter().copied())
        .fold(0.0, f64::max);
    let bound = (max_width / 2.0).max(2.0);
    for e in &graph.edges {
        for w in e.points.windows(2) {
            for k in 0..=4 {
                let t = k as f64 / 4.0;
                let p = [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ];
                let d = distance_to_truth(p, strokes);
                assert!(
                    d <= bound,
                    "output point {p:?} is {d:.2} px from the truth (bound {bound})"
                );
            }
        }
    }
    for s in strokes {
        for w in s.points.windows(2) {
            let steps = (ridgeline::dist(w[0], w[1]) / 0.5).ceil().max(1.0) as usize;
            for k in 0..=steps {
                let t = k as f64 / steps as f64;
                let p = [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ];
                let d = distance_to_graph(p, graph);
                assert!(
                    d <= bound,
                    "truth point {p:?} is {d:.2} px from the output (bound {bound})"
                );
            }
        }
    }
}

fn check_x(angle: f64, width: f64) {
    let c = [100.0, 100.0];
    let strokes = [
        through(c, 90.0 - angle / 2.0, 80.0, width),
        through(c, 90.0 + angle / 2.0, 80.0, width),
    ];
    let graph = trace(&render(&strokes, 200, 200));
    assert_eq!(
        degrees(&graph),
        vec![1, 1, 1, 1, 4],
        "X at {angle} deg, width {width}"
    );
    let crossing = graph.junctions().next().expect("one crossing");
    let error = ridgeline::dist(graph.vertices[crossing].pos, c);
    assert!(error <= width.max(2.0), "crossing placed {error:.1} px off");
    assert_geometry(&graph, &strokes);
}

#[test]
fn x_crossing_at_90_degrees_is_one_vertex_of_degree_4() {
    for width in [3.0, 5.0, 8.0] {
        check_x(90.0, width);
    }
}

#[test]
fn x_crossing_at_45_degrees_is_one_vertex_of_degree_4() {
    for width in [3.0, 5.0, 8.0] {
        check_x(45.0, width);
    }
}

#[test]
fn x_crossing_at_30_degrees_is_one_vertex_of_degree_4() {
    for width in [3.0, 5.0, 8.0] {
        check_x(30.0, width);
    }
}

#[test]
fn t_junction_is_one_vertex_of_degree_3() {
    for width in [3.0, 6.0] {
        let strokes = [
            line([20.0, 30.0], [140.0, 30.0], width),
            line([80.0, 30.0], [80.0, 130.0], width),
        ];
        let graph = trace(&render(&strokes, 160, 150));
        assert_eq!(degrees(&graph), vec![1, 1, 1, 3], "T at width {width}");
        assert_geometry(&graph, &strokes);
    }
}

#[test]
fn y_junction_is_one_vertex_of_degree_3() {
    for width in [3.0, 6.0] {
        let c = [80.0, 70.0];
        let strokes = [
            line(c, [80.0, 140.0], width),
            line(c, [30.0, 20.0], width),
            line(c, [130.0, 20.0], width),
        ];
        let graph = trace(&render(&strokes, 160, 160));
        assert_eq!(degrees(&graph), vec![1, 1, 1, 3], "Y at width {width}");
        assert_geometry(&graph, &strokes);
    }
}

#[test]
fn circle_is_one_cycle_without_endpoints() {
    for width in [3.0, 7.0] {
        let strokes = [circle([70.0, 70.0], 45.0, width)];
        let graph = trace(&render(&strokes, 140, 140));
        assert_eq!(graph.endpoints().count(), 0);
        assert_eq!(graph.junctions().count(), 0);
        assert_eq!(graph.components(), 1);
        assert_eq!(graph.cycles(), 1);
        assert_geometry(&graph, &strokes);
    }
}

#[test]
fn figure_8_is_one_crossing_and_two_cycles() {
    // A lemniscate of Gerono-like closed curve crossing itself once at the center.
    let n = 400;
    let points: Vec<[f64; 2]> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64 * 2.0 * std::f64::consts::PI;
            [90.0 + 45.0 * (2.0 * t).sin(), 110.0 + 90.0 * t.sin() * 0.9]
        })
        .collect();
    let strokes = [Stroke::new(points, 5.0)];
    let graph = trace(&render(&strokes, 180, 220));
    assert_eq!(degrees(&graph), vec![4], "figure 8");
    assert_eq!(graph.cycles(), 2);
    assert_geometry(&graph, &strokes);
}

#[test]
fn parallel_strokes_3_px_apart_stay_two_components() {
    let width = 5.0;
    let gap = 3.0;
    let strokes = [
        line([20.0, 40.0], [180.0, 40.0], width),
        line(
            [20.0, 40.0 + width + gap],
            [180.0, 40.0 + width + gap],
            width,
        ),
    ];
    let binary = render(&strokes, 200, 90);
    let graph = trace(&binary);
    assert_eq!(graph.components(), 2);
    assert_eq!(degrees(&graph), vec![1, 1, 1, 1]);
    assert_geometry(&graph, &strokes);
}

#[test]
fn stroke_whose_width_grows_3x_is_one_edge() {
    let points: Vec<[f64; 2]> = (0..=40).map(|i| [20.0 + 4.0 * i as f64, 50.0]).collect();
    let widths = (0..=40).map(|i| 4.0 + 8.0 * i as f64 / 40.0).collect();
    let strokes = [Stroke { points, widths }];
    let graph = trace(&render(&strokes, 200, 100));
    assert_eq!(degrees(&graph), vec![1, 1]);
    assert_geometry(&graph, &strokes);
}

#[test]
fn stroke_with_30_percent_dropout_is_still_one_stroke() {
    let strokes = [line([20.0, 40.0], [220.0, 60.0], 6.0)];
    let mut binary = render(&strokes, 240, 100);
    // Deterministic 30% dropout over the whole stroke (SplitMix64).
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for pixel in binary.ink.iter_mut() {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        if *pixel && (z % 100) < 30 {
            *pixel = false;
        }
    }
    let graph = trace(&binary);
    assert_eq!(graph.components(), 1, "one component");
    assert_eq!(graph.endpoints().count(), 2, "two ends, no spurs");
    assert_eq!(graph.junctions().count(), 0);
    assert_geometry(&graph, &strokes);
}

#[test]
fn a_drawing_of_1px_lines_is_not_read_as_broken_ink() {
    // Already-thinned line art: four horizontal and four vertical lines one pixel wide, 4 px
    // apart (3x3 holes). Each line end hangs on by a single neighbour, 16 of the 160 ink pixels:
    // line ends, not the specks of dropout, so the drawing keeps the 8-neighbourhood and the
    // skeleton, every hole a cycle and every line on its ink.
    let mut binary = Binary::new(30, 30);
    for k in 0..4 {
        for t in 4..26 {
            binary.set(7 + 4 * k, t, true);
            binary.set(t, 7 + 4 * k, true);
        }
    }
    let trace = trace_binary(&binary, &Params::default()).expect("trace succeeds");
    assert_eq!(trace.dropout(), Some(false));
    let graph = trace.graph;
    graph.validate().expect("stroke graph is valid");
    assert_eq!(graph.junctions().count(), 16);
    assert_eq!(graph.endpoints().count(), 16);
    assert_eq!(graph.cycles(), 9);
    for e in &graph.edges {
        for w in e.points.windows(2) {
            for k in 0..=8 {
                let t = f64::from(k) / 8.0;
                let p = [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ];
                let on_ink = (0..4).any(|k| {
                    let c = 7.5 + 4.0 * f64::from(k);
                    (p[0] - c).abs() <= 0.5 || (p[1] - c).abs() <= 0.5
                });
                assert!(on_ink, "{p:?} is off the ink");
            }
        }
    }
}

#[test]
fn separate_parts_are_separate_components() {
    let strokes = [
        line([20.0, 20.0], [100.0, 20.0], 4.0),
        circle([60.0, 90.0], 25.0, 4.0),
        through([170.0, 80.0], 60.0, 40.0, 4.0),
        through([170.0, 80.0], 120.0, 40.0, 4.0),
    ];
    let graph = trace(&render(&strokes, 230, 140));
    assert_eq!(graph.components(), 3);
    assert_eq!(graph.cycles(), 1);
    assert_eq!(graph.junctions().count(), 1);
    assert_geometry(&graph, &strokes);
}

#[test]
fn a_lone_dot_is_a_lone_vertex() {
    let mut binary = Binary::new(20, 20);
    for y in 8..12 {
        for x in 8..12 {
            binary.set(x, y, true);
        }
    }
    let graph = trace(&binary);
    assert_eq!(graph.vertices.len(), 1);
    assert_eq!(graph.edges.len(), 0);
}

#[test]
fn same_input_gives_identical_output() {
    let strokes = [
        through([60.0, 60.0], 30.0, 50.0, 5.0),
        circle([60.0, 60.0], 30.0, 4.0),
    ];
    let binary = render(&strokes, 120, 120);
    assert_eq!(trace(&binary), trace(&binary));
}

#[test]
fn a_large_page_traced_with_stages_is_the_same_trace_in_the_same_chunks() {
    // Over 16k ink points, so `trace_binary` cuts the page into chunks of components (that
    // this equals the page traced as one point set is the driver's unit test of the same name);
    // tracing with stages is the same trace. Rings with blobs and rings inside (holes that hold
    // another component), strokes 2 px apart, crossings.
    let mut strokes = Vec::new();
    for row in 0..4 {
        for col in 0..6 {
            let c = [40.0 + 70.0 * col as f64, 40.0 + 70.0 * row as f64];
            strokes.push(circle(c, 26.0, 4.0));
            match (row + col) % 3 {
                0 => strokes.push(circle(c, 12.0, 4.0)),
                1 => strokes.push(Stroke::new(vec![c, [c[0] + 3.0, c[1] + 2.0]], 9.0)),
                _ => {
                    strokes.push(through(c, 30.0, 12.0, 3.0));
                    strokes.push(through(c, 120.0, 12.0, 3.0));
                }
            }
        }
    }
    for k in 0..6 {
        let y = 300.0 + 6.0 * k as f64;
        strokes.push(line([20.0, y], [400.0, y], 3.0));
    }
    let binary = render(&strokes, 440, 350);
    assert!(binary.count() > 16_384, "{} ink pixels", binary.count());
    let params = Params::default();
    let chunked = trace_binary(&binary, &params).expect("trace");
    // The traced stages are those of the same chunks: the same graph, in the same order, and
    // the stages of every chunk one after the other.
    let staged = ridgeline::trace_binary_with_stages(&binary, &params).expect("trace");
    assert_eq!(staged.graph, chunked.graph);
    let stages = staged.stages.expect("stages kept");
    // The stages are those of the method, which traces only the ink around the skeleton's
    // junctions (docs/design.md, "Skeleton-carried geometry"): a part of the points.
    assert!(!stages.points.is_empty() && stages.points.len() < chunked.point_count);
    stages.points.validate().expect("joined points");
    stages
        .samples
        .validate(stages.points.len())
        .expect("joined samples");
    let n = stages.points.len();
    stages.node_graph.validate(n).expect("joined H");
    stages.refined.validate(n).expect("joined 1-D graph");
    // And the rings inside rings kept their loops.
    assert!(
        chunked.graph.cycles() >= 24 + 8,
        "{} cycles",
        chunked.graph.cycles()
    );
}

/// Mean and largest distance from the graph's polylines (every point) to the truth.
fn deviation(graph: &StrokeGraph, strokes: &[Stroke]) -> (f64, f64) {
    let (mut sum, mut most, mut count) = (0.0, 0.0f64, 0usize);
    for e in &graph.edges {
        for &p in &e.points {
            let d = distance_to_truth(p, strokes);
            sum += d;
            most = most.max(d);
            count += 1;
        }
    }
    (sum / count.max(1) as f64, most)
}

#[test]
fn dense_fit_follows_a_tight_loop_closer_than_the_coarse_fit() {
    // A loop only a few stroke widths around: the coarse fit's nodes, one width apart, cut it
    // by chords; the dense re-fit (one point per 2 px from each edge's own pixels) follows it.
    // Both on the node graph's own polylines (the skeleton would carry either).
    let strokes = vec![circle([40.0, 40.0], 9.0, 6.0)];
    let binary = render(&strokes, 80, 80);
    let mut node_graph = Params::default();
    node_graph.finish.skeleton = false;
    let coarse = trace_binary(&binary, &node_graph)
        .expect("trace succeeds")
        .graph;
    let mut dense_params = node_graph.clone();
    dense_params.experiments.dense_fit = true;
    let dense = trace_binary(&binary, &dense_params)
        .expect("trace succeeds")
        .graph;
    dense.validate().expect("stroke graph is valid");
    assert_eq!(degrees(&dense), degrees(&coarse), "same topology");
    let count = |g: &StrokeGraph| g.edges.iter().map(|e| e.points.len()).sum::<usize>();
    // A point every 2 px of the slices, the one vertex and the smoothing's joins: about 2.5 px.
    let around = 2.0 * std::f64::consts::PI * 9.0;
    assert!(
        count(&dense) > count(&coarse) && count(&dense) as f64 >= around / 2.5,
        "a point every 2-2.5 px around the loop: {} against {} coarse",
        count(&dense),
        count(&coarse)
    );
    let (coarse_mean, _) = deviation(&coarse, &strokes);
    let (dense_mean, dense_max) = deviation(&dense, &strokes);
    assert!(
        dense_mean < coarse_mean && dense_max < 1.0,
        "dense mean {dense_mean:.2} max {dense_max:.2}, coarse mean {coarse_mean:.2}"
    );
}

#[test]
fn dense_fit_keeps_crossings_and_t_junctions() {
    let strokes = vec![
        through([80.0, 80.0], 30.0, 60.0, 8.0),
        through([80.0, 80.0], 150.0, 60.0, 8.0),
        line([20.0, 140.0], [140.0, 140.0], 6.0),
        line([80.0, 140.0], [80.0, 190.0], 6.0),
    ];
    let binary = render(&strokes, 160, 200);
    let mut params = Params::default();
    params.experiments.dense_fit = true;
    let graph = trace_binary(&binary, &params)
        .expect("trace succeeds")
        .graph;
    graph.validate().expect("stroke graph is valid");
    assert_eq!(degrees(&graph), vec![1, 1, 1, 1, 1, 1, 1, 3, 4]);
    assert_geometry(&graph, &strokes);
}

/// A 3 x 3 grid of `width` px lines whose cells are `cell` px across.
fn grid(width: f64, cell: f64) -> (Vec<Stroke>, u32) {
    let (pitch, margin) = (cell + width, 10.0 + width);
    let far = margin + 3.0 * pitch;
    let mut strokes = Vec::new();
    for i in 0..=3 {
        let t = margin + i as f64 * pitch;
        strokes.push(line([margin, t], [far, t], width));
        strokes.push(line([t, margin], [t, far], width));
    }
    (strokes, (far + margin) as u32 + 1)
}

fn cycles(graph: &StrokeGraph) -> i64 {
    // One component: cycles = E - V + 1.
    graph.edges.len() as i64 - graph.vertices.len() as i64 + 1
}

#[test]
fn ink_disks_keep_every_cell_of_a_grid_whose_cells_are_half_a_width() {
    // 6 px lines, 3 px cells: a disk one width across wraps around a cell, so the default loses
    // some of the nine cells; disks cut short of ink hidden behind a cell keep them all.
    let (strokes, size) = grid(6.0, 3.0);
    let binary = render(&strokes, size, size);
    let mut ink_disks = Params::default();
    ink_disks.experiments.ink_disks = true;
    let mut all = ink_disks.clone();
    all.experiments.site_clusters = true;
    all.experiments.dense_fit = true;
    all.experiments.junctions_on_ink = true;
    for params in [ink_disks, all] {
        let graph = trace_binary(&binary, &params)
            .expect("trace succeeds")
            .graph;
        graph.validate().expect("stroke graph is valid");
        assert_eq!(cycles(&graph), 9, "{params:?}");
        assert!(graph.vertices.iter().all(|v| v.degree != 1), "no ends");
    }
}

#[test]
fn terminals_that_curl_end_at_the_centre_of_their_caps() {
    use ridgeline_testkit::score::{score, truth_graph};
    use ridgeline_testkit::synth::text_line;
    // Thinning erodes a curling tip most, and along the end's own line the ink ends a pixel or
    // two on: the ends of a `c`, an `e` or an `S` 3 px wide stayed one to two widths short of
    // their caps, a missed end and a spurious one each.
    for height in [24.0, 36.0, 56.0] {
        for width in [3.0, 5.0] {
            for text in ["c", "e", "s", "S", "C", "G", "J", "3", "5"] {
                let case = text_line("curl", text, height, width);
                let truth = truth_graph(&case);
                let s = score(&case, &truth, &trace(&case.binary));
                assert!(
                    s.endpoints_found == s.true_endpoints && s.spurious_endpoints == 0,
                    "`{text}` {height} px high, {width} px wide: {} of {} ends found, {} spurious",
                    s.endpoints_found,
                    s.true_endpoints,
                    s.spurious_endpoints
                );
            }
        }
    }
}
