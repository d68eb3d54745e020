//! The driver: the one path from an image, a mask or a point list to the stroke graph
//! (ARCHITECTURE.md, "The pipeline").
//!
//! ```text
//! gray ─binarize─> Binary ─┐                                   (or the fingerprint front end)
//!                          ├─ small components dropped (min_area)
//!                          ├─ dropout mode per group of components (docs/design.md, "The front end")
//!                          └─ chunks of whole components ─> PointSet per chunk
//! point list ─units─> PointSet ─┘
//! PointSet ─§3.1 sample─> Samples ─§3.2 graph─> NodeGraph ─§3.3 refine─> NodeGraph (1-D)
//!          ─§3.4 fit─> StrokeGraph ─skeleton─> StrokeGraph ─sub-pixel / print prior─> warnings
//! ```
//!
//! Every public entry validates its [`Params`] once and then runs this path; the `*_with_stages`
//! entries run the same path with [`Recording::Stages`], which keeps each chunk's intermediate
//! results and joins them as the graphs are joined, so the pictures show the output's own trace.

use std::time::{Duration, Instant};

use crate::binary::{Binary, MaskView};
use crate::decisions::{Decisions, PrintDecisions, ThresholdUsed, Warning};
use crate::error::{Error, Result};
use crate::gray::GrayView;
use crate::node_graph::NodeGraph;
use crate::params::{FingerprintParams, Params, Polarity};
use crate::point_set::{Components, Grid, PackedComponents, PointSet};
use crate::samples::Samples;
use crate::stroke_graph::StrokeGraph;
use crate::{
    cloud3d, fingerprint, fit, graph, minutiae, point_list, raster, refine, sample, skeleton,
    subpixel, warnings,
};

/// Points per chunk when a large input is traced in parallel (whole components per chunk).
const CHUNK_POINTS: usize = 16_384;

/// Wall-clock time spent in each stage of one trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Image decoding (zero when the caller passed pixels).
    pub decode: Duration,
    /// Thresholding and polarity (for a print: its front end, as [`FingerprintTrace::enhance`]).
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
    /// The skeleton carrying the geometry (docs/design.md, "Skeleton-carried geometry"; zero
    /// with [`FinishParams::skeleton`](crate::FinishParams::skeleton) off).
    pub skeleton: Duration,
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
        self.skeleton += other.skeleton;
    }
}

/// Intermediate results kept for `--debug` pictures. When the input was traced in parts (chunks
/// of components, or groups in and out of dropout mode), the parts' stages follow one another in
/// the order their graphs do, each part's indices shifted past the parts before it.
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
    /// ([`fingerprint::minutiae::fingerprint_minutiae`]).
    pub minutiae: Vec<minutiae::Minutia>,
    /// Time of the front end (segmentation to enhanced binary image).
    pub enhance: Duration,
}

/// Whether a trace keeps its intermediate stages ([`Trace::stages`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Recording {
    /// Only the result.
    Off,
    /// The result and the stages that made it.
    Stages,
}

/// What tracing a mask or a point set gives, before the front end's results join it.
struct Traced {
    graph: StrokeGraph,
    point_count: usize,
    timings: Timings,
    stages: Option<Stages>,
}

impl Traced {
    /// Joins traces of disjoint parts of one input, in order: each part's graph (and stages)
    /// after those of the parts before it.
    fn join(parts: Vec<Traced>) -> Traced {
        let mut graph = StrokeGraph::default();
        let mut timings = Timings::default();
        let mut point_count = 0;
        let mut stages = Vec::with_capacity(parts.len());
        let mut recorded = true;
        for part in parts {
            append_graph(&mut graph, part.graph);
            point_count += part.point_count;
            timings.add(&part.timings);
            match part.stages {
                Some(s) => stages.push(s),
                None => recorded = false,
            }
        }
        Traced {
            graph,
            point_count,
            timings,
            stages: (recorded && !stages.is_empty()).then(|| Stages::join(stages)),
        }
    }

    /// The [`Trace`] of this result (the one place one is built); the front end's results are
    /// added by the entry that ran it.
    fn into_trace(self, dropout_share: Option<f64>) -> Trace {
        Trace {
            graph: self.graph,
            binary: None,
            point_count: self.point_count,
            stages: self.stages,
            timings: self.timings,
            decisions: None,
            warnings: Vec::new(),
            dropout_share,
            fingerprint: None,
        }
    }
}

