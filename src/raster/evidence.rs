//! What the gray image says before it is binarized (docs/design.md, "The front end"): which side
//! of a split is made of strokes, how wide they are, and whether one global level separates ink
//! from paper everywhere or the light varies across the image.
//!
//! Both measurements look at a sample of the image, not at every pixel, so deciding costs a
//! small share of binarizing.

use rayon::prelude::*;

use crate::gray::GrayView;

/// Lattice samples the stroke evidence aims for; the step between sampled rows and columns is
/// chosen to give about this many.
pub(crate) const LATTICE_SAMPLES: usize = 65_536;

/// The lattice samples of a print's polarity decision (docs/fingerprints.md, "Speed: the
/// polarity's lattice"): a quarter of [`LATTICE_SAMPLES`]. A print's ridges and valleys repeat
/// every 5 to 20 px in every part of it, so a lattice two or three pixels apart still meets each
/// ridge and valley several times along every sampled row and column, where a page's text may
/// fill only a corner of it.
pub(crate) const PRINT_LATTICE_SAMPLES: usize = LATTICE_SAMPLES / 4;

/// Chord statistics of the two sides of a split.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Chords {
    /// Mean chord over the dark side's samples, px (0 when the side is empty).
    pub dark_mean: f64,
    /// Mean chord over the light side's samples, px.
    pub light_mean: f64,
    /// Median chord of the dark side, px.
    pub dark_median: f64,
    /// Median chord of the light side, px.
    pub light_median: f64,
    /// The most common chord of the dark side, px (the smaller of equally common ones): the
    /// stroke width even where a photo or a banner puts a wide spread of long chords on the
    /// side.
    pub dark_mode: f64,
    /// The most common chord of the light side, px.
    pub light_mode: f64,
    /// The lower quartile of the chords of the side with the smaller one, px: the stroke width
    /// even where a badly placed split puts large areas of paper on the ink's side.
    pub thinner_quartile: f64,
}

/// The chord of a pixel is the shorter of its horizontal and vertical runs of pixels of its own
/// side: about the stroke width on a stroke (in any direction but the stroke's own, where the
/// run is long), the gap to the next stroke on the paper. Measured at every `step`-th pixel of
/// every `step`-th row, `step` chosen for about [`LATTICE_SAMPLES`] samples.
pub(crate) fn chords(dark: &[bool], width: usize, height: usize) -> Chords {
    chords_sampled(dark, width, height, LATTICE_SAMPLES)
}

/// [`chords`] with `step` chosen for about `samples` lattice samples.
///
/// With AVX2 at run time the routine is compiled for it (the vertical passes eight lanes of
/// `u32` a vector instruction instead of four): whole numbers, so the same chords.
pub(crate) fn chords_sampled(dark: &[bool], width: usize, height: usize, samples: usize) -> Chords {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { chords_wide(dark, width, height, samples) };
    }
    chords_lanes(dark, width, height, samples)
}

/// [`chords`] compiled for AVX2.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn chords_wide(dark: &[bool], width: usize, height: usize, samples: usize) -> Chords {
    chords_lanes(dark, width, height, samples)
}

/// [`chords`]' work, inlined into the version the CPU runs.
#[inline(always)]
fn chords_lanes(dark: &[bool], width: usize, height: usize, samples: usize) -> Chords {
    if width == 0 || height == 0 {
        return Chords::default();
    }
    let step = ((width * height / samples.max(1)) as f64)
        .sqrt()
        .floor()
        .max(1.0) as usize;
    let (cols, rows) = (width.div_ceil(step), height.div_ceil(step));
    // Vertical runs at the lattice points, row-major: the sampled columns' values row by row,
    // each one's run length so far down the image, then each run's length carried back up
    // (every row a pass along it, in vector lanes, rather than a walk down each column).
    // Every column sampled (a small image): the image's own values.
    let sampled;
    let values = if step == 1 {
        &dark[..height * width]
    } else {
        let mut values = vec![false; height * cols];
        for (y, out) in values.chunks_exact_mut(cols).enumerate() {
            let row = &dark[y * width..(y + 1) * width];
            for (o, &v) in out.iter_mut().zip(row.iter().step_by(step)) {
                *o = v;
            }
        }
        sampled = values;
        &sampled[..]
    };
    let mut vertical = vec![1u32; height * cols];
    for y in 1..height {
        let (above, below) = vertical.split_at_mut(y * cols);
        let (above, below) = (&above[(y - 1) * cols..], &mut below[..cols]);
        let (a, b) = (
            &values[(y - 1) * cols..y * cols],
            &values[y * cols..(y + 1) * cols],
        );
        for ((out, &up), (&a, &b)) in below.iter_mut().zip(above).zip(a.iter().zip(b)) {
            // `if a == b { up + 1 } else { 1 }`, written so that the compiler puts it in lanes.
            *out = 1 + up * u32::from(a == b);
        }
    }
    for y in (0..height - 1).rev() {
        let (above, below) = vertical.split_at_mut((y + 1) * cols);
        let (above, below) = (&mut above[y * cols..], &below[..cols]);
        let (a, b) = (
            &values[y * cols..(y + 1) * cols],
            &values[(y + 1) * cols..(y + 2) * cols],
        );
        for ((out, &down), (&a, &b)) in above.iter_mut().zip(below).zip(a.iter().zip(b)) {
            // `if a == b { down } else { *out }` as a mask, which the compiler puts in lanes.
            let same = u32::from(a == b).wrapping_neg();
            *out = (down & same) | (*out & !same);
        }
    }
    // Each side's chords counted by length (a chord is at most the image's longer side): the
    // statistics below are those of the sorted chords, read off the counts.
    // The light side's counts first, then the dark side's. Each sampled row's horizontal runs
    // are found and their lattice points counted as each run is found: a point's chord is the
    // shorter of its run's length and its vertical run (the counts are whole numbers, the same
    // in any order, so groups of rows are counted apart and added up).
    let longest = width.max(height);
    let count_row = |mut counts: Vec<usize>, r: usize| {
        let row = &dark[r * step * width..(r * step + 1) * width];
        let down = &vertical[r * step * cols..(r * step + 1) * cols];
        lattice_runs(row, step, |lattice, across, on| {
            let side = &mut counts[usize::from(on) * (longest + 1)..][..longest + 1];
            for &down in &down[lattice] {
                side[across.min(down) as usize] += 1;
            }
        });
        counts
    };
    let counts = (0..rows)
        .into_par_iter()
        .fold(|| vec![0usize; 2 * (longest + 1)], count_row)
        .reduce_with(|mut a, b| {
            a.iter_mut().zip(&b).for_each(|(a, b)| *a += b);
            a
        })
        .unwrap_or_else(|| vec![0usize; 2 * (longest + 1)]);
    let (light_counts, dark_counts) = counts.split_at(longest + 1);
    let dark_side = Counted::new(dark_counts);
    let light_side = Counted::new(light_counts);
    let thinner_quartile = dark_side.quartile().min(light_side.quartile());
    Chords {
        dark_mean: dark_side.mean(),
        light_mean: light_side.mean(),
        dark_median: dark_side.median(),
        light_median: light_side.median(),
        dark_mode: dark_side.mode(),
        light_mode: light_side.mode(),
        thinner_quartile: if thinner_quartile.is_finite() {
            thinner_quartile
        } else {
            0.0
        },
    }
}

