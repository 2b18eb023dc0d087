"""ADCIRC fort.14 and SCHISM hgrid.gr3: written, then parsed line by line."""

from __future__ import annotations

import itertools
import re
import warnings

import numpy as np
import pytest
from io_meshes import cell_mesh as grid_mesh
from io_meshes import edge_ids, signed_areas

from coastmesh.errors import (
    CoastmeshWarning,
    ConfigError,
    FormatError,
    InputDataError,
    OutputExistsError,
)
from coastmesh.io.meshes.adcirc import (
    _write,
    read_fort14,
    read_fort14_mesh,
    write_fort14,
    write_gr3,
)
from coastmesh.types import Mesh

WRITERS = [("fort.14", write_fort14), ("hgrid.gr3", write_gr3)]


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
    # mainland starts where it meets the open boundary, runs counter-clockwise;
    # essential no-normal-flow types by default (0 external, 1 island)
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
def test_island_of_two_ids_is_one_island_segment(tmp_path, name, writer):
    """ADCIRC and SCHISM take an island as one segment, whatever its ids."""

    def ids(p, q):
        found = south_open(p, q)
        if found == 3 and min(p[1], q[1]) >= 1 and p[1] == q[1] == 2:
            return 4  # the north side of the hole
        return found

    mesh = grid_mesh(
        4,
        {(1, 1)},
        ids,
        {**KINDS, 4: "shoreline"},
        names={1: "coast", 2: "south", 3: "rock", 4: "reef"},
    )
    writer(tmp_path / name, mesh)
    grid = read_fort14(tmp_path / name)
    land = grid["land_boundaries"]
    island = land[1]["nodes"].tolist()
    assert [b["ibtype"] for b in land] == [0, 1]
    if name == "fort.14":
        assert island[0] == island[-1]  # closed by repeating the first node
        island = island[:-1]
    else:
        assert island[0] != island[-1]  # SCHISM: not repeated
    assert same_cycle(island, ISLAND_CW)
    # the ids of its edges are in the comment, and read back
    assert (
        "id 3 rock; id 4 @" in land[1]["comment"]
        or "id 4 reef; id 3 @" in (land[1]["comment"])
    )
    back = read_fort14_mesh(tmp_path / name, crs="EPSG:32630")
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        mesh.boundary_edges, mesh.boundary_ids
    )
    assert back.boundary_names == mesh.boundary_names


@pytest.fixture(scope="module")
def generated(mesh_with_islands):
    """The shared square with two islands (tests/conftest.py), with depth."""
    return mesh_with_islands


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_generated_mesh_covers_every_boundary_edge_once(
    tmp_path, generated, name, writer
):
    writer(tmp_path / name, generated)
    grid = read_fort14(tmp_path / name)
    np.testing.assert_array_equal(grid["elements"], generated.triangles + 1)
    want = edge_ids(generated.boundary_edges, generated.boundary_ids)
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
    real = _write.write_table
    calls = []

    def failing(handle, columns):
        calls.append(1)
        real(handle, columns)
        if len(calls) == 2:  # after the nodes and elements
            raise RuntimeError("disk full")

    monkeypatch.setattr(_write, "write_table", failing)
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
    with pytest.raises(FormatError, match="nan at node 3 \\(1 nodes are not finite\\)"):
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


# --- reading into a Mesh ------------------------------------------------------


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_mesh_read_back_has_ids_names_kinds_depth_and_crs(
    tmp_path, square, name, writer
):
    writer(tmp_path / name, square)
    back = read_fort14_mesh(tmp_path / name)
    np.testing.assert_array_equal(back.points, square.points)
    np.testing.assert_array_equal(back.triangles, square.triangles)
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        square.boundary_edges, square.boundary_ids
    )
    assert back.boundary_names == {1: "coast", 2: "south", 3: "rock"}
    assert back.boundary_kinds == KINDS
    np.testing.assert_allclose(back.point_data["depth"], square.point_data["depth"])
    assert back.crs.to_epsg() == 32630


