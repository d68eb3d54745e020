//! Whole pages (docs/design.md, "Whole pages"): the ink pixels of a large image as chunks of whole
//! components, each chunk's point set built by the thread that traces it.
//!
//! Building the page's point set first and cutting it into chunks afterwards made one pass over a
//! `u32` index of every pixel, neighbour lists and a distance transform of the whole page, all on
//! one thread, and then copied every chunk out of it. Here one parallel pass over the mask finds the
//! runs of ink in each row and the page-wide figures (`Dis_ave`, the dropout test), a union-find
//! over the runs finds the 8-connected components, and each chunk's points, pixel index, neighbour
//! lists and half-widths come from its own runs ([`build_from_runs`]: only the pixel index is the
//! size of the chunk's window, which holds many times its ink on a page of text). The survey is
//! the one the whole image uses and the builder gives what the whole image's gives (`points.rs`),
//! so the point sets are the ones [`crate::PointSet::split_components`] cuts from the whole page's,
//! bit for bit (tested below), and the traces are identical too.

use super::points::{build_from_runs, check_point_count, survey_counted, Survey};
use crate::binary::MaskView;
use crate::csr::Csr;
use crate::error::Result;
use crate::mask::{ink_total, run_components, Run};
use crate::params::Params;
use crate::point_set::{Components, PointSet};

/// The ink of an image as chunks of whole 8-connected components, in the order of each
/// component's first pixel, each chunk about `target` points or one component.
pub(crate) struct PixelChunks {
    /// `Dis_ave` of the whole image.
    spacing: f64,
    /// The runs of every chunk, one chunk after the other, in raster order within a chunk.
    runs: Vec<Run>,
    /// The page-wide component of each run (numbered in order of first pixel).
    labels: Vec<u32>,
    /// Chunk `c` holds `runs[offsets[c]..offsets[c + 1]]`.
    offsets: Vec<usize>,
}

/// Splits the ink of `binary` into chunks of whole components of about `target` points, or returns
/// `None` when the image is better traced as one point set: at most `target` ink pixels, or
/// dropout mode (whose 5x5 neighbourhoods and closed distance transform reach across component
/// gaps). Dropout mode is `dropout` when given, else decided as [`super::points`] decides it.
pub(crate) fn pixel_chunks(
    binary: MaskView<'_>,
    params: &Params,
    dropout: Option<bool>,
    target: usize,
) -> Result<Option<PixelChunks>> {
    if binary.width == 0 || binary.height == 0 || binary.check_size().is_err() {
        return Ok(None);
    }
    // The ink is counted (and refused beyond the limits) before the survey allocates anything.
    let width = binary.width as usize;
    let count = ink_total(binary.ink, width);
    if count <= target {
        check_point_count(count, params)?;
        return Ok(None);
    }
    // The runs, `Dis_ave` and the dropout test, exactly as `points` finds them.
    let Survey {
        runs,
        spacing,
        dropout,
    } = survey_counted(binary, params, dropout, count)?;
    if dropout {
        return Ok(None);
    }

    // 8-connected components, numbered in order of their first pixel, as
    // `PointSet::chunks_of` numbers them.
    let (label, sizes) = run_components(&runs);

    // Consecutive components fill a chunk up to `target` points (as `PointSet::chunks_of` does).
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
            sink.push(chunk_of[l as usize] as usize, (*run, l));
        }
    });
    let (runs, labels) = grouped.values.into_iter().unzip();
    Ok(Some(PixelChunks {
        spacing,
        runs,
        labels,
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

    /// The point set of chunk `c`: [`build_from_runs`] over the bounding box of its runs, holding
    /// only its own ink; and its [`PointSet::component_labels`], read off the page's components
    /// (a chunk holds consecutive components of the page, numbered in the same order of first
    /// pixel, so its labels are the page's less its first). Without `neighbours` the points have
    /// no neighbour lists (for the skeleton alone: [`build_from_runs`]).
    pub(crate) fn part(&self, c: usize, neighbours: bool) -> Result<(PointSet, Components)> {
        let range = self.offsets[c]..self.offsets[c + 1];
        let runs = &self.runs[range.clone()];
        let (Some(first), Some(last)) = (runs.first(), runs.last()) else {
            return Ok((PointSet::default(), (Vec::new(), Vec::new())));
        };
        let labels = &self.labels[range];
        let base = labels.iter().copied().min().unwrap_or(0);
        let mut sizes: Vec<usize> = Vec::new();
        let mut point_labels = Vec::with_capacity(self.size(c));
        for (run, &l) in runs.iter().zip(labels) {
            let local = (l - base) as usize;
            if sizes.len() <= local {
                sizes.resize(local + 1, 0);
            }
            sizes[local] += run.len();
            point_labels.extend(std::iter::repeat_n(local as u32, run.len()));
        }
        let (y0, y1) = (first.y as usize, last.y as usize + 1);
        let x0 = runs.iter().map(|r| r.x0).min().unwrap_or(0) as usize;
        let x1 = runs.iter().map(|r| r.x1).max().unwrap_or(0) as usize;
        // The chunk's runs are the page's, each a maximal run of its row, and no run of another
        // chunk touches them: they are the maximal runs of the window holding this chunk's ink.
        let points = build_from_runs(runs, (x0, y0), (x1 - x0, y1 - y0), self.spacing, neighbours)?;
        Ok((points, (point_labels, sizes)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binary::Binary;
    use crate::raster::points;

    /// A page of blobs, rings, touching and nearly touching strokes and a frame, with pixels on
    /// every image edge.
    fn page() -> Binary {
        let (w, h) = (97u32, 83u32);
        let mut binary = Binary::new(w, h);
        let mut lcg = crate::synth::lcg(12345u64);
        let mut rand = move || (lcg() >> 33) as u32;
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
        let mut params = Params::default();
        params.front_end.dropout = Some(false);
        let whole = points(&binary, &params).expect("points");
        for target in [1, 50, 300, 1000] {
            let chunks = pixel_chunks(binary.view(), &params, params.front_end.dropout, target)
                .expect("chunks")
                .expect("more ink than the target");
            let expected = whole.split_components(target);
            assert_eq!(chunks.len(), expected.len(), "target {target}");
            for (c, want) in expected.iter().enumerate() {
                let (got, components) = chunks.part(c, true).expect("part");
                assert_eq!(
                    components,
                    want.component_labels(),
                    "target {target} chunk {c}"
                );
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
        assert!(
            pixel_chunks(binary.view(), &params, params.front_end.dropout, ink)
                .expect("ok")
                .is_none()
        );
        let mut forced = Params::default();
        forced.front_end.dropout = Some(true);
        assert!(
            pixel_chunks(binary.view(), &forced, forced.front_end.dropout, 10)
                .expect("ok")
                .is_none()
        );
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
        assert!(
            pixel_chunks(binary.view(), &params, params.front_end.dropout, 10)
                .expect("ok")
                .is_none()
        );
        // Without the holes the bars are traced in chunks.
        let mut solid = Binary::new(60, 40);
        for y in 2..38 {
            for x in 2..58 {
                solid.set(x, y, true);
            }
        }
        assert!(!points(&solid, &params).expect("points").dropout);
        assert!(
            pixel_chunks(solid.view(), &params, params.front_end.dropout, 10)
                .expect("ok")
                .is_some()
        );
    }

    #[test]
    fn too_many_points_are_refused() {
        let binary = page();
        let mut params = Params::default();
        params.front_end.limits.max_points = 10;
        assert!(pixel_chunks(binary.view(), &params, params.front_end.dropout, 5).is_err());
    }
}
