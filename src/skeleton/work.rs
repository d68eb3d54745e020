//! The skeleton graph being edited ([`Work`]) over the ink it was thinned from ([`Ink`]), with the
//! edits every reconciliation step shares: incidence, joining at degree-2 vertices, cutting an
//! arm at a junction's disk, and writing the final [`StrokeGraph`].

use crate::csr::Csr;
use crate::geometry::{ceil_f64, dist, floor_f64, tangents};
use crate::stroke_graph::{Edge, StrokeGraph, Vertex};

use super::MIN_WIDTH_PX;

/// The ink is sampled along a line every half pixel (px): finer than a pixel, so a line does not
/// step over a corner of background.
const INK_STEP_PX: f64 = 0.5;

/// Strokes this wide (px: the skeleton's width, 1 where every pixel of the stroke lies on the
/// ink's edge, i.e. strokes one or two pixels wide) are lines of single pixels, linked through
/// pixel corners ([`Ink::holds_thin`]).
const THIN_STROKE_PX: f64 = 1.0;

/// How near a pixel edge (px) a point off the ink may lie and still count as on a one-pixel line
/// ([`Ink::at_or_linked`]): an eighth of a pixel, the rounding of where a line crosses a row.
const PIXEL_EDGE_PX: f64 = 0.125;

/// The lowest bit of each byte of a word: eight pixels of a row of the mask read at once
/// ([`Ink::nearest_background`]).
const LANES: u64 = 0x0101_0101_0101_0101;

/// [`Ink::nearest_background`]: the clearance of a point and where it comes from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Clearance {
    /// [`Ink::clearance`].
    pub(super) clearance: f64,
    /// The squared distance to the nearest background centre, of which `clearance` is the
    /// square root (the square of the limit and a pixel when none is within the limit).
    pub(super) squared: f64,
    /// The nearest background pixel's centre in the window's coordinates, if within the limit.
    pub(super) pixel: Option<[f64; 2]>,
}

/// An ink mask over a window of the image.
pub(super) struct Ink {
    pub(super) mask: Vec<bool>,
    pub(super) width: usize,
    pub(super) height: usize,
    /// The image coordinates of the window's corner.
    pub(super) origin: [f64; 2],
}

impl Ink {
    pub(super) fn at(&self, p: [f64; 2]) -> bool {
        self.at_window(p[0] - self.origin[0], p[1] - self.origin[1])
    }

    /// Whether the pixel holding `(x, y)`, in the window's coordinates, is ink.
    #[inline]
    pub(super) fn at_window(&self, x: f64, y: f64) -> bool {
        // Truncation is the floor where the value is not negative, and so is its test. A
        // coordinate of 2⁶³ or more is outside (no window is that wide: its mask would not fit
        // in memory), as the saturating `as i64` left it; below, the conversion needs no
        // saturation, one instruction (the saturating one's checks were most of a lookup's
        // instructions in `section_exit`'s walk: docs/performance.md).
        const FAR: f64 = 9_223_372_036_854_775_808.0; // 2⁶³
        if !(x >= 0.0 && y >= 0.0 && x < FAR && y < FAR) {
            return false;
        }
        // SAFETY: `0 <= x, y < 2⁶³` (checked above; not NaN), so their truncations fit an `i64`.
        let (px, py) = unsafe { (x.to_int_unchecked::<i64>(), y.to_int_unchecked::<i64>()) };
        let (px, py) = (px as usize, py as usize);
        px < self.width && py < self.height && self.mask[py * self.width + px]
    }

    /// [`Ink::at_window`] for a point in the window, without the tests of its bounds.
    ///
    /// # Safety
    ///
    /// `0 <= x < width` and `0 <= y < height` (so neither is NaN).
    #[inline]
    pub(super) unsafe fn at_inside(&self, x: f64, y: f64) -> bool {
        debug_assert!(x >= 0.0 && y >= 0.0 && x < self.width as f64 && y < self.height as f64);
        // SAFETY: the caller's promise, so the truncations fit an `i64`.
        let (px, py) = unsafe { (x.to_int_unchecked::<i64>(), y.to_int_unchecked::<i64>()) };
        self.mask[py as usize * self.width + px as usize]
    }

