//! §3.4 Approximation improvement, and building the stroke graph.
//!
//! In: the refined 1-D [`NodeGraph`] (§3.3) and the [`PointSet`]. Out: a [`StrokeGraph`] whose
//! edges are polylines from vertex to vertex. The steps, each in its own module:
//!
//! 1. `layout`: cut the graph into chains between vertices (nodes of degree other than 2, one node
//!    per closed loop) and resample every chain to node spacing `h = max(3, median width)`
//!    ("equalizing the edge length", adaptation 12 of docs/design.md); with clean-up, an isolated
//!    chain shorter than its stroke is wide is a dot and becomes one lone vertex;
//! 2. `assign`: give every point to the nearest fitted node of its own ink component (a
//!    geodesic Voronoi partition over the neighbour graph), then take the L1 median `q'_i` of each
//!    node's points by Weiszfeld's iteration (`math::l1_median`);
//! 3. `solve`: minimize Eq. (4), `sum W_i |q_i - q'_i|^2 + w |L Q|^2`. By default `L` is the "held"
//!    Laplacian of adaptation 12 (one row `q_i - (q_a + q_b) / 2` per degree-2 node, so ends and
//!    junctions are not pulled inward) with data weight `anchor_weight` on ends and junctions; with
//!    [`LaplacianRule::Uniform`] it is the uniform graph Laplacian, as the paper writes it (whose
//!    preset also sets the data weights to 1);
//! 4. `place` (clean-up only): ends out to where the ink ends, junctions where their arms' lines
//!    meet (adaptations 13, 14), and with
//!    [`ExperimentParams::junctions_on_ink`](crate::ExperimentParams::junctions_on_ink) a junction
//!    left off the ink moved onto the nearest point of its cell;
//! 5. `dense` ([`ExperimentParams::dense_fit`](crate::ExperimentParams::dense_fit), off by
//!    default): after the junctions are placed, every edge re-fitted from its own points, one point
//!    per slice of `2 Dis_ave` at the median offset of the slice's points across the edge, leaving
//!    out the stretch next to each junction where the arms share ink; ends are then placed on the
//!    dense edges;
//! 6. widths (`2 x half_width` of the nearest point) and unit tangents along every polyline.

mod assign;
mod dense;
mod layout;
pub(crate) mod math;
mod place;
mod solve;
#[cfg(test)]
mod tests;

use crate::csr::Csr;
use crate::geometry::floor_i64;
use crate::node_graph::NodeGraph;
use crate::params::{LaplacianRule, Params};
use crate::point_set::PointSet;
use crate::stroke_graph::{Edge, StrokeGraph, Vertex};
use assign::Groups;
use layout::Layout;
use place::{End, Ink, Placement};
use rayon::prelude::*;
use solve::Smoothness;

/// Data weight of a fitted node that no point reached: it follows its neighbours (Eq. (4) still
/// needs a positive weight everywhere for a unique solution).
const UNSUPPORTED_WEIGHT: f64 = 1e-3;
/// Weiszfeld stops when a step is shorter than this, in `unit`s.
const MEDIAN_TOLERANCE: f64 = 1e-4;

/// Fits the refined graph to the points and builds the stroke graph (image size left at zero for
/// the caller to set), nodes spaced `h` apart: parts of one image traced apart (chunks of its
/// components) share the `h` of the whole image (see [`node_spacing`]), so the result does not
/// depend on how the image was cut.
#[cfg(test)]
pub fn fit_with_spacing(
    graph: &NodeGraph,
    points: &PointSet,
    params: &Params,
    h: f64,
) -> StrokeGraph {
    fit_in_components(graph, points, params, h, None)
}

