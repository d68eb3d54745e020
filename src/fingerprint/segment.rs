//! Segmentation: which blocks hold the print (docs/fingerprints.md, "Segmentation").
//!
//! As pyfing's GMFS: the gradient magnitude averaged over a neighbourhood is high where ridges
//! alternate with valleys and low on the empty background, so a block is print where its mean
//! gradient magnitude, averaged over 3 x 3 blocks, reaches a fraction (`segment_threshold`, 0.2)
//! of the image's 95th percentile of gradient magnitude. The block mask is then cleaned: a closing
//! (one block) bridges gaps between ridges' blocks, only the largest component is kept, holes not
//! open to the image edge are filled (a faint patch inside the print is still print), and an
//! opening (one block) removes protrusions and blocks hanging on by a corner.
//!
//! A second pass ([`refine`]) runs after the enhancement: the Gabor filter tuned to the local
//! orientation and period gains on the ridges (a matched filter) and not on noise, so where the
//! gradient magnitude of a noisy, faint or bare area passes for ridges, the response does not.
//! A block stays print where the response's root mean square, averaged over its 3 x 3
//! neighbourhood within the print, reaches `response_threshold` (0.2) of the print's 95th
//! percentile; the mask is cleaned again the same way.
//!
//! In: the gradients (then the enhanced image); out: [`Segmentation`].

use super::fields::{
    floor_small, whole_small, BlockGrid, OrientationField, Plane, RidgePeriods, Segmentation,
};
use super::math::{components, BlockGradients};
use crate::mask::morph3;
use crate::median::upper_median_by;
use crate::params::FingerprintParams;
use rayon::prelude::*;

/// The percentile of the pixels' gradient magnitudes the threshold is a fraction of.
const PERCENTILE: f64 = 0.95;

/// Segments the print from its gradients: every pixel's gradient `magnitude` (row-major) and
/// the means per block in `gradients`.
pub(crate) fn segment(
    magnitude: Vec<f32>,
    gradients: &BlockGradients,
    params: &FingerprintParams,
) -> Segmentation {
    let grid = gradients.grid;
    let (cols, rows) = (grid.cols as usize, grid.rows as usize);
    let block_mean = &gradients.mean_magnitude;
    let level = percentile(magnitude, PERCENTILE) * params.segment_threshold as f32;
    let mut inside = vec![false; grid.len()];
    for j in 0..rows {
        for i in 0..cols {
            let (mut sum, mut n) = (0.0f32, 0.0f32);
            for jj in j.saturating_sub(1)..(j + 2).min(rows) {
                for ii in i.saturating_sub(1)..(i + 2).min(cols) {
                    sum += block_mean[grid.index(ii, jj)];
                    n += 1.0;
                }
            }
            inside[grid.index(i, j)] = level > 0.0 && sum / n >= level;
        }
    }
    let inside = clean(&inside, cols, rows);
    Segmentation { grid, inside }
}

/// The RMS of `enhanced` over each block inside `segmentation` (0 outside it).
pub(crate) fn block_rms(enhanced: &Plane, segmentation: &Segmentation) -> Vec<f32> {
    let grid = segmentation.grid;
    let mut rms = vec![0.0f32; grid.len()];
    for j in 0..grid.rows as usize {
        for i in 0..grid.cols as usize {
            let b = grid.index(i, j);
            if segmentation.inside[b] {
                rms[b] = rms_of_block(enhanced, grid, i, j);
            }
        }
    }
    rms
}

/// The RMS of `enhanced` over block `(i, j)` of `grid`.
fn rms_of_block(enhanced: &Plane, grid: BlockGrid, i: usize, j: usize) -> f32 {
    let w = grid.width as usize;
    let (x0, x1, y0, y1) = grid.pixels(i, j);
    let mut sum = 0.0f64;
    for y in y0..y1 {
        for &v in &enhanced.values[y * w + x0..y * w + x1] {
            sum += f64::from(v) * f64::from(v);
        }
    }
    let n = ((x1 - x0) * (y1 - y0)).max(1);
    (sum / n as f64).sqrt() as f32
}

/// The second pass (see the module doc): `segmentation` less the blocks where the enhanced
/// response is weak (`segmentation` unchanged when nothing would be left), with the
/// [`block_rms`] of `enhanced` over it: a block's RMS reads only its own pixels, so those of the
/// blocks both passes keep are the ones the pass measured, and only the blocks the cleaning adds
/// are measured again.
pub(crate) fn refine(
    segmentation: &Segmentation,
    enhanced: &Plane,
    threshold: f64,
    keep_out: &[bool],
) -> (Segmentation, Vec<f32>) {
    let grid = segmentation.grid;
    let (cols, rows) = (grid.cols as usize, grid.rows as usize);
    let w = grid.width as usize;
    if threshold <= 0.0 || enhanced.values.len() != w * grid.height as usize {
        return (segmentation.clone(), block_rms(enhanced, segmentation));
    }
    let mut rms = block_rms(enhanced, segmentation);
    let inside_rms: Vec<f32> = rms
        .iter()
        .zip(&segmentation.inside)
        .filter(|(_, &inside)| inside)
        .map(|(&r, _)| r)
        .collect();
    let level = percentile(inside_rms, PERCENTILE) * threshold as f32;
    let mut keep = vec![false; grid.len()];
    for j in 0..rows {
        for i in 0..cols {
            if !segmentation.inside[grid.index(i, j)] {
                continue;
            }
            let (mut sum, mut n) = (0.0f32, 0.0f32);
            for jj in j.saturating_sub(1)..(j + 2).min(rows) {
                for ii in i.saturating_sub(1)..(i + 2).min(cols) {
                    let b = grid.index(ii, jj);
                    if segmentation.inside[b] {
                        sum += rms[b];
                        n += 1.0;
                    }
                }
            }
            keep[grid.index(i, j)] = level > 0.0 && sum / n >= level;
        }
    }
    let mut inside = clean(&keep, cols, rows);
    for (m, &out) in inside.iter_mut().zip(keep_out) {
        if out {
            *m = false;
        }
    }
    if !inside.iter().any(|&v| v) {
        return (segmentation.clone(), rms);
    }
    for j in 0..rows {
        for i in 0..cols {
            let b = grid.index(i, j);
            if !inside[b] {
                rms[b] = 0.0;
            } else if !segmentation.inside[b] {
                rms[b] = rms_of_block(enhanced, grid, i, j);
            }
        }
    }
    (Segmentation { grid, inside }, rms)
}

/// Orientations tried for a block's rows along the ridges, evenly over a half turn from the
/// block's own.
const ROW_ORIENTATIONS: usize = 12;
/// How far [`ridge_evidence`]'s rows reach along the ridges each way from the block's centre, in
/// ridge periods (one period across).
const ROW_LENGTH: f64 = 1.5;
/// How far apart, in the print's ridge periods (its median), the blocks are whose rows
/// [`ridge_evidence`] measures for the ridges' amplitude: the rows of a block span a period each
/// way across the ridges, so blocks nearer than two periods read mostly the same pixels and
/// their amplitudes are nearly one measurement; on a lattice two periods apart each way the
/// rectangles still cover the print (each 2 x 3 periods, one per 2 x 2 periods squared).
const AMPLITUDE_SPACING_PERIODS: f64 = 2.0;

/// How much of a block's rows its [`BlockEvidence`] holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Rows {
    /// None: the window's mean only.
    #[default]
    Mean,
    /// The block's own orientation: the ridges' amplitude, that orientation's F ratio and noise.
    Own,
    /// The amplitude at the own orientation, the F ratio and noise at the best of
    /// [`ROW_ORIENTATIONS`] (a core's curved ridges, or an orientation the field got wrong, still
    /// count as ridges).
    Full,
}

impl Rows {
    /// The orientations whose rows are measured.
    fn orientations(self) -> usize {
        match self {
            Rows::Mean => 0,
            Rows::Own => 1,
            Rows::Full => ROW_ORIENTATIONS,
        }
    }
}

/// [`ridge_evidence`]'s: each block's evidence, and the print's gray levels measured from it.
pub(crate) struct RidgeEvidence {
    /// Per block of the grid, what is measured of it (the default outside the print).
    pub blocks: Vec<BlockEvidence>,
    /// Whether every gray level is whole (as `whole_levels` finds), for [`measure_evidence`].
    pub whole: bool,
    print: PrintGray,
}

impl RidgeEvidence {
    /// The blocks' evidence, the print's middle gray and half swing taken from it (the swing
    /// from the blocks whose rows are measured).
    fn of(segmentation: &Segmentation, blocks: Vec<BlockEvidence>, whole: bool) -> RidgeEvidence {
        let print = PrintGray::of(segmentation, &blocks);
        RidgeEvidence {
            blocks,
            whole,
            print,
        }
    }
}

/// Per block inside `segmentation`, how clearly the gray image around it shows ridges
/// (docs/fingerprints.md, "Segmentation"): every block's window mean gray, and the rows at the
/// own orientation (the ridges' amplitude, that orientation's F ratio and noise) of the blocks on
/// a lattice [`AMPLITUDE_SPACING_PERIODS`] of the print's median period apart each way (every
/// block where that is under two blocks, or where no lattice block is print), from which the
/// print's middle gray and the ridges' half swing are taken. [`measure_evidence`] completes a
/// block's rows where [`blank_blocks`] needs them. The default outside the print. `whole` says
/// whether every level of `gray` is whole (`whole_levels`; the caller that made the plane from
/// 8-bit gray knows it without reading the pixels again).
pub(crate) fn ridge_evidence(
    gray: &Plane,
    whole: bool,
    segmentation: &Segmentation,
    field: &OrientationField,
    periods: &RidgePeriods,
) -> RidgeEvidence {
    let grid = segmentation.grid;
    let cols = grid.cols as usize;
    let spacing = AMPLITUDE_SPACING_PERIODS * periods.median_inside(segmentation);
    let step = ((spacing / f64::from(grid.block)).floor() as usize).max(1);
    let on = |step: usize, b: usize| (b % cols) % step == 0 && (b / cols) % step == 0;
    let step = if (0..grid.len()).any(|b| segmentation.inside[b] && on(step, b)) {
        step
    } else {
        1
    };
    // Off the lattice only the mean: from the lines' sums where the levels are whole (exact).
    let prefix = if whole { line_prefix_sums(gray) } else { None };
    let blocks = (0..grid.len())
        .into_par_iter()
        .map_init(EvidenceScratch::default, |scratch, b| {
            if !segmentation.inside[b] {
                return BlockEvidence::default();
            }
            if on(step, b) {
                return block_evidence(gray, whole, grid, field, periods, b, Rows::Own, scratch);
            }
            match &prefix {
                Some(prefix) => {
                    let period = f64::from(periods.period[b]).max(2.0);
                    window_mean(gray, prefix, grid.center(b % cols, b / cols), period)
                }
                None => block_evidence(gray, whole, grid, field, periods, b, Rows::Mean, scratch),
            }
        })
        .collect();
    RidgeEvidence::of(segmentation, blocks, whole)
}

