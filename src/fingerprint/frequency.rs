//! Ridge period per block (docs/fingerprints.md, "Ridge period"): the x-signature of Hong, Wan
//! and Jain, as pyfing's XSFFE computes it.
//!
//! Around each print block's center a window `signature_length` px long across the ridges
//! (along the normal of the local orientation) and two blocks wide along them is sampled; the
//! means of its rows along the ridge are the x-signature, a wave with one period per ridge. The
//! distances between consecutive maxima and between consecutive minima that lie between
//! `period_min` and `period_max` (3 and 25 px: 1/3 to 1/25 px⁻¹) are the candidate periods; with
//! at least three, the block's period is the mean of those within 2 px (or 20 %) of their median.
//! Where pores or the lighter middle of a wide ridge add shallow extremes inside the ridges, that
//! mean is half the period: the block is halved when its signature, less its mean, correlates
//! negatively with itself shifted by the measure and positively shifted by twice it, and a halved
//! block's period is doubled where at least a third of its measured 3 x 3 neighbours are halved
//! too (a single noisy block is not).
//! Blocks without a measure (background, a crease, a core) are filled wave by wave from the mean
//! of their filled neighbours, then every block is averaged with its 3 x 3 neighbours.
//!
//! In: the smoothed gray image, [`Segmentation`] and [`OrientationField`]; out: [`RidgePeriods`].

use super::fields::{OrientationField, Plane, RidgePeriods, Segmentation};
use crate::median::upper_median_by;
use crate::params::FingerprintParams;
use rayon::prelude::*;

/// Fewest candidate distances for a measured period.
const MIN_DISTANCES: usize = 3;

/// The ridge period of every block.
pub(crate) fn ridge_periods(
    smoothed: &Plane,
    segmentation: &Segmentation,
    field: &OrientationField,
    params: &FingerprintParams,
) -> RidgePeriods {
    let grid = segmentation.grid;
    let (cols, rows) = (grid.cols as usize, grid.rows as usize);
    let length = params.signature_length.max(4) as usize;
    let across = (2 * grid.block).max(2) as usize;
    // Each block's measure is its own (scratch space per thread): the blocks in parallel, the
    // same values whatever the thread count.
    let measures: Vec<(f32, bool, bool)> = (0..grid.len())
        .into_par_iter()
        .map_init(
            || SignatureScratch::new(length),
            |scratch, b| {
                if !segmentation.inside[b] {
                    return (0.0, false, false);
                }
                let (i, j) = (b % cols, b / cols);
                block_period(
                    smoothed,
                    grid.center(i, j),
                    field.angle[b],
                    across,
                    params,
                    scratch,
                )
            },
        )
        .collect();
    let mut period: Vec<f32> = measures.iter().map(|m| m.0).collect();
    let measured: Vec<bool> = measures.iter().map(|m| m.1).collect();
    let halved: Vec<bool> = measures.iter().map(|m| m.2).collect();
    double_halved(&mut period, &measured, &halved, cols, rows);
    let period = fill_and_smooth(period, &measured, cols, rows, params.default_period as f32);
    let (lo, hi) = (params.period_min as f32, params.period_max as f32);
    RidgePeriods {
        grid,
        period: period.into_iter().map(|p| p.clamp(lo, hi)).collect(),
        measured,
    }
}

/// [`block_period`]'s scratch space, kept from one block to the next (a print has about a
/// thousand blocks): the signature, the candidate distances, the window's rows' starts and steps
/// and the starts' coordinates apart.
struct SignatureScratch {
    signature: Vec<f32>,
    distances: Vec<f32>,
    steps: Vec<[f64; 2]>,
    starts: Vec<[f64; 2]>,
    coordinates: (Vec<f64>, Vec<f64>),
}

impl SignatureScratch {
    /// For signatures of `length` samples.
    fn new(length: usize) -> SignatureScratch {
        SignatureScratch {
            signature: vec![0.0; length],
            distances: Vec::with_capacity(length),
            steps: Vec::new(),
            starts: Vec::with_capacity(length),
            coordinates: (Vec::with_capacity(length), Vec::with_capacity(length)),
        }
    }
}

