//! The `--debug` pictures: one per stage, of the expected size, showing what they claim to show.

use crate::support::{run_ok, write_mask_png};
use std::fs;
use std::path::Path;

use image::{Rgb, RgbImage};
use ridgeline::debug::{picture_scale, stage_pictures, stage_pngs, PICTURE_NAMES};
use ridgeline::{
    trace_binary_with_stages, Binary, Edge, Grid, Params, Stages, StrokeGraph, Vertex,
};
use ridgeline_testkit::synth::{render, Stroke};

const SIDE: u32 = 80;
const CENTER: [f64; 2] = [40.0, 40.0];
const ARM: f64 = 30.0;

/// A '+' of two 6 px strokes crossing at the image center.
fn plus() -> Binary {
    let strokes = [
        Stroke::new(
            vec![[CENTER[0] - ARM, CENTER[1]], [CENTER[0] + ARM, CENTER[1]]],
            6.0,
        ),
        Stroke::new(
            vec![[CENTER[0], CENTER[1] - ARM], [CENTER[0], CENTER[1] + ARM]],
            6.0,
        ),
    ];
    render(&strokes, SIDE, SIDE)
}

/// The ends of the '+', right, left, down, up.
fn ends() -> [[f64; 2]; 4] {
    [
        [CENTER[0] + ARM, CENTER[1]],
        [CENTER[0] - ARM, CENTER[1]],
        [CENTER[0], CENTER[1] + ARM],
        [CENTER[0], CENTER[1] - ARM],
    ]
}

/// The point set of `binary` built here, independently of the raster stage: pixel centers in
/// raster order, the pixel index, the 8-neighbours of each point (ascending), half-widths by brute
/// force.
struct HandPoints {
    points: Vec<[f64; 2]>,
    index: Vec<u32>,
    neighbors: Vec<Vec<u32>>,
    half_width: Vec<f32>,
}

fn hand_points(binary: &Binary) -> HandPoints {
    let (w, h) = (binary.width as i64, binary.height as i64);
    let mut index = vec![Grid::NONE; (w * h) as usize];
    let mut points = Vec::new();
    for y in 0..h {
        for x in 0..w {
            if binary.get(x, y) {
                index[(y * w + x) as usize] = points.len() as u32;
                points.push([x as f64 + 0.5, y as f64 + 0.5]);
            }
        }
    }
    let background: Vec<[f64; 2]> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| !binary.get(x, y))
        .map(|(x, y)| [x as f64 + 0.5, y as f64 + 0.5])
        .collect();
    let half_width = points
        .iter()
        .map(|&p| {
            background
                .iter()
                .map(|&q| ridgeline::dist(p, q))
                .fold(f64::INFINITY, f64::min) as f32
        })
        .collect();
    let neighbors = points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] as i64, p[1] as i64);
            let mut list = Vec::new();
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (dx, dy) != (0, 0) && binary.get(nx, ny) {
                        list.push(index[(ny * w + nx) as usize]);
                    }
                }
            }
            list
        })
        .collect();
    HandPoints {
        points,
        index,
        neighbors,
        half_width,
    }
}

/// The stroke graph a perfect trace of the '+' gives: one degree-4 vertex, four ends.
fn plus_graph() -> StrokeGraph {
    let mut vertices = vec![Vertex {
        pos: CENTER,
        degree: 4,
        width: 6.0,
    }];
    let mut edges = Vec::new();
    for (i, end) in ends().into_iter().enumerate() {
        vertices.push(Vertex {
            pos: end,
            degree: 1,
            width: 6.0,
        });
        let mid = [(CENTER[0] + end[0]) / 2.0, (CENTER[1] + end[1]) / 2.0];
        let d = [(end[0] - CENTER[0]) / ARM, (end[1] - CENTER[1]) / ARM];
        edges.push(Edge {
            from: 0,
            to: i + 1,
            points: vec![CENTER, mid, end],
            widths: vec![6.0; 3],
            directions: vec![d; 3],
        });
    }
    StrokeGraph {
        width: SIDE,
        height: SIDE,
        vertices,
        edges,
    }
}

