//! §3.2 Non-linear region identification: the node graph `H` and its clusters ("colors").
//!
//! `H` joins two nodes when their point sets touch. The paper tests shared k-nearest neighbours of
//! the associated points; on a pixel grid the same relation is "some 8-neighbour pixel pair has
//! owners i and j" (docs/design.md, adaptation 7), which is O(N) and needs no tree. For point lists
//! the neighbour graph of the [`PointSet`] is the k-nearest-neighbour graph, so the same rule *is*
//! the paper's.
//!
//! Clusters: the paper weights edges shorter than `1.5 r_min` with zero and groups nodes at equal
//! shortest distance from a root, i.e. nodes joined by zero-weight edges. Applied to all nodes that
//! chains whole thin strokes into one cluster, so only non-linear nodes are clustered (adaptation
//! 8).

use petgraph::algo::dijkstra;
use petgraph::graph::{NodeIndex, UnGraph};
use petgraph::unionfind::UnionFind;

use crate::geometry::floor_i64;
use crate::node_graph::{GraphNode, NodeGraph};
use crate::params::{ClusterRule, Params};
use crate::point_set::PointSet;
use crate::samples::Samples;

/// Builds `H` from the sampled nodes and colors its non-linear clusters.
pub fn build(points: &PointSet, samples: &Samples, params: &Params) -> NodeGraph {
    let nodes: Vec<GraphNode> = samples
        .nodes
        .iter()
        .map(|node| GraphNode {
            pos: node.pos,
            r_min: node.r_min,
            width: node.width,
            direction: node.direction,
            linear: node.linear,
            cluster: None,
            tip: node.tip,
        })
        .collect();
    let owner = &samples.owner;

    // An edge for every pair of owners that meet across a neighbour pair.
    let mut edges: Vec<[u32; 2]> = Vec::new();
    for p in 0..points.len() as u32 {
        let a = owner[p as usize];
        for &q in points.neighbors_of(p) {
            let b = owner[q as usize];
            // A cut between two parts meets many neighbour pairs in a row: the pair just
            // pushed is left out again here rather than sorted away below.
            let edge = [a.min(b), a.max(b)];
            if q > p && a != b && edges.last() != Some(&edge) {
                edges.push(edge);
            }
        }
        // Keep the buffer small on big pages: duplicates are dense along strokes.
        if edges.len() > 1 << 20 {
            edges.sort_unstable();
            edges.dedup();
        }
    }
    edges.sort_unstable();
    edges.dedup();

    let mut graph = NodeGraph {
        nodes,
        edges,
        owner: owner.clone(),
    };
    match params.method.cluster_rule {
        ClusterRule::EqualDistance => color_clusters_as_written(&mut graph, params),
        ClusterRule::NonLinear => color_clusters(&mut graph, points, params),
    }
    debug_assert_eq!(graph.validate(points.len()), Ok(()));
    graph
}

/// Union of non-linear nodes joined by edges shorter than `cluster_link · r_min` (with
/// [`ExperimentParams::site_clusters`](crate::ExperimentParams::site_clusters), only where the
/// segment between them stays on the ink); every non-linear node gets a cluster id (numbered in
/// node order), linear nodes none.
fn color_clusters(graph: &mut NodeGraph, points: &PointSet, params: &Params) {
    let n = graph.nodes.len();
    let mut union = UnionFind::<u32>::new(n);
    for &[a, b] in &graph.edges {
        let (na, nb) = (&graph.nodes[a as usize], &graph.nodes[b as usize]);
        if na.linear || nb.linear {
            continue;
        }
        let link = params.method.cluster_link * 0.5 * (na.r_min + nb.r_min);
        if crate::geometry::dist(na.pos, nb.pos) < link
            && (!params.experiments.site_clusters || segment_on_ink(points, na.pos, nb.pos))
        {
            union.union(a, b);
        }
    }
    let mut ids = vec![u32::MAX; n];
    let mut next = 0u32;
    for i in 0..n {
        if graph.nodes[i].linear {
            continue;
        }
        let root = union.find(i as u32) as usize;
        if ids[root] == u32::MAX {
            ids[root] = next;
            next += 1;
        }
        graph.nodes[i].cluster = Some(ids[root]);
    }
}

/// The paper's rule as written ([`ClusterRule::EqualDistance`]): edge weight 0 below `cluster_link
/// · r_min`, else the edge length; shortest distances from a root per component; nodes at equal
/// distance form one group. Groups of one node stay uncolored (a color on every node would forbid
/// all contraction).
fn color_clusters_as_written(graph: &mut NodeGraph, params: &Params) {
    let n = graph.nodes.len();
    let mut h: UnGraph<(), f64> = UnGraph::with_capacity(n, graph.edges.len());
    for _ in 0..n {
        h.add_node(());
    }
    for &[a, b] in &graph.edges {
        let (na, nb) = (&graph.nodes[a as usize], &graph.nodes[b as usize]);
        let length = crate::geometry::dist(na.pos, nb.pos);
        let weight = if length < params.method.cluster_link * 0.5 * (na.r_min + nb.r_min) {
            0.0
        } else {
            length
        };
        h.add_edge(
            NodeIndex::new(a as usize),
            NodeIndex::new(b as usize),
            weight,
        );
    }
    // (component, distance bits) -> group; roots in node order keep the result deterministic.
    let mut component = vec![u32::MAX; n];
    let mut distance = vec![0.0f64; n];
    for root in 0..n {
        if component[root] != u32::MAX {
            continue;
        }
        for (node, d) in dijkstra(&h, NodeIndex::new(root), None, |e| *e.weight()) {
            component[node.index()] = root as u32;
            distance[node.index()] = d;
        }
    }
    let mut keys: Vec<(u32, u64, usize)> = (0..n)
        .map(|i| (component[i], distance[i].to_bits(), i))
        .collect();
    keys.sort_unstable();
    let mut next = 0u32;
    let mut start = 0;
    while start < keys.len() {
        let mut end = start + 1;
        while end < keys.len() && keys[end].0 == keys[start].0 && keys[end].1 == keys[start].1 {
            end += 1;
        }
        if end - start >= 2 {
            for key in &keys[start..end] {
                graph.nodes[key.2].cluster = Some(next);
            }
            next += 1;
        }
        start = end;
    }
}

/// Whether the segment `a`-`b` lies on ink pixels (sampled every half pixel); true without a
/// pixel grid or in dropout mode. Two junction sites on either side of a cell, a counter or a gap between strokes
/// fail it: the segment between them crosses the paper.
fn segment_on_ink(points: &PointSet, a: [f64; 2], b: [f64; 2]) -> bool {
    let Some(grid) = &points.grid else {
        return true;
    };
    // Dropout ink is full of specks of paper: no test there.
    if points.dropout {
        return true;
    }
    let steps = (2.0 * crate::geometry::dist(a, b)).ceil().max(1.0) as usize;
    (0..=steps).all(|i| {
        let t = i as f64 / steps as f64;
        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        grid.point_at(floor_i64(p[0]), floor_i64(p[1])).is_some()
    })
}
