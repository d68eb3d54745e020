//! How the `trace_points` fuzz target reads its bytes, shared with the replay of its findings in
//! `tests/hostile.rs` (included there by path).
//!
//! The first byte chooses how the rest is read:
//! - 0: text, through the point-list parser (the CLI's path for `.txt`/`.xy` files);
//! - 1: raw little-endian f64 pairs, handed to the library as they are (NaN, infinities,
//!   subnormals, 1e308...);
//! - 2: byte pairs as small integer coordinates times a scale from the next byte, so that the
//!   fuzzer reaches dense, stroke-like sets (collinear runs, duplicates, clusters) easily.
//!
//! Bit 2 of the first byte selects the paper's parameters.

use ridgeline::Params;

/// The points and parameters `data` stands for, or `None` when it stands for nothing.
pub fn points_and_params(data: &[u8]) -> Option<(Vec<[f64; 2]>, Params)> {
    let (&selector, rest) = data.split_first()?;
    let list: Vec<[f64; 2]> = match selector & 3 {
        0 => ridgeline::point_list::parse(&String::from_utf8_lossy(rest)).ok()?,
        1 => rest
            .chunks_exact(16)
            .map(|c| {
                let x = f64::from_le_bytes(c[..8].try_into().unwrap_or_default());
                let y = f64::from_le_bytes(c[8..].try_into().unwrap_or_default());
                [x, y]
            })
            .collect(),
        _ => {
            let (&scale, pairs) = rest.split_first()?;
            // Scales from 1/16 to 16 around 1 (pixel-like spacing).
            let scale = 2f64.powi(i32::from(scale % 9) - 4);
            pairs
                .chunks_exact(2)
                .map(|c| [f64::from(c[0]) * scale, f64::from(c[1]) * scale])
                .collect()
        }
    };
    let params = if selector & 4 != 0 {
        Params::paper()
    } else {
        Params::default()
    };
    Some((list, params))
}
