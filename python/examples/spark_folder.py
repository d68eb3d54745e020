"""Traces every image under a folder with PySpark in local mode: the binaryFile source, traced
with mapInPandas, written as Parquet rows (the path, the graph's counts and ridgeline's JSON
document). Needs Java (17 works) besides pyspark, pandas and pyarrow.

    python spark_folder.py FOLDER OUT_DIR [--cores 2]
"""

import argparse

import pandas as pd
from pyspark.sql import SparkSession

import ridgeline

COUNTS = ["vertices", "edges", "endpoints", "junctions", "components", "cycles"]
SCHEMA = "path string, " + ", ".join(f"{name} long" for name in COUNTS) + ", json string, error string"


def trace_frames(frames):
    """Frames of (path, content) rows to frames of output rows."""
    for frame in frames:
        rows = []
        for path, content in zip(frame["path"], frame["content"]):
            try:
                trace = ridgeline.trace(bytes(content), source_path=path, threads=1)
                rows.append({"path": path, **trace.stats, "json": trace.to_json(), "error": None})
            except ridgeline.RidgelineError as err:
                rows.append({"path": path, **{name: None for name in COUNTS}, "json": None, "error": str(err)})
        yield pd.DataFrame(rows, columns=["path", *COUNTS, "json", "error"])


def trace_folder(folder: str, out_dir: str, cores: int = 2) -> int:
    """Writes OUT_DIR/*.parquet; returns the number of rows."""
    spark = (
        SparkSession.builder.master(f"local[{cores}]")
        .appName("ridgeline")
        .config("spark.sql.execution.arrow.maxRecordsPerBatch", "4")
        .config("spark.ui.enabled", "false")
        .getOrCreate()
    )
    try:
        files = (
            spark.read.format("binaryFile")
            .option("pathGlobFilter", "*.{png,jpg,jpeg,tif,tiff,bmp,gif,webp,pgm,pnm}")
            .option("recursiveFileLookup", "true")
            .load(folder)
        )
        rows = files.select("path", "content").mapInPandas(trace_frames, schema=SCHEMA)
        rows.write.mode("overwrite").parquet(out_dir)
        return spark.read.parquet(out_dir).count()
    finally:
        spark.stop()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("out_dir")
    parser.add_argument("--cores", type=int, default=2)
    args = parser.parse_args()
    print(f"traced {trace_folder(args.folder, args.out_dir, args.cores)} files into {args.out_dir}")
