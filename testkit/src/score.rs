//! Quality scores of a predicted stroke graph against known centerlines (docs/design.md,
//! "Measuring quality").
//!
//! - [`truth_graph`] turns a case's true strokes into the graph *the ink shows*: strokes split where
//!   they cross, a stroke end whose ink touches another stroke joined to it (a T), short overshooting
//!   tails inside another stroke's ink dropped, junctions closer than one stroke width made one
//!   vertex, closed strokes as loops.
//! - [`score`] compares a prediction with it: centerline precision / recall / F1 at
//!   [`TAUS`], chamfer and Hausdorff distances on samples every 0.5 px; junction, crossing and
//!   endpoint scores on the prediction normalized with a 1 px tolerance; components and cycles.
//! - [`aggregate`] pools the scores of a group of cases.
//! - [`ScoreOptions`] changes the tolerances and where the ink's holes come from, for cases whose
//!   ink is not drawn from their strokes (font outlines with approximate medians); [`score`],
//!   [`truth_graph`] and [`normalize`] use the defaults.
//!
//! Scoring never panics on a broken prediction: edges with bad indices, fewer than two points or
//! non-finite coordinates are left out.

use std::cmp::Ordering;
use std::collections::{BTreeMap, BinaryHeap};

use petgraph::unionfind::UnionFind;
use serde::Serialize;

use crate::synth::{render, Case};
use ridgeline::csr::Csr;
use ridgeline::draw::Stroke;
use ridgeline::geometry::{point_in_polygon, segment_dist};
use ridgeline::mask::{label_components, on_image_edge, Connectivity};
use ridgeline::Binary;
use ridgeline::{dist, Edge, StrokeGraph, Vertex};

/// Distance tolerances (px) at which centerline precision, recall and F1 are reported.
pub const TAUS: [f64; 3] = [1.0, 2.0, 3.0];

/// Crossings at least this steep (degrees) count in [`Scores::crossing_accuracy`]; shallower ones
/// (the 15-degree cases) are reported apart in [`Scores::shallow_crossing_accuracy`].
pub const STEEP_CROSSING: f64 = 22.5;

/// Spacing of the samples along centerlines, px.
const SPACING: f64 = 0.5;

/// The prediction's graph tolerance, px: ends this close to a centerline are joined to it and
/// junctions this close are merged.
const PREDICTION_TOLERANCE: f64 = 1.0;

/// The smallest matching radius for junctions and endpoints, px (the radius is
/// `max(MIN_MATCH_RADIUS, local stroke width)`).
pub const MIN_MATCH_RADIUS: f64 = 3.0;

/// How a case is scored.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ScoreOptions {
    /// Distance tolerances (px) at which centerline precision, recall and F1 are reported.
    /// Default value: [`TAUS`] (1, 2, 3 px); truths only known approximately (font medians a few
    /// px off the center) need wider ones.
    pub taus: [f64; 3],
    /// Whether the holes that decide which cycles the ink shows are those of the case's binary
    /// rather than those of its strokes drawn as [`crate::synth::render`] draws them (before any
    /// dropout). Default value: `false`, right wherever the binary is drawn from the strokes; set
    /// it when the ink comes from elsewhere (filled font outlines).
    pub holes_from_binary: bool,
    /// The smallest radius (px) within which a predicted junction or endpoint matches a true
    /// one (the radius is this or the local stroke width, whichever is larger). Default value:
    /// [`MIN_MATCH_RADIUS`] (3 px); truths whose vertices are only known to a few px (brush tips
    /// a few px wide at the end of approximate medians) need more.
    pub min_match_radius: f64,
    /// Whether the truth reads a loop of a stroke that encloses no hole of the ink (a closed
    /// outline the pen fills: the Hershey Japanese font's triangles at the end of a bar, its
    /// teardrop dots and wedges) as the stroke its ink shows, from the loop's junction to its
    /// farthest point or, for a loop alone, between its two points farthest apart when it is
    /// longer than wide by a width, rather than dropping it (a loop alone becoming a dot).
    /// Default value: `false`. docs/quality.md, "Spurious ends on japanese (issue 31)".
    pub filled_loops_as_strokes: bool,
    /// Whether the truth reads a stroke that turns and comes back over its own ink (a retrace:
    /// the pen runs back along what it drew, as script fonts draw the peaks of `u` and `i` and
    /// the hooks of `r`) as the ink shows it: the stroke ends at the turn, and where it leaves
    /// that ink it goes on from the nearest point of what it drew (a T), rather than as one line
    /// through the turn with no end ([`fold_retraces`]). Default value: `false`.
    /// docs/quality.md, "Session of 2026-12-07, thirteenth".
    pub retraces_as_arms: bool,
}

impl Default for ScoreOptions {
    fn default() -> Self {
        ScoreOptions {
            taus: TAUS,
            holes_from_binary: false,
            min_match_radius: MIN_MATCH_RADIUS,
            filled_loops_as_strokes: false,
            retraces_as_arms: false,
        }
    }
}

/// Scores of one prediction against one case's truth.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Scores {
    /// Case name.
    pub case: String,
    /// Case group (`hard`, `text`, `prints`).
    pub group: String,
    /// Number of true strokes (the denominator of [`Scores::spurs_per_stroke`]).
    pub true_strokes: usize,
    /// Share of predicted centerline samples within each of [`TAUS`] of the truth.
    pub precision: [f64; 3],
    /// Share of true centerline samples within each of [`TAUS`] of the prediction.
    pub recall: [f64; 3],
    /// Harmonic mean of precision and recall at each of [`TAUS`].
    pub f1: [f64; 3],
    /// Mean chamfer distance, px: the mean of both directions' mean nearest-sample distance.
    pub chamfer: f64,
    /// Hausdorff distance, px.
    pub hausdorff: f64,
    /// True vertices of degree 3 or more.
    pub true_junctions: usize,
    /// Predicted vertices of degree 3 or more (after normalization).
    pub predicted_junctions: usize,
    /// Junctions matched one to one within `max(3, local width)`.
    pub junctions_matched: usize,
    /// `junctions_matched / predicted_junctions` (1 when nothing was predicted).
    pub junction_precision: f64,
    /// `junctions_matched / true_junctions` (1 when there is no true junction).
    pub junction_recall: f64,
    /// Every true crossing (degree-4 vertex) with its angle and whether it was found.
    pub crossings: Vec<Crossing>,
    /// Share of true crossings of [`STEEP_CROSSING`] degrees or more found, if there are any.
    pub crossing_accuracy: Option<f64>,
    /// Share of true crossings shallower than [`STEEP_CROSSING`] found, if there are any.
    pub shallow_crossing_accuracy: Option<f64>,
    /// True degree-1 vertices.
    pub true_endpoints: usize,
    /// Predicted degree-1 vertices (after normalization).
    pub predicted_endpoints: usize,
    /// True endpoints matched one to one by a predicted endpoint within `max(3, width)`.
    pub endpoints_found: usize,
    /// `endpoints_found / true_endpoints` (1 when there is no true endpoint).
    pub endpoint_recall: f64,
    /// Predicted endpoints with no true endpoint within `max(3, width)`.
    pub spurious_endpoints: usize,
    /// `spurious_endpoints / true_strokes`.
    pub spurs_per_stroke: f64,
    /// Connected components of the truth graph.
    pub true_components: usize,
    /// Connected components of the normalized prediction.
    pub predicted_components: usize,
    /// Whether the component counts agree.
    pub components_exact: bool,
    /// Independent cycles of the truth graph.
    pub true_cycles: usize,
    /// Independent cycles of the normalized prediction.
    pub predicted_cycles: usize,
    /// Whether the cycle counts agree.
    pub cycles_exact: bool,
    /// Whether the graph is exactly right: every true junction matched one to one by a predicted
    /// junction of the same degree and no predicted junction left over, every true endpoint
    /// matched one to one and no predicted endpoint left over (so no spurious end), and the
    /// component and cycle counts exact.
    pub exactly_right: bool,
    /// Length of the predicted centerlines, px.
    pub centerline_length: f64,
    /// Length of the predicted centerlines over background pixels, px ([`off_ink`]).
    pub off_ink_length: f64,
    /// `off_ink_length / centerline_length` (0 for an empty prediction).
    pub off_ink: f64,
    /// The distance tolerances of `precision`, `recall` and `f1`, px.
    pub taus: [f64; 3],
    /// Whether every true junction is matched by a predicted junction of its degree (part of
    /// [`Scores::exactly_right`]; [`Scores::misses`] reads it). Not serialized: the case's JSON
    /// stays as it was, [`Misses`] carries it.
    #[serde(skip)]
    pub junction_degrees_agree: bool,
}

/// Why a graph is not exactly right ([`Scores::misses`]): each way [`Scores::exactly_right`]
/// can fail, any number of them at once. A graph is exactly right when none holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Misses {
    /// A true junction has no predicted junction matched to it.
    pub missed_junction: bool,
    /// A predicted junction is matched to no true junction.
    pub extra_junction: bool,
    /// A true junction is matched by a predicted junction of another degree.
    pub wrong_degree: bool,
    /// A true end has no predicted end matched to it.
    pub missed_end: bool,
    /// A predicted end is matched to no true end (a spur, or a stroke broken in two).
    pub spurious_end: bool,
    /// The number of independent cycles differs.
    pub wrong_cycles: bool,
    /// The number of components differs.
    pub wrong_components: bool,
}

impl Misses {
    /// The names of the misses, in the order of the fields (the columns of the quality
    /// example's table).
    pub const NAMES: [&'static str; 7] = [
        "missed junction",
        "extra junction",
        "wrong degree",
        "missed end",
        "spurious end",
        "wrong cycles",
        "wrong components",
    ];

    /// The misses as flags in the order of [`Misses::NAMES`].
    pub fn flags(&self) -> [bool; 7] {
        [
            self.missed_junction,
            self.extra_junction,
            self.wrong_degree,
            self.missed_end,
            self.spurious_end,
            self.wrong_cycles,
            self.wrong_components,
        ]
    }

    /// Whether any miss holds (exactly when the graph is not [`Scores::exactly_right`]).
    pub fn any(&self) -> bool {
        self.flags().iter().any(|&f| f)
    }
}

impl Scores {
    /// Why the graph is not exactly right: read from the counts, so it agrees with
    /// [`Scores::exactly_right`] (no miss exactly when it is right).
    pub fn misses(&self) -> Misses {
        // A matched junction of the wrong degree: the degrees disagree though every true
        // junction is matched.
        let all_matched = self.junctions_matched == self.true_junctions;
        Misses {
            missed_junction: self.junctions_matched < self.true_junctions,
            extra_junction: self.predicted_junctions > self.junctions_matched,
            wrong_degree: all_matched && !self.junction_degrees_agree,
            missed_end: self.endpoints_found < self.true_endpoints,
            spurious_end: self.predicted_endpoints > self.endpoints_found,
            wrong_cycles: !self.cycles_exact,
            wrong_components: !self.components_exact,
        }
    }
}

/// The share of a group's cases with each miss ([`Misses`]), pooled by [`miss_shares`].
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MissShares {
    /// Number of cases.
    pub cases: usize,
    /// Share of cases that are not exactly right.
    pub not_exactly_right: f64,
    /// Share of cases with a missed junction.
    pub missed_junction: f64,
    /// Share of cases with an extra junction.
    pub extra_junction: f64,
    /// Share of cases with every junction matched but one of the wrong degree.
    pub wrong_degree: f64,
    /// Share of cases with a missed end.
    pub missed_end: f64,
    /// Share of cases with a spurious end.
    pub spurious_end: f64,
    /// Share of cases with wrong cycles.
    pub wrong_cycles: f64,
    /// Share of cases with wrong components.
    pub wrong_components: f64,
}

impl MissShares {
    /// The shares in the order of [`Misses::NAMES`].
    pub fn shares(&self) -> [f64; 7] {
        [
            self.missed_junction,
            self.extra_junction,
            self.wrong_degree,
            self.missed_end,
            self.spurious_end,
            self.wrong_cycles,
            self.wrong_components,
        ]
    }
}

/// The share of `scores`' cases with each [`Misses`] (all zero for no case).
pub fn miss_shares(scores: &[Scores]) -> MissShares {
    let n = scores.len();
    let misses: Vec<Misses> = scores.iter().map(Scores::misses).collect();
    let share = |f: &dyn Fn(&Misses) -> bool| {
        if n == 0 {
            0.0
        } else {
            misses.iter().filter(|m| f(m)).count() as f64 / n as f64
        }
    };
    MissShares {
        cases: n,
        not_exactly_right: share(&|m| m.any()),
        missed_junction: share(&|m| m.missed_junction),
        extra_junction: share(&|m| m.extra_junction),
        wrong_degree: share(&|m| m.wrong_degree),
        missed_end: share(&|m| m.missed_end),
        spurious_end: share(&|m| m.spurious_end),
        wrong_cycles: share(&|m| m.wrong_cycles),
        wrong_components: share(&|m| m.wrong_components),
    }
}

/// One true crossing and how the prediction did there.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Crossing {
    /// Position of the true degree-4 vertex.
    pub pos: [f64; 2],
    /// Angle between the two strokes through it, degrees in `[0, 90]`.
    pub angle: f64,
    /// Whether the matched predicted vertex has degree 4 or more with no other predicted junction
    /// nearby.
    pub correct: bool,
}

