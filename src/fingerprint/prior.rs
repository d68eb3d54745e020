//! The orientation field as a prior on the traced ridges (docs/fingerprints.md, "Ridges along
//! the flow"): two ridges never join through a valley and never cross. On a print, ridges run
//! side by side along the flow; where the binarization joins two of them the traced graph shows
//! it in two ways, both undone here:
//!
//! - a **bar across the flow**: an edge between two junctions, shorter than
//!   `bridge_periods` ridge periods, whose chord is more than 45° off the local ridge direction.
//!   It goes, and its junctions, left with two edges each, are joined through: the two ridges it
//!   tied run on apart.
//! - an **X where two ridges touch**: a vertex with four arms that pair, without crossing, into
//!   two ridges running on along the flow (each pair within 60° of straight, every arm within 45°
//!   of the ridge direction). The vertex is split in two, one per ridge, each joined through.
//!
//! The minutiae filter drops the bifurcations of bars too ([`crate::minutiae`]); this makes the
//! graph itself, and so the JSON and SVG, follow the ridges.

use super::{orientation_gap, PrintAnalysis};
use crate::params::FingerprintParams;
use crate::stroke_graph::{Edge, StrokeGraph};
use std::f64::consts::{FRAC_PI_3, FRAC_PI_4, PI};

/// `graph` with its bars across the flow removed and its touching ridges split apart.
pub(crate) fn ridges_along_the_flow(
    graph: StrokeGraph,
    print: &PrintAnalysis,
    params: &FingerprintParams,
) -> StrokeGraph {
    let mut work = Work::new(graph);
    // Bars: decided on the graph as traced, all at once.
    let bars: Vec<usize> = (0..work.edges.len())
        .filter(|&e| work.is_bar(e, print, params.bridge_periods))
        .collect();
    for e in bars {
        work.remove_edge(e);
    }
    for v in 0..work.vertices.len() {
        if work.ends[v].len() == 4 {
            work.split_touching(v, print);
        }
    }
    work.finish()
}

/// A graph being edited: edges that can be removed, each vertex's edge ends.
struct Work {
    width: u32,
    height: u32,
    vertices: Vec<crate::stroke_graph::Vertex>,
    edges: Vec<Option<Edge>>,
    /// Per vertex, its edge ends: (edge, whether it is the edge's start).
    ends: Vec<Vec<(usize, bool)>>,
    /// Vertices an edit touched: joined through when left with two edges, dropped with none.
    touched: Vec<bool>,
}

impl Work {
    fn new(graph: StrokeGraph) -> Self {
        let mut ends = vec![Vec::new(); graph.vertices.len()];
        for (e, edge) in graph.edges.iter().enumerate() {
            ends[edge.from].push((e, true));
            ends[edge.to].push((e, false));
        }
        Work {
            width: graph.width,
            height: graph.height,
            touched: vec![false; graph.vertices.len()],
            vertices: graph.vertices,
            edges: graph.edges.into_iter().map(Some).collect(),
            ends,
        }
    }

    /// Whether edge `e` is a short bar across the flow between two junctions.
    fn is_bar(&self, e: usize, print: &PrintAnalysis, bridge_periods: f64) -> bool {
        let Some(edge) = &self.edges[e] else {
            return false;
        };
        if edge.from == edge.to || self.ends[edge.from].len() < 3 || self.ends[edge.to].len() < 3 {
            return false;
        }
        let (Some(first), Some(last)) = (edge.points.first(), edge.points.last()) else {
            return false;
        };
        let middle = [(first[0] + last[0]) / 2.0, (first[1] + last[1]) / 2.0];
        let period = print.periods.at(middle).max(1.0);
        edge.length() < bridge_periods * period && print.across_the_flow(*first, *last)
    }

    fn remove_edge(&mut self, e: usize) {
        if let Some(edge) = self.edges[e].take() {
            for v in [edge.from, edge.to] {
                self.ends[v].retain(|&(f, _)| f != e);
                self.touched[v] = true;
            }
        }
    }

