//! The SVG and JSON writers on hand-built graphs, and the `ridgeline` binary as a user runs it.

use std::fs;

use crate::support::{
    entries, repository_root, ridgeline, run_ok, stderr, temp_dir, write_strokes_png,
};

use base64::Engine;
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::{Edge, GrayImage, Params, StrokeGraph, Vertex};

// ---------------------------------------------------------------------------------------------
// Writers

/// A Y: junction 0 at (20, 20) with three arms to endpoints 1, 2, 3, plus an isolated dot 4.
/// Coordinates with many decimals check the rounding.
fn y_graph() -> StrokeGraph {
    let junction = [20.0, 20.0];
    let ends = [
        [20.0 + 1.0 / 3.0, 2.123_456],
        [5.5, 35.0],
        [36.987_654, 34.25],
    ];
    let mut vertices = vec![Vertex {
        pos: junction,
        degree: 3,
        width: 6.0,
    }];
    let mut edges = Vec::new();
    for (i, end) in ends.iter().enumerate() {
        vertices.push(Vertex {
            pos: *end,
            degree: 1,
            width: 4.0 + i as f64,
        });
        let mid = [
            (junction[0] + end[0]) / 2.0 + 0.25,
            (junction[1] + end[1]) / 2.0,
        ];
        let points = vec![junction, mid, *end];
        let d = [end[0] - junction[0], end[1] - junction[1]];
        let n = d[0].hypot(d[1]);
        edges.push(Edge {
            from: 0,
            to: i + 1,
            widths: vec![6.0, 5.0, 4.0 + i as f64],
            directions: vec![[d[0] / n, d[1] / n]; 3],
            points,
        });
    }
    vertices.push(Vertex {
        pos: [40.0, 5.0],
        degree: 0,
        width: 3.0,
    });
    let graph = StrokeGraph {
        width: 48,
        height: 40,
        vertices,
        edges,
    };
    graph.validate().expect("hand-built graph is valid");
    graph
}

fn parse_points(text: &str) -> Vec<[f64; 2]> {
    text.split_whitespace()
        .map(|pair| {
            let (x, y) = pair.split_once(',').expect("x,y");
            [x.parse().expect("x"), y.parse().expect("y")]
        })
        .collect()
}

fn group<'a, 'i>(doc: &'a roxmltree::Document<'i>, id: &str) -> Option<roxmltree::Node<'a, 'i>> {
    doc.descendants()
        .find(|n| n.has_tag_name("g") && n.attribute("id") == Some(id))
}

#[test]
fn svg_has_one_polyline_per_edge_at_the_graph_coordinates() {
    let graph = y_graph();
    let text = svg::to_string(&graph, None, &SvgOptions::default());
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(root.attribute("width"), Some("48"));
    assert_eq!(root.attribute("height"), Some("40"));
    assert_eq!(root.attribute("viewBox"), Some("0 0 48 40"));
    assert!(
        doc.descendants().all(|n| !n.has_tag_name("image")),
        "no image was given"
    );

    let polylines: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .collect();
    assert_eq!(polylines.len(), graph.edges.len());
    for (polyline, edge) in polylines.iter().zip(&graph.edges) {
        let points = parse_points(polyline.attribute("points").expect("points"));
        assert_eq!(points.len(), edge.points.len());
        for (written, truth) in points.iter().zip(&edge.points) {
            assert!(
                (written[0] - truth[0]).abs() <= 0.005 + 1e-9,
                "{written:?} vs {truth:?}"
            );
            assert!(
                (written[1] - truth[1]).abs() <= 0.005 + 1e-9,
                "{written:?} vs {truth:?}"
            );
        }
    }
    // At most 2 decimals anywhere in the coordinates.
    for polyline in &polylines {
        for number in polyline.attribute("points").unwrap_or("").split([' ', ',']) {
            let decimals = number.split_once('.').map_or(0, |(_, d)| d.len());
            assert!(decimals <= 2, "{number}");
        }
    }

    let edges = group(&doc, "edges").expect("edge group");
    assert_eq!(edges.attribute("fill"), Some("none"));
    assert_eq!(edges.attribute("stroke-linejoin"), Some("round"));
    assert_eq!(edges.attribute("stroke-linecap"), Some("round"));
    // Median of the vertex widths 6, 4, 5, 6, 3 is 5: 0.12 x 5 = 0.6.
    let width: f64 = edges
        .attribute("stroke-width")
        .expect("width")
        .parse()
        .expect("number");
    assert!((width - 0.6).abs() < 1e-9, "{width}");

    let circles = |id: &str| {
        group(&doc, id).map_or(0, |g| {
            g.children().filter(|c| c.has_tag_name("circle")).count()
        })
    };
    assert_eq!(circles("endpoints"), 3);
    assert_eq!(circles("junctions"), 1);
    assert_eq!(circles("dots"), 1);
    let junction = group(&doc, "junctions")
        .and_then(|g| g.first_element_child())
        .expect("circle");
    assert_eq!(junction.attribute("cx"), Some("20"));
    assert_eq!(junction.attribute("cy"), Some("20"));
    assert_ne!(
        group(&doc, "endpoints").and_then(|g| g.attribute("fill")),
        group(&doc, "junctions").and_then(|g| g.attribute("fill"))
    );
}

