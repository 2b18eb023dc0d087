"""``coastmesh demo``: the paper's examples and a whole case on the bundled data."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.commands._common import PathLike, modes_label
from coastmesh.commands.simplify_raster import simplify_raster_file
from coastmesh.commands.simplify_shoreline import simplify_shoreline_file
from coastmesh.data import path as data_path
from coastmesh.errors import CoastmeshWarning
from coastmesh.io import atomic_directory
from coastmesh.types import Progress, Report

__all__ = ["DemoStep", "run_demo"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class DemoStep(Report):
    """One output set of :func:`run_demo`.

    Attributes
    ----------
    title : str
        What was done, e.g. ``"West Norway shoreline, window 100, 1 mode"``.
    outputs : tuple of str
        File names written into the demo folder (data, then plot).
    report : ShorelineReport, RasterReport or CaseResult
        What the step did (each has ``summary()`` and ``to_dict()``).
    """

    title: str
    outputs: tuple[str, ...]
    report: Any

    def summary(self) -> str:
        """Return a one-line summary: the title and the step's own summary."""
        return f"{self.title}: {self.report.summary()}"


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
    eight model formats, ADCIRC and SCHISM smoke-test run folders, the quality
    report and the figures. ``README.txt`` lists
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
    jobs: list[tuple[Callable[..., Report], str, str, int, int]] = [
        (simplify_shoreline_file, "norway_west_gshhg_f.geojson", ".gpkg", w, m)
        for w, m in _DEMO_SHORELINES
    ]
    jobs += [
        (simplify_raster_file, "etopo1_0.1deg_orkney_wide.tif", ".tif", w, m)
        for w, m in _DEMO_RASTERS
    ]
    steps = []
    with atomic_directory(outdir, overwrite=overwrite) as folder:
        for done, (run, source, suffix, window, modes) in enumerate(jobs, start=1):
            if suffix == ".gpkg":
                stem = f"norway_west_L{window}_r{modes}"
                what = f"West Norway shoreline, window {window} points"
            else:
                stem = f"orkney_etopo1_{window}x{window}_r{modes}"
                what = f"Orkney ETOPO1, window {window} x {window} cells"
            report = run(
                data_path(source),
                folder / f"{stem}{suffix}",
                window=window,
                modes=modes,
                plot=folder / f"{stem}.png",
            )
            title = f"{what}, {modes_label(modes)}"
            steps.append(DemoStep(title, (f"{stem}{suffix}", f"{stem}.png"), report))
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

    from coastmesh.case import CaseResult, run_case

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)  # dropped small islands
        result = run_case(
            data_path("pentland_firth.toml"), output=folder / "pentland_firth"
        )
    title = (
        "Orkney and the Pentland Firth: shoreline PCA by region, loxodrome open "
        "boundaries, graded Gmsh mesh, depth from the PCA of ETOPO1, 8 model formats, "
        "ADCIRC and SCHISM smoke tests, quality report"
    )
    outputs = ("pentland_firth/summary.txt", "pentland_firth/figures/mesh.png")
    assert isinstance(result, CaseResult)  # a mesh case, not a study
    # the folder is renamed from its .partial name when the demo ends
    result = dataclasses.replace(result, output=final / "pentland_firth")
    logger.info("demo: %s", result.summary())
    return DemoStep(title, outputs, result)


_DEMO_RASTERS = ((8, 1), (8, 16), (8, 48))


def _demo_readme(steps: list[DemoStep]) -> str:
    from coastmesh.version import __version__

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
