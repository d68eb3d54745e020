//! Pictures of every stage (`--debug DIR`), in the spirit of the paper's Figure 1: what the
//! pipeline saw and decided at each step, so that a bad result can be traced to the stage that
//! made it.
//!
//! | file | shows |
//! |---|---|
//! | `1-foreground.png` | the binarized foreground: ink dark gray on white |
//! | `2-sampling.png` | §3.1: the points tinted by the node that owns them (the partition `P_i`), each node's disk of radius `r_i` around its barycenter; linear nodes blue, non-linear nodes orange |
//! | `3-node-graph.png` | §3.2: graph `H` (edges dark gray), linear nodes gray, non-linear nodes in one color per cluster |
//! | `4-refined.png` | §3.3: the 1-D graph after contraction, merging and clean-up; nodes of degree 1 green, degree ≥ 3 blue, others dark |
//! | `5-fitted.png` | §3.4: the fitted polylines, one color per edge, with their points as dots |
//! | `6-final.png` | the stroke graph over the foreground: centerlines red, endpoints green, junctions blue (the SVG's colors) |
//!
//! With `--fingerprint`, the front end's stages come first ([`print_pictures`]):
//! `0-segmentation.png` (outside the print tinted orange), `0-orientation.png` (a line along the
//! ridges per block, dark where coherent) and `0-enhanced.png` (the Gabor response, ridges dark);
//! the stage pictures above are then those of the enhanced image's binarization.
//!
//! The paper shows contraction and merging as two panels; the pipeline keeps only the graph after
//! all of §3.3 ([`Stages::refined`]), so both are one picture here.
//!
//! Pictures are upscaled by a whole factor (pixels stay sharp squares) so that the longer side is
//! at least [`MIN_LONG_SIDE`] px, at most [`MAX_UPSCALE`] times, and never beyond
//! [`MAX_PICTURE_PIXELS`]; an image larger than that is drawn scaled down instead.

use std::io::Cursor;

use image::{ImageFormat, Rgb, RgbImage};
use imageproc::drawing::{
    draw_filled_circle_mut, draw_hollow_circle_mut, draw_line_segment_mut, draw_polygon_mut,
};
use imageproc::point::Point;

use crate::binary::Binary;
use crate::decisions::{Decisions, ThresholdUsed};
use crate::error::{Error, Result};
use crate::export::svg::{EDGE_COLOR, ENDPOINT_COLOR, JUNCTION_COLOR};
use crate::fingerprint::PrintAnalysis;
use crate::pipeline::Stages;
use crate::stroke_graph::StrokeGraph;
use image::GrayImage;

/// Pictures are upscaled until their longer side reaches this many pixels (within the limits
/// below).
pub const MIN_LONG_SIDE: u32 = 800;
/// Largest upscale factor.
pub const MAX_UPSCALE: u32 = 4;
/// Largest picture, in pixels: upscaling stops below it, and larger images are drawn scaled down.
pub const MAX_PICTURE_PIXELS: u64 = 16_000_000;

/// File names of the pictures, in pipeline order.
pub const PICTURE_NAMES: [&str; 6] = [
    "1-foreground.png",
    "2-sampling.png",
    "3-node-graph.png",
    "4-refined.png",
    "5-fitted.png",
    "6-final.png",
];

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
/// Ink in the foreground picture.
const INK: Rgb<u8> = Rgb([70, 70, 70]);
/// Ink as the backdrop of the graph pictures: light enough that lines and dots stand out.
const BACKDROP: Rgb<u8> = Rgb([218, 218, 218]);
const LINEAR: Rgb<u8> = Rgb([31, 119, 180]);
const NON_LINEAR: Rgb<u8> = Rgb([255, 127, 14]);
const GRAPH_EDGE: Rgb<u8> = Rgb([80, 80, 80]);
const LINEAR_NODE: Rgb<u8> = Rgb([140, 140, 140]);
const CURVE: Rgb<u8> = Rgb([30, 30, 30]);
/// Isolated nodes and vertices (degree 0).
const ISOLATED: Rgb<u8> = Rgb([200, 0, 200]);

/// Distinct colors for clusters and edges, dark enough to stand out on the light gray ink
/// (after Sasha Trubetskoy's list, without the red, green and blue that mean edge, endpoint and
/// junction elsewhere).
const PALETTE: [Rgb<u8>; 12] = [
    Rgb([245, 130, 49]),
    Rgb([145, 30, 180]),
    Rgb([0, 160, 200]),
    Rgb([240, 50, 230]),
    Rgb([110, 190, 0]),
    Rgb([0, 128, 128]),
    Rgb([154, 99, 36]),
    Rgb([230, 180, 0]),
    Rgb([128, 0, 0]),
    Rgb([128, 128, 0]),
    Rgb([0, 0, 117]),
    Rgb([255, 105, 180]),
];

