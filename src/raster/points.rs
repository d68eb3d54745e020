//! Ink pixels to the strip point set `P` (docs/design.md, adaptation 1): one point per ink pixel
//! center in raster order, the pixel neighbour graph (8-neighbourhood, or 5x5 in dropout mode) in
//! CSR form, the half-width from an exact Euclidean distance transform, and `Dis_ave`.
//!
//! Everything here is O(pixels) with no allocation per point; rows run in parallel and write only
//! their own slices, so the output does not depend on the thread count.

use rayon::prelude::*;

use crate::binary::MaskView;
use crate::error::{Error, Result};
use crate::mask::{
    close3, ink_row_starts, ink_total, split_by, squared_distance_at, squared_distance_rows,
    tiny_hole_in_stroke, Mask, Run, RunEnvelope,
};
use crate::params::Params;
use crate::point_set::{Grid, PointSet};

/// `Dis_ave` above this switches dropout mode on (adaptation 2): more than about 5% of the
/// points have no ink pixel touching them.
const DROPOUT_SPACING: f64 = 1.05;
/// Share of ink pixels with exactly one ink 8-neighbour, line ends left out
/// ([`ends_a_line`]), above which dropout mode switches on.
pub(super) const LOOSE_FRACTION: f64 = 0.025;
/// Pixels a chain one pixel wide runs from a pixel with a single ink 8-neighbour, without
/// branching or ending, for that pixel to be the end of a line rather than a speck or a spike:
/// three widths of the line.
const LINE_END_RUN: usize = 3;

/// Nearest-neighbour search radius (Chebyshev, pixels) for points with no touching ink pixel.
/// Points with nothing closer are isolated specks, not samples of a stroke, and are left out of
/// `Dis_ave`.
const SPACING_SEARCH: i64 = 6;

/// Builds the point set of the ink pixels of `binary`: the page's figures from [`survey`], then
/// [`build`] over the whole image. Dropout mode is `dropout` when given, else decided here
/// (docs/design.md, adaptation 2).
pub fn points(binary: MaskView<'_>, params: &Params, dropout: Option<bool>) -> Result<PointSet> {
    let survey = survey(binary, params, dropout)?;
    let window = Window {
        ink: binary.ink,
        width: binary.width as usize,
        height: binary.height as usize,
        x0: 0,
        y0: 0,
    };
    build(&window, survey.spacing, survey.dropout)
}

/// What one pass over the rows of an image finds before any point exists: its runs of ink and
/// the figures that hold for the whole page, whether it is traced whole or in chunks.
pub(super) struct Survey {
    /// The runs of ink in raster order.
    pub(super) runs: Vec<Run>,
    /// `Dis_ave` (1 when no pixel has a neighbour).
    pub(super) spacing: f64,
    /// Whether dropout mode is on (adaptation 2).
    pub(super) dropout: bool,
}

/// Surveys `binary` (refusing a mask of the wrong size, or more ink pixels than the limits allow):
/// one parallel pass over the rows finds the runs of ink, the `Dis_ave` terms and the pixels with
/// a single 8-neighbour; the rows are summed in order, so the figures do not depend on the thread
/// count. Dropout mode is `dropout` when given.
pub(super) fn survey(
    binary: MaskView<'_>,
    params: &Params,
    dropout: Option<bool>,
) -> Result<Survey> {
    binary.check_size()?;
    let count = ink_total(binary.ink, binary.width as usize);
    survey_counted(binary, params, dropout, count)
}

/// [`survey`] of a mask of the right size whose ink pixels were counted (`count`) by the caller.
pub(super) fn survey_counted(
    binary: MaskView<'_>,
    params: &Params,
    dropout: Option<bool>,
    count: usize,
) -> Result<Survey> {
    let (width, height) = (binary.width as usize, binary.height as usize);
    let ink = binary.ink;
    check_point_count(count, params)?;
    let rows: Vec<(Vec<Run>, (f64, u64), usize)> = (0..height)
        .into_par_iter()
        .map_init(
            || vec![0u8; width + 2],
            |column, y| {
                let row = &ink[y * width..(y + 1) * width];
                // Ink in each column of rows y - 1..=y + 1, at `column[x + 1]`: a pixel's degree
                // is the sum over its three columns, less itself.
                let column = &mut column[..];
                for (c, &on) in column[1..=width].iter_mut().zip(row) {
                    *c = u8::from(on);
                }
                let neighbour_rows = [y.checked_sub(1), Some(y + 1).filter(|&v| v < height)];
                for v in neighbour_rows.into_iter().flatten() {
                    let other = &ink[v * width..(v + 1) * width];
                    for (c, &on) in column[1..=width].iter_mut().zip(other) {
                        *c += u8::from(on);
                    }
                }
                let mut runs = Vec::new();
                let mut spacing = (0.0f64, 0u64);
                let mut loose = 0;
                let mut x = 0;
                loop {
                    x = next_ink(row, x);
                    if x >= width {
                        break;
                    }
                    let start = x;
                    while x < width && row[x] {
                        let degree = u32::from(column[x] + column[x + 1] + column[x + 2]) - 1;
                        loose += usize::from(degree == 1 && !ends_a_line(binary, x, y));
                        if let Some(d) = nearest_distance(binary, x, y, degree) {
                            spacing.0 += d;
                            spacing.1 += 1;
                        }
                        x += 1;
                    }
                    runs.push(Run {
                        y: y as u32,
                        x0: start as u32,
                        x1: x as u32,
                    });
                }
                (runs, spacing, loose)
            },
        )
        .collect();
    let mut spacing_sum = (0.0f64, 0u64);
    let mut loose = 0;
    for (_, spacing, row_loose) in &rows {
        spacing_sum = (spacing_sum.0 + spacing.0, spacing_sum.1 + spacing.1);
        loose += row_loose;
    }
    let spacing = if spacing_sum.1 == 0 {
        1.0
    } else {
        spacing_sum.0 / spacing_sum.1 as f64
    };
    let runs: Vec<Run> = rows.into_iter().flat_map(|(runs, _, _)| runs).collect();
    // Tiny holes (as `mask::tiny_hole_pixels` counts them): each is counted from its first pixel
    // in raster order, which ends a run of ink.
    let holes = || {
        runs.par_iter()
            .filter(|r| r.y > 0 && (r.y as usize) + 1 < height && (r.x1 as usize) + 1 < width)
            .filter_map(|r| {
                tiny_hole_in_stroke(ink, width, height, r.y as usize * width + r.x1 as usize)
            })
            .sum()
    };
    let dropout = dropout.unwrap_or_else(|| dropout_mode(params, count, loose, spacing, holes));
    Ok(Survey {
        runs,
        spacing,
        dropout,
    })
}

/// The pixels a point set is built from: a row-major mask whose pixel `(0, 0)` is the image's
/// pixel `(x0, y0)` (the whole image, or the bounding box of one chunk of components holding only
/// that chunk's ink).
pub(super) struct Window<'a> {
    pub(super) ink: &'a [bool],
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) x0: usize,
    pub(super) y0: usize,
}

