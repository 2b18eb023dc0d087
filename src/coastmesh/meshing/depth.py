"""Bathymetry on the mesh nodes: interpolation, missing data, depth floor, slope limit.

The rule for nodes the raster cannot give a value to (outside it, or next to a
nodata cell) is the nearest valid cell on the Earth (a k-d tree in earth-centred
coordinates), and the report counts them. Depths are metres, positive down.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS
from scipy.spatial import cKDTree

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.earth import earth_centred, metres_per_unit, reproject_points
from coastmesh.meshing.quality import mesh_earth_centred
from coastmesh.meshing.topology import unique_edges
from coastmesh.sizing.raster import interpolate_bilinear, raster_grid
from coastmesh.types import Mesh, Report

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["DEPTH_METHODS", "DepthReport", "depth_at_nodes", "limit_slope"]

#: ``"bilinear"``: bilinear interpolation; ``"mean"``: the mean of the cells over
#: each node's surrounding area where the mesh is coarser than the raster
#: (bilinear elsewhere).
DEPTH_METHODS = ("bilinear", "mean")


@dataclass(frozen=True, slots=True)
class DepthReport(Report):
    """What :func:`depth_at_nodes` did.

    Attributes
    ----------
    nodes : int
        Mesh nodes given a depth.
    method : str
        ``"bilinear"`` or ``"mean"`` (:data:`DEPTH_METHODS`).
    averaged : int
        Nodes whose depth is the mean of the cells around them (``"mean"``).
    nearest : int
        Nodes outside the raster or next to nodata that took the nearest valid
        cell on the Earth.
    below_min_depth : int
        Nodes raised to the minimum depth.
    slope_limited : int
        Nodes made shallower by the slope limit.
    min, max : float
        Smallest and largest depth, metres, positive down.
    """

    nodes: int
    method: str
    averaged: int
    nearest: int
    below_min_depth: int
    slope_limited: int
    min: float
    max: float

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"depth at {self.nodes:,} nodes ({self.method}; {self.averaged:,} by cell "
            f"means): {self.min:.1f} to {self.max:.1f} m; {self.nearest:,} nodes "
            f"outside the raster or at nodata took the nearest valid cell; "
            f"{self.below_min_depth:,} raised to the minimum depth; "
            f"{self.slope_limited:,} changed by the slope limit"
        )


def depth_at_nodes(
    mesh: Mesh,
    raster: xr.DataArray,
    *,
    positive: str = "up",
    method: str = "bilinear",
    min_depth: float | None = None,
    max_slope: float | None = None,
) -> tuple[NDArray[np.float64], DepthReport]:
    """Interpolate a bathymetry raster onto the nodes of a mesh.

    Parameters
    ----------
    mesh : Mesh
        The mesh; ``mesh.crs`` must be known.
    raster : xarray.DataArray
        Dims ``("y", "x")``, 1-D cell-centre coordinates, a ``crs`` attr, NaN for
        nodata (as :func:`coastmesh.io.read_raster` returns).
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO), ``"down"`` for
        depths.
    method : {"bilinear", "mean"}
        ``"mean"`` averages the valid cells within half the mean length of each
        node's edges where that covers more than one cell, and interpolates
        bilinearly elsewhere.
    min_depth : float, optional
        Depths below this (metres; e.g. 5 for a model without wetting and drying)
        are raised to it.
    max_slope : float, optional
        Largest ``|depth difference| / edge length`` along any mesh edge; deeper
        nodes are made shallower until it holds (:func:`limit_slope`).

    Returns
    -------
    depth : ndarray of shape (N,)
        Metres, positive down.
    report : DepthReport

    Raises
    ------
    ConfigError
        For a bad ``positive``, ``method``, ``min_depth`` or ``max_slope``, a
        mesh without a CRS, or a raster
        :func:`~coastmesh.sizing.raster.raster_grid` refuses.
    InputDataError
        If the raster has no valid cell.

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[-10.0, -20.0], [-30.0, -40.0]], dims=("y", "x"),
    ...                  coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> m = Mesh([[0.5, 0.5], [0.0, 0.0], [3.0, 0.0]], [[1, 2, 0]],
    ...          [[1, 2], [2, 0], [0, 1]], [1, 1, 1], 1, "EPSG:4326")
    >>> depth, report = depth_at_nodes(m, r)
    >>> depth.tolist(), report.nearest
    ([25.0, 10.0, 20.0], 1)
    """
    if positive not in ("up", "down"):
        raise ConfigError(f"positive = {positive!r}: use 'up' or 'down'")
    if method not in DEPTH_METHODS:
        raise ConfigError(f"method = {method!r}: use one of {DEPTH_METHODS}")
    if min_depth is not None and not np.isfinite(min_depth):
        raise ConfigError(f"min_depth = {min_depth}: not a finite number of metres")
    if mesh.crs is None:
        raise ConfigError("the mesh has no CRS: give the CRS of its coordinates")
    rx, ry, values, raster_crs = raster_grid(raster)
    if not np.isfinite(values).any():
        raise InputDataError("the bathymetry raster has no valid cell")
    px, py = reproject_points(mesh.points, mesh.crs, raster_crs).T
    z = interpolate_bilinear(rx, ry, values, px, py)
    averaged = 0
    if method == "mean":
        radius = _node_radius(mesh)
        means, used = _box_means(rx, ry, values, px, py, radius, raster_crs)
        z = np.where(used, means, z)
        averaged = int(used.sum())
    missing = ~np.isfinite(z)
    if missing.any():
        z[missing] = _nearest_valid(
            rx, ry, values, px[missing], py[missing], raster_crs
        )
    depth = -z if positive == "up" else z
    shallow = 0
    if min_depth is not None:
        shallow = int((depth < min_depth).sum())
        depth = np.maximum(depth, min_depth)
    limited = 0
    if max_slope is not None:
        limited_depth = limit_slope(mesh, depth, max_slope)
        limited = int((limited_depth != depth).sum())
        depth = limited_depth
    report = DepthReport(
        nodes=len(depth),
        method=method,
        averaged=averaged,
        nearest=int(missing.sum()),
        below_min_depth=shallow,
        slope_limited=limited,
        min=float(depth.min()),
        max=float(depth.max()),
    )
    return depth, report


def limit_slope(
    mesh: Mesh, depth: NDArray[np.float64], max_slope: float
) -> NDArray[np.float64]:
    """Make deep nodes shallower until no mesh edge is steeper than ``max_slope``.

    The result is the largest field below ``depth`` with
    ``h(p) <= h(q) + max_slope * L(p, q)`` along every edge: the min-plus
    convolution over the mesh graph, ``h(p) = min_q depth(q) + s * dist(q, p)``,
    computed by one multi-source Dijkstra (scipy). Shallow water and the coast
    keep their depths; steep flanks are eased from the deep side.

    Parameters
    ----------
    mesh : Mesh
        The mesh (edge lengths are measured on the Earth).
    depth : ndarray of shape (N,)
        Depths, metres.
    max_slope : float
        Largest slope (dimensionless, > 0), e.g. 0.1.

    Returns
    -------
    ndarray of shape (N,)
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    if not (max_slope > 0 and np.isfinite(max_slope)):
        raise ConfigError(f"max_slope = {max_slope}: must be a number > 0")
    depth = np.asarray(depth, dtype=np.float64)
    edges, lengths = _edges_on_earth(mesh)
    n = len(depth)
    base = depth.min()
    # node n is a source joined to every node by its (shifted) depth
    rows = np.concatenate([edges[:, 0], edges[:, 1], np.full(n, n)])
    cols = np.concatenate([edges[:, 1], edges[:, 0], np.arange(n)])
    weights = np.concatenate(
        [max_slope * lengths, max_slope * lengths, depth - base + 1e-300]
    )
    graph = coo_matrix((weights, (rows, cols)), shape=(n + 1, n + 1)).tocsr()
    limited = dijkstra(graph, directed=True, indices=n)[:n] + base
    return np.minimum(limited, depth)


