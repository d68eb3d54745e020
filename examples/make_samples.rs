//! Writes the sample images in `samples/` from the synthetic fixtures (`ridgeline_testkit::synth`).
//!
//! ```text
//! cargo run --example make_samples            # samples/*.png
//! cargo run --example make_samples -- DIR     # also every fixture case as DIR/<name>.png
//! ```

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{GrayImage, ImageEncoder};
use ridgeline::Binary;
use ridgeline_testkit::synth::{self, Case, Stroke};
use std::path::Path;

/// Ink as 0 on 255 (or the reverse with `light_on_dark`), 8-bit gray.
fn to_gray(binary: &Binary, light_on_dark: bool) -> GrayImage {
    let (ink, paper) = if light_on_dark { (255, 0) } else { (0, 255) };
    let pixels = binary
        .ink
        .iter()
        .map(|&i| if i { ink } else { paper })
        .collect();
    GrayImage::from_raw(binary.width, binary.height, pixels).unwrap_or_default()
}

fn save(gray: &GrayImage, path: &Path) -> anyhow::Result<()> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    // Maximum compression: the samples are committed, two-level images compress very well.
    let encoder = PngEncoder::new_with_quality(file, CompressionType::Best, FilterType::Adaptive);
    encoder.write_image(
        gray.as_raw(),
        gray.width(),
        gray.height(),
        image::ExtendedColorType::L8,
    )?;
    println!(
        "wrote {} ({}x{})",
        path.display(),
        gray.width(),
        gray.height()
    );
    Ok(())
}

fn find<'a>(cases: &'a [Case], name: &str) -> anyhow::Result<&'a Case> {
    cases
        .iter()
        .find(|c| c.name == name)
        .ok_or_else(|| anyhow::anyhow!("no fixture named {name}"))
}

/// A character-like figure with many crossings: '#' laid over a ring, crossed by a diagonal.
fn crossings() -> Case {
    let w = 6.0;
    let (r, g, s) = (60.0, 22.0, 78.0);
    let ring: Vec<[f64; 2]> = (0..=400)
        .map(|i| {
            let t = i as f64 / 400.0 * std::f64::consts::TAU;
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    let strokes = vec![
        Stroke::new(ring, w),
        Stroke::new(vec![[-s, -g], [s, -g]], w),
        Stroke::new(vec![[-s, g], [s, g]], w),
        Stroke::new(vec![[-g, -s], [-g, s]], w),
        Stroke::new(vec![[g, -s], [g, s]], w),
        Stroke::new(vec![[-s, s], [s, -s]], w),
    ];
    synth::frame("crossings", "samples", strokes, 2.0 * w + 4.0)
}

fn main() -> anyhow::Result<()> {
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("samples");
    std::fs::create_dir_all(&out)?;

    let text = synth::text_line("text", "Sphinx of black quartz, judge my vow.", 40.0, 4.0);
    save(&to_gray(&text.binary, false), &out.join("text.png"))?;
    save(
        &to_gray(&crossings().binary, false),
        &out.join("crossings.png"),
    )?;

    // Light ridges on a dark background, to exercise polarity detection.
    let prints = synth::print_cases();
    let print = find(&prints, "print5_arch_minutiae")?;
    save(&to_gray(&print.binary, true), &out.join("fingerprint.png"))?;

    let hard = synth::hard_cases();
    for (file, name) in [
        ("x30", "x30_w8"),
        ("t", "t_w8"),
        ("circle", "circle"),
        ("figure8", "figure8"),
        ("parallel3", "parallel3"),
        ("width3x", "width3x"),
        ("dropout30", "dropout30"),
        ("parts", "parts"),
    ] {
        save(
            &to_gray(&find(&hard, name)?.binary, false),
            &out.join(format!("{file}.png")),
        )?;
    }

    // Optionally every fixture, for looking at them.
    if let Some(dir) = std::env::args().nth(1) {
        let dir = Path::new(&dir);
        std::fs::create_dir_all(dir)?;
        for case in synth::all_cases() {
            save(
                &to_gray(&case.binary, false),
                &dir.join(format!("{}.png", case.name)),
            )?;
        }
    }
    Ok(())
}
