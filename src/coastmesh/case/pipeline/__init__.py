"""A case built as a list of stages over one run state.

Read top to bottom, :data:`STAGES` is what building a case does. Each stage
reads the run state the stages before it made (its ``run`` parameter's type:
:class:`~coastmesh.case.pipeline.state.CaseRun`,
:class:`~coastmesh.case.pipeline.state.ShorelineRun`, ...,
:mod:`~coastmesh.case.pipeline.state` has them all) and returns it with its
part made; where regional and global cases differ, a stage asks the run's
strategy (:class:`~coastmesh.case.pipeline.strategy.Regional`,
:class:`~coastmesh.case.pipeline.world.Global`). After each stage the figures
that can be drawn start (:meth:`coastmesh.case.figures.FigureJobs.follow`).

==========================  ==============  ==================================
stage                       reads -> gives  makes
==========================  ==============  ==================================
:func:`shoreline_stage`     CaseRun ->      the shoreline layer and each
                            ShorelineRun    shoreline set
:func:`domain_stage`        ShorelineRun    the domain: sets stitched, open
                            -> DomainRun    boundaries, the sea, structures
                                            cut out
:func:`closing_stage`       DomainRun       water too narrow to mesh closed as
                                            land
:func:`site_stage`          DomainRun       farms, turbines and lines read and
                                            checked
:func:`size_stage`          DomainRun ->    the size field: every size term,
                            SizedRun        combined
:func:`mesh_stage`          SizedRun ->     the mesh, in parts, cleaned
                            MeshedRun
:func:`channel_stage`       MeshedRun       dead-end channels one element wide
                                            closed
:func:`conform_stage`       MeshedRun       elements brought to their sizes
                                            where a size term asks
:func:`depth_stage`         MeshedRun ->    depths at the nodes
                            DepthRun
:func:`time_step_stage`     DepthRun        the elements that throttle the
                                            time step relieved
:func:`quality_stage`       DepthRun ->     the quality report, and advice
                            FinishedRun
==========================  ==============  ==================================

:func:`build_run` runs them in order on one run. Before each stage it checks
that the run is the state the stage reads (:func:`stage_input`): a stage put
before the one that makes what it reads raises a :class:`TypeError` naming
it and what the run lacks, before it runs.
"""

from __future__ import annotations

import dataclasses
import inspect
import typing
from dataclasses import replace

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.advice import quality_stage
from coastmesh.case.pipeline.depth import depth_stage, time_step_stage
from coastmesh.case.pipeline.farms import site_features
from coastmesh.case.pipeline.mesh import channel_stage, conform_stage, mesh_stage
from coastmesh.case.pipeline.size import size_stage
from coastmesh.case.pipeline.state import (
    CaseRun,
    DomainRun,
    FinishedRun,
    RunContext,
    ShorelineRun,
    Stage,
)
from coastmesh.case.pipeline.strategy import Regional, Strategy
from coastmesh.case.pipeline.structures import with_structures
from coastmesh.case.pipeline.world import Global

__all__ = [
    "STAGES",
    "STRATEGIES",
    "CaseRun",
    "FinishedRun",
    "RunContext",
    "build_run",
    "closing_stage",
    "domain_stage",
    "shoreline_stage",
    "site_stage",
    "stage_input",
    "strategy_of",
]


def shoreline_stage(run: CaseRun, ctx: RunContext) -> ShorelineRun:
    """Read the shoreline layer and build every shoreline set."""
    return run.with_shorelines(run.strategy.shorelines(run, ctx))


def domain_stage(run: ShorelineRun, ctx: RunContext) -> DomainRun:
    """Stitch the sets, draw the open boundaries, build the domain.

    The ``[[structures]]`` are cut out of it here, before the closing, so that
    narrow water between a structure and the coast is closed as any other.
    """
    domain = run.strategy.domain(run, ctx)
    return run.with_domain(with_structures(domain, run.config))


