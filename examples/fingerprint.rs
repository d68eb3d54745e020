//! The fingerprint benchmark (docs/fingerprints.md): minutiae of the fingerprint front end
//! (`Params::fingerprint`) on the test kit's dense synthetic prints (`dense_print_cases`: about
//! 30 minutiae each, as on a real capture), clean and degraded (blur, noise, a contrast map,
//! creases, ridge breaks, pores, a partial print, all at once), scored against the minutiae of
//! their true ridges, and counts, median ridge periods and times on real prints; with `--peer`, the classical peer
//! (`../shared/bench/peer_minutiae.py`, pyfing) on the same images; with `--pictures`, a picture
//! of each synthetic image's minutiae against the truth and of the front end's stages, beside the
//! images in the temporary folder `ridgeline-fingerprint-bench`.
//!
//! ```text
//! cargo run --release --example fingerprint [-- --peer] [--pictures] [--errors] [--real DIR] [--enhance smoothing]
//! ```
//!
//! Truth: the ends of the true ridge polylines but those cut by the finger's outline
//! (`finger_area`) and, on a partial print, those beyond the cut; an end that touches another
//! ridge (within its width) is a bifurcation, else an ending. A true minutia within 16 px of the
//! outline or the cut is optional (the print's border band, where a detector's mask margin may
//! drop it or it may be found): a detection matched to it counts neither way. Scoring: one-to-one
//! matching, nearest pairs first, within 8 px and 16 px: precision, recall, F1, and the share of
//! matched pairs of the same kind. Off ink: the share of the traced centerlines' length on
//! pixels that are not ridge in the enhanced binary, per capture and per real print.
//! `--errors` prints every false and missed minutia and every true one found with the wrong type;
//! `--pictures` draws each capture's minutiae over the true ridges (light blue) and the traced
//! ones (dark red).

