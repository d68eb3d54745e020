//! Small image operations the fingerprint stages share: a separable Gaussian blur, Sobel
//! gradients, the exact squared Euclidean distance transform and the closing by a disk it gives,
//! and connected components on a grid of block flags (its 3x3 morphology is the masks' own,
//! `mask::morph3`).

use super::fields::Plane;
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
/// along the box's columns only), the pixels outside the box zero (`sigma <= 0`: a copy).
///
/// Each sum is kept in a register over all its taps, [`BLUR_LANES`] columns side by side, and
/// stored once, where the passes used to add each tap into the row in memory (the same terms in
/// the same order from 0: a test holds it to that version bit for bit); with AVX2 at run time the
/// lanes are eight wide ([`wide_lanes`]; the same operations, so the same values).
pub(crate) fn gaussian_blur_within(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
) -> Plane {
    #[cfg(target_arch = "x86_64")]
    if wide_lanes() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { gaussian_blur_within_wide(plane, sigma, xs, ys) };
    }
    gaussian_blur_within_lanes::<false>(plane, sigma, xs, ys)
}

/// [`gaussian_blur_within`] compiled for AVX2, its sums in AVX registers (`wide`).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gaussian_blur_within_wide(
    plane: &Plane,
    sigma: f64,
    xs: Range<usize>,
    ys: Range<usize>,
) -> Plane {
    gaussian_blur_within_lanes::<true>(plane, sigma, xs, ys)
}

/// Columns of [`gaussian_blur_within`] summed side by side.
const BLUR_LANES: usize = 16;

