//! Thinning, a raster operation: the ink's specks filled ([`fill_specks_at`]), Zhang-Suen's
//! skeleton ([`zhang_suen`]) made one pixel thick ([`one_pixel_thick_framed_at`]), and a dot put back for
//! every component thinning erased; one component at a time over its own box
//! ([`skeleton_by_component`]). docs/design.md, "Skeleton-carried geometry", first point.

use crate::csr::Csr;

/// Offsets of the 8 neighbours in the order P2..P9 of Zhang and Suen (N, NE, E, SE, S, SW, W, NW).
pub(super) const RING: [(i64, i64); 8] = [
    (0, -1),
    (1, -1),
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
];

/// For each sub-iteration of [`zhang_suen`], whether a pixel whose 8 neighbours are the bits of
/// the index (bit k: [`RING`]`[k]`, P2..P9) goes: 2-6 ink neighbours, one 0->1 transition
/// around them, and not kept by the sub-iteration's condition (P4 P6 (P2 + P8), then P2 P8
/// (P4 + P6)). Made once at compile time, not for every component thinned.
const DELETED: [[bool; 256]; 2] = deletion_table();

const fn deletion_table() -> [[bool; 256]; 2] {
    let mut table = [[false; 256]; 2];
    let mut n = 0;
    while n < 256 {
        let (mut b, mut a, mut k) = (0, 0, 0);
        while k < 8 {
            if bit(n, k) {
                b += 1;
            }
            if !bit(n, k) && bit(n, k + 1) {
                a += 1;
            }
            k += 1;
        }
        let deletable = b >= 2 && b <= 6 && a == 1;
        table[0][n] = deletable && !(bit(n, 2) && bit(n, 4) && (bit(n, 0) || bit(n, 6)));
        table[1][n] = deletable && !(bit(n, 0) && bit(n, 6) && (bit(n, 2) || bit(n, 4)));
        n += 1;
    }
    table
}

/// Whether the neighbourhood `n` has neighbour `k` (mod 8) on.
const fn bit(n: usize, k: usize) -> bool {
    n & (1 << (k % 8)) != 0
}

/// Zhang & Suen (1984), "A fast parallel algorithm for thinning digital patterns": two
/// sub-iterations, each deleting in parallel the boundary pixels with 2-6 neighbours, one 0->1
/// transition around them, and (south-east | north-west) boundary conditions, until stable. The
/// skeleton keeps the ink's connectivity and holes.
pub(super) fn zhang_suen(ink: &[bool], width: usize, height: usize) -> Vec<bool> {
    // A copy with a one-pixel background border, so every neighbour is an index offset.
    let pw = width + 2;
    let mut padded = vec![false; pw * (height + 2)];
    for y in 0..height {
        padded[(y + 1) * pw + 1..(y + 1) * pw + 1 + width]
            .copy_from_slice(&ink[y * width..(y + 1) * width]);
    }
    zhang_suen_framed(&mut padded, pw);
    let mut thin = vec![false; width * height];
    for y in 0..height {
        thin[y * width..(y + 1) * width]
            .copy_from_slice(&padded[(y + 1) * pw + 1..(y + 1) * pw + 1 + width]);
    }
    thin
}

/// [`zhang_suen`] in place on a `width`-wide grid whose first and last rows and columns are
/// background (so every neighbour of an ink pixel is an index offset).
fn zhang_suen_framed(padded: &mut [bool], width: usize) {
    let ink: Vec<usize> = padded
        .iter()
        .enumerate()
        .filter_map(|(i, &on)| on.then_some(i))
        .collect();
    zhang_suen_framed_at(padded, width, &ink, &mut ThinningMarks::default());
}

/// The 8 neighbours of pixel `i` of a `width`-wide grid as the bits of a byte (bit k:
/// [`RING`]`[k]`, P2..P9), `i` not on the grid's first or last row or column. Read as the three
/// rows of the 3 x 3 block around `i` (one bounds check for the block, where one per neighbour
/// cost most of the thinning: docs/performance.md).
// Always inlined: the thinning reads it for every ink pixel, and a call there costs a
// tenth of the thinning (docs/performance.md, "Session of 2026-12-06, third").
#[inline(always)]
pub(super) fn neighbourhood(grid: &[bool], width: usize, i: usize) -> u8 {
    let block = &grid[i - width - 1..i + width + 2];
    let (above, row, below) = (
        &block[..3],
        &block[width..width + 3],
        &block[2 * width..2 * width + 3],
    );
    u8::from(above[1])
        | u8::from(above[2]) << 1
        | u8::from(row[2]) << 2
        | u8::from(below[2]) << 3
        | u8::from(below[1]) << 4
        | u8::from(below[0]) << 5
        | u8::from(row[0]) << 6
        | u8::from(above[0]) << 7
}

/// The marks [`zhang_suen_framed_at`] keeps per pixel of its grid, kept from one grid to the next
/// (the components of a window, [`skeleton_by_component`]) instead of a zeroed pair of arrays per
/// grid: clear (false, 0) between calls, where only the ink pixels were ever marked.
#[derive(Default)]
struct ThinningMarks {
    /// Whether the pixel is among the candidates.
    queued: Vec<bool>,
    /// The sub-iteration the pixel was last (re)queued in.
    since: Vec<u32>,
    /// An ink pixel's [`neighbourhood`], kept up to date as its neighbours go (written for every
    /// ink pixel of a grid before it is read, so never cleared).
    code: Vec<u8>,
}

