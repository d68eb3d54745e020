//! Regions of a page that are not strokes (docs/design.md, "The front end"): halftone photos,
//! frames and page edges, found from the ink's own evidence in units of the page's stroke width
//! `w` (the most common chord of the ink), and left out of the trace unless kept.
//!
//! The idea is Leptonica's halftone mask (`pixGenHalftoneMask`: a seed of what is solid at a
//! coarse scale, opened so that no text survives, filled into what is connected to it), made
//! stricter for a stroke tool: the coarse scale is a cell of [`CELL_WIDTHS`] `w`, and a cell is
//!
//! - **solid** when most of it is thick ink, at least [`THICK_WIDTHS`] `w` across both ways (no
//!   stroke of the page is that wide; a dark photo, a scanner's frame and the dark beyond a page's
//!   edge are);
//! - **dark field** when most of it is on the ink side of the global level while the threshold
//!   left almost no ink in it (a dark margin beyond the paper that the local threshold read as a
//!   ground of its own);
//! - **dense** when it holds ink but no open paper, no paper pixel farther than `w` from ink
//!   (halftone dots and textures; text leaves paper between its lines);
//! - **texture** when its gray, seen at half a stroke width, holds many pieces or many holes
//!   ([`TEXTURE_PIECES`]): a halftone's dots, a grille's lattice, whatever the threshold made of
//!   them.
//!
//! When no block of cells could seed (a cheap look at each cell's ink and dark shares and its
//! texture, [`seed_possible`], the texture looked at first in every third row of cells only),
//! nothing more is done: a page of text pays for one pass.
//!
//! A region grows from seeds of [`SEED_CELLS`] x [`SEED_CELLS`] solid, dark-field or texture cells (the
//! opening: a rule, a table's grid or a bold letter is never that wide), or of [`SEED_CELLS`] such
//! cells in a row along the image's edge (a frame), through the solid, dark-field and dotted cells
//! (dense ones where at least [`MIN_DOTS`] pieces of ink begin: a halftone's screen) connected to
//! them and the dense cells beside those. Dotted cells do not seed: a fingerprint's broken ridges
//! are dotted too. A region touching the
//! image's edge is a `frame` when it is a ring of bands around the image and a `page_edge` otherwise; one inside
//! the page, or one of texture cells at least half, is a `halftone`; a halftone's box grows by a
//! row or column of cells while half the side's cells beyond it hold pieces of ink that also lie
//! within it or are specks, each no larger than `w^2` (the photo's light rim, whose specks and
//! open paper kept those cells out, see [`grow_box`]). Its ink is removed; so are the pieces of ink left wholly within a
//! cell of it (a photo's last dots, the line a local threshold draws along a dark margin), while a
//! stroke that touches it and leaves it, such as a letter touching a frame, stays.
//!
//! Then the rings of lines around the page ([`rings`]): a printed border, the edges of a bound
//! book's pages, one hollow piece around the text, with what runs along it and lies beyond it, and
//! the specks in its band outward of the text.
//!
//! Last, the faint ink ([`faint`]): pieces that barely reach the text's contrast, left out when
//! they are most of the ink (a local threshold that read the paper's grain as ink).

use crate::decisions::{Ground, Region};
use crate::gray::GrayView;
use crate::mask::{label_components, Connectivity};
use crate::median::upper_median_by;
use crate::params::RegionKind;
use rayon::prelude::*;

/// A cell's side, in stroke widths: about a letter's height, less than a line of text.
const CELL_WIDTHS: f64 = 4.0;
/// The narrowest cell, px.
const MIN_CELL: usize = 8;
/// Ink at least this many stroke widths across in both directions is thick.
const THICK_WIDTHS: f64 = 3.0;
/// A cell at least this share thick ink is solid.
const SOLID_SHARE: f64 = 0.5;
/// A cell at least this share on the ink side of the global level is dark ...
const DARK_SHARE: f64 = 0.5;
/// ... and a dark field when the threshold left less than this share of it ink.
const DARK_FIELD_INK: f64 = 0.1;
/// A cell with less than this share of open paper and at least [`DENSE_INK`] ink is dense.
const OPEN_PAPER: f64 = 0.02;
/// See [`OPEN_PAPER`].
const DENSE_INK: f64 = 0.02;
/// A dark field ends in a step when the gray falls across its border by at least this share of
/// its fall from the paper.
const STEP_SHARE: f64 = 0.5;
/// A dense cell where at least this many pieces of ink (8-connected) begin is a halftone's screen
/// of dots, which carries a region on (a letter or two begin in a cell of text).
const MIN_DOTS: u32 = 4;
/// A dotted cell is at least this share ink: a screen's dots cover a tenth of it and more where
/// there is any tone, scattered specks on paper much less.
const DOTS_INK: f64 = 0.1;
/// A cell is a texture (a halftone's dots, a grille's bars, a pattern's cells) when its gray,
/// seen at half a stroke width (block means) and cut at two levels either side of the global one,
/// shows at least this many pieces (or at least this many holes) in both cuts: one per eight
/// squared stroke widths, where a cell of text shows less than one (a letter, a counter) and
/// a fingerprint's pores, finer than half a ridge, are gone at that scale.
const TEXTURE_PIECES: f64 = 2.0;
/// A seed is this many cells square, all solid or dark field: three cells, twelve stroke widths.
const SEED_CELLS: usize = 3;
/// A region along the image's edge is a frame when it spans at least this share of the image's
/// width and of its height ...
const FRAME_SPAN: f64 = 0.5;
/// ... and covers at most this share of its own box (a ring of bands, not a field).
const FRAME_FILL: f64 = 0.5;

/// Ink is faint when it never reaches this share of the page's text contrast within a stroke
/// width ([`faint`]): a threshold halfway between paper and ink leaves none of the text's ink
/// lighter than half its contrast.
const FAINT_SHARE: f64 = 0.5;
/// A piece of ink is faint when less than this share of its pixels reach [`FAINT_SHARE`] of the
/// text's contrast: a stroke's core is most of it, a texture's darkest grains are few.
const FAINT_CORE: f64 = 0.05;
/// Faint pieces are left out only when they are at least this share of the ink.
const FAINT_INK: f64 = 0.5;
/// The page's text contrast is the darkness this share of the ink stays under: the strokes'
/// cores even where a texture is most of the ink.
const TEXT_QUANTILE: f64 = 0.99;

/// A piece of ink is a ring around the page ([`rings`]) when at least this share of its pixels
/// lie within [`RING_BAND`] of its box's border: a frame of lines, where a table's grid or a
/// drawing spreads its ink over the inside as well.
const RING_SHARE: f64 = 0.9;
/// See [`RING_SHARE`]: the band's width as a share of the box's shorter side.
const RING_BAND: f64 = 0.125;
/// A ring is looked for only where some row holds a run of ink at least this share of the
/// image's width (the long side of a frame of lines, unbroken for half its length): a page of
/// text has none and is spared the labelling.
const RING_RUN: f64 = 0.25;

/// A piece of ink smaller than this many squared stroke widths is a speck, smaller than any
/// letter (a stroke three widths long): a dot, a comma, the dirt along a page's edge.
const SPECK_AREA: f64 = 3.0;

/// A group at least this share texture cells is a halftone (a photo or a pattern), wherever it
/// lies.
const TEXTURED_GROUP: f64 = 0.5;

/// A region along the image's edge that is not a frame is a page edge when at least this share
/// of its cells are even dark: dark field, or at least [`PAGE_EDGE_INK`] ink (see [`find`]).
const PAGE_EDGE_EVEN: f64 = 0.5;
/// See [`PAGE_EDGE_EVEN`]: a cell this share ink shows no paper between strokes.
const PAGE_EDGE_INK: f64 = 0.95;

/// Pixels per task of the parallel passes over the page.
const PIXELS_PER_TASK: usize = 1 << 16;

/// The Euler number's share of a 2 x 2 window of blocks (Gray's bit quads, see
/// [`texture_cells`]) whose blocks are `a`, `b` (top left, top right), `c`, `d` (bottom left,
/// bottom right), each 0 or 1: `+1` for one block set, `-1` for three, `-2` for a diagonal pair
/// (two set, `a` and `d` alike), else 0. Arithmetic rather than a table, so that a row of
/// windows is summed in vector lanes.
#[inline]
fn quad_euler(a: u8, b: u8, c: u8, d: u8) -> i32 {
    let n = i32::from(a + b + c + d);
    (n & 1) * (2 - n) - 2 * i32::from(n == 2 && a == d)
}

/// Four times the Euler number of each cell's windows ([`quad_euler`]), rows of cells in
/// parallel: `padded` holds rows of `bw + 2` blocks, window `(x, y)` is blocks `(x, y)` to
/// `(x + 1, y + 1)` for `x` in `0..=bw` and `y` in `0..cell_row.len()`, counted in cell `(cell_col[x],
/// cell_row[y])` of `cols` x `rows` cells (both rising with their window's position); the rows
/// of cells not `wanted` are left 0.
fn euler_quads(
    padded: &[u8],
    bw: usize,
    cell_col: &[usize],
    cell_row: &[usize],
    (cols, rows): (usize, usize),
    wanted: &(dyn Fn(usize) -> bool + Sync),
) -> Vec<i32> {
    let pw = bw + 2;
    // The windows of cell column c: col_starts[c]..col_starts[c + 1].
    let col_starts: Vec<usize> = (0..=cols)
        .map(|c| cell_col.partition_point(|&k| k < c))
        .collect();
    let mut quads = vec![0i32; cols * rows];
    quads
        .par_chunks_mut(cols)
        .enumerate()
        .for_each(|(cy, quads)| {
            if !wanted(cy) {
                return;
            }
            let ys = cell_row.partition_point(|&c| c < cy)..cell_row.partition_point(|&c| c <= cy);
            for y in ys {
                let (top, bottom) = (
                    &padded[y * pw..(y + 1) * pw],
                    &padded[(y + 1) * pw..(y + 2) * pw],
                );
                for (quad, xs) in quads.iter_mut().zip(col_starts.windows(2)) {
                    let (a, b) = (&top[xs[0]..xs[1]], &top[xs[0] + 1..xs[1] + 1]);
                    let (c, d) = (&bottom[xs[0]..xs[1]], &bottom[xs[0] + 1..xs[1] + 1]);
                    *quad += a
                        .iter()
                        .zip(b)
                        .zip(c)
                        .zip(d)
                        .map(|(((&a, &b), &c), &d)| quad_euler(a, b, c, d))
                        .sum::<i32>();
                }
            }
        });
    quads
}

/// Two sums per pixel column over some rows of an image, made in `u16` lanes (twice as many to a
/// vector as `u32`) as many rows at a time as `u16` holds, then added to `u32` sums: the same
/// integers as summing in `u32`, for the per-cell passes over every pixel of a page.
struct ColumnSums {
    /// The sums, per pixel column.
    columns: [Vec<u32>; 2],
    /// The sums of the rows being added.
    lanes: [Vec<u16>; 2],
}

impl ColumnSums {
    fn new(width: usize) -> ColumnSums {
        ColumnSums {
            columns: [vec![0; width], vec![0; width]],
            lanes: [vec![0; width], vec![0; width]],
        }
    }

    /// Sets the sums to those over rows `ys` of the two figures `each` gives a pixel from its gray
    /// level and whether it is ink (`ink`, row-major), each at most `most`.
    fn add_rows(
        &mut self,
        gray: GrayView<'_>,
        ink: &[bool],
        ys: std::ops::Range<usize>,
        most: u16,
        each: impl Fn(u8, bool) -> (u16, u16),
    ) {
        let width = self.columns[0].len();
        let [first, second] = &mut self.columns;
        first.fill(0);
        second.fill(0);
        let at_once = usize::from(u16::MAX / most.max(1));
        let mut y0 = ys.start;
        while y0 < ys.end {
            let y1 = (y0 + at_once).min(ys.end);
            let [a, b] = &mut self.lanes;
            a.fill(0);
            b.fill(0);
            for y in y0..y1 {
                let pixels = gray.row(y).iter().zip(&ink[y * width..(y + 1) * width]);
                for ((a, b), (&v, &i)) in a.iter_mut().zip(b.iter_mut()).zip(pixels) {
                    let (p, q) = each(v, i);
                    *a += p;
                    *b += q;
                }
            }
            for (sum, &a) in first.iter_mut().zip(a.iter()) {
                *sum += u32::from(a);
            }
            for (sum, &b) in second.iter_mut().zip(b.iter()) {
                *sum += u32::from(b);
            }
            y0 = y1;
        }
    }
}

/// The pixel rows of the `cy`-th row of cells `cell` px high, of an image `height` px high.
fn cell_rows(cy: usize, cell: usize, height: usize) -> std::ops::Range<usize> {
    (cy * cell).min(height)..((cy + 1) * cell).min(height)
}

/// What a cell shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cell {
    Stroke,
    Solid,
    DarkField,
    Dense,
    /// Dense, and holding at least [`MIN_DOTS`] pieces of ink: a halftone's screen.
    Dots,
    /// Its gray a fine texture ([`TEXTURE_PIECES`]), whatever the threshold made of it.
    Texture,
}

/// Finds the regions of `ink` (row-major, the gray's size) that are not strokes, removes the ink
/// of those whose kind is not in `keep`, and returns them all, in the order a row-major scan of
/// the cells first meets them.
///
/// `gray` is the image the ink came from, `dark_ink` its polarity and `level` the global level
/// (ink side: at or below it when the ink is dark); `stroke_width` is the page's, px; `grounds`
/// are the reversed grounds, whose cells are none of a region's; `histogram` counts `gray`'s
/// pixels per level.
///
/// The passes over every pixel (the texture's blocks, the cells' counts, the faint ink's
/// paper and contrast) run in parallel by rows of cells, each cell's figures summed in the same
/// order as one pass would (integers): the regions do not depend on the thread count.
#[allow(clippy::too_many_arguments)]
pub(crate) fn find(
    gray: GrayView<'_>,
    histogram: &[u64; 256],
    ink: &mut [bool],
    dark_ink: bool,
    level: u8,
    stroke_width: f64,
    grounds: &[Ground],
    keep: &[RegionKind],
) -> Vec<Region> {
    let mut regions = fields(
        gray,
        histogram,
        ink,
        dark_ink,
        level,
        stroke_width,
        grounds,
        keep,
    );
    let found = rings(
        ink,
        gray.width() as usize,
        gray.height() as usize,
        stroke_width,
        &regions,
        !keep.contains(&RegionKind::Frame),
    );
    regions.extend(found);
    regions.extend(faint(
        gray,
        ink,
        dark_ink,
        stroke_width,
        grounds,
        !keep.contains(&RegionKind::Faint),
    ));
    regions
}

