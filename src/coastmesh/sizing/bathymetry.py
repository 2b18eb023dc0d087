"""Size from the depth: elements per tidal wavelength, per bathymetric slope."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import GRAVITY

if TYPE_CHECKING:
    pass

__all__ = [
    "M2_PERIOD",
    "slope_size",
    "wavelength_size",
]

#: Period of the principal lunar semi-diurnal tide M2, seconds.
M2_PERIOD = 12.4206012 * 3600.0


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