@pytest.mark.parametrize(("name", "writer"), WRITERS)
def test_files_without_id_comments_number_the_segments(tmp_path, square, name, writer):
    """Other tools write no comments: one id per segment, open ones first."""
    writer(tmp_path / name, square, title="from another tool")
    text = (tmp_path / name).read_text()
    (tmp_path / name).write_text(re.sub(r" *=[^\n]*", "", text))
    grid = read_fort14(tmp_path / name)
    back = read_fort14_mesh(tmp_path / name)
    assert back.crs is None and back.boundary_names == {}
    segments = grid["open_boundaries"] + grid["land_boundaries"]
    assert sorted(set(back.boundary_ids.tolist())) == list(range(1, len(segments) + 1))
    assert back.boundary_kinds == {
        k: "open" if k <= grid["nope"] else "shoreline"
        for k in range(1, len(segments) + 1)
    }
    # the same edges, the island (SCHISM: not closed by repetition) closed too
    assert set(edge_ids(back.boundary_edges, back.boundary_ids)) == set(
        edge_ids(square.boundary_edges, square.boundary_ids)
    )
    crs = read_fort14_mesh(tmp_path / name, crs="EPSG:32630").crs
    assert crs.to_epsg() == 32630


def test_reading_fort14_written_by_hand(tmp_path):
    """Clockwise elements, a land segment of IBTYPE 20, DP up."""
    path = tmp_path / "fort.14"
    path.write_text(
        "made by hand\n2 4\n1 0 0 -1\n2 1 0 -2\n3 1 1 -3\n4 0 1 -4\n"
        "1 3 1 3 2\n2 3 1 4 3\n"  # both clockwise
        "1\n2\n2 0\n1\n2\n"  # one open segment: 1 -> 2
        "1\n4\n4 20\n2\n3\n4\n1\n"  # land: 2 -> 3 -> 4 -> 1, type 20
    )
    back = read_fort14_mesh(path, positive="up", crs="EPSG:32630")
    assert back.triangles.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert (signed_areas(back) > 0).all()
    assert back.boundary_edges.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    assert back.boundary_ids.tolist() == [1, 2, 2, 2]
    assert back.boundary_kinds == {1: "open", 2: "shoreline"}
    assert back.point_data["depth"].tolist() == [1.0, 2.0, 3.0, 4.0]


@pytest.mark.parametrize(
    ("land", "match"),
    [
        ("1\n2\n2 24\n1\n2\n", "land segment 1 has IBTYPE 24, an internal barrier"),
        (
            "1\n2\n2 0 = Number of nodes for land boundary 1: id 1 coast\n3\n4\n",
            "boundary id 1 is on both an open and a land segment",
        ),
    ],
)
def test_mesh_reader_refuses_what_a_mesh_cannot_hold(tmp_path, land, match):
    path = tmp_path / "fort.14"
    path.write_text(
        "t\n2 4\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n1 3 1 2 3\n2 3 1 3 4\n"
        "1\n2\n2 0 = Number of nodes for open boundary 1: id 1 sea\n1\n2\n" + land
    )
    with pytest.raises(InputDataError, match=match):
        read_fort14_mesh(path)
    read_fort14(path)  # the raw parse reads it


def test_mesh_reader_needs_nodes_in_order_and_a_sign(tmp_path, square):
    write_fort14(tmp_path / "fort.14", square)
    with pytest.raises(ConfigError, match="positive='sideways'"):
        read_fort14_mesh(tmp_path / "fort.14", positive="sideways")
    lines = (tmp_path / "fort.14").read_text().splitlines()
    lines[3] = "7" + lines[3].lstrip()[1:]  # node 2 numbered 7
    (tmp_path / "fort.14").write_text("\n".join(lines) + "\n")
    with pytest.raises(InputDataError, match="node line 2 has node number JN = 7"):
        read_fort14_mesh(tmp_path / "fort.14")
    write_gr3(tmp_path / "h.gr3", square)
    with pytest.raises(InputDataError, match="CRS is EPSG:32630, but crs=EPSG:4326"):
        read_fort14_mesh(tmp_path / "h.gr3", crs="EPSG:4326")


def test_natural_land_types_on_request(tmp_path, square):
    """``land="natural"``: ADCIRC's IBTYPE 20 and 21; anything else is refused."""
    write_fort14(tmp_path / "fort.14", square, land="natural")
    land = read_fort14(tmp_path / "fort.14")["land_boundaries"]
    assert [b["ibtype"] for b in land] == [20, 21]
    back = read_fort14_mesh(tmp_path / "fort.14")
    assert back.boundary_kinds == square.boundary_kinds
    with pytest.raises(ConfigError, match="land='weak'; expected one of"):
        write_fort14(tmp_path / "x.14", square, land="weak")
    assert not (tmp_path / "x.14").exists()
