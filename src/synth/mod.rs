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
