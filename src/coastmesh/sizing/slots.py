"""Slots: water narrower than a width, to be closed as land before meshing."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.geometry.earth import densified, reproject
from coastmesh.types import Domain

__all__ = [
    "SLIVER",
    "TILE_VERTICES",
    "domain_slots",
    "off_open_boundaries",
    "slots",
    "slots_near",
    "tiles",
]

#: Most vertices of the polygon in one tile of :func:`slots`.
TILE_VERTICES = 50_000
#: The opening of :func:`slots` is grown by this fraction of its radius.
SLIVER = 1e-6
#: A box: ``(xmin, ymin, xmax, ymax)``.
_Box = tuple[float, ...]


def slots(
    polygon: shapely.Polygon,
    width: float,
    *,
    threads: int = 1,
    tile_vertices: int = TILE_VERTICES,
) -> NDArray[np.object_]:
    """Return the slots of water narrower than ``width``: too thin for a grid.

    The water left out of the polygon's opening by a disk of diameter
    ``width`` (GEOS buffers in and out), in pieces; a piece counts only if it is
    at least twice ``width`` long (the diagonal of its bounding box), so that
    the corners the opening rounds off do not. Slots far narrower than a size
    grid cell (a spike of a coastline) are invisible to
    :func:`~coastmesh.sizing.channel.local_width`. The second buffer grows by
    ``SLIVER`` of the radius more: GEOS's rounding puts straight coasts back
    a hair off, and the slivers that left passed for slots (4,723 of 4,727
    pieces on the NW-shelf fine domain, micrometres thick).

    A polygon of more than ``tile_vertices`` vertices is opened in
    :func:`tiles`, on ``threads`` threads (GEOS lets go of the GIL): the
    opening at a point depends only on the water within ``width`` of it, so
    each tile is opened with the water within a little more than ``width`` of
    it, and the pieces that touch a tile's edge are merged. The tiles depend
    on the polygon alone, so the slots do not depend on ``threads``; they are
    the same water as in one piece (to GEOS's rounding), though a piece may
    come out in two that touch at a point. On the NW-shelf fine domain
    (171,000 vertices, 4 tiles): 3.3 s in one piece, 2.4-2.8 s in tiles one
    after the other, 1.6-1.9 s on 2 threads.

    Examples
    --------
    >>> bay = shapely.Polygon([(0, 0), (100, 0), (100, 100), (52, 100), (52, 300),
    ...                        (48, 300), (48, 100), (0, 100)])
    >>> [round(p.area, -1) for p in slots(bay, 10.0)]  # the 4 m x 200 m slot
    [800.0]
    """
    r = width / 2
    cores = tiles(polygon, tile_vertices)
    if len(cores) == 1:
        pieces = _thin(polygon, polygon, None, r)
    else:
        margin = 1.01 * width  # the opening within the core sees all it needs

        def tile(core: shapely.Polygon) -> NDArray[np.object_]:
            window = shapely.box(
                *(np.array(core.bounds) + [-margin, -margin, margin, margin])
            )
            return _thin(polygon, shapely.intersection(polygon, window), core, r)

        with ThreadPoolExecutor(max(1, min(int(threads), len(cores)))) as pool:
            found = np.concatenate(list(pool.map(tile, cores)))
        edges = shapely.union_all(shapely.boundary(cores))
        touch = shapely.intersects(found, edges)
        merged = shapely.get_parts(shapely.union_all(found[touch]))
        pieces = np.concatenate(
            [found[~touch], merged[shapely.get_type_id(merged) == 3]]
        )
    return _long(pieces, width)


def slots_near(
    polygon: shapely.Polygon,
    width: float,
    boxes: NDArray[np.float64],
    land: shapely.Geometry | None = None,
) -> NDArray[np.object_]:
    """Return the slots of ``polygon`` less ``land`` that lie in ``boxes``.

    As :func:`slots`, looking only in each box of ``boxes`` (rows of ``xmin,
    ymin, xmax, ymax``) with the water within a little more than ``width`` of
    it: after a few polygons of water are closed, the slivers they leave are
    next to them, and the rest of the water need not be opened again. A slot
    that crosses a box's edge is cut there (boxes around the closed polygons,
    wider than ``width``, hold the slivers at their edges). Boxes that overlap
    may return a slot twice.

    Examples
    --------
    >>> bay = shapely.Polygon([(0, 0), (100, 0), (100, 100), (52, 100), (52, 300),
    ...                        (48, 300), (48, 100), (0, 100)])
    >>> boxes = np.array([[0.0, 50.0, 100.0, 350.0]])
    >>> [round(p.area, -1) for p in slots_near(bay, 10.0, boxes)]
    [800.0]
    >>> len(slots_near(bay, 10.0, np.array([[0.0, 0.0, 100.0, 40.0]])))
    0
    """
    r, margin = width / 2, 1.01 * width
    found = []
    for box in np.asarray(boxes, dtype=np.float64).reshape(-1, 4):
        window = shapely.clip_by_rect(
            polygon, *(box + [-margin, -margin, margin, margin])
        )
        if land is not None:
            window = shapely.difference(window, land)
        found.append(_thin(window, window, shapely.box(*box), r))
    pieces = np.concatenate(found) if found else np.empty(0, dtype=object)
    return _long(pieces, width)


def _long(pieces: NDArray[np.object_], width: float) -> NDArray[np.object_]:
    """Return the pieces at least ``2 width`` long (their bounding box's diagonal)."""
    if not len(pieces):
        return pieces
    bounds = shapely.bounds(pieces)
    length = np.hypot(bounds[:, 2] - bounds[:, 0], bounds[:, 3] - bounds[:, 1])
    long: NDArray[np.object_] = pieces[length >= 2 * width]
    return long


def _thin(
    polygon: shapely.Polygon,
    window: shapely.Geometry,
    core: shapely.Polygon | None,
    r: float,
) -> NDArray[np.object_]:
    """Return the pieces of the polygon (in ``core``, else all) the opening misses."""
    # the opening grown by a millionth of r: GEOS's rounding leaves slivers
    # (micrometres wide or less) along straight coasts where the opening meets
    # them, long enough to pass for slots, or to make a corner's piece look
    # long when joined to it at a tile's edge
    grow = max(SLIVER * r, 1e-12 * float(np.abs(shapely.bounds(window)).max()))
    opened = shapely.buffer(shapely.buffer(window, -r), r + grow)
    inside = polygon if core is None else shapely.intersection(polygon, core)
    # shapely is untyped here (types-shapely is not among the dependencies)
    pieces: NDArray[np.object_] = shapely.get_parts(shapely.difference(inside, opened))
    polygons: NDArray[np.object_] = pieces[shapely.get_type_id(pieces) == 3]
    return polygons


def tiles(polygon: shapely.Geometry, most: int) -> NDArray[np.object_]:
    """Return boxes tiling the polygon's bounds, each holding at most ``most`` vertices.

    A box with more is split in two at the median of its vertices across its
    longer side (a k-d tree's cells), so the tiles hold about equal numbers of
    vertices: the cost of opening the water goes with them.

    Examples
    --------
    >>> square = shapely.Polygon([(0, 0), (4, 0), (4, 1), (0, 1)]).segmentize(0.5)
    >>> [b.bounds for b in tiles(square, 12)]
    [(0.0, 0.0, 2.0, 1.0), (2.0, 0.0, 4.0, 1.0)]
    """
    xy: NDArray[np.float64] = shapely.get_coordinates(polygon)
    todo: list[tuple[_Box, NDArray[np.float64]]] = [
        (tuple(map(float, shapely.bounds(polygon))), xy)
    ]
    done: list[_Box] = []
    while todo:
        box, inside = todo.pop()
        halves = _halves(box, inside) if len(inside) > most else None
        if halves is None:
            done.append(box)
        else:
            todo += halves[::-1]
    # shapely is untyped here (types-shapely is not among the dependencies)
    boxes: NDArray[np.object_] = shapely.box(*np.array(done).T)
    return boxes


def _halves(
    box: _Box, inside: NDArray[np.float64]
) -> list[tuple[_Box, NDArray[np.float64]]] | None:
    """Return the box split in two at the median of its vertices, or None.

    Across its longer side if it can be, else across the other; None if
    neither can (half its vertices on its edge).
    """
    x0, y0, x1, y1 = box
    for axis in (0, 1) if x1 - x0 >= y1 - y0 else (1, 0):
        cut = float(np.median(inside[:, axis]))
        if not (x0, y0)[axis] < cut < (x1, y1)[axis]:
            continue
        below = inside[:, axis] < cut
        lo, hi = list(box), list(box)
        lo[axis + 2], hi[axis] = cut, cut
        return [(tuple(lo), inside[below]), (tuple(hi), inside[~below])]
    return None


def domain_slots(
    domain: Domain, mesh_crs: CRS | str, width: float, *, threads: int = 1
) -> NDArray[np.object_]:
    """Return the slots of the domain's water narrower than ``width``, as land.

    :func:`slots` of the domain (in ``mesh_crs``, metres; on ``threads``
    threads), grown by ``width / 10`` so that they overlap the land, in the
    domain's CRS; none that touches an open boundary (it must still cross the
    coast there to close the domain). :func:`coastmesh.build_case` closes the
    slots narrower than half of ``h_min`` whatever ``narrow`` says: no element
    fits in them, and their tips make the worst elements of a mesh.
    """
    mesh_crs = CRS.from_user_input(mesh_crs)
    water = densified(domain, [domain.polygon], mesh_crs)[0]
    thin = slots(water, width, threads=threads)
    if not len(thin):
        return thin
    grown = reproject(shapely.buffer(thin, width / 10), mesh_crs, domain.crs)
    return off_open_boundaries(grown, domain)


def off_open_boundaries(
    polygons: NDArray[np.object_], domain: Domain
) -> NDArray[np.object_]:
    """Drop the polygons that touch an open boundary of the domain."""
    opened = [shapely.LineString(s.coords) for s in domain.segments if s.kind == "open"]
    if not opened or not len(polygons):
        return polygons
    touch: NDArray[np.bool_] = shapely.intersects(polygons, shapely.union_all(opened))
    return polygons[~touch]
