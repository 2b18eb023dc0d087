"""PCA (singular spectrum) approximation of one shoreline contour.

The contract (Avdis et al. 2015, section II.A) for a contour of ``n`` points, a
partition (window) of ``L`` points and ``r`` modes:

* one partition per point: partition ``k`` holds points ``k .. k+L-1``, cyclically
  for a closed ring (``M = n`` partitions), or ``k = 0 .. n-L`` for an open line
  (``M = n-L+1``);
* x and y are separate problems; ``S`` (L x M) holds the partitions as columns, each
  column loses its mean, ``C = S S^T / M``, eigenvectors by decreasing eigenvalue;
* each column is projected on the first ``r`` eigenvectors and gets its mean back;
* each point is the mean of its reconstructed values over the partitions holding it.

How it is computed fast
-----------------------
The partitions overlap by ``L-1`` points, so ``S`` is a Hankel (trajectory) matrix
and nothing here ever builds it. With ``Q = I - 11^T/L`` the per-partition centring,
``C = Q G Q / M`` where ``G[a, b] = sum_k z[k+a] z[k+b]`` is a lag product:

* closed ring: ``G`` is the Toeplitz matrix of the cyclic autocorrelation of ``z``,
  taken from the linear autocorrelation of the ring extended cyclically by ``L-1``
  points on either side (one FFT), less the lag products of the extensions;
* open line: ``G`` is the Toeplitz matrix of the linear autocorrelation (all windows
  of the zero-padded line) minus the ``2(L-1)`` windows that stick out of the line,
  summed in ``O(L^2)`` by prefix sums along the diagonals.

With ``U`` the leading eigenvectors, partition ``k`` is rebuilt as ``B s_k`` with
``B = U U^T Q + 11^T/L``. Summing the rebuilt partitions over every partition that
holds a point is a correlation of the extended line with the kernel
``h[d] = sum_{m-i=d} B[i, m]`` of ``2L-1`` taps: one FFT convolution reusing the
spectrum above. For a ring the cyclic extension makes the kernel wrap onto itself
when ``n < 2L-1``, so short rings stay exact; for an open line the overhanging
windows are subtracted. Time is ``O(n log n + L^2 r)`` plus the
eigenproblem, memory ``O(n + L^2)``. Small problems take a direct path that builds
the ``M x L`` windows as a strided view, which is faster below about 2^17 values.

Everything is computed on ``x - mean(x)``: the result is shift-equivariant, and
working near zero keeps the lag products well conditioned.
"""

from __future__ import annotations

import numpy as np
import scipy.fft
from numpy.lib.stride_tricks import as_strided, sliding_window_view
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import InputDataError
from coastmesh.pca._eigen import centred_covariance, leading_eigenvectors
from coastmesh.pca.checks import check_modes, check_window
from coastmesh.pca.threads import single_threaded_blas

__all__ = ["contour_modes", "simplify_contour"]

_DIRECT_MAX_VALUES = 1 << 17  # M * L below which the strided direct path is faster


def simplify_contour(
    coords: ArrayLike, window: int, modes: int, *, closed: bool
) -> NDArray[np.float64] | None:
    """Approximate a contour from the leading PCA modes of its partitions.

    Parameters
    ----------
    coords : array_like of shape (n, 2)
        Contour vertices in CRS units. A closed ring is given without its repeated
        closing vertex.
    window : int
        Partition size ``L``, in points (the paper's segment size), ``>= 2``.
    modes : int
        Number of leading modes kept, ``1 <= modes <= window``.
    closed : bool
        Whether the contour is a closed ring (partitions wrap around) or an open line.

    Returns
    -------
    ndarray of shape (n, 2) or None
        The approximated vertices, one per input vertex, or None when ``n < window``
        (the paper's small-island filter).

    Raises
    ------
    ValueError
        If ``coords`` is not of shape (n, 2) or holds NaN or infinite values, or
        if ``window`` or ``modes`` are out of range
        (:class:`~coastmesh.errors.ConfigError`).

    Notes
    -----
    x and y are approximated separately. See the module docstring for the method:
    Hankel embedding, per-partition centring, covariance from lag products,
    projection on the leading eigenvectors and averaging over the overlapping
    partitions as one FFT convolution. ``modes == window`` returns the input to
    rounding.

    References
    ----------
    A. Avdis et al., "Shoreline and bathymetry approximation in mesh generation for
    tidal renewable simulations", EWTEC 2015, section II.A.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    >>> ring = np.c_[np.cos(t), np.sin(t)] + 0.01 * np.c_[np.cos(40 * t), 0 * t]
    >>> out = simplify_contour(ring, 20, 1, closed=True)
    >>> out.shape
    (200, 2)
    >>> bool(np.abs(out[:, 0] - np.cos(t)).max() < np.abs(ring[:, 0] - np.cos(t)).max())
    True
    >>> simplify_contour(ring[:10], 20, 1, closed=False) is None
    True
    """
    xy = _as_coords(coords)
    window = check_window(window)
    modes = check_modes(modes, window)
    if len(xy) < window:
        return None
    shift = xy.mean(axis=0)
    z = (xy - shift).T  # (2, n): x and y are separate problems, batched in the FFTs
    closed = bool(closed)
    n_windows = len(xy) if closed else len(xy) - window + 1
    with single_threaded_blas():
        if n_windows * window <= _DIRECT_MAX_VALUES:
            out = np.stack([_direct(row, window, modes, closed) for row in z])
        else:
            out = _approximate(z, window, modes, closed)
    return (out + shift[:, None]).T