/// Picture pixels per image pixel for a `width` x `height` image: a whole number from 1 to
/// [`MAX_UPSCALE`] while the picture stays within [`MAX_PICTURE_PIXELS`], below 1 for images
/// larger than that.
pub fn picture_scale(width: u32, height: u32) -> f64 {
    let long = width.max(height).max(1);
    let area = (width.max(1) as u64) * (height.max(1) as u64);
    if area > MAX_PICTURE_PIXELS {
        return (MAX_PICTURE_PIXELS as f64 / area as f64).sqrt();
    }
    let mut scale = MIN_LONG_SIDE.div_ceil(long).clamp(1, MAX_UPSCALE);
    while scale > 1 && area * (scale as u64).pow(2) > MAX_PICTURE_PIXELS {
        scale -= 1;
    }
    scale as f64
}

/// Draws every stage; returns `(file name, picture)` pairs in pipeline order (the names of
/// [`PICTURE_NAMES`]). `stages` are the ones of the trace of `binary` that produced `graph` (see [`crate::trace_binary_with_stages`]).
pub fn stage_pictures(
    binary: &Binary,
    stages: &Stages,
    graph: &StrokeGraph,
) -> Vec<(String, RgbImage)> {
    let scene = Scene {
        binary,
        stages,
        graph,
    };
    (0..PICTURE_NAMES.len())
        .map(|stage| (PICTURE_NAMES[stage].to_string(), scene.draw(stage)))
        .collect()
}

