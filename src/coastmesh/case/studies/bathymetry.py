"""Bathymetry PCA study: the paper's figure 4, as a case of ``coastmesh run``.

A raster is approximated from the leading ``r`` PCA modes of its ``w x w`` windows
(:func:`coastmesh.pca.simplify_raster`) for every ``r`` from 1 to ``w**2``; with all
``w**2`` modes the input comes back to rounding. The study writes the approximations
for the chosen mode counts as GeoTIFFs, a table of the difference from the input and
of the energy kept, and four figures: maps, 3-D surfaces, the eigenvalue spectrum
and the RMS difference against the number of modes.

References
----------
A. Avdis et al., "Shoreline and bathymetry approximation in mesh generation for
tidal renewable simulations", EWTEC 2015, sections II.B and III.B, figure 4.
"""

from __future__ import annotations

import csv
import json
import logging
import re
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from coastmesh.case import schema
from coastmesh.case.schema import Table
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.types import Progress, Report, StageFactory

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = [
    "BathymetryStudyConfig",
    "BathymetryStudyResult",
    "parse_study",
    "run_study",
]

logger = logging.getLogger(__name__)

_PREFIX = re.compile(r"[A-Za-z0-9_.-]+")
_COLUMNS = ("modes", "rms_m", "max_abs_diff_m", "energy_fraction", "seconds")


@dataclass(frozen=True, slots=True)
class BathymetryStudyConfig:
    """The ``[study]`` table of a ``kind = "bathymetry"`` case; paths resolved.

    Attributes
    ----------
    path : Path
        The raster, in any format :func:`coastmesh.io.read_raster` reads.
    bbox : tuple of 4 floats or None
        ``(minx, miny, maxx, maxy)`` to read, in the raster's CRS units; None
        reads all of it.
    window : int
        Side of the square windows (partitions), in cells: ``window**2`` modes.
    modes : tuple of int
        The mode counts drawn and written as rasters, each in ``1 .. window**2``.
    prefix : str
        Output rasters are named ``<prefix>_r<modes>.tif``.
    """

    path: Path
    bbox: tuple[float, float, float, float] | None = None
    window: int = 8
    modes: tuple[int, ...] = (1, 16, 32, 48)
    prefix: str = "bathymetry"

    def __post_init__(self) -> None:
        schema.integer(2)(self.window, "window")
        _mode_counts(self.window)(list(self.modes), "modes")
        _prefix(self.prefix, "prefix")


@dataclass(frozen=True, slots=True)
class BathymetryStudyResult(Report):
    """What :func:`run_study` made.

    Attributes
    ----------
    files : tuple of str
        The files written, relative to the output folder.
    rows : tuple of dict
        One per mode count in the table (the chosen ones and ``window**2``):
        ``modes``, ``rms_m`` and ``max_abs_diff_m`` (difference from the input,
        metres), ``energy_fraction`` (leading eigenvalues over their total) and
        ``seconds`` (time of that approximation).
    seconds : float
        Wall time of the whole study.
    """

    files: tuple[str, ...]
    rows: tuple[dict[str, float], ...]
    seconds: float

    def summary(self) -> str:
        """Return a one-line summary."""
        rms = ", ".join(f"{r['modes']}: {r['rms_m']:.3g}" for r in self.rows)
        return (
            f"bathymetry PCA: RMS difference from the input (m) by mode count {rms}; "
            f"{len(self.files)} files in {self.seconds:.1f} s"
        )


def parse_study(
    table: Table, path_of: Callable[[object, str], Path]
) -> BathymetryStudyConfig:
    """Read the ``[study]`` table of a ``kind = "bathymetry"`` case.

    Parameters
    ----------
    table : coastmesh.case.schema.Table
        The table; keys ``path`` (required), ``bbox``, ``window`` (default 8),
        ``modes`` (default: 1 and a quarter, half and three quarters of
        ``window**2``, i.e. 1, 16, 32, 48 for 8) and ``prefix`` (default: the
        raster's file name without its extension).
    path_of : callable
        ``path_of(value, key)`` resolves a path relative to the case file.

    Returns
    -------
    BathymetryStudyConfig

    Raises
    ------
    ConfigError
        If a key is unknown or missing or a value is bad; the message names it.

    Examples
    --------
    >>> from pathlib import Path
    >>> from coastmesh.case.schema import Table
    >>> table = Table({"path": "orkney.tif", "window": 4}, "study", "case.toml")
    >>> study = parse_study(table, lambda value, key: Path("/data") / value)
    >>> study.path.as_posix(), study.window, study.modes, study.prefix
    ('/data/orkney.tif', 4, (1, 4, 8, 12), 'orkney')
    """
    path = table.get("path", path_of)
    bbox = table.get("bbox", schema.box, None)
    window = table.get("window", schema.integer(2), 8)
    modes = table.get("modes", _mode_counts(window), _default_modes(window))
    prefix = table.get("prefix", _prefix, path.stem)
    table.done()
    return BathymetryStudyConfig(path, bbox, window, modes, prefix)


