//! Oriented smoothing, the other contextual enhancement (docs/fingerprints.md, "Enhancement";
//! the method SourceAFIS uses): each pixel of the print is averaged along its block's ridge
//! direction, which joins a ridge across pores, breaks and noise, and the result is compared with
//! its own average across the ridges, a local mean over one ridge period: where the ridge-wise
//! average is darker than that mean the pixel is ridge (for dark ridges).
//!
//! Both averages are uniform, of bilinear samples 1 px apart on a line through the pixel: along
//! the ridge over `smoothing_along` periods, across it over one period. They use the block's
//! orientation and period, as the Gabor filter does ([`super::enhance`]), so the two differ only
//! in the filter: the Gabor filter fits one wave of the block's period, this one a box along the
//! ridge and a box across it, at a tenth of the cost per pixel.
//!
//! In: the gray image, [`Segmentation`], [`OrientationField`], [`RidgePeriods`]; out: the
//! enhanced [`Plane`], ridges positive, zero outside the print.

use super::fields::{BlockGrid, OrientationField, Plane, RidgePeriods, Segmentation};
use crate::params::FingerprintParams;
use rayon::prelude::*;

/// The enhanced image: the ridge-wise average minus its across-ridge mean, with the sign that
/// makes ridges positive (`dark_ridges` says which side of the gray levels they are), zero
/// outside the print.
pub(crate) fn enhance(
    gray: &Plane,
    segmentation: &Segmentation,
    field: &OrientationField,
    periods: &RidgePeriods,
    params: &FingerprintParams,
    dark_ridges: bool,
) -> Plane {
    let grid = segmentation.grid;
    let empty = || Plane {
        width: grid.width,
        height: grid.height,
        values: vec![0.0; gray.values.len()],
    };
    if grid.is_empty() {
        return empty();
    }
    // The ridge-wise average is needed inside the print and one block around it (the across-ridge
    // mean of a pixel near the border reads it there).
    let near = crate::mask::morph3(
        &segmentation.inside,
        grid.cols as usize,
        grid.rows as usize,
        true,
    );
    let lines = Lines {
        grid,
        field,
        periods,
    };
    let along = lines.average(gray, &near, false, |p| {
        (params.smoothing_along * p / 2.0).max(1.0)
    });
    let across = lines.average(&along, &segmentation.inside, true, |p| p / 2.0);
    let sign = if dark_ridges { -1.0f32 } else { 1.0 };
    let mut out = empty();
    for ((value, inside), (a, m)) in out
        .values
        .iter_mut()
        .zip(segmentation.pixel_mask())
        .zip(along.values.iter().zip(&across.values))
    {
        if inside {
            *value = sign * (a - m);
        }
    }
    out
}

/// The blocks' ridge directions and periods, for averaging along lines.
struct Lines<'a> {
    grid: BlockGrid,
    field: &'a OrientationField,
    periods: &'a RidgePeriods,
}

impl Lines<'_> {
    /// Each pixel of the blocks in `wanted` averaged over a line of bilinear samples 1 px apart
    /// through it, `reach(period)` px to either side, along the block's ridge direction or
    /// (`across`) its normal. Pixels of other blocks keep their value.
    fn average(
        &self,
        plane: &Plane,
        wanted: &[bool],
        across: bool,
        reach: impl Fn(f64) -> f64 + Sync,
    ) -> Plane {
        let Lines {
            grid,
            field,
            periods,
        } = *self;
        let (w, b) = (grid.width as usize, grid.block as usize);
        let mut values = plane.values.clone();
        values
            .par_chunks_mut(w * b)
            .enumerate()
            .for_each(|(j, band)| {
                for i in 0..grid.cols as usize {
                    let index = grid.index(i, j);
                    if !wanted[index] {
                        continue;
                    }
                    let theta = f64::from(field.angle[index]);
                    let (dx, dy) = if across {
                        (-theta.sin(), theta.cos())
                    } else {
                        (theta.cos(), theta.sin())
                    };
                    let steps = reach(f64::from(periods.period[index])).round().max(1.0) as i64;
                    let n = (2 * steps + 1) as f32;
                    let (x0, x1, y0, y1) = grid.pixels(i, j);
                    for y in y0..y1 {
                        for x in x0..x1 {
                            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                            let sum: f32 = (-steps..=steps)
                                .map(|t| plane.sample(cx + t as f64 * dx, cy + t as f64 * dy))
                                .sum();
                            band[(y - y0) * w + x] = sum / n;
                        }
                    }
                }
            });
        Plane {
            width: plane.width,
            height: plane.height,
            values,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fingerprint::tests::{ridge_agreement, ridges_in_disk, uniform_print};

    #[test]
    fn smoothing_restores_ridges_through_noise_and_a_gap() {
        // Ridges at 30 degrees, period 9; salt noise and a blank band across them.
        let (w, h, period, theta) = (96usize, 96usize, 9.0, 0.5f64);
        let mut gray = ridges_in_disk(w as u32, h as u32, period, theta, [48.0, 48.0], 200.0);
        for (i, v) in gray.values.iter_mut().enumerate() {
            if (44..47).contains(&(i % w)) {
                *v = 128.0;
            } else if (i * 7919) % 13 == 0 {
                *v = 255.0 - *v;
            }
        }
        let grid = BlockGrid::new(w as u32, h as u32, 8);
        let (s, field, periods) = uniform_print(grid, theta as f32, period as f32);
        let e = enhance(
            &gray,
            &s,
            &field,
            &periods,
            &FingerprintParams::default(),
            true,
        );
        let agree = ridge_agreement(&e, period, theta, [48.0, 48.0], (16, 80));
        assert!(agree > 0.99, "{agree}");
    }

    #[test]
    fn nothing_outside_the_print() {
        let gray = ridges_in_disk(64, 64, 8.0, 0.0, [32.0, 32.0], 200.0);
        let grid = BlockGrid::new(64, 64, 8);
        let (mut s, field, periods) = uniform_print(grid, 0.0, 8.0);
        s.inside.iter_mut().for_each(|inside| *inside = false);
        s.inside[grid.index(3, 3)] = true;
        let e = enhance(
            &gray,
            &s,
            &field,
            &periods,
            &FingerprintParams::default(),
            true,
        );
        for (k, &v) in e.values.iter().enumerate() {
            let (x, y) = (k as u32 % 64, k as u32 / 64);
            if !(24..32).contains(&x) || !(24..32).contains(&y) {
                assert_eq!(v, 0.0, "({x}, {y})");
            }
        }
        assert!(e.values.iter().any(|&v| v != 0.0));
    }
}
