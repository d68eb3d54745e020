"""ridgeline: raster images of strokes traced into stroke graphs (centerline polylines meeting at
junctions). Every parameter keyword is a field of the library's Params, spelled as in the
"parameters" object of the JSON output; docs/json.md explains each with its unit and range."""

import os
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._errors import (
    DecodeError as DecodeError,
    LimitError as LimitError,
    ParameterError as ParameterError,
    PointListError as PointListError,
    RidgelineError as RidgelineError,
)

__version__: str
__all__: List[str]

ImageInput = Union[
    npt.NDArray[np.uint8],
    npt.NDArray[np.uint16],
    npt.NDArray[np.float32],
    npt.NDArray[np.float64],
    npt.NDArray[np.bool_],
    npt.ArrayLike,  # anything with the array interface, such as a Pillow image
    bytes,
    bytearray,
    memoryview,
    str,
    "os.PathLike[str]",
]
FileInput = Union[bytes, bytearray, memoryview, str, "os.PathLike[str]"]
PointsInput = Union[npt.ArrayLike, str, "os.PathLike[str]"]

def default_params() -> Dict[str, Any]:
    """Every keyword parameter of trace() with its default, in the library's order."""

def paper_params() -> Dict[str, Any]:
    """The paper's own rules and values (the command line's --paper), as keywords."""

def trace(
    image: ImageInput,
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    # parameters (generated from default_params(): RIDGELINE_BLESS=1 pytest tests/test_stubs.py)
    threshold: Mapping[str, Any] = ...,  # default {'method': 'auto'}
    polarity: str = 'auto',
    limits: Mapping[str, Any] = ...,  # default {'max_pixels': 100000000, 'max_side': 65535, 'max_points': 50000000, 'max_pages': 1000}
    dropout: Any = None,
    dropout_fraction: float = 0.015,
    r_min_rule: str = 'stroke_width',
    r_min_factor: float = 1.0,
    r_max_factor: float = 3.0,
    r_growth: float = 1.25,
    linearity: float = 0.9,
    arms_test: bool = True,
    k: int = 5,
    cluster_rule: str = 'non_linear',
    cluster_link: float = 1.5,
    merge_span: float = 2.0,
    laplacian: str = 'held',
    smoothness: float = 1.0,
    anchor_weight: float = 10.0,
    weiszfeld_iterations: int = 20,
    spacing_factor: float = 1.0,
    cleanup: bool = True,
    skeleton: bool = True,
    min_area: int = 0,
    subpixel: bool = True,
    valleys: bool = True,
    reverse_grounds: bool = True,
    keep_regions: list[str] = [],
    ink_disks: bool = False,
    site_clusters: bool = False,
    dense_fit: bool = False,
    junctions_on_ink: bool = False,
    decide_by_ink: bool = False,
    cusps_by_ink: bool = False,
    fingerprint: Any = None,
    # end of parameters
) -> Trace:
    """Traces one image into its stroke graph, with the GIL released: a numpy array (uint8 or
    uint16 gray levels, float32/float64 in [0, 1], rows x columns or x 1-4 channels: gray, gray
    and alpha, RGB, RGBA; or a 2-D bool ink mask), anything with the array interface (a Pillow
    image), encoded image bytes, or a path. Read in place, without a copy: a 2-D uint8 array
    whose rows have unit column stride (C order, or rows and columns cut from a C-order array,
    or every n-th row), a C-order bool array; other uint8 layouts (Fortran order, column steps,
    flipped or transposed views) are copied first; colour, 16-bit and float arrays are converted
    once to 8-bit gray as the same pixels saved as PNG are (luminance, transparent pixels as
    paper). A float array with NaN or values outside [0, 1] is a ValueError. Every keyword but source_path and threads is a
    parameter of the library with the same name and default. Raises ParameterError, LimitError,
    DecodeError (ValueErrors), OSError for an unreadable file, TypeError for a wrong argument."""