/// Calls `each(lattice, length, value)` for every run of equal values of the line `row`, in order:
/// `lattice` the indices `k` of the elements `k * step` the run holds. Each run's end is looked
/// for eight pixels at a time (the first byte of a word that differs from the run's value), then
/// pixel by pixel within the last word.
#[inline(always)]
fn lattice_runs(
    row: &[bool],
    step: usize,
    mut each: impl FnMut(std::ops::Range<usize>, u32, bool),
) {
    // SAFETY: a `bool` is one byte holding 0 or 1, a valid `u8`; the slice is read only.
    let bytes: &[u8] = unsafe { std::slice::from_raw_parts(row.as_ptr().cast(), row.len()) };
    let len = bytes.len();
    let mut start = 0;
    while start < len {
        let v = bytes[start];
        let mut end = start + 1;
        let splat = u64::from(v) * 0x0101_0101_0101_0101;
        while let Some(word) = bytes[end..].first_chunk::<8>() {
            let differ = u64::from_le_bytes(*word) ^ splat;
            if differ != 0 {
                end += differ.trailing_zeros() as usize / 8;
                break;
            }
            end += 8;
        }
        while end < len && bytes[end] == v {
            end += 1;
        }
        // The lattice elements in start..end.
        let lattice = if step == 1 {
            start..end
        } else {
            start.div_ceil(step)..end.div_ceil(step)
        };
        each(lattice, (end - start) as u32, v != 0);
        start = end;
    }
}

/// One side's chords as counts by length.
struct Counted<'a> {
    counts: &'a [usize],
    total: usize,
}

impl<'a> Counted<'a> {
    fn new(counts: &'a [usize]) -> Self {
        Counted {
            counts,
            total: counts.iter().sum(),
        }
    }

    /// The `k`-th smallest chord (from 0), `k` below the total.
    fn nth(&self, k: usize) -> f64 {
        let mut seen = 0;
        for (v, &n) in self.counts.iter().enumerate() {
            seen += n;
            if seen > k {
                return v as f64;
            }
        }
        0.0
    }

    /// The chord at a quarter of the sorted chords, infinite for none.
    fn quartile(&self) -> f64 {
        if self.total == 0 {
            f64::INFINITY
        } else {
            self.nth(self.total / 4)
        }
    }

    /// The upper median, 0 for none.
    fn median(&self) -> f64 {
        if self.total == 0 {
            0.0
        } else {
            self.nth(self.total / 2)
        }
    }

    /// The mean, 0 for none (the sum of whole numbers is exact in `f64`).
    fn mean(&self) -> f64 {
        if self.total == 0 {
            return 0.0;
        }
        let sum: usize = self.counts.iter().enumerate().map(|(v, &n)| v * n).sum();
        sum as f64 / self.total as f64
    }

    /// The most common chord (the smallest of equally common ones), 0 for none.
    fn mode(&self) -> f64 {
        let (mut best, mut best_count) = (0, 0);
        for (v, &c) in self.counts.iter().enumerate() {
            if c > best_count {
                (best, best_count) = (v, c);
            }
        }
        best as f64
    }
}

/// The length of the run each element belongs to.
pub(super) fn run_lengths(values: impl Iterator<Item = bool>) -> Vec<u32> {
    let mut runs = Vec::new();
    let (mut current, mut start, mut n) = (None, 0usize, 0usize);
    for v in values {
        if current != Some(v) {
            runs.extend(std::iter::repeat_n((n - start) as u32, n - start));
            (current, start) = (Some(v), n);
        }
        n += 1;
    }
    runs.extend(std::iter::repeat_n((n - start) as u32, n - start));
    runs
}

