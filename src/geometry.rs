//! Plane geometry every stage shares: distances to points and segments, walking a polyline by arc
//! length, the point-in-polygon test, the tangents of a polyline, the 2x2 PCA of §3.1 (Eq. (2)-(3) in two dimensions), the point nearest to a set of lines
//! (a junction's arms, §3.4) and a total order on `f64` for heap keys.
//!
//! Ground floor: plain functions on `[f64; 2]`, no stage types. The distances, the polygon test
//! and the tangents are public, for measuring a [`StrokeGraph`](crate::StrokeGraph) against other
//! geometry (the test kit's scorer and synthetic cases use them rather than copies); the arc-length
//! walk (§3.4's resampling, the minutiae's arm directions), the PCA and the float order are the
//! stages' own.

/// Euclidean distance.
#[inline]
pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    hypot(a[0] - b[0], a[1] - b[1])
}

/// `dist(a, b).partial_cmp(&r)`, the distance itself taken only where [`dist_bounds`] leave
/// the answer open: the stages compare hundreds of thousands of distances a page with a radius
/// or a reach (a pen's disk over its pixels, the points of an arm beyond a reach), and the
/// bounds cost a square root where [`hypot`] costs its correction step besides
/// (docs/performance.md, "Session of 2026-12-08, eighteenth").
#[inline]
pub(crate) fn cmp_dist(a: [f64; 2], b: [f64; 2], r: f64) -> Option<std::cmp::Ordering> {
    if let Some((low, high)) = dist_bounds(a, b) {
        if high < r {
            return Some(std::cmp::Ordering::Less);
        }
        if low > r {
            return Some(std::cmp::Ordering::Greater);
        }
    }
    dist(a, b).partial_cmp(&r)
}

/// Bounds `low <= dist(a, b) <= high`: the square root of the rounded sum of the rounded
/// squares, widened by a billionth of itself and `1e-150`. That root lies within about 2.5
/// units in the last place of the exact distance of the same differences, and [`hypot`] within
/// one (the library's bound), both far inside the billionth; where the squares underflow, the
/// root is off by less than `1e-160`. `None` where the root is not finite (a NaN or infinite
/// coordinate, or squares that overflow): no bound is claimed there.
#[inline]
pub(crate) fn dist_bounds(a: [f64; 2], b: [f64; 2]) -> Option<(f64, f64)> {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    let rough = (dx * dx + dy * dy).sqrt();
    if !rough.is_finite() {
        return None;
    }
    let margin = 1e-9 * rough + 1e-150;
    Some((rough - margin, rough + margin))
}

/// `x.hypot(y)`, bit for bit as the GNU C library (2.35 and later) computes it, inlined: the
/// stages take millions of lengths a page, and the library call was 3.6 % of a page's time
/// (docs/performance.md, "Session of 2026-12-05: pages, again"). For `ax >= ay`, the absolute
/// values, with neither huge nor tiny: `ax + ay` when `ay <= ax 2^-54`, else `h = sqrt(ax^2 +
/// ay^2)` corrected by one step of Borges' "An Improved Algorithm for hypot(a, b)" (the
/// library's kernel without a fused multiply-add). Infinite, NaN, huge (above `2^511`) and tiny
/// (below `2^-511`) arguments go to the library, which scales them.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    const LARGE: f64 = 6.703903964971299e153; // 2^511
    const TINY: f64 = 1.4916681462400413e-154; // 2^-511
    const EPS: f64 = 5.551115123125783e-17; // 2^-54
    let (x, y) = (x.abs(), y.abs());
    let (ax, ay) = if x < y { (y, x) } else { (x, y) };
    // Lengths along a row or column of pixels (the library's `ax + ay` for a zero `ay`).
    if ay == 0.0 && ax <= LARGE {
        return ax;
    }
    // Also false for NaN, whose comparisons fail.
    if !(ax <= LARGE && ay >= TINY) {
        return x.hypot(y);
    }
    if ay <= ax * EPS {
        return ax + ay;
    }
    let h = (ax * ax + ay * ay).sqrt();
    let (t1, t2) = if h <= 2.0 * ay {
        let delta = h - ay;
        (ax * (2.0 * delta - ax), (delta - 2.0 * (ax - ay)) * delta)
    } else {
        let delta = h - ax;
        (
            2.0 * delta * (ax - 2.0 * ay),
            (4.0 * delta - ay) * ay + delta * delta,
        )
    };
    h - (t1 + t2) / (2.0 * h)
}

/// `x.floor() as i64`, the same for every `f64` (NaN gives 0, the far ones saturate), without the
/// library call that `f64::floor` is on x86-64 without SSE4.1: a truncation, one down where it
/// went up. The stages look up pixels by it (`floor(x)` is the pixel of `x`) millions of times
/// a page (docs/performance.md). Between -2⁶³ and 2⁶³ the truncation needs no saturation: one
/// instruction where the saturating `as` adds its checks for NaN and the far values.
#[inline]
pub(crate) fn floor_i64(x: f64) -> i64 {
    const FAR: f64 = 9_223_372_036_854_775_808.0; // 2⁶³
    if x > -FAR && x < FAR {
        // SAFETY: -2⁶³ < x < 2⁶³ (so not NaN): its truncation fits an `i64`.
        let t = unsafe { x.to_int_unchecked::<i64>() };
        // One down only where `x` is negative and not whole: `t` is then above -2⁶³.
        return if (t as f64) > x { t - 1 } else { t };
    }
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// `x.floor()`, bit for bit for every `f64` but NaN (a NaN either way), without the library
/// call that `f64::floor` is on x86-64 without SSE4.1 (about 25 instructions a call, at a few
/// hundred thousand calls a page: docs/performance.md). Below 2⁵² in magnitude the truncation
/// is exact and one down where it went up; the floor has the sign of `x` (`-0.0` stays `-0.0`,
/// a value in (-1, 0) gives -1). From 2⁵² on every `f64` is whole, and infinities and NaN are
/// their own floor.
#[inline]
pub(crate) fn floor_f64(x: f64) -> f64 {
    const WHOLE: f64 = 4_503_599_627_370_496.0; // 2⁵²
    if x.abs() < WHOLE {
        // SAFETY: |x| < 2⁵² (so not NaN): its truncation fits an `i64`.
        let t = unsafe { x.to_int_unchecked::<i64>() } as f64;
        let f = if t > x { t - 1.0 } else { t };
        return f.copysign(x);
    }
    x
}

/// `x.ceil()`, bit for bit as [`floor_f64`] is the floor: `-floor(-x)` (a value in (-1, 0)
/// gives `-0.0`, as the library's).
#[inline]
pub(crate) fn ceil_f64(x: f64) -> f64 {
    -floor_f64(-x)
}

/// Cumulative arc length at each polyline point.
pub(crate) fn arc_lengths(polyline: &[[f64; 2]]) -> Vec<f64> {
    let mut s = Vec::with_capacity(polyline.len());
    let mut total = 0.0;
    for (i, p) in polyline.iter().enumerate() {
        if i > 0 {
            total += dist(polyline[i - 1], *p);
        }
        s.push(total);
    }
    s
}

/// The point at arc length `t` along a polyline with cumulative lengths `s`, and the index of the
/// segment it lies on (clamped to the ends).
pub(crate) fn point_at(polyline: &[[f64; 2]], s: &[f64], t: f64) -> ([f64; 2], usize) {
    let n = polyline.len();
    if n < 2 || t <= 0.0 {
        return (polyline.first().copied().unwrap_or([0.0, 0.0]), 0);
    }
    if t >= s[n - 1] {
        return (polyline[n - 1], n - 2);
    }
    // First point beyond t; the segment before it holds t.
    let j = s.partition_point(|&x| x <= t).clamp(1, n - 1);
    let (a, b) = (polyline[j - 1], polyline[j]);
    let len = s[j] - s[j - 1];
    let f = if len > 0.0 { (t - s[j - 1]) / len } else { 0.0 };
    ([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])], j - 1)
}

