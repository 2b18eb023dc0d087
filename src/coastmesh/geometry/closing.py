"""Close narrow water between world shorelines, fast: on rasters, ring by ring.

A mesh of size ``h`` cannot resolve water narrower than ``h``: the coast
resampled at ``h`` would cross itself there. :func:`close_narrow_water` fills
it by a morphological closing (dilate the land by ``width / 2``, erode it
back) in the stereographic plane, where a length on the Earth is ``k`` times
longer, ``k = 1 + r^2 / 4R^2`` at a distance ``r`` from the plane's centre.
The plane is cut into rings over which ``k`` changes by at most 20 %, and
each ring is closed at its largest ``k``: the width closed is ``width`` to
within that 20 % anywhere on the Earth.

Buffering the whole world's coast with GEOS, as this was done first, takes
minutes at GSHHG's full resolution (10 M vertices) and more memory than a
12 GB machine has. Here each ring is rasterised instead, at a cell of
``width / 8`` at its scale, in tiles of 256 x 256 cells where it has coast
(:mod:`~coastmesh.geometry.cells`):

1. the cells whose centre the land holds (winding numbers, by scan lines),
   and the cells its coast crosses;
2. a binary closing of the cells the land touches (either), with a disk of
   3.5 cells: land thinner than a cell (a barrier island) still bounds the
   water behind it, and a cell the coast crosses is land half way across on
   average;
3. the necks the disk's closing leaves between points of land facing each
   other over less than about 0.7 of the width, bridged along straight runs
   of cells (:func:`~coastmesh.geometry.cells.bridge`), and the land closed
   again round the bridges;
4. the cells the closing fills, the cells the coast crosses inside the closed
   land (water narrower than a cell), and the land cells beside those, so a
   patch covers the water part of each cell the coast crosses there, traced
   into polygons (marching squares);
5. and the inlets narrower than a cell that open on the sea, which the
   rasters see as coast, found on the coast itself
   (:func:`~coastmesh.geometry.inlets.inlet_patches`);
6. those patches unioned with the exact land they touch, one connected group
   at a time; holes left that cannot hold the disk are filled.

The coast keeps its exact vertices wherever the closing changed nothing, and
GEOS works only where it did; where it did, the coast is moved by up to a cell
(``width / 8``) from where the buffers put it, mostly seawards at the edges of
the patches. Land smaller than ``keep_area`` is also opened (land narrower
than ``width`` taken away) on the same rasters; land of ``keep_area`` or more
is never opened, but its thin parts (what the opening would take farther
than ``width / 2`` from the land it keeps: spits, peninsulas, long necks) are
grown by ``width / 2`` each side and closed again, so that it too can be
resolved at ``width``. Which land is thin is judged by the ring it lies in
alone, and that ring keeps all it grows, past its edge too: rings judge at
scales up to 20 % apart, and a neck grown by one and cut off at its edge left
a wedge of water beside it. The buffers' closing is kept in the tests, which
compare the two (``tests/geometry/closing_reference.py``).
"""

from __future__ import annotations

import itertools
import math
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.geometry import cells
from coastmesh.geometry.earth import (
    EARTH_RADIUS,
    ellipsoid_area_scale,
    reproject_points,
)
from coastmesh.geometry.inlets import inlet_patches
from coastmesh.geometry.sphere import plane_scale
from coastmesh.geometry.unions import group_labels, groups_of, meeting_pairs

__all__ = ["IslandChange", "close_narrow_water", "earth_areas", "island_changes"]

_R2 = 2.0 * EARTH_RADIUS  #: r = _R2 sqrt(k - 1) inverts plane_scale (any pole)
_DISK = 4  #: the closing's disk radius, in cells: a cell is width / 8
_CLOSE = _DISK - 0.5  #: the disk of the closing of the cells land touches
_TILE = 256  #: a tile's core, cells a side
_BRIDGE = _DISK // 2  #: the bridging's segments reach this far each side
#: (cells): with the cells the coast crosses, gaps of water up to about 0.7
#: of the width (5 to 7 cells), the necks that make elements of under half
#: the size; the disk's closing already fills those between square corners
#: up to 0.41 of it
_HALO = 8 * _DISK + 2 * _BRIDGE + 4  #: the closing, the opening, the
#: thickening (grown from the opening's reach) and the closing again reach 2,
#: 2, 2 and 2 disks, and the bridging two segments' halves (a segment
#: covering a cell at its end)
_WINDOW = _TILE + 2 * _HALO  #: a tile's window, cells a side
_OVERLAP = 2  #: cells past a tile's core (and a ring's edge) traced too
_THICK = 2 * _DISK  #: how far (cells) the thickening reaches from the thin land
#: it grows (a disk less a cell, then the closing's disk): a ring traces that
#: far past its edges, so what it grows from its own thin land is all kept
_INLET = 1 / 6  #: inlets narrower than this (of width) found on the coast: a cell
#: at any ring's scale (width / 8, and up to 20 % more in its inner part)
_INLET_REACH = 2.0  #: and up to this (of width) round
_BATCH = 24  #: tiles rasterised at once
_PREPARED = threading.Lock()  #: one thread at a time asks the prepared polygons
_KEY = 2**20  #: tile columns and rows lie in (-_KEY, _KEY)


