//! Whole pages (docs/design.md, "Whole pages"): the ink pixels of a large image as chunks of whole
//! components, each chunk's point set built by the thread that traces it.
//!
//! Building the page's point set first and cutting it into chunks afterwards made one pass over a
//! `u32` index of every pixel, neighbour lists and a distance transform of the whole page, all on
//! one thread, and then copied every chunk out of it. Here one parallel pass over the mask finds the
//! runs of ink in each row and the page-wide figures (`Dis_ave`, the dropout test), a union-find
//! over the runs finds the 8-connected components, and each chunk's points, pixel index, neighbour
//! lists and half-widths come from its own window of the mask. The point sets are the ones
//! [`crate::PointSet::split_components`] cuts from the whole page's, bit for bit (tested below), so
//! the traces are identical too.

use rayon::prelude::*;

use super::points::{check_point_count, dropout_mode, for_each_in_window, nearest_distance};
use crate::csr::Csr;
use crate::mask::{ink_row_starts, run_components, tiny_hole, Run, RunEnvelope};
use crate::{Binary, Grid, Params, PointSet, Result};

/// The ink of an image as chunks of whole 8-connected components, in the order of each
/// component's first pixel, each chunk about `target` points or one component.
pub(crate) struct PixelChunks {
    /// `Dis_ave` of the whole image.
    spacing: f64,
    /// The runs of every chunk, one chunk after the other, in raster order within a chunk.
    runs: Vec<Run>,
    /// Chunk `c` holds `runs[offsets[c]..offsets[c + 1]]`.
    offsets: Vec<usize>,
}

