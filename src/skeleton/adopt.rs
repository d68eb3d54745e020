//! Adoption of the method's lines: §3.4's fitted polyline replaces a skeleton edge where the two
//! follow each other ([`Work::adopt_method_geometry`], [`follows`]). docs/design.md,
//! "Skeleton-carried geometry".

use foldhash::fast::FixedState;
use kiddo::{ImmutableKdTree, SquaredEuclidean};

use crate::csr::Csr;
use crate::geometry::{bounds, floor_i64};
use crate::stroke_graph::StrokeGraph;

use super::work::{median, Work};
use super::MIN_WIDTH_PX;

/// A skeleton vertex is matched to a method vertex within the stroke width and at least this
/// (px): the method's vertices sit within a pixel or two of the skeleton's on a hairline.
const MATCH_REACH_PX: f64 = 2.0;

/// A skeleton edge and a method's line follow each other when no point of either lies farther
/// than this many stroke widths from the other (and [`FOLLOW_LOOSE_PX`]): the method's line
/// keeps to this stroke's ink.
const FOLLOW_LOOSE: f64 = 0.5;

/// See [`FOLLOW_LOOSE`] (px).
const FOLLOW_LOOSE_PX: f64 = 1.0;

/// ...and all but a tenth of their points lie within this (px) of the other: the skeleton's
/// pixel path and a centred line differ by about half a pixel.
const FOLLOW_TIGHT_PX: f64 = 1.0;

impl Work {
    /// Geometry where the method is right (§3.4's fitted polylines, smooth and centred below
    /// a pixel): a skeleton vertex is matched to the nearest of the method's vertices of the
    /// same kind (an end to an end, a junction to a junction of the same degree) within
    /// `max(2 px, w)` ([`MATCH_REACH_PX`]), and a skeleton edge between two matched vertices
    /// takes the polyline of the method's edge between their partners when the two lie within
    /// `max(1 px, w / 2)` of each other everywhere ([`FOLLOW_LOOSE`]) and within 1 px for 90 %
    /// of their points ([`FOLLOW_TIGHT_PX`]), on the ink (so the method's line keeps to this
    /// stroke's ink). The
    /// skeleton keeps its own paths wherever the method's graph differs: chords, fused
    /// junctions, lost arms and loops (docs/quality.md, "Fidelity directions").
    pub(super) fn adopt_method_geometry(&mut self, method: &StrokeGraph) {
        let Some(mut partner) = self.match_vertices(method) else {
            return;
        };
        let moved = self.take_method_lines(method, &mut partner);
        self.move_to_partners(method, &partner, &moved);
    }

    /// Step 1: each skeleton end and junction's partner among the method's vertices (or
    /// `usize::MAX`), nearest pairs first, each vertex matched once; `None` when the method
    /// has no vertex to match.
    fn match_vertices(&self, method: &StrokeGraph) -> Option<Vec<usize>> {
        if method.vertices.is_empty() {
            return None;
        }
        let positions: Vec<[f64; 2]> = method.vertices.iter().map(|v| v.pos).collect();
        let tree = ImmutableKdTree::<f64, 2>::new_from_slice(&positions).ok()?;
        let degree = self.degrees();
        let at = self.incident();
        // The stroke width at a vertex: the widest median of its edges.
        let stroke_at = |v: usize| {
            at.row(v)
                .iter()
                .filter_map(|&e| self.edges[e].as_ref())
                .map(|e| median(&e.widths))
                .fold(MIN_WIDTH_PX, f64::max)
        };
        let mut partner = vec![usize::MAX; self.vertices.len()];
        let mut taken = vec![false; method.vertices.len()];
        let mut order: Vec<(f64, usize, usize)> = Vec::new();
        for v in (0..self.vertices.len()).filter(|&v| self.alive[v] && degree[v] != 2) {
            if degree[v] == 0 {
                continue;
            }
            let reach = stroke_at(v).max(MATCH_REACH_PX);
            let pos = self.vertices[v].pos;
            for found in tree
                .query(&pos)
                .within::<SquaredEuclidean<f64>>(reach * reach)
                .execute()
            {
                let m = found.item as usize;
                let dm = method.vertices[m].degree;
                if (degree[v] == 1 && dm == 1) || (degree[v] >= 3 && dm == degree[v]) {
                    order.push((found.distance, v, m));
                }
            }
        }
        // Nearest pairs first, each vertex matched once.
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        for (_, v, m) in order {
            if partner[v] == usize::MAX && !taken[m] {
                partner[v] = m;
                taken[m] = true;
            }
        }
        Some(partner)
    }

