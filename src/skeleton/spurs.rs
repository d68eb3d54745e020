//! Spurs: the arms test (§3.1's idea applied to the skeleton) decides which terminal branches
//! are the boundary's bumps and go ([`Work::prune_spurs`], [`spur_reach`]). docs/design.md,
//! "Skeleton-carried geometry".

use crate::geometry::dist;

use super::work::{median, Work};
use super::{disk_radius, MIN_WIDTH_PX};

/// A branch whose tip lies farther than this many stroke widths (plus [`SPUR_TIP_MARGIN_PX`])
/// from its junction is an arm: the envelope reaches at most about 4 widths from the junction.
const SPUR_TIP_REACH: f64 = 5.0;

/// See [`SPUR_TIP_REACH`] (px): a hairline's junction disk and a pixel of its tip.
const SPUR_TIP_MARGIN_PX: f64 = 2.0;

/// The envelope a branch is measured against holds the junction's other edges' points within
/// this many stroke widths of it: the strokes the branch leaves, not their far ends.
const ENVELOPE_REACH: f64 = 3.0;

/// A spur reaches at most this many stroke widths beyond the envelope (a sharp corner's branch
/// reaches about `0.2 w`); an arm half a width long or more reaches beyond it.
const SPUR_REACH: f64 = 0.4;

/// See [`SPUR_REACH`] (px): a bump of the boundary reaches about a pixel.
const SPUR_REACH_PX: f64 = 1.5;

impl Work {
    /// Spurs: terminal branches whose ink does not reach beyond their junction's disk by more
    /// than `max(1.5 px, 0.4 w)` ([`SPUR_REACH_PX`], [`SPUR_REACH`]) are removed, least reaching first, while
    /// their junction keeps three edges (of the two stubs of a forked stroke end, the longer
    /// one stays as the stroke's end). A sharp corner's branch reaches about `0.2 w`, a boundary
    /// bump about a pixel; an arm half a width long or more is kept.
    pub(super) fn prune_spurs(&mut self) {
        let mut degree = self.degrees();
        let at = self.incidence();
        // The stroke width an arm leaves: the narrowest median width of the junction's other
        // edges (the width at the junction itself is inflated where strokes meet).
        let mut spurs = Vec::new();
        for (e, edge) in self.edges.iter().enumerate() {
            let Some(edge) = edge else { continue };
            let (junction, tip, forward) = match (degree[edge.from], degree[edge.to]) {
                (1, d) if d >= 3 => (edge.to, edge.from, false),
                (d, 1) if d >= 3 => (edge.from, edge.to, true),
                _ => continue,
            };
            let others = || {
                at[junction]
                    .iter()
                    .filter(move |&&o| o != e)
                    .filter_map(|&o| self.edges[o].as_ref())
            };
            let stroke = others()
                .map(|other| median(&other.widths))
                .fold(f64::INFINITY, f64::min);
            let j = &self.vertices[junction];
            let stroke = if stroke.is_finite() { stroke } else { j.width };
            let tip_pos = self.vertices[tip].pos;
            if dist(tip_pos, j.pos) > SPUR_TIP_REACH * stroke.max(MIN_WIDTH_PX) + SPUR_TIP_MARGIN_PX
            {
                continue;
            }
            let mut points = edge.points.clone();
            let mut widths = edge.widths.clone();
            if !forward {
                points.reverse();
                widths.reverse();
            }
            // The envelope: the junction and its other edges' points near it.
            let mut envelope = vec![(j.pos, j.width)];
            for other in others() {
                envelope.extend(
                    other
                        .points
                        .iter()
                        .copied()
                        .zip(other.widths.iter().copied())
                        .filter(|&(q, _)| dist(q, j.pos) <= ENVELOPE_REACH * stroke),
                );
            }
            let reach = spur_reach(&points, &widths, &envelope);
            if reach <= (SPUR_REACH * stroke).max(SPUR_REACH_PX) {
                spurs.push((reach, e, junction, tip));
            }
        }
        spurs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (_, e, junction, tip) in spurs {
            if degree[junction] < 3 {
                continue;
            }
            degree[junction] -= 1;
            degree[tip] -= 1;
            self.edges[e] = None;
            self.alive[tip] = false;
        }
    }
}

/// How far the ink of a terminal branch reaches beyond the envelope of the strokes it leaves:
/// for each of its points `p` (with `r(p)` the half-width there), how far its disk sticks out of
/// the nearest-fitting disk `(q, r(q))` among `envelope` (the junction and the points of its
/// other edges), `min_q |p - q| + r(p) - r(q)`; the largest over the branch. A spur, a bump of
/// the boundary or the branch into a rounded corner, reaches about a pixel; an arm's ink sticks
/// out by its length. Widths are full widths (`r = (w + 1) / 2`, the pixel itself counted).
pub(super) fn spur_reach(points: &[[f64; 2]], widths: &[f64], envelope: &[([f64; 2], f64)]) -> f64 {
    points
        .iter()
        .zip(widths)
        .map(|(&p, &w)| {
            let r = disk_radius(w);
            envelope
                .iter()
                .map(|&(q, wq)| dist(p, q) + r - disk_radius(wq))
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|e| e.is_finite())
        .fold(0.0f64, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_short_arm_reaches_beyond_its_junction_and_a_bump_does_not() {
        // A junction of width 8 (radius 4.5 with the pixel); a bump ends 3 px out, where the
        // stroke's edge is; an arm of 1.5 widths ends 12 px out with its full width.
        let junction = [0.0, 0.0];
        let envelope = [(junction, 8.0), ([4.0, 0.0], 8.0), ([-4.0, 0.0], 8.0)];
        let bump = spur_reach(&[[0.0, 1.0], [0.0, 3.0]], &[7.0, 1.0], &envelope);
        let arm = spur_reach(&[[0.0, 4.0], [0.0, 12.0]], &[8.0, 6.0], &envelope);
        assert!(bump < 1.0, "{bump}");
        assert!(arm > 0.5 * 8.0, "{arm}");
    }
}
