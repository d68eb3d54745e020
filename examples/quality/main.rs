//! The quality benchmark: every case with known centerlines is traced by ridgeline, by ridgeline
//! with the paper's own parameters (`Params::paper()`), by a Zhang-Suen thinning baseline and by
//! that baseline with the pruning a careful user adds, then scored against the truth as the ink
//! shows it (`ridgeline_testkit::score`). Prints a table per group, with a row of the best thinning
//! baseline per column, the time each group took, and writes everything as JSON.
//!
//! ```text
//! cargo run --release --example quality [-- --json PATH] [--group NAME[,NAME...]] [--case NAME]
//!     [--hanzi-every N] [--pictures DIR] [--why] [--verbose]
//! ```
//!
//! Groups (docs/quality.md says what each one shows): `hard`, `text`, `prints` (the first
//! benchmark), the Hershey fonts `scriptc`, `cursive`, `gothiceng`, `timesr` and `japanese`, the
//! generated `cells`, `letters`, `zigzags`, `triples`, `arms`, and `hanzi` (characters of a real
//! font, read from `../shared/data/hanzi` when present; skipped with a note when not;
//! `--hanzi-every N` keeps every N-th character for a quicker run), `degraded`, the graph's
//! hardest decisions `overhangs`, `loops`, `thin` and `stars`, `points` (strip-shaped point
//! sets, the paper's own input, scored in units of the strip width: `points.rs`), then `real`
//! (below). Without
//! `--group` every group runs (about a minute and a half on two cores).
//!
//! When `../shared/data` (beside the crate root) holds real fingerprints and text, ridgeline also
//! runs on them (group `real`, no truth): time, counts, and endpoint / junction / short-branch
//! rates.
//!
//! Columns: `IoU` is the intersection over union of the strokes re-rendered with their widths and
//! the input foreground (`ridgeline::strokes::coverage_iou`); `exactly right` is the share of cases
//! whose graph is exactly right (`Scores::exactly_right`: every junction and end matched one to
//! one with none left over, components and cycles exact); `off-ink` is the share of the predicted
//! centerline length over background pixels (`ridgeline_testkit::score::off_ink`). The real fingerprints
//! get their minutiae counts (`ridgeline::minutiae`, endings and bifurcations away from the
//! print's border).
//!
//! Why graphs are not exactly right: with `--why` (or `--verbose`) each group's table is followed
//! by the share of cases, per method, with a missed junction, an extra junction, a matched junction
//! of the wrong degree, a missed end, a spurious end, wrong cycles and wrong components
//! (`ridgeline_testkit::score::Misses`; a case may have several). The JSON always holds them
//! (`misses`).

mod hanzi;
mod pictures;
mod points;
mod thinning;

use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use ridgeline::minutiae::{minutiae, MinutiaKind, MinutiaeOptions};
use ridgeline::strokes::coverage_iou;
use ridgeline::{Limits, Params, Polarity, StrokeGraph};
use ridgeline_testkit::score::{
    aggregate, miss_shares, score_with, truth_graph_with, GroupScores, MissShares, Misses,
    ScoreOptions, Scores,
};
use ridgeline_testkit::synth::{self, Case, Degraded, CROWDED_GROUPS, GRAPH_GROUPS};
use serde::Serialize;

/// Command-line arguments.
struct Args {
    json: PathBuf,
    groups: Option<Vec<String>>,
    case: Option<String>,
    hanzi_every: usize,
    pictures: Option<PathBuf>,
    /// Print why graphs are not exactly right after each group's table.
    why: bool,
    verbose: bool,
}

const USAGE: &str = "usage: quality [--json PATH] [--group NAME[,NAME...]] [--case NAME] [--hanzi-every N] [--pictures DIR] [--why] [--verbose]";

fn parse_args() -> anyhow::Result<Args> {
    let mut args = Args {
        json: Path::new(env!("CARGO_MANIFEST_DIR")).join("target/quality.json"),
        groups: None,
        case: None,
        hanzi_every: 1,
        pictures: None,
        why: false,
        verbose: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().with_context(|| format!("{arg} needs a value"));
        match arg.as_str() {
            "--json" => args.json = PathBuf::from(value()?),
            "--group" => {
                let names: Vec<String> =
                    value()?.split(',').map(|g| g.trim().to_string()).collect();
                for name in &names {
                    if name != "real" && name != "points" && !all_groups().contains(&name.as_str())
                    {
                        bail!(
                            "unknown group {name:?}; groups: {}, points, real",
                            all_groups().join(", ")
                        );
                    }
                }
                args.groups = Some(names);
            }
            "--case" => args.case = Some(value()?),
            "--hanzi-every" => {
                args.hanzi_every = value()?
                    .parse()
                    .ok()
                    .filter(|&n: &usize| n >= 1)
                    .context("--hanzi-every needs a whole number, at least 1")?
            }
            "--pictures" => args.pictures = Some(PathBuf::from(value()?)),
            "--why" => args.why = true,
            "--verbose" | "-v" => args.verbose = true,
            "--help" | "-h" => {
                println!("{USAGE}\ngroups: {}, points, real", all_groups().join(", "));
                std::process::exit(0);
            }
            other => bail!("unknown argument {other:?} (try --help)"),
        }
    }
    Ok(args)
}

/// Every group with a truth, in the order of the tables.
fn all_groups() -> Vec<&'static str> {
    let mut groups = vec!["hard", "text", "prints"];
    groups.extend(CROWDED_GROUPS);
    groups.push("hanzi");
    groups.push("degraded");
    groups.extend(GRAPH_GROUPS);
    groups.push("pages");
    groups
}

/// The methods compared in every table.
const METHODS: [&str; 5] = [
    "ridgeline",
    "node graph",
    "paper",
    "thinning",
    "thinning+pruning",
];

/// The extra row of the `degraded` group: ridgeline on the clean mask of the same case, the score
/// the degraded capture is measured against.
const CLEAN: &str = "ridgeline on clean";

/// The extra row of the `pages` group: ridgeline tracing every region that is not strokes
/// (`--keep-regions all`), as it did before it found them.
const KEPT: &str = "ridgeline, regions kept";

/// The methods of one group's table: [`METHODS`], for `degraded` and `pages` also [`CLEAN`], for
/// `pages` also [`KEPT`].
fn group_methods(group: &str) -> Vec<&'static str> {
    let mut list = METHODS.to_vec();
    if group == "degraded" || group == "pages" {
        list.insert(1, CLEAN);
    }
    if group == "pages" {
        list.insert(2, KEPT);
    }
    list
}

/// The baselines whose best per column gets a row of its own.
const BASELINES: [&str; 2] = ["thinning", "thinning+pruning"];

/// The "ridgeline" method's parameters: the defaults, with the fields of the JSON object in
/// `RIDGELINE_PARAMS` (if set) laid over them, so variants are measured on one build
/// (`RIDGELINE_PARAMS='{"dense_fit": true}'`).
fn variant_params() -> anyhow::Result<Params> {
    let Ok(overrides) = std::env::var("RIDGELINE_PARAMS") else {
        return Ok(Params::default());
    };
    let mut value = serde_json::to_value(Params::default())?;
    let overrides: serde_json::Value =
        serde_json::from_str(&overrides).context("RIDGELINE_PARAMS is not JSON")?;
    let (Some(fields), Some(over)) = (value.as_object_mut(), overrides.as_object()) else {
        bail!("RIDGELINE_PARAMS must be a JSON object");
    };
    for (key, v) in over {
        fields.insert(key.clone(), v.clone());
    }
    let params: Params = serde_json::from_value(value)?;
    // A misspelt name would be dropped silently: each one must come back out as it went in.
    let back = serde_json::to_value(&params)?;
    for (key, v) in over {
        let default_false = v == &serde_json::Value::Bool(false);
        if back.get(key) != Some(v) && !default_false {
            bail!("RIDGELINE_PARAMS: no parameter {key:?}");
        }
    }
    Ok(params)
}

