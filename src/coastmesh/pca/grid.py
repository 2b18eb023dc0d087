"""PCA approximation of a raster (bathymetry) from 2-D windows.

The contract (Avdis et al. 2015, section II.B) for a grid of ``ny x nx`` cells
(NaN = missing), a window of ``wy x wx`` cells (``L = wy wx``) and ``r`` modes:

* the partitions are all windows lying wholly inside the grid with no missing
  cell, each flattened row-major to a vector of ``L`` values;
* each partition loses its mean, ``C = S S^T / M``, eigenvectors by decreasing
  eigenvalue, projection on the first ``r`` and the mean added back;
* a cell becomes the mean of its reconstructed values over the partitions that
  hold it; a cell that no partition covers keeps its value; missing stays missing.

How it is computed fast
-----------------------
Let ``z`` be the grid minus the mean of its valid cells, with missing cells set to
zero and the grid padded with ``w-1`` zeros on every side. Over *all* windows of the
padded grid, the lag products ``G[a, b] = sum_k z[k+a] z[k+b]`` are the 2-D
autocorrelation of ``z`` (one 2-D FFT), laid out block-Toeplitz. Windows that hold
no valid cell contribute nothing; windows that hold some valid cells but are not
partitions (they overlap the edge of the grid or a missing cell) are few, and their
contribution is subtracted explicitly. The same split serves the reconstruction:
the sum of the rebuilt windows over all windows is a 2-D correlation of ``z`` with a
``(2wy-1) x (2wx-1)`` kernel (one FFT convolution), from which the partial windows
are subtracted. Cost: ``O(N log N)`` for ``N`` cells plus ``O(L r)`` per partial
window, against ``O(N L^2)`` for the literal method; memory ``O(N)``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.fft
import scipy.signal
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError
from coastmesh.pca._checks import check_modes, check_window_2d
from coastmesh.pca._eigen import leading_eigenvectors

__all__ = ["raster_modes", "simplify_raster"]

_CHUNK = 1 << 16  # partial windows handled per batch (memory: _CHUNK * L floats)


def simplify_raster(
    values: ArrayLike,
    window: int | tuple[int, int],
    modes: int,
    *,
    progress: Callable[[int, int], None] | None = None,
) -> NDArray[np.float64]:
    """Approximate a raster from the leading PCA modes of its windows.

    Parameters
    ----------
    values : array_like of shape (ny, nx)
        The grid, row by row; NaN marks a missing cell.
    window : int or (int, int)
        Window size in cells: an int for a square window, or ``(rows, columns)``.
        The paper uses 8 (64 modes).
    modes : int
        Number of leading modes kept, ``1 <= modes <= rows * columns``.
    progress : callable, optional
        Called as ``progress(done, total)`` as the stages finish.

    Returns
    -------
    ndarray of shape (ny, nx)
        The approximated grid, float64. Cells that no complete window covers keep
        their input value; missing cells stay NaN.

    Raises
    ------
    ValueError
        If ``values`` is not 2-D or holds infinite values, if the grid is smaller
        than the window, or if ``window`` or ``modes`` are out of range
        (:class:`~coastmesh.errors.ConfigError`).

    Notes
    -----
    See the module docstring: 2-D Hankel embedding, per-window centring, covariance
    from the 2-D autocorrelation, projection on the leading eigenvectors and
    averaging over overlapping windows as one 2-D FFT convolution, with the windows
    at the edges and at missing cells corrected explicitly. ``modes == rows *
    columns`` returns the input to rounding.

    References
    ----------
    A. Avdis et al., "Shoreline and bathymetry approximation in mesh generation for
    tidal renewable simulations", EWTEC 2015, section II.B.

    Examples
    --------
    >>> import numpy as np
    >>> y, x = np.mgrid[0:40, 0:50]
    >>> smooth = np.sin(x / 8.0) + np.cos(y / 6.0)
    >>> noisy = smooth + 0.1 * np.random.default_rng(0).standard_normal(smooth.shape)
    >>> out = simplify_raster(noisy, 8, 3)
    >>> bool(np.abs(out - smooth).mean() < np.abs(noisy - smooth).mean())
    True
    >>> bool(np.allclose(simplify_raster(noisy, 4, 16), noisy))
    True
    """
    grid = np.asarray(values, dtype=np.float64)
    if grid.ndim != 2:
        raise ValueError(f"values must be a 2-D grid; got {grid.ndim} dimensions")
    wy, wx = check_window_2d(window)
    size = wy * wx
    modes = check_modes(modes, size)
    ny, nx = grid.shape
    if ny < wy or nx < wx:
        raise ConfigError(
            f"window = {wy} x {wx} cells: larger than the raster ({ny} x {nx} cells)"
        )
    if np.isinf(grid).any():
        raise ValueError("values hold infinite values; use NaN for missing cells")
    report = progress or (lambda done, total: None)

    valid = np.isfinite(grid)
    complete = bool(valid.all())
    if not complete and not valid.any():
        return grid.copy()
    shift = grid.mean() if complete else grid[valid].mean()
    z = grid - shift if complete else np.where(valid, grid - shift, 0.0)
    counts = _window_counts(valid, complete, wy, wx)
    full = counts == size  # window corners (in the padded grid) of the partitions
    n_windows = int(full.sum())
    if n_windows == 0:
        return grid.copy()
    partial = np.argwhere((counts > 0) & (counts < size))
    padded = np.pad(z, ((wy - 1, wy - 1), (wx - 1, wx - 1)))
    fft_shape = (
        scipy.fft.next_fast_len(ny + wy - 1, real=True),
        scipy.fft.next_fast_len(nx + wx - 1, real=True),
    )
    spectrum = scipy.fft.rfft2(z, fft_shape)
    report(1, 4)

    gram = _all_window_gram(spectrum, fft_shape, wy, wx)
    for rows in _partial_windows(padded, partial, wy, wx):
        gram -= rows.T @ rows
    row = gram.mean(axis=0)
    cov = (gram - row[None, :] - row[:, None] + row.mean()) / n_windows
    _, u = leading_eigenvectors(0.5 * (cov + cov.T), modes)
    report(2, 4)

    # Sum of the rebuilt windows over all windows of the zero-padded grid: a
    # correlation with the averaging kernel, computed with the spectrum above (the
    # FFT shape leaves room for every lag, so nothing wraps onto the grid).
    kernel = _averaging_kernel(u, wy, wx)
    ky, kx = np.meshgrid(np.arange(-(wy - 1), wy), np.arange(-(wx - 1), wx), indexing="ij")
    folded = np.zeros(fft_shape)
    folded[ky % fft_shape[0], kx % fft_shape[1]] = kernel
    total = scipy.fft.irfft2(spectrum * scipy.fft.rfft2(folded).conj(), fft_shape)
    total = np.ascontiguousarray(total[:ny, :nx])
    report(3, 4)
    # Remove the windows that are not partitions (edges, missing cells).
    flat = total.ravel()
    offset_y = np.repeat(np.arange(wy), wx)[None, :] - (wy - 1)
    offset_x = np.tile(np.arange(wx), wy)[None, :] - (wx - 1)
    for start, rows in zip(
        range(0, len(partial), _CHUNK),
        _partial_windows(padded, partial, wy, wx),
        strict=True,
    ):
        mean = rows.mean(axis=1, keepdims=True)
        rows -= mean
        rebuilt = (rows @ u) @ u.T
        rebuilt += mean
        corner = partial[start : start + _CHUNK]
        iy = corner[:, 0, None] + offset_y
        ix = corner[:, 1, None] + offset_x
        inside = (iy >= 0) & (iy < ny) & (ix >= 0) & (ix < nx)
        flat -= np.bincount(
            (iy * nx + ix)[inside], weights=rebuilt[inside], minlength=flat.size
        )
    cover = _cover_counts(full, complete, wy, wx, ny, nx)
    if complete:  # every cell is covered
        out = total / cover
        out += shift
    else:
        covered = cover > 0
        out = grid.copy()
        out[covered] = total[covered] / cover[covered] + shift
    report(4, 4)
    return out


def raster_modes(
    values: ArrayLike, window: int | tuple[int, int]
) -> NDArray[np.float64]:
    """Return the eigenvalue spectrum of the window covariance of a raster.

    Parameters
    ----------
    values : array_like of shape (ny, nx)
        The grid; NaN marks a missing cell.
    window : int or (int, int)
        Window size in cells.

    Returns
    -------
    ndarray of shape (rows * columns,)
        Eigenvalues, decreasing, in the grid's units squared: the energy per mode.

    Examples
    --------
    >>> import numpy as np
    >>> lam = raster_modes(np.random.default_rng(1).standard_normal((30, 30)), 4)
    >>> lam.shape
    (16,)
    """
    grid = np.asarray(values, dtype=np.float64)
    wy, wx = check_window_2d(window)
    if grid.ndim != 2 or grid.shape[0] < wy or grid.shape[1] < wx:
        raise ConfigError(f"window = {wy} x {wx} cells: larger than the raster")
    view = sliding_window_view(grid, (wy, wx))
    ok = np.isfinite(view).all(axis=(2, 3))
    if not ok.any():
        raise ValueError("the raster has no complete window without missing cells")
    valid = np.isfinite(grid)
    complete = bool(valid.all())
    z = np.where(valid, grid - grid[valid].mean(), 0.0)
    padded = np.pad(z, ((wy - 1, wy - 1), (wx - 1, wx - 1)))
    counts = _window_counts(valid, complete, wy, wx)
    fft_shape = (
        scipy.fft.next_fast_len(grid.shape[0] + wy - 1, real=True),
        scipy.fft.next_fast_len(grid.shape[1] + wx - 1, real=True),
    )
    gram = _all_window_gram(scipy.fft.rfft2(z, fft_shape), fft_shape, wy, wx)
    partial = np.argwhere((counts > 0) & (counts < wy * wx))
    for rows in _partial_windows(padded, partial, wy, wx):
        gram -= rows.T @ rows
    row = gram.mean(axis=0)
    cov = (gram - row[None, :] - row[:, None] + row.mean()) / int(ok.sum())
    return np.linalg.eigvalsh(0.5 * (cov + cov.T))[::-1]


def _box_sum(mask: NDArray, wy: int, wx: int) -> NDArray[np.int64]:
    """Sum of ``mask`` over every ``wy x wx`` window of ``mask`` zero-padded by
    ``w-1`` on every side; index = window corner in the padded grid."""
    padded = np.pad(mask.astype(np.int64), ((wy, wy - 1), (wx, wx - 1)))
    cs = padded.cumsum(axis=0).cumsum(axis=1)
    return cs[wy:, wx:] - cs[:-wy, wx:] - cs[wy:, :-wx] + cs[:-wy, :-wx]


def _ones_box_1d(n: int, w: int) -> NDArray[np.int64]:
    """Cells of a row of ``n`` ones inside each of the ``n+w-1`` padded windows."""
    p = np.arange(n + w - 1)
    return np.minimum(p, n - 1) - np.maximum(p - (w - 1), 0) + 1


def _window_counts(valid, complete: bool, wy: int, wx: int) -> NDArray[np.int64]:
    """Valid cells in each window of the padded grid; index = window corner."""
    if complete:  # separable: rows inside times columns inside
        ny, nx = valid.shape
        return np.outer(_ones_box_1d(ny, wy), _ones_box_1d(nx, wx))
    return _box_sum(valid, wy, wx)


def _cover_counts(full, complete: bool, wy: int, wx: int, ny: int, nx: int):
    """Partitions holding each cell of the ``ny x nx`` grid.

    ``full[p]`` marks the partition whose corner is cell ``p - (w-1)`` of the grid.
    """
    if complete:  # partitions start at 0 .. n-w along each axis
        return np.outer(_ones_box_1d(ny - wy + 1, wy), _ones_box_1d(nx - wx + 1, wx))
    starts = full[wy - 1 : wy - 1 + ny - wy + 1, wx - 1 : wx - 1 + nx - wx + 1]
    return _box_sum(starts, wy, wx)


def _all_window_gram(spectrum, fft_shape, wy: int, wx: int) -> NDArray[np.float64]:
    """``G[a, b]`` summed over all windows of the zero-padded grid.

    That is the 2-D autocorrelation of the grid at lag ``b - a``, from its spectrum.
    """
    acf = scipy.fft.irfft2(spectrum * spectrum.conj(), fft_shape)
    ay, ax = np.divmod(np.arange(wy * wx), wx)
    lag_y = (ay[None, :] - ay[:, None]) % fft_shape[0]
    lag_x = (ax[None, :] - ax[:, None]) % fft_shape[1]
    return acf[lag_y, lag_x]


def _partial_windows(padded, corners, wy: int, wx: int):
    """Yield the windows at ``corners`` of the padded grid as (n, L) row batches."""
    view = sliding_window_view(padded, (wy, wx))
    for start in range(0, len(corners), _CHUNK):
        c = corners[start : start + _CHUNK]
        yield view[c[:, 0], c[:, 1]].reshape(len(c), wy * wx)


def _averaging_kernel(u: NDArray[np.float64], wy: int, wx: int):
    """Kernel ``h[d] = sum_{m-i=d} B[i, m]`` with ``B = U U^T Q + 11^T/L``."""
    v = u - u.mean(axis=0)
    kernel = np.zeros((2 * wy - 1, 2 * wx - 1))
    for q in range(u.shape[1]):
        kernel += scipy.signal.correlate(
            v[:, q].reshape(wy, wx), u[:, q].reshape(wy, wx), mode="full"
        )
    dy = wy - np.abs(np.arange(-(wy - 1), wy))
    dx = wx - np.abs(np.arange(-(wx - 1), wx))
    return kernel + np.outer(dy, dx) / (wy * wx)
