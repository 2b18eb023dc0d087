"""PCA of many contours at once: small ones batched, the work spread over threads.

A world shoreline has hundreds of thousands of rings, most of a few hundred points
or fewer. Done one by one (:func:`~coastmesh.pca.simplify_contour`), each such
ring pays for its own Python calls and its own ``L x L`` eigenproblems. Here the
contours that the per-contour kernel would take its direct path for are sorted
by length and grouped; each group is padded to its longest member and computed
as stacked arrays:

* **Rings.** ``G[a, b] = r[|b - a|]``, the Toeplitz matrix of the cyclic lag
  products ``r[d] = sum_j z[j] z[(j+d) mod n]``, summed directly over strided
  views; ``C = Q G Q / M`` as in :func:`~coastmesh.pca.simplify_contour`. As ``G``
  and ``Q`` commute with the exchange matrix ``J`` (reversal), so does ``C``: its
  eigenvectors are symmetric ``[x; Jx]`` or skew ``[x; -Jx]``, the eigenvectors
  of the two half-size matrices ``A + B`` and ``A - B`` (``A`` the leading block
  of ``C``, ``B`` its reversed off-diagonal block). Two ``L/2`` eigenproblems
  cost about a quarter of one of size ``L``. Each point is then the correlation
  of the cyclically extended ring with the averaging kernel ``h`` of the modes.
* **Open lines.** The centred windows are built (``M x L`` each, as in the direct
  path), the covariances are one stacked product, and the rebuilt windows are
  summed back diagonal by diagonal.

The leading eigenpairs come from LAPACK's ``evr`` (as in the per-contour kernel),
called through ctypes so that it releases the GIL. Longer contours go to
:func:`~coastmesh.pca.simplify_contour` one by one. Batches and long contours are
tasks for a thread pool, with BLAS kept to one thread; each task writes its own
rows of the output, and the split does not depend on the number of threads, so
neither does the result (bit for bit). It agrees with the per-contour kernel to
rounding (``U U^T`` does not depend on the signs of the eigenvectors).
"""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import cython_lapack, lapack

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.pca import line
from coastmesh.pca.checks import check_modes, check_window, deterministic_start
from coastmesh.pca.threads import single_threaded_blas
from coastmesh.types import local_cores

__all__ = ["check_workers", "simplify_contours", "simplify_packed"]

_BATCH_VALUES = 1 << 21  # rows x (L^2 or M L) of one batch: about 16 MB per array
_STRETCH = 1.25  # the longest contour of a batch is at most this times its shortest


def check_workers(workers: object) -> int:
    """Return the number of threads: ``None`` means every core this process may use.

    Examples
    --------
    >>> check_workers(2)
    2
    >>> check_workers(None) >= 1
    True
    """
    if workers is None:
        return local_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"workers = {workers!r}: must be a positive integer or None")
    return workers


def simplify_contours(
    contours: Sequence[ArrayLike],
    window: int,
    modes: int,
    *,
    closed: bool | Sequence[bool],
    workers: int | None = None,
) -> list[NDArray[np.float64] | None]:
    """Approximate many contours, as :func:`~coastmesh.pca.simplify_contour` each.

    Parameters
    ----------
    contours : sequence of array_like of shape (n_i, 2)
        Contour vertices; a closed ring without its repeated closing vertex.
    window : int
        Partition size ``L`` in points, ``>= 2``.
    modes : int
        Leading modes kept, ``1 <= modes <= window``.
    closed : bool or sequence of bool
        Whether each contour (or every contour) is a closed ring.
    workers : int, optional
        Threads to use; all the cores by default. The result does not depend on it.

    Returns
    -------
    list of ndarray of shape (n_i, 2) or None
        One per contour; None for those with fewer than ``window`` points.

    Raises
    ------
    ValueError
        If a contour is not of shape (n, 2) or ``closed`` not one flag per contour;
        ``InputDataError`` for a non-finite vertex, ``ConfigError`` for a bad
        ``window``, ``modes`` or ``workers``.

    Examples
    --------
    >>> import numpy as np
    >>> from coastmesh.pca import simplify_contour
    >>> t = np.linspace(0, 2 * np.pi, 300, endpoint=False)
    >>> rings = [np.c_[np.cos(t), np.sin(t) + 0.01 * np.cos(50 * t)], np.eye(2)]
    >>> out = simplify_contours(rings, 30, 1, closed=True)
    >>> out[1] is None
    True
    >>> one = simplify_contour(rings[0], 30, 1, closed=True)
    >>> bool(np.abs(out[0] - one).max() < 1e-12)
    True
    """
    arrays = [np.asarray(c, dtype=np.float64) for c in contours]
    for k, xy in enumerate(arrays):
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise ValueError(f"contour {k}: coords must have shape (n, 2); {xy.shape}")
    if np.ndim(closed) and np.shape(closed) != (len(arrays),):
        raise ValueError(f"closed has {np.size(closed)} flags, {len(arrays)} contours")
    flags = np.broadcast_to(np.asarray(closed, dtype=bool), (len(arrays),))
    counts = np.array([len(a) for a in arrays], dtype=np.int64)
    starts = np.cumsum(counts) - counts
    coords = np.concatenate(arrays) if arrays else np.empty((0, 2))
    out = simplify_packed(
        coords, starts, counts, window, modes, closed=flags, workers=workers
    )
    return [
        out[s : s + n] if n >= window else None
        for s, n in zip(starts.tolist(), counts.tolist(), strict=True)
    ]


