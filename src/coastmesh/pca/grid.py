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
Let ``z`` be the grid minus a typical value (the mean of the first strip's valid
cells), with missing cells set to zero, and think of it padded with ``w-1`` zeros
on every side. Over *all* windows of the padded grid, sums of products at fixed
offsets are 2-D correlations, one FFT each:

* the covariance uses each window relative to its first cell, a fixed linear map
  of the window's internal x and y differences, so it is assembled from the auto-
  and cross-correlations of the two difference fields (differences between missing
  cells count as zero). FFT rounding then scales with the relief's roughness, not
  with its depth range;
* the sum of the rebuilt windows over all windows is a correlation of ``z`` with a
  ``(2wy-1) x (2wx-1)`` kernel.

Windows with no valid cell contribute nothing; windows with some valid cells that
are not partitions (they overlap the grid's edge or a missing cell) are few, and
both sums subtract them explicitly. The grid is processed in strips of rows in two
passes (covariance, then reconstruction), so working memory stays bounded
(:mod:`coastmesh.pca.chunks` runs each pass on one chunk at a time, for grids
read from a file by parallel tasks). Cost:
``O(N log N)`` for ``N`` cells plus ``O(L r)`` per partial window, against
``O(N L^2)`` for the literal method.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
import scipy.fft
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import ConfigError
from coastmesh.pca._block import Block, cover_counts
from coastmesh.pca._eigen import centred_covariance, leading_eigenvectors
from coastmesh.pca.checks import check_modes, check_window_2d
from coastmesh.types import Progress

__all__ = ["RowSliced", "raster_modes", "simplify_raster"]

_STRIP_CELLS = 1 << 22  # cells per strip of rows (working memory ~100 B a cell)


class RowSliced(Protocol):
    """A grid read by strips of rows: numpy, memmap, h5py, netCDF4, xarray, dask."""

    def __getitem__(self, rows: slice, /) -> ArrayLike:
        """Return the rows ``rows`` of the grid."""


def simplify_raster(
    values: RowSliced,
    window: int | tuple[int, int],
    modes: int,
    *,
    progress: Progress | None = None,
    out: NDArray[np.float64] | None = None,
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
        ``values`` may be any array that slices by rows (numpy, memmap, h5py,
        netCDF4, xarray or dask): it is read in strips of rows, so a grid larger
        than memory can be processed with ``out`` on disk.
    progress : callable, optional
        Called as ``progress(done, total)`` after each strip of each of the two
        passes (covariance, then reconstruction).
    out : array of shape (ny, nx), optional
        Where to write the result, strip by strip (e.g. a ``numpy.memmap``).

    Returns
    -------
    ndarray of shape (ny, nx)
        The approximated grid (``out`` if given), float64. Cells that no complete
        window covers keep their input value; missing cells stay NaN.

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
    wy, wx = check_window_2d(window)
    modes = check_modes(modes, wy * wx)
    shape = _check_grid(values, wy, wx)
    strips = _strips(shape, wy, wx)
    report = progress or (lambda done, total: None)
    steps = 2 * len(strips)

    shift, gram, n_windows, only = _covariance_sums(
        values, strips, wy, wx, report, steps
    )
    if out is None:
        out = np.empty(shape, dtype=np.float64)
    if n_windows == 0:  # no complete window: every cell keeps its value
        for r0, r1 in strips:
            out[r0:r1] = np.asarray(values[r0:r1], dtype=np.float64)
        report(steps, steps)
        return out
    _, u = leading_eigenvectors(centred_covariance(gram, n_windows), modes)
    ny = shape[0]
    for step, (r0, r1) in enumerate(strips, start=len(strips) + 1):
        lo, hi = max(0, r0 - wy + 1), min(ny, r1 + wy - 1)
        if only is not None:  # a single strip: pass 1's block is this one
            b = only
        else:
            b = Block(np.asarray(values[lo:hi], dtype=np.float64), shift, wy, wx)
        out[r0:r1] = _rebuild_rows(b, u, shift, slice(r0 - lo, r1 - lo))[0]
        report(step, steps)
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
    wy, wx = check_window_2d(window)
    shape = _check_grid(values, wy, wx)
    strips = _strips(shape, wy, wx)
    _, gram, n_windows, _ = _covariance_sums(values, strips, wy, wx, None, 0)
    if n_windows == 0:
        raise ValueError("the raster has no complete window without missing cells")
    energy = np.linalg.eigvalsh(centred_covariance(gram, n_windows))[::-1]
    return energy.astype(np.float64, copy=False)


def _check_grid(values, wy: int, wx: int) -> tuple[int, int]:
    shape = tuple(np.shape(values))
    if len(shape) != 2:
        raise ValueError(f"values must be a 2-D grid; got {len(shape)} dimensions")
    ny, nx = shape
    if ny < wy or nx < wx:
        raise ConfigError(
            f"window = {wy} x {wx} cells: larger than the raster ({ny} x {nx} cells)"
        )
    return ny, nx


def _strips(shape: tuple[int, int], wy: int, wx: int) -> list[tuple[int, int]]:
    """Row ranges owned by each strip: the windows whose top row lies in them."""
    ny, nx = shape
    rows = max(4 * wy, _STRIP_CELLS // max(nx + 2 * wx, 1))
    return [(r0, min(ny, r0 + rows)) for r0 in range(0, ny, rows)]


def _covariance_sums(values, strips, wy, wx, report, steps):
    """Pass 1: the shift, the lag products and the count of the partitions.

    Also returns the prepared block when there is only one strip (pass 2 reuses it).

    Strip ``[r0, r1)`` reads rows ``[r0, r1 + wy - 1)``: the partitions wholly in
    that block are exactly those whose top row is in ``[r0, r1)``.
    """
    ny = strips[-1][1]
    gram = np.zeros((wy * wx, wy * wx))
    n_windows = 0
    shift = None
    b = None
    for step, (r0, r1) in enumerate(strips, start=1):
        block = np.asarray(values[r0 : min(ny, r1 + wy - 1)], dtype=np.float64)
        if np.isinf(block).any():
            row, col = np.argwhere(np.isinf(block))[0]
            raise ValueError(
                f"values[{r0 + row}, {col}] is infinite; use NaN for missing cells"
            )
        if shift is None:  # work near zero: the mean of the first valid strip
            valid = np.isfinite(block)
            shift = float(block[valid].mean()) if valid.any() else None
        if shift is not None:
            b = Block(block, shift, wy, wx)
            g, m = _block_gram(b)
            gram += g
            n_windows += m
        if report is not None:
            report(step, steps)
    return shift or 0.0, gram, n_windows, b if len(strips) == 1 else None


def _block_gram(b: Block):
    """``T = sum t_k t_k^T`` over the partitions of a block, and their number.

    ``t_k = s_k - s_k[0]``, the window relative to its first cell, has the same
    centred vector ``Q t_k = Q s_k``, and it is a fixed linear map ``P`` of the
    window's internal differences ``e_k`` (down the first column, then along each
    row). So ``T = P E P^T`` with ``E = sum e_k e_k^T``: over all windows of the
    zero-padded block that is made of the auto- and cross-correlations of the x
    and y difference fields (FFTs), less the partial windows done explicitly.
    Working on differences, not values, keeps the FFT's rounding relative to the
    grid's roughness rather than to its total variance (the depth range).
    """
    wy, wx = b.wy, b.wx
    shape = b.fft_shape
    fx = scipy.fft.rfft2(b.dx, shape)
    fy = scipy.fft.rfft2(b.dy, shape)
    corr = {
        (0, 0): _small_lags(fx.conj() * fx, shape, wy),
        (1, 1): _small_lags(fy.conj() * fy, shape, wy),
        (0, 1): _small_lags(fx.conj() * fy, shape, wy),
    }
    field, oy, ox = _difference_layout(wy, wx)
    lag_y = oy[None, :] - oy[:, None]
    lag_x = ox[None, :] - ox[:, None]
    e = np.empty((len(field), len(field)))
    for (fa, fb), r in corr.items():  # r[d] = sum_j A[j] B[j + d]
        rows, cols = np.ix_(field == fa, field == fb)
        e[rows, cols] = r[lag_y[rows, cols] + wy - 1, lag_x[rows, cols] % shape[1]]
        if fa != fb:
            e[cols.T, rows.T] = e[rows, cols].T
    for _, rows in b.partial_differences():
        e -= rows.T @ rows
    path = _difference_path(wy, wx)
    return path @ e @ path.T, int(b.full.sum())


def _small_lags(product, shape, wy: int) -> NDArray[np.float64]:
    """Inverse 2-D FFT of a cross-spectrum at the row lags ``-(wy-1) .. wy-1`` only.

    Row ``i`` of the result is lag ``i - (wy-1)``; columns are all x lags (mod
    ``shape[1]``). The inverse along y runs on every column, but the inverse
    along x only on the ``2wy-1`` rows needed: about half a full inverse.
    """
    rows = scipy.fft.ifft(product, axis=0)
    wanted = np.arange(-(wy - 1), wy) % shape[0]
    return scipy.fft.irfft(rows[wanted], shape[1], axis=1)


def _difference_layout(wy: int, wx: int):
    """Field (0 = x, 1 = y) and offset of each internal difference of a window."""
    xy_, xx_ = np.divmod(np.arange(wy * (wx - 1)), wx - 1)
    yy_, yx_ = np.divmod(np.arange((wy - 1) * wx), wx)
    field = np.r_[np.zeros(len(xy_), int), np.ones(len(yy_), int)]
    return field, np.r_[xy_, yy_], np.r_[xx_, yx_]


def _difference_path(wy: int, wx: int) -> NDArray[np.float64]:
    """Return ``P`` (L x n_e), mapping a window's differences to its values.

    Cell ``(iy, ix)`` less cell ``(0, 0)`` is the sum of the y differences down
    column 0 and the x differences along row ``iy``.
    """
    n_x = wy * (wx - 1)
    path = np.zeros((wy * wx, n_x + (wy - 1) * wx))
    for iy in range(wy):
        for ix in range(wx):
            a = iy * wx + ix
            path[a, n_x + np.arange(iy) * wx] = 1.0
            path[a, iy * (wx - 1) + np.arange(ix)] = 1.0
    return path


def _rebuild_rows(b: Block, u, shift: float, part: slice | tuple[slice, slice]):
    """Pass 2 on a block: the approximated cells ``part`` and their partition counts.

    Cells that no partition covers keep their value; ``shift`` is added back.
    """
    total, cover = _block_sums(b, u)
    total, cover, block = total[part], cover[part], b.block[part]
    if (cover > 0).all():  # the usual case: every cell is covered
        strip = total / cover
        strip += shift
    else:
        covered = cover > 0
        strip = block.copy()
        strip[covered] = total[covered] / cover[covered] + shift
    return strip, cover


def _block_sums(b: Block, u):
    """Sum of the rebuilt partitions over each cell of a block, and their number."""
    wy, wx = b.wy, b.wx
    ny, nx = b.shape
    # All windows of the zero-padded block: a correlation with the averaging kernel,
    # from the block's spectrum (the FFT shape leaves room for every lag).
    kernel = _averaging_kernel(u, wy, wx)
    ky, kx = np.meshgrid(
        np.arange(-(wy - 1), wy), np.arange(-(wx - 1), wx), indexing="ij"
    )
    folded = np.zeros(b.fft_shape)
    folded[ky % b.fft_shape[0], kx % b.fft_shape[1]] = kernel
    total = scipy.fft.irfft2(b.spectrum * scipy.fft.rfft2(folded).conj(), b.fft_shape)
    total = np.ascontiguousarray(total[:ny, :nx])
    # Less the windows that are not partitions (edges, missing cells), summed in
    # the padded grid, where every cell of every window has an index.
    ny_p, nx_p = ny + 2 * (wy - 1), nx + 2 * (wx - 1)
    cells = (np.repeat(np.arange(wy), wx) * nx_p + np.tile(np.arange(wx), wy))[None, :]
    correction = np.zeros(ny_p * nx_p)
    for corner, windows in b.partial_windows():
        mean = windows.mean(axis=1, keepdims=True)
        np.subtract(windows, mean, out=windows)
        rebuilt = (windows @ u) @ u.T
        rebuilt += mean
        index = (corner[:, 0] * nx_p + corner[:, 1])[:, None] + cells
        correction += np.bincount(
            index.ravel(), weights=rebuilt.ravel(), minlength=correction.size
        )
    total -= correction.reshape(ny_p, nx_p)[wy - 1 : wy - 1 + ny, wx - 1 : wx - 1 + nx]
    return total, cover_counts(b.full, b.complete, wy, wx, ny, nx)


def _averaging_kernel(u: NDArray[np.float64], wy: int, wx: int):
    """Kernel ``h[d] = sum_{m-i=d} B[i, m]`` with ``B = U U^T Q + 11^T/L``."""
    v = (u - u.mean(axis=0)).reshape(wy, wx, -1)
    u = u.reshape(wy, wx, -1)
    kernel = np.zeros((2 * wy - 1, 2 * wx - 1))
    # kernel[d] += U[i] V[i + d]: each cell i of U adds V, shifted by -i
    for iy in range(wy):
        for ix in range(wx):
            kernel[wy - 1 - iy : 2 * wy - 1 - iy, wx - 1 - ix : 2 * wx - 1 - ix] += (
                v @ u[iy, ix]
            )
    dy = wy - np.abs(np.arange(-(wy - 1), wy))
    dx = wx - np.abs(np.arange(-(wx - 1), wx))
    return kernel + np.outer(dy, dx) / (wy * wx)
