//! The minutiae of a print traced with the fingerprint front end (docs/fingerprints.md,
//! "Minutiae"): the endings and bifurcations of the traced graph ([`crate::minutiae`] finds them
//! and holds the conventions), less those the structure of the ridges shows to be false, each
//! with a quality from the print's analysis ([`PrintAnalysis`]).
//!
//! Input: the [`StrokeGraph`] traced from the enhanced binary and the [`PrintAnalysis`] it came
//! from. Output: `Vec<Minutia>` in vertex order. Deterministic.

use super::PrintAnalysis;
use crate::binary::Binary;
use crate::geometry::{arc_lengths, dist, point_at};
use crate::minutiae::{detect, drop_broken_ridges, Minutia, MinutiaKind, MinutiaeOptions};
use crate::params::FingerprintParams;
use crate::stroke_graph::StrokeGraph;
use std::cell::Cell;

/// The minutiae of a print traced with the fingerprint front end (docs/fingerprints.md,
/// "Minutiae"): every ending and bifurcation of `graph`, less those the structure of the ridges
/// shows to be false, each with a quality from `print`. Lengths are in ridge periods `T` of the
/// block where they are measured:
///
/// - border: within `border_margin` px or `border_periods · T`, whichever is more, of the
///   print's border (the segmentation mask, and the closing of the enhanced ridges by one
///   ridge period) or the image's; but a minutia that points into the print, at least
///   `inward_border_periods · T` from the border, of quality at least `inward_border_quality`
///   of the print's median and, near the image's edge, with its ridges on the confirmed ridges
///   for `inward_border_confirmed` of their first `2 T`, stays;
/// - fragments and islands: an edge with two free ends shorter than `fragment_periods · T`
///   (both ends go), or whose ends come within `T` of each other around at least `3 T` of ridge
///   (a ring broken once);
/// - spurs: an edge from a bifurcation to a free end shorter than `spur_periods · T` (both go);
/// - bridges: an edge between two bifurcations shorter than `bridge_periods · T` that runs across
///   the flow (more than 45° from the local ridge orientation): a bar between neighbouring ridges;
/// - lakes and pores: two bifurcations joined by two edges each shorter than
///   `2 bridge_periods · T` (both go);
/// - broken ridges: two endings facing each other along the flow within `gap_periods · T`;
/// - clouds: a minutia with two others within `cloud_periods · T`, and those, when their quality
///   is below `cloud_quality` of the print's median;
/// - detached branches: a bifurcation of which one arm crosses a valley in the gray image (off
///   [`PrintAnalysis::ridges`] for at least 1 px, back on them within `0.6 T` of the junction)
///   while the other two stay on the ridges for `T` is an ending at the arm's tip: a ridge that
///   stops just short of its neighbour, the shallow valley at its tip filled by the enhancement.
///
/// Each direction is the ridge orientation at the minutia in the sense of its arm's chord
/// (`along_the_flow`). The quality is [`PrintAnalysis::quality_at`]: coherence times contrast,
/// in percent.
pub fn fingerprint_minutiae(
    graph: &StrokeGraph,
    print: &PrintAnalysis,
    params: &FingerprintParams,
) -> Vec<Minutia> {
    let options = MinutiaeOptions::default();
    let confirmed = confirmed_edges(graph, &print.ridges, params.confirmed_share);
    let graph = &confirmed;
    let mut found = detect(graph, &options);
    let mut false_vertex = vec![false; graph.vertices.len()];
    let degree = |v: usize| graph.vertices.get(v).map_or(0, |v| v.degree);
    // Short edges between two bifurcations, by vertex pair, to find lakes.
    let mut short_bars: Vec<(usize, usize)> = Vec::new();
    for edge in &graph.edges {
        let (a, b) = (edge.from, edge.to);
        if a == b || a >= false_vertex.len() || b >= false_vertex.len() {
            continue;
        }
        let length: f64 = edge.points.windows(2).map(|p| dist(p[0], p[1])).sum();
        let (Some(first), Some(last)) = (edge.points.first(), edge.points.last()) else {
            continue;
        };
        let middle = [(first[0] + last[0]) / 2.0, (first[1] + last[1]) / 2.0];
        let period = print.periods.at(middle).max(1.0);
        let short = |factor: f64| length < factor * period;
        let remove = match (degree(a), degree(b)) {
            (1, 1) => {
                short(params.fragment_periods) || nearly_closed([*first, *last], length, period)
            }
            (1, 3) | (3, 1) => short(params.spur_periods),
            (3, 3) => {
                if short(2.0 * params.bridge_periods) {
                    short_bars.push((a.min(b), a.max(b)));
                }
                short(params.bridge_periods) && print.across_the_flow(*first, *last)
            }
            _ => false,
        };
        if remove {
            false_vertex[a] = true;
            false_vertex[b] = true;
        }
    }
    short_bars.sort_unstable();
    for pair in short_bars.windows(2) {
        if pair[0] == pair[1] {
            false_vertex[pair[0].0] = true;
            false_vertex[pair[0].1] = true;
        }
    }
    found.retain(|m| !false_vertex.get(m.vertex).copied().unwrap_or(false));
    detached_branches(&mut found, graph, print);
    if !print.orientation.grid.is_empty() {
        for m in &mut found {
            m.direction = along_the_flow(m.direction, print.orientation.angle_at(m.pos));
        }
    }
    // Broken ridges, with the gap in periods of the print's median period.
    let mut periods: Vec<f64> = found.iter().map(|m| print.periods.at(m.pos)).collect();
    let typical = if periods.is_empty() {
        params.default_period
    } else {
        let middle = periods.len() / 2;
        *periods.select_nth_unstable_by(middle, f64::total_cmp).1
    };
    if params.gap_periods > 0.0 {
        // Two endings closer than half a period, whichever way they point, are one ridge broken
        // where it turns too fast for the filter (the apex of a loop's innermost ridge): the
        // ends of two ridges are at least a valley, about half a period, apart.
        drop_broken_ridges(
            &mut found,
            &MinutiaeOptions {
                broken_ridge_gap: 0.5 * typical,
                broken_ridge_angle_deg: 180.0,
                ..options
            },
        );
        drop_broken_ridges(
            &mut found,
            &MinutiaeOptions {
                broken_ridge_gap: params.gap_periods * typical,
                ..options
            },
        );
    }
    if params.cloud_periods > 0.0 {
        // A cloud's minutiae go when their quality is low: noise, a scar. Where the ridges are
        // clear and coherent a cluster is the finger's (a core, a delta, short ridges).
        let needed = params.cloud_quality * f64::from(median_quality(&found, print));
        let cloud = in_clouds(&found, typical * params.cloud_periods);
        let mut k = 0;
        found.retain(|m| {
            k += 1;
            !cloud[k - 1] || f64::from(print.quality_at(m.pos)) >= needed
        });
    }
    // The border: distance to the nearest pixel outside the print, which is both inside the
    // segmentation mask and inside the closing of the enhanced ridges by a disk of one ridge
    // period (every valley filled, the outline of the ridges kept): the mask's blocks reach past
    // the last ridges by up to a block and its smoothing, and the ridges cut by the outline
    // end there, not at minutiae.
    let grid = print.segmentation.grid;
    let margin = params.border_margin.max(params.border_periods * typical);
    if margin > 0.0 && !grid.is_empty() {
        let (w, h) = (grid.width as usize, grid.height as usize);
        let mut masked = vec![false; w * h];
        print
            .segmentation
            .outside_runs(|run| masked[run].fill(true));
        let outside = PrintOutside::new(masked, &print.ridges.ink, [w, h], typical.max(4.0));
        let at_least = |m: &Minutia, margin: f64| {
            let [x, y] = m.pos;
            let pixel = [(x as usize).min(w - 1), (y as usize).min(h - 1)];
            x >= margin
                && y >= margin
                && w as f64 - x >= margin
                && h as f64 - y >= margin
                && !outside.within(pixel, margin * margin)
        };
        let inward_margin = params.inward_border_periods * typical;
        if inward_margin > 0.0 && inward_margin < margin {
            let needed = params.inward_border_quality * f64::from(median_quality(&found, print));
            let near_image_edge = |m: &Minutia| {
                let [x, y] = m.pos;
                x < margin || y < margin || w as f64 - x < margin || h as f64 - y < margin
            };
            // Near the image's edge the print may end at the finger's outline with bare, noisy
            // skin beyond it, traced as short ridges the gray image only half confirms.
            let confirmed_arms = |m: &Minutia| {
                !near_image_edge(m)
                    || arms_confirmed(graph, m.vertex, &print.ridges, ARM_PERIODS * typical)
                        >= params.inward_border_confirmed
            };
            found.retain(|m| {
                at_least(m, margin)
                    || (at_least(m, inward_margin)
                        && f64::from(print.quality_at(m.pos)) >= needed
                        && !points_out(m, |q| outside.at(q), [w, h], margin)
                        && confirmed_arms(m))
            });
        } else {
            found.retain(|m| at_least(m, margin));
        }
    }
    for m in &mut found {
        m.quality = Some(print.quality_at(m.pos));
    }
    found
}

