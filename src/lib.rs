//! ridgeline turns raster images of strokes (scanned text, handwriting, Chinese characters,
//! fingerprints) into stroke graphs: the centerlines as polylines meeting at junctions.
//!
//! The method is the one of *Efficient reconstruction of non-simple curves* (anisotropic adaptive
//! sampling, non-linear region clustering, edge refinement, least-squares fitting), adapted to pixel
//! images. Data flows one way through stages that sit side by side; this file is the one place that
//! chains them:
//!
//! ```text
//! bytes ─decode─> gray ─binarize─> Binary ─points─> PointSet ─sample─> Samples
//!       ─graph─> NodeGraph (H + clusters) ─refine─> NodeGraph (1-D) ─fit─> StrokeGraph ─export─> SVG/JSON
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
mod decisions;
mod error;
mod gray;
mod mask;
mod node_graph;
mod params;
mod point_set;
mod samples;
mod stroke_graph;
mod subpixel;

pub mod csr;
pub mod curves;
pub mod debug;
pub mod draw;
pub mod export;
pub mod fingerprint;
pub(crate) mod fit;
pub mod geometry;
mod graph;
pub mod minutiae;
pub mod point_list;
pub mod raster;
mod refine;
mod sample;
mod skeleton;
pub mod strokes;
pub mod warnings;

// The unit tests of `skeleton.rs` draw their inputs under the name the test kit gives the drawing
// helper (`ridgeline_testkit::synth` re-exports `draw`); the test kit itself depends on this crate,
// so the unit tests cannot use it.
#[cfg(test)]
mod synth {
    pub(crate) use crate::draw::{render, Stroke};
}

pub use binary::{Binary, MaskView};
pub use decisions::{Decisions, PrintDecisions, ThresholdUsed, Warning, UNEVEN_LIGHT};
pub use error::{Error, Result};
pub use geometry::dist;
pub use gray::GrayView;
pub use image::GrayImage;
pub use node_graph::{GraphNode, NodeGraph};
pub use params::{
    ClusterRule, Enhancement, FingerprintParams, LaplacianRule, Limits, Params, Polarity, RMinRule,
    Threshold, DENSE_SPACING, MAX_WEISZFELD_ITERATIONS,
};
pub use point_set::{Grid, PointSet};
pub use samples::{Node, Samples};
pub use stroke_graph::{Edge, StrokeGraph, Vertex};

use std::time::{Duration, Instant};

/// Wall-clock time spent in each stage of one trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Image decoding (zero when the caller passed pixels).
    pub decode: Duration,
    /// Thresholding and polarity.
    pub binarize: Duration,
    /// Point set, neighbour graph and distance transform.
    pub points: Duration,
    /// §3.1 sampling.
    pub sampling: Duration,
    /// §3.2 node graph and clusters.
    pub graph: Duration,
    /// §3.3 contraction, merging and clean-up.
    pub refine: Duration,
    /// §3.4 fitting and building the stroke graph.
    pub fit: Duration,
}

impl Timings {
    /// Adds `other`'s time per stage to this one's.
    pub fn add(&mut self, other: &Timings) {
        self.decode += other.decode;
        self.binarize += other.binarize;
        self.points += other.points;
        self.sampling += other.sampling;
        self.graph += other.graph;
        self.refine += other.refine;
        self.fit += other.fit;
    }
}

/// Intermediate results kept for `--debug` pictures.
#[derive(Clone, Debug, Default)]
pub struct Stages {
    /// The points the pipeline ran on.
    pub points: PointSet,
    /// The sampled nodes.
    pub samples: Samples,
    /// Graph `H` with clusters (§3.2).
    pub node_graph: NodeGraph,
    /// The 1-D graph after §3.3.
    pub refined: NodeGraph,
}

/// Everything one trace produces.
#[derive(Clone, Debug)]
pub struct Trace {
    /// The result.
    pub graph: StrokeGraph,
    /// The foreground mask (images only).
    pub binary: Option<Binary>,
    /// Number of points the pipeline ran on (ink pixels, or lines of a point list).
    pub point_count: usize,
    /// Intermediate results, when asked for.
    pub stages: Option<Stages>,
    /// Time per stage.
    pub timings: Timings,
    /// What the front end decided (images only): polarity, threshold, dropout mode.
    pub decisions: Option<Decisions>,
    /// What is probably wrong with the result ([`warnings`]).
    pub warnings: Vec<Warning>,
    /// The share of the ink traced in dropout mode (images and masks; docs/design.md,
    /// adaptation 2): it is decided per group of nearby components (docs/design.md, "The front
    /// end"). [`Trace::dropout`] says whether any was.
    pub dropout_share: Option<f64>,
    /// What the fingerprint front end found and the print's minutiae (images traced with
    /// [`Params::fingerprint`] set only).
    pub fingerprint: Option<Box<FingerprintTrace>>,
}