#[test]
fn svg_options_hide_markers_and_set_the_line_width() {
    let graph = y_graph();
    let options = SvgOptions::default()
        .with_show_vertices(false)
        .with_stroke_width(Some(2.5));
    let text = svg::to_string(&graph, None, &options);
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    assert!(group(&doc, "endpoints").is_none());
    assert!(group(&doc, "junctions").is_none());
    // The isolated dot is content, not a marker.
    assert!(group(&doc, "dots").is_some());
    assert_eq!(
        group(&doc, "edges").and_then(|g| g.attribute("stroke-width")),
        Some("2.5")
    );
    // Wide strokes give a wider line than the 0.6 px floor.
    let mut wide = y_graph();
    for v in &mut wide.vertices {
        v.width = 20.0;
    }
    let text = svg::to_string(&wide, None, &SvgOptions::default());
    assert!(text.contains(r#"stroke-width="2.4""#), "{text}");
}

#[test]
fn svg_embeds_the_source_image_over_the_whole_canvas() {
    let graph = y_graph();
    let image = GrayImage::from_fn(48, 40, |x, y| image::Luma([((x * 5 + y * 3) % 256) as u8]));
    let text = svg::to_string(&graph, Some(&image), &SvgOptions::default());
    let doc = roxmltree::Document::parse(&text).expect("well-formed SVG");
    let node = doc
        .descendants()
        .find(|n| n.has_tag_name("image"))
        .expect("an <image>");
    assert_eq!(node.attribute("x"), Some("0"));
    assert_eq!(node.attribute("y"), Some("0"));
    assert_eq!(node.attribute("width"), Some("48"));
    assert_eq!(node.attribute("height"), Some("40"));
    assert_eq!(node.attribute("preserveAspectRatio"), Some("none"));
    let href = node.attribute("href").expect("href");
    let data = href
        .strip_prefix("data:image/png;base64,")
        .expect("a base64 PNG");
    let png = base64::engine::general_purpose::STANDARD
        .decode(data)
        .expect("base64");
    let decoded = image::load_from_memory(&png).expect("PNG").to_luma8();
    assert_eq!(decoded, image);
    // The image is drawn first, under the centerlines.
    let first = doc.root_element().first_element_child().expect("child");
    assert!(first.has_tag_name("image"));
}

#[test]
fn json_round_trips_through_serde_json() {
    let graph = y_graph();
    let mut params = Params::default();
    params.method.k = 7;
    let meta = JsonMeta::new(params.clone()).with_source_path("scans/y.png");
    let text = json::to_string(&graph, &meta);
    assert_eq!(text, json::to_string(&graph, &meta), "deterministic");
    let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");

    assert_eq!(value["ridgeline"], env!("CARGO_PKG_VERSION"));
    assert_eq!(value["source"]["path"], "scans/y.png");
    assert_eq!(value["source"]["width"], 48);
    assert_eq!(value["source"]["height"], 40);
    let back: Params = serde_json::from_value(value["parameters"].clone()).expect("Params");
    assert_eq!(back, params);

    let vertices = value["vertices"].as_array().expect("vertices");
    assert_eq!(vertices.len(), graph.vertices.len());
    for (i, (v, truth)) in vertices.iter().zip(&graph.vertices).enumerate() {
        assert_eq!(v["id"], i);
        assert_eq!(v["degree"], truth.degree);
        let x = v["x"].as_f64().expect("x");
        assert!((x - truth.pos[0]).abs() <= 0.0005 + 1e-12);
        assert_eq!(x, (x * 1000.0).round() / 1000.0, "3 decimals");
        assert_eq!(v["width"].as_f64(), Some(truth.width));
    }
    assert_eq!(vertices[1]["x"].as_f64(), Some(20.333));
    assert_eq!(vertices[1]["y"].as_f64(), Some(2.123));

    let edges = value["edges"].as_array().expect("edges");
    assert_eq!(edges.len(), graph.edges.len());
    for (i, (e, truth)) in edges.iter().zip(&graph.edges).enumerate() {
        assert_eq!(e["id"], i);
        assert_eq!(e["from"], truth.from);
        assert_eq!(e["to"], truth.to);
        let length = e["length"].as_f64().expect("length");
        assert!((length - truth.length()).abs() <= 0.0005 + 1e-12);
        let points = e["points"].as_array().expect("points");
        assert_eq!(points.len(), truth.points.len());
        for (p, q) in points.iter().zip(&truth.points) {
            let p = [p[0].as_f64().expect("x"), p[1].as_f64().expect("y")];
            assert!((p[0] - q[0]).abs() <= 0.0005 + 1e-12 && (p[1] - q[1]).abs() <= 0.0005 + 1e-12);
        }
        assert_eq!(
            e["widths"].as_array().map(Vec::len),
            Some(truth.widths.len())
        );
        assert_eq!(
            e["directions"].as_array().map(Vec::len),
            Some(truth.directions.len())
        );
    }

    let stats = &value["stats"];
    assert_eq!(stats["vertices"], 5);
    assert_eq!(stats["edges"], 3);
    assert_eq!(stats["endpoints"], 3);
    assert_eq!(stats["junctions"], 1);
    assert_eq!(stats["components"], 2);
    assert_eq!(stats["cycles"], 0);
}

#[test]
fn json_of_an_empty_graph_and_a_pretty_one() {
    let graph = StrokeGraph {
        width: 10,
        height: 8,
        ..StrokeGraph::default()
    };
    let text = json::to_string(&graph, &JsonMeta::default());
    let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert!(value["source"]["path"].is_null());
    assert_eq!(value["vertices"].as_array().map(Vec::len), Some(0));
    assert_eq!(value["stats"]["components"], 0);

    let compact = json::to_string(&y_graph(), &JsonMeta::default());
    let pretty = json::to_string(&y_graph(), &JsonMeta::default().with_pretty(true));
    assert_eq!(compact.lines().count(), 1);
    assert!(pretty.lines().count() > 10);
    let a: serde_json::Value = serde_json::from_str(&compact).expect("json");
    let b: serde_json::Value = serde_json::from_str(&pretty).expect("json");
    assert_eq!(a, b);
}

// ---------------------------------------------------------------------------------------------
// The binary

#[test]
fn a_missing_file_fails_and_is_named() {
    let dir = temp_dir();
    let output = ridgeline(&["no-such-scan.png"], dir.path());
    assert!(!output.status.success());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("no-such-scan.png"),
        "{}",
        stderr(&output)
    );
    assert!(entries(dir.path()).is_empty(), "nothing written");
}

#[test]
fn help_mentions_every_flag_group_and_flag() {
    let dir = temp_dir();
    let output = ridgeline(&["--help"], dir.path());
    assert!(output.status.success());
    let long = String::from_utf8_lossy(&output.stdout).into_owned();
    let output = ridgeline(&["--help-method"], dir.path());
    assert!(output.status.success());
    let method = String::from_utf8_lossy(&output.stdout).into_owned();
    // The paper's parameters are in the method section only.
    for flag in [
        "--r-min-factor",
        "--linearity",
        "--merge-span",
        "--smoothness",
    ] {
        assert!(method.contains(flag), "--help-method lacks {flag}");
        assert!(!long.contains(flag), "--help shows the method's {flag}");
    }
    assert!(
        !method.contains("--no-image"),
        "--help-method shows --no-image"
    );
    let help = format!("{long}{method}");
    for heading in [
        "Output",
        "Input and binarization",
        "Method",
        "Sampling",
        "Graph and refinement",
        "Fitting",
        "Limits",
        "Running",
        "Examples",
    ] {
        assert!(help.contains(heading), "help lacks the group {heading}");
    }
    for flag in [
        "--output",
        "--format",
        "--no-image",
        "--no-vertices",
        "--line-width",
        "--pretty",
        "--points",
        "--threshold",
        "--sauvola",
        "--window",
        "--sauvola-k",
        "--polarity",
        "--dropout",
        "--dropout-fraction",
        "--paper",
        "--r-min-rule",
        "--r-min-factor",
        "--r-max-factor",
        "--r-growth",
        "--linearity",
        "--no-arms-test",
        "--arms-test",
        "--k",
        "--clusters",
        "--cluster-link",
        "--merge-span",
        "--no-cleanup",
        "--cleanup",
        "--laplacian",
        "--smoothness",
        "--anchor-weight",
        "--weiszfeld-iterations",
        "--spacing-factor",
        "--max-pixels",
        "--max-side",
        "--max-points",
        "--jobs",
        "--quiet",
    ] {
        assert!(help.contains(flag), "help lacks {flag}");
    }
    for example in ["page.png", "print.png", "points.xy", "scans/"] {
        assert!(
            help.contains(example),
            "help lacks the example with {example}"
        );
    }
}

#[test]
fn timings_are_written_only_when_asked_and_leave_the_graph_alone() {
    let dir = temp_dir();
    write_strokes_png(&dir.path().join("page.png"));
    let line: String = (0..60).map(|i| format!("{} {}\n", i, i % 2)).collect();
    fs::write(dir.path().join("line.xy"), line).unwrap();
    let mut stages = [
        "decode", "binarize", "points", "sampling", "graph", "refine", "fit", "skeleton", "wall",
    ];
    stages.sort_unstable();
    for input in ["page.png", "line.xy"] {
        let read = |name: &str| -> serde_json::Value {
            serde_json::from_slice(&fs::read(dir.path().join(name)).unwrap()).unwrap()
        };
        run_ok(&[input, "-o", "plain.json"], dir.path());
        run_ok(&[input, "--timings", "-o", "timed.json"], dir.path());
        let (plain, timed) = (read("plain.json"), read("timed.json"));
        assert!(
            plain.get("timings").is_none(),
            "{input}: no times unless asked"
        );
        let timings = timed["timings"].as_object().expect("timings");
        let mut keys: Vec<&str> = timings.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(keys, stages, "{input}");
        assert!(timings
            .values()
            .all(|t| t.as_f64().is_some_and(|t| t >= 0.0)));
        assert!(timings["wall"].as_f64().unwrap() > 0.0, "{input}");
        // Everything else is the document without times.
        let mut untimed = timed.clone();
        untimed.as_object_mut().unwrap().remove("timings");
        assert_eq!(untimed, plain, "{input}");
    }
    // The SVG has no place for times: the flag is named as doing nothing there.
    let output = run_ok(&["page.png", "--timings", "-o", "page.svg"], dir.path());
    assert!(stderr(&output).contains("--timings changes only the JSON"));
}

#[test]
fn short_help_is_short_and_its_examples_run() {
    let dir = temp_dir();
    let output = ridgeline(&["-h"], dir.path());
    assert!(output.status.success());
    let help = String::from_utf8_lossy(&output.stdout).into_owned();
    let lines = help.lines().count();
    assert!(lines <= 60, "-h is {lines} lines");
    // The files the examples name: a page, a print, a point list, a folder of scans.
    let samples = repository_root().join("samples");
    fs::copy(samples.join("text.png"), dir.path().join("page.png")).expect("copy");
    fs::copy(
        samples.join("fingerprint.png"),
        dir.path().join("print.png"),
    )
    .expect("copy");
    let ring: String = (0..400)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 400.0;
            format!(
                "{:.2} {:.2}\n",
                100.0 + 60.0 * a.cos(),
                100.0 + 60.0 * a.sin()
            )
        })
        .collect();
    fs::write(dir.path().join("points.xy"), ring).expect("write");
    fs::create_dir(dir.path().join("scans")).expect("mkdir");
    for name in ["t.png", "x30.png"] {
        fs::copy(samples.join(name), dir.path().join("scans").join(name)).expect("copy");
    }
    let examples: Vec<&str> = help
        .lines()
        .filter_map(|line| line.trim().strip_prefix("ridgeline "))
        .collect();
    assert!(examples.len() >= 5, "{help}");
    for example in &examples {
        let args: Vec<&str> = example.split_whitespace().collect();
        let output = ridgeline(&args, dir.path());
        assert!(
            output.status.success(),
            "ridgeline {example}: {}",
            stderr(&output)
        );
    }
    for written in [
        "page.svg",
        "print.json",
        "print.xyt",
        "points.svg",
        "out/t.json",
        "out/x30.json",
        "stages/6-final.png",
    ] {
        assert!(dir.path().join(written).is_file(), "no {written}");
    }
    // The print example finds minutiae with --fingerprint, as it says.
    let print = fs::read_to_string(dir.path().join("print.json")).expect("read");
    assert!(
        print.contains("\"minutiae\":[{"),
        "no minutiae in print.json"
    );
}