/// [`zhang_suen_framed`] given the grid's ink pixels (`ink`: every one of them, each once, in
/// any order), so that nothing but the ink is visited: the deletions of a sub-iteration are
/// decided together, so the order of the pixels does not change the result.
fn zhang_suen_framed_at(
    padded: &mut [bool],
    width: usize,
    ink: &[usize],
    marks: &mut ThinningMarks,
) {
    let pw = width as isize;
    let offsets: [isize; 8] = RING.map(|(dx, dy)| dy as isize * pw + dx as isize);
    // The 8 neighbours as the bits of a byte (bit k: RING[k]), and for each sub-iteration a
    // table of the neighbourhoods whose center goes.
    let table = &DELETED;
    // Only a pixel with a background neighbour can go; after a sub-iteration only the
    // neighbours of what went can newly have one. Checking just those gives the same result as
    // checking every ink pixel each time, in a time that grows with the ink, not with the ink
    // times the stroke width.
    // A pixel whose neighbourhood has not changed since both sub-iterations checked it cannot
    // go until a neighbour goes: `since` is the sub-iteration it was (re)queued in.
    // Each ink pixel's neighbourhood is read once and then kept (`code`): a pixel that goes
    // clears its bit in each ink neighbour's, where reading the 8 neighbours again at every check
    // cost most of the thinning (docs/performance.md).
    if marks.queued.len() < padded.len() {
        marks.queued.resize(padded.len(), false);
        marks.since.resize(padded.len(), 0);
        marks.code.resize(padded.len(), 0);
    }
    let (queued, since, code) = (&mut marks.queued, &mut marks.since, &mut marks.code);
    for &i in ink {
        code[i] = neighbourhood(padded, width, i);
    }
    let mut candidates: Vec<usize> = ink
        .iter()
        .copied()
        .filter(|&i| code[i] != u8::MAX)
        .collect();
    for &i in &candidates {
        queued[i] = true;
    }
    let mut marked = Vec::new();
    let mut idle = 0;
    let mut step = 0;
    let mut t = 0u32;
    // Stable when two sub-iterations in a row delete nothing.
    while idle < 2 {
        marked.clear();
        marked.extend(
            candidates
                .iter()
                .copied()
                .filter(|&i| table[step][code[i] as usize]),
        );
        for &i in &marked {
            padded[i] = false;
            queued[i] = false;
        }
        idle = if marked.is_empty() { idle + 1 } else { 0 };
        // The next candidates: those checked once since their neighbourhood last changed (the
        // other sub-iteration may delete them) and the ink neighbours of every deleted pixel.
        candidates.retain(|&i| {
            let keep = padded[i] && since[i] == t;
            if !keep {
                queued[i] = false;
            }
            keep
        });
        for &i in &marked {
            for (k, offset) in offsets.into_iter().enumerate() {
                let j = (i as isize + offset) as usize;
                if padded[j] {
                    // `i` is `j`'s neighbour on the opposite side, RING[k + 4].
                    code[j] &= !(1u8 << ((k + 4) % 8));
                    since[j] = t + 1;
                    if !queued[j] {
                        queued[j] = true;
                        candidates.push(j);
                    }
                }
            }
        }
        step = 1 - step;
        t += 1;
    }
    // Only ink pixels were marked: clear for the next grid.
    for &i in ink {
        queued[i] = false;
        since[i] = 0;
    }
}

/// The scratch of [`zhang_suen_bits`], kept from one component's box to the next.
#[derive(Default)]
struct BitGrid {
    /// The grid a bit a pixel, `width.div_ceil(64)` words a row: bit `x % 64` of a row's word
    /// `x / 64` is column `x`.
    bits: Vec<u64>,
    /// For each word, the last sub-iteration that is to decide it: the second after the last
    /// change among it and its eight neighbouring words.
    until: Vec<u32>,
    /// For each row, the last sub-iteration that is to decide any of its words.
    rows_until: Vec<u32>,
    /// A sub-iteration's deletions: row, word, and the word's pixels that go.
    gone: Vec<(usize, usize, u64)>,
}

/// [`zhang_suen_framed_at`] 64 pixels at a time: the grid (`width` wide, its first and last rows
/// and columns background; `ink` every ink pixel, in raster order) is packed a bit a pixel, and
/// a sub-iteration decides a word of a row at once from the grid as it was before it (its
/// deletions are decided together, then made). The same conditions as [`DELETED`], bit-sliced:
/// the neighbours P2..P9 are the row words shifted by one column, "two or more" of eight flags
/// is kept as a running pair of words (seen once, seen twice), one 0->1 transition is "at least
/// one and not two", 2-6 ink neighbours "two ink and two background". A sweep skips the words
/// without ink, and a word none of whose eight neighbouring words (nor itself) changed since
/// both sub-iterations last decided it: decided on the same pixels, it would lose none (the
/// pixel queue's rule, a word at a time).
fn zhang_suen_bits(padded: &mut [bool], width: usize, ink: &[usize], grid: &mut BitGrid) {
    let height = padded.len() / width;
    let words = width.div_ceil(64);
    let BitGrid {
        bits,
        until,
        rows_until,
        gone,
    } = grid;
    bits.clear();
    bits.resize(words * height, 0);
    until.clear();
    until.resize(words * height, 1);
    rows_until.clear();
    rows_until.resize(height, 1);
    for (y, x) in rows_and_columns(ink, width) {
        bits[y * words + x / 64] |= 1 << (x % 64);
    }
    // Two flags of a word or more among `flags`.
    let twice = |flags: [u64; 8]| {
        let (mut once, mut twice) = (0u64, 0u64);
        for f in flags {
            twice |= once & f;
            once |= f;
        }
        (once, twice)
    };
    let (mut step, mut idle, mut t) = (0, 0, 0u32);
    // Stable when two sub-iterations in a row delete nothing.
    while idle < 2 {
        gone.clear();
        for y in 1..height.saturating_sub(1) {
            if rows_until[y] < t {
                continue;
            }
            let (above, row, below) = (
                &bits[(y - 1) * words..y * words],
                &bits[y * words..(y + 1) * words],
                &bits[(y + 1) * words..(y + 2) * words],
            );
            for k in 0..words {
                let c = row[k];
                if c == 0 || until[y * words + k] < t {
                    continue;
                }
                // Column x's neighbour at x + 1 (east) and x - 1 (west), across the words.
                let east = |v: &[u64]| (v[k] >> 1) | v.get(k + 1).map_or(0, |&n| n << 63);
                let west = |v: &[u64]| (v[k] << 1) | if k > 0 { v[k - 1] >> 63 } else { 0 };
                // P2..P9: N, NE, E, SE, S, SW, W, NW (RING's order).
                let p = [
                    above[k],
                    east(above),
                    east(row),
                    east(below),
                    below[k],
                    west(below),
                    west(row),
                    west(above),
                ];
                let rises: [u64; 8] = std::array::from_fn(|j| !p[j] & p[(j + 1) % 8]);
                let (one_rise, two_rises) = twice(rises);
                // 2-6 ink neighbours: the count's bits say "two or more" (2, 4 or 8 set)
                // and "seven or eight" (8, or 4, 2 and 1 set).
                let [b0, b1, b2, b3] = ink_count(p);
                let two_ink = b1 | b2 | b3;
                let two_background = !(b3 | (b2 & b1 & b0));
                let kept = if step == 0 {
                    p[2] & p[4] & (p[0] | p[6])
                } else {
                    p[0] & p[6] & (p[2] | p[4])
                };
                let going = c & one_rise & !two_rises & two_ink & two_background & !kept;
                if going != 0 {
                    gone.push((y, k, going));
                }
            }
        }
        idle = if gone.is_empty() { idle + 1 } else { 0 };
        for &(y, k, going) in gone.iter() {
            bits[y * words + k] &= !going;
            rows_until[y - 1..=y + 1].fill(t + 2);
            for first in [y - 1, y, y + 1].map(|r| r * words) {
                until[first + k.saturating_sub(1)..first + (k + 2).min(words)].fill(t + 2);
            }
            let mut rest = going;
            while rest != 0 {
                padded[y * width + k * 64 + rest.trailing_zeros() as usize] = false;
                rest &= rest - 1;
            }
        }
        step = 1 - step;
        t += 1;
    }
}

