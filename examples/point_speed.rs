//! Speed on point sets of 10^3 to 10^6 points, in the plane and in space: random points in a
//! band 8 units wide around a sine wave (`sine_strip`) and filling a helix tube 8 units across
//! (`helix_tube`), the curve growing with the count so the density stays that of the quality
//! benchmark's point group. Prints one table row per size: the best of a few runs, in ms, and the
//! graph's counts (one curve with two ends is right), and the CPU time of all threads (from
//! `/proc/self/task/*/schedstat` on Linux, `-` elsewhere): on a machine shared with other work
//! the wall time is that CPU time stretched by the load. A benchmark, not a test:
//! `cargo run --release --example point_speed [-- MAX_EXPONENT] [--from EXPONENT] [--seed S]
//! [--only plane|space|cloud] [--inspect] [--write FILE]` (`--help` says what they do). Last, a uniform cloud of 200,000 points (no strip, density 0.2 per
//! unit²), which must come back as not strip-shaped.

use std::time::Instant;

use ridgeline::Params;
use ridgeline_testkit::synth::{helix_tube, sine_strip, uniform_cloud};

/// CPU time of this process's live threads, in ms, where Linux reports it.
fn cpu_ms() -> Option<f64> {
    let mut total = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let stat = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
        total += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(total as f64 / 1e6)
}

fn show(ms: Option<f64>) -> String {
    ms.map_or("-".to_string(), |ms| format!("{ms:.1}"))
}

/// The command line: `[MAX_EXPONENT] [--from EXPONENT] [--seed S] [--only plane|space|cloud]`.
struct Options {
    from: u32,
    to: u32,
    seed: u64,
    only: Option<String>,
    inspect: bool,
    write: Option<String>,
}

fn options() -> Options {
    let mut options = Options {
        from: 3,
        to: 6,
        seed: 7,
        only: None,
        inspect: false,
        write: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .unwrap_or_else(|| panic!("{name} needs a value (see --help)"))
        };
        match arg.as_str() {
            "--from" => options.from = value("--from").parse().expect("--from EXPONENT"),
            "--seed" => options.seed = value("--seed").parse().expect("--seed S"),
            "--only" => options.only = Some(value("--only")),
            "--inspect" => options.inspect = true,
            "--write" => options.write = Some(value("--write")),
            "-h" | "--help" => {
                println!(
                    "point_speed [MAX_EXPONENT (6)] [--from EXPONENT (3)] [--seed S (7)] [--only plane|space|cloud] [--inspect] [--write FILE]\n\
                     --inspect: where the plane's graph is not one curve, its vertices, edges and the half-widths around them\n\
                     --write FILE: write the largest plane set as `x y` lines and stop"
                );
                std::process::exit(0);
            }
            exponent => options.to = exponent.parse().expect("MAX_EXPONENT"),
        }
    }
    options
}

/// Where a strip's graph is not one curve: its vertices and edges, and the half-widths of the
/// points around each vertex of degree other than 1, in bins of 4 units along x.
fn inspect(plane: &[[f64; 2]], graph: &ridgeline::StrokeGraph, params: &Params) {
    for (i, v) in graph.vertices.iter().enumerate() {
        println!(
            "vertex {i}: ({:.1}, {:.1}) degree {} width {:.2}",
            v.pos[0], v.pos[1], v.degree, v.width
        );
    }
    for e in &graph.edges {
        let length: f64 = e
            .points
            .windows(2)
            .map(|w| ridgeline::dist(w[0], w[1]))
            .sum();
        println!(
            "edge {} - {}: {} points, length {length:.1}",
            e.from,
            e.to,
            e.points.len()
        );
    }
    let set = ridgeline::point_list::point_set(plane, params).expect("point set");
    for v in graph.vertices.iter().filter(|v| v.degree != 1) {
        println!(
            "around ({:.1}, {:.1}): x bin, points, median half-width, spread of y",
            v.pos[0], v.pos[1]
        );
        for bin in -10..=10 {
            let (lo, hi) = (
                v.pos[0] + bin as f64 * 4.0,
                v.pos[0] + (bin + 1) as f64 * 4.0,
            );
            let mut h: Vec<f32> = Vec::new();
            let mut ys: Vec<f64> = Vec::new();
            for (p, w) in set.points.iter().zip(&set.half_width) {
                if p[0] >= lo && p[0] < hi && (p[1] - v.pos[1]).abs() < 40.0 {
                    h.push(*w);
                    ys.push(p[1]);
                }
            }
            h.sort_by(f32::total_cmp);
            ys.sort_by(f64::total_cmp);
            if !h.is_empty() {
                println!(
                    "  {lo:.0}..{hi:.0}: {} points, half-width {:.2} (min {:.2}, max {:.2}), y {:.1}..{:.1}",
                    h.len(),
                    h[h.len() / 2],
                    h[0],
                    h[h.len() - 1],
                    ys[0],
                    ys[ys.len() - 1]
                );
            }
        }
    }
}