/// The pictures of [`stage_pictures`] as the bytes of PNG files, named as in [`PICTURE_NAMES`]:
/// what `--debug DIR` writes (the caller does the writing). Each picture is drawn and encoded
/// only when the iterator reaches it, so a big page's pictures are not all in memory at once.
pub fn stage_pngs<'a>(
    binary: &'a Binary,
    stages: &'a Stages,
    graph: &'a StrokeGraph,
) -> impl Iterator<Item = Result<(&'static str, Vec<u8>)>> + 'a {
    let scene = Scene {
        binary,
        stages,
        graph,
    };
    PICTURE_NAMES.iter().enumerate().map(move |(stage, &name)| {
        let mut png = Vec::new();
        scene
            .draw(stage)
            .write_to(&mut Cursor::new(&mut png), ImageFormat::Png)
            .map_err(|err| Error::Encode(format!("{name}: {err}")))?;
        Ok((name, png))
    })
}

/// File name of the picture of the front end's decisions ([`decisions_png`]).
pub const DECISIONS_PICTURE: &str = "0-decisions.png";

/// Tint of the ink in the decisions picture.
const DECIDED_INK: Rgb<u8> = Rgb([0, 90, 220]);
/// Block grid of the local threshold.
const BLOCK_GRID: Rgb<u8> = Rgb([255, 150, 0]);
/// The outline of a region that is not strokes (left out of the trace unless kept) in the
/// decisions picture.
const REGION_OUTLINE: Rgb<u8> = Rgb([220, 0, 200]);
/// Outline of a reversed ground.
const GROUND_OUTLINE: Rgb<u8> = Rgb([0, 170, 60]);

/// The front end's decisions over the gray image it decided on (docs/design.md, "The front end"):
/// the gray pixels, the side taken as ink tinted blue (so a wrong polarity shows as tinted
/// paper), with the local threshold its blocks as an orange grid, and the reversed grounds
/// (polarity per region) outlined in green, the regions that are not strokes in magenta. Named
/// [`DECISIONS_PICTURE`] by `--debug`.
pub fn decisions_picture(gray: &GrayImage, binary: &Binary, decisions: &Decisions) -> RgbImage {
    let (w, h) = gray.dimensions();
    let mut canvas = Canvas::new(w, h);
    if binary.width != w || binary.height != h || binary.ink.len() != (w * h) as usize {
        return canvas.image;
    }
    let (out_w, out_h) = canvas.image.dimensions();
    let scale = canvas.scale;
    let source = |o: u32, n: u32| (((o as f64 + 0.5) / scale) as u32).min(n.max(1) - 1);
    let window = match decisions.threshold {
        ThresholdUsed::Local { window } => Some(window.max(1)),
        _ => None,
    };
    for y in 0..out_h {
        let sy = source(y, h);
        for x in 0..out_w {
            let sx = source(x, w);
            let v = gray.get_pixel(sx, sy).0[0];
            let mut color = Rgb([v, v, v]);
            if binary.ink[(sy * w + sx) as usize] {
                let blend = |a: u8, b: u8| ((a as u16 + b as u16) / 2) as u8;
                color = Rgb(std::array::from_fn(|k| blend(v, DECIDED_INK.0[k])));
            }
            if let Some(b) = window {
                // The first picture column (row) of every block's first image column (row).
                let on_grid =
                    |o: u32, s: u32, n: u32| s % b == 0 && (o == 0 || source(o - 1, n) != s);
                if on_grid(x, sx, w) || on_grid(y, sy, h) {
                    color = BLOCK_GRID;
                }
            }
            let on_outline = |g: &crate::decisions::Ground| {
                let (x1, y1) = (g.x + g.width - 1, g.y + g.height - 1);
                let across = (g.x..=x1).contains(&sx) && (g.y..=y1).contains(&sy);
                across && (sx == g.x || sx == x1 || sy == g.y || sy == y1)
            };
            if decisions.reversed_grounds.iter().any(on_outline) {
                color = GROUND_OUTLINE;
            }
            let on_region = |r: &crate::decisions::Region| {
                on_outline(&crate::decisions::Ground {
                    x: r.x,
                    y: r.y,
                    width: r.width,
                    height: r.height,
                })
            };
            if decisions.regions.iter().any(on_region) {
                color = REGION_OUTLINE;
            }
            canvas.image.put_pixel(x, y, color);
        }
    }
    canvas.image
}

/// [`decisions_picture`] as the bytes of a PNG file.
pub fn decisions_png(gray: &GrayImage, binary: &Binary, decisions: &Decisions) -> Result<Vec<u8>> {
    let mut png = Vec::new();
    decisions_picture(gray, binary, decisions)
        .write_to(&mut Cursor::new(&mut png), ImageFormat::Png)
        .map_err(|err| Error::Encode(format!("{DECISIONS_PICTURE}: {err}")))?;
    Ok(png)
}

/// File names of the fingerprint front end's pictures ([`print_pictures`]), in stage order.
pub const PRINT_PICTURE_NAMES: [&str; 3] =
    ["0-segmentation.png", "0-orientation.png", "0-enhanced.png"];

/// Outside the print in the segmentation picture.
const OUTSIDE_PRINT: Rgb<u8> = Rgb([255, 150, 0]);

/// Pictures of the fingerprint front end (docs/fingerprints.md, "Stages"), named as in
/// [`PRINT_PICTURE_NAMES`]: the gray image with the blocks outside the segmentation mask tinted
/// orange; the orientation field as a short line along the ridges per block over the faded
/// image, dark where coherent and pale where not; the enhanced image (the Gabor response, ridges
/// dark, zero mid-gray), whose sign inside the print is the binary image that is traced.
pub fn print_pictures(gray: &GrayImage, analysis: &PrintAnalysis) -> Vec<(&'static str, RgbImage)> {
    let (w, h) = gray.dimensions();
    let grid = analysis.segmentation.grid;
    let mask = analysis.segmentation.pixel_mask();
    let fits = grid.width == w
        && grid.height == h
        && mask.len() == w as usize * h as usize
        && analysis.enhanced.values.len() == mask.len();
    let mut pictures = Vec::new();
    // Segmentation.
    let mut canvas = Canvas::new(w, h);
    if fits {
        canvas.paint(|x, y| {
            let v = gray.get_pixel(x as u32, y as u32).0[0];
            if mask[y * w as usize + x] {
                Rgb([v, v, v])
            } else {
                Rgb(std::array::from_fn(|k| {
                    ((u16::from(v) + u16::from(OUTSIDE_PRINT.0[k])) / 2) as u8
                }))
            }
        });
    }
    pictures.push((PRINT_PICTURE_NAMES[0], canvas.image));
    // Orientation field.
    let mut canvas = Canvas::new(w, h);
    if fits {
        canvas.paint(|x, y| {
            let v = gray.get_pixel(x as u32, y as u32).0[0];
            let v = (175 + u16::from(v) * 80 / 255) as u8;
            Rgb([v, v, v])
        });
        let field = &analysis.orientation;
        let half = 0.45 * f64::from(grid.block);
        for j in 0..grid.rows as usize {
            for i in 0..grid.cols as usize {
                let b = grid.index(i, j);
                if !analysis.segmentation.inside[b] {
                    continue;
                }
                let c = grid.center(i, j);
                let angle = f64::from(field.angle[b]);
                let coherence = f64::from(field.coherence[b]).clamp(0.0, 1.0);
                let d = [half * angle.cos(), half * angle.sin()];
                let tone = (220.0 * (1.0 - coherence)) as u8;
                canvas.line(
                    [c[0] - d[0], c[1] - d[1]],
                    [c[0] + d[0], c[1] + d[1]],
                    canvas.line_width(),
                    Rgb([tone, tone / 2, 160 + tone / 4]),
                );
            }
        }
    }
    pictures.push((PRINT_PICTURE_NAMES[1], canvas.image));
    // Enhanced image.
    let mut canvas = Canvas::new(w, h);
    if fits {
        let values = &analysis.enhanced.values;
        let mut magnitudes: Vec<f32> = values
            .iter()
            .map(|v| v.abs())
            .filter(|v| *v > 0.0)
            .collect();
        let scale = if magnitudes.is_empty() {
            1.0
        } else {
            let k = (magnitudes.len() - 1) * 95 / 100;
            *magnitudes.select_nth_unstable_by(k, f32::total_cmp).1
        };
        canvas.paint(|x, y| {
            let r = values[y * w as usize + x] / scale.max(f32::MIN_POSITIVE);
            let v = (128.0 - 127.0 * r.clamp(-1.0, 1.0)) as u8;
            Rgb([v, v, v])
        });
    }
    pictures.push((PRINT_PICTURE_NAMES[2], canvas.image));
    pictures
}

/// The pictures of [`print_pictures`] as the bytes of PNG files.
pub fn print_pngs(
    gray: &GrayImage,
    analysis: &PrintAnalysis,
) -> Result<Vec<(&'static str, Vec<u8>)>> {
    print_pictures(gray, analysis)
        .into_iter()
        .map(|(name, picture)| {
            let mut png = Vec::new();
            picture
                .write_to(&mut Cursor::new(&mut png), ImageFormat::Png)
                .map_err(|err| Error::Encode(format!("{name}: {err}")))?;
            Ok((name, png))
        })
        .collect()
}

/// What the pictures are drawn from.
struct Scene<'a> {
    binary: &'a Binary,
    stages: &'a Stages,
    graph: &'a StrokeGraph,
}