/// How many of the eight flags are set, 64 pixels at a time: bit `j` of the count's plane
/// `b` is bit `b` of the number of the words whose bit `j` is set (0 to 8), from a tree of
/// full adders (a sum and a carry of three flags each).
fn ink_count(p: [u64; 8]) -> [u64; 4] {
    let full = |a: u64, b: u64, c: u64| {
        let t = a ^ b;
        (t ^ c, (a & b) | (t & c))
    };
    // Ones: p0..p7 = s3 + p7 + 2 (c1 + c2 + c3).
    let (s1, c1) = full(p[0], p[1], p[2]);
    let (s2, c2) = full(p[3], p[4], p[5]);
    let (s3, c3) = full(s1, s2, p[6]);
    let (b0, c4) = (s3 ^ p[7], s3 & p[7]);
    // Twos: c1 + c2 + c3 + c4 = b1 + 2 (d1 + d2).
    let (t1, d1) = full(c1, c2, c3);
    let (b1, d2) = (t1 ^ c4, t1 & c4);
    [b0, b1, d1 ^ d2, d1 & d2]
}

/// The one-pixel skeleton of a window's ink (`ink`, every component's pixels), every component
/// kept: [`fill_specks_at`] (the filled specks written into `ink`), [`zhang_suen`],
/// [`one_pixel_thick_framed_at`], and for a component thinning erased whole (a 2 x 2 block, a
/// short 2-pixel-thick diagonal) its deepest pixel by `half` (ties: the first in raster order),
/// a dot.
///
/// Each step reads a pixel's 8 neighbours only, and two 8-connected components are never
/// neighbours (a speck's enclosing ink is one component), so each component is thinned alone, in
/// a copy of its own bounding box with a background frame: the result is the whole window's,
/// pixel for pixel, in a time that grows with the ink and not with the window (a chunk's window
/// holds many times its ink on a text page). The components' pixels (window indices, rising) are
/// given in CSR form: component `c` is `members[offsets[c]..offsets[c + 1]]`. Returns the
/// skeleton's pixels in raster order and each one's skeleton neighbours (bit k for
/// [`RING`]`[k]`), read in its component's box: no other component's skeleton neighbours it,
/// so they are the window's, and nothing the window's size is made.
pub(super) fn skeleton_by_component(
    ink: &mut [bool],
    width: usize,
    offsets: &[usize],
    members: &[usize],
    half: impl Fn(usize) -> f32,
) -> (Vec<usize>, Vec<u8>) {
    // Each pixel above its neighbours' byte: sorted, raster order.
    let mut skeleton_pixels: Vec<u64> = Vec::new();
    let (mut local, mut filled, mut thin) = (Vec::new(), Vec::new(), Vec::new());
    let mut candidates = Vec::new();
    let mut grid = BitGrid::default();
    for c in offsets.windows(2) {
        let pixels = &members[c[0]..c[1]];
        let (Some(&first), Some(&last)) = (pixels.first(), pixels.last()) else {
            continue;
        };
        let (y0, y1) = (first / width, last / width);
        let (x0, x1) = rows_and_columns(pixels, width)
            .fold((usize::MAX, 0), |(lo, hi), (_, x)| (lo.min(x), hi.max(x)));
        // The box with a one-pixel background frame; `to_window` maps its pixels back.
        let (lw, lh) = (x1 - x0 + 3, y1 - y0 + 3);
        let to_window = |j: usize| (j / lw + y0 - 1) * width + (j % lw + x0 - 1);
        // Each step below visits the component's own pixels (in the box's raster order), not
        // the whole box, which a long ridge of a print makes many times its ink.
        local.clear();
        local.resize(lw * lh, false);
        filled.clear();
        filled
            .extend(rows_and_columns(pixels, width).map(|(y, x)| (y - y0 + 1) * lw + (x - x0 + 1)));
        for &j in &filled {
            local[j] = true;
        }
        let specks = fill_specks_at(&mut local, lw, lh, &filled);
        // The component's ink with its specks: its own pixels (ink already) and the filled
        // specks'.
        for &j in &specks {
            ink[to_window(j)] = true;
        }
        if !specks.is_empty() {
            filled.extend(specks);
            filled.sort_unstable();
            filled.dedup();
        }
        zhang_suen_bits(&mut local, lw, &filled, &mut grid);
        thin.clear();
        thin.extend(filled.iter().copied().filter(|&j| local[j]));
        candidates.clone_from(&thin);
        one_pixel_thick_framed_at(&mut local, lw, &mut candidates);
        let mut kept = false;
        // `thin` rises (a part of `filled`), so its rows come one division a row.
        let survivors = thin.iter().copied().filter(|&j| local[j]);
        for (j, (y, x)) in survivors.clone().zip(rows_and_columns_of(survivors, lw)) {
            let i = (y + y0 - 1) * width + (x + x0 - 1);
            let code = neighbourhood(&local, lw, j);
            skeleton_pixels.push(((i as u64) << 8) | u64::from(code));
            kept = true;
        }
        if !kept {
            // The component's ink with its specks, in raster order.
            if let Some(deepest) = filled
                .iter()
                .map(|&j| to_window(j))
                .max_by(|&a, &b| half(a).total_cmp(&half(b)).then(b.cmp(&a)))
            {
                // Alone in its component: no skeleton neighbours.
                skeleton_pixels.push((deepest as u64) << 8);
            }
        }
    }
    // Raster order: a counting sort by row (each component's pixels already rise, so a row's
    // pixels rise within each component that crosses it), then each row that several
    // components cross sorted on its own. Each pixel is listed once, so this is the order
    // `sort_unstable` gives.
    let rows = ink.len() / width.max(1);
    let mut by_row = Csr::build(rows, |sink| {
        for &p in &skeleton_pixels {
            sink.push((p >> 8) as usize / width, p);
        }
    });
    if by_row.values().len() == skeleton_pixels.len() {
        for row in 0..rows {
            let pixels = by_row.row_mut(row);
            if !pixels.is_sorted() {
                pixels.sort_unstable();
            }
        }
        skeleton_pixels = by_row.values;
    } else {
        // A pixel outside the window (never): the whole list sorted instead.
        skeleton_pixels.sort_unstable();
    }
    skeleton_pixels
        .iter()
        .map(|&p| ((p >> 8) as usize, p as u8))
        .unzip()
}

