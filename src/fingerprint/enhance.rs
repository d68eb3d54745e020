//! Contextual enhancement (docs/fingerprints.md, "Enhancement"): each block is filtered with an
//! even Gabor filter tuned to its ridge orientation and period (Hong, Wan and Jain 1998; pyfing's
//! GBFEN), and the sign of the response is the binarization.
//!
//! The filter is `exp(-(u²/σ_n² + v²/σ_r²)/2) cos(2π u / T)` with `u` across the ridge (along the
//! normal), `v` along it, `T` the block's period, `σ_n = gabor_sigma_across · T` (5/12, pyfing's
//! value) and `σ_r = gabor_sigma_along · T`; it is made zero-mean and of unit energy, so the
//! local gray level and contrast drop out and the response is the local ridge wave. One kernel per
//! block (8 px); blocks outside the print are not filtered. With the default round envelope
//! (`σ_n = σ_r`) the kernel is two separable terms and a constant (`SeparableGabor`), applied as
//! rows then columns; otherwise it is applied directly. Dark ridges give a
//! negative response; the plane returned has ridges positive.
//!
//! In: the gray image, [`Segmentation`], [`OrientationField`], [`RidgePeriods`]; out: the
//! enhanced [`Plane`].

use super::fields::{OrientationField, Plane, RidgePeriods, Segmentation};
use crate::params::FingerprintParams;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Blocks whose coherence is below this are filtered in sub-blocks (docs/fingerprints.md,
/// "Enhancement").
const TURNING_COHERENCE: f32 = 0.5;
/// Side of those sub-blocks, px.
const SUB_BLOCK: usize = 4;

/// The enhanced image: the Gabor response, ridges positive (`dark_ridges` says which side of the
/// gray levels the ridges are), zero outside the print. `gray` is taken, padded and let go
/// before the response is allocated (with the round envelope; the direct filter reads it).
pub(crate) fn enhance(
    gray: Plane,
    segmentation: &Segmentation,
    field: &OrientationField,
    periods: &RidgePeriods,
    params: &FingerprintParams,
    dark_ridges: bool,
) -> Plane {
    let grid = segmentation.grid;
    let (w, b) = (grid.width as usize, grid.block as usize);
    let sign = if dark_ridges { -1.0f32 } else { 1.0 };
    if w == 0 || b == 0 {
        return Plane {
            width: grid.width,
            height: grid.height,
            values: vec![0.0f32; gray.values.len()],
        };
    }
    // With a round envelope (σ across = σ along) the filter is a sum of two separable terms
    // and a constant (`SeparableGabor`): 3 (2r + 1) taps a pixel in each direction instead of
    // (2r + 1)², the same response up to rounding. The image is padded once by the largest
    // radius the print needs.
    let padded = (params.gabor_sigma_across == params.gabor_sigma_along).then(|| {
        let pad = (0..grid.len())
            .filter(|&k| segmentation.inside[k])
            .map(|k| kernel_radius(params.gabor_sigma_across * f64::from(periods.period[k])))
            .max()
            .unwrap_or(1);
        (padded_plane(&gray, pad), pad)
    });
    let len = gray.values.len();
    // The padded image is all the separable filter reads: the plane goes here.
    let gray = padded.is_none().then_some(gray);
    let mut values = vec![0.0f32; len];
    values
        .par_chunks_mut(w * b)
        .enumerate()
        .for_each(|(j, band)| {
            let (mut kernel, mut rows, mut parts) = (Vec::new(), RowSums::default(), Vec::new());
            let (mut filter, mut scratch) = (SeparableGabor::default(), GaborScratch::default());
            let band_y0 = j * b;
            for i in 0..grid.cols as usize {
                let index = grid.index(i, j);
                if !segmentation.inside[index] {
                    continue;
                }
                let period = f64::from(periods.period[index]);
                let (x0, x1, y0, y1) = grid.pixels(i, j);
                // Where the flow turns within the block (low coherence: cores, deltas, the apex
                // of a tight loop), one direction per block misses the ridges at its corners:
                // sub-blocks take the direction interpolated at their centers.
                parts.clear();
                if field.coherence[index] < TURNING_COHERENCE {
                    for ys in (y0..y1).step_by(SUB_BLOCK) {
                        for xs in (x0..x1).step_by(SUB_BLOCK) {
                            let (xe, ye) = ((xs + SUB_BLOCK).min(x1), (ys + SUB_BLOCK).min(y1));
                            let centre = [(xs + xe) as f64 / 2.0, (ys + ye) as f64 / 2.0];
                            parts.push(((xs, xe, ys, ye), field.angle_at(centre)));
                        }
                    }
                } else {
                    parts.push(((x0, x1, y0, y1), f64::from(field.angle[index])));
                }
                for &(pixels, theta) in &parts {
                    let out = (&mut *band, band_y0);
                    if let Some((padded, pad)) = &padded {
                        filter.tune(theta, period, params, &mut scratch);
                        filter.apply(padded, *pad, pixels, sign, out, &mut rows);
                    } else if let Some(gray) = &gray {
                        let radius = gabor_kernel(theta, period, params, &mut kernel);
                        apply_kernel(gray, &kernel, radius, pixels, sign, out);
                    }
                }
            }
        });
    Plane {
        width: grid.width,
        height: grid.height,
        values,
    }
}

/// The response of the `(2 radius + 1)²` `kernel` over the block `(x0, x1, y0, y1)` of `gray`
/// (clamped at the image's edges), times `sign`, into `band` (rows from `band_y0`, image width).
fn apply_kernel(
    gray: &Plane,
    kernel: &[f32],
    radius: usize,
    (x0, x1, y0, y1): (usize, usize, usize, usize),
    sign: f32,
    (band, band_y0): (&mut [f32], usize),
) {
    let (w, side) = (gray.width as usize, 2 * radius + 1);
    for y in y0..y1 {
        for x in x0..x1 {
            let mut s = 0.0f32;
            for (row, taps) in kernel.chunks_exact(side).enumerate() {
                let yy = y as i64 + row as i64 - radius as i64;
                let x_start = x as i64 - radius as i64;
                if x_start >= 0 && x_start + side as i64 <= w as i64 {
                    let yy = yy.clamp(0, i64::from(gray.height) - 1) as usize;
                    let start = yy * w + x_start as usize;
                    let line = &gray.values[start..start + side];
                    s += taps.iter().zip(line).map(|(k, v)| k * v).sum::<f32>();
                } else {
                    for (c, &k) in taps.iter().enumerate() {
                        s += k * gray.at(x_start + c as i64, yy);
                    }
                }
            }
            band[(y - band_y0) * w + x] = sign * s;
        }
    }
}

/// The window radius of a Gaussian envelope of `sigma` px: 3 σ, 1-64 px.
fn kernel_radius(sigma: f64) -> usize {
    (3.0 * sigma).ceil().clamp(1.0, 64.0) as usize
}

/// `gray` with `pad` pixels added on every side, each the nearest pixel of the image (as
/// [`Plane::at`] clamps).
fn padded_plane(gray: &Plane, pad: usize) -> Plane {
    let (w, h) = (
        gray.width as usize + 2 * pad,
        gray.height as usize + 2 * pad,
    );
    let (gw, gh) = (gray.width as usize, gray.height as usize);
    if gw == 0 || gh == 0 || gray.values.len() != gw * gh {
        let mut values = Vec::with_capacity(w * h);
        for y in 0..h {
            let yy = y as i64 - pad as i64;
            values.extend((0..w).map(|x| gray.at(x as i64 - pad as i64, yy)));
        }
        return Plane {
            width: w as u32,
            height: h as u32,
            values,
        };
    }
    // Each row the image's nearest, its first and last pixel repeated either side.
    let mut values = Vec::with_capacity(w * h);
    for y in 0..h {
        let yy = y.saturating_sub(pad).min(gh - 1);
        let row = &gray.values[yy * gw..(yy + 1) * gw];
        values.extend(std::iter::repeat_n(row[0], pad));
        values.extend_from_slice(row);
        values.extend(std::iter::repeat_n(row[gw - 1], pad));
    }
    Plane {
        width: w as u32,
        height: h as u32,
        values,
    }
}

/// The filter of [`gabor_kernel`] when its envelope is round (`σ` across = along): with
/// `g(t) = exp(-t² / 2σ²)` and the wave `cos(αx + βy)` (`(α, β) = 2π n / T`, `n` the ridge
/// normal), the kernel is `A(x) B(y) - C(x) D(y) - m`, `A = g cos αx`, `C = g sin αx`,
/// `B = g cos βy`, `D = g sin βy`, `m` its mean over the window, all over its energy.
#[derive(Default)]
struct SeparableGabor {
    radius: usize,
    /// `A`, `C` over `x` and `B`, `D` over `y`, offsets `-r..=r`.
    a: Vec<f32>,
    c: Vec<f32>,
    b: Vec<f32>,
    d: Vec<f32>,
    /// The mean `m` subtracted.
    mean: f32,
    /// One over the energy of the zero-mean kernel (0 for a flat one).
    scale: f32,
}

/// Scratch space of [`SeparableGabor::tune`]: the envelope and the four taps in double
/// precision, kept from one kernel to the next (a print has a kernel per block and per turning
/// block's sub-block, thousands of them).
#[derive(Default)]
struct GaborScratch {
    envelope: Vec<f64>,
    /// The bits of the σ `envelope` was made for.
    envelope_sigma: Option<u64>,
    a: Vec<f64>,
    c: Vec<f64>,
    b: Vec<f64>,
    d: Vec<f64>,
}

impl SeparableGabor {
    #[cfg(test)]
    fn new(theta: f64, period: f64, params: &FingerprintParams) -> SeparableGabor {
        let mut filter = SeparableGabor::default();
        filter.tune(theta, period, params, &mut GaborScratch::default());
        filter
    }

    /// Makes this the filter for ridge direction `theta` and period `period`, in the vectors it
    /// has and `scratch` (the same values as from fresh ones: a test holds them bit for bit).
    fn tune(
        &mut self,
        theta: f64,
        period: f64,
        params: &FingerprintParams,
        scratch: &mut GaborScratch,
    ) {
        let sigma = params.gabor_sigma_across * period;
        let radius = kernel_radius(sigma) as i64;
        let normal = [-theta.sin(), theta.cos()];
        let (alpha, beta) = (TAU * normal[0] / period, TAU * normal[1] / period);
        // The envelope's taps, the same for both directions.
        let GaborScratch {
            envelope,
            envelope_sigma,
            a,
            c,
            b,
            d,
        } = scratch;
        // `g(t) = exp(-t² / 2σ²)` is even, exactly (`-t · t` is the same at `±t`), so each
        // `t ≥ 0` is evaluated once; and it depends on σ alone, so it is kept while σ is the
        // same (the sub-blocks of a turning block share their block's period).
        if *envelope_sigma != Some(sigma.to_bits()) {
            let r = radius as usize;
            envelope.clear();
            envelope.resize(2 * r + 1, 0.0);
            for t in 0..=r {
                let t_f = t as f64;
                let g = (-t_f * t_f / (2.0 * sigma * sigma)).exp();
                envelope[r - t] = g;
                envelope[r + t] = g;
            }
            *envelope_sigma = Some(sigma.to_bits());
        }
        mirrored_taps(envelope, alpha, (a, c));
        mirrored_taps(envelope, beta, (b, d));
        let sum = |v: &[f64]| v.iter().sum::<f64>();
        let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(p, q)| p * q).sum::<f64>();
        let n = ((2 * radius + 1) * (2 * radius + 1)) as f64;
        let mean = (sum(a) * sum(b) - sum(c) * sum(d)) / n;
        let energy = dot(a, a) * dot(b, b) - 2.0 * dot(a, c) * dot(b, d) + dot(c, c) * dot(d, d)
            - n * mean * mean;
        let scale = if energy > 0.0 {
            1.0 / energy.sqrt()
        } else {
            0.0
        };
        let single = |from: &[f64], to: &mut Vec<f32>| {
            to.clear();
            to.extend(from.iter().map(|&x| x as f32));
        };
        single(a, &mut self.a);
        single(c, &mut self.c);
        single(b, &mut self.b);
        single(d, &mut self.d);
        self.radius = radius as usize;
        self.mean = mean as f32;
        self.scale = scale as f32;
    }

    /// The row sums of `N` columns (`window` their taps, `N + 2r` values) in registers: each
    /// column's sums are added tap by tap as [`SeparableGabor::row_sums_any`] adds them.
    #[inline(always)]
    fn row_sums<const N: usize>(
        &self,
        window: &[f32],
        (sa, sc, sg): (&mut [f32], &mut [f32], &mut [f32]),
    ) {
        let (mut a_sums, mut c_sums, mut sums) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
        for (t, (&a, &c)) in self.a.iter().zip(&self.c).enumerate() {
            let line: &[f32; N] = match window[t..t + N].try_into() {
                Ok(line) => line,
                Err(_) => return self.row_sums_any(window, (sa, sc, sg)),
            };
            for x in 0..N {
                a_sums[x] += a * line[x];
                c_sums[x] += c * line[x];
                sums[x] += line[x];
            }
        }
        sa.copy_from_slice(&a_sums);
        sc.copy_from_slice(&c_sums);
        sg.copy_from_slice(&sums);
    }

    /// The row sums of any number of columns: Σ A·gray, Σ C·gray and Σ gray over the taps.
    #[inline(always)]
    fn row_sums_any(&self, window: &[f32], (sa, sc, sg): (&mut [f32], &mut [f32], &mut [f32])) {
        for (t, (&a, &c)) in self.a.iter().zip(&self.c).enumerate() {
            for (x, &v) in window[t..t + sa.len()].iter().enumerate() {
                sa[x] += a * v;
                sc[x] += c * v;
                sg[x] += v;
            }
        }
    }

    /// The response over the block `(x0, x1, y0, y1)` of the image that `padded` holds with
    /// `pad` px around it, times `sign`, into `band` (rows `y0..y1`, image width); `rows` is
    /// scratch space. With AVX2 at run time the row and column sums go eight lanes a vector
    /// instruction instead of four, a 4 px sub-block's two rows at a time (`math::wide_lanes`:
    /// the same operations, so the same values; a test holds the two bit for bit).
    fn apply(
        &self,
        padded: &Plane,
        pad: usize,
        pixels: (usize, usize, usize, usize),
        sign: f32,
        out: (&mut [f32], usize),
        rows: &mut RowSums,
    ) {
        #[cfg(target_arch = "x86_64")]
        if super::math::wide_lanes() {
            // SAFETY: the CPU has AVX2 (checked at run time).
            return unsafe { self.apply_wide(padded, pad, pixels, sign, out, rows) };
        }
        self.apply_lanes::<false>(padded, pad, pixels, sign, out, rows);
    }

    /// [`SeparableGabor::apply`] compiled for AVX2, its sums of eight columns in AVX registers
    /// (`wide`).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn apply_wide(
        &self,
        padded: &Plane,
        pad: usize,
        pixels: (usize, usize, usize, usize),
        sign: f32,
        out: (&mut [f32], usize),
        rows: &mut RowSums,
    ) {
        self.apply_lanes::<true>(padded, pad, pixels, sign, out, rows);
    }

    /// [`SeparableGabor::apply`]'s sums, inlined into the version the CPU runs (`WIDE`: the one
    /// for AVX2, which the CPU must have).
    #[inline(always)]
    fn apply_lanes<const WIDE: bool>(
        &self,
        padded: &Plane,
        pad: usize,
        (x0, x1, y0, y1): (usize, usize, usize, usize),
        sign: f32,
        (band, band_y0): (&mut [f32], usize),
        rows: &mut RowSums,
    ) {
        let (r, pw) = (self.radius, padded.width as usize);
        let (bw, side) = (x1 - x0, 2 * self.radius + 1);
        let width = pw - 2 * pad;
        let window_rows = y1 - y0 + 2 * r;
        // Per padded row of the window and column of the block: Σ A·gray, Σ C·gray, Σ gray,
        // each summed tap by tap in the same order for every column, so that the columns of a
        // row are summed side by side (vector lanes) and every sum is the one a column alone
        // would give.
        for sums in [&mut rows.a, &mut rows.c, &mut rows.g] {
            sums.clear();
            sums.resize(window_rows * bw, 0.0);
        }
        let mut k = 0;
        while k < window_rows {
            let start = (y0 + pad - r + k) * pw + x0 + pad - r;
            // Two rows at a time, their sums one after the other: a sub-block's four columns
            // of both in one AVX register, or eight columns of each side by side.
            // SAFETY: `WIDE` only where the CPU has AVX2 (`apply_wide`).
            #[cfg(target_arch = "x86_64")]
            if WIDE && (bw == 4 || bw == 8) && k + 1 < window_rows && {
                let span = k * bw..(k + 2) * bw;
                let next = start + pw;
                let windows = (
                    &padded.values[start..start + side - 1 + bw],
                    &padded.values[next..next + side - 1 + bw],
                );
                let sums = (
                    &mut rows.a[span.clone()],
                    &mut rows.c[span.clone()],
                    &mut rows.g[span],
                );
                unsafe { wide::row_sums_x2((&self.a, &self.c), windows, sums) }
            } {
                k += 2;
                continue;
            }
            let span = k * bw..(k + 1) * bw;
            // Borrowed again for the AVX2 sums, which may leave them to the baseline ones.
            #[cfg_attr(not(target_arch = "x86_64"), allow(unused_mut))]
            let mut sums = (
                &mut rows.a[span.clone()],
                &mut rows.c[span.clone()],
                &mut rows.g[span],
            );
            let window = &padded.values[start..start + side - 1 + bw];
            match bw {
                // SAFETY: `WIDE` only where the CPU has AVX2 (`apply_wide`).
                #[cfg(target_arch = "x86_64")]
                8 if WIDE
                    && unsafe {
                        wide::row_sums8(&self.a, &self.c, window, reborrow(&mut sums))
                    } => {}
                8 => self.row_sums::<8>(window, sums),
                4 => self.row_sums::<4>(window, sums),
                _ => self.row_sums_any(window, sums),
            }
            k += 1;
        }
        let mut y = y0;
        while y < y1 {
            let row = (y - band_y0) * width;
            // Two output rows at a time: a sub-block's in one AVX register (their row sums,
            // four apart, are eight adjacent values), or eight columns of each side by side.
            // SAFETY: as above.
            #[cfg(target_arch = "x86_64")]
            if WIDE && (bw == 4 || bw == 8) && y + 1 < y1 && {
                let (top, bottom) = band[row + x0..row + width + x1].split_at_mut(width);
                let out = (&mut top[..bw], &mut bottom[..bw]);
                let first = (y - y0) * bw;
                unsafe {
                    if bw == 4 {
                        wide::column_sums4x2(self, rows, first, sign, out)
                    } else {
                        wide::column_sums8x2(self, rows, first, sign, out)
                    }
                }
            } {
                y += 2;
                continue;
            }
            let out = &mut band[row + x0..row + x1];
            match bw {
                // SAFETY: as above.
                #[cfg(target_arch = "x86_64")]
                8 if WIDE
                    && unsafe { wide::column_sums8(self, rows, (y - y0) * bw, sign, out) } => {}
                8 => self.column_sums::<8>(rows, (y - y0) * bw, sign, out),
                // The sub-blocks of turning blocks: four columns side by side (vector lanes)
                // rather than one after another.
                4 => self.column_sums::<4>(rows, (y - y0) * bw, sign, out),
                _ => self.column_sums_any(rows, (y - y0) * bw, sign, out),
            }
            y += 1;
        }
    }

    /// One output row of `N` columns from the row sums starting at `first` (the window's top
    /// row): Σ over the rows of B·ΣA - D·ΣC - m·Σgray, times the scale and `sign`.
    #[inline(always)]
    fn column_sums<const N: usize>(
        &self,
        rows: &RowSums,
        first: usize,
        sign: f32,
        out: &mut [f32],
    ) {
        let mut s = [0.0f32; N];
        for (k, (&b, &d)) in self.b.iter().zip(&self.d).enumerate() {
            let at = first + k * N;
            let (Ok(ha), Ok(hc), Ok(h1)) = (
                <&[f32; N]>::try_from(&rows.a[at..at + N]),
                <&[f32; N]>::try_from(&rows.c[at..at + N]),
                <&[f32; N]>::try_from(&rows.g[at..at + N]),
            ) else {
                return self.column_sums_any(rows, first, sign, out);
            };
            for x in 0..N {
                s[x] += b * ha[x] - d * hc[x] - self.mean * h1[x];
            }
        }
        for (dst, &v) in out.iter_mut().zip(&s) {
            *dst = sign * self.scale * v;
        }
    }

    /// [`SeparableGabor::column_sums`] for any number of columns.
    #[inline(always)]
    fn column_sums_any(&self, rows: &RowSums, first: usize, sign: f32, out: &mut [f32]) {
        let bw = out.len();
        for (x, dst) in out.iter_mut().enumerate() {
            let mut s = 0.0f32;
            for (k, (&b, &d)) in self.b.iter().zip(&self.d).enumerate() {
                let at = first + k * bw + x;
                s += b * rows.a[at] - d * rows.c[at] - self.mean * rows.g[at];
            }
            *dst = sign * self.scale * s;
        }
    }
}

