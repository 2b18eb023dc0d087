"""``coastmesh simplify-raster``: PCA of a raster in 2-D windows."""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.commands._common import (
    PathLike,
    check_crs,
    check_outputs,
    listed,
    modes_label,
    parse_crs,
    provenance,
)
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io import AtomicOutputs, check_bbox, raster_driver
from coastmesh.pca import check_modes, check_window_2d, simplify_raster
from coastmesh.types import Progress, Report

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["RasterReport", "raster_report", "simplify_raster_file"]

logger = logging.getLogger(__name__)


def simplify_raster_file(
    src: PathLike,
    dst: PathLike,
    *,
    window: int | tuple[int, int],
    modes: int,
    bbox: Sequence[float] | None = None,
    crs: CRS | str | None = None,
    overwrite: bool = False,
    plot: PathLike | None = None,
    progress: Progress | None = None,
) -> RasterReport:
    """Approximate a raster from the leading PCA modes of its windows and write it.

    Parameters
    ----------
    src : str or path-like
        Any raster GDAL reads (GeoTIFF, GEBCO-style NetCDF, ...); band 1 is used.
    dst : str or path-like
        The output file (``.tif`` or ``.nc``); georeferencing, CRS, data type and
        nodata are kept.
    window : int or (int, int)
        Window size in cells, square or ``(rows, columns)``, each ``>= 2``.
    modes : int
        Leading modes kept, ``1 <= modes <= rows * columns``.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the CRS units of ``src``: cut to it first.
    crs : pyproj.CRS or str, optional
        CRS of ``src`` if the file declares none.
    overwrite : bool, default False
        Whether existing outputs may be replaced.
    plot : str or path-like, optional
        Also draw the input, the result and their difference side by side.
    progress : callable, optional
        Called as ``progress(done, total)``.

    Returns
    -------
    RasterReport

    Raises
    ------
    ConfigError
        If ``window``, ``modes``, ``bbox`` or ``crs`` is invalid, or the raster
        (after ``bbox``) is smaller than the window.
    InputDataError
        If ``src`` is missing, has no CRS, has infinite values, or ``bbox`` misses it.
    FormatError
        If ``src`` is not a raster or an output extension is unknown.
    OutputExistsError
        If an output exists and ``overwrite`` is false.
    """
    from coastmesh.io import read_raster, write_raster

    start = time.perf_counter()
    wy, wx = check_window_2d(window)
    modes = check_modes(modes, wy * wx)
    box = None if bbox is None else check_bbox(bbox)
    assigned = parse_crs(crs)
    raster_driver(dst)
    check_outputs(dst, plot, overwrite=overwrite)

    original = read_raster(src, bbox=box)
    original.attrs["crs"] = _raster_crs(original, assigned, src)
    values = original.values
    ny, nx = values.shape
    if ny < wy or nx < wx:
        where = " (after bbox)" if box is not None else ""
        raise ConfigError(
            f"window = {wy} x {wx} cells: larger than the raster {src}{where}, "
            f"which has {ny} x {nx} cells"
        )
    if np.isinf(values).any():
        row, col = np.argwhere(np.isinf(values))[0]
        raise InputDataError(
            f"cell (row {row}, column {col}) is {values[row, col]}; "
            "only finite values or nodata are allowed",
            path=os.fspath(src),
        )
    simplified = simplify_raster(values, (wy, wx), modes, progress=progress)
    result = original.copy(data=simplified)
    result.attrs.update(
        provenance("simplify-raster", src, window=f"{wy}x{wx}", modes=modes)
    )
    with AtomicOutputs(overwrite=overwrite) as outputs:
        write_raster(outputs.stage(dst), result)
        if plot is not None:
            from coastmesh import plot as plotting

            figure = plotting.raster_figure(
                original,
                result,
                title=(
                    f"{Path(src).name}: window {wy} x {wx} cells, {modes_label(modes)}"
                ),
            )
            plotting.save_figure(figure, outputs.stage(plot))
    logger.info("wrote %s", listed(dst, plot))
    report = raster_report(values, simplified, wy, wx, time.perf_counter() - start)
    logger.info("raster: %s", report.summary())
    return report


def _raster_crs(raster: xr.DataArray, crs: CRS | None, src: PathLike) -> str:
    """Return the raster's CRS as stored (WKT): its own, else ``crs``."""
    declared = raster.attrs.get("crs")
    check_crs(
        None if declared is None else CRS.from_user_input(declared), crs, "raster", src
    )
    return declared if declared is not None else crs.to_wkt()


@dataclass(frozen=True, slots=True)
class RasterReport(Report):
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
