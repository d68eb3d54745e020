//! Text from the Hershey fonts vendored in `data/hershey/` (public-domain glyphs; see
//! `data/hershey/ORIGIN.md`): the single-stroke Roman simplex (`futural`) of the `text` group, and
//! the script, cursive, Gothic, Times and Japanese fonts of the groups of [`font_cases`] and
//! [`japanese_cases`]. Glyphs are polylines already, so the truth of a line of text is its glyphs'
//! polylines, scaled.

use super::{frame, render, Case, SplitMix64, Stroke};
use std::sync::OnceLock;

/// The vendored font files, in the classic `.jhf` format.
const FUTURAL: &str = include_str!("../../data/hershey/futural.jhf");
const SCRIPTC: &str = include_str!("../../data/hershey/scriptc.jhf");
const CURSIVE: &str = include_str!("../../data/hershey/cursive.jhf");
const GOTHICENG: &str = include_str!("../../data/hershey/gothiceng.jhf");
const TIMESR: &str = include_str!("../../data/hershey/timesr.jhf");
const JAPANESE: &str = include_str!("../../data/hershey/japanese.jhf");

/// The fonts of [`font_cases`]: Hershey script complex, cursive, Gothic English and Times Roman.
pub const FONTS: [&str; 4] = ["scriptc", "cursive", "gothiceng", "timesr"];

/// Hershey coordinates are relative to the letter `R`.
const ORIGIN: i32 = b'R' as i32;

/// Hershey y of the baseline (letters stand on `[`).
const BASELINE: f64 = 9.0;

/// Hershey cap height: from `F` (-12) to the baseline.
pub(crate) const CAP_HEIGHT: f64 = 21.0;

/// Hershey x-height: from `M` (-5) to the baseline.
const X_HEIGHT: f64 = 14.0;

/// One glyph: its side bearings and pen-down polylines, in Hershey units (y down).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Glyph {
    /// Left bearing (negative): the glyph's left edge relative to its origin.
    pub left: i32,
    /// Right bearing: the right edge; the advance is `right - left`.
    pub right: i32,
    /// Pen-down polylines (whole units as parsed; [`Glyph::single_pass`] cuts them anywhere).
    pub strokes: Vec<Vec<[f64; 2]>>,
}

/// Hershey units: a pen pass lying everywhere within this distance of a glyph's other passes only
/// thickens a stroke (see [`Glyph::single_pass`]).
pub const SINGLE_PASS_TOLERANCE: f64 = 1.5;

impl Glyph {
    /// The glyph without the pen passes that only thicken a stroke: the complex and Gothic fonts
    /// draw a thick stroke as two or three passes one unit apart and hook small serif ticks onto
    /// stroke ends, which on a plotter gives thick and thin strokes. Passes are taken longest
    /// first; of each, the parts farther than `tolerance` units from every part kept so far are
    /// kept, each joined by a straight piece to the nearest kept point where it was cut (so it
    /// still meets what it left), and the rest is dropped, as are parts shorter than one unit.
    /// Of two passes side by side the longer stays, and a serif that sticks out stays as the
    /// part that sticks out. The rendered width then does the thickening, and the truth keeps
    /// one centerline per stroke.
    pub fn single_pass(&self, tolerance: f64) -> Glyph {
        let length =
            |s: &[[f64; 2]]| -> f64 { s.windows(2).map(|w| ridgeline::dist(w[0], w[1])).sum() };
        let mut order: Vec<usize> = (0..self.strokes.len()).collect();
        order.sort_by(|&a, &b| {
            length(&self.strokes[b])
                .total_cmp(&length(&self.strokes[a]))
                .then(a.cmp(&b))
        });
        let mut kept: Vec<Vec<[f64; 2]>> = Vec::new();
        for &i in &order {
            // The pass every half unit (its own vertices included), each sample marked by
            // whether it is near what is kept.
            let pass = &self.strokes[i];
            let mut samples: Vec<[f64; 2]> = Vec::new();
            for w in pass.windows(2) {
                let n = (ridgeline::dist(w[0], w[1]) / 0.5).ceil().max(1.0) as usize;
                for k in 0..n {
                    let t = k as f64 / n as f64;
                    samples.push([
                        w[0][0] + t * (w[1][0] - w[0][0]),
                        w[0][1] + t * (w[1][1] - w[0][1]),
                    ]);
                }
            }
            if let Some(&last) = pass.last() {
                samples.push(last);
            }
            let near: Vec<bool> = samples
                .iter()
                .map(|&p| {
                    kept.iter().any(|s| {
                        s.windows(2)
                            .any(|w| ridgeline::geometry::segment_dist(p, w[0], w[1]) <= tolerance)
                    })
                })
                .collect();
            let mut k = 0;
            while k < samples.len() {
                if near[k] {
                    k += 1;
                    continue;
                }
                let mut end = k;
                while end + 1 < samples.len() && !near[end + 1] {
                    end += 1;
                }
                // Only the vertices of the pass and the two ends: the samples between them lie
                // on its segments.
                let mut part: Vec<[f64; 2]> = vec![samples[k]];
                for &q in samples.iter().take(end).skip(k + 1) {
                    if pass.contains(&q) {
                        part.push(q);
                    }
                }
                part.push(samples[end]);
                part.dedup();
                if length(&part) >= 1.0 {
                    // Where the pass was cut, it is joined straight to the nearest point kept,
                    // as its ink runs on into the ink kept there.
                    if k > 0 {
                        part.insert(0, nearest_on(&kept, samples[k - 1]));
                    }
                    if end + 1 < samples.len() {
                        part.push(nearest_on(&kept, samples[end + 1]));
                    }
                    part.dedup();
                    kept.push(part);
                }
                k = end + 1;
            }
        }
        Glyph {
            left: self.left,
            right: self.right,
            strokes: kept,
        }
    }
}