/// [`gaussian_blur_within`]'s passes, inlined into the version the CPU runs (`WIDE`: the one for
/// AVX2, which the CPU must have).
#[inline(always)]
fn gaussian_blur_within_lanes<const WIDE: bool>(
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
    if xs.is_empty() || ys.is_empty() {
        return Plane {
            width: plane.width,
            height: plane.height,
            values: vec![0.0f32; w * h],
        };
    }
    // The rows the column taps of the box's rows reach (clamped at the borders), from `reach`;
    // both planes grow a row at a time, each row zeroed just before its sums are stored (in the
    // cache, where zeroing the planes whole wrote them out to memory first).
    let reach = ys.start.saturating_sub(r)..(ys.end + r).min(h);
    let mut rows = Vec::with_capacity(reach.len() * w);
    let mut starts: Vec<usize> = (0..kernel.len()).collect();
    for y in reach.clone() {
        let line = &plane.values[y * w..(y + 1) * w];
        rows.resize(rows.len() + w, 0.0);
        let at = rows.len() - w;
        let row = &mut rows[at..];
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
            weighted_sums::<WIDE>(
                &kernel,
                &line[inner.start - r..inner.end + r],
                &starts,
                &mut row[inner.clone()],
            );
            [xs.start..inner.start, inner.end..xs.end]
        };
        for x in border.into_iter().flatten() {
            let mut s = 0.0;
            let lo = x as i64 - r as i64;
            for (k, &c) in kernel.iter().enumerate() {
                let xx = (lo + k as i64).clamp(0, w as i64 - 1) as usize;
                s += c * line[xx];
            }
            row[x] = s;
        }
    }
    let mut out = Vec::with_capacity(w * h);
    out.resize(ys.start * w, 0.0);
    for y in ys {
        starts.clear();
        starts.extend((0..kernel.len()).map(|k| {
            let yy = (y as i64 + k as i64 - r as i64).clamp(0, h as i64 - 1) as usize;
            (yy - reach.start) * w + xs.start
        }));
        out.resize(out.len() + w, 0.0);
        weighted_sums::<WIDE>(
            &kernel,
            &rows,
            &starts,
            &mut out[y * w + xs.start..y * w + xs.end],
        );
    }
    out.resize(w * h, 0.0);
    Plane {
        width: plane.width,
        height: plane.height,
        values: out,
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

/// [`weighted_sums`] in AVX registers: sixteen columns at a time (two registers), then eight,
/// then one by one; each tap's weight broadcast, the same operations in the same order as the
/// baseline sums (no fused multiply-add), so the same values (a test holds them bit for bit).
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
            let pair = x + 16 <= n;
            let (mut s0, mut s1) = (_mm256_setzero_ps(), _mm256_setzero_ps());
            for (&c, &start) in taps.clone() {
                let c = _mm256_set1_ps(c);
                // SAFETY: `start + x + 8 <= start + n <= src.len()` (and `+ 16` for the pair).
                unsafe {
                    let at = src.as_ptr().add(start + x);
                    s0 = _mm256_add_ps(s0, _mm256_mul_ps(c, _mm256_loadu_ps(at)));
                    if pair {
                        s1 = _mm256_add_ps(s1, _mm256_mul_ps(c, _mm256_loadu_ps(at.add(8))));
                    }
                }
            }
            // SAFETY: `x + 8 <= n` (and `x + 16` for the pair), within `out`.
            unsafe {
                _mm256_storeu_ps(out.as_mut_ptr().add(x), s0);
                if pair {
                    _mm256_storeu_ps(out.as_mut_ptr().add(x + 8), s1);
                }
            }
            x += if pair { 16 } else { 8 };
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

/// Sobel gradients `(g_x, g_y)` (x to the right, y down), borders clamped.
///
/// Inside the image each row's gradients are worked out from the three rows around it, taken
/// as slices shifted by a column, so that the columns go side by side in vector lanes (the same
/// sums, term by term, as the nine pixels read one by one: a test holds it bit for bit); the
/// pixels on the image's edge read their clamped neighbours one by one.
pub(crate) fn sobel(plane: &Plane) -> (Plane, Plane) {
    let (w, h) = (plane.width as usize, plane.height as usize);
    if plane.values.len() != w * h {
        return sobel_clamped(plane);
    }
    // Each row pushed as it is worked out: the planes are not zeroed first.
    let mut gx = Vec::with_capacity(plane.values.len());
    let mut gy = Vec::with_capacity(plane.values.len());
    let edge = |x: usize, y: usize| {
        let (x, y) = (x as i64, y as i64);
        let p = |dx: i64, dy: i64| plane.at(x + dx, y + dy);
        (
            (p(1, -1) + 2.0 * p(1, 0) + p(1, 1)) - (p(-1, -1) + 2.0 * p(-1, 0) + p(-1, 1)),
            (p(-1, 1) + 2.0 * p(0, 1) + p(1, 1)) - (p(-1, -1) + 2.0 * p(0, -1) + p(1, -1)),
        )
    };
    let push_edge = |gx: &mut Vec<f32>, gy: &mut Vec<f32>, x, y| {
        let (ex, ey) = edge(x, y);
        gx.push(ex);
        gy.push(ey);
    };
    let v = &plane.values;
    for y in 0..h {
        if y == 0 || y + 1 == h || w < 3 {
            for x in 0..w {
                push_edge(&mut gx, &mut gy, x, y);
            }
            continue;
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
        push_edge(&mut gx, &mut gy, 0, y);
        gx.extend((0..n).map(|i| (c[i] + 2.0 * f[i] + m[i]) - (a[i] + 2.0 * d[i] + g[i])));
        gy.extend((0..n).map(|i| (g[i] + 2.0 * k[i] + m[i]) - (a[i] + 2.0 * b[i] + c[i])));
        push_edge(&mut gx, &mut gy, w - 1, y);
    }
    let plane_of = |values| Plane {
        width: plane.width,
        height: plane.height,
        values,
    };
    (plane_of(gx), plane_of(gy))
}

/// [`sobel`] with every pixel's neighbours clamped at the image's edges, one pixel at a time
/// (for a plane whose values do not match its size; and the reference the tests hold the
/// lanes to).
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
                let lanes =
                    gaussian_blur_within_lanes::<false>(&plane, sigma, xs.clone(), ys.clone());
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
