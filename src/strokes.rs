//! Strokes through crossings (docs/design.md, "Beyond the paper"): the edges of a [`StrokeGraph`]
//! chained into maximal *strokes* that run straight through junctions, the way a pen drew them.
//!
//! At each vertex the incident edge ends are paired by good continuation:
//! - degree 2 (two edges, or a self-loop): the two ends always continue each other;
//! - degree 3: the two arms that continue each other best (deviation from straight at most
//!   [`StrokeOptions::t_max_deviation_deg`]) are paired when the third arm clearly does not continue
//!   either of them (its best deviation is at least [`StrokeOptions::t_margin_deg`] worse). A T
//!   gives the bar and the stem; a symmetric Y (120° between arms, every pair 60° from straight)
//!   gives three strokes;
//! - degree 4 or more: greedy pairing of the most nearly opposite ends within
//!   [`StrokeOptions::max_deviation_deg`]; ends left over stop there.
//!
//! The tangent of an edge end is the chord from the vertex to the polyline point about two stroke
//! widths along the edge ([`Edge::end_direction`](crate::Edge::end_direction)): the first segment
//! alone follows the bend that arms make where they overlap at a junction. Pairing is a matching on
//! edge ends, so the chains are paths or cycles, and every edge lies in exactly one stroke. Isolated vertices (no edges) give no stroke.
//!
//! Input: a [`StrokeGraph`]. Output: `Vec<Stroke>`, deterministic (ties broken by edge index).

use crate::binary::Binary;
use crate::geometry::dist;
use crate::stroke_graph::StrokeGraph;
use serde::Serialize;

/// Options for [`strokes`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StrokeOptions {
    /// Largest deviation from straight, in degrees, for two edge ends to continue each other at a
    /// vertex of degree 4 or more. Default value: 45.
    pub max_deviation_deg: f64,
    /// Largest deviation from straight, in degrees, for two arms of a degree-3 vertex to continue
    /// each other. Default value: 30.
    pub t_max_deviation_deg: f64,
    /// At a degree-3 vertex the third arm must continue the pair at least this many degrees worse
    /// than the pair continues itself. Default value: 20.
    pub t_margin_deg: f64,
    /// Length over which the tangent of an edge end is measured, in stroke widths at the vertex.
    /// Default value: 2.
    pub tangent_widths: f64,
    /// Shortest tangent length, px (for thin strokes and vertices of unknown width).
    /// Default value: 3.
    pub min_tangent_length: f64,
}

impl Default for StrokeOptions {
    fn default() -> Self {
        StrokeOptions {
            max_deviation_deg: 45.0,
            t_max_deviation_deg: 30.0,
            t_margin_deg: 20.0,
            tangent_widths: 2.0,
            min_tangent_length: 3.0,
        }
    }
}

/// One stroke: graph edges chained end to end through the vertices where they continue each other.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stroke {
    /// Indices of the graph's edges, in drawing order.
    pub edges: Vec<usize>,
    /// For each edge of `edges`, whether it is traversed from its `to` vertex to its `from` vertex.
    pub reversed: Vec<bool>,
    /// The joined polyline (the shared vertex point appears once). A closed stroke repeats its
    /// first point at the end.
    pub points: Vec<[f64; 2]>,
    /// Stroke width at each point, px.
    pub widths: Vec<f64>,
    /// Whether the stroke comes back to where it started (a cycle of continuing edges).
    pub closed: bool,
}

impl Stroke {
    /// Length of the polyline.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| dist(w[0], w[1])).sum()
    }
}

/// Deviation from straight, in degrees, of two outgoing directions: 0 when exactly opposite.
fn deviation_deg(a: [f64; 2], b: [f64; 2]) -> f64 {
    let cos = (-(a[0] * b[0] + a[1] * b[1])).clamp(-1.0, 1.0);
    cos.acos().to_degrees()
}

/// An edge end: `2 * edge` for the end at `from`, `2 * edge + 1` for the end at `to`.
type End = usize;

