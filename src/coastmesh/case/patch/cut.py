"""The hole a patch fills: the elements cut out of an existing mesh, and its rings.

:func:`check_elements` refuses a mesh with inverted, degenerate or duplicate
elements; :func:`cut_hole` takes out every element that meets the polygon (and
those a valid hole needs besides: round a node where the hole would touch
itself), checks that what is kept is still one piece, and returns the hole's
boundary as rings of the existing mesh's nodes, each edge a seam (shared with
a kept element) or a piece of the mesh's own boundary (coast, open boundary).
It refuses a hole in several pieces, and one that still touches itself at a
node once widened (where the mesh's own boundary meets itself).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from coastmesh.errors import InputDataError
from coastmesh.meshing.cleanup.planar import signed_areas

__all__ = ["Hole", "check_elements", "cut_hole", "grow_hole"]

#: How many rounds of widening (pinches, sharp corners) the hole gets at most.
_ROUNDS = 20
#: A corner of the hole sharper than this (degrees) is opened: the kept
#: elements round it go too, so the patch has no sliver there.
MIN_CORNER = 45.0


@dataclass(frozen=True, eq=False)
class Hole:
    """The elements cut out of a mesh, and the boundary of the hole they leave.

    Attributes
    ----------
    removed : ndarray of bool of shape (m,)
        The elements taken out.
    rings : list of ndarray of int
        The hole's rings as node indices of the mesh, closed (first = last),
        the outer ring first, counter-clockwise, then the holes in it
        (islands of the mesh, or kept elements it surrounds), clockwise.
    seam : list of ndarray of bool
        Per ring, per edge: a seam edge (shared with a kept element); else an
        edge of the mesh's own boundary.
    inner_nodes : ndarray of int
        The nodes only removed elements used, off the rings: they go with them.
    widened : int
        Elements taken out though they do not meet the polygon: round a node
        where the hole would touch itself, or would make a corner sharper than
        :data:`MIN_CORNER` (a corner of the mesh's own boundary stays as it is).
    """

    removed: NDArray[np.bool_]
    rings: list[NDArray[np.int64]]
    seam: list[NDArray[np.bool_]]
    inner_nodes: NDArray[np.int64]
    widened: int = 0


def check_elements(
    points: NDArray[np.float64], triangles: NDArray[np.int64], name: str
) -> bool:
    """Refuse inverted, degenerate or duplicate elements, naming the first.

    Inverted: clockwise where the others are counter-clockwise (or the other
    way); the numbers in the message are 1-based, as the formats write them.
    Returns whether the elements turn clockwise (all of them, then).
    """
    area = signed_areas(points[triangles])
    flat = np.flatnonzero(area == 0)
    if flat.size:
        raise InputDataError(
            f"{name}: element {flat[0] + 1} (nodes "
            f"{(triangles[flat[0]] + 1).tolist()}) has no area; {flat.size} such "
            "elements: refused"
        )
    majority = 1.0 if (area > 0).sum() >= (area < 0).sum() else -1.0
    inverted = np.flatnonzero(np.sign(area) != majority)
    if inverted.size:
        raise InputDataError(
            f"{name}: element {inverted[0] + 1} (nodes "
            f"{(triangles[inverted[0]] + 1).tolist()}) is inverted (turns the other "
            f"way from the rest); {inverted.size} such elements: refused"
        )
    key = np.sort(triangles, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        k = int(first[np.flatnonzero(counts > 1)[0]])
        twin = int(np.flatnonzero((key == key[k]).all(axis=1))[1])
        raise InputDataError(
            f"{name}: elements {k + 1} and {twin + 1} have the same nodes "
            f"{(triangles[k] + 1).tolist()}: duplicate elements are refused"
        )
    return majority < 0


def cut_hole(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    polygon: shapely.Polygon,
    name: str,
) -> Hole:
    """Take out the elements that meet ``polygon``; return the hole.

    ``points`` and ``polygon`` are in one CRS (the meshing CRS).

    Raises
    ------
    InputDataError
        If no element meets the polygon, the elements kept are not one piece
        (the polygon would cut the mesh in two), those cut out are not (the
        hole would be several), or the hole touches itself at a node where the
        mesh's own boundary does (no widening can open it).
    """
    cells = shapely.polygons(points[triangles])
    tree = shapely.STRtree(cells)
    hit = tree.query(polygon, predicate="intersects")
    if not hit.size:
        raise InputDataError(
            f"{name}: the patch polygon meets no element of the mesh (bounds "
            f"{tuple(round(v) for v in polygon.bounds)} in the meshing CRS); it "
            "must lie in the mesh"
        )
    removed = np.zeros(len(triangles), dtype=bool)
    removed[hit] = True
    return _hole(points, triangles, removed, len(hit), name)


def grow_hole(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    hole: Hole,
    nodes: NDArray[np.int64],
    name: str,
) -> Hole:
    """Return ``hole`` with every kept element at ``nodes`` cut out too.

    The seam moves out past those nodes (where the patch met it badly); the
    hole is widened and checked again as :func:`cut_hole` does.

    Raises
    ------
    InputDataError
        As :func:`cut_hole`: the grown hole would cut the mesh in two, be
        several, or touch itself where the mesh's own boundary does.
    """
    at = np.zeros(len(points), dtype=bool)
    at[nodes] = True
    removed = hole.removed | at[triangles].any(axis=1)
    # the elements that met the polygon are as many as before; the rest widen
    return _hole(
        points, triangles, removed, int(hole.removed.sum()) - hole.widened, name
    )


def _hole(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    removed: NDArray[np.bool_],
    hit: int,
    name: str,
) -> Hole:
    """Widen the elements ``removed`` into a valid hole, check it, find its rings.

    ``hit``: how many of them met the polygon (the rest count as widened).
    """
    angles = _corner_angles(points, triangles)
    for _ in range(_ROUNDS):
        opened = np.union1d(
            _pinched_nodes(triangles, removed, len(points)),
            _sharp_nodes(triangles, removed, angles, len(points)),
        )
        wider = removed | np.isin(triangles, opened).any(axis=1)
        if (wider == removed).all():
            break  # nothing left to open (a pinch of the mesh's own boundary)
        removed = wider
    _check_one_piece(triangles, removed, len(points), name)
    holes = _pieces(triangles[removed], len(points))
    if holes > 1:
        raise InputDataError(
            f"{name}: the patch polygon cuts {holes} separate holes in the mesh "
            "(parts of it, or an island or land between them): patch one site at "
            "a time, or give one polygon that joins them"
        )
    pinched = _pinched_nodes(triangles, removed, len(points))
    if pinched.size:
        raise InputDataError(
            f"{name}: the hole would touch itself at node {pinched[0] + 1}, where "
            f"the mesh's own boundary meets itself ({pinched.size} such nodes): "
            "refused; make the polygon keep clear of it"
        )
    rings, seam = _rings(points, triangles, removed)
    used_kept = np.zeros(len(points), dtype=bool)
    used_kept[triangles[~removed].ravel()] = True
    used_removed = np.zeros(len(points), dtype=bool)
    used_removed[triangles[removed].ravel()] = True
    on_ring = np.zeros(len(points), dtype=bool)
    on_ring[np.concatenate(rings)] = True  # the mesh's own boundary in the hole
    inner = np.flatnonzero(used_removed & ~used_kept & ~on_ring)
    return Hole(removed, rings, seam, inner, int(removed.sum()) - hit)


def _corner_angles(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Each triangle's angle at each of its corners, degrees, (m, 3)."""
    p = points[triangles]
    out = np.empty(triangles.shape)
    for i in range(3):
        u = p[:, (i + 1) % 3] - p[:, i]
        v = p[:, (i + 2) % 3] - p[:, i]
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        out[:, i] = np.degrees(np.arctan2(np.abs(cross), (u * v).sum(axis=1)))
    return out


def _sharp_nodes(
    triangles: NDArray[np.int64],
    removed: NDArray[np.bool_],
    angles: NDArray[np.float64],
    n: int,
) -> NDArray[np.int64]:
    """Ring nodes where the hole's corner is sharper than :data:`MIN_CORNER`.

    Only where kept elements are there to open it (a sharp corner of the
    mesh's own boundary stays).
    """
    edges, _ = _hole_edges(triangles, removed)
    on_ring = np.zeros(n, dtype=bool)
    on_ring[edges.ravel()] = True
    inside = np.bincount(
        triangles[removed].ravel(), angles[removed].ravel(), minlength=n
    )
    kept = np.bincount(triangles[~removed].ravel(), minlength=n) > 0
    return np.flatnonzero(on_ring & kept & (inside < MIN_CORNER))


def _edges(triangles: NDArray[np.int64]) -> NDArray[np.int64]:
    """Each triangle's three edges, (3m, 2), in the triangle's order."""
    return triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)


