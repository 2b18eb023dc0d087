"""Bathymetry on the mesh nodes: sources, coverage, land, depth floor, slope limit.

The depth comes from a stack of rasters (:class:`~coastmesh.depth.DepthSources`,
highest priority first, blended at their seams). Every node must lie within the
sources' cover (up to one cell diagonal); ``outside="nearest"`` gives the rest
the nearest valid cell on the Earth instead, with a warning. Nodes the rasters
put on land (depth <= 0 m) get the ``land`` treatment. Depths are metres,
positive down.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from coastmesh.depth.sources import DepthSource, DepthSources
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import mesh_earth_centred
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import unique_edges

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "DEPTH_METHODS",
    "LAND_TREATMENTS",
    "OUTSIDE_RULES",
    "DepthReport",
    "depth_at_nodes",
    "limit_slope",
]

#: ``"bilinear"``: bilinear interpolation; ``"mean"``: the mean of the cells over
#: each node's surrounding area where the mesh is coarser than the raster
#: (bilinear elsewhere).
DEPTH_METHODS = ("bilinear", "mean")
#: What a node in the mesh's sea gets where the rasters say land (depth <= 0):
#: ``"min_depth"`` the depth floor; ``"nearest_sea"`` the nearest wet cell;
#: ``"smooth"`` the nearest wet cell, then a taper of every depth within
#: ``land_distance`` of the coast to ``min_depth`` at the coast.
LAND_TREATMENTS = ("min_depth", "nearest_sea", "smooth")
#: Nodes beyond every source's cover: ``"error"`` or ``"nearest"`` valid cell.
OUTSIDE_RULES = ("error", "nearest")


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
        Nodes beyond every source's cover that took the nearest valid cell on
        the Earth (``outside="nearest"``).
    below_min_depth : int
        Nodes raised to the minimum depth.
    slope_limited : int
        Nodes made shallower by the slope limit.
    min, max : float
        Smallest and largest depth, metres, positive down.
    sources : tuple of str
        The sources' names, in priority order.
    per_source : tuple of int
        Nodes whose depth came from each source.
    blended : int
        Nodes in a blend zone (a source mixed with the ones below).
    snapped : int
        Nodes within a cell diagonal outside a source's data, given its
        nearest cell.
    land : int
        Nodes the rasters put on land (depth <= 0 m).
    land_treatment : str
        What those got (:data:`LAND_TREATMENTS`).
    tapered : int
        Nodes made shallower by the ``"smooth"`` coastal taper.
    """

    nodes: int
    method: str
    averaged: int
    nearest: int
    below_min_depth: int
    slope_limited: int
    min: float
    max: float
    sources: tuple[str, ...] = ()
    per_source: tuple[int, ...] = ()
    blended: int = 0
    snapped: int = 0
    land: int = 0
    land_treatment: str = "min_depth"
    tapered: int = 0

    def summary(self) -> str:
        """Return a one-line summary."""
        shares = ", ".join(
            f"{name} {count:,}"
            for name, count in zip(self.sources, self.per_source, strict=True)
        )
        return (
            f"depth at {self.nodes:,} nodes ({self.method}; {self.averaged:,} by cell "
            f"means): {self.min:.1f} to {self.max:.1f} m; by source: {shares}; "
            f"{self.blended:,} blended, {self.snapped:,} within a cell of the data, "
            f"{self.nearest:,} outside every source took the nearest cell; "
            f"{self.land:,} on land in the rasters ({self.land_treatment}); "
            f"{self.below_min_depth:,} raised to the minimum depth; "
            f"{self.slope_limited:,} changed by the slope limit"
        )


