//! Speed on point sets of 10^3 to 10^6 points, in the plane and in space: random points in a
//! band 8 units wide around a sine wave (`sine_strip`) and filling a helix tube 8 units across
//! (`helix_tube`), the curve growing with the count so the density stays that of the quality
//! benchmark's point group. Prints one table row per size: the best of a few runs, in ms, and the
//! graph's counts (one curve with two ends is right). A benchmark, not a test:
//! `cargo run --release --example point_speed [-- MAX_EXPONENT]`.

use std::time::Instant;

use ridgeline::Params;
use ridgeline_testkit::synth::{helix_tube, sine_strip};

fn main() {
    let max_exponent: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(6);
    let params = Params::default();
    println!(
        "| points | plane ms | plane stages ms (points / §3.1 / §3.2 / §3.3 / §3.4) | plane vertices / edges | space ms | space vertices / edges |"
    );
    println!("|---|---|---|---|---|---|");
    for exponent in 3..=max_exponent {
        let count = 10usize.pow(exponent);
        let runs = if count <= 100_000 { 3 } else { 1 };
        let plane = sine_strip(count, 7);
        let space = helix_tube(count, 7);
        let mut best = [f64::INFINITY; 2];
        let mut counts = [(0, 0); 2];
        let mut stages = String::new();
        for _ in 0..runs {
            let start = Instant::now();
            let trace = ridgeline::trace_points(&plane, &params).expect("plane");
            best[0] = best[0].min(start.elapsed().as_secs_f64() * 1e3);
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
            let start = Instant::now();
            let trace = ridgeline::trace_points3d(&space, &params).expect("space");
            best[1] = best[1].min(start.elapsed().as_secs_f64() * 1e3);
            counts[1] = (trace.graph.vertices.len(), trace.graph.edges.len());
        }
        println!(
            "| {count} | {:.1} | {stages} | {} / {} | {:.1} | {} / {} |",
            best[0], counts[0].0, counts[0].1, best[1], counts[1].0, counts[1].1
        );
    }
}
