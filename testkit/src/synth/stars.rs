//! Group `stars`: a stroke starting on the crossing of two others, as where 乀 leaves the
//! crossing of 木's bar and vertical, or in 炔 (docs/quality.md, "Stars split by thinning, and
//! frame T's"). A bar crosses a vertical; a third stroke starts on the vertical at or a little
//! below the crossing and leaves it downwards at a slant. Thinning forks the third stroke off
//! where the inks part, a width or more down the vertical, so the skeleton shows a crossing and a
//! Y; the truth (`score::truth_graph`: junctions closer than one stroke width are one vertex) is
//! one vertex of degree 5 when the third stroke starts less than a width from the crossing.

use super::{frame, Case, Stroke};

/// How far below the crossing the third stroke starts on the vertical, in stroke widths.
pub const STAR_OFFSETS: [f64; 4] = [0.0, 0.25, 0.5, 0.75];

/// The angles the third stroke leaves the vertical at, degrees.
pub const STAR_ANGLES: [f64; 4] = [30.0, 40.0, 45.0, 55.0];

/// Stroke widths of the `stars` group, px.
pub const STAR_WIDTHS: [f64; 4] = [8.0, 10.0, 12.0, 15.0];

/// Group `stars`: at every width of [`STAR_WIDTHS`], the bar and the vertical `max(40, 6 w)` px
/// either side of their crossing (on a pixel center), the third stroke starting
/// [`STAR_OFFSETS`] widths down the vertical and leaving it at [`STAR_ANGLES`] degrees, as long
/// as the vertical's lower half.
pub fn star_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let c = [0.5, 0.5];
    for w in STAR_WIDTHS {
        let half = (6.0 * w).max(40.0);
        for offset in STAR_OFFSETS {
            for angle in STAR_ANGLES {
                let (s, k) = (angle.to_radians().sin(), angle.to_radians().cos());
                let start = [c[0], c[1] + offset * w];
                let strokes = vec![
                    Stroke::new(vec![[c[0], c[1] - half], [c[0], c[1] + half]], w),
                    Stroke::new(vec![[c[0] - half, c[1]], [c[0] + half, c[1]]], w),
                    Stroke::new(vec![start, [start[0] + half * s, start[1] + half * k]], w),
                ];
                cases.push(frame(
                    &format!("star_o{offset}_a{angle}_w{w}"),
                    "stars",
                    strokes,
                    2.0 * w + 1.0,
                ));
            }
        }
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::score::truth_graph;

    #[test]
    fn every_star_is_one_vertex_of_degree_five() {
        let cases = star_cases();
        assert_eq!(
            cases.len(),
            STAR_WIDTHS.len() * STAR_OFFSETS.len() * STAR_ANGLES.len()
        );
        for case in &cases {
            let truth = truth_graph(case);
            let degrees: Vec<usize> = truth
                .junctions()
                .map(|v| truth.vertices[v].degree)
                .collect();
            assert_eq!(degrees, vec![5], "{}", case.name);
            assert_eq!(truth.endpoints().count(), 5, "{}", case.name);
        }
    }
}
