//! Point sets in space, the paper's Fig. 7: tubes of random points around known space curves
//! (`ridgeline_testkit::synth::tube_cases`), read from every point-file format and written as
//! JSON with `z`, PLY and OBJ.

use std::fs;

use ridgeline::point_list::{read, PointData};
use ridgeline::{CurveGraph3d, Params};
use ridgeline_testkit::synth::{tube_cases, TubeCase};

use crate::support::{median, ridgeline, run_ok, stderr, temp_dir};

fn case(name: &str) -> TubeCase {
    tube_cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no tube case {name}"))
}

fn median_width(graph: &CurveGraph3d) -> f64 {
    median(graph.edges.iter().flat_map(|e| e.widths.iter().copied()))
}

/// The largest distance from a true centerline sample to the traced polylines' points.
fn farthest_miss(graph: &CurveGraph3d, case: &TubeCase) -> f64 {
    let traced: Vec<[f64; 3]> = graph
        .edges
        .iter()
        .flat_map(|e| e.points.iter().copied())
        .collect();
    case.curves
        .iter()
        .flat_map(|c| c.points.iter().step_by(8))
        .map(|&t| {
            traced
                .iter()
                .map(|&p| ridgeline::dist3(p, t))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// A helix: one curve, two ends where the tube ends, its diameter within 10 %, on the curve.
#[test]
fn a_helix_is_one_curve_with_its_diameter() {
    let c = case("helix");
    let trace = ridgeline::trace_points3d(&c.points, &Params::default()).expect("trace");
    let g = &trace.graph;
    g.validate().expect("valid graph");
    assert_eq!(g.junctions().count(), 0, "junctions");
    assert_eq!(g.endpoints().count(), 2, "ends");
    assert_eq!(g.components(), 1);
    for end in g.endpoints() {
        let near = c
            .ends
            .iter()
            .map(|&e| ridgeline::dist3(e, g.vertices[end].pos))
            .fold(f64::INFINITY, f64::min);
        assert!(
            near < 0.5 * c.width,
            "end {end} is {near} from the true end"
        );
    }
    let w = median_width(g);
    assert!(
        (w / c.width - 1.0).abs() <= 0.1,
        "diameter {w} against {}",
        c.width
    );
    // Polyline nodes are a few diameters apart, so a true sample lies within one of them.
    let miss = farthest_miss(g, &c);
    assert!(miss < 2.0 * c.width, "a true sample {miss} from the trace");
}

/// A Y in space: one junction of degree 3 at the true one, three ends; a trefoil knot: one closed
/// curve, no junction.
#[test]
fn a_y_in_space_and_a_knot() {
    let c = case("y_3d");
    let trace = ridgeline::trace_points3d(&c.points, &Params::default()).expect("trace");
    let g = &trace.graph;
    let junctions: Vec<usize> = g.junctions().collect();
    assert_eq!(junctions.len(), 1, "junctions");
    let j = &g.vertices[junctions[0]];
    assert_eq!(j.degree, 3);
    assert!(
        ridgeline::dist3(j.pos, c.junctions[0].0) < c.width,
        "{:?}",
        j.pos
    );
    assert_eq!(g.endpoints().count(), 3);
    let c = case("trefoil");
    let trace = ridgeline::trace_points3d(&c.points, &Params::default()).expect("trace");
    let g = &trace.graph;
    assert_eq!(g.junctions().count(), 0);
    assert_eq!(g.endpoints().count(), 0);
    assert_eq!((g.components(), g.cycles()), (1, 1));
}

/// The same set in other units (scaled by powers of two, exact) gives the same graph, scaled;
/// the same points in another order give the same topology.
#[test]
fn scaled_tubes_give_the_same_graph_scaled() {
    let c = case("crossing_tubes");
    let base = ridgeline::trace_points3d(&c.points, &Params::default()).expect("trace");
    assert_eq!(base.graph.junctions().count(), 1);
    assert_eq!(
        base.graph.vertices[base.graph.junctions().next().unwrap()].degree,
        4
    );
    for factor in [1.0 / 1024.0, 1024.0] {
        let scaled: Vec<[f64; 3]> = c.points.iter().map(|p| p.map(|x| x * factor)).collect();
        let trace = ridgeline::trace_points3d(&scaled, &Params::default()).expect("scaled");
        let g = &trace.graph;
        assert_eq!(g.vertices.len(), base.graph.vertices.len());
        assert_eq!(g.edges.len(), base.graph.edges.len());
        for (a, b) in g.vertices.iter().zip(&base.graph.vertices) {
            assert_eq!(a.degree, b.degree);
            let back = a.pos.map(|x| x / factor);
            assert!(
                ridgeline::dist3(back, b.pos) < 1e-6 * c.width,
                "{back:?} {:?}",
                b.pos
            );
        }
    }
}

/// A cloud filling a cube is no tube: a warning says so and nothing is traced.
#[test]
fn a_uniform_cloud_in_space_is_not_traced() {
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 40.0
    };
    let cloud: Vec<[f64; 3]> = (0..6000).map(|_| [next(), next(), next()]).collect();
    let trace = ridgeline::trace_points3d(&cloud, &Params::default()).expect("trace");
    assert!(trace.graph.vertices.is_empty());
    assert_eq!(trace.warnings.len(), 1);
    assert_eq!(trace.warnings[0].code, "not_strip_shaped");
}

/// Every point-file format gives the same points: x y z lines, CSV with its columns named in
/// another order, XYZ with normals after the coordinates, PLY in ASCII and binary.
#[test]
fn every_format_reads_the_same_points() {
    let points = [[1.5, -2.0, 3.25], [0.0, 4.0, -1.0], [7.0, 8.0, 9.5]];
    let lines: String = points
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    let csv: String = "id,z,X,y\n".to_string()
        + &points
            .iter()
            .enumerate()
            .map(|(i, p)| format!("{i},{},{},{}\n", p[2], p[0], p[1]))
            .collect::<String>();
    let xyz: String = points
        .iter()
        .map(|p| format!("{} {} {} 0 0 1\n", p[0], p[1], p[2]))
        .collect();
    let mut ascii =
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
        property float z\nend_header\n"
            .to_vec();
    ascii.extend(lines.bytes());
    let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property double x\nproperty double y\nproperty double z\nend_header\n"
        .to_vec();
    for p in points {
        for x in p {
            binary.extend(f64::to_le_bytes(x));
        }
    }
    let want = PointData::Space(points.to_vec());
    assert_eq!(read(lines.as_bytes(), Some("txt")).unwrap(), want);
    assert_eq!(read(csv.as_bytes(), Some("csv")).unwrap(), want);
    assert_eq!(read(xyz.as_bytes(), Some("xyz")).unwrap(), want);
    assert_eq!(read(&ascii, None).unwrap(), want);
    assert_eq!(read(&binary, Some("ply")).unwrap(), want);
    // The plane stays the plane.
    assert_eq!(
        read(b"x,y\n1,2\n3,4\n", Some("csv")).unwrap(),
        PointData::Plane(vec![[1.0, 2.0], [3.0, 4.0]])
    );
    assert_eq!(
        read(b"name;y;x\na;2;1\n", None).unwrap(),
        PointData::Plane(vec![[1.0, 2.0]])
    );
}

/// Bad point files are errors that say what is wrong, never panics.
#[test]
fn bad_point_files_are_clear_errors() {
    let message = |bytes: &[u8], extension: Option<&str>| match read(bytes, extension) {
        Err(e) => e.to_string(),
        Ok(data) => panic!("read {} points from a bad file", data.len()),
    };
    assert!(message(b"1 2 3\n4 5\n", None).contains("line 2"));
    assert!(message(b"1 2 3 4\n", None).contains("2 or 3 numbers"));
    assert!(message(b"1 2\n", Some("xyz")).contains("3 numbers"));
    assert!(message(b"x,y,z\n1,2,abc\n", None).contains("z 'abc' is not a number"));
    assert!(message(b"x,y,z\n1,2\n", None).contains("line 2"));
    assert!(message(b"1 2 inf\n", None).contains("not finite"));
    assert!(message(&[0xff, 0xfe, 0x00], None).contains("not text"));
    assert!(message(b"ply\nformat ascii 1.0\n", None).contains("end_header"));
    assert!(message(b"not a ply\n", Some("ply")).contains("ply"));
}

/// The command line: a PLY file in, JSON with `z`, PLY and OBJ out, each read back; an SVG of a
/// 3D set is an error that says what to write instead.
#[test]
fn the_command_line_writes_json_ply_and_obj_that_read_back() {
    let dir = temp_dir();
    let c = case("y_3d");
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nend_header\n",
        c.points.len()
    )
    .into_bytes();
    for p in &c.points {
        for x in p {
            ply.extend((*x as f32).to_le_bytes());
        }
    }
    fs::write(dir.path().join("y.ply"), ply).unwrap();
    run_ok(&["y.ply", "-o", "y.json"], dir.path());
    let json: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("y.json")).unwrap()).unwrap();
    assert_eq!(json["parameters"]["input"], "points3d");
    assert_eq!(json["stats"]["junctions"], 1);
    assert_eq!(json["stats"]["endpoints"], 3);
    assert!(json.get("timings").is_none(), "no times unless asked");
    // `--timings`: a set in space records its wall time only, and the graph is the same.
    run_ok(&["y.ply", "--timings", "-o", "timed.json"], dir.path());
    let timed: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.path().join("timed.json")).unwrap()).unwrap();
    let timings = timed["timings"].as_object().expect("timings");
    assert_eq!(timings.keys().collect::<Vec<_>>(), ["wall"]);
    assert!(timings["wall"].as_f64().unwrap() > 0.0);
    assert_eq!(timed["edges"], json["edges"]);
    let vertices = json["vertices"].as_array().unwrap();
    assert!(vertices.iter().all(|v| v["z"].is_number()));
    let edge = &json["edges"][0];
    assert!(edge["points"]
        .as_array()
        .unwrap()
        .iter()
        .all(|p| p.as_array().unwrap().len() == 3));

    run_ok(&["y.ply", "-o", "curve.ply"], dir.path());
    let out = fs::read(dir.path().join("curve.ply")).unwrap();
    let PointData::Space(back) = read(&out, Some("ply")).expect("our PLY reads back") else {
        panic!("a PLY reads as points in space");
    };
    let text = String::from_utf8(out).unwrap();
    let edges_line = text
        .lines()
        .find(|l| l.starts_with("element edge "))
        .expect("an edge element");
    let segments: usize = edges_line["element edge ".len()..].parse().unwrap();
    let body: Vec<&str> = text.split("end_header\n").nth(1).unwrap().lines().collect();
    assert_eq!(body.len(), back.len() + segments);
    // Every segment joins two listed vertices; the junction's vertex has three segments.
    let mut degree = vec![0usize; back.len()];
    for line in &body[back.len()..] {
        let ends: Vec<usize> = line.split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!(ends.len(), 2);
        degree[ends[0]] += 1;
        degree[ends[1]] += 1;
    }
    assert_eq!(degree.iter().filter(|&&d| d == 3).count(), 1);
    assert_eq!(degree.iter().filter(|&&d| d == 1).count(), 3);

    run_ok(&["y.ply", "-o", "curve.obj"], dir.path());
    let obj = fs::read_to_string(dir.path().join("curve.obj")).unwrap();
    let count = obj.lines().filter(|l| l.starts_with("v ")).count();
    assert_eq!(count, back.len());
    let polylines: Vec<&str> = obj.lines().filter(|l| l.starts_with("l ")).collect();
    assert_eq!(polylines.len(), 3);
    for l in polylines {
        assert!(l[2..]
            .split(' ')
            .all(|i| (1..=count).contains(&i.parse::<usize>().unwrap())));
    }

    let refused = ridgeline(&["y.ply", "-o", "y.svg"], dir.path());
    assert!(!refused.status.success());
    let text = stderr(&refused);
    assert!(text.contains("in space") && text.contains(".ply"), "{text}");
    assert!(!text.contains("panicked"), "{text}");
}