impl Scene<'_> {
    fn draw(&self, stage: usize) -> RgbImage {
        let mut canvas = Canvas::new(self.binary.width, self.binary.height);
        match stage {
            0 => canvas.foreground(self.binary, INK),
            1 => self.sampling(&mut canvas),
            2 => self.node_graph(&mut canvas),
            3 => self.refined(&mut canvas),
            4 => self.fitted(&mut canvas),
            _ => self.final_graph(&mut canvas),
        }
        canvas.image
    }

    /// §3.1: the partition `P_i` as pale tints, the disks, and the nodes.
    fn sampling(&self, canvas: &mut Canvas) {
        canvas.foreground(self.binary, BACKDROP);
        let nodes = &self.stages.samples.nodes;
        let tints = cell_colors(nodes.len(), &self.stages.node_graph.edges);
        for (point, &owner) in self
            .stages
            .points
            .points
            .iter()
            .zip(&self.stages.samples.owner)
        {
            if let Some(&tint) = tints.get(owner as usize) {
                canvas.cell(*point, pale(PALETTE[tint]));
            }
        }
        let dot = canvas.dot_radius();
        for node in nodes {
            let color = if node.linear { LINEAR } else { NON_LINEAR };
            canvas.ring(node.pos, node.radius, color);
            canvas.disk(node.pos, dot * 0.6, color);
        }
    }

    /// §3.2: graph `H` with its clusters.
    fn node_graph(&self, canvas: &mut Canvas) {
        canvas.foreground(self.binary, BACKDROP);
        let graph = &self.stages.node_graph;
        for &[a, b] in &graph.edges {
            if let (Some(na), Some(nb)) = (graph.nodes.get(a as usize), graph.nodes.get(b as usize))
            {
                canvas.line(na.pos, nb.pos, 1.0, GRAPH_EDGE);
            }
        }
        let dot = canvas.dot_radius();
        for node in &graph.nodes {
            match (node.linear, node.cluster) {
                (false, Some(cluster)) => {
                    canvas.disk(node.pos, dot, PALETTE[cluster as usize % PALETTE.len()]);
                }
                (false, None) => canvas.disk(node.pos, dot, ISOLATED),
                (true, _) => canvas.disk(node.pos, dot * 0.6, LINEAR_NODE),
            }
        }
    }

    /// §3.3: the 1-D graph, nodes by degree.
    fn refined(&self, canvas: &mut Canvas) {
        canvas.foreground(self.binary, BACKDROP);
        let graph = &self.stages.refined;
        let mut degree = vec![0usize; graph.nodes.len()];
        for &[a, b] in &graph.edges {
            if let (Some(na), Some(nb)) = (graph.nodes.get(a as usize), graph.nodes.get(b as usize))
            {
                canvas.line(na.pos, nb.pos, canvas.line_width(), CURVE);
                degree[a as usize] += 1;
                degree[b as usize] += 1;
            }
        }
        let dot = canvas.dot_radius();
        for (node, &d) in graph.nodes.iter().zip(&degree) {
            match d {
                0 => canvas.disk(node.pos, dot, ISOLATED),
                1 => canvas.disk(node.pos, dot * 1.5, rgb(ENDPOINT_COLOR)),
                2 => canvas.disk(node.pos, dot * 0.6, CURVE),
                _ => canvas.disk(node.pos, dot * 1.5, rgb(JUNCTION_COLOR)),
            }
        }
    }

    /// §3.4: the fitted polylines, one color per edge, with their points.
    fn fitted(&self, canvas: &mut Canvas) {
        canvas.foreground(self.binary, BACKDROP);
        let dot = canvas.dot_radius();
        for (i, edge) in self.graph.edges.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            for pair in edge.points.windows(2) {
                canvas.line(pair[0], pair[1], 2.0 * canvas.line_width(), color);
            }
            for &point in &edge.points {
                canvas.disk(point, dot * 0.45, CURVE);
            }
        }
    }

    /// The result as the SVG shows it.
    fn final_graph(&self, canvas: &mut Canvas) {
        canvas.foreground(self.binary, BACKDROP);
        let red = rgb(EDGE_COLOR);
        for edge in &self.graph.edges {
            for pair in edge.points.windows(2) {
                canvas.line(pair[0], pair[1], canvas.line_width(), red);
            }
        }
        let marker = canvas.dot_radius() * 1.8;
        for vertex in &self.graph.vertices {
            match vertex.degree {
                0 => canvas.disk(vertex.pos, marker * 0.6, red),
                1 => canvas.disk(vertex.pos, marker, rgb(ENDPOINT_COLOR)),
                2 => {}
                _ => canvas.disk(vertex.pos, marker, rgb(JUNCTION_COLOR)),
            }
        }
    }
}