use ridgeline::draw::Stroke;
use ridgeline::minutiae::{Minutia, MinutiaKind};
use ridgeline::{GrayImage, Params};
use ridgeline_testkit::synth::{
    dense_print_cases, finger_area, Case, SplitMix64, DENSE_PRINT_SIZE,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The width of the print's border band, px: a true minutia nearer than this to the finger's
/// outline or to a partial print's cut is optional in the scoring. Twice the 8 px tolerance: a
/// detector may drop minutiae there (its mask's margin) or find them, and neither is wrong.
const BORDER_BAND: f64 = 16.0;

/// The ridge period the peer is made for, px: the middle, on a log scale, of the 5-16 px periods
/// of pyfing's Gabor bank (about 500 ppi). Each real print is also given to the peer at whichever
/// of 2x, 1x and 1/2x brings its median period closest to this.
const PEER_PERIOD: f64 = 8.94;

/// The scales a print is offered to the peer at.
const PEER_SCALES: [f64; 3] = [2.0, 1.0, 0.5];

#[derive(Clone, Copy, Debug, PartialEq)]
struct Point {
    pos: [f64; 2],
    bifurcation: bool,
    /// A true minutia in the print's border band (see the module doc): a detection matched to
    /// it is neither right nor wrong, and missing it is no miss.
    optional: bool,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let peer = args.iter().any(|a| a == "--peer");
    // Pictures of every synthetic image's minutiae against the truth, in the work folder.
    let pictures = args.iter().any(|a| a == "--pictures");
    // Each synthetic image's false and missed minutiae within 8 px, listed.
    let errors = args.iter().any(|a| a == "--errors");
    let real = args
        .windows(2)
        .find(|w| w[0] == "--real")
        .map(|w| PathBuf::from(&w[1]))
        .unwrap_or_else(|| PathBuf::from("../shared/data/fingerprints"));
    let work = std::env::temp_dir().join("ridgeline-fingerprint-bench");
    std::fs::create_dir_all(&work)?;
    // `--enhance smoothing` measures oriented smoothing in place of the Gabor filter.
    let mut params = Params::fingerprint();
    if let Some(method) = args.windows(2).find(|w| w[0] == "--enhance").map(|w| &w[1]) {
        let print = params.fingerprint.as_mut().expect("the preset has one");
        print.enhancement = serde_json::from_value(serde_json::Value::String(method.clone()))
            .map_err(|_| format!("--enhance {method}: expected gabor or smoothing"))?;
    }

    // Synthetic prints with a real print's minutia density, clean and degraded.
    let variants = [
        "clean", "blur", "noise", "contrast", "creases", "breaks", "pores", "partial", "all",
    ];
    let cases = dense_print_cases();
    let mut images: Vec<(String, String, GrayImage, Vec<Point>)> = Vec::new();
    for (index, case) in cases.iter().enumerate() {
        let truth = truth_of(&case.strokes, case.binary.width);
        for (v, variant) in variants.iter().enumerate() {
            let (gray, cut) = capture(case, variant, 0xF1A6 + (index * 16 + v) as u64);
            // A partial print has fewer true minutiae: those on the captured side of the cut.
            let truth: Vec<Point> = truth
                .iter()
                .filter_map(|p| {
                    let depth = cut.map_or(f64::INFINITY, |c| c.depth(p.pos));
                    (depth >= 0.0).then_some(Point {
                        optional: p.optional || depth < BORDER_BAND,
                        ..*p
                    })
                })
                .collect();
            images.push((variant.to_string(), case.name.clone(), gray, truth));
        }
    }
    let mut paths = Vec::new();
    for (variant, name, gray, _) in &images {
        let path = work.join(format!("{name}_{variant}.png"));
        gray.save(&path)?;
        paths.push(path);
    }
    let peer_found = if peer {
        run_peer(&paths, &work.join("peer.json"))
    } else {
        None
    };
    let mut rows: BTreeMap<(usize, String), [Score; 4]> = BTreeMap::new();
    // Per capture: traced centerline length off the enhanced ridges, and in all, px.
    let mut off_ink: BTreeMap<usize, [f64; 2]> = BTreeMap::new();
    let mut seconds = [0.0f64; 2];
    for (k, (variant, _, gray, truth)) in images.iter().enumerate() {
        let clock = Instant::now();
        let trace = ridgeline::trace_image(gray, &params)?;
        seconds[0] += clock.elapsed().as_secs_f64();
        let ours: Vec<Point> = trace
            .fingerprint
            .as_ref()
            .map(|f| f.minutiae.iter().map(point_of).collect())
            .unwrap_or_default();
        let order = variants.iter().position(|v| v == variant).unwrap_or(0);
        let off = off_enhanced_ink(&trace);
        let share = off_ink.entry(order).or_default();
        share[0] += off[0];
        share[1] += off[1];
        let entry = rows.entry((order, variant.clone())).or_default();
        let matched = entry[0].add(&ours, truth, 8.0);
        entry[1].add(&ours, truth, 16.0);
        if errors {
            let report = |what: &str, p: &Point| {
                let kind = if p.bifurcation { "fork" } else { "end" };
                let [x, y] = p.pos;
                println!("{}: {what} {kind} at {x:.0},{y:.0}", paths[k].display());
            };
            for (i, f) in ours.iter().enumerate() {
                if !matched.iter().any(|m| m.0 == i) {
                    report("false", f);
                }
            }
            for (j, t) in truth.iter().enumerate() {
                if !t.optional && !matched.iter().any(|m| m.1 == j) {
                    report("missed", t);
                }
            }
            for &(i, j) in &matched {
                if !truth[j].optional && ours[i].bifurcation != truth[j].bifurcation {
                    report("wrong type, truth's", &truth[j]);
                }
            }
        }
        if pictures {
            let name = paths[k].with_extension("").to_string_lossy().into_owned();
            let ridges = &cases[k / variants.len()].strokes;
            picture(gray, &trace, ridges, &ours, truth, &matched)
                .save(format!("{name}-minutiae.png"))?;
            if let Some(print) = &trace.fingerprint {
                for (stage, image) in ridgeline::debug::print_pictures(gray, &print.analysis) {
                    image.save(format!("{name}-{}", &stage[2..]))?;
                }
            }
        }
        if let Some((found, time)) = peer_found.as_ref().and_then(|p| p.get(&paths[k])) {
            seconds[1] += time;
            entry[2].add(found, truth, 8.0);
            entry[3].add(found, truth, 16.0);
        }
    }
    println!(
        "Synthetic prints ({} cases x {} captures, {DENSE_PRINT_SIZE} x {DENSE_PRINT_SIZE} px)",
        cases.len(),
        variants.len()
    );
    println!();
    println!("| capture | truth | ridgeline P / R / F1 @8 | errors @8 | F1 @16 | type acc. | off ink | peer P / R / F1 @8 | peer errors @8 | peer F1 @16 | peer type acc. |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for ((order, variant), s) in &rows {
        let off = off_ink.get(order).copied().unwrap_or_default();
        let peer_cells = if peer_found.is_some() {
            format!(
                "{:.2} / {:.2} / {:.2} | {} | {:.2} | {:.2}",
                s[2].precision(),
                s[2].recall(),
                s[2].f1(),
                s[2].errors(),
                s[3].f1(),
                s[2].type_accuracy()
            )
        } else {
            "- | - | - | -".to_string()
        };
        println!(
            "| {variant} | {} | {:.2} / {:.2} / {:.2} | {} | {:.2} | {:.2} | {} | {peer_cells} |",
            s[0].truth,
            s[0].precision(),
            s[0].recall(),
            s[0].f1(),
            s[0].errors(),
            s[1].f1(),
            s[0].type_accuracy(),
            percent(off)
        );
    }
    println!();
    println!(
        "time over the {} synthetic images: ridgeline {:.2} s{}",
        images.len(),
        seconds[0],
        if peer_found.is_some() {
            format!(", peer {:.2} s", seconds[1])
        } else {
            String::new()
        }
    );

    // Real prints: counts and times.
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&real) {
        Ok(dir) => dir.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(_) => Vec::new(),
    };
    files.sort();
    if files.is_empty() {
        return Ok(());
    }
    let peer_real = if peer {
        run_peer(&files, &work.join("peer_real.json"))
    } else {
        None
    };
    println!();
    let mut rows = Vec::new();
    let mut rescaled = Vec::new();
    for file in &files {
        let bytes = std::fs::read(file)?;
        let gray = ridgeline::decode(&bytes, &params.front_end.limits)?;
        let clock = Instant::now();
        let trace = ridgeline::trace_image(&gray, &params)?;
        let time = clock.elapsed().as_secs_f64();
        let count = trace.fingerprint.as_ref().map_or(0, |f| f.minutiae.len());
        let off = percent(off_enhanced_ink(&trace));
        let period = median_period(&trace);
        // The peer supports 500 ppi only (pyfing's frequency stage refuses any other
        // resolution) and its Gabor bank covers 5-16 px periods; a print whose median period is
        // closer to PEER_PERIOD at 2x or 1/2x is given to it at that scale as well (the count of
        // minutiae does not depend on the scale of their coordinates).
        let scale = PEER_SCALES
            .into_iter()
            .min_by(|a, b| {
                let off = |f: f64| (period * f / PEER_PERIOD).ln().abs();
                off(*a).total_cmp(&off(*b))
            })
            .unwrap_or(1.0);
        let scaled = (peer && period > 0.0 && scale != 1.0).then(|| {
            let path = work.join(format!(
                "x{scale}_{}.png",
                file.file_stem()
                    .map_or(String::new(), |n| n.to_string_lossy().into_owned())
            ));
            let size = |n: u32| ((f64::from(n) * scale).round() as u32).max(1);
            // Catmull-Rom to enlarge; the triangle filter (a mean over each output pixel's
            // footprint) to halve.
            let filter = if scale > 1.0 {
                image::imageops::FilterType::CatmullRom
            } else {
                image::imageops::FilterType::Triangle
            };
            let resized =
                image::imageops::resize(&gray, size(gray.width()), size(gray.height()), filter);
            resized.save(&path).map(|_| path)
        });
        if let Some(path) = scaled {
            rescaled.push((file.clone(), scale, path?));
        }
        rows.push((
            file.clone(),
            gray.width(),
            gray.height(),
            count,
            off,
            time,
            period,
        ));
    }
    let peer_rescaled = if rescaled.is_empty() {
        None
    } else {
        let paths: Vec<PathBuf> = rescaled.iter().map(|(_, _, p)| p.clone()).collect();
        run_peer(&paths, &work.join("peer_real_rescaled.json"))
    };
    println!(
        "| print | size | median period, px | ridgeline minutiae | off ink | time, s | peer minutiae | peer time, s | peer at 2x or 1/2x | ratio to the peer at its scale |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let (mut in_band, mut compared) = (0, 0);
    for (file, width, height, count, off, time, period) in rows {
        let native = peer_real.as_ref().and_then(|p| p.get(&file));
        let (pc, pt) = match native {
            Some((found, t)) => (found.len().to_string(), format!("{t:.2}")),
            None => ("-".into(), "-".into()),
        };
        let other = rescaled
            .iter()
            .find(|(f, _, _)| *f == file)
            .and_then(|(_, scale, path)| Some((*scale, peer_rescaled.as_ref()?.get(path)?)));
        let other_cell = other.map_or("-".into(), |(scale, (found, _))| {
            format!("{} at {scale}x", found.len())
        });
        // The peer at the scale it is made for: the rescaled print where there is one.
        let reference = other
            .map(|(_, (found, _))| found.len())
            .or(native.map(|(f, _)| f.len()));
        let ratio = reference.map(|r| count as f64 / r.max(1) as f64);
        if let Some(ratio) = ratio {
            compared += 1;
            in_band += usize::from((0.5..=2.0).contains(&ratio));
        }
        let ratio = ratio.map_or("-".into(), |r| format!("{r:.2}"));
        println!(
            "| {} | {width}x{height} | {period:.1} | {count} | {off} | {time:.2} | {pc} | {pt} | {other_cell} | {ratio} |",
            file.file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
        );
    }
    if compared > 0 {
        println!();
        println!("prints within 1/2-2x the peer at its scale: {in_band} of {compared}");
    }
    Ok(())
}

/// The median of the ridge periods of the print's blocks, px (0 without the front end).
fn median_period(trace: &ridgeline::Trace) -> f64 {
    trace.fingerprint.as_ref().map_or(0.0, |print| {
        let analysis = &print.analysis;
        analysis.periods.median_inside(&analysis.segmentation)
    })
}

/// The traced centerlines' length on pixels that are not ridge in the enhanced binary (the Gabor
/// response not positive), and their whole length, px: sampled every half pixel, each sample
/// on the pixel that holds it.
fn off_enhanced_ink(trace: &ridgeline::Trace) -> [f64; 2] {
    let Some(print) = &trace.fingerprint else {
        return [0.0, 0.0];
    };
    let enhanced = &print.analysis.enhanced;
    let ridge = |x: f64, y: f64| {
        let (x, y) = (x.floor(), y.floor());
        x >= 0.0
            && y >= 0.0
            && (x as u32) < enhanced.width
            && (y as u32) < enhanced.height
            && enhanced.values[y as usize * enhanced.width as usize + x as usize] > 0.0
    };
    let (mut off, mut total) = (0.0, 0.0);
    for edge in &trace.graph.edges {
        for pair in edge.points.windows(2) {
            let length = ridgeline::dist(pair[0], pair[1]);
            let steps = (2.0 * length).ceil().max(1.0) as usize;
            for k in 0..steps {
                let t = (k as f64 + 0.5) / steps as f64;
                let x = pair[0][0] + t * (pair[1][0] - pair[0][0]);
                let y = pair[0][1] + t * (pair[1][1] - pair[0][1]);
                total += length / steps as f64;
                if !ridge(x, y) {
                    off += length / steps as f64;
                }
            }
        }
    }
    [off, total]
}

/// `part / whole` of a pair as a percentage with two decimals.
fn percent([part, whole]: [f64; 2]) -> String {
    if whole > 0.0 {
        format!("{:.2} %", 100.0 * part / whole)
    } else {
        "-".to_string()
    }
}

fn point_of(m: &Minutia) -> Point {
    Point {
        pos: m.pos,
        bifurcation: m.kind == MinutiaKind::Bifurcation,
        optional: false,
    }
}

/// The true minutiae: ends of the true ridges inside the image (see the module doc).
fn truth_of(strokes: &[Stroke], size: u32) -> Vec<Point> {
    let (center, axes) = finger_area(size);
    // How far inside the outline `p` lies along the ray from the centre, px (the outline is
    // nearly a circle); the outline's clipping puts a cut end on the ellipse itself.
    let inside_outline = |p: [f64; 2]| {
        let (u, v) = ((p[0] - center[0]) / axes[0], (p[1] - center[1]) / axes[1]);
        let rho = (u * u + v * v).sqrt().max(1e-9);
        ridgeline::dist(p, center) * (1.0 / rho - 1.0)
    };
    let mut out = Vec::new();
    for (s, stroke) in strokes.iter().enumerate() {
        let n = stroke.points.len();
        if n < 2 {
            continue;
        }
        for end in [0, n - 1] {
            let p = stroke.points[end];
            let inside = inside_outline(p);
            if inside < 1e-3 {
                continue;
            }
            // The traced level sets are cut into pieces: an end met by another piece's end (or
            // its own other end, a closed ridge) is where the ridge goes on.
            let continued = strokes.iter().enumerate().any(|(t, other)| {
                let m = other.points.len();
                [0, m.saturating_sub(1)]
                    .into_iter()
                    .filter(|&k| !(t == s && k == end))
                    .any(|k| ridgeline::dist(p, other.points[k]) < 1.5)
            });
            if continued {
                continue;
            }
            let width = stroke.widths.get(end).copied().unwrap_or(3.0);
            // Touching another ridge, or this one far along it: a bifurcation.
            let touches = strokes.iter().enumerate().any(|(t, other)| {
                other.points.iter().enumerate().any(|(k, q)| {
                    let far_along = t != s || (k as i64 - end as i64).abs() > 20;
                    far_along && ridgeline::dist(p, *q) <= width
                })
            });
            out.push(Point {
                pos: p,
                bifurcation: touches,
                optional: inside < BORDER_BAND,
            });
        }
    }
    // An end shared by two strokes is one minutia.
    let mut unique: Vec<Point> = Vec::new();
    for p in out {
        if !unique.iter().any(|u| ridgeline::dist(u.pos, p.pos) < 2.0) {
            unique.push(p);
        }
    }
    unique
}

/// The line beyond which a partial print is bare: points `p` with `(p - centre) . normal` above
/// `offset`.
#[derive(Clone, Copy, Debug)]
struct Cut {
    center: [f64; 2],
    normal: [f64; 2],
    offset: f64,
}

impl Cut {
    /// How far `p` lies inside the captured side, px (negative beyond the cut).
    fn depth(&self, p: [f64; 2]) -> f64 {
        self.offset
            - ((p[0] - self.center[0]) * self.normal[0] + (p[1] - self.center[1]) * self.normal[1])
    }
}

/// The gray capture of a print's ink: dark ridges on light skin, degraded as `variant` says; and
/// for a partial print, where it was cut.
fn capture(case: &Case, variant: &str, seed: u64) -> (GrayImage, Option<Cut>) {
    let binary = &case.binary;
    let (w, h) = (binary.width as usize, binary.height as usize);
    let mut rng = SplitMix64::new(seed);
    let all = variant == "all";
    let mut print = binary.clone();
    // The finger touched only part of the sensor: everything beyond a line at 10-35 % of the
    // image size from the centre, on a random side, is bare.
    let cut = (variant == "partial" || all).then(|| {
        let angle = rng.range(0.0, std::f64::consts::TAU);
        Cut {
            center: [w as f64 / 2.0, h as f64 / 2.0],
            normal: [angle.cos(), angle.sin()],
            offset: rng.range(0.1, 0.35) * w as f64,
        }
    });
    if let Some(line) = cut {
        for y in 0..h {
            for x in 0..w {
                if line.depth([x as f64, y as f64]) < 0.0 {
                    print.ink[y * w + x] = false;
                }
            }
        }
    }
    let mut depth: Vec<f64> = print
        .ink
        .iter()
        .map(|&i| if i { 1.0 } else { 0.0 })
        .collect();
    let erase = |depth: &mut [f64], c: [f64; 2], radius: f64| {
        let r = radius.ceil() as i64;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (c[0].round() as i64 + dx, c[1].round() as i64 + dy);
                let (fx, fy) = (x as f64 - c[0], y as f64 - c[1]);
                if x >= 0
                    && y >= 0
                    && (x as usize) < w
                    && (y as usize) < h
                    && fx * fx + fy * fy <= radius * radius
                {
                    depth[y as usize * w + x as usize] = 0.0;
                }
            }
        }
    };
    // Points of the true ridges at least `clear` px (along the ridge) from its ends, where a
    // break or a pore cannot move or fake a minutia.
    let ends: Vec<[f64; 2]> = case
        .strokes
        .iter()
        .flat_map(|s| [s.points[0], s.points[s.points.len() - 1]])
        .collect();
    let far_from_ends =
        |p: [f64; 2], clear: f64| ends.iter().all(|&e| ridgeline::dist(e, p) >= clear);
    if variant == "breaks" || all {
        // 25 ridges broken across their whole width (dry skin, scars): gaps of about one ridge
        // width, which a good extractor bridges, not minutiae.
        let points: Vec<([f64; 2], f64)> = case
            .strokes
            .iter()
            .flat_map(|s| s.points.iter().copied().zip(s.widths.iter().copied()))
            .collect();
        let mut made = 0;
        for _ in 0..2000 {
            if made == 25 || points.is_empty() {
                break;
            }
            let (p, width) = points[rng.below(points.len())];
            if far_from_ends(p, 15.0) {
                erase(&mut depth, p, width / 2.0 + rng.range(0.5, 1.5));
                made += 1;
            }
        }
    }
    if variant == "pores" || all {
        // Sweat pores: light dots on the ridge centres every 6-14 px along the ridges.
        for stroke in &case.strokes {
            let width = stroke.widths.first().copied().unwrap_or(3.0);
            let mut next = rng.range(3.0, 14.0);
            let mut along = 0.0;
            for pair in stroke.points.windows(2) {
                along += ridgeline::dist(pair[0], pair[1]);
                if along >= next {
                    next = along + rng.range(6.0, 14.0);
                    if far_from_ends(pair[1], 6.0) {
                        erase(&mut depth, pair[1], rng.range(0.6, 0.3 * width + 0.2));
                    }
                }
            }
        }
    }
    if variant == "creases" || all {
        // Three light lines across the ridges, 2-3 px wide.
        for _ in 0..3 {
            let (cx, cy) = (
                rng.range(30.0, w as f64 - 30.0),
                rng.range(30.0, h as f64 - 30.0),
            );
            let angle = rng.range(0.0, std::f64::consts::PI);
            let half = rng.range(1.0, 1.5);
            let (nx, ny) = (-angle.sin(), angle.cos());
            for y in 0..h {
                for x in 0..w {
                    let d = ((x as f64 - cx) * nx + (y as f64 - cy) * ny).abs();
                    if d <= half {
                        depth[y * w + x] = 0.0;
                    }
                }
            }
        }
    }
    if variant == "blur" || all {
        depth = blur(&depth, w, h, 1.5);
    } else {
        depth = blur(&depth, w, h, 0.7);
    }
    let contrast_map = variant == "contrast" || all;
    let (fx, fy, phase) = (
        rng.range(0.01, 0.03),
        rng.range(0.01, 0.03),
        rng.range(0.0, 6.3),
    );
    let noise = if variant == "noise" || all { 25.0 } else { 0.0 };
    let mut pixels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            // Dry and wet skin: the ridge depth between 25 % and 100 %, the skin level moving too.
            let (contrast, skin) = if contrast_map {
                let s = ((x as f64 * fx + phase).sin() * (y as f64 * fy).cos() + 1.0) / 2.0;
                (0.25 + 0.75 * s, 230.0 - 60.0 * (1.0 - s))
            } else {
                (1.0, 230.0)
            };
            let n = if noise > 0.0 {
                gaussian(&mut rng) * noise
            } else {
                0.0
            };
            let v = skin - 180.0 * contrast * depth[y * w + x] + n;
            pixels.push(v.round().clamp(0.0, 255.0) as u8);
        }
    }
    (
        GrayImage::from_raw(w as u32, h as u32, pixels).unwrap_or_default(),
        cut,
    )
}

