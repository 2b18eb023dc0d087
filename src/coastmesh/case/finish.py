"""The case's report and result, once its mesh is made and measured."""

from __future__ import annotations

import logging
import sys
import time
from typing import Any

from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.report import CaseReport, MeshReport
from coastmesh.case.result import CaseResult
from coastmesh.sizing.domain import SizeField

__all__ = ["finish_case", "peak_memory_mb"]

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