    /// Step 2: each skeleton edge between two partnered vertices (or a ring without a
    /// junction) takes the closest of the method's edges between their partners that keeps to
    /// the ink and [`follows`] it; each method edge is taken once. A ring's vertex gets the
    /// partner of the ring it took. Returns the vertices whose edges took a method line.
    fn take_method_lines(&mut self, method: &StrokeGraph, partner: &mut [usize]) -> Vec<bool> {
        let mut method_at = vec![Vec::new(); method.vertices.len()];
        for (f, edge) in method.edges.iter().enumerate() {
            method_at[edge.from].push(f);
            if edge.to != edge.from {
                method_at[edge.to].push(f);
            }
        }
        let degree = self.degrees();
        let mut used = vec![false; method.edges.len()];
        let mut moved = vec![false; self.vertices.len()];
        // The method's closed curves without a junction (a ring, a closed ridge).
        let method_rings: Vec<(usize, [f64; 4])> = method
            .edges
            .iter()
            .enumerate()
            .filter(|(_, f)| f.from == f.to && method.vertices[f.from].degree == 2)
            .map(|(f, edge)| (f, bbox(&edge.points)))
            .collect();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            let loose = (FOLLOW_LOOSE * median(&edge.widths)).max(FOLLOW_LOOSE_PX);
            let ring = edge.from == edge.to && degree[edge.from] == 2;
            let candidates: Vec<(usize, bool)> = if ring {
                let b = bbox(&edge.points);
                method_rings
                    .iter()
                    .filter(|(_, r)| {
                        r[0] <= b[2] + loose
                            && b[0] <= r[2] + loose
                            && r[1] <= b[3] + loose
                            && b[1] <= r[3] + loose
                    })
                    .map(|&(f, _)| (f, true))
                    .collect()
            } else {
                let (a, b) = (partner[edge.from], partner[edge.to]);
                if a == usize::MAX || b == usize::MAX {
                    continue;
                }
                method_at[a]
                    .iter()
                    .map(|&f| (f, &method.edges[f]))
                    .filter(|(_, c)| (c.from == a && c.to == b) || (c.from == b && c.to == a))
                    .map(|(f, c)| (f, c.from == a && c.to == b))
                    .collect()
            };
            let mut best: Option<(f64, usize, bool)> = None;
            for (f, forward) in candidates {
                if used[f] {
                    continue;
                }
                let line = &method.edges[f].points;
                if !line.windows(2).all(|s| self.ink.holds(s[0], s[1])) {
                    continue;
                }
                if let Some(gap) = follows(&edge.points, line, FOLLOW_TIGHT_PX, loose) {
                    if best.is_none_or(|(g, ..)| gap < g) {
                        best = Some((gap, f, forward));
                    }
                }
            }
            if ring {
                if let Some((_, f, _)) = best {
                    partner[edge.from] = method.edges[f].from;
                }
            }
            let Some((_, f, forward)) = best else {
                continue;
            };
            used[f] = true;
            let source = &method.edges[f];
            let mut points = source.points.clone();
            let mut widths = source.widths.clone();
            let mut directions = source.directions.clone();
            if !forward {
                points.reverse();
                widths.reverse();
                directions.reverse();
                for d in &mut directions {
                    *d = [-d[0], -d[1]];
                }
            }
            let edge = self.edges[e].as_mut().expect("live edge");
            edge.points = points;
            edge.widths = widths;
            edge.directions = directions;
            for v in [edge.from, edge.to] {
                moved[v] = true;
            }
        }
        moved
    }

    /// Step 3: the vertices whose edges took the method's lines sit where the method put them;
    /// the skeleton edges that meet them there are joined to the new position.
    fn move_to_partners(&mut self, method: &StrokeGraph, partner: &[usize], moved: &[bool]) {
        let at = self.incident();
        for v in (0..self.vertices.len()).filter(|&v| moved[v]) {
            let pos = method.vertices[partner[v]].pos;
            self.vertices[v].pos = pos;
            for &e in at.row(v) {
                let Some(edge) = self.edges[e].as_mut() else {
                    continue;
                };
                if edge.from == v {
                    edge.points[0] = pos;
                }
                if edge.to == v {
                    let last = edge.points.len() - 1;
                    edge.points[last] = pos;
                }
            }
        }
    }
}

