"""``coastmesh simplify-raster``: PCA of a raster in 2-D windows."""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

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
from coastmesh.pca import check_modes, check_window_2d, check_workers, simplify_raster
from coastmesh.types import Progress, Report

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
    workers: int | None = None,
    scheduler: str | None = None,
    memory_mb: float | None = None,
    stream: bool | None = None,
) -> RasterReport:
    """Approximate a raster from the leading PCA modes of its windows and write it.

    A GeoTIFF output is streamed: the raster is read, computed and written in
    chunks, as Dask tasks on local threads or on a cluster, so memory stays
    bounded whatever its size (:mod:`coastmesh.commands.raster_stream`).
    A NetCDF output is computed in memory. Both give the same result, to
    rounding (1e-9).

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
    workers : int, optional
        Threads to compute the chunks on; default all the cores. The result
        does not depend on it, bit for bit.
    scheduler : str, optional
        A Dask scheduler's address (``"tcp://host:8786"``): the chunks are
        tasks on its cluster, whose workers must see ``src`` at the same path.
    memory_mb : float, optional
        Working memory of each worker thread, in megabytes (default 768): it
        sets the size of the chunks, and changes the result only by rounding.
    stream : bool, optional
        Whether to stream; default: for a GeoTIFF output. NetCDF is written
        in memory only.

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
    workers = check_workers(workers)
    geotiff = raster_driver(dst) == "GTiff"
    if (stream or scheduler is not None) and not geotiff:
        raise ConfigError(
            f"{dst}: only a GeoTIFF output is streamed (and computed on a Dask "
            "scheduler); use a .tif name"
        )
    if memory_mb is not None and not memory_mb > 0:
        raise ConfigError(f"memory = {memory_mb} MB: must be > 0")
    check_outputs(dst, plot, overwrite=overwrite)
    if geotiff and stream is not False:
        return _stream_file(
            src,
            dst,
            window=(wy, wx),
            modes=modes,
            bbox=box,
            crs=assigned,
            overwrite=overwrite,
            plot=plot,
            progress=progress,
            workers=workers,
            scheduler=scheduler,
            memory_mb=memory_mb,
            start=start,
        )

    original = read_raster(src, bbox=box)
    original.attrs["crs"] = _raster_crs(original.attrs.get("crs"), assigned, src)
    values = original.values
    _check_size(values.shape, (wy, wx), src, box)
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


def _stream_file(
    src: PathLike,
    dst: PathLike,
    *,
    window: tuple[int, int],
    modes: int,
    bbox: tuple[float, float, float, float] | None,
    crs: CRS | None,
    overwrite: bool,
    plot: PathLike | None,
    progress: Progress | None,
    workers: int,
    scheduler: str | None,
    memory_mb: float | None,
    start: float,
) -> RasterReport:
    """:func:`simplify_raster_file` for a GeoTIFF output: streamed, on Dask."""
    from coastmesh.commands.raster_chunks import MEMORY_MB, plan_chunks
    from coastmesh.commands.raster_stream import open_client, stream_raster
    from coastmesh.io import open_raster_source, read_decimated

    wy, wx = window
    source = open_raster_source(src, bbox=bbox)
    stored_crs = _raster_crs(source.crs, crs, src)
    _check_size(source.shape, window, src, bbox)
    with open_client(workers, scheduler) as client:  # before any output exists
        with AtomicOutputs(overwrite=overwrite) as outputs:
            staged = outputs.stage(dst)
            totals = stream_raster(
                source,
                staged,
                window=window,
                modes=modes,
                client=client,
                crs=stored_crs,
                notes=_notes(source.units, src, window, modes),
                plan=plan_chunks(
                    source.shape, window, memory_mb=memory_mb or MEMORY_MB
                ),
                threads=workers,
                progress=progress,
            )
            if plot is not None:
                from coastmesh import plot as plotting

                result = open_raster_source(staged)
                figure = plotting.raster_figure(
                    read_decimated(source),
                    read_decimated(result),
                    title=f"{Path(src).name}: window {wy} x {wx} cells, "
                    f"{modes_label(modes)}",
                )
                plotting.save_figure(figure, outputs.stage(plot))
    logger.info("wrote %s", listed(dst, plot))
    ny, nx = source.shape
    valid = ny * nx - totals.cells_missing
    report = RasterReport(
        rows=ny,
        columns=nx,
        cells_missing=totals.cells_missing,
        cells_covered=totals.cells_covered,
        cells_changed=totals.cells_changed,
        rms_change=float(np.sqrt(totals.square_change / valid)) if valid else 0.0,
        max_change=totals.max_change,
        seconds=time.perf_counter() - start,
    )
    logger.info("raster: %s (%d chunks)", report.summary(), totals.chunks)
    return report


def _check_size(
    shape: tuple[int, int], window: tuple[int, int], src: PathLike, bbox: object
) -> None:
    (ny, nx), (wy, wx) = shape, window
    if ny < wy or nx < wx:
        where = " (after bbox)" if bbox is not None else ""
        raise ConfigError(
            f"window = {wy} x {wx} cells: larger than the raster {src}{where}, "
            f"which has {ny} x {nx} cells"
        )


def _notes(
    units: str | None, src: PathLike, window: tuple[int, int], modes: int
) -> dict[str, str]:
    notes = {"units": units} if units else {}
    notes.update(
        provenance(
            "simplify-raster", src, window=f"{window[0]}x{window[1]}", modes=modes
        )
    )
    return notes


def _raster_crs(declared: str | None, crs: CRS | None, src: PathLike) -> str:
    """Return the raster's CRS as stored (WKT): its own, else ``crs``."""
    check_crs(
        None if declared is None else CRS.from_user_input(declared), crs, "raster", src
    )
    if declared is not None:
        return declared
    assert crs is not None  # check_crs raised without either
    return crs.to_wkt()


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