def contour_modes(
    values: ArrayLike, window: int, *, closed: bool
) -> NDArray[np.float64]:
    """Return the eigenvalue spectrum of one coordinate of a contour.

    Parameters
    ----------
    values : array_like of shape (n,)
        One coordinate (x or y) of the contour, ``n >= window``.
    window : int
        Partition size ``L`` in points.
    closed : bool
        Whether the contour is a closed ring.

    Returns
    -------
    ndarray of shape (L,)
        Eigenvalues of the partition covariance, decreasing (CRS units squared).

    Examples
    --------
    >>> import numpy as np
    >>> lam = contour_modes(np.sin(np.arange(100) / 5.0), 10, closed=False)
    >>> bool(lam[0] >= lam[-1] >= -1e-12)
    True
    """
    z = np.asarray(values, dtype=np.float64)
    window = check_window(window)
    if z.ndim != 1 or len(z) < window:
        raise ValueError(f"values must be 1-D with at least window ({window}) points")
    covs = _covariances((z - z.mean())[None, :], window, bool(closed))[2]
    return np.linalg.eigvalsh(covs[0])[::-1]


def _as_coords(coords: ArrayLike) -> NDArray[np.float64]:
    xy = np.asarray(coords, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"coords must have shape (n, 2); got shape {xy.shape}")
    bad = ~np.isfinite(xy).all(axis=1)
    if bad.any():
        vertex = int(np.flatnonzero(bad)[0])
        raise InputDataError(
            f"vertex {vertex} has a non-finite coordinate {tuple(xy[vertex])}"
        )
    return xy


def _approximate(z: NDArray[np.float64], window: int, modes: int, closed: bool):
    """FFT path for ``z`` of shape (k, n): returns the approximated (k, n)."""
    n = z.shape[1]
    spectrum, size, covs = _covariances(z, window, closed)
    kernels = np.zeros((len(z), size))
    corrections = np.zeros((len(z), n))
    for dim, cov in enumerate(covs):
        _, u = leading_eigenvectors(cov, modes)
        kernel = _averaging_kernel(u)  # taps d = -(L-1) .. L-1
        kernels[dim, :window] = kernel[window - 1 :]
        kernels[dim, size - window + 1 :] = kernel[: window - 1]
        if not closed:  # the windows sticking out of the line are not partitions
            for part, offset in zip(
                _overhang(z[dim], window), (-(window - 1), n - window + 1), strict=True
            ):
                corrections[dim] += _scatter(_rebuild(part, u), offset, n)
    # total[j] = sum_d h[d] framed[j + L-1 + d]: a correlation, from the same
    # spectrum; the FFT size leaves room for every tap, so nothing wraps.
    total = scipy.fft.irfft(spectrum * scipy.fft.rfft(kernels).conj(), size)
    total = total[:, window - 1 : window - 1 + n]
    if closed:
        return total / window
    return (total - corrections) / _open_counts(n, window)


def _covariances(z: NDArray[np.float64], window: int, closed: bool):
    """Partition covariances ``C = Q G Q / M`` of each row of ``z`` (k, n).

    Returns the spectrum of the framed rows (ring extended cyclically, or line
    zero-padded, by ``L-1`` points on either side), the FFT size and the
    (k, L, L) covariances. No trajectory matrix is built.
    """
    n = z.shape[1]
    # room for the frame, and for lags up to L-1 past it without wrapping
    size = scipy.fft.next_fast_len(n + (3 if closed else 2) * (window - 1), real=True)
    if closed:
        framed = z[:, np.arange(-(window - 1), n + window - 1) % n]
        spectrum = scipy.fft.rfft(framed, size)
        lags = scipy.fft.irfft(spectrum * spectrum.conj(), size)[:, :window]
        # cyclic lag products sum_j z[j] z[(j+d) mod n]: the frame's lag products
        # less those starting in the L-1 points added before and after the ring
        head = sliding_window_view(framed[:, : 2 * window - 2], window - 1, axis=1)
        lags -= (head[:, :window] @ framed[:, : window - 1, None])[..., 0]
        tail = framed[:, n + window - 1 :]
        for dim in range(len(z)):
            lags[dim, : window - 1] -= np.correlate(tail[dim], tail[dim], "full")[
                window - 2 :
            ]
        grams = [_toeplitz(row) for row in lags]
        n_windows = n
    else:
        framed = np.pad(z, ((0, 0), (window - 1, window - 1)))
        spectrum = scipy.fft.rfft(framed, size)
        lags = scipy.fft.irfft(spectrum * spectrum.conj(), size)[:, :window]
        grams = []
        for dim, row in enumerate(lags):
            gram = _toeplitz(row)
            gram -= _overhang_gram(z[dim], window)
            gram -= _overhang_gram(z[dim, ::-1], window)[::-1, ::-1]
            grams.append(gram)
        n_windows = n - window + 1
    covs = np.stack([centred_covariance(g, n_windows) for g in grams])
    return spectrum, size, covs


