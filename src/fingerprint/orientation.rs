//! The orientation field (docs/fingerprints.md, "Orientation"): the gradient structure tensor
//! summed per block, smoothed as a doubled-angle vector field, with its coherence.
//!
//! Per block the sums `G_xx = Σ g_x²`, `G_yy = Σ g_y²`, `G_xy = Σ g_x g_y` give the doubled-angle
//! vector `(G_xx - G_yy, 2 G_xy)`, whose angle is twice the dominant gradient direction (Kass and
//! Witkin; Bazen and Gerez): doubling makes opposite gradients, the two flanks of one ridge, add
//! instead of cancelling. The vectors and the energies `G_xx + G_yy` of the print's blocks are
//! smoothed with a Gaussian of `orientation_sigma` px over the block centers (as pyfing's GBFOE
//! smooths with a Gaussian of tens of pixels); the ridge runs across the gradient, at half the
//! vector's angle plus π/2, and the coherence is the smoothed vector's length over the smoothed
//! energy. Background blocks take the smoothed value of the print around them, so the Gabor
//! filter near the border still has a direction.
//!
//! In: the gradients' sums per block and the [`Segmentation`]; out: [`OrientationField`].

use super::fields::{OrientationField, Segmentation};
use super::math::BlockGradients;
use crate::params::FingerprintParams;
use std::f64::consts::{FRAC_PI_2, PI};

/// The orientation field of the print from its `gradients`' sums per block.
pub(crate) fn orientation(
    gradients: &BlockGradients,
    segmentation: &Segmentation,
    params: &FingerprintParams,
) -> OrientationField {
    let grid = segmentation.grid;
    let (cols, rows) = (grid.cols as usize, grid.rows as usize);
    // Per block: doubled-angle vector and energy; zero outside the print.
    let tensor: Vec<[f64; 3]> = (gradients.tensor.iter().zip(&segmentation.inside))
        .map(|(&[xx, yy, xy], &inside)| {
            if inside {
                [xx - yy, 2.0 * xy, xx + yy]
            } else {
                [0.0; 3]
            }
        })
        .collect();
    let sigma = (params.orientation_sigma / f64::from(grid.block)).max(0.5);
    let radius = (3.0 * sigma).ceil() as i64;
    let weights: Vec<f64> = (-radius..=radius)
        .map(|d| (-((d * d) as f64) / (2.0 * sigma * sigma)).exp())
        .collect();
    // Separable smoothing: rows, then columns.
    let mut rows_pass = vec![[0.0f64; 3]; grid.len()];
    for j in 0..rows {
        for i in 0..cols {
            let mut s = [0.0f64; 3];
            for (k, &wt) in weights.iter().enumerate() {
                let ii = i as i64 + k as i64 - radius;
                if ii < 0 || ii >= cols as i64 {
                    continue;
                }
                let t = tensor[grid.index(ii as usize, j)];
                for c in 0..3 {
                    s[c] += wt * t[c];
                }
            }
            rows_pass[grid.index(i, j)] = s;
        }
    }
    let mut angle = vec![0.0f32; grid.len()];
    let mut coherence = vec![0.0f32; grid.len()];
    for j in 0..rows {
        for i in 0..cols {
            let mut s = [0.0f64; 3];
            for (k, &wt) in weights.iter().enumerate() {
                let jj = j as i64 + k as i64 - radius;
                if jj < 0 || jj >= rows as i64 {
                    continue;
                }
                let t = rows_pass[grid.index(i, jj as usize)];
                for c in 0..3 {
                    s[c] += wt * t[c];
                }
            }
            let b = grid.index(i, j);
            if s[2] > 0.0 {
                let gradient = s[1].atan2(s[0]) / 2.0;
                angle[b] = (gradient + FRAC_PI_2).rem_euclid(PI) as f32;
                coherence[b] = ((s[0] * s[0] + s[1] * s[1]).sqrt() / s[2]).min(1.0) as f32;
            }
        }
    }
    OrientationField {
        grid,
        angle,
        coherence,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fingerprint::fields::BlockGrid;
    use crate::fingerprint::math::gradients;
    use crate::fingerprint::tests::ridges_in_disk;

    fn angle_error(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(PI);
        d.min(PI - d)
    }

    #[test]
    fn ridges_at_any_angle_are_found_with_high_coherence() {
        for degrees in [0.0f64, 30.0, 90.0, 135.0, 170.0] {
            let theta = degrees.to_radians();
            let gray = ridges_in_disk(128, 128, 8.0, theta, [64.0, 64.0], 200.0);
            let (_, gradients) = gradients(&gray, 8);
            let grid = BlockGrid::new(128, 128, 8);
            let inside = Segmentation {
                grid,
                inside: vec![true; grid.len()],
            };
            let f = orientation(&gradients, &inside, &FingerprintParams::default());
            let centre = grid.index(8, 8);
            let found = f64::from(f.angle[centre]);
            assert!(
                angle_error(found, theta) < 2f64.to_radians(),
                "{degrees}: {found}"
            );
            assert!(f.coherence[centre] > 0.9, "{}", f.coherence[centre]);
            assert!(angle_error(f.angle_at([40.0, 90.0]), theta) < 2f64.to_radians());
        }
    }

    #[test]
    fn background_blocks_take_the_print_around_them_and_empty_gives_zero() {
        let gray = ridges_in_disk(96, 96, 8.0, 1.0, [48.0, 48.0], 200.0);
        let (_, gradients) = gradients(&gray, 8);
        let grid = BlockGrid::new(96, 96, 8);
        let mut inside = vec![true; grid.len()];
        inside[grid.index(5, 5)] = false;
        let s = Segmentation { grid, inside };
        let f = orientation(&gradients, &s, &FingerprintParams::default());
        assert!(angle_error(f64::from(f.angle[grid.index(5, 5)]), 1.0) < 0.05);
        let none = Segmentation {
            grid,
            inside: vec![false; grid.len()],
        };
        let f = orientation(&gradients, &none, &FingerprintParams::default());
        assert!(f.coherence.iter().all(|&c| c == 0.0));
    }
}
