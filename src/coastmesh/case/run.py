"""Run a whole case and write its outputs, as ``coastmesh run`` does.

:func:`run_case` is :func:`~coastmesh.case.build.build_case`, then
:meth:`~coastmesh.case.result.CaseResult.write`, with each figure started as
soon as what it shows is made (:mod:`coastmesh.case.figures`). A case with
``[case] kind = "shorelines"`` or ``"bathymetry"`` runs one of the paper's PCA
studies (:mod:`coastmesh.case.studies`) instead.
"""

from __future__ import annotations

import dataclasses
import importlib
import logging
import os
import time
from collections.abc import Callable
from pathlib import Path

from coastmesh.case.build import as_case, build_drawing, worker_count
from coastmesh.case.config import CaseConfig, StudyCase
from coastmesh.case.figures import FigureJobs
from coastmesh.case.processes import start_server
from coastmesh.case.result import CaseResult, write_case_copy
from coastmesh.io import atomic_directory, check_directory
from coastmesh.types import Report, StageFactory, quiet_stage

__all__ = ["run_case"]

logger = logging.getLogger(__name__)


def run_case(
    case: CaseConfig | StudyCase | str | os.PathLike[str],
    *,
    output: str | os.PathLike[str] | None = None,
    overwrite: bool = False,
    stage: StageFactory | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
) -> CaseResult | Report:
    """Run a case end to end and write its outputs.

    Parameters
    ----------
    case : CaseConfig, path or str
        The case, the path of its TOML file, or its TOML text (see
        :func:`~coastmesh.case.build.build_case`).
    output : str or path-like, optional
        The output folder; default the case's ``[case] output``.
    overwrite : bool, default False
        Whether an existing, non-empty output folder may be replaced.
    stage : callable, optional
        ``stage(label)`` returns a context manager yielding a
        ``progress(done, total)`` callback, entered once per stage.
    workers : int, optional
        Local processes the parts are meshed on (see
        :func:`~coastmesh.case.build.build_case`) and the figures drawn on;
        default ``[run] workers``, else all cores.
    scheduler : str, optional
        A Dask scheduler's address: the parts are meshed on its cluster.

    Returns
    -------
    CaseResult or Report
        With ``output`` and ``files`` set; for a study case
        (:class:`~coastmesh.case.config.StudyCase`), the study's result.

    Raises
    ------
    ConfigError
        For a bad case file or a value that does not fit the data (e.g. a seed
        on land).
    InputDataError
        If a data file is missing or holds the wrong kind of geometry.
    MeshingError
        If Gmsh fails.
    OutputExistsError
        If the output folder exists, is not empty, and ``overwrite`` is false;
        checked before any work.
    """
    config = as_case(case)
    target = Path(output) if output is not None else config.output
    assert target is not None  # CaseConfig.__post_init__ sets output (out/NAME)
    check_directory(target, overwrite=overwrite)  # fail before the work
    if isinstance(config, StudyCase):
        return _run_study(config, target, overwrite, stage)
    started = time.perf_counter()
    # the figures are drawn on local processes, whatever meshed the parts, and
    # each starts as soon as what it shows is made
    local = worker_count(workers if workers is not None else config.run.workers)
    if local > 1:
        start_server()  # the workers' fork server imports while this one reads
    with FigureJobs(local) as figures:
        result = build_drawing(
            config, stage=stage, workers=workers, scheduler=scheduler, figures=figures
        )
        result = result.write(target, overwrite=overwrite, stage=stage, figures=figures)
    result = dataclasses.replace(result, seconds=time.perf_counter() - started)
    logger.info("%s", result.summary())
    return result


def _run_study(
    config: StudyCase, target: Path, overwrite: bool, stage: StageFactory | None
) -> Report:
    """Run a PCA study case (``[case] kind``) into ``target``, atomically."""
    module = importlib.import_module(f"coastmesh.case.studies.{config.kind}")
    # each study module's run_study(study, folder, stage) returns its Report
    run_study: Callable[[object, Path, StageFactory], Report] = module.run_study
    with atomic_directory(target, overwrite=overwrite) as folder:
        result = run_study(config.study, folder, stage or quiet_stage)
        write_case_copy(folder, config)
        (folder / "summary.txt").write_text(result.summary() + "\n", encoding="utf-8")
    logger.info("%s: %s", config.name, result.summary())
    return result
