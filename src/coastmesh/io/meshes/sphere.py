"""Meshes on the sphere: lon/lat and unit vectors, antimeridian crossings, a check.

A global mesh is a :class:`~coastmesh.types.Mesh` in a geographic CRS (points are
longitude, latitude in degrees, longitude in [-180, 180)) whose triangles run
counter-clockwise seen from outside the sphere. Each triangle is read on the
sphere: its corners are the unit vectors of its nodes and its edges the shorter
great-circle arcs between them (the reading UGRID settles on, ugrid-conventions
issue #40). The triangles that cross the antimeridian look long in the lon/lat
plane (a longitude span over 180 degrees) and run clockwise there, which is how
ADCIRC finds them (``CAL_ELXV_SPCOOR`` in ``mesh.F``: a negative Jacobian).

The writers ask :func:`on_sphere` which meshes need these conventions: those in a
geographic CRS with at least one crossing triangle. Every other mesh is written
exactly as before. :func:`sphere_boundary_rings` orders the boundary of such a
mesh with the domain on the left, measured on the sphere, and
:func:`check_on_sphere` rebuilds every triangle on the sphere to check a mesh
that was written and read back.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError
from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import lonlat_to_xyz, wrap_longitude
from coastmesh.types import Mesh
from coastmesh.types.topology import (
    BoundaryRing,
    BoundaryString,
    boundary_rings,
    rings_to_strings,
)

__all__ = [
    "SphereCheck",
    "check_on_sphere",
    "crossing_triangles",
    "is_geographic",
    "misdrawn_triangles",
    "on_sphere",
    "pole_triangles",
    "solid_angles",
    "sphere_boundary_rings",
    "sphere_boundary_strings",
]

_FULL = 4 * np.pi  # steradians of the whole sphere


def is_geographic(mesh: Mesh) -> bool:
    """Whether the mesh's points are longitude, latitude (a geographic CRS).

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, "EPSG:4326")
    >>> is_geographic(m), is_geographic(Mesh(m.points, m.triangles, [], [], 1, None))
    (True, False)
    """
    return mesh.crs is not None and bool(mesh.crs.is_geographic)


def crossing_triangles(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.bool_]:
    """Which triangles cross the antimeridian (longitude span over 180 degrees).

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Longitude, latitude in degrees.
    triangles : ndarray of shape (M, 3)
        Node indices.

    Returns
    -------
    ndarray of bool, shape (M,)
        Also true for the triangles around a pole, whose nodes spread over
        more than half the longitudes.

    Examples
    --------
    >>> points = np.array([[179.0, 0.0], [-179.0, 0.0], [179.5, 1.0], [178.0, 1.0]])
    >>> crossing_triangles(points, np.array([[0, 1, 2], [0, 2, 3]])).tolist()
    [True, False]
    """
    if len(triangles) == 0:
        return np.zeros(0, dtype=bool)
    lon = points[:, 0][triangles]
    return lon.max(axis=1) - lon.min(axis=1) > 180


def misdrawn_triangles(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.bool_]:
    """Which triangles the lon/lat plane does not draw as they are on the sphere.

    Those across the antimeridian (:func:`crossing_triangles`), and those with a
    node at a pole (latitude +-90, whose longitude says nothing): which way they
    run, and their shape, are read on the sphere only.

    Examples
    --------
    >>> points = np.array([[10.0, 89.0], [20.0, 89.0], [50.0, 90.0], [15.0, 88.0]])
    >>> misdrawn_triangles(points, np.array([[0, 1, 2], [0, 3, 1]])).tolist()
    [True, False]
    """
    at_pole = (np.abs(points[:, 1]) == 90)[triangles].any(axis=1)
    return crossing_triangles(points, triangles) | at_pole


def on_sphere(mesh: Mesh) -> bool:
    """Whether a mesh needs the conventions of global meshes when written.

    True for a mesh in a geographic CRS with a triangle that crosses the
    antimeridian (:func:`crossing_triangles`); the writers handle every other
    mesh as before, in the plane.

    Examples
    --------
    >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1]], [[0, 1, 2]], [], [], 1,
    ...          "EPSG:4326")
    >>> on_sphere(m), on_sphere(Mesh(m.points, m.triangles, [], [], 1, None))
    (True, False)
    """
    return is_geographic(mesh) and bool(
        crossing_triangles(mesh.points, mesh.triangles).any()
    )


def solid_angles(
    xyz: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Return the signed area of each triangle on the unit sphere, in steradians.

    Van Oosterom and Strackee's formula, ``tan(A / 2) = a . (b x c) / (1 + a . b +
    b . c + c . a)``: positive for a triangle counter-clockwise seen from outside.

    Parameters
    ----------
    xyz : ndarray of shape (N, 3)
        Unit vectors of the nodes.
    triangles : ndarray of shape (M, 3)
        Node indices.

    Returns
    -------
    ndarray of shape (M,)

    Examples
    --------
    >>> octant = lonlat_to_xyz([[0, 0], [90, 0], [0, 90]])
    >>> round(float(solid_angles(octant, np.array([[0, 1, 2]]))[0] / np.pi), 12)
    0.5
    """
    a, b, c = (xyz[triangles[:, k]] for k in range(3))
    triple = np.einsum("ij,ij->i", a, np.cross(b, c))
    dots = np.einsum("ij,ij->i", a, b) + np.einsum("ij,ij->i", b, c)
    dots += np.einsum("ij,ij->i", c, a)
    return 2 * np.arctan2(triple, 1 + dots)


