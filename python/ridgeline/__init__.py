"""ridgeline: raster images of strokes (scanned text, handwriting, Chinese characters,
fingerprints) traced into stroke graphs, the centerlines as polylines meeting at junctions.

>>> import numpy as np, ridgeline
>>> plus = np.full((80, 80), 255, np.uint8)
>>> plus[37:43, 10:70] = 0          # a horizontal bar, 6 px thick
>>> plus[10:70, 37:43] = 0          # and a vertical one
>>> t = ridgeline.trace(plus)
>>> t.stats["junctions"], t.stats["endpoints"], list(t.vertex_degree).count(4)
(1, 4, 1)

``trace`` reads a numpy array (uint8 or uint16 gray levels, floats in [0, 1], RGB or RGBA, or a
bool ink mask), anything with the array interface (a Pillow image), encoded image bytes, or a
path; ``trace_pages`` every page of a multi-page TIFF; ``trace_points`` an N x 2 point array or a
point-list file. Every parameter of the library is a keyword of the same name and default
(:func:`default_params` lists them; docs/json.md explains each), and the result, a :class:`Trace`,
gives the graph as numpy arrays, as lists of dicts, and as the command line's SVG and JSON.

The GIL is released while an image is read and traced, so threads trace in parallel.
"""

from __future__ import annotations

import inspect
import os
from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _ridgeline
from ._errors import (
    DecodeError,
    LimitError,
    ParameterError,
    PointListError,
    RidgelineError,
)
from ._ridgeline import Trace

__version__: str = _ridgeline.__version__

__all__ = [
    "trace",
    "trace_pages",
    "trace_points",
    "default_params",
    "paper_params",
    "Trace",
    "RidgelineError",
    "ParameterError",
    "LimitError",
    "DecodeError",
    "PointListError",
    "__version__",
]


def default_params() -> Dict[str, Any]:
    """Every keyword parameter of :func:`trace` with its default, in the library's order.

    The values are spelled as in the ``parameters`` object of the JSON output, so
    ``trace(image, **json.loads(doc)["parameters"])`` traces with what a document records.
    """
    return _ridgeline.default_params()


def paper_params() -> Dict[str, Any]:
    """The paper's own rules and values (the command line's ``--paper``), as keywords:
    ``trace(image, **paper_params())``; any of them can still be changed."""
    return _ridgeline.paper_params()


def trace(
    image: Union[np.ndarray, bytes, bytearray, memoryview, str, "os.PathLike[str]"],
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    **params: Any,
) -> Trace:
    """Traces one image into its stroke graph.

    ``image`` is a numpy array, encoded image bytes, or a path:

    - a 2-D uint8 array, gray levels (thresholded and its polarity found as ``threshold`` and
      ``polarity`` say), read with the GIL released and in place (without a copy) when its
      layout allows: rows with unit column stride a positive stride apart (C order, rows and
      columns cut from a C-order array, every n-th row; also rows x columns x 1). Other layouts
      (Fortran order, every n-th column, flipped or transposed views) are copied into C order;
    - a 2-D bool array, the ink mask (True = ink), traced as it is (in place in C order);
    - any other image array, converted once (with the GIL released) to the 8-bit gray image the
      same pixels saved as PNG give the command line: uint8 or uint16 (scaled by 255 or 65535)
      or float32/float64 gray levels in [0, 1] (NaN or values outside are refused), as rows x
      columns (gray) or rows x columns x channels (1 gray, 2 gray and alpha, 3 RGB, 4 RGBA).
      Colour becomes luminance (Rec. 709 weights); transparent pixels are paper (white, or black
      behind white ink), as in image files;
    - an object with the array interface (a Pillow image: modes L, LA, RGB, RGBA, I;16, F as
      numpy reads them; mode 1 as gray, palette and other modes converted to RGB(A) by Pillow
      first), read as ``numpy.asarray(image)``;
    - the bytes of an image file (PNG, JPEG, TIFF, BMP, PNM, GIF, WebP; of a multi-page TIFF the
      first page, see :func:`trace_pages`), or the path of one.

    The :class:`Trace` of a uint8 or bool array keeps a reference to it, not a copy:
    ``to_svg()`` (and for a mask ``mask`` and ``minutiae``) read it as it is when called; that
    of a converted array keeps the converted gray image.

    ``source_path`` is recorded as ``source.path`` in the JSON (default: the path traced, as
    given; ``None`` for arrays and bytes). ``threads`` runs the call on that many threads (default:
    every core; give 1 when many calls run side by side, in threads or processes).

    Every other keyword is a parameter of the library, with the same name and default (see
    :func:`default_params`); a dict given for ``limits`` or ``threshold`` updates the default one,
    so ``limits={"max_points": 10**6}`` keeps the other limits. ``fingerprint=True`` runs the
    fingerprint front end as the command line's ``--fingerprint`` does, and a dict for it updates
    that preset: ``fingerprint={"enhancement": "smoothing"}`` is ``--enhance smoothing``.

    Raises :class:`ParameterError` (a ``ValueError``) for a parameter out of range,
    :class:`LimitError` for an input beyond ``limits``, :class:`DecodeError` for bytes that are not
    an image, ``OSError`` for a file that cannot be read, ``TypeError`` for an argument of the wrong type (an array of another dtype: integers
    other than uint8 and uint16, complex) or an unknown keyword, ``ValueError`` for an array
    whose shape is no image or a float array with NaN or values outside [0, 1].
    """
    return _ridgeline.trace(_as_array(image), source_path, threads, params)


