//! The binary-image toolkit, shared by both front ends (images and point lists), the fingerprint
//! front end and the test kit's scorer: the exact Euclidean distance transform that gives each
//! point its half-width, the dilation and closing by a disk (of the minutiae's print region), the
//! 3x3 morphology (the closing of dropout mode, the fingerprint segmentation's block
//! flags), the labelling of connected components, and the count of tiny background holes that
//! switches dropout mode on (docs/design.md, adaptation 2).
//!
//! Ground floor: plain math on row-major `bool` masks; it knows nothing about stages. Its one
//! labelling ([`label_components`], [`on_image_edge`]) is public for the test kit's scorer.

pub use imageproc::region_labelling::Connectivity;
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;
use std::ops::Range;

/// The connected components of the pixels of `flags` equal to `value`: one label per pixel,
/// numbered from 1 in raster order of each component's first pixel (0 for the other pixels), and
/// `sizes[l]` the pixel count of label `l` (`sizes[0]` the other pixels). `flags` holds `width *
/// height` pixels, row-major.
///
/// The labels of imageproc's labelling (`region_labelling::connected_components`, unit test
/// `labels_are_imageproc_labels`), found over the runs of pixels of each row as
/// [`run_components`] finds them: a union-find over the runs instead of over every pixel, so the
/// one array of the image's size is the labels returned (imageproc's takes a gray copy, its
/// provisional labels and a forest of two words per pixel, 24 bytes a pixel beside the result).
///
/// # Panics
///
/// When `flags` does not hold `width * height` pixels.
pub fn label_components(
    flags: &[bool],
    width: usize,
    height: usize,
    value: bool,
    connectivity: Connectivity,
) -> (Vec<u32>, Vec<usize>) {
    assert_eq!(flags.len(), width * height, "a {width}x{height} mask");
    let mut runs = Vec::new();
    for (y, row) in flags.chunks_exact(width.max(1)).enumerate() {
        let mut x = 0;
        while x < width {
            if row[x] != value {
                x += 1;
                continue;
            }
            let start = x;
            while x < width && row[x] == value {
                x += 1;
            }
            runs.push(Run {
                y: y as u32,
                x0: start as u32,
                x1: x as u32,
            });
        }
    }
    let (run_labels, run_sizes) = components_of_runs(&runs, connectivity);
    let mut labels = vec![0u32; flags.len()];
    for (run, &label) in runs.iter().zip(&run_labels) {
        let row = run.y as usize * width;
        labels[row + run.x0 as usize..row + run.x1 as usize].fill(label + 1);
    }
    let mut sizes = Vec::with_capacity(run_sizes.len() + 1);
    sizes.push(flags.len() - run_sizes.iter().sum::<usize>());
    sizes.extend(run_sizes);
    (labels, sizes)
}

/// For each label of [`label_components`] (`count` of them, 0 included), whether it holds a pixel
/// on the image's edge: the components that are no holes.
pub fn on_image_edge(labels: &[u32], width: usize, height: usize, count: usize) -> Vec<bool> {
    let mut edge = vec![false; count];
    if width == 0 || height == 0 {
        return edge;
    }
    for x in 0..width {
        edge[labels[x] as usize] = true;
        edge[labels[(height - 1) * width + x] as usize] = true;
    }
    for y in 0..height {
        edge[labels[y * width] as usize] = true;
        edge[labels[y * width + width - 1] as usize] = true;
    }
    edge
}

/// Squared distance transform values at the ink pixels only, in raster order: entry `i` belongs to
/// the `i`-th ink pixel of `ink`. Pixels outside the image count as background, so a 1-px line has 1 and
/// the center of a 3-px line 2. See [`squared_distance_rows`].
pub(crate) fn ink_distances(ink: &[bool], width: usize, height: usize) -> Vec<f32> {
    let row_starts = ink_row_starts(ink, width, height);
    let mut half_width = vec![0f32; row_starts[height]];
    squared_distance_rows(ink, width, height, &row_starts, &mut half_width, |d2| {
        (d2 as f64).sqrt() as f32
    });
    half_width
}

/// A run of ink pixels `x0..x1` (end excluded) in row `y`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Run {
    pub y: u32,
    pub x0: u32,
    pub x1: u32,
}

impl Run {
    pub(crate) fn len(&self) -> usize {
        (self.x1 - self.x0) as usize
    }
}

/// The 8-connected components of `runs` (in raster order, none touching the next in its row):
/// each run's component, numbered in order of the components' first runs, and each component's
/// pixel count. A run touches the runs of the row above that overlap it or meet it at a corner;
/// a union-find over the runs.
pub(crate) fn run_components(runs: &[Run]) -> (Vec<u32>, Vec<usize>) {
    components_of_runs(runs, Connectivity::Eight)
}

/// [`run_components`] with either connectivity: with [`Connectivity::Four`] a run touches only
/// the runs of the row above that share a column with it.
fn components_of_runs(runs: &[Run], connectivity: Connectivity) -> (Vec<u32>, Vec<usize>) {
    // Runs `a` above and `b` touch when `a.x0 < b.x1 + reach && b.x0 < a.x1 + reach`.
    let reach = u32::from(connectivity == Connectivity::Eight);
    let mut sets = UnionFind::<u32>::new(runs.len());
    let mut above = 0..0;
    let mut start = 0;
    while start < runs.len() {
        let y = runs[start].y;
        let end = start + runs[start..].partition_point(|r| r.y == y);
        if above.end > above.start && runs[above.start].y + 1 == y {
            let (mut i, mut j) = (above.start, start);
            while i < above.end && j < end {
                let (a, b) = (runs[i], runs[j]);
                if a.x0 < b.x1 + reach && b.x0 < a.x1 + reach {
                    sets.union(i as u32, j as u32);
                }
                // The run that ends first cannot touch anything further along the other row.
                if a.x1 < b.x1 {
                    i += 1;
                } else {
                    j += 1;
                }
            }
        }
        above = start..end;
        start = end;
    }
    first_seen_labels(&mut sets, runs.len(), |r| runs[r].len())
}

/// The sets of `sets` (over `0..n`) numbered in order of their first members, each element's
/// number, and each set's total `weight`: labels that do not depend on which member the
/// union-find made the root.
pub(crate) fn first_seen_labels(
    sets: &mut UnionFind<u32>,
    n: usize,
    weight: impl Fn(usize) -> usize,
) -> (Vec<u32>, Vec<usize>) {
    let mut label_of_root = vec![u32::MAX; n];
    let mut labels = Vec::with_capacity(n);
    let mut sizes: Vec<usize> = Vec::new();
    for i in 0..n {
        let root = sets.find_mut(i as u32) as usize;
        if label_of_root[root] == u32::MAX {
            label_of_root[root] = sizes.len() as u32;
            sizes.push(0);
        }
        let label = label_of_root[root];
        sizes[label as usize] += weight(i);
        labels.push(label);
    }
    (labels, sizes)
}

