"""The closing of narrow water by GEOS buffers: the literal reference.

This is :func:`coastmesh.geometry.close_narrow_water` as it was before it ran
on rasters (:mod:`coastmesh.geometry.closing`): a morphological closing with
shapely buffers of the whole land, ring by ring of the stereographic plane,
then an opening but for land of ``keep_area`` or more. It is exact to the
buffers' arcs, and slow: 51 s for GSHHG's intermediate world, minutes at full
resolution. The fast closing is checked against it (``test_closing.py``).
Never import it from the package.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import shapely
import shapely.affinity

from coastmesh.geometry.earth import EARTH_RADIUS


def close_narrow_water_reference(land, width, *, within=None, keep_area=0.0, thin=None):
    """Close water narrower than ``width`` between and within land polygons.

    A morphological closing (buffer out by ``width / 2``, then back in) in the
    stereographic plane, where a length on the Earth is ``k`` times longer,
    ``k = 1 + r^2 / 4R^2``: the plane is cut into rings over which ``k``
    changes by at most 20 %; each ring's land, with a margin, is closed at that
    ring's largest ``k`` and cut back to the ring. Land narrower than ``width``
    is then opened away, but for land of ``keep_area`` or more (square metres
    on the Earth, ``k^2`` at each polygon's centroid), whose thin parts are
    grown by ``width / 2`` instead (:func:`_thickened`; appended to ``thin``
    if given), and the necks between land facing itself over a straight gap
    narrower than 0.7 ``width`` bridged (:func:`_bridged`); land beyond ``within``
    (metres in the plane) is kept as it is. Returns the polygons, the largest
    first, and how many fewer there are than the input's.
    """
    land = np.asarray(land, dtype=object)
    radius = 2.0 * EARTH_RADIUS
    corners = np.abs(np.asarray(shapely.total_bounds(land))).reshape(2, 2)
    outer = float(np.hypot(*corners.max(axis=0)))
    if within is not None:
        outer = min(outer, within)
    edges = [0.0]
    while edges[-1] < outer:  # k(r1) / k(r0) <= 1.2
        r0 = edges[-1]
        k0 = 1.0 + (r0 / radius) ** 2
        edges.append(max(radius * math.sqrt(max(1.2 * k0 - 1.0, 0.0)), r0 + 1.0))
    union = shapely.union_all(land)
    big = _big_land(union, keep_area, radius)
    pieces = []
    for r0, r1 in itertools.pairwise(edges):
        half = 0.5 * width * (1.0 + (r1 / radius) ** 2)  # the ring's largest k
        ring = _annulus(r0, r1)
        near = union.intersection(_annulus(max(r0 - 3 * half, 0.0), r1 + 3 * half))
        if near.is_empty:
            continue
        # GEOS 3.14 can return nothing for buffer(d).buffer(-d) of a polygon
        # with a spike (a valid one, 42 km2 at d = 600 m); a back buffer a
        # millionth shorter does not, and differs by nothing a test can see
        back = half * (1.0 - 1e-6)
        closed = near.buffer(half, quad_segs=4).buffer(-back, quad_segs=4)
        opened = closed.buffer(-back, quad_segs=4).buffer(half, quad_segs=4)
        kept = _thickened(_kept(closed, big), opened, half, back, thin)
        piece = _bridged(shapely.union_all([opened, *kept]), 0.35 * 2 * half)
        pieces.append(piece.intersection(ring))
    if within is not None:  # the land beyond, as it is
        pieces.append(union.difference(_annulus(0.0, edges[-1])))
    # the rings' seams can leave spikes of no width; a metre's closing and
    # opening takes them away
    closed = shapely.union_all(pieces).buffer(1.0).buffer(-2.0).buffer(1.0)
    parts = shapely.get_parts(closed)
    parts = parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]
    first = np.argmax(shapely.area(parts))
    parts = np.concatenate([parts[first : first + 1], np.delete(parts, first)])
    return parts, max(len(land) - len(parts), 0)


def _big_land(union, keep_area, radius):
    """The land polygons of ``keep_area`` or more on the Earth; None if none."""
    if keep_area <= 0:
        return None
    parts = shapely.get_parts(union)
    r = np.hypot(*shapely.get_coordinates(shapely.centroid(parts)).T)
    k = 1.0 + (r / radius) ** 2
    big = parts[shapely.area(parts) / k**2 >= keep_area]
    if not len(big):
        return None
    out = shapely.union_all(big)
    shapely.prepare(out)
    return out


def _kept(closed, big):
    """The land of ``closed`` on ``big`` land, as it is (not opened)."""
    if big is None:
        return []
    parts = shapely.get_parts(closed)
    return list(parts[shapely.intersects(parts, big)])


def _thickened(kept, opened, half, back, found=None):
    """Big land ``kept`` with its thin parts grown by ``half`` and closed again.

    Thin: what the opening took from it farther than ``half`` from the
    opened land (spits, peninsulas; not the corners it rounds). Each ring's
    thin parts are appended to ``found`` if given.
    """
    if not kept:
        return kept
    land = shapely.union_all(kept)
    thin = land.difference(opened.buffer(half, quad_segs=4))
    if thin.is_empty:
        return kept
    if found is not None:
        found.append(thin)
    grown = shapely.union(land, thin.buffer(half, quad_segs=4))
    return [grown.buffer(half, quad_segs=4).buffer(-back, quad_segs=4)]


def _bridged(land, half):
    """``land`` and every point on a straight gap of at most ``2 half`` across it.

    The union, over 12 directions 15 degrees apart, of the closing by a
    segment of ``half`` each side: the Minkowski sum with the segment (the
    land moved both ways, and each edge swept), then the same of the water
    taken away.
    """
    if land.is_empty:
        return land
    frame = shapely.box(*land.buffer(4 * half, quad_segs=1).bounds)
    out = [land]
    for angle in np.deg2rad(np.arange(0.0, 180.0, 15.0)):
        u = half * np.array([math.cos(angle), math.sin(angle)])
        grown = _swept(land, u)
        out.append(frame.difference(_swept(frame.difference(grown), u)))
    return shapely.union_all(out)


def _swept(polygons, u):
    """The Minkowski sum of ``polygons`` with the segment from ``-u`` to ``u``."""
    rings = shapely.get_rings(shapely.get_parts(polygons))
    xy, ring = shapely.get_coordinates(rings, return_index=True)
    same = ring[1:] == ring[:-1]
    a, b = xy[:-1][same], xy[1:][same]
    quads = shapely.polygons(np.stack([a - u, b - u, b + u, a + u, a - u], axis=1))
    moved = [shapely.affinity.translate(polygons, *s) for s in (u, -u)]
    return shapely.union_all([*moved, *quads[shapely.is_valid(quads)]])


def _annulus(r0, r1):
    """The ring between radii ``r0`` and ``r1`` about the plane's centre."""
    outer = shapely.Point(0.0, 0.0).buffer(r1, quad_segs=256)
    if r0 <= 0.0:
        return outer
    return outer.difference(shapely.Point(0.0, 0.0).buffer(r0, quad_segs=256))
