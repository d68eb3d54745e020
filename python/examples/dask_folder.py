"""Traces every image under a folder with Dask: a bag of file names, mapped on local worker
processes, one JSON line per image (its path, the graph's counts and ridgeline's JSON document).

    python dask_folder.py FOLDER OUT_DIR [--workers 2]
"""

import argparse
import json
from pathlib import Path

import dask.bag as db

import ridgeline

IMAGES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".gif", ".webp", ".pgm", ".pnm"}


def row(path: str) -> dict:
    """One output row: the path (to join results back), the counts and the JSON, or the error."""
    try:
        # One thread per trace: the workers already keep every core busy.
        trace = ridgeline.trace(path, threads=1)
    except (ridgeline.RidgelineError, OSError) as err:
        return {"path": path, "error": str(err)}
    return {"path": path, **trace.stats, "json": trace.to_json(), "error": None}


def trace_folder(folder: str, out_dir: str, workers: int = 2) -> list:
    """Writes OUT_DIR/part-N.jsonl (written by the workers) and returns the files written."""
    paths = sorted(str(p) for p in Path(folder).rglob("*") if p.suffix.lower() in IMAGES)
    bag = db.from_sequence(paths, npartitions=max(1, min(len(paths), 4 * workers)))
    lines = bag.map(row).map(lambda r: json.dumps(r) + "\n")
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    return lines.to_textfiles(f"{out_dir}/part-*.jsonl", compute=True, scheduler="processes", num_workers=workers)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("out_dir")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    written = trace_folder(args.folder, args.out_dir, args.workers)
    print(f"wrote {len(written)} files into {args.out_dir}")
