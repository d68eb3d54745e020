//! The compiled part of the Python package `ridgeline` (`ridgeline._ridgeline`): tracing an image,
//! its pages or a point list with the GIL released, and the [`result::Trace`] the Python code
//! reads. The public functions, their docstrings and signatures live in `ridgeline/__init__.py`;
//! this module takes the keyword arguments as one dict.
//!
//! Everything that takes time runs inside `Python::detach` (the GIL released): reading the file,
//! decoding, tracing, chaining strokes. A numpy array is read in place where its layout allows
//! (`gray_in_place`, and C-order bool masks), else copied there. Threads
//! of one process therefore trace in parallel; `threads=n` runs a call on a pool of `n` threads
//! (the library otherwise spreads a large page over every core, which is what one call wants and
//! not what many calls side by side want).

mod errors;
mod params;
mod report;
mod result;

use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::Arc;
use std::time::Instant;

use numpy::ndarray::ArrayView2;
use numpy::{PyArray2, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict, PyList, PyMemoryView, PyString};
use ridgeline::raster::Picture;
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::{GrayImage, GrayView, MaskView, Params};

use result::{Backdrop, Kind, Trace, Traced};

/// What `trace` was given, read far enough to let go of the GIL.
enum Input<'a> {
    /// A 2-D uint8 array (gray levels) or bool array (ink mask), as a view of its memory.
    Gray(ArrayView2<'a, u8>),
    Mask(ArrayView2<'a, bool>),
    /// Encoded image bytes (shared: an SVG shows them as they are).
    Bytes(Arc<Vec<u8>>),
    /// A file to read.
    Path(PathBuf),
}

/// Reads an array's dtype and shape, or the bytes, or the path, refusing anything else with a
/// `TypeError` that says what is accepted.
fn classify<'py>(image: &Bound<'py, PyAny>) -> PyResult<Classified<'py>> {
    if let Ok(array) = image.cast::<PyUntypedArray>() {
        let shape = array.shape().to_vec();
        let dtype = array.dtype().to_string();
        if array.ndim() != 2 {
            return Err(PyValueError::new_err(format!(
                "expected a 2-D array (rows x columns) of gray levels or ink flags, got shape {shape:?}; \
                 convert colour to gray first (for example img.mean(axis=2).astype(numpy.uint8))"
            )));
        }
        if let Ok(gray) = image.cast::<PyArray2<u8>>() {
            return Ok(Classified::Gray(gray.readonly()));
        }
        if let Ok(mask) = image.cast::<PyArray2<bool>>() {
            return Ok(Classified::Mask(mask.readonly()));
        }
        return Err(PyTypeError::new_err(format!(
            "expected a uint8 array (gray levels 0-255) or a bool array (True = ink), got dtype {dtype}; \
             for example (img * 255).astype(numpy.uint8) for floats in [0, 1]"
        )));
    }
    if let Ok(bytes) = image.cast::<PyBytes>() {
        return Ok(Classified::Bytes(bytes.as_bytes().to_vec()));
    }
    if let Ok(bytes) = image.cast::<PyByteArray>() {
        return Ok(Classified::Bytes(bytes.to_vec()));
    }
    if image.is_instance_of::<PyMemoryView>() {
        let bytes: Vec<u8> = image
            .py()
            .import("builtins")?
            .getattr("bytes")?
            .call1((image,))?
            .extract()?;
        return Ok(Classified::Bytes(bytes));
    }
    if let Some(path) = path_of(image)? {
        return Ok(Classified::Path(path));
    }
    Err(PyTypeError::new_err(format!(
        "expected a 2-D numpy array (uint8 or bool), encoded image bytes, or a path, got {}",
        image.get_type().name()?
    )))
}

/// A `str` or `os.PathLike` as a path.
fn path_of(value: &Bound<'_, PyAny>) -> PyResult<Option<PathBuf>> {
    if value.is_instance_of::<PyString>() || value.hasattr("__fspath__")? {
        return Ok(Some(value.extract()?));
    }
    Ok(None)
}

/// [`Input`] with the numpy borrows that keep its views valid.
enum Classified<'py> {
    Gray(numpy::PyReadonlyArray2<'py, u8>),
    Mask(numpy::PyReadonlyArray2<'py, bool>),
    Bytes(Vec<u8>),
    Path(PathBuf),
}

impl Classified<'_> {
    /// The input, borrowing the arrays and taking the bytes (read once).
    fn input(&mut self) -> Input<'_> {
        match self {
            Classified::Gray(array) => Input::Gray(array.as_array()),
            Classified::Mask(array) => Input::Mask(array.as_array()),
            Classified::Bytes(bytes) => Input::Bytes(Arc::new(std::mem::take(bytes))),
            Classified::Path(path) => Input::Path(std::mem::take(path)),
        }
    }
}