/// The halftones, frames and page edges of [`find`] (the cells' regions), their ink removed
/// unless kept.
#[allow(clippy::too_many_arguments)]
fn fields(
    gray: GrayView<'_>,
    histogram: &[u64; 256],
    ink: &mut [bool],
    dark_ink: bool,
    level: u8,
    stroke_width: f64,
    grounds: &[Ground],
    keep: &[RegionKind],
) -> Vec<Region> {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    if ink.len() != width * height || stroke_width < 1.0 {
        return Vec::new();
    }
    let cell = ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    if cols < SEED_CELLS || rows < SEED_CELLS {
        return Vec::new();
    }
    let counts = seed_counts(gray, ink, dark_ink, level, cell);
    // Every block of SEED_CELLS x SEED_CELLS cells holds one of every SEED_CELLS-th row of cells:
    // the textures of those rows alone (the others taken as possible) rule out nearly every page
    // of text, for a third of the texture's pass; the other rows are looked at when they do not.
    let sampled = |cy: usize| cy % SEED_CELLS == SEED_CELLS - 1;
    let texture_of = |wanted: &(dyn Fn(usize) -> bool + Sync)| {
        texture_cells(gray, histogram, dark_ink, level, stroke_width, cell, wanted)
    };
    let some = texture_of(&sampled);
    if !seed_in_counts(&counts, cols, rows, &some) {
        return Vec::new();
    }
    let rest = texture_of(&|cy| !sampled(cy));
    let texture: Vec<bool> = some
        .iter()
        .zip(&rest)
        .enumerate()
        .map(|(c, (&some, &rest))| if sampled(c / cols) { some } else { rest })
        .collect();
    if !seed_in_counts(&counts, cols, rows, &texture) {
        return Vec::new();
    }
    let (cells, ink_shares) = classify(
        gray,
        ink,
        dark_ink,
        level,
        stroke_width,
        cell,
        grounds,
        &texture,
    );
    let groups = grow(&cells, cols, rows);
    if groups.is_empty() {
        return Vec::new();
    }
    let mut regions = Vec::new();
    let mut removed_cells = vec![false; cols * rows];
    // The pieces of ink, labelled when a photo's box is to be grown.
    let mut pieces = None;
    for mut group in photos(groups, &cells, cols, rows) {
        let textured = group.iter().filter(|&&c| cells[c] == Cell::Texture).count();
        let mut region = describe(&group, cols, rows, cell, width, height);
        if textured as f64 >= TEXTURED_GROUP * group.len() as f64 {
            region.kind = RegionKind::Halftone;
        }
        if region.kind == RegionKind::Halftone {
            let (labels, sizes) = pieces.get_or_insert_with(|| {
                label_components(ink, width, height, true, Connectivity::Eight)
            });
            let grid = Grid::new(width, height, cell);
            group = grow_box(&group, labels, sizes, stroke_width, &grid);
            let kind = region.kind;
            region = describe(&group, cols, rows, cell, width, height);
            region.kind = kind;
        }
        // Beyond a page's edge lies one even dark: cells all ink, or a dark field the threshold
        // left. Solid ink reaching the image's edge with paper showing through it is as likely an
        // over-inked part of the drawing (an ink card's smudged ridges): no page edge.
        if region.kind == RegionKind::PageEdge {
            let even = group
                .iter()
                .filter(|&&c| cells[c] == Cell::DarkField || ink_shares[c] >= PAGE_EDGE_INK)
                .count();
            if (even as f64) < PAGE_EDGE_EVEN * group.len() as f64 {
                continue;
            }
        }
        if !keep.contains(&region.kind) {
            for &c in &group {
                removed_cells[c] = true;
            }
        }
        regions.push(region);
    }
    remove(ink, &Grid::new(width, height, cell), &removed_cells);
    regions
}

/// The rings of lines around the page ([`RegionKind::Frame`]): pieces of ink (8-connected)
/// whose box spans at least [`FRAME_SPAN`] of the image's width and of its height and whose
/// pixels lie in a ring along that box's border ([`RING_SHARE`]): a border printed around a
/// page, the edges of a bound book's pages that a scan shows around the text. No stroke of a
/// page is that large and that hollow. Each ring's ink is removed when `remove` says so, with
/// the pieces left wholly within the cells it crossed and the cells beside them (the specks and
/// bits of the page edges beside it); a stroke touching the ring keeps what leaves those cells.
/// A ring within one of the regions `found` before is none of its own.
fn rings(
    ink: &mut [bool],
    width: usize,
    height: usize,
    stroke_width: f64,
    found: &[Region],
    remove: bool,
) -> Vec<Region> {
    if ink.len() != width * height || width == 0 || stroke_width < 1.0 {
        return Vec::new();
    }
    let long_run = ((RING_RUN * width as f64).ceil() as usize).max(1);
    if !ink.chunks(width).any(|row| has_run(row, long_run)) {
        return Vec::new();
    }
    let (labels, sizes) = label_components(ink, width, height, true, Connectivity::Eight);
    // Each piece's box (none for the paper's label 0).
    let mut boxes: Vec<Option<PieceBox>> = vec![None; sizes.len()];
    for (y, row) in labels.chunks(width).enumerate() {
        for (x, &l) in row.iter().enumerate() {
            if l > 0 {
                let b = boxes[l as usize].get_or_insert(PieceBox {
                    x0: x,
                    y0: y,
                    x1: x,
                    y1: y,
                });
                *b = PieceBox {
                    x0: b.x0.min(x),
                    y0: b.y0.min(y),
                    x1: b.x1.max(x),
                    y1: b.y1.max(y),
                };
            }
        }
    }
    let large: Vec<Option<PieceBox>> = boxes
        .iter()
        .map(|b| {
            b.filter(|b| {
                b.width() as f64 >= FRAME_SPAN * width as f64
                    && b.height() as f64 >= FRAME_SPAN * height as f64
            })
        })
        .collect();
    if large.iter().all(Option::is_none) {
        return Vec::new();
    }
    let mut in_band = vec![0usize; sizes.len()];
    for (y, row) in labels.chunks(width).enumerate() {
        for (x, &l) in row.iter().enumerate() {
            if let Some(b) = large[l as usize] {
                if b.inset(x, y).is_some_and(|d| (d as f64) < b.band()) {
                    in_band[l as usize] += 1;
                }
            }
        }
    }
    let rings: Vec<usize> = (1..sizes.len())
        .filter(|&l| large[l].is_some() && in_band[l] as f64 >= RING_SHARE * sizes[l] as f64)
        .collect();
    // What goes with each ring: the pieces running along its band (the other edges of a stack
    // of pages) and those beyond its lines, between them and the image's edge.
    let mut frame = vec![false; sizes.len()];
    let mut framed = Vec::new();
    let mut regions = Vec::new();
    for &l in &rings {
        let Some(b) = boxes[l] else { continue };
        let band = b.band();
        let mut along = vec![0usize; sizes.len()];
        let mut enclosed = 0;
        for (y, row) in labels.chunks(width).enumerate() {
            for (x, &m) in row.iter().enumerate() {
                match b.inset(x, y) {
                    Some(d) if m > 0 && (d as f64) < band => along[m as usize] += 1,
                    Some(_) if m > 0 && m as usize != l => enclosed += 1,
                    _ => {}
                }
            }
        }
        // A frame is around something: a rectangle or a circle drawn on its own is a stroke.
        // A ring touching all four edges of the image is the image's own margin (the paper,
        // when the ink is light) or a scanner's frame, which [`fields`] finds when thick. A ring
        // in a region already found (a frame of bands, kept) is that region.
        let margin = b.x0 == 0 && b.y0 == 0 && b.x1 + 1 == width && b.y1 + 1 == height;
        let within_found = found.iter().any(|r| {
            let (rx1, ry1) = ((r.x + r.width) as usize, (r.y + r.height) as usize);
            b.x0 >= r.x as usize && b.y0 >= r.y as usize && b.x1 < rx1 && b.y1 < ry1
        });
        if enclosed < sizes[l] || margin || within_found {
            continue;
        }
        framed.push(l);
        frame[l] = true;
        for m in 1..sizes.len() {
            let Some(piece) = boxes[m] else { continue };
            let long = piece.width() as f64 >= FRAME_SPAN * b.width() as f64
                || piece.height() as f64 >= FRAME_SPAN * b.height() as f64;
            if long && along[m] as f64 >= RING_SHARE * sizes[m] as f64 {
                frame[m] = true;
            }
        }
        regions.push(Region {
            kind: RegionKind::Frame,
            x: b.x0 as u32,
            y: b.y0 as u32,
            width: b.width() as u32,
            height: b.height() as u32,
        });
    }
    if !remove || framed.is_empty() {
        return regions;
    }
    let beyond = beyond_frame(
        &labels,
        &sizes,
        &frame,
        &boxes,
        &framed,
        width,
        stroke_width,
    );
    let grid = Grid::new(
        width,
        height,
        ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL),
    );
    let mut crossed = vec![false; grid.cols * grid.rows];
    for (p, (i, &l)) in ink.iter_mut().zip(&labels).enumerate() {
        let l = l as usize;
        if frame[l] || beyond[l] {
            *i = false;
        }
        if frame[l] {
            crossed[(p / width / grid.cell) * grid.cols + (p % width) / grid.cell] = true;
        }
    }
    remove_enclosed(ink, &grid, &crossed);
    regions
}

/// A piece of ink's box, its first and last columns and rows.
#[derive(Clone, Copy, Debug)]
struct PieceBox {
    x0: usize,
    y0: usize,
    x1: usize,
    y1: usize,
}

impl PieceBox {
    fn width(&self) -> usize {
        self.x1 - self.x0 + 1
    }

    fn height(&self) -> usize {
        self.y1 - self.y0 + 1
    }

    /// A ring's band along the box's border ([`RING_BAND`] of its shorter side), px.
    fn band(&self) -> f64 {
        RING_BAND * self.width().min(self.height()) as f64
    }

    /// The gap between two boxes, px: the most of the columns and the rows between them (0
    /// when they touch or overlap).
    fn gap(&self, other: &PieceBox) -> usize {
        let dx = self
            .x0
            .saturating_sub(other.x1)
            .max(other.x0.saturating_sub(self.x1));
        let dy = self
            .y0
            .saturating_sub(other.y1)
            .max(other.y0.saturating_sub(self.y1));
        dx.max(dy).saturating_sub(1)
    }

    /// How far the pixel `(x, y)` lies inside the box from its nearest side; `None` outside.
    fn inset(&self, x: usize, y: usize) -> Option<usize> {
        (x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1).then(|| {
            (x - self.x0)
                .min(self.x1 - x)
                .min(y - self.y0)
                .min(self.y1 - y)
        })
    }
}

/// Whether `row` holds a run of at least `long` ink pixels. Looked at every `long / 2` pixels
/// (a run that long covers two looks in a row) and measured where two looks in a row are ink:
/// a row of text costs a few looks, not a pass.
fn has_run(row: &[bool], long: usize) -> bool {
    if long <= 1 {
        return row.contains(&true);
    }
    let step = long / 2;
    let mut x = 0;
    while x < row.len() {
        if row[x] && row.get(x + step).copied().unwrap_or(false) {
            let start = row[..x].iter().rposition(|&i| !i).map_or(0, |p| p + 1);
            let end = row[x..]
                .iter()
                .position(|&i| !i)
                .map_or(row.len(), |p| x + p);
            if end - start >= long {
                return true;
            }
            x = end + 1;
        } else {
            x += step;
        }
    }
    false
}

