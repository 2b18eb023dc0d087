"""msh files: round trips in 2.2 and 4.1, ASCII and binary, read by meshio and Gmsh."""

from __future__ import annotations

import meshio
import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from io_meshes import canonical, same_mesh, same_topology

from coastmesh.errors import FormatError, InputDataError, OutputExistsError
from coastmesh.io.meshes.msh import read_msh, write_msh
from coastmesh.meshing.engine import generate_mesh
from coastmesh.meshing.gmsh.model import gmsh_session
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

FORMATS = [("2.2", False), ("2.2", True), ("4.1", False), ("4.1", True)]


@pytest.fixture(scope="module")
def mesh():
    outer = np.array([[0, 0], [4000, 0], [4000, 3000], [0, 3000], [0, 0]], float)
    island = np.array(
        [[1500, 1000], [1500, 2000], [2500, 2000], [2500, 1000], [1500, 1000]], float
    )
    segments = (
        BoundarySegment(outer[0:3], "open", "sea", 2),
        BoundarySegment(outer[2:5], "shoreline", "coast", 1),
        BoundarySegment(island, "shoreline", "island", 4),
    )
    domain = Domain(
        shapely.Polygon(outer, [island]), segments, crs="EPSG:32630", surface_id=11
    )
    grid = SizeGrid([0.0, 4000.0], [0.0, 3000.0], [[200.0, 400.0], [200.0, 400.0]])
    return generate_mesh(domain, grid)


@pytest.mark.parametrize(("version", "binary"), FORMATS)
def test_round_trip(tmp_path, write_read, mesh, version, binary):
    path = tmp_path / f"mesh-{version}-{binary}.msh"
    back = write_read(
        path,
        lambda p, m: write_msh(p, m, version=version, binary=binary),
        read_msh,
        mesh,
        same_mesh,
    )
    assert back.crs is None
    if version == "2.2":
        same_topology(back, mesh)  # node and edge order survive as written
    else:
        for got, want in zip(canonical(back), canonical(mesh), strict=True):
            np.testing.assert_array_equal(got, want)
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


@pytest.mark.parametrize(("version", "binary"), FORMATS)
def test_meshio_reads_the_physical_tags(tmp_path, mesh, version, binary):
    path = tmp_path / "m.msh"
    write_msh(path, mesh, version=version, binary=binary)
    data = meshio.read(path)
    tags = {}
    for block, physical in zip(
        data.cells, data.cell_data["gmsh:physical"], strict=True
    ):
        tags.setdefault(block.type, []).append(np.asarray(physical))
    assert set(np.concatenate(tags["triangle"]).tolist()) == {11}
    lines = np.concatenate(tags["line"])
    assert sorted(lines.tolist()) == sorted(mesh.boundary_ids.tolist())
    assert sum(len(b.data) for b in data.cells if b.type == "triangle") == len(
        mesh.triangles
    )


@pytest.mark.parametrize(("version", "binary"), FORMATS)
def test_gmsh_reads_the_physical_groups(tmp_path, mesh, version, binary):
    path = tmp_path / "m.msh"
    write_msh(path, mesh, version=version, binary=binary)
    with gmsh_session() as gmsh:
        gmsh.open(str(path))
        groups = gmsh.model.getPhysicalGroups()
        counts = {}
        for dim, tag in groups:
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                _, elements, _ = gmsh.model.mesh.getElements(dim, entity)
                counts[(dim, tag)] = counts.get((dim, tag), 0) + sum(
                    len(e) for e in elements
                )
    ids, n = np.unique(mesh.boundary_ids, return_counts=True)
    expected = {(1, int(i)): int(c) for i, c in zip(ids, n, strict=True)}
    expected[(2, 11)] = len(mesh.triangles)
    assert counts == expected


def test_existing_file_is_kept_unless_overwrite(tmp_path, mesh):
    path = tmp_path / "m.msh"
    path.write_text("keep")
    with pytest.raises(OutputExistsError):
        write_msh(path, mesh)
    assert path.read_text() == "keep"
    write_msh(path, mesh, overwrite=True)
    assert read_msh(path).surface_id == 11


def test_unknown_version_writes_nothing(tmp_path, mesh):
    with pytest.raises(FormatError, match=r"pick one of 2\.2, 4\.1"):
        write_msh(tmp_path / "m.msh", mesh, version="3.0")
    assert list(tmp_path.iterdir()) == []


def test_reading_bad_files(tmp_path):
    with pytest.raises(InputDataError, match="file not found"):
        read_msh(tmp_path / "missing.msh")
    junk = tmp_path / "junk.msh"
    junk.write_text("not a mesh\n")
    with pytest.raises(FormatError, match=r"junk\.msh"):
        read_msh(junk)
    untagged = tmp_path / "untagged.msh"
    untagged.write_text(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
        "3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n"
    )
    with pytest.raises(FormatError, match=r"untagged\.msh: some elements have no"):
        read_msh(untagged)


def test_crs_is_attached_on_read(tmp_path, mesh):
    path = tmp_path / "m.msh"
    write_msh(path, mesh)
    assert read_msh(path, crs="EPSG:32630").crs.to_epsg() == 32630


