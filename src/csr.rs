//! Compressed sparse rows: the one builder behind every "count, prefix sum, fill" in the workspace
//! (neighbour lists, a node's points, chunks of runs, the rows of the fit's normal matrix, and the
//! test kit's sample graph and grid cells).
//!
//! Ground floor: knows nothing about stages. Public (not part of the tracing pipeline) so that the
//! test kit's scorer builds its graphs with this code rather than a copy. Nothing here panics:
//! values pushed to a row that does not exist are dropped, and rows outside the table read as
//! empty.
//!
//! ```
//! use ridgeline::csr::Csr;
//!
//! // Edges of a path 0 - 1 - 2, both ways: the neighbours of each vertex.
//! let edges = [(0, 1), (1, 2)];
//! let neighbours = Csr::build(3, |sink| {
//!     for &(a, b) in &edges {
//!         sink.push(a, b);
//!         sink.push(b, a);
//!     }
//! });
//! assert_eq!(neighbours.row(1), [0, 2]);
//! assert_eq!(neighbours.offsets(), [0, 1, 3, 4]);
//! assert!(neighbours.row(7).is_empty());
//! ```

/// Values grouped by row: row `i` holds `values[offsets[i]..offsets[i + 1]]`, in the order they
/// were pushed. Built only by [`Csr::build`] (or empty, [`Csr::default`]), so the offsets always
/// run from 0 to `values.len()` without decreasing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Csr<T> {
    /// `rows + 1` offsets into `values`, from 0 to `values.len()`.
    pub(crate) offsets: Vec<usize>,
    /// The values, row after row.
    pub(crate) values: Vec<T>,
}

/// What [`Csr::build`]'s closure pushes `(row, value)` pairs into: the first call counts them,
/// the second writes them.
pub struct CsrSink<'a, T>(Pass<'a, T>);

enum Pass<'a, T> {
    /// The first pass: counts per row (shifted by one, ready for the prefix sum).
    Count(&'a mut [usize]),
    /// The second pass: the next free slot of each row, the end of each row, and the values.
    Fill {
        next: &'a mut [usize],
        ends: &'a [usize],
        values: &'a mut [T],
    },
}

impl<T> CsrSink<'_, T> {
    /// Adds `value` to row `row`. A row at or beyond the row count given to [`Csr::build`] does not
    /// exist, and the value is dropped.
    #[inline]
    pub fn push(&mut self, row: usize, value: T) {
        match &mut self.0 {
            Pass::Count(counts) => {
                if row < counts.len() - 1 {
                    counts[row + 1] += 1;
                }
            }
            Pass::Fill { next, ends, values } => {
                // A row pushed more often than in the first pass keeps what was counted.
                if row < next.len() && next[row] < ends[row] {
                    values[next[row]] = value;
                    next[row] += 1;
                }
            }
        }
    }
}

impl<T: Copy + Default> Csr<T> {
    /// Builds `rows` rows from the pairs `emit` pushes. `emit` is called twice (count, then fill)
    /// and must push the same pairs both times (slots a row was counted for but not given stay
    /// `T::default()`); within a row the values keep their push order (a stable counting sort), so
    /// the result is as deterministic as `emit`.
    pub fn build(rows: usize, mut emit: impl FnMut(&mut CsrSink<'_, T>)) -> Self {
        let mut offsets = vec![0usize; rows + 1];
        emit(&mut CsrSink(Pass::Count(&mut offsets)));
        for i in 0..rows {
            offsets[i + 1] += offsets[i];
        }
        let mut next = offsets[..rows].to_vec();
        let mut values = vec![T::default(); offsets[rows]];
        emit(&mut CsrSink(Pass::Fill {
            next: &mut next,
            ends: &offsets[1..],
            values: &mut values,
        }));
        Csr { offsets, values }
    }
}

impl<T> Csr<T> {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Where row `i`'s values lie in [`Csr::values`]; empty for a row beyond [`Csr::rows`].
    #[inline]
    fn span(&self, i: usize) -> std::ops::Range<usize> {
        match (
            self.offsets.get(i),
            i.checked_add(1).and_then(|j| self.offsets.get(j)),
        ) {
            (Some(&start), Some(&end)) => start..end,
            _ => 0..0,
        }
    }

    /// The values of row `i` (empty for a row beyond [`Csr::rows`]).
    #[inline]
    pub fn row(&self, i: usize) -> &[T] {
        &self.values[self.span(i)]
    }

    /// The values of row `i`, to sort or edit in place (empty for a row beyond [`Csr::rows`]).
    pub fn row_mut(&mut self, i: usize) -> &mut [T] {
        let span = self.span(i);
        &mut self.values[span]
    }