/// Whether every value of `gray` is a whole number of at most 2¹⁶ in size (8-bit gray levels
/// are): then [`row_f_ratio`]'s sums over the disc are exact in any order.
#[cfg(test)]
fn whole_levels(gray: &Plane) -> bool {
    // `v` rounded to the nearest whole number where `|v| ≤ 2²²` (added to 1.5·2²³ it lies where
    // the spacing of `f32` is 1); the pixels that fail counted without a branch (vector lanes).
    let nearest = |v: f32| (v + 12_582_912.0) - 12_582_912.0;
    let failing: usize = gray
        .values
        .iter()
        .map(|&v| usize::from(!((v.abs() <= 65_536.0) & (nearest(v) == v))))
        .sum();
    failing == 0
}

/// The evidence of block `b` (inside the print) with `rows` measured, as [`ridge_evidence`]'s
/// (`whole` its [`RidgeEvidence::whole`]): the mean, and the amplitude where measured, are the
/// same bits whatever `rows`.
pub(crate) fn measure_evidence(
    gray: &Plane,
    whole: bool,
    segmentation: &Segmentation,
    field: &OrientationField,
    periods: &RidgePeriods,
    b: usize,
    rows: Rows,
) -> BlockEvidence {
    block_evidence(
        gray,
        whole,
        segmentation.grid,
        field,
        periods,
        b,
        rows,
        &mut EvidenceScratch::default(),
    )
}

/// [`row_f_ratio`] of block `b` at its centre, orientation and period.
#[allow(clippy::too_many_arguments)]
fn block_evidence(
    gray: &Plane,
    whole: bool,
    grid: BlockGrid,
    field: &OrientationField,
    periods: &RidgePeriods,
    b: usize,
    rows: Rows,
    scratch: &mut EvidenceScratch,
) -> BlockEvidence {
    let cols = grid.cols as usize;
    let (i, j) = (b % cols, b / cols);
    let own = f64::from(field.angle[b]);
    let period = f64::from(periods.period[b]).max(2.0);
    row_f_ratio(gray, whole, grid.center(i, j), own, period, rows, scratch)
}

/// [`row_f_ratio`]'s scratch space, kept from one block to the next.
#[derive(Default)]
struct EvidenceScratch {
    /// The window's lines: `y` and the first and last `x` of the disc on it.
    lines: Vec<(i64, i64, i64)>,
    /// Count, sum and sum of squares per row.
    rows: Vec<(usize, f64, f64)>,
}

/// The print's gray levels as [`blank_blocks`] reads them: its middle gray, the median of its
/// blocks' window means, and its ridges' half swing, the median of their amplitudes (at their
/// own orientations) times √2 (a sinusoid's peak over its standard deviation).
struct PrintGray {
    middle: f64,
    swing: f64,
}

impl PrintGray {
    fn of(segmentation: &Segmentation, evidence: &[BlockEvidence]) -> PrintGray {
        let median_of = |value: fn(&BlockEvidence) -> Option<f32>| {
            let mut values: Vec<f32> = evidence
                .iter()
                .zip(&segmentation.inside)
                .filter(|(_, &inside)| inside)
                .filter_map(|(e, _)| value(e))
                .collect();
            f64::from(upper_median_by(&mut values, f32::total_cmp).unwrap_or(0.0))
        };
        PrintGray {
            middle: median_of(|e| Some(e.mean)),
            swing: std::f64::consts::SQRT_2
                * median_of(|e| (e.rows != Rows::Mean).then_some(e.amplitude)),
        }
    }

    /// Which side of the middle gray the block's window mean sits on when it is at least
    /// `off_middle` of the half swing off it: -1 dark, 1 light, 0 nearer.
    fn side(&self, e: &BlockEvidence, off_middle: f64) -> i32 {
        let d = f64::from(e.mean) - self.middle;
        if d.abs() < off_middle * self.swing {
            0
        } else if d < 0.0 {
            -1
        } else {
            1
        }
    }
}

/// What [`ridge_evidence`] finds around one block.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct BlockEvidence {
    /// The rows' F ratio at the orientations of `rows` (about 1 on noise, 0 on a flat patch).
    pub f_ratio: f32,
    /// The mean gray level of the window (before the plane is taken off).
    pub mean: f32,
    /// The ridges' amplitude there: the standard deviation of the rows' means at the block's own
    /// orientation less what the noise alone gives them (0 when the noise explains it all).
    pub amplitude: f32,
    /// The pixels' standard deviation within the rows at the best orientation (the noise).
    pub noise: f32,
    /// Which rows `amplitude`, `f_ratio` and `noise` are measured from (0 for [`Rows::Mean`]).
    pub rows: Rows,
}

/// The evidence of the rectangle around `c` (see [`ROW_LENGTH`] and docs/fingerprints.md,
/// "Segmentation"): the F ratio of a one-way analysis of variance of the pixels within one
/// period `T` of `c` across the ridges and 1.5 `T` along them (the best-fitting plane of the
/// gray levels over the disc that holds the rectangle at any orientation taken off: shading, the
/// edge of a wet patch), grouped into rows along the ridges one pixel apart. Where ridges and
/// valleys alternate, the rows' means differ far more than the pixels within a row; on a flat
/// patch or noise they differ only by each mean's own noise, so the ratio of the variance
/// between the rows' means to the variance of a row mean (the pixels' variance within the rows
/// over their count, plus the rounding noise of 8-bit gray, 1/12 level², so that a flat patch
/// without noise is no ridge) is about 1. Unitless, in the image's own units (gray levels
/// against gray levels, lengths in the period). The best of the orientations of
/// [`ROW_ORIENTATIONS`] from `own` that `rows` says (`own` itself first, where the amplitude is
/// measured; none, the window's mean only, for [`Rows::Mean`]); `scratch` is scratch space.
///
/// The disc's pixels are read once, for the plane's sums (its moments from whole-pixel offsets:
/// exact sums for 8-bit gray); each orientation then reads only the part of each line that can
/// reach the rectangle ([`line_span`]), each pixel less the plane as it is read.
///
/// With AVX2 at run time the whole routine is compiled for it and each line's pixels go four to
/// an AVX register ([`wide::line_rows4`]: the same operations on each pixel, the rows' sums
/// taken in the same order, so the same values bit for bit; `math::wide_lanes`).
fn row_f_ratio(
    gray: &Plane,
    whole: bool,
    c: [f64; 2],
    own: f64,
    period: f64,
    rows: Rows,
    scratch: &mut EvidenceScratch,
) -> BlockEvidence {
    #[cfg(target_arch = "x86_64")]
    if super::math::wide_lanes() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { row_f_ratio_wide(gray, whole, c, own, period, rows, scratch) };
    }
    row_f_ratio_lanes::<false>(gray, whole, c, own, period, rows, scratch)
}

/// [`row_f_ratio`] compiled for AVX2, each line's pixels four to a register (`wide`).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn row_f_ratio_wide(
    gray: &Plane,
    whole: bool,
    c: [f64; 2],
    own: f64,
    period: f64,
    rows: Rows,
    scratch: &mut EvidenceScratch,
) -> BlockEvidence {
    row_f_ratio_lanes::<true>(gray, whole, c, own, period, rows, scratch)
}