/// The stages of the trace of `binary`, after checking that the point set they ran on is the one
/// built here by hand ([`hand_points`]).
fn hand_stages(binary: &Binary) -> Stages {
    let trace = trace_binary_with_stages(binary, &Params::default()).expect("trace");
    let stages = trace.stages.expect("stages kept");
    let hand = hand_points(binary);
    let points = &stages.points;
    points.validate().expect("valid point set");
    assert_eq!(points.points, hand.points);
    assert_eq!(points.spacing, 1.0);
    for (i, (got, want)) in points.half_width.iter().zip(&hand.half_width).enumerate() {
        assert!(
            (got - want).abs() < 1e-5,
            "half-width of point {i}: {got} vs {want}"
        );
    }
    assert_eq!(points.half_width.len(), hand.half_width.len());
    for (i, list) in hand.neighbors.iter().enumerate() {
        assert_eq!(
            points.neighbors_of(i as u32),
            &list[..],
            "neighbours of {i}"
        );
    }
    let grid = points.grid.as_ref().expect("pixel grid");
    assert_eq!(
        (grid.width, grid.height, grid.x0, grid.y0),
        (SIDE, SIDE, 0, 0)
    );
    assert_eq!(grid.index, hand.index);
    stages
}

fn rgb(hex: &str) -> Rgb<u8> {
    let channel = |i: usize| u8::from_str_radix(&hex[1 + 2 * i..3 + 2 * i], 16).expect("hex");
    Rgb([channel(0), channel(1), channel(2)])
}

/// Pixels of `color` within `radius` picture px of image point `at`.
fn count_near(picture: &RgbImage, at: [f64; 2], radius: f64, color: Rgb<u8>, scale: f64) -> usize {
    let (cx, cy) = (at[0] * scale, at[1] * scale);
    picture
        .enumerate_pixels()
        .filter(|(x, y, p)| {
            **p == color && (*x as f64 + 0.5 - cx).hypot(*y as f64 + 0.5 - cy) <= radius
        })
        .count()
}

fn count(picture: &RgbImage, color: Rgb<u8>) -> usize {
    picture.pixels().filter(|p| **p == color).count()
}

/// The checks every set of pictures of the '+' must pass.
fn check_pictures(pictures: &[(String, RgbImage)], graph: &StrokeGraph) {
    let names: Vec<&str> = pictures.iter().map(|(name, _)| name.as_str()).collect();
    assert_eq!(names, PICTURE_NAMES);
    let scale = picture_scale(SIDE, SIDE);
    assert_eq!(scale, 4.0, "an 80 px image is drawn 4x");
    let white = Rgb([255, 255, 255]);
    for (name, picture) in pictures {
        assert_eq!(picture.dimensions(), (320, 320), "{name}");
        let drawn = picture.pixels().filter(|p| **p != white).count();
        // The '+' covers about 2 x 60 x 6 image px = 16 x that in picture px; every picture
        // shows at least the foreground, none is all ink.
        assert!(drawn > 5_000 && drawn < 320 * 320 / 2, "{name}: {drawn}");
    }
    let picture = |name: &str| &pictures[PICTURE_NAMES.iter().position(|n| *n == name).unwrap()].1;

    // Foreground: ink exactly where the binary is, scaled 4x.
    let binary = plus();
    let foreground = picture("1-foreground.png");
    for (x, y, p) in foreground.enumerate_pixels() {
        let ink = binary.get((x / 4) as i64, (y / 4) as i64);
        assert_eq!(*p != white, ink, "foreground at picture ({x}, {y})");
    }

    // Sampling: the crossing is non-linear (orange disks), the arms linear (blue).
    let sampling = picture("2-sampling.png");
    assert!(count(sampling, Rgb([255, 127, 14])) > 0, "non-linear disks");
    assert!(count(sampling, Rgb([31, 119, 180])) > 0, "linear disks");

    // Final: a green marker at every end and a blue one at the junction, where the graph has them.
    let final_picture = picture("6-final.png");
    let (green, blue) = (rgb("#3cb44b"), rgb("#4363d8"));
    for v in graph.endpoints() {
        let at = graph.vertices[v].pos;
        assert!(
            count_near(final_picture, at, 12.0, green, scale) > 20,
            "green marker at {at:?}"
        );
    }
    for v in graph.junctions() {
        let at = graph.vertices[v].pos;
        assert!(
            count_near(final_picture, at, 12.0, blue, scale) > 20,
            "blue marker at {at:?}"
        );
    }
    let stray = final_picture
        .enumerate_pixels()
        .filter(|(x, y, p)| {
            (**p == green || **p == blue)
                && graph.vertices.iter().all(|v| {
                    (*x as f64 + 0.5 - v.pos[0] * scale).hypot(*y as f64 + 0.5 - v.pos[1] * scale)
                        > 12.0
                })
        })
        .count();
    assert_eq!(stray, 0, "markers only at vertices");
    assert!(
        count(final_picture, rgb("#e6194b")) > 200,
        "red centerlines"
    );
}

