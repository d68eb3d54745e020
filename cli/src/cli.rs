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
use std::io::{IsTerminal, Read, Write};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

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
use ridgeline::{
    ClusterRule, Enhancement, LaplacianRule, Params, Polarity, RMinRule, StrokeGraph, Threshold,
};

/// Extensions read as images (decoded by content, so a wrong extension still decodes).
const IMAGE_EXTENSIONS: &[&str] = &[
    "png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pnm", "pbm", "pgm", "ppm",
];
/// The formats written, for messages.
const OUTPUT_FORMATS: &str =
    "SVG (.svg), JSON (.json), NIST minutiae (.xyt) and ISO/IEC 19794-2 records (.ist, .iso19794)";
/// Most bytes read from standard input (`-`).
const MAX_STDIN_BYTES: u64 = 4 << 30;

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

Outputs are written atomically: a failed run never leaves an output half-written or emptied,
and never writes over an input. Each run ends with one line on stderr (--quiet: none).
Exit status: 0 on success (a blank page is a warning), 1 if any input failed, 2 on usage errors.";

/// Turns raster images of strokes (scans, handwriting, fingerprints) and point lists into stroke
/// graphs: centerline polylines meeting at junctions, written as SVG over the image or as JSON.
#[derive(Debug, Parser)]
#[command(name = "ridgeline", version, after_help = EXAMPLES, max_term_width = 100)]
pub struct Cli {
    /// Image files, point lists, or directories (walked recursively, files sorted by name); '-'
    /// reads standard input (an image when its bytes start like one, else a point list); every
    /// page of a multi-page TIFF is traced (see --max-pages)
    #[arg(required = true, value_name = "INPUT")]
    inputs: Vec<PathBuf>,

    /// Output file (.svg or .json), directory, or '-' for stdout [default: each input's path
    /// with its extension replaced by .svg or .json; stdout for standard input]
    ///
    /// PATH is a directory when there are several inputs or a directory input, when it ends in
    /// '/', or when it is an existing directory; it is created if missing (the folder of an
    /// output file must exist). Outputs keep the inputs' layout in it: a file found at a/x.png
    /// in a walked directory is written to PATH/a/x.svg, and named files keep their paths below
    /// the deepest folder holding them all (a/x.png b/x.png: PATH/a/x.svg PATH/b/x.svg); names
    /// that still clash get the parent directory's name added. An output is never written over
    /// an input.
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
    /// Point lists get no pictures. The output is the same as without --debug; stages 2-5 are
    /// of the whole image as one point set (where dropout mode is decided per group of
    /// components, the output's groups are traced apart), 6-final is the output.
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

    /// How gray becomes ink and paper: auto uses Otsu's global level where it separates ink from
    /// paper all over the image and the local threshold (halfway between each neighbourhood's ink
    /// and paper, blocks of about six stroke widths) where the light or contrast varies; otsu and
    /// local force one. The JSON's "decisions" say what was used [default: auto]
    #[arg(
        long,
        value_enum,
        value_name = "METHOD",
        conflicts_with_all = ["sauvola", "threshold"],
        help_heading = "Input and binarization"
    )]
    binarize: Option<BinarizeArg>,

    /// Fixed threshold: gray levels 0-255 at or below LEVEL are dark [default: --binarize auto]
    #[arg(
        long,
        value_name = "LEVEL",
        conflicts_with = "sauvola",
        help_heading = "Input and binarization"
    )]
    threshold: Option<u8>,

    /// Sauvola's adaptive threshold with a fixed window [default: --binarize auto]
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

    /// Which side of the threshold is ink: auto decides from stroke evidence (ink is the thinner
    /// side, paper fills the border; dark when the evidence is weak, with a warning), and then
    /// per region (a thick field holding light strokes, white letters on a dark banner, is read
    /// as a ground: see --no-reverse-grounds); dark ink on light paper, or light strokes
    /// (fingerprint ridges) on a dark background, everywhere [default: auto]
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

    /// Drop ink components of fewer than N pixels before tracing (specks of a noisy scan; the
    /// speckle warning suggests a value) [default: 0]
    #[arg(long, value_name = "N", help_heading = "Input and binarization")]
    min_area: Option<usize>,

    /// Keep a gray image's centerline where the pixel grid puts it, without placing it below the
    /// pixel from the gray levels (each point moved along its normal, at most 0.75 px, to the
    /// middle of the stroke's cross-section) [default: refined, paper: not]
    #[arg(long, help_heading = "Input and binarization")]
    no_subpixel: bool,

    /// Place a gray image's centerline below the pixel from its gray levels; turns it back on
    /// after --paper [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_subpixel",
        help_heading = "Input and binarization"
    )]
    subpixel: bool,

    /// Keep as ink the thresholded pixels that a gray image shows lighter than the ink on both
    /// sides of them (crotches and gaps the blur filled), instead of giving them back to the
    /// paper [default: given back, paper: kept]
    #[arg(long, help_heading = "Input and binarization")]
    no_valleys: bool,

    /// Give a gray image's blur-filled crotches and gaps back to the paper; turns it back on
    /// after --paper [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_valleys",
        help_heading = "Input and binarization"
    )]
    valleys: bool,

    /// With --polarity auto, keep as ink a thick field holding light strokes (white letters on a
    /// dark banner) instead of reading it as a ground whose strokes are the ink [default: read
    /// as a ground, paper: kept as ink]
    #[arg(long, help_heading = "Input and binarization")]
    no_reverse_grounds: bool,

    /// Read thick fields holding light strokes as grounds; turns it back on after --paper
    /// [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_reverse_grounds",
        help_heading = "Input and binarization"
    )]
    reverse_grounds: bool,

    /// Start from the paper's own rules and values (r_min = 10 Dis_ave, r_max = 6 r_min, no arms
    /// test, equal-distance clusters, whole-cluster merging, uniform Laplacian and fit weights, no
    /// clean-up); every other flag given still overrides them
    #[arg(long, help_heading = "Method")]
    paper: bool,

    /// Fingerprint preset: segmentation, orientation field, ridge period and Gabor enhancement
    /// before tracing, and the minutiae inside the print, filtered and with a quality (implies
    /// --minutiae); every other flag given still overrides it (ridges dark or light as the image
    /// shows unless --polarity is given)
    #[arg(long, help_heading = "Method")]
    fingerprint: bool,

    /// The fingerprint front end's enhancement: a Gabor filter tuned to each block's ridge
    /// orientation and period, or oriented smoothing (an average along the ridge against its mean
    /// across one period: faster, docs/fingerprints.md compares them); implies --fingerprint
    /// [default: gabor]
    #[arg(long, value_name = "METHOD", help_heading = "Method")]
    enhance: Option<EnhanceArg>,

    /// Resolution written into ISO/IEC 19794-2 records, dots per inch [default: the one the
    /// image file states (PNG pHYs, JPEG JFIF density, TIFF XResolution), else 500]
    #[arg(long, value_name = "DPI", help_heading = "Output")]
    dpi: Option<f64>,

    /// Centerlines from the node graph's own fitted polylines (§3.4) instead of the pixel
    /// skeleton the method decides on: faster, but chords cut across cells, counters and loops
    /// finer than a stroke width [default: skeleton on, paper: off]
    #[arg(long, help_heading = "Method")]
    no_skeleton: bool,

    /// Centerlines carried by a pixel skeleton of the ink (every hole a cycle, no edge off the
    /// ink), crossings, spurs and bends decided by the method's graph; turns it back on after
    /// --paper (images only; not in dropout mode) [default: on, paper: off]
    #[arg(long, overrides_with = "no_skeleton", help_heading = "Method")]
    skeleton: bool,

    /// How r_min is chosen: from the local stroke width or from the point spacing Dis_ave
    /// [default: width, paper: spacing]
    #[arg(
        long,
        value_enum,
        value_name = "RULE",
        help_heading = "Sampling (paper §3.1)"
    )]
    r_min_rule: Option<RMinRuleArg>,

    /// r_min factor: r_min = max(3 Dis_ave, factor x local stroke width), px; with
    /// --r-min-rule spacing r_min = factor x Dis_ave [default: 1, paper: 10]
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

    /// Use the rim "arms" test besides PCA, also with --paper (the last of --arms-test and
    /// --no-arms-test wins)
    #[arg(
        long,
        overrides_with = "no_arms_test",
        help_heading = "Sampling (paper §3.1)"
    )]
    arms_test: bool,

    /// k nearest neighbours for point lists, 2-64 [default: 5]
    #[arg(
        long = "k",
        value_name = "K",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    k: Option<usize>,

    /// Which nodes form the clusters (non-linear regions) that refinement merges
    /// [default: non-linear, paper: equal-distance]
    #[arg(
        long,
        value_enum,
        value_name = "RULE",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    clusters: Option<ClusterArg>,

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

    /// Run the clean-up after §3.3 and the placement of ends and junctions, also with --paper
    /// (the last of --cleanup and --no-cleanup wins)
    #[arg(
        long,
        overrides_with = "no_cleanup",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    cleanup: bool,

    /// Smoothness term of Eq. (4): held (degree-2 nodes only) or the uniform Laplacian over every
    /// node [default: held, paper: uniform]
    #[arg(
        long,
        value_enum,
        value_name = "RULE",
        help_heading = "Fitting (paper §3.4)"
    )]
    laplacian: Option<LaplacianArg>,

    /// Laplacian weight w of Eq. (4), >= 0: higher is smoother, lower follows the ink more
    /// closely [default: 1]
    #[arg(long, value_name = "W", help_heading = "Fitting (paper §3.4)")]
    smoothness: Option<f64>,

    /// Data weight on junctions and endpoints in the fit, > 0 [default: 10, paper: 1]
    #[arg(long, value_name = "WEIGHT", help_heading = "Fitting (paper §3.4)")]
    anchor_weight: Option<f64>,

    /// Weiszfeld iterations for the L1 medians, 0-1000 [default: 20]
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

    /// Print errors only: no summary line, no progress bar, no warnings
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
    /// Minutiae as NIST `x y theta quality` lines (Bozorth3's input).
    Xyt,
    /// Minutiae as an ISO/IEC 19794-2:2005 finger minutiae record (binary).
    Iso,
}