/// A picture of a `width` x `height` image at [`picture_scale`]; draws in image coordinates.
struct Canvas {
    image: RgbImage,
    scale: f64,
    width: u32,
    height: u32,
}

impl Canvas {
    fn new(width: u32, height: u32) -> Canvas {
        let scale = picture_scale(width, height);
        let side = |n: u32| ((n as f64 * scale).round() as u32).max(1);
        Canvas {
            image: RgbImage::from_pixel(side(width), side(height), WHITE),
            scale,
            width,
            height,
        }
    }

    /// Radius of a node dot, picture px: visible at every scale.
    fn dot_radius(&self) -> f64 {
        (1.2 * self.scale).max(2.0)
    }

    /// Width of curve lines, picture px.
    fn line_width(&self) -> f64 {
        (0.5 * self.scale).max(1.0)
    }

    /// Paints the ink of `binary` (same size as the canvas's image) in `ink`.
    fn foreground(&mut self, binary: &Binary, ink: Rgb<u8>) {
        if binary.width != self.width
            || binary.height != self.height
            || binary.ink.len() != self.width as usize * self.height as usize
        {
            return;
        }
        let (out_w, out_h) = self.image.dimensions();
        // Source column of every picture column, computed once (nearest neighbour).
        let source =
            |o: u32, n: u32| (((o as f64 + 0.5) / self.scale) as usize).min(n as usize - 1);
        let columns: Vec<usize> = (0..out_w).map(|x| source(x, self.width)).collect();
        for y in 0..out_h {
            let row = source(y, self.height) * self.width as usize;
            for (x, &column) in columns.iter().enumerate() {
                if binary.ink[row + column] {
                    self.image.put_pixel(x as u32, y, ink);
                }
            }
        }
    }

