//! §3.3 Edge refinement: turn the node graph `H` into a 1-D curve graph.
//!
//! - **Contraction** (as in the paper): repeatedly collapse the shortest, lowest-degree edge that
//!   lies on a triangle into its midpoint, never joining two different clusters, until no triangle
//!   is left.
//! - **Merging**: the nodes of degree > 2 of one cluster become one node. The paper merges the
//!   whole cluster; one cluster once spanned a handwritten word and became one star vertex, so they
//!   are merged in groups whose members are all within `merge_span · r_min` of each other
//!   (docs/design.md, adaptation 9).
//! - **Clean-up** (the paper's "restructuring operators", adaptations 10 and 11), repeated until
//!   stable: contract cycles that enclose no background hole; prune terminal branches shorter than
//!   the stroke width; collapse junction-junction bars shorter than the stroke width; merge two Y's
//!   joined by a short bar whose outer arms pair up anti-parallel into one crossing.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::csr::Csr;
use crate::geometry::{dist, floor_i64, hypot, point_in_polygon, TotalF64};
use crate::node_graph::{GraphNode, NodeGraph};
use crate::params::Params;
use crate::point_set::{on_lattice, PointSet};

/// Refines `H` into a 1-D graph (no triangles; one vertex per crossing). `components` are the
/// points' [`PointSet::component_labels`] when they are known (found here otherwise, and when
/// their length is not the points').
pub fn refine(
    graph: &NodeGraph,
    points: &PointSet,
    params: &Params,
    components: Option<&[u32]>,
) -> NodeGraph {
    // Holes guide contraction, merging and clean-up; without clean-up (the paper's rules) they are
    // unknown.
    let holes = if params.finish.cleanup {
        Holes::find(points, graph, components)
    } else {
        Holes::Unknown
    };
    let mut work = Work::new(graph, holes);
    work.contract_triangles();
    debug_assert_eq!(work.contractible_triangle_edge(), None);
    let holes = work.holes.clone();
    work.merge_clusters(params.method.merge_span, &holes);
    // Scattered points (a point list off any lattice) place a Y-bar-Y's crossing where its
    // strokes cross (see `Work::merge_y_bar_y`); images and lattice points keep their rule.
    let scattered = points.grid.is_none() && !on_lattice(&points.points, points.spacing);
    if params.finish.cleanup {
        for _ in 0..8 {
            let mut changed = work.contract_hole_free_cycles(&holes);
            changed |= work.prune_spurs(points);
            changed |= work.collapse_short_bars();
            changed |= work.merge_y_bar_y(scattered);
            if !changed {
                break;
            }
        }
    }
    let refined = work.finish(&graph.owner);
    debug_assert_eq!(refined.validate(points.len()), Ok(()));
    refined
}

/// The graph being rewritten: adjacency sets, merge forest for re-owning points.
struct Work {
    nodes: Vec<GraphNode>,
    /// How many original nodes each node stands for (weights merged positions).
    mass: Vec<f64>,
    adj: Vec<Vec<u32>>,
    alive: Vec<bool>,
    /// Merge forest: `parent[i] == i` for live nodes.
    parent: Vec<u32>,
    /// Background holes of the ink (unknown without clean-up).
    holes: Holes,
}

impl Work {
    fn new(graph: &NodeGraph, holes: Holes) -> Self {
        let n = graph.nodes.len();
        Work {
            nodes: graph.nodes.clone(),
            mass: vec![1.0; n],
            adj: graph.adjacency(),
            alive: vec![true; n],
            parent: (0..n as u32).collect(),
            holes,
        }
    }

    fn degree(&self, a: u32) -> usize {
        self.adj[a as usize].len()
    }

    fn len(&self, a: u32, b: u32) -> f64 {
        dist(self.nodes[a as usize].pos, self.nodes[b as usize].pos)
    }

    fn adjacent(&self, a: u32, b: u32) -> bool {
        self.adj[a as usize].binary_search(&b).is_ok()
    }