/// The x-signature's measure of one block centred at `c` with ridge direction `angle`: its
/// period, whether it was measured, and whether it looks halved (see [`ridge_periods`]).
fn block_period(
    smoothed: &Plane,
    c: [f64; 2],
    angle: f32,
    across: usize,
    params: &FingerprintParams,
    scratch: &mut SignatureScratch,
) -> (f32, bool, bool) {
    let SignatureScratch {
        signature,
        distances,
        steps,
        starts,
        coordinates,
    } = scratch;
    let length = signature.len();
    let theta = f64::from(angle);
    let (along, normal) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
    // The window's sample positions are `c + u normal + v along`, summed in that order.
    let offset = |k: usize| k as f64 - across as f64 / 2.0 + 0.5;
    steps.clear();
    steps.extend((0..across).map(|k| [offset(k) * along[0], offset(k) * along[1]]));
    let u_of = |t: usize| t as f64 - length as f64 / 2.0 + 0.5;
    let row_start = |t: usize| {
        let u = u_of(t);
        [c[0] + u * normal[0], c[1] + u * normal[1]]
    };
    starts.clear();
    starts.extend((0..length).map(row_start));
    x_signature(smoothed, starts, steps, signature, coordinates);
    distances.clear();
    for extremum in [1.0f32, -1.0] {
        let mut last: Option<usize> = None;
        extrema(signature, extremum, |k| {
            if let Some(l) = last {
                let d = (k - l) as f32;
                if f64::from(d) >= params.period_min && f64::from(d) <= params.period_max {
                    distances.push(d);
                }
            }
            last = Some(k);
        });
    }
    if distances.len() < MIN_DISTANCES {
        return (0.0, false, false);
    }
    let m = upper_median_by(distances, f32::total_cmp).unwrap_or(0.0);
    let tolerance = (0.2 * m).max(2.0);
    // The distances close to the median, summed in their order (as collected and summed).
    let (sum, close) = distances
        .iter()
        .filter(|&&d| (d - m).abs() <= tolerance)
        .fold((0.0f32, 0usize), |(sum, k), &d| (sum + d, k + 1));
    if close > 0 {
        let p = sum / close as f32;
        // Extra shallow extremes inside the ridges (pores, a lighter middle of a wide
        // ridge) halve the distances; the signature then correlates negatively with
        // itself one distance away and positively two away.
        let halved = f64::from(2.0 * p) <= params.period_max && {
            let mean = signature.iter().sum::<f32>() / length as f32;
            correlation(signature, mean, p) < 0.0 && correlation(signature, mean, 2.0 * p) > 0.0
        };
        return (p, true, halved);
    }
    (0.0, false, false)
}

/// Visits, in rising order, each `k` in `1..len - 1` where `extremum · signature[k]` rises
/// strictly from `k - 1` and does not fall to `k + 1` (a maximum for `extremum` 1, a minimum for
/// -1). The tests are made for 64 samples at a time without a branch, their answers bits of a
/// word, which are then visited: a branch on each sample's answer was mispredicted about as often
/// as a wave's samples turn (docs/performance.md).
fn extrema(signature: &[f32], extremum: f32, mut visit: impl FnMut(usize)) {
    let length = signature.len();
    let mut first = 1;
    while first + 1 < length {
        let end = (first + 64).min(length - 1);
        let mut bits = 0u64;
        for k in first..end {
            let (p, q, r) = (
                extremum * signature[k - 1],
                extremum * signature[k],
                extremum * signature[k + 1],
            );
            bits |= u64::from((q > p) & (q >= r)) << (k - first);
        }
        while bits != 0 {
            visit(first + bits.trailing_zeros() as usize);
            bits &= bits - 1;
        }
        first = end;
    }
}

/// The x-signature: for each row `t` of the window, the mean of the samples at `starts[t] +
/// steps[k]`, summed over `k` in order from 0. The rows whose two ends lie inside the image by a
/// pixel and a half (the first run of them: all of them when the window's corners do) take their
/// four pixels directly, side by side ([`Plane::add_samples_inside`]; a row's samples lie
/// between its ends, as `steps` are multiples of one vector by rising offsets, up to rounding,
/// which the slack covers); the others are clamped at the image's edges. The same values either
/// way. With AVX2 at run time the lanes are twice as wide (`math::wide_lanes`: the same
/// operations, so the same values; a test holds the two bit for bit).
/// `coordinates` is scratch space.
fn x_signature(
    smoothed: &Plane,
    starts: &[[f64; 2]],
    steps: &[[f64; 2]],
    signature: &mut [f32],
    coordinates: &mut (Vec<f64>, Vec<f64>),
) {
    #[cfg(target_arch = "x86_64")]
    if super::math::wide_lanes() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { x_signature_wide(smoothed, starts, steps, signature, coordinates) };
    }
    x_signature_lanes::<false>(smoothed, starts, steps, signature, coordinates);
}

/// [`x_signature`] compiled for AVX2, the rows inside sampled four at a time in AVX registers
/// (`wide::add_samples_inside`).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn x_signature_wide(
    smoothed: &Plane,
    starts: &[[f64; 2]],
    steps: &[[f64; 2]],
    signature: &mut [f32],
    coordinates: &mut (Vec<f64>, Vec<f64>),
) {
    x_signature_lanes::<true>(smoothed, starts, steps, signature, coordinates);
}

