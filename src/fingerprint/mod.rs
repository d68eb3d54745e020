//! The fingerprint front end (docs/fingerprints.md): what a print needs before its ridges can be
//! traced, in stages with a plain data type each ([`fields`]):
//!
//! ```text
//! gray ─segment─> Segmentation ─orientation─> OrientationField ─frequency─> RidgePeriods
//!      ─enhance─> enhanced Plane (Gabor response) ─sign inside the print─> Binary
//! ```
//!
//! The constants follow pyfing's classical pipeline (GMFS segmentation, GBFOE orientations,
//! XSFFE frequencies, GBFEN Gabor enhancement), at 500 dpi. `lib.rs` runs [`analyze`] in place of
//! the text front end (`raster::binarize`) when [`crate::Params::fingerprint`] is set, then the
//! normal pipeline on the binary image, then the fingerprint minutiae filter
//! ([`minutiae::fingerprint_minutiae`]).

mod enhance;
pub mod fields;
mod frequency;
pub(crate) mod math;
pub mod minutiae;
mod orientation;
pub(crate) mod prior;
mod segment;
mod smooth;

use crate::binary::Binary;
use crate::gray::GrayView;
use crate::params::{Enhancement, FingerprintParams};
use fields::{OrientationField, Plane, RidgePeriods, Segmentation};
use serde::Serialize;

/// Everything the fingerprint front end found on one print.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PrintAnalysis {
    /// Which blocks hold the print.
    pub segmentation: Segmentation,
    /// Ridge orientation and coherence per block.
    pub orientation: OrientationField,
    /// Ridge period per block.
    pub periods: RidgePeriods,
    /// The Gabor response, ridges positive, zero outside the print. In a trace, kept only when
    /// its stages are recorded (`--debug`, [`crate::Trace::stages`]); empty otherwise.
    #[serde(skip)]
    pub enhanced: Plane,
    /// The ridges the pixels confirm: enhanced ridge (positive response) where the gray image is
    /// also on the ridges' side of its local mean (Gaussian of half the print's median period),
    /// both after the gradients' smoothing.
    /// Beyond the last ridge of the print the zero-mean filter rings into a ghost ridge over
    /// bare skin; the gray image there is as light as the skin, so the ghost is not confirmed,
    /// and the closing of these ridges is the print's outline (`minutiae`'s border).
    #[serde(skip)]
    pub ridges: Binary,
    /// Contrast per block in `[0, 1]`: the root mean square of the enhanced response over the
    /// block, divided by its median over the print's blocks and capped at 1 (0 outside).
    pub contrast: Vec<f32>,
    /// Whether the ridges were taken as the image's dark side.
    #[serde(skip)]
    pub dark_ridges: bool,
    /// How sure that polarity is, in [0, 1), when it was decided from the image; `None` when it
    /// was given (`FrontEndParams::polarity`).
    #[serde(skip)]
    pub polarity_confidence: Option<f64>,
}

impl PrintAnalysis {
    /// Whether the chord from `a` to `b` runs across the ridge flow: more than 45° off the ridge
    /// direction at its middle (a bar between neighbouring ridges, not a ridge).
    pub(crate) fn across_the_flow(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let middle = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let chord = (b[1] - a[1]).atan2(b[0] - a[0]);
        orientation_gap(chord, self.orientation.angle_at(middle)) > std::f64::consts::FRAC_PI_4
    }

    /// A minutia's quality 0-100 at `pos`: coherence times contrast of its block, in percent.
    pub fn quality_at(&self, pos: [f64; 2]) -> u8 {
        let grid = self.orientation.grid;
        if grid.is_empty() {
            return 0;
        }
        let (i, j) = grid.block_of(pos);
        let b = grid.index(i, j);
        let c = self.orientation.coherence.get(b).copied().unwrap_or(0.0);
        let k = self.contrast.get(b).copied().unwrap_or(0.0);
        (100.0 * c * k).round().clamp(0.0, 100.0) as u8
    }
}

/// Runs segmentation, orientation field, ridge periods and Gabor enhancement on `gray` and
/// returns them with the binarization of the enhanced image (ink: positive response inside the
/// print). `dark_ridges` says whether ridges are darker than valleys.
#[cfg(test)]
pub(crate) fn analyze(
    gray: GrayView<'_>,
    params: &FingerprintParams,
    dark_ridges: bool,
) -> (PrintAnalysis, Binary) {
    let given = || Ok::<_, std::convert::Infallible>((dark_ridges, None));
    match analyze_deciding(gray, params, given) {
        Ok(analyzed) => analyzed,
        Err(never) => match never {},
    }
}

