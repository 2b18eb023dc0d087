"""The Earth in one place: reprojection, earth-centred coordinates, lengths.

Every module that moves coordinates between CRSs or measures on the Earth goes
through here:

- :func:`transformer` returns a cached ``pyproj.Transformer`` (``always_xy=True``,
  so x is longitude or easting everywhere);
- :func:`reproject` and :func:`reproject_points` move shapely geometries and
  ``(n, 2)`` point arrays from one CRS to another;
- :func:`earth_centred` puts points of any geographic, projected or compound CRS
  into WGS84 earth-centred, earth-fixed metres (EPSG:4978) at height 0, where
  distances are chords and a k-d tree finds nearest neighbours on the Earth;
- :func:`arc_lengths` lengthens such chords to arcs of the WGS84 ellipsoid;
- :func:`metres_per_unit` and :data:`METRES_PER_DEGREE` turn CRS units into
  metres, and :data:`EARTH_RADIUS` is the sphere lengths in degrees are taken on.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS, Transformer

from coastmesh.types import Domain, Mesh

__all__ = [
    "EARTH_RADIUS",
    "GRAVITY",
    "METRES_PER_DEGREE",
    "arc_lengths",
    "densified",
    "earth_centred",
    "ellipsoid_area_scale",
    "mesh_earth_centred",
    "metres_per_unit",
    "reproject",
    "reproject_points",
    "transformer",
]

#: Mean radius of the Earth (IUGG, R1 of WGS84), metres: the length of one radian
#: of great-circle arc, used for lengths the paper gives in degrees.
EARTH_RADIUS = 6_371_008.8

#: Length of one degree of great-circle arc on the sphere of radius
#: :data:`EARTH_RADIUS`, metres (111 195 m; a degree of latitude, near enough).
METRES_PER_DEGREE = EARTH_RADIUS * math.pi / 180.0
#: Standard gravity, m/s2: every wave speed of coastmesh uses it.
GRAVITY = 9.80665

_ECEF = CRS.from_epsg(4978)  # WGS84 earth-centred, earth-fixed, metres
_A = 6_378_137.0  # WGS84 semi-major axis, metres
_E2 = (2 - 1 / 298.257223563) / 298.257223563  # WGS84 first eccentricity squared


def ellipsoid_area_scale(lat: ArrayLike) -> NDArray[np.float64]:
    """Return the WGS84 ellipsoid's area over the sphere's at geodetic ``lat``.

    A global case's plane (:func:`~coastmesh.geometry.sphere.plane_crs`) puts
    longitude and geodetic latitude on the sphere of radius
    :data:`EARTH_RADIUS` as they are, so an area measured there is the
    ellipsoid's divided by ``M N / R^2`` (the meridian and prime-vertical
    radii of curvature): 0.9955 at the equator, 1.0074 at 70 degrees. An
    island of 500.8 km2 on the ellipsoid measures 497.1 km2 on the sphere at
    70.9 N.

    Examples
    --------
    >>> [round(float(v), 4) for v in ellipsoid_area_scale([0.0, 70.0, -90.0])]
    [0.9955, 1.0074, 1.009]
    """
    sin = np.sin(np.radians(np.asarray(lat, dtype=float)))
    return _A**2 * (1 - _E2) / (1 - _E2 * sin * sin) ** 2 / EARTH_RADIUS**2


def transformer(src: Any, dst: Any) -> Transformer:
    """Return the transformer from CRS ``src`` to CRS ``dst``, x first.

    Parameters
    ----------
    src, dst : pyproj.CRS or CRS-like
        Anything :meth:`pyproj.CRS.from_user_input` takes: a CRS, ``"EPSG:4326"``,
        an EPSG code, WKT, a PROJ string.

    Returns
    -------
    pyproj.Transformer
        With ``always_xy=True``: longitude (or easting) first in and out. The same
        object for the same pair of CRSs (a least-recently-used cache of 64 pairs);
        pyproj's transformers are safe to share between threads.

    Examples
    --------
    >>> t = transformer("EPSG:4326", "EPSG:32630")
    >>> [round(v) for v in t.transform(-3.0, 0.0)]
    [500000, 0]
    >>> t is transformer("EPSG:4326", "EPSG:32630")
    True
    """
    return _cached_transformer(CRS.from_user_input(src), CRS.from_user_input(dst))


@functools.lru_cache(maxsize=64)
def _cached_transformer(src: CRS, dst: CRS) -> Transformer:
    return Transformer.from_crs(src, dst, always_xy=True)


def reproject(geometry: Any, src: Any, dst: Any) -> Any:
    """Move shapely geometries from CRS ``src`` to CRS ``dst``.

    Parameters
    ----------
    geometry : shapely.Geometry or array_like of shapely geometries
        In ``src``; None passes through. Z coordinates are dropped.
    src, dst : pyproj.CRS or CRS-like
        The CRSs (see :func:`transformer`).

    Returns
    -------
    shapely.Geometry or ndarray of shapely geometries
        The geometries in ``dst``, vertex by vertex (no densifying); the input
        itself when ``src`` and ``dst`` are equal.

    Examples
    --------
    >>> import shapely
    >>> line = shapely.LineString([(-3.0, 0.0), (-3.0, 1.0)])
    >>> utm = reproject(line, "EPSG:4326", "EPSG:32630")
    >>> [round(v) for v in utm.bounds]
    [500000, 0, 500000, 110530]
    >>> reproject(line, "EPSG:4326", 4326) is line
    True
    """
    src, dst = CRS.from_user_input(src), CRS.from_user_input(dst)
    if src == dst:
        return geometry
    t = transformer(src, dst)
    return shapely.transform(
        geometry, lambda xy: np.column_stack(t.transform(xy[:, 0], xy[:, 1]))
    )


def reproject_points(xy: ArrayLike, src: Any, dst: Any) -> NDArray[np.float64]:
    """Move points from CRS ``src`` to CRS ``dst``.

    Parameters
    ----------
    xy : array_like of shape (n, 2)
        Points in ``src``, x (longitude or easting) first.
    src, dst : pyproj.CRS or CRS-like
        The CRSs (see :func:`transformer`).

    Returns
    -------
    ndarray of shape (n, 2)
        The points in ``dst``, a new float64 array; ``inf`` where a point has no
        position in ``dst``.

    Raises
    ------
    ValueError
        If ``xy`` is not of shape (n, 2).

    Examples
    --------
    >>> reproject_points([[-3.0, 0.0], [3.0, 0.0]], "EPSG:4326", "EPSG:3395").round()
    array([[-333958.,       0.],
           [ 333958.,       0.]])
    """
    points = _points(xy, "xy")
    src, dst = CRS.from_user_input(src), CRS.from_user_input(dst)
    if src == dst:
        return points.copy()
    return np.column_stack(transformer(src, dst).transform(points[:, 0], points[:, 1]))


def earth_centred(
    points: ArrayLike, crs: Any, *, name: str = "points"
) -> NDArray[np.float64]:
    """Return points in WGS84 earth-centred, earth-fixed metres, at height 0.

    Parameters
    ----------
    points : array_like of shape (n, 2)
        Points in ``crs``, x (longitude or easting) first.
    crs : pyproj.CRS or CRS-like
        A geographic or projected CRS, or a compound CRS whose horizontal part is
        one (its vertical part is ignored: the height is 0 on the ellipsoid of
        the horizontal datum).
    name : str
        What ``points`` are, for error messages (``"mesh.points"``, say).

    Returns
    -------
    ndarray of shape (n, 3)
        x, y, z in EPSG:4978, metres. A CRS on another datum is shifted to
        WGS84 by pyproj.

    Raises
    ------
    ValueError
        If ``points`` is not of shape (n, 2), ``crs`` is neither geographic nor
        projected (a geocentric CRS, say), or a point has no position on the
        Earth (outside the projection, latitude beyond 90, NaN); the message
        names the first such point and counts them.

    Examples
    --------
    >>> earth_centred([[0.0, 0.0], [90.0, 0.0], [0.0, 90.0]], "EPSG:4326").round(3)
    array([[6378137.   ,       0.   ,       0.   ],
           [      0.   , 6378137.   ,       0.   ],
           [      0.   ,       0.   , 6356752.314]])
    """
    xy = _points(points, name)
    crs = CRS.from_user_input(crs)
    horizontal = crs.sub_crs_list[0] if crs.is_compound else crs
    if not (horizontal.is_geographic or horizontal.is_projected):
        raise ValueError(
            f"the CRS of {name} is {crs.name!r} ({crs.type_name}), expected a "
            "geographic or projected CRS"
        )
    to_ecef = transformer(horizontal, _ECEF)
    xyz = np.column_stack(to_ecef.transform(xy[:, 0], xy[:, 1], np.zeros(len(xy))))
    bad = np.flatnonzero(~np.isfinite(xyz).all(axis=1))
    if bad.size:
        x, y = xy[bad[0]]
        raise ValueError(
            f"{name}[{bad[0]}] = ({x}, {y}) has no position on the Earth in "
            f"{crs.name!r}; {bad.size} such points: is the CRS right?"
        )
    return xyz


def arc_lengths(p: ArrayLike, q: ArrayLike) -> NDArray[np.float64]:
    """Return the lengths on the WGS84 ellipsoid between earth-centred points.

    Parameters
    ----------
    p, q : array_like of shape (k, 3)
        Points on the ellipsoid in earth-centred metres (:func:`earth_centred`).

    Returns
    -------
    ndarray of shape (k,)
        The length from ``p[i]`` to ``q[i]``, metres.

    Notes
    -----
    The chord ``c`` between the two points is lengthened to the arc
    ``2 R asin(c / 2R)`` of the circle whose radius ``R`` is the ellipsoid's
    normal-section radius of curvature at the chord's midpoint in the chord's
    direction (Euler's formula from the meridional and prime-vertical radii).
    That arc is within 3e-12 (relative) of the WGS84 geodesic from 1 km to
    100 km, 5e-11 at 200 km and 2e-9 at 500 km; below 1 km the rounding of the
    earth-centred coordinates (1e-9 m) dominates. The chord alone would be short
    by ``(s / R)**2 / 24``: 1e-7 at 10 km, 1e-6 at 31 km, 1e-5 at 100 km.

    Examples
    --------
    >>> from pyproj import Geod
    >>> ends = earth_centred([[-3.0, 58.0], [-2.0, 58.5]], "EPSG:4326")
    >>> arc = arc_lengths(ends[:1], ends[1:])[0]
    >>> geodesic = Geod(ellps="WGS84").inv(-3.0, 58.0, -2.0, 58.5)[2]
    >>> bool(abs(arc / geodesic - 1) < 1e-11)
    True
    """
    p = np.asarray(p, dtype=np.float64)
    q = np.asarray(q, dtype=np.float64)
    d = q - p
    chord = np.sqrt(np.einsum("ij,ij->i", d, d))
    x, y, z = (0.5 * (p + q)).T
    rho = np.hypot(x, y)
    polar = (1 - _E2) * rho  # tan(latitude) = z / ((1 - e2) rho)
    hyp = np.hypot(z, polar)
    sin, cos = z / hyp, polar / hyp
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_rho = np.where(rho > 0, 1 / rho, 0.0)
        east = (d[:, 1] * x - d[:, 0] * y) * inv_rho
        north = cos * d[:, 2] - sin * (d[:, 0] * x + d[:, 1] * y) * inv_rho
        north2, east2 = north * north, east * east
        w2 = 1 - _E2 * sin * sin
        # Euler: 1/R = cos2(az) / M + sin2(az) / N; M = a (1 - e2) / w3, N = a / w
        across = north2 + east2
        radius = np.where(
            across > 0,
            _A * across / ((north2 * w2 / (1 - _E2) + east2) * np.sqrt(w2)),
            _A,
        )
    return 2 * radius * np.arcsin(np.minimum(chord / (2 * radius), 1.0))


def metres_per_unit(crs: Any) -> float:
    """Return the length of one unit of a CRS's coordinates, in metres.

    Parameters
    ----------
    crs : pyproj.CRS or CRS-like
        Any CRS.

    Returns
    -------
    float
        For a geographic CRS, :data:`METRES_PER_DEGREE` (a degree of latitude,
        near enough; a degree of longitude is shorter by the cosine of the
        latitude). Otherwise the linear unit of the first axis in metres
        (0.3048 for feet), or 1 when the CRS does not say.

    Examples
    --------
    >>> metres_per_unit("EPSG:32630"), metres_per_unit("EPSG:2222")
    (1.0, 0.3048)
    >>> round(metres_per_unit("EPSG:4326"))
    111195
    """
    crs = CRS.from_user_input(crs)
    if crs.is_geographic:
        return METRES_PER_DEGREE
    axes = crs.axis_info
    if not axes or axes[0].unit_conversion_factor is None:
        return 1.0
    return float(axes[0].unit_conversion_factor)


def _points(xy: ArrayLike, name: str) -> NDArray[np.float64]:
    points = np.asarray(xy, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 2:
        raise ValueError(f"{name} must have shape (n, 2); got shape {points.shape}")
    return points


def mesh_earth_centred(mesh: Mesh) -> tuple[NDArray[np.float64], bool]:
    """Return the nodes of a mesh in earth-centred metres, or planar without a CRS.

    Parameters
    ----------
    mesh : Mesh
        Points in a geographic, projected or compound CRS, or planar metres
        when ``mesh.crs`` is None.

    Returns
    -------
    xyz : ndarray of shape (N, 3)
        WGS84 earth-centred coordinates at height 0
        (:func:`~coastmesh.geometry.earth.earth_centred`); for a mesh without a
        CRS, its points with z = 0.
    planar : bool
        True when the mesh has no CRS.

    Raises
    ------
    ValueError
        If ``mesh.crs`` is neither geographic nor projected, or a node has no
        position on the Earth.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, "EPSG:4326")
    >>> xyz, planar = mesh_earth_centred(m)
    >>> xyz[0].tolist(), planar
    ([6378137.0, 0.0, 0.0], False)
    """
    points = mesh.points
    if mesh.crs is None:
        return np.column_stack([points, np.zeros(len(points))]), True
    return earth_centred(points, mesh.crs, name="mesh.points"), False


def densified(
    domain: Domain, geometries: list[shapely.Geometry], crs: CRS | str
) -> NDArray[np.object_]:
    """Return geometries of the domain in ``crs``, densified first.

    Vertices go in every 1/4000 of the domain's extent, so that straight
    edges in the domain's CRS (a meridian, a loxodrome) keep their shape.
    """
    b = domain.polygon.bounds
    step = max(b[2] - b[0], b[3] - b[1]) / 4000
    # reproject takes and returns any geometry or array of them
    out: NDArray[np.object_] = reproject(
        shapely.segmentize(np.array(geometries, dtype=object), step),
        domain.crs,
        crs,
    )
    return out
