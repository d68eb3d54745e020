"""Throughput on one machine: pages per second through Python (one call at a time, threads,
processes, Dask, Ray, Spark) against the command line's batch mode on the same pages, and the
binding's overhead per page.

    python throughput.py PAGE [--copies 8] [--workers 2] [--repeat 3] [--engines dask,ray,spark]
                              [--overhead-only]

PAGE is traced as COPIES files (the repository's A4 page: `cargo run --release --example page --
--keep DIR --no-scans` writes DIR/page_2480x3508.png). Every path writes one JSON document per
page, as `ridgeline DIR -o OUT --format json` does. The command line is found as for the tests
(RIDGELINE_CLI, else target/release/ridgeline). Prints markdown tables; figures are medians over
REPEAT runs, with the load average, since a shared machine's other work slows every path alike.
The array rows trace the page as a numpy array (its traced mask drawn black on white, C order)
and a blank array of the same size, whose call does nothing but cross the binding and read the
pixels once; `--overhead-only` prints the one-page table alone.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import numpy as np

import ridgeline

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]


def cli_path() -> str:
    given = os.environ.get("RIDGELINE_CLI")
    if given:
        return given
    built = REPO / "target" / "release" / "ridgeline"
    if built.exists():
        return str(built)
    found = shutil.which("ridgeline")
    if not found:
        sys.exit("no ridgeline binary: cargo build --release -p ridgeline-cli, or set RIDGELINE_CLI")
    return found


def load() -> str:
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "?"


def trace_to_file(job: tuple) -> int:
    """Traces one page with one thread and writes its JSON; returns the vertex count."""
    path, out = job
    trace = ridgeline.trace(path, threads=1)
    Path(out).write_text(trace.to_json())
    return trace.stats["vertices"]


def cpu_seconds() -> float:
    """User + system time of this process and of its finished children."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def timed(work) -> float:
    start = time.perf_counter()
    work()
    return time.perf_counter() - start


def overhead(page: Path, cli: str, repeat: int) -> list:
    """Per-page figures on one page: where the time of one call goes."""
    call, native, json_time, arrays, cli_wall, py_wall = [], [], [], [], [], []
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "page.json"
        ridgeline.trace(page)  # warm the file cache and the thread pool
        for _ in range(repeat):
            start = time.perf_counter()
            trace = ridgeline.trace(page)
            call.append(time.perf_counter() - start)
            native.append(trace.timings["native"])
            json_time.append(timed(trace.to_json))
            arrays.append(
                timed(lambda: [trace.vertex_xy, trace.vertex_degree, trace.vertex_width, trace.edge_vertices,
                               trace.edge_offsets, trace.point_xy, trace.point_width, trace.point_direction])
            )
            py_wall.append(timed(lambda: out.write_text(ridgeline.trace(page).to_json())))
            cli_wall.append(timed(lambda: subprocess.run([cli, str(page), "-o", str(out), "--quiet"], check=True)))
    m = statistics.median
    gil_held = m(c - n for c, n in zip(call, native))
    # The same page as an array, and a blank one: the array is read in place (GrayView), so the
    # blank call is the binding's fixed cost plus one histogram pass over the pixels.
    gray = np.where(ridgeline.trace(page).mask, 0, 255).astype(np.uint8)
    blank = np.full_like(gray, 255)
    array_call, array_native, blank_call = [], [], []
    ridgeline.trace(gray)
    for _ in range(repeat):
        start = time.perf_counter()
        trace = ridgeline.trace(gray)
        array_call.append(time.perf_counter() - start)
        array_native.append(trace.timings["native"])
    for _ in range(5 * repeat):
        blank_call.append(timed(lambda: ridgeline.trace(blank)))
    array_held = m(c - n for c, n in zip(array_call, array_native))
    copied = ridgeline.trace(blank)._input_copied if hasattr(ridgeline.Trace, "_input_copied") else True
    return [
        ("trace(path): whole call", m(call)),
        ("  of which with the GIL released (read, decode, trace, strokes)", m(native)),
        ("  of which with the GIL held (arguments, parameters, result object)", gil_held),
        ("  binding overhead, share of the trace", gil_held / m(native)),
        ("to_json()", m(json_time)),
        ("all eight numpy arrays", m(arrays)),
        ("Python: trace(path) + to_json() + write, in one process", m(py_wall)),
        ("command line: ridgeline PAGE -o page.json (process start included)", m(cli_wall)),
        ("  Python against the command line", m(py_wall) / m(cli_wall) - 1),
        (f"trace(array), {gray.shape[1]}x{gray.shape[0]} uint8 ({'copied' if copied else 'read in place'}): whole call", m(array_call)),
        ("  of which with the GIL released (the array read, trace, strokes)", m(array_native)),
        ("  of which with the GIL held", array_held),
        ("  binding overhead (GIL held), share of the trace", array_held / m(array_native)),
        ("trace(blank array of the same size): whole call", m(blank_call)),
    ]


