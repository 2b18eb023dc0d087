"""Triangles and edges measured on the Earth: the kernels behind the quality report.

Every length is measured on the WGS84 ellipsoid, never in degrees: the nodes go to
earth-centred coordinates (EPSG:4978, :func:`mesh_earth_centred`) and each side is
the chord between its two nodes, turned into the arc of the ellipsoid's local
curvature (:func:`~coastmesh.geometry.earth.arc_lengths`). A mesh without a CRS is
taken as planar, in metres. Angles, radii and areas then follow from the three
sides of each triangle (:func:`triangle_measures`); :func:`edge_measures` measures
every edge once, and :class:`Place` says where an element or node is.
:mod:`~coastmesh.meshing.quality.mesh_quality`,
:mod:`~coastmesh.meshing.quality.time_step` and
:mod:`~coastmesh.meshing.quality.corners` build on these.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.geometry.earth import arc_lengths, reproject_points
from coastmesh.geometry.sphere import lonlat_to_xyz, xyz_to_lonlat
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import unique_edges

__all__ = [
    "TRIANGLE_MEASURES",
    "Place",
    "edge_measures",
    "lengths",
    "places",
    "triangle_measures",
]

#: What :func:`triangle_measures` can return, by key.
TRIANGLE_MEASURES = (
    "min_angle",
    "radius_ratio",
    "area",
    "r_in",
    "mean_edge",
    "angles",
)

_BLOCK = 1 << 16  # triangles or edges per block: bounds the temporary memory


def lengths(
    p: NDArray[np.float64], q: NDArray[np.float64], planar: bool
) -> NDArray[np.float64]:
    """Return the lengths (metres) from ``p`` to ``q``, both (k, 3): arcs or chords.

    Arcs on the ellipsoid (:func:`~coastmesh.geometry.earth.arc_lengths`) unless
    ``planar``, then straight distances.

    Examples
    --------
    >>> lengths(np.zeros((1, 3)), np.array([[3.0, 4.0, 0.0]]), True).tolist()
    [5.0]
    """
    if not planar:
        return arc_lengths(p, q)
    d = q - p
    length: NDArray[np.float64] = np.sqrt(np.einsum("ij,ij->i", d, d))  # einsum: Any
    return length


def triangle_measures(
    xyz: NDArray[np.float64],
    triangles: NDArray[np.int64],
    planar: bool,
    keys: tuple[str, ...] = ("min_angle", "radius_ratio", "area"),
) -> dict[str, NDArray[np.float64]]:
    """Measure each triangle from its three side lengths, in blocks.

    Parameters
    ----------
    xyz : ndarray of shape (N, 3)
        The nodes, from :func:`mesh_earth_centred`.
    triangles : ndarray of shape (M, 3)
        Node indices.
    planar : bool
        Whether the sides are straight distances rather than ellipsoid arcs.
    keys : tuple of str
        What to return, from :data:`TRIANGLE_MEASURES`.

    Returns
    -------
    dict of str to ndarray
        ``"min_angle"`` (M,) degrees; ``"radius_ratio"`` (M,) ``2 r_in / r_circ``;
        ``"area"`` (M,) square metres; ``"r_in"`` (M,) the inscribed radius
        ``2 A / P``, metres; ``"mean_edge"`` (M,) the mean side length ``P / 3``,
        metres; ``"angles"`` (M, 3) the angle at each node of the triangle,
        degrees, summing to 180.

    Notes
    -----
    With the sides sorted ``a >= b >= c``, the minimum angle (opposite ``c``) is
    the law of cosines in half-angle form, ``1 - cos C = (c - (a - b))
    (c + (a - b)) / (2ab)``, accurate for slivers; the area is Heron's formula
    in Kahan's stable form, ``A = sqrt((a + (b + c)) (c - (a - b)) (c + (a - b))
    (a + (b - c))) / 4``; ``2 r_in / r_circ = (c - (a - b)) (c + (a - b))
    (a + (b - c)) / (abc)``; and ``r_in = sqrt((c - (a - b)) (c + (a - b))
    (a + (b - c)) / (a + b + c)) / 2``. The angle at a node, opposite side ``x``
    between sides ``y`` and ``z``, is ``2 atan2(sqrt((x - y + z) (x + y - z)),
    sqrt((x + y + z) (y + z - x)))``, well conditioned from 0 to 180 degrees.

    Examples
    --------
    >>> xyz = np.array([[0.0, 0, 0], [4, 0, 0], [0, 3, 0]])
    >>> q = triangle_measures(xyz, np.array([[0, 1, 2]]), True,
    ...                       ("r_in", "mean_edge", "angles"))
    >>> q["r_in"].tolist(), q["mean_edge"].tolist(), np.round(q["angles"], 4).tolist()
    ([1.0], [4.0], [[90.0, 36.8699, 53.1301]])
    """
    unknown = sorted(set(keys) - set(TRIANGLE_MEASURES))
    if unknown:
        raise ValueError(
            f"keys {unknown} unknown: expected some of {TRIANGLE_MEASURES}"
        )
    m = len(triangles)
    out = {key: np.empty((m, 3) if key == "angles" else m) for key in keys}
    for start in range(0, m, _BLOCK):
        block = triangles[start : start + _BLOCK]
        p = [xyz[block[:, k]] for k in range(3)]
        sides = np.column_stack(
            [lengths(p[(k + 1) % 3], p[(k + 2) % 3], planar) for k in range(3)]
        )  # side k is opposite node k
        part = slice(start, start + len(block))
        if "angles" in out:
            out["angles"][part] = _node_angles(sides)
        _shape_measures(np.sort(sides, axis=1), out, part)
    return out


def _shape_measures(
    sides: NDArray[np.float64], out: dict[str, NDArray[np.float64]], part: slice
) -> None:
    """Fill ``out[key][part]`` from the sides, sorted ``c <= b <= a`` in each row."""
    c, b, a = sides.T
    f1 = np.maximum(c - (a - b), 0.0)
    f2 = c + (a - b)
    f3 = a + (b - c)
    perimeter = a + (b + c)
    with np.errstate(divide="ignore", invalid="ignore"):
        if "min_angle" in out:
            half = np.where(a * b > 0, f1 * f2 / (4 * a * b), 0.0)
            out["min_angle"][part] = np.degrees(
                2 * np.arcsin(np.sqrt(np.minimum(half, 1)))
            )
        if "radius_ratio" in out:
            out["radius_ratio"][part] = np.where(
                a * b * c > 0, f1 * f2 * f3 / (a * b * c), 0.0
            )
        if "r_in" in out:
            out["r_in"][part] = np.where(
                perimeter > 0, 0.5 * np.sqrt(f1 * f2 * f3 / perimeter), 0.0
            )
    if "area" in out:
        out["area"][part] = 0.25 * np.sqrt(perimeter * f1 * f2 * f3)
    if "mean_edge" in out:
        out["mean_edge"][part] = perimeter / 3


def _node_angles(sides: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the angle (degrees) at each node, from the sides opposite (k, 3)."""
    angles = np.empty_like(sides)
    for k in range(3):
        x, y, z = sides[:, k], sides[:, (k + 1) % 3], sides[:, (k + 2) % 3]
        top = np.maximum((x - y + z) * (x + y - z), 0.0)
        bottom = np.maximum((x + y + z) * (y + z - x), 0.0)
        angles[:, k] = np.degrees(2 * np.arctan2(np.sqrt(top), np.sqrt(bottom)))
    return angles


