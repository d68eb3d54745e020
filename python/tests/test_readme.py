"""The README's Python example runs as written, from a folder holding the samples, and writes
what the command line writes."""

import json
import re
from pathlib import Path

from support import REPO, run_cli


def python_blocks() -> list:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_the_readme_python_example_runs_as_written(tmp_path, monkeypatch):
    blocks = python_blocks()
    assert blocks, "the README has no python block"
    (tmp_path / "samples").symlink_to(REPO / "samples")
    monkeypatch.chdir(tmp_path)
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {"__name__": "readme"})
    written = (tmp_path / "text.json").read_text()
    assert json.loads(written)["stats"]["edges"] > 0
    # "the same bytes as `ridgeline samples/text.png -o text.json`"
    run_cli("samples/text.png", "-o", str(tmp_path / "cli.json"), cwd=Path(tmp_path))
    assert written == (tmp_path / "cli.json").read_text()