    /// How far the ink goes on from `from` along the unit vector `u`: the first sample, every
    /// half pixel from half a pixel on, that is off the ink or beyond `limit`.
    pub(super) fn exit(&self, from: [f64; 2], u: [f64; 2], limit: f64) -> f64 {
        let mut t = INK_STEP_PX;
        while t <= limit && self.at([from[0] + t * u[0], from[1] + t * u[1]]) {
            t += INK_STEP_PX;
        }
        t
    }

    /// The distance from `p` to the nearest background pixel centre, looked for up to `limit`
    /// px (beyond that, `limit` and a pixel more are returned): the radius of the disk on the
    /// ink at `p`, measured as the skeleton's widths are (a skeleton pixel's disk holds the ink
    /// pixels closer to it than the nearest background pixel). Pixels outside the window are
    /// background.
    ///
    /// Row by row outwards from `p`'s own: a row's nearest background centre is the nearest
    /// background pixel on either side of `p`'s column (the rounded difference of the
    /// coordinates never shrinks as the column moves away), so each row costs a scan along its
    /// ink from `p`'s column, no farther than a centre could still be nearer than the nearest
    /// found, not a test of every pixel within the limit. Every centre of the rows `r` away lies
    /// at least `r - 1/2` px from `p`, so the search stops once that is beyond the nearest
    /// found. The result is the least of the squared distances of all pixels within the limit,
    /// whatever the order of the search (the clearance is asked at every step of every end's
    /// walk, `Work::walk_middle`, and was first found by testing every pixel of square rings).
    pub(super) fn clearance(&self, p: [f64; 2], limit: f64) -> f64 {
        self.nearest_background(p, limit).clearance
    }

    /// [`Ink::clearance`] with the background pixel centre that sets it.
    pub(super) fn nearest_background(&self, p: [f64; 2], limit: f64) -> Clearance {
        let (x, y) = (p[0] - self.origin[0], p[1] - self.origin[1]);
        let (cx, cy) = (floor_f64(x), floor_f64(y));
        let k = ceil_f64(limit.max(0.0)) as i64 + 1;
        let none = limit.max(0.0) + 1.0;
        let mut best = none * none;
        let mut nearest = None;
        // `p`'s column in the window, when it is in it: along it a row is scanned; outside it
        // (or NaN) that column's own pixel is background in every row.
        let column = (cx >= 0.0 && cx < self.width as f64).then_some(cx as usize);
        let offer = |dx: i64, qy: f64, ey: f64, best: &mut f64, nearest: &mut Option<[f64; 2]>| {
            let qx = cx + dx as f64 + 0.5;
            let ex = qx - x;
            let d = ex * ex + ey * ey;
            if d < *best {
                *best = d;
                *nearest = Some([qx, qy]);
            }
        };
        for r in 0..=k {
            let inner = r as f64 - 0.5;
            if inner > 0.0 && inner * inner > best {
                break;
            }
            for &dy in &[-r, r][..usize::from(r > 0) + 1] {
                let qy = cy + dy as f64 + 0.5;
                let ey = qy - y;
                let ey2 = ey * ey;
                // The least squared distance of a centre in this row `j` columns from `p`'s
                // (`|ex| >= j - 1/2`): the scan stops where it reaches the nearest found.
                let beyond = |j: usize| {
                    let near = j as f64 - 0.5;
                    near * near + ey2
                };
                if ey2 >= best || ey2.is_nan() {
                    continue;
                }
                let row_y = cy + dy as f64;
                let (line, c) = match column {
                    Some(c) if row_y >= 0.0 && row_y < self.height as f64 => {
                        let start = row_y as usize * self.width;
                        (&self.mask[start..start + self.width], c)
                    }
                    _ => {
                        offer(0, qy, ey, &mut best, &mut nearest);
                        continue;
                    }
                };
                if !line[c] {
                    offer(0, qy, ey, &mut best, &mut nearest);
                    continue;
                }
                // Left, then right, to the first background pixel (the columns beyond the
                // window are background); each scan's first offset, 0 once that side's pixel
                // is found. The four pixels left of `c` and the three right of it at once where
                // the row holds them: the nearest background in them is the first the scan would
                // reach (offered even where the scan would have stopped short of it: no nearer
                // than the nearest found, it changes nothing).
                let mut from = [1, 1];
                if let Some(eight) = c
                    .checked_sub(4)
                    .and_then(|first| line.get(first..first + 8))
                    .and_then(|eight| <&[bool; 8]>::try_from(eight).ok())
                {
                    let background = !u64::from_le_bytes(eight.map(u8::from)) & LANES;
                    let left = background & (LANES >> 32);
                    from[0] = if left == 0 {
                        5
                    } else {
                        let j = 4 - (63 - left.leading_zeros()) / 8;
                        offer(-i64::from(j), qy, ey, &mut best, &mut nearest);
                        0
                    };
                    let right = background >> 40;
                    from[1] = if right == 0 {
                        4
                    } else {
                        let j = right.trailing_zeros() / 8 + 1;
                        offer(i64::from(j), qy, ey, &mut best, &mut nearest);
                        0
                    };
                }
                let mut j = from[0];
                while j > 0 && beyond(j) < best {
                    if j > c || !line[c - j] {
                        offer(-(j as i64), qy, ey, &mut best, &mut nearest);
                        break;
                    }
                    j += 1;
                }
                let mut j = from[1];
                while j > 0 && beyond(j) < best {
                    if c + j >= line.len() || !line[c + j] {
                        offer(j as i64, qy, ey, &mut best, &mut nearest);
                        break;
                    }
                    j += 1;
                }
            }
        }
        match nearest {
            Some(pixel) => Clearance {
                clearance: best.sqrt(),
                squared: best,
                pixel: Some(pixel),
            },
            None => Clearance {
                clearance: none,
                squared: best,
                pixel: None,
            },
        }
    }

