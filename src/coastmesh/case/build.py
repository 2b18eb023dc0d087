"""Build a whole case in memory: :func:`build_case`.

The case runs through the stages of :data:`coastmesh.case.pipeline.STAGES`
(shorelines, domain, closing, size field, meshing, depth, time step, quality),
each reported to the ``stage`` factory and the log, with the parts of the water
meshed on a process pool or a Dask cluster (:mod:`coastmesh.case.executor`).
Nothing is written: :meth:`CaseResult.write` writes the files, and
:func:`coastmesh.run_case` does both.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import time

from coastmesh.case.config import CaseConfig, StudyCase
from coastmesh.case.executor import TaskRunner, open_runner
from coastmesh.case.figures import FigureJobs
from coastmesh.case.pipeline import RunContext, build_run
from coastmesh.case.pipeline.depth import check_rasters
from coastmesh.case.result import CaseResult
from coastmesh.errors import ConfigError
from coastmesh.types import StageFactory, local_cores, quiet_stage

__all__ = ["as_case", "build_case", "build_drawing", "worker_count"]

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
    figure once it is measured (:meth:`~coastmesh.case.figures.FigureJobs.follow`):
    with a pool, they are drawn while this process goes on.
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
    runner: TaskRunner,
    figures: FigureJobs | None,
) -> CaseResult:
    """Build the case (see :func:`build_case`) with the parts meshed by ``runner``."""
    check_rasters(config)  # a bad raster fails now, not after the meshing
    ctx = RunContext(threads, runner, stage or quiet_stage, figures)
    run = build_run(config, ctx)
    result = CaseResult.of(run, ctx.seconds, time.perf_counter() - ctx.started)
    logger.info("%s", result.summary())
    return result


def worker_count(workers: int | None) -> int:
    """``workers``, checked; None is every core this process may use."""
    if workers is None:
        return local_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"workers = {workers!r}: expected an integer >= 1")
    return workers


def as_case(case: object) -> CaseConfig | StudyCase:
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
