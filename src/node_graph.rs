//! A graph on nodes: §3.2's graph `H` with its clusters, and after §3.3 the 1-D curve graph.

/// A node of the graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GraphNode {
    /// Position.
    pub pos: [f64; 2],
    /// `r_min` at this node (px).
    pub r_min: f64,
    /// Local stroke width (px).
    pub width: f64,
    /// Principal direction (unit vector).
    pub direction: [f64; 2],
    /// Whether the node was sampled in a linear region.
    pub linear: bool,
    /// The non-linear cluster ("color") the node belongs to, if any.
    pub cluster: Option<u32>,
    /// Whether the node holds a stroke end (see [`crate::Node::tip`]).
    pub tip: bool,
}

/// An undirected graph on [`GraphNode`]s with the point partition.
///
/// Invariants: edges join distinct existing nodes, each unordered pair at most once; `owner` has one
/// entry per point of the [`crate::PointSet`], each a valid node index.
#[derive(Clone, Debug, Default)]
pub struct NodeGraph {
    /// The nodes.
    pub nodes: Vec<GraphNode>,
    /// Undirected edges `[a, b]` with `a < b`, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Owner node of each point.
    pub owner: Vec<u32>,
}

impl NodeGraph {
    /// Adjacency lists (sorted) built from [`NodeGraph::edges`].
    pub(crate) fn adjacency(&self) -> Vec<Vec<u32>> {
        let mut adj = vec![Vec::new(); self.nodes.len()];
        for &[a, b] in &self.edges {
            adj[a as usize].push(b);
            adj[b as usize].push(a);
        }
        for list in &mut adj {
            list.sort_unstable();
        }
        adj
    }

    /// Checks the invariants listed on the type.
    pub fn validate(&self, points: usize) -> Result<(), String> {
        let n = self.nodes.len() as u32;
        for w in self.edges.windows(2) {
            if w[0] >= w[1] {
                return Err(format!("edges not sorted/unique at {:?}", w[1]));
            }
        }
        for &[a, b] in &self.edges {
            if a >= b || b >= n {
                return Err(format!("bad edge {a}-{b}"));
            }
        }
        if self.owner.len() != points {
            return Err(format!("{} owners for {} points", self.owner.len(), points));
        }
        if let Some(p) = self.owner.iter().position(|&o| o >= n) {
            return Err(format!("point {p} owned by missing node"));
        }
        Ok(())
    }
}