/// [`x_signature`]'s sampling, inlined into the version the CPU runs (`WIDE`: the one for AVX2,
/// which the CPU must have).
#[inline(always)]
fn x_signature_lanes<const WIDE: bool>(
    smoothed: &Plane,
    starts: &[[f64; 2]],
    steps: &[[f64; 2]],
    signature: &mut [f32],
    (xs, ys): &mut (Vec<f64>, Vec<f64>),
) {
    let (w, h) = (f64::from(smoothed.width), f64::from(smoothed.height));
    let within = |p: [f64; 2]| p[0] >= 1.5 && p[1] >= 1.5 && p[0] <= w - 1.5 && p[1] <= h - 1.5;
    let row_inside = |t: usize| {
        let start = starts[t];
        [steps.first(), steps.last()]
            .into_iter()
            .flatten()
            .all(|step| within([start[0] + step[0], start[1] + step[1]]))
    };
    let length = starts.len().min(signature.len());
    let first = (0..length).find(|&t| row_inside(t)).unwrap_or(length);
    let end = (first..length).find(|&t| !row_inside(t)).unwrap_or(length);
    xs.clear();
    ys.clear();
    xs.extend(starts[first..end].iter().map(|p| p[0]));
    ys.extend(starts[first..end].iter().map(|p| p[1]));
    signature[first..end].fill(0.0);
    #[cfg(target_arch = "x86_64")]
    let extremes = if WIDE { wide::extremes(xs, ys) } else { None };
    // Where every step's samples are inside the image, the rows four at a time with all their
    // steps (the sums kept in a register); otherwise step after step over the rows.
    #[cfg_attr(not(target_arch = "x86_64"), allow(unused_mut))]
    let mut step_by_step = true;
    #[cfg(target_arch = "x86_64")]
    if WIDE
        && steps
            .iter()
            .all(|&step| wide::all_inside(smoothed, extremes, step))
    {
        let sums = &mut signature[first..end];
        // SAFETY: `WIDE` only where the CPU has AVX2 (`x_signature_wide`); `all_inside` holds
        // for every step.
        let done = unsafe { wide::rows_inside(smoothed, xs, ys, steps, sums) };
        for (t, sum) in sums.iter_mut().enumerate().skip(done) {
            for step in steps {
                *sum += smoothed.sample_inside(xs[t] + step[0], ys[t] + step[1]);
            }
        }
        step_by_step = false;
    }
    for step in steps.iter().filter(|_| step_by_step) {
        let sums = &mut signature[first..end];
        #[cfg(target_arch = "x86_64")]
        if WIDE {
            // SAFETY: `WIDE` only where the CPU has AVX2 (`x_signature_wide`).
            unsafe { wide::add_samples_inside(smoothed, xs, ys, extremes, *step, sums) };
            continue;
        }
        smoothed.add_samples_inside(xs, ys, *step, sums);
    }
    // The rows that reach past the image's edge, sample by sample: most of their samples still
    // have their four pixels inside (`x` in `[0.5, width - 0.5)`, `y` likewise; false for NaN),
    // read without the clamping (the same value); the others clamped.
    let four_inside = |x: f64, y: f64| x >= 0.5 && y >= 0.5 && x < w - 0.5 && y < h - 0.5;
    for t in (0..first).chain(end..length) {
        let start = starts[t];
        let mut sum = 0.0f32;
        for step in steps {
            let (x, y) = (start[0] + step[0], start[1] + step[1]);
            sum += if four_inside(x, y) {
                smoothed.sample_inside(x, y)
            } else {
                smoothed.sample(x, y)
            };
        }
        signature[t] = sum;
    }
    for s in signature.iter_mut() {
        *s /= steps.len() as f32;
    }
}

/// [`Plane::add_samples_inside`] four samples at a time in AVX registers: the same operations
/// (the coordinates less half a pixel, their floors, the fractions rounded to `f32`, the pixel's
/// index from `y · width + x` in `f64`, the bilinear mix; no fused multiply-add), so the same
/// values (a test holds them bit for bit); the four pixels of each sample read as two adjacent
/// pairs ([`pairs`]).
#[cfg(target_arch = "x86_64")]
mod wide {
    use super::Plane;
    use std::arch::x86_64::{
        __m128, __m256d, _mm256_add_pd, _mm256_and_pd, _mm256_cmp_pd, _mm256_cvtpd_epi32,
        _mm256_cvtpd_ps, _mm256_floor_pd, _mm256_loadu_pd, _mm256_movemask_pd, _mm256_mul_pd,
        _mm256_set1_pd, _mm256_sub_pd, _mm_add_ps, _mm_castpd_ps, _mm_loadu_ps, _mm_mul_ps,
        _mm_set1_ps, _mm_setr_pd, _mm_shuffle_ps, _mm_storeu_ps, _mm_storeu_si128, _mm_sub_ps,
        _CMP_GE_OQ, _CMP_LE_OQ,
    };

