//! Fuzz target (a): arbitrary bytes -> pages -> decode -> trace -> SVG (over the page's picture)
//! and JSON.
//!
//! Small limits keep every execution fast (at most 256 x 256 pixels, 4 TIFF pages); whatever the
//! bytes, the library must return an error or a valid stroke graph, never panic, and
//! `ridgeline::decode` must give the first page's gray.

#![no_main]

use libfuzzer_sys::fuzz_target;
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, Backdrop, SvgOptions};
use ridgeline::export::Features;
use ridgeline::raster::Picture;
use ridgeline::{Limits, Params};

fuzz_target!(|data: &[u8]| {
    let mut limits = Limits::default();
    limits.max_pixels = 256 * 256;
    limits.max_side = 256;
    limits.max_points = 256 * 256;
    limits.max_pages = 4;
    let Ok(pages) = ridgeline::raster::pages(data, &limits) else {
        return;
    };
    let count = pages.page_count();
    for page in pages.with_pictures(true) {
        let Ok(page) = page else {
            continue;
        };
        if page.number == 1 {
            match ridgeline::decode(data, &limits) {
                Ok(gray) if gray == page.gray => {}
                _ => panic!("decode differs from the first page"),
            }
        }
        let gray = &page.gray;
        // The default parameters, and the paper's on small images (a second code path through
        // sampling, merging and fitting) while keeping executions short.
        let mut presets = vec![Params::default()];
        if gray.width() * gray.height() <= 64 * 64 {
            presets.push(Params::paper());
        }
        for params in presets {
            let mut params = params;
            params.front_end.limits = limits;
            let Ok(trace) = ridgeline::trace_image(gray, &params) else {
                continue;
            };
            if let Err(e) = trace.graph.validate() {
                panic!("invalid stroke graph: {e}");
            }
            let backdrop = match &page.picture {
                Picture::Original { mime } => Backdrop::Encoded { bytes: data, mime },
                Picture::Color(image) => Backdrop::Color(image),
                Picture::Gray => Backdrop::Gray(gray),
            };
            let _ = svg::to_string_with(
                &trace.graph,
                Some(backdrop),
                &SvgOptions::default(),
                &Features::default(),
            );
            let meta = JsonMeta::new(params).with_page(page.number, count);
            let _ = json::to_string(&trace.graph, &meta);
        }
    }
});