/// [`analyze`] with the polarity decided by `polarity` (whether ridges are dark, and the
/// decision's confidence when it was made from the image), run beside the stages that do not
/// depend on it: segmentation, orientation, periods and the enhancement up to its sign (the
/// filters are linear, so light ridges only negate the response of dark ones, exactly).
pub(crate) fn analyze_deciding<E: Send>(
    gray: GrayView<'_>,
    params: &FingerprintParams,
    polarity: impl FnOnce() -> Result<(bool, Option<f64>), E> + Send,
) -> Result<(PrintAnalysis, Binary), E> {
    let (decided, front) = rayon::join(polarity, || front_stages(gray, params));
    let (dark_ridges, polarity_confidence) = decided?;
    let FrontStages {
        smoothed,
        segmentation,
        orientation,
        periods,
        mut enhanced,
        blank,
    } = front;
    let blank = blank.map_or_else(Vec::new, |blank| {
        blank.blocks(
            gray,
            &segmentation,
            &orientation,
            &periods,
            params,
            dark_ridges,
        )
    });
    if !dark_ridges {
        enhanced.values.iter_mut().for_each(|v| *v = -*v);
    }
    let (width, height) = (enhanced.width, enhanced.height);
    let (segmentation, rms) =
        segment::refine(&segmentation, &enhanced, params.response_threshold, &blank);
    segmentation.outside_runs(|run| enhanced.values[run].fill(0.0));
    let contrast = block_contrast(rms, &segmentation);
    let binary = Binary {
        width,
        height,
        ink: enhanced.values.iter().map(|&r| r > 0.0).collect(),
    };
    let ridges = confirmed_ridges(&smoothed, &binary, &segmentation, &periods, dark_ridges);
    Ok((
        PrintAnalysis {
            segmentation,
            orientation,
            periods,
            enhanced,
            ridges,
            contrast,
            dark_ridges,
            polarity_confidence,
        },
        binary,
    ))
}

/// What [`front_stages`] gives: the stages that do not depend on the print's polarity.
struct FrontStages {
    smoothed: Plane,
    segmentation: Segmentation,
    orientation: OrientationField,
    periods: RidgePeriods,
    /// The enhanced image for dark ridges (ridges positive where they are dark).
    enhanced: Plane,
    /// What the print's blocks that show no ridges are found from, once the polarity is known
    /// (`None` with `blank_evidence` 0).
    blank: Option<Blank>,
}

/// The evidence of [`segment::blank_blocks`], completed from the gray image once the polarity
/// is known.
struct Blank {
    evidence: segment::RidgeEvidence,
}

impl Blank {
    /// The print's blocks that show no ridges ([`segment::blank_blocks`]) for the polarity
    /// decided, to be left out of it. The evidence's middle gray and swing are measured once
    /// for both polarities, and the blocks it completes for one are those it would give the
    /// other, so the blocks found are those found when both were (docs/fingerprints.md,
    /// "Ridges through a solid wet area").
    ///
    /// The gray levels as `f32` are made again from `gray`, and only when a block is measured:
    /// kept from the front stages, that plane stood beside the enhancement's padded image and
    /// response (docs/fingerprints.md, "Speed: the front stages' planes").
    fn blocks(
        mut self,
        gray: GrayView<'_>,
        segmentation: &Segmentation,
        orientation: &OrientationField,
        periods: &RidgePeriods,
        params: &FingerprintParams,
        dark_ridges: bool,
    ) -> Vec<bool> {
        let plane = std::sync::OnceLock::new();
        let whole = self.evidence.whole;
        let measure = |b, rows| {
            let plane = plane.get_or_init(|| gray_plane(gray));
            segment::measure_evidence(plane, whole, segmentation, orientation, periods, b, rows)
        };
        segment::blank_blocks(
            segmentation,
            &mut self.evidence,
            measure,
            params.blank_evidence,
            params.blank_off_middle,
            periods.median_inside(segmentation),
            dark_ridges,
        )
    }
}