def simplify_packed(
    coords: NDArray[np.float64],
    starts: ArrayLike,
    counts: ArrayLike,
    window: int,
    modes: int,
    *,
    closed: ArrayLike,
    workers: int | None = None,
    progress: Callable[[int, int], object] | None = None,
    out: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """Approximate contours stored as rows of one coordinate array.

    Parameters
    ----------
    coords : ndarray of shape (P, 2)
        Vertices; contour ``i`` is ``coords[starts[i] : starts[i] + counts[i]]``
        (a ring without its closing vertex). Rows outside every contour are
        ignored.
    starts, counts : array_like of int, shape (K,)
        Where each contour starts, and its number of points.
    window, modes : int
        Partition size ``L`` and leading modes kept.
    closed : array_like of bool, shape (K,)
        Whether each contour is a closed ring.
    workers : int, optional
        Threads to use; all the cores by default. The result does not depend on it.
    progress : callable, optional
        Called as ``progress(points_done, points_total)`` from the calling thread,
        over the contours of at least ``window`` points.
    out : ndarray of shape (P, 2), optional
        Where to write the result; may be ``coords`` itself (each contour is read
        before its rows are written).

    Returns
    -------
    ndarray of shape (P, 2)
        ``out``, with the approximated vertices in the rows of their contour; the
        other rows are NaN if ``out`` was not given, untouched if it was.

    Raises
    ------
    InputDataError
        If a vertex of a contour is not finite (``feature`` is the contour).
    ConfigError
        If ``window``, ``modes`` or ``workers`` is out of range.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    >>> xy = np.r_[np.c_[np.cos(t), np.sin(t)], [[5.0, 5.0]] * 3]
    >>> out = simplify_packed(xy, [0, 40], [40, 3], 8, 1, closed=[True, False])
    >>> out.shape, bool(np.isnan(out[40:]).all())
    ((43, 2), True)
    """
    window = check_window(window)
    modes = check_modes(modes, window)
    workers = check_workers(workers)
    coords = np.asarray(coords, dtype=np.float64)
    starts = np.asarray(starts, dtype=np.int64).ravel()
    counts = np.asarray(counts, dtype=np.int64).ravel()
    closed = np.broadcast_to(np.asarray(closed, dtype=bool), counts.shape)
    _check_finite(coords, starts, counts)
    if out is None:
        out = np.full(coords.shape, np.nan)
    elif out.shape != coords.shape or out.dtype != np.float64:
        raise ValueError(f"out must be float64 of shape {coords.shape}")
    tasks = _plan(coords, starts, counts, closed, window, modes, out)
    total = int(counts[counts >= window].sum())
    done = 0
    with single_threaded_blas():  # held here: the threads never change the limit
        if workers == 1 or len(tasks) < 2:
            for task in tasks:
                done += task()
                if progress is not None:
                    progress(done, total)
            return out
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(task) for task in tasks]
            try:
                for future in as_completed(futures):
                    done += future.result()
                    if progress is not None:
                        progress(done, total)
            except BaseException:
                pool.shutdown(wait=False, cancel_futures=True)
                raise
    return out


def _check_finite(coords, starts, counts) -> None:
    if np.isfinite(coords).all():
        return
    owner = np.repeat(np.arange(len(counts)), counts)
    rows = np.arange(len(owner)) + np.repeat(
        starts - np.cumsum(counts) + counts, counts
    )
    bad = np.flatnonzero(~np.isfinite(coords[rows]).all(axis=1))
    if bad.size:
        contour, row = int(owner[bad[0]]), rows[bad[0]]
        raise InputDataError(
            f"contour {contour}, vertex {row - starts[contour]} has a non-finite "
            f"coordinate {tuple(coords[row])}",
            feature=contour,
        )


