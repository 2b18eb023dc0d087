"""A face of water cut along a line at its clean crossings only.

Where no straight cut of a face of water is clean wherever it crosses it
(:mod:`~coastmesh.meshing.parts.cuts`: on ``world_fine.toml`` a line across
the world ocean crosses it 10 to 60 times, and one crossing in three would
make thin triangles), the face is still cut along a line: at the crossings
that are clean. A crossing that is not is left uncut, so the water on its two
sides stays one face there. :func:`split_costs` finds what such a cut makes:
the face's pieces on either side of the line (GEOS's rectangle clip, in the
turned plane of :class:`~coastmesh.meshing.parts.crossings.Turned` for an
oblique line), joined across the crossings left uncut, with their expected
triangles. A piece of under ``small`` expected triangles (a bay the line cuts
off, a sliver) is joined across one of its crossings too, so it makes no face
of its own. :func:`faces_of` and :func:`cells_of` then find the faces the
kept crossings make and the size grid's nodes in each.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.geometry.cells import points_inside
from coastmesh.meshing.parts.crossings import Turned

__all__ = ["Split", "cells_of", "faces_of", "split_costs"]

#: A kept crossing is drawn this much longer (relative to its length) at both
#: ends before the face is polygonized: its ends lie on the face's boundary to
#: the last bits only, and a crossing that stops short would dangle.
_REACH = 1e-6


class Split(NamedTuple):
    """What cutting a face along a line at its clean crossings makes.

    ``kept``: the indices of the crossings cut; ``costs``: the expected
    triangles of each face it makes, largest first.
    """

    kept: list[int]
    costs: list[float]


def split_costs(
    polygon: shapely.Polygon,
    turned: Turned,
    at: float,
    cells: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    chords: list[shapely.LineString],
    clean: list[bool],
    small: float,
) -> Split:
    """Return the crossings a cut along a line keeps, and the faces' costs.

    Parameters
    ----------
    polygon : shapely.Polygon
        One face of water.
    turned : Turned
        ``polygon`` turned so that the line runs along y (as is, for a line
        along an axis); the line is where the coordinate along its normal
        is ``at``.
    at : float
        The line's place along its normal.
    cells : (x, y, weight)
        The size grid's nodes in ``polygon`` and their expected triangles.
    chords : list of shapely.LineString
        The line's crossings of ``polygon`` (``turned.chords``).
    clean : list of bool
        Whether each crossing is clean; those that are not are left uncut.
    small : float
        A face of fewer expected triangles is joined to a neighbour across
        one of its crossings.

    Returns
    -------
    Split
    """
    x, y, w = cells
    plane, u, v, first = _frame(polygon, turned, x, y)
    x0, y0, x1, y1 = plane.bounds
    if first:
        below = shapely.clip_by_rect(plane, x0 - 1, y0 - 1, at, y1 + 1)
        above = shapely.clip_by_rect(plane, at, y0 - 1, x1 + 1, y1 + 1)
        low = u < at
    else:
        below = shapely.clip_by_rect(plane, x0 - 1, y0 - 1, x1 + 1, at)
        above = shapely.clip_by_rect(plane, x0 - 1, at, x1 + 1, y1 + 1)
        low = v < at
    sides = [_polygons(below), _polygons(above)]
    pieces = sides[0] + sides[1]
    cost = np.zeros(len(pieces))
    for k0, side, mask in ((0, sides[0], low), (len(sides[0]), sides[1], ~low)):
        labels = cells_of(side, u, v, mask)
        held = labels >= 0  # none where the side holds no water
        cost[k0 : k0 + len(side)] = np.bincount(
            labels[held], w[held], minlength=len(side)
        )
    # each crossing's piece on either side: the nearest to its middle
    near = [shapely.STRtree(side) if side else None for side in sides]
    ends: list[tuple[int, int] | None] = []
    for chord in chords:
        xy = shapely.get_coordinates(chord)
        if not turned.axis:
            xy = xy @ turned.forward
        middle = shapely.points(xy.mean(axis=0))
        if near[0] is None or near[1] is None:
            ends.append(None)
            continue
        a = int(near[0].query_nearest(middle, all_matches=False)[0])
        b = int(near[1].query_nearest(middle, all_matches=False)[0])
        ends.append((a, len(sides[0]) + b))
    root = list(range(len(pieces)))

    def find(i: int) -> int:
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    glued = set()
    for k, (pair, ok) in enumerate(zip(ends, clean, strict=True)):
        if pair is not None and not ok:
            root[find(pair[0])] = find(pair[1])
            glued.add(k)
    # a face too small to mesh alone: joined across its first crossing kept
    for k, pair in enumerate(ends):
        if pair is None or k in glued:
            continue
        totals = _totals(cost, find)
        a, b = find(pair[0]), find(pair[1])
        if a != b and min(totals[a], totals[b]) < small:
            root[a] = b
            glued.add(k)
    totals = _totals(cost, find)
    kept = [
        k
        for k, pair in enumerate(ends)
        if pair is not None and k not in glued and find(pair[0]) != find(pair[1])
    ]
    return Split(kept, sorted(totals.values(), reverse=True))


def _totals(cost: NDArray[np.float64], find: Callable[[int], int]) -> dict[int, float]:
    """Return each joined face's cost, by its root piece."""
    totals: dict[int, float] = {}
    for k, c in enumerate(cost):
        r = find(k)
        totals[r] = totals.get(r, 0.0) + float(c)
    return totals


