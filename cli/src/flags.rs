//! The first step of the command line: the flags as clap parses them ([`Cli`]), with their help.
//! Nothing here is checked beyond what clap checks; [`crate::settings`] turns the flags into the
//! one [`crate::settings::Settings`] that every later step reads.
//!
//! Flags whose values are the library's own types (`--binarize`, `--polarity`, `--r-min-rule`,
//! ...) parse straight into them through one table per flag ([`one_of`]): the library knows
//! nothing of clap, and no enum here mirrors one of its enums.

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{CommandFactory, Parser, ValueEnum};

use ridgeline::{ClusterRule, Enhancement, LaplacianRule, Polarity, RMinRule, Threshold};

/// The examples under `-h` and `--help` (tests run each one).
pub const EXAMPLES: &str = "\
Examples:
  A scanned page: writes page.svg next to page.png, centerlines over the scan
    ridgeline page.png
  A fingerprint: ridges and minutiae (with a quality each) as JSON, and the minutiae for Bozorth3
    ridgeline --fingerprint print.png -o print.json
    ridgeline --fingerprint print.png -o print.xyt
  A point list (\"x y\" or \"x,y\" per line) with the paper's own parameter values
    ridgeline --paper points.xy -o points.svg
  A batch: every image and point list under scans/, 2 files at a time, into out/ as JSON
    ridgeline scans/ -o out/ --format json --jobs 2
  A result looks wrong: pictures of every stage into stages/
    ridgeline --debug stages/ page.png

Every flag: --help. The method's parameters in the paper's notation: --help-method.";

/// What `--help` adds after the examples.
const AFTER_LONG_HELP: &str = "\
Outputs are written atomically: a failed run never leaves an output half-written or emptied,
and never writes over an input. Each run ends with one line on stderr (--quiet: none).
Exit status: 0 on success (a blank page is a warning), 1 if any input failed, 2 on usage errors.";

/// What `--help-method` says before the method's flags.
const METHOD: &str = "\
The method's parameters. ridgeline follows \"Efficient reconstruction of non-simple curves\"
(docs/design.md): the ink's pixel centres (or a point list's points) are covered by disks
(§3.1), each grown from r_min by the factor r_growth, at most to r_max, while its points stay
linear: the linearity l of Eq. (3), from the principal axes of the points in the disk, above a
threshold. Dis_ave is the mean distance from a point to its nearest neighbour (1 px on an
image). Disks whose points touch are joined into the node graph H (§3.2), whose non-linear nodes
form clusters; refinement (§3.3) contracts each cluster into junctions, giving a 1-D graph; the
fit (§3.4) moves its nodes onto the strokes' centres by least squares (Eq. (4): data terms, a
Laplacian smoothness term of weight w, L1 medians by Weiszfeld's iterations). By default a pixel
skeleton then carries the centerlines and the method's graph decides crossings, spurs and bends
(--no-skeleton keeps the fitted polylines). Defaults are ridgeline's; --paper gives the paper's
values; any flag given overrides both.";

/// The method's own parameters (§3.1-3.4, in the paper's notation): shown by `--help-method`
/// only.
const METHOD_FLAGS: &[&str] = &[
    "r_min_rule",
    "r_min_factor",
    "r_max_factor",
    "r_growth",
    "linearity",
    "no_arms_test",
    "arms_test",
    "k",
    "clusters",
    "cluster_link",
    "merge_span",
    "no_cleanup",
    "cleanup",
    "laplacian",
    "smoothness",
    "anchor_weight",
    "weiszfeld_iterations",
    "spacing_factor",
];

/// What `-h` shows; every other flag only `--help` (the method's, `--help-method`).
const SHORT_HELP_FLAGS: &[&str] = &[
    "inputs",
    "output",
    "format",
    "fingerprint",
    "paper",
    "points",
    "polarity",
    "binarize",
    "min_area",
    "strokes",
    "minutiae",
    "curves",
    "debug",
    "jobs",
    "quiet",
    "help_method",
];

