//! Features beyond thinning (docs/design.md, "Beyond the paper"): strokes through crossings, width
//! coverage, minutiae and Bézier curves, end to end from rendered centerlines.

use crate::support::{ridgeline, run_ok, write_mask_png};
use ridgeline::curves::{fit_beziers, fit_edges, CurveOptions};
use ridgeline::minutiae::{minutiae, MinutiaKind, MinutiaeOptions};
use ridgeline::strokes::{coverage_iou, strokes, StrokeOptions};
use ridgeline::{trace_binary, Binary, Edge, Params, StrokeGraph, Vertex};
use ridgeline_testkit::synth::{print_cases, render, Stroke as TrueStroke};
use serde_json::Value;
use std::f64::consts::{PI, TAU};
use std::fs;
use std::path::Path;

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
        // The distance to the curve, as to the polyline through its dense samples (a long
        // segment's samples lie up to a pixel apart, too far apart to stand for it as points).
        let to_segment = |p: [f64; 2], a: [f64; 2], b: [f64; 2]| {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len2 = dx * dx + dy * dy;
            let t = if len2 > 0.0 {
                (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
        };
        for p in &edge.points {
            let d = samples
                .windows(2)
                .map(|s| to_segment(*p, s[0], s[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= options.tolerance + 0.05, "{d}");
        }
    }
    assert_eq!(
        fit_beziers(&trace.graph.edges[0].points, 0.5, 60.0).len(),
        fit_edges(&trace.graph, &options)[0].len()
    );
}

// ---------------------------------------------------------------------------------------------
// The features through the `ridgeline` binary

/// Writes the rendering of `truth` as a PNG of dark ink on light paper; returns the mask.
fn write_png(truth: &[TrueStroke], width: u32, height: u32, path: &Path) -> Binary {
    let binary = render(truth, width, height);
    write_mask_png(&binary, path);
    binary
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&fs::read_to_string(path).expect("read JSON")).expect("valid JSON")
}

fn pair(value: &Value) -> [f64; 2] {
    [value[0].as_f64().expect("x"), value[1].as_f64().expect("y")]
}

fn pairs(value: &Value) -> Vec<[f64; 2]> {
    value.as_array().expect("list").iter().map(pair).collect()
}

/// A '+' on the left and a 'T' on the right: 4 strokes (2 through the crossing, bar and stem).
fn plus_and_t() -> Vec<TrueStroke> {
    vec![
        line([20.0, 70.0], [120.0, 70.0], 7.0),
        line([70.0, 20.0], [70.0, 120.0], 7.0),
        line([150.0, 30.0], [250.0, 30.0], 7.0),
        line([200.0, 30.0], [200.0, 120.0], 7.0),
    ]
}

#[test]
fn cli_json_lists_strokes_that_partition_the_edges() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    write_png(&plus_and_t(), 270, 140, &dir.path().join("pt.png"));
    run_ok(&["pt.png", "-o", "pt.json"], dir.path());
    let doc = read_json(&dir.path().join("pt.json"));
    let edges = doc["edges"].as_array().expect("edges");
    let strokes = doc["strokes"].as_array().expect("strokes always listed");
    assert_eq!(strokes.len(), 4, "{strokes:?}");
    assert!(doc.get("minutiae").is_none(), "minutiae only on request");
    let mut seen = vec![0; edges.len()];
    for (id, stroke) in strokes.iter().enumerate() {
        assert_eq!(stroke["id"].as_u64(), Some(id as u64));
        let ids: Vec<usize> = stroke["edges"]
            .as_array()
            .expect("edge ids")
            .iter()
            .map(|e| e.as_u64().expect("id") as usize)
            .collect();
        let reversed = stroke["reversed"].as_array().expect("reversed");
        assert_eq!(reversed.len(), ids.len());
        let points = pairs(&stroke["points"]);
        assert_eq!(
            stroke["widths"].as_array().expect("widths").len(),
            points.len()
        );
        assert_eq!(stroke["closed"].as_bool(), Some(false));
        // The joined polyline starts where its first edge starts (or ends, when reversed).
        let first = &edges[ids[0]]["points"];
        let start = if reversed[0].as_bool() == Some(true) {
            pair(&first[first.as_array().expect("points").len() - 1])
        } else {
            pair(&first[0])
        };
        assert!((start[0] - points[0][0]).abs() < 1e-9 && (start[1] - points[0][1]).abs() < 1e-9);
        for e in ids {
            seen[e] += 1;
        }
        // Every stroke here is straight: from end to end at least 80 px.
        let (a, b) = (points[0], points[points.len() - 1]);
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) > 80.0, "{a:?} {b:?}");
    }
    assert!(seen.iter().all(|&n| n == 1), "{seen:?}");
}