impl Format {
    fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Json => "json",
            Format::Xyt => "xyt",
            Format::Iso => "ist",
        }
    }
}

/// `--binarize` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum BinarizeArg {
    /// Otsu where the light is even, the local threshold where it is not.
    Auto,
    /// Otsu's global level everywhere.
    Otsu,
    /// The local threshold everywhere.
    Local,
}

/// `--polarity` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PolarityArg {
    /// Decided from stroke evidence.
    Auto,
    /// Dark ink on light paper.
    Dark,
    /// Light strokes on a dark background.
    Light,
}

/// `--r-min-rule` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum RMinRuleArg {
    /// r_min = max(3 Dis_ave, factor x local stroke width).
    Width,
    /// r_min = factor x Dis_ave, as in the paper.
    Spacing,
}

/// `--clusters` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ClusterArg {
    /// Non-linear nodes joined by short edges.
    NonLinear,
    /// Nodes at equal shortest distance from a root, as in the paper.
    EqualDistance,
}

/// `--laplacian` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum LaplacianArg {
    /// Smoothness rows for degree-2 nodes only.
    Held,
    /// The uniform Laplacian of every node, as in the paper.
    Uniform,
}

/// `--enhance` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum EnhanceArg {
    /// Gabor filter per block.
    Gabor,
    /// Oriented smoothing along and across the ridges.
    Smoothing,
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
        if cli.fingerprint || cli.enhance.is_some() {
            params.fingerprint = Params::fingerprint().fingerprint;
        }
        if let (Some(method), Some(print)) = (cli.enhance, params.fingerprint.as_mut()) {
            print.enhancement = match method {
                EnhanceArg::Gabor => Enhancement::Gabor,
                EnhanceArg::Smoothing => Enhancement::Smoothing,
            };
        }
        if let Some(method) = cli.binarize {
            params.front_end.threshold = match method {
                BinarizeArg::Auto => Threshold::Auto,
                BinarizeArg::Otsu => Threshold::Otsu,
                BinarizeArg::Local => Threshold::Local,
            };
        }
        if let Some(level) = cli.threshold {
            params.front_end.threshold = Threshold::Fixed { level };
        }
        if cli.sauvola {
            params.front_end.threshold = Threshold::Sauvola {
                window: cli.window.unwrap_or(Threshold::DEFAULT_SAUVOLA_WINDOW),
                k: cli.sauvola_k.unwrap_or(Threshold::DEFAULT_SAUVOLA_K),
            };
        }
        if let Some(polarity) = cli.polarity {
            params.front_end.polarity = match polarity {
                PolarityArg::Auto => Polarity::Auto,
                PolarityArg::Dark => Polarity::DarkInk,
                PolarityArg::Light => Polarity::LightInk,
            };
        }
        if let Some(dropout) = cli.dropout {
            params.front_end.dropout = match dropout {
                Dropout::On => Some(true),
                Dropout::Off => Some(false),
                Dropout::Auto => None,
            };
        }
        if let Some(rule) = cli.r_min_rule {
            params.method.r_min_rule = match rule {
                RMinRuleArg::Width => RMinRule::StrokeWidth,
                RMinRuleArg::Spacing => RMinRule::Spacing,
            };
        }
        if let Some(rule) = cli.clusters {
            params.method.cluster_rule = match rule {
                ClusterArg::NonLinear => ClusterRule::NonLinear,
                ClusterArg::EqualDistance => ClusterRule::EqualDistance,
            };
        }
        if let Some(rule) = cli.laplacian {
            params.fit.laplacian = match rule {
                LaplacianArg::Held => LaplacianRule::Held,
                LaplacianArg::Uniform => LaplacianRule::Uniform,
            };
        }
        fn set<T: Copy>(field: &mut T, flag: Option<T>) {
            if let Some(value) = flag {
                *field = value;
            }
        }
        set(&mut params.front_end.dropout_fraction, cli.dropout_fraction);
        set(&mut params.front_end.min_area, cli.min_area);
        set(&mut params.method.r_min_factor, cli.r_min_factor);
        set(&mut params.method.r_max_factor, cli.r_max_factor);
        set(&mut params.method.r_growth, cli.r_growth);
        set(&mut params.method.linearity, cli.linearity);
        set(&mut params.method.k, cli.k);
        set(&mut params.method.cluster_link, cli.cluster_link);
        set(&mut params.method.merge_span, cli.merge_span);
        set(&mut params.fit.smoothness, cli.smoothness);
        set(&mut params.fit.anchor_weight, cli.anchor_weight);
        set(
            &mut params.fit.weiszfeld_iterations,
            cli.weiszfeld_iterations,
        );
        set(&mut params.fit.spacing_factor, cli.spacing_factor);
        set(&mut params.front_end.limits.max_pixels, cli.max_pixels);
        set(&mut params.front_end.limits.max_side, cli.max_side);
        set(&mut params.front_end.limits.max_points, cli.max_points);
        set(&mut params.front_end.limits.max_pages, cli.max_pages);
        if cli.no_arms_test {
            params.method.arms_test = false;
        }
        if cli.arms_test {
            params.method.arms_test = true;
        }
        if cli.no_cleanup {
            params.finish.cleanup = false;
        }
        if cli.cleanup {
            params.finish.cleanup = true;
        }
        if cli.no_subpixel {
            params.front_end.subpixel = false;
        }
        if cli.subpixel {
            params.front_end.subpixel = true;
        }
        if cli.no_valleys {
            params.front_end.valleys = false;
        }
        if cli.valleys {
            params.front_end.valleys = true;
        }
        if cli.no_reverse_grounds {
            params.front_end.reverse_grounds = false;
        }
        if cli.reverse_grounds {
            params.front_end.reverse_grounds = true;
        }
        if cli.no_skeleton {
            params.finish.skeleton = false;
        }
        if cli.skeleton {
            params.finish.skeleton = true;
        }
        params.validate().map_err(|err| match err {
            ridgeline::Error::InvalidParam { field, reason } => {
                UsageError(format!("{} {reason}", flag_of(field)))
            }
            other => UsageError(other.to_string()),
        })?;
        Ok(params)
    }
}

