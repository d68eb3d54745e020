//! Small image operations the fingerprint stages share: a separable Gaussian blur, Sobel
//! gradients, the exact squared Euclidean distance transform and the closing by a disk it gives,
//! and connected components on a grid of block flags (its 3x3 morphology is the masks' own,
//! `mask::morph3`).

use super::fields::{BlockGrid, Plane};
use crate::mask::{label_components, Connectivity};
use std::ops::Range;

/// Gaussian blur with standard deviation `sigma` px (radius `ceil(3 sigma)`), borders clamped.
/// `sigma <= 0` returns a copy.
pub(crate) fn gaussian_blur(plane: &Plane, sigma: f64) -> Plane {
    let (w, h) = (plane.width as usize, plane.height as usize);
    gaussian_blur_within(plane, sigma, 0..w, 0..h)
}

/// [`gaussian_blur`] at the pixels of the box `xs` x `ys` only: each of them the same sum, term
/// by term, as the whole image's blur gives (the rows the box's column taps reach are blurred
/// along the box's columns only), the pixels outside the box zero (`sigma <= 0`: a copy). The
/// plane of [`gaussian_blur_rows`]' rows.
pub(crate) fn gaussian_blur_within(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
) -> Plane {
    if sigma.is_nan() || sigma <= 0.0 || plane.values.is_empty() {
        return plane.clone();
    }
    let (w, h) = (plane.width as usize, plane.height as usize);
    // Each row stored once, the zeros around the box's part of it pushed as it comes: the
    // plane is not zeroed first (in the cache, where zeroing it whole wrote it out to memory
    // first).
    let mut out = Vec::with_capacity(w * h);
    gaussian_blur_rows(plane, sigma, xs, ys, &mut |y, x0, row| {
        out.resize(y * w + x0, 0.0);
        out.extend_from_slice(row);
    });
    out.resize(w * h, 0.0);
    Plane {
        width: plane.width,
        height: plane.height,
        values: out,
    }
}

/// [`gaussian_blur_within`]'s rows, handed to `row` one after the other as `(y, x0, values)`:
/// row `y`'s blurred values from column `x0` on, over the box `xs` x `ys` clamped to the plane
/// (`sigma <= 0`: the plane's own values). Nothing the size of the plane is allocated: only the
/// rows the column taps reach at once (`2 ceil(3 sigma) + 1`) are kept.
///
/// Each sum is kept in a register over all its taps, [`BLUR_LANES`] columns side by side, and
/// stored once, where the passes used to add each tap into the row in memory (the same terms in
/// the same order from 0: a test holds it to that version bit for bit); with AVX2 at run time the
/// lanes are eight wide ([`wide_lanes`]; the same operations, so the same values).
pub(crate) fn gaussian_blur_rows(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
    row: &mut dyn FnMut(usize, usize, &[f32]),
) {
    #[cfg(target_arch = "x86_64")]
    if wide_lanes() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { gaussian_blur_rows_wide(plane, sigma, xs, ys, row) };
    }
    gaussian_blur_rows_lanes::<false>(plane, sigma, xs, ys, row)
}

/// [`gaussian_blur_rows`] compiled for AVX2, its sums in AVX registers (`wide`).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gaussian_blur_rows_wide(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
    row: &mut dyn FnMut(usize, usize, &[f32]),
) {
    gaussian_blur_rows_lanes::<true>(plane, sigma, xs, ys, row)
}

/// Columns of [`gaussian_blur_rows`] summed side by side.
const BLUR_LANES: usize = 16;

