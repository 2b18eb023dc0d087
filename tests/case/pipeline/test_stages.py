"""The run states of a case: each stage reads the state the stages before it make."""

from __future__ import annotations

import dataclasses
import typing
from pathlib import Path

import pytest
from pyproj import CRS

import coastmesh.case.pipeline as pipeline
from coastmesh.case.parse import read_case
from coastmesh.case.pipeline import (
    STAGES,
    CaseRun,
    FinishedRun,
    RunContext,
    build_run,
    domain_stage,
    stage_input,
    strategy_of,
)
from coastmesh.case.pipeline.mesh import mesh_stage
from coastmesh.case.pipeline.size import size_stage
from coastmesh.case.pipeline.state import (
    DomainRun,
    ShorelineRun,
    Shorelines,
    SizedRun,
)
from coastmesh.types import quiet_stage

CASE = Path(__file__).parents[2] / "data" / "coasts" / "vestfjorden.toml"


@pytest.fixture(scope="module")
def config():
    return read_case(CASE)


def _stand_in_shorelines(run: CaseRun, ctx: RunContext) -> ShorelineRun:
    """A shoreline stage that reads nothing (its part is never looked at)."""
    return run.with_shorelines(Shorelines(features=None, crs=CRS("EPSG:4326")))


def test_each_stage_reads_the_state_the_stages_before_it_make():
    """Walked through the annotations: no stage reads a part made after it."""
    state = CaseRun
    for stage in STAGES:
        reads = stage_input(stage)
        assert issubclass(state, reads), stage.__name__
        gives = typing.get_type_hints(stage)["return"]
        assert issubclass(gives, reads), stage.__name__
        if gives is not reads:  # a stage that makes a part: the next state
            state = gives
    assert state is FinishedRun


def test_the_stages_declare_what_they_read():
    reads = {stage.__name__: stage_input(stage).__name__ for stage in STAGES}
    assert reads == {
        "shoreline_stage": "CaseRun",
        "domain_stage": "ShorelineRun",
        "closing_stage": "DomainRun",
        "site_stage": "DomainRun",
        "size_stage": "DomainRun",
        "mesh_stage": "SizedRun",
        "channel_stage": "MeshedRun",
        "conform_stage": "MeshedRun",
        "depth_stage": "MeshedRun",
        "time_step_stage": "DepthRun",
        "quality_stage": "DepthRun",
    }


def test_a_stage_before_what_it_reads_is_refused_before_it_runs(config, monkeypatch):
    ran = []

    def size_stage_spy(run: DomainRun, ctx: RunContext) -> SizedRun:
        ran.append("size")
        return size_stage(run, ctx)

    # the size stage put straight after the shorelines, before the domain
    monkeypatch.setattr(
        pipeline, "STAGES", (_stand_in_shorelines, size_stage_spy, *STAGES[1:])
    )
    ctx = RunContext(1, None, quiet_stage)
    with pytest.raises(TypeError) as info:
        build_run(config, ctx)
    assert str(info.value) == (
        "STAGES: size_stage_spy reads a DomainRun, but the run is a ShorelineRun, "
        "with no domain yet: it must come after the stages that make what it reads"
    )
    assert ran == []


def test_the_first_stage_misplaced_fails_at_once(config, monkeypatch):
    monkeypatch.setattr(pipeline, "STAGES", (domain_stage, *STAGES))
    with pytest.raises(
        TypeError,
        match="domain_stage reads a ShorelineRun, but the run is a CaseRun, with "
        "no shorelines yet",
    ):
        build_run(config, RunContext(1, None, quiet_stage))
    monkeypatch.setattr(pipeline, "STAGES", (_stand_in_shorelines, mesh_stage))
    with pytest.raises(TypeError, match="a ShorelineRun, with no domain, size yet"):
        build_run(config, RunContext(1, None, quiet_stage))


def test_stages_that_leave_the_run_unfinished_are_refused(config, monkeypatch):
    monkeypatch.setattr(pipeline, "STAGES", (_stand_in_shorelines,))
    with pytest.raises(TypeError) as info:
        build_run(config, RunContext(1, None, quiet_stage))
    assert str(info.value) == (
        "STAGES leave the run a ShorelineRun, not a FinishedRun: it has no "
        "domain, size, mesh, depth, quality"
    )


def test_a_stage_must_read_a_run_state():
    def odd(run: int, ctx: RunContext) -> CaseRun:
        raise AssertionError("never called")

    with pytest.raises(TypeError, match="odd: its parameter 'run' is annotated"):
        stage_input(odd)


def test_a_run_grows_by_one_part_per_stage_that_makes_one(config):
    run = CaseRun(config, strategy_of(config))
    shorelines, domain, size = object(), object(), object()
    sized = run.with_shorelines(shorelines).with_domain(domain).with_size(size)
    assert type(sized) is SizedRun
    assert (sized.config, sized.strategy) == (run.config, run.strategy)
    assert (sized.shorelines, sized.domain, sized.size) == (shorelines, domain, size)
    assert sized.site is None
    # the site, set on the domain's run, is carried on
    site = object()
    on = run.with_shorelines(shorelines).with_domain(domain)
    on = dataclasses.replace(on, site=site)
    assert on.with_size(size).site is site
    # a part made again leaves behind what was made from the old one
    again = sized.with_domain(object())
    assert type(again) is DomainRun
    assert not hasattr(again, "size")
