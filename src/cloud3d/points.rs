//! The 3D point set `P`: duplicates dropped, pixel-like units (`Dis_ave` near 1, as in the plane,
//! docs/design.md "Hostile input"), symmetric `k`-nearest-neighbour lists (§3.2) from a k-d tree,
//! the parts of that graph, and each point's local tube diameter from the PCA of §3.1.

use std::collections::HashSet;

use foldhash::fast::FixedState;

use kiddo::ImmutableKdTree;
use petgraph::unionfind::UnionFind;

use super::math::{eigen, linearity, tube_diameter, Moments, V3};
use crate::csr::symmetric_from_lists;
use crate::error::{Error, Result};
use crate::params::Params;
use crate::point_index::{
    check_extent, cross_pairs, joined_parts, k_nearest, power_of_two_near, sparse_points, z_order,
    Cells,
};

/// How far, in its own `k`-th neighbour distances, a point reaches for a point of another part
/// (the plane's rule, `point_list`: random points leave clumps cut off the tube they lie in).
const ISLAND_REACH: f64 = 2.0;

/// Fewest points in a window for its covariance to say anything about the tube.
const WINDOW_MIN_POINTS: f64 = 20.0;

/// A window is a piece of tube when linear by Eq. (3) at §3.1's threshold.
const WINDOW_LINEARITY: f64 = 0.9;

/// A set is tube-shaped when at least this share of its windowed points lie in a linear window
/// at some scale (the plane's `NOT_STRIP_SHARE`).
const NOT_TUBE_SHARE: f64 = 0.5;

/// The point set in pipeline units.
#[derive(Clone, Debug, Default)]
pub(super) struct Cloud {
    pub points: Vec<V3>,
    /// CSR offsets into `neighbors`.
    pub offsets: Vec<u32>,
    pub neighbors: Vec<u32>,
    /// `Dis_ave`.
    pub spacing: f64,
    /// Local tube diameter at each point.
    pub width: Vec<f64>,
    /// Component of the neighbour graph each point belongs to.
    pub part: Vec<u32>,
}

impl Cloud {
    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn neighbors_of(&self, i: u32) -> &[u32] {
        &self.neighbors[self.offsets[i as usize] as usize..self.offsets[i as usize + 1] as usize]
    }
}

/// The list's units and back: translated to its bounding box's corner, divided by a power of two.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Units {
    pub origin: V3,
    pub scale: f64,
}

impl Units {
    pub fn to_list(self, p: V3) -> V3 {
        [
            p[0] * self.scale + self.origin[0],
            p[1] * self.scale + self.origin[1],
            p[2] * self.scale + self.origin[2],
        ]
    }
}

/// A point is sparse when its `k`-th nearest neighbour is more than this many times farther than
/// the median point's (the plane's `SPARSE_REACH`: a thousandfold sparser in space).
const SPARSE_REACH: f64 = 10.0;

/// [`cloud`]'s answer: the cloud in pipeline units, its units, `Some(share)` when the set is not
/// tube-shaped (only `share` of its windowed points lie in a linear window), and how many
/// distinct points were left out as a sparse cloud around the tubes.
pub(super) type Built = (Cloud, Units, Option<f64>, usize);

/// Builds the cloud of `list` in pipeline units, after leaving out the points of a sparse cloud
/// around the tubes (the plane's rule, `point_list`'s `sparse_outliers`): points far sparser
/// than the set's own sampling ([`SPARSE_REACH`]) that, taken alone at their own spacing, are
/// not tube-shaped either. A part sampled as sparsely but shaped as a tube stays.
pub(super) fn cloud(list: &[V3], params: &Params) -> Result<Built> {
    match cloud_once(list, params, true)? {
        Prepared::Ready(built) => Ok(built),
        Prepared::LeaveOut(kept) => {
            let left_out = distinct(list).len() - kept.len();
            match cloud_once(&kept, params, false)? {
                Prepared::Ready((cloud, units, not_tube, _)) => {
                    Ok((cloud, units, not_tube, left_out))
                }
                Prepared::LeaveOut(_) => Err(Error::InvalidParams(
                    "points left out twice (an internal error)".to_string(),
                )),
            }
        }
    }
}

/// [`cloud_once`]'s answer: the cloud, or the distinct points to trace instead (the sparse
/// cloud around them left out).
enum Prepared {
    Ready(Built),
    LeaveOut(Vec<V3>),
}

/// Exact repeats dropped, keeping the first occurrence; `-0.0` equals `0.0`.
fn distinct(list: &[V3]) -> Vec<V3> {
    let mut seen = HashSet::with_capacity_and_hasher(list.len(), FixedState::default());
    list.iter()
        .map(|p| [p[0] + 0.0, p[1] + 0.0, p[2] + 0.0])
        .filter(|p| seen.insert(p.map(f64::to_bits)))
        .collect()
}

