//! §3.4 first step: the refined 1-D graph cut into chains between vertices, each chain resampled
//! to equal node spacing ("splitting the relatively long edges and merging the relatively short
//! ones", docs/design.md, adaptation 12: spacing `h`).

use crate::csr::Csr;
use crate::geometry::{arc_lengths, point_at};
use crate::node_graph::NodeGraph;

/// One fitted edge: vertex `from` to vertex `to` through the contiguous interior unknowns
/// `interior.0..interior.1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayoutEdge {
    /// Start vertex.
    pub from: usize,
    /// End vertex (equal to `from` for a loop).
    pub to: usize,
    /// Range of interior unknowns, in order from `from` to `to`.
    pub interior: (u32, u32),
}

/// The equalized graph: one unknown per fitted node, numbered so that the least-squares solve
/// factors well (chain interiors first, chain by chain, then the vertices).
#[derive(Clone, Debug, Default)]
pub struct Layout {
    /// Initial position of each unknown.
    pub pos: Vec<[f64; 2]>,
    /// The old graph nodes each unknown was resampled between (equal for vertices): where its
    /// nearest point is looked for, and its fallback width.
    pub near: Vec<[u32; 2]>,
    /// Number of interior (chain) unknowns; vertex `k` is unknown `interior_count + k`.
    pub interior_count: usize,
    /// Old node of each vertex, in increasing node order.
    pub vertex_node: Vec<u32>,
    /// The edges, in the order the chains were found.
    pub edges: Vec<LayoutEdge>,
}

impl Layout {
    /// The unknown of vertex `k`.
    #[inline]
    pub fn vertex_unknown(&self, k: usize) -> u32 {
        (self.interior_count + k) as u32
    }

    /// The unknowns along an edge, vertex to vertex.
    pub fn polyline(&self, e: &LayoutEdge) -> Vec<u32> {
        let mut ids = Vec::with_capacity((e.interior.1 - e.interior.0) as usize + 2);
        ids.push(self.vertex_unknown(e.from));
        ids.extend(e.interior.0..e.interior.1);
        ids.push(self.vertex_unknown(e.to));
        ids
    }

    /// Number of edge ends at each vertex (a loop counts twice).
    pub fn degrees(&self) -> Vec<usize> {
        let mut degree = vec![0; self.vertex_node.len()];
        for e in &self.edges {
            degree[e.from] += 1;
            degree[e.to] += 1;
        }
        degree
    }
}

/// A path of old nodes between two vertices (both ends included).
struct Chain {
    from: usize,
    to: usize,
    nodes: Vec<u32>,
}