def pole_triangles(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.int8]:
    """Which pole each triangle holds inside: 1 north, -1 south, 0 none.

    A counter-clockwise triangle around the North Pole turns once eastwards
    (its longitude steps add up to +360 degrees), one around the South Pole once
    westwards. A triangle with a node at a pole does not hold it inside.

    Examples
    --------
    >>> points = np.array([[0, 89], [120, 89], [-120, 89], [0, -89], [-120, -89],
    ...                    [120, -89], [10, 0]])
    >>> pole_triangles(points, np.array([[0, 1, 2], [3, 4, 5], [0, 6, 1]])).tolist()
    [1, -1, 0]
    """
    lon = points[:, 0][triangles]
    steps = np.diff(np.concatenate([lon, lon[:, :1]], axis=1), axis=1)
    turns = np.rint(wrap_longitude(steps).sum(axis=1) / 360).astype(np.int8)
    at_pole = (np.abs(points[:, 1]) == 90)[triangles].any(axis=1)
    return np.where(at_pole, 0, turns).astype(np.int8)


@dataclass(frozen=True, slots=True)
class SphereCheck:
    """Every triangle of a lon/lat mesh rebuilt on the sphere.

    Attributes
    ----------
    triangles : int
        Number of triangles.
    clockwise : int
        Triangles that do not run counter-clockwise seen from outside the sphere
        (zero or negative area); 0 for a well-formed mesh.
    area : float
        Sum of the triangle areas, square metres on the sphere of ``radius``.
    largest : float
        Area of the largest triangle, square metres. A triangle read across the
        wrong side of the sphere (a crossing triangle unwrapped the wrong way)
        shows here as a huge area.
    crossing : int
        Triangles that cross the antimeridian (:func:`crossing_triangles`).
    polar : int
        Triangles with a pole inside (:func:`pole_triangles`).
    radius : float
        The sphere's radius, metres.
    """

    triangles: int
    clockwise: int
    area: float
    largest: float
    crossing: int
    polar: int
    radius: float

    @property
    def ok(self) -> bool:
        """True if every triangle runs counter-clockwise seen from outside."""
        return self.clockwise == 0


def check_on_sphere(mesh: Mesh, *, radius: float = EARTH_RADIUS) -> SphereCheck:
    """Rebuild every triangle of a lon/lat mesh on the sphere and measure it.

    Parameters
    ----------
    mesh : Mesh
        Points are longitude, latitude in degrees (any longitude range): a mesh
        in a geographic CRS, or with no CRS (a file that stores none).
    radius : float, default :data:`~coastmesh.geometry.EARTH_RADIUS`
        The sphere the areas are measured on, metres.

    Returns
    -------
    SphereCheck

    Raises
    ------
    FormatError
        If the mesh's CRS is projected (its points are not lon/lat) or a
        latitude is outside [-90, 90].

    Examples
    --------
    >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1], [-179.5, 1]],
    ...          [[0, 1, 2], [1, 3, 2]], [], [], 1, "EPSG:4326")
    >>> check = check_on_sphere(m)
    >>> check.ok, check.crossing, round(check.area / 1e9, 3)
    (True, 2, 18.546)
    >>> check_on_sphere(Mesh(m.points, m.triangles[:, ::-1], [], [], 1, None)).ok
    False
    """
    if mesh.crs is not None and not mesh.crs.is_geographic:
        raise FormatError(
            f"check_on_sphere needs longitude, latitude; the mesh's CRS "
            f"{mesh.crs.name!r} is not geographic"
        )
    lat = mesh.points[:, 1]
    if len(lat) and np.abs(lat).max() > 90:
        raise FormatError(
            f"check_on_sphere: latitude {lat[np.argmax(np.abs(lat))]} is outside "
            "[-90, 90]"
        )
    area = solid_angles(lonlat_to_xyz(mesh.points), mesh.triangles) * radius**2
    return SphereCheck(
        triangles=len(mesh.triangles),
        clockwise=int((area <= 0).sum()),
        area=float(np.abs(area).sum()),
        largest=float(np.abs(area).max(initial=0.0)),
        crossing=int(crossing_triangles(mesh.points, mesh.triangles).sum()),
        polar=int(np.count_nonzero(pole_triangles(mesh.points, mesh.triangles))),
        radius=float(radius),
    )


