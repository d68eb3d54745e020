//! Compressed sparse rows: the one builder behind every "count, prefix sum, fill" in the stages
//! (neighbour lists, a node's points, chunks of runs, the rows of the fit's normal matrix).
//!
//! Ground floor: knows nothing about stages.

/// Values grouped by row: row `i` holds `values[offsets[i]..offsets[i + 1]]`, in the order they
/// were pushed.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Csr<T> {
    /// `rows + 1` offsets into `values`, from 0 to `values.len()`.
    pub offsets: Vec<usize>,
    /// The values, row after row.
    pub values: Vec<T>,
}

/// What [`Csr::build`]'s closure pushes `(row, value)` pairs into: the first call counts them,
/// the second writes them.
pub(crate) enum CsrSink<'a, T> {
    /// The first pass: counts per row (shifted by one, ready for the prefix sum).
    Count(&'a mut [usize]),
    /// The second pass: the next free slot of each row, and the values.
    Fill {
        /// Next slot per row.
        next: &'a mut [usize],
        /// Where the values go.
        values: &'a mut [T],
    },
}

impl<T> CsrSink<'_, T> {
    /// Adds `value` to row `row` (which must be below the row count given to [`Csr::build`]).
    #[inline]
    pub fn push(&mut self, row: usize, value: T) {
        match self {
            CsrSink::Count(counts) => counts[row + 1] += 1,
            CsrSink::Fill { next, values } => {
                values[next[row]] = value;
                next[row] += 1;
            }
        }
    }
}

impl<T: Copy + Default> Csr<T> {
    /// Builds `rows` rows from the pairs `emit` pushes. `emit` is called twice (count, then fill)
    /// and must push the same pairs both times; within a row the values keep their push order (a
    /// stable counting sort), so the result is as deterministic as `emit`.
    pub fn build(rows: usize, mut emit: impl FnMut(&mut CsrSink<'_, T>)) -> Self {
        let mut offsets = vec![0usize; rows + 1];
        emit(&mut CsrSink::Count(&mut offsets));
        for i in 0..rows {
            offsets[i + 1] += offsets[i];
        }
        let mut next = offsets[..rows].to_vec();
        let mut values = vec![T::default(); offsets[rows]];
        emit(&mut CsrSink::Fill {
            next: &mut next,
            values: &mut values,
        });
        Csr { offsets, values }
    }
}

impl<T> Csr<T> {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// The values of row `i`.
    pub fn row(&self, i: usize) -> &[T] {
        &self.values[self.offsets[i]..self.offsets[i + 1]]
    }

    /// The values of row `i`, to sort or edit in place.
    pub fn row_mut(&mut self, i: usize) -> &mut [T] {
        &mut self.values[self.offsets[i]..self.offsets[i + 1]]
    }
}

/// A symmetric neighbour relation in CSR form with `u32` offsets, as [`crate::PointSet`] holds
/// it: every pair `(i, j)` that `pairs` hands to its callback joins `i` to `j` and `j` to `i`;
/// each of the `n` rows is sorted and its repeats (pairs given both ways) dropped.
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
    fn no_rows_and_no_values() {
        let csr: Csr<u32> = Csr::build(0, |_| {});
        assert_eq!(csr.rows(), 0);
        assert_eq!(csr.offsets, [0]);
        let empty: Csr<u32> = Csr::build(3, |_| {});
        assert!((0..3).all(|i| empty.row(i).is_empty()));
    }
}
