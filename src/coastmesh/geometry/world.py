"""The world ocean as one polygon: world shorelines joined and put in a plane.

A global case meshes the ocean bounded by the world's shorelines, with no open
boundary. Two things stand between a world shoreline layer and a polygon Gmsh
can mesh:

* **Polygons split at the dateline.** GSHHG (and layers made from it) stores
  land that crosses the antimeridian (Eurasia, some Pacific islands) as two
  polygons that meet along longitude 180, and Antarctica as two land polygons
  closed along the 0 and 180 meridians and down to latitude -90.
  :func:`join_dateline` joins each pair into one polygon: the western half moves
  east by 360 degrees, so the two share their cut edge, and the union removes it.
  Longitudes then run past 180; every transform below takes them as they are.
* **The sphere in a plane.** The ocean is mapped to a plane by the stereographic
  projection whose singular point (the projection's *pole*, mapped to infinity)
  lies on land: inside Antarctica by default, at the South Pole. The plane is
  conformal, so angles are kept and a triangle shaped well in the plane is
  shaped well on the sphere; lengths are scaled by
  :func:`~coastmesh.geometry.sphere.stereographic_scale`, which
  the size field is multiplied by. The land polygon holding the pole becomes the
  outside of the ocean: its coast (:func:`polar_ring` for a polygon that runs
  down to the South Pole) is the ocean's exterior ring, and every other land
  polygon is a hole. :func:`world_ocean` builds that polygon and checks that it
  is one: a layer that does not cover the world, or a pole in the sea, is an
  error that says so.

The plane is on a sphere of radius :data:`~coastmesh.geometry.earth.EARTH_RADIUS`
(``+proj=stere +R=...``): global tidal models run on the sphere, and longitude and
latitude are taken as spherical coordinates, as they are there.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.errors import InputDataError
from coastmesh.geometry.earth import EARTH_RADIUS, reproject
from coastmesh.geometry.layers import valid_polygons
from coastmesh.geometry.sphere import plane_crs

__all__ = [
    "WorldLand",
    "WorldOcean",
    "close_narrow_water",
    "join_dateline",
    "polar_ring",
    "world_land",
    "world_ocean",
]

#: Latitudes within this of -90 are the South Pole (degrees).
_POLE_TOLERANCE = 1e-6

_MIN_LON_SPAN = 300.0  #: a world layer spans at least this much longitude (deg)
_STEP = 0.25  #: longest edge (deg) before the land goes into the plane


def join_dateline(geoms: ArrayLike) -> NDArray[np.object_]:
    """Join the polygons split at the antimeridian into one polygon each.

    Parameters
    ----------
    geoms : array_like of shapely polygons (lon/lat degrees, None allowed)

    Returns
    -------
    ndarray of object
        The polygons that touch neither longitude 180 nor -180, unchanged and in
        their order, then one polygon per group that shares a cut edge along the
        antimeridian (the western pieces moved east by 360 degrees). Polygons
        that touch the antimeridian without a partner are kept (moved east if
        they lie west of it).

    Examples
    --------
    >>> east = shapely.box(170.0, 60.0, 180.0, 70.0)
    >>> west = shapely.box(-180.0, 62.0, -170.0, 68.0)
    >>> out = join_dateline([shapely.box(0, 0, 1, 1), east, west])
    >>> len(out), out[1].bounds, out[1].area
    (2, (170.0, 60.0, 190.0, 70.0), 160.0)
    """
    geoms = np.asarray(geoms, dtype=object).ravel()
    geoms = geoms[~shapely.is_missing(geoms)]
    parts = shapely.get_parts(geoms)
    bounds = shapely.bounds(parts)
    east = bounds[:, 2] >= 180.0
    west = bounds[:, 0] <= -180.0
    if not (east.any() and west.any()):
        return parts
    moved = shapely.transform(parts[west], lambda xy: xy + [360.0, 0.0])
    cut = valid_polygons(np.concatenate([parts[east & ~west], moved]))
    joined = shapely.get_parts(shapely.union_all(cut))
    return np.concatenate([parts[~(east | west)], joined])


def polar_ring(polygon: shapely.Polygon) -> NDArray[np.float64]:
    """Return the coast of a land polygon that runs down to the South Pole, as a ring.

    GSHHG closes Antarctica along two meridians and along latitude -90. Once its
    halves are joined (:func:`join_dateline`) the polygon spans 360 degrees of
    longitude: its exterior is the coast from one seam meridian to the other,
    then down the seam, along -90 and up the other seam. The coast alone, with
    the two ends (one point on the sphere) made one, is a closed ring round the
    pole.

    Returns
    -------
    ndarray of shape (n, 2)
        The coast's vertices, lon/lat, closed on the sphere: longitudes run on
        along the coast, so no edge jumps across the antimeridian, and the last
        vertex is the first moved by 360 degrees (the same point).

    Raises
    ------
    InputDataError
        If the polygon does not reach the South Pole, or its coast does not
        close round it.

    Examples
    --------
    >>> cap = shapely.Polygon([(0, -70), (180, -75), (360, -70), (360, -90),
    ...                        (0, -90)])
    >>> polar_ring(cap).tolist()
    [[0.0, -70.0], [180.0, -75.0], [360.0, -70.0]]
    """
    xy = shapely.get_coordinates(polygon.exterior)[:-1]
    at_pole = xy[:, 1] <= -90.0 + _POLE_TOLERANCE
    if not at_pole.any():
        raise InputDataError("the polar land polygon does not reach latitude -90")
    # start just after the pole run, so the coast is one run
    last = int(np.flatnonzero(at_pole)[-1])
    xy = np.roll(xy, -(last + 1), axis=0)
    at_pole = np.roll(at_pole, -(last + 1))
    coast = xy[: int(np.flatnonzero(at_pole)[0])]
    # the seams: the straight meridian pieces leading to and from the pole
    lon0, lon1 = coast[0, 0], coast[-1, 0]
    first = int(np.argmax(coast[:, 0] != lon0))  # last vertex of the first seam
    end = len(coast) - int(np.argmax(coast[::-1, 0] != lon1))
    coast = coast[max(first - 1, 0) : end + 1]
    span = coast[-1, 0] - coast[0, 0]
    if abs(abs(span) - 360.0) > 1e-9 or abs(coast[-1, 1] - coast[0, 1]) > 1e-9:
        raise InputDataError(
            "the polar land polygon's coast does not close round the pole: it runs "
            f"from ({coast[0, 0]:.4f}, {coast[0, 1]:.4f}) to "
            f"({coast[-1, 0]:.4f}, {coast[-1, 1]:.4f}); are both halves in the layer?"
        )
    return coast


@dataclass(frozen=True, slots=True)
class WorldOcean:
    """The world ocean as one polygon in the stereographic plane.

    Attributes
    ----------
    polygon : shapely.Polygon
        The ocean, in :attr:`crs` (metres in the plane).
    crs : pyproj.CRS
        The plane (:func:`plane_crs`).
    pole : tuple of float
        The projection's singular point, (lon, lat), on land.
    islands : int
        Land polygons that are holes of the ocean.
    joined : int
        Pieces split at the antimeridian that were joined to their other half.
    enclosed : int
        Pieces of water enclosed by land and cut off from the ocean (lagoons
        closed by the shoreline data, or water cut off by the closing), left out.
    closed : int
        Land polygons merged with a neighbour across water narrower than
        ``close`` (:func:`close_narrow_water`).
    """

    polygon: shapely.Polygon
    crs: CRS
    pole: tuple[float, float]
    islands: int
    joined: int
    enclosed: int
    closed: int = 0


def world_ocean(
    land: ArrayLike,
    crs: CRS | str = "EPSG:4326",
    *,
    pole=(0.0, -90.0),
    close: float | None = None,
) -> WorldOcean:
    """Build the world ocean from a world shoreline layer.

    Parameters
    ----------
    land : array_like of shapely polygons
        Land polygons of the whole world (lon/lat in ``crs``), split at the
        antimeridian or not.
    crs : CRS-like
        A geographic CRS.
    pole : (lon, lat)
        The projection's singular point; it must lie on land.
    close : float, optional
        Close water narrower than this (metres on the Earth) between pieces of
        land, and inlets narrower than this (:func:`close_narrow_water`): a
        mesh of that size could not resolve them.

    Raises
    ------
    InputDataError
        If the layer does not cover the world (both hemispheres, at least
        300 degrees of longitude), ``pole`` is in the sea, or the ocean is not
        one valid polygon.
    """
    world = world_land(land, crs, pole=pole)
    outer, islands, plane = world.shell, world.islands, world.crs
    closed = 0
    if close is not None and close > 0:
        # the polar land as a frame round the ocean, so it closes with the rest
        frame = shapely.box(*shapely.buffer(outer, outer.length / 100).bounds)
        land = np.concatenate([[frame.difference(outer)], islands])
        land, closed = close_narrow_water(land, close, within=1.05 * world.reach)
        outer, islands = frame.difference(land[0]), land[1:]
    ocean = shapely.get_parts(outer.difference(shapely.union_all(islands)))
    if len(ocean) == 0:
        raise InputDataError("the world shorelines leave no ocean")
    ocean = ocean[np.argsort(-shapely.area(ocean), kind="stable")]
    if not ocean[0].is_valid:
        reason = shapely.is_valid_reason(ocean[0])
        raise InputDataError(f"the world ocean is not a valid polygon: {reason}")
    return WorldOcean(
        polygon=ocean[0],
        crs=plane,
        pole=(float(pole[0]), float(pole[1])),
        islands=len(ocean[0].interiors),
        joined=world.joined,
        enclosed=len(ocean) - 1,
        closed=closed,
    )


def close_narrow_water(
    land: NDArray[np.object_],
    width: float,
    *,
    within: float | None = None,
    keep_area: float = 0.0,
) -> tuple[NDArray[np.object_], int]:
    """Close water narrower than ``width`` between and within land polygons.

    A morphological closing (buffer out by ``width / 2``, then back in) in the
    stereographic plane, where a length on the Earth is ``k`` times longer.
    ``k = 1 + r^2 / 4R^2`` depends only on the distance ``r`` from the plane's
    centre, so the plane is cut into rings (annuli) over which ``k`` changes by
    at most 20 %: each ring's land, with a margin, is closed at that ring's
    scale and cut back to the ring. The width closed is ``width`` to within
    that 20 %, anywhere on the Earth.

    Parameters
    ----------
    land : ndarray of shapely polygons
        Land in a stereographic plane of :func:`plane_crs` (any pole): the
        scale there depends only on the distance from the plane's centre.
    width : float
        Metres on the Earth.
    within : float, optional
        Only within this distance of the plane's centre (metres in the plane):
        land beyond it (the far side of a frame round the ocean) is kept as it
        is, however thin.
    keep_area : float, default 0
        Land polygons of at least this area (square metres on the Earth)
        keep their closed shape: the opening, which takes land narrower than
        ``width``, applies to smaller land only. A tide model must keep the
        islands it was asked for, whole: they block and steer the flow.

    Returns
    -------
    land : ndarray of shapely geometries
        The land after the closing: the frame's part first (when it was given),
        then the rest.
    merged : int
        Land polygons that became one with another.
    """
    # k depends only on r in every stereographic plane: no CRS or pole needed
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
        closed = near.buffer(half, quad_segs=4).buffer(-half, quad_segs=4)
        # and land narrower than width (spits, thin peninsulas) opened up,
        # but for land of keep_area or more: it keeps its closed shape
        opened = closed.buffer(-half, quad_segs=4).buffer(half, quad_segs=4)
        kept = _kept(closed, big)
        pieces.append(shapely.union_all([opened, *kept]).intersection(ring))
    if within is not None:  # the land beyond, as it is
        pieces.append(union.difference(_annulus(0.0, edges[-1])))
    # the rings' seams (circles: parallels of latitude) can leave spikes of no
    # width where two rings closed differently; a closing and an opening by
    # a metre takes them away
    closed = shapely.union_all(pieces).buffer(1.0).buffer(-2.0).buffer(1.0)
    parts = shapely.get_parts(closed)
    parts = parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]
    # the frame's part first
    first = np.argmax(shapely.area(parts))
    parts = np.concatenate([parts[first : first + 1], np.delete(parts, first)])
    merged = max(len(land) - len(parts), 0)
    return parts, merged


def _big_land(
    union: shapely.Geometry, keep_area: float, radius: float
) -> shapely.Geometry | None:
    """Return the land polygons of ``keep_area`` or more on the Earth; None if none.

    A plane's areas are ``k^2`` times the Earth's, ``k`` taken at each
    polygon's centroid.
    """
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


def _kept(closed: shapely.Geometry, big: shapely.Geometry | None) -> list:
    """Return the land of ``closed`` on ``big`` land, as it is (not opened).

    The opening rounds every corner and takes every strip of land narrower
    than the width: islands lose their arms, and an island narrow everywhere
    goes whole. Land a tide model was asked to keep (``keep_area`` or more)
    keeps its closed shape instead; the closing has already filled the water
    too narrow to mesh. Only smaller land is opened.
    """
    if big is None:
        return []
    parts = shapely.get_parts(closed)
    return list(parts[shapely.intersects(parts, big)])


def _annulus(r0: float, r1: float) -> shapely.Geometry:
    """Return the ring between radii ``r0`` and ``r1`` about the plane's centre."""
    outer = shapely.Point(0.0, 0.0).buffer(r1, quad_segs=256)
    if r0 <= 0.0:
        return outer
    return outer.difference(shapely.Point(0.0, 0.0).buffer(r0, quad_segs=256))


