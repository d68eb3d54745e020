//! Features beyond thinning (issue 6): strokes through crossings, width coverage, minutiae and
//! Bézier curves, end to end from rendered centerlines.

use ridgeline::curves::{fit_beziers, fit_edges, CurveOptions};
use ridgeline::minutiae::{minutiae, MinutiaKind, MinutiaeOptions};
use ridgeline::strokes::{coverage_iou, strokes, StrokeOptions};
use ridgeline::synth::{render, Stroke as TrueStroke};
use ridgeline::{trace_binary, Edge, Params, StrokeGraph, Vertex};
use std::f64::consts::{PI, TAU};

fn polar(c: [f64; 2], r: f64, degrees: f64) -> [f64; 2] {
    let a = degrees.to_radians();
    [c[0] + r * a.cos(), c[1] + r * a.sin()]
}

/// A straight true stroke between two points, sampled every 2 px.
fn line(a: [f64; 2], b: [f64; 2], width: f64) -> TrueStroke {
    let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / 2.0).ceil().max(1.0) as usize;
    let points = (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        })
        .collect();
    TrueStroke::new(points, width)
}

/// Traces the rendering of `truth` and chains its edges into strokes.
fn traced_strokes(
    truth: &[TrueStroke],
    size: u32,
) -> (StrokeGraph, Vec<ridgeline::strokes::Stroke>) {
    let binary = render(truth, size, size);
    let trace = trace_binary(&binary, &Params::default()).expect("trace");
    trace.graph.validate().expect("valid graph");
    let s = strokes(&trace.graph, &StrokeOptions::default());
    let mut seen = vec![0; trace.graph.edges.len()];
    s.iter()
        .flat_map(|st| st.edges.iter())
        .for_each(|&e| seen[e] += 1);
    assert!(
        seen.iter().all(|&n| n == 1),
        "every edge in exactly one stroke"
    );
    (trace.graph, s)
}

#[test]
fn traced_plus_gives_two_strokes() {
    let c = [100.0, 100.0];
    let truth = [
        line([40.0, 100.0], [160.0, 100.0], 8.0),
        line([100.0, 40.0], [100.0, 160.0], 8.0),
    ];
    let (_, s) = traced_strokes(&truth, 200);
    assert_eq!(s.len(), 2);
    for stroke in &s {
        let (a, b) = (stroke.points[0], stroke.points[stroke.points.len() - 1]);
        assert!(
            (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) > 100.0,
            "runs through {c:?}"
        );
    }
}

#[test]
fn traced_x_at_30_degrees_gives_two_strokes() {
    let c = [120.0, 120.0];
    let truth = [
        line(polar(c, 90.0, 180.0), polar(c, 90.0, 0.0), 6.0),
        line(polar(c, 90.0, 210.0), polar(c, 90.0, 30.0), 6.0),
    ];
    let (_, s) = traced_strokes(&truth, 240);
    assert_eq!(s.len(), 2);
}

#[test]
fn traced_eight_gives_one_closed_stroke() {
    let c = [100.0, 100.0];
    let points: Vec<[f64; 2]> = (0..=240)
        .map(|k| {
            let t = k as f64 / 240.0 * TAU;
            let q = 1.0 + t.sin() * t.sin();
            [
                c[0] + 70.0 * t.sin() * t.cos() / q,
                c[1] + 70.0 * t.cos() / q,
            ]
        })
        .collect();
    let (_, s) = traced_strokes(&[TrueStroke::new(points, 6.0)], 200);
    assert_eq!(s.len(), 1);
    assert!(s[0].closed);
}

#[test]
fn traced_t_gives_bar_and_stem() {
    let truth = [
        line([40.0, 60.0], [160.0, 60.0], 8.0),
        line([100.0, 60.0], [100.0, 170.0], 8.0),
    ];
    let (_, s) = traced_strokes(&truth, 200);
    assert_eq!(s.len(), 2);
    let bar = s
        .iter()
        .max_by(|a, b| a.length().total_cmp(&b.length()))
        .expect("strokes");
    let (a, b) = (bar.points[0], bar.points[bar.points.len() - 1]);
    assert!(
        (a[1] - 60.0).abs() < 4.0 && (b[1] - 60.0).abs() < 4.0,
        "the bar is one stroke"
    );
}

/// A symmetric Y (arms 120 degrees apart): no two arms continue each other within 30 degrees, so
/// each arm is its own stroke.
#[test]
fn traced_symmetric_y_gives_three_strokes() {
    let c = [100.0, 100.0];
    let truth: Vec<_> = [90.0, 210.0, 330.0]
        .iter()
        .map(|&a| line(c, polar(c, 70.0, a), 8.0))
        .collect();
    let (_, s) = traced_strokes(&truth, 200);
    assert_eq!(s.len(), 3);
}

/// A graph that is the truth itself re-renders exactly; thinner widths cover less.
#[test]
fn coverage_iou_is_one_for_the_truth_and_drops_with_width() {
    let truth = vec![
        TrueStroke {
            points: vec![[20.0, 30.0], [80.0, 40.0], [150.0, 90.0]],
            widths: vec![4.0, 8.0, 12.0],
        },
        TrueStroke::new(vec![[100.0, 20.0], [100.0, 170.0]], 6.0),
    ];
    let binary = render(&truth, 200, 200);
    let as_graph = |scale: f64| {
        let mut graph = truth_graph(&truth, 200);
        graph.vertices.iter_mut().for_each(|v| v.width *= scale);
        graph
            .edges
            .iter_mut()
            .flat_map(|e| e.widths.iter_mut())
            .for_each(|w| *w *= scale);
        graph
    };
    assert_eq!(coverage_iou(&as_graph(1.0), &binary), 1.0);
    let thin = coverage_iou(&as_graph(0.5), &binary);
    assert!(thin > 0.3 && thin < 0.7, "{thin}");
    assert_eq!(
        coverage_iou(&StrokeGraph::default(), &ridgeline::Binary::new(0, 0)),
        1.0
    );
}