/// The point-set builder of a whole image (chunks of a large one use [`build_from_runs`], which
/// gives the same from the runs of ink, and only outside dropout mode): the ink
/// pixels of `window` as points in raster order, its pixel index, the neighbour lists (the
/// 8-neighbourhood, 5x5 in dropout mode) and the half-widths from the exact distance transform of
/// the window (pixels beyond it are background: they are not this window's ink), with the page's
/// `spacing` and `dropout`. A chunk's window holds whole components, so every distance to the
/// background and every neighbour list is the one the whole image gives its pixels.
pub(super) fn build(window: &Window, spacing: f64, dropout: bool) -> Result<PointSet> {
    let (ink, width, height) = (window.ink, window.width, window.height);
    let (x0, y0) = (window.x0, window.y0);
    let row_starts = ink_row_starts(ink, width, height);
    let count = row_starts[height];

    // Points, the pixel -> point index and the 8-neighbour degrees (at `degrees[i + 1]`, the
    // layout of the CSR offsets), row by row.
    let mut points = vec![[0.0f64; 2]; count];
    let mut index = vec![Grid::NONE; width * height];
    let mut degrees = vec![0u32; count + 1];
    if width > 0 {
        index
            .par_chunks_mut(width)
            .zip(split_by(&mut points, &row_starts).into_par_iter())
            .zip(split_by(&mut degrees[1..], &row_starts).into_par_iter())
            .enumerate()
            .for_each(|(y, ((index_row, points_row), degree_row))| {
                let mut id = row_starts[y];
                let mut k = 0;
                for (x, slot) in index_row.iter_mut().enumerate() {
                    if ink[y * width + x] {
                        *slot = id as u32;
                        points_row[k] = [(x0 + x) as f64 + 0.5, (y0 + y) as f64 + 0.5];
                        let mut degree = 0;
                        for_each_in_window(ink, width, height, 1, x, y, |other| {
                            degree += u32::from(other)
                        });
                        degree_row[k] = degree;
                        id += 1;
                        k += 1;
                    }
                }
            });
    }
    let grid = Grid {
        width: width as u32,
        height: height as u32,
        index,
        x0: x0 as i64,
        y0: y0 as i64,
    };

    // Half-width = distance to the nearest background pixel center. In dropout mode the gaps
    // punched into a stroke would make it look thin, so the transform runs on the 3x3 closing.
    let mut half_width = vec![0f32; count];
    let to_half_width = |d2: u64| (d2 as f64).sqrt() as f32;
    if dropout && count > 0 {
        let closed = close3(ink, width, height);
        let closed_starts = ink_row_starts(&closed, width, height);
        let closed = Mask {
            ink: &closed,
            width,
            height,
            row_starts: &closed_starts,
        };
        let original = Mask {
            ink,
            width,
            height,
            row_starts: &row_starts,
        };
        squared_distance_at(&closed, &original, &mut half_width, to_half_width);
    } else {
        squared_distance_rows(
            ink,
            width,
            height,
            &row_starts,
            &mut half_width,
            to_half_width,
        );
    }

    let reach = if dropout { 2 } else { 1 };
    let (offsets, neighbors) = neighbour_csr(ink, &grid, &row_starts, reach, degrees)?;

    Ok(PointSet {
        points,
        half_width,
        offsets,
        neighbors,
        spacing,
        dropout,
        grid: Some(grid),
    })
}

/// [`build`] outside dropout mode from the window's runs of ink instead of its mask: `runs` in
/// raster order, each a maximal run of ink of its row (as the survey finds them), in image
/// coordinates, inside the window of `width` x `height` pixels at `(x0, y0)`. Only the pixel index
/// is the window's size (filled run by run); every other pass visits the ink pixels alone, which
/// matters for a chunk, whose window holds many times its ink on a page of text. The same points,
/// index, neighbour lists and half-widths as [`build`] on the window's mask (tested below): the
/// neighbours are read from the index in the same raster order, and the distance transform's
/// column pass counts each pixel's ink above and below it through the index, its row pass runs
/// over the same runs.
///
/// Without `neighbours` the points have no neighbour lists (every list empty: a valid point set
/// of isolated points), for a chunk the skeleton alone traces, which reads the points, their
/// pixel index and half-widths but no neighbour list (the method's stages, which walk them, do
/// not run there).
pub(super) fn build_from_runs(
    runs: &[Run],
    (x0, y0): (usize, usize),
    (width, height): (usize, usize),
    spacing: f64,
    neighbours: bool,
) -> Result<PointSet> {
    let count: usize = runs.iter().map(Run::len).sum();
    let origin = (x0 as i64, y0 as i64);
    let local = |run: &Run| window_run(run, origin);
    let mut points = Vec::with_capacity(count);
    push_pixel_centres(&mut points, runs);
    let index = index_of_runs(runs, origin, (width, height));

    let (offsets, neighbors) = if neighbours {
        eight_neighbours_of_runs(&index, (width, height), count, runs.iter().map(local))?
    } else {
        (vec![0u32; count + 1], Vec::new())
    };

    // Half-width = distance to the nearest background pixel center (`squared_distance_rows`):
    // the column pass as the length of each pixel's column of ink down to it and up to it
    // (virtual background beyond the window), through the index in raster order and back.
    let mut down = vec![0u32; count];
    let mut k = 0;
    for run in runs {
        let (y, a, b) = local(run);
        for x in a..b {
            down[k] = match y.checked_sub(1).map(|v| index[v * width + x]) {
                Some(above) if above != Grid::NONE => down[above as usize] + 1,
                _ => 1,
            };
            k += 1;
        }
    }
    let mut up = vec![0u32; count];
    for run in runs.iter().rev() {
        let (y, a, b) = local(run);
        for x in (a..b).rev() {
            k -= 1;
            let below = (y + 1 < height).then(|| index[(y + 1) * width + x]);
            up[k] = match below {
                Some(below) if below != Grid::NONE => up[below as usize] + 1,
                _ => 1,
            };
        }
    }
    for (g, &u) in down.iter_mut().zip(&up) {
        *g = (*g).min(u);
    }
    drop(up);
    let mut half_width = vec![0f32; count];
    let mut envelope = RunEnvelope::with_capacity(width);
    let mut k = 0;
    for run in runs {
        let len = run.len();
        let d2 = envelope.squared_distances(&down[k..k + len]);
        for (out, &d2) in half_width[k..k + len].iter_mut().zip(d2) {
            *out = (d2 as f64).sqrt() as f32;
        }
        k += len;
    }

    Ok(PointSet {
        points,
        half_width,
        offsets,
        neighbors,
        spacing,
        dropout: false,
        grid: Some(window_grid(index, (width, height), origin)),
    })
}

/// A run in the coordinates of a window whose first pixel is image column `x0` and row `y0`:
/// its row, first and end column.
fn window_run(run: &Run, (x0, y0): (i64, i64)) -> (usize, usize, usize) {
    (
        (i64::from(run.y) - y0) as usize,
        (i64::from(run.x0) - x0) as usize,
        (i64::from(run.x1) - x0) as usize,
    )
}

