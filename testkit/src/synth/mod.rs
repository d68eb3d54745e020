//! Ground-truth fixtures: known centerlines rendered thickly, shared by the tests, the benchmarks
//! and the generator of `samples/`.
//!
//! Every case carries the polylines it was drawn from, so quality is measured against the truth
//! (docs/design.md, "Measuring quality"). Three groups make [`all_cases`]: `hard` (crossings,
//! junctions, loops, near misses, dropout), `text` (Hershey single-stroke glyphs) and `prints`
//! (fingerprint-like ridge fields traced as level sets of a phase function). The groups where
//! strokes crowd (docs/quality.md) come on their own: [`font_cases`] (Hershey script, cursive,
//! Gothic and Times lines), [`japanese_cases`] (Hershey kana and kanji) and the generated
//! [`cell_cases`], [`letter_cases`], [`zigzag_cases`], [`triple_cases`] and [`arm_cases`]; the
//! groups that score the graph's hardest decisions too ([`GRAPH_GROUPS`]): [`overhang_cases`]
//! (a stroke running a little past the one it meets), [`loop_cases`] (script loops crossing at
//! 10-40 degrees), [`thin_cases`] (one- and two-pixel drawings) and [`star_cases`] (a stroke
//! starting on the crossing of two others).
//! Everything is deterministic: the same call gives the same pixels and the same truth.

mod crowded;
mod degraded;
mod hershey;
mod loops;
mod overhangs;
mod pages;
mod prints;
mod rng;
mod shapes;
mod stars;
mod strips;
mod thin_lines;

pub use crowded::{
    arm_cases, cell_cases, letter_cases, triple_cases, zigzag_cases, ARM_LENGTHS, CELL_SIZES,
    LETTER_WIDTHS, TRIPLE_SPREADS, ZIGZAG_CORNERS,
};
pub use degraded::{degrade, degrade_cases, Degraded, Recipe};
pub use hershey::{
    font_cases, japanese_cases, page, text_cases, text_line, Font, Glyph, FONTS,
    SINGLE_PASS_TOLERANCE,
};
pub use loops::{loop_cases, LOOP_ANGLES, LOOP_WIDTHS};
pub use overhangs::{overhang_cases, OVERHANGS, OVERHANG_WIDTHS};
pub use pages::{page_cases, PAGE_CASES};
pub use prints::{dense_print_cases, finger_area, print_cases, DENSE_PRINT_SIZE};
pub use rng::SplitMix64;
pub use shapes::hard_cases;
pub use stars::{star_cases, STAR_ANGLES, STAR_OFFSETS, STAR_WIDTHS};
pub use strips::{
    helix_tube, sine_strip, strip_cases, tube_cases, uniform_cloud, StripCase, StripCurve,
    TubeCase, TubeCurve, STRIP_WIDTH, TUBE_WIDTH,
};
pub use thin_lines::{thin_cases, THIN_WIDTHS};

pub use ridgeline::draw::{render, Stroke};
use ridgeline::Binary;

/// One generated test image with its truth.
#[derive(Clone, Debug)]
pub struct Case {
    /// Unique name, e.g. `x30_w8`.
    pub name: String,
    /// Group for tables: `hard`, `text`, `prints`.
    pub group: String,
    /// The rendered foreground (after any dropout).
    pub binary: Binary,
    /// The true centerlines.
    pub strokes: Vec<Stroke>,
}

/// Every fixture of the first benchmark groups: [`hard_cases`], then [`text_cases`], then
/// [`print_cases`].
pub fn all_cases() -> Vec<Case> {
    let mut cases = hard_cases();
    cases.extend(text_cases());
    cases.extend(print_cases());
    cases
}

/// The generated groups where strokes crowd, by name, in the benchmark's order: the four
/// [`FONTS`], `japanese`, `cells`, `letters`, `zigzags`, `triples`, `arms`.
pub const CROWDED_GROUPS: [&str; 10] = [
    "scriptc",
    "cursive",
    "gothiceng",
    "timesr",
    "japanese",
    "cells",
    "letters",
    "zigzags",
    "triples",
    "arms",
];

/// The generated groups that score the graph where its decisions are hardest, by name, in the
/// benchmark's order: [`overhang_cases`], [`loop_cases`], [`thin_cases`], [`star_cases`].
pub const GRAPH_GROUPS: [&str; 4] = ["overhangs", "loops", "thin", "stars"];

