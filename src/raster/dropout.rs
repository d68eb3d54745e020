//! Dropout mode decided per group of nearby components (docs/design.md, adaptation 2, and "The
//! front end"): a page where only some strokes are broken and speckled keeps the plain
//! 8-neighbourhood, the skeleton and the exact half-widths on its solid strokes.
//!
//! A group is the ink within 3 px of each other (the components of the ink grown by one pixel),
//! so the fragments of one broken stroke, which dropout mode's 5x5 neighbourhood joins, stay in
//! one group. Each group is tested as the whole image is ([`super::points`]): pixels hanging on by
//! a single 8-neighbour that do not end a line, isolated pixels, tiny holes.

use super::points::{ends_a_line, LOOSE_FRACTION};
use crate::binary::{Binary, MaskView};
use crate::mask::{label_components, morph3, tiny_hole_in_stroke, Connectivity};
use crate::params::Params;

/// Loose or isolated pixels below this count never switch a group on (a few line ends).
const MIN_LOOSE: usize = 16;
/// Share of a group's pixels with no 8-neighbour above which it is in dropout mode (the
/// whole-image test's `Dis_ave` > 1.05 holds at about this share).
const ISOLATED_FRACTION: f64 = 0.05;

/// The ink split into the groups in dropout mode and the rest, when the groups disagree; `None`
/// when one decision holds for every group (then the whole image's decision stands).
pub(crate) fn split(binary: MaskView<'_>, params: &Params) -> Option<(Binary, Binary)> {
    let (w, h) = (binary.width as usize, binary.height as usize);
    if w < 3 || h < 3 || binary.ink.len() != w * h {
        return None;
    }
    let grown = morph3(binary.ink, w, h, true);
    let (labels, sizes) = label_components(&grown, w, h, true, Connectivity::Eight);
    let label = |i: usize| labels[i] as usize;
    let groups = sizes.len();
    // Per group: ink pixels, loose (one 8-neighbour), isolated (none), tiny-hole pixels.
    let mut stats = vec![[0usize; 4]; groups];
    let ink = binary.ink;
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if !ink[i] {
                // A tiny hole is counted once, from its first pixel, whose left neighbour is ink.
                if x > 0 && ink[i - 1] {
                    if let Some(size) = tiny_hole_in_stroke(ink, w, h, i) {
                        stats[label(i - 1)][3] += size;
                    }
                }
                continue;
            }
            let mut neighbours = 0;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    if (dx, dy) != (0, 0) && binary.get(x as i64 + dx, y as i64 + dy) {
                        neighbours += 1;
                    }
                }
            }
            let s = &mut stats[label(i)];
            s[0] += 1;
            s[1] += usize::from(neighbours == 1 && !ends_a_line(binary, x, y));
            s[2] += usize::from(neighbours == 0);
        }
    }
    let broken: Vec<bool> = stats
        .iter()
        .map(|&[count, loose, isolated, holes]| {
            let count_f = count as f64;
            (loose > MIN_LOOSE && loose as f64 > LOOSE_FRACTION * count_f)
                || (isolated > MIN_LOOSE && isolated as f64 > ISOLATED_FRACTION * count_f)
                || (count > 0 && holes as f64 > params.front_end.dropout_fraction * count_f)
        })
        .collect();
    let with_ink = |on: bool| stats.iter().zip(&broken).any(|(s, &b)| s[0] > 0 && b == on);
    if !with_ink(true) || !with_ink(false) {
        return None;
    }
    let mut solid = Binary::new(binary.width, binary.height);
    let mut speckled = Binary::new(binary.width, binary.height);
    for (i, &on) in ink.iter().enumerate() {
        if on {
            if broken[label(i)] {
                speckled.ink[i] = true;
            } else {
                solid.ink[i] = true;
            }
        }
    }
    Some((solid, speckled))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::{render, Stroke};

    /// A solid bar on top, a bar with a third of its pixels knocked out below, 20 px apart.
    fn half_broken() -> Binary {
        let mut binary = render(
            &[
                Stroke::new(vec![[10.0, 15.0], [150.0, 15.0]], 6.0),
                Stroke::new(vec![[10.0, 45.0], [150.0, 45.0]], 6.0),
            ],
            160,
            60,
        );
        let mut state = 12345u64;
        for y in 35..56 {
            for x in 0..160 {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                if (state >> 33) % 3 == 0 {
                    binary.set(x, y, false);
                }
            }
        }
        binary
    }

    #[test]
    fn only_the_broken_strokes_go_to_dropout_mode() {
        let binary = half_broken();
        let (solid, speckled) = split(binary.view(), &Params::default()).expect("groups disagree");
        assert!(solid.get(80, 15) && !solid.get(80, 45));
        assert!(!speckled.get(80, 15));
        assert_eq!(solid.count() + speckled.count(), binary.count());
        // Solid strokes alone: one decision, no split.
        let clean = render(
            &[Stroke::new(vec![[10.0, 15.0], [150.0, 15.0]], 6.0)],
            160,
            30,
        );
        assert!(split(clean.view(), &Params::default()).is_none());
    }

    #[test]
    fn one_pixel_lines_crossing_at_a_shallow_angle_are_not_dropout() {
        // Two 1-px lines crossing at 15 degrees enclose single background pixels where they
        // part: gaps between the lines, not specks in a stroke. In dropout mode the 5x5
        // neighbourhood joined the lines across the background, 22 % of the centerline off
        // the ink.
        let (c, half) = ([34.5, 16.5], 30.0f64);
        let line = |deg: f64| {
            let (dx, dy) = (half * deg.to_radians().cos(), half * deg.to_radians().sin());
            Stroke::new(vec![[c[0] - dx, c[1] - dy], [c[0] + dx, c[1] + dy]], 1.0)
        };
        let binary = render(&[line(7.0), line(22.0)], 70, 34);
        let trace = crate::trace_binary(&binary, &Params::default()).unwrap();
        assert_eq!(trace.dropout(), Some(false));
        let graph = &trace.graph;
        assert_eq!(graph.endpoints().count(), 4);
        for edge in &graph.edges {
            for pair in edge.points.windows(2) {
                let mid = [
                    (pair[0][0] + pair[1][0]) / 2.0,
                    (pair[0][1] + pair[1][1]) / 2.0,
                ];
                let near_ink = (-1..=1).any(|dy| {
                    (-1..=1).any(|dx| {
                        binary.get(mid[0].floor() as i64 + dx, mid[1].floor() as i64 + dy)
                    })
                });
                assert!(
                    near_ink,
                    "a segment's middle {mid:?} is a pixel off the ink"
                );
            }
        }
    }

    #[test]
    fn a_page_with_one_broken_stroke_keeps_the_solid_one_out_of_dropout_mode() {
        let binary = half_broken();
        let trace = crate::trace_binary(&binary, &Params::default()).unwrap();
        assert_eq!(trace.dropout(), Some(true));
        let share = trace.dropout_share.expect("a share for a mask");
        assert!(share > 0.2 && share < 0.8, "{share}");
        // Two strokes, each one edge between two ends.
        assert_eq!(trace.graph.components(), 2, "{:?}", trace.graph.edges.len());
        assert_eq!(trace.graph.endpoints().count(), 4);
    }
}