    /// Paints every picture pixel with `color(x, y)` of the image pixel under it (nearest).
    fn paint(&mut self, color: impl Fn(usize, usize) -> Rgb<u8>) {
        let (out_w, out_h) = self.image.dimensions();
        let source =
            |o: u32, n: u32| (((o as f64 + 0.5) / self.scale) as usize).min(n.max(1) as usize - 1);
        let columns: Vec<usize> = (0..out_w).map(|x| source(x, self.width)).collect();
        for y in 0..out_h {
            let row = source(y, self.height);
            for (x, &column) in columns.iter().enumerate() {
                self.image.put_pixel(x as u32, y, color(column, row));
            }
        }
    }

    /// Fills the picture square of the image pixel containing `point`.
    fn cell(&mut self, point: [f64; 2], color: Rgb<u8>) {
        if !(point[0] >= 0.0 && point[1] >= 0.0) {
            return;
        }
        let (out_w, out_h) = self.image.dimensions();
        let (cx, cy) = (point[0].floor(), point[1].floor());
        let span = |c: f64, n: u32| {
            let start = (c * self.scale).floor() as u32;
            let end = (((c + 1.0) * self.scale).floor() as u32).max(start + 1);
            start.min(n)..end.min(n)
        };
        for y in span(cy, out_h) {
            for x in span(cx, out_w) {
                self.image.put_pixel(x, y, color);
            }
        }
    }

    /// Picture coordinates of image point `p`, or `None` when it is not finite or far outside
    /// (so that no drawing routine loops over a huge range).
    fn to_picture(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let (x, y) = (p[0] * self.scale, p[1] * self.scale);
        let limit = 4.0 * (self.image.width().max(self.image.height()) as f64) + 64.0;
        (x.is_finite() && y.is_finite() && x.abs() < limit && y.abs() < limit).then_some([x, y])
    }

    /// A line `width` picture px wide from image point `a` to `b`: imageproc's 1-px line, or a
    /// filled quadrilateral with round ends for wider lines.
    fn line(&mut self, a: [f64; 2], b: [f64; 2], width: f64, color: Rgb<u8>) {
        let (Some(a), Some(b)) = (self.to_picture(a), self.to_picture(b)) else {
            return;
        };
        if width <= 1.5 {
            let at = |p: [f64; 2]| (p[0] as f32, p[1] as f32);
            draw_line_segment_mut(&mut self.image, at(a), at(b), color);
            return;
        }
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let length = dx.hypot(dy);
        if length > 0.0 {
            let half = width / 2.0;
            let normal = [-dy / length * half, dx / length * half];
            let corner = |p: [f64; 2], sign: f64| {
                Point::new(
                    (p[0] + sign * normal[0] - 0.5).round() as i32,
                    (p[1] + sign * normal[1] - 0.5).round() as i32,
                )
            };
            let quad = [
                corner(a, 1.0),
                corner(b, 1.0),
                corner(b, -1.0),
                corner(a, -1.0),
            ];
            draw_polygon_mut(&mut self.image, &quad, color);
        }
        // Round joins between the segments of a polyline.
        self.disk_px(a, width / 2.0 - 0.5, color);
        self.disk_px(b, width / 2.0 - 0.5, color);
    }

    /// A filled disk of `radius` picture px around image point `center`.
    fn disk(&mut self, center: [f64; 2], radius: f64, color: Rgb<u8>) {
        if let Some(center) = self.to_picture(center) {
            self.disk_px(center, radius, color);
        }
    }

    fn disk_px(&mut self, center: [f64; 2], radius: f64, color: Rgb<u8>) {
        let center = (center[0].floor() as i32, center[1].floor() as i32);
        draw_filled_circle_mut(&mut self.image, center, radius.round() as i32, color);
    }

    /// A circle of `radius` image px around image point `center`.
    fn ring(&mut self, center: [f64; 2], radius: f64, color: Rgb<u8>) {
        let radius = radius * self.scale;
        let largest = (self.image.width() + self.image.height()) as f64;
        if !(radius.is_finite() && radius >= 0.0 && radius <= largest) {
            return;
        }
        if let Some(c) = self.to_picture(center) {
            let c = (c[0].floor() as i32, c[1].floor() as i32);
            draw_hollow_circle_mut(&mut self.image, c, radius.round() as i32, color);
        }
    }
}

