//! Strip-shaped point sets, the paper's own input (§3): random points in bands several units wide
//! around known curves (`ridgeline_testkit::synth::strip_cases`), not thin curves.

use ridgeline::{Params, StrokeGraph};
use ridgeline_testkit::synth::{strip_cases, StripCase};

use crate::support::median;

fn case(name: &str) -> StripCase {
    strip_cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no strip case {name}"))
}

fn median_width(graph: &StrokeGraph) -> f64 {
    median(graph.edges.iter().flat_map(|e| e.widths.iter().copied()))
}

/// §3.1: the local width of a band of random points is read from its PCA, in the band's units.
#[test]
fn strip_width_within_ten_percent_of_the_truth() {
    for name in ["line", "circle", "sine", "spiral"] {
        let c = case(name);
        let trace = ridgeline::trace_points(&c.points, &Params::default()).expect("trace");
        let w = median_width(&trace.graph);
        assert!(
            (w / c.width - 1.0).abs() <= 0.1,
            "{name}: width {w} against {}",
            c.width
        );
    }
}

/// A line and a circle of random points in a band 8 units wide: one stroke with two ends, one
/// loop, by default.
#[test]
fn wide_strips_give_their_curves_by_default() {
    let line = ridgeline::trace_points(&case("line").points, &Params::default()).expect("line");
    let g = &line.graph;
    assert_eq!(g.junctions().count(), 0, "line: junctions");
    assert_eq!(g.endpoints().count(), 2, "line: ends");
    assert_eq!(g.components(), 1);
    let circle =
        ridgeline::trace_points(&case("circle").points, &Params::default()).expect("circle");
    let g = &circle.graph;
    assert_eq!(g.junctions().count(), 0, "circle: junctions");
    assert_eq!(g.endpoints().count(), 0, "circle: ends");
    assert_eq!(g.cycles(), 1);
}

/// The result does not depend on the unit: the same set scaled by 1/1024 and by 1024 (powers of
/// two, exact) gives the same graph, scaled.
#[test]
fn scaled_strips_give_the_same_graph_scaled() {
    let c = case("cross45");
    let base = ridgeline::trace_points(&c.points, &Params::default()).expect("base");
    for factor in [1.0 / 1024.0, 1024.0] {
        let scaled = c.scaled("scaled", factor);
        let trace = ridgeline::trace_points(&scaled.points, &Params::default()).expect("scaled");
        let (a, b) = (&base.graph, &trace.graph);
        assert_eq!(a.vertices.len(), b.vertices.len(), "x{factor}");
        assert_eq!(a.edges.len(), b.edges.len(), "x{factor}");
        for (u, v) in a.vertices.iter().zip(&b.vertices) {
            assert_eq!(u.degree, v.degree);
            let d = ridgeline::dist([u.pos[0] * factor, u.pos[1] * factor], v.pos);
            assert!(d <= 1e-9 * factor.max(1.0) * 1e3, "x{factor}: {u:?} {v:?}");
            assert!((u.width * factor - v.width).abs() <= 1e-6 * factor * u.width.max(1.0));
        }
    }
}

/// A uniform cloud is not strip-shaped: no curve is traced and the warning says so (not advice
/// about polarity); a strip of random points raises no such warning.
#[test]
fn a_uniform_cloud_is_reported_as_not_strip_shaped() {
    let cloud = ridgeline_testkit::synth::uniform_cloud(5_000, 200.0, 3);
    let trace = ridgeline::trace_points(&cloud, &Params::default()).expect("trace");
    let codes: Vec<&str> = trace.warnings.iter().map(|w| w.code).collect();
    assert_eq!(codes, ["not_strip_shaped"], "{:?}", trace.warnings);
    assert!(trace.graph.edges.is_empty() && trace.graph.vertices.is_empty());
    assert_eq!(trace.point_count, 5_000);
    for params in [Params::default(), Params::paper()] {
        let line = ridgeline::trace_points(&case("line").points, &params).expect("trace");
        assert!(line.warnings.is_empty(), "{:?}", line.warnings);
        assert!(!line.graph.edges.is_empty());
    }
}

