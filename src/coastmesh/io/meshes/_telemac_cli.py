"""The boundary of a Telemac mesh from its ``.cli`` file, by Telemac's rules.

:func:`cli_boundary` reads the ``.cli`` beside a SELAFIN file (one line per
boundary node, ``LIHBOR LIUBOR LIVBOR HBOR UBOR VBOR AUBOR LITBOR TBOR ATBOR BTBOR
N K``, read list-directed: text after the 13 values is skipped) and gives the
boundary edges and ids that :func:`coastmesh.io.meshes.telemac_read.read_selafin_mesh`
returns. The rules are those of BIEF ``front2.f``, which numbers Telemac's liquid
boundaries:

- a node is solid where ``LIHBOR = 2`` (``KLOG``), liquid otherwise, and a
  segment between a liquid and a solid node is solid;
- each contour is walked from its south-westernmost node (least x + y, then least
  y among the nodes within 1e-4 of the range of x + y), the contours in the order
  of those nodes among the nodes left;
- a liquid boundary starts after a solid run, and where ``LIHBOR`` or ``LIUBOR``
  changes between two liquid nodes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError
from coastmesh.types.topology import unique_edges

__all__ = ["LAND_ID", "cli_boundary", "outline"]

LAND_ID = 1  # the id of every solid segment; liquid boundary k gets k + 1
_WALL = 2  # KLOG: LIHBOR of a solid node
_CLI = "LIHBOR LIUBOR LIVBOR HBOR UBOR VBOR AUBOR LITBOR TBOR ATBOR BTBOR N K"
_INT_COLUMNS = [0, 1, 2, 7, 11, 12]
_FLOAT_COLUMNS = [3, 4, 5, 6, 8, 9, 10]
_NEAR = 1e-4  # front2.f: nodes this near the south-westernmost, as a share of range


def _read_cli(
    cli: Path, npoin: int, name: str
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Return each line's number, codes (LIHBOR, LIUBOR) and node (0-based)."""
    lines: list[int] = []
    rows: list[list[str]] = []
    with open(cli, encoding="latin-1") as text:
        for number, line in enumerate(text, start=1):
            words = line.split(maxsplit=13)[:13]
            if not words:
                continue
            if len(words) < 13:
                raise FormatError(
                    f"{cli}: line {number} has {len(words)} values; expected 13: {_CLI}"
                )
            lines.append(number)
            rows.append(words)
    table = np.array(rows, dtype=str).reshape(-1, 13)
    try:
        codes = table[:, _INT_COLUMNS].astype(np.int64)
        table[:, _FLOAT_COLUMNS].astype(np.float64)
    except ValueError:
        number, words = next(
            (k, row) for k, row in zip(lines, rows, strict=True) if not _numbers(row)
        )
        raise FormatError(
            f"{cli}: line {number} ({' '.join(words)}) holds a value that is not a "
            f"number; expected integers {_CLI}, with reals for the prescribed values"
        ) from None
    numbers = np.array(lines, dtype=np.int64)
    nodes = codes[:, 4]
    bad = np.flatnonzero((nodes < 1) | (nodes > npoin))
    if len(bad):
        raise FormatError(
            f"{cli}: line {numbers[bad[0]]}: node N = {nodes[bad[0]]} is not a node "
            f"of {name}, which has NPOIN = {npoin} (N runs 1..NPOIN)"
        )
    order = np.argsort(nodes, kind="stable")
    twice = np.flatnonzero(nodes[order][1:] == nodes[order][:-1])
    if len(twice):
        a, b = numbers[order[twice[0]]], numbers[order[twice[0] + 1]]
        raise FormatError(
            f"{cli}: lines {a} and {b} both list node {nodes[order[twice[0]]]}; "
            "each boundary node has one line"
        )
    return numbers, codes[:, :2], nodes - 1


def _numbers(words: list[str]) -> bool:
    """Whether a .cli line's 13 values are integers and reals where they must be."""
    row = np.array(words, dtype=str)
    try:
        row[_INT_COLUMNS].astype(np.int64)
        row[_FLOAT_COLUMNS].astype(np.float64)
    except ValueError:
        return False
    return True


