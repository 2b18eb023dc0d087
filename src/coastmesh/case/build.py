"""Build a whole case in memory: :func:`build_case`.

The stages, each reported to the ``stage`` factory and the log:

1. read the shoreline file; 2. build each shoreline set; 3. stitch the sets by
region, draw the open boundaries and build the domain
(:mod:`coastmesh.case.inputs`);
4. the size field (:func:`coastmesh.sizing.domain_size_field`): gradations from
   named shoreline sets and open boundaries, bathymetry terms, a gradation
   limit, on a grid in the meshing CRS;
5. mesh with Gmsh and clean up (:func:`~coastmesh.meshing.generate_mesh` and
   :func:`~coastmesh.meshing.clean_mesh`, both part by part, on a process pool
   or a Dask cluster: :mod:`coastmesh.case.executor`), put depths on the nodes
   (:func:`~coastmesh.depth.depth_at_nodes`) and measure the quality
   (:func:`~coastmesh.meshing.mesh_quality`).

Nothing is written: :meth:`CaseResult.write` writes the files, and
:func:`coastmesh.run_case` does both.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
from pyproj import CRS

from coastmesh.case.config import CaseConfig, StudyCase
from coastmesh.case.executor import open_runner
from coastmesh.case.figures import FigureJobs, parts_jobs, setup_jobs
from coastmesh.case.finish import finish_case, measure_mesh, peak_memory_mb
from coastmesh.case.globe import build_global
from coastmesh.case.inputs import (
    bathymetry_terms,
    build_case_domain,
    build_shoreline_set,
    depth_stack,
    read_shorelines,
)
from coastmesh.case.result import CaseResult
from coastmesh.case.sources import check_rasters
from coastmesh.errors import ConfigError
from coastmesh.geometry.layers import densify_long_edges
from coastmesh.meshing import (
    CleanupOptions,
    default_mesh_crs,
)
from coastmesh.meshing.engine import mesh_in_parts
from coastmesh.meshing.gmsh.model import release_memory
from coastmesh.meshing.parts.tasks import Runner
from coastmesh.sizing.domain import (
    BoundaryGradation,
    SizeField,
    domain_slots,
    size_field_with_report,
)
from coastmesh.sizing.terms import ChannelSize, CourantSize, warn_narrow
from coastmesh.types import (
    Mesh,
    Progress,
    SizeGrid,
    StageFactory,
    local_cores,
    quiet_stage,
)

__all__ = [
    "CLOSE_PASSES",
    "as_case",
    "build_case",
    "build_drawing",
    "peak_memory_mb",
    "worker_count",
]

#: Most times narrow channels are closed and the domain built again.
CLOSE_PASSES = 2

logger = logging.getLogger(__name__)


def build_case(
    case: CaseConfig | str | os.PathLike[str],
    *,
    stage: StageFactory | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
) -> CaseResult:
    """Build a whole mesh case in memory; write nothing.

    Parameters
    ----------
    case : CaseConfig, path or str
        The case: a :class:`CaseConfig`, the path of a case file, or the TOML
        text of one (relative paths then are relative to the working folder).
    stage : callable, optional
        ``stage(label)`` returns a context manager yielding a
        ``progress(done, total)`` callback, entered once per stage (the command
        line draws a progress bar per stage with it).
    workers : int, optional
        Local processes the parts of the water (``[mesh] parts``) are meshed
        on; default ``[run] workers``, else every core. The mesh does not
        depend on it.
    scheduler : str, optional
        A Dask scheduler's address (``"tcp://host:8786"``): the parts are
        meshed as tasks on its cluster; default ``[run] scheduler``, else
        none (this machine). The mesh does not depend on it.

    Returns
    -------
    CaseResult
        The mesh, domain, size field and every report;
        :meth:`CaseResult.write` writes them as ``coastmesh run`` does.

    Raises
    ------
    ConfigError
        For a bad case, a study case (use :func:`coastmesh.run_case`), a
        value that does not fit the data (e.g. a seed on land), or a
        scheduler that does not answer (checked before any work).
    InputDataError
        If a data file is missing or holds the wrong kind of geometry.
    MeshingError
        If Gmsh fails.

    Notes
    -----
    ``docs/python-api.md`` builds the Orkney case from Python, region by
    region, then plots the mesh and writes two formats.

    A case meshed in several parts on several workers starts worker
    processes, which import the main script again: call this from a script
    under ``if __name__ == "__main__":`` (or pass ``workers=1``).
    """
    return build_drawing(case, stage=stage, workers=workers, scheduler=scheduler)


def build_drawing(
    case: CaseConfig | str | os.PathLike[str],
    *,
    stage: StageFactory | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    figures: FigureJobs | None = None,
) -> CaseResult:
    """:func:`build_case`, starting each figure on ``figures`` once it can.

    The domain, size and channel figures start once the size field is made,
    the parts figure once the water is meshed, the mesh's figures once it has
    its depths (again if the time-step relief changes it), the quality
    figure once it is measured
    (:mod:`coastmesh.case.figures`): with a pool, they are drawn while this
    process goes on. A global case starts only the mesh's and the quality
    figure; the others start when it is written.
    """
    if workers is not None:
        worker_count(workers)  # checked before any work
    config = as_case(case)
    if isinstance(config, StudyCase):
        raise ConfigError(
            f"{config.source}: a {config.kind} study writes its tables and figures; "
            "run it with coastmesh.run_case (or coastmesh run), not build_case"
        )
    threads = worker_count(workers if workers is not None else config.run.workers)
    with open_runner(threads, scheduler or config.run.scheduler) as runner:
        drawing = figures if config.outputs.figures else None
        return _build(config, stage, threads, runner, drawing)


def _build(
    config: CaseConfig,
    stage: StageFactory | None,
    threads: int,
    runner: Runner,
    figures: FigureJobs | None,
) -> CaseResult:
    """Build the case (see :func:`build_case`) with the parts meshed by ``runner``."""
    started = time.perf_counter()
    timings: dict[str, float] = {}
    stage = stage or quiet_stage

    @contextlib.contextmanager
    def timed(label: str) -> Iterator[Progress]:
        t0 = time.perf_counter()
        logger.info("stage: %s", label)
        with stage(label) as progress:
            yield progress
        timings[label] = round(time.perf_counter() - t0, 3)

    check_rasters(config)  # a bad raster fails now, not after the meshing
    if config.domain.kind == "global":
        return build_global(
            config, timed, timings, threads, runner,
            figures=figures, cleanup=_cleanup(config),
        )  # fmt: skip
    with timed("reading shorelines"):
        features, crs = read_shorelines(config)
    sets, set_reports = {}, {}
    dense = None  # the coasts with long edges split: the same for every PCA set
    for s in config.sets:
        label = f"shoreline set {s.name!r} ({s.label})"
        with timed(label) as progress:
            if dense is None and s.pca:
                dense = densify_long_edges(features.geometry)
            sets[s.name], set_reports[s.name] = build_shoreline_set(
                s, features, crs, config.shorelines.min_area, progress, dense
            )
        logger.info("%s: %s", label, set_reports[s.name].summary())
    with timed("building the domain"):
        inputs = build_case_domain(config, sets, crs)
    domain = inputs.domain
    mesh_crs = (
        CRS.from_user_input(config.mesh.crs)
        if config.mesh.crs
        else default_mesh_crs(domain)
    )
    inputs, closed, slots = _close_water(
        config, sets, crs, inputs, mesh_crs, timed, threads
    )
    domain = inputs.domain
    with timed("size field") as progress:
        sized = _size_field(config, domain, mesh_crs, progress, runner=runner)
    if slots:
        channels = dataclasses.replace(sized.report.channels, slots=slots)
        sized = dataclasses.replace(
            sized, report=dataclasses.replace(sized.report, channels=channels)
        )
    if closed is not None:
        if sized.report.channels.narrow_channels:
            warn_narrow(sized.report.channels, after_closing=CLOSE_PASSES)
        channels = dataclasses.replace(
            sized.report.channels,
            narrow="close",
            closed=closed.narrow_channels,
            closed_km2=closed.narrow_km2,
        )
        report = dataclasses.replace(sized.report, channels=channels)
        sized = dataclasses.replace(sized, report=report)
    _start_setup_figures(figures, config, domain, sized)
    size = sized.field
    output_crs = CRS.from_user_input(config.mesh.output_crs or crs)
    cleanup = _cleanup(config)
    release_memory()  # what the shoreline sets and slots freed, before the workers
    with timed("meshing") as progress:
        mesh, parts = mesh_in_parts(
            domain,
            SizeGrid.from_dataarray(size),
            mesh_crs=mesh_crs,
            output_crs=output_crs,
            seed=config.mesh.seed,
            algorithm=config.mesh.algorithm,
            optimize=config.mesh.optimize,
            parts=config.mesh.parts,
            threads=threads,
            runner=runner,
            cleanup=cleanup,
            progress=progress,
        )
    if parts.parts > 1:
        logger.info("parts: %s", parts.summary())
    _start_parts_figure(figures, config, domain, parts, mesh)
    mesh, after = measure_mesh(
        config, mesh, timed, sized, parts.cleanup, figures=figures, domain=domain
    )
    return finish_case(
        config, mesh, inputs, sized, parts, after, timings, started,
        crs=crs, mesh_crs=mesh_crs, output_crs=output_crs, set_reports=set_reports,
    )  # fmt: skip


def _start_setup_figures(
    figures: FigureJobs | None, config: CaseConfig, domain: Any, sized: SizeField
) -> None:
    """Start the figures of the domain and size field: drawn during the meshing.

    Whether they go to the pool is decided on the triangles the size field
    asks for over its whole grid (land too: an overestimate of the mesh).
    """
    if figures is not None:
        jobs = setup_jobs(
            config.name,
            domain,
            sized.field,
            channel_width=sized.width,
            channels=sized.report.channels,
        )
        h = sized.field.values
        cell = float(abs(sized.field.x[1] - sized.field.x[0]))
        figures.start(jobs, int((4 / np.sqrt(3) * cell**2 / h**2).sum()))


def _start_parts_figure(
    figures: FigureJobs | None, config: CaseConfig, domain: Any, parts: Any, mesh: Mesh
) -> None:
    """Start the figure of the parts: drawn while the mesh is measured."""
    if figures is not None:
        jobs = parts_jobs(config.name, domain, parts, mesh.crs)
        figures.start(jobs, len(mesh.triangles))


def _cleanup(config: CaseConfig) -> CleanupOptions | None:
    c = config.cleanup
    if not c.enabled:
        return None
    return CleanupOptions(c.boundary_triangles, c.max_valence, c.min_angle, c.smooth)


def worker_count(workers: int | None) -> int:
    """``workers``, checked; None is every core this process may use."""
    if workers is None:
        return local_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"workers = {workers!r}: expected an integer >= 1")
    return workers


def as_case(case: Any) -> CaseConfig | StudyCase:
    """Return ``case`` as a case: a config as it is, a path or TOML text read.

    A string holding a newline is TOML text; any other string or path names a
    case file.
    """
    from coastmesh.case.parse import parse_case, read_case

    if isinstance(case, CaseConfig | StudyCase):
        return case
    if isinstance(case, str) and "\n" in case:
        # relative paths are taken from the working folder; the text is not a
        # file, so the case keeps no source (case.toml is written from it)
        parsed = parse_case(case, "<case text>")
        if isinstance(parsed, StudyCase):
            return parsed
        return dataclasses.replace(parsed, source=None, text="")
    if isinstance(case, str | os.PathLike):
        return read_case(case)
    raise TypeError(
        f"case is a {type(case).__name__}; expected a CaseConfig, the path of a "
        "case file, or its TOML text"
    )


def _size_field(
    config: CaseConfig,
    domain: Any,
    mesh_crs: CRS,
    progress: Progress | None,
    *,
    channels_only: bool = False,
    runner: Runner | None = None,
) -> SizeField:
    """``[mesh_size]`` as :func:`coastmesh.sizing.size_field_with_report` takes it.

    The Courant term takes its depths from ``[mesh_size.bathymetry]``, else from
    ``[bathymetry]``. ``channels_only``: the channel term alone, on the same
    grid and floor (to find the narrow channels to close). ``runner``: where
    the distance terms run, in bands (:mod:`coastmesh.sizing.bands`).
    """
    size = config.size
    if channels_only:
        return size_field_with_report(
            domain,
            mesh_crs=mesh_crs,
            h_max=size.h_max,
            h_min=_floor(config),
            cell=size.cell,
            channels=ChannelSize(size.channels.elements_across, "close"),
        )
    bathymetry = None
    if size.bathymetry is not None:
        bathymetry = bathymetry_terms(size.bathymetry, domain)
    channels = None
    if size.channels.enabled:
        # with "close", build_case has closed them already, and warns of any
        # left after that
        channels = ChannelSize(size.channels.elements_across, size.channels.narrow)
    courant = None
    if size.courant is not None:
        source = size.bathymetry or config.bathymetry
        min_depth = getattr(source, "min_depth", None)
        courant = CourantSize(
            bathymetry.raster
            if bathymetry is not None
            else depth_stack(source, domain),
            dt=size.courant.dt,
            positive=source.positive,
            courant_max=size.courant.courant_max,
            courant_min=size.courant.courant_min,
            velocity=size.courant.velocity,
            min_depth=min_depth if min_depth is not None and min_depth > 0 else 1.0,
        )
    return size_field_with_report(
        domain,
        mesh_crs=mesh_crs,
        h_max=size.h_max,
        gradations=[
            BoundaryGradation(g.lines, g.h_min, g.d_grade, g.d_hold)
            for g in size.gradations
        ],
        h_min=size.h_min,
        cell=size.cell,
        rate=size.rate,
        bathymetry=bathymetry,
        channels=channels,
        courant=courant,
        progress=progress,
        runner=runner,
    )


def _close_water(
    config: CaseConfig,
    sets: dict[str, Any],
    crs: CRS,
    inputs: Any,
    mesh_crs: CRS,
    timed: StageFactory,
    threads: int = 1,
) -> tuple[Any, Any, int]:
    """Close what the channel term asks: narrow channels and slots, or slots.

    Returns the domain inputs, the report of the channels closed (or None) and
    the number of slots closed with ``narrow = "keep"``.
    """
    if not config.size.channels.enabled:
        return inputs, None, 0
    if config.size.channels.narrow == "close":
        with timed("closing narrow channels"):
            inputs, closed = _close_channels(config, sets, crs, inputs, mesh_crs)
        return inputs, closed, 0
    with timed("closing slots"):
        thin = domain_slots(
            inputs.domain, mesh_crs, _floor(config) / 2, threads=threads
        )
        if len(thin):
            inputs = build_case_domain(config, sets, crs, closed=thin, stitched=inputs)
            logger.info("closed %d slots narrower than h_min / 2", len(thin))
    return inputs, None, len(thin)


def _floor(config: CaseConfig) -> float:
    """Return the size field's floor: ``h_min``, else the smallest gradation's."""
    size = config.size
    return size.h_min or min([g.h_min for g in size.gradations] or [size.h_max])


def _close_channels(
    config: CaseConfig,
    sets: dict[str, Any],
    crs: CRS,
    inputs: Any,
    mesh_crs: CRS,
) -> tuple[Any, Any]:
    """Make the narrow channels land; return the domain inputs and what closed.

    The channels are found by the channel term alone (no gradation or
    bathymetry term: the width of the water needs neither), on the size field's
    grid. A cut can leave new narrow water next to it, so this is done up to
    ``CLOSE_PASSES`` times; what is narrow after the last pass is kept, and
    :func:`build_case` warns of it. Returns ``(inputs, report)``, the report
    counting every channel closed (None when none was).
    """
    closed_count, closed_km2, land = 0, 0.0, []
    report = None
    for _ in range(CLOSE_PASSES):
        found = _size_field(config, inputs.domain, mesh_crs, None, channels_only=True)
        if not len(found.narrow):
            break
        report = found.report.channels
        closed_count += len(found.narrow)
        closed_km2 += report.narrow_km2
        land.extend(found.narrow)
        inputs = build_case_domain(
            config, sets, crs, closed=np.array(land, dtype=object), stitched=inputs
        )
    if report is None:
        return inputs, None
    closed = dataclasses.replace(
        report, narrow_channels=closed_count, narrow_km2=closed_km2
    )
    warn_narrow(closed, closed=True)
    return inputs, closed
