//! Drawing centerlines back to pixels: [`render`] turns polylines with a width at each point into
//! a [`Binary`]. [`crate::strokes::coverage_iou`] compares a traced graph with its ink this way, and
//! the test kit (`ridgeline-testkit`) draws its cases with known centerlines with it.

use crate::binary::Binary;

/// A stroke to draw: a centerline polyline with the stroke width at each point (round caps and
/// joins). A closed stroke repeats its first point at the end. The test kit's cases carry their
/// true centerlines as these.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// Centerline points, image coordinates.
    pub points: Vec<[f64; 2]>,
    /// Stroke width at each point, px.
    pub widths: Vec<f64>,
}

impl Stroke {
    /// A stroke of constant width.
    pub fn new(points: Vec<[f64; 2]>, width: f64) -> Self {
        let widths = vec![width; points.len()];
        Stroke { points, widths }
    }

    /// The largest width along the stroke (0 for an empty stroke).
    pub fn max_width(&self) -> f64 {
        self.widths.iter().fold(0.0, |m: f64, &w| m.max(w))
    }

    /// Moves every point by `offset`.
    pub fn translate(&mut self, offset: [f64; 2]) {
        for p in &mut self.points {
            p[0] += offset[0];
            p[1] += offset[1];
        }
    }
}

/// Renders strokes thickly: a pixel is ink when its center lies within half the (linearly
/// interpolated) width of a stroke's centerline; round caps and joins.
///
/// Each segment only visits the pixels of its own bounding box, and the test is done on squared
/// distances without allocating, so a dense A4 page renders in a few tens of milliseconds.
pub fn render(strokes: &[Stroke], width: u32, height: u32) -> Binary {
    let mut binary = Binary::new(width, height);
    let w = width as usize;
    for stroke in strokes {
        let n = stroke.points.len().min(stroke.widths.len());
        for i in 0..n {
            let a = stroke.points[i];
            let b = stroke.points[(i + 1).min(n - 1)];
            // A lone point is its own segment (a dot); otherwise the last point is covered by
            // the previous segment's cap.
            if i + 1 == n && n > 1 {
                break;
            }
            let (ra, rb) = (
                stroke.widths[i] / 2.0,
                stroke.widths[(i + 1).min(n - 1)] / 2.0,
            );
            let r = ra.max(rb);
            let x0 = (a[0].min(b[0]) - r - 1.0).floor().max(0.0) as usize;
            let x1 = (a[0].max(b[0]) + r + 1.0).ceil().clamp(0.0, width as f64) as usize;
            let y0 = (a[1].min(b[1]) - r - 1.0).floor().max(0.0) as usize;
            let y1 = (a[1].max(b[1]) + r + 1.0).ceil().clamp(0.0, height as f64) as usize;
            let d = [b[0] - a[0], b[1] - a[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let inv_len2 = if len2 > 0.0 { 1.0 / len2 } else { 0.0 };
            for y in y0..y1 {
                let py = y as f64 + 0.5 - a[1];
                let row = &mut binary.ink[y * w..(y + 1) * w];
                for (x, ink) in row.iter_mut().enumerate().take(x1).skip(x0) {
                    if *ink {
                        continue;
                    }
                    let px = x as f64 + 0.5 - a[0];
                    let t = ((px * d[0] + py * d[1]) * inv_len2).clamp(0.0, 1.0);
                    let (ex, ey) = (px - t * d[0], py - t * d[1]);
                    let radius = ra + t * (rb - ra);
                    if ex * ex + ey * ey <= radius * radius {
                        *ink = true;
                    }
                }
            }
        }
    }
    binary
}