/// Scores of a group of cases, pooled.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct GroupScores {
    /// Number of cases scored.
    pub cases: usize,
    /// Mean precision at each of [`TAUS`].
    pub precision: [f64; 3],
    /// Mean recall at each of [`TAUS`].
    pub recall: [f64; 3],
    /// Mean F1 at each of [`TAUS`].
    pub f1: [f64; 3],
    /// Mean chamfer distance, px.
    pub chamfer: f64,
    /// Mean Hausdorff distance, px.
    pub hausdorff: f64,
    /// Pooled true junctions.
    pub true_junctions: usize,
    /// Pooled predicted junctions.
    pub predicted_junctions: usize,
    /// Pooled matched junctions.
    pub junctions_matched: usize,
    /// Pooled junction precision.
    pub junction_precision: f64,
    /// Pooled junction recall.
    pub junction_recall: f64,
    /// True crossings of [`STEEP_CROSSING`] degrees or more.
    pub crossings: usize,
    /// Of those, found.
    pub crossings_correct: usize,
    /// Pooled accuracy over steep crossings, if there are any.
    pub crossing_accuracy: Option<f64>,
    /// True crossings shallower than [`STEEP_CROSSING`].
    pub shallow_crossings: usize,
    /// Of those, found.
    pub shallow_crossings_correct: usize,
    /// Pooled accuracy over shallow crossings, if there are any.
    pub shallow_crossing_accuracy: Option<f64>,
    /// Pooled true endpoints.
    pub true_endpoints: usize,
    /// Pooled endpoints found.
    pub endpoints_found: usize,
    /// Pooled endpoint recall.
    pub endpoint_recall: f64,
    /// Pooled spurious endpoints.
    pub spurious_endpoints: usize,
    /// Pooled true strokes.
    pub true_strokes: usize,
    /// Spurious endpoints per true stroke, pooled.
    pub spurs_per_stroke: f64,
    /// Share of cases whose component count is exact.
    pub components_exact: f64,
    /// Share of cases whose cycle count is exact.
    pub cycles_exact: f64,
    /// Share of cases whose graph is exactly right ([`Scores::exactly_right`]).
    pub exactly_right: f64,
    /// Pooled length of the predicted centerlines, px.
    pub centerline_length: f64,
    /// Pooled length of the predicted centerlines over background pixels, px.
    pub off_ink_length: f64,
    /// `off_ink_length / centerline_length`, pooled over the cases (0 when nothing was
    /// predicted).
    pub off_ink: f64,
    /// The distance tolerances of `precision`, `recall` and `f1` (those of the first case).
    pub taus: [f64; 3],
}

/// Pools the scores of a group: means of the geometric scores, pooled counts for junctions,
/// crossings, endpoints and spurs, shares of exact components and cycles.
pub fn aggregate(scores: &[Scores]) -> GroupScores {
    let n = scores.len();
    if n == 0 {
        return GroupScores::default();
    }
    let mean = |f: &dyn Fn(&Scores) -> f64| scores.iter().map(f).sum::<f64>() / n as f64;
    let sum = |f: &dyn Fn(&Scores) -> usize| scores.iter().map(f).sum::<usize>();
    let share = |num: usize, den: usize| {
        if den == 0 {
            1.0
        } else {
            num as f64 / den as f64
        }
    };
    let mut g = GroupScores {
        cases: n,
        ..GroupScores::default()
    };
    for k in 0..TAUS.len() {
        g.precision[k] = mean(&|s| s.precision[k]);
        g.recall[k] = mean(&|s| s.recall[k]);
        g.f1[k] = mean(&|s| s.f1[k]);
    }
    g.chamfer = mean(&|s| s.chamfer);
    g.hausdorff = mean(&|s| s.hausdorff);
    g.true_junctions = sum(&|s| s.true_junctions);
    g.predicted_junctions = sum(&|s| s.predicted_junctions);
    g.junctions_matched = sum(&|s| s.junctions_matched);
    g.junction_precision = share(g.junctions_matched, g.predicted_junctions);
    g.junction_recall = share(g.junctions_matched, g.true_junctions);
    for c in scores.iter().flat_map(|s| &s.crossings) {
        if c.angle >= STEEP_CROSSING {
            g.crossings += 1;
            g.crossings_correct += c.correct as usize;
        } else {
            g.shallow_crossings += 1;
            g.shallow_crossings_correct += c.correct as usize;
        }
    }
    g.crossing_accuracy =
        (g.crossings > 0).then(|| g.crossings_correct as f64 / g.crossings as f64);
    g.shallow_crossing_accuracy = (g.shallow_crossings > 0)
        .then(|| g.shallow_crossings_correct as f64 / g.shallow_crossings as f64);
    g.true_endpoints = sum(&|s| s.true_endpoints);
    g.endpoints_found = sum(&|s| s.endpoints_found);
    g.endpoint_recall = share(g.endpoints_found, g.true_endpoints);
    g.spurious_endpoints = sum(&|s| s.spurious_endpoints);
    g.true_strokes = sum(&|s| s.true_strokes);
    g.spurs_per_stroke = if g.true_strokes == 0 {
        0.0
    } else {
        g.spurious_endpoints as f64 / g.true_strokes as f64
    };
    g.components_exact = mean(&|s| s.components_exact as usize as f64);
    g.cycles_exact = mean(&|s| s.cycles_exact as usize as f64);
    g.exactly_right = mean(&|s| s.exactly_right as usize as f64);
    g.centerline_length = scores.iter().map(|s| s.centerline_length).sum();
    g.off_ink_length = scores.iter().map(|s| s.off_ink_length).sum();
    g.off_ink = if g.centerline_length > 0.0 {
        g.off_ink_length / g.centerline_length
    } else {
        0.0
    };
    g.taus = scores[0].taus;
    g
}

// ---------------------------------------------------------------------------------------------
// The truth as the ink shows it

/// The true stroke graph of a case as its ink shows it: stroke polylines split where they cross; a
/// stroke end whose ink (its round cap, rendered as [`crate::synth::render`] does) touches the ink
/// of another stroke, or of a part of its own stroke it does not reach along itself, is joined to
/// the nearest point of that stroke (a T); a short tail past a crossing whose end lies inside the
/// other stroke's ink is dropped; junctions closer than one stroke width are one vertex (two T's at
/// one point make one degree-4 vertex); closed strokes are loops. Degree-2 vertices are dissolved,
/// so every vertex is an end, a junction, a loop anchor or an isolated dot. A loop or a pair of
/// parallel edges around no hole of the ink (a closed stroke too small to leave one, a lens between
/// two strokes that cross twice closely) is not a cycle: the loop becomes a dot, the longer of the
/// parallel edges stays.
///
/// A compact cycle of three or more edges around no hole (three crossings closer together than
/// the ink's width leaves room for, the cells of a grid too small to show) is one vertex: its
/// vertices are merged and its edges dropped.
pub fn truth_graph(case: &Case) -> StrokeGraph {
    truth_graph_with(case, &ScoreOptions::default())
}

/// [`truth_graph`], with the holes taken as `options` says.
pub fn truth_graph_with(case: &Case, options: &ScoreOptions) -> StrokeGraph {
    let holes = case_holes(case, options);
    let mut net = if options.retraces_as_arms {
        Net::from_strokes(&fold_retraces(&case.strokes, &case.binary))
    } else {
        Net::from_strokes(&case.strokes)
    };
    let r_max = net.max_half_width();
    net.split_crossings(None);
    net.drop_tails(r_max);
    net.join_ends(Join::Ink {
        r_max,
        holes: &holes,
    });
    net.join_kisses(r_max, &holes);
    // Merging moves wire ends, so wires that met apart may cross near the merged vertex: split
    // them there and merge again, until no crossing is left farther than the prediction's
    // tolerance from a vertex (those the normalization merges into the vertex, so the truth
    // still normalizes to itself), a few rounds at most.
    for _ in 0..8 {
        net.merge_junctions(&|a, b| a.max(b));
        net.dissolve();
        net.drop_filled_cycles(&holes, options.filled_loops_as_strokes);
        let mut changed = false;
        while net.collapse_filled_cycles(&holes) {
            net.drop_filled_cycles(&holes, options.filled_loops_as_strokes);
            changed = true;
        }
        if !net.split_crossings(Some(PREDICTION_TOLERANCE)) && !changed {
            break;
        }
    }
    net.into_stroke_graph(case.binary.width, case.binary.height)
}

/// The strokes with each stretch where a stroke comes back over its own ink left out
/// ([`ScoreOptions::retraces_as_arms`]). A sample of a stroke (every [`SPACING`] px) is on a
/// retrace when an earlier sample of the same stroke lies within a quarter of the wider of their
/// widths (it runs along the earlier sample's centerline; the legs of a hook a width apart make a
/// wedge, whose ink shows a turn, not an arm), with ink all along the segment between them, and the stroke ran
/// farther than that distance plus a width between them (not the stroke's own neighbourhood). A
/// run of such samples is a retrace when the stroke, between the run's first sample and the
/// earlier one nearest it, stays within a width of that first sample and comes nearer to the
/// earlier sample all the way back from its turn: it turned within its own ink, as a hairpin does
/// (a small loop closed on itself comes right back, then leaves again); and when the run ends at
/// least a width from the turn (the legs of a corner wider than 15 degrees run that close for
/// less, and a blob's outline stays within it). A loop whose crossing looks the same goes farther (a loop around a hole is
/// wider than a width), and so does a closed stroke meeting its start. The stroke then ends at
/// its turn (the sample of that stretch farthest from the run's start), the run is dropped, and
/// the rest of the stroke, unless it lies all within half a width of what is kept, becomes a
/// stroke of its own starting at the nearest point of what is kept: the T the ink shows. Closed
/// strokes are left as they are.
pub fn fold_retraces(strokes: &[Stroke], binary: &Binary) -> Vec<Stroke> {
    let mut out = Vec::with_capacity(strokes.len());
    for stroke in strokes {
        let n = stroke.points.len().min(stroke.widths.len());
        let closed = n >= 4 && dist(stroke.points[0], stroke.points[n - 1]) <= 1e-9;
        let usable = n >= 2
            && stroke.points[..n].iter().all(|&p| finite(p))
            && stroke.widths[..n].iter().all(|w| w.is_finite());
        if closed || !usable {
            out.push(stroke.clone());
            continue;
        }
        let (points, widths, arcs) = densify(&stroke.points[..n], &stroke.widths[..n]);
        let on_ink = |a: [f64; 2], b: [f64; 2]| {
            let steps = (dist(a, b) / SPACING).ceil().max(1.0) as usize;
            (0..=steps).all(|k| {
                let p = lerp(a, b, k as f64 / steps as f64);
                binary.get(p[0].floor() as i64, p[1].floor() as i64)
            })
        };
        // The nearest earlier sample each sample retraces, if any.
        let matched: Vec<Option<usize>> = (0..points.len())
            .map(|i| {
                (0..i)
                    .filter(|&j| {
                        let (d, w) = (dist(points[i], points[j]), widths[i].max(widths[j]));
                        d <= w / 4.0 && arcs[i] - arcs[j] >= d + w && on_ink(points[i], points[j])
                    })
                    .min_by(|&a, &b| {
                        dist(points[i], points[a]).total_cmp(&dist(points[i], points[b]))
                    })
            })
            .collect();
        // Runs of retracing samples whose stroke turned within a width of their start: (the
        // turn, the run's first and last sample).
        let mut runs: Vec<(usize, usize, usize)> = Vec::new();
        let mut i = 0;
        while i < points.len() {
            let Some(j) = matched[i] else {
                i += 1;
                continue;
            };
            let mut end = i;
            while end + 1 < points.len() && matched[end + 1].is_some() {
                end += 1;
            }
            let far = |k: &usize| dist(points[*k], points[i]);
            let turn = (j..i).max_by(|a, b| far(a).total_cmp(&far(b))).unwrap_or(j);
            let width = widths[i].max(widths[j]);
            // From the turn back to the run the stroke comes nearer to where it passed: a hairpin
            // (a small loop closed on itself comes right back there first, then leaves again).
            let back = |k: usize| dist(points[k], points[j]);
            let nearest_back = (turn..=i).map(back).fold(f64::INFINITY, f64::min);
            let local = far(&turn) <= width && back(i) - nearest_back <= width / 4.0;
            let along = dist(points[end], points[turn]) >= width;
            if local && along && runs.last().is_none_or(|r| r.2 < turn) {
                runs.push((turn, i, end));
            }
            i = end + 1;
        }
        if runs.is_empty() {
            out.push(stroke.clone());
            continue;
        }
        // The kept pieces: the stroke up to the first turn, then after each run up to the next
        // turn, each later piece starting at the nearest point of the pieces kept before it.
        let piece = |from: usize, to: usize| Stroke {
            points: points[from..=to].to_vec(),
            widths: widths[from..=to].to_vec(),
        };
        let mut kept: Vec<Stroke> = vec![piece(0, runs[0].0)];
        for (k, &(_, _, end)) in runs.iter().enumerate() {
            let from = end + 1;
            let to = runs.get(k + 1).map_or(points.len() - 1, |r| r.0);
            if from >= points.len() || to <= from {
                continue;
            }
            let nearest = |p: [f64; 2]| {
                kept.iter()
                    .flat_map(|s| s.points.iter().zip(&s.widths))
                    .min_by(|a, b| dist(*a.0, p).total_cmp(&dist(*b.0, p)))
                    .map(|(&q, &w)| (q, w))
            };
            let covered = (from..=to).all(|m| {
                nearest(points[m]).is_some_and(|(q, _)| dist(q, points[m]) <= widths[m] / 2.0)
            });
            if covered {
                continue;
            }
            let mut rest = piece(from, to);
            if let Some((q, w)) = nearest(points[from]) {
                rest.points.insert(0, q);
                rest.widths.insert(0, w);
            }
            kept.push(rest);
        }
        out.extend(kept);
    }
    out
}