/// How far along each of its ridges a minutia kept within the border margin near the image's
/// edge must be on the confirmed ridges (`FingerprintParams::inward_border_confirmed`), in ridge
/// periods.
const ARM_PERIODS: f64 = 2.0;

/// The median quality ([`PrintAnalysis::quality_at`]) of `found` (0 for none).
fn median_quality(found: &[Minutia], print: &PrintAnalysis) -> u8 {
    let mut qualities: Vec<u8> = found.iter().map(|m| print.quality_at(m.pos)).collect();
    let middle = qualities.len() / 2;
    if qualities.is_empty() {
        0
    } else {
        *qualities.select_nth_unstable(middle).1
    }
}

/// The least share, over the ridges (edges) leaving `vertex`, of their first `reach` px that
/// lies on `ridges` ([`PrintAnalysis::ridges`]), sampled every half pixel; a ridge shorter than
/// `reach` counts its missing length as off the ridges.
fn arms_confirmed(graph: &StrokeGraph, vertex: usize, ridges: &Binary, reach: f64) -> f64 {
    const STEP: f64 = 0.5;
    let mut least = 1.0f64;
    for edge in &graph.edges {
        for (v, at_start) in [(edge.from, true), (edge.to, false)] {
            if v != vertex || edge.from == edge.to {
                continue;
            }
            let s = arc_lengths(&edge.points);
            let total = s.last().copied().unwrap_or(0.0);
            let (mut on, mut n) = (0usize, 0usize);
            let mut t = 0.0;
            while t <= reach {
                n += 1;
                if t < total {
                    let (q, _) = point_at(&edge.points, &s, if at_start { t } else { total - t });
                    if ridges.get(q[0].floor() as i64, q[1].floor() as i64) {
                        on += 1;
                    }
                }
                t += STEP;
            }
            least = least.min(on as f64 / n.max(1) as f64);
        }
    }
    least
}

