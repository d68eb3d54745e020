//! The last step: the run. Inputs found, outputs planned, then every job traced in parallel
//! (`--jobs`), with a progress bar on a terminal; a failure or a panic in one file is that file's
//! failure, not the batch's; Ctrl-C lets the files being traced finish; warnings and failures
//! are reported after the run in input order, whatever the thread count.
//!
//! Exit status: 0 when every input was traced (a blank page is a warning, not a failure), 1 when
//! any input failed, 2 for usage errors (bad flags, parameters out of range, `-o -` with several
//! inputs), 130 when interrupted.

use std::fmt;
use std::fs;
use std::io::IsTerminal;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::FromArgMatches;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use ridgeline::export::json::JsonMeta;
use ridgeline::export::svg::Backdrop;
use ridgeline::point_list::PointData;
use ridgeline::raster::{Page, Picture};
use ridgeline::StrokeGraph;

use crate::flags::{self, Cli, Format};
use crate::inputs::{collect_inputs, read_stdin, sniff, Failure, Kind};
use crate::outputs::{
    page_destination, plan, render, render_space, write_debug_pictures, write_output, Destination,
    Job, Reserved,
};
use crate::settings::{describe, Settings};

/// What one traced input gave, for the line printed after a run.
struct Traced {
    warnings: Vec<String>,
    /// Where the output went, as the user should read it.
    output: String,
    vertices: usize,
    edges: usize,
    junctions: usize,
}

/// Parses the command line and runs it. Usage errors come back as [`UsageError`].
pub fn run() -> Result<ExitCode> {
    let parsed = flags::command()
        .try_get_matches()
        .and_then(|matches| Cli::from_arg_matches(&matches));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(err) => {
            // --help and --version are "errors" that print to stdout and exit 0; clap knows the
            // right stream and status for each.
            let _ = err.print();
            return Ok(ExitCode::from(err.exit_code().clamp(0, 255) as u8));
        }
    };
    if cli.help_method {
        print!("{}", flags::method_help());
        return Ok(ExitCode::SUCCESS);
    }
    let started = Instant::now();
    let settings = Settings::try_from(&cli)?;
    run_with(&settings, started)
}

