//! Fingerprint minutiae from the stroke graph (docs/design.md, "Beyond the paper"): ridge
//! endings are the degree-1 vertices, bifurcations the degree-3 vertices, each with a direction
//! from its incident edges.
//!
//! **Direction convention**: an angle in radians in `(-π, π]`, measured in image coordinates (x to
//! the right, y down, so positive angles turn clockwise on screen). Both kinds follow NIST's
//! minutia direction, the one mindtct writes to `.xyt` (docs/fingerprints.md, "Outputs"): the
//! direction points *out of the ridge pattern at the minutia*, the way an ending points,
//! - ending: the direction in which the ridge runs into its end (from the ridge towards the end
//!   point and beyond);
//! - bifurcation: from the fork along the single ridge (the *stem*), away from the two branches:
//!   the direction of the ending that the valley between the branches makes in the inverted
//!   print. The stem is the arm opposite the narrowest angle between two arms.
//!
//! So a minutia keeps its direction when noise turns it from one kind into the other (a branch
//! broken off its fork leaves an ending pointing the same way). ISO/IEC 19794-2 and ANSI INCITS
//! 378 point the other way for both kinds ([`crate::export::iso19794`]).
//!
//! Arm directions are chords over about two ridge widths ([`Edge::end_direction`](crate::Edge::end_direction)).
//!
//! **Border**: minutiae closer than [`MinutiaeOptions::border_margin`] to the border of the print are
//! dropped, because the ridges are cut there, not ended. With a mask, the print region is the
//! morphological closing of the ink by a disk of radius `R` (about 1.5 ridge periods: every
//! valley filled, the outline kept) and its border is where that region ends or the image ends;
//! without a mask it is the image border.
//!
//! **Broken ridges**: two endings that face each other across a short gap are one ridge broken by
//! noise; both are dropped when [`MinutiaeOptions::broken_ridge_gap`] is positive.
//!
//! Input: a [`StrokeGraph`] and optionally its foreground mask. Output: `Vec<Minutia>` in vertex
//! order. Deterministic.

use crate::binary::Binary;
use crate::geometry::dist;
use crate::stroke_graph::StrokeGraph;
use serde::Serialize;

/// Kind of minutia.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MinutiaKind {
    /// A ridge ending (degree-1 vertex).
    Ending,
    /// A ridge bifurcation (degree-3 vertex).
    Bifurcation,
}

/// One minutia.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Minutia {
    /// Ending or bifurcation.
    pub kind: MinutiaKind,
    /// The stroke-graph vertex it comes from (for an ending read from a bifurcation whose branch
    /// crosses a valley, [`crate::fingerprint::minutiae::fingerprint_minutiae`], the junction's, not at `pos`).
    pub vertex: usize,
    /// Position, image coordinates.
    pub pos: [f64; 2],
    /// Direction in radians, in `(-π, π]`, y down (see the module doc for the convention).
    pub direction: f64,
    /// Ridge width at the minutia, px.
    pub width: f64,
    /// Quality 0-100 from the local coherence and contrast of the print
    /// ([`crate::fingerprint::minutiae::fingerprint_minutiae`]); `None` without the fingerprint front end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quality: Option<u8>,
}

/// Options for [`minutiae`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MinutiaeOptions {
    /// Minutiae closer than this to the print's border are dropped, px. Default value: 10.
    pub border_margin: f64,
    /// Radius `R` of the closing that turns the ink into the print region, px; `None` takes
    /// 3 median ridge widths (about 1.5 ridge periods, a period being about two widths), at least
    /// 4 px. Default value: `None`.
    pub region_radius: Option<f64>,
    /// Two endings facing each other closer than this are a broken ridge and both are dropped, px;
    /// 0 keeps them. Default value: 10.
    pub broken_ridge_gap: f64,
    /// How far, in degrees, each of two facing endings may point away from the other.
    /// Default value: 30.
    pub broken_ridge_angle_deg: f64,
    /// Length over which arm directions are measured, in ridge widths at the vertex.
    /// Default value: 2.
    pub tangent_widths: f64,
    /// Shortest arm-direction length, px. Default value: 3.
    pub min_tangent_length: f64,
}

impl Default for MinutiaeOptions {
    fn default() -> Self {
        MinutiaeOptions {
            border_margin: 10.0,
            region_radius: None,
            broken_ridge_gap: 10.0,
            broken_ridge_angle_deg: 30.0,
            tangent_widths: 2.0,
            min_tangent_length: 3.0,
        }
    }
}