/// The command line as the tool parses it: [`Cli`] with the method's flags kept for
/// `--help-method` and `-h` kept short.
pub fn command() -> clap::Command {
    Cli::command().mut_args(|arg| {
        let id = arg.get_id().as_str();
        if METHOD_FLAGS.contains(&id) {
            arg.hide(true)
        } else {
            let short = SHORT_HELP_FLAGS.contains(&id);
            arg.hide_short_help(!short)
        }
    })
}

/// `--help-method`: the method's flags, in the paper's notation, with their defaults and the
/// paper's values.
pub fn method_help() -> String {
    Cli::command()
        .about(METHOD)
        .after_help("Every other flag: --help.")
        .mut_args(|arg| {
            let method = METHOD_FLAGS.contains(&arg.get_id().as_str());
            arg.hide(!method)
        })
        .render_long_help()
        .to_string()
}

/// Turns images of strokes (scans, handwriting, fingerprints) and point lists into stroke graphs:
/// centerlines meeting at junctions, as SVG over the image, JSON, or fingerprint minutiae.
#[derive(Debug, Parser)]
#[command(
    name = "ridgeline",
    version,
    after_help = EXAMPLES,
    after_long_help = format!("{EXAMPLES}\n\n{AFTER_LONG_HELP}"),
    max_term_width = 100
)]
pub struct Cli {
    /// Images, point lists, or directories; '-' reads standard input
    ///
    /// Directories are walked recursively, files sorted by name; standard input is an image when
    /// its bytes start like one, else a point list; every page of a multi-page TIFF is traced
    /// (see --max-pages)
    #[arg(required_unless_present = "help_method", value_name = "INPUT")]
    pub(crate) inputs: Vec<PathBuf>,

    /// Output file (.svg .json .xyt .ist), directory, or '-' for stdout [default: beside the input]
    ///
    /// By default each input's path with its extension replaced by the format's (.svg, .json,
    /// .xyt or .ist); stdout for standard input.
    ///
    /// PATH is a directory when there are several inputs or a directory input, when it ends in
    /// '/', or when it is an existing directory; it is created if missing (the folder of an
    /// output file must exist). Outputs keep the inputs' layout in it: a file found at a/x.png
    /// in a walked directory is written to PATH/a/x.svg, and named files keep their paths below
    /// the deepest folder holding them all (a/x.png b/x.png: PATH/a/x.svg PATH/b/x.svg); names
    /// that still clash get the parent directory's name added. An output is never written over
    /// an input.
    #[arg(short, long, value_name = "PATH", help_heading = "Output")]
    pub(crate) output: Option<PathBuf>,

    /// Output format [default: from the -o extension, else svg]
    #[arg(short, long, value_enum, help_heading = "Output")]
    pub(crate) format: Option<Format>,

    /// SVG: do not embed the source image under the centerlines [default: embedded as given]
    ///
    /// PNG, JPEG, GIF and WebP files are embedded as they are (their own bytes); TIFF, BMP and
    /// PNM as a PNG of their pixels, in colour and with transparency when they have them, each
    /// page of a multi-page TIFF under its own output. (JPEG, PNG and WebP files with an
    /// orientation tag are embedded as their pixels too, unrotated, as they are traced.)
    #[arg(long, help_heading = "Output")]
    pub(crate) no_image: bool,

    /// SVG: do not mark endpoints (green) and junctions (blue)
    #[arg(long, help_heading = "Output")]
    pub(crate) no_vertices: bool,

    /// SVG: centerline width, px [default: max(0.6, 0.12 x median stroke width)]
    #[arg(long, value_name = "PX", help_heading = "Output")]
    pub(crate) line_width: Option<f64>,

    /// JSON: indent the document instead of writing one line
    #[arg(long, help_heading = "Output")]
    pub(crate) pretty: bool,

    /// JSON: add the seconds each stage took, as `timings`
    ///
    /// Seconds per stage (decode, binarize, points, sampling, graph, refine, fit, skeleton; a
    /// large page is traced in parts at once, and each stage's time is summed over its parts) and
    /// `wall`, the wall-clock time of decoding and tracing the file. Times differ from run to
    /// run: with --timings the same input no longer gives the same bytes. A point list in space
    /// records the wall time only.
    #[arg(long, help_heading = "Output")]
    pub(crate) timings: bool,

