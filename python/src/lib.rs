//! The compiled part of the Python package `ridgeline` (`ridgeline._ridgeline`): tracing an image,
//! its pages or a point list with the GIL released, and the [`result::Trace`] the Python code
//! reads. The public functions, their docstrings and signatures live in `ridgeline/__init__.py`;
//! this module takes the keyword arguments as one dict.
//!
//! Everything that takes time runs inside `Python::detach` (the GIL released): reading the file,
//! decoding, tracing, chaining strokes. A uint8 gray array is read in place where its layout
//! allows (`gray_in_place`, and C-order bool masks), else copied there; colour, 16-bit and float
//! arrays are converted there once to 8-bit gray, as the same pixels in a file are
//! (`gray_of_pixels`). Threads
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

use numpy::ndarray::{ArrayView1, ArrayView2, ArrayViewD, Axis, Ix3};
use numpy::{
    PyArray2, PyArray3, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict, PyList, PyMemoryView, PyString};
use ridgeline::point_list::PointData;
use ridgeline::raster::Picture;
use ridgeline::strokes::{strokes, StrokeOptions};
use ridgeline::{GrayImage, GrayView, MaskView, Params};

use result::{Backdrop, Kind, Trace, Traced};

/// What `trace` was given, read far enough to let go of the GIL.
enum Input<'a> {
    /// A 2-D uint8 array (gray levels) or bool array (ink mask), as a view of its memory.
    Gray(ArrayView2<'a, u8>),
    Mask(ArrayView2<'a, bool>),
    /// Any other image array (colour, 16 bits, floats), converted once to gray.
    Pixels(PixelView<'a>),
    /// Encoded image bytes (shared: an SVG shows them as they are).
    Bytes(Arc<Vec<u8>>),
    /// A file to read.
    Path(PathBuf),
}

/// Reads an array's dtype and shape, or the bytes, or the path, refusing anything else with a
/// `TypeError` (or, for a shape that is no image, a `ValueError`) that says what is accepted.
fn classify<'py>(image: &Bound<'py, PyAny>) -> PyResult<Classified<'py>> {
    if let Ok(array) = image.cast::<PyUntypedArray>() {
        let shape = array.shape().to_vec();
        let dtype = array.dtype().to_string();
        let channels = match shape.len() {
            2 => 1,
            3 if (1..=4).contains(&shape[2]) => shape[2],
            _ => {
                return Err(PyValueError::new_err(format!(
                    "expected an image array: rows x columns (gray levels or ink flags) or rows x \
                     columns x 1-4 channels (gray, gray and alpha, RGB, RGBA), got shape {shape:?}"
                )))
            }
        };
        if let Ok(gray) = image.cast::<PyArray2<u8>>() {
            return Ok(Classified::Gray(gray.readonly()));
        }
        if let Ok(mask) = image.cast::<PyArray2<bool>>() {
            return Ok(Classified::Mask(mask.readonly()));
        }
        if channels == 1 {
            // rows x columns x 1: the gray levels with a unit axis, read like a 2-D array.
            if let Ok(gray) = image.cast::<PyArray3<u8>>() {
                return Ok(Classified::GrayAxis(gray.readonly()));
            }
        }
        let pixels = if let Ok(array) = image.cast::<PyArrayDyn<u8>>() {
            Some(Pixels::U8(array.readonly()))
        } else if let Ok(array) = image.cast::<PyArrayDyn<u16>>() {
            Some(Pixels::U16(array.readonly()))
        } else if let Ok(array) = image.cast::<PyArrayDyn<f32>>() {
            Some(Pixels::F32(array.readonly()))
        } else if let Ok(array) = image.cast::<PyArrayDyn<f64>>() {
            Some(Pixels::F64(array.readonly()))
        } else {
            None
        };
        if let Some(pixels) = pixels {
            return Ok(Classified::Pixels(pixels));
        }
        return Err(PyTypeError::new_err(format!(
            "expected an image array of dtype uint8 (0-255), uint16 (0-65535), float32 or float64 \
             (0-1), or bool (True = ink), got dtype {dtype}"
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
        "expected a numpy array (or an object with the array interface, such as a Pillow image), \
         encoded image bytes, or a path, got {}",
        image.get_type().name()?
    )))
}

/// The readonly borrow of an array of another dtype or shape than 2-D uint8, converted once to
/// the gray image the library traces.
enum Pixels<'py> {
    U8(numpy::PyReadonlyArrayDyn<'py, u8>),
    U16(numpy::PyReadonlyArrayDyn<'py, u16>),
    F32(numpy::PyReadonlyArrayDyn<'py, f32>),
    F64(numpy::PyReadonlyArrayDyn<'py, f64>),
}

/// A view of [`Pixels`].
enum PixelView<'a> {
    U8(ArrayViewD<'a, u8>),
    U16(ArrayViewD<'a, u16>),
    F32(ArrayViewD<'a, f32>),
    F64(ArrayViewD<'a, f64>),
}

impl Pixels<'_> {
    fn view(&self) -> PixelView<'_> {
        match self {
            Pixels::U8(array) => PixelView::U8(array.as_array()),
            Pixels::U16(array) => PixelView::U16(array.as_array()),
            Pixels::F32(array) => PixelView::F32(array.as_array()),
            Pixels::F64(array) => PixelView::F64(array.as_array()),
        }
    }
}

/// The gray image of rows x columns (x channels) pixels, as the same pixels saved as PNG decode
/// (`ridgeline::raster::gray_from_unit_pixels`: luminance, transparent pixels as paper). Integers
/// are scaled by their largest value; floats must lie in [0, 1].
fn gray_of_pixels(view: PixelView<'_>) -> ridgeline::Result<GrayImage> {
    match view {
        PixelView::U8(view) => gray_of_unit(view, |v| f32::from(v) / 255.0),
        PixelView::U16(view) => gray_of_unit(view, |v| f32::from(v) / 65535.0),
        // `check_floats` refused NaN and values outside [0, 1] before.
        PixelView::F32(view) => gray_of_unit(view, |v| v),
        PixelView::F64(view) => gray_of_unit(view, |v| v as f32),
    }
}

/// Refuses a float array whose values are not gray levels in [0, 1] with a `ValueError` naming
/// the first NaN or the range found.
fn check_floats(pixels: &Pixels<'_>) -> PyResult<()> {
    match pixels.view() {
        PixelView::F32(view) => check_unit_range(&view, |&v| f64::from(v)),
        PixelView::F64(view) => check_unit_range(&view, |&v| v),
        PixelView::U8(_) | PixelView::U16(_) => Ok(()),
    }
}

fn check_unit_range<T>(view: &ArrayViewD<'_, T>, value: impl Fn(&T) -> f64) -> PyResult<()> {
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (index, v) in view.indexed_iter() {
        let v = value(v);
        if v.is_nan() {
            return Err(PyValueError::new_err(format!(
                "the float image holds NaN (first at row {}, column {}); a float image holds \
                 gray levels in [0, 1]",
                index[0], index[1]
            )));
        }
        low = low.min(v);
        high = high.max(v);
    }
    if low < 0.0 || high > 1.0 {
        return Err(PyValueError::new_err(format!(
            "a float image holds gray levels in [0, 1], this one from {low} to {high}; scale it \
             (for example (img - img.min()) / (img.max() - img.min())) or give it as uint8 or uint16"
        )));
    }
    Ok(())
}

fn gray_of_unit<T: Copy>(
    view: ArrayViewD<'_, T>,
    unit: impl Fn(T) -> f32,
) -> ridgeline::Result<GrayImage> {
    let view = match view.ndim() {
        2 => view.insert_axis(Axis(2)),
        _ => view,
    };
    let view = view
        .into_dimensionality::<Ix3>()
        .map_err(|err| ridgeline::Error::InvalidParams(format!("image array: {err}")))?;
    let (rows, columns, channels) = view.dim();
    let (width, height) = dimensions(&view.index_axis(Axis(2), 0))?;
    let pixel = |lane: ArrayView1<'_, T>| -> [f32; 4] {
        let c = |i: usize| unit(lane[i]);
        match channels {
            1 => [c(0), c(0), c(0), 1.0],
            2 => [c(0), c(0), c(0), c(1)],
            3 => [c(0), c(1), c(2), 1.0],
            _ => [c(0), c(1), c(2), c(3)],
        }
    };
    let has_alpha = channels == 2 || channels == 4;
    debug_assert!(rows * columns * channels == view.len());
    let (gray, _) = ridgeline::raster::gray_from_unit_pixels(
        width,
        height,
        || view.lanes(Axis(2)).into_iter().map(pixel),
        has_alpha,
    )?;
    Ok(gray)
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
    /// Rows x columns x 1 uint8.
    GrayAxis(numpy::PyReadonlyArray3<'py, u8>),
    Pixels(Pixels<'py>),
    Mask(numpy::PyReadonlyArray2<'py, bool>),
    Bytes(Vec<u8>),
    Path(PathBuf),
}

impl Classified<'_> {
    /// The input, borrowing the arrays and taking the bytes (read once).
    fn input(&mut self) -> Input<'_> {
        match self {
            Classified::Gray(array) => Input::Gray(array.as_array()),
            Classified::GrayAxis(array) => {
                Input::Gray(array.as_array().index_axis_move(Axis(2), 0))
            }
            Classified::Pixels(pixels) => Input::Pixels(pixels.view()),
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
            field: "limits.max_side",
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
            .stack_size(ridgeline::WORKER_STACK_BYTES)
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
        space: None,
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
    let pages = ridgeline::raster::pages(&bytes, &params.front_end.limits)?.with_pictures(true);
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
        Input::Pixels(view) => {
            let gray = gray_of_pixels(view)?;
            let trace = ridgeline::trace_image(&gray, params)?;
            let mut one = traced(trace, params, started, Default::default());
            one.input_copied = Some(true);
            one.backdrop = Backdrop::Gray(gray);
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
    if let Classified::Pixels(pixels) = &classified {
        check_floats(pixels)?;
    }
    // The Trace of an array reads it again for `to_svg()`, `mask` and `minutiae` (it keeps no
    // copy of its pixels).
    let array = match &classified {
        Classified::Gray(_) => Some(Backdrop::Array(image.clone().unbind())),
        Classified::GrayAxis(_) => {
            // The SVG reads the gray levels as rows x columns: a view without the unit axis.
            let full = pyo3::types::PySlice::full(py);
            let plane = image.get_item((full.clone(), full, 0))?;
            Some(Backdrop::Array(plane.unbind()))
        }
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

/// Point input: an N x 2 or N x 3 float64 array, or a point file read by the library's reader
/// (`x y` or `x y z` lines, CSV, PLY, XYZ).
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
                        "expected an N x 2 or N x 3 float64 array (ridgeline.trace_points converts array-likes)",
                    )
                })?
                .readonly(),
        ),
    };
    // The array stays borrowed for the call: its points are read with the GIL released.
    let points = match &source {
        Source::Array(array) => {
            let view = array.as_array();
            if view.ncols() != 2 && view.ncols() != 3 {
                return Err(PyValueError::new_err(format!(
                    "expected an N x 2 or N x 3 array of (x, y) or (x, y, z) points, got shape {:?}",
                    view.shape()
                )));
            }
            Points::Array(view)
        }
        Source::File(path) => Points::File(path.clone()),
    };
    let mut one = detached(py, threads, || {
        let started = Instant::now();
        let data = match points {
            Points::Array(view) if view.ncols() == 3 => PointData::Space(
                view.rows()
                    .into_iter()
                    .map(|row| [row[0], row[1], row[2]])
                    .collect(),
            ),
            Points::Array(view) => PointData::Plane(
                view.rows()
                    .into_iter()
                    .map(|row| [row[0], row[1]])
                    .collect(),
            ),
            Points::File(path) => {
                let bytes = std::fs::read(&path).map_err(|source| ridgeline::Error::Io {
                    path: path.clone(),
                    source,
                })?;
                let extension = path.extension().and_then(|e| e.to_str());
                ridgeline::point_list::read(&bytes, extension)?
            }
        };
        match data {
            PointData::Plane(list) => {
                let trace = ridgeline::trace_points(&list, &params)?;
                Ok(traced(trace, &params, started, Default::default()))
            }
            PointData::Space(list) => {
                let space = ridgeline::trace_points3d(&list, &params)?;
                let plane = ridgeline::Trace {
                    graph: result::plane_view(&space.graph),
                    binary: None,
                    point_count: space.point_count,
                    stages: None,
                    timings: Default::default(),
                    decisions: None,
                    warnings: space.warnings.clone(),
                    dropout_share: None,
                    fingerprint: None,
                };
                let mut one = traced(plane, &params, started, Default::default());
                one.space = Some(space);
                Ok(one)
            }
        }
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