/// Traces a grayscale image ([`crate::trace_image`]): binarize (or the fingerprint front end),
/// the mask's pipeline, sub-pixel placement, the front end's decisions and the warnings.
pub(crate) fn image(gray: GrayView<'_>, params: &Params, recording: Recording) -> Result<Trace> {
    params.validate()?;
    if let Some(print) = &params.fingerprint {
        return print_image(gray, params, print, recording);
    }
    let start = Instant::now();
    let (binary, decisions) = raster::binarize_deciding(gray, params)?;
    let binarize_time = start.elapsed();
    let mut trace = trace_mask(binary.view(), params, recording)?;
    if params.front_end.subpixel {
        let dark_ink = decisions.polarity == crate::decisions::InkSide::Dark;
        subpixel::center_on_gray(&mut trace.graph, gray, &binary, dark_ink);
    }
    Ok(with_decisions(trace, binary, decisions, binarize_time))
}

/// Traces a foreground mask ([`crate::trace_binary`]): the mask's pipeline and the warnings.
pub(crate) fn mask(binary: MaskView<'_>, params: &Params, recording: Recording) -> Result<Trace> {
    params.validate()?;
    let mut trace = trace_mask(binary, params, recording)?;
    trace.warnings = warnings::of(&trace.graph, None, Some(binary));
    Ok(trace)
}

/// Traces a point list ([`crate::trace_points`], the paper's own setting): the same stages,
/// neighbours from a k-d tree. The stages run in pixel-like units and the result is mapped back
/// (docs/design.md, "Hostile input"; see [`point_list::Units`]).
pub(crate) fn point_list(list: &[[f64; 2]], params: &Params) -> Result<Trace> {
    params.validate()?;
    let start = Instant::now();
    let point_list::Prepared {
        set: points,
        units,
        not_strip,
        left_out,
        parts,
    } = point_list::point_set_in_units(list, params)?;
    let points_time = start.elapsed();
    let (width, height) = point_list::extent(list);
    // A set that is not strip-shaped holds no curve for the method to find (§3): nothing is
    // traced, in time linear in its size, and the warning says why.
    let count = points.len();
    let points = if not_strip.is_some() {
        PointSet {
            offsets: vec![0],
            ..PointSet::default()
        }
    } else {
        points
    };
    let mut traced = trace_points_in_parts(points, parts, params, Recording::Off)?;
    traced.point_count = count;
    traced.graph.width = width;
    traced.graph.height = height;
    traced.timings.points += points_time;
    units.restore_graph(&mut traced.graph);
    let mut trace = traced.into_trace(None);
    trace.warnings = warnings::of(&trace.graph, None, None);
    if let Some(share) = not_strip {
        trace.warnings.push(warnings::not_strip_shaped(share));
    }
    if left_out > 0 {
        trace
            .warnings
            .push(warnings::sparse_points_left_out(left_out, count + left_out));
    }
    Ok(trace)
}

/// Traces a 3D point list ([`crate::trace_points3d`]): the stages in space (`cloud3d`), then
/// the warning for a set that is not tube-shaped.
pub(crate) fn point_cloud3d(list: &[[f64; 3]], params: &Params) -> Result<crate::curve3d::Trace3d> {
    params.validate()?;
    let start = Instant::now();
    let (graph, point_count, not_tube, left_out) = cloud3d::trace(list, params)?;
    let mut warnings = Vec::new();
    if let Some(share) = not_tube {
        warnings.push(warnings::not_strip_shaped(share));
    }
    if left_out > 0 {
        warnings.push(warnings::sparse_points_left_out(
            left_out,
            point_count + left_out,
        ));
    }
    Ok(crate::curve3d::Trace3d {
        graph,
        point_count,
        warnings,
        time: start.elapsed(),
    })
}

