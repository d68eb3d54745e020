//! The `ridgeline` command-line tool: a thin layer over the library, in the steps ripgrep takes.
//! `flags` (clap's definitions) → `settings` (one validated [`settings::Settings`], the only
//! thing later steps see) → `inputs` (the files to trace) → `outputs` (where each output goes,
//! and writing it) → `run` (the parallel loop, progress and the report).

mod flags;
mod inputs;
mod outputs;
mod run;
mod settings;

use std::process::ExitCode;

fn main() -> ExitCode {
    match run::run() {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            // Status 2 for a tool called wrongly, 1 for anything that went wrong while running.
            if err.downcast_ref::<settings::UsageError>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
