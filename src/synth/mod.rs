//! Ground-truth fixtures: known centerlines rendered thickly, shared by the tests, the benchmarks
//! and the generator of `samples/`.

use crate::Binary;

/// A true stroke: a centerline polyline with the stroke width at each point (round caps and joins).
/// A closed stroke repeats its first point at the end.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// Centerline points, image coordinates.
    pub points: Vec<[f64; 2]>,
    /// Stroke width at each point, px.
    pub widths: Vec<f64>,
}

/// One generated test image with its truth.
#[derive(Clone, Debug)]
pub struct Case {
    /// Unique name, e.g. `x30_w8`.
    pub name: String,
    /// Group for tables: `hard`, `text`, `prints`.
    pub group: String,
    /// The rendered foreground (after any dropout).
    pub binary: Binary,
    /// The true centerlines.
    pub strokes: Vec<Stroke>,
}

impl Stroke {
    /// A stroke of constant width.
    pub fn new(points: Vec<[f64; 2]>, width: f64) -> Self {
        let widths = vec![width; points.len()];
        Stroke { points, widths }
    }
}

/// Renders strokes thickly: a pixel is ink when its center lies within half the (linearly
/// interpolated) width of a stroke's centerline; round caps and joins.
pub fn render(strokes: &[Stroke], width: u32, height: u32) -> Binary {
    let mut binary = Binary::new(width, height);
    for stroke in strokes {
        let n = stroke.points.len();
        for i in 0..n {
            let a = stroke.points[i];
            let b = stroke.points[(i + 1).min(n - 1)];
            let (ra, rb) = (
                stroke.widths[i] / 2.0,
                stroke.widths[(i + 1).min(n - 1)] / 2.0,
            );
            let r = ra.max(rb);
            let x0 = (a[0].min(b[0]) - r - 1.0).floor().max(0.0) as i64;
            let x1 = (a[0].max(b[0]) + r + 1.0).ceil().min(width as f64) as i64;
            let y0 = (a[1].min(b[1]) - r - 1.0).floor().max(0.0) as i64;
            let y1 = (a[1].max(b[1]) + r + 1.0).ceil().min(height as f64) as i64;
            let d = [b[0] - a[0], b[1] - a[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            for y in y0..y1 {
                for x in x0..x1 {
                    let p = [x as f64 + 0.5, y as f64 + 0.5];
                    let t = if len2 > 0.0 {
                        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let q = [a[0] + t * d[0], a[1] + t * d[1]];
                    let radius = ra + t * (rb - ra);
                    if (p[0] - q[0]).hypot(p[1] - q[1]) <= radius {
                        binary.set(x, y, true);
                    }
                }
            }
        }
    }
    binary
}
