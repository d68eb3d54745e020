//! Group `overhangs`: a stroke running a little past the one it meets, and the corners and T's
//! without any overhang that they must not be confused with (docs/quality.md). Where two strokes
//! of a character meet at a corner (the corners of 口 and 日) or at a T (a stem under a bar),
//! fonts and hands often run one stroke a fraction of a width past the other. Whether that
//! overhang is an arm is what the truth says, by the scorer's one rule for every group
//! (`score::truth_graph`): a tail past the stroke it meets is dropped when its centerline ends
//! inside that stroke's ink (within its half-width and half a pixel), and kept otherwise. So the
//! same group scores both "keep the arm" (overhangs of 1 and 2 widths) and "drop the spur"
//! (overhangs of a quarter and half a width, and the corners without overhang, which thinning
//! gives a branch into the corner).

use super::{frame, sample_curve, Case, Stroke};

/// Overhangs of the group, in stroke widths: how far the overhanging stroke's centerline runs
/// past the centerline of the stroke it meets (its round cap sticks out that far past the other
/// stroke's ink edge).
pub const OVERHANGS: [f64; 4] = [0.25, 0.5, 1.0, 2.0];

/// Stroke widths of the `overhangs` group, px.
pub const OVERHANG_WIDTHS: [f64; 5] = [3.0, 5.0, 8.0, 11.0, 14.0];

fn framed(name: String, strokes: Vec<Stroke>) -> Case {
    let w = strokes.iter().map(Stroke::max_width).fold(0.0, f64::max);
    frame(&name, "overhangs", strokes, 2.0 * w + 1.0)
}

/// Group `overhangs`, at every width of [`OVERHANG_WIDTHS`], legs `max(40, 8 w)` px long, on
/// pixel centers:
///
/// - `corner_o{k}`: the top-left corner of a box whose left side runs [`OVERHANGS`] `k` widths
///   above the top side (the top side starts on the left side's centerline: a T at the corner);
/// - `tee_o{k}`: a stem from below that runs `k` widths past a bar's centerline (a crossing with
///   a short second arm);
/// - `corner_round`, `corner_arc`, `corner_square`: the same corner with no overhang, drawn with
///   a round pen, with a centerline rounded on a radius of one width, and squared off (the outer
///   corner's square filled with ink, as a font or a square pen draws it);
/// - `tee_plain`: a stem ending on the bar's centerline.
pub fn overhang_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let c = [0.5, 0.5];
    for w in OVERHANG_WIDTHS {
        let leg = (8.0 * w).max(40.0);
        // The corner at `c`: the left side goes down, the top side goes right.
        let down = [c[0], c[1] + leg];
        let right = [c[0] + leg, c[1]];
        for k in OVERHANGS {
            let left = Stroke::new(vec![down, [c[0], c[1] - k * w]], w);
            let top = Stroke::new(vec![c, right], w);
            cases.push(framed(format!("corner_o{k}_w{w}"), vec![left, top]));
            let bar = Stroke::new(vec![[c[0] - leg, c[1]], right], w);
            let stem = Stroke::new(vec![down, [c[0], c[1] - k * w]], w);
            cases.push(framed(format!("tee_o{k}_w{w}"), vec![bar, stem]));
        }
        cases.push(framed(
            format!("corner_round_w{w}"),
            vec![Stroke::new(vec![down, c, right], w)],
        ));
        // A quarter circle of radius w around (c + w, c + w) joins the legs.
        let center = [c[0] + w, c[1] + w];
        let arc = sample_curve(
            |t: f64| [center[0] - w * t.cos(), center[1] - w * t.sin()],
            0.0,
            std::f64::consts::FRAC_PI_2,
            1.0,
        );
        let mut points = vec![down];
        points.extend(arc);
        points.push(right);
        cases.push(framed(
            format!("corner_arc_w{w}"),
            vec![Stroke::new(points, w)],
        ));
        let mut square = framed(
            format!("corner_square_w{w}"),
            vec![Stroke::new(vec![down, c, right], w)],
        );
        fill_square(&mut square, 1, w);
        cases.push(square);
        cases.push(framed(
            format!("tee_plain_w{w}"),
            vec![
                Stroke::new(vec![[c[0] - leg, c[1]], right], w),
                Stroke::new(vec![down, c], w),
            ],
        ));
    }
    cases
}

/// Fills with ink the axis-aligned square of side `w` centered on point `k` of the case's first
/// stroke (pixel centers inside it or on its edge): the corner a square pen draws.
fn fill_square(case: &mut Case, k: usize, w: f64) {
    let p = case.strokes[0].points[k];
    let b = &mut case.binary;
    let half = w / 2.0;
    let (x0, x1) = ((p[0] - half - 0.5).floor(), (p[0] + half).ceil());
    let (y0, y1) = ((p[1] - half - 0.5).floor(), (p[1] + half).ceil());
    for y in (y0.max(0.0) as u32)..(y1.max(0.0) as u32).min(b.height) {
        for x in (x0.max(0.0) as u32)..(x1.max(0.0) as u32).min(b.width) {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            if (px - p[0]).abs() <= half && (py - p[1]).abs() <= half {
                b.ink[y as usize * b.width as usize + x as usize] = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::truth_graph;

    #[test]
    fn the_truth_keeps_long_overhangs_and_drops_short_ones() {
        let cases = overhang_cases();
        assert_eq!(
            cases.len(),
            OVERHANG_WIDTHS.len() * (2 * OVERHANGS.len() + 4)
        );
        for case in &cases {
            let truth = truth_graph(case);
            let junctions: Vec<usize> = truth
                .junctions()
                .map(|v| truth.vertices[v].degree)
                .collect();
            let ends = truth.endpoints().count();
            let name = case.name.as_str();
            // At a corner the overhang's cap touches the other stroke's cap until it runs a
            // width past it, and the truth joins touching ends: an arm from two widths on.
            let arm = name.contains("_o2_") || (name.starts_with("tee") && name.contains("_o1_"));
            let (want_junctions, want_ends) = if name.starts_with("corner_o") {
                if arm {
                    (vec![3], 3)
                } else {
                    (vec![], 2)
                }
            } else if name.starts_with("tee_o") {
                if arm {
                    (vec![4], 4)
                } else {
                    (vec![3], 3)
                }
            } else if name.starts_with("tee_plain") {
                (vec![3], 3)
            } else {
                (vec![], 2)
            };
            assert_eq!(junctions, want_junctions, "{name}");
            assert_eq!(ends, want_ends, "{name}");
        }
    }

    #[test]
    fn a_square_corner_has_a_square_of_ink() {
        let cases = overhang_cases();
        let round = cases
            .iter()
            .find(|c| c.name == "corner_round_w8")
            .expect("round");
        let square = cases
            .iter()
            .find(|c| c.name == "corner_square_w8")
            .expect("square");
        assert_eq!(round.binary.width, square.binary.width);
        // The square adds the outer corner's pixels beyond the round pen's quarter disk.
        assert!(square.binary.count() > round.binary.count());
        let p = square.strokes[0].points[1];
        let (x, y) = ((p[0] - 3.5).floor() as i64, (p[1] - 3.5).floor() as i64);
        assert!(square.binary.get(x, y) && !round.binary.get(x, y));
    }
}