/// The bounding box `[min x, min y, max x, max y]` of a polyline.
fn bbox(points: &[[f64; 2]]) -> [f64; 4] {
    points.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        },
    )
}

/// How closely two polylines follow each other: `None` when a point of either lies farther than
/// `loose` from the other, or when more than a tenth of either's points lie farther than
/// `tight`; else the largest distance.
fn follows(p: &[[f64; 2]], q: &[[f64; 2]], tight: f64, loose: f64) -> Option<f64> {
    if p.is_empty() || q.is_empty() {
        return None;
    }
    Some(directed_gap(p, q, tight, loose)?.max(directed_gap(q, p, tight, loose)?))
}

/// [`follows`] one way: the largest distance from a point of `from` to the polyline `to`, or
/// `None` when one lies farther than `loose` or more than a tenth farther than `tight`.
fn directed_gap(from: &[[f64; 2]], to: &[[f64; 2]], tight: f64, loose: f64) -> Option<f64> {
    // Squared distances, compared with squared bounds.
    let (tight2, loose2) = (tight * tight, loose * loose);
    let segments: Vec<([f64; 2], [f64; 2])> = match to {
        [only] => vec![(*only, *only)],
        _ => to.windows(2).map(|s| (s[0], s[1])).collect(),
    };
    // A point farther than `loose` (and a micrometre of a pixel, far above the rounding of the
    // closest point) outside `to`'s box on one axis is farther than `loose` from each segment.
    let (lo, hi) = bounds(to);
    let reach = loose + 1e-6;
    if from.iter().any(|x| {
        x[0] < lo[0] - reach || x[0] > hi[0] + reach || x[1] < lo[1] - reach || x[1] > hi[1] + reach
    }) {
        return None;
    }
    // The segments of `to` bucketed in square cells at least `2 loose` across, so a point only
    // looks at the segments of the (at most four) cells within `loose` of it: linear in the
    // points, however long the lines (a page-long stroke has tens of thousands).
    let grid = SegmentGrid::new(&segments, (2.0 * loose).max(4.0), lo, hi);
    let mut worst = 0.0f64;
    let mut off = 0;
    for &x in from {
        let mut d2 = f64::INFINITY;
        grid.near(x, loose, |k| {
            let (a, b) = segments[k];
            d2 = d2.min(crate::geometry::segment_dist2(x, a, b));
        });
        if d2 > loose2 {
            return None;
        }
        if d2 > tight2 {
            off += 1;
        }
        worst = worst.max(d2);
    }
    (off * 10 <= from.len()).then_some(worst.sqrt())
}

/// Segments bucketed by the square cells (`cell` px, cell `(i, j)` covering `[i cell, (i + 1)
/// cell)` on x and likewise on y) that their boxes cover: a dense table over the segments' own
/// box when it has at most a few cells per segment, else a hash map of the cells used (a long
/// diagonal stroke's box is mostly empty).
enum SegmentGrid {
    Dense {
        cell: f64,
        first: [i64; 2],
        columns: i64,
        rows: i64,
        /// Each cell's segments, row by row of cells.
        cells: Csr<u32>,
    },
    Sparse {
        cell: f64,
        // A fixed-seed hasher: the buckets' order is never read, only their contents.
        buckets: std::collections::HashMap<(i64, i64), Vec<usize>, FixedState>,
    },
}