/// [`fit_with_spacing`], given the points' [`PointSet::component_labels`] when they are known.
pub(crate) fn fit_in_components(
    graph: &NodeGraph,
    points: &PointSet,
    params: &Params,
    h: f64,
    components: Option<&[u32]>,
) -> StrokeGraph {
    if graph.nodes.is_empty() {
        return StrokeGraph::default();
    }
    let unit = length_unit(points);
    let layout = layout::equalize(graph, h, params.finish.cleanup);
    let count = layout.pos.len();

    let owned = if graph.owner.len() == points.len() {
        Groups::new(&graph.owner, graph.nodes.len())
    } else {
        Groups::default()
    };
    // Lookups by pixel (a site's first point, the width under a point) must not land on a
    // neighbouring component's pixel: a whole page holds its neighbours, a chunk may not.
    let computed;
    let components = match components {
        Some(components) if components.len() == points.len() => components,
        _ => {
            computed = points.component_labels().0;
            &computed[..]
        }
    };
    // The component of each fitted node: that of the points its old graph nodes owned.
    let component_of = |i: usize| -> Option<u32> {
        layout.near[i]
            .iter()
            .find_map(|&old| owned.of(old as usize).first())
            .and_then(|&p| components.get(p as usize).copied())
    };
    let site_components: Vec<Option<u32>> = (0..layout.pos.len()).map(component_of).collect();
    let cells = assign::assign(
        points,
        components,
        &site_components,
        &owned,
        &layout.pos,
        &layout.near,
        unit,
    );
    let iterations = params.fit.weiszfeld_iterations;
    // A ten-thousandth of a pixel (of `Dis_ave` for point lists): far below what the output keeps
    // (0.01 px), and it halves the Weiszfeld work on a page (most cells settle in a few steps).
    let tolerance = MEDIAN_TOLERANCE * unit;
    // Per-node medians are independent: parallel, and the same whatever the thread count.
    let medians: Vec<Option<[f64; 2]>> = (0..count)
        .into_par_iter()
        .map_init(math::MedianScratch::default, |scratch, i| {
            math::l1_median(&points.points, cells.of(i), iterations, tolerance, scratch)
        })
        .collect();

    let degrees = layout.degrees();
    let anchor = params.fit.anchor_weight;
    let mut weights = vec![1.0; count];
    let mut targets = layout.pos.clone();
    for i in 0..count {
        match medians[i] {
            Some(m) => targets[i] = m,
            None => weights[i] = UNSUPPORTED_WEIGHT,
        }
    }
    for (k, &degree) in degrees.iter().enumerate() {
        let i = layout.vertex_unknown(k) as usize;
        if degree != 2 && medians[i].is_some() {
            weights[i] = anchor;
        }
    }
    let mut polylines: Vec<Vec<u32>> = layout.edges.iter().map(|e| layout.polyline(e)).collect();
    let smoothness = match params.fit.laplacian {
        LaplacianRule::Uniform => uniform_laplacian(&polylines, count),
        LaplacianRule::Held => held_laplacian(&layout, &polylines, &degrees),
    };
    let mut positions = solve::solve(&targets, &weights, &smoothness, params.fit.smoothness)
        .unwrap_or_else(|| targets.clone());

    // The coarse unknown each position stands for (the dense re-fit appends positions).
    let mut parent: Vec<u32> = (0..positions.len() as u32).collect();
    // Dense re-fit needs the clean-up's junction placement first (its slices stop one width
    // short of the junctions), and steady slices: off in dropout mode, whose ink is broken.
    let dense = params.experiments.dense_fit && params.finish.cleanup && !points.dropout;
    if params.finish.cleanup {
        let ink = Ink::new(points, unit, components);

        let placement = Placement {
            ink: &ink,
            spacing: h,
            step: 0.5 * unit.min(1.0),
        };
        let ends = vertex_ends(&layout, &polylines);
        for (k, &degree) in degrees.iter().enumerate() {
            let width = vertex_width(graph, &layout, k, h);
            let v = layout.vertex_unknown(k);
            if degree >= 3 {
                let component = site_components[v as usize];
                placement.place_junction(
                    v,
                    component,
                    &ends[k],
                    width,
                    &mut polylines,
                    &mut positions,
                );
            }
        }
        if params.experiments.junctions_on_ink {
            for (k, &degree) in degrees.iter().enumerate() {
                let v = layout.vertex_unknown(k);
                if degree >= 3 {
                    let component = site_components[v as usize];
                    place::onto_ink(
                        &ink,
                        points,
                        cells.of(v as usize),
                        component,
                        &mut positions[v as usize],
                    );
                }
            }
        }
        if dense {
            refit_densely(
                &layout,
                graph,
                &degrees,
                h,
                &cells,
                points,
                &mut polylines,
                &mut positions,
                &mut parent,
            );
        }
        for (k, &degree) in degrees.iter().enumerate() {
            let width = vertex_width(graph, &layout, k, h);
            let v = layout.vertex_unknown(k);
            if degree == 1 {
                let component = site_components[v as usize];
                placement.place_end(v, component, &ends[k], width, &polylines, &mut positions);
            }
        }
    }
    let width = |p: [f64; 2], v: u32| {
        let own = site_components.get(v as usize).copied().flatten();
        let on_own = |q: u32| own.is_none_or(|c| components.get(q as usize) == Some(&c));
        width_at(graph, points, &layout, &cells, p, v, on_own)
    };
    let fitted = build(&layout, &polylines, &positions, &degrees, |p, i| {
        width(p, parent[i as usize])
    });
    // The fit's output is a valid stroke graph (ARCHITECTURE.md, "What each boundary
    // guarantees"); checked in debug builds, as every stage checks its own.
    debug_assert_eq!(fitted.validate(), Ok(()));
    fitted
}

