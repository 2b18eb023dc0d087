"""ADCIRC fort.14 and SCHISM hgrid.gr3: written, then parsed line by line."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

from coastmesh.errors import (
    CoastmeshWarning,
    ConfigError,
    FormatError,
    InputDataError,
    OutputExistsError,
)
from coastmesh.io import adcirc
from coastmesh.io.adcirc import read_fort14, write_fort14, write_gr3
from coastmesh.types import Mesh

WRITERS = [("fort.14", write_fort14), ("hgrid.gr3", write_gr3)]


def grid_mesh(n, holes, edge_id, kinds, *, depth=True, crs="EPSG:32630"):
    """An n x n square of unit cells, two ccw triangles each, minus ``holes``.

    Node (i, j) has index j * (n + 1) + i and coordinates (i, j); each boundary
    edge gets ``edge_id((x0, y0), (x1, y1))``.
    """
    xs, ys = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
    points = np.column_stack([xs.ravel(), ys.ravel()])
    triangles = []
    for j in range(n):
        for i in range(n):
            if (i, j) in holes:
                continue
            a = j * (n + 1) + i
            triangles += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    triangles = np.array(triangles)
    count = {}
    for tri in triangles:
        for a, b in zip(tri, np.roll(tri, -1), strict=True):
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    edges = np.array(sorted(k for k, c in count.items() if c == 1))
    ids = [edge_id(tuple(points[a]), tuple(points[b])) for a, b in edges]
    point_data = {"depth": 10.0 + points[:, 0] + 2.5 * points[:, 1]} if depth else {}
    return Mesh(
        points,
        triangles,
        edges,
        ids,
        1,
        crs,
        point_data,
        {1: "coast", 2: "south", 3: "rock", 4: "reef"},
        kinds,
    )


def south_open(p, q):
    """South side open (2), rest of the exterior coast (1), the hole rock (3)."""
    if p[1] == q[1] == 0:
        return 2
    if p[0] == q[0] and p[0] in (0, 4):
        return 1  # west or east side
    if p[1] == q[1] == 4:
        return 1  # north side
    return 3


KINDS = {1: "shoreline", 2: "open", 3: "shoreline"}


@pytest.fixture(scope="module")
def square():
    """4 x 4 cells with a 1-cell hole at cell (1, 1); open boundary on the south."""
    return grid_mesh(4, {(1, 1)}, south_open, KINDS)


def node(x, y, n=4):
    return y * (n + 1) + x


# expected node strings, from the coordinates (1-based)
OPEN = [node(x, 0) + 1 for x in range(5)]  # west to east: domain on the left
MAINLAND = (
    [node(4, y) + 1 for y in range(5)]
    + [node(x, 4) + 1 for x in (3, 2, 1, 0)]
    + [node(0, y) + 1 for y in (3, 2, 1, 0)]
)
ISLAND_CW = [node(1, 1) + 1, node(1, 2) + 1, node(2, 2) + 1, node(2, 1) + 1]


def same_cycle(got, want):
    """Whether ``got`` is ``want`` rotated (a closed ring listed from any node)."""
    got, want = list(got), list(want)
    if len(got) != len(want) or want[0] not in got:
        return False
    k = got.index(want[0])
    return got[k:] + got[:k] == want


def signed_area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def lines_of(path):
    return path.read_text().splitlines()


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_nodes_elements_and_depth(tmp_path, square, name, writer):
    path = tmp_path / name
    writer(path, square)
    grid = read_fort14(path)
    n, m = len(square.points), len(square.triangles)
    assert (grid["ne"], grid["np"]) == (m, n)
    np.testing.assert_array_equal(grid["node_ids"], np.arange(1, n + 1))
    np.testing.assert_allclose(grid["xy"], square.points, atol=1e-12)
    np.testing.assert_allclose(grid["depth"], square.point_data["depth"], atol=1e-12)
    np.testing.assert_array_equal(grid["element_ids"], np.arange(1, m + 1))
    assert (grid["nhy"] == 3).all()
    np.testing.assert_array_equal(grid["elements"], square.triangles + 1)
    assert grid["title"] == "coastmesh EPSG:32630"


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_positive_up_negates_the_depth(tmp_path, square, name, writer):
    writer(tmp_path / name, square, positive="up")
    got = read_fort14(tmp_path / name)["depth"]
    np.testing.assert_allclose(got, -square.point_data["depth"], atol=1e-12)
    assert (got < 0).all()


def test_fort14_boundaries(tmp_path, square):
    path = tmp_path / "fort.14"
    write_fort14(path, square)
    grid = read_fort14(path)
    assert grid["nope"] == len(grid["open_boundaries"]) == 1
    (sea,) = grid["open_boundaries"]
    assert sea["nodes"].tolist() == OPEN and sea["ibtypee"] == 0
    assert grid["neta"] == sum(len(b["nodes"]) for b in grid["open_boundaries"]) == 5
    assert grid["nbou"] == len(grid["land_boundaries"]) == 2
    mainland, island = grid["land_boundaries"]
    # mainland starts where it meets the open boundary, runs counter-clockwise
    assert mainland["nodes"].tolist() == MAINLAND and mainland["ibtype"] == 0
    # island: IBTYPE 1, closed by repeating its first node, clockwise
    assert island["ibtype"] == 1
    assert island["nodes"][0] == island["nodes"][-1]
    assert same_cycle(island["nodes"][:-1], ISLAND_CW)
    assert signed_area(square.points[island["nodes"][:-1] - 1]) < 0
    assert grid["nvel"] == sum(len(b["nodes"]) for b in grid["land_boundaries"])
    assert grid["nvel"] == 13 + 5
    assert grid["trailing_lines"] == 0


def test_gr3_boundaries(tmp_path, square):
    path = tmp_path / "hgrid.gr3"
    write_gr3(path, square)
    grid = read_fort14(path)
    (sea,) = grid["open_boundaries"]
    assert sea["nodes"].tolist() == OPEN
    assert sea["ibtypee"] is None  # SCHISM: the count alone
    mainland, island = grid["land_boundaries"]
    assert mainland["nodes"].tolist() == MAINLAND and mainland["ibtype"] == 0
    # SCHISM: flag 1, the last island node differs from the first
    assert island["ibtype"] == 1 and island["nodes"][0] != island["nodes"][-1]
    assert same_cycle(island["nodes"], ISLAND_CW)
    assert (grid["neta"], grid["nvel"]) == (5, 13 + 4)
    assert grid["trailing_lines"] == 0


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_counts_match_the_lines_of_the_file(tmp_path, square, name, writer):
    """Check the header counts against the file itself, not through the parser."""
    path = tmp_path / name
    writer(path, square)
    lines = lines_of(path)
    m, n = (int(v) for v in lines[1].split()[:2])
    at = 2 + n + m
    nope, neta = int(lines[at].split()[0]), int(lines[at + 1].split()[0])
    at += 2
    seen = 0
    for _ in range(nope):
        count = int(lines[at].split()[0])
        seen += count
        assert all(len(line.split()) == 1 for line in lines[at + 1 : at + 1 + count])
        at += 1 + count
    assert seen == neta
    nbou, nvel = int(lines[at].split()[0]), int(lines[at + 1].split()[0])
    at += 2
    seen = 0
    for _ in range(nbou):
        count = int(lines[at].split()[0])
        seen += count
        at += 1 + count
    assert seen == nvel
    assert at == len(lines)  # nothing left over: every count was right
    assert "= Number of open boundaries" in lines[2 + n + m]
    assert "= Total number of land boundary nodes" in path.read_text()


def test_open_boundary_comment_names_the_id(tmp_path, square):
    write_fort14(tmp_path / "fort.14", square)
    text = (tmp_path / "fort.14").read_text()
    assert "5 0 = Number of nodes for open boundary 1: id 2 south" in text
    assert "= Number of nodes for land boundary 2: id 3 rock" in text


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_exterior_of_one_land_id(tmp_path, name):
    """No open boundary: ADCIRC closes the ring, SCHISM links two segments."""
    mesh = grid_mesh(2, set(), lambda p, q: 1, {1: "shoreline"})
    writer = write_fort14 if name == "fort.14" else write_gr3
    writer(tmp_path / name, mesh)
    grid = read_fort14(tmp_path / name)
    assert grid["nope"] == grid["neta"] == 0
    ring = [node(x, 0, 2) + 1 for x in (0, 1, 2)] + [node(2, 1, 2) + 1]
    ring += [node(x, 2, 2) + 1 for x in (2, 1, 0)] + [node(0, 1, 2) + 1]
    lists = [b["nodes"].tolist() for b in grid["land_boundaries"]]
    assert all(b["ibtype"] == 0 for b in grid["land_boundaries"])
    if name == "fort.14":
        (closed,) = lists
        assert closed[0] == closed[-1] and same_cycle(closed[:-1], ring)
    else:
        first, second = lists
        assert first[-1] == second[0] and second[-1] == first[0]
        assert same_cycle(first[:-1] + second[:-1], ring)
    assert grid["nvel"] == sum(map(len, lists))


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_island_of_two_ids_is_two_mainland_segments(tmp_path, name, writer):
    def ids(p, q):
        found = south_open(p, q)
        if found == 3 and min(p[1], q[1]) >= 1 and p[1] == q[1] == 2:
            return 4  # the north side of the hole
        return found

    mesh = grid_mesh(4, {(1, 1)}, ids, {**KINDS, 4: "shoreline"})
    writer(tmp_path / name, mesh)
    land = read_fort14(tmp_path / name)["land_boundaries"]
    assert [b["ibtype"] for b in land] == [0, 0, 0]
    first, second = (b["nodes"].tolist() for b in land[1:])
    assert first[-1] == second[0] and second[-1] == first[0]  # not closed, linked
    assert sorted([first, second], key=len) == [
        [node(1, 2) + 1, node(2, 2) + 1],
        [node(2, 2) + 1, node(2, 1) + 1, node(1, 1) + 1, node(1, 2) + 1],
    ]


@pytest.fixture(scope="module")
def generated(mesh_with_islands):
    """The shared square with two islands (tests/conftest.py), with depth."""
    return mesh_with_islands


def edge_ids(mesh):
    return {
        (min(a, b), max(a, b)): int(pid)
        for (a, b), pid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True)
    }


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_generated_mesh_covers_every_boundary_edge_once(
    tmp_path, generated, name, writer
):
    writer(tmp_path / name, generated)
    grid = read_fort14(tmp_path / name)
    np.testing.assert_array_equal(grid["elements"], generated.triangles + 1)
    want = edge_ids(generated)
    seen = {}
    parts = (("open", grid["open_boundaries"]), ("land", grid["land_boundaries"]))
    for kind, segments in parts:
        for segment in segments:
            nodes = segment["nodes"] - 1
            if name == "hgrid.gr3" and segment.get("ibtype") == 1:
                nodes = np.append(nodes, nodes[0])  # a SCHISM island closes itself
            for a, b in itertools.pairwise(nodes):
                key = (min(a, b), max(a, b))
                assert key in want, f"{key} is not a boundary edge"
                assert key not in seen, f"{key} listed twice"
                seen[key] = kind
    assert set(seen) == set(want)
    for key, kind in seen.items():
        assert kind == ("open" if want[key] == 2 else "land")
    ibtypes = [b["ibtype"] for b in grid["land_boundaries"]]
    assert ibtypes == [0, 1, 1]  # mainland first, then the two islands


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_missing_kind_names_the_id(tmp_path, square, name, writer):
    mesh = Mesh(
        square.points,
        square.triangles,
        square.boundary_edges,
        square.boundary_ids,
        1,
        square.crs,
        square.point_data,
        square.boundary_names,
        {1: "shoreline"},
    )
    match = r"id\(s\) 2 \('south'\), 3 \('rock'\) have no kind.*boundary_kinds="
    with pytest.raises(FormatError, match=match):
        writer(tmp_path / name, mesh)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_existing_file_is_kept_unless_overwrite(tmp_path, square, name, writer):
    path = tmp_path / name
    path.write_text("keep me")
    with pytest.raises(OutputExistsError, match="already exists"):
        writer(path, square)
    assert path.read_text() == "keep me"
    writer(path, square, overwrite=True)
    assert read_fort14(path)["np"] == len(square.points)


def test_failure_while_writing_leaves_no_file(tmp_path, square, monkeypatch):
    real = adcirc.write_table
    calls = []

    def failing(handle, columns):
        calls.append(1)
        real(handle, columns)
        if len(calls) == 2:  # after the nodes and elements
            raise RuntimeError("disk full")

    monkeypatch.setattr(adcirc, "write_table", failing)
    with pytest.raises(RuntimeError, match="disk full"):
        write_fort14(tmp_path / "fort.14", square)
    assert list(tmp_path.iterdir()) == []  # no file, no staging folder


def test_missing_depth_writes_zeros_with_a_warning(tmp_path):
    mesh = grid_mesh(2, set(), lambda p, q: 1, {1: "shoreline"}, depth=False)
    with pytest.warns(CoastmeshWarning, match="no point_data\\['depth'\\]") as caught:
        write_fort14(tmp_path / "fort.14", mesh)
    assert len(caught) == 1
    assert caught[0].filename == __file__  # points at the caller
    assert (read_fort14(tmp_path / "fort.14")["depth"] == 0).all()


def test_bad_depth_and_options_are_refused(tmp_path, square):
    depth = square.point_data["depth"].copy()
    depth[3] = np.nan
    bad = square.with_point_data(depth=depth)
    with pytest.raises(FormatError, match="not finite at 1 nodes \\(first: node 3\\)"):
        write_fort14(tmp_path / "fort.14", bad)
    with pytest.raises(ConfigError, match="positive='sideways'"):
        write_fort14(tmp_path / "fort.14", square, positive="sideways")
    with pytest.raises(ConfigError, match="one line"):
        write_gr3(tmp_path / "hgrid.gr3", square, title="two\nlines")
    assert list(tmp_path.iterdir()) == []


def test_geographic_coordinates_keep_their_digits(tmp_path, square):
    lonlat = Mesh(
        square.points * 1e-3 + [-3.123456789012, 58.987654321098],
        square.triangles,
        square.boundary_edges,
        square.boundary_ids,
        1,
        "EPSG:4326",
        square.point_data,
        square.boundary_names,
        KINDS,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_fort14(tmp_path / "fort.14", lonlat, title="Orkney test")
    grid = read_fort14(tmp_path / "fort.14")
    np.testing.assert_allclose(grid["xy"], lonlat.points, rtol=0, atol=1e-12)
    assert grid["title"] == "Orkney test"


def test_reader_rejects_a_short_segment(tmp_path):
    """A segment count larger than its node lines: the parser must not trust it."""
    path = tmp_path / "fort.14"
    path.write_text(
        "t\n1 3\n1 0 0 1\n2 1 0 1\n3 0 1 1\n1 3 1 2 3\n"
        "1 = NOPE\n3 = NETA\n3 0 = NVDLL\n1\n2\n0 = NBOU\n0 = NVEL\n"
    )
    with pytest.raises(InputDataError, match=r"line 12 \(NBDV\).*1\.\.NP"):
        read_fort14(path)
    path.write_text("t\n1 3\n1 0 0 1\n2 1 0 1\n")
    with pytest.raises(InputDataError, match="ends at line 4"):
        read_fort14(path)


def test_write_table_formats_columns():
    import io

    out = io.BytesIO()
    adcirc.write_table(
        out,
        [
            (np.array([1, 12, -3]), None),
            (np.array([-0.4e-15, 123.456, -7.0]), 6),
        ],
    )
    # right-aligned, a column for the sign, no "-0.000"
    assert out.getvalue().decode().splitlines() == [
        "  1    0.000",
        " 12  123.456",
        " -3   -7.000",
    ]
    rng = np.random.default_rng(5)
    values = rng.normal(0, 1e4, 2000)
    out = io.BytesIO()
    adcirc.write_table(out, [(values, 15)])
    text = out.getvalue().decode().splitlines()
    decimals = 15 - len(str(int(np.abs(values).max())))
    assert {len(line) for line in text} == {len(text[0])}  # one column width
    assert all(len(line.split(".")[1]) == decimals for line in text)
    back = np.array(text, dtype=float)
    # rounded to the decimals, within one unit in the last place
    assert np.abs(back - values).max() <= 10.0**-decimals
