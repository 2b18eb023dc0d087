"""Region ids beside fort.14 (ADCIRC fort.13) and hgrid.gr3 (SCHISM .regions.prop).

The fort.13 is checked line by line against the layout of the ADCIRC manual and
against what ADCIRC's reader does with it (``src/nodalattr.F``, ``ReadNodalAttr``:
an attribute it does not know is skipped, three header lines and one line per
node) and adcprep (``prep/prep.F``, ``PREP13``); the .prop against SCHISM's
element property reader (``schism_init.F90``: ``j, value`` per element).
"""

from __future__ import annotations

import os
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from io_meshes import strip_mesh

from coastmesh.errors import FormatError, InputDataError, OutputExistsError
from coastmesh.io import formats_table, mesh_format, read_mesh, write_mesh
from coastmesh.io.meshes.adcirc import (
    node_regions,
    read_fort13,
    read_fort14_mesh,
    regions_from_nodes,
)
from coastmesh.types import Mesh

NX = NY = 6  # nodes: 5 x 5 cells, 50 triangles
CELLS = (NX - 1) * (NY - 1)
SEA, FARM, TURBINE = 7, 20, 100


def _cell_triangles(i, j):
    """The two triangles of cell (i, j) in strip_mesh's order."""
    c = j * (NX - 1) + i
    return [c, c + CELLS]


def _node(i, j):
    return j * NX + i


def farm_mesh(regions=None, *, surface_id=SEA) -> Mesh:
    """A 6 x 6 node grid (100 m) with a farm (20) of 3 x 3 cells and a turbine
    footprint (100) of the middle cell; the rest is sea (7)."""
    grid = strip_mesh(NX, NY, x0=500000.0, y0=6500000.0, surface_id=surface_id)
    if regions is None:
        regions = np.full(len(grid.triangles), surface_id)
        for i in range(1, 4):
            for j in range(1, 4):
                regions[_cell_triangles(i, j)] = FARM
        regions[_cell_triangles(2, 2)] = TURBINE
    return Mesh(
        grid.points,
        grid.triangles,
        grid.boundary_edges,
        grid.boundary_ids,
        surface_id,
        grid.crs,
        grid.point_data,
        grid.boundary_names,
        grid.boundary_kinds,
        regions,
        {FARM: "inner_sound", TURBINE: "t1"},
    )


def plain_mesh() -> Mesh:
    return strip_mesh(NX, NY, x0=500000.0, y0=6500000.0, surface_id=SEA)


def reference_node_ids(mesh: Mesh) -> np.ndarray:
    """Literal rule: a node takes the innermost (least total area, then smallest
    id) of the regions other than the sea around it; the sea's if none."""
    area = {}
    for tri, region in zip(mesh.triangles, mesh.regions, strict=True):
        (x0, y0), (x1, y1), (x2, y2) = mesh.points[tri]
        a = abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / 2
        area[int(region)] = area.get(int(region), 0.0) + a
    out = []
    for node in range(len(mesh.points)):
        around = {
            int(r)
            for tri, r in zip(mesh.triangles, mesh.regions, strict=True)
            if node in tri
        }
        inner = [r for r in around if r != mesh.surface_id]
        out.append(min(inner, key=lambda r: (area[r], r)) if inner else mesh.surface_id)
    return np.array(out)


# --- what ADCIRC and adcprep do with a fort.13 -----------------------------------


def adcirc_reads(lines, nwp_names, known):
    """Follow ReadNodalAttr (nodalattr.F) over the lines of a fort.13.

    ``known``: the names ADCIRC recognises; ``nwp_names``: those fort.15 lists.
    Returns the loaded attributes {name: (default, {node: value})}; raises
    AssertionError where ADCIRC would stop or read out of step.
    """
    at = iter(lines)
    next(at)  # AGRID, read as (A80)
    num_of_nodes = int(next(at).split()[0])
    nattr = int(next(at).split()[0])
    defaults = {}
    for _ in range(nattr):
        name = next(at).split()[0]  # list-directed: the first word
        if name in known:
            next(at)  # units (A80)
            count = int(next(at).split()[0])
            defaults[name] = [float(v) for v in next(at).split()[:count]]
        else:  # "contains invalid name", then 3 lines skipped
            for _ in range(3):
                next(at)
    # checkForMissingNodalAttributes: every fort.15 name that ADCIRC knows
    assert {n for n in nwp_names if n in known} <= set(defaults)
    loaded = {}
    for _ in range(nattr):
        name = next(at).split()[0]
        count = int(next(at).split()[0])
        rows = [next(at) for _ in range(count)]
        if name in nwp_names and name in known:
            values = {int(r.split()[0]): float(r.split()[1]) for r in rows}
            assert all(1 <= n <= num_of_nodes for n in values)
            loaded[name] = (defaults[name], values)
    assert next(at, None) is None, "lines left after the last attribute"
    return loaded


