//! ridgeline turns raster images of strokes (scanned text, handwriting, Chinese characters,
//! fingerprints) into stroke graphs: the centerlines as polylines meeting at junctions.
//!
//! The method is the one of *Efficient reconstruction of non-simple curves* (anisotropic adaptive
//! sampling, non-linear region clustering, edge refinement, least-squares fitting), adapted to pixel
//! images. Data flows one way through stages that sit side by side; the driver (`pipeline.rs`) is
//! the one place that chains them, and this file holds its public entry points:
//!
//! ```text
//! bytes ─decode─> gray ─binarize─> Binary ─points─> PointSet ─sample─> Samples
//!       ─graph─> NodeGraph (H + clusters) ─refine─> NodeGraph (1-D) ─fit─> StrokeGraph
//!       ─skeleton─> StrokeGraph ─export─> SVG/JSON
//! ```
//!
//! # Example
//!
//! Trace a '+' drawn with 6 px strokes: the result is one vertex of degree 4 at the crossing,
//! four stroke ends of degree 1, and four edges between them.
//!
//! ```
//! use ridgeline::draw::{render, Stroke};
//! use ridgeline::{trace_binary, Params};
//!
//! let plus = render(
//!     &[
//!         Stroke::new(vec![[10.0, 40.0], [70.0, 40.0]], 6.0),
//!         Stroke::new(vec![[40.0, 10.0], [40.0, 70.0]], 6.0),
//!     ],
//!     80,
//!     80,
//! );
//! let trace = trace_binary(&plus, &Params::default())?;
//! let graph = &trace.graph;
//! let crossings: Vec<_> = graph.vertices.iter().filter(|v| v.degree == 4).collect();
//! assert_eq!(crossings.len(), 1);
//! assert!(ridgeline::dist(crossings[0].pos, [40.0, 40.0]) < 2.0);
//! assert_eq!(graph.endpoints().count(), 4);
//! assert_eq!(graph.edges.len(), 4);
//!
//! // The same graph as SVG (over the image, when one is given) and as JSON.
//! let svg = ridgeline::export::svg::to_string(graph, None, &Default::default());
//! assert!(svg.starts_with("<svg"));
//! let meta = ridgeline::export::json::JsonMeta::new(Params::default());
//! let json = ridgeline::export::json::to_string(graph, &meta);
//! assert!(json.contains("\"junctions\":1"));
//! # Ok::<(), ridgeline::Error>(())
//! ```
//!
//! # Where to start
//!
//! - From a file: [`decode`] then [`trace_image`] (every page of a multi-page TIFF, with what to
//!   show under the centerlines: [`raster::pages`]); from a mask: [`trace_binary`]; from pixels
//!   you own elsewhere, without a copy: a [`GrayView`] or [`MaskView`] of them; from `x y`
//!   points: [`point_list::parse`] then [`trace_points`]. Every tunable is in [`Params`], whose
//!   defaults are the values that measure best on pixel images ([`Params::paper`] gives the
//!   paper's).
//! - The result is a [`StrokeGraph`]; [`export::svg`] and [`export::json`] write it, and
//!   [`strokes`], [`minutiae`] and [`curves`] derive pen strokes, fingerprint minutiae and Bézier
//!   curves from it.
//! - To see what each stage did, trace with [`trace_binary_with_stages`] and draw the stages with
//!   [`debug::stage_pictures`] or encode them with [`debug::stage_pngs`] (the CLI's `--debug DIR`).
//!   [`thin`] gives plain thinning, for comparison.
//! - Errors are [`Error`]; the library never panics on input, and refuses inputs larger than
//!   [`Limits`] before allocating for them.

#![warn(missing_docs)]

mod binary;
mod cloud3d;
mod curve3d;
mod decisions;
mod error;
mod gray;
mod median;
mod node_graph;
mod params;
mod pipeline;
mod point_index;
mod point_set;
mod samples;
mod stroke_graph;
mod subpixel;
#[cfg(test)]
mod test_rng;

pub mod csr;
pub mod curves;
pub mod debug;
pub mod draw;
pub mod export;
pub mod fingerprint;
pub(crate) mod fit;
pub mod geometry;
mod graph;
pub mod mask;
pub mod minutiae;
pub mod point_list;
pub mod raster;
mod refine;
mod sample;
mod skeleton;
pub mod strokes;
pub mod warnings;

/// The stack of each worker thread a caller starts for ridgeline's parallel passes (bytes): a
/// worker that waits for a pass of one file steals other files' work and runs it on top of its
/// own stack, so a batch nests whole traces; the default of 2 MiB overflowed about one batch of
/// FVC2002's 320 prints in eight at `--jobs 2`. Only the pages a thread touches are used.
pub const WORKER_STACK_BYTES: usize = 64 << 20;