/// The pieces of ink wholly beyond a frame's lines: each of their pixels lies between the
/// image's edge and the innermost of the `frame` pieces' pixels on a side of a ring's box that
/// the frame lines for at least [`FRAME_SPAN`] of its length, that innermost line taken as its
/// least depth within a cell of [`CELL_WIDTHS`] `w` along the side (a gap in the line lets no
/// piece through). With them goes the dirt along the edge: groups of pieces wholly within the
/// ring's band on its lined sides, each within a cell of another, none within a cell of the
/// rest of the page's ink larger than a speck, at least half of them specks ([`SPECK_AREA`]).
/// A line of text reaching into the band is joined to its letters beyond it (words and lines
/// are less than a cell apart), a full stop or an i's dot lies within a cell of its letters,
/// and a page number or a catchword on its own in the band is letters, not specks.
fn beyond_frame(
    labels: &[u32],
    sizes: &[usize],
    frame: &[bool],
    boxes: &[Option<PieceBox>],
    rings: &[usize],
    width: usize,
    stroke_width: f64,
) -> Vec<bool> {
    let pieces = frame.len();
    let window = ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL);
    let mut beyond = vec![false; pieces];
    for b in rings.iter().filter_map(|&l| boxes[l]) {
        let band = b.band();
        // A side as (its length, the (along, depth) of a pixel of the box).
        type Side = fn((usize, usize), &PieceBox) -> (usize, usize);
        let sides: [(usize, Side); 4] = [
            (b.height(), |(x, y), b| (y - b.y0, x - b.x0)),
            (b.height(), |(x, y), b| (y - b.y0, b.x1 - x)),
            (b.width(), |(x, y), b| (x - b.x0, y - b.y0)),
            (b.width(), |(x, y), b| (x - b.x0, b.y1 - y)),
        ];
        let mut inner: Vec<Vec<Option<usize>>> = sides.iter().map(|s| vec![None; s.0]).collect();
        for (p, &m) in labels.iter().enumerate() {
            let (x, y) = (p % width, p / width);
            if m > 0 && frame[m as usize] && b.inset(x, y).is_some() {
                for (s, &(_, side)) in sides.iter().enumerate() {
                    let (a, d) = side((x, y), &b);
                    if (d as f64) < band {
                        let e = &mut inner[s][a];
                        *e = Some(e.map_or(d, |e: usize| e.max(d)));
                    }
                }
            }
        }
        // The innermost line's least depth within a window along the side; sides the frame
        // does not line are left out.
        let depths: Vec<Option<Vec<usize>>> = inner
            .iter()
            .map(|line| {
                let lined = line.iter().filter(|d| d.is_some()).count();
                ((lined as f64) >= FRAME_SPAN * line.len() as f64).then(|| {
                    (0..line.len())
                        .map(|a| {
                            let (lo, hi) =
                                (a.saturating_sub(window), (a + window + 1).min(line.len()));
                            line[lo..hi]
                                .iter()
                                .map(|d| d.unwrap_or(0))
                                .min()
                                .unwrap_or(0)
                        })
                        .collect()
                })
            })
            .collect();
        let mut beyond_pixels = vec![0usize; pieces];
        let mut band_pixels = vec![0usize; pieces];
        for (p, &m) in labels.iter().enumerate() {
            let m = m as usize;
            let (x, y) = (p % width, p / width);
            if m == 0 || frame[m] || b.inset(x, y).is_none() {
                continue;
            }
            let (mut out, mut in_band) = (false, false);
            for (&(_, side), depth) in sides.iter().zip(&depths) {
                if let Some(depth) = depth {
                    let (a, d) = side((x, y), &b);
                    out |= d < depth[a];
                    in_band |= (d as f64) < band;
                }
            }
            beyond_pixels[m] += usize::from(out);
            band_pixels[m] += usize::from(in_band);
        }
        for m in 1..pieces {
            beyond[m] |= beyond_pixels[m] == sizes[m];
        }
        // The dirt along the edge: groups of pieces wholly in the band of lined sides, each
        // within a cell of another ([`PieceBox::gap`]), none within a cell of the rest of the
        // page's ink larger than a speck (the text), at least half of them specks.
        let speck = |m: usize| (sizes[m] as f64) < SPECK_AREA * stroke_width * stroke_width;
        let loose: Vec<usize> = (1..pieces)
            .filter(|&m| !frame[m] && !beyond[m] && band_pixels[m] == sizes[m])
            .collect();
        if loose.is_empty() {
            continue;
        }
        let mut group: Vec<usize> = (0..loose.len()).collect();
        fn root(group: &mut [usize], mut i: usize) -> usize {
            while group[i] != i {
                group[i] = group[group[i]];
                i = group[i];
            }
            i
        }
        let near = |m: usize, n: usize| match (boxes[m], boxes[n]) {
            (Some(a), Some(c)) => a.gap(&c) <= window,
            _ => false,
        };
        for i in 0..loose.len() {
            for j in i + 1..loose.len() {
                if near(loose[i], loose[j]) {
                    let (ri, rj) = (root(&mut group, i), root(&mut group, j));
                    group[ri.max(rj)] = ri.min(rj);
                }
            }
        }
        let is_loose = {
            let mut is = vec![false; pieces];
            loose.iter().for_each(|&m| is[m] = true);
            is
        };
        // Per group: joined to the page's other ink, its pieces, its specks.
        let mut joined = vec![false; loose.len()];
        let mut counts = vec![(0usize, 0usize); loose.len()];
        for (i, &m) in loose.iter().enumerate() {
            let r = root(&mut group, i);
            if (1..pieces)
                .any(|n| !is_loose[n] && !frame[n] && !beyond[n] && !speck(n) && near(m, n))
            {
                joined[r] = true;
            }
            counts[r].0 += 1;
            counts[r].1 += usize::from(speck(m));
        }
        for (i, &m) in loose.iter().enumerate() {
            let r = root(&mut group, i);
            if !joined[r] && 2 * counts[r].1 >= counts[r].0 {
                beyond[m] = true;
            }
        }
    }
    beyond
}

/// The faint ink ([`RegionKind::Faint`]): the pieces of ink (8-connected) of which less than
/// [`FAINT_CORE`] of the pixels reach [`FAINT_SHARE`] of the page's text contrast, as one region
/// (the box of their ink), removed when `remove` says so, when together they are at least
/// [`FAINT_INK`] of the ink; none otherwise.
///
/// The darkness of a pixel is how far its gray lies from its cell's paper towards the ink (the
/// mean gray of the cell's paper pixels, cells of [`CELL_WIDTHS`] `w`; a cell with less than a
/// quarter paper takes its neighbours'), and the page's text contrast is the darkness the ink
/// reaches at its [`TEXT_QUANTILE`]: the cores of the strokes, however much more of the ink a
/// texture is. A threshold that splits ink from paper halfway leaves a stroke of the text
/// mostly at least half its contrast, so a page of text has no faint piece. Where faint pieces
/// are most of the ink, a local threshold (which finds ink in every neighbourhood) has read the
/// paper itself: its grain, a cover's cracks, show-through from the back of the page. Fewer
/// faint pieces are left: ruled lines drawn fainter than the writing and a print's lighter
/// ridges are as faint (docs/design.md, "The front end"). A faint net joined to a stroke is one
/// piece with it and stays.
fn faint(
    gray: GrayView<'_>,
    ink: &mut [bool],
    dark_ink: bool,
    stroke_width: f64,
    grounds: &[Ground],
    remove: bool,
) -> Option<Region> {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    if ink.len() != width * height || stroke_width < 1.0 || width == 0 || height == 0 {
        return None;
    }
    let cell = ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    let turn = |v: u8| i32::from(if dark_ink { v } else { 255 - v });
    // The paper's mean gray (turned: ink dark) per cell, where a quarter of the cell is paper
    // (rows of cells in parallel).
    let mut sums = vec![(0u64, 0u32, 0u32); cols * rows];
    sums.par_chunks_mut(cols).enumerate().for_each_init(
        || ColumnSums::new(width),
        |column_sums, (cy, sums)| {
            // Each pixel column's paper over the row of cells (whole rows, without a branch, in
            // vector lanes: the level masked off under ink), then each cell's columns, turned per
            // cell: `255 n - sum` under light ink.
            let ys = cell_rows(cy, cell, height);
            let cell_rows = ys.len() as u32;
            column_sums.add_rows(gray, ink, ys, u16::from(u8::MAX), |v, i| {
                (u16::from(v & u8::from(i).wrapping_sub(1)), u16::from(!i))
            });
            let [paper_sums, paper_counts] = &column_sums.columns;
            let columns = paper_sums.chunks(cell).zip(paper_counts.chunks(cell));
            for (s, (sums, counts)) in sums.iter_mut().zip(columns) {
                let (sum, n) = (sums.iter().sum::<u32>(), counts.iter().sum::<u32>());
                let turned = if dark_ink { sum } else { 255 * n - sum };
                *s = (u64::from(turned), n, cell_rows * sums.len() as u32);
            }
        },
    );
    // The cells with ink (fewer paper pixels than pixels): the others add nothing below.
    let inked: Vec<bool> = sums.iter().map(|&(_, paper, all)| paper < all).collect();
    let paper = paper_means(&sums, cols, rows)?;
    // A reversed ground's strokes are lighter than the ground around them: neither measured nor
    // left out.
    let in_ground = |p: usize| {
        let (x, y) = ((p % width) as u32, (p / width) as u32);
        grounds
            .iter()
            .any(|g| (g.x..g.x + g.width).contains(&x) && (g.y..g.y + g.height).contains(&y))
    };
    let darkness = |p: usize| {
        paper[(p / width / cell) * cols + (p % width) / cell] - turn(gray.row(p / width)[p % width])
    };
    // The text's contrast: the darkness at TEXT_QUANTILE of the ink, from a histogram (rows
    // in parallel, the counts summed).
    let rows_per_task = (PIXELS_PER_TASK / width).max(1);
    let (histogram, total) = (0..height)
        .into_par_iter()
        .with_min_len(rows_per_task)
        .fold(
            || ([0u64; 511], 0u64),
            |(mut histogram, mut total), y| {
                let row = y * width..(y + 1) * width;
                let papers = &paper[(y / cell) * cols..(y / cell + 1) * cols];
                let inked = &inked[(y / cell) * cols..(y / cell + 1) * cols];
                let cells = gray.row(y).chunks(cell).zip(ink[row].chunks(cell));
                for (c, ((values, ink), (&paper, &inked))) in
                    cells.zip(papers.iter().zip(inked)).enumerate()
                {
                    if !inked {
                        continue;
                    }
                    for (x, (&v, &i)) in (c * cell..).zip(values.iter().zip(ink)) {
                        if i && (grounds.is_empty() || !in_ground(y * width + x)) {
                            histogram[(paper - turn(v) + 255) as usize] += 1;
                            total += 1;
                        }
                    }
                }
                (histogram, total)
            },
        )
        .reduce(
            || ([0u64; 511], 0u64),
            |(mut a, n), (b, m)| {
                for (a, b) in a.iter_mut().zip(b) {
                    *a += b;
                }
                (a, n + m)
            },
        );
    let contrast = text_contrast(&histogram, total)?;
    // Without reversed grounds every ink pixel was measured: the histogram's total is the ink.
    let all_ink: usize = if grounds.is_empty() {
        total as usize
    } else {
        ink.par_chunks(PIXELS_PER_TASK)
            .map(|ink| ink.iter().filter(|&&i| i).count())
            .sum()
    };
    faint_pieces(
        ink, width, height, &histogram, contrast, all_ink, in_ground, darkness, remove,
    )
}

/// The cells' paper levels of [`faint`] from each cell's (sum, count) of paper pixels and its
/// pixel count: the mean where a quarter of the cell is paper; a cell with less takes the mean of
/// its known neighbours (8-connected), ring by ring. `None` when no cell has enough paper.
fn paper_means(sums: &[(u64, u32, u32)], cols: usize, rows: usize) -> Option<Vec<i32>> {
    let mut paper: Vec<Option<i32>> = sums
        .iter()
        .map(|&(sum, n, all)| (4 * n >= all && n > 0).then(|| (sum / u64::from(n)) as i32))
        .collect();
    if paper.iter().all(Option::is_none) {
        return None;
    }
    while paper.iter().any(Option::is_none) {
        let before = paper.clone();
        for c in 0..cols * rows {
            if before[c].is_some() {
                continue;
            }
            let (x, y) = (c % cols, c / cols);
            let (mut sum, mut n) = (0i64, 0i64);
            for ny in y.saturating_sub(1)..(y + 2).min(rows) {
                for nx in x.saturating_sub(1)..(x + 2).min(cols) {
                    if let Some(p) = before[ny * cols + nx] {
                        sum += i64::from(p);
                        n += 1;
                    }
                }
            }
            if n > 0 {
                paper[c] = Some((sum / n) as i32);
            }
        }
    }
    Some(paper.into_iter().map(|p| p.unwrap_or(0)).collect())
}

/// The text's contrast of [`faint`]: the darkness at [`TEXT_QUANTILE`] of the measured ink, from
/// the histogram of darkness + 255 over `total` pixels; `None` when there is no ink or it is not
/// darker than the paper.
fn text_contrast(histogram: &[u64; 511], total: u64) -> Option<i32> {
    if total == 0 {
        return None;
    }
    let rank = (TEXT_QUANTILE * total as f64).ceil() as u64;
    let mut seen = 0;
    let contrast = histogram
        .iter()
        .position(|&n| {
            seen += n;
            seen >= rank
        })
        .map_or(0, |d| d as i32 - 255);
    (contrast > 0).then_some(contrast)
}

/// The rest of [`faint`] once the text's contrast is known: the faint pieces of ink as one region,
/// removed from `ink` when `remove` says so.
#[allow(clippy::too_many_arguments)]
fn faint_pieces(
    ink: &mut [bool],
    width: usize,
    height: usize,
    histogram: &[u64; 511],
    contrast: i32,
    all_ink: usize,
    in_ground: impl Fn(usize) -> bool,
    darkness: impl Fn(usize) -> i32,
    remove: bool,
) -> Option<Region> {
    let measured = |ink: &[bool], p: usize| ink[p] && !in_ground(p);
    let reaches = |p: usize| f64::from(darkness(p)) >= FAINT_SHARE * f64::from(contrast);
    // A faint piece of n pixels has more than (1 - FAINT_CORE) n measured pixels that do not
    // reach the share, so all faint pieces together are fewer than those pixels over
    // (1 - FAINT_CORE): when that bound is under FAINT_INK of the ink (a page of text), there is
    // nothing to leave out, and the page need not be labelled.
    // The measured pixels short of the share, read off the histogram.
    let short: u64 = histogram
        .iter()
        .enumerate()
        .filter(|&(d, _)| f64::from(d as i32 - 255) < FAINT_SHARE * f64::from(contrast))
        .map(|(_, &n)| n)
        .sum();
    if (short as f64) < (1.0 - FAINT_CORE) * FAINT_INK * all_ink as f64 {
        return None;
    }
    // Per piece of ink (8-connected), its pixels and those that reach the share of the text's
    // contrast (ink in a ground counts as reaching it, so a ground's strokes stay).
    let (labels, sizes) = label_components(ink, width, height, true, Connectivity::Eight);
    let mut reaching = vec![0usize; sizes.len()];
    for (p, &l) in labels.iter().enumerate() {
        if l > 0 && (!measured(ink, p) || reaches(p)) {
            reaching[l as usize] += 1;
        }
    }
    let faint: Vec<bool> = reaching
        .iter()
        .zip(&sizes)
        .enumerate()
        .map(|(l, (&r, &n))| l > 0 && (r as f64) < FAINT_CORE * n as f64)
        .collect();
    // Only where the faint pieces are most of the ink: the threshold has read the paper itself
    // (its grain, a cover's cracks) as ink. Fewer faint pieces beside the text are as likely
    // faint content (ruled lines, a print's lighter ridges) as show-through.
    let faint_ink: usize = faint
        .iter()
        .zip(&sizes)
        .filter(|(&f, _)| f)
        .map(|(_, &n)| n)
        .sum();
    if (faint_ink as f64) < FAINT_INK * all_ink as f64 {
        return None;
    }
    let (mut x0, mut y0, mut x1, mut y1) = (width, height, 0, 0);
    let mut any = false;
    for (p, (i, &l)) in ink.iter_mut().zip(&labels).enumerate() {
        if faint[l as usize] {
            let (x, y) = (p % width, p / width);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            any = true;
            if remove {
                *i = false;
            }
        }
    }
    any.then(|| Region {
        kind: RegionKind::Faint,
        x: x0 as u32,
        y: y0 as u32,
        width: (x1 - x0 + 1) as u32,
        height: (y1 - y0 + 1) as u32,
    })
}