def run_study(
    config: BathymetryStudyConfig, folder: Path, stage: StageFactory
) -> BathymetryStudyResult:
    """Approximate a raster with 1 .. ``window**2`` modes and write what it shows.

    Parameters
    ----------
    config : BathymetryStudyConfig
        The study.
    folder : Path
        The output folder, existing and empty.
    stage : callable
        ``stage(label)`` returns a context manager yielding ``progress(done, total)``.

    Returns
    -------
    BathymetryStudyResult

    Raises
    ------
    InputDataError
        If the raster cannot be read, is smaller than a window, or has no window
        without missing cells.

    Notes
    -----
    Writes ``<prefix>_r<modes>.tif`` for each chosen mode count and for
    ``window**2``; ``table.md``, ``table.csv`` and ``study.json`` (the table, the
    eigenvalue spectrum and the whole RMS curve); and ``figures/maps.png``,
    ``figures/surfaces.png``, ``figures/spectrum.png`` and ``figures/rms.png``.
    Every approximation is :func:`coastmesh.pca.simplify_raster` on the whole grid;
    the energy kept by ``r`` modes is the sum of the ``r`` leading eigenvalues of
    the window covariance (:func:`coastmesh.pca.raster_modes`) over their total.
    """
    from coastmesh.io import read_raster, write_raster
    from coastmesh.pca import raster_modes, simplify_raster
    from coastmesh.pca.threads import single_threaded_blas

    started = time.perf_counter()
    folder = Path(folder)
    w = config.window
    size = w * w
    with stage("read the raster") as progress:
        raster = read_raster(config.path, bbox=config.bbox)
        progress(1, 1)
    values = np.asarray(raster.values, dtype=np.float64)
    ny, nx = values.shape
    if ny < w or nx < w:
        raise InputDataError(
            f"{ny} x {nx} cells is smaller than one window "
            f"(window = {w}); widen bbox or use a smaller window",
            path=str(config.path),
        )
    logger.info("bathymetry study: %d x %d cells, window %d x %d", ny, nx, w, w)
    # The matrices are small (L = window**2 rows): BLAS threads cost more than they
    # give (measured on the 51 x 101 Orkney grid: 0.11 s -> 0.008 s per approximation).
    with single_threaded_blas():
        with stage("eigenvalue spectrum") as progress:
            try:
                spectrum = raster_modes(values, w)
            except ValueError as exc:
                raise InputDataError(str(exc), path=str(config.path)) from None
            progress(1, 1)
        energy = np.cumsum(np.clip(spectrum, 0.0, None))
        energy /= energy[-1]
        shown = sorted({*config.modes, size})
        curve: list[dict[str, float]] = []
        kept: dict[int, NDArray[np.float64]] = {}
        valid = np.isfinite(values)
        with stage(f"approximations with 1 .. {size} modes") as progress:
            for r in range(1, size + 1):
                t0 = time.perf_counter()
                approx = simplify_raster(values, w, r)
                seconds = time.perf_counter() - t0
                diff = np.abs(approx - values)[valid]
                curve.append(
                    {
                        "modes": r,
                        "rms_m": float(np.sqrt(np.mean(diff**2))),
                        "max_abs_diff_m": float(diff.max()),
                        "energy_fraction": float(energy[r - 1]),
                        "seconds": seconds,
                    }
                )
                if r in shown:
                    kept[r] = approx
                progress(r, size)
    rows = tuple(curve[r - 1] for r in shown)
    logger.info(
        "bathymetry study: RMS difference %s m",
        ", ".join(f"{row['rms_m']:.3g} ({row['modes']} modes)" for row in rows),
    )

    files = []
    with stage("write rasters and tables") as progress:
        for k, r in enumerate(shown, start=1):
            name = f"{config.prefix}_r{r}.tif"
            write_raster(folder / name, _approximation(raster, kept[r], w, r))
            files.append(name)
            progress(k, len(shown) + 1)
        files += _write_tables(folder, config, raster, rows, curve, spectrum)
        progress(len(shown) + 1, len(shown) + 1)
    with stage("figures") as progress:
        files += _write_figures(folder, config, raster, kept, curve, spectrum, progress)
    return BathymetryStudyResult(tuple(files), rows, time.perf_counter() - started)


