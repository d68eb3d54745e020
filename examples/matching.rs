//! Matching benchmark (docs/fingerprints.md, "Matching benchmark"): ridgeline's minutiae judged by
//! a real matcher on real prints, beside NIST's mindtct on the same prints.
//!
//! ```sh
//! cargo build --release -p ridgeline-cli
//! cargo run --release --example matching [-- --ridgeline BIN] [--nbis DIR] [--work DIR] [DB ...]
//! ```
//!
//! The protocol is the one of `../shared/bench/fvc/fvc_eer.py` (FVC's): every print of each
//! database (`DB`, default every folder under `../shared/data/fvc2002`, prints named
//! `FINGER_IMPRESSION.png`) is written as `.xyt` by `BIN --fingerprint -q -j 1 PRINT -o OUT.xyt`
//! (default `target/release/ridgeline`: one process per print, as a user runs it) and by
//! mindtct; every genuine pair (two impressions of one finger) and impostor pair (prints of two
//! fingers) is scored by Bozorth3 with its defaults. Printed per database and extractor:
//! minutiae per print, EER (as FVC2000 defines it), FMR100 and FMR1000 (the lowest FNMR with FMR
//! at most 1 % and 0.1 %), seconds per print, and the angle agreement with mindtct: every
//! ridgeline minutia paired with a mindtct minutia within 8 px (closest pairs first, each minutia
//! in at most one pair), the median angle difference over the pairs whose mindtct minutia is an
//! ending and over those whose is a bifurcation (with the number of pairs).
//!
//! mindtct and Bozorth3 come from `--nbis DIR` (`mindtct_pgm`, `bozorth3`), else they are built
//! from NIST's sources with `../shared/bench/fvc/build.sh` into a temporary folder (needs gcc).
//! Without `../shared/data/fvc2002` (a clean clone) it says so and does nothing.

use std::collections::HashMap;
use std::error::Error;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// Farthest apart, px, a ridgeline and a mindtct minutia may be to be compared.
const PAIR_DISTANCE: f64 = 8.0;

/// One minutia of an `.xyt` file: x, y (y up), theta in degrees, and whether mindtct's `.min`
/// calls it a bifurcation (`None` for ridgeline's, whose `.xyt` has no kind).
#[derive(Clone, Copy)]
struct Xyt {
    x: f64,
    y: f64,
    theta: f64,
    bifurcation: Option<bool>,
}