    /// Also draw every stage of each image as a PNG into DIR
    ///
    /// DIR is created if missing. The pictures: 1-foreground (the binarized ink), 2-sampling (the
    /// disks: linear blue, non-linear orange), 3-node-graph (graph H, a color per non-linear
    /// cluster), 4-refined (the 1-D graph), 5-fitted (a color per edge), 6-final (centerlines
    /// red, endpoints green, junctions blue). With several inputs each gets DIR/<output name>/.
    /// Point lists get no pictures. The output is the same as without --debug; stages 2-5 are
    /// of the whole image as one point set (where dropout mode is decided per group of
    /// components, the output's groups are traced apart), 6-final is the output.
    #[arg(long, value_name = "DIR", help_heading = "Output")]
    pub(crate) debug: Option<PathBuf>,
    /// SVG: draw pen strokes (edges chained through crossings), each in its own color
    ///
    /// Edges chained straight through crossings, the way a pen drew them, instead of edges; the
    /// JSON always lists the strokes
    #[arg(long, help_heading = "Features")]
    pub(crate) strokes: bool,

    /// SVG: draw each edge as wide as its mean stroke width, semi-transparent under its
    /// centerline, so the drawing covers the ink where the widths are right
    #[arg(long, help_heading = "Features")]
    pub(crate) width: bool,

    /// Fingerprint minutiae (ridge endings, bifurcations) in the JSON and SVG; see --fingerprint
    ///
    /// Ridge endings and bifurcations with their direction, except near the print's border,
    /// listed in the JSON and marked in the SVG
    #[arg(long, help_heading = "Features")]
    pub(crate) minutiae: bool,

    /// SVG: smooth cubic Bézier paths instead of polylines
    #[arg(long, help_heading = "Features")]
    pub(crate) curves: bool,

