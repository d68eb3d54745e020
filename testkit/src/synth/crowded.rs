//! Generated cases where strokes crowd (the failures listed in docs/quality.md): cells a fraction of
//! a stroke width across, multi-arm letters from thin to bold, sharp zig-zag corners, three
//! crossings close together, short arms and dots touching a stroke. Every case is drawn from known
//! polylines, framed with a margin of two widths plus one pixel, so its truth is exact.

use super::{frame, render, Case, Font, Stroke};
use ridgeline::Binary;

/// Unit vector at `degrees` (image coordinates: y down, so positive angles turn clockwise).
fn dir(degrees: f64) -> [f64; 2] {
    let a = degrees.to_radians();
    [a.cos(), a.sin()]
}

fn at(c: [f64; 2], d: [f64; 2], s: f64) -> [f64; 2] {
    [c[0] + d[0] * s, c[1] + d[1] * s]
}

fn framed(name: String, group: &str, strokes: Vec<Stroke>) -> Case {
    let w = strokes.iter().map(Stroke::max_width).fold(0.0, f64::max);
    frame(&name, group, strokes, 2.0 * w + 1.0)
}

/// Cell widths of the `cells` group: the background between two neighbouring strokes' ink, in
/// stroke widths.
pub const CELL_SIZES: [f64; 4] = [0.5, 1.0, 2.0, 3.0];

/// Group `cells`: closed boxes divided into 1 x 1, 1 x 2 (日), 2 x 2 (田) and 3 x 3 cells, and open
/// grids of 2 x 2 (#) and 4 x 4 lines that run one pitch past each other, with cells
/// [`CELL_SIZES`] stroke widths across and strokes 4, 6 and 10 px wide (4 rather than 3, so half
/// a width is two whole pixels of background: a hole, not a speck). A box is its frame (one
/// closed stroke, so its corners are corners) with the inner lines ending on it (T's) and
/// crossing one another (X's).
pub fn cell_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for w in [4.0f64, 6.0, 10.0] {
        for cells in CELL_SIZES {
            // Centerline spacing: one stroke width of ink plus the cell.
            let pitch = w * (1.0 + cells);
            for (kind, columns, rows) in [
                ("box1x1", 1, 1),
                ("box1x2", 1, 2),
                ("box2x2", 2, 2),
                ("box3x3", 3, 3),
            ] {
                let (x1, y1) = (columns as f64 * pitch, rows as f64 * pitch);
                let mut strokes = vec![Stroke::new(
                    vec![[0.0, 0.0], [x1, 0.0], [x1, y1], [0.0, y1], [0.0, 0.0]],
                    w,
                )];
                for i in 1..columns {
                    let x = i as f64 * pitch;
                    strokes.push(Stroke::new(vec![[x, 0.0], [x, y1]], w));
                }
                for j in 1..rows {
                    let y = j as f64 * pitch;
                    strokes.push(Stroke::new(vec![[0.0, y], [x1, y]], w));
                }
                cases.push(framed(format!("{kind}_c{cells}_w{w}"), "cells", strokes));
            }
            for (kind, lines) in [("hash", 2), ("grid4", 4)] {
                let over = pitch.max(2.0 * w);
                let end = (lines - 1) as f64 * pitch + over;
                let mut strokes = Vec::new();
                for i in 0..lines {
                    let s = i as f64 * pitch;
                    strokes.push(Stroke::new(vec![[s, -over], [s, end]], w));
                    strokes.push(Stroke::new(vec![[-over, s], [end, s]], w));
                }
                cases.push(framed(format!("{kind}_c{cells}_w{w}"), "cells", strokes));
            }
        }
    }
    cases
}

/// Stroke widths of the `letters` group, px.
pub const LETTER_WIDTHS: [f64; 5] = [3.0, 5.0, 8.0, 11.0, 14.0];

