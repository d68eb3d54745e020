"""The recipes of docs/scale-out.md, run on a few generated pages: every row carries its path, the
graph's counts and the same JSON as tracing the file directly; a broken file gives a row with its
error instead of stopping the job. Dask is part of the test requirements and always runs; Ray and
Spark run when they are installed (the CI installs them)."""

import json
import shutil
from pathlib import Path

import pytest

import ridgeline
from support import REPO

EXAMPLES = REPO / "python" / "examples"
COUNTS = ["vertices", "edges", "endpoints", "junctions", "components", "cycles"]


@pytest.fixture(scope="module")
def folder(tmp_path_factory, pages):
    """The generated pages, in a subfolder too, and a file that is not an image."""
    root = tmp_path_factory.mktemp("folder")
    nested = root / "scans"
    nested.mkdir()
    for i, page in enumerate(sorted(pages.glob("*.png"))):
        (root if i % 2 else nested).joinpath(page.name).write_bytes(page.read_bytes())
    (root / "broken.png").write_bytes(b"not an image at all")
    return root


def workers_import_the_examples(monkeypatch):
    """Ray's and Spark's worker processes unpickle the recipe's functions by module name, so they
    need the examples folder on their path (a recipe run as a script ships its functions whole)."""
    import os

    paths = [str(EXAMPLES), os.environ.get("PYTHONPATH", "")]
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(p for p in paths if p))


def check_rows(rows, folder: Path, strip_scheme: bool = False):
    by_path = {}
    for row in rows:
        path = row["path"][len("file:"):] if strip_scheme and row["path"].startswith("file:") else row["path"]
        by_path[path] = row
    images = sorted(str(p) for p in folder.rglob("*.png"))
    assert sorted(by_path) == images
    for path, row in by_path.items():
        if path.endswith("broken.png"):
            assert "cannot decode image" in row["error"]
            continue
        assert row["error"] is None
        direct = ridgeline.trace(path, source_path=row["path"])
        assert row["json"] == direct.to_json()
        assert {name: row[name] for name in COUNTS} == direct.stats
        assert direct.stats["junctions"] > 10


def test_dask_recipe(folder, tmp_path):
    import dask_folder

    written = dask_folder.trace_folder(str(folder), str(tmp_path / "out"), workers=2)
    assert written
    rows = [json.loads(line) for name in sorted((tmp_path / "out").glob("*.jsonl")) for line in name.read_text().splitlines()]
    check_rows(rows, folder)


def test_ray_recipe(folder, tmp_path, monkeypatch):
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'ray[data]')")
    pytest.importorskip("pyarrow", reason="pyarrow is not installed")
    import pyarrow.parquet as pq
    import ray_folder

    workers_import_the_examples(monkeypatch)

    count = ray_folder.trace_folder(str(folder), str(tmp_path / "out"), cpus=2)
    rows = pq.read_table(tmp_path / "out").to_pylist()
    assert count == len(rows)
    check_rows(rows, folder)


def test_spark_recipe(folder, tmp_path, monkeypatch):
    pytest.importorskip("pyspark", reason="PySpark is not installed (pip install pyspark pandas pyarrow)")
    pytest.importorskip("pandas", reason="pandas is not installed")
    if shutil.which("java") is None:
        pytest.skip("PySpark needs Java, and there is no java on PATH")
    import pyarrow.parquet as pq
    import spark_folder

    workers_import_the_examples(monkeypatch)

    count = spark_folder.trace_folder(str(folder), str(tmp_path / "out"), cores=2)
    rows = pq.read_table(tmp_path / "out").to_pylist()
    assert count == len(rows)
    check_rows(rows, folder, strip_scheme=True)


@pytest.mark.parametrize("name", ["dask_folder.py", "ray_folder.py", "spark_folder.py"])
def test_the_document_shows_each_recipe_as_it_is_tested(name):
    document = (REPO / "docs" / "scale-out.md").read_text()
    assert (EXAMPLES / name).read_text() in document, f"docs/scale-out.md should hold {name} verbatim"


def test_the_notebook_example_runs(tmp_path):
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, str(EXAMPLES / "notebook.py")], cwd=tmp_path, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "crossings at" in done.stdout and "refused: invalid parameter linearity" in done.stdout
    written = json.loads((tmp_path / "crossings.json").read_text())
    assert written == json.loads(ridgeline.trace(REPO / "samples" / "crossings.png").to_json())
    assert (tmp_path / "crossings.svg").read_text().startswith("<svg")