    /// The squared distance from `p` to the pixel centre `q` given in the window's coordinates
    /// (as [`Clearance::pixel`]), computed as [`Ink::nearest_background`] computes it: so a
    /// background centre found for one point bounds the clearance of another bit for bit.
    pub(super) fn squared_to_centre(&self, p: [f64; 2], q: [f64; 2]) -> f64 {
        let (x, y) = (p[0] - self.origin[0], p[1] - self.origin[1]);
        let (ex, ey) = (q[0] - x, q[1] - y);
        ex * ex + ey * ey
    }

    /// Whether the point `p` is on the ink as a line along a stroke one pixel wide can be: on
    /// an ink pixel, within [`PIXEL_EDGE_PX`] of one across a pixel edge, or in the corner of a
    /// background pixel through which two diagonal ink pixels alone are linked (the other pixel
    /// at that corner background too). Such ink is 8-connected: a straight line along it passes
    /// a corner at every step of its staircase, never exactly through the corner point.
    pub(super) fn at_or_linked(&self, p: [f64; 2]) -> bool {
        if self.at(p) {
            return true;
        }
        let (x, y) = (p[0] - self.origin[0], p[1] - self.origin[1]);
        const EDGE: f64 = PIXEL_EDGE_PX;
        if [(-EDGE, 0.0), (EDGE, 0.0), (0.0, -EDGE), (0.0, EDGE)]
            .iter()
            .any(|&(ex, ey)| self.at_window(x + ex, y + ey))
        {
            return true;
        }
        let (fx, fy) = (floor_f64(x), floor_f64(y));
        // The corner of the pixel nearest `p`, as the steps towards it.
        let dx = if x - fx < 0.5 { -1.0 } else { 1.0 };
        let dy = if y - fy < 0.5 { -1.0 } else { 1.0 };
        let (cx, cy) = (fx + 0.5, fy + 0.5);
        self.at_window(cx + dx, cy)
            && self.at_window(cx, cy + dy)
            && !self.at_window(cx + dx, cy + dy)
    }

    /// [`Ink::holds`] with the corners of diagonal links taken as ink ([`Ink::at_or_linked`]).
    pub(super) fn holds_linked(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        sampled(a, b).all(|p| self.at_or_linked(p))
    }

