//! Spatial indexing shared by point lists in the plane (`point_list`) and in space (`cloud3d`),
//! generic over the dimension `D`: the `k` nearest neighbours of every point (§3.2), the pairs
//! that join islands of the `k`-nearest-neighbour graph to the strip around them, and square or
//! cubic cells of a doubling side holding the moments of the windowed PCA (§3.1, Eq. (2)).
//!
//! Every function here gives what a direct loop over the points in index order gives, byte for
//! byte; the order of the work is chosen for speed only. Queries are run in the points' order
//! along a Z-order (Morton) curve, so consecutive queries visit the same leaves of the k-d tree
//! and the time stays near linear in the number of points however the input is ordered (random
//! points in random order made every query a cache miss).

use std::num::NonZero;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use crate::error::{Error, Result};

/// Coordinates are translated so the smallest is 0; an extent beyond this would overflow squared
/// distances.
const MAX_EXTENT: f64 = 1e150;

/// An error unless points translated so the smallest coordinate is 0 span at most
/// [`MAX_EXTENT`] (and no coordinate is NaN).
pub(crate) fn check_extent(extent: f64) -> Result<()> {
    if extent.is_nan() || extent > MAX_EXTENT {
        return Err(Error::InvalidParams(format!(
            "the points span {extent:e} units; at most {MAX_EXTENT:e} is supported"
        )));
    }
    Ok(())
}

/// The power of two nearest `x` on a log scale (1 for anything not positive and finite), so that
/// rescaling by it is exact short of underflow.
pub(crate) fn power_of_two_near(x: f64) -> f64 {
    if x.is_finite() && x > 0.0 {
        2f64.powi(x.log2().round().clamp(-1000.0, 1000.0) as i32)
    } else {
        1.0
    }
}

/// Points per parallel batch of queries: consecutive along the Z-order curve.
const QUERY_BATCH: usize = 1024;

/// The indices of `points` in Z-order over their bounding box (ties by index), a permutation.
pub(crate) fn z_order<const D: usize>(points: &[[f64; D]]) -> Vec<u32> {
    let mut low = [f64::INFINITY; D];
    let mut high = [f64::NEG_INFINITY; D];
    for p in points {
        for d in 0..D {
            low[d] = low[d].min(p[d]);
            high[d] = high[d].max(p[d]);
        }
    }
    let bits = (64 / D).min(21) as u32;
    let top = ((1u64 << bits) - 1) as f64;
    let mut codes: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            let mut code = 0u64;
            for d in 0..D {
                let span = high[d] - low[d];
                let t = if span > 0.0 {
                    ((p[d] - low[d]) / span * top).clamp(0.0, top)
                } else {
                    0.0
                };
                let q = t as u64;
                for b in 0..bits {
                    code |= ((q >> b) & 1) << (b as usize * D + d);
                }
            }
            (code, i as u32)
        })
        .collect();
    codes.par_sort_unstable();
    codes.into_iter().map(|(_, i)| i).collect()
}

/// The `k` nearest other points of every point, nearest first (ties by index, so the choice
/// never depends on the tree's layout), as `n * k` slots (`u32::MAX` where there are fewer), and
/// for each point the distances to its nearest and its `k`-th. Needs `k >= 1` and distinct points.
pub(crate) fn k_nearest<const D: usize>(
    points: &[[f64; D]],
    tree: &ImmutableKdTree<f64, D>,
    order: &[u32],
    k: usize,
) -> (Vec<u32>, Vec<(f64, f64)>) {
    let n = points.len();
    let wanted = NonZero::new(k + 1).unwrap_or(NonZero::<usize>::MIN);
    // Answers in query order, then put back in index order.
    let mut ordered = vec![u32::MAX; n * k];
    let mut distances = vec![(0.0, 0.0); n];
    ordered
        .par_chunks_mut(k * QUERY_BATCH)
        .zip(distances.par_chunks_mut(QUERY_BATCH))
        .zip(order.par_chunks(QUERY_BATCH))
        .for_each(|((lists, near), batch)| {
            for ((list, near), &i) in lists.chunks_mut(k).zip(near.iter_mut()).zip(batch) {
                let mut found = tree
                    .query(&points[i as usize])
                    .nearest_n::<SquaredEuclidean<f64>>(wanted)
                    .execute();
                found.retain(|r| r.item != i);
                found.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.item.cmp(&b.item)));
                for (slot, r) in list.iter_mut().zip(&found) {
                    *slot = r.item;
                }
                *near = (
                    found.first().map_or(0.0, |r| r.distance.sqrt()),
                    found.get(k - 1).map_or(0.0, |r| r.distance.sqrt()),
                );
            }
        });
    let mut lists = vec![u32::MAX; n * k];
    let mut nearest = vec![(0.0, 0.0); n];
    for (at, &i) in order.iter().enumerate() {
        let i = i as usize;
        lists[i * k..(i + 1) * k].copy_from_slice(&ordered[at * k..(at + 1) * k]);
        nearest[i] = distances[at];
    }
    (lists, nearest)
}

