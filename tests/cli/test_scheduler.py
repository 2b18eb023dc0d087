"""``coastmesh run --scheduler``: the parts meshed on a Dask cluster."""

from __future__ import annotations

import dataclasses
import json
import re
import warnings
from pathlib import Path

import pytest

import coastmesh
from coastmesh.case import executor

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow

SHELF = (
    Path(__file__).parents[2] / "examples" / "nw_european_shelf" / "intermediate.toml"
)
ORKNEY = Path(__file__).parents[2] / "examples" / "orkney" / "pentland_firth.toml"


@pytest.fixture(scope="module")
def scheduler():
    """A local Dask cluster of two worker processes, one thread each."""
    from distributed import LocalCluster

    with (
        warnings.catch_warnings(),
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
    ):
        yield cluster.scheduler_address


def _case_file(path: Path, source: Path, parts: int, tmp_path: Path) -> Path:
    """The case with [mesh] parts, data paths absolute, one format, no figures."""
    case = coastmesh.read_case(source)
    case = dataclasses.replace(
        case,
        mesh=dataclasses.replace(case.mesh, parts=parts),
        outputs=dataclasses.replace(case.outputs, formats=("msh2",), figures=False),
        output=tmp_path / "unused",
    )
    path.write_text(coastmesh.dump_case(case))
    return path


def _dask_and_local(run_cli, case, scheduler, workers, tmp_path):
    """Run the case on the cluster and locally; return each mesh and parts report."""
    out = {}
    for how, args in {
        "dask": ("--scheduler", scheduler),
        "local": ("--workers", workers),
    }.items():
        folder = tmp_path / how
        result = run_cli("run", case, "-o", folder, *args)
        assert result.exit_code == 0, result.output
        report = json.loads((folder / "report.json").read_text())
        out[how] = next(folder.glob("*.msh")).read_bytes(), report["parts"]
    return out


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_a_cluster_makes_the_mesh_a_local_run_makes(run_cli, scheduler, tmp_path):
    case = _case_file(tmp_path / "case.toml", ORKNEY, 3, tmp_path)
    runs = _dask_and_local(run_cli, case, scheduler, "1", tmp_path)
    # one clean cut of the two asked (a warning says so): two parts; the
    # third there was before, of 11 triangles, was a sliver between the cut's
    # crossings, now joined to a neighbour
    assert all(parts["parts"] >= 2 for _, parts in runs.values())
    assert runs["dask"][0] == runs["local"][0]  # byte for byte


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_the_intermediate_shelf_on_a_cluster_is_the_local_mesh(
    run_cli, scheduler, tmp_path
):
    case = _case_file(tmp_path / "shelf.toml", SHELF, 4, tmp_path)
    runs = _dask_and_local(run_cli, case, scheduler, "2", tmp_path)
    for _, parts in runs.values():
        assert parts["parts"] >= 4 and len(parts["workers"]) == 2
    assert runs["dask"][0] == runs["local"][0]


def test_an_unreachable_scheduler_fails_fast_and_writes_nothing(
    run_cli, tmp_path, monkeypatch
):
    monkeypatch.setattr(executor, "SCHEDULER_TIMEOUT", 2.0)
    case = _case_file(tmp_path / "case.toml", ORKNEY, 3, tmp_path)
    out = tmp_path / "never"
    result = run_cli("run", case, "-o", out, "--scheduler", "tcp://127.0.0.1:9")
    assert result.exit_code == 2  # a bad value, as for any bad option
    assert re.search(
        r"scheduler = 'tcp://127.0.0.1:9': no Dask scheduler", result.output
    )
    assert "dask scheduler" in result.output
    assert not out.exists() and not list(tmp_path.glob("never*"))
