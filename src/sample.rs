//! §3.1 Anisotropic adaptive sampling: points `P` → nodes `Q`, each owning a part `P_i` of `P`.
//!
//! Farthest-point sampling driven by the anisotropic distance of Eq. (1), with a disk whose radius
//! adapts to the local linearity of Eq. (3). The adaptations to pixel images, each needed on the
//! ground-truth suite (docs/design.md, adaptations 3-6):
//! - `r_min` follows the local stroke width instead of `10 Dis_ave`: a fixed 10 px disk is already
//!   linear at `r_min` on thin strokes (so nothing is marked non-linear) and spans neighbouring
//!   strokes.
//! - The disk is *connected*: only points joined to the center by neighbour paths inside the disk.
//!   One bottleneck search from the center orders the points by the radius at which they join the
//!   disk, so every radius is a prefix of one list and the moments are cumulative sums.
//! - A node is non-linear when PCA fails at every radius up to `r_max` *or* the rim of the disk does
//!   not cut the ink in 1 or 2 places (PCA alone calls a 15° crossing linear).
//! - Each point belongs to the first node whose disk covers it, so the `P_i` partition `P`.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::geometry::{floor_f64, floor_i64, principal, TotalF64};
use crate::params::{Params, RMinRule};
use crate::point_set::PointSet;
use crate::samples::{Node, Samples};

/// Marks a point that no node owns yet.
const UNOWNED: u32 = u32::MAX;

/// End of a bucket's stack in the disk search queue.
const NIL: u32 = u32::MAX;

/// hostile input: keys at or above this go to a binary heap instead of the bucket array. The
/// array has one bucket per quarter unit² of squared radius, so radii of thousands of units
/// (blobs thousands of pixels wide, `--r-min-factor 1e9`, point lists in large units) asked for
/// up to 2^31 buckets (51 GB) for a handful of points. Below this (radii < 512 px) nothing
/// changes; above it the order is the same up to ties.
const BUCKET_KEYS: u32 = 1 << 20;

/// Samples nodes over `points` (Algorithm 1 of the paper, with the adaptations above).
pub fn sample(points: &PointSet, params: &Params) -> Samples {
    let n = points.len();
    let mut sampler = Sampler::new(points, params);
    let mut nodes = Vec::new();
    // Max-heap of (anisotropic distance D, point): candidates for the next center.
    let mut frontier: BinaryHeap<(TotalF64, Reverse<u32>)> = BinaryHeap::new();
    let mut seed_cursor = 0usize;
    // hostile input: a point is a center at most once. With k-nearest-neighbour graphs
    // (point lists) a neighbour can lie beyond `r_min`, so a center's disk may take no new point
    // while the center still borders uncovered ink: it came back off the heap with the same key
    // forever (10 collinear points hung). On pixel images a center's neighbours are all inside
    // its disk (r >= 3 > 2√2), so this never fires there.
    let mut was_center = vec![false; n];
    loop {
        // The farthest covered point that still borders uncovered ink is the next center; when the
        // frontier is exhausted, a new part starts at the first uncovered point (raster order, so
        // an extremity of its part).
        let center = loop {
            match frontier.pop() {
                Some((TotalF64(d), Reverse(p))) => {
                    if d == sampler.distance[p as usize]
                        && !was_center[p as usize]
                        && sampler.borders_uncovered(p)
                    {
                        break Some(p);
                    }
                }
                None => {
                    while seed_cursor < n && sampler.owner[seed_cursor] != UNOWNED {
                        seed_cursor += 1;
                    }
                    break (seed_cursor < n).then_some(seed_cursor as u32);
                }
            }
        };
        let Some(center) = center else { break };
        was_center[center as usize] = true;
        let id = nodes.len() as u32;
        let (node, taken) = sampler.node_at(center, id, &mut frontier);
        // hostile input: a node that took no point would own an empty `P_i`, which the later
        // stages do not expect; its `D` updates are kept, the node is not (nothing refers to
        // `id`). Never happens on pixel images (see `was_center`).
        if taken > 0 {
            nodes.push(node);
        }
    }
    let samples = Samples {
        nodes,
        owner: sampler.owner,
    };
    debug_assert_eq!(samples.validate(n), Ok(()));
    samples
}

