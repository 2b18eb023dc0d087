"""Telemac SELAFIN + .cli: read back by xarray-selafin, raw records, .cli lines."""

from __future__ import annotations

import struct

import numpy as np
import pytest
import shapely
import xarray as xr
from io_meshes import strip_mesh

from coastmesh.errors import CoastmeshWarning, FormatError, OutputExistsError
from coastmesh.io import MeshFormat
from coastmesh.io.meshes import telemac
from coastmesh.io.meshes.telemac import write_selafin
from coastmesh.types import Mesh
from coastmesh.types.topology import boundary_rings


def grid_mesh(nx=6, ny=5, dx=100.0, x0=0.0, y0=0.0, ids=None, crs="EPSG:32630"):
    """A structured grid (:func:`io_meshes.strip_mesh`); south open (2), coast (1).

    ``ids`` overrides the id of each boundary edge, counter-clockwise from (x0, y0).
    """
    return strip_mesh(nx, ny, dx=dx, x0=x0, y0=y0, ids=ids, crs=crs)


@pytest.fixture(scope="module")
def island_mesh(mesh_with_islands):
    """The shared square with two islands (tests/conftest.py), with depth."""
    return mesh_with_islands


def read_cli(path):
    """Parse a .cli file strictly: 13 columns per line, as Telemac lists them."""
    text = path.read_bytes().decode("ascii")
    assert "\r" not in text and text.endswith("\n") and "\n\n" not in text
    rows = [line.split() for line in text.splitlines()]
    assert all(len(row) == 13 for row in rows)
    codes = np.array([[int(r[i]) for i in (0, 1, 2, 7)] for r in rows])
    values = np.array([[float(r[i]) for i in (3, 4, 5, 6, 8, 9, 10)] for r in rows])
    n = np.array([int(r[11]) for r in rows])
    k = np.array([int(r[12]) for r in rows])
    return codes, values, n, k


def read_records(path):
    """Split a file into Fortran sequential records (big-endian int32 markers)."""
    data = path.read_bytes()
    records, pos = [], 0
    while pos < len(data):
        (size,) = struct.unpack(">i", data[pos : pos + 4])
        body = data[pos + 4 : pos + 4 + size]
        (tail,) = struct.unpack(">i", data[pos + 4 + size : pos + 8 + size])
        assert tail == size and len(body) == size
        records.append(body)
        pos += size + 8
    return records


def node_kinds(mesh):
    """Nodes on an open edge (liquid) and nodes on shoreline edges only."""
    open_ids = [i for i, k in mesh.boundary_kinds.items() if k == "open"]
    is_open = np.isin(mesh.boundary_ids, open_ids)
    liquid = set(np.unique(mesh.boundary_edges[is_open]).tolist())
    solid = set(np.unique(mesh.boundary_edges).tolist()) - liquid
    return liquid, solid


def test_xarray_selafin_reads_the_mesh(tmp_path, write_read, island_mesh):
    mesh = island_mesh
    path = tmp_path / "mesh.slf"

    def read(p):
        with xr.open_dataset(p, engine="selafin") as ds:
            return ds.load(), dict(ds.attrs)

    def unchanged(a, b):
        np.testing.assert_array_equal(a.points, b.points)
        np.testing.assert_array_equal(a.triangles, b.triangles)
        np.testing.assert_array_equal(a.point_data["depth"], b.point_data["depth"])

    ds, attrs = write_read(path, write_selafin, read, mesh, unchanged)
    assert ds.sizes["node"] == len(mesh.points)
    np.testing.assert_array_equal(attrs["ikle2"] - 1, mesh.triangles)
    np.testing.assert_array_equal(ds["x"].values, mesh.points[:, 0].astype(np.float32))
    np.testing.assert_array_equal(ds["y"].values, mesh.points[:, 1].astype(np.float32))
    assert attrs["variables"] == {"B": ("BOTTOM", "M")}
    assert ds.sizes["time"] == 1
    bottom = ds["B"].values[0]
    np.testing.assert_allclose(bottom, -mesh.point_data["depth"], rtol=1e-6)
    assert bottom.dtype == np.float32 and (bottom < 0).all()  # elevation: up
    assert attrs["float_size"] == 4 and attrs["endian"] == ">"
    assert attrs["params"] == (1, 0, 0, 0, 0, 0, 0, 0, 0, 0)
    assert attrs["title"] == "coastmesh mesh, EPSG:32630"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.cli", "mesh.slf"]


def test_records_follow_the_serafin_layout(tmp_path):
    mesh = grid_mesh()
    write_selafin(tmp_path / "m.slf", mesh)
    records = read_records(tmp_path / "m.slf")
    n, m = len(mesh.points), len(mesh.triangles)
    sizes = [80, 8, 32, 40, 16, 12 * m, 4 * n, 4 * n, 4 * n, 4, 4 * n]
    assert [len(r) for r in records] == sizes
    assert records[0][72:] == b"SERAFIN "
    assert np.frombuffer(records[1], ">i4").tolist() == [1, 0]
    assert records[2] == b"BOTTOM          M               "
    assert np.frombuffer(records[4], ">i4").tolist() == [m, n, 3, 1]
    ikle = np.frombuffer(records[5], ">i4").reshape(m, 3)  # element after element
    np.testing.assert_array_equal(ikle, mesh.triangles + 1)
    np.testing.assert_array_equal(
        np.frombuffer(records[7], ">f4"), mesh.points[:, 0].astype(np.float32)
    )
    assert np.frombuffer(records[9], ">f4").tolist() == [0.0]  # time


