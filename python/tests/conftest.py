import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
# The tests' helpers (support.py) and the runnable examples, imported by the tests that run them.
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "examples"))

import support  # noqa: E402


@pytest.fixture(scope="session")
def pages(tmp_path_factory):
    """A folder of four generated half-size pages (PNG)."""
    folder = tmp_path_factory.mktemp("pages")
    support.write_pages(folder, 4)
    return folder
