//! Warnings that tell the truth: signs in a traced graph (and in the front end's decisions) that
//! the result is probably wrong, each with what to try (docs/design.md, "The front end").
//!
//! Each sign is one a clean input of strokes does not show: a polarity decided on weak evidence;
//! most of the centerline in one component full of cycles (the paper's web between strokes
//! traced as ink); a dense mesh of junctions joined by edges shorter than the strokes are wide
//! (halftone or a photo region); many components no longer than a stroke is wide (speckle); a
//! vertex where more arms meet than strokes ever cross; ridge texture (parallel centerlines about
//! two stroke widths apart) over most of the image, a fingerprint traced as a page.
//!
//! Advice is given only where following it changes the result as the message says (tests in
//! this module follow each one): a flag the front end already used, or one that does nothing to
//! the input (a point list has no threshold, polarity or ink components), is not suggested.

use std::collections::BTreeSet;

use crate::binary::MaskView;
use crate::decisions::{Decisions, InkSide, ThresholdUsed, Warning};
use crate::geometry::{floor_f64, floor_i64, hypot};
use crate::median::upper_median;
use crate::stroke_graph::StrokeGraph;

/// A polarity confidence below this is reported.
pub const LOW_POLARITY_CONFIDENCE: f64 = 0.2;
/// From this polarity confidence on (half the scale: the evidence for the decided side clearly
/// outweighs the other), a sign of a background traced as ink is not answered with advice to
/// trace the other side: on such images the cause is a grid, a texture or strokes merged by
/// the threshold, and `--polarity` would trace the paper.
const SURE_POLARITY_CONFIDENCE: f64 = 0.5;
/// The largest component holding more than this share of the centerline ...
const HUGE_SHARE: f64 = 0.5;
/// ... with at least this many independent cycles is reported.
const HUGE_CYCLES: usize = 20;
/// Edges between two junctions shorter than this many stroke widths are mesh edges ...
const MESH_EDGE_WIDTHS: f64 = 2.0;
/// ... reported when they are more than this share of the edges ...
const MESH_SHARE: f64 = 0.3;
/// ... and the graph has at least this many edges.
const MESH_MIN_EDGES: usize = 100;
/// Components whose centerline is shorter than this many stroke widths are specks ...
const SPECK_WIDTHS: f64 = 1.5;
/// ... reported when there are at least this many ...
const SPECK_MIN_COUNT: usize = 50;
/// ... and they are more than this share of the components.
const SPECK_SHARE: f64 = 0.4;
/// A vertex of this degree or more is reported (three strokes crossing at one point make 6).
pub const HIGH_DEGREE: usize = 8;
/// Ridge texture is looked for in square blocks this many stroke widths across ...
const TEXTURE_BLOCK_WIDTHS: f64 = 6.0;
/// ... holding at least this much centerline, in block sides (parallel lines at most three
/// widths apart, as ridges are: ridge and valley about one width each) ...
const TEXTURE_LINES: f64 = 1.5;
/// ... running one way: the coherence of their directions (the length of the mean of the
/// doubled direction angles, 1 for parallel lines, near 0 for every direction) at least this.
const TEXTURE_COHERENCE: f64 = 0.5;
/// An image whose ridge-texture blocks are more than this share of its blocks is reported ...
const TEXTURE_SHARE: f64 = 0.4;
/// ... when it has at least this many of them (a few blocks of hatching are no print).
const TEXTURE_MIN_BLOCKS: usize = 16;

/// The warning for a point list that is not strip-shaped: only `share` of its points lie in a
/// linear neighbourhood at any scale (§3.1), so nothing was traced.
pub(crate) fn not_strip_shaped(share: f64) -> Warning {
    Warning {
        code: "not_strip_shaped",
        message: format!(
            "the points are not strip-shaped: only {:.0}% of them lie along a strip at any scale \
             (a cloud or a blob, not points around curves), so no curve was traced",
            100.0 * share
        ),
    }
}

