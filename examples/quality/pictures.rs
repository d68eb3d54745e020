//! `--pictures DIR`: one PNG per case, side by side (one above the other for wide cases) the truth
//! graph and each method's graph over
//! the case's ink (gray), edges dark, junctions red, ends blue, two screen pixels per image pixel
//! for small cases. For looking at what a table row counts.

use std::path::Path;

use anyhow::Context;
use image::{Rgb, RgbImage};
use ridgeline::StrokeGraph;
use ridgeline_testkit::synth::Case;

const INK: Rgb<u8> = Rgb([205, 205, 205]);
const PAPER: Rgb<u8> = Rgb([255, 255, 255]);
const EDGE: Rgb<u8> = Rgb([20, 110, 40]);
const JUNCTION: Rgb<u8> = Rgb([220, 20, 20]);
const END: Rgb<u8> = Rgb([20, 60, 230]);

/// Writes `DIR/<case>.png`: the truth, then one panel per method (empty when it failed).
pub fn write(
    dir: &Path,
    case: &Case,
    truth: &StrokeGraph,
    methods: &[&str],
    graphs: &[Option<StrokeGraph>],
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let b = &case.binary;
    // QUALITY_PICTURE_SCALE=N magnifies the panels N times (to look at single pixels).
    let scale = std::env::var("QUALITY_PICTURE_SCALE")
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
        .filter(|&s| (1..=16).contains(&s))
        .unwrap_or(if b.width.max(b.height) <= 500 { 2 } else { 1 });
    let (pw, ph) = (b.width * scale, b.height * scale);
    let panels = 1 + methods.len() as u32;
    let gap = 4;
    let stacked = pw > ph;
    let (cols, rows) = if stacked { (1, panels) } else { (panels, 1) };
    let mut out = RgbImage::from_pixel(cols * (pw + gap), rows * (ph + gap), Rgb([90, 90, 90]));
    let all = std::iter::once(Some(truth)).chain(graphs.iter().map(Option::as_ref));
    for (k, graph) in all.enumerate() {
        let (x0, y0) = if stacked {
            (0, k as u32 * (ph + gap))
        } else {
            (k as u32 * (pw + gap), 0)
        };
        for y in 0..ph {
            for x in 0..pw {
                let ink = b.get((x / scale) as i64, (y / scale) as i64);
                out.put_pixel(x0 + x, y0 + y, if ink { INK } else { PAPER });
            }
        }
        let Some(graph) = graph else { continue };
        let mut plot = |p: [f64; 2], color: Rgb<u8>, radius: i64| {
            let (cx, cy) = (
                (p[0] * scale as f64).floor() as i64,
                (p[1] * scale as f64).floor() as i64,
            );
            for dy in -radius..=radius {
                for dx in -radius..=radius {
                    let (x, y) = (cx + dx, cy + dy);
                    if dx * dx + dy * dy <= radius * radius
                        && x >= 0
                        && y >= 0
                        && x < pw as i64
                        && y < ph as i64
                    {
                        out.put_pixel(x0 + x as u32, y0 + y as u32, color);
                    }
                }
            }
        };
        for e in &graph.edges {
            for w in e.points.windows(2) {
                let n = (ridgeline::dist(w[0], w[1]) * scale as f64 * 2.0)
                    .ceil()
                    .max(1.0) as usize;
                for i in 0..=n {
                    let t = i as f64 / n as f64;
                    let p = [
                        w[0][0] + t * (w[1][0] - w[0][0]),
                        w[0][1] + t * (w[1][1] - w[0][1]),
                    ];
                    if p[0].is_finite() && p[1].is_finite() {
                        plot(p, EDGE, 0);
                    }
                }
            }
        }
        for v in &graph.vertices {
            match v.degree {
                1 => plot(v.pos, END, 2),
                d if d >= 3 => plot(v.pos, JUNCTION, 2),
                _ => {}
            }
        }
    }
    let path = dir.join(format!("{}.png", case.name));
    out.save(&path)
        .with_context(|| format!("writing {}", path.display()))
}