/// Reusable state of the sampling loop: no allocation per node beyond the reused buffers.
struct Sampler<'a> {
    points: &'a PointSet,
    params: &'a Params,
    owner: Vec<u32>,
    /// Points all of whose neighbours are owned (see [`Sampler::borders_uncovered`]).
    closed: Vec<bool>,
    /// `D` of Algorithm 1: the smallest Eq. (1) distance from any node so far.
    distance: Vec<f64>,
    /// Epoch stamps marking points reached by the current bottleneck search.
    seen: Vec<u32>,
    /// Epoch stamps for the rim component search.
    rim_seen: Vec<u32>,
    epoch: u32,
    /// Points of the current disk search in the order they join the disk, with their keys.
    order: Vec<(u32, u32)>,
    /// Center of the current disk search.
    center: [f64; 2],
    /// Moments over the first `summed` points of `order`: (n, Σx, Σy, Σxx, Σxy, Σyy) relative
    /// to the center, summed in `order`'s order when [`Sampler::pca`] asks for them (the
    /// searches reach points past every radius asked, so summing as they queue wasted work).
    sums: [f64; 6],
    summed: usize,
    /// Bucket queue of the disk search: `heads[k]` is the last point queued with key `k` (or
    /// [`NIL`]), `next[p]` the point queued before `p` with the same key. Each bucket is a stack
    /// threaded through one array (a point is queued at most once per search), so a push or pop
    /// is two stores and no bucket owns an allocation.
    heads: Vec<u32>,
    next: Vec<u32>,
    /// Bit `k % 64` of word `k / 64` set when bucket `k` holds a point: the search jumps to the
    /// next bucket in use instead of stepping through the empty ones (on a pixel grid at least
    /// three keys in four are never used, squared distances being integers).
    occupied: Vec<u64>,
    /// Buckets in use (to clear), next bucket to pop, points queued, largest key admitted.
    used: usize,
    cursor: usize,
    queued: usize,
    limit: u32,
    /// Points reached with keys beyond the current bound, admitted when the bound grows.
    overflow: Vec<(u32, u32)>,
    /// hostile input: queued points with keys of [`BUCKET_KEYS`] or more, smallest first.
    far: BinaryHeap<Reverse<(u32, u32)>>,
    stack: Vec<u32>,
    /// [`ExperimentParams::ink_disks`](crate::ExperimentParams::ink_disks) is in force (a pixel
    /// grid, not dropout mode).
    ink_bound: bool,
    /// Epoch stamps of the points of the current disk seen from its center (see
    /// [`sees`]).
    visible: Vec<u32>,
    /// Smallest key of a disk point hidden from the center (`u32::MAX` when none yet).
    first_hidden: u32,
}

impl<'a> Sampler<'a> {
    fn new(points: &'a PointSet, params: &'a Params) -> Self {
        let n = points.len();
        Sampler {
            points,
            params,
            owner: vec![UNOWNED; n],
            closed: vec![false; n],
            distance: vec![0.0; n],
            seen: vec![0; n],
            rim_seen: vec![0; n],
            epoch: 0,
            order: Vec::new(),
            center: [0.0; 2],
            sums: [0.0; 6],
            summed: 0,
            heads: Vec::new(),
            next: vec![NIL; n],
            occupied: Vec::new(),
            used: 0,
            cursor: 0,
            queued: 0,
            limit: 0,
            overflow: Vec::new(),
            far: BinaryHeap::new(),
            stack: Vec::new(),
            ink_bound: params.experiments.ink_disks && points.grid.is_some() && !points.dropout,
            visible: if params.experiments.ink_disks {
                vec![0; n]
            } else {
                Vec::new()
            },
            first_hidden: u32::MAX,
        }
    }

    /// Whether `p` has a neighbour no node owns yet. Ownership only grows, so a `false` is final
    /// and is remembered: interior points are asked once per disk that holds them.
    fn borders_uncovered(&mut self, p: u32) -> bool {
        if self.closed[p as usize] {
            return false;
        }
        let borders = self
            .points
            .neighbors_of(p)
            .iter()
            .any(|&q| self.owner[q as usize] == UNOWNED);
        self.closed[p as usize] = !borders;
        borders
    }

