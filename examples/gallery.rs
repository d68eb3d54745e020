//! The gallery: ridgeline run on every image in `samples/`, each shown as input beside result.
//!
//! ```sh
//! cargo run --release --example gallery [-- OUTDIR]
//! ```
//!
//! Writes `OUTDIR/<name>.png` (default `docs/gallery`) for every image in `samples/`: the input on
//! the left (or on top, for wide images), and on the right the SVG that ridgeline writes, rendered
//! with resvg — centerlines red, endpoints green, junctions blue, over the image. It also writes the
//! `--debug` pictures of one sample into `OUTDIR/stages/`, for the README.
//!
//! When `../shared/data/{text,fingerprints}` exists (real scans, not part of this repository), their
//! images are traced too and written to `target/gallery-shared/`: they are read in place and never
//! copied into the repository.
//!
//! It also writes `OUTDIR/fingerprint-minutiae.png`, for the README's fingerprint section: a
//! synthetic print of the test kit (`dense_print_cases`) captured blurred, unevenly lit, noised and
//! JPEG-compressed, traced with `--fingerprint`: the capture, the enhanced image, and the ridges
//! with the minutiae over it (endings red circles, bifurcations blue squares, a line along each
//! one's direction).
//!
//! And `OUTDIR/points-figure8.png`, for the README's point-set section: the test kit's figure 8 of
//! random points in a strip 8 units wide (`strip_cases`), the points on the left and the traced
//! graph over them on the right.
//!
//! Prints one line per image: size, ink pixels, vertices, edges, endpoints, junctions, time.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{anyhow, Context, Result};
use image::imageops::{self, FilterType};
use image::{GrayImage, Rgb, RgbImage};
use resvg::{tiny_skia, usvg};
use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::{Params, StrokeGraph};

/// The combined picture is at most about this wide.
const MAX_WIDTH: u32 = 1200;
/// Nor taller than this per panel.
const MAX_PANEL_HEIGHT: u32 = 1000;
/// Pixels per unit of the point-set picture's drawing, and its margin around the points (units).
const POINTS_SCALE: f64 = 2.0;
const POINTS_MARGIN: f64 = 6.0;
/// Small images are enlarged at most this much.
const MAX_UPSCALE: f64 = 4.0;
/// Enlargement of the detail pictures.
const DETAIL_SCALE: f64 = 3.0;
/// White space between and around the panels.
const GAP: u32 = 8;
/// The sample whose stage pictures go into `OUTDIR/stages/`.
const STAGES_SAMPLE: &str = "crossings";

const IMAGE_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp"];

fn main() -> Result<()> {
    let out_dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("docs/gallery"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let params = Params::default();

    println!(
        "{:<44} {:>11} {:>8} {:>6} {:>6} {:>5} {:>5} {:>8}",
        "image", "size", "ink", "verts", "edges", "ends", "junc", "ms"
    );
    for input in images_in(&root.join("samples"))? {
        let stages = input.file_stem().is_some_and(|s| s == STAGES_SAMPLE);
        let stage_dir = stages.then(|| out_dir.join("stages"));
        show(&input, &out_dir, &params, stage_dir.as_deref())?;
    }

    show_print(&out_dir)?;
    show_points(&out_dir)?;

    let shared = root.join("../shared/data");
    // Default parameters everywhere: the gallery shows what a first run gives.
    for group in ["text", "fingerprints"] {
        let dir = shared.join(group);
        if !dir.is_dir() {
            continue;
        }
        let out = root.join("target/gallery-shared").join(group);
        for input in images_in(&dir)? {
            // One unreadable scan should not hide the others.
            if let Err(err) = show(&input, &out, &params, None) {
                println!("{}: {err:#}", input.display());
            }
        }
    }
    Ok(())
}

/// The images directly in `dir`, sorted by name; none when `dir` does not exist.
fn images_in(dir: &Path) -> Result<Vec<PathBuf>> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut found: Vec<PathBuf> = fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| {
            path.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| IMAGE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
        })
        .collect();
    found.sort();
    Ok(found)
}

