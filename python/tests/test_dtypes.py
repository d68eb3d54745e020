"""Image arrays as other libraries hand them over (OpenCV and Pillow: uint8 RGB and RGBA;
scikit-image: floats in [0, 1], uint16; Pillow images themselves) trace without a conversion by
hand, exactly as the same pixels saved as PNG trace on the command line."""

from pathlib import Path

import numpy as np
import pytest

import ridgeline
import support
from support import run_cli

PAGE = support.draw_page(420, 300, seed=5)
INK = PAGE < 128


def _colour_page(ink_rgb, paper_rgb, dtype=np.uint8):
    top = np.iinfo(dtype).max
    page = np.empty(PAGE.shape + (3,), np.float64)
    page[...] = paper_rgb
    page[INK] = ink_rgb
    # A gradient in the paper, so that the conversion's weights matter.
    page[..., 0] -= np.linspace(0.0, 0.1, PAGE.shape[1])[None, :]
    return np.round(np.clip(page, 0, 1) * top).astype(dtype)


def _with_alpha(rgb_or_gray, alpha):
    return np.concatenate([rgb_or_gray.reshape(PAGE.shape + (-1,)), alpha[..., None]], axis=2)


RGB8 = _colour_page((0.1, 0.15, 0.45), (0.98, 0.94, 0.86))
OPAQUE = np.full(PAGE.shape, 255, np.uint8)
# Ink on a transparent background (alpha 0 off the ink): the paper is white.
RGBA8 = _with_alpha(RGB8, np.where(INK, 255, 0).astype(np.uint8))
# White ink on transparent: the paper is black, the ink keeps its contrast.
WHITE_INK = _with_alpha(np.full(PAGE.shape + (3,), 255, np.uint8), np.where(INK, 255, 0).astype(np.uint8))
GRAY_ALPHA = _with_alpha(PAGE, np.where(INK, 255, 40).astype(np.uint8))
GRAY16 = (PAGE.astype(np.uint16) * 257 - np.linspace(0, 3000, PAGE.shape[1]).astype(np.uint16)[None, :] * (~INK))
RGB16 = _colour_page((0.1, 0.15, 0.45), (0.98, 0.94, 0.86), np.uint16)
RGBA16 = _with_alpha(RGB16, np.where(INK, 65535, 1000).astype(np.uint16))

AS_PNG = [
    ("RGB uint8", RGB8),
    ("RGBA uint8", RGBA8),
    ("white ink on transparent", WHITE_INK),
    ("gray and alpha uint8", GRAY_ALPHA),
    ("gray uint16", GRAY16),
    ("RGB uint16", RGB16),
    ("RGBA uint16", RGBA16),
]


def _cli_json(tmp_path: Path, pixels: np.ndarray) -> str:
    support.write_png(tmp_path / "page.png", pixels)
    run_cli("page.png", "-o", "page.json", cwd=tmp_path)
    return (tmp_path / "page.json").read_text()


@pytest.mark.parametrize("name,pixels", AS_PNG, ids=[n for n, _ in AS_PNG])
def test_arrays_trace_as_the_same_pixels_saved_as_png(tmp_path, name, pixels):
    expected = _cli_json(tmp_path, pixels)
    result = ridgeline.trace(pixels, source_path="page.png")
    assert result.to_json() == expected, name
    assert result.stats["edges"] > 15
    # Converted once into the gray image traced (and drawn under the SVG's centerlines).
    assert result._input_copied is True
    assert "<image" in result.to_svg()
    # Any layout of the same pixels traces the same.
    flipped = np.ascontiguousarray(pixels[::-1])[::-1]
    assert ridgeline.trace(flipped, source_path="page.png").to_json() == expected


def test_floats_in_0_1_trace_as_their_8_bit_levels(tmp_path):
    expected = _cli_json(tmp_path, PAGE)
    for dtype in (np.float64, np.float32):
        gray = (PAGE / 255.0).astype(dtype)
        assert ridgeline.trace(gray, source_path="page.png").to_json() == expected, dtype
        assert ridgeline.trace(np.asfortranarray(gray), source_path="page.png").to_json() == expected
    rgb_expected = _cli_json(tmp_path, RGB8)
    rgb = (RGB8 / 255.0).astype(np.float32)
    assert ridgeline.trace(rgb, source_path="page.png").to_json() == rgb_expected
    rgba = (RGBA8 / 255.0).astype(np.float64)
    assert ridgeline.trace(rgba, source_path="page.png").to_json() == _cli_json(tmp_path, RGBA8)


def test_gray_with_a_unit_channel_axis_is_read_in_place():
    expected = ridgeline.trace(PAGE, source_path="a")
    result = ridgeline.trace(PAGE[:, :, None], source_path="a")
    assert result._input_copied is False
    assert result.to_json() == expected.to_json()
    assert result.to_svg() == expected.to_svg()


def test_a_colour_page_traces_like_its_gray_one():
    gray = ridgeline.trace(PAGE)
    colour = ridgeline.trace(np.repeat(PAGE[:, :, None], 3, axis=2))
    opaque = ridgeline.trace(_with_alpha(np.repeat(PAGE[:, :, None], 3, axis=2), OPAQUE))
    assert colour.to_json() == gray.to_json() == opaque.to_json()