/// [`point_at`] for arc lengths that never decrease from one call to the next (resampling a
/// polyline from its start to its end): the segment is found by walking on from the last one,
/// not by a binary search each time; the same points and segments.
pub(crate) struct ArcWalk<'a> {
    polyline: &'a [[f64; 2]],
    s: &'a [f64],
    /// The number of cumulative lengths at most the last `t` (`point_at`'s partition point).
    passed: usize,
}

impl<'a> ArcWalk<'a> {
    /// A walk along `polyline` with cumulative lengths `s`.
    pub(crate) fn new(polyline: &'a [[f64; 2]], s: &'a [f64]) -> Self {
        ArcWalk {
            polyline,
            s,
            passed: 0,
        }
    }

    /// `point_at(polyline, s, t)`, `t` at least the last call's.
    pub(crate) fn at(&mut self, t: f64) -> ([f64; 2], usize) {
        let (polyline, s) = (self.polyline, self.s);
        let n = polyline.len();
        if n < 2 || t <= 0.0 {
            return (polyline.first().copied().unwrap_or([0.0, 0.0]), 0);
        }
        if t >= s[n - 1] {
            return (polyline[n - 1], n - 2);
        }
        while self.passed < n && s[self.passed] <= t {
            self.passed += 1;
        }
        let j = self.passed.clamp(1, n - 1);
        let (a, b) = (polyline[j - 1], polyline[j]);
        let len = s[j] - s[j - 1];
        let f = if len > 0.0 { (t - s[j - 1]) / len } else { 0.0 };
        ([a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])], j - 1)
    }
}

/// Euclidean distance from `p` to the segment `a`-`b`.
pub fn segment_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    segment_closest(p, a, b).0
}

/// Distance from `p` to the segment `a`-`b` and the parameter in `[0, 1]` of the closest point.
pub fn segment_closest(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let (q, t) = closest_on_segment(p, a, b);
    (dist(p, q), t)
}

/// Squared distance from `p` to the segment `a`-`b`, for comparisons against squared bounds
/// where a square root per point would cost (long polylines compared point by point).
pub(crate) fn segment_dist2(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (q, _) = closest_on_segment(p, a, b);
    let (x, y) = (q[0] - p[0], q[1] - p[1]);
    x * x + y * y
}

/// The point of the segment `a`-`b` closest to `p`, and its parameter in `[0, 1]`.
fn closest_on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ([a[0] + t * d[0], a[1] + t * d[1]], t)
}

/// Whether `p` lies inside the closed polygon (last point joined to the first), by the even-odd
/// rule. Points exactly on an edge may fall either way; fewer than three corners enclose nothing.
pub fn point_in_polygon(p: [f64; 2], polygon: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Unit tangents of a polyline by central differences (one-sided at its ends), as the
/// skeleton-carried tracing writes [`Edge::directions`](crate::Edge::directions); `[1, 0]` where
/// the two neighbours of a point coincide.
pub fn tangents(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i.saturating_sub(1)], points[(i + 1).min(n - 1)]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len = hypot(d[0], d[1]);
            if len > 0.0 {
                [d[0] / len, d[1] / len]
            } else {
                [1.0, 0.0]
            }
        })
        .collect()
}

/// Closed-form eigen-decomposition of the 2x2 covariance `[[cxx, cxy], [cxy, cyy]]`: the
/// linearity `l = λ_max / (λ_min + λ_max)` (Eq. (3) in 2-D, in `[0.5, 1]`) and the unit
/// eigenvector of `λ_max`, with a canonical sign (x > 0, or x = 0 and y > 0). A covariance with
/// no spread (trace at most 1e-12, or NaN) gives `(0.5, [1, 0])`.
///
/// A closed form rather than nalgebra's `SymmetricEigen` (which the tests check it against): it
/// runs at every growth step of every disk, and is about 6 times faster (1e6 covariances: 34 ms
/// against 217 ms in a release build, measured when the closed form was written).
pub(crate) fn principal(cxx: f64, cxy: f64, cyy: f64) -> (f64, [f64; 2]) {
    let trace = cxx + cyy;
    if trace.is_nan() || trace <= 1e-12 {
        return (0.5, [1.0, 0.0]);
    }
    let half_diff = (cxx - cyy) / 2.0;
    let root = (half_diff * half_diff + cxy * cxy).sqrt();
    let lambda_max = trace / 2.0 + root;
    let linearity = (lambda_max / trace).clamp(0.5, 1.0);
    // Eigenvector of λ_max; pick the better-conditioned of the two forms.
    let direction = if cxy.abs() > 1e-12 {
        let v = [lambda_max - cyy, cxy];
        let norm = hypot(v[0], v[1]);
        [v[0] / norm, v[1] / norm]
    } else if cxx >= cyy {
        [1.0, 0.0]
    } else {
        [0.0, 1.0]
    };
    // A canonical sign keeps results independent of accumulation order.
    if direction[0] < 0.0 || (direction[0] == 0.0 && direction[1] < 0.0) {
        (linearity, [-direction[0], -direction[1]])
    } else {
        (linearity, direction)
    }
}

/// `f64` with a total order ([`f64::total_cmp`]), for heap and sort keys.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TotalF64(pub f64);

impl Eq for TotalF64 {}