    /// [`Ink::holds`], or for a stroke at most [`THIN_STROKE_PX`] wide [`Ink::holds_linked`]:
    /// a straight line along a one-pixel staircase leaves the pixels at its steps, so asking it
    /// to stay on them refuses every straight stroke of a 1-px drawing (docs/quality.md,
    /// "Session of 2026-12-06, sixth: thin drawings (issue 31)").
    pub(super) fn holds_thin(&self, a: [f64; 2], b: [f64; 2], stroke: f64) -> bool {
        if stroke <= THIN_STROKE_PX {
            self.holds_linked(a, b)
        } else {
            self.holds(a, b)
        }
    }

    /// Whether the segment `a`-`b` lies on the ink, sampled every half pixel.
    pub(super) fn holds(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        sampled(a, b).all(|p| self.at(p))
    }
}

/// The points of the segment `a`-`b` every [`INK_STEP_PX`] or less, both ends included.
pub(super) fn sampled(a: [f64; 2], b: [f64; 2]) -> impl Iterator<Item = [f64; 2]> {
    let n = ceil_f64(dist(a, b) / INK_STEP_PX).max(1.0) as usize;
    (0..=n).map(move |i| {
        let t = i as f64 / n as f64;
        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
    })
}

/// The skeleton graph being edited: removed edges are `None`, removed vertices `alive == false`.
pub(super) struct Work {
    /// The ink the skeleton was thinned from, to keep every straightened line on it.
    pub(super) ink: Ink,
    pub(super) vertices: Vec<Vertex>,
    pub(super) alive: Vec<bool>,
    /// Vertices that were dots (no edge) from the start: kept with degree 0.
    pub(super) dot: Vec<bool>,
    pub(super) edges: Vec<Option<Edge>>,
}

impl Work {
    pub(super) fn new(graph: StrokeGraph, ink: Ink) -> Work {
        let n = graph.vertices.len();
        let dot = graph.vertices.iter().map(|v| v.degree == 0).collect();
        Work {
            ink,
            vertices: graph.vertices,
            alive: vec![true; n],
            dot,
            // Tangents are written by `finish`, once the polylines are final.
            edges: graph
                .edges
                .into_iter()
                .map(|mut e| {
                    e.directions.clear();
                    Some(e)
                })
                .collect(),
        }
    }

    pub(super) fn degrees(&self) -> Vec<usize> {
        let mut degree = vec![0; self.vertices.len()];
        for e in self.edges.iter().flatten() {
            degree[e.from] += 1;
            degree[e.to] += 1;
        }
        degree
    }

    /// The edges at each vertex (a loop listed once), in one table for the steps that only read
    /// them (a vector per vertex is an allocation and a free per vertex per step, tens of
    /// thousands a page).
    pub(super) fn incident(&self) -> Csr<usize> {
        Csr::build(self.vertices.len(), |sink| {
            for (e, edge) in self.edges.iter().enumerate() {
                let Some(edge) = edge else { continue };
                sink.push(edge.from, e);
                if edge.to != edge.from {
                    sink.push(edge.to, e);
                }
            }
        })
    }

    /// The edges at each vertex (a loop listed once), a vector each for the steps that edit
    /// them.
    pub(super) fn incidence(&self) -> Vec<Vec<usize>> {
        let at = self.incident();
        (0..at.rows()).map(|v| at.row(v).to_vec()).collect()
    }

    /// Vertices left with two edge ends (after pruning) are not junctions: their two edges
    /// become one.
    pub(super) fn join_degree_two(&mut self) {
        let degree = self.degrees();
        let mut at = self.incidence();
        for v in 0..self.vertices.len() {
            if !self.alive[v] || degree[v] != 2 {
                continue;
            }
            let incident: Vec<usize> = at[v]
                .iter()
                .copied()
                .filter(|&e| self.edges[e].is_some())
                .collect();
            let [a, b] = incident[..] else { continue };
            let is_loop = |e: usize| self.edges[e].as_ref().is_some_and(|x| x.from == x.to);
            if a == b || is_loop(a) || is_loop(b) {
                continue;
            }
            let (Some(mut first), Some(mut second)) = (self.edges[a].take(), self.edges[b].take())
            else {
                continue;
            };
            if first.to != v {
                reverse(&mut first);
            }
            if second.from != v {
                reverse(&mut second);
            }
            first.points.pop();
            first.widths.pop();
            first.points.extend(second.points);
            first.widths.extend(second.widths);
            first.to = second.to;
            let far = first.to;
            self.alive[v] = false;
            self.edges[a] = Some(first);
            at[v].clear();
            for e in &mut at[far] {
                if *e == b {
                    *e = a;
                }
            }
            at[far].sort_unstable();
            at[far].dedup();
        }
    }

