//! Binarization: grayscale to the foreground mask, with the threshold method and ink polarity of
//! [`Params`].
//!
//! Polarity matters as much as the level: text is dark ink on light paper, fingerprint ridges are
//! often light on a dark background. `Auto` takes the minority side as ink (strokes are thin, so
//! they cover less of the page than the paper, even when the page lies on a dark table, where the
//! border would point the wrong way); only when the split is close to even (fingerprints, where
//! ridges and valleys are about as wide) does it look at the image border, which is then paper.

use rayon::prelude::*;

use crate::{Binary, GrayImage, Params, Polarity, Result, Threshold};

/// Sauvola's dynamic range of the standard deviation `R` for 8-bit images.
const SAUVOLA_R: f64 = 128.0;
/// Border shares between these bounds do not say which side is paper.
const AMBIGUOUS_BORDER: (f64, f64) = (0.4, 0.6);

/// Binarizes a grayscale image: ink is `true`. A uniform image gives an empty mask.
pub fn binarize(gray: &GrayImage, params: &Params) -> Result<Binary> {
    let (width, height) = gray.dimensions();
    let mut binary = Binary::new(width, height);
    let pixels = gray.as_raw();
    // One pass gives the range, Otsu's level and the polarity share (a page is tens of MB of
    // pixels; the histogram is built per block in parallel and summed: integer counts, so the sum
    // does not depend on the thread count).
    let histogram = histogram(pixels);
    let (Some(min), Some(max)) = (
        histogram.iter().position(|&c| c > 0),
        histogram.iter().rposition(|&c| c > 0),
    ) else {
        return Ok(binary);
    };
    if min == max {
        return Ok(binary);
    }
    match params.threshold {
        Threshold::Otsu | Threshold::Fixed { .. } => {
            let level = match params.threshold {
                Threshold::Fixed { level } => level,
                _ => otsu_level_of(&histogram, pixels.len()),
            };
            let dark_ink = match params.polarity {
                Polarity::DarkInk => true,
                Polarity::LightInk => false,
                Polarity::Auto => dark_is_ink(gray, &histogram, level),
            };
            binary
                .ink
                .par_chunks_mut(BLOCK)
                .zip(pixels.par_chunks(BLOCK))
                .for_each(|(ink, values)| {
                    for (ink, &v) in ink.iter_mut().zip(values) {
                        *ink = (v <= level) == dark_ink;
                    }
                });
        }
        Threshold::Sauvola { window, k } => {
            let dark_ink = match params.polarity {
                Polarity::DarkInk => true,
                Polarity::LightInk => false,
                Polarity::Auto => sauvola_dark_is_ink(gray),
            };
            sauvola(gray, window, k, dark_ink, &mut binary.ink);
        }
    }
    Ok(binary)
}

/// Pixels per parallel block of the whole-image passes.
const BLOCK: usize = 1 << 16;

/// The 256-bin histogram of `pixels`.
fn histogram(pixels: &[u8]) -> [u64; 256] {
    pixels
        .par_chunks(BLOCK)
        .map(|block| {
            let mut counts = [0u64; 256];
            for &v in block {
                counts[v as usize] += 1;
            }
            counts
        })
        .reduce(
            || [0u64; 256],
            |mut a, b| {
                for (a, b) in a.iter_mut().zip(b) {
                    *a += b;
                }
                a
            },
        )
}

/// Otsu's level over a 256-bin histogram: pixels `<= level` form the dark class. Same rule as
/// `imageproc::contrast::otsu_level` (first level of maximal between-class variance), with 64-bit
/// counts so images above 16 megapixels cannot overflow.
pub fn otsu_level(pixels: &[u8]) -> u8 {
    otsu_level_of(&histogram(pixels), pixels.len())
}

