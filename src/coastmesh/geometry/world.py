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

import re
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.errors import InputDataError
from coastmesh.geometry.closing import close_narrow_water
from coastmesh.geometry.earth import reproject, reproject_points
from coastmesh.geometry.layers import valid_polygons
from coastmesh.geometry.sphere import plane_crs

__all__ = [
    "WorldLand",
    "WorldOcean",
    "geos_errors_named",
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
        # the bounds a buffer of the shell would have; buffering a full
        # resolution coast to read its bounds took a second
        wide = shell.length / 100
        x0, y0, x1, y1 = shapely.bounds(shell)
        return shapely.box(x0 - wide, y0 - wide, x1 + wide, y1 + wide).difference(shell)


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


@contextmanager
def geos_errors_named(path: str, plane: CRS | None) -> Iterator[None]:
    """Turn a GEOS error on the world layer into one that names the place.

    GEOS names a point of the plane ("side location conflict at -4803976.18
    -3753404.44"), which a user cannot find; this gives it in lon/lat, with
    the layer, and what to do.

    Raises
    ------
    InputDataError
        For a ``shapely.errors.GEOSException`` inside the block.

    Examples
    --------
    >>> with geos_errors_named("world.gpkg", None):
    ...     pass
    """
    try:
        yield
    except shapely.errors.GEOSException as exc:
        number = r"(-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)"
        found = re.search(number + r"[ ,]+" + number, str(exc))
        place = ""
        if found and plane is not None:
            xy = np.array([[float(found[1]), float(found[2])]])
            lon, lat = reproject_points(xy, plane, "EPSG:4326")[0]
            place = f" at ({lon:.4f}, {lat:.4f}) (lon, lat)"
        raise InputDataError(
            f"GEOS could not combine the world layer's polygons{place}: {exc}. "
            "The layer's polygons there may be invalid or touch themselves "
            "once in the plane: repair them (ogr2ogr -makevalid), or leave "
            "that place out with a [[cuts]] line",
            path=path,
        ) from exc