/// Every cell's class and its share of ink.
#[allow(clippy::too_many_arguments)]
fn classify(
    gray: GrayView<'_>,
    ink: &[bool],
    dark_ink: bool,
    level: u8,
    stroke_width: f64,
    cell: usize,
    grounds: &[Ground],
    texture: &[bool],
) -> (Vec<Cell>, Vec<f64>) {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    // Thick: the whole square of side THICK_WIDTHS w around the pixel is ink.
    let thick_radius = ((THICK_WIDTHS * stroke_width - 1.0) / 2.0).ceil().max(1.0) as usize;
    let thick = box_all(ink, true, width, height, thick_radius);
    // Open paper: no ink within w (Chebyshev).
    let open = box_all(ink, false, width, height, stroke_width.ceil() as usize);
    let mut counts = vec![[0u32; 5]; cols * rows];
    // Where each piece of ink begins (its first pixel in row-major order).
    let mut starts = vec![0u32; cols * rows];
    {
        let (labels, sizes) = label_components(ink, width, height, true, Connectivity::Eight);
        let mut begun = vec![false; sizes.len()];
        for (p, &l) in labels.iter().enumerate() {
            let l = l as usize;
            if l > 0 && !begun[l] {
                begun[l] = true;
                starts[(p / width / cell) * cols + (p % width) / cell] += 1;
            }
        }
    }
    // The sum and count of the paper's gray levels per cell.
    let mut paper_gray = vec![(0u64, 0u32); cols * rows];
    let is_dark = |v: u8| if dark_ink { v <= level } else { v > level };
    // Row by row, a cell's width of pixels at a time.
    for y in 0..height {
        let span = y * width..(y + 1) * width;
        let base = (y / cell) * cols;
        let pieces = gray
            .row(y)
            .chunks(cell)
            .zip(ink[span.clone()].chunks(cell))
            .zip(thick[span.clone()].chunks(cell))
            .zip(open[span].chunks(cell));
        for (c, (((row, ink), thick), open)) in pieces.enumerate() {
            let count = |values: &[bool]| values.iter().filter(|&&v| v).count() as u32;
            let counts = &mut counts[base + c];
            counts[0] += row.len() as u32;
            counts[1] += count(ink);
            counts[2] += count(thick);
            counts[3] += count(open);
            counts[4] += row.iter().filter(|&&v| is_dark(v)).count() as u32;
            let g = &mut paper_gray[base + c];
            for (&v, &i) in row.iter().zip(ink) {
                if !i {
                    g.0 += u64::from(v);
                    g.1 += 1;
                }
            }
        }
    }
    let in_ground = |c: usize| {
        let (x0, y0) = ((c % cols) * cell, (c / cols) * cell);
        grounds.iter().any(|g| {
            let (gx, gy) = (g.x as usize, g.y as usize);
            x0 < gx + g.width as usize
                && gx < x0 + cell
                && y0 < gy + g.height as usize
                && gy < y0 + cell
        })
    };
    let mut classes: Vec<Cell> = counts
        .iter()
        .enumerate()
        .map(|(c, counts)| {
            let n = f64::from(counts[0].max(1));
            let share = |k: usize| f64::from(counts[k]) / n;
            if in_ground(c) {
                Cell::Stroke
            } else if share(2) >= SOLID_SHARE {
                Cell::Solid
            } else if share(4) >= DARK_SHARE && share(1) < DARK_FIELD_INK {
                Cell::DarkField
            } else if texture[c] {
                Cell::Texture
            } else if share(3) < OPEN_PAPER && share(1) >= DENSE_INK {
                if starts[c] >= MIN_DOTS && share(1) >= DOTS_INK {
                    Cell::Dots
                } else {
                    Cell::Dense
                }
            } else {
                Cell::Stroke
            }
        })
        .collect();
    let paper_gray: Vec<f64> = paper_gray
        .iter()
        .map(|&(sum, n)| sum as f64 / f64::from(n.max(1)))
        .collect();
    keep_stepped_dark_fields(&mut classes, &paper_gray, cols, rows);
    let ink_shares = counts
        .iter()
        .map(|c| f64::from(c[1]) / f64::from(c[0].max(1)))
        .collect();
    (classes, ink_shares)
}

/// Whether any seed can be found: a cheap look at each cell's share of ink and of dark before the
/// costlier tests (thick ink, open paper, the pieces of ink). A solid cell is at least
/// [`SOLID_SHARE`] ink and a dark field at least [`DARK_SHARE`] dark with little ink; a seed needs
/// [`SEED_CELLS`] x [`SEED_CELLS`] cells that could be solid, dark fields or textures, or
/// [`SEED_CELLS`] in a row along the image's edge that could be solid. A page of text has none.
#[cfg(test)]
fn seed_possible(
    gray: GrayView<'_>,
    ink: &[bool],
    dark_ink: bool,
    level: u8,
    cell: usize,
    texture: &[bool],
) -> bool {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    let counts = seed_counts(gray, ink, dark_ink, level, cell);
    seed_in_counts(&counts, cols, rows, texture)
}

/// The counts of ink, dark and all pixels per cell that [`seed_possible`] looks at.
fn seed_counts(
    gray: GrayView<'_>,
    ink: &[bool],
    dark_ink: bool,
    level: u8,
    cell: usize,
) -> Vec<[u32; 3]> {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    // Ink, dark and all pixels per cell, a cell's width of pixels at a time, rows of cells in
    // parallel.
    // Each pixel column's ink and pixels at or below the level over the row of cells (whole
    // rows in vector lanes), then each cell's columns; the dark side is their complement under
    // light ink.
    let mut counts = vec![[0u32; 3]; cols * rows];
    counts.par_chunks_mut(cols).enumerate().for_each_init(
        || ColumnSums::new(width),
        |sums, (cy, counts)| {
            let ys = cell_rows(cy, cell, height);
            let cell_rows = ys.len() as u32;
            sums.add_rows(gray, ink, ys, 1, move |v, i| {
                (u16::from(i), u16::from(v <= level))
            });
            let [inks, at_or_below] = &sums.columns;
            let columns = inks.chunks(cell).zip(at_or_below.chunks(cell));
            for (counts, (inks, below)) in counts.iter_mut().zip(columns) {
                let all = cell_rows * inks.len() as u32;
                let below = below.iter().sum::<u32>();
                let dark = if dark_ink { below } else { all - below };
                *counts = [inks.iter().sum::<u32>(), dark, all];
            }
        },
    );
    counts
}

/// [`seed_possible`] from the cells' counts of ink, dark and all pixels.
fn seed_in_counts(counts: &[[u32; 3]], cols: usize, rows: usize, texture: &[bool]) -> bool {
    let share = |c: usize, k: usize| f64::from(counts[c][k]) / f64::from(counts[c][2].max(1));
    let solid = |c: usize| share(c, 0) >= SOLID_SHARE;
    let candidate = |c: usize| {
        solid(c) || (share(c, 1) >= DARK_SHARE && share(c, 0) < DARK_FIELD_INK) || texture[c]
    };
    let block = |x: usize, y: usize| {
        (0..SEED_CELLS).all(|dy| (0..SEED_CELLS).all(|dx| candidate((y + dy) * cols + x + dx)))
    };
    let inside = (0..=rows - SEED_CELLS).any(|y| (0..=cols - SEED_CELLS).any(|x| block(x, y)));
    let along_edge = (0..cols * rows).any(|c| {
        let (x, y) = (c % cols, c / cols);
        let along_row = (y == 0 || y + 1 == rows) && x + SEED_CELLS <= cols;
        let along_col = (x == 0 || x + 1 == cols) && y + SEED_CELLS <= rows;
        (along_row && (0..SEED_CELLS).all(|d| solid(c + d)))
            || (along_col && (0..SEED_CELLS).all(|d| solid(c + d * cols)))
    });
    inside || along_edge
}

/// The cell (of `cells`, each `cell` px) of each window of blocks `side` px square along one
/// axis of `blocks` blocks padded with one block each side: window `i` starts at padded block
/// `i`, the block at `i - 1` (the first window at the first block).
fn window_cells(blocks: usize, side: usize, cell: usize, cells: usize) -> Vec<usize> {
    (0..=blocks)
        .map(|i| ((i.max(1) - 1) * side / cell).min(cells - 1))
        .collect()
}

/// Which cells are textures ([`TEXTURE_PIECES`]). The gray is averaged over blocks of half a
/// stroke width (a fingerprint's pores and a scan's grain, finer than that, are gone) and cut at
/// two levels, halfway from the global level to the ink's median gray and halfway to the paper's:
/// a texture shows its pieces in both cuts, where the noise of a shaded area near the level
/// shows them in one only. Pieces are counted by the Euler number (pieces of ink, 8-connected,
/// less their holes) from the 2 x 2 windows of blocks (Gray's bit quads: `4 E = Q1 - Q3 - 2 QD`),
/// each window counted in the cell of its first block.
///
/// Only the rows of cells `wanted` says are looked at (with the blocks their windows need); the
/// cells of the others are said to be textures, so that a seed test on them rules out only what
/// the rows looked at rule out.
fn texture_cells(
    gray: GrayView<'_>,
    histogram: &[u64; 256],
    dark_ink: bool,
    level: u8,
    stroke_width: f64,
    cell: usize,
    wanted: &(dyn Fn(usize) -> bool + Sync),
) -> Vec<bool> {
    let (width, height) = (gray.width() as usize, gray.height() as usize);
    let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
    // Gray turned so that the ink is dark (`255 - v` under light ink): ink at or below `cut`.
    let cut = if dark_ink {
        level
    } else {
        254u8.saturating_sub(level)
    };
    // The pixels at each turned level.
    let turned = |t: usize| histogram[if dark_ink { t } else { 255 - t }];
    let median_of = |range: std::ops::RangeInclusive<usize>| -> Option<f64> {
        let total: u64 = range.clone().map(turned).sum();
        let mut seen = 0;
        for v in range {
            seen += turned(v);
            if total > 0 && 2 * seen >= total {
                return Some(v as f64);
            }
        }
        None
    };
    let (Some(ink_gray), Some(paper_gray)) = (
        median_of(0..=usize::from(cut)),
        median_of(usize::from(cut) + 1..=255),
    ) else {
        return vec![false; cols * rows];
    };
    let cut = f64::from(cut);
    let levels = [cut - (cut - ink_gray) / 2.0, cut + (paper_gray - cut) / 2.0];
    // Block means, each block `side` px square (cut to the image), at or below each level: the
    // blocks padded with a block of paper all round, so that the window at (x, y) is the padded
    // blocks (x, y) to (x + 1, y + 1). The sums are kept for one row of blocks at a time.
    let side = ((stroke_width / 2.0).floor() as usize).max(1);
    let (bw, bh) = (width.div_ceil(side), height.div_ceil(side));
    let pw = bw + 2;
    // The cell column of each window's first block (x is one more than the block's position),
    // and the cell row of each row of windows (rising with it).
    let cell_col = window_cells(bw, side, cell, cols);
    let cell_row = window_cells(bh, side, cell, rows);
    // The padded rows of blocks the wanted rows' windows read: window row y reads rows y, y + 1.
    let mut needed = vec![false; bh + 2];
    for (y, &cy) in cell_row.iter().enumerate() {
        if wanted(cy) {
            needed[y] = true;
            needed[y + 1] = true;
        }
    }
    // Rows of blocks in parallel, each padded row of the two cuts written by one task. A block
    // row's pixels are summed column by column first (a pass the compiler runs in vector lanes),
    // then each block's columns; the gray is turned per block (`255 n - sum` under light ink).
    // A block's mean is at or below a level exactly when its integer sum is at or below the
    // largest sum whose mean is ([`largest_sum_at_or_below`]): the same test without a division
    // per block.
    let mut padded = [vec![0u8; pw * (bh + 2)], vec![0u8; pw * (bh + 2)]];
    {
        let [low, high] = &mut padded;
        let inner = pw..pw * (bh + 1);
        let blocks_per_task = (PIXELS_PER_TASK / (side * width).max(1)).max(1);
        let last = width - (bw - 1) * side;
        low[inner.clone()]
            .par_chunks_mut(pw)
            .zip(high[inner].par_chunks_mut(pw))
            .enumerate()
            .with_min_len(blocks_per_task)
            .for_each_init(
                || vec![0u32; width],
                |columns, (by, (low, high))| {
                    if !needed[by + 1] {
                        return;
                    }
                    let ys = by * side..((by + 1) * side).min(height);
                    let block_rows = ys.len();
                    columns.fill(0);
                    for y in ys {
                        for (sum, &v) in columns.iter_mut().zip(gray.row(y)) {
                            *sum += u32::from(v);
                        }
                    }
                    // The limits for the full blocks and the last, narrower one.
                    let limits = |columns_wide: usize| {
                        let size = (block_rows * columns_wide) as u32;
                        (
                            size,
                            levels.map(|level| largest_sum_at_or_below(size, level)),
                        )
                    };
                    let (full, narrow) = (limits(side), limits(last));
                    cut_blocks(columns, side, dark_ink, [full, narrow], low, high);
                },
            );
    }
    let counts =
        padded.map(|padded| euler_quads(&padded, bw, &cell_col, &cell_row, (cols, rows), wanted));
    (0..cols * rows)
        .map(|c| {
            let (a, b) = (counts[0][c], counts[1][c]);
            !wanted(c / cols)
                || a.signum() == b.signum()
                    && f64::from(a.abs().min(b.abs())) / 4.0 >= TEXTURE_PIECES
        })
        .collect()
}

