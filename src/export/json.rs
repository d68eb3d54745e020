//! JSON output: the stroke graph with what produced it, for other programs.
//!
//! The document records the crate version, the source, and the [`Params`] used, so a result can be
//! reproduced; then vertices, edges (polyline, width and unit tangent at each point), the
//! [`Features`] given (strokes through crossings, minutiae) and summary statistics. Floats are
//! rounded to 3 decimals; keys come in a fixed order, so the same graph always gives the same bytes.
//!
//! Per point: `widths` are the local stroke width (2 x distance to the background, docs/design.md,
//! "Beyond the paper"); `directions` are unit tangents in the direction of travel from `from` to
//! `to`. One could take the local direction from the sampling PCA; the fit stage computes it
//! instead by central differences on the fitted polyline (wrapping around closed loops), which is the
//! direction of the centerline actually written, and agrees with the PCA axis of the ink around it
//! wherever the stroke is straight over a few widths.
//!
//! ```json
//! {"ridgeline":"0.1.0","source":{"path":"a.png","width":64,"height":48},"parameters":{…},
//!  "vertices":[{"id":0,"x":10.5,"y":4.5,"degree":1,"width":3.2}, …],
//!  "edges":[{"id":0,"from":0,"to":1,"length":20.0,"points":[[10.5,4.5],…],"widths":[3.2,…],
//!            "directions":[[1.0,0.0],…]}, …],
//!  "strokes":[{"id":0,"edges":[0,2],"reversed":[false,true],"closed":false,"length":40.0,
//!              "points":[[10.5,4.5],…],"widths":[3.2,…]}, …],
//!  "minutiae":[{"kind":"ending","vertex":0,"x":10.5,"y":4.5,"direction":3.142,"width":3.2}, …],
//!  "stats":{"vertices":2,"edges":1,"endpoints":2,"junctions":0,"components":1,"cycles":0}}
//! ```

use serde::ser::{Serialize, SerializeSeq, Serializer};
use serde::Serialize as DeriveSerialize;
use std::time::Duration;

use super::Features;
use crate::curves::CubicBezier;
use crate::decisions::{Decisions, PrintDecisions, Warning};
use crate::minutiae::Minutia;
use crate::params::Params;
use crate::pipeline::Timings;
use crate::stroke_graph::{Edge, StrokeGraph, Vertex};
use crate::strokes::Stroke;

/// The decisions with their floats rounded like the graph's.
struct RoundedDecisions<'a>(&'a Decisions);

impl Serialize for RoundedDecisions<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let d = self.0;
        let mut s = serializer.serialize_struct("Decisions", 10)?;
        s.serialize_field("polarity", &d.polarity)?;
        s.serialize_field("polarity_confidence", &d.polarity_confidence.map(Rounded))?;
        s.serialize_field("threshold", &d.threshold)?;
        s.serialize_field("stroke_width", &Rounded(d.stroke_width))?;
        s.serialize_field("uneven_light", &Rounded(d.uneven_light))?;
        s.serialize_field("dropout", &d.dropout)?;
        s.serialize_field("dropout_share", &d.dropout_share.map(Rounded))?;
        if d.reversed_grounds.is_empty() {
            s.skip_field("reversed_grounds")?;
        } else {
            s.serialize_field("reversed_grounds", &d.reversed_grounds)?;
        }
        if d.regions.is_empty() {
            s.skip_field("regions")?;
        } else {
            s.serialize_field("regions", &d.regions)?;
        }
        match &d.print {
            Some(print) => s.serialize_field("print", &RoundedPrint(print))?,
            None => s.skip_field("print")?,
        }
        s.end()
    }
}

/// The fingerprint front end's measures with their floats rounded like the graph's.
struct RoundedPrint<'a>(&'a PrintDecisions);

impl Serialize for RoundedPrint<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let p = self.0;
        let mut s = serializer.serialize_struct("PrintDecisions", 3)?;
        s.serialize_field("ridge_period", &Rounded(p.ridge_period))?;
        s.serialize_field("print_share", &Rounded(p.print_share))?;
        s.serialize_field("coherence", &Rounded(p.coherence))?;
        s.end()
    }
}