/// [`row_f_ratio`]'s work, inlined into the version the CPU runs (`WIDE`: the one for AVX2,
/// which the CPU must have).
#[inline(always)]
fn row_f_ratio_lanes<const WIDE: bool>(
    gray: &Plane,
    whole: bool,
    c: [f64; 2],
    own: f64,
    period: f64,
    rows: Rows,
    scratch: &mut EvidenceScratch,
) -> BlockEvidence {
    let measured = rows;
    let EvidenceScratch { lines, rows } = scratch;
    let w = i64::from(gray.width);
    let along = ROW_LENGTH * period;
    let disc = Disc::new(gray, c, period);
    let (r, cx, cy) = (disc.r, disc.cx, disc.cy);
    // The plane's sums over the disc, in offsets `X`, `Y` from (cx, cy): whole numbers.
    let (mut n, mut sx, mut sy, mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut sv, mut sxv, mut syv) = (0.0f64, 0.0f64, 0.0f64);
    lines.clear();
    for y in disc.rows() {
        let Some((a, b)) = disc.line(y) else {
            continue;
        };
        lines.push((y, a, b));
        let line = &gray.values[(y * w + a) as usize..=(y * w + b) as usize];
        // Whole levels (and offsets below 2¹⁶): every partial sum a whole number below 2⁵³,
        // exact, so the sums may be taken four lanes at a time.
        // SAFETY: `WIDE` only where the CPU has AVX2 (`row_f_ratio_wide`).
        #[cfg(target_arch = "x86_64")]
        let (s, s_x) = if WIDE && whole && r < 1 << 16 {
            unsafe { wide::line_sums(line, a - cx) }
        } else {
            line_sums(line, a - cx)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let (s, s_x) = line_sums(line, a - cx);
        let (k, yy) = ((b - a + 1) as f64, (y - cy) as f64);
        // Σ X over a..=b and Σ X², X = x - cx, in closed form (whole numbers).
        let (xa, xb) = ((a - cx) as f64, (b - cx) as f64);
        let x1 = (xa + xb) * k / 2.0;
        let x2 = (xb * (xb + 1.0) * (2.0 * xb + 1.0) - (xa - 1.0) * xa * (2.0 * xa - 1.0)) / 6.0;
        n += k;
        sx += x1;
        sy += yy * k;
        sxx += x2;
        sxy += yy * x1;
        syy += yy * yy * k;
        sv += s;
        sxv += s_x;
        syv += yy * s;
    }
    if n < 8.0 {
        return BlockEvidence {
            rows: measured,
            ..BlockEvidence::default()
        };
    }
    // The best plane v ≈ m + p dx + q dy by least squares (the moments about the means, times
    // n: whole numbers for whole gray levels).
    let mv = sv / n;
    let (axx, axy, ayy) = (n * sxx - sx * sx, n * sxy - sx * sy, n * syy - sy * sy);
    let (axv, ayv) = (n * sxv - sx * sv, n * syv - sy * sv);
    let det = axx * ayy - axy * axy;
    let (p, q) = if det > 0.0 {
        ((ayy * axv - axy * ayv) / det, (axx * ayv - axy * axv) / det)
    } else {
        (0.0, 0.0)
    };
    // The means of the offsets from `c`.
    let (mx, my) = (
        sx / n + (cx as f64 + 0.5 - c[0]),
        sy / n + (cy as f64 + 0.5 - c[1]),
    );
    let count = 2 * period.ceil() as usize + 2;
    let off = count as f64;
    let mut orientations_seen = BestRows::default();
    for o in 0..measured.orientations() {
        let theta = own + std::f64::consts::PI * o as f64 / ROW_ORIENTATIONS as f64;
        let (nx, ny) = (-theta.sin(), theta.cos());
        // Each pixel's row, `count` (a row of its own, left out) where the pixel is off the
        // rectangle; only the part of each line that can reach the rectangle is looked at.
        rows.clear();
        rows.resize(count + 1, (0, 0.0, 0.0));
        let geometry = RowGeometry {
            c0: c[0],
            nx,
            ny,
            period,
            along,
            off,
            p,
            mx,
        };
        for &(y, a, b) in lines.iter() {
            let ddy = y as f64 + 0.5 - c[1];
            let len = (b - a + 1) as usize;
            let span = line_span(a as f64 + 0.5 - c[0], len, ddy, nx, ny, period, along);
            let plane_y = mv + q * (ddy - my);
            let line = &gray.values[(y * w + a) as usize..(y * w + a) as usize + len];
            let (x0, line) = (a + span.start as i64, &line[span]);
            // SAFETY: `WIDE` only where the CPU has AVX2 (`row_f_ratio_wide`).
            #[cfg(target_arch = "x86_64")]
            let done = if WIDE {
                unsafe { wide::line_rows4(line, x0, &geometry, ddy, plane_y, rows) }
            } else {
                0
            };
            #[cfg(not(target_arch = "x86_64"))]
            let done = 0;
            geometry.line_rows(&line[done..], x0 + done as i64, ddy, plane_y, rows);
        }
        let Some(anova) = RowsAnova::of(&rows[..count]) else {
            continue;
        };
        orientations_seen.take(o, &anova);
    }
    orientations_seen.evidence(mv, measured)
}

/// The disc that holds [`row_f_ratio`]'s rectangle around `c` at any orientation (radius
/// `√(1 + 1.5²)` periods): the pixels whose centres lie within it, line by line.
struct Disc {
    c: [f64; 2],
    reach: f64,
    /// The radius rounded up, px.
    r: i64,
    /// The pixel that holds `c`.
    cx: i64,
    cy: i64,
    /// The image's columns and lines the disc's square can reach.
    x_lo: i64,
    x_hi: i64,
    y_lo: i64,
    y_hi: i64,
    /// Where the centre's coordinates are whole or half pixels (a block's centre always is):
    /// twice them, and four times the squared reach rounded down, for [`Disc::line`]'s test in
    /// whole numbers ([`Disc::whole_line`]).
    halves: Option<(i64, i64, i64)>,
}

impl Disc {
    #[inline(always)]
    fn new(gray: &Plane, c: [f64; 2], period: f64) -> Disc {
        let (w, h) = (i64::from(gray.width), i64::from(gray.height));
        let along = ROW_LENGTH * period;
        let reach = (period * period + along * along).sqrt();
        let r = reach.ceil() as i64;
        let (cx, cy) = (c[0].floor() as i64, c[1].floor() as i64);
        // Twice a coordinate, where it is a whole number small enough that every offset of a
        // pixel centre from it (a multiple of a half) and its square are exact in `f64`.
        let twice = |v: f64| {
            let t = 2.0 * v;
            (t == t.floor() && t.abs() < (1u64 << 24) as f64).then_some(t as i64)
        };
        let reach2 = 4.0 * (reach * reach);
        let halves = match (twice(c[0]), twice(c[1])) {
            (Some(c2x), Some(c2y)) if reach2 >= 0.0 && reach2 < (1u64 << 60) as f64 => {
                Some((c2x, c2y, reach2.floor() as i64))
            }
            _ => None,
        };
        Disc {
            c,
            reach,
            r,
            cx,
            cy,
            x_lo: (cx - r).max(0),
            x_hi: (cx + r).min(w - 1),
            y_lo: (cy - r).max(0),
            y_hi: (cy + r).min(h - 1),
            halves,
        }
    }

    /// The image lines the disc may cross.
    #[inline(always)]
    fn rows(&self) -> std::ops::RangeInclusive<i64> {
        self.y_lo..=self.y_hi
    }

    /// The first and last column of the disc's pixels on line `y`, if any: in whole numbers
    /// where the centre allows ([`Disc::whole_line`]), else solved ([`Disc::line_solved`]).
    #[inline(always)]
    fn line(&self, y: i64) -> Option<(i64, i64)> {
        if let Some(halves) = self.halves {
            return self.whole_line(y, halves);
        }
        self.line_solved(y)
    }

    /// [`Disc::line`] where the centre lies on whole or half pixels (`halves`: twice its
    /// coordinates and `⌊4 reach²⌋`). A pixel centre's offsets from it are then multiples of
    /// a half, their squares and sum exact, so the pixel's test `dx² + dy² ≤ reach²` (in
    /// `f64`, `reach²` rounded as there) is `m² + n² ≤ ⌊4 reach²⌋` for the whole numbers
    /// `m = 2x + 1 - 2c_x`, `n = 2y + 1 - 2c_y`: the line's run is the columns with `|m|` at
    /// most the whole square root of what `n²` leaves, the same pixels without the test at
    /// each end of the run.
    #[inline(always)]
    fn whole_line(&self, y: i64, (c2x, c2y, reach2): (i64, i64, i64)) -> Option<(i64, i64)> {
        let n = 2 * y + 1 - c2y;
        let left = reach2 - n * n;
        if left < 0 {
            return None;
        }
        let s = whole_sqrt(left);
        // `|2x + 1 - c2x| ≤ s`: `x` from ⌈(c2x - 1 - s) / 2⌉ to ⌊(c2x - 1 + s) / 2⌋.
        let a = (c2x - s).div_euclid(2).max(self.x_lo);
        let b = (c2x - 1 + s).div_euclid(2).min(self.x_hi);
        (a <= b).then_some((a, b))
    }

    /// [`Disc::line`] for any centre: the bounds solved in real numbers, then each end checked
    /// with the pixel's own test.
    #[inline(always)]
    fn line_solved(&self, y: i64) -> Option<(i64, i64)> {
        let (c, reach) = (self.c, self.reach);
        let ddy = y as f64 + 0.5 - c[1];
        let inside_disc = |x: i64| {
            let ddx = x as f64 + 0.5 - c[0];
            ddx * ddx + ddy * ddy <= reach * reach
        };
        let half = (reach * reach - ddy * ddy).max(0.0).sqrt();
        let guess = (
            (c[0] - 0.5 - half).ceil() as i64,
            (c[0] - 0.5 + half).floor() as i64,
        );
        disc_run(self.x_lo, self.x_hi, guess, inside_disc)
    }
}

/// The whole square root of `n` (at least 0). Below 2⁵⁰ the `f64` root's truncation is it: `n`
/// is exact, the root of a square `k²` is `k`, and the root of `(k + 1)² - 1` lies more than
/// `1 / (2k + 2)` below `k + 1`, farther than half its ulp (at most `(k + 1) · 2⁻⁵³`) for
/// `k < 2²⁵`, so it never rounds up to `k + 1`. Above, the `f64` root is within one of it, and
/// the steps make it exact.
#[inline(always)]
fn whole_sqrt(n: i64) -> i64 {
    let mut s = (n as f64).sqrt() as i64;
    if n >= 1 << 50 {
        while s * s > n {
            s -= 1;
        }
        while (s + 1) * (s + 1) <= n {
            s += 1;
        }
    }
    s
}

/// Sums of each image line's gray levels from its start (`width + 1` a line, the first 0), for
/// [`window_mean`]: whole numbers where every level is (as `whole_levels` finds), so any line's
/// part is their difference, exact. `None` where a line's sum could leave `i32`.
fn line_prefix_sums(gray: &Plane) -> Option<Vec<i32>> {
    let w = gray.width as usize;
    if (w as u64 + 1) * 65_536 >= i32::MAX as u64 || w == 0 {
        return None;
    }
    let mut sums = Vec::with_capacity((w + 1) * gray.height as usize);
    for line in gray.values.chunks_exact(w) {
        let mut sum = 0i32;
        sums.push(0);
        sums.extend(line.iter().map(|&v| {
            sum += v as i32;
            sum
        }));
    }
    Some(sums)
}

/// [`row_f_ratio`]'s window mean alone (what it gives for [`Rows::Mean`], the same bits), from
/// `prefix`, [`line_prefix_sums`] of a `gray` of whole levels: each line of the disc its
/// difference of two sums (exact), where [`row_f_ratio`] adds its pixels.
fn window_mean(gray: &Plane, prefix: &[i32], c: [f64; 2], period: f64) -> BlockEvidence {
    #[cfg(target_arch = "x86_64")]
    if super::math::wide_lanes() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { window_mean_wide(gray, prefix, c, period) };
    }
    window_mean_lanes(gray, prefix, c, period)
}

/// [`window_mean`] compiled for AVX2 (`floor` and `ceil` one instruction each).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn window_mean_wide(
    gray: &Plane,
    prefix: &[i32],
    c: [f64; 2],
    period: f64,
) -> BlockEvidence {
    window_mean_lanes(gray, prefix, c, period)
}

#[inline(always)]
fn window_mean_lanes(gray: &Plane, prefix: &[i32], c: [f64; 2], period: f64) -> BlockEvidence {
    let stride = gray.width as usize + 1;
    let disc = Disc::new(gray, c, period);
    let (mut n, mut sv) = (0.0f64, 0.0f64);
    for y in disc.rows() {
        let Some((a, b)) = disc.line(y) else {
            continue;
        };
        let line = &prefix[y as usize * stride..(y as usize + 1) * stride];
        n += (b - a + 1) as f64;
        sv += f64::from(line[b as usize + 1] - line[a as usize]);
    }
    if n < 8.0 {
        return BlockEvidence::default();
    }
    BlockEvidence {
        mean: (sv / n) as f32,
        ..BlockEvidence::default()
    }
}

/// Σ v and Σ X·v over a line of the disc, its first pixel at the offset `x0` from the centre's
/// column, one pixel after the other.
#[inline(always)]
fn line_sums(line: &[f32], x0: i64) -> (f64, f64) {
    let (mut s, mut s_x) = (0.0f64, 0.0f64);
    for (x, &v) in (x0..).zip(line) {
        s += f64::from(v);
        s_x += x as f64 * f64::from(v);
    }
    (s, s_x)
}

/// What [`row_f_ratio`] needs to put a pixel of a line in its row: the centre's `x` (`c0`), the
/// rows' normal `(nx, ny)`, the rectangle's half sides (`period` across, `along` along), the row
/// of the pixels off it (`off`), and the plane's slope `p` across the lines about the mean offset
/// `mx`.
struct RowGeometry {
    c0: f64,
    nx: f64,
    ny: f64,
    period: f64,
    along: f64,
    off: f64,
    p: f64,
    mx: f64,
}