/// The prediction as a graph with a 1 px tolerance: ends within 1 px of a centerline joined to it,
/// crossing polylines split, junctions within 1 px merged, degree-2 vertices dissolved. As for the
/// truth, a join that would close a cycle around no hole of the case's ink is not made (so the
/// truth normalizes to itself).
pub fn normalize(case: &Case, predicted: &StrokeGraph) -> StrokeGraph {
    normalize_with(case, predicted, &ScoreOptions::default())
}

/// [`normalize`], with the holes taken as `options` says.
pub fn normalize_with(case: &Case, predicted: &StrokeGraph, options: &ScoreOptions) -> StrokeGraph {
    let holes = case_holes(case, options);
    let mut net = Net::from_graph(predicted);
    net.split_crossings(None);
    net.join_ends(Join::Distance {
        tol: PREDICTION_TOLERANCE,
        holes: &holes,
    });
    net.merge_junctions(&|_, _| PREDICTION_TOLERANCE);
    net.dissolve();
    net.into_stroke_graph(predicted.width, predicted.height)
}

// ---------------------------------------------------------------------------------------------
// Scoring

/// Scores `predicted` against `truth` (normally [`truth_graph`] of `case`).
pub fn score(case: &Case, truth: &StrokeGraph, predicted: &StrokeGraph) -> Scores {
    score_with(case, truth, predicted, &ScoreOptions::default())
}

/// [`score`] with the tolerances and holes of `options` (`truth` normally [`truth_graph_with`]
/// of `case` and the same options).
pub fn score_with(
    case: &Case,
    truth: &StrokeGraph,
    predicted: &StrokeGraph,
    options: &ScoreOptions,
) -> Scores {
    let mut s = Scores {
        case: case.name.clone(),
        group: case.group.clone(),
        true_strokes: case.strokes.len(),
        taus: options.taus,
        ..Scores::default()
    };
    geometry(case, truth, predicted, &mut s);
    let ink = off_ink(predicted, &case.binary);
    s.centerline_length = ink.length;
    s.off_ink_length = ink.off;
    s.off_ink = ink.share();

    let norm = normalize_with(case, predicted, options);
    let radius = |w: f64| w.max(options.min_match_radius);

    // Junctions: one-to-one matching, nearest pairs first.
    let true_j: Vec<usize> = truth.junctions().collect();
    let pred_j: Vec<usize> = norm.junctions().collect();
    let matches = match_vertices(truth, &true_j, &norm, &pred_j, &radius);
    s.true_junctions = true_j.len();
    s.predicted_junctions = pred_j.len();
    s.junctions_matched = matches.iter().filter(|m| m.is_some()).count();
    s.junction_precision = ratio(s.junctions_matched, s.predicted_junctions);
    s.junction_recall = ratio(s.junctions_matched, s.true_junctions);
    let junction_degrees_agree = true_j
        .iter()
        .zip(&matches)
        .all(|(&t, m)| m.is_some_and(|p| norm.vertices[p].degree == truth.vertices[t].degree));

    // Crossings: the matched vertex must carry all four arms, alone.
    for (k, &t) in true_j.iter().enumerate() {
        if truth.vertices[t].degree != 4 {
            continue;
        }
        let pos = truth.vertices[t].pos;
        let r = radius(truth.vertices[t].width);
        let correct = match matches[k] {
            Some(p) => {
                norm.vertices[p].degree >= 4
                    && pred_j
                        .iter()
                        .all(|&q| q == p || dist(norm.vertices[q].pos, pos) > r)
            }
            None => false,
        };
        s.crossings.push(Crossing {
            pos,
            angle: crossing_angle(truth, t),
            correct,
        });
    }
    let accuracy = |steep: bool| {
        let chosen: Vec<&Crossing> = s
            .crossings
            .iter()
            .filter(|c| (c.angle >= STEEP_CROSSING) == steep)
            .collect();
        (!chosen.is_empty())
            .then(|| chosen.iter().filter(|c| c.correct).count() as f64 / chosen.len() as f64)
    };
    s.crossing_accuracy = accuracy(true);
    s.shallow_crossing_accuracy = accuracy(false);

    // Endpoints.
    let true_e: Vec<usize> = truth.endpoints().collect();
    let pred_e: Vec<usize> = norm.endpoints().collect();
    let matches = match_vertices(truth, &true_e, &norm, &pred_e, &radius);
    s.true_endpoints = true_e.len();
    s.predicted_endpoints = pred_e.len();
    s.endpoints_found = matches.iter().filter(|m| m.is_some()).count();
    s.endpoint_recall = ratio(s.endpoints_found, s.true_endpoints);
    s.spurious_endpoints = pred_e
        .iter()
        .filter(|&&p| {
            let pos = norm.vertices[p].pos;
            !true_e
                .iter()
                .any(|&t| dist(truth.vertices[t].pos, pos) <= radius(truth.vertices[t].width))
        })
        .count();
    s.spurs_per_stroke = if s.true_strokes == 0 {
        0.0
    } else {
        s.spurious_endpoints as f64 / s.true_strokes as f64
    };

    s.true_components = truth.components();
    s.predicted_components = norm.components();
    s.components_exact = s.true_components == s.predicted_components;
    s.true_cycles = truth.cycles();
    s.predicted_cycles = norm.cycles();
    s.cycles_exact = s.true_cycles == s.predicted_cycles;
    s.junction_degrees_agree = junction_degrees_agree;
    s.exactly_right = junction_degrees_agree
        && s.predicted_junctions == s.true_junctions
        && s.endpoints_found == s.true_endpoints
        && s.predicted_endpoints == s.true_endpoints
        && s.components_exact
        && s.cycles_exact;
    s
}

/// How much of a graph's centerline lies over background pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct OffInk {
    /// Length of the usable edges' polylines, px.
    pub length: f64,
    /// Of that, the length over background pixels (or outside the image), px.
    pub off: f64,
}

impl OffInk {
    /// `off / length`, 0 when there is no centerline.
    pub fn share(&self) -> f64 {
        if self.length > 0.0 {
            self.off / self.length
        } else {
            0.0
        }
    }
}

/// The length of `graph`'s centerlines lying over background pixels of `binary`: every polyline
/// is cut into pieces at most `SPACING` (0.5 px) long, and a piece is off the ink when the
/// pixel under its midpoint is background or outside the image (pixel `(c, r)` covers
/// `[c, c + 1) x [r, r + 1)`). Edges with bad indices or non-finite points are left out, as in
/// [`score`].
pub fn off_ink(graph: &StrokeGraph, binary: &Binary) -> OffInk {
    let mut out = OffInk::default();
    for e in graph.edges.iter().filter(|e| usable_edge(graph, e)) {
        for w in e.points.windows(2) {
            let len = dist(w[0], w[1]);
            let n = (len / SPACING).ceil().max(1.0) as usize;
            let piece = len / n as f64;
            for k in 0..n {
                let p = lerp(w[0], w[1], (k as f64 + 0.5) / n as f64);
                out.length += piece;
                if !binary.get(p[0].floor() as i64, p[1].floor() as i64) {
                    out.off += piece;
                }
            }
        }
    }
    out
}

fn ratio(num: usize, den: usize) -> f64 {
    if den == 0 {
        1.0
    } else {
        num as f64 / den as f64
    }
}

/// Centerline precision, recall, F1, chamfer and Hausdorff on samples every [`SPACING`] px, each
/// sample's distance taken to the other side's centerline itself (its nearest segment), not to
/// that side's nearest sample: two identical lines sampled from different starts would otherwise
/// be up to a quarter of the spacing apart, a floor of about 0.06-0.125 px on the chamfer that
/// favours outputs on the truth's own half-pixel grid (docs/quality.md, "Distances to the
/// centerline, not to its samples").
fn geometry(case: &Case, truth: &StrokeGraph, predicted: &StrokeGraph, s: &mut Scores) {
    let true_samples = centerline_samples(truth);
    let pred_samples = centerline_samples(predicted);
    // An empty side is as far as the image is wide: finite, so means stay meaningful.
    let far = (case.binary.width as f64)
        .hypot(case.binary.height as f64)
        .max(1.0);
    let nearest_all = |from: &CenterlineSamples, to: &CenterlineSamples| -> Vec<f64> {
        let grid = PointGrid::new(&to.pos, 2.0);
        let mut near = Vec::new();
        from.pos
            .iter()
            .map(|&p| match grid.nearest(&to.pos, p) {
                None => far,
                // Every point of a segment lies within `SPACING` of a sample carrying that
                // segment (the start of its piece), so the segment nearest `p` carries a sample
                // within `d + SPACING`.
                Some((_, d)) => {
                    near.clear();
                    grid.within(&to.pos, p, d + SPACING + 1e-9, &mut near);
                    near.iter()
                        .map(|&i| {
                            let (a, b) = to.segment[i as usize];
                            segment_dist(p, a, b)
                        })
                        .fold(d, f64::min)
                }
            })
            .collect()
    };
    let d_pred = nearest_all(&pred_samples, &true_samples);
    let d_true = nearest_all(&true_samples, &pred_samples);
    let taus = s.taus;
    for (k, &tau) in taus.iter().enumerate() {
        let within = |d: &[f64]| {
            if d.is_empty() {
                None
            } else {
                Some(d.iter().filter(|&&x| x <= tau).count() as f64 / d.len() as f64)
            }
        };
        // An empty prediction claims nothing wrong (precision 1) and finds nothing.
        let precision = within(&d_pred).unwrap_or(1.0);
        let recall = within(&d_true).unwrap_or(1.0);
        s.precision[k] = precision;
        s.recall[k] = recall;
        s.f1[k] = if precision + recall > 0.0 {
            2.0 * precision * recall / (precision + recall)
        } else {
            0.0
        };
    }
    let mean = |d: &[f64]| {
        if d.is_empty() {
            far
        } else {
            d.iter().sum::<f64>() / d.len() as f64
        }
    };
    let max = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
    s.chamfer = match (d_pred.is_empty(), d_true.is_empty()) {
        (true, true) => 0.0,
        _ => 0.5 * (mean(&d_pred) + mean(&d_true)),
    };
    s.hausdorff = match (d_pred.is_empty(), d_true.is_empty()) {
        (true, true) => 0.0,
        (true, false) | (false, true) => far,
        (false, false) => max(&d_pred).max(max(&d_true)),
    };
}

/// Samples of a centerline and the segment each lies on.
struct CenterlineSamples {
    pos: Vec<[f64; 2]>,
    /// The segment of its edge that each sample lies on (an isolated vertex: a point).
    segment: Vec<([f64; 2], [f64; 2])>,
}

/// Samples every [`SPACING`] px along every usable edge, plus isolated vertices.
fn centerline_samples(graph: &StrokeGraph) -> CenterlineSamples {
    let mut out = CenterlineSamples {
        pos: Vec::new(),
        segment: Vec::new(),
    };
    for e in graph.edges.iter().filter(|e| usable_edge(graph, e)) {
        for w in e.points.windows(2) {
            let n = (dist(w[0], w[1]) / SPACING).ceil().max(1.0) as usize;
            for k in 0..n {
                out.pos.push(lerp(w[0], w[1], k as f64 / n as f64));
                out.segment.push((w[0], w[1]));
            }
        }
        let last = e.points[e.points.len() - 1];
        out.pos.push(last);
        out.segment.push((last, last));
    }
    let mut degree = vec![0usize; graph.vertices.len()];
    for e in graph.edges.iter().filter(|e| usable_edge(graph, e)) {
        degree[e.from] += 1;
        degree[e.to] += 1;
    }
    for (v, vertex) in graph.vertices.iter().enumerate() {
        if degree[v] == 0 && finite(vertex.pos) {
            out.pos.push(vertex.pos);
            out.segment.push((vertex.pos, vertex.pos));
        }
    }
    out
}

fn usable_edge(graph: &StrokeGraph, e: &Edge) -> bool {
    e.from < graph.vertices.len()
        && e.to < graph.vertices.len()
        && e.points.len() >= 2
        && e.points.iter().all(|&p| finite(p))
}

