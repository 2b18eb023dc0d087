"""The sphere in one place: lon/lat and vectors, the stereographic plane.

Global meshes live on the sphere of radius
:data:`~coastmesh.geometry.earth.EARTH_RADIUS`, with longitude and latitude taken
as spherical coordinates (global tidal models run on the sphere):

* :func:`lonlat_to_xyz`, :func:`xyz_to_lonlat` and :func:`wrap_longitude` turn
  longitude and latitude into points of the sphere and back;
* :func:`plane_crs` is the stereographic plane a world is meshed in, whose
  singular point lies on land, and :func:`stereographic_scale` its scale factor
  (:func:`plane_scale` the same from a point's distance from the centre);
* :func:`empty_pole` finds a point far from every node of a mesh, and
  :func:`local_plane` a conformal plane for a mesh (round the world: the
  stereographic plane of that point).

Lengths on the WGS84 ellipsoid (earth-centred coordinates, arcs) are in
:mod:`coastmesh.geometry.earth`.
"""

from __future__ import annotations

import math
import warnings
from typing import overload

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS, Transformer
from scipy.spatial import cKDTree

from coastmesh.errors import InputDataError
from coastmesh.geometry.earth import EARTH_RADIUS, transformer
from coastmesh.types import Mesh

__all__ = [
    "empty_pole",
    "is_world_plane",
    "local_plane",
    "lonlat_to_xyz",
    "plane_crs",
    "plane_scale",
    "stereographic_scale",
    "wrap_longitude",
    "xyz_to_lonlat",
]

_LONLAT = CRS.from_epsg(4326)


def wrap_longitude(lon: ArrayLike) -> NDArray[np.float64]:
    """Return longitudes in degrees moved into [-180, 180).

    Examples
    --------
    >>> wrap_longitude([180.0, -180.0, 190.0, -190.0, 359.5]).tolist()
    [-180.0, -180.0, -170.0, 170.0, -0.5]
    """
    lon = np.asarray(lon, dtype=np.float64)
    return np.where((lon >= -180) & (lon < 180), lon, (lon + 180) % 360 - 180)


