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
import math
import re
import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.case.config import _box, _integer, _Table
from coastmesh.errors import ConfigError, InputDataError

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

Progress = Callable[[int, int], None]
StageFactory = Callable[[str], AbstractContextManager[Progress]]

_PREFIX = re.compile(r"[A-Za-z0-9_.-]+")
_KM_PER_DEGREE = 111.32  # one degree of latitude (and of longitude at the equator)
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
        _integer(2)(self.window, "window")
        _mode_counts(self.window)(list(self.modes), "modes")
        _prefix(self.prefix, "prefix")


@dataclass(frozen=True, slots=True)
class BathymetryStudyResult:
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
    rows: tuple[dict[str, Any], ...]
    seconds: float

    def summary(self) -> str:
        """Return a one-line summary."""
        rms = ", ".join(f"{r['modes']}: {r['rms_m']:.3g}" for r in self.rows)
        return (
            f"bathymetry PCA: RMS difference from the input (m) by mode count {rms}; "
            f"{len(self.files)} files in {self.seconds:.1f} s"
        )


def parse_study(
    table: _Table, path_of: Callable[[Any, str], Path]
) -> BathymetryStudyConfig:
    """Read the ``[study]`` table of a ``kind = "bathymetry"`` case.

    Parameters
    ----------
    table : coastmesh.case.config._Table
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
    >>> from coastmesh.case.config import _Table
    >>> table = _Table({"path": "orkney.tif", "window": 4}, "study", "case.toml")
    >>> study = parse_study(table, lambda value, key: Path("/data") / value)
    >>> study.path.as_posix(), study.window, study.modes, study.prefix
    ('/data/orkney.tif', 4, (1, 4, 8, 12), 'orkney')
    """
    path = table.get("path", path_of)
    bbox = table.get("bbox", _box, None)
    window = table.get("window", _integer(2), 8)
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
        curve, kept = [], {}
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


def _mode_counts(window: int) -> Callable[[Any, str], tuple[int, ...]]:
    size = window * window

    def convert(value: Any, key: str) -> tuple[int, ...]:
        if not isinstance(value, list | tuple) or not value:
            raise ConfigError(f"{key} = {value!r}: expected a list of mode counts")
        counts = tuple(_integer(1)(m, f"{key}[{k}]") for k, m in enumerate(value))
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


def _prefix(value: Any, key: str) -> str:
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


def _write_tables(folder, config, raster, rows, curve, spectrum) -> list[str]:
    from coastmesh import __version__

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


def _write_figures(folder, config, raster, kept, curve, spectrum, progress):
    from coastmesh.plot.base import save_figure

    (folder / "figures").mkdir()
    panels = [(_title(r), kept[r]) for r in config.modes]
    panels.append((f"input: {config.path.name}", raster.values))
    builders = {
        "maps": lambda: _maps_figure(raster, panels),
        "surfaces": lambda: _surfaces_figure(raster, panels),
        "spectrum": lambda: _spectrum_figure(spectrum, config.modes),
        "rms": lambda: _rms_figure(curve, config.modes),
    }
    files = []
    for k, (name, build) in enumerate(builders.items(), start=1):
        files.append(f"figures/{name}.png")
        save_figure(build(), folder / files[-1])
        progress(k, len(builders))
    return files


def _title(modes: int) -> str:
    return f"{modes} mode{'s' * (modes != 1)}"


def _grid(count: int) -> tuple[int, int]:
    columns = min(count, 3)
    return math.ceil(count / columns), columns


def _relief(panels) -> tuple[Any, Any]:
    """Colour map and norm shared by every panel: the range of all of them."""
    from coastmesh.plot.base import relief_style

    low = min(float(np.nanmin(v)) for _, v in panels)
    high = max(float(np.nanmax(v)) for _, v in panels)
    return relief_style(None, low, high)


def _maps_figure(raster: xr.DataArray, panels) -> Figure:
    """Each approximation and the input as a map, on one colour scale."""
    from matplotlib.figure import Figure

    from coastmesh.plot.base import as_crs, geographic_axes, raster_extent

    rows, columns = _grid(len(panels))
    figure = Figure(figsize=(5.2 * columns, 3.6 * rows), layout="constrained")
    axes = np.asarray(figure.subplots(rows, columns, squeeze=False)).ravel()
    cmap, norm = _relief(panels)
    extent = raster_extent(raster)
    crs = as_crs(raster.attrs.get("crs"))
    for k, (ax, (title, values)) in enumerate(zip(axes, panels, strict=False)):
        image = ax.imshow(values, extent=extent, origin="upper", cmap=cmap, norm=norm)
        ax.set_title(f"({chr(ord('a') + k)}) {title}")
        geographic_axes(ax, crs, (extent[0], extent[2], extent[1], extent[3]))
    for ax in axes[len(panels) :]:
        ax.set_axis_off()
    bar = figure.colorbar(image, ax=axes[: len(panels)].tolist(), shrink=0.8)
    bar.set_label(f"elevation ({raster.attrs.get('units') or 'm'})")
    figure.suptitle("PCA approximations of the bathymetry and topography")
    return figure