def adcprep_splits(lines):
    """Follow PREP13 (prep.F): header names are read as (A80) lines and each body
    name (list-directed) must be one of them; defaults and rows list-directed."""
    at = iter(lines)
    next(at)
    int(next(at).split()[0])
    nattr = int(next(at).split()[0])
    header = {}
    for _ in range(nattr):
        name = next(at).strip()  # (A80), compared trim(adjustl())
        next(at)
        count = int(next(at).split()[0])
        assert len(next(at).split()) >= count
        header[name] = count
    for _ in range(nattr):
        name = next(at).split()[0]
        assert name in header, f"{name!r} not found in the header"
        for _ in range(int(next(at).split()[0])):
            row = next(at).split()
            int(row[0])
            [float(v) for v in row[1 : 1 + header[name]]]
    assert next(at, None) is None


ADCIRC_NAMES = {"mannings_n_at_sea_floor", "surface_submergence_state"}


# --- fort.13 ----------------------------------------------------------------------


def test_fort13_holds_what_adcirc_expects_line_by_line(tmp_path):
    mesh = farm_mesh()
    write_mesh(tmp_path / "fort.14", mesh)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fort.13", "fort.14"]
    text = (tmp_path / "fort.13").read_text(encoding="ascii")
    assert text.endswith("\n") and "\t" not in text and "\r" not in text
    lines = text.splitlines()
    expected_ids = reference_node_ids(mesh)
    non_default = np.flatnonzero(expected_ids != SEA)
    header = [
        "coastmesh region ids, innermost first: 100 20",  # AGRID
        str(len(mesh.points)),  # NumOfNodes = NP of the fort.14
        "1",  # NAttr
        "coastmesh_region_id",  # AttrName
        "unitless",  # Units
        "1",  # ValuesPerNode
        str(SEA),  # DefaultAttrVal: the sea's id
        "coastmesh_region_id",  # AttrName again
        str(len(non_default)),  # NumNodesNotDefaultVal
    ]
    assert lines[:9] == header
    body = lines[9:]
    assert len(body) == len(non_default) == 16
    for line in body:
        assert re.fullmatch(r"\s*\d+ +\d+", line), line  # integers, no comment
    table = np.array([line.split() for line in body], dtype=np.int64)
    np.testing.assert_array_equal(table[:, 0], non_default + 1)
    np.testing.assert_array_equal(table[:, 1], expected_ids[non_default])
    # the grid beside it has as many nodes
    assert (tmp_path / "fort.14").read_text().splitlines()[1].split() == [
        str(len(mesh.triangles)),
        str(len(mesh.points)),
    ]


def test_a_footprint_keeps_every_node_of_its_outline():
    mesh = farm_mesh()
    ids = node_regions(mesh)
    np.testing.assert_array_equal(ids, reference_node_ids(mesh))
    footprint = {_node(i, j) for i in (2, 3) for j in (2, 3)}
    farm = {_node(i, j) for i in range(1, 5) for j in range(1, 5)} - footprint
    assert {int(k) for k in np.flatnonzero(ids == TURBINE)} == footprint
    assert {int(k) for k in np.flatnonzero(ids == FARM)} == farm
    assert (np.delete(ids, sorted(footprint | farm)) == SEA).all()


def test_adcirc_skips_the_attribute_and_adcprep_splits_it(tmp_path):
    write_mesh(tmp_path / "fort.14", farm_mesh())
    lines = (tmp_path / "fort.13").read_text().splitlines()
    # NWP = 0: fort.13 is not read at all; NWP lists it: logged, skipped
    assert adcirc_reads(lines, [], ADCIRC_NAMES) == {}
    assert adcirc_reads(lines, ["coastmesh_region_id"], ADCIRC_NAMES) == {}
    adcprep_splits(lines)
    assert read_fort13(tmp_path / "fort.13")["attributes"].keys() == {
        "coastmesh_region_id"
    }


def _with_mannings(lines, n):
    """The fort.13 with a Manning's n attribute added, its body block first."""
    header, body = lines[:9], lines[9:]
    nodes = sorted({int(line.split()[0]) for line in body})
    mannings = [f"{k} 0.05" for k in nodes]
    return (
        [header[0], str(n), "2"]
        + header[3:7]
        + ["mannings_n_at_sea_floor", "s/m^(1/3)", "1", "0.025"]
        + ["mannings_n_at_sea_floor", str(len(mannings)), *mannings]
        + header[7:]
        + body
    )


