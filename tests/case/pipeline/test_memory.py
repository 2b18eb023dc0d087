"""The memory a mesh will need, estimated before meshing from the size field."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import pytest

from coastmesh.case import run_case
from coastmesh.case.parse import read_case
from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
from coastmesh.case.pipeline import mesh as mesh_module
from coastmesh.case.pipeline.mesh import expected_triangles
from coastmesh.errors import ConfigError
from coastmesh.types import quiet_stage

CASE = Path(__file__).parents[2] / "data" / "coasts" / "vestfjorden.toml"


@pytest.fixture(scope="module")
def meshed():
    """The case's run up to its mesh."""
    config = read_case(CASE)
    run = CaseRun(config, strategy_of(config))
    ctx = RunContext(1, None, quiet_stage)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for stage in STAGES:
            run = stage(run, ctx)
            if stage.__name__ == "mesh_stage":
                return run
    raise AssertionError("no mesh stage")


def test_the_expected_triangles_are_the_mesh_s(meshed):
    expected = expected_triangles(meshed)
    assert expected == pytest.approx(len(meshed.mesh.mesh.triangles), rel=0.25)
    # the literal sum, node by node
    grid, h = meshed.size.grid, meshed.size.field.values
    total = 0.0
    for j in range(h.shape[0]):
        for i in range(h.shape[1]):
            if grid.sea[j, i]:
                area = (grid.cell / grid.scale[j, i]) ** 2
                total += 4.0 / math.sqrt(3.0) * area / h[j, i] ** 2
    assert expected == pytest.approx(total, rel=1e-9)


def test_a_mesh_too_big_for_the_machine_is_refused_before_meshing(
    tmp_path, monkeypatch
):
    pages = {"SC_PAGE_SIZE": 4096, "SC_PHYS_PAGES": 1000}  # 4 MB of memory
    monkeypatch.setattr(mesh_module.os, "sysconf", lambda name: pages[name])
    called = []
    monkeypatch.setattr(mesh_module, "mesh_in_parts", lambda *a, **k: called.append(1))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(
            ConfigError,
            match=r"asks for about [\d,]+ triangles, "
            r"which need about 0\.\d GB to mesh; this machine has "
            r"0\.0 GB",
        ) as caught:
            run_case(CASE, output=tmp_path / "out")
    assert "h_min" in str(caught.value) and not called
    assert not (tmp_path / "out").exists()
    assert not list(tmp_path.iterdir())
