//! `ridgeline.Trace`: one traced image or point list, read from Python as numpy arrays, as lists
//! of dicts shaped like the JSON output (docs/json.md, unrounded), or as SVG, JSON and networkx.

use std::sync::{Arc, OnceLock};
use std::time::Duration;

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use ridgeline::curves::{fit_beziers, fit_edges, CubicBezier, CurveOptions};
use ridgeline::export::json::{self, JsonMeta};
use ridgeline::export::svg::{self, SvgOptions};
use ridgeline::export::Features;
use ridgeline::minutiae::{minutiae, Minutia, MinutiaKind, MinutiaeOptions};
use ridgeline::strokes::Stroke;
use ridgeline::{Binary, Decisions, Edge, GrayImage, Params, StrokeGraph, Timings, Warning};

/// What the input was: an image (or mask) or a point list, whose SVG canvas fits the drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Image,
    Points,
}

/// What an SVG shows under the centerlines, closest to what was traced.
pub enum Backdrop {
    /// A point list: nothing.
    None,
    /// The file's own bytes (PNG, JPEG, GIF, WebP), as the command line embeds them.
    Encoded {
        bytes: Arc<Vec<u8>>,
        mime: &'static str,
    },
    /// The decoded pixels in colour (TIFF, BMP, PNM in colour).
    Color(image::DynamicImage),
    /// The decoded gray pixels.
    Gray(GrayImage),
    /// The caller's uint8 array, read again when the SVG is written (it is not copied meanwhile).
    Array(Py<PyAny>),
    /// The caller's bool array, read again for the SVG (the ink drawn black on white), `mask` and
    /// `minutiae`.
    MaskArray(Py<PyAny>),
}

impl Backdrop {
    /// The same backdrop, sharing the array or the bytes.
    pub fn clone_ref(&self, py: Python<'_>) -> Backdrop {
        match self {
            Backdrop::None => Backdrop::None,
            Backdrop::Encoded { bytes, mime } => Backdrop::Encoded {
                bytes: Arc::clone(bytes),
                mime,
            },
            Backdrop::Color(image) => Backdrop::Color(image.clone()),
            Backdrop::Gray(image) => Backdrop::Gray(image.clone()),
            Backdrop::Array(array) => Backdrop::Array(array.clone_ref(py)),
            Backdrop::MaskArray(array) => Backdrop::MaskArray(array.clone_ref(py)),
        }
    }
}

/// One traced page, made with the GIL released.
pub struct Traced {
    pub graph: StrokeGraph,
    pub binary: Option<Binary>,
    pub strokes: Vec<Stroke>,
    pub params: Params,
    pub point_count: usize,
    pub timings: Timings,
    /// Decoding the page (zero for arrays and point lists).
    pub decode: Duration,
    /// Everything the call did with the GIL released, from reading the input to the strokes.
    pub native: Duration,
    /// Page number and page count of the file.
    pub page: Option<(usize, usize)>,
    pub backdrop: Backdrop,
    pub kind: Kind,
    /// What the front end decided (images), and what is probably wrong with the result.
    pub decisions: Option<Decisions>,
    pub warnings: Vec<Warning>,
    /// For an array: whether its layout made the call copy it (`Trace._input_copied`).
    pub input_copied: Option<bool>,
    /// With the fingerprint front end: the minutiae it kept inside the print, with a quality.
    pub print_minutiae: Option<Vec<Minutia>>,
    /// The resolution the image file states, dots per inch (encoded input only).
    pub resolution: Option<f64>,
    /// A point set in space: its trace, whose graph `graph` shows seen from above (z dropped).
    pub space: Option<ridgeline::Trace3d>,
}

