"""Whole runs: file names and options in, files out.

Each function checks its parameters and opens its inputs before computing, and
writes all its outputs (data and plot) through one :class:`AtomicOutputs`, so a
failure at any point leaves no output behind.
"""

from __future__ import annotations

import logging
import os
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.datasets import path as data_path
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.shoreline import (
    ShorelineReport,
    check_coordinates,
    simplify_shorelines,
)
from coastmesh.io._atomic import AtomicOutputs, atomic_directory, check_output
from coastmesh.io._inputs import check_bbox
from coastmesh.io._registry import plot_format, raster_driver, vector_driver
from coastmesh.io.vector import read_features, write_features
from coastmesh.pca import check_modes, check_window, check_window_2d, simplify_raster
from coastmesh.reports import RasterReport, raster_report
from coastmesh.types import Features

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "DemoStep",
    "RasterReport",
    "run_demo",
    "simplify_raster_file",
    "simplify_shoreline_file",
]

logger = logging.getLogger(__name__)

Progress = Callable[[int, int], None]
PathLike = str | os.PathLike[str]

_SHORELINE_TYPES = (
    shapely.GeometryType.LINESTRING,
    shapely.GeometryType.LINEARRING,
    shapely.GeometryType.POLYGON,
    shapely.GeometryType.MULTILINESTRING,
    shapely.GeometryType.MULTIPOLYGON,
)


@dataclass(frozen=True, slots=True)
class DemoStep:
    """One output set of :func:`run_demo`.

    Attributes
    ----------
    title : str
        What was done, e.g. ``"West Norway shoreline, window 100, 1 mode"``.
    outputs : tuple of str
        File names written into the demo folder (data, then plot).
    report : ShorelineReport, RasterReport or CaseResult
        What the step did (each has ``summary()``).
    """

    title: str
    outputs: tuple[str, ...]
    report: Any


def simplify_shoreline_file(
    src: PathLike,
    dst: PathLike,
    *,
    window: int,
    modes: int,
    layer: str | None = None,
    bbox: Sequence[float] | None = None,
    crs: CRS | str | None = None,
    overwrite: bool = False,
    plot: PathLike | None = None,
    progress: Progress | None = None,
) -> ShorelineReport:
    """Approximate every ring and line of a vector layer by PCA and write it.

    Parameters
    ----------
    src : str or path-like
        Any vector file GDAL reads, with polygons and/or lines.
    dst : str or path-like
        The output file (``.gpkg``, ``.shp``, ``.geojson``, ``.fgb``). Attributes
        and CRS are kept; features whose every contour is shorter than the window
        are left out.
    window : int
        Partition size in points (vertices), ``>= 2``.
    modes : int
        Leading modes kept, ``1 <= modes <= window``.
    layer : str, optional
        The layer of ``src``; needed if it has several.
    bbox : sequence of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` in the CRS units of ``src``: clip to it first.
    crs : pyproj.CRS or str, optional
        CRS of ``src`` if the file declares none.
    overwrite : bool, default False
        Whether existing outputs may be replaced.
    plot : str or path-like, optional
        Also draw the input and the result over each other to this image.
    progress : callable, optional
        Called as ``progress(points_done, points_total)``.

    Returns
    -------
    ShorelineReport

    Raises
    ------
    ConfigError
        If ``window``, ``modes``, ``bbox`` or ``crs`` is invalid.
    InputDataError
        If ``src`` is missing, empty (in ``bbox``), has no CRS, holds points, or
        has a non-finite coordinate; the message names file, layer and feature id.
    FormatError
        If ``src`` is not a vector file or an output extension is unknown.
    OutputExistsError
        If an output exists and ``overwrite`` is false.
    """
    window = check_window(window)
    modes = check_modes(modes, window)
    box = None if bbox is None else check_bbox(bbox)
    assigned = _parse_crs(crs)
    vector_driver(dst)
    _check_outputs(dst, plot, overwrite=overwrite)

    features = read_features(src, layer=layer, bbox=box)
    features = _with_crs(features, assigned)
    try:
        check_coordinates(features.geometry)
    except InputDataError as exc:
        raise _locate(exc, features) from exc
    _check_shoreline_types(features)
    try:
        geometry, report = simplify_shorelines(
            features.geometry, window, modes, progress=progress
        )
    except InputDataError as exc:
        raise _locate(exc, features) from exc
    gone = shapely.is_missing(geometry) & ~shapely.is_missing(features.geometry)
    result = features.with_geometry(geometry).take(~gone)
    logger.info("shoreline: %s", report.summary())
    if len(result) == 0:
        warnings.warn(
            f"every feature of {features.path} was dropped: all its rings and lines "
            f"have fewer than window = {window} points; {os.fspath(dst)} is empty",
            CoastmeshWarning,
            stacklevel=2,
        )

    notes = _provenance("simplify-shoreline", src, window=window, modes=modes)
    with AtomicOutputs(overwrite=overwrite) as outputs:
        write_features(outputs.stage(dst), result, layer=Path(dst).stem, metadata=notes)
        if plot is not None:
            from coastmesh import plot as plotting

            figure = plotting.shoreline_figure(
                features.geometry,
                result.geometry,
                crs=features.crs,
                title=f"{Path(src).name}: window {window} points, {_modes(modes)}",
            )
            plotting.save_figure(figure, outputs.stage(plot))
    logger.info("wrote %s", _listed(dst, plot))
    return report


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
    from coastmesh.io.raster import read_raster, write_raster

    start = time.perf_counter()
    wy, wx = check_window_2d(window)
    modes = check_modes(modes, wy * wx)
    box = None if bbox is None else check_bbox(bbox)
    assigned = _parse_crs(crs)
    raster_driver(dst)
    _check_outputs(dst, plot, overwrite=overwrite)

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
        _provenance("simplify-raster", src, window=f"{wy}x{wx}", modes=modes)
    )
    with AtomicOutputs(overwrite=overwrite) as outputs:
        write_raster(outputs.stage(dst), result)
        if plot is not None:
            from coastmesh import plot as plotting

            figure = plotting.raster_figure(
                original,
                result,
                title=f"{Path(src).name}: window {wy} x {wx} cells, {_modes(modes)}",
            )
            plotting.save_figure(figure, outputs.stage(plot))
    logger.info("wrote %s", _listed(dst, plot))
    report = raster_report(values, simplified, wy, wx, time.perf_counter() - start)
    logger.info("raster: %s", report.summary())
    return report