/// The taps `g(t) cos kt` and `g(t) sin kt` for `t` in `-r..=r` (`envelope` holds `g`, `2r + 1`
/// values, the same at `±t`). Cosine is even and sine odd, so the taps at `-t` mirror those at
/// `t`: each `t ≥ 0` is worked out once. The library's `sin` and `cos` give `t = 1`; each further
/// `t` turns the one before by `k` (`e^{ik(t+1)} = e^{ikt} e^{ik}`, a complex product), where the
/// library's call per `t` was the kernel's largest cost (about 90 instructions, two dozen a
/// kernel). The turned values are within a few units in the last place of a `f64` of the
/// library's (at most 8e-16 apart over 3 million random kernels; a test holds them within 1e-13),
/// far below the `f32` the taps are kept in: of those kernels' 444 million taps, 14 rounded to
/// another `f32`, and no mean or scale (docs/performance.md).
fn mirrored_taps(envelope: &[f64], k: f64, (cosines, sines): (&mut Vec<f64>, &mut Vec<f64>)) {
    let radius = envelope.len() / 2;
    for taps in [&mut *cosines, &mut *sines] {
        taps.clear();
        taps.resize(envelope.len(), 0.0);
    }
    // `sin ±0 = ±0` and `cos ±0 = 1` exactly: `k = ±0` without the library's call, its turns
    // keeping the sign of zero as `k·t` does.
    let turn = if k == 0.0 { (k, 1.0) } else { k.sin_cos() };
    // `t = 0`: the angle `k·0` is `±0`, written from `after` (as the direct evaluation has it,
    // `sin(-0) = -0`).
    let (mut sin, mut cos) = (k * 0.0, 1.0);
    let (cos_before, cos_after) = cosines.split_at_mut(radius);
    let (sin_before, sin_after) = sines.split_at_mut(radius);
    let (envelope_before, envelope_after) = envelope.split_at(radius);
    let (Some(g), Some(c), Some(s)) = (
        envelope_after.first(),
        cos_after.first_mut(),
        sin_after.first_mut(),
    ) else {
        return;
    };
    (*c, *s) = (g * cos, g * sin);
    // `t = 1, 2, …` outward on both sides at once, without an index to check.
    let after = envelope_after[1..]
        .iter()
        .zip(&mut cos_after[1..])
        .zip(&mut sin_after[1..]);
    let before = envelope_before
        .iter()
        .rev()
        .zip(cos_before.iter_mut().rev())
        .zip(sin_before.iter_mut().rev());
    for (t, (((g_after, c_after), s_after), ((g_before, c_before), s_before))) in
        (1..).zip(after.zip(before))
    {
        (sin, cos) = if t == 1 {
            turn
        } else {
            (sin * turn.1 + cos * turn.0, cos * turn.1 - sin * turn.0)
        };
        *c_before = g_before * cos;
        *s_before = -(g_before * sin);
        *c_after = g_after * cos;
        *s_after = g_after * sin;
    }
}