/// Squared Euclidean distance (between pixel centres) from each pixel to the nearest `site`
/// pixel, exact, infinite when there is no site. Pixels outside the image are never sites.
/// Returns one value per pixel.
///
/// The first pass of Meijster et al. (2000): each pixel's distance to the nearest site in its own
/// column, capped at `far` (a column with no site within `far` of the pixel reads `far`).
///
/// Worked a row at a time (each row from the one above, then from the one below), which the
/// compiler turns into vector lanes: the same values as the pixel-by-pixel recurrence.
fn column_distances(sites: &[bool], width: usize, height: usize, far: u32) -> Vec<u32> {
    let mut g = vec![far; width * height];
    if width == 0 {
        return g;
    }
    for (y, site_row) in sites.chunks_exact(width).take(height).enumerate() {
        let (done, rest) = g.split_at_mut(y * width);
        let row = &mut rest[..width];
        if y == 0 {
            for (g, &s) in row.iter_mut().zip(site_row) {
                *g = if s { 0 } else { far };
            }
        } else {
            let above = &done[(y - 1) * width..];
            for ((g, &s), &a) in row.iter_mut().zip(site_row).zip(above) {
                *g = if s { 0 } else { (a + 1).min(far) };
            }
        }
    }
    for y in (0..height.saturating_sub(1)).rev() {
        let (head, below) = g.split_at_mut((y + 1) * width);
        for (g, &b) in head[y * width..].iter_mut().zip(&below[..width]) {
            *g = (*g).min(b + 1);
        }
    }
    g
}

/// The distance transform of Meijster et al. (2000), as [`squared_distance_at`] computes it for
/// the ink, over the whole image: the distance to a site along each column, then per row the
/// lower envelope of the parabolas ([`envelope_row`]). The reference of [`dilate_disk`]'s tests.
#[cfg(test)]
pub(crate) fn squared_distances(sites: &[bool], width: usize, height: usize) -> Vec<f32> {
    if !sites.iter().any(|&s| s) {
        return vec![f32::INFINITY; sites.len()];
    }
    // No column distance reaches `far`: the parabola of a column without sites lies above every
    // real one.
    let far = (width + height) as u32;
    let g = column_distances(sites, width, height, far);
    let mut out = vec![0.0f32; width * height];
    out.par_chunks_mut(width.max(1))
        .zip(g.par_chunks(width.max(1)))
        .for_each_init(
            || (vec![0usize; width], vec![0i64; width], vec![0u64; width]),
            |(s, t, d2), (out, g)| {
                envelope_row(g, s, t, d2);
                for (o, &d) in out.iter_mut().zip(d2.iter()) {
                    *o = d as f32;
                }
            },
        );
    out
}

/// The closing of `ink` by a disk of radius `radius` px: dilation, then erosion, both by exact
/// Euclidean distance between pixel centres, squared distances compared with `radius²` in `f32`.
/// Pixels outside the image do not erode it, so a shape cut by the image edge keeps its closing
/// up to that edge.
///
/// Both steps only ask whether a site lies within the radius, so each is a dilation by the disk
/// ([`dilate_disk`]) rather than a full distance transform: the same sets, a few operations a
/// pixel. A radius that is not finite closes to nothing (no squared distance exceeds it).
///
/// The closing holds nothing farther than the radius from the ink's bounding box, and what it
/// holds there depends on pixels no farther than twice the radius: both steps run over that
/// box grown by twice the radius (and two pixels), the rest of the image left out.
pub(crate) fn close_disk(ink: &[bool], width: usize, height: usize, radius: f64) -> Vec<bool> {
    let r2 = (radius * radius) as f32;
    let mut out = vec![false; width * height];
    if !r2.is_finite() || width == 0 {
        return out;
    }
    let Some((xs, ys)) = ink_box(ink, width) else {
        return out;
    };
    let margin = (f64::from(r2).sqrt().ceil() as usize)
        .saturating_mul(2)
        .saturating_add(2);
    let (x0, x1) = (
        xs.start.saturating_sub(margin),
        xs.end.saturating_add(margin).min(width),
    );
    let (y0, y1) = (
        ys.start.saturating_sub(margin),
        ys.end.saturating_add(margin).min(height),
    );
    let cols = x1 - x0;
    let mut window = Vec::with_capacity(cols * (y1 - y0));
    for y in y0..y1 {
        window.extend_from_slice(&ink[y * width + x0..y * width + x1]);
    }
    let closed = closing(&window, cols, y1 - y0, r2);
    for (y, row) in (y0..y1).zip(closed.chunks_exact(cols)) {
        out[y * width + x0..y * width + x1].copy_from_slice(row);
    }
    out
}

/// The columns and rows of the bounding box of the ink of a `width`-wide mask, `None` without
/// ink.
pub(crate) fn ink_box(ink: &[bool], width: usize) -> Option<(Range<usize>, Range<usize>)> {
    if width == 0 {
        return None;
    }
    let mut found: Option<(Range<usize>, Range<usize>)> = None;
    for (y, row) in ink.chunks_exact(width).enumerate() {
        if let (Some(first), Some(last)) = (
            row.iter().position(|&on| on),
            row.iter().rposition(|&on| on),
        ) {
            found = Some(match found {
                None => (first..last + 1, y..y + 1),
                Some((xs, ys)) => (xs.start.min(first)..xs.end.max(last + 1), ys.start..y + 1),
            });
        }
    }
    found
}

/// [`close_disk`] over the whole of `ink`, `r2` the squared radius (finite).
fn closing(ink: &[bool], width: usize, height: usize, r2: f32) -> Vec<bool> {
    let dilated = dilate_disk(ink, width, height, r2);
    let outside: Vec<bool> = dilated.iter().map(|&d| !d).collect();
    let mut region = dilate_disk(&outside, width, height, r2);
    for r in &mut region {
        *r = !*r;
    }
    region
}