@pytest.mark.parametrize("version", ["2.2", "4.1"])
def test_reads_a_file_written_by_gmsh(tmp_path, version):
    path = tmp_path / "gmsh.msh"
    with gmsh_session() as gmsh:
        gmsh.model.occ.addRectangle(0, 0, 0, 3, 2)
        gmsh.model.occ.synchronize()
        curves = [tag for _, tag in gmsh.model.getEntities(1)]
        gmsh.model.addPhysicalGroup(1, curves[:2], tag=3)
        gmsh.model.addPhysicalGroup(1, curves[2:], tag=4)
        gmsh.model.addPhysicalGroup(2, [1], tag=8)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", float(version))
        gmsh.write(str(path))
        _, triangles = gmsh.model.mesh.getElementsByType(2)
        n_lines = {
            pid: sum(
                len(gmsh.model.mesh.getElementsByType(1, c)[0])
                for c in gmsh.model.getEntitiesForPhysicalGroup(1, pid)
            )
            for pid in (3, 4)
        }
    mesh = read_msh(path)
    assert mesh.surface_id == 8
    assert len(mesh.triangles) == len(triangles) // 3
    assert {int(i): int((mesh.boundary_ids == i).sum()) for i in (3, 4)} == n_lines
    used = mesh.points[np.unique(mesh.triangles)]
    assert used.min(axis=0).tolist() == [0, 0] and used.max(axis=0).tolist() == [3, 2]


@pytest.mark.parametrize("version", ["2.2", "4.1"])
def test_one_edge_boundaries_and_all_boundary_nodes(tmp_path, version):
    """msh 4.1 needs a node per entity: one-edge ids and no interior node."""
    m = Mesh(
        [[0, 0], [1, 0], [1, 1], [0, 1]],
        [[0, 1, 2], [0, 2, 3]],
        [[0, 1], [1, 2], [2, 3], [3, 0]],
        [5, 6, 6, 7],
        3,
        None,
    )
    write_msh(tmp_path / "m.msh", m, version=version)
    back = read_msh(tmp_path / "m.msh")

    def by_coordinates(mesh):
        return {
            tuple(sorted(mesh.points[edge].ravel())): pid
            for edge, pid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True)
        }

    assert by_coordinates(back) == by_coordinates(m)
    assert back.surface_id == 3


def test_boundary_names_and_kinds_round_trip(tmp_path):
    m = Mesh(
        [[0, 0], [1, 0], [0, 1]],
        [[0, 1, 2]],
        [[0, 1], [1, 2], [2, 0]],
        [1, 1, 2],
        7,
        None,
        boundary_names={1: "coast", 2: "north"},
        boundary_kinds={1: "shoreline", 2: "open"},
    )
    write_msh(tmp_path / "m.msh", m, version="2.2")
    text = (tmp_path / "m.msh").read_text()
    assert '1 2 "open:north"' in text and '2 7 "domain"' in text
    back = read_msh(tmp_path / "m.msh")
    assert back.boundary_names == {1: "coast", 2: "north"}
    assert back.boundary_kinds == {1: "shoreline", 2: "open"}


@settings(deadline=None, max_examples=30)
@given(
    n=st.integers(3, 400),
    ids=st.lists(st.integers(1, 9), min_size=1, max_size=4),
    named=st.booleans(),
    scale=st.sampled_from([1e-9, 1.0, 7.3e5, -3.2e7]),
    seed=st.integers(0, 2**16),
)
def test_ascii_22_is_the_bytes_meshio_writes(
    tmp_path_factory, n, ids, named, scale, seed
):
    # the block writer against meshio's row-by-row writer: the same file
    import meshio.gmsh

    from coastmesh.io.meshes.msh import _to_meshio

    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n, 2)) * scale
    triangles = rng.integers(0, n, size=(2 * n, 3))
    chain = rng.permutation(n)[: n // 2 + 2]  # a chain of edges, an id per stretch
    edges = np.column_stack([chain[:-1], chain[1:]])
    edge_ids = np.sort(np.array(ids)[rng.integers(0, len(ids), len(edges))])
    names = {i: f"b{i}" for i in ids} if named else {}
    kinds = dict.fromkeys(ids[:1], "open") if named else {}
    m = Mesh(points, triangles, edges, edge_ids, 5, None, {}, names, kinds)
    folder = tmp_path_factory.mktemp("msh")
    write_msh(folder / "ours.msh", m)
    meshio.gmsh.write(folder / "meshio.msh", _to_meshio(meshio, m), "2.2", binary=False)
    assert (folder / "ours.msh").read_bytes() == (folder / "meshio.msh").read_bytes()


@settings(deadline=None, max_examples=50)
@given(
    rows=st.lists(
        st.tuples(
            st.integers(0, 2**40), st.integers(0, 10**6), st.sampled_from([0, 9, 10])
        ),
        min_size=1,
        max_size=60,
    ),
    text=st.sampled_from(["%d 2 2 7 1 %d %d\n", "%d %d %d\n", "x%d y%d z%d\n"]),
)
def test_integer_rows_are_what_percent_d_writes(rows, text):
    # the vectorised writer of integer rows against Python's own %d
    import io

    from coastmesh.io.meshes.msh import _write_rows

    columns = [np.array(c, dtype=np.int64) for c in zip(*rows, strict=True)]
    out = io.BytesIO()
    _write_rows(out, text, *columns)
    assert out.getvalue() == "".join(text % r for r in rows).encode()