/// The methods to run on `group`: all of [`group_methods`], or those named in `QUALITY_METHODS`
/// (separated by `;` or `,`; a name that holds a comma, such as `ridgeline, regions kept`, is
/// named whole between semicolons).
fn methods(group: &str) -> Vec<&'static str> {
    match std::env::var("QUALITY_METHODS") {
        Ok(list) => group_methods(group)
            .into_iter()
            .filter(|m| named(&list, m))
            .collect(),
        Err(_) => group_methods(group),
    }
}

/// Whether `list` (see [`methods`]) names `method`: one of its `;`-separated items is the name,
/// or, when an item is no method's whole name (of any group), one of its `,`-separated parts is.
fn named(list: &str, method: &str) -> bool {
    let whole = |item: &str| METHODS.contains(&item) || item == CLEAN || item == KEPT;
    list.split(';')
        .map(str::trim)
        .any(|item| item == method || (!whole(item) && item.split(',').any(|x| x.trim() == method)))
}

/// One method on one case. With a degraded capture (`gray`), ridgeline's methods trace the gray
/// image with their front end, the thinning baselines run on Otsu's mask with the polarity known
/// (`ridgeline on clean` traces the clean mask).
fn run_method(
    method: &str,
    case: &Case,
    gray: Option<&Degraded>,
) -> anyhow::Result<(StrokeGraph, Vec<String>)> {
    // The graph and the codes of the warnings it raised.
    let graph_and_codes = |trace: ridgeline::Trace| {
        let codes = trace.warnings.iter().map(|w| w.code.to_string()).collect();
        (trace.graph, codes)
    };
    let trace = |params: &Params| -> anyhow::Result<(StrokeGraph, Vec<String>)> {
        Ok(graph_and_codes(match gray {
            Some(d) => ridgeline::trace_image(&d.gray, params)?,
            None => ridgeline::trace_binary(&case.binary, params)?,
        }))
    };
    let baseline_mask = || -> anyhow::Result<ridgeline::Binary> {
        Ok(match gray {
            Some(d) => {
                let mut params = Params::default();
                params.front_end.polarity = if d.recipe.inverted {
                    Polarity::LightInk
                } else {
                    Polarity::DarkInk
                };
                ridgeline::raster::binarize(&d.gray, &params)?
            }
            None => case.binary.clone(),
        })
    };
    Ok(match method {
        "ridgeline" => trace(&variant_params()?)?,
        "paper" => trace(&Params::paper())?,
        "node graph" => {
            let mut params = Params::default();
            params.finish.skeleton = false;
            trace(&params)?
        }
        CLEAN => graph_and_codes(ridgeline::trace_binary(&case.binary, &variant_params()?)?),
        KEPT => {
            let mut params = variant_params()?;
            params.front_end.keep_regions = ridgeline::RegionKind::ALL.to_vec();
            trace(&params)?
        }
        "thinning" => (thinning::trace(&baseline_mask()?), Vec::new()),
        "thinning+pruning" => (thinning::trace_pruned(&baseline_mask()?), Vec::new()),
        other => bail!("unknown method {other}"),
    })
}

/// The cases of one group, how they are scored, and what was left out.
struct Group {
    cases: Vec<Case>,
    /// The degraded captures of the cases, by case name (group `degraded` only).
    captures: HashMap<String, Degraded>,
    options: ScoreOptions,
    note: Option<String>,
}

/// The groups drawn with Hershey fonts that draw ornaments as closed outlines the pen fills
/// (the Japanese font's end triangles, teardrop dots and wedges; the filled bowls and knobs of
/// the script, blackletter and serif fonts): their truth reads such a loop around no hole as the
/// stroke its ink shows (`ScoreOptions::filled_loops_as_strokes`), as every other reading of
/// the truth follows the ink rather than the pen's path. The generated groups draw pen paths
/// (a 1-px comb's tooth one pixel past its bar is no arm: `synth::thin_cases`) and keep the
/// default. docs/quality.md, "Spurious ends on japanese" and "Session of 2026-12-07,
/// thirteenth".
const FILLED_OUTLINE_FONTS: [&str; 5] = ["japanese", "scriptc", "cursive", "gothiceng", "timesr"];

fn load_group(name: &str, hanzi_every: usize) -> anyhow::Result<Group> {
    if name == "hanzi" {
        let Some(mut cases) = hanzi::cases()? else {
            return Ok(Group {
                cases: Vec::new(),
                options: hanzi::OPTIONS,
                captures: HashMap::new(),
                note: Some(format!(
                    "skipped: no data in {} (see docs/quality.md)",
                    hanzi::data_dir().display()
                )),
            });
        };
        let total = cases.len();
        let mut note = None;
        if hanzi_every > 1 {
            // Every N-th character in code-point order: deterministic, and it keeps the spread
            // of stroke counts.
            cases = cases.into_iter().step_by(hanzi_every).collect();
            note = Some(format!(
                "{} of {total} characters (every {hanzi_every}th in code-point order, --hanzi-every)",
                cases.len()
            ));
        }
        return Ok(Group {
            cases,
            options: hanzi::OPTIONS,
            captures: HashMap::new(),
            note,
        });
    }
    if name == "degraded" {
        let mut clean = synth::text_cases();
        clean.extend(synth::letter_cases());
        clean.extend(synth::hard_cases());
        let degraded = synth::degrade_cases(clean, 0xD1E7);
        let cases = degraded.iter().map(|d| d.case.clone()).collect();
        return Ok(Group {
            cases,
            // Scored at 2 px and more: the capture moves edges by a pixel before any tracing.
            options: ScoreOptions {
                taus: [2.0, 3.0, 4.0],
                ..ScoreOptions::default()
            },
            captures: degraded
                .into_iter()
                .map(|d| (d.case.name.clone(), d))
                .collect(),
            note: Some(
                "text, letters and hard cases drawn anti-aliased, blurred, unevenly lit, noised, \
                 JPEG q70, every third inverted; scored against the clean truth"
                    .to_string(),
            ),
        });
    }
    if name == "pages" {
        let pages = synth::page_cases();
        return Ok(Group {
            cases: pages.iter().map(|d| d.case.clone()).collect(),
            // Scored as the degraded captures are: the scan moves edges by a pixel.
            options: ScoreOptions {
                taus: [2.0, 3.0, 4.0],
                ..ScoreOptions::default()
            },
            captures: pages
                .into_iter()
                .map(|d| (d.case.name.clone(), d))
                .collect(),
            note: Some(
                "text pages with a halftone photo, a dark frame, rules and a table grid (content, \
                 in the truth), a grille, show-through, a torn page edge, and photographed; \
                 off-ink is the traced length outside the text's strokes"
                    .to_string(),
            ),
        });
    }
    let cases = ridgeline_testkit::synth::group_cases(name)
        .with_context(|| format!("unknown group {name}"))?;
    Ok(Group {
        cases,
        options: ScoreOptions {
            filled_loops_as_strokes: FILLED_OUTLINE_FONTS.contains(&name),
            retraces_as_arms: FILLED_OUTLINE_FONTS.contains(&name),
            ..ScoreOptions::default()
        },
        captures: HashMap::new(),
        note: None,
    })
}