def edge_measures(
    xyz: NDArray[np.float64],
    mesh: Mesh,
    planar: bool,
    node_size: NDArray[np.float64] | None,
) -> dict[str, NDArray[Any]]:
    """Measure every edge once (:func:`~coastmesh.types.topology.unique_edges`).

    Returns ``"edges"`` (K, 2), ``"triangles"`` (K,), ``"length"`` (K,) metres
    and, with ``node_size``, ``"ratio"`` (K,): see
    :func:`~coastmesh.meshing.quality.mesh_quality.edge_quality`.
    """
    edges, shared = unique_edges(mesh.triangles, len(mesh.points))
    length = np.empty(len(edges))
    for start in range(0, len(edges), _BLOCK):
        lo, hi = edges[start : start + _BLOCK].T
        length[start : start + len(lo)] = lengths(xyz[lo], xyz[hi], planar)
    out = {"edges": edges, "triangles": shared, "length": length}
    if node_size is not None:
        target = node_size[edges[:, 0]]
        target += node_size[edges[:, 1]]
        target *= 0.5
        out["ratio"] = np.divide(length, target, out=target)
    return out


@dataclass(frozen=True, slots=True)
class Place(Report):
    """Where an element or a node of a mesh is.

    Attributes
    ----------
    index : int
        The triangle or node index.
    x, y : float
        Its position (a triangle's centroid) in the mesh CRS.
    lon, lat : float or None
        The same on WGS84, degrees; None for a mesh without a CRS.
    """

    index: int
    x: float
    y: float
    lon: float | None
    lat: float | None

    def summary(self) -> str:
        """Return ``"(lon, lat)"`` in degrees, or ``"(x, y)"`` without a CRS.

        Examples
        --------
        >>> Place(3, 500.0, 20.0, -3.1, 58.71234).summary()
        '(-3.1000, 58.7123)'
        """
        if self.lon is None or self.lat is None:
            return f"({self.x:g}, {self.y:g})"
        return f"({self.lon:.4f}, {self.lat:.4f})"


def places(mesh: Mesh, index: NDArray[np.int64], *, triangles: bool) -> list[Place]:
    """Return where the triangles (their centroids) or nodes ``index`` are.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    index : ndarray of int of shape (k,)
        Triangle indices if ``triangles``, else node indices.
    triangles : bool
        Whether ``index`` holds triangles.

    Returns
    -------
    list of Place
        In the order of ``index``.

    Examples
    --------
    >>> m = Mesh([[0, 0], [3, 0], [0, 3]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, None)
    >>> places(m, np.array([0]), triangles=True)[0].summary()
    '(1, 1)'
    """
    index = np.asarray(index, dtype=np.int64)
    if triangles and mesh.crs is not None and CRS(mesh.crs).is_geographic:
        # the centroid on the sphere: a mean of longitudes is wrong across
        # the antimeridian (179 and -179 would give 0)
        corners = lonlat_to_xyz(mesh.points[mesh.triangles[index]].reshape(-1, 2))
        xy = xyz_to_lonlat(corners.reshape(-1, 3, 3).mean(axis=1))
    elif triangles:
        xy = mesh.points[mesh.triangles[index]].mean(axis=1)
    else:
        xy = mesh.points[index]
    lonlat = (
        None
        if mesh.crs is None or len(index) == 0
        else reproject_points(xy, mesh.crs, "EPSG:4326")
    )
    return [
        Place(
            index=int(i),
            x=float(xy[k, 0]),
            y=float(xy[k, 1]),
            lon=None if lonlat is None else float(lonlat[k, 0]),
            lat=None if lonlat is None else float(lonlat[k, 1]),
        )
        for k, i in enumerate(index)
    ]
