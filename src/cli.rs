//! The `ridgeline` command line: flags, turned into validated [`Params`] in one place
//! (`TryFrom<&Cli> for Params`), inputs into jobs (files, directories walked, outputs named), jobs
//! run in parallel, outputs written atomically, failures gathered and reported at the end.
//!
//! Exit status: 0 when every input was traced (a blank page is a warning, not a failure), 1 when
//! any input failed, 2 for usage errors (bad flags, parameters out of range, `-o -` with several
//! inputs).

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::fs;
use std::io::{IsTerminal, Write};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use ridgeline::curves::{fit_beziers, fit_edges, CurveOptions};
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, Backdrop, SvgOptions};
use ridgeline::export::Features;
use ridgeline::minutiae::{minutiae, MinutiaeOptions};
use ridgeline::raster::{Page, Picture};
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::{Params, Polarity, StrokeGraph, Threshold};

/// Sauvola window when `--sauvola` is given without `--window` (the value `Threshold` documents).
const SAUVOLA_WINDOW: u32 = 31;
/// Sauvola `k` when `--sauvola` is given without `--sauvola-k`.
const SAUVOLA_K: f64 = 0.2;

/// Extensions read as images (decoded by content, so a wrong extension still decodes).
const IMAGE_EXTENSIONS: &[&str] = &[
    "png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pnm", "pbm", "pgm", "ppm",
];
/// Extensions read as point lists.
const POINT_LIST_EXTENSIONS: &[&str] = &["txt", "csv", "xy", "pts"];