#[test]
fn usage_errors_exit_with_status_2() {
    let dir = temp_dir();
    write_strokes_png(&dir.path().join("a.png"));
    write_strokes_png(&dir.path().join("b.png"));
    for args in [
        &["--linearity", "1.5", "a.png"][..],
        &["--no-such-flag", "a.png"],
        &[],
        &["-o", "-", "a.png", "b.png"],
        &["--window", "15", "a.png"],
        &["--line-width", "0", "a.png"],
    ] {
        let output = ridgeline(args, dir.path());
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
        assert!(!stderr(&output).is_empty());
    }
    assert_eq!(entries(dir.path()).len(), 2, "nothing written");
}

#[test]
fn an_existing_output_survives_a_bad_input() {
    let dir = temp_dir();
    fs::write(dir.path().join("bad.png"), b"this is not a PNG").expect("write");
    fs::write(dir.path().join("out.svg"), b"keep me").expect("write");
    let output = ridgeline(&["bad.png", "-o", "out.svg"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("bad.png"));
    assert_eq!(
        fs::read(dir.path().join("out.svg")).expect("read"),
        b"keep me"
    );
    // No temporary file left behind either.
    assert_eq!(entries(dir.path()).len(), 2, "{:?}", entries(dir.path()));
}

#[test]
fn an_empty_directory_is_an_error() {
    let dir = temp_dir();
    fs::create_dir(dir.path().join("empty")).expect("mkdir");
    fs::write(dir.path().join("empty/readme.md"), b"no images").expect("write");
    let output = ridgeline(&["empty", "-o", "out/"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("empty"), "{}", stderr(&output));
}

// The tests below run the real pipeline.

#[test]
fn dash_output_writes_to_stdout() {
    let dir = temp_dir();
    write_strokes_png(&dir.path().join("page.png"));
    let output = ridgeline(&["page.png", "-o", "-"], dir.path());
    assert!(output.status.success(), "{}", stderr(&output));
    let text = String::from_utf8(output.stdout).expect("UTF-8");
    let doc = roxmltree::Document::parse(&text).expect("SVG on stdout");
    assert_eq!(doc.root_element().attribute("width"), Some("80"));
    assert!(doc.descendants().any(|n| n.has_tag_name("polyline")));
    assert!(doc.descendants().any(|n| n.has_tag_name("image")));
    assert_eq!(entries(dir.path()).len(), 1, "no file written");

    let output = ridgeline(
        &["page.png", "-o", "-", "--format", "json", "--no-image"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON on stdout");
    assert_eq!(value["source"]["path"], "page.png");
    assert!(value["stats"]["edges"].as_u64().unwrap_or(0) >= 2);
}

#[test]
fn default_output_sits_next_to_the_input_and_format_follows_the_extension() {
    let dir = temp_dir();
    fs::create_dir(dir.path().join("scans")).expect("mkdir");
    write_strokes_png(&dir.path().join("scans/page.png"));
    let output = ridgeline(&["scans/page.png", "--quiet"], dir.path());
    assert!(output.status.success(), "{}", stderr(&output));
    let svg_text = fs::read_to_string(dir.path().join("scans/page.svg")).expect("page.svg");
    assert!(svg_text.starts_with("<svg"));

    let output = ridgeline(&["scans/page.png", "-o", "page.json"], dir.path());
    assert!(output.status.success(), "{}", stderr(&output));
    let text = fs::read_to_string(dir.path().join("page.json")).expect("page.json");
    let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(value["source"]["width"], 80);
}

#[test]
fn a_batch_goes_on_past_a_bad_file_and_names_it() {
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    fs::create_dir_all(scans.join("more")).expect("mkdir");
    write_strokes_png(&scans.join("a.png"));
    write_strokes_png(&scans.join("more/c.png"));
    fs::write(scans.join("b.png"), b"not an image at all").expect("write");
    fs::write(scans.join("notes.md"), b"skip me").expect("write");
    let output = ridgeline(&["scans", "-o", "out", "--jobs", "2"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let err = stderr(&output);
    assert!(err.contains("b.png"), "{err}");
    assert!(
        err.contains("notes.md"),
        "the skipped file is mentioned: {err}"
    );
    let out = dir.path().join("out");
    assert!(fs::read_to_string(out.join("a.svg"))
        .expect("a.svg")
        .starts_with("<svg"));
    // The walked folder's layout is kept.
    assert!(fs::read_to_string(out.join("more/c.svg"))
        .expect("more/c.svg")
        .starts_with("<svg"));
    assert!(!out.join("b.svg").exists());
    assert_eq!(entries(&out).len(), 2, "{:?}", entries(&out));
}

#[test]
fn batch_output_does_not_depend_on_the_thread_count() {
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    fs::create_dir_all(scans.join("x")).expect("mkdir");
    write_strokes_png(&scans.join("page.png"));
    write_strokes_png(&scans.join("x/page.png"));
    for (jobs, out) in [("1", "one"), ("2", "two")] {
        let output = ridgeline(
            &["scans", "-o", out, "--jobs", jobs, "-f", "json"],
            dir.path(),
        );
        assert!(output.status.success(), "{}", stderr(&output));
    }
    let one = dir.path().join("one");
    assert_eq!(
        entries(&one),
        [one.join("page.json"), one.join("x")],
        "the walked folder's layout is kept"
    );
    for name in ["page.json", "x/page.json"] {
        let path = one.join(name);
        let other = dir.path().join("two").join(name);
        assert_eq!(
            fs::read(&path).expect("read"),
            fs::read(other).expect("read")
        );
    }
}

#[test]
fn a_blank_page_is_a_warning_not_an_error() {
    let dir = temp_dir();
    GrayImage::from_pixel(40, 30, image::Luma([255]))
        .save(dir.path().join("blank.png"))
        .expect("png");
    let output = ridgeline(&["blank.png"], dir.path());
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stderr(&output).contains("warning"), "{}", stderr(&output));
    let text = fs::read_to_string(dir.path().join("blank.svg")).expect("blank.svg");
    let doc = roxmltree::Document::parse(&text).expect("SVG");
    assert_eq!(
        doc.descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .count(),
        0
    );
}

/// The graph part (vertices and edges) of a JSON document.
fn graph_part(document: &serde_json::Value) -> (serde_json::Value, serde_json::Value) {
    (document["vertices"].clone(), document["edges"].clone())
}

/// `ridgeline samples/t.png` with `flags`, as JSON on stdout.
fn traced_t(flags: &[&str]) -> serde_json::Value {
    let root = crate::support::repository_root();
    let mut args = vec!["samples/t.png", "-o", "-", "--format", "json"];
    args.extend_from_slice(flags);
    let output = ridgeline(&args, root);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).expect("JSON on stdout")
}

#[test]
fn paper_alone_gives_the_paper_preset_and_its_golden_graph() {
    let paper = traced_t(&["--paper"]);
    let root = crate::support::repository_root();
    let golden: serde_json::Value =
        serde_json::from_slice(&fs::read(root.join("tests/golden/t.paper.json")).expect("golden"))
            .expect("golden JSON");
    assert_eq!(graph_part(&paper), graph_part(&golden));
    assert_eq!(
        paper["parameters"],
        serde_json::to_value(Params::paper()).expect("params as JSON")
    );
}

#[test]
fn flags_given_with_paper_override_its_rules() {
    let paper = traced_t(&["--paper"]);
    let heavy = traced_t(&["--paper", "--anchor-weight", "50"]);
    assert_eq!(heavy["parameters"]["anchor_weight"], 50.0);
    assert_ne!(
        graph_part(&heavy),
        graph_part(&paper),
        "--anchor-weight ignored"
    );
    // Each rule can be chosen apart from the preset.
    let held = traced_t(&["--paper", "--laplacian", "held"]);
    assert_eq!(held["parameters"]["laplacian"], "held");
    assert_ne!(graph_part(&held), graph_part(&paper), "--laplacian ignored");
    let width = traced_t(&["--paper", "--r-min-rule", "width", "--r-min-factor", "1"]);
    assert_eq!(width["parameters"]["r_min_rule"], "stroke_width");
    assert_ne!(
        graph_part(&width),
        graph_part(&paper),
        "--r-min-rule ignored"
    );
    let clusters = traced_t(&["--r-min-rule", "spacing", "--clusters", "equal-distance"]);
    assert_eq!(clusters["parameters"]["cluster_rule"], "equal_distance");
}

/// Writes the test kit's arch print with known minutiae as a PNG mask.
fn write_arch_print(path: &std::path::Path) {
    let case = ridgeline_testkit::synth::print_cases()
        .into_iter()
        .find(|c| c.name.contains("arch_minutiae"))
        .expect("the kit has this print");
    crate::support::write_mask_png(&case.binary, path);
}

/// `--fingerprint` reads the polarity from the image: the same print with light ridges on a dark
/// ground (an enhanced print's look) is read as light ridges, with its confidence, and gives the
/// minutiae of the dark print; `--polarity` still decides when given (no confidence), and
/// forced dark on the light print it traces the valleys instead.
#[test]
fn fingerprint_polarity_is_read_from_the_image() {
    let dir = temp_dir();
    let d = dir.path();
    write_arch_print(&d.join("dark.png"));
    let mut light = image::open(d.join("dark.png")).expect("PNG").to_luma8();
    image::imageops::invert(&mut light);
    light.save(d.join("light.png")).expect("png");
    let read = |name: &str, extra: &[&str]| -> serde_json::Value {
        let mut args = vec![name, "--fingerprint", "-o", "out.json"];
        args.extend_from_slice(extra);
        crate::support::run_ok(&args, d);
        serde_json::from_str(&fs::read_to_string(d.join("out.json")).expect("json"))
            .expect("parses")
    };
    let dark = read("dark.png", &[]);
    let light = read("light.png", &[]);
    assert_eq!(light["decisions"]["polarity"], "light");
    let confidence = light["decisions"]["polarity_confidence"]
        .as_f64()
        .expect("decided");
    assert!(confidence > 0.5, "{}", light["decisions"]);
    let kinds_and_places = |doc: &serde_json::Value| -> Vec<(String, i64, i64)> {
        doc["minutiae"]
            .as_array()
            .expect("minutiae")
            .iter()
            .map(|m| {
                (
                    m["kind"].as_str().expect("kind").to_string(),
                    m["x"].as_f64().expect("x").round() as i64,
                    m["y"].as_f64().expect("y").round() as i64,
                )
            })
            .collect()
    };
    let expected = kinds_and_places(&dark);
    assert!(!expected.is_empty());
    assert_eq!(kinds_and_places(&light), expected);
    let forced = read("light.png", &["--polarity", "light"]);
    assert_eq!(forced["decisions"]["polarity"], "light");
    assert!(forced["decisions"]["polarity_confidence"].is_null());
    assert_eq!(kinds_and_places(&forced), expected);
    let valleys = read("light.png", &["--polarity", "dark"]);
    assert_eq!(valleys["decisions"]["polarity"], "dark");
    assert_ne!(kinds_and_places(&valleys), expected);
}

/// The ISO record's resolution is `--dpi`, else the one the image file states, else 500 dpi.
#[test]
fn iso_records_take_the_resolution_the_file_states() {
    let dir = temp_dir();
    let d = dir.path();
    write_arch_print(&d.join("plain.png"));
    // The same pixels stating 1000 dpi (39 370 px per metre).
    let gray = image::open(d.join("plain.png")).expect("PNG").to_luma8();
    let mut stated = Vec::new();
    let mut encoder = png::Encoder::new(&mut stated, gray.width(), gray.height());
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_pixel_dims(Some(png::PixelDimensions {
        xppu: 39_370,
        yppu: 39_370,
        unit: png::Unit::Meter,
    }));
    let mut writer = encoder.write_header().expect("header");
    writer.write_image_data(gray.as_raw()).expect("pixels");
    writer.finish().expect("finish");
    fs::write(d.join("stated.png"), stated).expect("write");
    let resolution = |args: &[&str]| -> (u16, u16) {
        let mut all = vec!["--fingerprint", "--format", "iso", "-o", "out.ist"];
        all.extend_from_slice(args);
        crate::support::run_ok(&all, d);
        let iso = fs::read(d.join("out.ist")).expect("ist");
        (
            u16::from_be_bytes([iso[18], iso[19]]),
            u16::from_be_bytes([iso[20], iso[21]]),
        )
    };
    // px/cm: 1000 dpi = 393.7, 500 dpi = 196.85, 300 dpi = 118.1.
    assert_eq!(resolution(&["stated.png"]), (394, 394));
    assert_eq!(resolution(&["plain.png"]), (197, 197));
    assert_eq!(resolution(&["stated.png", "--dpi", "300"]), (118, 118));
}

/// `--enhance smoothing` runs the fingerprint front end with oriented smoothing in place of the
/// Gabor filter (it implies `--fingerprint`), records it, and finds minutiae with a quality; an
/// unknown method is a usage error.
#[test]
fn enhance_chooses_the_fingerprint_enhancement() {
    let dir = temp_dir();
    let d = dir.path();
    write_arch_print(&d.join("print.png"));
    let traced = |method: &str| -> serde_json::Value {
        let out = format!("{method}.json");
        crate::support::run_ok(&["print.png", "--enhance", method, "-o", &out], d);
        serde_json::from_str(&fs::read_to_string(d.join(&out)).expect("json")).expect("parses")
    };
    let smoothing = traced("smoothing");
    assert_eq!(
        smoothing["parameters"]["fingerprint"]["enhancement"],
        "smoothing"
    );
    assert_eq!(
        smoothing["decisions"]["threshold"]["enhancement"],
        "smoothing"
    );
    let minutiae = smoothing["minutiae"].as_array().expect("minutiae listed");
    assert!(!minutiae.is_empty());
    assert!(minutiae.iter().all(|m| m["quality"].as_u64().is_some()));
    let gabor = traced("gabor");
    assert_eq!(gabor["parameters"]["fingerprint"]["enhancement"], "gabor");
    assert_ne!(gabor["edges"], smoothing["edges"], "the two filters differ");
    let bad = crate::support::ridgeline(&["print.png", "--enhance", "median", "-o", "x.json"], d);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("smoothing"));
    assert!(!d.join("x.json").exists());
}

/// More minutiae than an ISO/IEC 19794-2 record holds: the record keeps 255 (of highest
/// quality), the run succeeds and says so on stderr, and the JSON keeps every one.
#[test]
fn an_over_full_iso_record_keeps_255_and_says_so() {
    let dir = temp_dir();
    let d = dir.path();
    // 13 x 16 short horizontal dashes, 4 px thick and 14 px long, 12 px of paper between them
    // along the rows (their traced ends 16 px apart, beyond the broken-ridge gap) and 12 px
    // across: two endings each, 336 once those at the outline of the dashes are left out.
    let mut page = GrayImage::from_pixel(370, 288, image::Luma([235]));
    for row in 0..16 {
        for column in 0..13 {
            let (x0, y0) = (16 + column * 26, 16 + row * 16);
            for y in y0..y0 + 4 {
                for x in x0..x0 + 14 {
                    page.put_pixel(x, y, image::Luma([20]));
                }
            }
        }
    }
    page.save(d.join("dashes.png")).expect("png");
    crate::support::run_ok(&["dashes.png", "--minutiae", "-o", "dashes.json"], d);
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(d.join("dashes.json")).expect("json"))
            .expect("parses");
    let count = json["minutiae"].as_array().expect("minutiae").len();
    assert!(count > 255, "{count}");
    let output = crate::support::run_ok(&["dashes.png", "--format", "iso", "-o", "dashes.ist"], d);
    let message = stderr(&output);
    assert!(
        message.contains(&format!(
            "warning: dashes.png: {count} minutiae, more than the 255 an ISO/IEC 19794-2 record holds: wrote the 255 of highest quality"
        )),
        "{message}"
    );
    let iso = fs::read(d.join("dashes.ist")).expect("ist");
    assert_eq!(iso[27], 255);
    assert_eq!(iso.len(), 30 + 6 * 255);
}

/// `--fingerprint` writes the same minutiae as JSON (with a quality), as NIST `.xyt` lines and as
/// an ISO/IEC 19794-2 record whose header matches the file; without it nothing of the front end
/// appears in the output.
#[test]
fn fingerprint_minutiae_as_json_xyt_and_iso_records() {
    let dir = temp_dir();
    let d = dir.path();
    write_arch_print(&d.join("print.png"));
    crate::support::run_ok(&["print.png", "--fingerprint", "-o", "print.json"], d);
    crate::support::run_ok(&["print.png", "--fingerprint", "-o", "print.xyt"], d);
    crate::support::run_ok(
        &[
            "print.png",
            "--fingerprint",
            "--format",
            "iso",
            "-o",
            "print.ist",
        ],
        d,
    );
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(d.join("print.json")).expect("json"))
            .expect("parses");
    let minutiae = json["minutiae"].as_array().expect("minutiae listed");
    assert!(!minutiae.is_empty());
    assert!(minutiae
        .iter()
        .all(|m| m["quality"].as_u64().is_some_and(|q| q <= 100)));
    assert!(json["parameters"]["fingerprint"].is_object());
    // What the front end decided: ridges dark (read from the image: the paper around the print
    // is light), the enhanced image's sign as the threshold, and a ridge period about twice the
    // ridge width (ridges and valleys are about as wide).
    let decided = &json["decisions"];
    assert_eq!(decided["polarity"], "dark");
    let confidence = decided["polarity_confidence"].as_f64().expect("decided");
    assert!(confidence > 0.5 && confidence < 1.0, "{decided}");
    assert_eq!(decided["threshold"]["method"], "enhanced");
    assert_eq!(decided["threshold"]["enhancement"], "gabor");
    let width = decided["stroke_width"].as_f64().expect("width");
    let period = decided["print"]["ridge_period"].as_f64().expect("period");
    assert!(
        width > 1.0 && (1.4 * width..2.8 * width).contains(&period),
        "{decided}"
    );
    let share = decided["print"]["print_share"].as_f64().expect("share");
    assert!(share > 0.2 && share <= 1.0, "{decided}");
    let coherence = decided["print"]["coherence"].as_f64().expect("coherence");
    assert!(coherence > 0.5 && coherence <= 1.0, "{decided}");
    let xyt = fs::read_to_string(d.join("print.xyt")).expect("xyt");
    assert_eq!(xyt.lines().count(), minutiae.len());
    for (line, m) in xyt.lines().zip(minutiae) {
        let v: Vec<i64> = line
            .split(' ')
            .map(|t| t.parse().expect("integer"))
            .collect();
        assert_eq!(v.len(), 4, "{line}");
        assert_eq!(v[0], m["x"].as_f64().expect("x").round() as i64);
        assert_eq!(v[1], (200.0 - m["y"].as_f64().expect("y")).round() as i64);
        assert!((0..360).contains(&v[2]) && (0..=100).contains(&v[3]));
    }
    let iso = fs::read(d.join("print.ist")).expect("ist");
    assert_eq!(&iso[..8], b"FMR\0 20\0");
    assert_eq!(
        u32::from_be_bytes([iso[8], iso[9], iso[10], iso[11]]) as usize,
        iso.len()
    );
    assert_eq!(usize::from(iso[27]), minutiae.len());
    assert_eq!(iso.len(), 30 + 6 * minutiae.len());
    // The default run writes no quality and no fingerprint parameters.
    crate::support::run_ok(&["print.png", "--minutiae", "-o", "plain.json"], d);
    let plain = fs::read_to_string(d.join("plain.json")).expect("json");
    // (Its warnings may point to --fingerprint: the print is ridge texture over the image.)
    assert!(!plain.contains("\"quality\"") && !plain.contains("\"fingerprint\""));
    assert!(!plain.contains("\"print\"") && !plain.contains("enhanced"));
    // --debug draws the front end's stages too, and finds the same minutiae.
    crate::support::run_ok(
        &[
            "print.png",
            "--fingerprint",
            "--debug",
            "stages",
            "-o",
            "debug.json",
        ],
        d,
    );
    for name in ridgeline::debug::PRINT_PICTURE_NAMES
        .iter()
        .chain(&ridgeline::debug::PICTURE_NAMES)
        .chain(&[ridgeline::debug::DECISIONS_PICTURE])
    {
        let picture = image::open(d.join("stages").join(name)).expect("a PNG picture");
        assert!(picture.width() >= 200, "{name}");
    }
    let debug: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(d.join("debug.json")).expect("json"))
            .expect("parses");
    assert_eq!(debug["minutiae"], json["minutiae"]);
}