def throughput(folder: Path, count: int, workers: int, repeat: int, cli: str, engines: list) -> list:
    pages = sorted(folder.glob("*.png"))
    rows = []

    def measure(name, run, cpu_counted=True):
        """`cpu_counted`: all the work runs in this process or in children it waits for, so the
        CPU time per page is known (not for worker pools that outlive the run)."""
        walls, cpus = [], []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory() as out:
                before = cpu_seconds()
                walls.append(timed(lambda: run(Path(out))))
                cpus.append(cpu_seconds() - before)
        wall = statistics.median(walls)
        cpu = statistics.median(cpus) / count if cpu_counted else None
        rows.append((name, wall, count / wall, cpu, load()))
        print(f"  {name}: {wall:.2f} s, {count / wall:.2f} pages/s (load {load()})", file=sys.stderr)

    for jobs in [1, workers]:
        measure(f"command line, --jobs {jobs}",
                lambda out, jobs=jobs: subprocess.run(
                    [cli, str(folder), "-o", str(out), "--format", "json", "--jobs", str(jobs), "--quiet"], check=True))

    def one_at_a_time(out):
        for page in pages:
            (out / (page.stem + ".json")).write_text(ridgeline.trace(page).to_json())

    measure("Python, one call at a time (each call on every core)", one_at_a_time)

    def with_threads(out):
        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(trace_to_file, [(str(p), str(out / (p.stem + ".json"))) for p in pages]))

    measure(f"Python, {workers} threads (threads=1 each)", with_threads)

    with ProcessPoolExecutor(workers) as pool:
        list(pool.map(trace_to_file, [(str(pages[0]), os.devnull)] * workers))  # start the workers

        def with_processes(out):
            list(pool.map(trace_to_file, [(str(p), str(out / (p.stem + ".json"))) for p in pages]))

        measure(f"Python, {workers} processes (started beforehand, threads=1 each)", with_processes, False)

    # The engines: their start (a process pool, a Ray cluster, a Spark session) is part of every
    # run, so they also trace three times the pages; the difference gives their rate once started.
    sys.path.insert(0, str(HERE))
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(HERE), os.environ.get("PYTHONPATH")]))
    more = folder.parent / "more"
    more.mkdir(exist_ok=True)
    for i in range(3 * count):
        shutil.copy(pages[0], more / f"page{i:03}.png")
    recipes = []
    if "dask" in engines:
        import dask_folder

        recipes.append((f"Dask bag, processes scheduler, {workers} workers", dask_folder.trace_folder))
    if "ray" in engines:
        import ray_folder

        recipes.append((f"Ray Data, ray.init(num_cpus={workers})", ray_folder.trace_folder))
    if "spark" in engines:
        import spark_folder

        recipes.append((f"PySpark local[{workers}]", spark_folder.trace_folder))
    for name, recipe in recipes:
        measure(f"{name}, start included", lambda out, recipe=recipe: recipe(str(folder), str(out / "rows"), workers), False)
        small = rows[-1][1]
        walls = []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory() as out:
                walls.append(timed(lambda: recipe(str(more), out + "/rows", workers)))
        large = statistics.median(walls)
        rate = 2 * count / (large - small) if large > small else float("inf")
        rows.append((f"{name}, once started ({3 * count} - {count} pages)", large - small, rate, None, load()))
        print(f"  {name}: {3 * count} pages {large:.2f} s, started rate {rate:.2f} pages/s", file=sys.stderr)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("page", type=Path)
    parser.add_argument("--copies", type=int, default=8)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--engines", default="dask,ray,spark")
    parser.add_argument("--overhead-only", action="store_true", help="print the one-page table only")
    args = parser.parse_args()
    cli = cli_path()
    trace = ridgeline.trace(args.page)
    print(f"page {args.page.name}: {trace.width}x{trace.height}, {trace.point_count} ink px, "
          f"{trace.stats['vertices']} vertices, {trace.stats['edges']} edges; {os.cpu_count()} CPUs; "
          f"load average {load()} at the start\n")
    print("| one page | seconds (share) |\n|---|---|")
    for name, value in overhead(args.page, cli, args.repeat):
        shown = f"{100 * value:.1f} %" if "share" in name or "against" in name else f"{value:.3f}"
        print(f"| {name} | {shown} |")
    if args.overhead_only:
        print(f"\nload average at the end: {load()}")
        return
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch) / "pages"
        folder.mkdir()
        for i in range(args.copies):
            shutil.copy(args.page, folder / f"page{i:03}.png")
        engines = [e for e in args.engines.split(",") if e]
        rows = throughput(folder, args.copies, args.workers, args.repeat, cli, engines)
    print(f"\n| {args.copies} pages | wall s | pages/s | CPU s per page | load |\n|---|---|---|---|---|")
    for name, wall, rate, cpu, at in rows:
        shown = "-" if cpu is None else f"{cpu:.2f}"
        print(f"| {name} | {wall:.2f} | {rate:.2f} | {shown} | {at} |")
    print(f"\nload average at the end: {load()}")
    json.dump({"rows": rows}, sys.stderr)


if __name__ == "__main__":
    main()