def depth_at_nodes(
    mesh: Mesh,
    raster: xr.DataArray | DepthSources,
    *,
    positive: str = "up",
    method: str = "bilinear",
    min_depth: float | None = None,
    max_slope: float | None = None,
    outside: str = "error",
    land: str = "min_depth",
    land_distance: float | None = None,
) -> tuple[NDArray[np.float64], DepthReport]:
    """Interpolate bathymetry onto the nodes of a mesh.

    Parameters
    ----------
    mesh : Mesh
        The mesh; ``mesh.crs`` must be known.
    raster : xarray.DataArray or DepthSources
        One raster (dims ``("y", "x")``, 1-D cell-centre coordinates, a ``crs``
        attr, NaN for nodata, as :func:`coastmesh.io.read_raster` returns), or a
        stack of them in priority order.
    positive : {"up", "down"}
        A single raster's sign: ``"up"`` for elevations (GEBCO, ETOPO),
        ``"down"`` for depths. A stack carries its own.
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
    outside : {"error", "nearest"}
        Nodes beyond every source's cover (more than a cell diagonal from its
        data): an error, or the nearest valid cell on the Earth and a warning.
    land : {"min_depth", "nearest_sea", "smooth"}
        Nodes where the rasters say land (:data:`LAND_TREATMENTS`).
    land_distance : float, optional
        Metres; the width of the coastal taper of ``land="smooth"``.

    Returns
    -------
    depth : ndarray of shape (N,)
        Metres, positive down.
    report : DepthReport

    Raises
    ------
    ConfigError
        For a bad ``positive``, ``method``, ``min_depth``, ``max_slope``,
        ``outside``, ``land`` or ``land_distance``, or a mesh without a CRS.
    InputDataError
        If a source has no valid cell or covers no node, or nodes lie beyond
        every source with ``outside="error"``; the message names the sources,
        the share each covers and where the gap is.

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[-10.0, -20.0], [-30.0, -40.0]], dims=("y", "x"),
    ...                  coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> m = Mesh([[0.5, 0.5], [0.0, 0.0], [3.0, 0.0]], [[1, 2, 0]],
    ...          [[1, 2], [2, 0], [0, 1]], [1, 1, 1], 1, "EPSG:4326")
    >>> depth, report = depth_at_nodes(m, r, outside="nearest")
    >>> depth.tolist(), report.nearest
    ([25.0, 10.0, 20.0], 1)
    """
    _check_args(mesh, method, min_depth, outside, land, land_distance)
    sources = _stack(raster, positive)
    radius = _node_radius(mesh) if method == "mean" else None
    sample = sources.sample(mesh.points, mesh.crs, radius=radius)
    for name, hit, k in zip(
        sources.names, sample.hits, range(len(sources)), strict=True
    ):
        if hit == 0 and not (sample.source == k).any():
            raise InputDataError(
                f"bathymetry source {name} does not overlap the mesh: no node lies "
                "within its data (is it the right region and CRS?)"
            )
    depth, source = sample.depth.copy(), sample.source.copy()
    gap = sample.uncovered
    if gap.any():
        if outside == "error":
            raise InputDataError(
                sources.uncovered_message(sample, mesh.points, mesh.crs)
                + "; add a source that covers them, or set outside = 'nearest'"
            )
        depth[gap], source[gap], _ = sources.nearest(mesh.points[gap], mesh.crs)
        warnings.warn(
            sources.uncovered_message(sample, mesh.points, mesh.crs)
            + ": they took the nearest valid cell (outside = 'nearest')",
            CoastmeshWarning,
            stacklevel=2,
        )
    dry = depth <= 0
    tapered = 0
    if dry.any() and land in ("nearest_sea", "smooth"):
        wet, _, _ = sources.nearest(mesh.points[dry], mesh.crs, kind="wet")
        depth[dry] = np.where(np.isfinite(wet), wet, depth[dry])
    if land == "smooth":
        depth, tapered = _taper(mesh, depth, min_depth, land_distance)
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
        averaged=int(sample.averaged.sum()),
        nearest=int(gap.sum()),
        below_min_depth=shallow,
        slope_limited=limited,
        min=float(depth.min()),
        max=float(depth.max()),
        sources=sources.names,
        per_source=tuple(int((source == k).sum()) for k in range(len(sources))),
        blended=int(sample.blended.sum()),
        snapped=int(sample.snapped.sum()),
        land=int(dry.sum()),
        land_treatment=land,
        tapered=tapered,
    )
    return depth, report


def node_sources(mesh: Mesh, raster: xr.DataArray | DepthSources) -> NDArray:
    """Return the index of the source each node's depth came from (-1: none)."""
    sources = _stack(raster, "up")
    sample = sources.sample(mesh.points, mesh.crs)
    source = sample.source.copy()
    gap = sample.uncovered
    if gap.any():
        _, source[gap], _ = sources.nearest(mesh.points[gap], mesh.crs)
    return source


def _stack(raster: xr.DataArray | DepthSources, positive: str) -> DepthSources:
    if isinstance(raster, DepthSources):
        return raster
    if positive not in ("up", "down"):
        raise ConfigError(f"positive = {positive!r}: use 'up' or 'down'")
    return DepthSources([DepthSource(raster, positive)])


def _check_args(mesh, method, min_depth, outside, land, land_distance) -> None:
    if method not in DEPTH_METHODS:
        raise ConfigError(f"method = {method!r}: use one of {DEPTH_METHODS}")
    if min_depth is not None and not np.isfinite(min_depth):
        raise ConfigError(f"min_depth = {min_depth}: not a finite number of metres")
    if outside not in OUTSIDE_RULES:
        raise ConfigError(f"outside = {outside!r}: use one of {OUTSIDE_RULES}")
    if land not in LAND_TREATMENTS:
        raise ConfigError(f"land = {land!r}: use one of {LAND_TREATMENTS}")
    if land == "smooth":
        if min_depth is None:
            raise ConfigError("land = 'smooth' tapers to min_depth: give min_depth")
        if land_distance is None or not (land_distance > 0):
            raise ConfigError(
                f"land_distance = {land_distance}: land = 'smooth' needs the width "
                "of the coastal taper, a distance > 0 m"
            )
    if mesh.crs is None:
        raise ConfigError("the mesh has no CRS: give the CRS of its coordinates")


def _taper(mesh: Mesh, depth, min_depth: float, width: float):
    """Taper depths within ``width`` of the coast to ``min_depth`` at the coast.

    ``depth = min_depth + (depth - min_depth) * d / width`` where ``d`` (metres,
    on the Earth) is the distance to the nearest coast node (the nodes of the
    boundary edges of kind ``"shoreline"``). Only makes depths shallower.
    """
    coast_ids = [k for k, kind in mesh.boundary_kinds.items() if kind == "shoreline"]
    on_coast = np.isin(mesh.boundary_ids, coast_ids)
    if not mesh.boundary_kinds:  # no kinds known: every boundary is coast
        on_coast[:] = True
    coast = np.unique(mesh.boundary_edges[on_coast])
    if coast.size == 0:
        return depth, 0
    xyz, _ = mesh_earth_centred(mesh)
    d, _ = cKDTree(xyz[coast]).query(xyz, distance_upper_bound=width)
    near = np.isfinite(d) & (depth > min_depth)
    s = d[near] / width
    depth = depth.copy()
    depth[near] = min_depth + (depth[near] - min_depth) * s
    return depth, int(near.sum())


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