#[test]
fn text_files_among_the_scans_are_skipped_unless_they_are_point_lists() {
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    fs::create_dir(&scans).expect("mkdir");
    write_strokes_png(&scans.join("a.png"));
    fs::write(
        scans.join("README.txt"),
        "Scans of the 1766 print, page 3\nby hand\n",
    )
    .expect("write");
    fs::write(scans.join("title.txt"), "Scans\n").expect("write");
    fs::write(scans.join("line.xy"), "0 0\n10 0\n20 0\n30 0\n40 0\n").expect("write");
    let output = ridgeline(&["scans", "-o", "out", "-f", "json"], dir.path());
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    let out = dir.path().join("out");
    assert_eq!(entries(&out), [out.join("a.json"), out.join("line.json")]);
    assert!(
        err.contains("README.txt: skipped, not a point list")
            && err.contains("line 1: expected 2 or 3 numbers")
            && err.contains("title.txt: skipped, not a point list: no points in it"),
        "{err}"
    );
    assert!(err.contains("traced 2 of 2 inputs"), "{err}");
    assert!(!err.contains("error"), "{err}");

    // Named on the command line, the same file is a point list that fails.
    let output = ridgeline(&["scans/README.txt", "-o", "readme.svg"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).starts_with("error: scans/README.txt: "));
    assert!(!dir.path().join("readme.svg").exists());

    // A folder of text alone has nothing to trace.
    let notes = dir.path().join("notes");
    fs::create_dir(&notes).expect("mkdir");
    fs::write(notes.join("README.txt"), "nothing here\n").expect("write");
    let output = ridgeline(&["notes", "-o", "out2"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("nothing to trace"),
        "{}",
        stderr(&output)
    );
}

#[cfg(unix)]
#[test]
fn a_closed_stdout_ends_quietly() {
    use std::process::{Command, Stdio};
    let dir = temp_dir();
    write_strokes_png(&dir.path().join("page.png"));
    for _ in 0..3 {
        // The reader has gone away before anything is written (`| head -c 0`): a pipe whose
        // only reader, `true`, has exited, so every write fails however fast the trace is.
        let mut reader = Command::new("true")
            .stdin(Stdio::piped())
            .spawn()
            .expect("run true");
        let pipe = reader.stdin.take().expect("the pipe's writing end");
        reader.wait().expect("the reader exits");
        let child = Command::new(env!("CARGO_BIN_EXE_ridgeline"))
            .args(["page.png", "-o", "-"])
            .current_dir(dir.path())
            .stdout(Stdio::from(pipe))
            .stderr(Stdio::piped())
            .spawn()
            .expect("run ridgeline");
        let output = child.wait_with_output().expect("wait");
        let err = stderr(&output);
        assert!(output.status.success(), "{err}");
        assert!(err.is_empty(), "no error line, nothing else: {err}");
    }
}

#[cfg(unix)]
#[test]
fn ctrl_c_says_what_was_finished_and_keeps_it() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    fs::create_dir(&scans).expect("mkdir");
    write_strokes_png(&scans.join("p000.png"));
    const FILES: usize = 400;
    for i in 1..FILES {
        fs::copy(scans.join("p000.png"), scans.join(format!("p{i:03}.png"))).expect("copy");
    }
    let out = dir.path().join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_ridgeline"))
        .args(["scans", "-o", "out", "--jobs", "1"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run ridgeline");
    let started = Instant::now();
    while !out.join("p000.svg").exists() {
        assert!(started.elapsed() < Duration::from_secs(60), "no output");
        std::thread::sleep(Duration::from_millis(1));
    }
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(sent.success());
    let output = child.wait_with_output().expect("wait");
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(130), "{err}");
    let written = entries(&out);
    let finished = written.len();
    assert!((1..FILES).contains(&finished), "{finished} written: {err}");
    assert!(
        err.contains(&format!(
            "interrupted after {finished} of {FILES} files; finished outputs kept; not traced: \
             scans/p{finished:03}.png"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!("and {} more", FILES - finished - 5)),
        "{err}"
    );
    // Every output is whole: no temporary file, every SVG complete.
    for path in &written {
        let text = fs::read_to_string(path).expect("read");
        assert!(text.trim_end().ends_with("</svg>"), "{}", path.display());
    }
}

#[test]
fn the_regions_left_out_are_named_and_the_advice_traces_them() {
    // Generated pages of text inside a dark scanner frame and inside a book's thin page edges:
    // the frame is left out and named.
    for name in ["page_frame", "page_book_edges"] {
        regions_advice_traces_them(name);
    }
}

fn regions_advice_traces_them(name: &str) {
    let page = ridgeline_testkit::synth::page_cases()
        .into_iter()
        .find(|c| c.case.name == name)
        .expect("the framed page");
    let dir = temp_dir();
    page.gray.save(dir.path().join("page.png")).expect("png");
    let plain = ridgeline(&["page.png", "-o", "plain.json"], dir.path());
    assert!(plain.status.success(), "{}", stderr(&plain));
    let message = stderr(&plain);
    let kinds = message
        .split("pass --keep-regions ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .unwrap_or_else(|| panic!("no --keep-regions advice in {message:?}"))
        .to_string();
    assert!(message.contains("left out"), "{message}");
    let kept = ridgeline(
        &["page.png", "--keep-regions", &kinds, "-o", "kept.json"],
        dir.path(),
    );
    assert!(kept.status.success(), "{}", stderr(&kept));
    assert!(!stderr(&kept).contains("left out"), "{}", stderr(&kept));
    // Following the advice traces what was left out: more centerline than without it.
    let length = |name: &str| {
        let text = fs::read_to_string(dir.path().join(name)).expect(name);
        let doc: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        doc["edges"]
            .as_array()
            .expect("edges")
            .iter()
            .map(|e| e["length"].as_f64().expect("length"))
            .sum::<f64>()
    };
    assert!(
        length("kept.json") > 1.05 * length("plain.json"),
        "{} against {}",
        length("kept.json"),
        length("plain.json")
    );
}