/// The fingerprint path of [`image`]: front end, the mask's pipeline on its binary image, the prior
/// of ridges along the flow, then the fingerprint minutiae filter. Ridges are dark unless
/// `params.front_end.polarity` says light (a print's ridges and valleys are about as wide, so the
/// stroke evidence of the text front end cannot tell them apart).
fn print_image(
    gray: GrayView<'_>,
    params: &Params,
    print: &FingerprintParams,
    recording: Recording,
) -> Result<Trace> {
    let (width, height) = gray.dimensions();
    let pixels = u64::from(width) * u64::from(height);
    if pixels > params.front_end.limits.max_pixels {
        return Err(Error::Limit {
            what: "image pixels",
            actual: pixels,
            limit: params.front_end.limits.max_pixels,
            field: "limits.max_pixels",
        });
    }
    let start = Instant::now();
    // Given, or decided from the image exactly as the automatic front end decides it for any
    // other image, up to the decision only (its binary would not be used: the print is
    // binarized by its enhancement, and the steps after the decision, such as opening the
    // valleys and reversing grounds, cost as much as the decision again). A plain
    // Otsu split read two of the real gray prints (docs/fingerprints.md) as light; this reads
    // all of them as their ridges are.
    // The decision runs beside the front end's stages that do not depend on it.
    let polarity = || match params.front_end.polarity {
        Polarity::DarkInk => Ok((true, None)),
        Polarity::LightInk => Ok((false, None)),
        Polarity::Auto => {
            let decided = raster::decide_polarity(gray, params)?;
            Ok((
                decided.polarity == crate::decisions::InkSide::Dark,
                decided.polarity_confidence,
            ))
        }
    };
    let (mut analysis, binary) = fingerprint::analyze_deciding(gray, print, polarity)?;
    let enhance = start.elapsed();
    // Only the stages' pictures read the Gabor response once the print is binarized: freed
    // before tracing, whose memory then stands where the front end's stood (a print's page
    // faults follow the heap's high-water mark: docs/fingerprints.md, "Speed: the front stages'
    // planes").
    if recording == Recording::Off {
        analysis.enhanced = fingerprint::fields::Plane::default();
    }

    let mut trace = trace_mask(binary.view(), params, recording)?;
    trace.graph = fingerprint::prior::ridges_along_the_flow(
        std::mem::take(&mut trace.graph),
        &analysis,
        print,
    );
    let decisions = print_decisions(&analysis, &binary, print);
    let mut trace = with_decisions(trace, binary, decisions, enhance);
    let minutiae = fingerprint::minutiae::fingerprint_minutiae(&trace.graph, &analysis, print);
    trace.fingerprint = Some(Box::new(FingerprintTrace {
        analysis,
        minutiae,
        enhance,
    }));
    Ok(trace)
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
    trace.warnings = warnings::of(&trace.graph, Some(&decisions), Some(binary.view()));
    trace.decisions = Some(decisions);
    trace.binary = Some(binary);
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
    // The median chord is read by `stroke_width` alone, so it is measured only when asked for.
    let stroke_width = if print.ridge_width {
        raster::chords(&binary.ink, binary.width as usize, binary.height as usize).dark_median
    } else {
        0.0
    };
    Decisions {
        polarity: crate::decisions::InkSide::of(analysis.dark_ridges),
        polarity_confidence: analysis.polarity_confidence,
        threshold: ThresholdUsed::Enhanced {
            enhancement: print.enhancement,
        },
        stroke_width,
        uneven_light: 0.0,
        dropout: None,
        dropout_share: None,
        reversed_grounds: Vec::new(),
        regions: Vec::new(),
        print: Some(PrintDecisions {
            ridge_period: analysis.periods.median_inside(&analysis.segmentation),
            print_share: blocks_inside as f64 / inside.len().max(1) as f64,
            coherence: f64::from(
                crate::median::upper_median_by(&mut coherence, f32::total_cmp).unwrap_or(0.0),
            ),
        }),
    }
}

/// The pipeline of a mask: its components of fewer than
/// [`FrontEndParams::min_area`](crate::FrontEndParams::min_area) pixels dropped, then [`trace_ink`]
/// with dropout mode as `params.front_end.dropout` says (decided here when `None`).
fn trace_mask(binary: MaskView<'_>, params: &Params, recording: Recording) -> Result<Trace> {
    let kept;
    let binary = if params.front_end.min_area > 0 {
        kept = raster::drop_small_components(binary, params.front_end.min_area);
        kept.view()
    } else {
        binary
    };
    let (mut traced, dropout_share) =
        trace_ink(binary, params, params.front_end.dropout, recording)?;
    traced.graph.width = binary.width;
    traced.graph.height = binary.height;
    Ok(traced.into_trace(Some(dropout_share)))
}

/// Traces the ink of `binary` with dropout mode `dropout` (decided here when `None`); returns the
/// result and the share of the ink traced in dropout mode.
///
/// A large mask outside dropout mode goes straight to chunks of components, each chunk's points
/// built where it is traced; otherwise the ink becomes one point set, and when dropout mode is
/// on for it but the groups of nearby components disagree, the solid groups and the broken ones
/// are traced apart, each in its own mode (docs/design.md, "The front end").
fn trace_ink(
    binary: MaskView<'_>,
    params: &Params,
    dropout: Option<bool>,
    recording: Recording,
) -> Result<(Traced, f64)> {
    let start = Instant::now();
    if let Some(chunks) = raster::pixel_chunks(binary, params, dropout, CHUNK_POINTS)? {
        let scan_time = start.elapsed();
        let sizes: Vec<usize> = (0..chunks.len()).map(|c| chunks.size(c)).collect();
        // Chunks are never in dropout mode. With the skeleton, each chunk's neighbour lists are
        // made only where the method (§3.1-§3.4) traces all of it: where it traces a part
        // ([`skeleton::Prepared::needing_method`]), the part's lists are read from its own pixel
        // index ([`raster::kept_pixels`]), and where the skeleton alone traces the chunk and its
        // stages are not recorded, nothing walks them ([`skeleton_only`]).
        let neighbours = !params.finish.skeleton;
        let mut traced = trace_chunks(
            &sizes,
            |c| {
                chunks
                    .part(c, neighbours)
                    .map(|(points, labels)| (points, Some(labels)))
            },
            neighbours,
            params,
            recording,
        )?;
        traced.timings.points += scan_time;
        // Chunks are only cut outside dropout mode.
        return Ok((traced, 0.0));
    }
    let points = raster::points_in_mode(binary, params, dropout)?;
    let points_time = start.elapsed();
    let on = points.dropout;
    if on && dropout.is_none() {
        if let Some((solid, speckled)) = raster::split_dropout(binary, params) {
            drop(points);
            let (solid_trace, _) = trace_ink(solid.view(), params, Some(false), recording)?;
            let (broken_trace, _) = trace_ink(speckled.view(), params, Some(true), recording)?;
            let mut traced = Traced::join(vec![solid_trace, broken_trace]);
            traced.timings.points += points_time;
            let share = speckled.count() as f64 / binary.count().max(1) as f64;
            return Ok((traced, share));
        }
    }
    let mut traced = trace_points(points, params, recording)?;
    traced.timings.points += points_time;
    Ok((traced, if on { 1.0 } else { 0.0 }))
}