    /// Splits vertex `v` of four arms into two vertices of two arms each when the arms pair,
    /// without crossing, into two ridges along the flow.
    fn split_touching(&mut self, v: usize, print: &PrintAnalysis) {
        let pos = self.vertices[v].pos;
        let period = print.periods.at(pos).max(1.0);
        let flow = print.orientation.angle_at(pos);
        let mut arms: Vec<(f64, (usize, bool))> = Vec::with_capacity(4);
        for &(e, at_start) in &self.ends[v] {
            let Some(edge) = &self.edges[e] else {
                return;
            };
            if edge.from == edge.to {
                return;
            }
            let Some(d) = edge.end_direction(at_start, period) else {
                return;
            };
            let angle = d[1].atan2(d[0]);
            if orientation_gap(angle, flow) > FRAC_PI_4 {
                return;
            }
            arms.push((angle, (e, at_start)));
        }
        arms.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Two pairings of neighbours around the vertex do not cross: (0 1)(2 3) and (1 2)(3 0).
        // Each pair's bend from straight, the worse of the two pairs.
        let bend = |i: usize, j: usize| {
            let d = (arms[i].0 - arms[j].0).rem_euclid(2.0 * PI);
            (PI - d.min(2.0 * PI - d)).abs()
        };
        let pairings = [[(0, 1), (2, 3)], [(1, 2), (3, 0)]];
        let worst = |p: &[(usize, usize); 2]| bend(p[0].0, p[0].1).max(bend(p[1].0, p[1].1));
        let Some(best) = pairings.iter().min_by(|a, b| worst(a).total_cmp(&worst(b))) else {
            return;
        };
        if worst(best) > FRAC_PI_3 {
            return;
        }
        // The second pair moves to a new vertex at the same place.
        let moved = [arms[best[1].0].1, arms[best[1].1].1];
        let new = self.vertices.len();
        self.vertices.push(self.vertices[v].clone());
        self.ends.push(moved.to_vec());
        self.touched.push(true);
        self.ends[v].retain(|end| !moved.contains(end));
        self.touched[v] = true;
        for (e, at_start) in moved {
            if let Some(edge) = self.edges[e].as_mut() {
                if at_start {
                    edge.from = new;
                } else {
                    edge.to = new;
                }
            }
        }
    }

    /// Joins every touched vertex of two edges through, drops touched vertices of none, and
    /// renumbers.
    fn finish(mut self) -> StrokeGraph {
        let gone: Vec<bool> = (0..self.vertices.len())
            .map(|v| {
                if !self.touched[v] {
                    return false;
                }
                match self.ends[v].as_slice() {
                    [] => true,
                    &[(a, a_start), (b, b_start)] if a != b => {
                        self.join_through(v, (a, a_start), (b, b_start));
                        true
                    }
                    _ => false,
                }
            })
            .collect();
        let mut index = vec![usize::MAX; self.vertices.len()];
        let mut vertices = Vec::new();
        for (v, vertex) in self.vertices.into_iter().enumerate() {
            if !gone[v] {
                index[v] = vertices.len();
                vertices.push(crate::stroke_graph::Vertex {
                    degree: self.ends[v].len(),
                    ..vertex
                });
            }
        }
        let edges = self
            .edges
            .into_iter()
            .flatten()
            .map(|mut edge| {
                edge.from = index[edge.from];
                edge.to = index[edge.to];
                edge
            })
            .collect();
        StrokeGraph {
            width: self.width,
            height: self.height,
            vertices,
            edges,
        }
    }

    /// Replaces edges `a` and `b`, which meet at `v`, by one edge through `v` (stored as `a`).
    fn join_through(&mut self, v: usize, a: (usize, bool), b: (usize, bool)) {
        let (Some(first), Some(second)) = (self.edges[a.0].take(), self.edges[b.0].take()) else {
            return;
        };
        // `first` ends at v, `second` starts there.
        let first = if a.1 { reversed(first) } else { first };
        let second = if b.1 { second } else { reversed(second) };
        let (start, end) = (first.from, second.to);
        let mut joined = first;
        joined.points.extend_from_slice(&second.points[1..]);
        joined.widths.extend_from_slice(&second.widths[1..]);
        joined.directions.extend_from_slice(&second.directions[1..]);
        joined.to = end;
        self.edges[a.0] = Some(joined);
        self.ends[v].clear();
        // The far ends now belong to the joined edge: its start at `start`, its end at `end`.
        // (When `start == end` the joined edge is a loop and both entries are in one list.)
        if let Some(entry) = self.ends[start].iter_mut().find(|(e, _)| *e == a.0) {
            *entry = (a.0, true);
        }
        if let Some(entry) = self.ends[end].iter_mut().find(|(e, _)| *e == b.0) {
            *entry = (a.0, false);
        }
    }
}