/// What one extractor did on one database.
#[derive(Default)]
struct Run {
    seconds: f64,
    templates: HashMap<String, PathBuf>,
    minutiae: usize,
    failed: usize,
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let shared = root.join("../shared");
    let value = |flag: &str| args.windows(2).find(|w| w[0] == flag).map(|w| w[1].clone());
    let tool = value("--ridgeline")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/release/ridgeline"));
    let mut dbs: Vec<PathBuf> = Vec::new();
    let mut skip = false;
    for a in &args {
        if skip {
            skip = false;
        } else if a.starts_with("--") {
            skip = true;
        } else {
            dbs.push(PathBuf::from(a));
        }
    }
    if dbs.is_empty() {
        let data = shared.join("data/fvc2002");
        if !data.is_dir() {
            println!("no {}: nothing to measure", data.display());
            return Ok(());
        }
        dbs = fs::read_dir(&data)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .collect();
        dbs.sort();
    }
    if !tool.exists() {
        return Err(format!(
            "no {}: build it with `cargo build --release -p ridgeline-cli` or name one with --ridgeline",
            tool.display()
        )
        .into());
    }
    let built = tempfile::tempdir()?;
    let nbis = match value("--nbis") {
        Some(dir) => PathBuf::from(dir),
        None => {
            let script = shared.join("bench/fvc/build.sh");
            let status = Command::new("bash")
                .arg(&script)
                .arg(built.path())
                .status()
                .map_err(|e| format!("{}: {e}", script.display()))?;
            if !status.success() {
                return Err(format!("{} failed", script.display()).into());
            }
            built.path().to_path_buf()
        }
    };
    let (mindtct, bozorth3) = (nbis.join("mindtct_pgm"), nbis.join("bozorth3"));
    let scratch = tempfile::tempdir()?;
    let work = value("--work")
        .map(PathBuf::from)
        .unwrap_or_else(|| scratch.path().to_path_buf());
    println!("ridgeline: {}", tool.display());
    println!();
    println!("| database | extractor | minutiae/print | EER % | FMR100 % | FMR1000 % | s/print | ending Δθ° (pairs) | bifurcation Δθ° (pairs) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for db in &dbs {
        let name = db
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let dir = work.join(&name);
        fs::create_dir_all(&dir)?;
        let mut prints: Vec<PathBuf> = fs::read_dir(db)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                let ext = p.extension().map(|e| e.to_string_lossy().to_lowercase());
                matches!(
                    ext.as_deref(),
                    Some("png" | "tif" | "tiff" | "bmp" | "jpg" | "pgm")
                )
            })
            .collect();
        prints.sort();
        let (mut peer, mut ours) = (Run::default(), Run::default());
        let mut agreement: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        for print in &prints {
            let stem = print
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            // mindtct reads an 8-bit PGM.
            let gray = image::open(print)?.to_luma8();
            let pgm = dir.join(format!("{stem}.pgm"));
            let mut bytes = format!("P5\n{} {}\n255\n", gray.width(), gray.height()).into_bytes();
            bytes.extend_from_slice(gray.as_raw());
            fs::write(&pgm, bytes)?;
            let out_root = dir.join(format!("{stem}.mt"));
            let start = Instant::now();
            let status = Command::new(&mindtct).arg(&pgm).arg(&out_root).status()?;
            peer.seconds += start.elapsed().as_secs_f64();
            let peer_xyt = dir.join(format!("{stem}.mt.xyt"));
            if !status.success() || !peer_xyt.exists() {
                fs::write(&peer_xyt, "")?;
                peer.failed += 1;
            }
            let mut theirs = read_xyt(&peer_xyt)?;
            mark_kinds(&mut theirs, &dir.join(format!("{stem}.mt.min")));
            for ext in ["dm", "hcm", "lcm", "lfm", "qm", "brw", "min"] {
                let _ = fs::remove_file(dir.join(format!("{stem}.mt.{ext}")));
            }
            let _ = fs::remove_file(&pgm);
            let tool_xyt = dir.join(format!("{stem}.tool.xyt"));
            let _ = fs::remove_file(&tool_xyt);
            let start = Instant::now();
            let output = Command::new(&tool)
                .args(["--fingerprint", "-q", "-j", "1"])
                .arg(print)
                .arg("-o")
                .arg(&tool_xyt)
                .output()?;
            ours.seconds += start.elapsed().as_secs_f64();
            if !output.status.success() || !tool_xyt.exists() {
                // A failed print matches nothing.
                fs::write(&tool_xyt, "")?;
                ours.failed += 1;
                eprintln!(
                    "{name}/{stem}: ridgeline failed: {}",
                    String::from_utf8_lossy(&output.stderr).trim()
                );
            }
            let mine = read_xyt(&tool_xyt)?;
            peer.minutiae += theirs.len();
            ours.minutiae += mine.len();
            for (difference, bifurcation) in paired_angle_differences(&mine, &theirs) {
                agreement[usize::from(bifurcation)].push(difference);
            }
            peer.templates.insert(stem.clone(), peer_xyt);
            ours.templates.insert(stem, tool_xyt);
        }
        let stems: Vec<String> = prints
            .iter()
            .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
            .collect();
        let finger = |s: &str| s.split('_').next().unwrap_or("").to_string();
        let (mut genuine, mut impostor) = (Vec::new(), Vec::new());
        for (i, a) in stems.iter().enumerate() {
            for b in &stems[i + 1..] {
                if finger(a) == finger(b) {
                    genuine.push((a.clone(), b.clone()));
                } else {
                    impostor.push((a.clone(), b.clone()));
                }
            }
        }
        let n = prints.len().max(1) as f64;
        for (label, run) in [("mindtct", &peer), ("ridgeline", &ours)] {
            let pairs = |list: &[(String, String)]| -> Vec<(PathBuf, PathBuf)> {
                list.iter()
                    .map(|(a, b)| (run.templates[a].clone(), run.templates[b].clone()))
                    .collect()
            };
            let g = bozorth(&bozorth3, &pairs(&genuine), &dir, &format!("{label}.gen"))?;
            let i = bozorth(&bozorth3, &pairs(&impostor), &dir, &format!("{label}.imp"))?;
            let angles = if label == "ridgeline" {
                let cell = |v: &mut Vec<f64>| match median(v) {
                    Some(m) => format!("{m:.0} ({})", v.len()),
                    None => "—".to_string(),
                };
                let [e, b] = &mut agreement;
                (cell(e), cell(b))
            } else {
                ("".to_string(), "".to_string())
            };
            let failed = if run.failed > 0 {
                format!(" ({} failed)", run.failed)
            } else {
                String::new()
            };
            println!(
                "| {name} | {label}{failed} | {:.1} | {:.2} | {:.2} | {:.2} | {:.3} | {} | {} |",
                run.minutiae as f64 / n,
                100.0 * eer(&g, &i),
                100.0 * fnmr_at(&g, &i, 0.01),
                100.0 * fnmr_at(&g, &i, 0.001),
                run.seconds / n,
                angles.0,
                angles.1
            );
        }
    }
    println!();
    println!(
        "Δθ: median angle difference, ridgeline against mindtct, of minutiae within {PAIR_DISTANCE} px, by mindtct's kind."
    );
    Ok(())
}