/// The cases of one generated group by name: those of [`all_cases`] (`hard`, `text`, `prints`),
/// the [`CROWDED_GROUPS`] and the [`GRAPH_GROUPS`]; `None` for any other name.
pub fn group_cases(group: &str) -> Option<Vec<Case>> {
    Some(match group {
        "hard" => hard_cases(),
        "text" => text_cases(),
        "prints" => print_cases(),
        "japanese" => japanese_cases(),
        "cells" => cell_cases(),
        "letters" => letter_cases(),
        "zigzags" => zigzag_cases(),
        "triples" => triple_cases(),
        "arms" => arm_cases(),
        "overhangs" => overhang_cases(),
        "loops" => loop_cases(),
        "thin" => thin_cases(),
        "stars" => star_cases(),
        font if FONTS.contains(&font) => font_cases(font),
        _ => return None,
    })
}

/// Frames strokes in an image just big enough to hold their ink with a margin of at least
/// `margin` px on every side, renders them and names the case. The strokes are moved by whole
/// pixels, so centerlines placed on pixel centers stay on pixel centers.
pub fn frame(name: &str, group: &str, mut strokes: Vec<Stroke>, margin: f64) -> Case {
    let mut min = [f64::INFINITY; 2];
    let mut max = [f64::NEG_INFINITY; 2];
    for stroke in &strokes {
        for (p, w) in stroke.points.iter().zip(&stroke.widths) {
            for k in 0..2 {
                min[k] = min[k].min(p[k] - w / 2.0);
                max[k] = max[k].max(p[k] + w / 2.0);
            }
        }
    }
    if !min[0].is_finite() {
        min = [0.0; 2];
        max = [0.0; 2];
    }
    let offset = [(margin - min[0]).ceil(), (margin - min[1]).ceil()];
    for stroke in &mut strokes {
        stroke.translate(offset);
    }
    let width = (max[0] + offset[0] + margin).ceil().max(1.0) as u32;
    let height = (max[1] + offset[1] + margin).ceil().max(1.0) as u32;
    let binary = render(&strokes, width, height);
    Case {
        name: name.to_string(),
        group: group.to_string(),
        binary,
        strokes,
    }
}

/// Knocks out ink: each ink pixel inside `region` = `[x0, y0, x1, y1]` (half-open, pixels) turns
/// to background with probability `fraction`, drawn from a [`SplitMix64`] seeded with `seed`.
/// Models broken, speckled strokes (faint scans, dry ink).
pub fn dropout(binary: &mut Binary, region: [u32; 4], fraction: f64, seed: u64) {
    let mut rng = SplitMix64::new(seed);
    let x1 = region[2].min(binary.width);
    let y1 = region[3].min(binary.height);
    let w = binary.width as usize;
    for y in region[1]..y1 {
        for x in region[0]..x1 {
            let i = y as usize * w + x as usize;
            // One draw per pixel of the region, ink or not, so the pattern does not depend on
            // which pixels happen to be ink.
            let drop = rng.next_f64() < fraction;
            if drop {
                binary.ink[i] = false;
            }
        }
    }
}

