//! The command line a new user trusts: nothing of theirs is overwritten, outputs land where they
//! expect, every run says what happened, and every range the help states is checked.

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::support::{entries, ridgeline, run_ok, stderr, temp_dir, write_strokes_png};

/// A point list of an L: two strokes meeting at a corner, far from the origin.
const POINTS: &str = "1000 2000\n1001 2000\n1002 2000\n1003 2000\n1004 2000\n1005 2000\n\
                      1006 2000\n1007 2000\n1008 2000\n1008 2001\n1008 2002\n1008 2003\n\
                      1008 2004\n1008 2005\n1008 2006\n1008 2007\n1008 2008\n";

fn json_of(path: &Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).expect("read JSON")).expect("JSON")
}

/// Runs the binary with `stdin` as its standard input.
fn ridgeline_with_stdin(args: &[&str], dir: &Path, stdin: &[u8]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ridgeline"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start ridgeline");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin)
        .expect("write stdin");
    child.wait_with_output().expect("run ridgeline")
}

// ---------------------------------------------------------------------------------------------
// Data safety

#[test]
fn an_input_is_never_written_over() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("t.png"));
    let original = fs::read(d.join("t.png")).expect("read");
    fs::write(d.join("pts.txt"), POINTS).expect("write");
    fs::write(d.join("pts.svg"), POINTS).expect("write");
    fs::hard_link(d.join("pts.txt"), d.join("link.svg")).expect("hard link");
    #[cfg(unix)]
    std::os::unix::fs::symlink("pts.txt", d.join("sym.json")).expect("symlink");
    let before = entries(d);
    for args in [
        &["t.png", "-o", "t.png"][..],
        &["t.png", "-o", "./t.png"],
        &["pts.txt", "-o", "link.svg"],
        &["--points", "pts.svg", "-o", "./pts.svg"],
        &["--points", "pts.svg", "-o", "pts.svg"],
        #[cfg(unix)]
        &["pts.txt", "-o", "sym.json"],
    ] {
        let output = ridgeline(args, d);
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("never writes over") || err.contains("not .png"),
            "{args:?}: {err}"
        );
    }
    assert_eq!(fs::read(d.join("t.png")).expect("read"), original);
    assert_eq!(fs::read_to_string(d.join("pts.txt")).expect("read"), POINTS);
    assert_eq!(fs::read_to_string(d.join("pts.svg")).expect("read"), POINTS);
    assert_eq!(entries(d), before, "nothing written");

    // Pictures of the stages never replace an input either.
    fs::create_dir(d.join("stages")).expect("mkdir");
    write_strokes_png(&d.join("stages/1-foreground.png"));
    let picture = fs::read(d.join("stages/1-foreground.png")).expect("read");
    let output = ridgeline(&["stages/1-foreground.png", "--debug", "stages"], d);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert_eq!(
        fs::read(d.join("stages/1-foreground.png")).expect("read"),
        picture
    );
}

#[test]
fn an_output_extension_ridgeline_does_not_write_is_a_usage_error() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("t.png"));
    for (args, names) in [
        (&["t.png", "-o", "out.png"][..], "not .png"),
        (&["t.png", "-o", "out.txt"], "not .txt"),
        (&["t.png", "-o", "OUT.PDF"], "not .pdf"),
        (
            &["t.png", "-o", "out.svg", "--format", "json"],
            "contradicts",
        ),
    ] {
        let output = ridgeline(args, d);
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: {err}");
        if names.starts_with("not") {
            assert!(
                err.contains("SVG (.svg), JSON (.json), NIST minutiae (.xyt)"),
                "{err}"
            );
        }
    }
    assert_eq!(entries(d), [d.join("t.png")], "nothing written");
    // Upper case is the same format; no extension gets --format.
    run_ok(&["t.png", "-o", "OUT.SVG"], d);
    assert!(fs::read_to_string(d.join("OUT.SVG"))
        .expect("OUT.SVG")
        .starts_with("<svg"));
    run_ok(&["t.png", "-o", "plain", "--format", "json"], d);
    assert!(json_of(&d.join("plain"))["vertices"].is_array());
}

