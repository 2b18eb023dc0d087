"""What a case makes: :class:`CaseResult`, in memory, and the files it writes.

:meth:`CaseResult.write` writes the model formats, the domain, the size field,
the reports and the figures into ``<folder>.partial-XXXX/``, renamed to
``folder`` when all is written.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig, OutputConfig, StudyCase
from coastmesh.case.dump import dump_case
from coastmesh.case.figures import FigureJobs, figure_jobs
from coastmesh.case.pipeline.farms import write_turbines
from coastmesh.case.pipeline.state import FinishedRun
from coastmesh.case.report import CaseReport
from coastmesh.errors import ConfigError
from coastmesh.geometry import OpenBoundary
from coastmesh.io import (
    atomic_directory,
    mesh_format,
    write_domain,
    write_mesh,
    write_model_test,
    write_raster,
    write_report,
)
from coastmesh.io.meshes.model_tests import model_test_step
from coastmesh.types import Domain, Features, Mesh, SizeGrid, StageFactory, quiet_stage
from coastmesh.version import __version__

if TYPE_CHECKING:
    import xarray as xr

    from coastmesh.case.pipeline.farms import SiteFeatures
    from coastmesh.meshing import QualityReport

__all__ = ["CaseResult", "model_dt", "write_case_copy"]


@dataclass(frozen=True, slots=True)
class CaseResult:
    """A case built in memory by :func:`coastmesh.build_case`.

    Attributes
    ----------
    config : CaseConfig
        The case.
    mesh : Mesh
        Points in the output CRS, triangles, boundary edges with their ids,
        names and kinds, and node data: ``size`` (the target size, metres) and,
        with ``[bathymetry]``, ``depth`` (metres, positive down).
    domain : Domain
        The domain meshed, in the case CRS.
    size : xarray.DataArray
        The size field, metres, on a grid in the mesh CRS (:attr:`size_grid`
        as a :class:`~coastmesh.types.SizeGrid`).
    report : CaseReport
        Every stage's report (shoreline sets, stitching, domain, size, mesh,
        cleanup, depth, quality, times).
    regions : tuple of (name, id, geometry or None)
        Where each shoreline set is used, in the case CRS.
    open_boundaries : tuple of OpenBoundary
        The open boundaries as drawn, before trimming at the coast.
    crs : pyproj.CRS
        The case CRS.
    seconds : float
        Wall time, building (and, after :func:`coastmesh.run_case`, writing).
    output : pathlib.Path or None
        The folder written by :func:`coastmesh.run_case`; None in memory.
    files : tuple of str
        The files written there, relative to it.
    channel_width : xarray.DataArray or None
        With the channel term: the width of the water on the size grid, metres
        (NaN outside the domain, inf where wider than matters).
    site : SiteFeatures or None
        The case's farms and turbines, checked, in the mesh CRS
        (:mod:`coastmesh.case.pipeline.farms`); None without them.
    """

    config: CaseConfig
    mesh: Mesh
    domain: Domain
    size: xr.DataArray
    report: CaseReport
    regions: tuple[tuple[str, int, shapely.Geometry | None], ...]
    open_boundaries: tuple[OpenBoundary, ...]
    crs: CRS
    seconds: float
    output: Path | None = None
    files: tuple[str, ...] = ()
    channel_width: xr.DataArray | None = None
    site: SiteFeatures | None = None

    @classmethod
    def of(
        cls, run: FinishedRun, seconds: Mapping[str, float], elapsed: float
    ) -> CaseResult:
        """Return what a finished run made, its report read from it.

        ``seconds``: the time of each timed step; ``elapsed``: the whole build.
        """
        domain = run.domain
        return cls(
            config=run.config,
            mesh=run.mesh.mesh,
            domain=domain.domain,
            size=run.size.field,
            report=CaseReport.of(run, seconds),
            regions=domain.regions,
            open_boundaries=domain.open_boundaries,
            crs=run.shorelines.crs,
            seconds=elapsed,
            channel_width=run.size.layers.get("width"),
            site=run.site,
        )

    @property
    def name(self) -> str:
        """The case's name."""
        return self.config.name

    @property
    def nodes(self) -> int:
        """Number of mesh nodes."""
        return len(self.mesh.points)

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return len(self.mesh.triangles)

    @property
    def boundary_edges(self) -> dict[str, int]:
        """Boundary edges by ``"name (id)"``."""
        return self.report.mesh.boundary_edges

    @property
    def size_grid(self) -> SizeGrid:
        """The size field as a :class:`~coastmesh.types.SizeGrid` (mesh CRS)."""
        return SizeGrid.from_dataarray(self.size)

    def to_dict(self) -> dict[str, object]:
        """Return the report as data, with where it was written and the time."""
        return self.report.to_dict() | {
            "output": None if self.output is None else str(self.output),
            "seconds_total": self.seconds,
        }

    def summary(self) -> str:
        """Return a one-line summary."""
        where = (
            ""
            if self.output is None
            else f"; {len(self.files)} files in {self.output}/"
        )
        return (
            f"{self.name}: {self.report.mesh.summary()}{where} in {self.seconds:.1f} s"
        )

    def write(
        self,
        folder: str | os.PathLike[str],
        *,
        formats: tuple[str, ...] | list[str] | None = None,
        overwrite: bool = False,
        stage: StageFactory | None = None,
        workers: int = 1,
        figures: FigureJobs | None = None,
    ) -> CaseResult:
        """Write the mesh formats, domain, size field, reports and figures.

        This is what ``coastmesh run`` writes: everything goes into
        ``<folder>.partial-XXXX/``, renamed to ``folder`` at the end, so a
        failure leaves nothing.

        Parameters
        ----------
        folder : str or path-like
            The output folder; it must not exist or be empty, unless
            ``overwrite``.
        formats : sequence of str, optional
            Mesh formats by name (:func:`coastmesh.io.mesh_formats`); default
            the case's ``[output] formats``.
        overwrite : bool, default False
            Whether a non-empty ``folder`` may be replaced.
        stage : callable, optional
            ``stage(label)`` returns a context manager (for a progress bar).
        workers : int, default 1
            Processes the figures of a large mesh are drawn on
            (:mod:`coastmesh.case.figures`; started as spawned ones are, by
            importing the main script: a script that passes more
            than 1 runs under ``if __name__ == "__main__":``), while this one
            writes the mesh files. The files are the same for any number.
        figures : FigureJobs, optional
            Figures already being drawn (:func:`coastmesh.run_case` starts
            them while the mesh is measured); ``workers`` is then its own.

        Returns
        -------
        CaseResult
            This result with ``output``, ``files`` and ``report.files`` set.

        Raises
        ------
        ConfigError
            If a format is unknown.
        OutputExistsError
            If ``folder`` exists, is not empty, and ``overwrite`` is false.
        """
        result = self
        if formats is not None:  # checked as the case's [output] formats
            outputs = dataclasses.replace(self.config.outputs, formats=tuple(formats))
            config = dataclasses.replace(self.config, outputs=outputs)
            result = dataclasses.replace(self, config=config)
        report = _write_case(
            result,
            Path(folder),
            result.config.outputs,
            overwrite=overwrite,
            stage=stage,
            figures=figures or FigureJobs(workers),
        )
        return dataclasses.replace(
            result,
            output=Path(folder),
            files=report.files,
            report=report,
        )