/// Splits the ink of `binary` into chunks of whole components of about `target` points, or returns
/// `None` when the image is better traced as one point set: at most `target` ink pixels, or
/// dropout mode (whose 5x5 neighbourhoods and closed distance transform reach across component
/// gaps).
pub(crate) fn pixel_chunks(
    binary: &Binary,
    params: &Params,
    target: usize,
) -> Result<Option<PixelChunks>> {
    let (width, height) = (binary.width as usize, binary.height as usize);
    let ink = &binary.ink[..];
    if width == 0 || height == 0 || ink.len() != width * height {
        return Ok(None);
    }
    let row_starts = ink_row_starts(ink, width, height);
    let count = row_starts[height];
    check_point_count(count, params)?;
    if count <= target {
        return Ok(None);
    }

    // One pass over the rows: the runs, the `Dis_ave` terms and the loose pixels, exactly as
    // `points` finds them (the spacing sums in the same order, so `Dis_ave` is the same number).
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
                while x < width {
                    if !row[x] {
                        x += 1;
                        continue;
                    }
                    let start = x;
                    while x < width && row[x] {
                        let degree = u32::from(column[x] + column[x + 1] + column[x + 2]) - 1;
                        loose += usize::from(degree == 1);
                        if let Some(d) = nearest_distance(ink, width, height, x, y, degree) {
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
            .filter_map(|r| tiny_hole(ink, width, height, r.y as usize * width + r.x1 as usize))
            .sum()
    };
    if dropout_mode(params, count, loose, spacing, holes) {
        return Ok(None);
    }

    // 8-connected components, numbered in order of their first pixel, as
    // `PointSet::component_chunks` numbers them.
    let (label, sizes) = run_components(&runs);

    // Consecutive components fill a chunk up to `target` points (as `component_chunks` does).
    let mut chunk_of = Vec::with_capacity(sizes.len());
    let mut chunks = 0u32;
    let mut filled = 0usize;
    for &size in &sizes {
        if filled > 0 && filled + size > target {
            filled = 0;
        }
        if filled == 0 {
            chunks += 1;
        }
        chunk_of.push(chunks - 1);
        filled += size;
    }
    // The runs grouped by chunk, keeping raster order within each (a stable counting sort).
    let grouped = Csr::build(chunks as usize, |sink| {
        for (run, &l) in runs.iter().zip(&label) {
            sink.push(chunk_of[l as usize] as usize, *run);
        }
    });
    Ok(Some(PixelChunks {
        spacing,
        runs: grouped.values,
        offsets: grouped.offsets,
    }))
}

impl PixelChunks {
    /// Number of chunks.
    pub(crate) fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of points in chunk `c`.
    pub(crate) fn size(&self, c: usize) -> usize {
        self.runs[self.offsets[c]..self.offsets[c + 1]]
            .iter()
            .map(Run::len)
            .sum()
    }

    /// The point set of chunk `c`: its pixels in raster order, the 8-neighbour lists, the
    /// half-widths and the pixel index of its bounding box.
    pub(crate) fn part(&self, c: usize) -> PointSet {
        let runs = &self.runs[self.offsets[c]..self.offsets[c + 1]];
        let (y0, y1) = (runs[0].y as usize, runs[runs.len() - 1].y as usize + 1);
        let x0 = runs.iter().map(|r| r.x0).min().unwrap_or(0) as usize;
        let x1 = runs.iter().map(|r| r.x1).max().unwrap_or(0) as usize;
        let (w, h) = (x1 - x0, y1 - y0);
        let n: usize = runs.iter().map(Run::len).sum();

        let mut points = Vec::with_capacity(n);
        let mut index = vec![Grid::NONE; w * h];
        for run in runs {
            let row = (run.y as usize - y0) * w;
            for x in run.x0 as usize..run.x1 as usize {
                index[row + x - x0] = points.len() as u32;
                points.push([x as f64 + 0.5, run.y as f64 + 0.5]);
            }
        }
        // Neighbours in raster order of the window, so sorted by point index.
        let mut offsets = Vec::with_capacity(n + 1);
        let mut neighbors = Vec::with_capacity(8 * n);
        offsets.push(0);
        for run in runs {
            for x in run.x0 as usize..run.x1 as usize {
                for_each_in_window(&index, w, h, 1, x - x0, run.y as usize - y0, |j| {
                    if j != Grid::NONE {
                        neighbors.push(j);
                    }
                });
                offsets.push(neighbors.len() as u32);
            }
        }

        // Half-widths: the exact distance transform of the whole image, evaluated at this
        // chunk's pixels from its own runs. The ink right above, below, left or right of one of
        // its pixels touches it, so it belongs to the same component: the vertical distances to
        // the background (the column pass) come from the chunk's own index, and each run is a
        // whole run of the image's row, independent of the rest of the row (the row pass).
        let mut up = vec![0u32; n];
        for run in runs {
            let row = (run.y as usize - y0) * w;
            for x in run.x0 as usize - x0..run.x1 as usize - x0 {
                let p = index[row + x] as usize;
                up[p] = match row.checked_sub(w).map(|above| index[above + x]) {
                    Some(q) if q != Grid::NONE => up[q as usize] + 1,
                    _ => 1,
                };
            }
        }
        let mut g = up;
        let mut down = vec![0u32; n];
        for run in runs.iter().rev() {
            let row = (run.y as usize - y0) * w;
            for x in (run.x0 as usize - x0..run.x1 as usize - x0).rev() {
                let p = index[row + x] as usize;
                let below = row + w + x;
                down[p] = match index.get(below) {
                    Some(&q) if q != Grid::NONE => down[q as usize] + 1,
                    _ => 1,
                };
                g[p] = g[p].min(down[p]);
            }
        }
        let mut half_width = vec![0f32; n];
        let mut envelope = RunEnvelope::with_capacity(w);
        let mut first = 0;
        for run in runs {
            let span = first..first + run.len();
            let d2 = envelope.squared_distances(&g[span.clone()]);
            for (out, &d2) in half_width[span].iter_mut().zip(d2) {
                *out = (d2 as f64).sqrt() as f32;
            }
            first += run.len();
        }

        PointSet {
            points,
            half_width,
            offsets,
            neighbors,
            spacing: self.spacing,
            dropout: false,
            grid: Some(Grid {
                width: w as u32,
                height: h as u32,
                index,
                x0: x0 as i64,
                y0: y0 as i64,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::points;

    /// A page of blobs, rings, touching and nearly touching strokes and a frame, with pixels on
    /// every image edge.
    fn page() -> Binary {
        let (w, h) = (97u32, 83u32);
        let mut binary = Binary::new(w, h);
        let mut seed = 12345u64;
        let mut rand = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as u32
        };
        for _ in 0..40 {
            let (cx, cy, r) = (rand() % w, rand() % h, 1 + rand() % 6);
            let hollow = rand() % 3 == 0;
            for y in cy.saturating_sub(r)..(cy + r + 1).min(h) {
                for x in cx.saturating_sub(r)..(cx + r + 1).min(w) {
                    let d2 = (x as i64 - cx as i64).pow(2) + (y as i64 - cy as i64).pow(2);
                    let r2 = (r * r) as i64;
                    if d2 <= r2 && !(hollow && d2 < r2 / 3) {
                        binary.set(x as i64, y as i64, true);
                    }
                }
            }
        }
        for x in 0..w {
            binary.set(x as i64, 0, true);
        }
        for y in 0..h {
            binary.set(w as i64 - 1, y as i64, true);
        }
        // Diagonal neighbours only: one component.
        for k in 0..6 {
            binary.set(10 + k, 70 + k, true);
        }
        binary
    }

    #[test]
    fn chunks_are_the_point_sets_cut_from_the_whole_page() {
        let binary = page();
        let params = Params {
            dropout: Some(false),
            ..Params::default()
        };
        let whole = points(&binary, &params).expect("points");
        for target in [1, 50, 300, 1000] {
            let chunks = pixel_chunks(&binary, &params, target)
                .expect("chunks")
                .expect("more ink than the target");
            let expected = whole.split_components(target);
            assert_eq!(chunks.len(), expected.len(), "target {target}");
            for (c, want) in expected.iter().enumerate() {
                let got = chunks.part(c);
                assert_eq!(got.points, want.points, "target {target} chunk {c}");
                assert_eq!(got.offsets, want.offsets);
                assert_eq!(got.neighbors, want.neighbors);
                assert_eq!(got.half_width, want.half_width);
                assert_eq!(got.spacing.to_bits(), want.spacing.to_bits());
                let (g, e) = (got.grid.expect("grid"), want.grid.as_ref().expect("grid"));
                assert_eq!(
                    (g.x0, g.y0, g.width, g.height),
                    (e.x0, e.y0, e.width, e.height)
                );
                assert_eq!(&g.index, &e.index);
            }
        }
    }

    #[test]
    fn small_images_and_dropout_stay_whole() {
        let binary = page();
        let params = Params::default();
        let ink = binary.ink.iter().filter(|&&b| b).count();
        assert!(pixel_chunks(&binary, &params, ink).expect("ok").is_none());
        let forced = Params {
            dropout: Some(true),
            ..Params::default()
        };
        assert!(pixel_chunks(&binary, &forced, 10).expect("ok").is_none());
    }

    #[test]
    fn pinholes_switch_dropout_on_as_for_the_whole_page() {
        // Bars punched with single-pixel holes (3% of the ink) in every other row.
        let mut binary = Binary::new(60, 40);
        for y in 2..38 {
            for x in 2..58 {
                let hole = y % 2 == 0 && x % 16 == (y / 2) % 16 && x > 2 && x < 57;
                binary.set(x, y, !hole);
            }
        }
        let params = Params::default();
        assert!(points(&binary, &params).expect("points").dropout);
        assert!(pixel_chunks(&binary, &params, 10).expect("ok").is_none());
        // Without the holes the bars are traced in chunks.
        let mut solid = Binary::new(60, 40);
        for y in 2..38 {
            for x in 2..58 {
                solid.set(x, y, true);
            }
        }
        assert!(!points(&solid, &params).expect("points").dropout);
        assert!(pixel_chunks(&solid, &params, 10).expect("ok").is_some());
    }

    #[test]
    fn too_many_points_are_refused() {
        let binary = page();
        let mut params = Params::default();
        params.limits.max_points = 10;
        assert!(pixel_chunks(&binary, &params, 5).is_err());
    }
}
