//! §3.1 Anisotropic adaptive sampling.

use crate::{Params, PointSet, Samples};

/// Samples nodes over the points.
pub fn sample(_points: &PointSet, _params: &Params) -> Samples {
    todo!("sampling")
}