    pub(super) fn finish(self, width: u32, height: u32) -> StrokeGraph {
        let degree = self.degrees();
        let mut index = vec![usize::MAX; self.vertices.len()];
        let mut vertices = Vec::new();
        for (i, v) in self.vertices.into_iter().enumerate() {
            if self.alive[i] && (degree[i] > 0 || self.dot[i]) {
                index[i] = vertices.len();
                vertices.push(Vertex {
                    degree: degree[i],
                    ..v
                });
            }
        }
        let edges = self
            .edges
            .into_iter()
            .flatten()
            .map(|mut e| {
                e.from = index[e.from];
                e.to = index[e.to];
                // The method's lines keep their fitted tangents; the skeleton's get theirs.
                if e.directions.len() != e.points.len() {
                    e.directions = tangents(&e.points);
                }
                e
            })
            .collect();
        StrokeGraph {
            width,
            height,
            vertices,
            edges,
        }
    }
}

/// The points of `edge` listed from the junction outwards: from its start when `forward`.
pub(super) fn points_outwards(edge: &Edge, forward: bool) -> Vec<[f64; 2]> {
    if forward {
        edge.points.clone()
    } else {
        edge.points.iter().rev().copied().collect()
    }
}

/// The median of a polyline's widths (1 for none): the stroke's width, unmoved by the wider
/// pixels where it meets another.
///
/// The upper median in [`f64::total_cmp`]'s order (`crate::median::upper_median`), among
/// integer keys in the same order (one comparison each where `total_cmp` is several). Values
/// equal in that order are the same bits, so the value picked is the same.
///
/// A skeleton edge's widths are a distance transform's few levels, mostly in runs along the
/// edge, and the steps of the reconciliation ask for the same edges' medians tens of
/// thousands of times a page: the distinct keys are counted (the last one matched tried
/// first), and the key whose count carries the rank past `n / 2` is the median. More than
/// [`FEW_WIDTHS`] distinct keys (a fitted edge's interpolated widths) are selected among, in a
/// buffer on the stack for the short polylines most edges are.
pub(super) fn median(widths: &[f64]) -> f64 {
    let n = widths.len();
    if n == 0 {
        return MIN_WIDTH_PX;
    }
    let key = few_widths_median(widths).unwrap_or_else(|| selected_median(widths));
    // The key's map is its own inverse (it keeps the sign bit and flips the others or not by it).
    f64::from_bits(total_order_key(f64::from_bits(key as u64)) as u64)
}

/// The most distinct keys [`median`] counts before it selects instead.
const FEW_WIDTHS: usize = 8;

/// The key of [`median`] of the non-empty `widths` when they hold at most [`FEW_WIDTHS`]
/// distinct keys: each distinct key with its count, then the keys in rising order until the
/// counts pass the rank `n / 2`.
fn few_widths_median(widths: &[f64]) -> Option<i64> {
    let mut keys = [0i64; FEW_WIDTHS];
    let mut counts = [0usize; FEW_WIDTHS];
    let (mut distinct, mut last) = (0, 0);
    for &w in widths {
        let k = total_order_key(w);
        if distinct > 0 && keys[last] == k {
            counts[last] += 1;
            continue;
        }
        match keys[..distinct].iter().position(|&x| x == k) {
            Some(i) => last = i,
            None if distinct == FEW_WIDTHS => return None,
            None => {
                (keys[distinct], last) = (k, distinct);
                distinct += 1;
            }
        }
        counts[last] += 1;
    }
    // Insertion sort of the few keys, their counts alongside.
    for i in 1..distinct {
        let mut j = i;
        while j > 0 && keys[j - 1] > keys[j] {
            keys.swap(j - 1, j);
            counts.swap(j - 1, j);
            j -= 1;
        }
    }
    let rank = widths.len() / 2;
    let mut below = 0;
    for (&k, &c) in keys[..distinct].iter().zip(&counts) {
        below += c;
        if below > rank {
            return Some(k);
        }
    }
    None
}

