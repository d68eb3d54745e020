//! §3.1 in space: anisotropic adaptive sampling with balls. From each center the ball grows from
//! `r_min` by the growth factor until its points are linear by Eq. (3) (three axes) or it reaches
//! `r_max`, where the node is non-linear and keeps `r_min`; the next center is the point farthest
//! from the nodes by Eq. (1). As in the plane (docs/design.md, adaptations 3, 4 and 6): `r_min`
//! follows the local tube diameter, a ball holds only the points joined to its center by
//! neighbour paths inside it, and each point belongs to the first node whose ball covers it, so
//! the `P_i` partition `P`.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::math::{add, dist2, dot, eigen, linearity, scale, sub, Moments, V3};
use super::points::Cloud;
use crate::params::{Params, RMinRule};

/// A sampled node `q_i`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    /// Barycenter of its points `P_i`.
    pub pos: V3,
    pub r_min: f64,
    pub linear: bool,
    /// Local tube diameter at the center.
    pub width: f64,
}

/// The nodes and the owner of each point.
pub(super) struct Sampled {
    pub nodes: Vec<Node>,
    pub owner: Vec<u32>,
}

/// Order key of a non-negative distance (bit order equals numeric order for non-negative floats).
fn key(d: f64) -> u64 {
    d.max(0.0).to_bits()
}

pub(super) fn sample(cloud: &Cloud, params: &Params) -> Sampled {
    let n = cloud.len();
    let method = &params.method;
    let mut owner = vec![u32::MAX; n];
    let mut best = vec![f64::INFINITY; n];
    let mut frontier: BinaryHeap<(u64, Reverse<u32>)> = BinaryHeap::new();
    let mut nodes: Vec<Node> = Vec::new();
    // Restarts go to the uncovered point lowest in (x, y, z): an extremity of its part, whatever
    // the input order.
    let mut by_position: Vec<u32> = (0..n as u32).collect();
    by_position.sort_by(|&a, &b| {
        let (p, q) = (cloud.points[a as usize], cloud.points[b as usize]);
        p[0].total_cmp(&q[0])
            .then(p[1].total_cmp(&q[1]))
            .then(p[2].total_cmp(&q[2]))
            .then(a.cmp(&b))
    });
    let mut cursor = 0usize;
    // Search state reused across balls: a stamp per point marks the current search.
    let mut stamp = vec![u32::MAX; n];
    let mut reach = vec![0.0f64; n];
    let mut done = vec![u32::MAX; n];
    let mut order: Vec<(f64, u32)> = Vec::new();
    let mut prefix: Vec<Moments> = Vec::new();
    loop {
        let center = loop {
            match frontier.pop() {
                Some((d, Reverse(p))) => {
                    if d != key(best[p as usize]) {
                        continue;
                    }
                    if cloud
                        .neighbors_of(p)
                        .iter()
                        .any(|&q| owner[q as usize] == u32::MAX)
                    {
                        break Some(p);
                    }
                }
                None => {
                    while cursor < n && owner[by_position[cursor] as usize] != u32::MAX {
                        cursor += 1;
                    }
                    break by_position.get(cursor).copied();
                }
            }
        };
        let Some(center) = center else { break };
        let id = nodes.len() as u32;
        let c = cloud.points[center as usize];
        let width = cloud.width[center as usize];
        let r_min = match method.r_min_rule {
            RMinRule::StrokeWidth => (3.0 * cloud.spacing).max(method.r_min_factor * width),
            RMinRule::Spacing => method.r_min_factor * cloud.spacing,
        };
        let r_max = method.r_max_factor * r_min;
        // Bottleneck search (adaptation 4): a point's reach is the largest distance to the
        // center along its best neighbour path; the ball of radius r is the prefix of `order`
        // with reach at most r.
        order.clear();
        let mut heap: BinaryHeap<Reverse<(u64, u32)>> = BinaryHeap::new();
        stamp[center as usize] = id;
        reach[center as usize] = 0.0;
        heap.push(Reverse((key(0.0), center)));
        let r_max2 = r_max * r_max;
        while let Some(Reverse((k, p))) = heap.pop() {
            let here = reach[p as usize];
            if done[p as usize] == id || k != key(here) {
                continue;
            }
            done[p as usize] = id;
            order.push((here, p));
            for &q in cloud.neighbors_of(p) {
                if done[q as usize] == id {
                    continue;
                }
                let d2 = dist2(cloud.points[q as usize], c);
                if d2 > r_max2 {
                    continue;
                }
                let r = here.max(d2.sqrt());
                if stamp[q as usize] != id || r < reach[q as usize] {
                    stamp[q as usize] = id;
                    reach[q as usize] = r;
                    heap.push(Reverse((key(r), q)));
                }
            }
        }
        let order_list = &order;
        prefix.clear();
        let mut m = Moments::default();
        for &(_, p) in order_list.iter() {
            m.add(sub(cloud.points[p as usize], c));
            prefix.push(m);
        }
        let count_within = |r: f64| order_list.partition_point(|&(reach, _)| reach <= r);
        // Grow the ball until linear (Eq. (3)) or past r_max.
        let mut r = r_min;
        let mut chosen: Option<(f64, V3, f64)> = None;
        let mut last_axes = (
            [0.0; 3],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        );
        while r <= r_max * (1.0 + 1e-12) {
            let count = count_within(r);
            if count >= 3 {
                let (values, vectors) = eigen(prefix[count - 1].covariance());
                let l = linearity(values);
                last_axes = (values, vectors);
                if l > method.linearity {
                    chosen = Some((r, vectors[2], l));
                    break;
                }
            }
            r *= method.r_growth;
        }
        let (radius, linear) = match chosen {
            Some((radius, _, _)) => (radius, true),
            None => (r_min, false),
        };
        let count = count_within(radius).max(1);
        let axes = if count >= 3 {
            eigen(prefix[count - 1].covariance())
        } else {
            last_axes
        };
        let ball = &order_list[..count];
        // The node owns the points of its ball no earlier node covered.
        let mut sum = [0.0; 3];
        let mut owned = 0usize;
        for &(_, p) in ball {
            if owner[p as usize] == u32::MAX {
                owner[p as usize] = id;
                sum = add(sum, cloud.points[p as usize]);
                owned += 1;
            }
        }
        if owned == 0 {
            // The center's uncovered neighbours lie beyond the ball: the node takes them, so
            // every node owns a point and sampling always advances.
            for &q in cloud.neighbors_of(center) {
                if owner[q as usize] == u32::MAX {
                    owner[q as usize] = id;
                    sum = add(sum, cloud.points[q as usize]);
                    owned += 1;
                }
            }
            if owner[center as usize] == u32::MAX {
                owner[center as usize] = id;
                sum = add(sum, c);
                owned += 1;
            }
        }
        let pos = scale(sum, 1.0 / owned.max(1) as f64);
        let (_, vectors) = axes;
        // Eq. (1) with the node as origin and the ball's three principal axes: far along the
        // first axis first; r_2, r_3 the offsets along the other two.
        for &(_, p) in ball {
            let d = sub(cloud.points[p as usize], pos);
            let along = dot(d, vectors[2]).abs();
            let r2 = dot(d, vectors[1]).abs();
            let r3 = dot(d, vectors[0]).abs();
            let value = along + 0.1 / (1.0 + r2) + 0.1 / (1.0 + r3);
            if value < best[p as usize] {
                best[p as usize] = value;
                frontier.push((key(value), Reverse(p)));
            }
        }
        nodes.push(Node {
            pos,
            r_min,
            linear,
            width,
        });
    }
    Sampled { nodes, owner }
}