/// Outliers (the figure 8 with 2 % more points drawn uniformly over a box around it): the
/// outliers, a hundredfold sparser than the strip and no strip themselves, are left out with a
/// warning that counts them, and add no vertex. A part sampled as sparsely but shaped as a strip
/// is kept.
#[test]
fn sparse_outliers_are_left_out_with_a_warning() {
    let c = case("outliers2pct");
    let clean = case("figure8");
    let extra = c.points.len() - clean.points.len();
    let trace = ridgeline::trace_points(&c.points, &Params::default()).expect("trace");
    let g = &trace.graph;
    let degrees: Vec<usize> = g.junctions().map(|v| g.vertices[v].degree).collect();
    assert_eq!(degrees, [4], "junctions");
    assert_eq!(g.endpoints().count(), 0, "ends");
    assert_eq!((g.components(), g.cycles()), (1, 2));
    let warning = trace
        .warnings
        .iter()
        .find(|w| w.code == "sparse_points_left_out")
        .unwrap_or_else(|| panic!("no warning: {:?}", trace.warnings));
    // Most of the outliers go (those that fell on the strip or next to it stay), no strip point.
    let traced = trace.point_count;
    assert!(
        traced >= clean.points.len() && traced <= clean.points.len() + extra / 4,
        "{traced} points traced"
    );
    let count = c.points.len() - traced;
    assert!(
        warning
            .message
            .starts_with(&format!("{count} of {} points", c.points.len())),
        "{}",
        warning.message
    );
    // A clean strip leaves nothing out.
    let line = case("line");
    let plain = ridgeline::trace_points(&line.points, &Params::default()).expect("line");
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    assert_eq!(plain.point_count, line.points.len());
    // A second strip as sparse as the outliers (over a hundredfold sparser than the first), far
    // from it: a strip at its own scale, so it stays.
    let mut two = line.points.clone();
    two.extend((0..80).map(|i| {
        let t = i as f64;
        [7.5 * t, 400.0 + 8.0 * ((t * 0.618_034).fract() - 0.5)]
    }));
    let trace = ridgeline::trace_points(&two, &Params::default()).expect("two");
    assert_eq!(trace.point_count, two.len(), "{:?}", trace.warnings);
    assert!(trace.warnings.is_empty(), "{:?}", trace.warnings);
}

fn junction_degrees(graph: &StrokeGraph) -> Vec<usize> {
    let mut degrees: Vec<usize> = graph
        .junctions()
        .map(|v| graph.vertices[v].degree)
        .collect();
    degrees.sort_unstable();
    degrees
}

/// Junctions of random points in bands: six arms meeting at one point give one vertex of degree 6
/// and six ends; bands 4 and 12 units wide crossing at right angles, one vertex of degree 4; a
/// figure 8 (its lobes are linear but hollow windows, no band) one crossing and two loops.
#[test]
fn strip_junctions_have_their_degree() {
    for (name, degrees, ends) in [
        ("star6", vec![6], 6),
        ("cross_w4_w12", vec![4], 4),
        ("figure8", vec![4], 0),
    ] {
        let c = case(name);
        let trace = ridgeline::trace_points(&c.points, &Params::default()).expect("trace");
        let g = &trace.graph;
        assert_eq!(junction_degrees(g), degrees, "{name}: junctions");
        assert_eq!(g.endpoints().count(), ends, "{name}: ends");
        assert_eq!(g.components(), 1, "{name}: components");
    }
}

/// Two bands crossing at 20°: they run side by side over several widths, and a window long
/// enough to call one band linear must not take in the other (the width is §3.1's PCA of one
/// band): the widths along the arms stay those of one band (their mean was 2.4 band widths).
#[test]
fn strips_crossing_at_a_small_angle_keep_one_band_width_and_one_crossing() {
    let c = case("cross20");
    let trace = ridgeline::trace_points(&c.points, &Params::default()).expect("trace");
    let widths: Vec<f64> = trace
        .graph
        .edges
        .iter()
        .flat_map(|e| e.widths.iter().copied())
        .collect();
    // The crossing itself is wider than one band; it is a small part of the arms.
    let mean = widths.iter().sum::<f64>() / widths.len() as f64;
    assert!(mean <= 1.25 * c.width, "mean width {mean}");
    let w = median_width(&trace.graph);
    assert!((w / c.width - 1.0).abs() <= 0.1, "width {w}");
    // One crossing, where the bands' centerlines cross (its two halves, found far apart along
    // the acute crossing, are joined where the strokes cross, not at their centroid).
    let g = &trace.graph;
    assert_eq!(junction_degrees(g), [4], "junctions");
    assert_eq!(g.endpoints().count(), 4, "ends");
    let crossing = g.junctions().next().map(|v| g.vertices[v].pos);
    let truth = c.junctions[0].0;
    let off = crossing.map_or(f64::INFINITY, |p| ridgeline::dist(p, truth));
    assert!(
        off <= c.width,
        "crossing {crossing:?}, {off} from the truth {truth:?}"
    );
}