def run_demo(
    outdir: PathLike = "out",
    *,
    overwrite: bool = False,
    progress: Progress | None = None,
) -> list[DemoStep]:
    """Run the paper's examples on the bundled data and write them to a folder.

    The West Norway shoreline (GSHHG) is approximated with windows of 100 and 500
    points and 1 mode, and 100 points and 5 modes; the ETOPO1 Orkney raster with
    8 x 8 windows and 1, 16 and 48 modes. Each result is written with a plot of
    input and result. Then the bundled Orkney case (``pentland_firth.toml``) runs
    the whole chain into ``pentland_firth/``: shoreline PCA by region, loxodrome
    open boundaries, a graded Gmsh mesh, depths from the PCA of the ETOPO1 grid,
    eight model formats, the quality report and the figures. ``README.txt`` lists
    the files.

    Parameters
    ----------
    outdir : str or path-like, default "out"
        The folder to create. It is filled as ``<outdir>.partial-XXXX`` and
        renamed at the end, so a failed run leaves nothing.
    overwrite : bool, default False
        Whether an existing, non-empty ``outdir`` may be replaced.
    progress : callable, optional
        Called as ``progress(steps_done, steps_total)`` after each step.

    Returns
    -------
    list of DemoStep
        One entry per result, in the order written.

    Raises
    ------
    OutputExistsError
        If ``outdir`` exists, is not empty, and ``overwrite`` is false.
    """
    shoreline = data_path("norway_west_gshhg_f.geojson")
    raster = data_path("etopo1_0.1deg_orkney_wide.tif")
    jobs = [("shoreline", window, modes) for window, modes in _DEMO_SHORELINES]
    jobs += [("raster", window, modes) for window, modes in _DEMO_RASTERS]
    steps = []
    with atomic_directory(outdir, overwrite=overwrite) as folder:
        for done, (kind, window, modes) in enumerate(jobs, start=1):
            if kind == "shoreline":
                stem = f"norway_west_L{window}_r{modes}"
                data = f"{stem}.gpkg"
                report: ShorelineReport | RasterReport = simplify_shoreline_file(
                    shoreline,
                    folder / data,
                    window=window,
                    modes=modes,
                    plot=folder / f"{stem}.png",
                )
                title = (
                    f"West Norway shoreline, window {window} points, {_modes(modes)}"
                )
            else:
                stem = f"orkney_etopo1_{window}x{window}_r{modes}"
                data = f"{stem}.tif"
                report = simplify_raster_file(
                    raster,
                    folder / data,
                    window=window,
                    modes=modes,
                    plot=folder / f"{stem}.png",
                )
                title = (
                    f"Orkney ETOPO1, window {window} x {window} cells, {_modes(modes)}"
                )
            steps.append(DemoStep(title, (data, f"{stem}.png"), report))
            logger.info("demo: %s: %s", title, report.summary())
            if progress is not None:
                progress(done, len(jobs) + _DEMO_CASES)
        if _DEMO_CASES:
            steps.append(_demo_case(folder, Path(outdir)))
            if progress is not None:
                progress(len(jobs) + 1, len(jobs) + 1)
        (folder / "README.txt").write_text(_demo_readme(steps), encoding="utf-8")
    return steps


_DEMO_SHORELINES = ((100, 1), (500, 1), (100, 5))
#: 1: also run the bundled Orkney case (the whole chain); 0 in quick tests
_DEMO_CASES = 1


