//! The strip point set `P` of the paper: one point per foreground pixel center (or one per line of
//! a point list), with the neighbour graph every later stage walks and the local half-width.

#[cfg(test)]
use crate::csr::symmetric_neighbours;
use crate::geometry::floor_i64;
use crate::mask::{first_seen_labels, run_components, Run};
use petgraph::unionfind::UnionFind;

/// The connected components of a point set, as [`PointSet::component_labels`] gives them: one
/// label per point, and each label's point count.
pub(crate) type Components = (Vec<u32>, Vec<usize>);

/// [`Components`] held while a chunk waits between its refinement and its fit (ARCHITECTURE.md,
/// "Large inputs"): the labels as runs of one label in point order (a component's pixels come in
/// rows of ink, so a few runs per row of each component instead of a label per point).
#[derive(Debug, Default)]
pub(crate) struct PackedComponents {
    /// (label, number of consecutive points with it), in point order.
    runs: Vec<(u32, u32)>,
    sizes: Vec<usize>,
}

impl PackedComponents {
    pub(crate) fn pack((labels, sizes): Components) -> Self {
        let mut runs: Vec<(u32, u32)> = Vec::new();
        for label in labels {
            match runs.last_mut() {
                Some((l, n)) if *l == label && *n < u32::MAX => *n += 1,
                _ => runs.push((label, 1)),
            }
        }
        runs.shrink_to_fit();
        PackedComponents { runs, sizes }
    }

    /// The [`Components`] that were packed.
    pub(crate) fn unpack(self) -> Components {
        let count = self.runs.iter().map(|&(_, n)| n as usize).sum();
        let mut labels = Vec::with_capacity(count);
        for (label, n) in self.runs {
            labels.extend(std::iter::repeat_n(label, n as usize));
        }
        (labels, self.sizes)
    }
}

/// The largest pixel index kept as a thread's spare ([`Grid::release`]), entries: 16 MiB.
const MAX_SPARE_INDEX: usize = 1 << 22;

thread_local! {
    /// A pixel index a window of this thread was done with, every entry [`Grid::NONE`] again,
    /// for the thread's next window ([`Grid::blank_index`]).
    static SPARE_INDEX: std::cell::Cell<Vec<u32>> = const { std::cell::Cell::new(Vec::new()) };
}

/// A pixel grid the points came from: lets stages use pixel adjacency instead of tree queries.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    /// Width of the indexed window in pixels.
    pub width: u32,
    /// Height of the indexed window in pixels.
    pub height: u32,
    /// Point index of each pixel of the window (row-major), or [`Grid::NONE`] for background.
    pub index: Vec<u32>,
    /// Image column of the window's first pixel (0 for a whole image; a part of the image when
    /// the point set is one chunk of components).
    pub x0: i64,
    /// Image row of the window's first pixel.
    pub y0: i64,
}

impl Grid {
    /// Marks a background pixel in [`Grid::index`].
    pub const NONE: u32 = u32::MAX;

    /// Checks that the grid indexes exactly `points`: one index entry per pixel of the window,
    /// each [`Grid::NONE`] or the point whose pixel it is, and every point the center of a pixel
    /// of the window.
    fn validate(&self, points: &[[f64; 2]]) -> Result<(), String> {
        let pixels = (self.width as usize).checked_mul(self.height as usize);
        if pixels != Some(self.index.len()) {
            return Err(format!(
                "grid of {}x{} pixels has {} index entries",
                self.width,
                self.height,
                self.index.len()
            ));
        }
        let mut indexed = 0usize;
        for (pixel, &id) in self.index.iter().enumerate() {
            if id == Self::NONE {
                continue;
            }
            let (x, y) = (pixel % self.width as usize, pixel / self.width as usize);
            let center = [
                (self.x0 + x as i64) as f64 + 0.5,
                (self.y0 + y as i64) as f64 + 0.5,
            ];
            if points.get(id as usize) != Some(&center) {
                return Err(format!(
                    "grid pixel ({x}, {y}) indexes point {id}, not its own"
                ));
            }
            indexed += 1;
        }
        if indexed != points.len() {
            return Err(format!(
                "grid indexes {indexed} of {} points (each point once, at its pixel)",
                points.len()
            ));
        }
        Ok(())
    }

