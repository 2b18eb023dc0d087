"""Mesh quality measured on the Earth: angles, radius ratios, edge sizes, valence.

Every length is measured on the WGS84 ellipsoid, never in degrees: the nodes go to
earth-centred coordinates (EPSG:4978) and each side is the chord between its two
nodes, turned into the arc of the ellipsoid's local curvature, which matches the
geodesic to 3e-12 from 1 km to 100 km. Angles, radius ratios and areas then follow from
the three sides of each triangle. A mesh without a CRS is taken as planar, in
metres; the report says so. The report (:class:`QualityReport`) is data, defined
in :mod:`coastmesh.meshing.quality_report`; :func:`coastmesh.io.write_report`
writes it.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.geometry.earth import arc_lengths, earth_centred
from coastmesh.meshing.quality_report import (
    AngleStats,
    EdgeRatioStats,
    QualityReport,
    RatioStats,
    ValenceStats,
)
from coastmesh.meshing.topology import unique_edges
from coastmesh.types import Mesh

# the report types are in coastmesh.meshing.quality_report
__all__ = ["edge_quality", "mesh_earth_centred", "mesh_quality", "triangle_quality"]

logger = logging.getLogger(__name__)

_BLOCK = 1 << 16  # triangles or edges per block: bounds the temporary memory


def triangle_quality(mesh: Mesh) -> dict[str, NDArray[np.float64]]:
    """Measure each triangle on the Earth: minimum angle, radius ratio, area.

    Parameters
    ----------
    mesh : Mesh
        Points in a geographic or projected CRS, or planar metres when
        ``mesh.crs`` is None.

    Returns
    -------
    dict of str to ndarray of shape (M,)
        ``"min_angle"`` in degrees, ``"radius_ratio"`` ``2 r_in / r_circ`` (1 for
        equilateral, 0 for degenerate) and ``"area"`` in square metres.

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        If ``mesh.crs`` is neither geographic nor projected, or a node has no
        position on the Earth.

    Notes
    -----
    The nodes go to WGS84 earth-centred coordinates (EPSG:4978) at height 0
    (:func:`~coastmesh.geometry.earth.earth_centred`). Each side is the chord
    between its nodes lengthened to the arc of the ellipsoid's normal-section
    curvature (:func:`~coastmesh.geometry.earth.arc_lengths`): within 3e-12
    (relative) of the WGS84 geodesic from 1 km to 100 km, where the chord alone
    would be short by ``(s / R)**2 / 24`` (1e-7 at 10 km). A CRS on another datum
    is shifted to WGS84 by pyproj; its height-0 surface then lies up to about
    100 m off WGS84's, which scales lengths (not angles) by up to 2e-5.

    With the sides sorted ``a >= b >= c``, the minimum angle (opposite ``c``) is
    the law of cosines in half-angle form, ``1 - cos C = (c - (a - b))
    (c + (a - b)) / (2ab)``, accurate for slivers; the area is Heron's formula
    in Kahan's stable form, ``A = sqrt((a + (b + c)) (c - (a - b)) (c + (a - b))
    (a + (b - c))) / 4``; and ``2 r_in / r_circ = (c - (a - b)) (c + (a - b))
    (a + (b - c)) / (abc)``. Triangles are processed in blocks, so the memory
    used beyond the three output arrays stays bounded.

    Examples
    --------
    >>> import numpy as np
    >>> m = Mesh([[0, 0], [100, 0], [0, 100]], [[0, 1, 2]],
    ...          [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, None)
    >>> q = triangle_quality(m)
    >>> print(np.round(q["min_angle"], 6), np.round(q["radius_ratio"], 4), q["area"])
    [45.] [0.8284] [5000.]
    """
    xyz, planar = mesh_earth_centred(_check_mesh(mesh))
    return _triangle_measures(xyz, mesh.triangles, planar)


def edge_quality(
    mesh: Mesh, *, size: ArrayLike | None = None
) -> dict[str, NDArray[Any]]:
    """Measure each edge of the mesh once, on the Earth.

    Parameters
    ----------
    mesh : Mesh
        As for :func:`triangle_quality`.
    size : array_like of shape (N,), optional
        Target edge length at each node, metres; default
        ``mesh.point_data["size"]`` if present.

    Returns
    -------
    dict of str to ndarray
        ``"edges"`` (K, 2) node indices, lower first, sorted; ``"triangles"``
        (K,) the number of triangles at each edge (1 on the boundary);
        ``"length"`` (K,) metres (see :func:`triangle_quality`, Notes); and, when
        a size is known, ``"ratio"`` (K,) the length over the mean target size of
        the two nodes.

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        If ``size`` does not hold one finite value > 0 per node, or as for
        :func:`triangle_quality`.

    Examples
    --------
    >>> m = Mesh([[0, 0], [300, 0], [0, 400]], [[0, 1, 2]],
    ...          [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, None)
    >>> q = edge_quality(m, size=[100.0, 100.0, 100.0])
    >>> q["edges"].tolist(), q["length"].tolist(), q["ratio"].tolist()
    ([[0, 1], [0, 2], [1, 2]], [300.0, 400.0, 500.0], [3.0, 4.0, 5.0])
    """
    xyz, planar = mesh_earth_centred(_check_mesh(mesh))
    return _edge_measures(xyz, mesh, planar, _node_size(mesh, size))


def mesh_quality(mesh: Mesh, *, size: ArrayLike | None = None) -> QualityReport:
    """Measure a mesh on the Earth: angles, radius ratios, edge sizes, valence.

    Parameters
    ----------
    mesh : Mesh
        Points in a geographic or projected CRS, or planar metres when
        ``mesh.crs`` is None; at least one triangle.
    size : array_like of shape (N,), optional
        Target edge length at each node, metres; default
        ``mesh.point_data["size"]`` if present. Without either, the report has no
        edge-size block.

    Returns
    -------
    QualityReport

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        If the mesh has no triangles, ``size`` does not hold one finite value
        > 0 per node, ``mesh.crs`` is neither geographic nor projected, or a node
        has no position on the Earth.

    Notes
    -----
    Lengths, angles and ratios as :func:`triangle_quality` computes them. Edges
    are found by sorting their node pairs; an edge in a single triangle is on the
    boundary, and so are its nodes. Triangles with all three nodes on the
    boundary include those with two boundary sides and those bridging a channel
    one element wide. Takes about 1 s and 130 MB per million triangles (the
    mesh itself is 32 MB); triangles and edges are measured in blocks.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 2, 2], 1, None,
    ...          boundary_names={1: "coast", 2: "sea"})
    >>> report = mesh_quality(m)
    >>> report.triangles, round(report.min_angle.min, 9)
    (2, 45.0)
    >>> report.all_boundary_triangles.tolist()
    [0, 1]
    >>> print(report.summary().splitlines()[2])
      boundary edges by id: 1 coast: 2; 2 sea: 2
    """
    started = time.perf_counter()
    _check_mesh(mesh)
    if len(mesh.triangles) == 0:
        raise ValueError("mesh has no triangles: nothing to measure")
    node_size = _node_size(mesh, size)
    xyz, planar = mesh_earth_centred(mesh)
    shape = _triangle_measures(xyz, mesh.triangles, planar, area=False)
    edges = _edge_measures(xyz, mesh, planar, node_size)
    n = len(mesh.points)
    valence = np.bincount(mesh.triangles.ravel(), minlength=n)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[edges["edges"][edges["triangles"] == 1].ravel()] = True
    interior = ~on_boundary & (valence > 0)
    all_boundary = np.flatnonzero(on_boundary[mesh.triangles].all(axis=1))
    ids, counts = np.unique(mesh.boundary_ids, return_counts=True)
    report = QualityReport(
        nodes=n,
        triangles=len(mesh.triangles),
        unused_nodes=int((valence == 0).sum()),
        boundary_edges={int(i): int(c) for i, c in zip(ids, counts, strict=True)},
        boundary_names=dict(mesh.boundary_names),
        boundary_kinds=dict(mesh.boundary_kinds),
        crs=None if mesh.crs is None else mesh.crs.name,
        planar=planar,
        min_angle=AngleStats.from_values(shape["min_angle"]),
        radius_ratio=RatioStats.from_values(shape["radius_ratio"]),
        edge_ratio=(
            EdgeRatioStats.from_values(edges["ratio"]) if "ratio" in edges else None
        ),
        interior_valence=ValenceStats.from_values(valence[interior]),
        boundary_valence=ValenceStats.from_values(valence[on_boundary]),
        all_boundary_triangles=all_boundary,
    )
    logger.info(
        "quality: %d triangles, min angle %.2f deg, %d below 30, %d all-boundary",
        report.triangles,
        report.min_angle.min,
        report.min_angle.below_30,
        len(all_boundary),
    )
    logger.debug("quality measured in %.2f s", time.perf_counter() - started)
    return report


def _check_mesh(mesh: object) -> Mesh:
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    return mesh


def _node_size(mesh: Mesh, size: ArrayLike | None) -> NDArray[np.float64] | None:
    """Return the checked target size at each node, or None if there is none."""
    name = "size"
    if size is None:
        if "size" not in mesh.point_data:
            return None
        size, name = mesh.point_data["size"], "mesh.point_data['size']"
    values = np.asarray(size, dtype=np.float64)
    n = len(mesh.points)
    if values.shape != (n,):
        raise ValueError(
            f"{name} has shape {values.shape}, expected ({n},): one target edge "
            "length (metres) per node"
        )
    bad = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
    if bad.size:
        raise ValueError(
            f"{name}[{bad[0]}] is {values[bad[0]]}, expected a finite target edge "
            f"length > 0 (metres); {bad.size} such values"
        )
    return values


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


def _lengths(
    p: NDArray[np.float64], q: NDArray[np.float64], planar: bool
) -> NDArray[np.float64]:
    """Return the lengths (metres) from ``p`` to ``q`` (k, 3): chords, or arcs.

    Arcs on the ellipsoid (:func:`~coastmesh.geometry.earth.arc_lengths`) unless
    ``planar``.
    """
    if not planar:
        return arc_lengths(p, q)
    d = q - p
    return np.sqrt(np.einsum("ij,ij->i", d, d))


def _triangle_measures(
    xyz: NDArray[np.float64],
    triangles: NDArray[np.int64],
    planar: bool,
    *,
    area: bool = True,
) -> dict[str, NDArray[np.float64]]:
    m = len(triangles)
    keys = (
        ("min_angle", "radius_ratio", "area") if area else ("min_angle", "radius_ratio")
    )
    out = {key: np.empty(m) for key in keys}
    for start in range(0, m, _BLOCK):
        block = triangles[start : start + _BLOCK]
        p = [xyz[block[:, k]] for k in range(3)]
        sides = np.sort(
            np.column_stack(
                [_lengths(p[(k + 1) % 3], p[(k + 2) % 3], planar) for k in range(3)]
            ),
            axis=1,
        )
        c, b, a = sides.T
        f1 = np.maximum(c - (a - b), 0.0)
        f2 = c + (a - b)
        f3 = a + (b - c)
        with np.errstate(divide="ignore", invalid="ignore"):
            half = np.where(a * b > 0, f1 * f2 / (4 * a * b), 0.0)
            ratio = np.where(a * b * c > 0, f1 * f2 * f3 / (a * b * c), 0.0)
        part = slice(start, start + len(block))
        out["min_angle"][part] = np.degrees(2 * np.arcsin(np.sqrt(np.minimum(half, 1))))
        out["radius_ratio"][part] = ratio
        if area:
            out["area"][part] = 0.25 * np.sqrt((a + (b + c)) * f1 * f2 * f3)
    return out


def _edge_measures(
    xyz: NDArray[np.float64],
    mesh: Mesh,
    planar: bool,
    node_size: NDArray[np.float64] | None,
) -> dict[str, NDArray[Any]]:
    """Every edge once (:func:`~coastmesh.meshing.topology.unique_edges`)."""
    edges, shared = unique_edges(mesh.triangles, len(mesh.points))
    length = np.empty(len(edges))
    for start in range(0, len(edges), _BLOCK):
        lo, hi = edges[start : start + _BLOCK].T
        length[start : start + len(lo)] = _lengths(xyz[lo], xyz[hi], planar)
    out = {"edges": edges, "triangles": shared, "length": length}
    if node_size is not None:
        target = node_size[edges[:, 0]]
        target += node_size[edges[:, 1]]
        target *= 0.5
        out["ratio"] = np.divide(length, target, out=target)
    return out
