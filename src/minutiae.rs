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
use crate::fingerprint::PrintAnalysis;
use crate::geometry::dist;
use crate::geometry::{arc_lengths, point_at};
use crate::params::FingerprintParams;
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
    /// crosses a valley, [`fingerprint_minutiae`], the junction's, not at `pos`).
    pub vertex: usize,
    /// Position, image coordinates.
    pub pos: [f64; 2],
    /// Direction in radians, in `(-π, π]`, y down (see the module doc for the convention).
    pub direction: f64,
    /// Ridge width at the minutia, px.
    pub width: f64,
    /// Quality 0-100 from the local coherence and contrast of the print
    /// ([`fingerprint_minutiae`]); `None` without the fingerprint front end.
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

/// The minutiae of a print traced with the fingerprint front end (docs/fingerprints.md,
/// "Minutiae"): every ending and bifurcation of `graph`, less those the structure of the ridges
/// shows to be false, each with a quality from `print`. Lengths are in ridge periods `T` of the
/// block where they are measured:
///
/// - border: within `border_margin` px of the print's border (the segmentation mask, and the
///   closing of the enhanced ridges by one ridge period) or the image's;
/// - fragments and islands: an edge with two free ends shorter than `fragment_periods · T`
///   (both ends go), or whose ends come within `T` of each other around at least `3 T` of ridge
///   (a ring broken once);
/// - spurs: an edge from a bifurcation to a free end shorter than `spur_periods · T` (both go);
/// - bridges: an edge between two bifurcations shorter than `bridge_periods · T` that runs across
///   the flow (more than 45° from the local ridge orientation): a bar between neighbouring ridges;
/// - lakes and pores: two bifurcations joined by two edges each shorter than
///   `2 bridge_periods · T` (both go);
/// - broken ridges: two endings facing each other along the flow within `gap_periods · T`;
/// - detached branches: a bifurcation of which one arm crosses a valley in the gray image (off
///   [`PrintAnalysis::ridges`] for at least 1 px, back on them within `0.6 T` of the junction)
///   while the other two stay on the ridges for `T` is an ending at the arm's tip: a ridge that
///   stops just short of its neighbour, the shallow valley at its tip filled by the enhancement.
///
/// The quality is [`PrintAnalysis::quality_at`]: coherence times contrast, in percent.
pub fn fingerprint_minutiae(
    graph: &StrokeGraph,
    print: &PrintAnalysis,
    params: &FingerprintParams,
) -> Vec<Minutia> {
    let options = MinutiaeOptions::default();
    let confirmed = confirmed_edges(graph, &print.ridges, params.confirmed_share);
    let graph = &confirmed;
    let mut found = detect(graph, &options);
    let mut false_vertex = vec![false; graph.vertices.len()];
    let degree = |v: usize| graph.vertices.get(v).map_or(0, |v| v.degree);
    // Short edges between two bifurcations, by vertex pair, to find lakes.
    let mut short_bars: Vec<(usize, usize)> = Vec::new();
    for edge in &graph.edges {
        let (a, b) = (edge.from, edge.to);
        if a == b || a >= false_vertex.len() || b >= false_vertex.len() {
            continue;
        }
        let length: f64 = edge.points.windows(2).map(|p| dist(p[0], p[1])).sum();
        let (Some(first), Some(last)) = (edge.points.first(), edge.points.last()) else {
            continue;
        };
        let middle = [(first[0] + last[0]) / 2.0, (first[1] + last[1]) / 2.0];
        let period = print.periods.at(middle).max(1.0);
        let short = |factor: f64| length < factor * period;
        let remove = match (degree(a), degree(b)) {
            (1, 1) => {
                short(params.fragment_periods) || nearly_closed([*first, *last], length, period)
            }
            (1, 3) | (3, 1) => short(params.spur_periods),
            (3, 3) => {
                if short(2.0 * params.bridge_periods) {
                    short_bars.push((a.min(b), a.max(b)));
                }
                short(params.bridge_periods) && print.across_the_flow(*first, *last)
            }
            _ => false,
        };
        if remove {
            false_vertex[a] = true;
            false_vertex[b] = true;
        }
    }
    short_bars.sort_unstable();
    for pair in short_bars.windows(2) {
        if pair[0] == pair[1] {
            false_vertex[pair[0].0] = true;
            false_vertex[pair[0].1] = true;
        }
    }
    found.retain(|m| !false_vertex.get(m.vertex).copied().unwrap_or(false));
    detached_branches(&mut found, graph, print);
    // Broken ridges, with the gap in periods of the print's median period.
    let mut periods: Vec<f64> = found.iter().map(|m| print.periods.at(m.pos)).collect();
    let typical = if periods.is_empty() {
        params.default_period
    } else {
        let middle = periods.len() / 2;
        *periods.select_nth_unstable_by(middle, f64::total_cmp).1
    };
    if params.gap_periods > 0.0 {
        // Two endings closer than half a period, whichever way they point, are one ridge broken
        // where it turns too fast for the filter (the apex of a loop's innermost ridge): the
        // ends of two ridges are at least a valley, about half a period, apart.
        drop_broken_ridges(
            &mut found,
            &MinutiaeOptions {
                broken_ridge_gap: 0.5 * typical,
                broken_ridge_angle_deg: 180.0,
                ..options
            },
        );
        drop_broken_ridges(
            &mut found,
            &MinutiaeOptions {
                broken_ridge_gap: params.gap_periods * typical,
                ..options
            },
        );
    }
    if params.cloud_periods > 0.0 {
        drop_clouds(&mut found, typical * params.cloud_periods);
    }
    // The border: distance to the nearest pixel outside the print, which is both inside the
    // segmentation mask and inside the closing of the enhanced ridges by a disk of one ridge
    // period (every valley filled, the outline of the ridges kept): the mask's blocks reach past
    // the last ridges by up to a block and its smoothing, and the ridges cut by the outline
    // end there, not at minutiae.
    let grid = print.segmentation.grid;
    if params.border_margin > 0.0 && !grid.is_empty() {
        let (w, h) = (grid.width as usize, grid.height as usize);
        let region = print_region(&print.ridges, typical.max(4.0));
        let outside: Vec<bool> = print
            .segmentation
            .pixel_mask()
            .iter()
            .zip(&region)
            .map(|(&p, &r)| !(p && r))
            .collect();
        let margin = params.border_margin;
        let to_outside = crate::mask::squared_distances_to(&outside, w, h, margin);
        found.retain(|m| {
            let [x, y] = m.pos;
            if !(x >= margin && y >= margin && w as f64 - x >= margin && h as f64 - y >= margin) {
                return false;
            }
            let index = (y as usize).min(h - 1) * w + (x as usize).min(w - 1);
            f64::from(to_outside[index]) >= margin * margin
        });
    }
    for m in &mut found {
        m.quality = Some(print.quality_at(m.pos));
    }
    found
}