/// Samples a parametric curve `f(t)`, `t` in `[t0, t1]`, with at most `spacing` px between
/// consecutive points (refined from a coarse pass, so the spacing holds where the curve is fast).
pub(crate) fn sample_curve(
    f: impl Fn(f64) -> [f64; 2],
    t0: f64,
    t1: f64,
    spacing: f64,
) -> Vec<[f64; 2]> {
    // A coarse pass estimates the length; then a uniform step in t with a safety factor, checked.
    let coarse = 256;
    let mut length = 0.0;
    let mut prev = f(t0);
    let mut max_step: f64 = 0.0;
    for i in 1..=coarse {
        let p = f(t0 + (t1 - t0) * i as f64 / coarse as f64);
        let step = (p[0] - prev[0]).hypot(p[1] - prev[1]);
        length += step;
        max_step = max_step.max(step);
        prev = p;
    }
    // Speed varies along the curve: size the step from the fastest coarse interval.
    let fast = max_step * coarse as f64;
    let mut n = ((fast.max(length) / spacing) * 1.25).ceil().max(1.0) as usize;
    loop {
        let points: Vec<[f64; 2]> = (0..=n)
            .map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64))
            .collect();
        let ok = points
            .windows(2)
            .all(|s| (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1]) <= spacing);
        if ok || n > 1 << 22 {
            return points;
        }
        n *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nearest ink pixel center to `p` is within `tol` px.
    fn near_ink(binary: &Binary, p: [f64; 2], tol: f64) -> bool {
        let r = tol.ceil() as i64 + 1;
        let (cx, cy) = (p[0].floor() as i64, p[1].floor() as i64);
        for y in cy - r..=cy + r {
            for x in cx - r..=cx + r {
                if binary.get(x, y) && (x as f64 + 0.5 - p[0]).hypot(y as f64 + 0.5 - p[1]) <= tol {
                    return true;
                }
            }
        }
        false
    }

    /// Whether pixel center `p` is within the local half width + `slack` of some stroke.
    fn explained(strokes: &[Stroke], p: [f64; 2], slack: f64) -> bool {
        strokes.iter().any(|s| {
            let n = s.points.len();
            (0..n.saturating_sub(1).max(1)).any(|i| {
                let j = (i + 1).min(n - 1);
                let (d, t) = ridgeline::geometry::segment_closest(p, s.points[i], s.points[j]);
                d <= (s.widths[i] + t * (s.widths[j] - s.widths[i])) / 2.0 + slack
            })
        })
    }

    fn check_case(case: &Case) {
        let b = &case.binary;
        assert_eq!(
            b.ink.len(),
            b.width as usize * b.height as usize,
            "{}",
            case.name
        );
        assert!(!case.strokes.is_empty(), "{}", case.name);
        let dropped = case.name.starts_with("dropout");
        for s in &case.strokes {
            assert_eq!(s.points.len(), s.widths.len(), "{}", case.name);
            assert!(s.points.len() >= 2, "{}", case.name);
            for p in &s.points {
                assert!(p[0].is_finite() && p[1].is_finite(), "{}", case.name);
                // Dropout may clear every pixel near a truth point; the region is part of a
                // stroke at least 7 px wide, so 2.5 px still finds surviving ink.
                let tol = if dropped { 3.5 } else { 1.0 };
                assert!(
                    near_ink(b, *p, tol),
                    "{}: truth point {:?} off the ink",
                    case.name,
                    p
                );
            }
        }
        // Every ink pixel lies in some stroke's rendered width (+1 px).
        for y in 0..b.height as i64 {
            for x in 0..b.width as i64 {
                if b.get(x, y) {
                    let p = [x as f64 + 0.5, y as f64 + 0.5];
                    assert!(
                        explained(&case.strokes, p, 1.0),
                        "{}: stray ink at {x},{y}",
                        case.name
                    );
                }
            }
        }
    }

    #[test]
    fn hard_cases_truth_on_ink() {
        let cases = hard_cases();
        assert!(cases.len() >= 40);
        for case in &cases {
            assert_eq!(case.group, "hard");
            check_case(case);
        }
    }

    #[test]
    fn text_cases_truth_on_ink() {
        let cases = text_cases();
        assert!((20..=30).contains(&cases.len()));
        for case in &cases {
            assert_eq!(case.group, "text");
            check_case(case);
        }
    }

    #[test]
    fn print_cases_truth_on_ink() {
        let cases = print_cases();
        assert!(cases.len() >= 8);
        for case in &cases {
            assert_eq!(case.group, "prints");
            check_case(case);
        }
    }

    #[test]
    fn crowded_cases_truth_on_ink() {
        for group in CROWDED_GROUPS {
            let cases = group_cases(group).expect("known group");
            assert!(cases.len() >= 15, "{group}: {}", cases.len());
            for case in &cases {
                assert_eq!(case.group, group);
                check_case(case);
            }
        }
        assert!(group_cases("nonsense").is_none());
    }

    #[test]
    fn cells_are_their_size() {
        // Half a width of background between neighbouring strokes' ink: 2 px at 4 px strokes.
        let case = group_cases("cells")
            .expect("cells")
            .into_iter()
            .find(|c| c.name == "box1x2_c0.5_w4")
            .expect("the case");
        let b = &case.binary;
        let column = b.width as i64 / 2;
        let runs: Vec<(bool, usize)> = (0..b.height as i64).fold(Vec::new(), |mut runs, y| {
            let ink = b.get(column, y);
            match runs.last_mut() {
                Some((v, n)) if *v == ink => *n += 1,
                _ => runs.push((ink, 1)),
            }
            runs
        });
        // Background, frame, cell, bar, cell, frame, background.
        let inner: Vec<usize> = runs[1..runs.len() - 1].iter().map(|r| r.1).collect();
        assert_eq!(inner, vec![4, 2, 4, 2, 4], "{runs:?}");
    }

    #[test]
    fn touching_dots_touch() {
        for case in group_cases("arms")
            .expect("arms")
            .iter()
            .filter(|c| c.name.starts_with("dot"))
        {
            let (bar, dot) = (&case.strokes[0], &case.strokes[1]);
            let (w, h) = (case.binary.width, case.binary.height);
            let bar_ink = render(std::slice::from_ref(bar), w, h);
            let dot_ink = render(std::slice::from_ref(dot), w, h);
            let touches = (0..h as i64).any(|y| {
                (0..w as i64).any(|x| {
                    dot_ink.get(x, y)
                        && [(1, 0), (-1, 0), (0, 1), (0, -1), (0, 0)]
                            .iter()
                            .any(|&(dx, dy)| bar_ink.get(x + dx, y + dy))
                })
            });
            assert!(touches, "{}", case.name);
        }
    }

    #[test]
    fn names_unique() {
        let mut cases = all_cases();
        for group in CROWDED_GROUPS {
            cases.extend(group_cases(group).expect("known group"));
        }
        let mut names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
        names.sort_unstable();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n);
    }

    #[test]
    fn deterministic() {
        let (a, b) = (all_cases(), all_cases());
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.name, y.name);
            assert_eq!(x.binary, y.binary);
            assert_eq!(x.strokes, y.strokes);
        }
        let (p, q) = (page(600, 400, 3), page(600, 400, 3));
        assert_eq!(p.binary, q.binary);
        assert_eq!(p.strokes, q.strokes);
        assert_ne!(page(600, 400, 4).strokes, p.strokes);
    }

    #[test]
    fn margins_hold() {
        for case in hard_cases() {
            let w = case
                .strokes
                .iter()
                .map(Stroke::max_width)
                .fold(0.0, f64::max);
            let m = (2.0 * w) as i64;
            let b = &case.binary;
            for y in 0..b.height as i64 {
                for x in 0..b.width as i64 {
                    if b.get(x, y) {
                        let edge = x
                            .min(y)
                            .min(b.width as i64 - 1 - x)
                            .min(b.height as i64 - 1 - y);
                        assert!(
                            edge >= m - 1,
                            "{}: ink at {x},{y} inside the margin",
                            case.name
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn render_disk_and_capsule() {
        // A dot of width 5 on a pixel center: the 21 pixel centers within 2.5 px.
        let dot = render(&[Stroke::new(vec![[10.5, 10.5]], 5.0)], 21, 21);
        assert_eq!(dot.count(), 21);
        // A horizontal capsule of width 3 from x=5.5 to 15.5 on row 10: rows 9..=11, each reaching
        // one pixel past the end centers (the caps cover (4.5, 9.5), at sqrt(2) < 1.5).
        let bar = render(&[Stroke::new(vec![[5.5, 10.5], [15.5, 10.5]], 3.0)], 21, 21);
        assert_eq!(bar.count(), 13 * 3);
        assert!(bar.get(4, 10) && !bar.get(3, 10) && bar.get(4, 9) && !bar.get(4, 8));
    }

    #[test]
    fn dropout_fraction() {
        let mut b = Binary::new(100, 100);
        b.ink.iter_mut().for_each(|i| *i = true);
        dropout(&mut b, [0, 0, 100, 50], 0.3, 1);
        let removed = 10_000 - b.count();
        assert!((1300..1700).contains(&removed), "{removed}");
        assert!(b.ink[50 * 100..].iter().all(|&i| i));
    }

    #[test]
    fn page_fills_and_renders() {
        let case = page(800, 600, 1);
        assert_eq!((case.binary.width, case.binary.height), (800, 600));
        assert!(case.strokes.len() > 50);
        check_case(&case);
    }
}