/// The warning for a point list some of whose points were left out: `count` of its `total`
/// distinct points lay far sparser than the rest and formed no strip at their own scale (a
/// sparse cloud of outliers around the strips), so only the others were traced.
pub(crate) fn sparse_points_left_out(count: usize, total: usize) -> Warning {
    Warning {
        code: "sparse_points_left_out",
        message: format!(
            "{count} of {total} points were left out: their neighbours lie more than ten times \
             farther than the rest's (a hundredfold sparser in the plane, a thousandfold in \
             space) and they form no strip at their own scale (outliers around the strips)"
        ),
    }
}

/// The warnings for `graph`, with the front end's `decisions` when the input was an image and the
/// `ink` it was traced from (before any component was dropped) when it was an image or a mask.
pub fn of(
    graph: &StrokeGraph,
    decisions: Option<&Decisions>,
    ink: Option<MaskView<'_>>,
) -> Vec<Warning> {
    let mut out = Vec::new();
    if let Some(confidence) = decisions.and_then(|d| d.polarity_confidence) {
        if confidence < LOW_POLARITY_CONFIDENCE {
            let (side, other) = match decisions.map(|d| d.polarity) {
                Some(crate::decisions::InkSide::Light) => ("light", "dark"),
                _ => ("dark", "light"),
            };
            out.push(Warning {
                code: "polarity_uncertain",
                message: format!(
                    "which side is ink is uncertain (confidence {confidence:.2}): the {side} side \
                     was traced; pass --polarity {other} if the strokes are {other}"
                ),
            });
        }
    }
    let n = graph.vertices.len();
    if graph.edges.iter().any(|e| e.from >= n || e.to >= n) {
        return out;
    }
    let mut widths: Vec<f64> = graph.edges.iter().map(median_width).collect();
    let width = upper_median(&mut widths).unwrap_or(0.0).max(1.0);
    // Length, edges and vertices of each component, at its root.
    let root = graph.component_roots();
    let mut length = vec![0.0; n];
    let mut edges = vec![0usize; n];
    let mut vertices = vec![0usize; n];
    for &r in &root {
        vertices[r] += 1;
    }
    for e in &graph.edges {
        length[root[e.from]] += e.length();
        edges[root[e.from]] += 1;
    }
    let total: f64 = length.iter().sum();
    let roots: Vec<usize> = (0..n).filter(|&v| root[v] == v).collect();
    if let Some(&big) = roots
        .iter()
        .max_by(|&&a, &&b| length[a].total_cmp(&length[b]))
    {
        let cycles = (edges[big] + 1).saturating_sub(vertices[big]);
        let share = length[big] / total.max(f64::MIN_POSITIVE);
        if total > 0.0 && share > HUGE_SHARE && cycles >= HUGE_CYCLES {
            let cause = match (decisions, image_advice(decisions)) {
                (Some(d), None) => format!(
                    "a grid, a texture or strokes merged by the threshold (the polarity, {} ink, \
                     was decided with confidence {:.2})",
                    side_name(d.polarity),
                    d.polarity_confidence.unwrap_or(1.0)
                ),
                (_, advice) => format!(
                    "the paper or a background may have been traced as ink{}",
                    advice.unwrap_or_default()
                ),
            };
            out.push(Warning {
                code: "one_huge_component",
                message: format!(
                    "{:.0}% of the centerline is one component with {cycles} cycles: {cause}",
                    100.0 * share,
                ),
            });
        }
    }
    let junction = |v: usize| graph.vertices[v].degree >= 3;
    let mesh_edges = graph
        .edges
        .iter()
        .filter(|e| junction(e.from) && junction(e.to) && e.length() < MESH_EDGE_WIDTHS * width)
        .count();
    if graph.edges.len() >= MESH_MIN_EDGES
        && mesh_edges as f64 > MESH_SHARE * graph.edges.len() as f64
    {
        out.push(Warning {
            code: "mesh",
            message: format!(
                "{mesh_edges} of {} edges join two junctions within two stroke widths: a halftone \
                 or photo region, or strokes merged by the threshold; crop to the strokes{}",
                graph.edges.len(),
                image_advice(decisions).unwrap_or_default()
            ),
        });
    }
    let texture = decisions
        .filter(|d| d.print.is_none())
        .and_then(|_| ridge_texture(graph, width));
    if let Some(share) = texture {
        out.push(Warning {
            code: "fingerprint_like",
            message: format!(
                "parallel ridges about two stroke widths apart cover {:.0}% of the image, like a \
                 fingerprint: pass --fingerprint to enhance the print before tracing and keep \
                 its minutiae",
                100.0 * share
            ),
        });
    }
    let speck_roots: Vec<usize> = roots
        .iter()
        .copied()
        .filter(|&r| length[r] < SPECK_WIDTHS * width)
        .collect();
    let specks = speck_roots.len();
    if texture.is_none()
        && specks >= SPECK_MIN_COUNT
        && specks as f64 > SPECK_SHARE * roots.len() as f64
    {
        // --min-area drops ink components, so it is suggested from the specks' own areas, and
        // only where it drops most of them and no component holding more than a speck.
        let advice = ink
            .and_then(|ink| min_area_for(graph, &root, &speck_roots, ink))
            .map(|(area, dropped)| {
                format!(
                    ": pass --min-area {area} to drop the {dropped} ink components under {area} \
                     pixels"
                )
            })
            .unwrap_or_default();
        out.push(Warning {
            code: "speckle",
            message: format!(
                "{specks} of {} components are specks no longer than a stroke is wide{advice}",
                roots.len()
            ),
        });
    }
    let high = graph
        .vertices
        .iter()
        .filter(|v| v.degree >= HIGH_DEGREE)
        .count();
    if high > 0 {
        let max = graph.vertices.iter().map(|v| v.degree).max().unwrap_or(0);
        out.push(Warning {
            code: "high_degree",
            message: format!(
                "{high} vertices where {HIGH_DEGREE} or more edges meet (up to {max}): strokes \
                 merged into a blob, or a background traced as ink"
            ),
        });
    }
    out
}

