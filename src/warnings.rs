//! Warnings that tell the truth: signs in a traced graph (and in the front end's decisions) that
//! the result is probably wrong, each with what to try (docs/design.md, "The front end").
//!
//! Each sign is one a clean input of strokes does not show: a polarity decided on weak evidence;
//! most of the centerline in one component full of cycles (the paper's web between strokes
//! traced as ink); a dense mesh of junctions joined by edges shorter than the strokes are wide
//! (halftone or a photo region); many components no longer than a stroke is wide (speckle); a
//! vertex where more arms meet than strokes ever cross.

use crate::decisions::{Decisions, Warning};
use crate::median::upper_median;
use crate::stroke_graph::StrokeGraph;

/// A polarity confidence below this is reported.
pub const LOW_POLARITY_CONFIDENCE: f64 = 0.2;
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

/// The warnings for `graph`, with the front end's `decisions` when the input was an image.
pub fn of(graph: &StrokeGraph, decisions: Option<&Decisions>) -> Vec<Warning> {
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
            out.push(Warning {
                code: "one_huge_component",
                message: format!(
                    "{:.0}% of the centerline is one component with {cycles} cycles: the paper or \
                     a background may have been traced as ink; try --polarity or --binarize otsu",
                    100.0 * share
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
                 or photo region, or strokes merged by the threshold; crop to the strokes or try \
                 --polarity",
                graph.edges.len()
            ),
        });
    }
    let specks = roots
        .iter()
        .filter(|&&r| length[r] < SPECK_WIDTHS * width)
        .count();
    if specks >= SPECK_MIN_COUNT && specks as f64 > SPECK_SHARE * roots.len() as f64 {
        let area = (width * width).ceil() as usize;
        out.push(Warning {
            code: "speckle",
            message: format!(
                "{specks} of {} components are specks no longer than a stroke is wide: pass \
                 --min-area {area} to drop ink components under {area} pixels",
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
        of(graph, decisions).iter().map(|w| w.code).collect()
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
        let warnings = of(&graph(&positions, &edges), None);
        assert_eq!(warnings.len(), 1);
        assert_eq!(warnings[0].code, "speckle");
        assert!(
            warnings[0].message.contains("--min-area 9"),
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
}