    /// Largest distance from a centerline point to its Bézier curve, px (> 0) [default: 0.5]
    #[arg(
        long,
        value_name = "PX",
        requires = "curves",
        help_heading = "Features"
    )]
    pub(crate) curve_tolerance: Option<f64>,

    /// Where the centerline turns by more than this, the curve keeps a corner, degrees (0-180)
    /// [default: 60]
    #[arg(
        long,
        value_name = "DEG",
        requires = "curves",
        help_heading = "Features"
    )]
    pub(crate) corner_angle: Option<f64>,

    /// Read every named file as a point list (.txt .csv .xy .pts always are)
    ///
    /// Whatever its extension; files ending in .txt, .csv, .xy or .pts always are
    #[arg(long, help_heading = "Input and binarization")]
    pub(crate) points: bool,

    /// How gray becomes ink and paper [default: auto]
    ///
    /// auto uses Otsu's global level where it separates ink from paper all over the image and the local threshold (halfway between each neighbourhood's ink
    /// and paper, blocks of about six stroke widths) where the light or contrast varies; otsu and
    /// local force one. The JSON's "decisions" say what was used
    #[arg(
        long,
        value_parser = one_of(BINARIZE),
        value_name = "METHOD",
        conflicts_with_all = ["sauvola", "threshold"],
        help_heading = "Input and binarization"
    )]
    pub(crate) binarize: Option<Threshold>,

    /// Fixed threshold: gray levels 0-255 at or below LEVEL are dark [default: --binarize auto]
    #[arg(
        long,
        value_name = "LEVEL",
        conflicts_with = "sauvola",
        help_heading = "Input and binarization"
    )]
    pub(crate) threshold: Option<u8>,

    /// Sauvola's adaptive threshold with a fixed window [default: --binarize auto]
    #[arg(long, help_heading = "Input and binarization")]
    pub(crate) sauvola: bool,

    /// Sauvola window side, px (odd, >= 3) [default: 31]
    #[arg(
        long,
        value_name = "PX",
        requires = "sauvola",
        help_heading = "Input and binarization"
    )]
    pub(crate) window: Option<u32>,

    /// Sauvola sensitivity k, in [0, 1] [default: 0.2]
    #[arg(
        long,
        value_name = "K",
        requires = "sauvola",
        help_heading = "Input and binarization"
    )]
    pub(crate) sauvola_k: Option<f64>,

    /// Which side of the threshold is ink [default: auto]
    ///
    /// auto decides from stroke evidence (ink is the thinner
    /// side, paper fills the border; dark when the evidence is weak, with a warning), and then
    /// per region (a thick field holding light strokes, white letters on a dark banner, is read
    /// as a ground: see --no-reverse-grounds); dark ink on light paper, or light strokes
    /// (fingerprint ridges) on a dark background, everywhere
    #[arg(
        long,
        value_parser = one_of(POLARITY),
        value_name = "INK",
        help_heading = "Input and binarization"
    )]
    pub(crate) polarity: Option<Polarity>,

    /// Dropout mode for broken, speckled strokes (closing before the distance transform, wider
    /// neighbourhoods); auto decides from tiny background holes [default: auto]
    #[arg(
        long,
        value_parser = one_of(DROPOUT),
        value_name = "MODE",
        help_heading = "Input and binarization"
    )]
    pub(crate) dropout: Option<DropoutMode>,

    /// Share of ink pixels that tiny background holes must exceed for auto dropout mode, in
    /// (0, 1) [default: 0.015]
    #[arg(long, value_name = "SHARE", help_heading = "Input and binarization")]
    pub(crate) dropout_fraction: Option<f64>,

    /// Drop ink components of fewer than N pixels (specks; the speckle warning suggests N)
    ///
    /// Before tracing, as specks of a noisy scan [default: 0]
    #[arg(long, value_name = "N", help_heading = "Input and binarization")]
    pub(crate) min_area: Option<usize>,

    /// Keep a gray image's centerline where the pixel grid puts it, without placing it below the
    /// pixel from the gray levels (each point moved along its normal, at most 0.75 px, to the
    /// middle of the stroke's cross-section) [default: refined, paper: not]
    #[arg(long, help_heading = "Input and binarization")]
    pub(crate) no_subpixel: bool,

    /// Place a gray image's centerline below the pixel from its gray levels; turns it back on
    /// after --paper [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_subpixel",
        help_heading = "Input and binarization"
    )]
    pub(crate) subpixel: bool,

    /// Keep as ink the thresholded pixels that a gray image shows lighter than the ink on both
    /// sides of them (crotches and gaps the blur filled), instead of giving them back to the
    /// paper [default: given back, paper: kept]
    #[arg(long, help_heading = "Input and binarization")]
    pub(crate) no_valleys: bool,

    /// Give a gray image's blur-filled crotches and gaps back to the paper; turns it back on
    /// after --paper [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_valleys",
        help_heading = "Input and binarization"
    )]
    pub(crate) valleys: bool,

    /// With --polarity auto, keep as ink a thick field holding light strokes (white letters on a
    /// dark banner) instead of reading it as a ground whose strokes are the ink [default: read
    /// as a ground, paper: kept as ink]
    #[arg(long, help_heading = "Input and binarization")]
    pub(crate) no_reverse_grounds: bool,

    /// Read thick fields holding light strokes as grounds; turns it back on after --paper
    /// [default: on, paper: off]
    #[arg(
        long,
        overrides_with = "no_reverse_grounds",
        help_heading = "Input and binarization"
    )]
    pub(crate) reverse_grounds: bool,

    /// Trace these regions that are not strokes anyway: halftone, frame, page_edge, faint, or all
    /// [default: none; the regions found are left out and listed in the JSON's decisions]
    #[arg(
        long,
        value_name = "KIND,...",
        value_delimiter = ',',
        help_heading = "Input and binarization"
    )]
    pub(crate) keep_regions: Vec<String>,

    /// Start from the paper's own rules and values (see --help-method)
    ///
    /// r_min = 10 Dis_ave, r_max = 6 r_min, no arms
    /// test, equal-distance clusters, whole-cluster merging, uniform Laplacian and fit weights, no
    /// clean-up); every other flag given still overrides them
    #[arg(long, help_heading = "Method")]
    pub(crate) paper: bool,

    /// Fingerprint: enhance the print first, then minutiae with a quality inside it
    ///
    /// Segmentation, orientation field, ridge period and Gabor enhancement before tracing, and the minutiae inside the print, filtered and with a quality (implies
    /// --minutiae); every other flag given still overrides it (ridges dark or light as the image
    /// shows unless --polarity is given)
    #[arg(long, help_heading = "Method")]
    pub(crate) fingerprint: bool,

    /// The fingerprint front end's enhancement: a Gabor filter tuned to each block's ridge
    /// orientation and period, or oriented smoothing (an average along the ridge against its mean
    /// across one period: faster, docs/fingerprints.md compares them); implies --fingerprint
    /// [default: gabor]
    #[arg(
        long,
        value_name = "METHOD",
        value_parser = one_of(ENHANCEMENTS),
        help_heading = "Method"
    )]
    pub(crate) enhance: Option<Enhancement>,

    /// Resolution written into ISO/IEC 19794-2 records, dots per inch [default: the one the
    /// image file states (PNG pHYs, JPEG JFIF density, TIFF XResolution), else 500]
    #[arg(long, value_name = "DPI", help_heading = "Output")]
    pub(crate) dpi: Option<f64>,

    /// Centerlines from the node graph's own fitted polylines (§3.4) instead of the pixel
    /// skeleton the method decides on: faster, but chords cut across cells, counters and loops
    /// finer than a stroke width [default: skeleton on, paper: off]
    #[arg(long, help_heading = "Method")]
    pub(crate) no_skeleton: bool,

    /// Centerlines carried by a pixel skeleton of the ink (every hole a cycle, no edge off the
    /// ink), crossings, spurs and bends decided by the method's graph; turns it back on after
    /// --paper (images only; not in dropout mode) [default: on, paper: off]
    #[arg(long, overrides_with = "no_skeleton", help_heading = "Method")]
    pub(crate) skeleton: bool,

    /// How r_min is chosen: from the local stroke width or from the point spacing Dis_ave
    /// [default: width, paper: spacing]
    #[arg(
        long,
        value_parser = one_of(R_MIN_RULES),
        value_name = "RULE",
        help_heading = "Sampling (paper §3.1)"
    )]
    pub(crate) r_min_rule: Option<RMinRule>,

    /// r_min factor: r_min = max(3 Dis_ave, factor x local stroke width), px; with
    /// --r-min-rule spacing r_min = factor x Dis_ave [default: 1, paper: 10]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    pub(crate) r_min_factor: Option<f64>,

    /// r_max / r_min, >= 1 [default: 3, paper: 6]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    pub(crate) r_max_factor: Option<f64>,

    /// Disk radius growth per step, > 1 [default: 1.25]
    #[arg(long, value_name = "FACTOR", help_heading = "Sampling (paper §3.1)")]
    pub(crate) r_growth: Option<f64>,

    /// Linearity threshold of Eq. (3): a disk is linear when l > this, in (0.5, 1) [default: 0.9]
    #[arg(long, value_name = "L", help_heading = "Sampling (paper §3.1)")]
    pub(crate) linearity: Option<f64>,

    /// Detect non-linear nodes by PCA alone, without the rim "arms" test [default: arms test on,
    /// paper: off]
    #[arg(long, help_heading = "Sampling (paper §3.1)")]
    pub(crate) no_arms_test: bool,

    /// Use the rim "arms" test besides PCA, also with --paper (the last of --arms-test and
    /// --no-arms-test wins)
    #[arg(
        long,
        overrides_with = "no_arms_test",
        help_heading = "Sampling (paper §3.1)"
    )]
    pub(crate) arms_test: bool,

    /// k nearest neighbours for point lists, 2-64 [default: 5]
    #[arg(
        long = "k",
        value_name = "K",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    pub(crate) k: Option<usize>,

    /// Which nodes form the clusters (non-linear regions) that refinement merges
    /// [default: non-linear, paper: equal-distance]
    #[arg(
        long,
        value_parser = one_of(CLUSTER_RULES),
        value_name = "RULE",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    pub(crate) clusters: Option<ClusterRule>,

    /// Cluster link length, in units of r_min: shorter edges join non-linear nodes into one
    /// cluster [default: 1.5]
    #[arg(
        long,
        value_name = "R_MIN",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    pub(crate) cluster_link: Option<f64>,

    /// Junction nodes of a cluster merge only when all are within this many r_min of each other
    /// ('inf' merges whole clusters) [default: 2, paper: inf]
    #[arg(
        long,
        value_name = "R_MIN",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    pub(crate) merge_span: Option<f64>,

    /// Skip the clean-up after §3.3 (hole-free cycles, spurs, short bars) and the placement of
    /// ends and junctions [default: clean-up on, paper: off]
    #[arg(long, help_heading = "Graph and refinement (paper §3.2, §3.3)")]
    pub(crate) no_cleanup: bool,

    /// Run the clean-up after §3.3 and the placement of ends and junctions, also with --paper
    /// (the last of --cleanup and --no-cleanup wins)
    #[arg(
        long,
        overrides_with = "no_cleanup",
        help_heading = "Graph and refinement (paper §3.2, §3.3)"
    )]
    pub(crate) cleanup: bool,

    /// Smoothness term of Eq. (4): held (degree-2 nodes only) or the uniform Laplacian over every
    /// node [default: held, paper: uniform]
    #[arg(
        long,
        value_parser = one_of(LAPLACIAN_RULES),
        value_name = "RULE",
        help_heading = "Fitting (paper §3.4)"
    )]
    pub(crate) laplacian: Option<LaplacianRule>,

    /// Laplacian weight w of Eq. (4), >= 0: higher is smoother, lower follows the ink more
    /// closely [default: 1]
    #[arg(long, value_name = "W", help_heading = "Fitting (paper §3.4)")]
    pub(crate) smoothness: Option<f64>,

    /// Data weight on junctions and endpoints in the fit, > 0 [default: 10, paper: 1]
    #[arg(long, value_name = "WEIGHT", help_heading = "Fitting (paper §3.4)")]
    pub(crate) anchor_weight: Option<f64>,

    /// Weiszfeld iterations for the L1 medians, 0-1000 [default: 20]
    #[arg(long, value_name = "N", help_heading = "Fitting (paper §3.4)")]
    pub(crate) weiszfeld_iterations: Option<usize>,

    /// Node spacing, in units of the median stroke width (at least 3 px) [default: 1]
    #[arg(long, value_name = "WIDTHS", help_heading = "Fitting (paper §3.4)")]
    pub(crate) spacing_factor: Option<f64>,

    /// Largest image decoded, in pixels (width x height) [default: 100000000]
    #[arg(long, value_name = "PIXELS", help_heading = "Limits")]
    pub(crate) max_pixels: Option<u64>,

    /// Largest image side, px [default: 65535]
    #[arg(long, value_name = "PX", help_heading = "Limits")]
    pub(crate) max_side: Option<u32>,

    /// Largest number of ink pixels or list points traced [default: 50000000]
    #[arg(long, value_name = "POINTS", help_heading = "Limits")]
    pub(crate) max_points: Option<u64>,

    /// Largest number of pages of a multi-page TIFF [default: 1000]
    ///
    /// Every page is traced, one at a time: page 1 to the input's output (<name>.svg), page N to
    /// <name>.pN.svg beside it (likewise .json, whose "source" then records "page" and "pages").
    /// A file with more pages is refused before any is decoded. '-o -' takes single-page inputs
    /// only.
    #[arg(long, value_name = "PAGES", help_heading = "Limits")]
    pub(crate) max_pages: Option<u64>,

    /// Files traced at once [default: number of CPU cores]
    #[arg(short, long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..), help_heading = "Running")]
    pub(crate) jobs: Option<u16>,

    /// Print errors only: no summary line, no progress bar, no warnings
    #[arg(short, long, help_heading = "Running")]
    pub(crate) quiet: bool,

    /// Print the method's parameters, in the paper's notation (§3.1-3.4), and exit
    #[arg(long, help_heading = "Running")]
    pub(crate) help_method: bool,
}

