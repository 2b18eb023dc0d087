"""``coastmesh convert``: a mesh to a model format, with depth on the nodes."""

from __future__ import annotations

import numpy as np

from coastmesh.data import path as data_path
from coastmesh.io.adcirc import read_fort14
from coastmesh.io.msh import read_msh, write_msh


def test_convert_to_fort14_with_bathymetry(run_cli, example_run, tmp_path):
    _, out = example_run
    src = out / "pentland_firth.msh"
    raster = data_path("etopo1_0.1deg_orkney_wide.tif")
    dst = tmp_path / "fort.14"
    result = run_cli("convert", src, dst, "--bathymetry", raster, "--min-depth", "2")
    assert result.exit_code == 0, result.output
    assert "fort14" in result.output and "nodes" in result.output
    grid = read_fort14(dst)
    mesh = read_msh(src)
    assert grid["np"] == len(mesh.points) and grid["ne"] == len(mesh.triangles)
    assert grid["depth"].min() == 2.0
    assert grid["nope"] >= 4  # kinds come from the physical names open:NAME


def test_convert_needs_kinds_for_plain_msh(run_cli, tmp_path):
    from coastmesh.types import Mesh

    m = Mesh(
        [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]],
        [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
        [[0, 1], [1, 2], [2, 3], [3, 0]],
        [2, 1, 1, 1],
        1,
        None,
    )
    write_msh(tmp_path / "plain.msh", m, version="4.1")  # no physical names
    out = tmp_path / "plain.gr3"
    failed = run_cli("convert", tmp_path / "plain.msh", out)
    assert failed.exit_code == 1 and "boundary_kinds" in failed.output
    assert not out.exists()
    ok = run_cli("convert", tmp_path / "plain.msh", out, "--open-ids", "2")
    assert ok.exit_code == 0, ok.output
    grid = read_fort14(out)
    assert grid["nope"] == 1
    nodes = np.asarray(grid["open_boundaries"][0]["nodes"]) - 1
    # msh 4.1 renumbers the nodes: compare the open boundary by its coordinates
    np.testing.assert_array_equal(grid["xy"][nodes], [[0, 0], [1, 0]])
    wrong = run_cli(
        "convert", tmp_path / "plain.msh", tmp_path / "x.gr3", "--open-ids", "9"
    )
    assert wrong.exit_code == 2 and "no such boundary ids" in wrong.output


def test_unknown_extension_and_existing_output(run_cli, example_run, tmp_path):
    _, out = example_run
    bad = run_cli("convert", out / "pentland_firth.msh", tmp_path / "mesh.xyz")
    assert bad.exit_code == 1 and "unknown mesh format" in bad.output
    target = tmp_path / "m.vtu"
    target.write_text("mine")
    again = run_cli("convert", out / "pentland_firth.msh", target)
    assert again.exit_code == 1 and "--overwrite" in again.output
    assert target.read_text() == "mine"
