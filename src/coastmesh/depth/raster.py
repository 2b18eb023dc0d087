"""Rasters as plain arrays: checked axes, values and CRS, and depths at a coast.

A raster here is an :class:`xarray.DataArray` with dims ``("y", "x")``, 1-D
cell-centre coordinates and a ``crs`` attribute (WKT), as
:func:`coastmesh.io.read_raster` returns it; NaN marks missing cells. The sizing
and node-depth steps unpack it once with :func:`raster_grid` and sample it with
:func:`~coastmesh.geometry.grids.interpolate_bilinear` (or, for depths at a
coast, :func:`interpolate_wet`, which never mixes a land cell into the sea).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError
from coastmesh.geometry.grids import bilinear_corners

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["interpolate_wet", "raster_crs", "raster_grid"]


def raster_grid(
    raster: xr.DataArray,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], CRS]:
    """Unpack a raster into its axes, values and CRS, both axes ascending.

    Parameters
    ----------
    raster : xarray.DataArray
        Dims ``("y", "x")``, 1-D cell-centre coordinates, a ``crs`` attribute;
        rows north-up or south-up.

    Returns
    -------
    x : ndarray of shape (nx,)
        Cell-centre x coordinates, increasing, float64.
    y : ndarray of shape (ny,)
        Cell-centre y coordinates, increasing, float64.
    values : ndarray of shape (ny, nx)
        The cells, float64, flipped with the axes so that ``values[j, i]`` is
        at ``(x[i], y[j])``; a new array when a flip or a cast was needed, a
        view of the raster's data otherwise.
    crs : pyproj.CRS
        From the ``crs`` attribute.

    Raises
    ------
    ConfigError
        If the dims are not ``("y", "x")``, there is no ``crs`` attribute, or
        an axis is not strictly monotonic.

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[1.0, 2.0], [3.0, 4.0]], dims=("y", "x"),
    ...                  coords={"y": [10.0, 0.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> x, y, values, crs = raster_grid(r)
    >>> y.tolist(), values.tolist(), crs.to_epsg()
    ([0.0, 10.0], [[3.0, 4.0], [1.0, 2.0]], 4326)
    """
    crs = raster_crs(raster)
    dims = tuple(raster.dims)
    values = np.asarray(raster.values, dtype=np.float64)
    axes = []
    for axis, dim in enumerate(dims):
        coords = np.asarray(raster[dim].values, dtype=np.float64)
        if len(coords) > 1 and coords[0] > coords[-1]:
            coords, values = coords[::-1], np.flip(values, axis)
        if not (np.diff(coords) > 0).all():
            raise ConfigError(
                f"raster {dim} coordinates are not strictly monotonic: cell centres "
                "must increase or decrease along each axis"
            )
        axes.append(coords)
    y, x = axes
    return x, y, values, crs


def raster_crs(raster: xr.DataArray) -> CRS:
    """Return a raster's CRS, from its ``crs`` attribute, without reading its cells.

    Raises
    ------
    ConfigError
        If the dims are not ``("y", "x")`` or there is no ``crs`` attribute.
    """
    dims = tuple(raster.dims)
    if dims != ("y", "x"):
        raise ConfigError(f"raster dims {dims}: expected ('y', 'x')")
    if "crs" not in raster.attrs:
        raise ConfigError(
            "raster has no 'crs' attribute: give the CRS of its coordinates (WKT)"
        )
    return CRS.from_user_input(raster.attrs["crs"])


def interpolate_wet(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    depth: NDArray[np.float64],
    px: ArrayLike,
    py: ArrayLike,
) -> NDArray[np.float64]:
    """Interpolate depths bilinearly over the wet cells only.

    At a coast the four cells around a point mix land heights with sea depths,
    and plain bilinear interpolation gives a sea point a depth pulled towards
    (or past) zero by the land. Here the bilinear weights are renormalised over
    the wet cells (``depth > 0``, depths positive down), so a point with any wet
    cell around it takes a weighted mean of wet depths alone.

    Parameters
    ----------
    x, y : ndarray of shape (nx,), (ny,)
        Cell-centre coordinates, increasing.
    depth : ndarray of shape (ny, nx)
        Depths, positive down; NaN where missing.
    px, py : array_like of the same shape
        Where to interpolate, in the grid's CRS.

    Returns
    -------
    ndarray of the shape of ``px``
        The wet-weighted depth; ``0.0`` where every cell with a weight is dry
        (the point is on land in the raster); NaN where
        :func:`~coastmesh.geometry.grids.interpolate_bilinear` gives NaN
        (outside, or a missing cell with a weight).

    Examples
    --------
    >>> depth = np.array([[-30.0, 10.0], [20.0, 30.0]])  # one land cell
    >>> interpolate_wet(np.array([0.0, 1.0]), np.array([0.0, 1.0]), depth,
    ...                 [0.5, 0.0], [0.5, 0.0]).tolist()
    [20.0, 0.0]
    """
    px, py = np.broadcast_arrays(
        np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64)
    )
    if len(x) < 2 or len(y) < 2:
        return np.full(px.shape, np.nan)
    bad, corners = bilinear_corners(x, y, px.ravel(), py.ravel())
    total = np.zeros(px.size)
    weights = np.zeros(px.size)
    for (j, i), weight in corners:
        corner = depth[j, i]
        used = weight > 0
        bad |= used & np.isnan(corner)
        with np.errstate(invalid="ignore"):
            wet = used & (corner > 0)
        total += np.where(wet, corner * weight, 0.0)
        weights += np.where(wet, weight, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(weights > 0, total / weights, 0.0)
    out[bad] = np.nan
    return out.reshape(px.shape)
