//! The quality benchmark (issue 3): every generated case with known centerlines is traced by
//! ridgeline, by ridgeline with the paper's own parameters, and by a Zhang-Suen thinning baseline,
//! then scored against the truth as the ink shows it (`ridgeline::score`). Prints a table per group
//! and writes everything as JSON.
//!
//! ```text
//! cargo run --release --example quality [-- --json PATH] [--group hard|text|prints] [--case NAME] [--verbose]
//! ```
//!
//! When `../shared/data` (beside the crate root) holds real fingerprints and text, ridgeline also
//! runs on them (no truth): time, counts, and endpoint / junction / short-branch rates.
//!
//! Issue 6 columns: `IoU` is the intersection over union of the strokes re-rendered with their
//! widths and the input foreground (`ridgeline::strokes::coverage_iou`; goal >= 0.9 on text), and
//! the real fingerprints get their minutiae counts (`ridgeline::minutiae`, endings and
//! bifurcations away from the print's border).

mod thinning;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context};
use ridgeline::minutiae::{minutiae, MinutiaKind, MinutiaeOptions};
use ridgeline::score::{aggregate, score, truth_graph, GroupScores, Scores};
use ridgeline::strokes::coverage_iou;
use ridgeline::synth::Case;
use ridgeline::{Limits, Params, StrokeGraph};
use serde::Serialize;

/// Command-line arguments.
struct Args {
    json: PathBuf,
    group: Option<String>,
    case: Option<String>,
    verbose: bool,
}

fn parse_args() -> anyhow::Result<Args> {
    let mut args = Args {
        json: Path::new(env!("CARGO_MANIFEST_DIR")).join("target/quality.json"),
        group: None,
        case: None,
        verbose: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().with_context(|| format!("{arg} needs a value"));
        match arg.as_str() {
            "--json" => args.json = PathBuf::from(value()?),
            "--group" => args.group = Some(value()?),
            "--case" => args.case = Some(value()?),
            "--verbose" | "-v" => args.verbose = true,
            "--help" | "-h" => {
                println!(
                    "usage: quality [--json PATH] [--group hard|text|prints] [--case NAME] [--verbose]"
                );
                std::process::exit(0);
            }
            other => bail!("unknown argument {other:?} (try --help)"),
        }
    }
    Ok(args)
}

/// The methods compared in every table.
const METHODS: [&str; 3] = ["ridgeline", "paper", "thinning"];

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

/// The methods to run: all of [`METHODS`], or those named in `QUALITY_METHODS` (comma-separated).
fn methods() -> Vec<&'static str> {
    match std::env::var("QUALITY_METHODS") {
        Ok(list) => METHODS
            .into_iter()
            .filter(|m| list.split(',').any(|x| x.trim() == *m))
            .collect(),
        Err(_) => METHODS.to_vec(),
    }
}