/// Traces one point set: whole when small, else in chunks of whole components.
fn trace_points(points: PointSet, params: &Params, recording: Recording) -> Result<Traced> {
    trace_points_in_parts(points, None, params, recording)
}

/// [`trace_points`], given the components of the neighbour graph when they are known (`parts`:
/// one label per point, shared by a component's points; see
/// [`PointSet::first_seen`]).
fn trace_points_in_parts(
    points: PointSet,
    parts: Option<Vec<u32>>,
    params: &Params,
    recording: Recording,
) -> Result<Traced> {
    if points.len() <= CHUNK_POINTS {
        return Ok(trace_one(points, params, recording, None));
    }
    let labels = match parts {
        Some(parts) if parts.len() == points.len() => PointSet::first_seen(&parts),
        _ => points.component_labels(),
    };
    // One component is one chunk, a copy of the whole set: traced as it is (the chunk's node
    // spacing is its own, as `trace_chunks` would take it).
    if labels.1.len() == 1 && points.grid.is_none() {
        return Ok(trace_one(points, params, recording, Some(labels)));
    }
    let chunks = PointSet::chunks_of(labels, CHUNK_POINTS);
    let sizes: Vec<usize> = (0..chunks.len()).map(|c| chunks.size(c)).collect();
    trace_chunks(
        &sizes,
        |c| Ok((chunks.part(&points, c), None)),
        true,
        params,
        recording,
    )
}

/// §3.1-§3.4 and the skeleton on one point set; `components` are its
/// [`PointSet::component_labels`] when known (found here once otherwise, for the refinement, the
/// fit and the skeleton).
fn trace_one(
    mut points: PointSet,
    params: &Params,
    recording: Recording,
    components: Option<Components>,
) -> Traced {
    let mut timings = Timings::default();
    let components = components.unwrap_or_else(|| points.component_labels());
    let refining = refine_with_skeleton(
        &mut points,
        &components,
        true,
        params,
        recording,
        &mut timings,
    );
    let (method_points, method_components) = method_part(&points, &components, &refining.part);
    let clock = Instant::now();
    let graph = if refining.skeleton_only {
        StrokeGraph::default()
    } else {
        let h = fit::node_spacing(&[&refining.refined], method_points, params);
        fit::fit_in_components(
            &refining.refined,
            method_points,
            params,
            h,
            Some(&method_components.0),
        )
    };
    timings.fit = clock.elapsed();
    let point_count = points.len();
    let points = match refining.part {
        Some((part, _)) => part,
        None => points,
    };
    finish_one(
        graph,
        refining.prepared,
        points,
        point_count,
        refining.refined,
        refining.kept,
        params,
        timings,
    )
}

/// The skeleton of `points` prepared for carrying the geometry ([`skeleton::prepare`]) when
/// [`FinishParams::skeleton`](crate::FinishParams::skeleton) asks for it, and the points the
/// method (§3.1-§3.4) traces, with their components, where some components need no decision
/// of the method ([`skeleton::Prepared::needing_method`]; `None`: the method traces all of
/// `points`). Both are the skeleton's time.
fn prepare_skeleton(
    points: &mut PointSet,
    components: &Components,
    params: &Params,
    skeleton_only: bool,
    timings: &mut Timings,
) -> (Option<skeleton::Prepared>, Option<(PointSet, Components)>) {
    if !params.finish.skeleton {
        return (None, None);
    }
    let clock = Instant::now();
    let labels = (&components.0[..], &components.1[..]);
    let prepared = skeleton::prepare(
        points,
        &params.experiments,
        params.fingerprint.is_some(),
        Some(labels),
    );
    let needs = match &prepared {
        Some(prepared) if !skeleton_only => prepared.needing_method(points, labels),
        _ => None,
    };
    let part = needs.map(|needs| {
        // The whole set's pixel index is not read again: the part's reuses it.
        let mut whole_grid = points.grid.take();
        if let Some(grid) = &mut whole_grid {
            grid.release(&points.points);
        }
        let part = raster::kept_pixels(points, &needs);
        points.grid = whole_grid;
        let part = part.unwrap_or_else(|| points.kept(&needs));
        let components = part.component_labels();
        (part, components)
    });
    timings.skeleton += clock.elapsed();
    (prepared, part)
}

