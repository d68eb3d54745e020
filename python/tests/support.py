"""Fixtures of the Python tests: synthetic pages drawn with numpy, written as PNG without any
imaging library, and the command-line tool to compare with."""

from __future__ import annotations

import os
import shutil
import struct
import subprocess
import zlib
from pathlib import Path
from typing import List, Optional

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SAMPLES = REPO / "samples"


def cli() -> Path:
    """The `ridgeline` binary: $RIDGELINE_CLI, else the workspace's release or debug build.

    The comparison with the command line is the point of several tests, so a missing binary
    fails them with what to run instead of skipping them.
    """
    given = os.environ.get("RIDGELINE_CLI")
    candidates = [Path(given)] if given else []
    candidates += [REPO / "target" / "release" / "ridgeline", REPO / "target" / "debug" / "ridgeline"]
    for candidate in candidates:
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    found = shutil.which("ridgeline")
    if found:
        return Path(found)
    raise RuntimeError(
        "no ridgeline binary: run `cargo build --release -p ridgeline-cli` at the repository "
        "root, or set RIDGELINE_CLI"
    )


def run_cli(*args: str, cwd: Optional[Path] = None) -> subprocess.CompletedProcess:
    """Runs the command line quietly; fails with its stderr when it fails."""
    done = subprocess.run(
        [str(cli()), "--quiet", *args], cwd=cwd, capture_output=True, text=True, check=False
    )
    if done.returncode != 0:
        raise AssertionError(f"ridgeline {' '.join(args)} failed: {done.stderr}")
    return done


def write_png(path: Path, pixels: np.ndarray) -> Path:
    """Writes a uint8 or uint16 array as a PNG of that bit depth (filter 0 on every row): rows x
    columns as gray, rows x columns x 2, 3 or 4 as gray and alpha, RGB or RGBA."""
    assert pixels.dtype in (np.uint8, np.uint16) and pixels.ndim in (2, 3)
    height, width = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    color_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]
    depth = 8 * pixels.dtype.itemsize
    samples = pixels.astype(pixels.dtype.newbyteorder(">"), copy=False).reshape(height, -1)
    raw = b"".join(b"\x00" + samples[row].tobytes() for row in range(height))

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, depth, color_type, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    path.write_bytes(png)
    return path


def draw_page(width: int, height: int, seed: int, stroke: int = 4, cell: int = 40) -> np.ndarray:
    """A page of handwriting-like glyphs: each cell of a grid of lines holds a few random
    strokes (bent polylines) drawn `stroke` px wide in black on white. Deterministic in `seed`."""
    rng = np.random.default_rng(seed)
    page = np.full((height, width), 255, np.uint8)
    radius = stroke / 2
    offsets = np.array(
        [(dy, dx) for dy in range(-stroke, stroke + 1) for dx in range(-stroke, stroke + 1) if dy * dy + dx * dx <= radius * radius],
        dtype=np.int64,
    )
    margin = 2 * cell
    centers: List[np.ndarray] = []
    for top in range(margin, height - margin - cell, int(1.6 * cell)):
        left = margin
        while left < width - margin - cell:
            glyph = int(cell * rng.uniform(0.5, 0.9))
            for _ in range(int(rng.integers(1, 4))):
                corners = rng.uniform(0, glyph, size=(int(rng.integers(2, 5)), 2)) + (left, top)
                for a, b in zip(corners[:-1], corners[1:]):
                    steps = int(np.hypot(*(b - a))) + 1
                    t = np.linspace(0.0, 1.0, steps)[:, None]
                    centers.append(np.rint(a + t * (b - a)).astype(np.int64))
            left += glyph + int(cell * rng.uniform(0.15, 0.6))
    if centers:
        xy = np.concatenate(centers)
        ys = (xy[:, 1][:, None] + offsets[None, :, 0]).ravel()
        xs = (xy[:, 0][:, None] + offsets[None, :, 1]).ravel()
        inside = (ys >= 0) & (ys < height) & (xs >= 0) & (xs < width)
        page[ys[inside], xs[inside]] = 0
    return page


def write_pages(folder: Path, count: int, width: int = 620, height: int = 877) -> List[Path]:
    """`count` generated pages as PNG files in `folder` (page-000.png, ...)."""
    folder.mkdir(parents=True, exist_ok=True)
    return [write_png(folder / f"page-{i:03}.png", draw_page(width, height, seed=i)) for i in range(count)]
