//! Crotches and gaps the blur filled, opened again from the gray (docs/design.md, "The front
//! end"; `FrontEndParams::valleys`).
//!
//! A blurred capture adds the tails of two strokes where they come close: in the acute angle
//! between two arms of a junction, and in a gap narrower than the blur, the gray gets darker
//! than halfway and the threshold takes the crotch or the gap for ink. The junction the tracer
//! then finds slides into the filled crotch (§3.2's non-linear region and the skeleton's branch
//! point both move with the ink), and close strokes merge. The gray still shows what happened:
//! such a pixel is *lighter* than the ink on both sides of it, a valley between two ridges of
//! darkness, which no pixel of one stroke is (across a stroke the darkness rises to its middle
//! and falls; along it, it stays level). Those pixels go back to the paper.
//!
//! In: the gray image, the ink's polarity and the thresholded mask. Out: the mask with the
//! valley pixels cleared, the same whatever the thread count (what opens is a set, reached by a
//! flood). Bilevel images are not given to it (binarization skips them: their ink has one
//! level, and the smoothing alone would make every sharp crotch a valley).

use rayon::prelude::*;

use super::evidence::Surface;
use crate::gray::GrayView;

/// A valley's sides are at least this many gray levels past the threshold into the ink: less is
/// within the noise of a stroke's edge (on the degraded captures 24-32 measure alike, 40 and 16
/// worse; docs/design.md, "The front end").
const MIN_SIDES: i32 = 28;
/// A valley is nearer the threshold than this share of the way from the threshold to its
/// sides' ink (percent), so at least a quarter of that way lighter than both. The edge of a
/// real concave corner (the inside of a V's apex), which the blur also leaves lighter than the
/// two arms, is deeper in the ink; 50 opens too little of a filled crotch, 90 notches such
/// corners into spurs.
const NEAR_THRESHOLD: i32 = 75;

/// The threshold the mask was made with.
pub(crate) enum Level<'a> {
    /// One global gray level (Otsu's).
    Global(u8),
    /// The local threshold surface.
    Local(Surface<'a>),
}

