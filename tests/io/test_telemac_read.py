"""Telemac SELAFIN + .cli read back: round trips, xarray-selafin's files, bad files."""

from __future__ import annotations

import shutil
import struct

import numpy as np
import pytest
import xarray as xr
import xarray_selafin.xarray_backend  # noqa: F401  (registers ds.selafin.write)
from io_meshes import cell_mesh, edge_ids, same_mesh, strip_mesh

from coastmesh.errors import (
    CoastmeshWarning,
    ConfigError,
    FormatError,
    InputDataError,
)
from coastmesh.io import mesh_format, read_mesh, write_mesh
from coastmesh.io.meshes.telemac import write_selafin
from coastmesh.io.meshes.telemac_read import read_selafin_mesh

# south edges 0-4, east 5-8, north 9-13, west 14-17 of a 6 x 5 strip_mesh, ccw
SOUTH, EAST, NORTH, WEST = range(5), range(5, 9), range(9, 14), range(14, 18)
# byte offsets in a file write_selafin writes (records of 80, 8, 32, 40 bytes first)
NDP_AT = 88 + 16 + 40 + 48 + 4 + 8
IKLE_AT = NDP_AT + 4 + 4 + 4 + 4  # the first node of the first element


def strip(ids, kinds, **kwargs):
    """A 6 x 5 strip_mesh with these edge ids and kinds, no names."""
    return strip_mesh(6, 5, ids=ids, kinds=kinds, names={}, **kwargs)


def edge_kinds(mesh):
    """Each undirected boundary edge, mapped to its kind."""
    return {
        edge: mesh.boundary_kinds[pid]
        for edge, pid in edge_ids(mesh.boundary_edges, mesh.boundary_ids).items()
    }


def holes_mesh():
    """A 6 x 6 square of cells with two one-cell holes; south side open (id 2)."""
    return cell_mesh(
        6,
        {(1, 1), (4, 3)},
        lambda a, b: 2 if a[1] == b[1] == 0 else (3 if 0 < a[0] < 6 else 1),
        {1: "shoreline", 2: "open", 3: "shoreline"},
    )


@pytest.fixture(params=["islands", "strip", "holes"])
def written(request, mesh_with_islands):
    return {
        "islands": mesh_with_islands,
        "strip": strip_mesh(6, 5, jitter=20.0, x0=500000.0, y0=6500000.0),
        "holes": holes_mesh(),
    }[request.param]


def test_round_trip(tmp_path, write_read, written):
    back = write_read(
        tmp_path / "m.slf", write_selafin, read_selafin_mesh, written, same_mesh
    )
    single = written.points.astype(np.float32).astype(np.float64)
    np.testing.assert_array_equal(back.points, single)
    np.testing.assert_array_equal(back.triangles, written.triangles)
    depth = written.point_data["depth"].astype(np.float32).astype(np.float64)
    np.testing.assert_array_equal(back.point_data["depth"], depth)
    assert edge_kinds(back) == edge_kinds(written)
    # every land id comes back as 1; each of these meshes has one open run: 2
    assert edge_ids(back.boundary_edges, back.boundary_ids) == {
        edge: 2 if kind == "open" else 1 for edge, kind in edge_kinds(written).items()
    }
    assert back.boundary_kinds == {1: "shoreline", 2: "open"}
    assert back.boundary_names == {}
    assert back.crs == written.crs  # from the title write_selafin gives
    assert back.surface_id == 1
    # the edges run as the .cli lists the nodes: ring by ring, domain on the left
    cli = np.loadtxt(tmp_path / "m.cli", usecols=11, dtype=int) - 1
    np.testing.assert_array_equal(back.boundary_edges[:, 0], cli)


def test_ids_number_the_liquid_boundaries_as_telemac(tmp_path):
    """front2.f: from the south-westernmost node, a run across it numbered first."""
    ids = np.ones(18, dtype=int)
    ids[list(SOUTH) + list(WEST)] = 4  # one liquid run through the SW corner
    ids[[8, 9, 10]] = 6  # the NE corner
    mesh = strip(ids, {1: "shoreline", 4: "open", 6: "open"})
    write_selafin(tmp_path / "m.slf", mesh)
    back = read_selafin_mesh(tmp_path / "m.slf")
    expected = np.select([ids == 4, ids == 6], [2, 3], 1)
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        mesh.boundary_edges, expected
    )
    assert back.boundary_kinds == {1: "shoreline", 2: "open", 3: "open"}


