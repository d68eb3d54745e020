//! A curve graph as polylines for 3D viewers (Blender, MeshLab, CloudCompare): PLY with a
//! `vertex` element (`x y z` and the tube's `width`) and an `edge` element (`vertex1 vertex2`, one
//! per segment), and Wavefront OBJ with `v` lines and one `l` line per edge. The graph's vertices
//! come first, in their order, then each edge's interior points, so vertex `i` of the graph is
//! vertex `i` of the file (`i + 1` in OBJ); a plane graph is written with `z = 0`
//! ([`CurveGraph3d::from_plane`]). Numbers are written in full (Rust's shortest round-trip
//! form), so the same graph gives the same bytes.

use std::fmt::Write;

use crate::curve3d::CurveGraph3d;

/// The file's points with their widths, and per edge the indices of its polyline.
type Layout = (Vec<([f64; 3], f64)>, Vec<Vec<usize>>);

/// The file's points and, per edge, the indices of its polyline.
fn layout(graph: &CurveGraph3d) -> Layout {
    let mut points: Vec<([f64; 3], f64)> =
        graph.vertices.iter().map(|v| (v.pos, v.width)).collect();
    let mut lines = Vec::with_capacity(graph.edges.len());
    for e in &graph.edges {
        let n = e.points.len();
        let mut line = Vec::with_capacity(n);
        line.push(e.from);
        for i in 1..n.saturating_sub(1) {
            line.push(points.len());
            points.push((e.points[i], e.widths.get(i).copied().unwrap_or(0.0)));
        }
        line.push(e.to);
        lines.push(line);
    }
    (points, lines)
}

/// Writes `graph` as an ASCII PLY file of vertices and edges.
pub fn to_ply(graph: &CurveGraph3d) -> String {
    let (points, lines) = layout(graph);
    let segments: usize = lines.iter().map(|l| l.len().saturating_sub(1)).sum();
    let mut out = String::new();
    let _ = write!(
        out,
        "ply\nformat ascii 1.0\ncomment ridgeline {}: curve centerlines, one edge per segment\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         property double width\nelement edge {segments}\nproperty int vertex1\n\
         property int vertex2\nend_header\n",
        env!("CARGO_PKG_VERSION"),
        points.len()
    );
    for (p, w) in &points {
        let _ = writeln!(
            out,
            "{} {} {} {}",
            p[0] + 0.0,
            p[1] + 0.0,
            p[2] + 0.0,
            w + 0.0
        );
    }
    for line in &lines {
        for pair in line.windows(2) {
            let _ = writeln!(out, "{} {}", pair[0], pair[1]);
        }
    }
    out
}

/// Writes `graph` as a Wavefront OBJ file: `v` lines, then one `l` polyline per edge.
pub fn to_obj(graph: &CurveGraph3d) -> String {
    let (points, lines) = layout(graph);
    let mut out = format!(
        "# ridgeline {}: curve centerlines, one polyline (l) per edge\n",
        env!("CARGO_PKG_VERSION")
    );
    for (p, _) in &points {
        let _ = writeln!(out, "v {} {} {}", p[0] + 0.0, p[1] + 0.0, p[2] + 0.0);
    }
    for line in &lines {
        out.push('l');
        for &i in line {
            let _ = write!(out, " {}", i + 1);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve3d::{Edge3d, Vertex3d};

    fn graph() -> CurveGraph3d {
        let vertex = |pos, degree| Vertex3d {
            pos,
            degree,
            width: 2.0,
        };
        CurveGraph3d {
            vertices: vec![vertex([0.0, 0.0, 0.0], 3), vertex([5.0, 0.0, 1.5], 1)],
            edges: vec![
                Edge3d {
                    from: 0,
                    to: 1,
                    points: vec![[0.0, 0.0, 0.0], [2.5, 0.5, 1.0], [5.0, 0.0, 1.5]],
                    widths: vec![2.0; 3],
                },
                Edge3d {
                    from: 0,
                    to: 0,
                    points: vec![
                        [0.0, 0.0, 0.0],
                        [1.0, 1.0, 0.0],
                        [0.0, 2.0, 0.0],
                        [0.0, 0.0, 0.0],
                    ],
                    widths: vec![2.0; 4],
                },
            ],
        }
    }

    #[test]
    fn ply_and_obj_list_every_point_and_segment() {
        let g = graph();
        g.validate().unwrap();
        let ply = to_ply(&g);
        assert!(ply.contains("element vertex 5\n"), "{ply}");
        assert!(ply.contains("element edge 5\n"), "{ply}");
        let body: Vec<&str> = ply.split("end_header\n").nth(1).unwrap().lines().collect();
        assert_eq!(body.len(), 10);
        assert_eq!(body[1], "5 0 1.5 2");
        assert_eq!(&body[5..], ["0 2", "2 1", "0 3", "3 4", "4 0"]);
        let obj = to_obj(&g);
        let lines: Vec<&str> = obj.lines().filter(|l| l.starts_with('l')).collect();
        assert_eq!(lines, ["l 1 3 2", "l 1 4 5 1"]);
        assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 5);
    }
}
