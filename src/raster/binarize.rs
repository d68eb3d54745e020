//! Binarization: grayscale to the foreground mask, with the threshold method and ink polarity of
//! [`Params`], and a record of what was decided (docs/design.md, "The front end").
//!
//! Polarity matters as much as the level: text is dark ink on light paper, fingerprint ridges are
//! sometimes light on a dark background. `Auto` decides from stroke evidence (ink is the thinner
//! side, paper fills the border; [`super::evidence::polarity`]). The automatic threshold is
//! Otsu's global level where it separates ink from paper all over the image, and the local
//! threshold where the light or the contrast varies ([`super::evidence::lighting`]).

use rayon::prelude::*;

use super::evidence::{self, PolarityEvidence};
use super::grounds;
use super::regions;
use super::valleys;
use crate::binary::Binary;
use crate::decisions::{Decisions, InkSide, ThresholdUsed, UNEVEN_LIGHT};
use crate::error::Result;
use crate::gray::GrayView;
use crate::params::{Params, Polarity, Threshold};

/// Sauvola's dynamic range of the standard deviation `R` for 8-bit images.
const SAUVOLA_R: f64 = 128.0;

/// Binarizes a grayscale image, ink `true` (a uniform image gives an empty mask), and says what
/// was decided.
pub(crate) fn binarize_deciding(
    gray: GrayView<'_>,
    params: &Params,
) -> Result<(Binary, Decisions)> {
    binarize_until(gray, params, false)
}

/// The polarity [`binarize_deciding`] decides (`polarity`, `polarity_confidence` and the stroke
/// width of the [`Decisions`]), without the steps after it that only shape its binary: a print's
/// decision (its only caller), its chords read on a sparser lattice
/// (`evidence::PRINT_LATTICE_SAMPLES`).
pub(crate) fn decide_polarity(gray: GrayView<'_>, params: &Params) -> Result<Decisions> {
    Ok(binarize_until(gray, params, true)?.1)
}