    /// The pixel at each of four indices into `values` and its right neighbour, as two vectors
    /// (the pixels, the neighbours): each pair is adjacent, so it is one 8-byte load, and two
    /// shuffles sort the four pairs. The same values as four gathers; on an AMD EPYC (Zen 3) the
    /// gathers took most of the x-signature's time, the pairs about a third less of it
    /// (docs/performance.md).
    ///
    /// # Safety
    /// Every index and the one after it must lie within `values`' allocation.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn pairs(values: *const f32, index: [u32; 4]) -> (__m128, __m128) {
        // SAFETY: by the caller, each pair's 8 bytes are inside `values`; unaligned reads.
        let pair =
            |k: usize| unsafe { values.add(index[k] as usize).cast::<f64>().read_unaligned() };
        // The second pair of each vector loaded straight into its upper half.
        let (low, high) = (
            _mm_castpd_ps(_mm_setr_pd(pair(0), pair(1))),
            _mm_castpd_ps(_mm_setr_pd(pair(2), pair(3))),
        );
        (
            _mm_shuffle_ps::<0b10_00_10_00>(low, high),
            _mm_shuffle_ps::<0b11_01_11_01>(low, high),
        )
    }

    /// The least and the greatest of `xs` and of `ys` (`[x_min, x_max, y_min, y_max]`); `None`
    /// when they are empty or one is NaN.
    pub(super) fn extremes(xs: &[f64], ys: &[f64]) -> Option<[f64; 4]> {
        if xs.is_empty() || ys.is_empty() || xs.iter().chain(ys).any(|v| v.is_nan()) {
            return None;
        }
        let range = |vs: &[f64]| {
            vs.iter()
                .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], &v| {
                    [lo.min(v), hi.max(v)]
                })
        };
        let ([x_min, x_max], [y_min, y_max]) = (range(xs), range(ys));
        Some([x_min, x_max, y_min, y_max])
    }

    /// Adds to each `sums[t]` the sample at `(xs[t] + offset[0], ys[t] + offset[1])`, whose four
    /// pixels are inside the image, as [`Plane::add_samples_inside`] does, `extremes` being
    /// `xs`' and `ys`' ([`extremes`]). Where the samples at the extremes have their pixels inside,
    /// all of them have (rounding is monotone: a lesser coordinate never gives a greater sum or
    /// floor), and four samples at a time are worked out without testing theirs; otherwise the
    /// registers test each four, and from the first four that are not inside (the rounding's
    /// slack at the window's edge; none where the caller is right), and the last one to three,
    /// [`Plane::sample_inside`] takes them one by one.
    ///
    /// # Safety
    /// The CPU must have AVX2; `extremes`, when given, those of `xs` and `ys`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn add_samples_inside(
        plane: &Plane,
        xs: &[f64],
        ys: &[f64],
        extremes: Option<[f64; 4]>,
        offset: [f64; 2],
        sums: &mut [f32],
    ) {
        let n = xs.len().min(ys.len()).min(sums.len());
        let (w, h) = (plane.width as usize, plane.height as usize);
        let mut t = 0;
        if w >= 2 && h >= 2 && plane.values.len() == w * h && w * h <= i32::MAX as usize {
            // SAFETY: AVX2 by the caller; the image's size checked above.
            t = unsafe {
                if all_inside(plane, extremes, offset) {
                    add_lanes::<false>(plane, xs, ys, offset, sums, n)
                } else {
                    add_lanes::<true>(plane, xs, ys, offset, sums, n)
                }
            };
        }
        for t in t..n {
            sums[t] += plane.sample_inside(xs[t] + offset[0], ys[t] + offset[1]);
        }
    }

    /// The bilinear samples of a `w`-wide plane's `values` at four points whose coordinates less
    /// half a pixel are `(fx, fy)`, of floors `(cx, cy)`: the fractions rounded to `f32`, the
    /// pixel's index from `cy · w + cx` in `f64`, the four pixels read as two adjacent pairs
    /// ([`pairs`]) and mixed as [`Plane::sample_inside`] mixes them.
    ///
    /// # Safety
    /// The CPU must have AVX2; each point's pixel and the one below right of it inside the plane
    /// (`0 <= cx <= w - 2`, `0 <= cy <= h - 2` for a `w x h` plane of `w · h <= i32::MAX`).
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn sample4(
        values: *const f32,
        w: usize,
        (fx, fy): (__m256d, __m256d),
        (cx, cy): (__m256d, __m256d),
    ) -> __m128 {
        let one = _mm_set1_ps(1.0);
        let (tx, ty) = (
            _mm256_cvtpd_ps(_mm256_sub_pd(fx, cx)),
            _mm256_cvtpd_ps(_mm256_sub_pd(fy, cy)),
        );
        // Whole numbers in `0..w · h <= i32::MAX`: exact, and unsigned.
        let pixel = _mm256_cvtpd_epi32(_mm256_add_pd(
            _mm256_mul_pd(cy, _mm256_set1_pd(w as f64)),
            cx,
        ));
        let mut index = [0u32; 4];
        // SAFETY: four `u32` into a four-element array, unaligned store.
        unsafe { _mm_storeu_si128(index.as_mut_ptr().cast(), pixel) };
        // SAFETY: `pixel = cy · w + cx` with `0 <= cx <= w - 2`, `0 <= cy <= h - 2` (by the
        // caller), so `pixel + w + 1 <= w · h - 1`: all four pairs of both rows inside `values`.
        let ((a, b), (c, d)) = unsafe { (pairs(values, index), pairs(values.add(w), index)) };
        let (left, up) = (_mm_sub_ps(one, tx), _mm_sub_ps(one, ty));
        let top = _mm_add_ps(_mm_mul_ps(a, left), _mm_mul_ps(b, tx));
        let bottom = _mm_add_ps(_mm_mul_ps(c, left), _mm_mul_ps(d, tx));
        _mm_add_ps(_mm_mul_ps(top, up), _mm_mul_ps(bottom, ty))
    }

    /// Whether the plane suits the four-at-a-time sampling (at least 2 x 2 pixels, its values
    /// `w · h <= i32::MAX`) and every sample at `(xs[t] + offset[0], ys[t] + offset[1])` has
    /// its four pixels inside it, `extremes` being `xs`' and `ys`' ([`extremes`]): where the
    /// samples at the extremes have, all have (rounding is monotone: a lesser coordinate never
    /// gives a greater sum or floor).
    pub(super) fn all_inside(plane: &Plane, extremes: Option<[f64; 4]>, offset: [f64; 2]) -> bool {
        let (w, h) = (plane.width as usize, plane.height as usize);
        if w < 2 || h < 2 || plane.values.len() != w * h || w * h > i32::MAX as usize {
            return false;
        }
        // The lanes' operations on the extremes: the pixels' column or row.
        let corner = |v: f64, o: f64| ((v + o) - 0.5).floor();
        extremes.is_some_and(|[x_min, x_max, y_min, y_max]| {
            corner(x_min, offset[0]) >= 0.0
                && corner(x_max, offset[0]) <= (w - 2) as f64
                && corner(y_min, offset[1]) >= 0.0
                && corner(y_max, offset[1]) <= (h - 2) as f64
        })
    }

    /// The x-signature's rows four at a time, every step of `steps` for each four before the
    /// next, their sums held in a register: to each `sums[t]` (of whole fours of rows; returns
    /// how many) the samples at `(xs[t] + step[0], ys[t] + step[1])` added in the order of
    /// `steps`, the same additions, in the same order, of the same values as
    /// [`add_samples_inside`] step after step, without storing and reading back the sums
    /// between steps.
    ///
    /// # Safety
    /// The CPU must have AVX2; [`all_inside`] must hold for every step.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn rows_inside(
        plane: &Plane,
        xs: &[f64],
        ys: &[f64],
        steps: &[[f64; 2]],
        sums: &mut [f32],
    ) -> usize {
        let n = xs.len().min(ys.len()).min(sums.len());
        let (w, values, half) = (
            plane.width as usize,
            plane.values.as_ptr(),
            _mm256_set1_pd(0.5),
        );
        let end = n - n % 4;
        for t in (0..end).step_by(4) {
            // SAFETY: `t + 4 <= end <= n`, within `xs`, `ys` and `sums`.
            let (x, y, mut sum) = unsafe {
                (
                    _mm256_loadu_pd(xs.as_ptr().add(t)),
                    _mm256_loadu_pd(ys.as_ptr().add(t)),
                    _mm_loadu_ps(sums.as_ptr().add(t)),
                )
            };
            for step in steps {
                let (fx, fy) = (
                    _mm256_sub_pd(_mm256_add_pd(x, _mm256_set1_pd(step[0])), half),
                    _mm256_sub_pd(_mm256_add_pd(y, _mm256_set1_pd(step[1])), half),
                );
                let (cx, cy) = (_mm256_floor_pd(fx), _mm256_floor_pd(fy));
                // SAFETY: every sample's pixels are inside the plane ([`all_inside`] for every
                // step, by the caller).
                sum = _mm_add_ps(sum, unsafe { sample4(values, w, (fx, fy), (cx, cy)) });
            }
            // SAFETY: as the loads above.
            unsafe { _mm_storeu_ps(sums.as_mut_ptr().add(t), sum) };
        }
        end
    }

    /// [`add_samples_inside`]'s four samples at a time, up to the first four whose pixels the
    /// registers show not inside the image when `TESTED` (without it, every sample's pixels must
    /// be inside); returns how many samples it added.
    ///
    /// # Safety
    /// The CPU must have AVX2; `n` at most the length of `xs`, `ys` and `sums`; the plane `w x h`
    /// with `w, h >= 2`, `values.len() == w · h <= i32::MAX`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn add_lanes<const TESTED: bool>(
        plane: &Plane,
        xs: &[f64],
        ys: &[f64],
        offset: [f64; 2],
        sums: &mut [f32],
        n: usize,
    ) -> usize {
        let (w, h) = (plane.width as usize, plane.height as usize);
        let (ox, oy, half) = (
            _mm256_set1_pd(offset[0]),
            _mm256_set1_pd(offset[1]),
            _mm256_set1_pd(0.5),
        );
        let zero = _mm256_set1_pd(0.0);
        let (last_x, last_y) = (
            _mm256_set1_pd((w - 2) as f64),
            _mm256_set1_pd((h - 2) as f64),
        );
        let values = plane.values.as_ptr();
        let (mut t, end) = (0, n - n % 4);
        while t < end {
            // SAFETY: `t + 4 <= end <= n`, within `xs`, `ys` and `sums`.
            let (x, y) = unsafe {
                (
                    _mm256_loadu_pd(xs.as_ptr().add(t)),
                    _mm256_loadu_pd(ys.as_ptr().add(t)),
                )
            };
            let (fx, fy) = (
                _mm256_sub_pd(_mm256_add_pd(x, ox), half),
                _mm256_sub_pd(_mm256_add_pd(y, oy), half),
            );
            let (cx, cy) = (_mm256_floor_pd(fx), _mm256_floor_pd(fy));
            if TESTED {
                // The pixel and the one below right of it inside the image (false for NaN).
                let inside = _mm256_and_pd(
                    _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_GE_OQ>(cx, zero),
                        _mm256_cmp_pd::<_CMP_LE_OQ>(cx, last_x),
                    ),
                    _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_GE_OQ>(cy, zero),
                        _mm256_cmp_pd::<_CMP_LE_OQ>(cy, last_y),
                    ),
                );
                if _mm256_movemask_pd(inside) != 0b1111 {
                    break;
                }
            }
            // SAFETY: the pixels of the four are inside the image (tested, or by the caller).
            let sample = unsafe { sample4(values, w, (fx, fy), (cx, cy)) };
            // SAFETY: as the loads above.
            unsafe {
                let at = sums.as_mut_ptr().add(t);
                _mm_storeu_ps(at, _mm_add_ps(_mm_loadu_ps(at), sample));
            }
            t += 4;
        }
        t
    }
}

