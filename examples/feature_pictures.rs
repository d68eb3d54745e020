//! The pictures of the README's feature section (docs/design.md, "Beyond the paper"), made by the
//! project's own code: a generated case is traced, its strokes, widths, minutiae or curves are
//! drawn by the SVG writer exactly as `ridgeline --strokes` (and friends) would, and resvg renders
//! the SVG to a PNG.
//!
//! ```text
//! cargo run --example feature_pictures [-- OUTPUT_DIR]     # default: docs/features
//! ```
//!
//! Writes `strokes.png` (a Hershey text line of the benchmark, one color per stroke: crossings
//! run straight through), `width.png` (the same line drawn with each edge's mean width over the ink),
//! `minutiae.png` (a synthetic print with its ridge endings and bifurcations) and `curves.png`
//! (each stroke as cubic Bézier paths instead of a polyline).

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context, Result};
use ridgeline::curves::{fit_beziers, CurveOptions};
use ridgeline::export::svg::{self, Backdrop, SvgOptions};
use ridgeline::export::Features;
use ridgeline::minutiae::{minutiae, MinutiaeOptions};
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::{Binary, GrayImage, Params, StrokeGraph};
use ridgeline_testkit::synth::{print_cases, text_cases, text_line, Case};

fn main() -> Result<()> {
    let out = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/features"));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let params = Params::default();

    // Strokes through crossings: a benchmark text line with a crossing (x) and T's (f, j).
    let text = text_cases()
        .into_iter()
        .find(|c| c.name == "text1_h56_w7")
        .ok_or_else(|| anyhow!("no text1_h56_w7 text case"))?;
    let graph = trace(&text, &params)?;
    let chained = strokes(&graph, &StrokeOptions::default());
    let options = SvgOptions::default()
        .with_show_vertices(false)
        .with_stroke_width(Some(2.0));
    let features = Features::default().with_strokes(Some(&chained));
    let picture = svg::to_string_with(
        &graph,
        Some(Backdrop::Gray(&gray(&text.binary))),
        &options,
        &features,
    );
    save(&picture, 2.0, &out.join("strokes.png"))?;
    println!(
        "strokes.png: {} edges chained into {} strokes",
        graph.edges.len(),
        chained.len()
    );

    // Width along the centerline: each edge as wide as its mean width covers the ink.
    let options = SvgOptions::default()
        .with_show_vertices(false)
        .with_show_widths(true);
    let picture = svg::to_string_with(
        &graph,
        Some(Backdrop::Gray(&gray(&text.binary))),
        &options,
        &Features::default(),
    );
    save(&picture, 2.0, &out.join("width.png"))?;
    println!(
        "width.png: coverage IoU {:.3}",
        ridgeline::strokes::coverage_iou(&graph, &text.binary)
    );

    // Minutiae on a synthetic print with one ridge ending and one bifurcation.
    let print = print_cases()
        .into_iter()
        .find(|c| c.name.ends_with("_arch_minutiae"))
        .ok_or_else(|| anyhow!("no arch_minutiae print case"))?;
    let graph = trace(&print, &params)?;
    let found = minutiae(&graph, Some(&print.binary), &MinutiaeOptions::default());
    let features = Features::default().with_minutiae(Some(&found));
    let options = SvgOptions::default().with_show_vertices(false);
    let picture = svg::to_string_with(
        &graph,
        Some(Backdrop::Gray(&gray(&print.binary))),
        &options,
        &features,
    );
    save(&picture, 3.0, &out.join("minutiae.png"))?;
    println!("minutiae.png: {} minutiae", found.len());

    // Smooth curves: Bézier paths per stroke instead of polylines.
    let word = text_line("curves", "Sphinx of quartz", 56.0, 5.0);
    let graph = trace(&word, &params)?;
    let chained = strokes(&graph, &StrokeOptions::default());
    let curve = CurveOptions::default();
    let curves: Vec<_> = chained
        .iter()
        .map(|s| fit_beziers(&s.points, curve.tolerance, curve.corner_angle_deg))
        .collect();
    let features = Features::default()
        .with_strokes(Some(&chained))
        .with_curves(Some(&curves));
    let options = SvgOptions::default()
        .with_show_vertices(false)
        .with_stroke_width(Some(2.0));
    let picture = svg::to_string_with(
        &graph,
        Some(Backdrop::Gray(&gray(&word.binary))),
        &options,
        &features,
    );
    save(&picture, 2.0, &out.join("curves.png"))?;
    let points: usize = chained.iter().map(|s| s.points.len()).sum();
    let segments: usize = curves.iter().map(Vec::len).sum();
    println!("curves.png: {points} polyline points as {segments} cubic segments");
    Ok(())
}

/// Traces a case's foreground.
fn trace(case: &Case, params: &Params) -> Result<StrokeGraph> {
    let trace = ridgeline::trace_binary(&case.binary, params)?;
    trace
        .graph
        .validate()
        .map_err(|e| anyhow!("{}: {e}", case.name))?;
    Ok(trace.graph)
}

/// The mask as a light gray page with darker gray ink, so that colored lines stand out on it.
fn gray(binary: &Binary) -> GrayImage {
    GrayImage::from_fn(binary.width, binary.height, |x, y| {
        image::Luma([if binary.get(x as i64, y as i64) {
            150
        } else {
            250
        }])
    })
}

/// Renders `svg` with resvg at `scale` on white and saves it as a PNG.
fn save(svg: &str, scale: f32, path: &Path) -> Result<()> {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default())?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * scale).ceil() as u32,
        (size.height() * scale).ceil() as u32,
    );
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h).ok_or_else(|| anyhow!("empty picture"))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    // On an opaque white background premultiplied RGBA is plain RGBA.
    let image = image::RgbaImage::from_raw(w, h, pixmap.data().to_vec())
        .ok_or_else(|| anyhow!("pixmap size"))?;
    image
        .save(path)
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