def close_narrow_water(
    land: NDArray[np.object_],
    width: float,
    *,
    within: float | None = None,
    keep_area: float = 0.0,
    zone: shapely.Geometry | None = None,
    threads: int = 1,
    crs: CRS | None = None,
) -> tuple[NDArray[np.object_], int]:
    """Close water narrower than ``width`` between and within land polygons.

    A morphological closing with a disk of diameter ``width`` on the Earth, in
    the stereographic plane, ring by ring (see the module's docstring), to
    within 20 % of ``width`` and a cell of ``width / 8``. Land smaller than
    ``keep_area`` is opened as well: strips of it narrower than ``width`` go;
    larger land's strips are thickened to ``width``.

    Parameters
    ----------
    land : ndarray of shapely polygons
        Land in a stereographic plane of
        :func:`~coastmesh.geometry.sphere.plane_crs` (any pole): the scale
        there depends only on the distance from the plane's centre.
    width : float
        Metres on the Earth.
    within : float, optional
        Only within this distance of the plane's centre (metres in the plane):
        land beyond it (the far side of a frame round the ocean) is kept as it
        is, however thin.
    keep_area : float, default 0
        Land of at least this area (square metres on the Earth), with what the
        closing joins to it, is never opened: its parts thinner than
        ``width`` are thickened to it instead. The opening applies to smaller
        land only. A tide model must keep the islands it was asked for,
        whole: they block and steer the flow.
    zone : shapely geometry, optional
        Only inside it (in the plane); land elsewhere is kept as it is.
    threads : int, default 1
        Threads the rings and the unions run on (numpy and GEOS let go of
        Python's lock). The result does not depend on it.
    crs : pyproj.CRS, optional
        The plane's CRS: ``keep_area`` is then measured on the WGS84
        ellipsoid, as ``[shorelines] min_area`` is (:func:`earth_areas`);
        without it, on the sphere.

    Returns
    -------
    land : ndarray of shapely Polygons
        The land after the closing, the largest polygon first (a frame round
        the ocean, when one was given). Polygons the closing did not touch are
        the input's own objects.
    merged : int
        Input polygons fewer in the output (joined to another, or opened away).

    Examples
    --------
    Two squares 2 km apart near the plane's centre, closed at 5 km:

    >>> squares = [shapely.box(0, 0, 50e3, 50e3), shapely.box(52e3, 0, 99e3, 50e3)]
    >>> closed, merged = close_narrow_water(squares, 5e3)
    >>> len(closed), merged, closed[0].contains(shapely.Point(51e3, 25e3))
    (1, 1, True)
    """
    given = np.asarray(land, dtype=object).ravel()
    polygons = _polygons_of(given)
    if len(polygons) == 0 or width <= 0:
        return polygons, 0
    region = _Region.of(polygons, width, within, zone)
    # the land near where the closing may change it; the rest stays as it is
    near = np.ones(len(polygons), dtype=bool)
    if region.box is not None:
        near = shapely.intersects(shapely.box(*region.box), polygons)
    active, polygons = polygons[near], polygons[~near]
    if len(active) == 0:
        return np.concatenate([active, polygons]), 0
    edges = _Edges.of(active, region.box)
    land_pairs = meeting_pairs(active)
    big = _big(active, keep_area, land_pairs, crs)
    shapely.prepare(active)
    tree = shapely.STRtree(active)
    with ThreadPoolExecutor(max(1, int(threads))) as pool:
        # and the inlets narrower than a cell that open on the sea, which the
        # rasters see as coast (but those a patch covers already): found on
        # the coast itself, beside the rings, on copies of the land (GEOS
        # builds a prepared polygon's index on its first use, and the rings
        # ask the originals, one thread at a time: _PREPARED)
        inlets_found = pool.submit(
            inlet_patches,
            cells.copies(active),
            _INLET * width,
            _INLET_REACH * width,
        )
        done = list(
            pool.map(
                lambda r: _close_ring(
                    _Ring(r[0], r[1], width, region), edges, big, active, tree
                ),
                region.rings,
            )
        )
        inlets = inlets_found.result()
    adds = np.array([p for added, _ in done for p in added], dtype=object)
    cuts = np.array([p for _, cut in done for p in cut], dtype=object)
    point = shapely.get_coordinates(shapely.point_on_surface(inlets))
    new = region.holds(point[:, 0], point[:, 1])
    new[shapely.STRtree(adds).query(inlets, predicate="covered_by")[0]] = False
    adds = np.concatenate([adds, inlets[new]])
    parts, kept = _apply(active, adds, big, land_pairs, width, region, threads)
    parts = _open(parts, kept, cuts, width, region)
    parts = np.concatenate([parts, polygons])
    if len(parts) == 0:  # all of it was land narrower than width, opened away
        return parts, len(given)
    first = int(np.argmax(shapely.area(parts)))
    parts = np.concatenate([parts[first : first + 1], np.delete(parts, first)])
    return parts, max(len(given) - len(parts), 0)