/// Appends the pixel centres of `runs`, run after run (image coordinates). One exact-size
/// extension per run: a flattened iterator's extension checks the capacity for every point.
fn push_pixel_centres(points: &mut Vec<[f64; 2]>, runs: &[Run]) {
    for run in runs {
        let row = run.y as f64 + 0.5;
        points.extend((run.x0..run.x1).map(|x| [x as f64 + 0.5, row]));
    }
}

/// The pixel index of a `width` x `height` window whose first pixel is image pixel `origin`
/// holding the pixels of `runs` (in it, raster order), numbered in that order.
fn index_of_runs(runs: &[Run], origin: (i64, i64), (width, height): (usize, usize)) -> Vec<u32> {
    let mut index = Grid::blank_index(width * height);
    let mut first = 0u32;
    for run in runs {
        let (y, a, b) = window_run(run, origin);
        for (slot, id) in index[y * width + a..y * width + b].iter_mut().zip(first..) {
            *slot = id;
        }
        first += run.x1 - run.x0;
    }
    index
}

/// The [`Grid`] of a `width` x `height` window whose first pixel is image pixel `(x0, y0)`.
fn window_grid(index: Vec<u32>, (width, height): (usize, usize), (x0, y0): (i64, i64)) -> Grid {
    Grid {
        width: width as u32,
        height: height as u32,
        index,
        x0,
        y0,
    }
}

/// The 8-neighbour lists in CSR form of the `count` ink pixels `pixels` (window coordinates, in
/// point order) of a window whose pixel index is `index`: each list in raster order of the
/// neighbours (so sorted by point index). The reference of [`eight_neighbours_of_runs`].
#[cfg(test)]
fn eight_neighbours(
    index: &[u32],
    (width, height): (usize, usize),
    count: usize,
    pixels: impl Iterator<Item = (usize, usize)>,
) -> Result<(Vec<u32>, Vec<u32>)> {
    let mut offsets = Vec::with_capacity(count + 1);
    offsets.push(0u32);
    let mut neighbors = Vec::new();
    for (x, y) in pixels {
        for_each_in_window(index, width, height, 1, x, y, |j| {
            if j != Grid::NONE {
                neighbors.push(j);
            }
        });
        close_list(&mut offsets, &neighbors)?;
    }
    neighbors.shrink_to_fit();
    Ok((offsets, neighbors))
}

/// The first ink pixel of `row` at or after `from` (`row.len()` when there is none). The
/// background between runs (most of a page) is skipped eight pixels to a word.
pub(super) fn next_ink(row: &[bool], from: usize) -> usize {
    let Some(rest) = row.get(from..) else {
        return row.len();
    };
    let mut words = rest.chunks_exact(8);
    let mut x = from;
    for word in &mut words {
        let bytes: [u8; 8] = std::array::from_fn(|i| u8::from(word[i]));
        let bits = u64::from_le_bytes(bytes);
        if bits != 0 {
            // The lowest byte set is the first ink pixel (little-endian order).
            return x + bits.trailing_zeros() as usize / 8;
        }
        x += 8;
    }
    words
        .remainder()
        .iter()
        .position(|&on| on)
        .map_or(row.len(), |k| x + k)
}

/// Ends a pixel's list in the CSR arrays, which index with u32 (`PointSet`): an error past that.
fn close_list(offsets: &mut Vec<u32>, neighbors: &[u32]) -> Result<()> {
    if neighbors.len() > u32::MAX as usize {
        return Err(Error::Limit {
            what: "neighbour pairs",
            actual: neighbors.len() as u64,
            limit: u32::MAX as u64,
            field: "limits.max_points",
        });
    }
    offsets.push(neighbors.len() as u32);
    Ok(())
}

/// [`eight_neighbours`] of the pixels of `runs` (window coordinates: row, first and end column,
/// in point order), each list read from the index in the same raster order, without the
/// per-pixel window bounds and the closure: a pixel's eight cells are gathered into a small
/// buffer (a cell without ink is written and not counted) and appended at once. The rows above
/// and below are read only where they exist, the columns beside only inside the window, as
/// [`for_each_in_window`] clips them. The same lists, bit for bit (tested below).
fn eight_neighbours_of_runs(
    index: &[u32],
    (width, height): (usize, usize),
    count: usize,
    runs: impl Iterator<Item = (usize, usize, usize)>,
) -> Result<(Vec<u32>, Vec<u32>)> {
    let mut offsets = Vec::with_capacity(count + 1);
    offsets.push(0u32);
    // Room for every pixel's eight cells: the lists are appended without ever moving what was
    // appended before (growing by doubling copied them about once over), and the room not
    // used is given back below (`shrink_to_fit`), never having been touched.
    let mut neighbors: Vec<u32> = Vec::with_capacity(8 * count);
    let mut cells = [0u32; 8];
    for (y, a, b) in runs {
        let row = &index[y * width..(y + 1) * width];
        let above = y.checked_sub(1).map(|v| &index[v * width..(v + 1) * width]);
        let below = (y + 1 < height).then(|| &index[(y + 1) * width..(y + 2) * width]);
        for x in a..b {
            let mut n = 0;
            let mut take = |cell: u32| {
                cells[n] = cell;
                n += usize::from(cell != Grid::NONE);
            };
            if x > 0 && x + 1 < width {
                // Inside the window's columns: three cells above and below, one on each side.
                let three = |line: &[u32]| -> [u32; 3] { [line[x - 1], line[x], line[x + 1]] };
                if let Some(above) = above {
                    three(above).into_iter().for_each(&mut take);
                }
                take(row[x - 1]);
                take(row[x + 1]);
                if let Some(below) = below {
                    three(below).into_iter().for_each(&mut take);
                }
            } else {
                let (u0, u1) = (x.saturating_sub(1), (x + 1).min(width - 1));
                if let Some(above) = above {
                    above[u0..=u1].iter().for_each(|&cell| take(cell));
                }
                if x > 0 {
                    take(row[x - 1]);
                }
                if x + 1 < width {
                    take(row[x + 1]);
                }
                if let Some(below) = below {
                    below[u0..=u1].iter().for_each(|&cell| take(cell));
                }
            }
            // All eight cells appended, then the list cut to its `n` neighbours: a copy of a
            // fixed size, without the call a copy of `n` cells makes.
            let end = neighbors.len() + n;
            neighbors.extend_from_slice(&cells);
            neighbors.truncate(end);
            close_list(&mut offsets, &neighbors)?;
        }
    }
    neighbors.shrink_to_fit();
    Ok((offsets, neighbors))
}

/// What [`set_aside`] keeps of a waiting point set's pixels: their runs, in point order (each
/// about a sixth of the memory of its points on a page of text).
#[derive(Debug, Default)]
pub(crate) struct Aside {
    runs: Vec<Run>,
}

