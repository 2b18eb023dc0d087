"""DHI MIKE .mesh: read back with mikeio; node codes decode to the boundary kinds."""

from __future__ import annotations

import numpy as np
import pytest
from io_meshes import cell_mesh, edge_ids

from coastmesh.errors import (
    CoastmeshWarning,
    FormatError,
    InputDataError,
    OutputExistsError,
)
from coastmesh.io.meshes import mike
from coastmesh.io.meshes.mike import read_mike_mesh, write_mike_mesh

N = 4  # cells per side


def node(x, y):
    return y * (N + 1) + x


def grid_mesh(edge_id, kinds, *, holes=((1, 1),), depth=True, crs="EPSG:32630"):
    """N x N unit cells minus ``holes`` (:func:`io_meshes.cell_mesh`), no names."""
    return cell_mesh(N, set(holes), edge_id, kinds, depth=depth, crs=crs, names={})


def south_open(p, q):
    """South side open (2), rest of the exterior coast (1), the hole rock (3)."""
    if p[1] == q[1] == 0:
        return 2
    if (p[0] == q[0] and p[0] in (0, N)) or p[1] == q[1] == N:
        return 1
    return 3


def south_and_east_open(p, q):
    """As :func:`south_open`, and the east side open with id 5."""
    if p[0] == q[0] == N:
        return 5
    return south_open(p, q)


KINDS = {1: "shoreline", 2: "open", 3: "shoreline", 5: "open"}


@pytest.fixture(scope="module")
def square():
    return grid_mesh(south_open, KINDS)


def read_nodes(path):
    """Parse the node lines of a .mesh file: ids, x, y, z, codes."""
    lines = path.read_text().splitlines()
    n = int(lines[0].split()[2])
    table = np.array([line.split() for line in lines[1 : n + 1]], dtype=float)
    return table[:, 0].astype(int), table[:, 1:3], table[:, 3], table[:, 4].astype(int)


def face_codes(mesh, codes):
    """Boundary face codes by MIKE's rule (DHI MIKECore-Examples MeshValidator).

    Faces run from node to node in each (counter-clockwise) element; a boundary
    face is land (1) if either node is 1, else it takes its to-node's code.
    """
    half = {}
    for tri in mesh.triangles:
        for a, b in zip(tri, np.roll(tri, -1), strict=True):
            half[(a, b)] = True
    out = {}
    for a, b in half:
        if (b, a) in half:
            continue  # internal face
        code = 1 if codes[a] == 1 or codes[b] == 1 else codes[b]
        out[(min(a, b), max(a, b))] = int(code)
    return out


def test_read_back_with_mikeio(tmp_path, square):
    mikeio = pytest.importorskip("mikeio")
    path = tmp_path / "square.mesh"
    assert write_mike_mesh(path, square) == {2: 2}
    msh = mikeio.Mesh(path)
    assert msh.n_nodes == len(square.points)
    assert msh.n_elements == len(square.triangles)
    np.testing.assert_allclose(msh.node_coordinates[:, :2], square.points, atol=1e-12)
    # z is elevation by default: -depth
    np.testing.assert_allclose(msh.zn, -square.point_data["depth"], atol=1e-12)
    np.testing.assert_array_equal(np.array(msh.element_table), square.triangles)
    codes = np.asarray(msh.codes)
    south = [node(x, 0) for x in range(N + 1)]
    assert (codes[south] == 2).all()  # the corners too: see face_codes
    boundary = np.unique(square.boundary_edges)
    land = np.setdiff1d(boundary, south)
    assert (codes[land] == 1).all()
    interior = np.setdiff1d(np.arange(len(square.points)), boundary)
    assert len(interior) == 5 and (codes[interior] == 0).all()
    assert sorted(msh.geometry.boundary_codes) == [1, 2]
    assert msh.geometry.projection_string.startswith('PROJCS["WGS_1984_UTM_Zone_30N"')
    assert not msh.geometry.is_geo


