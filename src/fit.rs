//! §3.4 Approximation improvement: equalize, L1 medians, Laplacian least squares; build the
//! stroke graph.

use crate::{NodeGraph, Params, PointSet, StrokeGraph};

/// Fits the refined graph to the points and builds the stroke graph.
pub fn fit(_graph: &NodeGraph, _points: &PointSet, _params: &Params) -> StrokeGraph {
    todo!("fit")
}