impl PartialOrd for TotalF64 {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for TotalF64 {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The paths among those `moved` that cross or touch another path, or themselves, other than
/// where two segments share an end point; in rising order. `None` is a removed path.
pub(crate) fn crossing_paths(paths: &[Option<&[[f64; 2]]>], moved: &[bool]) -> Vec<usize> {
    const CELL_PX: f64 = 4.0;
    let key = |v: f64| floor_i64(v / CELL_PX);
    // Every segment under every cell its box covers, sorted by cell: a cell's segments are one
    // run of the list, in the order of their paths and their places along them. One `u64` each:
    // the cell's two coordinates (16 bits each; a wider page folds far-apart cells together,
    // which only adds pairs to test) above the segment's number. A segment keeps its path, its
    // place along it and its two end points (read once, not through its path at every pair).
    let count: usize = paths
        .iter()
        .flatten()
        .map(|path| path.len().saturating_sub(1))
        .sum();
    let mut segments: Vec<Segment> = Vec::with_capacity(count);
    // Most segments lie under one or two cells.
    let mut cells: Vec<u64> = Vec::with_capacity(2 * count);
    let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
    for (e, path) in paths.iter().enumerate() {
        let Some(path) = path else { continue };
        for (k, s) in path.windows(2).enumerate() {
            let id = segments.len() as u64;
            let (low, high) = (
                [s[0][0].min(s[1][0]), s[0][1].min(s[1][1])],
                [s[0][0].max(s[1][0]), s[0][1].max(s[1][1])],
            );
            // Both fit in 32 bits: the keys below number the segments so, a path's places are
            // some of them, and 2^32 paths would be a list of 64 GiB.
            segments.push(Segment {
                path: e as u32,
                place: k as u32,
                ends: [s[0], s[1]],
                length: (s[1][0] - s[0][0]).abs() + (s[1][1] - s[0][1]).abs(),
            });
            let (x0, x1) = (key(low[0]), key(high[0]));
            let (y0, y1) = (key(low[1]), key(high[1]));
            lo = [lo[0].min(x0), lo[1].min(y0)];
            hi = [hi[0].max(x1), hi[1].max(y1)];
            for cx in x0..=x1 {
                for cy in y0..=y1 {
                    cells.push(((cx as u16 as u64) << 48) | ((cy as u16 as u64) << 32) | id);
                }
            }
        }
    }
    group_cells(&mut cells, lo, hi);
    let id = |cell: u64| &segments[(cell & u64::from(u32::MAX)) as usize];
    let mut crossing = vec![false; paths.len()];
    for run in cells.chunk_by(|a, b| a >> 32 == b >> 32) {
        for (i, &a) in run.iter().enumerate() {
            let a = id(a);
            for &b in &run[i + 1..] {
                let b = id(b);
                let (ap, bp) = (a.path as usize, b.path as usize);
                if !moved[ap] && !moved[bp] {
                    continue;
                }
                if crossing[ap] && crossing[bp] {
                    continue;
                }
                if a.path == b.path && a.place.abs_diff(b.place) <= 1 {
                    continue;
                }
                if boxes_apart(a, b) {
                    continue;
                }
                let ([a0, a1], [b0, b1]) = (a.ends, b.ends);
                if segments_meet(a0, a1, b0, b1) {
                    for e in [ap, bp] {
                        if moved[e] {
                            crossing[e] = true;
                        }
                    }
                }
            }
        }
    }
    (0..paths.len()).filter(|&e| crossing[e]).collect()
}

/// A segment of [`crossing_paths`]: its path, its place along the path, its end points and its
/// length in the 1-norm (`NaN` when a coordinate is). 48 bytes: the corners of its box are
/// worked out from its ends where a pair is tested ([`Segment::low`], [`Segment::high`]), not
/// kept, since a print's segments are alive at the run's peak of memory, and every fresh page
/// of the peak costs a page fault (docs/fingerprints.md, "Speed").
struct Segment {
    path: u32,
    place: u32,
    ends: [[f64; 2]; 2],
    length: f64,
}

impl Segment {
    /// The lower corner of the segment's box.
    #[inline]
    fn low(&self) -> [f64; 2] {
        let [p, q] = self.ends;
        [p[0].min(q[0]), p[1].min(q[1])]
    }