/// Whether the skeleton alone traces the point sets `params` make outside dropout mode (see
/// [`skeleton_only`]).
fn skeleton_traces(params: &Params) -> bool {
    params.fingerprint.is_some() && params.finish.skeleton
}

/// Whether the skeleton alone traces `points`: a print's ridges ([`Params::fingerprint`]) whose
/// skeleton carries the geometry ([`skeleton::prepare`]: not in dropout mode, not with
/// `--no-skeleton`). There the method's graph (§3.1-§3.4) would only lend its crossings, which
/// ridges do not make, and its end and junction positions, and the prints' minutiae matched no
/// worse without them, each ridge fitted to its own ink instead (docs/fingerprints.md, "Speed").
/// The method's stages still run when they are recorded, for their pictures, but decide nothing.
fn skeleton_only(points: &PointSet, params: &Params) -> bool {
    skeleton_traces(params)
        && !points.dropout
        && points.grid.as_ref().is_some_and(|g| !g.index.is_empty())
}

/// The skeleton on one fitted point set (§3.4's graph carried by it), and the point set's trace
/// with its stages when they were kept.
#[allow(clippy::too_many_arguments)]
fn finish_one(
    graph: StrokeGraph,
    prepared: Option<skeleton::Prepared>,
    mut points: PointSet,
    point_count: usize,
    refined: NodeGraph,
    kept: Option<(Samples, NodeGraph)>,
    params: &Params,
    mut timings: Timings,
) -> Traced {
    let graph = carry_on_skeleton(graph, prepared, params, &mut timings);
    // The pixel index goes to the thread's next window unless the stages keep it.
    if kept.is_none() {
        if let Some(grid) = &mut points.grid {
            grid.release(&points.points);
        }
    }
    // The stages' pictures show the points the method traced (`points`).
    Traced {
        graph,
        point_count,
        timings,
        stages: kept.map(|(samples, node_graph)| Stages {
            points,
            samples,
            node_graph,
            refined,
        }),
    }
}