/// The pixels within the disk of a site: those whose squared distance (between pixel centres)
/// to the nearest `site`, as `f32`, is at most `r2` (finite, not negative); pixels outside the
/// image are never sites. As [`squared_distances`] would say, without computing the distances:
/// with `g` the distance to a site along each column, pixel `x` of a row is covered when some
/// column `i` of the row has `(x - i)² + g(i)² <= T`, `T` the largest integer at most `r2`, that
/// is when `|x - i|` is at most `i`'s half-width `⌊√(T - g(i)²)⌋`: two sweeps of the row carry
/// the farthest reach of the half-widths seen.
pub(crate) fn dilate_disk(sites: &[bool], width: usize, height: usize, r2: f32) -> Vec<bool> {
    let mut out = vec![false; width * height];
    if width == 0 || height == 0 || r2.is_nan() || r2 < 0.0 {
        return out;
    }
    // Every squared distance within the image is at most `cap`.
    let cap = ((width - 1) * (width - 1) + (height - 1) * (height - 1)) as u64;
    let t = if f64::from(r2) >= cap as f64 {
        cap
    } else {
        let mut t = r2 as u64;
        while ((t + 1) as f32) <= r2 {
            t += 1;
        }
        t
    };
    // The largest column distance that still reaches, and the half-width of each up to it.
    let mut g_max = (t as f64).sqrt() as u64;
    while g_max * g_max > t {
        g_max -= 1;
    }
    while (g_max + 1) * (g_max + 1) <= t {
        g_max += 1;
    }
    let g_max = g_max.min((width + height) as u64) as u32;
    let half: Vec<i64> = (0..=u64::from(g_max))
        .map(|g| {
            let rest = t - g * g;
            let mut h = (rest as f64).sqrt() as u64;
            while h * h > rest {
                h -= 1;
            }
            while (h + 1) * (h + 1) <= rest {
                h += 1;
            }
            h as i64
        })
        .collect();
    // Column distances, capped above `g_max` (such a column reaches no pixel of its row).
    let far = g_max + 1;
    // A column at `far` gets a negative half-width that reaches no pixel of the row either way
    // (`x + h < -1` rightwards, `x - h > width` leftwards), so the sweeps need no branch.
    let mut half = half;
    half.push(-(width as i64) - 2);
    let g = column_distances(sites, width, height, far);
    // Columns at `far` reach no pixel, so a run of them that no disk from before it reaches
    // (rightwards; from after it, leftwards) stays uncovered and leaves the reach as it was for
    // the pixels beyond (a far column's end lies past the image's other side): such runs of
    // `FAR_RUN` columns are skipped, where a print's closing finds no site across its middle.
    let far_run = |g: &[u32]| g.iter().fold(0, |any, &d| any | (d ^ far)) == 0;
    out.par_chunks_mut(width)
        .zip(g.par_chunks(width))
        .for_each(|(out, g)| {
            // Rightwards: the farthest right end of the disks of the columns at or before x.
            let n = out.len().min(g.len());
            let (out, g) = (&mut out[..n], &g[..n]);
            let mut reach = -1i64;
            for start in (0..n).step_by(FAR_RUN) {
                let end = (start + FAR_RUN).min(n);
                // `out` starts uncovered.
                if reach < start as i64 && far_run(&g[start..end]) {
                    continue;
                }
                for x in start..end {
                    reach = reach.max(x as i64 + half[g[x] as usize]);
                    out[x] = reach >= x as i64;
                }
            }
            // Leftwards: the farthest left end of those at or after x.
            let mut reach = i64::MAX;
            for start in (0..n).step_by(FAR_RUN).rev() {
                let end = (start + FAR_RUN).min(n);
                if reach >= end as i64 && far_run(&g[start..end]) {
                    continue;
                }
                for x in (start..end).rev() {
                    reach = reach.min(x as i64 - half[g[x] as usize]);
                    out[x] |= reach <= x as i64;
                }
            }
        });
    out
}

/// Columns of a row that [`dilate_disk`] skips together where none has a site within reach.
const FAR_RUN: usize = 32;

/// The number of ink pixels in `pixels`. A `bool` is one byte holding 0 or 1, so a block of at
/// most 255 of them sums in a `u8` without overflow, and the compiler adds 16 bytes at a time
/// (`filter(..).count()` widened each pixel to a `usize`: about 2.4 instructions a pixel).
pub(crate) fn ink_count(pixels: &[bool]) -> usize {
    // 128: at most 255, and a whole number of the vector loop's unrolled steps.
    pixels
        .chunks(128)
        .map(|block| {
            let sum = block
                .iter()
                .fold(0u8, |sum, &on| sum.wrapping_add(u8::from(on)));
            usize::from(sum)
        })
        .sum()
}

/// The number of ink pixels of a row-major mask `width` pixels wide, its rows counted in parallel.
pub(crate) fn ink_total(ink: &[bool], width: usize) -> usize {
    ink.par_chunks(width.max(1)).map(ink_count).sum()
}

/// Prefix counts of ink per row: the ink pixels of row `y` are numbers
/// `row_starts[y]..row_starts[y + 1]` in raster order. Has `height + 1` entries.
pub(crate) fn ink_row_starts(ink: &[bool], width: usize, height: usize) -> Vec<usize> {
    let counts: Vec<usize> = if width == 0 {
        vec![0; height]
    } else {
        ink.par_chunks(width).map(ink_count).collect()
    };
    let mut starts = Vec::with_capacity(height + 1);
    let mut total = 0;
    starts.push(0);
    for c in counts {
        total += c;
        starts.push(total);
    }
    starts
}

/// Splits `data` into consecutive pieces `starts[k]..starts[k + 1]` (so each row's share can be
/// written in parallel).
pub(crate) fn split_by<'a, T>(mut data: &'a mut [T], starts: &[usize]) -> Vec<&'a mut [T]> {
    let mut pieces = Vec::with_capacity(starts.len().saturating_sub(1));
    for w in starts.windows(2) {
        let (head, tail) = std::mem::take(&mut data).split_at_mut(w[1] - w[0]);
        pieces.push(head);
        data = tail;
    }
    pieces
}

/// Exact squared Euclidean distance transform (Meijster et al. 2000), evaluated at the ink pixels:
/// writes `value(d²)` for the `k`-th ink pixel of the image into `out[k]` (`out` has one entry per
/// ink pixel; `row_starts` from [`ink_row_starts`]). Pixels outside the image are background.
pub(crate) fn squared_distance_rows<T, F>(
    ink: &[bool],
    width: usize,
    height: usize,
    row_starts: &[usize],
    out: &mut [T],
    value: F,
) where
    T: Send,
    F: Fn(u64) -> T + Sync,
{
    let mask = Mask {
        ink,
        width,
        height,
        row_starts,
    };
    squared_distance_at(&mask, &mask, out, value);
}