/// The point of the polylines nearest to `p` (`p` itself when there is none).
fn nearest_on(polylines: &[Vec<[f64; 2]>], p: [f64; 2]) -> [f64; 2] {
    let mut best = (f64::INFINITY, p);
    for s in polylines {
        for w in s.windows(2) {
            let (d, t) = ridgeline::geometry::segment_closest(p, w[0], w[1]);
            if d < best.0 {
                best = (
                    d,
                    [
                        w[0][0] + t * (w[1][0] - w[0][0]),
                        w[0][1] + t * (w[1][1] - w[0][1]),
                    ],
                );
            }
        }
    }
    best.1
}

/// A Hershey font: its glyphs in file order, and which of them draw ASCII 32 (space) to 126 (`~`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Font {
    glyphs: Vec<Glyph>,
    /// For ASCII 32-126, the index in `glyphs` of the first glyph numbered with that code.
    ascii: Vec<Option<usize>>,
}

impl Font {
    /// Parses `.jhf` text: each glyph is a 5-column number, a 3-column count of coordinate pairs
    /// (the bearings count as one), then the pairs as letters relative to `R`, with ` R` lifting
    /// the pen. Long glyphs wrap onto the next line. Glyph numbers 32-126 are taken to be ASCII
    /// codes (the Latin fonts are numbered so; the Japanese one numbers every glyph 12345 and is
    /// used through [`Font::glyphs`]). Returns `None` on malformed text or when there is no glyph.
    pub fn parse(text: &str) -> Option<Font> {
        let bytes = text.as_bytes();
        let mut glyphs = Vec::new();
        let mut ascii = vec![None; 95];
        let mut i = 0;
        loop {
            while i < bytes.len() && (bytes[i] == b'\n' || bytes[i] == b'\r') {
                i += 1;
            }
            if i >= bytes.len() {
                break;
            }
            let number: usize = std::str::from_utf8(bytes.get(i..i + 5)?)
                .ok()?
                .trim()
                .parse()
                .ok()?;
            let count: usize = std::str::from_utf8(bytes.get(i + 5..i + 8)?)
                .ok()?
                .trim()
                .parse()
                .ok()?;
            i += 8;
            // The coordinate pairs, skipping the line breaks of wrapped glyphs.
            let mut pairs = Vec::with_capacity(count);
            let mut pending = None;
            while pairs.len() < count {
                let &b = bytes.get(i)?;
                i += 1;
                if b == b'\n' || b == b'\r' {
                    continue;
                }
                match pending.take() {
                    None => pending = Some(b),
                    Some(first) => pairs.push((first, b)),
                }
            }
            let (&(l, r), rest) = pairs.split_first()?;
            let mut glyph = Glyph {
                left: l as i32 - ORIGIN,
                right: r as i32 - ORIGIN,
                strokes: vec![],
            };
            let mut current: Vec<[f64; 2]> = Vec::new();
            for &(x, y) in rest {
                if x == b' ' && y == b'R' {
                    if current.len() > 1 {
                        glyph.strokes.push(std::mem::take(&mut current));
                    }
                    current.clear();
                } else {
                    current.push([(x as i32 - ORIGIN) as f64, (y as i32 - ORIGIN) as f64]);
                }
            }
            if current.len() > 1 {
                glyph.strokes.push(current);
            }
            if (32..=126).contains(&number) && ascii[number - 32].is_none() {
                ascii[number - 32] = Some(glyphs.len());
            }
            glyphs.push(glyph);
        }
        (!glyphs.is_empty()).then_some(Font { glyphs, ascii })
    }