/// The distinct points' sparse cloud around the tubes, as flags, when there is one (see
/// [`cloud`]); `local` are the points in any units, `reach` their `k`-th neighbour distances.
fn sparse_outliers(local: &[V3], reach: &[f64], k: usize) -> Result<Option<Vec<bool>>> {
    let Some((sparse, alone)) = sparse_points(local, reach, SPARSE_REACH) else {
        return Ok(None);
    };
    let k = k.min(alone.len() - 1);
    if k > 0 {
        let (offsets, neighbors, spacing, _, part) = nearest_neighbours(&alone, k)?;
        let (_, linear, windowed) = tube_widths(&alone, spacing, &part, &offsets, &neighbors);
        if windowed > 0 && linear as f64 >= NOT_TUBE_SHARE * windowed as f64 {
            return Ok(None);
        }
    }
    Ok(Some(sparse))
}

/// [`cloud`] on one list; with `leave_out`, a sparse cloud found is answered instead.
fn cloud_once(list: &[V3], params: &Params, leave_out: bool) -> Result<Prepared> {
    if list.len() as u64 > params.front_end.limits.max_points {
        return Err(Error::Limit {
            what: "points",
            actual: list.len() as u64,
            limit: params.front_end.limits.max_points,
            field: "limits.max_points",
        });
    }
    if let Some(i) = list.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        let p = list[i];
        return Err(Error::PointParse {
            line: i + 1,
            message: format!(
                "point {} ({}, {}, {}) is not finite",
                i + 1,
                p[0],
                p[1],
                p[2]
            ),
        });
    }
    let points = distinct(list);
    let n = points.len();
    if n == 0 {
        let cloud = Cloud {
            offsets: vec![0],
            spacing: 1.0,
            ..Cloud::default()
        };
        let units = Units {
            origin: [0.0; 3],
            scale: 1.0,
        };
        return Ok(Prepared::Ready((cloud, units, None, 0)));
    }
    let min = points.iter().fold([f64::INFINITY; 3], |m, p| {
        [m[0].min(p[0]), m[1].min(p[1]), m[2].min(p[2])]
    });
    let extent = points.iter().fold(0.0f64, |m, p| {
        m.max(p[0] - min[0]).max(p[1] - min[1]).max(p[2] - min[2])
    });
    check_extent(extent)?;
    // Powers of two only, so every rescaling is exact: first the extent to about 1, then
    // `Dis_ave` to about 1.
    let coarse = power_of_two_near(extent);
    let mut local: Vec<V3> = points
        .iter()
        .map(|p| {
            [
                (p[0] - min[0]) / coarse,
                (p[1] - min[1]) / coarse,
                (p[2] - min[2]) / coarse,
            ]
        })
        .collect();
    let k = params.method.k.min(n - 1);
    let (offsets, neighbors, spacing, reach, part) = if k == 0 {
        (
            vec![0; n + 1],
            Vec::new(),
            1.0,
            Vec::new(),
            (0..n as u32).collect(),
        )
    } else {
        nearest_neighbours(&local, k)?
    };
    if leave_out && k > 0 {
        if let Some(sparse) = sparse_outliers(&local, &reach, k)? {
            let kept = points
                .iter()
                .zip(&sparse)
                .filter(|(_, &s)| !s)
                .map(|(p, _)| *p)
                .collect();
            return Ok(Prepared::LeaveOut(kept));
        }
    }
    let fine = if k == 0 {
        1.0
    } else {
        power_of_two_near(spacing)
    };
    for p in &mut local {
        *p = [p[0] / fine, p[1] / fine, p[2] / fine];
    }
    let spacing = if k == 0 { 1.0 } else { spacing / fine };
    let (width, linear, windowed) = tube_widths(&local, spacing, &part, &offsets, &neighbors);
    let not_tube = (windowed > 0 && (linear as f64) < NOT_TUBE_SHARE * windowed as f64)
        .then(|| linear as f64 / windowed as f64);
    let units = Units {
        origin: min,
        scale: coarse * fine,
    };
    let cloud = Cloud {
        points: local,
        offsets,
        neighbors,
        spacing,
        width,
        part,
    };
    Ok(Prepared::Ready((cloud, units, not_tube, 0)))
}

/// Symmetric `k` nearest neighbours (§3.2) as CSR, joined across islands, `Dis_ave`, each
/// point's `k`-th neighbour distance and the parts (components) of that graph.
#[allow(clippy::type_complexity)]
fn nearest_neighbours(
    points: &[V3],
    k: usize,
) -> Result<(Vec<u32>, Vec<u32>, f64, Vec<f64>, Vec<u32>)> {
    let n = points.len();
    let tree: ImmutableKdTree<f64, 3> = ImmutableKdTree::new_from_slice(points)
        .map_err(|e| Error::InvalidParams(format!("cannot index the points: {e:?}")))?;
    let order = z_order(points);
    let (lists, nearest) = k_nearest(points, &tree, &order, k);
    let spacing = nearest.iter().map(|d| d.0).sum::<f64>() / n as f64;
    // Islands: a point reaches every point of another component within twice its `k`-th
    // neighbour distance.
    let mut sets = UnionFind::<u32>::new(n);
    for (i, list) in lists.chunks(k).enumerate() {
        for &j in list.iter().filter(|&&j| j != u32::MAX) {
            sets.union(i as u32, j);
        }
    }
    let labels = sets.into_labeling();
    let bridges: Vec<(u32, u32)> = if labels.iter().all(|&l| l == labels[0]) {
        Vec::new()
    } else {
        cross_pairs(points, &tree, &order, &labels, |i| {
            ISLAND_REACH * nearest[i].1
        })
    };
    drop(tree);
    // The parts: the components the bridges join.
    let part = joined_parts(labels, &bridges);
    let (offsets, neighbors) = symmetric_from_lists(n, &lists, k, &bridges);
    Ok((
        offsets,
        neighbors,
        spacing,
        nearest.iter().map(|d| d.1).collect(),
        part,
    ))
}