/// Frees what a point set can rebuild while it waits between stages (a chunk between its
/// refinement and its fit, ARCHITECTURE.md, "Large inputs"): the pixel index, and for pixels
/// outside dropout mode the points themselves (kept as their runs) and the 8-neighbour lists,
/// which are read off the index. All chunks wait at once: this is most of their memory.
/// [`restore`] makes them again, the same.
pub(crate) fn set_aside(points: &mut PointSet) -> Aside {
    let Some(grid) = &mut points.grid else {
        return Aside::default();
    };
    // Pixel centers in raster order (`PointSet::validate`), so the runs give them back exactly;
    // anything else keeps its points.
    let runs = (!points.dropout)
        .then(|| pixel_runs(points.points.iter()))
        .flatten();
    let Some(runs) = runs else {
        grid.release(&points.points);
        return Aside::default();
    };
    // The index is set back to `Grid::NONE` a run at a time rather than a point at a time;
    // released with no point left to clear, it becomes the thread's spare all the same.
    clear_runs(grid, &runs);
    grid.release(&[]);
    points.points = Vec::new();
    points.offsets = Vec::new();
    points.neighbors = Vec::new();
    Aside { runs }
}

/// Sets the entries of `runs`' pixels (image coordinates, inside the window) in `grid`'s index
/// back to [`Grid::NONE`], as [`Grid::release`] does for their points.
fn clear_runs(grid: &mut Grid, runs: &[Run]) {
    let origin = (grid.x0, grid.y0);
    let width = grid.width as usize;
    for run in runs {
        let (y, a, b) = window_run(run, origin);
        if let Some(cells) = grid.index.get_mut(y * width + a..y * width + b) {
            cells.fill(Grid::NONE);
        }
    }
}

/// The runs of `centers`, pixel centres in raster order (image coordinates), each run the
/// centres of consecutive pixels of a row; `None` where a centre is not a pixel's.
fn pixel_runs<'a>(centers: impl Iterator<Item = &'a [f64; 2]>) -> Option<Vec<Run>> {
    let mut runs: Vec<Run> = Vec::new();
    // The centre that would continue the last run: most centres are that one, and the compare
    // with it (a whole pixel's centre, exact in f64) spares their conversions below.
    let mut next = [f64::NAN; 2];
    for p in centers {
        if *p == next {
            // (A run ending at `u32::MAX` is refused below, as its next pixel is.)
            if let Some(run) = runs.last_mut().filter(|run| run.x1 < u32::MAX) {
                run.x1 += 1;
                next[0] += 1.0;
                continue;
            }
        }
        let (x, y) = (p[0] - 0.5, p[1] - 0.5);
        if !(x >= 0.0 && y >= 0.0 && x < u32::MAX as f64 && y < u32::MAX as f64) {
            return None;
        }
        // Whole numbers (`fract() == 0`, without its library call): in that range, those that
        // truncation leaves as they are.
        let (whole_x, whole_y) = (x as u32, y as u32);
        if f64::from(whole_x) != x || f64::from(whole_y) != y {
            return None;
        }
        let (x, y) = (whole_x, whole_y);
        match runs.last_mut() {
            Some(run) if run.y == y && run.x1 == x => run.x1 += 1,
            _ => runs.push(Run {
                y,
                x0: x,
                x1: x + 1,
            }),
        }
        next = [f64::from(x) + 1.5, p[1]];
    }
    Some(runs)
}

/// The 8-neighbour lists of a pixel point set outside dropout mode built without them
/// ([`build_from_runs`] without `neighbours`), read from its pixel index as [`build_from_runs`]
/// reads them: for a chunk whose method (§3.1-§3.4) turns out to trace all of it. Nothing
/// changes where the points are not pixel centres in raster order or their grid is gone.
pub(crate) fn add_neighbours(points: &mut PointSet) {
    let Some(grid) = &points.grid else {
        return;
    };
    if points.dropout || grid.index.is_empty() {
        return;
    }
    if let Some(runs) = pixel_runs(points.points.iter()) {
        read_neighbours(points, &runs);
    }
}

/// The 8-neighbour lists of `points`, whose pixels are `runs`, read from their grid's pixel
/// index; nothing changes without a grid or where the lists would not fit `u32`.
fn read_neighbours(points: &mut PointSet, runs: &[Run]) {
    let Some(grid) = &points.grid else {
        return;
    };
    let origin = (grid.x0, grid.y0);
    let size = (grid.width as usize, grid.height as usize);
    let pixels = runs.iter().map(|run| window_run(run, origin));
    let lists = eight_neighbours_of_runs(&grid.index, size, points.len(), pixels);
    if let Ok((offsets, neighbors)) = lists {
        points.offsets = offsets;
        points.neighbors = neighbors;
    }
}

/// The points `keep` marks of a pixel point set outside dropout mode (pixel centres in raster
/// order, its neighbour lists the 8-neighbours [`build_from_runs`] reads, or none) as a point
/// set of their own: [`PointSet::kept`]'s, bit for bit (tested below), without reading
/// `points`' neighbour lists: the part's pixel index over the bounding box of its pixels is
/// filled run by run and its 8-neighbour lists read from it, which are the whole set's lists
/// with the points left out dropped (every kept neighbour lies in the part's box, in the same
/// raster order). The whole set's pixel index should be released first ([`Grid::release`]):
/// the part's reuses it. `None` where the points are not pixel centres in raster order.
pub(crate) fn kept_pixels(points: &PointSet, keep: &[bool]) -> Option<PointSet> {
    if points.dropout || keep.len() != points.len() {
        return None;
    }
    let members = || (0..points.len()).filter(|&p| keep[p]);
    let runs = pixel_runs(members().map(|p| &points.points[p]))?;
    let (Some(first), Some(last)) = (runs.first(), runs.last()) else {
        return Some(points.kept(keep));
    };
    let (y0, y1) = (first.y as usize, last.y as usize + 1);
    let x0 = runs.iter().map(|r| r.x0).min().unwrap_or(0) as usize;
    let x1 = runs.iter().map(|r| r.x1).max().unwrap_or(0) as usize;
    let size = (x1 - x0, y1 - y0);
    let origin = (x0 as i64, y0 as i64);
    let index = index_of_runs(&runs, origin, size);
    let count = runs.iter().map(Run::len).sum();
    let pixels = runs.iter().map(|run| window_run(run, origin));
    let (offsets, neighbors) = eight_neighbours_of_runs(&index, size, count, pixels).ok()?;
    // The kept points are the centres of the runs' pixels, bit for bit (`pixel_runs` took only
    // whole pixel centres): made from the runs, and both vectors sized once.
    let mut kept_points = Vec::with_capacity(count);
    push_pixel_centres(&mut kept_points, &runs);
    let mut half_width = Vec::with_capacity(count);
    half_width.extend(
        points
            .half_width
            .iter()
            .zip(keep)
            .filter_map(|(&h, &k)| k.then_some(h)),
    );
    Some(PointSet {
        points: kept_points,
        half_width,
        offsets,
        neighbors,
        spacing: points.spacing,
        dropout: false,
        grid: Some(window_grid(index, size, origin)),
    })
}