def test_pillow_images_are_read_through_the_array_interface():
    Image = pytest.importorskip("PIL.Image")
    for pixels in (PAGE, RGB8, RGBA8, GRAY_ALPHA):
        assert ridgeline.trace(Image.fromarray(pixels)).to_json() == ridgeline.trace(pixels).to_json()
    # Mode "1" reads as bool with True = white: traced as the gray page it shows, not inverted.
    bilevel = Image.fromarray(PAGE).convert("1", dither=Image.Dither.NONE)
    shown = np.asarray(bilevel.convert("L"))
    assert (shown[INK] == 0).all()
    assert ridgeline.trace(bilevel).to_json() == ridgeline.trace(shown).to_json()
    # A palette image: the colours it shows, not its palette indices.
    palette = Image.fromarray(RGB8).quantize(8)
    shown = np.asarray(palette.convert("RGB"))
    traced = ridgeline.trace(palette)
    assert traced.to_json() == ridgeline.trace(shown).to_json()
    assert traced.stats["edges"] > 15


def test_other_objects_with_the_array_interface():
    class Wrapped:
        def __init__(self, array):
            self.__array_interface__ = array.__array_interface__
            self._keep = array

    assert ridgeline.trace(Wrapped(RGB8)).to_json() == ridgeline.trace(RGB8).to_json()


REFUSED = [
    ("float above 1", PAGE.astype(np.float64), ValueError, r"\[0, 1\], this one from 0 to 255"),
    ("negative float", PAGE / 255.0 - 0.5, ValueError, r"\[0, 1\]"),
    ("NaN", np.where(INK, np.nan, 1.0), ValueError, r"NaN \(first at row \d+, column \d+\)"),
    ("int32", PAGE.astype(np.int32), TypeError, "uint8.*uint16.*float32.*got dtype int32"),
    ("int64 RGB", RGB8.astype(np.int64), TypeError, "got dtype int64"),
    ("complex", PAGE.astype(np.complex64), TypeError, "got dtype complex64"),
    ("five channels", np.zeros((10, 10, 5), np.uint8), ValueError, r"1-4 channels.*\[10, 10, 5\]"),
    ("1-D", np.zeros(10, np.uint8), ValueError, r"got shape \[10\]"),
]


@pytest.mark.parametrize("name,array,error,pattern", REFUSED, ids=[n for n, *_ in REFUSED])
def test_what_is_refused_says_why(name, array, error, pattern):
    with pytest.raises(error, match=pattern):
        ridgeline.trace(array)


def test_to_dataframe_is_the_branch_table():
    pd = pytest.importorskip("pandas")
    page = np.full((120, 200), 255, np.uint8)
    page[37:43, 10:70] = 0  # a plus: one junction, four arms
    page[10:70, 37:43] = 0
    page[95:101, 20:90] = 0  # a bar on its own
    yy, xx = np.mgrid[:120, :200]
    ring = np.hypot(yy - 50, xx - 150)
    page[(ring > 22) & (ring < 28)] = 0  # a ring: a closed loop
    t = ridgeline.trace(page)
    frame = t.to_dataframe()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == [
        "skeleton-id", "node-id-src", "node-id-dst", "branch-distance", "branch-type", "kind",
        "image-coord-src-0", "image-coord-src-1", "image-coord-dst-0", "image-coord-dst-1",
        "euclidean-distance", "degree-src", "degree-dst", "mean-width",
    ]
    assert len(frame) == t.stats["edges"] and frame.index.name == "edge"
    assert sorted(frame["branch-type"]) == [0, 1, 1, 1, 1, 3]
    assert list(frame["kind"].cat.categories) == ["end-to-end", "junction-to-end", "junction-to-junction", "cycle"]
    assert (frame["kind"].cat.codes == frame["branch-type"]).all()
    assert frame["skeleton-id"].nunique() == t.stats["components"] == 3
    plus = frame[frame["branch-type"] == 1]
    assert plus["skeleton-id"].nunique() == 1
    np.testing.assert_array_equal(frame["branch-distance"], t.edge_length)
    np.testing.assert_array_equal(frame[["node-id-src", "node-id-dst"]], t.edge_vertices)
    xy = t.vertex_xy
    np.testing.assert_array_equal(frame["image-coord-src-0"], xy[t.edge_vertices[:, 0], 1])
    np.testing.assert_array_equal(frame["image-coord-dst-1"], xy[t.edge_vertices[:, 1], 0])
    np.testing.assert_array_equal(frame["degree-src"], t.vertex_degree[t.edge_vertices[:, 0]])
    # The strokes are 6 px wide; a loop's ends are one vertex.
    assert frame["mean-width"].between(5, 7).all(), frame["mean-width"]
    loop = frame[frame["kind"] == "cycle"].iloc[0]
    assert loop["euclidean-distance"] == 0 and loop["branch-distance"] > 2 * np.pi * 22
    bar = frame[frame["kind"] == "end-to-end"].iloc[0]
    assert abs(bar["euclidean-distance"] - bar["branch-distance"]) < 1
    # An empty page gives an empty table with the same columns.
    empty = ridgeline.trace(np.full((30, 30), 255, np.uint8)).to_dataframe()
    assert len(empty) == 0 and list(empty.columns) == list(frame.columns)
