//! Output of §3.1: the sampled nodes `Q`, each with its disk, and the partition of `P` into the
//! associated point sets `P_i`.

/// One sampled node `q_i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// The node: barycenter of its associated points `P_i`.
    pub pos: [f64; 2],
    /// The sampling center (a point of `P`) the disk was grown around.
    pub center: u32,
    /// Final disk radius `r_i`.
    pub radius: f64,
    /// `r_min` used for this node (it follows the local stroke width).
    pub r_min: f64,
    /// Principal direction of the disk (unit vector), the `v_2` of Eq. (3).
    pub direction: [f64; 2],
    /// Linearity `l(S)` of Eq. (3) on the final disk.
    pub linearity: f64,
    /// False when the node sits in a non-linear region (crossing, junction, sharp bend, end).
    pub linear: bool,
    /// Local stroke width `w_loc` around the node, in px.
    pub width: f64,
    /// Whether the node's disk holds a stroke end (its rim cuts the ink once).
    pub tip: bool,
}

/// The nodes and which node owns each point.
#[derive(Clone, Debug, Default)]
pub struct Samples {
    /// The nodes in sampling order.
    pub nodes: Vec<Node>,
    /// Owner node of each point: `P_i = { p : owner[p] == i }` (a partition of `P`).
    pub owner: Vec<u32>,
}
