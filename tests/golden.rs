//! Golden outputs: every image in `samples/`, a fixed set of the quality benchmark's generated cases
//! (the test kit's, drawn from known polylines) and a few point lists, traced with the default and
//! with the paper's parameters, compared byte for byte with the JSON stored in `tests/golden/`.
//!
//! A change that should not move outputs proves it here. A change that does move them regenerates
//! the files with `RIDGELINE_BLESS=1 cargo test golden` and says in its commit which moved and why;
//! the files are never edited by hand.

use std::fs;
use std::path::{Path, PathBuf};

use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::Features;
use ridgeline::minutiae::{minutiae, MinutiaeOptions};
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::{Params, StrokeGraph};

fn root() -> PathBuf {
    crate::support::repository_root().to_path_buf()
}

/// The JSON document of `graph` with its strokes and minutiae, as the CLI writes it.
fn document(graph: &StrokeGraph, params: &Params, source: &str) -> String {
    let chained = strokes(graph, &StrokeOptions::default());
    let marks = minutiae(graph, None, &MinutiaeOptions::default());
    let meta = JsonMeta::new(params.clone())
        .with_source_path(source)
        .with_pretty(true);
    let features = Features::default()
        .with_strokes(Some(&chained))
        .with_minutiae(Some(&marks));
    json::to_string_with(graph, &meta, &features)
}

/// Point lists with known shapes: an X of two noisy lines and a circle, as the paper's own input.
fn point_lists() -> Vec<(&'static str, Vec<[f64; 2]>)> {
    let mut cross = Vec::new();
    for i in 0..200 {
        let t = i as f64 * 0.5;
        let wobble = ((i * 7919) % 13) as f64 / 13.0 - 0.5;
        cross.push([t, t + wobble]);
        cross.push([t, 100.0 - t - wobble]);
    }
    let circle = (0..400)
        .map(|i| {
            let a = i as f64 / 400.0 * std::f64::consts::TAU;
            let r = 50.0 + ((i * 104729) % 7) as f64 / 7.0;
            [60.0 + r * a.cos(), 60.0 + r * a.sin()]
        })
        .collect();
    vec![("points-cross", cross), ("points-circle", circle)]
}

/// Generated cases, by group and name: an acute and a wide crossing, a K, cells finer than a
/// stroke, a bold `w` and `t`, a sharp zig-zag, three close crossings and a short arm.
const GENERATED: [(&str, &str); 9] = [
    ("hard", "x15_w8"),
    ("hard", "x30_w14"),
    ("hard", "k_w3"),
    ("cells", "box2x2_c0.5_w10"),
    ("letters", "letter_w_w11"),
    ("letters", "letter_t_w8"),
    ("zigzags", "zigzag30_w6"),
    ("triples", "triple_even_s1_w8"),
    ("arms", "arm_square_k1_w8"),
];

/// Every golden case: its file stem and its document under both parameter sets.
fn cases() -> Vec<(String, String)> {
    let mut out = Vec::new();
    let presets = [("default", Params::default()), ("paper", Params::paper())];
    let mut samples: Vec<PathBuf> = fs::read_dir(root().join("samples"))
        .expect("samples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    samples.sort();
    for path in samples {
        let stem = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let bytes = fs::read(&path).expect("read sample");
        let gray = ridgeline::decode(&bytes, &Default::default()).expect("decode sample");
        for (preset, params) in &presets {
            let trace = ridgeline::trace_image(&gray, params).expect("trace sample");
            let source = format!("samples/{stem}.png");
            out.push((
                format!("{stem}.{preset}"),
                document(&trace.graph, params, &source),
            ));
        }
    }
    for (group, name) in GENERATED {
        let cases = ridgeline_testkit::synth::group_cases(group).expect("a generated group");
        let case = cases
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no generated case {name} in {group}"));
        for (preset, params) in &presets {
            let trace = ridgeline::trace_binary(&case.binary, params).expect("trace case");
            let source = format!("generated/{group}/{name}");
            out.push((
                format!("{name}.{preset}"),
                document(&trace.graph, params, &source),
            ));
        }
    }
    for (name, list) in point_lists() {
        for (preset, params) in &presets {
            let trace = ridgeline::trace_points(&list, params).expect("trace points");
            out.push((
                format!("{name}.{preset}"),
                document(&trace.graph, params, name),
            ));
        }
    }
    out
}

fn golden_path(name: &str) -> PathBuf {
    root().join("tests/golden").join(format!("{name}.json"))
}

#[test]
fn outputs_equal_the_golden_files() {
    let bless = std::env::var_os("RIDGELINE_BLESS").is_some();
    let mut differing = Vec::new();
    let cases = cases();
    for (name, text) in &cases {
        let path = golden_path(name);
        if bless {
            fs::create_dir_all(path.parent().expect("parent")).expect("create tests/golden");
            fs::write(&path, text).expect("write golden file");
            continue;
        }
        match fs::read_to_string(&path) {
            Ok(stored) if &stored == text => {}
            Ok(_) => differing.push(format!("{name} differs")),
            Err(_) => differing.push(format!("{name} has no golden file")),
        }
    }
    for entry in fs::read_dir(root().join("tests/golden")).expect("tests/golden") {
        let path = entry.expect("entry").path();
        let stem = Path::new(path.file_name().expect("name"))
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        if !cases.iter().any(|(name, _)| *name == stem) {
            differing.push(format!("{} belongs to no case", path.display()));
        }
    }
    assert!(
        differing.is_empty(),
        "outputs moved (regenerate with RIDGELINE_BLESS=1 if that is intended): {}",
        differing.join(", ")
    );
}