def _polygons_of(geoms: NDArray[np.object_]) -> NDArray[np.object_]:
    """Return the polygons of ``geoms``: polygons as they are, multis in parts."""
    geoms = geoms[~shapely.is_missing(geoms)]
    kind = shapely.get_type_id(geoms)
    one = kind == shapely.GeometryType.POLYGON
    parts = shapely.get_parts(geoms[~one])
    parts = parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]
    return np.concatenate([geoms[one], parts])


def _rings(outer: float) -> list[tuple[float, float]]:
    """Return the rings of the plane, to ``outer``, over which k grows <= 20 %."""
    edges = [0.0]
    while edges[-1] < outer:  # k(r1) / k(r0) <= 1.2
        r0 = edges[-1]
        k0 = plane_scale(r0)
        edges.append(max(_R2 * math.sqrt(max(1.2 * k0 - 1.0, 0.0)), r0 + 1.0))
    return list(itertools.pairwise(edges))


@dataclass(frozen=True, slots=True)
class _Region:
    """Where the closing may change the land: within ``outer``, in ``zone``.

    ``rings`` are the plane's rings that meet it; ``box`` (with a zone) is the
    zone's bounds grown by a tile's window at the largest of their cells: the
    land whose edges the tiles there see.
    """

    outer: float
    zone: shapely.Geometry | None
    rings: list[tuple[float, float]]
    box: tuple[float, float, float, float] | None

    @classmethod
    def of(
        cls,
        polygons: NDArray[np.object_],
        width: float,
        within: float | None,
        zone: shapely.Geometry | None,
    ) -> _Region:
        """Return the region of ``polygons`` closed at ``width`` (see above)."""
        corners = np.abs(np.asarray(shapely.total_bounds(polygons))).reshape(2, 2)
        outer = float(np.hypot(*corners.max(axis=0)))
        outer = outer if within is None else min(outer, within)
        rings = _rings(outer)
        if zone is None:
            return cls(outer, None, rings, None)
        x0, y0, x1, y1 = zone.bounds
        lo, hi = _gap(x0, y0, x1, y1), _top(x0, y0, x1, y1)
        rings = [(r0, r1) for r0, r1 in rings if r0 <= hi and r1 >= lo]
        last = max((r1 for _, r1 in rings), default=0.0)
        grow = (_WINDOW + 1) * _cell(width, last) * math.sqrt(2.0)
        return cls(outer, zone, rings, (x0 - grow, y0 - grow, x1 + grow, y1 + grow))

    def holds(self, x: NDArray, y: NDArray) -> NDArray[np.bool_]:
        """Return which points (plane metres) the closing may change."""
        inside = np.hypot(x, y) <= self.outer
        if self.zone is not None:
            inside &= shapely.contains_xy(self.zone, x, y)
        return inside


def _cell(width: float, r1: float) -> float:
    """Return the cell of a ring out to ``r1``: width / 8 at its largest k.

    The closing's disk, of diameter ``width`` on the Earth, is 4 cells across
    there, and fewer further in (down to 20 % fewer at the ring's inner edge).
    """
    return 0.5 * width * plane_scale(r1) / _DISK


@dataclass(frozen=True, slots=True)
class _Ring:
    """One ring of the plane and its raster: cell, disk, tiles."""

    r0: float
    r1: float
    width: float
    region: _Region

    @property
    def cell(self) -> float:
        """The ring's cell, metres in the plane (:func:`_cell`)."""
        return _cell(self.width, self.r1)

    @property
    def band(self) -> tuple[float, float]:
        """The radii whose cells this ring changes: itself and an overlap.

        The overlap holds all that the ring grows from the thin land in it
        (:data:`_THICK`): a neighbouring ring, at its own scale, may not see
        that land as thin, and would leave a wedge of water beside a thickened
        neck cut off at the edge.
        """
        m = (_OVERLAP + _THICK) * self.cell
        return max(self.r0 - m, 0.0), min(self.r1 + m, self.region.outer)


@dataclass(frozen=True, slots=True)
class _Edges:
    """The edges of every ring of the land.

    ``a`` and ``b`` are their ends (n, 2); ``owner`` the polygon each is of;
    ``sense`` +1 where the ring runs as an exterior anticlockwise (or a hole
    clockwise) would, else -1; ``near`` and ``far`` bound the distance of
    each from the plane's centre, from below and above.
    """

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    owner: NDArray[np.intp]
    sense: NDArray[np.int8]
    near: NDArray[np.float64]
    far: NDArray[np.float64]

    @classmethod
    def of(
        cls,
        polygons: NDArray[np.object_],
        box: tuple[float, float, float, float] | None = None,
    ) -> _Edges:
        """Return the edges of ``polygons`` (only those that meet ``box``)."""
        rings, owner = shapely.get_rings(polygons, return_index=True)
        exterior = np.r_[True, owner[1:] != owner[:-1]]
        sense = np.where(shapely.is_ccw(rings) == exterior, 1, -1).astype(np.int8)
        xy, ring = shapely.get_coordinates(rings, return_index=True)
        same = ring[1:] == ring[:-1]
        if box is not None:
            lo, hi = np.minimum(xy[:-1], xy[1:]), np.maximum(xy[:-1], xy[1:])
            same &= (hi >= box[:2]).all(axis=1) & (lo <= box[2:]).all(axis=1)
        r = np.hypot(xy[:, 0], xy[:, 1])
        ra, rb = r[:-1][same], r[1:][same]
        a, b, ring = xy[:-1][same], xy[1:][same], ring[:-1][same]
        # no nearer than its nearer end less its length: enough to pick edges
        near = np.maximum(np.minimum(ra, rb) - np.hypot(*(b - a).T), 0.0)
        return cls(a, b, owner[ring], sense[ring], near, np.maximum(ra, rb))