def test_ids_follow_telemac_not_the_written_ids(tmp_path):
    ids = np.ones(18, dtype=int)
    ids[list(NORTH)], ids[list(SOUTH)] = 2, 3  # Telemac's first is the south
    adjacent = ids.copy()
    adjacent[list(EAST)] = 5  # open ids that meet are one liquid boundary
    for k, written_ids in enumerate([ids, adjacent]):
        kinds = {1: "shoreline", 2: "open", 3: "open", 5: "open"}
        mesh = strip(written_ids, {i: kinds[i] for i in np.unique(written_ids)})
        write_selafin(tmp_path / f"{k}.slf", mesh)
        back = read_selafin_mesh(tmp_path / f"{k}.slf")
        expected = {1: 1, 2: 3, 3: 2} if k == 0 else {1: 1, 2: 2, 3: 2, 5: 2}
        assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
            mesh.boundary_edges, [expected[i] for i in written_ids]
        )


def test_contours_are_numbered_from_the_south_west(tmp_path):
    """front2.f: then the contour of the south-westernmost node left, and so on."""

    def edge_id(a, b):
        xs, ys = {a[0], b[0]}, {a[1], b[1]}
        if ys == {0}:
            return 2  # south
        if xs <= {4, 5} and ys <= {3, 4}:
            return 5  # the hole at (4, 3)
        return 6 if xs <= {1, 2} and ys <= {1, 2} else 1  # the hole at (1, 1)

    kinds = {1: "shoreline", 2: "open", 5: "open", 6: "open"}
    mesh = cell_mesh(6, {(1, 1), (4, 3)}, edge_id, kinds)
    write_selafin(tmp_path / "m.slf", mesh)
    cli = tmp_path / "m.cli"
    lines = cli.read_text().splitlines(keepends=True)
    cli.write_text("".join(lines[:-8] + lines[-4:] + lines[-8:-4]))  # (4, 3) first
    back = read_selafin_mesh(tmp_path / "m.slf")
    assert int(lines[-1].split()[11]) - 1 == 3 * 7 + 5  # the hole at (4, 3) was last
    expected = {1: 1, 2: 2, 6: 3, 5: 4}
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        mesh.boundary_edges, [expected[i] for i in mesh.boundary_ids.tolist()]
    )


def test_a_change_of_codes_starts_a_liquid_boundary(tmp_path):
    mesh = strip(np.where(np.arange(18) < 5, 2, 1), {1: "shoreline", 2: "open"})
    write_selafin(tmp_path / "m.slf", mesh)
    cli = tmp_path / "m.cli"
    lines = cli.read_text().splitlines(keepends=True)
    assert [int(line.split()[11]) for line in lines[:6]] == [1, 2, 3, 4, 5, 6]
    lines[3:6] = [line.replace("5 4 4", "4 5 5", 1) for line in lines[3:6]]
    cli.write_text("".join(lines))
    back = read_selafin_mesh(tmp_path / "m.slf")
    # the edge from node 3 (5 4 4) to node 4 (4 5 5) stays with the first
    expected = [2, 2, 2, 3, 3] + [1] * 13
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        mesh.boundary_edges, expected
    )


def test_positive_down_and_crs(tmp_path, mesh_with_islands):
    path = tmp_path / "m.slf"
    write_selafin(path, mesh_with_islands, positive="down", title="Orkney run 3")
    back = read_selafin_mesh(path, positive="down")
    depth = mesh_with_islands.point_data["depth"].astype(np.float32)
    np.testing.assert_array_equal(back.point_data["depth"], depth)
    assert back.crs is None  # a title of its own: no CRS
    assert read_selafin_mesh(path, crs="EPSG:32630").crs.to_epsg() == 32630
    with pytest.raises(ConfigError, match="positive='depth'"):
        read_selafin_mesh(path, positive="depth")
    write_selafin(tmp_path / "utm.slf", mesh_with_islands)
    with pytest.raises(InputDataError, match="EPSG:32630, but crs=EPSG:4326"):
        read_selafin_mesh(tmp_path / "utm.slf", crs="EPSG:4326")


def test_read_mesh_picks_selafin_by_extension(tmp_path, mesh_with_islands):
    for name in ("a.slf", "b.selafin"):
        write_mesh(tmp_path / name, mesh_with_islands)
        back = read_mesh(tmp_path / name)
        assert len(back.triangles) == len(mesh_with_islands.triangles), name
        assert back.boundary_kinds == {1: "shoreline", 2: "open"}
    fmt = mesh_format("selafin")
    assert fmt.read is read_selafin_mesh
    assert fmt.mode == "read and write"
    assert fmt.read_options == ("positive",)