/// Segmentation, orientation field, ridge periods and the enhancement for dark ridges.
fn front_stages(gray: GrayView<'_>, params: &FingerprintParams) -> FrontStages {
    let plane = gray_plane(gray);
    let smoothed = math::gaussian_blur(&plane, params.gradient_sigma);
    let (magnitude, gradients) = math::gradients(&smoothed, params.block);
    let segmentation = segment::segment(magnitude, &gradients, params);
    let orientation = orientation::orientation(&gradients, &segmentation, params);
    drop(gradients);
    let periods = frequency::ridge_periods(&smoothed, &segmentation, &orientation, params);
    // Blocks that show no ridges (a wet smear, a blank margin) are no print: the filter would
    // draw ridges through them from the orientation and period around. Which they are depends
    // on the polarity (decided beside these stages): the evidence is measured here, and the
    // blocks of the polarity decided are found from it once it is known ([`Blank::blocks`]);
    // the second segmentation pass leaves them out (the filter's response in a block reads only
    // the image and the block's own orientation and period).
    // The plane's levels are 8-bit gray's: whole numbers (`segment::whole_levels`).
    let evidence = (params.blank_evidence > 0.0)
        .then(|| segment::ridge_evidence(&plane, true, &segmentation, &orientation, &periods));
    // The Gabor filter takes the plane and lets it go once it has padded it, before its
    // response is allocated.
    let enhanced = match params.enhancement {
        Enhancement::Gabor => {
            enhance::enhance(plane, &segmentation, &orientation, &periods, params, true)
        }
        Enhancement::Smoothing => {
            smooth::enhance(&plane, &segmentation, &orientation, &periods, params, true)
        }
    };
    let blank = evidence.map(|evidence| Blank { evidence });
    FrontStages {
        smoothed,
        segmentation,
        orientation,
        periods,
        enhanced,
        blank,
    }
}

/// The gray levels of `gray` as `f32`.
fn gray_plane(gray: GrayView<'_>) -> Plane {
    let (width, height) = gray.dimensions();
    // Allocated at its size (collected from the rows, the vector would grow by doubling, each
    // time copied, to a third more than it holds).
    let mut values = Vec::with_capacity(width as usize * height as usize);
    for row in gray.rows() {
        values.extend(row.iter().map(|&v| f32::from(v)));
    }
    Plane {
        width,
        height,
        values,
    }
}

/// The enhanced ridges (`binary`) where the gray image (`smoothed` as for the gradients, so
/// that pixel noise does not confirm a ghost) is also on the ridges' side of its local mean, over
/// a Gaussian of half the median period of the print ([`PrintAnalysis::ridges`]).
fn confirmed_ridges(
    smoothed: &Plane,
    binary: &Binary,
    segmentation: &Segmentation,
    periods: &RidgePeriods,
    dark_ridges: bool,
) -> Binary {
    let period = periods.median_inside(segmentation);
    // Only the enhanced ridges' pixels read the mean: it is blurred over their bounding box
    // (the same value at each of them as the whole image's blur), a row at a time (no plane of
    // it kept: docs/fingerprints.md, "Speed: the front stages' planes").
    let w = binary.width as usize;
    let (xs, ys) = crate::mask::ink_box(&binary.ink, w).unwrap_or((0..0, 0..0));
    let mut ink = vec![false; binary.ink.len()];
    let sigma = (period / 2.0).max(1.0);
    math::gaussian_blur_rows(smoothed, sigma, xs, ys, &mut |y, x0, mean| {
        let row = y * w + x0..y * w + x0 + mean.len();
        let (confirmed, enhanced) = (&mut ink[row.clone()], &binary.ink[row.clone()]);
        for (((c, &ink), &g), &m) in confirmed
            .iter_mut()
            .zip(enhanced)
            .zip(&smoothed.values[row])
            .zip(mean)
        {
            *c = ink && if dark_ridges { g < m } else { g > m };
        }
    });
    Binary { ink, ..*binary }
}

/// The angle between two orientations (undirected lines), in `[0, π/2]`.
pub(crate) fn orientation_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// Per block, the RMS of the response (`rms`, [`segment::block_rms`]) over the print's median
/// RMS, capped at 1.
fn block_contrast(mut rms: Vec<f32>, segmentation: &Segmentation) -> Vec<f32> {
    let mut inside: Vec<f32> = rms
        .iter()
        .zip(&segmentation.inside)
        .filter(|(_, &i)| i)
        .map(|(&r, _)| r)
        .collect();
    let m = crate::median::upper_median_by(&mut inside, f32::total_cmp).unwrap_or(0.0);
    if m > 0.0 {
        rms.iter_mut().for_each(|r| *r = (*r / m).min(1.0));
    }
    rms
}

#[cfg(test)]
pub(crate) mod tests {
    use super::fields::BlockGrid;
    use super::*;
    use image::GrayImage;
    use std::f64::consts::TAU;

    /// Every block of `grid` print, with ridge direction `theta` and period `period`.
    pub(crate) fn uniform_print(
        grid: BlockGrid,
        theta: f32,
        period: f32,
    ) -> (Segmentation, OrientationField, RidgePeriods) {
        (
            Segmentation {
                grid,
                inside: vec![true; grid.len()],
            },
            OrientationField {
                grid,
                angle: vec![theta; grid.len()],
                coherence: vec![1.0; grid.len()],
            },
            RidgePeriods {
                grid,
                period: vec![period; grid.len()],
                measured: vec![true; grid.len()],
            },
        )
    }