/// The key of [`median`] of the non-empty `widths`, selected among all their keys.
fn selected_median(widths: &[f64]) -> i64 {
    const ON_STACK: usize = 64;
    let n = widths.len();
    let pick = |keys: &mut [i64]| *keys.select_nth_unstable(n / 2).1;
    if n <= ON_STACK {
        let mut keys = [0i64; ON_STACK];
        for (k, &w) in keys.iter_mut().zip(widths) {
            *k = total_order_key(w);
        }
        pick(&mut keys[..n])
    } else {
        let mut keys: Vec<i64> = widths.iter().map(|&w| total_order_key(w)).collect();
        pick(&mut keys)
    }
}

/// An integer whose order is [`f64::total_cmp`]'s on the values (the transform `total_cmp`
/// itself makes): a negative value's bits other than the sign flipped.
#[inline]
fn total_order_key(v: f64) -> i64 {
    let bits = v.to_bits() as i64;
    bits ^ ((((bits >> 63) as u64) >> 1) as i64)
}

fn reverse(edge: &mut Edge) {
    std::mem::swap(&mut edge.from, &mut edge.to);
    edge.points.reverse();
    edge.widths.reverse();
}

/// The index of the point where an arm first leaves the disk of radius `reach` around `hub`,
/// walking from its start when `at_start`, else from its end; the far end when it never does.
fn cut_index(points: &[[f64; 2]], at_start: bool, hub: [f64; 2], reach: f64) -> usize {
    let n = points.len();
    let beyond = |i: &usize| dist(points[*i], hub) > reach;
    if at_start {
        (0..n).find(beyond).unwrap_or(n - 1)
    } else {
        (0..n).rev().find(beyond).unwrap_or(0)
    }
}

/// Where [`cut_arm`] would cut.
pub(super) fn cut_point(edge: &Edge, at_start: bool, hub: [f64; 2], reach: f64) -> [f64; 2] {
    edge.points[cut_index(&edge.points, at_start, hub, reach)]
}