/// The polarity evidence of a split into dark and light sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PolarityEvidence {
    /// Whether the dark side is ink.
    pub dark_is_ink: bool,
    /// How sure, in [0, 1): 0 is a coin toss.
    pub confidence: f64,
    /// The ink side's most common chord, px: the stroke width the image shows.
    pub stroke_width: f64,
    /// The other side's most common chord, px.
    pub other_width: f64,
    /// The stroke width whichever side is ink ([`Chords::thinner_quartile`]), px.
    pub thinner_width: f64,
}

/// Weight of the prior for dark ink on light paper (the common case: print, handwriting, inked
/// prints), in the units of the log thickness ratio: it decides only when the strokes' evidence
/// is weak.
const DARK_PRIOR: f64 = 0.5;
/// Thickness ratios beyond `e^3` (20 times) say no more.
const MAX_THICKNESS_EVIDENCE: f64 = 3.0;

/// Which side of a split is ink, from stroke evidence (docs/design.md, "The front end"):
///
/// - ink is the thinner side: the log ratio of the sides' mean chords (paper's chords span the
///   gaps between strokes and the margins, ink's only the stroke width);
/// - paper is the side that fills the image border: the light share minus the dark share of a
///   ring inset by 1% of the image's smaller side (at least 2 px), so a scanner's one-pixel frame
///   does not count;
/// - a weak prior for dark ink.
///
/// The three add to a score `z` whose sign decides; the confidence is `tanh(|z| / 2)`. The
/// chords are measured on about `samples` lattice points ([`chords_sampled`]).
pub(crate) fn polarity(
    dark: &[bool],
    width: usize,
    height: usize,
    samples: usize,
) -> PolarityEvidence {
    let chords = chords_sampled(dark, width, height, samples);
    let thickness = if chords.dark_mean > 0.0 && chords.light_mean > 0.0 {
        (chords.light_mean / chords.dark_mean)
            .ln()
            .clamp(-MAX_THICKNESS_EVIDENCE, MAX_THICKNESS_EVIDENCE)
    } else {
        0.0
    };
    let z = thickness + border_evidence(dark, width, height) + DARK_PRIOR;
    let dark_is_ink = z >= 0.0;
    PolarityEvidence {
        dark_is_ink,
        confidence: (z.abs() / 2.0).tanh(),
        stroke_width: if dark_is_ink {
            chords.dark_mode
        } else {
            chords.light_mode
        },
        other_width: if dark_is_ink {
            chords.light_mode
        } else {
            chords.dark_mode
        },
        thinner_width: chords.thinner_quartile,
    }
}

/// Light share minus dark share of the inset border ring, in [-1, 1] (0 for an image too small
/// to have one).
fn border_evidence(dark: &[bool], width: usize, height: usize) -> f64 {
    let inset = (width.min(height) / 100).max(2);
    if width <= 2 * inset || height <= 2 * inset {
        return 0.0;
    }
    let (x0, x1, y0, y1) = (inset, width - 1 - inset, inset, height - 1 - inset);
    let (mut dark_count, mut total) = (0usize, 0usize);
    let mut visit = |x: usize, y: usize| {
        dark_count += usize::from(dark[y * width + x]);
        total += 1;
    };
    for x in x0..=x1 {
        visit(x, y0);
        visit(x, y1);
    }
    for y in y0 + 1..y1 {
        visit(x0, y);
        visit(x1, y);
    }
    1.0 - 2.0 * dark_count as f64 / total.max(1) as f64
}

/// How the light falls across the image, from blocks of it: each block's darkest and lightest
/// levels (2nd and 98th percentiles) and the local threshold halfway between; blocks without
/// strokes keep their own paper level and their neighbours' offset of the threshold from paper
/// (docs/design.md, "The front end").
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Lighting {
    /// Block side, px.
    pub block: usize,
    /// Blocks per row and per column.
    pub cols: usize,
    /// Blocks per column.
    pub rows: usize,
    /// The local threshold at each block's center, row-major.
    pub thresholds: Vec<f64>,
    /// The darkest level (for dark ink; the lightest for light ink) of the 98% of each paper
    /// block's pixels nearest its paper level: a global level past it puts specks of ink on that
    /// block's paper. `None` for the blocks with strokes, and inside bold strokes.
    pub paper_tails: Vec<Option<f64>>,
    /// Each block's darkest and lightest level, row-major: where both lie on one side of a
    /// level, every pixel of the block does ([`disagreement`] counts no pixel there).
    pub ranges: Vec<[u8; 2]>,
}

/// The (2nd, 50th, 98th) percentiles of a block of `total` pixels from its `histogram`: for each
/// share, the first level where the pixels counted so far reach `share · total`, all three in
/// one pass (the shares rise, so do their levels; the counts so far are whole numbers, exact in
/// `f64`, as they were summed there one share at a time). 0 for a share never reached.
///
/// A whole count reaches `share · total` exactly when it reaches its ceiling, so the targets are
/// compared as integers.
fn block_percentiles(histogram: &[u32; 256], total: f64) -> [f64; 3] {
    let targets = [0.02, 0.5, 0.98].map(|share| (share * total).ceil() as u64);
    let mut out = [0.0; 3];
    let (mut next, mut seen) = (0, 0u64);
    // Sixteen levels at a time where they reach no target (most of them: a block of a page holds
    // few levels), then level by level.
    for (group, counts) in histogram.chunks_exact(16).enumerate() {
        let sum: u64 = counts.iter().map(|&n| u64::from(n)).sum();
        if seen + sum < targets[next] {
            seen += sum;
            continue;
        }
        for (v, &count) in (group * 16..).zip(counts) {
            seen += u64::from(count);
            while next < 3 && seen >= targets[next] {
                out[next] = v as f64;
                next += 1;
            }
            if next == 3 {
                return out;
            }
        }
    }
    out
}