/// Rebuilds what [`set_aside`] freed: the points and the pixel index from their runs, then the
/// 8-neighbour lists from the index in the order [`build_from_runs`] makes them.
pub(crate) fn restore(points: &mut PointSet, aside: Aside) {
    let Aside { runs } = aside;
    if !runs.is_empty() {
        points.points = Vec::with_capacity(points.half_width.len());
        push_pixel_centres(&mut points.points, &runs);
    }
    let Some(grid) = &mut points.grid else {
        return;
    };
    // The points' pixels, as `Grid::rebuild` places them.
    if runs.is_empty() {
        grid.rebuild(&points.points);
    } else {
        let size = (grid.width as usize, grid.height as usize);
        grid.index = index_of_runs(&runs, (grid.x0, grid.y0), size);
    }
    if points.dropout || points.offsets.len() == points.len() + 1 {
        return;
    }
    // `set_aside` frees the lists only of pixels it keeps as runs. The lists were this long
    // before (the `u32` limit was checked when they were first made).
    debug_assert!(!runs.is_empty() || points.is_empty());
    read_neighbours(points, &runs);
}

/// Refuses more ink pixels than `params.front_end.limits.max_points` (or than `u32` point indices
/// can number, `Grid::NONE` reserved) before anything is allocated per point.
pub(super) fn check_point_count(count: usize, params: &Params) -> Result<()> {
    if count as u64 > params.front_end.limits.max_points || count as u64 >= u32::MAX as u64 {
        return Err(Error::Limit {
            what: "foreground points",
            actual: count as u64,
            limit: params.front_end.limits.max_points,
            field: "limits.max_points",
        });
    }
    Ok(())
}

/// Whether dropout mode is on for `count` ink pixels of which `loose` have exactly one ink
/// 8-neighbour, with `Dis_ave` = `spacing`; `holes` counts the tiny-hole pixels and is only called
/// when the other tests do not already decide.
fn dropout_mode(
    params: &Params,
    count: usize,
    loose: usize,
    spacing: f64,
    holes: impl FnOnce() -> usize,
) -> bool {
    // Heavy dropout (over half the pixels of a stroke gone) opens the holes to the outside, so
    // they are no longer tiny; what remains is pixels hanging on by a single neighbour, which
    // solid strokes of any width have only at 1-px line ends. Adaptation 2: sparse points.
    let loose = loose as f64;
    (loose > LOOSE_FRACTION * count as f64 && loose >= 16.0)
        || spacing > DROPOUT_SPACING
        // Adaptation 2: tiny holes above a share of the ink (1.5% by default; 0.5% misfired
        // on script, whose loops leave tiny holes).
        || holes() as f64 > params.front_end.dropout_fraction * count as f64
}

/// Whether the ink pixel `(x, y)`, which has a single ink 8-neighbour, ends a line one pixel
/// wide: the chain of pixels from it runs [`LINE_END_RUN`] pixels without branching or ending (a
/// staircase's two pixels side by side are one step). A drawing of 1-px lines (thin line art, an
/// already thinned mask) has a loose pixel at every line end; dropout's are specks, short
/// fragments and spikes on a stroke, whose chains end or branch at once.
pub(super) fn ends_a_line(mask: MaskView<'_>, x: usize, y: usize) -> bool {
    let mut seen = [(0i64, 0i64); 2 * LINE_END_RUN + 1];
    seen[0] = (x as i64, y as i64);
    let (mut len, mut current) = (1, seen[0]);
    for _ in 0..LINE_END_RUN {
        let mut next = [(0i64, 0i64); 8];
        let mut count = 0;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let p = (current.0 + dx, current.1 + dy);
                if (dx, dy) != (0, 0) && mask.get(p.0, p.1) && !seen[..len].contains(&p) {
                    next[count] = p;
                    count += 1;
                }
            }
        }
        let step = match count {
            1 => next[0],
            // A staircase: two side by side, the step goes on from the diagonal one.
            2 if (next[0].0 - next[1].0).abs() + (next[0].1 - next[1].1).abs() == 1 => {
                let diagonal = |p: (i64, i64)| p.0 != current.0 && p.1 != current.1;
                let (a, b) = if diagonal(next[0]) {
                    (next[1], next[0])
                } else {
                    (next[0], next[1])
                };
                seen[len] = a;
                len += 1;
                b
            }
            _ => return false,
        };
        seen[len] = step;
        len += 1;
        current = step;
    }
    true
}

/// The neighbour graph in CSR form: the ink pixels within Chebyshev distance `reach` (1: the
/// 8-neighbourhood; 2: the 5x5 neighbourhood of dropout mode), sorted by point index (the window
/// is scanned in raster order). Two passes over the rows (degrees, then lists) so nothing is
/// allocated per point.
fn neighbour_csr(
    ink: &[bool],
    grid: &Grid,
    row_starts: &[usize],
    reach: usize,
    degrees_8: Vec<u32>,
) -> Result<(Vec<u32>, Vec<u32>)> {
    let (width, height) = (grid.width as usize, grid.height as usize);
    let index = &grid.index[..];

    // Pass 1: the degree of point i goes to offsets[i + 1], row by row (counted on the mask,
    // which is a quarter the size of the index); then prefix sums. The 8-neighbour degrees are
    // already known.
    let mut offsets = degrees_8;
    if reach != 1 {
        split_by(&mut offsets[1..], row_starts)
            .into_par_iter()
            .enumerate()
            .for_each(|(y, row)| {
                let mut k = 0;
                for (x, &on) in ink[y * width..(y + 1) * width].iter().enumerate() {
                    if on {
                        let mut degree = 0;
                        for_each_in_window(ink, width, height, reach, x, y, |other| {
                            degree += u32::from(other)
                        });
                        row[k] = degree;
                        k += 1;
                    }
                }
            });
    }
    let mut total = 0u64;
    for slot in offsets.iter_mut() {
        total += *slot as u64;
        // The CSR arrays index with u32 (`PointSet`): 24 neighbours of 178 million points.
        if total > u32::MAX as u64 {
            return Err(Error::Limit {
                what: "neighbour pairs",
                actual: total,
                limit: u32::MAX as u64,
                field: "limits.max_points",
            });
        }
        *slot = total as u32;
    }

    // Pass 2: the lists, each row into its own slice of `neighbors`.
    let mut neighbors = vec![0u32; total as usize];
    let neighbor_starts: Vec<usize> = row_starts.iter().map(|&s| offsets[s] as usize).collect();
    split_by(&mut neighbors, &neighbor_starts)
        .into_par_iter()
        .enumerate()
        .for_each(|(y, row)| {
            let mut k = 0;
            for (x, &on) in ink[y * width..(y + 1) * width].iter().enumerate() {
                if on {
                    for_each_in_window(index, width, height, reach, x, y, |j| {
                        if j != Grid::NONE {
                            row[k] = j;
                            k += 1;
                        }
                    });
                }
            }
        });
    Ok((offsets, neighbors))
}

