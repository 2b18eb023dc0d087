"""A strip of raster rows prepared for the FFT sums of :mod:`coastmesh.pca.grid`.

:class:`Block` holds the strip's values shifted near zero, its valid cells, and
the windows of the zero-padded strip that are not partitions (they overlap the
edge or a missing cell); :func:`window_counts` and :func:`cover_counts` count
valid cells per window and partitions per cell with summed-area tables.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.fft
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import NDArray

__all__ = ["Block", "cover_counts", "window_counts"]

_CHUNK = 1 << 16  # partial windows handled per batch (memory: _CHUNK * L floats)


class Block:
    """One strip of rows, prepared for the FFT sums over its windows.

    The spectrum (for the reconstruction) and the difference fields (for the
    covariance) are computed on first use: each pass needs only one of them.
    """

    def __init__(self, block, shift: float, wy: int, wx: int) -> None:
        ny, nx = block.shape
        self.block = block
        self.valid = np.isfinite(block)
        self.complete = bool(self.valid.all())
        self.z = (
            block - shift if self.complete else np.where(self.valid, block - shift, 0.0)
        )
        self.shape, self.wy, self.wx = (ny, nx), wy, wx
        counts = window_counts(self.valid, self.complete, wy, wx)
        self.full = counts == wy * wx  # window corners (padded grid) of partitions
        self.partial = np.argwhere((counts > 0) & (counts < wy * wx))
        self.fft_shape = (
            scipy.fft.next_fast_len(ny + wy - 1, real=True),
            scipy.fft.next_fast_len(nx + wx - 1, real=True),
        )

    @functools.cached_property
    def spectrum(self):
        """2-D real FFT of the block, zero-padded to ``fft_shape``."""
        return scipy.fft.rfft2(self.z, self.fft_shape)

    @functools.cached_property
    def dx(self):
        """Differences along x between valid neighbours (0 where either is missing)."""
        v, z = self.valid, self.z
        return np.where(v[:, 1:] & v[:, :-1], z[:, 1:] - z[:, :-1], 0.0)

    @functools.cached_property
    def dy(self):
        """Differences along y between valid neighbours (0 where either is missing)."""
        v, z = self.valid, self.z
        return np.where(v[1:] & v[:-1], z[1:] - z[:-1], 0.0)

    def partial_differences(self):
        """Yield (corners, internal differences) of the non-partition windows.

        The differences are (n, n_e) rows: the x differences row by row, then the
        y differences (``_difference_layout`` in :mod:`coastmesh.pca.grid`).
        """
        wy, wx = self.wy, self.wx
        dx = np.pad(self.dx, ((wy - 1, wy - 1), (wx - 1, wx)))
        dy = np.pad(self.dy, ((wy - 1, wy), (wx - 1, wx - 1)))
        view_x = sliding_window_view(dx, (wy, wx - 1))
        view_y = sliding_window_view(dy, (wy - 1, wx))
        for start in range(0, len(self.partial), _CHUNK):
            c = self.partial[start : start + _CHUNK]
            yield (
                c,
                np.concatenate(
                    [
                        view_x[c[:, 0], c[:, 1]].reshape(len(c), -1),
                        view_y[c[:, 0], c[:, 1]].reshape(len(c), -1),
                    ],
                    axis=1,
                ),
            )

    def partial_windows(self):
        """Yield (corners, windows as (n, L) rows) of the non-partition windows."""
        wy, wx = self.wy, self.wx
        padded = np.pad(self.z, ((wy - 1, wy - 1), (wx - 1, wx - 1)))
        view = sliding_window_view(padded, (wy, wx))
        for start in range(0, len(self.partial), _CHUNK):
            c = self.partial[start : start + _CHUNK]
            yield c, view[c[:, 0], c[:, 1]].reshape(len(c), self.wy * self.wx)


def _box_sum(mask: NDArray, wy: int, wx: int) -> NDArray[np.int64]:
    """Sum ``mask`` over every ``wy x wx`` window of the grid zero-padded by w-1.

    The index of the result is the window's corner in the padded grid.
    """
    padded = np.pad(mask.astype(np.int64), ((wy, wy - 1), (wx, wx - 1)))
    cs = padded.cumsum(axis=0).cumsum(axis=1)
    return cs[wy:, wx:] - cs[:-wy, wx:] - cs[wy:, :-wx] + cs[:-wy, :-wx]


def _ones_box_1d(n: int, w: int) -> NDArray[np.int64]:
    """Cells of a row of ``n`` ones inside each of the ``n+w-1`` padded windows."""
    p = np.arange(n + w - 1)
    return np.minimum(p, n - 1) - np.maximum(p - (w - 1), 0) + 1


def window_counts(valid, complete: bool, wy: int, wx: int) -> NDArray[np.int64]:
    """Count the valid cells in each window of the padded grid (index = corner)."""
    if complete:  # separable: rows inside times columns inside
        ny, nx = valid.shape
        return np.outer(_ones_box_1d(ny, wy), _ones_box_1d(nx, wx))
    return _box_sum(valid, wy, wx)


def cover_counts(full, complete: bool, wy: int, wx: int, ny: int, nx: int):
    """Partitions holding each cell of the ``ny x nx`` grid.

    ``full[p]`` marks the partition whose corner is cell ``p - (w-1)`` of the grid.
    """
    if complete:  # partitions start at 0 .. n-w along each axis
        return np.outer(_ones_box_1d(ny - wy + 1, wy), _ones_box_1d(nx - wx + 1, wx))
    starts = full[wy - 1 : wy - 1 + ny - wy + 1, wx - 1 : wx - 1 + nx - wx + 1]
    return _box_sum(starts, wy, wx)