/// What the JSON says besides the graph. Build it from [`JsonMeta::new`] or
/// [`JsonMeta::default`] and assign the public fields: more may be added.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct JsonMeta {
    /// The input file as the user named it; `null` in the JSON when absent. Default value: `None`.
    pub source_path: Option<String>,
    /// The parameters the graph was traced with. Default value: [`Params::default`].
    pub params: Params,
    /// Indent the document for people instead of writing it on one line. Default value: `false`.
    pub pretty: bool,
    /// For one page of a multi-page input: its 1-based number and the input's page count, written
    /// as `source.page` and `source.pages` (absent for single images). Default value: `None`.
    pub page: Option<(usize, usize)>,
    /// What the front end decided (images), written as `decisions`. Default value: `None`.
    pub decisions: Option<Decisions>,
    /// What is probably wrong with the result, written as `warnings` (always, possibly empty).
    /// Default value: none.
    pub warnings: Vec<Warning>,
    /// The kind of input whose rules the parameters were applied by, written as
    /// `parameters.input` when given: `points2d` (a point list in the plane: widths from the
    /// PCA of §3.1 rather than a distance transform) or `points3d` (the stages in space,
    /// docs/design.md, "Point sets in space"); images leave it out. Default value: `None`.
    pub input: Option<&'static str>,
    /// Seconds per stage, written as `timings` after `stats` when given (each stage summed over
    /// the parts traced in parallel, so their sum can exceed the wall-clock time). Times differ
    /// from run to run: a document with them is no longer the same bytes for the same input.
    /// Default value: `None`.
    pub timings: Option<Timings>,
    /// Wall-clock seconds of the whole trace (decoding included when the caller timed it),
    /// written as `timings.wall` when given. Default value: `None`.
    pub wall: Option<Duration>,
}

impl JsonMeta {
    /// Metadata for a graph traced with `params`.
    pub fn new(params: Params) -> Self {
        JsonMeta {
            params,
            ..JsonMeta::default()
        }
    }

    /// Sets [`JsonMeta::source_path`].
    pub fn with_source_path(mut self, path: impl Into<String>) -> Self {
        self.source_path = Some(path.into());
        self
    }

    /// Sets [`JsonMeta::pretty`].
    pub fn with_pretty(mut self, pretty: bool) -> Self {
        self.pretty = pretty;
        self
    }

    /// Sets [`JsonMeta::decisions`] and [`JsonMeta::warnings`] from a trace.
    pub fn with_trace(mut self, trace: &crate::pipeline::Trace) -> Self {
        self.decisions = trace.decisions.clone();
        self.warnings = trace.warnings.clone();
        self
    }

    /// Sets [`JsonMeta::input`].
    pub fn with_input(mut self, input: &'static str) -> Self {
        self.input = Some(input);
        self
    }

    /// Sets [`JsonMeta::timings`] and [`JsonMeta::wall`].
    pub fn with_timings(mut self, timings: Option<Timings>, wall: Duration) -> Self {
        self.timings = timings;
        self.wall = Some(wall);
        self
    }

    /// Sets [`JsonMeta::page`]: page `number` of `count`, recorded when `count` is more than 1.
    pub fn with_page(mut self, number: usize, count: usize) -> Self {
        self.page = (count > 1).then_some((number, count));
        self
    }
}

/// Writes `graph` and `meta` as a JSON document.
pub fn to_string(graph: &StrokeGraph, meta: &JsonMeta) -> String {
    to_string_with(graph, meta, &Features::default())
}

/// Writes `graph`, `meta` and the `features` given as a JSON document: `strokes`, `minutiae` and
/// `curves` lists appear when the features hold them. Curves are read as one list of cubic
/// Béziers per edge, in edge order (`"curves":[[[p0,p1,p2,p3],…],…]`).
pub fn to_string_with(graph: &StrokeGraph, meta: &JsonMeta, features: &Features) -> String {
    let document = Document {
        ridgeline: env!("CARGO_PKG_VERSION"),
        source: Source {
            path: meta.source_path.as_deref(),
            page: meta.page.map(|(number, _)| number),
            pages: meta.page.map(|(_, count)| count),
            width: graph.width,
            height: graph.height,
        },
        parameters: ParamsOut {
            params: &meta.params,
            input: meta.input,
        },
        decisions: meta.decisions.as_ref().map(RoundedDecisions),
        warnings: &meta.warnings,
        vertices: Vertices(&graph.vertices),
        edges: Edges(&graph.edges),
        strokes: features.strokes.map(Strokes),
        minutiae: features.minutiae.map(Minutiae),
        curves: features.curves.map(Curves),
        stats: Stats::of(graph),
        timings: TimingsOut::of(meta),
    };
    // Serializing plain structs, numbers and strings into memory cannot fail; the fallback only
    // keeps this function free of panics.
    let text = if meta.pretty {
        serde_json::to_string_pretty(&document)
    } else {
        serde_json::to_string(&document)
    };
    let mut text = text.unwrap_or_else(|_| String::from("{}"));
    text.push('\n');
    text
}