#[test]
fn pictures_of_stages_on_a_hand_checked_point_set() {
    let binary = plus();
    let stages = hand_stages(&binary);
    let graph = plus_graph();
    let pictures = stage_pictures(&binary, &stages, &graph);
    if let Some(dir) = std::env::var_os("RIDGELINE_KEEP_PICTURES") {
        for (name, picture) in &pictures {
            picture.save(Path::new(&dir).join(name)).expect("save");
        }
    }
    check_pictures(&pictures, &graph);
    assert_eq!(graph.junctions().count(), 1);
    assert_eq!(graph.endpoints().count(), 4);
}

#[test]
fn stage_pngs_are_the_pictures_encoded() {
    let binary = plus();
    let stages = hand_stages(&binary);
    let graph = plus_graph();
    let expected = stage_pictures(&binary, &stages, &graph);
    let pngs: Vec<(&str, Vec<u8>)> = stage_pngs(&binary, &stages, &graph)
        .collect::<ridgeline::Result<_>>()
        .expect("encoded");
    let names: Vec<&str> = pngs.iter().map(|(name, _)| *name).collect();
    assert_eq!(names, PICTURE_NAMES);
    for ((name, png), (_, picture)) in pngs.iter().zip(expected) {
        let read = image::load_from_memory(png).expect("PNG").to_rgb8();
        assert!(read == picture, "{name} round-trips");
    }
}

#[test]
fn pictures_of_empty_and_mismatched_stages_do_not_panic() {
    let binary = plus();
    let pictures = stage_pictures(&binary, &Stages::default(), &StrokeGraph::default());
    assert_eq!(pictures.len(), PICTURE_NAMES.len());
    let tiny = Binary::new(1, 1);
    for (_, picture) in stage_pictures(&tiny, &hand_stages(&binary), &plus_graph()) {
        assert_eq!(picture.dimensions(), (4, 4));
    }
}

#[test]
fn pictures_of_the_traced_plus() {
    let binary = plus();
    let trace = trace_binary_with_stages(&binary, &Params::default()).expect("trace");
    let stages = trace.stages.as_ref().expect("stages kept");
    let degrees: Vec<usize> = trace.graph.vertices.iter().map(|v| v.degree).collect();
    assert_eq!(
        degrees.iter().filter(|&&d| d == 4).count(),
        1,
        "{degrees:?}"
    );
    let pictures = stage_pictures(&binary, stages, &trace.graph);
    check_pictures(&pictures, &trace.graph);
}

#[test]
fn cli_debug_writes_the_pictures() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    write_mask_png(&plus(), &dir.path().join("plus.png"));
    let run = |args: &[&str]| {
        run_ok(args, dir.path());
    };

    // One input: the pictures go into DIR itself, created with its parents, and nothing else
    // (no temporary file) is left there.
    run(&["plus.png", "-o", "plus.svg", "--debug", "pictures/a/b"]);
    assert!(dir.path().join("plus.svg").is_file());
    let pictures = dir.path().join("pictures").join("a").join("b");
    let mut names: Vec<String> = fs::read_dir(&pictures)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut expected: Vec<&str> = vec![ridgeline::debug::DECISIONS_PICTURE];
    expected.extend(PICTURE_NAMES);
    assert_eq!(names, expected, "the pictures and no temporary files");
    for name in expected {
        let picture = image::open(pictures.join(name)).expect(name);
        assert_eq!((picture.width(), picture.height()), (320, 320), "{name}");
    }

    // Several inputs: one subdirectory per output name.
    fs::create_dir(dir.path().join("in")).expect("mkdir");
    write_mask_png(&plus(), &dir.path().join("in").join("one.png"));
    write_mask_png(&plus(), &dir.path().join("in").join("two.png"));
    run(&["in", "-o", "out/", "--debug", "batch"]);
    for stem in ["one", "two"] {
        for name in PICTURE_NAMES {
            assert!(
                dir.path().join("batch").join(stem).join(name).is_file(),
                "{stem}/{name}"
            );
        }
    }
}