def trace_pages(
    image: FileInput,
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    # parameters (generated from default_params(): RIDGELINE_BLESS=1 pytest tests/test_stubs.py)
    threshold: Mapping[str, Any] = ...,  # default {'method': 'auto'}
    polarity: str = 'auto',
    limits: Mapping[str, Any] = ...,  # default {'max_pixels': 100000000, 'max_side': 65535, 'max_points': 50000000, 'max_pages': 1000}
    dropout: Any = None,
    dropout_fraction: float = 0.015,
    r_min_rule: str = 'stroke_width',
    r_min_factor: float = 1.0,
    r_max_factor: float = 3.0,
    r_growth: float = 1.25,
    linearity: float = 0.9,
    arms_test: bool = True,
    k: int = 5,
    cluster_rule: str = 'non_linear',
    cluster_link: float = 1.5,
    merge_span: float = 2.0,
    laplacian: str = 'held',
    smoothness: float = 1.0,
    anchor_weight: float = 10.0,
    weiszfeld_iterations: int = 20,
    spacing_factor: float = 1.0,
    cleanup: bool = True,
    skeleton: bool = True,
    min_area: int = 0,
    subpixel: bool = True,
    valleys: bool = True,
    reverse_grounds: bool = True,
    keep_regions: list[str] = [],
    ink_disks: bool = False,
    site_clusters: bool = False,
    dense_fit: bool = False,
    junctions_on_ink: bool = False,
    decide_by_ink: bool = False,
    cusps_by_ink: bool = False,
    fingerprint: Any = None,
    # end of parameters
) -> List[Trace]:
    """Traces every page of an image file (a multi-page TIFF), one Trace per page."""

def trace_points(
    xy: PointsInput,
    /,
    *,
    source_path: Optional[str] = None,
    threads: Optional[int] = None,
    # parameters (generated from default_params(): RIDGELINE_BLESS=1 pytest tests/test_stubs.py)
    threshold: Mapping[str, Any] = ...,  # default {'method': 'auto'}
    polarity: str = 'auto',
    limits: Mapping[str, Any] = ...,  # default {'max_pixels': 100000000, 'max_side': 65535, 'max_points': 50000000, 'max_pages': 1000}
    dropout: Any = None,
    dropout_fraction: float = 0.015,
    r_min_rule: str = 'stroke_width',
    r_min_factor: float = 1.0,
    r_max_factor: float = 3.0,
    r_growth: float = 1.25,
    linearity: float = 0.9,
    arms_test: bool = True,
    k: int = 5,
    cluster_rule: str = 'non_linear',
    cluster_link: float = 1.5,
    merge_span: float = 2.0,
    laplacian: str = 'held',
    smoothness: float = 1.0,
    anchor_weight: float = 10.0,
    weiszfeld_iterations: int = 20,
    spacing_factor: float = 1.0,
    cleanup: bool = True,
    skeleton: bool = True,
    min_area: int = 0,
    subpixel: bool = True,
    valleys: bool = True,
    reverse_grounds: bool = True,
    keep_regions: list[str] = [],
    ink_disks: bool = False,
    site_clusters: bool = False,
    dense_fit: bool = False,
    junctions_on_ink: bool = False,
    decide_by_ink: bool = False,
    cusps_by_ink: bool = False,
    fingerprint: Any = None,
    # end of parameters
) -> Trace:
    """Traces an N x 2 array of (x, y) points or an N x 3 array of (x, y, z) points, or a point
    file (x y or x y z lines, CSV, PLY, XYZ)."""