/// Output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Centerlines drawn over the source image.
    Svg,
    /// Vertices, edges and statistics for other programs.
    Json,
    /// Minutiae as NIST `x y theta quality` lines (Bozorth3's input).
    Xyt,
    /// Minutiae as an ISO/IEC 19794-2:2005 finger minutiae record (binary).
    Iso,
    /// Centerlines as PLY vertices and edges, for 3D viewers (z = 0 for images and 2D points).
    Ply,
    /// Centerlines as Wavefront OBJ polylines (v and l lines), for 3D viewers.
    Obj,
}

impl Format {
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Json => "json",
            Format::Xyt => "xyt",
            Format::Iso => "ist",
            Format::Ply => "ply",
            Format::Obj => "obj",
        }
    }
}

/// `--dropout`: always on, always off, or decided from the image (`None`), as
/// [`ridgeline::Params::dropout`] holds it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DropoutMode(pub Option<bool>);

/// One flag's values: the name a user types, what it means (shown by `--help`) and the
/// library's value it stands for.
type Values<T> = &'static [(&'static str, &'static str, T)];

/// `--binarize` values.
const BINARIZE: Values<Threshold> = &[
    (
        "auto",
        "Otsu where the light is even, the local threshold where it is not",
        Threshold::Auto,
    ),
    ("otsu", "Otsu's global level everywhere", Threshold::Otsu),
    ("local", "The local threshold everywhere", Threshold::Local),
];