def _frame(
    polygon: shapely.Polygon,
    turned: Turned,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
) -> tuple[shapely.Polygon, NDArray[np.float64], NDArray[np.float64], bool]:
    """Return the plane the line is straight in, the cells there, and its axis.

    ``first``: whether the line runs across the first coordinate (x, or the
    turned plane's along) or the second (y).
    """
    if not turned.axis:
        uv = np.column_stack([x, y]) @ turned.forward
        return turned.turned, uv[:, 0], uv[:, 1], True
    return polygon, x, y, turned.direction[1] == 0.0


def _polygons(geometry: shapely.Geometry) -> list[shapely.Polygon]:
    return [g for g in shapely.get_parts(geometry) if g.geom_type == "Polygon"]


def faces_of(
    polygon: shapely.Polygon, chords: list[shapely.LineString]
) -> list[shapely.Polygon]:
    """Return the faces the ``chords`` (crossings of ``polygon``) cut it into.

    Examples
    --------
    >>> square = shapely.box(0, 0, 4, 4)
    >>> faces = faces_of(square, [shapely.LineString([(1, 0), (1, 4)])])
    >>> sorted(f.area for f in faces)
    [4.0, 12.0]
    """
    lines = [shapely.LineString(r.coords) for r in shapely.get_rings(polygon)]
    for chord in chords:
        xy = shapely.get_coordinates(chord)[[0, -1]]
        step = _REACH * (xy[1] - xy[0])
        lines.append(shapely.LineString([xy[0] - step, xy[1] + step]))
    noded = shapely.node(shapely.GeometryCollection(lines))
    faces = shapely.get_parts(shapely.polygonize(list(noded.geoms)))
    shapely.prepare(polygon)
    inside = shapely.contains(polygon, shapely.point_on_surface(faces))
    return list(faces[inside])


def cells_of(
    faces: list[shapely.Polygon],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mask: NDArray[np.bool_] | None = None,
) -> NDArray[np.int64]:
    """Return the index of the face that holds each point (``mask``: those only).

    The largest face (by area) is asked last, and holds what the others do
    not: a world's faces hold millions of grid nodes, most in the largest.
    Points outside ``mask`` get -1.

    Examples
    --------
    >>> faces = [shapely.box(0, 0, 1, 1), shapely.box(1, 0, 3, 1)]
    >>> cells_of(faces, np.array([0.5, 2.5, 1.5]), np.array([0.5, 0.5, 0.5]))
    array([0, 1, 1])
    """
    left = np.ones(len(x), dtype=bool) if mask is None else mask.copy()
    labels = np.full(len(x), -1, dtype=np.int64)
    if not faces:
        return labels
    order = np.argsort(-shapely.area(faces), kind="stable")
    for k in order[1:]:
        x0, y0, x1, y1 = faces[k].bounds
        at = np.flatnonzero(left & (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1))
        held = at[points_inside(faces[k], x[at], y[at])]
        labels[held] = k
        left[held] = False
    labels[left] = order[0]
    return labels