    /// The vendored Roman simplex font, parsed once.
    pub fn futural() -> &'static Font {
        static FONT: OnceLock<Font> = OnceLock::new();
        // The file is part of the source tree and checked by a test; an empty font would only
        // give empty text, never a panic.
        FONT.get_or_init(|| Font::parse(FUTURAL).unwrap_or_default())
    }

    /// A vendored font by file name (`futural`, `scriptc`, `cursive`, `gothiceng`, `timesr`,
    /// `japanese`), parsed once, as drawn.
    pub fn named(name: &str) -> Option<&'static Font> {
        static FONTS: OnceLock<Vec<(&'static str, Font)>> = OnceLock::new();
        if name == "futural" {
            return Some(Font::futural());
        }
        let fonts = FONTS.get_or_init(|| {
            [
                ("scriptc", SCRIPTC),
                ("cursive", CURSIVE),
                ("gothiceng", GOTHICENG),
                ("timesr", TIMESR),
                ("japanese", JAPANESE),
            ]
            .into_iter()
            .map(|(name, text)| (name, Font::parse(text).unwrap_or_default()))
            .collect()
        });
        fonts.iter().find(|(n, _)| *n == name).map(|(_, f)| f)
    }

    /// The font with every glyph reduced to its single passes ([`Glyph::single_pass`]).
    pub fn single_pass(&self, tolerance: f64) -> Font {
        Font {
            glyphs: self
                .glyphs
                .iter()
                .map(|g| g.single_pass(tolerance))
                .collect(),
            ascii: self.ascii.clone(),
        }
    }

    /// The font as [`font_cases`] and [`japanese_cases`] draw it at `scale` px per unit with
    /// strokes `width` px wide: the parts of passes within [`SINGLE_PASS_TOLERANCE`] units of the
    /// passes kept, or within the width plus 2 px (closer than that, two passes' inks merge with
    /// at most a pixel of background between them, and the ink shows one stroke), go.
    pub fn drawn_at(&self, scale: f64, width: f64) -> Font {
        self.single_pass(SINGLE_PASS_TOLERANCE.max((width + 2.0) / scale))
    }

    /// Every glyph, in file order.
    pub fn glyphs(&self) -> &[Glyph] {
        &self.glyphs
    }

    /// The glyph of `c`; characters outside ASCII 32-126 or missing from the font fall back to
    /// `?`.
    pub fn glyph(&self, c: char) -> Option<&Glyph> {
        let code = c as u32;
        let slot = |code: u32| {
            self.ascii
                .get(code.wrapping_sub(32) as usize)
                .copied()
                .flatten()
        };
        slot(code)
            .or_else(|| slot(b'?' as u32))
            .and_then(|i| self.glyphs.get(i))
    }

    /// Width of `text` in Hershey units.
    pub fn advance(&self, text: &str) -> f64 {
        text.chars()
            .filter_map(|c| self.glyph(c))
            .map(|g| (g.right - g.left) as f64)
            .sum()
    }

    /// Lays out one line of text with its left edge at `x` and its baseline at `baseline`, `scale`
    /// px per Hershey unit, strokes `width` px wide. Returns the strokes and the pen position
    /// after the last glyph.
    pub fn line(
        &self,
        text: &str,
        x: f64,
        baseline: f64,
        scale: f64,
        width: f64,
    ) -> (Vec<Stroke>, f64) {
        let mut pen = x;
        let mut strokes = Vec::new();
        for c in text.chars() {
            let Some(glyph) = self.glyph(c) else { continue };
            for polyline in &glyph.strokes {
                let points = polyline
                    .iter()
                    .map(|p| {
                        [
                            pen + (p[0] - glyph.left as f64) * scale,
                            baseline + (p[1] - BASELINE) * scale,
                        ]
                    })
                    .collect();
                strokes.push(Stroke::new(points, width));
            }
            pen += (glyph.right - glyph.left) as f64 * scale;
        }
        (strokes, pen)
    }
}