const EXAMPLES: &str = "\
Examples:
  Scanned page: writes page.svg next to page.png, centerlines over the scan
    ridgeline page.png
  Fingerprint with light ridges on a dark background, unevenly lit, as JSON
    ridgeline --polarity light --sauvola --window 25 print.png -o print.json
  Point list (\"x y\" or \"x,y\" per line) with the paper's own parameter values
    ridgeline --paper points.xy -o points.svg
  Batch: every image and point list under scans/, 4 files at a time, into out/
    ridgeline scans/ -o out/ --format json --jobs 4
  Why does a result look wrong? Pictures of every stage into stages/
    ridgeline --debug stages/ page.png

Outputs are written atomically: a failed run never leaves an output half-written or emptied.
Exit status: 0 on success (a blank page is a warning), 1 if any input failed, 2 on usage errors.";

/// Turns raster images of strokes (scans, handwriting, fingerprints) and point lists into stroke
/// graphs: centerline polylines meeting at junctions, written as SVG over the image or as JSON.
#[derive(Debug, Parser)]
#[command(name = "ridgeline", version, after_help = EXAMPLES, max_term_width = 100)]
pub struct Cli {
    /// Image files, point lists, or directories (walked recursively, files sorted by name); every
    /// page of a multi-page TIFF is traced (see --max-pages)
    #[arg(required = true, value_name = "INPUT")]
    inputs: Vec<PathBuf>,

    /// Output file, directory, or '-' for stdout [default: each input's path with its extension
    /// replaced by .svg or .json]
    ///
    /// PATH is a directory when there are several inputs or a directory input, when it ends in
    /// '/', or when it is an existing directory; it is created if missing. Files in it are named
    /// <input stem>.<svg|json>, with the parent directory's name added when two inputs share a
    /// stem.
    #[arg(short, long, value_name = "PATH", help_heading = "Output")]
    output: Option<PathBuf>,

    /// Output format [default: from the -o extension (.json or .svg), else svg]
    #[arg(short, long, value_enum, help_heading = "Output")]
    format: Option<Format>,

    /// SVG: do not embed the source image under the centerlines [default: embedded as given]
    ///
    /// PNG, JPEG, GIF and WebP files are embedded as they are (their own bytes); TIFF, BMP and
    /// PNM as a PNG of their pixels, in colour and with transparency when they have them, each
    /// page of a multi-page TIFF under its own output. (JPEG, PNG and WebP files with an
    /// orientation tag are embedded as their pixels too, unrotated, as they are traced.)
    #[arg(long, help_heading = "Output")]
    no_image: bool,

    /// SVG: do not mark endpoints (green) and junctions (blue)
    #[arg(long, help_heading = "Output")]
    no_vertices: bool,

    /// SVG: centerline width, px [default: max(0.6, 0.12 x median stroke width)]
    #[arg(long, value_name = "PX", help_heading = "Output")]
    line_width: Option<f64>,

    /// JSON: indent the document instead of writing one line
    #[arg(long, help_heading = "Output")]
    pretty: bool,

    /// Also draw every pipeline stage of each image as a PNG into DIR [default: no pictures]
    ///
    /// DIR is created if missing. The pictures: 1-foreground (the binarized ink), 2-sampling (the
    /// disks: linear blue, non-linear orange), 3-node-graph (graph H, a color per non-linear
    /// cluster), 4-refined (the 1-D graph), 5-fitted (a color per edge), 6-final (centerlines
    /// red, endpoints green, junctions blue). With several inputs each gets DIR/<output name>/.
    /// Point lists get no pictures.
    #[arg(long, value_name = "DIR", help_heading = "Output")]
    debug: Option<PathBuf>,
    /// SVG: draw strokes (edges chained straight through crossings, the way a pen drew them), each
    /// in its own color, instead of edges; JSON always lists the strokes
    #[arg(long, help_heading = "Features")]
    strokes: bool,

    /// SVG: draw each edge as wide as its mean stroke width, semi-transparent under its
    /// centerline, so the drawing covers the ink where the widths are right
    #[arg(long, help_heading = "Features")]
    width: bool,

    /// Fingerprint minutiae: ridge endings and bifurcations with their direction, except near the
    /// print's border, listed in the JSON and marked in the SVG
    #[arg(long, help_heading = "Features")]
    minutiae: bool,

    /// SVG: smooth cubic Bézier paths instead of polylines
    #[arg(long, help_heading = "Features")]
    curves: bool,

    /// Largest distance from a centerline point to its Bézier curve, px (> 0) [default: 0.5]
    #[arg(
        long,
        value_name = "PX",
        requires = "curves",
        help_heading = "Features"
    )]
    curve_tolerance: Option<f64>,

    /// Where the centerline turns by more than this, the curve keeps a corner, degrees (0-180)
    /// [default: 60]
    #[arg(
        long,
        value_name = "DEG",
        requires = "curves",
        help_heading = "Features"
    )]
    corner_angle: Option<f64>,

    /// Read every named file as a point list, whatever its extension (files ending in .txt, .csv,
    /// .xy or .pts always are)
    #[arg(long, help_heading = "Input and binarization")]
    points: bool,

    /// Fixed threshold: gray levels 0-255 at or below LEVEL are dark [default: Otsu's level]
    #[arg(
        long,
        value_name = "LEVEL",
        conflicts_with = "sauvola",
        help_heading = "Input and binarization"
    )]
    threshold: Option<u8>,

    /// Sauvola's adaptive threshold, for unevenly lit scans and photos [default: Otsu]
    #[arg(long, help_heading = "Input and binarization")]
    sauvola: bool,

    /// Sauvola window side, px (odd, >= 3) [default: 31]
    #[arg(
        long,
        value_name = "PX",
        requires = "sauvola",
        help_heading = "Input and binarization"
    )]
    window: Option<u32>,

    /// Sauvola sensitivity k, in [0, 1] [default: 0.2]
    #[arg(
        long,
        value_name = "K",
        requires = "sauvola",
        help_heading = "Input and binarization"
    )]
    sauvola_k: Option<f64>,

    /// Which side of the threshold is ink: the minority side, dark ink on light paper, or light
    /// strokes (fingerprint ridges) on a dark background [default: auto]
    #[arg(
        long,
        value_enum,
        value_name = "INK",
        help_heading = "Input and binarization"
    )]
    polarity: Option<PolarityArg>,

    /// Dropout mode for broken, speckled strokes (closing before the distance transform, wider
    /// neighbourhoods); auto decides from tiny background holes [default: auto]
    #[arg(
        long,
        value_enum,
        value_name = "MODE",
        help_heading = "Input and binarization"
    )]
    dropout: Option<Dropout>,

    /// Share of ink pixels that tiny background holes must exceed for auto dropout mode, in
    /// (0, 1) [default: 0.015]
    #[arg(long, value_name = "SHARE", help_heading = "Input and binarization")]
    dropout_fraction: Option<f64>,

    /// Start from the paper's own parameter values (r_min = 10 Dis_ave, r_max = 6 r_min, no arms
    /// test, whole-cluster merging, uniform fit weights, no clean-up); flags below still override
    #[arg(long, help_heading = "Method")]
    paper: bool,

    /// r_min factor: r_min = max(3 Dis_ave, factor x local stroke width), px; with --paper
    /// r_min = factor x Dis_ave [default: 1, paper: 10]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    r_min_factor: Option<f64>,

    /// r_max / r_min, >= 1 [default: 3, paper: 6]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    r_max_factor: Option<f64>,

    /// Disk radius growth per step, > 1 [default: 1.25]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    r_growth: Option<f64>,

    /// Linearity threshold of Eq. (3): a disk is linear when l > this, in (0.5, 1) [default: 0.9]
    #[arg(long, value_name = "L", help_heading = "Sampling (paper §3.1)")]
    linearity: Option<f64>,

    /// Detect non-linear nodes by PCA alone, without the rim "arms" test [default: arms test on,
    /// paper: off]
    #[arg(long, help_heading = "Sampling (paper §3.1)")]
    no_arms_test: bool,

    /// k nearest neighbours for point lists, 2-64 [default: 5]
    #[arg(
        long = "k",
        value_name = "K",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    k: Option<usize>,

    /// Cluster link length, in units of r_min: shorter edges join non-linear nodes into one
    /// cluster [default: 1.5]
    #[arg(
        long,
        value_name = "R_MIN",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    cluster_link: Option<f64>,

    /// Junction nodes of a cluster merge only when all are within this many r_min of each other
    /// ('inf' merges whole clusters) [default: 2, paper: inf]
    #[arg(
        long,
        value_name = "R_MIN",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    merge_span: Option<f64>,

    /// Skip the clean-up after §3.3 (hole-free cycles, spurs, short bars) and the placement of
    /// ends and junctions [default: clean-up on, paper: off]
    #[arg(long, help_heading = "Graph and refinement (paper §3.2, §3.3)")]
    no_cleanup: bool,

    /// Laplacian weight w of Eq. (4), >= 0: higher is smoother, lower follows the ink more
    /// closely [default: 1]
    #[arg(long, value_name = "W", help_heading = "Fitting (paper §3.4)")]
    smoothness: Option<f64>,

    /// Data weight on junctions and endpoints in the fit, > 0 [default: 10, paper: 1]
    #[arg(long, value_name = "WEIGHT", help_heading = "Fitting (paper §3.4)")]
    anchor_weight: Option<f64>,

    /// Weiszfeld iterations for the L1 medians [default: 20]
    #[arg(long, value_name = "N", help_heading = "Fitting (paper §3.4)")]
    weiszfeld_iterations: Option<usize>,

    /// Node spacing, in units of the median stroke width (at least 3 px) [default: 1]
    #[arg(long, value_name = "WIDTHS", help_heading = "Fitting (paper §3.4)")]
    spacing_factor: Option<f64>,

    /// Largest image decoded, in pixels (width x height) [default: 100000000]
    #[arg(long, value_name = "PIXELS", help_heading = "Limits")]
    max_pixels: Option<u64>,

    /// Largest image side, px [default: 65535]
    #[arg(long, value_name = "PX", help_heading = "Limits")]
    max_side: Option<u32>,

    /// Largest number of ink pixels or list points traced [default: 50000000]
    #[arg(long, value_name = "POINTS", help_heading = "Limits")]
    max_points: Option<u64>,

    /// Largest number of pages of a multi-page TIFF [default: 1000]
    ///
    /// Every page is traced, one at a time: page 1 to the input's output (<name>.svg), page N to
    /// <name>.pN.svg beside it (likewise .json, whose "source" then records "page" and "pages").
    /// A file with more pages is refused before any is decoded. '-o -' takes single-page inputs
    /// only.
    #[arg(long, value_name = "PAGES", help_heading = "Limits")]
    max_pages: Option<u64>,

    /// Files traced at once [default: number of CPU cores]
    #[arg(short, long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..), help_heading = "Running")]
    jobs: Option<u16>,

    /// Print errors only: no progress bar, no warnings
    #[arg(short, long, help_heading = "Running")]
    quiet: bool,
}