    /// Bottleneck search from `center`: extends `order` with every point whose best path from the
    /// center stays within `bound` (key = the largest distance from the center along the path).
    ///
    /// Keys only grow along a path, so the queue is monotone: a bucket queue on quantized squared
    /// distances (exact on a pixel grid) replaces a binary heap, and the first time a point is
    /// queued is already with its final key, so every point is queued and visited once.
    fn grow_disk(&mut self, center: [f64; 2], bound: f64) {
        let limit = quantize_bound(bound);
        let grew = limit > self.limit;
        if grew {
            self.limit = limit;
        }
        // Every bucket a key admitted to the queue can need, so that neither the points let in
        // from `overflow` nor the search below grow `heads`; keys of `BUCKET_KEYS` or more go to
        // the far heap.
        let admitted = self.limit;
        let buckets = (admitted as usize + 1).min(BUCKET_KEYS as usize);
        if self.heads.len() < buckets {
            self.heads.resize(buckets, NIL);
            self.occupied.resize(buckets.div_ceil(64), 0);
        }
        // The search's state as locals: its loop reads and writes them for every point reached.
        // Behind `self` (and as vectors, whose pointer and length live in memory) they were read
        // again after every store; as slices and scalars they stay in registers.
        let points = self.points;
        let epoch = self.epoch;
        let ink_bound = self.ink_bound;
        let (offsets, neighbors, coords) = (
            &points.offsets[..],
            &points.neighbors[..],
            &points.points[..],
        );
        let Sampler {
            seen,
            next,
            heads,
            occupied,
            used,
            cursor,
            queued,
            overflow,
            far,
            order,
            visible,
            first_hidden,
            ..
        } = self;
        let (seen, next, heads, occupied) = (
            &mut seen[..],
            &mut next[..],
            &mut heads[..],
            &mut occupied[..],
        );
        let (mut used_to, mut cursor_at, mut waiting) = (*used, *cursor, *queued);
        // Points reached beyond an earlier bound that this one admits join their buckets in the
        // order the list holds them after each removal (`enqueue`'s order, which fixes the order
        // within a bucket).
        if grew {
            let mut k = 0;
            while k < overflow.len() {
                let (key, p) = overflow[k];
                if key > admitted {
                    k += 1;
                    continue;
                }
                overflow.swap_remove(k);
                if key < BUCKET_KEYS {
                    let b = key as usize;
                    next[p as usize] = heads[b];
                    heads[b] = p;
                    occupied[b / 64] |= 1u64 << (b % 64);
                    used_to = used_to.max(b + 1);
                } else {
                    far.push(Reverse((key, p)));
                }
                waiting += 1;
            }
        }
        while waiting > 0 {
            // Buckets first, then (hostile input) the far heap, whose keys are all larger.
            let (key, p) = if cursor_at < used_to && cursor_at as u32 <= limit {
                // The cursor stops where stepping bucket by bucket would: at the first bucket in
                // use, else at the end of the buckets in use or past the bound.
                let end = used_to.min(limit as usize + 1);
                let Some(k) = next_occupied(occupied, cursor_at, end) else {
                    cursor_at = end;
                    continue;
                };
                cursor_at = k;
                let p = heads[k];
                let rest = next[p as usize];
                heads[k] = rest;
                if rest == NIL {
                    occupied[k / 64] &= !(1u64 << (k % 64));
                }
                (k as u32, p)
            } else {
                match far.peek() {
                    Some(&Reverse((key, p))) if key <= limit && cursor_at >= used_to => {
                        far.pop();
                        (key, p)
                    }
                    _ => break,
                }
            };
            waiting -= 1;
            order.push((key, p));
            if ink_bound {
                let q = coords[p as usize];
                if sees(points, visible, epoch, center, q) {
                    visible[p as usize] = epoch;
                } else if key < *first_hidden {
                    *first_hidden = key;
                }
            }
            for &r in neighbours(offsets, neighbors, p) {
                let mark = &mut seen[r as usize];
                if *mark == epoch {
                    continue;
                }
                *mark = epoch;
                let s = coords[r as usize];
                let d2 = (s[0] - center[0]).powi(2) + (s[1] - center[1]).powi(2);
                let key = quantize(d2).max(key);
                // `enqueue`, its common case inline: a key the queue admits, in a bucket.
                if key <= admitted && key < BUCKET_KEYS {
                    let k = key as usize;
                    next[r as usize] = heads[k];
                    heads[k] = r;
                    occupied[k / 64] |= 1u64 << (k % 64);
                    waiting += 1;
                    used_to = used_to.max(k + 1);
                } else if key > admitted {
                    overflow.push((key, r));
                } else {
                    far.push(Reverse((key, r)));
                    waiting += 1;
                }
            }
        }
        (*used, *cursor, *queued) = (used_to, cursor_at, waiting);
    }

    fn enqueue(&mut self, key: u32, p: u32) {
        if key > self.limit {
            self.overflow.push((key, p));
            return;
        }
        if key >= BUCKET_KEYS {
            self.far.push(Reverse((key, p)));
            self.queued += 1;
            return;
        }
        let k = key as usize;
        if self.heads.len() <= k {
            self.heads.resize(k + 1, NIL);
            self.occupied.resize((k + 1).div_ceil(64), 0);
        }
        self.next[p as usize] = self.heads[k];
        self.heads[k] = p;
        self.occupied[k / 64] |= 1u64 << (k % 64);
        self.queued += 1;
        self.used = self.used.max(k + 1);
    }