    /// The upper corner of the segment's box.
    #[inline]
    fn high(&self) -> [f64; 2] {
        let [p, q] = self.ends;
        [p[0].max(q[0]), p[1].max(q[1])]
    }
}

/// Whether the boxes of the segments `a` and `b` lie so far apart, along a row or a column,
/// that [`segments_meet`] cannot find a point in common: a few comparisons before its products
/// and quotients (most pairs under a cell are a path's segments a pixel or more apart along
/// it).
///
/// [`segments_meet`] accepts points up to `1e-9` of a segment's length beyond it, and its
/// quotients `t` and `u` of nearly parallel segments (down to `1e-12` of the product of their
/// lengths) carry a rounding of up to about `3.3e-4` of `|q| / |r|` and of `|t|` (`q` from `a`'s
/// first end to `b`'s, `r` and `s` the segments): the point they put in common lies at most
/// about `6.6e-4 |q| + 3.4e-4 (|r| + |s|)` outside either segment. The margin, `1e-2` of
/// `|q| + |r| + |s|` (in the 1-norm, at least the Euclidean one) and a millionth of a pixel,
/// holds that more than ten times over; the parallel branch meets within `1e-9` of a pixel
/// and of the lengths. A coordinate that is `NaN` or infinite makes the margin so, and the
/// boxes are not apart.
#[inline]
fn boxes_apart(a: &Segment, b: &Segment) -> bool {
    let (p, q) = (a.ends[0], b.ends[0]);
    let reach = (q[0] - p[0]).abs() + (q[1] - p[1]).abs() + a.length + b.length;
    let margin = 1e-2 * reach + 1e-6;
    let (a_low, a_high, b_low, b_high) = (a.low(), a.high(), b.low(), b.high());
    a_low[0] - b_high[0] > margin
        || b_low[0] - a_high[0] > margin
        || a_low[1] - b_high[1] > margin
        || b_low[1] - a_high[1] > margin
}

/// Orders [`crossing_paths`]'s keys so that each cell's are one run, in the order they were
/// pushed (rising segment numbers), as sorting them does: by a stable counting sort on the
/// cell's row, then on its column (two passes over the keys, a count per row and per column of
/// the cells `lo..=hi` cover), where sorting the keys cost `log n` passes. The runs may come in
/// another order than sorted keys' (the columns and rows are counted from `lo`, and a key's
/// 16 bits fold negative ones); which pairs a run holds is the same, and [`crossing_paths`]'s
/// answer does not depend on the order of the runs. Few keys, or a span of more than 2^16 cells
/// (where the 16 bits fold cells together), are sorted.
fn group_cells(cells: &mut Vec<u64>, lo: [i64; 2], hi: [i64; 2]) {
    let span = |k: usize| hi[k].saturating_sub(lo[k]).saturating_add(1);
    let spans = [span(0), span(1)];
    if cells.len() < 256
        || spans.iter().any(|&s| !(1..=1 << 16).contains(&s))
        || (spans[0] + spans[1]) as usize > cells.len()
    {
        cells.sort_unstable();
        return;
    }
    let mut other = vec![0u64; cells.len()];
    // Rows (bits 32-47) first, then columns (bits 48-63): stable, so the columns' pass keeps
    // the rows' order within a column, and both keep the push order within a cell.
    for (k, shift) in [(1, 32), (0, 48)] {
        let slot = |c: u64| usize::from(((c >> shift) as u16).wrapping_sub(lo[k] as u16));
        let mut start = vec![0usize; spans[k] as usize + 1];
        for &c in cells.iter() {
            start[slot(c) + 1] += 1;
        }
        for i in 1..start.len() {
            start[i] += start[i - 1];
        }
        for &c in cells.iter() {
            let s = &mut start[slot(c)];
            other[*s] = c;
            *s += 1;
        }
        std::mem::swap(cells, &mut other);
    }
}

/// Whether the closed segments `a0-a1` and `b0-b1` have a point in common other than an end
/// point they share.
///
/// The two tests against a length (parallel: the cross product against `1e-12 |r| |s|`; apart:
/// against `1e-9 |r|`) are first made on the squares, where the answer is clear by a factor of
/// four (far above the rounding of a few products, about 1e-15 of each): the lengths' square
/// roots ([`hypot`]) only where it is not, with the same outcome as measuring them always.
fn segments_meet(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> bool {
    let shared = [a0, a1]
        .iter()
        .any(|p| [b0, b1].iter().any(|q| p[0] == q[0] && p[1] == q[1]));
    let r = [a1[0] - a0[0], a1[1] - a0[1]];
    let s = [b1[0] - b0[0], b1[1] - b0[1]];
    let denom = r[0] * s[1] - r[1] * s[0];
    let q = [b0[0] - a0[0], b0[1] - a0[1]];
    let rr = r[0] * r[0] + r[1] * r[1];
    let ss = s[0] * s[0] + s[1] * s[1];
    // `|x| <= factor * max(length, 1e-300)`, `length²` being `squares` (`trusted`: made of
    // squared lengths from 1e-100 to 1e100, so that nothing below under- or overflows), decided
    // on the squares where that is clear, else as written.
    let moderate = |v: f64| (1e-100..=1e100).contains(&v);
    let within = |x: f64, factor: f64, squares: f64, trusted: bool, length: &dyn Fn() -> f64| {
        if x == 0.0 {
            return true;
        }
        if trusted && moderate(x.abs()) {
            let (x2, bound2) = (x * x, factor * factor * squares);
            if x2 > 4.0 * bound2 {
                return false;
            }
            if x2 < 0.25 * bound2 {
                return true;
            }
        }
        x.abs() <= factor * length().max(1e-300)
    };
    let (r_fine, s_fine) = (moderate(rr), moderate(ss));
    let both = || hypot(r[0], r[1]) * hypot(s[0], s[1]);
    if within(denom, 1e-12, rr * ss, r_fine && s_fine, &both) {
        // Parallel: they meet only when collinear and overlapping beyond a shared end.
        let across = q[0] * r[1] - q[1] * r[0];
        // Apart when `|across|` exceeds the bound (a NaN does not).
        if !across.is_nan() && !within(across, 1e-9, rr, r_fine, &|| hypot(r[0], r[1])) {
            return false;
        }
        if rr <= 0.0 {
            return false;
        }
        let t0 = (q[0] * r[0] + q[1] * r[1]) / rr;
        let t1 = t0 + (s[0] * r[0] + s[1] * r[1]) / rr;
        let (lo, hi) = (t0.min(t1), t0.max(t1));
        let overlap = hi.min(1.0) - lo.max(0.0);
        return if shared {
            overlap > 1e-9
        } else {
            overlap >= -1e-9
        };
    }
    let t = (q[0] * s[1] - q[1] * s[0]) / denom;
    let u = (q[0] * r[1] - q[1] * r[0]) / denom;
    let slack = -1e-9..=1.0 + 1e-9;
    if !(slack.contains(&t) && slack.contains(&u)) {
        return false;
    }
    // Non-parallel segments sharing an end point meet only there.
    !shared
}

/// The point minimizing the summed squared distances to lines `(point, unit direction)`:
/// `sum (I - d d^T) x = sum (I - d d^T) c`. `None` when the lines are (nearly) parallel, i.e. the
/// smaller eigenvalue of the normal matrix is below `min_eigen`.
///
/// The 2x2 system in closed form rather than through nalgebra (eigenvalues, then Cholesky; the
/// tests check the two agree): about 4 times faster (3e5 junctions of 3 arms: 8.6 ms against
/// 33.7 ms in a release build, measured when the closed form was written).
pub(crate) fn line_intersection(
    lines: &[([f64; 2], [f64; 2])],
    min_eigen: f64,
) -> Option<[f64; 2]> {
    let (mut a, mut b, mut d, mut rx, mut ry) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(c, u) in lines {
        // Projector onto the line's normal.
        let (pxx, pxy, pyy) = (1.0 - u[0] * u[0], -u[0] * u[1], 1.0 - u[1] * u[1]);
        a += pxx;
        b += pxy;
        d += pyy;
        rx += pxx * c[0] + pxy * c[1];
        ry += pxy * c[0] + pyy * c[1];
    }
    let det = a * d - b * b;
    let half_trace = 0.5 * (a + d);
    let smallest = half_trace - (half_trace * half_trace - det).max(0.0).sqrt();
    // Written so that a NaN eigenvalue is refused too.
    if smallest.partial_cmp(&min_eigen) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    Some([(d * rx - b * ry) / det, (a * ry - b * rx) / det])
}

/// The corners of a polyline's bounding box.
pub(crate) fn bounds(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    points.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}

/// `v / |v|`, or `None` for a (near) zero vector.
#[inline]
pub(crate) fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let n = hypot(v[0], v[1]);
    (n > 1e-12).then(|| [v[0] / n, v[1] / n])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`crossing_paths`] as it was: its keys sorted, every pair measured by
    /// [`segments_meet_measured`].
    fn crossing_paths_sorted(paths: &[Option<&[[f64; 2]]>], moved: &[bool]) -> Vec<usize> {
        let key = |v: f64| floor_i64(v / 4.0);
        let mut segments: Vec<(usize, usize)> = Vec::new();
        let mut cells: Vec<u64> = Vec::new();
        for (e, path) in paths.iter().enumerate() {
            let Some(path) = path else { continue };
            for (k, s) in path.windows(2).enumerate() {
                let id = segments.len() as u64;
                segments.push((e, k));
                for cx in key(s[0][0].min(s[1][0]))..=key(s[0][0].max(s[1][0])) {
                    for cy in key(s[0][1].min(s[1][1]))..=key(s[0][1].max(s[1][1])) {
                        cells.push(((cx as u16 as u64) << 48) | ((cy as u16 as u64) << 32) | id);
                    }
                }
            }
        }
        cells.sort_unstable();
        let segment = |(e, k): (usize, usize)| {
            let points = paths[e].expect("live path");
            (points[k], points[k + 1])
        };
        let id = |cell: u64| segments[(cell & u64::from(u32::MAX)) as usize];
        let mut crossing = vec![false; paths.len()];
        for run in cells.chunk_by(|a, b| a >> 32 == b >> 32) {
            for (i, &a) in run.iter().enumerate() {
                let a = id(a);
                for &b in &run[i + 1..] {
                    let b = id(b);
                    if !moved[a.0] && !moved[b.0] {
                        continue;
                    }
                    if crossing[a.0] && crossing[b.0] {
                        continue;
                    }
                    if a.0 == b.0 && a.1.abs_diff(b.1) <= 1 {
                        continue;
                    }
                    let ((a0, a1), (b0, b1)) = (segment(a), segment(b));
                    if segments_meet_measured(a0, a1, b0, b1) {
                        for e in [a.0, b.0] {
                            if moved[e] {
                                crossing[e] = true;
                            }
                        }
                    }
                }
            }
        }
        (0..paths.len()).filter(|&e| crossing[e]).collect()
    }