/// One line of text as a case (group `text`): `cap_height` px capitals, strokes `width` px wide,
/// framed with a margin of two widths.
pub fn text_line(name: &str, text: &str, cap_height: f64, width: f64) -> Case {
    let (strokes, _) = Font::futural().line(text, 0.0, 0.0, cap_height / CAP_HEIGHT, width);
    frame(name, "text", strokes, 2.0 * width + 1.0)
}

/// The text lines of [`text_cases`]: pangram fragments, digits and punctuation with crossings.
const LINES: [&str; 8] = [
    "the quick brown",
    "fox jumps over",
    "THE LAZY DOG",
    "0123456789",
    "Pack my box with",
    "five dozen jugs",
    "Sphinx of quartz",
    "Waltz, 47 & #9?",
];

/// Every text case (group `text`): each of 8 lines at cap heights 24, 36 and 56 px, with stroke
/// widths 3, 5 or 7 px chosen so the width never exceeds a fifth of the cap height (24 cases).
pub fn text_cases() -> Vec<Case> {
    let widths = [3.0, 5.0, 7.0];
    let mut cases = Vec::new();
    for (i, text) in LINES.iter().enumerate() {
        for (height, width) in [
            (24.0, 3.0),
            (36.0, widths[i % 3]),
            (56.0, widths[(i + 1) % 3]),
        ] {
            cases.push(text_line(
                &format!("text{i}_h{height}_w{width}"),
                text,
                height,
                width,
            ));
        }
    }
    cases
}

/// Every case of one of the [`FONTS`] (group named after the font): the lines of [`text_cases`]
/// at the same cap heights and stroke widths (3-7 px), in that font with the pen passes that only
/// thicken a stroke removed ([`Font::drawn_at`]). Empty for a name that is not one of the
/// [`FONTS`].
pub fn font_cases(name: &str) -> Vec<Case> {
    let Some(font) = Font::named(name).filter(|_| FONTS.contains(&name)) else {
        return Vec::new();
    };
    // One reduced font per (scale, width) pair.
    let mut drawn: Vec<(f64, f64, Font)> = Vec::new();
    let widths = [3.0, 5.0, 7.0];
    let mut cases = Vec::new();
    for (i, text) in LINES.iter().enumerate() {
        for (height, width) in [
            (24.0, 3.0),
            (36.0, widths[i % 3]),
            (56.0, widths[(i + 1) % 3]),
        ] {
            let scale = height / CAP_HEIGHT;
            let index = match drawn.iter().position(|d| d.0 == scale && d.1 == width) {
                Some(k) => k,
                None => {
                    drawn.push((scale, width, font.drawn_at(scale, width)));
                    drawn.len() - 1
                }
            };
            let (strokes, _) = drawn[index].2.line(text, 0.0, 0.0, scale, width);
            cases.push(frame(
                &format!("{name}{i}_h{height}_w{width}"),
                name,
                strokes,
                2.0 * width + 1.0,
            ));
        }
    }
    cases
}

/// Pixels per Hershey unit of the Japanese glyphs: their em is about 27 units, so a glyph is
/// about 100 px across and its strokes, often 3-4 units apart, 12-16 px.
const JAPANESE_SCALE: f64 = 4.0;