fn finite(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// One-to-one matching of `true_ids` to `pred_ids` within `radius(true width)`, nearest pairs
/// first; returns the predicted partner of each true vertex.
pub fn match_vertices(
    truth: &StrokeGraph,
    true_ids: &[usize],
    pred: &StrokeGraph,
    pred_ids: &[usize],
    radius: &dyn Fn(f64) -> f64,
) -> Vec<Option<usize>> {
    let mut pairs = Vec::new();
    for (i, &t) in true_ids.iter().enumerate() {
        let (pos, r) = (truth.vertices[t].pos, radius(truth.vertices[t].width));
        for (j, &p) in pred_ids.iter().enumerate() {
            let d = dist(pos, pred.vertices[p].pos);
            if d <= r {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut partner = vec![None; true_ids.len()];
    let mut taken = vec![false; pred_ids.len()];
    for (_, i, j) in pairs {
        if partner[i].is_none() && !taken[j] {
            partner[i] = Some(pred_ids[j]);
            taken[j] = true;
        }
    }
    partner
}

/// Angle (degrees, `[0, 90]`) between the two lines through a degree-4 vertex: its arms are paired
/// into the two most nearly straight continuations.
fn crossing_angle(graph: &StrokeGraph, v: usize) -> f64 {
    let arms = arm_directions(graph, v);
    if arms.len() != 4 {
        return 90.0;
    }
    let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
    let pairings = [[0, 1, 2, 3], [0, 2, 1, 3], [0, 3, 1, 2]];
    let best = pairings
        .iter()
        .max_by(|p, q| {
            let straight =
                |k: &[usize; 4]| -dot(arms[k[0]], arms[k[1]]) - dot(arms[k[2]], arms[k[3]]);
            straight(p).total_cmp(&straight(q))
        })
        .copied()
        .unwrap_or([0, 1, 2, 3]);
    let line = |a: [f64; 2], b: [f64; 2]| unit([a[0] - b[0], a[1] - b[1]]);
    let (l1, l2) = (
        line(arms[best[0]], arms[best[1]]),
        line(arms[best[2]], arms[best[3]]),
    );
    dot(l1, l2).abs().min(1.0).acos().to_degrees()
}

/// Unit directions of the arms leaving vertex `v`, each measured to the point one stroke width
/// (at least 2 px) along its edge.
fn arm_directions(graph: &StrokeGraph, v: usize) -> Vec<[f64; 2]> {
    let pos = graph.vertices[v].pos;
    let reach = graph.vertices[v].width.max(2.0);
    let toward = |points: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut last = pos;
        for p in points {
            last = p;
            if dist(p, pos) >= reach {
                break;
            }
        }
        unit([last[0] - pos[0], last[1] - pos[1]])
    };
    let mut arms = Vec::new();
    for e in graph.edges.iter().filter(|e| usable_edge(graph, e)) {
        if e.from == v {
            arms.push(toward(&mut e.points.iter().copied()));
        }
        if e.to == v {
            arms.push(toward(&mut e.points.iter().rev().copied()));
        }
    }
    arms
}

fn unit(d: [f64; 2]) -> [f64; 2] {
    let n = d[0].hypot(d[1]);
    if n > 0.0 {
        [d[0] / n, d[1] / n]
    } else {
        [1.0, 0.0]
    }
}

fn lerp(a: [f64; 2], b: [f64; 2], t: f64) -> [f64; 2] {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

// ---------------------------------------------------------------------------------------------
// Nearest-sample queries: a uniform grid in CSR form

/// Points bucketed in square cells: radius queries and nearest-point queries by growing rings.
struct PointGrid {
    origin: [f64; 2],
    cell: f64,
    nx: i64,
    ny: i64,
    /// The points of each cell, row-major.
    cells: Csr<u32>,
}

impl PointGrid {
    fn new(points: &[[f64; 2]], cell: f64) -> Self {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points.iter().filter(|p| finite(**p)) {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            return PointGrid {
                origin: [0.0; 2],
                cell,
                nx: 0,
                ny: 0,
                cells: Csr::default(),
            };
        }
        let nx = ((hi[0] - lo[0]) / cell).floor() as i64 + 1;
        let ny = ((hi[1] - lo[1]) / cell).floor() as i64 + 1;
        let mut grid = PointGrid {
            origin: lo,
            cell,
            nx,
            ny,
            cells: Csr::default(),
        };
        let cells: Vec<Option<usize>> = points.iter().map(|&p| grid.cell_index(p)).collect();
        grid.cells = Csr::build((nx * ny) as usize, |sink| {
            for (i, c) in cells.iter().enumerate() {
                if let Some(c) = *c {
                    sink.push(c, i as u32);
                }
            }
        });
        grid
    }

    fn cell_of(&self, p: [f64; 2]) -> (i64, i64) {
        (
            ((p[0] - self.origin[0]) / self.cell).floor() as i64,
            ((p[1] - self.origin[1]) / self.cell).floor() as i64,
        )
    }

    fn cell_index(&self, p: [f64; 2]) -> Option<usize> {
        if !finite(p) {
            return None;
        }
        let (cx, cy) = self.cell_of(p);
        (cx >= 0 && cy >= 0 && cx < self.nx && cy < self.ny).then(|| (cy * self.nx + cx) as usize)
    }

    fn bucket(&self, cx: i64, cy: i64) -> &[u32] {
        if cx < 0 || cy < 0 || cx >= self.nx || cy >= self.ny {
            return &[];
        }
        self.cells.row((cy * self.nx + cx) as usize)
    }

    /// Indices of the points within `r` of `p` (exact test), appended to `out`.
    fn within(&self, points: &[[f64; 2]], p: [f64; 2], r: f64, out: &mut Vec<u32>) {
        let (x0, y0) = self.cell_of([p[0] - r, p[1] - r]);
        let (x1, y1) = self.cell_of([p[0] + r, p[1] + r]);
        for cy in y0.max(0)..=y1.min(self.ny - 1) {
            for cx in x0.max(0)..=x1.min(self.nx - 1) {
                out.extend(
                    self.bucket(cx, cy)
                        .iter()
                        .filter(|&&i| dist(points[i as usize], p) <= r),
                );
            }
        }
    }

    /// The nearest point and its distance.
    fn nearest(&self, points: &[[f64; 2]], p: [f64; 2]) -> Option<(u32, f64)> {
        if self.cells.values().is_empty() || !finite(p) {
            return None;
        }
        let (qx, qy) = self.cell_of(p);
        let mut best: Option<(u32, f64)> = None;
        // Rings beyond this one cannot hold any cell of the grid.
        let last_ring = [qx, self.nx - 1 - qx, qy, self.ny - 1 - qy]
            .iter()
            .map(|d| d.abs())
            .max()
            .unwrap_or(0)
            + self.nx.max(self.ny);
        for ring in 0..=last_ring {
            let mut visit = |cx: i64, cy: i64| {
                for &i in self.bucket(cx, cy) {
                    let d = dist(points[i as usize], p);
                    if best.is_none_or(|(_, b)| d < b) {
                        best = Some((i, d));
                    }
                }
            };
            if ring == 0 {
                visit(qx, qy);
            } else {
                for cx in qx - ring..=qx + ring {
                    visit(cx, qy - ring);
                    visit(cx, qy + ring);
                }
                for cy in qy - ring + 1..qy + ring {
                    visit(qx - ring, cy);
                    visit(qx + ring, cy);
                }
            }
            // Every point in ring + 1 or beyond is at least `ring * cell` away.
            if let Some((_, b)) = best {
                if b <= ring as f64 * self.cell {
                    break;
                }
            }
        }
        best
    }
}

// ---------------------------------------------------------------------------------------------
// The working graph both the truth and the normalized prediction are built in

/// A centerline polyline between two vertices of a [`Net`].
#[derive(Clone, Debug)]
struct Wire {
    from: usize,
    to: usize,
    points: Vec<[f64; 2]>,
    widths: Vec<f64>,
    /// Arc position of each point along the source polyline (a true stroke or a predicted edge).
    arcs: Vec<f64>,
    /// Index of the source polyline.
    source: usize,
    alive: bool,
}

impl Wire {
    fn length(&self) -> f64 {
        self.points.windows(2).map(|w| dist(w[0], w[1])).sum()
    }

    fn reverse(&mut self) {
        std::mem::swap(&mut self.from, &mut self.to);
        self.points.reverse();
        self.widths.reverse();
        self.arcs.reverse();
    }
}

#[derive(Clone, Debug)]
struct Node {
    pos: [f64; 2],
    width: f64,
    /// Kept when it has no edge (a dot, or an isolated predicted vertex).
    keep_isolated: bool,
    alive: bool,
}

/// Vertices and wires, mutable: split, joined, merged and dissolved until it is the graph to score.
#[derive(Clone, Debug, Default)]
struct Net {
    nodes: Vec<Node>,
    wires: Vec<Wire>,
    /// Length of each source polyline if it is closed (arc distances wrap around), else `None`.
    closed_length: Vec<Option<f64>>,
}

/// The holes of a case's ink as drawn, before any dropout: the truth is what the strokes show.
/// With [`ScoreOptions::holes_from_binary`], the holes of the binary itself.
fn case_holes(case: &Case, options: &ScoreOptions) -> Holes {
    let max_width = case
        .strokes
        .iter()
        .flat_map(|s| s.widths.iter().copied())
        .filter(|w| w.is_finite())
        .fold(0.0, f64::max);
    if options.holes_from_binary {
        return Holes::new(&case.binary, max_width);
    }
    Holes::new(
        &render(&case.strokes, case.binary.width, case.binary.height),
        max_width,
    )
}

/// How free ends are joined to nearby centerlines.
#[derive(Clone, Copy)]
enum Join<'a> {
    /// The truth: an end joins when its round cap's pixels touch (8-neighbour) pixels of another
    /// stroke's ink, unless the join would close a cycle around no hole of the ink. `r_max` is the
    /// largest half-width of any stroke.
    Ink { r_max: f64, holes: &'a Holes },
    /// The prediction: an end joins a centerline within `tol`, unless that would close a cycle
    /// around no hole of the ink.
    Distance { tol: f64, holes: &'a Holes },
}

/// How a wire end follows its vertex when the vertex moves.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Follow {
    /// Add the vertex position as a new end point (a T's stem reaching the bar's centerline).
    Extend,
    /// Replace the end point (junctions merged into their centroid).
    Snap,
}

impl Net {
    fn add_node(&mut self, pos: [f64; 2], width: f64, keep_isolated: bool) -> usize {
        self.nodes.push(Node {
            pos,
            width,
            keep_isolated,
            alive: true,
        });
        self.nodes.len() - 1
    }

    fn from_strokes(strokes: &[Stroke]) -> Net {
        let mut net = Net::default();
        for (source, stroke) in strokes.iter().enumerate() {
            let n = stroke.points.len().min(stroke.widths.len());
            let mut points = Vec::with_capacity(n);
            let mut widths = Vec::with_capacity(n);
            for k in 0..n {
                let (p, w) = (stroke.points[k], stroke.widths[k]);
                if finite(p) && w.is_finite() && points.last().is_none_or(|&q| dist(p, q) > 1e-9) {
                    points.push(p);
                    widths.push(w.max(0.0));
                }
            }
            // A closed stroke repeats its first point at the end (a triangle has four points).
            let closed = points.len() >= 4 && dist(points[0], points[points.len() - 1]) <= 1e-9;
            net.add_polyline(source, &points, &widths, closed);
        }
        net
    }

    fn add_polyline(&mut self, source: usize, points: &[[f64; 2]], widths: &[f64], closed: bool) {
        if points.is_empty() {
            self.closed_length.push(None);
            return;
        }
        if points.len() == 1 {
            self.add_node(points[0], widths[0], true);
            self.closed_length.push(None);
            return;
        }
        let (points, widths, arcs) = densify(points, widths);
        let length = arcs[arcs.len() - 1];
        self.closed_length.push(closed.then_some(length));
        let from = self.add_node(points[0], widths[0], false);
        let to = if closed {
            from
        } else {
            self.add_node(points[points.len() - 1], widths[widths.len() - 1], false)
        };
        self.wires.push(Wire {
            from,
            to,
            points,
            widths,
            arcs,
            source,
            alive: true,
        });
    }

    fn from_graph(graph: &StrokeGraph) -> Net {
        let mut net = Net::default();
        for v in &graph.vertices {
            let width = if v.width.is_finite() {
                v.width.max(0.0)
            } else {
                0.0
            };
            let pos = if finite(v.pos) { v.pos } else { [0.0, 0.0] };
            net.add_node(pos, width, true);
        }
        for (source, e) in graph.edges.iter().enumerate() {
            net.closed_length.push(None);
            if !usable_edge(graph, e) {
                continue;
            }
            let widths: Vec<f64> = (0..e.points.len())
                .map(|k| {
                    e.widths
                        .get(k)
                        .copied()
                        .filter(|w| w.is_finite())
                        .unwrap_or(0.0)
                })
                .collect();
            let (points, widths, arcs) = densify(&e.points, &widths);
            net.wires.push(Wire {
                from: e.from,
                to: e.to,
                points,
                widths,
                arcs,
                source,
                alive: true,
            });
        }
        net
    }

    fn max_half_width(&self) -> f64 {
        let wires = self.wires.iter().flat_map(|w| w.widths.iter().copied());
        wires
            .chain(self.nodes.iter().map(|n| n.width))
            .fold(0.0, f64::max)
            / 2.0
    }

    fn degrees(&self) -> Vec<usize> {
        let mut degree = vec![0; self.nodes.len()];
        for w in self.wires.iter().filter(|w| w.alive) {
            degree[w.from] += 1;
            degree[w.to] += 1;
        }
        degree
    }

    /// Splits wires where they cross one another or themselves (proper crossings away from wire
    /// ends; a wire end on another wire is a touch, left to [`Net::join_ends`]). With
    /// `away_from`, crossings that close to a live vertex are left alone. Returns whether any
    /// crossing was split.
    fn split_crossings(&mut self, away_from: Option<f64>) -> bool {
        let live: Vec<[f64; 2]> = self
            .nodes
            .iter()
            .map(|n| if n.alive { n.pos } else { [f64::NAN; 2] })
            .collect();
        let node_grid = PointGrid::new(&live, 2.0);
        // Wires are densified to segments at most SPACING long, so two that cross have midpoints
        // within SPACING. Ends moved by merges and joins can leave longer end segments: a long
        // segment is also tested against every segment whose midpoint lies within half its
        // length plus half the longest one.
        let mut segments = Vec::new();
        let mut mids = Vec::new();
        let mut lengths = Vec::new();
        for (w, wire) in self.wires.iter().enumerate().filter(|(_, w)| w.alive) {
            for i in 0..wire.points.len() - 1 {
                segments.push((w, i));
                mids.push(lerp(wire.points[i], wire.points[i + 1], 0.5));
                lengths.push(dist(wire.points[i], wire.points[i + 1]));
            }
        }
        let short_reach = SPACING + 1e-6;
        let longest = lengths.iter().copied().fold(0.0, f64::max);
        let reach = |a: usize| {
            if lengths[a] <= SPACING + 1e-9 {
                short_reach
            } else {
                (lengths[a] + longest) / 2.0 + 1e-6
            }
        };
        let grid = PointGrid::new(&mids, 2.0);
        // Per wire: (segment, t, node) breakpoints.
        let mut hits: BTreeMap<usize, Vec<(usize, f64, usize)>> = BTreeMap::new();
        // Loop anchors a crossing passes through, with the crossing's vertex.
        let mut anchors: Vec<(usize, usize)> = Vec::new();
        // Crossings found so far per pair of wires: a crossing through a polyline vertex is
        // found on up to four pairs of segments and must make one vertex.
        let mut found: BTreeMap<(usize, usize), Vec<[f64; 2]>> = BTreeMap::new();
        let mut near = Vec::new();
        let mut pairs = Vec::new();
        for a in 0..segments.len() {
            near.clear();
            grid.within(&mids, mids[a], reach(a), &mut near);
            near.sort_unstable();
            pairs.clear();
            for &b in &near {
                let b = b as usize;
                if b > a {
                    pairs.push((a, b));
                } else if b < a && dist(mids[a], mids[b]) > reach(b) {
                    // A short segment the long one reaches but that does not reach back.
                    pairs.push((b, a));
                }
            }
            for &(a, b) in &pairs {
                let ((wa, i), (wb, j)) = (segments[a], segments[b]);
                let (pa, pb) = (&self.wires[wa].points, &self.wires[wb].points);
                let is_loop = |w: usize| self.wires[w].from == self.wires[w].to;
                // Neighbouring segments of one wire share a point; so do a loop's first and last.
                if wa == wb
                    && (i.abs_diff(j) <= 1
                        || (is_loop(wa) && i.min(j) == 0 && i.max(j) == pa.len() - 2))
                {
                    continue;
                }
                let Some((t, u, point)) = intersect(pa[i], pa[i + 1], pb[j], pb[j + 1]) else {
                    continue;
                };
                // A crossing at the end of an open wire is a touch, left to `join_ends`; at the
                // anchor of a loop it is a crossing through the anchor, which then becomes the
                // crossing vertex.
                let at_end = |k: usize, s: f64, points: &[[f64; 2]]| {
                    (k == 0 && s <= 1e-9) || (k == points.len() - 2 && s >= 1.0 - 1e-9)
                };
                let (end_a, end_b) = (at_end(i, t, pa), at_end(j, u, pb));
                if (end_a && !is_loop(wa)) || (end_b && !is_loop(wb)) {
                    continue;
                }
                if let Some(tol) = away_from {
                    let near_vertex = node_grid
                        .nearest(&live, point)
                        .is_some_and(|(_, d)| d <= tol);
                    if near_vertex {
                        continue;
                    }
                }
                let seen = found.entry((wa, wb)).or_default();
                if seen.iter().any(|&q| dist(q, point) <= 1e-7) {
                    continue;
                }
                seen.push(point);
                let width_at = |wire: &Wire, k: usize, s: f64| {
                    wire.widths[k] + s * (wire.widths[k + 1] - wire.widths[k])
                };
                let width = width_at(&self.wires[wa], i, t).max(width_at(&self.wires[wb], j, u));
                let node = self.add_node(point, width, false);
                for (w, k, s, end) in [(wa, i, t, end_a), (wb, j, u, end_b)] {
                    if end {
                        anchors.push((self.wires[w].from, node));
                    } else {
                        hits.entry(w).or_default().push((k, s, node));
                    }
                }
            }
        }
        let found_any = !hits.is_empty() || !anchors.is_empty();
        for (w, mut breaks) in hits {
            breaks.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            let wire = self.wires[w].clone();
            self.wires[w].alive = false;
            let last = wire.points.len() - 2;
            let mut cuts = vec![(0, 0.0, wire.from)];
            cuts.extend(breaks);
            cuts.push((last, 1.0, wire.to));
            for pair in cuts.windows(2) {
                let piece = cut(&wire, (pair[0].0, pair[0].1), (pair[1].0, pair[1].1));
                self.wires.push(Wire {
                    from: pair[0].2,
                    to: pair[1].2,
                    ..piece
                });
            }
        }
        if !anchors.is_empty() {
            let mut sets = UnionFind::<usize>::new(self.nodes.len());
            for &(anchor, node) in &anchors {
                sets.union(anchor, node);
            }
            let mut anchored = vec![false; self.nodes.len()];
            for &(_, node) in &anchors {
                anchored[node] = true;
            }
            self.merge(&sets, &anchored, Follow::Snap, None);
        }
        found_any
    }

    /// Drops the tail of a stroke that runs a little past a crossing and ends inside the crossed
    /// stroke's ink: the ink shows a T there, not a crossing and an end.
    fn drop_tails(&mut self, r_max: f64) {
        let degree = self.degrees();
        let samples = Samples::new(self);
        let mut near = Vec::new();
        let mut dropped = Vec::new();
        for (w, wire) in self.wires.iter().enumerate().filter(|(_, w)| w.alive) {
            for free_at_start in [true, false] {
                let (end, other) = if free_at_start {
                    (wire.from, wire.to)
                } else {
                    (wire.to, wire.from)
                };
                if end == other
                    || degree[end] != 1
                    || degree[other] < 3
                    || wire.length() > 2.0 * r_max + 2.0
                {
                    continue;
                }
                let k = if free_at_start {
                    0
                } else {
                    wire.points.len() - 1
                };
                let (p, r_p, arc_p) = (wire.points[k], wire.widths[k] / 2.0, wire.arcs[k]);
                near.clear();
                samples.grid.within(&samples.pos, p, r_max + 0.5, &mut near);
                let inside = near.iter().any(|&s| {
                    let s = s as usize;
                    let Some((sw, si)) = samples.wire_of(s) else {
                        return false;
                    };
                    let other_wire = &self.wires[sw];
                    let d = dist(samples.pos[s], p);
                    let r_s = samples.width[s] / 2.0;
                    // The ink is that of the stroke crossed (a wire at the crossing): an end
                    // inside a third stroke's ink is a T on that stroke, left to `join_ends`.
                    let crossed = other_wire.from == other || other_wire.to == other;
                    crossed
                        && d <= r_s + 0.5
                        && self.distinct_parts(
                            (wire.source, arc_p, r_p),
                            (other_wire.source, other_wire.arcs[si], r_s),
                            d,
                        )
                });
                if inside {
                    dropped.push((w, end));
                }
            }
        }
        for (w, end) in dropped {
            self.wires[w].alive = false;
            self.nodes[end].alive = false;
        }
    }

    /// Whether two points lie on different strokes, or on parts of one stroke that do not reach
    /// each other along it.
    fn distinct_parts(&self, a: (usize, f64, f64), b: (usize, f64, f64), d: f64) -> bool {
        if a.0 != b.0 {
            return true;
        }
        let mut along = (a.1 - b.1).abs();
        if let Some(Some(length)) = self.closed_length.get(a.0) {
            along = along.min(length - along);
        }
        along > d + a.2 + b.2 + 2.0
    }

    /// Joins free ends (degree 1) to the nearest centerline they touch that they do not already
    /// reach along the graph.
    fn join_ends(&mut self, rule: Join) {
        let degree = self.degrees();
        let samples = Samples::new(self);
        let mut search = Dijkstra::new(samples.pos.len());
        let mut near = Vec::new();
        let mut joins: Vec<(usize, usize)> = Vec::new();
        for end in 0..self.nodes.len() {
            if !self.nodes[end].alive || degree[end] != 1 {
                continue;
            }
            let p = self.nodes[end].pos;
            let r_p = self.nodes[end].width / 2.0;
            let (reach, margin_max) = match rule {
                Join::Ink { r_max, .. } => (r_p + r_max + 1.5, r_p + r_max + 2.0),
                Join::Distance { tol, .. } => (tol, 2.0 * tol + 1.0),
            };
            near.clear();
            samples.grid.within(&samples.pos, p, reach, &mut near);
            if near.is_empty() {
                continue;
            }
            // Far enough to find every cycle that could fail to leave a hole in the ink.
            let limit = match rule {
                Join::Ink { holes, .. } | Join::Distance { holes, .. } => holes.cycle_reach,
            };
            search.run(&samples, end, (reach + margin_max + 1.0).max(limit));
            // "Far" samples: reached along the graph only the long way round, or not at all.
            let mut far: Vec<(f64, usize)> = near
                .iter()
                .map(|&s| (dist(samples.pos[s as usize], p), s as usize))
                .filter(|&(d, s)| {
                    let g = search.distance(s);
                    match rule {
                        // Joining would close a cycle: the ink must show it as a hole.
                        Join::Ink { holes, .. } => {
                            !g.is_finite()
                                || (g > d + r_p + samples.width[s] / 2.0 + 2.0
                                    && holes.inside(&search.path(&samples, s)))
                        }
                        Join::Distance { tol, holes } => {
                            !g.is_finite()
                                || (g > d + 2.0 * tol + 1.0
                                    && holes.inside(&search.path(&samples, s)))
                        }
                    }
                })
                .collect();
            // A stroke's centerline is a better target than another free end at the same place
            // (two ends meeting on a stem make a K, not a corner beside the stem).
            let free_end = |s: usize| s < degree.len() && degree[s] == 1;
            far.sort_by(|a, b| {
                (free_end(a.1), a.0)
                    .partial_cmp(&(free_end(b.1), b.0))
                    .unwrap_or(Ordering::Equal)
                    .then(a.1.cmp(&b.1))
            });
            let Some(&(_, target)) = far.first() else {
                continue;
            };
            let d = dist(samples.pos[target], p);
            let touches = match rule {
                Join::Ink { .. } => {
                    // The end's own ink: its cap, or where the cap is too small to hold a pixel
                    // center (a 1 px stroke ending between pixel centers), the pixels the
                    // renderer drew for its last sample step.
                    let back = samples
                        .links
                        .row(end)
                        .first()
                        .map(|&s| samples.pos[s as usize]);
                    ink_touches(p, back, r_p, &far, &samples)
                }
                Join::Distance { tol, .. } => d <= tol,
            };
            if touches {
                joins.push((end, target));
            }
        }
        if let Join::Ink { holes, .. } = rule {
            self.drop_closing_pairs(&mut joins, &samples, holes);
        }
        if joins.is_empty() {
            return;
        }
        // Targets inside wires become new vertices; then each end is united with its target.
        let mut requests: Vec<(usize, usize)> = joins
            .iter()
            .filter_map(|&(_, t)| samples.wire_of(t))
            .collect();
        requests.sort_unstable();
        requests.dedup();
        let split_nodes = self.split_wires(&requests);
        let mut sets = UnionFind::<usize>::new(self.nodes.len());
        let mut anchored = vec![true; self.nodes.len()];
        for &(end, target) in &joins {
            anchored[end] = false;
            let target_node = match samples.wire_of(target) {
                Some(key) => split_nodes[&key],
                None => target,
            };
            sets.union(end, target_node);
        }
        self.merge(&sets, &anchored, Follow::Extend, None);
    }

    /// Of two `joins` (end, target sample) by the two ends of one wire to the same wire (or the
    /// same node), the farther is dropped when the two together would close a cycle around no
    /// hole of the ink: each end was searched for before the other joined, so neither saw the
    /// cycle (an arm a width long leaving a stroke: its foot lies on the stroke, and its cap's
    /// ink touches the stroke's ink, so both ends joined the stroke and the arm became a loop).
    fn drop_closing_pairs(
        &self,
        joins: &mut Vec<(usize, usize)>,
        samples: &Samples,
        holes: &Holes,
    ) {
        let target_of = |end: usize| joins.iter().find(|j| j.0 == end).map(|j| j.1);
        let mut dropped = Vec::new();
        for &(end, target) in joins.iter() {
            let Some(wire) = self
                .wires
                .iter()
                .find(|w| w.alive && w.from != w.to && (w.from == end || w.to == end))
            else {
                continue;
            };
            let other = if wire.from == end { wire.to } else { wire.from };
            let Some(other_target) = target_of(other) else {
                continue;
            };
            // The cycle: this wire from `end` to `other`, then along the targets' wire back.
            let mut cycle: Vec<[f64; 2]> = wire.points.clone();
            if wire.from != end {
                cycle.reverse();
            }
            match (samples.wire_of(other_target), samples.wire_of(target)) {
                (Some((wa, ia)), Some((wb, ib))) if wa == wb => {
                    let points = &self.wires[wa].points;
                    if ia <= ib {
                        cycle.extend_from_slice(&points[ia..=ib]);
                    } else {
                        cycle.extend(points[ib..=ia].iter().rev());
                    }
                }
                (None, None) if other_target == target => {
                    cycle.push(samples.pos[target]);
                }
                _ => continue,
            }
            if holes.inside(&cycle) {
                continue;
            }
            // The farther end stays free when its centerline ends beyond the other stroke's
            // ink (by half a pixel), as a tail past a crossed stroke stays ([`Net::drop_tails`]):
            // then the ink shows an arm; nearer, a bump of the stroke's edge.
            let d = |e: usize, t: usize| dist(self.nodes[e].pos, samples.pos[t]);
            if (d(end, target), end) > (d(other, other_target), other)
                && d(end, target) > samples.width[target] / 2.0 + 0.5
            {
                dropped.push(end);
            }
        }
        joins.retain(|j| !dropped.contains(&j.0));
    }

    /// Joins strokes whose inks touch where neither of them ends or crosses the other (a script
    /// loop closing on the next letter, a stroke grazing another): the ink shows one junction
    /// there. A pair of wire points on distinct parts whose round ink disks touch as
    /// [`crate::synth::render`] draws them is a candidate when the graph does not join them, or
    /// joins them only the long way round around a hole of the ink (so a shallow crossing's or a
    /// sharp corner's arms, which share ink up to the vertex, are not). Nearest first, a
    /// candidate farther than 1.5 widths from every one taken is taken; both wires are split
    /// there and the two points merged into one vertex.
    fn join_kisses(&mut self, r_max: f64, holes: &Holes) {
        let samples = Samples::new(self);
        // Which samples the graph connects at all (a pair in two components touches across).
        let mut parts = UnionFind::<usize>::new(samples.pos.len());
        for v in 0..samples.pos.len() {
            for &u in samples.links.row(v) {
                parts.union(v, u as usize);
            }
        }
        let mut search = Dijkstra::new(samples.pos.len());
        let mut near = Vec::new();
        let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
        for s in self.nodes.len()..samples.pos.len() {
            let Some((ws, is)) = samples.wire_of(s) else {
                continue;
            };
            let (p, r_p) = (samples.pos[s], samples.width[s] / 2.0);
            let arc_p = self.wires[ws].arcs[is];
            near.clear();
            samples
                .grid
                .within(&samples.pos, p, r_p + r_max + 1.5, &mut near);
            let mut touching: Vec<(f64, usize)> = near
                .iter()
                .map(|&q| q as usize)
                .filter(|&q| q > s)
                .filter_map(|q| {
                    let (wq, iq) = samples.wire_of(q)?;
                    let d = dist(samples.pos[q], p);
                    let r_q = samples.width[q] / 2.0;
                    let wire_q = &self.wires[wq];
                    (d <= r_p + r_q + 1.5
                        && self.distinct_parts(
                            (self.wires[ws].source, arc_p, r_p),
                            (wire_q.source, wire_q.arcs[iq], r_q),
                            d,
                        ))
                    .then_some((d, q))
                })
                .collect();
            if touching.is_empty() {
                continue;
            }
            search.run(&samples, s, (2.0 * r_max + 4.0).max(holes.cycle_reach));
            // A pair connected beyond the search's reach (the arms of a shallow crossing share
            // ink far out) needs the whole way round to tell whether it encloses a hole.
            let beyond = touching
                .iter()
                .any(|&(_, q)| !search.distance(q).is_finite() && parts.equiv(q, s));
            if beyond {
                search.run(&samples, s, f64::INFINITY);
            }
            touching.retain(|&(d, q)| {
                let g = search.distance(q);
                let r_q = samples.width[q] / 2.0;
                (!g.is_finite()
                    || (g > d + r_p + r_q + 2.0 && holes.inside(&search.path(&samples, q))))
                    && ink_touches(p, None, r_p, &[(d, q)], &samples)
            });
            candidates.extend(touching.into_iter().map(|(d, q)| (d, s, q)));
        }
        if candidates.is_empty() {
            return;
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut taken: Vec<(usize, usize)> = Vec::new();
        for &(_, s, q) in &candidates {
            let spacing = 1.5 * samples.width[s].max(samples.width[q]);
            let clear = taken.iter().all(|&(a, b)| {
                [a, b].iter().all(|&t| {
                    dist(samples.pos[t], samples.pos[s]) > spacing
                        && dist(samples.pos[t], samples.pos[q]) > spacing
                })
            });
            if clear {
                taken.push((s, q));
            }
        }
        let mut requests: Vec<(usize, usize)> = taken
            .iter()
            .flat_map(|&(s, q)| [s, q])
            .filter_map(|t| samples.wire_of(t))
            .collect();
        requests.sort_unstable();
        requests.dedup();
        let split_nodes = self.split_wires(&requests);
        let mut sets = UnionFind::<usize>::new(self.nodes.len());
        for &(s, q) in &taken {
            if let (Some(a), Some(b)) = (samples.wire_of(s), samples.wire_of(q)) {
                sets.union(split_nodes[&a], split_nodes[&b]);
            }
        }
        self.merge(&sets, &vec![true; self.nodes.len()], Follow::Snap, None);
    }

    /// Splits wires at the given (wire, point index) places; returns the vertex at each place.
    fn split_wires(&mut self, requests: &[(usize, usize)]) -> BTreeMap<(usize, usize), usize> {
        let mut at = BTreeMap::new();
        let mut by_wire: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &(w, i) in requests {
            by_wire.entry(w).or_default().push(i);
        }
        for (w, idx) in by_wire {
            let wire = self.wires[w].clone();
            let last = wire.points.len() - 1;
            let mut cuts = vec![(0, wire.from)];
            for i in idx {
                let node = if i == 0 {
                    wire.from
                } else if i == last {
                    wire.to
                } else {
                    self.add_node(wire.points[i], wire.widths[i], false)
                };
                at.insert((w, i), node);
                if i != 0 && i != last {
                    cuts.push((i, node));
                }
            }
            cuts.push((last, wire.to));
            if cuts.len() == 2 {
                continue;
            }
            self.wires[w].alive = false;
            for pair in cuts.windows(2) {
                let (a, b) = (pair[0].0, pair[1].0);
                self.wires.push(Wire {
                    from: pair[0].1,
                    to: pair[1].1,
                    points: wire.points[a..=b].to_vec(),
                    widths: wire.widths[a..=b].to_vec(),
                    arcs: wire.arcs[a..=b].to_vec(),
                    source: wire.source,
                    alive: true,
                });
            }
        }
        at
    }

    /// Merges junctions (degree 3 or more) closer than `radius(width_a, width_b)` into their
    /// centroid, dropping the short bridges between them.
    fn merge_junctions(&mut self, radius: &dyn Fn(f64, f64) -> f64) {
        let degree = self.degrees();
        let junctions: Vec<usize> = (0..self.nodes.len())
            .filter(|&v| self.nodes[v].alive && degree[v] >= 3)
            .collect();
        let pos: Vec<[f64; 2]> = junctions.iter().map(|&v| self.nodes[v].pos).collect();
        let max_width = junctions
            .iter()
            .map(|&v| self.nodes[v].width)
            .fold(0.0, f64::max);
        let reach = radius(max_width, max_width);
        let grid = PointGrid::new(&pos, reach.max(1.0));
        let mut sets = UnionFind::<usize>::new(self.nodes.len());
        let mut near = Vec::new();
        let mut any = false;
        for (a, &v) in junctions.iter().enumerate() {
            near.clear();
            grid.within(&pos, pos[a], reach, &mut near);
            for &b in &near {
                let u = junctions[b as usize];
                if u != v
                    && dist(pos[a], pos[b as usize])
                        <= radius(self.nodes[v].width, self.nodes[u].width)
                {
                    sets.union(u, v);
                    any = true;
                }
            }
        }
        if any {
            self.merge(
                &sets,
                &vec![true; self.nodes.len()],
                Follow::Snap,
                Some(2.0 * reach + 1.0),
            );
        }
    }

    /// Replaces each set of vertices by one at the mean of its `anchored` members (of all members
    /// when none is anchored); wires follow. With `drop_bridges`, wires between two members of one
    /// set no longer than that are dropped.
    fn merge(
        &mut self,
        sets: &UnionFind<usize>,
        anchored: &[bool],
        follow: Follow,
        drop_bridges: Option<f64>,
    ) {
        let n = self.nodes.len();
        let root_of = smallest_members(sets, n);
        let mut sum = vec![([0.0, 0.0], 0usize, [0.0, 0.0], 0usize, 0.0f64, false); n];
        for v in (0..n).filter(|&v| self.nodes[v].alive) {
            let root = root_of[v];
            let entry = &mut sum[root];
            let p = self.nodes[v].pos;
            entry.0 = [entry.0[0] + p[0], entry.0[1] + p[1]];
            entry.1 += 1;
            if anchored[v] {
                entry.2 = [entry.2[0] + p[0], entry.2[1] + p[1]];
                entry.3 += 1;
            }
            entry.4 = entry.4.max(self.nodes[v].width);
            entry.5 |= self.nodes[v].keep_isolated;
        }
        for (v, &(all, count, anchor, anchors, width, keep)) in sum.iter().enumerate() {
            if !self.nodes[v].alive {
                continue;
            }
            if root_of[v] != v {
                self.nodes[v].alive = false;
                continue;
            }
            let pos = if anchors > 0 {
                [anchor[0] / anchors as f64, anchor[1] / anchors as f64]
            } else {
                [all[0] / count as f64, all[1] / count as f64]
            };
            self.nodes[v] = Node {
                pos,
                width,
                keep_isolated: keep,
                alive: true,
            };
        }
        for wire in self.wires.iter_mut().filter(|w| w.alive) {
            let (from, to) = (root_of[wire.from], root_of[wire.to]);
            if let Some(limit) = drop_bridges {
                if from == to && wire.from != wire.to && wire.length() <= limit {
                    wire.alive = false;
                    continue;
                }
            }
            wire.from = from;
            wire.to = to;
            let (start, end) = (self.nodes[from].pos, self.nodes[to].pos);
            attach(wire, start, true, follow);
            attach(wire, end, false, follow);
        }
    }

    /// Joins the two wires at every vertex of degree 2 into one (closed chains end as a loop at
    /// one vertex), and removes vertices left without wires unless they are dots.
    fn dissolve(&mut self) {
        loop {
            let mut incident: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
            for (w, wire) in self.wires.iter().enumerate().filter(|(_, w)| w.alive) {
                incident[wire.from].push(w);
                incident[wire.to].push(w);
            }
            let mut touched = vec![false; self.wires.len()];
            let mut changed = false;
            for (v, ends) in incident.iter().enumerate() {
                if ends.len() != 2 || ends[0] == ends[1] || touched[ends[0]] || touched[ends[1]] {
                    continue;
                }
                let (a, b) = (ends[0], ends[1]);
                touched[a] = true;
                touched[b] = true;
                let mut first = self.wires[a].clone();
                let mut second = self.wires[b].clone();
                if first.to != v {
                    first.reverse();
                }
                if second.from != v {
                    second.reverse();
                }
                first.points.extend_from_slice(&second.points[1..]);
                first.widths.extend_from_slice(&second.widths[1..]);
                first.arcs.extend_from_slice(&second.arcs[1..]);
                first.to = second.to;
                self.wires[a] = first;
                self.wires[b].alive = false;
                self.nodes[v].alive = false;
                changed = true;
            }
            if !changed {
                break;
            }
        }
        let degree = self.degrees();
        for (v, node) in self.nodes.iter_mut().enumerate() {
            if degree[v] == 0 && !node.keep_isolated {
                node.alive = false;
            }
        }
    }

    /// Removes the cycles of one or two edges that enclose no hole of the ink: a loop alone becomes
    /// a dot at its centroid, a loop at a junction is dropped, of two edges between the same
    /// vertices the shorter is dropped. With `loops_as_strokes`
    /// ([`ScoreOptions::filled_loops_as_strokes`]) a loop that makes a stroke of its ink
    /// ([`Net::filled_loop_as_stroke`]) becomes that stroke instead.
    fn drop_filled_cycles(&mut self, holes: &Holes, loops_as_strokes: bool) {
        loop {
            let degree = self.degrees();
            let mut changed = false;
            let mut between: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
            for w in 0..self.wires.len() {
                let wire = &self.wires[w];
                if !wire.alive {
                    continue;
                }
                if wire.from != wire.to {
                    between
                        .entry((wire.from.min(wire.to), wire.from.max(wire.to)))
                        .or_default()
                        .push(w);
                    continue;
                }
                if holes.inside(&wire.points) {
                    continue;
                }
                let v = wire.from;
                if loops_as_strokes {
                    if let Some((a, b)) = self.filled_loop_as_stroke(w, &degree) {
                        self.loop_to_stroke(w, a, b);
                        changed = true;
                        continue;
                    }
                }
                if degree[v] == 2 {
                    let n = wire.points.len() as f64;
                    let sum = wire
                        .points
                        .iter()
                        .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
                    let width = wire.widths.iter().copied().fold(0.0, f64::max);
                    let node = &mut self.nodes[v];
                    node.pos = [sum[0] / n, sum[1] / n];
                    node.width = width;
                    node.keep_isolated = true;
                }
                self.wires[w].alive = false;
                changed = true;
            }
            for wires in between.values().filter(|w| w.len() >= 2) {
                let mut by_length: Vec<(f64, usize)> =
                    wires.iter().map(|&w| (self.wires[w].length(), w)).collect();
                by_length.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                // The shortest against the next: a lens without a hole is one stroke.
                let (a, b) = (by_length[0].1, by_length[1].1);
                let mut ring = self.wires[a].points.clone();
                let other = &self.wires[b];
                if other.from == self.wires[a].to {
                    ring.extend_from_slice(&other.points);
                } else {
                    ring.extend(other.points.iter().rev());
                }
                if !holes.inside(&ring) {
                    self.wires[a].alive = false;
                    changed = true;
                }
            }
            if !changed {
                return;
            }
            self.dissolve();
        }
    }

    /// The stroke the ink of the filled loop `w` (a closed outline the pen fills, around no
    /// hole) shows, as its two ends, if it shows one. A loop alone is a stroke between its two
    /// points farthest apart when its outline is longer than it is across by more than the
    /// stroke's width (the ink longer than wide by a width; a round dot stays a dot). A loop
    /// at a junction (a triangle at the end of a bar) is a stroke from the junction to the
    /// loop's point farthest from it, when that point's cap clears the ink of the junction's
    /// other strokes (else the cap touches them, as the joined ends of [`Net::join_ends`] do).
    fn filled_loop_as_stroke(&self, w: usize, degree: &[usize]) -> Option<([f64; 2], [f64; 2])> {
        let wire = &self.wires[w];
        let v = wire.from;
        let width = wire.widths.iter().copied().fold(0.0, f64::max);
        let points = &wire.points;
        let far_from = |q: [f64; 2]| {
            points
                .iter()
                .copied()
                .max_by(|a, b| dist(*a, q).total_cmp(&dist(*b, q)))
        };
        if degree[v] == 2 {
            let n = points.len() as f64;
            let sum = points
                .iter()
                .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
            let a = far_from([sum[0] / n, sum[1] / n])?;
            let b = far_from(a)?;
            let length = dist(a, b);
            if length <= 0.0 {
                return None;
            }
            let normal = [-(b[1] - a[1]) / length, (b[0] - a[0]) / length];
            let across = |p: &[f64; 2]| (p[0] - a[0]) * normal[0] + (p[1] - a[1]) * normal[1];
            let breadth = points.iter().map(across).fold(f64::NEG_INFINITY, f64::max)
                - points.iter().map(across).fold(f64::INFINITY, f64::min);
            return (length > breadth + width).then_some((a, b));
        }
        let a = self.nodes[v].pos;
        let b = far_from(a)?;
        let clear = self.wires.iter().enumerate().all(|(o, other)| {
            o == w
                || !other.alive
                || (other.from != v && other.to != v)
                || other
                    .points
                    .iter()
                    .zip(&other.widths)
                    .all(|(&q, &q_width)| dist(q, b) > (q_width + width) / 2.0)
        });
        (clear && dist(a, b) > width / 2.0).then_some((a, b))
    }

    /// Replaces the loop `w` by a straight wire from its vertex, moved to `a`, to a new end at `b`
    /// (sampled every half pixel, the loop's widest width all along).
    fn loop_to_stroke(&mut self, w: usize, a: [f64; 2], b: [f64; 2]) {
        let width = self.wires[w].widths.iter().copied().fold(0.0, f64::max);
        let v = self.wires[w].from;
        self.nodes[v].pos = a;
        let end = self.add_node(b, width, false);
        let length = dist(a, b);
        let steps = (length / 0.5).ceil().max(1.0) as usize;
        let points: Vec<[f64; 2]> = (0..=steps)
            .map(|i| {
                let t = i as f64 / steps as f64;
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
            })
            .collect();
        let wire = &mut self.wires[w];
        wire.to = end;
        wire.arcs = points.iter().map(|&p| dist(a, p)).collect();
        wire.widths = vec![width; points.len()];
        wire.points = points;
    }

    /// Collapses compact cycles of three or more wires that enclose no hole of the ink (the ink
    /// shows one blob there, with all the cycle's outer arms leaving it): for each wire, shortest
    /// first, the shortest other way between its ends closes the cycle tested; the cycle's
    /// vertices are merged into their centroid and its wires dropped. Only cycles up to twice
    /// [`Holes::cycle_reach`] long are looked for (a filled polygon's perimeter is at most about
    /// that: a triangle whose inradius is half the width has one of 5.2 widths). Returns whether
    /// anything changed; shorter cycles (loops, lenses) are [`Net::drop_filled_cycles`]'s.
    fn collapse_filled_cycles(&mut self, holes: &Holes) -> bool {
        let limit = 2.0 * holes.cycle_reach;
        let n = self.nodes.len();
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (w, wire) in self.wires.iter().enumerate().filter(|(_, w)| w.alive) {
            if wire.from != wire.to {
                incident[wire.from].push(w);
                incident[wire.to].push(w);
            }
        }
        let lengths: Vec<f64> = self.wires.iter().map(Wire::length).collect();
        let mut order: Vec<usize> = (0..self.wires.len())
            .filter(|&w| {
                let wire = &self.wires[w];
                wire.alive && wire.from != wire.to && lengths[w] < limit
            })
            .collect();
        order.sort_by(|&a, &b| lengths[a].total_cmp(&lengths[b]).then(a.cmp(&b)));
        let mut consumed = vec![false; self.wires.len()];
        let mut sets = UnionFind::<usize>::new(n);
        let mut any = false;
        let mut distance = vec![f64::INFINITY; n];
        let mut via: Vec<Option<usize>> = vec![None; n];
        let mut touched: Vec<usize> = Vec::new();
        for &w in &order {
            if consumed[w] {
                continue;
            }
            let (source, target) = (self.wires[w].from, self.wires[w].to);
            // Shortest path from `target` back to `source` over the other live wires.
            for &t in &touched {
                distance[t] = f64::INFINITY;
                via[t] = None;
            }
            touched.clear();
            let budget = limit - lengths[w];
            let mut heap = BinaryHeap::new();
            distance[target] = 0.0;
            touched.push(target);
            heap.push(Reached(0.0, target));
            while let Some(Reached(d, v)) = heap.pop() {
                if d > distance[v] || v == source {
                    continue;
                }
                for &u in &incident[v] {
                    if u == w || consumed[u] {
                        continue;
                    }
                    let wire = &self.wires[u];
                    let next_node = if wire.from == v { wire.to } else { wire.from };
                    let next = d + lengths[u];
                    if next < distance[next_node] && next <= budget {
                        if distance[next_node].is_infinite() {
                            touched.push(next_node);
                        }
                        distance[next_node] = next;
                        via[next_node] = Some(u);
                        heap.push(Reached(next, next_node));
                    }
                }
            }
            if distance[source].is_infinite() {
                continue;
            }
            // The cycle: this wire from source to target, then the path back to the source.
            let mut cycle = vec![w];
            let mut ring = self.wires[w].points.clone();
            let mut path = Vec::new();
            let mut v = source;
            while let Some(u) = via[v] {
                path.push(u);
                let wire = &self.wires[u];
                v = if wire.from == v { wire.to } else { wire.from };
            }
            // `path` runs from the source back to the target; walk it from the target.
            let mut at = target;
            for &u in path.iter().rev() {
                let wire = &self.wires[u];
                if wire.from == at {
                    ring.extend_from_slice(&wire.points[1..]);
                    at = wire.to;
                } else {
                    ring.extend(wire.points.iter().rev().skip(1));
                    at = wire.from;
                }
                cycle.push(u);
            }
            if cycle.len() < 3 || holes.inside(&ring) {
                continue;
            }
            // Only a compact cycle is a blob: every point within 1.5 widths of its vertices'
            // centroid (a long thin cycle around no hole is two passes along one stroke, which
            // one vertex would not show either, so it is left as it is).
            let mut members: Vec<usize> = cycle
                .iter()
                .flat_map(|&u| [self.wires[u].from, self.wires[u].to])
                .collect();
            members.sort_unstable();
            members.dedup();
            let corners: Vec<[f64; 2]> = members.iter().map(|&v| self.nodes[v].pos).collect();
            let centroid = corners.iter().fold([0.0, 0.0], |a, p| {
                [
                    a[0] + p[0] / corners.len() as f64,
                    a[1] + p[1] / corners.len() as f64,
                ]
            });
            let width = cycle
                .iter()
                .flat_map(|&u| self.wires[u].widths.iter().copied())
                .fold(0.0, f64::max);
            if ring.iter().any(|&p| dist(p, centroid) > 1.5 * width) {
                continue;
            }
            for &u in &cycle {
                consumed[u] = true;
                sets.union(self.wires[u].from, self.wires[u].to);
            }
            any = true;
        }
        if !any {
            return false;
        }
        for (w, wire) in self.wires.iter_mut().enumerate() {
            if consumed[w] {
                wire.alive = false;
            }
        }
        self.merge(&sets, &vec![true; n], Follow::Snap, None);
        self.dissolve();
        true
    }

    fn into_stroke_graph(self, width: u32, height: u32) -> StrokeGraph {
        let degree = self.degrees();
        let mut index = vec![usize::MAX; self.nodes.len()];
        let mut vertices = Vec::new();
        for (v, node) in self.nodes.iter().enumerate() {
            if node.alive {
                index[v] = vertices.len();
                vertices.push(Vertex {
                    pos: node.pos,
                    degree: degree[v],
                    width: node.width,
                });
            }
        }
        let edges = self
            .wires
            .into_iter()
            .filter(|w| w.alive)
            .map(|mut w| {
                // Ends sit exactly on their vertices (crossing points are computed once per pair
                // of segments, so the second wire's end can differ by rounding).
                let last = w.points.len() - 1;
                w.points[0] = self.nodes[w.from].pos;
                w.points[last] = self.nodes[w.to].pos;
                let directions = tangents(&w.points);
                Edge {
                    from: index[w.from],
                    to: index[w.to],
                    points: w.points,
                    widths: w.widths,
                    directions,
                }
            })
            .collect();
        StrokeGraph {
            width,
            height,
            vertices,
            edges,
        }
    }
}

/// Makes a wire end at `pos`: by adding it as a new end point or by moving the end point.
fn attach(wire: &mut Wire, pos: [f64; 2], at_start: bool, follow: Follow) {
    let k = if at_start { 0 } else { wire.points.len() - 1 };
    if dist(wire.points[k], pos) <= 1e-9 {
        wire.points[k] = pos;
        return;
    }
    match follow {
        Follow::Snap => wire.points[k] = pos,
        Follow::Extend if at_start => {
            wire.points.insert(0, pos);
            wire.widths.insert(0, wire.widths[0]);
            wire.arcs.insert(0, wire.arcs[0]);
        }
        Follow::Extend => {
            wire.points.push(pos);
            wire.widths.push(wire.widths[k]);
            wire.arcs.push(wire.arcs[k]);
        }
    }
}

/// Unit tangents by central differences.
fn tangents(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i.saturating_sub(1)], points[(i + 1).min(n - 1)]);
            unit([b[0] - a[0], b[1] - a[1]])
        })
        .collect()
}

/// A polyline resampled so no segment is longer than [`SPACING`], with widths and arc positions.
fn densify(points: &[[f64; 2]], widths: &[f64]) -> (Vec<[f64; 2]>, Vec<f64>, Vec<f64>) {
    let mut out = (Vec::new(), Vec::new(), Vec::new());
    let mut arc = 0.0;
    for i in 0..points.len() - 1 {
        let (a, b) = (points[i], points[i + 1]);
        let len = dist(a, b);
        let n = (len / SPACING).ceil().max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.0.push(lerp(a, b, t));
            out.1.push(widths[i] + t * (widths[i + 1] - widths[i]));
            out.2.push(arc + t * len);
        }
        arc += len;
    }
    out.0.push(points[points.len() - 1]);
    out.1.push(widths[widths.len() - 1]);
    out.2.push(arc);
    out
}