/// Every pair `(i, j)`, sorted, of points in different components (`labels`) with `j` within
/// `reach(i)` of `i`. A pair always has a point outside the largest component, so only those
/// points are searched in the whole `tree`; the others search a tree of the points outside it
/// (islands are few, so the work is about one cheap query per point).
pub(crate) fn cross_pairs<const D: usize>(
    points: &[[f64; D]],
    tree: &ImmutableKdTree<f64, D>,
    order: &[u32],
    labels: &[u32],
    reach: impl Fn(usize) -> f64 + Sync,
) -> Vec<(u32, u32)> {
    let mut sizes = vec![0usize; points.len()];
    for &l in labels {
        sizes[l as usize] += 1;
    }
    // The largest component, the first of equal size.
    let largest =
        (0..sizes.len()).fold(0, |best, l| if sizes[l] > sizes[best] { l } else { best }) as u32;
    let outside: Vec<u32> = (0..points.len() as u32)
        .filter(|&i| labels[i as usize] != largest)
        .collect();
    let outside_points: Vec<[f64; D]> = outside.iter().map(|&i| points[i as usize]).collect();
    let small = ImmutableKdTree::<f64, D>::new_from_slice(&outside_points).ok();
    // Unsorted visits: the pairs are sorted at the end, so the order a query meets them in
    // never reaches the output, and no per-query result list is sorted or allocated.
    let mut pairs: Vec<(u32, u32)> = order
        .par_chunks(QUERY_BATCH)
        .flat_map_iter(|batch| {
            let mut found: Vec<(u32, u32)> = Vec::new();
            for &i in batch {
                let i = i as usize;
                let radius = reach(i);
                let r2 = radius * radius;
                match (&small, labels[i] == largest) {
                    (Some(small), true) => small
                        .query(&points[i])
                        .within::<SquaredEuclidean<f64>>(r2)
                        .unsorted()
                        .visit(|r| found.push((i as u32, outside[r.item as usize]))),
                    _ => tree
                        .query(&points[i])
                        .within::<SquaredEuclidean<f64>>(r2)
                        .unsorted()
                        .visit(|r| {
                            if labels[r.item as usize] != labels[i] {
                                found.push((i as u32, r.item));
                            }
                        }),
                }
            }
            found
        })
        .collect();
    pairs.par_sort_unstable();
    pairs
}

/// The components of the neighbour graph that joins the pairs whose components are `labels` (any
/// label per component) and the `bridges` across them: each point's label, a point of its
/// component, as a union-find over the whole graph would give some label (only which points
/// share one is read). The bridges join components, so a union-find over them alone does.
pub(crate) fn joined_parts(labels: Vec<u32>, bridges: &[(u32, u32)]) -> Vec<u32> {
    if bridges.is_empty() {
        return labels;
    }
    let mut sets = UnionFind::<u32>::new(labels.len());
    for &(i, j) in bridges {
        sets.union(labels[i as usize], labels[j as usize]);
    }
    let root = sets.into_labeling();
    labels.into_iter().map(|l| root[l as usize]).collect()
}

/// The largest of `f(x)` over `xs`, where `f` (`hypot`, a square root) is dear and rises with
/// `key` (a squared distance): `f` is taken only of the values whose key is within rounding of the
/// largest key, a faithful `f` being below every such value's for the others. `None` when empty.
pub(crate) fn dear_max<T: Copy>(
    xs: impl Iterator<Item = T> + Clone,
    key: impl Fn(T) -> f64,
    f: impl Fn(T) -> f64,
) -> Option<f64> {
    let top = xs.clone().map(&key).fold(f64::NEG_INFINITY, f64::max);
    let all = !(NORMAL_KEYS).contains(&top);
    xs.filter(|&x| all || key(x) >= top * (1.0 - NEAR_KEY))
        .map(f)
        .reduce(f64::max)
}