/// The minutiae of an `.xyt` file (`x y theta quality` per line).
fn read_xyt(path: &Path) -> Result<Vec<Xyt>> {
    let text = fs::read_to_string(path)?;
    let mut found = Vec::new();
    for line in text.lines() {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| format!("{}: {line:?}: {e}", path.display()))?;
        if let [x, y, theta, ..] = v[..] {
            found.push(Xyt {
                x,
                y,
                theta,
                bifurcation: None,
            });
        }
    }
    Ok(found)
}

/// Marks each of mindtct's minutiae with its kind from its `.min` file, whose minutia lines,
/// in the `.xyt`'s order, name the kind `RIG` (ending) or `BIF` (bifurcation) between colons.
fn mark_kinds(minutiae: &mut [Xyt], min_file: &Path) {
    let Ok(text) = fs::read_to_string(min_file) else {
        return;
    };
    let kinds = text.lines().filter_map(|line| {
        line.split(':').map(str::trim).find_map(|f| match f {
            "RIG" => Some(false),
            "BIF" => Some(true),
            _ => None,
        })
    });
    for (m, bifurcation) in minutiae.iter_mut().zip(kinds) {
        m.bifurcation = Some(bifurcation);
    }
}

/// Angle differences, degrees in `[0, 180]`, of `ours` paired with `theirs` within
/// [`PAIR_DISTANCE`], closest pairs first, each minutia in at most one pair; with whether
/// mindtct's minutia of the pair is a bifurcation.
fn paired_angle_differences(ours: &[Xyt], theirs: &[Xyt]) -> Vec<(f64, bool)> {
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (i, a) in ours.iter().enumerate() {
        for (j, b) in theirs.iter().enumerate() {
            let d = (a.x - b.x).hypot(a.y - b.y);
            if d <= PAIR_DISTANCE && b.bifurcation.is_some() {
                candidates.push((d, i, j));
            }
        }
    }
    candidates.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)).then(p.2.cmp(&q.2)));
    let (mut used_ours, mut used_theirs) = (vec![false; ours.len()], vec![false; theirs.len()]);
    let mut found = Vec::new();
    for (_, i, j) in candidates {
        if used_ours[i] || used_theirs[j] {
            continue;
        }
        used_ours[i] = true;
        used_theirs[j] = true;
        let d = (ours[i].theta - theirs[j].theta).rem_euclid(360.0);
        found.push((d.min(360.0 - d), theirs[j].bifurcation == Some(true)));
    }
    found
}

fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    Some(if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    })
}

/// Bozorth3's score of each pair of templates, in order.
fn bozorth(
    bozorth3: &Path,
    pairs: &[(PathBuf, PathBuf)],
    dir: &Path,
    tag: &str,
) -> Result<Vec<f64>> {
    let list = dir.join(format!("{tag}.lis"));
    let scores = dir.join(format!("{tag}.scores"));
    let mut text = String::new();
    for (a, b) in pairs {
        text.push_str(&format!("{}\n{}\n", a.display(), b.display()));
    }
    fs::write(&list, text)?;
    let status = Command::new(bozorth3)
        .args(["-A", "outfmt=spg", "-A", "maxfiles=1000000", "-o"])
        .arg(&scores)
        .arg("-M")
        .arg(&list)
        .status()?;
    if !status.success() {
        return Err(format!("bozorth3 failed on {}", list.display()).into());
    }
    let mut by_pair: HashMap<(String, String), f64> = HashMap::new();
    for line in fs::read_to_string(&scores)?.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if let [s, p, g] = f[..] {
            by_pair.insert((p.to_string(), g.to_string()), s.parse()?);
        }
    }
    pairs
        .iter()
        .map(|(a, b)| {
            by_pair
                .get(&(a.display().to_string(), b.display().to_string()))
                .copied()
                .ok_or_else(|| format!("no score for {} {}", a.display(), b.display()).into())
        })
        .collect()
}

/// FMR and FNMR at every distinct score taken as the threshold (and one above all).
fn rates(genuine: &[f64], impostor: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut thresholds: Vec<f64> = genuine.iter().chain(impostor).copied().collect();
    let top = thresholds.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    thresholds.push(top + 1.0);
    thresholds.sort_by(f64::total_cmp);
    thresholds.dedup();
    let share = |v: &[f64], f: &dyn Fn(f64) -> bool| {
        v.iter().filter(|&&s| f(s)).count() as f64 / v.len().max(1) as f64
    };
    let fmr = thresholds
        .iter()
        .map(|&t| share(impostor, &|s| s >= t))
        .collect();
    let fnmr = thresholds
        .iter()
        .map(|&t| share(genuine, &|s| s < t))
        .collect();
    (fmr, fnmr)
}

/// Equal error rate as FVC2000 defines it (the script's `eer`).
fn eer(genuine: &[f64], impostor: &[f64]) -> f64 {
    let (fmr, fnmr) = rates(genuine, impostor);
    let i1 = (0..fmr.len())
        .filter(|&i| fnmr[i] <= fmr[i])
        .max()
        .unwrap_or(0);
    let i2 = (0..fmr.len())
        .filter(|&i| fnmr[i] >= fmr[i])
        .min()
        .unwrap_or(0);
    let (lo, hi) = if fnmr[i1] + fmr[i1] <= fnmr[i2] + fmr[i2] {
        (fnmr[i1], fmr[i1])
    } else {
        (fmr[i2], fnmr[i2])
    };
    (lo + hi) / 2.0
}

/// The lowest FNMR with FMR at most `target`.
fn fnmr_at(genuine: &[f64], impostor: &[f64], target: f64) -> f64 {
    let (fmr, fnmr) = rates(genuine, impostor);
    (0..fmr.len())
        .filter(|&i| fmr[i] <= target)
        .map(|i| fnmr[i])
        .fold(1.0, f64::min)
}