/// Traces chunks `0..count` of whole components in parallel, each point set made by `part` on the
/// thread that traces it (with its [`PointSet::component_labels`] when `part` knows them: they
/// are found once per chunk otherwise, for the refinement, the fit and the skeleton), and joins the graphs (and stages) in chunk order. The result does not
/// depend on the thread count, nor on where the chunks were cut: every stage treats components
/// independently, and the one figure taken over the whole input, the fit's node spacing `h` (the
/// median stroke width), is taken between the refinement of all chunks and their fits.
/// Chunks are started largest first (a page's one giant component would otherwise be picked up
/// late and run alone at the end); `sizes` are their point counts. Without `neighbours` the
/// point sets `part` makes have no neighbour lists ([`raster::add_neighbours`] adds them where
/// the method traces a whole chunk).
fn trace_chunks(
    sizes: &[usize],
    part: impl Fn(usize) -> Result<(PointSet, Option<Components>)> + Sync,
    neighbours: bool,
    params: &Params,
    recording: Recording,
) -> Result<Traced> {
    use rayon::prelude::*;
    /// A chunk between its passes: refined (§3.1-§3.3), waiting for the spacing of §3.4 that
    /// all chunks' graphs set.
    struct Refined {
        c: usize,
        /// The points the method traced, set aside while they wait.
        points: (PointSet, Option<raster::Aside>),
        components: PackedComponents,
        prepared: Option<skeleton::Prepared>,
        /// All of the chunk's points, traced by the method or not.
        point_count: usize,
        refined: NodeGraph,
        timings: Timings,
        kept: Option<(Samples, NodeGraph)>,
    }
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&c| std::cmp::Reverse(sizes[c]));
    let refined: Vec<Refined> = order
        .into_par_iter()
        .map(|c| {
            let clock = Instant::now();
            let (mut points, components) = part(c)?;
            let components = components.unwrap_or_else(|| points.component_labels());
            let mut timings = Timings {
                points: clock.elapsed(),
                ..Timings::default()
            };
            let Refining {
                skeleton_only,
                prepared,
                part,
                refined,
                kept,
            } = refine_with_skeleton(
                &mut points,
                &components,
                neighbours,
                params,
                recording,
                &mut timings,
            );
            // Where the method traced a part of the points, only that part waits for the fit.
            let point_count = points.len();
            let (mut points, components) = match part {
                Some(part) => {
                    // The whole set's pixel index was released where the part was cut
                    // (`prepare_skeleton`): an empty index has no entry to set back.
                    if let Some(grid) = points.grid.as_mut().filter(|g| !g.index.is_empty()) {
                        grid.release(&points.points);
                    }
                    part
                }
                None => (points, components),
            };
            // The points, their pixel index and neighbour lists are the bulk of a chunk's
            // memory; the chunks wait for the others without them, so the next chunk's reuse
            // the same memory. A chunk the skeleton alone traces has no fit to wait for, and
            // unless the stages keep its points nothing reads them again: they go now, the
            // pixel index to the thread's next window (or, with no other window, freed), so
            // the skeleton's carry runs in their memory (a print's page faults follow the
            // heap's high-water mark: docs/fingerprints.md, "Speed: the front stages' planes").
            // Their component labels wait as runs.
            if skeleton_only && kept.is_none() {
                let mut grid = points.grid.take();
                if let Some(grid) = grid.as_mut().filter(|g| !g.index.is_empty()) {
                    if sizes.len() == 1 {
                        grid.index = Vec::new();
                    } else {
                        grid.release(&points.points);
                    }
                }
                points = PointSet {
                    spacing: points.spacing,
                    dropout: points.dropout,
                    grid,
                    ..PointSet::default()
                };
            }
            let aside = (!skeleton_only).then(|| raster::set_aside(&mut points));
            let components = PackedComponents::pack(components);
            Ok(Refined {
                c,
                points: (points, aside),
                components,
                prepared,
                point_count,
                refined,
                timings,
                kept,
            })
        })
        .collect::<Result<_>>()?;
    let Some(Refined {
        points: (first, _), ..
    }) = refined.first()
    else {
        return Ok(Traced::join(Vec::new()));
    };
    let graphs: Vec<&NodeGraph> = refined.iter().map(|chunk| &chunk.refined).collect();
    let h = fit::node_spacing(&graphs, first, params);
    let mut parts: Vec<(usize, Traced)> = refined
        .into_par_iter()
        .map(
            |Refined {
                 c,
                 points: (mut points, aside),
                 components,
                 prepared,
                 point_count,
                 refined,
                 mut timings,
                 kept,
             }| {
                let clock = Instant::now();
                let components = components.unpack();
                // Set aside only when a fit is to come: none where the skeleton alone traces.
                let graph = match aside {
                    Some(aside) => {
                        raster::restore(&mut points, aside);
                        fit::fit_in_components(&refined, &points, params, h, Some(&components.0))
                    }
                    None => StrokeGraph::default(),
                };
                timings.fit = clock.elapsed();
                let traced = finish_one(
                    graph,
                    prepared,
                    points,
                    point_count,
                    refined,
                    kept,
                    params,
                    timings,
                );
                (c, traced)
            },
        )
        .collect();
    parts.sort_by_key(|&(c, _)| c);
    // The threads' spare pixel indices are not kept past the trace.
    rayon::broadcast(|_| Grid::drop_spare_index());
    Ok(Traced::join(parts.into_iter().map(|(_, t)| t).collect()))
}

/// A point set between the method's refinement (§3.1-§3.3) and its fit: see
/// [`refine_with_skeleton`].
struct Refining {
    /// Whether the skeleton alone traces the points ([`skeleton_only`]).
    skeleton_only: bool,
    prepared: Option<skeleton::Prepared>,
    /// The points the method traced, where it traced a part ([`prepare_skeleton`]).
    part: Option<(PointSet, Components)>,
    refined: NodeGraph,
    kept: Option<(Samples, NodeGraph)>,
}

/// The skeleton of `points` (with its `components`) prepared ([`prepare_skeleton`]) and the
/// method's stages run on the points it needs ([`method_stages`]), timed into `timings`. Where
/// `points` were built without neighbour lists (not `neighbours`) and the method traces all of
/// them, their lists are added first ([`raster::add_neighbours`]).
fn refine_with_skeleton(
    points: &mut PointSet,
    components: &Components,
    neighbours: bool,
    params: &Params,
    recording: Recording,
    timings: &mut Timings,
) -> Refining {
    let skeleton_only = skeleton_only(points, params);
    let (prepared, part) = prepare_skeleton(points, components, params, skeleton_only, timings);
    let method_runs = !(skeleton_only && recording == Recording::Off);
    if !neighbours && part.is_none() && method_runs {
        raster::add_neighbours(points);
    }
    let (method_points, method_components) = method_part(points, components, &part);
    let (refined, kept) = method_stages(
        method_points,
        method_components,
        params,
        timings,
        recording,
        skeleton_only,
    );
    Refining {
        skeleton_only,
        prepared,
        part,
        refined,
        kept,
    }
}