/// The three row sums' slices again, for a call that may leave them to another.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn reborrow<'a>(
    (sa, sc, sg): &'a mut (&mut [f32], &mut [f32], &mut [f32]),
) -> (&'a mut [f32], &'a mut [f32], &'a mut [f32]) {
    (sa, sc, sg)
}

/// [`SeparableGabor::row_sums`] and [`SeparableGabor::column_sums`] of eight columns, or of two
/// rows of four columns, in AVX registers: each tap's eight values loaded once and its weights
/// broadcast, the same operations in the same order as the baseline sums (no fused
/// multiply-add), so the same values (a test holds them bit for bit). Each returns false, having written nothing, where the slices
/// are not of the lengths it needs; the caller then sums as on baseline x86-64.
#[cfg(target_arch = "x86_64")]
mod wide {
    use super::{RowSums, SeparableGabor};
    use std::arch::x86_64::{
        __m256, _mm256_add_ps, _mm256_castps128_ps256, _mm256_castps256_ps128,
        _mm256_extractf128_ps, _mm256_insertf128_ps, _mm256_loadu_ps, _mm256_mul_ps,
        _mm256_set1_ps, _mm256_setzero_ps, _mm256_storeu_ps, _mm256_sub_ps, _mm_loadu_ps,
        _mm_storeu_ps,
    };

