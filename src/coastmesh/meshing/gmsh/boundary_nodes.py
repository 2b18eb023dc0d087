"""The boundary nodes, made once by Gmsh's own 1-D mesher.

Gmsh meshes each boundary piece (a spline through the points of
:func:`~coastmesh.meshing.gmsh.resample.resample_rings`, at most
:data:`~coastmesh.meshing.gmsh.boundary_nodes.CURVE_POINTS` points) from the size grid:
equal steps of the integral of 1/h, rounded up, so no boundary edge is longer
than its target. That is done here once, for the whole boundary, before the
water is cut; the nodes are then fixed, and every part (or the whole water)
is meshed inside them. So the boundary nodes, where the worst triangles of a
coastal mesh sit, are the same however the water is cut, and a cut that ends
on a boundary curve cannot move the nodes along it.
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.errors import MeshingError
from coastmesh.meshing.gmsh.model import add_size_view, gmsh_session, set_options
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.types import SizeGrid

__all__ = ["CURVE_POINTS", "boundary_nodes", "chunked"]

#: The most points of one Gmsh spline (:func:`chunked`).
CURVE_POINTS = 500


def boundary_nodes(
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    size: SizeGrid,
) -> tuple[list[tuple[NDArray[np.float64], int]], shapely.Polygon]:
    """Return the boundary as chains of its mesh nodes, and the water.

    On one Gmsh thread, so that the nodes are the same bytes every run. On
    two, Gmsh reads the size view through an octree that starts each search
    from the element it found last, so which thread looked last picks, on an
    element's edge, between two values that differ in the last bits, and
    nodes move by some 1e-15 of the domain's size (seen on ``world.toml``:
    one piece of 1,945 in some runs, and the mesh's nodes near it by up to
    4e-9 degrees); in turns with two threads it was no slower.

    Parameters
    ----------
    rings : list of list of list of ndarray of shape (k, 2)
        From :func:`~coastmesh.meshing.gmsh.resample.resample_rings`, in the
        meshing CRS.
    ids : list of list of int
        Each ring's segments' physical ids.
    size : SizeGrid
        Target sizes in map units.

    Returns
    -------
    pieces : list of (ndarray of shape (m, 2), int)
        Per piece, in ring order, its nodes from end to end (the ends are the
        piece's own end points) and its physical id.
    water : shapely.Polygon
        The polygon those nodes bound.

    Raises
    ------
    MeshingError
        If Gmsh fails.
    """
    with gmsh_session() as gmsh:
        try:
            set_options(gmsh, threads=1, seed=0, algorithm="frontal-delaunay")
            by_ring = _ring_pieces(rings, ids)
            curves = _add_curves(gmsh, by_ring)
            xy = np.concatenate([p for p, _, _ in curves])
            bounds = (*xy.min(axis=0), *xy.max(axis=0))
            add_size_view(gmsh, size, bounds, _along(gmsh, curves, size))
            gmsh.model.mesh.generate(1)
            pieces = []
            for piece, pid, tag in curves:
                _, coords, params = gmsh.model.mesh.getNodes(1, tag)
                inner = coords.reshape(-1, 3)[np.argsort(params), :2]
                pieces.append((np.vstack([piece[:1], inner, piece[-1:]]), pid))
        except Exception as exc:  # gmsh raises bare Exception with its last error
            raise MeshingError(f"Gmsh failed on the boundary: {exc}") from exc
    starts = np.cumsum([0] + [len(r) for r in by_ring])
    coords = [
        np.concatenate([pieces[a][0][:1], *(p[1:] for p, _ in pieces[a:b])])
        for a, b in itertools.pairwise(starts)
    ]
    return pieces, shapely.Polygon(coords[0], coords[1:])


def _along(
    gmsh: Any, curves: list[tuple[NDArray[np.float64], int, int]], size: Any
) -> NDArray[np.float64] | None:
    """Points along the curves, a quarter of a size-grid cell apart; or None.

    Gmsh's 1-D mesher asks for sizes on the curves only, so the size view
    needs only the grid cells along them (:func:`add_size_view` with these
    points): on the NW-shelf fine case 34,920 cells of its 839,004, and the
    same boundary nodes. A spline through ``n`` points takes them at
    the parameters ``k / (n - 1)``; each span is sampled at steps of at most a
    quarter cell along its chord (on the sphere, of the cell's shorter side
    in the plane at the span's ends; a span is shorter than a cell there).
    None (the whole grid) if that takes more points than the grid has
    cells, or if Gmsh's spline does not pass its points at those parameters.
    """
    spans = np.array([len(piece) - 1 for piece, _, _ in curves])
    ends = np.cumsum(spans)
    # every span of every curve at once: its chord, its samples, their parameters
    points = np.concatenate([piece for piece, _, _ in curves])
    at = np.delete(np.arange(len(points) - 1), np.cumsum(spans + 1)[:-1] - 1)
    if isinstance(size, SizeGrid) and min(len(size.x), len(size.y)) >= 2:
        step = 0.25 * min(np.min(np.diff(size.x)), np.min(np.diff(size.y)))
    elif isinstance(size, SphereSizeGrid):
        cell = size.plane_cell(points)
        step = 0.25 * np.minimum(cell[at], cell[at + 1])
    else:
        return None
    chords = np.hypot(*(points[at + 1] - points[at]).T)
    steps = np.maximum(np.ceil(chords / step), 1).astype(np.int64)
    if steps.sum() > _size_cells(size):  # more samples than cells: nothing saved
        return None
    first = np.cumsum(steps) - steps  # each span's first sample
    owner = np.searchsorted(ends, np.arange(len(at)), side="right")  # its curve
    span = np.repeat(np.arange(len(at)), steps)
    within = np.arange(len(span)) - first[span]
    local = span - (ends - spans)[owner[span]]  # the span's number in its curve
    t = (local + within / steps[span]) / spans[owner[span]]
    cut = np.cumsum(steps)[ends - 1]
    out = []
    for (_, _, tag), params in zip(curves, np.split(t, cut[:-1]), strict=True):
        xy = np.asarray(gmsh.model.getValue(1, tag, np.append(params, 1.0)))
        out.append(xy.reshape(-1, 3)[:, :2])
    along = np.concatenate(out)
    # each span's first sample and each curve's last must be its points
    # (each curve ends with one sample more: its parameter 1)
    knots = along[np.concatenate([first + owner, cut + np.arange(len(cut))])]
    expected = points[np.concatenate([at, np.cumsum(spans + 1) - 1])]
    if not np.allclose(knots, expected, rtol=0.0, atol=1e-3 * np.min(step)):
        return None
    return along


def _size_cells(size: Any) -> int:
    """Return how many cells a size grid (in the plane or on the sphere) has."""
    grid = size if isinstance(size, SizeGrid) else size.grid
    return int(grid.values.size)


def _ring_pieces(rings: list, ids: list) -> list[list]:
    """Return each ring's pieces, chunked, with their ids."""
    return [
        chunked(
            [(p, pid) for seg, pid in zip(ring, ring_ids, strict=True) for p in seg]
        )
        for ring, ring_ids in zip(rings, ids, strict=True)
    ]


def _add_curves(
    gmsh: Any, by_ring: list[list]
) -> list[tuple[NDArray[np.float64], int, int]]:
    """Add each ring's pieces as Gmsh splines; return (piece, id, curve tag)."""
    geo = gmsh.model.geo
    out = []
    for pieces in by_ring:
        first = geo.addPoint(*pieces[0][0][0], 0.0)
        start = first
        for k, (piece, pid) in enumerate(pieces):
            inner = [geo.addPoint(x, y, 0.0) for x, y in piece[1:-1]]
            end = first if k == len(pieces) - 1 else geo.addPoint(*piece[-1], 0.0)
            tags = [start, *inner, end]
            curve = geo.addLine(*tags) if len(tags) == 2 else geo.addSpline(tags)
            out.append((np.asarray(piece, dtype=np.float64), pid, curve))
            start = end
    geo.synchronize()
    return out


def chunked(pieces: list[tuple[NDArray, int]], most: int = CURVE_POINTS) -> list:
    """Split (piece, id) pairs of more than ``most`` points; ends are shared.

    Made for Gmsh's threads (one spline through thousands of points is one
    long serial job: in chunks, the NW-shelf intermediate boundary took 1.1 s
    on 2 threads instead of 2.8 s on one). The boundary is meshed on one
    thread now (:func:`boundary_nodes`); the chunks stay, as the splines they
    make decide where the nodes go.

    Examples
    --------
    >>> [len(p) for p, _ in chunked([(np.zeros((1201, 2)), 3)], most=500)]
    [401, 401, 401]
    """
    out = []
    for piece, pid in pieces:
        n = int(np.ceil((len(piece) - 1) / (most - 1)))
        if n <= 1:
            out.append((piece, pid))
            continue
        cuts = np.linspace(0, len(piece) - 1, n + 1).round().astype(int)
        out += [(piece[a : b + 1], pid) for a, b in itertools.pairwise(cuts)]
    return out