    fn in_triangle(&self, a: u32, b: u32) -> bool {
        let (la, lb) = (&self.adj[a as usize], &self.adj[b as usize]);
        let (mut i, mut j) = (0, 0);
        while i < la.len() && j < lb.len() {
            match la[i].cmp(&lb[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    // A triangle around a background hole is a real (small) loop, not a
                    // thick-region artifact: it must survive contraction.
                    let c = la[i];
                    let triangle = [
                        self.nodes[a as usize].pos,
                        self.nodes[b as usize].pos,
                        self.nodes[c as usize].pos,
                    ];
                    if !self.holes.encloses_known(&triangle, a) {
                        return true;
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        false
    }

    /// Merges `b` into `a`, placing the result at `pos`. Returns `a`.
    fn merge(&mut self, a: u32, b: u32, pos: [f64; 2]) -> u32 {
        debug_assert!(a != b && self.alive[a as usize] && self.alive[b as usize]);
        let (ai, bi) = (a as usize, b as usize);
        let neighbours = std::mem::take(&mut self.adj[bi]);
        for &x in &neighbours {
            let list = &mut self.adj[x as usize];
            if let Ok(k) = list.binary_search(&b) {
                list.remove(k);
            }
            if x != a {
                if let Err(k) = list.binary_search(&a) {
                    list.insert(k, a);
                }
                if let Err(k) = self.adj[ai].binary_search(&x) {
                    self.adj[ai].insert(k, x);
                }
            }
        }
        if let Ok(k) = self.adj[ai].binary_search(&b) {
            self.adj[ai].remove(k);
        }
        let (na, nb) = (self.nodes[ai], self.nodes[bi]);
        let (ma, mb) = (self.mass[ai], self.mass[bi]);
        let node = &mut self.nodes[ai];
        node.pos = pos;
        node.r_min = na.r_min.max(nb.r_min);
        node.width = (na.width * ma + nb.width * mb) / (ma + mb);
        node.linear = na.linear && nb.linear;
        node.cluster = na.cluster.or(nb.cluster);
        node.tip = na.tip && nb.tip;
        self.mass[ai] = ma + mb;
        self.alive[bi] = false;
        self.parent[bi] = a;
        a
    }

    /// Merges a set of live nodes into its lowest index at `pos`.
    fn merge_all(&mut self, group: &[u32], pos: [f64; 2]) -> u32 {
        let mut sorted = group.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        let target = sorted[0];
        for &b in &sorted[1..] {
            self.merge(target, b, pos);
        }
        self.nodes[target as usize].pos = pos;
        target
    }

    fn centroid(&self, group: &[u32]) -> [f64; 2] {
        let mut sum = [0.0, 0.0];
        let mut mass = 0.0;
        for &i in group {
            let m = self.mass[i as usize];
            sum[0] += self.nodes[i as usize].pos[0] * m;
            sum[1] += self.nodes[i as usize].pos[1] * m;
            mass += m;
        }
        [sum[0] / mass, sum[1] / mass]
    }

    /// Contraction operator: collapse the shortest, lowest-degree triangle edge until no triangle
    /// is left (edges joining two different clusters are never collapsed).
    fn contract_triangles(&mut self) {
        let mut heap: BinaryHeap<Reverse<(TotalF64, usize, u32, u32)>> = BinaryHeap::new();
        for a in 0..self.nodes.len() as u32 {
            for &b in &self.adj[a as usize] {
                if a < b && self.in_triangle(a, b) {
                    heap.push(Reverse(self.edge_key(a, b)));
                }
            }
        }
        while let Some(Reverse((TotalF64(length), degree, a, b))) = heap.pop() {
            if !(self.alive[a as usize] && self.alive[b as usize] && self.adjacent(a, b)) {
                continue;
            }
            if !self.in_triangle(a, b) {
                continue;
            }
            let (ca, cb) = (
                self.nodes[a as usize].cluster,
                self.nodes[b as usize].cluster,
            );
            if matches!((ca, cb), (Some(x), Some(y)) if x != y) {
                continue;
            }
            let key = self.edge_key(a, b);
            if key.0 .0 != length || key.1 != degree {
                heap.push(Reverse(key));
                continue;
            }
            let (pa, pb) = (self.nodes[a as usize].pos, self.nodes[b as usize].pos);
            let mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
            let m = self.merge(a, b, mid);
            // New triangle edges can only involve the merged node and its neighbours.
            let around = self.adj[m as usize].clone();
            for &x in &around {
                if self.in_triangle(m, x) {
                    heap.push(Reverse(self.edge_key(m.min(x), m.max(x))));
                }
                for &y in &self.adj[x as usize] {
                    if y > x && y != m && self.adjacent(m, y) {
                        heap.push(Reverse(self.edge_key(x, y)));
                    }
                }
            }
        }
    }

    /// An edge that contraction should have collapsed: on a triangle that encloses no known hole,
    /// between nodes of one cluster (or unclustered ones). None after [`Work::contract_triangles`]:
    /// what triangles remain go around a hole or have every edge between two clusters.
    fn contractible_triangle_edge(&self) -> Option<(u32, u32)> {
        (0..self.nodes.len() as u32)
            .filter(|&a| self.alive[a as usize])
            .flat_map(|a| self.adj[a as usize].iter().map(move |&b| (a, b)))
            .find(|&(a, b)| {
                let (ca, cb) = (
                    self.nodes[a as usize].cluster,
                    self.nodes[b as usize].cluster,
                );
                a < b && !matches!((ca, cb), (Some(x), Some(y)) if x != y) && self.in_triangle(a, b)
            })
    }

    fn edge_key(&self, a: u32, b: u32) -> (TotalF64, usize, u32, u32) {
        (
            TotalF64(self.len(a, b)),
            self.degree(a).min(self.degree(b)),
            a,
            b,
        )
    }

    /// Merging operator with complete-linkage groups (adaptation 9).
    fn merge_clusters(&mut self, span: f64, holes: &Holes) {
        let mut members: Vec<Vec<u32>> = Vec::new();
        for i in 0..self.nodes.len() as u32 {
            if !self.alive[i as usize] || self.degree(i) <= 2 {
                continue;
            }
            if let Some(c) = self.nodes[i as usize].cluster {
                let c = c as usize;
                if members.len() <= c {
                    members.resize(c + 1, Vec::new());
                }
                members[c].push(i);
            }
        }
        for (cluster, list) in members.iter().enumerate() {
            if list.len() < 2 {
                continue;
            }
            for group in complete_linkage(list, |a, b| {
                let limit = span
                    * self.nodes[a as usize]
                        .r_min
                        .max(self.nodes[b as usize].r_min);
                // Two junctions on either side of a background hole are two junctions (the
                // crossings of a small '#'), however close: merging them would erase the hole.
                self.len(a, b) <= limit
                    && !holes.near_segment(
                        self.nodes[a as usize].pos,
                        self.nodes[b as usize].pos,
                        a,
                    )
            }) {
                // hostile input (found by fuzzing): `absorb_dangling` after an earlier group
                // of this cluster may already have merged members of this one (they dropped to
                // degree 1 or 2); merging a dead node again tripped `merge`'s assertion (and in
                // release counted its mass twice). Only the live members are merged.
                let group: Vec<u32> = group
                    .into_iter()
                    .filter(|&i| self.alive[i as usize])
                    .collect();
                if group.len() < 2 || self.merge_loses_hole(&group, holes) {
                    continue;
                }
                let pos = self.centroid(&group);
                let m = self.merge_all(&group, pos);
                self.absorb_dangling(m, cluster as u32);
            }
        }
    }

    /// Whether merging `group` would erase a cycle around a background hole: two members with a
    /// common neighbour `x` lose the cycle `a - x - b - (path back to a)`, which is a real loop
    /// when it encloses a hole (two crossings of a small '#' on either side of its hole).
    fn merge_loses_hole(&self, group: &[u32], holes: &Holes) -> bool {
        if !matches!(holes, Holes::Known { .. }) {
            return false;
        }
        for (i, &a) in group.iter().enumerate() {
            for &b in &group[i + 1..] {
                for &x in &self.adj[a as usize] {
                    if group.contains(&x) || !self.adjacent(b, x) {
                        continue;
                    }
                    let mut polygon = vec![self.nodes[a as usize].pos, self.nodes[x as usize].pos];
                    let reach = 20.0 * self.nodes[a as usize].width.max(3.0);
                    if let Some(path) = self.shortest_path(b, a, reach, |_, y| y == x) {
                        polygon.extend(path.iter().map(|&k| self.nodes[k as usize].pos));
                    } else {
                        polygon.push(self.nodes[b as usize].pos);
                    }
                    if holes.encloses(&polygon, a) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Shortest path from `from` to `to` (both included, in that order) no longer than `limit`,
    /// over the edges `x -> y` for which `skip(x, y)` is false (Dijkstra on edge lengths).
    fn shortest_path(
        &self,
        from: u32,
        to: u32,
        limit: f64,
        skip: impl Fn(u32, u32) -> bool,
    ) -> Option<Vec<u32>> {
        let mut best: std::collections::HashMap<u32, (f64, u32)> = std::collections::HashMap::new();
        let mut heap = BinaryHeap::new();
        best.insert(from, (0.0, from));
        heap.push(Reverse((TotalF64(0.0), from)));
        while let Some(Reverse((TotalF64(d), x))) = heap.pop() {
            if best.get(&x).is_some_and(|&(bd, _)| bd < d) {
                continue;
            }
            if x == to {
                let mut path = vec![to];
                let mut cur = to;
                while cur != from {
                    cur = best[&cur].1;
                    path.push(cur);
                }
                path.reverse();
                return Some(path);
            }
            for &y in &self.adj[x as usize] {
                if skip(x, y) {
                    continue;
                }
                let nd = d + self.len(x, y);
                if nd <= limit && best.get(&y).is_none_or(|&(bd, _)| nd < bd) {
                    best.insert(y, (nd, x));
                    heap.push(Reverse((TotalF64(nd), y)));
                }
            }
        }
        None
    }

    /// After a merge, nodes of the same cluster hanging off the merged node alone (left over from
    /// the paths between the merged members) join it.
    fn absorb_dangling(&mut self, m: u32, cluster: u32) {
        loop {
            let dangling: Vec<u32> = self.adj[m as usize]
                .iter()
                .copied()
                .filter(|&x| {
                    self.nodes[x as usize].cluster == Some(cluster)
                        && (self.degree(x) == 1 || (self.degree(x) == 2 && self.in_triangle(m, x)))
                })
                .collect();
            if dangling.is_empty() {
                return;
            }
            let pos = self.nodes[m as usize].pos;
            for x in dangling {
                if self.alive[x as usize] {
                    self.merge(m, x, pos);
                }
            }
        }
    }

    /// Live nodes in index order.
    fn live(&self) -> Vec<u32> {
        (0..self.nodes.len() as u32)
            .filter(|&i| self.alive[i as usize])
            .collect()
    }

    /// Clean-up 1: a cycle that encloses no background hole is an artifact of sampling a thick
    /// region; small ones collapse to a point, long ones lose their longest edge.
    fn contract_hole_free_cycles(&mut self, holes: &Holes) -> bool {
        let mut changed = false;
        for (a, b) in self.non_tree_edges() {
            if !(self.alive[a as usize] && self.alive[b as usize] && self.adjacent(a, b)) {
                continue;
            }
            let reach = 20.0
                * self.nodes[a as usize]
                    .width
                    .max(self.nodes[b as usize].width)
                    .max(3.0);
            let Some(mut cycle) = self.shortest_path(a, b, reach, |x, y| x == a && y == b) else {
                continue;
            };
            // Walked from `b` back to `a` (the order the perimeter has always been summed in).
            cycle.reverse();
            let polygon: Vec<[f64; 2]> =
                cycle.iter().map(|&i| self.nodes[i as usize].pos).collect();
            let perimeter: f64 = (0..polygon.len())
                .map(|i| dist(polygon[i], polygon[(i + 1) % polygon.len()]))
                .sum();
            let width = cycle
                .iter()
                .map(|&i| self.nodes[i as usize].width)
                .fold(0.0, f64::max);
            let hole_free = match holes {
                Holes::Known { .. } => !holes.encloses(&polygon, a),
                // Without a pixel grid there is no hole map: only a cycle too small to go around
                // any background is taken as an artifact.
                Holes::Unknown => perimeter < std::f64::consts::PI * width,
            };
            if !hole_free {
                continue;
            }
            if perimeter <= 3.0 * width.max(3.0) {
                let pos = self.centroid(&cycle);
                self.merge_all(&cycle, pos);
            } else {
                let mut longest = (0.0, cycle[0], cycle[1]);
                for i in 0..cycle.len() {
                    let (x, y) = (cycle[i], cycle[(i + 1) % cycle.len()]);
                    let l = self.len(x, y);
                    if l > longest.0 {
                        longest = (l, x, y);
                    }
                }
                self.remove_edge(longest.1, longest.2);
            }
            changed = true;
        }
        changed
    }

    fn remove_edge(&mut self, a: u32, b: u32) {
        if let Ok(k) = self.adj[a as usize].binary_search(&b) {
            self.adj[a as usize].remove(k);
        }
        if let Ok(k) = self.adj[b as usize].binary_search(&a) {
            self.adj[b as usize].remove(k);
        }
    }

    /// Edges outside a breadth-first spanning forest: each closes one independent cycle.
    fn non_tree_edges(&self) -> Vec<(u32, u32)> {
        let n = self.nodes.len();
        let mut visited = vec![false; n];
        let mut tree_parent = vec![u32::MAX; n];
        let mut extra = Vec::new();
        let mut queue = std::collections::VecDeque::new();
        for root in self.live() {
            if visited[root as usize] {
                continue;
            }
            visited[root as usize] = true;
            queue.push_back(root);
            while let Some(x) = queue.pop_front() {
                for &y in &self.adj[x as usize] {
                    if !visited[y as usize] {
                        visited[y as usize] = true;
                        tree_parent[y as usize] = x;
                        queue.push_back(y);
                    } else if y > x && tree_parent[x as usize] != y && tree_parent[y as usize] != x
                    {
                        extra.push((x, y));
                    }
                }
            }
        }
        extra
    }

    /// Walks from `start` (coming from `prev`) along degree-2 nodes; returns the nodes passed
    /// (excluding `start`, including the node where the walk stops) and the length walked.
    fn walk(&self, prev: u32, start: u32) -> (Vec<u32>, f64) {
        let mut path = vec![start];
        let mut length = self.len(prev, start);
        let (mut from, mut at) = (prev, start);
        while self.degree(at) == 2 {
            let next = if self.adj[at as usize][0] == from {
                self.adj[at as usize][1]
            } else {
                self.adj[at as usize][0]
            };
            if next == start || path.len() > self.nodes.len() {
                break;
            }
            length += self.len(at, next);
            path.push(next);
            from = at;
            at = next;
        }
        (path, length)
    }

    /// Clean-up 2: terminal branches shorter than the stroke width at their junction are spurs.
    fn prune_spurs(&mut self, points: &PointSet) -> bool {
        let mut changed = false;
        for e in self.live() {
            if !self.alive[e as usize] || self.degree(e) != 1 {
                continue;
            }
            let first = self.adj[e as usize][0];
            let (path, length) = self.walk(e, first);
            let junction = *path.last().unwrap_or(&first);
            if self.degree(junction) < 3 {
                continue;
            }
            // A spur is a bump on the side of a stroke: its ink ends within about one width of
            // the junction. A real short branch (the bar of an 'f', the tail of a 't') sticks out
            // well beyond the stroke it leaves, so its ink tip, not its last node, decides.
            let width = self.nodes[junction as usize].width;
            let reach = match ink_tip(
                points,
                self.nodes[first as usize].pos,
                self.nodes[e as usize].pos,
                3.0 * width,
            ) {
                Some(tip) => dist(self.nodes[junction as usize].pos, tip),
                None => length,
            };
            if reach < SPUR_REACH * width {
                let pos = self.nodes[junction as usize].pos;
                let mut group = vec![junction, e];
                group.extend_from_slice(&path[..path.len() - 1]);
                let m = self.merge_all(&group, pos);
                self.nodes[m as usize].pos = pos;
                changed = true;
            }
        }
        changed
    }

    /// The chains leaving junction `j`: (first node, nodes walked, length).
    fn arms(&self, j: u32) -> Vec<(Vec<u32>, f64)> {
        self.adj[j as usize]
            .iter()
            .map(|&x| self.walk(j, x))
            .collect()
    }

    /// Clean-up 3: two junctions joined by a chain shorter than the stroke width are one junction.
    fn collapse_short_bars(&mut self) -> bool {
        let mut changed = false;
        for j in self.live() {
            if !self.alive[j as usize] || self.degree(j) < 3 {
                continue;
            }
            for (path, length) in self.arms(j) {
                let Some(&k) = path.last() else { continue };
                if k == j || !self.alive[k as usize] || self.degree(k) < 3 {
                    continue;
                }
                let width = 0.5 * (self.nodes[j as usize].width + self.nodes[k as usize].width);
                if length < width {
                    let mut group = path.clone();
                    group.push(j);
                    let pos = self.centroid(&[j, k]);
                    self.merge_all(&group, pos);
                    changed = true;
                    break;
                }
            }
        }
        changed
    }

    /// [`Work::arm_direction`] and the position of the node about `reach` away.
    fn arm_reach(&self, j: u32, path: &[u32], reach: f64) -> ([f64; 2], [f64; 2]) {
        (
            self.arm_direction(j, path, reach),
            self.arm_target(j, path, reach),
        )
    }

    /// The position of the first node along an arm from `j` at least `reach` away (the arm's
    /// last node when none is).
    fn arm_target(&self, j: u32, path: &[u32], reach: f64) -> [f64; 2] {
        let origin = self.nodes[j as usize].pos;
        let mut target = origin;
        for &x in path {
            target = self.nodes[x as usize].pos;
            if dist(origin, target) >= reach {
                break;
            }
        }
        target
    }

    /// Direction from `j` along an arm, to the node about `reach` away.
    fn arm_direction(&self, j: u32, path: &[u32], reach: f64) -> [f64; 2] {
        let origin = self.nodes[j as usize].pos;
        let target = self.arm_target(j, path, reach);
        let d = [target[0] - origin[0], target[1] - origin[1]];
        let norm = hypot(d[0], d[1]).max(1e-12);
        [d[0] / norm, d[1] / norm]
    }

    /// Clean-up 4 (adaptation 11): Y-bar-Y → X. Two degree-3 vertices joined by a short bar, whose
    /// outer arms open away from the bar and pair up anti-parallel (within 25°), are one crossing
    /// that thinning-like sampling split in two. The bar limit `3 w / sin(θ/2)` grows as the
    /// crossing gets more acute (θ = angle between one Y's outer arms).
    ///
    /// The crossing goes to the centroid of the two Ys, or with `scattered` (random points, whose
    /// two Ys of an acute crossing lie unevenly far out along it, their masses more uneven still)
    /// to where the two strokes cross: the lines through the paired arms' nodes about `reach`
    /// beyond each Y, when they meet within the bar; else the bar's middle.
    fn merge_y_bar_y(&mut self, scattered: bool) -> bool {
        let mut changed = false;
        let cos25 = 25f64.to_radians().cos();
        for a in self.live() {
            if !self.alive[a as usize] || self.degree(a) != 3 {
                continue;
            }
            let arms_a = self.arms(a);
            for (bar_index, (bar, bar_length)) in arms_a.iter().enumerate() {
                let Some(&b) = bar.last() else { continue };
                if b <= a || self.degree(b) != 3 {
                    continue;
                }
                let w = 0.5 * (self.nodes[a as usize].width + self.nodes[b as usize].width);
                let reach = 2.0 * w.max(2.0);
                let bar_dir = {
                    let (pa, pb) = (self.nodes[a as usize].pos, self.nodes[b as usize].pos);
                    let d = [pb[0] - pa[0], pb[1] - pa[1]];
                    let n = hypot(d[0], d[1]).max(1e-12);
                    [d[0] / n, d[1] / n]
                };
                let outer_a: Vec<([f64; 2], [f64; 2])> = arms_a
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != bar_index)
                    .map(|(_, (path, _))| self.arm_reach(a, path, reach))
                    .collect();
                let bar_back: Vec<u32> = {
                    let mut back: Vec<u32> = bar[..bar.len() - 1].iter().rev().copied().collect();
                    back.push(a);
                    back
                };
                let outer_b: Vec<([f64; 2], [f64; 2])> = self
                    .arms(b)
                    .iter()
                    .filter(|(path, _)| path.first() != bar_back.first())
                    .map(|(path, _)| self.arm_reach(b, path, reach))
                    .collect();
                if outer_a.len() != 2 || outer_b.len() != 2 {
                    continue;
                }
                let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
                let opens_away = outer_a.iter().all(|&(u, _)| dot(u, bar_dir) < 0.0)
                    && outer_b.iter().all(|&(u, _)| dot(u, bar_dir) > 0.0);
                if !opens_away {
                    continue;
                }
                let anti = |u: [f64; 2], v: [f64; 2]| -dot(u, v) >= cos25;
                let straight = anti(outer_a[0].0, outer_b[0].0) && anti(outer_a[1].0, outer_b[1].0);
                let swapped = anti(outer_a[0].0, outer_b[1].0) && anti(outer_a[1].0, outer_b[0].0);
                if !(straight || swapped) {
                    continue;
                }
                let theta = dot(outer_a[0].0, outer_a[1].0).clamp(-1.0, 1.0).acos();
                let limit = 3.0 * w / (theta / 2.0).sin().max(1e-3);
                if *bar_length < limit {
                    let mut group = bar.clone();
                    group.push(a);
                    let pos = if scattered {
                        let (pa, pb) = (self.nodes[a as usize].pos, self.nodes[b as usize].pos);
                        let (b0, b1) = if straight { (0, 1) } else { (1, 0) };
                        let first = (outer_a[0].1, outer_b[b0].1);
                        let second = (outer_a[1].1, outer_b[b1].1);
                        stroke_crossing(first, second, pa, pb)
                    } else {
                        self.centroid(&[a, b])
                    };
                    self.merge_all(&group, pos);
                    changed = true;
                    break;
                }
            }
        }
        changed
    }

    /// Compacts live nodes (in index order) and re-owns every point.
    fn finish(self, owner: &[u32]) -> NodeGraph {
        let n = self.nodes.len();
        let root: Vec<u32> = (0..n as u32)
            .map(|i| {
                let mut r = i;
                while self.parent[r as usize] != r {
                    r = self.parent[r as usize];
                }
                r
            })
            .collect();
        let mut new_index = vec![u32::MAX; n];
        let mut nodes = Vec::new();
        for (i, slot) in new_index.iter_mut().enumerate() {
            if self.alive[i] {
                *slot = nodes.len() as u32;
                nodes.push(self.nodes[i]);
            }
        }
        let mut edges = Vec::new();
        for a in 0..n {
            if !self.alive[a] {
                continue;
            }
            for &b in &self.adj[a] {
                if (a as u32) < b {
                    let (x, y) = (new_index[a], new_index[b as usize]);
                    edges.push([x.min(y), x.max(y)]);
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let owner = owner
            .iter()
            .map(|&o| new_index[root[o as usize] as usize])
            .collect();
        NodeGraph {
            nodes,
            edges,
            owner,
        }
    }
}

/// Where two strokes cross, each the line through two points (a Y-bar-Y's paired arms, see
/// `Work::merge_y_bar_y`): their intersection when it lies within the bar from `a` to `b`
/// (projected, with a margin of a tenth of the bar each side), else the bar's middle.
fn stroke_crossing(
    first: ([f64; 2], [f64; 2]),
    second: ([f64; 2], [f64; 2]),
    a: [f64; 2],
    b: [f64; 2],
) -> [f64; 2] {
    let middle = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let d1 = [first.1[0] - first.0[0], first.1[1] - first.0[1]];
    let d2 = [second.1[0] - second.0[0], second.1[1] - second.0[1]];
    let cross = d1[0] * d2[1] - d1[1] * d2[0];
    let scale = hypot(d1[0], d1[1]) * hypot(d2[0], d2[1]);
    // Lines within about a degree of parallel meet nowhere in particular.
    if cross.is_nan() || cross.abs() <= 0.02 * scale {
        return middle;
    }
    let e = [second.0[0] - first.0[0], second.0[1] - first.0[1]];
    let t = (e[0] * d2[1] - e[1] * d2[0]) / cross;
    let x = [first.0[0] + t * d1[0], first.0[1] + t * d1[1]];
    let bar = [b[0] - a[0], b[1] - a[1]];
    let length2 = bar[0] * bar[0] + bar[1] * bar[1];
    if length2.is_nan() || length2 <= 0.0 {
        return middle;
    }
    let along = ((x[0] - a[0]) * bar[0] + (x[1] - a[1]) * bar[1]) / length2;
    let off = ((x[0] - a[0]) * bar[1] - (x[1] - a[1]) * bar[0]).abs() / length2.sqrt();
    if (-0.1..=1.1).contains(&along) && off <= 0.5 * length2.sqrt() {
        x
    } else {
        middle
    }
}

/// A terminal branch whose ink reaches less than this many stroke widths from its junction is a
/// spur (a corner of a thick stroke reaches about 0.7 w, a real short branch 1.5 w or more).
const SPUR_REACH: f64 = 1.1;

/// The last ink position when walking from `end` away from `from` (in 0.5 px steps, at most
/// `limit`); `None` without a pixel grid.
fn ink_tip(points: &PointSet, from: [f64; 2], end: [f64; 2], limit: f64) -> Option<[f64; 2]> {
    let grid = points.grid.as_ref()?;
    let d = [end[0] - from[0], end[1] - from[1]];
    let norm = hypot(d[0], d[1]);
    if norm < 1e-9 {
        return Some(end);
    }
    let u = [d[0] / norm, d[1] / norm];
    let on_ink = |p: [f64; 2]| grid.point_at(floor_i64(p[0]), floor_i64(p[1])).is_some();
    let mut tip = end;
    let mut t = 0.5;
    while t <= limit {
        let p = [end[0] + u[0] * t, end[1] + u[1] * t];
        if !on_ink(p) {
            break;
        }
        tip = p;
        t += 0.5;
    }
    Some(tip)
}

/// Complete-linkage agglomeration: groups in which every pair satisfies `close`.
fn complete_linkage(items: &[u32], close: impl Fn(u32, u32) -> bool) -> Vec<Vec<u32>> {
    let mut groups: Vec<Vec<u32>> = items.iter().map(|&i| vec![i]).collect();
    loop {
        let mut merged = false;
        'search: for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                if groups[i]
                    .iter()
                    .all(|&a| groups[j].iter().all(|&b| close(a, b)))
                {
                    let taken = groups.remove(j);
                    groups[i].extend(taken);
                    merged = true;
                    break 'search;
                }
            }
        }
        if !merged {
            return groups;
        }
    }
}

/// Background holes (bounded background components) of the ink, each by a representative pixel.
#[derive(Clone)]
enum Holes {
    /// The holes of each component of the ink.
    Known {
        /// The holes, sorted by the x of their representatives.
        holes: Vec<Hole>,
        /// The component of each node's points.
        node_component: Vec<u32>,
    },
    /// Point-list input: no pixel grid.
    Unknown,
}

/// One background hole of a component.
#[derive(Clone, Copy, Debug)]
struct Hole {
    /// A pixel center inside the hole, near its centroid.
    rep: [f64; 2],
    /// The component of the ink around it.
    component: u32,
}

impl Holes {
    /// The holes of each connected component of the ink: the background regions (4-connected)
    /// that the component alone encloses, other components' pixels counting as background. So a
    /// component's holes do not depend on which other components are traced with it (a chunk of
    /// a page or the whole page), and a blob inside a ring does not see the ring's hole.
    ///
    /// Per component, its bounding box is cut into background runs between its ink runs; each
    /// row's runs are joined to the overlapping runs of the row above with a union-find, so the
    /// cost follows the number of runs and the boxes' heights, not their areas.
    fn find(points: &PointSet, graph: &NodeGraph, components: Option<&[u32]>) -> Holes {
        if points.grid.is_none() {
            return Holes::Unknown;
        }
        // Specks of background inside dropout ink are not holes (the closing of adaptation 2).
        let min_size = if points.dropout { 4 } else { 2 };
        let computed;
        let labels = match components {
            Some(labels) if labels.len() == points.len() => labels,
            _ => {
                computed = points.component_labels().0;
                &computed[..]
            }
        };
        // Ink runs (component, row, x0, x1 exclusive) from the pixel centers.
        let mut ink: Vec<(u32, i64, i64, i64)> = Vec::new();
        for (p, &label) in points.points.iter().zip(labels) {
            let (x, y) = (floor_i64(p[0]), floor_i64(p[1]));
            match ink.last_mut() {
                Some(run) if run.0 == label && run.1 == y && run.3 == x => run.3 += 1,
                _ => ink.push((label, y, x, x + 1)),
            }
        }
        let ink = by_component(ink);
        let mut holes: Vec<Hole> = Vec::new();
        let mut background: Vec<(i64, i64, i64)> = Vec::new();
        let mut row_start: Vec<usize> = Vec::new();
        for component in ink.chunk_by(|a, b| a.0 == b.0) {
            let (y0, y1) = (component[0].1, component[component.len() - 1].1);
            let x0 = component.iter().map(|r| r.2).min().unwrap_or(0);
            let x1 = component.iter().map(|r| r.3).max().unwrap_or(0);
            // Background runs of the box, row by row.
            background.clear();
            row_start.clear();
            let mut k = 0;
            for y in y0..=y1 {
                row_start.push(background.len());
                let mut x = x0;
                while k < component.len() && component[k].1 == y {
                    let (_, _, a, b) = component[k];
                    if a > x {
                        background.push((y, x, a));
                    }
                    x = x.max(b);
                    k += 1;
                }
                if x < x1 {
                    background.push((y, x, x1));
                }
            }
            row_start.push(background.len());
            let regions = background_regions(&background, &row_start);
            // Per region: touches the box's edge?, size, sums for the centroid.
            let mut stats: std::collections::BTreeMap<u32, (bool, i64, f64, f64)> =
                std::collections::BTreeMap::new();
            for (r, &(y, a, b)) in background.iter().enumerate() {
                let entry = stats.entry(regions[r]).or_insert((false, 0, 0.0, 0.0));
                let n = b - a;
                entry.0 |= y == y0 || y == y1 || a == x0 || b == x1;
                entry.1 += n;
                entry.2 += (a + b) as f64 / 2.0 * n as f64;
                entry.3 += (y as f64 + 0.5) * n as f64;
            }
            // The representative: the hole pixel nearest the centroid (inside for convex holes).
            let mut best: std::collections::BTreeMap<u32, ([f64; 2], f64)> =
                std::collections::BTreeMap::new();
            for (r, &(y, a, b)) in background.iter().enumerate() {
                let (edge, size, sx, sy) = stats[&regions[r]];
                if edge || size < min_size {
                    continue;
                }
                let c = [sx / size as f64, sy / size as f64];
                let px = (c[0] - 0.5).round().clamp(a as f64, b as f64 - 1.0) + 0.5;
                let p = [px, y as f64 + 0.5];
                let d = dist(p, c);
                let slot = best.entry(regions[r]).or_insert((p, f64::INFINITY));
                if d < slot.1 {
                    *slot = (p, d);
                }
            }
            holes.extend(best.values().map(|&(rep, _)| Hole {
                rep,
                component: component[0].0,
            }));
        }
        holes.sort_by(|a, b| (a.rep[0].total_cmp(&b.rep[0])).then(a.component.cmp(&b.component)));
        let mut node_component = vec![u32::MAX; graph.nodes.len()];
        for (&node, &label) in graph.owner.iter().zip(labels) {
            if let Some(slot) = node_component.get_mut(node as usize) {
                *slot = label;
            }
        }
        Holes::Known {
            holes,
            node_component,
        }
    }

    /// All holes and the component of node `node` (`None` without hole knowledge).
    fn of_node(&self, node: u32) -> Option<(&[Hole], u32)> {
        match self {
            Holes::Known {
                holes,
                node_component,
            } => Some((
                holes,
                node_component
                    .get(node as usize)
                    .copied()
                    .unwrap_or(u32::MAX),
            )),
            Holes::Unknown => None,
        }
    }

    /// Whether a known hole of `node`'s component lies inside the polygon (false without hole
    /// knowledge).
    fn encloses_known(&self, polygon: &[[f64; 2]], node: u32) -> bool {
        matches!(self, Holes::Known { .. }) && self.encloses(polygon, node)
    }

    /// Whether a representative pixel of a hole of `node`'s component lies in the disk whose
    /// diameter is `a`-`b`.
    fn near_segment(&self, a: [f64; 2], b: [f64; 2], node: u32) -> bool {
        let Some((holes, component)) = self.of_node(node) else {
            return false;
        };
        let center = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let radius = dist(a, b) / 2.0 + 0.5;
        let start = holes.partition_point(|h| h.rep[0] < center[0] - radius);
        holes[start..]
            .iter()
            .take_while(|h| h.rep[0] <= center[0] + radius)
            .any(|h| h.component == component && dist(h.rep, center) <= radius)
    }

    /// Whether a representative pixel of a hole of `node`'s component lies inside the polygon
    /// (even-odd rule); true without hole knowledge.
    fn encloses(&self, polygon: &[[f64; 2]], node: u32) -> bool {
        let Some((holes, component)) = self.of_node(node) else {
            return true;
        };
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in polygon {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
        }
        let start = holes.partition_point(|h| h.rep[0] < x0);
        holes[start..]
            .iter()
            .take_while(|h| h.rep[0] <= x1)
            .any(|h| h.component == component && point_in_polygon(h.rep, polygon))
    }
}

/// The ink runs `(component, row, x0, x1)` sorted (what `sort_unstable` gives), a counting sort
/// by component: runs read off points in raster order already rise within each component, so
/// only a component whose runs do not (checked) is sorted on its own.
fn by_component(ink: Vec<(u32, i64, i64, i64)>) -> Vec<(u32, i64, i64, i64)> {
    let components = ink.iter().map(|r| r.0 as usize + 1).max().unwrap_or(0);
    if components > ink.len() {
        let mut ink = ink;
        ink.sort_unstable();
        return ink;
    }
    let mut grouped = Csr::build(components, |sink| {
        for &run in &ink {
            sink.push(run.0 as usize, run);
        }
    });
    for c in 0..components {
        let runs = grouped.row_mut(c);
        if !runs.is_sorted() {
            runs.sort_unstable();
        }
    }
    grouped.values
}

/// Labels the 4-connected regions of background runs `(row, x0, x1 exclusive)` listed row by row
/// (`row_start[i]` is the first run of the `i`-th row, rows consecutive): each run is joined to
/// the overlapping runs of the row above with a union-find.
fn background_regions(runs: &[(i64, i64, i64)], row_start: &[usize]) -> Vec<u32> {
    let mut union = petgraph::unionfind::UnionFind::<u32>::new(runs.len());
    for rows in row_start.windows(3) {
        let (above, here) = (rows[0]..rows[1], rows[1]..rows[2]);
        let mut i = above.start;
        for j in here {
            let (_, x0, x1) = runs[j];
            while i < above.end && runs[i].2 <= x0 {
                i += 1;
            }
            let mut k = i;
            while k < above.end && runs[k].1 < x1 {
                union.union(k as u32, j as u32);
                k += 1;
            }
        }
    }
    union.into_labeling()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node of a hand-built graph: non-linear when it has a cluster.
    fn node(pos: [f64; 2], width: f64, cluster: Option<u32>) -> GraphNode {
        GraphNode {
            pos,
            r_min: 3.0,
            width,
            direction: [1.0, 0.0],
            linear: cluster.is_none(),
            cluster,
            tip: false,
        }
    }

    /// The work graph of `nodes` and `edges`, without hole knowledge (as without clean-up).
    fn work(nodes: Vec<GraphNode>, edges: &[[u32; 2]]) -> Work {
        let mut edges: Vec<[u32; 2]> = edges.iter().map(|&[a, b]| [a.min(b), a.max(b)]).collect();
        edges.sort_unstable();
        let graph = NodeGraph {
            nodes,
            edges,
            owner: Vec::new(),
        };
        assert_eq!(graph.validate(0), Ok(()));
        Work::new(&graph, Holes::Unknown)
    }

    #[test]
    fn runs_by_component_are_the_runs_sorted() {
        let mut lcg = crate::synth::lcg(7);
        let mut rand = move |n: u64| (lcg() >> 33) % n;
        for case in 0..200 {
            // Runs in raster order with random components; every tenth case shuffled too, and
            // some with labels far beyond the run count.
            let mut ink: Vec<(u32, i64, i64, i64)> = (0..rand(60) as i64)
                .map(|k| {
                    let label = if case % 7 == 0 {
                        1000 + rand(5)
                    } else {
                        rand(6)
                    };
                    (label as u32, k / 4, 3 * (k % 4), 3 * (k % 4) + 2)
                })
                .collect();
            if case % 10 == 0 {
                for i in (1..ink.len()).rev() {
                    ink.swap(i, rand(i as u64 + 1) as usize);
                }
            }
            let mut sorted = ink.clone();
            sorted.sort_unstable();
            assert_eq!(by_component(ink), sorted, "case {case}");
        }
    }

    /// Degrees of the live nodes, in node order.
    fn degrees(work: &Work) -> Vec<usize> {
        work.live().into_iter().map(|i| work.degree(i)).collect()
    }

    /// Two Y's joined at `[0, 0]`-`[bar, 0]`, the left one's arms to `left`, mirrored in y; the
    /// right one's arms to `right`, mirrored in y. Nodes: 0 and 1 the Y's, then the arm ends.
    fn two_ys(bar: f64, left: [f64; 2], right: [f64; 2], width: f64) -> Work {
        let nodes = vec![
            node([0.0, 0.0], width, Some(0)),
            node([bar, 0.0], width, Some(0)),
            node(left, width, None),
            node([left[0], -left[1]], width, None),
            node(right, width, None),
            node([right[0], -right[1]], width, None),
        ];
        work(nodes, &[[0, 1], [0, 2], [0, 3], [1, 4], [1, 5]])
    }

    #[test]
    fn contraction_removes_triangles_within_a_cluster_only() {
        // A triangle with a tail: its shortest edge (1-2) collapses to its midpoint, the tail
        // stays.
        let nodes = vec![
            node([0.0, 0.0], 3.0, None),
            node([2.0, 0.0], 3.0, None),
            node([1.5, 1.5], 3.0, None),
            node([10.0, 0.0], 3.0, None),
        ];
        let mut w = work(nodes.clone(), &[[0, 1], [1, 2], [0, 2], [1, 3]]);
        w.contract_triangles();
        assert_eq!(w.contractible_triangle_edge(), None);
        assert_eq!(w.live(), [0, 1, 3]);
        assert_eq!(degrees(&w), [1, 2, 1]);
        assert_eq!(w.nodes[1].pos, [1.75, 0.75]);
        // The same triangle with its corners in three clusters is three regions: untouched.
        let clustered: Vec<GraphNode> = nodes
            .iter()
            .enumerate()
            .map(|(i, n)| GraphNode {
                cluster: (i < 3).then_some(i as u32),
                ..*n
            })
            .collect();
        let mut w = work(clustered, &[[0, 1], [1, 2], [0, 2], [1, 3]]);
        w.contract_triangles();
        assert_eq!(w.live().len(), 4);
        assert_eq!(w.contractible_triangle_edge(), None);
    }

    #[test]
    fn merging_joins_close_junctions_of_one_cluster() {
        // Two Y's 2 apart in one cluster (r_min 3, span 2: within 6) become one crossing.
        let mut w = two_ys(2.0, [-5.0, 3.0], [7.0, 3.0], 3.0);
        w.merge_clusters(2.0, &Holes::Unknown);
        assert_eq!(degrees(&w), [4, 1, 1, 1, 1]);
        assert_eq!(w.nodes[0].pos, [1.0, 0.0], "at the centroid");
        // 20 apart they are two junctions; with the paper's whole-cluster merge, one.
        let mut w = two_ys(20.0, [-5.0, 3.0], [25.0, 3.0], 3.0);
        w.merge_clusters(2.0, &Holes::Unknown);
        assert_eq!(degrees(&w), [3, 3, 1, 1, 1, 1]);
        let mut w = two_ys(20.0, [-5.0, 3.0], [25.0, 3.0], 3.0);
        w.merge_clusters(f64::INFINITY, &Holes::Unknown);
        assert_eq!(degrees(&w), [4, 1, 1, 1, 1]);
    }

    #[test]
    fn spur_pruning_drops_short_branches_only() {
        // A line of nodes 4 apart with a branch at its middle, 3 long (a spur: under 1.1 widths
        // of 4) or 10 long (an arm). Without a pixel grid the branch's length is its reach.
        for (branch, pruned) in [(3.0, true), (10.0, false)] {
            let mut nodes: Vec<GraphNode> = (0..5)
                .map(|i| node([4.0 * i as f64, 0.0], 4.0, None))
                .collect();
            nodes.push(node([8.0, branch], 4.0, None));
            let mut w = work(nodes, &[[0, 1], [1, 2], [2, 3], [3, 4], [2, 5]]);
            assert_eq!(
                w.prune_spurs(&PointSet::default()),
                pruned,
                "branch {branch}"
            );
            let expected: &[usize] = if pruned {
                &[1, 2, 2, 2, 1]
            } else {
                &[1, 2, 3, 2, 1, 1]
            };
            assert_eq!(degrees(&w), expected, "branch {branch}");
            assert_eq!(
                w.nodes[2].pos,
                [8.0, 0.0],
                "the junction stays where it was"
            );
        }
    }

    #[test]
    fn short_bars_between_junctions_collapse() {
        // A bar of 2 between two junctions of width 4 is one junction; a bar of 6 stays.
        let mut w = two_ys(2.0, [-6.0, 4.0], [8.0, 4.0], 4.0);
        assert!(w.collapse_short_bars());
        assert_eq!(degrees(&w), [4, 1, 1, 1, 1]);
        assert_eq!(w.nodes[0].pos, [1.0, 0.0]);
        let mut w = two_ys(6.0, [-6.0, 4.0], [12.0, 4.0], 4.0);
        assert!(!w.collapse_short_bars());
        assert_eq!(degrees(&w), [3, 3, 1, 1, 1, 1]);
    }

    #[test]
    fn y_bar_y_becomes_one_crossing_when_the_arms_pair_up() {
        // An acute X sampled as two Y's 4 apart (width 3): the outer arms open away from the bar
        // and pair up anti-parallel, so the bar (under 3 w / sin(θ/2) ≈ 31) is merged.
        let mut w = two_ys(4.0, [-10.0, 4.0], [14.0, 4.0], 3.0);
        assert!(w.merge_y_bar_y(false));
        assert_eq!(degrees(&w), [4, 1, 1, 1, 1]);
        assert_eq!(w.nodes[0].pos, [2.0, 0.0]);
        // Arms at right angles to the bar on one side (a stroke passing the end of another) do
        // not open away from it: two junctions stay.
        let mut w = two_ys(4.0, [-10.0, 4.0], [4.0, 10.0], 3.0);
        assert!(!w.merge_y_bar_y(false));
        assert_eq!(degrees(&w), [3, 3, 1, 1, 1, 1]);
        // Arms that open away but do not pair up (a wide and a narrow Y) stay too.
        let mut w = two_ys(4.0, [-10.0, 4.0], [6.0, 10.0], 3.0);
        assert!(!w.merge_y_bar_y(false));
        assert_eq!(degrees(&w), [3, 3, 1, 1, 1, 1]);
    }

    #[test]
    fn y_bar_y_on_scattered_points_goes_where_the_strokes_cross() {
        // The same acute X, its left Y holding nine times the points of the right one: the
        // centroid leans to the left Y, the strokes still cross at (2, 0).
        let mut w = two_ys(4.0, [-10.0, 4.0], [14.0, 4.0], 3.0);
        w.mass[0] = 9.0;
        assert!(w.merge_y_bar_y(false));
        assert!(w.nodes[0].pos[0] < 1.0, "{:?}", w.nodes[0].pos);
        let mut w = two_ys(4.0, [-10.0, 4.0], [14.0, 4.0], 3.0);
        w.mass[0] = 9.0;
        assert!(w.merge_y_bar_y(true));
        assert_eq!(degrees(&w), [4, 1, 1, 1, 1]);
        let p = w.nodes[0].pos;
        assert!(dist(p, [2.0, 0.0]) < 1e-9, "{p:?}");
    }

    #[test]
    fn complete_linkage_requires_every_pair_close() {
        // 0, 1, 2 on a line 1 apart: with limit 1.5, {0,1} and {2} (0-2 is 2 apart).
        let pos = [0.0f64, 1.0, 2.0];
        let groups = complete_linkage(&[0, 1, 2], |a, b| {
            (pos[a as usize] - pos[b as usize]).abs() <= 1.5
        });
        assert_eq!(groups.len(), 2);
        assert!(groups.iter().all(|g| g.len() <= 2));
    }
}
