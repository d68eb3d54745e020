"""The result's arrays, lists and documents describe one and the same graph; parameters round
trip; networkx gets the graph."""

import json

import numpy as np
import pytest

import ridgeline
from support import SAMPLES


@pytest.fixture(scope="module")
def crossings():
    return ridgeline.trace(SAMPLES / "crossings.png")


def test_arrays_lists_and_json_agree(crossings):
    t = crossings
    document = json.loads(t.to_json())
    V, E = len(document["vertices"]), len(document["edges"])
    assert t.vertex_xy.shape == (V, 2) and t.vertex_xy.dtype == np.float64
    assert t.vertex_degree.shape == (V,) and t.vertex_width.shape == (V,)
    assert t.edge_vertices.shape == (E, 2) and t.edge_offsets.shape == (E + 1,)
    offsets = t.edge_offsets
    assert offsets[0] == 0 and np.all(np.diff(offsets) >= 2)
    assert t.point_xy.shape == (offsets[-1], 2)
    assert t.point_width.shape == (offsets[-1],) and t.point_direction.shape == (offsets[-1], 2)
    # Degrees count edge ends (a loop twice).
    assert t.vertex_degree.sum() == 2 * E
    assert np.array_equal(np.bincount(t.edge_vertices.ravel(), minlength=V), t.vertex_degree)
    edges = t.edges
    for i, edge in enumerate(document["edges"]):
        points = t.point_xy[offsets[i] : offsets[i + 1]]
        # Polylines start and end at their vertices.
        assert np.allclose(points[0], t.vertex_xy[edge["from"]])
        assert np.allclose(points[-1], t.vertex_xy[edge["to"]])
        assert np.allclose(points, edge["points"], atol=5e-4)
        assert np.allclose(t.point_width[offsets[i] : offsets[i + 1]], edge["widths"], atol=5e-4)
        assert [edge["from"], edge["to"]] == t.edge_vertices[i].tolist()
        assert t.edge_length[i] == pytest.approx(edge["length"], abs=5e-4)
        assert edges[i]["points"] == points.tolist()
    assert np.allclose(np.linalg.norm(t.point_direction, axis=1), 1.0, atol=1e-6)
    for i, vertex in enumerate(t.vertices):
        assert vertex["id"] == i and vertex["degree"] == t.vertex_degree[i]
        assert (vertex["x"], vertex["y"]) == tuple(t.vertex_xy[i])
    assert [s["edges"] for s in t.strokes] == [s["edges"] for s in document["strokes"]]
    assert t.stats == document["stats"]
    assert t.stats["junctions"] >= 8  # the '#' over a ring crossed by a diagonal


def test_each_array_access_is_a_new_array(crossings):
    xy = crossings.vertex_xy
    xy[:] = -1
    assert (crossings.vertex_xy >= 0).all()


def test_the_mask_is_the_ink_traced(crossings):
    mask = crossings.mask
    assert mask.dtype == np.bool_ and mask.shape == (crossings.height, crossings.width)
    assert mask.sum() == crossings.point_count


def test_networkx_graph(crossings):
    nx = pytest.importorskip("networkx", reason="networkx is optional; the CI installs it")
    graph = crossings.to_networkx()
    assert isinstance(graph, nx.MultiGraph)
    assert graph.number_of_nodes() == crossings.stats["vertices"]
    assert graph.number_of_edges() == crossings.stats["edges"]
    assert nx.number_connected_components(graph) == crossings.stats["components"]
    assert dict(graph.degree()) == {i: int(d) for i, d in enumerate(crossings.vertex_degree)}
    data = graph.get_edge_data(*crossings.edge_vertices[0].tolist())[0]
    assert data["points"].shape[1] == 2 and data["length"] == pytest.approx(crossings.edge_length[0])


def test_params_round_trip_and_reproduce(crossings):
    params = crossings.params
    assert params == ridgeline.default_params()
    path = SAMPLES / "x30.png"
    custom = ridgeline.trace(path, linearity=0.85, limits={"max_points": 10**6}, skeleton=False)
    assert custom.params["linearity"] == 0.85
    assert custom.params["limits"]["max_points"] == 10**6
    assert custom.params["limits"]["max_side"] == ridgeline.default_params()["limits"]["max_side"]
    again = ridgeline.trace(path, **custom.params)
    assert again.to_json() == custom.to_json()
    # The parameters a JSON document records trace the same again.
    recorded = json.loads(custom.to_json())["parameters"]
    assert ridgeline.trace(path, **recorded).to_json() == custom.to_json()