def lonlat_to_xyz(lonlat: ArrayLike, radius: float = 1.0) -> NDArray[np.float64]:
    """Return the points of the sphere of ``radius`` at longitude, latitude.

    Parameters
    ----------
    lonlat : array_like of shape (N, 2)
        Longitude and latitude in degrees.
    radius : float, default 1.0
        The sphere's radius: 1 gives unit vectors.

    Returns
    -------
    ndarray of shape (N, 3)
        x towards (0, 0), y towards (90, 0), z towards the North Pole.

    Examples
    --------
    >>> lonlat_to_xyz([[0, 0], [90, 0], [0, 90]]).round(12).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    lonlat = np.asarray(lonlat, dtype=np.float64).reshape(-1, 2)
    lon, lat = np.radians(lonlat[:, 0]), np.radians(lonlat[:, 1])
    return radius * np.column_stack(
        [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]
    )


def xyz_to_lonlat(xyz: ArrayLike) -> NDArray[np.float64]:
    """Return the longitude, latitude in degrees of points given in x, y, z.

    Parameters
    ----------
    xyz : array_like of shape (N, 3)
        Points away from the centre, on a sphere of any radius.

    Returns
    -------
    ndarray of shape (N, 2)
        Longitude in [-180, 180), latitude in [-90, 90].

    Examples
    --------
    >>> xyz_to_lonlat([[-1.0, 0.0, 0.0], [0.0, -2.0, 0.0], [0.0, 0.0, 3.0]]).tolist()
    [[-180.0, 0.0], [-90.0, 0.0], [0.0, 90.0]]
    """
    xyz = np.asarray(xyz, dtype=np.float64).reshape(-1, 3)
    x, y, z = xyz.T
    lon = wrap_longitude(np.degrees(np.arctan2(y, x)))
    lat = np.degrees(np.arctan2(z, np.hypot(x, y)))
    return np.column_stack([lon, lat])


def plane_crs(pole: tuple[float, float] = (0.0, -90.0)) -> CRS:
    """Return the stereographic plane whose singular point is ``pole`` (lon, lat).

    The plane touches the sphere at the antipode of ``pole``, where the scale is
    1; the pole itself goes to infinity and must lie on land.

    Examples
    --------
    >>> crs = plane_crs()
    >>> crs.is_projected, crs.to_dict()["lat_0"], crs.to_dict()["R"]
    (True, 90, 6371008.8)
    """
    lon, lat = (float(v) for v in pole)
    if not (-90.0 <= lat <= 90.0 and math.isfinite(lon)):
        raise InputDataError(f"the projection pole ({lon}, {lat}) is not on the Earth")
    centre_lon = (lon + 180.0 + 180.0) % 360.0 - 180.0
    return CRS.from_proj4(
        f"+proj=stere +lat_0={-lat:.12g} +lon_0={centre_lon:.12g} +k=1 "
        f"+x_0=0 +y_0=0 +R={EARTH_RADIUS} +units=m +no_defs +type=crs"
    )


def is_world_plane(crs: CRS) -> bool:
    """Return whether ``crs`` is a stereographic plane of :func:`plane_crs`.

    Its areas and lengths are those on the sphere times ``k^2`` and ``k``.

    Examples
    --------
    >>> is_world_plane(plane_crs((103.0, 46.0))), is_world_plane(CRS("EPSG:3413"))
    (True, False)
    """
    if not crs.is_projected:
        return False
    with warnings.catch_warnings():  # PROJ's warning that a PROJ string is lossy
        warnings.simplefilter("ignore", UserWarning)
        p = crs.to_dict()
    return (
        p.get("proj") == "stere"
        and p.get("R") == EARTH_RADIUS
        and p.get("k", 1) == 1
        and p.get("x_0", 0) == 0
        and p.get("y_0", 0) == 0
    )


def stereographic_scale(
    lon: ArrayLike, lat: ArrayLike, pole: tuple[float, float] = (0.0, -90.0)
) -> NDArray[np.float64]:
    """Scale of the stereographic plane of :func:`plane_crs` at (lon, lat).

    ``k = 2 / (1 + cos c)``, ``c`` the angle from the plane's centre (the
    antipode of ``pole``): 1 at the centre, 2 a quarter of the way round, and
    without bound at the pole. A length of ``h`` metres on the sphere is
    ``k h`` metres in the plane.

    Examples
    --------
    >>> stereographic_scale([0.0, 0.0, 0.0], [90.0, 0.0, -60.0]).round(6).tolist()
    [1.0, 2.0, 14.928203]
    """
    lon = np.radians(np.asarray(lon, dtype=np.float64))
    lat = np.radians(np.asarray(lat, dtype=np.float64))
    plon, plat = math.radians(pole[0]), math.radians(pole[1])
    # 1 - cos(angle from the pole) = chord^2 / 2, exact near the pole too
    chord2 = (
        (np.cos(lat) * np.cos(lon) - math.cos(plat) * math.cos(plon)) ** 2
        + (np.cos(lat) * np.sin(lon) - math.cos(plat) * math.sin(plon)) ** 2
        + (np.sin(lat) - math.sin(plat)) ** 2
    )
    with np.errstate(divide="ignore"):
        return 4.0 / chord2


@overload
def plane_scale(r: float, *, radius: float = ...) -> float: ...
@overload
def plane_scale(
    r: NDArray[np.float64], *, radius: float = ...
) -> NDArray[np.float64]: ...
def plane_scale(
    r: float | NDArray[np.float64], *, radius: float = EARTH_RADIUS
) -> float | NDArray[np.float64]:
    """Scale of a stereographic plane at a distance ``r`` from its centre.

    The :func:`stereographic_scale` ``k`` of a point given in the plane rather
    than by its longitude and latitude: a point at the angle ``c`` from the
    centre lies ``r = 2 R tan(c / 2)`` from it, so ``k = 2 / (1 + cos c) =
    1 + tan^2(c / 2) = 1 + (r / 2R)^2``. It holds in the plane of
    :func:`plane_crs` for every pole, and in any stereographic plane of a
    sphere of radius ``R`` with scale 1 at its centre.

    Parameters
    ----------
    r : float or ndarray
        Distances from the plane's centre, metres in the plane.
    radius : float, default EARTH_RADIUS
        The sphere's radius ``R``, metres.

    Returns
    -------
    float or ndarray
        ``k``, plane metres per metre on the sphere: a float for a float, an
        array of the shape of ``r`` for an array.

    Examples
    --------
    >>> plane_scale(0.0), plane_scale(2 * EARTH_RADIUS)
    (1.0, 2.0)
    """
    return 1.0 + (r / (2.0 * radius)) ** 2


def local_plane(mesh: Mesh) -> Transformer | None:
    """Return the map to a conformal plane (angles there are angles on the Earth).

    None for a projected (or planar) mesh: its own plane is used.
    """
    if mesh.crs is None or mesh.crs.is_projected:
        return None
    if np.ptp(mesh.points[:, 0]) > 180.0:  # round the world: away from every node
        return transformer(mesh.crs, plane_crs(empty_pole(mesh.points)))
    lon, lat = np.median(mesh.points, axis=0)
    plane = CRS.from_proj4(
        f"+proj=sterea +lat_0={lat} +lon_0={lon} +k=1 +datum=WGS84 +units=m"
    )
    return transformer(mesh.crs, plane)


def empty_pole(lonlat: NDArray[np.float64]) -> tuple[float, float]:
    """Return a point far from every node, for a plane's singular point.

    The South or North Pole, or the antipode of the nodes' mean direction:
    whichever is farthest from a node.

    Examples
    --------
    >>> nodes = np.array([[0.0, 0.0], [120.0, 10.0], [-120.0, -10.0], [0, 80]])
    >>> empty_pole(nodes)
    (0.0, -90.0)
    """
    xyz = lonlat_to_xyz(lonlat)
    mean = -xyz.mean(axis=0)
    mean = mean / np.linalg.norm(mean) if np.linalg.norm(mean) > 0 else [0, 0, -1]
    candidates = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], mean])
    gap, _ = cKDTree(xyz).query(candidates)
    x, y, z = candidates[int(np.argmax(gap))]
    pole_lat = float(np.degrees(np.arcsin(np.clip(z, -1.0, 1.0))))
    pole_lon = float(np.degrees(np.arctan2(y, x))) if abs(z) < 1.0 else 0.0
    return (pole_lon + 0.0, pole_lat)