def _big(
    polygons: NDArray[np.object_],
    keep_area: float,
    land: tuple[NDArray[np.intp], NDArray[np.intp]],
    crs: CRS | None = None,
) -> NDArray[np.bool_]:
    """Return which polygons are land of ``keep_area`` or more on the Earth.

    Polygons that intersect (``land``: the pairs that do) count as one piece
    of land, of their areas' sum.
    """
    if keep_area <= 0:
        return np.zeros(len(polygons), dtype=bool)
    label = group_labels(len(polygons), land)
    areas = earth_areas(polygons, crs)
    return np.bincount(label, weights=areas)[label] >= keep_area


def earth_areas(
    polygons: NDArray[np.object_], crs: CRS | None = None
) -> NDArray[np.float64]:
    """Return the areas on the Earth of (multi)polygons in a stereographic plane.

    In square metres; other geometries have none. On the sphere of radius
    :data:`~coastmesh.geometry.earth.EARTH_RADIUS` without ``crs``; with the
    plane's ``crs``, on the WGS84 ellipsoid, as a regional case and
    :func:`~coastmesh.geometry.domain.polygon_areas` in longitude and
    latitude measure them: each polygon's sphere area times
    :func:`~coastmesh.geometry.earth.ellipsoid_area_scale` at its centroid's
    latitude (exact to first order in the polygon's span in latitude; an
    island's area off by the sphere's 0.7 % at 70 N had it taken for one under
    ``min_area``).

    The plane's area element is ``k^2`` times the Earth's, ``k = 1 + r^2 /
    4R^2``; by Green's theorem the Earth's area of a region is the integral of
    ``(x dy - y dx) / (2 k)`` round its boundary, taken along each straight
    edge at its middle: the rule's error is of the order of the square of
    ``k``'s change along an edge, 1e-5 or less for edges of a quarter of a
    degree on the Earth (the world layers' longest, :func:`world_land`).

    Examples
    --------
    A disc of radius 2R about the centre is a hemisphere:

    >>> disc = shapely.Point(0, 0).buffer(2 * EARTH_RADIUS, quad_segs=256)
    >>> round(float(earth_areas([disc])[0]) / (2 * math.pi * EARTH_RADIUS**2), 4)
    1.0
    """
    geoms = np.asarray(polygons, dtype=object).ravel()
    one = shapely.get_type_id(geoms) == shapely.GeometryType.POLYGON
    parts, of = shapely.get_parts(geoms[~one], return_index=True)  # multis'
    polygons = np.concatenate([geoms[one], parts])
    of = np.concatenate([np.flatnonzero(one), np.flatnonzero(~one)[of]])
    rings, owner = shapely.get_rings(polygons, return_index=True)
    if len(rings) == 0:
        return np.zeros(len(geoms))
    xy, ring = shapely.get_coordinates(rings, return_index=True)
    a, b = xy[:-1], xy[1:]  # and, between rings, pairs weighed by 0 below
    mid = 0.5 * (a + b)
    half_over_k = 0.5 / plane_scale(np.hypot(mid[:, 0], mid[:, 1]))
    term = (a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]) * half_over_k
    term[ring[1:] != ring[:-1]] = 0.0
    per_ring = np.abs(np.bincount(ring[:-1], term, len(rings)))
    exterior = np.r_[True, owner[1:] != owner[:-1]]
    area = np.bincount(owner, np.where(exterior, per_ring, -per_ring), len(polygons))
    if crs is not None:
        centre = shapely.get_coordinates(shapely.centroid(polygons))
        scale = ellipsoid_area_scale(reproject_points(centre, crs, "EPSG:4326")[:, 1])
        area *= np.where(np.isfinite(scale), scale, 1.0)  # empty: no centroid
    return np.bincount(of, area, len(geoms)).astype(np.float64, copy=False)


def _close_ring(
    ring: _Ring,
    edges: _Edges,
    big: NDArray[np.bool_],
    polygons: NDArray[np.object_],
    tree: shapely.STRtree,
) -> tuple[list, list]:
    """Close one ring: return the patches of land it adds, and those it cuts."""
    tiles, pairs = _tiles(ring, edges)
    adds, cuts = [], []
    bounds = np.searchsorted(pairs[:, 1], np.arange(0, len(tiles) + _BATCH, _BATCH))
    for start, (i, j) in zip(
        range(0, len(tiles), _BATCH), itertools.pairwise(bounds), strict=False
    ):
        batch = tiles[start : start + _BATCH]
        edge, tile = pairs[i:j, 0], pairs[i:j, 1] - start
        origin = (batch * _TILE - _HALO).astype(np.float64) * ring.cell
        added, cut = _close_tiles(ring, edges, edge, tile, origin, big, polygons, tree)
        adds += added
        cuts += cut
    return adds, cuts


