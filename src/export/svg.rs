//! SVG output: the centerlines drawn over the source image, for looking at a result in a browser.
//!
//! Coordinates are image coordinates (pixel `(x, y)` covers `[x, x+1] x [y, y+1]`), so the
//! polylines are written as they are, over an `<image>` that covers `[0, W] x [0, H]`. The document
//! is written by hand rather than through the `svg` crate: nothing in it comes from the user but
//! numbers, it streams into one `String` without a node per polyline, and the attribute order stays
//! fixed, which keeps the output byte-for-byte deterministic.

use std::fmt::Write;
use std::io::Cursor;

use base64::Engine;
use image::{GrayImage, ImageFormat};

use super::push_number;
use crate::StrokeGraph;

/// Color of the centerlines (and of isolated dots).
pub const EDGE_COLOR: &str = "#e6194b";
/// Color of the markers at stroke ends (degree 1).
pub const ENDPOINT_COLOR: &str = "#3cb44b";
/// Color of the markers at junctions and crossings (degree 3 or more).
pub const JUNCTION_COLOR: &str = "#4363d8";

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
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            show_vertices: true,
            stroke_width: None,
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
}

/// The line width used for `graph`: the explicit one when it is a positive number, otherwise
/// `max(0.6, 0.12 x median vertex width)`.
pub fn stroke_width(graph: &StrokeGraph, options: &SvgOptions) -> f64 {
    if let Some(width) = options.stroke_width.filter(|w| w.is_finite() && *w > 0.0) {
        return width;
    }
    let mut widths: Vec<f64> = graph
        .vertices
        .iter()
        .map(|v| v.width)
        .filter(|w| w.is_finite())
        .collect();
    if widths.is_empty() {
        return 0.6;
    }
    widths.sort_by(f64::total_cmp);
    let median = widths[widths.len() / 2];
    (0.12 * median).max(0.6)
}

/// Writes `graph` as an SVG document of the image's size, over `image` (embedded as a base64 PNG)
/// when one is given.
pub fn to_string(graph: &StrokeGraph, image: Option<&GrayImage>, options: &SvgOptions) -> String {
    let points: usize = graph.edges.iter().map(|e| e.points.len()).sum();
    let mut out = String::with_capacity(512 + 14 * points + 64 * graph.vertices.len());
    let (w, h) = (graph.width, graph.height);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    if let Some(png) = image.and_then(encode_png) {
        // preserveAspectRatio="none": the picture must cover [0, W] x [0, H] exactly, or the
        // centerlines would drift off their pixels; pixelated so that zooming in shows the pixels
        // the centerline was traced from.
        let _ = write!(
            out,
            r#"<image x="0" y="0" width="{w}" height="{h}" preserveAspectRatio="none" style="image-rendering:pixelated" href="data:image/png;base64,"#
        );
        base64::engine::general_purpose::STANDARD.encode_string(&png, &mut out);
        out.push_str("\"/>\n");
    }

    let line = stroke_width(graph, options);
    out.push_str(r#"<g id="edges" fill="none" stroke=""#);
    out.push_str(EDGE_COLOR);
    out.push_str(r#"" stroke-width=""#);
    push_number(&mut out, line, DECIMALS);
    out.push_str("\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n");
    for edge in &graph.edges {
        out.push_str(r#"<polyline points=""#);
        for (i, p) in edge.points.iter().enumerate() {
            if i > 0 {
                out.push(' ');
            }
            push_number(&mut out, p[0], DECIMALS);
            out.push(',');
            push_number(&mut out, p[1], DECIMALS);
        }
        out.push_str("\"/>\n");
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
    out.push_str("</svg>\n");
    out
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

/// PNG bytes of `image`; `None` for an empty image or if encoding fails, in which case the SVG is
/// written without its backdrop rather than not at all.
fn encode_png(image: &GrayImage) -> Option<Vec<u8>> {
    if image.width() == 0 || image.height() == 0 {
        return None;
    }
    let mut png = Cursor::new(Vec::new());
    image.write_to(&mut png, ImageFormat::Png).ok()?;
    Some(png.into_inner())
}