/// Every Japanese glyph of the Hershey font as a case (group `japanese`): kana and kanji drawn
/// with the pen passes that only thicken a stroke removed ([`Font::drawn_at`]),
/// `JAPANESE_SCALE` px per unit, stroke
/// widths 3, 4, 5, 6, 7 px in turn. Glyphs that repeat an earlier one (the file's placeholder
/// dots) or span less than 8 units (punctuation) are left out. Named `ja<index in the file>_w<w>`.
pub fn japanese_cases() -> Vec<Case> {
    let Some(font) = Font::named("japanese") else {
        return Vec::new();
    };
    let widths = [3.0, 4.0, 5.0, 6.0, 7.0];
    let drawn: Vec<Font> = widths
        .iter()
        .map(|&w| font.drawn_at(JAPANESE_SCALE, w))
        .collect();
    let mut seen: Vec<&Vec<Vec<[f64; 2]>>> = Vec::new();
    let mut cases = Vec::new();
    for (index, glyph) in font.glyphs().iter().enumerate() {
        let points = glyph.strokes.iter().flatten();
        let span = |k: usize| {
            let lo = points.clone().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = points
                .clone()
                .map(|p| p[k])
                .fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        };
        if glyph.strokes.is_empty() || span(0).max(span(1)) < 8.0 || seen.contains(&&glyph.strokes)
        {
            continue;
        }
        seen.push(&glyph.strokes);
        let k = cases.len() % widths.len();
        let width = widths[k];
        let strokes = drawn[k].glyphs[index]
            .strokes
            .iter()
            .map(|s| {
                let points = s
                    .iter()
                    .map(|p| [p[0] * JAPANESE_SCALE, p[1] * JAPANESE_SCALE])
                    .collect();
                Stroke::new(points, width)
            })
            .collect();
        cases.push(frame(
            &format!("ja{index:03}_w{width}"),
            "japanese",
            strokes,
            2.0 * width + 1.0,
        ));
    }
    cases
}

/// Words the page is written with (letters and digits only, so no glyph reaches into the
/// neighbouring lines).
const WORDS: [&str; 24] = [
    "the", "quick", "brown", "fox", "jumps", "over", "lazy", "dog", "pack", "my", "box", "with",
    "five", "dozen", "liquor", "jugs", "Sphinx", "of", "black", "quartz", "judge", "vow", "1984",
    "2025",
];