    /// Empties the queue for the next search, keeping the bucket allocations.
    fn reset_queue(&mut self) {
        // A bucket holds a point exactly when its bit is set (a pop that empties a bucket leaves
        // `NIL` in its head and clears its bit), so only the heads of set bits need clearing:
        // most searches stop with a few buckets still in use out of the hundreds they reached.
        for (w, word) in self.occupied[..self.used.div_ceil(64)]
            .iter_mut()
            .enumerate()
        {
            let mut bits = std::mem::take(word);
            while bits != 0 {
                self.heads[w * 64 + bits.trailing_zeros() as usize] = NIL;
                bits &= bits - 1;
            }
        }
        debug_assert!(self.heads[..self.used].iter().all(|&h| h == NIL));
        self.used = 0;
        self.cursor = 0;
        self.queued = 0;
        self.limit = 0;
        self.overflow.clear();
        self.far.clear();
    }

    /// Number of points of the disk of radius `r` (a prefix of `order`).
    fn prefix(&self, r: f64) -> usize {
        let limit = quantize_bound(r);
        self.order.partition_point(|&(key, _)| key <= limit)
    }

    /// Eq. (2)-(3) on the first `count` points: (linearity, unit principal direction, mean offset).
    fn pca(&mut self, count: usize) -> (f64, [f64; 2], [f64; 2]) {
        if count == 0 {
            return (0.0, [1.0, 0.0], [0.0, 0.0]);
        }
        let [n, sx, sy, sxx, sxy, syy] = self.moments(count);
        let (mx, my) = (sx / n, sy / n);
        let cxx = sxx / n - mx * mx;
        let cxy = sxy / n - mx * my;
        let cyy = syy / n - my * my;
        let (linearity, direction) = principal(cxx, cxy, cyy);
        (linearity, direction, [mx, my])
    }

    /// The moments of the first `count` points of `order`, summed from the first point in
    /// `order`'s order (so the same sums, bit for bit, whichever counts were asked before): the
    /// running sums go on from the last count asked, or start again for a smaller one.
    fn moments(&mut self, count: usize) -> [f64; 6] {
        if count < self.summed {
            self.sums = [0.0; 6];
            self.summed = 0;
        }
        let center = self.center;
        let mut sums = self.sums;
        for &(_, p) in &self.order[self.summed..count] {
            let q = self.points.points[p as usize];
            let (dx, dy) = (q[0] - center[0], q[1] - center[1]);
            sums = [
                sums[0] + 1.0,
                sums[1] + dx,
                sums[2] + dy,
                sums[3] + dx * dx,
                sums[4] + dx * dy,
                sums[5] + dy * dy,
            ];
        }
        self.sums = sums;
        self.summed = count;
        sums
    }

    /// Number of places (up to 3) where the rim `(r - 2, r]` of the disk cuts the ink.
    ///
    /// A count of 3 stops the search early and leaves rim points marked, which a later call for
    /// the same node sees as rim points too (see `node_at`).
    fn rim_cuts(&mut self, center: [f64; 2], count: usize, r: f64) -> usize {
        let inner = (r - 2.0 * self.points.spacing).max(0.0);
        let inner2 = inner * inner;
        // Keys are never below the Euclidean distance, so rim points sit in the suffix of the
        // disk whose keys exceed the inner radius.
        let start = self.order[..count].partition_point(|&(key, _)| key <= quantize_bound(inner));
        let points = self.points;
        let (offsets, neighbors, coords) = (
            &points.offsets[..],
            &points.neighbors[..],
            &points.points[..],
        );
        let epoch = self.epoch;
        let Sampler {
            order,
            rim_seen,
            stack,
            ..
        } = self;
        // The marks as a slice and the point set's arrays taken out once (see `grow_disk`).
        let rim_seen = &mut rim_seen[..];
        let suffix = &order[start..count];
        // Rim points are marked with the current epoch in `rim_seen`; components counted by DFS
        // from them in disk order. A second pass over the suffix finds them again without a
        // list: the only other points of the suffix marked with `epoch` are rim points left by
        // a count of 3 at a larger radius (see `node_at`), whose distance is past that larger
        // radius's inner one and so past this one's, which makes them rim points here too.
        for &(_, p) in suffix {
            let q = coords[p as usize];
            if (q[0] - center[0]).powi(2) + (q[1] - center[1]).powi(2) > inner2 {
                rim_seen[p as usize] = epoch;
            }
        }
        let mut cuts = 0;
        for &(_, start) in suffix {
            if rim_seen[start as usize] != epoch {
                continue;
            }
            cuts += 1;
            if cuts > 2 {
                return cuts;
            }
            rim_seen[start as usize] = epoch.wrapping_sub(1);
            stack.push(start);
            while let Some(p) = stack.pop() {
                for &q in neighbours(offsets, neighbors, p) {
                    if rim_seen[q as usize] == epoch {
                        rim_seen[q as usize] = epoch.wrapping_sub(1);
                        stack.push(q);
                    }
                }
            }
        }
        cuts
    }

