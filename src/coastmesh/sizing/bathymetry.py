"""Size from the depth: elements per tidal wavelength, per bathymetric slope."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS, GRAVITY

__all__ = [
    "M2_PERIOD",
    "slope_size",
    "slope_size_sphere",
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


def slope_size_sphere(
    depth: ArrayLike,
    lat: ArrayLike,
    *,
    per_slope: float,
    min_depth: float = 1.0,
    sea: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """:func:`slope_size` on a world longitude/latitude grid, from the sea alone.

    ``h = 2 pi d / (n |grad d|)``, the gradient taken with each grid step's
    true length: ``R cos(lat) dlon`` east-west, ``R dlat`` north-south, and
    across the antimeridian. A difference uses only nodes with a depth in the
    sea: central where both neighbours have one, one-sided where one has, none
    where neither has; so no node of the sea takes a slope from land.

    Parameters
    ----------
    depth : array_like of shape (ny, nx + 1)
        Depth, metres, positive down, at the nodes of a grid of equal steps from
        longitude -180 to 180 (the last column is the first meridian again).
    lat : array_like of shape (ny,)
        The rows' latitudes, degrees, ascending and equally spaced.
    per_slope : float
        Elements per ``2 pi`` topographic length scales (> 0).
    min_depth : float
        Depth floor, metres (> 0): shallower depths are raised to it.
    sea : ndarray of bool, shape (ny, nx + 1), optional
        The nodes in the sea (default: all); NaN depths are not in it either.

    Returns
    -------
    ndarray of shape (ny, nx + 1)
        Sizes, metres: ``inf`` off the sea and where the bottom is flat.

    Notes
    -----
    At a pole (a row at latitude +-90, one point) the east-west difference is
    0: the north-south one, along each meridian, is the slope there.

    Examples
    --------
    Depth growing 1 m per km northward, 3000 m at the equator:

    >>> lat = np.array([-1.0, 0.0, 1.0])
    >>> y = np.radians(lat) * 6_371_008.8
    >>> d = np.repeat((3000.0 + y / 1000.0)[:, None], 9, axis=1)
    >>> h = slope_size_sphere(d, lat, per_slope=10)
    >>> round(float(h[1, 4]))  # 2 pi 3000 m / (10 x 0.001)
    1884956
    """
    if not per_slope > 0:
        raise ConfigError(f"per_slope = {per_slope}: must be > 0")
    d = np.array(depth, dtype=np.float64)
    phi = np.radians(np.asarray(lat, dtype=np.float64))
    if d.ndim != 2 or d.shape[0] != phi.size or d.shape[1] < 5 or phi.size < 2:
        raise ConfigError(f"depth has shape {d.shape}; lat has {phi.size} rows")
    known = np.isfinite(d) if sea is None else np.isfinite(d) & sea
    d = np.where(known & (d < min_depth), min_depth, d)[:, :-1]
    known = known[:, :-1]
    nx = d.shape[1]
    dx = EARTH_RADIUS * np.cos(phi) * (2 * math.pi / nx)
    dy = EARTH_RADIUS * float(phi[1] - phi[0])
    gx = _difference(d, known, dx[:, None], wrap=True)
    gx[np.abs(phi) >= math.pi / 2 - 1e-12] = 0.0  # a pole: one point
    gy = _difference(d.T, known.T, dy, wrap=False).T
    steep = np.hypot(gx, gy)
    with np.errstate(divide="ignore", invalid="ignore"):
        size = np.where(
            known & (steep > 0), 2 * np.pi * d / (per_slope * steep), np.inf
        )
    return np.hstack([size, size[:, :1]])


def _difference(
    d: NDArray[np.float64],
    known: NDArray[np.bool_],
    step: NDArray[np.float64] | float,
    *,
    wrap: bool,
) -> NDArray[np.float64]:
    """Return the derivative along axis 1 from the known neighbours (0 with none)."""
    if wrap:
        after, before = np.roll(d, -1, axis=1), np.roll(d, 1, axis=1)
        k_after, k_before = np.roll(known, -1, axis=1), np.roll(known, 1, axis=1)
    else:
        edge = np.zeros((d.shape[0], 1), dtype=bool)
        after = np.hstack([d[:, 1:], d[:, -1:]])
        before = np.hstack([d[:, :1], d[:, :-1]])
        k_after = np.hstack([known[:, 1:], edge])
        k_before = np.hstack([edge, known[:, :-1]])
    with np.errstate(divide="ignore", invalid="ignore"):
        central = (after - before) / (2 * step)
        forward = (after - d) / step
        backward = (d - before) / step
    out = np.where(
        k_after & k_before,
        central,
        np.where(k_after, forward, np.where(k_before, backward, 0.0)),
    )
    return np.where(known, out, 0.0)