def _demo_case(folder: Path, final: Path) -> DemoStep:
    """Run the bundled Pentland Firth case into ``folder/pentland_firth``."""
    import dataclasses
    import warnings

    from coastmesh.case import run_case

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)  # dropped small islands
        result = run_case(
            data_path("pentland_firth.toml"), output=folder / "pentland_firth"
        )
    title = (
        "Orkney and the Pentland Firth: shoreline PCA by region, loxodrome open "
        "boundaries, graded Gmsh mesh, depth from the PCA of ETOPO1, 8 model formats, "
        "quality report"
    )
    outputs = ("pentland_firth/summary.txt", "pentland_firth/figures/mesh.png")
    # the folder is renamed from its .partial name when the demo ends
    result = dataclasses.replace(result, output=final / "pentland_firth")
    logger.info("demo: %s", result.summary())
    return DemoStep(title, outputs, result)


_DEMO_RASTERS = ((8, 1), (8, 16), (8, 48))


def _demo_readme(steps: list[DemoStep]) -> str:
    from coastmesh import __version__

    lines = [
        f"coastmesh {__version__} demo: PCA approximation of shorelines and "
        "bathymetry, and a whole tidal-model mesh",
        "",
        "Inputs (bundled with coastmesh, see coastmesh/data/README.md):",
        "  norway_west_gshhg_f.geojson    GSHHG 2.3.6 full resolution, LGPL-3.0+",
        "  etopo1_0.1deg_orkney_wide.tif  ETOPO1 bedrock, 0.1 degree, public domain",
        "  orkney_gshhg_f.geojson         GSHHG 2.3.6 full resolution, LGPL-3.0+",
        "  pentland_firth.toml            the case run into pentland_firth/",
        "",
        "Outputs (the .png files draw input and result together):",
    ]
    for step in steps:
        lines.append(f"  {', '.join(step.outputs)}")
        lines.append(f"      {step.title}")
        lines.append(f"      {step.report.summary()}")
    return "\n".join(lines) + "\n"


def _listed(dst: PathLike, plot: PathLike | None) -> str:
    return os.fspath(dst) + ("" if plot is None else f" and {os.fspath(plot)}")


def _modes(modes: int) -> str:
    return f"{modes} mode" if modes == 1 else f"{modes} modes"


def _check_outputs(dst: PathLike, plot: PathLike | None, *, overwrite: bool) -> None:
    check_output(dst, overwrite=overwrite)
    if plot is not None:
        plot_format(plot)
        check_output(plot, overwrite=overwrite)
        if os.path.abspath(plot) == os.path.abspath(dst):
            raise ConfigError(f"plot = {os.fspath(plot)}: the same file as the output")


def _parse_crs(crs: CRS | str | None) -> CRS | None:
    if crs is None or isinstance(crs, CRS):
        return crs
    try:
        return CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"crs = {crs!r}: not a CRS pyproj knows ({exc})") from None


def _with_crs(features: Features, crs: CRS | None) -> Features:
    if features.crs is None:
        if crs is None:
            raise InputDataError(
                "the layer has no CRS; give one with --crs (e.g. --crs EPSG:4326)",
                path=features.path,
                layer=features.layer,
            )
        return replace(features, crs=crs)
    if crs is not None and features.crs != crs:
        raise ConfigError(
            f"crs = {crs.to_string()!r}, but {features.path} declares "
            f"{features.crs.to_string()!r}; --crs is only for files without one"
        )
    return features


def _raster_crs(raster: xr.DataArray, crs: CRS | None, src: PathLike) -> str:
    declared = raster.attrs.get("crs")
    if declared is None:
        if crs is None:
            raise InputDataError(
                "the raster has no CRS; give one with --crs (e.g. --crs EPSG:4326)",
                path=os.fspath(src),
            )
        return crs.to_wkt()
    if crs is not None and CRS.from_user_input(declared) != crs:
        raise ConfigError(
            f"crs = {crs.to_string()!r}, but {os.fspath(src)} declares "
            f"{CRS.from_user_input(declared).to_string()!r}; "
            "--crs is only for files without one"
        )
    return declared


def _check_shoreline_types(features: Features) -> None:
    types = shapely.get_type_id(features.geometry)
    bad = np.flatnonzero((types >= 0) & ~np.isin(types, _SHORELINE_TYPES))
    if bad.size:
        first = int(bad[0])
        raise InputDataError(
            f"{features.geometry[first].geom_type} is not a polygon or a line "
            f"({bad.size} such features); shorelines must be polygons or lines",
            path=features.path,
            layer=features.layer,
            feature=int(features.fids[first]),
        )


def _locate(exc: InputDataError, features: Features) -> InputDataError:
    """Return ``exc`` again, naming the file, layer and feature id."""
    if exc.feature is None:
        return InputDataError(exc.message, path=features.path, layer=features.layer)
    return InputDataError(
        exc.message,
        path=features.path,
        layer=features.layer,
        feature=int(features.fids[exc.feature]),
    )


def _provenance(command: str, src: PathLike, **parameters: object) -> dict[str, str]:
    from coastmesh import __version__

    settings = " ".join(f"--{k} {v}" for k, v in parameters.items())
    stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    notes = {
        "history": f"{stamp} coastmesh {__version__} {command} {os.fspath(src)} "
        f"{settings}",
        "coastmesh_version": __version__,
        "coastmesh_command": command,
        "coastmesh_source": os.fspath(src),
    }
    notes.update({f"coastmesh_{k}": str(v) for k, v in parameters.items()})
    return notes
