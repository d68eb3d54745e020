//! Speed on point sets of 10^3 to 10^6 points, in the plane and in space: random points in a
//! band 8 units wide around a sine wave (`sine_strip`) and filling a helix tube 8 units across
//! (`helix_tube`), the curve growing with the count so the density stays that of the quality
//! benchmark's point group. Prints one table row per size: the best of a few runs, in ms, and the
//! graph's counts (one curve with two ends is right), and the CPU time of all threads (from
//! `/proc/self/task/*/schedstat` on Linux, `-` elsewhere): on a machine shared with other work
//! the wall time is that CPU time stretched by the load. A benchmark, not a test:
//! `cargo run --release --example point_speed [-- MAX_EXPONENT]`. Last, a uniform cloud of 200,000
//! points (no strip, density 0.2 per unit²), which must come back as not strip-shaped.

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

fn main() {
    let max_exponent: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(6);
    let params = Params::default();
    println!(
        "| points | plane ms | plane CPU ms | plane stages ms (points / §3.1 / §3.2 / §3.3 / §3.4) | plane vertices / edges | space ms | space CPU ms | space vertices / edges |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for exponent in 3..=max_exponent {
        let count = 10usize.pow(exponent);
        let runs = if count <= 100_000 { 3 } else { 1 };
        let plane = sine_strip(count, 7);
        let space = helix_tube(count, 7);
        let mut best = [f64::INFINITY; 2];
        let mut cpu: [Option<f64>; 2] = [None; 2];
        let least = |old: Option<f64>, new: Option<f64>| match (old, new) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        let mut counts = [(0, 0); 2];
        let mut stages = String::new();
        for _ in 0..runs {
            let (start, cpu_start) = (Instant::now(), cpu_ms());
            let trace = ridgeline::trace_points(&plane, &params).expect("plane");
            best[0] = best[0].min(start.elapsed().as_secs_f64() * 1e3);
            cpu[0] = least(cpu[0], cpu_ms().zip(cpu_start).map(|(b, a)| b - a));
            counts[0] = (trace.graph.vertices.len(), trace.graph.edges.len());
            let t = &trace.timings;
            stages = format!(
                "{:.0} / {:.0} / {:.0} / {:.0} / {:.0}",
                t.points.as_secs_f64() * 1e3,
                t.sampling.as_secs_f64() * 1e3,
                t.graph.as_secs_f64() * 1e3,
                t.refine.as_secs_f64() * 1e3,
                t.fit.as_secs_f64() * 1e3
            );
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
