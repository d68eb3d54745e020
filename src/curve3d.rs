//! The result of tracing a 3D point set: curve centerlines as 3D polylines meeting at vertices,
//! the space curve counterpart of [`crate::StrokeGraph`] (no image, so no pixel extent).

use petgraph::unionfind::UnionFind;
use serde::Serialize;

/// Euclidean distance between two points in space.
pub fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A vertex: a curve end (degree 1), a junction (degree 3 or more), the anchor of a closed curve
/// (degree 2, an edge from the vertex to itself) or an isolated clump (degree 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Vertex3d {
    /// Position, in the input's unit.
    pub pos: [f64; 3],
    /// Number of edge ends at this vertex (a self-loop counts twice).
    pub degree: usize,
    /// Local tube diameter at the vertex, in the input's unit.
    pub width: f64,
}

/// An edge: one centerline polyline from vertex `from` to vertex `to`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Edge3d {
    /// Start vertex index.
    pub from: usize,
    /// End vertex index (equal to `from` for a closed curve).
    pub to: usize,
    /// The polyline, starting at `vertices[from].pos` and ending at `vertices[to].pos`.
    pub points: Vec<[f64; 3]>,
    /// Local tube diameter at each polyline point.
    pub widths: Vec<f64>,
}

impl Edge3d {
    /// Length of the polyline.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| dist3(w[0], w[1])).sum()
    }
}

/// The curve graph of a 3D point set.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CurveGraph3d {
    /// The vertices.
    pub vertices: Vec<Vertex3d>,
    /// The edges.
    pub edges: Vec<Edge3d>,
}

impl CurveGraph3d {
    /// A plane graph in space, at `z = 0` (for the 3D writers).
    pub fn from_plane(graph: &crate::stroke_graph::StrokeGraph) -> CurveGraph3d {
        let lift = |p: [f64; 2]| [p[0], p[1], 0.0];
        CurveGraph3d {
            vertices: graph
                .vertices
                .iter()
                .map(|v| Vertex3d {
                    pos: lift(v.pos),
                    degree: v.degree,
                    width: v.width,
                })
                .collect(),
            edges: graph
                .edges
                .iter()
                .map(|e| Edge3d {
                    from: e.from,
                    to: e.to,
                    points: e.points.iter().map(|&p| lift(p)).collect(),
                    widths: e.widths.clone(),
                })
                .collect(),
        }
    }

    /// Vertices of degree 1 (curve ends).
    pub fn endpoints(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.vertices.len()).filter(|&v| self.vertices[v].degree == 1)
    }

    /// Vertices of degree 3 or more (junctions and crossings).
    pub fn junctions(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.vertices.len()).filter(|&v| self.vertices[v].degree >= 3)
    }

    /// Number of connected components (isolated vertices count as components).
    pub fn components(&self) -> usize {
        let mut sets = UnionFind::<usize>::new(self.vertices.len());
        for e in &self.edges {
            sets.union(e.from, e.to);
        }
        let roots = sets.into_labeling();
        (0..roots.len()).filter(|&v| roots[v] == v).count()
    }

    /// Cycle rank (independent cycles): `E - V + C`.
    pub fn cycles(&self) -> usize {
        self.edges.len() + self.components() - self.vertices.len()
    }

    /// Checks the invariants: degrees match edge ends, each polyline has at least two points,
    /// starts and ends at its vertices, has one width per point, and nothing is NaN.
    pub fn validate(&self) -> Result<(), String> {
        let mut degree = vec![0usize; self.vertices.len()];
        let finite = |p: &[f64; 3]| p.iter().all(|c| c.is_finite());
        for (i, e) in self.edges.iter().enumerate() {
            if e.from >= self.vertices.len() || e.to >= self.vertices.len() {
                return Err(format!("edge {i} refers to a missing vertex"));
            }
            degree[e.from] += 1;
            degree[e.to] += 1;
            if e.points.len() < 2 {
                return Err(format!("edge {i} has {} points", e.points.len()));
            }
            if e.widths.len() != e.points.len() {
                return Err(format!("edge {i}: widths do not match its points"));
            }
            if !e.points.iter().all(finite) {
                return Err(format!("edge {i} has a non-finite point"));
            }
            if !e.widths.iter().all(|w| w.is_finite() && *w >= 0.0) {
                return Err(format!("edge {i} has a bad width"));
            }
            let (first, last) = (e.points[0], e.points[e.points.len() - 1]);
            if first != self.vertices[e.from].pos || last != self.vertices[e.to].pos {
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
            if !finite(&vertex.pos) || !vertex.width.is_finite() {
                return Err(format!("vertex {v} is not finite"));
            }
        }
        Ok(())
    }
}

/// Everything tracing a 3D point set produces ([`crate::trace_points3d`]).
#[derive(Clone, Debug, Default)]
pub struct Trace3d {
    /// The result.
    pub graph: CurveGraph3d,
    /// Number of distinct points the pipeline ran on.
    pub point_count: usize,
    /// What is probably wrong with the result (`not_strip_shaped` for a set that is no tube).
    pub warnings: Vec<crate::decisions::Warning>,
    /// Wall-clock time of the whole trace.
    pub time: std::time::Duration,
}
