//! Small image operations the fingerprint stages share: a separable Gaussian blur, Sobel
//! gradients, the exact squared Euclidean distance transform and the closing by a disk it gives,
//! and connected components on a grid of block flags (its 3x3 morphology is the masks' own,
//! `mask::morph3`).

use super::fields::Plane;
use crate::mask::{label_components, Connectivity};
use std::cmp::Ordering;

/// Gaussian blur with standard deviation `sigma` px (radius `ceil(3 sigma)`), borders clamped.
/// `sigma <= 0` returns a copy.
pub(crate) fn gaussian_blur(plane: &Plane, sigma: f64) -> Plane {
    if sigma.is_nan() || sigma <= 0.0 || plane.values.is_empty() {
        return plane.clone();
    }
    let kernel = gaussian_kernel(sigma);
    let r = (kernel.len() / 2) as i64;
    let (w, h) = (plane.width as usize, plane.height as usize);
    let mut rows = vec![0.0f32; w * h];
    for y in 0..h {
        let line = &plane.values[y * w..(y + 1) * w];
        let row = &mut rows[y * w..(y + 1) * w];
        // Away from the borders, the taps without clamping, tap by tap for all those columns
        // side by side (the same sum for each column, term by term).
        let r = r as usize;
        let inner = if w > 2 * r { r..w - r } else { 0..0 };
        for (k, &c) in kernel.iter().enumerate().filter(|_| !inner.is_empty()) {
            let taps = &line[inner.start + k - r..];
            for (out, &v) in row[inner.clone()].iter_mut().zip(taps) {
                *out += c * v;
            }
        }
        for (x, out) in row.iter_mut().enumerate() {
            if inner.contains(&x) {
                continue;
            }
            let mut s = 0.0;
            let lo = x as i64 - r as i64;
            for (k, &c) in kernel.iter().enumerate() {
                let xx = (lo + k as i64).clamp(0, w as i64 - 1) as usize;
                s += c * line[xx];
            }
            *out = s;
        }
    }
    let mut out = vec![0.0f32; w * h];
    for y in 0..h {
        for (k, &c) in kernel.iter().enumerate() {
            let yy = (y as i64 + k as i64 - r).clamp(0, h as i64 - 1) as usize;
            let (src, dst) = (&rows[yy * w..(yy + 1) * w], &mut out[y * w..(y + 1) * w]);
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
pub(crate) fn sobel(plane: &Plane) -> (Plane, Plane) {
    let (w, h) = (plane.width as i64, plane.height as i64);
    let mut gx = Vec::with_capacity(plane.values.len());
    let mut gy = Vec::with_capacity(plane.values.len());
    let v = &plane.values;
    for y in 0..h {
        for x in 0..w {
            if x > 0 && y > 0 && x + 1 < w && y + 1 < h {
                // Inside: the nine pixels directly (the values `at` gives, the same sums).
                let (up, mid, down) = (
                    ((y - 1) * w + x) as usize,
                    (y * w + x) as usize,
                    ((y + 1) * w + x) as usize,
                );
                let (a, b, c) = (v[up - 1], v[up], v[up + 1]);
                let (d, f) = (v[mid - 1], v[mid + 1]);
                let (g, k, m) = (v[down - 1], v[down], v[down + 1]);
                gx.push((c + 2.0 * f + m) - (a + 2.0 * d + g));
                gy.push((g + 2.0 * k + m) - (a + 2.0 * b + c));
                continue;
            }
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

/// The exact squared Euclidean distance from every pixel centre of a `width` x `height` image to
/// the nearest of `sites` (0 on a site; `f32::INFINITY` everywhere when there is none). Pixels
/// outside the image are no sites. Meijster, Roerdink and Hesselink's separable transform: the
/// distance along each column, then per row the lower envelope of the parabolas
/// `(x - i)² + g(i)²`, in integers (the same values as [`crate::mask::squared_distances_to`]
/// wherever that one is exact, without its padding and run envelopes).
pub(crate) fn squared_distances(sites: &[bool], width: usize, height: usize) -> Vec<f32> {
    if !sites.iter().any(|&s| s) {
        return vec![f32::INFINITY; sites.len()];
    }
    // No column distance reaches `far`: a pixel's parabola through a column without sites
    // lies above every real one.
    let far = (width + height) as i64;
    let mut g = vec![far; width * height];
    for y in 0..height {
        let (done, rest) = g.split_at_mut(y * width);
        let row = &mut rest[..width];
        let above = if y > 0 {
            &done[(y - 1) * width..]
        } else {
            &[][..]
        };
        for (x, (d, &s)) in row
            .iter_mut()
            .zip(&sites[y * width..(y + 1) * width])
            .enumerate()
        {
            *d = if s {
                0
            } else if y > 0 {
                (above[x] + 1).min(far)
            } else {
                far
            };
        }
    }
    for y in (0..height.saturating_sub(1)).rev() {
        let (head, below) = g.split_at_mut((y + 1) * width);
        let row = &mut head[y * width..];
        for (d, &b) in row.iter_mut().zip(&below[..width]) {
            *d = (*d).min(b + 1);
        }
    }
    let mut out = vec![0.0f32; width * height];
    // The envelope's parabolas (their columns) and where each starts to be the lowest.
    let mut column = vec![0usize; width];
    let mut start = vec![0i64; width];
    for y in 0..height {
        let row = &g[y * width..(y + 1) * width];
        let f = |x: i64, i: usize| (x - i as i64).pow(2) + row[i] * row[i];
        // Where parabola `u` (right of `i`) starts to lie below parabola `i`.
        let separation = |i: usize, u: usize| {
            let (i2, u2) = (i as i64, u as i64);
            (u2 * u2 - i2 * i2 + row[u] * row[u] - row[i] * row[i]).div_euclid(2 * (u2 - i2))
        };
        // `q` + 1 parabolas in the envelope (`q` = -1: none yet).
        let mut q = 0isize;
        column[0] = 0;
        start[0] = 0;
        for u in 1..width {
            while q >= 0 && f(start[q as usize], column[q as usize]) > f(start[q as usize], u) {
                q -= 1;
            }
            if q < 0 {
                q = 0;
                column[0] = u;
            } else {
                let from = 1 + separation(column[q as usize], u);
                if from < width as i64 {
                    q += 1;
                    column[q as usize] = u;
                    start[q as usize] = from;
                }
            }
        }
        let out_row = &mut out[y * width..(y + 1) * width];
        for x in (0..width).rev() {
            out_row[x] = f(x as i64, column[q as usize]) as f32;
            if x as i64 == start[q as usize] {
                q -= 1;
            }
        }
    }
    out
}

/// The closing of `ink` by a disk of radius `radius` px (dilate, then erode, both by exact
/// Euclidean distance): the same pixels as [`crate::mask::close_disk`]. Pixels outside the image
/// do not erode it, so a print cut by the image edge keeps its region up to that edge.
pub(crate) fn close_disk(ink: &[bool], width: usize, height: usize, radius: f64) -> Vec<bool> {
    let r2 = (radius * radius) as f32;
    let outside: Vec<bool> = squared_distances(ink, width, height)
        .iter()
        // Not within the radius (a NaN radius dilates nothing, as the masks' closing).
        .map(|&d| !matches!(d.partial_cmp(&r2), Some(Ordering::Less | Ordering::Equal)))
        .collect();
    squared_distances(&outside, width, height)
        .iter()
        .map(|&d| d > r2)
        .collect()
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
    fn masks() -> Vec<(Vec<bool>, usize, usize)> {
        let mut state = 12345u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as usize
        };
        let mut out = Vec::new();
        for (w, h, density) in [
            (37, 23, 40),
            (1, 9, 3),
            (50, 1, 5),
            (64, 48, 2),
            (17, 31, 0),
        ] {
            let mut ink: Vec<bool> = (0..w * h)
                .map(|_| density > 0 && next() % 100 < density)
                .collect();
            // A bar, so the far side of the image is far from some ink.
            for y in 0..h / 2 {
                ink[y * w + w / 3] = density > 0;
            }
            out.push((ink, w, h));
        }
        out.push((vec![true; 12 * 5], 12, 5));
        out
    }

    #[test]
    fn distances_and_closing_are_the_masks_own() {
        for (ink, w, h) in masks() {
            let exact = squared_distances(&ink, w, h);
            let reference = crate::mask::squared_distances_to(&ink, w, h, (w + h) as f64);
            assert_eq!(exact, reference, "{w} x {h}");
            for radius in [0.0, 1.0, 1.5, 2.9, 4.0, 7.5] {
                assert_eq!(
                    close_disk(&ink, w, h, radius),
                    crate::mask::close_disk(&ink, w, h, radius),
                    "{w} x {h}, radius {radius}"
                );
            }
        }
        // A single site: the squared distances of the grid.
        let mut ink = vec![false; 5 * 4];
        ink[2 * 5 + 1] = true;
        let d = squared_distances(&ink, 5, 4);
        assert_eq!(d[0], 5.0);
        assert_eq!(d[3 * 5 + 4], 10.0);
    }

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