/// The (2nd, 50th, 98th) percentiles ([`block_percentiles`]) and the range (darkest, lightest)
/// of each `block` px square block of `gray`, `cols` x `rows` of them (cut to the image),
/// row-major, rows of blocks in parallel.
fn block_stats(
    gray: GrayView<'_>,
    block: usize,
    cols: usize,
    rows: usize,
) -> (Vec<[f64; 3]>, Vec<[u8; 2]>) {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    // The range first, each pixel column's over the block's rows (whole rows in vector lanes)
    // and then each block's columns': a block of one level (a page's blank paper) has it at
    // every share, without its histogram.
    (0..rows)
        .into_par_iter()
        .flat_map_iter(|r| {
            let (y0, y1) = (r * block, ((r + 1) * block).min(height));
            let (mut lo, mut hi) = (gray.row(y0).to_vec(), gray.row(y0).to_vec());
            for y in y0 + 1..y1 {
                for ((lo, hi), &v) in lo.iter_mut().zip(hi.iter_mut()).zip(gray.row(y)) {
                    *lo = (*lo).min(v);
                    *hi = (*hi).max(v);
                }
            }
            (0..cols).map(move |c| {
                let (x0, x1) = (c * block, ((c + 1) * block).min(width));
                let range = [
                    lo[x0..x1].iter().fold(u8::MAX, |a, &v| a.min(v)),
                    hi[x0..x1].iter().fold(u8::MIN, |a, &v| a.max(v)),
                ];
                if range[0] == range[1] {
                    return ([f64::from(range[0]); 3], range);
                }
                let mut histogram = [0u32; 256];
                for y in y0..y1 {
                    for &v in &gray.row(y)[x0..x1] {
                        histogram[v as usize] += 1;
                    }
                }
                let total = ((x1 - x0) * (y1 - y0)) as f64;
                (block_percentiles(&histogram, total), range)
            })
        })
        .unzip()
}

/// Blocks whose range is below this many gray levels hold no stroke whatever the image.
const MIN_CONTRAST: f64 = 24.0;
/// A block holds strokes when its range reaches this share of the image's high block ranges
/// (95th percentile): lower ranges are noise, texture or faint paper structure.
const CONTENT_SHARE: f64 = 0.35;

/// Measures the lighting with blocks of about six stroke widths (at least 8 px, at most 128, and
/// at most a quarter of the image's smaller side, so that there are blocks to compare), the ink
/// dark or light as `dark_ink` says. `None` for an image with no block holding strokes.
pub(crate) fn lighting(gray: GrayView<'_>, stroke_width: f64, dark_ink: bool) -> Option<Lighting> {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    let block = lighting_block(gray, stroke_width);
    let (cols, rows) = (width.div_ceil(block), height.div_ceil(block));
    if cols == 0 || rows == 0 {
        return None;
    }
    let (stats, ranges) = block_stats(gray, block, cols, rows);
    let mut contrasts: Vec<f64> = stats.iter().map(|s| s[2] - s[0]).collect();
    let high = {
        let k = ((contrasts.len() as f64 * 0.95) as usize).min(contrasts.len() - 1);
        *contrasts.select_nth_unstable_by(k, |a, b| a.total_cmp(b)).1
    };
    let floor = MIN_CONTRAST.max(CONTENT_SHARE * high);
    let content: Vec<bool> = stats.iter().map(|s| s[2] - s[0] >= floor).collect();
    if !content.iter().any(|&c| c) {
        return None;
    }
    // A block with strokes puts its threshold halfway between its ink and paper levels. A block
    // without strokes takes its neighbours' levels (filled in wave by wave) and their threshold,
    // but where its median is nearer their paper level than their ink level it is paper, and its
    // threshold moves at least half their contrast away from that median towards the ink: the
    // paper of a darker (or, under light ink, lighter) corner stays paper (docs/design.md, "The
    // front end").
    let mut levels: Vec<Option<[f64; 2]>> = stats
        .iter()
        .zip(&content)
        .map(|(&[lo, _, hi], &c)| c.then_some(if dark_ink { [hi, lo] } else { [lo, hi] }))
        .collect();
    while levels.iter().any(Option::is_none) {
        let previous = levels.clone();
        for r in 0..rows {
            for c in 0..cols {
                if previous[r * cols + c].is_some() {
                    continue;
                }
                let (mut sum, mut n) = ([0.0; 2], 0.0);
                for nr in r.saturating_sub(1)..(r + 2).min(rows) {
                    for nc in c.saturating_sub(1)..(c + 2).min(cols) {
                        if let Some(known) = previous[nr * cols + nc] {
                            sum[0] += known[0];
                            sum[1] += known[1];
                            n += 1.0;
                        }
                    }
                }
                if n > 0.0 {
                    levels[r * cols + c] = Some([sum[0] / n, sum[1] / n]);
                }
            }
        }
    }
    // Each block's threshold, and for a paper block its ink-side tail.
    let (middle, paper_tails): (Vec<f64>, Vec<Option<f64>>) = stats
        .iter()
        .zip(&content)
        .zip(&levels)
        .map(|((&[lo, median, hi], &c), known)| {
            if c {
                return ((lo + hi) / 2.0, None);
            }
            let [paper, ink] = known.unwrap_or([median; 2]);
            let filled = (paper + ink) / 2.0;
            if (median - paper).abs() > (median - ink).abs() {
                return (filled, None);
            }
            let off_paper = median + (ink - paper) / 2.0;
            let threshold = if ink < paper {
                filled.min(off_paper)
            } else {
                filled.max(off_paper)
            };
            (threshold, Some(if dark_ink { lo } else { hi }))
        })
        .unzip();
    // The threshold surface: each block's middle averaged with its neighbours'.
    let mut thresholds = vec![0.0; middle.len()];
    for r in 0..rows {
        for c in 0..cols {
            let (mut sum, mut n) = (0.0, 0.0);
            for nr in r.saturating_sub(1)..(r + 2).min(rows) {
                for nc in c.saturating_sub(1)..(c + 2).min(cols) {
                    sum += middle[nr * cols + nc];
                    n += 1.0;
                }
            }
            thresholds[r * cols + c] = sum / n;
        }
    }
    Some(Lighting {
        block,
        cols,
        rows,
        thresholds,
        paper_tails,
        ranges,
    })
}