/// A row-major mask with its per-row ink counts (see [`ink_row_starts`]).
pub(crate) struct Mask<'a> {
    /// Row-major ink flags.
    pub ink: &'a [bool],
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Ink pixels before each row; `height + 1` entries.
    pub row_starts: &'a [usize],
}

/// Like [`squared_distance_rows`] for the distance transform of `mask`, written only at the ink
/// pixels of `keep`, a subset of `mask` of the same size: `out[k]` for the `k`-th ink pixel of
/// `keep`. Dropout mode measures on the closing but keeps the original pixels.
pub(crate) fn squared_distance_at<T, F>(mask: &Mask, keep: &Mask, out: &mut [T], value: F)
where
    T: Send,
    F: Fn(u64) -> T + Sync,
{
    let Mask {
        ink,
        width,
        height,
        row_starts,
    } = *mask;
    if width == 0 || height == 0 {
        return;
    }
    // Column pass: g = vertical distance to the nearest background pixel in the column, with
    // virtual background rows at -1 and `height`. Stored only for the ink pixels, in raster order
    // (the background has 0), with one running value per column for each sweep.
    let count = row_starts[height];
    let mut g = vec![0u32; count];
    let mut run = vec![0u32; width];
    let mut k = 0;
    for ink_row in ink.chunks_exact(width) {
        for (x, &on) in ink_row.iter().enumerate() {
            if on {
                run[x] += 1;
                g[k] = run[x];
                k += 1;
            } else {
                run[x] = 0;
            }
        }
    }
    run.fill(0);
    let mut k = count;
    for ink_row in ink.chunks_exact(width).rev() {
        for (x, &on) in ink_row.iter().enumerate().rev() {
            if on {
                run[x] += 1;
                k -= 1;
                g[k] = g[k].min(run[x]);
            } else {
                run[x] = 0;
            }
        }
    }

    // Row pass, rows in parallel: each row writes only its own ink pixels' entries. A run of ink
    // between two background pixels (or the image edge: virtual background) is independent of the
    // rest of the row: every background pixel beyond the run's ends is farther than the end
    // pixel itself. So the lower envelope runs over the ink only, O(ink) instead of O(pixels),
    // and a run's `g` values are contiguous.
    let pieces = split_by(out, keep.row_starts);
    pieces.into_par_iter().enumerate().for_each_init(
        || RunEnvelope::with_capacity(width),
        |envelope, (y, piece)| {
            let row_g = &g[row_starts[y]..row_starts[y + 1]];
            let ink_row = &ink[y * width..(y + 1) * width];
            let keep_row = &keep.ink[y * width..(y + 1) * width];
            // k: this row's ink pixels of `mask` seen so far; kept: entries of `piece` written.
            let mut k = 0;
            let mut kept = 0;
            let mut x = 0;
            while kept < piece.len() && x < width {
                if !ink_row[x] {
                    x += 1;
                    continue;
                }
                let start = x;
                while x < width && ink_row[x] {
                    x += 1;
                }
                let len = x - start;
                let run_d2 = envelope.squared_distances(&row_g[k..k + len]);
                for (i, &d2) in run_d2.iter().enumerate() {
                    if keep_row[start + i] {
                        piece[kept] = value(d2);
                        kept += 1;
                    }
                }
                k += len;
            }
        },
    );
}

/// The row pass of the distance transform for one run of ink between two background pixels (or
/// the image edges), with reusable buffers. A run is independent of the rest of its row: every
/// background pixel beyond its ends is farther than the end pixel itself.
pub(crate) struct RunEnvelope {
    s: Vec<usize>,
    t: Vec<i64>,
    d2: Vec<u64>,
}

impl RunEnvelope {
    /// Buffers for runs of up to `width` pixels (they grow when a run is longer).
    pub(crate) fn with_capacity(width: usize) -> Self {
        RunEnvelope {
            s: vec![0; width],
            t: vec![0; width],
            d2: vec![0; width],
        }
    }

    /// Squared distances to the background of the run's pixels, given `g`, each pixel's vertical
    /// distance to the background of its column.
    pub(crate) fn squared_distances(&mut self, g: &[u32]) -> &[u64] {
        let len = g.len();
        if self.d2.len() < len {
            self.s.resize(len, 0);
            self.t.resize(len, 0);
            self.d2.resize(len, 0);
        }
        let d2 = &mut self.d2[..len];
        // Every parabola of the envelope lies at or above `min(g)²`, and no pixel is farther
        // from the run's ends than `(len + 1) / 2`: where the smallest column distance reaches
        // that (a short run across a tall stroke, most runs of text), the run's ends are the
        // nearest background of all its pixels and the envelope is not needed.
        let nearest_column = g.iter().copied().min().unwrap_or(0) as usize;
        if nearest_column >= len.div_ceil(2) {
            for (i, d2) in d2.iter_mut().enumerate() {
                *d2 = ((i + 1).min(len - i) as u64).pow(2);
            }
            return d2;
        }
        envelope_row(g, &mut self.s[..len], &mut self.t[..len], d2);
        for (i, d2) in d2.iter_mut().enumerate() {
            // The background pixels (or virtual columns) just before and after the run.
            let side = ((i + 1).min(len - i) as u64).pow(2);
            *d2 = (*d2).min(side);
        }
        d2
    }
}

/// One row of Meijster's second phase: `d2[x] = min_i (x - i)² + g(i)²`.
fn envelope_row(g: &[u32], s: &mut [usize], t: &mut [i64], d2: &mut [u64]) {
    let w = g.len();
    let f = |x: usize, i: usize| -> i64 {
        let dx = x as i64 - i as i64;
        dx * dx + (g[i] as i64) * (g[i] as i64)
    };
    // Sep(i, u): first x where the parabola of u is below that of i (floor division).
    let sep = |i: usize, u: usize| -> i64 {
        let (ii, uu) = (i as i64, u as i64);
        let (gi, gu) = (g[i] as i64, g[u] as i64);
        (uu * uu - ii * ii + gu * gu - gi * gi).div_euclid(2 * (uu - ii))
    };
    let mut q: isize = 0;
    s[0] = 0;
    t[0] = 0;
    for u in 1..w {
        while q >= 0 && f(t[q as usize] as usize, s[q as usize]) > f(t[q as usize] as usize, u) {
            q -= 1;
        }
        if q < 0 {
            q = 0;
            s[0] = u;
        } else {
            let boundary = 1 + sep(s[q as usize], u);
            if boundary < w as i64 {
                q += 1;
                s[q as usize] = u;
                t[q as usize] = boundary;
            }
        }
    }
    for u in (0..w).rev() {
        d2[u] = f(u, s[q as usize]) as u64;
        if u as i64 == t[q as usize] {
            q -= 1;
        }
    }
}