/// One method on one case.
#[derive(Serialize)]
struct Outcome {
    case: String,
    group: String,
    method: String,
    time_ms: f64,
    /// The failure (an error or a panic), if the method did not produce a graph.
    failure: Option<String>,
    scores: Option<Scores>,
    /// Re-rendered widths against the input foreground.
    iou: Option<f64>,
    /// The codes of the warnings the trace raised (ridgeline's methods).
    warnings: Vec<String>,
}

/// One method on one group.
#[derive(Serialize)]
struct GroupRow {
    group: String,
    method: String,
    failures: usize,
    mean_time_ms: f64,
    scores: GroupScores,
    /// Mean of the cases' IoU; `None` when no case was traced.
    mean_iou: Option<f64>,
}

/// The best of the thinning baselines on each column of one group (each value may come from a
/// different baseline): higher is better except for chamfer, Hausdorff, spurs, off-ink, time and
/// failures.
#[derive(Serialize)]
struct BestBaseline {
    group: String,
    methods: Vec<String>,
    f1: [f64; 3],
    chamfer: f64,
    hausdorff: f64,
    junction_precision: f64,
    junction_recall: f64,
    crossing_accuracy: Option<f64>,
    shallow_crossing_accuracy: Option<f64>,
    spurs_per_stroke: f64,
    endpoint_recall: f64,
    components_exact: f64,
    cycles_exact: f64,
    exactly_right: f64,
    off_ink: f64,
    mean_iou: Option<f64>,
    mean_time_ms: f64,
    failures: usize,
}

/// The truth's topology against the ink's: the scorer's truth of a case is built from its
/// strokes, and where the ink is not drawn from them (hanzi) or strokes crowd, it may count other
/// components or cycles than the binary shows (8-connected ink components; holes: 4-connected
/// background components away from the border larger than [`SPECK`] pixels). Cases with
/// dropout differ by design.
#[derive(Serialize)]
struct TruthCheck {
    group: String,
    /// Cases whose truth has another number of components than the ink.
    components_differ: Vec<String>,
    /// Cases whose truth has another number of independent cycles than the ink has holes.
    cycles_differ: Vec<String>,
    /// Cases whose truth scored against itself is not exactly right.
    self_not_exact: Vec<String>,
    /// Pooled off-ink share of the truth's own centerlines.
    truth_off_ink: f64,
}

/// Background components of at most this many pixels are specks, not holes: where two strokes
/// meet at a sharp angle the rendering can enclose one or two pixels (docs/design.md,
/// adaptation 2, takes holes of 3 px or less for noise too).
const SPECK: usize = 3;

/// Ink components (8-connected) and holes (4-connected background components that do not reach
/// the border, larger than [`SPECK`]) of a binary.
fn ink_topology(binary: &ridgeline::Binary) -> (usize, usize) {
    let (w, h) = (binary.width as i64, binary.height as i64);
    let mut seen = vec![false; binary.ink.len()];
    let (mut components, mut holes) = (0, 0);
    let mut stack = Vec::new();
    for start in 0..binary.ink.len() {
        if seen[start] {
            continue;
        }
        let ink = binary.ink[start];
        let mut border = false;
        let mut size = 0;
        seen[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = (i as i64 % w, i as i64 / w);
            border |= x == 0 || y == 0 || x == w - 1 || y == h - 1;
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if (dx == 0 && dy == 0) || (!ink && dx != 0 && dy != 0) {
                        continue;
                    }
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w || ny >= h {
                        continue;
                    }
                    let j = (ny * w + nx) as usize;
                    if !seen[j] && binary.ink[j] == ink {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        if ink {
            components += 1;
        } else if !border && size > SPECK {
            holes += 1;
        }
    }
    (components, holes)
}

/// How long one group took.
#[derive(Serialize)]
struct GroupTiming {
    group: String,
    cases: usize,
    /// Generating or reading the cases, s.
    load_s: f64,
    /// Building the truths, s.
    truth_s: f64,
    /// Tracing and scoring with every method, s.
    methods_s: f64,
    note: Option<String>,
}

/// ridgeline on one real image (no truth).
#[derive(Serialize)]
struct RealImage {
    file: String,
    width: u32,
    height: u32,
    time_ms: f64,
    failure: Option<String>,
    vertices: usize,
    edges: usize,
    centerline_px: f64,
    endpoints_per_1000px: f64,
    junctions_per_1000px: f64,
    /// Share of edges ending in an endpoint that are shorter than their mean stroke width.
    spur_share: f64,
    /// Re-rendered widths against the binarized foreground.
    iou: f64,
    /// Ridge endings and bifurcations (fingerprints only).
    endings: Option<usize>,
    bifurcations: Option<usize>,
}

/// Why one method's graphs on one group are not exactly right.
#[derive(Serialize)]
struct MissRow {
    group: String,
    method: String,
    shares: MissShares,
}

#[derive(Serialize)]
struct Report {
    groups: Vec<GroupRow>,
    /// Why graphs are not exactly right, per group and method.
    misses: Vec<MissRow>,
    best_baselines: Vec<BestBaseline>,
    timings: Vec<GroupTiming>,
    truth_checks: Vec<TruthCheck>,
    cases: Vec<Outcome>,
    /// The point-set group (`points`), scored in units of the strip width.
    point_sets: Vec<points::PointOutcome>,
    real_images: Vec<RealImage>,
}

/// Runs `f`, turning an error or a panic into a message.
fn guarded<T>(f: impl FnOnce() -> anyhow::Result<T>) -> Result<T, String> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(e)) => Err(format!("error: {e:#}")),
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(format!("panic: {message}"))
        }
    }
}