/// The smallest of `f(x)` over `xs`, as [`dear_max`] the largest.
pub(crate) fn dear_min<T: Copy>(
    xs: impl Iterator<Item = T> + Clone,
    key: impl Fn(T) -> f64,
    f: impl Fn(T) -> f64,
) -> Option<f64> {
    let low = xs.clone().map(&key).fold(f64::INFINITY, f64::min);
    let all = !(NORMAL_KEYS).contains(&low);
    xs.filter(|&x| all || key(x) <= low * (1.0 + NEAR_KEY))
        .map(f)
        .reduce(f64::min)
}

/// Relative margin on a squared distance, far above its rounding (a few units in 2^-52) and far
/// below any gap that matters.
const NEAR_KEY: f64 = 1e-9;

/// Keys whose rounding is relative (not subnormal, not overflowed): outside, [`dear_max`] and
/// [`dear_min`] take `f` of every value.
const NORMAL_KEYS: std::ops::RangeInclusive<f64> = 1e-280..=1e280;

/// The occupied cells of side `c` of a point set, per part: cell `(part, floor(p / c))`, sorted,
/// and each point's cell. [`Cells::coarser`] doubles the side, merging cells, so the cells of
/// every scale cost their own number, not the points'.
pub(crate) struct Cells<const D: usize> {
    /// The occupied cells, sorted: a part label and integer cell coordinates.
    pub keys: Vec<(u32, [i64; D])>,
    /// Each point's index in `keys`.
    pub point_slot: Vec<u32>,
}

/// Cell coordinates up to which halving the coordinates equals recomputing them from the points
/// at the doubled side (`floor(x / 2c) = floor(floor(x / c) / 2)`, and `as i64` does not
/// saturate).
const EXACT_CELL: i64 = 1 << 52;

impl<const D: usize> Cells<D> {
    /// The cells of side `cell` (points with nonnegative coordinates).
    pub fn new(points: &[[f64; D]], part: &[u32], cell: f64) -> Self {
        let n = points.len().min(part.len());
        let key = |i: usize| (part[i], points[i].map(|x| (x / cell).floor() as i64));
        // The points sorted by cell (ties by index), then one walk numbers the distinct cells:
        // a sort of the points instead of one binary search per point, each a few cache misses.
        let Some(mut packed) = packed_keys(n, &key) else {
            return Self::from_point_keys((0..n).map(key).collect());
        };
        // Each key packed into one `u64` whose order is the keys' order: a sort of 16-byte items
        // instead of 32-byte ones, the same order, and no list of every point's key.
        packed.par_sort_unstable();
        let mut keys: Vec<(u32, [i64; D])> = Vec::new();
        let mut point_slot = vec![0u32; n];
        let mut last = None;
        for &(code, i) in &packed {
            if last != Some(code) {
                last = Some(code);
                keys.push(key(i as usize));
            }
            point_slot[i as usize] = (keys.len() - 1) as u32;
        }
        Cells { keys, point_slot }
    }

    fn from_point_keys(point_keys: Vec<(u32, [i64; D])>) -> Self {
        let mut by_key: Vec<((u32, [i64; D]), u32)> = point_keys
            .into_iter()
            .enumerate()
            .map(|(i, key)| (key, i as u32))
            .collect();
        by_key.par_sort_unstable();
        let mut keys: Vec<(u32, [i64; D])> = Vec::new();
        let mut point_slot = vec![0u32; by_key.len()];
        for &(key, i) in &by_key {
            if keys.last() != Some(&key) {
                keys.push(key);
            }
            point_slot[i as usize] = (keys.len() - 1) as u32;
        }
        Cells { keys, point_slot }
    }