fn median_width(edge: &crate::stroke_graph::Edge) -> f64 {
    upper_median(&mut edge.widths.clone()).unwrap_or(0.0)
}

/// What to try when the paper or a background may have been traced as ink: the other side
/// (`--polarity`), and Otsu's global level where another threshold was used. None for a point
/// list or a mask, which have neither, and where the polarity was decided with confidence
/// [`SURE_POLARITY_CONFIDENCE`] or more (when `--polarity` forced it, the other side is advised).
fn image_advice(decisions: Option<&Decisions>) -> Option<String> {
    let decisions = decisions?;
    if decisions
        .polarity_confidence
        .is_some_and(|c| c >= SURE_POLARITY_CONFIDENCE)
    {
        return None;
    }
    let other = match decisions.polarity {
        InkSide::Light => "dark",
        InkSide::Dark => "light",
    };
    let otsu = match decisions.threshold {
        ThresholdUsed::Otsu { .. } | ThresholdUsed::Uniform => String::new(),
        _ => " or --binarize otsu".to_string(),
    };
    Some(format!(
        "; if the strokes are {other}, pass --polarity {other}{otsu}"
    ))
}

fn side_name(side: InkSide) -> &'static str {
    match side {
        InkSide::Light => "light",
        InkSide::Dark => "dark",
    }
}

