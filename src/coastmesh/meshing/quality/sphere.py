"""A global mesh checked on the sphere: angles, orientation, overlaps, long sides.

A global mesh holds longitude and latitude (EPSG:4326, longitudes wrapping at
+-180); a triangle is read on the sphere, its corners the unit vectors of its
nodes (:func:`~coastmesh.geometry.sphere.lonlat_to_xyz`) and its sides the
shorter great-circle arcs between them, so a triangle across the antimeridian
is measured as it is. :func:`sphere_quality` checks what a tidal model needs of
such a mesh (issue 33's target: the 1st-percentile minimum angle at least 30
degrees, and no element inverted or duplicated across the antimeridian) and
returns a :class:`SphereQuality`:

* the spherical angles of every triangle (between the great-circle arcs at each
  corner) and the spherical area (their excess over 180 degrees);
* the triangles whose orientation seen from outside the sphere, the sign of
  ``(b - a) x (c - a) . (a + b + c)``, disagrees with the majority's;
* distinct nodes at one place on the sphere (longitude -180 and 180), the same
  three nodes twice, an edge of more than two triangles, and an edge whose two
  triangles lie on the same side of it (a fold): the ways a triangle is
  duplicated or overlaps another, with coincident nodes taken as one;
* the triangles with a side longer than a few degrees of arc, which is what a
  wrong wrap at the antimeridian makes of a triangle.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import lonlat_to_xyz, xyz_to_lonlat
from coastmesh.meshing.quality.measure import Place
from coastmesh.types import Mesh, Report

__all__ = [
    "MIN_ANGLE_TARGET",
    "SAME_NODE",
    "SPAN_LIMIT",
    "SphereQuality",
    "sphere_quality",
    "sphere_triangle_measures",
]

#: The 1st-percentile minimum angle (degrees) a global mesh must reach.
MIN_ANGLE_TARGET = 30.0
#: A side longer than this (degrees of arc) is flagged as spanning too far.
SPAN_LIMIT = 10.0
#: Nodes closer than this (radians; 6 mm on the Earth) are one node.
SAME_NODE = 1e-9
#: Flagged triangles listed in the report with their places; the rest are counted.
MAX_LISTED = 10

_BLOCK = 1 << 16  # triangles per block: bounds the temporary memory
_ALONG = np.array([0.48, 0.6, 0.64])  # a unit vector off every axis plane


@dataclass(frozen=True, slots=True)
class SphereQuality(Report):
    """What :func:`sphere_quality` found in a lon/lat mesh, on the sphere.

    Attributes
    ----------
    triangles : int
        Number of triangles.
    min_angle, min_angle_p1 : float
        The smallest spherical angle of any triangle, and the 1st percentile of
        the triangles' smallest angles, degrees.
    below_30 : int
        Triangles whose smallest angle is below 30 degrees.
    inverted : int
        Triangles whose orientation seen from outside the sphere disagrees with
        the majority's, or is nil (three nodes on one great circle, or two at
        one place).
    coincident_nodes : int
        Nodes at the place of another node (within :data:`SAME_NODE`): a seam
        of nodes doubled at the antimeridian.
    duplicated : int
        Triangles whose three nodes (coincident nodes taken as one) are those of
        an earlier triangle.
    overused_edges : int
        Edges of more than two triangles.
    folded_edges : int
        Edges of two triangles that lie on the same side of them: the
        triangles overlap.
    spanning : int
        Triangles with a side longer than ``span_limit``.
    max_arc : float
        The longest side of any triangle, degrees of arc.
    span_limit : float
        The longest side allowed, degrees of arc.
    area : float
        Sum of the triangles' spherical areas, square metres on the sphere of
        radius :data:`~coastmesh.geometry.earth.EARTH_RADIUS`.
    worst : Place or None
        The triangle with the smallest angle (its centroid on the sphere).
    flagged : tuple of Place
        The first :data:`MAX_LISTED` triangles that are inverted, duplicated,
        at an overused or folded edge, or spanning, by index.
    """

    triangles: int
    min_angle: float
    min_angle_p1: float
    below_30: int
    inverted: int
    coincident_nodes: int
    duplicated: int
    overused_edges: int
    folded_edges: int
    spanning: int
    max_arc: float
    span_limit: float
    area: float
    worst: Place | None = None
    flagged: tuple[Place, ...] = field(default=(), compare=False)

    @property
    def ok(self) -> bool:
        """Whether the mesh meets the target: p01 angle >= 30 deg, nothing flagged.

        Nothing inverted, coincident, duplicated, overused, folded or spanning.
        """
        bad = (
            self.inverted,
            self.coincident_nodes,
            self.duplicated,
            self.overused_edges,
            self.folded_edges,
            self.spanning,
        )
        return self.min_angle_p1 >= MIN_ANGLE_TARGET and not any(bad)

    def summary(self) -> str:
        """Return a one-line summary.

        Examples
        --------
        >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1], [-179.5, 1]],
        ...          [[0, 1, 2], [1, 3, 2]], [], [], 1, "EPSG:4326")
        >>> print(sphere_quality(m).summary())
        on the sphere: 2 triangles, min angle 29.74 deg (p1 29.78, 1 below 30), \