def closing_stage(run: DomainRun, ctx: RunContext) -> DomainRun:
    """Close water too narrow to mesh; cut the domain by it."""
    return replace(run, domain=run.strategy.close_water(run, ctx))


def site_stage(run: DomainRun, ctx: RunContext) -> DomainRun:
    """Read and check the farms, turbines and lines (none: nothing to do)."""
    if not (run.config.farms or run.config.turbines or run.config.lines):
        return run
    with ctx.timed("farms, turbines and lines"):
        return replace(run, site=site_features(run.config, run.domain))


#: What building a case does, in order.
STAGES: tuple[Stage, ...] = (
    shoreline_stage,
    domain_stage,
    closing_stage,
    site_stage,
    size_stage,
    mesh_stage,
    channel_stage,
    conform_stage,
    depth_stage,
    time_step_stage,
    quality_stage,
)


#: The strategy of each kind of case, by its ``[domain] kind``
#: (:data:`coastmesh.case.config.kinds.DOMAIN_KINDS` has what its case file allows).
STRATEGIES: dict[str, type[Strategy]] = {"regional": Regional, "global": Global}


def strategy_of(config: CaseConfig) -> Strategy:
    """Return the strategy of a case: global or regional (``[domain] kind``)."""
    return STRATEGIES[config.domain.kind]()


def stage_input(stage: Stage) -> type[CaseRun]:
    """Return the run state a stage reads: its first parameter's annotation.

    Raises
    ------
    TypeError
        If that annotation is not a run state (a subclass of :class:`CaseRun`).

    Examples
    --------
    >>> stage_input(domain_stage).__name__
    'ShorelineRun'
    """
    name = next(iter(inspect.signature(stage).parameters))
    state = typing.get_type_hints(stage)[name]
    if not (isinstance(state, type) and issubclass(state, CaseRun)):
        raise TypeError(
            f"{stage.__name__}: its parameter {name!r} is annotated {state!r}; "
            "expected a run state (CaseRun or a subclass)"
        )
    return state


#: The run state each stage of :data:`STAGES` reads, read once.
_INPUTS: dict[Stage, type[CaseRun]] = {stage: stage_input(stage) for stage in STAGES}


def build_run(config: CaseConfig, ctx: RunContext) -> FinishedRun:
    """Run every stage of :data:`STAGES` on a case; return the finished run.

    Raises
    ------
    TypeError
        If a stage of :data:`STAGES` comes before one that makes what it reads
        (checked before it runs), or they leave the run unfinished.
    """
    run = CaseRun(config, strategy_of(config))
    for stage in STAGES:
        _check_input(stage, run)
        run = stage(run, ctx)
        if ctx.figures is not None:
            ctx.figures.follow(run)
    if not isinstance(run, FinishedRun):
        raise TypeError(
            f"STAGES leave the run a {type(run).__name__}, not a FinishedRun: it "
            f"has no {_lacking(run, FinishedRun)}"
        )
    return run


def _check_input(stage: Stage, run: CaseRun) -> None:
    """Raise unless ``run`` is the state ``stage`` reads."""
    state = _INPUTS.get(stage) or stage_input(stage)
    if not isinstance(run, state):
        raise TypeError(
            f"STAGES: {stage.__name__} reads a {state.__name__}, but the run is a "
            f"{type(run).__name__}, with no {_lacking(run, state)} yet: it must "
            "come after the stages that make what it reads"
        )


def _lacking(run: CaseRun, state: type[CaseRun]) -> str:
    """Name the parts ``state`` must have and ``run`` has not, in the stages' order.

    A part with a default (the site) is not named: the state can do without.
    """
    have = {f.name for f in dataclasses.fields(run)}
    return ", ".join(
        f.name
        for f in dataclasses.fields(state)
        if f.name not in have
        and f.default is dataclasses.MISSING
        and f.default_factory is dataclasses.MISSING
    )