/// [`ExperimentParams::dense_fit`](crate::ExperimentParams::dense_fit): every edge re-fitted from
/// its own points (see `dense`), leaving out one stroke width at each junction end.
#[allow(clippy::too_many_arguments)]
fn refit_densely(
    layout: &Layout,
    graph: &NodeGraph,
    degrees: &[usize],
    h: f64,
    cells: &Groups,
    points: &PointSet,
    polylines: &mut [Vec<u32>],
    positions: &mut Vec<[f64; 2]>,
    parent: &mut Vec<u32>,
) {
    // Arm directions at each junction end, from the fitted polylines two widths out.
    let direction = |edge: usize, at_start: bool, reach: f64| -> Option<[f64; 2]> {
        let mut arm: Vec<[f64; 2]> = polylines[edge]
            .iter()
            .map(|&i| positions[i as usize])
            .collect();
        if !at_start {
            arm.reverse();
        }
        let s = crate::geometry::arc_lengths(&arm);
        let (far, _) = crate::geometry::point_at(&arm, &s, reach.min(s[s.len() - 1]));
        math::unit([far[0] - arm[0][0], far[1] - arm[0][1]])
    };
    let mut skips: Vec<[f64; 2]> = vec![[0.0, 0.0]; layout.edges.len()];
    for (k, ends) in vertex_ends(layout, polylines).iter().enumerate() {
        if degrees[k] < 3 {
            continue;
        }
        let w = vertex_width(graph, layout, k, h);
        let arms: Vec<Option<[f64; 2]>> = ends
            .iter()
            .map(|end| direction(end.edge, end.at_start, 2.0 * w))
            .collect();
        for (i, end) in ends.iter().enumerate() {
            // Two strokes of width w leaving at angle θ share ink out to about w / sin θ along
            // each: the slices start there (θ at most 90°; one width at least, four at most,
            // where the junction's arm lines end).
            let sine = arms[i].map_or(1.0, |u| {
                arms.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .filter_map(|(_, v)| *v)
                    .map(|v| {
                        let cos = (u[0] * v[0] + u[1] * v[1]).max(0.0);
                        (1.0 - cos * cos).sqrt()
                    })
                    .fold(1.0, f64::min)
            });
            let skip = (w / sine.max(0.25)).clamp(w, 4.0 * w);
            skips[end.edge][usize::from(!end.at_start)] = skip;
        }
    }
    let edges = layout
        .edges
        .iter()
        .zip(polylines.iter_mut())
        .zip(&skips)
        .map(|((e, ids), &skip)| dense::EdgeSpan {
            ids,
            owners: layout.polyline(e),
            skip,
        })
        .collect();
    let spacing = crate::params::DENSE_SPACING * points.spacing.max(length_unit(points));
    dense::refit(edges, positions, parent, cells, points, spacing);
}

/// Lengths in pixels for images; in units of the point spacing `Dis_ave` for point lists.
fn length_unit(points: &PointSet) -> f64 {
    if points.grid.is_some() || !(points.spacing.is_finite() && points.spacing > 0.0) {
        1.0
    } else {
        points.spacing
    }
}

/// Adaptation 12: the node spacing `h = max(3, spacing_factor x median stroke width)` over the
/// nodes of `graphs` (the refined graphs of all parts of one input; lengths in the unit of
/// `points`, any one of the parts' point sets).
pub fn node_spacing(graphs: &[&NodeGraph], points: &PointSet, params: &Params) -> f64 {
    let unit = length_unit(points);
    let mut widths: Vec<f64> = graphs
        .iter()
        .flat_map(|graph| &graph.nodes)
        .map(|n| n.width)
        .filter(|w| w.is_finite() && *w > 0.0)
        .collect();
    let floor = 3.0 * unit;
    match crate::median::upper_median(&mut widths) {
        Some(median) => (params.fit.spacing_factor * median).max(floor),
        None => floor,
    }
}

/// The local stroke width at vertex `k`: its graph node's width, or `h` when that is unknown.
fn vertex_width(graph: &NodeGraph, layout: &Layout, k: usize, h: f64) -> f64 {
    let w = graph.nodes[layout.vertex_node[k] as usize].width;
    if w.is_finite() && w > 0.0 {
        w
    } else {
        h
    }
}

/// The edge ends at each vertex.
fn vertex_ends(layout: &Layout, polylines: &[Vec<u32>]) -> Vec<Vec<End>> {
    let mut ends = vec![Vec::new(); layout.vertex_node.len()];
    for (edge, e) in layout.edges.iter().enumerate() {
        debug_assert_eq!(polylines[edge][0], layout.vertex_unknown(e.from));
        ends[e.from].push(End {
            edge,
            at_start: true,
        });
        ends[e.to].push(End {
            edge,
            at_start: false,
        });
    }
    ends
}

