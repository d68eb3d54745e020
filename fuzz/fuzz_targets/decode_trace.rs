//! Fuzz target (a): arbitrary bytes -> decode -> trace -> SVG and JSON.
//!
//! Small limits keep every execution fast (at most 256 x 256 pixels); whatever the bytes, the
//! library must return an error or a valid stroke graph, never panic.

#![no_main]

use libfuzzer_sys::fuzz_target;
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::{Limits, Params};

fuzz_target!(|data: &[u8]| {
    let limits = Limits {
        max_pixels: 256 * 256,
        max_side: 256,
        max_points: 256 * 256,
    };
    let Ok(gray) = ridgeline::decode(data, &limits) else {
        return;
    };
    // The default parameters, and the paper's on small images (a second code path through
    // sampling, merging and fitting) while keeping executions short.
    let mut presets = vec![Params::default()];
    if gray.width() * gray.height() <= 64 * 64 {
        presets.push(Params::paper());
    }
    for params in presets {
        let params = Params { limits, ..params };
        let Ok(trace) = ridgeline::trace_image(&gray, &params) else {
            continue;
        };
        if let Err(e) = trace.graph.validate() {
            panic!("invalid stroke graph: {e}");
        }
        let _ = svg::to_string(&trace.graph, Some(&gray), &SvgOptions::default());
        let _ = json::to_string(&trace.graph, &JsonMeta::new(params));
    }
});