impl RowGeometry {
    /// The pixels `line` of a line at the offset `ddy` from the centre, the first at `x0`, less
    /// the plane (`plane_y` on this line), added to their rows' count, sum and sum of squares.
    #[inline(always)]
    fn line_rows(
        &self,
        line: &[f32],
        x0: i64,
        ddy: f64,
        plane_y: f64,
        rows: &mut [(usize, f64, f64)],
    ) {
        let RowGeometry {
            c0,
            nx,
            ny,
            period,
            along,
            off,
            p,
            mx,
        } = *self;
        for (x, &v) in (x0..).zip(line) {
            let dx = x as f64 + 0.5 - c0;
            // `u` across the ridges, `t` along them.
            let (u, t) = (dx * nx + ddy * ny, dx * ny - ddy * nx);
            let kept = u.abs() <= period && t.abs() <= along;
            // `u + T` is in [0, 2T] for a pixel kept: its floor is at most 2⌈T⌉ < `count`.
            let row = whole_small(floor_small(if kept { u + period } else { off }));
            let v = f64::from(v) - (plane_y + p * (dx - mx));
            let row = &mut rows[row as usize];
            row.0 += 1;
            row.1 += v;
            row.2 += v * v;
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod wide {
    use super::RowGeometry;
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_and_pd, _mm256_andnot_pd, _mm256_blendv_pd, _mm256_cmp_pd,
        _mm256_cvtps_pd, _mm256_cvttpd_epi32, _mm256_floor_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_setr_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd, _mm_loadu_ps,
        _mm_storeu_si128, _CMP_LE_OQ,
    };

    /// [`super::line_sums`] four pixels at a time (four partial sums, added up at the end), then
    /// the rest one by one: for whole gray levels (of at most 2¹⁶, offsets far below 2²⁰) every
    /// product and partial sum is a whole number below 2⁵³, exact, so the sums are the one-by-one
    /// loop's bit for bit; for other values they may differ in the last bits.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn line_sums(line: &[f32], x0: i64) -> (f64, f64) {
        let fours = line.len() / 4 * 4;
        let first = x0 as f64;
        let mut xs = _mm256_setr_pd(first, first + 1.0, first + 2.0, first + 3.0);
        let four = _mm256_set1_pd(4.0);
        let (mut s, mut s_x) = (_mm256_setzero_pd(), _mm256_setzero_pd());
        for four_pixels in line[..fours].chunks_exact(4) {
            // SAFETY: four values of `four_pixels`.
            let v = _mm256_cvtps_pd(unsafe { _mm_loadu_ps(four_pixels.as_ptr()) });
            s = _mm256_add_pd(s, v);
            s_x = _mm256_add_pd(s_x, _mm256_mul_pd(xs, v));
            xs = _mm256_add_pd(xs, four);
        }
        let (mut lanes, mut x_lanes) = ([0.0f64; 4], [0.0f64; 4]);
        // SAFETY: four values each.
        unsafe {
            _mm256_storeu_pd(lanes.as_mut_ptr(), s);
            _mm256_storeu_pd(x_lanes.as_mut_ptr(), s_x);
        }
        let (rest, rest_x) = super::line_sums(&line[fours..], x0 + fours as i64);
        (
            lanes[0] + lanes[1] + lanes[2] + lanes[3] + rest,
            x_lanes[0] + x_lanes[1] + x_lanes[2] + x_lanes[3] + rest_x,
        )
    }

    /// [`RowGeometry::line_rows`] four pixels at a time, as many whole fours as `line` holds;
    /// returns how many pixels it took in (the rest are left to the one-by-one loop). Each
    /// pixel's offsets, row and value are worked out as there, operation by operation, in AVX
    /// lanes (the floor of `u + T` by `vroundpd`, exact as `floor_small` is for it), then added
    /// to their rows one by one in the line's order: the same sums, bit for bit.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn line_rows4(
        line: &[f32],
        x0: i64,
        g: &RowGeometry,
        ddy: f64,
        plane_y: f64,
        rows: &mut [(usize, f64, f64)],
    ) -> usize {
        let fours = line.len() / 4 * 4;
        // `x as f64` for the four pixels; whole numbers, so adding 4 stays exact.
        let first = x0 as f64;
        let mut xs = _mm256_setr_pd(first, first + 1.0, first + 2.0, first + 3.0);
        let (half, four) = (_mm256_set1_pd(0.5), _mm256_set1_pd(4.0));
        let (c0, nx, ny) = (
            _mm256_set1_pd(g.c0),
            _mm256_set1_pd(g.nx),
            _mm256_set1_pd(g.ny),
        );
        let (ddy_ny, ddy_nx) = (_mm256_set1_pd(ddy * g.ny), _mm256_set1_pd(ddy * g.nx));
        let (period, along, off) = (
            _mm256_set1_pd(g.period),
            _mm256_set1_pd(g.along),
            _mm256_set1_pd(g.off),
        );
        let (p, mx, plane_y) = (
            _mm256_set1_pd(g.p),
            _mm256_set1_pd(g.mx),
            _mm256_set1_pd(plane_y),
        );
        let sign = _mm256_set1_pd(-0.0);
        let (mut index, mut value, mut square) = ([0i32; 4], [0.0f64; 4], [0.0f64; 4]);
        for four_pixels in line[..fours].chunks_exact(4) {
            let dx = _mm256_sub_pd(_mm256_add_pd(xs, half), c0);
            let u = _mm256_add_pd(_mm256_mul_pd(dx, nx), ddy_ny);
            let t = _mm256_sub_pd(_mm256_mul_pd(dx, ny), ddy_nx);
            let kept = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_andnot_pd(sign, u), period),
                _mm256_cmp_pd::<_CMP_LE_OQ>(_mm256_andnot_pd(sign, t), along),
            );
            let row = _mm256_floor_pd(_mm256_blendv_pd(off, _mm256_add_pd(u, period), kept));
            // SAFETY: four values of `four_pixels`.
            let gray = _mm256_cvtps_pd(unsafe { _mm_loadu_ps(four_pixels.as_ptr()) });
            let plane = _mm256_add_pd(plane_y, _mm256_mul_pd(p, _mm256_sub_pd(dx, mx)));
            let v = _mm256_sub_pd(gray, plane);
            // SAFETY: four values each.
            unsafe {
                _mm_storeu_si128(index.as_mut_ptr().cast(), _mm256_cvttpd_epi32(row));
                _mm256_storeu_pd(value.as_mut_ptr(), v);
                _mm256_storeu_pd(square.as_mut_ptr(), _mm256_mul_pd(v, v));
            }
            for ((&row, &v), &v2) in index.iter().zip(&value).zip(&square) {
                let row = &mut rows[row as usize];
                row.0 += 1;
                row.1 += v;
                row.2 += v2;
            }
            xs = _mm256_add_pd(xs, four);
        }
        fours
    }
}

/// The run of `lo..=hi` where `inside` holds, for an `inside` that holds on one run (a line of a
/// disc) which holds `guess` if it holds anywhere near: `None` when it holds nowhere. Each end
/// is found from the ends of `guess` (the run solved in real numbers) by a step or two, with
/// `inside`'s own test, so that the run is exactly the pixels it holds for.
fn disc_run(
    lo: i64,
    hi: i64,
    guess: (i64, i64),
    inside: impl Fn(i64) -> bool,
) -> Option<(i64, i64)> {
    // A window past the image's side has no pixels on the line.
    if lo > hi {
        return None;
    }
    let (mut a, mut b) = (guess.0.clamp(lo, hi + 1), guess.1.clamp(lo - 1, hi));
    while a > lo && inside(a - 1) {
        a -= 1;
    }
    while a <= hi && !inside(a) {
        a += 1;
    }
    if a > hi {
        return None;
    }
    b = b.max(a);
    while b < hi && inside(b + 1) {
        b += 1;
    }
    while !inside(b) {
        b -= 1;
    }
    Some((a, b))
}

/// The one-way analysis of variance of a window's rows ([`ridge_evidence`]), each row its pixel
/// count, sum and sum of squares.
/// What the rows' analyses over a block's orientations give its [`BlockEvidence`]: the
/// amplitude at the first (the block's own) orientation, the F ratio and the noise at the best.
#[derive(Default)]
struct BestRows {
    amplitude: f64,
    ratio: f64,
    spread: f64,
}

impl BestRows {
    /// The analysis of orientation `o` (0 the block's own) taken in.
    fn take(&mut self, o: usize, anova: &RowsAnova) {
        if o == 0 {
            self.amplitude = (anova.between - anova.noise).max(0.0).sqrt();
        }
        if anova.ratio > self.ratio {
            self.ratio = anova.ratio;
            self.spread = anova.within.sqrt();
        }
    }

    fn evidence(&self, mean: f64, rows: Rows) -> BlockEvidence {
        BlockEvidence {
            f_ratio: self.ratio as f32,
            mean: mean as f32,
            amplitude: self.amplitude as f32,
            noise: self.spread as f32,
            rows,
        }
    }
}

struct RowsAnova {
    /// The variance between the rows' means over the noise of a row mean.
    ratio: f64,
    /// The variance between the rows' means.
    between: f64,
    /// The noise of a row mean (with the rounding of 8-bit gray).
    noise: f64,
    /// The pixels' variance within the rows.
    within: f64,
}

impl RowsAnova {
    /// `None` when fewer than four rows have the three pixels a mean and a spread need.
    fn of(rows: &[(usize, f64, f64)]) -> Option<RowsAnova> {
        let (mut within, mut pixels, mut used) = (0.0, 0usize, 0usize);
        let (mut sum_means, mut sum_squared_means) = (0.0, 0.0);
        for &(k, sum, squares) in rows {
            // A row needs a few pixels for its mean and its spread.
            if k < 3 {
                continue;
            }
            let mean = sum / k as f64;
            within += squares - sum * mean;
            pixels += k;
            used += 1;
            sum_means += mean;
            sum_squared_means += mean * mean;
        }
        if used < 4 {
            return None;
        }
        let within = within / (pixels - used) as f64;
        let between = sum_squared_means / used as f64 - (sum_means / used as f64).powi(2);
        let per_row = pixels as f64 / used as f64;
        let noise = within / per_row + 1.0 / 12.0;
        Some(RowsAnova {
            ratio: between / noise,
            between,
            noise,
            within,
        })
    }
}

/// Below this slope a bound of [`line_span`] does not narrow the line.
const SPAN_MIN_SLOPE: f64 = 0.01;
/// How far [`line_span`]'s bounds are widened, px: far above the rounding of `u` and `t`
/// (about 10⁻¹⁴ px, 10⁻¹² px once divided by the least slope), so that no pixel the exact
/// test keeps is left out.
const SPAN_MARGIN: f64 = 1e-6;