pub use binary::{Binary, MaskView};
pub use curve3d::{dist3, CurveGraph3d, Edge3d, Trace3d, Vertex3d};
pub use decisions::{
    Decisions, InkSide, PrintDecisions, Region, ThresholdUsed, Warning, UNEVEN_LIGHT,
};
pub use error::{Error, Result};
pub use geometry::dist;
pub use gray::GrayView;
pub use image::GrayImage;
pub use node_graph::{GraphNode, NodeGraph};
pub use params::{
    ClusterRule, Enhancement, ExperimentParams, FingerprintParams, FinishParams, FitParams,
    FrontEndParams, LaplacianRule, Limits, MethodParams, Params, Polarity, RMinRule, RegionKind,
    Threshold, DENSE_SPACING, MAX_WEISZFELD_ITERATIONS,
};
pub use pipeline::{FingerprintTrace, Stages, Timings, Trace};
pub use point_set::{Grid, PointSet};
pub use samples::{Node, Samples};
pub use stroke_graph::{Edge, StrokeGraph, Vertex};

use pipeline::Recording;

/// Decodes an image file's bytes to grayscale, refusing images larger than `limits` before
/// allocating their pixels.
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    raster::decode(bytes, limits)
}

/// Traces a grayscale image: binarize, then run the pipeline on the ink pixels. With
/// [`Params::fingerprint`] set, the fingerprint front end (segmentation, orientation field,
/// ridge period, Gabor enhancement; [`fingerprint`]) makes the binary image instead, and the
/// trace carries the print's filtered minutiae ([`Trace::fingerprint`]).
///
/// `gray` is a `&GrayImage` or a [`GrayView`] of pixels borrowed from elsewhere (rows any
/// distance apart); the pixels are read in place, never copied.
pub fn trace_image<'a>(gray: impl Into<GrayView<'a>>, params: &Params) -> Result<Trace> {
    pipeline::image(gray.into(), params, Recording::Off)
}

/// Traces a foreground mask: a `&Binary`, or a [`MaskView`] of flags borrowed from elsewhere,
/// read in place.
pub fn trace_binary<'a>(binary: impl Into<MaskView<'a>>, params: &Params) -> Result<Trace> {
    pipeline::mask(binary.into(), params, Recording::Off)
}

/// Traces a point list (the paper's own setting): the same pipeline, neighbours from a k-d tree.
pub fn trace_points(list: &[[f64; 2]], params: &Params) -> Result<Trace> {
    pipeline::point_list(list, params)
}

/// Traces a 3D point list (the paper's Fig. 7): the same four stages with three principal axes
/// (Eq. (1)-(3)) and the least squares of Eq. (4) in space; the result's polylines carry `z` and
/// the tube's diameter ([`Trace3d`]). [`point_files::read`] reads `x y z` lines, CSV, PLY and
/// XYZ files.
pub fn trace_points3d(list: &[[f64; 3]], params: &Params) -> Result<Trace3d> {
    pipeline::point_cloud3d(list, params)
}

/// [`trace_image`], keeping the intermediate stages for pictures ([`Trace::stages`]): the same
/// trace, the same result, with the stages that made it. `gray` as for [`trace_image`].
pub fn trace_image_with_stages<'a>(
    gray: impl Into<GrayView<'a>>,
    params: &Params,
) -> Result<Trace> {
    pipeline::image(gray.into(), params, Recording::Stages)
}

/// [`trace_binary`], keeping the intermediate stages for pictures ([`Trace::stages`]).
pub fn trace_binary_with_stages<'a>(
    binary: impl Into<MaskView<'a>>,
    params: &Params,
) -> Result<Trace> {
    pipeline::mask(binary.into(), params, Recording::Stages)
}

/// Zhang-Suen thinning of a mask and the graph thinning tools extract from its one-pixel skeleton
/// (junction pixels clustered into one vertex, ends, the pixel paths between them, widths from the
/// distance transform), without any stage of the method: the quality benchmark's thinning
/// baseline, and the skeleton the default tracing carries its geometry on (docs/design.md,
/// "Skeleton-carried geometry"). Refuses a mask whose `ink` is not `width x height` pixels.
pub fn thin(binary: &Binary) -> Result<StrokeGraph> {
    binary.check_size()?;
    Ok(skeleton::thin(binary))
}

// The unit tests of `skeleton/` draw their inputs under the name the test kit gives the drawing
// helper (`ridgeline_testkit::synth` re-exports `draw`); the test kit itself depends on this crate,
// so the unit tests cannot use it.
#[cfg(test)]
mod synth {
    pub(crate) use crate::draw::{render, Stroke};

    /// The binary of `rows` drawn as text, `#` for ink, each row one pixel row.
    pub(crate) fn drawn(rows: &[&str]) -> crate::binary::Binary {
        let width = rows.iter().map(|r| r.len()).max().unwrap_or(0);
        let ink = rows
            .iter()
            .flat_map(|r| (0..width).map(move |x| r.as_bytes().get(x) == Some(&b'#')))
            .collect();
        crate::binary::Binary {
            width: width as u32,
            height: rows.len() as u32,
            ink,
        }
    }

    /// A fixed pseudo-random sequence for the unit tests' inputs: the linear congruential
    /// generator of Knuth's MMIX from `seed`, each call the next state (whose high bits are
    /// the random ones).
    pub(crate) fn lcg(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state
        }
    }
}