    /// The cells of twice the side, as [`Cells::new`] would give them for `2 * cell`.
    pub fn coarser(self, points: &[[f64; D]], part: &[u32], cell: f64) -> Self {
        let exact = self
            .keys
            .iter()
            .all(|(_, c)| c.iter().all(|&x| (0..EXACT_CELL).contains(&x)));
        if !exact {
            return Self::new(points, part, 2.0 * cell);
        }
        let parents: Vec<(u32, [i64; D])> = self
            .keys
            .iter()
            .map(|&(label, c)| (label, c.map(|x| x >> 1)))
            .collect();
        let mut keys = parents.clone();
        keys.dedup();
        // Children sorted by (part, coordinates) give parents sorted up to runs; sort to be sure.
        keys.par_sort_unstable();
        keys.dedup();
        let parent_slot: Vec<u32> = parents
            .iter()
            .map(|key| keys.binary_search(key).unwrap_or(0) as u32)
            .collect();
        let point_slot = self
            .point_slot
            .iter()
            .map(|&s| parent_slot[s as usize])
            .collect();
        Cells { keys, point_slot }
    }

    /// The slot of a cell, if occupied.
    pub fn slot(&self, key: &(u32, [i64; D])) -> Option<usize> {
        self.keys.binary_search(key).ok()
    }

    /// `measure(cell, slots)` for every cell, in parallel, in the order of `keys`: `slots` are
    /// the slots of the `3^D` cells of the cell's window (same part, each coordinate moved by
    /// -1, 0 or 1; `u32::MAX` where empty), the offset `(d_0, ..., d_{D-1})` at
    /// `sum (d_i + 1) 3^i` (the first axis fastest). Each cell's neighbours are the same as
    /// [`Cells::slot`] finds for the coordinates moved by `saturating_add`; the walk finds them
    /// with one cursor per column of the window moving forward through the sorted cells
    /// instead of a binary search per neighbour.
    pub fn windows<T: Send>(
        &self,
        measure: impl Fn(&(u32, [i64; D]), &[u32]) -> T + Sync + Send,
    ) -> Vec<T> {
        let size = 3usize.pow(D as u32);
        assert!(size <= MAX_WINDOW, "windows of at most three dimensions");
        // Away from the ends of `i64` no move saturates, and moving a coordinate keeps the
        // order of the keys, so the cursors only move forward.
        let walkable = self.keys.iter().all(|(_, c)| {
            c.iter()
                .all(|&x| (i64::MIN + 1..=i64::MAX - 1).contains(&x))
        });
        let columns = size / 3;
        self.keys
            .par_chunks(WINDOW_BATCH)
            .flat_map_iter(|cells| {
                let mut answers = Vec::with_capacity(cells.len());
                let mut slots = [u32::MAX; MAX_WINDOW];
                let mut cursor = [0usize; MAX_WINDOW / 3];
                // The bottom cell of column `col` of the window of `(label, c)`.
                let bottom = |&(label, c): &(u32, [i64; D]), col: usize| {
                    let mut at = c;
                    let mut rest = col;
                    for x in at.iter_mut().take(D - 1) {
                        *x = x.saturating_add((rest % 3) as i64 - 1);
                        rest /= 3;
                    }
                    at[D - 1] = at[D - 1].saturating_sub(1);
                    (label, at)
                };
                if walkable {
                    if let Some(first) = cells.first() {
                        for (col, cursor) in cursor.iter_mut().enumerate().take(columns) {
                            let start = bottom(first, col);
                            *cursor = self.keys.partition_point(|k| k < &start);
                        }
                    }
                }
                for cell in cells {
                    for col in 0..columns {
                        let start = bottom(cell, col);
                        if walkable {
                            let mut j = cursor[col];
                            while j < self.keys.len() && self.keys[j] < start {
                                j += 1;
                            }
                            cursor[col] = j;
                            for step in 0..3 {
                                let mut want = start;
                                want.1[D - 1] += step as i64;
                                let at = col + step * columns;
                                if j < self.keys.len() && self.keys[j] == want {
                                    slots[at] = j as u32;
                                    j += 1;
                                } else {
                                    slots[at] = u32::MAX;
                                }
                            }
                        } else {
                            for step in 0..3 {
                                let mut want = (cell.0, cell.1);
                                let mut rest = col;
                                for x in want.1.iter_mut().take(D - 1) {
                                    *x = x.saturating_add((rest % 3) as i64 - 1);
                                    rest /= 3;
                                }
                                want.1[D - 1] = want.1[D - 1].saturating_add(step as i64 - 1);
                                slots[col + step * columns] =
                                    self.slot(&want).map_or(u32::MAX, |s| s as u32);
                            }
                        }
                    }
                    answers.push(measure(cell, &slots[..size]));
                }
                answers
            })
            .collect()
    }
}