def test_header_and_element_lines(tmp_path, square):
    path = tmp_path / "square.mesh"
    write_mike_mesh(path, square)
    lines = path.read_text().splitlines()
    item, unit, n, projection = lines[0].split(maxsplit=3)
    assert (item, unit, int(n)) == ("100079", "1000", len(square.points))
    assert projection.startswith("PROJCS[")
    m = len(square.triangles)
    assert lines[1 + len(square.points)].split() == [str(m), "3", "21"]
    elements = np.array([line.split() for line in lines[2 + len(square.points) :]], int)
    np.testing.assert_array_equal(elements[:, 0], np.arange(1, m + 1))
    np.testing.assert_array_equal(elements[:, 1:], square.triangles + 1)
    ids, xy, _, _ = read_nodes(path)
    np.testing.assert_array_equal(ids, np.arange(1, len(square.points) + 1))
    np.testing.assert_allclose(xy, square.points, atol=1e-12)


def test_codes_decode_to_the_boundary_kinds(tmp_path):
    """Two open boundaries meeting at a corner, land between them elsewhere."""
    mesh = grid_mesh(south_and_east_open, KINDS)
    path = tmp_path / "two.mesh"
    codes_of = write_mike_mesh(path, mesh)
    assert codes_of == {2: 2, 5: 3}  # sorted open ids -> 2, 3, ...
    _, _, _, codes = read_nodes(path)
    want = {
        (min(a, b), max(a, b)): codes_of.get(int(pid), 1)
        for (a, b), pid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True)
    }
    assert face_codes(mesh, codes) == want
    # the south-east corner ends the south boundary (walking ccw): its code is 2
    assert codes[node(N, 0)] == 2 and codes[node(N, N)] == 3
    assert codes[node(0, 0)] == 2  # land meets open: the open code


def test_positive_down_writes_the_depth(tmp_path, square):
    path = tmp_path / "down.mesh"
    write_mike_mesh(path, square, positive="down")
    _, _, z, _ = read_nodes(path)
    np.testing.assert_allclose(z, square.point_data["depth"], atol=1e-12)


@pytest.mark.parametrize(
    ("crs", "crs_wkt", "expected"),
    [
        ("EPSG:4326", None, "LONG/LAT"),
        (None, None, "NON-UTM"),
        ("EPSG:32630", "UTM-30", "UTM-30"),
    ],
)
def test_projection_string(tmp_path, crs, crs_wkt, expected):
    mesh = grid_mesh(south_open, KINDS, crs=crs)
    path = tmp_path / "p.mesh"
    write_mike_mesh(path, mesh, crs_wkt=crs_wkt)
    assert path.read_text().splitlines()[0].split(maxsplit=3)[3] == expected


def test_geographic_mesh_is_geo_in_mikeio(tmp_path):
    mikeio = pytest.importorskip("mikeio")
    mesh = grid_mesh(south_open, KINDS, crs="EPSG:4326")
    write_mike_mesh(tmp_path / "ll.mesh", mesh)
    assert mikeio.Mesh(tmp_path / "ll.mesh").geometry.is_geo


def test_single_land_edge_between_open_boundaries_is_refused(tmp_path):
    def ids(p, q):
        if p[1] == q[1] == 0:
            return 2
        if p[0] == q[0] == N and min(p[1], q[1]) == 0:
            return 1  # one land edge at the bottom of the east side
        return 5 if p[0] == q[0] == N else south_open(p, q)

    mesh = grid_mesh(ids, KINDS)
    with pytest.raises(FormatError, match="land boundary of one edge between two open"):
        write_mike_mesh(tmp_path / "bad.mesh", mesh)
    assert list(tmp_path.iterdir()) == []


def test_missing_kind_names_the_id(tmp_path):
    mesh = grid_mesh(south_open, {1: "shoreline", 3: "shoreline"})
    with pytest.raises(FormatError, match=r"id\(s\) 2 have no kind.*boundary_kinds="):
        write_mike_mesh(tmp_path / "k.mesh", mesh)
    assert list(tmp_path.iterdir()) == []


def test_existing_file_is_kept_unless_overwrite(tmp_path, square):
    path = tmp_path / "square.mesh"
    path.write_text("keep me")
    with pytest.raises(OutputExistsError, match="already exists"):
        write_mike_mesh(path, square)
    assert path.read_text() == "keep me"
    write_mike_mesh(path, square, overwrite=True)
    assert path.read_text().startswith("100079 1000 ")


