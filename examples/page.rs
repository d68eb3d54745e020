//! Page benchmark (docs/performance.md): time per stage, wall time and peak memory of tracing a
//! whole page, from the PNG file to the SVG written, as the command line does it (default
//! parameters, the scan embedded under the centerlines).
//!
//! ```text
//! cargo run --release --example page [-- --repeat 3] [--peer] [--python PATH] [--no-scans] [--keep DIR] [IMAGE...]
//! ```
//!
//! `--batch N` (N = 20 when not given) instead measures the command line's batch speed-up: N generated pages traced with
//! `ridgeline --jobs 1` and `--jobs 2` (needs `cargo build --release` for the binary), outputs
//! compared byte for byte, with the cores each run kept busy (CPU / wall: a `--jobs 2` run that
//! the machine gave fewer than two cores cannot show the speed-up) and the threads it kept
//! runnable (running or waiting for a core, from `/proc/PID/task/*/schedstat`: the parallelism
//! the program offers, whatever the load).
//!
//! `--keep DIR` writes the generated pages into DIR (kept) instead of a temporary directory.
//!
//! `--front-end` instead measures what the automatic front end's choices cost (docs/performance.md,
//! "The front end's choices"): the A4 page captured in gray (anti-aliased, blurred, noised, JPEG;
//! evenly lit, lit unevenly, and lit unevenly with light strokes on a dark ground), each traced
//! with the defaults and with what the defaults decided given as flags (threshold, polarity,
//! dropout: Otsu or the local threshold forced, which skips the tests that choose between them),
//! in alternating rounds; outputs compared.
//!
//! Inputs: a generated A4 page at 300 dpi of dense text ([`ridgeline_testkit::synth::page`], 2480 x 3508,
//! 40 px x-height, 4 px strokes), the same page at half the size per side (1240 x 1754: the
//! generator keeps the glyph size and stroke width and fills a quarter of the area with the same
//! kind of lines) and a larger page of the same text with about a million ink pixels (3100 x
//! 4385), all written as PNG into a temporary directory; then the three largest real scans of
//! `../shared/data/text/` when present, and any IMAGE given.
//!
//! Each trace runs in a fresh child process of this same binary (`--child FILE`), so that each
//! peak memory (`VmHWM` of `/proc/self/status`) is that input's own. `--repeat` rounds trace every
//! input once each (the peer right after ours), so a change of load on a shared machine hits all
//! inputs alike; the table shows the median of each figure over the rounds, with the process CPU
//! time beside the wall time (the load average is printed: on a busy shared machine wall times
//! grow while CPU times do not). Stage times come from
//! [`ridgeline::Timings`]: when a page is traced as parallel chunks they are summed over the
//! chunks (CPU time), so they can add up to more than the wall time.
//!
//! `--peer` also runs `../shared/bench/peer_page.py` (scikit-image skeletonize + sknw) on the same
//! files in the same session, and prints ours/peer; `--python PATH` names the interpreter that has
//! scikit-image and sknw (default `python3`).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::{GrayImage, Params};

/// Stage names in report order; the child prints one value per name, in this order.
const STAGES: [&str; 9] = [
    "decode", "binarize", "points", "sampling", "graph", "refine", "fit", "skeleton", "export",
];

