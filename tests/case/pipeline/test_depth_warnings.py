"""The depth's warnings are given once, about the mesh the case ends with.

The depths are read twice when the time-step relief changes the mesh (the
merged nodes need theirs): the warnings of the first reading wait for the
relief, and are given only if it left the mesh as it was.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from pathlib import Path

import pytest

from coastmesh.case.parse import read_case
from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
from coastmesh.case.pipeline import depth as depth_module
from coastmesh.depth.nodes import CoarseRasterWarning
from coastmesh.types import quiet_stage

CASE = Path(__file__).parents[2] / "data" / "coasts" / "vestfjorden.toml"


def _coarse_warnings(config, monkeypatch=None, refuse=False):
    """Build the case; return its run and the coarse-raster warnings given."""
    if refuse:  # a relief that is not accepted: the mesh stays as it was
        relieve = depth_module.relieve_time_step

        def refused(mesh, **kwargs):
            _, report = relieve(mesh, **kwargs)
            return mesh, replace(report, accepted=False)

        monkeypatch.setattr(depth_module, "relieve_time_step", refused)
    run = CaseRun(config, strategy_of(config))
    ctx = RunContext(1, None, quiet_stage)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for stage in STAGES:
            run = stage(run, ctx)
    coarse = [w for w in caught if issubclass(w.category, CoarseRasterWarning)]
    return run, coarse


@pytest.fixture(scope="module")
def config():
    return read_case(CASE)


def test_a_relieved_mesh_gets_one_warning_about_its_own_nodes(config):
    run, coarse = _coarse_warnings(config)
    relief = run.depth.relief
    assert relief.accepted and relief.collapses + relief.moves >= 1
    assert len(coarse) == 1
    # the final reading's: its nodes, and the coarse ones of the final report
    nodes = len(run.mesh.mesh.points)
    assert f"{run.depth.report.coarse:,} of {nodes:,} nodes" in str(coarse[0].message)
    assert run.depth.deferred == ()


def test_a_refused_relief_gives_the_first_reading_s_warning(config, monkeypatch):
    run, coarse = _coarse_warnings(config, monkeypatch, refuse=True)
    assert not run.depth.relief.accepted
    assert len(coarse) == 1
    assert f"of {len(run.mesh.mesh.points):,} nodes" in str(coarse[0].message)


def test_without_the_relief_the_warning_is_given_at_once(config):
    cleanup = replace(config.cleanup, time_step=False)
    run, coarse = _coarse_warnings(replace(config, cleanup=cleanup))
    assert run.depth.relief is None
    assert len(coarse) == 1