fn gaussian(rng: &mut SplitMix64) -> f64 {
    let u = rng.range(1e-12, 1.0);
    let v = rng.range(0.0, 1.0);
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

fn blur(values: &[f64], w: usize, h: usize, sigma: f64) -> Vec<f64> {
    let r = (3.0 * sigma).ceil() as i64;
    let k: Vec<f64> = (-r..=r)
        .map(|i| (-((i * i) as f64) / (2.0 * sigma * sigma)).exp())
        .collect();
    let sum: f64 = k.iter().sum();
    let mut tmp = vec![0.0; w * h];
    let mut out = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            tmp[y * w + x] = k
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    c * values[y * w + (x as i64 + j as i64 - r).clamp(0, w as i64 - 1) as usize]
                })
                .sum::<f64>()
                / sum;
        }
    }
    for y in 0..h {
        for x in 0..w {
            out[y * w + x] = k
                .iter()
                .enumerate()
                .map(|(j, c)| {
                    c * tmp[(y as i64 + j as i64 - r).clamp(0, h as i64 - 1) as usize * w + x]
                })
                .sum::<f64>()
                / sum;
        }
    }
    out
}

#[derive(Clone, Copy, Debug, Default)]
struct Score {
    truth: usize,
    found: usize,
    matched: usize,
    same_type: usize,
}