# Pillow modes numpy reads as the pixels they show (``np.asarray`` of a Pillow image): gray, gray
# and alpha, RGB, RGBA, 16-bit gray. Mode "1" reads as bool with True = white, the opposite of an
# ink mask, and palette or other colour models as indices or other channels: those are converted
# by Pillow itself first.
_PILLOW_AS_IS = {"L", "LA", "RGB", "RGBA", "I;16", "I;16L", "I;16B", "I;16N", "F"}


def _as_array(image: Any) -> Any:
    """An object with the array interface (a Pillow image, an xarray or dask array, ...) as a
    numpy array; arrays, bytes and paths as they are."""
    if isinstance(image, (np.ndarray, bytes, bytearray, memoryview, str, os.PathLike)):
        return image
    if type(image).__module__.startswith("PIL.") and hasattr(image, "convert"):
        mode = getattr(image, "mode", None)
        if mode == "1":
            image = image.convert("L")
        elif mode not in _PILLOW_AS_IS:
            transparent = "A" in (mode or "") or "transparency" in getattr(image, "info", {})
            image = image.convert("RGBA" if transparent else "RGB")
        return np.asarray(image)
    if any(hasattr(image, name) for name in ("__array_interface__", "__array_struct__", "__array__")):
        return np.asarray(image)
    return image


def trace_pages(
    image: Union[bytes, bytearray, memoryview, str, "os.PathLike[str]"],
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    **params: Any,
) -> List[Trace]:
    """Traces every page of an image file (a multi-page TIFF; one page for other formats), one
    :class:`Trace` per page, each recording its page in ``Trace.page`` and in its JSON, like the
    command line's ``name.json``, ``name.p2.json``, ... Arguments as for :func:`trace`;
    ``limits["max_pages"]`` bounds the page count before any page is decoded."""
    return _ridgeline.trace_pages(image, source_path, threads, params)


def trace_points(
    xy: Union[np.ndarray, Any, str, "os.PathLike[str]"],
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    **params: Any,
) -> Trace:
    """Traces a point set (the paper's own setting): ``xy`` is an N x 2 array-like of (x, y)
    coordinates or an N x 3 one of (x, y, z) (a set in space, the paper's Fig. 7), or the path of
    a point file (``x y`` or ``x y z`` lines, CSV with named columns, PLY, XYZ; read by the same
    reader as the command line). For a set in space the result's arrays carry the third column
    (``vertex_xy``, ``point_xy`` and ``point_direction`` have three), ``to_json()`` writes ``z``
    and ``to_svg()`` raises. Keywords as for :func:`trace` (``k`` is the number of nearest
    neighbours)."""
    if not isinstance(xy, (str, os.PathLike)):
        xy = np.asarray(xy, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] not in (2, 3):
            raise ValueError(
                f"expected an N x 2 or N x 3 array of (x, y) or (x, y, z) points, got shape {xy.shape}"
            )
    return _ridgeline.trace_points(xy, source_path, threads, params)


def _with_parameter_keywords(function):
    """Gives ``function`` the signature that lists every parameter keyword with its default, so
    ``help()``, ``inspect.signature`` and notebooks show them (the stub, ``__init__.pyi``, lists
    them for editors)."""
    signature = inspect.signature(function)
    fixed = [p for p in signature.parameters.values() if p.kind is not inspect.Parameter.VAR_KEYWORD]
    keywords = [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=value)
        for name, value in default_params().items()
    ]
    function.__signature__ = signature.replace(parameters=fixed + keywords)
    return function


for _function in (trace, trace_pages, trace_points):
    _with_parameter_keywords(_function)
del _function