/// The parameters, with the kind of input after them when [`JsonMeta::input`] names one (and
/// exactly [`Params`]' own serialization when not).
struct ParamsOut<'a> {
    params: &'a Params,
    input: Option<&'static str>,
}

impl Serialize for ParamsOut<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(DeriveSerialize)]
        struct WithInput<'a> {
            #[serde(flatten)]
            params: &'a Params,
            input: &'static str,
        }
        match self.input {
            None => self.params.serialize(serializer),
            Some(input) => WithInput {
                params: self.params,
                input,
            }
            .serialize(serializer),
        }
    }
}

#[derive(DeriveSerialize)]
struct Document<'a> {
    ridgeline: &'static str,
    source: Source<'a>,
    parameters: ParamsOut<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    decisions: Option<RoundedDecisions<'a>>,
    warnings: &'a [Warning],
    vertices: Vertices<'a>,
    edges: Edges<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    strokes: Option<Strokes<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    minutiae: Option<Minutiae<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    curves: Option<Curves<'a>>,
    stats: Stats,
    #[serde(skip_serializing_if = "Option::is_none")]
    timings: Option<TimingsOut>,
}

/// Seconds per stage and of the whole trace, to the microsecond; absent stages (a point set in
/// space records none) are left out.
#[derive(DeriveSerialize)]
struct TimingsOut {
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    stages: Option<StagesOut>,
    #[serde(skip_serializing_if = "Option::is_none")]
    wall: Option<f64>,
}

#[derive(DeriveSerialize)]
struct StagesOut {
    decode: f64,
    binarize: f64,
    points: f64,
    sampling: f64,
    graph: f64,
    refine: f64,
    fit: f64,
    skeleton: f64,
}

impl TimingsOut {
    fn of(meta: &JsonMeta) -> Option<TimingsOut> {
        let seconds = |d: Duration| (d.as_secs_f64() * 1e6).round() / 1e6;
        if meta.timings.is_none() && meta.wall.is_none() {
            return None;
        }
        Some(TimingsOut {
            stages: meta.timings.map(|t| StagesOut {
                decode: seconds(t.decode),
                binarize: seconds(t.binarize),
                points: seconds(t.points),
                sampling: seconds(t.sampling),
                graph: seconds(t.graph),
                refine: seconds(t.refine),
                fit: seconds(t.fit),
                skeleton: seconds(t.skeleton),
            }),
            wall: meta.wall.map(seconds),
        })
    }
}

/// Cubic Béziers per edge: each segment as its four points `[p0, p1, p2, p3]`.
struct Curves<'a>(&'a [Vec<CubicBezier>]);

impl Serialize for Curves<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let rounded = |p: [f64; 2]| [Rounded(p[0]), Rounded(p[1])];
        let mut seq = serializer.serialize_seq(Some(self.0.len()))?;
        for segments in self.0 {
            let out: Vec<[[Rounded; 2]; 4]> = segments
                .iter()
                .map(|c| [rounded(c.p0), rounded(c.p1), rounded(c.p2), rounded(c.p3)])
                .collect();
            seq.serialize_element(&out)?;
        }
        seq.end()
    }
}

#[derive(DeriveSerialize)]
struct Source<'a> {
    path: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    page: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pages: Option<usize>,
    width: u32,
    height: u32,
}

#[derive(DeriveSerialize)]
struct Stats {
    vertices: usize,
    edges: usize,
    endpoints: usize,
    junctions: usize,
    components: usize,
    cycles: usize,
}