/// [`otsu_level`] from the histogram of `total` pixels.
fn otsu_level_of(histogram: &[u64; 256], total: usize) -> u8 {
    let total = total as f64;
    let total_sum: f64 = histogram
        .iter()
        .enumerate()
        .map(|(v, &c)| v as f64 * c as f64)
        .sum();
    let (mut dark_weight, mut dark_sum) = (0.0f64, 0.0f64);
    let (mut best, mut best_variance) = (0u8, 0.0f64);
    for (level, &count) in histogram.iter().enumerate() {
        dark_weight += count as f64;
        if dark_weight == 0.0 {
            continue;
        }
        let light_weight = total - dark_weight;
        if light_weight == 0.0 {
            break;
        }
        dark_sum += level as f64 * count as f64;
        let mean_difference = dark_sum / dark_weight - (total_sum - dark_sum) / light_weight;
        let variance = dark_weight * light_weight * mean_difference * mean_difference;
        if variance > best_variance {
            best_variance = variance;
            best = level as u8;
        }
    }
    best
}

/// Whether the dark side of `level` is ink: the minority side of the whole image is ink; when the
/// split is close to even (40-60%), the side holding most of the border pixels is paper.
fn dark_is_ink(gray: &GrayImage, histogram: &[u64; 256], level: u8) -> bool {
    let dark_all: u64 = histogram[..=level as usize].iter().sum();
    let share_all = dark_all as f64 / gray.as_raw().len().max(1) as f64;
    if share_all < AMBIGUOUS_BORDER.0 {
        return true;
    }
    if share_all > AMBIGUOUS_BORDER.1 {
        return false;
    }
    let (dark, total) = border_counts(gray, |v| v <= level);
    dark * 2 <= total
}

/// Polarity for Sauvola, which is decided before thresholding because the formula is asymmetric:
/// the global Otsu split of the border when it is clear; otherwise (unevenly lit pages put both
/// sides on the border) the border is paper, so ink lies on the side of the mean away from it.
fn sauvola_dark_is_ink(gray: &GrayImage) -> bool {
    let level = otsu_level(gray.as_raw());
    let (dark, total) = border_counts(gray, |v| v <= level);
    let share = dark as f64 / total.max(1) as f64;
    if share < AMBIGUOUS_BORDER.0 {
        return true;
    }
    if share > AMBIGUOUS_BORDER.1 {
        return false;
    }
    let (border_sum, border_count) = border_sum(gray);
    let all: u64 = gray.as_raw().iter().map(|&v| v as u64).sum();
    let border_mean = border_sum as f64 / border_count.max(1) as f64;
    let mean = all as f64 / gray.as_raw().len().max(1) as f64;
    border_mean >= mean
}

/// Visits each pixel of the outermost ring once.
fn for_each_border(gray: &GrayImage, mut visit: impl FnMut(u8)) {
    let (w, h) = gray.dimensions();
    let row = |y: u32| &gray.as_raw()[(y * w) as usize..((y + 1) * w) as usize];
    for &v in row(0) {
        visit(v);
    }
    if h > 1 {
        for &v in row(h - 1) {
            visit(v);
        }
    }
    for y in 1..h.saturating_sub(1) {
        visit(row(y)[0]);
        if w > 1 {
            visit(row(y)[(w - 1) as usize]);
        }
    }
}

fn border_counts(gray: &GrayImage, dark: impl Fn(u8) -> bool) -> (usize, usize) {
    let (mut hits, mut total) = (0, 0);
    for_each_border(gray, |v| {
        hits += usize::from(dark(v));
        total += 1;
    });
    (hits, total)
}

fn border_sum(gray: &GrayImage) -> (u64, u64) {
    let (mut sum, mut count) = (0u64, 0u64);
    for_each_border(gray, |v| {
        sum += v as u64;
        count += 1;
    });
    (sum, count)
}

