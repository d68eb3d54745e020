//! Group `loops`: the loops of script letters and cursive joins, whose two strands cross at a
//! shallow angle (docs/quality.md). Each loop is one stroke that crosses itself: it comes in
//! along one strand, runs out past the crossing, turns on a circular arc and comes back along the
//! other strand, through the crossing and out. Near a shallow crossing the two strands share ink
//! for several widths (`w / tan(angle / 2)` px in all), so the ink shows one thick stroke there;
//! the truth is still one crossing (degree 4) and one cycle, whose hole the ink keeps.

use super::{frame, sample_curve, Case, Stroke};

/// Crossing angles of the group, degrees (between the two strands at the crossing).
pub const LOOP_ANGLES: [f64; 4] = [10.0, 20.0, 30.0, 40.0];

/// Stroke widths of the `loops` group, px.
pub const LOOP_WIDTHS: [f64; 4] = [3.0, 4.0, 5.0, 7.0];

/// Unit vector at `degrees` (image coordinates: y down).
fn dir(degrees: f64) -> [f64; 2] {
    let a = degrees.to_radians();
    [a.cos(), a.sin()]
}

fn at(c: [f64; 2], d: [f64; 2], s: f64) -> [f64; 2] {
    [c[0] + d[0] * s, c[1] + d[1] * s]
}

/// One loop crossing itself at `c`: the path from `c` out along the strand at `axis + angle / 2`
/// degrees (`axis - angle / 2` when `mirror`), around the circle of radius `radius` tangent to both
/// strands, and back along the other strand to `c`. Also returns the length of each strand from
/// `c` to the circle.
fn loop_path(
    c: [f64; 2],
    axis: f64,
    angle: f64,
    radius: f64,
    mirror: bool,
) -> (Vec<[f64; 2]>, f64) {
    let half = angle / 2.0;
    let sign = if mirror { -1.0 } else { 1.0 };
    // The circle's center lies on the axis, `radius / sin(half)` from the crossing; each strand
    // touches it `radius / tan(half)` from the crossing.
    let to_center = radius / half.to_radians().sin();
    let strand = radius / half.to_radians().tan();
    let center = at(c, dir(axis), to_center);
    let out = at(c, dir(axis + sign * half), strand);
    // The arc turns through 180 + angle degrees around the far side of the circle.
    let start = axis + sign * (half + 90.0);
    let sweep = -sign * (180.0 + angle);
    let arc = sample_curve(
        |t: f64| at(center, dir(start + t * sweep), radius),
        0.0,
        1.0,
        1.0,
    );
    let mut path = vec![c, out];
    path.extend(arc);
    path.push(c);
    (path, strand)
}

fn framed(name: String, strokes: Vec<Stroke>) -> Case {
    let w = strokes.iter().map(Stroke::max_width).fold(0.0, f64::max);
    frame(&name, "loops", strokes, 2.0 * w + 1.0)
}

/// Group `loops`: at every width of [`LOOP_WIDTHS`] and crossing angle of [`LOOP_ANGLES`], loops
/// whose hole is two widths across (circle radius `1.5 w`):
///
/// - `l`: an upright loop, slanted 15 degrees as script is, entered from below along one strand
///   and left along the other (tails as long as the strands, so the four arms of the crossing
///   part as an X's do);
/// - `e`: the same loop leaning 50 degrees, as an `e`'s eye;
/// - `join`: a loop lying on the baseline, as a cursive join between two letters makes;
/// - `f`: the upper and the lower loop of a script `f`, one stroke crossing itself twice, a stem
///   between the crossings; at 20 degrees and more (at 10 the strands near the lower crossing
///   share ink so long that the scorer's truth cuts that loop open).
pub fn loop_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let c = [0.5, 0.5];
    for w in LOOP_WIDTHS {
        let radius = 1.5 * w;
        for angle in LOOP_ANGLES {
            let half = angle / 2.0;
            for (label, axis) in [("l", -75.0), ("e", -40.0), ("join", -8.0)] {
                let (path, strand) = loop_path(c, axis, angle, radius, false);
                // Coming in along the first strand's line, leaving along the second's.
                let mut points = vec![at(c, dir(axis + half), -strand)];
                points.extend(path);
                points.push(at(c, dir(axis - half), -strand));
                cases.push(framed(
                    format!("{label}_a{angle}_w{w}"),
                    vec![Stroke::new(points, w)],
                ));
            }
            if angle < 20.0 {
                continue;
            }
            // The f: the upper loop crosses at `c`, the stem runs down its second strand's line to
            // the lower crossing, the lower loop (axis turned half round, entered along the stem)
            // comes back up along the first strand's direction. The stem is long enough that the
            // two short tails, parallel and `stem sin(angle)` apart, stay apart by two widths.
            let axis = -75.0;
            let (upper, strand) = loop_path(c, axis, angle, radius, false);
            let stem = strand + 3.0 * w / angle.to_radians().sin();
            let below = at(c, dir(axis - half), -stem);
            let (lower, _) = loop_path(below, axis + 180.0, angle, radius, true);
            let mut points = vec![at(c, dir(axis + half), -strand / 2.0)];
            points.extend(upper);
            points.extend(lower);
            points.push(at(below, dir(axis + half), strand / 2.0));
            cases.push(framed(
                format!("f_a{angle}_w{w}"),
                vec![Stroke::new(points, w)],
            ));
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::truth_graph;

    #[test]
    fn every_loop_is_a_crossing_around_a_hole() {
        let cases = loop_cases();
        assert_eq!(cases.len(), LOOP_WIDTHS.len() * (LOOP_ANGLES.len() * 4 - 1));
        for case in &cases {
            let truth = truth_graph(case);
            let loops = if case.name.starts_with("f_") { 2 } else { 1 };
            let degrees: Vec<usize> = truth
                .junctions()
                .map(|v| truth.vertices[v].degree)
                .collect();
            assert_eq!(degrees, vec![4; loops], "{}", case.name);
            assert_eq!(truth.cycles(), loops, "{}", case.name);
            assert_eq!(truth.endpoints().count(), 2, "{}", case.name);
        }
    }
}
