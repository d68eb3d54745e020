//! Degraded captures of the generated cases: what a phone photo or a poor scan does to clean
//! strokes. Each case's strokes are drawn anti-aliased in gray (4 x 4 samples per pixel), then
//! blurred, lit unevenly from one side, noised and JPEG-compressed; a third of them are light
//! strokes on a dark ground. The truth stays the clean case's: its strokes, and its binary for
//! what counts as ink.
//!
//! Everything is seeded: the same call gives the same pixels.

use image::{codecs::jpeg::JpegEncoder, GrayImage, Luma};

use super::{render, Case, SplitMix64, Stroke};

/// How one case was degraded.
#[derive(Clone, Debug, PartialEq)]
pub struct Recipe {
    /// Light strokes on a dark ground.
    pub inverted: bool,
    /// Gray level of the paper (before the lighting) and of the ink.
    pub paper: u8,
    /// Gray level of fully covered ink pixels.
    pub ink: u8,
    /// Standard deviation of the Gaussian blur, px.
    pub blur: f64,
    /// Share of the light lost across the image: the far side gets `1 - falloff` of it.
    pub falloff: f64,
    /// Direction the light falls off towards, radians.
    pub light_angle: f64,
    /// Standard deviation of the additive Gaussian noise, gray levels.
    pub noise: f64,
    /// JPEG quality the image went through.
    pub jpeg_quality: u8,
}

impl Recipe {
    /// A short label for tables, e.g. `inv b1.2 l45% n8 q70`.
    pub fn label(&self) -> String {
        format!(
            "{}b{:.1} l{:.0}% n{:.0} q{}",
            if self.inverted { "inv " } else { "" },
            self.blur,
            self.falloff * 100.0,
            self.noise,
            self.jpeg_quality
        )
    }
}

/// One degraded capture: the clean case (truth strokes and truth ink) and the gray image.
#[derive(Clone, Debug)]
pub struct Degraded {
    /// The clean case; its `group` is `degraded`.
    pub case: Case,
    /// The degraded capture.
    pub gray: GrayImage,
    /// What was done to it.
    pub recipe: Recipe,
}

/// Supersampling factor per axis of the anti-aliased drawing.
const SUPERSAMPLE: u32 = 4;