/// [`gaussian_blur_rows`]' passes, inlined into the version the CPU runs (`WIDE`: the one for
/// AVX2, which the CPU must have).
#[inline(always)]
fn gaussian_blur_rows_lanes<const WIDE: bool>(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
    row: &mut dyn FnMut(usize, usize, &[f32]),
) {
    let (w, h) = (plane.width as usize, plane.height as usize);
    let (xs, ys) = (xs.start..xs.end.min(w), ys.start..ys.end.min(h));
    if xs.is_empty() || ys.is_empty() || plane.values.is_empty() {
        return;
    }
    if sigma.is_nan() || sigma <= 0.0 {
        for y in ys {
            row(y, xs.start, &plane.values[y * w + xs.start..y * w + xs.end]);
        }
        return;
    }
    let kernel = gaussian_kernel(sigma);
    let r = kernel.len() / 2;
    // The rows the column taps of the box's rows reach (clamped at the borders), from `reach`,
    // blurred along the box's columns as the taps first reach them, each into the slot of a
    // ring of the `2r + 1` rows one output row reads (row `y` at `(y - reach.start) % ring`:
    // the rows a later output row reads were blurred after any row their slots held before).
    let reach = ys.start.saturating_sub(r)..(ys.end + r).min(h);
    let ring = kernel.len().min(reach.len());
    let mut rows = vec![0.0f32; ring * w];
    let taps: Vec<usize> = (0..kernel.len()).collect();
    // Away from the borders, the taps without clamping, tap by tap for all those columns
    // side by side (the same sum for each column, term by term).
    let inner = if w > 2 * r {
        xs.start.max(r)..xs.end.min(w - r)
    } else {
        0..0
    };
    let border = if inner.is_empty() {
        [xs.clone(), 0..0]
    } else {
        [xs.start..inner.start, inner.end..xs.end]
    };
    let mut next = reach.start;
    let mut starts = Vec::with_capacity(kernel.len());
    let mut out = vec![0.0f32; xs.len()];
    for y in ys {
        while next <= (y + r).min(h - 1) {
            let line = &plane.values[next * w..(next + 1) * w];
            let slot = (next - reach.start) % ring;
            let blurred = &mut rows[slot * w..(slot + 1) * w];
            if !inner.is_empty() {
                weighted_sums::<WIDE>(
                    &kernel,
                    &line[inner.start - r..inner.end + r],
                    &taps,
                    &mut blurred[inner.clone()],
                );
            }
            for x in border.clone().into_iter().flatten() {
                let mut s = 0.0;
                let lo = x as i64 - r as i64;
                for (k, &c) in kernel.iter().enumerate() {
                    let xx = (lo + k as i64).clamp(0, w as i64 - 1) as usize;
                    s += c * line[xx];
                }
                blurred[x] = s;
            }
            next += 1;
        }
        // Tap `k` reads row `y + k - r` clamped, one row on from the tap before or the same
        // row again: its slot is the one after or the same (one division a row).
        let mut last = y.saturating_sub(r);
        let mut slot = (last - reach.start) % ring;
        starts.clear();
        for k in 0..kernel.len() {
            let yy = (y + k).saturating_sub(r).min(h - 1);
            if yy != last {
                last = yy;
                slot = if slot + 1 == ring { 0 } else { slot + 1 };
            }
            starts.push(slot * w + xs.start);
        }
        weighted_sums::<WIDE>(&kernel, &rows, &starts, &mut out);
        row(y, xs.start, &out);
    }
}

/// `out[x] = Σ_k kernel[k] · src[starts[k] + x]`, added from 0 in the order of `k`,
/// [`BLUR_LANES`] columns at a time in registers (`WIDE`: in AVX registers, which the CPU must
/// have).
#[inline(always)]
fn weighted_sums<const WIDE: bool>(kernel: &[f32], src: &[f32], starts: &[usize], out: &mut [f32]) {
    // SAFETY: `WIDE` only where the CPU has AVX2 (`gaussian_blur_within_wide`).
    #[cfg(target_arch = "x86_64")]
    if WIDE && unsafe { wide::weighted_sums(kernel, src, starts, out) } {
        return;
    }
    let mut chunks = out.chunks_exact_mut(BLUR_LANES);
    let mut x = 0;
    for chunk in &mut chunks {
        let mut sums = [0.0f32; BLUR_LANES];
        for (&c, &start) in kernel.iter().zip(starts) {
            let line = &src[start + x..start + x + BLUR_LANES];
            for (s, &v) in sums.iter_mut().zip(line) {
                *s += c * v;
            }
        }
        chunk.copy_from_slice(&sums);
        x += BLUR_LANES;
    }
    for (i, o) in chunks.into_remainder().iter_mut().enumerate() {
        let mut s = 0.0f32;
        for (&c, &start) in kernel.iter().zip(starts) {
            s += c * src[start + x + i];
        }
        *o = s;
    }
}

/// [`weighted_sums`] in AVX registers: thirty-two columns at a time (four registers), then
/// sixteen or eight, then one by one; each tap's weight broadcast, the same operations in the
/// same order as the baseline sums (no fused multiply-add), so the same values (a test holds
/// them bit for bit).
#[cfg(target_arch = "x86_64")]
mod wide {
    use std::arch::x86_64::{
        _mm256_add_ps, _mm256_loadu_ps, _mm256_mul_ps, _mm256_set1_ps, _mm256_setzero_ps,
        _mm256_storeu_ps,
    };