/// Output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Format {
    /// Centerlines drawn over the source image.
    Svg,
    /// Vertices, edges and statistics for other programs.
    Json,
}

impl Format {
    fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Json => "json",
        }
    }
}

/// `--polarity` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PolarityArg {
    /// The minority side after thresholding is ink.
    Auto,
    /// Dark ink on light paper.
    Dark,
    /// Light strokes on a dark background.
    Light,
}

/// `--dropout` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Dropout {
    /// Always on.
    On,
    /// Always off.
    Off,
    /// Decided from the image.
    Auto,
}

/// A mistake in how the tool was called; `main` exits with status 2 for it.
#[derive(Debug)]
pub struct UsageError(String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// The one place where flags become parameters: start from the defaults (or the paper's values
/// with `--paper`), apply only the flags that were given, then let [`Params::validate`] check the
/// ranges.
impl TryFrom<&Cli> for Params {
    type Error = UsageError;

    fn try_from(cli: &Cli) -> Result<Params, UsageError> {
        let mut params = if cli.paper {
            Params::paper()
        } else {
            Params::default()
        };
        if let Some(level) = cli.threshold {
            params.threshold = Threshold::Fixed { level };
        }
        if cli.sauvola {
            params.threshold = Threshold::Sauvola {
                window: cli.window.unwrap_or(SAUVOLA_WINDOW),
                k: cli.sauvola_k.unwrap_or(SAUVOLA_K),
            };
        }
        if let Some(polarity) = cli.polarity {
            params.polarity = match polarity {
                PolarityArg::Auto => Polarity::Auto,
                PolarityArg::Dark => Polarity::DarkInk,
                PolarityArg::Light => Polarity::LightInk,
            };
        }
        if let Some(dropout) = cli.dropout {
            params.dropout = match dropout {
                Dropout::On => Some(true),
                Dropout::Off => Some(false),
                Dropout::Auto => None,
            };
        }
        fn set<T: Copy>(field: &mut T, flag: Option<T>) {
            if let Some(value) = flag {
                *field = value;
            }
        }
        set(&mut params.dropout_fraction, cli.dropout_fraction);
        set(&mut params.r_min_factor, cli.r_min_factor);
        set(&mut params.r_max_factor, cli.r_max_factor);
        set(&mut params.r_growth, cli.r_growth);
        set(&mut params.linearity, cli.linearity);
        set(&mut params.k, cli.k);
        set(&mut params.cluster_link, cli.cluster_link);
        set(&mut params.merge_span, cli.merge_span);
        set(&mut params.smoothness, cli.smoothness);
        set(&mut params.anchor_weight, cli.anchor_weight);
        set(&mut params.weiszfeld_iterations, cli.weiszfeld_iterations);
        set(&mut params.spacing_factor, cli.spacing_factor);
        set(&mut params.limits.max_pixels, cli.max_pixels);
        set(&mut params.limits.max_side, cli.max_side);
        set(&mut params.limits.max_points, cli.max_points);
        set(&mut params.limits.max_pages, cli.max_pages);
        if cli.no_arms_test {
            params.arms_test = false;
        }
        if cli.no_cleanup {
            params.cleanup = false;
        }
        if !(params.dropout_fraction > 0.0 && params.dropout_fraction < 1.0) {
            return Err(UsageError(format!(
                "--dropout-fraction must be in (0, 1), got {}",
                params.dropout_fraction
            )));
        }
        params
            .validate()
            .map_err(|err| UsageError(err.to_string()))?;
        Ok(params)
    }
}

/// How an input file is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Image,
    PointList,
}