/// The part of a wire between two (segment, t) places, `a` before `b`.
fn cut(wire: &Wire, a: (usize, f64), b: (usize, f64)) -> Wire {
    let at = |(k, t): (usize, f64)| {
        let s = |v: &[f64]| v[k] + t * (v[k + 1] - v[k]);
        (
            lerp(wire.points[k], wire.points[k + 1], t),
            s(&wire.widths),
            s(&wire.arcs),
        )
    };
    let mut piece = Wire {
        points: vec![],
        widths: vec![],
        arcs: vec![],
        ..wire.clone()
    };
    let mut push = |(p, w, s): ([f64; 2], f64, f64)| {
        if piece.points.last().is_none_or(|&q| dist(p, q) > 1e-9) {
            piece.points.push(p);
            piece.widths.push(w);
            piece.arcs.push(s);
        }
    };
    push(at(a));
    for k in a.0 + 1..=b.0 {
        push((wire.points[k], wire.widths[k], wire.arcs[k]));
    }
    let end = at(b);
    if piece.points.len() == 1 || dist(piece.points[piece.points.len() - 1], end.0) > 1e-9 {
        piece.points.push(end.0);
        piece.widths.push(end.1);
        piece.arcs.push(end.2);
    }
    piece
}

/// Where segments `a0-a1` and `b0-b1` cross: parameters in `[0, 1]` on both, and the point.
fn intersect(
    a0: [f64; 2],
    a1: [f64; 2],
    b0: [f64; 2],
    b1: [f64; 2],
) -> Option<(f64, f64, [f64; 2])> {
    let r = [a1[0] - a0[0], a1[1] - a0[1]];
    let s = [b1[0] - b0[0], b1[1] - b0[1]];
    let denom = r[0] * s[1] - r[1] * s[0];
    if denom.abs() <= 1e-12 * (r[0].hypot(r[1]) * s[0].hypot(s[1])).max(1e-300) {
        return None;
    }
    let q = [b0[0] - a0[0], b0[1] - a0[1]];
    let t = (q[0] * s[1] - q[1] * s[0]) / denom;
    let u = (q[0] * r[1] - q[1] * r[0]) / denom;
    // Closed segments with a little slack: a crossing through a shared polyline vertex must not
    // slip between two segments by rounding (the caller removes the duplicates).
    let slack = -1e-9..=1.0 + 1e-9;
    if !(slack.contains(&t) && slack.contains(&u)) {
        return None;
    }
    let (t, u) = (t.clamp(0.0, 1.0), u.clamp(0.0, 1.0));
    Some((t, u, lerp(a0, a1, t)))
}