def _plan(coords, starts, counts, closed, window, modes, out) -> list[Callable]:
    """Tasks, costliest first: long contours one by one, short ones in batches.

    The split depends only on the contours, never on the number of threads.
    """
    kept = counts >= window
    n_windows = np.where(closed, counts, counts - window + 1)
    long = kept & (n_windows * window > line._DIRECT_MAX_VALUES)
    tasks = []  # (cost estimate, task)
    for c in np.flatnonzero(long).tolist():
        n = int(counts[c])
        task = _one(coords, out, int(starts[c]), n, window, modes, bool(closed[c]))
        tasks.append((60.0 * n * np.log2(n), task))
    short = np.flatnonzero(kept & ~long)
    short = short[np.lexsort((counts[short], ~closed[short]))]
    # values per contour in a batch: its L x L covariance, or a line's M x L windows
    values = np.where(closed, window * window, np.maximum(n_windows, window) * window)
    group: list[int] = []
    for c in [*short.tolist(), -1]:
        if group and (
            c < 0
            or closed[c] != closed[group[0]]
            or counts[c] > _STRETCH * counts[group[0]]
            or 2 * (len(group) + 1) * values[c] > _BATCH_VALUES
        ):
            sel, ring = np.array(group), bool(closed[group[0]])
            cost = len(group) * (window**3 / 2 + 8.0 * counts[group[-1]] * window)
            task = _batch(coords, out, starts[sel], counts[sel], window, modes, ring)
            tasks.append((cost, task))
            group = []
        if c >= 0:
            group.append(c)
    tasks.sort(key=lambda t: -t[0])
    return [task for _, task in tasks]


def _one(coords, out, start, n, window, modes, closed) -> Callable[[], int]:
    def run() -> int:
        rows = slice(start, start + n)
        out[rows] = line.simplify_contour(coords[rows], window, modes, closed=closed)
        return n

    return run


def _batch(coords, out, starts, counts, window, modes, closed) -> Callable[[], int]:
    def run() -> int:
        inside = np.arange(counts.max()) < counts[:, None]  # (k, N)
        rows = (starts[:, None] + np.arange(counts.max()))[inside]
        kernel = _ring_batch if closed else _line_batch
        values, shift = kernel(coords, starts, counts, inside, window, modes)
        xy = values.reshape(len(counts), 2, -1).transpose(0, 2, 1) + shift[:, None]
        out[rows] = xy[inside]  # each contour's mean added back
        return int(counts.sum())

    return run


def _frame(coords, starts, counts, inside, index):
    """Rows ``(x, y)`` per contour of ``coords[start + index]``, less each mean."""
    xy = coords[starts[:, None] + index]  # (k, W, 2)
    own = coords[(starts[:, None] + np.arange(inside.shape[1]))[inside]]
    owner = np.repeat(np.arange(len(counts)), counts)
    shift = np.stack([np.bincount(owner, w) for w in own.T], axis=1) / counts[:, None]
    rows = (xy - shift[:, None, :]).transpose(0, 2, 1).reshape(2 * len(counts), -1)
    return np.ascontiguousarray(rows), shift


def _ring_batch(coords, starts, counts, inside, window, modes):
    """Approximate closed rings padded to the longest: (x, y) rows less the mean."""
    size = inside.shape[1]
    span = np.arange(-(window - 1), size + window - 1)
    framed, shift = _frame(coords, starts, counts, inside, span % counts[:, None])
    n = np.repeat(counts, 2)
    z = framed[:, window - 1 : window - 1 + size] * np.repeat(inside, 2, axis=0)
    ahead = sliding_window_view(framed[:, window - 1 :], window, axis=1)  # (2k, N, L)
    lags = np.einsum("rj,rjd->rd", z, ahead)  # cyclic: r[d] = sum_j z[j] z[j+d]
    even, odd = _halves(lags, n)
    u = _centrosymmetric_modes(even, odd, window, modes)
    taps = sliding_window_view(framed, 2 * window - 1, axis=1)[:, :size]
    total = np.einsum("rji,ri->rj", taps, _kernels(u))
    return total / window, shift