/// One child's medians: stage seconds, wall seconds, process CPU seconds, peak resident memory in MB, and counts.
#[derive(Clone, Debug, Default)]
struct Figures {
    stages: [f64; STAGES.len()],
    wall: f64,
    cpu: f64,
    /// CPU seconds of decoding and binarizing alone (the floor of reading the page), measured in
    /// a run of its own so that the load does not inflate it as it does the stages' wall times.
    floor_cpu: f64,
    peak_mb: f64,
    ink: usize,
    vertices: usize,
    edges: usize,
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut repeat = 3usize;
    let mut peer = false;
    let mut scans = true;
    let mut child = None;
    let mut keep = None;
    let mut batch = 0usize;
    let mut front_end = false;
    let mut python = String::from("python3");
    let mut extra = Vec::new();
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--repeat" => {
                i += 1;
                repeat = args.get(i).and_then(|v| v.parse().ok()).unwrap_or(3).max(1);
            }
            "--peer" => peer = true,
            "--python" => {
                i += 1;
                if let Some(path) = args.get(i) {
                    python.clone_from(path);
                }
            }
            "--no-scans" => scans = false,
            "--front-end" => front_end = true,
            "--batch" => {
                i += 1;
                batch = args.get(i).and_then(|v| v.parse().ok()).unwrap_or(20);
            }
            "--keep" => {
                i += 1;
                keep = args.get(i).map(PathBuf::from);
            }
            "--child" => {
                i += 1;
                child = args.get(i).cloned();
            }
            "-h" | "--help" => {
                println!(
                    "usage: page [--repeat N] [--peer] [--python PATH] [--no-scans] [--keep DIR] \
                     [--batch [N]] [--front-end] [IMAGE...]\n(see the header of examples/page.rs \
                     and docs/performance.md)"
                );
                return;
            }
            other if other.starts_with('-') => {
                eprintln!("page: unknown option {other}; try --help");
                std::process::exit(2);
            }
            other => extra.push(PathBuf::from(other)),
        }
        i += 1;
    }
    if let Some(file) = child {
        run_child(Path::new(&file), repeat);
        return;
    }

    if batch > 0 {
        run_batch(batch, repeat);
        return;
    }
    if front_end {
        run_front_end(repeat.max(5));
        return;
    }
    let temp = tempfile::tempdir().expect("temporary directory");
    let dir = keep.unwrap_or_else(|| temp.path().to_path_buf());
    std::fs::create_dir_all(&dir).expect("page directory");
    let mut inputs: Vec<(String, PathBuf)> = Vec::new();
    for (name, w, h) in [
        ("A4 half", 1240, 1754),
        ("A4 300dpi", 2480, 3508),
        ("1M ink", 3100, 4385),
    ] {
        let clock = Instant::now();
        let case = ridgeline_testkit::synth::page(w, h, 1);
        let path = dir.join(format!("page_{w}x{h}.png"));
        to_gray(&case.binary).save(&path).expect("write page PNG");
        eprintln!(
            "generated {name} {w}x{h}, {} ink px, in {:.2} s: {}",
            case.binary.count(),
            clock.elapsed().as_secs_f64(),
            path.display()
        );
        inputs.push((name.to_string(), path));
    }
    if scans {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/text");
        for path in largest_images(&data, 3) {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().chars().take(4).collect())
                .unwrap_or_default();
            inputs.push((name, path));
        }
    }
    for path in extra {
        inputs.push((path.display().to_string(), path));
    }

    let exe = std::env::current_exe().expect("own path");
    let peer_script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/bench/peer_page.py");
    println!(
        "ridgeline page benchmark: {} threads, median of {repeat} runs; stage times summed over \
         parallel chunks, TOTAL = wall time (read PNG -> SVG written), CPU = process user+system \
         time; load average {}",
        rayon::current_num_threads(),
        load_average()
    );
    println!(
        "{:<10} {:>9} {:>7} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>7} {:>7} {:>7}",
        "input",
        "size",
        "ink px",
        "decode",
        "binar",
        "points",
        "sample",
        "graph",
        "refine",
        "fit",
        "skel",
        "export",
        "TOTAL",
        "CPU",
        "peak MB",
        "peer s",
        "ours/pr"
    );
    // Rounds: every input once per round (ours, then the peer right after), so that a change of
    // load on the shared machine hits all inputs alike; medians over the rounds.
    let mut runs: Vec<Vec<Figures>> = vec![Vec::new(); inputs.len()];
    let mut peer_runs: Vec<Vec<f64>> = vec![Vec::new(); inputs.len()];
    for _ in 0..repeat {
        for (k, (_, path)) in inputs.iter().enumerate() {
            runs[k].extend(spawn_child(&exe, path, 1));
            if peer {
                peer_runs[k].extend(run_peer(&python, &peer_script, path, 1));
            }
        }
    }
    let mut results = Vec::new();
    for (k, (name, path)) in inputs.iter().enumerate() {
        let Some(figures) = median_figures(&runs[k]) else {
            println!("{name:<10} failed");
            continue;
        };
        let peer_time = median(&mut peer_runs[k]);
        let (w, h) = image::image_dimensions(path).unwrap_or((0, 0));
        let mut row = format!("{name:<10} {:>9} {:>7}", format!("{w}x{h}"), figures.ink);
        for s in figures.stages {
            row.push_str(&format!(" {s:>6.3}"));
        }
        row.push_str(&format!(
            " {:>6.3} {:>6.3} {:>7.0}",
            figures.wall, figures.cpu, figures.peak_mb
        ));
        match peer_time {
            Some(p) => row.push_str(&format!(" {p:>7.3} {:>7.2}", figures.wall / p)),
            None => row.push_str(&format!(" {:>7} {:>7}", "-", "-")),
        }
        println!("{row}");
        results.push((name.clone(), figures, peer_time));
    }
    println!("load average at the end: {}", load_average());
    if let [(_, small, _), (_, large, _), ..] = results.as_slice() {
        println!(
            "growth half -> full page (4x the area): wall {:.2}x, CPU {:.2}x; ink {:.2}x",
            large.wall / small.wall,
            large.cpu / small.cpu,
            large.ink as f64 / small.ink.max(1) as f64
        );
        println!(
            "full page: {} vertices, {} edges; targets: total < 1.0 s {}, peak < 300 MB {}, \
             growth <= 4.5x {}",
            large.vertices,
            large.edges,
            verdict(large.wall < 1.0),
            verdict(large.peak_mb < 300.0),
            verdict(large.wall / small.wall <= 4.5)
        );
        // docs/performance.md, "Targets": the page's CPU against the floor of reading it, both
        // in CPU seconds (the floor from a decode and binarize of its own), so that the load,
        // which stretches wall times, does not move the ratio.
        let floor = large.floor_cpu;
        println!(
            "full page: CPU / CPU of (decode + binarize) {:.1} (target <= 5: {}), peak {:.0} MB \
             (target <= 60 MB: {})",
            large.cpu / floor.max(1e-9),
            verdict(large.cpu <= 5.0 * floor),
            large.peak_mb,
            verdict(large.peak_mb <= 60.0)
        );
    }
    // The peer goal of docs/performance.md, per input traced side by side.
    let ratios: Vec<String> = results
        .iter()
        .filter_map(|(name, figures, peer)| {
            peer.map(|p| {
                let ratio = figures.wall / p;
                format!("{name} {ratio:.2} {}", verdict(ratio < 0.5))
            })
        })
        .collect();
    if !ratios.is_empty() {
        println!("ours/peer < 0.5: {}", ratios.join(", "));
    }
}

