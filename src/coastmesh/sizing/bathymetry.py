"""Size terms from bathymetry: tidal wavelength and bathymetric slope."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import reproject_points
from coastmesh.sizing.raster import interpolate_bilinear, raster_grid
from coastmesh.sizing.sources import DepthSources

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "GRAVITY",
    "M2_PERIOD",
    "BathymetrySize",
    "bathymetry_size",
    "depth_on_grid",
    "slope_size",
    "wavelength_size",
]

#: Period of the principal lunar semi-diurnal tide M2, seconds.
M2_PERIOD = 12.4206012 * 3600.0
#: Standard gravity, m/s2: every wave speed of coastmesh uses it.
GRAVITY = 9.80665


def depth_on_grid(
    raster: xr.DataArray | DepthSources,
    x: ArrayLike,
    y: ArrayLike,
    *,
    crs: CRS | str,
    positive: str = "up",
) -> NDArray[np.float64]:
    """Interpolate a bathymetry raster bilinearly onto the nodes of a size grid.

    Parameters
    ----------
    raster : xarray.DataArray or DepthSources
        Dims ``("y", "x")`` with 1-D cell-centre coordinates and a ``crs`` attr
        (WKT), as :func:`coastmesh.io.read_raster` returns; NaN = missing. Or a
        stack of rasters (:class:`~coastmesh.sizing.DepthSources`), which
        carries its own signs.
    x, y : array_like of shape (nx,), (ny,)
        Node coordinates of the grid in ``crs``.
    crs : pyproj.CRS or str
        CRS of the grid.
    positive : {"up", "down"}
        Sign of the raster: ``"up"`` for elevations (GEBCO, ETOPO: depths are
        negative), ``"down"`` for depths.

    Returns
    -------
    ndarray of shape (ny, nx)
        Depth, metres, positive down; NaN outside the raster or at missing cells.

    Raises
    ------
    ConfigError
        For a bad ``positive``, or a raster without dims ``("y", "x")``, a
        ``crs`` attribute or monotonic axes
        (:func:`~coastmesh.sizing.raster.raster_grid`).

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
    if isinstance(raster, DepthSources):
        return raster.sample(nodes, crs).depth.reshape(gx.shape)
    rx, ry, values, raster_crs = raster_grid(raster)
    px, py = reproject_points(nodes, crs, raster_crs).T
    z = interpolate_bilinear(rx, ry, values, px, py).reshape(gx.shape)
    return -z if positive == "up" else z


def wavelength_size(
    depth: ArrayLike,
    *,
    per_wavelength: float,
    period: float = M2_PERIOD,
    min_depth: float = 1.0,
) -> NDArray[np.float64]:
    """Size that resolves a tidal wave with ``per_wavelength`` elements.

    ``h = T sqrt(g d) / n``, the shallow-water wavelength of a wave of period ``T``
    in depth ``d`` divided by ``n``. Land and missing cells (NaN, or depth below
    ``min_depth``) use ``min_depth``.

    Parameters
    ----------
    depth : array_like
        Depth, metres, positive down.
    per_wavelength : float
        Elements per wavelength (> 0), e.g. 50.
    period : float
        Wave period, seconds (default M2).
    min_depth : float
        Depth floor, metres (> 0).

    Returns
    -------
    ndarray
        Sizes, metres.

    Examples
    --------
    >>> round(float(wavelength_size([100.0], per_wavelength=100)[0]))
    14002
    """
    if not per_wavelength > 0:
        raise ConfigError(f"per_wavelength = {per_wavelength}: must be > 0")
    if not (period > 0 and min_depth > 0):
        raise ConfigError(f"period = {period}, min_depth = {min_depth}: must be > 0")
    d = np.asarray(depth, dtype=float)
    d = np.where(np.isnan(d) | (d < min_depth), min_depth, d)
    return period * np.sqrt(GRAVITY * d) / per_wavelength


def slope_size(
    depth: ArrayLike,
    spacing: tuple[float, float],
    *,
    per_slope: float,
    min_depth: float = 1.0,
) -> NDArray[np.float64]:
    """Size that resolves the bathymetric slope: ``h = 2 pi d / (n |grad d|)``.

    Where the depth changes by its own value over a distance ``L = d / |grad d|``
    (the topographic length scale), ``n`` elements per ``2 pi L`` are asked for.
    Flat areas get an infinite size (no constraint); combine with others by
    minimum.

    Parameters
    ----------
    depth : array_like of shape (ny, nx)
        Depth, metres, positive down, on a regular grid.
    spacing : (float, float)
        Grid spacing ``(dy, dx)``, metres.
    per_slope : float
        Elements per ``2 pi`` topographic length scales (> 0).
    min_depth : float
        Depth floor, metres (> 0); land and missing cells use it.

    Returns
    -------
    ndarray of shape (ny, nx)
        Sizes, metres (``inf`` where the bottom is flat).

    Examples
    --------
    >>> d = np.tile(np.linspace(10.0, 110.0, 11), (3, 1))  # 10 m deeper per 100 m
    >>> h = slope_size(d, (100.0, 100.0), per_slope=10)
    >>> round(float(h[1, 5]), 1)  # 60 m deep, slope 0.1: 2 pi 600 / 10
    377.0
    """
    if not per_slope > 0:
        raise ConfigError(f"per_slope = {per_slope}: must be > 0")
    dy, dx = spacing
    d = np.asarray(depth, dtype=float)
    d = np.where(np.isnan(d) | (d < min_depth), min_depth, d)
    gy, gx = np.gradient(d, dy, dx)
    steep = np.hypot(gx, gy)
    with np.errstate(divide="ignore"):
        return np.where(steep > 0, 2 * np.pi * d / (per_slope * steep), np.inf)


@dataclass(frozen=True, slots=True)
class BathymetrySize:
    """Size terms from a bathymetry raster: tidal wavelength and slope.

    Parameters
    ----------
    raster : xarray.DataArray or DepthSources
        As :func:`coastmesh.io.read_raster` returns (dims ``("y", "x")``, a
        ``crs`` attr, NaN for nodata).
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO).
    per_wavelength : float, optional
        Elements per tidal wavelength (:func:`~coastmesh.sizing.wavelength_size`).
    period : float
        The tide's period, seconds; default M2.
    per_slope : float, optional
        Elements per ``2 pi d / |grad d|`` (:func:`~coastmesh.sizing.slope_size`).
    min_depth : float
        Depth floor of both terms, metres.
    """

    raster: xr.DataArray | DepthSources
    positive: str = "up"
    per_wavelength: float | None = None
    period: float = M2_PERIOD
    per_slope: float | None = None
    min_depth: float = 1.0


def bathymetry_size(
    b: BathymetrySize, field: xr.DataArray, mesh_crs: CRS
) -> NDArray[np.float64]:
    """Return the smaller of the wavelength and slope terms on a size field's grid.

    ``field`` is a size field DataArray (dims ``("y", "x")``, in ``mesh_crs``).
    """
    depth = depth_on_grid(
        b.raster, field.x.values, field.y.values, crs=mesh_crs, positive=b.positive
    )
    size = np.full(depth.shape, np.inf)
    if b.per_wavelength is not None:
        size = np.minimum(
            size,
            wavelength_size(
                depth,
                per_wavelength=b.per_wavelength,
                period=b.period,
                min_depth=b.min_depth,
            ),
        )
    if b.per_slope is not None:
        cell = float(field.x[1] - field.x[0])
        size = np.minimum(
            size,
            slope_size(
                depth, (cell, cell), per_slope=b.per_slope, min_depth=b.min_depth
            ),
        )
    return size
