//! Minutiae as an ISO/IEC 19794-2:2005 finger minutiae record (docs/fingerprints.md, "Outputs"):
//! the binary record format most matchers and smart cards read. All numbers are big-endian.
//!
//! | offset | bytes | field |
//! |---|---|---|
//! | 0 | 4 | format identifier `"FMR\0"` |
//! | 4 | 4 | version `" 20\0"` |
//! | 8 | 4 | length of the whole record |
//! | 12 | 2 | capture equipment: 4 bits of certification flags, 12 bits of equipment ID (0: unknown) |
//! | 14 | 2 | image width, px |
//! | 16 | 2 | image height, px |
//! | 18 | 2 | horizontal resolution, px per cm |
//! | 20 | 2 | vertical resolution, px per cm |
//! | 22 | 1 | number of finger views (1) |
//! | 23 | 1 | reserved (0) |
//! | 24 | 4 | finger view: position (0: unknown finger), view number (4 bits, 0) and impression type (4 bits, 0: live-scan plain), finger quality 0-100, number of minutiae |
//! | 28 | 6 each | minutia: type (2 bits: 01 ending, 10 bifurcation) and x (14 bits); 2 reserved bits and y (14 bits); angle; quality 0-100 |
//! | end | 2 | length of the extended data (0: none) |
//!
//! Coordinates are pixels from the top-left corner, y down; the angle is in units of 360/256
//! degrees, counterclockwise from the +x axis as the image is seen. The standard's minutia
//! direction (the one ANSI INCITS 378 shares) bisects the narrowest angle of the three rays at
//! the fork of a ridge (bifurcation) or of a valley (ending): an ending points *into* its ridge,
//! a bifurcation from the fork *between* its branches. That is the opposite of NIST's `.xyt`
//! direction, which ridgeline keeps ([`crate::minutiae`]: out of the ridge past an ending, along
//! the stem away from a bifurcation's branches), so the record holds ridgeline's direction turned
//! by half a turn. The finger quality is the mean of the minutiae's qualities.

use crate::error::{Error, Result};
use crate::minutiae::{Minutia, MinutiaKind};

/// Largest coordinate a minutia can have (14 bits).
const MAX_COORDINATE: f64 = 16383.0;

/// Most minutiae one finger view holds (its count is one byte).
pub const MAX_MINUTIAE: usize = 255;

/// The [`MAX_MINUTIAE`] of highest quality among `minutiae` (all of them when they fit), in
/// their order; of equal qualities the earlier ones. What a matcher does with more minutiae
/// than it takes (Bozorth3 keeps its 150 of highest quality): the ones it can trust most.
pub fn best_for_record(minutiae: &[Minutia]) -> Vec<Minutia> {
    if minutiae.len() <= MAX_MINUTIAE {
        return minutiae.to_vec();
    }
    let mut order: Vec<usize> = (0..minutiae.len()).collect();
    order.sort_by_key(|&i| (std::cmp::Reverse(minutiae[i].quality.unwrap_or(0)), i));
    order.truncate(MAX_MINUTIAE);
    order.sort_unstable();
    order.into_iter().map(|i| minutiae[i]).collect()
}