/// Adaptation 12: smoothness rows `q_i - (q_a + q_b) / 2` only where the curve passes through
/// (chain interiors and the anchor of a closed loop), none at ends and junctions.
fn held_laplacian(layout: &Layout, polylines: &[Vec<u32>], degrees: &[usize]) -> Smoothness {
    let mut rows = Smoothness::new();
    for ids in polylines {
        for w in ids.windows(3) {
            rows.push(w[1], &[w[0], w[2]]);
        }
    }
    for (edge, e) in layout.edges.iter().enumerate() {
        let ids = &polylines[edge];
        if e.from == e.to && degrees[e.from] == 2 && ids.len() >= 4 {
            rows.push(ids[0], &[ids[1], ids[ids.len() - 2]]);
        }
    }
    rows
}

/// The paper's Eq. (4) as written: the uniform graph Laplacian, a row for every node.
fn uniform_laplacian(polylines: &[Vec<u32>], count: usize) -> Smoothness {
    let neighbors = Csr::build(count, |sink| {
        for ids in polylines {
            for w in ids.windows(2) {
                sink.push(w[0] as usize, w[1]);
                sink.push(w[1] as usize, w[0]);
            }
        }
    });
    let mut rows = Smoothness::new();
    for i in 0..count {
        rows.push(i as u32, neighbors.row(i));
    }
    rows
}

/// Stroke width at a fitted position: `2 x half_width` of the pixel under it if `on_own` (it is
/// on the node's own component), else of the nearest of the node's points, else the old node's
/// width.
fn width_at(
    graph: &NodeGraph,
    points: &PointSet,
    layout: &Layout,
    cells: &Groups,
    p: [f64; 2],
    unknown: u32,
    on_own: impl Fn(u32) -> bool,
) -> f64 {
    let half = |i: u32| points.half_width.get(i as usize).map(|&h| 2.0 * h as f64);
    let cell = cells.of(unknown as usize);
    if let Some(grid) = &points.grid {
        let under = grid.point_at(floor_i64(p[0]), floor_i64(p[1]));
        if let Some(w) = under.filter(|&q| on_own(q)).and_then(half) {
            return w;
        }
    }
    let nearest = cell.iter().copied().min_by(|&a, &b| {
        let (da, db) = (
            math::distance(points.points[a as usize], p),
            math::distance(points.points[b as usize], p),
        );
        da.total_cmp(&db).then(a.cmp(&b))
    });
    if let Some(w) = nearest.and_then(half) {
        return w;
    }
    let w = graph.nodes[layout.near[unknown as usize][0] as usize].width;
    if w.is_finite() && w >= 0.0 {
        w
    } else {
        0.0
    }
}

/// Unit tangents by central differences (wrapping around a closed loop).
fn directions(line: &[[f64; 2]], closed: bool) -> Vec<[f64; 2]> {
    let n = line.len();
    let closed = closed && n >= 4;
    let chord = math::unit([line[n - 1][0] - line[0][0], line[n - 1][1] - line[0][1]]);
    let mut last = chord.unwrap_or([1.0, 0.0]);
    (0..n)
        .map(|i| {
            let prev = if i > 0 {
                i - 1
            } else if closed {
                n - 2
            } else {
                0
            };
            let next = if i + 1 < n {
                i + 1
            } else if closed {
                1
            } else {
                n - 1
            };
            let d = [line[next][0] - line[prev][0], line[next][1] - line[prev][1]];
            last = math::unit(d).unwrap_or(last);
            last
        })
        .collect()
}

fn build(
    layout: &Layout,
    polylines: &[Vec<u32>],
    positions: &[[f64; 2]],
    degrees: &[usize],
    width_at: impl Fn([f64; 2], u32) -> f64,
) -> StrokeGraph {
    let vertices = (0..layout.vertex_node.len())
        .map(|k| {
            let v = layout.vertex_unknown(k);
            let pos = positions[v as usize];
            Vertex {
                pos,
                degree: degrees[k],
                width: width_at(pos, v),
            }
        })
        .collect();
    let edges = layout
        .edges
        .iter()
        .zip(polylines)
        .map(|(e, ids)| {
            let line: Vec<[f64; 2]> = ids.iter().map(|&i| positions[i as usize]).collect();
            let widths = ids
                .iter()
                .zip(&line)
                .map(|(&i, &p)| width_at(p, i))
                .collect();
            let directions = directions(&line, e.from == e.to);
            Edge {
                from: e.from,
                to: e.to,
                points: line,
                widths,
                directions,
            }
        })
        .collect();
    StrokeGraph {
        width: 0,
        height: 0,
        vertices,
        edges,
    }
}