impl Trace {
    /// Whether dropout mode was on for any of the ink.
    pub fn dropout(&self) -> Option<bool> {
        self.dropout_share.map(|share| share > 0.0)
    }
}

/// The fingerprint front end's stages and the minutiae it keeps (docs/fingerprints.md).
#[derive(Clone, Debug)]
pub struct FingerprintTrace {
    /// Segmentation, orientation field, ridge periods, the enhanced image and its contrast.
    pub analysis: fingerprint::PrintAnalysis,
    /// The minutiae inside the print, filtered and with qualities
    /// ([`minutiae::fingerprint_minutiae`]).
    pub minutiae: Vec<minutiae::Minutia>,
    /// Time of the front end (segmentation to enhanced binary image).
    pub enhance: Duration,
}

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
    trace_gray(gray.into(), params)
}

/// [`trace_image`] on its one input type.
fn trace_gray(gray: GrayView<'_>, params: &Params) -> Result<Trace> {
    params.validate()?;
    if let Some(print) = &params.fingerprint {
        return trace_print(gray, params, print);
    }
    let start = Instant::now();
    let (binary, decisions) = raster::binarize_deciding(gray, params)?;
    let binarize_time = start.elapsed();
    let mut trace = trace_mask(binary.view(), params)?;
    refine_on_gray(&mut trace, gray, &binary, &decisions, params);
    Ok(with_decisions(trace, binary, decisions, binarize_time))
}

/// Places the centerline of `trace` below the pixel from the gray levels, when
/// [`Params::subpixel`] asks for it.
fn refine_on_gray(
    trace: &mut Trace,
    gray: GrayView<'_>,
    binary: &Binary,
    decisions: &Decisions,
    params: &Params,
) {
    if params.subpixel {
        let dark_ink = decisions.polarity == "dark";
        subpixel::center_on_gray(&mut trace.graph, gray, binary, dark_ink);
    }
}

/// Completes the trace of an image's mask: the front end's `decisions` with the dropout mode the
/// trace found, the warnings both give, the mask and the time binarizing took.
fn with_decisions(
    mut trace: Trace,
    binary: Binary,
    mut decisions: Decisions,
    binarize_time: Duration,
) -> Trace {
    trace.timings.binarize = binarize_time;
    decisions.dropout = trace.dropout();
    decisions.dropout_share = trace.dropout_share;
    trace.warnings = warnings::of(&trace.graph, Some(&decisions));
    trace.decisions = Some(decisions);
    trace.binary = Some(binary);
    trace
}

/// The fingerprint path of [`trace_image`]: front end, the normal pipeline on its binary image,
/// then the fingerprint minutiae filter. Ridges are dark or light as `params.polarity` says, else
/// as the image shows ([`print_front_end`]).
fn trace_print(gray: GrayView<'_>, params: &Params, print: &FingerprintParams) -> Result<Trace> {
    let (analysis, binary, enhance) = print_front_end(gray, params, print)?;
    let trace = trace_mask(binary.view(), params)?;
    Ok(with_minutiae(trace, binary, analysis, enhance, print))
}

/// The fingerprint front end of [`trace_print`]: the print's analysis, its binary image and the
/// time they took, after the pixel limit is checked.
fn print_front_end(
    gray: GrayView<'_>,
    params: &Params,
    print: &FingerprintParams,
) -> Result<(fingerprint::PrintAnalysis, Binary, Duration)> {
    let (width, height) = gray.dimensions();
    let pixels = u64::from(width) * u64::from(height);
    if pixels > params.limits.max_pixels {
        return Err(Error::Limit {
            what: "image pixels",
            actual: pixels,
            limit: params.limits.max_pixels,
            flag: "--max-pixels",
        });
    }
    let start = Instant::now();
    // Given, or decided from the image as the automatic polarity decides it (ridges and
    // valleys are about as wide, so the print's background at the image border decides, and
    // the prior for dark ink when it does not show).
    let (dark_ridges, confidence) = match params.polarity {
        Polarity::DarkInk => (true, None),
        Polarity::LightInk => (false, None),
        Polarity::Auto => {
            let (dark, confidence) = raster::split_polarity(gray);
            (dark, Some(confidence))
        }
    };
    let (mut analysis, binary) = fingerprint::analyze(gray, print, dark_ridges);
    analysis.polarity_confidence = confidence;
    Ok((analysis, binary, start.elapsed()))
}