#[test]
fn traced_widths_cover_the_ink() {
    let truth = [
        line([30.0, 50.0], [170.0, 60.0], 7.0),
        line([60.0, 20.0], [90.0, 180.0], 5.0),
        TrueStroke {
            points: (0..=60)
                .map(|k| polar([120.0, 130.0], 35.0, k as f64 * 6.0))
                .collect(),
            widths: vec![6.0; 61],
        },
    ];
    let binary = render(&truth, 200, 200);
    let trace = trace_binary(&binary, &Params::default()).expect("trace");
    let iou = coverage_iou(&trace.graph, &binary);
    assert!(iou >= 0.85, "IoU {iou}");
}

/// Concentric arc ridges 4 px wide, 9 px apart, one of them (radius `r`) stopping halfway at the
/// top (270 degrees, y down).
fn arcs() -> (Vec<TrueStroke>, [f64; 2], f64) {
    let c = [150.0, 150.0];
    let mut truth = Vec::new();
    for ring in 0..7 {
        let radius = 30.0 + 9.0 * ring as f64;
        let span = if ring == 3 { 70.0 } else { 140.0 };
        let points = (0..=100)
            .map(|k| polar(c, radius, 200.0 + span * k as f64 / 100.0))
            .collect();
        truth.push(TrueStroke::new(points, 4.0));
    }
    (truth, c, 30.0 + 9.0 * 3.0)
}

/// The truth as a stroke graph: each true stroke one edge between two ends.
fn truth_graph(truth: &[TrueStroke], size: u32) -> StrokeGraph {
    let mut graph = StrokeGraph {
        width: size,
        height: size,
        ..Default::default()
    };
    for t in truth {
        let v = graph.vertices.len();
        let n = t.points.len();
        graph.vertices.push(Vertex {
            pos: t.points[0],
            degree: 1,
            width: t.widths[0],
        });
        graph.vertices.push(Vertex {
            pos: t.points[n - 1],
            degree: 1,
            width: t.widths[n - 1],
        });
        graph.edges.push(Edge {
            from: v,
            to: v + 1,
            points: t.points.clone(),
            widths: t.widths.clone(),
            directions: vec![[1.0, 0.0]; n],
        });
    }
    graph
}

fn check_arc_minutiae(m: &[ridgeline::minutiae::Minutia], c: [f64; 2], r: f64, within: f64) {
    let endings: Vec<_> = m.iter().filter(|m| m.kind == MinutiaKind::Ending).collect();
    assert_eq!(endings.len(), 1, "{m:?}");
    let tip = polar(c, r, 270.0);
    assert!((endings[0].pos[0] - tip[0]).hypot(endings[0].pos[1] - tip[1]) < within);
    // The ridge runs clockwise on screen into its end: direction 270 + 90 = 360 degrees.
    let d = endings[0].direction.rem_euclid(TAU);
    assert!(d.min(TAU - d) < 0.3, "direction {d}");
    assert!(m
        .iter()
        .all(|m| m.direction > -PI - 1e-12 && m.direction <= PI));
}

/// The arcs' cut ends at the print's outline are not minutiae; the one ridge ending inside is.
#[test]
fn minutiae_of_the_truth_skip_the_print_border() {
    let (truth, c, r) = arcs();
    let binary = render(&truth, 300, 300);
    let graph = truth_graph(&truth, 300);
    check_arc_minutiae(
        &minutiae(&graph, Some(&binary), &MinutiaeOptions::default()),
        c,
        r,
        1e-9,
    );
    // Without the mask only the image border counts: all 14 ends are far from it.
    assert_eq!(
        minutiae(&graph, None, &MinutiaeOptions::default()).len(),
        14
    );
}

/// The same through the pipeline.
#[test]
fn traced_minutiae_inside_the_print() {
    let (truth, c, r) = arcs();
    let binary = render(&truth, 300, 300);
    let trace = trace_binary(&binary, &Params::default()).expect("trace");
    let m = minutiae(&trace.graph, Some(&binary), &MinutiaeOptions::default());
    check_arc_minutiae(&m, c, r, 4.0);
}
#[test]
fn traced_edges_fit_with_curves_within_tolerance() {
    let truth = [TrueStroke::new(
        (0..=90)
            .map(|k| polar([100.0, 100.0], 60.0, k as f64 * 4.0))
            .collect(),
        6.0,
    )];
    let binary = render(&truth, 200, 200);
    let trace = trace_binary(&binary, &Params::default()).expect("trace");
    let options = CurveOptions::default();
    for (edge, segments) in trace
        .graph
        .edges
        .iter()
        .zip(fit_edges(&trace.graph, &options))
    {
        assert!(segments.len() < edge.points.len());
        let samples: Vec<[f64; 2]> = segments
            .iter()
            .flat_map(|s| (0..=200).map(move |k| s.eval(k as f64 / 200.0)))
            .collect();
        for p in &edge.points {
            let d = samples
                .iter()
                .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= options.tolerance + 0.05, "{d}");
        }
    }
    assert_eq!(
        fit_beziers(&trace.graph.edges[0].points, 0.5, 60.0).len(),
        fit_edges(&trace.graph, &options)[0].len()
    );
}