    /// Frees the pixel index, keeping the window: a chunk waiting between stages holds no
    /// per-pixel memory (see [`Grid::rebuild`]). `points` are the ones it indexes: their entries
    /// are set back to [`Grid::NONE`] and the index kept as this thread's spare
    /// ([`Grid::blank_index`]), so the next window's index is neither allocated nor cleared
    /// whole (docs/performance.md, "Session of 2026-12-05: pages, again").
    pub(crate) fn release(&mut self, points: &[[f64; 2]]) {
        let mut index = std::mem::take(&mut self.index);
        let width = self.width as usize;
        for p in points {
            let (x, y) = (floor_i64(p[0]) - self.x0, floor_i64(p[1]) - self.y0);
            if let Some(entry) = index.get_mut(y as usize * width + x as usize) {
                *entry = Self::NONE;
            }
        }
        debug_assert!(index.iter().all(|&i| i == Self::NONE));
        if index.len() <= MAX_SPARE_INDEX {
            SPARE_INDEX.with(|spare| {
                let kept = spare.take();
                spare.set(if kept.capacity() >= index.capacity() {
                    kept
                } else {
                    index
                });
            });
        }
    }

    /// `len` entries, all [`Grid::NONE`]: this thread's spare index ([`Grid::release`]) where
    /// it is large enough, else a new one.
    pub(crate) fn blank_index(len: usize) -> Vec<u32> {
        let mut index = SPARE_INDEX.with(|spare| spare.take());
        if index.capacity() < len {
            return vec![Self::NONE; len];
        }
        // Every entry of the spare is NONE: shortened it stays so, lengthened it is filled.
        index.resize(len, Self::NONE);
        index
    }

    /// Frees this thread's spare index ([`Grid::release`]), at the end of a trace.
    pub(crate) fn drop_spare_index() {
        SPARE_INDEX.with(|spare| drop(spare.take()));
    }

    /// Fills the pixel index of the window from `points`, the pixel centers of the window's ink.
    pub(crate) fn rebuild(&mut self, points: &[[f64; 2]]) {
        let width = self.width as usize;
        self.index = Self::blank_index(width * self.height as usize);
        for (i, p) in points.iter().enumerate() {
            let (x, y) = (floor_i64(p[0]) - self.x0, floor_i64(p[1]) - self.y0);
            self.index[y as usize * width + x as usize] = i as u32;
        }
    }

    /// The point at pixel `(x, y)`, if it is ink (`None` also where [`Grid::index`] is shorter
    /// than the window).
    #[inline]
    pub fn point_at(&self, x: i64, y: i64) -> Option<u32> {
        let (x, y) = (x.checked_sub(self.x0)?, y.checked_sub(self.y0)?);
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return None;
        }
        let id = *self
            .index
            .get(y as usize * self.width as usize + x as usize)?;
        (id != Self::NONE).then_some(id)
    }
}

/// Whether every point lies on the square lattice of step `spacing` through the first point
/// (pixel centers listed as points, or a pixel grid's points; a point list's coordinates are
/// translated to their minimum and scaled by powers of two, so lattice points stay exactly on it).
pub(crate) fn on_lattice(points: &[[f64; 2]], spacing: f64) -> bool {
    let Some(&first) = points.first() else {
        return true;
    };
    let off = |x: f64, x0: f64| {
        let t = (x - x0) / spacing;
        (t - t.round()).abs() > 1e-6
    };
    !points
        .iter()
        .any(|p| off(p[0], first[0]) || off(p[1], first[1]))
}

/// Chunks of whole components of a point set (see [`PointSet::split_components`]).
pub(crate) struct ComponentChunks {
    /// CSR offsets into `members`, one chunk after the other.
    offsets: Vec<u32>,
    /// Point indices of each chunk, ascending.
    members: Vec<u32>,
    /// Each point's position in its chunk.
    local: Vec<u32>,
}

impl ComponentChunks {
    /// Number of chunks.
    pub(crate) fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of points in chunk `c`.
    pub(crate) fn size(&self, c: usize) -> usize {
        (self.offsets[c + 1] - self.offsets[c]) as usize
    }

    /// Chunk `c` of `points` (the set these chunks were made from) as a point set of its own.
    pub(crate) fn part(&self, points: &PointSet, c: usize) -> PointSet {
        let members = &self.members[self.offsets[c] as usize..self.offsets[c + 1] as usize];
        points.subset(members, &self.local)
    }
}

