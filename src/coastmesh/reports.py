"""Reports of whole runs: what was read, changed and written."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["RasterReport", "raster_report"]


@dataclass(frozen=True, slots=True)
class RasterReport:
    """What :func:`simplify_raster_file` did.

    Attributes
    ----------
    rows, columns : int
        Raster size in cells (after ``bbox``).
    cells_missing : int
        Cells without data (nodata/NaN); they stay missing.
    cells_covered : int
        Cells inside at least one full window of valid cells; only these change.
    cells_changed : int
        Cells whose value changed.
    rms_change, max_change : float
        Root-mean-square and largest absolute change over the valid cells, in the
        raster's units (metres for elevation).
    seconds : float
        Wall time, reading and writing included.
    """

    rows: int
    columns: int
    cells_missing: int
    cells_covered: int
    cells_changed: int
    rms_change: float
    max_change: float
    seconds: float

    @property
    def cells(self) -> int:
        """All cells, ``rows * columns``."""
        return self.rows * self.columns

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.rows} x {self.columns} cells, {self.cells_missing} missing; "
            f"{self.cells_covered} covered by a full window, {self.cells_changed} "
            f"changed; change rms {self.rms_change:.3g}, max {self.max_change:.3g}; "
            f"{self.seconds:.1f} s"
        )


def raster_report(
    before: NDArray[np.float64],
    after: NDArray[np.float64],
    wy: int,
    wx: int,
    seconds: float,
) -> RasterReport:
    """Compare a raster before and after; return a :class:`RasterReport`.

    Parameters
    ----------
    before, after : ndarray of shape (ny, nx)
        The input and the result; NaN marks missing cells.
    wy, wx : int
        Window size in cells (rows, columns).
    seconds : float
        Wall time of the run.

    Returns
    -------
    RasterReport

    Examples
    --------
    >>> import numpy as np
    >>> before = np.zeros((5, 5))
    >>> before[0, 0] = np.nan
    >>> report = raster_report(before, before + 1.0, 3, 3, 0.5)
    >>> report.cells_missing, report.cells_covered, report.rms_change
    (1, 24, 1.0)
    """
    valid = np.isfinite(before)
    change = np.abs(after[valid] - before[valid])
    return RasterReport(
        rows=before.shape[0],
        columns=before.shape[1],
        cells_missing=int((~valid).sum()),
        cells_covered=int(_covered(valid, wy, wx).sum()),
        cells_changed=int((change > 0).sum()),
        rms_change=float(np.sqrt(np.mean(change**2))) if change.size else 0.0,
        max_change=float(change.max()) if change.size else 0.0,
        seconds=seconds,
    )


def _covered(valid: NDArray[np.bool_], wy: int, wx: int) -> NDArray[np.bool_]:
    """Cells inside at least one ``wy x wx`` window made only of valid cells."""
    full = _window_sums(valid, wy, wx) == wy * wx
    padded = np.zeros((full.shape[0] + 2 * (wy - 1), full.shape[1] + 2 * (wx - 1)))
    padded[wy - 1 : wy - 1 + full.shape[0], wx - 1 : wx - 1 + full.shape[1]] = full
    return _window_sums(padded, wy, wx) > 0


def _window_sums(grid: NDArray, wy: int, wx: int) -> NDArray[np.int64]:
    """Sum over every ``wy x wx`` window lying inside ``grid``; index = corner."""
    table = np.zeros((grid.shape[0] + 1, grid.shape[1] + 1), dtype=np.int64)
    table[1:, 1:] = grid.astype(np.int64).cumsum(axis=0).cumsum(axis=1)
    return table[wy:, wx:] - table[:-wy, wx:] - table[wy:, :-wx] + table[:-wy, :-wx]