fn main() -> anyhow::Result<()> {
    let args = parse_args()?;
    // Panics are caught per case and reported in the tables; keep stderr quiet.
    std::panic::set_hook(Box::new(|_| {}));
    let started = Instant::now();

    let selected: Vec<&str> = all_groups()
        .into_iter()
        .filter(|g| {
            args.groups
                .as_ref()
                .is_none_or(|s| s.iter().any(|n| n == g))
        })
        .collect();
    let mut report = Report {
        groups: Vec::new(),
        misses: Vec::new(),
        best_baselines: Vec::new(),
        timings: Vec::new(),
        truth_checks: Vec::new(),
        cases: Vec::new(),
        point_sets: Vec::new(),
        real_images: Vec::new(),
    };
    let mut any_case = false;
    for &name in &selected {
        let load_start = Instant::now();
        let Group {
            cases,
            captures,
            options,
            note,
        } = guarded(|| load_group(name, args.hanzi_every))
            .map_err(|e| anyhow::anyhow!("group {name}: {e}"))?;
        // QUALITY_TRUTH_FILLED_LOOPS=all: every group's truth reads filled loops as the strokes
        // their ink shows (`ScoreOptions::filled_loops_as_strokes`); `=none`: no group's does,
        // the Hershey fonts' included (their truth as the pen drew it, the figures before the
        // thirteenth session of 2026-12-07; docs/quality.md, "Spurious ends on japanese").
        let options = ScoreOptions {
            filled_loops_as_strokes: match std::env::var("QUALITY_TRUTH_FILLED_LOOPS").as_deref() {
                Ok("all") => true,
                Ok("none") => false,
                _ => options.filled_loops_as_strokes,
            },
            // QUALITY_TRUTH_RETRACES=all / =none: the same for the strokes that come back over
            // their own ink (`ScoreOptions::retraces_as_arms`).
            retraces_as_arms: match std::env::var("QUALITY_TRUTH_RETRACES").as_deref() {
                Ok("all") => true,
                Ok("none") => false,
                _ => options.retraces_as_arms,
            },
            ..options
        };
        let cases: Vec<Case> = cases
            .into_iter()
            .filter(|c| args.case.as_ref().is_none_or(|n| &c.name == n))
            .collect();
        let load_s = load_start.elapsed().as_secs_f64();
        if cases.is_empty() {
            if let Some(note) = &note {
                println!("\n## {name}: {note}");
            }
            continue;
        }
        any_case = true;
        let mut truth_s = 0.0;
        let methods_start = Instant::now();
        let mut outcomes = Vec::new();
        let mut check = TruthCheck {
            group: name.to_string(),
            components_differ: Vec::new(),
            cycles_differ: Vec::new(),
            self_not_exact: Vec::new(),
            truth_off_ink: 0.0,
        };
        let (mut truth_length, mut truth_off) = (0.0, 0.0);
        for case in &cases {
            let truth_start = Instant::now();
            let truth = guarded(|| Ok(truth_graph_with(case, &options)));
            truth_s += truth_start.elapsed().as_secs_f64();
            if let Ok(truth) = &truth {
                let (components, holes) = ink_topology(&case.binary);
                if truth.components() != components {
                    check.components_differ.push(case.name.clone());
                }
                if truth.cycles() != holes {
                    check.cycles_differ.push(case.name.clone());
                }
                let own = score_with(case, truth, truth, &options);
                if !own.exactly_right {
                    check.self_not_exact.push(case.name.clone());
                }
                truth_length += own.centerline_length;
                truth_off += own.off_ink_length;
            }
            let mut traced = Vec::new();
            let capture = captures.get(&case.name);
            if let Some(dir) = &args.pictures {
                // The case's ink as the methods read it, to trace it again by hand.
                std::fs::create_dir_all(dir)?;
                let path = dir.join(format!("{}.ink.png", case.name));
                let b = &case.binary;
                image::GrayImage::from_fn(b.width, b.height, |x, y| {
                    image::Luma([if b.get(x as i64, y as i64) { 0 } else { 255 }])
                })
                .save(&path)
                .with_context(|| format!("writing {}", path.display()))?;
            }
            if let (Some(dir), Some(d)) = (&args.pictures, capture) {
                std::fs::create_dir_all(dir)?;
                let path = dir.join(format!("{}.capture.png", case.name));
                d.gray
                    .save(&path)
                    .with_context(|| format!("writing {}", path.display()))?;
            }
            for method in methods(name) {
                let start = Instant::now();
                let (result, warnings) = match guarded(|| run_method(method, case, capture)) {
                    Ok((graph, warnings)) => (Ok(graph), warnings),
                    Err(e) => (Err(e), Vec::new()),
                };
                let time_ms = start.elapsed().as_secs_f64() * 1e3;
                let iou = result
                    .as_ref()
                    .ok()
                    .map(|graph| coverage_iou(graph, &case.binary));
                let (failure, scores) = match (&truth, &result) {
                    (Ok(truth), Ok(graph)) => {
                        match guarded(|| Ok(score_with(case, truth, graph, &options))) {
                            Ok(s) => (None, Some(s)),
                            Err(e) => (Some(format!("scoring: {e}")), None),
                        }
                    }
                    (Err(e), _) => (Some(format!("truth: {e}")), None),
                    (_, Err(e)) => (Some(e.clone()), None),
                };
                if std::env::var("QUALITY_DUMP_CROSSINGS").is_ok() && method == "ridgeline" {
                    if let (Ok(truth), Ok(graph), Some(sc)) = (&truth, &result, &scores) {
                        dump_crossings(&case.name, truth, graph, sc);
                    }
                }
                if std::env::var("QUALITY_DUMP_ENDS").is_ok() && method == "ridgeline" {
                    if let (Ok(truth), Ok(graph)) = (&truth, &result) {
                        dump_ends(case, truth, graph, &options);
                        dump_missed(case, truth, graph, &options);
                    }
                }
                if std::env::var("QUALITY_DUMP_JUNCTIONS").is_ok() && method == "ridgeline" {
                    if let (Ok(truth), Ok(graph)) = (&truth, &result) {
                        dump_junctions(case, truth, graph, &options);
                    }
                }
                traced.push(result.ok());
                outcomes.push(Outcome {
                    case: case.name.clone(),
                    group: case.group.clone(),
                    method: method.to_string(),
                    time_ms,
                    failure,
                    scores,
                    iou,
                    warnings,
                });
            }
            if let (Some(dir), Ok(truth)) = (&args.pictures, &truth) {
                pictures::write(dir, case, truth, &methods(name), &traced)?;
            }
        }
        let methods_s = methods_start.elapsed().as_secs_f64() - truth_s;
        check.truth_off_ink = if truth_length > 0.0 {
            truth_off / truth_length
        } else {
            0.0
        };

        let rows: Vec<GroupRow> = group_methods(name)
            .iter()
            .map(|&method| group_row(name, method, &outcomes))
            .collect();
        let best = best_baseline(name, &rows);
        println!("\n## {name} ({} cases)\n", cases.len());
        if let Some(note) = &note {
            println!("{note}\n");
        }
        print_table(&rows, &best);
        let misses: Vec<MissRow> = group_methods(name)
            .iter()
            .map(|&method| miss_row(name, method, &outcomes))
            .collect();
        if args.why || args.verbose {
            print_misses(&misses);
        }
        report.misses.extend(misses);
        let warned: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.method == "ridgeline" && !o.warnings.is_empty())
            .collect();
        let low: Vec<&Outcome> = outcomes
            .iter()
            .filter(|o| o.method == "ridgeline")
            .filter(|o| o.scores.as_ref().is_some_and(|s| s.f1[0] < 0.9))
            .collect();
        let low_warned = low.iter().filter(|o| !o.warnings.is_empty()).count();
        let mut codes: Vec<&str> = warned
            .iter()
            .flat_map(|o| o.warnings.iter().map(String::as_str))
            .collect();
        codes.sort_unstable();
        codes.dedup();
        println!(
            "\nwarnings (ridgeline): on {} of {} cases ({}); {low_warned} of the {} cases under F1@{} .9 warned",
            warned.len(),
            cases.len(),
            if codes.is_empty() { "none".to_string() } else { codes.join(", ") },
            low.len(),
            tau(options.taus[0]),
        );
        if !captures.is_empty() {
            // The polarity the default front end decides on each capture, against the recipe's.
            let mut names: Vec<&String> = captures.keys().collect();
            names.sort();
            let wrong: Vec<&str> = names
                .iter()
                .filter(|name| {
                    let d = &captures[name.as_str()];
                    let expected = ridgeline::InkSide::of(!d.recipe.inverted);
                    ridgeline::trace_image(&d.gray, &Params::default())
                        .ok()
                        .and_then(|t| t.decisions)
                        .is_none_or(|decided| decided.polarity != expected)
                })
                .map(|name| name.as_str())
                .collect();
            println!(
                "polarity (defaults): right on {} of {} captures{}",
                names.len() - wrong.len(),
                names.len(),
                if wrong.is_empty() {
                    String::new()
                } else {
                    format!("; wrong on {}", wrong.join(", "))
                }
            );
        }
        let timing = GroupTiming {
            group: name.to_string(),
            cases: cases.len(),
            load_s,
            truth_s,
            methods_s,
            note,
        };
        println!(
            "\n{name}: {:.1} s ({:.1} s making the cases, {:.1} s their truths, {:.1} s tracing and scoring)",
            timing.load_s + timing.truth_s + timing.methods_s,
            timing.load_s,
            timing.truth_s,
            timing.methods_s
        );
        let list = |names: &[String]| {
            if names.is_empty() {
                String::new()
            } else {
                let shown: Vec<&str> = names.iter().take(6).map(String::as_str).collect();
                let more = if names.len() > 6 { ", ..." } else { "" };
                format!(" ({}{more})", shown.join(", "))
            }
        };
        println!(
            "truth check: components differ from the ink's in {}{}, cycles from its holes in {}{}; truth against itself not exactly right in {}{}; truth off-ink {:.2}%",
            check.components_differ.len(),
            list(&check.components_differ),
            check.cycles_differ.len(),
            list(&check.cycles_differ),
            check.self_not_exact.len(),
            list(&check.self_not_exact),
            100.0 * check.truth_off_ink,
        );
        if args.verbose {
            print_cases(&outcomes);
        }
        report.truth_checks.push(check);
        report.groups.extend(rows);
        report.best_baselines.push(best);
        report.timings.push(timing);
        report.cases.extend(outcomes);
    }
    let run_points = args
        .groups
        .as_ref()
        .is_none_or(|g| g.iter().any(|n| n == "points"));
    if run_points {
        report.point_sets = points::run(args.case.as_deref(), args.verbose);
        any_case |= !report.point_sets.is_empty();
    }
    let run_real = args
        .groups
        .as_ref()
        .is_none_or(|g| g.iter().any(|n| n == "real"));
    if !any_case && !run_real {
        bail!("no case matches the filters");
    }
    let failures: Vec<&Outcome> = report
        .cases
        .iter()
        .filter(|o| o.failure.is_some())
        .collect();
    if !failures.is_empty() {
        println!(
            "\n{} failures (method/case: reason), first ones:",
            failures.len()
        );
        for o in failures.iter().take(10) {
            println!(
                "  {}/{}: {}",
                o.method,
                o.case,
                o.failure.as_deref().unwrap_or("")
            );
        }
    }

    if run_real && args.case.is_none() {
        report.real_images = real_images(args.verbose);
    }

    if let Some(dir) = args.json.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let json = serde_json::to_string_pretty(&report)?;
    std::fs::write(&args.json, json).with_context(|| format!("writing {}", args.json.display()))?;
    println!(
        "\nwrote {} ({:.1} s in all)",
        args.json.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn group_row(group: &str, method: &str, outcomes: &[Outcome]) -> GroupRow {
    let mine: Vec<&Outcome> = outcomes.iter().filter(|o| o.method == method).collect();
    let scores: Vec<Scores> = mine.iter().filter_map(|o| o.scores.clone()).collect();
    let ious: Vec<f64> = mine.iter().filter_map(|o| o.iou).collect();
    GroupRow {
        group: group.to_string(),
        method: method.to_string(),
        failures: mine.iter().filter(|o| o.failure.is_some()).count(),
        mean_time_ms: mine.iter().map(|o| o.time_ms).sum::<f64>() / mine.len().max(1) as f64,
        scores: aggregate(&scores),
        mean_iou: (!ious.is_empty()).then(|| ious.iter().sum::<f64>() / ious.len() as f64),
    }
}

fn miss_row(group: &str, method: &str, outcomes: &[Outcome]) -> MissRow {
    let scores: Vec<Scores> = outcomes
        .iter()
        .filter(|o| o.method == method)
        .filter_map(|o| o.scores.clone())
        .collect();
    MissRow {
        group: group.to_string(),
        method: method.to_string(),
        shares: miss_shares(&scores),
    }
}

/// The compact table of why graphs are not exactly right: per method, the share of cases with
/// each miss (a case may have several).
fn print_misses(rows: &[MissRow]) {
    println!("\nwhy not exactly right (share of cases; a case may have several):\n");
    println!("| method | not right | {} |", Misses::NAMES.join(" | "));
    println!("|---|---|{}", "---|".repeat(Misses::NAMES.len()));
    for r in rows.iter().filter(|r| r.shares.cases > 0) {
        let cells: Vec<String> = r
            .shares
            .shares()
            .iter()
            .map(|x| format!("{:.0}%", 100.0 * x))
            .collect();
        println!(
            "| {} | {:.0}% | {} |",
            r.method,
            100.0 * r.shares.not_exactly_right,
            cells.join(" | ")
        );
    }
}

fn best_baseline(group: &str, rows: &[GroupRow]) -> BestBaseline {
    let base: Vec<&GroupRow> = rows
        .iter()
        .filter(|r| BASELINES.contains(&r.method.as_str()) && r.scores.cases > 0)
        .collect();
    let max = |f: &dyn Fn(&GroupRow) -> f64| base.iter().map(|r| f(r)).fold(f64::NAN, f64::max);
    let min = |f: &dyn Fn(&GroupRow) -> f64| base.iter().map(|r| f(r)).fold(f64::NAN, f64::min);
    let max_opt =
        |f: &dyn Fn(&GroupRow) -> Option<f64>| base.iter().filter_map(|r| f(r)).reduce(f64::max);
    BestBaseline {
        group: group.to_string(),
        methods: base.iter().map(|r| r.method.clone()).collect(),
        f1: std::array::from_fn(|k| max(&|r| r.scores.f1[k])),
        chamfer: min(&|r| r.scores.chamfer),
        hausdorff: min(&|r| r.scores.hausdorff),
        junction_precision: max(&|r| r.scores.junction_precision),
        junction_recall: max(&|r| r.scores.junction_recall),
        crossing_accuracy: max_opt(&|r| r.scores.crossing_accuracy),
        shallow_crossing_accuracy: max_opt(&|r| r.scores.shallow_crossing_accuracy),
        spurs_per_stroke: min(&|r| r.scores.spurs_per_stroke),
        endpoint_recall: max(&|r| r.scores.endpoint_recall),
        components_exact: max(&|r| r.scores.components_exact),
        cycles_exact: max(&|r| r.scores.cycles_exact),
        exactly_right: max(&|r| r.scores.exactly_right),
        off_ink: min(&|r| r.scores.off_ink),
        mean_iou: max_opt(&|r| r.mean_iou),
        mean_time_ms: min(&|r| r.mean_time_ms),
        failures: rows
            .iter()
            .filter(|r| BASELINES.contains(&r.method.as_str()))
            .map(|r| r.failures)
            .min()
            .unwrap_or(0),
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| format!("{v:.3}"))
}

/// A tolerance for a column header: `1`, `2.5`.
fn tau(t: f64) -> String {
    format!("{t}")
}

fn print_table(rows: &[GroupRow], best: &BestBaseline) {
    let taus = rows
        .iter()
        .find(|r| r.scores.cases > 0)
        .map_or(ridgeline_testkit::score::TAUS, |r| r.scores.taus);
    println!(
        "| method | F1@{} | F1@{} | chamfer | Hausdorff | junction P | junction R | X >=30° | X 15° | spurs/stroke | endpoint R | components exact | cycles exact | exactly right | off-ink | IoU | ms | failed |",
        tau(taus[0]),
        tau(taus[1])
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let s = &r.scores;
        if s.cases == 0 {
            println!(
                "| {} | - | - | - | - | - | - | - | - | - | - | - | - | - | - | {} | {:.1} | {} |",
                r.method,
                opt(r.mean_iou),
                r.mean_time_ms,
                r.failures
            );
            continue;
        }
        println!(
            "| {} | {:.3} | {:.3} | {:.2} | {:.1} | {:.2} | {:.2} | {} | {} | {:.3} | {:.2} | {:.0}% | {:.0}% | {:.0}% | {:.2}% | {} | {:.1} | {} |",
            r.method,
            s.f1[0],
            s.f1[1],
            s.chamfer,
            s.hausdorff,
            s.junction_precision,
            s.junction_recall,
            opt(s.crossing_accuracy),
            opt(s.shallow_crossing_accuracy),
            s.spurs_per_stroke,
            s.endpoint_recall,
            100.0 * s.components_exact,
            100.0 * s.cycles_exact,
            100.0 * s.exactly_right,
            100.0 * s.off_ink,
            opt(r.mean_iou),
            r.mean_time_ms,
            r.failures,
        );
    }
    if best.methods.is_empty() {
        return;
    }
    let b = best;
    println!(
        "| best thinning | {:.3} | {:.3} | {:.2} | {:.1} | {:.2} | {:.2} | {} | {} | {:.3} | {:.2} | {:.0}% | {:.0}% | {:.0}% | {:.2}% | {} | {:.1} | {} |",
        b.f1[0],
        b.f1[1],
        b.chamfer,
        b.hausdorff,
        b.junction_precision,
        b.junction_recall,
        opt(b.crossing_accuracy),
        opt(b.shallow_crossing_accuracy),
        b.spurs_per_stroke,
        b.endpoint_recall,
        100.0 * b.components_exact,
        100.0 * b.cycles_exact,
        100.0 * b.exactly_right,
        100.0 * b.off_ink,
        opt(b.mean_iou),
        b.mean_time_ms,
        b.failures,
    );
}

fn print_cases(outcomes: &[Outcome]) {
    let taus = outcomes
        .iter()
        .find_map(|o| o.scores.as_ref())
        .map_or(ridgeline_testkit::score::TAUS, |s| s.taus);
    println!(
        "\n| case | method | F1@{} | F1@{} | Hausdorff | junctions matched/predicted/true | crossings right | spurs | endpoints found/true | components | cycles | exactly right | off-ink | IoU | ms |",
        tau(taus[0]),
        tau(taus[1])
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for o in outcomes {
        let Some(s) = &o.scores else {
            println!(
                "| {} | {} | failed: {} |",
                o.case,
                o.method,
                o.failure.as_deref().unwrap_or("")
            );
            continue;
        };
        let found = s.crossings.iter().filter(|c| c.correct).count();
        println!(
            "| {} | {} | {:.3} | {:.3} | {:.1} | {}/{}/{} | {}/{} | {} | {}/{} | {}/{} | {}/{} | {} | {:.2}% | {} | {:.1} |",
            o.case,
            o.method,
            s.f1[0],
            s.f1[1],
            s.hausdorff,
            s.junctions_matched,
            s.predicted_junctions,
            s.true_junctions,
            found,
            s.crossings.len(),
            s.spurious_endpoints,
            s.endpoints_found,
            s.true_endpoints,
            s.predicted_components,
            s.true_components,
            s.predicted_cycles,
            s.true_cycles,
            if s.exactly_right { "yes" } else { "no" },
            100.0 * s.off_ink,
            opt(o.iou),
            o.time_ms,
        );
    }
}

/// ridgeline on the real images in `../shared/data/{fingerprints,text}`, if present.
fn real_images(verbose: bool) -> Vec<RealImage> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data");
    let mut files = Vec::new();
    for dir in ["fingerprints", "text"] {
        let Ok(entries) = std::fs::read_dir(data.join(dir)) else {
            continue;
        };
        let mut found: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let ext = p
                    .extension()
                    .and_then(|e| e.to_str())
                    .unwrap_or("")
                    .to_lowercase();
                [
                    "png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pgm", "pbm",
                ]
                .contains(&ext.as_str())
            })
            .collect();
        found.sort();
        files.extend(found);
    }
    if files.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::new();
    for path in &files {
        let name = path
            .strip_prefix(&data)
            .unwrap_or(path)
            .display()
            .to_string();
        let mut image = RealImage {
            file: name,
            width: 0,
            height: 0,
            time_ms: 0.0,
            failure: None,
            vertices: 0,
            edges: 0,
            centerline_px: 0.0,
            endpoints_per_1000px: 0.0,
            junctions_per_1000px: 0.0,
            spur_share: 0.0,
            iou: 0.0,
            endings: None,
            bifurcations: None,
        };
        let decoded = guarded(|| {
            let bytes = std::fs::read(path)?;
            Ok(ridgeline::decode(&bytes, &Limits::default())?)
        });
        let start = Instant::now();
        let traced = decoded.and_then(|gray| {
            image.width = gray.width();
            image.height = gray.height();
            guarded(|| {
                let trace = ridgeline::trace_image(&gray, &variant_params()?)?;
                Ok((trace.graph, trace.binary))
            })
        });
        image.time_ms = start.elapsed().as_secs_f64() * 1e3;
        let fingerprint = path
            .parent()
            .and_then(|d| d.file_name())
            .is_some_and(|d| d == "fingerprints");
        match traced {
            Ok((g, binary)) => {
                if let Some(binary) = &binary {
                    image.iou = coverage_iou(&g, binary);
                }
                if fingerprint {
                    let found = minutiae(&g, binary.as_ref(), &MinutiaeOptions::default());
                    let count = |kind| found.iter().filter(|m| m.kind == kind).count();
                    image.endings = Some(count(MinutiaKind::Ending));
                    image.bifurcations = Some(count(MinutiaKind::Bifurcation));
                }
                let length: f64 = g.edges.iter().map(|e| e.length()).sum();
                let per_1000 = |n: usize| {
                    if length > 0.0 {
                        1000.0 * n as f64 / length
                    } else {
                        0.0
                    }
                };
                let short_tips = g
                    .edges
                    .iter()
                    .filter(|e| {
                        let tip = g.vertices[e.from].degree == 1 || g.vertices[e.to].degree == 1;
                        let width = e.widths.iter().sum::<f64>() / e.widths.len().max(1) as f64;
                        tip && e.length() < width
                    })
                    .count();
                image.vertices = g.vertices.len();
                image.edges = g.edges.len();
                image.centerline_px = length;
                image.endpoints_per_1000px = per_1000(g.endpoints().count());
                image.junctions_per_1000px = per_1000(g.junctions().count());
                image.spur_share = if g.edges.is_empty() {
                    0.0
                } else {
                    short_tips as f64 / g.edges.len() as f64
                };
            }
            Err(e) => image.failure = Some(e),
        }
        out.push(image);
    }

    println!("\n## real images (ridgeline, no truth)\n");
    println!("| image | size | ms | vertices | edges | centerline px | endpoints /1000px | junctions /1000px | spur share | IoU | endings | bifurcations |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &out {
        match &r.failure {
            Some(f) => {
                let reason = if verbose { f.as_str() } else { f.lines().next().unwrap_or("") };
                println!("| {} | {}x{} | failed: {} |", r.file, r.width, r.height, reason)
            }
            None => println!(
                "| {} | {}x{} | {:.0} | {} | {} | {:.0} | {:.2} | {:.2} | {:.3} | {:.3} | {} | {} |",
                r.file,
                r.width,
                r.height,
                r.time_ms,
                r.vertices,
                r.edges,
                r.centerline_px,
                r.endpoints_per_1000px,
                r.junctions_per_1000px,
                r.spur_share,
                r.iou,
                r.endings.map_or("-".into(), |n| n.to_string()),
                r.bifurcations.map_or("-".into(), |n| n.to_string()),
            ),
        }
    }
    out
}

