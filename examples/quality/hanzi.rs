//! The `hanzi` group: Chinese characters drawn by a real font, read from `../shared/data/hanzi`
//! (its README: pen strokes as filled SVG outlines in a 1024 box with y up, and approximate stroke
//! medians). Never copied into the repository; the group is skipped when the data is absent.
//!
//! Each character is rendered with resvg at [`SIZE`] px per 1024 units (the outlines filled, a
//! pixel ink when it is at least half covered). The truth is the medians, which run straight
//! through crossings, made to match the ink the way rendered truths do (docs/quality.md):
//! - each point's width is twice the distance to the background of the pen stroke's *own*
//!   outline (rendered alone), at most 2 px away from the median, less one pixel (the width a
//!   rendered truth would need to cover the same pixels, docs/design.md adaptation 3's `w_loc`);
//! - each end is moved out along the median's last direction to the farthest pixel of its own
//!   outline minus half the width there, as a rendered truth's round cap ends (the medians stop a
//!   little short of the tips);
//! - the truth graph is built by the scorer as for every group, with the holes of the rendered
//!   ink ([`ScoreOptions::holes_from_binary`]), geometry is scored at 2.5, 5 and 7.5 px (8, 16
//!   and 24 units: the medians are only known to a few units), and junctions and ends match
//!   within 5 px at least (16 units) rather than 3.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::Context;
use resvg::{tiny_skia, usvg};
use ridgeline::geometry::segment_closest;
use ridgeline::{dist, Binary};
use ridgeline_testkit::score::ScoreOptions;
use ridgeline_testkit::synth::{Case, Stroke};
use serde::Deserialize;

use crate::thinning::distance_to_background;

/// Pixels per character (the 1024-unit box).
pub const SIZE: f64 = 330.0;

/// Background around the box, px.
const MARGIN: f64 = 12.0;

/// How the hanzi group is scored.
pub const OPTIONS: ScoreOptions = ScoreOptions {
    taus: [2.5, 5.0, 7.5],
    holes_from_binary: true,
    min_match_radius: 5.0,
    filled_loops_as_strokes: false,
    retraces_as_arms: false,
};

/// One character of `characters.json`.
#[derive(Deserialize)]
struct Character {
    strokes: Vec<String>,
    medians: Vec<Vec<[f64; 2]>>,
}

/// Where the data is looked for: `../shared/data/hanzi` beside the crate root.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/hanzi")
}

/// Every character of the data set as a case, in the file's key order (sorted by code point), or
/// `None` when the data is absent.
pub fn cases() -> anyhow::Result<Option<Vec<Case>>> {
    let path = data_dir().join("characters.json");
    if !path.exists() {
        return Ok(None);
    }
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let characters: BTreeMap<String, Character> =
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
    let mut cases = Vec::with_capacity(characters.len());
    for (name, character) in &characters {
        cases.push(case(name, character).with_context(|| format!("character {name}"))?);
    }
    Ok(Some(cases))
}

/// From the data's box (y up) to image coordinates.
fn to_image(p: [f64; 2]) -> [f64; 2] {
    let k = SIZE / 1024.0;
    [MARGIN + p[0] * k, MARGIN + (900.0 - p[1]) * k]
}

fn image_side() -> u32 {
    (SIZE + 2.0 * MARGIN).ceil() as u32
}