/// The continuation partner of every edge end (`usize::MAX` for none).
fn pair_ends(graph: &StrokeGraph, options: &StrokeOptions) -> Vec<End> {
    const NONE: usize = usize::MAX;
    let mut partner = vec![NONE; 2 * graph.edges.len()];
    // Ends at each vertex, in end order (deterministic).
    let mut at_vertex: Vec<Vec<End>> = vec![Vec::new(); graph.vertices.len()];
    for (e, edge) in graph.edges.iter().enumerate() {
        if edge.from < at_vertex.len() && edge.to < at_vertex.len() {
            at_vertex[edge.from].push(2 * e);
            at_vertex[edge.to].push(2 * e + 1);
        }
    }
    let mut directions: Vec<Option<[f64; 2]>> = Vec::new();
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (v, ends) in at_vertex.iter().enumerate() {
        if ends.len() < 2 {
            continue;
        }
        if ends.len() == 2 {
            partner[ends[0]] = ends[1];
            partner[ends[1]] = ends[0];
            continue;
        }
        let width = graph.vertices[v].width;
        let width = if width.is_finite() && width > 0.0 {
            width
        } else {
            0.0
        };
        let length = (options.tangent_widths * width).max(options.min_tangent_length);
        directions.clear();
        directions.extend(
            ends.iter()
                .map(|&end| graph.edges[end / 2].end_direction(end % 2 == 0, length)),
        );
        candidates.clear();
        for i in 0..ends.len() {
            for j in i + 1..ends.len() {
                if let (Some(a), Some(b)) = (directions[i], directions[j]) {
                    candidates.push((deviation_deg(a, b), i, j));
                }
            }
        }
        // Most nearly opposite first; ties by position in the end list (edge index order).
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        if ends.len() == 3 {
            let Some(&(best, i, j)) = candidates.first() else {
                continue;
            };
            let k = 3 - i - j;
            let third = candidates
                .iter()
                .filter(|c| c.1 == k || c.2 == k)
                .map(|c| c.0)
                .fold(f64::INFINITY, f64::min);
            // A T: the bar continues itself, the stem clearly does not continue the bar.
            if best <= options.t_max_deviation_deg && third - best >= options.t_margin_deg {
                partner[ends[i]] = ends[j];
                partner[ends[j]] = ends[i];
            }
            continue;
        }
        for &(deviation, i, j) in candidates.iter() {
            if deviation > options.max_deviation_deg {
                break;
            }
            if partner[ends[i]] == NONE && partner[ends[j]] == NONE {
                partner[ends[i]] = ends[j];
                partner[ends[j]] = ends[i];
            }
        }
    }
    partner
}

/// Chains the edges of `graph` into maximal strokes through the vertices where they continue each
/// other (see the module doc). Every edge belongs to exactly one stroke. Strokes are ordered by
/// their lowest edge index; a closed stroke starts at its lowest-index edge in its stored direction,
/// an open one at the end of the chain reached by walking back from its lowest-index edge.
pub fn strokes(graph: &StrokeGraph, options: &StrokeOptions) -> Vec<Stroke> {
    const NONE: usize = usize::MAX;
    let partner = pair_ends(graph, options);
    let edge_count = graph.edges.len();
    let mut used = vec![false; edge_count];
    let mut result = Vec::new();
    for first in 0..edge_count {
        if used[first] {
            continue;
        }
        // Walk backwards from `first` (entered at its `from` end) to the start of the chain.
        let mut entry: End = 2 * first;
        let mut closed = false;
        for _ in 0..edge_count {
            let previous = partner[entry];
            if previous == NONE {
                break;
            }
            if previous / 2 == first {
                closed = true;
                entry = 2 * first;
                break;
            }
            // The previous edge is left at `previous`, so it was entered at its other end.
            entry = previous ^ 1;
        }
        let mut stroke = Stroke {
            edges: Vec::new(),
            reversed: Vec::new(),
            points: Vec::new(),
            widths: Vec::new(),
            closed,
        };
        for _ in 0..edge_count {
            let e = entry / 2;
            if used[e] {
                break;
            }
            used[e] = true;
            let reversed = entry % 2 == 1;
            let edge = &graph.edges[e];
            stroke.edges.push(e);
            stroke.reversed.push(reversed);
            let skip = usize::from(!stroke.points.is_empty());
            if reversed {
                stroke.points.extend(edge.points.iter().rev().skip(skip));
                stroke.widths.extend(edge.widths.iter().rev().skip(skip));
            } else {
                stroke.points.extend(edge.points.iter().skip(skip));
                stroke.widths.extend(edge.widths.iter().skip(skip));
            }
            let next = partner[entry ^ 1];
            if next == NONE {
                break;
            }
            entry = next;
        }
        result.push(stroke);
    }
    result
}