/// Doubles the period of every halved block (see [`ridge_periods`]) where at least a third of
/// the measured blocks of its 3 x 3 neighbourhood are halved too: pores and light ridge middles
/// cover a stretch of the print, while noise halves a block here and there.
fn double_halved(period: &mut [f32], measured: &[bool], halved: &[bool], cols: usize, rows: usize) {
    for j in 0..rows {
        for i in 0..cols {
            let b = j * cols + i;
            if !halved[b] {
                continue;
            }
            let around = neighbourhood(i, j, cols, rows).filter(|&c| measured[c]);
            let (n, h) = around.fold((0, 0), |(n, h), c| (n + 1, h + usize::from(halved[c])));
            if 3 * h >= n {
                period[b] *= 2.0;
            }
        }
    }
}

/// The indices of block `(i, j)`'s 3 x 3 neighbourhood inside a `cols` x `rows` grid, row by row.
fn neighbourhood(i: usize, j: usize, cols: usize, rows: usize) -> impl Iterator<Item = usize> {
    (j.saturating_sub(1)..(j + 2).min(rows))
        .flat_map(move |jj| (i.saturating_sub(1)..(i + 2).min(cols)).map(move |ii| jj * cols + ii))
}

/// The normalized correlation of the signature, less its `mean`, with itself shifted by `lag`
/// samples (linear interpolation between samples); 0 when the overlap is flat or under 4 samples.
fn correlation(signature: &[f32], mean: f32, lag: f32) -> f32 {
    let n = signature.len();
    let whole = lag.floor() as usize;
    let frac = lag - whole as f32;
    if whole + 1 + 4 > n {
        return 0.0;
    }
    let (mut sxy, mut sxx, mut syy) = (0.0f32, 0.0f32, 0.0f32);
    for t in 0..n - whole - 1 {
        let x = signature[t] - mean;
        let y = (1.0 - frac) * signature[t + whole] + frac * signature[t + whole + 1] - mean;
        sxy += x * y;
        sxx += x * x;
        syy += y * y;
    }
    if sxx <= 0.0 || syy <= 0.0 {
        return 0.0;
    }
    sxy / (sxx * syy).sqrt()
}