impl SegmentGrid {
    /// The grid of `segments`, whose points lie in the box `lo`-`hi`.
    fn new(segments: &[([f64; 2], [f64; 2])], cell: f64, lo: [f64; 2], hi: [f64; 2]) -> Self {
        let key = |v: f64| floor_i64(v / cell);
        let covered = |(a, b): ([f64; 2], [f64; 2])| {
            (
                key(a[0].min(b[0]))..=key(a[0].max(b[0])),
                key(a[1].min(b[1]))..=key(a[1].max(b[1])),
            )
        };
        let first = [key(lo[0]), key(lo[1])];
        let (columns, rows) = (key(hi[0]) - first[0] + 1, key(hi[1]) - first[1] + 1);
        if columns.saturating_mul(rows) > 4 * segments.len() as i64 + 64 {
            let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>, FixedState> =
                std::collections::HashMap::default();
            for (k, &s) in segments.iter().enumerate() {
                let (xs, ys) = covered(s);
                for cx in xs {
                    for cy in ys.clone() {
                        buckets.entry((cx, cy)).or_default().push(k);
                    }
                }
            }
            return SegmentGrid::Sparse { cell, buckets };
        }
        let index = |cx: i64, cy: i64| ((cy - first[1]) * columns + (cx - first[0])) as usize;
        // Each cell's segments in rising order.
        let cells = Csr::build((columns * rows) as usize, |sink| {
            for (k, &s) in segments.iter().enumerate() {
                let (xs, ys) = covered(s);
                for cx in xs {
                    for cy in ys.clone() {
                        sink.push(index(cx, cy), k as u32);
                    }
                }
            }
        });
        SegmentGrid::Dense {
            cell,
            first,
            columns,
            rows,
            cells,
        }
    }