/// The points the method traces: the `part` that [`prepare_skeleton`] cut (the junction
/// windows) or, without one, all of them.
fn method_part<'a>(
    points: &'a PointSet,
    components: &'a Components,
    part: &'a Option<(PointSet, Components)>,
) -> (&'a PointSet, &'a Components) {
    part.as_ref().map_or((points, components), |(p, c)| (p, c))
}

/// [`refine_stages`], or nothing where the skeleton alone traces `points` ([`skeleton_only`])
/// and the stages are not recorded for their pictures.
fn method_stages(
    points: &PointSet,
    components: &Components,
    params: &Params,
    timings: &mut Timings,
    recording: Recording,
    skeleton_only: bool,
) -> (NodeGraph, Option<(Samples, NodeGraph)>) {
    if skeleton_only && recording == Recording::Off {
        return (NodeGraph::default(), None);
    }
    refine_stages(points, components, params, timings, recording)
}

/// §3.1-§3.3 on one point set, timed into `timings`; the sampling and `H` are kept when
/// recording.
fn refine_stages(
    points: &PointSet,
    components: &Components,
    params: &Params,
    timings: &mut Timings,
    recording: Recording,
) -> (NodeGraph, Option<(Samples, NodeGraph)>) {
    let clock = Instant::now();
    let samples = sample::sample(points, params);
    timings.sampling = clock.elapsed();

    let clock = Instant::now();
    let node_graph = graph::build(points, &samples, params);
    timings.graph = clock.elapsed();

    let clock = Instant::now();
    let refined = refine::refine(&node_graph, points, params, Some(&components.0));
    timings.refine = clock.elapsed();
    let kept = (recording == Recording::Stages).then_some((samples, node_graph));
    (refined, kept)
}