/// The most cells in a window ([`Cells::windows`]): three dimensions.
const MAX_WINDOW: usize = 27;

/// Cells per parallel batch of [`Cells::windows`].
const WINDOW_BATCH: usize = 2048;

/// Each point's key (`key(i)` for `i < n`) with its index, packed into one `u64` that sorts as
/// the key (part label, then coordinates in order), when every coordinate is nonnegative and the
/// bits of the largest label and coordinates fit in 64; `None` otherwise.
fn packed_keys<const D: usize>(
    n: usize,
    key: &(impl Fn(usize) -> (u32, [i64; D]) + Sync),
) -> Option<Vec<(u64, u32)>> {
    // The largest label and coordinates, `None` at a negative coordinate.
    let high = (0..n)
        .into_par_iter()
        .map(|i| {
            let (label, c) = key(i);
            c.iter().all(|&x| x >= 0).then_some((label, c))
        })
        .reduce(
            || Some((0u32, [0i64; D])),
            |a, b| {
                let ((la, ca), (lb, cb)) = (a?, b?);
                let mut c = ca;
                for d in 0..D {
                    c[d] = c[d].max(cb[d]);
                }
                Some((la.max(lb), c))
            },
        )?;
    let bits = |x: u64| 64 - x.leading_zeros();
    let widths: [u32; D] = high.1.map(|x| bits(x as u64));
    let total = bits(u64::from(high.0)) + widths.iter().sum::<u32>();
    if total > 64 {
        return None;
    }
    Some(
        (0..n)
            .into_par_iter()
            .map(|i| {
                let (label, c) = key(i);
                let mut code = u64::from(label);
                for d in 0..D {
                    // A shift by 64 (a width of 0 bits never happens past the first value).
                    code = code.checked_shl(widths[d]).unwrap_or(0) | c[d] as u64;
                }
                (code, i as u32)
            })
            .collect(),
    )
}