def test_the_paper_preset_differs_from_the_defaults():
    paper, default = ridgeline.paper_params(), ridgeline.default_params()
    assert set(paper) == set(default)
    assert paper["merge_span"] == float("inf") and paper["skeleton"] is False
    assert paper["r_min_rule"] == "spacing" and default["r_min_rule"] == "stroke_width"


def test_numpy_scalars_and_ints_are_accepted_where_numbers_are():
    path = SAMPLES / "t.png"
    expected = ridgeline.trace(path, r_min_factor=2.0, k=6).to_json()
    assert ridgeline.trace(path, r_min_factor=2, k=np.int64(6)).to_json() == expected
    assert ridgeline.trace(path, r_min_factor=np.float64(2.0), k=6).to_json() == expected


def test_svg_draws_over_the_array_it_traced():
    gray = np.full((60, 90), 255, np.uint8)
    gray[28:33, 5:85] = 0
    svg = ridgeline.trace(gray).to_svg()
    assert svg.startswith("<svg") and "data:image/png;base64," in svg
    assert "<image" not in ridgeline.trace(gray).to_svg(image=False)
    assert "data:image/png;base64," in ridgeline.trace(gray == 0).to_svg()


def test_repr(crossings):
    assert "crossings.png" in repr(crossings) and "junctions" in repr(crossings)


def test_decisions_are_the_front_ends_as_in_the_json():
    for name, polarity, codes in [
        ("crossings.png", "dark", []),
        # A print traced as a page: the ridge texture points to --fingerprint.
        ("fingerprint.png", "light", ["fingerprint_like"]),
    ]:
        t = ridgeline.trace(SAMPLES / name)
        recorded = json.loads(t.to_json())["decisions"]
        assert t.decisions["polarity"] == polarity == recorded["polarity"]
        assert t.decisions["threshold"] == recorded["threshold"]
        assert t.decisions["polarity_confidence"] == pytest.approx(recorded["polarity_confidence"], abs=5e-4)
        assert [w["code"] for w in t.warnings] == codes
    forced = ridgeline.trace(SAMPLES / "fingerprint.png", polarity="light")
    assert forced.decisions["polarity_confidence"] is None
    # Masks and point lists are not thresholded: no decisions.
    assert ridgeline.trace(np.zeros((20, 20), bool)).decisions is None
    assert ridgeline.trace_points([[0, 0], [1, 1], [2, 2]]).decisions is None


def test_warnings_say_what_is_probably_wrong():
    rng = np.random.default_rng(0)
    speckled = np.full((300, 300), 255, np.uint8)
    speckled[148:153, 20:280] = 0
    for y, x in rng.integers(5, 290, (200, 2)):
        speckled[y : y + 3, x : x + 3] = 0
    t = ridgeline.trace(speckled)
    assert [w["code"] for w in t.warnings] == ["speckle"]
    assert "--min-area" in t.warnings[0]["message"]
    assert t.warnings == json.loads(t.to_json())["warnings"]
    # The keyword the warning suggests clears it.
    assert ridgeline.trace(speckled, min_area=22).warnings == []


def test_timings_cover_the_call(crossings):
    timings = crossings.timings
    stages = sum(v for k, v in timings.items() if k != "native")
    assert timings["native"] > 0 and timings["decode"] > 0
    # Stage times are summed over chunks traced in parallel, so only their order of size is bound.
    assert stages < 4 * timings["native"] + 0.01


def test_an_empty_page_gives_an_empty_graph():
    t = ridgeline.trace(np.full((50, 50), 255, np.uint8))
    assert t.stats["vertices"] == 0 and t.vertex_xy.shape == (0, 2) and t.edge_offsets.tolist() == [0]
    assert t.to_networkx().number_of_nodes() == 0 if _has_networkx() else True


def _has_networkx():
    try:
        import networkx  # noqa: F401
    except ImportError:
        return False
    return True


def test_points_trace_a_ring_as_one_cycle():
    angles = np.linspace(0, 2 * np.pi, 500, endpoint=False)
    ring = np.column_stack([100 + 40 * np.cos(angles), 100 + 40 * np.sin(angles)])
    t = ridgeline.trace_points(ring)
    assert t.stats["cycles"] == 1 and t.stats["components"] == 1
    assert t.mask is None and t.page is None
    assert np.allclose(np.hypot(*(t.point_xy - 100).T), 40, atol=1.5)