    /// Calls `visit` with every segment of every cell within `reach` of `x` on both axes (a
    /// segment may come more than once).
    fn near(&self, x: [f64; 2], reach: f64, mut visit: impl FnMut(usize)) {
        match self {
            SegmentGrid::Dense {
                cell,
                first,
                columns,
                rows,
                cells,
            } => {
                let key = |v: f64| floor_i64(v / cell);
                // Cells outside the table hold no segment.
                let (x0, x1) = (
                    key(x[0] - reach).max(first[0]),
                    key(x[0] + reach).min(first[0] + columns - 1),
                );
                let (y0, y1) = (
                    key(x[1] - reach).max(first[1]),
                    key(x[1] + reach).min(first[1] + rows - 1),
                );
                for cy in y0..=y1 {
                    for cx in x0..=x1 {
                        let i = ((cy - first[1]) * columns + (cx - first[0])) as usize;
                        for &k in cells.row(i) {
                            visit(k as usize);
                        }
                    }
                }
            }
            SegmentGrid::Sparse { cell, buckets } => {
                let key = |v: f64| floor_i64(v / cell);
                for cx in key(x[0] - reach)..=key(x[0] + reach) {
                    for cy in key(x[1] - reach)..=key(x[1] + reach) {
                        for &k in buckets.get(&(cx, cy)).map_or(&[][..], Vec::as_slice) {
                            visit(k);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`follows`] as it was: every segment of the other line bucketed in a hash map, every
    /// point looked up in it.
    fn follows_by_hash_map(p: &[[f64; 2]], q: &[[f64; 2]], tight: f64, loose: f64) -> Option<f64> {
        let (tight2, loose2) = (tight * tight, loose * loose);
        let cell = (2.0 * loose).max(4.0);
        let key = |v: f64| floor_i64(v / cell);
        let directed = |from: &[[f64; 2]], to: &[[f64; 2]]| -> Option<f64> {
            let segments: Vec<([f64; 2], [f64; 2])> = match to {
                [only] => vec![(*only, *only)],
                _ => to.windows(2).map(|s| (s[0], s[1])).collect(),
            };
            let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>, FixedState> =
                std::collections::HashMap::default();
            for (k, &(a, b)) in segments.iter().enumerate() {
                for cx in key(a[0].min(b[0]))..=key(a[0].max(b[0])) {
                    for cy in key(a[1].min(b[1]))..=key(a[1].max(b[1])) {
                        buckets.entry((cx, cy)).or_default().push(k);
                    }
                }
            }
            let mut worst = 0.0f64;
            let mut off = 0;
            for &x in from {
                let mut d2 = f64::INFINITY;
                for cx in key(x[0] - loose)..=key(x[0] + loose) {
                    for cy in key(x[1] - loose)..=key(x[1] + loose) {
                        for &k in buckets.get(&(cx, cy)).map_or(&[][..], Vec::as_slice) {
                            let (a, b) = segments[k];
                            d2 = d2.min(crate::geometry::segment_dist2(x, a, b));
                        }
                    }
                }
                if d2 > loose2 {
                    return None;
                }
                if d2 > tight2 {
                    off += 1;
                }
                worst = worst.max(d2);
            }
            (off * 10 <= from.len()).then_some(worst.sqrt())
        };
        if p.is_empty() || q.is_empty() {
            return None;
        }
        Some(directed(p, q)?.max(directed(q, p)?))
    }

    /// `follows` gives what the hash-map buckets gave, bit for bit, on random pairs of lines:
    /// a pixel path and a smoother line beside it (a pixel or so off, sometimes a stretch
    /// farther), short and long (the long diagonal ones take the hash map), single points,
    /// lines exactly `loose` off.
    #[test]
    fn follows_is_the_hash_map_one() {
        let mut next = crate::synth::lcg(4411u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let (mut some, mut none) = (0, 0);
        for case in 0..3000 {
            let n = [1, 2, 5, 30, 200, 1500][case % 6];
            let step = [[1.0, 0.0], [1.0, 1.0], [0.7, 0.3], [0.0, -1.0]][(unit() * 4.0) as usize];
            let start = [
                (unit() * 500.0).floor() + 0.5,
                (unit() * 500.0).floor() + 0.5,
            ];
            let skeleton: Vec<[f64; 2]> = (0..n)
                .map(|i| {
                    let wiggle = if unit() < 0.3 { 1.0 } else { 0.0 };
                    [
                        (start[0] + i as f64 * step[0]).floor() + 0.5,
                        (start[1] + i as f64 * step[1] + wiggle).floor() + 0.5,
                    ]
                })
                .collect();
            let offset = [0.0, 0.3, 0.9, 1.5, 3.0][(unit() * 5.0) as usize];
            let every = 1 + (unit() * 6.0) as usize;
            let mut method: Vec<[f64; 2]> = skeleton
                .iter()
                .step_by(every)
                .map(|p| {
                    [
                        p[0] + (unit() - 0.5) * offset,
                        p[1] + (unit() - 0.5) * offset,
                    ]
                })
                .collect();
            if unit() < 0.2 && method.len() > 4 {
                // A stretch that wanders off.
                let k = method.len() / 2;
                method[k][1] += 2.0 + unit() * 4.0;
            }
            if unit() < 0.1 {
                method.reverse();
            }
            let loose = [1.0, 1.5, 2.0, 3.25][(unit() * 4.0) as usize];
            let tight = 1.0;
            for (a, b) in [(&skeleton, &method), (&method, &skeleton)] {
                let ours = follows(a, b, tight, loose);
                let theirs = follows_by_hash_map(a, b, tight, loose);
                assert_eq!(
                    ours.map(f64::to_bits),
                    theirs.map(f64::to_bits),
                    "case {case}: {ours:?} {theirs:?}"
                );
                if ours.is_some() {
                    some += 1;
                } else {
                    none += 1;
                }
            }
        }
        assert!(some > 500 && none > 500, "{some} followed, {none} not");
    }
}