/// The print's outside as the border test asks about it: the pixels outside the segmentation
/// mask, and those outside the closing of the confirmed ridges by a disk ([`mask::close_disk`]'s
/// closing, the same pixels), the closing worked out only where it is asked about. A pixel is in
/// the closing when every image pixel within the disk of it is within the disk of a ridge pixel
/// (the dilation), so whether a pixel outside the closing lies near a minutia is whether a pixel
/// outside the dilation lies within the disk of the pixels near it; each pixel's dilation is
/// found once, by looking for ridge pixels within its disk, nearest rows first. The minutiae of
/// a print ask about a few thousand pixels, where the closing of the whole image was about 5 %
/// of a print's instructions (docs/performance.md).
///
/// [`mask::close_disk`]: crate::mask::close_disk
struct PrintOutside<'a> {
    /// The pixels outside the segmentation mask, row-major.
    masked: Vec<bool>,
    /// The confirmed ridges' pixels, row-major.
    ridges: &'a [bool],
    /// Width and height, px.
    size: [usize; 2],
    /// The half-width of the disk's row at each row offset from its centre, 0 to the radius;
    /// empty when the closing is (no ridge pixel, or a radius that is not finite).
    half: Vec<usize>,
    /// Per pixel, whether it is within the disk of a ridge pixel: 0 not worked out yet, 1 no,
    /// 2 yes.
    dilated: Vec<Cell<u8>>,
}

impl<'a> PrintOutside<'a> {
    /// The outside of a print of `size` whose mask leaves out `masked`, its ridges `ridges`
    /// closed by a disk of `radius` px: the pixels whose squared distance, between pixel
    /// centres, is at most the largest whole number at most the `f32` square of `radius`, as
    /// [`mask::close_disk`] has it (distances within the image are at most its diagonal's
    /// square, which caps the number).
    ///
    /// [`mask::close_disk`]: crate::mask::close_disk
    fn new(masked: Vec<bool>, ridges: &'a [bool], [w, h]: [usize; 2], radius: f64) -> Self {
        let r2 = (radius * radius) as f32;
        let cap = (w.saturating_sub(1).pow(2) + h.saturating_sub(1).pow(2)) as u64;
        let any_ridge = ridges.len() >= w * h && ridges[..w * h].contains(&true);
        let half = if !r2.is_finite() || !any_ridge {
            Vec::new()
        } else {
            // The largest whole number whose `f32` is at most `r2`, or the cap.
            let t = if f64::from(r2) >= cap as f64 {
                cap
            } else {
                (r2 as u64..)
                    .take_while(|&t| t as f32 <= r2)
                    .last()
                    .unwrap_or(0)
            };
            let root = |n: u64| {
                let mut r = (n as f64).sqrt() as u64;
                while r * r > n {
                    r -= 1;
                }
                while (r + 1) * (r + 1) <= n {
                    r += 1;
                }
                r
            };
            (0..=root(t)).map(|g| root(t - g * g) as usize).collect()
        };
        PrintOutside {
            masked,
            ridges,
            size: [w, h],
            half,
            dilated: (0..w * h).map(|_| Cell::new(0)).collect(),
        }
    }

    /// Calls `visit(y, x0, x1)` for each image row `y` within the disk of row `row` (the disk's
    /// rows nearest first), with the columns `x0..=x1` within it of the run `lo..=hi` of `row`.
    fn disk_rows(
        &self,
        row: usize,
        (lo, hi): (usize, usize),
        mut visit: impl FnMut(usize, usize, usize) -> bool,
    ) -> bool {
        let [w, h] = self.size;
        self.half.iter().enumerate().any(|(dy, &reach)| {
            let (x0, x1) = (lo.saturating_sub(reach), (hi + reach).min(w - 1));
            [
                row.checked_sub(dy),
                (dy > 0).then_some(row + dy).filter(|&y| y < h),
            ]
            .into_iter()
            .flatten()
            .any(|y| visit(y, x0, x1))
        })
    }

    /// Whether pixel `(x, y)` is within the disk of a ridge pixel: at once for a ridge pixel,
    /// from `dilated` for one already asked about.
    #[inline(always)]
    fn is_dilated(&self, x: usize, y: usize) -> bool {
        let p = y * self.size[0] + x;
        if self.ridges[p] {
            return true;
        }
        match self.dilated[p].get() {
            0 => self.dilate(x, y, p),
            known => known == 2,
        }
    }