fn run_with(settings: &Settings, started: Instant) -> Result<ExitCode> {
    let mut warnings = settings.ignored_flags.clone();
    let mut failures = Vec::new();
    let (files, batch) = collect_inputs(settings, &mut warnings, &mut failures);
    let unreadable_inputs = failures.len();
    let plan = plan(settings, files, batch)?;
    let jobs = &plan.jobs;

    let progress =
        (jobs.len() > 1 && !settings.quiet && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::new(jobs.len() as u64);
            if let Ok(style) =
                ProgressStyle::with_template("{bar:40} {pos}/{len} files, {elapsed} (eta {eta})")
            {
                bar.set_style(style);
            }
            bar
        });
    let mut pool = rayon::ThreadPoolBuilder::new().stack_size(ridgeline::WORKER_STACK_BYTES);
    if let Some(threads) = settings.threads {
        pool = pool.num_threads(threads);
        // One thread: this one, rather than a worker started for the run while this one waits
        // (its stack and its allocator's arena are pages touched for nothing).
        if threads == 1 {
            pool = pool.use_current_thread();
        }
    }
    let pool = pool.build().context("cannot start the worker threads")?;
    if jobs.len() > 1 {
        handle_interrupts(settings.quiet);
    }
    let outcomes: Vec<Outcome> = pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let outcome = run_job(job, settings, &plan.reserved);
                if let Some(bar) = &progress {
                    bar.inc(1);
                }
                outcome
            })
            .collect()
    });
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }

    // Reported in input order after the run, so that the messages are as deterministic as the
    // outputs, whatever the thread count.
    let mut traced = Vec::new();
    let mut skipped = 0;
    let mut not_started = Vec::new();
    for (job, outcome) in jobs.iter().zip(outcomes) {
        match outcome {
            Outcome::StdoutClosed => return Ok(ExitCode::SUCCESS),
            Outcome::NotStarted => not_started.push(job),
            Outcome::Skipped(reason) => {
                skipped += 1;
                warnings.push(format!(
                    "{}: skipped, {}",
                    job.input.display(),
                    NotAPointList(reason)
                ));
            }
            Outcome::Traced(result) => {
                warnings.extend(
                    result
                        .warnings
                        .iter()
                        .map(|w| format!("{}: {w}", job.input.display())),
                );
                traced.push((job, result));
            }
            Outcome::Failed(message) => failures.push(Failure {
                input: job.input.clone(),
                message,
            }),
        }
    }
    if !settings.quiet {
        for warning in &warnings {
            eprintln!("warning: {warning}");
        }
    }
    let total = jobs.len() + unreadable_inputs - skipped;
    if !not_started.is_empty() {
        let finished = traced.len() + failures.len() - unreadable_inputs;
        let failed = match failures.len() {
            0 => String::new(),
            n => format!(" ({n} failed)"),
        };
        eprintln!(
            "interrupted after {finished} of {} files{failed}; finished outputs kept; not traced: {}",
            jobs.len() - skipped,
            listed(not_started.iter().map(|job| job.input.display().to_string()))
        );
        for failure in &failures {
            eprintln!("  {}: {}", failure.input.display(), failure.message);
        }
        return Ok(ExitCode::from(INTERRUPTED_STATUS as u8));
    }
    if total == 0 {
        anyhow::bail!("nothing to trace: every file found was skipped");
    }
    if total <= 1 {
        if let Some(failure) = failures.first() {
            eprintln!("error: {}: {}", failure.input.display(), failure.message);
            return Ok(ExitCode::FAILURE);
        }
        if let (false, Some((job, result))) = (settings.quiet, traced.first()) {
            eprintln!(
                "{} -> {}: {} in {:.2} s",
                job.input.display(),
                result.output,
                counts(result),
                started.elapsed().as_secs_f64()
            );
        }
        return Ok(ExitCode::SUCCESS);
    }
    if !failures.is_empty() {
        eprintln!("error: {} of {total} inputs failed:", failures.len());
        for failure in &failures {
            eprintln!("  {}: {}", failure.input.display(), failure.message);
        }
    }
    if !settings.quiet {
        let (vertices, edges, junctions) = traced.iter().fold((0, 0, 0), |sum, (_, r)| {
            (sum.0 + r.vertices, sum.1 + r.edges, sum.2 + r.junctions)
        });
        let failed = match failures.len() {
            0 => String::new(),
            n => format!(", {n} failed"),
        };
        eprintln!(
            "traced {} of {total} inputs{failed} in {:.2} s ({vertices} vertices, {edges} edges, \
             {junctions} junctions)",
            traced.len(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok(if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// The first few of `names` and how many more there are.
fn listed(names: impl ExactSizeIterator<Item = String>) -> String {
    const SHOWN: usize = 5;
    let count = names.len();
    let mut shown: Vec<String> = names.take(SHOWN).collect();
    if count > SHOWN {
        shown.push(format!("and {} more", count - SHOWN));
    }
    shown.join(", ")
}

/// "12 vertices, 14 edges, 3 junctions".
fn counts(result: &Traced) -> String {
    format!(
        "{} vertices, {} edges, {} junctions",
        result.vertices, result.edges, result.junctions
    )
}

/// Runs one job; a panic inside the library becomes this file's failure instead of ending the
/// batch. Returns what the job gave, or the message of its failure.
fn run_job(job: &Job, settings: &Settings, reserved: &Reserved) -> Outcome {
    if INTERRUPTED.load(Ordering::SeqCst) {
        return Outcome::NotStarted;
    }
    match catch_unwind(AssertUnwindSafe(|| {
        trace_and_write(job, settings, reserved)
    })) {
        Ok(Ok(traced)) => Outcome::Traced(traced),
        Ok(Err(err)) => {
            if let Some(NotAPointList(reason)) = err.downcast_ref::<NotAPointList>() {
                return Outcome::Skipped(reason.clone());
            }
            let closed = err.chain().any(|cause| {
                cause
                    .downcast_ref::<std::io::Error>()
                    .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            });
            if closed && job.destination == Destination::Stdout {
                return Outcome::StdoutClosed;
            }
            Outcome::Failed(describe(&err))
        }
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Outcome::Failed(format!("internal error, please report it: {message}"))
        }
    }
}

/// What became of one job.
enum Outcome {
    Traced(Traced),
    /// A text file found in a directory that is no point list (see [`Kind::FoundText`]).
    Skipped(String),
    Failed(String),
    /// Ctrl-C came before the job started.
    NotStarted,
    /// The reader of standard output closed it (`ridgeline in.png -o - | head`): nothing more
    /// to say to anyone.
    StdoutClosed,
}

/// Why a [`Kind::FoundText`] file is not a point list.
#[derive(Debug)]
struct NotAPointList(String);

impl fmt::Display for NotAPointList {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "not a point list: {}", self.0)
    }
}

impl std::error::Error for NotAPointList {}

/// Set by the first Ctrl-C of a batch: files not yet started are left alone.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// From the first Ctrl-C on, a batch starts no more files and finishes those being traced (each
/// output is written whole or not at all); the second ends the process at once. Without a
/// handler (it could not be installed) Ctrl-C ends the process as usual.
fn handle_interrupts(quiet: bool) {
    let _ = ctrlc::set_handler(move || {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(INTERRUPTED_STATUS);
        }
        if !quiet {
            eprintln!("interrupted: finishing the files being traced (Ctrl-C again to stop now)");
        }
    });
}