/// The row and column of each of `pixels` (indices into rows `width` long), one division per
/// row rather than per pixel when they rise (a component's pixels in raster order); any order
/// gives the same pairs.
fn rows_and_columns(pixels: &[usize], width: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
    rows_and_columns_of(pixels.iter().copied(), width)
}

/// [`rows_and_columns`] of the indices `pixels` yields.
fn rows_and_columns_of(
    pixels: impl Iterator<Item = usize>,
    width: usize,
) -> impl Iterator<Item = (usize, usize)> {
    // The row of the last pixel and the index where it starts (none yet: a start past every
    // index, so that the first pixel divides).
    let (mut row, mut start) = (0, usize::MAX);
    pixels.map(move |i| {
        if i < start || i - start >= width {
            row = i / width;
            start = row * width;
        }
        (row, i - start)
    })
}

/// Zhang-Suen can leave runs two pixels thick (a 45 degree staircase, an L-shaped step) whose
/// pixels all have three or more skeleton neighbours, so the graph would make one junction of the
/// whole run. Removes, in raster order until none is left, every skeleton pixel that is simple
/// (its removal changes neither the skeleton's 8-connectivity nor its holes: Yokoi's
/// 8-connectivity number is 1) and is no tip: it has three or more skeleton neighbours, or two
/// that make it the inner corner of an L. Ends, the middle pixels of one-pixel lines and the
/// centers of real junctions are not simple. The whole grid scanned for its pixels: the tests'
/// reference for [`one_pixel_thick_framed_at`], which the thinning uses.
#[cfg(test)]
pub(super) fn one_pixel_thick(skeleton: &mut [bool], width: usize, height: usize) {
    let candidates: Vec<usize> = skeleton
        .iter()
        .enumerate()
        .filter_map(|(i, &on)| on.then_some(i))
        .collect();
    one_pixel_thick_at(skeleton, width, height, candidates);
}

/// [`one_pixel_thick`] given the skeleton's pixels (`candidates`: every one of them, each once,
/// in raster order, the order the removals are made in). The tests' reference for
/// [`one_pixel_thick_framed_at`], which the thinning uses.
#[cfg(test)]
fn one_pixel_thick_at(
    skeleton: &mut [bool],
    width: usize,
    height: usize,
    mut candidates: Vec<usize>,
) {
    let (w, h) = (width as i64, height as i64);
    let on =
        |s: &[bool], x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && s[(y * w + x) as usize];
    // Neighbours counter-clockwise from east: E, NE, N, NW, W, SW, S, SE.
    const AROUND: [(i64, i64); 8] = [
        (1, 0),
        (1, -1),
        (0, -1),
        (-1, -1),
        (-1, 0),
        (-1, 1),
        (0, 1),
        (1, 1),
    ];
    loop {
        let mut changed = false;
        for &i in &candidates {
            if !skeleton[i] {
                continue;
            }
            let (x, y) = ((i as i64) % w, (i as i64) / w);
            let n: [bool; 8] =
                std::array::from_fn(|k| on(skeleton, x + AROUND[k].0, y + AROUND[k].1));
            // Two neighbours: only the inner corner of an L step (both of them 4-neighbours)
            // goes; two neighbours side by side are the tip of a run, which removing would
            // shorten (the run would be eaten away from its end).
            match n.iter().filter(|&&v| v).count() {
                0 | 1 => continue,
                2 if (0..8).step_by(2).filter(|&k| n[k]).count() != 2 => continue,
                _ => {}
            }
            // Yokoi: C8 = sum over k in {0, 2, 4, 6} of x'k - x'k x'k+1 x'k+2, x' = not x.
            let c8: i32 = (0..4)
                .map(|j| {
                    let k = 2 * j;
                    let (a, b, c) = (!n[k], !n[k + 1], !n[(k + 2) % 8]);
                    i32::from(a) - i32::from(a && b && c)
                })
                .sum();
            if c8 == 1 {
                skeleton[i] = false;
                changed = true;
            }
        }
        if !changed {
            return;
        }
        candidates.retain(|&i| skeleton[i]);
    }
}