/// Group `letters`: the multi-arm letters `m w M H E # t f` of the Roman simplex font (the one of
/// the `text` group) at 84 px cap height (4 px per Hershey unit), strokes [`LETTER_WIDTHS`] wide,
/// from thin to bold: arches leaving a stem, four arms into one point, bars that must not go
/// missing.
pub fn letter_cases() -> Vec<Case> {
    let font = Font::futural();
    let mut cases = Vec::new();
    for w in LETTER_WIDTHS {
        for (c, label) in [
            ('m', "m"),
            ('w', "w"),
            ('M', "M_upper"),
            ('H', "H_upper"),
            ('E', "E_upper"),
            ('#', "hash"),
            ('t', "t"),
            ('f', "f"),
        ] {
            let (strokes, _) = font.line(&c.to_string(), 0.0, 0.0, 4.0, w);
            cases.push(framed(format!("letter_{label}_w{w}"), "letters", strokes));
        }
    }
    cases
}

/// Corner angles of the `zigzags` group, degrees (the angle between the two segments at a corner).
pub const ZIGZAG_CORNERS: [f64; 5] = [30.0, 60.0, 90.0, 120.0, 150.0];

/// Group `zigzags`: one stroke of five segments turning alternately left and right with every
/// corner [`ZIGZAG_CORNERS`] degrees, 3, 6 and 10 px wide, segments `max(40, 8 w)` long. At the
/// sharp corners the two segments share ink for `w / (2 tan(angle / 2))` px; the corner must stay
/// a corner, not be cut or become a junction.
pub fn zigzag_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for w in [3.0f64, 6.0, 10.0] {
        for corner in ZIGZAG_CORNERS {
            let length = (8.0 * w).max(40.0);
            // Segments leave the axis by +-(90 - corner / 2) degrees; the axis is tilted by 7
            // degrees so no segment runs along the pixel grid.
            let tilt = 90.0 - corner / 2.0;
            let mut points = vec![[0.0, 0.0]];
            for k in 0..5 {
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let last = points[points.len() - 1];
                points.push(at(last, dir(7.0 + sign * tilt), length));
            }
            cases.push(framed(
                format!("zigzag{corner}_w{w}"),
                "zigzags",
                vec![Stroke::new(points, w)],
            ));
        }
    }
    cases
}

/// Spreads of the `triples` group: the radius, in stroke widths, of the circle through the three
/// pairwise crossings.
pub const TRIPLE_SPREADS: [f64; 4] = [0.5, 1.0, 1.5, 2.0];

/// Group `triples`: three straight strokes whose three pairwise crossings lie on a circle of
/// radius [`TRIPLE_SPREADS`] stroke widths (each line passes the center at half that distance),
/// at 0/60/120 and 0/45/100 degrees, 4 and 8 px wide. At 0.5 widths the crossings are closer than
/// a width, so the truth is one degree-6 vertex; at 2 widths the ink leaves a triangular hole.
pub fn triple_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let c = [0.5, 0.5];
    for w in [4.0f64, 8.0] {
        for spread in TRIPLE_SPREADS {
            for (label, angles) in [("even", [0.0, 60.0, 120.0]), ("uneven", [0.0, 45.0, 100.0])] {
                let half = (6.0 * w).max(40.0);
                let offset = spread * w / 2.0;
                let strokes = angles
                    .iter()
                    .zip([1.0, -1.0, 1.0])
                    .map(|(&a, side)| {
                        let d = dir(a + 10.0);
                        // The second line is moved to the other side, so the three normals are
                        // at most 180 degrees apart and the lines bound a triangle around the
                        // center (equilateral for 0/60/120, with inradius `offset`).
                        let n = [-d[1] * side, d[0] * side];
                        let p = at(c, n, offset);
                        Stroke::new(vec![at(p, d, -half), at(p, d, half)], w)
                    })
                    .collect();
                cases.push(framed(
                    format!("triple_{label}_s{spread}_w{w}"),
                    "triples",
                    strokes,
                ));
            }
        }
    }
    cases
}

/// Arm lengths of the `arms` group, in stroke widths: how far the arm's ink reaches beyond the
/// edge of the stroke it leaves, along the arm.
pub const ARM_LENGTHS: [f64; 3] = [1.0, 1.5, 2.0];