/// Sauvola's threshold `T = m (1 + k (s / R - 1))` over a `window` x `window` box clipped to the
/// image; ink where the (inverted, for light ink) value is `<= T`.
///
/// Window sums slide down the image as per-column sums over the window's rows, in `u64` (squared
/// sums overflow `u32` past ~66k pixels), so memory stays O(width) instead of two full integral
/// images.
fn sauvola(gray: &GrayImage, window: u32, k: f64, dark_ink: bool, ink: &mut [bool]) {
    let (w, h) = (gray.width() as usize, gray.height() as usize);
    let radius = (window / 2) as usize;
    let value = |x: usize, y: usize| -> u64 {
        let v = gray.as_raw()[y * w + x];
        (if dark_ink { v } else { 255 - v }) as u64
    };
    let mut column_sum = vec![0u64; w];
    let mut column_squares = vec![0u64; w];
    let add_row = |sum: &mut [u64], squares: &mut [u64], y: usize, sign_add: bool| {
        for x in 0..w {
            let v = value(x, y);
            if sign_add {
                sum[x] += v;
                squares[x] += v * v;
            } else {
                sum[x] -= v;
                squares[x] -= v * v;
            }
        }
    };
    for y in 0..radius.min(h) {
        add_row(&mut column_sum, &mut column_squares, y, true);
    }
    let mut prefix_sum = vec![0u64; w + 1];
    let mut prefix_squares = vec![0u64; w + 1];
    for y in 0..h {
        // Window rows are y - radius ..= y + radius, clipped.
        if y + radius < h {
            add_row(&mut column_sum, &mut column_squares, y + radius, true);
        }
        if y > radius {
            add_row(&mut column_sum, &mut column_squares, y - radius - 1, false);
        }
        let rows = (y + radius).min(h - 1) + 1 - y.saturating_sub(radius);
        for x in 0..w {
            prefix_sum[x + 1] = prefix_sum[x] + column_sum[x];
            prefix_squares[x + 1] = prefix_squares[x] + column_squares[x];
        }
        let out = &mut ink[y * w..(y + 1) * w];
        for (x, pixel) in out.iter_mut().enumerate() {
            let (x0, x1) = (x.saturating_sub(radius), (x + radius).min(w - 1) + 1);
            let count = ((x1 - x0) * rows) as f64;
            let sum = (prefix_sum[x1] - prefix_sum[x0]) as f64;
            let squares = (prefix_squares[x1] - prefix_squares[x0]) as f64;
            let mean = sum / count;
            let deviation = (squares / count - mean * mean).max(0.0).sqrt();
            let threshold = mean * (1.0 + k * (deviation / SAUVOLA_R - 1.0));
            *pixel = (value(x, y) as f64) <= threshold;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Luma;

    fn params(threshold: Threshold, polarity: Polarity) -> Params {
        Params {
            threshold,
            polarity,
            ..Params::default()
        }
    }

    /// Strokes (a cross and a box) on paper; `paper` and `ink` gray levels.
    fn drawing(paper: u8, ink: u8) -> (GrayImage, Vec<bool>) {
        let (w, h) = (60u32, 40u32);
        let mut truth = vec![false; (w * h) as usize];
        let mut img = GrayImage::from_pixel(w, h, Luma([paper]));
        for y in 0..h {
            for x in 0..w {
                let on = (18..22).contains(&y) && (5..55).contains(&x)
                    || (28..31).contains(&x) && (4..36).contains(&y);
                if on {
                    img.put_pixel(x, y, Luma([ink]));
                    truth[(y * w + x) as usize] = true;
                }
            }
        }
        (img, truth)
    }

    #[test]
    fn otsu_on_two_levels_matches_imageproc() {
        let (img, truth) = drawing(200, 50);
        let level = otsu_level(img.as_raw());
        assert!((50..200).contains(&level), "{level}");
        assert_eq!(level, imageproc::contrast::otsu_level(&img));
        let binary = binarize(&img, &Params::default()).unwrap();
        assert_eq!(binary.ink, truth);
    }

    #[test]
    fn polarity_both_ways() {
        let (dark_on_light, truth) = drawing(230, 20);
        let (light_on_dark, _) = drawing(20, 230);
        let auto = Params::default();
        assert_eq!(binarize(&dark_on_light, &auto).unwrap().ink, truth);
        assert_eq!(binarize(&light_on_dark, &auto).unwrap().ink, truth);
        // Forced polarity inverts.
        let forced = params(Threshold::Otsu, Polarity::LightInk);
        let inverted = binarize(&dark_on_light, &forced).unwrap();
        assert!(inverted.ink.iter().zip(&truth).all(|(a, b)| a != b));
        let forced = params(Threshold::Fixed { level: 128 }, Polarity::DarkInk);
        assert_eq!(binarize(&dark_on_light, &forced).unwrap().ink, truth);
    }

    #[test]
    fn ambiguous_border_takes_the_minority_side() {
        // Left half dark, right half light, a light blob in the dark half: border split 50/50,
        // dark is the majority overall, so the light side is ink.
        let mut img = GrayImage::from_fn(20, 20, |x, _| Luma([if x < 10 { 30 } else { 220 }]));
        for y in 0..20 {
            img.put_pixel(10, y, Luma([30]));
            img.put_pixel(11, y, Luma([30]));
        }
        let binary = binarize(&img, &Params::default()).unwrap();
        assert!(binary.count() < 200);
        assert!(binary.get(15, 5) && !binary.get(3, 5));
    }

    #[test]
    fn uniform_image_gives_empty_mask() {
        for threshold in [
            Threshold::Otsu,
            Threshold::Fixed { level: 255 },
            Threshold::Sauvola { window: 15, k: 0.2 },
        ] {
            let img = GrayImage::from_pixel(30, 20, Luma([17]));
            let binary = binarize(&img, &params(threshold, Polarity::DarkInk)).unwrap();
            assert_eq!(binary.count(), 0);
            assert_eq!((binary.width, binary.height), (30, 20));
        }
        let empty = GrayImage::new(0, 0);
        assert_eq!(binarize(&empty, &Params::default()).unwrap().count(), 0);
    }

    /// Lighting falls from 250 on the right to 90 on the left; strokes are 45% darker than the
    /// paper under them. A global threshold marks the dim side as ink; Sauvola finds the strokes.
    fn gradient_lit(light_strokes: bool) -> (GrayImage, Vec<bool>) {
        let (w, h) = (300u32, 200u32);
        let mut truth = vec![false; (w * h) as usize];
        let img = GrayImage::from_fn(w, h, |x, y| {
            let light = 90.0 + 160.0 * x as f64 / (w - 1) as f64;
            let on = (y % 40) >= 18 && (y % 40) < 22 || (x % 50) >= 23 && (x % 50) < 26;
            truth[(y * w + x) as usize] = on;
            let v = if light_strokes {
                if on {
                    light
                } else {
                    light * 0.4
                }
            } else if on {
                light * 0.55
            } else {
                light
            };
            Luma([v.round() as u8])
        });
        (img, truth)
    }

    fn agreement(found: &[bool], truth: &[bool]) -> (f64, f64) {
        let true_count = truth.iter().filter(|&&t| t).count() as f64;
        let found_count = found.iter().filter(|&&t| t).count() as f64;
        let hits = found.iter().zip(truth).filter(|(a, b)| **a && **b).count() as f64;
        (hits / true_count, hits / found_count.max(1.0))
    }

    #[test]
    fn sauvola_finds_strokes_under_uneven_light() {
        let sauvola = params(Threshold::Sauvola { window: 31, k: 0.2 }, Polarity::Auto);
        for light_strokes in [false, true] {
            let (img, truth) = gradient_lit(light_strokes);
            let binary = binarize(&img, &sauvola).unwrap();
            let (recall, precision) = agreement(&binary.ink, &truth);
            assert!(
                recall > 0.97 && precision > 0.97,
                "{light_strokes}: {recall} {precision}"
            );
            let otsu = binarize(&img, &Params::default()).unwrap();
            let (recall, precision) = agreement(&otsu.ink, &truth);
            assert!(
                recall < 0.9 || precision < 0.9,
                "Otsu should fail: {recall} {precision}"
            );
        }
    }
}