#[test]
fn cli_strokes_svg_has_one_polyline_per_stroke_in_distinct_colors() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    write_png(&plus_and_t(), 270, 140, &dir.path().join("pt.png"));
    run_ok(&["pt.png", "--strokes", "-o", "pt.svg"], dir.path());
    run_ok(&["pt.png", "-o", "pt.json"], dir.path());
    let text = fs::read_to_string(dir.path().join("pt.svg")).expect("SVG");
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let group = doc
        .descendants()
        .find(|n| n.has_tag_name("g") && n.attribute("id") == Some("strokes"))
        .expect("strokes group");
    assert!(
        doc.descendants()
            .all(|n| !(n.has_tag_name("g") && n.attribute("id") == Some("edges"))),
        "strokes replace the edges"
    );
    let polylines: Vec<_> = group
        .children()
        .filter(|n| n.has_tag_name("polyline"))
        .collect();
    let json = read_json(&dir.path().join("pt.json"));
    let strokes = json["strokes"].as_array().expect("strokes");
    assert_eq!(polylines.len(), 4);
    assert_eq!(polylines.len(), strokes.len());
    let mut colors: Vec<&str> = polylines
        .iter()
        .map(|p| p.attribute("stroke").expect("own color"))
        .collect();
    colors.sort();
    colors.dedup();
    assert_eq!(colors.len(), polylines.len(), "distinct colors");
    for (polyline, stroke) in polylines.iter().zip(strokes) {
        let count = polyline
            .attribute("points")
            .expect("points")
            .split_whitespace()
            .count();
        assert_eq!(count, stroke["points"].as_array().expect("points").len());
    }
}

#[test]
fn cli_minutiae_json_finds_the_endings_and_bifurcations_of_a_synthetic_print() {
    let case = print_cases()
        .into_iter()
        .find(|c| c.name.ends_with("_arch_minutiae"))
        .expect("print case");
    let dir = tempfile::TempDir::new().expect("temp dir");
    write_mask_png(&case.binary, &dir.path().join("print.png"));
    run_ok(
        &[
            "print.png",
            "--polarity",
            "dark",
            "--minutiae",
            "-o",
            "print.json",
        ],
        dir.path(),
    );
    let doc = read_json(&dir.path().join("print.json"));
    let found = doc["minutiae"].as_array().expect("minutiae");
    let kinds: Vec<&str> = found
        .iter()
        .map(|m| m["kind"].as_str().expect("kind"))
        .collect();
    // The case has one ridge ending at (0.35, 0.4) and one bifurcation at (0.66, 0.62) of its
    // 200 px side; the ridges cut by the print's outline give no minutia.
    let near = |kind: &str, at: [f64; 2]| {
        found.iter().any(|m| {
            m["kind"].as_str() == Some(kind)
                && (m["x"].as_f64().expect("x") - at[0]).hypot(m["y"].as_f64().expect("y") - at[1])
                    < 8.0
        })
    };
    assert!(near("ending", [70.0, 80.0]), "{found:?}");
    assert!(near("bifurcation", [132.0, 124.0]), "{found:?}");
    assert!(found.len() <= 4, "few spurious minutiae: {kinds:?}");
    for m in found {
        let d = m["direction"].as_f64().expect("direction");
        assert!(d.abs() <= PI + 1e-3, "{d}");
        let vertex = m["vertex"].as_u64().expect("vertex") as usize;
        let degree = doc["vertices"][vertex]["degree"].as_u64();
        match m["kind"].as_str() {
            Some("ending") => assert_eq!(degree, Some(1)),
            Some("bifurcation") => assert_eq!(degree, Some(3)),
            other => panic!("unknown kind {other:?}"),
        }
    }
    // The SVG marks them.
    run_ok(
        &[
            "print.png",
            "--polarity",
            "dark",
            "--minutiae",
            "-o",
            "print.svg",
        ],
        dir.path(),
    );
    let text = fs::read_to_string(dir.path().join("print.svg")).expect("SVG");
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let marks = doc
        .descendants()
        .find(|n| n.has_tag_name("g") && n.attribute("id") == Some("minutiae"))
        .expect("minutiae group");
    let lines = marks.children().filter(|n| n.has_tag_name("line")).count();
    assert_eq!(lines, found.len(), "one direction line per minutia");
}

