//! §3.2 Node graph H and non-linear region clustering.

use crate::{NodeGraph, Params, PointSet, Samples};

/// Builds graph H with clusters.
pub fn build(_points: &PointSet, _samples: &Samples, _params: &Params) -> NodeGraph {
    todo!("graph")
}
