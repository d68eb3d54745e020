"""Traces every image under a folder with Ray Data on a local cluster: the files read as binary
rows, traced in batches by worker processes, written as Parquet rows (the path, the graph's
counts and ridgeline's JSON document).

    python ray_folder.py FOLDER OUT_DIR [--cpus 2]
"""

import argparse

import ray

import ridgeline

IMAGES = ["png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "pgm", "pnm"]
COUNTS = ["vertices", "edges", "endpoints", "junctions", "components", "cycles"]


def trace_batch(batch: dict) -> dict:
    """A batch of {"bytes", "path"} rows to output rows; a file that fails gets its error."""
    out = {"path": [], **{name: [] for name in COUNTS}, "json": [], "error": []}
    for content, path in zip(batch["bytes"], batch["path"]):
        try:
            trace = ridgeline.trace(content, source_path=path, threads=1)
            stats, document, error = trace.stats, trace.to_json(), None
        except ridgeline.RidgelineError as err:
            stats, document, error = {name: None for name in COUNTS}, None, str(err)
        out["path"].append(path)
        for name in COUNTS:
            out[name].append(stats[name])
        out["json"].append(document)
        out["error"].append(error)
    return out


def trace_folder(folder: str, out_dir: str, cpus: int = 2) -> int:
    """Writes OUT_DIR/*.parquet; returns the number of rows."""
    ray.init(num_cpus=cpus, include_dashboard=False, ignore_reinit_error=True)
    try:
        files = ray.data.read_binary_files(folder, include_paths=True, file_extensions=IMAGES)
        rows = files.map_batches(trace_batch, batch_size=4, batch_format="numpy")
        rows.write_parquet(out_dir)
        # Counted from the files written: counting `rows` would trace everything again.
        return ray.data.read_parquet(out_dir).count()
    finally:
        ray.shutdown()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("out_dir")
    parser.add_argument("--cpus", type=int, default=2)
    args = parser.parse_args()
    print(f"traced {trace_folder(args.folder, args.out_dir, args.cpus)} files into {args.out_dir}")
