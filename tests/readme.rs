//! The README's examples run as written: every `sh` block, in a folder holding a copy of
//! `samples/`, with the built `ridgeline` on the `PATH`. (Its Python block is run by
//! `python/tests/test_readme.py`.)

use std::fs;
use std::process::Command;

use crate::support::{repository_root, temp_dir};

/// The bodies of the README's fenced blocks of `language`.
fn fenced(text: &str, language: &str) -> Vec<String> {
    let opening = format!("```{language}");
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        match &mut current {
            None if line.trim_end() == opening => current = Some(String::new()),
            None => {}
            Some(_) if line.trim_end() == "```" => blocks.extend(current.take()),
            Some(block) => {
                block.push_str(line);
                block.push('\n');
            }
        }
    }
    blocks
}

/// Shell functions standing in for the commands of a block that are not ridgeline's own: `cargo
/// run --release -- ARGS` is the binary this test runs; `cargo test`, `cargo build`, `cargo
/// install` and `pip install` build or install what the test already has, and are only noted.
/// Any other `cargo` or `pip` command fails the block.
const PRELUDE: &str = r#"
cargo() {
  case "$1" in
    run) while [ "$1" != "--" ]; do shift; done; shift; ridgeline "$@" ;;
    test|build|install) echo "cargo $*" >> setup.log ;;
    *) echo "unexpected: cargo $*" >&2; return 1 ;;
  esac
}
pip() {
  case "$1" in
    install) echo "pip $*" >> setup.log ;;
    *) echo "unexpected: pip $*" >&2; return 1 ;;
  esac
}
"#;

#[test]
fn every_shell_example_of_the_readme_runs() {
    let readme = fs::read_to_string(repository_root().join("README.md")).expect("read README");
    let blocks = fenced(&readme, "sh");
    assert!(blocks.len() >= 5, "README has {} sh blocks", blocks.len());
    let dir = temp_dir();
    let samples = dir.path().join("samples");
    fs::create_dir(&samples).expect("mkdir");
    for entry in fs::read_dir(repository_root().join("samples")).expect("list samples") {
        let path = entry.expect("entry").path();
        fs::copy(&path, samples.join(path.file_name().expect("name"))).expect("copy");
    }
    let bin = dir.path().join("bin");
    fs::create_dir(&bin).expect("mkdir");
    fs::copy(env!("CARGO_BIN_EXE_ridgeline"), bin.join("ridgeline")).expect("copy binary");
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for block in &blocks {
        let output = Command::new("sh")
            .arg("-ec")
            .arg(format!("{PRELUDE}\n{block}"))
            .env("PATH", &path)
            .current_dir(dir.path())
            .output()
            .expect("run sh");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success() && !stderr.contains("error"),
            "README block failed:\n{block}\n{stderr}"
        );
    }
    for written in [
        "crossings.svg",
        "samples/text.svg",
        "text.json",
        "text.svg",
        "stages/6-final.png",
        "out/text.json",
        "out/fingerprint.json",
        "print.json",
        "print.xyt",
        "print.ist",
        "ring.svg",
        "ring-paper.svg",
        "helix.ply",
        "helix.json",
    ] {
        assert!(
            dir.path().join(written).is_file(),
            "the README's examples wrote no {written}"
        );
    }
    // Only the setup commands were stood in for.
    let setup = fs::read_to_string(dir.path().join("setup.log")).expect("setup.log");
    assert_eq!(
        setup.lines().collect::<Vec<_>>(),
        [
            "cargo test",
            "cargo install --path cli",
            "pip install ./python"
        ]
    );
    // The fingerprint example finds minutiae, as the README says.
    let print = fs::read_to_string(dir.path().join("print.json")).expect("read");
    assert!(
        print.contains("\"minutiae\":[{"),
        "no minutiae in print.json"
    );
    // The ring of points is one closed stroke, as the README says: one component, one cycle.
    let output = crate::support::ridgeline(&["ring.xy", "-o", "ring.json"], dir.path());
    assert!(output.status.success());
    let ring: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("ring.json")).expect("read"))
            .expect("JSON");
    assert_eq!(ring["stats"]["components"], 1, "{}", ring["stats"]);
    assert_eq!(ring["stats"]["cycles"], 1, "{}", ring["stats"]);
    // The helix is one curve with two ends, about 8 across, and its PLY reads back.
    let helix: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("helix.json")).expect("read"))
            .expect("JSON");
    assert_eq!(helix["stats"]["components"], 1, "{}", helix["stats"]);
    assert_eq!(helix["stats"]["endpoints"], 2, "{}", helix["stats"]);
    assert_eq!(helix["stats"]["junctions"], 0, "{}", helix["stats"]);
    let width = helix["vertices"][0]["width"].as_f64().expect("width");
    assert!((width / 8.0 - 1.0).abs() < 0.1, "width {width}");
    let ply = fs::read(dir.path().join("helix.ply")).expect("read");
    assert!(ridgeline::point_list::read(&ply, Some("ply")).is_ok());
}
