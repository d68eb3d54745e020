//! The pipeline on a 3D point set, the paper's Fig. 7: its four stages with three principal axes
//! (Eq. (1)-(3)) and the least squares of Eq. (4) in space, each a submodule following the
//! plane's stage of the same name (docs/design.md, "Point sets in space"). There is no raster,
//! skeleton or sub-pixel step in space: the fit's polylines are the result.
//!
//! ```text
//! x y z list ─points─> Cloud (k nearest, Dis_ave, tube diameters) ─§3.1 sample─> nodes
//!            ─§3.2 H, clusters; §3.3 contraction, merging, clean-up─> 1-D graph
//!            ─§3.4 fit─> CurveGraph3d
//! ```

mod fit;
mod math;
mod points;
mod refine;
mod sample;

use crate::curve3d::CurveGraph3d;
use crate::error::Result;
use crate::params::Params;

/// What tracing a 3D list gives: the graph in the list's units, the number of distinct points
/// traced, `Some(share)` when the set is not tube-shaped (then the graph is empty) and how many
/// distinct points were left out as a sparse cloud around the tubes.
pub(crate) fn trace(
    list: &[[f64; 3]],
    params: &Params,
) -> Result<(CurveGraph3d, usize, Option<f64>, usize)> {
    let (cloud, units, not_tube, left_out) = points::cloud(list, params)?;
    let count = cloud.len();
    if not_tube.is_some() || count == 0 {
        return Ok((CurveGraph3d::default(), count, not_tube, left_out));
    }
    let sampled = sample::sample(&cloud, params);
    let refined = refine::refine(&cloud, &sampled, params);
    let mut graph = fit::fit(&cloud, &refined, params);
    // Back to the list's units; edge ends are their vertices' positions exactly.
    for v in &mut graph.vertices {
        v.pos = units.to_list(v.pos);
        v.width *= units.scale;
    }
    for e in &mut graph.edges {
        for p in &mut e.points {
            *p = units.to_list(*p);
        }
        for w in &mut e.widths {
            *w *= units.scale;
        }
        let last = e.points.len() - 1;
        e.points[0] = graph.vertices[e.from].pos;
        e.points[last] = graph.vertices[e.to].pos;
    }
    debug_assert_eq!(graph.validate(), Ok(()));
    Ok((graph, count, not_tube, left_out))
}
