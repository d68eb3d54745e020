"""Arrays are read in place where their layout allows: every row with unit column stride, rows a
positive stride apart (uint8), C order (bool). Any layout traces the same as its C-order copy."""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import ridgeline
import support

# A page with strokes, inside a larger buffer so that crops and steps have somewhere to come from.
BASE = np.pad(support.draw_page(330, 250, seed=3), ((6, 9), (11, 7)), constant_values=255)

# (name, layout of BASE, read in place)
GRAY_LAYOUTS = [
    ("C order", lambda a: a, True),
    ("read-only", lambda a: _read_only(a), True),
    ("rows and columns cut", lambda a: a[6:-9, 11:-7], True),
    ("every other row", lambda a: a[::2], True),
    ("one column", lambda a: a[:, 40:41], True),
    ("Fortran order", np.asfortranarray, False),
    ("every other column", lambda a: a[:, ::2], False),
    ("rows flipped", lambda a: a[::-1], False),
    ("columns flipped", lambda a: a[:, ::-1], False),
    ("transposed", lambda a: a.T, False),
]


def _read_only(array):
    array = array.copy()
    array.flags.writeable = False
    return array


@pytest.mark.parametrize("name,layout,in_place", GRAY_LAYOUTS, ids=[n for n, _, _ in GRAY_LAYOUTS])
def test_gray_layouts_trace_as_their_c_order_copy(name, layout, in_place):
    array = layout(BASE)
    expected = ridgeline.trace(np.ascontiguousarray(array), source_path="a")
    assert expected._input_copied is False
    result = ridgeline.trace(array, source_path="a")
    assert result._input_copied is (not in_place), name
    assert result.to_json() == expected.to_json()
    assert result.to_svg() == expected.to_svg()


MASK_LAYOUTS = [
    ("C order", lambda a: a, True),
    ("Fortran order", np.asfortranarray, False),
    ("rows and columns cut", lambda a: a[6:-9, 11:-7], False),
    ("rows flipped", lambda a: a[::-1], False),
]


@pytest.mark.parametrize("name,layout,in_place", MASK_LAYOUTS, ids=[n for n, _, _ in MASK_LAYOUTS])
def test_mask_layouts_trace_as_their_c_order_copy(name, layout, in_place):
    mask = layout(BASE < 128)
    expected = ridgeline.trace(np.ascontiguousarray(mask), source_path="m")
    result = ridgeline.trace(mask, source_path="m")
    assert result._input_copied is (not in_place), name
    assert result.to_json() == expected.to_json()
    assert result.to_svg() == expected.to_svg()
    assert np.array_equal(result.mask, mask) and result.mask.flags.c_contiguous
    assert result.minutiae == expected.minutiae


def test_files_and_bytes_report_no_layout():
    assert ridgeline.trace(support.SAMPLES / "t.png")._input_copied is None
    assert ridgeline.trace_points([[0, 0], [1, 1], [2, 2]])._input_copied is None


# Peak memory of one process tracing one large array, as a multiple of the array's size. A page
# read in place costs the trace's own buffers (about 0.4 of the array's size on this page of
# sparse lines) and a copied one a whole array more.
MEMORY = textwrap.dedent(
    """
    import resource, sys
    import numpy as np
    import ridgeline

    layout = sys.argv[1]
    page = np.full((6000, 6200), 255, np.uint8)      # 37 MB, above glibc's mmap threshold
    for y in range(100, 5900, 400):
        page[y : y + 5, 100:6100] = 0
    page = {"c": page, "fortran": np.asfortranarray(page), "crop": page[:, 50:]}[layout]
    small = np.full((50, 50), 255, np.uint8)
    small[20:25, 5:45] = 0
    ridgeline.trace(small, threads=1)                 # the module, its pools and caches
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    trace = ridgeline.trace(page, threads=1)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    assert trace.stats["edges"] == 15, trace.stats
    print(json.dumps({"growth": (after - before) / page.nbytes, "copied": trace._input_copied}))
    """
).replace("import resource, sys", "import json, resource, sys")


def _peak_growth(layout):
    done = subprocess.run([sys.executable, "-c", MEMORY, layout], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ru_maxrss is in KiB on Linux only")
def test_an_array_read_in_place_costs_no_copy_of_its_pixels():
    c_order, crop, fortran = _peak_growth("c"), _peak_growth("crop"), _peak_growth("fortran")
    assert (c_order["copied"], crop["copied"], fortran["copied"]) == (False, False, True)
    # The copy is measurable (so the measurement can tell: it costs one array's size), and the
    # layouts read in place lack it.
    assert fortran["growth"] > 1.0, fortran
    assert c_order["growth"] < fortran["growth"] - 0.7, (c_order, fortran)
    assert crop["growth"] < fortran["growth"] - 0.7, (crop, fortran)
