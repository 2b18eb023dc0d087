"""Model domains: the sea bounded by shorelines and open boundaries.

The land polygons and the open-boundary lines are noded together (GEOS), and the
faces of the resulting planar graph are built with ``shapely.polygonize``. The
domain is the sea face that holds the seed point (or the largest sea face); open
boundaries are thereby trimmed at their first crossings with the shorelines,
dangling ends drop out, and islands inside become holes. Every edge of the result
is tagged as shoreline or as the open boundary it lies on.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS, Geod

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.earth import metres_per_unit, reproject
from coastmesh.geometry.layers import valid_polygons
from coastmesh.geometry.no_sea import no_sea_error, open_water_exits
from coastmesh.geometry.sphere import is_world_plane
from coastmesh.geometry.unions import union_meeting
from coastmesh.types import BoundarySegment, Domain, Report

__all__ = [
    "DomainReport",
    "OpenBoundary",
    "build_domain",
    "domain_with_land",
    "domain_with_structures",
    "polygon_areas",
    "smaller_than",
]

_GEOD = Geod(ellps="WGS84")


@dataclass(frozen=True, slots=True)
class OpenBoundary:
    """An open-boundary line, before trimming.

    Parameters
    ----------
    coords : ndarray of shape (k, 2)
        The line, in the domain CRS, ``k >= 2``.
    name : str
        Its name (for reports and outputs).
    physical_id : int
        The boundary id given to its mesh edges, ``> 0``.
    """

    coords: NDArray[np.float64]
    name: str
    physical_id: int

    def __post_init__(self) -> None:
        xy = np.asarray(self.coords, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) < 2:
            raise ConfigError(
                f"open boundary {self.name!r}: coords must have shape (k >= 2, 2); "
                f"got {xy.shape}"
            )
        if not np.isfinite(xy).all():
            raise ConfigError(f"open boundary {self.name!r}: non-finite coordinates")
        if self.physical_id <= 0:
            raise ConfigError(
                f"open boundary {self.name!r}: physical_id = {self.physical_id} "
                "must be > 0"
            )
        object.__setattr__(self, "coords", xy)


@dataclass(frozen=True, slots=True)
class DomainReport(Report):
    """What :func:`build_domain` found and changed.

    Attributes
    ----------
    land_in : int
        Non-empty land geometries given.
    land_repaired : int
        Of those, the invalid ones made valid (GEOS ``make_valid``).
    land_overlaps_merged : int
        Land polygons that merged into others where they overlapped or touched:
        the polygons given less the polygons of their union.
    sea_faces : int
        Faces of the noded shorelines and open boundaries that are not land.
    holes : int
        Islands (holes) of the domain.
    holes_dropped : int
        Islands smaller than the minimum area, dropped.
    segments : dict of str to int
        Boundary edges (vertex to vertex) by boundary name.
    """

    land_in: int
    land_repaired: int
    land_overlaps_merged: int
    sea_faces: int
    holes: int
    holes_dropped: int
    segments: dict[str, int] = field(default_factory=dict)

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.land_in} land polygons ({self.land_repaired} repaired, "
            f"{self.land_overlaps_merged} overlaps merged); {self.sea_faces} sea "
            f"faces; domain with {self.holes} islands ({self.holes_dropped} "
            f"below the minimum area dropped)"
        )


def build_domain(
    land: ArrayLike,
    open_boundaries: list[OpenBoundary],
    *,
    crs: CRS | str,
    seed: tuple[float, float] | None = None,
    min_area: float = 0.0,
    shoreline_id: int = 1,
    surface_id: int = 1,
    shorelines: Sequence[tuple[str, int, shapely.Geometry | None]] | None = None,
) -> tuple[Domain, DomainReport]:
    """Build the sea polygon closed by shorelines and open boundaries.

    Parameters
    ----------
    land : array_like of shapely polygons
        Land (GSHHG-style polygons, full resolution or PCA reconstructions), in
        ``crs``. Invalid and overlapping polygons are repaired and merged.
    open_boundaries : list of OpenBoundary
        Lines that close the sea; they may overshoot the coast.
    crs : pyproj.CRS or str
        CRS of everything (geographic or projected).
    seed : (float, float), optional
        A point in the sea inside the wanted domain; default: the largest sea face.
    min_area : float
        Islands (holes) smaller than this are dropped, square metres (geodesic
        area for a geographic CRS).
    shoreline_id : int
        Boundary id of the shoreline edges (when ``shorelines`` is not given).
    surface_id : int
        Physical id of the domain's surface (its triangles).
    shorelines : sequence of (name, physical_id, region), optional
        Shoreline sets by region, as :func:`~coastmesh.geometry.stitch_shorelines`
        returns them: a shoreline edge takes the name and id of the first set whose
        region holds its midpoint, or of the set whose region is None. Default: one
        set ``("shoreline", shoreline_id, None)``.

    Returns
    -------
    domain : coastmesh.meshing.Domain
        The valid sea polygon and its boundary as tagged segments: runs covering
        every ring in order, consecutive runs sharing their end points.
    report : DomainReport

    Raises
    ------
    ConfigError
        If the seed is on land or in no closed face, or ids are invalid.
    InputDataError
        If the shorelines and open boundaries enclose no sea at all.

    Examples
    --------
    >>> import shapely
    >>> land = [shapely.box(0, 0, 10, 2), shapely.box(4, 5, 5, 6)]
    >>> walls = [OpenBoundary([(1, 1), (1, 9), (9, 9), (9, 1)], "open", 2)]
    >>> domain, report = build_domain(land, walls, crs="EPSG:3857")
    >>> poly, segs = domain.polygon, domain.segments
    >>> poly.area, len(poly.interiors), sorted({s.kind for s in segs})
    (55.0, 1, ['open', 'shoreline'])
    """
    crs = CRS.from_user_input(crs)
    if shorelines is None:
        shorelines = [("shoreline", shoreline_id, None)]
    shorelines = list(shorelines)
    _check_ids(shorelines, open_boundaries)
    geoms = np.asarray(land, dtype=object).ravel()
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    polygons = valid_polygons(geoms)
    merged = shapely.multipolygons(union_meeting(polygons))
    overlaps = len(polygons) - len(shapely.get_parts(merged))

    lines = [shapely.LineString(b.coords) for b in open_boundaries]
    linework = shapely.node(shapely.union_all([shapely.boundary(merged), *lines]))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(linework)))
    sea = faces[~shapely.within(shapely.point_on_surface(faces), merged)]
    sea = sea[shapely.area(sea) > _degenerate_area(linework)]
    if len(sea) == 0:
        raise no_sea_error(merged, open_boundaries, crs)
    if seed is not None:
        point = shapely.Point(seed)
        if shapely.contains(merged, point):
            raise ConfigError(f"seed = {seed}: lies on land")
        holding = [f for f in sea if shapely.covers(shapely.Polygon(f.exterior), point)]
        if not holding:
            exits = open_water_exits(seed, merged, open_boundaries, crs)
            raise ConfigError(
                f"seed = {seed}: in no sea region closed by the shorelines and open "
                "boundaries" + (f": {exits}" if exits else "")
            )
        domain = min(holding, key=lambda f: f.area)  # the innermost face
    else:
        domain = sea[np.argmax(shapely.area(sea))]
    domain, dropped = _drop_small_holes(domain, min_area, crs)
    segments = _tag_boundary(domain, open_boundaries, shorelines)
    counts = _edge_counts(segments)
    report = DomainReport(
        land_in=len(geoms),
        land_repaired=int((~shapely.is_valid(geoms)).sum()),
        land_overlaps_merged=int(overlaps),
        sea_faces=len(sea),
        holes=len(domain.interiors),
        holes_dropped=dropped,
        segments=counts,
    )
    return Domain(domain, tuple(segments), crs, surface_id), report


def _degenerate_area(linework: shapely.Geometry) -> float:
    """Return the area of a face that is only rounding: a point or a sliver.

    A land polygon of no area (a DEM sample a hair above the level at the
    raster's edge gives one, 1e-29 square degrees) polygonizes to a face that
    is not within the land; it is no sea.
    """
    minx, miny, maxx, maxy = shapely.bounds(linework)
    return 1e-18 * max(maxx - minx, maxy - miny) ** 2


def domain_with_land(
    domain: Domain,
    closed: ArrayLike,
    open_boundaries: list[OpenBoundary],
    report: DomainReport,
    *,
    seed: tuple[float, float] | None = None,
    min_area: float = 0.0,
    shorelines: Sequence[tuple[str, int, shapely.Geometry | None]] | None = None,
    land: ArrayLike | None = None,
    keep: ArrayLike = (),
) -> tuple[Domain, DomainReport]:
    """Return ``domain`` with the polygons ``closed`` made land.

    What :func:`build_domain` would give with ``closed`` added to its
    ``land``, without building the whole coast again: the sea polygon less
    ``closed`` and the islands of ``land`` smaller than ``min_area`` that
    ``closed`` touches (:func:`build_domain` dropped them; joined to the closed
    water they are land again); of its pieces, the one that holds ``seed``
    (else the largest: water cut off by the closing goes); islands smaller
    than ``min_area`` dropped, except those that overlap a polygon of
    ``keep`` (structures: land the user placed); the boundary tagged again
    (the new coast takes the shoreline set of the region it lies in).
    ``report`` is :func:`build_domain`'s; its holes and segments are updated.

    Raises
    ------
    ConfigError
        If ``closed`` covers the seed.
    InputDataError
        If no sea is left.

    Examples
    --------
    >>> import shapely
    >>> land = [shapely.box(0, 0, 10, 2), shapely.box(4, 5, 5, 6)]
    >>> walls = [OpenBoundary([(1, 1), (1, 9), (9, 9), (9, 1)], "open", 2)]
    >>> domain, report = build_domain(land, walls, crs="EPSG:3857")
    >>> closed = [shapely.box(4.5, 1, 5.5, 5.5)]  # joins the island to the coast
    >>> again, _ = build_domain([*land, *closed], walls, crs="EPSG:3857")
    >>> fast, fast_report = domain_with_land(domain, closed, walls, report)
    >>> fast.polygon.equals(again.polygon), fast_report.holes
    (True, 0)
    """
    crs = domain.crs
    if shorelines is None:
        shorelines = [("shoreline", 1, None)]
    closed = valid_polygons(np.asarray(closed, dtype=object).ravel())
    cut = shapely.union_all(closed)
    if land is not None and min_area > 0 and len(closed):
        land = np.asarray(land, dtype=object).ravel()
        near = land[np.unique(shapely.STRtree(land).query(closed, "intersects")[1])]
        near = near[_rough_area(near, crs) < 2 * min_area]  # no mainland
        if len(near):
            small = near[smaller_than(near, crs, min_area)]
            cut = shapely.union_all([cut, *valid_polygons(small)])
    pieces = shapely.get_parts(shapely.difference(domain.polygon, cut))
    pieces = pieces[shapely.get_type_id(pieces) == 3]
    if len(pieces) == 0:
        raise InputDataError("closing the narrow water leaves no sea")
    if seed is None:
        polygon = pieces[np.argmax(shapely.area(pieces))]
    else:
        held = [q for q in pieces if shapely.covers(q, shapely.Point(seed))]
        if not held:
            raise ConfigError(
                f"seed = {seed}: lies in water closed as land (too narrow to "
                "mesh): move the seed to wider water, or mark that water as a "
                "[[sites]] region to keep it"
            )
        polygon = held[0]
    # the difference leaves twin vertices (1e-15 apart) where the coasts cross
    extent = max(np.ptp(np.asarray(polygon.exterior.coords), axis=0).max(), 1.0)
    polygon = shapely.remove_repeated_points(polygon, 1e-12 * extent)
    polygon, dropped = _drop_small_holes(polygon, min_area, crs, keep)
    segments = _tag_boundary(polygon, open_boundaries, list(shorelines))
    counts = _edge_counts(segments)
    new_report = DomainReport(
        land_in=report.land_in + len(closed),
        land_repaired=report.land_repaired,
        land_overlaps_merged=report.land_overlaps_merged,
        sea_faces=report.sea_faces,
        holes=len(polygon.interiors),
        holes_dropped=report.holes_dropped + dropped,
        segments=counts,
    )
    return Domain(polygon, tuple(segments), crs, domain.surface_id), new_report


def domain_with_structures(
    domain: Domain,
    structures: Sequence[tuple[str, int, shapely.Polygon]],
    open_boundaries: list[OpenBoundary],
    report: DomainReport,
    *,
    shorelines: Sequence[tuple[str, int, shapely.Geometry | None]],
    seed: tuple[float, float] | None = None,
) -> tuple[Domain, DomainReport]:
    """Return ``domain`` with ``structures`` (name, id, polygon) cut out of its sea.

    Each structure becomes a hole, or a notch in the coast it touches; the
    boundary edges on its outline take its name and id (a land boundary, kind
    ``"shoreline"``), the rest are tagged as before from ``shorelines``. No
    hole is dropped for its size.

    Raises
    ------
    ConfigError
        Naming the structure: one not valid, or not in the sea; two that
        touch; one that crosses an open boundary, covers the seed, or cuts the
        sea in two.

    Examples
    --------
    >>> import shapely
    >>> land = [shapely.box(0, 0, 10, 2)]
    >>> walls = [OpenBoundary([(1, 1), (1, 9), (9, 9), (9, 1)], "open", 2)]
    >>> domain, report = build_domain(land, walls, crs="EPSG:3857")
    >>> pier = ("pier", 7, shapely.box(4, 1.5, 4.5, 4))
    >>> cut, _ = domain_with_structures(
    ...     domain, [pier], walls, report, shorelines=[("shoreline", 1, None)]
    ... )
    >>> cut.polygon.area, sorted({s.name for s in cut.segments})
    (55.0, ['open', 'pier', 'shoreline'])
    """
    sea = domain.polygon
    shapes = _check_structures(sea, structures, domain.segments, seed)
    pieces = shapely.get_parts(shapely.difference(sea, shapely.union_all(shapes)))
    pieces = pieces[(shapely.get_type_id(pieces) == 3) & (shapely.area(pieces) > 0)]
    if len(pieces) != 1:
        names = [
            n
            for (n, _, _), p in zip(structures, shapes, strict=True)
            if len(_pieces(sea, p)) > 1
        ] or [n for n, _, _ in structures]
        raise ConfigError(
            f"structures {names}: cut the sea in {len(pieces)} pieces; a structure "
            "must leave the sea in one piece (give a gap, or move the open boundary)"
        )
    extent = max(np.ptp(np.asarray(pieces[0].exterior.coords), axis=0).max(), 1.0)
    polygon = shapely.remove_repeated_points(pieces[0], 1e-12 * extent)
    tagged = [*((n, i, p) for (n, i, _), p in zip(structures, shapes, strict=True))]
    segments = _tag_boundary(polygon, open_boundaries, [*tagged, *shorelines])
    new_report = DomainReport(
        land_in=report.land_in,
        land_repaired=report.land_repaired,
        land_overlaps_merged=report.land_overlaps_merged,
        sea_faces=report.sea_faces,
        holes=len(polygon.interiors),
        holes_dropped=report.holes_dropped,
        segments=_edge_counts(segments),
    )
    return Domain(polygon, tuple(segments), domain.crs, domain.surface_id), new_report


def _pieces(sea: shapely.Polygon, cut: shapely.Geometry) -> NDArray[np.object_]:
    parts = shapely.get_parts(shapely.difference(sea, cut))
    return parts[(shapely.get_type_id(parts) == 3) & (shapely.area(parts) > 0)]


def _check_structures(sea, structures, segments, seed) -> list[shapely.Polygon]:
    """Return the structures' polygons, checked against the sea and each other."""
    shapes: list[shapely.Polygon] = []
    opened = [
        (s.name, shapely.LineString(s.coords)) for s in segments if s.kind == "open"
    ]
    for name, _, polygon in structures:
        where = f"structure {name!r}"
        if not isinstance(polygon, shapely.Polygon) or not polygon.is_valid:
            reason = shapely.is_valid_reason(polygon)
            raise ConfigError(f"{where}: the polygon is not valid ({reason})")
        if shapely.intersection(polygon, sea).area <= 0:
            raise ConfigError(
                f"{where}: lies wholly on land or outside the domain; a structure "
                "must stand in the sea that is meshed"
            )
        for other, line in opened:
            if polygon.intersects(line):
                raise ConfigError(f"{where}: crosses the open boundary {other!r}")
        for other, shape in zip(structures, shapes, strict=False):
            if polygon.intersects(shape):
                raise ConfigError(f"{where}: touches structure {other[0]!r}")
        if seed is not None and polygon.covers(shapely.Point(seed)):
            raise ConfigError(f"{where}: covers the seed {tuple(seed)}")
        shapes.append(polygon)
    return shapes


def _edge_counts(segments) -> dict[str, int]:
    """Return the boundary edges (vertex to vertex) by boundary name."""
    counts: dict[str, int] = {}
    for seg in segments:
        counts[seg.name] = counts.get(seg.name, 0) + len(seg.coords) - 1
    return counts


def _rough_area(polygons: NDArray[np.object_], crs: CRS) -> NDArray[np.float64]:
    """Return the polygons' areas in square metres, to within a few per cent.

    Planar, scaled by the cosine of the latitude in a geographic CRS.
    """
    area = shapely.area(polygons)
    if not crs.is_geographic:
        return area * metres_per_unit(crs) ** 2
    lat = np.radians(shapely.get_y(shapely.centroid(polygons)))
    return area * (np.pi / 180 * 6_371_008.8) ** 2 * np.cos(lat)


def polygon_areas(polygons: ArrayLike, crs: CRS) -> NDArray[np.float64]:
    """Return the areas of polygons in square metres.

    Geodesic (WGS84) for a geographic CRS, planar in the CRS's unit otherwise.

    Examples
    --------
    >>> import shapely
    >>> polygon_areas([shapely.box(0, 0, 10, 20)], CRS("EPSG:32630")).tolist()
    [200.0]
    """
    geoms = np.asarray(polygons, dtype=object).ravel()
    if len(geoms) == 0:
        return np.zeros(0)
    if crs.is_geographic:
        if crs.to_epsg() != 4326:
            geoms = reproject(geoms, crs, "EPSG:4326")
        return np.array([abs(_geodesic_area(p)) for p in geoms])
    if is_world_plane(crs):  # a global case's plane: the areas on WGS84
        from coastmesh.geometry.closing import earth_areas  # (with scipy: late)

        return earth_areas(geoms, crs)
    return shapely.area(geoms) * metres_per_unit(crs) ** 2


def _geodesic_area(geometry: Any) -> float:
    """``Geod.geometry_area_perimeter(geometry)[0]``, the same sum, bit for bit.

    pyproj reads each ring through ``ring.xy`` (a Python array: 37 ms for a
    ring of 100,000 vertices here, against 0.2 ms for
    :func:`shapely.get_coordinates`).
    """
    if hasattr(geometry, "geoms"):
        total = 0.0
        for part in geometry.geoms:
            total += _geodesic_area(part)
        return total
    if geometry.is_empty:
        return 0.0
    total = 0.0
    for ring in (geometry.exterior, *geometry.interiors):
        xy = shapely.get_coordinates(ring)
        total += _GEOD.polygon_area_perimeter(xy[:, 0], xy[:, 1])[0]
    return total


#: Equal-area projection of the ellipsoid, to sort polygons by area at once
_EQUAL_AREA = CRS.from_proj4("+proj=cea +ellps=WGS84 +units=m")
#: How far from the limit an equal-area measure decides by itself (a factor)
_CLEAR = 1.25


def smaller_than(polygons: ArrayLike, crs: CRS, limit: float) -> NDArray[np.bool_]:
    """Return which polygons have a smaller area than ``limit`` square metres.

    The same as ``polygon_areas(polygons, crs) < limit``. In a geographic CRS,
    polygons are measured at once in an equal-area projection of the
    ellipsoid, and only those within a factor of 1.25 of ``limit`` there (or
    wider than 10 degrees, where straight edges in the projection stray from
    the geodesics) are measured one by one on the ellipsoid: a straight edge
    in the projection moves an island's area by far less than that. A layer
    of 39,000 islands takes 0.3 s instead of 1.0 s.

    Examples
    --------
    >>> import shapely
    >>> tiny, big = shapely.box(0, 60, 0.001, 60.001), shapely.box(0, 60, 1, 61)
    >>> smaller_than([tiny, big], CRS("EPSG:4326"), 1e6).tolist()
    [True, False]
    """
    polygons = np.asarray(polygons, dtype=object).ravel()
    if not crs.is_geographic or len(polygons) < 64:  # few, or planar: at once
        return polygon_areas(polygons, crs) < limit
    area = shapely.area(reproject(polygons, crs, _EQUAL_AREA))
    minx, _, maxx, _ = shapely.bounds(reproject(polygons, crs, "EPSG:4326")).T
    unsure = (
        ~((area < limit / _CLEAR) | (area > limit * _CLEAR))
        | (maxx - minx > 10.0)
        | ~np.isfinite(area)
    )
    small = area < limit
    small[unsure] = polygon_areas(polygons[unsure], crs) < limit
    return small


def _drop_small_holes(
    domain: shapely.Polygon, min_area: float, crs: CRS, kept: ArrayLike = ()
):
    holes = [shapely.Polygon(r) for r in domain.interiors]
    if not holes or min_area <= 0:
        return domain, 0
    keep = ~smaller_than(holes, crs, min_area)
    kept = np.asarray(kept, dtype=object).ravel()
    if len(kept):  # holes that hold land the user placed stay, whatever their size
        hit = shapely.STRtree(kept).query(holes, "intersects")[0]
        keep[hit] = True
    kept = [r for r, k in zip(domain.interiors, keep, strict=True) if k]
    return shapely.Polygon(domain.exterior, kept), int((~keep).sum())


def _check_ids(shorelines, open_boundaries) -> None:
    names = [name for name, _, _ in shorelines] + [b.name for b in open_boundaries]
    if len(set(names)) != len(names):
        raise ConfigError(f"boundary names repeat: {names}")
    for name, physical_id, _ in shorelines:
        if isinstance(physical_id, bool) or int(physical_id) <= 0:
            raise ConfigError(f"shoreline {name!r}: id = {physical_id!r} must be > 0")
    if sum(region is None for _, _, region in shorelines) != 1:
        raise ConfigError("shorelines: exactly one set must have region None")
    owners = {b.physical_id: b.name for b in open_boundaries}
    for name, physical_id, _ in shorelines:
        if physical_id in owners:
            raise ConfigError(
                f"shoreline {name!r}: id {physical_id} is also the id of open "
                f"boundary {owners[physical_id]!r}"
            )


def _tag_boundary(domain, open_boundaries, shorelines):
    # every open-boundary line cut into its 2-point pieces, in one R-tree
    pieces, owned = [], []
    for k, b in enumerate(open_boundaries):
        pieces.append(shapely.linestrings(np.stack([b.coords[:-1], b.coords[1:]], 1)))
        owned.append(np.full(len(b.coords) - 1, k))
    tree = shapely.STRtree(np.concatenate(pieces) if pieces else [])
    owners = np.concatenate(owned) if owned else np.empty(0, dtype=int)
    extent = max(np.ptp(np.asarray(domain.exterior.coords), axis=0).max(), 1.0)
    tolerance = 1e-9 * extent
    background = next(k for k, (_, _, r) in enumerate(shorelines) if r is None)
    segments: list[BoundarySegment] = []
    for ring in [domain.exterior, *domain.interiors]:
        xy = np.asarray(ring.coords)[:-1]
        n = len(xy)
        mid = 0.5 * (xy + np.roll(xy, -1, axis=0))  # edge i runs from i to i+1
        points = shapely.points(mid)
        # owners: k >= 0 an open boundary, -1 - k the shoreline set k
        owner = np.full(n, -1 - background)
        free = np.ones(n, dtype=bool)
        for k, (_, _, region) in enumerate(shorelines):
            if region is None:
                continue
            shapely.prepare(region)
            inside = free & shapely.dwithin(region, points, tolerance)
            owner[inside] = -1 - k
            free &= ~inside
        if len(owners):
            edge, piece = tree.query(points, predicate="dwithin", distance=tolerance)
            # an edge near several lines (where two cross) goes to the first one
            first = np.full(n, len(open_boundaries))
            np.minimum.at(first, edge, owners[piece])
            hit = first < len(open_boundaries)
            owner[hit] = first[hit]
        changes = np.flatnonzero(owner != np.roll(owner, 1))
        if len(changes) == 0:  # the whole ring is one run
            segments.append(
                _segment(np.vstack([xy, xy[:1]]), owner[0], open_boundaries, shorelines)
            )
            continue
        for k, start in enumerate(changes):
            stop = changes[(k + 1) % len(changes)]
            idx = np.arange(start, start + ((stop - start) % n or n) + 1) % n
            segments.append(
                _segment(xy[idx], owner[start], open_boundaries, shorelines)
            )
    return segments


def _segment(coords, owner, open_boundaries, shorelines) -> BoundarySegment:
    if owner < 0:
        name, physical_id, _ = shorelines[-1 - owner]
        return BoundarySegment(coords, "shoreline", name, physical_id)
    b = open_boundaries[owner]
    return BoundarySegment(coords, "open", b.name, b.physical_id)