#[test]
fn a_missing_output_folder_is_named_not_a_temporary_file() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("t.png"));
    let output = ridgeline(&["t.png", "-o", "nodir/sub/out.svg"], d);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("nodir/sub/out.svg"), "{err}");
    assert!(err.contains("folder nodir/sub does not exist"), "{err}");
    assert!(
        !err.contains(".ridgeline-") && !err.contains(".tmp"),
        "{err}"
    );
    assert!(
        !d.join("nodir").exists(),
        "no folder made for an output file"
    );
    // A file where a folder should be.
    fs::write(d.join("plain"), b"a file").expect("write");
    let output = ridgeline(&["t.png", "-o", "plain/out.svg"], d);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("plain is a file, not a folder"), "{err}");
    // An output directory is still created.
    run_ok(&["t.png", "-o", "newdir/deeper/"], d);
    assert!(d.join("newdir/deeper/t.svg").is_file());
}

#[test]
fn a_batch_does_not_take_its_own_outputs_for_inputs() {
    let dir = temp_dir();
    let d = dir.path();
    fs::create_dir(d.join("scans")).expect("mkdir");
    write_strokes_png(&d.join("scans/a.png"));
    write_strokes_png(&d.join("scans/b.png"));
    for _ in 0..2 {
        let output = run_ok(&["scans", "-o", "scans", "--format", "json"], d);
        let err = stderr(&output);
        assert!(!err.contains("warning"), "{err}");
        assert!(err.contains("traced 2 of 2 inputs"), "{err}");
    }
    // The same with SVG, and with the outputs (and pictures) in a folder inside the inputs.
    for _ in 0..2 {
        let output = run_ok(&["scans", "-o", "scans/out/", "--debug", "scans/stages"], d);
        let err = stderr(&output);
        assert!(!err.contains("warning"), "{err}");
        assert!(err.contains("traced 2 of 2 inputs"), "{err}");
    }
    assert!(d.join("scans/out/a.svg").is_file());
    assert!(!d.join("scans/out/out").exists());
    assert!(!d.join("scans/out/stages").exists());
}

#[test]
fn an_output_directory_keeps_the_layout_of_the_inputs() {
    let dir = temp_dir();
    let d = dir.path();
    for folder in ["a", "b", "tree/deep"] {
        fs::create_dir_all(d.join(folder)).expect("mkdir");
        write_strokes_png(&d.join(folder).join("x.png"));
    }
    run_ok(&["a/x.png", "./b/x.png", "-o", "out/"], d);
    assert_eq!(entries(&d.join("out")), [d.join("out/a"), d.join("out/b")]);
    assert!(d.join("out/a/x.svg").is_file() && d.join("out/b/x.svg").is_file());
    // Files named in one folder land at the top of the output folder.
    run_ok(&["a/x.png", "-o", "one/"], d);
    assert_eq!(entries(&d.join("one")), [d.join("one/x.svg")]);
    // A walked folder's subfolders are kept.
    run_ok(&["tree", "-o", "walked"], d);
    assert!(d.join("walked/deep/x.svg").is_file());
}

// ---------------------------------------------------------------------------------------------
// Inputs

#[test]
fn standard_input_is_read_and_sniffed() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("x.png"));
    let png = fs::read(d.join("x.png")).expect("read");
    let output = ridgeline_with_stdin(&["-", "-o", "y.svg"], d, &png);
    assert!(output.status.success(), "{}", stderr(&output));
    let from_stdin = fs::read_to_string(d.join("y.svg")).expect("y.svg");
    run_ok(&["x.png", "-o", "z.svg"], d);
    assert_eq!(
        from_stdin,
        fs::read_to_string(d.join("z.svg")).expect("z.svg"),
        "the same drawing as from the file"
    );
    // Text is a point list; without -o the result goes to standard output.
    let output = ridgeline_with_stdin(&["-", "--format", "json"], d, POINTS.as_bytes());
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(value["source"]["path"], "-");
    assert!(value["stats"]["edges"].as_u64().unwrap_or(0) >= 1);
    // Garbage is an error, not a panic.
    let output = ridgeline_with_stdin(&["-", "-o", "bad.svg"], d, &[0xff, 0xfe, 0, 1, 2]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("not a recognized image format"));
    assert!(!d.join("bad.svg").exists());
}