/// Cuts an arm's polyline where it first leaves the disk of radius `reach` around `hub` (from its
/// start when `at_start`, else from its end) and joins it straight to `hub`.
pub(super) fn cut_arm(edge: &mut Edge, at_start: bool, hub: [f64; 2], reach: f64) {
    let cut = cut_index(&edge.points, at_start, hub, reach);
    if at_start {
        let width = edge.widths.first().copied().unwrap_or(MIN_WIDTH_PX);
        edge.points.drain(..cut);
        edge.widths.drain(..cut);
        edge.points.insert(0, hub);
        edge.widths.insert(0, width);
    } else {
        let width = edge.widths.last().copied().unwrap_or(MIN_WIDTH_PX);
        edge.points.truncate(cut + 1);
        edge.widths.truncate(cut + 1);
        edge.points.push(hub);
        edge.widths.push(width);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::median::upper_median;

    #[test]
    fn the_median_by_integer_keys_is_the_total_order_median() {
        // Half-widths of the distance transform (square roots of integers, many repeats), and
        // values of every kind: zeros of both signs, negatives, infinities, NaNs of both signs,
        // on the stack and beyond it.
        let mut next = crate::synth::lcg(2468u64);
        let specials = [
            0.0,
            -0.0,
            -1.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
        ];
        for case in 0..20_000 {
            let n = (next() >> 33) as usize % 150;
            let mut widths: Vec<f64> = Vec::with_capacity(n);
            for i in 0..n {
                let r = next() >> 11;
                let w = if case % 3 == 0 && r % 5 == 0 {
                    specials[(r / 5) as usize % specials.len()]
                } else if case % 3 == 1 {
                    // A distance transform's few levels, some edges with more than
                    // `FEW_WIDTHS` of them, in runs or not.
                    let levels = 1 + case % 11;
                    if (r >> 20) % 4 != 0 && i > 0 {
                        widths[i - 1]
                    } else {
                        ((((r % levels as u64) + 1) as f64).sqrt() * 2.0 - 1.0).max(0.0)
                    }
                } else {
                    (((r % 40) + 1) as f64).sqrt() / 2.0
                };
                widths.push(w);
            }
            let old = upper_median(&mut widths.clone()).unwrap_or(MIN_WIDTH_PX);
            assert_eq!(median(&widths).to_bits(), old.to_bits(), "{widths:?}");
        }
    }

    /// [`Ink::clearance`] as it was first written: every pixel of each square ring around
    /// `p`'s own, ring after ring.
    fn clearance_by_rings(ink: &Ink, p: [f64; 2], limit: f64) -> f64 {
        let (x, y) = (p[0] - ink.origin[0], p[1] - ink.origin[1]);
        let (cx, cy) = (x.floor(), y.floor());
        let k = limit.max(0.0).ceil() as i64 + 1;
        let none = limit.max(0.0) + 1.0;
        let mut best = none * none;
        let mut found = false;
        let mut visit = |dx: i64, dy: i64, best: &mut f64| {
            let (qx, qy) = (cx + dx as f64 + 0.5, cy + dy as f64 + 0.5);
            if !ink.at_window(qx, qy) {
                let (ex, ey) = (qx - x, qy - y);
                let d = ex * ex + ey * ey;
                if d < *best {
                    *best = d;
                    found = true;
                }
            }
        };
        for r in 0..=k {
            let inner = r as f64 - 0.5;
            if inner > 0.0 && inner * inner > best {
                break;
            }
            if r == 0 {
                visit(0, 0, &mut best);
                continue;
            }
            for d in -r..=r {
                visit(d, -r, &mut best);
                visit(d, r, &mut best);
            }
            for d in 1 - r..r {
                visit(-r, d, &mut best);
                visit(r, d, &mut best);
            }
        }
        if found {
            best.sqrt()
        } else {
            none
        }
    }

    #[test]
    fn the_clearance_by_rows_is_the_clearance_by_rings_bit_for_bit() {
        // Windows of every shape from a pixel on, mostly ink (wide strokes, so the searches go
        // several rows out) or sparse; points inside, on pixel edges and corners, beside and far
        // from the window, and not numbers; limits from below zero to beyond the window.
        let mut next = crate::synth::lcg(1357u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        for case in 0..4_000 {
            let width = 1 + (unit() * 24.0) as usize;
            let height = 1 + (unit() * 24.0) as usize;
            let density = if case % 4 == 0 { 0.3 } else { 0.9 };
            let mask = (0..width * height).map(|_| unit() < density).collect();
            let origin = [
                (unit() * 2000.0).floor() - 1000.0,
                (unit() * 3.0).floor() + unit(),
            ];
            let ink = Ink {
                mask,
                width,
                height,
                origin,
            };
            for _ in 0..50 {
                let mut coordinate = |extent: usize| {
                    let v = (unit() * (extent as f64 + 12.0) - 6.0).max(-6.0);
                    match (unit() * 10.0) as u32 {
                        0 => v.floor(),
                        1 => v.floor() + 0.5,
                        _ => v,
                    }
                };
                let local = [coordinate(width), coordinate(height)];
                let mut p = [origin[0] + local[0], origin[1] + local[1]];
                match case % 50 {
                    1 => p[0] = f64::NAN,
                    2 => p[1] = f64::INFINITY,
                    3 => p[0] = 1e300,
                    4 => p[1] = -1e19,
                    _ => {}
                }
                let limit = match (unit() * 20.0) as u32 {
                    0 => -1.0,
                    1 => f64::NAN,
                    2 => 0.0,
                    _ => unit() * 12.0,
                };
                let rows = ink.clearance(p, limit);
                let rings = clearance_by_rings(&ink, p, limit);
                assert_eq!(rows.to_bits(), rings.to_bits(), "{p:?} {limit} {origin:?}");
            }
        }
    }
}