/// Ridge endings and bifurcations of `graph`, without those near the print's border (estimated from
/// `mask` when given, else the image border) and, optionally, broken-ridge pairs. See the module
/// doc for the conventions.
pub fn minutiae(
    graph: &StrokeGraph,
    mask: Option<&Binary>,
    options: &MinutiaeOptions,
) -> Vec<Minutia> {
    let mut found = detect(graph, options);
    if options.broken_ridge_gap > 0.0 {
        drop_broken_ridges(&mut found, options);
    }
    if options.border_margin > 0.0 {
        match mask {
            Some(mask) => {
                let radius = options
                    .region_radius
                    .unwrap_or_else(|| (3.0 * median_width(graph)).max(4.0));
                let region = print_region(mask, radius);
                found.retain(|m| {
                    clear_of_border(
                        &region,
                        mask.width,
                        mask.height,
                        m.pos,
                        options.border_margin,
                    )
                });
            }
            None if graph.width > 0 && graph.height > 0 => {
                let (w, h) = (graph.width as f64, graph.height as f64);
                let margin = options.border_margin;
                found.retain(|m| {
                    let [x, y] = m.pos;
                    x >= margin && y >= margin && w - x >= margin && h - y >= margin
                });
            }
            None => {}
        }
    }
    found
}

/// Every degree-1 and degree-3 vertex with its direction.
pub(crate) fn detect(graph: &StrokeGraph, options: &MinutiaeOptions) -> Vec<Minutia> {
    // Outgoing arm directions per vertex, in edge order.
    let mut arms: Vec<Vec<[f64; 2]>> = vec![Vec::new(); graph.vertices.len()];
    for edge in &graph.edges {
        for (vertex, at_start) in [(edge.from, true), (edge.to, false)] {
            let Some(v) = graph.vertices.get(vertex) else {
                continue;
            };
            if v.degree != 1 && v.degree != 3 {
                continue;
            }
            let width = if v.width.is_finite() && v.width > 0.0 {
                v.width
            } else {
                0.0
            };
            let length = (options.tangent_widths * width).max(options.min_tangent_length);
            let fallback = || {
                let d = if at_start {
                    edge.directions.first()
                } else {
                    edge.directions.last()
                };
                d.map(|d| if at_start { *d } else { [-d[0], -d[1]] })
            };
            if let Some(d) = edge.end_direction(at_start, length).or_else(fallback) {
                arms[vertex].push(d);
            }
        }
    }
    let mut found = Vec::new();
    for (v, vertex) in graph.vertices.iter().enumerate() {
        let arm = &arms[v];
        let (kind, inflow) = match (vertex.degree, arm.len()) {
            (1, 1) => (MinutiaKind::Ending, [-arm[0][0], -arm[0][1]]),
            (3, 3) => {
                // The two branches enclose the narrowest angle; the stem is the third arm.
                let pairs = [(0, 1, 2), (0, 2, 1), (1, 2, 0)];
                let mut stem = 2;
                let mut widest = f64::NEG_INFINITY;
                for (i, j, k) in pairs {
                    let closeness = arm[i][0] * arm[j][0] + arm[i][1] * arm[j][1];
                    if closeness > widest {
                        widest = closeness;
                        stem = k;
                    }
                }
                // Out along the stem, away from the branches (the module doc's convention).
                (MinutiaKind::Bifurcation, arm[stem])
            }
            _ => continue,
        };
        let direction = inflow[1].atan2(inflow[0]);
        let direction = if direction.is_finite() {
            direction
        } else {
            0.0
        };
        found.push(Minutia {
            kind,
            vertex: v,
            pos: vertex.pos,
            direction,
            width: vertex.width,
            quality: None,
        });
    }
    found
}

/// Drops pairs of endings that face each other across a gap shorter than `broken_ridge_gap`,
/// closest pairs first, each ending in at most one pair.
pub(crate) fn drop_broken_ridges(found: &mut Vec<Minutia>, options: &MinutiaeOptions) {
    let cos_limit = options.broken_ridge_angle_deg.to_radians().cos();
    let endings: Vec<usize> = (0..found.len())
        .filter(|&i| found[i].kind == MinutiaKind::Ending)
        .collect();
    // Endings sorted by x, so candidates are a window of the sweep (O(n log n + pairs)).
    let mut by_x = endings.clone();
    by_x.sort_by(|&a, &b| found[a].pos[0].total_cmp(&found[b].pos[0]).then(a.cmp(&b)));
    let faces = |from: &Minutia, to: &Minutia, gap: f64| {
        let d = [from.direction.cos(), from.direction.sin()];
        ((to.pos[0] - from.pos[0]) * d[0] + (to.pos[1] - from.pos[1]) * d[1]) >= cos_limit * gap
    };
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (k, &a) in by_x.iter().enumerate() {
        for &b in &by_x[k + 1..] {
            if found[b].pos[0] - found[a].pos[0] > options.broken_ridge_gap {
                break;
            }
            let gap = dist(found[a].pos, found[b].pos);
            if gap <= options.broken_ridge_gap
                && gap > 0.0
                && faces(&found[a], &found[b], gap)
                && faces(&found[b], &found[a], gap)
            {
                pairs.push((gap, a.min(b), a.max(b)));
            }
        }
    }
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)).then(p.2.cmp(&q.2)));
    let mut dropped = vec![false; found.len()];
    for (_, a, b) in pairs {
        if !dropped[a] && !dropped[b] {
            dropped[a] = true;
            dropped[b] = true;
        }
    }
    let mut index = 0;
    found.retain(|_| {
        index += 1;
        !dropped[index - 1]
    });
}

