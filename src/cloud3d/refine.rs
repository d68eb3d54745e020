//! §3.2 and §3.3 in space: the graph `H` on the nodes (joined where the `k` nearest neighbours of
//! their points meet, §3.2), the clusters of non-linear nodes (docs/design.md, adaptation 8),
//! contraction of the shortest, lowest-degree edges on triangles (never across two clusters),
//! merging of each cluster's nodes of degree > 2 in tight groups (adaptation 9), and the clean-up
//! the paper leaves to "classic operators" (adaptation 10): short cycles contracted, spurs
//! pruned, bars between junctions shorter than the tube's diameter collapsed.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use petgraph::unionfind::UnionFind;

use super::math::{add, dist2, scale, V3};
use super::points::Cloud;
use super::sample::Sampled;
use crate::geometry::TotalF64;
use crate::params::Params;

/// The refined 1-D graph: live nodes only, renumbered.
pub(super) struct Refined {
    pub pos: Vec<V3>,
    pub width: Vec<f64>,
    /// Sorted adjacency lists.
    pub adj: Vec<Vec<u32>>,
    /// Refined node of each point.
    pub owner: Vec<u32>,
}

struct Work {
    pos: Vec<V3>,
    r_min: Vec<f64>,
    width: Vec<f64>,
    weight: Vec<f64>,
    cluster: Vec<Option<u32>>,
    alive: Vec<bool>,
    adj: Vec<Vec<u32>>,
    /// The node each dead node was merged into.
    into: Vec<u32>,
}

impl Work {
    fn degree(&self, a: u32) -> usize {
        self.adj[a as usize].len()
    }

    fn length(&self, a: u32, b: u32) -> f64 {
        dist2(self.pos[a as usize], self.pos[b as usize]).sqrt()
    }

    fn connected(&self, a: u32, b: u32) -> bool {
        self.adj[a as usize].binary_search(&b).is_ok()
    }