/// The input points with everything the stages need to know about them.
///
/// Invariants (checked by [`PointSet::validate`]): all coordinates finite; `half_width` has one
/// finite, non-negative entry per point; `offsets` has `len() + 1` entries rising from 0 to
/// `neighbors.len()`; the neighbour relation is symmetric and has no self-loops; `spacing` is
/// finite and positive when there are points; a grid indexes exactly the points, each a pixel
/// center of its window.
#[derive(Clone, Debug, Default)]
pub struct PointSet {
    /// Point coordinates. For images: pixel centers, pixel `(c, r)` at `(c + 0.5, r + 0.5)`.
    pub points: Vec<[f64; 2]>,
    /// Distance from each point to the background (half the local stroke width), in the same unit
    /// as the coordinates. A pixel one step inside the edge has 1.
    pub half_width: Vec<f32>,
    /// CSR offsets into [`PointSet::neighbors`]: the neighbours of point `i` are
    /// `neighbors[offsets[i]..offsets[i + 1]]`.
    pub offsets: Vec<u32>,
    /// Flattened neighbour lists (8-neighbourhood on images, 5x5 in dropout mode, symmetric k
    /// nearest neighbours for point lists).
    pub neighbors: Vec<u32>,
    /// `Dis_ave` of the paper: mean distance from a point to its nearest neighbour.
    pub spacing: f64,
    /// Whether dropout mode is on (sparse or broken foreground: wider neighbourhoods).
    pub dropout: bool,
    /// The pixel grid, for points that came from an image.
    pub grid: Option<Grid>,
}