def _edges_on_earth(mesh: Mesh) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Return the unique edges and their lengths, metres (earth-centred chords)."""
    edges, _ = unique_edges(mesh.triangles, len(mesh.points))
    xyz, _ = mesh_earth_centred(mesh)
    return edges, np.linalg.norm(xyz[edges[:, 0]] - xyz[edges[:, 1]], axis=1)


def _node_radius(mesh: Mesh) -> NDArray[np.float64]:
    """Half the mean length of each node's edges, metres: its surrounding area."""
    edges, lengths = _edges_on_earth(mesh)
    n = len(mesh.points)
    total = np.bincount(edges.ravel(), np.repeat(lengths, 2), minlength=n)
    count = np.bincount(edges.ravel(), minlength=n)
    return 0.5 * total / np.maximum(count, 1)


def _box_means(rx, ry, values, px, py, radius, raster_crs: CRS):
    """Mean of the valid cells within ``radius`` of each node (summed-area tables)."""
    dx, dy = abs(rx[1] - rx[0]), abs(ry[1] - ry[0])
    half_x = half_y = radius / metres_per_unit(raster_crs)
    if raster_crs.is_geographic:  # a degree of longitude is shorter
        half_x = half_y / np.maximum(np.cos(np.radians(py)), 1e-6)
    kx = np.floor(half_x / dx).astype(np.int64)
    ky = np.floor(half_y / dy).astype(np.int64)
    used = (kx >= 1) | (ky >= 1)
    ci = np.rint((px - rx[0]) / (rx[1] - rx[0])).astype(np.int64)
    cj = np.rint((py - ry[0]) / (ry[1] - ry[0])).astype(np.int64)
    ny, nx = values.shape
    used &= (ci >= 0) & (ci < nx) & (cj >= 0) & (cj < ny)
    valid = np.isfinite(values)
    sums = np.zeros((ny + 1, nx + 1))
    sums[1:, 1:] = np.where(valid, values, 0.0).cumsum(0).cumsum(1)
    counts = np.zeros((ny + 1, nx + 1))
    counts[1:, 1:] = valid.cumsum(0).cumsum(1)
    i0, i1 = np.clip(ci - kx, 0, nx), np.clip(ci + kx + 1, 0, nx)
    j0, j1 = np.clip(cj - ky, 0, ny), np.clip(cj + ky + 1, 0, ny)

    def box(table):
        return table[j1, i1] - table[j0, i1] - table[j1, i0] + table[j0, i0]

    n = box(counts)
    with np.errstate(invalid="ignore", divide="ignore"):
        means = box(sums) / n
    used &= n > 0
    return means, used


def _nearest_valid(rx, ry, values, px, py, raster_crs: CRS) -> NDArray[np.float64]:
    """Values of the nearest valid cells on the Earth (earth-centred k-d tree)."""
    gx, gy = np.meshgrid(rx, ry)
    valid = np.isfinite(values)
    cells = np.column_stack([gx[valid], gy[valid]])
    tree = cKDTree(earth_centred(cells, raster_crs, name="raster cells"))
    _, k = tree.query(earth_centred(np.column_stack([px, py]), raster_crs))
    return values[valid][k]