/// Group `arms`: a straight stroke with a short arm leaving its middle (square to it, at 45
/// degrees, or square on both sides: a crossing whose second stroke is short), the arm's ink
/// reaching [`ARM_LENGTHS`] widths beyond the stroke's edge, 4, 8 and 12 px wide; and a dot (a
/// round blob 1, 1.5 or 2 widths across, drawn as a stroke half its width long) touching the side
/// or the end of a stroke 4 or 8 px wide. The ink shows each arm and dot as a branch of its own:
/// a junction and an end.
pub fn arm_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let c = [0.5, 0.5];
    for w in [4.0f64, 8.0, 12.0] {
        let half = (8.0 * w).max(40.0);
        let bar = || Stroke::new(vec![[c[0] - half, c[1]], [c[0] + half, c[1]]], w);
        for k in ARM_LENGTHS {
            // Square to the bar: the centerline leaves the bar's centerline and its cap ends k w
            // beyond the bar's ink edge.
            let square = Stroke::new(vec![c, [c[0], c[1] - k * w]], w);
            cases.push(framed(
                format!("arm_square_k{k}_w{w}"),
                "arms",
                vec![bar(), square],
            ));
            // At 45 degrees: the centerline crosses the bar's edge (w / 2 off its centerline)
            // after w / (2 sin 45) px.
            let length = k * w + w / 2.0 * (std::f64::consts::SQRT_2 - 1.0);
            let slanted = Stroke::new(vec![c, at(c, dir(-45.0), length)], w);
            cases.push(framed(
                format!("arm_slanted_k{k}_w{w}"),
                "arms",
                vec![bar(), slanted],
            ));
            let both = Stroke::new(vec![[c[0], c[1] + k * w], [c[0], c[1] - k * w]], w);
            cases.push(framed(
                format!("arm_cross_k{k}_w{w}"),
                "arms",
                vec![bar(), both],
            ));
        }
    }
    for w in [4.0f64, 8.0] {
        let half = (8.0 * w).max(40.0);
        let bar = Stroke::new(vec![[c[0] - half, c[1]], [c[0] + half, c[1]]], w);
        for size in [1.0, 1.5, 2.0] {
            let d = size * w;
            for (place, anchor, away) in [
                ("side", c, dir(-60.0)),
                ("end", [c[0] + half, c[1]], dir(-30.0)),
            ] {
                let dot = touching_dot(&bar, anchor, away, d);
                cases.push(framed(
                    format!("dot_{place}_d{size}_w{w}"),
                    "arms",
                    vec![bar.clone(), dot],
                ));
            }
        }
    }
    cases
}

/// A dot `d` px across (a stroke of width `d`, `d / 2` long, pointing along `away`) moved in from
/// `anchor` along `away` until its ink first shares a pixel edge with the ink of `bar`.
fn touching_dot(bar: &Stroke, anchor: [f64; 2], away: [f64; 2], d: f64) -> Stroke {
    // Draw in a local image around the anchor, shifted so every coordinate is positive.
    let reach = 2.0 * d + bar.max_width() + 8.0;
    let shift = [reach - anchor[0].floor(), reach - anchor[1].floor()];
    let size = (2.0 * reach) as u32 + 1;
    let moved = |s: &Stroke| {
        let mut s = s.clone();
        s.translate(shift);
        s
    };
    let bar_ink = render(&[moved(bar)], size, size);
    let dot_at = |t: f64| {
        let start = at(anchor, away, t);
        Stroke::new(vec![start, at(start, away, d / 2.0)], d)
    };
    let touches = |ink: &Binary| {
        (0..size as i64).any(|y| {
            (0..size as i64).any(|x| {
                ink.get(x, y)
                    && [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)]
                        .iter()
                        .any(|&(dx, dy)| bar_ink.get(x + dx, y + dy))
            })
        })
    };
    let mut t = bar.max_width() / 2.0 + d;
    while t > 0.0 && !touches(&render(&[moved(&dot_at(t))], size, size)) {
        t -= 0.25;
    }
    dot_at(t.max(0.0))
}