def test_a_fort13_the_user_extends_still_runs_and_reads_back(tmp_path):
    mesh = farm_mesh()
    write_mesh(tmp_path / "fort.14", mesh)
    path = tmp_path / "fort.13"
    lines = _with_mannings(path.read_text().splitlines(), len(mesh.points))
    path.write_text("\n".join(lines) + "\n")
    loaded = adcirc_reads(lines, ["mannings_n_at_sea_floor"], ADCIRC_NAMES)
    default, values = loaded["mannings_n_at_sea_floor"]
    assert default == [0.025] and set(values.values()) == {0.05}
    adcprep_splits(lines)
    back = read_mesh(tmp_path / "fort.14")
    np.testing.assert_array_equal(back.regions, mesh.regions)


def test_a_fort13_without_region_ids_is_ignored(tmp_path):
    write_mesh(tmp_path / "fort.14", plain_mesh())
    n = len(plain_mesh().points)
    (tmp_path / "fort.13").write_text(
        f"grid\n{n}\n1\nsurface_submergence_state\nunitless\n1\n0\n"
        "surface_submergence_state\n1\n3 1\n"
    )
    back = read_mesh(tmp_path / "fort.14")
    assert (back.regions == back.surface_id).all()


def test_a_fort13_that_does_not_fit_the_grid_is_refused(tmp_path):
    write_mesh(tmp_path / "fort.14", farm_mesh())
    path = tmp_path / "fort.13"
    lines = path.read_text().splitlines()
    path.write_text("\n".join([lines[0], "35", *lines[2:]]) + "\n")
    with pytest.raises(InputDataError, match=r"fort\.13.*NumOfNodes is 35"):
        read_mesh(tmp_path / "fort.14")
    lines[-1] = lines[-1].split()[0] + " 20.5"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputDataError, match="integers >= 1"):
        read_mesh(tmp_path / "fort.14")


def test_fort14_round_trip_gives_the_regions_back(tmp_path):
    mesh = farm_mesh()
    write_mesh(tmp_path / "case.14", mesh)
    assert (tmp_path / "case.13").is_file()  # the grid's stem
    back = read_mesh(tmp_path / "case.14")
    np.testing.assert_array_equal(back.regions, mesh.regions)
    assert back.surface_id == SEA  # the attribute's default
    assert back.region_ids == [SEA, FARM, TURBINE]
    assert back.region_names == {}  # not kept


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from([7, 7, 20, 21, 100]), min_size=50, max_size=50))
def test_fort14_gives_back_every_triangle_its_nodes_determine(tmp_path_factory, ids):
    mesh = farm_mesh(np.array(ids))
    folder = tmp_path_factory.mktemp("fort14")
    write_mesh(folder / "fort.14", mesh)
    node_ids = node_regions(mesh)
    np.testing.assert_array_equal(node_ids, reference_node_ids(mesh))
    if not (mesh.regions != SEA).any():
        assert not (folder / "fort.13").exists()
        return
    back = read_fort14_mesh(folder / "fort.14")
    determined = (node_ids[mesh.triangles] == mesh.regions[:, None]).any(axis=1)
    assert determined.any()
    np.testing.assert_array_equal(back.regions[determined], mesh.regions[determined])
    assert (back.regions[~determined] != mesh.regions[~determined]).all()


def test_regions_from_nodes_ranks_by_area_without_the_agrid_order():
    mesh = farm_mesh()
    ids = node_regions(mesh)
    listed = regions_from_nodes(mesh.points, mesh.triangles, ids, SEA, [100, 20])
    guessed = regions_from_nodes(mesh.points, mesh.triangles, ids, SEA)
    np.testing.assert_array_equal(listed, mesh.regions)
    np.testing.assert_array_equal(guessed, mesh.regions)


# --- SCHISM .regions.prop ---------------------------------------------------------


def test_prop_has_one_line_per_element_with_its_id(tmp_path):
    mesh = farm_mesh()
    write_mesh(tmp_path / "hgrid.gr3", mesh)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "hgrid.gr3",
        "hgrid.regions.prop",
    ]
    lines = (tmp_path / "hgrid.regions.prop").read_text().splitlines()
    assert len(lines) == len(mesh.triangles)
    for k, (line, region) in enumerate(zip(lines, mesh.regions, strict=True), 1):
        # schism_init.F90: read(32,*) j, value -- element after element
        assert re.fullmatch(r"\s*\d+ +\d+", line), line
        j, value = (int(w) for w in line.split())
        assert (j, value) == (k, region)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from([7, 7, 20, 21, 100]), min_size=50, max_size=50))
def test_gr3_round_trip_is_exact(tmp_path_factory, ids):
    mesh = farm_mesh(np.array(ids))
    folder = tmp_path_factory.mktemp("gr3")
    write_mesh(folder / "hgrid.gr3", mesh)
    back = read_mesh(folder / "hgrid.gr3")
    if not (mesh.regions != SEA).any():
        assert not (folder / "hgrid.regions.prop").exists()
        assert (back.regions == back.surface_id).all()
        return
    np.testing.assert_array_equal(back.regions, mesh.regions)
    counts = np.bincount(mesh.regions)
    assert back.surface_id == int(np.argmax(counts))  # the most triangles