    /// Σ A·gray, Σ C·gray and Σ gray over the taps `a`, `c` of the eight columns whose taps
    /// `window` holds (at least `taps + 7` values), into `sa`, `sc`, `sg` (eight each).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn row_sums8(
        a: &[f32],
        c: &[f32],
        window: &[f32],
        (sa, sc, sg): (&mut [f32], &mut [f32], &mut [f32]),
    ) -> bool {
        let taps = a.len();
        if c.len() != taps || window.len() < taps + 7 || [sa.len(), sc.len(), sg.len()] != [8; 3] {
            return false;
        }
        // SAFETY: the CPU has AVX2, as this function's caller guarantees; each tap `t` reads
        // `window[t..t + 8]`, within it as `t + 8 <= taps + 7 <= window.len()`; eight values
        // each out, checked above.
        unsafe {
            tap_sums(
                (a, c),
                |t| _mm256_loadu_ps(window.as_ptr().add(t)),
                (sa, sc, sg),
            )
        };
        true
    }

    /// Σ A·line, Σ C·line and Σ line over the taps `a`, `c`, `line(t)` the eight values of tap
    /// `t`, into `sa`, `sc`, `sg`: [`row_sums8`]'s and [`row_sums_x2`]'s sums, which differ only
    /// in how a tap's eight values are loaded.
    ///
    /// # Safety
    /// The CPU must have AVX2, `line` must be safe to call for every tap, and `sa`, `sc`, `sg`
    /// must hold eight values each.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn tap_sums(
        (a, c): (&[f32], &[f32]),
        line: impl Fn(usize) -> __m256,
        (sa, sc, sg): (&mut [f32], &mut [f32], &mut [f32]),
    ) {
        let (mut va, mut vc, mut vg) = (
            _mm256_setzero_ps(),
            _mm256_setzero_ps(),
            _mm256_setzero_ps(),
        );
        for (t, (&a, &c)) in a.iter().zip(c).enumerate() {
            let line = line(t);
            va = _mm256_add_ps(va, _mm256_mul_ps(_mm256_set1_ps(a), line));
            vc = _mm256_add_ps(vc, _mm256_mul_ps(_mm256_set1_ps(c), line));
            vg = _mm256_add_ps(vg, line);
        }
        // SAFETY: eight values each, as the caller guarantees.
        unsafe {
            _mm256_storeu_ps(sa.as_mut_ptr(), va);
            _mm256_storeu_ps(sc.as_mut_ptr(), vc);
            _mm256_storeu_ps(sg.as_mut_ptr(), vg);
        }
    }

    /// Whether two rows' windows hold the `columns` values each of every tap of `a` and `c`
    /// (`taps + columns - 1`), and each of the three sums' slices (`sums`) two rows of them.
    fn two_rows_fit(
        (a, c): (&[f32], &[f32]),
        (window, next): (&[f32], &[f32]),
        sums: [usize; 3],
        columns: usize,
    ) -> bool {
        let taps = a.len();
        c.len() == taps
            && window.len() >= taps + columns - 1
            && next.len() >= taps + columns - 1
            && sums == [2 * columns; 3]
    }

    /// [`row_sums8`] of two rows, `window` and `next`, of four or eight columns (at least
    /// `taps + 3` or `taps + 7` values each, `sa`, `sc`, `sg` eight or sixteen each): each row's
    /// sums the ones [`SeparableGabor::row_sums`] gives it, the same operations, the first row's
    /// into the first half of `sa`, `sc`, `sg` and the next row's into the second. Four columns
    /// go in one register (`window`'s in the low four lanes); eight side by side, the two rows'
    /// sums independent, so their additions overlap where one row's wait on the addition before
    /// (a tap's three sums are each the one before plus a term).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn row_sums_x2(
        (a, c): (&[f32], &[f32]),
        (window, next): (&[f32], &[f32]),
        (sa, sc, sg): (&mut [f32], &mut [f32], &mut [f32]),
    ) -> bool {
        let columns = sa.len() / 2;
        if !matches!(columns, 4 | 8)
            || !two_rows_fit(
                (a, c),
                (window, next),
                [sa.len(), sc.len(), sg.len()],
                columns,
            )
        {
            return false;
        }
        // SAFETY: the CPU has AVX2, as this function's caller guarantees; each tap `t` reads
        // `columns` values from `t` of each row, within both as `t + columns <= taps + columns
        // - 1`; `2 · columns` values each out, checked above.
        unsafe {
            if columns == 4 {
                let line = |t: usize| {
                    _mm256_insertf128_ps::<1>(
                        _mm256_castps128_ps256(_mm_loadu_ps(window.as_ptr().add(t))),
                        _mm_loadu_ps(next.as_ptr().add(t)),
                    )
                };
                tap_sums((a, c), line, (sa, sc, sg));
            } else {
                eight_columns_x2([a, c], [window, next], [sa, sc, sg]);
            }
        }
        true
    }

    /// [`row_sums_x2`] of eight columns, once checked: `rows` at least `taps + 7` values each,
    /// `sums` sixteen each.
    ///
    /// # Safety
    /// The CPU must have AVX2, and the lengths must be as said.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn eight_columns_x2(
        [a, c]: [&[f32]; 2],
        [window, next]: [&[f32]; 2],
        [sa, sc, sg]: [&mut [f32]; 3],
    ) {
        let (mut va, mut vc, mut vg) = (
            _mm256_setzero_ps(),
            _mm256_setzero_ps(),
            _mm256_setzero_ps(),
        );
        let (mut wa, mut wc, mut wg) = (va, vc, vg);
        for (t, (&a, &c)) in a.iter().zip(c).enumerate() {
            // SAFETY: the CPU has AVX2 and tap `t` reads eight values from `t` of each row,
            // within both as `t + 8 <= taps + 7`, by the caller.
            let (line, below) = unsafe {
                (
                    _mm256_loadu_ps(window.as_ptr().add(t)),
                    _mm256_loadu_ps(next.as_ptr().add(t)),
                )
            };
            let (a, c) = (_mm256_set1_ps(a), _mm256_set1_ps(c));
            va = _mm256_add_ps(va, _mm256_mul_ps(a, line));
            vc = _mm256_add_ps(vc, _mm256_mul_ps(c, line));
            vg = _mm256_add_ps(vg, line);
            wa = _mm256_add_ps(wa, _mm256_mul_ps(a, below));
            wc = _mm256_add_ps(wc, _mm256_mul_ps(c, below));
            wg = _mm256_add_ps(wg, below);
        }
        // SAFETY: sixteen values each, by the caller.
        unsafe {
            _mm256_storeu_ps(sa.as_mut_ptr(), va);
            _mm256_storeu_ps(sc.as_mut_ptr(), vc);
            _mm256_storeu_ps(sg.as_mut_ptr(), vg);
            _mm256_storeu_ps(sa.as_mut_ptr().add(8), wa);
            _mm256_storeu_ps(sc.as_mut_ptr().add(8), wc);
            _mm256_storeu_ps(sg.as_mut_ptr().add(8), wg);
        }
    }

    /// One output row of eight columns from the row sums starting at `first`: Σ over the rows
    /// of B·ΣA - D·ΣC - m·Σgray, times the scale and `sign`, into `out` (eight values).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn column_sums8(
        filter: &SeparableGabor,
        rows: &RowSums,
        first: usize,
        sign: f32,
        out: &mut [f32],
    ) -> bool {
        if out.len() != 8 {
            return false;
        }
        // SAFETY: the CPU has AVX2, as this function's caller guarantees.
        let Some(scaled) = (unsafe { column_terms(filter, rows, (first, 8), sign) }) else {
            return false;
        };
        // SAFETY: eight values, checked above.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), scaled) };
        true
    }

    /// Σ over the taps `k` of B·ΣA - D·ΣC - m·Σgray, the eight row sums of tap `k` starting at
    /// `first + k · stride`, times the scale and `sign`: one output row of eight columns
    /// (`stride` 8) or two output rows of four (`stride` 4: the lower row's sums start four
    /// after the upper's). `None` where the row sums do not hold them all.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn column_terms(
        filter: &SeparableGabor,
        rows: &RowSums,
        (first, stride): (usize, usize),
        sign: f32,
    ) -> Option<__m256> {
        let taps = filter.b.len();
        let end = first + stride * taps.saturating_sub(1) + 8;
        if filter.d.len() != taps
            || [rows.a.len(), rows.c.len(), rows.g.len()]
                .iter()
                .any(|&n| n < end)
        {
            return None;
        }
        let mean = _mm256_set1_ps(filter.mean);
        let mut s = _mm256_setzero_ps();
        for (k, (&b, &d)) in filter.b.iter().zip(&filter.d).enumerate() {
            let at = first + k * stride;
            // SAFETY: `at + 8 <= end`, within each of the three, checked above.
            let (ha, hc, h1) = unsafe {
                (
                    _mm256_loadu_ps(rows.a.as_ptr().add(at)),
                    _mm256_loadu_ps(rows.c.as_ptr().add(at)),
                    _mm256_loadu_ps(rows.g.as_ptr().add(at)),
                )
            };
            let term = _mm256_sub_ps(
                _mm256_sub_ps(
                    _mm256_mul_ps(_mm256_set1_ps(b), ha),
                    _mm256_mul_ps(_mm256_set1_ps(d), hc),
                ),
                _mm256_mul_ps(mean, h1),
            );
            s = _mm256_add_ps(s, term);
        }
        Some(_mm256_mul_ps(_mm256_set1_ps(sign * filter.scale), s))
    }

    /// [`column_sums8`] of two output rows, the lower's row sums starting eight after the
    /// upper's (`first`): each row the same operations in the same order as [`column_terms`],
    /// its value into `top` and `bottom` (eight each); the two rows' additions overlap.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn column_sums8x2(
        filter: &SeparableGabor,
        rows: &RowSums,
        first: usize,
        sign: f32,
        (top, bottom): (&mut [f32], &mut [f32]),
    ) -> bool {
        let taps = filter.b.len();
        let end = first + 8 * taps + 8;
        if top.len() != 8
            || bottom.len() != 8
            || filter.d.len() != taps
            || [rows.a.len(), rows.c.len(), rows.g.len()]
                .iter()
                .any(|&n| n < end)
        {
            return false;
        }
        let mean = _mm256_set1_ps(filter.mean);
        let (mut s, mut s_below) = (_mm256_setzero_ps(), _mm256_setzero_ps());
        for (k, (&b, &d)) in filter.b.iter().zip(&filter.d).enumerate() {
            let (b, d) = (_mm256_set1_ps(b), _mm256_set1_ps(d));
            let term = |at: usize| {
                // SAFETY: `at + 8 <= first + 8 · taps + 8 = end`, within each of the three,
                // checked above.
                let (ha, hc, h1) = unsafe {
                    (
                        _mm256_loadu_ps(rows.a.as_ptr().add(at)),
                        _mm256_loadu_ps(rows.c.as_ptr().add(at)),
                        _mm256_loadu_ps(rows.g.as_ptr().add(at)),
                    )
                };
                _mm256_sub_ps(
                    _mm256_sub_ps(_mm256_mul_ps(b, ha), _mm256_mul_ps(d, hc)),
                    _mm256_mul_ps(mean, h1),
                )
            };
            let at = first + k * 8;
            s = _mm256_add_ps(s, term(at));
            s_below = _mm256_add_ps(s_below, term(at + 8));
        }
        let scale = _mm256_set1_ps(sign * filter.scale);
        // SAFETY: eight values each, checked above.
        unsafe {
            _mm256_storeu_ps(top.as_mut_ptr(), _mm256_mul_ps(scale, s));
            _mm256_storeu_ps(bottom.as_mut_ptr(), _mm256_mul_ps(scale, s_below));
        }
        true
    }

    /// Two output rows of four columns from the row sums starting at `first` (the top row's;
    /// the bottom row's start four later, so both rows' terms of a tap are eight adjacent
    /// values): [`SeparableGabor::column_sums`] for four columns, the same operations, in one
    /// register, into `top` and `bottom` (four values each).
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn column_sums4x2(
        filter: &SeparableGabor,
        rows: &RowSums,
        first: usize,
        sign: f32,
        (top, bottom): (&mut [f32], &mut [f32]),
    ) -> bool {
        if top.len() != 4 || bottom.len() != 4 {
            return false;
        }
        // SAFETY: the CPU has AVX2, as this function's caller guarantees.
        let Some(scaled) = (unsafe { column_terms(filter, rows, (first, 4), sign) }) else {
            return false;
        };
        // SAFETY: four values each, checked above.
        unsafe {
            _mm_storeu_ps(top.as_mut_ptr(), _mm256_castps256_ps128(scaled));
            _mm_storeu_ps(bottom.as_mut_ptr(), _mm256_extractf128_ps::<1>(scaled));
        }
        true
    }
}