/// Bifurcations of which one arm leaves the junction across a valley the gray image shows: off
/// [`PrintAnalysis::ridges`] for at least a pixel within one period of the junction, on them
/// again beyond, while the other two arms stay on the ridges over the same period. The ridge of
/// that arm ends just short of its neighbour and the enhancement, which smooths along the flow,
/// filled the shallow valley at its tip: the minutia is an ending at the far side of the gap,
/// pointing towards the junction.
fn detached_branches(found: &mut [Minutia], graph: &StrokeGraph, print: &PrintAnalysis) {
    const STEP: f64 = 0.5;
    // Per vertex, its arms: the edges leaving it, and whether they start there.
    let mut arms: Vec<Vec<(usize, bool)>> = vec![Vec::new(); graph.vertices.len()];
    for (e, edge) in graph.edges.iter().enumerate() {
        if edge.from == edge.to {
            continue;
        }
        for (v, at_start) in [(edge.from, true), (edge.to, false)] {
            if let Some(a) = arms.get_mut(v) {
                a.push((e, at_start));
            }
        }
    }
    // Samples every `STEP` px of arc from the vertex along an arm, up to `reach` px: on the
    // ridges, and where.
    let samples = |(e, at_start): (usize, bool), reach: f64| -> Vec<(bool, [f64; 2])> {
        let points = &graph.edges[e].points;
        let s = arc_lengths(points);
        let total = s.last().copied().unwrap_or(0.0);
        (0..)
            .map(|k| f64::from(k) * STEP)
            .take_while(|&t| t <= reach && t < total)
            .map(|t| {
                let (q, _) = point_at(points, &s, if at_start { t } else { total - t });
                (
                    print.ridges.get(q[0].floor() as i64, q[1].floor() as i64),
                    q,
                )
            })
            .collect()
    };
    let run = (1.0 / STEP).ceil() as usize;
    // The far side of the first gap of at least `run` samples, followed by `run` on-ridge
    // samples.
    let gap_end = |s: &[(bool, [f64; 2])]| {
        let mut k = 0;
        while k < s.len() {
            if s[k].0 {
                k += 1;
                continue;
            }
            let start = k;
            while k < s.len() && !s[k].0 {
                k += 1;
            }
            if k - start >= run && k + run <= s.len() && s[k..k + run].iter().all(|x| x.0) {
                return Some(k);
            }
        }
        None
    };
    for m in found.iter_mut() {
        let Some(arm) = arms.get(m.vertex) else {
            continue;
        };
        if m.kind != MinutiaKind::Bifurcation || arm.len() != 3 {
            continue;
        }
        let reach = print.periods.at(m.pos).max(4.0);
        let sampled: Vec<Vec<(bool, [f64; 2])>> = arm.iter().map(|&a| samples(a, reach)).collect();
        let gaps: Vec<(usize, usize)> = (0..3)
            .filter_map(|i| gap_end(&sampled[i]).map(|k| (i, k)))
            .collect();
        let [(i, k)] = gaps[..] else {
            continue;
        };
        let through_on = (0..3)
            .filter(|&j| j != i)
            .all(|j| sampled[j].iter().all(|x| x.0));
        if !through_on || k as f64 * STEP > 0.6 * reach {
            continue;
        }
        let tip = sampled[i][k].1;
        let towards = [m.pos[0] - tip[0], m.pos[1] - tip[1]];
        m.kind = MinutiaKind::Ending;
        m.pos = tip;
        m.direction = towards[1].atan2(towards[0]);
    }
}

