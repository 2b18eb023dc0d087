"""Mesh quality measured on the Earth: angles, radius ratios, edge sizes, valence.

Every length is measured on the WGS84 ellipsoid, never in degrees: the nodes go to
earth-centred coordinates (EPSG:4978) and each side is the chord between its two
nodes, turned into the arc of the ellipsoid's local curvature, which matches the
geodesic to 3e-12 from 1 km to 100 km (:mod:`coastmesh.meshing.quality.measure`).
Angles, radius ratios and areas then follow from the three sides of each triangle.
A mesh without a CRS is taken as planar, in metres; the report says so. With
depths on the nodes, the report has the stable time step and Courant numbers
(:mod:`coastmesh.meshing.quality.time_step`); it always has the sharp boundary
corners (:mod:`coastmesh.meshing.quality.corners`). The report
(:class:`QualityReport`) is data, defined in
:mod:`coastmesh.meshing.quality.report`; :func:`coastmesh.io.write_report`
writes it.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.geometry.earth import mesh_earth_centred
from coastmesh.meshing.quality.corners import SHARP_ANGLE, corner_stats, interior_angles
from coastmesh.meshing.quality.measure import edge_measures, triangle_measures
from coastmesh.meshing.quality.report import (
    AngleStats,
    EdgeRatioStats,
    QualityReport,
    RatioStats,
    ValenceStats,
    histograms,
)
from coastmesh.meshing.quality.time_step import (
    TimeStepStats,
    check_time_step_options,
    node_depth,
    time_step_arrays,
    time_step_stats,
)
from coastmesh.types import Mesh

# the report types are in coastmesh.meshing.quality.report
__all__ = ["edge_quality", "mesh_quality", "triangle_quality"]

logger = logging.getLogger(__name__)


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
    return triangle_measures(xyz, mesh.triangles, planar)


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
    return edge_measures(xyz, mesh, planar, _node_size(mesh, size))


def mesh_quality(
    mesh: Mesh,
    *,
    size: ArrayLike | None = None,
    dt: float | None = None,
    velocity: float = 0.0,
    courant_max: float | None = None,
    courant_min: float | None = None,
) -> QualityReport:
    """Measure a mesh on the Earth: shapes, sizes, valence, corners, time step.

    Parameters
    ----------
    mesh : Mesh
        Points in a geographic or projected CRS, or planar metres when
        ``mesh.crs`` is None; at least one triangle. With
        ``point_data["depth"]`` (metres, positive down) the report has the
        stable time step.
    size : array_like of shape (N,), optional
        Target edge length at each node, metres; default
        ``mesh.point_data["size"]`` if present. Without either, the report has no
        edge-size block.
    dt : float, optional
        The model's time step, seconds (> 0): the report then has the Courant
        number of each triangle at it (with a depth).
    velocity : float, default 0
        Velocity scale added to the wave speed ``sqrt(g d)``, m/s (>= 0).
    courant_max, courant_min : float, optional
        Count the triangles whose Courant number at ``dt`` is above
        ``courant_max`` or below ``courant_min``.

    Returns
    -------
    QualityReport

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        If the mesh has no triangles, ``size`` does not hold one finite value
        > 0 per node, the depth not one value per node, an option is out of
        range (``courant_min`` >= ``courant_max``, or a limit without ``dt``),
        ``mesh.crs`` is neither geographic nor projected, or a node has no
        position on the Earth.

    Notes
    -----
    Lengths, angles and ratios as :func:`triangle_quality` computes them. Edges
    are found by sorting their node pairs; an edge in a single triangle is on the
    boundary, and so are its nodes. Triangles with all three nodes on the
    boundary include those with two boundary sides and those bridging a channel
    one element wide (at most one boundary side: ``channel_spanning_triangles``).
    A boundary node's interior angle is the sum of its triangles' angles there;
    below 45 degrees it is a sharp corner
    (:func:`~coastmesh.meshing.quality.corners.boundary_angles`), and the radius ratios
    are also given without the triangles that touch one. The time step and
    Courant numbers are those of
    :func:`~coastmesh.meshing.quality.time_step.element_time_steps`. Takes about 1.3 s
    and 110 MB per million triangles, 2 s and 180 MB with depths (the mesh
    itself is 32 MB); triangles and edges are measured in blocks.

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
    >>> deep = m.with_point_data(depth=[10.0, 10.0, 40.0, 40.0])
    >>> round(mesh_quality(deep, dt=0.1).time_step.courant.max, 4)
    1.7403
    """
    started = time.perf_counter()
    _check_mesh(mesh)
    if len(mesh.triangles) == 0:
        raise ValueError("mesh has no triangles: nothing to measure")
    node_size = _node_size(mesh, size)
    depth = node_depth(mesh)
    check_time_step_options(velocity, dt, courant_max, courant_min)
    xyz, planar = mesh_earth_centred(mesh)
    keys = ("min_angle", "radius_ratio")
    shape = triangle_measures(
        xyz,
        mesh.triangles,
        planar,
        keys if depth is None else (*keys, "r_in", "mean_edge"),
    )
    edges = edge_measures(xyz, mesh, planar, node_size)
    n = len(mesh.points)
    valence = np.bincount(mesh.triangles.ravel(), minlength=n)
    boundary = edges["edges"][edges["triangles"] == 1]
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[boundary.ravel()] = True
    interior = ~on_boundary & (valence > 0)
    all_boundary = np.flatnonzero(on_boundary[mesh.triangles].all(axis=1))
    corners, at_corner = corner_stats(
        mesh, *interior_angles(xyz, planar, mesh.triangles, boundary), boundary
    )
    away = shape["radius_ratio"][~at_corner]
    time_step = None
    if depth is not None:
        time_step = _time_step(
            mesh, shape, depth, at_corner, velocity, dt, (courant_min, courant_max)
        )
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
        corners=corners,
        radius_ratio_away_from_corners=(
            RatioStats.from_values(away) if away.size else None
        ),
        time_step=time_step,
        all_boundary_triangles=all_boundary,
        channel_spanning_triangles=_channel_spanning(
            mesh.triangles, all_boundary, boundary, n
        ),
        histograms=histograms(shape, edges),
    )
    _log_quality(report, started)
    return report


def _log_quality(report: QualityReport, started: float) -> None:
    """Log the report's one-line summary (INFO) and the time taken (DEBUG)."""
    logger.info(
        "quality: %d triangles, min angle %.2f deg, %d below 30, %d all-boundary, "
        "%d boundary corners below %g deg",
        report.triangles,
        report.min_angle.min,
        report.min_angle.below_30,
        len(report.all_boundary_triangles),
        report.corners.sharp,
        SHARP_ANGLE,
    )
    if report.time_step is not None:
        logger.info("quality: %s", report.time_step.summary())
    logger.debug("quality measured in %.2f s", time.perf_counter() - started)