/// Traces `input` and writes `<out_dir>/<stem>.png`, input beside result; with `stage_dir`, also
/// the stage pictures.
fn show(input: &Path, out_dir: &Path, params: &Params, stage_dir: Option<&Path>) -> Result<()> {
    let bytes = fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    let gray = ridgeline::decode(&bytes, &params.front_end.limits)?;
    let clock = Instant::now();
    let trace = ridgeline::trace_image(&gray, params)?;
    let elapsed = clock.elapsed();
    let graph = &trace.graph;
    let ink = trace.binary.as_ref().map_or(0, |b| b.count());
    println!(
        "{:<44} {:>11} {:>8} {:>6} {:>6} {:>5} {:>5} {:>8.1}",
        input.file_name().unwrap_or_default().to_string_lossy(),
        format!("{}x{}", gray.width(), gray.height()),
        ink,
        graph.vertices.len(),
        graph.edges.len(),
        graph.endpoints().count(),
        graph.junctions().count(),
        elapsed.as_secs_f64() * 1e3,
    );

    let (w, h) = gray.dimensions();
    let stacked = w > 2 * h;
    let panel_width = if stacked {
        MAX_WIDTH - 2 * GAP
    } else {
        (MAX_WIDTH - 3 * GAP) / 2
    };
    let scale = panel_scale(w, h, panel_width);
    let tree = svg_tree(graph, &gray, scale)?;
    fs::create_dir_all(out_dir).with_context(|| format!("cannot create {}", out_dir.display()))?;
    let stem = input.file_stem().unwrap_or_default().to_string_lossy();
    let whole = [0, 0, w, h];
    let picture = side_by_side(&gray, &tree, whole, scale, stacked)?;
    save(&picture, &out_dir.join(format!("{stem}.png")))?;

    // When the whole image had to be shown at less than 2x, a detail from its middle at
    // DETAIL_SCALE shows what the centerlines do inside the strokes.
    if scale < 2.0 {
        let side = |n: u32, limit: u32| n.min((limit as f64 / DETAIL_SCALE) as u32);
        let (cw, ch) = (side(w, panel_width), side(h, MAX_PANEL_HEIGHT / 2));
        let window = [(w - cw) / 2, (h - ch) / 2, cw, ch];
        let tree = svg_tree(graph, &gray, DETAIL_SCALE)?;
        let detail = side_by_side(&gray, &tree, window, DETAIL_SCALE, stacked)?;
        save(&detail, &out_dir.join(format!("{stem}-detail.png")))?;
    }

    if let Some(dir) = stage_dir {
        let binary = trace
            .binary
            .as_ref()
            .ok_or_else(|| anyhow!("no foreground for {}", input.display()))?;
        let staged = ridgeline::trace_binary_with_stages(binary, params)?;
        let stages = staged
            .stages
            .as_ref()
            .ok_or_else(|| anyhow!("stages not kept"))?;
        fs::create_dir_all(dir)?;
        for picture in ridgeline::debug::stage_pngs(binary, stages, &staged.graph) {
            let (name, png) = picture?;
            fs::write(dir.join(name), png)?;
        }
    }
    Ok(())
}

/// The README's point-set picture: the figure 8 of random points of the quality example's point
/// group, drawn as dots at [`POINTS_SCALE`] pixels per unit, and its graph traced from the points
/// (not from the drawing) over them.
fn show_points(out_dir: &Path) -> Result<()> {
    let case = ridgeline_testkit::synth::strip_cases()
        .into_iter()
        .find(|c| c.name == "figure8")
        .ok_or_else(|| anyhow!("the test kit has no figure8 strip case"))?;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &case.points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Image coordinates: a margin of POINTS_MARGIN units around the points.
    let at = |p: &[f64; 2]| {
        [
            (p[0] - lo[0] + POINTS_MARGIN) * POINTS_SCALE,
            (p[1] - lo[1] + POINTS_MARGIN) * POINTS_SCALE,
        ]
    };
    let points: Vec<[f64; 2]> = case.points.iter().map(at).collect();
    let [w, h] = at(&hi).map(|v| (v + POINTS_MARGIN * POINTS_SCALE).ceil() as u32);
    let mut gray = GrayImage::from_pixel(w, h, image::Luma([255]));
    for p in &points {
        let (x, y) = (p[0] as u32, p[1] as u32);
        if x < w && y < h {
            gray.put_pixel(x, y, image::Luma([90]));
        }
    }
    let clock = Instant::now();
    let trace = ridgeline::trace_points(&points, &Params::default())?;
    // The SVG's canvas is the graph's size, which for a point list is the points' extent: make it
    // the drawing's, so that the two line up.
    let mut graph = trace.graph;
    (graph.width, graph.height) = (w, h);
    let graph = &graph;
    println!(
        "{:<44} {:>11} {:>8} {:>6} {:>6} {:>5} {:>5} {:>8.1}",
        "figure8 (points)",
        format!("{w}x{h}"),
        points.len(),
        graph.vertices.len(),
        graph.edges.len(),
        graph.endpoints().count(),
        graph.junctions().count(),
        clock.elapsed().as_secs_f64() * 1e3,
    );
    let scale = panel_scale(w, h, (MAX_WIDTH - 3 * GAP) / 2);
    let tree = svg_tree(graph, &gray, scale)?;
    fs::create_dir_all(out_dir).with_context(|| format!("cannot create {}", out_dir.display()))?;
    let picture = side_by_side(&gray, &tree, [0, 0, w, h], scale, false)?;
    save(&picture, &out_dir.join("points-figure8.png"))
}

