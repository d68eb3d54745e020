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
    keep_freed_memory();
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

/// Keeps the memory a job frees for its next allocations instead of giving it back to the
/// system at once. glibc's allocator by default serves blocks over 128 KB (raised up to the
/// largest freed) with their own mappings and returns the top of a heap above 128 KB when it is
/// freed: a print's planes of 0.1-0.7 MB each, allocated and freed stage after stage, then come
/// back as fresh pages, and the kernel zeroes every page again on its first touch (about half
/// of a 500 ppi print's page faults, docs/performance.md, "Session of 2026-12-06, fourth").
/// Blocks up to 32 MB (glibc's largest threshold) now come from the heap, and up to 64 MB of
/// free memory at a heap's top stay there. The peak is unchanged: memory freed is reused, not
/// added to; a process keeps at most 64 MB more than it uses per heap.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    const MMAP_THRESHOLD: libc::c_int = 32 << 20;
    const TRIM_THRESHOLD: libc::c_int = 64 << 20;
    // SAFETY: `mallopt` only sets the allocator's parameters (under its own lock) and is called
    // here first thing in `main`, before any other thread exists. If it refuses a value (it
    // returns 0) the allocator keeps its defaults, which are correct, only slower.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
        libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD);
    }
}

/// Other allocators keep their own policies.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}
