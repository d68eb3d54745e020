//! Polarity per region (docs/design.md, "The front end"): a thick field of ink holding light
//! strokes, such as white letters on a dark banner of a dark-on-light page, is a ground, not ink.
//! Its pixels go to the paper and the strokes it encloses become the ink.
//!
//! A ground is told from a bold stroke, a dense character, a photo or a print's merged ridges by
//! the holes it encloses (light regions, 4-connected, that reach nothing but it):
//!
//! - at least [`MIN_HOLES`] of them are clearly strokes: at least [`MIN_HOLE_CHORD`] px wide (the
//!   median chord of their pixels, the shorter of the horizontal and vertical runs as in
//!   [`super::evidence::chords`]) and at least [`HOLE_ELONGATION`] times their squared chord in
//!   area, where a pore, a pinhole or a crack is not;
//! - the field's own median chord is at least [`GROUND_TO_STROKE`] times theirs: a character's
//!   counters and a print's valleys are about as wide as its strokes or ridges;
//! - they hold at least [`MIN_HOLE_SHARE`] of the field's area and at most all of it: a scanner's
//!   frame or a photo encloses a few stray light specks, not text, and a frame around a page is
//!   smaller than the page it encloses.
//!
//! A ground's pixels go to the paper; every hole of it that is a stroke, even a thinner or
//! shorter one ([`MIN_REVERSED_CHORD`]), is reversed (its light pixels become ink, the ink
//! inside it, a letter's counters, becomes paper); its other holes stay paper. Ink strokes that
//! touch the ground go with it.

use crate::mask::{label_components, on_image_edge, Connectivity};
use rayon::prelude::*;

use super::evidence::run_lengths;
use super::points::next_ink;
use crate::decisions::Ground;
use crate::median::upper_median_by;

/// The narrowest hole that shows a ground, px: thinner light lines are as often cracks, pores
/// and noise as strokes.
const MIN_HOLE_CHORD: u32 = 3;
/// A hole that shows a ground is at least this many times its squared chord in area (a stroke
/// six widths long).
const HOLE_ELONGATION: f64 = 6.0;
/// How many times wider than the holes that show it a ground's median chord is at least.
const GROUND_TO_STROKE: f64 = 6.0;
/// The narrowest ground, px: [`GROUND_TO_STROKE`] times [`MIN_HOLE_CHORD`].
const MIN_GROUND_CHORD: u32 = 18;
/// The smallest ground, pixels.
const MIN_GROUND_AREA: usize = 1024;
/// The holes that show a ground hold at least this share of its area, and at most all of it
/// (a ground is the larger field, like paper).
const MIN_HOLE_SHARE: f64 = 0.03;
/// A ground shows itself by at least this many holes.
const MIN_HOLES: usize = 2;
/// Once a field is a ground, every hole it encloses at least this wide, px, and at least
/// [`REVERSED_ELONGATION`] times its squared chord in area, is reversed: small letters and
/// digits on a banner are thinner than its large ones, and a character's dots are short, but a
/// round or square pinhole is under 1.5 squared chords.
const MIN_REVERSED_CHORD: u32 = 2;
/// See [`MIN_REVERSED_CHORD`].
const REVERSED_ELONGATION: f64 = 1.5;
/// Step of the lattice that probes for thick ink, px.
const PROBE_STEP: usize = 4;
/// Lattice points of chord at least [`MIN_GROUND_CHORD`] an image needs before any component is
/// labelled.
const MIN_THICK_PROBES: usize = 16;

