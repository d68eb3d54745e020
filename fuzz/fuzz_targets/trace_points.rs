//! Fuzz target (b): arbitrary point sets -> trace -> SVG and JSON. How the bytes are read is in
//! `point_bytes.rs`. At most 4096 points per execution.

#![no_main]

use libfuzzer_sys::fuzz_target;
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, SvgOptions};

mod point_bytes;

const MAX_POINTS: usize = 4096;

fuzz_target!(|data: &[u8]| {
    let Some((list, params)) = point_bytes::points_and_params(data) else {
        return;
    };
    if list.len() > MAX_POINTS {
        return;
    }
    let Ok(trace) = ridgeline::trace_points(&list, &params) else {
        return;
    };
    if let Err(e) = trace.graph.validate() {
        panic!("invalid stroke graph: {e}");
    }
    let _ = svg::to_string(&trace.graph, None, &SvgOptions::default());
    let _ = json::to_string(&trace.graph, &JsonMeta::new(params));
});