// ---------------------------------------------------------------------------------------------
// Saying what happened

#[test]
fn every_run_says_what_it_did_unless_quiet() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("x.png"));
    write_strokes_png(&d.join("y.png"));
    let output = run_ok(&["x.png"], d);
    let err = stderr(&output);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("x.png -> x.svg: "), "{err}");
    for word in ["vertices", "edges", "junctions", " s"] {
        assert!(lines[0].contains(word), "{word}: {err}");
    }
    let output = run_ok(&["x.png", "--quiet"], d);
    assert!(stderr(&output).is_empty(), "{}", stderr(&output));

    fs::write(d.join("bad.png"), b"not an image").expect("write");
    let output = ridgeline(&["x.png", "y.png", "bad.png", "-o", "out/"], d);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    let last = err.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("traced 2 of 3 inputs, 1 failed in "),
        "{err}"
    );
}

#[test]
fn flags_that_change_nothing_in_the_chosen_format_warn() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("x.png"));
    let output = run_ok(&["x.png", "--pretty"], d);
    assert!(
        stderr(&output).contains("warning: --pretty changes only the JSON"),
        "{}",
        stderr(&output)
    );
    let output = run_ok(&["x.png", "-o", "x.json", "--no-image", "--width"], d);
    assert!(
        stderr(&output).contains("warning: --no-image, --width change only the SVG"),
        "{}",
        stderr(&output)
    );
    // --curves works in the JSON: one list of Béziers per edge, each segment four points.
    run_ok(&["x.png", "-o", "c.json", "--curves"], d);
    let value = json_of(&d.join("c.json"));
    let curves = value["curves"].as_array().expect("curves");
    assert_eq!(
        curves.len(),
        value["edges"].as_array().expect("edges").len()
    );
    let segment = &curves[0][0];
    assert_eq!(segment.as_array().map(Vec::len), Some(4), "{segment}");
    // The first segment starts where its edge does.
    let start = &value["edges"][0]["points"][0];
    assert_eq!(&segment[0], start);
    let output = run_ok(&["x.png", "-o", "plain.json"], d);
    assert!(!stderr(&output).contains("warning"));
    assert!(json_of(&d.join("plain.json")).get("curves").is_none());
}

#[test]
fn every_stated_range_is_checked_and_names_its_flag() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("x.png"));
    for (flag, value, extra) in [
        ("--window", "4", Some("--sauvola")),
        ("--window", "1", Some("--sauvola")),
        ("--sauvola-k", "1.5", Some("--sauvola")),
        ("--r-min-factor", "0", None),
        ("--r-min-factor", "inf", None),
        ("--r-max-factor", "0.5", None),
        ("--r-growth", "1", None),
        ("--linearity", "0.4", None),
        ("--k", "65", None),
        ("--cluster-link", "-1", None),
        ("--merge-span", "0", None),
        ("--smoothness", "-0.5", None),
        ("--anchor-weight", "0", None),
        ("--weiszfeld-iterations", "100000", None),
        ("--spacing-factor", "NaN", None),
        ("--dropout-fraction", "1", None),
        ("--max-pixels", "0", None),
        ("--max-side", "0", None),
        ("--max-points", "0", None),
    ] {
        let given = format!("{flag}={value}");
        let mut args = vec![given.as_str(), "x.png"];
        args.extend(extra);
        let output = ridgeline(&args, d);
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(flag), "{args:?}: {err}");
    }
    assert_eq!(entries(d), [d.join("x.png")], "nothing written");
    // The library says the same, by field.
    let mut params = ridgeline::Params::default();
    params.front_end.threshold = ridgeline::Threshold::Sauvola { window: 4, k: 0.2 };
    let err = ridgeline::trace_points(&[[0.0, 0.0]], &params).expect_err("even window");
    assert!(err.to_string().contains("threshold.window"), "{err}");
}

