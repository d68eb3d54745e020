//! Writing a stroke graph as SVG and JSON (the last box of the pipeline diagram).
//!
//! Export depends on [`StrokeGraph`](crate::StrokeGraph) alone (and on the source image for the SVG
//! backdrop): it never runs a stage. Both writers are deterministic, so the same graph always gives
//! the same bytes, and both round coordinates (2 decimals in SVG, 3 in JSON) because the fit's
//! sub-pixel precision beyond that is noise that only makes files larger.
//!
//! What goes beyond the graph (strokes through crossings, minutiae, Bézier curves) is computed by
//! the caller and handed over as [`Features`].

pub mod iso19794;
pub mod json;
pub mod polylines;
pub mod svg;
pub mod xyt;

use std::fmt::Write;

use crate::curves::CubicBezier;
use crate::minutiae::Minutia;
use crate::strokes::Stroke;

/// Results computed from the graph beyond the graph itself (docs/design.md, "Beyond the paper"),
/// handed to the writers as plain data so that export never runs a computation of its own. Build it
/// from [`Features::default`] (nothing) and the `with_*` setters: more may be added.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Features<'a> {
    /// Strokes through crossings ([`crate::strokes::strokes`]). JSON: a `strokes` list. SVG: one
    /// line per stroke, each in its own color, instead of one per edge. Default value: `None`.
    pub strokes: Option<&'a [Stroke]>,
    /// Ridge endings and bifurcations ([`crate::minutiae::minutiae`]). JSON: a `minutiae` list.
    /// SVG: a mark at each, with a short line along its direction. Default value: `None`.
    pub minutiae: Option<&'a [Minutia]>,
    /// Cubic Béziers ([`crate::curves::fit_beziers`]). SVG: drawn as `<path>`s instead of
    /// polylines, one list per drawn line: per stroke when [`Features::strokes`] is given, else per
    /// edge; a line whose list is missing or empty is drawn as its polyline. JSON: a `curves`
    /// list, one entry per edge. Default value: `None`.
    pub curves: Option<&'a [Vec<CubicBezier>]>,
}

impl<'a> Features<'a> {
    /// Sets [`Features::strokes`].
    pub const fn with_strokes(mut self, strokes: Option<&'a [Stroke]>) -> Self {
        self.strokes = strokes;
        self
    }

    /// Sets [`Features::minutiae`].
    pub const fn with_minutiae(mut self, minutiae: Option<&'a [Minutia]>) -> Self {
        self.minutiae = minutiae;
        self
    }

    /// Sets [`Features::curves`].
    pub const fn with_curves(mut self, curves: Option<&'a [Vec<CubicBezier>]>) -> Self {
        self.curves = curves;
        self
    }
}

/// Appends `value` with at most `decimals` decimals, trailing zeros trimmed (`12.50` → `12.5`,
/// `3.00` → `3`) and negative zero written as `0`. Non-finite values are written as `0` so that
/// the document stays well-formed whatever the graph holds.
pub(crate) fn push_number(out: &mut String, value: f64, decimals: usize) {
    if !value.is_finite() {
        out.push('0');
        return;
    }
    // A page writes hundreds of thousands of numbers: scaled integers are several times faster
    // than the formatter. Where the scaled value is within rounding error of a tie (or too large
    // for an exact integer), only the formatter's exact decimal rounding gives the same digits.
    const SCALES: [f64; 5] = [1.0, 10.0, 100.0, 1000.0, 10000.0];
    if let Some(&scale) = SCALES.get(decimals) {
        let scaled = value * scale;
        let fraction = scaled - scaled.floor();
        if scaled.abs() < 1e12 && (fraction - 0.5).abs() > 1e-6 {
            let units = scaled.round() as i64;
            if units < 0 {
                out.push('-');
            }
            let (units, scale) = (units.unsigned_abs(), scale as u64);
            let mut digits = itoa(units / scale);
            out.push_str(digits.as_str());
            let mut fraction = units % scale;
            if fraction > 0 {
                let mut width = decimals;
                while fraction % 10 == 0 {
                    fraction /= 10;
                    width -= 1;
                }
                out.push('.');
                digits = itoa(fraction);
                for _ in digits.as_str().len()..width {
                    out.push('0');
                }
                out.push_str(digits.as_str());
            }
            return;
        }
    }
    let start = out.len();
    // Writing into a String cannot fail.
    let _ = write!(out, "{value:.decimals$}");
    if out[start..].contains('.') {
        let trimmed = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + trimmed);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// Decimal digits of `value`, without allocating.
fn itoa(mut value: u64) -> Digits {
    let mut digits = Digits {
        bytes: [0; 20],
        start: 20,
    };
    loop {
        digits.start -= 1;
        digits.bytes[digits.start] = b'0' + (value % 10) as u8;
        value /= 10;
        if value == 0 {
            return digits;
        }
    }
}

/// The digits [`itoa`] writes.
struct Digits {
    bytes: [u8; 20],
    start: usize,
}

impl Digits {
    fn as_str(&self) -> &str {
        // Only ASCII digits are ever written.
        std::str::from_utf8(&self.bytes[self.start..]).unwrap_or("0")
    }
}

#[cfg(test)]
mod tests {
    use super::push_number;

    fn number(value: f64, decimals: usize) -> String {
        let mut out = String::from("x");
        push_number(&mut out, value, decimals);
        out[1..].to_string()
    }

    #[test]
    fn numbers_are_trimmed_and_rounded() {
        assert_eq!(number(12.5, 2), "12.5");
        assert_eq!(number(3.0, 2), "3");
        assert_eq!(number(0.004, 2), "0");
        assert_eq!(number(-0.004, 2), "0");
        assert_eq!(number(-1.236, 2), "-1.24");
        assert_eq!(number(100.0, 2), "100");
        assert_eq!(number(0.1234, 3), "0.123");
        assert_eq!(number(f64::NAN, 2), "0");
        assert_eq!(number(-0.5, 0), "0");
        assert_eq!(
            number(0.125, 2),
            "0.12",
            "an exact tie rounds to even, as the formatter does"
        );
        assert_eq!(number(2480.0, 3), "2480");
        assert_eq!(number(-7.05, 2), "-7.05");
        assert_eq!(number(1e15, 2), "1000000000000000");
    }

    /// The fast path writes exactly what the formatter (then trimmed) writes.
    #[test]
    fn numbers_match_the_formatter() {
        let formatted = |value: f64, decimals: usize| {
            let mut s = format!("{value:.decimals$}");
            if s.contains('.') {
                s = s.trim_end_matches('0').trim_end_matches('.').to_string();
            }
            if s == "-0" {
                s = "0".to_string();
            }
            s
        };
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        for k in 0..200_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let unit = (seed >> 11) as f64 / (1u64 << 53) as f64;
            let value = match k % 4 {
                0 => (unit - 0.5) * 8000.0,
                1 => (unit * 4000.0 * 8.0).round() / 8.0,
                2 => (unit - 0.5) * 2e-3,
                _ => (unit * 1000.0).round() / 1000.0 + 0.0005,
            };
            for decimals in 0..=4 {
                assert_eq!(
                    number(value, decimals),
                    formatted(value, decimals),
                    "{value:e}"
                );
            }
        }
    }
}