def _surfaces_figure(raster: xr.DataArray, panels) -> Figure:
    """Each approximation and the input as a semi-transparent 3-D surface."""
    import mpl_toolkits.mplot3d  # noqa: F401  (registers the 3d projection)
    from matplotlib.figure import Figure

    from coastmesh.plot.base import as_crs

    x, y = np.meshgrid(raster["x"].values, raster["y"].values)
    crs = as_crs(raster.attrs.get("crs"))
    low = min(float(np.nanmin(v)) for _, v in panels)
    high = max(float(np.nanmax(v)) for _, v in panels)
    width, depth = float(np.ptp(x)), float(np.ptp(y))
    if crs is not None and crs.is_geographic:  # to km on the ground
        middle = math.radians(float(np.mean(y)))
        width *= _KM_PER_DEGREE * math.cos(middle)
        depth *= _KM_PER_DEGREE
    else:
        width, depth = width / 1000, depth / 1000
    relief_km = max(high - low, 1e-9) / 1000
    exaggeration = _nice(0.3 * max(width, depth) / relief_km)
    cmap, norm = _relief(panels)
    rows, columns = _grid(len(panels))
    figure = Figure(figsize=(6.0 * columns, 4.6 * rows), layout="constrained")
    for k, (title, values) in enumerate(panels):
        ax = figure.add_subplot(rows, columns, k + 1, projection="3d")
        ax.plot_surface(
            x, y, values, cmap=cmap, norm=norm, rstride=1, cstride=1,
            linewidth=0, antialiased=False, alpha=0.85,
        )  # fmt: skip
        ax.set_zlim(low, high)
        ax.set_box_aspect((width, depth, relief_km * exaggeration), zoom=1.1)
        ax.view_init(elev=30, azim=110)
        ax.set_title(f"({chr(ord('a') + k)}) {title}")
        ax.set_xlabel("longitude" if crs is not None and crs.is_geographic else "x")
        ax.set_ylabel("latitude" if crs is not None and crs.is_geographic else "y")
        ax.set_zlabel(f"elevation ({raster.attrs.get('units') or 'm'})")
    figure.suptitle(
        f"PCA approximations as surfaces, vertical exaggeration x{exaggeration:g}, "
        "seen from the north-north-west"
    )
    return figure


def _nice(value: float) -> float:
    """Round down to 1, 2 or 5 times a power of ten (at least 1)."""
    if value <= 1:
        return 1.0
    power = 10 ** math.floor(math.log10(value))
    return max(step * power for step in (1, 2, 5) if step * power <= value)


def _spectrum_figure(spectrum: NDArray[np.float64], modes: tuple[int, ...]) -> Figure:
    """Eigenvalue per mode (log scale) and the cumulative energy fraction."""
    from matplotlib.figure import Figure

    index = np.arange(1, len(spectrum) + 1)
    energy = np.cumsum(np.clip(spectrum, 0.0, None))
    energy /= energy[-1]
    positive = spectrum > spectrum[0] * 1e-12
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    left, right = figure.subplots(1, 2)
    left.semilogy(index[positive], spectrum[positive], "o-", markersize=3)
    left.set_xlabel("mode")
    left.set_ylabel("eigenvalue (m$^2$): energy of the mode")
    left.set_title("eigenvalue spectrum")
    if not positive.all():
        first = int(index[~positive].min())
        which = f"mode {first}" if first == index[-1] else f"modes {first}..{index[-1]}"
        left.annotate(
            f"{which}: ~0, not drawn (each window loses its mean)",
            xy=(0.97, 0.95), xycoords="axes fraction", ha="right", va="top",
        )  # fmt: skip
    right.plot(index, 100 * energy, "-", color="tab:gray")
    picks = np.asarray(modes) - 1
    right.plot(index[picks], 100 * energy[picks], "o", color="tab:red")
    for k in picks:
        right.annotate(
            f"{index[k]}: {100 * energy[k]:.1f} %", (index[k], 100 * energy[k]),
            textcoords="offset points", xytext=(6, -4), va="top",
        )  # fmt: skip
    right.set_ylim(100 * energy[0] - 8, 101)
    right.set_xlabel("modes kept")
    right.set_ylabel("energy kept (%)")
    right.set_title("cumulative energy")
    right.grid(True, alpha=0.3)
    return figure


def _rms_figure(curve: list[dict[str, Any]], modes: tuple[int, ...]) -> Figure:
    """RMS and largest difference from the input against the number of modes."""
    from matplotlib.figure import Figure

    index = np.array([c["modes"] for c in curve])
    rms = np.array([c["rms_m"] for c in curve])
    worst = np.array([c["max_abs_diff_m"] for c in curve])
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    picks = np.asarray(modes) - 1
    for ax, values, title in zip(
        figure.subplots(1, 2),
        (rms, worst),
        ("RMS difference from the input", "largest |difference| from the input"),
        strict=True,
    ):
        ax.plot(index, values, "o-", markersize=3)
        ax.plot(index[picks], values[picks], "o", color="tab:red")
        for k in picks:
            ax.annotate(
                f"{index[k]}: {values[k]:.1f} m", (index[k], values[k]),
                textcoords="offset points", xytext=(5, 5),
            )  # fmt: skip
        ax.set_xlabel("modes kept")
        ax.set_ylabel("metres")
        ax.set_title(title)
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
    return figure
