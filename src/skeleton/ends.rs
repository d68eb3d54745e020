//! Ends and dots: an end carried on to the centre of its cap ([`Work::extend_ends`]); a blob no
//! longer than wide is a dot ([`Work::collapse_dots`]). docs/design.md, "Skeleton-carried
//! geometry".

use crate::geometry::{dist, hypot};

use super::work::{median, Work};
use super::{disk_radius, MIN_LINE_PX, MIN_WIDTH_PX};

/// An end's direction is taken over this many stroke widths from its tip: beyond the cap that
/// thinning rounds.
const END_DIRECTION: f64 = 2.0;

/// The narrowest width (px) [`END_DIRECTION`] is measured in: a hairline's direction over at
/// least 3 px.
const END_DIRECTION_MIN_WIDTH_PX: f64 = 1.5;

/// The ink ahead of an end is followed at most this many stroke widths (plus
/// [`END_SEARCH_PX`]): thinning erodes an end by about a half-width, more along a diagonal.
const END_SEARCH: f64 = 2.0;

/// See [`END_SEARCH`] (px).
const END_SEARCH_PX: f64 = 4.0;

/// An end is carried on by at least this (px), or stays: less is within its own pixel.
const MIN_EXTENSION_PX: f64 = 1.0;

impl Work {
    /// Thinning erodes a stroke's end, most along a diagonal: each end is carried on along its
    /// own direction (taken over the last two widths) to where the ink ends, less the stroke's
    /// half-width, the centre of its cap. Ends are only ever lengthened.
    pub(super) fn extend_ends(&mut self) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            for at_start in [true, false] {
                let Some(edge) = &self.edges[e] else { break };
                let v = if at_start { edge.from } else { edge.to };
                if degree[v] != 1 || edge.from == edge.to || edge.points.len() < 2 {
                    continue;
                }
                let stroke = median(&edge.widths);
                let half = disk_radius(stroke);
                let mut inwards: Vec<[f64; 2]> = edge.points.clone();
                if !at_start {
                    inwards.reverse();
                }
                let tip = inwards[0];
                let back = inwards
                    .iter()
                    .find(|&&p| {
                        dist(p, tip) >= END_DIRECTION * stroke.max(END_DIRECTION_MIN_WIDTH_PX)
                    })
                    .copied()
                    .unwrap_or(inwards[inwards.len() - 1]);
                let d = [tip[0] - back[0], tip[1] - back[1]];
                let n = hypot(d[0], d[1]);
                if n < MIN_LINE_PX {
                    continue;
                }
                let u = [d[0] / n, d[1] / n];
                // Where the ink ends ahead of the tip (at most a few widths on).
                let reach = self.ink.exit(tip, u, END_SEARCH * stroke + END_SEARCH_PX) - half;
                if reach < MIN_EXTENSION_PX {
                    continue;
                }
                let end = [tip[0] + reach * u[0], tip[1] + reach * u[1]];
                let width = edge.widths[if at_start { 0 } else { edge.widths.len() - 1 }];
                let edge = self.edges[e].as_mut().expect("live edge");
                super::spurs::extend_end(edge, at_start, end, width);
                self.vertices[v].pos = end;
            }
        }
    }

    /// A blob of ink no longer than it is wide (the dot of an `i`, a full stop) thins to a short
    /// segment between two ends: it is a dot, one vertex of degree 0 at the segment's middle.
    pub(super) fn collapse_dots(&mut self) {
        let degree = self.degrees();
        for e in 0..self.edges.len() {
            let Some(edge) = &self.edges[e] else { continue };
            if edge.from == edge.to || degree[edge.from] != 1 || degree[edge.to] != 1 {
                continue;
            }
            let length = edge.length();
            let width = edge.widths.iter().copied().fold(MIN_WIDTH_PX, f64::max);
            if length > width {
                continue;
            }
            let (a, b) = (edge.points[0], edge.points[edge.points.len() - 1]);
            let (keep, gone) = (edge.from, edge.to);
            self.vertices[keep].pos = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            self.vertices[keep].width = width;
            self.dot[keep] = true;
            self.alive[gone] = false;
            self.edges[e] = None;
        }
    }
}