impl Stats {
    fn of(graph: &StrokeGraph) -> Stats {
        // `components` indexes vertices by the edges' ends: only trust it on a graph whose edges
        // refer to existing vertices, so that a malformed graph is written, not a panic.
        let n = graph.vertices.len();
        let well_formed = graph.edges.iter().all(|e| e.from < n && e.to < n);
        let components = if well_formed { graph.components() } else { 0 };
        Stats {
            vertices: n,
            edges: graph.edges.len(),
            endpoints: graph.endpoints().count(),
            junctions: graph.junctions().count(),
            components,
            // Cycle rank E - V + C, as `StrokeGraph::cycles`.
            cycles: (graph.edges.len() + components).saturating_sub(n),
        }
    }
}

/// A float rounded to 3 decimals (a thousandth of a pixel), negative zero as zero. Non-finite
/// values become `null` (serde_json's rule), which keeps the document parseable.
#[derive(Clone, Copy)]
struct Rounded(f64);

impl Serialize for Rounded {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // Adding 0.0 turns -0.0 into 0.0.
        serializer.serialize_f64((self.0 * 1000.0).round() / 1000.0 + 0.0)
    }
}

/// The vertices, serialized from the graph without copying it.
struct Vertices<'a>(&'a [Vertex]);

impl Serialize for Vertices<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(DeriveSerialize)]
        struct VertexOut {
            id: usize,
            x: Rounded,
            y: Rounded,
            degree: usize,
            width: Rounded,
        }
        let mut seq = serializer.serialize_seq(Some(self.0.len()))?;
        for (id, v) in self.0.iter().enumerate() {
            seq.serialize_element(&VertexOut {
                id,
                x: Rounded(v.pos[0]),
                y: Rounded(v.pos[1]),
                degree: v.degree,
                width: Rounded(v.width),
            })?;
        }
        seq.end()
    }
}

/// The edges, serialized from the graph without copying their polylines.
struct Edges<'a>(&'a [Edge]);

impl Serialize for Edges<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(DeriveSerialize)]
        struct EdgeOut<'e> {
            id: usize,
            from: usize,
            to: usize,
            length: Rounded,
            points: Pairs<'e>,
            widths: Singles<'e>,
            directions: Pairs<'e>,
        }
        let mut seq = serializer.serialize_seq(Some(self.0.len()))?;
        for (id, e) in self.0.iter().enumerate() {
            seq.serialize_element(&EdgeOut {
                id,
                from: e.from,
                to: e.to,
                length: Rounded(e.length()),
                points: Pairs(&e.points),
                widths: Singles(&e.widths),
                directions: Pairs(&e.directions),
            })?;
        }
        seq.end()
    }
}

/// The strokes through crossings, serialized without copying their polylines.
struct Strokes<'a>(&'a [Stroke]);

impl Serialize for Strokes<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(DeriveSerialize)]
        struct StrokeOut<'s> {
            id: usize,
            edges: &'s [usize],
            reversed: &'s [bool],
            closed: bool,
            length: Rounded,
            points: Pairs<'s>,
            widths: Singles<'s>,
        }
        let mut seq = serializer.serialize_seq(Some(self.0.len()))?;
        for (id, s) in self.0.iter().enumerate() {
            seq.serialize_element(&StrokeOut {
                id,
                edges: &s.edges,
                reversed: &s.reversed,
                closed: s.closed,
                length: Rounded(s.length()),
                points: Pairs(&s.points),
                widths: Singles(&s.widths),
            })?;
        }
        seq.end()
    }
}

/// The minutiae: kind, vertex, position, direction (radians, y down, see
/// [`crate::minutiae`]), ridge width, and the quality 0-100 when the fingerprint front end gave one.
struct Minutiae<'a>(&'a [Minutia]);

impl Serialize for Minutiae<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(DeriveSerialize)]
        struct MinutiaOut {
            kind: crate::minutiae::MinutiaKind,
            vertex: usize,
            x: Rounded,
            y: Rounded,
            direction: Rounded,
            width: Rounded,
            #[serde(skip_serializing_if = "Option::is_none")]
            quality: Option<u8>,
        }
        serializer.collect_seq(self.0.iter().map(|m| MinutiaOut {
            kind: m.kind,
            vertex: m.vertex,
            x: Rounded(m.pos[0]),
            y: Rounded(m.pos[1]),
            direction: Rounded(m.direction),
            width: Rounded(m.width),
            quality: m.quality,
        }))
    }
}