/// The status of a process ended by Ctrl-C (128 + SIGINT), as shells report it.
const INTERRUPTED_STATUS: i32 = 130;

/// Reads one job's input, traces it (each page of a multi-page file) and writes its output.
fn trace_and_write(job: &Job, settings: &Settings, reserved: &Reserved) -> Result<Traced> {
    let params = &settings.params;
    let stdin = match job.kind {
        Kind::Stdin => Some(read_stdin()?),
        Kind::Image | Kind::PointList | Kind::FoundText => None,
    };
    let kind = match &stdin {
        Some(bytes) => sniff(bytes),
        None => job.kind,
    };
    if kind == Kind::FoundText || kind == Kind::PointList {
        let bytes = match stdin {
            Some(bytes) => Ok(bytes),
            None => fs::read(&job.input).context("cannot read the file"),
        };
        let extension = job.input.extension().and_then(|e| e.to_str());
        let clock = Instant::now();
        let data = bytes.and_then(|bytes| Ok(ridgeline::point_list::read(&bytes, extension)?));
        let parse = clock.elapsed();
        let data = match (kind, data) {
            (Kind::FoundText, Err(err)) => return Err(NotAPointList(format!("{err:#}")).into()),
            (Kind::FoundText, Ok(data)) if data.is_empty() => {
                return Err(NotAPointList("no points in it".into()).into())
            }
            (_, data) => data?,
        };
        if data.is_empty() {
            anyhow::bail!(
                "the point list has no points (only blank lines, comments or a header line)"
            );
        }
        let list = match data {
            PointData::Plane(list) => list,
            PointData::Space(list) => return trace_space(job, settings, &list, clock),
        };
        let mut trace = ridgeline::trace_points(&list, params)?;
        trace.timings.decode = parse;
        let mut warnings = Vec::new();
        if job.debug.is_some() {
            warnings.push("--debug draws pictures of images only; none for a point list".into());
        }
        if trace.graph.vertices.is_empty() {
            warnings.push("no strokes found; wrote an empty drawing".to_string());
        }
        let mut meta = JsonMeta::new(params.clone())
            .with_trace(&trace)
            .with_input("points2d");
        if settings.timings {
            meta = meta.with_timings(Some(trace.timings), clock.elapsed());
        }
        warnings.extend(trace.warnings.iter().map(|w| w.message.clone()));
        let text = render(
            job,
            settings,
            Kind::PointList,
            &trace,
            None,
            meta,
            None,
            &mut warnings,
        )?;
        let output = write_output(job, &job.destination, &text)?;
        return Ok(Traced::of(&trace.graph, warnings, output));
    }
    let bytes = match stdin {
        Some(bytes) => bytes,
        None => fs::read(&job.input).context("cannot read the file")?,
    };
    // Only an SVG with its backdrop shows the picture; without one no colour copy is kept.
    let pictures = settings.format == Format::Svg && settings.embed_image;
    let clock = Instant::now();
    let mut pages =
        ridgeline::raster::pages(&bytes, &params.front_end.limits)?.with_pictures(pictures);
    let count = pages.page_count();
    let file_dpi = pages.resolution();
    if count > 1 && job.destination == Destination::Stdout {
        anyhow::bail!(
            "the file has {count} pages and -o - writes one document; give an output file \
             (page 1 goes to it, page N to <name>.pN.svg beside it) or a directory"
        );
    }
    let mut warnings = Vec::new();
    if pages.chain_damaged() {
        warnings.push(format!(
            "the TIFF's list of pages is damaged after page {count}; traced the {count} page(s) \
             before the break"
        ));
    }
    if count == 1 {
        let page = pages.next().context("the file holds no image")??;
        let file = FileOf {
            count,
            file_dpi,
            started: clock,
            decode: clock.elapsed(),
        };
        // While the page is traced, the file's bytes are kept only if they are its picture.
        drop(pages);
        let bytes = match page.picture {
            Picture::Original { .. } => bytes,
            _ => Vec::new(),
        };
        let mut traced = trace_page(job, settings, reserved, &bytes, &page, &file)?;
        warnings.append(&mut traced.warnings);
        traced.warnings = warnings;
        return Ok(traced);
    }
    let mut failed = Vec::new();
    let mut all = Traced::of(&StrokeGraph::default(), warnings, String::new());
    let mut outputs = Vec::new();
    for number in 1..=count {
        let started = Instant::now();
        let Some(page) = pages.next() else { break };
        let file = FileOf {
            count,
            file_dpi,
            started,
            decode: started.elapsed(),
        };
        let traced = page
            .map_err(anyhow::Error::from)
            .and_then(|page| trace_page(job, settings, reserved, &bytes, &page, &file));
        match traced {
            Ok(traced) => {
                all.warnings.extend(
                    traced
                        .warnings
                        .into_iter()
                        .map(|w| format!("page {number}: {w}")),
                );
                all.vertices += traced.vertices;
                all.edges += traced.edges;
                all.junctions += traced.junctions;
                outputs.push(traced.output);
            }
            Err(err) => failed.push(format!("page {number}: {}", describe(&err))),
        }
    }
    if !failed.is_empty() {
        let written = match count - failed.len() {
            0 => "",
            _ => " (the others were written)",
        };
        anyhow::bail!(
            "{} of {count} pages failed{written}: {}",
            failed.len(),
            failed.join("; ")
        );
    }
    all.output = match (outputs.first(), outputs.last()) {
        (Some(first), Some(last)) => format!("{first} ... {last} ({count} pages)"),
        _ => String::new(),
    };
    Ok(all)
}