/// One row of [`texture_cells`]' blocks cut at its two levels: `columns` holds each pixel
/// column's sum over the row's pixels, a block is `side` columns (the last one what is left),
/// `limits` the (size, largest sums at or below the two levels) of the full blocks and of the
/// last; `low` and `high` get 1 for the blocks at or below each level, from their second byte.
fn cut_blocks(
    columns: &[u32],
    side: usize,
    dark_ink: bool,
    limits: [(u32, [i64; 2]); 2],
    low: &mut [u8],
    high: &mut [u8],
) {
    for (b, block) in columns.chunks(side).enumerate() {
        let sum = block.iter().sum::<u32>();
        let (size, [low_limit, high_limit]) = if block.len() == side {
            limits[0]
        } else {
            limits[1]
        };
        let sum = i64::from(if dark_ink { sum } else { 255 * size - sum });
        low[1 + b] = u8::from(sum <= low_limit);
        high[1 + b] = u8::from(sum <= high_limit);
    }
}

/// The largest sum `s` of `size` gray levels (`0..=255 size`) whose mean `s / size`, divided in
/// `f64` as [`texture_cells`] first did, is at or below `level`; -1 when none is. The rounded
/// quotient never falls as `s` grows, so a sum's mean is at or below `level` exactly when the sum
/// is at or below this one.
fn largest_sum_at_or_below(size: u32, level: f64) -> i64 {
    let at_or_below = |s: i64| s as f64 / f64::from(size.max(1)) <= level;
    let (mut lo, mut hi) = (-1i64, 255 * i64::from(size));
    if at_or_below(hi) {
        return hi;
    }
    // at_or_below(lo) (or lo is -1) and !at_or_below(hi).
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if at_or_below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Demotes the dark fields that do not end in a step: beyond a page's edge the gray falls from
/// the paper's level to the dark in about a cell, where a shadow or uneven light darkens the
/// paper gradually. A field (4-connected dark-field cells) stays when the median fall of the
/// paper's gray across its border, to the stroke cells beside it, is at least [`STEP_SHARE`] of
/// the fall from the page's paper (the median stroke cell) to the field's median.
fn keep_stepped_dark_fields(classes: &mut [Cell], paper_gray: &[f64], cols: usize, rows: usize) {
    let mut stroke: Vec<f64> = (0..classes.len())
        .filter(|&c| classes[c] == Cell::Stroke)
        .map(|c| paper_gray[c])
        .collect();
    let Some(paper) = upper_median_by(&mut stroke, f64::total_cmp) else {
        return;
    };
    let mut seen = vec![false; classes.len()];
    for start in 0..classes.len() {
        if classes[start] != Cell::DarkField || seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut field, mut stack, mut steps) = (Vec::new(), vec![start], Vec::new());
        while let Some(c) = stack.pop() {
            field.push(c);
            for n in neighbours(c, cols, rows) {
                match classes[n] {
                    Cell::DarkField if !seen[n] => {
                        seen[n] = true;
                        stack.push(n);
                    }
                    Cell::Stroke => steps.push((paper_gray[n] - paper_gray[c]).abs()),
                    _ => {}
                }
            }
        }
        let mut grays: Vec<f64> = field.iter().map(|&c| paper_gray[c]).collect();
        let dark = upper_median_by(&mut grays, f64::total_cmp).unwrap_or(paper);
        let step = upper_median_by(&mut steps, f64::total_cmp).unwrap_or(0.0);
        if step < STEP_SHARE * (paper - dark).abs() {
            for c in field {
                classes[c] = Cell::Stroke;
            }
        }
    }
}

/// The 4-neighbours of cell `c`.
fn neighbours(c: usize, cols: usize, rows: usize) -> impl Iterator<Item = usize> {
    let (x, y) = (c % cols, c / cols);
    [
        (x > 0).then(|| c - 1),
        (x + 1 < cols).then(|| c + 1),
        (y > 0).then(|| c - cols),
        (y + 1 < rows).then(|| c + cols),
    ]
    .into_iter()
    .flatten()
}

/// Whether the square of side `2 radius + 1` around each pixel, cut to the image, is all `value`
/// in `mask`. One pass down the rows: each row's horizontal test comes from the length of the
/// run of `value` ending at each pixel (the window `[s, e]` is all `value` when the run ending at
/// `e` is at least `e - s + 1` long), and each column keeps the length of its run of rows that
/// passed it, so a row's answer is known once the row `radius` below it is read. No copy of the
/// mask, no column-wise pass over it.
fn box_all(mask: &[bool], value: bool, width: usize, height: usize, radius: usize) -> Vec<bool> {
    let mut out = vec![false; mask.len()];
    if width == 0 || height == 0 {
        return out;
    }
    // Per column, how many rows up to the current one pass the horizontal test in a row.
    let mut up = vec![0u32; width];
    let mut run = vec![0u32; width];
    // The window of position `i` in a line of `n`, cut to it, as (start, end).
    let window = |i: usize, n: usize| (i.saturating_sub(radius), (i + radius).min(n - 1));
    let emit = |out: &mut [bool], up: &[u32], y: usize, e: usize| {
        let (s, _) = window(y, height);
        let need = (e - s + 1) as u32;
        for (o, &u) in out[y * width..(y + 1) * width].iter_mut().zip(up) {
            *o = u >= need;
        }
    };
    for e in 0..height {
        let row = &mask[e * width..(e + 1) * width];
        let mut length = 0u32;
        for (r, &v) in run.iter_mut().zip(row) {
            length = if v == value { length + 1 } else { 0 };
            *r = length;
        }
        for (x, u) in up.iter_mut().enumerate() {
            let (s, end) = window(x, width);
            let across = run[end] as usize > end - s;
            *u = if across { *u + 1 } else { 0 };
        }
        if e >= radius {
            emit(&mut out, &up, e - radius, e);
        }
    }
    // The last rows' windows end at the image's last row.
    for y in height.saturating_sub(radius)..height {
        emit(&mut out, &up, y, height - 1);
    }
    out
}

/// The groups of cells (each a list of cell indices) grown from the seeds: solid and dark-field
/// cells connected (4-connected) to a seed, and the dense cells beside them.
fn grow(cells: &[Cell], cols: usize, rows: usize) -> Vec<Vec<usize>> {
    let seedable = |c: usize| matches!(cells[c], Cell::Solid | Cell::DarkField | Cell::Texture);
    let carries = |c: usize| seedable(c) || cells[c] == Cell::Dots;
    let mut seed = vec![false; cells.len()];
    for y in 0..=rows - SEED_CELLS {
        for x in 0..=cols - SEED_CELLS {
            let all = (0..SEED_CELLS)
                .all(|dy| (0..SEED_CELLS).all(|dx| seedable((y + dy) * cols + x + dx)));
            if all {
                for dy in 0..SEED_CELLS {
                    for dx in 0..SEED_CELLS {
                        seed[(y + dy) * cols + x + dx] = true;
                    }
                }
            }
        }
    }
    // Along the image's edge a band of SEED_CELLS solid cells seeds too: a frame is thick ink
    // along the edge, however far it reaches in. Not dark fields: a band of them is the shade of
    // uneven light in a corner as often as the dark beyond a page, which is a field.
    let solid = |c: usize| cells[c] == Cell::Solid;
    for c in 0..cells.len() {
        let (x, y) = (c % cols, c / cols);
        let along_row = (y == 0 || y + 1 == rows) && x + SEED_CELLS <= cols;
        let along_col = (x == 0 || x + 1 == cols) && y + SEED_CELLS <= rows;
        if along_row && (0..SEED_CELLS).all(|d| solid(c + d)) {
            (0..SEED_CELLS).for_each(|d| seed[c + d] = true);
        }
        if along_col && (0..SEED_CELLS).all(|d| solid(c + d * cols)) {
            (0..SEED_CELLS).for_each(|d| seed[c + d * cols] = true);
        }
    }
    let mut taken = vec![false; cells.len()];
    let mut groups = Vec::new();
    for start in 0..cells.len() {
        if !seed[start] || taken[start] {
            continue;
        }
        taken[start] = true;
        let mut group = Vec::new();
        let mut stack = vec![start];
        while let Some(c) = stack.pop() {
            group.push(c);
            if !carries(c) {
                // A dense cell joins but does not carry the region further: a line of text
                // beside a photo is dense too.
                continue;
            }
            for n in neighbours(c, cols, rows) {
                if !taken[n] && cells[n] != Cell::Stroke {
                    taken[n] = true;
                    stack.push(n);
                }
            }
        }
        group.sort_unstable();
        groups.push(group);
    }
    groups
}

/// The groups with the halftones (those not on the grid's edge) made whole: a photo's light
/// parts hold open paper and its dark parts merged dots, so it can come as pieces, and the pieces
/// whose boxes come within a cell of each other are one photo; a photo inside a page is its box.
fn photos(groups: Vec<Vec<usize>>, cells: &[Cell], cols: usize, rows: usize) -> Vec<Vec<usize>> {
    let bounds = |group: &[usize]| {
        let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
        for &c in group {
            let (x, y) = (c % cols, c / cols);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
        [x0, y0, x1, y1]
    };
    let on_edge = |b: &[usize; 4]| b[0] == 0 || b[1] == 0 || b[2] + 1 == cols || b[3] + 1 == rows;
    let mut out = Vec::new();
    let mut boxes: Vec<[usize; 4]> = Vec::new();
    for group in groups {
        let b = bounds(&group);
        let textured = group.iter().filter(|&&c| cells[c] == Cell::Texture).count();
        if on_edge(&b) && (textured as f64) < TEXTURED_GROUP * group.len() as f64 {
            out.push(group);
        } else {
            boxes.push(b);
        }
    }
    // Merge boxes within a cell of each other until none are; each merge shrinks the list.
    let near = |a: &[usize; 4], b: &[usize; 4]| {
        a[0] <= b[2] + 2 && b[0] <= a[2] + 2 && a[1] <= b[3] + 2 && b[1] <= a[3] + 2
    };
    'merging: loop {
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if near(&boxes[i], &boxes[j]) {
                    let b = boxes.remove(j);
                    let a = &mut boxes[i];
                    *a = [
                        a[0].min(b[0]),
                        a[1].min(b[1]),
                        a[2].max(b[2]),
                        a[3].max(b[3]),
                    ];
                    continue 'merging;
                }
            }
        }
        break;
    }
    for [x0, y0, x1, y1] in boxes {
        out.push(
            (y0..=y1)
                .flat_map(|y| (x0..=x1).map(move |x| y * cols + x))
                .collect(),
        );
    }
    out.sort_by_key(|group| group[0]);
    out
}

/// The pixel image cut into cells.
struct Grid {
    width: usize,
    height: usize,
    cell: usize,
    cols: usize,
    rows: usize,
}

impl Grid {
    /// A `width` x `height` image cut into cells of `cell` px.
    fn new(width: usize, height: usize, cell: usize) -> Grid {
        Grid {
            width,
            height,
            cell,
            cols: width.div_ceil(cell),
            rows: height.div_ceil(cell),
        }
    }
}

/// A photo's cells (a box of them) grown by a row or column of cells at a time, while the cells
/// just outside a side, along at least half of it, hold ink of pieces (8-connected, `labels`)
/// that also lie within the box: the photo carried on past the cells that were classed as it
/// (its light parts, where the threshold left a few dots and open paper between them). A line of
/// text beside a photo does not run into it, and a stroke touching it is one piece at one place
/// along a side, not half of it.
///
/// A cell outside counts too when it is speckled: at least [`MIN_DOTS`] pieces of ink lie in it
/// that are each no larger than a stroke is wide squared (`w^2` pixels), the screen's last dots
/// where the photo's tone lightens towards its rim, each cut off from the dots within the box by
/// paper. A letter is several `w^2` (a stroke at least three widths long); a cell of text holds
/// at most a dot or two that small (an i's dot, a full stop), a dotted leader two.
fn grow_box(
    group: &[usize],
    labels: &[u32],
    sizes: &[usize],
    stroke_width: f64,
    grid: &Grid,
) -> Vec<usize> {
    let count = sizes.len();
    let speck = stroke_width * stroke_width;
    let Grid {
        width,
        height,
        cell,
        cols,
        rows,
    } = *grid;
    let (mut x0, mut y0, mut x1, mut y1) = (cols, rows, 0, 0);
    for &c in group {
        let (x, y) = (c % cols, c / cols);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    // Which pieces have a pixel within cells [cx0, cx1] x [cy0, cy1].
    let mut inside = vec![false; count];
    let mark = |inside: &mut [bool], [cx0, cy0, cx1, cy1]: [usize; 4]| {
        for y in cy0 * cell..((cy1 + 1) * cell).min(height) {
            let row = &labels[y * width..(y + 1) * width];
            for &l in &row[cx0 * cell..((cx1 + 1) * cell).min(width)] {
                if l > 0 {
                    inside[l as usize] = true;
                }
            }
        }
    };
    // Whether cell (cx, cy) holds a pixel of a piece inside.
    let holds = |inside: &[bool], cx: usize, cy: usize| {
        (cy * cell..((cy + 1) * cell).min(height)).any(|y| {
            let row = &labels[y * width..(y + 1) * width];
            row[cx * cell..((cx + 1) * cell).min(width)]
                .iter()
                .any(|&l| l > 0 && inside[l as usize])
        })
    };
    // Whether cell (cx, cy) holds at least MIN_DOTS specks (pieces of at most w^2 pixels).
    let speckled = |cx: usize, cy: usize| {
        let mut specks: Vec<u32> = Vec::new();
        for y in cy * cell..((cy + 1) * cell).min(height) {
            let row = &labels[y * width..(y + 1) * width];
            for &l in &row[cx * cell..((cx + 1) * cell).min(width)] {
                if l > 0 && sizes[l as usize] as f64 <= speck && !specks.contains(&l) {
                    specks.push(l);
                }
            }
        }
        specks.len() >= MIN_DOTS as usize
    };
    mark(&mut inside, [x0, y0, x1, y1]);
    loop {
        // The strips just outside each side, as cell boxes, and the side's length.
        let strips = [
            (x0 > 0).then(|| [x0 - 1, y0, x0 - 1, y1]),
            (x1 + 1 < cols).then(|| [x1 + 1, y0, x1 + 1, y1]),
            (y0 > 0).then(|| [x0, y0 - 1, x1, y0 - 1]),
            (y1 + 1 < rows).then(|| [x0, y1 + 1, x1, y1 + 1]),
        ];
        let mut grown = None;
        for (side, strip) in strips.iter().enumerate() {
            let Some([sx0, sy0, sx1, sy1]) = *strip else {
                continue;
            };
            let cells = (sx1 - sx0 + 1) * (sy1 - sy0 + 1);
            let held = (sy0..=sy1)
                .flat_map(|cy| (sx0..=sx1).map(move |cx| (cx, cy)))
                .filter(|&(cx, cy)| holds(&inside, cx, cy) || speckled(cx, cy))
                .count();
            if 2 * held >= cells {
                grown = Some((side, [sx0, sy0, sx1, sy1]));
                break;
            }
        }
        let Some((side, strip)) = grown else {
            break;
        };
        match side {
            0 => x0 -= 1,
            1 => x1 += 1,
            2 => y0 -= 1,
            _ => y1 += 1,
        }
        mark(&mut inside, strip);
    }
    (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| y * cols + x))
        .collect()
}