/// Whether a ridge of `length` px whose two `ends` come within one `period` of each other runs
/// around a loop of at least three periods: a ring broken in one place (the innermost ridge of a
/// whorl, tighter than the filter resolves), whose two ends are not endings.
fn nearly_closed(ends: [[f64; 2]; 2], length: f64, period: f64) -> bool {
    dist(ends[0], ends[1]) < period && length >= 3.0 * period
}

/// `graph` without the edges of which less than `share` of the length lies on `ridges` (the
/// ridges the gray image confirms, [`PrintAnalysis::ridges`]), the degrees counted again: the
/// Gabor filter rings into a ghost ridge where a valley is wider than the period (inside the
/// innermost recurve of a loop, beyond the print's last ridge), and the ends and forks of a
/// ghost are not the finger's. A ridge broken by a crease, a pore or a dry patch is confirmed
/// over the rest of its length and stays.
fn confirmed_edges(graph: &StrokeGraph, ridges: &Binary, share: f64) -> StrokeGraph {
    let mut out = StrokeGraph {
        width: graph.width,
        height: graph.height,
        vertices: graph.vertices.clone(),
        edges: Vec::with_capacity(graph.edges.len()),
    };
    if share <= 0.0 || ridges.ink.is_empty() {
        out.edges = graph.edges.clone();
        return out;
    }
    for v in &mut out.vertices {
        v.degree = 0;
    }
    for edge in &graph.edges {
        let (mut on, mut total) = (0.0, 0.0);
        for pair in edge.points.windows(2) {
            let length = dist(pair[0], pair[1]);
            let steps = length.ceil().max(1.0) as usize;
            for k in 0..steps {
                let t = (k as f64 + 0.5) / steps as f64;
                let x = pair[0][0] + t * (pair[1][0] - pair[0][0]);
                let y = pair[0][1] + t * (pair[1][1] - pair[0][1]);
                total += length / steps as f64;
                if ridges.get(x.floor() as i64, y.floor() as i64) {
                    on += length / steps as f64;
                }
            }
        }
        if total == 0.0 || on >= share * total {
            for v in [edge.from, edge.to] {
                if let Some(v) = out.vertices.get_mut(v) {
                    v.degree += 1;
                }
            }
            out.edges.push(edge.clone());
        }
    }
    out
}

