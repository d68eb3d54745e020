//! SVG output: the centerlines drawn over the source image, for looking at a result in a browser.
//!
//! Coordinates are image coordinates (pixel `(x, y)` covers `[x, x+1] x [y, y+1]`), so the
//! polylines are written as they are, over an `<image>` that covers `[0, W] x [0, H]`. The document
//! is written by hand rather than through the `svg` crate: nothing in it comes from the user but
//! numbers and a MIME type from a fixed list (so nothing needs escaping), it streams into one
//! `String` without a node per polyline, and the attribute order stays as written. The crate sorts
//! attributes by name (every output would change) and was slower even when handed our coordinate
//! strings: 58 ms against 41 ms for a page-sized graph of 30 000 edges.
//!
//! The image under the centerlines is a [`Backdrop`]: gray or colour pixels, written as a PNG, or
//! an already encoded file (a PNG, JPEG, GIF or WebP as the user gave it) written as it is.
//!
//! Layers, bottom to top: the image; with [`SvgOptions::show_widths`], every edge as wide as the ink
//! (its mean width), semi-transparent; the centerlines, one polyline per edge, or per stroke in its
//! own color when [`Features::strokes`] is given, or Bézier `<path>`s when [`Features::curves`] is;
//! dots and vertex markers; minutiae marks when [`Features::minutiae`] is given.

use std::borrow::Cow;
use std::fmt::Write;
use std::io::Cursor;

use base64::Engine;
use image::{DynamicImage, GrayImage, ImageFormat};

use super::{push_number, Features};
use crate::curves::CubicBezier;
use crate::minutiae::{Minutia, MinutiaKind};
use crate::stroke_graph::StrokeGraph;

/// Color of the centerlines (and of isolated dots).
pub const EDGE_COLOR: &str = "#e6194b";
/// Color of the markers at stroke ends (degree 1).
pub const ENDPOINT_COLOR: &str = "#3cb44b";
/// Color of the markers at junctions and crossings (degree 3 or more).
pub const JUNCTION_COLOR: &str = "#4363d8";

/// Opacity of the width layer: the ink (and the lack of it) shows through.
pub const WIDTH_OPACITY: f64 = 0.45;

/// Decimals of the coordinates: a hundredth of a pixel is below anything the fit resolves.
const DECIMALS: usize = 2;

/// What the SVG shows. Build it from [`SvgOptions::default`] and the `with_*` setters (or assign
/// the public fields): more options will be added, so the struct cannot be written as a literal
/// outside this crate.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SvgOptions {
    /// Draw small circles at endpoints and junctions. Default value: `true`.
    pub show_vertices: bool,
    /// Line width of the centerlines in px; `None` picks `max(0.6, 0.12 x median vertex width)`,
    /// thin enough to see the ink around it. Default value: `None`.
    pub stroke_width: Option<f64>,
    /// Draw each edge, under its centerline, with a line as wide as its mean stroke width (and
    /// each dot as a disk of its width), in a group of opacity [`WIDTH_OPACITY`], so that the
    /// drawing covers the ink where the widths are right. Default value: `false`.
    pub show_widths: bool,
    /// Size the canvas (`viewBox`) to the drawing, with a margin, instead of `[0, W] x [0, H]`:
    /// for point lists, whose coordinates need not start near the origin. The coordinates are
    /// written as they are either way. Default value: `false`.
    pub fit_canvas: bool,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            show_vertices: true,
            stroke_width: None,
            show_widths: false,
            fit_canvas: false,
        }
    }
}

impl SvgOptions {
    /// Sets [`SvgOptions::show_vertices`].
    pub const fn with_show_vertices(mut self, show_vertices: bool) -> Self {
        self.show_vertices = show_vertices;
        self
    }

    /// Sets [`SvgOptions::stroke_width`].
    pub const fn with_stroke_width(mut self, stroke_width: Option<f64>) -> Self {
        self.stroke_width = stroke_width;
        self
    }

    /// Sets [`SvgOptions::show_widths`].
    pub const fn with_show_widths(mut self, show_widths: bool) -> Self {
        self.show_widths = show_widths;
        self
    }

    /// Sets [`SvgOptions::fit_canvas`].
    pub const fn with_fit_canvas(mut self, fit_canvas: bool) -> Self {
        self.fit_canvas = fit_canvas;
        self
    }
}

