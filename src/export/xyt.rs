//! Minutiae as NIST's `.xyt` text, the input of the NBIS matcher Bozorth3 (docs/fingerprints.md,
//! "Outputs"): one line per minutia, `x y theta quality`, four integers separated by spaces.
//!
//! The convention is the one NBIS's `mindtct` writes (`lfs2nist_minutia_XYT`):
//! - `x` is the column in pixels, `y` is **flipped**: `height - y_image`, so the origin is the
//!   image's bottom-left corner and y grows upwards;
//! - `theta` is in whole degrees `0..360`, counterclockwise from the +x axis in that y-up frame.
//!   ridgeline writes the minutia's own direction, which is NIST's ([`crate::minutiae`]): out of
//!   the ridge past the end of an ending; from the fork along the stem, away from the branches,
//!   of a bifurcation (the ending the valley between the branches makes in the inverted print).
//!   So an ending whose ridge runs to the right into it has `theta = 0`, and a bifurcation whose
//!   stem leaves the fork up the screen has `theta = 90`. Bozorth3 compares the angles of one
//!   template with each other and with another template's, so templates to be matched must come
//!   from one convention;
//! - `quality` is 0-100 ([`Minutia::quality`]), 50 when the minutia has none.
//!
//! Minutiae are written in the order given; coordinates are rounded to the nearest pixel.

use crate::minutiae::Minutia;
use std::fmt::Write;

/// The `.xyt` text of `minutiae` found on an image `height` pixels high.
pub fn to_string(minutiae: &[Minutia], height: u32) -> String {
    let mut out = String::with_capacity(minutiae.len() * 16);
    for m in minutiae {
        let (x, y, theta) = nist_xyt(m, height);
        let quality = m.quality.map_or(50, |q| q.min(100));
        let _ = writeln!(out, "{x} {y} {theta} {quality}");
    }
    out
}

/// `(x, y, theta)` of `m` in NIST's convention (see the module doc).
pub fn nist_xyt(m: &Minutia, height: u32) -> (i64, i64, i64) {
    let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
    let x = finite(m.pos[0]).round() as i64;
    let y = (f64::from(height) - finite(m.pos[1])).round() as i64;
    // y down and clockwise on screen -> y up and counterclockwise: the angle changes sign.
    let degrees = (-finite(m.direction))
        .to_degrees()
        .rem_euclid(360.0)
        .round() as i64
        % 360;
    (x, y, degrees)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::minutiae::MinutiaKind;
    use std::f64::consts::FRAC_PI_2;

    fn minutia(pos: [f64; 2], direction: f64, quality: Option<u8>) -> Minutia {
        Minutia {
            kind: MinutiaKind::Ending,
            vertex: 0,
            pos,
            direction,
            width: 4.0,
            quality,
        }
    }

    #[test]
    fn y_is_flipped_and_angles_turn_counterclockwise() {
        let text = to_string(
            &[
                minutia([10.4, 20.0], 0.0, Some(77)),
                // Up the screen (y down: -pi/2) is 90 degrees in the y-up frame.
                minutia([30.0, 290.0], -FRAC_PI_2, None),
                // Down the screen is 270, and a hair below 0 rounds to 0, never 360.
                minutia([0.0, 0.0], FRAC_PI_2, Some(200)),
                minutia([1.0, 1.0], -1e-9, Some(3)),
            ],
            300,
        );
        assert_eq!(text, "10 280 0 77\n30 10 90 50\n0 300 270 100\n1 299 0 3\n");
        assert_eq!(to_string(&[], 10), "");
    }
}
