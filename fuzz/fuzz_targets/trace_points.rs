//! Fuzz target (b): arbitrary point sets -> trace -> SVG and JSON.
//!
//! The first byte chooses how the rest is read:
//! - 0: text, through the point-list parser (the CLI's path for `.txt`/`.xy` files);
//! - 1: raw little-endian f64 pairs, handed to the library as they are (NaN, infinities,
//!   subnormals, 1e308...);
//! - 2: byte pairs as small integer coordinates times a scale from the next byte, so that the
//!   fuzzer reaches dense, stroke-like sets (collinear runs, duplicates, clusters) easily.
//!
//! Bit 2 of the first byte selects the paper's parameters. At most 4096 points per execution.

#![no_main]

use libfuzzer_sys::fuzz_target;
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::Params;

const MAX_POINTS: usize = 4096;

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    let list: Vec<[f64; 2]> = match selector & 3 {
        0 => match ridgeline::point_list::parse(&String::from_utf8_lossy(rest)) {
            Ok(list) => list,
            Err(_) => return,
        },
        1 => rest
            .chunks_exact(16)
            .map(|c| {
                let x = f64::from_le_bytes(c[..8].try_into().unwrap_or_default());
                let y = f64::from_le_bytes(c[8..].try_into().unwrap_or_default());
                [x, y]
            })
            .collect(),
        _ => {
            let Some((&scale, pairs)) = rest.split_first() else {
                return;
            };
            // Scales from 1/16 to 16 around 1 (pixel-like spacing).
            let scale = 2f64.powi(i32::from(scale % 9) - 4);
            pairs
                .chunks_exact(2)
                .map(|c| [f64::from(c[0]) * scale, f64::from(c[1]) * scale])
                .collect()
        }
    };
    if list.len() > MAX_POINTS {
        return;
    }
    let params = if selector & 4 != 0 {
        Params::paper()
    } else {
        Params::default()
    };
    let Ok(trace) = ridgeline::trace_points(&list, &params) else {
        return;
    };
    if let Err(e) = trace.graph.validate() {
        panic!("invalid stroke graph: {e}");
    }
    let _ = svg::to_string(&trace.graph, None, &SvgOptions::default());
    let _ = json::to_string(&trace.graph, &JsonMeta::new(params));
});