/// Completes the trace of a print's binary image with its minutiae, its front end and what that
/// decided, and the warnings.
fn with_minutiae(
    mut trace: Trace,
    binary: Binary,
    analysis: fingerprint::PrintAnalysis,
    enhance: Duration,
    print: &FingerprintParams,
) -> Trace {
    trace.graph = fingerprint::prior::ridges_along_the_flow(
        std::mem::take(&mut trace.graph),
        &analysis,
        print,
    );
    let decisions = print_decisions(&analysis, &binary, print);
    let mut trace = with_decisions(trace, binary, decisions, enhance);
    let minutiae = minutiae::fingerprint_minutiae(&trace.graph, &analysis, print);
    trace.fingerprint = Some(Box::new(FingerprintTrace {
        analysis,
        minutiae,
        enhance,
    }));
    trace
}

/// The fingerprint front end's decisions: the polarity it was given or decided, with its
/// confidence when decided, the enhanced image's sign as the threshold, the ridge width (median
/// chord of the enhanced ridges), and what it measured on the print.
fn print_decisions(
    analysis: &fingerprint::PrintAnalysis,
    binary: &Binary,
    print: &FingerprintParams,
) -> Decisions {
    let inside = &analysis.segmentation.inside;
    let blocks_inside = inside.iter().filter(|&&i| i).count();
    let mut coherence: Vec<f32> = analysis
        .orientation
        .coherence
        .iter()
        .zip(inside)
        .filter(|(_, &i)| i)
        .map(|(&c, _)| c)
        .collect();
    let chords = raster::chords(&binary.ink, binary.width as usize, binary.height as usize);
    Decisions {
        polarity: if analysis.dark_ridges {
            "dark"
        } else {
            "light"
        },
        polarity_confidence: analysis.polarity_confidence,
        threshold: ThresholdUsed::Enhanced {
            enhancement: print.enhancement,
        },
        stroke_width: chords.dark_median,
        uneven_light: 0.0,
        dropout: None,
        dropout_share: None,
        reversed_grounds: Vec::new(),
        print: Some(PrintDecisions {
            ridge_period: analysis.periods.median_inside(&analysis.segmentation),
            print_share: blocks_inside as f64 / inside.len().max(1) as f64,
            coherence: f64::from(fingerprint::math::median(&mut coherence)),
        }),
    }
}

/// Traces a foreground mask: a `&Binary`, or a [`MaskView`] of flags borrowed from elsewhere,
/// read in place.
pub fn trace_binary<'a>(binary: impl Into<MaskView<'a>>, params: &Params) -> Result<Trace> {
    let mut trace = trace_mask(binary.into(), params)?;
    trace.warnings = warnings::of(&trace.graph, None);
    Ok(trace)
}

/// [`trace_binary`] without the warnings: an image's trace gives them with its decisions.
fn trace_mask(binary: MaskView<'_>, params: &Params) -> Result<Trace> {
    params.validate()?;
    if params.min_area > 0 {
        let kept = raster::drop_small_components(binary, params.min_area);
        return trace_mask(
            kept.view(),
            &Params {
                min_area: 0,
                ..params.clone()
            },
        );
    }
    let start = Instant::now();
    // A large mask goes straight to chunks of components, each chunk's points built where it is
    // traced; a small one (or one in dropout mode) becomes one point set first.
    if let Some(chunks) = raster::pixel_chunks(binary, params, CHUNK_POINTS)? {
        let scan_time = start.elapsed();
        let sizes: Vec<usize> = (0..chunks.len()).map(|c| chunks.size(c)).collect();
        let mut trace = run_chunks(&sizes, |c| chunks.part(c), params)?;
        trace.graph.width = binary.width;
        trace.graph.height = binary.height;
        trace.timings.points += scan_time;
        // Chunks are only cut outside dropout mode.
        trace.dropout_share = Some(0.0);
        return Ok(trace);
    }
    let points = raster::points(binary, params)?;
    let points_time = start.elapsed();
    let dropout = points.dropout;
    // Dropout mode is decided per group of nearby components where the groups disagree.
    if dropout && params.dropout.is_none() {
        if let Some((solid, speckled)) = raster::split_dropout(binary, params) {
            drop(points);
            let forced = |on: bool| Params {
                dropout: Some(on),
                ..params.clone()
            };
            let mut trace = trace_mask(solid.view(), &forced(false))?;
            let broken = trace_mask(speckled.view(), &forced(true))?;
            append_graph(&mut trace.graph, broken.graph);
            trace.timings.add(&broken.timings);
            trace.timings.points += points_time;
            trace.point_count += broken.point_count;
            trace.dropout_share = Some(speckled.count() as f64 / binary.count().max(1) as f64);
            return Ok(trace);
        }
    }
    let mut trace = run(points, binary.width, binary.height, params, false)?;
    trace.timings.points += points_time;
    trace.dropout_share = Some(if dropout { 1.0 } else { 0.0 });
    Ok(trace)
}