/// The pixels of a window's line (`len` pixels one apart from the offset `dx0`, at the offset
/// `dy`) that can lie in the rectangle `|u| ≤ T`, `|t| ≤ L` of the normal `(nx, ny)`, as a range
/// of the line's indices: each bound solved for `dx` and widened by [`SPAN_MARGIN`], so that the
/// range holds every pixel the exact test keeps (it may hold a few more, which the test drops).
fn line_span(
    dx0: f64,
    len: usize,
    dy: f64,
    nx: f64,
    ny: f64,
    period: f64,
    along: f64,
) -> std::ops::Range<usize> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    // `|slope dx + offset| ≤ half`, for a slope far enough from 0.
    let mut narrow = |slope: f64, offset: f64, half: f64| {
        if slope.abs() >= SPAN_MIN_SLOPE {
            let (a, b) = ((-half - offset) / slope, (half - offset) / slope);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
        }
    };
    narrow(nx, dy * ny, period);
    narrow(ny, -dy * nx, along);
    // In the line's indices, clamped to [-1, len + 1] before the conversions (for which the
    // floor of a value of at least -1 is its truncation plus 1, less 1).
    let bound = |x: f64| ((x - dx0).clamp(-1.0, len as f64 + 1.0) + 1.0) as i64 - 1;
    let first = bound(lo - SPAN_MARGIN).max(0) as usize;
    let end = (bound(hi + SPAN_MARGIN) + 1).clamp(0, len as i64) as usize;
    first.min(end)..end
}

#[cfg(test)]
/// [`row_f_ratio`] as it was first written (pixels as tuples, the row index by `floor`): the
/// reference its rewrite is tested against, bit for bit.
///
/// [`ridge_evidence`] of the rectangle around `c` (see [`ROW_LENGTH`]), its rows starting at the
/// orientation `own`; `window` (offsets and gray levels less the plane) and `rows` (count, sum
/// and sum of squares per row) are scratch space.
fn row_f_ratio_reference(
    gray: &Plane,
    c: [f64; 2],
    own: f64,
    period: f64,
    window: &mut Vec<(f64, f64, f64)>,
    rows: &mut Vec<(usize, f64, f64)>,
) -> BlockEvidence {
    let (w, h) = (i64::from(gray.width), i64::from(gray.height));
    // The disc that holds the square at any orientation.
    let along = ROW_LENGTH * period;
    let reach = (period * period + along * along).sqrt();
    let r = reach.ceil() as i64;
    let (cx, cy) = (c[0].floor() as i64, c[1].floor() as i64);
    window.clear();
    for y in (cy - r).max(0)..=(cy + r).min(h - 1) {
        for x in (cx - r).max(0)..=(cx + r).min(w - 1) {
            let (dx, dy) = (x as f64 + 0.5 - c[0], y as f64 + 0.5 - c[1]);
            if dx * dx + dy * dy <= reach * reach {
                let v = gray.values[(y * w + x) as usize];
                window.push((dx, dy, f64::from(v)));
            }
        }
    }
    if window.len() < 8 {
        return BlockEvidence {
            rows: Rows::Full,
            ..BlockEvidence::default()
        };
    }
    let n = window.len() as f64;
    // The best plane v ≈ m + p dx + q dy by least squares, taken off.
    let (mut sx, mut sy, mut sv) = (0.0, 0.0, 0.0);
    for &(dx, dy, v) in window.iter() {
        sx += dx;
        sy += dy;
        sv += v;
    }
    let (mx, my, mv) = (sx / n, sy / n, sv / n);
    let (mut sxx, mut sxy, mut syy, mut sxv, mut syv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(dx, dy, v) in window.iter() {
        let (x, y, v) = (dx - mx, dy - my, v - mv);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
        sxv += x * v;
        syv += y * v;
    }
    let det = sxx * syy - sxy * sxy;
    let (p, q) = if det > 0.0 {
        ((syy * sxv - sxy * syv) / det, (sxx * syv - sxy * sxv) / det)
    } else {
        (0.0, 0.0)
    };
    for item in window.iter_mut() {
        item.2 -= mv + p * (item.0 - mx) + q * (item.1 - my);
    }
    let count = 2 * period.ceil() as usize + 2;
    let mut orientations_seen = BestRows::default();
    for o in 0..ROW_ORIENTATIONS {
        let theta = own + std::f64::consts::PI * o as f64 / ROW_ORIENTATIONS as f64;
        let (nx, ny) = (-theta.sin(), theta.cos());
        rows.clear();
        rows.resize(count, (0, 0.0, 0.0));
        for &(dx, dy, v) in window.iter() {
            // `u` across the ridges, `t` along them.
            let (u, t) = (dx * nx + dy * ny, dx * ny - dy * nx);
            if u.abs() > period || t.abs() > along {
                continue;
            }
            let row = &mut rows[((u + period).floor() as usize).min(count - 1)];
            row.0 += 1;
            row.1 += v;
            row.2 += v * v;
        }
        let Some(anova) = RowsAnova::of(rows) else {
            continue;
        };
        orientations_seen.take(o, &anova);
    }
    orientations_seen.evidence(mv, Rows::Full)
}

/// The least blank area kept out of the print, in ridge periods squared (a square two periods a
/// side): a lone block of low evidence is chance.
const BLANK_AREA_PERIODS2: f64 = 4.0;

/// The blocks of the print that show no ridges (docs/fingerprints.md, "Ridges through a solid
/// wet area: the smear's own signature"). A block whose 3 x 3 neighbourhood is all print is a
/// seed where its F ratio (the best of [`ROW_ORIENTATIONS`]) is below `level` and its window's
/// mean sits off the print's middle gray on the ridges' side (darker, for `dark_ridges`) by at
/// least `off_middle` of the ridges' half swing and by more than its own noise: a wet smear is
/// as dark as the ridges, while faint ridges, however noisy, average to the middle gray. The
/// print's middle gray and the half swing are [`PrintGray`]'s. A seed also takes its neighbours
/// as far off the middle on that side: a block at the edge of a smear sees the ridges around it
/// through its window, but its mean is still the smear's. That is the side where the filter
/// invents ridges the gray image then confirms. Areas smaller than [`BLANK_AREA_PERIODS2`]
/// periods squared (`period`, the print's median) stay print. None when `level` is 0.
///
/// `evidence` is [`ridge_evidence`]'s; `measure` gives a block's [`measure_evidence`], asked (in
/// parallel) for the blocks whose F ratio or noise can decide and kept in `evidence`: the own
/// orientation's rows of a block off the middle on the ridges' side that could seed, then the
/// best of [`ROW_ORIENTATIONS`] for those whose own F ratio is below `level` (the best is at
/// least that), then for those of the seeds' neighbours off the middle on that side. The others'
/// F ratio and noise do not change what is blank.
pub(crate) fn blank_blocks(
    segmentation: &Segmentation,
    evidence: &mut RidgeEvidence,
    measure: impl Fn(usize, Rows) -> BlockEvidence + Sync,
    level: f64,
    off_middle: f64,
    period: f64,
    dark_ridges: bool,
) -> Vec<bool> {
    let grid = segmentation.grid;
    let (cols, rows) = (grid.cols as usize, grid.rows as usize);
    let RidgeEvidence {
        blocks: evidence,
        print,
        ..
    } = evidence;
    if level <= 0.0 || evidence.len() != grid.len() {
        return vec![false; grid.len()];
    }
    let inside = |b: usize| segmentation.inside[b];
    let ridges_side = if dark_ridges { -1 } else { 1 };
    // Off the middle on the ridges' side by the window's mean alone (or outside the print).
    let off = |evidence: &[BlockEvidence], b: usize| {
        inside(b) && print.side(&evidence[b], off_middle) == ridges_side
    };
    // And by more than the block's own noise.
    let side = |evidence: &[BlockEvidence], b: usize| {
        let e = &evidence[b];
        off(evidence, b) && (f64::from(e.mean) - print.middle).abs() >= f64::from(e.noise)
    };
    let neighbours = |b: usize| {
        let (i, j) = (b % cols, b / cols);
        (j.saturating_sub(1)..(j + 2).min(rows)).flat_map(move |jj| {
            (i.saturating_sub(1)..(i + 2).min(cols)).map(move |ii| jj * cols + ii)
        })
    };
    // Not at the print's rim, where the windows reach the background beyond the last ridges
    // (a light seed there took faint ridges along a partial print's cut).
    let interior = |b: usize| {
        let (i, j) = (b % cols, b / cols);
        i > 0 && j > 0 && i + 1 < cols && j + 1 < rows && neighbours(b).all(inside)
    };
    let complete = |evidence: &mut [BlockEvidence], wanted: Vec<usize>, rows: Rows| {
        let done: Vec<BlockEvidence> = wanted.par_iter().map(|&b| measure(b, rows)).collect();
        for (b, e) in wanted.into_iter().zip(done) {
            evidence[b] = e;
        }
    };
    let wanted = (0..grid.len())
        .filter(|&b| off(evidence, b) && interior(b) && evidence[b].rows == Rows::Mean)
        .collect();
    complete(evidence, wanted, Rows::Own);
    let can_seed = |evidence: &[BlockEvidence], b: usize| {
        off(evidence, b) && f64::from(evidence[b].f_ratio) < level && interior(b)
    };
    let wanted = (0..grid.len())
        .filter(|&b| can_seed(evidence, b) && evidence[b].rows != Rows::Full)
        .collect();
    complete(evidence, wanted, Rows::Full);
    let seeds: Vec<bool> = (0..grid.len())
        .map(|b| can_seed(evidence, b) && side(evidence, b))
        .collect();
    let near_seed = |b: usize| neighbours(b).any(|n| seeds[n]);
    let wanted = (0..grid.len())
        .filter(|&b| off(evidence, b) && near_seed(b) && evidence[b].rows != Rows::Full)
        .collect();
    complete(evidence, wanted, Rows::Full);
    let blank: Vec<bool> = (0..grid.len())
        .map(|b| side(evidence, b) && near_seed(b))
        .collect();
    let (label, sizes) = components(&blank, cols, rows, true);
    let block_area = f64::from(grid.block * grid.block);
    let least = BLANK_AREA_PERIODS2 * period * period;
    (0..grid.len())
        .map(|b| blank[b] && sizes[label[b]] as f64 * block_area >= least)
        .collect()
}

/// Closing, largest component, holes filled, opening, largest component (see the module doc).
fn clean(flags: &[bool], cols: usize, rows: usize) -> Vec<bool> {
    let closed = morph3(&morph3(flags, cols, rows, true), cols, rows, false);
    let mut mask = largest(&closed, cols, rows);
    // Background components that touch no edge of the grid are holes.
    let (label, sizes) = components(&mask, cols, rows, false);
    let mut open_to_edge = vec![false; sizes.len()];
    for j in 0..rows {
        for i in 0..cols {
            let l = label[j * cols + i];
            if l != usize::MAX && (i == 0 || j == 0 || i + 1 == cols || j + 1 == rows) {
                open_to_edge[l] = true;
            }
        }
    }
    for (m, &l) in mask.iter_mut().zip(&label) {
        if l != usize::MAX && !open_to_edge[l] {
            *m = true;
        }
    }
    let opened = morph3(&morph3(&mask, cols, rows, false), cols, rows, true);
    // The opening may leave nothing of a thin print: then keep the filled mask.
    if opened.iter().any(|&v| v) {
        largest(&opened, cols, rows)
    } else {
        mask
    }
}

/// The largest 4-connected component of `flags` (the first in raster order on ties).
fn largest(flags: &[bool], cols: usize, rows: usize) -> Vec<bool> {
    let (label, sizes) = components(flags, cols, rows, true);
    let Some(best) = (0..sizes.len()).max_by_key(|&c| (sizes[c], std::cmp::Reverse(c))) else {
        return vec![false; flags.len()];
    };
    label.iter().map(|&l| l == best).collect()
}

/// The `q` quantile of `values` (0 for none).
fn percentile(mut values: Vec<f32>, q: f64) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let k = ((values.len() - 1) as f64 * q).round() as usize;
    let v = if values.len() >= RADIX_SELECT_FROM {
        nth_smallest(&values, k)
    } else {
        *values.select_nth_unstable_by(k, f32::total_cmp).1
    };
    if v > 0.0 {
        v
    } else {
        upper_median_by(&mut values, f32::total_cmp).unwrap_or(0.0)
    }
}

