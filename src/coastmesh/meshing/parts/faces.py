"""The faces of water: the boundary noded with the cuts, as loops of curves.

:func:`split_faces` nodes the boundary with the cuts of
:mod:`~coastmesh.meshing.parts.cuts` and finds the faces of water; each face is a
list of loops of signed curves, so the curves of a cut are shared by the two
faces beside it (:mod:`~coastmesh.meshing.parts.tasks` meshes the faces). The noding
(``shapely.node``) and the faces (``shapely.polygonize``) are GEOS; what is
written here is the bookkeeping from faces to loops of signed curves.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

__all__ = [
    "Faces",
    "canonical_order",
    "face_polygon",
    "merge_small_faces",
    "split_faces",
]


@dataclass(frozen=True, slots=True)
class Faces:
    """The boundary noded with the cuts, and the faces of water.

    Attributes
    ----------
    curves : list of ndarray of shape (k, 2)
        Pieces of the boundary (split where a cut meets them) and of the cuts.
    ids : list of int or None
        Each curve's physical id; None for a piece of a cut.
    faces : list of list of list of int
        Per face of water, its loops (the outer one first), each a list of
        signed 1-based curve indices: ``-i`` runs curve ``i - 1`` backwards.
    """

    curves: list[NDArray[np.float64]]
    ids: list[int | None]
    faces: list[list[list[int]]]


def split_faces(
    pieces: list[tuple[NDArray[np.float64], int]],
    polygon: shapely.Polygon,
    cuts: list[shapely.LineString],
) -> Faces:
    """Node the boundary pieces with the cuts and return the faces of water.

    Parameters
    ----------
    pieces : list of (ndarray of shape (k, 2), int)
        The boundary as curves with their physical ids; consecutive pieces of a
        ring share end points exactly.
    polygon : shapely.Polygon
        The water the pieces bound.
    cuts : list of shapely.LineString
        From :func:`~coastmesh.meshing.parts.cuts.cut_lines`.

    Returns
    -------
    Faces
        Every face of water bounded by the pieces and the cuts.

    Examples
    --------
    >>> ring = np.array([[0, 0], [4, 0], [4, 2], [0, 2], [0, 0]], dtype=float)
    >>> f = split_faces([(ring, 7)], shapely.Polygon(ring),
    ...                 [shapely.LineString([(2, -1), (2, 3)])])
    >>> len(f.faces), sorted(i for i in f.ids if i is not None), f.ids.count(None)
    (2, [7, 7, 7], 1)
    """
    lines = [shapely.LineString(p) for p, _ in pieces] + list(cuts)
    noded = shapely.node(shapely.GeometryCollection(lines))
    curves = [np.asarray(g.coords) for g in noded.geoms]
    # the id of each curve: the piece its first edge's midpoint lies on
    tree = shapely.STRtree([shapely.LineString(p) for p, _ in pieces])
    mids = shapely.points([0.5 * (c[0] + c[1]) for c in curves])
    near, dist = tree.query_nearest(mids, return_distance=True, all_matches=False)
    on_piece = np.full(len(curves), -1)
    on_piece[near[0]] = near[1]
    scale = max(np.ptp(shapely.get_coordinates(polygon), axis=0).max(), 1.0)
    ids = [
        pieces[int(on_piece[k])][1] if dist[k] <= 1e-9 * scale else None
        for k in range(len(curves))
    ]
    first_edge: dict[tuple[tuple[float, ...], tuple[float, ...]], int] = {}
    for k, c in enumerate(curves):
        first_edge[(tuple(c[0]), tuple(c[1]))] = k + 1
        first_edge[(tuple(c[-1]), tuple(c[-2]))] = -(k + 1)
    ends = {tuple(c[0]) for c in curves} | {tuple(c[-1]) for c in curves}
    faces = []
    for face in shapely.polygonize(list(noded.geoms)).geoms:
        if not polygon.contains(face.point_on_surface()):
            continue  # an island, or outside
        loops = [
            _loop(ring, first_edge, ends, curves)
            for ring in [face.exterior, *face.interiors]
        ]
        faces.append(loops)
    # keep the curves the faces use (not the cuts' ends outside the water)
    used = sorted({abs(i) - 1 for loops in faces for loop in loops for i in loop})
    new = {old: k + 1 for k, old in enumerate(used)}
    faces = [
        [[int(np.sign(i)) * new[abs(i) - 1] for i in loop] for loop in loops]
        for loops in faces
    ]
    return Faces([curves[k] for k in used], [ids[k] for k in used], faces)


def face_polygon(faces: Faces, index: int) -> shapely.Polygon:
    """Return face ``index`` of ``faces`` as a polygon (its loops' points)."""
    rings = [
        np.concatenate(
            [faces.curves[abs(s) - 1][:: 1 if s > 0 else -1][:-1] for s in loop]
        )
        for loop in faces.faces[index]
    ]
    return shapely.Polygon(rings[0], rings[1:])


def merge_small_faces(
    faces: Faces,
    polygon: shapely.Polygon,
    cost: Callable[[shapely.Polygon], float],
    small: float,
    fixed: Sequence[shapely.Geometry] = (),
) -> tuple[Faces, int]:
    """Join each face of under ``small`` cost to a neighbour: drop a cut between.

    The cut planners keep a crossing that would leave a piece of few
    triangles uncut (:mod:`~coastmesh.meshing.parts.cuts`), but two cuts of
    different lines that run close together, or a face that holds no size
    grid node (its cost is counted at the grid's nodes), can still leave a
    sliver of water between them: a part of a few triangles, meshed and
    seamed alone. Such a face joins the neighbour of least cost across a
    piece of cut (its longest with that neighbour; never one lying on
    ``fixed``, the outlines that must stay cuts), so the parts stay as
    even as they were; the faces are found again, until no face is under
    ``small`` or none can be joined.

    Parameters
    ----------
    faces : Faces
        From :func:`split_faces`.
    polygon : shapely.Polygon
        The water, as :func:`split_faces` took it.
    cost : callable
        A face's polygon to its cost (expected triangles).
    small : float
        Faces of a lower cost are joined.
    fixed : sequence of shapely geometries
        Cuts that stay, whatever their faces' cost.

    Returns
    -------
    faces : Faces
    dropped : int
        Pieces of cut dropped.

    Examples
    --------
    >>> ring = np.array([[0, 0], [10, 0], [10, 2], [0, 2], [0, 0]], dtype=float)
    >>> cuts = [shapely.LineString([(x, -1), (x, 3)]) for x in (5.0, 5.1)]
    >>> f = split_faces([(ring, 7)], shapely.Polygon(ring), cuts)
    >>> g, dropped = merge_small_faces(f, shapely.Polygon(ring), lambda p: p.area, 1.0)
    >>> len(f.faces), len(g.faces), dropped
    (3, 2, 1)
    """
    on_fixed = shapely.union_all(list(fixed)) if len(fixed) else None
    dropped = 0
    while len(faces.faces) > 1:
        costs = [cost(face_polygon(faces, i)) for i in range(len(faces.faces))]
        sides: dict[int, list[int]] = {}
        for i, loops in enumerate(faces.faces):
            for loop in loops:
                for s in loop:
                    sides.setdefault(abs(s) - 1, []).append(i)
        gone: set[int] = set()
        for i in np.argsort(costs, kind="stable"):
            if costs[i] >= small:
                break
            # (a piece of cut, the face beyond it) for each piece that may go
            beyond = [
                (g, j)
                for loop in faces.faces[i]
                for g in {abs(s) - 1 for s in loop}
                if faces.ids[g] is None and not _lies_on(faces.curves[g], on_fixed)
                for j in sides[g]
                if j != i
            ]
            if beyond:  # to the least face beyond, across its longest piece
                g, _ = min(
                    beyond, key=lambda p: (costs[p[1]], -_length(faces.curves[p[0]]))
                )
                gone.add(g)
        if not gone:
            break
        dropped += len(gone)
        keep = [g for g in range(len(faces.curves)) if g not in gone]
        boundary = [
            (faces.curves[g], pid) for g in keep if (pid := faces.ids[g]) is not None
        ]
        cuts = [
            shapely.LineString(faces.curves[g]) for g in keep if faces.ids[g] is None
        ]
        faces = split_faces(boundary, polygon, cuts)
    return faces, dropped


def _length(curve: NDArray[np.float64]) -> float:
    return float(np.hypot(*np.diff(curve, axis=0).T).sum())


def _lies_on(curve: NDArray[np.float64], fixed: shapely.Geometry | None) -> bool:
    """Whether a curve's first edge's midpoint lies on ``fixed`` (to 1e-9)."""
    if fixed is None:
        return False
    middle = shapely.points(0.5 * (curve[0] + curve[1]))
    scale = max(float(np.abs(curve).max()), 1.0)
    return bool(shapely.distance(fixed, middle) <= 1e-9 * scale)


def _loop(
    ring: shapely.LinearRing,
    first_edge: dict[tuple[tuple[float, ...], tuple[float, ...]], int],
    ends: set[tuple[float, ...]],
    curves: list[NDArray[np.float64]],
) -> list[int]:
    """Return a face's ring as signed curve indices, from a curve end."""
    xy = np.asarray(ring.coords)[:-1]
    start = next(k for k in range(len(xy)) if tuple(xy[k]) in ends)
    xy = np.vstack([np.roll(xy, -start, axis=0), xy[start : start + 1]])
    loop, k = [], 0
    while k < len(xy) - 1:
        signed = first_edge[(tuple(xy[k]), tuple(xy[k + 1]))]
        loop.append(signed)
        k += len(curves[abs(signed) - 1]) - 1
    return loop


def canonical_order(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    edges: NDArray[np.int64],
    edge_ids: NDArray[np.int64],
) -> tuple[
    NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]
]:
    """Return nodes in (x, y) order, triangles and edges in order of their nodes.

    This numbering depends on the mesh only, not on the order in which Gmsh
    or the parts' tasks made the nodes.
    Each triangle keeps its orientation (it is rotated, never flipped).
    """
    # numpy sorts complex numbers by real part, then imaginary part: the
    # lexsort of (x, y), stable as it is, in half its time (1.46 M nodes)
    order = np.argsort(points[:, 0] + 1j * points[:, 1], kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    triangles = _lowest_first(rank[triangles])
    triangles = triangles[_row_order(triangles, len(points))]
    edges = rank[edges]
    keep = np.lexsort(edges.T[::-1])
    return points[order], triangles, edges[keep], edge_ids[keep]


def _lowest_first(triangles: NDArray[np.int64]) -> NDArray[np.int64]:
    """Turn each triangle to start at its (first) lowest node, as ``argmin``."""
    a, b, c = triangles.T
    second = (b < a) & (b <= c)
    third = (c < a) & (c < b)
    out = triangles.copy()
    out[second] = triangles[second][:, [1, 2, 0]]
    out[third] = triangles[third][:, [2, 0, 1]]
    return out


def _row_order(triangles: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """Return the order of ``triangles`` by their first, second, third node.

    In a conforming mesh, triangles oriented alike and turned to start at
    their lowest node differ in their first two nodes (a directed edge is in
    one triangle only), so one int64 key sorts them: five times faster than a
    lexsort of the three columns on 3 M triangles. Otherwise, the lexsort.
    """
    if n < 3_000_000_000:  # n * n fits in an int64
        key = triangles[:, 0] * n + triangles[:, 1]
        order = np.argsort(key, kind="stable")
        if len(order) < 2 or (np.diff(key[order]) > 0).all():
            return order
    return np.lexsort(triangles.T[::-1])