/// For a skeleton pixel whose 8 neighbours are the bits of the index (bit k: [`RING`]`[k]`, as
/// [`neighbourhood`] reads them), whether [`one_pixel_thick_framed_at`] removes it: three or more
/// neighbours, or two that are both 4-neighbours (the inner corner of an L), and Yokoi's
/// 8-connectivity number 1. Made once at compile time.
const THINNED: [bool; 256] = thinned_table();

const fn thinned_table() -> [bool; 256] {
    let mut table = [false; 256];
    let mut n = 0;
    while n < 256 {
        // Counter-clockwise from east (E, NE, N, NW, W, SW, S, SE): neighbour k is RING's
        // (2 - k) mod 8.
        let mut around = [false; 8];
        let mut k = 0;
        while k < 8 {
            around[k] = bit(n, 10 - k);
            k += 1;
        }
        let (mut count, mut fours, mut c8) = (0, 0, 0i32);
        k = 0;
        while k < 8 {
            if around[k] {
                count += 1;
                if k % 2 == 0 {
                    fours += 1;
                }
            }
            k += 1;
        }
        // Yokoi: C8 = sum over k in {0, 2, 4, 6} of x'k - x'k x'k+1 x'k+2, x' = not x.
        k = 0;
        while k < 8 {
            let (a, b, c) = (!around[k], !around[k + 1], !around[(k + 2) % 8]);
            if a {
                c8 += 1;
                if b && c {
                    c8 -= 1;
                }
            }
            k += 2;
        }
        table[n] = count >= 2 && (count != 2 || fours == 2) && c8 == 1;
        n += 1;
    }
    table
}

/// [`one_pixel_thick`] on a `width`-wide grid whose first and last rows and columns are
/// background, given the skeleton's pixels (`candidates`: every one of them, each once, in raster
/// order, the order the removals are made in; left holding those that stay): each pixel's
/// neighbourhood read as one byte ([`neighbourhood`]) and decided by the table [`THINNED`], the
/// same decisions [`one_pixel_thick_at`] makes neighbour by neighbour.
fn one_pixel_thick_framed_at(skeleton: &mut [bool], width: usize, candidates: &mut Vec<usize>) {
    loop {
        let mut changed = false;
        for &i in candidates.iter() {
            if skeleton[i] && THINNED[neighbourhood(skeleton, width, i) as usize] {
                skeleton[i] = false;
                changed = true;
            }
        }
        if !changed {
            return;
        }
        candidates.retain(|&i| skeleton[i]);
    }
}

/// Background specks of at most 3 pixels enclosed by ink (a sharp meeting of two strokes or a
/// rendering gap; the noise the dropout test counts, `mask::tiny_hole`) are not holes: filled,
/// so the skeleton makes no cycle around them. The whole grid scanned: the tests' reference for
/// [`fill_specks_at`], which the thinning uses.
#[cfg(test)]
pub(super) fn fill_specks(ink: &mut [bool], w: usize, h: usize) {
    if w < 3 || h < 3 {
        return;
    }
    let mut specks = Vec::new();
    for i in w..ink.len() - w {
        if !ink[i] && ink[i - 1] {
            if let Some((pixels, len)) = crate::mask::tiny_hole_pixels_at(ink, w, h, i) {
                specks.extend_from_slice(&pixels[..len]);
            }
        }
    }
    for p in specks {
        ink[p] = true;
    }
}