/// Calls `visit` with the cells within Chebyshev distance `reach` of `(x, y)`, the center
/// excluded, in raster order.
#[inline(always)]
fn for_each_in_window<T: Copy>(
    cells: &[T],
    width: usize,
    height: usize,
    reach: usize,
    x: usize,
    y: usize,
    mut visit: impl FnMut(T),
) {
    let (u0, u1) = (x.saturating_sub(reach), (x + reach).min(width - 1));
    for v in y.saturating_sub(reach)..=(y + reach).min(height - 1) {
        let row = &cells[v * width + u0..=v * width + u1];
        for (u, &cell) in (u0..).zip(row) {
            if u != x || v != y {
                visit(cell);
            }
        }
    }
}

/// The contribution of ink pixel `(x, y)` to `Dis_ave` (mean distance to the nearest other ink
/// pixel). Pixels touching another ink pixel (8-neighbourhood) count one grid step, 1: they are
/// adjacent samples of the pixel grid, and counting √2 for diagonal contacts would call every thin
/// diagonal line sparse. Other pixels count their true Euclidean nearest distance, searched up to
/// [`SPACING_SEARCH`]; with nothing that close they are left out (`None`). `degree_8` is the
/// number of ink pixels touching `(x, y)`.
fn nearest_distance(mask: MaskView<'_>, x: usize, y: usize, degree_8: u32) -> Option<f64> {
    if degree_8 > 0 {
        return Some(1.0);
    }
    isolated_distance(&|u, v| mask.get(u, v), x as i64, y as i64)
}

