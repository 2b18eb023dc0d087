"""build_case builds in memory and writes nothing; CaseResult.write writes a run."""

from __future__ import annotations

import dataclasses
import json
import tempfile
import warnings

import numpy as np
import pytest
from conftest import EXAMPLE, coarse_example_text

import coastmesh
from coastmesh.case import CaseResult, build_case, parse_case, read_case
from coastmesh.errors import ConfigError, OutputExistsError

pytestmark = pytest.mark.xdist_group("coarse")


@pytest.fixture
def coarse(coarse_case):
    """The example with coarser sizes, built in memory once a session."""
    return coarse_case


def test_build_case_writes_nothing(tmp_path, monkeypatch):
    work, scratch = tmp_path / "work", tmp_path / "tmp"
    work.mkdir()
    scratch.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    monkeypatch.setenv("TMPDIR", str(scratch))
    case = parse_case(coarse_example_text(), EXAMPLE)
    case = dataclasses.replace(case, output=tmp_path / "never")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        result = coastmesh.build_case(case)
    assert isinstance(result, CaseResult)
    assert list(work.iterdir()) == [] and list(scratch.iterdir()) == []
    assert not case.output.exists()
    assert result.output is None and result.files == ()
    assert result.nodes == len(result.mesh.points) > 1000


@pytest.mark.slow
def test_same_mesh_as_run(example_run):
    """build_case on the example gives the nodes and triangles coastmesh run wrote."""
    ran, out = example_run
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        built = coastmesh.build_case(EXAMPLE)
    np.testing.assert_array_equal(built.mesh.points, ran.mesh.points)
    np.testing.assert_array_equal(built.mesh.triangles, ran.mesh.triangles)
    np.testing.assert_array_equal(built.mesh.boundary_ids, ran.mesh.boundary_ids)
    written = coastmesh.read_mesh(out / "pentland_firth.msh")
    np.testing.assert_array_equal(written.triangles, built.mesh.triangles)
    np.testing.assert_allclose(written.points, built.mesh.points, rtol=0, atol=1e-12)


def test_result_holds_every_stage(coarse):
    r = coarse
    assert r.mesh.crs.to_epsg() == 4326
    assert set(r.mesh.point_data) == {"size", "depth"}
    assert {s.name for s in r.domain.segments} == {
        "full",
        "pca_5_50",
        "pca_1_50",
        "west",
        "north",
        "east",
        "south",
    }
    assert r.size_grid.values.shape == r.size.shape
    report = r.report
    assert set(report.shoreline_sets) == {"full", "pca_5_50", "pca_1_50"}
    for part in (
        "stitch",
        "domain",
        "size_field",
        "mesh",
        "cleanup",
        "depth",
        "quality",
    ):
        assert getattr(report, part) is not None, part
        assert getattr(report, part).summary()
    data = report.to_dict()
    assert json.loads(json.dumps(data)) == data
    assert data["mesh"]["nodes"] == r.nodes
    assert data["quality"]["triangles"] == r.triangles
    assert data["depth"]["nodes"] == r.nodes
    assert r.boundary_edges == data["mesh"]["boundary_edges"]
    assert "nodes" in r.summary() and "files" not in r.summary()


def test_write_writes_a_run(coarse, tmp_path):
    out = tmp_path / "run"
    written = coarse.write(out, formats=["msh2", "ugrid"])
    assert written.output == out
    assert {"pentland_firth.msh", "pentland_firth.nc", "report.json"} <= set(
        written.files
    )
    # formats= replaces the case's formats; its smoke-test folders stay
    models = [name for name in written.files if name.startswith("model_test/")]
    assert {"model_test/adcirc/fort.14", "model_test/schism/hgrid.gr3"} <= set(models)
    assert not any(
        name.endswith((".14", ".gr3")) for name in set(written.files) - set(models)
    )
    on_disk = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()}
    assert on_disk == set(written.files)
    report = json.loads((out / "report.json").read_text())
    assert report == json.loads(json.dumps(written.report.to_dict()))
    assert report["files"] == list(written.files)
    assert (out / "summary.txt").read_text() == written.report.summary() + "\n"
    # the copy of the case file as run (its relative paths are the file's own)
    copy = read_case(out / "case.toml")
    assert copy.size.gradations == coarse.config.size.gradations
    assert copy.text.endswith(coarse.config.text)
    with pytest.raises(OutputExistsError):
        coarse.write(out)
    with pytest.raises(ConfigError, match=r"output.formats\[0\] = 'nope'"):
        coarse.write(tmp_path / "other", formats=["nope"])
    assert not (tmp_path / "other").exists()


def test_a_case_built_in_python_writes_a_case_file_that_runs(coarse, tmp_path):
    case = dataclasses.replace(coarse.config, source=None, text="")
    result = dataclasses.replace(coarse, config=case)
    out = tmp_path / "python"
    result.write(out, formats=["msh2"])
    again = read_case(out / "case.toml")
    # the case as written: with the formats asked for
    written = dataclasses.replace(
        case, outputs=dataclasses.replace(case.outputs, formats=("msh2",))
    )
    assert (
        dataclasses.replace(again, source=None, text="", output=case.output) == written
    )


def test_build_case_takes_text_paths_and_configs(tmp_path, monkeypatch):
    monkeypatch.chdir(EXAMPLE.parent)  # the example's relative paths
    with pytest.raises(ConfigError, match=r"unknown key 'mesh\.sed'"):
        build_case(coarse_example_text().replace("seed = 0", "sed = 0"))
    with pytest.raises(TypeError, match="expected a CaseConfig"):
        build_case(42)
    study = EXAMPLE.parents[1] / "norway" / "sognefjorden.toml"
    with pytest.raises(ConfigError, match=r"run it with coastmesh\.run_case"):
        build_case(study)


def test_peak_memory_where_the_platform_cannot_tell(coarse, monkeypatch):
    """On Windows there is no resource module: the report says so."""
    import builtins

    from coastmesh.case.report import peak_memory_mb

    assert peak_memory_mb() > 0
    real_import = builtins.__import__

    def no_resource(name, *args, **kwargs):
        if name == "resource":
            raise ImportError("No module named 'resource'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_resource)
    assert peak_memory_mb() is None
    report = dataclasses.replace(coarse.report, peak_memory_mb=None)
    assert "peak memory: not measured on this platform" in report.summary()
    assert report.to_dict()["peak_memory_mb"] is None


@pytest.mark.parametrize("workers", [0, -2, 1.5, True])
def test_bad_workers_are_refused_before_any_work(workers):
    # checked first: a missing case file would be the other error
    with pytest.raises(ConfigError, match=r"workers = .*expected an integer >= 1"):
        build_case("/no/such/case.toml", workers=workers)