def test_failure_while_writing_leaves_no_file(tmp_path, square, monkeypatch):
    real = mike.write_table

    def failing(handle, columns):
        real(handle, columns)
        raise RuntimeError("disk full")

    monkeypatch.setattr(mike, "write_table", failing)
    with pytest.raises(RuntimeError, match="disk full"):
        write_mike_mesh(tmp_path / "square.mesh", square)
    assert list(tmp_path.iterdir()) == []


def test_missing_depth_writes_zeros_with_a_warning(tmp_path):
    mesh = grid_mesh(south_open, KINDS, depth=False)
    with pytest.warns(CoastmeshWarning, match="no point_data") as caught:
        write_mike_mesh(tmp_path / "z.mesh", mesh)
    assert len(caught) == 1 and caught[0].filename == __file__
    _, _, z, _ = read_nodes(tmp_path / "z.mesh")
    assert (z == 0).all()


def test_bad_crs_wkt_is_refused(tmp_path, square):
    with pytest.raises(FormatError, match="crs_wkt="):
        write_mike_mesh(tmp_path / "w.mesh", square, crs_wkt="two\nlines")
    assert list(tmp_path.iterdir()) == []


# --- reading ------------------------------------------------------------------


def test_read_back_matches_mikeio_and_the_face_rule(tmp_path):
    mikeio = pytest.importorskip("mikeio")
    mesh = grid_mesh(south_and_east_open, KINDS)
    path = tmp_path / "two.mesh"
    codes_of = write_mike_mesh(path, mesh)
    back = read_mike_mesh(path)
    other = mikeio.Mesh(path)
    np.testing.assert_allclose(back.points, other.node_coordinates[:, :2], atol=0)
    np.testing.assert_array_equal(back.triangles, np.array(other.element_table))
    np.testing.assert_allclose(back.point_data["depth"], -np.asarray(other.zn))
    _, _, _, codes = read_nodes(path)
    assert edge_ids(back.boundary_edges, back.boundary_ids) == face_codes(mesh, codes)
    assert set(back.boundary_ids.tolist()) == {1, *codes_of.values()}
    assert back.boundary_kinds == {1: "shoreline", 2: "open", 3: "open"}
    assert back.crs == mesh.crs and back.boundary_names == {}


@pytest.mark.parametrize(
    ("projection", "crs", "expected"),
    [("LONG/LAT", None, 4326), ("NON-UTM", None, None), ("UTM-30", 32630, 32630)],
)
def test_header_projection_gives_the_crs(tmp_path, square, projection, crs, expected):
    path = tmp_path / "p.mesh"
    write_mike_mesh(path, square, crs_wkt=projection)
    back = read_mike_mesh(path, crs=crs)
    assert (back.crs and back.crs.to_epsg()) == expected


def test_positive_down_reads_z_as_depth(tmp_path, square):
    write_mike_mesh(tmp_path / "d.mesh", square, positive="down")
    back = read_mike_mesh(tmp_path / "d.mesh", positive="down")
    np.testing.assert_allclose(back.point_data["depth"], square.point_data["depth"])


def test_reader_errors_name_the_line(tmp_path, square):
    path = tmp_path / "q.mesh"
    write_mike_mesh(path, square)
    lines = path.read_text().splitlines()
    header = 1 + len(square.points)
    quads = lines[:header] + [lines[header].replace(" 3 21", " 4 25")]
    path.write_text("\n".join(quads + lines[header + 1 :]) + "\n")
    with pytest.raises(InputDataError, match=rf"line {header + 1} \(NELEM NPE TYPE\)"):
        read_mike_mesh(path)
    water = [line.rsplit(" ", 1)[0] + " 0" for line in lines[1:header]]
    path.write_text("\n".join([lines[0], *water, *lines[header:]]) + "\n")
    with pytest.raises(InputDataError, match="code 0 \\(water\\) at both ends"):
        read_mike_mesh(path)
    path.write_text("100079 1000 x LONG/LAT\n")
    with pytest.raises(InputDataError, match=r"line 1 .*expected 3 integers"):
        read_mike_mesh(path)
