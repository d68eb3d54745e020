//! Group `thin`: drawings whose strokes are one or two pixels wide (docs/quality.md): thin line
//! art, and masks that are already a skeleton (a one-pixel drawing is what a thinning tool
//! writes). A one-pixel stroke is ink like any other: junctions two or three pixels apart are
//! distinct junctions, a loop around a few background pixels is a loop, a branch of a few pixels
//! is an arm.

use super::{frame, text_cases, Case, Font, Stroke};

/// Stroke widths of the `thin` group, px.
pub const THIN_WIDTHS: [f64; 2] = [1.0, 2.0];

/// Unit vector at `degrees` (image coordinates: y down).
fn dir(degrees: f64) -> [f64; 2] {
    let a = degrees.to_radians();
    [a.cos(), a.sin()]
}

fn at(c: [f64; 2], d: [f64; 2], s: f64) -> [f64; 2] {
    [c[0] + d[0] * s, c[1] + d[1] * s]
}

fn framed(name: String, strokes: Vec<Stroke>) -> Case {
    frame(&name, "thin", strokes, 4.0)
}

/// The strokes with every width set to `w`.
fn with_width(strokes: &[Stroke], w: f64) -> Vec<Stroke> {
    strokes
        .iter()
        .map(|s| Stroke {
            points: s.points.clone(),
            widths: vec![w; s.points.len()],
        })
        .collect()
}

/// Group `thin`, at each width of [`THIN_WIDTHS`]:
///
/// - `letter_*`: the multi-arm letters of the `letters` group (`m w M H E # t f`, Roman simplex at
///   4 px per Hershey unit);
/// - `text*`: the first four lines of the `text` group at 36 px cap height;
/// - `x{a}`: two straight strokes crossing at 15, 30, 60 and 90 degrees;
/// - `ladder_g{g}`: two rails 8 px apart joined by rungs every `g` = `w + 2`, `w + 3` and `w + 5`
///   px (junctions that close, cells one to four pixels across);
/// - `comb_b{b}`: a bar with teeth on one side, 6 px apart, whose ink reaches `b` = `w + 1`,
///   `w + 2` and `w + 4` px beyond the bar's (short arms, not spurs: each tooth's centerline ends
///   beyond the bar's ink, though at `w + 1` on a 2 px bar its cap's ink touches the bar's);
/// - `grid_p{p}`: a 4 x 4 grid of lines `p` = `w + 3` and `w + 5` px apart (cells of two and four
///   pixels across, each a hole).
pub fn thin_cases() -> Vec<Case> {
    let font = Font::futural();
    let lines: Vec<Case> = text_cases()
        .into_iter()
        .filter(|c| c.name.contains("_h36_"))
        .take(4)
        .collect();
    let mut cases = Vec::new();
    for w in THIN_WIDTHS {
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
            cases.push(framed(format!("thin_letter_{label}_w{w}"), strokes));
        }
        for line in &lines {
            let name = line.name.split('_').next().unwrap_or("text");
            cases.push(framed(
                format!("thin_{name}_w{w}"),
                with_width(&line.strokes, w),
            ));
        }
        let c = [0.5, 0.5];
        for angle in [15.0, 30.0, 60.0, 90.0] {
            let (a, b) = (dir(7.0), dir(7.0 + angle));
            let strokes = vec![
                Stroke::new(vec![at(c, a, -30.0), at(c, a, 30.0)], w),
                Stroke::new(vec![at(c, b, -30.0), at(c, b, 30.0)], w),
            ];
            cases.push(framed(format!("thin_x{angle}_w{w}"), strokes));
        }
        for gap in [w + 2.0, w + 3.0, w + 5.0] {
            let length = 8.0 * gap;
            let mut strokes = vec![
                Stroke::new(vec![[0.5, 0.5], [length + 0.5, 0.5]], w),
                Stroke::new(vec![[0.5, 8.5], [length + 0.5, 8.5]], w),
            ];
            for k in 1..8 {
                let x = k as f64 * gap + 0.5;
                strokes.push(Stroke::new(vec![[x, 0.5], [x, 8.5]], w));
            }
            cases.push(framed(format!("thin_ladder_g{gap}_w{w}"), strokes));
        }
        for tooth in [w + 1.0, w + 2.0, w + 4.0] {
            let mut strokes = vec![Stroke::new(vec![[0.5, 0.5], [48.5, 0.5]], w)];
            for k in 1..8 {
                let x = k as f64 * 6.0 + 0.5;
                strokes.push(Stroke::new(vec![[x, 0.5], [x, 0.5 + tooth]], w));
            }
            cases.push(framed(format!("thin_comb_b{tooth}_w{w}"), strokes));
        }
        for pitch in [w + 3.0, w + 5.0] {
            let mut strokes = Vec::new();
            let (start, end) = (-pitch, 4.0 * pitch);
            for i in 0..4 {
                let s = i as f64 * pitch + 0.5;
                strokes.push(Stroke::new(vec![[s, start], [s, end]], w));
                strokes.push(Stroke::new(vec![[start, s], [end, s]], w));
            }
            cases.push(framed(format!("thin_grid_p{pitch}_w{w}"), strokes));
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::truth_graph;

    #[test]
    fn close_junctions_stay_apart_in_the_truth() {
        let cases = thin_cases();
        for w in THIN_WIDTHS {
            let ladder = cases
                .iter()
                .find(|c| c.name == format!("thin_ladder_g{}_w{w}", w + 2.0))
                .expect("ladder");
            let truth = truth_graph(ladder);
            // Seven rungs, two T's each; six cells between them are holes, as are none of the ends.
            assert_eq!(truth.junctions().count(), 14, "w{w}");
            assert_eq!(truth.cycles(), 6, "w{w}");
            let comb = cases
                .iter()
                .find(|c| c.name == format!("thin_comb_b{}_w{w}", w + 2.0))
                .expect("comb");
            let truth = truth_graph(comb);
            assert_eq!(truth.endpoints().count(), 9, "w{w}");
        }
    }

    #[test]
    fn a_letter_has_the_same_truth_at_one_and_two_pixels() {
        // Hershey strokes end on pixel corners: at 1 px an end's round cap holds no pixel
        // center, yet its ink touches the stroke it ends on (the bar of H on its stems).
        let cases = thin_cases();
        for label in ["m", "w", "M_upper", "H_upper", "E_upper", "hash", "t", "f"] {
            let counts = |w: f64| {
                let name = format!("thin_letter_{label}_w{w}");
                let case = cases.iter().find(|c| c.name == name).expect("letter");
                let truth = truth_graph(case);
                (truth.junctions().count(), truth.endpoints().count())
            };
            assert_eq!(counts(1.0), counts(2.0), "{label}");
        }
    }
}