    /// [`PrintOutside::is_dilated`] worked out: a ridge pixel in the disk's rows, nearest first.
    #[inline(never)]
    fn dilate(&self, x: usize, y: usize, p: usize) -> bool {
        let [w, h] = self.size;
        let ridge_in = |row: usize, x0: usize, x1: usize| {
            self.ridges[row * w + x0..=row * w + x1].contains(&true)
        };
        let mut found = false;
        for (dy, &reach) in self.half.iter().enumerate() {
            let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(w - 1));
            if (dy <= y && ridge_in(y - dy, x0, x1))
                || (dy > 0 && y + dy < h && ridge_in(y + dy, x0, x1))
            {
                found = true;
                break;
            }
        }
        self.dilated[p].set(1 + u8::from(found));
        found
    }

    /// Whether pixel `q` (row-major index) is outside the print.
    fn at(&self, q: usize) -> bool {
        if self.masked[q] || self.half.is_empty() {
            return true;
        }
        let w = self.size[0];
        let (x, y) = (q % w, q / w);
        self.disk_rows(y, (x, x), |yy, x0, x1| {
            (x0..=x1).any(|xx| !self.is_dilated(xx, yy))
        })
    }

    /// Whether a pixel outside the print lies at a squared distance below `d2` from `pixel`
    /// (between pixel centres): the distance transform of the outside read at one pixel,
    /// looking only within the distance asked about.
    fn within(&self, [x, y]: [usize; 2], d2: f64) -> bool {
        if d2.is_nan() || d2 <= 0.0 {
            return false;
        }
        let [w, h] = self.size;
        let reach = d2.sqrt().ceil() as usize;
        let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(w - 1));
        let (y0, y1) = (y.saturating_sub(reach), (y + reach).min(h - 1));
        let near = |qx: usize, dy: f64| (dy * dy + (qx.abs_diff(x) as f64).powi(2)) < d2;
        // The pixels within the disk of those near `pixel`, a run of columns per row: each
        // near row's run holds column `x` (the nearest), and so does its run widened by the
        // disk, so the runs a row gets from the rows near it make one run.
        let first = y0.saturating_sub(self.half.len());
        let mut runs = vec![(usize::MAX, 0usize); y1 + self.half.len() + 1 - first];
        for qy in y0..=y1 {
            let dy = qy.abs_diff(y) as f64;
            let Some(lo) = (x0..=x).find(|&qx| near(qx, dy)) else {
                continue;
            };
            let hi = (x..=x1).rev().find(|&qx| near(qx, dy)).unwrap_or(x);
            if self.masked[qy * w + lo..=qy * w + hi].contains(&true) || self.half.is_empty() {
                return true;
            }
            self.disk_rows(qy, (lo, hi), |py, a, b| {
                let run = &mut runs[py - first];
                *run = (run.0.min(a), run.1.max(b));
                false
            });
        }
        runs.iter()
            .enumerate()
            .any(|(k, &(a, b))| a <= b && (a..=b).any(|px| !self.is_dilated(px, first + k)))
    }
}

/// Whether `m`'s direction, followed for `reach` px, leaves the print (`outside` of a row-major
/// pixel index, `size` the width and height) or the image: a ridge cut by the print's outline ends pointing out of it.
fn points_out(
    m: &Minutia,
    outside: impl Fn(usize) -> bool,
    [w, h]: [usize; 2],
    reach: f64,
) -> bool {
    let (dy, dx) = m.direction.sin_cos();
    (1..=reach.ceil() as usize).any(|k| {
        let (x, y) = (m.pos[0] + k as f64 * dx, m.pos[1] + k as f64 * dy);
        !(x >= 0.0 && y >= 0.0 && x < w as f64 && y < h as f64)
            || outside(y as usize * w + x as usize)
    })
}