/// The share of the image covered by ridge texture (see [`TEXTURE_COHERENCE`]), when it is more
/// than [`TEXTURE_SHARE`]; `width` is the median stroke width.
fn ridge_texture(graph: &StrokeGraph, width: f64) -> Option<f64> {
    let side = TEXTURE_BLOCK_WIDTHS * width;
    let columns = (graph.width as f64 / side).floor() as usize;
    let rows = (graph.height as f64 / side).floor() as usize;
    if columns * rows < TEXTURE_MIN_BLOCKS {
        return None;
    }
    // Per block: centerline length and the sum of its doubled direction angles, length-weighted.
    let mut blocks = vec![(0.0, 0.0, 0.0); columns * rows];
    for edge in &graph.edges {
        for pair in edge.points.windows(2) {
            let (dx, dy) = (pair[1][0] - pair[0][0], pair[1][1] - pair[0][1]);
            let length = hypot(dx, dy);
            let (x, y) = (
                (pair[0][0] + pair[1][0]) / 2.0,
                (pair[0][1] + pair[1][1]) / 2.0,
            );
            let (column, row) = (floor_f64(x / side), floor_f64(y / side));
            if length == 0.0 || column < 0.0 || row < 0.0 {
                continue;
            }
            let (column, row) = (column as usize, row as usize);
            if column >= columns || row >= rows {
                continue;
            }
            let angle = 2.0 * dy.atan2(dx);
            let block = &mut blocks[row * columns + column];
            block.0 += length;
            block.1 += length * angle.cos();
            block.2 += length * angle.sin();
        }
    }
    let textured = blocks
        .iter()
        .filter(|(length, c, s)| {
            *length >= TEXTURE_LINES * side && hypot(*c, *s) >= TEXTURE_COHERENCE * length
        })
        .count();
    let share = textured as f64 / blocks.len() as f64;
    (textured >= TEXTURE_MIN_BLOCKS && share > TEXTURE_SHARE).then_some(share)
}