def test_a_prop_that_does_not_fit_the_grid_is_refused(tmp_path):
    write_mesh(tmp_path / "hgrid.gr3", farm_mesh())
    path = tmp_path / "hgrid.regions.prop"
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(InputDataError, match="ends at line 49"):
        read_mesh(tmp_path / "hgrid.gr3")
    path.write_text("\n".join([lines[1], lines[0], *lines[2:]]) + "\n")
    with pytest.raises(InputDataError, match="line 1 has element number 2"):
        read_mesh(tmp_path / "hgrid.gr3")
    path.write_text("\n".join([*lines, "51 7"]) + "\n")
    with pytest.raises(InputDataError, match="1 lines follow the 50 elements"):
        read_mesh(tmp_path / "hgrid.gr3")
    path.write_text("\n".join(["1 -1", *lines[1:]]) + "\n")  # a fluxflag, say
    with pytest.raises(InputDataError, match="region id is -1 at element 1"):
        read_mesh(tmp_path / "hgrid.gr3")


# --- when they are written, and atomically ----------------------------------------


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_no_region_file_without_regions(tmp_path, name):
    write_mesh(tmp_path / name, plain_mesh())
    assert [p.name for p in tmp_path.iterdir()] == [name]
    assert (read_mesh(tmp_path / name).regions == 1).all()


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_regions_false_writes_the_grid_alone(tmp_path, name):
    write_mesh(tmp_path / name, farm_mesh(), regions=False)
    assert [p.name for p in tmp_path.iterdir()] == [name]


def test_the_registry_says_which_files_a_mesh_gets():
    fort14, gr3 = mesh_format("fort14"), mesh_format("gr3")
    assert fort14.region_companions == (".13",) and fort14.companions == ()
    assert gr3.region_companions == (".regions.prop",)
    assert fort14.companions_for(farm_mesh()) == (".13",)
    assert gr3.companions_for(plain_mesh()) == ()
    assert mesh_format("selafin").companions_for(farm_mesh()) == (".cli",)
    assert "regions" in gr3.holds and "regions" not in fort14.holds
    assert "node_regions" in fort14.holds
    table = formats_table()
    assert "(+ `.13` with regions)" in table
    assert "(+ `.regions.prop` with regions)" in table


@pytest.mark.parametrize(
    ("name", "beside"), [("fort.14", "fort.13"), ("hgrid.gr3", "hgrid.regions.prop")]
)
def test_an_existing_region_file_is_kept_unless_overwrite(tmp_path, name, beside):
    (tmp_path / beside).write_text("mine\n")
    with pytest.raises(OutputExistsError, match=rf"{re.escape(beside)} already"):
        write_mesh(tmp_path / name, farm_mesh())
    assert sorted(p.name for p in tmp_path.iterdir()) == [beside]
    assert (tmp_path / beside).read_text() == "mine\n"
    write_mesh(tmp_path / name, farm_mesh(), overwrite=True)
    assert (tmp_path / beside).read_text() != "mine\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([name, beside])


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_a_failed_write_leaves_neither_file(tmp_path, monkeypatch, name):
    from coastmesh.io.meshes.adcirc import _write

    def broken(path, mesh, flavour):
        path.write_text("half a fi")
        raise OSError("disk full")

    monkeypatch.setattr(_write, "write_region_file", broken)
    with pytest.raises(OSError, match="disk full"):
        write_mesh(tmp_path / name, farm_mesh())
    assert os.listdir(tmp_path) == []  # no grid, no region file, no staging


def test_a_grid_cannot_take_the_name_of_its_region_file(tmp_path):
    with pytest.raises(FormatError, match=r"cannot end in \.13"):
        write_mesh(tmp_path / "mesh.13", farm_mesh(), format="fort14")
    write_mesh(tmp_path / "mesh.13", plain_mesh(), format="fort14")  # no regions
    assert os.listdir(tmp_path) == ["mesh.13"]


def test_the_mesh_is_not_changed(tmp_path):
    mesh = farm_mesh()
    regions = mesh.regions.copy()
    write_mesh(tmp_path / "fort.14", mesh)
    write_mesh(tmp_path / "hgrid.gr3", mesh)
    np.testing.assert_array_equal(mesh.regions, regions)


def test_a_fort13_of_other_attributes_is_not_parsed(tmp_path):
    write_mesh(tmp_path / "fort.14", plain_mesh())
    (tmp_path / "fort.13").write_text("grid\n36\n1\nz0land\nm\n12\n0.2D-01 ...\n")
    assert (read_mesh(tmp_path / "fort.14").regions == 1).all()