def test_cli_lists_every_boundary_node_once_with_codes_by_kind(tmp_path, island_mesh):
    mesh = island_mesh
    write_selafin(tmp_path / "m.slf", mesh)
    codes, values, n, k = read_cli(tmp_path / "m.cli")
    boundary = np.unique(mesh.boundary_edges)
    assert sorted(n - 1) == boundary.tolist()  # exactly the boundary nodes
    assert k.tolist() == list(range(1, len(n) + 1))
    assert (values == 0).all()
    liquid, solid = node_kinds(mesh)
    by_node = dict(zip((n - 1).tolist(), codes.tolist(), strict=True))
    assert {tuple(by_node[i]) for i in liquid} == {(5, 4, 4, 4)}
    assert {tuple(by_node[i]) for i in solid} == {(2, 2, 2, 2)}


def test_cli_follows_the_rings_exterior_ccw_then_islands_cw(tmp_path, island_mesh):
    mesh = island_mesh
    write_selafin(tmp_path / "m.slf", mesh)
    _, _, n, _ = read_cli(tmp_path / "m.cli")
    edges = {tuple(sorted(e)) for e in mesh.boundary_edges.tolist()}
    # cut the list where consecutive nodes are not joined by a boundary edge
    nodes = (n - 1).tolist()
    cuts = [
        i
        for i in range(1, len(nodes))
        if tuple(sorted((nodes[i - 1], nodes[i]))) not in edges
    ]
    rings = np.split(np.array(nodes), cuts)
    assert len(rings) == 3
    for ring in rings:  # each piece closes on itself
        assert tuple(sorted((ring[-1], ring[0]))) in edges
    orientation = [shapely.LinearRing(mesh.points[r]).is_ccw for r in rings]
    assert orientation == [True, False, False]
    areas = [shapely.Polygon(mesh.points[r]).area for r in rings]
    assert areas[0] == max(areas)
    expected = np.concatenate([r.nodes for r in boundary_rings(mesh)])
    np.testing.assert_array_equal(n - 1, expected)


def test_ipobo_numbers_the_nodes_in_cli_order(tmp_path, island_mesh):
    mesh = island_mesh
    write_selafin(tmp_path / "m.slf", mesh)
    with xr.open_dataset(tmp_path / "m.slf", engine="selafin") as ds:
        ipobo = np.asarray(ds.attrs["ipobo"])
    _, _, n, k = read_cli(tmp_path / "m.cli")
    assert ipobo.shape == (len(mesh.points),)
    np.testing.assert_array_equal(ipobo[n - 1], k)
    assert np.count_nonzero(ipobo) == len(n)


def test_junction_nodes_keep_the_tagged_segment_kinds(tmp_path):
    """Telemac (BIEF front2.f): a segment is liquid only if both ends are liquid."""
    mesh = grid_mesh(nx=6, ny=5)
    write_selafin(tmp_path / "m.slf", mesh)
    codes, _, n, _ = read_cli(tmp_path / "m.cli")
    liquid = dict(zip((n - 1).tolist(), (codes[:, 0] != 2).tolist(), strict=True))
    assert liquid[0] and liquid[5]  # the corners where the open south edge ends
    assert not liquid[11] and not liquid[1 * 6 + 0]  # their land neighbours
    open_ids = {i for i, kind in mesh.boundary_kinds.items() if kind == "open"}
    for (a, b), pid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True):
        assert (liquid[a] and liquid[b]) == (pid in open_ids)


def test_open_codes_and_positive_down(tmp_path):
    mesh = grid_mesh()
    write_selafin(tmp_path / "m.slf", mesh, open_codes=(4, 5, 5), positive="down")
    codes, _, n, _ = read_cli(tmp_path / "m.cli")
    liquid, _ = node_kinds(mesh)
    opened = {
        tuple(c) for c, i in zip(codes.tolist(), n - 1, strict=True) if i in liquid
    }
    assert opened == {(4, 5, 5, 4)}
    with xr.open_dataset(tmp_path / "m.slf", engine="selafin") as ds:
        np.testing.assert_allclose(ds["B"].values[0], mesh.point_data["depth"])


@pytest.mark.parametrize("codes", ["5 4", "5 4 x", "5 4 7", "2 2 2", (5, 4, 4, 4)])
def test_bad_open_codes_are_refused(tmp_path, codes):
    with pytest.raises(FormatError, match="open_codes"):
        write_selafin(tmp_path / "m.slf", grid_mesh(), open_codes=codes)
    assert list(tmp_path.iterdir()) == []


def test_bad_positive_is_refused(tmp_path):
    with pytest.raises(FormatError, match="positive is 'depth'"):
        write_selafin(tmp_path / "m.slf", grid_mesh(), positive="depth")