/// A palette index per node such that nodes joined in `H` (their point sets touch, §3.2) differ
/// where the palette allows: greedy coloring in node order, so the cells `P_i` of the partition
/// are told apart in the sampling picture.
fn cell_colors(nodes: usize, edges: &[[u32; 2]]) -> Vec<usize> {
    let mut adjacency = vec![Vec::new(); nodes];
    for &[a, b] in edges {
        if (a as usize) < nodes && (b as usize) < nodes {
            adjacency[a as usize].push(b as usize);
            adjacency[b as usize].push(a as usize);
        }
    }
    let mut colors = vec![usize::MAX; nodes];
    for node in 0..nodes {
        let mut used = [false; PALETTE.len()];
        for &other in &adjacency[node] {
            if let Some(flag) = used.get_mut(colors[other]) {
                *flag = true;
            }
        }
        colors[node] = used
            .iter()
            .position(|&u| !u)
            .unwrap_or(node % PALETTE.len());
    }
    colors
}

/// `color` mixed 3 : 1 with white.
fn pale(color: Rgb<u8>) -> Rgb<u8> {
    Rgb(color.0.map(|c| ((c as u16 + 3 * 255) / 4) as u8))
}

/// `#rrggbb` as a pixel (black if malformed; the constants used are well-formed).
fn rgb(hex: &str) -> Rgb<u8> {
    let channel = |i: usize| {
        hex.get(1 + 2 * i..3 + 2 * i)
            .and_then(|s| u8::from_str_radix(s, 16).ok())
            .unwrap_or(0)
    };
    Rgb([channel(0), channel(1), channel(2)])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The front end's pictures: the corner outside the print tinted, the centre not; an
    /// orientation line drawn in the print; ridges dark in the enhanced picture.
    #[test]
    fn print_pictures_show_the_front_end() {
        let plane =
            crate::fingerprint::tests::ridges_in_disk(120, 120, 9.0, 0.3, [60.0, 60.0], 40.0);
        let gray = GrayImage::from_raw(
            120,
            120,
            plane
                .values
                .iter()
                .map(|&v| v.clamp(0.0, 255.0) as u8)
                .collect(),
        )
        .expect("size matches");
        let (analysis, binary) = crate::fingerprint::analyze(
            (&gray).into(),
            &crate::params::FingerprintParams::default(),
            true,
        );
        let pictures = print_pictures(&gray, &analysis);
        let names: Vec<&str> = pictures.iter().map(|p| p.0).collect();
        assert_eq!(names, PRINT_PICTURE_NAMES);
        let scale = picture_scale(120, 120) as u32;
        for (_, picture) in &pictures {
            assert_eq!(picture.dimensions(), (120 * scale, 120 * scale));
        }
        let at = |p: &RgbImage, x: u32, y: u32| p.get_pixel(x * scale, y * scale).0;
        let corner = at(&pictures[0].1, 2, 2);
        assert!(
            corner[0] > corner[2] + 40,
            "outside tinted orange: {corner:?}"
        );
        let centre = at(&pictures[0].1, 60, 60);
        assert!(
            centre[0] == centre[1] && centre[1] == centre[2],
            "{centre:?}"
        );
        assert!(
            pictures[1]
                .1
                .pixels()
                .any(|p| u16::from(p.0[2]) > u16::from(p.0[0]) + 60),
            "orientation lines drawn"
        );
        // A ridge pixel of the binary image is dark in the enhanced picture.
        let ridge = (0..120 * 120)
            .find(|&k| binary.ink[k] && analysis.enhanced.values[k] > 0.0)
            .expect("ridges");
        let v = at(&pictures[2].1, (ridge % 120) as u32, (ridge / 120) as u32);
        assert!(v[0] < 128, "{v:?}");
        assert!(print_pngs(&gray, &analysis).is_ok_and(|p| p.len() == 3));
    }

    #[test]
    fn scale_is_whole_and_bounded() {
        assert_eq!(picture_scale(100, 50), 4.0);
        assert_eq!(picture_scale(300, 200), 3.0);
        assert_eq!(picture_scale(800, 600), 1.0);
        assert_eq!(picture_scale(2480, 3508), 1.0);
        assert_eq!(picture_scale(500, 10), 2.0);
        let huge = picture_scale(10_000, 10_000);
        assert!(huge < 1.0 && 1e8 * huge * huge <= MAX_PICTURE_PIXELS as f64 + 1.0);
    }

    #[test]
    fn touching_cells_get_different_colors() {
        // A star: node 0 touches 1..=5, and 1-2 touch.
        let edges = [[0, 1], [0, 2], [0, 3], [0, 4], [0, 5], [1, 2]];
        let colors = cell_colors(6, &edges);
        for [a, b] in edges {
            assert_ne!(colors[a as usize], colors[b as usize]);
        }
        assert!(colors.iter().all(|&c| c < PALETTE.len()));
    }

    #[test]
    fn colors_parse() {
        assert_eq!(rgb("#3cb44b"), Rgb([0x3c, 0xb4, 0x4b]));
        assert_eq!(rgb("#zz"), Rgb([0, 0, 0]));
        assert_eq!(pale(Rgb([255, 0, 0])), Rgb([255, 191, 191]));
    }

    #[test]
    fn far_away_and_nan_coordinates_draw_nothing() {
        let mut canvas = Canvas::new(10, 10);
        canvas.line([f64::NAN, 0.0], [5.0, 5.0], 3.0, CURVE);
        canvas.line([-1e12, 0.0], [1e12, 5.0], 3.0, CURVE);
        canvas.ring([5.0, 5.0], 1e12, CURVE);
        canvas.disk([f64::INFINITY, 1.0], 3.0, CURVE);
        assert!(canvas.image.pixels().all(|p| *p == WHITE));
    }
}