impl Score {
    /// One-to-one matching within `tolerance`, nearest pairs first; returns the matched pairs
    /// (found, truth).
    fn add(&mut self, found: &[Point], truth: &[Point], tolerance: f64) -> Vec<(usize, usize)> {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (i, f) in found.iter().enumerate() {
            for (j, t) in truth.iter().enumerate() {
                let d = ridgeline::dist(f.pos, t.pos);
                if d <= tolerance {
                    pairs.push((d, i, j));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut used_f, mut used_t) = (vec![false; found.len()], vec![false; truth.len()]);
        let mut matched = Vec::new();
        for (_, i, j) in pairs {
            if !used_f[i] && !used_t[j] {
                used_f[i] = true;
                used_t[j] = true;
                matched.push((i, j));
                if truth[j].optional {
                    continue;
                }
                self.matched += 1;
                if found[i].bifurcation == truth[j].bifurcation {
                    self.same_type += 1;
                }
            }
        }
        self.truth += truth.iter().filter(|t| !t.optional).count();
        // Detections matched to optional truth are not counted either way.
        self.found += found.len() - matched.iter().filter(|m| truth[m.1].optional).count();
        matched
    }
    /// False and missed minutiae (optional truth counted neither way).
    fn errors(&self) -> usize {
        (self.found - self.matched) + (self.truth - self.matched)
    }
    fn precision(&self) -> f64 {
        if self.found == 0 {
            1.0
        } else {
            self.matched as f64 / self.found as f64
        }
    }
    fn recall(&self) -> f64 {
        if self.truth == 0 {
            1.0
        } else {
            self.matched as f64 / self.truth as f64
        }
    }
    fn f1(&self) -> f64 {
        let (p, r) = (self.precision(), self.recall());
        if p + r == 0.0 {
            0.0
        } else {
            2.0 * p * r / (p + r)
        }
    }
    fn type_accuracy(&self) -> f64 {
        if self.matched == 0 {
            0.0
        } else {
            self.same_type as f64 / self.matched as f64
        }
    }
}

/// Runs the peer on `images`; each image's minutiae and seconds, or `None` when it cannot run.
fn run_peer(images: &[PathBuf], json: &Path) -> Option<BTreeMap<PathBuf, (Vec<Point>, f64)>> {
    let script = Path::new("../shared/bench/peer_minutiae.py");
    let status = std::process::Command::new("python3")
        .arg(script)
        .args(images)
        .arg("--json")
        .arg(json)
        .stdout(std::process::Stdio::null())
        .status()
        .ok()?;
    if !status.success() {
        eprintln!(
            "the peer did not run (see {} for what it needs)",
            script.display()
        );
        return None;
    }
    let text = std::fs::read_to_string(json).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    let mut out = BTreeMap::new();
    for (path, entry) in value.as_object()? {
        let seconds = entry.get("seconds").and_then(|s| s.as_f64()).unwrap_or(0.0);
        let found = entry
            .get("minutiae")
            .and_then(|m| m.as_array())
            .map(|list| {
                list.iter()
                    .filter_map(|m| {
                        Some(Point {
                            pos: [m.get("x")?.as_f64()?, m.get("y")?.as_f64()?],
                            bifurcation: m.get("kind")?.as_str()? == "bifurcation",
                            optional: false,
                        })
                    })
                    .collect()
            })
            .unwrap_or_default();
        out.insert(PathBuf::from(path), (found, seconds));
    }
    Some(out)
}

/// A picture of one synthetic print at 3x: the gray image faded, the traced ridges dark red, the
/// true minutiae as green rings (orange when missed, gray in the border band), the found ones
/// as dots (red ending, blue bifurcation) with a magenta ring when they match no truth.
fn picture(
    gray: &GrayImage,
    trace: &ridgeline::Trace,
    ridges: &[Stroke],
    found: &[Point],
    truth: &[Point],
    matched: &[(usize, usize)],
) -> image::RgbImage {
    use image::Rgb;
    use imageproc::drawing::{
        draw_filled_circle_mut, draw_hollow_circle_mut, draw_line_segment_mut,
    };
    const SCALE: f64 = 3.0;
    let (w, h) = gray.dimensions();
    let mut out = image::RgbImage::from_fn(w * 3, h * 3, |x, y| {
        let v = gray.get_pixel(x / 3, y / 3).0[0];
        let v = (155 + u16::from(v) * 100 / 255) as u8;
        Rgb([v, v, v])
    });
    // The true ridges in light blue under the traced ones in dark red.
    let lines = ridges
        .iter()
        .map(|r| (&r.points, Rgb([120, 170, 255])))
        .chain(
            trace
                .graph
                .edges
                .iter()
                .map(|e| (&e.points, Rgb([150, 20, 20]))),
        );
    for (points, color) in lines {
        for pair in points.windows(2) {
            let a = ((pair[0][0] * SCALE) as f32, (pair[0][1] * SCALE) as f32);
            let b = ((pair[1][0] * SCALE) as f32, (pair[1][1] * SCALE) as f32);
            draw_line_segment_mut(&mut out, a, b, color);
        }
    }
    let at = |p: [f64; 2]| ((p[0] * SCALE) as i32, (p[1] * SCALE) as i32);
    for (j, t) in truth.iter().enumerate() {
        let hit = matched.iter().any(|m| m.1 == j);
        let color = if t.optional {
            Rgb([150, 150, 150])
        } else if hit {
            Rgb([0, 170, 0])
        } else {
            Rgb([255, 140, 0])
        };
        for r in [14, 15, 16] {
            draw_hollow_circle_mut(&mut out, at(t.pos), r, color);
        }
    }
    for (i, f) in found.iter().enumerate() {
        let color = if f.bifurcation {
            Rgb([30, 60, 230])
        } else {
            Rgb([230, 20, 20])
        };
        draw_filled_circle_mut(&mut out, at(f.pos), 5, color);
        if !matched.iter().any(|m| m.0 == i) {
            for r in [9, 10] {
                draw_hollow_circle_mut(&mut out, at(f.pos), r, Rgb([230, 0, 230]));
            }
        }
    }
    out
}