/// A group's kind and box (its cells' box, cut to the image).
fn describe(
    group: &[usize],
    cols: usize,
    rows: usize,
    cell: usize,
    width: usize,
    height: usize,
) -> Region {
    let (mut x0, mut y0, mut x1, mut y1) = (cols, rows, 0, 0);
    for &c in group {
        let (x, y) = (c % cols, c / cols);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    let on_edge = x0 == 0 || y0 == 0 || x1 + 1 == cols || y1 + 1 == rows;
    let (span_x, span_y) = (x1 - x0 + 1, y1 - y0 + 1);
    let fill = group.len() as f64 / (span_x * span_y) as f64;
    let around =
        span_x as f64 >= FRAME_SPAN * cols as f64 && span_y as f64 >= FRAME_SPAN * rows as f64;
    let kind = if !on_edge {
        RegionKind::Halftone
    } else if around && fill <= FRAME_FILL {
        RegionKind::Frame
    } else {
        RegionKind::PageEdge
    };
    let (px0, py0) = (x0 * cell, y0 * cell);
    let (px1, py1) = (((x1 + 1) * cell).min(width), ((y1 + 1) * cell).min(height));
    Region {
        kind,
        x: px0 as u32,
        y: py0 as u32,
        width: (px1 - px0) as u32,
        height: (py1 - py0) as u32,
    }
}

/// Removes the ink of the `removed` cells, then every piece of ink (8-connected) left wholly
/// within those cells and the cells beside them.
fn remove(ink: &mut [bool], grid: &Grid, removed: &[bool]) {
    if !removed.iter().any(|&r| r) {
        return;
    }
    let &Grid {
        width, cell, cols, ..
    } = grid;
    // Row by row, a cell's width of pixels at a time.
    for (y, row) in ink.chunks_mut(width).enumerate() {
        let cells = &removed[(y / cell) * cols..(y / cell + 1) * cols];
        for (pixels, &gone) in row.chunks_mut(cell).zip(cells) {
            if gone {
                pixels.fill(false);
            }
        }
    }
    remove_enclosed(ink, grid, removed);
}

/// Removes every piece of ink (8-connected) wholly within the `removed` cells and the cells
/// beside them.
fn remove_enclosed(ink: &mut [bool], grid: &Grid, removed: &[bool]) {
    let &Grid {
        width,
        height,
        cell,
        cols,
        rows,
    } = grid;
    let mut near = removed.to_vec();
    for y in 0..rows {
        for x in 0..cols {
            if removed[y * cols + x] {
                for ny in y.saturating_sub(1)..(y + 2).min(rows) {
                    for nx in x.saturating_sub(1)..(x + 2).min(cols) {
                        near[ny * cols + nx] = true;
                    }
                }
            }
        }
    }
    let (labels, sizes) = label_components(ink, width, height, true, Connectivity::Eight);
    let mut inside = vec![0usize; sizes.len()];
    for (y, row) in labels.chunks(width).enumerate() {
        let cells = &near[(y / cell) * cols..(y / cell + 1) * cols];
        for (pixels, &near) in row.chunks(cell).zip(cells) {
            if near {
                for &l in pixels {
                    if l > 0 {
                        inside[l as usize] += 1;
                    }
                }
            }
        }
    }
    for (v, &l) in ink.iter_mut().zip(&labels) {
        let l = l as usize;
        if l > 0 && inside[l] == sizes[l] {
            *v = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decisions::Decisions;
    use crate::params::Params;
    use image::{GrayImage, Luma};

    const PAPER: u8 = 230;
    const INK: u8 = 20;

    // The passes of [`texture_cells`], [`seed_possible`] and [`faint`] as they were written
    // before they ran by rows of cells in parallel (one pass over the rows, the texture's
    // histogram its own): the references the parallel passes are tested against, bit for bit.

    fn texture_cells_in_one_pass(
        gray: GrayView<'_>,
        dark_ink: bool,
        level: u8,
        stroke_width: f64,
        cell: usize,
    ) -> Vec<bool> {
        let (width, height) = (gray.width() as usize, gray.height() as usize);
        let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
        // Gray turned so that the ink is dark: ink at or below `cut`.
        let turn = |v: u8| if dark_ink { v } else { 255 - v };
        let cut = if dark_ink {
            level
        } else {
            254u8.saturating_sub(level)
        };
        let mut histogram = [0u64; 256];
        for y in 0..height {
            for &v in gray.row(y) {
                histogram[usize::from(turn(v))] += 1;
            }
        }
        let median_of = |range: std::ops::RangeInclusive<usize>| -> Option<f64> {
            let total: u64 = range.clone().map(|v| histogram[v]).sum();
            let mut seen = 0;
            for v in range {
                seen += histogram[v];
                if total > 0 && 2 * seen >= total {
                    return Some(v as f64);
                }
            }
            None
        };
        let (Some(ink_gray), Some(paper_gray)) = (
            median_of(0..=usize::from(cut)),
            median_of(usize::from(cut) + 1..=255),
        ) else {
            return vec![false; cols * rows];
        };
        let cut = f64::from(cut);
        let levels = [cut - (cut - ink_gray) / 2.0, cut + (paper_gray - cut) / 2.0];
        // Block means, each block `side` px square (cut to the image), at or below each level: the
        // blocks padded with a block of paper all round, so that the window at (x, y) is the padded
        // blocks (x, y) to (x + 1, y + 1). The sums are kept for one row of blocks at a time.
        let side = ((stroke_width / 2.0).floor() as usize).max(1);
        let (bw, bh) = (width.div_ceil(side), height.div_ceil(side));
        let pw = bw + 2;
        let mut padded = [vec![0u8; pw * (bh + 2)], vec![0u8; pw * (bh + 2)]];
        let mut sums = vec![0u32; bw];
        for by in 0..bh {
            sums.fill(0);
            let ys = by * side..((by + 1) * side).min(height);
            let block_rows = ys.len();
            for y in ys {
                for (sum, block) in sums.iter_mut().zip(gray.row(y).chunks(side)) {
                    *sum += block.iter().map(|&v| u32::from(turn(v))).sum::<u32>();
                }
            }
            let at = (by + 1) * pw + 1;
            for (b, &sum) in sums.iter().enumerate() {
                let size = (block_rows * (((b + 1) * side).min(width) - b * side)) as u32;
                let mean = f64::from(sum) / f64::from(size.max(1));
                for (padded, level) in padded.iter_mut().zip(levels) {
                    padded[at + b] = u8::from(mean <= level);
                }
            }
        }
        // The cell column of each window's first block (x is one more than the block's position).
        let cell_col: Vec<usize> = (0..=bw)
            .map(|x| ((x.max(1) - 1) * side / cell).min(cols - 1))
            .collect();
        let counts = padded.map(|padded| {
            let mut quads = vec![0i32; cols * rows];
            for y in 0..=bh {
                let cy = ((y.max(1) - 1) * side / cell).min(rows - 1);
                let (top, bottom) = (&padded[y * pw..(y + 1) * pw], &padded[(y + 1) * pw..]);
                for x in 0..=bw {
                    let quad = top[x] | top[x + 1] << 1 | bottom[x] << 2 | bottom[x + 1] << 3;
                    let value = match quad.count_ones() {
                        1 => 1,
                        3 => -1,
                        2 if quad == 0b1001 || quad == 0b0110 => -2,
                        _ => 0,
                    };
                    if value != 0 {
                        quads[cy * cols + cell_col[x]] += value;
                    }
                }
            }
            quads
        });
        (0..cols * rows)
            .map(|c| {
                let (a, b) = (counts[0][c], counts[1][c]);
                a.signum() == b.signum() && f64::from(a.abs().min(b.abs())) / 4.0 >= TEXTURE_PIECES
            })
            .collect()
    }

    fn seed_possible_in_one_pass(
        gray: GrayView<'_>,
        ink: &[bool],
        dark_ink: bool,
        level: u8,
        cell: usize,
        texture: &[bool],
    ) -> bool {
        let (width, height) = (gray.width() as usize, gray.height() as usize);
        let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
        // Ink, dark and all pixels per cell, a cell's width of pixels at a time.
        let mut counts = vec![[0u32; 3]; cols * rows];
        let is_dark = |v: u8| if dark_ink { v <= level } else { v > level };
        for y in 0..height {
            let base = (y / cell) * cols;
            let pieces = gray
                .row(y)
                .chunks(cell)
                .zip(ink[y * width..(y + 1) * width].chunks(cell));
            for (c, (row, ink)) in pieces.enumerate() {
                let counts = &mut counts[base + c];
                counts[0] += ink.iter().filter(|&&i| i).count() as u32;
                counts[1] += row.iter().filter(|&&v| is_dark(v)).count() as u32;
                counts[2] += row.len() as u32;
            }
        }
        seed_in_counts(&counts, cols, rows, texture)
    }

    /// [`faint`]'s parallel steps (the cells' sums, the histogram, the count of ink) done in one
    /// pass each, the shared steps called as it calls them.
    fn faint_in_one_pass(
        gray: GrayView<'_>,
        ink: &mut [bool],
        dark_ink: bool,
        stroke_width: f64,
        grounds: &[Ground],
        remove: bool,
    ) -> Option<Region> {
        let (width, height) = (gray.width() as usize, gray.height() as usize);
        if ink.len() != width * height || stroke_width < 1.0 || width == 0 || height == 0 {
            return None;
        }
        let cell = ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL);
        let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
        let turn = |v: u8| i32::from(if dark_ink { v } else { 255 - v });
        // The paper's mean gray (turned: ink dark) per cell, where a quarter of the cell is paper.
        let mut sums = vec![(0u64, 0u32, 0u32); cols * rows];
        for y in 0..height {
            let base = (y / cell) * cols;
            let cells = gray
                .row(y)
                .chunks(cell)
                .zip(ink[y * width..(y + 1) * width].chunks(cell));
            for (c, (row, ink)) in cells.enumerate() {
                let s = &mut sums[base + c];
                for (&v, &i) in row.iter().zip(ink) {
                    if !i {
                        s.0 += turn(v) as u64;
                        s.1 += 1;
                    }
                }
                s.2 += row.len() as u32;
            }
        }
        let paper = paper_means(&sums, cols, rows)?;
        let in_ground = |p: usize| {
            let (x, y) = ((p % width) as u32, (p / width) as u32);
            grounds
                .iter()
                .any(|g| (g.x..g.x + g.width).contains(&x) && (g.y..g.y + g.height).contains(&y))
        };
        let darkness = |p: usize| {
            paper[(p / width / cell) * cols + (p % width) / cell]
                - turn(gray.row(p / width)[p % width])
        };
        let mut histogram = [0u64; 511];
        let mut total = 0u64;
        for p in (0..ink.len()).filter(|&p| ink[p] && !in_ground(p)) {
            histogram[(darkness(p) + 255) as usize] += 1;
            total += 1;
        }
        let contrast = text_contrast(&histogram, total)?;
        let all_ink = ink.iter().filter(|&&i| i).count();
        faint_pieces(
            ink, width, height, &histogram, contrast, all_ink, in_ground, darkness, remove,
        )
    }

    /// A page of short strokes 3 px wide (letters' worth of bars on lines of text) within
    /// `[x0, x1) x [y0, y1)`, and whatever `paint` adds.
    fn page(
        width: u32,
        height: u32,
        text: [u32; 4],
        paint: impl Fn(u32, u32) -> Option<u8>,
    ) -> GrayImage {
        let [x0, y0, x1, y1] = text;
        GrayImage::from_fn(width, height, |x, y| {
            if let Some(v) = paint(x, y) {
                return Luma([v]);
            }
            let inside = (x0..x1).contains(&x) && (y0..y1).contains(&y);
            // Lines 24 px apart; in each, vertical bars 3 px wide 14 px tall every 9 px and a
            // bar across every fourth.
            let (lx, ly) = ((x - x0.min(x)) % 9, (y - y0.min(y)) % 24);
            let bar = lx < 3 && ly < 14;
            let across = (x - x0.min(x)) % 36 < 12 && (6..9).contains(&ly);
            Luma([if inside && (bar || across) {
                INK
            } else {
                PAPER
            }])
        })
    }

    fn decide(gray: &GrayImage, keep: &[RegionKind]) -> (crate::binary::Binary, Decisions) {
        decide_with(gray, keep, crate::params::Polarity::Auto)
    }

    fn decide_with(
        gray: &GrayImage,
        keep: &[RegionKind],
        polarity: crate::params::Polarity,
    ) -> (crate::binary::Binary, Decisions) {
        let mut params = Params::default();
        params.front_end.polarity = polarity;
        params.front_end.keep_regions = keep.to_vec();
        crate::raster::binarize_deciding(gray.into(), &params).expect("binarized")
    }

    fn kinds(decisions: &Decisions) -> Vec<RegionKind> {
        decisions.regions.iter().map(|r| r.kind).collect()
    }

    /// The square test as its definition says, pixel by pixel.
    fn box_all_by_definition(
        mask: &[bool],
        value: bool,
        width: usize,
        height: usize,
        radius: usize,
    ) -> Vec<bool> {
        (0..width * height)
            .map(|p| {
                let (x, y) = (p % width, p / width);
                let ys = y.saturating_sub(radius)..(y + radius + 1).min(height);
                ys.flat_map(|v| {
                    (x.saturating_sub(radius)..(x + radius + 1).min(width)).map(move |u| (u, v))
                })
                .all(|(u, v)| mask[v * width + u] == value)
            })
            .collect()
    }

    #[test]
    fn the_square_test_agrees_with_its_definition() {
        let mut rng = crate::test_rng::XorShift::new(0x2545_F491_4F6C_DD1D);
        for (width, height) in [(1, 1), (1, 9), (9, 1), (23, 17), (40, 3), (5, 31)] {
            for density in [0.05, 0.5, 0.9, 0.99] {
                let mask: Vec<bool> = (0..width * height).map(|_| rng.unit() <= density).collect();
                for radius in [0, 1, 2, 3, 7, 40] {
                    for value in [true, false] {
                        assert_eq!(
                            box_all(&mask, value, width, height, radius),
                            box_all_by_definition(&mask, value, width, height, radius),
                            "{width} x {height}, radius {radius}, value {value}, density {density}"
                        );
                    }
                }
            }
        }
    }

    /// The cells of the box `[x0, x1] x [y0, y1]` of an 8 x 8 grid, row-major.
    fn box_cells(x0: usize, y0: usize, x1: usize, y1: usize) -> Vec<usize> {
        (y0..=y1)
            .flat_map(|y| (x0..=x1).map(move |x| y * 8 + x))
            .collect()
    }

    #[test]
    fn a_photo_box_grows_where_its_pieces_run_on_and_not_for_one_stroke() {
        // A 64 x 64 image in cells of 8; the photo's box is cells 2..=4 x 2..=5 (x 16..40).
        let grid = Grid::new(64, 64, 8);
        let photo = box_cells(2, 2, 4, 5);
        let labels_of = |piece: &dyn Fn(usize, usize) -> bool| -> Vec<u32> {
            (0..64 * 64)
                .map(|p| u32::from(piece(p % 64, p / 64)))
                .collect()
        };
        let sizes_of = |labels: &[u32]| -> Vec<usize> {
            let mut sizes = vec![0; *labels.iter().max().unwrap_or(&0) as usize + 1];
            labels.iter().for_each(|&l| sizes[l as usize] += 1);
            sizes
        };
        let grow = |labels: &[u32]| grow_box(&photo, labels, &sizes_of(labels), 3.0, &grid);
        // Merged dots running 3 px past the box's right side all along it: one more column.
        let mesh = labels_of(&|x, y| (20..43).contains(&x) && (16..48).contains(&y));
        assert_eq!(grow(&mesh), box_cells(2, 2, 5, 5));
        // A stroke touching the box at one place along its side (a quarter of it): no growth.
        let stroke = labels_of(&|x, y| (36..60).contains(&x) && (18..21).contains(&y));
        assert_eq!(grow(&stroke), photo);
        // Ink beside the box that does not enter it (a line of text): no growth.
        let text = labels_of(&|x, y| (42..60).contains(&x) && (16..48).contains(&y));
        assert_eq!(grow(&text), photo);
        // Each its own piece: dots of `dot` px square on a 4 px screen in the column of cells
        // right of the box, `every` rows of dots out of 4 (the photo's light rim, cut off from
        // its dots inside by paper).
        let rim = |dot: usize, every: usize| -> Vec<u32> {
            (0..64 * 64)
                .map(|p| {
                    let (x, y) = (p % 64, p / 64);
                    let on = (40..48).contains(&x)
                        && (16..48).contains(&y)
                        && x % 4 < dot
                        && y % 4 < dot
                        && (y / 4) % 4 < every;
                    if on {
                        (1 + (y / 4) * 16 + x / 4) as u32
                    } else {
                        0
                    }
                })
                .collect()
        };
        // Specks of 4 px (under w^2 = 9), four to a cell: one more column.
        assert_eq!(grow(&rim(2, 4)), box_cells(2, 2, 5, 5));
        // Two specks to a cell (a dotted leader, an i's dot): no growth.
        assert_eq!(grow(&rim(2, 1)), photo);
        // Pieces of 16 px, larger than a speck (letters): no growth.
        let letters = rim(4, 4)
            .iter()
            .enumerate()
            .map(|(p, &l)| if (p % 64) % 8 < 4 { l } else { 0 })
            .collect::<Vec<u32>>();
        assert_eq!(grow(&letters), photo);
    }

    /// A page of text (ink 20 on paper 230) left of x = 160 and a net of faint lines (gray 205)
    /// `every` px apart both ways, 1 px wide, right of it (not touching the text, as a local
    /// threshold leaves paper around a dark stroke); the ink mask as a local threshold gives it:
    /// the text and the net.
    fn page_on_a_net(every: u32) -> (GrayImage, Vec<bool>) {
        let gray = page(320, 240, [20, 20, 150, 220], |x, y| {
            (x >= 160 && (x % every == 0 || y % every == 0)).then_some(205)
        });
        let text = page(320, 240, [20, 20, 150, 220], |_, _| None);
        let ink = gray
            .pixels()
            .zip(text.pixels())
            .map(|(g, t)| g.0[0] < 215 || t.0[0] == INK)
            .collect();
        (gray, ink)
    }

    #[test]
    fn a_net_of_faint_ink_that_is_most_of_the_ink_is_left_out_and_the_text_stays() {
        let (gray, mut ink) = page_on_a_net(4);
        let text: Vec<bool> = page(320, 240, [20, 20, 150, 220], |_, _| None)
            .pixels()
            .map(|p| p.0[0] == INK)
            .collect();
        let net = ink.iter().zip(&text).filter(|(&i, &t)| i && !t).count();
        let strokes = text.iter().filter(|&&t| t).count();
        assert!(
            net > strokes,
            "the net is most of the ink: {net} vs {strokes}"
        );
        let mut kept = ink.clone();
        let region = faint((&gray).into(), &mut ink, true, 3.0, &[], true);
        assert_eq!(region.map(|r| r.kind), Some(RegionKind::Faint));
        // Every stroke pixel stays; of the net, only what touches the strokes.
        assert!(text.iter().zip(&ink).all(|(&t, &i)| !t || i));
        let left = ink.iter().zip(&text).filter(|(&i, &t)| i && !t).count();
        assert!(left * 4 < net, "{left} of the net's {net} px left");
        // Kept when asked: the region is reported and no ink moves.
        let before = kept.clone();
        let region = faint((&gray).into(), &mut kept, true, 3.0, &[], false);
        assert_eq!(region.map(|r| r.kind), Some(RegionKind::Faint));
        assert_eq!(kept, before);
    }

    #[test]
    fn a_few_faint_lines_beside_the_text_stay() {
        // Lines 40 px apart: faint, but less of the ink than the text (ruled lines, a print's
        // lighter ridges).
        let (gray, mut ink) = page_on_a_net(40);
        let before = ink.clone();
        assert_eq!(faint((&gray).into(), &mut ink, true, 3.0, &[], true), None);
        assert_eq!(ink, before);
        // A page of text alone: nothing.
        let text = page(320, 240, [20, 20, 300, 220], |_, _| None);
        let mut ink: Vec<bool> = text.pixels().map(|p| p.0[0] == INK).collect();
        assert_eq!(faint((&text).into(), &mut ink, true, 3.0, &[], true), None);
    }

    #[test]
    fn a_page_of_text_has_no_region() {
        let gray = page(320, 240, [20, 20, 300, 220], |_, _| None);
        let (_, decisions) = decide(&gray, &[]);
        assert!(decisions.regions.is_empty(), "{:?}", decisions.regions);
    }

    #[test]
    fn a_halftone_photo_is_found_and_left_out_and_kept_when_asked() {
        // Dots on a 4 px screen, growing across the photo until they merge.
        let photo = |x: u32, y: u32| {
            let inside = (180..300).contains(&x) && (30..210).contains(&y);
            inside.then(|| {
                let r = 0.8 + 2.2 * f64::from(x - 180) / 120.0;
                let (dx, dy) = (f64::from(x % 4) - 1.5, f64::from(y % 4) - 1.5);
                if dx.hypot(dy) <= r {
                    INK
                } else {
                    PAPER
                }
            })
        };
        let gray = page(320, 240, [20, 20, 160, 220], photo);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Halftone]);
        let r = decisions.regions[0];
        // The photo's dark part at least (its light dots, far from the merged ones, are not
        // reached: dotted cells carry a region but do not seed one).
        assert!(r.x <= 250 && r.x + r.width >= 290, "{r:?}");
        // At most half of the photo's ink left (its dark part gone); the text all there.
        let ink_in = |b: &crate::binary::Binary, x0: u32, x1: u32| {
            (0..240)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| b.ink[(y * 320 + x) as usize])
                .count()
        };
        let (kept, _) = decide(&gray, &[RegionKind::Halftone]);
        assert!(ink_in(&binary, 180, 300) * 2 < ink_in(&kept, 180, 300));
        let clean = decide(&page(320, 240, [20, 20, 160, 220], |_, _| None), &[]).0;
        assert_eq!(ink_in(&binary, 0, 170), ink_in(&clean, 0, 170));
        let (_, decisions) = decide(&gray, &[RegionKind::Halftone]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Halftone]);
        assert!(ink_in(&kept, 180, 300) > 5000);
    }

    /// Ink pixels of `binary` within the columns `[x0, x1)`.
    fn ink_between(binary: &crate::binary::Binary, x0: u32, x1: u32) -> usize {
        (0..binary.height)
            .flat_map(|y| (x0..x1).map(move |x| (x, y)))
            .filter(|&(x, y)| binary.ink[(y * binary.width + x) as usize])
            .count()
    }

    #[test]
    fn a_grille_behind_the_text_is_found_and_left_out() {
        // Two families of bars 2 px wide, 5 and 7 px apart, crossing: a lattice of small holes
        // whose bars are thinner than the text's strokes.
        let grille = |x: u32, y: u32| {
            let inside = (180..300).contains(&x) && (20..220).contains(&y);
            inside.then_some(if (x + y) % 5 < 2 || (x + 480 - y) % 7 < 2 {
                50
            } else {
                PAPER
            })
        };
        let gray = page(320, 240, [20, 20, 160, 220], grille);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(
            kinds(&decisions),
            vec![RegionKind::Halftone],
            "{:?}",
            decisions.regions
        );
        let r = decisions.regions[0];
        assert!(r.x <= 190 && r.x + r.width >= 290, "{r:?}");
        assert!(ink_between(&binary, 180, 300) < 200, "the grille is gone");
        // The text is all there.
        let clean = decide(&page(320, 240, [20, 20, 160, 220], |_, _| None), &[]).0;
        assert_eq!(ink_between(&binary, 0, 170), ink_between(&clean, 0, 170));
        let (kept, _) = decide(&gray, &[RegionKind::Halftone]);
        assert!(ink_between(&kept, 180, 300) > 5000);
    }

    #[test]
    fn a_light_halftone_of_separate_dots_is_found() {
        // Dots 2 px across on a 4 px screen, paper between them: a light tone, no dot merged.
        let photo = |x: u32, y: u32| {
            let inside = (180..300).contains(&x) && (30..210).contains(&y);
            inside.then_some(if x % 4 < 2 && y % 4 < 2 { INK } else { PAPER })
        };
        let gray = page(320, 240, [20, 20, 160, 220], photo);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Halftone]);
        assert!(ink_between(&binary, 180, 300) < 100, "the dots are gone");
    }

    #[test]
    fn a_print_with_pores_is_no_texture() {
        // Ridges 8 px wide 16 px apart over the whole image, each with a pore of 2 x 2 px every
        // 6 px: many holes per cell, but finer than half a ridge.
        let gray = GrayImage::from_fn(320, 240, |x, y| {
            let ridge = (x + y / 3) % 16 < 8;
            let pore = (x + y / 3) % 16 >= 3 && (x + y / 3) % 16 < 5 && y % 6 < 2;
            Luma([if ridge && !pore { INK } else { PAPER }])
        });
        let (_, decisions) = decide(&gray, &[]);
        assert!(decisions.regions.is_empty(), "{:?}", decisions.regions);
    }

    /// The parallel passes give what the one-pass versions gave, bit for bit: the texture
    /// cells, the seed test, the faint ink's region and the ink it leaves, on pages of text,
    /// halftones, nets and noise of odd sizes (cells cut at the edges), both polarities, several
    /// stroke widths and levels, with and without reversed grounds.
    #[test]
    fn the_passes_by_rows_of_cells_equal_the_passes_in_one() {
        let mut next = crate::synth::lcg(32);
        let mut pages: Vec<GrayImage> = Vec::new();
        for (width, height) in [(320, 240), (301, 187), (97, 403)] {
            let text = [10, 12, width - 15, height - 9];
            pages.push(page(width, height, text, |_, _| None));
            pages.push(page(width, height, text, |x, y| {
                (x > width / 2 && x % 4 < 2 && y % 4 < 2).then_some(INK)
            }));
            pages.push(page(width, height, text, |x, y| {
                (x > width / 2 && (x % 4 == 0 || y % 4 == 0)).then_some(205)
            }));
            let noise: Vec<u8> = (0..width * height).map(|_| (next() >> 33) as u8).collect();
            pages.push(GrayImage::from_raw(width, height, noise).expect("size"));
            let dark = page(width, height, text, |x, y| {
                (y < height / 3 && x < width / 2).then_some(INK)
            });
            pages.push(dark);
        }
        for gray in &pages {
            let view: GrayView<'_> = gray.into();
            let histogram = super::super::binarize::histogram(view);
            let (width, height) = (gray.width(), gray.height());
            for level in [60u8, 128, 215] {
                let ink_dark: Vec<bool> = gray.pixels().map(|p| p.0[0] <= level).collect();
                for dark_ink in [true, false] {
                    let ink: Vec<bool> = ink_dark.iter().map(|&d| d == dark_ink).collect();
                    for stroke_width in [1.0, 2.6, 3.0, 4.0, 5.5, 7.0, 9.0] {
                        let cell = ((CELL_WIDTHS * stroke_width).round() as usize).max(MIN_CELL);
                        let texture = texture_cells(
                            view,
                            &histogram,
                            dark_ink,
                            level,
                            stroke_width,
                            cell,
                            &|_| true,
                        );
                        let before =
                            texture_cells_in_one_pass(view, dark_ink, level, stroke_width, cell);
                        assert_eq!(texture, before);
                        // The rows looked at alone: theirs as in the whole, the others textures.
                        let sampled = |cy: usize| cy % SEED_CELLS == SEED_CELLS - 1;
                        let some = texture_cells(
                            view,
                            &histogram,
                            dark_ink,
                            level,
                            stroke_width,
                            cell,
                            &sampled,
                        );
                        let cols = (width as usize).div_ceil(cell);
                        for (c, (&some, &all)) in some.iter().zip(&texture).enumerate() {
                            assert_eq!(some, all || !sampled(c / cols));
                        }
                        assert_eq!(
                            seed_possible(view, &ink, dark_ink, level, cell, &texture),
                            seed_possible_in_one_pass(view, &ink, dark_ink, level, cell, &texture)
                        );
                        let ground = Ground {
                            x: width / 3,
                            y: height / 4,
                            width: width / 4,
                            height: height / 3,
                        };
                        for grounds in [&[][..], &[ground][..]] {
                            for remove in [true, false] {
                                let (mut a, mut b) = (ink.clone(), ink.clone());
                                let region =
                                    faint(view, &mut a, dark_ink, stroke_width, grounds, remove);
                                let one_pass = faint_in_one_pass(
                                    view,
                                    &mut b,
                                    dark_ink,
                                    stroke_width,
                                    grounds,
                                    remove,
                                );
                                assert_eq!(region, one_pass);
                                assert_eq!(a, b);
                            }
                        }
                    }
                }
            }
        }
    }

    /// The largest sum whose `f64` mean is at or below a level is the bound of the sums tested
    /// one by one: every sum of random block sizes (1 to 40 x 40 px) against levels on and
    /// between whole levels, below 0 and above 255.
    #[test]
    fn the_largest_sum_at_or_below_a_level_bounds_the_means_tested_one_by_one() {
        let mut next = crate::synth::lcg(1976u64);
        let mut rand = move |n: u64| (next() >> 33) % n;
        for case in 0..400 {
            let size = 1 + rand(1600) as u32;
            let level = match case % 5 {
                0 => rand(256) as f64,
                1 => rand(256) as f64 + 0.5,
                2 => -1.0,
                3 => 255.0 + rand(2) as f64,
                _ => rand(25_600) as f64 / 100.0,
            };
            let limit = largest_sum_at_or_below(size, level);
            for sum in 0..=255 * size {
                let mean = f64::from(sum) / f64::from(size);
                assert_eq!(
                    i64::from(sum) <= limit,
                    mean <= level,
                    "size {size} level {level} sum {sum}"
                );
            }
        }
    }

    /// The Euler shares by arithmetic are Gray's bit quads (the rule as written before), and a
    /// row of cells' sums of them the sums window by window, on random blocks and cell sizes.
    #[test]
    fn the_euler_quads_by_columns_of_cells_equal_the_quads_window_by_window() {
        for quad in 0u8..16 {
            let bits = [quad & 1, quad >> 1 & 1, quad >> 2 & 1, quad >> 3 & 1];
            let want = match quad.count_ones() {
                1 => 1,
                3 => -1,
                2 if quad == 0b1001 || quad == 0b0110 => -2,
                _ => 0,
            };
            assert_eq!(
                quad_euler(bits[0], bits[1], bits[2], bits[3]),
                want,
                "{quad:04b}"
            );
        }
        let mut next = crate::synth::lcg(1975u64);
        let mut rand = move |n: usize| (next() >> 33) as usize % n;
        for _ in 0..300 {
            let (bw, bh) = (1 + rand(80), 1 + rand(60));
            let (side, cell) = (1 + rand(3), 8 + rand(12));
            let (width, height) = (bw * side - rand(side), bh * side - rand(side));
            let (cols, rows) = (width.div_ceil(cell), height.div_ceil(cell));
            let pw = bw + 2;
            let density = 1 + rand(9);
            let mut padded = vec![0u8; pw * (bh + 2)];
            for y in 1..=bh {
                for x in 1..=bw {
                    padded[y * pw + x] = u8::from(rand(10) < density);
                }
            }
            let cell_col = window_cells(bw, side, cell, cols);
            let cell_row = window_cells(bh, side, cell, rows);
            let mut want = vec![0i32; cols * rows];
            for y in 0..=bh {
                for x in 0..=bw {
                    let (top, bottom) = (&padded[y * pw..], &padded[(y + 1) * pw..]);
                    let quad = top[x] | top[x + 1] << 1 | bottom[x] << 2 | bottom[x + 1] << 3;
                    want[cell_row[y] * cols + cell_col[x]] += match quad.count_ones() {
                        1 => 1,
                        3 => -1,
                        2 if quad == 0b1001 || quad == 0b0110 => -2,
                        _ => 0,
                    };
                }
            }
            assert_eq!(
                euler_quads(&padded, bw, &cell_col, &cell_row, (cols, rows), &|_| true),
                want
            );
        }
    }

    #[test]
    fn a_page_of_text_ends_the_search_early() {
        let text = page(320, 240, [20, 20, 300, 220], |_, _| None);
        let (binary, _) = decide(&text, &[]);
        let view: GrayView<'_> = (&text).into();
        let histogram = super::super::binarize::histogram(view);
        let texture = texture_cells(view, &histogram, true, 128, 3.0, 12, &|_| true);
        assert!(texture.iter().all(|&t| !t));
        assert!(!seed_possible(view, &binary.ink, true, 128, 12, &texture));
        // A dark block 40 px square could seed.
        let block = page(320, 240, [20, 20, 300, 220], |x, y| {
            ((100..140).contains(&x) && (100..140).contains(&y)).then_some(INK)
        });
        let (binary, _) = decide(&block, &[]);
        let view: GrayView<'_> = (&block).into();
        assert!(seed_possible(view, &binary.ink, true, 128, 12, &texture));
    }

    #[test]
    fn a_frame_is_found_and_a_stroke_touching_it_stays() {
        // A dark band 12 px wide around the image (less ink than the text, whose strokes give
        // the page's width); a bar 3 px wide from the text to the frame.
        let frame = |x: u32, y: u32| {
            let d = x.min(y).min(479 - x).min(359 - y);
            if d < 12 || ((118..121).contains(&y) && x >= 440) {
                Some(INK)
            } else {
                None
            }
        };
        let gray = page(480, 360, [40, 40, 440, 320], frame);
        let (binary, decisions) = decide(&gray, &[]);
        let found = kinds(&decisions);
        assert_eq!(found, vec![RegionKind::Frame], "{:?}", decisions.regions);
        let at = |x: u32, y: u32| binary.ink[(y * 480 + x) as usize];
        assert!(!at(5, 5) && !at(475, 120), "the frame is gone");
        // The bar stays up to within a cell of the frame.
        assert!((440..450).all(|x| at(x, 119)), "the touching stroke stays");
        let (kept, decisions) = decide(&gray, &found);
        assert_eq!(kinds(&decisions), found);
        assert!(kept.ink[5 * 480 + 5]);
    }

    #[test]
    fn a_ring_of_lines_around_the_text_goes_with_what_lies_along_and_beyond_it() {
        // The edges of a bound book's pages: a line 2 px wide along the top and another down
        // the right, joined; a second line along the bottom, apart; a speck between the right
        // line and the image's edge. The text inside stays whole.
        let line = |x: u32, y: u32| {
            let top = (20..22).contains(&y) && x <= 470;
            let right = (436..438).contains(&x) && (20..=340).contains(&y);
            let bottom = (330..332).contains(&y) && x <= 400;
            let speck = (449..452).contains(&x) && (199..202).contains(&y);
            (top || right || bottom || speck).then_some(INK)
        };
        let text = [60, 60, 420, 300];
        let gray = page(480, 360, text, line);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(
            kinds(&decisions),
            vec![RegionKind::Frame],
            "{:?}",
            decisions.regions
        );
        let at = |x: u32, y: u32| binary.ink[(y * 480 + x) as usize];
        assert!(!at(200, 20) && !at(436, 200), "the ring is gone");
        assert!(!at(200, 330), "the line along it is gone");
        assert!(!at(450, 200), "the speck beyond it is gone");
        let (clean, _) = decide(&page(480, 360, text, |_, _| None), &[]);
        assert_eq!(binary.ink, clean.ink, "the text is whole");
        let (kept, decisions) = decide(&gray, &[RegionKind::Frame]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Frame]);
        assert!(kept.ink[20 * 480 + 200] && kept.ink[200 * 480 + 450]);
    }

    #[test]
    fn the_specks_between_a_ring_and_the_text_go_and_a_full_stop_stays() {
        // A ring of lines 2 px wide around the text, 80 px out from it on the right; a column
        // of specks 2 px square every 10 px, 25 px inside the right line (the dirt along a
        // book's edge); a full stop 4 px after the text's last stroke.
        let ring = |x: u32, y: u32| {
            let (xs, ys) = ((20..=460).contains(&x), (20..=340).contains(&y));
            let lines = (ys && ((20..22).contains(&x) || (456..458).contains(&x)))
                || (xs && ((20..22).contains(&y) || (338..340).contains(&y)));
            let column = (430..432).contains(&x) && (40..320).contains(&y) && y % 10 < 2;
            let stop = (381..383).contains(&x) && (70..72).contains(&y);
            (lines || column || stop).then_some(INK)
        };
        let text = [60, 60, 380, 300];
        let gray = page(480, 360, text, ring);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Frame]);
        let at = |b: &crate::binary::Binary, x: u32, y: u32| b.ink[(y * 480 + x) as usize];
        assert!(
            (40..320).all(|y| !at(&binary, 430, y)),
            "the column of specks is gone"
        );
        assert!(at(&binary, 381, 70), "the full stop stays");
        let (clean, _) = decide(&page(480, 360, text, |_, _| None), &[]);
        let text_ink = |b: &crate::binary::Binary| ink_between(b, 0, 380);
        assert_eq!(text_ink(&binary), text_ink(&clean), "the text is whole");
        // Kept when asked.
        let (kept, _) = decide(&gray, &[RegionKind::Frame]);
        assert!(at(&kept, 430, 40) && at(&kept, 430, 310));
        // Text reaching into the band keeps its strokes and a dot above its last one.
        let ring_and_dot = |x: u32, y: u32| {
            let (xs, ys) = ((20..=460).contains(&x), (20..=340).contains(&y));
            let lines = (ys && ((20..22).contains(&x) || (456..458).contains(&x)))
                || (xs && ((20..22).contains(&y) || (338..340).contains(&y)));
            let dot = (438..440).contains(&x) && (56..58).contains(&y);
            (lines || dot).then_some(INK)
        };
        let text = [60, 60, 441, 300];
        let (binary, decisions) = decide(&page(480, 360, text, ring_and_dot), &[]);
        assert_eq!(kinds(&decisions), vec![RegionKind::Frame]);
        let (clean, _) = decide(&page(480, 360, text, |_, _| None), &[]);
        assert_eq!(
            ink_between(&binary, 40, 441),
            ink_between(&clean, 40, 441) + 4
        );
        assert!(at(&binary, 438, 56), "the dot stays");
    }

    #[test]
    fn a_long_run_is_found_by_its_looks_as_by_a_pass() {
        let mut seed = 17u64;
        for len in [1, 2, 3, 7, 40, 97] {
            for density in [10, 60, 90, 99] {
                let row: Vec<bool> = (0..len)
                    .map(|_| {
                        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                        (seed >> 33) % 100 < density
                    })
                    .collect();
                for long in 1..=len + 1 {
                    let mut run = 0;
                    let by_pass = row.iter().any(|&i| {
                        run = if i { run + 1 } else { 0 };
                        run >= long
                    });
                    assert_eq!(has_run(&row, long), by_pass, "{row:?} {long}");
                }
            }
        }
    }

    #[test]
    fn a_rectangle_drawn_on_its_own_is_a_stroke() {
        // A rectangle 3 px wide spanning most of the image, nothing inside: the drawing itself.
        let gray = GrayImage::from_fn(400, 300, |x, y| {
            let (dx, dy) = (x.abs_diff(200), y.abs_diff(150));
            let on =
                (dx <= 170 && (120..123).contains(&dy)) || (dy <= 122 && (168..171).contains(&dx));
            Luma([if on { INK } else { PAPER }])
        });
        let (binary, decisions) = decide(&gray, &[]);
        assert!(decisions.regions.is_empty(), "{:?}", decisions.regions);
        assert!(binary.ink[30 * 400 + 200], "the rectangle stays");
    }

    #[test]
    fn smudged_ridges_reaching_the_edge_are_no_page_edge() {
        // Bands of ink 10 px thick with 2 px of paper between them, from the text to the
        // image's right edge: an over-inked print's ridges, solid cells with paper showing.
        let ridges = |x: u32, y: u32| (x >= 276 && y < 120 && y % 12 < 10).then_some(INK);
        let gray = page(320, 240, [20, 20, 180, 220], ridges);
        let (binary, decisions) = decide(&gray, &[]);
        assert!(decisions.regions.is_empty(), "{:?}", decisions.regions);
        assert!(binary.ink[5 * 320 + 300], "the ridges stay ink");
    }

    #[test]
    fn a_dark_field_beyond_a_torn_edge_is_a_page_edge_and_a_shadow_is_none() {
        let edge = |x: u32, y: u32| (x >= 250 + (y / 7) % 5).then_some(40);
        let gray = page(320, 240, [20, 20, 220, 220], edge);
        let (binary, decisions) = decide(&gray, &[]);
        assert_eq!(kinds(&decisions), vec![RegionKind::PageEdge]);
        assert!((0..240).all(|y| (262..320).all(|x| !binary.ink[(y * 320 + x) as usize])));
        // The same darkness reached gradually, as uneven light does, is no edge.
        let text = page(320, 240, [20, 20, 300, 220], |_, _| None);
        let gray = GrayImage::from_fn(320, 240, |x, y| {
            let t = (f64::from(x) / 320.0).powi(2);
            let base = f64::from(text.get_pixel(x, y).0[0]);
            Luma([(base * (1.0 - 0.75 * t)).round() as u8])
        });
        let (_, decisions) = decide(&gray, &[]);
        assert!(decisions.regions.is_empty(), "{:?}", decisions.regions);
    }
}