/// The 3x3 morphological closing (dilation then erosion, square element) of dropout mode
/// (adaptation 2): it bridges the one- and two-pixel gaps that random dropout leaves inside
/// strokes, so the distance transform sees the stroke's full width. Computed on the image padded
/// with one ring of background, so the result is the closing on an unbounded background plane,
/// cropped: it contains `ink` and does not glue strokes to the image border.
pub(crate) fn close3(ink: &[bool], width: usize, height: usize) -> Vec<bool> {
    let (pw, ph) = (width + 2, height + 2);
    let mut padded = vec![false; pw * ph];
    for y in 0..height {
        padded[(y + 1) * pw + 1..(y + 1) * pw + 1 + width]
            .copy_from_slice(&ink[y * width..(y + 1) * width]);
    }
    let dilated = morph3(&padded, pw, ph, true);
    let closed = morph3(&dilated, pw, ph, false);
    let mut out = Vec::with_capacity(width * height);
    for y in 0..height {
        out.extend_from_slice(&closed[(y + 1) * pw + 1..(y + 1) * pw + 1 + width]);
    }
    out
}

/// Dilation (`dilate`) or erosion by the 3x3 square, as a separable max or min filter over the
/// pixels inside the image: outside it counts as background for dilation and as ink for erosion,
/// so the image edge neither grows a mask nor eats it (the fingerprint segmentation's block
/// flags rely on that; [`close3`] pads the image first when the edge should erode).
pub(crate) fn morph3(mask: &[bool], width: usize, height: usize, dilate: bool) -> Vec<bool> {
    if width == 0 || height == 0 {
        return Vec::new();
    }
    // Combines three equally long slices element by element (written as straight loops over
    // slices so they vectorize).
    let combine3 = |out: &mut [bool], a: &[bool], b: &[bool], c: &[bool]| {
        if dilate {
            for (((o, &a), &b), &c) in out.iter_mut().zip(a).zip(b).zip(c) {
                *o = a | b | c;
            }
        } else {
            for (((o, &a), &b), &c) in out.iter_mut().zip(a).zip(b).zip(c) {
                *o = a & b & c;
            }
        }
    };
    let mut horizontal = vec![false; mask.len()];
    horizontal
        .par_chunks_mut(width)
        .zip(mask.par_chunks(width))
        .for_each(|(out, row)| {
            if width < 3 {
                for x in 0..width {
                    let (a, b) = (x.saturating_sub(1), (x + 1).min(width - 1));
                    out[x] = if dilate {
                        row[a] | row[x] | row[b]
                    } else {
                        row[a] & row[x] & row[b]
                    };
                }
                return;
            }
            combine3(
                &mut out[1..width - 1],
                &row[..width - 2],
                &row[1..width - 1],
                &row[2..],
            );
            out[0] = if dilate {
                row[0] | row[1]
            } else {
                row[0] & row[1]
            };
            let last = width - 1;
            out[last] = if dilate {
                row[last - 1] | row[last]
            } else {
                row[last - 1] & row[last]
            };
        });
    let mut result = vec![false; mask.len()];
    result
        .par_chunks_mut(width)
        .enumerate()
        .for_each(|(y, out)| {
            let row = |v: usize| &horizontal[v * width..(v + 1) * width];
            let (above, below) = (row(y.saturating_sub(1)), row((y + 1).min(height - 1)));
            combine3(out, above, row(y), below);
        });
    result
}

/// Total pixel count of the background 4-connected components of at most 3 pixels that do not
/// touch the image border: the specks random dropout punches into strokes (adaptation 2).
pub(crate) fn tiny_hole_pixels(ink: &[bool], width: usize, height: usize) -> usize {
    if width < 3 || height < 3 {
        return 0;
    }
    (1..height - 1)
        .into_par_iter()
        .map(|y| {
            let mut total = 0;
            for x in 1..width - 1 {
                let i = y * width + x;
                // A hole is counted from its first pixel in raster order, whose left neighbour
                // is ink: a background one would be in the same hole, and earlier.
                if ink[i] || !ink[i - 1] {
                    continue;
                }
                if let Some(size) = tiny_hole(ink, width, height, i) {
                    total += size;
                }
            }
            total
        })
        .sum()
}

/// The size of the background component of pixel `start` when it has at most 3 pixels, does not
/// touch the border, and `start` is its first pixel in raster order (so each is counted once).
pub(crate) fn tiny_hole(ink: &[bool], width: usize, height: usize, start: usize) -> Option<usize> {
    tiny_hole_pixels_at(ink, width, height, start).map(|(_, len)| len)
}

/// [`tiny_hole`], counted only where the hole lies inside a stroke: `None` as well when every ink
/// pixel around it also touches (8-adjacent) background that is no tiny hole. Such a hole lies
/// between lines at most one pixel thick (1-px lines meeting at a shallow angle enclose single
/// background pixels), a gap of the drawing rather than a speck punched into a stroke's body,
/// which has ink around the speck on every side (docs/design.md, "The front end").
pub(crate) fn tiny_hole_in_stroke(
    ink: &[bool],
    width: usize,
    height: usize,
    start: usize,
) -> Option<usize> {
    let (hole, len) = tiny_hole_pixels_at(ink, width, height, start)?;
    let hole = &hole[..len];
    // The hole touches no border, so its pixels' 8-neighbours are inside the image.
    let around = |p: usize| {
        [
            p - width - 1,
            p - width,
            p - width + 1,
            p - 1,
            p + 1,
            p + width - 1,
            p + width,
            p + width + 1,
        ]
    };
    let open = |q: usize| !ink[q] && !hole.contains(&q) && !in_speck(ink, width, height, q);
    let inside = hole.iter().flat_map(|&p| around(p)).any(|r| {
        ink[r] && {
            let (x, y) = (r % width, r / width);
            // A ring pixel on the border has background beyond it.
            x > 0 && y > 0 && x + 1 < width && y + 1 < height && !around(r).into_iter().any(open)
        }
    });
    inside.then_some(len)
}