def _line_batch(coords, starts, counts, inside, window, modes):
    """Approximate open lines padded to the longest: (x, y) rows less the mean."""
    size = inside.shape[1]
    index = np.minimum(np.arange(size), counts[:, None] - 1)
    framed, shift = _frame(coords, starts, counts, inside, index)
    n_windows = np.repeat(counts - window + 1, 2)
    windows = sliding_window_view(framed, window, axis=1)  # (2k, K, L)
    real = np.arange(windows.shape[1]) < n_windows[:, None]
    mean = windows.mean(axis=2, keepdims=True)
    centred = (windows - mean) * real[..., None]
    cov = np.matmul(centred.transpose(0, 2, 1), centred) / n_windows[:, None, None]
    leading = _Leading(window, modes)
    u = np.stack([leading(0.5 * (c + c.T))[1] for c in cov])
    rebuilt = (np.matmul(np.matmul(centred, u), u.transpose(0, 2, 1)) + mean) * real[
        ..., None
    ]
    total = np.zeros((len(framed), size))
    for i in range(window):
        total[:, i : i + windows.shape[1]] += rebuilt[:, :, i]
    j = np.arange(size)
    last = n_windows[:, None] - 1
    cover = np.minimum(j, last) - np.maximum(0, j - window + 1) + 1
    return total / np.maximum(cover, 1), shift


def _halves(lags, count):
    """Return ``A + B`` and ``A - B`` of ``C = Q G Q / M``, ``G[a, b] = r[|a - b|]``.

    ``A`` is the leading ``L/2`` block of ``C`` and ``B[a, b] = C[a, L-1-b]``; for
    odd ``L`` the first matrix has one more row and column for the middle point,
    scaled so that ``[x; sqrt(2) y; Jx]`` is an eigenvector of ``C``.
    """
    rows, size = lags.shape
    half = size // 2
    total = np.cumsum(lags, axis=1)
    row = (total + total[:, ::-1] - lags[:, :1]) / size  # mean over b of G[a, b]
    mean = row.mean(axis=1)
    a = np.arange(half)
    near = lags[:, np.abs(a[:, None] - a[None, :])]  # G[a, b]
    far = lags[:, size - 1 - a[:, None] - a[None, :]]  # G[a, L-1-b]
    scale = 1.0 / count[:, None, None]
    odd = (near - far) * scale  # the centring terms cancel
    centring = row[:, :half, None] + row[:, None, :half] - mean[:, None, None]
    even = np.empty((rows, size - half, size - half))
    even[:, :half, :half] = (near + far - 2.0 * centring) * scale
    if size % 2:
        middle = lags[:, half - a] - row[:, :half] - (row[:, half] - mean)[:, None]
        even[:, :half, half] = np.sqrt(2.0) * middle * scale[:, 0]
        even[:, half, :half] = even[:, :half, half]
        even[:, half, half] = (lags[:, 0] - 2.0 * row[:, half] + mean) * scale[:, 0, 0]
    return even, odd


def _centrosymmetric_modes(even, odd, size, modes):
    """Leading eigenvectors (R, L, modes) of ``C`` from its halves (overwritten).

    For one mode, a half is not solved if its top eigenvalue is surely the smaller:
    its Frobenius norm (both are semi-definite) is below a Rayleigh quotient of the
    other half.
    """
    rows, half = len(odd), size // 2
    vectors = np.zeros((rows, size, 2 * modes))
    values = np.full((rows, 2 * modes), -np.inf)
    solve = np.ones((2, rows), dtype=bool)
    if modes == 1:
        norms = [np.sqrt(np.einsum("rab,rab->r", h, h)) for h in (even, odd)]
        low = [_rayleigh(h) for h in (even, odd)]
        solve[0] = ~(low[1] > norms[0] * (1.0 + 1e-9))
        solve[1] = ~(low[0] > norms[1] * (1.0 + 1e-9))
    leading_even = _Leading(size - half, min(modes, size - half))
    leading_odd = _Leading(half, min(modes, half))
    for r in np.flatnonzero(solve[0]).tolist():
        w, v = leading_even(even[r])
        values[r, : len(w)] = w
        vectors[r, : len(v), : len(w)] = v
        vectors[r, size - half :, : len(w)] = v[:half][::-1]
    for r in np.flatnonzero(solve[1]).tolist():
        w, v = leading_odd(odd[r])
        values[r, modes : modes + len(w)] = w
        vectors[r, :half, modes : modes + len(w)] = v
        vectors[r, size - half :, modes : modes + len(w)] = -v[::-1]
    if size % 2:
        vectors[:, half, :modes] *= np.sqrt(2.0)
    vectors /= np.sqrt(2.0)
    order = np.argsort(-values, axis=1, kind="stable")[:, :modes]
    return np.take_along_axis(vectors, order[:, None, :], axis=2)