    /// [`segments_meet`] as it was: both lengths measured for every pair.
    fn segments_meet_measured(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> bool {
        let shared = [a0, a1]
            .iter()
            .any(|p| [b0, b1].iter().any(|q| p[0] == q[0] && p[1] == q[1]));
        let r = [a1[0] - a0[0], a1[1] - a0[1]];
        let s = [b1[0] - b0[0], b1[1] - b0[1]];
        let denom = r[0] * s[1] - r[1] * s[0];
        let q = [b0[0] - a0[0], b0[1] - a0[1]];
        let scale = hypot(r[0], r[1]) * hypot(s[0], s[1]);
        if denom.abs() <= 1e-12 * scale.max(1e-300) {
            // Parallel: they meet only when collinear and overlapping beyond a shared end.
            let across = q[0] * r[1] - q[1] * r[0];
            if across.abs() > 1e-9 * hypot(r[0], r[1]).max(1e-300) {
                return false;
            }
            let rr = r[0] * r[0] + r[1] * r[1];
            if rr <= 0.0 {
                return false;
            }
            let t0 = (q[0] * r[0] + q[1] * r[1]) / rr;
            let t1 = t0 + (s[0] * r[0] + s[1] * r[1]) / rr;
            let (lo, hi) = (t0.min(t1), t0.max(t1));
            let overlap = hi.min(1.0) - lo.max(0.0);
            return if shared {
                overlap > 1e-9
            } else {
                overlap >= -1e-9
            };
        }
        let t = (q[0] * s[1] - q[1] * s[0]) / denom;
        let u = (q[0] * r[1] - q[1] * r[0]) / denom;
        let slack = -1e-9..=1.0 + 1e-9;
        if !(slack.contains(&t) && slack.contains(&u)) {
            return false;
        }
        // Non-parallel segments sharing an end point meet only there.
        !shared
    }

    /// Zeros, the extremes, the bounds where [`hypot`] hands over to the library (2^-511 and
    /// 2^511), values whose squares underflow or overflow, the infinities and NaN.
    const SPECIAL: [f64; 17] = [
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        5e-324,
        1e-160,
        1.4916681462400413e-154,
        1e-150,
        1.0,
        1.0 + f64::EPSILON,
        1e150,
        6.703903964971299e153,
        1e154,
        1e300,
        f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];

    /// [`hypot`] gives the library's bits (the GNU C library's, whose algorithm it repeats) on
    /// the lengths the stages take (pixel steps, sub-pixel offsets, both signs, zeros), on
    /// near-equal sides, on sides 2^-54 and less apart in size, across the exponents, and on
    /// the huge, tiny, infinite and NaN arguments it hands to the library.
    #[test]
    fn hypot_is_the_library_hypot_bit_for_bit() {
        let mut next = crate::synth::lcg(2035u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let mut cases: Vec<(f64, f64)> = Vec::new();
        for a in -40..=40 {
            for b in -40..=40 {
                cases.push((a as f64 * 0.5, b as f64 * 0.5));
                cases.push((a as f64 + 0.25, b as f64 - 0.125));
            }
        }
        for &a in &SPECIAL {
            for &b in &SPECIAL {
                cases.push((a, b));
                cases.push((-a, b));
            }
        }
        for _ in 0..400_000 {
            let a = (unit() - 0.5) * 4000.0;
            let b = (unit() - 0.5) * 4000.0;
            cases.push((a, b));
            cases.push((a, a * (1.0 + (unit() - 0.5) * 1e-6)));
            cases.push((a, a * (unit() * 2f64.powi(-50))));
            let (ea, eb) = ((unit() * 1200.0) as i32 - 600, (unit() * 120.0) as i32 - 60);
            cases.push((a * 2f64.powi(ea), b * 2f64.powi(ea + eb)));
        }
        for (x, y) in cases {
            let (ours, library) = (hypot(x, y), x.hypot(y));
            assert!(
                ours.to_bits() == library.to_bits() || (ours.is_nan() && library.is_nan()),
                "hypot({x:e}, {y:e}) = {ours:e}, the library gives {library:e}"
            );
        }
    }

    /// [`cmp_dist`] answers as comparing [`dist`] does, and [`dist_bounds`] hold the distance:
    /// on pixel centres against pixel-like points and radii (many exactly at the distance, as
    /// 3-4-5 triangles and axis steps put them), on radii a few units in the last place from
    /// the distance, across the exponents (squares that underflow and overflow), and on
    /// infinite and NaN coordinates and radii.
    #[test]
    fn distance_comparisons_are_the_distances() {
        use std::cmp::Ordering;
        let mut next = crate::synth::lcg(2036u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let check = |a: [f64; 2], b: [f64; 2], r: f64| {
            let d = dist(a, b);
            assert_eq!(cmp_dist(a, b, r), d.partial_cmp(&r), "{a:?} {b:?} {r:e}");
            if let Some((low, high)) = dist_bounds(a, b) {
                assert!(
                    low <= d && d <= high,
                    "{a:?} {b:?}: {d:e} not in {low:e}..{high:e}"
                );
            }
        };
        for x in -12..=12 {
            for y in -12..=12 {
                let c = [x as f64 + 0.5, y as f64 + 0.5];
                for &p in &[[0.5, 0.5], [0.0, 0.0], [0.25, -0.75], [3.5, 4.5]] {
                    for k in 0..=40 {
                        check(c, p, k as f64 * 0.25);
                    }
                    let d = dist(c, p);
                    for step in -3i64..=3 {
                        let r = f64::from_bits((d.to_bits() as i64 + step).max(0) as u64);
                        check(c, p, r);
                    }
                }
            }
        }
        for &u in &SPECIAL {
            for &v in &SPECIAL {
                for &r in &SPECIAL {
                    check([u, v], [0.0, 0.0], r);
                    check([-u, 1.0], [v, 0.0], -r);
                }
            }
        }
        for _ in 0..300_000 {
            let e = (unit() * 1200.0) as i32 - 600;
            let s = 2f64.powi(e);
            let a = [(unit() - 0.5) * 4000.0 * s, (unit() - 0.5) * 4000.0 * s];
            let b = [(unit() - 0.5) * 4000.0 * s, (unit() - 0.5) * 4000.0 * s];
            let d = dist(a, b);
            check(a, b, d);
            check(a, b, d * (1.0 + (unit() - 0.5) * 1e-8));
            check(a, b, (unit() * 3000.0) * s);
            let near =
                f64::from_bits((d.to_bits() as i64 + (unit() * 9.0) as i64 - 4).max(0) as u64);
            check(a, b, near);
        }
        assert_eq!(cmp_dist([0.0, 0.0], [3.0, 4.0], 5.0), Some(Ordering::Equal));
    }

    #[test]
    fn segments_whose_boxes_lie_apart_do_not_meet() {
        // Pairs whose lines meet just beyond an end (by 1e-12 to 1e-1 of a length), at angles
        // from 1e-13 to 1 radian (the nearly parallel ones where `segments_meet`'s quotients
        // round most), lengths from a hundredth of a pixel to a page, pixel steps: wherever
        // `boxes_apart` skips a pair, `segments_meet` says apart.
        let mut next = crate::synth::lcg(2468u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let (mut skipped, mut kept) = (0, 0);
        for case in 0..400_000 {
            let (a0, a1, b0, b1) = if case % 4 == 0 {
                let pixel = |u: f64| (u * 8.0).floor() + 0.5;
                let step = |u: f64| ((u * 3.0).floor() - 1.0).max(-1.0);
                let a0 = [pixel(unit()), pixel(unit())];
                let b0 = [pixel(unit()), pixel(unit())];
                let a1 = [a0[0] + step(unit()), a0[1] + step(unit())];
                let b1 = [b0[0] + step(unit()), b0[1] + step(unit())];
                (a0, a1, b0, b1)
            } else {
                let scale = 10f64.powf(-2.0 + unit() * 5.5);
                let a0 = [unit() * 4000.0, unit() * 4000.0];
                let angle = unit() * std::f64::consts::TAU;
                let r = [angle.cos() * scale, angle.sin() * scale];
                let a1 = [a0[0] + r[0], a0[1] + r[1]];
                // The lines meet at `t` just outside `a`, `b` reaching towards it.
                let beyond = 10f64.powf(-12.0 + unit() * 11.0);
                let t = if unit() < 0.5 { 1.0 + beyond } else { -beyond };
                let meet = [a0[0] + t * r[0], a0[1] + t * r[1]];
                let turn =
                    10f64.powf(-13.0 + unit() * 13.0) * if unit() < 0.5 { -1.0 } else { 1.0 };
                let (c, sn) = ((angle + turn).cos(), (angle + turn).sin());
                let len = scale * 10f64.powf(unit() * 2.0 - 1.0);
                let (u0, u1) = (-unit() * 1.2, unit() * 1.2);
                let b0 = [meet[0] + u0 * len * c, meet[1] + u0 * len * sn];
                let b1 = [meet[0] + u1 * len * c, meet[1] + u1 * len * sn];
                (a0, a1, b0, b1)
            };
            let segment = |p: [f64; 2], q: [f64; 2]| Segment {
                path: 0,
                place: 0,
                ends: [p, q],
                length: (q[0] - p[0]).abs() + (q[1] - p[1]).abs(),
            };
            if boxes_apart(&segment(a0, a1), &segment(b0, b1)) {
                skipped += 1;
                assert!(
                    !segments_meet(a0, a1, b0, b1),
                    "{case}: {a0:?} {a1:?} {b0:?} {b1:?}"
                );
            } else {
                kept += 1;
            }
        }
        assert!(skipped > 50_000 && kept > 50_000, "{skipped} {kept}");
        let nan = Segment {
            path: 0,
            place: 0,
            ends: [[0.0, 0.0], [f64::NAN, 1.0]],
            length: f64::NAN,
        };
        let far = Segment {
            path: 1,
            place: 0,
            ends: [[5.0, 5.0], [6.0, 6.0]],
            length: 2.0,
        };
        assert!(!boxes_apart(&nan, &far) && !boxes_apart(&far, &nan));
    }

    #[test]
    fn segments_meet_measures_lengths_only_where_the_squares_leave_it_open() {
        // Pixel steps (axis-aligned and diagonal, collinear, parallel, crossing, sharing ends),
        // copies moved 1e-13 to 1e-6 px (near the thresholds of both tests), random segments,
        // zero-length ones and extreme scales: the same answer as measuring both lengths.
        let mut next = crate::synth::lcg(1357u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let (mut meet, mut apart, mut parallel) = (0, 0, 0);
        for case in 0..200_000 {
            let kind = case % 6;
            let pixel = |u: f64| (u * 8.0).floor() + 0.5;
            let step = |u: f64| ((u * 3.0).floor() - 1.0).max(-1.0);
            let (a0, a1, b0, b1) = match kind {
                0 | 1 => {
                    let a0 = [pixel(unit()), pixel(unit())];
                    let a1 = [a0[0] + step(unit()), a0[1] + step(unit())];
                    let b0 = if unit() < 0.3 {
                        a1
                    } else {
                        [pixel(unit()), pixel(unit())]
                    };
                    let b1 = [b0[0] + step(unit()), b0[1] + step(unit())];
                    (a0, a1, b0, b1)
                }
                2 => {
                    // A nearly parallel or nearly collinear copy.
                    let a0 = [unit() * 10.0, unit() * 10.0];
                    let a1 = [a0[0] + unit() * 6.0 - 3.0, a0[1] + unit() * 6.0 - 3.0];
                    let off =
                        10f64.powf(-13.0 + unit() * 7.0) * if unit() < 0.5 { -1.0 } else { 1.0 };
                    let shift = unit() * 2.0 - 0.5;
                    let d = [a1[0] - a0[0], a1[1] - a0[1]];
                    let b0 = [
                        a0[0] + shift * d[0] - off * d[1],
                        a0[1] + shift * d[1] + off * d[0],
                    ];
                    let twist = if unit() < 0.5 { off } else { 0.0 };
                    let b1 = [b0[0] + d[0] + twist, b0[1] + d[1]];
                    (a0, a1, b0, b1)
                }
                3 => {
                    let p = |u: &mut dyn FnMut() -> f64| [u() * 10.0, u() * 10.0];
                    (p(&mut unit), p(&mut unit), p(&mut unit), p(&mut unit))
                }
                4 => {
                    // Degenerate: a point, or both.
                    let a0 = [pixel(unit()), pixel(unit())];
                    let b0 = [pixel(unit()), pixel(unit())];
                    let b1 = if unit() < 0.5 {
                        b0
                    } else {
                        [b0[0] + 1.0, b0[1]]
                    };
                    (a0, a0, b0, b1)
                }
                _ => {
                    // Extreme scales, where the squares under- or overflow.
                    let scale = 10f64.powf(unit() * 600.0 - 300.0);
                    let p = |u: &mut dyn FnMut() -> f64| [(u() - 0.5) * scale, (u() - 0.5) * scale];
                    let a0 = p(&mut unit);
                    let a1 = p(&mut unit);
                    let b0 = if unit() < 0.5 { a1 } else { p(&mut unit) };
                    let b1 = if unit() < 0.3 {
                        [b0[0] + (a1[0] - a0[0]), b0[1] + (a1[1] - a0[1])]
                    } else {
                        p(&mut unit)
                    };
                    (a0, a1, b0, b1)
                }
            };
            let old = segments_meet_measured(a0, a1, b0, b1);
            assert_eq!(
                segments_meet(a0, a1, b0, b1),
                old,
                "{case}: {a0:?} {a1:?} {b0:?} {b1:?}"
            );
            let r = [a1[0] - a0[0], a1[1] - a0[1]];
            let s = [b1[0] - b0[0], b1[1] - b0[1]];
            if (r[0] * s[1] - r[1] * s[0]).abs() <= 1e-12 * (hypot(r[0], r[1]) * hypot(s[0], s[1]))
            {
                parallel += 1;
            }
            if old {
                meet += 1;
            } else {
                apart += 1;
            }
        }
        assert!(
            meet > 20_000 && apart > 20_000 && parallel > 20_000,
            "{meet} {apart} {parallel}"
        );
    }

    #[test]
    fn crossing_paths_grouped_by_counting_finds_what_the_sorted_keys_did() {
        // Random pixel walks (the skeleton's paths: they cross, touch, retrace and run side by
        // side), smoothed copies of them, removed paths, random `moved` flags, windows from
        // small (sorted) to large (counted), some reaching below zero (folded keys), and now and
        // then a path far off (a span too wide to count): the same paths.
        let mut next = crate::synth::lcg(8642u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let mut found = 0;
        for case in 0..400 {
            let size = 5.0 + unit() * 80.0;
            let count = 1 + (unit() * 60.0) as usize;
            let shift = if case % 4 == 0 { -size / 2.0 } else { 0.0 };
            let mut owned: Vec<Option<Vec<[f64; 2]>>> = Vec::new();
            for _ in 0..count {
                if unit() < 0.1 {
                    owned.push(None);
                    continue;
                }
                let mut p = [
                    (unit() * size + shift).floor() + 0.5,
                    (unit() * size + shift).floor() + 0.5,
                ];
                let len = 2 + (unit() * 40.0) as usize;
                let mut path = vec![p];
                for _ in 1..len {
                    p = [
                        p[0] + (unit() * 3.0).floor() - 1.0,
                        p[1] + (unit() * 3.0).floor() - 1.0,
                    ];
                    path.push(p);
                }
                if unit() < 0.3 {
                    for q in path.iter_mut().skip(1) {
                        *q = [q[0] + unit() * 0.6 - 0.3, q[1] + unit() * 0.6 - 0.3];
                    }
                }
                if unit() < 0.02 {
                    // A long run along a row: a span of more than 2^16 cells.
                    let last = path[path.len() - 1];
                    path.push([last[0] + 3e5, last[1]]);
                }
                owned.push(Some(path));
            }
            let paths: Vec<Option<&[[f64; 2]]>> = owned.iter().map(|p| p.as_deref()).collect();
            let moved: Vec<bool> = (0..count).map(|_| unit() < 0.6).collect();
            let new = crossing_paths(&paths, &moved);
            assert_eq!(new, crossing_paths_sorted(&paths, &moved), "{case}");
            found += new.len();
        }
        assert!(found > 500, "{found}");
    }

    /// The values every rounding test takes: zeros, halves, the ones either side of a whole
    /// number, the smallest normal, the last fractions below 2⁵², the far, infinite and NaN.
    fn rounding_cases() -> Vec<f64> {
        vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1.0 - f64::EPSILON / 2.0,
            -(1.0 - f64::EPSILON / 2.0),
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN,
        ]
    }

    #[test]
    fn floor_i64_is_the_floor_cast() {
        let mut next = crate::synth::lcg(99u64);
        let mut cases = rounding_cases();
        // Either side of 2⁶³, where the cast saturates.
        cases.extend([
            9.223372036854776e18,
            -9.223372036854776e18,
            9.223372036854775e18,
            -9.223372036854775e18,
            -9.223372036854774e18 - 0.5,
        ]);
        for _ in 0..100_000 {
            let bits = next();
            // Any bit pattern, and pixel-like values with fractions.
            cases.push(f64::from_bits(bits));
            cases.push((bits >> 11) as f64 / (1u64 << 40) as f64 - 4096.0);
            cases.push((bits >> 40) as f64 + 0.5 - 8_000_000.0);
        }
        for x in cases {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
    }

    #[test]
    fn floor_and_ceil_without_the_library_are_the_library_s() {
        let mut next = crate::synth::lcg(77u64);
        let mut cases = rounding_cases();
        // From 2⁵² on, where every value is whole.
        cases.extend([
            4_503_599_627_370_496.0,
            -4_503_599_627_370_496.0,
            4_503_599_627_370_497.0,
            9_007_199_254_740_993.0,
        ]);
        for _ in 0..100_000 {
            let bits = next();
            // Any bit pattern, pixel-like values with fractions, values near whole ones.
            cases.push(f64::from_bits(bits));
            cases.push((bits >> 11) as f64 / (1u64 << 40) as f64 - 4096.0);
            let whole = ((bits >> 44) as f64 - 524_288.0).floor();
            cases.push(whole);
            cases.push(whole + f64::EPSILON * whole.abs().max(1.0));
            cases.push(whole - f64::EPSILON * whole.abs().max(1.0));
        }
        for x in cases {
            if x.is_nan() {
                assert!(floor_f64(x).is_nan() && ceil_f64(x).is_nan());
                continue;
            }
            assert_eq!(floor_f64(x).to_bits(), x.floor().to_bits(), "{x:e}");
            assert_eq!(ceil_f64(x).to_bits(), x.ceil().to_bits(), "{x:e}");
        }
        assert!(floor_f64(f64::NAN).is_nan() && ceil_f64(-f64::NAN).is_nan());
    }

    #[test]
    fn distances_to_points_and_segments() {
        assert_eq!(dist([0.0, 0.0], [3.0, 4.0]), 5.0);
        assert_eq!(
            segment_closest([1.0, 2.0], [0.0, 0.0], [4.0, 0.0]),
            (2.0, 0.25)
        );
        // Beyond an end, the end is closest; a degenerate segment is a point.
        assert_eq!(segment_dist([7.0, 4.0], [0.0, 0.0], [4.0, 0.0]), 5.0);
        assert_eq!(
            segment_closest([3.0, 4.0], [0.0, 0.0], [0.0, 0.0]),
            (5.0, 0.0)
        );
    }

    #[test]
    fn walking_a_polyline_by_arc_length() {
        let line = [[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]];
        let s = arc_lengths(&line);
        assert_eq!(s, vec![0.0, 3.0, 7.0]);
        assert_eq!(point_at(&line, &s, 5.0), ([3.0, 2.0], 1));
        assert_eq!(point_at(&line, &s, 9.0).0, [3.0, 4.0]);
    }

    /// The walk gives `point_at`'s points and segments, bit for bit, for rising arc lengths
    /// (repeated ones, ones before the start and past the end) on random polylines, repeated
    /// points (zero-length segments) among them.
    #[test]
    fn the_arc_walk_is_point_at() {
        let mut next = crate::synth::lcg(515u64);
        let mut unit = move || (next() >> 11) as f64 / (1u64 << 53) as f64;
        for case in 0..2000 {
            let n = 1 + case % 40;
            let mut p = [unit() * 100.0, unit() * 100.0];
            let line: Vec<[f64; 2]> = (0..n)
                .map(|_| {
                    if unit() > 0.15 {
                        p = [
                            p[0] + unit() * 4.0 - 2.0,
                            p[1] + (unit() * 3.0).floor() - 1.0,
                        ];
                    }
                    p
                })
                .collect();
            let s = arc_lengths(&line);
            let total = s[n - 1];
            let mut walk = ArcWalk::new(&line, &s);
            let mut t = -1.0;
            while t <= total + 1.0 {
                let (ours, theirs) = (walk.at(t), point_at(&line, &s, t));
                assert_eq!(ours.1, theirs.1, "case {case} t {t}");
                assert_eq!(ours.0.map(f64::to_bits), theirs.0.map(f64::to_bits));
                // Sometimes the same length twice, sometimes exactly a corner's.
                t = match (unit() * 4.0) as usize {
                    0 => t,
                    1 => s[(unit() * n as f64) as usize].max(t),
                    _ => t + unit() * 0.7,
                };
            }
        }
    }

    #[test]
    fn point_in_polygon_by_the_even_odd_rule() {
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(point_in_polygon([1.0, 1.0], &square));
        assert!(!point_in_polygon([3.0, 1.0], &square));
        assert!(!point_in_polygon([1.0, 1.0], &square[..2]));
    }

    #[test]
    fn principal_of_a_horizontal_segment() {
        let (l, d) = principal(10.0, 0.0, 0.1);
        assert!(l > 0.98);
        assert!((d[0] - 1.0).abs() < 1e-9 && d[1].abs() < 1e-9);
    }

    #[test]
    fn principal_of_a_diagonal_and_isotropic_cloud() {
        // Points along y = x: cov = [[1, 1], [1, 1]].
        let (l, d) = principal(1.0, 1.0, 1.0);
        assert!((l - 1.0).abs() < 1e-9);
        assert!((d[0] - d[1]).abs() < 1e-9 && (d[0] - 0.5f64.sqrt()).abs() < 1e-9);
        let (l, _) = principal(1.0, 0.0, 1.0);
        assert!((l - 0.5).abs() < 1e-9);
        assert_eq!(principal(0.0, 0.0, 0.0), (0.5, [1.0, 0.0]));
    }

    #[test]
    fn principal_agrees_with_nalgebra() {
        let covariances = [
            (3.0, 1.0, 2.0),
            (1.0, -0.7, 0.6),
            (0.2, 0.05, 9.0),
            (5.0, 0.0, 1.0),
            (1.0, 1e-13, 2.0),
        ];
        for (cxx, cxy, cyy) in covariances {
            let (l, d) = principal(cxx, cxy, cyy);
            let eigen = nalgebra::Matrix2::new(cxx, cxy, cxy, cyy).symmetric_eigen();
            let k = if eigen.eigenvalues[0] >= eigen.eigenvalues[1] {
                0
            } else {
                1
            };
            let lambda_max = eigen.eigenvalues[k];
            let v = eigen.eigenvectors.column(k);
            assert!(
                (l - lambda_max / (cxx + cyy)).abs() < 1e-9,
                "{cxx} {cxy} {cyy}"
            );
            // The same axis: |cos| of the angle between them is 1.
            assert!(
                ((d[0] * v[0] + d[1] * v[1]).abs() - 1.0).abs() < 1e-6,
                "{cxx} {cxy} {cyy}"
            );
        }
    }

    #[test]
    fn total_order_puts_every_float_in_place() {
        let mut keys = [
            TotalF64(2.0),
            TotalF64(-1.0),
            TotalF64(0.5),
            TotalF64(f64::INFINITY),
        ];
        keys.sort();
        assert_eq!(keys.map(|k| k.0), [-1.0, 0.5, 2.0, f64::INFINITY]);
    }
}