def sphere_boundary_rings(mesh: Mesh) -> list[BoundaryRing]:
    """Order the boundary edges of a lon/lat mesh into rings, on the sphere.

    As :func:`~coastmesh.types.topology.boundary_rings`, which works in the
    plane, with the two things it measures taken on the sphere: which way the
    triangles run (the domain is on the left of each ring, seen from outside)
    and which ring is the exterior, the one that cuts off the largest area on
    its right (the land around a regional domain; the largest continent of a
    global ocean).

    Parameters
    ----------
    mesh : Mesh
        Points are longitude, latitude in degrees; triangles run
        counter-clockwise seen from outside the sphere.

    Returns
    -------
    list of BoundaryRing
        The exterior first, then the other rings by their smallest node index.

    Raises
    ------
    FormatError
        As :func:`~coastmesh.types.topology.boundary_rings`.

    Examples
    --------
    >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1], [-179.5, 1]],
    ...          [[0, 1, 2], [1, 3, 2]], [[0, 1], [1, 3], [3, 2], [2, 0]],
    ...          [1, 1, 1, 1], 1, "EPSG:4326")
    >>> [(r.nodes.tolist(), r.exterior) for r in sphere_boundary_rings(m)]
    [([0, 1, 3, 2], True)]
    """
    xyz = lonlat_to_xyz(mesh.points)
    rings = boundary_rings(_tangent_proxy(mesh, xyz))
    if len(rings) < 2:
        return rings
    outer = int(np.argmax(_areas_on_the_right(xyz, [ring.nodes for ring in rings])))
    others = sorted(
        (r for k, r in enumerate(rings) if k != outer), key=lambda r: int(r.nodes.min())
    )
    return [
        BoundaryRing(r.nodes, r.ids, k == 0)
        for k, r in enumerate([rings[outer], *others])
    ]


def sphere_boundary_strings(mesh: Mesh) -> list[BoundaryString]:
    """Split the rings of :func:`sphere_boundary_rings` into runs of one id.

    As :func:`~coastmesh.types.topology.boundary_strings`, on the sphere.

    Examples
    --------
    >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1], [-179.5, 1]],
    ...          [[0, 1, 2], [1, 3, 2]], [[0, 1], [1, 3], [3, 2], [2, 0]],
    ...          [2, 1, 1, 1], 1, "EPSG:4326")
    >>> [(s.physical_id, s.nodes.tolist()) for s in sphere_boundary_strings(m)]
    [(2, [0, 1]), (1, [1, 3, 2, 0])]
    """
    return rings_to_strings(sphere_boundary_rings(mesh))


def _tangent_proxy(mesh: Mesh, xyz: NDArray[np.float64]) -> Mesh:
    """Return the mesh with its nodes in the tangent plane at its first triangle.

    :func:`~coastmesh.types.topology.boundary_rings` reads which way the
    triangles run from the first one, in the plane: in the tangent plane at that
    triangle (east, north), it runs as it does seen from outside the sphere.
    """
    if len(mesh.triangles) == 0:
        return mesh
    centre = xyz[mesh.triangles[0]].sum(axis=0)
    centre /= np.linalg.norm(centre)
    up = [1.0, 0.0, 0.0] if abs(centre[2]) > 0.9 else [0.0, 0.0, 1.0]
    east = np.cross(up, centre)  # (east, north, centre) is right-handed
    east /= np.linalg.norm(east)
    north = np.cross(centre, east)
    plane = np.column_stack([xyz @ east, xyz @ north])
    return Mesh(plane, mesh.triangles, mesh.boundary_edges, mesh.boundary_ids, 1, None)


def _areas_on_the_right(
    xyz: NDArray[np.float64], rings: list[NDArray[np.int64]]
) -> NDArray[np.float64]:
    """Area cut off on the right of each closed ring of nodes, steradians.

    The fan of triangles from a ring's first node adds up to the area on the
    left of the ring, modulo the whole sphere.
    """
    sizes = np.array([len(nodes) for nodes in rings])
    fans = np.maximum(sizes - 2, 0)
    ring = np.repeat(np.arange(len(rings)), fans)
    flat = np.concatenate(rings)
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    step = np.arange(int(fans.sum())) - np.repeat(np.cumsum(fans) - fans, fans) + 1
    first = flat[start[ring]]
    fan = np.column_stack(
        [first, flat[start[ring] + step], flat[start[ring] + step + 1]]
    )
    solid = np.bincount(ring, solid_angles(xyz, fan), minlength=len(rings))
    left = solid.astype(np.float64, copy=False) % _FULL
    return _FULL - left