/// Median of all polyline widths (0 when there are none).
fn median_width(graph: &StrokeGraph) -> f64 {
    let mut widths: Vec<f64> = graph
        .edges
        .iter()
        .flat_map(|e| e.widths.iter().copied())
        .filter(|w| w.is_finite())
        .collect();
    crate::median::upper_median(&mut widths).unwrap_or(0.0)
}

/// The print region: the closing of the ink by a disk of radius `radius` (dilate, then erode, both
/// by exact Euclidean distance). Pixels outside the image do not erode it, so a print cut by the
/// image edge keeps its region up to that edge.
pub(crate) fn print_region(mask: &Binary, radius: f64) -> Vec<bool> {
    crate::mask::close_disk(&mask.ink, mask.width as usize, mask.height as usize, radius)
}

/// Whether no pixel outside `region` (and no point outside the image) lies within `margin` of `pos`.
fn clear_of_border(region: &[bool], width: u32, height: u32, pos: [f64; 2], margin: f64) -> bool {
    let (w, h) = (width as f64, height as f64);
    let [x, y] = pos;
    if !(x >= margin && y >= margin && w - x >= margin && h - y >= margin) {
        return false;
    }
    let x0 = (x - margin - 0.5).floor().max(0.0) as usize;
    let x1 = ((x + margin - 0.5).ceil().max(0.0) as usize).min(width as usize - 1);
    let y0 = (y - margin - 0.5).floor().max(0.0) as usize;
    let y1 = ((y + margin - 0.5).ceil().max(0.0) as usize).min(height as usize - 1);
    for py in y0..=y1 {
        for px in x0..=x1 {
            let centre = [px as f64 + 0.5, py as f64 + 0.5];
            if dist(centre, pos) < margin && !region[py * width as usize + px] {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::stroke_graph::graph_from;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Options with the border and broken-ridge filters off, so tests see every minutia.
    pub(crate) fn no_filters() -> MinutiaeOptions {
        MinutiaeOptions {
            border_margin: 0.0,
            broken_ridge_gap: 0.0,
            ..Default::default()
        }
    }

    /// Whether two directions agree within 0.05 rad, whichever way round the circle.
    pub(crate) fn angle_close(a: f64, b: f64) -> bool {
        let d = (a - b).rem_euclid(2.0 * PI);
        d.min(2.0 * PI - d) < 0.05
    }

    #[test]
    fn ending_points_the_way_the_ridge_runs_into_it() {
        // A ridge from (50, 100) to (150, 100): the right end faces +x, the left end -x.
        let g = graph_from(
            &[[50.0, 100.0], [150.0, 100.0]],
            &[(0, 1, vec![[100.0, 100.0]])],
            4.0,
        );
        let m = minutiae(&g, None, &no_filters());
        assert_eq!(m.len(), 2);
        assert!(m
            .iter()
            .all(|m| m.kind == MinutiaKind::Ending && m.width == 4.0));
        assert!(angle_close(m[0].direction, PI), "{}", m[0].direction);
        assert!(angle_close(m[1].direction, 0.0), "{}", m[1].direction);
    }

    #[test]
    fn bifurcation_points_from_the_fork_along_the_stem() {
        // Stem from the left, branches opening to the right (up-right and down-right): the
        // direction points left, away from the branches, as the ending of the valley between
        // the branches does in the inverted print.
        let c = [100.0, 100.0];
        let g = graph_from(
            &[c, [150.0, 70.0], [40.0, 100.0], [150.0, 130.0]],
            &[(0, 1, vec![]), (2, 0, vec![]), (0, 3, vec![])],
            4.0,
        );
        let m = minutiae(&g, None, &no_filters());
        let fork: Vec<_> = m
            .iter()
            .filter(|m| m.kind == MinutiaKind::Bifurcation)
            .collect();
        assert_eq!(fork.len(), 1);
        assert_eq!(fork[0].vertex, 0);
        assert!(angle_close(fork[0].direction, PI), "{}", fork[0].direction);
        assert_eq!(
            m.iter().filter(|m| m.kind == MinutiaKind::Ending).count(),
            3
        );
        // Rotated a quarter turn (stem from above, branches below): the direction turns with it
        // and points up the screen (y down: -π/2).
        let g = graph_from(
            &[c, [70.0, 150.0], [100.0, 40.0], [130.0, 150.0]],
            &[(0, 1, vec![]), (2, 0, vec![]), (0, 3, vec![])],
            4.0,
        );
        let m = minutiae(&g, None, &no_filters());
        assert!(
            angle_close(m[0].direction, -FRAC_PI_2),
            "{}",
            m[0].direction
        );
    }

    #[test]
    fn image_border_margin_without_mask() {
        // Graph is 200 x 200: an ending 5 px from the left edge is dropped, one 50 px in is kept.
        let g = graph_from(&[[5.0, 100.0], [50.0, 100.0]], &[(0, 1, vec![])], 4.0);
        let options = MinutiaeOptions {
            broken_ridge_gap: 0.0,
            ..Default::default()
        };
        let m = minutiae(&g, None, &options);
        assert_eq!(m.len(), 1);
        assert_eq!(m[0].vertex, 1);
    }

    #[test]
    fn print_border_from_the_mask() {
        // Ink: horizontal ridges 4 px wide, period 9, filling x in [40, 160), y in [40, 160).
        let mut mask = Binary::new(200, 200);
        for y in 40..160 {
            if (y - 40) % 9 < 4 {
                for x in 40..160 {
                    mask.set(x, y, true);
                }
            }
        }
        // Endings at the print's left edge (1 px in) and near its top edge (2 px in), and two
        // deep inside.
        let g = graph_from(
            &[[41.0, 42.0], [100.0, 42.0], [60.0, 96.0], [100.0, 96.0]],
            &[(0, 1, vec![]), (2, 3, vec![])],
            4.0,
        );
        let m = minutiae(
            &g,
            Some(&mask),
            &MinutiaeOptions {
                broken_ridge_gap: 0.0,
                ..Default::default()
            },
        );
        let kept: Vec<usize> = m.iter().map(|m| m.vertex).collect();
        assert_eq!(kept, vec![2, 3]);
        // Vertex 1 at (100, 42) lies 2 px inside the region's top edge: dropped with any margin > 2.
        let region = print_region(&mask, 12.0);
        assert!(region[100 * 200 + 100], "valleys are filled");
        assert!(!region[20 * 200 + 100], "outside the print");
    }

    #[test]
    fn broken_ridge_pair_is_dropped_but_not_parallel_endings() {
        // Ridge broken at x in (95, 103); below, endings 7 px apart on two ridges 4 px apart
        // (34 degrees off each other's line) are real and stay.
        let g = graph_from(
            &[
                [20.0, 100.0],
                [95.0, 100.0],
                [103.0, 100.0],
                [180.0, 100.0],
                [20.0, 109.0],
                [95.0, 109.0],
                [101.0, 113.0],
                [180.0, 113.0],
            ],
            &[
                (0, 1, vec![]),
                (2, 3, vec![]),
                (4, 5, vec![]),
                (6, 7, vec![]),
            ],
            4.0,
        );
        let options = MinutiaeOptions {
            border_margin: 0.0,
            ..Default::default()
        };
        let m = minutiae(&g, None, &options);
        let kept: Vec<usize> = m.iter().map(|m| m.vertex).collect();
        assert_eq!(kept, vec![0, 3, 4, 5, 6, 7]);
    }

    #[test]
    fn endings_closer_than_half_a_period_are_one_broken_ridge_whichever_way() {
        let at = |x: f64, direction: f64, vertex: usize| Minutia {
            kind: MinutiaKind::Ending,
            vertex,
            pos: [x, 50.0],
            direction,
            width: 3.0,
            quality: None,
        };
        // Two ends 4 px apart pointing the same way (the apex of a tight recurve), and two
        // 8 px apart, as far as neighbouring ridges' ends: with a period of 9 the first pair goes.
        let mut found = vec![
            at(20.0, FRAC_PI_2, 0),
            at(24.0, FRAC_PI_2, 1),
            at(60.0, FRAC_PI_2, 2),
            at(68.0, FRAC_PI_2, 3),
        ];
        drop_broken_ridges(
            &mut found,
            &MinutiaeOptions {
                broken_ridge_gap: 0.5 * 9.0,
                broken_ridge_angle_deg: 180.0,
                ..Default::default()
            },
        );
        let kept: Vec<usize> = found.iter().map(|m| m.vertex).collect();
        assert_eq!(kept, vec![2, 3]);
    }
}
