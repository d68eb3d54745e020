"""Conversions to other libraries' types, each importing its library only when called."""

from __future__ import annotations

from typing import Any


def to_networkx(trace: Any) -> Any:
    """The stroke graph of ``trace`` as a ``networkx.MultiGraph``.

    A multigraph, because two vertices may be joined by several edges and a closed loop is an
    edge from a vertex to itself. Nodes are the vertex ids with ``pos`` (an ``(x, y)`` tuple, px),
    ``degree`` and ``width``; each edge is keyed by its edge id and has ``points`` (an (n, 2)
    array running from ``u`` to ``v`` as stored: for ``u > v`` networkx may list it as ``(v, u)``,
    so read ``from``), ``widths``, ``length``, ``from`` and ``to``.
    """
    try:
        import networkx
    except ImportError as err:  # pragma: no cover - depends on the environment
        raise ImportError(
            "Trace.to_networkx needs networkx: pip install networkx"
        ) from err

    graph = networkx.MultiGraph()
    xy = trace.vertex_xy
    degree = trace.vertex_degree
    width = trace.vertex_width
    for vertex in range(len(xy)):
        graph.add_node(
            vertex,
            pos=(float(xy[vertex, 0]), float(xy[vertex, 1])),
            degree=int(degree[vertex]),
            width=float(width[vertex]),
        )
    ends = trace.edge_vertices
    offsets = trace.edge_offsets
    points = trace.point_xy
    widths = trace.point_width
    lengths = trace.edge_length
    for edge in range(len(ends)):
        start, stop = int(offsets[edge]), int(offsets[edge + 1])
        u, v = int(ends[edge, 0]), int(ends[edge, 1])
        graph.add_edge(
            u,
            v,
            key=edge,
            points=points[start:stop],
            widths=widths[start:stop],
            length=float(lengths[edge]),
            **{"from": u, "to": v},
        )
    return graph


# skan's branch types (skan.summarize, "branch-type"), by how many ends are junctions.
_KINDS = ("end-to-end", "junction-to-end", "junction-to-junction", "cycle")


def to_dataframe(trace: Any) -> Any:
    """The branch table of ``trace``, one row per edge (index: the edge id), in the columns of
    skan's ``summarize`` where the meaning is the same, so code written for skan reads it:

    - ``skeleton-id``: the connected component (numbered by its smallest vertex id, from 0);
    - ``node-id-src``, ``node-id-dst``: the vertex ids of the edge's ends (``from``, ``to``);
    - ``branch-distance``: the length of its centerline, px;
    - ``branch-type``: skan's code, 0 end to end (an isolated stroke), 1 junction to end,
      2 junction to junction, 3 a closed loop (both ends one vertex); ``kind`` says it in words;
    - ``image-coord-src-0``, ``image-coord-src-1``, ``image-coord-dst-0``, ``image-coord-dst-1``:
      the ends' row and column (y and x, px, subpixel), skan's (row, column) order;
    - ``euclidean-distance``: the straight distance between the ends, px;

    and ridgeline's own: ``degree-src``, ``degree-dst`` (the ends' degrees: 1 stroke end, 3+
    junction or crossing, 2 a loop's anchor) and ``mean-width``, the stroke width averaged along
    the centerline's length (at a junction, the arm's width next to it, not the junction's), px. A junction is an end of degree 3 or more.
    """
    try:
        import pandas
    except ImportError as err:  # pragma: no cover - depends on the environment
        raise ImportError("Trace.to_dataframe needs pandas: pip install pandas") from err

    import numpy as np

    xy = trace.vertex_xy
    degree = trace.vertex_degree
    ends = trace.edge_vertices
    offsets = trace.edge_offsets
    widths = trace.point_width
    src, dst = ends[:, 0], ends[:, 1]

    # Components by union-find over the edges, each named by its smallest vertex.
    parent = np.arange(len(xy))

    def root(v: int) -> int:
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for a, b in zip(src.tolist(), dst.tolist()):
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([root(v) for v in range(len(xy))], dtype=np.int64)
    _, component = np.unique(roots, return_inverse=True)

    junctions = (degree[src] >= 3).astype(np.int64) + (degree[dst] >= 3).astype(np.int64)
    branch_type = np.where(src == dst, 3, junctions)
    mean_width = np.full(len(ends), np.nan)
    points = trace.point_xy
    for e in range(len(ends)):
        p = points[offsets[e] : offsets[e + 1]]
        w = widths[offsets[e] : offsets[e + 1]].copy()
        if len(w) == 0:
            continue
        # A junction's disc is wider than the arms that meet in it: an end at a junction
        # takes the width of its neighbouring point.
        if len(w) > 1:
            if degree[src[e]] >= 3:
                w[0] = w[1]
            if degree[dst[e]] >= 3:
                w[-1] = w[-2]
        # Averaged along the centerline's length (each segment weighs its length), so a
        # polyline that keeps few points on a straight stretch and many at a bend is not
        # weighed by where its points happen to be.
        seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
        total = seg.sum()
        mean_width[e] = (seg * (w[:-1] + w[1:]) / 2).sum() / total if total > 0 else w.mean()
    table = {
        "skeleton-id": component.reshape(-1)[src] if len(ends) else np.zeros(0, np.int64),
        "node-id-src": src,
        "node-id-dst": dst,
        "branch-distance": trace.edge_length,
        "branch-type": branch_type,
        "kind": pandas.Categorical.from_codes(branch_type, categories=list(_KINDS)),
        "image-coord-src-0": xy[src, 1],
        "image-coord-src-1": xy[src, 0],
        "image-coord-dst-0": xy[dst, 1],
        "image-coord-dst-1": xy[dst, 0],
        "euclidean-distance": np.hypot(*(xy[dst] - xy[src]).T),
        "degree-src": degree[src],
        "degree-dst": degree[dst],
        "mean-width": mean_width,
    }
    frame = pandas.DataFrame(table, index=pandas.RangeIndex(len(ends), name="edge"))
    return frame
