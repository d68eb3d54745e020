"""The module gives what the command line gives: the same JSON bytes and SVG bytes for the same
input and parameters, whichever way the image is handed over."""

import json
from pathlib import Path

import numpy as np
import pytest

import ridgeline
import support
from support import REPO, SAMPLES, run_cli

SAMPLE_NAMES = sorted(p.name for p in SAMPLES.glob("*.png"))


def cli_output(tmp_path: Path, source: str, *flags: str, suffix: str = ".json") -> str:
    out = tmp_path / ("out" + suffix)
    run_cli(source, "-o", str(out), *flags, cwd=Path.cwd())
    return out.read_text()


def test_there_are_samples():
    assert len(SAMPLE_NAMES) >= 10


@pytest.mark.parametrize("name", SAMPLE_NAMES)
def test_json_equals_the_command_lines_on_every_sample(tmp_path, monkeypatch, name):
    monkeypatch.chdir(REPO)
    source = f"samples/{name}"
    expected = cli_output(tmp_path, source)
    result = ridgeline.trace(source)
    assert result.to_json() == expected
    # The counts the module reports are the document's.
    assert result.stats == json.loads(expected)["stats"]


@pytest.mark.parametrize("name", ["crossings.png", "fingerprint.png", "dropout30.png"])
def test_svg_equals_the_command_lines(tmp_path, monkeypatch, name):
    monkeypatch.chdir(REPO)
    source = f"samples/{name}"
    assert ridgeline.trace(source).to_svg() == cli_output(tmp_path, source, suffix=".svg")
    flags = ["--strokes", "--width", "--minutiae", "--curves", "--no-vertices", "--no-image"]
    expected = cli_output(tmp_path, source, *flags, suffix=".svg")
    drawn = ridgeline.trace(source).to_svg(
        strokes=True, widths=True, minutiae=True, curves=True, vertices=False, image=False
    )
    assert drawn == expected


# Flags of the command line and the keywords that mean the same.
VARIANTS = [
    (["--paper"], ridgeline.paper_params()),
    (["--sauvola", "--window", "25"], {"threshold": {"method": "sauvola", "window": 25, "k": 0.2}}),
    (["--threshold", "100", "--polarity", "dark"], {"threshold": {"method": "fixed", "level": 100}, "polarity": "dark"}),
    (["--no-skeleton", "--linearity", "0.8", "--k", "7"], {"skeleton": False, "linearity": 0.8, "k": 7}),
    (["--dropout", "on", "--max-points", "200000"], {"dropout": True, "limits": {"max_points": 200000}}),
    (["--merge-span", "inf", "--laplacian", "uniform"], {"merge_span": float("inf"), "laplacian": "uniform"}),
]


@pytest.mark.parametrize("flags,keywords", VARIANTS, ids=[" ".join(f) for f, _ in VARIANTS])
def test_keywords_mean_what_the_flags_mean(tmp_path, monkeypatch, flags, keywords):
    monkeypatch.chdir(REPO)
    for name in ["text.png", "crossings.png"]:
        source = f"samples/{name}"
        expected = cli_output(tmp_path, source, *flags)
        assert ridgeline.trace(source, **keywords).to_json() == expected
        # The parameters the document records are keywords that trace the same (`--paper`'s
        # infinite merge_span is recorded as null).
        recorded = json.loads(expected)["parameters"]
        assert ridgeline.trace(source, **recorded).to_json() == expected