/// The degraded group: every case of `cases` whose binary is its strokes drawn as
/// [`render`] draws them (cases with knocked-out ink are left out: the knock-out is not in the
/// strokes), degraded with a recipe drawn from `seed` and the case's position. Every third case
/// is inverted.
pub fn degrade_cases(cases: Vec<Case>, seed: u64) -> Vec<Degraded> {
    cases
        .into_iter()
        .filter(|case| render(&case.strokes, case.binary.width, case.binary.height) == case.binary)
        .enumerate()
        .map(|(i, mut case)| {
            let mut rng = SplitMix64::new(seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            let inverted = i % 3 == 2;
            let (dark, light) = (rng.range(10.0, 70.0) as u8, rng.range(190.0, 250.0) as u8);
            let recipe = Recipe {
                inverted,
                paper: if inverted { dark } else { light },
                ink: if inverted { light } else { dark },
                blur: rng.range(0.5, 1.3),
                falloff: rng.range(0.2, 0.6),
                light_angle: rng.range(0.0, std::f64::consts::TAU),
                noise: rng.range(3.0, 10.0),
                jpeg_quality: 70,
            };
            let gray = degrade(
                &case.strokes,
                case.binary.width,
                case.binary.height,
                &recipe,
                &mut rng,
            );
            case.group = "degraded".to_string();
            Degraded { case, gray, recipe }
        })
        .collect()
}

/// Draws `strokes` in a `width` x `height` gray image and degrades it by `recipe`, the noise
/// drawn from `rng`.
pub fn degrade(
    strokes: &[Stroke],
    width: u32,
    height: u32,
    recipe: &Recipe,
    rng: &mut SplitMix64,
) -> GrayImage {
    let coverage = coverage(strokes, width, height);
    let (paper, ink) = (recipe.paper as f32, recipe.ink as f32);
    let scene = GrayImage::from_fn(width, height, |x, y| {
        let c = coverage[(y * width + x) as usize];
        Luma([(paper + (ink - paper) * c).round().clamp(0.0, 255.0) as u8])
    });
    let blurred = if recipe.blur > 0.0 {
        imageproc::filter::gaussian_blur_f32(&scene, recipe.blur as f32)
    } else {
        scene
    };
    // Light falls off linearly along the light direction, from full on one side of the image to
    // `1 - falloff` on the other.
    let (dx, dy) = (recipe.light_angle.cos(), recipe.light_angle.sin());
    let corners = [
        [0.0, 0.0],
        [width as f64, 0.0],
        [0.0, height as f64],
        [width as f64, height as f64],
    ];
    let along = |p: [f64; 2]| p[0] * dx + p[1] * dy;
    let lo = corners
        .iter()
        .map(|&p| along(p))
        .fold(f64::INFINITY, f64::min);
    let hi = corners
        .iter()
        .map(|&p| along(p))
        .fold(f64::NEG_INFINITY, f64::max);
    let span = (hi - lo).max(1.0);
    let mut lit = blurred;
    for (x, y, pixel) in lit.enumerate_pixels_mut() {
        let t = (along([x as f64 + 0.5, y as f64 + 0.5]) - lo) / span;
        let gain = 1.0 - recipe.falloff * t;
        let noise = recipe.noise * gaussian(rng);
        pixel.0[0] = (pixel.0[0] as f64 * gain + noise).round().clamp(0.0, 255.0) as u8;
    }
    jpeg(&lit, recipe.jpeg_quality)
}

/// Share of each pixel covered by the strokes, from [`SUPERSAMPLE`]² samples per pixel.
fn coverage(strokes: &[Stroke], width: u32, height: u32) -> Vec<f32> {
    let s = SUPERSAMPLE;
    let scaled: Vec<Stroke> = strokes
        .iter()
        .map(|stroke| Stroke {
            points: stroke
                .points
                .iter()
                .map(|p| [p[0] * s as f64, p[1] * s as f64])
                .collect(),
            widths: stroke.widths.iter().map(|w| w * s as f64).collect(),
        })
        .collect();
    let fine = render(&scaled, width * s, height * s);
    let mut coverage = vec![0f32; (width * height) as usize];
    let fine_width = (width * s) as usize;
    for (i, &ink) in fine.ink.iter().enumerate() {
        if ink {
            let (fx, fy) = ((i % fine_width) as u32, (i / fine_width) as u32);
            coverage[((fy / s) * width + fx / s) as usize] += 1.0 / (s * s) as f32;
        }
    }
    coverage
}

/// A standard normal draw (Box-Muller).
fn gaussian(rng: &mut SplitMix64) -> f64 {
    let u = rng.next_f64().max(f64::MIN_POSITIVE);
    let v = rng.next_f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// `gray` through a JPEG encoder at `quality` and back.
fn jpeg(gray: &GrayImage, quality: u8) -> GrayImage {
    let mut bytes = Vec::new();
    JpegEncoder::new_with_quality(&mut bytes, quality)
        .encode_image(gray)
        .expect("encoding a gray image into memory cannot fail");
    image::load_from_memory(&bytes)
        .expect("a JPEG just written decodes")
        .to_luma8()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::text_cases;

    #[test]
    fn degraded_cases_are_deterministic_and_a_third_inverted() {
        let cases: Vec<Case> = text_cases().into_iter().take(6).collect();
        let a = degrade_cases(cases.clone(), 7);
        let b = degrade_cases(cases, 7);
        assert_eq!(a.len(), 6);
        assert!(a
            .iter()
            .zip(&b)
            .all(|(a, b)| a.gray == b.gray && a.recipe == b.recipe));
        assert_eq!(a.iter().filter(|d| d.recipe.inverted).count(), 2);
    }

    #[test]
    fn ink_stays_darker_than_the_paper_around_it() {
        let case = text_cases().remove(0);
        let d = &degrade_cases(vec![case], 3)[0];
        assert!(!d.recipe.inverted);
        // Mean gray over truth ink against over the paper: the strokes are still there.
        let (mut ink, mut n_ink, mut paper, mut n_paper) = (0.0, 0.0, 0.0, 0.0);
        for (i, &on) in d.case.binary.ink.iter().enumerate() {
            let v = d.gray.as_raw()[i] as f64;
            if on {
                ink += v;
                n_ink += 1.0;
            } else {
                paper += v;
                n_paper += 1.0;
            }
        }
        assert!(
            ink / n_ink + 40.0 < paper / n_paper,
            "{} {}",
            ink / n_ink,
            paper / n_paper
        );
    }
}