/// The flag that sets a [`Params`] field, as named by [`Params::validate`]'s errors and by the
/// library's limit errors.
fn flag_of(field: &str) -> String {
    match field {
        "threshold.window" => "--window".into(),
        "threshold.k" => "--sauvola-k".into(),
        other => format!(
            "--{}",
            other.trim_start_matches("limits.").replace('_', "-")
        ),
    }
}

/// `err` as the command line reports it, each cause after the one before as `{err:#}` writes
/// them, except that a limit of the library, which names its [`Params`] field, names the flag
/// that raises it.
fn describe(err: &anyhow::Error) -> String {
    err.chain()
        .map(|cause| match cause.downcast_ref::<ridgeline::Error>() {
            Some(ridgeline::Error::Limit {
                what,
                actual,
                limit,
                field,
            }) => format!(
                "{what}: {actual}, over the limit of {limit}; raise it with {} if the input is \
                 trusted",
                flag_of(field)
            ),
            _ => cause.to_string(),
        })
        .collect::<Vec<_>>()
        .join(": ")
}

/// How an input file is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Image,
    PointList,
    /// Standard input (`-`): an image when the bytes start like one, else a point list.
    Stdin,
    /// A file with a point-list extension found in a walked directory: a point list when it
    /// parses as one with at least one point, else skipped with a warning (a `README.txt` among
    /// the scans).
    FoundText,
}

/// One input file, as found on the command line or in a walked directory.
#[derive(Clone, Debug)]
struct InputFile {
    path: PathBuf,
    kind: Kind,
    /// Its place under an output directory: the path below the walked directory it was found in,
    /// or, for a named file, below the deepest folder holding all named files
    /// ([`lay_out_named_files`]). `a/x.png` and `b/x.png` thus keep apart as `out/a/x.svg` and
    /// `out/b/x.svg`.
    layout: PathBuf,
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
    /// The destination lies in a subfolder of the output directory, created when writing.
    create_folder: bool,
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
    /// `--minutiae` (or `--fingerprint`).
    minutiae: bool,
    /// `--dpi`, for ISO/IEC 19794-2 records (else the file's, else [`DEFAULT_DPI`]).
    dpi: Option<f64>,
    /// `--curves` with its tolerance and corner angle.
    curves: Option<CurveOptions>,
    /// What later pages of a multi-page input (named inside the job, `name.pN.svg`) must not
    /// write over: the inputs, by identity, and the outputs planned for the other inputs.
    reserved: Reserved,
}

/// Files no page output may replace (see [`Settings::reserved`]).
#[derive(Default)]
struct Reserved {
    inputs: BTreeMap<FileId, PathBuf>,
    outputs: BTreeSet<PathBuf>,
}

impl Reserved {
    fn of(jobs: &[Job]) -> Reserved {
        Reserved {
            inputs: jobs
                .iter()
                .filter(|job| job.input.as_os_str() != "-")
                .filter_map(|job| Some((file_id(&job.input)?, job.input.clone())))
                .collect(),
            outputs: jobs
                .iter()
                .filter_map(|job| match &job.destination {
                    Destination::File(path) => Some(path.clone()),
                    Destination::Stdout => None,
                })
                .collect(),
        }
    }

