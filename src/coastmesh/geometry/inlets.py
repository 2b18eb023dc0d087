"""Narrow inlets: where a coast comes back near itself, the part it cuts off.

The rasters of :func:`~coastmesh.geometry.closing.close_narrow_water` see
water narrower than a cell only where the land round it closes it off; an
inlet narrower than a cell that opens on the sea inside the cells along the
coast (a river mouth, a creek running along the shore) is seen as coast, and
kept. Resampled at a mesh's size, such an inlet's banks cross.

:func:`inlet_patches` finds them on the coast itself: each ring is walked in
steps of half ``gap`` (on the Earth, in a stereographic plane), and
wherever a step comes back within ``gap`` of an earlier one, across water,
between 4 ``gap`` and ``reach`` further along the ring, the ring between
them and the chord across bound an inlet. Each largest such piece is
returned, to be unioned with the land. Written here with numpy: it is a
search along each ring, in lags, for which a spatial index (every pair of
nearby steps) would find mostly steps next to each other on the same ring.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.geometry.sphere import plane_scale

__all__ = ["inlet_patches"]

_STEPS = 2  #: steps to a gap
_DEEP = 4  #: gaps round a piece at least (so it is about 1.5 gaps deep)


def inlet_patches(
    polygons: NDArray[np.object_], gap: float, reach: float
) -> NDArray[np.object_]:
    """Return the pieces cut off where the polygons' rings come back near themselves.

    Parameters
    ----------
    polygons : ndarray of shapely Polygons
        Land in a stereographic plane (exteriors and holes are walked alike).
    gap : float
        Metres on the Earth: a chord shorter than this closes a piece off.
    reach : float
        Metres on the Earth: the longest stretch of ring a piece is bounded by.

    Returns
    -------
    ndarray of shapely Polygons
        The pieces, each bounded by a stretch of ring and its chord (valid;
        the largest of those that nest).

    Examples
    --------
    A square with an inlet 300 m wide and 3 km deep in its side:

    >>> ring = [(0, 0), (10e3, 0), (10e3, 4.85e3), (7e3, 4.85e3), (7e3, 5.15e3),
    ...         (10e3, 5.15e3), (10e3, 10e3), (0, 10e3)]
    >>> (inlet,) = inlet_patches([shapely.Polygon(ring)], 1e3, 20e3)
    >>> inlet.contains(shapely.Point(8e3, 5e3)), round(inlet.area / 1e6, 2)
    (True, 0.9)
    """
    polygons = np.asarray(polygons, dtype=object)
    shapely.prepare(polygons)  # asked whether chords cross land, many times
    xy, ring, owner = _steps(polygons, gap / _STEPS)
    if len(xy) == 0:
        return np.empty(0, dtype=object)
    start, count = np.unique(ring, return_index=True, return_counts=True)[1:]
    pos = np.arange(len(xy)) - np.repeat(start, count)
    n = np.repeat(count, count)
    k = plane_scale(np.hypot(xy[:, 0], xy[:, 1]))
    near = (gap * k) ** 2  # the gap in the plane, squared, at each step
    found = []
    for lag in range(_DEEP * _STEPS, math.ceil(reach / gap * _STEPS) + 1):
        fits = lag < n // 2  # half round a ring at most: its short side
        j = np.repeat(start, count) + (pos + lag) % n
        d2 = ((xy[j] - xy) ** 2).sum(axis=1)
        hit = np.flatnonzero(fits & (d2 < near))
        # across water, not across a spit of land
        middle = 0.5 * (xy[hit] + xy[j[hit]])
        land = shapely.contains_xy(polygons[owner[hit]], middle[:, 0], middle[:, 1])
        found.append(np.column_stack([hit[~land], np.full(int((~land).sum()), lag)]))
    pairs = np.concatenate(found)
    if len(pairs) == 0:
        return np.empty(0, dtype=object)
    first, lags = _largest(pairs, pos, ring)
    return _pieces(xy, start[ring[first]], n[first], pos[first], lags)


def _steps(
    polygons: NDArray[np.object_], step: float
) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.intp]]:
    """Return points along every ring at about ``step`` metres on the Earth apart.

    Vertices are kept where a step's length has been walked since the last
    one kept, and edges longer than a step are cut in steps; each ring's
    points are in its order, the last not repeating the first. Returns the
    points, their ring, and their polygon.
    """
    rings, polygon = shapely.get_rings(polygons, return_index=True)
    xy, ring = shapely.get_coordinates(rings, return_index=True)
    a, b = xy[:-1], xy[1:]
    same = ring[1:] == ring[:-1]
    mid = 0.5 * (a + b)
    k = plane_scale(np.hypot(mid[:, 0], mid[:, 1]))
    length = np.where(same, np.hypot(*(b - a).T) / k, 0.0)  # on the Earth
    pieces = np.where(same, np.maximum(np.ceil(length / step), 1), 0).astype(np.int64)
    e = np.repeat(np.arange(len(a)), pieces)
    t = (np.arange(len(e)) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(
        pieces, pieces
    )
    points = a[e] + t[:, None] * (b - a)[e]
    walked = np.cumsum(np.repeat(length / pieces.clip(1), pieces))
    walked -= np.repeat(length / pieces.clip(1), pieces)  # at each point
    ring = ring[e]
    # one point a step: the first in each step of each ring
    bucket = np.floor(walked / step).astype(np.int64)
    first = np.r_[True, (ring[1:] != ring[:-1]) | (bucket[1:] != bucket[:-1])]
    return points[first], ring[first], polygon[ring[first]]


def _largest(
    pairs: NDArray[np.intp], pos: NDArray[np.intp], ring: NDArray[np.intp]
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Return the (first step, lag) of the pairs not inside another's stretch.

    Nor nearly: a stretch must reach past those before it by 2 gaps, or it
    is the same piece seen from a step on.
    """
    first, lag = pairs[:, 0], pairs[:, 1]
    order = np.lexsort((-lag, pos[first], ring[first]))
    first, lag = first[order], lag[order]
    end = pos[first] + lag
    # the furthest end of the stretches before, in the same ring
    ring_of = ring[first]
    new_ring = np.r_[True, ring_of[1:] != ring_of[:-1]]
    group = np.cumsum(new_ring) - 1
    offset = group * (2 * int(end.max()) + 2)  # keeps each ring's ends apart
    before = np.r_[-1, np.maximum.accumulate(end + offset)[:-1]] - offset
    keep = new_ring | (end > before + 2 * _STEPS)
    return first[keep], lag[keep]