    fn in_triangle(&self, a: u32, b: u32) -> bool {
        let (x, y) = (&self.adj[a as usize], &self.adj[b as usize]);
        let (mut i, mut j) = (0, 0);
        while i < x.len() && j < y.len() {
            match x[i].cmp(&y[j]) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => return true,
            }
        }
        false
    }

    /// Merges `group` (live, distinct) into its first member, placed at `pos`.
    fn merge(&mut self, group: &[u32], pos: V3) {
        let keep = group[0];
        let mut neighbours: Vec<u32> = Vec::new();
        let mut weight = 0.0;
        let mut width = 0.0;
        let mut r_min = 0.0f64;
        let mut cluster = None;
        for &g in group {
            neighbours.extend(&self.adj[g as usize]);
            weight += self.weight[g as usize];
            width += self.width[g as usize] * self.weight[g as usize];
            r_min = r_min.max(self.r_min[g as usize]);
            cluster = cluster.or(self.cluster[g as usize]);
        }
        neighbours.sort_unstable();
        neighbours.dedup();
        neighbours.retain(|x| !group.contains(x));
        for &g in group {
            for x in std::mem::take(&mut self.adj[g as usize]) {
                let list = &mut self.adj[x as usize];
                if let Ok(i) = list.binary_search(&g) {
                    list.remove(i);
                }
            }
        }
        for &x in &neighbours {
            let list = &mut self.adj[x as usize];
            if let Err(i) = list.binary_search(&keep) {
                list.insert(i, keep);
            }
        }
        for &g in &group[1..] {
            self.alive[g as usize] = false;
            self.into[g as usize] = keep;
        }
        let k = keep as usize;
        self.adj[k] = neighbours;
        self.pos[k] = pos;
        self.weight[k] = weight;
        self.width[k] = width / weight.max(f64::MIN_POSITIVE);
        self.r_min[k] = r_min;
        self.cluster[k] = cluster;
    }

    fn edge_key(&self, a: u32, b: u32) -> (TotalF64, usize, u32, u32) {
        (
            TotalF64(self.length(a, b)),
            self.degree(a).min(self.degree(b)),
            a,
            b,
        )
    }

    /// Contraction: collapse the shortest, lowest-degree triangle edge to its midpoint until no
    /// triangle is left whose edge may collapse (none across two clusters). True if any did.
    fn contract(&mut self) -> bool {
        let mut heap = BinaryHeap::new();
        for a in 0..self.pos.len() as u32 {
            for &b in &self.adj[a as usize] {
                if a < b && self.in_triangle(a, b) {
                    heap.push(Reverse(self.edge_key(a, b)));
                }
            }
        }
        let mut changed = false;
        while let Some(Reverse((TotalF64(length), degree, a, b))) = heap.pop() {
            if !self.alive[a as usize] || !self.alive[b as usize] || !self.connected(a, b) {
                continue;
            }
            let key = self.edge_key(a, b);
            if key.0 .0 != length || key.1 != degree {
                heap.push(Reverse(key));
                continue;
            }
            if !self.in_triangle(a, b) {
                continue;
            }
            if let (Some(x), Some(y)) = (self.cluster[a as usize], self.cluster[b as usize]) {
                if x != y {
                    continue;
                }
            }
            let mid = scale(add(self.pos[a as usize], self.pos[b as usize]), 0.5);
            self.merge(&[a, b], mid);
            changed = true;
            let m = a;
            let around = self.adj[m as usize].clone();
            for &x in &around {
                if self.in_triangle(m, x) {
                    heap.push(Reverse(self.edge_key(m.min(x), m.max(x))));
                }
                for &y in &self.adj[x as usize] {
                    if x < y && self.in_triangle(x, y) {
                        heap.push(Reverse(self.edge_key(x, y)));
                    }
                }
            }
        }
        changed
    }

    /// Merging: the nodes of degree > 2 of each cluster become one node, in groups whose members
    /// are all within `span` times their `r_min` of each other (complete linkage, in index
    /// order). True if any merged.
    fn merge_clusters(&mut self, span: f64) -> bool {
        let mut by_cluster: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
        for i in 0..self.pos.len() as u32 {
            if let (true, Some(c)) = (self.alive[i as usize], self.cluster[i as usize]) {
                if self.degree(i) > 2 {
                    by_cluster.entry(c).or_default().push(i);
                }
            }
        }
        let mut changed = false;
        for members in by_cluster.into_values() {
            let mut groups: Vec<Vec<u32>> = Vec::new();
            for m in members {
                let fits = |g: &Vec<u32>| {
                    g.iter().all(|&x| {
                        let reach = span * self.r_min[x as usize].max(self.r_min[m as usize]);
                        self.length(x, m) <= reach
                    })
                };
                match groups.iter_mut().find(|g| fits(g)) {
                    Some(g) => g.push(m),
                    None => groups.push(vec![m]),
                }
            }
            for g in groups.into_iter().filter(|g| g.len() > 1) {
                let mean = g
                    .iter()
                    .fold([0.0; 3], |s, &x| add(s, self.pos[x as usize]));
                self.merge(&g, scale(mean, 1.0 / g.len() as f64));
                changed = true;
            }
        }
        changed
    }

    /// Cycles shorter than `2 pi r_min` (a tube's cross-section sampled as a ring around a thick
    /// region, never a curve's own loop, which is many diameters long) become one node.
    fn contract_short_cycles(&mut self) -> bool {
        let mut changed = false;
        for a in 0..self.pos.len() as u32 {
            if !self.alive[a as usize] {
                continue;
            }
            let neighbours = self.adj[a as usize].clone();
            for b in neighbours {
                if b < a || !self.alive[a as usize] || !self.alive[b as usize] {
                    continue;
                }
                if !self.connected(a, b) {
                    continue;
                }
                let limit = 2.0 * std::f64::consts::PI * self.r_min[a as usize];
                let Some((path, length)) = self.path_avoiding(a, b, limit) else {
                    continue;
                };
                if length + self.length(a, b) <= limit {
                    let mean = path
                        .iter()
                        .fold([0.0; 3], |s, &x| add(s, self.pos[x as usize]));
                    let mut group = path.clone();
                    group.sort_unstable();
                    let pos = scale(mean, 1.0 / path.len() as f64);
                    self.merge(&group, pos);
                    changed = true;
                }
            }
        }
        changed
    }

    /// The shortest path from `a` to `b` not using the edge `a-b`, if shorter than `limit`.
    fn path_avoiding(&self, a: u32, b: u32, limit: f64) -> Option<(Vec<u32>, f64)> {
        let mut dist: std::collections::HashMap<u32, (f64, u32)> = Default::default();
        let mut heap = BinaryHeap::new();
        dist.insert(a, (0.0, a));
        heap.push(Reverse((TotalF64(0.0), a)));
        while let Some(Reverse((TotalF64(d), x))) = heap.pop() {
            if dist.get(&x).is_some_and(|&(best, _)| best < d) {
                continue;
            }
            if x == b {
                let mut path = vec![b];
                let mut at = b;
                while at != a {
                    at = dist[&at].1;
                    path.push(at);
                }
                return Some((path, d));
            }
            for &y in &self.adj[x as usize] {
                if x == a && y == b {
                    continue;
                }
                let nd = d + self.length(x, y);
                if nd > limit {
                    continue;
                }
                if dist.get(&y).is_none_or(|&(best, _)| nd < best) {
                    dist.insert(y, (nd, x));
                    heap.push(Reverse((TotalF64(nd), y)));
                }
            }
        }
        None
    }

    /// Spurs: a branch from an end through nodes of degree 2 to a junction, shorter than the
    /// junction's `r_min` (about the tube's diameter), goes; shortest first, one at a time.
    fn prune_spurs(&mut self) -> bool {
        let mut changed = false;
        loop {
            let mut shortest: Option<(f64, Vec<u32>)> = None;
            for e in 0..self.pos.len() as u32 {
                if !self.alive[e as usize] || self.degree(e) != 1 {
                    continue;
                }
                let mut path = vec![e];
                let mut length = 0.0;
                let (mut prev, mut at) = (e, self.adj[e as usize][0]);
                while self.degree(at) == 2 && at != e {
                    length += self.length(prev, at);
                    path.push(at);
                    let next = self.adj[at as usize]
                        .iter()
                        .copied()
                        .find(|&x| x != prev)
                        .unwrap_or(prev);
                    prev = at;
                    at = next;
                }
                length += self.length(prev, at);
                if self.degree(at) < 3 || length >= self.r_min[at as usize] {
                    continue;
                }
                if shortest.as_ref().is_none_or(|(l, _)| length < *l) {
                    shortest = Some((length, path));
                }
            }
            let Some((_, path)) = shortest else {
                return changed;
            };
            for &x in &path {
                for y in std::mem::take(&mut self.adj[x as usize]) {
                    let list = &mut self.adj[y as usize];
                    if let Ok(i) = list.binary_search(&x) {
                        list.remove(i);
                    }
                }
                self.alive[x as usize] = false;
                self.into[x as usize] = u32::MAX;
            }
            changed = true;
        }
    }

    /// Bars between two junctions shorter than the tube's diameter become one junction.
    fn collapse_bars(&mut self) -> bool {
        let mut changed = false;
        for a in 0..self.pos.len() as u32 {
            if !self.alive[a as usize] || self.degree(a) < 3 {
                continue;
            }
            let neighbours = self.adj[a as usize].clone();
            for b in neighbours {
                if !self.alive[a as usize] || !self.alive[b as usize] || b == a {
                    continue;
                }
                if self.degree(b) < 3 || !self.connected(a, b) {
                    continue;
                }
                let w = self.width[a as usize].max(self.width[b as usize]);
                if self.length(a, b) < w {
                    let mid = scale(add(self.pos[a as usize], self.pos[b as usize]), 0.5);
                    let group = [a.min(b), a.max(b)];
                    self.merge(&group, mid);
                    changed = true;
                }
            }
        }
        changed
    }
}