/// [`fill_specks`] given the ink's pixels (`pixels`: every one of them, in raster order): a
/// speck is looked for right of each ink pixel only, as [`fill_specks`] looks at each
/// background pixel right of ink, in the same order. Returns the pixels filled (one may be
/// listed more than once).
fn fill_specks_at(ink: &mut [bool], w: usize, h: usize, pixels: &[usize]) -> Vec<usize> {
    let mut specks = Vec::new();
    if w < 3 || h < 3 {
        return specks;
    }
    for &p in pixels {
        let i = p + 1;
        if i >= w && i < ink.len() - w && !ink[i] {
            if let Some((pixels, len)) = crate::mask::tiny_hole_pixels_at(ink, w, h, i) {
                specks.extend_from_slice(&pixels[..len]);
            }
        }
    }
    for &p in &specks {
        ink[p] = true;
    }
    specks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::{render, Stroke};

    /// The compile-time table equals Zhang and Suen's conditions written out per neighbourhood
    /// (the table each thinning used to build).
    #[test]
    fn deletion_table_matches_the_conditions() {
        for (step, table) in DELETED.iter().enumerate() {
            for (n, &got) in table.iter().enumerate() {
                let p: [bool; 8] = std::array::from_fn(|k| n & (1 << k) != 0);
                let b = p.iter().filter(|&&v| v).count();
                let a = (0..8).filter(|&k| !p[k] && p[(k + 1) % 8]).count();
                let keep = if step == 0 {
                    p[2] && p[4] && (p[0] || p[6])
                } else {
                    p[0] && p[6] && (p[2] || p[4])
                };
                let deleted = (2..=6).contains(&b) && a == 1 && !keep;
                assert_eq!(got, deleted, "step {step}, neighbourhood {n:08b}");
            }
        }
        assert!(DELETED[0].iter().any(|&d| d) && DELETED[1].iter().any(|&d| !d));
    }

    #[test]
    fn thinning_by_component_equals_thinning_the_whole_window() {
        // A ring around a dot, an X, a thick bar with specks punched into it, a 2 x 2 block
        // (erased whole by Zhang-Suen) and a short thick diagonal, in one window: some boxes
        // overlap others.
        let ring: Vec<[f64; 2]> = (0..=48)
            .map(|k| {
                let a = k as f64 / 48.0 * std::f64::consts::TAU;
                [30.0 + 18.0 * a.cos(), 30.0 + 18.0 * a.sin()]
            })
            .collect();
        let mut binary = render(
            &[
                Stroke::new(ring, 4.0),
                Stroke::new(vec![[29.0, 29.0], [31.0, 31.0]], 3.0),
                Stroke::new(vec![[60.0, 10.0], [90.0, 40.0]], 5.0),
                Stroke::new(vec![[60.0, 40.0], [90.0, 10.0]], 5.0),
                Stroke::new(vec![[10.0, 70.0], [90.0, 70.0]], 9.0),
                Stroke::new(vec![[70.0, 85.0], [74.0, 89.0]], 2.0),
            ],
            100,
            100,
        );
        let (w, h) = (100usize, 100usize);
        for (x, y) in [(20, 70), (40, 70), (41, 70), (60, 69), (60, 70)] {
            binary.ink[y * w + x] = false;
        }
        for (x, y) in [(5, 90), (6, 90), (5, 91), (6, 91)] {
            binary.ink[y * w + x] = true;
        }
        // The components (8-connected), each pixel list rising.
        let mut label = vec![usize::MAX; w * h];
        let mut components: Vec<Vec<usize>> = Vec::new();
        for start in 0..w * h {
            if !binary.ink[start] || label[start] != usize::MAX {
                continue;
            }
            let mut members = vec![start];
            label[start] = components.len();
            let mut next = 0;
            while next < members.len() {
                let (x, y) = ((members[next] % w) as i64, (members[next] / w) as i64);
                next += 1;
                for (dx, dy) in RING {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    if binary.ink[j] && label[j] == usize::MAX {
                        label[j] = components.len();
                        members.push(j);
                    }
                }
            }
            members.sort_unstable();
            components.push(members);
        }
        assert!(components.len() >= 5, "{} components", components.len());
        let half = |i: usize| {
            if binary.ink[i] {
                1.0 + (i % 7) as f32
            } else {
                0.0
            }
        };

        // The whole window: specks, Zhang-Suen, one pixel thick, a dot for an erased component.
        let mut whole_ink = binary.ink.clone();
        fill_specks(&mut whole_ink, w, h);
        let mut whole = zhang_suen(&whole_ink, w, h);
        one_pixel_thick(&mut whole, w, h);
        let mut erased = 0;
        for members in &components {
            if members.iter().all(|&i| !whole[i]) {
                let deepest = members
                    .iter()
                    .copied()
                    .max_by(|&a, &b| half(a).total_cmp(&half(b)).then(b.cmp(&a)))
                    .expect("a component has pixels");
                whole[deepest] = true;
                erased += 1;
            }
        }
        assert!(erased >= 1, "the 2 x 2 block is erased by Zhang-Suen");
        assert_ne!(whole_ink, binary.ink, "specks were filled");

        let mut offsets = vec![0];
        let mut members = Vec::new();
        for component in &components {
            members.extend_from_slice(component);
            offsets.push(members.len());
        }
        let mut ink = binary.ink.clone();
        let (pixels, codes) = skeleton_by_component(&mut ink, w, &offsets, &members, half);
        assert_eq!(ink, whole_ink);
        let listed: Vec<usize> = (0..w * h).filter(|&i| whole[i]).collect();
        assert_eq!(pixels, listed);
        // Each pixel's neighbours, read from the whole window's skeleton.
        let read: Vec<u8> = listed
            .iter()
            .map(|&i| {
                let (x, y) = ((i % w) as i64, (i / w) as i64);
                RING.iter().enumerate().fold(0u8, |code, (k, &(dx, dy))| {
                    let (a, b) = (x + dx, y + dy);
                    let on = a >= 0
                        && b >= 0
                        && a < w as i64
                        && b < h as i64
                        && whole[b as usize * w + a as usize];
                    code | u8::from(on) << k
                })
            })
            .collect();
        assert_eq!(codes, read);
        assert!(codes.iter().any(|&c| c.count_ones() >= 3), "a junction");
    }

    #[test]
    fn rows_and_columns_equal_the_divisions() {
        // Rising runs with gaps of whole rows, as a component's pixels come, and then the same
        // indices shuffled: each pair is the quotient and the remainder.
        let mut lcg = crate::synth::lcg(4242u64);
        let mut next = move || (lcg() >> 33) as usize;
        for width in [1, 2, 3, 7, 64, 1000] {
            let mut pixels = Vec::new();
            let mut i = next() % (3 * width);
            for _ in 0..400 {
                pixels.push(i);
                i += 1 + match next() % 4 {
                    0 => next() % 3,
                    1 => width * (next() % 3),
                    2 => next() % (2 * width + 1),
                    _ => 0,
                };
            }
            let expected: Vec<(usize, usize)> =
                pixels.iter().map(|&i| (i / width, i % width)).collect();
            assert_eq!(
                rows_and_columns(&pixels, width).collect::<Vec<_>>(),
                expected
            );
            for k in (1..pixels.len()).rev() {
                pixels.swap(k, next() % (k + 1));
            }
            let expected: Vec<(usize, usize)> =
                pixels.iter().map(|&i| (i / width, i % width)).collect();
            assert_eq!(
                rows_and_columns(&pixels, width).collect::<Vec<_>>(),
                expected
            );
        }
    }

    #[test]
    fn the_steps_given_the_ink_equal_the_steps_over_the_grid() {
        // Pseudo-random specks and blobs (a fixed linear congruential sequence) in framed grids:
        // filling specks, Zhang-Suen and one pixel thick given the ink's list give what the
        // scans of the whole grid give.
        let mut lcg = crate::synth::lcg(777u64);
        let mut next = move || (lcg() >> 33) as usize;
        for (w, h, density) in [(23, 17, 2), (40, 31, 3), (9, 50, 4), (3, 3, 2), (60, 44, 5)] {
            let mut grid = vec![false; w * h];
            for y in 1..h - 1 {
                for x in 1..w - 1 {
                    grid[y * w + x] = next() % density != 0;
                }
            }
            let list = |g: &[bool]| -> Vec<usize> { (0..g.len()).filter(|&i| g[i]).collect() };
            let (mut by_scan, mut by_list) = (grid.clone(), grid.clone());
            fill_specks(&mut by_scan, w, h);
            let specks = fill_specks_at(&mut by_list, w, h, &list(&grid));
            assert_eq!(by_scan, by_list);
            assert!(specks.iter().all(|&p| !grid[p] && by_list[p]));
            let ink = list(&by_list);
            zhang_suen_framed(&mut by_scan, w);
            // The list in another order: the result does not depend on it.
            let reversed: Vec<usize> = ink.iter().rev().copied().collect();
            zhang_suen_framed_at(&mut by_list, w, &reversed, &mut ThinningMarks::default());
            assert_eq!(by_scan, by_list);
            one_pixel_thick(&mut by_scan, w, h);
            let thin = list(&by_list);
            one_pixel_thick_at(&mut by_list, w, h, thin);
            assert_eq!(by_scan, by_list);
        }
    }

    #[test]
    fn the_ink_count_counts_every_pattern() {
        // Bit j of the words: the eight neighbours of pattern j, for all 256 patterns in
        // four groups of 64.
        for group in 0..4u64 {
            let p: [u64; 8] = std::array::from_fn(|k| {
                (0..64u64).fold(0, |word, j| word | (((group * 64 + j) >> k & 1) << j))
            });
            let planes = ink_count(p);
            for j in 0..64u64 {
                let count = (0..4).fold(0, |n, b| n | ((planes[b] >> j & 1) << b));
                assert_eq!(count, u64::from((group * 64 + j).count_ones()));
            }
        }
    }

    #[test]
    fn thinning_a_word_at_a_time_equals_thinning_a_pixel_at_a_time() {
        // Pseudo-random blobs and bars in framed grids narrower and wider than a word (rows of
        // one to four words, ink across the words' edges), and a fixed grid reused: the same
        // pixels stay.
        let mut lcg = crate::synth::lcg(6464u64);
        let mut next = move || (lcg() >> 33) as usize;
        let mut grid = BitGrid::default();
        let mut stayed = 0;
        for (w, h) in [
            (5, 5),
            (23, 17),
            (64, 9),
            (65, 20),
            (66, 31),
            (130, 40),
            (200, 25),
        ] {
            for density in [2, 3, 5] {
                let mut ink = vec![false; w * h];
                // Random pixels, then thick bars and blobs, some across word edges.
                for y in 1..h - 1 {
                    for x in 1..w - 1 {
                        ink[y * w + x] = next() % density == 0;
                    }
                }
                for _ in 0..(w * h / 60).max(1) {
                    let (cx, cy, r) = (next() % w, next() % h, 1 + next() % 6);
                    for y in cy.saturating_sub(r).max(1)..(cy + r).min(h - 1) {
                        for x in cx.saturating_sub(2 * r).max(1)..(cx + 2 * r).min(w - 1) {
                            ink[y * w + x] = true;
                        }
                    }
                }
                let list: Vec<usize> = (0..w * h).filter(|&i| ink[i]).collect();
                let (mut by_pixel, mut by_word) = (ink.clone(), ink.clone());
                zhang_suen_framed(&mut by_pixel, w);
                zhang_suen_bits(&mut by_word, w, &list, &mut grid);
                assert_eq!(by_pixel, by_word, "{w} x {h}, 1 in {density}");
                stayed += by_word.iter().filter(|&&on| on).count();
            }
        }
        assert!(stayed > 1000, "{stayed}");
    }

    /// [`zhang_suen_framed_at`] reading every candidate's neighbourhood from the grid at each
    /// check, as it did before it kept them ([`ThinningMarks::code`]).
    fn zhang_suen_framed_at_reading(padded: &mut [bool], width: usize, ink: &[usize]) {
        let pw = width as isize;
        let offsets: [isize; 8] = RING.map(|(dx, dy)| dy as isize * pw + dx as isize);
        let bits = |grid: &[bool], i: usize| neighbourhood(grid, width, i);
        let table = &DELETED;
        let mut queued = vec![false; padded.len()];
        let mut since = vec![0u32; padded.len()];
        let mut candidates: Vec<usize> = ink
            .iter()
            .copied()
            .filter(|&i| bits(padded, i) != u8::MAX)
            .collect();
        for &i in &candidates {
            queued[i] = true;
        }
        let mut marked = Vec::new();
        let (mut idle, mut step, mut t) = (0, 0, 0u32);
        while idle < 2 {
            marked.clear();
            marked.extend(
                candidates
                    .iter()
                    .copied()
                    .filter(|&i| table[step][bits(padded, i) as usize]),
            );
            for &i in &marked {
                padded[i] = false;
                queued[i] = false;
            }
            idle = if marked.is_empty() { idle + 1 } else { 0 };
            candidates.retain(|&i| {
                let keep = padded[i] && since[i] == t;
                if !keep {
                    queued[i] = false;
                }
                keep
            });
            for &i in &marked {
                for offset in offsets {
                    let j = (i as isize + offset) as usize;
                    if padded[j] {
                        since[j] = t + 1;
                        if !queued[j] {
                            queued[j] = true;
                            candidates.push(j);
                        }
                    }
                }
            }
            step = 1 - step;
            t += 1;
        }
    }

    #[test]
    fn thinning_with_kept_neighbourhoods_equals_reading_them() {
        // Random framed grids of several densities and sizes, thinned one after another with
        // the same marks (as the components of a window are), against reading the grid.
        let mut lcg = crate::synth::lcg(31337u64);
        let mut next = move || (lcg() >> 33) as usize;
        let mut marks = ThinningMarks::default();
        let mut deleted = 0;
        for (w, h, density) in [
            (40, 31, 3),
            (3, 3, 2),
            (23, 17, 2),
            (9, 50, 4),
            (60, 44, 5),
            (33, 33, 8),
            (12, 70, 6),
        ] {
            let mut grid = vec![false; w * h];
            for y in 1..h - 1 {
                for x in 1..w - 1 {
                    grid[y * w + x] = next() % density != 0;
                }
            }
            let ink: Vec<usize> = (0..w * h).filter(|&i| grid[i]).collect();
            let (mut reading, mut keeping) = (grid.clone(), grid.clone());
            zhang_suen_framed_at_reading(&mut reading, w, &ink);
            zhang_suen_framed_at(&mut keeping, w, &ink, &mut marks);
            assert_eq!(reading, keeping, "{w} x {h}, density {density}");
            deleted += ink.iter().filter(|&&i| !keeping[i]).count();
        }
        assert!(deleted > 1000, "{deleted} pixels deleted");
    }

    /// The neighbourhood byte one neighbour at a time, as the thinning read it before
    /// [`neighbourhood`].
    fn neighbourhood_by_offsets(grid: &[bool], width: usize, i: usize) -> u8 {
        let offsets: [isize; 8] = RING.map(|(dx, dy)| dy as isize * width as isize + dx as isize);
        (0..8).fold(0u8, |b, k| {
            b | (u8::from(grid[(i as isize + offsets[k]) as usize]) << k)
        })
    }

    #[test]
    fn the_neighbourhood_byte_equals_the_neighbours_one_at_a_time() {
        let mut lcg = crate::synth::lcg(4242u64);
        let mut next = move || (lcg() >> 33) as usize;
        for (w, h, density) in [(3, 3, 2), (4, 7, 2), (23, 17, 3), (64, 5, 5), (9, 50, 4)] {
            let grid: Vec<bool> = (0..w * h).map(|_| next() % density != 0).collect();
            for y in 1..h - 1 {
                for x in 1..w - 1 {
                    let i = y * w + x;
                    assert_eq!(
                        neighbourhood(&grid, w, i),
                        neighbourhood_by_offsets(&grid, w, i),
                        "{w} x {h}, pixel ({x}, {y})"
                    );
                }
            }
        }
        // Every neighbourhood, around the middle of a 3 x 3 grid.
        for n in 0..256usize {
            let mut grid = vec![false; 9];
            for (k, (dx, dy)) in RING.iter().enumerate() {
                grid[((1 + dy) * 3 + 1 + dx) as usize] = n & (1 << k) != 0;
            }
            assert_eq!(neighbourhood(&grid, 3, 4) as usize, n);
        }
    }

    #[test]
    fn one_pixel_thick_by_table_equals_it_neighbour_by_neighbour() {
        // Random framed grids of several densities (many neighbourhoods, many removals in a
        // row), and the same grids thinned by Zhang-Suen first (the skeletons it is used on).
        let mut lcg = crate::synth::lcg(9090u64);
        let mut next = move || (lcg() >> 33) as usize;
        let mut removed = 0;
        for (w, h, density) in [
            (3, 3, 2),
            (5, 4, 2),
            (23, 17, 2),
            (40, 31, 3),
            (9, 50, 4),
            (60, 44, 5),
            (33, 33, 8),
        ] {
            for thinned in [false, true] {
                let mut grid = vec![false; w * h];
                for y in 1..h - 1 {
                    for x in 1..w - 1 {
                        grid[y * w + x] = next() % density != 0;
                    }
                }
                if thinned {
                    zhang_suen_framed(&mut grid, w);
                }
                let pixels: Vec<usize> = (0..w * h).filter(|&i| grid[i]).collect();
                let (mut by_pixel, mut by_table) = (grid.clone(), grid.clone());
                one_pixel_thick_at(&mut by_pixel, w, h, pixels.clone());
                let mut candidates = pixels.clone();
                one_pixel_thick_framed_at(&mut by_table, w, &mut candidates);
                assert_eq!(by_pixel, by_table, "{w} x {h}, density {density}");
                let kept: Vec<usize> = (0..w * h).filter(|&i| by_table[i]).collect();
                assert_eq!(candidates, kept);
                removed += pixels.len() - kept.len();
            }
        }
        assert!(removed > 100, "{removed} pixels removed");
    }

    #[test]
    fn a_thick_staircase_thins_to_one_pixel() {
        // A 2-pixel-thick 45 degree staircase: every pixel has three neighbours.
        let (w, h) = (12, 12);
        let mut skeleton = vec![false; w * h];
        for i in 1..10 {
            skeleton[i * w + i] = true;
            skeleton[i * w + i + 1] = true;
        }
        one_pixel_thick(&mut skeleton, w, h);
        let on = |x: usize, y: usize| skeleton[y * w + x];
        let neighbours = |x: usize, y: usize| {
            RING.iter()
                .filter(|&&(dx, dy)| {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    nx >= 0
                        && ny >= 0
                        && (nx as usize) < w
                        && (ny as usize) < h
                        && on(nx as usize, ny as usize)
                })
                .count()
        };
        let pixels: Vec<(usize, usize)> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| on(x, y))
            .collect();
        assert!(pixels.len() >= 9, "{pixels:?}");
        assert!(
            pixels.iter().all(|&(x, y)| neighbours(x, y) <= 2),
            "{pixels:?}"
        );
    }
}