def _rayleigh(matrices, steps: int = 3):
    """Rayleigh quotients (below the top eigenvalues) after power steps."""
    v = np.tile(deterministic_start(matrices.shape[1]), (len(matrices), 1))
    for _ in range(steps):
        v = np.einsum("rab,rb->ra", matrices, v)
        v /= np.maximum(np.linalg.norm(v, axis=1), 1e-300)[:, None]
    return np.einsum("ra,rab,rb->r", v, matrices, v)


class _Leading:
    """The ``count`` leading eigenpairs of symmetric ``size x size`` matrices.

    LAPACK ``dsyevr`` through its C pointer in ``scipy.linalg.cython_lapack``,
    called with ctypes, which releases the GIL (scipy's Python wrapper keeps it),
    with one workspace for every call. Each thread needs its own.
    """

    def __init__(self, size: int, count: int) -> None:
        self.size, self.count = size, count
        self.w, self.z = np.empty(size), np.empty((count, size))
        self.work, self.iwork = np.empty(26 * size), np.empty(10 * size, np.int32)
        self.isuppz = np.empty(2 * size, np.int32)
        # n, lda, il, iu, m (out), ldz, lwork, liwork, info (out)
        self.ints = np.array([size, size, size - count + 1, size, 0, size], np.int32)
        self.ints = np.r_[self.ints, 26 * size, 10 * size, 0].astype(np.int32)
        self.reals = np.array([0.0, 1.0, 0.0])  # vl, vu (not used), abstol
        self.flags = np.frombuffer(b"VIU", dtype=np.uint8).copy()
        i, r, f = (a.ctypes.data for a in (self.ints, self.reals, self.flags))
        self.args = [f, f + 1, f + 2, i, 0, i + 4, r, r + 8, i + 8, i + 12, r + 16]
        self.args += [i + 16, self.w.ctypes.data, self.z.ctypes.data, i + 20]
        self.args += [self.isuppz.ctypes.data, self.work.ctypes.data, i + 24]
        self.args += [self.iwork.ctypes.data, i + 28, i + 32]

    def __call__(self, matrix):
        """Return values (decreasing) and vectors (columns); ``matrix`` is scratch."""
        function = _dsyevr()
        if function is None:  # no C pointer: scipy's wrapper
            w, z, found, _, info = lapack.dsyevr(
                matrix, compute_v=1, range="I", il=int(self.ints[2]), iu=self.size
            )
            z = z.T
        else:
            matrix = np.ascontiguousarray(matrix, dtype=np.float64)
            self.args[4] = matrix.ctypes.data  # symmetric: C order is Fortran order
            function(*self.args)
            w, z, found, info = self.w, self.z, self.ints[4], self.ints[8]
        if info != 0 or found != self.count:  # pragma: no cover - LAPACK failure
            raise np.linalg.LinAlgError(f"LAPACK dsyevr failed (info = {info})")
        return w[self.count - 1 :: -1].copy(), z[::-1].T.copy()


@functools.cache
def _dsyevr():
    """``dsyevr`` as a ctypes function, or None if scipy does not export it."""
    try:
        capsule = cython_lapack.__pyx_capi__["dsyevr"]
        name = ctypes.PYFUNCTYPE(ctypes.c_char_p, ctypes.py_object)(
            ("PyCapsule_GetName", ctypes.pythonapi)
        )(capsule)
        pointer = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object, ctypes.c_char_p)(
            ("PyCapsule_GetPointer", ctypes.pythonapi)
        )(capsule, name)
    except (AttributeError, KeyError, TypeError, ValueError):  # pragma: no cover
        return None
    signature = b"void (char *, char *, char *, int *,"  # and 21 pointers in all
    if not name.startswith(signature) or name.count(b"*") != 21:  # pragma: no cover
        return None
    return ctypes.CFUNCTYPE(None, *[ctypes.c_void_p] * 21)(pointer)


def _kernels(u):
    """Averaging kernels ``h`` (R, 2L-1) of stacked modes ``u`` (R, L, r)."""
    rows, size, modes = u.shape
    padded = np.zeros((rows, 3 * size - 2, modes))
    padded[:, size - 1 : 2 * size - 1] = u - u.mean(axis=1, keepdims=True)  # Q U
    shifted = sliding_window_view(padded, size, axis=1)  # (R, 2L-1, r, L)
    lags = np.arange(-(size - 1), size)
    return np.einsum("riqn,rnq->ri", shifted, u) + (size - np.abs(lags)) / size