/// The canvas `[x, y, width, height]` of a drawing fitted to `graph`: the bounding box of its
/// polylines and vertices, grown on every side by 5 % of its longer side and at least the marker
/// radius and the widths drawn; `None` for an empty graph.
pub fn fitted_canvas(graph: &StrokeGraph, options: &SvgOptions) -> Option<[f64; 4]> {
    let points = graph
        .edges
        .iter()
        .flat_map(|e| e.points.iter().copied())
        .chain(graph.vertices.iter().map(|v| v.pos));
    let mut bounds: Option<[f64; 4]> = None;
    for [x, y] in points.filter(|p| p[0].is_finite() && p[1].is_finite()) {
        let b = bounds.get_or_insert([x, y, x, y]);
        *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    let [x0, y0, x1, y1] = bounds?;
    let widest = graph
        .vertices
        .iter()
        .map(|v| v.width)
        .filter(|w| w.is_finite())
        .fold(0.0f64, f64::max);
    let line = stroke_width(graph, options);
    let margin = (0.05 * (x1 - x0).max(y1 - y0)).max(4.0 * line).max(widest);
    Some([
        x0 - margin,
        y0 - margin,
        x1 - x0 + 2.0 * margin,
        y1 - y0 + 2.0 * margin,
    ])
}

/// The line width used for `graph`: the explicit one when it is a positive number, otherwise
/// `max(0.6, 0.12 x median vertex width)`.
pub fn stroke_width(graph: &StrokeGraph, options: &SvgOptions) -> f64 {
    if let Some(width) = options.stroke_width.filter(|w| w.is_finite() && *w > 0.0) {
        return width;
    }
    median_vertex_width(graph).map_or(0.6, |median| (0.12 * median).max(0.6))
}

/// The picture under the centerlines, embedded in the SVG as a base64 `data:` URL stretched over
/// `[0, W] x [0, H]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Backdrop<'a> {
    /// Gray pixels, written as a PNG.
    Gray(&'a GrayImage),
    /// Pixels in colour (any layout the PNG encoder takes: gray, gray with alpha, RGB, RGBA at 8
    /// or 16 bits), written as a PNG.
    Color(&'a DynamicImage),
    /// An encoded image written as it is, e.g. the user's own PNG or JPEG file.
    Encoded {
        /// The file's bytes.
        bytes: &'a [u8],
        /// Its MIME type (`image/png`, `image/jpeg`, `image/gif`, `image/webp`, ...); a value
        /// that is not of the form `type/subtype` in lowercase letters, digits and `+.-` is
        /// refused and the SVG written without its backdrop.
        mime: &'a str,
    },
}

impl<'a> From<&'a GrayImage> for Backdrop<'a> {
    fn from(image: &'a GrayImage) -> Self {
        Backdrop::Gray(image)
    }
}

/// Writes `graph` as an SVG document of the image's size, over `image` (embedded as a base64 PNG)
/// when one is given.
pub fn to_string(graph: &StrokeGraph, image: Option<&GrayImage>, options: &SvgOptions) -> String {
    to_string_with(
        graph,
        image.map(Backdrop::Gray),
        options,
        &Features::default(),
    )
}

/// Like [`to_string`], over any [`Backdrop`] and drawing the `features` given: strokes in their own
/// colors instead of edges, Bézier paths instead of polylines, minutiae marks (see the module doc
/// for the layers).
pub fn to_string_with(
    graph: &StrokeGraph,
    backdrop: Option<Backdrop>,
    options: &SvgOptions,
    features: &Features,
) -> String {
    let points: usize = graph.edges.iter().map(|e| e.points.len()).sum();
    let layers = if options.show_widths { 2 } else { 1 };
    let mut out = String::with_capacity(512 + layers * 14 * points + 64 * graph.vertices.len());
    let (w, h) = (graph.width, graph.height);
    match fitted_canvas(graph, options).filter(|_| options.fit_canvas) {
        Some(canvas) => {
            out.push_str(r#"<svg xmlns="http://www.w3.org/2000/svg" width=""#);
            push_number(&mut out, canvas[2], DECIMALS);
            out.push_str(r#"" height=""#);
            push_number(&mut out, canvas[3], DECIMALS);
            out.push_str(r#"" viewBox=""#);
            for (i, value) in canvas.iter().enumerate() {
                if i > 0 {
                    out.push(' ');
                }
                push_number(&mut out, *value, DECIMALS);
            }
            out.push_str("\">\n");
        }
        None => {
            let _ = writeln!(
                out,
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
            );
        }
    }
    let encoded = backdrop.and_then(|backdrop| match backdrop {
        Backdrop::Gray(image) => encode_png(image.dimensions(), |out| {
            image.write_to(out, ImageFormat::Png)
        })
        .map(|png| (Cow::Owned(png), "image/png")),
        Backdrop::Color(image) => encode_png((image.width(), image.height()), |out| {
            image.write_to(out, ImageFormat::Png)
        })
        .map(|png| (Cow::Owned(png), "image/png")),
        Backdrop::Encoded { bytes, mime } => {
            (!bytes.is_empty() && is_mime(mime)).then_some((Cow::Borrowed(bytes), mime))
        }
    });
    if let Some((data, mime)) = encoded {
        // preserveAspectRatio="none": the picture must cover [0, W] x [0, H] exactly, or the
        // centerlines would drift off their pixels; pixelated so that zooming in shows the pixels
        // the centerline was traced from.
        let _ = write!(
            out,
            r#"<image x="0" y="0" width="{w}" height="{h}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:{mime};base64,"#
        );
        base64::engine::general_purpose::STANDARD.encode_string(&data, &mut out);
        out.push_str("\"/>\n");
    }

    // The stroke each edge belongs to, for coloring the width layer like the centerlines.
    let mut stroke_of = vec![None; graph.edges.len()];
    if let Some(strokes) = features.strokes {
        for (s, stroke) in strokes.iter().enumerate() {
            for &e in &stroke.edges {
                if let Some(slot) = stroke_of.get_mut(e) {
                    *slot = Some(s);
                }
            }
        }
    }
    if options.show_widths {
        write_widths(&mut out, graph, &stroke_of);
    }

    let line = stroke_width(graph, options);
    match features.strokes {
        Some(strokes) => {
            // Each stroke carries its own color; the group holds what they share.
            out.push_str(r#"<g id="strokes" fill="none" stroke-width=""#);
            push_number(&mut out, line, DECIMALS);
            out.push_str("\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n");
            for (s, stroke) in strokes.iter().enumerate() {
                let color = stroke_color(s);
                write_line(
                    &mut out,
                    &stroke.points,
                    curves_of(features, s),
                    Some(&color),
                );
            }
        }
        None => {
            out.push_str(r#"<g id="edges" fill="none" stroke=""#);
            out.push_str(EDGE_COLOR);
            out.push_str(r#"" stroke-width=""#);
            push_number(&mut out, line, DECIMALS);
            out.push_str("\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n");
            write_edge_lines(&mut out, graph, features);
        }
    }
    out.push_str("</g>\n");

    // An isolated vertex (a dot, the tittle of an i) has no edge to draw: it is content, not a
    // marker, so it is drawn in the edge color whatever `show_vertices` says.
    let radius = (2.0 * line).max(1.0);
    write_circles(&mut out, graph, "dots", EDGE_COLOR, radius, |degree| {
        degree == 0
    });
    if options.show_vertices {
        write_circles(
            &mut out,
            graph,
            "endpoints",
            ENDPOINT_COLOR,
            radius,
            |degree| degree == 1,
        );
        write_circles(
            &mut out,
            graph,
            "junctions",
            JUNCTION_COLOR,
            radius,
            |degree| degree >= 3,
        );
    }
    if let Some(minutiae) = features.minutiae.filter(|m| !m.is_empty()) {
        // Marks about two ridge widths across: big enough to see, small enough not to hide the
        // neighbouring ridges.
        let size = (2.0 * median_vertex_width(graph).unwrap_or(2.0)).max(4.0);
        out.push_str("<g id=\"minutiae\">\n");
        out.push_str(&svg_marks(minutiae, size));
        out.push_str("</g>\n");
    }
    out.push_str("</svg>\n");
    out
}

/// Edges per block of [`write_edge_lines`].
const EDGE_BLOCK: usize = 1024;

/// Each edge's centerline ([`write_line`]), one after the other in edge order. A page has tens of
/// thousands of edges and writing them otherwise ran alone on one core after the trace
/// (docs/performance.md, "Session of 2026-12-05, late"): blocks of edges are written in parallel,
/// each into its own string, and joined in order, so the text is the same whatever the thread
/// count.
fn write_edge_lines(out: &mut String, graph: &StrokeGraph, features: &Features) {
    use rayon::prelude::*;
    let write_block = |first: usize, edges: &[crate::stroke_graph::Edge], text: &mut String| {
        for (e, edge) in (first..).zip(edges) {
            write_line(text, &edge.points, curves_of(features, e), None);
        }
    };
    if graph.edges.len() <= EDGE_BLOCK {
        write_block(0, &graph.edges, out);
        return;
    }
    let blocks: Vec<String> = graph
        .edges
        .par_chunks(EDGE_BLOCK)
        .enumerate()
        .map(|(b, edges)| {
            let points: usize = edges.iter().map(|e| e.points.len()).sum();
            let mut text = String::with_capacity(32 + 14 * points);
            write_block(b * EDGE_BLOCK, edges, &mut text);
            text
        })
        .collect();
    for text in blocks {
        out.push_str(&text);
    }
}

/// The curves to draw for line `index`, when there are any.
fn curves_of<'a>(features: &Features<'a>, index: usize) -> Option<&'a [CubicBezier]> {
    features
        .curves
        .and_then(|curves| curves.get(index))
        .map(Vec::as_slice)
        .filter(|segments| !segments.is_empty())
}

/// One centerline: a `<path>` of `curves` when given, else a `<polyline>` of `points`, in `color`
/// when given (else the group's).
fn write_line(
    out: &mut String,
    points: &[[f64; 2]],
    curves: Option<&[CubicBezier]>,
    color: Option<&str>,
) {
    match curves {
        Some(segments) => {
            out.push_str(r#"<path d=""#);
            out.push_str(&svg_path_data(segments));
        }
        None => {
            out.push_str(r#"<polyline points=""#);
            push_points(out, points);
        }
    }
    out.push('"');
    if let Some(color) = color {
        out.push_str(r#" stroke=""#);
        out.push_str(color);
        out.push('"');
    }
    out.push_str("/>\n");
}

/// `x,y x,y …` with [`DECIMALS`] decimals.
fn push_points(out: &mut String, points: &[[f64; 2]]) {
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        push_number(out, p[0], DECIMALS);
        out.push(',');
        push_number(out, p[1], DECIMALS);
    }
}

/// The width layer: each edge as a polyline as wide as its mean width, each dot as a disk of its
/// width, in its stroke's color (or the edge color), under one group opacity so that overlaps at
/// joints do not darken.
fn write_widths(out: &mut String, graph: &StrokeGraph, stroke_of: &[Option<usize>]) {
    out.push_str(
        r#"<g id="widths" fill="none" stroke-linejoin="round" stroke-linecap="round" opacity=""#,
    );
    push_number(out, WIDTH_OPACITY, DECIMALS);
    out.push_str("\">\n");
    for (e, edge) in graph.edges.iter().enumerate() {
        let Some(width) = mean_width(&edge.widths) else {
            continue;
        };
        let color = match stroke_of.get(e).copied().flatten() {
            Some(s) => stroke_color(s),
            None => EDGE_COLOR.to_string(),
        };
        out.push_str(r#"<polyline points=""#);
        push_points(out, &edge.points);
        out.push_str(r#"" stroke=""#);
        out.push_str(&color);
        out.push_str(r#"" stroke-width=""#);
        push_number(out, width, DECIMALS);
        out.push_str("\"/>\n");
    }
    for vertex in graph.vertices.iter().filter(|v| v.degree == 0) {
        if !(vertex.width.is_finite() && vertex.width > 0.0) {
            continue;
        }
        out.push_str(r#"<circle cx=""#);
        push_number(out, vertex.pos[0], DECIMALS);
        out.push_str(r#"" cy=""#);
        push_number(out, vertex.pos[1], DECIMALS);
        out.push_str(r#"" r=""#);
        push_number(out, vertex.width / 2.0, DECIMALS);
        out.push_str(r#"" fill=""#);
        out.push_str(EDGE_COLOR);
        out.push_str("\"/>\n");
    }
    out.push_str("</g>\n");
}

/// Mean of the finite positive widths; `None` when there is none.
fn mean_width(widths: &[f64]) -> Option<f64> {
    let (sum, count) = widths
        .iter()
        .filter(|w| w.is_finite() && **w > 0.0)
        .fold((0.0, 0usize), |(sum, count), w| (sum + w, count + 1));
    (count > 0).then(|| sum / count as f64)
}

/// Median of the finite vertex widths; `None` when there is none.
fn median_vertex_width(graph: &StrokeGraph) -> Option<f64> {
    let mut widths: Vec<f64> = graph
        .vertices
        .iter()
        .map(|v| v.width)
        .filter(|w| w.is_finite())
        .collect();
    crate::median::upper_median(&mut widths)
}

/// One group of filled circles at the vertices whose degree passes `select`; nothing when none
/// does.
fn write_circles(
    out: &mut String,
    graph: &StrokeGraph,
    id: &str,
    color: &str,
    radius: f64,
    select: impl Fn(usize) -> bool,
) {
    let mut chosen = graph
        .vertices
        .iter()
        .filter(|v| select(v.degree))
        .peekable();
    if chosen.peek().is_none() {
        return;
    }
    let _ = writeln!(out, r#"<g id="{id}" fill="{color}" stroke="none">"#);
    for vertex in chosen {
        out.push_str(r#"<circle cx=""#);
        push_number(out, vertex.pos[0], DECIMALS);
        out.push_str(r#"" cy=""#);
        push_number(out, vertex.pos[1], DECIMALS);
        out.push_str(r#"" r=""#);
        push_number(out, radius, DECIMALS);
        out.push_str("\"/>\n");
    }
    out.push_str("</g>\n");
}

/// PNG bytes of an image of `size` written by `write`; `None` for an empty image or if encoding
/// fails, in which case the SVG is written without its backdrop rather than not at all.
fn encode_png(
    size: (u32, u32),
    write: impl FnOnce(&mut Cursor<Vec<u8>>) -> image::ImageResult<()>,
) -> Option<Vec<u8>> {
    if size.0 == 0 || size.1 == 0 {
        return None;
    }
    let mut png = Cursor::new(Vec::new());
    write(&mut png).ok()?;
    Some(png.into_inner())
}

/// Whether `mime` can go into the `data:` URL as it is: `type/subtype` in lowercase ASCII letters,
/// digits and `+.-`.
fn is_mime(mime: &str) -> bool {
    let allowed = |part: &str| {
        !part.is_empty()
            && part
                .bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b"+.-".contains(&b))
    };
    matches!(mime.split_once('/'), Some((kind, subtype)) if allowed(kind) && allowed(subtype))
}
/// SVG path data for joined segments: `M x y C x1 y1 x2 y2 x y C …`, 2 decimals. Empty for no
/// segments. A segment that does not start where the previous one ended begins a new subpath.
pub(crate) fn svg_path_data(segments: &[CubicBezier]) -> String {
    let mut data = String::new();
    let mut at: Option<[f64; 2]> = None;
    for s in segments {
        if at.is_none_or(|p| crate::geometry::dist(p, s.p0) > 1e-6) {
            let separator = if data.is_empty() { "" } else { " " };
            let _ = write!(data, "{separator}M {:.2} {:.2}", s.p0[0], s.p0[1]);
        }
        let _ = write!(
            data,
            " C {:.2} {:.2} {:.2} {:.2} {:.2} {:.2}",
            s.p1[0], s.p1[1], s.p2[0], s.p2[1], s.p3[0], s.p3[1]
        );
        at = Some(s.p3);
    }
    data
}

/// SVG marks for minutiae: a circle (ending, red) or a square (bifurcation, blue) of side `size`
/// px at each position, with a line of length `2 size` along its direction; 2-decimal coordinates.
pub fn svg_marks(minutiae: &[Minutia], size: f64) -> String {
    let mut svg = String::new();
    for m in minutiae {
        let [x, y] = m.pos;
        let tip = [
            x + 2.0 * size * m.direction.cos(),
            y + 2.0 * size * m.direction.sin(),
        ];
        let half = size / 2.0;
        let color = match m.kind {
            MinutiaKind::Ending => {
                let _ = write!(svg, "<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"{half:.2}\"");
                "#d62728"
            }
            MinutiaKind::Bifurcation => {
                let _ = write!(
                    svg,
                    "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{size:.2}\" height=\"{size:.2}\"",
                    x - half,
                    y - half
                );
                "#1f77b4"
            }
        };
        let _ = writeln!(
            svg,
            " fill=\"none\" stroke=\"{color}\" stroke-width=\"1.00\"/>"
        );
        let _ = writeln!(
            svg,
            "<line x1=\"{x:.2}\" y1=\"{y:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{color}\" stroke-width=\"1.00\"/>",
            tip[0], tip[1]
        );
    }
    svg
}

/// A distinct color for stroke `index`: hues spaced by the golden angle.
pub(crate) fn stroke_color(index: usize) -> String {
    let hue = (index as f64 * 137.507_764) % 360.0;
    format!("hsl({hue:.1},75%,42%)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curves::fit_beziers;

    /// The edges written in parallel blocks equal the one loop over them that wrote them before,
    /// with and without curves, below, at and above a block, on any thread count.
    #[test]
    fn edge_lines_in_blocks_equal_the_edge_loop() {
        let mut lcg = crate::synth::lcg(99);
        let mut coordinate = move || (lcg() >> 11) as f64 / (1u64 << 53) as f64 * 3000.0 - 5.0;
        for count in [0, 1, 7, EDGE_BLOCK, EDGE_BLOCK + 1, 3 * EDGE_BLOCK + 17] {
            let edges: Vec<crate::stroke_graph::Edge> = (0..count)
                .map(|e| {
                    let points: Vec<[f64; 2]> = (0..1 + e % 9)
                        .map(|_| [coordinate(), coordinate()])
                        .collect();
                    crate::stroke_graph::Edge {
                        from: 0,
                        to: 0,
                        widths: vec![2.0; points.len()],
                        directions: vec![[1.0, 0.0]; points.len()],
                        points,
                    }
                })
                .collect();
            let graph = StrokeGraph {
                edges,
                ..StrokeGraph::default()
            };
            // Curves for every third edge (the rest drawn as polylines).
            let curves: Vec<Vec<CubicBezier>> = graph
                .edges
                .iter()
                .enumerate()
                .map(|(e, edge)| match e % 3 {
                    0 => fit_beziers(&edge.points, 0.5, 60.0),
                    _ => Vec::new(),
                })
                .collect();
            let with_curves = Features {
                curves: Some(&curves),
                ..Features::default()
            };
            for features in [Features::default(), with_curves] {
                let mut want = String::new();
                for (e, edge) in graph.edges.iter().enumerate() {
                    write_line(&mut want, &edge.points, curves_of(&features, e), None);
                }
                for threads in [1, 3] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .expect("pool");
                    let mut got = String::new();
                    pool.install(|| write_edge_lines(&mut got, &graph, &features));
                    assert_eq!(got, want, "{count} edges, {threads} threads");
                }
            }
        }
    }

    #[test]
    fn path_data_of_joined_segments_and_of_none() {
        let two = fit_beziers(&[[0.0, 0.0], [3.0, 4.0]], 0.0, 60.0);
        assert_eq!(
            svg_path_data(&two),
            "M 0.00 0.00 C 1.00 1.33 2.00 2.67 3.00 4.00"
        );
        assert_eq!(svg_path_data(&[]), "");
    }

    #[test]
    fn minutia_marks_one_shape_and_line_each() {
        let mark = |kind, pos: [f64; 2], direction| Minutia {
            kind,
            vertex: 0,
            pos,
            direction,
            width: 4.0,
            quality: None,
        };
        let svg = svg_marks(
            &[
                mark(MinutiaKind::Ending, [150.0, 100.0], 0.0),
                mark(
                    MinutiaKind::Bifurcation,
                    [50.0, 100.0],
                    std::f64::consts::PI,
                ),
            ],
            6.0,
        );
        assert_eq!(svg.matches("<circle").count(), 1);
        assert_eq!(svg.matches("<rect").count(), 1);
        assert_eq!(svg.matches("<line").count(), 2);
        assert!(svg.contains("x2=\"162.00\" y2=\"100.00\""), "{svg}");
        assert_ne!(stroke_color(0), stroke_color(1));
    }
}