/// Local tube diameters from the PCA of §3.1 (Eq. (2)-(3) with three axes): windows of 3 x 3 x 3
/// cubic cells of side `c` around each point's cell, from per-cell moments of the point's own
/// part, at `c = 2 Dis_ave, 4 Dis_ave, ...`; a point takes the first window that is linear by
/// Eq. (3) and at least twice as long as the diameter it measures there (below that the window is
/// filled and isotropic, and measures its own size). Points no window measures (in a junction, a
/// crossing) take the diameter of the nearest point that has one, by hops; a part no window
/// measures gets `3 Dis_ave`. Also returns how many points were ever in a linear window and how
/// many ever in a window of enough points (the not-tube-shaped test).
fn tube_widths(
    points: &[V3],
    spacing: f64,
    part: &[u32],
    offsets: &[u32],
    neighbors: &[u32],
) -> (Vec<f64>, usize, usize) {
    let n = points.len();
    let extent = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0]).max(p[1]).max(p[2]));
    let mut measured = vec![f64::NAN; n];
    let mut windowed = vec![false; n];
    let mut cell = 2.0 * spacing;
    let mut cells: Option<Cells<3>> = None;
    let mut moments: Vec<Moments> = Vec::new();
    while measured.iter().any(|m| m.is_nan()) && cell <= 2.0 * extent.max(spacing) {
        let grid = match cells.take() {
            None => Cells::new(points, part, cell),
            Some(finer) => finer.coarser(points, part, 0.5 * cell),
        };
        // Moments per cell about its corner, summed in point order.
        moments.clear();
        moments.resize(grid.keys.len(), Moments::default());
        for (p, &slot) in points.iter().zip(&grid.point_slot) {
            let c = grid.keys[slot as usize].1;
            let corner = [c[0] as f64 * cell, c[1] as f64 * cell, c[2] as f64 * cell];
            moments[slot as usize].add([p[0] - corner[0], p[1] - corner[1], p[2] - corner[2]]);
        }
        let measure = |_: &(u32, [i64; 3]), slots: &[u32]| -> Option<f64> {
            let mut window = Moments::default();
            for dz in -1..=1i64 {
                for dy in -1..=1i64 {
                    for dx in -1..=1i64 {
                        let slot = slots[(9 * (dz + 1) + 3 * (dy + 1) + dx + 1) as usize];
                        if slot != u32::MAX {
                            let offset = [dx as f64 * cell, dy as f64 * cell, dz as f64 * cell];
                            window.add_shifted(&moments[slot as usize], offset);
                        }
                    }
                }
            }
            if window.n < WINDOW_MIN_POINTS {
                return None;
            }
            let (values, _) = eigen(window.covariance());
            let diameter = tube_diameter(values);
            Some(
                if linearity(values) > WINDOW_LINEARITY && 3.0 * cell >= 2.0 * diameter {
                    diameter
                } else {
                    f64::NAN
                },
            )
        };
        let per_cell: Vec<Option<f64>> = grid.windows(measure);
        for i in 0..n {
            if !measured[i].is_nan() {
                continue;
            }
            if let Some(d) = per_cell[grid.point_slot[i] as usize] {
                windowed[i] = true;
                measured[i] = d;
            }
        }
        cells = Some(grid);
        cell *= 2.0;
    }
    let linear = measured.iter().filter(|m| m.is_finite()).count();
    let windowed = windowed.iter().filter(|&&w| w).count();
    // Breadth first from every measured point at once, in index order.
    let mut queue: std::collections::VecDeque<u32> = (0..n as u32)
        .filter(|&i| measured[i as usize].is_finite())
        .collect();
    while let Some(p) = queue.pop_front() {
        let value = measured[p as usize];
        for &q in &neighbors[offsets[p as usize] as usize..offsets[p as usize + 1] as usize] {
            if !measured[q as usize].is_finite() {
                measured[q as usize] = value;
                queue.push_back(q);
            }
        }
    }
    let fallback = 3.0 * spacing;
    let width = measured
        .into_iter()
        .map(|m| {
            if m.is_finite() {
                m.max(spacing)
            } else {
                fallback
            }
        })
        .collect();
    (width, linear, windowed)
}