@dataclass(frozen=True, slots=True)
class WorldLand:
    """World land in the stereographic plane, ready for shoreline sets.

    Attributes
    ----------
    shell : shapely.Polygon
        The inside of the polar land's coast in the plane: the ocean and every
        other piece of land (Antarctica is what lies outside it).
    islands : ndarray of shapely polygons
        Every other piece of land, in the plane.
    crs : pyproj.CRS
        The plane.
    pole : (lon, lat)
    joined : int
        Pieces split at the antimeridian joined to their other half.
    """

    shell: shapely.Polygon
    islands: NDArray[np.object_]
    crs: CRS
    pole: tuple[float, float]
    joined: int

    @property
    def reach(self) -> float:
        """The ocean's farthest distance from the plane's centre, metres."""
        xy = shapely.get_coordinates(self.shell.exterior)
        return float(np.hypot(xy[:, 0], xy[:, 1]).max())

    def frame(self, shell: shapely.Polygon | None = None) -> shapely.Polygon:
        """Return the polar land as a polygon: a wide box less ``shell``."""
        shell = self.shell if shell is None else shell
        box = shapely.box(*shapely.buffer(shell, shell.length / 100).bounds)
        return box.difference(shell)


def world_land(
    land: ArrayLike, crs: CRS | str = "EPSG:4326", *, pole=(0.0, -90.0)
) -> WorldLand:
    """Put a world shoreline layer in the plane: joined, the polar land a shell.

    Takes and checks what :func:`world_ocean` takes; see there.
    """
    crs = CRS.from_user_input(crs)
    if not crs.is_geographic:
        raise InputDataError(
            f"a global case needs its world shorelines in longitude and latitude; "
            f"the layer is in {crs.name!r}"
        )
    geoms = np.asarray(land, dtype=object).ravel()
    geoms = valid_polygons(geoms)
    _check_cover(geoms)
    before = len(shapely.get_parts(geoms))
    parts = join_dateline(geoms)
    # land down to the South Pole (Antarctica, closed along -90): its coast
    reaches = shapely.bounds(parts)[:, 1] <= -90.0 + _POLE_TOLERANCE
    if float(pole[1]) <= -90.0 + _POLE_TOLERANCE:
        if reaches.sum() != 1:
            raise InputDataError(
                f"{int(reaches.sum())} land polygons reach the South Pole, expected "
                "1 (Antarctica): does the layer hold Antarctica (GSHHG level 5 or 6)?"
            )
        polar = int(np.flatnonzero(reaches)[0])
    else:
        holds = shapely.covers(parts, shapely.Point(*pole)) | shapely.covers(
            parts, shapely.Point(pole[0] + 360.0, pole[1])
        )
        if not holds.any() or holds[reaches].any():
            raise InputDataError(
                f"the projection pole ({pole[0]}, {pole[1]}) is in the sea: it must "
                "lie on land, well inside a continent (the South Pole is the usual "
                "choice)"
            )
        polar = int(np.flatnonzero(holds)[0])
    # every piece of land as its rings, the polar ones as their coast; edges
    # straight in lon/lat bend in the plane, so short ones stay simple there
    rings = list(shapely.get_exterior_ring(parts))
    for i in np.flatnonzero(reaches):  # closed in the plane, not in lon/lat
        rings[i] = shapely.LineString(polar_ring(parts[i]))
    plane = plane_crs(pole)
    rings = reproject(shapely.segmentize(np.asarray(rings), _STEP), crs, plane)
    for i in np.flatnonzero(reaches):  # the two ends are one point
        rings[i] = shapely.LinearRing(shapely.get_coordinates(rings[i])[:-1])
    outer = valid_polygons([shapely.Polygon(rings[polar])])
    outer = outer[np.argmax(shapely.area(outer))]
    holes = [
        [reproject(shapely.segmentize(r, _STEP), crs, plane) for r in p.interiors]
        for p in parts
    ]
    islands = valid_polygons(
        [
            shapely.Polygon(r, h)
            for i, (r, h) in enumerate(zip(rings, holes, strict=True))
            if i != polar
        ]
    )
    return WorldLand(
        outer, islands, plane, (float(pole[0]), float(pole[1])), before - len(parts)
    )


def _check_cover(geoms: NDArray[np.object_]) -> None:
    """Refuse a layer that is not of the whole world."""
    if len(geoms) == 0:
        raise InputDataError("a global case needs a world shoreline layer; it is empty")
    x0, y0, x1, y1 = shapely.total_bounds(geoms)
    if x1 - x0 < _MIN_LON_SPAN or y0 > 0.0 or y1 < 0.0:
        raise InputDataError(
            f"the shorelines span longitude {x0:.1f} to {x1:.1f} and latitude "
            f"{y0:.1f} to {y1:.1f}: a global case needs a world layer that covers "
            "both hemispheres (GSHHG level 1 with Antarctica, level 5 or 6)"
        )
