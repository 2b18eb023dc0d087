"""Regular grids: the cell around a point, and bilinear interpolation in it.

The one home of bilinear interpolation between the nodes of a rectilinear grid
(1-D ascending axes, values on their nodes). Three layers use it: the depth
rasters (:mod:`coastmesh.depth.raster`), the size grids in the meshing plane
(:func:`coastmesh.geometry.projection.sample_size`, which must read a grid as
Gmsh does), and the longitude/latitude size grid of a global mesh
(:class:`coastmesh.meshing.gmsh.sphere_sizes.SphereSizeGrid`). It lives in
:mod:`coastmesh.geometry` because that is the lowest layer all three may
import (``depth`` and ``meshing`` are above it, ``projection`` is in it;
``pca`` below holds the PCA kernels alone), in a module of its own because it
is about grids, not shorelines or the Earth.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "bilinear_corners",
    "cell_of",
    "interpolate_bilinear",
    "interpolate_nearest",
]

#: One corner of the cells around points: its (rows, columns) and its weights.
Corner = tuple[tuple[NDArray[np.intp], NDArray[np.intp]], NDArray[np.float64]]


def cell_of(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    px: NDArray[np.float64],
    py: NDArray[np.float64],
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Return the cell holding each point: the column and row of its low corner.

    Parameters
    ----------
    x, y : ndarray of shape (nx,), (ny,)
        Node coordinates, strictly increasing, at least two each.
    px, py : ndarray of the same shape
        The points, in the grid's coordinates.

    Returns
    -------
    i, j : ndarray of int
        ``x[i] <= px < x[i + 1]`` and ``y[j] <= py < y[j + 1]``, clipped to
        ``0 .. nx - 2`` and ``0 .. ny - 2``: a point on the last column or row
        is in the last cell, a point outside in the nearest cell.

    Examples
    --------
    >>> axis = np.array([0.0, 1.0, 2.0])
    >>> i, j = cell_of(axis, axis, np.array([0.0, 1.0, 2.0, 5.0]), np.zeros(4))
    >>> i.tolist(), j.tolist()
    ([0, 1, 1, 1], [0, 0, 0, 0])
    """
    i = np.clip(np.searchsorted(x, px, side="right") - 1, 0, len(x) - 2)
    j = np.clip(np.searchsorted(y, py, side="right") - 1, 0, len(y) - 2)
    return i, j


def interpolate_nearest(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    values: NDArray[np.float64],
    px: ArrayLike,
    py: ArrayLike,
) -> NDArray[np.float64]:
    """Return the value of the node nearest each point, along each axis.

    For a raster whose nodes are its cell centres, the value of the cell each
    point is in: classes and codes (a habitat map) keep their values.

    Parameters
    ----------
    x, y : ndarray of shape (nx,), (ny,)
        Node (cell-centre) coordinates, strictly increasing.
    values : ndarray of shape (ny, nx)
        The values at the nodes; NaN where missing.
    px, py : array_like of the same shape
        Where to read, in the grid's coordinates.

    Returns
    -------
    ndarray of the shape of ``px``
        NaN for points beyond half a cell outside the outer nodes (a single
        node along an axis: a cell of no width) and for NaN points. A point
        half-way between two nodes takes the lower one.

    Examples
    --------
    >>> axis = np.array([0.0, 1.0, 2.0])
    >>> v = np.array([[1.0, 2.0, 3.0]] * 3)
    >>> interpolate_nearest(axis, axis, v, [0.4, 0.5, 0.6, 2.5, 2.6], [1.0] * 5)
    array([ 1.,  1.,  2.,  3., nan])
    """
    px, py = np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64)
    i, in_x = _nearest_node(x, px)
    j, in_y = _nearest_node(y, py)
    out = np.asarray(values, dtype=np.float64)[j, i]
    return np.where(in_x & in_y, out, np.nan)


