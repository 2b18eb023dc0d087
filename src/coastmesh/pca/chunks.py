"""The two passes of the raster PCA, one chunk of the grid at a time.

:func:`~coastmesh.pca.simplify_raster` runs these passes itself, strip of rows
after strip. Here each chunk (a rectangle of cells) is a call on its own, so the
chunks can be computed anywhere and in any order (a process pool, a Dask
cluster), from cells read out of a file, and the grid never has to be in memory
at once:

1. :func:`chunk_gram` on every chunk: the lag products of its partitions and
   their number. Summed over the chunks (in a fixed order, so the result does
   not depend on who computed what), they give the window covariance.
2. :func:`chunk_modes`: its leading eigenvectors, once.
3. :func:`chunk_rebuild` on every chunk: the approximated cells.

A chunk owns rows ``[r0, r1)`` and columns ``[c0, c1)`` of a grid of
``ny x nx`` cells, for windows of ``wy x wx`` cells. Pass 1 reads rows
``[r0, min(ny, r1 + wy - 1))`` and columns ``[c0, min(nx, c1 + wx - 1))``: the
partitions wholly inside them are exactly those whose top left cell is in the
chunk, so every partition is counted once. Pass 2 reads ``wy - 1`` rows and
``wx - 1`` columns more on each side (within the grid): every window that holds
a cell of the chunk.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from coastmesh.pca._block import Block
from coastmesh.pca._eigen import centred_covariance, leading_eigenvectors
from coastmesh.pca.checks import check_modes, check_window_2d
from coastmesh.pca.grid import _block_gram, _rebuild_rows

__all__ = ["chunk_gram", "chunk_modes", "chunk_rebuild"]


def chunk_gram(
    block: ArrayLike, window: int | tuple[int, int], *, shift: float
) -> tuple[NDArray[np.float64], int]:
    """Pass 1 on a chunk: the lag products of its partitions, and their number.

    Parameters
    ----------
    block : array_like of shape (m, n)
        The chunk's cells and ``wy - 1`` rows below and ``wx - 1`` columns to the
        right (within the grid); NaN marks a missing cell.
    window : int or (int, int)
        Window size in cells, square or ``(rows, columns)``.
    shift : float
        A typical value of the grid (such as the mean of the block's valid
        cells), subtracted before the sums to keep them well conditioned. The
        result does not depend on it, to rounding.

    Returns
    -------
    gram : ndarray of shape (L, L)
        ``sum t_k t_k^T`` over the partitions ``k`` wholly inside ``block``, with
        ``t_k`` the window (flattened row by row) less its first cell;
        ``L = rows * columns``.
    count : int
        The number of those partitions.

    Raises
    ------
    ValueError
        If ``block`` is not 2-D or holds infinite values, or ``shift`` is not
        finite.

    Examples
    --------
    >>> import numpy as np
    >>> from coastmesh.pca import simplify_raster
    >>> grid = np.cumsum(np.random.default_rng(3).standard_normal((40, 30)), 0)
    >>> shift = float(grid.mean())
    >>> sums = [chunk_gram(grid[0:23], 4, shift=shift),    # rows 0..19
    ...         chunk_gram(grid[20:40], 4, shift=shift)]   # rows 20..39
    >>> count = sum(m for _, m in sums)
    >>> count == (40 - 3) * (30 - 3)
    True
    >>> u = chunk_modes(sum(g for g, _ in sums), count, 3)
    >>> top, _ = chunk_rebuild(grid[0:23], 4, u, shift=shift, rows=slice(0, 20))
    >>> low, _ = chunk_rebuild(grid[17:40], 4, u, shift=shift, rows=slice(3, 23))
    >>> bool(np.allclose(np.vstack([top, low]), simplify_raster(grid, 4, 3)))
    True
    """
    wy, wx = check_window_2d(window)
    values = _check_block(block, shift)
    size = wy * wx
    if values.shape[0] < wy or values.shape[1] < wx or not np.isfinite(values).any():
        return np.zeros((size, size)), 0
    return _block_gram(Block(values, shift, wy, wx))


def chunk_modes(
    gram: NDArray[np.float64], count: int, modes: int
) -> NDArray[np.float64]:
    """Pass 2's modes: the leading eigenvectors of the window covariance.

    Parameters
    ----------
    gram : ndarray of shape (L, L)
        The sum of :func:`chunk_gram`'s ``gram`` over all the chunks.
    count : int
        The sum of their ``count``: all the partitions, ``>= 1``.
    modes : int
        Leading modes kept, ``1 <= modes <= L``.

    Returns
    -------
    ndarray of shape (L, modes)
        Orthonormal eigenvectors of ``C = Q G Q / count`` (each partition less
        its own mean), by decreasing eigenvalue.

    Raises
    ------
    ValueError
        If ``gram`` is not square, ``count < 1`` or ``modes`` is out of range.
    """
    gram = np.asarray(gram, dtype=np.float64)
    if gram.ndim != 2 or gram.shape[0] != gram.shape[1]:
        raise ValueError(f"gram must be a square matrix; got shape {gram.shape}")
    if count < 1:
        raise ValueError(
            f"count = {count}: no partition (no complete window without missing "
            "cells); nothing to compute modes from"
        )
    modes = check_modes(modes, gram.shape[0])
    return leading_eigenvectors(centred_covariance(gram, count), modes)[1]


def chunk_rebuild(
    block: ArrayLike,
    window: int | tuple[int, int],
    vectors: NDArray[np.float64],
    *,
    shift: float,
    rows: slice,
    columns: slice = slice(None),
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Pass 2 on a chunk: its cells, approximated from the leading modes.

    Parameters
    ----------
    block : array_like of shape (m, n)
        The chunk's cells and ``wy - 1`` rows and ``wx - 1`` columns more on each
        side (within the grid); NaN marks a missing cell.
    window : int or (int, int)
        Window size in cells, square or ``(rows, columns)``.
    vectors : ndarray of shape (L, modes)
        From :func:`chunk_modes`.
    shift : float
        The same typical value for every chunk (such as the mean of the first
        chunk's valid cells): the rebuilt windows are computed less it.
    rows, columns : slice
        The chunk's own rows ``[r0, r1)`` and columns ``[c0, c1)`` within
        ``block``; all the columns by default.

    Returns
    -------
    values : ndarray of shape (r1 - r0, c1 - c0)
        The approximated cells, float64: each the mean of its rebuilt values
        over the partitions that hold it. Cells that no partition covers keep
        their value; missing cells stay NaN.
    cover : ndarray of shape (r1 - r0, c1 - c0)
        The number of partitions holding each cell.

    Raises
    ------
    ValueError
        If ``block`` is not 2-D or holds infinite values, or ``vectors`` does not
        have ``L`` rows.
    """
    wy, wx = check_window_2d(window)
    values = _check_block(block, shift)
    vectors = np.asarray(vectors, dtype=np.float64)
    if vectors.ndim != 2 or vectors.shape[0] != wy * wx:
        raise ValueError(
            f"vectors must have shape ({wy * wx}, modes) for a {wy} x {wx} window; "
            f"got {vectors.shape}"
        )
    part = (rows, columns)
    if values.shape[0] < wy or values.shape[1] < wx:  # no window fits
        cells = values[part].copy()
        return cells, np.zeros(cells.shape, dtype=np.int64)
    return _rebuild_rows(Block(values, shift, wy, wx), vectors, shift, part)


def _check_block(block: ArrayLike, shift: float) -> NDArray[np.float64]:
    values = np.asarray(block, dtype=np.float64)
    if values.ndim != 2:
        raise ValueError(f"block must be 2-D; got {values.ndim} dimensions")
    if not np.isfinite(shift):
        raise ValueError(f"shift = {shift}: must be finite")
    if np.isinf(values).any():
        row, col = np.argwhere(np.isinf(values))[0]
        raise ValueError(f"block[{row}, {col}] is infinite; use NaN for missing cells")
    return values