/// Scratch space of [`SeparableGabor::apply`]: the row sums of the window, one column of the
/// block after another within each row.
#[derive(Default)]
struct RowSums {
    a: Vec<f32>,
    c: Vec<f32>,
    g: Vec<f32>,
}

/// Fills `kernel` (row-major, `(2r+1)²`) with the zero-mean, unit-energy even Gabor filter for
/// ridge direction `theta` and period `period`, and returns its radius `r`.
fn gabor_kernel(
    theta: f64,
    period: f64,
    params: &FingerprintParams,
    kernel: &mut Vec<f32>,
) -> usize {
    let sigma_n = params.gabor_sigma_across * period;
    let sigma_r = params.gabor_sigma_along * period;
    let radius = kernel_radius(sigma_n.max(sigma_r)) as i64;
    let (along, normal) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
    kernel.clear();
    for dy in -radius..=radius {
        for dx in -radius..=radius {
            let (x, y) = (dx as f64, dy as f64);
            let u = x * normal[0] + y * normal[1];
            let v = x * along[0] + y * along[1];
            let envelope =
                (-(u * u / (sigma_n * sigma_n) + v * v / (sigma_r * sigma_r)) / 2.0).exp();
            kernel.push((envelope * (TAU * u / period).cos()) as f32);
        }
    }
    let mean = kernel.iter().sum::<f32>() / kernel.len() as f32;
    kernel.iter_mut().for_each(|k| *k -= mean);
    let norm = kernel.iter().map(|k| k * k).sum::<f32>().sqrt();
    if norm > 0.0 {
        kernel.iter_mut().for_each(|k| *k /= norm);
    }
    radius as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fingerprint::fields::BlockGrid;
    use crate::fingerprint::tests::{ridge_agreement, ridges_in_disk, uniform_print};
    use std::f64::consts::{FRAC_PI_2, PI};

    /// The taps as [`SeparableGabor::new`] computed them before [`mirrored_taps`]: every `t`
    /// evaluated by the library.
    fn direct_taps(envelope: &[f64], k: f64) -> (Vec<f64>, Vec<f64>) {
        let radius = (envelope.len() / 2) as i64;
        (-radius..=radius)
            .zip(envelope)
            .map(|(t, &g)| {
                let t = t as f64;
                (g * (k * t).cos(), g * (k * t).sin())
            })
            .unzip()
    }

    #[test]
    fn mirrored_taps_are_the_direct_ones_within_rounding() {
        let params = FingerprintParams::default();
        for period in [3.0, 4.5, 5.0, 7.25, 8.9, 9.0, 11.3, 17.0, 24.9, 25.0] {
            let sigma: f64 = params.gabor_sigma_across * period;
            let radius = kernel_radius(sigma) as i64;
            let envelope: Vec<f64> = (-radius..=radius)
                .map(|t| {
                    let t = t as f64;
                    (-t * t / (2.0 * sigma * sigma)).exp()
                })
                .collect();
            for step in 0..180 {
                let theta = f64::from(step) * PI / 180.0 + 0.001 * period;
                let normal = [-theta.sin(), theta.cos()];
                for k in [
                    TAU * normal[0] / period,
                    TAU * normal[1] / period,
                    0.0,
                    -0.0,
                ] {
                    // Into vectors holding other taps (as when the kernels' scratch space is
                    // reused).
                    let mut mirrored = (vec![7.0; 3], vec![-1.0; 40]);
                    mirrored_taps(&envelope, k, (&mut mirrored.0, &mut mirrored.1));
                    let direct = direct_taps(&envelope, k);
                    for (turned, evaluated) in [(&mirrored.0, &direct.0), (&mirrored.1, &direct.1)]
                    {
                        assert_eq!(turned.len(), evaluated.len());
                        for (p, q) in turned.iter().zip(evaluated) {
                            assert!((p - q).abs() <= 1e-13, "k {k}: {p} against {q}");
                        }
                    }
                    // The library's own values at `t = 0, ±1`, the signs of zero included.
                    let r = radius as usize;
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(
                        bits(&mirrored.0[r - 1..=r + 1]),
                        bits(&direct.0[r - 1..=r + 1])
                    );
                    assert_eq!(
                        bits(&mirrored.1[r - 1..=r + 1]),
                        bits(&direct.1[r - 1..=r + 1])
                    );
                    // The taps as kept (`f32`): those of the direct evaluation.
                    let single =
                        |v: &[f64]| v.iter().map(|&x| (x as f32).to_bits()).collect::<Vec<_>>();
                    assert_eq!(single(&mirrored.0), single(&direct.0), "cos, k {k}");
                    assert_eq!(single(&mirrored.1), single(&direct.1), "sin, k {k}");
                }
            }
        }
    }

    #[test]
    fn a_filter_tuned_again_is_a_fresh_one_bit_for_bit() {
        // One filter and scratch space tuned block after block, through periods that grow and
        // shrink the window, against a fresh filter for each.
        let params = FingerprintParams::default();
        let (mut filter, mut scratch) = (SeparableGabor::default(), GaborScratch::default());
        let tuned = [
            (0.3, 9.0),
            (1.2, 24.0),
            (2.5, 3.0),
            (0.0, 11.3),
            (3.1, 9.0),
            (1.7, 9.0),
            (0.4, 9.0),
        ];
        for (theta, period) in tuned {
            filter.tune(theta, period, &params, &mut scratch);
            // The envelope (kept while σ is the same, each `t ≥ 0` evaluated once) is the one
            // evaluated at every `t`.
            let sigma = params.gabor_sigma_across * period;
            let radius = kernel_radius(sigma) as i64;
            let direct: Vec<u64> = (-radius..=radius)
                .map(|t| {
                    let t = t as f64;
                    (-t * t / (2.0 * sigma * sigma)).exp().to_bits()
                })
                .collect();
            let kept: Vec<u64> = scratch.envelope.iter().map(|g| g.to_bits()).collect();
            assert_eq!(kept, direct, "envelope, period {period}");
            let fresh = SeparableGabor::new(theta, period, &params);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(filter.radius, fresh.radius);
            for (got, want) in [
                (&filter.a, &fresh.a),
                (&filter.b, &fresh.b),
                (&filter.c, &fresh.c),
                (&filter.d, &fresh.d),
            ] {
                assert_eq!(bits(got), bits(want), "{theta} {period}");
            }
            assert_eq!(filter.mean.to_bits(), fresh.mean.to_bits());
            assert_eq!(filter.scale.to_bits(), fresh.scale.to_bits());
        }
    }

    #[test]
    fn the_filter_in_the_cpus_lanes_is_the_baseline_one_bit_for_bit() {
        // Pseudo-random gray (a fixed linear congruential sequence), periods from 3 to 25 px at
        // any direction, blocks of 8 px, turning blocks' 4 px sub-blocks and the narrower ones
        // at the image's edges, at its corners and inside.
        let mut lcg = crate::synth::lcg(2026u64);
        let mut next = move || (lcg() >> 33) as usize;
        let (w, h) = (83usize, 61usize);
        let gray = Plane {
            width: w as u32,
            height: h as u32,
            values: (0..w * h).map(|_| (next() % 256) as f32).collect(),
        };
        let params = FingerprintParams::default();
        let mut rows = RowSums::default();
        for k in 0..120 {
            let (theta, period) = (
                (next() % 3600) as f64 / 1145.9,
                3.0 + (next() % 2201) as f64 / 100.0,
            );
            let filter = SeparableGabor::new(theta, period, &params);
            let pad = filter.radius + k % 3;
            let padded = padded_plane(&gray, pad);
            // Sub-blocks of four columns also with an odd number of rows (two rows in a
            // register, then one).
            let (side, tall) = ([8, 4, 3, 5, 1][k % 5], [8, 4, 3, 5, 1, 2][k % 6]);
            let (x0, y0) = (next() % (w - side + 1), next() % (h - tall + 1));
            let (x0, y0) = match k % 7 {
                0 => (0, 0),
                1 => (w - side, h - tall),
                _ => (x0, y0),
            };
            let block = (x0, x0 + side, y0, y0 + tall);
            let mut baseline = vec![0.0f32; w * tall];
            let mut run = vec![0.0f32; w * tall];
            let sign = if k % 2 == 0 { -1.0 } else { 1.0 };
            filter.apply_lanes::<false>(&padded, pad, block, sign, (&mut baseline, y0), &mut rows);
            filter.apply(&padded, pad, block, sign, (&mut run, y0), &mut rows);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&run), bits(&baseline), "{theta} {period} {block:?}");
        }
    }

    #[test]
    fn four_columns_side_by_side_are_the_one_by_one_sums_bit_for_bit() {
        // The turning blocks' sub-blocks: four columns in lanes against each column alone, over
        // random row sums of filters of every radius the periods give.
        let mut lcg = crate::synth::lcg(35u64);
        let mut next = move || (lcg() >> 33) as f32 / 2_147_483_648.0;
        let params = FingerprintParams::default();
        for k in 0..40 {
            let (theta, period) = (f64::from(next()) * 3.2, 3.0 + 22.0 * f64::from(next()));
            let filter = SeparableGabor::new(theta, period, &params);
            let taps = filter.b.len();
            let extra = k % 3;
            let random = |n: usize, next: &mut dyn FnMut() -> f32| -> Vec<f32> {
                (0..n).map(|_| 512.0 * next() - 256.0).collect()
            };
            let n = (taps + extra) * 4;
            let rows = RowSums {
                a: random(n, &mut next),
                c: random(n, &mut next),
                g: random(n, &mut next),
            };
            let (first, sign) = (extra * 4, if k % 2 == 0 { -1.0 } else { 1.0 });
            let (mut lanes, mut alone) = ([0.0f32; 4], [0.0f32; 4]);
            filter.column_sums::<4>(&rows, first, sign, &mut lanes);
            filter.column_sums_any(&rows, first, sign, &mut alone);
            assert_eq!(
                lanes.map(f32::to_bits),
                alone.map(f32::to_bits),
                "{theta} {period}"
            );
        }
    }

    #[test]
    fn the_padded_plane_repeats_the_nearest_pixel() {
        for (width, height, pad) in [(5u32, 4u32, 3usize), (1, 1, 2), (7, 2, 0), (3, 6, 9)] {
            let gray = Plane {
                width,
                height,
                values: (0..width * height).map(|v| (v * 7 % 11) as f32).collect(),
            };
            let padded = padded_plane(&gray, pad);
            let (w, h) = (width as usize + 2 * pad, height as usize + 2 * pad);
            assert_eq!((padded.width as usize, padded.height as usize), (w, h));
            for y in 0..h {
                for x in 0..w {
                    let (dx, dy) = (x as i64 - pad as i64, y as i64 - pad as i64);
                    assert_eq!(padded.values[y * w + x], gray.at(dx, dy), "{x} {y}");
                }
            }
        }
    }

    #[test]
    fn kernel_is_zero_mean_unit_energy_and_peaks_on_the_ridge() {
        let mut k = Vec::new();
        let r = gabor_kernel(0.3, 9.0, &FingerprintParams::default(), &mut k);
        let side = 2 * r + 1;
        assert_eq!(k.len(), side * side);
        assert!(k.iter().sum::<f32>().abs() < 1e-4);
        assert!((k.iter().map(|v| v * v).sum::<f32>() - 1.0).abs() < 1e-4);
        let centre = k[r * side + r];
        assert!(k.iter().all(|&v| v <= centre));
    }

    #[test]
    fn the_separable_filter_is_the_kernel_inside_and_at_the_border() {
        let (w, h) = (64usize, 48usize);
        let gray = Plane {
            width: w as u32,
            height: h as u32,
            values: (0..w * h)
                .map(|i| ((i * 7919 + (i / w) * 104_729) % 251) as f32)
                .collect(),
        };
        let params = FingerprintParams::default();
        for (theta, period) in [(0.3, 7.0), (1.2, 11.0), (2.5, 17.0)] {
            let mut kernel = Vec::new();
            let r = gabor_kernel(theta, period, &params, &mut kernel);
            let side = 2 * r + 1;
            let filter = SeparableGabor::new(theta, period, &params);
            assert_eq!(filter.radius, r);
            let padded = padded_plane(&gray, r + 3);
            for (x0, y0) in [(0, 0), (24, 16), (56, 40)] {
                let mut band = vec![0.0f32; w * 8];
                filter.apply(
                    &padded,
                    r + 3,
                    (x0, x0 + 8, y0, y0 + 8),
                    -1.0,
                    (&mut band, y0),
                    &mut RowSums::default(),
                );
                for y in y0..y0 + 8 {
                    for x in x0..x0 + 8 {
                        let direct: f32 = kernel
                            .iter()
                            .enumerate()
                            .map(|(k, &tap)| {
                                let (dx, dy) =
                                    ((k % side) as i64 - r as i64, (k / side) as i64 - r as i64);
                                tap * gray.at(x as i64 + dx, y as i64 + dy)
                            })
                            .sum();
                        let got = band[(y - y0) * w + x];
                        assert!(
                            (got + direct).abs() < 2e-3 * (1.0 + direct.abs()),
                            "{theta} {period} ({x}, {y}): {got} vs {}",
                            -direct
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn sub_blocks_follow_the_rings_around_a_core() {
        // Dark rings of period 8 around (48, 48) under noise four times their depth; each
        // block's direction is the rings' tangent at its centre. Within 14 px of the core the
        // direction turns by up to 90 degrees across a block: with the coherence low there the
        // block is filtered in sub-blocks, and more of the rings come out right.
        let (w, period, c) = (96usize, 8.0f64, 48.0f64);
        const NOISE: f64 = 2.5;
        let radius = |x: f64, y: f64| ((x - c).powi(2) + (y - c).powi(2)).sqrt();
        let gray = Plane {
            width: w as u32,
            height: w as u32,
            values: (0..w * w)
                .map(|i| {
                    let (x, y) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
                    let mut h = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                    h ^= h >> 31;
                    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
                    h ^= h >> 29;
                    let noise = (h % 201) as f64 - 100.0;
                    (128.0 - 60.0 * (TAU * radius(x, y) / period).cos() + NOISE * noise) as f32
                })
                .collect(),
        };
        let grid = BlockGrid::new(w as u32, w as u32, 8);
        let (s, mut field, periods) = uniform_print(grid, 0.0, period as f32);
        for j in 0..grid.rows as usize {
            for i in 0..grid.cols as usize {
                let (x, y) = (i as f64 * 8.0 + 4.0 - c, j as f64 * 8.0 + 4.0 - c);
                let k = grid.index(i, j);
                field.angle[k] = (y.atan2(x) + FRAC_PI_2).rem_euclid(PI) as f32;
                field.coherence[k] = if x.hypot(y) < 14.0 { 0.2 } else { 1.0 };
            }
        }
        let agreement = |field: &OrientationField| {
            let e = enhance(
                gray.clone(),
                &s,
                field,
                &periods,
                &FingerprintParams::default(),
                true,
            );
            let (mut agree, mut total) = (0, 0);
            for (i, &v) in e.values.iter().enumerate() {
                let (x, y) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
                let r = radius(x, y);
                let wave = (TAU * r / period).cos();
                if (3.0..14.0).contains(&r) && wave.abs() >= 0.5 {
                    total += 1;
                    agree += usize::from((v > 0.0) == (wave > 0.0));
                }
            }
            agree as f64 / total as f64
        };
        let whole = {
            let mut f = field.clone();
            f.coherence.iter_mut().for_each(|c| *c = 1.0);
            agreement(&f)
        };
        let split = agreement(&field);
        assert!(
            split > 0.98 && split > whole + 0.015,
            "sub-blocks {split:.3}, whole blocks {whole:.3}"
        );
    }

    #[test]
    fn enhancement_restores_ridges_through_noise_and_a_gap() {
        // Horizontal dark ridges, period 8; salt noise and a blank band across them.
        let (w, h, period) = (96usize, 96usize, 8.0);
        let mut gray = ridges_in_disk(w as u32, h as u32, period, 0.0, [48.0, 48.0], 200.0);
        for (i, v) in gray.values.iter_mut().enumerate() {
            if (44..48).contains(&(i % w)) {
                *v = 128.0;
            } else if (i * 7919) % 13 == 0 {
                *v = 255.0 - *v;
            }
        }
        let grid = BlockGrid::new(w as u32, h as u32, 8);
        let (s, field, periods) = uniform_print(grid, 0.0, period as f32);
        let e = enhance(
            gray,
            &s,
            &field,
            &periods,
            &FingerprintParams::default(),
            true,
        );
        let agree = ridge_agreement(&e, period, 0.0, [48.0, 48.0], (16, 80));
        assert!(agree > 0.99, "{agree}");
    }
}