def cli_boundary(
    cli: Path,
    name: str,
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the boundary edges, ring by ring in ``.cli`` order, and their ids."""
    lines, codes, nodes = _read_cli(cli, len(points), name)
    rings = _cli_rings(cli, lines, nodes, triangles, len(points))
    ids = _liquid_ids(rings, codes, points[nodes])
    order = np.concatenate(rings) if rings else np.empty(0, dtype=np.int64)
    following = np.concatenate([np.roll(ring, -1) for ring in rings] or [order])
    edges = np.column_stack([nodes[order], nodes[following]])
    return edges, np.concatenate(ids or [order])


def _cli_rings(
    cli: Path,
    lines: NDArray[np.int64],
    nodes: NDArray[np.int64],
    triangles: NDArray[np.int64],
    n: int,
) -> list[NDArray[np.int64]]:
    """Split the ``.cli`` lines into rings: positions, the domain on the left."""
    edges, count = unique_edges(triangles, n)
    outer = edges[count == 1]
    outer_keys = outer[:, 0] * n + outer[:, 1]  # sorted by unique_edges

    def joined(a: NDArray[np.int64], b: NDArray[np.int64]) -> NDArray[np.bool_]:
        return np.isin(np.minimum(a, b) * n + np.maximum(a, b), outer_keys)

    if len(nodes) == 0:
        if len(outer):
            raise FormatError(
                f"{cli}: no lines for the {len(outer)} boundary nodes; Telemac takes "
                "one line per boundary node"
            )
        return []
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[outer.ravel()] = True
    off = np.flatnonzero(~on_boundary[nodes])
    if len(off):
        raise FormatError(
            f"{cli}: line {lines[off[0]]}: node {nodes[off[0]] + 1} is not on the "
            "boundary of the mesh (no edge of one triangle ends there)"
        )
    cuts = np.flatnonzero(~joined(nodes[:-1], nodes[1:])) + 1
    starts = np.concatenate([[0], cuts])
    ends = np.append(cuts, len(nodes))
    closed = joined(nodes[ends - 1], nodes[starts]) & (ends - starts >= 3)
    if not closed.all():
        s, e = starts[~closed][0], ends[~closed][0]
        raise FormatError(
            f"{cli}: lines {lines[s]} to {lines[e - 1]} (nodes {nodes[s] + 1} to "
            f"{nodes[e - 1] + 1}) do not close into a boundary ring: node "
            f"{nodes[e - 1] + 1} is not joined to node {nodes[s] + 1} by a boundary "
            "edge, nor to the next line's node; the lines follow each boundary "
            "ring, node after node"
        )
    if len(nodes) != len(outer):
        left = np.setdiff1d(outer.ravel(), nodes)
        first = f" (the first left out is node {left[0] + 1})" if len(left) else ""
        raise FormatError(
            f"{cli}: {len(nodes)} lines in {len(starts)} rings, but the mesh has "
            f"{len(outer)} boundary edges: a ring is missing{first}; Telemac takes "
            "one line per boundary node"
        )
    half = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)  # counter-clockwise
    directed = np.sort(half[:, 0] * n + half[:, 1])
    key = nodes[starts] * n + nodes[starts + 1]
    forward = directed[np.searchsorted(directed, key).clip(0, len(directed) - 1)]
    return [
        np.arange(s, e) if f == k else np.arange(e - 1, s - 1, -1)
        for s, e, f, k in zip(starts, ends, forward, key, strict=True)
    ]


def _liquid_ids(
    rings: list[NDArray[np.int64]],
    codes: NDArray[np.int64],
    xy: NDArray[np.float64],
) -> list[NDArray[np.int64]]:
    """Return the id of each ring's edges: 1 solid, k + 1 on liquid boundary k."""
    ring_of = np.empty(len(codes), dtype=np.int64)
    for r, ring in enumerate(rings):
        ring_of[ring] = r
    ids = list(rings)
    done = np.zeros(len(codes), dtype=bool)
    next_id = LAND_ID + 1
    while not done.all():
        rest = np.flatnonzero(~done)
        start = rest[_south_west(xy[rest])]
        ring = rings[ring_of[start]]
        shift = int(np.flatnonzero(ring == start)[0])
        labels = _ring_labels(codes[np.roll(ring, -shift)])
        ring_ids = np.where(labels > 0, labels + next_id - 1, LAND_ID)
        ids[ring_of[start]] = np.roll(ring_ids, shift)
        next_id += int(labels.max(initial=0))
        done[ring] = True
    return ids


def _south_west(xy: NDArray[np.float64]) -> int:
    """Return the node ``front2.f`` starts a contour at: least x + y, then least y."""
    ns = xy[:, 0] + xy[:, 1]
    first = int(np.argmin(ns))
    near = np.flatnonzero(np.abs(ns[first] - ns) < (ns.max() - ns[first]) * _NEAR)
    if len(near):
        best = int(near[np.argmin(xy[near, 1])])
        if xy[best, 1] < xy[first, 1]:
            return best
    return first


def _ring_labels(codes: NDArray[np.int64]) -> NDArray[np.int64]:
    """Return the number of each edge's liquid run along one contour; 0 if solid.

    ``codes`` holds LIHBOR, LIUBOR of the contour's nodes, in order; edge ``j``
    runs from node ``j`` to node ``j + 1``.
    """
    liquid = codes[:, 0] != _WALL
    edge = liquid & np.roll(liquid, -1)
    if not edge.any():
        return np.zeros(len(codes), dtype=np.int64)
    change = (codes != np.roll(codes, -1, axis=0)).any(axis=1)  # node j to j + 1
    starts = edge & ~(np.roll(edge, 1) & ~np.roll(change, 1))
    if not starts.any():
        starts[0] = True  # a contour liquid all round, with one set of codes
    run = np.cumsum(starts)
    if edge[0] and not starts[0]:
        run[run == run[-1]] = 0  # the run across the first node is the first
        run += 1
    return np.where(edge, run, 0)


def outline(triangles: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """Return the edges of one triangle, as the triangles run (domain on the left)."""
    edges, count = unique_edges(triangles, n)
    outer = edges[count == 1]
    half = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    keys = np.minimum(half[:, 0], half[:, 1]) * n + np.maximum(half[:, 0], half[:, 1])
    return half[np.isin(keys, outer[:, 0] * n + outer[:, 1])]