/// The side of [`lighting`]'s blocks for strokes `stroke_width` px wide, px: its measure depends
/// on the image, this side and the ink's side alone.
pub(crate) fn lighting_block(gray: GrayView<'_>, stroke_width: f64) -> usize {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    ((6.0 * stroke_width).round() as usize)
        .clamp(8, 128)
        .min((width.min(height) / 4).max(8))
}

/// Whether the global `level` puts specks of ink on the paper of some block without strokes
/// (a darker corner under dark ink, a lighter one under light ink): that block's paper is
/// within its own noise of the level.
pub(crate) fn level_reaches_paper(lighting: &Lighting, level: u8, dark_ink: bool) -> bool {
    let level = f64::from(level);
    lighting.paper_tails.iter().flatten().any(|&tail| {
        if dark_ink {
            tail <= level
        } else {
            tail > level
        }
    })
}

/// Pixels on which the global `level` and each block's own local threshold disagree, and the
/// pixels dark under the local thresholds: what [`local_dark`] would change, without making it.
pub(crate) fn disagreement(gray: GrayView<'_>, lighting: &Lighting, level: u8) -> (usize, usize) {
    let width = gray.width() as usize;
    if width == 0 {
        return (0, 0);
    }
    let (block, cols) = (lighting.block, lighting.cols);
    // Both tests are levels: `v <= t` is `v < below(t)` for the gray levels, and the global one
    // `v < level + 1`; the two disagree on the pixels between their bounds, which are the
    // difference of the counts below each. Counted in `u32` lanes, a block's row at a time.
    let below = |t: f64| -> u16 {
        if t >= 255.0 {
            256
        } else if t >= 0.0 {
            // The truncation of a level in [0, 255) is its floor (`f64::floor` is a library
            // call on the baseline x86-64, made for every block of every row).
            t as u16 + 1
        } else {
            0 // negative or NaN: no level is at or below it
        }
    };
    let global = u16::from(level) + 1;
    gray.par_rows(1)
        .enumerate()
        .map(|(y, row)| {
            let blocks = (y / block) * cols..(y / block + 1) * cols;
            let (thresholds, ranges) = (
                &lighting.thresholds[blocks.clone()],
                &lighting.ranges[blocks],
            );
            let (mut differ, mut dark) = (0, 0);
            for ((chunk, &t), &[lo, hi]) in row.chunks(block).zip(thresholds).zip(ranges) {
                // Below a bound the block's range is on one side of is all or none of it.
                let count = |bound: u16| {
                    if u16::from(hi) < bound {
                        chunk.len()
                    } else if u16::from(lo) >= bound {
                        0
                    } else {
                        count_below(chunk, bound)
                    }
                };
                let (local, global) = (count(below(t)), count(global));
                differ += local.abs_diff(global);
                dark += local;
            }
            (differ, dark)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
}

/// How many of `values` are below `bound` (a gray level, or 256 for all), counted in byte lanes
/// 255 values at a time.
fn count_below(values: &[u8], bound: u16) -> usize {
    let Some(last) = bound.checked_sub(1) else {
        return 0;
    };
    let Ok(last) = u8::try_from(last) else {
        return values.len();
    };
    values
        .chunks(255)
        .map(|piece| usize::from(piece.iter().fold(0u8, |n, &v| n + u8::from(v <= last))))
        .sum()
}

/// The dark side of `gray` under the local threshold of `lighting`, interpolated bilinearly
/// between block centers.
pub(crate) fn local_dark(gray: GrayView<'_>, lighting: &Lighting, dark: &mut [bool]) {
    let width = gray.width() as usize;
    let surface = lighting.surface(width);
    // The pixel columns by the pair of block columns they lie between: along a run of them the
    // two thresholds are the same, so the loop over its pixels needs no lookups (vector lanes);
    // each pixel's threshold is the one `Surface::row` gives, from the same operations.
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    for (x, &(c0, c1, _)) in surface.columns.iter().enumerate() {
        match runs.last_mut() {
            Some((end, a, b)) if (*a, *b) == (c0, c1) => *end = x + 1,
            _ => runs.push((x + 1, c0, c1)),
        }
    }
    let weights: Vec<f64> = surface.columns.iter().map(|&(_, _, fx)| fx).collect();
    dark.par_chunks_mut(width)
        .zip(gray.par_rows(1))
        .enumerate()
        .for_each(|(y, (out, values))| {
            let row = surface.block_row(y);
            let mut start = 0;
            for &(end, c0, c1) in &runs {
                let (t0, t1) = (row[c0], row[c1]);
                let pixels = out[start..end]
                    .iter_mut()
                    .zip(&values[start..end])
                    .zip(&weights[start..end]);
                for ((o, &v), &fx) in pixels {
                    *o = f64::from(v) <= t0 * (1.0 - fx) + t1 * fx;
                }
                start = end;
            }
        });
}

/// The local threshold of a [`Lighting`] at every pixel of an image, interpolated bilinearly
/// between block centers, one row at a time.
pub(crate) struct Surface<'a> {
    lighting: &'a Lighting,
    /// For each pixel column: the block column to its left, the next one and the next one's
    /// weight.
    columns: Vec<(usize, usize, f64)>,
}

impl Lighting {
    /// The threshold surface over an image `width` pixels wide.
    pub(crate) fn surface(&self, width: usize) -> Surface<'_> {
        Surface {
            lighting: self,
            columns: (0..width).map(|x| self.cell(x, self.cols)).collect(),
        }
    }

    /// Position of pixel center `p` on the block-center grid of `n` blocks: the cell to its
    /// left/top and the weight of the next one.
    fn cell(&self, p: usize, n: usize) -> (usize, usize, f64) {
        let g = ((p as f64 + 0.5) / self.block as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let i = g.floor() as usize;
        let j = (i + 1).min(n - 1);
        (i, j, g - i as f64)
    }
}

impl Surface<'_> {
    /// The threshold at each block column's centre on row `y`.
    fn block_row(&self, y: usize) -> Vec<f64> {
        let lighting = self.lighting;
        let cols = lighting.cols;
        let (r0, r1, fy) = lighting.cell(y, lighting.rows);
        let t = &lighting.thresholds;
        (0..cols)
            .map(|c| t[r0 * cols + c] * (1.0 - fy) + t[r1 * cols + c] * fy)
            .collect()
    }

    /// The threshold at each pixel of row `y`.
    pub(crate) fn row(&self, y: usize) -> impl Iterator<Item = f64> + '_ {
        let row = self.block_row(y);
        self.columns
            .iter()
            .map(move |&(c0, c1, fx)| row[c0] * (1.0 - fx) + row[c1] * fx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::median::upper_median_by;

    /// The chords as first written: every lattice point's runs kept, each side's chords sorted.
    fn chords_by_sorting(dark: &[bool], width: usize, height: usize, samples: usize) -> Chords {
        let step = ((width * height / samples) as f64).sqrt().floor().max(1.0) as usize;
        let (cols, rows) = (width.div_ceil(step), height.div_ceil(step));
        let (mut dark_chords, mut light_chords) = (Vec::new(), Vec::new());
        let horizontal: Vec<Vec<u32>> = (0..rows)
            .map(|r| {
                run_lengths(
                    dark[r * step * width..(r * step + 1) * width]
                        .iter()
                        .copied(),
                )
            })
            .collect();
        let vertical: Vec<Vec<u32>> = (0..cols)
            .map(|c| run_lengths((0..height).map(|y| dark[y * width + c * step])))
            .collect();
        for r in 0..rows {
            for c in 0..cols {
                let chord = horizontal[r][c * step].min(vertical[c][r * step]);
                if dark[r * step * width + c * step] {
                    dark_chords.push(chord);
                } else {
                    light_chords.push(chord);
                }
            }
        }
        let quartile = |chords: &mut Vec<u32>| -> f64 {
            if chords.is_empty() {
                return f64::INFINITY;
            }
            let k = chords.len() / 4;
            *chords.select_nth_unstable(k).1 as f64
        };
        let thinner_quartile = quartile(&mut dark_chords).min(quartile(&mut light_chords));
        let (dark_mode, light_mode) = (mode(&dark_chords), mode(&light_chords));
        let (dark_mean, dark_median) = mean_and_median(&mut dark_chords);
        let (light_mean, light_median) = mean_and_median(&mut light_chords);
        Chords {
            dark_mean,
            light_mean,
            dark_median,
            light_median,
            dark_mode,
            light_mode,
            thinner_quartile: if thinner_quartile.is_finite() {
                thinner_quartile
            } else {
                0.0
            },
        }
    }

    /// The most common value (the smallest of equally common ones), 0 for none.
    fn mode(values: &[u32]) -> f64 {
        let Some(&max) = values.iter().max() else {
            return 0.0;
        };
        let mut counts = vec![0u32; max as usize + 1];
        for &v in values {
            counts[v as usize] += 1;
        }
        // The first of the largest counts.
        let (mut best, mut best_count) = (0, 0);
        for (v, &c) in counts.iter().enumerate() {
            if c > best_count {
                (best, best_count) = (v, c);
            }
        }
        best as f64
    }

    fn mean_and_median(values: &mut [u32]) -> (f64, f64) {
        if values.is_empty() {
            return (0.0, 0.0);
        }
        let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len() as f64;
        let median = upper_median_by(values, Ord::cmp).map_or(0.0, f64::from);
        (mean, median)
    }

    /// The counted chords are the sorted ones, with the runs found word by word, on the
    /// baseline build and (where the CPU has it) the AVX2 one: runs of a few pixels under
    /// noise, and long runs (whole rows, runs across several eight-pixel words).
    #[test]
    fn chords_counted_are_chords_sorted() {
        let mut seed = 3u64;
        let sizes = [
            (1, 1),
            (1, 9),
            (13, 1),
            (40, 31),
            (97, 60),
            (700, 400),
            (301, 7),
        ];
        for (w, h) in sizes {
            for density in [0, 3, 30, 55, 100, 101, 102] {
                let dark: Vec<bool> = (0..w * h)
                    .map(|p| {
                        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                        match density {
                            // Runs of 5 to 40 pixels across the rows, as wide strokes make.
                            101 => (p + p / w) % (5 + (p / w) % 36) < 3 + (p / w) % 3,
                            // Rows all of one side.
                            102 => (p / w) % 3 == 0,
                            // Runs of a few pixels, as strokes make.
                            _ => ((p / 3) % 7 < 3) ^ ((seed >> 33) % 100 < density),
                        }
                    })
                    .collect();
                let sorted = chords_by_sorting(&dark, w, h, LATTICE_SAMPLES);
                assert_eq!(chords(&dark, w, h), sorted, "{w}x{h} density {density}");
                // Pages' lattice and a print's decision's sparser one.
                for samples in [LATTICE_SAMPLES, PRINT_LATTICE_SAMPLES] {
                    let sorted = chords_by_sorting(&dark, w, h, samples);
                    let at = format!("{w}x{h} density {density}, {samples} samples");
                    assert_eq!(chords_sampled(&dark, w, h, samples), sorted, "{at}");
                    assert_eq!(chords_lanes(&dark, w, h, samples), sorted, "{at}");
                    #[cfg(target_arch = "x86_64")]
                    if std::arch::is_x86_feature_detected!("avx2") {
                        // SAFETY: the CPU has AVX2.
                        let wide = unsafe { chords_wide(&dark, w, h, samples) };
                        assert_eq!(wide, sorted, "{at}");
                    }
                }
            }
        }
    }

    /// The blocks' statistics as [`lighting`] first measured them: a histogram of every block.
    fn block_stats_by_histograms(
        gray: GrayView<'_>,
        block: usize,
        cols: usize,
        rows: usize,
    ) -> Vec<[f64; 3]> {
        let (width, height) = (gray.width() as usize, gray.height() as usize);
        let mut stats = Vec::new();
        for r in 0..rows {
            let (y0, y1) = (r * block, ((r + 1) * block).min(height));
            for c in 0..cols {
                let (x0, x1) = (c * block, ((c + 1) * block).min(width));
                let mut histogram = [0u32; 256];
                for y in y0..y1 {
                    for &v in &gray.row(y)[x0..x1] {
                        histogram[v as usize] += 1;
                    }
                }
                stats.push(block_percentiles(
                    &histogram,
                    ((x1 - x0) * (y1 - y0)) as f64,
                ));
            }
        }
        stats
    }

    /// [`disagreement`] as first written: both tests at every pixel, the local one in `f64`.
    fn disagreement_pixel_by_pixel(
        gray: GrayView<'_>,
        lighting: &Lighting,
        level: u8,
    ) -> (usize, usize) {
        let (block, cols) = (lighting.block, lighting.cols);
        let (mut differ, mut dark) = (0, 0);
        for y in 0..gray.height() as usize {
            let thresholds = &lighting.thresholds[(y / block) * cols..(y / block + 1) * cols];
            for (chunk, &t) in gray.row(y).chunks(block).zip(thresholds) {
                for &v in chunk {
                    let local = (v as f64) <= t;
                    differ += usize::from(local != (v <= level));
                    dark += usize::from(local);
                }
            }
        }
        (differ, dark)
    }

    /// Random pages for the tests of the blocks' passes: blank paper, paper with strokes of one
    /// level, two levels only, smooth shading and noise, of odd sizes (blocks cut at the edges).
    fn random_grays(seed: u64) -> Vec<image::GrayImage> {
        let mut next = crate::synth::lcg(seed);
        let mut rand = move |n: u64| (next() >> 33) % n;
        let mut pages = Vec::new();
        for case in 0..60u64 {
            let (w, h) = (1 + rand(120) as u32, 1 + rand(90) as u32);
            let (paper, ink) = (rand(256) as u8, rand(256) as u8);
            let kind = case % 5;
            let pixels: Vec<u8> = (0..w * h)
                .map(|p| {
                    let (x, y) = (p % w, p / w);
                    match kind {
                        0 => paper,
                        1 if (x / 3 + y) % 11 < 2 => ink,
                        1 => paper,
                        2 => [paper, ink][rand(2) as usize],
                        3 => ((x * 255) / w.max(1)) as u8 ^ (y as u8 & 7),
                        _ => rand(256) as u8,
                    }
                })
                .collect();
            pages.push(image::GrayImage::from_raw(w, h, pixels).expect("size"));
        }
        pages
    }

    /// The blocks' percentiles without the histogram of one-level blocks, and their ranges, are
    /// those of a histogram of every block.
    #[test]
    fn block_stats_equal_those_of_a_histogram_per_block() {
        for gray in random_grays(71) {
            let view: GrayView<'_> = (&gray).into();
            let (w, h) = (gray.width() as usize, gray.height() as usize);
            for block in [1, 2, 7, 8, 24, 200] {
                let (cols, rows) = (w.div_ceil(block), h.div_ceil(block));
                let (stats, ranges) = block_stats(view, block, cols, rows);
                assert_eq!(stats, block_stats_by_histograms(view, block, cols, rows));
                for (b, range) in ranges.iter().enumerate() {
                    let (r, c) = (b / cols, b % cols);
                    let values: Vec<u8> = (r * block..((r + 1) * block).min(h))
                        .flat_map(|y| gray.as_raw()[y * w..(y + 1) * w].to_vec())
                        .enumerate()
                        .filter(|(x, _)| (c * block..((c + 1) * block).min(w)).contains(&(x % w)))
                        .map(|(_, v)| v)
                        .collect();
                    let lo = values.iter().min().copied();
                    let hi = values.iter().max().copied();
                    assert_eq!((Some(range[0]), Some(range[1])), (lo, hi), "block {b}");
                }
            }
        }
    }

    /// `measured` with each threshold replaced at random: whole levels, between them, below 0,
    /// above 255, NaN, or any level.
    fn odd_thresholds(measured: &Lighting, rand: &mut impl FnMut(u64) -> u64) -> Lighting {
        let mut odd = measured.clone();
        for t in odd.thresholds.iter_mut() {
            *t = match rand(7) {
                0 => rand(256) as f64,
                1 => rand(256) as f64 + 0.5,
                2 => -0.0,
                3 => -3.5,
                4 => 255.0 + rand(3) as f64,
                5 => f64::NAN,
                _ => rand(25_600) as f64 / 100.0 - 0.004,
            };
        }
        odd
    }

    /// The disagreement counted by bounds and ranges is the one tested pixel by pixel, with the
    /// measured lighting and with thresholds on whole levels, between them, below 0, above 255
    /// and NaN, at every global level's extremes.
    #[test]
    fn disagreement_by_bounds_equals_the_test_at_every_pixel() {
        let mut next = crate::synth::lcg(72);
        let mut rand = move |n: u64| (next() >> 33) % n;
        for gray in random_grays(73) {
            let view: GrayView<'_> = (&gray).into();
            for dark_ink in [true, false] {
                let Some(measured) = lighting(view, 1.0 + rand(6) as f64, dark_ink) else {
                    continue;
                };
                let odd = odd_thresholds(&measured, &mut rand);
                for lighting in [&measured, &odd] {
                    for level in [0, 1, rand(256) as u8, 254, 255] {
                        assert_eq!(
                            disagreement(view, lighting, level),
                            disagreement_pixel_by_pixel(view, lighting, level)
                        );
                    }
                }
            }
        }
    }

    /// The local split by runs of pixel columns between the same block columns is the split by
    /// each pixel's threshold from [`Surface::row`], with the measured lighting and with
    /// thresholds on whole levels, between them, below 0, above 255 and NaN.
    #[test]
    fn the_local_split_by_runs_is_the_split_pixel_by_pixel() {
        let mut next = crate::synth::lcg(76);
        let mut rand = move |n: u64| (next() >> 33) % n;
        for gray in random_grays(77) {
            let view: GrayView<'_> = (&gray).into();
            let (w, h) = (gray.width() as usize, gray.height() as usize);
            for dark_ink in [true, false] {
                let Some(measured) = lighting(view, 1.0 + rand(6) as f64, dark_ink) else {
                    continue;
                };
                let odd = odd_thresholds(&measured, &mut rand);
                for lighting in [&measured, &odd] {
                    let surface = lighting.surface(w);
                    let want: Vec<bool> = (0..h)
                        .flat_map(|y| {
                            let row = view.row(y).to_vec();
                            row.into_iter()
                                .zip(surface.row(y).collect::<Vec<_>>())
                                .map(|(v, t)| (v as f64) <= t)
                        })
                        .collect();
                    let mut dark = vec![false; w * h];
                    local_dark(view, lighting, &mut dark);
                    assert_eq!(dark, want);
                }
            }
        }
    }

    /// Counting below a bound in byte lanes counts every value below it.
    #[test]
    fn count_below_counts_in_byte_lanes() {
        let mut next = crate::synth::lcg(74);
        for len in [0, 1, 254, 255, 256, 600, 1000] {
            let values: Vec<u8> = (0..len).map(|_| (next() >> 40) as u8).collect();
            for bound in [0u16, 1, 2, 100, 255, 256] {
                let want = values.iter().filter(|&&v| u16::from(v) < bound).count();
                assert_eq!(count_below(&values, bound), want, "{len} {bound}");
            }
        }
        assert_eq!(count_below(&[255; 300], 256), 300);
        assert_eq!(count_below(&[0; 300], 1), 300);
    }

    /// The block percentiles in one pass are those of one pass per share (as first written):
    /// histograms of random blocks, sparse and dense, of 1 to 16 384 pixels.
    #[test]
    fn block_percentiles_in_one_pass_are_those_of_three() {
        let three_passes = |histogram: &[u32; 256], total: f64| {
            let mut out = [0.0; 3];
            for (o, share) in out.iter_mut().zip([0.02, 0.5, 0.98]) {
                let target = share * total;
                let mut seen = 0.0;
                for (v, &count) in histogram.iter().enumerate() {
                    seen += count as f64;
                    if seen >= target {
                        *o = v as f64;
                        break;
                    }
                }
            }
            out
        };
        let mut seed = 7u64;
        let mut next = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 33) as usize
        };
        for case in 0..2000 {
            let pixels = 1 + next() % [3, 50, 1000, 16_384][case % 4];
            let (low, spread) = (next() % 256, 1 + next() % 256);
            let mut histogram = [0u32; 256];
            for _ in 0..pixels {
                histogram[(low + next() % spread) % 256] += 1;
            }
            let total = pixels as f64;
            assert_eq!(
                block_percentiles(&histogram, total),
                three_passes(&histogram, total),
                "case {case}"
            );
        }
    }
}
