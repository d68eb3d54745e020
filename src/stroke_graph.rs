//! The result: stroke centerlines as polylines (edges) meeting at vertices.

use petgraph::unionfind::UnionFind;
use serde::Serialize;

use crate::geometry::{dist, hypot};

/// A vertex: a stroke end (degree 1), a junction (degree 3 or more), or the anchor of a closed
/// loop (degree 2, an edge from the vertex to itself), or an isolated blob (degree 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Vertex {
    /// Position in image coordinates (pixel `(c, r)` covers `[c, c+1] x [r, r+1]`).
    pub pos: [f64; 2],
    /// Number of edge ends at this vertex (a self-loop counts twice).
    pub degree: usize,
    /// Local stroke width at the vertex, px (2 x distance to the background).
    pub width: f64,
}

/// An edge: one centerline polyline from vertex `from` to vertex `to`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Edge {
    /// Start vertex index.
    pub from: usize,
    /// End vertex index (equal to `from` for a closed loop).
    pub to: usize,
    /// The polyline, starting at `vertices[from].pos` and ending at `vertices[to].pos`.
    pub points: Vec<[f64; 2]>,
    /// Local stroke width at each polyline point, px.
    pub widths: Vec<f64>,
    /// Unit tangent at each polyline point (direction of travel).
    pub directions: Vec<[f64; 2]>,
}

impl Edge {
    /// Length of the polyline.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| dist(w[0], w[1])).sum()
    }

    /// Unit direction in which the edge leaves its `from` vertex (`at_start`) or its `to` vertex:
    /// the chord from the vertex to the polyline point `length` further along the edge. The length
    /// is clamped to half the edge (a third for a self-loop, whose two ends must not share a
    /// chord). `None` when the chord is degenerate. The strokes chain edges and the minutiae aim
    /// their marks by it.
    pub fn end_direction(&self, at_start: bool, length: f64) -> Option<[f64; 2]> {
        let n = self.points.len();
        if n < 2 {
            return None;
        }
        let point = |i: usize| {
            if at_start {
                self.points[i]
            } else {
                self.points[n - 1 - i]
            }
        };
        let total = self.length();
        let share = if self.from == self.to { 3.0 } else { 2.0 };
        let target = length.min(total / share);
        let origin = point(0);
        let mut far = point(n - 1);
        let mut walked = 0.0;
        for i in 1..n {
            let (a, b) = (point(i - 1), point(i));
            let step = dist(a, b);
            if walked + step >= target {
                let t = if step > 0.0 {
                    (target - walked) / step
                } else {
                    0.0
                };
                far = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                break;
            }
            walked += step;
        }
        let chord = [far[0] - origin[0], far[1] - origin[1]];
        let norm = hypot(chord[0], chord[1]);
        (norm > 1e-9 && norm.is_finite()).then(|| [chord[0] / norm, chord[1] / norm])
    }
}

/// The stroke graph of one image or point set.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StrokeGraph {
    /// Width of the source image (px); for point sets, the bounding box's right edge.
    pub width: u32,
    /// Height of the source image (px).
    pub height: u32,
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// The edges.
    pub edges: Vec<Edge>,
}

impl StrokeGraph {
    /// Vertices of degree 1 (stroke ends).
    pub fn endpoints(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.vertices.len()).filter(|&v| self.vertices[v].degree == 1)
    }

    /// Vertices of degree 3 or more (junctions and crossings).
    pub fn junctions(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.vertices.len()).filter(|&v| self.vertices[v].degree >= 3)
    }

    /// Number of connected components (isolated vertices count as components).
    pub fn components(&self) -> usize {
        let roots = self.component_roots();
        (0..roots.len()).filter(|&v| roots[v] == v).count()
    }

    /// For each vertex, the vertex that stands for its connected component (union-find over the
    /// edges): the components are the vertices that are their own root.
    pub(crate) fn component_roots(&self) -> Vec<usize> {
        let mut sets = UnionFind::<usize>::new(self.vertices.len());
        for e in &self.edges {
            sets.union(e.from, e.to);
        }
        sets.into_labeling()
    }

    /// Cycle rank (independent cycles): `E - V + C`.
    pub fn cycles(&self) -> usize {
        self.edges.len() + self.components() - self.vertices.len()
    }

    /// Checks the invariants: degrees match edge ends, each polyline has at least two points, starts
    /// and ends at its vertices, has one width and direction per point, and nothing is NaN.
    pub fn validate(&self) -> Result<(), String> {
        let mut degree = vec![0usize; self.vertices.len()];
        for (i, e) in self.edges.iter().enumerate() {
            if e.from >= self.vertices.len() || e.to >= self.vertices.len() {
                return Err(format!("edge {i} refers to a missing vertex"));
            }
            degree[e.from] += 1;
            degree[e.to] += 1;
            if e.points.len() < 2 {
                return Err(format!("edge {i} has {} points", e.points.len()));
            }
            if e.widths.len() != e.points.len() || e.directions.len() != e.points.len() {
                return Err(format!(
                    "edge {i}: widths/directions do not match its points"
                ));
            }
            let finite = |p: &[f64; 2]| p[0].is_finite() && p[1].is_finite();
            if !e.points.iter().all(finite) || !e.directions.iter().all(finite) {
                return Err(format!("edge {i} has a non-finite point"));
            }
            if !e.widths.iter().all(|w| w.is_finite() && *w >= 0.0) {
                return Err(format!("edge {i} has a bad width"));
            }
            let (first, last) = (e.points[0], e.points[e.points.len() - 1]);
            if dist(first, self.vertices[e.from].pos) > 1e-6
                || dist(last, self.vertices[e.to].pos) > 1e-6
            {
                return Err(format!("edge {i} does not start and end at its vertices"));
            }
        }
        for (v, vertex) in self.vertices.iter().enumerate() {
            if vertex.degree != degree[v] {
                return Err(format!(
                    "vertex {v} has degree {} but {} edge ends",
                    vertex.degree, degree[v]
                ));
            }
            if !(vertex.pos[0].is_finite() && vertex.pos[1].is_finite() && vertex.width.is_finite())
            {
                return Err(format!("vertex {v} is not finite"));
            }
        }
        Ok(())
    }
}

/// A stroke graph built from vertex positions and edge polylines, with every width set to
/// `width` and directions along the polylines: for tests of the feature modules.
#[cfg(test)]
pub(crate) fn graph_from(
    positions: &[[f64; 2]],
    edges: &[(usize, usize, Vec<[f64; 2]>)],
    width: f64,
) -> StrokeGraph {
    let mut vertices: Vec<Vertex> = positions
        .iter()
        .map(|&pos| Vertex {
            pos,
            degree: 0,
            width,
        })
        .collect();
    let mut out = Vec::new();
    for (from, to, interior) in edges {
        vertices[*from].degree += 1;
        vertices[*to].degree += 1;
        let mut points = vec![positions[*from]];
        points.extend(interior.iter().copied());
        points.push(positions[*to]);
        let directions = (0..points.len())
            .map(|i| {
                let (a, b) = (
                    points[i.saturating_sub(1)],
                    points[(i + 1).min(points.len() - 1)],
                );
                let n = dist(a, b).max(1e-12);
                [(b[0] - a[0]) / n, (b[1] - a[1]) / n]
            })
            .collect();
        out.push(Edge {
            from: *from,
            to: *to,
            widths: vec![width; points.len()],
            points,
            directions,
        });
    }
    StrokeGraph {
        width: 200,
        height: 200,
        vertices,
        edges: out,
    }
}