/// `--polarity` values.
const POLARITY: Values<Polarity> = &[
    ("auto", "Decided from stroke evidence", Polarity::Auto),
    ("dark", "Dark ink on light paper", Polarity::DarkInk),
    (
        "light",
        "Light strokes on a dark background",
        Polarity::LightInk,
    ),
];

/// `--dropout` values.
const DROPOUT: Values<DropoutMode> = &[
    ("on", "Always on", DropoutMode(Some(true))),
    ("off", "Always off", DropoutMode(Some(false))),
    ("auto", "Decided from the image", DropoutMode(None)),
];

/// `--enhance` values.
const ENHANCEMENTS: Values<Enhancement> = &[
    ("gabor", "Gabor filter per block", Enhancement::Gabor),
    (
        "smoothing",
        "Oriented smoothing along and across the ridges",
        Enhancement::Smoothing,
    ),
];

/// `--r-min-rule` values.
const R_MIN_RULES: Values<RMinRule> = &[
    (
        "width",
        "r_min = max(3 Dis_ave, factor x local stroke width)",
        RMinRule::StrokeWidth,
    ),
    (
        "spacing",
        "r_min = factor x Dis_ave, as in the paper",
        RMinRule::Spacing,
    ),
];

/// `--clusters` values.
const CLUSTER_RULES: Values<ClusterRule> = &[
    (
        "non-linear",
        "Non-linear nodes joined by short edges",
        ClusterRule::NonLinear,
    ),
    (
        "equal-distance",
        "Nodes at equal shortest distance from a root, as in the paper",
        ClusterRule::EqualDistance,
    ),
];

/// `--laplacian` values.
const LAPLACIAN_RULES: Values<LaplacianRule> = &[
    (
        "held",
        "Smoothness rows for degree-2 nodes only",
        LaplacianRule::Held,
    ),
    (
        "uniform",
        "The uniform Laplacian of every node, as in the paper",
        LaplacianRule::Uniform,
    ),
];

/// A parser admitting exactly the names in `values` (listed with their meaning by `--help`) and
/// giving the library's value each stands for.
fn one_of<T: Clone + Send + Sync + 'static>(values: Values<T>) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        values
            .iter()
            .map(|(name, help, _)| PossibleValue::new(*name).help(*help)),
    )
    .try_map(move |name: String| {
        values
            .iter()
            .find(|(known, _, _)| *known == name)
            .map(|(_, _, value)| value.clone())
            .ok_or_else(|| format!("unknown value {name:?}"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;
    use ridgeline::curves::CurveOptions;
    use ridgeline::Params;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
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
}