/// Whether background pixel `q` lies in a 4-connected background component of at most 3 pixels
/// that does not touch the image border.
fn in_speck(ink: &[bool], width: usize, height: usize, q: usize) -> bool {
    speck_at(ink, width, height, q).is_some()
}

/// The pixels of [`tiny_hole`]'s component, `start` first (the first `len` of the array): what
/// filling the speck sets.
pub(crate) fn tiny_hole_pixels_at(
    ink: &[bool],
    width: usize,
    height: usize,
    start: usize,
) -> Option<([usize; 3], usize)> {
    let (component, len) = speck_at(ink, width, height, start)?;
    (component[..len].iter().min() == Some(&start)).then_some((component, len))
}

/// The 4-connected background component of `start` (the first `len` of the array, `start`
/// first) when it has at most 3 pixels and does not touch the image border.
fn speck_at(
    ink: &[bool],
    width: usize,
    height: usize,
    start: usize,
) -> Option<([usize; 3], usize)> {
    let mut component = [start; 3];
    let mut len = 1;
    let mut next = 0;
    while next < len {
        let p = component[next];
        next += 1;
        let (x, y) = (p % width, p / width);
        if x == 0 || y == 0 || x == width - 1 || y == height - 1 {
            return None;
        }
        for q in [p - 1, p + 1, p - width, p + width] {
            if ink[q] || component[..len].contains(&q) {
                continue;
            }
            if len == 3 {
                return None;
            }
            component[len] = q;
            len += 1;
        }
    }
    Some((component, len))
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Luma};

    /// The column pass pixel by pixel, as it was written before it went a row at a time.
    fn column_distances_by_pixel(
        sites: &[bool],
        width: usize,
        height: usize,
        far: u32,
    ) -> Vec<u32> {
        let mut g = vec![far; width * height];
        for y in 0..height {
            for x in 0..width {
                let p = y * width + x;
                g[p] = if sites[p] {
                    0
                } else if y > 0 {
                    (g[p - width] + 1).min(far)
                } else {
                    far
                };
            }
        }
        for p in (0..width * height.saturating_sub(1)).rev() {
            g[p] = g[p].min(g[p + width] + 1);
        }
        g
    }

    #[test]
    fn the_column_pass_by_rows_is_the_pass_by_pixels() {
        let mut seed = 41u64;
        for (w, h) in [(0, 3), (3, 0), (1, 1), (1, 7), (9, 1), (17, 12), (64, 31)] {
            for density in [0, 3, 30, 95] {
                let sites = random_sites(&mut seed, w * h, density);
                for far in [1, 2, 5, (w + h) as u32 + 1] {
                    assert_eq!(
                        column_distances(&sites, w, h, far),
                        column_distances_by_pixel(&sites, w, h, far),
                        "{w}x{h} density {density} far {far}"
                    );
                }
            }
        }
    }

    /// Squared distances to the nearest site by trying every site (infinite for none).
    fn brute_force(sites: &[bool], w: usize, h: usize) -> Vec<f64> {
        (0..w * h)
            .map(|p| {
                let (x, y) = ((p % w) as f64, (p / w) as f64);
                sites
                    .iter()
                    .enumerate()
                    .filter(|(_, &s)| s)
                    .map(|(i, _)| ((i % w) as f64 - x).powi(2) + ((i / w) as f64 - y).powi(2))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    /// A run's squared distances (short runs across tall strokes included, which skip the
    /// envelope) equal the direct minimum over its columns and the background at its ends.
    #[test]
    fn run_envelope_equals_the_direct_minimum() {
        let mut seed = 7u64;
        let mut envelope = RunEnvelope::with_capacity(4);
        for len in 1..12usize {
            for _ in 0..50 {
                let g: Vec<u32> = (0..len)
                    .map(|_| {
                        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                        1 + ((seed >> 33) % 9) as u32
                    })
                    .collect();
                let direct: Vec<u64> = (0..len)
                    .map(|x| {
                        let ends = ((x + 1).min(len - x) as u64).pow(2);
                        (0..len)
                            .map(|i| (x.abs_diff(i) as u64).pow(2) + u64::from(g[i]).pow(2))
                            .fold(ends, u64::min)
                    })
                    .collect();
                assert_eq!(envelope.squared_distances(&g), &direct[..], "g = {g:?}");
            }
        }
    }

    /// `len` sites, each set with `density` % chance, from a linear congruential `seed`.
    fn random_sites(seed: &mut u64, len: usize, density: u64) -> Vec<bool> {
        (0..len)
            .map(|_| {
                *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                density > 0 && (*seed >> 33) % 100 < density
            })
            .collect()
    }

    #[test]
    fn distances_to_sites_are_exact() {
        let mut seed = 99u64;
        for (w, h) in [(1, 1), (1, 6), (7, 1), (23, 17), (40, 9)] {
            for density in [0, 2, 31, 97] {
                let sites = random_sites(&mut seed, w * h, density);
                let d: Vec<f64> = squared_distances(&sites, w, h)
                    .iter()
                    .map(|&v| f64::from(v))
                    .collect();
                assert_eq!(d, brute_force(&sites, w, h), "{w}x{h} density {density}");
            }
        }
    }

    #[test]
    fn the_dilation_by_a_disk_is_the_distance_within_the_radius() {
        let mut seed = 17u64;
        for (w, h) in [(1, 1), (5, 1), (1, 4), (21, 14), (33, 25)] {
            for density in [0, 1, 7, 40] {
                let sites = random_sites(&mut seed, w * h, density);
                let d = brute_force(&sites, w, h);
                for r2 in [0.0f32, 1.0, 1.99, 2.0, 8.5, 25.0, 60.3, 1e4, 1e9] {
                    let expected: Vec<bool> = d.iter().map(|&d| d as f32 <= r2).collect();
                    assert_eq!(
                        dilate_disk(&sites, w, h, r2),
                        expected,
                        "{w}x{h} density {density} r2 {r2}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_dilation_skips_runs_of_far_columns_and_stays_exact() {
        // Wide rows with a few small patches of sites: runs of columns without a site within
        // reach, before, between and after the patches' disks, at every offset from the runs'
        // boundaries, and radii reaching into, across and past whole runs.
        let mut seed = 23u64;
        let mut next = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 33) as usize
        };
        for (w, h) in [(150, 9), (97, 31), (64, 5), (33, 3), (200, 1)] {
            for patches in [0, 1, 2, 5] {
                let mut sites = vec![false; w * h];
                for _ in 0..patches {
                    let (px, py) = (next() % w, next() % h);
                    for _ in 0..4 {
                        let (x, y) = ((px + next() % 3).min(w - 1), (py + next() % 3).min(h - 1));
                        sites[y * w + x] = true;
                    }
                }
                let d = brute_force(&sites, w, h);
                for r2 in [0.0f32, 2.0, 30.0, 250.0, 1100.0, 5000.0] {
                    let expected: Vec<bool> = d.iter().map(|&d| d as f32 <= r2).collect();
                    assert_eq!(
                        dilate_disk(&sites, w, h, r2),
                        expected,
                        "{w}x{h} patches {patches} r2 {r2}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_closing_by_a_disk_is_the_closing_by_definition() {
        let mut seed = 5u64;
        for (w, h) in [(1, 1), (3, 1), (19, 13), (30, 22)] {
            let ink: Vec<bool> = (0..w * h)
                .map(|_| {
                    seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                    (seed >> 33) % 100 < 12
                })
                .collect();
            for radius in [0.0, 1.0, 1.5, 3.2, 6.0, 100.0, f64::NAN, -2.0] {
                let r2 = (radius * radius) as f32;
                let to_ink = brute_force(&ink, w, h);
                let dilated: Vec<bool> = to_ink.iter().map(|&d| d as f32 <= r2).collect();
                let outside: Vec<bool> = dilated.iter().map(|&d| !d).collect();
                let expected: Vec<bool> = brute_force(&outside, w, h)
                    .iter()
                    .map(|&d| d as f32 > r2)
                    .collect();
                assert_eq!(
                    close_disk(&ink, w, h, radius),
                    expected,
                    "{w}x{h} radius {radius}"
                );
            }
        }
    }

    #[test]
    fn the_closing_of_ink_in_a_corner_of_the_image_is_the_whole_images() {
        // Ink in a patch (the closing then runs over the patch's box grown by twice the radius),
        // in the middle, at an edge and at a corner, against the closing over the whole image.
        let mut seed = 11u64;
        let (w, h) = (61, 47);
        for (px, py) in [(25, 20), (0, 10), (50, 0), (52, 40), (3, 36)] {
            let patch = random_sites(&mut seed, 9 * 7, 35);
            let mut ink = vec![false; w * h];
            for (k, &on) in patch.iter().enumerate() {
                let (x, y) = (px + k % 9, py + k / 9);
                if x < w && y < h {
                    ink[y * w + x] = on;
                }
            }
            for radius in [0.0, 1.0, 2.5, 4.0, 9.3, 30.0, 1e3] {
                let r2 = (radius * radius) as f32;
                assert_eq!(
                    close_disk(&ink, w, h, radius),
                    closing(&ink, w, h, r2),
                    "patch at {px} {py}, radius {radius}"
                );
            }
        }
        assert_eq!(close_disk(&[false; 12], 4, 3, 2.0), vec![false; 12]);
    }

    #[test]
    fn one_pixel_and_empty_images() {
        for connectivity in [Connectivity::Four, Connectivity::Eight] {
            assert_eq!(
                label_components(&[true], 1, 1, true, connectivity),
                (vec![1], vec![0, 1])
            );
            assert_eq!(
                label_components(&[true], 1, 1, false, connectivity),
                (vec![0], vec![1])
            );
        }
        assert_eq!(
            label_components(&[], 0, 0, true, Connectivity::Four),
            (vec![], vec![0])
        );
        assert_eq!(
            label_components(&[], 0, 3, true, Connectivity::Eight),
            (vec![], vec![0])
        );
    }

    #[test]
    fn labels_are_imageproc_labels() {
        // Random masks of several densities and shapes (one row, one column, wide, tall), both
        // values and both connectivities, against imageproc's labelling of the same pixels.
        let mut seed = 99u64;
        for (w, h) in [
            (1usize, 7usize),
            (9, 1),
            (2, 2),
            (17, 13),
            (40, 3),
            (5, 31),
            (64, 64),
        ] {
            for density in [10u64, 35, 50, 65, 90] {
                let flags: Vec<bool> = (0..w * h)
                    .map(|_| {
                        seed = seed
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        (seed >> 33) % 100 < density
                    })
                    .collect();
                for value in [true, false] {
                    for connectivity in [Connectivity::Four, Connectivity::Eight] {
                        let image = GrayImage::from_fn(w as u32, h as u32, |x, y| {
                            Luma([u8::from(flags[y as usize * w + x as usize] == value) * 255])
                        });
                        let expected = imageproc::region_labelling::connected_components(
                            &image,
                            connectivity,
                            Luma([0u8]),
                        )
                        .into_raw();
                        let (labels, sizes) = label_components(&flags, w, h, value, connectivity);
                        assert_eq!(
                            labels, expected,
                            "{w}x{h} {density}% {value} {connectivity:?}"
                        );
                        let mut counted = vec![0usize; sizes.len()];
                        for &l in &labels {
                            counted[l as usize] += 1;
                        }
                        assert_eq!(sizes, counted);
                    }
                }
            }
        }
    }

    #[test]
    fn labels_in_raster_order_of_first_pixel() {
        let (flags, w, h) = mask(&["#..#", "#.##", "..#.", "#..."]);
        let (four, sizes) = label_components(&flags, w, h, true, Connectivity::Four);
        assert_eq!(four, vec![1, 0, 0, 2, 1, 0, 2, 2, 0, 0, 2, 0, 3, 0, 0, 0]);
        assert_eq!(sizes, vec![9, 2, 4, 1]);
        let (eight, _) = label_components(&flags, w, h, true, Connectivity::Eight);
        assert_eq!(eight, four);
        let (paper, sizes) = label_components(&flags, w, h, false, Connectivity::Four);
        assert_eq!(paper[1], 1);
        assert_eq!(sizes.iter().sum::<usize>(), 16);
        let (diagonal, w, h) = mask(&["#.", ".#"]);
        let four = label_components(&diagonal, w, h, true, Connectivity::Four);
        let eight = label_components(&diagonal, w, h, true, Connectivity::Eight);
        assert_eq!(four, (vec![1, 0, 0, 2], vec![2, 1, 1]));
        assert_eq!(eight, (vec![1, 0, 0, 1], vec![2, 2]));
    }

    /// The 3x3 square by definition: every window cell, outside the image `!dilate`.
    fn morph3_by_definition(flags: &[bool], w: usize, h: usize, dilate: bool) -> Vec<bool> {
        let at = |x: i64, y: i64| {
            if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
                !dilate
            } else {
                flags[y as usize * w + x as usize]
            }
        };
        let mut out = Vec::with_capacity(w * h);
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                let window = (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)));
                let mut values = window.map(|(dx, dy)| at(x + dx, y + dy));
                out.push(if dilate {
                    values.any(|v| v)
                } else {
                    values.all(|v| v)
                });
            }
        }
        out
    }

    #[test]
    fn morph3_is_the_3x3_square_with_the_edge_neither_growing_nor_eating() {
        let mut seed = 7u64;
        for (w, h) in [
            (1, 1),
            (1, 5),
            (5, 1),
            (2, 2),
            (2, 7),
            (3, 3),
            (9, 4),
            (16, 11),
        ] {
            for _ in 0..20 {
                let flags: Vec<bool> = (0..w * h)
                    .map(|_| {
                        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                        (seed >> 40) % 3 != 0
                    })
                    .collect();
                for dilate in [false, true] {
                    assert_eq!(
                        morph3(&flags, w, h, dilate),
                        morph3_by_definition(&flags, w, h, dilate),
                        "{w}x{h} dilate {dilate}"
                    );
                }
            }
        }
    }

    fn mask(rows: &[&str]) -> (Vec<bool>, usize, usize) {
        let w = rows[0].len();
        let ink = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| b == b'#'))
            .collect();
        (ink, w, rows.len())
    }

    /// Brute force: nearest background center, outside pixels included.
    fn brute(ink: &[bool], w: usize, h: usize) -> Vec<u64> {
        let mut out = Vec::new();
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                if !ink[y as usize * w + x as usize] {
                    continue;
                }
                let mut best = u64::MAX;
                for by in -1..=h as i64 {
                    for bx in -1..=w as i64 {
                        let outside = bx < 0 || by < 0 || bx >= w as i64 || by >= h as i64;
                        if outside || !ink[by as usize * w + bx as usize] {
                            best = best.min(((bx - x).pow(2) + (by - y).pow(2)) as u64);
                        }
                    }
                }
                out.push(best);
            }
        }
        out
    }

    #[test]
    fn the_ink_count_by_blocks_is_the_count_one_by_one() {
        let mut state = 7u32;
        for len in (0..600).chain([1000, 4096, 4097]) {
            for density in [0, 1, 3, 7, 8] {
                let pixels: Vec<bool> = (0..len)
                    .map(|_| {
                        state = state.wrapping_mul(1_103_515_245).wrapping_add(12345);
                        (state >> 16) % 8 < density
                    })
                    .collect();
                let by_one = pixels.iter().filter(|&&on| on).count();
                assert_eq!(
                    ink_count(&pixels),
                    by_one,
                    "{len} pixels, density {density}"
                );
            }
        }
    }

    fn exact(ink: &[bool], w: usize, h: usize) -> Vec<u64> {
        let starts = ink_row_starts(ink, w, h);
        let mut out = vec![0u64; starts[h]];
        squared_distance_rows(ink, w, h, &starts, &mut out, |d2| d2);
        out
    }

    #[test]
    fn distance_transform_matches_brute_force() {
        // A deterministic pseudo-random blobby mask.
        let (w, h) = (37, 23);
        let mut state = 12345u32;
        let ink: Vec<bool> = (0..w * h)
            .map(|i| {
                state = state.wrapping_mul(1_103_515_245).wrapping_add(12345);
                let (x, y) = (i % w, i / w);
                (state >> 16) % 7 != 0 && (x * y) % 11 != 3
            })
            .collect();
        assert_eq!(exact(&ink, w, h), brute(&ink, w, h));
        let all = vec![true; w * h];
        assert_eq!(exact(&all, w, h), brute(&all, w, h));
    }

    #[test]
    fn distance_on_3_and_5_pixel_lines() {
        let (ink, w, h) = mask(&[
            "...........",
            "###########",
            "###########",
            "###########",
            "...........",
            "...........",
            "###########",
            "###########",
            "###########",
            "###########",
            "###########",
            "...........",
        ]);
        let d: Vec<f32> = ink_distances(&ink, w, h);
        // Center of a 3-px line at x = 5 (row 2): 2; edge rows 1.
        assert_eq!(d[w + 5], 2.0);
        assert_eq!(d[5], 1.0);
        // Center row of the 5-px line (row 8 = third line of block 2): 3.
        assert_eq!(d[3 * w + 2 * w + 5], 3.0);
        // Ends of the lines touch the image border: 1.
        assert_eq!(d[w], 1.0);
    }

    #[test]
    fn closing_fills_pinholes() {
        let (ink, w, h) = mask(&["......", ".####.", ".#.##.", ".####.", "......"]);
        let closed = close3(&ink, w, h);
        assert!(closed[2 * w + 2]);
        assert_eq!(closed.iter().filter(|&&b| b).count(), 12);
    }

    #[test]
    fn a_speck_between_one_pixel_lines_is_no_hole_in_a_stroke() {
        // Two 1-px lines meeting at a shallow angle (where 1-px strokes cross at 15 degrees)
        // enclose (5,2); a 3-px stroke holds (5,2) below.
        let (ink, w, h) = mask(&[
            "..........",
            "...###....",
            ".####.##..",
            ".....#####",
            "..........",
        ]);
        let at = |x: usize, y: usize| y * w + x;
        assert_eq!(tiny_hole(&ink, w, h, at(5, 2)), Some(1));
        assert_eq!(tiny_hole_in_stroke(&ink, w, h, at(5, 2)), None);
        let (ink, w, h) = mask(&[
            "..........",
            ".########.",
            ".####.###.",
            ".########.",
            "..........",
        ]);
        assert_eq!(tiny_hole_in_stroke(&ink, w, h, at(5, 2)), Some(1));
        // A neighbouring speck is no open background: two specks in one stroke both count.
        let (ink, w, h) = mask(&[
            "..........",
            ".########.",
            ".###.#.##.",
            ".########.",
            "..........",
        ]);
        assert_eq!(tiny_hole_in_stroke(&ink, w, h, at(4, 2)), Some(1));
        assert_eq!(tiny_hole_in_stroke(&ink, w, h, at(6, 2)), Some(1));
    }

    #[test]
    fn tiny_holes_counted_once() {
        let (ink, w, h) = mask(&[
            "..........",
            ".########.",
            ".#.##..##.",
            ".########.",
            ".#....####",
            ".########.",
            "..........",
        ]);
        // Holes: 1 px at (2,2), 2 px at (5..7,2); the 4-px hole on row 4 is too big.
        assert_eq!(tiny_hole_pixels(&ink, w, h), 3);
    }
}