/// The pixels of a uint8 array in place: rows of unit column stride a positive row stride apart
/// (C order, or rows or columns cut from a C-order array). `None` for other layouts (Fortran
/// order, every other column, flipped axes), which are copied.
fn gray_in_place<'a>(view: &ArrayView2<'a, u8>) -> Option<GrayView<'a>> {
    let (rows, columns) = view.dim();
    let (width, height) = (u32::try_from(columns).ok()?, u32::try_from(rows).ok()?);
    if let Some(packed) = view.to_slice() {
        return GrayView::new(packed, width, height, columns);
    }
    let [row_stride, column_stride] = [view.strides()[0], view.strides()[1]];
    if column_stride != 1 && columns > 1 {
        return None;
    }
    let row_stride = usize::try_from(row_stride).ok().filter(|&s| s >= columns)?;
    // `to_slice` took every array with fewer than two rows or no pixels.
    let span = (rows - 1).checked_mul(row_stride)?.checked_add(columns)?;
    // SAFETY: the first and the last pixel lie in the array's one buffer (numpy allocates each
    // array's data as one block, and a view shares its base's), so the `span` bytes from the first
    // pixel to the last are inside that block and initialized. Bytes between the rows may belong
    // to the rest of the base array; `GrayView` never reads them. The numpy readonly borrow held
    // by the caller keeps the buffer alive for `'a` and stops other Rust code from writing to it;
    // Python code in another thread could still write to it, as to any array that native code
    // reads with the GIL released (`to_slice` of a C-order array has the same exposure).
    let pixels = unsafe { std::slice::from_raw_parts(view.as_ptr(), span) };
    GrayView::new(pixels, width, height, row_stride)
}

/// The row-major copy of a 2-D view that [`gray_in_place`] or a mask cannot read in place.
fn row_major<T: Copy>(view: &ArrayView2<'_, T>) -> Vec<T> {
    view.iter().copied().collect()
}

fn dimensions<T>(view: &ArrayView2<'_, T>) -> ridgeline::Result<(u32, u32)> {
    let (rows, columns) = view.dim();
    match (u32::try_from(columns), u32::try_from(rows)) {
        (Ok(width), Ok(height)) => Ok((width, height)),
        _ => Err(ridgeline::Error::Limit {
            what: "image side",
            actual: rows.max(columns) as u64,
            limit: u64::from(u32::MAX),
            flag: "--max-side",
        }),
    }
}

/// Runs `work` on a pool of `threads` threads, or on the global pool. Each calling thread keeps
/// its own pools: two Python threads sharing a pool of one thread would take turns on it.
fn on_pool<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> T {
    thread_local! {
        static POOLS: RefCell<Vec<(usize, Rc<rayon::ThreadPool>)>> = const { RefCell::new(Vec::new()) };
    }
    let Some(threads) = threads else {
        return work();
    };
    let pool = POOLS.with(|pools| {
        let mut pools = pools.borrow_mut();
        if let Some((_, pool)) = pools.iter().find(|(n, _)| *n == threads) {
            return Some(Rc::clone(pool));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("ridgeline-{i}"))
            .build()
            .ok()
            .map(Rc::new)?;
        pools.push((threads, Rc::clone(&pool)));
        Some(pool)
    });
    match pool {
        Some(pool) => pool.install(work),
        // The threads could not be started: the global pool still traces.
        None => work(),
    }
}

fn check_threads(threads: Option<usize>) -> PyResult<()> {
    if threads == Some(0) {
        return Err(PyValueError::new_err(
            "threads must be at least 1 (or None for every core)",
        ));
    }
    Ok(())
}

/// Runs `work` with the GIL released, on the pool `threads` asks for, turning a panic into a
/// `RuntimeError` and a library error into its exception.
fn detached<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    work: impl FnOnce() -> ridgeline::Result<T> + Send,
) -> PyResult<T> {
    let outcome = py.detach(|| catch_unwind(AssertUnwindSafe(|| on_pool(threads, work))));
    match outcome {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(err)) => Err(errors::to_py(py, err)),
        Err(panic) => Err(errors::internal(panic)),
    }
}

