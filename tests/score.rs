//! The quality scorer: the truth scored against itself is perfect, and known damage to a
//! prediction lowers the score that measures it.

use ridgeline::{Edge, StrokeGraph, Vertex};
use ridgeline_testkit::score::{
    aggregate, fold_retraces, normalize, off_ink, score, score_with, truth_graph, truth_graph_with,
    ScoreOptions, Scores,
};
use ridgeline_testkit::synth::{render, Case, Stroke};

fn case(name: &str, strokes: Vec<Stroke>, width: u32, height: u32) -> Case {
    Case {
        name: name.to_string(),
        group: "hard".to_string(),
        binary: render(&strokes, width, height),
        strokes,
    }
}

fn line(a: [f64; 2], b: [f64; 2], w: f64) -> Stroke {
    Stroke::new(vec![a, b], w)
}

/// A line through `center` at `angle` degrees, `half` long on each side.
fn through(center: [f64; 2], angle: f64, half: f64, w: f64) -> Stroke {
    let (s, c) = angle.to_radians().sin_cos();
    line(
        [center[0] - half * c, center[1] - half * s],
        [center[0] + half * c, center[1] + half * s],
        w,
    )
}

fn circle(center: [f64; 2], radius: f64, w: f64) -> Stroke {
    let n = 72;
    let points = (0..=n)
        .map(|k| {
            let a = std::f64::consts::TAU * (k % n) as f64 / n as f64;
            [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
        })
        .collect();
    Stroke::new(points, w)
}

/// Hand-made cases covering every rule of the truth: crossings, T's (touching at the centerline
/// and at the ink's edge), overshooting tails, several ends at one point, loops, self-touching
/// and self-crossing strokes, strokes that nearly touch.
fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (angle, w) in [(90.0, 6.0), (45.0, 8.0), (30.0, 5.0), (15.0, 4.0)] {
        out.push(case(
            &format!("x{angle}_w{w}"),
            vec![
                through([50.0, 50.0], 0.0, 40.0, w),
                through([50.0, 50.0], angle, 40.0, w),
            ],
            100,
            100,
        ));
    }
    out.push(case(
        "t_center",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 6.0),
            line([50.0, 20.0], [50.0, 80.0], 6.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "t_edge",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 6.0),
            line([50.0, 80.0], [50.0, 23.5], 5.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "t_overshoot",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 8.0),
            line([50.0, 80.0], [50.0, 17.0], 4.0),
        ],
        100,
        100,
    ));
    let c = [50.0, 50.0];
    out.push(case(
        "plus_of_four",
        [[50.0, 10.0], [90.0, 50.0], [50.0, 90.0], [10.0, 50.0]]
            .iter()
            .map(|&p| line(c, p, 6.0))
            .collect(),
        100,
        100,
    ));
    out.push(case(
        "star6",
        (0..6)
            .map(|k| {
                let a = (k as f64 * 60.0 + 10.0).to_radians();
                line(c, [c[0] + 40.0 * a.cos(), c[1] + 40.0 * a.sin()], 5.0)
            })
            .collect(),
        100,
        100,
    ));
    out.push(case(
        "k",
        vec![
            line([20.0, 10.0], [20.0, 90.0], 5.0),
            line([80.0, 10.0], [20.0, 55.0], 5.0),
            line([20.0, 55.0], [80.0, 90.0], 5.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "v_corner",
        vec![
            line([20.0, 10.0], [50.0, 90.0], 5.0),
            line([50.0, 90.0], [80.0, 10.0], 5.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "circle",
        vec![circle([50.0, 50.0], 30.0, 5.0)],
        100,
        100,
    ));
    out.push(case(
        "circle_cross",
        vec![
            circle([50.0, 50.0], 30.0, 5.0),
            through([50.0, 50.0], 45.0, 40.0, 5.0),
            through([50.0, 50.0], 135.0, 40.0, 5.0),
        ],
        100,
        100,
    ));
    // A figure-8: one closed stroke crossing itself once.
    let eight: Vec<[f64; 2]> = (0..=96)
        .map(|k| {
            let t = std::f64::consts::TAU * (k % 96) as f64 / 96.0;
            [50.0 + 35.0 * t.sin(), 50.0 + 25.0 * (2.0 * t).sin()]
        })
        .collect();
    out.push(case("figure8", vec![Stroke::new(eight, 5.0)], 100, 100));
    // An 'e': the stroke starts on the bowl it draws later.
    out.push(case(
        "e",
        vec![Stroke::new(
            vec![
                [20.0, 50.0],
                [80.0, 50.0],
                [80.0, 40.0],
                [65.0, 22.0],
                [40.0, 22.0],
                [24.0, 35.0],
                [20.0, 50.0],
                [24.0, 68.0],
                [45.0, 80.0],
                [80.0, 72.0],
            ],
            5.0,
        )],
        100,
        100,
    ));
    out.push(case(
        "near_touch",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 5.0),
            line([50.0, 80.0], [50.0, 27.0], 5.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "parallel",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 4.0),
            line([10.0, 27.0], [90.0, 27.0], 4.0),
        ],
        100,
        60,
    ));
    out.push(case(
        "hash",
        vec![
            line([30.0, 10.0], [30.0, 90.0], 5.0),
            line([70.0, 10.0], [70.0, 90.0], 5.0),
            line([10.0, 30.0], [90.0, 30.0], 5.0),
            line([10.0, 70.0], [90.0, 70.0], 5.0),
        ],
        100,
        100,
    ));
    out.push(case(
        "widening",
        vec![Stroke {
            points: vec![[10.0, 50.0], [50.0, 45.0], [90.0, 50.0]],
            widths: vec![3.0, 6.0, 9.0],
        }],
        100,
        100,
    ));
    out
}

fn assert_perfect(s: &Scores) {
    let name = &s.case;
    assert!(s.exactly_right, "{name}: not exactly right {s:?}");
    for k in 0..3 {
        assert_eq!(s.f1[k], 1.0, "{name}: F1 at tau index {k}");
    }
    assert!(s.hausdorff < 0.5, "{name}: hausdorff {}", s.hausdorff);
    assert_eq!(s.junction_precision, 1.0, "{name}: junction precision");
    assert_eq!(s.junction_recall, 1.0, "{name}: junction recall");
    assert!(
        s.crossings.iter().all(|c| c.correct),
        "{name}: crossings {:?}",
        s.crossings
    );
    assert_eq!(s.spurious_endpoints, 0, "{name}: spurs");
    assert_eq!(s.endpoint_recall, 1.0, "{name}: endpoint recall");
    assert!(
        s.components_exact && s.cycles_exact,
        "{name}: components/cycles {s:?}"
    );
}

/// Degrees of the truth's vertices, sorted, and its cycle count.
fn shape(c: &Case) -> (Vec<usize>, usize) {
    let t = truth_graph(c);
    let mut degrees: Vec<usize> = t.vertices.iter().map(|v| v.degree).collect();
    degrees.sort_unstable();
    (degrees, t.cycles())
}

#[test]
fn truth_scored_against_itself_is_perfect() {
    let mut all = Vec::new();
    for c in cases() {
        let truth = truth_graph(&c);
        truth
            .validate()
            .unwrap_or_else(|e| panic!("{}: {e}", c.name));
        let s = score(&c, &truth, &truth);
        assert_perfect(&s);
        // The truth of a case drawn from its strokes lies on its ink.
        assert_eq!(s.off_ink, 0.0, "{}: off-ink {}", c.name, s.off_ink);
        assert!(s.centerline_length > 0.0, "{}", c.name);
        all.push(s);
    }
    let group = aggregate(&all);
    assert_eq!(group.cases, all.len());
    assert_eq!(group.exactly_right, 1.0);
    assert_eq!(group.off_ink, 0.0);
    assert_eq!(group.f1, [1.0; 3]);
    assert_eq!(group.crossing_accuracy, Some(1.0));
    assert_eq!(group.shallow_crossing_accuracy, Some(1.0));
    assert_eq!(group.components_exact, 1.0);
}

#[test]
fn truth_follows_the_ink() {
    let by_name = |name: &str| cases().into_iter().find(|c| c.name == name).unwrap();
    // Crossings are degree-4 vertices, whatever the angle.
    for name in ["x90_w6", "x45_w8", "x30_w5", "x15_w4"] {
        assert_eq!(shape(&by_name(name)), (vec![1, 1, 1, 1, 4], 0), "{name}");
    }
    // A stem ending on the bar's centerline, at its ink's edge, or a little past it: a T.
    for name in ["t_center", "t_edge", "t_overshoot"] {
        assert_eq!(shape(&by_name(name)), (vec![1, 1, 1, 3], 0), "{name}");
    }
    // Four strokes from one point: one degree-4 vertex; six: degree 6; two T's at one point: 4.
    assert_eq!(shape(&by_name("plus_of_four")), (vec![1, 1, 1, 1, 4], 0));
    assert_eq!(shape(&by_name("star6")), (vec![1, 1, 1, 1, 1, 1, 6], 0));
    assert_eq!(shape(&by_name("k")), (vec![1, 1, 1, 1, 4], 0));
    // Two strokes sharing an end are one stroke with a corner.
    assert_eq!(shape(&by_name("v_corner")), (vec![1, 1], 0));
    assert_eq!(shape(&by_name("circle")), (vec![2], 1));
    assert_eq!(shape(&by_name("figure8")), (vec![4], 2));
    assert_eq!(shape(&by_name("e")), (vec![1, 3], 1));
    // The circle with a cross: 4 crossings on the circle and one in the middle.
    assert_eq!(
        shape(&by_name("circle_cross")),
        (vec![1, 1, 1, 1, 4, 4, 4, 4, 4], 4)
    );
    // Inks 2 px apart do not touch.
    assert_eq!(truth_graph(&by_name("near_touch")).components(), 2);
    assert_eq!(truth_graph(&by_name("parallel")).components(), 2);
}

fn shifted(g: &StrokeGraph, d: [f64; 2]) -> StrokeGraph {
    let mut out = g.clone();
    let mv = |p: &mut [f64; 2]| {
        p[0] += d[0];
        p[1] += d[1];
    };
    out.vertices.iter_mut().for_each(|v| mv(&mut v.pos));
    out.edges
        .iter_mut()
        .for_each(|e| e.points.iter_mut().for_each(mv));
    out
}

#[test]
fn shift_by_one_and_a_half_pixels() {
    let c = case(
        "bars",
        vec![
            line([10.0, 20.0], [90.0, 20.0], 5.0),
            line([10.0, 40.0], [90.0, 40.0], 5.0),
            line([10.0, 60.0], [90.0, 62.0], 5.0),
        ],
        100,
        100,
    );
    let truth = truth_graph(&c);
    let s = score(&c, &truth, &shifted(&truth, [0.0, 1.5]));
    assert!(s.f1[0] < 0.5, "F1@1 {}", s.f1[0]);
    assert_eq!(s.f1[1], 1.0);
    assert!((s.chamfer - 1.5).abs() < 0.1, "chamfer {}", s.chamfer);
}

#[test]
fn deleting_an_edge_lowers_recall() {
    let c = cases().into_iter().find(|c| c.name == "hash").unwrap();
    let truth = truth_graph(&c);
    let mut damaged = truth.clone();
    let longest = (0..damaged.edges.len())
        .max_by(|&a, &b| {
            damaged.edges[a]
                .length()
                .total_cmp(&damaged.edges[b].length())
        })
        .unwrap();
    let e = damaged.edges.remove(longest);
    damaged.vertices[e.from].degree -= 1;
    damaged.vertices[e.to].degree -= 1;
    let s = score(&c, &truth, &damaged);
    assert!(s.recall[1] < 0.95, "recall {}", s.recall[1]);
    assert_eq!(s.precision[1], 1.0);
    assert!(!s.cycles_exact);
}

/// Replaces the degree-4 vertex of an X by two Y's joined by a bridge 6 px long, the way thinning
/// draws a crossing: each Y takes two neighbouring arms and sits 3 px out between them.
fn two_ys(truth: &StrokeGraph) -> StrokeGraph {
    let x = truth.vertices.iter().position(|v| v.degree == 4).unwrap();
    let c = truth.vertices[x].pos;
    let mut out = truth.clone();
    // Each arm: (angle, edge, at start).
    let mut arms: Vec<(f64, usize, bool)> = Vec::new();
    for (i, e) in out.edges.iter().enumerate() {
        for at_start in [true, false] {
            if (at_start && e.from == x) || (!at_start && e.to == x) {
                let k = if at_start { 1 } else { e.points.len() - 2 };
                let d = [e.points[k][0] - c[0], e.points[k][1] - c[1]];
                arms.push((d[1].atan2(d[0]), i, at_start));
            }
        }
    }
    arms.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = out.vertices.len();
    for pair in arms.chunks(2) {
        let mid = [
            (pair[0].0.cos() + pair[1].0.cos()),
            (pair[0].0.sin() + pair[1].0.sin()),
        ];
        let n = mid[0].hypot(mid[1]);
        let pos = [c[0] + 3.0 * mid[0] / n, c[1] + 3.0 * mid[1] / n];
        let y = out.vertices.len();
        out.vertices.push(Vertex {
            pos,
            degree: 3,
            width: truth.vertices[x].width,
        });
        for &(_, i, at_start) in pair {
            let e = &mut out.edges[i];
            if at_start {
                e.from = y;
                e.points[0] = pos;
            } else {
                e.to = y;
                let last = e.points.len() - 1;
                e.points[last] = pos;
            }
        }
    }
    out.vertices[x].degree = 0;
    let (a, b) = (out.vertices[first].pos, out.vertices[first + 1].pos);
    out.edges.push(Edge {
        from: first,
        to: first + 1,
        points: vec![a, b],
        widths: vec![5.0; 2],
        directions: vec![[1.0, 0.0]; 2],
    });
    out.validate().unwrap();
    out
}

#[test]
fn two_ys_for_an_x_fail_the_crossing() {
    for name in ["x90_w6", "x45_w8"] {
        let c = cases().into_iter().find(|c| c.name == name).unwrap();
        let truth = truth_graph(&c);
        let s = score(&c, &truth, &two_ys(&truth));
        assert_eq!(s.crossing_accuracy, Some(0.0), "{name}");
        assert!(s.junction_precision < 1.0, "{name}");
        // The geometry barely changes.
        assert!(s.f1[2] > 0.95, "{name}: F1@3 {}", s.f1[2]);
    }
}

#[test]
fn prediction_is_normalized_with_one_pixel_tolerance() {
    // Two polylines crossing without a vertex, and a stem stopping 0.8 px short of a bar.
    let edge = |a: [f64; 2], b: [f64; 2], from, to| Edge {
        from,
        to,
        points: vec![a, b],
        widths: vec![5.0; 2],
        directions: vec![[1.0, 0.0]; 2],
    };
    let vertex = |pos| Vertex {
        pos,
        degree: 1,
        width: 5.0,
    };
    let g = StrokeGraph {
        width: 100,
        height: 100,
        vertices: [
            [10.0, 50.0],
            [90.0, 50.0],
            [50.0, 10.0],
            [50.0, 90.0],
            [70.0, 50.8],
            [70.0, 80.0],
        ]
        .into_iter()
        .map(vertex)
        .collect(),
        edges: vec![
            edge([10.0, 50.0], [90.0, 50.0], 0, 1),
            edge([50.0, 10.0], [50.0, 90.0], 2, 3),
            edge([70.0, 50.8], [70.0, 80.0], 4, 5),
        ],
    };
    let n = normalize(&case("blank", vec![], 100, 100), &g);
    n.validate().unwrap();
    let mut degrees: Vec<usize> = n.vertices.iter().map(|v| v.degree).collect();
    degrees.sort_unstable();
    assert_eq!(degrees, vec![1, 1, 1, 1, 1, 3, 4]);
}

#[test]
fn broken_predictions_do_not_panic() {
    let c = cases().into_iter().next().unwrap();
    let truth = truth_graph(&c);
    let empty = StrokeGraph::default();
    let s = score(&c, &truth, &empty);
    assert_eq!(s.f1, [0.0; 3]);
    assert_eq!(s.junction_recall, 0.0);
    let mut bad = truth.clone();
    bad.edges[0].to = 999;
    bad.edges[1].points = vec![[f64::NAN, 1.0], [2.0, 2.0]];
    bad.edges[2].points.truncate(1);
    let s = score(&c, &truth, &bad);
    assert!(s.recall[1] < 1.0);
}

#[test]
fn truth_of_every_generated_case_scored_against_itself_is_perfect() {
    let cases = ridgeline_testkit::synth::all_cases();
    assert!(!cases.is_empty());
    for c in &cases {
        let truth = truth_graph(c);
        truth
            .validate()
            .unwrap_or_else(|e| panic!("{}: {e}", c.name));
        assert_perfect(&score(c, &truth, &truth));
    }
}

#[test]
fn truth_of_every_crowded_case_scored_against_itself_is_perfect() {
    for group in ridgeline_testkit::synth::CROWDED_GROUPS {
        let cases = ridgeline_testkit::synth::group_cases(group).expect("known group");
        assert!(!cases.is_empty(), "{group}");
        for c in &cases {
            let truth = truth_graph(c);
            truth
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", c.name));
            let s = score(c, &truth, &truth);
            assert_perfect(&s);
            // A merged or collapsed vertex can sit on a speck of background; nothing more.
            assert!(s.off_ink < 0.01, "{}: truth off-ink {}", c.name, s.off_ink);
        }
    }
}

#[test]
fn off_ink_measures_centerline_over_background() {
    // A 5 px bar along row 20, and a polyline from its middle out over the background.
    let c = case("bar", vec![line([10.5, 20.5], [90.5, 20.5], 5.0)], 100, 60);
    let edge = |points: Vec<[f64; 2]>| Edge {
        from: 0,
        to: 1,
        widths: vec![5.0; points.len()],
        directions: vec![[1.0, 0.0]; points.len()],
        points,
    };
    let graph = |points: Vec<[f64; 2]>| StrokeGraph {
        width: 100,
        height: 60,
        vertices: vec![
            Vertex {
                pos: points[0],
                degree: 1,
                width: 5.0,
            },
            Vertex {
                pos: points[points.len() - 1],
                degree: 1,
                width: 5.0,
            },
        ],
        edges: vec![edge(points)],
    };
    let on = off_ink(&graph(vec![[20.5, 20.5], [80.5, 20.5]]), &c.binary);
    assert!((on.length - 60.0).abs() < 1e-9);
    assert_eq!(on.off, 0.0);
    assert_eq!(on.share(), 0.0);
    // Up from the bar's centerline: 2.5 px of ink (rows 20..=22 reach y = 23), then 17.5 px of
    // background.
    let out = off_ink(&graph(vec![[50.5, 20.5], [50.5, 40.5]]), &c.binary);
    assert!((out.length - 20.0).abs() < 1e-9);
    assert!((out.off - 17.5).abs() < 0.5 + 1e-9, "off {}", out.off);
    // Outside the image counts as background; an empty graph has no centerline.
    let outside = off_ink(&graph(vec![[-10.0, -10.0], [-20.0, -10.0]]), &c.binary);
    assert_eq!(outside.share(), 1.0);
    assert_eq!(off_ink(&StrokeGraph::default(), &c.binary).share(), 0.0);
}

#[test]
fn a_graph_shifted_off_the_ink_is_off_ink() {
    let c = cases().into_iter().find(|c| c.name == "hash").unwrap();
    let truth = truth_graph(&c);
    let s = score(&c, &truth, &truth);
    assert_eq!(s.off_ink, 0.0);
    // The bars are 5 px wide: 4 px down moves every horizontal bar off its ink (the vertical
    // ones stay on theirs for most of their length).
    let moved = score(&c, &truth, &shifted(&truth, [0.0, 4.0]));
    assert!(moved.off_ink > 0.3, "off-ink {}", moved.off_ink);
    let far = score(&c, &truth, &shifted(&truth, [4.0, 4.0]));
    assert!(
        far.off_ink > moved.off_ink,
        "{} {}",
        far.off_ink,
        moved.off_ink
    );
}

#[test]
fn a_missing_junction_or_an_extra_end_is_not_exactly_right() {
    // A T whose stem stops short of the bar: no junction, an extra end, two components.
    let c = cases().into_iter().find(|c| c.name == "t_center").unwrap();
    let truth = truth_graph(&c);
    assert_eq!(truth.junctions().count(), 1);
    let mut broken = truth.clone();
    let stem = broken
        .edges
        .iter()
        .position(|e| {
            let (a, b) = (e.points[0], e.points[e.points.len() - 1]);
            (a[0] - b[0]).abs() < 1.0
        })
        .expect("the vertical stem");
    let e = &mut broken.edges[stem];
    let (junction_at_start, k) = if broken.vertices[e.from].degree == 3 {
        (true, 0)
    } else {
        (false, e.points.len() - 1)
    };
    e.points[k][1] += 8.0;
    let j = if junction_at_start { e.from } else { e.to };
    let end = broken.vertices.len();
    broken.vertices.push(Vertex {
        pos: e.points[k],
        degree: 1,
        width: 6.0,
    });
    if junction_at_start {
        e.from = end;
    } else {
        e.to = end;
    }
    broken.vertices[j].degree -= 1;
    broken.validate().unwrap();
    let s = score(&c, &truth, &broken);
    assert_eq!(s.junction_recall, 0.0);
    assert!(!s.exactly_right);
    // The X read as two Y's: every end is right, the junctions are not.
    let x = cases().into_iter().find(|c| c.name == "x90_w6").unwrap();
    let truth = truth_graph(&x);
    let s = score(&x, &truth, &two_ys(&truth));
    assert_eq!(s.endpoint_recall, 1.0);
    assert_eq!(s.spurious_endpoints, 0);
    assert!(!s.exactly_right);
    // A spur off a bar: an extra junction and a spurious end, the geometry all but unchanged.
    let mut spurred = truth.clone();
    let e = spurred.edges[0].clone();
    let m = e.points.len() / 2;
    let (j, tip) = (spurred.vertices.len(), spurred.vertices.len() + 1);
    let at = e.points[m];
    spurred.vertices.push(Vertex {
        pos: at,
        degree: 3,
        width: 6.0,
    });
    spurred.vertices.push(Vertex {
        pos: [at[0] - 2.0, at[1] - 2.0],
        degree: 1,
        width: 6.0,
    });
    let piece = |from, to, points: Vec<[f64; 2]>| Edge {
        from,
        to,
        widths: vec![6.0; points.len()],
        directions: vec![[1.0, 0.0]; points.len()],
        points,
    };
    spurred.edges[0] = piece(e.from, j, e.points[..=m].to_vec());
    spurred.edges.push(piece(j, e.to, e.points[m..].to_vec()));
    spurred
        .edges
        .push(piece(j, tip, vec![at, [at[0] - 2.0, at[1] - 2.0]]));
    spurred.validate().unwrap();
    let s = score(&x, &truth, &spurred);
    assert_eq!(s.spurious_endpoints, 1);
    assert!(s.f1[1] > 0.99);
    assert!(!s.exactly_right);
}

#[test]
fn three_crossings_closer_than_the_ink_shows_are_one_vertex() {
    // Three lines, each 2 px (tight) or 8 px (apart) from the center, normals 120 degrees apart,
    // so they bound a triangle around it with that inradius.
    let triple = |name: &str, offset: f64| {
        let strokes = [(0.0f64, 1.0), (60.0, -1.0), (120.0, 1.0)]
            .iter()
            .map(|&(a, side)| {
                let (sn, cs) = (a + 10.0).to_radians().sin_cos();
                let n = [-sn * side, cs * side];
                let p = [60.0 + n[0] * offset, 60.0 + n[1] * offset];
                line(
                    [p[0] - 50.0 * cs, p[1] - 50.0 * sn],
                    [p[0] + 50.0 * cs, p[1] + 50.0 * sn],
                    6.0,
                )
            })
            .collect();
        case(name, strokes, 120, 120)
    };
    // Inradius 3 = half the width: the triangle's sides are 10.4 px, farther apart than one
    // width, but no background is left inside; the ink shows one degree-6 blob.
    let tight = triple("tight", 3.0);
    assert_eq!(shape(&tight), (vec![1, 1, 1, 1, 1, 1, 6], 0));
    // Inradius 8 leaves a hole: three crossings and the triangle between them.
    let apart = triple("apart", 8.0);
    assert_eq!(shape(&apart), (vec![1, 1, 1, 1, 1, 1, 4, 4, 4], 1));
    for c in [&tight, &apart] {
        let t = truth_graph(c);
        assert_perfect(&score(c, &t, &t));
    }
}

#[test]
fn strokes_whose_inks_touch_are_joined() {
    // Two rings whose centerlines pass 6.5 px apart: their 6 px inks touch (rows 8-adjacent)
    // without crossing or ending there; the ink is one component around two holes.
    let rings = case(
        "rings",
        vec![
            circle([30.0, 40.0], 15.0, 6.0),
            circle([66.5, 40.0], 15.0, 6.0),
        ],
        100,
        80,
    );
    let t = truth_graph(&rings);
    assert_eq!((t.components(), t.cycles()), (1, 2));
    assert_perfect(&score(&rings, &t, &t));
    // A bar grazing a ring's top, and one 2 px of background farther off.
    for (gap, components) in [(6.5, 1), (9.0, 2)] {
        let c = case(
            "ring_and_bar",
            vec![
                circle([50.0, 50.0], 20.0, 6.0),
                line([10.0, 30.0 - gap], [90.0, 30.0 - gap], 6.0),
            ],
            100,
            90,
        );
        let t = truth_graph(&c);
        assert_eq!((t.components(), t.cycles()), (components, 1), "gap {gap}");
        assert_perfect(&score(&c, &t, &t));
    }
}

#[test]
fn holes_can_come_from_the_binary() {
    // A ring drawn from its strokes has one hole either way; with the ring's middle filled in
    // the binary (ink not drawn from the strokes), only the binary's holes say there is none.
    let ring = case("ring", vec![circle([50.0, 50.0], 20.0, 5.0)], 100, 100);
    let binary_holes = ScoreOptions {
        holes_from_binary: true,
        ..ScoreOptions::default()
    };
    assert_eq!(truth_graph_with(&ring, &binary_holes).cycles(), 1);
    let mut filled = ring.clone();
    for y in 25..75 {
        for x in 25..75 {
            if (x as f64 + 0.5 - 50.0).hypot(y as f64 + 0.5 - 50.0) < 20.0 {
                filled.binary.set(x, y, true);
            }
        }
    }
    assert_eq!(truth_graph(&filled).cycles(), 1);
    let t = truth_graph_with(&filled, &binary_holes);
    assert_eq!(t.cycles(), 0);
    // Wider tolerances are reported as such.
    let wide = ScoreOptions {
        taus: [2.5, 5.0, 7.5],
        ..binary_holes
    };
    let s = score_with(&filled, &t, &t, &wide);
    assert_eq!(s.taus, [2.5, 5.0, 7.5]);
    assert!(s.exactly_right);
}

/// The ends (degree 1) and dots (degree 0) of a truth, and its junction count.
fn ends_dots_junctions(t: &StrokeGraph) -> (Vec<[f64; 2]>, usize, usize) {
    let ends = t.endpoints().map(|v| t.vertices[v].pos).collect();
    let dots = t.vertices.iter().filter(|v| v.degree == 0).count();
    (ends, dots, t.junctions().count())
}

#[test]
fn filled_loops_can_be_read_as_the_strokes_their_ink_shows() {
    let loops = ScoreOptions {
        filled_loops_as_strokes: true,
        ..ScoreOptions::default()
    };
    let near = |ends: &[[f64; 2]], p: [f64; 2]| ends.iter().any(|&e| ridgeline::dist(e, p) <= 1.5);

    // A bar ending in a triangle the pen fills (the Hershey Japanese font's end ornament): its
    // ink runs on to the triangle's far corner, 14 px past where the bar meets the triangle.
    let bar = Stroke::new(
        vec![
            [10.0, 30.0],
            [60.0, 30.0],
            [66.0, 22.0],
            [74.0, 30.0],
            [60.0, 30.0],
        ],
        6.0,
    );
    let c = case("bar_triangle", vec![bar], 90, 45);
    let (ends, _, junctions) = ends_dots_junctions(&truth_graph(&c));
    assert!(
        near(&ends, [60.0, 30.0]),
        "by default at the base: {ends:?}"
    );
    let t = truth_graph_with(&c, &loops);
    let (ends, dots, junctions_read) = ends_dots_junctions(&t);
    assert_eq!(
        (ends.len(), dots, junctions_read),
        (2, 0, junctions),
        "{ends:?}"
    );
    assert!(
        near(&ends, [10.0, 30.0]) && near(&ends, [74.0, 30.0]),
        "{ends:?}"
    );
    assert!(score_with(&c, &t, &t, &loops).exactly_right);

    // A teardrop outline filled by the pen is a stroke with two ends; a round one is a dot.
    let teardrop = Stroke::new(
        vec![
            [20.0, 30.0],
            [24.0, 27.0],
            [44.0, 30.0],
            [24.0, 33.0],
            [20.0, 30.0],
        ],
        6.0,
    );
    let c = case("teardrop", vec![teardrop], 60, 60);
    assert_eq!(ends_dots_junctions(&truth_graph(&c)).1, 1);
    let t = truth_graph_with(&c, &loops);
    let (ends, dots, _) = ends_dots_junctions(&t);
    assert_eq!((ends.len(), dots), (2, 0), "{ends:?}");
    assert!(score_with(&c, &t, &t, &loops).exactly_right);
    let c = case("round_dot", vec![circle([30.0, 30.0], 2.0, 6.0)], 60, 60);
    let (ends, dots, _) = ends_dots_junctions(&truth_graph_with(&c, &loops));
    assert_eq!((ends.len(), dots), (0, 1), "{ends:?}");

    // A loop around a hole stays a cycle.
    let c = case("ring", vec![circle([50.0, 50.0], 20.0, 5.0)], 100, 100);
    assert_eq!(truth_graph_with(&c, &loops).cycles(), 1);
}

#[test]
fn retraces_can_be_read_as_the_arms_their_ink_shows() {
    let folds = ScoreOptions {
        retraces_as_arms: true,
        ..ScoreOptions::default()
    };
    let near = |ends: &[[f64; 2]], p: [f64; 2]| ends.iter().any(|&e| ridgeline::dist(e, p) <= 1.5);

    // The peak of a script `u`: the pen goes up to (40, 10), comes back down over its own ink
    // and leaves it at (40, 40) to the right. The ink shows a stem with an arm up: a T at the
    // foot of the stem and an end at the peak, which the pen-path truth reads as one line.
    let u = Stroke::new(
        vec![
            [10.0, 40.0],
            [40.0, 40.0],
            [40.0, 10.0],
            [40.0, 40.0],
            [70.0, 40.0],
        ],
        4.0,
    );
    let c = case("u_peak", vec![u], 80, 50);
    let (ends, _, junctions) = ends_dots_junctions(&truth_graph(&c));
    assert_eq!(
        (ends.len(), junctions),
        (2, 0),
        "by default one line: {ends:?}"
    );
    let t = truth_graph_with(&c, &folds);
    let (ends, dots, junctions) = ends_dots_junctions(&t);
    assert_eq!((ends.len(), dots, junctions), (3, 0, 1), "{ends:?}");
    assert!(near(&ends, [40.0, 10.0]), "{ends:?}");
    assert!(score_with(&c, &t, &t, &folds).exactly_right);

    // A narrow V and a sharp one whose legs overlap only near the tip, a hook whose
    // return runs a width beside its way out (a wedge) and a closed ring are no retrace.
    let narrow = Stroke::new(
        vec![
            [10.0, 40.0],
            [40.0, 40.0],
            [46.0, 10.0],
            [52.0, 40.0],
            [80.0, 40.0],
        ],
        3.0,
    );
    let v = Stroke::new(vec![[10.0, 10.0], [40.0, 40.0], [50.0, 5.0]], 4.0);
    let hook = Stroke::new(
        vec![[10.0, 20.0], [50.0, 20.0], [47.0, 24.0], [30.0, 24.0]],
        4.0,
    );
    for (name, stroke, w, h) in [
        ("narrow_v", narrow, 90, 50),
        ("sharp_v", v, 60, 50),
        ("wedge_hook", hook, 60, 40),
        ("ring", circle([30.0, 30.0], 12.0, 4.0), 60, 60),
    ] {
        let c = case(name, vec![stroke.clone()], w, h);
        assert_eq!(fold_retraces(&c.strokes, &c.binary), vec![stroke], "{name}");
        assert_eq!(truth_graph_with(&c, &folds), truth_graph(&c), "{name}");
    }
}

#[test]
fn a_short_arm_whose_cap_touches_the_stroke_it_leaves_is_an_arm() {
    // A bar and a stub square to it, whose centerline ends `reach` px from the bar's. The stub's
    // foot lies on the bar and its cap's ink touches the bar's (a width long): both ends would
    // join the bar. The ink shows an arm when the stub's centerline ends beyond the bar's ink
    // (half a width and half a pixel), as a tail past a crossed stroke is one; nearer, a bump.
    for w in [4.0, 8.0, 12.0] {
        for (reach, arm) in [(w, true), (1.5 * w, true), (w / 2.0 + 0.25, false)] {
            let bar = line([10.5, 40.5], [110.5, 40.5], w);
            let stub = line([60.5, 40.5], [60.5, 40.5 - reach], w);
            let case = case("stub", vec![bar, stub], 121, 61);
            let truth = truth_graph(&case);
            let (ends, junctions) = (truth.endpoints().count(), truth.junctions().count());
            let expected = if arm { (3, 1) } else { (2, 0) };
            assert_eq!((ends, junctions), expected, "w {w}, reach {reach}");
        }
    }
}