/// From this many values on (an image's pixels, not its blocks) [`percentile`] counts instead
/// of selecting.
const RADIX_SELECT_FROM: usize = 1 << 16;

/// The `k`-th smallest of `values` (from 0; `k` below their number) in the order of
/// `f32::total_cmp`: the value `select_nth_unstable_by(k, f32::total_cmp)` puts at `k`, found by
/// counting the values' sort keys (the bits, ordered as `total_cmp` orders them) by their upper
/// [`NTH_HIGH_BITS`] bits, then selecting among the keys of that bin alone: two passes over the
/// values, nothing moved. An image's gradient magnitudes hold long runs of one bin (its flat
/// background's zeros), so the first pass counts the values into [`NTH_TABLES`] tables in turn
/// (whole numbers, added up at the end): a count does not wait for the one before it to be
/// stored. The tables are small (16 KB each), where one of every upper 16 bits (256 KB, as first
/// written) set the heap's high-water mark of a print.
fn nth_smallest(values: &[f32], k: usize) -> f32 {
    const BINS: usize = 1 << NTH_HIGH_BITS;
    const SHIFT: u32 = 32 - NTH_HIGH_BITS;
    let key = |v: f32| {
        let bits = v.to_bits();
        bits ^ (((bits as i32 >> 31) as u32) | 0x8000_0000)
    };
    let mut tables = vec![0u32; NTH_TABLES * BINS];
    // The bins of [`NTH_CHUNK`] values worked out side by side (vector lanes), then counted.
    let mut chunks = values.chunks_exact(NTH_CHUNK);
    let mut bins = [0u16; NTH_CHUNK];
    for chunk in &mut chunks {
        for (bin, &v) in bins.iter_mut().zip(chunk) {
            *bin = (key(v) >> SHIFT) as u16;
        }
        for turn in bins.chunks_exact(NTH_TABLES) {
            for (table, &bin) in tables.chunks_exact_mut(BINS).zip(turn) {
                table[usize::from(bin)] += 1;
            }
        }
    }
    let mut turns = chunks.remainder().chunks_exact(NTH_TABLES);
    for turn in &mut turns {
        for (table, &v) in tables.chunks_exact_mut(BINS).zip(turn) {
            table[(key(v) >> SHIFT) as usize] += 1;
        }
    }
    for (table, &v) in tables.chunks_exact_mut(BINS).zip(turns.remainder()) {
        table[(key(v) >> SHIFT) as usize] += 1;
    }
    // The bin of the `k`-th and its rank within the bin.
    let (mut high, mut rank) = (BINS, k);
    for bin in 0..BINS {
        let n: usize = (0..NTH_TABLES)
            .map(|t| tables[t * BINS + bin] as usize)
            .sum();
        if rank < n {
            high = bin;
            break;
        }
        rank -= n;
    }
    assert!(high < BINS, "k is below the number of values counted");
    // The bin's keys, in any order (the `rank`-th of them is the same): [`NTH_CHUNK`] values
    // tested side by side, and only a chunk that holds one of them looked at value by value
    // (about one value in twenty lies in the bin of the 95th percentile).
    let in_bin = |v: f32| (key(v) >> SHIFT) as usize == high;
    let mut keys = Vec::new();
    let mut chunks = values.chunks_exact(NTH_CHUNK);
    for chunk in &mut chunks {
        if chunk.iter().fold(false, |any, &v| any | in_bin(v)) {
            keys.extend(chunk.iter().filter(|&&v| in_bin(v)).map(|&v| key(v)));
        }
    }
    keys.extend(
        chunks
            .remainder()
            .iter()
            .filter(|&&v| in_bin(v))
            .map(|&v| key(v)),
    );
    let key = *keys.select_nth_unstable(rank).1;
    f32::from_bits(if key & 0x8000_0000 != 0 {
        key ^ 0x8000_0000
    } else {
        !key
    })
}

/// The upper bits of the sort keys [`nth_smallest`] counts by (sign, exponent and three bits of
/// the mantissa: bins an eighth of an octave wide).
const NTH_HIGH_BITS: u32 = 12;
/// How many tables [`nth_smallest`] counts into in turn.
const NTH_TABLES: usize = 4;
/// How many values [`nth_smallest`] works out the bins of at once.
const NTH_CHUNK: usize = 16;

#[cfg(test)]
mod tests {
    use super::*;

    /// The sum of four uniform draws on [-0.5, 0.5) from a xorshift generator (`state`): noise
    /// of mean 0 and variance 1/3, nearly Gaussian.
    fn four_uniforms(state: &mut u64) -> f32 {
        let mut sum = 0.0;
        for _ in 0..4 {
            *state ^= *state << 13;
            *state ^= *state >> 7;
            *state ^= *state << 17;
            sum += (*state >> 11) as f32 / (1u64 << 53) as f32 - 0.5;
        }
        sum
    }