/// Batch speed-up of the command line: `count` generated pages (seeds 1, 2, ...; full A4 and half
/// size in turn) traced by `ridgeline --jobs 1` and `--jobs 2`, `repeat` times each in turn;
/// median wall times, and the outputs compared byte for byte.
fn run_batch(count: usize, repeat: usize) {
    let exe = std::env::current_exe().expect("own path");
    let Some(cli) = exe
        .parent()
        .and_then(Path::parent)
        .map(|dir| dir.join("ridgeline"))
        .filter(|p| p.exists())
    else {
        eprintln!("no ridgeline binary next to the examples: run `cargo build --release` first");
        std::process::exit(1);
    };
    let dir = tempfile::tempdir().expect("temporary directory");
    let pages = dir.path().join("pages");
    std::fs::create_dir_all(&pages).expect("page directory");
    let mut ink = 0;
    for k in 0..count {
        let (w, h) = if k % 2 == 0 {
            (2480, 3508)
        } else {
            (1240, 1754)
        };
        let case = ridgeline_testkit::synth::page(w, h, k as u64 + 1);
        ink += case.binary.count();
        to_gray(&case.binary)
            .save(pages.join(format!("page{k:03}.png")))
            .expect("write page PNG");
    }
    println!(
        "batch: {count} generated pages ({} full A4, {} half size, {ink} ink px in all), {}; \
         load average {}",
        count.div_ceil(2),
        count / 2,
        cli.display(),
        load_average()
    );
    let mut times: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    // CPU seconds over wall seconds of each run: the cores the machine gave it. On a shared
    // machine (the kernel's autogroup scheduling gives each busy session about one share,
    // docs/performance.md) `--jobs 2` may get little more than one core whatever the program
    // does, and its speed-up then says nothing about the program.
    let mut cores: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    // The threads the run kept runnable on average (on a CPU or waiting in a run queue, from the
    // scheduler's own accounting): the parallelism the program offers, which the load does not
    // change. A `--jobs 2` run that keeps two threads runnable throughout would take half the
    // time of `--jobs 1` on two free cores.
    let mut demand: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for _ in 0..repeat {
        for (slot, jobs) in [1, 2].into_iter().enumerate() {
            let out = dir.path().join(format!("out{jobs}"));
            let cpu_before = children_cpu_seconds();
            let clock = Instant::now();
            let (status, runnable) = run_with_demand(
                Command::new(&cli)
                    .arg(&pages)
                    .arg("-o")
                    .arg(&out)
                    .arg("--jobs")
                    .arg(jobs.to_string())
                    .arg("--quiet"),
            );
            let seconds = clock.elapsed().as_secs_f64();
            let cpu = children_cpu_seconds() - cpu_before;
            assert!(status.success(), "ridgeline --jobs {jobs} failed");
            println!(
                "  --jobs {jobs}: {seconds:.3} s wall, {cpu:.2} s CPU, {:.2} cores busy, {:.2} \
                 threads runnable (load average {})",
                cpu / seconds,
                runnable / seconds,
                load_average()
            );
            times[slot].push(seconds);
            cores[slot].push(cpu / seconds);
            demand[slot].push(runnable / seconds);
        }
    }
    let one = median(&mut times[0]).unwrap_or(0.0);
    let two = median(&mut times[1]).unwrap_or(0.0);
    let busy = median(&mut cores[1]).unwrap_or(0.0);
    let mut identical = true;
    for k in 0..count {
        let name = format!("page{k:03}.svg");
        let a = std::fs::read(dir.path().join("out1").join(&name)).expect("output of --jobs 1");
        let b = std::fs::read(dir.path().join("out2").join(&name)).expect("output of --jobs 2");
        identical &= a == b;
    }
    println!(
        "batch median: --jobs 1 {one:.3} s, --jobs 2 {two:.3} s, speed-up {:.2}x (target >= 1.8x: \
         {}); outputs byte-identical: {identical}; load average {}",
        one / two,
        verdict(one / two >= 1.8),
        load_average()
    );
    let offered = [
        median(&mut demand[0]).unwrap_or(0.0),
        median(&mut demand[1]).unwrap_or(0.0),
    ];
    println!(
        "threads runnable on average (running or waiting for a core): --jobs 1 {:.2}, --jobs 2 \
         {:.2}, ratio {:.2}",
        offered[0],
        offered[1],
        offered[1] / offered[0].max(1e-9)
    );
    if busy < 1.8 {
        println!(
            "  --jobs 2 kept only {busy:.2} cores busy: the machine did not give it two, so the \
             speed-up above measures the load, not the program"
        );
    }
}

