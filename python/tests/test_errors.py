"""Bad inputs and bad parameters raise Python exceptions carrying the library's message."""

import pickle

import numpy as np
import pytest

import ridgeline
from support import SAMPLES

T = SAMPLES / "t.png"


def test_an_unknown_keyword_is_a_type_error_with_a_suggestion():
    with pytest.raises(TypeError, match="unexpected keyword argument 'linerity'.*did you mean 'linearity'"):
        ridgeline.trace(T, linerity=0.8)


@pytest.mark.parametrize(
    "keywords,field,message",
    [
        ({"linearity": 1.5}, "linearity", "must be in \\(0.5, 1\\), got 1.5"),
        ({"k": 1}, "k", "must be in 2-64"),
        ({"threshold": {"method": "sauvola", "window": 4, "k": 0.2}}, "threshold.window", "must be odd"),
        ({"limits": {"max_side": 0}}, "limits.max_side", "at least 1"),
        ({"polarity": "sideways"}, "polarity", "unknown variant `sideways`"),
        ({"r_growth": "fast"}, "r_growth", "invalid parameter r_growth"),
        ({"threshold": {"method": "sauvola"}}, "threshold", "missing field `window`"),
        ({"limits": {"max_point": 10}}, "limits.max_point", "not a key of this limits"),
    ],
)
def test_bad_parameters_are_value_errors_naming_the_field(keywords, field, message):
    with pytest.raises(ridgeline.ParameterError, match=message) as caught:
        ridgeline.trace(T, **keywords)
    assert isinstance(caught.value, ValueError)
    assert caught.value.field == field


def test_limits_raise_limit_error_with_the_keyword_to_raise_them():
    with pytest.raises(ridgeline.LimitError, match="points: .*, over the limit of") as caught:
        ridgeline.trace(T, limits={"max_points": 100})
    err = caught.value
    assert err.field == "limits.max_points" and err.limit == 100 and err.actual > 100
    assert 'limits={"max_points": ...}' in str(err)
    with pytest.raises(ridgeline.LimitError) as caught:
        ridgeline.trace(T, limits={"max_pixels": 1000})
    assert caught.value.field == "limits.max_pixels"
    with pytest.raises(ridgeline.LimitError):
        ridgeline.trace_points(np.random.default_rng(0).uniform(0, 50, (500, 2)), limits={"max_points": 10})


def test_errors_survive_pickling_as_worker_processes_send_them():
    with pytest.raises(ridgeline.LimitError) as caught:
        ridgeline.trace(T, limits={"max_points": 100})
    copy = pickle.loads(pickle.dumps(caught.value))
    assert type(copy) is ridgeline.LimitError and str(copy) == str(caught.value)
    assert (copy.field, copy.limit, copy.actual) == (caught.value.field, 100, caught.value.actual)
    with pytest.raises(ridgeline.ParameterError) as caught:
        ridgeline.trace(T, k=1)
    assert pickle.loads(pickle.dumps(caught.value)).field == "k"


def test_bytes_that_are_not_an_image_raise_decode_error():
    with pytest.raises(ridgeline.DecodeError, match="cannot decode image"):
        ridgeline.trace(b"certainly not an image")
    truncated = T.read_bytes()[:200]
    with pytest.raises(ridgeline.DecodeError):
        ridgeline.trace(truncated)
    with pytest.raises(ridgeline.RidgelineError):
        ridgeline.trace(b"")


def test_a_missing_file_is_file_not_found_with_its_name(tmp_path):
    missing = tmp_path / "nope.png"
    with pytest.raises(FileNotFoundError) as caught:
        ridgeline.trace(missing)
    assert caught.value.filename == str(missing)
    with pytest.raises(IsADirectoryError):
        ridgeline.trace(tmp_path)


@pytest.mark.parametrize(
    "image,error,message",
    [
        (np.zeros((10, 10), np.int32), TypeError, "got dtype int32"),
        (np.zeros((10, 10, 5), np.uint8), ValueError, "expected an image array"),
        (np.zeros(10, np.uint8), ValueError, "expected an image array"),
        (12, TypeError, "got int"),
        ([[0, 255]], TypeError, "got list"),
    ],
)
def test_inputs_of_the_wrong_kind_say_what_is_accepted(image, error, message):
    with pytest.raises(error, match=message):
        ridgeline.trace(image)


def test_bad_point_lists(tmp_path):
    with pytest.raises(ValueError, match="N x 2 or N x 3"):
        ridgeline.trace_points(np.zeros((5, 4)))
    bad = tmp_path / "bad.txt"
    bad.write_text("1 2\n3 4\n5 six\n")
    with pytest.raises(ridgeline.PointListError, match="line 3") as caught:
        ridgeline.trace_points(bad)
    assert caught.value.line == 3


def test_bad_output_options_and_threads():
    t = ridgeline.trace(T)
    with pytest.raises(ValueError, match="curve_tolerance"):
        t.to_json(curves=True, curve_tolerance=0)
    with pytest.raises(ValueError, match="corner_angle"):
        t.to_svg(curves=True, corner_angle=200)
    with pytest.raises(ValueError, match="threads"):
        ridgeline.trace(T, threads=0)
    with pytest.raises(TypeError):
        t.to_json(True)  # keywords only


def test_a_failed_call_leaves_the_module_working():
    with pytest.raises(ridgeline.RidgelineError):
        ridgeline.trace(b"junk")
    assert ridgeline.trace(T).stats["junctions"] == 1