/// `edge` run the other way.
fn reversed(mut edge: Edge) -> Edge {
    std::mem::swap(&mut edge.from, &mut edge.to);
    edge.points.reverse();
    edge.widths.reverse();
    edge.directions.reverse();
    for d in &mut edge.directions {
        *d = [-d[0], -d[1]];
    }
    edge
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fingerprint::fields::BlockGrid;
    use crate::fingerprint::tests::uniform_print;
    use crate::stroke_graph::graph_from;

    /// A print of horizontal ridges of period 9 over a 100 x 60 image.
    fn horizontal_print() -> PrintAnalysis {
        let (segmentation, orientation, periods) =
            uniform_print(BlockGrid::new(100, 60, 8), 0.0, 9.0);
        PrintAnalysis {
            segmentation,
            orientation,
            periods,
            ..PrintAnalysis::default()
        }
    }

    /// A graph of straight edges `(from, to)` between `positions`, 8 segments each, 4 px wide.
    fn graph(positions: &[[f64; 2]], edges: &[(usize, usize)]) -> StrokeGraph {
        let polylines: Vec<(usize, usize, Vec<[f64; 2]>)> = edges
            .iter()
            .map(|&(a, b)| {
                let (p, q) = (positions[a], positions[b]);
                let points = (0..=8)
                    .map(|k| {
                        let t = f64::from(k) / 8.0;
                        [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
                    })
                    .collect();
                (a, b, points)
            })
            .collect();
        graph_from(positions, &polylines, 4.0)
    }

    #[test]
    fn a_bar_across_the_flow_goes_and_the_ridges_run_on() {
        // Two ridges 9 px apart, tied by a vertical bar at x = 50.
        let g = graph(
            &[
                [10.0, 20.0],
                [50.0, 20.0],
                [90.0, 20.0],
                [10.0, 29.0],
                [50.0, 29.0],
                [90.0, 29.0],
            ],
            &[(0, 1), (1, 2), (3, 4), (4, 5), (1, 4)],
        );
        let out = ridges_along_the_flow(g, &horizontal_print(), &FingerprintParams::default());
        out.validate().expect("valid graph");
        assert_eq!(out.edges.len(), 2, "{out:?}");
        assert_eq!(out.vertices.len(), 4);
        assert!(out.vertices.iter().all(|v| v.degree == 1));
        let mut ys: Vec<f64> = out.edges.iter().map(|e| e.points[0][1]).collect();
        ys.sort_by(f64::total_cmp);
        assert_eq!(ys, vec![20.0, 29.0]);
        assert!(out.edges.iter().all(|e| (e.length() - 80.0).abs() < 1e-9));
    }

    #[test]
    fn a_branch_along_the_flow_and_a_long_bar_stay() {
        // A fork: a stem from the left splitting into two branches to the right.
        let fork = graph(
            &[[10.0, 25.0], [40.0, 25.0], [90.0, 20.0], [90.0, 30.0]],
            &[(0, 1), (1, 2), (1, 3)],
        );
        let out = ridges_along_the_flow(fork.clone(), &horizontal_print(), &Default::default());
        assert_eq!(out, fork);
        // A bar across the flow longer than 1.5 periods is not a bridge between neighbours.
        let long = graph(
            &[
                [10.0, 10.0],
                [50.0, 10.0],
                [90.0, 10.0],
                [10.0, 50.0],
                [50.0, 50.0],
                [90.0, 50.0],
            ],
            &[(0, 1), (1, 2), (3, 4), (4, 5), (1, 4)],
        );
        let out = ridges_along_the_flow(long.clone(), &horizontal_print(), &Default::default());
        assert_eq!(out, long);
    }

    #[test]
    fn two_touching_ridges_are_split_apart_and_a_crossing_across_the_flow_is_not() {
        // Two ridges bending towards each other until they touch at (50, 26).
        let touching = graph(
            &[
                [10.0, 20.0],
                [90.0, 20.0],
                [10.0, 32.0],
                [90.0, 32.0],
                [50.0, 26.0],
            ],
            &[(0, 4), (4, 1), (2, 4), (4, 3)],
        );
        let out = ridges_along_the_flow(touching, &horizontal_print(), &Default::default());
        out.validate().expect("valid graph");
        assert_eq!(out.edges.len(), 2, "{out:?}");
        assert!(out.vertices.iter().all(|v| v.degree == 1));
        // Each ridge keeps its own side: its two ends at the same height.
        for e in &out.edges {
            let (a, b) = (e.points[0], e.points[e.points.len() - 1]);
            assert_eq!(a[1], b[1], "{e:?}");
            assert!(e.points.iter().any(|p| p == &[50.0, 26.0]));
        }
        // Two ridges crossing at right angles: their arms do not run along the flow.
        let cross = graph(
            &[
                [20.0, 26.0],
                [80.0, 26.0],
                [50.0, 2.0],
                [50.0, 58.0],
                [50.0, 26.0],
            ],
            &[(0, 4), (4, 1), (2, 4), (4, 3)],
        );
        let out = ridges_along_the_flow(cross.clone(), &horizontal_print(), &Default::default());
        assert_eq!(out, cross);
    }
}