/// Runs `command` to its end, reading its threads' scheduler statistics every 20 ms
/// (`/proc/PID/task/*/schedstat`: nanoseconds on a core, nanoseconds waiting in a run queue);
/// returns its exit status and the seconds its threads were running or runnable, summed, as of
/// the last reading (each thread's last 20 ms may be missing). Linux only; 0 elsewhere.
fn run_with_demand(command: &mut Command) -> (std::process::ExitStatus, f64) {
    let mut child = command.spawn().expect("run ridgeline");
    let mut threads: std::collections::HashMap<std::ffi::OsString, f64> =
        std::collections::HashMap::new();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for ridgeline") {
            break status;
        }
        if let Ok(tasks) = std::fs::read_dir(format!("/proc/{}/task", child.id())) {
            for task in tasks.flatten() {
                let Ok(text) = std::fs::read_to_string(task.path().join("schedstat")) else {
                    continue;
                };
                let nanos: Vec<f64> = text
                    .split_whitespace()
                    .take(2)
                    .filter_map(|v| v.parse().ok())
                    .collect();
                if let [running, waiting] = nanos[..] {
                    threads.insert(task.file_name(), (running + waiting) * 1e-9);
                }
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status, threads.values().sum())
}

/// What the automatic front end's choices cost on a gray A4 page: each capture traced with the
/// defaults (A) and with their decisions forced (B: the threshold, polarity and dropout the
/// defaults chose, given as parameters), `repeat` rounds of A then B; medians and the median of
/// the pairwise CPU ratios. The outputs of A and B are the same graph.
fn run_front_end(repeat: usize) {
    use ridgeline::ThresholdUsed;
    use ridgeline_testkit::synth::{degrade, Recipe, SplitMix64};

    let dir = tempfile::tempdir().expect("temporary directory");
    let (w, h) = (2480, 3508);
    let case = ridgeline_testkit::synth::page(w, h, 1);
    let recipe = |inverted: bool, falloff: f64| Recipe {
        inverted,
        paper: if inverted { 40 } else { 230 },
        ink: if inverted { 225 } else { 35 },
        blur: 1.0,
        falloff,
        light_angle: 0.6,
        noise: 6.0,
        jpeg_quality: 70,
    };
    let captures = [
        ("even", recipe(false, 0.0)),
        ("uneven", recipe(false, 0.5)),
        ("uneven inv", recipe(true, 0.5)),
    ];
    let exe = std::env::current_exe().expect("own path");
    println!(
        "front end's choices on the gray A4 page ({w}x{h}): A = defaults, B = A's decisions forced; \
         median of {repeat} rounds; load average {}",
        load_average()
    );
    println!(
        "{:<11} {:<28} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9}",
        "capture", "decided", "A binar", "B binar", "A CPU", "B CPU", "A/B CPU", "same graph"
    );
    for (k, (name, recipe)) in captures.iter().enumerate() {
        let mut rng = SplitMix64::new(k as u64 + 1);
        let gray = degrade(&case.strokes, w, h, recipe, &mut rng);
        let path = dir.path().join(format!("gray_{k}.png"));
        gray.save(&path).expect("write capture PNG");
        let trace = ridgeline::trace_image(&gray, &Params::default()).expect("trace");
        let Some(decided) = trace.decisions else {
            println!("{name:<11} no decisions recorded");
            continue;
        };
        let threshold = match decided.threshold {
            ThresholdUsed::Otsu { .. } => serde_json::json!({"method": "otsu"}),
            ThresholdUsed::Local { .. } => serde_json::json!({"method": "local"}),
            other => {
                println!("{name:<11} decided {other:?}: not a choice this benchmark forces");
                continue;
            }
        };
        let forced = serde_json::json!({
            "threshold": threshold,
            "polarity": decided.polarity,
            "dropout": decided.dropout,
        })
        .to_string();
        let forced_trace =
            ridgeline::trace_image(&gray, &params_over_defaults(&forced)).expect("trace forced");
        let same = trace.graph == forced_trace.graph;
        let (mut a, mut b, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..repeat {
            let (Some(fa), Some(fb)) = (
                spawn_child_with(&exe, &path, 1, None),
                spawn_child_with(&exe, &path, 1, Some(&forced)),
            ) else {
                continue;
            };
            ratios.push(fa.cpu / fb.cpu.max(1e-9));
            a.push(fa);
            b.push(fb);
        }
        let (Some(ma), Some(mb), Some(ratio)) =
            (median_figures(&a), median_figures(&b), median(&mut ratios))
        else {
            println!("{name:<11} failed");
            continue;
        };
        let decided_text = match decided.threshold {
            ThresholdUsed::Otsu { level } => format!("otsu {level}, {}", decided.polarity),
            ThresholdUsed::Local { window } => format!("local {window} px, {}", decided.polarity),
            _ => String::new(),
        };
        println!(
            "{name:<11} {decided_text:<28} {:>8.3} {:>8.3} {:>7.3} {:>7.3} {:>7.3} {:>9}",
            ma.stages[1], mb.stages[1], ma.cpu, mb.cpu, ratio, same
        );
    }
    println!("load average at the end: {}", load_average());
}

/// The 1-minute load average: the machine is shared, and wall times mean little without it.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "unknown".into())
}