fn binarize_until(
    gray: GrayView<'_>,
    params: &Params,
    polarity_only: bool,
) -> Result<(Binary, Decisions)> {
    let (width, height) = gray.dimensions();
    let (w, h) = (width as usize, height as usize);
    let mut binary = Binary::new(width, height);
    let forced = match params.front_end.polarity {
        Polarity::Auto => None,
        Polarity::DarkInk => Some(true),
        Polarity::LightInk => Some(false),
    };
    let mut decisions = Decisions {
        polarity: InkSide::of(forced != Some(false)),
        polarity_confidence: None,
        threshold: ThresholdUsed::Uniform,
        stroke_width: 0.0,
        uneven_light: 0.0,
        dropout: None,
        dropout_share: None,
        reversed_grounds: Vec::new(),
        regions: Vec::new(),
        print: None,
    };
    // One pass gives the range and Otsu's level (a page is tens of MB of pixels; the histogram is
    // built per block in parallel and summed: integer counts, so the sum does not depend on the
    // thread count).
    let histogram = histogram(gray);
    let (Some(min), Some(max)) = (
        histogram.iter().position(|&c| c > 0),
        histogram.iter().rposition(|&c| c > 0),
    ) else {
        return Ok((binary, decisions));
    };
    if min == max {
        return Ok((binary, decisions));
    }
    let level = match params.front_end.threshold {
        Threshold::Fixed { level } => level,
        _ => otsu_level_of(&histogram, w * h),
    };
    // The dark side of the global level, then (automatic or local threshold) of the local one
    // where the global level fails.
    let mut dark = binary.ink;
    split(gray, &mut dark, move |v| v <= level);
    // A print's decision alone reads a sparser lattice (`evidence::PRINT_LATTICE_SAMPLES`).
    let lattice = if polarity_only {
        evidence::PRINT_LATTICE_SAMPLES
    } else {
        evidence::LATTICE_SAMPLES
    };
    let mut evidence = evidence::polarity(&dark, w, h, lattice);
    decisions.threshold = match params.front_end.threshold {
        Threshold::Fixed { level } => ThresholdUsed::Fixed { level },
        _ => ThresholdUsed::Otsu { level },
    };
    // The local threshold's lighting, where it is the one used.
    let mut local = None;
    // Sauvola's polarity is decided on the split the automatic threshold would make.
    if !matches!(
        params.front_end.threshold,
        Threshold::Otsu | Threshold::Fixed { .. }
    ) {
        let dark_ink = forced.unwrap_or(evidence.dark_is_ink);
        if let Some(lighting) = evidence::lighting(gray, evidence.thinner_width, dark_ink) {
            // Where the two splits differ on more than a share of the ink, one global level
            // does not fit the image (counted against each block's own threshold, a read-only
            // pass; the interpolated local split is only made when it is used).
            let (differ, local_dark_count) = evidence::disagreement(gray, &lighting, level);
            let ink = local_dark_count.min(dark.len() - local_dark_count).max(1);
            decisions.uneven_light = differ as f64 / ink as f64;
            // A global level that reaches some paper block's own levels specks (or, between
            // close strokes, bridges) that paper however little of the ink it moves.
            if params.front_end.threshold == Threshold::Local
                || decisions.uneven_light > UNEVEN_LIGHT
                || evidence::level_reaches_paper(&lighting, level, dark_ink)
            {
                evidence::local_dark(gray, &lighting, &mut dark);
                evidence = evidence::polarity(&dark, w, h, lattice);
                // The global split misjudged the stroke width where it failed; the blocks are
                // sized again from the local split's (blocks of the same side measure the same
                // lighting again: it is kept without measuring it).
                let block = evidence::lighting_block(gray, evidence.thinner_width);
                let again = (block != lighting.block)
                    .then(|| evidence::lighting(gray, evidence.thinner_width, dark_ink))
                    .flatten();
                let lighting = match again {
                    Some(again) => {
                        evidence::local_dark(gray, &again, &mut dark);
                        evidence = evidence::polarity(&dark, w, h, lattice);
                        again
                    }
                    None => lighting,
                };
                decisions.threshold = ThresholdUsed::Local {
                    window: lighting.block as u32,
                };
                local = Some(lighting);
            }
        }
    }
    let dark_ink = forced.unwrap_or(evidence.dark_is_ink);
    record_polarity(&mut decisions, dark_ink, forced.is_none(), &evidence);
    if polarity_only {
        binary.ink = dark;
        return Ok((binary, decisions));
    }
    if let Threshold::Sauvola { window, k } = params.front_end.threshold {
        sauvola(gray, window, k, dark_ink, &mut dark);
        decisions.threshold = ThresholdUsed::Sauvola { window, k };
    } else if !dark_ink {
        dark.par_iter_mut().for_each(|v| *v = !*v);
    }
    // A bilevel image has no valley (every ink pixel has the same level).
    let gray_levels = histogram[min + 1..max].iter().any(|&c| c > 0);
    if params.front_end.valleys
        && gray_levels
        && matches!(
            params.front_end.threshold,
            Threshold::Auto | Threshold::Otsu | Threshold::Local
        )
    {
        let threshold = match &local {
            Some(lighting) => valleys::Level::Local(lighting.surface(w)),
            None => valleys::Level::Global(level),
        };
        valleys::open(gray, dark_ink, &threshold, &mut dark);
    }
    if params.front_end.reverse_grounds && forced.is_none() {
        decisions.reversed_grounds = grounds::reverse(&mut dark, w, h);
        if !decisions.reversed_grounds.is_empty() {
            // The ink is another now: its strokes' width, not the grounds'.
            decisions.stroke_width = evidence::chords(&dark, w, h).dark_mode;
        }
    }
    decisions.regions = regions::find(
        gray,
        &histogram,
        &mut dark,
        dark_ink,
        level,
        decisions.stroke_width,
        &decisions.reversed_grounds,
        &params.front_end.keep_regions,
    );
    binary.ink = dark;
    Ok((binary, decisions))
}

fn record_polarity(
    decisions: &mut Decisions,
    dark_ink: bool,
    automatic: bool,
    evidence: &PolarityEvidence,
) {
    decisions.polarity = InkSide::of(dark_ink);
    decisions.polarity_confidence = automatic.then_some(evidence.confidence);
    decisions.stroke_width = if dark_ink == evidence.dark_is_ink {
        evidence.stroke_width
    } else {
        evidence.other_width
    };
}

/// Sets `out[y * width + x] = is_dark(gray.row(y)[x])`, in parallel blocks of rows.
fn split(gray: GrayView<'_>, out: &mut [bool], is_dark: impl Fn(u8) -> bool + Sync) {
    let width = gray.width() as usize;
    if width == 0 {
        return;
    }
    out.par_chunks_mut(width)
        .zip(gray.par_rows(BLOCK))
        .for_each(|(out, values)| {
            for (o, &v) in out.iter_mut().zip(values) {
                *o = is_dark(v);
            }
        });
}

/// Pixels per parallel block of the whole-image passes.
const BLOCK: usize = 1 << 16;