/// The pixel box `[x0, y0, x1, y1)` holding an outline: its path's numbers are coordinate pairs
/// (`M`, `L`, `Q`, `C` take only points), so their extremes bound it, control points included.
fn outline_box(path: &str) -> Option<[u32; 4]> {
    let numbers: Vec<f64> = path
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for pair in numbers.chunks_exact(2) {
        let p = to_image([pair[0], pair[1]]);
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let side = image_side() as f64;
    let clamp = |v: f64| v.clamp(0.0, side) as u32;
    (lo[0] <= hi[0]).then(|| {
        [
            clamp(lo[0].floor() - 2.0),
            clamp(lo[1].floor() - 2.0),
            clamp(hi[0].ceil() + 2.0),
            clamp(hi[1].ceil() + 2.0),
        ]
    })
}

/// The outlines filled and thresholded at half coverage, in the whole image.
fn rasterize(paths: &[&str]) -> anyhow::Result<Binary> {
    let side = image_side();
    rasterize_box(paths, [0, 0, side, side])
}

/// The outlines filled and thresholded at half coverage, in the pixel box `[x0, y0, x1, y1)` of
/// the image (a binary of the box's size).
fn rasterize_box(paths: &[&str], region: [u32; 4]) -> anyhow::Result<Binary> {
    let [x0, y0, x1, y1] = region;
    let (w, h) = ((x1 - x0).max(1), (y1 - y0).max(1));
    let k = SIZE / 1024.0;
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}"><g transform="matrix({k} 0 0 {neg} {dx} {dy})">"#,
        neg = -k,
        dx = MARGIN - x0 as f64,
        dy = MARGIN + 900.0 * k - y0 as f64,
    );
    for d in paths {
        svg.push_str(&format!(r#"<path fill="black" d="{d}"/>"#));
    }
    svg.push_str("</g></svg>");
    let tree = usvg::Tree::from_str(&svg, &usvg::Options::default())?;
    let mut pixmap = tiny_skia::Pixmap::new(w, h).context("pixmap")?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    let mut binary = Binary::new(w, h);
    for (ink, pixel) in binary.ink.iter_mut().zip(pixmap.data().chunks_exact(4)) {
        *ink = pixel[3] >= 128;
    }
    Ok(binary)
}

fn case(name: &str, character: &Character) -> anyhow::Result<Case> {
    let paths: Vec<&str> = character.strokes.iter().map(String::as_str).collect();
    let binary = rasterize(&paths)?;
    let mut strokes = Vec::new();
    let mut outlines = Vec::new();
    for (outline, median) in character.strokes.iter().zip(&character.medians) {
        // The stroke's own outline, in its own box of the image (the rest is background).
        let region = outline_box(outline).unwrap_or([0, 0, image_side(), image_side()]);
        let own = rasterize_box(&[outline], region)?;
        let half_width = distance_to_background(&own);
        let offset = [region[0] as f64, region[1] as f64];
        strokes.push(truth_stroke(median, &own, &half_width, offset));
        outlines.push(Outline { region, own });
    }
    join_touching_ends(&mut strokes, &outlines);
    let code = name.chars().next().map_or(0, |c| c as u32);
    Ok(Case {
        name: format!("hanzi_{name}_u{code:04X}"),
        group: "hanzi".into(),
        binary,
        strokes,
    })
}

/// One pen stroke's own outline, rasterized in its box of the image.
struct Outline {
    region: [u32; 4],
    own: Binary,
}

impl Outline {
    /// Whether image pixel `(x, y)` is ink of this outline.
    fn ink(&self, x: i64, y: i64) -> bool {
        self.own
            .get(x - self.region[0] as i64, y - self.region[1] as i64)
    }
}

/// Where a pen stroke's own outline, within `max(2 w, 10)` px of one of its median's ends,
/// shares or touches (8-neighbour) pixels of another stroke's outline, the ink shows the stroke
/// running into that one, whether or not the medians' rendered widths would touch there (brush
/// tips are thin, and the medians start and stop inside the outline): the end is continued
/// straight to the nearest point of the other median (a T, or a corner where two ends meet), as
/// long as that lies ahead of the end or beside it, not back over a crossing the stroke has
/// passed.
fn join_touching_ends(strokes: &mut [Stroke], outlines: &[Outline]) {
    let n = strokes.len();
    let mut extensions: Vec<(usize, bool, [f64; 2])> = Vec::new();
    for i in 0..n {
        let points = &strokes[i].points;
        if points.len() < 2 {
            continue;
        }
        for at_start in [true, false] {
            let (k, inner) = if at_start {
                (0, 1)
            } else {
                (points.len() - 1, points.len() - 2)
            };
            let (e, w) = (points[k], strokes[i].widths[k]);
            let outward = unit([e[0] - points[inner][0], e[1] - points[inner][1]]);
            let reach = (2.0 * w).max(10.0);
            let mut best: Option<(f64, [f64; 2])> = None;
            for j in (0..n).filter(|&j| j != i && strokes[j].points.len() >= 2) {
                if !outlines_touch(&outlines[i], &outlines[j], e, reach) {
                    continue;
                }
                let Some((d, q, w_q)) = nearest_on(&strokes[j], e) else {
                    continue;
                };
                let ahead = (q[0] - e[0]) * outward[0] + (q[1] - e[1]) * outward[1];
                if ahead < -0.3 * d || d > reach + w_q / 2.0 + 2.0 {
                    continue;
                }
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, q));
                }
            }
            if let Some((_, q)) = best {
                extensions.push((i, at_start, q));
            }
        }
    }
    for (i, at_start, q) in extensions {
        let stroke = &mut strokes[i];
        if at_start {
            let w = stroke.widths[0];
            stroke.points.insert(0, q);
            stroke.widths.insert(0, w);
        } else {
            let w = stroke.widths[stroke.widths.len() - 1];
            stroke.points.push(q);
            stroke.widths.push(w);
        }
    }
}

/// Whether outline `a`'s pixels within `reach` of `p` share or touch (8-neighbour) pixels of
/// outline `b`.
fn outlines_touch(a: &Outline, b: &Outline, p: [f64; 2], reach: f64) -> bool {
    let (x0, y0) = ((p[0] - reach).floor() as i64, (p[1] - reach).floor() as i64);
    let (x1, y1) = ((p[0] + reach).ceil() as i64, (p[1] + reach).ceil() as i64);
    (y0..=y1).any(|y| {
        (x0..=x1).any(|x| {
            (x as f64 + 0.5 - p[0]).hypot(y as f64 + 0.5 - p[1]) <= reach
                && a.ink(x, y)
                && (-1..=1).any(|dy| (-1..=1).any(|dx| b.ink(x + dx, y + dy)))
        })
    })
}