/// A graph in space seen from above: `z` dropped, directions the chords' in the plane.
pub fn plane_view(space: &ridgeline::CurveGraph3d) -> StrokeGraph {
    let flat = |p: [f64; 3]| [p[0], p[1]];
    StrokeGraph {
        width: 0,
        height: 0,
        vertices: space
            .vertices
            .iter()
            .map(|v| ridgeline::Vertex {
                pos: flat(v.pos),
                degree: v.degree,
                width: v.width,
            })
            .collect(),
        edges: space
            .edges
            .iter()
            .map(|e| {
                let points: Vec<[f64; 2]> = e.points.iter().map(|&p| flat(p)).collect();
                let directions = tangents(&e.points)
                    .into_iter()
                    .map(|t| {
                        let n = t[0].hypot(t[1]);
                        if n > 0.0 {
                            [t[0] / n, t[1] / n]
                        } else {
                            [0.0, 0.0]
                        }
                    })
                    .collect();
                Edge {
                    from: e.from,
                    to: e.to,
                    points,
                    widths: e.widths.clone(),
                    directions,
                }
            })
            .collect(),
    }
}

/// Unit tangents along a polyline in space by central differences (one-sided at its ends).
fn tangents(points: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i.saturating_sub(1)], points[(i + 1).min(n - 1)]);
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if length > 0.0 {
                d.map(|x| x / length)
            } else {
                [0.0; 3]
            }
        })
        .collect()
}