    /// The message refusing `path` when it is one of the inputs.
    fn overwrites_input(&self, path: &Path) -> Option<String> {
        let input = file_id(path).and_then(|id| self.inputs.get(&id))?;
        Some(format!(
            "{} is the input {}: ridgeline never writes over its inputs; choose another output \
             with -o",
            path.display(),
            input.display()
        ))
    }

    /// Refuses a page output that is an input or another input's planned output.
    fn check(&self, path: &Path) -> Result<()> {
        if let Some(message) = self.overwrites_input(path) {
            anyhow::bail!(message);
        }
        if self.outputs.contains(path) {
            anyhow::bail!(
                "{} is also the output of another input; give the inputs different names or \
                 an output directory",
                path.display()
            );
        }
        Ok(())
    }
}

/// What one traced input gave, for the line printed after a run.
struct Traced {
    warnings: Vec<String>,
    /// Where the output went, as the user should read it.
    output: String,
    vertices: usize,
    edges: usize,
    junctions: usize,
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
    let started = Instant::now();
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
    let format = output_format(cli)?;
    let mut settings = Settings {
        svg: SvgOptions::default()
            .with_show_vertices(!cli.no_vertices)
            .with_stroke_width(cli.line_width)
            .with_show_widths(cli.width),
        params,
        format,
        embed_image: !cli.no_image,
        pretty: cli.pretty,
        strokes: cli.strokes,
        minutiae: cli.minutiae || cli.fingerprint || cli.enhance.is_some(),
        dpi: cli.dpi,
        curves,
        reserved: Reserved::default(),
    };