/// `[[x, y], …]`, rounded.
struct Pairs<'a>(&'a [[f64; 2]]);

impl Serialize for Pairs<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.0.iter().map(|p| [Rounded(p[0]), Rounded(p[1])]))
    }
}

/// `[w, …]`, rounded.
struct Singles<'a>(&'a [f64]);

impl Serialize for Singles<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.0.iter().map(|&w| Rounded(w)))
    }
}

/// Writes the trace of a 3D point set as a JSON document: the same layout as the plane's, with
/// `z` on every vertex and every polyline point, the tube's diameter as `width`, and
/// `parameters.input` set to `points3d`; `source` holds the path alone (a point set has no pixel
/// extent), and there are no directions, strokes or minutiae.
///
/// ```json
/// {"ridgeline":"0.1.0","source":{"path":"helix.ply"},"parameters":{…,"input":"points3d"},
///  "warnings":[],"vertices":[{"id":0,"x":60.0,"y":0.0,"z":0.0,"degree":1,"width":8.0}, …],
///  "edges":[{"id":0,"from":0,"to":1,"length":770.1,"points":[[60.0,0.0,0.0],…],
///            "widths":[8.0,…]}],
///  "stats":{"vertices":2,"edges":1,"endpoints":2,"junctions":0,"components":1,"cycles":0}}
/// ```
pub fn to_string_3d(trace: &crate::curve3d::Trace3d, meta: &JsonMeta) -> String {
    use crate::curve3d::CurveGraph3d;
    #[derive(DeriveSerialize)]
    struct Source3d<'a> {
        path: Option<&'a str>,
    }
    #[derive(DeriveSerialize)]
    struct VertexOut {
        id: usize,
        x: Rounded,
        y: Rounded,
        z: Rounded,
        degree: usize,
        width: Rounded,
    }
    #[derive(DeriveSerialize)]
    struct EdgeOut {
        id: usize,
        from: usize,
        to: usize,
        length: Rounded,
        points: Vec<[Rounded; 3]>,
        widths: Vec<Rounded>,
    }
    #[derive(DeriveSerialize)]
    struct Document3d<'a> {
        ridgeline: &'static str,
        source: Source3d<'a>,
        parameters: ParamsOut<'a>,
        warnings: &'a [Warning],
        vertices: Vec<VertexOut>,
        edges: Vec<EdgeOut>,
        stats: Stats,
        #[serde(skip_serializing_if = "Option::is_none")]
        timings: Option<TimingsOut>,
    }
    let graph: &CurveGraph3d = &trace.graph;
    let n = graph.vertices.len();
    let well_formed = graph.edges.iter().all(|e| e.from < n && e.to < n);
    let components = if well_formed { graph.components() } else { 0 };
    let document = Document3d {
        ridgeline: env!("CARGO_PKG_VERSION"),
        source: Source3d {
            path: meta.source_path.as_deref(),
        },
        parameters: ParamsOut {
            params: &meta.params,
            input: Some(meta.input.unwrap_or("points3d")),
        },
        warnings: &trace.warnings,
        vertices: graph
            .vertices
            .iter()
            .enumerate()
            .map(|(id, v)| VertexOut {
                id,
                x: Rounded(v.pos[0]),
                y: Rounded(v.pos[1]),
                z: Rounded(v.pos[2]),
                degree: v.degree,
                width: Rounded(v.width),
            })
            .collect(),
        edges: graph
            .edges
            .iter()
            .enumerate()
            .map(|(id, e)| EdgeOut {
                id,
                from: e.from,
                to: e.to,
                length: Rounded(e.length()),
                points: e.points.iter().map(|p| p.map(Rounded)).collect(),
                widths: e.widths.iter().map(|&w| Rounded(w)).collect(),
            })
            .collect(),
        stats: Stats {
            vertices: n,
            edges: graph.edges.len(),
            endpoints: graph.endpoints().count(),
            junctions: graph.junctions().count(),
            components,
            cycles: (graph.edges.len() + components).saturating_sub(n),
        },
        timings: TimingsOut::of(meta),
    };
    let text = if meta.pretty {
        serde_json::to_string_pretty(&document)
    } else {
        serde_json::to_string(&document)
    };
    let mut text = text.unwrap_or_else(|_| String::from("{}"));
    text.push('\n');
    text
}
