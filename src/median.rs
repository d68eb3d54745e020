//! The one median every stage takes: of an even count, the upper of the two middle values (the
//! value at index `len / 2` once sorted), found by selection in O(n) rather than by sorting.
//!
//! Ground floor: plain functions on slices, no stage types.

use std::cmp::Ordering;

/// The upper median of `values` in the order `compare` (the value a sort by `compare` would put
/// at index `len / 2`); `None` when there are none. Reorders `values`.
pub(crate) fn upper_median_by<T: Copy>(
    values: &mut [T],
    compare: impl FnMut(&T, &T) -> Ordering,
) -> Option<T> {
    if values.is_empty() {
        return None;
    }
    let middle = values.len() / 2;
    Some(*values.select_nth_unstable_by(middle, compare).1)
}

/// The upper median of `values` in [`f64::total_cmp`]'s order; `None` when there are none.
/// Reorders `values`.
pub(crate) fn upper_median(values: &mut [f64]) -> Option<f64> {
    upper_median_by(values, f64::total_cmp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_upper_of_the_two_middle_values_as_a_sort_would_place_it() {
        assert_eq!(upper_median(&mut []), None);
        assert_eq!(upper_median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(upper_median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(upper_median_by(&mut [7u32, 7, 1, 9], Ord::cmp), Some(7));
        // Whatever the values, the same value as sorting and taking index len / 2.
        let mut seed = 12345u64;
        for n in 1..60 {
            let values: Vec<f64> = (0..n)
                .map(|_| {
                    seed = seed
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((seed >> 33) % 17) as f64 - 8.0
                })
                .collect();
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let mut selected = values.clone();
            assert_eq!(upper_median(&mut selected), Some(sorted[n / 2]));
        }
    }
}