fn run_method(method: &str, case: &Case) -> anyhow::Result<StrokeGraph> {
    Ok(match method {
        "ridgeline" => ridgeline::trace_binary(&case.binary, &variant_params()?)?.graph,
        "paper" => ridgeline::trace_binary(&case.binary, &Params::paper())?.graph,
        _ => thinning::trace(&case.binary),
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
    /// Re-rendered widths against the input foreground (issue 6).
    iou: Option<f64>,
}

/// One method on one group.
#[derive(Serialize)]
struct GroupRow {
    group: String,
    method: String,
    failures: usize,
    mean_time_ms: f64,
    scores: GroupScores,
    /// Mean of the cases' IoU (issue 6); `None` when no case was traced.
    mean_iou: Option<f64>,
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
    /// Re-rendered widths against the binarized foreground (issue 6).
    iou: f64,
    /// Ridge endings and bifurcations (fingerprints only).
    endings: Option<usize>,
    bifurcations: Option<usize>,
}

#[derive(Serialize)]
struct Report {
    groups: Vec<GroupRow>,
    cases: Vec<Outcome>,
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

    let cases: Vec<Case> = ridgeline::synth::all_cases()
        .into_iter()
        .filter(|c| args.group.as_ref().is_none_or(|g| &c.group == g))
        .filter(|c| args.case.as_ref().is_none_or(|n| &c.name == n))
        .collect();
    if cases.is_empty() {
        bail!("no case matches the filters");
    }

    let mut outcomes = Vec::new();
    for case in &cases {
        let truth = guarded(|| Ok(truth_graph(case)));
        for method in methods() {
            let start = Instant::now();
            let result = guarded(|| run_method(method, case));
            let time_ms = start.elapsed().as_secs_f64() * 1e3;
            let iou = result
                .as_ref()
                .ok()
                .map(|graph| coverage_iou(graph, &case.binary));
            let (failure, scores) = match (&truth, result) {
                (Ok(truth), Ok(graph)) => match guarded(|| Ok(score(case, truth, &graph))) {
                    Ok(s) => (None, Some(s)),
                    Err(e) => (Some(format!("scoring: {e}")), None),
                },
                (Err(e), _) => (Some(format!("truth: {e}")), None),
                (_, Err(e)) => (Some(e), None),
            };
            outcomes.push(Outcome {
                case: case.name.clone(),
                group: case.group.clone(),
                method: method.to_string(),
                time_ms,
                failure,
                scores,
                iou,
            });
        }
    }

    let mut groups: Vec<String> = Vec::new();
    for case in &cases {
        if !groups.contains(&case.group) {
            groups.push(case.group.clone());
        }
    }
    let mut rows = Vec::new();
    for group in &groups {
        for method in methods() {
            let mine: Vec<&Outcome> = outcomes
                .iter()
                .filter(|o| &o.group == group && o.method == method)
                .collect();
            let scores: Vec<Scores> = mine.iter().filter_map(|o| o.scores.clone()).collect();
            rows.push(GroupRow {
                group: group.clone(),
                method: method.to_string(),
                failures: mine.iter().filter(|o| o.failure.is_some()).count(),
                mean_time_ms: mine.iter().map(|o| o.time_ms).sum::<f64>()
                    / mine.len().max(1) as f64,
                scores: aggregate(&scores),
                mean_iou: {
                    let ious: Vec<f64> = mine.iter().filter_map(|o| o.iou).collect();
                    (!ious.is_empty()).then(|| ious.iter().sum::<f64>() / ious.len() as f64)
                },
            });
        }
    }

    for group in &groups {
        let count = cases.iter().filter(|c| &c.group == group).count();
        println!("\n## {group} ({count} cases)\n");
        print_table(rows.iter().filter(|r| &r.group == group));
        if args.verbose {
            print_cases(outcomes.iter().filter(|o| &o.group == group));
        }
    }
    let failures: Vec<&Outcome> = outcomes.iter().filter(|o| o.failure.is_some()).collect();
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

    let real_images = if std::env::var_os("QUALITY_NO_REAL").is_some() {
        Vec::new()
    } else {
        real_images(args.verbose)
    };

    let report = Report {
        groups: rows,
        cases: outcomes,
        real_images,
    };
    if let Some(dir) = args.json.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let json = serde_json::to_string_pretty(&report)?;
    std::fs::write(&args.json, json).with_context(|| format!("writing {}", args.json.display()))?;
    println!("\nwrote {}", args.json.display());
    Ok(())
}

fn opt(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| format!("{v:.3}"))
}

fn print_table<'a>(rows: impl Iterator<Item = &'a GroupRow>) {
    println!(
        "| method | F1@1 | F1@2 | chamfer | Hausdorff | junction P | junction R | X >=30° | X 15° | spurs/stroke | endpoint R | components exact | cycles exact | IoU | ms | failed |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let s = &r.scores;
        if s.cases == 0 {
            println!(
                "| {} | - | - | - | - | - | - | - | - | - | - | - | - | {} | {:.1} | {} |",
                r.method,
                opt(r.mean_iou),
                r.mean_time_ms,
                r.failures
            );
            continue;
        }
        println!(
            "| {} | {:.3} | {:.3} | {:.2} | {:.1} | {:.2} | {:.2} | {} | {} | {:.3} | {:.2} | {:.0}% | {:.0}% | {} | {:.1} | {} |",
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
            opt(r.mean_iou),
            r.mean_time_ms,
            r.failures,
        );
    }
}

fn print_cases<'a>(outcomes: impl Iterator<Item = &'a Outcome>) {
    println!("\n| case | method | F1@1 | F1@2 | Hausdorff | junctions P/R | crossings | spurs | endpoints | comp | cyc | IoU | ms |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
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
            "| {} | {} | {:.3} | {:.3} | {:.1} | {}/{}/{} | {}/{} | {} | {}/{} | {}/{} | {}/{} | {} | {:.1} |",
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
                let trace = ridgeline::trace_image(&gray, &Params::default())?;
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