#[test]
fn cli_output_does_not_depend_on_debug() {
    // A solid stroke above a speckled one: dropout mode is decided per group of components,
    // which the stage pictures' one point set cannot show; the output must be the same.
    let dir = tempfile::TempDir::new().expect("temp dir");
    let strokes = [
        Stroke::new(vec![[30.0, 40.0], [290.0, 40.0]], 6.0),
        Stroke::new(vec![[30.0, 200.0], [290.0, 230.0]], 8.0),
    ];
    let mut binary = render(&strokes, 320, 260);
    ridgeline_testkit::synth::dropout(&mut binary, [0, 150, 320, 260], 0.3, 40);
    write_mask_png(&binary, &dir.path().join("two.png"));
    run_ok(&["two.png", "-o", "plain.json"], dir.path());
    run_ok(
        &["two.png", "-o", "debug.json", "--debug", "pictures"],
        dir.path(),
    );
    let read = |name: &str| -> serde_json::Value {
        let text = fs::read_to_string(dir.path().join(name)).expect(name);
        let mut json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        json["stats"]
            .as_object_mut()
            .expect("stats")
            .retain(|key, _| !key.contains("time") && !key.ends_with("_s"));
        json
    };
    let (plain, debug) = (read("plain.json"), read("debug.json"));
    let share = plain["decisions"]["dropout_share"].as_f64().expect("share");
    assert!(
        share > 0.0 && share < 1.0,
        "dropout decided per group: {share}"
    );
    assert_eq!(plain, debug);
}

#[test]
fn help_explains_debug() {
    let output = run_ok(&["--help"], Path::new("."));
    let help = String::from_utf8_lossy(&output.stdout);
    for expected in ["--debug <DIR>", "6-final", "ridgeline --debug"] {
        assert!(help.contains(expected), "help lacks {expected:?}");
    }
}

/// Every key the JSON writer emits is described in `docs/json.md` (which keeps the two in step).
#[test]
fn json_fields_are_all_documented() {
    fn keys(value: &serde_json::Value, prefix: &str, out: &mut Vec<String>) {
        match value {
            serde_json::Value::Object(map) => {
                for (key, inner) in map {
                    out.push(format!("{prefix}{key}"));
                    // Nested parameter objects are documented with their parent's name.
                    let nested = match key.as_str() {
                        "limits" | "threshold" if prefix.is_empty() => format!("{key}."),
                        _ => String::new(),
                    };
                    keys(inner, &nested, out);
                }
            }
            serde_json::Value::Array(items) => {
                for item in items {
                    keys(item, prefix, out);
                }
            }
            _ => {}
        }
    }
    let docs = fs::read_to_string(crate::support::repository_root().join("docs/json.md"))
        .expect("docs/json.md");
    let mut sauvola = Params::paper();
    sauvola.front_end.threshold = ridgeline::Threshold::Sauvola { window: 25, k: 0.2 };
    let mut fixed = Params::default();
    fixed.front_end.threshold = ridgeline::Threshold::Fixed { level: 100 };
    for params in [Params::default(), sauvola, fixed] {
        let meta = ridgeline::export::json::JsonMeta::new(params).with_source_path("a.png");
        let text = ridgeline::export::json::to_string(&plus_graph(), &meta);
        let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let mut found = Vec::new();
        keys(&value, "", &mut found);
        assert!(found.len() > 30, "{found:?}");
        for key in found {
            assert!(
                docs.contains(&format!("`{key}`")),
                "docs/json.md lacks `{key}`"
            );
        }
    }
}