/// The points far sparser than the set's own sampling: those whose `k`-th neighbour distance
/// (`reach`) is more than `factor` times the median point's, as flags and as the points
/// themselves; `None` when there are none, or when every point is (no denser set to compare
/// with).
pub(crate) fn sparse_points<const D: usize>(
    points: &[[f64; D]],
    reach: &[f64],
    factor: f64,
) -> Option<(Vec<bool>, Vec<[f64; D]>)> {
    let median = crate::median::upper_median_by(&mut reach.to_vec(), f64::total_cmp)?;
    let sparse: Vec<bool> = reach.iter().map(|&r| r > factor * median).collect();
    let cloud: Vec<[f64; D]> = points
        .iter()
        .zip(&sparse)
        .filter(|(_, &s)| s)
        .map(|(p, _)| *p)
        .collect();
    (!cloud.is_empty() && cloud.len() < points.len()).then_some((sparse, cloud))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_order_is_a_permutation() {
        let points: Vec<[f64; 3]> = (0..500)
            .map(|i| {
                let t = i as f64 * 0.37;
                [t.sin() * 10.0, (t * 1.3).cos(), t]
            })
            .collect();
        let mut order = z_order(&points);
        order.sort_unstable();
        assert_eq!(order, (0..500).collect::<Vec<u32>>());
    }

    #[test]
    fn coarser_cells_equal_cells_made_at_the_doubled_side() {
        let points: Vec<[f64; 2]> = (0..2000)
            .map(|i| {
                let t = i as f64 * 0.618_033_988_7;
                [
                    (t * 7.1).fract() * 300.0,
                    (t * 3.3).fract() * 40.0 + t * 0.01,
                ]
            })
            .collect();
        let part: Vec<u32> = (0..2000).map(|i| (i % 3) as u32).collect();
        let mut cell = 0.75;
        let mut cells = Cells::new(&points, &part, cell);
        for _ in 0..12 {
            cells = cells.coarser(&points, &part, cell);
            cell *= 2.0;
            let direct = Cells::new(&points, &part, cell);
            assert_eq!(cells.keys, direct.keys);
            assert_eq!(cells.point_slot, direct.point_slot);
        }
    }

    /// Every cell's window from [`Cells::windows`] against a binary search per neighbour.
    fn windows_match_lookups<const D: usize>(cells: &Cells<D>) {
        let size = 3usize.pow(D as u32);
        let got = cells.windows(|_, slots| slots.to_vec());
        for (cell, slots) in cells.keys.iter().zip(&got) {
            assert_eq!(slots.len(), size);
            for (at, &slot) in slots.iter().enumerate() {
                let mut want = *cell;
                let mut rest = at;
                for x in want.1.iter_mut() {
                    *x = x.saturating_add((rest % 3) as i64 - 1);
                    rest /= 3;
                }
                let direct = cells.slot(&want).map_or(u32::MAX, |s| s as u32);
                assert_eq!(slot, direct, "cell {cell:?} offset {at}");
            }
        }
    }

    #[test]
    fn windows_equal_a_lookup_per_neighbour() {
        let plane: Vec<[f64; 2]> = (0..3000)
            .map(|i| {
                let t = i as f64 * 0.618_033_988_7;
                [(t * 7.1).fract() * 60.0, (t * 3.3).fract() * 9.0]
            })
            .collect();
        let part: Vec<u32> = (0..3000).map(|i| (i % 2) as u32).collect();
        for cell in [0.5, 1.0, 3.0, 100.0] {
            windows_match_lookups(&Cells::new(&plane, &part, cell));
        }
        let space: Vec<[f64; 3]> = (0..3000)
            .map(|i| {
                let t = i as f64 * 0.618_033_988_7;
                [(t * 7.1).fract() * 20.0, (t * 3.3).fract() * 9.0, t * 0.01]
            })
            .collect();
        for cell in [0.7, 2.0, 50.0] {
            windows_match_lookups(&Cells::new(&space, &part, cell));
        }
        // Coordinates at the ends of `i64`, where moves saturate: the lookups' own answers.
        let keys = vec![
            (0, [i64::MIN, 0]),
            (0, [i64::MIN, 1]),
            (0, [0, i64::MAX]),
            (0, [1, i64::MAX - 1]),
            (0, [1, i64::MAX]),
            (1, [i64::MAX, i64::MAX]),
        ];
        let edges = Cells {
            point_slot: (0..keys.len() as u32).collect(),
            keys,
        };
        windows_match_lookups(&edges);
    }

    #[test]
    fn knn_and_pairs_match_a_direct_search() {
        let points: Vec<[f64; 2]> = (0..300)
            .map(|i| {
                let t = i as f64;
                [
                    (t * 0.7548).fract() * 50.0 + if i < 20 { 200.0 } else { 0.0 },
                    (t * 0.5698).fract() * 5.0,
                ]
            })
            .collect();
        let tree = ImmutableKdTree::<f64, 2>::new_from_slice(&points).unwrap();
        let order = z_order(&points);
        let k = 5;
        let (lists, nearest) = k_nearest(&points, &tree, &order, k);
        let d2 = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
        for i in 0..points.len() {
            let mut all: Vec<(f64, usize)> = (0..points.len())
                .filter(|&j| j != i)
                .map(|j| (d2(points[i], points[j]), j))
                .collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            // The same distances (the choice among equal ones is the tree's).
            let got: Vec<f64> = lists[i * k..(i + 1) * k]
                .iter()
                .map(|&j| d2(points[i], points[j as usize]))
                .collect();
            let want: Vec<f64> = all[..k].iter().map(|&(d, _)| d).collect();
            assert_eq!(got, want, "point {i}");
            assert_eq!(nearest[i].0, all[0].0.sqrt());
            assert_eq!(nearest[i].1, all[k - 1].0.sqrt());
        }
        // Two components: the first 20 points and the rest; pairs within 160 units.
        let labels: Vec<u32> = (0..points.len()).map(|i| u32::from(i >= 20)).collect();
        let pairs = cross_pairs(&points, &tree, &order, &labels, |_| 160.0);
        let mut want = Vec::new();
        for i in 0..points.len() {
            for j in 0..points.len() {
                if labels[i] != labels[j] && d2(points[i], points[j]) <= 160.0 * 160.0 {
                    want.push((i as u32, j as u32));
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(pairs, want);
    }
}
