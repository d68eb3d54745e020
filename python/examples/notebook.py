# %% [markdown]
# # ridgeline in a notebook
#
# Cells in the "percent" format: open this file in Jupyter (jupytext), VS Code or PyCharm and run
# it cell by cell, or run it whole with `python examples/notebook.py [IMAGE]` (default: the
# repository's `samples/crossings.png`). It writes `crossings.svg` and `crossings.json` into the
# current folder.

# %%
import json
import sys
from pathlib import Path

import numpy as np

import ridgeline

image = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "samples" / "crossings.png"
trace = ridgeline.trace(image)
print(trace)
print(trace.stats)

# %% [markdown]
# The graph as numpy arrays: vertices (position, degree, width) and edges as offsets into one
# array of polyline points.

# %%
degrees, counts = np.unique(trace.vertex_degree, return_counts=True)
print("vertices by degree:", dict(zip(degrees.tolist(), counts.tolist())))
longest = int(np.argmax(trace.edge_length))
start, stop = trace.edge_offsets[longest], trace.edge_offsets[longest + 1]
print(f"longest edge {longest}: {trace.edge_length[longest]:.1f} px, {stop - start} points,",
      f"mean stroke width {trace.point_width[start:stop].mean():.1f} px")

# %% [markdown]
# Crossings are single vertices of degree 4 or more; pen strokes run straight through them.

# %%
crossings = trace.vertex_xy[trace.vertex_degree >= 4]
print("crossings at", np.round(crossings, 1).tolist())
strokes = sorted(trace.strokes, key=lambda s: -s["length"])
print(f"{len(strokes)} strokes; the longest covers edges {strokes[0]['edges']} ({strokes[0]['length']:.0f} px)")

# %% [markdown]
# Graph algorithms with networkx (optional: imported when `to_networkx` is called).

# %%
try:
    import networkx as nx
except ImportError:
    print("networkx not installed; skipping")
else:
    graph = trace.to_networkx()
    print("components:", nx.number_connected_components(graph), "cycle basis:", len(nx.cycle_basis(nx.Graph(graph))))

# %% [markdown]
# Parameters are keywords with the library's names and defaults; the JSON records every one.

# %%
paper = ridgeline.trace(image, **ridgeline.paper_params())
print("paper's rules:", paper.stats)
strict = ridgeline.trace(image, linearity=0.95, limits={"max_points": 5_000_000})
print("linearity 0.95:", strict.stats)
try:
    ridgeline.trace(image, linearity=2)
except ridgeline.ParameterError as err:
    print("refused:", err)

# %% [markdown]
# The same SVG and JSON as the command line (`ridgeline crossings.png -o crossings.svg`).

# %%
Path("crossings.svg").write_text(trace.to_svg(strokes=True))
Path("crossings.json").write_text(trace.to_json())
print("wrote crossings.svg and crossings.json;", json.loads(trace.to_json())["stats"])
