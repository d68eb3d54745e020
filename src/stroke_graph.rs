//! The result: stroke centerlines as polylines (edges) meeting at vertices.

use serde::Serialize;

use crate::geometry::dist;

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
        let mut parent: Vec<usize> = (0..self.vertices.len()).collect();
        fn find(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        let mut count = self.vertices.len();
        for e in &self.edges {
            let (a, b) = (find(&mut parent, e.from), find(&mut parent, e.to));
            if a != b {
                parent[a] = b;
                count -= 1;
            }
        }
        count
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