#[test]
fn polarity_is_spelled_as_on_the_command_line() {
    let dir = temp_dir();
    let d = dir.path();
    write_strokes_png(&d.join("x.png"));
    for (flag, written) in [("dark", "dark"), ("light", "light"), ("auto", "auto")] {
        run_ok(&["x.png", "--polarity", flag, "-o", "x.json"], d);
        assert_eq!(
            json_of(&d.join("x.json"))["parameters"]["polarity"],
            written
        );
    }
    // The old spelling is still read.
    let old: ridgeline::Polarity = serde_json::from_str("\"darkink\"").expect("old spelling");
    assert_eq!(old, ridgeline::Polarity::DarkInk);
}

#[test]
fn a_point_list_canvas_fits_the_points() {
    let dir = temp_dir();
    let d = dir.path();
    fs::write(d.join("l.txt"), POINTS).expect("write");
    run_ok(&["l.txt"], d);
    let text = fs::read_to_string(d.join("l.svg")).expect("l.svg");
    let doc = roxmltree::Document::parse(&text).expect("SVG");
    let view: Vec<f64> = doc
        .root_element()
        .attribute("viewBox")
        .expect("viewBox")
        .split(' ')
        .map(|v| v.parse().expect("number"))
        .collect();
    let [x, y, w, h] = view[..] else {
        panic!("viewBox {view:?}")
    };
    // Around the points (1000-1008, 2000-2008) with a margin, not from the origin.
    assert!(x > 980.0 && x < 1000.0, "{view:?}");
    assert!(y > 1980.0 && y < 2000.0, "{view:?}");
    assert!(x + w > 1008.0 && x + w < 1030.0, "{view:?}");
    assert!(y + h > 2008.0 && y + h < 2030.0, "{view:?}");
    // The coordinates are kept as given.
    let polyline = doc
        .descendants()
        .find(|n| n.has_tag_name("polyline"))
        .expect("polyline");
    let first: f64 = polyline
        .attribute("points")
        .and_then(|p| p.split([',', ' ']).next())
        .and_then(|v| v.parse().ok())
        .expect("x");
    assert!((999.0..1010.0).contains(&first), "{first}");
}

// ---------------------------------------------------------------------------------------------
// README

#[test]
fn the_readme_says_how_to_get_the_command_and_what_the_svg_shows() {
    let readme =
        fs::read_to_string(crate::support::repository_root().join("README.md")).expect("README.md");
    let section = |heading: &str| -> &str {
        let at = readme
            .find(heading)
            .unwrap_or_else(|| panic!("the README has no {heading:?}"));
        let rest = &readme[at + heading.len()..];
        &rest[..rest.find("\n## ").unwrap_or(rest.len())]
    };
    // A newcomer's first commands come first: trace a sample, run the tests.
    let start = &readme[..readme.find("## ").unwrap_or(readme.len())];
    for words in [
        "cargo run --release -- samples/",
        "cargo test",
        "first build compiles",
    ] {
        assert!(start.contains(words), "the README's start lacks {words:?}");
    }
    let install = section("## Install");
    for words in ["cargo install --path cli", "target/release/ridgeline"] {
        assert!(
            install.contains(words),
            "the README's Install lacks {words:?}"
        );
    }
    let start = section("## What the output means");
    use ridgeline::export::svg::{EDGE_COLOR, ENDPOINT_COLOR, JUNCTION_COLOR};
    for (color, meaning) in [
        (EDGE_COLOR, "centerlines"),
        (ENDPOINT_COLOR, "stroke ends"),
        (JUNCTION_COLOR, "junctions"),
    ] {
        let at = start
            .find(color)
            .unwrap_or_else(|| panic!("the README's start does not name {color} ({meaning})"));
        let before = &start[at.saturating_sub(60)..at];
        assert!(
            before.contains(meaning),
            "{color} is not said to be {meaning}"
        );
    }
    assert!(start.contains("red disc on its own is a dot"));
}