/// One traced page, before it becomes a Python object.
fn traced(
    trace: ridgeline::Trace,
    params: &Params,
    started: Instant,
    decode: std::time::Duration,
) -> Traced {
    let chained = strokes(&trace.graph, &StrokeOptions::default());
    Traced {
        print_minutiae: trace.fingerprint.map(|print| print.minutiae),
        resolution: None,
        decisions: trace.decisions,
        warnings: trace.warnings,
        binary: trace.binary,
        strokes: chained,
        graph: trace.graph,
        params: params.clone(),
        point_count: trace.point_count,
        timings: trace.timings,
        decode,
        native: started.elapsed(),
        page: None,
        backdrop: Backdrop::None,
        kind: Kind::Image,
        input_copied: None,
    }
}

/// Decodes and traces the pages of encoded `bytes`: every page, or only the first.
fn trace_encoded(
    bytes: Arc<Vec<u8>>,
    params: &Params,
    all: bool,
    started: Instant,
) -> ridgeline::Result<Vec<Traced>> {
    let pages = ridgeline::raster::pages(&bytes, &params.limits)?.with_pictures(true);
    let count = pages.page_count();
    let resolution = pages.resolution();
    let mut out = Vec::new();
    let mut clock = Instant::now();
    for page in pages {
        let page = page?;
        let decode = clock.elapsed();
        let trace = ridgeline::trace_image(&page.gray, params)?;
        let mut one = traced(trace, params, started, decode);
        one.page = Some((page.number, count));
        one.resolution = resolution;
        one.backdrop = match page.picture {
            Picture::Original { mime } => Backdrop::Encoded {
                bytes: Arc::clone(&bytes),
                mime,
            },
            Picture::Color(image) => Backdrop::Color(image),
            Picture::Gray => Backdrop::Gray(page.gray),
        };
        out.push(one);
        if !all {
            break;
        }
        clock = Instant::now();
    }
    Ok(out)
}

fn trace_input(input: Input<'_>, params: &Params, all: bool) -> ridgeline::Result<Vec<Traced>> {
    let started = Instant::now();
    match input {
        Input::Gray(view) => {
            let (width, height) = dimensions(&view)?;
            let copy;
            let (gray, copied) = match gray_in_place(&view) {
                Some(gray) => (gray, false),
                None => {
                    copy =
                        GrayImage::from_raw(width, height, row_major(&view)).ok_or_else(|| {
                            ridgeline::Error::InvalidParams("array shape and size disagree".into())
                        })?;
                    (GrayView::from(&copy), true)
                }
            };
            let trace = ridgeline::trace_image(gray, params)?;
            let mut one = traced(trace, params, started, Default::default());
            one.input_copied = Some(copied);
            Ok(vec![one])
        }
        Input::Mask(view) => {
            let (width, height) = dimensions(&view)?;
            // numpy's bool is one byte holding 0 or 1, Rust's `bool`: a C-order array is the
            // mask's row-major flags as they are.
            let copy;
            let (ink, copied) = match view.to_slice() {
                Some(ink) => (ink, false),
                None => {
                    copy = row_major(&view);
                    (&copy[..], true)
                }
            };
            let mask = MaskView { width, height, ink };
            let trace = ridgeline::trace_binary(mask, params)?;
            let mut one = traced(trace, params, started, Default::default());
            one.input_copied = Some(copied);
            Ok(vec![one])
        }
        Input::Bytes(bytes) => trace_encoded(bytes, params, all, started),
        Input::Path(path) => {
            let bytes =
                std::fs::read(&path).map_err(|source| ridgeline::Error::Io { path, source })?;
            trace_encoded(Arc::new(bytes), params, all, started)
        }
    }
}

/// The source path recorded in the JSON: the one given, else the path traced (as given).
fn recorded_path(
    image: &Bound<'_, PyAny>,
    source_path: Option<String>,
) -> PyResult<Option<String>> {
    if source_path.is_some() {
        return Ok(source_path);
    }
    Ok(path_of(image)?.map(|path| path.to_string_lossy().into_owned()))
}