/// The median of `values` (the upper one of an even count); `None` for none.
fn median(values: &mut [f64]) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied()
}

/// Field-by-field medians of several runs of one input.
fn median_figures(runs: &[Figures]) -> Option<Figures> {
    let first = runs.first()?;
    let of = |field: &dyn Fn(&Figures) -> f64| {
        median(&mut runs.iter().map(field).collect::<Vec<_>>()).unwrap_or(0.0)
    };
    let mut stages = [0.0; STAGES.len()];
    for (k, stage) in stages.iter_mut().enumerate() {
        *stage = of(&|f| f.stages[k]);
    }
    Some(Figures {
        stages,
        wall: of(&|f| f.wall),
        cpu: of(&|f| f.cpu),
        floor_cpu: of(&|f| f.floor_cpu),
        peak_mb: of(&|f| f.peak_mb),
        ..first.clone()
    })
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "met"
    } else {
        "NOT met"
    }
}

/// Ink black on white paper.
fn to_gray(binary: &ridgeline::Binary) -> GrayImage {
    let pixels = binary
        .ink
        .iter()
        .map(|&b| if b { 0 } else { 255 })
        .collect();
    GrayImage::from_raw(binary.width, binary.height, pixels).expect("size matches")
}

/// The `count` images of `dir` with the most pixels, largest first.
fn largest_images(dir: &Path, count: usize) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut sized: Vec<(u64, PathBuf)> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| {
            let (w, h) = image::image_dimensions(&p).ok()?;
            Some((w as u64 * h as u64, p))
        })
        .collect();
    sized.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| a.1.cmp(&b.1)));
    sized.into_iter().take(count).map(|(_, p)| p).collect()
}