/// Whether the round cap of radius `r_p` at `p` touches (shares or is 8-adjacent to a pixel of)
/// the ink around the `far` samples, with pixels decided as [`crate::synth::render`] does: a pixel
/// is ink when its center lies within half the width of the centerline.
///
/// A cap narrower than a pixel's half diagonal can hold no pixel center (a 1 px stroke ending on
/// a pixel corner): with `back`, the centerline point a sample step behind `p`, the cap's ink is
/// then the pixels the renderer drew within `r_p` of the last step `back`-`p`.
fn ink_touches(
    p: [f64; 2],
    back: Option<[f64; 2]>,
    r_p: f64,
    far: &[(f64, usize)],
    samples: &Samples,
) -> bool {
    let x0 = (p[0] - r_p).floor() as i64 - 1;
    let y0 = (p[1] - r_p).floor() as i64 - 1;
    let x1 = (p[0] + r_p).ceil() as i64 + 1;
    let y1 = (p[1] + r_p).ceil() as i64 + 1;
    let side = (x1 - x0 + 1) as usize;
    let center = |x: i64, y: i64| [x as f64 + 0.5, y as f64 + 0.5];
    // Ink of the far strokes in the box (0.03 px of slack for sampling the centerline).
    let mut ink = vec![false; side * (y1 - y0 + 1) as usize];
    for y in y0..=y1 {
        for x in x0..=x1 {
            let c = center(x, y);
            ink[(y - y0) as usize * side + (x - x0) as usize] = far
                .iter()
                .any(|&(_, s)| dist(c, samples.pos[s]) <= samples.width[s] / 2.0 + 0.03);
        }
    }
    let in_cap = |x: i64, y: i64| dist(center(x, y), p) <= r_p + 1e-9;
    let empty_cap = !(y0 + 1..y1).any(|y| (x0 + 1..x1).any(|x| in_cap(x, y)));
    let own = |x: i64, y: i64| match back {
        Some(q) if empty_cap => segment_dist(center(x, y), q, p) <= r_p + 1e-9,
        _ => in_cap(x, y),
    };
    for y in y0 + 1..y1 {
        for x in x0 + 1..x1 {
            if !own(x, y) {
                continue;
            }
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if ink[(y + dy - y0) as usize * side + (x + dx - x0) as usize] {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Background components of at most this many pixels are specks, not holes: where two strokes
/// meet at a sharp angle or three cross close together, the rendering can enclose a pixel or two
/// (docs/design.md, adaptation 2, takes holes of 3 px or less for noise too).
pub const SPECK: usize = 3;

/// The holes of the ink: background components (4-connected) larger than [`SPECK`] that do not
/// reach the image border.
/// A cycle of centerlines inside the ink encloses a hole entirely or not at all, so one pixel per
/// hole decides.
struct Holes {
    /// One pixel center per hole.
    reps: Vec<[f64; 2]>,
    /// Length of the longest cycle that might enclose no hole: a ring leaves a hole once its
    /// centerline's diameter exceeds the stroke width, so `pi (max width + 2)` with some slack.
    cycle_reach: f64,
}

impl Holes {
    fn new(ink: &Binary, max_width: f64) -> Holes {
        let (w, h) = (ink.width as usize, ink.height as usize);
        let (labels, sizes) = label_components(&ink.ink, w, h, false, Connectivity::Four);
        let border = on_image_edge(&labels, w, h, sizes.len());
        // One pixel per hole, its first in raster order (labels are numbered in that order).
        let mut reps = Vec::new();
        let mut next = 1;
        for (i, &l) in labels.iter().enumerate() {
            let l = l as usize;
            if l != next {
                continue;
            }
            next += 1;
            if !border[l] && sizes[l] > SPECK {
                reps.push([(i % w) as f64 + 0.5, (i / w) as f64 + 0.5]);
            }
        }
        Holes {
            reps,
            cycle_reach: std::f64::consts::PI * (max_width + 2.0) + 10.0,
        }
    }

    /// Whether the closed polygon (last point joined to the first) encloses a hole (even-odd rule).
    fn inside(&self, polygon: &[[f64; 2]]) -> bool {
        if polygon.len() < 3 {
            return false;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in polygon {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        self.reps.iter().any(|&q| {
            !(q[0] < lo[0] || q[0] > hi[0] || q[1] < lo[1] || q[1] > hi[1])
                && point_in_polygon(q, polygon)
        })
    }
}

/// Every vertex and wire point of a [`Net`] as a node of one graph (consecutive points joined), for
/// radius queries and walks along the centerlines. Nodes `0..nodes.len()` are the vertices.
struct Samples {
    pos: Vec<[f64; 2]>,
    width: Vec<f64>,
    /// For wire-interior samples: (wire, point index).
    place: Vec<Option<(usize, usize)>>,
    /// The samples joined to each sample.
    links: Csr<u32>,
    grid: PointGrid,
}

impl Samples {
    fn new(net: &Net) -> Samples {
        let mut pos: Vec<[f64; 2]> = net.nodes.iter().map(|n| n.pos).collect();
        let mut width: Vec<f64> = net.nodes.iter().map(|n| n.width).collect();
        let mut place = vec![None; pos.len()];
        let mut links = Vec::new();
        for (w, wire) in net.wires.iter().enumerate().filter(|(_, w)| w.alive) {
            let last = wire.points.len() - 1;
            let mut prev = wire.from;
            for i in 1..last {
                let id = pos.len();
                pos.push(wire.points[i]);
                width.push(wire.widths[i]);
                place.push(Some((w, i)));
                links.push((prev, id));
                prev = id;
            }
            links.push((prev, wire.to));
        }
        let links = Csr::build(pos.len(), |sink| {
            for &(a, b) in &links {
                sink.push(a, b as u32);
                sink.push(b, a as u32);
            }
        });
        // Only live vertices and wire points are searched.
        let searchable: Vec<[f64; 2]> = pos
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let live = i >= net.nodes.len() || net.nodes[i].alive;
                if live {
                    p
                } else {
                    [f64::NAN, f64::NAN]
                }
            })
            .collect();
        let grid = PointGrid::new(&searchable, 2.0);
        Samples {
            pos,
            width,
            place,
            links,
            grid,
        }
    }

    fn wire_of(&self, s: usize) -> Option<(usize, usize)> {
        self.place[s]
    }
}

/// Bounded shortest paths along the centerlines, reusing its buffers between searches.
struct Dijkstra {
    distance: Vec<f64>,
    previous: Vec<usize>,
    touched: Vec<usize>,
    heap: BinaryHeap<Reached>,
}

#[derive(PartialEq)]
struct Reached(f64, usize);

impl Eq for Reached {}

impl PartialOrd for Reached {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Reached {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on distance.
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl Dijkstra {
    fn new(n: usize) -> Self {
        Dijkstra {
            distance: vec![f64::INFINITY; n],
            previous: vec![usize::MAX; n],
            touched: Vec::new(),
            heap: BinaryHeap::new(),
        }
    }

    fn run(&mut self, samples: &Samples, source: usize, limit: f64) {
        for &t in &self.touched {
            self.distance[t] = f64::INFINITY;
        }
        self.touched.clear();
        self.heap.clear();
        self.distance[source] = 0.0;
        self.previous[source] = usize::MAX;
        self.touched.push(source);
        self.heap.push(Reached(0.0, source));
        while let Some(Reached(d, v)) = self.heap.pop() {
            if d > self.distance[v] {
                continue;
            }
            for &u in samples.links.row(v) {
                let u = u as usize;
                let next = d + dist(samples.pos[v], samples.pos[u]);
                if next < self.distance[u] && next <= limit {
                    if self.distance[u].is_infinite() {
                        self.touched.push(u);
                    }
                    self.distance[u] = next;
                    self.previous[u] = v;
                    self.heap.push(Reached(next, u));
                }
            }
        }
    }

    fn distance(&self, s: usize) -> f64 {
        self.distance[s]
    }

    /// The positions along the shortest path from `s` back to the source (`s` reached).
    fn path(&self, samples: &Samples, mut s: usize) -> Vec<[f64; 2]> {
        let mut out = vec![samples.pos[s]];
        while self.previous[s] != usize::MAX {
            s = self.previous[s];
            out.push(samples.pos[s]);
        }
        out
    }
}

/// The smallest member of each element's set: the vertex a merged set keeps, so the result does
/// not depend on which member the union-find makes its root.
fn smallest_members(sets: &UnionFind<usize>, n: usize) -> Vec<usize> {
    let mut smallest = vec![usize::MAX; n];
    for v in 0..n {
        let root = sets.find(v);
        smallest[root] = smallest[root].min(v);
    }
    (0..n).map(|v| smallest[sets.find(v)]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::overhang_cases;

    /// `graph` without the edge that ends at its end vertex `end`, nor that vertex.
    fn without_arm(graph: &StrokeGraph, end: usize) -> StrokeGraph {
        let mut out = graph.clone();
        let arm = out
            .edges
            .iter()
            .position(|e| e.from == end || e.to == end)
            .expect("the arm's edge");
        let edge = out.edges.remove(arm);
        let junction = if edge.from == end { edge.to } else { edge.from };
        out.vertices[junction].degree -= 1;
        out.vertices.remove(end);
        for e in &mut out.edges {
            e.from -= (e.from > end) as usize;
            e.to -= (e.to > end) as usize;
        }
        out
    }

    /// The overhang group's case `name` and its truth graph.
    fn overhang_case(name: &str) -> (Case, StrokeGraph) {
        let case = overhang_cases()
            .into_iter()
            .find(|c| c.name == name)
            .expect("the case");
        let truth = truth_graph(&case);
        (case, truth)
    }

    #[test]
    fn misses_say_why_a_graph_is_not_exactly_right() {
        let (case, truth) = overhang_case("tee_o2_w8");
        let right = score(&case, &truth, &truth);
        assert!(right.exactly_right);
        assert_eq!(right.misses(), Misses::default());
        // The arm above the bar cut off: its end is missed, and the crossing is a T.
        let top = truth
            .endpoints()
            .min_by(|&a, &b| truth.vertices[a].pos[1].total_cmp(&truth.vertices[b].pos[1]))
            .expect("an end");
        let cut = without_arm(&truth, top);
        let scores = score(&case, &truth, &cut);
        assert!(!scores.exactly_right);
        let misses = scores.misses();
        assert!(misses.any());
        assert_eq!(
            misses,
            Misses {
                wrong_degree: true,
                missed_end: true,
                ..Misses::default()
            }
        );
        let shares = miss_shares(&[right, scores]);
        assert_eq!(shares.cases, 2);
        assert_eq!(shares.not_exactly_right, 0.5);
        assert_eq!(shares.wrong_degree, 0.5);
        assert_eq!(shares.missed_end, 0.5);
        assert_eq!(shares.spurious_end, 0.0);
    }

    #[test]
    fn distances_are_to_the_centerline_not_to_its_samples() {
        let (case, truth) = overhang_case("tee_plain_w8");
        // The same lines, each edge's first point moved a fifth of a pixel along it: its samples
        // fall between the truth's, but every point lies on the truth's centerline.
        let mut shifted = truth.clone();
        for e in &mut shifted.edges {
            let (a, b) = (e.points[0], e.points[1]);
            let len = dist(a, b);
            e.points[0] = lerp(a, b, 0.2 / len);
        }
        let scores = score(&case, &truth, &shifted);
        assert!(scores.chamfer < 0.01, "chamfer {}", scores.chamfer);
        assert!(scores.f1[0] > 0.999, "F1@1 {}", scores.f1[0]);
        // Moved off the line by 0.3 px, the distance is the offset.
        let mut off = truth.clone();
        for e in &mut off.edges {
            for p in &mut e.points {
                p[0] += 0.3;
                p[1] += 0.3;
            }
        }
        let scores = score(&case, &truth, &off);
        assert!(
            (0.2..0.45).contains(&scores.chamfer),
            "chamfer {}",
            scores.chamfer
        );
    }
}