    /// Starts a disk search at point `center` (its disk empty, the center queued) and returns
    /// the center's position.
    fn start_search(&mut self, center: u32) -> [f64; 2] {
        // Two epochs per node: `epoch` marks search/rim membership, `epoch - 1` marks rim points
        // already visited by the component search.
        self.epoch = self.epoch.wrapping_add(2);
        if self.epoch < 2 {
            self.seen.fill(0);
            self.rim_seen.fill(0);
            self.visible.fill(0);
            self.epoch = 2;
        }
        self.order.clear();
        self.reset_queue();
        self.first_hidden = u32::MAX;
        let c = self.points.points[center as usize];
        self.center = c;
        self.sums = [0.0; 6];
        self.summed = 0;
        self.seen[center as usize] = self.epoch;
        self.enqueue(0, center);
        c
    }

    /// Grows the disk around `center` (Algorithm 1, line 2), makes the node, assigns its points and
    /// updates `D` (lines 3-4), pushing frontier points onto the sampling heap. Also returns how
    /// many points the node took (hostile input).
    fn node_at(
        &mut self,
        center: u32,
        id: u32,
        frontier: &mut BinaryHeap<(TotalF64, Reverse<u32>)>,
    ) -> (Node, usize) {
        let c = self.start_search(center);

        let spacing = self.points.spacing.max(1e-9);
        // Local width (adaptation 3): w_loc = 2 max(dt) - 1 over the disk of radius max(3, 3
        // dt(c)).
        let dt_center = self.points.half_width[center as usize] as f64;
        // A center on the edge of a wide stroke (dt(c) small) would not see the stroke's middle in
        // that disk: widen the probe until it reaches past the deepest point found (at most 3x).
        let mut probe = (3.0 * spacing).max(3.0 * dt_center);
        let mut max_dt = dt_center;
        // The probes are nested prefixes of `order`: each scans only what the last did not.
        let mut scanned = 0;
        for _ in 0..3 {
            self.grow_disk(c, probe);
            let count = self.prefix(probe).max(scanned);
            max_dt = self.order[scanned..count]
                .iter()
                .map(|&(_, p)| self.points.half_width[p as usize] as f64)
                .fold(max_dt, f64::max);
            scanned = count;
            if 2.0 * max_dt + spacing <= probe {
                break;
            }
            probe = 2.0 * max_dt + spacing;
        }
        let width = (2.0 * max_dt - spacing).max(spacing);
        let r_min = match self.params.method.r_min_rule {
            RMinRule::Spacing => self.params.method.r_min_factor * spacing,
            RMinRule::StrokeWidth => (3.0 * spacing).max(self.params.method.r_min_factor * width),
        };
        let r_max = self.params.method.r_max_factor * r_min;

        // Grow r from r_min by r_growth until the disk is linear (l > threshold) with 1-2 arms.
        let mut r = r_min;
        let mut linear = false;
        // Rim cuts of the first and the last radius tried, and how many radii were tried: the tip
        // test below asks for one of them again.
        let (mut first_cuts, mut last_cuts, mut tries) = (0, 0, 0);
        loop {
            self.grow_disk(c, r);
            let count = self.prefix(r);
            if self.params.method.arms_test {
                // The arms test (adaptation 5): the rim `(r - 2, r]` of the disk must cut the ink
                // in 1 or 2 places. A crossing gives 4 cuts, a T 3, a disk that holds a whole small
                // part 0.
                last_cuts = self.rim_cuts(c, count, r);
                if tries == 0 {
                    first_cuts = last_cuts;
                }
                tries += 1;
                if !(1..=2).contains(&last_cuts) {
                    break;
                }
            }
            let (l, _, _) = self.pca(count);
            if l > self.params.method.linearity {
                linear = true;
                break;
            }
            // Nothing more to reach: the whole part is inside the disk and it is not linear.
            if self.queued == 0 && self.overflow.is_empty() {
                break;
            }
            r *= self.params.method.r_growth;
            if r > r_max {
                break;
            }
        }
        if !linear {
            r = r_min;
        }
        // Ink disks: the disk stops short of the first point hidden from its center (ink behind
        // a hole or across a gap), but keeps at least the stroke's own half-width. Its `r_min`
        // shrinks with it, so the clusters and merge groups of §3.2-3.3 take its scale.
        let mut r_min = r_min;
        let mut bounded = false;
        if self.ink_bound && self.first_hidden <= quantize_bound(r) {
            let cut = ((self.first_hidden as f64 - 1.0).max(0.0) / 4.0).sqrt();
            let cut = cut.max(0.5 * width + spacing);
            if cut < r {
                r = cut;
                r_min = r_min.min(r);
                bounded = true;
            }
        }
        let count = self.prefix(r);
        let (linearity, direction, mean) = self.pca(count);
        let pos = [c[0] + mean[0], c[1] + mean[1]];
        // A disk whose rim cuts the ink once holds the end of a stroke: refinement keeps such
        // tips (short arms of thin strokes would otherwise be contracted away).
        //
        // The disk is one the arms test already cut when it ran: the last radius when linear, else
        // `r_min`, the first. Only a count of 3 (which leaves marks, see `rim_cuts`) at a larger
        // radius makes the count at `r_min` differ from the first one, so only then is it redone.
        let cuts = if bounded {
            // A fresh epoch: earlier counts may have left rim marks (see `rim_cuts`). No search
            // of this node runs after this, so `seen` may go stale.
            self.epoch = self.epoch.wrapping_add(2);
            if self.epoch < 2 {
                self.seen.fill(0);
                self.rim_seen.fill(0);
                self.visible.fill(0);
                self.epoch = 2;
            }
            self.rim_cuts(c, count, r)
        } else if tries == 0 || (!linear && last_cuts > 2 && tries > 1) {
            self.rim_cuts(c, count, r)
        } else if linear {
            last_cuts
        } else {
            first_cuts
        };
        let tip = cuts == 1;

        // Eq. (1) in 2-D: d = |u·(p - q)| + 0.1 / (1 + |v·(p - q)|), u the principal direction.
        let (u, v) = (direction, [-direction[1], direction[0]]);
        // The points whose `D` this node set, in disk order (reusing the search stack).
        let mut taken = 0;
        self.stack.clear();
        for i in 0..count {
            let p = self.order[i].1 as usize;
            let s = self.points.points[p];
            let (dx, dy) = (s[0] - pos[0], s[1] - pos[1]);
            let d = (u[0] * dx + u[1] * dy).abs() + 0.1 / (1.0 + (v[0] * dx + v[1] * dy).abs());
            if self.owner[p] == UNOWNED {
                self.owner[p] = id;
                self.distance[p] = d;
                taken += 1;
            } else if d < self.distance[p] {
                self.distance[p] = d;
            } else {
                continue;
            }
            self.stack.push(p as u32);
        }
        // Only points that border uncovered ink can become centers; coverage only grows, so a
        // point without uncovered neighbours now never needs to enter the heap. Nor does a point
        // whose `D` this node left as it was: the node that set it pushed it with that key if it
        // bordered uncovered ink then (else it never will again), and that entry is still in
        // the heap or was already taken as a center; a second copy of the same entry would
        // only be popped and dropped.
        let mut changed = std::mem::take(&mut self.stack);
        for &p in &changed {
            if self.borders_uncovered(p) {
                frontier.push((TotalF64(self.distance[p as usize]), Reverse(p)));
            }
        }
        changed.clear();
        self.stack = changed;
        let node = Node {
            pos,
            center,
            radius: r,
            r_min,
            direction,
            linearity,
            linear,
            width,
            tip,
        };
        (node, taken)
    }
}