/// Appends `part`'s vertices and edges to `graph`, its edges' ends shifted past `graph`'s
/// vertices.
fn append_graph(graph: &mut StrokeGraph, part: StrokeGraph) {
    let offset = graph.vertices.len();
    graph.vertices.extend(part.vertices);
    graph.edges.extend(part.edges.into_iter().map(|mut e| {
        e.from += offset;
        e.to += offset;
        e
    }));
}

/// Traces a point list (the paper's own setting): the same pipeline, neighbours from a k-d tree.
pub fn trace_points(list: &[[f64; 2]], params: &Params) -> Result<Trace> {
    params.validate()?;
    let start = Instant::now();
    // The stages run in pixel-like units and the result is mapped back (docs/design.md, "Hostile
    // input"; see `point_list::Units`).
    let (points, units) = point_list::point_set_in_units(list, params)?;
    let points_time = start.elapsed();
    let (w, h) = point_list::extent(list);
    let mut trace = run(points, w, h, params, false)?;
    units.restore_graph(&mut trace.graph);
    trace.warnings = warnings::of(&trace.graph, None);
    trace.timings.points += points_time;
    Ok(trace)
}

/// Like [`trace_image`], keeping the intermediate stages for pictures: the front end's decisions
/// and the warnings as [`trace_image`] gives them, the stages of one point set (dropout mode is
/// decided for the whole image here, not per group of components). `gray` as for
/// [`trace_image`].
pub fn trace_image_with_stages<'a>(
    gray: impl Into<GrayView<'a>>,
    params: &Params,
) -> Result<Trace> {
    let gray = gray.into();
    params.validate()?;
    if let Some(print) = &params.fingerprint {
        // The fingerprint front end makes its own binary image; the stages are those of tracing
        // it, once, and the minutiae are those of the graph the stages end with.
        let (analysis, binary, enhance) = print_front_end(gray, params, print)?;
        let binary = if params.min_area > 0 {
            raster::drop_small_components(binary.view(), params.min_area)
        } else {
            binary
        };
        let trace = trace_binary_with_stages(&binary, params)?;
        return Ok(with_minutiae(trace, binary, analysis, enhance, print));
    }
    let start = Instant::now();
    let (binary, decisions) = raster::binarize_deciding(gray, params)?;
    let binarize_time = start.elapsed();
    let binary = if params.min_area > 0 {
        raster::drop_small_components(binary.view(), params.min_area)
    } else {
        binary
    };
    let mut trace = trace_binary_with_stages(&binary, params)?;
    refine_on_gray(&mut trace, gray, &binary, &decisions, params);
    Ok(with_decisions(trace, binary, decisions, binarize_time))
}