def _tiles(ring: _Ring, edges: _Edges) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return the ring's tiles with coast, and (edge, tile) for each edge in each.

    A tile's window is its core and a halo round it; an edge is in every tile
    whose window its bounding box meets. Tiles are (column, row) of the grid
    of cores, 256 cells a side, from the plane's centre.
    """
    cell, (lo, hi) = ring.cell, ring.band
    span, halo = _TILE * cell, _HALO * cell
    reach = (_TILE + 2 * _HALO) * cell * math.sqrt(2.0)
    chosen = np.flatnonzero((edges.near <= hi + reach) & (edges.far >= lo - reach))
    a, b = edges.a[chosen], edges.b[chosen]
    first = np.floor((np.minimum(a, b) - halo) / span).astype(np.int64)
    last = np.floor((np.maximum(a, b) + halo) / span).astype(np.int64)
    nx, ny = (last - first + 1).T
    count = nx * ny
    e = np.repeat(np.arange(len(a)), count)
    k = np.arange(len(e)) - np.repeat(np.cumsum(count) - count, count)
    col, row = first[e, 0] + k % nx[e], first[e, 1] + k // nx[e]
    # each tile as one number, in the ring's few columns and rows: a counting
    # sort groups the pairs by tile
    corner = (col.min(), row.min()) if len(e) else (0, 0)
    columns = int(col.max() - corner[0] + 1) if len(e) else 1
    key = (row - corner[1]) * columns + (col - corner[0])
    order = np.argsort(
        key.astype(np.uint16 if key.max(initial=0) < 2**16 else np.int64), kind="stable"
    )
    present = np.flatnonzero(np.bincount(key, minlength=1))
    tiles = np.column_stack(
        [present % columns + corner[0], present // columns + corner[1]]
    )
    # only tiles whose core meets the ring's band (and the zone)
    x0, y0 = tiles[:, 0] * span, tiles[:, 1] * span
    x1, y1 = x0 + span, y0 + span
    wanted = (_gap(x0, y0, x1, y1) <= hi) & (_top(x0, y0, x1, y1) >= lo)
    if ring.region.zone is not None:
        wanted &= shapely.intersects(ring.region.zone, shapely.box(x0, y0, x1, y1))
    number = np.full(int(present[-1]) + 1 if len(present) else 1, -1)
    number[present[wanted]] = np.arange(int(wanted.sum()))
    tile = number[key[order]]
    keep = tile >= 0
    return tiles[wanted], np.column_stack([chosen[e[order[keep]]], tile[keep]])


def _gap(x0: NDArray, y0: NDArray, x1: NDArray, y1: NDArray) -> NDArray:
    """Return the least distance from the plane's centre to each box."""
    dx = np.maximum(np.maximum(x0, -x1), 0.0)
    return np.hypot(dx, np.maximum(np.maximum(y0, -y1), 0.0))


def _top(x0: NDArray, y0: NDArray, x1: NDArray, y1: NDArray) -> NDArray:
    """Return the greatest distance from the plane's centre to each box."""
    return np.hypot(np.maximum(abs(x0), abs(x1)), np.maximum(abs(y0), abs(y1)))


def _close_tiles(
    ring: _Ring,
    edges: _Edges,
    edge: NDArray[np.intp],
    tile: NDArray[np.intp],
    origin: NDArray[np.float64],
    big: NDArray[np.bool_],
    polygons: NDArray[np.object_],
    tree: shapely.STRtree,
) -> tuple[list, list]:
    """Close a batch of tiles: return the patches added and cut, as polygons."""
    cell, a, b = ring.cell, edges.a[edge], edges.b[edge]
    y_anchor = origin[:, 1] + 0.5 * cell  # the first row's centres
    point, holder = _holders(origin[:, 0], y_anchor, polygons, tree)
    anchor = np.bincount(point, minlength=len(origin))
    sense = edges.sense[edge]
    land = cells.winding(a, b, sense, tile, origin, anchor, cell, _WINDOW)
    coast = cells.crossed(a, b, tile, origin, cell, _WINDOW)
    closed = _closing(land | coast)
    # the big land's cells: all the land, but in tiles with small land too
    mine = big[edges.owner[edge]]
    small = np.unique(tile[~mine])
    big_land = land.copy()
    if len(small):
        renumber = np.full(len(origin), -1)
        renumber[small] = np.arange(len(small))
        sub = mine & (renumber[tile] >= 0)
        held = renumber[point[big[holder]]]
        count = np.bincount(held[held >= 0], minlength=len(small))
        big_land[small] = cells.winding(
            a[sub],
            b[sub],
            sense[sub],
            renumber[tile[sub]],
            origin[small],
            count,
            cell,
            _WINDOW,
        )
    opened = cells.dilate(cells.erode(closed, _DISK), _DISK)
    with_big = cells.joined(closed, big_land & land)
    grown = _thickened(closed, opened, with_big & _own(ring, origin))
    # and the necks between points of land that face each other over less
    # than 0.7 of the width (ice-front tongues, headlands), which the disk's
    # closing leaves open (one held world_fine's shortest time step to 0.45
    # of its p1), bridged before the closing again, which fills the narrow
    # water a bridge leaves beside it: in the cells traced, a cell round
    # them, and what those need
    near = slice(
        _HALO - _OVERLAP - 1 - 2 * _DISK - 2 * _BRIDGE,
        _HALO + _TILE + _OVERLAP + 1 + 2 * _DISK + 2 * _BRIDGE,
    )
    thick = grown.copy()
    thick[:, near, near] = _closing(cells.bridge(grown[:, near, near], _BRIDGE))
    region = _changeable(ring, origin)
    first = _HALO - _OVERLAP  # the first cell traced
    patch = _patch(thick, land, coast)
    adds = list(cells.trace(patch[_CORE] & region, origin, cell, first))
    if len(small) == 0:
        return adds, []
    # the opening of the land under keep_area, in the tiles that have some
    cut = _cut(closed[small], opened[small], with_big[small])
    return adds, list(
        cells.trace(cut[_CORE] & region[small], origin[small], cell, first)
    )