    /// Of the pixels in `[lo, hi)²` well inside a ridge or a valley of [`ridges_in_disk`]'s
    /// pattern (`|cos(2π u / T)| ≥ 0.5`), the share where `enhanced` is positive exactly on the
    /// ridges.
    pub(crate) fn ridge_agreement(
        enhanced: &Plane,
        period: f64,
        theta: f64,
        centre: [f64; 2],
        (lo, hi): (usize, usize),
    ) -> f64 {
        let normal = [-theta.sin(), theta.cos()];
        let w = enhanced.width as usize;
        let (mut agree, mut total) = (0usize, 0usize);
        for y in lo..hi {
            for x in lo..hi {
                let (dx, dy) = (x as f64 + 0.5 - centre[0], y as f64 + 0.5 - centre[1]);
                let wave = (TAU * (dx * normal[0] + dy * normal[1]) / period).cos();
                if wave.abs() < 0.5 {
                    continue;
                }
                total += 1;
                if (enhanced.values[y * w + x] > 0.0) == (wave > 0.0) {
                    agree += 1;
                }
            }
        }
        agree as f64 / total.max(1) as f64
    }

    /// Straight ridges of `period` px running at `theta` (dark where `cos(2π u / T) > 0`, `u` the
    /// distance from `centre` along the normal), inside a disk of `radius`; flat 200 outside.
    pub(crate) fn ridges_in_disk(
        width: u32,
        height: u32,
        period: f64,
        theta: f64,
        centre: [f64; 2],
        radius: f64,
    ) -> Plane {
        let normal = [-theta.sin(), theta.cos()];
        let mut values = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                let (dx, dy) = (x as f64 + 0.5 - centre[0], y as f64 + 0.5 - centre[1]);
                values.push(if dx * dx + dy * dy <= radius * radius {
                    let u = dx * normal[0] + dy * normal[1];
                    (128.0 - 100.0 * (TAU * u / period).cos()) as f32
                } else {
                    200.0
                });
            }
        }
        Plane {
            width,
            height,
            values,
        }
    }

    fn gray_of(plane: &Plane) -> GrayImage {
        GrayImage::from_raw(
            plane.width,
            plane.height,
            plane
                .values
                .iter()
                .map(|&v| v.clamp(0.0, 255.0) as u8)
                .collect(),
        )
        .expect("size matches")
    }

    #[test]
    fn the_chain_gives_ridges_inside_the_print_only() {
        let plane = ridges_in_disk(200, 200, 9.0, 0.5, [100.0, 100.0], 70.0);
        let (analysis, binary) = analyze(
            (&gray_of(&plane)).into(),
            &FingerprintParams::default(),
            true,
        );
        assert!(
            !binary.get(5, 5) && !binary.get(195, 100),
            "nothing outside the print"
        );
        // Inside: about half the pixels are ridge, and the ridge pixels are the dark ones.
        let mut ink = 0;
        let mut dark_ink = 0;
        let mut total = 0;
        for y in 70..130 {
            for x in 70..130 {
                total += 1;
                if binary.get(x, y) {
                    ink += 1;
                    if plane.values[y as usize * 200 + x as usize] < 128.0 {
                        dark_ink += 1;
                    }
                }
            }
        }
        let share = ink as f64 / total as f64;
        assert!((0.4..0.6).contains(&share), "{share}");
        assert!(dark_ink as f64 > 0.95 * ink as f64, "{dark_ink} / {ink}");
        let q = analysis.quality_at([100.0, 100.0]);
        assert!(q > 80, "{q}");
        assert_eq!(analysis.quality_at([2.0, 2.0]), 0);
        let p = analysis.periods.at([100.0, 100.0]);
        assert!((p - 9.0).abs() < 1.0, "{p}");
    }

    #[test]
    fn light_ridges_flip_the_sign_and_tiny_images_do_not_panic() {
        let plane = ridges_in_disk(120, 120, 9.0, 0.0, [60.0, 60.0], 200.0);
        let (_, dark) = analyze(
            (&gray_of(&plane)).into(),
            &FingerprintParams::default(),
            true,
        );
        let (_, light) = analyze(
            (&gray_of(&plane)).into(),
            &FingerprintParams::default(),
            false,
        );
        let differ = dark
            .ink
            .iter()
            .zip(&light.ink)
            .filter(|(a, b)| a != b)
            .count();
        assert!(differ as f64 > 0.9 * dark.ink.len() as f64);
        for (w, h) in [(1, 1), (3, 40), (0, 0)] {
            let gray = GrayImage::new(w, h);
            let (_, b) = analyze((&gray).into(), &FingerprintParams::default(), true);
            assert_eq!(b.ink.len(), (w * h) as usize);
        }
    }
}