def _write_case(
    result: CaseResult,
    folder: Path,
    outputs: OutputConfig,
    *,
    overwrite: bool = False,
    stage: StageFactory | None = None,
    figures: FigureJobs,
) -> CaseReport:
    """Write every output of a case into ``folder``, atomically.

    Parameters
    ----------
    result : CaseResult
        What the case made.
    folder : pathlib.Path
        The output folder.
    outputs : OutputConfig
        What to write (formats, domain, size field, quality, figures).
    overwrite : bool, default False
        Whether a non-empty ``folder`` may be replaced.
    stage : callable, optional
        ``stage(label)`` returns a context manager, entered once.
    figures : FigureJobs
        Draws the figures (:mod:`coastmesh.case.figures`): here, or on a
        pool while this process writes the mesh files.

    Returns
    -------
    CaseReport
        The report written (``report.json``): the case's, with ``files`` (names
        relative to ``folder``, in the order written) and ``model_tests``.
    """
    jobs = figure_jobs(result) if outputs.figures else []
    triangles = len(result.mesh.triangles)
    with (
        (stage or quiet_stage)("writing outputs"),
        atomic_directory(folder, overwrite=overwrite) as partial,
        figures,
    ):
        figures.start(jobs, triangles)  # on the pool, while the files are written
        files = _write_models(result, partial, outputs)
        tests, steps = _write_model_tests(result, partial, outputs.model_test)
        files += tests
        if result.site is not None and result.site.turbines:
            write_turbines(partial / "turbines.csv", result.site, result.mesh)
            files.append("turbines.csv")
        if outputs.domain:
            _write_domain(partial / "domain.gpkg", result)
            files.append("domain.gpkg")
        if outputs.size_field:
            write_raster(partial / "size.tif", result.size)
            files.append("size.tif")
        quality = result.report.quality
        if quality is not None and outputs.quality:
            write_report(
                partial / "quality.json", quality, summary=partial / "quality.txt"
            )
            files += ["quality.json", "quality.txt"]
        files += figures.save(jobs, partial, triangles)
        write_case_copy(partial, result.config)
        files += ["case.toml", "report.json", "summary.txt"]
        report = dataclasses.replace(
            result.report, files=tuple(files), model_tests=steps
        )
        write_report(partial / "report.json", report, summary=partial / "summary.txt")
    return report


