"""Where cuts meet the boundary: on a boundary node, never between two.

The boundary reaches the parts as fixed chains of nodes, made once
(:mod:`~coastmesh.meshing.gmsh.boundary_nodes`), so its nodes are the same whether the
water is meshed whole or in parts. A straight cut meets the boundary between
two of those nodes; inserting the meeting point would leave a boundary edge
as short as chance makes it, and a sliver beside it. :func:`join_cuts` moves
the nearer of the two nodes onto the meeting point instead, so the boundary
keeps its spacing and every cut ends on a node. A node that ends a piece (a
corner, the end of a segment) never moves: if it is the nearer one, the point
is added beside it (cuts keep half an edge from such nodes:
:mod:`~coastmesh.meshing.parts.cuts`). A later cut ending on an earlier one (a T)
gets its end point as a node of the earlier cut. What comes out is noded
linework that GEOS only has to polygonize; nothing is left to floating-point
intersection.
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray

__all__ = ["join_cuts"]

#: A point is on a line when nearer than this, relative to the water's extent.
_ON = 1e-9


def join_cuts(
    pieces: list[tuple[NDArray[np.float64], int]],
    water: shapely.Polygon,
    cuts: list[shapely.LineString],
) -> tuple[list[tuple[NDArray[np.float64], int]], list[NDArray[np.float64]]]:
    """Return the boundary pieces with the cuts' ends on their nodes, and chords.

    Parameters
    ----------
    pieces : list of (ndarray of shape (k, 2), int)
        The boundary's pieces with their physical ids, as
        :func:`~coastmesh.meshing.gmsh.boundary_nodes.boundary_nodes` returns them.
    water : shapely.Polygon
        The polygon they bound.
    cuts : list of shapely.LineString
        From :func:`~coastmesh.meshing.parts.cuts.cut_lines`, in order: a later cut
        may end on an earlier one.

    Returns
    -------
    pieces : list of (ndarray, int)
        The same pieces, a node moved onto each place a cut meets them (or,
        next to a piece's end, a node added there).
    chords : list of ndarray of shape (m, 2)
        Each crossing of the water by a cut, from boundary node (or T point) to
        boundary node (or T point), with the T points of later cuts as nodes.

    Examples
    --------
    >>> ring = np.array([[0, 0], [2, 0], [4, 0], [4, 2], [2, 2], [0, 2], [0, 0]],
    ...                 dtype=float)
    >>> pieces = [(ring[:4], 1), (ring[3:], 1)]
    >>> new, chords = join_cuts(pieces, shapely.Polygon(ring),
    ...                         [shapely.LineString([(2.4, -1), (2.4, 3)])])
    >>> new[0][0][1].tolist(), chords[0].tolist()  # the node at x=2 moved to 2.4
    ([2.4, 0.0], [[2.4, 0.0], [2.4, 2.0]])
    """
    scale = max(float(np.ptp(shapely.get_coordinates(water), axis=0).max()), 1.0)
    tol = _ON * scale
    arrays = [np.array(p, dtype=np.float64) for p, _ in pieces]
    starts = np.cumsum([0] + [len(a) - 1 for a in arrays])
    segments = np.concatenate([np.stack([a[:-1], a[1:]], axis=1) for a in arrays])
    tree = shapely.STRtree(shapely.linestrings(segments))
    chords: list[list[NDArray[np.float64]]] = []
    moves: dict[int, list[tuple[int, NDArray[np.float64]]]] = {}
    for line in cuts:
        wet = shapely.intersection(water, line)
        for g in shapely.get_parts(wet):
            if g.geom_type != "LineString" or g.is_empty:
                continue
            ends = np.asarray(g.coords)[[0, -1]]
            kept = True
            for end in ends:
                point = shapely.Point(end)
                k, d = tree.query_nearest(
                    point, return_distance=True, all_matches=False
                )
                if d[0] <= tol:  # on the boundary: a node moves there
                    seg = int(k[0])
                    piece = int(np.searchsorted(starts, seg, side="right") - 1)
                    moves.setdefault(piece, []).append((seg - starts[piece], end))
                    continue
                # a T: on an earlier chord, which gets this point as a node
                host = next(
                    (
                        c
                        for c in chords
                        if shapely.distance(shapely.LineString(c), point) <= tol
                    ),
                    None,
                )
                if host is None:
                    kept = False  # ends nowhere (cannot happen for a box's cut)
                    break
                host.append(end)
            if kept:
                chords.append([ends[0], ends[1]])
    arrays = [_move(a, moves.get(i, [])) for i, a in enumerate(arrays)]
    out = []
    for c in chords:
        a, b = c[0], c[1]
        inner = sorted(c[2:], key=lambda p: float(np.hypot(*(p - a))))
        out.append(np.array([a, *inner, b]))
    return [(a, pid) for a, (_, pid) in zip(arrays, pieces, strict=True)], out


def _move(
    piece: NDArray[np.float64], joins: list[tuple[int, NDArray[np.float64]]]
) -> NDArray[np.float64]:
    """Move the nearer node of each joined edge onto its join point.

    If the nearer node ends the piece (a corner), the point is added between
    them instead: moving the farther node would bend the boundary by more than
    half an edge.
    """
    piece = piece.copy()
    inserts = []
    moved: set[int] = set()
    last = len(piece) - 1
    for edge, point in joins:
        i = min((edge, edge + 1), key=lambda i: float(np.hypot(*(piece[i] - point))))
        if 0 < i < last and i not in moved:
            piece[i] = point
            moved.add(i)
        else:
            inserts.append((edge + 1, point))
    for at, point in sorted(inserts, key=lambda t: -t[0]):
        piece = np.insert(piece, at, point, axis=0)
    return piece
