//! Crotches and gaps the blur filled, opened again from the gray (docs/design.md, "The front
//! end"; `Params::valleys`).
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
//! valley pixels cleared. Bilevel images are left as they are (every ink pixel has the same
//! level, so none is a valley).

use rayon::prelude::*;

use super::evidence::Lighting;
use crate::GrayView;

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
    Local(&'a Lighting),
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
    let level = |v: u8| -> i32 {
        if dark_ink {
            255 - i32::from(v)
        } else {
            i32::from(v)
        }
    };
    let rows: Vec<&[u8]> = gray.rows().collect();
    let mut dark = vec![0i32; w * h];
    dark.par_chunks_mut(w).enumerate().for_each(|(y, out)| {
        let (ya, yb) = (y.saturating_sub(1), (y + 1).min(h - 1));
        for (x, o) in out.iter_mut().enumerate() {
            let (xa, xb) = (x.saturating_sub(1), (x + 1).min(w - 1));
            let row = |r: &[u8]| level(r[xa]) + 2 * level(r[x]) + level(r[xb]);
            *o = row(rows[ya]) + 2 * row(rows[y]) + row(rows[yb]);
        }
    });
    // Sides at distance 1 and 2 across the pixel, in four directions.
    const STEPS: [(i64, i64); 8] = [
        (1, 0),
        (0, 1),
        (1, 1),
        (1, -1),
        (2, 0),
        (0, 2),
        (2, 2),
        (2, -2),
    ];
    let candidate: Vec<bool> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let ink = &ink[y * w..(y + 1) * w];
            let dark = &dark;
            // The threshold along the row as a darkness, 16 times the level (ink is darker than
            // or equal to a dark-ink threshold, lighter than a light-ink one).
            let thresholds: Vec<i32> = match threshold {
                Level::Global(t) => vec![f64::from(*t); w],
                Level::Local(lighting) => lighting.row(y, w).collect(),
            }
            .into_iter()
            .map(|t| {
                let t = if dark_ink { 255.0 - t } else { t + 0.5 };
                (16.0 * t).round() as i32
            })
            .collect();
            (0..w).map(move |x| {
                if !ink[x] || x < 2 || y < 2 || x + 2 >= w || y + 2 >= h {
                    return false;
                }
                let at = |dx: i64, dy: i64| {
                    dark[(y as i64 + dy) as usize * w + (x as i64 + dx) as usize]
                };
                let (here, t) = (at(0, 0), thresholds[x]);
                STEPS.iter().any(|&(dx, dy)| {
                    let sides = at(dx, dy).min(at(-dx, -dy)) - t;
                    // Two pixels out, the pixels between must not be lighter: the valley's
                    // bottom is here, not beside it (the edge of a stroke next to a gap).
                    let (ix, iy) = (dx.signum(), dy.signum());
                    let between = if dx.abs() == 2 || dy.abs() == 2 {
                        at(ix, iy).min(at(-ix, -iy))
                    } else {
                        i32::MAX
                    };
                    sides >= 16 * MIN_SIDES
                        && 100 * (here - t) < NEAR_THRESHOLD * sides
                        && 8 * (between - here) >= -sides
                })
            })
        })
        .collect();
    // Only valleys that reach the paper through valleys open: a crotch or a gap runs out into
    // the paper around it, while a noise dip inside a bold stroke is ink all round (opening it
    // would punch a hole the ink does not have). What opens joins paper that is there, so no
    // new hole is ever made.
    let mut queue: Vec<usize> = (0..w * h)
        .filter(|&i| {
            candidate[i] && {
                let (x, y) = (i % w, i / w);
                neighbours(x, y, w, h).any(|j| !ink[j])
            }
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
    let (x0, x1, y0, y1) = (x.saturating_sub(1), (x + 1).min(w - 1), y.saturating_sub(1), (y + 1).min(h - 1));
    (y0..=y1)
        .flat_map(move |ny| (x0..=x1).map(move |nx| (nx, ny)))
        .filter(move |&(nx, ny)| (nx, ny) != (x, y))
        .map(move |(nx, ny)| ny * w + nx)
}