/// The `--min-area` that drops the specks (graph components rooted at `speck_roots`): one more
/// than the largest speck's ink component (8-connected, as `--min-area` counts them), and how
/// many ink components it drops; below the smallest component that is no speck when that is
/// smaller. None when that drops no more than half of the specks.
fn min_area_for(
    graph: &StrokeGraph,
    root: &[usize],
    speck_roots: &[usize],
    ink: MaskView<'_>,
) -> Option<(usize, usize)> {
    let (labels, area) = crate::mask::label_components(
        ink.ink,
        ink.width as usize,
        ink.height as usize,
        true,
        crate::mask::Connectivity::Eight,
    );
    // The ink component under a vertex: the label of an ink pixel at or next to it (a centerline
    // placed below the pixel may sit on the pixel beside the ink).
    let label_at = |pos: [f64; 2]| -> Option<usize> {
        let (x, y) = (floor_i64(pos[0]), floor_i64(pos[1]));
        [
            (0, 0),
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, -1),
            (-1, 1),
            (1, 1),
        ]
        .iter()
        .map(|(dx, dy)| (x + dx, y + dy))
        .filter(|&(x, y)| ink.get(x, y))
        .map(|(x, y)| labels[y as usize * ink.width as usize + x as usize] as usize)
        .find(|&l| l > 0)
    };
    let is_speck: Vec<bool> = {
        let mut marks = vec![false; root.len()];
        for &r in speck_roots {
            marks[r] = true;
        }
        marks
    };
    let mut largest_speck = 0;
    let mut smallest_other = usize::MAX;
    for (v, vertex) in graph.vertices.iter().enumerate() {
        let Some(l) = label_at(vertex.pos) else {
            continue;
        };
        if is_speck[root[v]] {
            largest_speck = largest_speck.max(area[l]);
        } else {
            smallest_other = smallest_other.min(area[l]);
        }
    }
    // Where a component that is no speck is smaller than a speck, the threshold stops below it
    // and is suggested only if it still drops most of the specks.
    let min_area = (largest_speck + 1).min(smallest_other);
    let speck_labels: BTreeSet<usize> = graph
        .vertices
        .iter()
        .enumerate()
        .filter(|&(v, _)| is_speck[root[v]])
        .filter_map(|(_, vertex)| label_at(vertex.pos))
        .collect();
    let dropped_specks = speck_labels.iter().filter(|&&l| area[l] < min_area).count();
    let dropped = area
        .iter()
        .skip(1)
        .filter(|&&a| a > 0 && a < min_area)
        .count();
    (min_area > 1 && 2 * dropped_specks > speck_labels.len()).then_some((min_area, dropped))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decisions::ThresholdUsed;
    use crate::draw::{render, Stroke};
    use crate::params::Params;
    use crate::stroke_graph::{Edge, Vertex};

    /// A graph of straight edges `(from, to)` between `positions`, 3 px wide, degrees counted.
    fn graph(positions: &[[f64; 2]], edges: &[(usize, usize)]) -> StrokeGraph {
        let mut degree = vec![0; positions.len()];
        for &(a, b) in edges {
            degree[a] += 1;
            degree[b] += 1;
        }
        StrokeGraph {
            width: 500,
            height: 500,
            vertices: positions
                .iter()
                .zip(degree)
                .map(|(&pos, degree)| Vertex {
                    pos,
                    degree,
                    width: 3.0,
                })
                .collect(),
            edges: edges
                .iter()
                .map(|&(from, to)| Edge {
                    from,
                    to,
                    points: vec![positions[from], positions[to]],
                    widths: vec![3.0; 2],
                    directions: vec![[1.0, 0.0]; 2],
                })
                .collect(),
        }
    }

    /// An `n` x `n` lattice of vertices `spacing` apart, each joined to its right and lower
    /// neighbours.
    fn lattice(n: usize, spacing: f64) -> StrokeGraph {
        let positions: Vec<[f64; 2]> = (0..n * n)
            .map(|i| [(i % n) as f64 * spacing, (i / n) as f64 * spacing])
            .collect();
        let mut edges = Vec::new();
        for i in 0..n * n {
            if i % n + 1 < n {
                edges.push((i, i + 1));
            }
            if i / n + 1 < n {
                edges.push((i, i + n));
            }
        }
        graph(&positions, &edges)
    }

    fn codes(graph: &StrokeGraph, decisions: Option<&Decisions>) -> Vec<&'static str> {
        of(graph, decisions, None).iter().map(|w| w.code).collect()
    }

    fn decided(confidence: f64) -> Decisions {
        Decisions {
            polarity: crate::decisions::InkSide::Dark,
            polarity_confidence: Some(confidence),
            threshold: ThresholdUsed::Otsu { level: 128 },
            stroke_width: 3.0,
            uneven_light: 0.0,
            dropout: Some(false),
            dropout_share: Some(0.0),
            reversed_grounds: Vec::new(),
            regions: Vec::new(),
            print: None,
        }
    }

    #[test]
    fn clean_strokes_raise_no_warning() {
        let plus = render(
            &[
                Stroke::new(vec![[10.0, 40.0], [70.0, 40.0]], 6.0),
                Stroke::new(vec![[40.0, 10.0], [40.0, 70.0]], 6.0),
            ],
            80,
            80,
        );
        let gray = image::GrayImage::from_fn(80, 80, |x, y| {
            image::Luma([if plus.get(x as i64, y as i64) {
                30
            } else {
                220
            }])
        });
        let trace = crate::trace_image(&gray, &Params::default()).unwrap();
        assert!(trace.warnings.is_empty(), "{:?}", trace.warnings);
    }

    #[test]
    fn weak_polarity_evidence_is_reported() {
        let one = graph(&[[0.0, 0.0], [50.0, 0.0]], &[(0, 1)]);
        assert_eq!(codes(&one, Some(&decided(0.1))), ["polarity_uncertain"]);
        assert!(codes(&one, Some(&decided(0.9))).is_empty());
        let forced = Decisions {
            polarity_confidence: None,
            ..decided(0.0)
        };
        assert!(codes(&one, Some(&forced)).is_empty());
    }

    #[test]
    fn one_component_full_of_cycles_is_reported() {
        // A 7 x 7 lattice of 30 px cells: 36 cycles, every edge ten widths long.
        assert_eq!(codes(&lattice(7, 30.0), None), ["one_huge_component"]);
        // A 4 x 4 one has 9 cycles only.
        assert!(codes(&lattice(4, 30.0), None).is_empty());
    }

    #[test]
    fn a_dense_mesh_is_reported() {
        // 4 px cells of 3 px strokes: a halftone screen.
        let found = codes(&lattice(12, 4.0), None);
        assert!(found.contains(&"mesh"), "{found:?}");
    }

    #[test]
    fn many_specks_are_reported() {
        // Three real strokes and sixty one-pixel specks.
        let mut positions = Vec::new();
        let mut edges = Vec::new();
        for i in 0..3 {
            positions.push([0.0, 20.0 * i as f64]);
            positions.push([100.0, 20.0 * i as f64]);
            edges.push((2 * i, 2 * i + 1));
        }
        for i in 0..60 {
            let n = positions.len();
            positions.push([200.0 + 10.0 * (i % 10) as f64, 10.0 * (i / 10) as f64]);
            positions.push([201.0 + 10.0 * (i % 10) as f64, 10.0 * (i / 10) as f64]);
            edges.push((n, n + 1));
        }
        let warnings = of(&graph(&positions, &edges), None, None);
        assert_eq!(warnings.len(), 1);
        assert_eq!(warnings[0].code, "speckle");
        // Without the ink (a point list) there are no ink components for --min-area to drop.
        assert!(
            !warnings[0].message.contains("--min-area"),
            "{}",
            warnings[0].message
        );
    }

    #[test]
    fn a_star_of_many_arms_is_reported() {
        let mut positions = vec![[100.0, 100.0]];
        let mut edges = Vec::new();
        for k in 0..9 {
            let a = k as f64 * std::f64::consts::TAU / 9.0;
            positions.push([100.0 + 50.0 * a.cos(), 100.0 + 50.0 * a.sin()]);
            edges.push((0, k + 1));
        }
        assert_eq!(codes(&graph(&positions, &edges), None), ["high_degree"]);
        // Three strokes crossing at one point (degree 6) are no warning.
        edges.truncate(6);
        positions.truncate(7);
        assert!(codes(&graph(&positions, &edges), None).is_empty());
    }

    #[test]
    fn min_area_drops_specks_before_tracing() {
        let mut binary = render(
            &[Stroke::new(vec![[10.0, 20.0], [70.0, 20.0]], 5.0)],
            80,
            40,
        );
        for k in 0..10 {
            binary.set(5 + 7 * k, 35, true);
        }
        let all = crate::trace_binary(&binary, &Params::default()).unwrap();
        let mut params = Params::default();
        params.front_end.min_area = 4;
        let cleaned = crate::trace_binary(&binary, &params).unwrap();
        assert!(all.graph.components() > 1);
        assert_eq!(cleaned.graph.components(), 1);
    }

    // Each warning's advice, followed, moves the result the way the message says.

    /// A gray image: `ink` dark (30) on light paper (220).
    fn gray_of(ink: &crate::binary::Binary) -> image::GrayImage {
        image::GrayImage::from_fn(ink.width, ink.height, |x, y| {
            image::Luma([if ink.get(x as i64, y as i64) { 30 } else { 220 }])
        })
    }

    fn with_code<'a>(trace: &'a crate::pipeline::Trace, code: &str) -> Option<&'a Warning> {
        trace.warnings.iter().find(|w| w.code == code)
    }

    #[test]
    fn the_speckle_advice_drops_the_specks_and_keeps_the_strokes() {
        let mut ink = render(
            &[
                Stroke::new(vec![[10.0, 20.0], [190.0, 20.0]], 5.0),
                Stroke::new(vec![[10.0, 60.0], [190.0, 90.0]], 5.0),
                Stroke::new(vec![[100.0, 40.0], [100.0, 190.0]], 5.0),
            ],
            200,
            200,
        );
        // 80 specks of 2 x 2 and 3 x 2 pixels on the paper.
        for k in 0..80i64 {
            let (x, y) = (8 + 12 * (k % 8), 110 + 10 * (k / 8));
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                ink.set(x + dx, y + dy, true);
            }
            if k % 2 == 0 {
                ink.set(x + 2, y, true);
                ink.set(x + 2, y + 1, true);
            }
        }
        let gray = gray_of(&ink);
        let trace = crate::trace_image(&gray, &Params::default()).unwrap();
        let warning = with_code(&trace, "speckle").expect("a speckle warning");
        let area: usize = warning
            .message
            .split("--min-area ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no --min-area N in {:?}", warning.message));
        // Every speck has 4 or 6 pixels: the advice drops them all, and nothing else.
        assert_eq!(area, 7, "{}", warning.message);
        let cleaned = crate::trace_image(&gray, &{
            let mut params = Params::default();
            params.front_end.min_area = area;
            params
        })
        .unwrap();
        assert!(
            with_code(&cleaned, "speckle").is_none(),
            "{:?}",
            cleaned.warnings
        );
        assert_eq!(cleaned.graph.components(), 2);
        let length =
            |t: &crate::pipeline::Trace| t.graph.edges.iter().map(|e| e.length()).sum::<f64>();
        assert!((length(&cleaned) - length(&trace)).abs() < 5.0);
    }

    #[test]
    fn ridge_texture_points_to_fingerprint_and_fingerprint_traces_the_print() {
        // Ridges 4 px wide, 8 px apart, gently curved, over the whole image.
        let gray = image::GrayImage::from_fn(240, 240, |x, y| {
            let phase = (x as f64 + 6.0 * (y as f64 / 40.0).sin()) * std::f64::consts::TAU / 8.0;
            image::Luma([(128.0 + 100.0 * phase.sin()) as u8])
        });
        let page = crate::trace_image(&gray, &Params::default()).unwrap();
        let warning = with_code(&page, "fingerprint_like").expect("a fingerprint warning");
        assert!(warning.message.contains("--fingerprint"));
        let print = crate::trace_image(
            &gray,
            &Params {
                fingerprint: Params::fingerprint().fingerprint,
                ..Params::default()
            },
        )
        .unwrap();
        assert!(print.fingerprint.is_some(), "the print front end ran");
        assert!(with_code(&print, "fingerprint_like").is_none());
        // A page of strokes is no print.
        let strokes = render(
            &[
                Stroke::new(vec![[10.0, 40.0], [230.0, 40.0]], 6.0),
                Stroke::new(vec![[40.0, 10.0], [40.0, 230.0]], 6.0),
            ],
            240,
            240,
        );
        let plain = crate::trace_image(&gray_of(&strokes), &Params::default()).unwrap();
        assert!(with_code(&plain, "fingerprint_like").is_none());
    }

    #[test]
    fn the_huge_component_advice_traces_the_strokes_instead_of_the_paper() {
        // 25 dark rings on white paper, traced with the wrong side forced as ink.
        let rings: Vec<Stroke> = (0..25)
            .map(|k| {
                let (cx, cy) = (20.0 + 40.0 * (k % 5) as f64, 20.0 + 40.0 * (k / 5) as f64);
                let points = (0..=24)
                    .map(|i| {
                        let a = i as f64 * std::f64::consts::TAU / 24.0;
                        [cx + 10.0 * a.cos(), cy + 10.0 * a.sin()]
                    })
                    .collect();
                Stroke::new(points, 3.0)
            })
            .collect();
        let gray = gray_of(&render(&rings, 200, 200));
        let wrong = crate::trace_image(&gray, &{
            let mut params = Params::default();
            params.front_end.polarity = crate::params::Polarity::LightInk;
            params
        })
        .unwrap();
        let warning = with_code(&wrong, "one_huge_component").expect("a huge component");
        // Otsu's level was used: --binarize otsu would change nothing, so it is not suggested.
        assert!(
            warning.message.ends_with("pass --polarity dark"),
            "{}",
            warning.message
        );
        let right = crate::trace_image(&gray, &{
            let mut params = Params::default();
            params.front_end.polarity = crate::params::Polarity::DarkInk;
            params
        })
        .unwrap();
        assert!(with_code(&right, "one_huge_component").is_none());
        assert_eq!(right.graph.components(), 25);
        assert_eq!(right.graph.cycles(), 25);
    }

    #[test]
    fn a_grid_decided_with_confidence_gets_no_polarity_advice() {
        // A grid of dark bars on white paper, 11 x 11 bars 3 px wide and 30 px apart: one
        // component of 100 cycles, with the polarity read from the image (dark ink, clearly).
        let bars: Vec<Stroke> = (0..11)
            .flat_map(|k| {
                let t = 10.0 + 30.0 * k as f64;
                [
                    Stroke::new(vec![[10.0, t], [310.0, t]], 3.0),
                    Stroke::new(vec![[t, 10.0], [t, 310.0]], 3.0),
                ]
            })
            .collect();
        let gray = gray_of(&render(&bars, 320, 320));
        let auto = crate::trace_image(&gray, &Params::default()).unwrap();
        let decisions = auto.decisions.as_ref().expect("an image's decisions");
        assert_eq!(decisions.polarity, InkSide::Dark);
        assert!(
            decisions.polarity_confidence.unwrap() >= SURE_POLARITY_CONFIDENCE,
            "{decisions:?}"
        );
        let warning = with_code(&auto, "one_huge_component").expect("a huge component");
        assert!(
            !warning.message.contains("--polarity"),
            "{}",
            warning.message
        );
        assert!(warning.message.contains("a grid"), "{}", warning.message);
        // The advice it no longer gives would trace the paper: the cells' fields, not the bars.
        let flipped = crate::trace_image(&gray, &{
            let mut params = Params::default();
            params.front_end.polarity = crate::params::Polarity::LightInk;
            params
        })
        .unwrap();
        assert!(flipped.graph.components() > auto.graph.components());
    }

    #[test]
    fn the_uncertain_polarity_advice_traces_the_drawn_strokes() {
        // Dark bars 4 px wide drawn 4 px apart from the top edge down (rows 8k to 8k + 3): the
        // gaps between them are as wide as the bars, so either side could be the ink.
        let gray = image::GrayImage::from_fn(200, 100, |_, y| {
            image::Luma([if (y / 4) % 2 == 0 { 40 } else { 200 }])
        });
        let auto = crate::trace_image(&gray, &Params::default()).unwrap();
        let warning = with_code(&auto, "polarity_uncertain").expect("an uncertain polarity");
        // The side suggested, as the message writes it: "pass --polarity SIDE if ...".
        let side = warning
            .message
            .split("--polarity ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .unwrap_or_else(|| panic!("no --polarity in {:?}", warning.message));
        let polarity = match side {
            "dark" => crate::params::Polarity::DarkInk,
            "light" => crate::params::Polarity::LightInk,
            other => panic!("unknown side {other:?} in {:?}", warning.message),
        };
        // Whichever side was decided, following the advice when the drawn strokes are on the
        // side it names traces them: every centerline point on a bar's middle row (8k + 2) for
        // dark, between the bars (8k + 6) for light.
        let middle = if side == "dark" { 2.0 } else { 6.0 };
        let followed = crate::trace_image(&gray, &{
            let mut params = Params::default();
            params.front_end.polarity = polarity;
            params
        })
        .unwrap();
        assert!(with_code(&followed, "polarity_uncertain").is_none());
        assert!(
            followed.graph.edges.len() >= 10,
            "{}",
            followed.graph.edges.len()
        );
        for edge in &followed.graph.edges {
            for p in &edge.points {
                let off = (p[1] - middle).rem_euclid(8.0);
                assert!(
                    off.min(8.0 - off) < 0.75,
                    "{p:?} is off the {side} bars' middles"
                );
            }
        }
        // Here the light side was read as ink, so the advice names the dark bars, as drawn.
        assert_eq!(side, "dark", "{}", warning.message);
    }

    #[test]
    fn a_point_list_or_a_mask_gets_no_image_advice() {
        let lattice = lattice(7, 30.0);
        let warnings = of(&lattice, None, None);
        assert_eq!(warnings[0].code, "one_huge_component");
        assert!(
            !warnings[0].message.contains("--"),
            "{}",
            warnings[0].message
        );
    }
}