/// A dense page of text (group `page`) for the page benchmark: lines of words picked by a
/// [`SplitMix64`] seeded with `seed`, 40 px x-height, 4 px strokes, filling a `width` x `height`
/// image (an A4 page at 300 dpi is 2480 x 3508). Renders in well under a second in release.
pub fn page(width: u32, height: u32, seed: u64) -> Case {
    let font = Font::futural();
    let scale = 40.0 / X_HEIGHT;
    let stroke_width = 4.0;
    // Lines 34 units apart leave 6 units between the deepest descender (16) and the tallest
    // ascender (-12) of the next line.
    let pitch = 34.0 * scale;
    let margin = 40.0;
    let mut rng = SplitMix64::new(seed);
    let mut strokes = Vec::new();
    let mut baseline = margin + 12.0 * scale + stroke_width;
    let right = width as f64 - margin;
    while baseline + 16.0 * scale + stroke_width + margin <= height as f64 {
        let mut text = String::new();
        loop {
            let word = WORDS[rng.below(WORDS.len())];
            let candidate = if text.is_empty() {
                word.to_string()
            } else {
                format!("{text} {word}")
            };
            if margin + font.advance(&candidate) * scale > right {
                break;
            }
            text = candidate;
        }
        if text.is_empty() {
            break;
        }
        let (line, _) = font.line(&text, margin, baseline, scale, stroke_width);
        strokes.extend(line);
        baseline += pitch;
    }
    let binary = render(&strokes, width, height);
    Case {
        name: format!("page_{width}x{height}_s{seed}"),
        group: "page".into(),
        binary,
        strokes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_glyph() {
        let font = Font::parse(FUTURAL).expect("vendored font parses");
        assert_eq!(font.glyphs.len(), 95);
        assert_eq!(&font, Font::futural());
        // Space: bearings only.
        let space = font.glyph(' ').expect("space");
        assert!(space.strokes.is_empty());
        assert_eq!((space.left, space.right), (-8, 8));
    }

    #[test]
    fn letter_a_has_three_strokes() {
        let a = Font::futural().glyph('A').expect("A");
        assert_eq!(a.strokes.len(), 3);
        // Apex at (0, -12), feet on the baseline, the bar at y = 2.
        assert_eq!(a.strokes[0], vec![[0.0, -12.0], [-8.0, 9.0]]);
        assert_eq!(a.strokes[1], vec![[0.0, -12.0], [8.0, 9.0]]);
        assert_eq!(a.strokes[2], vec![[-5.0, 2.0], [5.0, 2.0]]);
        assert_eq!((a.left, a.right), (-9, 9));
    }

    #[test]
    fn wrapped_glyphs_parse() {
        // '&' and '@' wrap onto a second line in the file.
        let font = Font::futural();
        let amp = font.glyph('&').expect("&");
        assert_eq!(amp.strokes.len(), 1);
        assert_eq!(amp.strokes[0].len(), 34);
        assert_eq!(font.glyph('@').expect("@").strokes.len(), 4);
    }

    #[test]
    fn every_vendored_font_parses() {
        for name in ["futural", "scriptc", "cursive", "gothiceng", "timesr"] {
            let font = Font::named(name).expect(name);
            for c in (32u8..=126).map(char::from) {
                assert!(font.glyph(c).is_some(), "{name}: {c:?}");
            }
            assert!(!font.glyph('m').expect("m").strokes.is_empty(), "{name}");
        }
        // The script font has no '^': it falls back to '?'.
        let script = Font::named("scriptc").expect("scriptc");
        assert_eq!(script.glyph('^'), script.glyph('?'));
        // The Japanese glyphs are all numbered 12345 and used in file order.
        let japanese = Font::named("japanese").expect("japanese");
        assert_eq!(japanese.glyphs().len(), 193);
        assert_eq!(Font::named("nonsense"), None);
    }

    #[test]
    fn single_pass_drops_thickening_passes() {
        // Times Roman 'I' is two stems one unit apart, a serif bar at each end.
        let times = Font::named("timesr").expect("timesr");
        let i = times.glyph('I').expect("I");
        let stems = |g: &Glyph| {
            g.strokes
                .iter()
                .filter(|s| (s[0][0] - s[s.len() - 1][0]).abs() < 0.5)
                .count()
        };
        assert_eq!(stems(i), 2);
        let single = i.single_pass(SINGLE_PASS_TOLERANCE);
        assert_eq!(stems(&single), 1);
        // Each serif bar sticks out beyond the stem on both sides, so both stay: one stroke
        // each side of the stem, joined to it.
        assert!(single.strokes.len() >= 3, "{:?}", single.strokes);
        // Passes far apart stay, cut only where they come within the tolerance of one another
        // (the ends of H's bar, rejoined to the stems).
        let length = |g: &Glyph| -> f64 {
            g.strokes
                .iter()
                .flat_map(|s| s.windows(2).map(|w| ridgeline::dist(w[0], w[1])))
                .sum()
        };
        let h = Font::futural().glyph('H').expect("H");
        let single = h.single_pass(SINGLE_PASS_TOLERANCE);
        assert_eq!(single.strokes.len(), 3);
        assert!((length(&single) - length(h)).abs() < 1e-9, "{single:?}");
    }

    #[test]
    fn font_and_japanese_cases_are_drawn() {
        for name in FONTS {
            let cases = font_cases(name);
            assert_eq!(cases.len(), 24, "{name}");
            assert!(cases
                .iter()
                .all(|c| c.group == name && c.binary.count() > 0));
        }
        assert!(font_cases("futural").is_empty());
        let japanese = japanese_cases();
        assert!((150..=193).contains(&japanese.len()), "{}", japanese.len());
        let widths: Vec<f64> = japanese.iter().map(|c| c.strokes[0].widths[0]).collect();
        assert_eq!(&widths[..5], &[3.0, 4.0, 5.0, 6.0, 7.0]);
    }

    #[test]
    fn malformed_text_is_refused() {
        assert_eq!(Font::parse("   65  9I[RFJ"), None);
        assert_eq!(Font::parse("hello"), None);
        assert_eq!(Font::parse(""), None);
    }

    #[test]
    fn line_layout_scales_cap_height() {
        let (strokes, pen) = Font::futural().line("H", 10.0, 100.0, 2.0, 3.0);
        let ys: Vec<f64> = strokes
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p[1]))
            .collect();
        let top = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let bottom = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!((top, bottom), (100.0 - 42.0, 100.0));
        assert_eq!(pen, 10.0 + 22.0 * 2.0);
    }
}