/// With `QUALITY_DUMP_ENDS` set: a line per spurious end of the case (ridgeline; a predicted end
/// with no true end within the matching radius, as the scorer counts it), with, in widths of the
/// nearest true vertex: the distance to the nearest true end and whether that end is missed, the
/// distance to the truth's nearest edge, the length of the end's edge, the degree of the vertex at
/// its other end and that vertex's distance to the nearest true junction, and a class letter: A
/// off the truth (its nearest edge more than 1.5 widths away) with a missed true end within 4.5
/// widths, B off the truth otherwise, C on the truth with a missed true end within 3 widths, D
/// (E) an edge of at most 3 widths to a junction with no (a) true junction within 1.5 widths, F
/// a longer edge to a junction, G the rest (docs/quality.md, "Spurious ends on japanese (issue 31)").
/// `QUALITY_DUMP_ENDS`: every true end no predicted end matches, in widths of the true end
/// (`w`): the nearest predicted end, junction and line, the true end's edge (length, degree of
/// its other vertex), and where the nearest predicted end lies along the true end's outward
/// direction (negative: short of it) and across it.
fn dump_missed(case: &Case, truth: &StrokeGraph, graph: &StrokeGraph, options: &ScoreOptions) {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let norm = ridgeline_testkit::score::normalize_with(case, graph, options);
    let radius = |w: f64| w.max(options.min_match_radius);
    let pred_e: Vec<usize> = norm.endpoints().collect();
    let pred_j: Vec<usize> = norm.junctions().collect();
    for t in truth.endpoints() {
        let tp = truth.vertices[t].pos;
        let w = truth.vertices[t].width.max(1.0);
        if pred_e
            .iter()
            .any(|&p| d(norm.vertices[p].pos, tp) <= radius(w))
        {
            continue;
        }
        let ne = pred_e
            .iter()
            .map(|&p| d(norm.vertices[p].pos, tp))
            .fold(f64::INFINITY, f64::min)
            / w;
        let nj = pred_j
            .iter()
            .map(|&p| d(norm.vertices[p].pos, tp))
            .fold(f64::INFINITY, f64::min)
            / w;
        let (len, other) = truth
            .edges
            .iter()
            .find(|e| e.from == t || e.to == t)
            .map_or((0.0, 0), |e| {
                let len: f64 = e.points.windows(2).map(|s| d(s[0], s[1])).sum();
                let o = if e.from == t { e.to } else { e.from };
                (len / w, truth.vertices[o].degree)
            });
        let pe = norm
            .edges
            .iter()
            .flat_map(|e| e.points.windows(2))
            .map(|s| ridgeline::geometry::segment_dist(tp, s[0], s[1]))
            .fold(f64::INFINITY, f64::min)
            / w;
        // Along the truth's end direction (outwards), how far the nearest predicted end lies
        // beyond the true end (w), and across.
        let (along, across) = truth
            .edges
            .iter()
            .find(|e| e.from == t || e.to == t)
            .and_then(|e| {
                let pts: Vec<[f64; 2]> = if e.from == t {
                    e.points.iter().rev().copied().collect()
                } else {
                    e.points.clone()
                };
                let back = pts
                    .iter()
                    .rev()
                    .find(|&&q| d(q, tp) >= w)
                    .copied()
                    .unwrap_or(pts[0]);
                let u = [tp[0] - back[0], tp[1] - back[1]];
                let l = u[0].hypot(u[1]);
                if l == 0.0 {
                    return None;
                }
                let u = [u[0] / l, u[1] / l];
                let p = pred_e
                    .iter()
                    .map(|&p| norm.vertices[p].pos)
                    .min_by(|a, b| d(*a, tp).total_cmp(&d(*b, tp)))?;
                let v = [p[0] - tp[0], p[1] - tp[1]];
                Some((
                    (v[0] * u[0] + v[1] * u[1]) / w,
                    (v[0] * u[1] - v[1] * u[0]).abs() / w,
                ))
            })
            .unwrap_or((f64::NAN, f64::NAN));
        println!("MDUMP {} ({:.0},{:.0}) w {:.1} pred_end {:.2} pred_junction {:.2} pred_edge {:.2} tedge {:.2} to_deg {} along {:.2} across {:.2}",
            case.name, tp[0], tp[1], w, ne, nj, pe, len, other, along, across);
    }
}