/// Clears the pixels of `ink` (row-major, the size of `gray`) that the gray shows lighter than
/// ink on both sides of them and near the `threshold` (the module doc), where they reach the
/// paper through such pixels; every pixel is decided from the mask as it came.
pub(crate) fn open(gray: GrayView<'_>, dark_ink: bool, threshold: &Level<'_>, ink: &mut [bool]) {
    let (w, h) = (gray.width() as usize, gray.height() as usize);
    if w < 5 || h < 5 {
        return;
    }
    // Darkness (ink high whatever the polarity), 16 times the level, smoothed by [1 2 1] x
    // [1 2 1] against the noise.
    let level: [u16; 256] =
        std::array::from_fn(|v| if dark_ink { 255 - v as u16 } else { v as u16 });
    // Separably: [1 2 1] along each row, then down each column.
    let mut across = vec![0u16; w * h];
    across
        .par_chunks_mut(w)
        .zip(gray.par_rows(1))
        .for_each(|(out, row)| {
            for (x, o) in out.iter_mut().enumerate() {
                let (xa, xb) = (x.saturating_sub(1), (x + 1).min(w - 1));
                *o = level[row[xa] as usize] + 2 * level[row[x] as usize] + level[row[xb] as usize];
            }
        });
    let mut dark = vec![0u16; w * h];
    dark.par_chunks_mut(w).enumerate().for_each(|(y, out)| {
        let (ya, yb) = (y.saturating_sub(1), (y + 1).min(h - 1));
        let (above, here, below) = (
            &across[ya * w..(ya + 1) * w],
            &across[y * w..(y + 1) * w],
            &across[yb * w..(yb + 1) * w],
        );
        for (x, o) in out.iter_mut().enumerate() {
            *o = above[x] + 2 * here[x] + below[x];
        }
    });
    drop(across);
    // Sides two pixels out across the pixel, in four directions (sides one pixel out measure
    // worse: docs/design.md, "The front end").
    const STEPS: [(i64, i64); 4] = [(2, 0), (0, 2), (2, 2), (2, -2)];
    // The threshold as a darkness, 16 times the level (ink is darker than or equal to a
    // dark-ink threshold, lighter than a light-ink one).
    let as_darkness = |t: f64| -> i32 {
        let t = if dark_ink { 255.0 - t } else { t + 0.5 };
        (16.0 * t).round() as i32
    };
    let global = match threshold {
        Level::Global(t) => as_darkness(f64::from(*t)),
        Level::Local(_) => 0,
    };
    let mut candidate = vec![false; w * h];
    candidate
        .par_chunks_mut(w)
        .enumerate()
        .skip(2)
        .take(h - 4)
        .for_each(|(y, out)| {
            let row_ink = &ink[y * w..(y + 1) * w];
            if !row_ink[2..w - 2].iter().any(|&i| i) {
                return;
            }
            // One global level is one darkness; the local surface's row is read once.
            let local: Vec<i32> = match threshold {
                Level::Global(_) => Vec::new(),
                Level::Local(surface) => surface.row(y).map(as_darkness).collect(),
            };
            let threshold_at = |x: usize| match threshold {
                Level::Global(_) => global,
                Level::Local(_) => local[x],
            };
            let at = |x: usize, dx: i64, dy: i64| {
                i32::from(dark[(y as i64 + dy) as usize * w + (x as i64 + dx) as usize])
            };
            for x in (2..w - 2).filter(|&x| row_ink[x]) {
                let (here, t) = (at(x, 0, 0), threshold_at(x));
                // No side is darker than full ink: a pixel that deep in the ink is no valley
                // (most of a stroke's pixels, decided without reading their neighbours).
                if 100 * (here - t) >= NEAR_THRESHOLD * (16 * 255 - t) {
                    continue;
                }
                out[x] = STEPS.iter().any(|&(dx, dy)| {
                    let sides = at(x, dx, dy).min(at(x, -dx, -dy)) - t;
                    // The pixels between must not be lighter: the valley's bottom is here,
                    // not beside it (the edge of a stroke next to a gap).
                    let (ix, iy) = (dx.signum(), dy.signum());
                    let between = at(x, ix, iy).min(at(x, -ix, -iy));
                    sides >= 16 * MIN_SIDES
                        && 100 * (here - t) < NEAR_THRESHOLD * sides
                        && 8 * (between - here) >= -sides
                });
            }
        });
    // Only valleys that reach the paper through valleys open: a crotch or a gap runs out into
    // the paper around it, while a noise dip inside a bold stroke is ink all round (opening it
    // would punch a hole the ink does not have). What opens joins paper that is there, so no
    // new hole is ever made.
    let mut queue: Vec<usize> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let (candidate, ink) = (&candidate, &*ink);
            (0..w)
                .filter(move |&x| candidate[y * w + x])
                .filter(move |&x| neighbours(x, y, w, h).any(|j| !ink[j]))
                .map(move |x| y * w + x)
        })
        .collect();
    let mut opened = vec![false; w * h];
    for &i in &queue {
        opened[i] = true;
    }
    while let Some(i) = queue.pop() {
        for j in neighbours(i % w, i / w, w, h) {
            if candidate[j] && !opened[j] {
                opened[j] = true;
                queue.push(j);
            }
        }
    }
    for (o, ink) in opened.iter().zip(ink.iter_mut()) {
        if *o {
            *ink = false;
        }
    }
}

