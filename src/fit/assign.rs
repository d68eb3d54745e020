//! §3.4 "every original point is associated with one of the nodes that is the nearest", made to
//! respect ink components (docs/design.md, adaptation 12): a multi-source shortest-path search over
//! the point neighbour graph from the point nearest to each fitted node, i.e. a geodesic Voronoi
//! partition. Two strokes a pixel apart never trade points, which Euclidean nearest-node assignment
//! would do.

use super::math::distance;
use crate::csr::Csr;
use crate::geometry::floor_i64;
use crate::point_set::PointSet;

/// Points grouped by an index (old graph nodes or fitted nodes), in CSR form.
#[derive(Clone, Debug, Default)]
pub struct Groups {
    members: Csr<u32>,
}

impl Groups {
    /// Groups points by `label`; labels `>= groups` (e.g. "unassigned") are left out.
    pub fn new(label: &[u32], groups: usize) -> Self {
        let members = Csr::build(groups, |sink| {
            for (p, &l) in label.iter().enumerate() {
                if (l as usize) < groups {
                    sink.push(l as usize, p as u32);
                }
            }
        });
        Groups { members }
    }

    /// The points of group `i` (empty for an unknown group).
    pub fn of(&self, i: usize) -> &[u32] {
        if i >= self.members.rows() {
            return &[];
        }
        self.members.row(i)
    }
}

/// Distances are quantized to a tenth of the point spacing so that the search can use a bucket
/// queue (Dial's algorithm): O(N) instead of a heap's O(N log N).
const STEPS_PER_SPACING: f64 = 10.0;
/// Longest single step, in quanta: longer k-NN links (outliers) are clamped so the circular bucket
/// array stays small.
const MAX_STEP: u32 = 1000;
const BUCKETS: usize = 2048;

/// Labels every point with the fitted node (`sites`) nearest to it along the neighbour graph.
///
/// Each site starts from one point: the ink pixel under it when that pixel is in the site's own
/// component (`site_components[i]`, labels from `components`), or else the nearest point owned
/// by the old nodes `near[i]` it was resampled between. Points no search reaches (a component without
/// any site) are left out.
///
/// One search runs over all sites at once. Ink components never exchange points, and each
/// component's pushes keep their order in the shared buckets, so every component gets the same
/// partition (ties included) as a search of its own would give; a large input reaches here cut
/// into chunks of whole components (`PointSet::chunks_of`), so the working set stays a
/// chunk's.
pub fn assign(
    points: &PointSet,
    components: &[u32],
    site_components: &[Option<u32>],
    owned: &Groups,
    sites: &[[f64; 2]],
    near: &[[u32; 2]],
    unit: f64,
) -> Groups {
    let n = points.len();
    // A point set without its neighbour arrays still gets its sources labelled.
    let linked = points.offsets.len() == n + 1;
    let neighbors_of = |p: u32| if linked { points.neighbors_of(p) } else { &[] };

    let per_unit = STEPS_PER_SPACING / unit;
    // Rounds by truncation after adding one half (d >= 0): `f64::round` is a library call.
    let quantize = |d: f64| (d * per_unit + 0.5).min(MAX_STEP as f64) as u32;
    // (distance in quanta, site) per point, side by side: one cache line per visit.
    let mut state = vec![(u32::MAX, u32::MAX); n];
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); BUCKETS];
    let mut pending = 0usize;
    for (i, (&site, pair)) in sites.iter().zip(near).enumerate() {
        if let (Some(grid), Some(&later)) = (&points.grid, sites.get(i + AHEAD_SITE)) {
            // Truncation, not `floor`: a hint needs no exact cell.
            let x = (later[0] as i64).saturating_sub(grid.x0);
            let y = (later[1] as i64).saturating_sub(grid.y0);
            if (0..grid.width as i64).contains(&x) && (0..grid.height as i64).contains(&y) {
                prefetch(&grid.index[y as usize * grid.width as usize + x as usize]);
            }
        }
        let own = site_components.get(i).copied().flatten();
        let Some(p) = source(points, components, own, owned, site, pair) else {
            continue;
        };
        let d = quantize(distance(site, points.points[p as usize]));
        if d < state[p as usize].0 {
            state[p as usize] = (d, i as u32);
            buckets[d as usize % BUCKETS].push(p);
            pending += 1;
        }
    }
    let mut current = 0usize;
    while pending > 0 {
        let slot = current % BUCKETS;
        let mut bucket = std::mem::take(&mut buckets[slot]);
        pending -= bucket.len();
        for (j, &p) in bucket.iter().enumerate() {
            if linked {
                ahead(points, &state, &bucket, j);
            }
            let (reached, owner) = state[p as usize];
            if reached as usize != current {
                continue; // superseded by a shorter path
            }
            let here = points.points[p as usize];
            for &q in neighbors_of(p) {
                if state[q as usize].0 as usize <= current {
                    continue; // settled: spare the distance
                }
                let step = quantize(distance(here, points.points[q as usize])).max(1);
                let d = current as u32 + step;
                if d < state[q as usize].0 {
                    state[q as usize] = (d, owner);
                    // step <= MAX_STEP < BUCKETS: never the slot being drained.
                    buckets[d as usize % BUCKETS].push(q);
                    pending += 1;
                }
            }
        }
        bucket.clear();
        buckets[slot] = bucket;
        current += 1;
    }
    let label: Vec<u32> = state.into_iter().map(|(_, site)| site).collect();
    Groups::new(&label, sites.len())
}