/// Where one output goes.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Destination {
    Stdout,
    File(PathBuf),
}

/// One input and where its output goes.
#[derive(Debug)]
struct Job {
    input: PathBuf,
    kind: Kind,
    destination: Destination,
    /// Where `--debug` pictures go.
    debug: Option<PathBuf>,
}

/// Everything that is the same for every job.
struct Settings {
    params: Params,
    format: Format,
    svg: SvgOptions,
    embed_image: bool,
    pretty: bool,
    /// `--strokes`.
    strokes: bool,
    /// `--minutiae`.
    minutiae: bool,
    /// `--curves` with its tolerance and corner angle.
    curves: Option<CurveOptions>,
}

/// An input that could not be traced, with the reason.
struct Failure {
    input: PathBuf,
    message: String,
}

/// Parses the command line and runs it. Usage errors come back as [`UsageError`].
pub fn run() -> Result<ExitCode> {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            // --help and --version are "errors" that print to stdout and exit 0; clap knows the
            // right stream and status for each.
            let _ = err.print();
            return Ok(ExitCode::from(err.exit_code().clamp(0, 255) as u8));
        }
    };
    run_with(&cli)
}

fn run_with(cli: &Cli) -> Result<ExitCode> {
    let params = Params::try_from(cli)?;
    if let Some(width) = cli.line_width.filter(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(UsageError(format!("--line-width must be > 0 px, got {width}")).into());
    }
    let curves = cli.curves.then(|| {
        let defaults = CurveOptions::default();
        CurveOptions {
            tolerance: cli.curve_tolerance.unwrap_or(defaults.tolerance),
            corner_angle_deg: cli.corner_angle.unwrap_or(defaults.corner_angle_deg),
        }
    });
    if let Some(options) = &curves {
        if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
            return Err(UsageError(format!(
                "--curve-tolerance must be > 0 px, got {}",
                options.tolerance
            ))
            .into());
        }
        if !(options.corner_angle_deg >= 0.0 && options.corner_angle_deg <= 180.0) {
            return Err(UsageError(format!(
                "--corner-angle must be in [0, 180] degrees, got {}",
                options.corner_angle_deg
            ))
            .into());
        }
    }
    let to_stdout = cli.output.as_deref() == Some(Path::new("-"));
    let format = cli.format.unwrap_or_else(|| match &cli.output {
        Some(path) if !to_stdout && extension_is(path, &["json"]) => Format::Json,
        _ => Format::Svg,
    });
    let settings = Settings {
        svg: SvgOptions::default()
            .with_show_vertices(!cli.no_vertices)
            .with_stroke_width(cli.line_width)
            .with_show_widths(cli.width),
        params,
        format,
        embed_image: !cli.no_image,
        pretty: cli.pretty,
        strokes: cli.strokes,
        minutiae: cli.minutiae,
        curves,
    };

    let mut warnings = Vec::new();
    let mut failures = Vec::new();
    let (files, batch) = collect_inputs(cli, &mut warnings, &mut failures);
    let unreadable_inputs = failures.len();
    let destinations = plan_outputs(cli, &files, batch, format)?;
    let several = files.len() > 1;
    let jobs: Vec<Job> = files
        .into_iter()
        .zip(destinations)
        .map(|((input, kind), destination)| {
            // One input draws into DIR itself; several into DIR/<output stem>, unique because
            // output names are.
            let debug = cli.debug.as_ref().map(|dir| match &destination {
                Destination::File(path) if several => {
                    dir.join(path.file_stem().unwrap_or(path.as_os_str()))
                }
                _ => dir.clone(),
            });
            Job {
                input,
                kind,
                destination,
                debug,
            }
        })
        .collect();

    let progress = (jobs.len() > 1 && !cli.quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(jobs.len() as u64);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} files, {elapsed} (eta {eta})")
        {
            bar.set_style(style);
        }
        bar
    });
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = cli.jobs {
        pool = pool.num_threads(usize::from(threads));
    }
    let pool = pool.build().context("cannot start the worker threads")?;
    let outcomes: Vec<Result<Vec<String>, String>> = pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let outcome = run_job(job, &settings);
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
    for (job, outcome) in jobs.iter().zip(outcomes) {
        match outcome {
            Ok(job_warnings) => warnings.extend(
                job_warnings
                    .into_iter()
                    .map(|w| format!("{}: {w}", job.input.display())),
            ),
            Err(message) => failures.push(Failure {
                input: job.input.clone(),
                message,
            }),
        }
    }
    if !cli.quiet {
        for warning in &warnings {
            eprintln!("warning: {warning}");
        }
    }
    if failures.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    let total = jobs.len() + unreadable_inputs;
    if total <= 1 {
        eprintln!(
            "error: {}: {}",
            failures[0].input.display(),
            failures[0].message
        );
    } else {
        eprintln!("error: {} of {total} inputs failed:", failures.len());
        for failure in &failures {
            eprintln!("  {}: {}", failure.input.display(), failure.message);
        }
    }
    Ok(ExitCode::FAILURE)
}