0 inverted, 0 coincident nodes, 0 duplicated, 0 overused and 0 folded edges, \
0 spanning over 10 deg (longest side 2.00 deg), area 18,546 km2: target missed
        """
        return (
            f"on the sphere: {self.triangles:,} triangles, min angle "
            f"{self.min_angle:.2f} deg (p1 {self.min_angle_p1:.2f}, "
            f"{self.below_30:,} below 30), {self.inverted:,} inverted, "
            f"{self.coincident_nodes:,} coincident nodes, {self.duplicated:,} "
            f"duplicated, {self.overused_edges:,} overused and "
            f"{self.folded_edges:,} folded edges, {self.spanning:,} spanning over "
            f"{self.span_limit:g} deg (longest side {self.max_arc:.2f} deg), area "
            f"{self.area / 1e6:,.0f} km2: target {'met' if self.ok else 'missed'}"
        )


def sphere_triangle_measures(
    xyz: NDArray[np.float64], triangles: NDArray[np.int64]
) -> dict[str, NDArray[np.float64]]:
    """Measure each triangle on the unit sphere, in blocks.

    Parameters
    ----------
    xyz : ndarray of shape (N, 3)
        Unit vectors of the nodes (:func:`~coastmesh.geometry.sphere.lonlat_to_xyz`).
    triangles : ndarray of shape (M, 3)
        Node indices.

    Returns
    -------
    dict of str to ndarray of shape (M,)
        ``"orientation"``: ``(b - a) x (c - a) . (a + b + c) / 3``, the volume
        ``a . (b x c)`` of the three unit vectors, positive for a triangle
        counter-clockwise seen from outside; ``"min_angle"``: the smallest
        spherical angle, degrees; ``"max_arc"``: the longest side, degrees of
        arc; ``"area"``: the spherical excess, steradians.

    Notes
    -----
    The angle at corner ``p``, between the arcs to ``q`` and ``r``, is that
    between the planes of the two great circles: ``atan2(a . (b x c),
    (p x (q - p)) . (p x (r - p)))``, signed as the orientation. Every product
    is taken of the sides ``q - p``, so the angles keep their precision on
    triangles of metres. The area is the sum of the three angles' magnitudes
    less pi (Girard's theorem).

    Examples
    --------
    >>> octant = lonlat_to_xyz([[0, 0], [90, 0], [0, 90]])
    >>> q = sphere_triangle_measures(octant, np.array([[0, 1, 2]]))
    >>> [round(float(q[k][0]), 9) for k in ("min_angle", "max_arc")]
    [90.0, 90.0]
    >>> round(float(q["area"][0] / np.pi), 12), float(q["orientation"][0]) > 0
    (0.5, True)
    """
    m = len(triangles)
    out = {key: np.empty(m) for key in ("orientation", "min_angle", "max_arc", "area")}
    columns = np.ascontiguousarray(np.asarray(xyz, dtype=np.float64).T)  # (3, N)
    for start in range(0, m, _BLOCK):
        block = triangles[start : start + _BLOCK]
        p = [columns[:, block[:, k]] for k in range(3)]
        sides = [p[(k + 1) % 3] - p[k] for k in range(3)]  # corner k to k + 1
        volume = _dot(_cross(sides[0], -sides[2]), p[0] + p[1] + p[2]) / 3
        angles = np.empty((3, len(block)))
        for k in range(3):
            ahead = _cross(p[k], sides[k])
            behind = _cross(p[k], -sides[(k + 2) % 3])
            angles[k] = np.arctan2(volume, _dot(ahead, behind))
        np.abs(angles, out=angles)
        chord = np.sqrt(np.max([_dot(s, s) for s in sides], axis=0))
        part = slice(start, start + len(block))
        out["orientation"][part] = volume
        out["min_angle"][part] = np.degrees(angles.min(axis=0))
        out["max_arc"][part] = np.degrees(2 * np.arcsin(np.minimum(chord / 2, 1.0)))
        out["area"][part] = angles.sum(axis=0) - np.pi
    return out


def _cross(u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the cross products of vectors given as rows of components (3, k)."""
    return np.stack(
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    )


def _dot(u: NDArray[np.float64], v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the dot products of vectors given as rows of components (3, k)."""
    # numpy's stub: Any (a row taken by an int index)
    dot: NDArray[np.float64] = u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
    return dot


def sphere_quality(mesh: Mesh, *, span_limit: float = SPAN_LIMIT) -> SphereQuality:
    """Check a global lon/lat mesh on the sphere (see the module notes).

    Parameters
    ----------
    mesh : Mesh
        Points are longitude, latitude in degrees (any longitude range): a mesh
        in a geographic CRS, or with no CRS; at least one triangle.
    span_limit : float, default :data:`SPAN_LIMIT`
        The longest side allowed, degrees of arc (> 0).

    Returns
    -------
    SphereQuality

    Raises
    ------
    ValueError
        If the mesh's CRS is projected, a latitude lies outside [-90, 90], the
        mesh has no triangles, or ``span_limit`` is not > 0.

    Notes
    -----
    Angles are spherical angles, not those of the flat triangle between the
    three unit vectors (they differ by a third of the spherical excess: 3e-5
    degrees on a triangle of 10 km). Coincident nodes are found by sorting the
    unit vectors along one direction, and taken as one before the topology is checked,
    so that a triangle doubled across the antimeridian on copied nodes counts
    as duplicated. An edge's two triangles are folded when the nodes opposite
    it lie on the same side of its great circle. Takes about 1 s per million
    triangles.

    Examples
    --------
    >>> m = Mesh([[179, 0], [-179, 0], [179.5, 1], [-179.5, 1]],
    ...          [[0, 1, 2], [1, 3, 2]], [], [], 1, "EPSG:4326")
    >>> q = sphere_quality(m)
    >>> q.inverted, q.duplicated, q.folded_edges, round(q.max_arc, 3)
    (0, 0, 0, 2.0)
    >>> flipped = Mesh(m.points, [[0, 1, 2], [1, 2, 3]], [], [], 1, "EPSG:4326")
    >>> q = sphere_quality(flipped)
    >>> q.inverted, q.folded_edges, [p.index for p in q.flagged]
    (1, 0, [1])
    """
    lonlat = _check(mesh, span_limit)
    xyz = lonlat_to_xyz(lonlat)
    measures = sphere_triangle_measures(xyz, mesh.triangles)
    orientation = measures["orientation"]
    majority = 1.0 if (orientation > 0).sum() >= (orientation < 0).sum() else -1.0
    same = _same_nodes(xyz)
    triangles = same[mesh.triangles]
    inverted = orientation * majority <= 0
    inverted |= (triangles == np.roll(triangles, 1, axis=1)).any(axis=1)
    overused, folded, at_fault = _edge_faults(triangles, np.sign(orientation), len(xyz))
    repeats, duplicated = _duplicated(triangles, at_fault | inverted)
    spanning = measures["max_arc"] > span_limit
    flagged = np.flatnonzero(inverted | duplicated | at_fault | spanning)
    angle = measures["min_angle"]
    return SphereQuality(
        triangles=len(triangles),
        min_angle=float(angle.min()),
        min_angle_p1=float(np.percentile(angle, 1)),
        below_30=int((angle < 30).sum()),
        inverted=int(inverted.sum()),
        coincident_nodes=int((same != np.arange(len(same))).sum()),
        duplicated=repeats,
        overused_edges=overused,
        folded_edges=folded,
        spanning=int(spanning.sum()),
        max_arc=float(measures["max_arc"].max()),
        span_limit=float(span_limit),
        area=float(measures["area"].sum()) * EARTH_RADIUS**2,
        worst=_places(xyz, mesh.triangles, np.array([np.argmin(angle)]))[0],
        flagged=tuple(_places(xyz, mesh.triangles, flagged[:MAX_LISTED])),
    )


def _check(mesh: Mesh, span_limit: float) -> NDArray[np.float64]:
    """Return the mesh's lon/lat points, checked (see :func:`sphere_quality`)."""
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    if mesh.crs is not None and not mesh.crs.is_geographic:
        raise ValueError(
            f"sphere_quality needs longitude, latitude; the mesh's CRS "
            f"{mesh.crs.name!r} is not geographic"
        )
    if len(mesh.triangles) == 0:
        raise ValueError("mesh has no triangles: nothing to measure")
    if not span_limit > 0:
        raise ValueError(f"span_limit = {span_limit}: must be > 0 degrees")
    lat = mesh.points[:, 1]
    bad = np.flatnonzero(~(np.abs(lat) <= 90))
    if bad.size:
        raise ValueError(
            f"mesh.points[{bad[0]}] has latitude {lat[bad[0]]}, outside [-90, 90]; "
            f"{bad.size} such points"
        )
    return mesh.points


def _same_nodes(xyz: NDArray[np.float64]) -> NDArray[np.int64]:
    """Return, for each node, the first node at its place (within :data:`SAME_NODE`).

    The nodes are sorted along one direction (one no meridian or parallel
    plane holds); only nodes that near along it are compared.
    """
    same = np.arange(len(xyz))
    along = xyz @ _ALONG
    order = np.argsort(along)
    along = along[order]
    for step in range(1, len(xyz)):
        near = np.flatnonzero(along[step:] - along[:-step] <= SAME_NODE)
        if near.size == 0:
            break
        a, b = order[near], order[near + step]
        d = xyz[a] - xyz[b]
        close = np.einsum("ij,ij->i", d, d) <= SAME_NODE**2
        np.minimum.at(same, np.maximum(a, b)[close], np.minimum(a, b)[close])
    while (same[same] != same).any():  # chains of close pairs: to their root
        same = same[same]
    return same


def _duplicated(
    triangles: NDArray[np.int64], suspects: NDArray[np.bool_]
) -> tuple[int, NDArray[np.bool_]]:
    """Count the triangles with an earlier one's three nodes; flag every copy.

    Only ``suspects`` are compared: a triangle's copy shares each of its edges
    with it, so those edges are of more than two triangles or folded, unless
    the triangle is flat (and so inverted).
    """
    index = np.flatnonzero(suspects)
    nodes = np.sort(triangles[index], axis=1)
    order = np.lexsort(nodes.T[::-1])
    nodes = nodes[order]
    same = (nodes[1:] == nodes[:-1]).all(axis=1)
    copy = np.zeros(len(nodes), dtype=bool)
    copy[1:] |= same
    copy[:-1] |= same
    flagged = np.zeros(len(triangles), dtype=bool)
    flagged[index[order[copy]]] = True
    return int(same.sum()), flagged


def _edge_faults(
    triangles: NDArray[np.int64], sign: NDArray[np.float64], n: int
) -> tuple[int, int, NDArray[np.bool_]]:
    """Count the edges of over two triangles, and the folded ones; flag their triangles.

    Each side of a triangle, as the pair (lower node, higher node), has the
    triangle's third node on its left (+1) or right (-1) on the sphere: the
    triangle's orientation, turned when the side runs from the higher node. An
    edge's two triangles are folded when their third nodes are on the same side.
    """
    m = len(triangles)
    i, j = triangles.ravel(), np.roll(triangles, -1, axis=1).ravel()
    keys = np.minimum(i, j) * n + np.maximum(i, j)
    side = np.repeat(sign, 3) * np.where(i < j, 1.0, -1.0)
    order = np.argsort(keys)
    keys = keys[order]
    starts = np.flatnonzero(np.r_[True, keys[1:] != keys[:-1]])
    count = np.diff(np.r_[starts, len(keys)])
    two = starts[count == 2]
    folded = side[order[two]] * side[order[two + 1]] > 0
    at_fault = np.zeros(m, dtype=bool)
    at_fault[order[np.repeat(count > 2, count)] // 3] = True
    at_fault[order[two[folded]] // 3] = True
    at_fault[order[two[folded] + 1] // 3] = True
    return int((count > 2).sum()), int(folded.sum()), at_fault


def _places(
    xyz: NDArray[np.float64], triangles: NDArray[np.int64], index: NDArray[np.int64]
) -> list[Place]:
    """Return where triangles ``index`` are: their centroids on the sphere."""
    lonlat = xyz_to_lonlat(xyz[triangles[index]].sum(axis=1))
    return [
        Place(int(i), float(lon), float(lat), float(lon), float(lat))
        for i, (lon, lat) in zip(index, lonlat, strict=True)
    ]