/// Reverses every ground of `ink` (row-major, `width` x `height`) in place and returns their
/// boxes, in the order a row-major lattice first meets them.
pub(crate) fn reverse(ink: &mut [bool], width: usize, height: usize) -> Vec<Ground> {
    let probes = thick_probes(ink, width, height);
    if probes.is_empty() {
        return Vec::new();
    }
    // Only the components holding thick ink are gathered (8-connected, as the ink is traced),
    // with a bit per pixel for the ones seen: a page of thin strokes costs the probe alone.
    let (cols, rows) = (width.div_ceil(PROBE_STEP), height.div_ceil(PROBE_STEP));
    let mut probe_at = vec![false; cols * rows];
    for &p in &probes {
        probe_at[(p / width / PROBE_STEP) * cols + (p % width) / PROBE_STEP] = true;
    }
    let mut seen = vec![0u64; (width * height).div_ceil(64)];
    let mut grounds = Vec::new();
    let mut stack = Vec::new();
    for start in probes {
        if seen[start / 64] >> (start % 64) & 1 == 1 {
            continue;
        }
        seen[start / 64] |= 1 << (start % 64);
        stack.push(start);
        let mut pixels = Vec::new();
        let (mut x0, mut y0, mut x1, mut y1) = (width, height, 0usize, 0usize);
        let mut thick = 0usize;
        while let Some(p) = stack.pop() {
            let (x, y) = (p % width, p / width);
            pixels.push(p);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            if x % PROBE_STEP == 0 && y % PROBE_STEP == 0 {
                thick += usize::from(probe_at[(y / PROBE_STEP) * cols + x / PROBE_STEP]);
            }
            for ny in y.saturating_sub(1)..(y + 2).min(height) {
                for nx in x.saturating_sub(1)..(x + 2).min(width) {
                    let q = ny * width + nx;
                    if ink[q] && seen[q / 64] >> (q % 64) & 1 == 0 {
                        seen[q / 64] |= 1 << (q % 64);
                        stack.push(q);
                    }
                }
            }
        }
        let region = Region {
            x0,
            y0,
            w: x1 - x0 + 1,
            h: y1 - y0 + 1,
        };
        // Half a ground's pixels at least are thick (its median chord is), a probe per
        // PROBE_STEP^2 of them; a component with a quarter of that is no ground.
        let area = pixels.len();
        if thick * 4 * PROBE_STEP * PROBE_STEP < area
            || area < MIN_GROUND_AREA
            || region.w < MIN_GROUND_CHORD as usize
            || region.h < MIN_GROUND_CHORD as usize
        {
            continue;
        }
        if reverse_ground(ink, &pixels, width, &region) {
            grounds.push(Ground {
                x: region.x0 as u32,
                y: region.y0 as u32,
                width: region.w as u32,
                height: region.h as u32,
            });
        }
    }
    grounds
}

/// The points of a lattice of step [`PROBE_STEP`] on ink of chord at least [`MIN_GROUND_CHORD`]
/// (row-major), or none when there are fewer than [`MIN_THICK_PROBES`]: a page of strokes has
/// none.
fn thick_probes(ink: &[bool], width: usize, height: usize) -> Vec<usize> {
    let need = MIN_GROUND_CHORD as usize;
    if width < need || height < need {
        return Vec::new();
    }
    // The probed rows in parallel, their probes collected in row order.
    let probed: Vec<usize> = (0..height).step_by(PROBE_STEP).collect();
    let mut found: Vec<usize> = probed
        .into_par_iter()
        .flat_map_iter(|y| row_probes(ink, width, height, y))
        .collect();
    if found.len() < MIN_THICK_PROBES {
        found.clear();
    }
    found
}

/// The probes of row `y` ([`thick_probes`]): along each horizontal run of at least
/// [`MIN_GROUND_CHORD`] px, every [`PROBE_STEP`]-th column whose vertical run through the row is
/// as long.
fn row_probes(ink: &[bool], width: usize, height: usize, y: usize) -> Vec<usize> {
    let need = MIN_GROUND_CHORD as usize;
    let mut found = Vec::new();
    let row = &ink[y * width..(y + 1) * width];
    let mut x = 0;
    loop {
        // The paper between runs (most of a page) skipped eight pixels at a time.
        x = next_ink(row, x);
        if x >= width {
            break;
        }
        let start = x;
        while x < width && row[x] {
            x += 1;
        }
        if x - start < need {
            continue;
        }
        // A long horizontal run: probe the vertical runs along it.
        for px in (start.next_multiple_of(PROBE_STEP)..x).step_by(PROBE_STEP) {
            let up = (0..y).rev().take_while(|&yy| ink[yy * width + px]).count();
            let down = (y..height).take_while(|&yy| ink[yy * width + px]).count();
            if up + down >= need {
                found.push(y * width + px);
            }
        }
    }
    found
}

/// A bounding box inside the image.
struct Region {
    x0: usize,
    y0: usize,
    w: usize,
    h: usize,
}

/// The chord (shorter of the horizontal and vertical runs of its own value) of each cell of a
/// `w` x `h` grid of `values`.
fn chords(values: &[bool], w: usize, h: usize) -> Vec<u32> {
    let mut chords: Vec<u32> = values
        .chunks(w)
        .flat_map(|row| run_lengths(row.iter().copied()))
        .collect();
    for x in 0..w {
        let vertical = run_lengths((0..h).map(|y| values[y * w + x]));
        for (y, run) in vertical.into_iter().enumerate() {
            let chord = &mut chords[y * w + x];
            *chord = (*chord).min(run);
        }
    }
    chords
}

