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