def test_the_fingerprint_presets_recorded_parameters_read_back(tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    for flags in (["--fingerprint"], ["--fingerprint", "--paper"]):
        recorded = json.loads(cli_output(tmp_path, "samples/fingerprint.png", *flags))["parameters"]
        assert recorded["fingerprint"] is not None
        again = ridgeline.trace("samples/fingerprint.png", **recorded)
        assert json.loads(again.to_json())["parameters"] == recorded


def test_fingerprint_true_is_the_preset_and_a_mapping_updates_it(tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    source = "samples/fingerprint.png"
    preset = json.loads(cli_output(tmp_path, source, "--fingerprint"))["parameters"]["fingerprint"]
    on = ridgeline.trace(source, fingerprint=True)
    assert json.loads(on.to_json())["parameters"]["fingerprint"] == preset
    assert all("quality" in m for m in on.minutiae)
    smoothing = ridgeline.trace(source, fingerprint={"enhancement": "smoothing"})
    recorded = json.loads(smoothing.to_json())["parameters"]["fingerprint"]
    assert recorded == {**preset, "enhancement": "smoothing"}
    assert smoothing.to_json(minutiae=True) == cli_output(tmp_path, source, "--enhance", "smoothing")
    assert json.loads(ridgeline.trace(source, fingerprint=False).to_json())["parameters"].get("fingerprint") is None
    with pytest.raises(ridgeline.ParameterError, match="fingerprint.blocks"):
        ridgeline.trace(source, fingerprint={"blocks": 8})


def test_xyt_and_iso_records_equal_the_command_lines(tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    source = "samples/fingerprint.png"
    result = ridgeline.trace(source, fingerprint=True)
    assert result.to_xyt() == cli_output(tmp_path, source, "--fingerprint", suffix=".xyt")
    assert len(result.to_xyt().splitlines()) == len(result.minutiae) > 0
    run_cli(source, "--fingerprint", "-o", str(tmp_path / "out.ist"), cwd=Path.cwd())
    assert result.to_iso() == (tmp_path / "out.ist").read_bytes()
    record = result.to_iso(dpi=1000)
    assert record[:8] == b"FMR\0 20\0" and int.from_bytes(record[18:20], "big") == 394
    with pytest.raises(ridgeline.ParameterError, match="dpi"):
        result.to_iso(dpi=0)


def test_features_and_pretty_equal_the_command_lines(tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    source = "samples/fingerprint.png"
    flags = ["--minutiae", "--curves", "--curve-tolerance", "0.8", "--corner-angle", "45", "--pretty"]
    expected = cli_output(tmp_path, source, *flags)
    result = ridgeline.trace(source)
    assert result.to_json(pretty=True, minutiae=True, curves=True, curve_tolerance=0.8, corner_angle=45) == expected
    assert result.minutiae == [
        {**m, "x": pytest.approx(m["x"], abs=5e-4), "y": pytest.approx(m["y"], abs=5e-4),
         "direction": pytest.approx(m["direction"], abs=5e-4), "width": pytest.approx(m["width"], abs=5e-4)}
        for m in json.loads(expected)["minutiae"]
    ]
    assert len(result.minutiae) > 0


def test_bytes_arrays_and_paths_trace_the_same(tmp_path):
    path = SAMPLES / "text.png"
    from_path = ridgeline.trace(path, source_path="text.png").to_json()
    from_bytes = ridgeline.trace(path.read_bytes(), source_path="text.png").to_json()
    assert from_bytes == from_path
    # The decoded pixels as an array, C order and Fortran order and a strided view.
    gray = np.array(ridgeline.trace(path).mask, dtype=np.uint8)  # any gray picture will do
    gray = np.where(gray, 0, 255).astype(np.uint8)
    support.write_png(tmp_path / "gray.png", gray)
    expected = ridgeline.trace(tmp_path / "gray.png", source_path="g").to_json()
    assert ridgeline.trace(gray, source_path="g").to_json() == expected
    assert ridgeline.trace(np.asfortranarray(gray), source_path="g").to_json() == expected
    doubled = np.repeat(gray, 2, axis=1)
    assert ridgeline.trace(doubled[:, ::2], source_path="g").to_json() == expected
    # A bool mask is traced as it is: the same ink, the same graph; no threshold was decided.
    masked = ridgeline.trace(gray == 0, source_path="g")
    assert masked.decisions is None
    without_decisions = json.loads(expected)
    del without_decisions["decisions"]
    assert json.loads(masked.to_json()) == without_decisions


def test_an_array_records_no_path_unless_given():
    gray = np.full((40, 60), 255, np.uint8)
    gray[18:23, 5:55] = 0
    document = json.loads(ridgeline.trace(gray).to_json())
    assert document["source"] == {"path": None, "width": 60, "height": 40}
    assert json.loads(ridgeline.trace(gray, source_path="scan-7.png").to_json())["source"]["path"] == "scan-7.png"


def test_every_page_of_a_tiff_equals_the_command_lines_page_files(tmp_path, monkeypatch):
    tiff = REPO / "fuzz" / "seeds" / "decode_trace" / "pages.tif"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pages.tif").write_bytes(tiff.read_bytes())
    run_cli("pages.tif", "-o", "pages.json", cwd=tmp_path)
    pages = ridgeline.trace_pages("pages.tif")
    assert len(pages) >= 2
    assert [p.page for p in pages] == [(n, len(pages)) for n in range(1, len(pages) + 1)]
    for number, page in enumerate(pages, start=1):
        name = "pages.json" if number == 1 else f"pages.p{number}.json"
        assert page.to_json() == (tmp_path / name).read_text()
    assert ridgeline.trace("pages.tif").to_json() == pages[0].to_json()


def test_point_lists_equal_the_command_lines(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    angles = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = np.column_stack([50 + 30 * np.cos(angles), 50 + 30 * np.sin(angles)])
    bar = np.column_stack([np.linspace(10, 90, 200), np.full(200, 50.0)])
    xy = np.round(np.concatenate([ring, bar]), 3)
    np.savetxt("points.txt", xy, fmt="%.3f")
    expected = cli_output(tmp_path, "points.txt")
    assert ridgeline.trace_points("points.txt").to_json() == expected
    assert ridgeline.trace_points(xy, source_path="points.txt").to_json() == expected
    assert ridgeline.trace_points(xy.tolist(), source_path="points.txt").to_json() == expected
    svg = cli_output(tmp_path, "points.txt", suffix=".svg")
    assert ridgeline.trace_points("points.txt").to_svg() == svg


def test_points_in_space_carry_z_and_equal_the_command_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    # A helix of random points filling a tube 8 units across.
    rng = np.random.default_rng(3)
    t = rng.uniform(0, 4 * np.pi, 12000)
    center = np.column_stack([50 * np.cos(t), 50 * np.sin(t), 60 * t / (2 * np.pi)])
    tangent = np.column_stack([-50 * np.sin(t), 50 * np.cos(t), np.full_like(t, 60 / (2 * np.pi))])
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    across = np.cross(tangent, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across, axis=1)[:, None]
    other = np.cross(tangent, across)
    radius = 4 * np.sqrt(rng.uniform(0, 1, len(t)))
    angle = rng.uniform(0, 2 * np.pi, len(t))
    xyz = center + (radius * np.cos(angle))[:, None] * across + (radius * np.sin(angle))[:, None] * other
    xyz = np.round(xyz, 3)
    np.savetxt("helix.xyz", xyz, fmt="%.3f")
    result = ridgeline.trace_points(xyz, source_path="helix.xyz")
    assert result.vertex_xy.shape == (2, 3)
    assert list(result.vertex_degree) == [1, 1]
    assert result.point_xy.shape[1] == 3
    assert result.point_direction.shape == result.point_xy.shape
    assert np.allclose(np.linalg.norm(result.point_direction, axis=1), 1.0)
    assert abs(np.median(result.point_width) / 8.0 - 1) < 0.1
    assert sorted(result.point_xy[:, 2])[0] < 5 and sorted(result.point_xy[:, 2])[-1] > 115
    assert "z" in result.vertices[0] and len(result.edges[0]["points"][0]) == 3
    expected = cli_output(tmp_path, "helix.xyz")
    assert result.to_json() == expected
    assert ridgeline.trace_points("helix.xyz").to_json() == expected
    assert json.loads(expected)["parameters"]["input"] == "points3d"
    with pytest.raises(ValueError, match="in space"):
        result.to_svg()