/// The README's fingerprint picture: a degraded synthetic print, its enhanced image, and the traced
/// ridges with the minutiae over the enhanced image, the middle of each at 2x.
fn show_print(out_dir: &Path) -> Result<()> {
    use ridgeline::export::svg::Backdrop;
    use ridgeline::export::Features;
    use ridgeline_testkit::synth::{degrade, dense_print_cases, Recipe, SplitMix64};

    let case = dense_print_cases()
        .into_iter()
        .find(|c| c.name.contains("loop"))
        .ok_or_else(|| anyhow!("the kit has a loop print"))?;
    let (w, h) = (case.binary.width, case.binary.height);
    let recipe = Recipe {
        inverted: false,
        paper: 215,
        ink: 70,
        blur: 1.2,
        falloff: 0.35,
        light_angle: 0.8,
        noise: 14.0,
        jpeg_quality: 70,
    };
    let gray = degrade(&case.strokes, w, h, &recipe, &mut SplitMix64::new(7));
    let trace = ridgeline::trace_image(&gray, &Params::fingerprint())?;
    let print = trace
        .fingerprint
        .as_ref()
        .ok_or_else(|| anyhow!("the fingerprint preset keeps its front end"))?;
    // The response, ridges dark and zero mid-gray, scaled by its 95th percentile.
    let values = &print.analysis.enhanced.values;
    let mut magnitudes: Vec<f32> = values
        .iter()
        .map(|v| v.abs())
        .filter(|&v| v > 0.0)
        .collect();
    magnitudes.sort_by(f32::total_cmp);
    let top = magnitudes
        .get(magnitudes.len() * 95 / 100)
        .copied()
        .unwrap_or(1.0)
        .max(1e-6);
    let enhanced = GrayImage::from_fn(w, h, |x, y| {
        let r = values[(y * w + x) as usize] / top;
        image::Luma([(128.0 - 127.0 * r.clamp(-1.0, 1.0)).round() as u8])
    });
    let features = Features::default().with_minutiae(Some(&print.minutiae));
    let options = SvgOptions::default()
        .with_show_vertices(false)
        .with_stroke_width(Some(0.8));
    let document = svg::to_string_with(
        &trace.graph,
        Some(Backdrop::Gray(&enhanced)),
        &options,
        &features,
    );
    let tree = usvg::Tree::from_str(&document, &usvg::Options::default())
        .context("resvg cannot parse the SVG")?;
    // 160 px of the print at 2x: about five ridge periods around the core each way.
    let scale = 2.0;
    let side = 160.min(w).min(h);
    let [x0, y0] = [(w - side) / 2, (h - side) / 2];
    let crop = |image: &GrayImage| imageops::crop_imm(image, x0, y0, side, side).to_image();
    let panels = [
        scaled_input(&crop(&gray), scale),
        scaled_input(&crop(&enhanced), scale),
        render_svg(
            &tree,
            [x0, y0],
            (side as f64 * scale) as u32,
            (side as f64 * scale) as u32,
            scale,
        )?,
    ];
    let (pw, ph) = panels[0].dimensions();
    let mut picture = RgbImage::from_pixel(3 * pw + 4 * GAP, ph + 2 * GAP, Rgb([255, 255, 255]));
    for (k, panel) in panels.iter().enumerate() {
        imageops::replace(
            &mut picture,
            panel,
            (GAP + k as u32 * (pw + GAP)) as i64,
            GAP as i64,
        );
    }
    fs::create_dir_all(out_dir)?;
    save(&picture, &out_dir.join("fingerprint-minutiae.png"))?;
    println!(
        "{:<44} {:>11} {:>8} {:>6} {:>6} minutiae {}",
        format!("synthetic print {} (degraded)", case.name),
        format!("{w}x{h}"),
        trace.binary.as_ref().map_or(0, |b| b.count()),
        trace.graph.vertices.len(),
        trace.graph.edges.len(),
        print.minutiae.len()
    );
    Ok(())
}

