//! Text from the Hershey single-stroke font (Roman simplex, `futural`, ASCII 32-126), vendored in
//! `data/hershey/` (public-domain glyphs; see `data/hershey/ORIGIN.md`). Glyphs are polylines
//! already, so the truth of a line of text is its glyphs' polylines, scaled.

use super::{frame, render, Case, SplitMix64, Stroke};
use std::sync::OnceLock;

/// The vendored font file, in the classic `.jhf` format.
const FUTURAL: &str = include_str!("../../data/hershey/futural.jhf");

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
    /// Pen-down polylines.
    pub strokes: Vec<Vec<[i32; 2]>>,
}

/// A Hershey font: the glyphs of ASCII 32 (space) to 126 (`~`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Font {
    glyphs: Vec<Glyph>,
}

impl Font {
    /// Parses `.jhf` text: each glyph is a 5-column number, a 3-column count of coordinate pairs
    /// (the bearings count as one), then the pairs as letters relative to `R`, with ` R` lifting
    /// the pen. Long glyphs wrap onto the next line. Returns `None` on malformed text or when a
    /// glyph of ASCII 32-126 is missing; glyph numbers are taken to be the ASCII codes.
    pub fn parse(text: &str) -> Option<Font> {
        let bytes = text.as_bytes();
        let mut glyphs = vec![None; 95];
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
            let mut current: Vec<[i32; 2]> = Vec::new();
            for &(x, y) in rest {
                if x == b' ' && y == b'R' {
                    if current.len() > 1 {
                        glyph.strokes.push(std::mem::take(&mut current));
                    }
                    current.clear();
                } else {
                    current.push([x as i32 - ORIGIN, y as i32 - ORIGIN]);
                }
            }
            if current.len() > 1 {
                glyph.strokes.push(current);
            }
            if (32..=126).contains(&number) {
                glyphs[number - 32] = Some(glyph);
            }
        }
        let glyphs = glyphs.into_iter().collect::<Option<Vec<Glyph>>>()?;
        Some(Font { glyphs })
    }

    /// The vendored Roman simplex font, parsed once.
    pub fn futural() -> &'static Font {
        static FONT: OnceLock<Font> = OnceLock::new();
        // The file is part of the source tree and checked by a test; an empty font would only
        // give empty text, never a panic.
        FONT.get_or_init(|| Font::parse(FUTURAL).unwrap_or_default())
    }

    /// The glyph of `c`; characters outside ASCII 32-126 fall back to `?`.
    pub fn glyph(&self, c: char) -> Option<&Glyph> {
        let code = c as u32;
        let index = if (32..=126).contains(&code) {
            code - 32
        } else {
            b'?' as u32 - 32
        };
        self.glyphs.get(index as usize)
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
                            pen + (p[0] - glyph.left) as f64 * scale,
                            baseline + (p[1] as f64 - BASELINE) * scale,
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
        assert_eq!(a.strokes[0], vec![[0, -12], [-8, 9]]);
        assert_eq!(a.strokes[1], vec![[0, -12], [8, 9]]);
        assert_eq!(a.strokes[2], vec![[-5, 2], [5, 2]]);
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