/// Cuts the graph into chains. Vertices are the nodes of degree other than 2, plus the lowest
/// node of every cycle made only of degree-2 nodes (a closed loop, like an 'o'); every vertex is
/// numbered in increasing node order and chains are found from vertices in that order. With
/// `collapse_dots`, an isolated chain shorter than its width becomes one lone vertex.
fn chains(graph: &NodeGraph, collapse_dots: bool) -> (Vec<u32>, Vec<Chain>) {
    let n = graph.nodes.len();
    // CSR adjacency with edge ids; malformed edges (self-loops, missing nodes) are skipped.
    let valid = |&&[a, b]: &&[u32; 2]| a != b && (a as usize) < n && (b as usize) < n;
    let mut adjacent = Csr::build(n, |sink| {
        for (e, &[a, b]) in graph.edges.iter().filter(valid).enumerate() {
            sink.push(a as usize, (b, e as u32));
            sink.push(b as usize, (a, e as u32));
        }
    });
    for i in 0..n {
        adjacent.row_mut(i).sort_unstable();
    }
    let around = |v: u32| adjacent.row(v as usize);
    let degree = |v: u32| adjacent.row(v as usize).len() as u32;

    let mut is_vertex: Vec<bool> = (0..n as u32).map(|v| degree(v) != 2).collect();
    let mut used = vec![false; adjacent.values.len() / 2];
    let mut on_chain = vec![false; n];
    type Found = Vec<(u32, u32, Vec<u32>)>;
    let mut found: Found = Vec::new();
    let walk = |start: u32,
                is_vertex: &[bool],
                used: &mut [bool],
                on_chain: &mut [bool],
                found: &mut Found| {
        for &(first, edge) in around(start) {
            if used[edge as usize] {
                continue;
            }
            used[edge as usize] = true;
            let mut nodes = vec![start];
            let (mut current, mut via) = (first, edge);
            while !is_vertex[current as usize] {
                nodes.push(current);
                on_chain[current as usize] = true;
                // A degree-2 node: leave by the edge we did not come in by.
                let Some(&(next, out)) = around(current).iter().find(|&&(_, e)| e != via) else {
                    break;
                };
                used[out as usize] = true;
                current = next;
                via = out;
            }
            nodes.push(current);
            found.push((start, current, nodes));
        }
    };
    for v in 0..n as u32 {
        if is_vertex[v as usize] {
            walk(v, &is_vertex, &mut used, &mut on_chain, &mut found);
        }
    }
    if collapse_dots {
        // A component that is one chain shorter than its stroke is wide is a dot, not a dash:
        // keep its first end as a lone vertex (its points still reach it) and drop the rest.
        found.retain(|(a, b, nodes)| {
            let dot = a != b && degree(*a) == 1 && degree(*b) == 1 && {
                let length: f64 = nodes
                    .windows(2)
                    .map(|w| {
                        crate::geometry::dist(
                            graph.nodes[w[0] as usize].pos,
                            graph.nodes[w[1] as usize].pos,
                        )
                    })
                    .sum();
                let width = nodes
                    .iter()
                    .map(|&v| graph.nodes[v as usize].width)
                    .fold(0.0, f64::max);
                length < 0.5 * width
            };
            if dot {
                is_vertex[*b as usize] = false;
                on_chain[*b as usize] = true;
            }
            !dot
        });
    }
    // What is left of the degree-2 nodes are closed loops: anchor each at its lowest node.
    for v in 0..n as u32 {
        if !is_vertex[v as usize] && !on_chain[v as usize] {
            is_vertex[v as usize] = true;
            walk(v, &is_vertex, &mut used, &mut on_chain, &mut found);
        }
    }
    let vertex_node: Vec<u32> = (0..n as u32).filter(|&v| is_vertex[v as usize]).collect();
    let mut index = vec![usize::MAX; n];
    for (k, &v) in vertex_node.iter().enumerate() {
        index[v as usize] = k;
    }
    let chains = found
        .into_iter()
        .filter(|(a, b, _)| index[*a as usize] != usize::MAX && index[*b as usize] != usize::MAX)
        .map(|(a, b, nodes)| Chain {
            from: index[a as usize],
            to: index[b as usize],
            nodes,
        })
        .collect();
    (vertex_node, chains)
}

/// Most segments per link of a chain (hostile input, docs/bad-input.md; see `equalize`).
const MAX_SEGMENTS_PER_LINK: usize = 256;

