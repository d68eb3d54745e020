//! Helpers shared by the test modules that run the `ridgeline` binary.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::Luma;
use ridgeline::{Binary, GrayImage};
use ridgeline_testkit::synth::{render, Stroke};

/// The repository root, where `samples/`, `docs/` and the golden files are. The tests belong to
/// the command-line crate, whose manifest is in `cli/`.
pub fn repository_root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// Runs the built `ridgeline` binary with `args` in `dir`.
pub fn ridgeline(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ridgeline"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run ridgeline")
}

/// The run's standard error as text.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

pub fn temp_dir() -> tempfile::TempDir {
    tempfile::TempDir::new().expect("temp dir")
}

/// The entries of `dir`, sorted.
pub fn entries(dir: &Path) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").path())
        .collect();
    paths.sort();
    paths
}

/// Runs the binary like [`ridgeline`]; panics with its stderr when it fails.
pub fn run_ok(args: &[&str], dir: &Path) -> Output {
    let output = ridgeline(args, dir);
    assert!(
        output.status.success(),
        "ridgeline {args:?} failed: {}",
        stderr(&output)
    );
    output
}

/// The mask as a scan: dark ink (20) on light paper (235).
pub fn mask_image(binary: &Binary) -> GrayImage {
    GrayImage::from_fn(binary.width, binary.height, |x, y| {
        Luma([if binary.get(x as i64, y as i64) {
            20
        } else {
            235
        }])
    })
}

/// Writes [`mask_image`] of `binary` as a PNG.
pub fn write_mask_png(binary: &Binary, path: &Path) {
    mask_image(binary).save(path).expect("write PNG");
}

/// Writes a PNG of dark strokes (a cross and a bar) on white paper, 80 x 80.
pub fn write_strokes_png(path: &Path) {
    let strokes = [
        Stroke::new(vec![[10.0, 10.0], [70.0, 50.0]], 5.0),
        Stroke::new(vec![[10.0, 50.0], [70.0, 10.0]], 5.0),
        Stroke::new(vec![[15.0, 70.0], [65.0, 70.0]], 4.0),
    ];
    write_mask_png(&render(&strokes, 80, 80), path);
}

/// The upper median of `values` (the middle one of an odd count); panics on none ("no edge").
pub fn median(values: impl Iterator<Item = f64>) -> f64 {
    let mut values: Vec<f64> = values.collect();
    assert!(!values.is_empty(), "no edge");
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}
