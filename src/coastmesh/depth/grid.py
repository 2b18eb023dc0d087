"""Depth on the nodes of a grid, from one raster or a stack of them."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.depth.raster import raster_grid
from coastmesh.depth.sources import DepthSource, DepthSources
from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import reproject_points
from coastmesh.geometry.grids import interpolate_bilinear, interpolate_nearest

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["READINGS", "depth_on_grid", "raster_at", "raster_on_grid"]

#: How :func:`raster_on_grid` reads a raster between its cell centres.
READINGS = ("bilinear", "nearest")


def raster_on_grid(
    raster: xr.DataArray,
    x: ArrayLike,
    y: ArrayLike,
    *,
    crs: CRS | str,
    how: str = "bilinear",
) -> NDArray[np.float64]:
    """Read any raster at the nodes of a grid, in the raster's own CRS.

    Parameters
    ----------
    raster : xarray.DataArray
        Dims ``("y", "x")`` with 1-D cell-centre coordinates and a ``crs`` attr
        (WKT), as :func:`coastmesh.io.read_raster` returns; NaN = missing.
    x, y : array_like of shape (nx,), (ny,)
        Node coordinates of the grid in ``crs``.
    crs : pyproj.CRS or str
        CRS of the grid; the nodes are moved into the raster's CRS.
    how : {"bilinear", "nearest"}
        As :func:`raster_at`.

    Returns
    -------
    ndarray of shape (ny, nx)
        The raster's values as they are (no sign changed); NaN outside it.

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[1.0, 2.0], [3.0, 4.0]], dims=("y", "x"),
    ...                  coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> raster_on_grid(r, [0.25, 0.75], [0.0], crs="EPSG:4326").tolist()
    [[1.25, 1.75]]
    >>> raster_on_grid(r, [0.25, 0.75], [0.0], crs="EPSG:4326", how="nearest").tolist()
    [[1.0, 2.0]]
    """
    gx, gy = np.meshgrid(np.asarray(x, float), np.asarray(y, float))
    nodes = np.column_stack([gx.ravel(), gy.ravel()])
    return raster_at(raster, nodes, crs, how=how).reshape(gx.shape)


def raster_at(
    raster: xr.DataArray,
    points: NDArray[np.float64],
    crs: CRS | str,
    *,
    how: str = "bilinear",
) -> NDArray[np.float64]:
    """Read any raster at points, in the raster's own CRS.

    Parameters
    ----------
    raster : xarray.DataArray
        As :func:`raster_on_grid` takes it.
    points : ndarray of shape (n, 2)
        The points, in ``crs``; moved into the raster's CRS unless that is
        ``crs`` (a caller that has them there already moves nothing).
    crs : pyproj.CRS or str
        CRS of ``points``.
    how : {"bilinear", "nearest"}
        ``"bilinear"`` between the four cell centres around a point (NaN where
        one with a weight is missing:
        :func:`~coastmesh.geometry.grids.interpolate_bilinear`); ``"nearest"``
        the value of the cell the point is in
        (:func:`~coastmesh.geometry.grids.interpolate_nearest`), for classes
        and codes.

    Returns
    -------
    ndarray of shape (n,)
        The raster's values as they are; NaN outside it.

    Raises
    ------
    ConfigError
        For another ``how``, or a raster without dims ``("y", "x")``, a ``crs``
        attribute or monotonic axes
        (:func:`~coastmesh.depth.raster.raster_grid`).
    """
    if how not in READINGS:
        raise ConfigError(f"how = {how!r}: use one of {', '.join(READINGS)}")
    rx, ry, values, raster_crs = raster_grid(raster)
    if CRS.from_user_input(crs) != raster_crs:
        points = reproject_points(points, crs, raster_crs)
    read = interpolate_bilinear if how == "bilinear" else interpolate_nearest
    return read(rx, ry, values, points[:, 0], points[:, 1])


def depth_on_grid(
    raster: xr.DataArray | DepthSources,
    x: ArrayLike,
    y: ArrayLike,
    *,
    crs: CRS | str,
    positive: str = "up",
    sea: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """Interpolate a bathymetry raster bilinearly onto the nodes of a size grid.

    Parameters
    ----------
    raster : xarray.DataArray or DepthSources
        Dims ``("y", "x")`` with 1-D cell-centre coordinates and a ``crs`` attr
        (WKT), as :func:`coastmesh.io.read_raster` returns; NaN = missing. Or a
        stack of rasters (:class:`~coastmesh.depth.DepthSources`), which
        carries its own signs.
    x, y : array_like of shape (nx,), (ny,)
        Node coordinates of the grid in ``crs``.
    crs : pyproj.CRS or str
        CRS of the grid.
    positive : {"up", "down"}
        Sign of the raster: ``"up"`` for elevations (GEBCO, ETOPO: depths are
        negative), ``"down"`` for depths.
    sea : ndarray of bool of shape (ny, nx), optional
        The nodes in the domain's sea. With it, the depths are those the mesh
        nodes get (``land = "wet"`` of :func:`~coastmesh.depth.depth_at_nodes`):
        the wet cells alone, and a sea node with no wet cell around takes the
        nearest wet cell; so a size term never reads a land height in the sea.

    Returns
    -------
    ndarray of shape (ny, nx)
        Depth, metres, positive down; NaN outside the raster or at missing cells.

    Raises
    ------
    ConfigError
        For a bad ``positive``, or a raster without dims ``("y", "x")``, a
        ``crs`` attribute or monotonic axes
        (:func:`~coastmesh.depth.raster.raster_grid`).

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[-10.0, -20.0], [-30.0, -40.0]], dims=("y", "x"),
    ...                  coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> depth_on_grid(r, [0.5], [0.5], crs="EPSG:4326").tolist()
    [[25.0]]
    """
    if positive not in ("up", "down"):
        raise ConfigError(f"positive = {positive!r}: use 'up' or 'down'")
    gx, gy = np.meshgrid(np.asarray(x, float), np.asarray(y, float))
    nodes = np.column_stack([gx.ravel(), gy.ravel()])
    if sea is not None:
        if isinstance(raster, DepthSources):
            stack = raster
        else:
            stack = DepthSources([DepthSource(raster, positive)])
        depth = stack.sample(nodes, crs, wet=True).depth
        dry = np.flatnonzero(sea.ravel() & (depth <= 0))
        if dry.size:
            value, _, _ = stack.nearest(nodes[dry], crs, kind="wet")
            depth[dry] = np.where(np.isfinite(value), value, depth[dry])
        return depth.reshape(gx.shape)
    if isinstance(raster, DepthSources):
        return raster.sample(nodes, crs).depth.reshape(gx.shape)
    z = raster_at(raster, nodes, crs).reshape(gx.shape)
    return -z if positive == "up" else z