#: The cells of a tile's window whose patches are kept: its core and an overlap
_CORE = (
    slice(None),
    slice(_HALO - _OVERLAP, _HALO + _TILE + _OVERLAP),
    slice(_HALO - _OVERLAP, _HALO + _TILE + _OVERLAP),
)


def _holders(
    x: NDArray, y: NDArray, polygons: NDArray[np.object_], tree: shapely.STRtree
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Return (point, polygon) for each polygon that holds each point."""
    point, polygon = tree.query(shapely.points(x, y))
    with _PREPARED:  # GEOS builds a prepared polygon's index on its first use
        inside = shapely.contains_xy(polygons[polygon], x[point], y[point])
    return point[inside], polygon[inside]


def _closing(touched: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Return the closing of the cells the land touches (its coast, or its centre).

    So land thinner than a cell, a barrier island, still bounds the water
    behind it. Such a cell's land reaches half way across it on average, so
    the disk is half a cell narrower than the width's (:data:`_CLOSE`).
    """
    return cells.erode(cells.dilate(touched, _CLOSE), _CLOSE)


def _thickened(
    closed: NDArray[np.bool_], opened: NDArray[np.bool_], with_big: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Return the closed land with big land's thin parts grown to the width.

    Big land narrower than the width (a spit, a peninsula, a long neck: what
    the opening takes away, farther than half the width from the land it
    keeps; not the corners it rounds, of over 60 degrees) is grown by half
    the width on each side, so a mesh at the width's size resolves it, and
    it stays land; the caller closes the land again round it. Land of
    ``keep_area`` or more is never opened away.
    """
    thin = closed & ~opened & with_big & ~cells.dilate(opened, _DISK)
    if not thin.any():
        return closed
    # the cells the coast crosses already widen it by about a cell: grown by
    # a cell less than the disk, it is the width wide
    return closed | cells.dilate(thin, _DISK - 1)


def _patch(
    closed: NDArray[np.bool_], land: NDArray[np.bool_], coast: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Return the cells to add to the exact land, from the closed land.

    The closed cells of no land (``land``: cells whose centre is land;
    ``coast``: cells the coast crosses); the cells the coast crosses inside
    the closed land (water narrower than a cell); and the land cells beside
    those, so the patch covers the water part of every cell the coast crosses
    there.
    """
    touched = land | coast
    patch = (closed & ~touched) | (cells.erode(closed, 1) & coast)
    patch |= cells.dilate(patch, 1) & touched
    return patch


def _cut(
    closed: NDArray[np.bool_], opened: NDArray[np.bool_], with_big: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Return the cells to cut from the exact land: the opening of small land.

    The cells the opening takes from closed land not joined to big land
    (``with_big``: the closed land that is), and the water cells beside them,
    so no sliver of exact land is left there.
    """
    removed = closed & ~opened & ~with_big
    return removed | (cells.dilate(removed, 1) & ~closed)


def _own(ring: _Ring, origin: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Return which cells of the tiles' windows lie in the ring itself.

    Only the ring judges whether big land there is thin: each thin neck is
    thickened by one ring, at one scale, however near a ring's edge.
    """
    offset = (np.arange(_WINDOW, dtype=np.float64) + 0.5) * ring.cell
    return _in_band(origin, offset, ring.r0, ring.r1)


def _changeable(ring: _Ring, origin: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Return which cells of the tiles' cores (and overlap) the ring may change."""
    span = np.arange(_HALO - _OVERLAP, _HALO + _TILE + _OVERLAP, dtype=np.float64)
    offset = (span + 0.5) * ring.cell
    return _in_band(origin, offset, *ring.band, ring.region.zone)


def _in_band(
    origin: NDArray[np.float64],
    offset: NDArray[np.float64],
    lo: float,
    hi: float,
    zone: shapely.Geometry | None = None,
) -> NDArray[np.bool_]:
    """Return which cells (centres ``origin + offset``) lie at radii in [lo, hi).

    And in ``zone``, if given. Tiles wholly in the band (and the zone) are
    wholly in; the rest are measured cell by cell.
    """
    x0, y0 = (origin + offset[0]).T
    x1, y1 = (origin + offset[-1]).T
    whole = (_gap(x0, y0, x1, y1) >= lo) & (_top(x0, y0, x1, y1) < hi)
    if zone is not None:
        whole &= shapely.contains(zone, shapely.box(x0, y0, x1, y1))
    inside = np.ones((len(origin), len(offset), len(offset)), dtype=bool)
    for t in np.flatnonzero(~whole):
        x, y = np.meshgrid(origin[t, 0] + offset, origin[t, 1] + offset)
        r = np.hypot(x, y)
        inside[t] = (r >= lo) & (r < hi)
        if zone is not None and inside[t].any():
            inside[t] &= shapely.contains_xy(zone, x, y)
    return inside


def _apply(
    polygons: NDArray[np.object_],
    adds: NDArray[np.object_],
    big: NDArray[np.bool_],
    land: tuple[NDArray[np.intp], NDArray[np.intp]],
    width: float,
    region: _Region,
    threads: int = 1,
) -> tuple[NDArray[np.object_], NDArray[np.bool_]]:
    """Union the land with the patches added, one connected group at a time.

    ``land`` are the pairs of land polygons that intersect.

    Returns the land's polygons and which of them hold big land. A group of
    one polygon is returned as it is: the closing did not touch it. The
    unions run on ``threads`` threads (GEOS lets go of Python's lock), the
    largest groups first.
    """
    n = len(polygons)
    geoms = np.concatenate([polygons, adds])
    i, j = meeting_pairs(polygons, adds)
    groups = groups_of(len(geoms), (np.r_[land[0], i], np.r_[land[1], j]))
    changed = [g for g in groups if len(g) > 1 or g[0] >= n]
    changed.sort(key=lambda g: -int(shapely.get_num_coordinates(geoms[g]).sum()))
    with ThreadPoolExecutor(max(1, int(threads))) as pool:
        unions = list(pool.map(lambda g: _union(geoms[g], width, region), changed))
    same = np.array([g[0] for g in groups if len(g) == 1 and g[0] < n], dtype=int)
    parts = np.concatenate([polygons[same], *unions])
    kept = np.concatenate(
        [big[same]]
        + [
            np.full(len(u), big[g[g < n]].any())
            for g, u in zip(changed, unions, strict=True)
        ]
    )
    return parts, kept


def _union(
    geoms: NDArray[np.object_], width: float, region: _Region
) -> NDArray[np.object_]:
    """Return the union of ``geoms`` as polygons, without holes the closing fills.

    The largest is unioned once with the union of the rest: GEOS's cascaded
    union would go over a continent once per level of its tree. A hole in
    ``region`` that cannot hold the closing's disk (under its area, at its
    scale) is water the closing fills: slivers left between a patch and a
    coast, say.
    """
    size = shapely.get_num_coordinates(geoms)
    largest = int(np.argmax(size))
    rest = _overlay(shapely.union_all, np.delete(geoms, largest))
    parts = shapely.get_parts(_overlay(shapely.union, geoms[largest], rest))
    parts = parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]
    for i in np.flatnonzero(shapely.get_num_interior_rings(parts) > 0):
        holes = np.array([shapely.Polygon(h) for h in parts[i].interiors])
        point = shapely.get_coordinates(shapely.point_on_surface(holes))
        small = shapely.area(holes) < _disk_area(holes, width)
        small &= region.holds(point[:, 0], point[:, 1])
        if small.any():
            kept = [h.exterior for h in holes[~small]]
            parts[i] = shapely.Polygon(parts[i].exterior, kept)
    return parts


def _overlay(operation, *geoms):
    """Return a shapely overlay ``operation`` of ``geoms``, snapped if it must be.

    GEOS's floating overlay can fail on edges that nearly coincide, as a
    patch's and a coast's do ("side location conflict"); its snap-rounding
    overlay to a millimetre cannot.
    """
    try:
        return operation(*geoms)
    except shapely.errors.GEOSException:
        return operation(*geoms, grid_size=1e-3)


def _disk_area(geoms: NDArray[np.object_], width: float) -> NDArray[np.float64]:
    """Return the area in the plane of a disk of diameter ``width`` at each geometry.

    The disk is the one the closing used there: at the largest k of the ring
    that holds the geometry's point (:func:`_rings`).
    """
    point = shapely.get_coordinates(shapely.point_on_surface(geoms))
    r = np.hypot(point[:, 0], point[:, 1])
    edges = np.array([r1 for _, r1 in _rings(float(r.max(initial=0.0)))] or [0.0])
    r1 = edges[np.minimum(np.searchsorted(edges, r), len(edges) - 1)]
    k = plane_scale(r1)
    return math.pi * (0.5 * width * k) ** 2


def _open(
    parts: NDArray[np.object_],
    kept: NDArray[np.bool_],
    cuts: NDArray[np.object_],
    width: float,
    region: _Region,
) -> NDArray[np.object_]:
    """Take the cut patches from land that holds no big land; drop what is left tiny.

    Land the opening keeps holds a disk of diameter ``width`` on the Earth; a
    piece of small land under half that disk's area (at its scale) holds none,
    and goes: islands too small for any cell centre, and slivers.
    """
    small = parts[~kept]
    if len(small) == 0:
        return parts
    if len(cuts):
        which, cut = shapely.STRtree(cuts).query(small, predicate="intersects")
        knives = np.array(
            [shapely.union_all(cuts[cut[which == k]]) for k in np.unique(which)]
        )
        opened = shapely.get_parts(
            _overlay(shapely.difference, small[np.unique(which)], knives)
        )
        small = np.concatenate([np.delete(small, np.unique(which)), opened])
        small = small[
            (shapely.get_type_id(small) == shapely.GeometryType.POLYGON)
            & ~shapely.is_empty(small)
        ]
    point = shapely.get_coordinates(shapely.point_on_surface(small))
    disk = _disk_area(small, width)
    tiny = shapely.area(small) < 0.5 * disk
    # and slivers with room for the disk nowhere, as the opening would find:
    # their widest inscribed circle (GEOS's, to 1 %) is under its radius
    half = np.sqrt(disk[~tiny] / math.pi)
    with np.errstate(divide="ignore"):  # GEOS warns on a sliver of no width
        circle = shapely.maximum_inscribed_circle(small[~tiny], 0.01 * half)
    tiny[~tiny] = shapely.length(circle) < half
    return np.concatenate([parts[kept], small[~tiny | ~region.holds(*point.T)]])


@dataclass(frozen=True, slots=True)
class IslandChange:
    """An island whose area the closing changed by more than a share of it.

    Attributes
    ----------
    point : tuple of float
        A point inside the island (plane metres).
    before : float
        Its area on the Earth before the closing (m2).
    after : float
        The area on the Earth of the land that holds that point after the
        closing, with whatever it was joined to; if no land holds it, the area
        left of the island; 0 if it is gone. NaN if it was joined to the frame
        round the ocean (``framed``), whose area in the plane means nothing.
    joined : int
        Other polygons of the input now in the same polygon.
    """

    point: tuple[float, float]
    before: float
    after: float
    joined: int


def island_changes(
    before: NDArray[np.object_],
    after: NDArray[np.object_],
    *,
    min_area: float,
    share: float = 0.1,
    framed: bool = False,
    crs: CRS | None = None,
) -> tuple[int, list[IslandChange]]:
    """Return the islands of ``min_area`` or more whose area changed by ``share``.

    Parameters
    ----------
    before, after : ndarray of shapely Polygons
        Land in a stereographic plane, before and after
        :func:`close_narrow_water`.
    min_area : float
        Square metres on the Earth: smaller islands are not looked at.
    share : float, default 0.1
        Listed if the area changed by more than this share of it.
    framed : bool, default False
        ``after[0]`` is the frame round the ocean (a global case's polar land):
        an island joined to it is listed, with its ``after`` NaN.
    crs : pyproj.CRS, optional
        The plane's CRS: areas on the WGS84 ellipsoid (:func:`earth_areas`).

    Returns
    -------
    islands : int
        The islands of ``min_area`` or more.
    changed : list of IslandChange
        Those that changed, the largest change (for its area) first; those
        joined to the frame first of all.

    Examples
    --------
    >>> squares = [shapely.box(0, 0, 50e3, 50e3), shapely.box(52e3, 0, 99e3, 50e3)]
    >>> closed, _ = close_narrow_water(squares, 5e3, keep_area=1e9)
    >>> islands, changed = island_changes(squares, closed, min_area=1e9)
    >>> islands, [(round(c.before / 1e6), round(c.after / 1e6), c.joined)
    ...           for c in changed]
    (2, [(2350, 4950, 1), (2500, 4950, 1)])
    """
    before = np.asarray(before, dtype=object)
    after = np.asarray(after, dtype=object)
    area = earth_areas(before, crs)
    point = shapely.get_coordinates(shapely.point_on_surface(before))
    holder = np.full(len(before), -1)
    shapely.prepare(after)
    tree = shapely.STRtree(after)
    p, q = tree.query(shapely.points(point))
    inside = shapely.contains_xy(after[q], point[p, 0], point[p, 1])
    holder[p[inside]] = q[inside]
    held = np.bincount(holder[holder >= 0], minlength=len(after))
    looked = area >= min_area
    held_looked = looked & (holder >= 0)
    holders = np.unique(holder[held_looked])  # only their areas are needed
    lookup = np.zeros(len(after))
    lookup[holders] = earth_areas(after[holders], crs)
    now = np.where(held_looked, lookup[np.maximum(holder, 0)], np.nan)
    for i in np.flatnonzero(looked & (holder < 0)):  # opened, or gone
        left = shapely.intersection(before[i], after[tree.query(before[i])])
        now[i] = earth_areas(left, crs).sum()
    polar = framed & (holder == 0)
    now[polar] = np.nan
    change = np.where(polar, np.inf, np.abs(now - area))
    listed = np.flatnonzero(looked & (change > share * area))
    listed = listed[np.argsort(-change[listed] / area[listed], kind="stable")]
    return int(looked.sum()), [
        IslandChange(
            (float(point[i, 0]), float(point[i, 1])),
            float(area[i]),
            float(now[i]),
            int(held[holder[i]] - 1) if holder[i] >= 0 else 0,
        )
        for i in listed
    ]