    let mut warnings = ignored_flags(cli, format);
    let mut failures = Vec::new();
    let (files, batch) = collect_inputs(cli, &mut warnings, &mut failures);
    let unreadable_inputs = failures.len();
    let destinations = plan_outputs(cli, &files, batch, format)?;
    let several = files.len() > 1;
    let jobs: Vec<Job> = files
        .into_iter()
        .zip(destinations)
        .map(|(file, (destination, create_folder))| {
            // One input draws into DIR itself; several into DIR/<output path without its
            // extension>, unique because output paths are.
            let debug = cli.debug.as_ref().map(|dir| match &destination {
                Destination::File(path) if several => dir.join(debug_folder(cli, path)),
                _ => dir.clone(),
            });
            Job {
                input: file.path,
                kind: file.kind,
                destination,
                create_folder,
                debug,
            }
        })
        .collect();
    settings.reserved = Reserved::of(&jobs);
    refuse_overwriting_inputs(&jobs, &settings.reserved)?;

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
    if jobs.len() > 1 {
        handle_interrupts(cli.quiet);
    }
    let outcomes: Vec<Outcome> = pool.install(|| {
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
    if !cli.quiet {
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
        if let (false, Some((job, result))) = (cli.quiet, traced.first()) {
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
    if !cli.quiet {
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

/// The output format: `--format`, else the `-o` file's extension, else SVG. An `-o` file whose
/// extension is not one ridgeline writes, or that contradicts `--format`, is a usage error: it
/// would otherwise get SVG text under a name that promises something else.
fn output_format(cli: &Cli) -> Result<Format, UsageError> {
    let file = cli
        .output
        .as_deref()
        .filter(|path| path.as_os_str() != "-" && !names_directory(path));
    let from_extension = match file.and_then(Path::extension) {
        None => None,
        Some(extension) => {
            let lower = extension.to_string_lossy().to_ascii_lowercase();
            match lower.as_str() {
                "svg" => Some(Format::Svg),
                "json" => Some(Format::Json),
                "xyt" => Some(Format::Xyt),
                "ist" | "iso19794" => Some(Format::Iso),
                _ => {
                    return Err(UsageError(format!(
                        "-o {}: ridgeline writes {OUTPUT_FORMATS}, not .{lower} (an output \
                         without an extension gets --format, or svg)",
                        cli.output.as_deref().unwrap_or(Path::new("")).display()
                    )))
                }
            }
        }
    };
    match (cli.format, from_extension) {
        (Some(flag), Some(extension)) if flag != extension => Err(UsageError(format!(
            "--format {} contradicts -o {}",
            flag.extension(),
            cli.output.as_deref().unwrap_or(Path::new("")).display()
        ))),
        (Some(flag), _) => Ok(flag),
        (None, Some(extension)) => Ok(extension),
        (None, None) => Ok(Format::Svg),
    }
}

/// Whether `-o path` names a directory whatever the number of inputs: it ends in a separator or
/// is an existing directory.
fn names_directory(path: &Path) -> bool {
    path.as_os_str()
        .to_string_lossy()
        .ends_with(std::path::is_separator)
        || path.is_dir()
}

/// Warnings for the flags given that change nothing in the chosen format.
fn ignored_flags(cli: &Cli, format: Format) -> Vec<String> {
    let (given, changes): (Vec<&str>, &str) = match format {
        Format::Json => (
            [
                (cli.no_image, "--no-image"),
                (cli.no_vertices, "--no-vertices"),
                (cli.line_width.is_some(), "--line-width"),
                (cli.width, "--width"),
                (cli.strokes, "--strokes"),
            ]
            .into_iter()
            .filter_map(|(on, flag)| on.then_some(flag))
            .collect(),
            "change only the SVG (the JSON always holds every width and the strokes)",
        ),
        Format::Svg => (
            cli.pretty.then_some("--pretty").into_iter().collect(),
            "changes only the JSON",
        ),
        Format::Xyt | Format::Iso => (
            [
                (cli.pretty, "--pretty"),
                (cli.strokes, "--strokes"),
                (cli.width, "--width"),
                (cli.curves, "--curves"),
            ]
            .into_iter()
            .filter_map(|(on, flag)| on.then_some(flag))
            .collect(),
            "change nothing in a minutiae file",
        ),
    };
    if given.is_empty() {
        return Vec::new();
    }
    let changes = if given.len() == 1 {
        changes.replacen("change ", "changes ", 1)
    } else {
        changes.replacen("changes ", "change ", 1)
    };
    vec![format!(
        "{} {changes}; writing {}",
        given.join(", "),
        format.extension().to_uppercase()
    )]
}

/// Expands the command line's inputs into the files to trace, in a fixed order: named files as
/// given, directories walked with their entries sorted by name. Inputs that do not exist and
/// directories with nothing to trace become failures; other files in directories are skipped
/// with a warning, except the formats ridgeline writes (its own earlier outputs) and the output
/// and `--debug` folders when they lie inside a walked directory. Returns the files and whether
/// this is a batch (several inputs or a directory).
fn collect_inputs(
    cli: &Cli,
    warnings: &mut Vec<String>,
    failures: &mut Vec<Failure>,
) -> (Vec<InputFile>, bool) {
    let mut files = Vec::new();
    let mut named = Vec::new();
    let mut seen = BTreeSet::new();
    let mut batch = cli.inputs.len() > 1;
    // Folders ridgeline writes into are never walked as inputs.
    let own_folders: Vec<PathBuf> = [cli.output.as_deref(), cli.debug.as_deref()]
        .into_iter()
        .flatten()
        .filter_map(|path| fs::canonicalize(path).ok())
        .filter(|path| path.is_dir())
        .collect();
    for input in &cli.inputs {
        if input.as_os_str() == "-" {
            if seen.insert(input.clone()) {
                files.push(InputFile {
                    path: input.clone(),
                    kind: if cli.points {
                        Kind::PointList
                    } else {
                        Kind::Stdin
                    },
                    layout: PathBuf::from("stdin"),
                });
            }
            continue;
        }
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
                named.push(files.len());
                files.push(InputFile {
                    path: input.clone(),
                    kind,
                    layout: PathBuf::new(),
                });
            }
            continue;
        }
        batch = true;
        let mut found = Vec::new();
        let mut skipped = Vec::new();
        if let Err(err) = walk(input, &own_folders, &mut found, &mut skipped) {
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
                Kind::FoundText
            } else {
                Kind::Image
            };
            let layout = path.strip_prefix(input).unwrap_or(&path).to_path_buf();
            if seen.insert(path.clone()) {
                files.push(InputFile { path, kind, layout });
            }
        }
    }
    lay_out_named_files(&mut files, &named);
    (files, batch)
}

/// Gives the files named on the command line their place under an output directory (see
/// [`InputFile::layout`]): their paths below the deepest folder that holds them all, so that
/// `scans/a.png scans/b.png` become `a.svg b.svg` and `a/x.png b/x.png` become `a/x.svg b/x.svg`.
/// Paths that climb out with `..` keep only their file name.
fn lay_out_named_files(files: &mut [InputFile], named: &[usize]) {
    fn parts(path: &Path) -> Option<Vec<Component<'_>>> {
        let kept: Vec<Component> = path
            .components()
            .filter(|c| *c != Component::CurDir)
            .collect();
        (!kept.contains(&Component::ParentDir)).then_some(kept)
    }
    let mut common: Option<Vec<Component>> = None;
    for &i in named {
        let Some(mut folder) = parts(&files[i].path) else {
            continue;
        };
        folder.pop();
        common = Some(match common {
            None => folder,
            Some(prefix) => prefix
                .into_iter()
                .zip(folder)
                .take_while(|(a, b)| a == b)
                .map(|(a, _)| a)
                .collect(),
        });
    }
    let depth = common.map_or(0, |prefix| prefix.len());
    for &i in named {
        let path = &files[i].path;
        files[i].layout = match parts(path) {
            Some(kept) => kept[depth.min(kept.len().saturating_sub(1))..]
                .iter()
                .collect(),
            None => PathBuf::from(path.file_name().unwrap_or(path.as_os_str())),
        };
    }
}

/// Walks `dir` recursively, entries sorted by name, collecting files with an image or point-list
/// extension into `found` and the others into `skipped`. Hidden entries (names starting with
/// '.'), the formats ridgeline writes and the folders in `own_folders` (canonical paths) are
/// passed over; symbolic links to directories are not followed (no cycles).
fn walk(
    dir: &Path,
    own_folders: &[PathBuf],
    found: &mut Vec<PathBuf>,
    skipped: &mut Vec<PathBuf>,
) -> Result<()> {
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
            let own = fs::canonicalize(&path).is_ok_and(|real| own_folders.contains(&real));
            if !own {
                walk(&path, own_folders, found, skipped)?;
            }
        } else if file_type.is_symlink() && path.is_dir() {
            continue;
        } else if extension_is(&path, IMAGE_EXTENSIONS)
            || extension_is(&path, POINT_LIST_EXTENSIONS)
        {
            found.push(path);
        } else if !extension_is(&path, &["svg", "json"]) {
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

/// Decides where each file's output goes (see `--output`), creating the output directory, and
/// whether its subfolder there must be created when it is written.
fn plan_outputs(
    cli: &Cli,
    files: &[InputFile],
    batch: bool,
    format: Format,
) -> Result<Vec<(Destination, bool)>> {
    let inputs: Vec<&Path> = files.iter().map(|file| file.path.as_path()).collect();
    let extension = format.extension();
    let Some(output) = &cli.output else {
        let folders: Vec<PathBuf> = inputs
            .iter()
            .map(|input| input.parent().unwrap_or(Path::new("")).to_path_buf())
            .collect();
        let paths = unique_paths(&inputs, &folders, extension);
        // Standard input has no path of its own to write beside: like a filter, it goes to
        // standard output.
        return Ok(files
            .iter()
            .zip(paths)
            .map(|(file, path)| match file.path.as_os_str() == "-" {
                true if files.len() == 1 => (Destination::Stdout, false),
                _ => (Destination::File(path), false),
            })
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
        return Ok(vec![(Destination::Stdout, false); files.len()]);
    }
    if !(batch || names_directory(output)) {
        // One output file: its folder must exist (only an output directory is created).
        let folder = match output.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if !folder.is_dir() {
            return Err(anyhow::anyhow!(
                "cannot write {}: {}",
                output.display(),
                missing_folder(folder)
            ));
        }
        return Ok(vec![
            (Destination::File(output.clone()), false);
            files.len()
        ]);
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
    let folders: Vec<PathBuf> = files
        .iter()
        .map(|file| output.join(file.layout.parent().unwrap_or(Path::new(""))))
        .collect();
    Ok(unique_paths(&inputs, &folders, extension)
        .into_iter()
        .zip(&folders)
        .map(|(path, folder)| (Destination::File(path), folder != output))
        .collect())
}

/// Why `folder` cannot take a file: an ancestor that is a file, or the folder is missing.
fn missing_folder(folder: &Path) -> String {
    let blocking = folder
        .ancestors()
        .find(|a| !a.as_os_str().is_empty() && a.exists() && !a.is_dir());
    match blocking {
        Some(file) => format!("{} is a file, not a folder", file.display()),
        None => format!("folder {} does not exist", folder.display()),
    }
}

/// The `--debug` folder of one input in a batch: its output path below the output directory (or
/// its file name), without the extension.
fn debug_folder(cli: &Cli, output: &Path) -> PathBuf {
    let below = cli
        .output
        .as_deref()
        .and_then(|dir| output.strip_prefix(dir).ok())
        .unwrap_or_else(|| Path::new(output.file_name().unwrap_or(output.as_os_str())));
    below.with_extension("")
}

/// A file's identity: device and inode where the platform has them (a hard link, a symbolic link
/// or `./x` is the same file), else its canonical path.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord)]
enum FileId {
    #[cfg(unix)]
    Inode(u64, u64),
    #[cfg(not(unix))]
    Path(PathBuf),
}

fn file_id(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let metadata = fs::metadata(path).ok()?;
        Some(FileId::Inode(metadata.dev(), metadata.ino()))
    }
    #[cfg(not(unix))]
    {
        fs::canonicalize(path).ok().map(FileId::Path)
    }
}

/// A run never writes over one of its own inputs: every output file and `--debug` picture that
/// already exists is compared with the inputs (`reserved`) by identity, before anything is
/// traced. (One metadata read per path, so that a batch of thousands stays linear; the
/// `same-file` crate would hold every input open.)
fn refuse_overwriting_inputs(jobs: &[Job], reserved: &Reserved) -> Result<(), UsageError> {
    for job in jobs {
        let pictures = job.debug.iter().flat_map(|dir| {
            ridgeline::debug::PICTURE_NAMES
                .into_iter()
                .chain([ridgeline::debug::DECISIONS_PICTURE])
                .chain(ridgeline::debug::PRINT_PICTURE_NAMES)
                .map(|name| dir.join(name))
        });
        let outputs = match &job.destination {
            Destination::File(path) => Some(path.clone()),
            Destination::Stdout => None,
        };
        for path in outputs.into_iter().chain(pictures) {
            if let Some(message) = reserved.overwrites_input(&path) {
                return Err(UsageError(message));
            }
        }
    }
    Ok(())
}

/// Output paths `<folder>/<stem>.<extension>`, one per input in its folder, all different and
/// none equal to an input. Clashes are resolved deterministically (the result depends only on
/// the lists): inputs that share a name get their parent directory's name appended
/// (`page-scans.svg`), then their own extension (`page-scans-png.svg`), then a counter in input
/// order (`page-2.svg`).
fn unique_paths(inputs: &[&Path], folders: &[PathBuf], extension: &str) -> Vec<PathBuf> {
    let candidate = |i: usize, level: usize| -> PathBuf {
        let input = inputs[i];
        let stem = match input.as_os_str() == "-" {
            true => "stdin".into(),
            false => input
                .file_stem()
                .unwrap_or(input.as_os_str())
                .to_string_lossy(),
        };
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
        folders[i].join(base)
    };
    let mut levels = vec![0usize; inputs.len()];
    for _ in 0..2 {
        let paths: Vec<PathBuf> = (0..inputs.len())
            .map(|i| with_extension_added(candidate(i, levels[i]), extension))
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
    (0..inputs.len())
        .map(|i| {
            let base = candidate(i, levels[i]);
            let mut path = with_extension_added(base.clone(), extension);
            let mut counter = 2;
            while taken.contains(&path) {
                let mut numbered = base.clone().into_os_string();
                numbered.push(format!("-{counter}"));
                path = with_extension_added(numbered.into(), extension);
                counter += 1;
            }
            taken.insert(path.clone());
            path
        })
        .collect()
}

/// `base` with `.extension` appended (`Path::with_extension` would replace a dotted part of the
/// name, as in `page.v2`).
fn with_extension_added(base: PathBuf, extension: &str) -> PathBuf {
    let mut name = base.into_os_string();
    name.push(".");
    name.push(extension);
    name.into()
}

/// Runs one job; a panic inside the library becomes this file's failure instead of ending the
/// batch. Returns what the job gave, or the message of its failure.
fn run_job(job: &Job, settings: &Settings) -> Outcome {
    if INTERRUPTED.load(Ordering::SeqCst) {
        return Outcome::NotStarted;
    }
    match catch_unwind(AssertUnwindSafe(|| trace_and_write(job, settings))) {
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

/// Reads all of standard input, refusing more than [`MAX_STDIN_BYTES`].
fn read_stdin() -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(MAX_STDIN_BYTES + 1)
        .read_to_end(&mut bytes)
        .context("cannot read standard input")?;
    if bytes.len() as u64 > MAX_STDIN_BYTES {
        anyhow::bail!(
            "standard input holds more than {} GiB; save it to a file first",
            MAX_STDIN_BYTES >> 30
        );
    }
    Ok(bytes)
}

/// How bytes from standard input are read: as an image when they start like one (the decoder
/// sniffs the format the same way for files), else as a point list when they are text.
fn sniff(bytes: &[u8]) -> Kind {
    if image::guess_format(bytes).is_err() && std::str::from_utf8(bytes).is_ok() {
        Kind::PointList
    } else {
        Kind::Image
    }
}

fn trace_and_write(job: &Job, settings: &Settings) -> Result<Traced> {
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
        let text = match stdin {
            Some(bytes) => String::from_utf8(bytes).context("standard input is not text"),
            None => fs::read_to_string(&job.input).context("cannot read the file"),
        };
        let list = text.and_then(|text| Ok(ridgeline::point_list::parse(&text)?));
        let list = match (kind, list) {
            (Kind::FoundText, Err(err)) => return Err(NotAPointList(format!("{err:#}")).into()),
            (Kind::FoundText, Ok(list)) if list.is_empty() => {
                return Err(NotAPointList("no points in it".into()).into())
            }
            (_, list) => list?,
        };
        if list.is_empty() {
            anyhow::bail!(
                "the point list has no points (only blank lines, comments or a header line)"
            );
        }
        let trace = ridgeline::trace_points(&list, params)?;
        let mut warnings = Vec::new();
        if job.debug.is_some() {
            warnings.push("--debug draws pictures of images only; none for a point list".into());
        }
        if trace.graph.vertices.is_empty() {
            warnings.push("no strokes found; wrote an empty drawing".to_string());
        }
        let meta = JsonMeta::new(params.clone()).with_trace(&trace);
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
        // While the page is traced, the file's bytes are kept only if they are its picture.
        drop(pages);
        let bytes = match page.picture {
            Picture::Original { .. } => bytes,
            _ => Vec::new(),
        };
        let mut traced = trace_page(job, settings, &bytes, &page, count, file_dpi)?;
        warnings.append(&mut traced.warnings);
        traced.warnings = warnings;
        return Ok(traced);
    }
    let mut failed = Vec::new();
    let mut all = Traced::of(&StrokeGraph::default(), warnings, String::new());
    let mut outputs = Vec::new();
    for (index, page) in pages.enumerate() {
        let number = index + 1;
        let traced = page
            .map_err(anyhow::Error::from)
            .and_then(|page| trace_page(job, settings, &bytes, &page, count, file_dpi));
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

/// Traces one page of an image file (`bytes`, of `count` pages) and writes its output: page 1 to
/// the job's destination, page N to `<stem>.pN.<extension>` beside it.
fn trace_page(
    job: &Job,
    settings: &Settings,
    bytes: &[u8],
    page: &Page,
    count: usize,
    file_dpi: Option<f64>,
) -> Result<Traced> {
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
    let meta = JsonMeta::new(params.clone())
        .with_page(page.number, count)
        .with_trace(&trace);
    warnings.extend(trace.warnings.iter().map(|w| w.message.clone()));
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
        settings.reserved.check(path)?;
    }
    let output = write_output(job, &destination, &text)?;
    Ok(Traced::of(&trace.graph, warnings, output))
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

/// Resolution of ISO/IEC 19794-2 records when neither `--dpi` nor the file gives one.
const DEFAULT_DPI: f64 = 500.0;

/// The output document of one traced graph (of an input read as `kind`): SVG over `backdrop`,
/// or JSON with `meta`; ISO records at `--dpi`, else `file_dpi`, else [`DEFAULT_DPI`], with the
/// 255 minutiae of highest quality when there are more (said in `warnings`).
#[allow(clippy::too_many_arguments)]
fn render(
    job: &Job,
    settings: &Settings,
    kind: Kind,
    trace: &ridgeline::Trace,
    backdrop: Option<Backdrop>,
    meta: JsonMeta,
    file_dpi: Option<f64>,
    warnings: &mut Vec<String>,
) -> Result<Vec<u8>> {
    let graph = &trace.graph;
    let binary = trace.binary.as_ref();
    // Strokes are cheap (one pass over the edge ends), so the JSON always lists them; the SVG
    // draws them on request.
    let chained = (settings.format == Format::Json || settings.strokes)
        .then(|| strokes(graph, &StrokeOptions::default()));
    // The foreground mask tells where the print ends; point lists have only the extent.
    // The fingerprint front end's minutiae are filtered inside its print; others come from the
    // graph and the mask.
    let wanted = settings.minutiae || matches!(settings.format, Format::Xyt | Format::Iso);
    let marks = wanted.then(|| match &trace.fingerprint {
        Some(print) => print.minutiae.clone(),
        None => minutiae(graph, binary, &MinutiaeOptions::default()),
    });
    Ok(match settings.format {
        Format::Xyt => {
            ridgeline::export::xyt::to_string(marks.as_deref().unwrap_or(&[]), graph.height)
                .into_bytes()
        }
        Format::Iso => {
            use ridgeline::export::iso19794::{best_for_record, to_bytes, MAX_MINUTIAE};
            let all = marks.as_deref().unwrap_or(&[]);
            // A record holds 255 minutiae; a matcher given more keeps those it trusts most,
            // so the record does too, and says so.
            let kept = best_for_record(all);
            if kept.len() < all.len() {
                warnings.push(format!(
                    "{} minutiae, more than the {MAX_MINUTIAE} an ISO/IEC 19794-2 record \
                     holds: wrote the {MAX_MINUTIAE} of highest quality (the JSON and .xyt \
                     outputs keep all {})",
                    all.len(),
                    all.len()
                ));
            }
            to_bytes(
                &kept,
                graph.width,
                graph.height,
                settings.dpi.or(file_dpi).unwrap_or(DEFAULT_DPI),
            )?
        }
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
            // A point list has no image to cover: the canvas fits the points.
            let svg_options = settings
                .svg
                .clone()
                .with_fit_canvas(kind == Kind::PointList);
            svg::to_string_with(graph, backdrop, &svg_options, &features).into_bytes()
        }
        Format::Json => {
            let meta = meta
                .with_source_path(job.input.to_string_lossy())
                .with_pretty(settings.pretty);
            // In the JSON, curves are per edge.
            let curves = settings.curves.map(|options| fit_edges(graph, &options));
            let features = Features::default()
                .with_strokes(chained.as_deref())
                .with_minutiae(marks.as_deref())
                .with_curves(curves.as_deref());
            json::to_string_with(graph, &meta, &features).into_bytes()
        }
    })
}

/// Writes one output document of `job` to stdout or (atomically) to its file; returns where it
/// went, as the user should read it.
fn write_output(job: &Job, destination: &Destination, text: &[u8]) -> Result<String> {
    Ok(match destination {
        Destination::Stdout => {
            let mut stdout = std::io::stdout().lock();
            stdout.write_all(text).context("cannot write to stdout")?;
            stdout.flush().context("cannot write to stdout")?;
            "stdout".to_string()
        }
        Destination::File(path) => {
            if job.create_folder {
                if let Some(folder) = path.parent() {
                    fs::create_dir_all(folder).with_context(|| {
                        format!("cannot create the output folder {}", folder.display())
                    })?;
                }
            }
            write_atomically(path, text)?;
            path.display().to_string()
        }
    })
}

/// Traces `gray` once, keeping the intermediate stages of the output's own trace, and writes
/// their pictures into `dir` (created if missing), each atomically, one at a time; the final
/// picture is the output's graph.
fn trace_with_pictures(
    gray: &ridgeline::GrayImage,
    params: &Params,
    dir: &Path,
) -> Result<ridgeline::Trace> {
    let mut trace = ridgeline::trace_image_with_stages(gray, params)?;
    if let (Some(stages), Some(binary)) = (&trace.stages, &trace.binary) {
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the --debug folder {}", dir.display()))?;
        if let Some(decisions) = &trace.decisions {
            let png = ridgeline::debug::decisions_png(gray, binary, decisions)?;
            write_atomically(&dir.join(ridgeline::debug::DECISIONS_PICTURE), &png)
                .context("cannot write the --debug pictures")?;
        }
        if let Some(print) = &trace.fingerprint {
            for (name, png) in ridgeline::debug::print_pngs(gray, &print.analysis)? {
                write_atomically(&dir.join(name), &png)
                    .context("cannot write the --debug pictures")?;
            }
        }
        for picture in ridgeline::debug::stage_pngs(binary, stages, &trace.graph) {
            let (name, png) = picture?;
            write_atomically(&dir.join(name), &png).context("cannot write the --debug pictures")?;
        }
    }
    trace.stages = None;
    Ok(trace)
}

/// The operating system's reason inside an I/O error, without the paths that wrappers (such as
/// the temporary file's) add.
fn os_reason(err: &std::io::Error) -> String {
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(err);
    while let Some(current) = source {
        if let Some(code) = current
            .downcast_ref::<std::io::Error>()
            .and_then(std::io::Error::raw_os_error)
        {
            return std::io::Error::from_raw_os_error(code).to_string();
        }
        source = current.source();
    }
    err.kind().to_string()
}

/// Writes `bytes` to `path` atomically ([`replace_file`]). Errors name `path` and the reason,
/// never the temporary file.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        anyhow::bail!("cannot write {}: {}", path.display(), missing_folder(dir));
    }
    replace_file(path, bytes)
        .map_err(|err| anyhow::anyhow!("cannot write {}: {}", path.display(), os_reason(&err)))
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over `path`: readers see the
/// old file or the new one, never a truncated one, and a failure leaves the old file as it was (and
/// no temporary file behind). The file is an ordinary one, readable as usual (mode 0644 less the
/// umask). The error is the operating system's, for the caller to name `path`.
fn replace_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    use std::sync::atomic::{AtomicU64, Ordering};
    // Unique among this process's writes; `create_new` refuses a name another process holds.
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let (temp, mut file) = loop {
        let name = format!(
            ".ridgeline-{}-{}.tmp",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let temp = dir.join(name);
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o644);
        }
        match options.open(&temp) {
            Ok(file) => break (temp, file),
            Err(err) if err.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(err) => return Err(err),
        }
    };
    let written = file.write_all(bytes).and_then(|()| {
        drop(file);
        std::fs::rename(&temp, path)
    });
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    written
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
        assert_eq!(params.method.r_min_rule, RMinRule::Spacing);
        assert_eq!(params.method.cluster_rule, ClusterRule::EqualDistance);
        assert_eq!(params.fit.laplacian, LaplacianRule::Uniform);
        assert_eq!(params.method.r_min_factor, 7.0);
        assert_eq!(params.method.merge_span, 3.0);
        assert_eq!(params.method.k, 8);
        assert_eq!(
            params.front_end.threshold,
            Threshold::Sauvola {
                window: 15,
                k: Threshold::DEFAULT_SAUVOLA_K
            }
        );
        assert_eq!(params.front_end.polarity, Polarity::LightInk);
        assert_eq!(params.front_end.dropout, Some(true));
        assert_eq!(params.front_end.limits.max_pixels, 1000);
        assert!(!params.method.arms_test);
        // Untouched fields keep the paper's values.
        assert_eq!(
            params.method.r_max_factor,
            Params::paper().method.r_max_factor
        );
        assert_eq!(params.fit.anchor_weight, Params::paper().fit.anchor_weight);
    }

    #[test]
    fn every_rule_of_the_paper_preset_can_be_given_back() {
        let params = Params::try_from(&parse(&[
            "--paper",
            "--r-min-rule",
            "width",
            "--r-min-factor",
            "1",
            "--r-max-factor",
            "3",
            "--arms-test",
            "--clusters",
            "non-linear",
            "--merge-span",
            "2",
            "--cleanup",
            "--laplacian",
            "held",
            "--anchor-weight",
            "10",
            "--skeleton",
            "--subpixel",
            "--valleys",
            "--reverse-grounds",
            "a.png",
        ]))
        .expect("valid");
        assert_eq!(params, Params::default());
        let grid = Params::try_from(&parse(&["--no-subpixel", "a.png"])).expect("valid");
        assert!(!grid.front_end.subpixel);
        let filled = Params::try_from(&parse(&["--no-valleys", "a.png"])).expect("valid");
        assert!(!filled.front_end.valleys);
        let banner = Params::try_from(&parse(&["--no-reverse-grounds", "a.png"])).expect("valid");
        assert!(!banner.front_end.reverse_grounds);
        let node_graph = Params::try_from(&parse(&["--no-skeleton", "a.png"])).expect("valid");
        assert!(!node_graph.finish.skeleton);
        let back = Params::try_from(&parse(&["--no-skeleton", "--skeleton", "a.png"])).expect("ok");
        assert!(back.finish.skeleton);
        // The last of a flag and its negation wins.
        let off = Params::try_from(&parse(&["--cleanup", "--no-cleanup", "a.png"])).expect("valid");
        assert!(!off.finish.cleanup);
        let on =
            Params::try_from(&parse(&["--no-arms-test", "--arms-test", "a.png"])).expect("valid");
        assert!(on.method.arms_test);
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
            format!(
                "default: {}, paper: {}",
                d.method.r_min_factor, p.method.r_min_factor
            ),
            format!(
                "default: {}, paper: {}",
                d.method.r_max_factor, p.method.r_max_factor
            ),
            format!("default: {}]", d.method.r_growth),
            format!("default: {}]", d.method.linearity),
            format!("default: {}]", d.method.k),
            format!("default: {}]", d.method.cluster_link),
            format!("default: {}, paper: inf", d.method.merge_span),
            format!("default: {}]", d.fit.smoothness),
            format!(
                "default: {}, paper: {}",
                d.fit.anchor_weight, p.fit.anchor_weight
            ),
            format!("default: {}]", d.fit.weiszfeld_iterations),
            format!("default: {}]", d.fit.spacing_factor),
            format!("default: {}]", d.front_end.dropout_fraction),
            format!("default: {}]", d.front_end.min_area),
            format!("default: {}]", d.front_end.limits.max_pixels),
            format!("default: {}]", d.front_end.limits.max_side),
            format!("default: {}]", d.front_end.limits.max_points),
            format!("default: {}]", d.front_end.limits.max_pages),
            format!("default: {}]", Threshold::DEFAULT_SAUVOLA_WINDOW),
            format!("default: {}]", Threshold::DEFAULT_SAUVOLA_K),
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
        let out = vec![PathBuf::from("out"); inputs.len()];
        let paths = unique_paths(&inputs, &out, "svg");
        let names: Vec<String> = paths
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["page-a.svg", "page-b-png.svg", "page-b-jpg.svg", "x.svg"]
        );
        let parents: Vec<PathBuf> = inputs
            .iter()
            .map(|p| p.parent().unwrap().to_path_buf())
            .collect();
        let next_to_input = unique_paths(&inputs, &parents, "svg");
        assert_eq!(next_to_input[0], Path::new("a/page.svg"));
        assert_eq!(next_to_input[1], Path::new("b/page-b-png.svg"));
        assert_eq!(next_to_input[3], Path::new("c/x.svg"));
        // An output never replaces an input.
        let own = unique_paths(&[Path::new("d/x.svg")], &[PathBuf::from("d")], "svg");
        assert_eq!(own[0], Path::new("d/x-2.svg"));
    }
}