/// Nearest ink pixel to an isolated one, by growing square rings until no closer one can exist.
fn isolated_distance(at: &impl Fn(i64, i64) -> bool, x: i64, y: i64) -> Option<f64> {
    let mut best = i64::MAX;
    for r in 2..=SPACING_SEARCH {
        if r * r >= best {
            break;
        }
        for d in -r..=r {
            for (dx, dy) in [(d, -r), (d, r), (-r, d), (r, d)] {
                if at(x + dx, y + dy) {
                    best = best.min(dx * dx + dy * dy);
                }
            }
        }
    }
    (best != i64::MAX).then(|| (best as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binary::Binary;
    use crate::raster::points;

    fn mask(rows: &[&str]) -> Binary {
        let mut binary = Binary::new(rows[0].len() as u32, rows.len() as u32);
        for (y, row) in rows.iter().enumerate() {
            for (x, c) in row.bytes().enumerate() {
                binary.set(x as i64, y as i64, c == b'#');
            }
        }
        binary
    }

    fn horizontal_bar(width: u32, height: u32, y0: u32, thickness: u32) -> Binary {
        let mut binary = Binary::new(width, height);
        for y in y0..y0 + thickness {
            for x in 2..width - 2 {
                binary.set(x as i64, y as i64, true);
            }
        }
        binary
    }

    /// The word-at-a-time skip finds the ink pixel the pixel-by-pixel walk finds, from every
    /// start, on rows of every length up to 40 with ink from none to all.
    #[test]
    fn next_ink_matches_the_walk() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for case in 0..3000 {
            let len = case % 41;
            let fill = (case / 41) % 11;
            let row: Vec<bool> = (0..len)
                .map(|_| {
                    state = state
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1_442_695_040_888_963_407);
                    (state >> 33) % 10 < fill as u64
                })
                .collect();
            for from in 0..=len + 1 {
                let walked = (from..len).find(|&x| row[x]).unwrap_or(len);
                assert_eq!(next_ink(&row, from), walked, "{row:?} from {from}");
            }
        }
    }

    /// Pseudo-random drop of ink pixels.
    fn drop_pixels(binary: &mut Binary, share: f64, seed: u64) {
        let mut state = seed;
        for pixel in binary.ink.iter_mut() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            if *pixel && ((state >> 33) as f64 / (1u64 << 31) as f64) < share {
                *pixel = false;
            }
        }
    }

    #[test]
    fn points_in_raster_order_with_grid() {
        let binary = mask(&[".#.", "##.", "..#"]);
        let set = points(&binary, &Params::default()).unwrap();
        assert_eq!(
            set.points,
            vec![[1.5, 0.5], [0.5, 1.5], [1.5, 1.5], [2.5, 2.5]]
        );
        let grid = set.grid.as_ref().unwrap();
        assert_eq!(grid.point_at(2, 2), Some(3));
        assert_eq!(grid.point_at(0, 0), None);
        set.validate().unwrap();
        assert_eq!(set.neighbors_of(2), &[0, 1, 3]);
        assert_eq!(set.neighbors_of(3), &[2]);
        assert_eq!(set.spacing, 1.0);
        assert!(!set.dropout);
    }

    #[test]
    fn half_width_on_3_and_5_pixel_lines() {
        for (thickness, center) in [(1u32, 1.0f32), (3, 2.0), (5, 3.0)] {
            let binary = horizontal_bar(40, 15, 5, thickness);
            let set = points(&binary, &Params::default()).unwrap();
            let grid = set.grid.as_ref().unwrap();
            let mid = grid.point_at(20, (5 + thickness / 2) as i64).unwrap();
            assert_eq!(
                set.half_width[mid as usize], center,
                "thickness {thickness}"
            );
            let edge = grid.point_at(20, 5).unwrap();
            assert_eq!(set.half_width[edge as usize], 1.0);
        }
    }

    #[test]
    fn dropout_detection_on_and_off() {
        let clean = horizontal_bar(200, 30, 10, 9);
        let set = points(&clean, &Params::default()).unwrap();
        assert!(!set.dropout);
        let mut broken = clean.clone();
        drop_pixels(&mut broken, 0.4, 7);
        let set = points(&broken, &Params::default()).unwrap();
        assert!(set.dropout);
        set.validate().unwrap();
        // 5x5 neighbourhood: an interior point sees up to 24 neighbours.
        let most = (0..set.len() as u32)
            .map(|i| set.neighbors_of(i).len())
            .max()
            .unwrap();
        assert!(most > 8 && most <= 24);
        // The closing restores the bar's width for the distance transform: center ~ 5.
        let grid = set.grid.as_ref().unwrap();
        let center: Vec<f32> = (50..150)
            .filter_map(|x| grid.point_at(x, 14))
            .map(|i| set.half_width[i as usize])
            .collect();
        let mean = center.iter().sum::<f32>() / center.len() as f32;
        assert!(mean > 4.0, "{mean}");
        // Forced off.
        let mut params = Params::default();
        params.front_end.dropout = Some(false);
        let set = points(&broken, &params).unwrap();
        assert!(!set.dropout);
        assert!(set.neighbors.len() <= 8 * set.len());
        // A few pinholes stay under the 1.5% share.
        let mut speckled = clean.clone();
        speckled.set(50, 14, false);
        speckled.set(120, 12, false);
        assert!(!points(&speckled, &Params::default()).unwrap().dropout);
    }

    #[test]
    fn line_ends_are_not_loose_pixels() {
        let end = |rows: &[&str], x: usize, y: usize| ends_a_line(mask(rows).view(), x, y);
        // The end of a straight line and of a staircase, each running on for 3 px and more.
        assert!(end(&["......", ".####.", "......"], 1, 1));
        assert!(end(&["#.....", ".##...", "...##.", "....#."], 0, 0));
        // A fragment of three pixels, a spike on a bar, a 2-px arm of a T: not line ends.
        assert!(!end(&["......", ".###..", "......"], 1, 1));
        assert!(!end(&["#.....", ".####.", ".####."], 0, 0));
        assert!(!end(&["..#...", "..#...", "#####."], 2, 0));
        // Short 1-px lines keep the plain neighbourhood; the same lines cut into 2-px pieces
        // switch dropout mode on.
        let mut lines = Binary::new(60, 60);
        let mut dashes = Binary::new(60, 60);
        for k in 0..12 {
            for t in 5..12 {
                lines.set(5 + 4 * k, t, true);
                lines.set(5 + 4 * k, t + 20, true);
                lines.set(5 + 4 * k, t + 40, true);
                if t % 3 != 2 {
                    dashes.set(5 + 4 * k, t, true);
                    dashes.set(5 + 4 * k, t + 20, true);
                    dashes.set(5 + 4 * k, t + 40, true);
                }
            }
        }
        assert!(!points(&lines, &Params::default()).unwrap().dropout);
        assert!(points(&dashes, &Params::default()).unwrap().dropout);
    }

    #[test]
    fn spacing_counts_isolated_points() {
        // Two pixels 3 apart horizontally: each has nearest distance 3.
        let binary = mask(&["........", ".#..#...", "........"]);
        let set = points(&binary, &Params::default()).unwrap();
        assert!((set.spacing - 3.0).abs() < 1e-12);
        assert!(set.dropout, "sparse points switch dropout mode on");
        assert!(
            set.neighbors_of(0).is_empty(),
            "3 px apart is outside the 5x5 window"
        );
        // A lone pixel has no neighbour: spacing falls back to 1.
        let lone = mask(&["...", ".#.", "..."]);
        let set = points(&lone, &params_forced_off()).unwrap();
        assert_eq!(set.spacing, 1.0);
        assert_eq!(set.offsets, vec![0, 0]);
    }

    fn params_forced_off() -> Params {
        let mut params = Params::default();
        params.front_end.dropout = Some(false);
        params
    }

    #[test]
    fn limits_and_empty_masks() {
        let binary = horizontal_bar(20, 10, 3, 2);
        let mut params = Params::default();
        params.front_end.limits.max_points = 10;
        match points(&binary, &params) {
            Err(Error::Limit { field, actual, .. }) => {
                assert_eq!(field, "limits.max_points");
                assert_eq!(actual, 32);
            }
            other => panic!("expected a limit error, got {other:?}"),
        }
        let empty = Binary::new(30, 20);
        let set = points(&empty, &Params::default()).unwrap();
        assert!(set.is_empty());
        assert_eq!(set.offsets, vec![0]);
        set.validate().unwrap();
        let nothing = Binary::new(0, 0);
        assert!(points(&nothing, &Params::default()).unwrap().is_empty());
    }

    #[test]
    fn output_does_not_depend_on_the_thread_count() {
        let mut binary = horizontal_bar(300, 200, 20, 150);
        drop_pixels(&mut binary, 0.3, 11);
        for dropout in [None, Some(true), Some(false)] {
            let mut params = Params::default();
            params.front_end.dropout = dropout;
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                pool.install(|| points(&binary, &params).unwrap())
            };
            let (one, three) = (run(1), run(3));
            assert_eq!(one.points, three.points);
            assert_eq!(one.half_width, three.half_width);
            assert_eq!(one.offsets, three.offsets);
            assert_eq!(one.neighbors, three.neighbors);
            assert_eq!(one.spacing.to_bits(), three.spacing.to_bits());
            assert_eq!(one.dropout, three.dropout);
        }
    }

    #[test]
    fn the_build_from_runs_equals_the_build_from_the_mask() {
        // Thin and thick bars, solid and with holes punched in, pixels on the image's edges.
        for (thickness, share, seed) in [(1, 0.0, 1), (9, 0.0, 2), (30, 0.05, 3), (38, 0.4, 4)] {
            let mut binary = horizontal_bar(61, 40, 1, thickness);
            drop_pixels(&mut binary, share, seed);
            for y in 0..40 {
                binary.set(0, y, y % 3 != 1);
            }
            let survey = survey(binary.view(), &params_forced_off(), Some(false)).unwrap();
            let window = Window {
                ink: &binary.ink,
                width: 61,
                height: 40,
                x0: 0,
                y0: 0,
            };
            let want = build(&window, survey.spacing, false).unwrap();
            let got =
                build_from_runs(&survey.runs, (0, 0), (61, 40), survey.spacing, true).unwrap();
            got.validate().unwrap();
            assert!(!got.is_empty());
            assert_eq!(got.points, want.points, "thickness {thickness}");
            assert_eq!(got.offsets, want.offsets);
            assert_eq!(got.neighbors, want.neighbors);
            assert_eq!(got.half_width, want.half_width);
            let (g, e) = (got.grid.unwrap(), want.grid.unwrap());
            assert_eq!(
                (g.width, g.height, g.x0, g.y0),
                (e.width, e.height, e.x0, e.y0)
            );
            assert_eq!(g.index, e.index);
            // Without neighbour lists: the same points, half-widths and index, every list
            // empty, still a valid point set.
            let bare =
                build_from_runs(&survey.runs, (0, 0), (61, 40), survey.spacing, false).unwrap();
            bare.validate().unwrap();
            assert_eq!(bare.points, want.points);
            assert_eq!(bare.half_width, want.half_width);
            assert_eq!(bare.grid.unwrap().index, g.index);
            assert!(bare.neighbors.is_empty());
            assert_eq!(bare.offsets, vec![0; bare.points.len() + 1]);
        }
    }

    /// A waiting chunk frees its index and (outside dropout mode) its points and neighbour lists;
    /// all come back the same, in a window offset from the image's corner.
    #[test]
    fn set_aside_and_restored_is_the_same_point_set() {
        let mut binary = horizontal_bar(45, 30, 3, 11);
        drop_pixels(&mut binary, 0.2, 7);
        for dropout in [false, true] {
            let mut params = Params::default();
            params.front_end.dropout = Some(dropout);
            let whole = points(&binary, &params).unwrap();
            let survey = survey(binary.view(), &params_forced_off(), Some(false)).unwrap();
            let built =
                build_from_runs(&survey.runs, (0, 2), (45, 26), survey.spacing, true).unwrap();
            for want in [whole, built] {
                let mut got = want.clone();
                let aside = set_aside(&mut got);
                assert!(got.grid.as_ref().unwrap().index.is_empty());
                assert_eq!(got.neighbors.is_empty(), !got.dropout);
                assert_eq!(got.points.is_empty(), !got.dropout);
                restore(&mut got, aside);
                got.validate().unwrap();
                assert_eq!(got.points, want.points);
                assert_eq!(got.offsets, want.offsets);
                assert_eq!(got.neighbors, want.neighbors);
                assert_eq!(got.grid.unwrap().index, want.grid.unwrap().index);
            }
        }
    }

    /// A part cut from a chunk built without neighbour lists is the part [`PointSet::kept`]
    /// cuts from the chunk built with them, and the lists added later are the built ones: on
    /// random windows and random parts, the whole index released first as the pipeline does.
    #[test]
    fn kept_pixels_are_the_kept_points_and_added_lists_the_built_ones() {
        let mut rng = crate::test_rng::XorShift::new(0x9e37_79b9_7f4a_7c15);
        let mut next = move || rng.next_u64();
        for round in 0..200 {
            let (w, h) = (1 + next() % 40, 1 + next() % 30);
            let mut binary = Binary::new(w as u32, h as u32);
            let fill = next() % 10;
            for pixel in binary.ink.iter_mut() {
                *pixel = next() % 10 < fill;
            }
            let survey = survey(binary.view(), &params_forced_off(), Some(false)).unwrap();
            if survey.runs.is_empty() {
                continue;
            }
            let (x0, y0) = (survey.runs.iter().map(|r| r.x0).min().unwrap() as usize, 0);
            let x1 = survey.runs.iter().map(|r| r.x1).max().unwrap() as usize;
            let window = (x1 - x0, h as usize);
            let with = build_from_runs(&survey.runs, (x0, y0), window, 1.0, true).unwrap();
            let mut without = build_from_runs(&survey.runs, (x0, y0), window, 1.0, false).unwrap();
            let share = next() % 11;
            let keep: Vec<bool> = (0..with.len()).map(|_| next() % 10 < share).collect();
            let want = with.kept(&keep);
            let mut released = without.clone();
            released
                .grid
                .as_mut()
                .unwrap()
                .release(&without.points.clone());
            let got = kept_pixels(&released, &keep).unwrap();
            got.validate().unwrap();
            assert_eq!(got.points, want.points, "{round}");
            assert_eq!(got.half_width, want.half_width, "{round}");
            assert_eq!(got.offsets, want.offsets, "{round}");
            assert_eq!(got.neighbors, want.neighbors, "{round}");
            // No grid where nothing is kept.
            let window = |g: &Option<Grid>| {
                g.as_ref()
                    .map(|g| (g.x0, g.y0, g.width, g.height, g.index.clone()))
            };
            assert_eq!(window(&got.grid), window(&want.grid), "{round}");
            add_neighbours(&mut without);
            assert_eq!(without.offsets, with.offsets, "{round}");
            assert_eq!(without.neighbors, with.neighbors, "{round}");
        }
    }

    /// The maximal runs of ink of a `width` x `height` mask, in raster order, as (row, first
    /// column, end column).
    fn runs_of(ink: &[bool], width: usize, height: usize) -> Vec<(usize, usize, usize)> {
        let mut runs = Vec::new();
        for y in 0..height {
            let mut x = 0;
            while x < width {
                if ink[y * width + x] {
                    let a = x;
                    while x < width && ink[y * width + x] {
                        x += 1;
                    }
                    runs.push((y, a, x));
                } else {
                    x += 1;
                }
            }
        }
        runs
    }

    /// The lists read run by run equal the per-pixel window's on 300 random windows: one row or
    /// column, ink on every edge, sparse to full.
    #[test]
    fn neighbours_of_runs_equal_the_window_scan() {
        let mut rand = crate::synth::lcg(2026);
        for case in 0..300 {
            let width = 1 + (rand() >> 33) as usize % 40;
            let height = 1 + (rand() >> 33) as usize % 30;
            let density = match case % 4 {
                0 => 0.1,
                1 => 0.5,
                2 => 0.9,
                _ => 1.0,
            };
            let ink: Vec<bool> = (0..width * height)
                .map(|_| ((rand() >> 33) as f64 / (1u64 << 31) as f64) < density)
                .collect();
            let mut index = vec![Grid::NONE; width * height];
            let mut count = 0u32;
            for (slot, _) in index.iter_mut().zip(&ink).filter(|(_, &on)| on) {
                *slot = count;
                count += 1;
            }
            let runs = runs_of(&ink, width, height);
            let pixels = runs
                .iter()
                .flat_map(|&(y, a, b)| (a..b).map(move |x| (x, y)));
            let size = (width, height);
            let want = eight_neighbours(&index, size, count as usize, pixels).unwrap();
            let got = eight_neighbours_of_runs(&index, size, count as usize, runs.iter().copied())
                .unwrap();
            assert_eq!(got, want, "case {case}: {width} x {height}");
        }
    }

    /// Restored from runs, random chunk-like windows (offset from the image's corner, ink on
    /// their edges) give back the points, index and lists their build made.
    #[test]
    fn restored_from_runs_on_random_windows() {
        let mut rand = crate::synth::lcg(77);
        for case in 0..60 {
            let (width, height) = (
                2 + (rand() >> 33) as usize % 50,
                2 + (rand() >> 33) as usize % 40,
            );
            let mut binary = Binary::new(width as u32, height as u32);
            for pixel in binary.ink.iter_mut() {
                *pixel = (rand() >> 33) % 3 != 0;
            }
            let survey = survey(binary.view(), &params_forced_off(), Some(false)).unwrap();
            let (x0, y0) = ((case % 5) * 7, (case % 3) * 11);
            let shifted: Vec<Run> = survey
                .runs
                .iter()
                .map(|r| Run {
                    y: r.y + y0 as u32,
                    x0: r.x0 + x0 as u32,
                    x1: r.x1 + x0 as u32,
                })
                .collect();
            let want =
                build_from_runs(&shifted, (x0, y0), (width, height), survey.spacing, true).unwrap();
            // The build from the window's mask, which reads no runs, agrees.
            let window = Window {
                ink: &binary.ink,
                width,
                height,
                x0,
                y0,
            };
            let from_mask = build(&window, survey.spacing, false).unwrap();
            assert_eq!(want.points, from_mask.points, "case {case}");
            assert_eq!(want.offsets, from_mask.offsets);
            assert_eq!(want.neighbors, from_mask.neighbors);
            let mut got = want.clone();
            let aside = set_aside(&mut got);
            restore(&mut got, aside);
            got.validate().unwrap();
            assert_eq!(got.points, want.points, "case {case}");
            assert_eq!(got.offsets, want.offsets);
            assert_eq!(got.neighbors, want.neighbors);
            assert_eq!(got.grid.unwrap().index, want.grid.unwrap().index);
        }
    }

    #[test]
    fn neighbours_match_brute_force() {
        let mut binary = horizontal_bar(30, 12, 2, 7);
        drop_pixels(&mut binary, 0.3, 3);
        for dropout in [false, true] {
            let mut params = Params::default();
            params.front_end.dropout = Some(dropout);
            let set = points(&binary, &params).unwrap();
            set.validate().unwrap();
            let reach = if dropout { 2.0 } else { 1.0 };
            for i in 0..set.len() {
                let expected: Vec<u32> = (0..set.len() as u32)
                    .filter(|&j| {
                        let (p, q) = (set.points[i], set.points[j as usize]);
                        j as usize != i
                            && (p[0] - q[0]).abs() <= reach
                            && (p[1] - q[1]).abs() <= reach
                    })
                    .collect();
                assert_eq!(set.neighbors_of(i as u32), &expected[..]);
            }
        }
    }
}