/// Traces a point set in space and writes it: JSON with `z`, PLY or OBJ polylines. SVG draws the
/// plane, and the minutiae formats a print's: for a 3D set they are an error that names what to
/// write instead.
fn trace_space(
    job: &Job,
    settings: &Settings,
    list: &[[f64; 3]],
    clock: Instant,
) -> Result<Traced> {
    if matches!(settings.format, Format::Svg | Format::Xyt | Format::Iso) {
        anyhow::bail!(
            "the points are in space (x y z), and {} output is for the plane; write JSON, PLY or \
             OBJ instead (-o NAME.json, -o NAME.ply, -o NAME.obj, or --format json|ply|obj)",
            settings.format.extension().to_uppercase()
        );
    }
    let trace = ridgeline::trace_points3d(list, &settings.params)?;
    let mut warnings = Vec::new();
    if job.debug.is_some() {
        warnings.push("--debug draws pictures of images only; none for a point list".into());
    }
    if trace.graph.vertices.is_empty() {
        warnings.push("no curves found; wrote an empty graph".to_string());
    }
    warnings.extend(trace.warnings.iter().map(|w| w.message.clone()));
    let text = render_space(job, settings, &trace, clock.elapsed());
    let output = write_output(job, &job.destination, &text)?;
    let graph = &trace.graph;
    Ok(Traced {
        warnings,
        output,
        vertices: graph.vertices.len(),
        edges: graph.edges.len(),
        junctions: graph.junctions().count(),
    })
}

impl Traced {
    fn of(graph: &StrokeGraph, warnings: Vec<String>, output: String) -> Traced {
        Traced {
            warnings,
            output,
            vertices: graph.vertices.len(),
            edges: graph.edges.len(),
            junctions: graph.vertices.iter().filter(|v| v.degree >= 3).count(),
        }
    }
}