def test_mesh_without_depth_writes_zero_and_warns(tmp_path):
    mesh = grid_mesh()
    bare = Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        mesh.boundary_ids,
        1,
        mesh.crs,
        boundary_kinds=mesh.boundary_kinds,
    )
    with pytest.warns(CoastmeshWarning, match="no point_data\\['depth'\\]"):
        write_selafin(tmp_path / "m.slf", bare)
    with xr.open_dataset(tmp_path / "m.slf", engine="selafin") as ds:
        assert (ds["B"].values == 0).all()


def test_non_finite_depth_is_refused(tmp_path):
    mesh = grid_mesh()
    depth = mesh.point_data["depth"].copy()
    depth[7] = np.nan
    with pytest.raises(FormatError, match="nan at node 7"):
        write_selafin(tmp_path / "m.slf", mesh.with_point_data(depth=depth))
    assert list(tmp_path.iterdir()) == []


def test_missing_kinds_are_named(tmp_path):
    mesh = grid_mesh()
    no_kinds = Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        mesh.boundary_ids,
        1,
        mesh.crs,
        mesh.point_data,
        boundary_kinds={2: "open"},
    )
    with pytest.raises(FormatError, match=r"id\(s\) 1 have no kind.*cli=False"):
        write_selafin(tmp_path / "m.slf", no_kinds)
    assert list(tmp_path.iterdir()) == []
    write_selafin(tmp_path / "m.slf", no_kinds, cli=False)
    assert [p.name for p in tmp_path.iterdir()] == ["m.slf"]


@pytest.mark.parametrize("run", [1, 2])
def test_short_shoreline_run_between_open_boundaries_is_refused(tmp_path, run):
    ids = np.full(18, 2)  # nx=6, ny=5: 18 boundary edges, all open ...
    ids[3 : 3 + run] = 3  # ... but a rock of `run` edges on the south side
    with pytest.raises(FormatError, match=r"shoreline boundary 3 \('rock'\)"):
        write_selafin(tmp_path / "m.slf", grid_mesh(ids=ids))
    assert list(tmp_path.iterdir()) == []


def test_three_edge_shoreline_run_is_kept(tmp_path):
    ids = np.full(18, 2)
    ids[1:4] = 3
    mesh = grid_mesh(ids=ids)
    write_selafin(tmp_path / "m.slf", mesh)
    codes, _, n, _ = read_cli(tmp_path / "m.cli")
    solid = (n[codes[:, 0] == 2] - 1).tolist()
    assert solid == [2, 3]  # the inner rock nodes; its ends 1 and 4 stay liquid


def test_existing_outputs_are_refused(tmp_path):
    mesh = grid_mesh()
    (tmp_path / "m.cli").write_text("keep")
    with pytest.raises(OutputExistsError, match=r"m\.cli already exists"):
        write_selafin(tmp_path / "m.slf", mesh)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.cli"]
    assert (tmp_path / "m.cli").read_text() == "keep"
    write_selafin(tmp_path / "m.slf", mesh, overwrite=True)
    assert read_cli(tmp_path / "m.cli")[2].size == 18
    with pytest.raises(OutputExistsError, match=r"m\.slf already exists"):
        write_selafin(tmp_path / "m.slf", mesh)


def test_failure_writing_the_cli_leaves_neither_file(tmp_path, monkeypatch):
    def broken(path, table, order):
        path.write_text("partial")
        raise OSError("disk full")

    monkeypatch.setattr(telemac, "_write_cli", broken)
    with pytest.raises(OSError, match="disk full"):
        write_selafin(tmp_path / "m.slf", grid_mesh())
    assert list(tmp_path.iterdir()) == []  # no target, no staging folder


def test_titles(tmp_path):
    geographic = grid_mesh(dx=0.01, x0=-3.0, y0=58.0, crs="EPSG:4326")
    write_selafin(tmp_path / "g.slf", geographic)
    title = read_records(tmp_path / "g.slf")[0][:72].decode().rstrip()
    assert title == "coastmesh mesh, EPSG:4326, geographic lon/lat degrees"
    write_selafin(tmp_path / "t.slf", grid_mesh(), title="Orkney run 3")
    assert read_records(tmp_path / "t.slf")[0] == b"Orkney run 3".ljust(72) + (
        b"SERAFIN "
    )
    with pytest.raises(FormatError, match=r"title .* at most 72 characters"):
        write_selafin(tmp_path / "x.slf", grid_mesh(), title="x" * 73)


def test_single_precision_collapse_warns(tmp_path):
    mesh = grid_mesh(dx=0.05, x0=500000.0, y0=6500000.0)  # 5 cm at UTM northings
    with pytest.warns(CoastmeshWarning, match="single precision"):
        write_selafin(tmp_path / "m.slf", mesh)


def test_registry_entry_is_accepted():
    fmt = MeshFormat(
        "selafin", (".slf", ".selafin"), write_selafin, "Telemac SELAFIN + .cli"
    )
    assert fmt.options == ("positive", "cli", "open_codes", "title")