/// [`ExperimentParams::ink_disks`](crate::ExperimentParams::ink_disks): whether the disk point
/// at `q` is seen from the center `c`, i.e. the pixel one step from `q` toward `c` (one of the
/// two bracketing the straight line) is a point of this disk seen from `c`. Points nearer the
/// center join the disk first (their keys are smaller), so one look per point decides along the
/// whole line; the two-pixel bracket forgives the staircase of a digitized edge.
fn sees(points: &PointSet, visible: &[u32], epoch: u32, c: [f64; 2], q: [f64; 2]) -> bool {
    let Some(grid) = &points.grid else {
        return true;
    };
    let (dx, dy) = (c[0] - q[0], c[1] - q[1]);
    let m = dx.abs().max(dy.abs());
    // The center and its neighbours see each other.
    if m <= 1.0 + 1e-9 {
        return true;
    }
    let step = [q[0] + dx / m, q[1] + dy / m];
    let pixels = if dx.abs() >= dy.abs() {
        let (x, y) = (floor_i64(step[0]), floor_i64(step[1] - 0.5));
        [(x, y), (x, y + 1)]
    } else {
        let (x, y) = (floor_i64(step[0] - 0.5), floor_i64(step[1]));
        [(x, y), (x + 1, y)]
    };
    pixels.iter().any(|&(x, y)| {
        grid.point_at(x, y)
            .is_some_and(|p| visible[p as usize] == epoch)
    })
}