def _pieces(
    xy: NDArray[np.float64],
    start: NDArray[np.intp],
    n: NDArray[np.intp],
    pos: NDArray[np.intp],
    lag: NDArray[np.intp],
) -> NDArray[np.object_]:
    """Return the polygons of the stretches (from ``pos``, ``lag`` steps long)."""
    index = np.repeat(start, lag + 1) + (
        np.repeat(pos, lag + 1)
        + np.arange(int((lag + 1).sum()))
        - np.repeat(np.cumsum(lag + 1) - (lag + 1), lag + 1)
    ) % np.repeat(n, lag + 1)
    coords = xy[index]
    offsets = np.r_[0, np.cumsum(lag + 1)]
    # each ring closed by its chord: repeat its first point
    closed = np.insert(coords, offsets[1:], coords[offsets[:-1]], axis=0)
    ring_offsets = offsets + np.arange(len(offsets))
    polygons = shapely.from_ragged_array(
        shapely.GeometryType.POLYGON,
        closed,
        (ring_offsets, np.arange(len(offsets))),
    )
    bad = ~shapely.is_valid(polygons)
    polygons[bad] = shapely.make_valid(polygons[bad])
    parts = shapely.get_parts(polygons)
    return parts[
        (shapely.get_type_id(parts) == shapely.GeometryType.POLYGON)
        & (shapely.area(parts) > 0)
    ]