/// Tiny, degenerate and extreme sets in space: a graph or an error, never a panic.
#[test]
fn degenerate_sets_in_space_give_a_graph_or_an_error() {
    let params = Params::default();
    let one = ridgeline::trace_points3d(&[[1.0, 2.0, 3.0]], &params).expect("one point");
    assert_eq!((one.graph.vertices.len(), one.graph.edges.len()), (1, 0));
    let twice = [[1.0, 2.0, 3.0], [1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
    let trace = ridgeline::trace_points3d(&twice, &params).expect("repeats");
    assert_eq!(trace.point_count, 2);
    let line: Vec<[f64; 3]> = (0..100).map(|i| [i as f64, 0.0, 0.0]).collect();
    let trace = ridgeline::trace_points3d(&line, &params).expect("a line");
    trace.graph.validate().expect("valid");
    assert_eq!(trace.graph.endpoints().count(), 2);
    let tiny: Vec<[f64; 3]> = line.iter().map(|p| p.map(|x| x * 1e-300)).collect();
    let trace = ridgeline::trace_points3d(&tiny, &params).expect("subnormal scale");
    trace.graph.validate().expect("valid");
    assert!(ridgeline::trace_points3d(&[[0.0; 3], [1e200, 0.0, 0.0]], &params).is_err());
    assert!(ridgeline::trace_points3d(&[[0.0, f64::NAN, 0.0]], &params).is_err());
    assert!(ridgeline::trace_points3d(&[], &params)
        .expect("empty")
        .graph
        .vertices
        .is_empty());
}

/// Outliers around a tube (a helix with 2 % more points drawn uniformly over a box around it, a
/// thousandfold sparser): most are left out with a warning that counts them, none of the tube's
/// points, and the helix stays one part; the helix alone leaves nothing out. (The few outliers
/// within about ten spacings of the tube stay and may still make a spur.)
#[test]
fn sparse_outliers_in_space_are_left_out_with_a_warning() {
    let c = case("helix");
    let clean = ridgeline::trace_points3d(&c.points, &Params::default()).expect("clean");
    assert!(clean.warnings.is_empty(), "{:?}", clean.warnings);
    let (lo, hi) = c.points.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        },
    );
    let mut seed = 11u64;
    let mut next = |axis: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let t = (seed >> 11) as f64 / (1u64 << 53) as f64;
        let margin = 2.0 * c.width;
        lo[axis] - margin + t * (hi[axis] - lo[axis] + 2.0 * margin)
    };
    let extra = c.points.len() / 50;
    let mut points = c.points.clone();
    points.extend((0..extra).map(|_| [next(0), next(1), next(2)]));
    let trace = ridgeline::trace_points3d(&points, &Params::default()).expect("trace");
    let g = &trace.graph;
    assert_eq!(g.components(), 1, "{:?}", g.vertices);
    let warning = trace
        .warnings
        .iter()
        .find(|w| w.code == "sparse_points_left_out")
        .unwrap_or_else(|| panic!("no warning: {:?}", trace.warnings));
    let left_out = points.len() - trace.point_count;
    assert!(
        left_out >= extra * 3 / 4 && left_out <= extra,
        "{left_out} of {extra} left out"
    );
    assert!(
        warning
            .message
            .starts_with(&format!("{left_out} of {} points", points.len())),
        "{}",
        warning.message
    );
}