/// [`PointSet::neighbors_of`] over the point set's CSR arrays taken out as slices once (the
/// same lists, none where the offsets do not give one), for the searches' inner loops.
#[inline]
fn neighbours<'n>(offsets: &'n [u32], neighbors: &'n [u32], p: u32) -> &'n [u32] {
    let p = p as usize;
    match (offsets.get(p), offsets.get(p + 1)) {
        (Some(&start), Some(&end)) => neighbors.get(start as usize..end as usize).unwrap_or(&[]),
        _ => &[],
    }
}

/// The first bucket at or after `from` and before `end` whose bit is set in `occupied` (which
/// covers at least `end` buckets).
fn next_occupied(occupied: &[u64], from: usize, end: usize) -> Option<usize> {
    let mut word = from / 64;
    let mut bits = occupied[word] & (u64::MAX << (from % 64));
    loop {
        if bits != 0 {
            let k = word * 64 + bits.trailing_zeros() as usize;
            return (k < end).then_some(k);
        }
        word += 1;
        if word * 64 >= end {
            return None;
        }
        bits = occupied[word];
    }
}

/// Squared distances in quarter units: exact for pixel centers (integer squared distances).
fn quantize(d2: f64) -> u32 {
    (d2 * 4.0 + 0.5).min(u32::MAX as f64 / 2.0) as u32
}