/// `ridgeline.trace` and `ridgeline.trace_pages` without their Python signature: `all` traces
/// every page of a multi-page TIFF.
fn trace_any(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    source_path: Option<String>,
    threads: Option<usize>,
    params: Option<&Bound<'_, PyDict>>,
    all: bool,
) -> PyResult<Vec<Trace>> {
    check_threads(threads)?;
    let params = params::from_kwargs(py, params)?;
    let source_path = recorded_path(image, source_path)?;
    let mut classified = classify(image)?;
    // The Trace of an array reads it again for `to_svg()`, `mask` and `minutiae` (it keeps no
    // copy of its pixels).
    let array = match &classified {
        Classified::Gray(_) => Some(Backdrop::Array(image.clone().unbind())),
        Classified::Mask(_) => Some(Backdrop::MaskArray(image.clone().unbind())),
        _ => None,
    };
    let input = classified.input();
    let pages = detached(py, threads, || trace_input(input, &params, all))?;
    drop(classified);
    Ok(pages
        .into_iter()
        .map(|mut page| {
            if let Some(array) = &array {
                page.backdrop = array.clone_ref(py);
            }
            Trace::new(page, source_path.clone())
        })
        .collect())
}

#[pyfunction]
#[pyo3(signature = (image, source_path, threads, params))]
fn trace(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    source_path: Option<String>,
    threads: Option<usize>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Trace> {
    let mut pages = trace_any(py, image, source_path, threads, params, false)?;
    Ok(pages.remove(0))
}

#[pyfunction]
#[pyo3(signature = (image, source_path, threads, params))]
fn trace_pages<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    source_path: Option<String>,
    threads: Option<usize>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyList>> {
    let pages = trace_any(py, image, source_path, threads, params, true)?;
    PyList::new(py, pages)
}

/// Point input: an N x 2 float64 array, or a point-list file read by the library's parser.
#[pyfunction]
#[pyo3(signature = (xy, source_path, threads, params))]
fn trace_points(
    py: Python<'_>,
    xy: &Bound<'_, PyAny>,
    source_path: Option<String>,
    threads: Option<usize>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Trace> {
    check_threads(threads)?;
    let params = params::from_kwargs(py, params)?;
    let source_path = recorded_path(xy, source_path)?;
    enum Source<'py> {
        Array(numpy::PyReadonlyArray2<'py, f64>),
        File(PathBuf),
    }
    enum Points<'a> {
        Array(ArrayView2<'a, f64>),
        File(PathBuf),
    }
    let source = match path_of(xy)? {
        Some(path) => Source::File(path),
        None => Source::Array(
            xy.cast::<PyArray2<f64>>()
                .map_err(|_| {
                    PyTypeError::new_err(
                        "expected an N x 2 float64 array (ridgeline.trace_points converts array-likes)",
                    )
                })?
                .readonly(),
        ),
    };
    // The array stays borrowed for the call: its points are read with the GIL released.
    let points = match &source {
        Source::Array(array) => {
            let view = array.as_array();
            if view.ncols() != 2 {
                return Err(PyValueError::new_err(format!(
                    "expected an N x 2 array of (x, y) points, got shape {:?}",
                    view.shape()
                )));
            }
            Points::Array(view)
        }
        Source::File(path) => Points::File(path.clone()),
    };
    let mut one = detached(py, threads, || {
        let started = Instant::now();
        let list = match points {
            Points::Array(view) => view
                .rows()
                .into_iter()
                .map(|row| [row[0], row[1]])
                .collect(),
            Points::File(path) => {
                let text = std::fs::read_to_string(&path)
                    .map_err(|source| ridgeline::Error::Io { path, source })?;
                ridgeline::point_list::parse(&text)?
            }
        };
        let trace = ridgeline::trace_points(&list, &params)?;
        Ok(traced(trace, &params, started, Default::default()))
    })?;
    drop(source);
    one.kind = Kind::Points;
    Ok(Trace::new(one, source_path))
}

/// Every keyword of `trace` with its default, in `Params`' field order.
#[pyfunction]
fn default_params(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    params::defaults(py)
}

/// The paper's own rules and values, as keywords.
#[pyfunction]
fn paper_params(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let defaults = params::cached_defaults(py)?;
    params::to_dict(py, &Params::paper(), Some(&defaults))
}

#[pymodule]
fn _ridgeline(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(trace, m)?)?;
    m.add_function(wrap_pyfunction!(trace_pages, m)?)?;
    m.add_function(wrap_pyfunction!(trace_points, m)?)?;
    m.add_function(wrap_pyfunction!(default_params, m)?)?;
    m.add_function(wrap_pyfunction!(paper_params, m)?)?;
    m.add_class::<Trace>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