/// Fills the unmeasured blocks wave by wave from their filled 8-neighbours, then averages each
/// block with its 3 x 3 neighbours; `fallback` everywhere when nothing was measured.
fn fill_and_smooth(
    mut period: Vec<f32>,
    measured: &[bool],
    cols: usize,
    rows: usize,
    fallback: f32,
) -> Vec<f32> {
    let mut filled = measured.to_vec();
    if !filled.iter().any(|&f| f) {
        return vec![fallback; period.len()];
    }
    let mut wave = Vec::new();
    loop {
        wave.clear();
        for j in 0..rows {
            for i in 0..cols {
                if filled[j * cols + i] {
                    continue;
                }
                let (mut sum, mut n) = (0.0f32, 0);
                for c in neighbourhood(i, j, cols, rows).filter(|&c| filled[c]) {
                    sum += period[c];
                    n += 1;
                }
                if n > 0 {
                    wave.push((j * cols + i, sum / n as f32));
                }
            }
        }
        if wave.is_empty() {
            break;
        }
        for &(b, p) in &wave {
            period[b] = p;
            filled[b] = true;
        }
    }
    let mut smoothed = vec![0.0f32; period.len()];
    for j in 0..rows {
        for i in 0..cols {
            let (mut sum, mut n) = (0.0f32, 0.0f32);
            for c in neighbourhood(i, j, cols, rows) {
                sum += period[c];
                n += 1.0;
            }
            smoothed[j * cols + i] = sum / n;
        }
    }
    smoothed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fingerprint::fields::BlockGrid;
    use crate::fingerprint::tests::ridges_in_disk;

    fn periods_of(period: f64, theta: f64) -> RidgePeriods {
        let gray = ridges_in_disk(128, 128, period, theta, [64.0, 64.0], 200.0);
        periods_in(&gray, theta, &[(8, 8), (7, 8)])
    }

    /// The periods of `gray` (128 x 128) with ridges along `theta` everywhere, inside the print
    /// on the 8 px blocks `inside` only.
    fn periods_in(gray: &Plane, theta: f64, inside_blocks: &[(usize, usize)]) -> RidgePeriods {
        let grid = BlockGrid::new(128, 128, 8);
        let mut inside = vec![false; grid.len()];
        for &(i, j) in inside_blocks {
            inside[grid.index(i, j)] = true;
        }
        let s = Segmentation { grid, inside };
        let field = OrientationField {
            grid,
            angle: vec![theta as f32; grid.len()],
            coherence: vec![1.0; grid.len()],
        };
        ridge_periods(gray, &s, &field, &FingerprintParams::default())
    }

    /// The extrema found 64 at a time are those of the loop with a branch on each sample, on
    /// random signatures with plateaus, ties at the ends and either sign of zero, at every length.
    #[test]
    fn extrema_by_words_are_extrema_one_by_one() {
        let one_by_one = |signature: &[f32], extremum: f32| -> Vec<usize> {
            let mut found = Vec::new();
            for k in 1..signature.len().saturating_sub(1) {
                let (p, q, r) = (
                    extremum * signature[k - 1],
                    extremum * signature[k],
                    extremum * signature[k + 1],
                );
                if q > p && q >= r {
                    found.push(k);
                }
            }
            found
        };
        let mut state = crate::synth::lcg(35);
        let mut next = move || state() >> 33;
        for case in 0..400 {
            let length = case % 200;
            let levels = 1 + next() % 6;
            let signature: Vec<f32> = (0..length)
                .map(|_| match next() % 8 {
                    0 => -0.0,
                    1 => 0.0,
                    _ => (next() % levels) as f32 - 2.5,
                })
                .collect();
            for extremum in [1.0f32, -1.0] {
                let mut found = Vec::new();
                extrema(&signature, extremum, |k| found.push(k));
                assert_eq!(found, one_by_one(&signature, extremum), "case {case}");
            }
        }
    }

    /// [`x_signature`] as it was first written: every sample clamped at the image's edges.
    fn x_signature_clamped(smoothed: &Plane, starts: &[[f64; 2]], steps: &[[f64; 2]]) -> Vec<f32> {
        starts
            .iter()
            .map(|start| {
                let mut sum = 0.0f32;
                for step in steps {
                    sum += smoothed.sample(start[0] + step[0], start[1] + step[1]);
                }
                sum / steps.len() as f32
            })
            .collect()
    }

    #[test]
    fn the_signature_is_the_clamped_one_bit_for_bit() {
        // Windows inside, across each edge and corner, and outside the image, at odd angles:
        // the rows read directly give the values of the rows clamped at the edges.
        let smoothed = Plane::uneven(70, 52, [7919, 263], 0.29, -9.0);
        let (length, across) = (48usize, 16usize);
        for c in [
            [35.2, 26.1],
            [3.0, 26.0],
            [66.5, 40.2],
            [20.0, 1.0],
            [2.0, 50.0],
            [-9.0, 70.0],
            [40.7, 30.3],
            [12.9, 17.4],
        ] {
            for angle in [0.0f64, 0.4, 1.3, 1.57, 2.2, 2.71, 3.0] {
                let (along, normal) = ([angle.cos(), angle.sin()], [-angle.sin(), angle.cos()]);
                let offset = |k: usize| k as f64 - across as f64 / 2.0 + 0.5;
                let steps: Vec<[f64; 2]> = (0..across)
                    .map(|k| [offset(k) * along[0], offset(k) * along[1]])
                    .collect();
                let starts: Vec<[f64; 2]> = (0..length)
                    .map(|t| {
                        let u = t as f64 - length as f64 / 2.0 + 0.5;
                        [c[0] + u * normal[0], c[1] + u * normal[1]]
                    })
                    .collect();
                // In the CPU's lanes (AVX2 where it has them) and in baseline ones.
                let mut signature = vec![0.0f32; length];
                let mut coordinates = (vec![1.0; 3], Vec::new());
                x_signature(&smoothed, &starts, &steps, &mut signature, &mut coordinates);
                let mut baseline = vec![0.0f32; length];
                x_signature_lanes::<false>(
                    &smoothed,
                    &starts,
                    &steps,
                    &mut baseline,
                    &mut coordinates,
                );
                let clamped = x_signature_clamped(&smoothed, &starts, &steps);
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&signature),
                    bits(&clamped),
                    "centre {c:?}, angle {angle}"
                );
                assert_eq!(
                    bits(&baseline),
                    bits(&clamped),
                    "centre {c:?}, angle {angle}"
                );
            }
        }
    }

    #[test]
    fn the_signature_measures_the_period_at_any_angle() {
        for (period, theta) in [(6.0, 0.0), (9.0, 0.7), (12.0, 2.0), (16.0, 1.57)] {
            let p = periods_of(period, theta);
            assert!(p.measured[p.grid.index(8, 8)]);
            // Unmeasured blocks are filled from the measured ones.
            assert!(!p.measured[0]);
            for b in [p.grid.index(8, 8), 0] {
                let found = f64::from(p.period[b]);
                assert!((found - period).abs() < 0.12 * period, "{period}: {found}");
            }
        }
    }

    #[test]
    fn ridges_with_lighter_middles_keep_their_period() {
        // Dark ridges 16 px apart whose middles are lighter: the profile -cos x + 0.6 cos 2x has
        // its minima 0.36 and 0.64 periods apart, so consecutive extremes are half a period apart
        // on average.
        let (size, period, theta) = (128u32, 16.0f64, 0.6f64);
        let normal = [-theta.sin(), theta.cos()];
        let mut values = Vec::with_capacity((size * size) as usize);
        for y in 0..size {
            for x in 0..size {
                let u = f64::from(x) * normal[0] + f64::from(y) * normal[1];
                let a = std::f64::consts::TAU * u / period;
                values.push((128.0 + 50.0 * (-a.cos() + 0.6 * (2.0 * a).cos())) as f32);
            }
        }
        let gray = Plane {
            width: size,
            height: size,
            values,
        };
        let blocks: Vec<(usize, usize)> =
            (5..11).flat_map(|j| (5..11).map(move |i| (i, j))).collect();
        let p = periods_in(&gray, theta, &blocks);
        let b = p.grid.index(8, 8);
        assert!(p.measured[b]);
        let found = f64::from(p.period[b]);
        assert!((found - period).abs() < 0.12 * period, "{found}");
    }

    #[test]
    fn nothing_measured_gives_the_default_within_limits() {
        let flat = Plane {
            width: 32,
            height: 32,
            values: vec![9.0; 1024],
        };
        let grid = BlockGrid::new(32, 32, 8);
        let s = Segmentation {
            grid,
            inside: vec![true; grid.len()],
        };
        let field = OrientationField {
            grid,
            angle: vec![0.0; grid.len()],
            coherence: vec![0.0; grid.len()],
        };
        let params = FingerprintParams::default();
        let p = ridge_periods(&flat, &s, &field, &params);
        assert!(p.measured.iter().all(|&m| !m));
        assert!(p
            .period
            .iter()
            .all(|&v| f64::from(v) == params.default_period));
    }
}
