//! Writing a stroke graph as SVG and JSON (the last box of the pipeline diagram).
//!
//! Export depends on [`StrokeGraph`](crate::StrokeGraph) alone (and on the source image for the SVG
//! backdrop): it never runs a stage. Both writers are deterministic, so the same graph always gives
//! the same bytes, and both round coordinates (2 decimals in SVG, 3 in JSON) because the fit's
//! sub-pixel precision beyond that is noise that only makes files larger.

pub mod json;
pub mod svg;

use std::fmt::Write;

/// Appends `value` with at most `decimals` decimals, trailing zeros trimmed (`12.50` → `12.5`,
/// `3.00` → `3`) and negative zero written as `0`. Non-finite values are written as `0` so that
/// the document stays well-formed whatever the graph holds.
pub(crate) fn push_number(out: &mut String, value: f64, decimals: usize) {
    if !value.is_finite() {
        out.push('0');
        return;
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
    }
}