fn median(values: &mut [u32]) -> f64 {
    upper_median_by(values, Ord::cmp).map_or(0.0, f64::from)
}

/// Tests the component of `pixels` (indices into `ink`, inside `region`) as a ground and
/// reverses it if it is one.
fn reverse_ground(ink: &mut [bool], pixels: &[usize], width: usize, region: &Region) -> bool {
    let area = pixels.len();
    // The box with a one-pixel frame of outside, so that what is not the component and reaches
    // the frame is outside it.
    let (w, h) = (region.w + 2, region.h + 2);
    let at = |x: usize, y: usize| -> Option<usize> {
        let inside = (1..=region.w).contains(&x) && (1..=region.h).contains(&y);
        inside.then(|| (y + region.y0 - 1) * width + x + region.x0 - 1)
    };
    let mut member = vec![false; w * h];
    for &p in pixels {
        let (x, y) = (p % width - region.x0 + 1, p / width - region.y0 + 1);
        member[y * w + x] = true;
    }
    let mut own = chords(&member, w, h);
    let mut own: Vec<u32> = own
        .iter_mut()
        .zip(&member)
        .filter_map(|(c, &m)| m.then_some(*c))
        .collect();
    let ground_chord = median(&mut own);
    if ground_chord < MIN_GROUND_CHORD as f64 {
        return false;
    }
    // What the component encloses: the parts of the rest of the box (4-connected, the
    // complement of 8-connected ink) that do not reach the frame.
    let (enclosed, sizes) = label_components(&member, w, h, false, Connectivity::Four);
    let regions = sizes.len() - 1;
    let reaches_frame = on_image_edge(&enclosed, w, h, sizes.len());
    // The light pixels' chords, per enclosed region.
    let light: Vec<bool> = (0..w * h)
        .map(|i| at(i % w, i / w).is_some_and(|p| !ink[p]))
        .collect();
    let light_chords = chords(&light, w, h);
    let mut per_region: Vec<Vec<u32>> = vec![Vec::new(); regions + 1];
    for i in 0..w * h {
        let r = enclosed[i] as usize;
        if r > 0 && !reaches_frame[r] && light[i] {
            per_region[r].push(light_chords[i]);
        }
    }
    // The holes that are strokes (reversed if the field is a ground), and of them the ones
    // clear enough to show that it is.
    let mut strokes = vec![false; regions + 1];
    let (mut showing, mut showing_chords, mut showing_area) = (0usize, Vec::new(), 0usize);
    for (r, chords) in per_region.iter_mut().enumerate() {
        let n = chords.len() as f64;
        let chord = median(chords);
        strokes[r] = chord >= MIN_REVERSED_CHORD as f64 && n >= REVERSED_ELONGATION * chord * chord;
        if chord >= MIN_HOLE_CHORD as f64 && n >= HOLE_ELONGATION * chord * chord {
            showing += 1;
            showing_area += chords.len();
            showing_chords.extend_from_slice(chords);
        }
    }
    if showing < MIN_HOLES
        || (showing_area as f64) < MIN_HOLE_SHARE * area as f64
        || showing_area > area
        || ground_chord < GROUND_TO_STROKE * median(&mut showing_chords)
    {
        return false;
    }
    for i in 0..w * h {
        let Some(p) = at(i % w, i / w) else {
            continue;
        };
        if member[i] {
            ink[p] = false;
        } else if strokes[enclosed[i] as usize] {
            ink[p] = !ink[p];
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`thick_probes`] with its rows in one pass, in order: the reference.
    fn thick_probes_in_one_pass(ink: &[bool], width: usize, height: usize) -> Vec<usize> {
        if width < MIN_GROUND_CHORD as usize || height < MIN_GROUND_CHORD as usize {
            return Vec::new();
        }
        let found: Vec<usize> = (0..height)
            .step_by(PROBE_STEP)
            .flat_map(|y| row_probes(ink, width, height, y))
            .collect();
        if found.len() < MIN_THICK_PROBES {
            return Vec::new();
        }
        found
    }

    /// The probes found row by row in parallel are the ones one pass found, in the same order,
    /// on masks of random rectangles (thick and thin) and specks of several sizes.
    #[test]
    fn the_probes_by_rows_in_parallel_equal_the_probes_in_one_pass() {
        let mut next = crate::synth::lcg(61u64);
        let mut rand = move |n: usize| (next() >> 33) as usize % n;
        let mut nonempty = 0;
        for (w, h) in [(211, 157), (64, 301), (500, 40), (30, 30)] {
            for _ in 0..20 {
                let mut ink = vec![false; w * h];
                for _ in 0..rand(40) {
                    let (x0, y0) = (rand(w), rand(h));
                    let (rw, rh) = (1 + rand(70), 1 + rand(70));
                    for y in y0..(y0 + rh).min(h) {
                        for x in x0..(x0 + rw).min(w) {
                            ink[y * w + x] = true;
                        }
                    }
                }
                for _ in 0..rand(500) {
                    ink[rand(w * h)] ^= true;
                }
                let probes = thick_probes(&ink, w, h);
                assert_eq!(probes, thick_probes_in_one_pass(&ink, w, h));
                nonempty += usize::from(!probes.is_empty());
            }
        }
        assert!(nonempty > 10, "{nonempty} masks with probes");
    }

    /// A `w` x `h` mask with the rectangles `fill` set and `clear` then cleared.
    fn mask(
        w: usize,
        h: usize,
        fill: &[(usize, usize, usize, usize)],
        clear: &[(usize, usize, usize, usize)],
    ) -> Vec<bool> {
        let mut ink = vec![false; w * h];
        for (set, rects) in [(true, fill), (false, clear)] {
            for &(x0, y0, rw, rh) in rects {
                for y in y0..y0 + rh {
                    for x in x0..x0 + rw {
                        ink[y * w + x] = set;
                    }
                }
            }
        }
        ink
    }

    #[test]
    fn light_bars_on_a_dark_banner_become_the_ink() {
        // A 200 x 60 banner with three light bars 4 px wide and 40 px long, and a dark stroke
        // beside it on the paper.
        let (w, h) = (260, 80);
        let bars = [(40, 15, 4, 40), (100, 15, 4, 40), (140, 30, 40, 4)];
        let mut ink = mask(w, h, &[(10, 10, 200, 60), (230, 10, 4, 50)], &bars);
        let grounds = reverse(&mut ink, w, h);
        assert_eq!(
            grounds,
            vec![Ground {
                x: 10,
                y: 10,
                width: 200,
                height: 60
            }]
        );
        let expected = mask(
            w,
            h,
            &bars
                .iter()
                .copied()
                .chain([(230, 10, 4, 50)])
                .collect::<Vec<_>>(),
            &[],
        );
        assert_eq!(ink, expected);
    }

    #[test]
    fn bold_strokes_with_counters_and_pinholes_stay_ink() {
        let (w, h) = (260, 80);
        // A bold ring (a letter O: its counter as wide as its stroke).
        let ring = mask(w, h, &[(10, 10, 60, 60)], &[(30, 30, 20, 20)]);
        // A dark field with two round pinholes only.
        let field = mask(
            w,
            h,
            &[(10, 10, 200, 60)],
            &[(40, 30, 4, 4), (120, 30, 4, 4)],
        );
        // A dark field with one light bar: one hole is a mark, not text.
        let one = mask(w, h, &[(10, 10, 200, 60)], &[(40, 15, 4, 30)]);
        for original in [ring, field, one] {
            let mut ink = original.clone();
            assert!(reverse(&mut ink, w, h).is_empty());
            assert_eq!(ink, original);
        }
    }

    #[test]
    fn merged_ridges_are_not_a_ground() {
        // A print's ridges merged at both ends: 20 px ridges between 4 px valleys, five times
        // as wide, not six.
        let (w, h) = (160, 120);
        let valleys: Vec<_> = (0..6).map(|k| (30 + 24 * k, 10, 4, 100)).collect();
        let original = mask(w, h, &[(10, 4, 140, 112)], &valleys);
        let mut ink = original.clone();
        assert!(reverse(&mut ink, w, h).is_empty());
        assert_eq!(ink, original);
    }

    #[test]
    fn a_scanners_frame_around_a_page_of_text_stays_ink() {
        // A dark frame 30 px thick around a light page holding thin dark lines of "text": the
        // page is the frame's one hole, larger than the frame, and its gaps between the lines
        // are half as wide as the frame, not a sixth.
        let (w, h) = (300, 260);
        let lines: Vec<_> = (0..10).map(|k| (50, 45 + 17 * k, 200, 3)).collect();
        let original = mask(w, h, &[(0, 0, 300, 260)], &[(30, 30, 240, 200)]);
        let mut with_text = original.clone();
        for &(x0, y0, rw, rh) in &lines {
            for y in y0..y0 + rh {
                for x in x0..x0 + rw {
                    with_text[y * w + x] = true;
                }
            }
        }
        let mut ink = with_text.clone();
        assert!(reverse(&mut ink, w, h).is_empty());
        assert_eq!(ink, with_text);
    }
}