#[cfg(test)]
mod decisions_tests {
    use super::*;
    use crate::params::Params;

    #[test]
    fn the_decisions_picture_tints_the_ink_and_draws_the_local_blocks() {
        // Light falling from right to left over dark bars: the local threshold.
        let gray = GrayImage::from_fn(200, 120, |x, y| {
            let light = 90.0 + 160.0 * x as f64 / 199.0;
            let on = (y % 30) >= 14 && (y % 30) < 18;
            image::Luma([(if on { light * 0.5 } else { light }) as u8])
        });
        let trace = crate::trace_image_with_stages(&gray, &Params::default()).unwrap();
        let decisions = trace.decisions.as_ref().unwrap();
        let ThresholdUsed::Local { window } = decisions.threshold else {
            panic!("{decisions:?}");
        };
        let binary = trace.binary.as_ref().unwrap();
        let picture = decisions_picture(&gray, binary, decisions);
        let scale = picture_scale(200, 120);
        let at = |x: u32, y: u32| {
            *picture.get_pixel(
                (x as f64 * scale + 1.0) as u32,
                (y as f64 * scale + 1.0) as u32,
            )
        };
        // Ink is tinted blue, paper stays gray, block corners are orange.
        let ink = at(101, 15);
        assert!(ink.0[2] > ink.0[0] + 40, "{ink:?}");
        let paper = at(101, 5);
        assert_eq!(paper.0[0], paper.0[2]);
        let corner = *picture.get_pixel(
            (window as f64 * scale) as u32,
            (window as f64 * scale) as u32 + 2,
        );
        assert_eq!(corner, BLOCK_GRID);
        assert!(decisions_png(&gray, binary, decisions)
            .unwrap()
            .starts_with(b"\x89PNG"));
    }

    #[test]
    fn the_decisions_picture_outlines_the_reversed_grounds() {
        // A dark banner holding three light bars.
        let bars = [(40, 20, 5, 40), (100, 20, 5, 40), (140, 38, 50, 5)];
        let gray = GrayImage::from_fn(240, 90, |x, y| {
            let inside = |&(x0, y0, w, h): &(u32, u32, u32, u32)| {
                (x0..x0 + w).contains(&x) && (y0..y0 + h).contains(&y)
            };
            let banner = (10..230).contains(&x) && (10..70).contains(&y);
            image::Luma([if banner && !bars.iter().any(inside) {
                30
            } else {
                230
            }])
        });
        let trace = crate::trace_image_with_stages(&gray, &Params::default()).unwrap();
        let decisions = trace.decisions.as_ref().unwrap();
        assert_eq!(decisions.reversed_grounds.len(), 1, "{decisions:?}");
        let picture = decisions_picture(&gray, trace.binary.as_ref().unwrap(), decisions);
        let scale = picture_scale(240, 90);
        let at = |x: u32, y: u32| {
            *picture.get_pixel((x as f64 * scale) as u32, (y as f64 * scale) as u32)
        };
        assert_eq!(at(10, 40), GROUND_OUTLINE);
        assert_ne!(at(20, 40), GROUND_OUTLINE);
        // The bars are the ink now, tinted blue; the banner is paper.
        let bar = at(42, 40);
        assert!(bar.0[2] > bar.0[0] + 40, "{bar:?}");
        let banner = at(20, 40);
        assert_eq!(banner.0[0], banner.0[2]);
    }
}