    /// The `rows + 1` offsets: row `i` is `values()[offsets()[i]..offsets()[i + 1]]`.
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// Every value, row after row.
    pub fn values(&self) -> &[T] {
        &self.values
    }
}

/// A symmetric neighbour relation in CSR form with `u32` offsets, as [`crate::PointSet`] holds
/// it: every pair `(i, j)` that `pairs` hands to its callback joins `i` to `j` and `j` to `i`;
/// each of the `n` rows is sorted and its repeats (pairs given both ways) dropped. (The stages
/// use [`symmetric_from_lists`], its parallel twin for `k`-nearest lists; this one builds the
/// tests' hand-made sets and checks the twin.)
#[cfg(test)]
pub(crate) fn symmetric_neighbours(
    n: usize,
    mut pairs: impl FnMut(&mut dyn FnMut(u32, u32)),
) -> (Vec<u32>, Vec<u32>) {
    let mut both = Csr::build(n, |sink| {
        pairs(&mut |i, j| {
            sink.push(i as usize, j);
            sink.push(j as usize, i);
        })
    });
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    let mut neighbors = Vec::with_capacity(both.values.len());
    for i in 0..n {
        let list = both.row_mut(i);
        list.sort_unstable();
        let start = neighbors.len();
        for &j in list.iter() {
            if neighbors.len() == start || neighbors.last() != Some(&j) {
                neighbors.push(j);
            }
        }
        offsets.push(neighbors.len() as u32);
    }
    (offsets, neighbors)
}

/// [`symmetric_neighbours`] of the pairs `(i, lists[i * k + s])` (slots holding `u32::MAX` are
/// empty) and `extra`, in parallel: the same rows. The rows are cut into one band of consecutive
/// rows per thread; each band reads every pair and keeps those that land in its rows, so no two
/// threads write the same memory. The order a row is filled in does not matter: each row is
/// sorted and its repeats dropped, and a sorted list of numbers has one order only.
pub(crate) fn symmetric_from_lists(
    n: usize,
    lists: &[u32],
    k: usize,
    extra: &[(u32, u32)],
) -> (Vec<u32>, Vec<u32>) {
    use rayon::prelude::*;
    let k = k.max(1);
    let bands = rayon::current_num_threads().clamp(1, 64);
    let band_rows = n.div_ceil(bands).max(1);
    let band = |b: usize| (b * band_rows).min(n)..((b + 1) * band_rows).min(n);
    // Calls `visit(row, value)` for both directions of every pair whose row lies in `rows`.
    let each_pair = |rows: std::ops::Range<usize>, visit: &mut dyn FnMut(usize, u32)| {
        for i in rows.clone() {
            for &j in lists[i * k..(i + 1) * k]
                .iter()
                .filter(|&&j| (j as usize) < n)
            {
                visit(i, j);
            }
        }
        for (i, list) in lists.chunks(k).enumerate().take(n) {
            for &j in list {
                if rows.contains(&(j as usize)) {
                    visit(j as usize, i as u32);
                }
            }
        }
        for &(i, j) in extra {
            if (i as usize) < n && (j as usize) < n {
                if rows.contains(&(i as usize)) {
                    visit(i as usize, j);
                }
                if rows.contains(&(j as usize)) {
                    visit(j as usize, i);
                }
            }
        }
    };
    let counts: Vec<Vec<u32>> = (0..bands)
        .into_par_iter()
        .map(|b| {
            let rows = band(b);
            let mut count = vec![0u32; rows.len()];
            let first = rows.start;
            each_pair(rows, &mut |row, _| count[row - first] += 1);
            count
        })
        .collect();
    let mut starts = Vec::with_capacity(n + 1);
    starts.push(0usize);
    for count in &counts {
        for &c in count {
            starts.push(starts[starts.len() - 1] + c as usize);
        }
    }
    let mut values = vec![0u32; starts[n]];
    let mut pieces: Vec<(usize, &mut [u32])> = Vec::with_capacity(bands);
    let mut rest: &mut [u32] = &mut values;
    for b in 0..bands {
        let rows = band(b);
        let (head, tail) =
            std::mem::take(&mut rest).split_at_mut(starts[rows.end] - starts[rows.start]);
        pieces.push((b, head));
        rest = tail;
    }
    // Each band filled, its rows sorted and their repeats dropped in place: the kept length of
    // each row.
    let lengths: Vec<Vec<u32>> = pieces
        .into_par_iter()
        .map(|(b, piece)| {
            let rows = band(b);
            let base = starts[rows.start];
            let mut next: Vec<usize> = starts[rows.clone()].iter().map(|&s| s - base).collect();
            let first = rows.start;
            each_pair(rows.clone(), &mut |row, value| {
                piece[next[row - first]] = value;
                next[row - first] += 1;
            });
            rows.map(|i| {
                let row = &mut piece[starts[i] - base..starts[i + 1] - base];
                row.sort_unstable();
                let mut kept = 0;
                for at in 0..row.len() {
                    if kept == 0 || row[kept - 1] != row[at] {
                        row[kept] = row[at];
                        kept += 1;
                    }
                }
                kept as u32
            })
            .collect()
        })
        .collect();
    // Rows moved down over the dropped repeats, in place.
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    let mut end = 0usize;
    for (i, &len) in lengths.iter().flatten().enumerate() {
        values.copy_within(starts[i]..starts[i] + len as usize, end);
        end += len as usize;
        offsets.push(end as u32);
    }
    values.truncate(end);
    // The repeats' room given back (the whole buffer was written, so it is resident).
    values.shrink_to_fit();
    (offsets, values)
}

/// The components of a neighbour graph given as compressed rows (`neighbors[offsets[p]..
/// offsets[p + 1]]` the neighbours of point `p`), as one label per point: the parts a point set's
/// windows and outlier tests keep apart.
pub(crate) fn parts(offsets: &[u32], neighbors: &[u32]) -> Vec<u32> {
    let n = offsets.len().saturating_sub(1);
    let mut sets = petgraph::unionfind::UnionFind::<u32>::new(n);
    for p in 0..n {
        for &q in &neighbors[offsets[p] as usize..offsets[p + 1] as usize] {
            sets.union(p as u32, q);
        }
    }
    sets.into_labeling()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_keep_push_order() {
        let pairs = [(2, 'a'), (0, 'b'), (2, 'c'), (0, 'd'), (3, 'e')];
        let csr = Csr::build(4, |sink| {
            for &(row, value) in &pairs {
                sink.push(row, value);
            }
        });
        assert_eq!(csr.offsets, [0, 2, 2, 4, 5]);
        assert_eq!(csr.rows(), 4);
        assert_eq!(csr.row(0), ['b', 'd']);
        assert!(csr.row(1).is_empty());
        assert_eq!(csr.row(2), ['a', 'c']);
        assert_eq!(csr.row(3), ['e']);
    }

    #[test]
    fn symmetric_neighbours_are_sorted_and_unique() {
        // 0-1 given both ways, 2-0 once, 3 alone.
        let pairs = [(0, 1), (1, 0), (2, 0)];
        let (offsets, neighbors) = symmetric_neighbours(4, |emit| {
            for &(i, j) in &pairs {
                emit(i, j);
            }
        });
        assert_eq!(offsets, [0, 2, 3, 4, 4]);
        assert_eq!(neighbors, [1, 2, 0, 0]);
    }

    #[test]
    fn symmetric_from_lists_equals_the_serial_build() {
        let (n, k) = (9000usize, 5usize);
        let mut lcg = crate::synth::lcg(11u64);
        let mut next = move || (lcg() >> 33) as u32;
        let lists: Vec<u32> = (0..n * k)
            .map(|s| {
                let r = next();
                if r % 17 == 0 {
                    u32::MAX
                } else {
                    // Mostly near the row, so rows meet their reverse pairs.
                    ((s / k) as u32 + r % 40).min(n as u32 - 1)
                }
            })
            .collect();
        let extra: Vec<(u32, u32)> = (0..500)
            .map(|_| (next() % n as u32, next() % n as u32))
            .collect();
        let serial = symmetric_neighbours(n, |emit| {
            for (i, list) in lists.chunks(k).enumerate() {
                for &j in list.iter().filter(|&&j| j != u32::MAX) {
                    emit(i as u32, j);
                }
            }
            for &(i, j) in &extra {
                emit(i, j);
            }
        });
        assert_eq!(symmetric_from_lists(n, &lists, k, &extra), serial);
        assert_eq!(symmetric_from_lists(0, &[], k, &[]), (vec![0], vec![]));
    }

    #[test]
    fn pushes_to_missing_rows_and_extra_pushes_are_dropped() {
        // Row 5 does not exist; the second pass pushes row 0 once more than the first.
        let mut pass = 0;
        let csr = Csr::build(2, |sink| {
            pass += 1;
            sink.push(0, 1u32);
            sink.push(5, 2);
            sink.push(usize::MAX, 3);
            if pass == 2 {
                sink.push(0, 4);
            }
            sink.push(1, 5);
        });
        assert_eq!(csr.offsets(), [0, 1, 2]);
        assert_eq!(csr.values(), [1, 5]);
        assert!(csr.row(2).is_empty() && csr.row(usize::MAX).is_empty());
        assert!(Csr::<u32>::default().row(0).is_empty());
    }

    #[test]
    fn no_rows_and_no_values() {
        let csr: Csr<u32> = Csr::build(0, |_| {});
        assert_eq!(csr.rows(), 0);
        assert_eq!(csr.offsets, [0]);
        let empty: Csr<u32> = Csr::build(3, |_| {});
        assert!((0..3).all(|i| empty.row(i).is_empty()));
    }
}
