//! Point-list input: parse `x y` lines or CSV and build the point set with k-d tree neighbours.

use crate::{Params, PointSet, Result};

/// Builds the point set for a list of points.
pub fn point_set(_list: &[[f64; 2]], _params: &Params) -> Result<PointSet> {
    todo!("point list")
}

/// Image-like extent (width, height) covering all points.
pub fn extent(list: &[[f64; 2]]) -> (u32, u32) {
    let mut w = 0.0f64;
    let mut h = 0.0f64;
    for p in list {
        w = w.max(p[0]);
        h = h.max(p[1]);
    }
    (
        (w.ceil() as u32).saturating_add(1),
        (h.ceil() as u32).saturating_add(1),
    )
}

/// Parses a point list: one point per line, `x y` or `x,y`.
pub fn parse(_text: &str) -> Result<Vec<[f64; 2]>> {
    todo!("point list parse")
}