fn dump_ends(case: &Case, truth: &StrokeGraph, graph: &StrokeGraph, options: &ScoreOptions) {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let norm = ridgeline_testkit::score::normalize_with(case, graph, options);
    let radius = |w: f64| w.max(options.min_match_radius);
    let true_e: Vec<usize> = truth.endpoints().collect();
    let pred_e: Vec<usize> = norm.endpoints().collect();
    let matched = |t: usize| {
        pred_e.iter().any(|&p| {
            d(norm.vertices[p].pos, truth.vertices[t].pos) <= radius(truth.vertices[t].width)
        })
    };
    let edge_dist = |p: [f64; 2]| {
        truth
            .edges
            .iter()
            .flat_map(|e| e.points.windows(2))
            .map(|s| ridgeline::geometry::segment_dist(p, s[0], s[1]))
            .fold(f64::INFINITY, f64::min)
    };
    for &p in &pred_e {
        let pos = norm.vertices[p].pos;
        if true_e
            .iter()
            .any(|&t| d(truth.vertices[t].pos, pos) <= radius(truth.vertices[t].width))
        {
            continue;
        }
        let Some(near) = (0..truth.vertices.len()).min_by(|&a, &b| {
            d(truth.vertices[a].pos, pos).total_cmp(&d(truth.vertices[b].pos, pos))
        }) else {
            continue;
        };
        let w = truth.vertices[near].width.max(1.0);
        let nearest_end = true_e.iter().copied().min_by(|&a, &b| {
            d(truth.vertices[a].pos, pos).total_cmp(&d(truth.vertices[b].pos, pos))
        });
        let (end_d, end_missed) = nearest_end.map_or((f64::INFINITY, false), |t| {
            (d(truth.vertices[t].pos, pos) / w, !matched(t))
        });
        let (len, other, other_j) = norm.edges.iter().find(|e| e.from == p || e.to == p).map_or(
            (0.0, 0, f64::INFINITY),
            |e| {
                let len: f64 = e.points.windows(2).map(|s| d(s[0], s[1])).sum();
                let o = if e.from == p { e.to } else { e.from };
                let to_junction = truth
                    .junctions()
                    .map(|t| d(truth.vertices[t].pos, norm.vertices[o].pos))
                    .fold(f64::INFINITY, f64::min);
                (len / w, norm.vertices[o].degree, to_junction / w)
            },
        );
        let off_truth = edge_dist(pos) / w;
        // The sharpest turn of the truth's centerline within 1.5 widths (degrees; 180 a pen
        // that goes back on itself): a spur at a retrace cusp lies beside one.
        let bend = truth
            .edges
            .iter()
            .flat_map(|e| e.points.windows(3))
            .filter(|s| d(s[1], pos) <= 1.5 * w)
            .map(|s| {
                let (a, b) = (
                    [s[1][0] - s[0][0], s[1][1] - s[0][1]],
                    [s[2][0] - s[1][0], s[2][1] - s[1][1]],
                );
                (a[0] * b[1] - a[1] * b[0])
                    .atan2(a[0] * b[0] + a[1] * b[1])
                    .abs()
                    .to_degrees()
            })
            .fold(0.0, f64::max);
        let class = if off_truth > 1.5 {
            if end_missed && end_d <= 4.5 {
                'A'
            } else {
                'B'
            }
        } else if end_missed && end_d <= 3.0 {
            'C'
        } else if other >= 3 && len <= 3.0 {
            if other_j > 1.5 {
                'D'
            } else {
                'E'
            }
        } else if other >= 3 {
            'F'
        } else {
            'G'
        };
        println!(
            "EDUMP {} {class} ({:.0},{:.0}) w {:.1} true_end {:.1}{} truth_edge {:.2} edge {:.1} \
             to_deg {} true_junction {:.1} bend {:.0}",
            case.name,
            pos[0],
            pos[1],
            w,
            end_d,
            if end_missed { " missed" } else { " found" },
            off_truth,
            len,
            other,
            other_j,
            bend
        );
        // QUALITY_DUMP_ENDS=points: the case's stroke vertices within four widths of the end.
        if std::env::var("QUALITY_DUMP_ENDS").is_ok_and(|v| v == "points") {
            for (k, stroke) in case.strokes.iter().enumerate() {
                let near: Vec<String> = stroke
                    .points
                    .iter()
                    .filter(|&&q| d(q, pos) <= 4.0 * w)
                    .map(|q| format!("({:.1},{:.1})", q[0], q[1]))
                    .collect();
                if !near.is_empty() {
                    println!("  stroke {k}: {}", near.join(" "));
                }
            }
        }
    }
}