fn main() {
    let options = options();
    let wants = |what: &str| options.only.as_deref().is_none_or(|o| o == what);
    let params = Params::default();
    if let Some(path) = &options.write {
        let plane = sine_strip(10usize.pow(options.to), options.seed);
        let text: String = plane
            .iter()
            .map(|p| format!("{} {}\n", p[0], p[1]))
            .collect();
        std::fs::write(path, text).expect("write the points");
        return;
    }
    println!(
        "| points | plane ms | plane CPU ms | plane stages ms (points / §3.1 / §3.2 / §3.3 / §3.4) | plane vertices / edges | space ms | space CPU ms | space vertices / edges |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for exponent in options.from..=options.to {
        if !wants("plane") && !wants("space") {
            break;
        }
        let count = 10usize.pow(exponent);
        let runs = if count <= 100_000 { 3 } else { 1 };
        // Only the sets that are traced are made.
        let plane = if wants("plane") {
            sine_strip(count, options.seed)
        } else {
            Vec::new()
        };
        let space = if wants("space") {
            helix_tube(count, options.seed)
        } else {
            Vec::new()
        };
        let mut best = [f64::INFINITY; 2];
        let mut cpu: [Option<f64>; 2] = [None; 2];
        let least = |old: Option<f64>, new: Option<f64>| match (old, new) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        let mut counts = [(0, 0); 2];
        let mut stages = String::new();
        for _ in 0..runs {
            if !wants("plane") {
                break;
            }
            let (start, cpu_start) = (Instant::now(), cpu_ms());
            let trace = ridgeline::trace_points(&plane, &params).expect("plane");
            best[0] = best[0].min(start.elapsed().as_secs_f64() * 1e3);
            cpu[0] = least(cpu[0], cpu_ms().zip(cpu_start).map(|(b, a)| b - a));
            counts[0] = (trace.graph.vertices.len(), trace.graph.edges.len());
            if options.inspect && counts[0] != (2, 1) {
                inspect(&plane, &trace.graph, &params);
            }
            let t = &trace.timings;
            stages = format!(
                "{:.0} / {:.0} / {:.0} / {:.0} / {:.0}",
                t.points.as_secs_f64() * 1e3,
                t.sampling.as_secs_f64() * 1e3,
                t.graph.as_secs_f64() * 1e3,
                t.refine.as_secs_f64() * 1e3,
                t.fit.as_secs_f64() * 1e3
            );
        }
        for _ in 0..runs {
            if !wants("space") {
                break;
            }
            let (start, cpu_start) = (Instant::now(), cpu_ms());
            let trace = ridgeline::trace_points3d(&space, &params).expect("space");
            best[1] = best[1].min(start.elapsed().as_secs_f64() * 1e3);
            cpu[1] = least(cpu[1], cpu_ms().zip(cpu_start).map(|(b, a)| b - a));
            counts[1] = (trace.graph.vertices.len(), trace.graph.edges.len());
        }
        println!(
            "| {count} | {:.1} | {} | {stages} | {} / {} | {:.1} | {} | {} / {} |",
            best[0],
            show(cpu[0]),
            counts[0].0,
            counts[0].1,
            best[1],
            show(cpu[1]),
            counts[1].0,
            counts[1].1
        );
    }
    if !wants("cloud") {
        return;
    }
    let cloud = uniform_cloud(200_000, 1000.0, 3);
    let (start, cpu_start) = (Instant::now(), cpu_ms());
    let trace = ridgeline::trace_points(&cloud, &params).expect("cloud");
    let wall = start.elapsed().as_secs_f64() * 1e3;
    let cpu = cpu_ms().zip(cpu_start).map(|(b, a)| b - a);
    println!(
        "\nuniform cloud of 200000 points: {wall:.1} ms ({} ms CPU), {} vertices, warnings: {}",
        show(cpu),
        trace.graph.vertices.len(),
        trace
            .warnings
            .iter()
            .map(|w| w.code.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
}