/// Drops every minutia that has at least two others within `radius`, with those others: a cloud
/// of minutiae is noise, not ridge structure. Sorted by x, so only a window is compared.
fn drop_clouds(found: &mut Vec<Minutia>, radius: f64) {
    let mut by_x: Vec<usize> = (0..found.len()).collect();
    by_x.sort_by(|&a, &b| found[a].pos[0].total_cmp(&found[b].pos[0]).then(a.cmp(&b)));
    let mut near: Vec<Vec<usize>> = vec![Vec::new(); found.len()];
    for (k, &a) in by_x.iter().enumerate() {
        for &b in &by_x[k + 1..] {
            if found[b].pos[0] - found[a].pos[0] > radius {
                break;
            }
            if dist(found[a].pos, found[b].pos) < radius {
                near[a].push(b);
                near[b].push(a);
            }
        }
    }
    let mut dropped = vec![false; found.len()];
    for (a, others) in near.iter().enumerate() {
        if others.len() >= 2 {
            dropped[a] = true;
            for &b in others {
                dropped[b] = true;
            }
        }
    }
    let mut index = 0;
    found.retain(|_| {
        index += 1;
        !dropped[index - 1]
    });
}

/// Every degree-1 and degree-3 vertex with its direction.
fn detect(graph: &StrokeGraph, options: &MinutiaeOptions) -> Vec<Minutia> {
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
fn drop_broken_ridges(found: &mut Vec<Minutia>, options: &MinutiaeOptions) {
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
fn print_region(mask: &Binary, radius: f64) -> Vec<bool> {
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
mod tests {
    use super::*;
    use crate::stroke_graph::graph_from;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn no_filters() -> MinutiaeOptions {
        MinutiaeOptions {
            border_margin: 0.0,
            broken_ridge_gap: 0.0,
            ..Default::default()
        }
    }

    fn angle_close(a: f64, b: f64) -> bool {
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
    fn a_ghost_arm_is_no_ridge_and_its_fork_no_bifurcation() {
        // A Y whose up-right arm lies in a valley (not on the confirmed ridges): without it the
        // fork is a bend (degree 2) and the arm's far end no ending.
        let c = [100.0, 100.0];
        let g = graph_from(
            &[c, [150.0, 70.0], [40.0, 100.0], [150.0, 130.0]],
            &[(0, 1, vec![]), (2, 0, vec![]), (0, 3, vec![])],
            4.0,
        );
        let mut ridges = Binary::new(200, 200);
        for (k, edge) in g.edges.iter().enumerate() {
            if k == 0 {
                continue;
            }
            for pair in edge.points.windows(2) {
                for t in 0..=200 {
                    let t = f64::from(t) / 200.0;
                    let x = pair[0][0] + t * (pair[1][0] - pair[0][0]);
                    let y = pair[0][1] + t * (pair[1][1] - pair[0][1]);
                    ridges.set(x as i64, y as i64, true);
                }
            }
        }
        let confirmed = confirmed_edges(&g, &ridges, 0.5);
        assert_eq!(confirmed.edges.len(), 2);
        confirmed.validate().expect("degrees match the edges");
        let degrees: Vec<usize> = confirmed.vertices.iter().map(|v| v.degree).collect();
        assert_eq!(degrees, vec![2, 0, 1, 1]);
        let found = detect(&confirmed, &no_filters());
        assert!(found.iter().all(|m| m.kind == MinutiaKind::Ending));
        assert_eq!(found.len(), 2);
        // A share of 0 keeps every edge; a ridge confirmed over 60 % of its length stays.
        assert_eq!(confirmed_edges(&g, &ridges, 0.0).edges.len(), 3);
        for x in 120..150 {
            for y in 60..90 {
                ridges.set(x, y, true);
            }
        }
        assert_eq!(confirmed_edges(&g, &ridges, 0.5).edges.len(), 3);
    }

    #[test]
    fn a_branch_across_a_valley_is_an_ending_and_a_break_further_out_is_not() {
        use crate::fingerprint::fields::BlockGrid;
        use crate::fingerprint::tests::uniform_print;
        // A ridge along y = 20 (ink rows 19-21) and a branch leaving it at (50, 20) up to the
        // right; period 9. The branch's ink is drawn where its arc from the junction is in
        // `inked` only.
        let (c, d) = ([50.0, 20.0], [30.0f64 / 36.06, -20.0 / 36.06]);
        let g = graph_from(
            &[c, [10.0, 20.0], [90.0, 20.0], [80.0, 0.0]],
            &[(1, 0, vec![]), (0, 2, vec![]), (0, 3, vec![])],
            3.0,
        );
        let (segmentation, orientation, periods) =
            uniform_print(BlockGrid::new(100, 60, 8), 0.0, 9.0);
        let print_with = |inked: &dyn Fn(f64) -> bool| {
            let mut ridges = Binary::new(100, 60);
            for y in 0..60i64 {
                for x in 0..100i64 {
                    let (u, v) = (x as f64 + 0.5 - c[0], y as f64 + 0.5 - c[1]);
                    let along = u * d[0] + v * d[1];
                    let across = (u * d[1] - v * d[0]).abs();
                    let branch = along >= 0.0 && across <= 1.5 && inked(along);
                    ridges.set(x, y, (19..=21).contains(&y) || branch);
                }
            }
            PrintAnalysis {
                segmentation: segmentation.clone(),
                orientation: orientation.clone(),
                periods: periods.clone(),
                ridges,
                ..PrintAnalysis::default()
            }
        };
        let fork_of = |print: &PrintAnalysis| {
            let mut found: Vec<Minutia> = detect(&g, &no_filters())
                .into_iter()
                .filter(|m| m.vertex == 0)
                .collect();
            detached_branches(&mut found, &g, print);
            found[0]
        };
        // The branch's ink starts 4 px out, past a valley from the ridge's edge: an ending at
        // the branch's tip, pointing back to the junction.
        let m = fork_of(&print_with(&|s| s >= 4.0));
        assert_eq!(m.kind, MinutiaKind::Ending);
        let tip = [c[0] + 4.0 * d[0], c[1] + 4.0 * d[1]];
        assert!(dist(m.pos, tip) < 1.0, "{:?}", m.pos);
        assert!(
            angle_close(m.direction, (-d[1]).atan2(-d[0])),
            "{}",
            m.direction
        );
        // Ink all the way, or a break beyond 0.6 period of the junction: a bifurcation.
        for inked in [&(|_: f64| true) as &dyn Fn(f64) -> bool, &|s| {
            !(6.0..8.0).contains(&s)
        }] {
            assert_eq!(fork_of(&print_with(inked)).kind, MinutiaKind::Bifurcation);
        }
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

    #[test]
    fn a_ring_broken_once_is_nearly_closed_but_not_a_hook_or_a_dash() {
        // Whether the polyline `points` is a broken ring, as the filter asks of an edge.
        let nearly_closed = |points: &[[f64; 2]], period: f64| {
            let length: f64 = points.windows(2).map(|p| dist(p[0], p[1])).sum();
            nearly_closed([points[0], points[points.len() - 1]], length, period)
        };
        // Arcs of radius 8 around (50, 50) from angle `gap` to 2π: a ring of period 9 broken by
        // a gap of `gap` radians.
        let arc = |gap: f64| -> Vec<[f64; 2]> {
            (0..=64)
                .map(|k| {
                    let a = gap + (std::f64::consts::TAU - gap) * f64::from(k) / 64.0;
                    [50.0 + 8.0 * a.cos(), 50.0 + 8.0 * a.sin()]
                })
                .collect()
        };
        assert!(
            nearly_closed(&arc(0.8), 9.0),
            "ends 6 px apart around 44 px"
        );
        assert!(
            !nearly_closed(&arc(std::f64::consts::PI), 9.0),
            "a half ring"
        );
        // Ends within a period of each other but only 2 periods of ridge: a short hook.
        let hook = [[0.0, 0.0], [9.0, 0.0], [9.0, 5.0], [0.0, 5.0]];
        assert!(!nearly_closed(&hook, 9.0));
        assert!(!nearly_closed(&[[0.0, 0.0]], 9.0));
    }

    #[test]
    fn a_cloud_goes_whole_and_a_pair_stays() {
        let at = |x: f64, y: f64, vertex: usize| Minutia {
            kind: MinutiaKind::Ending,
            vertex,
            pos: [x, y],
            direction: 0.0,
            width: 3.0,
            quality: None,
        };
        // Three within 9 px of the first (a cloud), a pair 6 px apart far away, one alone.
        let mut found = vec![
            at(50.0, 50.0, 0),
            at(55.0, 50.0, 1),
            at(50.0, 56.0, 2),
            at(58.0, 58.0, 3),
            at(150.0, 150.0, 4),
            at(156.0, 150.0, 5),
            at(100.0, 20.0, 6),
        ];
        drop_clouds(&mut found, 9.0);
        let kept: Vec<usize> = found.iter().map(|m| m.vertex).collect();
        assert_eq!(kept, vec![4, 5, 6]);
    }
}