def xarray_selafin_file(path, mesh, *, bed, float_size, endian, origin):
    """Write ``mesh`` with xarray-selafin: two steps, three variables, a date."""
    n = len(mesh.points)
    rng = np.random.default_rng(20240611)
    bottom = -mesh.point_data["depth"]
    times = np.array(["2020-01-01T00", "2020-01-01T01"], dtype="datetime64[ns]")
    ds = xr.Dataset(
        {
            "U": (("time", "node"), rng.normal(size=(2, n))),
            "B": (("time", "node"), np.stack([bottom, bottom + 1.0])),
            "S": (("time", "node"), rng.normal(size=(2, n))),
        },
        coords={
            "x": ("node", mesh.points[:, 0] - origin[0]),
            "y": ("node", mesh.points[:, 1] - origin[1]),
            "time": times,
        },
        attrs={
            "ikle2": (mesh.triangles + 1).astype(np.int32),
            "float_size": float_size,
            "endian": endian,
            "params": (1, 0, *origin, 0, 0, 0, 0, 0, 1),
            "date_start": (2020, 1, 1, 0, 0, 0),
            "variables": {
                "U": ("VELOCITY U", "M/S"),
                "B": (bed, "M"),
                "S": ("FREE SURFACE", "M"),
            },
        },
    )
    ds.selafin.write(str(path))


@pytest.mark.parametrize(
    "bed,float_size,endian,origin",
    [("BOTTOM", 8, "<", (500000, 6500000)), ("FOND", 4, ">", (0, 0))],
)
def test_files_of_xarray_selafin(tmp_path, bed, float_size, endian, origin):
    mesh = strip_mesh(6, 5, jitter=20.0, x0=500000.0, y0=6500000.0)
    write_selafin(tmp_path / "ours.slf", mesh)
    path = tmp_path / "theirs.slf"
    xarray_selafin_file(
        path, mesh, bed=bed, float_size=float_size, endian=endian, origin=origin
    )
    # the .cli beside it: write_selafin's lines, with comments after column 13
    lines = (tmp_path / "ours.cli").read_text().splitlines()
    (tmp_path / "theirs.cli").write_text("".join(f"{s} # edge\n" for s in lines))
    back = read_selafin_mesh(path, crs="EPSG:32630")
    with xr.open_dataset(path, engine="selafin") as ds:
        assert ds.attrs["float_size"] == float_size and ds.attrs["endian"] == endian
        assert ds.attrs["date_start"] == (2020, 1, 1, 0, 0, 0)
        np.testing.assert_array_equal(back.points[:, 0], ds["x"].values)
        np.testing.assert_array_equal(back.points[:, 1], ds["y"].values)
        np.testing.assert_array_equal(back.triangles, ds.attrs["ikle2"] - 1)
        (key,) = (k for k, (name, _) in ds.attrs["variables"].items() if name == bed)
        first = ds[key].isel(time=0).values
        np.testing.assert_array_equal(back.point_data["depth"], -first)
    atol = 1e-6 if float_size == 8 else 0.5  # float32 at 6500 km: 0.5 m apart
    np.testing.assert_allclose(back.points, mesh.points, rtol=0, atol=atol)
    assert edge_kinds(back) == edge_kinds(mesh)


def test_a_ring_listed_clockwise_is_turned_round(tmp_path):
    mesh = holes_mesh()
    write_selafin(tmp_path / "m.slf", mesh)
    forward = read_selafin_mesh(tmp_path / "m.slf")
    cli = tmp_path / "m.cli"
    lines = cli.read_text().splitlines(keepends=True)
    outer = len(forward.boundary_edges) - 8  # two holes of 4 edges each
    cli.write_text("".join(lines[:outer][::-1] + lines[outer:]))
    back = read_selafin_mesh(tmp_path / "m.slf")
    directed = {tuple(e) for e in back.boundary_edges.tolist()}
    assert directed == {tuple(e) for e in forward.boundary_edges.tolist()}
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        forward.boundary_edges, forward.boundary_ids
    )


def test_no_cli_reads_the_outline_as_land_and_warns(tmp_path, mesh_with_islands):
    write_selafin(tmp_path / "m.slf", mesh_with_islands, cli=False)
    with pytest.warns(CoastmeshWarning, match=r"no boundary conditions file m\.cli"):
        back = read_selafin_mesh(tmp_path / "m.slf")
    assert set(edge_ids(back.boundary_edges, back.boundary_ids)) == set(
        edge_ids(mesh_with_islands.boundary_edges, mesh_with_islands.boundary_ids)
    )
    assert set(back.boundary_ids.tolist()) == {1}
    assert back.boundary_kinds == {1: "shoreline"}
    # the domain on the left, as the triangles run
    half = {tuple(t[[i, (i + 1) % 3]]) for t in back.triangles for i in range(3)}
    assert {tuple(e) for e in back.boundary_edges.tolist()} <= half


def patched(data, at, value):
    return data[:at] + struct.pack(">i", value) + data[at + 4 :]