def _mode_counts(window: int) -> Callable[[object, str], tuple[int, ...]]:
    size = window * window

    def convert(value: object, key: str) -> tuple[int, ...]:
        if not isinstance(value, list | tuple) or not value:
            raise ConfigError(f"{key} = {value!r}: expected a list of mode counts")
        counts = tuple(schema.integer(1)(m, f"{key}[{k}]") for k, m in enumerate(value))
        for k, m in enumerate(counts):
            if m > size:
                raise ConfigError(
                    f"{key}[{k}] = {m}: must be <= window**2 = {size} "
                    f"(window = {window})"
                )
        if len(set(counts)) != len(counts):
            raise ConfigError(f"{key} = {list(value)!r}: a mode count is repeated")
        return counts

    return convert


def _default_modes(window: int) -> tuple[int, ...]:
    """1 and a quarter, a half and three quarters of the modes: the paper's figure."""
    size = window * window
    return tuple(sorted({1, size // 4, size // 2, 3 * size // 4} - {0}))


def _prefix(value: object, key: str) -> str:
    if not isinstance(value, str) or not _PREFIX.fullmatch(value):
        raise ConfigError(
            f"{key} = {value!r}: expected a file name start (letters, digits, "
            "'_', '.', '-')"
        )
    return value


def _approximation(
    raster: xr.DataArray, values: NDArray[np.float64], window: int, modes: int
) -> xr.DataArray:
    """Put an approximation on the input's grid, to be stored as float64."""
    out = raster.copy(data=values)
    out.attrs.update(
        dtype="float64",
        history=(
            f"coastmesh.pca.simplify_raster(window={window}, modes={modes}) of "
            f"{raster.attrs.get('source', '')}"
        ),
    )
    return out


def _write_tables(
    folder: Path,
    config: BathymetryStudyConfig,
    raster: xr.DataArray,
    rows: Sequence[dict[str, float]],
    curve: list[dict[str, float]],
    spectrum: NDArray[np.float64],
) -> list[str]:
    from coastmesh.version import __version__

    size = config.window**2
    lines = [
        "| modes | RMS difference (m) | max abs difference (m) | energy kept "
        "| seconds |\n|---:|---:|---:|---:|---:|\n",
    ]
    for row in rows:
        lines.append(
            f"| {row['modes']} | {row['rms_m']:.3f} | {row['max_abs_diff_m']:.3f} "
            f"| {row['energy_fraction']:.4f} | {row['seconds']:.3f} |\n"
        )
    lines.append(
        f"\n{raster.shape[0]} x {raster.shape[1]} cells of {config.path.name}, "
        f"windows of {config.window} x {config.window} cells; {size} modes give "
        f"the input back (RMS {rows[-1]['rms_m']:.1e} m).\n"
    )
    (folder / "table.md").write_text("".join(lines), encoding="utf-8")
    with (folder / "table.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    report = {
        "coastmesh": __version__,
        "input": str(config.path),
        "bbox": config.bbox,
        "cells": list(raster.shape),
        "window": config.window,
        "modes": list(config.modes),
        "units": raster.attrs.get("units", ""),
        "rows": list(rows),
        "eigenvalues": [float(v) for v in spectrum],
        "curve": curve,
    }
    (folder / "study.json").write_text(json.dumps(report, indent=1), encoding="utf-8")
    return ["table.md", "table.csv", "study.json"]


def _write_figures(
    folder: Path,
    config: BathymetryStudyConfig,
    raster: xr.DataArray,
    kept: Mapping[int, NDArray[np.float64]],
    curve: list[dict[str, float]],
    spectrum: NDArray[np.float64],
    progress: Progress,
) -> list[str]:
    from coastmesh.plot import studies as plot_studies
    from coastmesh.plot.base import save_figure

    (folder / "figures").mkdir()
    panels = [(_title(r), kept[r]) for r in config.modes]
    panels.append((f"input: {config.path.name}", raster.values))
    builders: dict[str, Callable[[], Figure]] = {
        "maps": lambda: plot_studies.relief_maps_figure(raster, panels),
        "surfaces": lambda: plot_studies.relief_surfaces_figure(raster, panels),
        "spectrum": lambda: plot_studies.spectrum_figure(spectrum, config.modes),
        "rms": lambda: plot_studies.rms_figure(curve, config.modes),
    }
    files = []
    for k, (name, build) in enumerate(builders.items(), start=1):
        files.append(f"figures/{name}.png")
        save_figure(build(), folder / files[-1])
        progress(k, len(builders))
    return files


def _title(modes: int) -> str:
    return f"{modes} mode{'s' * (modes != 1)}"