def _nearest_node(
    axis: NDArray[np.float64], p: NDArray[np.float64]
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """Return the node of ``axis`` nearest each ``p``, and which are in its cells.

    In its cells: within half a cell of the outer nodes.
    """
    axis = np.asarray(axis, dtype=np.float64)
    if len(axis) < 2:
        return np.zeros(p.shape, dtype=np.intp), p == axis[0]
    k = np.clip(np.searchsorted(axis, p), 1, len(axis) - 1)
    lower = (p - axis[k - 1]) <= (axis[k] - p)
    node = np.where(lower, k - 1, k)
    half_low = (axis[1] - axis[0]) / 2.0
    half_high = (axis[-1] - axis[-2]) / 2.0
    with np.errstate(invalid="ignore"):
        inside = (p >= axis[0] - half_low) & (p <= axis[-1] + half_high)
    return node.astype(np.intp), inside


def bilinear_corners(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    px: NDArray[np.float64],
    py: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], tuple[Corner, Corner, Corner, Corner]]:
    """Return which points are outside the nodes, and each corner's nodes and weight.

    Parameters
    ----------
    x, y : ndarray of shape (nx,), (ny,)
        Node coordinates, strictly increasing, at least two each.
    px, py : ndarray of shape (n,)
        The points, in the grid's coordinates.

    Returns
    -------
    outside : ndarray of bool, shape (n,)
        Points outside ``[x[0], x[-1]] x [y[0], y[-1]]`` (or NaN): their
        weights extrapolate.
    corners : tuple of 4 ``((rows, cols), weight)``
        The four corners of the cell around each point (:func:`cell_of`), as
        bilinear interpolation weighs them: south-west, south-east,
        north-west, north-east. Inside, the weights are in ``[0, 1]`` and sum
        to 1.

    Examples
    --------
    >>> axis = np.array([0.0, 1.0])
    >>> outside, corners = bilinear_corners(axis, axis, np.array([0.25, 2.0]),
    ...                                     np.array([0.5, 0.5]))
    >>> outside.tolist(), [w[0].item() for _, w in corners]
    ([False, True], [0.375, 0.125, 0.375, 0.125])
    """
    with np.errstate(invalid="ignore"):
        outside = ~((px >= x[0]) & (px <= x[-1]) & (py >= y[0]) & (py <= y[-1]))
    i, j = cell_of(x, y, px, py)
    tx = (px - x[i]) / (x[i + 1] - x[i])
    ty = (py - y[j]) / (y[j + 1] - y[j])
    return outside, (
        ((j, i), (1.0 - tx) * (1.0 - ty)),
        ((j, i + 1), tx * (1.0 - ty)),
        ((j + 1, i), (1.0 - tx) * ty),
        ((j + 1, i + 1), tx * ty),
    )


def interpolate_bilinear(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    values: NDArray[np.float64],
    px: ArrayLike,
    py: ArrayLike,
    *,
    clamp: bool = False,
) -> NDArray[np.float64]:
    """Interpolate a grid bilinearly between its nodes.

    Parameters
    ----------
    x, y : ndarray of shape (nx,), (ny,)
        Node (cell-centre) coordinates, strictly increasing.
    values : ndarray of shape (ny, nx)
        The values at the nodes; NaN where missing.
    px, py : array_like of the same shape
        Where to interpolate, in the grid's coordinates.
    clamp : bool, default False
        Move points outside the nodes onto the nearest edge of the grid (each
        coordinate clipped to its axis), so they take the edge's values, as
        Gmsh reads a size grid; else they are NaN.

    Returns
    -------
    ndarray of the shape of ``px``
        NaN outside the nodes (without ``clamp``), where a corner with a
        weight is missing, and everywhere when the grid has fewer than two
        nodes along an axis. A point on the line between two valid nodes has
        their value even when the nodes beyond the line are missing.

    Notes
    -----
    By hand, not scipy's ``RegularGridInterpolator``: that returns NaN at a
    point on a line of nodes next to a missing node (NaN times a zero weight),
    where the value is defined; here only corners with a weight count. The sum
    runs over the corners in the order of :func:`bilinear_corners`, from
    ``+0.0``, each term the value times its weight; the points whose sum is NaN
    are summed again over the corners with a weight alone.

    Examples
    --------
    >>> grid = np.array([[0.0, 10.0], [20.0, 30.0]])
    >>> axis = np.array([0.0, 1.0])
    >>> interpolate_bilinear(axis, axis, grid, [0.5, 2.0], [0.5, 0.5]).tolist()
    [15.0, nan]
    >>> interpolate_bilinear(axis, axis, grid, [0.5, 2.0], [0.5, 0.5],
    ...                      clamp=True).tolist()
    [15.0, 20.0]
    >>> holed = np.array([[0.0, 10.0], [20.0, np.nan]])
    >>> interpolate_bilinear(axis, axis, holed, [0.5, 0.5], [0.0, 0.5]).tolist()
    [5.0, nan]
    """
    px, py = np.broadcast_arrays(
        np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64)
    )
    if len(x) < 2 or len(y) < 2:
        return np.full(px.shape, np.nan)
    qx, qy = px.ravel(), py.ravel()
    if clamp:
        qx, qy = np.clip(qx, x[0], x[-1]), np.clip(qy, y[0], y[-1])
    bad, corners = bilinear_corners(x, y, qx, qy)
    out = np.zeros(qx.size)
    for (j, i), weight in corners:
        out += values[j, i] * weight
    holed = np.isnan(out) & ~bad  # a missing corner: with a weight, or not
    if holed.any():
        out[holed] = _weighted_only(values, corners, holed)
    out[bad] = np.nan
    return out.reshape(px.shape)


def _weighted_only(
    values: NDArray[np.float64],
    corners: tuple[Corner, ...],
    at: NDArray[np.bool_],
) -> NDArray[np.float64]:
    """Return the bilinear sums at points ``at`` over the corners with a weight.

    NaN where one of those is missing. A corner without a weight adds ``+0.0``
    here, where in the plain sum it adds ``value * 0`` (``+0.0`` or ``-0.0``,
    the same sum once it starts from ``+0.0``; NaN for a missing value).
    """
    out = np.zeros(int(at.sum()))
    missing = np.zeros(out.size, dtype=bool)
    for (j, i), weight in corners:
        corner, w = values[j[at], i[at]], weight[at]
        used = w > 0
        missing |= used & np.isnan(corner)
        out += np.where(used, corner * w, 0.0)
    out[missing] = np.nan
    return out