/// The fitted `graph` with its geometry carried by the skeleton `prepared` for it
/// ([`prepare_skeleton`]; `None`: no skeleton asked for, or none that carries the points: point
/// lists, dropout mode), timed (docs/design.md, "Skeleton-carried geometry").
fn carry_on_skeleton(
    graph: StrokeGraph,
    prepared: Option<skeleton::Prepared>,
    params: &Params,
    timings: &mut Timings,
) -> StrokeGraph {
    let Some(prepared) = prepared else {
        return graph;
    };
    let clock = Instant::now();
    // Every edge fitted to its ink, a print's ridges too: without the method's lines
    // ([`skeleton_only`]) the pixel paths alone placed minutiae worse.
    let carried = prepared.carry(&graph, &params.experiments);
    timings.skeleton += clock.elapsed();
    carried
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

impl Stages {
    /// The stages of disjoint parts of one input, one after the other: points, nodes and clusters
    /// of each part numbered after those of the parts before it. The pixel grid covers the
    /// parts' windows together when every part has one.
    fn join(parts: Vec<Stages>) -> Stages {
        if parts.len() == 1 {
            return parts.into_iter().next().unwrap_or_default();
        }
        let windows: Option<Vec<(i64, i64, i64, i64)>> = parts
            .iter()
            .map(|s| {
                s.points.grid.as_ref().map(|g| {
                    let (x0, y0) = (g.x0, g.y0);
                    (x0, y0, x0 + i64::from(g.width), y0 + i64::from(g.height))
                })
            })
            .collect();
        let mut joined = Stages::default();
        let points = &mut joined.points;
        points.offsets.push(0);
        for part in parts {
            let point_base = points.points.len() as u32;
            let neighbour_base = points.neighbors.len() as u32;
            let sample_base = joined.samples.nodes.len() as u32;
            points.spacing = part.points.spacing;
            points.dropout |= part.points.dropout;
            points.points.extend(&part.points.points);
            points.half_width.extend(&part.points.half_width);
            points
                .neighbors
                .extend(part.points.neighbors.iter().map(|&j| j + point_base));
            let offsets = part.points.offsets.iter().skip(1);
            points.offsets.extend(offsets.map(|&o| o + neighbour_base));
            joined
                .samples
                .nodes
                .extend(part.samples.nodes.iter().map(|node| {
                    let mut node = *node;
                    node.center += point_base;
                    node
                }));
            let owners = part.samples.owner.iter().map(|&o| o + sample_base);
            joined.samples.owner.extend(owners);
            append_node_graph(&mut joined.node_graph, part.node_graph);
            append_node_graph(&mut joined.refined, part.refined);
        }
        if let Some(windows) = windows.filter(|w| !w.is_empty()) {
            let x0 = windows.iter().map(|w| w.0).min().unwrap_or(0);
            let y0 = windows.iter().map(|w| w.1).min().unwrap_or(0);
            let x1 = windows.iter().map(|w| w.2).max().unwrap_or(0);
            let y1 = windows.iter().map(|w| w.3).max().unwrap_or(0);
            let mut grid = Grid {
                width: (x1 - x0) as u32,
                height: (y1 - y0) as u32,
                index: Vec::new(),
                x0,
                y0,
            };
            grid.rebuild(&points.points);
            points.grid = Some(grid);
        }
        joined
    }
}

/// Appends `part`'s nodes, edges and owners to `graph`: nodes and clusters numbered after
/// `graph`'s.
fn append_node_graph(graph: &mut NodeGraph, part: NodeGraph) {
    let node_base = graph.nodes.len() as u32;
    let cluster_base = graph
        .nodes
        .iter()
        .filter_map(|n| n.cluster)
        .max()
        .map_or(0, |c| c + 1);
    graph.nodes.extend(part.nodes.into_iter().map(|mut node| {
        node.cluster = node.cluster.map(|c| c + cluster_base);
        node
    }));
    let edges = part
        .edges
        .iter()
        .map(|&[a, b]| [a + node_base, b + node_base]);
    graph.edges.extend(edges);
    graph
        .owner
        .extend(part.owner.iter().map(|&o| o + node_base));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::{render, Stroke};

    /// The graph as sorted vertex and edge descriptions: equal for equal graphs whatever the order.
    fn canonical(graph: &StrokeGraph) -> (Vec<String>, Vec<String>) {
        let mut vertices: Vec<String> = graph
            .vertices
            .iter()
            .map(|v| format!("{:?} {} {}", v.pos, v.degree, v.width))
            .collect();
        let mut edges: Vec<String> = graph
            .edges
            .iter()
            .map(|e| format!("{:?} {:?}", e.points, e.widths))
            .collect();
        vertices.sort();
        edges.sort();
        (vertices, edges)
    }

    fn circle(center: [f64; 2], radius: f64, width: f64) -> Stroke {
        let n = (radius * 2.0 * std::f64::consts::PI).ceil() as usize;
        let points = (0..=n)
            .map(|i| {
                let t = i as f64 / n as f64 * 2.0 * std::f64::consts::PI;
                [center[0] + radius * t.cos(), center[1] + radius * t.sin()]
            })
            .collect();
        Stroke::new(points, width)
    }

    /// Over 16k ink points, so the driver cuts the page into chunks of components; the same
    /// page traced as one point set gives the same graph (up to the order of vertices and edges):
    /// ARCHITECTURE.md, "Large inputs". Rings with blobs and rings inside (holes that hold
    /// another component), strokes 2 px apart, crossings.
    #[test]
    fn a_large_page_traced_in_chunks_equals_the_page_traced_whole() {
        let mut strokes = Vec::new();
        for row in 0..4 {
            for col in 0..6 {
                let c = [40.0 + 70.0 * col as f64, 40.0 + 70.0 * row as f64];
                strokes.push(circle(c, 26.0, 4.0));
                match (row + col) % 3 {
                    0 => strokes.push(circle(c, 12.0, 4.0)),
                    1 => strokes.push(Stroke::new(vec![c, [c[0] + 3.0, c[1] + 2.0]], 9.0)),
                    _ => {
                        let (s, k) = 30f64.to_radians().sin_cos();
                        let (a, b) = (
                            [c[0] - 12.0 * k, c[1] - 12.0 * s],
                            [c[0] + 12.0 * k, c[1] + 12.0 * s],
                        );
                        strokes.push(Stroke::new(vec![a, b], 3.0));
                        strokes.push(Stroke::new(
                            vec![
                                [c[0] + 12.0 * s, c[1] - 12.0 * k],
                                [c[0] - 12.0 * s, c[1] + 12.0 * k],
                            ],
                            3.0,
                        ));
                    }
                }
            }
        }
        for k in 0..6 {
            let y = 300.0 + 6.0 * k as f64;
            strokes.push(Stroke::new(vec![[20.0, y], [400.0, y]], 3.0));
        }
        let binary = render(&strokes, 440, 350);
        let params = Params::default();
        let points = raster::points(&binary, &params).expect("points");
        assert!(points.len() > CHUNK_POINTS, "{} ink pixels", points.len());
        assert!(!points.dropout);
        let whole = trace_one(points, &params, Recording::Off, None);
        let chunked = mask(binary.view(), &params, Recording::Off).expect("trace");
        assert!(
            raster::pixel_chunks(binary.view(), &params, None, CHUNK_POINTS)
                .expect("chunks")
                .is_some_and(|chunks| chunks.len() > 1)
        );
        assert_eq!(chunked.point_count, whole.point_count);
        assert_eq!(canonical(&chunked.graph), canonical(&whole.graph));
        assert!(
            chunked.graph.cycles() >= 24 + 8,
            "{} cycles",
            chunked.graph.cycles()
        );
    }
}