/// Like [`trace_binary`], keeping the intermediate stages for pictures.
pub fn trace_binary_with_stages<'a>(
    binary: impl Into<MaskView<'a>>,
    params: &Params,
) -> Result<Trace> {
    let binary = binary.into();
    params.validate()?;
    let points = raster::points(binary, params)?;
    // One point set: dropout mode is on for all of the ink or none.
    let dropout = points.dropout;
    let mut trace = run(points, binary.width, binary.height, params, true)?;
    trace.dropout_share = Some(if dropout { 1.0 } else { 0.0 });
    Ok(trace)
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

/// Points per chunk when a large input is traced in parallel (whole components per chunk).
const CHUNK_POINTS: usize = 16_384;

fn run(points: PointSet, width: u32, height: u32, params: &Params, keep: bool) -> Result<Trace> {
    let mut trace = if keep || points.len() <= CHUNK_POINTS {
        let point_count = points.len();
        let (graph, stages, timings) = run_stages(points, params, keep);
        Trace {
            graph,
            binary: None,
            point_count,
            stages,
            timings,
            decisions: None,
            warnings: Vec::new(),
            dropout_share: None,
            fingerprint: None,
        }
    } else {
        let chunks = points.component_chunks(CHUNK_POINTS);
        let sizes: Vec<usize> = (0..chunks.len()).map(|c| chunks.size(c)).collect();
        run_chunks(&sizes, |c| Ok(chunks.part(&points, c)), params)?
    };
    trace.graph.width = width;
    trace.graph.height = height;
    Ok(trace)
}

/// Traces chunks `0..count` of whole components in parallel, each point set made by `part` on the
/// thread that traces it, and joins the graphs in chunk order. The result does not depend on the
/// thread count, nor on where the chunks were cut: every stage treats components independently,
/// and the one figure taken over the whole input, the fit's node spacing `h` (the median stroke
/// width), is taken between the refinement of all chunks and their fits.
/// Chunks are started largest first (a page's one giant component would otherwise be picked up
/// late and run alone at the end); `sizes` are their point counts.
fn run_chunks(
    sizes: &[usize],
    part: impl Fn(usize) -> Result<PointSet> + Sync,
    params: &Params,
) -> Result<Trace> {
    use rayon::prelude::*;
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&c| std::cmp::Reverse(sizes[c]));
    let refined: Vec<(usize, PointSet, NodeGraph, Timings)> = order
        .into_par_iter()
        .map(|c| {
            let clock = Instant::now();
            let mut points = part(c)?;
            let mut timings = Timings {
                points: clock.elapsed(),
                ..Timings::default()
            };
            let refined = refine_stages(&points, params, &mut timings, None);
            // The pixel index is the bulk of a chunk's memory; the chunks wait for the others
            // without it, so the next chunk's index reuses the same memory.
            if let Some(grid) = &mut points.grid {
                grid.release();
            }
            Ok((c, points, refined, timings))
        })
        .collect::<Result<_>>()?;
    let Some((_, first, _, _)) = refined.first() else {
        return Ok(Trace {
            graph: StrokeGraph::default(),
            binary: None,
            point_count: 0,
            stages: None,
            timings: Timings::default(),
            decisions: None,
            warnings: Vec::new(),
            dropout_share: None,
            fingerprint: None,
        });
    };
    let graphs: Vec<&NodeGraph> = refined.iter().map(|(_, _, graph, _)| graph).collect();
    let h = fit::node_spacing(&graphs, first, params);
    let mut parts: Vec<(usize, StrokeGraph, usize, Timings)> = refined
        .into_par_iter()
        .map(|(c, mut points, refined, mut timings)| {
            let clock = Instant::now();
            if let Some(grid) = &mut points.grid {
                grid.rebuild(&points.points);
            }
            let mut graph = fit::fit_with_spacing(&refined, &points, params, h);
            if params.skeleton {
                graph = skeleton::carry(&graph, &points);
            }
            timings.fit = clock.elapsed();
            (c, graph, points.len(), timings)
        })
        .collect();
    parts.sort_by_key(|&(c, ..)| c);
    let mut graph = StrokeGraph::default();
    let mut timings = Timings::default();
    let mut point_count = 0;
    for (_, part, n, t) in parts {
        append_graph(&mut graph, part);
        point_count += n;
        timings.add(&t);
    }
    Ok(Trace {
        graph,
        binary: None,
        point_count,
        stages: None,
        timings,
        decisions: None,
        warnings: Vec::new(),
        dropout_share: None,
        fingerprint: None,
    })
}

/// §3.1-§3.3 on one point set, timed into `timings`; the sampling and `H` go to `keep` when given.
fn refine_stages(
    points: &PointSet,
    params: &Params,
    timings: &mut Timings,
    keep: Option<&mut Option<(Samples, NodeGraph)>>,
) -> NodeGraph {
    let clock = Instant::now();
    let samples = sample::sample(points, params);
    timings.sampling = clock.elapsed();

    let clock = Instant::now();
    let node_graph = graph::build(points, &samples, params);
    timings.graph = clock.elapsed();

    let clock = Instant::now();
    let refined = refine::refine(&node_graph, points, params);
    timings.refine = clock.elapsed();
    if let Some(keep) = keep {
        *keep = Some((samples, node_graph));
    }
    refined
}

fn run_stages(
    points: PointSet,
    params: &Params,
    keep: bool,
) -> (StrokeGraph, Option<Stages>, Timings) {
    let mut timings = Timings::default();
    let mut kept = None;
    let refined = refine_stages(&points, params, &mut timings, keep.then_some(&mut kept));

    let clock = Instant::now();
    let mut graph = fit::fit(&refined, &points, params);
    if params.skeleton {
        graph = skeleton::carry(&graph, &points);
    }
    timings.fit = clock.elapsed();

    let stages = kept.map(|(samples, node_graph)| Stages {
        points,
        samples,
        node_graph,
        refined,
    });
    (graph, stages, timings)
}