/// §3.2 `H` and §3.3 on the sampled nodes.
pub(super) fn refine(cloud: &Cloud, sampled: &Sampled, params: &Params) -> Refined {
    let count = sampled.nodes.len();
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for p in 0..cloud.len() as u32 {
        let a = sampled.owner[p as usize];
        for &q in cloud.neighbors_of(p) {
            let b = sampled.owner[q as usize];
            if a < b {
                pairs.push((a, b));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut adj = vec![Vec::new(); count];
    for &(a, b) in &pairs {
        adj[a as usize].push(b);
        adj[b as usize].push(a);
    }
    for list in &mut adj {
        list.sort_unstable();
    }
    // Clusters: non-linear nodes joined by edges of H shorter than `cluster_link r_min`.
    let nodes = &sampled.nodes;
    let mut sets = UnionFind::<u32>::new(count);
    for &(a, b) in &pairs {
        let (x, y) = (&nodes[a as usize], &nodes[b as usize]);
        let link = params.method.cluster_link * x.r_min.max(y.r_min);
        if !x.linear && !y.linear && dist2(x.pos, y.pos) < link * link {
            sets.union(a, b);
        }
    }
    let labels = sets.into_labeling();
    let mut weight = vec![0.0; count];
    for &o in &sampled.owner {
        weight[o as usize] += 1.0;
    }
    let mut work = Work {
        pos: nodes.iter().map(|n| n.pos).collect(),
        r_min: nodes.iter().map(|n| n.r_min).collect(),
        width: nodes.iter().map(|n| n.width).collect(),
        weight,
        cluster: nodes
            .iter()
            .zip(&labels)
            .map(|(n, &l)| (!n.linear).then_some(l))
            .collect(),
        alive: vec![true; count],
        adj,
        into: (0..count as u32).collect(),
    };
    work.contract();
    work.merge_clusters(params.method.merge_span);
    if params.finish.cleanup {
        for _ in 0..8 {
            let mut changed = work.contract_short_cycles();
            changed |= work.contract();
            changed |= work.merge_clusters(params.method.merge_span);
            changed |= work.collapse_bars();
            changed |= work.prune_spurs();
            if !changed {
                break;
            }
        }
    }
    // Renumber the live nodes; every point goes to the node its own was merged into (a pruned
    // spur's points to none, then to the nearest live node by the fit's cells).
    let mut number = vec![u32::MAX; count];
    let mut next = 0u32;
    for (slot, &alive) in number.iter_mut().zip(&work.alive) {
        if alive {
            *slot = next;
            next += 1;
        }
    }
    // The live node each node ended in, once per node with the chains of merges compressed as
    // they are walked (a node merged many times over would otherwise be walked once per point).
    let mut last = work.into.clone();
    for i in 0..count as u32 {
        let mut end = i;
        while end != u32::MAX && !work.alive[end as usize] {
            end = last[end as usize];
        }
        let mut at = i;
        while at != u32::MAX && !work.alive[at as usize] {
            let next = last[at as usize];
            last[at as usize] = end;
            at = next;
        }
    }
    let resolve = |i: u32| -> u32 {
        let end = if work.alive[i as usize] {
            i
        } else {
            last[i as usize]
        };
        if end == u32::MAX {
            u32::MAX
        } else {
            number[end as usize]
        }
    };
    let owner: Vec<u32> = sampled.owner.iter().map(|&o| resolve(o)).collect();
    let live: Vec<usize> = (0..count).filter(|&i| work.alive[i]).collect();
    Refined {
        pos: live.iter().map(|&i| work.pos[i]).collect(),
        width: live.iter().map(|&i| work.width[i]).collect(),
        adj: live
            .iter()
            .map(|&i| {
                let mut list: Vec<u32> = work.adj[i].iter().map(|&j| number[j as usize]).collect();
                list.sort_unstable();
                list
            })
            .collect(),
        owner,
    }
}