/// Bifurcations of which one arm leaves the junction across a valley the gray image shows: off
/// [`PrintAnalysis::ridges`] for at least a pixel within one period of the junction, on them
/// again beyond, while the other two arms stay on the ridges over the same period. The ridge of
/// that arm ends just short of its neighbour and the enhancement, which smooths along the flow,
/// filled the shallow valley at its tip: the minutia is an ending at the far side of the gap,
/// pointing towards the junction.
fn detached_branches(found: &mut [Minutia], graph: &StrokeGraph, print: &PrintAnalysis) {
    const STEP: f64 = 0.5;
    // Per vertex, its arms: the edges leaving it, and whether they start there.
    let mut arms: Vec<Vec<(usize, bool)>> = vec![Vec::new(); graph.vertices.len()];
    for (e, edge) in graph.edges.iter().enumerate() {
        if edge.from == edge.to {
            continue;
        }
        for (v, at_start) in [(edge.from, true), (edge.to, false)] {
            if let Some(a) = arms.get_mut(v) {
                a.push((e, at_start));
            }
        }
    }
    // Samples every `STEP` px of arc from the vertex along an arm, up to `reach` px: on the
    // ridges, and where.
    let samples = |(e, at_start): (usize, bool), reach: f64| -> Vec<(bool, [f64; 2])> {
        let points = &graph.edges[e].points;
        let s = arc_lengths(points);
        let total = s.last().copied().unwrap_or(0.0);
        (0..)
            .map(|k| f64::from(k) * STEP)
            .take_while(|&t| t <= reach && t < total)
            .map(|t| {
                let (q, _) = point_at(points, &s, if at_start { t } else { total - t });
                (
                    print.ridges.get(q[0].floor() as i64, q[1].floor() as i64),
                    q,
                )
            })
            .collect()
    };
    let run = (1.0 / STEP).ceil() as usize;
    // The far side of the first gap of at least `run` samples, followed by `run` on-ridge
    // samples.
    let gap_end = |s: &[(bool, [f64; 2])]| {
        let mut k = 0;
        while k < s.len() {
            if s[k].0 {
                k += 1;
                continue;
            }
            let start = k;
            while k < s.len() && !s[k].0 {
                k += 1;
            }
            if k - start >= run && k + run <= s.len() && s[k..k + run].iter().all(|x| x.0) {
                return Some(k);
            }
        }
        None
    };
    for m in found.iter_mut() {
        let Some(arm) = arms.get(m.vertex) else {
            continue;
        };
        if m.kind != MinutiaKind::Bifurcation || arm.len() != 3 {
            continue;
        }
        let reach = print.periods.at(m.pos).max(4.0);
        let sampled: Vec<Vec<(bool, [f64; 2])>> = arm.iter().map(|&a| samples(a, reach)).collect();
        let gaps: Vec<(usize, usize)> = (0..3)
            .filter_map(|i| gap_end(&sampled[i]).map(|k| (i, k)))
            .collect();
        let [(i, k)] = gaps[..] else {
            continue;
        };
        let through_on = (0..3)
            .filter(|&j| j != i)
            .all(|j| sampled[j].iter().all(|x| x.0));
        if !through_on || k as f64 * STEP > 0.6 * reach {
            continue;
        }
        let tip = sampled[i][k].1;
        let towards = [m.pos[0] - tip[0], m.pos[1] - tip[1]];
        m.kind = MinutiaKind::Ending;
        m.pos = tip;
        m.direction = towards[1].atan2(towards[0]);
    }
}

/// A minutia's direction from the chord of its traced arm (`chord`, radians) and the ridge
/// orientation at it (`orientation`, radians in `[0, π)`): the orientation, turned by π when
/// the chord points the other way. The chord, over two ridge widths of a centerline that bends
/// where it ends or forks, is off by 7-8° in the median and by more than 22° for one minutia in
/// ten against mindtct's; the orientation field, averaged over the ridges around it
/// (`orientation_sigma`), is steady from one impression to the next, and a matcher compares
/// angles (docs/fingerprints.md, "Matching benchmark").
fn along_the_flow(chord: f64, orientation: f64) -> f64 {
    let sense = if (orientation - chord).cos() >= 0.0 {
        orientation
    } else {
        orientation + std::f64::consts::PI
    };
    sense.sin().atan2(sense.cos())
}

/// Whether a ridge of `length` px whose two `ends` come within one `period` of each other runs
/// around a loop of at least three periods: a ring broken in one place (the innermost ridge of a
/// whorl, tighter than the filter resolves), whose two ends are not endings.
fn nearly_closed(ends: [[f64; 2]; 2], length: f64, period: f64) -> bool {
    dist(ends[0], ends[1]) < period && length >= 3.0 * period
}

/// `graph` without the edges of which less than `share` of the length lies on `ridges` (the
/// ridges the gray image confirms, [`PrintAnalysis::ridges`]), the degrees counted again: the
/// Gabor filter rings into a ghost ridge where a valley is wider than the period (inside the
/// innermost recurve of a loop, beyond the print's last ridge), and the ends and forks of a
/// ghost are not the finger's. A ridge broken by a crease, a pore or a dry patch is confirmed
/// over the rest of its length and stays.
fn confirmed_edges(graph: &StrokeGraph, ridges: &Binary, share: f64) -> StrokeGraph {
    let mut out = StrokeGraph {
        width: graph.width,
        height: graph.height,
        vertices: graph.vertices.clone(),
        edges: Vec::with_capacity(graph.edges.len()),
    };
    if share <= 0.0 || ridges.ink.is_empty() {
        out.edges = graph.edges.clone();
        return out;
    }
    for v in &mut out.vertices {
        v.degree = 0;
    }
    for edge in &graph.edges {
        let (mut on, mut total) = (0.0, 0.0);
        for pair in edge.points.windows(2) {
            let length = dist(pair[0], pair[1]);
            let steps = length.ceil().max(1.0) as usize;
            for k in 0..steps {
                let t = (k as f64 + 0.5) / steps as f64;
                let x = pair[0][0] + t * (pair[1][0] - pair[0][0]);
                let y = pair[0][1] + t * (pair[1][1] - pair[0][1]);
                total += length / steps as f64;
                if ridges.get(x.floor() as i64, y.floor() as i64) {
                    on += length / steps as f64;
                }
            }
        }
        if total == 0.0 || on >= share * total {
            for v in [edge.from, edge.to] {
                if let Some(v) = out.vertices.get_mut(v) {
                    v.degree += 1;
                }
            }
            out.edges.push(edge.clone());
        }
    }
    out
}