/// The 8 neighbours of pixel `(x, y)` inside a `w` x `h` image, as indices.
fn neighbours(x: usize, y: usize, w: usize, h: usize) -> impl Iterator<Item = usize> {
    let (x0, x1, y0, y1) = (
        x.saturating_sub(1),
        (x + 1).min(w - 1),
        y.saturating_sub(1),
        (y + 1).min(h - 1),
    );
    (y0..=y1)
        .flat_map(move |ny| (x0..=x1).map(move |nx| (nx, ny)))
        .filter(move |&(nx, ny)| (nx, ny) != (x, y))
        .map(move |(nx, ny)| ny * w + nx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::GrayImage;
    use image::Luma;

    /// `ink` (row-major, `w` x `h`) drawn dark on light paper and blurred by a Gaussian of
    /// `sigma` px, as a camera or a poor scan would.
    fn blurred(ink: &[bool], w: u32, h: u32, sigma: f32) -> GrayImage {
        let sharp = GrayImage::from_fn(w, h, |x, y| {
            Luma([if ink[(y * w + x) as usize] { 30 } else { 220 }])
        });
        imageproc::filter::gaussian_blur_f32(&sharp, sigma)
    }

    fn dark_of(gray: &GrayImage, level: u8) -> Vec<bool> {
        gray.pixels().map(|p| p.0[0] <= level).collect()
    }

    /// Two 3 px arms from one point, 20° apart (a junction's acute crotch).
    fn crotch(w: u32, h: u32) -> Vec<bool> {
        let (ox, oy) = (6.0, h as f64 / 2.0);
        let arms = [(-10f64).to_radians(), 10f64.to_radians()];
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64 + 0.5 - ox, (i / w) as f64 + 0.5 - oy);
                arms.iter().any(|a| {
                    let along = x * a.cos() + y * a.sin();
                    let across = -x * a.sin() + y * a.cos();
                    along >= 0.0 && across.abs() <= 1.5
                })
            })
            .collect()
    }

    #[test]
    fn a_crotch_the_blur_filled_opens_back_to_its_ink() {
        let (w, h) = (60u32, 30u32);
        let truth = crotch(w, h);
        let gray = blurred(&truth, w, h, 1.1);
        let level = 125;
        let mut ink = dark_of(&gray, level);
        let extra = |ink: &[bool]| (0..ink.len()).filter(|&i| ink[i] && !truth[i]).count();
        let lost = |ink: &[bool]| (0..ink.len()).filter(|&i| !ink[i] && truth[i]).count();
        let (extra_before, lost_before) = (extra(&ink), lost(&ink));
        open((&gray).into(), true, &Level::Global(level), &mut ink);
        // The filled part of the crotch is paper again, and the arms keep their ink.
        assert!(
            extra(&ink) * 2 < extra_before,
            "ink off the arms: {extra_before} before, {} after",
            extra(&ink)
        );
        assert!(
            lost(&ink) <= lost_before + 2,
            "arm pixels lost: {}",
            lost(&ink)
        );
    }

    #[test]
    fn two_strokes_the_blur_joined_come_apart() {
        let (w, h) = (50u32, 20u32);
        // Two bars 3 px thick, 1 px apart.
        let truth: Vec<bool> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                (5..45).contains(&x) && ((6..9).contains(&y) || (10..13).contains(&y))
            })
            .collect();
        let gray = blurred(&truth, w, h, 0.9);
        let level = 125;
        let mut ink = dark_of(&gray, level);
        let gap = |ink: &[bool]| (8..42).filter(|&x| ink[(9 * w + x) as usize]).count();
        assert!(gap(&ink) > 30, "the blur joins the bars: {}", gap(&ink));
        open((&gray).into(), true, &Level::Global(level), &mut ink);
        assert_eq!(gap(&ink), 0, "the gap's row is paper again");
        let bars = (0..ink.len()).filter(|&i| ink[i] && truth[i]).count();
        assert!(bars * 100 >= 97 * truth.iter().filter(|&&t| t).count());
    }

    #[test]
    fn one_stroke_noise_and_bilevel_ink_stay() {
        let (w, h) = (40u32, 40u32);
        // A bold bar 12 px wide under noise, light ink on a dark ground: nothing inside it is
        // a valley reaching the paper.
        let mut lcg = crate::synth::lcg(12345u64);
        let mut noise = move || ((lcg() >> 33) % 21) as i32 - 10;
        let bar = |x: u32| (14..26).contains(&x);
        let noisy = GrayImage::from_fn(w, h, |x, _| {
            let v = if bar(x) { 220 } else { 40 };
            Luma([(v + noise()).clamp(0, 255) as u8])
        });
        let gray = imageproc::filter::gaussian_blur_f32(&noisy, 0.8);
        let mut ink: Vec<bool> = gray.pixels().map(|p| p.0[0] > 130).collect();
        let before = ink.clone();
        open((&gray).into(), false, &Level::Global(130), &mut ink);
        assert_eq!(ink, before);
        // A bilevel drawing of a crotch is left as it is: every ink pixel has the same level
        // (the smoothed darkness alone would call its crotch a valley).
        let truth = crotch(60, 30);
        let sharp = GrayImage::from_fn(60, 30, |x, y| {
            Luma([if truth[(y * 60 + x) as usize] { 0 } else { 255 }])
        });
        let binary =
            crate::raster::binarize(&sharp, &crate::params::Params::default()).expect("binarized");
        assert_eq!(binary.ink, truth);
    }
}