/// What the front end left out of the trace as not strokes (docs/design.md, "The front end"),
/// with the flag that traces it: "left out 2 regions that are not strokes (halftone, frame): pass
/// --keep-regions halftone,frame to trace them". None when nothing was left out.
fn regions_left_out(
    regions: &[ridgeline::Region],
    kept: &[ridgeline::RegionKind],
) -> Option<String> {
    let out: Vec<ridgeline::RegionKind> = regions
        .iter()
        .map(|r| r.kind)
        .filter(|kind| !kept.contains(kind))
        .collect();
    if out.is_empty() {
        return None;
    }
    let mut kinds: Vec<&str> = out.iter().map(|k| k.name()).collect();
    kinds.sort_unstable();
    kinds.dedup();
    let names = kinds.join(",");
    Some(format!(
        "left out {} region{} that {} not strokes ({}): pass --keep-regions {names} to trace {}",
        out.len(),
        if out.len() == 1 { "" } else { "s" },
        if out.len() == 1 { "is" } else { "are" },
        kinds.join(", "),
        if out.len() == 1 { "it" } else { "them" },
    ))
}

/// What a page's trace needs to know of its file, and when its decoding started.
struct FileOf {
    /// The file's page count.
    count: usize,
    /// The resolution the file records, if any.
    file_dpi: Option<f64>,
    /// When the page's decoding started (the file's, for a single image).
    started: Instant,
    /// How long the page took to decode.
    decode: std::time::Duration,
}

/// Traces one page of an image file (`bytes`, of `file.count` pages) and writes its output: page 1
/// to the job's destination, page N to `<stem>.pN.<extension>` beside it.
fn trace_page(
    job: &Job,
    settings: &Settings,
    reserved: &Reserved,
    bytes: &[u8],
    page: &Page,
    file: &FileOf,
) -> Result<Traced> {
    let (count, file_dpi) = (file.count, file.file_dpi);
    let params = &settings.params;
    let debug = job.debug.as_ref().map(|dir| match page.number {
        1 => dir.clone(),
        n => dir.join(format!("p{n}")),
    });
    let mut trace = match &debug {
        Some(dir) => {
            // Traced once, keeping the stages of the output's own trace for the pictures.
            let mut trace = ridgeline::trace_image_with_stages(&page.gray, params)?;
            write_debug_pictures(&page.gray, &trace, dir)?;
            trace.stages = None;
            trace
        }
        None => ridgeline::trace_image(&page.gray, params)?,
    };
    let mut warnings = Vec::new();
    if trace.graph.vertices.is_empty() {
        let ink = trace.binary.as_ref().map_or(0, |binary| binary.count());
        warnings.push(match (ink, page.transparency) {
            (0, Some(t)) if t.opaque_pixels == 0 => "no ink found (blank page?): every pixel is \
                 transparent, and transparent pixels are read as paper; wrote an empty drawing"
                .to_string(),
            (0, Some(t)) => format!(
                "no ink found (blank page?): the image has transparency, read as paper, and its \
                 opaque pixels as {} ink on {} paper; wrote an empty drawing",
                if t.light_ink { "light" } else { "dark" },
                if t.light_ink { "black" } else { "white" },
            ),
            (0, None) => "no ink found (blank page?); wrote an empty drawing".to_string(),
            _ => "no strokes found; wrote an empty drawing".to_string(),
        });
    }
    let backdrop = match &page.picture {
        Picture::Original { mime } => Backdrop::Encoded { bytes, mime },
        Picture::Color(image) => Backdrop::Color(image),
        Picture::Gray => Backdrop::Gray(&page.gray),
    };
    trace.timings.decode = file.decode;
    let mut meta = JsonMeta::new(params.clone())
        .with_page(page.number, count)
        .with_trace(&trace);
    if settings.timings {
        meta = meta.with_timings(Some(trace.timings), file.started.elapsed());
    }
    warnings.extend(trace.warnings.iter().map(|w| w.message.clone()));
    if let Some(notice) = trace
        .decisions
        .as_ref()
        .and_then(|d| regions_left_out(&d.regions, &params.front_end.keep_regions))
    {
        warnings.push(notice);
    }
    let backdrop = settings.embed_image.then_some(backdrop);
    let text = render(
        job,
        settings,
        Kind::Image,
        &trace,
        backdrop,
        meta,
        file_dpi,
        &mut warnings,
    )?;
    let destination = page_destination(&job.destination, page.number);
    if let (Destination::File(path), true) = (&destination, page.number > 1) {
        reserved.check(path)?;
    }
    let output = write_output(job, &destination, &text)?;
    Ok(Traced::of(&trace.graph, warnings, output))
}