/// The record of `minutiae` found on a `width x height` image scanned at `dpi` dots per inch.
/// Refuses more than [`MAX_MINUTIAE`] minutiae (choose them first with [`best_for_record`]),
/// an image or a position beyond 14-bit coordinates, and a resolution that is not positive.
pub fn to_bytes(minutiae: &[Minutia], width: u32, height: u32, dpi: f64) -> Result<Vec<u8>> {
    let count = u8::try_from(minutiae.len()).map_err(|_| {
        Error::Record(format!(
            "an ISO/IEC 19794-2 record holds at most {MAX_MINUTIAE} minutiae, got {}; keep the \
             ones of highest quality with export::iso19794::best_for_record",
            minutiae.len()
        ))
    })?;
    let side = |v: u32| {
        u16::try_from(v).map_err(|_| {
            Error::Record(format!(
                "an ISO/IEC 19794-2 record holds images up to 65535 px, got {v}"
            ))
        })
    };
    let (w, h) = (side(width)?, side(height)?);
    if !(dpi.is_finite() && dpi > 0.0 && dpi / 2.54 <= 65535.0) {
        return Err(Error::Record(format!(
            "resolution must be > 0 dpi, got {dpi}"
        )));
    }
    let per_cm = (dpi / 2.54).round().max(1.0) as u16;
    let length = 24 + 4 + 6 * minutiae.len() + 2;
    let mut out = Vec::with_capacity(length);
    out.extend_from_slice(b"FMR\0");
    out.extend_from_slice(b" 20\0");
    out.extend_from_slice(&(length as u32).to_be_bytes());
    out.extend_from_slice(&0u16.to_be_bytes());
    out.extend_from_slice(&w.to_be_bytes());
    out.extend_from_slice(&h.to_be_bytes());
    out.extend_from_slice(&per_cm.to_be_bytes());
    out.extend_from_slice(&per_cm.to_be_bytes());
    out.push(1);
    out.push(0);
    let qualities: Vec<u32> = minutiae
        .iter()
        .map(|m| u32::from(m.quality.unwrap_or(50).min(100)))
        .collect();
    let finger_quality = if qualities.is_empty() {
        0
    } else {
        (qualities.iter().sum::<u32>() as f64 / qualities.len() as f64).round() as u8
    };
    out.extend_from_slice(&[0, 0, finger_quality, count]);
    for (m, &q) in minutiae.iter().zip(&qualities) {
        let coordinate = |v: f64| {
            if v.is_finite() && v >= 0.0 && v.round() <= MAX_COORDINATE {
                Ok(v.round() as u16)
            } else {
                Err(Error::Record(format!(
                    "minutia at {v} px is outside an ISO/IEC 19794-2 record's 14-bit coordinates"
                )))
            }
        };
        let kind: u16 = match m.kind {
            MinutiaKind::Ending => 0b01,
            MinutiaKind::Bifurcation => 0b10,
        };
        let (x, y) = (coordinate(m.pos[0])?, coordinate(m.pos[1])?);
        out.extend_from_slice(&((kind << 14) | x).to_be_bytes());
        out.extend_from_slice(&y.to_be_bytes());
        let direction = if m.direction.is_finite() {
            m.direction
        } else {
            0.0
        };
        // y down and clockwise on screen -> counterclockwise as seen: the angle changes sign;
        // the standard's direction is ridgeline's turned by half a turn (module doc).
        let iso_degrees = (180.0 - direction.to_degrees()).rem_euclid(360.0);
        let units = (iso_degrees / (360.0 / 256.0)).round();
        out.push((units as u32 % 256) as u8);
        out.push(q as u8);
    }
    out.extend_from_slice(&0u16.to_be_bytes());
    debug_assert_eq!(out.len(), length);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn minutia(kind: MinutiaKind, pos: [f64; 2], direction: f64, quality: Option<u8>) -> Minutia {
        Minutia {
            kind,
            vertex: 0,
            pos,
            direction,
            width: 4.0,
            quality,
        }
    }

    #[test]
    fn record_layout_byte_by_byte() {
        let record = to_bytes(
            &[
                // An ending whose ridge runs to the right into it: the standard's direction
                // points back into the ridge, to the left, half a turn: 128 units.
                minutia(MinutiaKind::Ending, [100.4, 200.0], 0.0, Some(80)),
                // A bifurcation whose stem leaves the fork up the screen (branches below): the
                // standard's direction points down between the branches, three quarter turns
                // counterclockwise: 192 units.
                minutia(
                    MinutiaKind::Bifurcation,
                    [16383.0, 7.0],
                    -FRAC_PI_2,
                    Some(40),
                ),
            ],
            500,
            400,
            500.0,
        )
        .expect("encodes");
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            b'F', b'M', b'R', 0, b' ', b'2', b'0', 0,
            0, 0, 0, 42,            // 24 + 4 + 2 * 6 + 2
            0, 0,                   // equipment
            0x01, 0xF4, 0x01, 0x90, // 500 x 400
            0, 197, 0, 197,         // 500 dpi = 196.85 px/cm
            1, 0,                   // one view, reserved
            0, 0, 60, 2,            // finger position, view/impression, quality, count
            0x40, 100, 0, 200, 128, 80,     // ending: type 01, x 100; y 200; angle 128; q 80
            0xBF, 0xFF, 0, 7, 192, 40,      // bifurcation: type 10, x 16383; y 7; 192; q 40
            0, 0,                   // no extended data
        ];
        assert_eq!(record, expected);
        assert_eq!(to_bytes(&[], 10, 10, 500.0).expect("empty").len(), 30);
    }

    #[test]
    fn out_of_range_values_are_errors() {
        let m = minutia(MinutiaKind::Ending, [16384.0, 1.0], 0.0, None);
        assert!(matches!(
            to_bytes(&[m], 100, 100, 500.0),
            Err(Error::Record(_))
        ));
        assert!(to_bytes(&[], 70_000, 10, 500.0).is_err());
        assert!(to_bytes(&[], 10, 10, 0.0).is_err());
        assert!(to_bytes(&[], 10, 10, f64::NAN).is_err());
        let many = vec![minutia(MinutiaKind::Ending, [1.0, 1.0], 0.0, None); 256];
        let message = to_bytes(&many, 10, 10, 500.0)
            .expect_err("256 minutiae")
            .to_string();
        assert!(
            message.contains("at most 255 minutiae, got 256") && !message.contains("picture"),
            "{message}"
        );
    }

    #[test]
    fn the_best_255_are_kept_in_order() {
        // 300 minutiae of qualities 0-99 cycling: the 255 kept are every one of quality at
        // least the cut, the cut's ties the earlier ones, in input order.
        let all: Vec<Minutia> = (0..300)
            .map(|i| {
                minutia(
                    MinutiaKind::Ending,
                    [f64::from(i), 1.0],
                    0.0,
                    Some((i % 100) as u8),
                )
            })
            .collect();
        let kept = best_for_record(&all);
        assert_eq!(kept.len(), MAX_MINUTIAE);
        assert!(kept.windows(2).all(|p| p[0].pos[0] < p[1].pos[0]));
        // Qualities 15-99 three times each is 255.
        assert!(kept.iter().all(|m| m.quality >= Some(15)));
        assert_eq!(best_for_record(&all[..10]), all[..10].to_vec());
        to_bytes(&kept, 400, 10, 500.0).expect("fits");
    }
}
