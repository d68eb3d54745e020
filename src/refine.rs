//! §3.3 Edge refinement: contraction, merging, clean-up.

use crate::{NodeGraph, Params, PointSet};

/// Refines H into a 1-D graph.
pub fn refine(_graph: &NodeGraph, _points: &PointSet, _params: &Params) -> NodeGraph {
    todo!("refine")
}