def _hole_edges(
    triangles: NDArray[np.int64], removed: NDArray[np.bool_]
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Return the hole's boundary edges, oriented with the hole on their left; seams."""
    edges = _edges(triangles)
    owner = np.repeat(np.arange(len(triangles)), 3)
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    # per undirected edge: how many removed and kept triangles have it
    n_removed = np.bincount(inverse, weights=removed[owner], minlength=len(counts))
    mine = removed[owner]
    boundary = mine & (n_removed[inverse] == 1)
    seam = counts[inverse][boundary] == 2
    return edges[boundary], seam


def _pinched_nodes(
    triangles: NDArray[np.int64], removed: NDArray[np.bool_], n: int
) -> NDArray[np.int64]:
    """Nodes on more than two of the hole's boundary edges (the hole touches itself)."""
    edges, _ = _hole_edges(triangles, removed)
    degree = np.bincount(edges.ravel(), minlength=n)
    return np.flatnonzero(degree > 2)


def _check_one_piece(
    triangles: NDArray[np.int64], removed: NDArray[np.bool_], n: int, name: str
) -> None:
    """Check the kept elements are as many pieces as the mesh was (one, usually)."""
    before = _pieces(triangles, n)
    after = _pieces(triangles[~removed], n)
    if after > before:
        raise InputDataError(
            f"{name}: the patch polygon would cut the mesh in two ({after} pieces "
            f"left of {before}): the kept elements must stay one piece; make the "
            "polygon smaller, or wholly inside the water"
        )


def _pieces(triangles: NDArray[np.int64], n: int) -> int:
    """Count the connected pieces of triangles sharing an edge."""
    if not len(triangles):
        return 0
    key = np.sort(_edges(triangles), axis=1)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    owner = np.repeat(np.arange(len(triangles)), 3)
    # triangles joined through the edges they share: a bipartite graph
    graph = sparse.coo_matrix(
        (np.ones(len(owner)), (owner, inverse.ravel())),
        shape=(len(triangles), int(inverse.max()) + 1),
    ).tocsr()
    joined = graph @ graph.T
    count, _ = connected_components(joined, directed=False)
    return int(count)


def _rings(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    removed: NDArray[np.bool_],
) -> tuple[list[NDArray[np.int64]], list[NDArray[np.bool_]]]:
    """Chain the hole's boundary edges into rings: the outer one first."""
    edges, seam = _hole_edges(triangles, removed)
    following = {
        int(a): (int(b), bool(s)) for (a, b), s in zip(edges, seam, strict=True)
    }
    rings, seams = [], []
    while following:
        start = next(iter(following))
        nodes, flags = [start], []
        node = start
        while True:
            node, flag = following.pop(node)
            flags.append(flag)
            nodes.append(node)
            if node == start:
                break
        rings.append(np.array(nodes, dtype=np.int64))
        seams.append(np.array(flags, dtype=bool))
    areas = [shapely.Polygon(points[r]).area for r in rings]
    order = np.argsort([-a for a in areas])
    return [rings[k] for k in order], [seams[k] for k in order]