/// The point of a stroke's polyline nearest to `p`: distance, point, and the width there.
fn nearest_on(stroke: &Stroke, p: [f64; 2]) -> Option<(f64, [f64; 2], f64)> {
    let mut best: Option<(f64, [f64; 2], f64)> = None;
    for k in 0..stroke.points.len().saturating_sub(1) {
        let (a, b) = (stroke.points[k], stroke.points[k + 1]);
        let (dq, t) = segment_closest(p, a, b);
        if best.is_none_or(|(b, _, _)| dq < b) {
            let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let w = stroke.widths[k] + t * (stroke.widths[k + 1] - stroke.widths[k]);
            best = Some((dq, q, w));
        }
    }
    best
}

fn unit(d: [f64; 2]) -> [f64; 2] {
    let n = d[0].hypot(d[1]);
    if n > 0.0 {
        [d[0] / n, d[1] / n]
    } else {
        [1.0, 0.0]
    }
}

/// One pen stroke's truth from its median and its own outline's pixels (`own`, whose pixel
/// `(0, 0)` is the image's pixel `offset`).
fn truth_stroke(median: &[[f64; 2]], own: &Binary, half_width: &[f64], offset: [f64; 2]) -> Stroke {
    let (w, h) = (own.width as i64, own.height as i64);
    let (ox, oy) = (offset[0] as i64, offset[1] as i64);
    let dt = |x: i64, y: i64| {
        let (x, y) = (x - ox, y - oy);
        if x < 0 || y < 0 || x >= w || y >= h {
            0.0
        } else {
            half_width[(y * w + x) as usize]
        }
    };
    let own_ink = |x: i64, y: i64| own.get(x - ox, y - oy);
    // Twice the largest distance to the background within 2 px, less the pixel itself.
    let width_at = |p: [f64; 2]| {
        let (cx, cy) = (p[0].floor() as i64, p[1].floor() as i64);
        let mut best: f64 = 0.0;
        for y in cy - 2..=cy + 2 {
            for x in cx - 2..=cx + 2 {
                if (x as f64 + 0.5 - p[0]).hypot(y as f64 + 0.5 - p[1]) <= 2.0 {
                    best = best.max(dt(x, y));
                }
            }
        }
        (2.0 * best - 1.0).max(2.0)
    };
    let mut points: Vec<[f64; 2]> = Vec::new();
    for &p in median {
        let q = to_image(p);
        if points.last().is_none_or(|&last| dist(last, q) > 1e-6) {
            points.push(q);
        }
    }
    if points.len() >= 2 {
        let start = extend_end(&points, true, &own_ink, &width_at);
        let end = extend_end(&points, false, &own_ink, &width_at);
        if let Some(p) = start {
            points.insert(0, p);
        }
        if let Some(p) = end {
            points.push(p);
        }
    }
    let widths = points.iter().map(|&p| width_at(p)).collect();
    Stroke { points, widths }
}

/// The first (`at_start`) or last point of `points` moved out to the farthest own-outline pixel
/// along the median's direction there, less half the width halfway out; `None` when that is not
/// beyond the end. The direction is taken from the point `max(2 w, 8)` px back along the median,
/// so a brush's short entry hook (the median starting at the tip's corner) does not turn it.
fn extend_end(
    points: &[[f64; 2]],
    at_start: bool,
    own_ink: &dyn Fn(i64, i64) -> bool,
    width_at: &dyn Fn([f64; 2]) -> f64,
) -> Option<[f64; 2]> {
    let ordered: Vec<[f64; 2]> = if at_start {
        points.to_vec()
    } else {
        points.iter().rev().copied().collect()
    };
    let p = ordered[0];
    let back = (2.0 * width_at(p)).max(8.0);
    let mut q = ordered[ordered.len() - 1];
    let mut arc = 0.0;
    for w in ordered.windows(2) {
        arc += dist(w[0], w[1]);
        if arc >= back {
            q = w[1];
            break;
        }
    }
    let len = dist(p, q);
    if len <= 0.0 {
        return None;
    }
    let u = [(p[0] - q[0]) / len, (p[1] - q[1]) / len];
    let on = |t: f64| {
        own_ink(
            (p[0] + t * u[0]).floor() as i64,
            (p[1] + t * u[1]).floor() as i64,
        )
    };
    if !on(0.0) {
        return None;
    }
    let mut t = 0.0;
    while t < SIZE / 4.0 && on(t + 0.5) {
        t += 0.5;
    }
    // Half the width halfway out: the tip itself is only a pixel or two wide.
    let half = width_at([p[0] + 0.5 * t * u[0], p[1] + 0.5 * t * u[1]]) / 2.0;
    (t - half > 0.5).then(|| [p[0] + (t - half) * u[0], p[1] + (t - half) * u[1]])
}