/// The 256-bin histogram of `gray`'s pixels.
pub(super) fn histogram(gray: GrayView<'_>) -> [u64; 256] {
    gray.par_rows(BLOCK)
        .fold(
            // On the heap: the fold hands its tables from row to row, and 8 KB by value were
            // copied at each row (docs/performance.md).
            || vec![[0u64; 256]; 4],
            |mut tables, row| {
                // Four tables in turn, summed at the end: on a page of two levels nearly every
                // pixel adds to the same bin, and each addition waited for the one before it.
                let mut quads = row.chunks_exact(4);
                for quad in &mut quads {
                    for (table, &v) in tables.iter_mut().zip(quad) {
                        table[v as usize] += 1;
                    }
                }
                for &v in quads.remainder() {
                    tables[0][v as usize] += 1;
                }
                tables
            },
        )
        .map(|tables| {
            let mut counts = [0u64; 256];
            for table in tables.iter() {
                for (count, &n) in counts.iter_mut().zip(table) {
                    *count += n;
                }
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
#[cfg(test)]
pub fn otsu_level(pixels: &[u8]) -> u8 {
    let view = GrayView::new(pixels, pixels.len() as u32, 1, pixels.len()).expect("one row");
    otsu_level_of(&histogram(view), pixels.len())
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

/// Sauvola's threshold `T = m (1 + k (s / R - 1))` over a `window` x `window` box clipped to the
/// image; ink where the (inverted, for light ink) value is `<= T`.
///
/// Window sums slide down the image as per-column sums over the window's rows, in `u64` (squared
/// sums overflow `u32` past ~66k pixels), so memory stays O(width) instead of two full integral
/// images.
fn sauvola(gray: GrayView<'_>, window: u32, k: f64, dark_ink: bool, ink: &mut [bool]) {
    let (w, h) = (gray.width() as usize, gray.height() as usize);
    let radius = (window / 2) as usize;
    let value = |x: usize, y: usize| -> u64 {
        let v = gray.row(y)[x];
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
    use crate::raster::binarize;
    use image::GrayImage;
    use image::Luma;

    #[test]
    fn the_histogram_by_four_tables_counts_every_pixel() {
        // Widths that leave 0 to 3 pixels after the groups of four, rows padded by a stride,
        // two-level, few-level and random images.
        let mut lcg = crate::synth::lcg(31u64);
        let mut next = move || (lcg() >> 33) as usize;
        for case in 0..60 {
            let (w, h) = (1 + next() % 70, 1 + next() % 40);
            let stride = w + next() % 5;
            let levels = [2, 3, 256][case % 3];
            let pixels: Vec<u8> = (0..stride * h)
                .map(|_| ((next() % levels) * 255 / (levels - 1)) as u8)
                .collect();
            let view = GrayView::new(&pixels, w as u32, h as u32, stride).expect("a view");
            let mut expected = [0u64; 256];
            for y in 0..h {
                for &v in &pixels[y * stride..y * stride + w] {
                    expected[v as usize] += 1;
                }
            }
            assert_eq!(histogram(view), expected, "case {case}");
        }
    }

    fn params(threshold: Threshold, polarity: Polarity) -> Params {
        let mut params = Params::default();
        params.front_end.threshold = threshold;
        params.front_end.polarity = polarity;
        params
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
            let otsu = binarize(&img, &params(Threshold::Otsu, Polarity::Auto)).unwrap();
            let (recall, precision) = agreement(&otsu.ink, &truth);
            assert!(
                recall < 0.9 || precision < 0.9,
                "Otsu should fail: {recall} {precision}"
            );
        }
    }

    #[test]
    fn automatic_threshold_goes_local_under_uneven_light_and_finds_the_polarity() {
        for light_strokes in [false, true] {
            let (img, truth) = gradient_lit(light_strokes);
            let (binary, decisions) = binarize_deciding((&img).into(), &Params::default()).unwrap();
            let (recall, precision) = agreement(&binary.ink, &truth);
            assert!(
                recall > 0.97 && precision > 0.97,
                "{light_strokes}: {recall} {precision}"
            );
            assert!(
                matches!(decisions.threshold, ThresholdUsed::Local { .. }),
                "{decisions:?}"
            );
            assert!(decisions.uneven_light > UNEVEN_LIGHT);
            assert_eq!(decisions.polarity, InkSide::of(!light_strokes));
            assert!(
                decisions.polarity_confidence.unwrap() > 0.5,
                "{decisions:?}"
            );
            // The stroke widths drawn are 3 and 4 px.
            assert!(
                (2.0..=5.0).contains(&decisions.stroke_width),
                "{decisions:?}"
            );
        }
    }

    /// Even light with strokes on the right, and a small dim patch of blank paper in the left
    /// corner that falls past Otsu's level: too little to move a tenth of the ink, enough to
    /// speck the paper there.
    fn dim_corner() -> (GrayImage, Vec<bool>) {
        let (w, h) = (240u32, 160u32);
        let mut truth = vec![false; (w * h) as usize];
        let img = GrayImage::from_fn(w, h, |x, y| {
            let on = x >= 120 && (x % 24) < 3;
            truth[(y * w + x) as usize] = on;
            // Deterministic noise of +-6 levels.
            let noise = ((x * 7919 + y * 104_729) % 13) as f64 - 6.0;
            let reach = (1.0 - f64::from(x * x + y * y).sqrt() / 60.0).max(0.0);
            let paper = 220.0 - 100.0 * reach;
            Luma([(if on { 40.0 } else { paper } + noise).round() as u8])
        });
        (img, truth)
    }

    #[test]
    fn a_dim_patch_of_paper_makes_the_threshold_local_and_stays_paper() {
        let (img, truth) = dim_corner();
        let corner_ink = |ink: &[bool]| {
            (0..30)
                .flat_map(|y| (0..30).map(move |x| y * 240 + x))
                .filter(|&i| ink[i])
                .count()
        };
        let otsu = binarize(&img, &params(Threshold::Otsu, Polarity::Auto)).unwrap();
        assert!(corner_ink(&otsu.ink) > 10, "{}", corner_ink(&otsu.ink));
        let (binary, decisions) = binarize_deciding((&img).into(), &Params::default()).unwrap();
        assert!(decisions.uneven_light < UNEVEN_LIGHT, "{decisions:?}");
        assert!(
            matches!(decisions.threshold, ThresholdUsed::Local { .. }),
            "{decisions:?}"
        );
        assert_eq!(corner_ink(&binary.ink), 0);
        let (recall, precision) = agreement(&binary.ink, &truth);
        assert!(recall > 0.99 && precision > 0.99, "{recall} {precision}");
    }

    #[test]
    fn even_light_keeps_otsu_and_forced_polarity_has_no_confidence() {
        let (img, truth) = drawing(230, 20);
        let (binary, decisions) = binarize_deciding((&img).into(), &Params::default()).unwrap();
        assert_eq!(binary.ink, truth);
        assert!(
            matches!(decisions.threshold, ThresholdUsed::Otsu { .. }),
            "{decisions:?}"
        );
        assert!(decisions.uneven_light < UNEVEN_LIGHT);
        let forced = params(Threshold::Auto, Polarity::DarkInk);
        let (_, decisions) = binarize_deciding((&img).into(), &forced).unwrap();
        assert_eq!(
            (decisions.polarity, decisions.polarity_confidence),
            (InkSide::Dark, None)
        );
    }

    /// A dark banner with three light bars in it above dark strokes on light paper.
    fn banner() -> (GrayImage, Vec<bool>) {
        let (w, h) = (240u32, 160u32);
        let mut img = GrayImage::from_pixel(w, h, Luma([230]));
        let mut truth = vec![false; (w * h) as usize];
        let inside = |x: u32, y: u32, (x0, y0, rw, rh): (u32, u32, u32, u32)| {
            (x0..x0 + rw).contains(&x) && (y0..y0 + rh).contains(&y)
        };
        let bars = [(40, 20, 5, 40), (100, 20, 5, 40), (140, 38, 50, 5)];
        let strokes = [(40, 110, 4, 40), (60, 128, 120, 4)];
        for y in 0..h {
            for x in 0..w {
                let level = if bars.iter().any(|&b| inside(x, y, b)) {
                    truth[(y * w + x) as usize] = true;
                    235
                } else if inside(x, y, (10, 10, 220, 60)) {
                    30
                } else if strokes.iter().any(|&s| inside(x, y, s)) {
                    truth[(y * w + x) as usize] = true;
                    25
                } else {
                    230
                };
                img.put_pixel(x, y, Luma([level]));
            }
        }
        (img, truth)
    }

    #[test]
    fn light_strokes_on_a_dark_banner_are_the_ink_and_are_recorded() {
        let (img, truth) = banner();
        let (binary, decisions) = binarize_deciding((&img).into(), &Params::default()).unwrap();
        assert_eq!(decisions.polarity, InkSide::Dark);
        assert_eq!(binary.ink, truth);
        assert_eq!(decisions.reversed_grounds.len(), 1, "{decisions:?}");
        // Without the rule, or with the polarity forced, the banner is ink.
        let mut without = Params::default();
        without.front_end.reverse_grounds = false;
        for params in [without, params(Threshold::Auto, Polarity::DarkInk)] {
            let (binary, decisions) = binarize_deciding((&img).into(), &params).unwrap();
            assert!(decisions.reversed_grounds.is_empty());
            assert!(binary.ink[15 * 240 + 15], "the banner stays ink");
        }
    }
}