    /// `out[x] = Σ_k kernel[k] · src[starts[k] + x]`; false, having written nothing, where a
    /// tap's row does not reach `out`'s last column within `src` (the caller then sums as on
    /// baseline x86-64).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn weighted_sums(
        kernel: &[f32],
        src: &[f32],
        starts: &[usize],
        out: &mut [f32],
    ) -> bool {
        let n = out.len();
        if starts.len() != kernel.len()
            || starts
                .iter()
                .any(|&s| s.checked_add(n).is_none_or(|end| end > src.len()))
        {
            return false;
        }
        let taps = kernel.iter().zip(starts);
        let mut x = 0;
        while x + 8 <= n {
            // SAFETY: the CPU has AVX2 (by the caller); each group's last column is below
            // `n`, so every tap's row reaches it within `src` (checked above).
            x += unsafe {
                if x + 32 <= n {
                    lane_sums::<4>(kernel, src, starts, x, out)
                } else if x + 16 <= n {
                    lane_sums::<2>(kernel, src, starts, x, out)
                } else {
                    lane_sums::<1>(kernel, src, starts, x, out)
                }
            };
        }
        for (i, o) in out[x..].iter_mut().enumerate() {
            let mut s = 0.0f32;
            for (&c, &start) in taps.clone() {
                s += c * src[start + x + i];
            }
            *o = s;
        }
        true
    }

    /// [`weighted_sums`] of the `8 · L` columns from `x`, in `L` registers: each register's
    /// sums wait on the one before at every tap (an addition's latency), so more registers
    /// side by side keep more additions under way; the same terms in the same order for every
    /// column whatever `L`. Returns the columns written.
    ///
    /// # Safety
    /// The CPU must have AVX2; `x + 8 · L <= out.len()` and every `start + x + 8 · L` of
    /// `starts` at most `src.len()`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn lane_sums<const L: usize>(
        kernel: &[f32],
        src: &[f32],
        starts: &[usize],
        x: usize,
        out: &mut [f32],
    ) -> usize {
        let mut s = [_mm256_setzero_ps(); L];
        for (&c, &start) in kernel.iter().zip(starts) {
            let c = _mm256_set1_ps(c);
            // SAFETY: `start + x + 8 · L <= src.len()`, by the caller.
            let at = unsafe { src.as_ptr().add(start + x) };
            for (l, s) in s.iter_mut().enumerate() {
                // SAFETY: as above.
                *s = _mm256_add_ps(
                    *s,
                    _mm256_mul_ps(c, unsafe { _mm256_loadu_ps(at.add(8 * l)) }),
                );
            }
        }
        for (l, s) in s.into_iter().enumerate() {
            // SAFETY: `x + 8 · L <= out.len()`, by the caller.
            unsafe { _mm256_storeu_ps(out.as_mut_ptr().add(x + 8 * l), s) };
        }
        8 * L
    }
}