def write_case_copy(folder: Path, config: CaseConfig | StudyCase) -> None:
    """Keep the case as run, as ``case.toml``, saying where it came from.

    A case read from a file is copied as it is (its relative paths stay
    relative to that file); a case built in Python is written with
    :func:`~coastmesh.case.dump_case`, so ``coastmesh run case.toml`` runs it again.
    """
    if config.source is not None:
        header = (
            f"# A copy of {Path(config.source).resolve()}, as run by coastmesh "
            f"{__version__}.\n# Its relative paths are relative to that file, not "
            "to this copy.\n"
        )
        text = config.text
    else:
        header = (
            f"# A case built in Python, as run by coastmesh {__version__}.\n"
            "# Run it again with: coastmesh run case.toml\n"
        )
        # a study case is always read from its file
        text = dump_case(config) if isinstance(config, CaseConfig) else config.text
    (folder / "case.toml").write_text(header + text, encoding="utf-8")


def _write_models(result: CaseResult, folder: Path, outputs: OutputConfig) -> list[str]:
    """Write the mesh in each format of ``[output] formats``, and its companions.

    What each format can hold (nodes on the sphere, a depth sign, files written
    beside it) comes from the format registry, never from its name.
    """
    name = result.name
    files: list[str] = []
    taken: set[str] = set()
    for fmt_name in outputs.formats:
        fmt = mesh_format(fmt_name)
        suffix = fmt.extensions[0]
        filename = f"{name}{suffix}"
        if filename in taken:
            filename = f"{name}-{fmt_name}{suffix}"
        taken.add(filename)
        options: dict[str, object] = {}  # the format's own keyword options
        if outputs.positive and fmt_name in outputs.positive:
            options["positive"] = outputs.positive[fmt_name]
        if outputs.sphere_xyz and "sphere_xyz" in fmt.holds:
            options["sphere_xyz"] = True
        options |= (outputs.options or {}).get(fmt_name, {})
        write_mesh(
            folder / filename, result.mesh, format=fmt_name, overwrite=False, **options
        )
        files.append(filename)
        ends = fmt.companions_for(result.mesh)
        files += [f"{Path(filename).stem}{ext}" for ext in ends]
    return files


def _write_model_tests(
    result: CaseResult, folder: Path, models: tuple[str, ...]
) -> tuple[list[str], dict[str, float]]:
    """Write the smoke-test run folders of ``[output] model_test``.

    The time step is the one the case measured its Courant numbers at (the
    Courant term's ``dt``), else the mesh's largest stable one; SCHISM takes
    one of its own rules. Return the files and each model's step.
    """
    if not models:
        return [], {}
    dt = model_dt(result.report.quality)
    land = (result.config.outputs.options or {}).get("fort14", {}).get("land")
    if land is not None and not isinstance(land, str):
        raise ConfigError(
            f'output.options.fort14.land = {land!r}: expected "natural" or "essential"'
        )
    files, steps = [], {}
    for model in models:
        sub = folder / "model_test" / model
        written = write_model_test(sub, result.mesh, model, dt=dt, land=land)
        files += [f"model_test/{model}/{name}" for name in written]
        steps[model] = model_test_step(result.mesh, model, dt=dt)
    return files, steps


def model_dt(quality: QualityReport | None) -> float:
    """Return the time step a case reports for its mesh, s.

    The Courant term's ``dt`` (``quality.time_step.courant.dt``), else the
    largest time step at which every element is stable
    (``quality.time_step.min``).

    Raises
    ------
    ConfigError
        If the report has no time step (a mesh without depths).
    """
    step = None if quality is None else quality.time_step
    if step is None:
        raise ConfigError(
            "the mesh has no time step in its quality report (no depths at the "
            "nodes): a model test needs [bathymetry]"
        )
    if step.courant is not None:
        return float(step.courant.dt)
    return float(step.min)


def _write_domain(path: Path, result: CaseResult) -> None:
    """Write the domain GeoPackage, with the untrimmed boundaries and the regions."""
    # the walls and regions are where the domain was built (the stereographic
    # plane of a global case)
    walls, crs = result.open_boundaries, result.domain.crs
    extra = {}
    if walls:
        extra["open_boundaries_untrimmed"] = _layer(
            [shapely.LineString(w.coords) for w in walls],
            crs,
            name=[w.name for w in walls],
            physical_id=[w.physical_id for w in walls],
        )
    used = [(n, i, r) for n, i, r in result.regions if r is not None]
    if used:
        extra["regions"] = _layer(
            [r for _, _, r in used],
            crs,
            shoreline_set=[n for n, _, _ in used],
            physical_id=[i for _, i, _ in used],
        )
    notes = {
        "coastmesh_version": __version__,
        "case": result.name,
        "case_file": result.config.label,
    }
    write_domain(path, result.domain, metadata=notes, extra_layers=extra)


def _layer(
    geometry: Sequence[shapely.Geometry], crs: CRS, **fields: Sequence[object]
) -> Features:
    return Features(
        np.array(geometry, dtype=object),
        crs,
        {
            key: np.array(values, dtype=object if isinstance(values[0], str) else None)
            for key, values in fields.items()
        },
        np.arange(len(geometry)),
        "<memory>",
    )