/// With `QUALITY_DUMP_JUNCTIONS` set: a line per extra junction of the case (ridgeline; a
/// predicted junction the scorer matches to no true junction), with, in widths of the nearest
/// true vertex: the nearest true junction's distance and whether another predicted junction is
/// matched to it, the nearest true end's distance, the distance to the truth's nearest edge, the
/// junction's shortest edge and what is at its other end, and a class letter: S a spur's
/// junction (an edge of at most 3 widths to a spurious end), P a split (the nearest true junction,
/// within 3 widths, matched to another predicted junction), N placed off (an unmatched true
/// junction within 3 widths), O off the truth (its nearest edge more than 1.5 widths away), T a
/// true end within 3 widths (a touch or an overhang where the truth has an end), R the rest (on
/// a true stroke away from every true vertex) (docs/quality.md, "Spurious ends and extra
/// junctions on script (issue 31)").
fn dump_junctions(case: &Case, truth: &StrokeGraph, graph: &StrokeGraph, options: &ScoreOptions) {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let norm = ridgeline_testkit::score::normalize_with(case, graph, options);
    let radius = |w: f64| w.max(options.min_match_radius);
    let true_j: Vec<usize> = truth.junctions().collect();
    let pred_j: Vec<usize> = norm.junctions().collect();
    let partner = ridgeline_testkit::score::match_vertices(truth, &true_j, &norm, &pred_j, &radius);
    let true_e: Vec<usize> = truth.endpoints().collect();
    let spurious = |v: usize| {
        norm.vertices[v].degree == 1
            && !true_e.iter().any(|&t| {
                d(truth.vertices[t].pos, norm.vertices[v].pos) <= radius(truth.vertices[t].width)
            })
    };
    let edge_dist = |p: [f64; 2]| {
        truth
            .edges
            .iter()
            .flat_map(|e| e.points.windows(2))
            .map(|s| ridgeline::geometry::segment_dist(p, s[0], s[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let nearest = |ids: &[usize], pos: [f64; 2]| {
        ids.iter().copied().enumerate().min_by(|a, b| {
            d(truth.vertices[a.1].pos, pos).total_cmp(&d(truth.vertices[b.1].pos, pos))
        })
    };
    for &p in &pred_j {
        if partner.contains(&Some(p)) {
            continue;
        }
        let pos = norm.vertices[p].pos;
        let Some(near) = (0..truth.vertices.len()).min_by(|&a, &b| {
            d(truth.vertices[a].pos, pos).total_cmp(&d(truth.vertices[b].pos, pos))
        }) else {
            continue;
        };
        let w = truth.vertices[near].width.max(1.0);
        let (tj_d, tj_taken, tj_deg) =
            nearest(&true_j, pos).map_or((f64::INFINITY, false, 0), |(k, t)| {
                (
                    d(truth.vertices[t].pos, pos) / w,
                    partner[k].is_some(),
                    truth.vertices[t].degree,
                )
            });
        let te_d =
            nearest(&true_e, pos).map_or(f64::INFINITY, |(_, t)| d(truth.vertices[t].pos, pos) / w);
        let off_truth = edge_dist(pos) / w;
        // The junction's edges: length in widths and the degree (spurious end: 's') at the far end.
        let mut edges: Vec<(f64, String, bool)> = norm
            .edges
            .iter()
            .filter(|e| e.from == p || e.to == p)
            .map(|e| {
                let len: f64 = e.points.windows(2).map(|s| d(s[0], s[1])).sum::<f64>() / w;
                let o = if e.from == p { e.to } else { e.from };
                let spur = spurious(o);
                let tag = format!(
                    "{:.1}:d{}{}",
                    len,
                    norm.vertices[o].degree,
                    if spur { "s" } else { "" }
                );
                (len, tag, spur)
            })
            .collect();
        edges.sort_by(|a, b| a.0.total_cmp(&b.0));
        let class = if edges.iter().any(|e| e.2 && e.0 <= 3.0) {
            'S'
        } else if tj_d <= 3.0 && tj_taken {
            'P'
        } else if tj_d <= 3.0 {
            'N'
        } else if off_truth > 1.5 {
            'O'
        } else if te_d <= 3.0 {
            'T'
        } else {
            'R'
        };
        println!(
            "JDUMP {} {class} ({:.0},{:.0}) deg {} w {:.1} true_junction {:.1}{} d{} true_end {:.1} \
             truth_edge {:.2} edges [{}]",
            case.name,
            pos[0],
            pos[1],
            norm.vertices[p].degree,
            w,
            tj_d,
            if tj_taken { " taken" } else { " free" },
            tj_deg,
            te_d,
            off_truth,
            edges.iter().map(|e| e.1.as_str()).collect::<Vec<_>>().join(" ")
        );
    }
}

/// With `QUALITY_DUMP_CROSSINGS` set: a line per true crossing of the case (ridgeline), right or
/// missed, with the predicted and true junctions within four widths of it (degree and distance in
/// widths) and a line naming the case (docs/quality.md, "Where script loses crossings").
fn dump_crossings(
    name: &str,
    truth: &StrokeGraph,
    graph: &StrokeGraph,
    sc: &ridgeline_testkit::score::Scores,
) {
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    println!("XCASE {name}");
    for c in &sc.crossings {
        let t = truth
            .vertices
            .iter()
            .min_by(|a, b| d(a.pos, c.pos).total_cmp(&d(b.pos, c.pos)))
            .unwrap();
        let w = t.width.max(3.0);
        // The junctions of `g` within four widths, farther than `beyond` (the truth's own
        // crossing left out), as degree@distance in widths.
        let near = |g: &StrokeGraph, beyond: f64| -> Vec<String> {
            g.junctions()
                .map(|v| (g.vertices[v].degree, d(g.vertices[v].pos, c.pos)))
                .filter(|&(_, dist)| dist > beyond && dist <= 4.0 * w)
                .map(|(degree, dist)| format!("d{degree}@{:.1}", dist / t.width))
                .collect()
        };
        let near_p = near(graph, f64::NEG_INFINITY);
        let near_t = near(truth, 0.1);
        println!(
            "XDUMP {name} ({:.0},{:.0}) ang {:.0} w {:.1} {} pred [{}] truth [{}]",
            c.pos[0],
            c.pos[1],
            c.angle,
            t.width,
            if c.correct { "OK" } else { "MISS" },
            near_p.join(" "),
            near_t.join(" ")
        );
    }
}