/// The SVG that ridgeline writes for `graph` over `gray`, parsed for rendering at `scale`: lines
/// stay at least about one output pixel wide when the picture is scaled down.
fn svg_tree(graph: &StrokeGraph, gray: &GrayImage, scale: f64) -> Result<usvg::Tree> {
    let line = svg::stroke_width(graph, &SvgOptions::default()).max(1.2 / scale);
    let document = svg::to_string(
        graph,
        Some(gray),
        &SvgOptions::default().with_stroke_width(Some(line)),
    );
    usvg::Tree::from_str(&document, &usvg::Options::default()).context("resvg cannot parse the SVG")
}

/// Output pixels per image pixel: enlarge small images by a whole factor (pixels stay sharp),
/// shrink large ones to fit `panel_width` x [`MAX_PANEL_HEIGHT`].
fn panel_scale(width: u32, height: u32, panel_width: u32) -> f64 {
    let fit = (panel_width as f64 / width.max(1) as f64)
        .min(MAX_PANEL_HEIGHT as f64 / height.max(1) as f64);
    if fit >= 1.0 {
        fit.floor().min(MAX_UPSCALE)
    } else {
        fit
    }
}

/// The part `window` (`[x, y, width, height]`, image px) of the input and of the rendered SVG at
/// `scale`, next to each other (or one above the other when `stacked`), with white margins.
fn side_by_side(
    gray: &GrayImage,
    tree: &usvg::Tree,
    window: [u32; 4],
    scale: f64,
    stacked: bool,
) -> Result<RgbImage> {
    let [x0, y0, cw, ch] = window;
    let crop = imageops::crop_imm(gray, x0, y0, cw, ch).to_image();
    let left = scaled_input(&crop, scale);
    let (w, h) = left.dimensions();
    let right = render_svg(tree, [x0, y0], w, h, scale)?;
    let (total_w, total_h) = if stacked {
        (w + 2 * GAP, 2 * h + 3 * GAP)
    } else {
        (2 * w + 3 * GAP, h + 2 * GAP)
    };
    let mut picture = RgbImage::from_pixel(total_w, total_h, Rgb([255, 255, 255]));
    imageops::replace(&mut picture, &left, GAP as i64, GAP as i64);
    let (x, y) = if stacked {
        (GAP, h + 2 * GAP)
    } else {
        (w + 2 * GAP, GAP)
    };
    imageops::replace(&mut picture, &right, x as i64, y as i64);
    Ok(picture)
}

fn save(picture: &RgbImage, path: &Path) -> Result<()> {
    picture
        .save(path)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// The input at `scale`, as RGB: nearest neighbour when enlarging, smoothed when shrinking.
fn scaled_input(gray: &GrayImage, scale: f64) -> RgbImage {
    let size = |n: u32| ((n as f64 * scale).round() as u32).max(1);
    let (w, h) = (size(gray.width()), size(gray.height()));
    let filter = if scale >= 1.0 {
        FilterType::Nearest
    } else {
        FilterType::Triangle
    };
    let scaled = imageops::resize(gray, w, h, filter);
    RgbImage::from_fn(w, h, |x, y| {
        let v = scaled.get_pixel(x, y).0[0];
        Rgb([v, v, v])
    })
}

/// The SVG rendered by resvg at `scale` into a `width` x `height` picture on white, its top-left
/// corner at image point `origin`.
fn render_svg(
    tree: &usvg::Tree,
    origin: [u32; 2],
    width: u32,
    height: u32,
    scale: f64,
) -> Result<RgbImage> {
    let mut pixmap =
        tiny_skia::Pixmap::new(width, height).ok_or_else(|| anyhow!("empty picture"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let (s, dx, dy) = (
        scale as f32,
        -(origin[0] as f64 * scale) as f32,
        -(origin[1] as f64 * scale) as f32,
    );
    resvg::render(
        tree,
        tiny_skia::Transform::from_row(s, 0.0, 0.0, s, dx, dy),
        &mut pixmap.as_mut(),
    );
    // The pixmap is opaque (filled white first), so its premultiplied RGBA is plain RGBA.
    let rgba = pixmap.data();
    Ok(RgbImage::from_fn(width, height, |x, y| {
        let i = 4 * (y as usize * width as usize + x as usize);
        Rgb([rgba[i], rgba[i + 1], rgba[i + 2]])
    }))
}