def _toeplitz(row: NDArray[np.float64]) -> NDArray[np.float64]:
    """Symmetric Toeplitz matrix ``T[a, b] = row[|b - a|]``."""
    both = np.concatenate([row[:0:-1], row])  # both[L-1+d] = row[|d|]
    return np.ascontiguousarray(sliding_window_view(both, len(row))[::-1])


def _overhang(z: NDArray[np.float64], window: int):
    """Windows of the zero-padded open line that stick out of either end."""
    pad = np.zeros(window - 1)
    head = sliding_window_view(np.concatenate([pad, z[: window - 1]]), window)
    tail = sliding_window_view(np.concatenate([z[len(z) - window + 1 :], pad]), window)
    return head, tail


def _overhang_gram(z: NDArray[np.float64], window: int) -> NDArray[np.float64]:
    """Sum ``s_k s_k^T`` over the windows of the zero-padded line before its start.

    In ``O(L^2)``: ``H[a, a+d] = sum_{j<a} z[j] z[j+d]``, prefix sums of the lag
    products along each diagonal. The windows past the end are this of the
    reversed line, reversed.
    """
    padded = np.concatenate([z[: 2 * window - 2], np.zeros(window)])
    products = padded[: window - 1, None] * sliding_window_view(
        padded[: 2 * window - 2], window
    )  # products[j, d] = z[j] z[j+d]
    sums = np.zeros((window, window))
    np.cumsum(products, axis=0, out=sums[1:])  # sums[a, d] = sum_{j<a}
    upper = _skew(sums)[:, :window]  # upper[a, a+d] = sums[a, d]
    return upper + np.triu(upper, 1).T


def _rebuild(windows: NDArray[np.float64], u: NDArray[np.float64]):
    """Rebuild windows (rows) from modes ``u``: ``U U^T (s - mean) + mean``."""
    mean = windows.mean(axis=1, keepdims=True)
    return ((windows - mean) @ u) @ u.T + mean


def _skew(rows: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return a (K, K+L-1) array holding row ``k`` of ``rows`` (K, L) from column k."""
    count, width = rows.shape
    buffer = np.zeros((count, count + width))
    step = buffer.strides
    as_strided(buffer, shape=rows.shape, strides=(step[0] + step[1], step[1]))[...] = (
        rows
    )
    return buffer[:, : count + width - 1]


def _scatter(rebuilt: NDArray[np.float64], offset: int, n: int):
    """Sum rebuilt windows (rows, starting at ``offset + row``) onto ``n`` points."""
    count, window = rebuilt.shape
    if count > window:  # many windows: the skewed copy would be O(count^2)
        index = offset + np.arange(count)[:, None] + np.arange(window)[None, :]
        keep = (index >= 0) & (index < n)
        return np.bincount(index[keep], weights=rebuilt[keep], minlength=n)
    sums = _skew(rebuilt).sum(axis=0)  # sums[c] goes to point offset + c
    out = np.zeros(n)
    lo, hi = max(offset, 0), min(offset + len(sums), n)
    if hi > lo:
        out[lo:hi] = sums[lo - offset : hi - offset]
    return out


def _averaging_kernel(u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Kernel ``h[d] = sum_{m-i=d} B[i, m]``, ``d = -(L-1) .. L-1``.

    ``B = U U^T Q + 11^T/L`` maps a partition to its reconstruction, and ``h`` sums
    the reconstructions of all partitions that hold a point.
    """
    window = u.shape[0]
    v = u - u.mean(axis=0)  # Q U
    kernel = np.zeros(2 * window - 1)
    for q in range(u.shape[1]):
        kernel += np.correlate(v[:, q], u[:, q], mode="full")
    lags = np.arange(-(window - 1), window)
    return kernel + (window - np.abs(lags)) / window


def _open_counts(n: int, window: int) -> NDArray[np.float64]:
    """Count the partitions of an open line of ``n`` points holding each point."""
    j = np.arange(n)
    last = n - window
    return (np.minimum(j, last) - np.maximum(0, j - window + 1) + 1).astype(float)


def _direct(z: NDArray[np.float64], window: int, modes: int, closed: bool):
    """Strided implementation for small problems: windows as an (M, L) view."""
    n = len(z)
    ext = np.concatenate([z, z[: window - 1]]) if closed else z
    windows = sliding_window_view(ext, window)
    centred = windows - windows.mean(axis=1, keepdims=True)
    cov = centred.T @ centred / len(windows)
    _, u = leading_eigenvectors(0.5 * (cov + cov.T), modes)
    rebuilt = _rebuild(windows, u)
    total = _scatter(rebuilt, 0, len(ext))
    if closed:
        total[: window - 1] += total[n:]
        return total[:n] / window
    return total / _open_counts(n, window)