/// Expands the command line's inputs into the files to trace, in a fixed order: named files as
/// given, directories walked with their entries sorted by name. Inputs that do not exist and
/// directories with nothing to trace become failures; other files in directories are skipped
/// with a warning. Returns the files and whether this is a batch (several inputs or a directory).
fn collect_inputs(
    cli: &Cli,
    warnings: &mut Vec<String>,
    failures: &mut Vec<Failure>,
) -> (Vec<(PathBuf, Kind)>, bool) {
    let mut files = Vec::new();
    let mut seen = BTreeSet::new();
    let mut batch = cli.inputs.len() > 1;
    for input in &cli.inputs {
        let metadata = match fs::metadata(input) {
            Ok(metadata) => metadata,
            Err(err) => {
                failures.push(Failure {
                    input: input.clone(),
                    message: format!("cannot read: {err}"),
                });
                continue;
            }
        };
        if !metadata.is_dir() {
            let kind = if cli.points || extension_is(input, POINT_LIST_EXTENSIONS) {
                Kind::PointList
            } else {
                Kind::Image
            };
            if seen.insert(input.clone()) {
                files.push((input.clone(), kind));
            }
            continue;
        }
        batch = true;
        let mut found = Vec::new();
        let mut skipped = Vec::new();
        if let Err(err) = walk(input, &mut found, &mut skipped) {
            failures.push(Failure {
                input: input.clone(),
                message: format!("{err:#}"),
            });
            continue;
        }
        if !skipped.is_empty() {
            warnings.push(format!(
                "{}: skipped {} file(s) that are neither images nor point lists by extension, \
                 e.g. {}",
                input.display(),
                skipped.len(),
                skipped[0].display()
            ));
        }
        if found.is_empty() {
            failures.push(Failure {
                input: input.clone(),
                message: format!(
                    "no image or point-list files in this directory (extensions: {}, {})",
                    IMAGE_EXTENSIONS.join(" "),
                    POINT_LIST_EXTENSIONS.join(" ")
                ),
            });
            continue;
        }
        for path in found {
            let kind = if extension_is(&path, POINT_LIST_EXTENSIONS) {
                Kind::PointList
            } else {
                Kind::Image
            };
            if seen.insert(path.clone()) {
                files.push((path, kind));
            }
        }
    }
    (files, batch)
}

/// Walks `dir` recursively, entries sorted by name, collecting files with an image or point-list
/// extension into `found` and the others into `skipped`. Hidden entries (names starting with
/// '.') are ignored, and symbolic links to directories are not followed (no cycles).
fn walk(dir: &Path, found: &mut Vec<PathBuf>, skipped: &mut Vec<PathBuf>) -> Result<()> {
    let mut entries = fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("cannot list {}", dir.display()))?;
    entries.sort_by_key(|entry| entry.file_name());
    for entry in entries {
        if entry.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        let path = entry.path();
        let file_type = entry
            .file_type()
            .with_context(|| format!("cannot read {}", path.display()))?;
        if file_type.is_dir() {
            walk(&path, found, skipped)?;
        } else if file_type.is_symlink() && path.is_dir() {
            continue;
        } else if extension_is(&path, IMAGE_EXTENSIONS)
            || extension_is(&path, POINT_LIST_EXTENSIONS)
        {
            found.push(path);
        } else {
            skipped.push(path);
        }
    }
    Ok(())
}

/// Whether `path`'s extension is one of `extensions` (case-insensitive).
fn extension_is(path: &Path, extensions: &[&str]) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
}

/// Decides where each file's output goes (see `--output`), creating the output directory.
fn plan_outputs(
    cli: &Cli,
    files: &[(PathBuf, Kind)],
    batch: bool,
    format: Format,
) -> Result<Vec<Destination>> {
    let inputs: Vec<&Path> = files.iter().map(|(path, _)| path.as_path()).collect();
    let extension = format.extension();
    let Some(output) = &cli.output else {
        let next_to_input = |input: &Path| input.parent().unwrap_or(Path::new("")).to_path_buf();
        return Ok(unique_paths(&inputs, next_to_input, extension)
            .into_iter()
            .map(Destination::File)
            .collect());
    };
    if output.as_os_str() == "-" {
        if batch || files.len() > 1 {
            return Err(UsageError(
                "-o - writes one input to stdout; give one input file, or an output directory"
                    .into(),
            )
            .into());
        }
        return Ok(vec![Destination::Stdout; files.len()]);
    }
    let names_directory = output
        .as_os_str()
        .to_string_lossy()
        .ends_with(std::path::is_separator)
        || output.is_dir();
    if !(batch || names_directory) {
        return Ok(vec![Destination::File(output.clone()); files.len()]);
    }
    if output.exists() && !output.is_dir() {
        return Err(UsageError(format!(
            "{} is a file, but several inputs need an output directory",
            output.display()
        ))
        .into());
    }
    if !output.exists() && extension_is(output, &["svg", "json"]) {
        return Err(UsageError(format!(
            "several inputs need an output directory, not a file like {}",
            output.display()
        ))
        .into());
    }
    fs::create_dir_all(output)
        .with_context(|| format!("cannot create the output directory {}", output.display()))?;
    Ok(unique_paths(&inputs, |_| output.clone(), extension)
        .into_iter()
        .map(Destination::File)
        .collect())
}