    /// The disc's lines in whole numbers are the lines solved and checked at their ends, for
    /// centres on whole and half pixels (every block's), in and across the image's edges, at
    /// periods of any fraction and at whole reaches (a pixel centre on the circle).
    #[test]
    fn the_discs_lines_in_whole_numbers_are_the_solved_ones() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        let gray = Plane {
            width: 61,
            height: 47,
            values: vec![0.0; 61 * 47],
        };
        let mut lines = 0;
        for trial in 0..20_000 {
            let c = [next(160) as f64 / 2.0 - 10.0, next(130) as f64 / 2.0 - 10.0];
            let period = match trial % 3 {
                0 => 2.0 + next(1 << 20) as f64 / (1 << 16) as f64,
                // Whole reaches (pixel centres on the circle, up to the rounding of the root).
                1 => f64::from(2 + next(20) as u32) / (1.0 + ROW_LENGTH * ROW_LENGTH).sqrt(),
                _ => f64::from(2 + next(24) as u32),
            };
            let disc = Disc::new(&gray, c, period);
            let halves = disc.halves.expect("a centre on whole or half pixels");
            for y in disc.rows() {
                assert_eq!(
                    disc.whole_line(y, halves),
                    disc.line_solved(y),
                    "centre {c:?}, period {period}, line {y}"
                );
                lines += 1;
            }
        }
        assert!(lines > 100_000, "{lines}");
        // A centre off the half pixels takes the solved lines.
        assert!(Disc::new(&gray, [10.3, 12.0], 9.0).halves.is_none());
    }

    /// [`whole_sqrt`] is the whole square root at and either side of every square up to 2¹⁴,
    /// of random squares up to 2⁵⁰ and beyond, and of every number up to 2¹⁶.
    #[test]
    fn whole_square_roots_are_exact() {
        let check = |n: i64| {
            let s = whole_sqrt(n);
            assert!(s * s <= n && (s + 1) * (s + 1) > n, "{n}: {s}");
        };
        (0..1 << 16).for_each(check);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let ks = (1..1i64 << 14).chain((0..100_000).map(|_| 1 + (next() % (1 << 27)) as i64));
        for k in ks {
            for n in [k * k - 1, k * k, k * k + 1, k * k + 2 * k] {
                check(n);
            }
        }
    }

    /// [`nth_smallest`] as it was: one table of the keys' upper 16 bits, then one of the lower
    /// 16 bits of that bin's keys.
    fn nth_smallest_by_16_bits(values: &[f32], k: usize) -> f32 {
        let key = |v: f32| {
            let bits = v.to_bits();
            bits ^ (((bits as i32 >> 31) as u32) | 0x8000_0000)
        };
        let find = |counts: &[u32], mut k: usize| -> (u32, usize) {
            for (bin, &n) in counts.iter().enumerate() {
                if k < n as usize {
                    return (bin as u32, k);
                }
                k -= n as usize;
            }
            unreachable!("k is below the number of values counted")
        };
        let mut counts = vec![0u32; 1 << 16];
        for &v in values {
            counts[(key(v) >> 16) as usize] += 1;
        }
        let (high, k) = find(&counts, k);
        counts.iter_mut().for_each(|n| *n = 0);
        for &v in values {
            let key = key(v);
            if key >> 16 == high {
                counts[(key & 0xFFFF) as usize] += 1;
            }
        }
        let (low, _) = find(&counts, k);
        let key = high << 16 | low;
        f32::from_bits(if key & 0x8000_0000 != 0 {
            key ^ 0x8000_0000
        } else {
            !key
        })
    }

    /// The selection within the upper bits' bin is the two tables of 16 bits it replaced, bit for
    /// bit: gradient magnitudes (runs of zeros as a flat background gives, then a spread),
    /// values with many ties, any bits, and the special values, at many ranks, for lengths that
    /// are and are not multiples of the tables.
    #[test]
    fn the_nth_in_its_bin_is_the_nth_by_16_bits() {
        let mut lcg = crate::synth::lcg(3535u64);
        let mut next = move || (lcg() >> 33) as u32;
        let special = [
            0.0f32,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        for case in 0..40 {
            let len = 1 + (next() % 20_000) as usize;
            let kind = case % 4;
            let mut zeros = 0;
            let values: Vec<f32> = (0..len)
                .map(|_| {
                    if kind == 0 && zeros == 0 && next() % 50 == 0 {
                        zeros = next() % 400;
                    }
                    if zeros > 0 {
                        zeros -= 1;
                        return 0.0;
                    }
                    match kind {
                        0 => (next() % 100_000) as f32 / 37.0,
                        1 => (next() % 7) as f32,
                        2 => f32::from_bits(next() << 1 | next() & 1),
                        _ => match next() % 4 {
                            0 => special[next() as usize % special.len()],
                            _ => (next() % 2000) as f32 - 1000.0,
                        },
                    }
                })
                .collect();
            for k in (0..len).step_by(1 + len / 50).chain([len - 1]) {
                assert_eq!(
                    nth_smallest(&values, k).to_bits(),
                    nth_smallest_by_16_bits(&values, k).to_bits(),
                    "case {case}, k {k} of {len}"
                );
            }
        }
    }

    #[test]
    fn the_nth_by_counting_is_the_nth_selected() {
        // Pseudo-random values (a fixed linear congruential sequence): gradient magnitudes,
        // values with many ties, both signs, both zeros, infinities and NaNs.
        let mut lcg = crate::synth::lcg(4242u64);
        let mut next = move || (lcg() >> 33) as u32;
        let special = [
            0.0f32,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        for kind in 0..4 {
            let values: Vec<f32> = (0..3000)
                .map(|_| match kind {
                    0 => (next() % 100_000) as f32 / 37.0,
                    1 => (next() % 7) as f32,
                    2 => f32::from_bits(next() << 1 | next() & 1),
                    _ => match next() % 4 {
                        0 => special[next() as usize % special.len()],
                        _ => (next() % 2000) as f32 - 1000.0,
                    },
                })
                .collect();
            for k in (0..values.len()).step_by(97).chain([values.len() - 1]) {
                let mut sorted = values.clone();
                let selected = *sorted.select_nth_unstable_by(k, f32::total_cmp).1;
                assert_eq!(
                    nth_smallest(&values, k).to_bits(),
                    selected.to_bits(),
                    "kind {kind}, k {k}"
                );
            }
        }
    }

    /// The rewritten rows' F ratio agrees with the straightforward one (the plane's sums are
    /// taken in another order, so the last bits may differ): random gray levels (smooth ridges,
    /// noise, flat), periods from 2 to 20 px, any orientation, centres inside, at the edges and
    /// past them; on whole gray levels the window's mean is the same bits, on every case the
    /// own orientation alone gives the same mean and amplitude as all of them, and an F ratio
    /// at most theirs.
    #[test]
    fn the_rows_f_ratio_agrees_with_the_reference() {
        let mut lcg = crate::synth::lcg(35u64);
        let mut uniform = move || (lcg() >> 11) as f64 / (1u64 << 53) as f64;
        let (width, height) = (61u32, 47u32);
        let mut scratch = EvidenceScratch::default();
        let (mut tuples, mut rows) = (Vec::new(), Vec::new());
        for case in 0..300 {
            let (period, theta) = (2.0 + 18.0 * uniform(), 7.0 * uniform() - 3.5);
            let values: Vec<f32> = (0..width * height)
                .map(|k| {
                    let (x, y) = (f64::from(k % width), f64::from(k / width));
                    let ridge = ((x * theta.cos() + y * theta.sin()) / period * 6.3).sin();
                    match case % 3 {
                        0 => (128.0 + 60.0 * ridge + 20.0 * uniform()).round() as f32,
                        1 => (255.0 * uniform()) as f32,
                        _ => 77.0,
                    }
                })
                .collect();
            let plane = Plane {
                width,
                height,
                values,
            };
            let c = [
                (f64::from(width) + 20.0) * uniform() - 10.0,
                (f64::from(height) + 20.0) * uniform() - 10.0,
            ];
            let c = if case % 4 == 0 { c.map(f64::round) } else { c };
            // Orientations whose rows' normals lie on the axes (slopes of exactly 0) and any other.
            let own = match case % 5 {
                0 => 0.0,
                1 => std::f64::consts::FRAC_PI_2,
                _ => 4.0 * uniform() - 2.0,
            };
            let whole = whole_levels(&plane);
            let new = row_f_ratio(&plane, whole, c, own, period, Rows::Full, &mut scratch);
            let old = row_f_ratio_reference(&plane, c, own, period, &mut tuples, &mut rows);
            let own_only = row_f_ratio(&plane, whole, c, own, period, Rows::Own, &mut scratch);
            let mean_only = row_f_ratio(&plane, whole, c, own, period, Rows::Mean, &mut scratch);
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()) + 1e-6;
            assert!(
                close(new.f_ratio, old.f_ratio)
                    && close(new.mean, old.mean)
                    && close(new.amplitude, old.amplitude)
                    && close(new.noise, old.noise)
                    && new.rows == old.rows,
                "case {case}: {new:?} vs {old:?}"
            );
            if case % 3 != 1 {
                assert_eq!(new.mean.to_bits(), old.mean.to_bits(), "case {case}");
            }
            assert!(
                own_only.mean.to_bits() == new.mean.to_bits()
                    && own_only.amplitude.to_bits() == new.amplitude.to_bits()
                    && own_only.f_ratio <= new.f_ratio
                    && own_only.rows == Rows::Own,
                "case {case}: {own_only:?} vs {new:?}"
            );
            assert_eq!(
                mean_only,
                BlockEvidence {
                    mean: new.mean,
                    rows: Rows::Mean,
                    ..BlockEvidence::default()
                },
                "case {case}"
            );
            // From the lines' sums, where the levels are whole: the same bits.
            if let Some(prefix) = line_prefix_sums(&plane).filter(|_| whole) {
                assert_eq!(
                    window_mean(&plane, &prefix, c, period),
                    mean_only,
                    "case {case}"
                );
            }
        }
    }

    /// The rows' F ratio with each line's pixels in AVX lanes (where the CPU has AVX2) is the
    /// one-by-one loop's bit for bit: random gray levels (whole levels of smooth ridges and
    /// noise, fractional levels, flat), periods from 2 to 25 px, any orientation, centres inside,
    /// at the edges and past them, the own orientation alone and all of them.
    #[test]
    fn the_rows_in_lanes_are_the_rows_one_by_one() {
        let mut lcg = crate::synth::lcg(3535u64);
        let mut uniform = move || (lcg() >> 11) as f64 / (1u64 << 53) as f64;
        let (width, height) = (73u32, 59u32);
        let mut scratch = EvidenceScratch::default();
        let bits = |e: BlockEvidence| {
            (
                e.f_ratio.to_bits(),
                e.mean.to_bits(),
                e.amplitude.to_bits(),
                e.noise.to_bits(),
                e.rows,
            )
        };
        let mut compared = 0;
        for case in 0..400 {
            let (period, theta) = (2.0 + 23.0 * uniform(), 7.0 * uniform() - 3.5);
            let values: Vec<f32> = (0..width * height)
                .map(|k| {
                    let (x, y) = (f64::from(k % width), f64::from(k / width));
                    let ridge = ((x * theta.cos() + y * theta.sin()) / period * 6.3).sin();
                    match case % 4 {
                        0 => (128.0 + 60.0 * ridge + 20.0 * uniform()).round() as f32,
                        1 => (255.0 * uniform()) as f32,
                        2 => (128.0 + 60.0 * ridge + 20.0 * uniform()) as f32,
                        _ => 77.0,
                    }
                })
                .collect();
            let plane = Plane {
                width,
                height,
                values,
            };
            let c = [
                (f64::from(width) + 20.0) * uniform() - 10.0,
                (f64::from(height) + 20.0) * uniform() - 10.0,
            ];
            let c = if case % 5 == 0 { c.map(f64::round) } else { c };
            let own = match case % 6 {
                0 => 0.0,
                1 => std::f64::consts::FRAC_PI_2,
                _ => 4.0 * uniform() - 2.0,
            };
            // The disc's sums in lanes on whole levels only.
            let whole = whole_levels(&plane);
            assert_eq!(whole, case % 4 != 1 && case % 4 != 2, "case {case}");
            for measured in [Rows::Mean, Rows::Own, Rows::Full] {
                let one_by_one = row_f_ratio_lanes::<false>(
                    &plane,
                    whole,
                    c,
                    own,
                    period,
                    measured,
                    &mut scratch,
                );
                let chosen = row_f_ratio(&plane, whole, c, own, period, measured, &mut scratch);
                assert_eq!(bits(chosen), bits(one_by_one), "case {case}");
                #[cfg(target_arch = "x86_64")]
                if crate::fingerprint::math::wide_lanes() {
                    // SAFETY: the CPU has AVX2.
                    let wide = unsafe {
                        row_f_ratio_wide(&plane, whole, c, own, period, measured, &mut scratch)
                    };
                    assert_eq!(bits(wide), bits(one_by_one), "case {case}");
                }
                compared += usize::from(one_by_one.f_ratio > 0.0);
                if measured == Rows::Mean && whole {
                    let prefix = line_prefix_sums(&plane).expect("a narrow image");
                    let mean = window_mean(&plane, &prefix, c, period);
                    assert_eq!(bits(mean), bits(one_by_one), "case {case}");
                    #[cfg(target_arch = "x86_64")]
                    if crate::fingerprint::math::wide_lanes() {
                        // SAFETY: the CPU has AVX2.
                        let wide = unsafe { window_mean_wide(&plane, &prefix, c, period) };
                        assert_eq!(bits(wide), bits(one_by_one), "case {case}");
                    }
                    assert_eq!(
                        bits(window_mean_lanes(&plane, &prefix, c, period)),
                        bits(one_by_one),
                        "case {case}"
                    );
                }
            }
        }
        // Most cases have a window with rows to compare.
        assert!(compared > 500, "{compared}");
    }

    use crate::fingerprint::math::gradients;
    use crate::fingerprint::tests::ridges_in_disk;

    #[test]
    fn the_print_is_the_disk_of_ridges() {
        let gray = ridges_in_disk(160, 160, 9.0, 0.4, [80.0, 80.0], 50.0);
        let (magnitude, gradients) = gradients(&gray, 8);
        let s = segment(magnitude, &gradients, &FingerprintParams::default());
        assert!(s.contains_pixel(80, 80));
        assert!(s.contains_pixel(80, 40), "inside the disk near its edge");
        assert!(!s.contains_pixel(5, 5), "corner is background");
        assert!(!s.contains_pixel(80, 150));
        // About the disk's area, in blocks of 64 px.
        let disk = std::f64::consts::PI * 50.0 * 50.0 / 64.0;
        let area = s.area_blocks() as f64;
        assert!((area - disk).abs() < 0.25 * disk, "{area} vs {disk}");
    }

    /// Faint ridges in a disk under noise everywhere: the gradient magnitude takes the noise for
    /// print, the Gabor response does not.
    #[test]
    fn the_response_drops_noise_the_gradient_keeps() {
        let mut gray = ridges_in_disk(192, 192, 9.0, 0.4, [96.0, 96.0], 56.0);
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        for v in gray.values.iter_mut() {
            // Faint ridges (40 % of the test pattern's depth) on a flat 200, plus noise.
            let base = if *v == 200.0 {
                200.0
            } else {
                128.0 + 0.4 * (*v - 128.0)
            };
            *v = base + 50.0 * four_uniforms(&mut state);
        }
        let params = FingerprintParams::default();
        let smoothed = crate::fingerprint::math::gaussian_blur(&gray, params.gradient_sigma);
        let (magnitude, gradients) = gradients(&smoothed, 8);
        let first = segment(magnitude, &gradients, &params);
        assert!(
            first.contains_pixel(12, 12),
            "the gradient keeps the noisy corner"
        );
        let orientation = crate::fingerprint::orientation::orientation(&gradients, &first, &params);
        let periods =
            crate::fingerprint::frequency::ridge_periods(&smoothed, &first, &orientation, &params);
        let enhanced = crate::fingerprint::enhance::enhance(
            gray,
            &first,
            &orientation,
            &periods,
            &params,
            true,
        );
        let (refined, rms) = refine(&first, &enhanced, params.response_threshold, &[]);
        assert_eq!(rms, block_rms(&enhanced, &refined));
        assert!(refined.contains_pixel(96, 96) && refined.contains_pixel(96, 50));
        assert!(!refined.contains_pixel(12, 12) && !refined.contains_pixel(180, 96));
        let disk = std::f64::consts::PI * 56.0 * 56.0 / 64.0;
        let area = refined.area_blocks() as f64;
        // The disk and a rim of noise around it, against most of the image before.
        assert!(area >= 0.9 * disk && area <= 1.5 * disk, "{area} vs {disk}");
        assert!(first.area_blocks() as f64 > 2.0 * area);
        assert_eq!(
            refine(&first, &enhanced, 0.0, &[]),
            (first.clone(), block_rms(&enhanced, &first))
        );
    }

    /// The rows' F ratio: high on ridges, even faint ones (10 % of the depth) under noise; about
    /// 1 on noise alone; 0 on a flat patch.
    #[test]
    fn ridges_show_in_the_rows_and_flat_or_noisy_patches_do_not() {
        let (size, period, theta) = (96u32, 9.0f64, 0.4f64);
        let grid = BlockGrid::new(size, size, 8);
        let (s, field, periods) =
            crate::fingerprint::tests::uniform_print(grid, theta as f32, period as f32);
        let ridges = ridges_in_disk(size, size, period, theta, [48.0, 48.0], 200.0);
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut noise = |sigma: f32| sigma * four_uniforms(&mut state) * 3f32.sqrt();
        let faint: Vec<f32> = ridges
            .values
            .iter()
            .map(|&v| 128.0 + 0.1 * (v - 128.0))
            .collect();
        let faint_noisy: Vec<f32> = faint.iter().map(|&v| v + noise(5.0)).collect();
        let flat = vec![30.0f32; (size * size) as usize];
        let noisy: Vec<f32> = flat.iter().map(|&v| v + noise(10.0)).collect();
        let middle = grid.index(6, 6);
        let evidence = |values: Vec<f32>| {
            let plane = Plane {
                width: size,
                height: size,
                values,
            };
            let whole = whole_levels(&plane);
            let evidence =
                measure_evidence(&plane, whole, &s, &field, &periods, middle, Rows::Full);
            assert_eq!(evidence.rows, Rows::Full);
            evidence.f_ratio
        };
        let (clear, faint, faint_noisy, flat, noisy) = (
            evidence(ridges.values.clone()),
            evidence(faint),
            evidence(faint_noisy),
            evidence(flat),
            evidence(noisy),
        );
        assert!(clear > 100.0 && faint > 100.0, "{clear} {faint}");
        assert!(faint_noisy > 5.0, "{faint_noisy}");
        assert!(flat < 0.01, "{flat}");
        assert!((0.5..3.0).contains(&noisy), "{noisy}");
    }

    /// The blank blocks found from the lattice's evidence, completed only where it can decide,
    /// are those found from every block's full evidence with the same middle gray and swing: a
    /// print of straight ridges with a solid dark disc (the ridges' level) under noise, both
    /// polarities.
    #[test]
    fn blank_blocks_from_the_completed_evidence_are_those_from_the_full() {
        let (size, period, theta) = (160u32, 9.0f64, 0.4f64);
        let grid = BlockGrid::new(size, size, 8);
        let (s, field, periods) =
            crate::fingerprint::tests::uniform_print(grid, theta as f32, period as f32);
        let mut gray = ridges_in_disk(size, size, period, theta, [80.0, 80.0], 400.0);
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        for (k, v) in gray.values.iter_mut().enumerate() {
            let (dx, dy) = ((k % 160) as f32 - 80.0, (k / 160) as f32 - 80.0);
            if dx * dx + dy * dy <= 27.0 * 27.0 {
                *v = 28.0;
            }
            *v = (*v + 10.0 * 3f32.sqrt() * four_uniforms(&mut state)).round();
        }
        let asked = std::sync::atomic::AtomicUsize::new(0);
        let whole = whole_levels(&gray);
        let measure = |b, rows| {
            asked.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            measure_evidence(&gray, whole, &s, &field, &periods, b, rows)
        };
        let mut completed = ridge_evidence(&gray, whole, &s, &field, &periods);
        let mut every = RidgeEvidence {
            blocks: (0..grid.len()).map(|b| measure(b, Rows::Full)).collect(),
            whole,
            print: PrintGray {
                middle: completed.print.middle,
                swing: completed.print.swing,
            },
        };
        asked.store(0, std::sync::atomic::Ordering::Relaxed);
        for dark in [true, false] {
            let lazy = blank_blocks(&s, &mut completed, measure, 2.0, 0.5, period, dark);
            let eager = blank_blocks(&s, &mut every, measure, 2.0, 0.5, period, dark);
            assert_eq!(lazy, eager, "dark ridges {dark}");
            // The disc's centre is blank for dark ridges only.
            assert_eq!(lazy[grid.index(10, 10)], dark, "dark ridges {dark}");
        }
        let asked = asked.into_inner();
        assert!(
            asked > 0 && asked < grid.len() / 4,
            "{asked} of {} blocks completed",
            grid.len()
        );
    }

    /// The rows are measured on the lattice two periods apart (every second block each way at a
    /// period of 9 px in blocks of 8) and nowhere else, each block's mean everywhere, all the
    /// same bits as the block measured alone; on even ridges under noise the lattice's swing is
    /// within 5 % of every block's and the middle gray the same.
    #[test]
    fn the_amplitude_is_measured_on_a_lattice_two_periods_apart() {
        let (size, period, theta) = (160u32, 9.0f64, 0.4f64);
        let grid = BlockGrid::new(size, size, 8);
        let (s, field, periods) =
            crate::fingerprint::tests::uniform_print(grid, theta as f32, period as f32);
        let mut gray = ridges_in_disk(size, size, period, theta, [80.0, 80.0], 400.0);
        let mut state = 0x0DDB_1A5E_5BAD_5EEDu64;
        for v in gray.values.iter_mut() {
            *v = (*v + 10.0 * 3f32.sqrt() * four_uniforms(&mut state)).round();
        }
        let whole = whole_levels(&gray);
        assert!(whole);
        let evidence = ridge_evidence(&gray, whole, &s, &field, &periods);
        let cols = grid.cols as usize;
        let own: Vec<BlockEvidence> = (0..grid.len())
            .map(|b| measure_evidence(&gray, whole, &s, &field, &periods, b, Rows::Own))
            .collect();
        for (b, (e, own)) in evidence.blocks.iter().zip(&own).enumerate() {
            if (b % cols) % 2 == 0 && (b / cols) % 2 == 0 {
                assert_eq!(e, own, "block {b}");
            } else {
                let mean_only = BlockEvidence {
                    mean: own.mean,
                    rows: Rows::Mean,
                    ..BlockEvidence::default()
                };
                assert_eq!(*e, mean_only, "block {b}");
            }
        }
        let every = PrintGray::of(&s, &own);
        assert_eq!(evidence.print.middle.to_bits(), every.middle.to_bits());
        let (lattice, all) = (evidence.print.swing, every.swing);
        assert!(
            lattice > 0.0 && (lattice - all).abs() <= 0.05 * all,
            "{lattice} {all}"
        );
    }

    /// A dark flat core takes its dark rim when the ridges are dark, and is print when they are
    /// light; a lone flat block, a faint patch at the middle gray and a dark ridged block stay
    /// print.
    #[test]
    fn blank_blocks_are_flat_and_off_the_middle_gray() {
        let grid = BlockGrid::new(96, 96, 8);
        let (s, _, _) = crate::fingerprint::tests::uniform_print(grid, 0.0, 8.0);
        let ridges = BlockEvidence {
            f_ratio: 100.0,
            mean: 128.0,
            amplitude: 50.0,
            noise: 10.0,
            rows: Rows::Full,
        };
        let mut evidence = vec![ridges; grid.len()];
        let at = |i: usize, j: usize| grid.index(i, j);
        // The swing is 50 √2 ≈ 71: a smear at 28 is 1.4 of it below the middle.
        let smear = BlockEvidence {
            f_ratio: 1.0,
            mean: 28.0,
            amplitude: 0.0,
            noise: 10.0,
            rows: Rows::Full,
        };
        for j in 4..7 {
            for i in 4..7 {
                evidence[at(i, j)] = smear;
            }
        }
        // The smear's rim: dark, but its windows see the ridges around.
        for i in 3..8 {
            for j in [3, 7] {
                evidence[at(i, j)].mean = 60.0;
                evidence[at(j, i)].mean = 60.0;
            }
        }
        evidence[at(1, 10)] = smear;
        for (i, j) in [(9, 1), (10, 1), (9, 2), (10, 2)] {
            evidence[at(i, j)] = BlockEvidence {
                f_ratio: 1.5,
                mean: 135.0,
                amplitude: 3.0,
                noise: 10.0,
                rows: Rows::Full,
            };
        }
        evidence[at(10, 10)].mean = 28.0;
        // Every block's evidence is full: none is asked for.
        let full = |_, _| -> BlockEvidence { unreachable!("every block's evidence is full") };
        let mut evidence = RidgeEvidence::of(&s, evidence, true);
        let dark = blank_blocks(&s, &mut evidence, full, 2.0, 0.5, 8.0, true);
        let light = blank_blocks(&s, &mut evidence, full, 2.0, 0.5, 8.0, false);
        for j in 0..12 {
            for i in 0..12 {
                let rim = (3..8).contains(&i) && (3..8).contains(&j);
                assert_eq!(dark[at(i, j)], rim, "dark ridges, block {i}, {j}");
                assert!(!light[at(i, j)], "light ridges, block {i}, {j}");
            }
        }
        assert!(blank_blocks(&s, &mut evidence, full, 0.0, 0.5, 8.0, true)
            .iter()
            .all(|&b| !b));
    }

    #[test]
    fn holes_are_filled_and_specks_dropped() {
        // 7 x 7 blocks: a ring with a hole in the middle, and a lone block apart.
        let mut f = vec![false; 49];
        for j in 1..6 {
            for i in 1..5 {
                f[j * 7 + i] = true;
            }
        }
        f[3 * 7 + 2] = false;
        f[6] = true;
        let m = clean(&f, 7, 7);
        assert!(m[3 * 7 + 2], "hole filled");
        assert!(!m[6], "speck dropped");
    }

    #[test]
    fn a_flat_image_has_no_print() {
        let flat = Plane {
            width: 32,
            height: 32,
            values: vec![100.0; 1024],
        };
        let (magnitude, gradients) = gradients(&flat, 8);
        let s = segment(magnitude, &gradients, &FingerprintParams::default());
        assert_eq!(s.area_blocks(), 0);
    }
}
