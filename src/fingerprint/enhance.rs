//! Contextual enhancement (docs/fingerprints.md, "Enhancement"): each block is filtered with an
//! even Gabor filter tuned to its ridge orientation and period (Hong, Wan and Jain 1998; pyfing's
//! GBFEN), and the sign of the response is the binarization.
//!
//! The filter is `exp(-(u²/σ_n² + v²/σ_r²)/2) cos(2π u / T)` with `u` across the ridge (along the
//! normal), `v` along it, `T` the block's period, `σ_n = gabor_sigma_across · T` (5/12, pyfing's
//! value) and `σ_r = gabor_sigma_along · T`; it is made zero-mean and of unit energy, so the
//! local gray level and contrast drop out and the response is the local ridge wave. One kernel per
//! block (8 px), applied directly; blocks outside the print are not filtered. Dark ridges give a
//! negative response; the plane returned has ridges positive.
//!
//! In: the gray image, [`Segmentation`], [`OrientationField`], [`RidgePeriods`]; out: the
//! enhanced [`Plane`].

use super::fields::{OrientationField, Plane, RidgePeriods, Segmentation};
use crate::FingerprintParams;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The enhanced image: the Gabor response, ridges positive (`dark_ridges` says which side of the
/// gray levels the ridges are), zero outside the print.
pub(crate) fn enhance(
    gray: &Plane,
    segmentation: &Segmentation,
    field: &OrientationField,
    periods: &RidgePeriods,
    params: &FingerprintParams,
    dark_ridges: bool,
) -> Plane {
    let grid = segmentation.grid;
    let (w, b) = (grid.width as usize, grid.block as usize);
    let sign = if dark_ridges { -1.0f32 } else { 1.0 };
    let mut values = vec![0.0f32; gray.values.len()];
    if w == 0 || b == 0 {
        return Plane {
            width: grid.width,
            height: grid.height,
            values,
        };
    }
    values
        .par_chunks_mut(w * b)
        .enumerate()
        .for_each(|(j, band)| {
            let mut kernel = Vec::new();
            for i in 0..grid.cols as usize {
                let index = grid.index(i, j);
                if !segmentation.inside[index] {
                    continue;
                }
                let radius = gabor_kernel(
                    f64::from(field.angle[index]),
                    f64::from(periods.period[index]),
                    params,
                    &mut kernel,
                );
                let side = 2 * radius + 1;
                let (x0, x1, y0, y1) = grid.pixels(i, j);
                for y in y0..y1 {
                    for x in x0..x1 {
                        let mut s = 0.0f32;
                        for (row, taps) in kernel.chunks_exact(side).enumerate() {
                            let yy = y as i64 + row as i64 - radius as i64;
                            let x_start = x as i64 - radius as i64;
                            if x_start >= 0 && x_start + side as i64 <= w as i64 {
                                let yy = yy.clamp(0, i64::from(grid.height) - 1) as usize;
                                let line = &gray.values
                                    [yy * w + x_start as usize..yy * w + x_start as usize + side];
                                s += taps.iter().zip(line).map(|(k, v)| k * v).sum::<f32>();
                            } else {
                                for (c, &k) in taps.iter().enumerate() {
                                    s += k * gray.at(x_start + c as i64, yy);
                                }
                            }
                        }
                        band[(y - y0) * w + x] = sign * s;
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
    let radius = (3.0 * sigma_n.max(sigma_r)).ceil().clamp(1.0, 64.0) as i64;
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
            &gray,
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
