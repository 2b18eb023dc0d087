"""A case built as a list of stages over one run state.

Read top to bottom, :data:`STAGES` is what building a case does. Each stage
takes the :class:`~coastmesh.case.pipeline.state.CaseRun` and returns it with
its part made; where regional and global cases differ, a stage asks the run's
strategy (:class:`~coastmesh.case.pipeline.strategy.Regional`,
:class:`~coastmesh.case.pipeline.world.Global`). After each stage the figures
that can be drawn start (:meth:`coastmesh.case.figures.FigureJobs.follow`).

==========================  ==================================================
stage                       makes
==========================  ==================================================
:func:`shoreline_stage`     the shoreline layer and each shoreline set
:func:`domain_stage`        the domain: sets stitched, open boundaries, the sea,
                            structures cut out
:func:`closing_stage`       water too narrow to mesh closed as land
:func:`site_stage`          farms, turbines and lines read and checked
:func:`size_stage`          the size field: every size term, combined
:func:`mesh_stage`          the mesh, in parts, cleaned
:func:`channel_stage`       dead-end channels one element wide closed
:func:`depth_stage`         depths at the nodes
:func:`time_step_stage`     the elements that throttle the time step relieved
:func:`quality_stage`       the quality report, and advice
==========================  ==================================================
"""

from __future__ import annotations

from dataclasses import replace

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.advice import quality_stage
from coastmesh.case.pipeline.depth import depth_stage, time_step_stage
from coastmesh.case.pipeline.farms import site_features
from coastmesh.case.pipeline.mesh import channel_stage, mesh_stage
from coastmesh.case.pipeline.size import size_stage
from coastmesh.case.pipeline.state import CaseRun, RunContext, Stage, missing
from coastmesh.case.pipeline.strategy import Regional, Strategy
from coastmesh.case.pipeline.structures import with_structures
from coastmesh.case.pipeline.world import Global

__all__ = [
    "STAGES",
    "STRATEGIES",
    "CaseRun",
    "RunContext",
    "build_run",
    "closing_stage",
    "domain_stage",
    "shoreline_stage",
    "site_stage",
    "strategy_of",
]


def shoreline_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Read the shoreline layer and build every shoreline set."""
    return replace(run, shorelines=run.strategy.shorelines(run, ctx))


def domain_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Stitch the sets, draw the open boundaries, build the domain.

    The ``[[structures]]`` are cut out of it here, before the closing, so that
    narrow water between a structure and the coast is closed as any other.
    """
    domain = run.strategy.domain(run, ctx)
    return replace(run, domain=with_structures(domain, run.config))


def closing_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Close water too narrow to mesh; cut the domain by it."""
    return replace(run, domain=run.strategy.close_water(run, ctx))


def site_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Read and check the farms, turbines and lines (none: nothing to do)."""
    if not (run.config.farms or run.config.turbines or run.config.lines):
        return run
    with ctx.timed("farms, turbines and lines"):
        domain = run.domain or missing("domain")
        return replace(run, site=site_features(run.config, domain))


#: What building a case does, in order.
STAGES: tuple[Stage, ...] = (
    shoreline_stage,
    domain_stage,
    closing_stage,
    site_stage,
    size_stage,
    mesh_stage,
    channel_stage,
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


def build_run(config: CaseConfig, ctx: RunContext) -> CaseRun:
    """Run every stage of :data:`STAGES` on a case; return the finished run."""
    run = CaseRun(config, strategy_of(config))
    for stage in STAGES:
        run = stage(run, ctx)
        if ctx.figures is not None:
            ctx.figures.follow(run)
    return run