/// The point a site's search starts from.
fn source(
    points: &PointSet,
    components: &[u32],
    own: Option<u32>,
    owned: &Groups,
    site: [f64; 2],
    near: &[u32; 2],
) -> Option<u32> {
    if let Some(grid) = &points.grid {
        if let Some(p) = grid.point_at(floor_i64(site[0]), floor_i64(site[1])) {
            // The pixel under a site between two strokes may belong to the neighbouring
            // component; the search from it would claim that component's points.
            let same = own.is_none_or(|c| components.get(p as usize) == Some(&c));
            if (p as usize) < points.len() && same {
                return Some(p);
            }
        }
    }
    let mut best: Option<(f64, u32)> = None;
    let pair: &[u32] = if near[0] == near[1] {
        &near[..1]
    } else {
        &near[..]
    };
    for &old in pair {
        // A node of a huge blob can own millions of points; a regular subsample keeps this
        // bounded (the search from the source corrects a slightly farther start).
        let members = owned.of(old as usize);
        let stride = members.len().div_ceil(2048).max(1);
        for (k, &p) in members.iter().enumerate().step_by(stride) {
            if let Some(&later) = members.get(k + AHEAD_MEMBER * stride) {
                prefetch(&points.points[later as usize]);
            }
            let q = points.points[p as usize];
            let d = (q[0] - site[0]).powi(2) + (q[1] - site[1]).powi(2);
            let closer = match best {
                None => true,
                Some((b, bp)) => d < b || (d == b && p < bp),
            };
            if closer {
                best = Some((d, p));
            }
        }
    }
    best.map(|(_, p)| p)
}

/// Prefetch distances (bucket entries ahead of the one being settled) for a point's own data,
/// its neighbour list and its neighbours' data: each level needs the one before it in cache.
const AHEAD_POINT: usize = 16;
const AHEAD_LIST: usize = 8;
const AHEAD_NEIGHBORS: usize = 4;
/// Prefetch distances of the sources: sites ahead for the grid cell under them, members ahead in
/// the scan of an off-ink site's old nodes.
const AHEAD_SITE: usize = 8;
const AHEAD_MEMBER: usize = 8;

/// Asks for the memory that settling `bucket[j + ...]` will read.
#[inline(always)]
fn ahead(points: &PointSet, state: &[(u32, u32)], bucket: &[u32], j: usize) {
    if let Some(&a) = bucket.get(j + AHEAD_POINT) {
        prefetch(&points.offsets[a as usize]);
        prefetch(&points.points[a as usize]);
        prefetch(&state[a as usize]);
    }
    if let Some(&a) = bucket.get(j + AHEAD_LIST) {
        prefetch(&points.neighbors[points.offsets[a as usize] as usize..]);
    }
    if let Some(&a) = bucket.get(j + AHEAD_NEIGHBORS) {
        let list = points.neighbors_of(a);
        // Neighbour lists are sorted by index: the first and last are the rows above and below.
        if let (Some(&first), Some(&last)) = (list.first(), list.last()) {
            prefetch(&state[first as usize]);
            prefetch(&state[last as usize]);
            prefetch(&points.points[first as usize]);
            prefetch(&points.points[last as usize]);
        }
    }
}

#[inline(always)]
fn prefetch<T: ?Sized>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint; it never faults and reads nothing into the program.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            x as *const T as *const i8,
        )
    }
}
