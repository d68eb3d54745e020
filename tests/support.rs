//! Helpers shared by the test modules that run the `ridgeline` binary.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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