/// How well the widths cover the ink: every edge re-rendered with its per-point widths (round caps
/// and joins, as [`crate::draw::render`] draws the truth) and every isolated vertex as a disk, then
/// the intersection over union with the foreground of `binary`. 1 when both are empty. The quality
/// benchmark reports it (the target is at least 0.9 on text).
pub fn coverage_iou(graph: &StrokeGraph, binary: &Binary) -> f64 {
    let mut drawn: Vec<crate::draw::Stroke> = graph
        .edges
        .iter()
        .filter(|e| !e.points.is_empty() && e.points.len() == e.widths.len())
        .map(|e| crate::draw::Stroke {
            points: e.points.clone(),
            widths: e.widths.clone(),
        })
        .collect();
    drawn.extend(
        graph
            .vertices
            .iter()
            .filter(|v| v.degree == 0)
            .map(|v| crate::draw::Stroke {
                points: vec![v.pos],
                widths: vec![v.width],
            }),
    );
    let rendered = crate::draw::render(&drawn, binary.width, binary.height);
    let (mut both, mut either) = (0usize, 0usize);
    for (&a, &b) in rendered.ink.iter().zip(&binary.ink) {
        both += usize::from(a && b);
        either += usize::from(a || b);
    }
    if either == 0 {
        1.0
    } else {
        both as f64 / either as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stroke_graph::graph_from;

    /// A star: one center vertex, one straight arm to each given point.
    fn star(center: [f64; 2], tips: &[[f64; 2]], width: f64) -> StrokeGraph {
        let mut positions = vec![center];
        positions.extend_from_slice(tips);
        let edges: Vec<_> = (0..tips.len()).map(|i| (0, i + 1, Vec::new())).collect();
        graph_from(&positions, &edges, width)
    }

    fn polar(center: [f64; 2], radius: f64, degrees: f64) -> [f64; 2] {
        let a = degrees.to_radians();
        [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
    }

    fn assert_partition(graph: &StrokeGraph, strokes: &[Stroke]) {
        let mut seen = vec![0; graph.edges.len()];
        for s in strokes {
            assert_eq!(s.edges.len(), s.reversed.len());
            assert_eq!(s.points.len(), s.widths.len());
            for &e in &s.edges {
                seen[e] += 1;
            }
        }
        assert!(
            seen.iter().all(|&n| n == 1),
            "each edge in exactly one stroke: {seen:?}"
        );
    }

    #[test]
    fn plus_gives_two_straight_strokes() {
        let c = [100.0, 100.0];
        // Arms in an order that does not pair neighbours by index.
        let tips: Vec<_> = [0.0, 90.0, 180.0, 270.0]
            .iter()
            .map(|&a| polar(c, 50.0, a))
            .collect();
        let g = star(c, &tips, 6.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_partition(&g, &s);
        assert_eq!(s.len(), 2);
        for stroke in &s {
            assert_eq!(stroke.edges.len(), 2);
            assert!(!stroke.closed);
            assert!((stroke.length() - 100.0).abs() < 1e-9);
            assert_eq!(stroke.points.len(), 3, "shared vertex point appears once");
        }
        let mut pairs: Vec<Vec<usize>> = s.iter().map(|st| st.edges.clone()).collect();
        pairs.iter_mut().for_each(|p| p.sort());
        pairs.sort();
        assert_eq!(pairs, vec![vec![0, 2], vec![1, 3]]);
    }

    #[test]
    fn x_at_30_degrees_pairs_opposite_arms() {
        let c = [100.0, 100.0];
        let tips: Vec<_> = [0.0, 30.0, 180.0, 210.0]
            .iter()
            .map(|&a| polar(c, 60.0, a))
            .collect();
        let g = star(c, &tips, 8.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_partition(&g, &s);
        assert_eq!(s.len(), 2);
        for stroke in &s {
            let mut e = stroke.edges.clone();
            e.sort();
            assert!(e == vec![0, 2] || e == vec![1, 3], "{e:?}");
        }
    }

    #[test]
    fn tangent_uses_two_widths_not_the_first_segment() {
        // Arms of a '+' whose first segment bends 40 degrees (as arms do where they overlap); by
        // first segments alone, arms 2 and 3 would look nearly opposite (10 degrees off).
        let c = [100.0, 100.0];
        let mut positions = vec![c];
        let mut edges = Vec::new();
        for (k, (a, bend)) in [(0.0f64, 40.0), (90.0, -40.0), (180.0, -40.0), (270.0, 40.0)]
            .iter()
            .enumerate()
        {
            let bent = polar(c, 2.0, a + bend);
            let mid = polar(c, 6.0, *a);
            positions.push(polar(c, 50.0, *a));
            edges.push((0, k + 1, vec![bent, mid]));
        }
        let g = graph_from(&positions, &edges, 6.0);
        let s = strokes(&g, &StrokeOptions::default());
        let mut pairs: Vec<Vec<usize>> = s.iter().map(|st| st.edges.clone()).collect();
        pairs.iter_mut().for_each(|p| p.sort());
        pairs.sort();
        assert_eq!(pairs, vec![vec![0, 2], vec![1, 3]]);
        let first_segment = StrokeOptions {
            tangent_widths: 0.0,
            min_tangent_length: 1.0,
            ..Default::default()
        };
        let naive = strokes(&g, &first_segment);
        assert!(naive.iter().any(|st| {
            let mut e = st.edges.clone();
            e.sort();
            e == vec![2, 3]
        }));
        let d = g.edges[0].end_direction(true, 12.0).unwrap();
        assert!(
            d[1].abs() < 0.1,
            "chord over 2 widths is close to the arm: {d:?}"
        );
    }

    #[test]
    fn eight_is_one_closed_stroke() {
        // Two loops at one degree-4 vertex, crossing like a figure eight.
        let c = [100.0, 100.0];
        // Lemniscate of Bernoulli, lobes up and down, arms at +-45 degrees at the center.
        let lobe = |from: f64| -> Vec<[f64; 2]> {
            (1..60)
                .map(|k| {
                    let t = from + k as f64 / 60.0 * std::f64::consts::PI;
                    let q = 1.0 + t.sin() * t.sin();
                    [
                        c[0] + 40.0 * t.sin() * t.cos() / q,
                        c[1] + 40.0 * t.cos() / q,
                    ]
                })
                .collect()
        };
        let upper = lobe(std::f64::consts::FRAC_PI_2);
        let lower = lobe(-std::f64::consts::FRAC_PI_2);
        let g = graph_from(&[c], &[(0, 0, upper), (0, 0, lower)], 6.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_partition(&g, &s);
        assert_eq!(s.len(), 1, "{s:?}");
        assert!(s[0].closed);
        assert_eq!(s[0].points.first(), s[0].points.last());
    }

    #[test]
    fn circle_through_a_degree_two_loop_vertex_is_closed() {
        let c = [50.0, 50.0];
        let interior: Vec<_> = (1..30)
            .map(|k| polar([50.0, 70.0], 20.0, 270.0 + k as f64 * 12.0))
            .collect();
        let g = graph_from(&[c], &[(0, 0, interior)], 4.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_eq!(s.len(), 1);
        assert!(s[0].closed);
    }

    #[test]
    fn t_gives_bar_and_stem() {
        let c = [100.0, 100.0];
        let tips = [[40.0, 100.0], [100.0, 160.0], [160.0, 100.0]];
        let g = star(c, &tips, 6.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_partition(&g, &s);
        assert_eq!(s.len(), 2);
        let bar = s.iter().find(|st| st.edges.len() == 2).unwrap();
        let mut e = bar.edges.clone();
        e.sort();
        assert_eq!(e, vec![0, 2]);
    }

    #[test]
    fn symmetric_y_gives_three_strokes() {
        let c = [100.0, 100.0];
        let tips: Vec<_> = [90.0, 210.0, 330.0]
            .iter()
            .map(|&a| polar(c, 50.0, a))
            .collect();
        let g = star(c, &tips, 6.0);
        assert_eq!(strokes(&g, &StrokeOptions::default()).len(), 3);
    }

    #[test]
    fn letter_y_tail_continues_the_right_arm() {
        // Tail down-left, right arm up-right (continues it), left arm 40 degrees off.
        let c = [100.0, 100.0];
        let tips: Vec<_> = [120.0, 300.0, 260.0]
            .iter()
            .map(|&a| polar(c, 50.0, a))
            .collect();
        let g = star(c, &tips, 6.0);
        let s = strokes(&g, &StrokeOptions::default());
        assert_eq!(s.len(), 2);
        let long = s.iter().find(|st| st.edges.len() == 2).unwrap();
        let mut e = long.edges.clone();
        e.sort();
        assert_eq!(e, vec![0, 1]);
    }

    #[test]
    fn chain_through_degree_two_vertices_keeps_order_and_orientation() {
        // Path 0 -> 1 <- 2 -> 3: the middle edge is stored backwards.
        let positions = [[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [30.0, 0.0]];
        let g = graph_from(
            &positions,
            &[(1, 2, vec![]), (0, 1, vec![]), (2, 3, vec![])],
            2.0,
        );
        let s = strokes(&g, &StrokeOptions::default());
        assert_eq!(s.len(), 1);
        let xs: Vec<f64> = s[0].points.iter().map(|p| p[0]).collect();
        assert!(
            xs == vec![0.0, 10.0, 20.0, 30.0] || xs == vec![30.0, 20.0, 10.0, 0.0],
            "{xs:?}"
        );
        assert!(!s[0].closed);
    }

    #[test]
    fn deterministic() {
        let c = [100.0, 100.0];
        let tips: Vec<_> = [0.0, 60.0, 120.0, 180.0, 240.0, 300.0]
            .iter()
            .map(|&a| polar(c, 40.0, a))
            .collect();
        let g = star(c, &tips, 6.0);
        let a = strokes(&g, &StrokeOptions::default());
        let b = strokes(&g, &StrokeOptions::default());
        assert_eq!(a, b);
        assert_eq!(a.len(), 3);
    }
}