/// The largest key inside radius `r`.
fn quantize_bound(r: f64) -> u32 {
    floor_f64(r * r * 4.0 + 1e-6).min(u32::MAX as f64 / 2.0) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift64*), so that the cases are the same every run.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }

        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }

        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The pixels of a random `w` x `h` mask (each pixel ink with probability `fill`) as points at
    /// pixel centers with their 8-neighbours.
    fn pixel_points(rng: &mut Rng, w: i64, h: i64, fill: f64) -> PointSet {
        let mut index = vec![u32::MAX; (w * h) as usize];
        let mut points = PointSet {
            spacing: 1.0,
            ..PointSet::default()
        };
        for y in 0..h {
            for x in 0..w {
                if rng.unit() < fill {
                    index[(y * w + x) as usize] = points.points.len() as u32;
                    points.points.push([x as f64 + 0.5, y as f64 + 0.5]);
                }
            }
        }
        let mut lists = vec![Vec::new(); points.points.len()];
        for y in 0..h {
            for x in 0..w {
                let p = index[(y * w + x) as usize];
                if p == u32::MAX {
                    continue;
                }
                for (dx, dy) in [
                    (-1, -1),
                    (0, -1),
                    (1, -1),
                    (-1, 0),
                    (1, 0),
                    (-1, 1),
                    (0, 1),
                    (1, 1),
                ] {
                    let (u, v) = (x + dx, y + dy);
                    if (0..w).contains(&u) && (0..h).contains(&v) {
                        let q = index[(v * w + u) as usize];
                        if q != u32::MAX {
                            lists[p as usize].push(q);
                        }
                    }
                }
            }
        }
        points.half_width = vec![1.0; points.points.len()];
        points.set_neighbors_symmetric(&lists);
        points
    }

    /// `n` points at random real coordinates, each linked to a few random others.
    fn scattered_points(rng: &mut Rng, n: usize, size: f64) -> PointSet {
        let mut points = PointSet {
            points: (0..n)
                .map(|_| [rng.unit() * size, rng.unit() * size])
                .collect(),
            half_width: vec![1.0; n],
            spacing: 1.0,
            ..PointSet::default()
        };
        let lists: Vec<Vec<u32>> = (0..n)
            .map(|_| {
                (0..rng.below(4))
                    .map(|_| rng.below(n as u64) as u32)
                    .collect()
            })
            .collect();
        points.set_neighbors_symmetric(&lists);
        points
    }

    /// The disk search as it was written before the buckets in use were kept in a bitmap: the
    /// cursor steps through every bucket, empty or not, each bucket a stack. Returns `(key,
    /// point)` in the order the points join the disk, and the length of that list after each
    /// bound.
    fn stepping_search(
        points: &PointSet,
        center: u32,
        bounds: &[f64],
    ) -> (Vec<(u32, u32)>, Vec<usize>) {
        let c = points.points[center as usize];
        let mut buckets: Vec<Vec<u32>> = vec![vec![center]];
        let mut seen = vec![false; points.len()];
        seen[center as usize] = true;
        let (mut cursor, mut queued, mut limit) = (0usize, 1usize, 0u32);
        let mut overflow: Vec<(u32, u32)> = Vec::new();
        let (mut order, mut lengths) = (Vec::new(), Vec::new());
        for &bound in bounds {
            let new_limit = quantize_bound(bound);
            if new_limit > limit {
                limit = new_limit;
                let mut k = 0;
                while k < overflow.len() {
                    let (key, p) = overflow[k];
                    if key <= limit {
                        overflow.swap_remove(k);
                        if buckets.len() <= key as usize {
                            buckets.resize(key as usize + 1, Vec::new());
                        }
                        buckets[key as usize].push(p);
                        queued += 1;
                    } else {
                        k += 1;
                    }
                }
            }
            while queued > 0 && cursor < buckets.len() && cursor as u32 <= limit {
                let Some(p) = buckets[cursor].pop() else {
                    cursor += 1;
                    continue;
                };
                queued -= 1;
                let key = cursor as u32;
                order.push((key, p));
                for &r in points.neighbors_of(p) {
                    if std::mem::replace(&mut seen[r as usize], true) {
                        continue;
                    }
                    let s = points.points[r as usize];
                    let d2 = (s[0] - c[0]).powi(2) + (s[1] - c[1]).powi(2);
                    let key = quantize(d2).max(key);
                    if key <= limit {
                        if buckets.len() <= key as usize {
                            buckets.resize(key as usize + 1, Vec::new());
                        }
                        buckets[key as usize].push(r);
                        queued += 1;
                    } else {
                        overflow.push((key, r));
                    }
                }
            }
            lengths.push(order.len());
        }
        (order, lengths)
    }

    /// The moments of the first `count` points of `order`, summed one by one from zero.
    fn summed_moments(
        points: &PointSet,
        order: &[(u32, u32)],
        c: [f64; 2],
        count: usize,
    ) -> [f64; 6] {
        let mut sums = [0.0f64; 6];
        for &(_, p) in &order[..count] {
            let q = points.points[p as usize];
            let (dx, dy) = (q[0] - c[0], q[1] - c[1]);
            sums = [
                sums[0] + 1.0,
                sums[1] + dx,
                sums[2] + dy,
                sums[3] + dx * dx,
                sums[4] + dx * dy,
                sums[5] + dy * dy,
            ];
        }
        sums
    }

    #[test]
    fn next_occupied_finds_the_first_set_bit_in_range() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..2000 {
            let words = 1 + rng.below(5) as usize;
            let density = rng.below(40) + 1;
            let occupied: Vec<u64> = (0..words)
                .map(|_| (0..64).fold(0u64, |w, b| w | (u64::from(rng.below(density) == 0) << b)))
                .collect();
            let end = 1 + rng.below(words as u64 * 64) as usize;
            let from = rng.below(end as u64) as usize;
            let stepped = (from..end).find(|&k| occupied[k / 64] >> (k % 64) & 1 == 1);
            assert_eq!(
                next_occupied(&occupied, from, end),
                stepped,
                "{from}..{end}"
            );
        }
    }

    /// The disk search jumping over empty buckets visits the points in the order the stepping
    /// search did, with the same keys, bound after bound; the moments summed when asked equal
    /// the running sums kept per point before, bit for bit, whatever order the counts come in.
    #[test]
    fn disk_search_matches_the_stepping_search() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let params = Params::default();
        for case in 0..240 {
            let points = if case % 3 == 2 {
                let (n, size) = (30 + rng.below(200) as usize, 6.0 + rng.unit() * 60.0);
                scattered_points(&mut rng, n, size)
            } else {
                let (w, h) = (1 + rng.below(40) as i64, 1 + rng.below(40) as i64);
                let fill = 0.2 + 0.8 * rng.unit();
                pixel_points(&mut rng, w, h, fill)
            };
            if points.is_empty() {
                continue;
            }
            let mut sampler = Sampler::new(&points, &params);
            for _ in 0..6 {
                let center = rng.below(points.len() as u64) as u32;
                let mut bounds = Vec::new();
                let mut r = rng.unit() * 3.0;
                for _ in 0..1 + rng.below(6) {
                    bounds.push(r);
                    // Now and then the same bound twice.
                    if rng.below(4) > 0 {
                        r += rng.unit() * 8.0;
                    }
                }
                let (expected, lengths) = stepping_search(&points, center, &bounds);
                let c = sampler.start_search(center);
                for (&bound, &length) in bounds.iter().zip(&lengths) {
                    sampler.grow_disk(c, bound);
                    assert_eq!(
                        sampler.order,
                        expected[..length],
                        "case {case}, bound {bound}"
                    );
                }
                for _ in 0..8 {
                    let count = rng.below(sampler.order.len() as u64 + 1) as usize;
                    let want = summed_moments(&points, &sampler.order, c, count);
                    if count == 0 {
                        continue;
                    }
                    let got = sampler.moments(count);
                    assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "case {case}");
                }
            }
        }
    }
}