/// Decomposes the graph into chains and resamples each to spacing `h`. A chain keeps at least its
/// two end vertices; a loop keeps at least two interior nodes, and chains sharing both vertices
/// with another keep at least one, so that no two edges collapse onto the same segment.
pub fn equalize(graph: &NodeGraph, h: f64, collapse_dots: bool) -> Layout {
    let (vertex_node, chains) = chains(graph, collapse_dots);
    let mut pairs: Vec<(usize, usize)> = chains
        .iter()
        .map(|c| (c.from.min(c.to), c.from.max(c.to)))
        .collect();
    pairs.sort_unstable();
    let parallel = |c: &Chain| {
        let key = (c.from.min(c.to), c.from.max(c.to));
        pairs.partition_point(|&p| p <= key) - pairs.partition_point(|&p| p < key) > 1
    };
    let mut layout = Layout {
        vertex_node,
        ..Layout::default()
    };
    let mut polyline: Vec<[f64; 2]> = Vec::new();
    for chain in &chains {
        polyline.clear();
        polyline.extend(chain.nodes.iter().map(|&v| graph.nodes[v as usize].pos));
        let s = arc_lengths(&polyline);
        let length = s.last().copied().unwrap_or(0.0);
        let least = if chain.from == chain.to {
            3
        } else if parallel(chain) {
            2
        } else {
            1
        };
        // hostile input (found by fuzzing): a chain may span a gap far longer than its ink
        // (five points 1e9 units apart made 2.5 million fitted nodes, 18 s and gigabytes). At most
        // MAX_SEGMENTS_PER_LINK per link between refined nodes keeps the layout a multiple of the
        // node count; on images a link that long (768 px at h = 3) needs a blob far wider than
        // any stroke.
        let cap = MAX_SEGMENTS_PER_LINK.saturating_mul(chain.nodes.len().saturating_sub(1));
        let segments = ((length / h).round().min(cap as f64) as usize).max(least);
        let start = layout.pos.len() as u32;
        for j in 1..segments {
            let (p, k) = point_at(&polyline, &s, length * j as f64 / segments as f64);
            layout.pos.push(p);
            layout.near.push([
                chain.nodes[k],
                chain.nodes[(k + 1).min(chain.nodes.len() - 1)],
            ]);
        }
        let end = layout.pos.len() as u32;
        layout.edges.push(LayoutEdge {
            from: chain.from,
            to: chain.to,
            interior: (start, end),
        });
    }
    layout.interior_count = layout.pos.len();
    for &v in &layout.vertex_node {
        layout.pos.push(graph.nodes[v as usize].pos);
        layout.near.push([v, v]);
    }
    layout
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::node_graph::GraphNode;

    fn graph(positions: &[[f64; 2]], edges: &[[u32; 2]]) -> NodeGraph {
        let node = |pos| GraphNode {
            pos,
            r_min: 3.0,
            width: 3.0,
            direction: [1.0, 0.0],
            linear: true,
            cluster: None,
            tip: false,
        };
        let mut edges = edges.to_vec();
        edges.sort_unstable();
        NodeGraph {
            nodes: positions.iter().map(|&p| node(p)).collect(),
            edges,
            owner: Vec::new(),
        }
    }

    #[test]
    fn chains_run_between_vertices_and_loops_get_one_vertex() {
        // A T (junction 1 with arms to 0, 3 and via 2 to 4), a square loop 5-6-7-8, a lone node 9.
        let positions = [
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [20.0, 0.0],
            [10.0, 20.0],
            [50.0, 50.0],
            [60.0, 50.0],
            [60.0, 60.0],
            [50.0, 60.0],
            [90.0, 90.0],
        ];
        let g = graph(
            &positions,
            &[
                [0, 1],
                [1, 2],
                [1, 3],
                [2, 4],
                [5, 6],
                [6, 7],
                [7, 8],
                [5, 8],
            ],
        );
        let layout = equalize(&g, 5.0, true);
        assert_eq!(layout.vertex_node, vec![0, 1, 3, 4, 5, 9]);
        assert_eq!(layout.degrees(), vec![1, 3, 1, 1, 2, 0]);
        let loops: Vec<_> = layout.edges.iter().filter(|e| e.from == e.to).collect();
        assert_eq!(loops.len(), 1);
        // The 40 px loop at spacing 5 has 8 segments; the 20 px arm to node 4 has 4.
        assert_eq!(loops[0].interior.1 - loops[0].interior.0, 7);
        let stem = layout.edges.iter().find(|e| e.to == 3).unwrap();
        assert_eq!(stem.interior.1 - stem.interior.0, 3);
        for e in &layout.edges {
            let ids = layout.polyline(e);
            for w in ids.windows(2) {
                let d = crate::geometry::dist(layout.pos[w[0] as usize], layout.pos[w[1] as usize]);
                assert!((d - 5.0).abs() < 1e-9, "spacing {d}");
            }
        }
    }
}