/// Distance from `p` to the polyline.
fn distance_to_polyline(p: [f64; 2], line: &[[f64; 2]]) -> f64 {
    line.windows(2)
        .map(|w| ridgeline::geometry::segment_dist(p, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// The cubic segments of SVG path data `M x y C x1 y1 x2 y2 x y …`.
fn path_segments(data: &str) -> Vec<[[f64; 2]; 4]> {
    let tokens: Vec<&str> = data.split_whitespace().collect();
    let mut segments = Vec::new();
    let mut at = [0.0, 0.0];
    let mut i = 0;
    let number = |k: usize| -> f64 { tokens[k].parse().expect("number") };
    while i < tokens.len() {
        match tokens[i] {
            "M" => {
                at = [number(i + 1), number(i + 2)];
                i += 3;
            }
            "C" => {
                let p1 = [number(i + 1), number(i + 2)];
                let p2 = [number(i + 3), number(i + 4)];
                let p3 = [number(i + 5), number(i + 6)];
                segments.push([at, p1, p2, p3]);
                at = p3;
                i += 7;
            }
            other => panic!("unexpected path command {other}"),
        }
    }
    segments
}

#[test]
fn cli_curves_svg_paths_stay_within_tolerance_of_the_polylines() {
    let truth = [
        TrueStroke::new(
            (0..=90)
                .map(|k| polar([90.0, 90.0], 55.0, k as f64 * 4.0))
                .collect(),
            6.0,
        ),
        TrueStroke::new(
            (0..=60)
                .map(|k| {
                    let x = 20.0 + 2.5 * k as f64;
                    [x, 175.0 + 12.0 * (x / 15.0).sin()]
                })
                .collect(),
            5.0,
        ),
        line([30.0, 30.0], [60.0, 140.0], 5.0),
    ];
    let dir = tempfile::TempDir::new().expect("temp dir");
    write_png(&truth, 200, 200, &dir.path().join("c.png"));
    let tolerance = 0.5;
    run_ok(&["c.png", "--curves", "-o", "c.svg"], dir.path());
    run_ok(&["c.png", "-o", "c.json"], dir.path());
    let text = fs::read_to_string(dir.path().join("c.svg")).expect("SVG");
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let json = read_json(&dir.path().join("c.json"));
    let edges = json["edges"].as_array().expect("edges");
    let paths: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    assert_eq!(paths.len(), edges.len(), "one path per edge");
    assert!(doc.descendants().all(|n| !n.has_tag_name("polyline")));
    for (path, edge) in paths.iter().zip(edges) {
        let polyline = pairs(&edge["points"]);
        let segments = path_segments(path.attribute("d").expect("d"));
        assert!(!segments.is_empty());
        assert!(segments.len() < polyline.len(), "curves are shorter");
        for [p0, p1, p2, p3] in segments {
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let s = 1.0 - t;
                let (b0, b1, b2, b3) = (s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
                let q = [
                    b0 * p0[0] + b1 * p1[0] + b2 * p2[0] + b3 * p3[0],
                    b0 * p0[1] + b1 * p1[1] + b2 * p2[1] + b3 * p3[1],
                ];
                let d = distance_to_polyline(q, &polyline);
                assert!(d <= tolerance + 1.0, "curve point {q:?} is {d} px off");
            }
        }
    }
    // A tighter tolerance needs more segments; a bad one is a usage error.
    run_ok(
        &[
            "c.png",
            "--curves",
            "--curve-tolerance",
            "0.1",
            "-o",
            "fine.svg",
        ],
        dir.path(),
    );
    let fine = fs::read_to_string(dir.path().join("fine.svg")).expect("SVG");
    assert!(fine.matches(" C ").count() > text.matches(" C ").count());
    let bad = ridgeline(
        &["c.png", "--curves", "--curve-tolerance", "0", "-o", "x.svg"],
        dir.path(),
    );
    assert_eq!(bad.status.code(), Some(2));
}

/// `--width` draws the edges as wide as the ink: rendered by resvg without the image, the drawing
/// covers the ink.
#[test]
fn cli_width_svg_covers_the_ink() {
    let truth = [
        line([30.0, 50.0], [170.0, 60.0], 7.0),
        line([60.0, 20.0], [90.0, 180.0], 5.0),
        TrueStroke::new(
            (0..=60)
                .map(|k| polar([125.0, 130.0], 35.0, k as f64 * 6.0))
                .collect(),
            6.0,
        ),
    ];
    let dir = tempfile::TempDir::new().expect("temp dir");
    let binary = write_png(&truth, 200, 200, &dir.path().join("w.png"));
    run_ok(
        &[
            "w.png",
            "--width",
            "--no-image",
            "--no-vertices",
            "-o",
            "w.svg",
        ],
        dir.path(),
    );
    let text = fs::read_to_string(dir.path().join("w.svg")).expect("SVG");
    let tree = resvg::usvg::Tree::from_str(&text, &resvg::usvg::Options::default()).expect("SVG");
    let mut pixmap = resvg::tiny_skia::Pixmap::new(200, 200).expect("pixmap");
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    let (mut both, mut either) = (0usize, 0usize);
    for (pixel, &ink) in pixmap.pixels().iter().zip(&binary.ink) {
        // Anti-aliased edges count as drawn when at least half covered.
        let drawn = f64::from(pixel.alpha()) >= 0.5 * 255.0 * 0.45;
        both += usize::from(drawn && ink);
        either += usize::from(drawn || ink);
    }
    let iou = both as f64 / either as f64;
    assert!(iou > 0.8, "the width drawing covers the ink: IoU {iou}");
    assert_eq!(text.matches("<g id=\"widths\"").count(), 1);
}

/// The writers on a hand-built '+': what each feature adds, and that missing curves fall back to
/// polylines rather than failing.
#[test]
fn writers_draw_and_list_the_features_given() {
    use ridgeline::curves::CubicBezier;
    use ridgeline::export::json::{self, JsonMeta};
    use ridgeline::export::svg::{self, SvgOptions};
    use ridgeline::export::Features;
    let c = [50.0, 50.0];
    let mut graph = StrokeGraph {
        width: 100,
        height: 100,
        vertices: vec![Vertex {
            pos: c,
            degree: 4,
            width: 6.0,
        }],
        edges: Vec::new(),
    };
    for (k, a) in [0.0, 90.0, 180.0, 270.0].iter().enumerate() {
        let tip = polar(c, 40.0, *a);
        graph.vertices.push(Vertex {
            pos: tip,
            degree: 1,
            width: 4.0,
        });
        let mid = polar(c, 20.0, *a);
        graph.edges.push(Edge {
            from: 0,
            to: k + 1,
            points: vec![c, mid, tip],
            widths: vec![6.0, 5.0, 4.0],
            directions: vec![[1.0, 0.0]; 3],
        });
    }
    graph.validate().expect("valid");
    let chained = strokes(&graph, &StrokeOptions::default());
    assert_eq!(chained.len(), 2);
    let found = minutiae(
        &graph,
        None,
        &MinutiaeOptions {
            border_margin: 0.0,
            ..Default::default()
        },
    );
    assert_eq!(found.len(), 4, "four endings");

    // Curves for the first stroke only: it becomes a path, the second stays a polyline.
    let curves = vec![
        vec![CubicBezier {
            p0: chained[0].points[0],
            p1: chained[0].points[1],
            p2: chained[0].points[3],
            p3: chained[0].points[4],
        }],
        Vec::new(),
    ];
    let features = Features::default()
        .with_strokes(Some(&chained))
        .with_minutiae(Some(&found))
        .with_curves(Some(&curves));
    let options = SvgOptions::default().with_show_widths(true);
    let text = svg::to_string_with(&graph, None, &options, &features);
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let group = |id: &str| {
        doc.descendants()
            .find(|n| n.has_tag_name("g") && n.attribute("id") == Some(id))
            .unwrap_or_else(|| panic!("no group {id}"))
    };
    let in_strokes: Vec<&str> = group("strokes")
        .children()
        .filter(|n| n.is_element())
        .map(|n| n.tag_name().name())
        .collect();
    assert_eq!(in_strokes, ["path", "polyline"]);
    let widths: Vec<f64> = group("widths")
        .children()
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            n.attribute("stroke-width")
                .expect("width")
                .parse()
                .expect("number")
        })
        .collect();
    assert_eq!(widths, [5.0; 4], "each edge drawn with its mean width");
    let marks = group("minutiae");
    assert_eq!(
        marks.children().filter(|n| n.has_tag_name("line")).count(),
        4
    );
    // Plain `to_string` draws edges, no feature.
    let plain = svg::to_string(&graph, None, &SvgOptions::default());
    assert!(plain.contains("<g id=\"edges\""));
    assert!(!plain.contains("strokes") && !plain.contains("minutiae") && !plain.contains("<path"));

    let meta = JsonMeta::new(Params::default());
    let listed: Value =
        serde_json::from_str(&json::to_string_with(&graph, &meta, &features)).expect("JSON");
    assert_eq!(listed["strokes"].as_array().map(Vec::len), Some(2));
    assert_eq!(listed["strokes"][0]["length"].as_f64(), Some(80.0));
    assert_eq!(listed["minutiae"].as_array().map(Vec::len), Some(4));
    assert_eq!(listed["minutiae"][0]["kind"].as_str(), Some("ending"));
    let plain: Value = serde_json::from_str(&json::to_string(&graph, &meta)).expect("JSON");
    assert!(plain.get("strokes").is_none() && plain.get("minutiae").is_none());
}

/// The smallest difference between two angles in degrees.
fn degrees_apart(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// A drawn ridge ending and a drawn bifurcation of known directions, written as `.xyt` and as an
/// ISO/IEC 19794-2 record, read back by each standard's definition (docs/fingerprints.md,
/// "Outputs"):
/// - `.xyt` (NIST, as mindtct writes it): origin bottom-left, y up, theta in degrees
///   counterclockwise; an ending points out of its ridge past the end, a bifurcation from the
///   fork along the stem, away from the branches.
/// - ISO/IEC 19794-2: origin top-left, y down, angle in 360/256° units counterclockwise as the
///   image is seen; an ending points into its ridge, a bifurcation between its branches.
#[test]
fn drawn_minutiae_have_the_angles_of_xyt_and_iso_19794_2() {
    let (width, height) = (240u32, 200u32);
    // Ending: a ridge running up and to the right on screen (+60 px in x, -50 px in y) that ends
    // at (100, 120); its other end, at (40, 170), points the other way.
    let ending = [100.0, 120.0];
    // Bifurcation: a stem coming up the screen from (170, 175) to a fork at (170, 90), branches
    // leaving upwards to the left and right.
    let fork = [170.0, 90.0];
    let truth = [
        line([40.0, 170.0], ending, 7.0),
        line([170.0, 175.0], fork, 7.0),
        line(fork, [135.0, 25.0], 7.0),
        line(fork, [205.0, 25.0], 7.0),
    ];
    let binary = render(&truth, width, height);
    let trace = trace_binary(&binary, &Params::default()).expect("trace");
    let found = minutiae(&trace.graph, None, &MinutiaeOptions::default());
    let near = |kind: MinutiaKind, at: [f64; 2]| {
        let i = found
            .iter()
            .position(|m| m.kind == kind && ridgeline::dist(m.pos, at) < 8.0);
        i.unwrap_or_else(|| panic!("no {kind:?} near {at:?}: {found:?}"))
    };
    let (e, b) = (
        near(MinutiaKind::Ending, ending),
        near(MinutiaKind::Bifurcation, fork),
    );

    // .xyt: the ridge runs up and right into its end, so the ending points that way:
    // atan2(50, 60) = 39.8° counterclockwise in the y-up frame. The bifurcation points from the
    // fork down the stem: 270°.
    let xyt = ridgeline::export::xyt::to_string(&found, height);
    let lines: Vec<Vec<f64>> = xyt
        .lines()
        .map(|l| l.split(' ').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(lines.len(), found.len());
    let expected_ending = 50f64.atan2(60.0).to_degrees();
    for (i, at, theta) in [(e, ending, expected_ending), (b, fork, 270.0)] {
        let [x, y, t, _] = lines[i][..] else {
            panic!("four fields: {xyt}");
        };
        assert!((x - at[0]).abs() < 8.0 && (y - (f64::from(height) - at[1])).abs() < 8.0);
        assert!(degrees_apart(t, theta) <= 10.0, "{t} against {theta}");
    }

    // ISO/IEC 19794-2: the ending points back into its ridge (39.8 + 180 = 219.8°), the
    // bifurcation up between its branches (90°), both counterclockwise as the image is seen.
    let record =
        ridgeline::export::iso19794::to_bytes(&found, width, height, 500.0).expect("record");
    let unit = 360.0 / 256.0;
    for (i, kind_bits, at, angle) in [
        (e, 0b01, ending, expected_ending + 180.0),
        (b, 0b10, fork, 90.0),
    ] {
        let m = &record[28 + 6 * i..28 + 6 * i + 6];
        let (first, second) = (
            u16::from_be_bytes([m[0], m[1]]),
            u16::from_be_bytes([m[2], m[3]]),
        );
        assert_eq!(first >> 14, kind_bits);
        let (x, y) = (f64::from(first & 0x3FFF), f64::from(second & 0x3FFF));
        assert!(
            (x - at[0]).abs() < 8.0 && (y - at[1]).abs() < 8.0,
            "{x} {y}"
        );
        let a = f64::from(m[4]) * unit;
        assert!(degrees_apart(a, angle) <= 10.0, "{a} against {angle}");
    }
}

/// A drawn print for the wet-area test: rings of `PERIOD` px around the middle of a 288 px image
/// (dark ridges, 128 ± 100, on light skin 230 beyond a radius of 130 px), with a disc of radius
/// `WET_RADIUS` at `WET` either solid at the ridges' level (a wet smear: no valleys) or holding
/// the rings at a quarter of their depth (faint ridges, averaging to the middle gray), plus
/// Gaussian noise of `sigma` from `seed`.
fn wet_print(solid: bool, sigma: f64, seed: u64) -> ridgeline::GrayImage {
    const SIZE: u32 = 288;
    let mut rng = ridgeline_testkit::synth::SplitMix64::new(seed);
    let mut pixels = Vec::with_capacity((SIZE * SIZE) as usize);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let r = ridgeline::dist([px, py], [144.0, 144.0]);
            let wave = (TAU * r / PERIOD).cos();
            let in_disc = ridgeline::dist([px, py], WET) <= WET_RADIUS;
            let level = if r > 130.0 {
                230.0
            } else if in_disc && solid {
                28.0
            } else if in_disc {
                128.0 - 25.0 * wave
            } else {
                128.0 - 100.0 * wave
            };
            // Box-Muller.
            let (u, v) = (rng.next_f64().max(1e-12), rng.next_f64());
            let noise = sigma * (-2.0 * u.ln()).sqrt() * (TAU * v).cos();
            pixels.push((level + noise).round().clamp(0.0, 255.0) as u8);
        }
    }
    ridgeline::GrayImage::from_raw(SIZE, SIZE, pixels).expect("size matches")
}

const PERIOD: f64 = 9.0;
const WET: [f64; 2] = [190.0, 110.0];
const WET_RADIUS: f64 = 3.0 * PERIOD;

/// Ridges traced where the image shows none (issue 35; docs/fingerprints.md, "Ridges through a
/// solid wet area"): a solid dark disc of three periods' radius inside a print, a wet smear
/// without valleys, gets no minutiae whatever the noise draw, where the filter, with the flow and
/// the period of the rings around interpolated across it, drew ridges and minutiae through it
/// before (and does without the rule); a disc of faint ridges under the same noise stays print.
#[test]
fn no_minutiae_in_a_solid_wet_disc_and_faint_ridges_kept() {
    let in_disc = |trace: &ridgeline::Trace| {
        let print = trace.fingerprint.as_ref().expect("a print");
        print
            .minutiae
            .iter()
            .filter(|m| ridgeline::dist(m.pos, WET) <= WET_RADIUS + PERIOD / 2.0)
            .count()
    };
    let mut without_rule = Params::fingerprint();
    if let Some(print) = without_rule.fingerprint.as_mut() {
        print.blank_evidence = 0.0;
    }
    let mut invented = 0;
    for seed in 0..4u64 {
        let wet = wet_print(true, 10.0, 0x3E7 + seed);
        let trace = ridgeline::trace_image(&wet, &Params::fingerprint()).expect("trace");
        assert_eq!(in_disc(&trace), 0, "seed {seed}");
        invented += in_disc(&ridgeline::trace_image(&wet, &without_rule).expect("trace"));

        let faint = wet_print(false, 10.0, 0x3E7 + seed);
        let trace = ridgeline::trace_image(&faint, &Params::fingerprint()).expect("trace");
        let print = trace.fingerprint.as_ref().expect("a print");
        for dx in [-2.0, 0.0, 2.0] {
            for dy in [-2.0, 0.0, 2.0] {
                let (x, y) = (WET[0] + dx * 8.0, WET[1] + dy * 8.0);
                assert!(
                    print
                        .analysis
                        .segmentation
                        .contains_pixel(x as usize, y as usize),
                    "seed {seed}: faint ridges at ({x}, {y}) left out"
                );
            }
        }
    }
    assert!(invented > 0, "without the rule the disc has minutiae");
}

/// The ridges' width is measured only when asked for (`FingerprintParams::ridge_width`): without
/// it the print's graph, minutiae and every other decision are the same, and `stroke_width` is 0.
#[test]
fn a_print_without_its_ridge_width_traces_the_same() {
    let print = wet_print(false, 10.0, 0x3E7);
    let with = ridgeline::trace_image(&print, &Params::fingerprint()).expect("trace");
    let mut params = Params::fingerprint();
    if let Some(print) = params.fingerprint.as_mut() {
        print.ridge_width = false;
    }
    let without = ridgeline::trace_image(&print, &params).expect("trace");
    assert_eq!(with.graph, without.graph);
    let minutiae = |trace: &ridgeline::Trace| {
        trace
            .fingerprint
            .as_ref()
            .expect("a print")
            .minutiae
            .clone()
    };
    assert_eq!(minutiae(&with), minutiae(&without));
    let (mut measured, skipped) = (
        with.decisions.clone().expect("decisions"),
        without.decisions.clone().expect("decisions"),
    );
    assert!(
        measured.stroke_width > 0.0,
        "the ridges' width is measured by default"
    );
    assert_eq!(skipped.stroke_width, 0.0);
    measured.stroke_width = 0.0;
    assert_eq!(measured, skipped);
}
