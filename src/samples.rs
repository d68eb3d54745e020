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
///
/// Invariants ([`Samples::validate`]): `owner` has one entry per point, each a valid node index,
/// and every node owns at least one point (no `P_i` is empty); positions, radii and widths are
/// finite.
#[derive(Clone, Debug, Default)]
pub struct Samples {
    /// The nodes in sampling order.
    pub nodes: Vec<Node>,
    /// Owner node of each point: `P_i = { p : owner[p] == i }` (a partition of `P`).
    pub owner: Vec<u32>,
}

impl Samples {
    /// Checks the invariants listed on the type for a point set of `points` points.
    pub fn validate(&self, points: usize) -> Result<(), String> {
        if self.owner.len() != points {
            return Err(format!("{} owners for {points} points", self.owner.len()));
        }
        let mut owned = vec![false; self.nodes.len()];
        for (p, &o) in self.owner.iter().enumerate() {
            match owned.get_mut(o as usize) {
                Some(slot) => *slot = true,
                None => return Err(format!("point {p} owned by missing node {o}")),
            }
        }
        if let Some(i) = owned.iter().position(|&o| !o) {
            return Err(format!("node {i} owns no point"));
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let values = [
                node.pos[0],
                node.pos[1],
                node.radius,
                node.r_min,
                node.width,
            ];
            if values.iter().any(|v| !v.is_finite()) {
                return Err(format!("node {i} is not finite: {node:?}"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(pos: [f64; 2]) -> Node {
        Node {
            pos,
            center: 0,
            radius: 3.0,
            r_min: 3.0,
            direction: [1.0, 0.0],
            linearity: 1.0,
            linear: true,
            width: 3.0,
            tip: false,
        }
    }

    #[test]
    fn validate_finds_each_broken_invariant() {
        let good = Samples {
            nodes: vec![node([1.0, 1.0]), node([5.0, 1.0])],
            owner: vec![0, 0, 1],
        };
        assert_eq!(good.validate(3), Ok(()));
        assert!(good.validate(4).is_err(), "an owner per point");
        let missing = Samples {
            owner: vec![0, 2, 1],
            ..good.clone()
        };
        assert!(missing.validate(3).is_err(), "owner out of range");
        let empty = Samples {
            owner: vec![0, 0, 0],
            ..good.clone()
        };
        assert!(empty.validate(3).is_err(), "a node with no point");
        let mut nan = good.clone();
        nan.nodes[1].pos[0] = f64::NAN;
        assert!(nan.validate(3).is_err(), "NaN position");
    }
}