impl PointSet {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The neighbours of point `i` (none for a point or offsets that do not exist).
    #[inline]
    pub fn neighbors_of(&self, i: u32) -> &[u32] {
        let i = i as usize;
        match (self.offsets.get(i), self.offsets.get(i + 1)) {
            (Some(&start), Some(&end)) => self
                .neighbors
                .get(start as usize..end as usize)
                .unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Builds the CSR neighbour arrays from per-point lists, symmetrizing them (for hand-built
    /// point sets in tests).
    #[cfg(test)]
    pub(crate) fn set_neighbors_symmetric(&mut self, lists: &[Vec<u32>]) {
        let (offsets, neighbors) = symmetric_neighbours(self.points.len(), |emit| {
            for (i, list) in lists.iter().enumerate() {
                for &j in list {
                    if j as usize != i {
                        emit(i as u32, j);
                    }
                }
            }
        });
        self.offsets = offsets;
        self.neighbors = neighbors;
    }

    /// Splits the points into chunks of whole connected components (of the neighbour graph), each
    /// chunk about `target` points or one component, in the order of each component's first
    /// point. Every stage treats components independently, so tracing the chunks one by one gives
    /// the same result as tracing the whole set; the chunking does not depend on the thread count.
    #[cfg(test)]
    pub(crate) fn split_components(&self, target: usize) -> Vec<PointSet> {
        let chunks = Self::chunks_of(self.component_labels(), target);
        (0..chunks.len()).map(|c| chunks.part(self, c)).collect()
    }

    /// Each point's connected component (of the neighbour graph), numbered in order of the
    /// components' first points, and the components' sizes.
    pub(crate) fn component_labels(&self) -> (Vec<u32>, Vec<usize>) {
        let n = self.len();
        if self.offsets.len() != n + 1 {
            return ((0..n as u32).collect(), vec![1; n]);
        }
        if let Some(labels) = self.pixel_component_labels() {
            return labels;
        }
        // Union-find over the neighbour lists in index order: the lists are read as they lie in
        // memory (a depth-first walk jumps around them).
        let mut sets = UnionFind::<u32>::new(n);
        for p in 0..n as u32 {
            for &q in self.neighbors_of(p) {
                if q < p {
                    sets.union(p, q);
                }
            }
        }
        first_seen_labels(&mut sets, n, |_| 1)
    }

    /// [`PointSet::component_labels`] of a set whose components are known: `parts` gives the
    /// points of a component one label (any label below the point count), the answer numbers the
    /// components in the order their first points come, as the union-find does.
    pub(crate) fn first_seen(parts: &[u32]) -> (Vec<u32>, Vec<usize>) {
        let mut label_of = vec![u32::MAX; parts.len()];
        let mut sizes: Vec<usize> = Vec::new();
        let labels = parts
            .iter()
            .map(|&part| {
                let slot = &mut label_of[part as usize];
                if *slot == u32::MAX {
                    *slot = sizes.len() as u32;
                    sizes.push(0);
                }
                sizes[*slot as usize] += 1;
                *slot
            })
            .collect();
        (labels, sizes)
    }

    /// [`PointSet::component_labels`] from the runs of pixels, for pixel centers in raster order
    /// with 8-neighbour lists (images outside dropout mode): a union-find over runs instead of
    /// neighbour lists, several times faster. `None` for other point sets.
    fn pixel_component_labels(&self) -> Option<(Vec<u32>, Vec<usize>)> {
        if self.grid.is_none() || self.dropout {
            return None;
        }
        let mut runs: Vec<Run> = Vec::new();
        let mut run_of = Vec::with_capacity(self.len());
        for p in &self.points {
            // Truncation is the floor of what passes this test (and the floor passes it exactly
            // when the value does).
            let (x, y) = (p[0], p[1]);
            if !(x >= 0.0 && y >= 0.0 && x < u32::MAX as f64 && y < u32::MAX as f64) {
                return None;
            }
            let (x, y) = (x as u32, y as u32);
            match runs.last_mut() {
                Some(run) if run.y == y && run.x1 == x => run.x1 += 1,
                // Raster order, or the neighbour lists are the only truth.
                Some(run) if (run.y, run.x1) > (y, x) => return None,
                _ => runs.push(Run {
                    y,
                    x0: x,
                    x1: x + 1,
                }),
            }
            run_of.push(runs.len() as u32 - 1);
        }
        let (label, sizes) = run_components(&runs);
        Some((run_of.iter().map(|&r| label[r as usize]).collect(), sizes))
    }

    /// The chunks of [`PointSet::split_components`] as lists of point indices, so that each chunk's
    /// point set can be built where it is traced (in parallel, and only while it is traced: the
    /// copies of all chunks never exist at once), from the components `(label, sizes)` as
    /// [`PointSet::component_labels`] gives them.
    pub(crate) fn chunks_of(
        (mut label, sizes): (Vec<u32>, Vec<usize>),
        target: usize,
    ) -> ComponentChunks {
        let n = label.len();
        // Consecutive components fill a chunk up to `target` points.
        let mut chunk_of = Vec::with_capacity(sizes.len());
        let mut chunks = 0u32;
        let mut filled = 0usize;
        let mut chunk_sizes = Vec::new();
        for &size in &sizes {
            if filled > 0 && filled + size > target {
                chunk_sizes.push(filled as u32);
                chunks += 1;
                filled = 0;
            }
            chunk_of.push(chunks);
            filled += size;
        }
        if filled > 0 {
            chunk_sizes.push(filled as u32);
        }
        // Members of every chunk in CSR form, ascending within a chunk, and each point's position
        // in its chunk (the chunks partition the points, so one array serves them all).
        let mut offsets = Vec::with_capacity(chunk_sizes.len() + 1);
        offsets.push(0u32);
        for &size in &chunk_sizes {
            offsets.push(offsets[offsets.len() - 1] + size);
        }
        let mut fill: Vec<u32> = offsets[..offsets.len() - 1].to_vec();
        let mut members = vec![0u32; n];
        // `label` becomes each point's local index in place.
        for (p, slot) in label.iter_mut().enumerate() {
            let chunk = chunk_of[*slot as usize] as usize;
            let at = fill[chunk];
            members[at as usize] = p as u32;
            *slot = at - offsets[chunk];
            fill[chunk] += 1;
        }
        ComponentChunks {
            offsets,
            members,
            local: label,
        }
    }

    /// The points whose `keep` is set as a point set of their own (see [`PointSet::subset`]).
    pub(crate) fn kept(&self, keep: &[bool]) -> PointSet {
        let members: Vec<u32> = (0..self.len() as u32)
            .filter(|&p| keep[p as usize])
            .collect();
        let mut local = vec![u32::MAX; self.len()];
        for (k, &p) in members.iter().enumerate() {
            local[p as usize] = k as u32;
        }
        self.subset(&members, &local)
    }

    /// The points `members` (ascending) as a point set of their own; `local` maps every member to
    /// its position in `members` (and every other point to `u32::MAX`: neighbours outside
    /// `members` are left out).
    fn subset(&self, members: &[u32], local: &[u32]) -> PointSet {
        let mut part = PointSet {
            points: members.iter().map(|&p| self.points[p as usize]).collect(),
            half_width: members
                .iter()
                .map(|&p| self.half_width[p as usize])
                .collect(),
            offsets: Vec::with_capacity(members.len() + 1),
            neighbors: Vec::with_capacity(
                members.iter().map(|&p| self.neighbors_of(p).len()).sum(),
            ),
            spacing: self.spacing,
            dropout: self.dropout,
            grid: None,
        };
        part.offsets.push(0);
        for &p in members {
            part.neighbors.extend(
                self.neighbors_of(p)
                    .iter()
                    .map(|&q| local[q as usize])
                    .filter(|&q| q != u32::MAX),
            );
            part.offsets.push(part.neighbors.len() as u32);
        }
        if self.grid.is_some() {
            let (mut x0, mut y0, mut x1, mut y1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
            for p in &part.points {
                let (x, y) = (floor_i64(p[0]), floor_i64(p[1]));
                x0 = x0.min(x);
                y0 = y0.min(y);
                x1 = x1.max(x);
                y1 = y1.max(y);
            }
            if x0 <= x1 {
                let mut grid = Grid {
                    width: (x1 - x0 + 1) as u32,
                    height: (y1 - y0 + 1) as u32,
                    index: Vec::new(),
                    x0,
                    y0,
                };
                grid.rebuild(&part.points);
                part.grid = Some(grid);
            }
        }
        part
    }

    /// Checks the invariants listed on the type; returns a description of the first violation.
    /// Never panics, whatever the fields hold.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.points.len();
        if self.half_width.len() != n {
            return Err(format!(
                "{} half-widths for {} points",
                self.half_width.len(),
                n
            ));
        }
        if self.offsets.len() != n + 1 {
            return Err(format!("{} offsets for {} points", self.offsets.len(), n));
        }
        if self.offsets[0] != 0 || self.offsets[n] as usize != self.neighbors.len() {
            return Err(format!(
                "offsets run from {} to {} over {} neighbours",
                self.offsets[0],
                self.offsets[n],
                self.neighbors.len()
            ));
        }
        if let Some(i) = self.offsets.windows(2).position(|w| w[0] > w[1]) {
            return Err(format!("offsets fall at point {i}"));
        }
        if n >= Grid::NONE as usize {
            return Err(format!(
                "{n} points: at most {} can be indexed",
                Grid::NONE - 1
            ));
        }
        if let Some(i) = self
            .half_width
            .iter()
            .position(|h| !(h.is_finite() && *h >= 0.0))
        {
            return Err(format!("half-width of point {i} is {}", self.half_width[i]));
        }
        if n > 0 && !(self.spacing.is_finite() && self.spacing > 0.0) {
            return Err(format!("spacing {} is not positive", self.spacing));
        }
        if let Some(i) = self
            .points
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(format!("point {i} is not finite"));
        }
        for i in 0..n as u32 {
            for &j in self.neighbors_of(i) {
                if j == i || j as usize >= n || !self.neighbors_of(j).contains(&i) {
                    return Err(format!("neighbour relation broken at {i} - {j}"));
                }
            }
        }
        if let Some(grid) = &self.grid {
            grid.validate(&self.points)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A window's pixel index made from this thread's spare (a released index, larger or
    /// smaller) is the index made from a new array: every pixel [`Grid::NONE`] but the points'.
    #[test]
    fn an_index_from_the_spare_is_a_new_index() {
        let mut next = crate::synth::lcg(2026u64);
        let mut rand = move |n: u64| (next() >> 33) % n;
        for _ in 0..200 {
            let (width, height) = (1 + rand(90) as u32, 1 + rand(60) as u32);
            let (x0, y0) = (rand(50) as i64, rand(50) as i64);
            let mut points = Vec::new();
            for y in 0..height {
                for x in 0..width {
                    if rand(4) == 0 {
                        points.push([(x0 + x as i64) as f64 + 0.5, (y0 + y as i64) as f64 + 0.5]);
                    }
                }
            }
            let mut grid = Grid {
                width,
                height,
                index: Vec::new(),
                x0,
                y0,
            };
            grid.rebuild(&points);
            let mut fresh = vec![Grid::NONE; (width * height) as usize];
            for (i, p) in points.iter().enumerate() {
                let (x, y) = (p[0] as i64 - x0, p[1] as i64 - y0);
                fresh[(y * width as i64 + x) as usize] = i as u32;
            }
            assert_eq!(grid.index, fresh);
            grid.validate(&points).expect("valid grid");
            grid.release(&points);
            assert!(grid.index.is_empty());
        }
        Grid::drop_spare_index();
        assert!(Grid::blank_index(10).iter().all(|&i| i == Grid::NONE));
    }

    /// Points on a line (x = index) with the given undirected links.
    fn linked(n: usize, links: &[(u32, u32)]) -> PointSet {
        let mut points = PointSet {
            points: (0..n).map(|i| [i as f64, 0.0]).collect(),
            half_width: vec![1.0; n],
            spacing: 1.0,
            ..PointSet::default()
        };
        let mut lists = vec![Vec::new(); n];
        for &(a, b) in links {
            lists[a as usize].push(b);
        }
        points.set_neighbors_symmetric(&lists);
        points
    }

    #[test]
    fn chunks_hold_whole_components_in_order_of_first_point() {
        // Components {0, 5, 9} (joined late: 9 links 0 and 5 only at the end), {1, 2}, {3},
        // {4, 6, 7, 8} (a chain whose smallest point is reached from above).
        let points = linked(10, &[(9, 5), (9, 0), (1, 2), (8, 4), (8, 7), (6, 7)]);
        assert!(points.validate().is_ok());
        let expected: [&[f64]; 4] = [&[0.0, 5.0, 9.0], &[1.0, 2.0], &[3.0], &[4.0, 6.0, 7.0, 8.0]];
        // One component per chunk.
        let parts = points.split_components(1);
        assert_eq!(parts.len(), 4);
        for (part, xs) in parts.iter().zip(expected) {
            assert!(part.validate().is_ok());
            let got: Vec<f64> = part.points.iter().map(|p| p[0]).collect();
            assert_eq!(got, xs);
            // Neighbours stay inside the chunk and point at the same points as before.
            for i in 0..part.len() as u32 {
                for &j in part.neighbors_of(i) {
                    let (a, b) = (part.points[i as usize][0], part.points[j as usize][0]);
                    assert!(points.neighbors_of(a as u32).contains(&(b as u32)));
                }
            }
        }
        // Consecutive components share a chunk up to the target size.
        let sizes = |target| -> Vec<usize> {
            points
                .split_components(target)
                .iter()
                .map(|p| p.len())
                .collect()
        };
        assert_eq!(sizes(5), [5, 5]);
        assert_eq!(sizes(4), [3, 3, 4]);
        assert_eq!(points.split_components(100).len(), 1);
        assert!(PointSet::default().split_components(4).is_empty());
    }

    #[test]
    fn packed_components_unpack_to_the_same_labels() {
        let mut seed = 3u64;
        for len in [0usize, 1, 2, 17, 1000] {
            let labels: Vec<u32> = (0..len)
                .map(|_| {
                    seed = seed
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    // Long runs of one label, and now and then single points.
                    (seed >> 62) as u32
                })
                .scan(0u32, |run, bit| {
                    *run = if bit == 0 { *run + 1 } else { *run };
                    Some(*run % 5)
                })
                .collect();
            let sizes: Vec<usize> = (0..5)
                .map(|c| labels.iter().filter(|&&l| l == c).count())
                .collect();
            let components = (labels, sizes);
            let packed = PackedComponents::pack(components.clone());
            assert!(packed.runs.len() <= components.0.len());
            assert_eq!(packed.unpack(), components, "{len} labels");
        }
    }

    #[test]
    fn component_labels_from_runs_equal_those_from_neighbour_lists() {
        let (w, h) = (61u32, 47u32);
        let mut binary = crate::binary::Binary::new(w, h);
        let mut seed = 7u64;
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                binary.set(x, y, (seed >> 60) < 7);
            }
        }
        let mut params = crate::params::Params::default();
        params.front_end.dropout = Some(false);
        let pixels = crate::raster::points(&binary, &params).expect("points");
        let listed = PointSet {
            grid: None,
            ..pixels.clone()
        };
        let (labels, sizes) = pixels.component_labels();
        assert!(sizes.len() > 20, "{} components", sizes.len());
        assert_eq!((labels, sizes), listed.component_labels());
        // Both chunkings agree too.
        for (a, b) in pixels
            .split_components(100)
            .iter()
            .zip(listed.split_components(100))
        {
            assert_eq!(a.points, b.points);
        }
    }
}