/// An (n, 3) array of `triples`.
fn triple_array<'py>(
    py: Python<'py>,
    triples: Vec<[f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = triples.len();
    let array = Array2::from_shape_vec((n, 3), triples.into_flattened())
        .map_err(|err| PyRuntimeError::new_err(err.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// The result of `ridgeline.trace`, `ridgeline.trace_pages` or `ridgeline.trace_points`.
///
/// The stroke graph as numpy arrays (`vertex_xy`, `vertex_degree`, `vertex_width`; edges as
/// `edge_vertices` and `edge_offsets` into `point_xy`, `point_width`, `point_direction`), as
/// lists of dicts shaped like the JSON output (`vertices`, `edges`, `strokes`, `minutiae`), and
/// as documents (`to_json()`, `to_svg()`, `to_networkx()`). Each array property builds a new
/// array.
#[pyclass(module = "ridgeline", name = "Trace", frozen)]
pub struct Trace {
    traced: Traced,
    source_path: Option<String>,
    minutiae: OnceLock<Vec<Minutia>>,
}

impl Trace {
    pub fn new(traced: Traced, source_path: Option<String>) -> Trace {
        Trace {
            traced,
            source_path,
            minutiae: OnceLock::new(),
        }
    }

    fn graph(&self) -> &StrokeGraph {
        &self.traced.graph
    }

    fn minutiae_list(&self, py: Python<'_>) -> &[Minutia] {
        // Computed outside the cell: a thread waiting in `get_or_init` would hold the GIL that
        // the computing thread needs back.
        if let Some(found) = self.minutiae.get() {
            return found;
        }
        // The fingerprint front end's are filtered inside its print, as the command line's.
        if let Some(print) = &self.traced.print_minutiae {
            return self.minutiae.get_or_init(|| print.clone());
        }
        // A mask array is read as it is now (the trace kept no copy of it).
        let from_array = match &self.traced.backdrop {
            Backdrop::MaskArray(array) => mask_of(py, array).ok(),
            _ => None,
        };
        let found = py.detach(|| {
            minutiae(
                &self.traced.graph,
                from_array.as_ref().or(self.traced.binary.as_ref()),
                &MinutiaeOptions::default(),
            )
        });
        self.minutiae.get_or_init(|| found)
    }

    fn meta(&self, pretty: bool) -> JsonMeta {
        let mut meta = JsonMeta::new(self.traced.params.clone()).with_pretty(pretty);
        meta.decisions = self.traced.decisions.clone();
        meta.warnings = self.traced.warnings.clone();
        if let Some(path) = &self.source_path {
            meta = meta.with_source_path(path.clone());
        }
        if let Some((number, count)) = self.traced.page {
            meta = meta.with_page(number, count);
        }
        if self.traced.kind == Kind::Points {
            meta = meta.with_input("points2d");
        }
        meta
    }

    /// The JSON document, as the command line writes it with the same features.
    fn json_text(
        &self,
        pretty: bool,
        marks: Option<&[Minutia]>,
        curves: Option<&[Vec<CubicBezier>]>,
    ) -> String {
        if let Some(space) = &self.traced.space {
            let meta = self.meta(pretty).with_input("points3d");
            return json::to_string_3d(space, &meta);
        }
        let features = Features::default()
            .with_strokes(Some(&self.traced.strokes))
            .with_minutiae(marks)
            .with_curves(curves);
        json::to_string_with(self.graph(), &self.meta(pretty), &features)
    }
}

fn curve_options(tolerance: Option<f64>, corner_angle: Option<f64>) -> PyResult<CurveOptions> {
    let defaults = CurveOptions::default();
    let options = CurveOptions {
        tolerance: tolerance.unwrap_or(defaults.tolerance),
        corner_angle_deg: corner_angle.unwrap_or(defaults.corner_angle_deg),
    };
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(PyValueError::new_err(format!(
            "curve_tolerance must be > 0 px, got {}",
            options.tolerance
        )));
    }
    if !(0.0..=180.0).contains(&options.corner_angle_deg) {
        return Err(PyValueError::new_err(format!(
            "corner_angle must be in [0, 180] degrees, got {}",
            options.corner_angle_deg
        )));
    }
    Ok(options)
}

/// An (n, 2) array of `pairs`, their buffer handed to numpy as it is (no copy).
fn pair_array<'py, T: numpy::Element>(
    py: Python<'py>,
    pairs: Vec<[T; 2]>,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let n = pairs.len();
    let array = Array2::from_shape_vec((n, 2), pairs.into_flattened())
        .map_err(|err| PyRuntimeError::new_err(err.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// One `field` of every edge (points, widths, directions), edge after edge, in one allocation.
fn concatenated<T: Copy>(edges: &[Edge], field: impl Fn(&Edge) -> &[T]) -> Vec<T> {
    let mut all = Vec::with_capacity(edges.iter().map(|e| field(e).len()).sum());
    for edge in edges {
        all.extend_from_slice(field(edge));
    }
    all
}

/// A bool array's flags as a mask, read as the array is now.
fn mask_of(py: Python<'_>, array: &Py<PyAny>) -> PyResult<Binary> {
    let array = array.bind(py).cast::<PyArray2<bool>>()?.readonly();
    let view = array.as_array();
    let (rows, columns) = view.dim();
    Ok(Binary {
        width: columns as u32,
        height: rows as u32,
        ink: view.iter().copied().collect(),
    })
}

fn pairs<'py>(py: Python<'py>, points: &[[f64; 2]]) -> PyResult<Bound<'py, PyList>> {
    PyList::new(py, points.iter().map(|p| vec![p[0], p[1]]))
}

fn seconds(duration: Duration) -> f64 {
    duration.as_secs_f64()
}

#[pymethods]
impl Trace {
    /// Width of the image in px (for a point list, the largest x rounded up, plus 1).
    #[getter]
    fn width(&self) -> u32 {
        self.graph().width
    }

    /// Height of the image in px (for a point list, the largest y rounded up, plus 1).
    #[getter]
    fn height(&self) -> u32 {
        self.graph().height
    }

    /// Number of points traced: ink pixels, or points of the list.
    #[getter]
    fn point_count(&self) -> usize {
        self.traced.point_count
    }

    /// The source path recorded in the JSON (the path traced, or the `source_path` given).
    #[getter]
    fn source_path(&self) -> Option<&str> {
        self.source_path.as_deref()
    }

    /// `(number, count)` of this page in its file, from 1; `None` for arrays and point lists.
    #[getter]
    fn page(&self) -> Option<(usize, usize)> {
        self.traced.page
    }

    /// Every parameter used, as keywords: `ridgeline.trace(image, **t.params)` traces the same.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let defaults = crate::params::cached_defaults(py)?;
        crate::params::to_dict(py, &self.traced.params, Some(&defaults))
    }

    /// Seconds per stage (the library's timings; summed over threads when a large page was
    /// traced in parallel chunks), `decode`, and `native`: the wall time of the whole call with
    /// the GIL released (reading, decoding, tracing, strokes).
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = &self.traced.timings;
        let dict = PyDict::new(py);
        dict.set_item("decode", seconds(self.traced.decode))?;
        for (name, duration) in [
            ("binarize", t.binarize),
            ("points", t.points),
            ("sampling", t.sampling),
            ("graph", t.graph),
            ("refine", t.refine),
            ("fit", t.fit),
            ("skeleton", t.skeleton),
        ] {
            dict.set_item(name, seconds(duration))?;
        }
        dict.set_item("native", seconds(self.traced.native))?;
        Ok(dict)
    }

    /// Vertex positions, shape (V, 2), px; (V, 3) with `z` for a point set in space.
    #[getter]
    fn vertex_xy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if let Some(space) = &self.traced.space {
            return triple_array(py, space.graph.vertices.iter().map(|v| v.pos).collect());
        }
        pair_array(py, self.graph().vertices.iter().map(|v| v.pos).collect())
    }

    /// Vertex degrees, shape (V,): 1 stroke end, 3+ junction or crossing, 2 loop anchor, 0 dot.
    #[getter]
    fn vertex_degree<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let degrees: Vec<i64> = self
            .graph()
            .vertices
            .iter()
            .map(|v| v.degree as i64)
            .collect();
        degrees.into_pyarray(py)
    }

    /// Local stroke width at each vertex, shape (V,), px.
    #[getter]
    fn vertex_width<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let widths: Vec<f64> = self.graph().vertices.iter().map(|v| v.width).collect();
        widths.into_pyarray(py)
    }

    /// The vertex ids `(from, to)` of each edge, shape (E, 2).
    #[getter]
    fn edge_vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let ends = self.graph().edges.iter();
        pair_array(py, ends.map(|e| [e.from as i64, e.to as i64]).collect())
    }

    /// Shape (E + 1,): the points of edge `i` are `point_xy[edge_offsets[i]:edge_offsets[i + 1]]`.
    #[getter]
    fn edge_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let mut offsets = Vec::with_capacity(self.graph().edges.len() + 1);
        let mut total = 0i64;
        offsets.push(0);
        for edge in &self.graph().edges {
            total += edge.points.len() as i64;
            offsets.push(total);
        }
        Array1::from_vec(offsets).into_pyarray(py)
    }

    /// Length of each edge's polyline, shape (E,), px.
    #[getter]
    fn edge_length<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let lengths: Vec<f64> = self.graph().edges.iter().map(|e| e.length()).collect();
        lengths.into_pyarray(py)
    }

    /// Every edge's polyline points, edge after edge, shape (P, 2), px; (P, 3) with `z` for a
    /// point set in space.
    #[getter]
    fn point_xy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if let Some(space) = &self.traced.space {
            let all = space
                .graph
                .edges
                .iter()
                .flat_map(|e| e.points.iter().copied());
            return triple_array(py, all.collect());
        }
        pair_array(py, concatenated(&self.graph().edges, |e| &e.points))
    }

    /// Local stroke width at each point of `point_xy`, shape (P,), px.
    #[getter]
    fn point_width<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        concatenated(&self.graph().edges, |e| &e.widths).into_pyarray(py)
    }

    /// Unit tangent at each point of `point_xy` in the edge's direction of travel, shape (P, 2);
    /// (P, 3) for a point set in space.
    #[getter]
    fn point_direction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if let Some(space) = &self.traced.space {
            let all = space.graph.edges.iter().flat_map(|e| tangents(&e.points));
            return triple_array(py, all.collect());
        }
        pair_array(py, concatenated(&self.graph().edges, |e| &e.directions))
    }

    /// The foreground mask traced, shape (height, width), True = ink (for a bool array, a copy
    /// of the array as it is now); `None` for point lists.
    #[getter]
    fn mask<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<bool>>>> {
        let binary = match (&self.traced.backdrop, &self.traced.binary) {
            (Backdrop::MaskArray(array), _) => mask_of(py, array)?,
            (_, Some(binary)) => binary.clone(),
            (_, None) => return Ok(None),
        };
        let shape = (binary.height as usize, binary.width as usize);
        Ok(Array2::from_shape_vec(shape, binary.ink)
            .ok()
            .map(|array| array.into_pyarray(py)))
    }

    /// For an array: whether its layout made the call copy it (`False`: read in place). A test
    /// hook; `None` for files, bytes and point lists.
    #[getter(_input_copied)]
    fn input_copied(&self) -> Option<bool> {
        self.traced.input_copied
    }

    /// The vertices as dicts `{"id", "x", "y", "degree", "width"}` (the JSON's fields; with
    /// `"z"` for a point set in space).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (id, v) in self.graph().vertices.iter().enumerate() {
            let dict = PyDict::new(py);
            dict.set_item("id", id)?;
            dict.set_item("x", v.pos[0])?;
            dict.set_item("y", v.pos[1])?;
            if let Some(space) = &self.traced.space {
                dict.set_item("z", space.graph.vertices[id].pos[2])?;
            }
            dict.set_item("degree", v.degree)?;
            dict.set_item("width", v.width)?;
            list.append(dict)?;
        }
        Ok(list)
    }

    /// The edges as dicts `{"id", "from", "to", "length", "points", "widths", "directions"}`.
    #[getter]
    fn edges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (id, e) in self.graph().edges.iter().enumerate() {
            let dict = PyDict::new(py);
            dict.set_item("id", id)?;
            dict.set_item("from", e.from)?;
            dict.set_item("to", e.to)?;
            dict.set_item("length", e.length())?;
            match &self.traced.space {
                Some(space) => {
                    let edge = &space.graph.edges[id];
                    let points = edge.points.iter().map(|p| p.to_vec());
                    let directions = tangents(&edge.points).into_iter().map(|t| t.to_vec());
                    dict.set_item("points", PyList::new(py, points)?)?;
                    dict.set_item("widths", PyList::new(py, &e.widths)?)?;
                    dict.set_item("directions", PyList::new(py, directions)?)?;
                }
                None => {
                    dict.set_item("points", pairs(py, &e.points)?)?;
                    dict.set_item("widths", PyList::new(py, &e.widths)?)?;
                    dict.set_item("directions", pairs(py, &e.directions)?)?;
                }
            }
            list.append(dict)?;
        }
        Ok(list)
    }

    /// Pen strokes (edges chained straight through crossings) as dicts `{"id", "edges",
    /// "reversed", "closed", "length", "points", "widths"}`.
    #[getter]
    fn strokes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for (id, s) in self.traced.strokes.iter().enumerate() {
            let dict = PyDict::new(py);
            dict.set_item("id", id)?;
            dict.set_item("edges", PyList::new(py, &s.edges)?)?;
            dict.set_item("reversed", PyList::new(py, &s.reversed)?)?;
            dict.set_item("closed", s.closed)?;
            dict.set_item("length", s.length())?;
            dict.set_item("points", pairs(py, &s.points)?)?;
            dict.set_item("widths", PyList::new(py, &s.widths)?)?;
            list.append(dict)?;
        }
        Ok(list)
    }

    /// Fingerprint minutiae (ridge endings and bifurcations away from the print's border) as
    /// dicts `{"kind", "vertex", "x", "y", "direction", "width"}`, with `"quality"` (0-100) when
    /// the fingerprint front end traced them (`fingerprint=True`); computed on first use.
    #[getter]
    fn minutiae<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for m in self.minutiae_list(py) {
            let dict = PyDict::new(py);
            let kind = match m.kind {
                MinutiaKind::Ending => "ending",
                MinutiaKind::Bifurcation => "bifurcation",
            };
            dict.set_item("kind", kind)?;
            dict.set_item("vertex", m.vertex)?;
            dict.set_item("x", m.pos[0])?;
            dict.set_item("y", m.pos[1])?;
            dict.set_item("direction", m.direction)?;
            dict.set_item("width", m.width)?;
            if let Some(quality) = m.quality {
                dict.set_item("quality", quality)?;
            }
            list.append(dict)?;
        }
        Ok(list)
    }

    /// Counts: `vertices`, `edges`, `endpoints`, `junctions`, `components`, `cycles`.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let graph = self.graph();
        let dict = PyDict::new(py);
        dict.set_item("vertices", graph.vertices.len())?;
        dict.set_item("edges", graph.edges.len())?;
        dict.set_item("endpoints", graph.endpoints().count())?;
        dict.set_item("junctions", graph.junctions().count())?;
        dict.set_item("components", graph.components())?;
        dict.set_item("cycles", graph.cycles())?;
        Ok(dict)
    }

    /// What the front end decided for an image, as the JSON's `decisions` (unrounded):
    /// `polarity`, `polarity_confidence`, `threshold` (method and level or window),
    /// `stroke_width`, `uneven_light`, `dropout`; `None` for a mask or a point list.
    #[getter]
    fn decisions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::report::decisions(py, self.traced.decisions.as_ref())
    }

    /// What is probably wrong with the result, as dicts `{"code", "message"}` (the JSON's
    /// `warnings`): `code` is a stable name (`polarity_uncertain`, `speckle`, ...), `message`
    /// says what to try.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        crate::report::warnings(py, &self.traced.warnings)
    }

    /// The minutiae as NIST `.xyt` lines (`x y theta quality`, docs/fingerprints.md, "Outputs"),
    /// byte for byte what `ridgeline INPUT -o out.xyt` writes with the same parameters.
    fn to_xyt(&self, py: Python<'_>) -> String {
        ridgeline::export::xyt::to_string(self.minutiae_list(py), self.graph().height)
    }

    /// The minutiae as an ISO/IEC 19794-2:2005 finger minutiae record, what `ridgeline INPUT -o
    /// out.ist` writes: at most 255 minutiae (those of highest quality when there are more), at
    /// `dpi`, else the resolution the image file states, else 500.
    #[pyo3(signature = (*, dpi = None))]
    fn to_iso<'py>(
        &self,
        py: Python<'py>,
        dpi: Option<f64>,
    ) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        use ridgeline::export::iso19794::{best_for_record, to_bytes};
        let kept = best_for_record(self.minutiae_list(py));
        let graph = self.graph();
        if let Some(d) = dpi.filter(|d| !(d.is_finite() && *d > 0.0 && *d / 2.54 <= 65535.0)) {
            return Err(crate::errors::parameter(
                py,
                format!("invalid parameter dpi: must be > 0 and at most 166458, got {d}"),
                "dpi",
            ));
        }
        let dpi = dpi.or(self.traced.resolution).unwrap_or(500.0);
        let bytes = to_bytes(&kept, graph.width, graph.height, dpi)
            .map_err(|err| crate::errors::to_py(py, err))?;
        Ok(pyo3::types::PyBytes::new(py, &bytes))
    }

    /// The JSON document, byte for byte what `ridgeline INPUT -o out.json` writes with the same
    /// parameters and flags (`minutiae=True` is `--minutiae`, `curves=True` is `--curves`).
    #[pyo3(signature = (*, pretty = false, minutiae = false, curves = false, curve_tolerance = None, corner_angle = None))]
    fn to_json(
        &self,
        py: Python<'_>,
        pretty: bool,
        minutiae: bool,
        curves: bool,
        curve_tolerance: Option<f64>,
        corner_angle: Option<f64>,
    ) -> PyResult<String> {
        let options = curves
            .then(|| curve_options(curve_tolerance, corner_angle))
            .transpose()?;
        let marks = minutiae.then(|| self.minutiae_list(py));
        Ok(py.detach(|| {
            let curves = options.map(|options| fit_edges(self.graph(), &options));
            self.json_text(pretty, marks, curves.as_deref())
        }))
    }

    /// The SVG drawing, as `ridgeline INPUT -o out.svg` writes it with the same flags:
    /// `image=False` is `--no-image`, `vertices=False` `--no-vertices`, `line_width` `--line-width`,
    /// `widths` `--width`, `strokes` `--strokes`, `minutiae` `--minutiae`, `curves` `--curves`.
    #[pyo3(signature = (*, image = true, vertices = true, line_width = None, widths = false, strokes = false, minutiae = false, curves = false, curve_tolerance = None, corner_angle = None))]
    #[allow(clippy::too_many_arguments)]
    fn to_svg(
        &self,
        py: Python<'_>,
        image: bool,
        vertices: bool,
        line_width: Option<f64>,
        widths: bool,
        strokes: bool,
        minutiae: bool,
        curves: bool,
        curve_tolerance: Option<f64>,
        corner_angle: Option<f64>,
    ) -> PyResult<String> {
        if self.traced.space.is_some() {
            return Err(PyValueError::new_err(
                "the points are in space (x y z), and SVG draws the plane: use to_json(), \
                 or the arrays (point_xy has the z column)",
            ));
        }
        let options = curves
            .then(|| curve_options(curve_tolerance, corner_angle))
            .transpose()?;
        let marks = minutiae.then(|| self.minutiae_list(py));
        // A caller's array is read (with the GIL) into the library's gray image, a mask's ink
        // black on white.
        let from_array: Option<GrayImage> = match (&self.traced.backdrop, image) {
            (Backdrop::Array(array), true) => {
                let array = array.bind(py).cast::<PyArray2<u8>>()?.readonly();
                let view = array.as_array();
                let (rows, columns) = view.dim();
                let pixels: Vec<u8> = view.iter().copied().collect();
                GrayImage::from_raw(columns as u32, rows as u32, pixels)
            }
            (Backdrop::MaskArray(array), true) => {
                let array = array.bind(py).cast::<PyArray2<bool>>()?.readonly();
                let view = array.as_array();
                let (rows, columns) = view.dim();
                let pixels: Vec<u8> = view.iter().map(|&ink| if ink { 0 } else { 255 }).collect();
                GrayImage::from_raw(columns as u32, rows as u32, pixels)
            }
            _ => None,
        };
        Ok(py.detach(|| {
            let backdrop = match (&self.traced.backdrop, image) {
                (_, false) | (Backdrop::None, _) => None,
                (Backdrop::Encoded { bytes, mime }, true) => {
                    Some(svg::Backdrop::Encoded { bytes, mime })
                }
                (Backdrop::Color(picture), true) => Some(svg::Backdrop::Color(picture)),
                (Backdrop::Gray(gray), true) => Some(svg::Backdrop::Gray(gray)),
                (Backdrop::Array(_) | Backdrop::MaskArray(_), true) => {
                    from_array.as_ref().map(svg::Backdrop::Gray)
                }
            };
            let chained = strokes.then_some(self.traced.strokes.as_slice());
            // Curves follow what is drawn: one list per stroke with strokes, else per edge.
            let curves = options.map(|options| match chained {
                Some(chained) => chained
                    .iter()
                    .map(|s| fit_beziers(&s.points, options.tolerance, options.corner_angle_deg))
                    .collect::<Vec<_>>(),
                None => fit_edges(self.graph(), &options),
            });
            let features = Features::default()
                .with_strokes(chained)
                .with_minutiae(marks)
                .with_curves(curves.as_deref());
            let svg_options = SvgOptions::default()
                .with_show_vertices(vertices)
                .with_stroke_width(line_width)
                .with_show_widths(widths)
                .with_fit_canvas(self.traced.kind == Kind::Points);
            svg::to_string_with(self.graph(), backdrop, &svg_options, &features)
        }))
    }

    /// The graph as a `networkx.MultiGraph` (networkx is imported here, so it is needed only
    /// for this): one node per vertex (`pos`, `degree`, `width`), one edge per edge, keyed by
    /// its id (`points` and `widths` as numpy arrays, `length`).
    fn to_networkx<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("ridgeline._convert")?
            .call_method1("to_networkx", (slf,))
    }

    /// The branch table as a `pandas.DataFrame` (pandas is imported here, so it is needed only
    /// for this): one row per edge, in the columns of skan's `summarize` (`skeleton-id`,
    /// `node-id-src`, `node-id-dst`, `branch-distance`, `branch-type`, `image-coord-*`,
    /// `euclidean-distance`) and `kind`, `degree-src`, `degree-dst`, `mean-width`.
    fn to_dataframe<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("ridgeline._convert")?
            .call_method1("to_dataframe", (slf,))
    }

    fn __repr__(&self) -> String {
        let graph = self.graph();
        let source = match (&self.source_path, self.traced.page) {
            (Some(path), Some((number, count))) if count > 1 => {
                format!("{path} page {number}/{count}, ")
            }
            (Some(path), _) => format!("{path}, "),
            _ => String::new(),
        };
        format!(
            "<ridgeline.Trace {source}{}x{}: {} vertices, {} edges, {} junctions>",
            graph.width,
            graph.height,
            graph.vertices.len(),
            graph.edges.len(),
            graph.junctions().count()
        )
    }
}