@pytest.mark.parametrize(
    "broken,match",
    [
        (lambda d: d[:60], r"ends inside the title record"),
        (lambda d: d[: IKLE_AT + 40], r"ends inside the IKLE record"),
        (lambda d: d[:-2], r"ends inside the variable 'BOTTOM'"),
        (lambda d: patched(d, NDP_AT, 4), r"NDP = 4 nodes per element; only 2D"),
        (lambda d: patched(d, IKLE_AT, 31), r"element 1 has nodes \[31, "),
        (lambda d: patched(d, 88, 9), r"NBV1 NBV2 record \(byte 88\) holds 9 bytes"),
        (lambda d: d[:-1] + b"\x05", r"ends with the marker 5, not its byte count"),
        (lambda d: b"coastmesh mesh\n" + d, r"not a SELAFIN file"),
    ],
)
def test_broken_selafin_files(tmp_path, broken, match):
    path = tmp_path / "m.slf"
    write_selafin(path, strip_mesh(6, 5))
    path.write_bytes(broken(path.read_bytes()))
    with pytest.raises(FormatError, match=rf"m\.slf: .*{match}"):
        read_selafin_mesh(path)


COLUMNS = "LIHBOR LIUBOR LIVBOR HBOR UBOR VBOR AUBOR LITBOR TBOR ATBOR BTBOR N K"


def with_values(lines, at, **values):
    """The .cli lines, line ``at`` (from 0) with new values by column name."""
    words = lines[at].split()
    for column, value in values.items():
        words[COLUMNS.split().index(column)] = value
    return [*lines[:at], " ".join(words) + "\n", *lines[at + 1 :]]


CLI_BREAKS = {
    "beyond-npoin": (lambda ls: with_values(ls, 2, N="31"), "line 3: node N = 31"),
    "short-line": (
        lambda ls: [ls[0], ls[1].rsplit(maxsplit=1)[0] + "\n", *ls[2:]],
        "line 2 has 12 values",
    ),
    "not-a-number": (
        lambda ls: with_values(ls, 0, LIHBOR="x"),
        "line 1 .* not a number",
    ),
    "twice": (
        lambda ls: with_values(ls, 4, N=ls[1].split()[11]),
        "lines 2 and 5 both list node 2",
    ),
    "order": (lambda ls: [ls[1], ls[0], *ls[2:]], "lines 1 to 2 .* do not close"),
    "inside": (
        lambda ls: with_values(ls, 0, N="8"),
        "line 1: node 8 is not on the boundary",
    ),
}


@pytest.mark.parametrize("edit,match", CLI_BREAKS.values(), ids=CLI_BREAKS.keys())
def test_broken_cli_files(tmp_path, edit, match):
    write_selafin(tmp_path / "m.slf", strip_mesh(6, 5))
    cli = tmp_path / "m.cli"
    cli.write_text("".join(edit(cli.read_text().splitlines(keepends=True))))
    with pytest.raises(FormatError, match=rf"m\.cli: .*{match}"):
        read_selafin_mesh(tmp_path / "m.slf")


def test_a_ring_left_out_of_the_cli(tmp_path):
    write_selafin(tmp_path / "m.slf", holes_mesh())
    cli = tmp_path / "m.cli"
    lines = cli.read_text().splitlines(keepends=True)
    cli.write_text("".join(lines[:-4]))  # the second hole
    left_out = int(lines[-4].split()[11])
    with pytest.raises(
        FormatError,
        match=rf"m\.cli: 28 lines in 2 rings, but the mesh has 32 boundary edges: a "
        rf"ring is missing \(the first left out is node {left_out}\)",
    ):
        read_selafin_mesh(tmp_path / "m.slf")


def test_no_bed_variable_warns(tmp_path):
    mesh = strip_mesh(6, 5)
    write_selafin(tmp_path / "m.slf", mesh)
    data = (tmp_path / "m.slf").read_bytes()
    (tmp_path / "v.slf").write_bytes(data.replace(b"BOTTOM    ", b"VELOCITY U"))
    (tmp_path / "t.slf").write_bytes(data[: -(8 + 4 * len(mesh.points)) - 12])
    shutil.copy(tmp_path / "m.cli", tmp_path / "v.cli")
    shutil.copy(tmp_path / "m.cli", tmp_path / "t.cli")
    with pytest.warns(CoastmeshWarning, match=r"no variable BOTTOM or FOND among"):
        assert read_selafin_mesh(tmp_path / "v.slf").point_data == {}
    with pytest.warns(CoastmeshWarning, match=r"no time step, so no value of BOTTOM"):
        assert read_selafin_mesh(tmp_path / "t.slf").point_data == {}
