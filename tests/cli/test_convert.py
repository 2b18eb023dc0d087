"""``coastmesh convert``: a mesh from any readable format to another, with depth."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import assert_clean_failure

from coastmesh.data import path as data_path
from coastmesh.io import read_mesh, read_msh, write_mesh, write_msh
from coastmesh.io.meshes.adcirc import read_fort14, read_fort14_mesh


@pytest.fixture
def case_msh(coarse_case, tmp_path):
    """The coarse Orkney case's mesh as msh 2.2 (boundary names and kinds kept)."""
    path = tmp_path / "pentland_firth.msh"
    write_mesh(path, coarse_case.mesh)
    return path


@pytest.mark.xdist_group("coarse")
def test_convert_to_fort14_with_bathymetry(run_cli, case_msh, tmp_path):
    src = case_msh
    raster = data_path("etopo1_0.1deg_orkney_wide.tif")
    dst = tmp_path / "fort.14"
    result = run_cli("convert", src, dst, "--bathymetry", raster, "--min-depth", "2")
    assert result.exit_code == 0, result.output
    assert "fort14" in result.output and "nodes" in result.output
    grid = read_fort14(dst)
    mesh = read_msh(src)
    assert grid["np"] == len(mesh.points) and grid["ne"] == len(mesh.triangles)
    assert grid["depth"].min() == 2.0
    # kinds come from the physical names open:NAME: 4 open boundaries, which
    # ADCIRC lists as one segment where they meet (the ids in its comment)
    back = read_fort14_mesh(dst)
    assert sum(kind == "open" for kind in back.boundary_kinds.values()) >= 4
    assert grid["nope"] >= 1


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


@pytest.mark.xdist_group("coarse")
def test_unknown_extension_and_existing_output(run_cli, case_msh, tmp_path):
    bad = run_cli("convert", case_msh, tmp_path / "mesh.xyz")
    assert bad.exit_code == 1 and "unknown mesh format" in bad.output
    target = tmp_path / "m.vtu"
    target.write_text("mine")
    again = run_cli("convert", case_msh, target)
    assert again.exit_code == 1 and "--overwrite" in again.output
    assert target.read_text() == "mine"


def test_convert_from_any_readable_format(run_cli, mesh_with_islands, tmp_path):
    """fort.14 -> UGRID -> gr3: ids, names, kinds, depth and CRS come along."""
    write_mesh(tmp_path / "fort.14", mesh_with_islands)
    ugrid = run_cli("convert", tmp_path / "fort.14", tmp_path / "mesh.nc")
    assert ugrid.exit_code == 0, ugrid.output
    assert ugrid.output.startswith(f"{tmp_path / 'mesh.nc'} (ugrid): 269 nodes")
    gr3 = run_cli("convert", tmp_path / "mesh.nc", tmp_path / "hgrid.gr3")
    assert gr3.exit_code == 0, gr3.output
    back = read_mesh(tmp_path / "hgrid.gr3")
    assert back.boundary_names == mesh_with_islands.boundary_names
    assert back.boundary_kinds == mesh_with_islands.boundary_kinds
    assert back.crs == mesh_with_islands.crs
    np.testing.assert_allclose(
        back.point_data["depth"], mesh_with_islands.point_data["depth"], atol=1e-9
    )


def test_crs_is_for_files_without_one(run_cli, mesh_with_islands, tmp_path):
    write_mesh(tmp_path / "m.msh", mesh_with_islands)
    ok = run_cli("convert", tmp_path / "m.msh", tmp_path / "m.nc", "--crs", "32630")
    assert ok.exit_code == 0, ok.output
    assert read_mesh(tmp_path / "m.nc").crs.to_epsg() == 32630
    plain = run_cli("convert", tmp_path / "m.msh", tmp_path / "plain.nc")
    assert plain.exit_code == 0, plain.output
    assert read_mesh(tmp_path / "plain.nc").crs.to_epsg() == 4326  # the default
    clash = run_cli("convert", tmp_path / "m.nc", tmp_path / "x.vtu", "--crs", "4326")
    assert clash.exit_code == 1 and "m.nc: the file's CRS is EPSG:32630" in clash.output
    assert not (tmp_path / "x.vtu").exists()