fn spawn_child(exe: &Path, path: &Path, repeat: usize) -> Option<Figures> {
    spawn_child_with(exe, path, repeat, None)
}

/// [`spawn_child`] with `params`, JSON fields laid over the defaults (`RIDGELINE_PARAMS`).
fn spawn_child_with(
    exe: &Path,
    path: &Path,
    repeat: usize,
    params: Option<&str>,
) -> Option<Figures> {
    let mut command = Command::new(exe);
    command
        .arg("--child")
        .arg(path)
        .arg("--repeat")
        .arg(repeat.to_string());
    match params {
        Some(json) => command.env("RIDGELINE_PARAMS", json),
        None => command.env_remove("RIDGELINE_PARAMS"),
    };
    let output = command.output().ok()?;
    if !output.status.success() {
        eprintln!(
            "child failed on {}: {}",
            path.display(),
            String::from_utf8_lossy(&output.stderr)
        );
        return None;
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let line = text.lines().find(|l| l.starts_with("RESULT "))?;
    let values: Vec<f64> = line[7..]
        .split_whitespace()
        .filter_map(|v| v.parse().ok())
        .collect();
    if values.len() != STAGES.len() + 7 {
        return None;
    }
    let mut stages = [0.0; STAGES.len()];
    stages.copy_from_slice(&values[..STAGES.len()]);
    let values = &values[STAGES.len()..];
    Some(Figures {
        stages,
        wall: values[0],
        cpu: values[1],
        floor_cpu: values[2],
        peak_mb: values[3],
        ink: values[4] as usize,
        vertices: values[5] as usize,
        edges: values[6] as usize,
    })
}

/// Median wall time of the peer on `path`, from the script's last line.
fn run_peer(python: &str, script: &Path, path: &Path, repeat: usize) -> Option<f64> {
    let output = Command::new(python)
        .arg(script)
        .arg(path)
        .arg("--repeat")
        .arg(repeat.to_string())
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        eprintln!(
            "peer failed on {}: {}",
            path.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        );
        return None;
    }
    let line = text.lines().find(|l| l.contains("median"))?;
    let after = line.split("median").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

/// Traces `path` `repeat` times in this process and prints the medians on one `RESULT` line.
fn run_child(path: &Path, repeat: usize) {
    // Variants on one build: the fields of the JSON object in `RIDGELINE_PARAMS` laid over the
    // defaults (as in the quality benchmark).
    let params = match std::env::var("RIDGELINE_PARAMS") {
        Ok(json) => params_over_defaults(&json),
        Err(_) => Params::default(),
    };
    let out_dir = tempfile::tempdir().expect("temporary directory");
    let out_path = out_dir.path().join("out.svg");
    let mut runs: Vec<([f64; STAGES.len()], f64, f64, f64)> = Vec::new();
    let (mut ink, mut vertices, mut edges) = (0, 0, 0);
    for _ in 0..repeat {
        // The floor: decoding and binarizing alone, in CPU seconds, freed before the trace so
        // that the peak stays the trace's.
        let floor_start = cpu_seconds();
        let bytes = std::fs::read(path).expect("read input");
        let gray = ridgeline::decode(&bytes, &params.front_end.limits).expect("decode");
        drop(ridgeline::raster::binarize(&gray, &params).expect("binarize"));
        drop((gray, bytes));
        let floor_cpu = cpu_seconds() - floor_start;
        let cpu_start = cpu_seconds();
        let start = Instant::now();
        let bytes = std::fs::read(path).expect("read input");
        let gray = ridgeline::decode(&bytes, &params.front_end.limits).expect("decode");
        let decode = start.elapsed();
        let trace = ridgeline::trace_image(&gray, &params).expect("trace");
        let clock = Instant::now();
        let text = svg::to_string(&trace.graph, Some(&gray), &SvgOptions::default());
        std::fs::write(&out_path, text.as_bytes()).expect("write SVG");
        let export = clock.elapsed();
        let wall = start.elapsed();
        let t = trace.timings;
        let stages: [Duration; STAGES.len()] = [
            decode, t.binarize, t.points, t.sampling, t.graph, t.refine, t.fit, t.skeleton, export,
        ];
        let cpu = cpu_seconds() - cpu_start;
        runs.push((
            stages.map(|d| d.as_secs_f64()),
            wall.as_secs_f64(),
            cpu,
            floor_cpu,
        ));
        ink = trace.point_count;
        vertices = trace.graph.vertices.len();
        edges = trace.graph.edges.len();
    }
    let median = |mut v: Vec<f64>| median(&mut v).unwrap_or(0.0);
    let mut line = String::from("RESULT");
    for k in 0..STAGES.len() {
        line.push_str(&format!(
            " {}",
            median(runs.iter().map(|r| r.0[k]).collect())
        ));
    }
    line.push_str(&format!(" {}", median(runs.iter().map(|r| r.1).collect())));
    line.push_str(&format!(" {}", median(runs.iter().map(|r| r.2).collect())));
    line.push_str(&format!(" {}", median(runs.iter().map(|r| r.3).collect())));
    line.push_str(&format!(" {} {ink} {vertices} {edges}", peak_mb()));
    println!("{line}");
}

/// The defaults with the fields of the JSON object `json` laid over them.
fn params_over_defaults(json: &str) -> Params {
    let mut value = serde_json::to_value(Params::default()).expect("params serialize");
    let over: serde_json::Value = serde_json::from_str(json).expect("RIDGELINE_PARAMS");
    if let (Some(fields), Some(over)) = (value.as_object_mut(), over.as_object()) {
        for (key, v) in over {
            fields.insert(key.clone(), v.clone());
        }
    }
    serde_json::from_value(value).expect("RIDGELINE_PARAMS fields")
}

/// CPU time of this process so far (all threads, from each thread's `schedstat`, in ns), in
/// seconds; the rayon threads live as long as the process, so differences are exact.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    tasks
        .filter_map(|task| task.ok())
        .filter_map(|task| std::fs::read_to_string(task.path().join("schedstat")).ok())
        .filter_map(|stat| stat.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}

/// CPU time (user + system) of the waited-for child processes so far, in seconds (10 ms ticks):
/// fields 16 and 17 of `/proc/self/stat`.
fn children_cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the parenthesized command name start at field 3.
    let Some(rest) = stat.rfind(')').map(|i| &stat[i + 1..]) else {
        return 0.0;
    };
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k - 3).and_then(|v| v.parse::<f64>().ok());
    match (ticks(16), ticks(17)) {
        (Some(user), Some(system)) => (user + system) / 100.0,
        _ => 0.0,
    }
}

/// Peak resident memory of this process in MB (`VmHWM`), 0 when /proc is not there.
fn peak_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(0.0, |kb| kb / 1024.0)
}
