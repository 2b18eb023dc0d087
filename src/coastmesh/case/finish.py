"""A case's mesh measured (depths, time step, quality), then its report and result."""

from __future__ import annotations

import logging
import sys
import time
from typing import Any

from pyproj import CRS

from coastmesh.case.advice import warn_avoidable_corners, warn_spanning
from coastmesh.case.config import CaseConfig
from coastmesh.case.depths import depth_raster, node_depths, relieve
from coastmesh.case.figures import FigureJobs, mesh_jobs, quality_jobs
from coastmesh.case.report import CaseReport, MeshReport
from coastmesh.case.result import CaseResult
from coastmesh.meshing import mesh_quality
from coastmesh.sizing.domain import SizeField
from coastmesh.types import Mesh, StageFactory

__all__ = ["finish_case", "measure_mesh", "peak_memory_mb"]

logger = logging.getLogger("coastmesh.case.build")


def finish_case(
    config: CaseConfig,
    mesh: Any,
    inputs: Any,
    sized: SizeField,
    parts: Any,
    after: dict[str, Any],
    timings: dict[str, float],
    started: float,
    *,
    crs: CRS,
    mesh_crs: CRS,
    output_crs: CRS,
    set_reports: dict[str, Any],
) -> CaseResult:
    """Return the case's report and result, once its mesh is made and measured."""
    from coastmesh import __version__

    report = CaseReport(
        case=config.name,
        source=None if config.source is None else str(config.source),
        coastmesh_version=__version__,
        crs=crs.to_string(),
        mesh_crs=mesh_crs.to_wkt()
        if mesh_crs.to_epsg() is None
        else mesh_crs.to_string(),
        output_crs=output_crs.to_string(),
        shoreline_sets=set_reports,
        stitch=inputs.stitch_report,
        domain=inputs.domain_report,
        size_field=sized.report,
        mesh=MeshReport.of(mesh),
        seconds=timings,
        peak_memory_mb=peak_memory_mb(),
        parts=parts,
        **after,
    )
    result = CaseResult(
        config=config,
        mesh=mesh,
        domain=inputs.domain,
        size=sized.field,
        report=report,
        regions=tuple(inputs.regions),
        open_boundaries=tuple(inputs.open_boundaries),
        crs=crs,
        seconds=time.perf_counter() - started,
        channel_width=sized.width,
    )
    logger.info("%s", result.summary())
    return result


def peak_memory_mb() -> float | None:
    """Return the peak resident memory of this process, MB; None if unknown.

    The ``resource`` module is Unix-only: on Windows the peak is not measured.
    """
    try:
        import resource
    except ImportError:
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # Linux reports KiB, macOS bytes
    return round(peak / (1024 * 1024 if sys.platform == "darwin" else 1024), 1)


def measure_mesh(
    config: CaseConfig,
    mesh: Mesh,
    timed: StageFactory,
    sized: SizeField,
    cleanup: Any,
    *,
    figures: FigureJobs | None = None,
    domain: Any = None,
) -> tuple[Mesh, dict[str, Any]]:
    """Depth at the nodes, time step and quality, as the case asks.

    ``cleanup`` is the report of the cleanup done with the meshing, part by
    part. ``timed(label)`` times a stage. The mesh's figures start on
    ``figures`` once it has its depths (again if the time-step relief changes
    it), before its quality is measured, and the quality figure once it is;
    ``domain`` (the case's, needed with ``figures``) names the boundaries in
    them.
    """
    after: dict[str, Any] = {"cleanup": cleanup, "depth": None, "quality": None}
    c = config.cleanup
    started = False

    def start_figures(again: bool = False) -> None:
        if figures is not None:
            jobs = mesh_jobs(config.name, mesh, domain, config, after["depth"])
            figures.start(jobs, len(mesh.triangles), again=again)

    if config.bathymetry is not None:
        with timed("depth at the nodes") as progress:
            raster = depth_raster(config, mesh, progress)
            mesh, after["depth"] = node_depths(config, mesh, raster, progress)
        if c.enabled and c.time_step:
            # drawn while the time step is relieved (a stage of one core),
            # and again in the seldom case that the relief changes the mesh
            start_figures()
            started = True
            with timed("time step") as progress:
                relieved, after["time_step"], depth = relieve(
                    config, mesh, raster, after["cleanup"], progress
                )
            after["depth"] = depth or after["depth"]
            if relieved is not mesh:
                mesh = relieved
                start_figures(again=True)
    if not started:
        start_figures()
    if config.outputs.quality:
        courant = config.size.courant
        with timed("mesh quality"):
            after["quality"] = mesh_quality(
                mesh,
                dt=None if courant is None else courant.dt,
                velocity=0.0 if courant is None else courant.velocity,
                courant_max=None if courant is None else courant.courant_max,
                courant_min=None if courant is None else courant.courant_min,
            )
        if figures is not None:
            jobs = quality_jobs(config.name, mesh, after["quality"])
            figures.start(jobs, len(mesh.triangles))
        warn_avoidable_corners(after["quality"], mesh)
        field = sized.field
        warn_spanning(
            after["quality"],
            mesh,
            cell=float(abs(field.x[1] - field.x[0])),
            h_min=sized.report.h_min_m,
            narrow=config.size.channels.narrow,
        )
    return mesh, after