def test_selafin_converts_and_a_missing_input_is_named(
    run_cli, mesh_with_islands, tmp_path
):
    write_mesh(tmp_path / "m.slf", mesh_with_islands)
    slf = run_cli("convert", tmp_path / "m.slf", tmp_path / "m.vtu")
    assert slf.exit_code == 0, slf.output
    missing = run_cli("convert", tmp_path / "none.14", tmp_path / "n.vtu")
    assert missing.exit_code == 1 and "none.14: file not found" in missing.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.cli", "m.slf", "m.vtu"]


MODELS = Path(__file__).parents[1] / "data" / "models"


@pytest.mark.parametrize(
    ("src", "dst", "rules"),
    [
        (
            "before_bc770b9.14",
            "fort.14",
            ["A5 at node 7", "A3 at node 19", "A3 at node 31"],
        ),
        ("before_bc770b9.gr3", "hgrid.gr3", ["S4 at node 19", "S4 at node 31"]),
    ],
)
def test_convert_repairs_a_grid_that_breaks_its_models_rules(
    run_cli, tmp_path, src, dst, rules
):
    """A fort.14 / gr3 written before the rules: each break said, then repaired."""
    from model_rules import check_adcirc, check_schism

    result = run_cli("convert", MODELS / src, tmp_path / dst)
    assert result.exit_code == 0, result.output
    said = [line for line in result.output.splitlines() if ": repaired: " in line]
    assert [line.split(": repaired: ")[1].split(" (")[0] for line in said] == rules
    assert "written by the rules" in said[0]
    check = check_adcirc if dst == "fort.14" else check_schism
    assert check(tmp_path / dst) == []
    # to a format without lists, nothing to repair
    result = run_cli("convert", MODELS / src, tmp_path / "mesh.nc")
    assert result.exit_code == 0 and "repaired" not in result.output


def test_convert_refuses_lists_that_do_not_follow_the_boundary(run_cli, tmp_path):
    text = (MODELS / "before_bc770b9.14").read_text()
    # the island's second segment made to jump from node 31 to node 33
    broken = text.replace(
        "5 0 = Number of nodes for land boundary 3: id 4 reef\n31\n32\n33",
        "5 0 = Number of nodes for land boundary 3: id 4 reef\n31\n33\n32",
    )
    (tmp_path / "bad.14").write_text(broken)
    result = run_cli("convert", tmp_path / "bad.14", tmp_path / "out.14")
    assert_clean_failure(
        result,
        "bad.14",
        "land segment 3 lists nodes 31 and 33",
        "a segment follows the boundary",
    )
    assert not (tmp_path / "out.14").exists()


def test_convert_refuses_a_pinched_boundary_naming_the_node(run_cli, tmp_path):
    """Two triangles that touch at a corner: no model's lists can pass it once."""
    from coastmesh.types import Mesh

    m = Mesh([[0, 0], [1, 0], [0, 1], [2, 0], [1, 1]], [[0, 1, 2], [1, 3, 4]],
             [[0, 1], [1, 2], [2, 0], [1, 3], [3, 4], [4, 1]], [2, 1, 1, 1, 1, 1],
             1, None, boundary_kinds={1: "shoreline", 2: "open"})  # fmt: skip
    write_mesh(tmp_path / "pinched.nc", m)
    result = run_cli("convert", tmp_path / "pinched.nc", tmp_path / "fort.14")
    assert_clean_failure(
        result, "node 1 (0-based; 2 in a file numbered from 1)", "Illegal bnd node"
    )
    assert not (tmp_path / "fort.14").exists()