/// Which minutiae are in a cloud: every minutia that has at least two others within `radius`,
/// and those others. Sorted by x, so only a window is compared.
fn in_clouds(found: &[Minutia], radius: f64) -> Vec<bool> {
    let mut by_x: Vec<usize> = (0..found.len()).collect();
    by_x.sort_by(|&a, &b| found[a].pos[0].total_cmp(&found[b].pos[0]).then(a.cmp(&b)));
    let mut near: Vec<Vec<usize>> = vec![Vec::new(); found.len()];
    for (k, &a) in by_x.iter().enumerate() {
        for &b in &by_x[k + 1..] {
            if found[b].pos[0] - found[a].pos[0] > radius {
                break;
            }
            if dist(found[a].pos, found[b].pos) < radius {
                near[a].push(b);
                near[b].push(a);
            }
        }
    }
    let mut dropped = vec![false; found.len()];
    for (a, others) in near.iter().enumerate() {
        if others.len() >= 2 {
            dropped[a] = true;
            for &b in others {
                dropped[b] = true;
            }
        }
    }
    dropped
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::minutiae::tests::{angle_close, no_filters};
    use crate::stroke_graph::graph_from;

    #[test]
    fn a_ghost_arm_is_no_ridge_and_its_fork_no_bifurcation() {
        // A Y whose up-right arm lies in a valley (not on the confirmed ridges): without it the
        // fork is a bend (degree 2) and the arm's far end no ending.
        let c = [100.0, 100.0];
        let g = graph_from(
            &[c, [150.0, 70.0], [40.0, 100.0], [150.0, 130.0]],
            &[(0, 1, vec![]), (2, 0, vec![]), (0, 3, vec![])],
            4.0,
        );
        let mut ridges = Binary::new(200, 200);
        for (k, edge) in g.edges.iter().enumerate() {
            if k == 0 {
                continue;
            }
            for pair in edge.points.windows(2) {
                for t in 0..=200 {
                    let t = f64::from(t) / 200.0;
                    let x = pair[0][0] + t * (pair[1][0] - pair[0][0]);
                    let y = pair[0][1] + t * (pair[1][1] - pair[0][1]);
                    ridges.set(x as i64, y as i64, true);
                }
            }
        }
        let confirmed = confirmed_edges(&g, &ridges, 0.5);
        assert_eq!(confirmed.edges.len(), 2);
        confirmed.validate().expect("degrees match the edges");
        let degrees: Vec<usize> = confirmed.vertices.iter().map(|v| v.degree).collect();
        assert_eq!(degrees, vec![2, 0, 1, 1]);
        let found = detect(&confirmed, &no_filters());
        assert!(found.iter().all(|m| m.kind == MinutiaKind::Ending));
        assert_eq!(found.len(), 2);
        // A share of 0 keeps every edge; a ridge confirmed over 60 % of its length stays.
        assert_eq!(confirmed_edges(&g, &ridges, 0.0).edges.len(), 3);
        for x in 120..150 {
            for y in 60..90 {
                ridges.set(x, y, true);
            }
        }
        assert_eq!(confirmed_edges(&g, &ridges, 0.5).edges.len(), 3);
    }

    #[test]
    fn a_branch_across_a_valley_is_an_ending_and_a_break_further_out_is_not() {
        use crate::fingerprint::fields::BlockGrid;
        use crate::fingerprint::tests::uniform_print;
        // A ridge along y = 20 (ink rows 19-21) and a branch leaving it at (50, 20) up to the
        // right; period 9. The branch's ink is drawn where its arc from the junction is in
        // `inked` only.
        let (c, d) = ([50.0, 20.0], [30.0f64 / 36.06, -20.0 / 36.06]);
        let g = graph_from(
            &[c, [10.0, 20.0], [90.0, 20.0], [80.0, 0.0]],
            &[(1, 0, vec![]), (0, 2, vec![]), (0, 3, vec![])],
            3.0,
        );
        let (segmentation, orientation, periods) =
            uniform_print(BlockGrid::new(100, 60, 8), 0.0, 9.0);
        let print_with = |inked: &dyn Fn(f64) -> bool| {
            let mut ridges = Binary::new(100, 60);
            for y in 0..60i64 {
                for x in 0..100i64 {
                    let (u, v) = (x as f64 + 0.5 - c[0], y as f64 + 0.5 - c[1]);
                    let along = u * d[0] + v * d[1];
                    let across = (u * d[1] - v * d[0]).abs();
                    let branch = along >= 0.0 && across <= 1.5 && inked(along);
                    ridges.set(x, y, (19..=21).contains(&y) || branch);
                }
            }
            PrintAnalysis {
                segmentation: segmentation.clone(),
                orientation: orientation.clone(),
                periods: periods.clone(),
                ridges,
                ..PrintAnalysis::default()
            }
        };
        let fork_of = |print: &PrintAnalysis| {
            let mut found: Vec<Minutia> = detect(&g, &no_filters())
                .into_iter()
                .filter(|m| m.vertex == 0)
                .collect();
            detached_branches(&mut found, &g, print);
            found[0]
        };
        // The branch's ink starts 4 px out, past a valley from the ridge's edge: an ending at
        // the branch's tip, pointing back to the junction.
        let m = fork_of(&print_with(&|s| s >= 4.0));
        assert_eq!(m.kind, MinutiaKind::Ending);
        let tip = [c[0] + 4.0 * d[0], c[1] + 4.0 * d[1]];
        assert!(dist(m.pos, tip) < 1.0, "{:?}", m.pos);
        assert!(
            angle_close(m.direction, (-d[1]).atan2(-d[0])),
            "{}",
            m.direction
        );
        // Ink all the way, or a break beyond 0.6 period of the junction: a bifurcation.
        for inked in [&(|_: f64| true) as &dyn Fn(f64) -> bool, &|s| {
            !(6.0..8.0).contains(&s)
        }] {
            assert_eq!(fork_of(&print_with(inked)).kind, MinutiaKind::Bifurcation);
        }
    }

    #[test]
    fn a_ring_broken_once_is_nearly_closed_but_not_a_hook_or_a_dash() {
        // Whether the polyline `points` is a broken ring, as the filter asks of an edge.
        let nearly_closed = |points: &[[f64; 2]], period: f64| {
            let length: f64 = points.windows(2).map(|p| dist(p[0], p[1])).sum();
            nearly_closed([points[0], points[points.len() - 1]], length, period)
        };
        // Arcs of radius 8 around (50, 50) from angle `gap` to 2π: a ring of period 9 broken by
        // a gap of `gap` radians.
        let arc = |gap: f64| -> Vec<[f64; 2]> {
            (0..=64)
                .map(|k| {
                    let a = gap + (std::f64::consts::TAU - gap) * f64::from(k) / 64.0;
                    [50.0 + 8.0 * a.cos(), 50.0 + 8.0 * a.sin()]
                })
                .collect()
        };
        assert!(
            nearly_closed(&arc(0.8), 9.0),
            "ends 6 px apart around 44 px"
        );
        assert!(
            !nearly_closed(&arc(std::f64::consts::PI), 9.0),
            "a half ring"
        );
        // Ends within a period of each other but only 2 periods of ridge: a short hook.
        let hook = [[0.0, 0.0], [9.0, 0.0], [9.0, 5.0], [0.0, 5.0]];
        assert!(!nearly_closed(&hook, 9.0));
        assert!(!nearly_closed(&[[0.0, 0.0]], 9.0));
    }

    /// The outside as it was computed for the whole image: the closing of the ridges
    /// ([`crate::mask::close_disk`]) and the mask, and its distance read pixel by pixel.
    fn outside_of_the_whole_image(
        masked: &[bool],
        ridges: &[bool],
        [w, h]: [usize; 2],
        radius: f64,
    ) -> Vec<bool> {
        let region = crate::mask::close_disk(ridges, w, h, radius);
        region.iter().zip(masked).map(|(&r, &m)| !r || m).collect()
    }

    fn outside_within_pixel_by_pixel(
        outside: &[bool],
        [w, h]: [usize; 2],
        [x, y]: [usize; 2],
        d2: f64,
    ) -> bool {
        (0..h).any(|qy| {
            (0..w).any(|qx| {
                let (dy, dx) = (qy.abs_diff(y) as f64, qx.abs_diff(x) as f64);
                outside[qy * w + qx] && dy * dy + dx.powi(2) < d2
            })
        })
    }

    #[test]
    fn the_outside_worked_out_where_asked_is_the_whole_images() {
        let mut rng = crate::test_rng::XorShift::new(0x9E37_79B9_7F4A_7C15);
        for case in 0..24 {
            let (w, h) = (
                20 + (rng.next_u64() % 50) as usize,
                20 + (rng.next_u64() % 50) as usize,
            );
            // Ridges: stripes of a random period and direction over a random disc, with holes
            // and specks; the mask leaves out a random band of columns.
            let (period, angle) = (5.0 + 6.0 * rng.unit(), std::f64::consts::PI * rng.unit());
            let centre = [w as f64 * rng.unit(), h as f64 * rng.unit()];
            let radius = (w.min(h) as f64) * (0.3 + 0.5 * rng.unit());
            let ridges: Vec<bool> = (0..w * h)
                .map(|k| {
                    let (x, y) = ((k % w) as f64, (k / w) as f64);
                    let (dx, dy) = (x - centre[0], y - centre[1]);
                    let u = dx * angle.cos() + dy * angle.sin();
                    let noise = rng.unit();
                    (dx * dx + dy * dy <= radius * radius
                        && (u / period).rem_euclid(1.0) < 0.5
                        && noise > 0.05)
                        || noise > 0.995
                })
                .map(|r| r && case % 8 != 7)
                .collect();
            let band = (rng.next_u64() % w as u64) as usize;
            let masked: Vec<bool> = (0..w * h).map(|k| k % w < band / 3).collect();
            let disk = [4.0, 5.5, 7.3, 9.0, 12.0, f64::INFINITY][case % 6];
            let whole = outside_of_the_whole_image(&masked, &ridges, [w, h], disk);
            let lazy = PrintOutside::new(masked.clone(), &ridges, [w, h], disk);
            for _ in 0..40 {
                let pixel = [
                    (rng.next_u64() % w as u64) as usize,
                    (rng.next_u64() % h as u64) as usize,
                ];
                let d2 =
                    [0.0, 2.0, 30.25, 144.0, 400.0][(rng.next_u64() % 5) as usize] * rng.unit();
                assert_eq!(
                    lazy.within(pixel, d2),
                    outside_within_pixel_by_pixel(&whole, [w, h], pixel, d2),
                    "case {case}: {w} x {h}, disk {disk}, {pixel:?} within {d2}"
                );
            }
            for (q, &o) in whole.iter().enumerate() {
                assert_eq!(
                    lazy.at(q),
                    o,
                    "case {case}: pixel {q} of {w} x {h}, disk {disk}"
                );
            }
        }
    }

    #[test]
    fn a_minutia_points_out_of_the_print_when_its_direction_leaves_it() {
        // A print of 100 x 60 px whose left 40 columns are outside; minutiae 6 px inside it.
        let (w, h) = (100usize, 60usize);
        let outside: Vec<bool> = (0..w * h).map(|i| i % w < 40).collect();
        let at = |x: f64, y: f64, direction: f64| Minutia {
            kind: MinutiaKind::Ending,
            vertex: 0,
            pos: [x, y],
            direction,
            width: 3.0,
            quality: None,
        };
        let out = |m: Minutia| points_out(&m, |q| outside[q], [w, h], 12.0);
        use std::f64::consts::{FRAC_PI_2, PI};
        assert!(out(at(46.0, 30.0, PI)), "towards the outside");
        assert!(out(at(46.0, 30.0, 0.8 * PI)), "obliquely towards it");
        assert!(!out(at(46.0, 30.0, 0.0)), "into the print");
        assert!(!out(at(46.0, 30.0, FRAC_PI_2)), "along the border");
        // The image's edge is the print's edge too; beyond `reach` nothing counts.
        assert!(out(at(70.0, 5.0, -FRAC_PI_2)));
        assert!(!out(at(70.0, 20.0, -FRAC_PI_2)));
    }

    #[test]
    fn arms_are_confirmed_by_the_share_of_their_first_periods_on_the_ridges() {
        // An ending at (10, 20) whose ridge runs right along y = 20 for 60 px; the confirmed
        // ridges cover x in [10, 10 + covered).
        let g = graph_from(&[[10.0, 20.0], [70.0, 20.0]], &[(0, 1, vec![])], 3.0);
        let share = |covered: i64, vertex: usize| {
            let mut ridges = Binary::new(100, 40);
            for x in 10..10 + covered {
                ridges.set(x, 20, true);
            }
            arms_confirmed(&g, vertex, &ridges, 18.0)
        };
        assert!(share(61, 0) > 0.99, "on the ridges all along");
        let half = share(9, 0);
        assert!(
            (0.45..0.55).contains(&half),
            "half of the first 18 px: {half}"
        );
        assert!(share(61, 1) > 0.99, "from the other end too");
        assert!(share(0, 0) < 0.01);
        // A ridge shorter than the reach counts its missing length as off the ridges.
        let short = graph_from(&[[10.0, 20.0], [19.0, 20.0]], &[(0, 1, vec![])], 3.0);
        let mut ridges = Binary::new(100, 40);
        for x in 0..100 {
            ridges.set(x, 20, true);
        }
        let s = arms_confirmed(&short, 0, &ridges, 18.0);
        assert!((0.45..0.6).contains(&s), "{s}");
    }

    #[test]
    fn the_direction_is_the_flow_in_the_sense_of_the_chord() {
        use std::f64::consts::{FRAC_PI_2, PI};
        // Ridges running at 30°: a chord 10° off either way takes the flow's angle; a chord the
        // other way round takes the opposite sense.
        let flow = PI / 6.0;
        assert!(angle_close(along_the_flow(flow + 0.17, flow), flow));
        assert!(angle_close(along_the_flow(flow - 0.17, flow), flow));
        assert!(angle_close(
            along_the_flow(flow + PI - 0.17, flow),
            flow + PI
        ));
        // Across the flow the sense follows the nearer half turn; the result stays in (-π, π].
        let d = along_the_flow(flow + FRAC_PI_2 - 0.01, flow);
        assert!(angle_close(d, flow), "{d}");
        let d = along_the_flow(-3.0, 0.1);
        assert!(angle_close(d, 0.1 - PI) && d > -PI && d <= PI, "{d}");
    }

    #[test]
    fn a_cloud_goes_whole_and_a_pair_stays() {
        let at = |x: f64, y: f64, vertex: usize| Minutia {
            kind: MinutiaKind::Ending,
            vertex,
            pos: [x, y],
            direction: 0.0,
            width: 3.0,
            quality: None,
        };
        // Three within 9 px of the first (a cloud), a pair 6 px apart far away, one alone.
        let found = vec![
            at(50.0, 50.0, 0),
            at(55.0, 50.0, 1),
            at(50.0, 56.0, 2),
            at(58.0, 58.0, 3),
            at(150.0, 150.0, 4),
            at(156.0, 150.0, 5),
            at(100.0, 20.0, 6),
        ];
        let cloud = in_clouds(&found, 9.0);
        assert_eq!(cloud, [true, true, true, true, false, false, false]);
    }
}