def _time_step(
    mesh: Mesh,
    shape: dict[str, NDArray[np.float64]],
    depth: NDArray[np.float64],
    at_corner: NDArray[np.bool_],
    velocity: float,
    dt: float | None,
    window: tuple[float | None, float | None],
) -> TimeStepStats:
    """Return each triangle's stable time step (and Courant number), summed up."""
    arrays = time_step_arrays(
        shape["r_in"], shape["mean_edge"], depth[mesh.triangles], velocity, dt
    )
    return time_step_stats(
        mesh,
        arrays,
        velocity=velocity,
        dt=dt,
        courant_max=window[1],
        courant_min=window[0],
        at_corner=at_corner,
    )


def _channel_spanning(
    triangles: NDArray[np.int64],
    all_boundary: NDArray[np.int64],
    boundary: NDArray[np.int64],
    n: int,
) -> NDArray[np.int64]:
    """Return the triangles of ``all_boundary`` with at most one boundary side.

    ``boundary`` (K, 2) holds the boundary edges, lower node first, in
    increasing order of ``lo * n + hi`` (as
    :func:`~coastmesh.types.topology.unique_edges` returns them).
    """
    keys = boundary[:, 0] * n + boundary[:, 1]
    nodes = triangles[all_boundary]
    sides = np.zeros(len(all_boundary), dtype=np.int64)
    for k in range(3):
        i, j = nodes[:, k], nodes[:, (k + 1) % 3]
        side = np.minimum(i, j) * n + np.maximum(i, j)
        pos = np.minimum(np.searchsorted(keys, side), max(len(keys) - 1, 0))
        sides += keys[pos] == side if len(keys) else 0
    return all_boundary[sides <= 1]


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