class Trace:
    """One traced image or point list: the stroke graph as numpy arrays, as lists of dicts shaped
    like the JSON output, and as SVG, JSON and networkx."""

    @property
    def width(self) -> int:
        """Width of the image, px."""
    @property
    def height(self) -> int:
        """Height of the image, px."""
    @property
    def point_count(self) -> int:
        """Number of points traced: ink pixels, or points of the list."""
    @property
    def source_path(self) -> Optional[str]:
        """The source path recorded in the JSON."""
    @property
    def page(self) -> Optional[Tuple[int, int]]:
        """(number, count) of this page in its file; None for arrays and point lists."""
    @property
    def params(self) -> Dict[str, Any]:
        """Every parameter used, as keywords: trace(image, **t.params) traces the same."""
    @property
    def timings(self) -> Dict[str, float]:
        """Seconds per stage, decode, and native (the whole call with the GIL released)."""
    @property
    def vertex_xy(self) -> npt.NDArray[np.float64]:
        """Vertex positions, shape (V, 2), px."""
    @property
    def vertex_degree(self) -> npt.NDArray[np.int64]:
        """Vertex degrees, shape (V,)."""
    @property
    def vertex_width(self) -> npt.NDArray[np.float64]:
        """Local stroke width at each vertex, shape (V,), px."""
    @property
    def edge_vertices(self) -> npt.NDArray[np.int64]:
        """(from, to) vertex ids of each edge, shape (E, 2)."""
    @property
    def edge_offsets(self) -> npt.NDArray[np.int64]:
        """Shape (E + 1,): edge i's points are point_xy[edge_offsets[i]:edge_offsets[i + 1]]."""
    @property
    def edge_length(self) -> npt.NDArray[np.float64]:
        """Length of each edge's polyline, shape (E,), px."""
    @property
    def point_xy(self) -> npt.NDArray[np.float64]:
        """Every edge's polyline points, edge after edge, shape (P, 2), px."""
    @property
    def point_width(self) -> npt.NDArray[np.float64]:
        """Local stroke width at each point, shape (P,), px."""
    @property
    def point_direction(self) -> npt.NDArray[np.float64]:
        """Unit tangent at each point in the edge's direction of travel, shape (P, 2)."""
    @property
    def mask(self) -> Optional[npt.NDArray[np.bool_]]:
        """The foreground mask traced, shape (height, width) (for a bool array, a copy of the
        array as it is now); None for point lists."""
    @property
    def vertices(self) -> List[Dict[str, Any]]:
        """The vertices as dicts {"id", "x", "y", "degree", "width"}."""
    @property
    def edges(self) -> List[Dict[str, Any]]:
        """The edges as dicts {"id", "from", "to", "length", "points", "widths", "directions"}."""
    @property
    def strokes(self) -> List[Dict[str, Any]]:
        """Pen strokes as dicts {"id", "edges", "reversed", "closed", "length", "points", "widths"}."""
    @property
    def minutiae(self) -> List[Dict[str, Any]]:
        """Fingerprint minutiae as dicts {"kind", "vertex", "x", "y", "direction", "width"}, with
        "quality" (0-100) when traced with fingerprint=True."""
    @property
    def stats(self) -> Dict[str, int]:
        """Counts: vertices, edges, endpoints, junctions, components, cycles."""
    @property
    def decisions(self) -> Optional[Dict[str, Any]]:
        """What the front end decided for an image (polarity and its confidence, threshold,
        stroke width, dropout mode), as the JSON's decisions; None for masks and point lists."""
    @property
    def warnings(self) -> List[Dict[str, str]]:
        """What is probably wrong with the result: dicts {"code", "message"}, as in the JSON."""
    def to_json(
        self,
        *,
        pretty: bool = False,
        minutiae: bool = False,
        curves: bool = False,
        curve_tolerance: Optional[float] = None,
        corner_angle: Optional[float] = None,
    ) -> str:
        """The JSON document, byte for byte what the command line writes with the same flags."""
    def to_svg(
        self,
        *,
        image: bool = True,
        vertices: bool = True,
        line_width: Optional[float] = None,
        widths: bool = False,
        strokes: bool = False,
        minutiae: bool = False,
        curves: bool = False,
        curve_tolerance: Optional[float] = None,
        corner_angle: Optional[float] = None,
    ) -> str:
        """The SVG drawing, as the command line writes it with the same flags."""
    def to_xyt(self) -> str:
        """The minutiae as NIST .xyt lines (x y theta quality), as the command line's -o out.xyt."""
    def to_iso(self, *, dpi: Optional[float] = None) -> bytes:
        """The minutiae as an ISO/IEC 19794-2:2005 record (at most the 255 of highest quality), as
        the command line's -o out.ist; dpi default: the image file's, else 500."""
    def to_networkx(self) -> Any:
        """The graph as a networkx.MultiGraph (networkx imported on use)."""
    def to_dataframe(self) -> Any:
        """The branch table as a pandas.DataFrame (pandas imported on use), one row per edge in
        the columns of skan's summarize: skeleton-id, node-id-src, node-id-dst, branch-distance,
        branch-type (0 end-end, 1 junction-end, 2 junction-junction, 3 cycle), kind (the same in
        words), image-coord-src-0/-1 and image-coord-dst-0/-1 (row, column), euclidean-distance,
        degree-src, degree-dst, mean-width."""
    def __repr__(self) -> str: ...
