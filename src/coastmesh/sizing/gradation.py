"""Size from distance (the paper's gradations) and the gradation limit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError

__all__ = ["DEFAULT_RATE", "Gradation", "gradation_size", "limit_gradation"]

#: The gradation limit of the size field unless a case or a caller sets one
#: (metres per metre). Measured on the paper's NW-shelf meshes, whose gradations
#: grow 1.4-1.5 m per m: without a limit 630 of the 1,306 triangles under 30 deg
#: sat where the size grows faster than 0.5 m per m, and the 1st percentile of
#: the minimum angle was 27.6 (coarse) and 29.7 deg (intermediate). At 0.7 it is
#: 34.1 and 37.5 deg, for 20 % and 18 % more triangles; 0.5 buys 2 deg more for
#: 40 %. OceanMesh2D's default is 0.2 to 0.35.
DEFAULT_RATE = 0.7

#: A sweep's direction: along an axis of the grid, or a diagonal.
_Axis = Literal[0, 1, "diag", "anti"]


def gradation_size(
    distance: ArrayLike, h_min: float, h_max: float, d_hold: float, d_grade: float
) -> NDArray[np.float64]:
    """Target edge length graded by distance from a set of lines.

    ``h_min`` up to ``d_hold`` from the lines, then growing linearly to ``h_max``
    over ``d_grade``, and ``h_max`` beyond (Avdis et al. 2015, section III.C).

    Parameters
    ----------
    distance : array_like
        Distance from the lines, metres.
    h_min, h_max : float
        Sizes at and far from the lines, metres, ``0 < h_min <= h_max``.
    d_hold : float
        Distance over which ``h_min`` is kept, metres, ``>= 0``.
    d_grade : float
        Distance over which the size grows from ``h_min`` to ``h_max``, metres,
        ``> 0``.

    Returns
    -------
    ndarray
        Sizes in metres, the shape of ``distance``, within ``[h_min, h_max]``.

    Examples
    --------
    >>> gradation_size([0, 500, 1500, 9000], 100.0, 1000.0, 1000.0, 2000.0).tolist()
    [100.0, 100.0, 325.0, 1000.0]
    """
    if not 0 < h_min <= h_max:
        raise ConfigError(f"h_min = {h_min}, h_max = {h_max}: need 0 < h_min <= h_max")
    if not d_hold >= 0:
        raise ConfigError(f"d_hold = {d_hold}: must be >= 0 metres")
    if not d_grade > 0:
        raise ConfigError(f"d_grade = {d_grade}: must be > 0 metres")
    d = np.asarray(distance, dtype=np.float64)
    ramp = np.clip((d - d_hold) / d_grade, 0.0, 1.0)
    return np.clip(h_min + (h_max - h_min) * ramp, h_min, h_max)


def limit_gradation(
    size: ArrayLike, spacing: tuple[float, float], rate: float, *, max_sweeps: int = 100
) -> NDArray[np.float64]:
    """Lower a size field until neighbouring sizes never jump more than ``rate``.

    The result ``h`` satisfies ``h(p) <= h(q) + rate * |p - q|`` for all cells
    ``p, q`` (Euclidean distance), ``h <= size``, and it is close to the largest
    such field: ``min_q size(q) + rate * |p - q| / k <= h(p)`` with ``k = 1.0824``
    for square cells (see Notes).

    Parameters
    ----------
    size : array_like of shape (ny, nx)
        Sizes, metres.
    spacing : (float, float)
        Cell size ``(dy, dx)``, metres.
    rate : float
        Largest growth of the size per metre (dimensionless), ``> 0``; e.g. 0.2.
    max_sweeps : int
        Upper bound on relaxation sweeps (each has 8 directions).

    Returns
    -------
    ndarray of shape (ny, nx)

    Notes
    -----
    The largest field below ``size`` whose slope is at most ``rate`` is the
    min-plus convolution of ``size`` with the cone ``rate * |p|``. It is computed
    here along 8-neighbour paths (cumulative minima along rows, columns and both
    diagonals, repeated until nothing changes), with the rate divided by the
    largest excess of such a path over the straight line,
    ``k = 1 / cos(theta / 2)`` with ``theta`` the widest angle between step
    directions (1.0824 for square cells), so the Euclidean bound holds everywhere.
    This is the gradient limiting of Persson (2006, "Mesh size functions for
    implicit geometries and PDE-based gradient limiting"), solved by sweeps rather
    than a PDE.

    Examples
    --------
    >>> h = limit_gradation([[1.0, 100.0, 100.0]], (1.0, 1.0), 0.5)
    >>> bool(h[0, 1] <= 1.5 and h[0, 2] <= 2.0)
    True
    """
    h = np.array(size, dtype=np.float64)
    if h.ndim != 2:
        raise ConfigError(f"size must be a 2-D grid; got {h.ndim} dimensions")
    dy, dx = (float(v) for v in spacing)
    if not (dy > 0 and dx > 0):
        raise ConfigError(f"spacing = {spacing}: cell sizes must be > 0 metres")
    if not rate > 0:
        raise ConfigError(f"rate = {rate}: must be > 0")
    # An 8-neighbour path is at most 1 / cos(theta / 2) longer than the straight
    # line, theta the widest angle between neighbouring step directions (45 deg,
    # so 1.0824, for square cells).
    theta = max(np.arctan2(dy, dx), np.arctan2(dx, dy))
    r = rate * np.cos(theta / 2)
    steps: tuple[tuple[float, _Axis], ...] = (
        (dy, 0),
        (dx, 1),
        (np.hypot(dx, dy), "diag"),
        (np.hypot(dx, dy), "anti"),
    )
    for _ in range(max_sweeps):
        before = h.copy()
        for length, axis in steps:
            h = _sweep(h, r * length, axis)
        # a sweep rounds ``v - ramp + ramp``, so test for no change beyond rounding
        if np.max(before - h, initial=0.0) <= 1e-12 * np.max(h, initial=1.0):
            break
    return h


def _cone_1d(
    values: NDArray[np.float64], step: float, axis: int
) -> NDArray[np.float64]:
    """``min_j values[j] + step |i - j|`` along ``axis``: two cumulative minima."""
    n = values.shape[axis]
    shape = [1, 1]
    shape[axis] = n
    ramp = (np.arange(n, dtype=np.float64) * step).reshape(shape)
    forward = np.minimum.accumulate(values - ramp, axis=axis) + ramp
    flipped = np.flip(values + ramp, axis=axis)
    backward = np.flip(np.minimum.accumulate(flipped, axis=axis), axis=axis) - ramp
    cone: NDArray[np.float64] = np.minimum(forward, backward)  # numpy's stub: Any
    return cone


def _sweep(h: NDArray[np.float64], step: float, axis: _Axis) -> NDArray[np.float64]:
    if axis in (0, 1):
        return _cone_1d(h, step, axis)
    # diagonals: shear the grid so each diagonal becomes a column, then undo
    ny, nx = h.shape
    flip = axis == "anti"
    grid = h[:, ::-1] if flip else h
    sheared = np.full((ny, nx + ny - 1), np.inf)
    rows = np.arange(ny)[:, None]
    cols = np.arange(nx)[None, :] + (ny - 1 - rows)
    sheared[rows, cols] = grid
    done = _cone_1d(sheared, step, 0)  # inf pads the ends of each diagonal only
    out: NDArray[np.float64] = done[rows, cols]
    return out[:, ::-1] if flip else out


@dataclass(frozen=True, slots=True)
class Gradation:
    """The paper's gradation from one set of lines (all lengths in metres).

    Parameters
    ----------
    lines : ndarray of shapely geometries
        The shoreline set (lines or polygons) the size is graded from.
    h_min : float
        Size at the lines.
    d_hold : float
        Distance over which ``h_min`` is kept.
    d_grade : float
        Distance over which the size then grows linearly to the field's ``h_max``.
    name : str
        For reports.
    """

    lines: NDArray[np.object_]
    h_min: float
    d_hold: float
    d_grade: float
    name: str = "gradation"