/// Output paths `<dir>/<stem>.<extension>`, one per input, all different and none equal to an
/// input. Clashes are resolved deterministically (the result depends only on the list): inputs
/// that share a name get their parent directory's name appended (`page-scans.svg`), then their
/// own extension (`page-scans-png.svg`), then a counter in input order (`page-2.svg`).
fn unique_paths(
    inputs: &[&Path],
    directory_of: impl Fn(&Path) -> PathBuf,
    extension: &str,
) -> Vec<PathBuf> {
    let candidate = |input: &Path, level: usize| -> (PathBuf, String) {
        let stem = input
            .file_stem()
            .unwrap_or(input.as_os_str())
            .to_string_lossy();
        let mut base = stem.into_owned();
        if level >= 1 {
            if let Some(parent) = input.parent().and_then(Path::file_name) {
                base = format!("{base}-{}", parent.to_string_lossy());
            }
        }
        if level >= 2 {
            if let Some(own) = input.extension() {
                base = format!("{base}-{}", own.to_string_lossy());
            }
        }
        (directory_of(input), base)
    };
    let mut levels = vec![0usize; inputs.len()];
    for _ in 0..2 {
        let paths: Vec<PathBuf> = inputs
            .iter()
            .zip(&levels)
            .map(|(input, &level)| {
                let (dir, base) = candidate(input, level);
                dir.join(format!("{base}.{extension}"))
            })
            .collect();
        let mut count = BTreeMap::new();
        for path in &paths {
            *count.entry(path.clone()).or_insert(0usize) += 1;
        }
        let mut changed = false;
        for (path, level) in paths.iter().zip(&mut levels) {
            if count[path] > 1 {
                *level += 1;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // Never overwrite an input, and never give two inputs the same output.
    let mut taken: BTreeSet<PathBuf> = inputs.iter().map(|p| p.to_path_buf()).collect();
    inputs
        .iter()
        .zip(&levels)
        .map(|(input, &level)| {
            let (dir, base) = candidate(input, level);
            let mut path = dir.join(format!("{base}.{extension}"));
            let mut counter = 2;
            while taken.contains(&path) {
                path = dir.join(format!("{base}-{counter}.{extension}"));
                counter += 1;
            }
            taken.insert(path.clone());
            path
        })
        .collect()
}

/// Runs one job; a panic inside the library becomes this file's failure instead of ending the
/// batch. Returns the job's warnings, or the message of its failure.
fn run_job(job: &Job, settings: &Settings) -> Result<Vec<String>, String> {
    match catch_unwind(AssertUnwindSafe(|| trace_and_write(job, settings))) {
        Ok(Ok(warnings)) => Ok(warnings),
        Ok(Err(err)) => Err(format!("{err:#}")),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(format!("internal error, please report it: {message}"))
        }
    }
}

fn trace_and_write(job: &Job, settings: &Settings) -> Result<Vec<String>> {
    let params = &settings.params;
    if job.kind == Kind::PointList {
        let text = fs::read_to_string(&job.input).context("cannot read the file")?;
        let list = ridgeline::point_list::parse(&text)?;
        let trace = ridgeline::trace_points(&list, params)?;
        let mut warnings = Vec::new();
        if job.debug.is_some() {
            warnings.push("--debug draws pictures of images only; none for a point list".into());
        }
        if trace.graph.vertices.is_empty() {
            warnings.push(
                match list.len() {
                    0 => "the point list has no points; wrote an empty drawing",
                    _ => "no strokes found; wrote an empty drawing",
                }
                .to_string(),
            );
        }
        let meta = JsonMeta::new(params.clone());
        let text = render(job, settings, &trace.graph, None, None, meta);
        write_output(&job.destination, &text)?;
        return Ok(warnings);
    }
    let bytes = fs::read(&job.input).context("cannot read the file")?;
    // Only an SVG with its backdrop shows the picture; without one no colour copy is kept.
    let pictures = settings.format == Format::Svg && settings.embed_image;
    let mut pages = ridgeline::raster::pages(&bytes, &params.limits)?.with_pictures(pictures);
    let count = pages.page_count();
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
        // While the page is traced, the file's bytes are kept only if they are its picture.
        drop(pages);
        let bytes = match page.picture {
            Picture::Original { .. } => bytes,
            _ => Vec::new(),
        };
        warnings.extend(trace_page(job, settings, &bytes, &page, count)?);
        return Ok(warnings);
    }
    let mut failed = Vec::new();
    for (index, page) in pages.enumerate() {
        let number = index + 1;
        let traced = page
            .map_err(anyhow::Error::from)
            .and_then(|page| trace_page(job, settings, &bytes, &page, count));
        match traced {
            Ok(page_warnings) => warnings.extend(
                page_warnings
                    .into_iter()
                    .map(|w| format!("page {number}: {w}")),
            ),
            Err(err) => failed.push(format!("page {number}: {err:#}")),
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
    Ok(warnings)
}

/// Traces one page of an image file (`bytes`, of `count` pages) and writes its output: page 1 to
/// the job's destination, page N to `<stem>.pN.<extension>` beside it.
fn trace_page(
    job: &Job,
    settings: &Settings,
    bytes: &[u8],
    page: &Page,
    count: usize,
) -> Result<Vec<String>> {
    let params = &settings.params;
    let debug = job.debug.as_ref().map(|dir| match page.number {
        1 => dir.clone(),
        n => dir.join(format!("p{n}")),
    });
    let trace = match &debug {
        Some(dir) => trace_with_pictures(&page.gray, params, dir)?,
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
    let meta = JsonMeta::new(params.clone()).with_page(page.number, count);
    let backdrop = settings.embed_image.then_some(backdrop);
    let text = render(
        job,
        settings,
        &trace.graph,
        trace.binary.as_ref(),
        backdrop,
        meta,
    );
    write_output(&page_destination(&job.destination, page.number), &text)?;
    Ok(warnings)
}

/// Where page `number` of an input goes: page 1 to `destination`, page N to
/// `<stem>.pN.<extension>` beside it.
fn page_destination(destination: &Destination, number: usize) -> Destination {
    match destination {
        Destination::File(path) if number > 1 => {
            let mut name = path.file_stem().unwrap_or(path.as_os_str()).to_os_string();
            name.push(format!(".p{number}"));
            if let Some(extension) = path.extension() {
                name.push(".");
                name.push(extension);
            }
            Destination::File(path.with_file_name(name))
        }
        other => other.clone(),
    }
}

/// The output document of one traced graph: SVG over `backdrop`, or JSON with `meta`.
fn render(
    job: &Job,
    settings: &Settings,
    graph: &StrokeGraph,
    binary: Option<&ridgeline::Binary>,
    backdrop: Option<Backdrop>,
    meta: JsonMeta,
) -> String {
    // Strokes are cheap (one pass over the edge ends), so the JSON always lists them; the SVG
    // draws them on request.
    let chained = (settings.format == Format::Json || settings.strokes)
        .then(|| strokes(graph, &StrokeOptions::default()));
    // The foreground mask tells where the print ends; point lists have only the extent.
    let marks = settings
        .minutiae
        .then(|| minutiae(graph, binary, &MinutiaeOptions::default()));
    match settings.format {
        Format::Svg => {
            // Curves follow what is drawn: one list per stroke with --strokes, else per edge.
            let curves = settings.curves.map(|options| match &chained {
                Some(strokes) => strokes
                    .iter()
                    .map(|s| fit_beziers(&s.points, options.tolerance, options.corner_angle_deg))
                    .collect(),
                None => fit_edges(graph, &options),
            });
            let features = Features::default()
                .with_strokes(chained.as_deref())
                .with_minutiae(marks.as_deref())
                .with_curves(curves.as_deref());
            svg::to_string_with(graph, backdrop, &settings.svg, &features)
        }
        Format::Json => {
            let meta = meta
                .with_source_path(job.input.to_string_lossy())
                .with_pretty(settings.pretty);
            let features = Features::default()
                .with_strokes(chained.as_deref())
                .with_minutiae(marks.as_deref());
            json::to_string_with(graph, &meta, &features)
        }
    }
}

/// Writes one output document to stdout or (atomically) to its file.
fn write_output(destination: &Destination, text: &str) -> Result<()> {
    match destination {
        Destination::Stdout => {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(text.as_bytes())
                .context("cannot write to stdout")?;
            stdout.flush().context("cannot write to stdout")?;
        }
        Destination::File(path) => write_atomically(path, text.as_bytes())?,
    }
    Ok(())
}

/// Traces `gray` keeping the intermediate stages, and writes their pictures into `dir`.
fn trace_with_pictures(
    gray: &ridgeline::GrayImage,
    params: &Params,
    dir: &Path,
) -> Result<ridgeline::Trace> {
    let binary = ridgeline::raster::binarize(gray, params)?;
    let mut trace = ridgeline::trace_binary_with_stages(&binary, params)?;
    if let Some(stages) = &trace.stages {
        ridgeline::debug::write_stage_pictures(dir, &binary, stages, &trace.graph)
            .context("cannot write the --debug pictures")?;
    }
    trace.binary = Some(binary);
    Ok(trace)
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over `path`: readers see
/// the old file or the new one, never a truncated one, and a failure leaves the old file as it
/// was.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".ridgeline-").suffix(".tmp");
    // tempfile creates private (0600) files; outputs are ordinary files, readable as usual
    // (the umask still applies).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o644));
    }
    let mut file = builder
        .tempfile_in(dir)
        .with_context(|| format!("cannot create a file in {}", dir.display()))?;
    file.write_all(bytes)
        .with_context(|| format!("cannot write {}", path.display()))?;
    file.persist(path)
        .map_err(|err| err.error)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    fn parse(args: &[&str]) -> Cli {
        Cli::try_parse_from(std::iter::once("ridgeline").chain(args.iter().copied()))
            .expect("valid command line")
    }

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn no_flags_give_the_default_parameters() {
        let params = Params::try_from(&parse(&["a.png"])).expect("valid");
        assert_eq!(params, Params::default());
        let paper = Params::try_from(&parse(&["--paper", "a.png"])).expect("valid");
        assert_eq!(paper, Params::paper());
    }

    #[test]
    fn given_flags_override_the_preset() {
        let cli = parse(&[
            "--paper",
            "--r-min-factor",
            "7",
            "--merge-span",
            "3",
            "--k",
            "8",
            "--sauvola",
            "--window",
            "15",
            "--polarity",
            "light",
            "--dropout",
            "on",
            "--max-pixels",
            "1000",
            "--no-arms-test",
            "a.png",
        ]);
        let params = Params::try_from(&cli).expect("valid");
        assert!(params.paper);
        assert_eq!(params.r_min_factor, 7.0);
        assert_eq!(params.merge_span, 3.0);
        assert_eq!(params.k, 8);
        assert_eq!(
            params.threshold,
            Threshold::Sauvola {
                window: 15,
                k: SAUVOLA_K
            }
        );
        assert_eq!(params.polarity, Polarity::LightInk);
        assert_eq!(params.dropout, Some(true));
        assert_eq!(params.limits.max_pixels, 1000);
        assert!(!params.arms_test);
        // Untouched fields keep the paper's values.
        assert_eq!(params.r_max_factor, Params::paper().r_max_factor);
        assert_eq!(params.anchor_weight, Params::paper().anchor_weight);
    }

    #[test]
    fn out_of_range_parameters_are_usage_errors() {
        assert!(Params::try_from(&parse(&["--linearity", "1.5", "a.png"])).is_err());
        assert!(Params::try_from(&parse(&["--k", "1", "a.png"])).is_err());
        assert!(Params::try_from(&parse(&["--dropout-fraction", "2", "a.png"])).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--window", "9", "a.png"]).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--threshold", "300", "a.png"]).is_err());
        assert!(Cli::try_parse_from(["ridgeline", "--threshold", "9", "--sauvola", "a"]).is_err());
    }

    #[test]
    fn help_states_the_actual_defaults() {
        let help = Cli::command().render_long_help().to_string();
        let d = Params::default();
        let p = Params::paper();
        for expected in [
            format!("default: {}, paper: {}", d.r_min_factor, p.r_min_factor),
            format!("default: {}, paper: {}", d.r_max_factor, p.r_max_factor),
            format!("default: {}]", d.r_growth),
            format!("default: {}]", d.linearity),
            format!("default: {}]", d.k),
            format!("default: {}]", d.cluster_link),
            format!("default: {}, paper: inf", d.merge_span),
            format!("default: {}]", d.smoothness),
            format!("default: {}, paper: {}", d.anchor_weight, p.anchor_weight),
            format!("default: {}]", d.weiszfeld_iterations),
            format!("default: {}]", d.spacing_factor),
            format!("default: {}]", d.dropout_fraction),
            format!("default: {}]", d.limits.max_pixels),
            format!("default: {}]", d.limits.max_side),
            format!("default: {}]", d.limits.max_points),
            format!("default: {}]", d.limits.max_pages),
            format!("default: {SAUVOLA_WINDOW}]"),
            format!("default: {SAUVOLA_K}]"),
            format!("default: {}]", CurveOptions::default().tolerance),
            format!("default: {}]", CurveOptions::default().corner_angle_deg),
        ] {
            let flat = help.split_whitespace().collect::<Vec<_>>().join(" ");
            assert!(flat.contains(&expected), "help lacks {expected:?}");
        }
    }

    #[test]
    fn clashing_names_are_resolved_deterministically() {
        let inputs = [
            Path::new("a/page.png"),
            Path::new("b/page.png"),
            Path::new("b/page.jpg"),
            Path::new("c/x.png"),
        ];
        let out = Path::new("out");
        let paths = unique_paths(&inputs, |_| out.to_path_buf(), "svg");
        let names: Vec<String> = paths
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["page-a.svg", "page-b-png.svg", "page-b-jpg.svg", "x.svg"]
        );
        let next_to_input = unique_paths(&inputs, |p| p.parent().unwrap().to_path_buf(), "svg");
        assert_eq!(next_to_input[0], Path::new("a/page.svg"));
        assert_eq!(next_to_input[1], Path::new("b/page-b-png.svg"));
        assert_eq!(next_to_input[3], Path::new("c/x.svg"));
        // An output never replaces an input.
        let own = unique_paths(
            &[Path::new("d/x.svg")],
            |p| p.parent().unwrap().to_path_buf(),
            "svg",
        );
        assert_eq!(own[0], Path::new("d/x-2.svg"));
    }
}