/// Whether the CPU has AVX2, for the loops compiled twice, for baseline x86-64 and for AVX2:
/// eight lanes of `f32` a vector instruction instead of four, the same operations in the same
/// order, so the same values (no fused multiply-add: that is another feature, not enabled).
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn wide_lanes() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// A normalized Gaussian of standard deviation `sigma`, radius `ceil(3 sigma)`.
pub(crate) fn gaussian_kernel(sigma: f64) -> Vec<f32> {
    let r = (3.0 * sigma).ceil().max(1.0) as i64;
    let mut k: Vec<f32> = (-r..=r)
        .map(|i| (-(i * i) as f64 / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let sum: f32 = k.iter().sum();
    k.iter_mut().for_each(|v| *v /= sum);
    k
}

/// Sobel gradients `(g_x, g_y)` (x to the right, y down), borders clamped: the planes of
/// [`sobel_row`]'s rows (the tests' reference for [`gradients`], which keeps a row at a time).
#[cfg(test)]
pub(crate) fn sobel(plane: &Plane) -> (Plane, Plane) {
    let (w, h) = (plane.width as usize, plane.height as usize);
    // Each row pushed as it is worked out: the planes are not zeroed first.
    let mut gx = Vec::with_capacity(w * h);
    let mut gy = Vec::with_capacity(w * h);
    for y in 0..h {
        sobel_row(plane, y, &mut gx, &mut gy);
    }
    let plane_of = |values| Plane {
        width: plane.width,
        height: plane.height,
        values,
    };
    (plane_of(gx), plane_of(gy))
}

/// Appends row `y` of the Sobel gradients of `plane` (borders clamped) to `gx` and `gy`.
///
/// Inside the image the row's gradients are worked out from the three rows around it, taken
/// as slices shifted by a column, so that the columns go side by side in vector lanes (the same
/// sums, term by term, as the nine pixels read one by one: a test holds it bit for bit); the
/// pixels on the image's edge (and every pixel of a plane whose values do not match its size)
/// read their clamped neighbours one by one.
fn sobel_row(plane: &Plane, y: usize, gx: &mut Vec<f32>, gy: &mut Vec<f32>) {
    let (w, h) = (plane.width as usize, plane.height as usize);
    let edge = |x: usize| {
        let (x, y) = (x as i64, y as i64);
        let p = |dx: i64, dy: i64| plane.at(x + dx, y + dy);
        (
            (p(1, -1) + 2.0 * p(1, 0) + p(1, 1)) - (p(-1, -1) + 2.0 * p(-1, 0) + p(-1, 1)),
            (p(-1, 1) + 2.0 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2.0 * p(0, -1) + p(1, -1)),
        )
    };
    let push_edge = |gx: &mut Vec<f32>, gy: &mut Vec<f32>, x| {
        let (ex, ey) = edge(x);
        gx.push(ex);
        gy.push(ey);
    };
    let v = &plane.values;
    if v.len() != w * h || y == 0 || y + 1 >= h || w < 3 {
        for x in 0..w {
            push_edge(gx, gy, x);
        }
        return;
    }
    // Columns 1..w-1: the pixels left of, at and right of each, in the rows above, at and
    // below it (`a b c / d · f / g k m`), as slices of equal length.
    let n = w - 2;
    let (up, mid, down) = (
        &v[(y - 1) * w..y * w],
        &v[y * w..(y + 1) * w],
        &v[(y + 1) * w..(y + 2) * w],
    );
    let (a, b, c) = (&up[..n], &up[1..n + 1], &up[2..]);
    let (d, f) = (&mid[..n], &mid[2..]);
    let (g, k, m) = (&down[..n], &down[1..n + 1], &down[2..]);
    push_edge(gx, gy, 0);
    gx.extend((0..n).map(|i| (c[i] + 2.0 * f[i] + m[i]) - (a[i] + 2.0 * d[i] + g[i])));
    gy.extend((0..n).map(|i| (g[i] + 2.0 * k[i] + m[i]) - (a[i] + 2.0 * b[i] + c[i])));
    push_edge(gx, gy, w - 1);
}

/// What the segmentation and the orientation field read of the Sobel gradients, per block of
/// `grid` ([`gradients`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BlockGradients {
    /// The blocks of the image the gradients were taken of.
    pub grid: BlockGrid,
    /// Per block, the gradient structure tensor's sums `[Σ g_x², Σ g_y², Σ g_x g_y]` over its
    /// pixels, in double precision, added pixel by pixel in raster order.
    pub tensor: Vec<[f64; 3]>,
    /// Per block, the mean of its pixels' gradient magnitudes (each row's sum in double
    /// precision, the rows added in order).
    pub mean_magnitude: Vec<f32>,
}

/// The Sobel gradients of `plane` (borders clamped) as the segmentation and the orientation
/// field read them: every pixel's gradient magnitude `sqrt(g_x² + g_y²)` (row-major; the
/// segmentation's percentile reads them all) and the sums per block of `block` px
/// ([`BlockGradients`]). The gradients are worked out a row at a time and never kept as planes:
/// two full planes of `f32` at once, the largest part of a print's peak memory, where the
/// kernel zeroes each page on its first touch (docs/fingerprints.md, "Speed: the front stages'
/// planes"). Each sum takes the same terms in the same order as the planes' did.
// Not inlined into the front stages, where its loops measured 0.2 M instructions more a print.
#[inline(never)]
pub(crate) fn gradients(plane: &Plane, block: u32) -> (Vec<f32>, BlockGradients) {
    let grid = BlockGrid::new(plane.width, plane.height, block);
    let (w, h) = (plane.width as usize, plane.height as usize);
    let (cols, b) = (grid.cols as usize, grid.block as usize);
    let mut magnitude = Vec::with_capacity(w * h);
    let mut tensor = vec![[0.0f64; 3]; grid.len()];
    let mut sums = vec![0.0f64; grid.len()];
    let (mut gx, mut gy) = (Vec::with_capacity(w), Vec::with_capacity(w));
    for y in 0..h {
        gx.clear();
        gy.clear();
        sobel_row(plane, y, &mut gx, &mut gy);
        let start = magnitude.len();
        magnitude.extend(gx.iter().zip(&gy).map(|(a, b)| (a * a + b * b).sqrt()));
        let band = (y / b) * cols..(y / b + 1) * cols;
        let row = (&magnitude[start..], &gx[..], &gy[..]);
        let (tensor, sums) = (&mut tensor[band.clone()], &mut sums[band]);
        // The default block (8 px) with its width known to the compiler.
        if b == 8 {
            add_row::<8>(row, tensor, sums);
        } else {
            add_row_blocks(b, row, tensor, sums);
        }
    }
    let mut mean_magnitude = Vec::with_capacity(grid.len());
    for j in 0..grid.rows as usize {
        for i in 0..cols {
            let (x0, x1, y0, y1) = grid.pixels(i, j);
            let n = ((x1 - x0) * (y1 - y0)).max(1);
            mean_magnitude.push((sums[grid.index(i, j)] / n as f64) as f32);
        }
    }
    let blocks = BlockGradients {
        grid,
        tensor,
        mean_magnitude,
    };
    (magnitude, blocks)
}

/// Adds a row's part of each block of its band (`row`: the gradient magnitudes, `g_x` and `g_y`
/// of the row; `tensor` and `sums`: the band's blocks) to [`gradients`]' sums, blocks of `B` px.
#[inline(always)]
fn add_row<const B: usize>(
    (magnitude, gx, gy): (&[f32], &[f32], &[f32]),
    tensor: &mut [[f64; 3]],
    sums: &mut [f64],
) {
    let whole = magnitude.len() / B;
    let parts = (magnitude.chunks_exact(B).zip(gx.chunks_exact(B))).zip(gy.chunks_exact(B));
    for ((t, sum), ((m, gx), gy)) in tensor.iter_mut().zip(sums.iter_mut()).zip(parts) {
        add_block(m, gx, gy, t, sum);
    }
    if let (Some(t), Some(sum)) = (tensor.get_mut(whole), sums.get_mut(whole)) {
        let x0 = whole * B;
        add_block(&magnitude[x0..], &gx[x0..], &gy[x0..], t, sum);
    }
}

/// [`add_row`] for blocks of any width `b`.
fn add_row_blocks(
    b: usize,
    (magnitude, gx, gy): (&[f32], &[f32], &[f32]),
    tensor: &mut [[f64; 3]],
    sums: &mut [f64],
) {
    let parts = (magnitude.chunks(b).zip(gx.chunks(b))).zip(gy.chunks(b));
    for ((t, sum), ((m, gx), gy)) in tensor.iter_mut().zip(sums.iter_mut()).zip(parts) {
        add_block(m, gx, gy, t, sum);
    }
}

/// Adds one block's part of a row: its gradient magnitudes `m` (summed in double precision, then
/// added to `sum`) and `g_x`, `g_y` to the structure tensor `t`, pixel by pixel.
#[inline(always)]
fn add_block(m: &[f32], gx: &[f32], gy: &[f32], t: &mut [f64; 3], sum: &mut f64) {
    *sum += m.iter().map(|&v| f64::from(v)).sum::<f64>();
    // In registers over the row's part (stored back once).
    let [mut xx, mut yy, mut xy] = *t;
    for (&a, &c) in gx.iter().zip(gy) {
        let (a, c) = (f64::from(a), f64::from(c));
        xx += a * a;
        yy += c * c;
        xy += a * c;
    }
    *t = [xx, yy, xy];
}

/// [`sobel`] with every pixel's neighbours clamped at the image's edges, one pixel at a time
/// (the reference the tests hold the lanes to).
#[cfg(test)]
fn sobel_clamped(plane: &Plane) -> (Plane, Plane) {
    let (w, h) = (plane.width as i64, plane.height as i64);
    let mut gx = Vec::with_capacity(plane.values.len());
    let mut gy = Vec::with_capacity(plane.values.len());
    for y in 0..h {
        for x in 0..w {
            let p = |dx: i64, dy: i64| plane.at(x + dx, y + dy);
            gx.push((p(1, -1) + 2.0 * p(1, 0) + p(1, 1)) - (p(-1, -1) + 2.0 * p(-1, 0) + p(-1, 1)));
            gy.push((p(-1, 1) + 2.0 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2.0 * p(0, -1) + p(1, -1)));
        }
    }
    let plane_of = |values| Plane {
        width: plane.width,
        height: plane.height,
        values,
    };
    (plane_of(gx), plane_of(gy))
}

/// 4-connected component labels of the cells equal to `value` (`usize::MAX` elsewhere), with
/// each component's size, numbered in raster order of their first cell: the masks' labelling
/// ([`crate::mask::label_components`]) counted from 0.
pub(crate) fn components(
    flags: &[bool],
    cols: usize,
    rows: usize,
    value: bool,
) -> (Vec<usize>, Vec<usize>) {
    let (labels, sizes) = label_components(flags, cols, rows, value, Connectivity::Four);
    let labels = labels
        .into_iter()
        .map(|l| if l == 0 { usize::MAX } else { l as usize - 1 })
        .collect();
    (labels, sizes[1..].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mask::morph3;

    /// Speckled masks with a few blobs and lines (a fixed linear congruential sequence), of
    /// odd sizes, some without ink and one all ink.
    #[test]
    fn blur_keeps_a_constant_and_the_mean() {
        let p = Plane {
            width: 9,
            height: 7,
            values: (0..63).map(|i| if i == 31 { 63.0 } else { 0.0 }).collect(),
        };
        let b = gaussian_blur(&p, 1.0);
        let sum: f32 = b.values.iter().sum();
        assert!((sum - 63.0).abs() < 1e-3, "{sum}");
        assert!(b.values[31] < 63.0 && b.values[31] > b.values[30]);
        let flat = Plane {
            width: 5,
            height: 5,
            values: vec![7.0; 25],
        };
        assert!(gaussian_blur(&flat, 2.0)
            .values
            .iter()
            .all(|&v| (v - 7.0).abs() < 1e-4));
    }

    #[test]
    fn the_blur_within_a_box_is_the_whole_blur_there() {
        // Pseudo-random planes (a fixed linear congruential sequence), boxes inside, at the
        // borders and past them, and images narrower than the kernel.
        let mut lcg = crate::synth::lcg(12345u64);
        let mut next = move || (lcg() >> 33) as usize;
        for (width, height, sigma) in [(37, 29, 1.3), (50, 41, 4.5), (7, 40, 3.0), (40, 5, 2.2)] {
            let plane = Plane {
                width,
                height,
                values: (0..width * height).map(|_| (next() % 256) as f32).collect(),
            };
            let whole = gaussian_blur(&plane, sigma);
            let (w, h) = (width as usize, height as usize);
            for _ in 0..12 {
                let (a, b) = (next() % (w + 3), next() % (w + 3));
                let (c, d) = (next() % (h + 3), next() % (h + 3));
                let (xs, ys) = (a.min(b)..a.max(b), c.min(d)..c.max(d));
                let part = gaussian_blur_within(&plane, sigma, xs.clone(), ys.clone());
                for y in 0..h {
                    for x in 0..w {
                        let i = y * w + x;
                        let expected = if xs.contains(&x) && ys.contains(&y) {
                            whole.values[i]
                        } else {
                            0.0
                        };
                        assert_eq!(part.values[i].to_bits(), expected.to_bits(), "{x} {y}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_blur_in_registers_is_the_blur_tap_by_tap_bit_for_bit() {
        // Pseudo-random planes (a fixed linear congruential sequence) with negative values and
        // zeros, boxes inside, at the borders and past them, widths around the lanes' multiples
        // and images narrower than the kernel; in baseline lanes and in the CPU's own.
        let mut lcg = crate::synth::lcg(777u64);
        let mut next = move || (lcg() >> 33) as usize;
        let sizes = [
            (37, 29, 1.3),
            (50, 41, 4.5),
            (7, 40, 3.0),
            (40, 5, 2.2),
            (64, 20, 0.7),
        ];
        for (width, height, sigma) in sizes.into_iter().chain([(33, 33, 2.0), (17, 70, 5.5)]) {
            let plane = Plane {
                width,
                height,
                values: (0..width * height)
                    .map(|_| match next() % 5 {
                        0 => 0.0,
                        1 => -((next() % 300) as f32) * 0.71,
                        _ => (next() % 256) as f32 * 1.13,
                    })
                    .collect(),
            };
            let (w, h) = (width as usize, height as usize);
            let bits = |p: &Plane| p.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            for k in 0..14 {
                let (xs, ys) = if k == 0 {
                    (0..w, 0..h)
                } else {
                    let (a, b) = (next() % (w + 3), next() % (w + 3));
                    let (c, d) = (next() % (h + 3), next() % (h + 3));
                    (a.min(b)..a.max(b), c.min(d)..c.max(d))
                };
                let reference =
                    gaussian_blur_within_reference(&plane, sigma, xs.clone(), ys.clone());
                let mut lanes = Plane {
                    values: vec![0.0f32; w * h],
                    ..plane
                };
                gaussian_blur_rows_lanes::<false>(
                    &plane,
                    sigma,
                    xs.clone(),
                    ys.clone(),
                    &mut |y, x0, row| {
                        lanes.values[y * w + x0..y * w + x0 + row.len()].copy_from_slice(row);
                    },
                );
                let run = gaussian_blur_within(&plane, sigma, xs.clone(), ys.clone());
                assert_eq!(
                    bits(&lanes),
                    bits(&reference),
                    "{width} x {height}, {xs:?} {ys:?}"
                );
                assert_eq!(
                    bits(&run),
                    bits(&reference),
                    "{width} x {height}, {xs:?} {ys:?}"
                );
            }
        }
    }

    /// The blur before its sums were kept in registers: each tap added into the row in memory.
    /// [`gaussian_blur`] at the pixels of the box `xs` x `ys` only: each of them the same sum, term
    /// by term, as the whole image's blur gives (the rows the box's column taps reach are blurred
    /// along the box's columns only), the pixels outside the box zero (`sigma <= 0`: a copy).
    fn gaussian_blur_within_reference(
        plane: &Plane,
        sigma: f64,
        xs: Range<usize>,
        ys: Range<usize>,
    ) -> Plane {
        if sigma.is_nan() || sigma <= 0.0 || plane.values.is_empty() {
            return plane.clone();
        }
        let kernel = gaussian_kernel(sigma);
        let r = kernel.len() / 2;
        let (w, h) = (plane.width as usize, plane.height as usize);
        let (xs, ys) = (xs.start..xs.end.min(w), ys.start..ys.end.min(h));
        let mut rows = vec![0.0f32; w * h];
        let mut out = vec![0.0f32; w * h];
        if xs.is_empty() || ys.is_empty() {
            return Plane {
                width: plane.width,
                height: plane.height,
                values: out,
            };
        }
        // The rows the column taps of the box's rows reach (clamped at the borders).
        for y in ys.start.saturating_sub(r)..(ys.end + r).min(h) {
            let line = &plane.values[y * w..(y + 1) * w];
            let row = &mut rows[y * w..(y + 1) * w];
            // Away from the borders, the taps without clamping, tap by tap for all those columns
            // side by side (the same sum for each column, term by term).
            let inner = if w > 2 * r {
                xs.start.max(r)..xs.end.min(w - r)
            } else {
                0..0
            };
            for (k, &c) in kernel.iter().enumerate().filter(|_| !inner.is_empty()) {
                let taps = &line[inner.start + k - r..];
                for (out, &v) in row[inner.clone()].iter_mut().zip(taps) {
                    *out += c * v;
                }
            }
            for x in xs.clone() {
                if inner.contains(&x) {
                    continue;
                }
                let mut s = 0.0;
                let lo = x as i64 - r as i64;
                for (k, &c) in kernel.iter().enumerate() {
                    let xx = (lo + k as i64).clamp(0, w as i64 - 1) as usize;
                    s += c * line[xx];
                }
                row[x] = s;
            }
        }
        for y in ys {
            for (k, &c) in kernel.iter().enumerate() {
                let yy = (y as i64 + k as i64 - r as i64).clamp(0, h as i64 - 1) as usize;
                let (src, dst) = (
                    &rows[yy * w + xs.start..yy * w + xs.end],
                    &mut out[y * w + xs.start..y * w + xs.end],
                );
                for (d, &s) in dst.iter_mut().zip(src) {
                    *d += c * s;
                }
            }
        }
        Plane {
            width: plane.width,
            height: plane.height,
            values: out,
        }
    }

    #[test]
    fn sobel_of_a_ramp() {
        // Value = 2x - y: g_x = 8 * 2, g_y = -8 away from the border.
        let p = Plane {
            width: 6,
            height: 6,
            values: (0..36).map(|i| (2 * (i % 6) - i / 6) as f32).collect(),
        };
        let (gx, gy) = sobel(&p);
        assert_eq!(gx.values[2 * 6 + 2], 16.0);
        assert_eq!(gy.values[2 * 6 + 2], -8.0);
    }

    #[test]
    fn the_sobel_in_lanes_is_the_clamped_one_bit_for_bit() {
        // Pseudo-random planes (a fixed linear congruential sequence) of sizes down to one
        // pixel, thin in either direction.
        let mut lcg = crate::synth::lcg(4242u64);
        let mut next = move || ((lcg() >> 33) % 1000) as f32 * 0.37 - 90.0;
        for (width, height) in [
            (1, 1),
            (1, 7),
            (7, 1),
            (2, 5),
            (5, 2),
            (3, 3),
            (37, 29),
            (64, 3),
        ] {
            let plane = Plane {
                width,
                height,
                values: (0..width * height).map(|_| next()).collect(),
            };
            let (gx, gy) = sobel(&plane);
            let (cx, cy) = sobel_clamped(&plane);
            let bits = |p: &Plane| p.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&gx), bits(&cx), "{width} x {height}");
            assert_eq!(bits(&gy), bits(&cy), "{width} x {height}");
        }
    }

    /// The gradients a row at a time give the sums the planes of [`sobel`] gave, as the
    /// segmentation and the orientation field added them up, bit for bit.
    #[test]
    fn the_gradients_by_rows_are_the_planes_sums_bit_for_bit() {
        let mut lcg = crate::synth::lcg(977u64);
        let mut next = move || ((lcg() >> 33) % 1000) as f32 * 0.29 - 40.0;
        for (width, height, block) in [
            (1, 1, 8),
            (3, 40, 8),
            (37, 29, 8),
            (64, 48, 8),
            (50, 23, 7),
            (9, 9, 1),
        ] {
            let plane = Plane {
                width,
                height,
                values: (0..width * height).map(|_| next()).collect(),
            };
            let (magnitude, blocks) = gradients(&plane, block);
            let (gx, gy) = sobel(&plane);
            let planes_magnitude: Vec<f32> = (gx.values.iter().zip(&gy.values))
                .map(|(a, b)| (a * a + b * b).sqrt())
                .collect();
            let bits = |v: &[f32]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&magnitude), bits(&planes_magnitude));
            let grid = BlockGrid::new(width, height, block);
            assert_eq!(blocks.grid, grid);
            let w = width as usize;
            for j in 0..grid.rows as usize {
                for i in 0..grid.cols as usize {
                    let (x0, x1, y0, y1) = grid.pixels(i, j);
                    let (mut sum, mut xx, mut yy, mut xy) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
                    for y in y0..y1 {
                        sum += planes_magnitude[y * w + x0..y * w + x1]
                            .iter()
                            .map(|&v| f64::from(v))
                            .sum::<f64>();
                        for x in x0..x1 {
                            let (a, c) = (
                                f64::from(gx.values[y * w + x]),
                                f64::from(gy.values[y * w + x]),
                            );
                            xx += a * a;
                            yy += c * c;
                            xy += a * c;
                        }
                    }
                    let n = ((x1 - x0) * (y1 - y0)).max(1);
                    let b = grid.index(i, j);
                    let mean = (sum / n as f64) as f32;
                    assert_eq!(blocks.mean_magnitude[b].to_bits(), mean.to_bits());
                    let t = blocks.tensor[b];
                    assert_eq!(
                        [t[0].to_bits(), t[1].to_bits(), t[2].to_bits()],
                        [xx.to_bits(), yy.to_bits(), xy.to_bits()]
                    );
                }
            }
        }
    }

    #[test]
    fn morphology_and_components() {
        // A 5x4 grid with a 2x2 square and a single cell apart.
        let mut f = vec![false; 20];
        for c in [6, 7, 11, 12, 4] {
            f[c] = true;
        }
        let (label, sizes) = components(&f, 5, 4, true);
        assert_eq!(sizes, vec![1, 4]);
        assert_eq!(label[6], 1);
        let eroded = morph3(&f, 5, 4, false);
        assert!(eroded.iter().all(|&v| !v));
        let grown = morph3(&f, 5, 4, true);
        assert_eq!(grown.iter().filter(|&&v| v).count(), 18);
        // Erosion treats outside as print: a full grid stays full.
        assert!(morph3(&[true; 6], 3, 2, false).iter().all(|&v| v));
    }
}
