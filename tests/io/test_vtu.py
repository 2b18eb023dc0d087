"""VTU: written, read back by meshio, and read into a Mesh."""

from __future__ import annotations

import meshio
import meshio.vtu
import numpy as np
import pytest
from io_meshes import same_mesh, strip_mesh

from coastmesh.errors import FormatError, OutputExistsError
from coastmesh.io import MeshFormat
from coastmesh.io.meshes.vtu import read_vtu, write_vtu
from coastmesh.types import Mesh


def grid_mesh():
    """A 5 x 4 node grid with depth, size and a 2-component flow on the nodes."""
    n = 20
    return strip_mesh(
        5,
        4,
        point_data={
            "depth": 10.0 + np.arange(n, dtype=float),
            "size": np.full(n, 100.0),
            "flow": np.arange(2 * n, dtype=float).reshape(n, 2),
        },
    )


def test_round_trip_through_meshio(tmp_path, write_read):
    mesh = grid_mesh()
    back = write_read(tmp_path / "m.vtu", write_vtu, meshio.vtu.read, mesh, same_mesh)
    np.testing.assert_array_equal(back.points[:, :2], mesh.points)
    assert (back.points[:, 2] == 0).all()
    assert [c.type for c in back.cells] == ["triangle", "line"]
    np.testing.assert_array_equal(back.cells[0].data, mesh.triangles)
    np.testing.assert_array_equal(back.cells[1].data, mesh.boundary_edges)
    assert (back.cell_data["physical"][0] == mesh.surface_id).all()
    np.testing.assert_array_equal(back.cell_data["physical"][1], mesh.boundary_ids)
    assert (back.cell_data["boundary_id"][0] == 0).all()
    np.testing.assert_array_equal(back.cell_data["boundary_id"][1], mesh.boundary_ids)
    for key in ("depth", "size", "flow"):
        np.testing.assert_array_equal(back.point_data[key], mesh.point_data[key])


def test_without_boundary_edges_has_triangles_only(tmp_path):
    mesh = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 3, None)
    write_vtu(tmp_path / "t.vtu", mesh)
    back = meshio.vtu.read(tmp_path / "t.vtu")
    assert [c.type for c in back.cells] == ["triangle"]
    assert back.cell_data["physical"][0].tolist() == [3]


def test_existing_file_is_kept(tmp_path):
    (tmp_path / "m.vtu").write_text("keep")
    with pytest.raises(OutputExistsError):
        write_vtu(tmp_path / "m.vtu", grid_mesh())
    assert (tmp_path / "m.vtu").read_text() == "keep"


def test_read_back_into_a_mesh(tmp_path):
    mesh = grid_mesh()
    write_vtu(tmp_path / "m.vtu", mesh)
    back = read_vtu(tmp_path / "m.vtu", crs="EPSG:32630")
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    np.testing.assert_array_equal(back.boundary_edges, mesh.boundary_edges)
    np.testing.assert_array_equal(back.boundary_ids, mesh.boundary_ids)
    for key in ("depth", "size", "flow"):
        np.testing.assert_array_equal(back.point_data[key], mesh.point_data[key])
    assert back.crs == mesh.crs and back.boundary_names == {}


def test_reads_a_file_meshio_wrote(tmp_path):
    """An independent writer, without coastmesh's cell data."""
    points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]
    written = meshio.Mesh(
        points,
        [("triangle", [[0, 1, 2], [1, 3, 2]]), ("line", [[0, 1], [1, 3]])],
        point_data={"depth": [1.0, 2.0, 3.0, 4.0]},
    )
    meshio.vtu.write(tmp_path / "other.vtu", written)
    back = read_vtu(tmp_path / "other.vtu")
    assert back.triangles.tolist() == [[0, 1, 2], [1, 3, 2]]
    assert back.boundary_ids.tolist() == [1, 1] and back.surface_id == 1
    assert back.point_data["depth"].tolist() == [1.0, 2.0, 3.0, 4.0]
    assert back.crs is None


def test_reader_refuses_what_is_not_a_flat_triangle_mesh(tmp_path):
    lifted = meshio.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 5]], [("triangle", [[0, 1, 2]])])
    meshio.vtu.write(tmp_path / "lifted.vtu", lifted)
    with pytest.raises(FormatError, match="z != 0"):
        read_vtu(tmp_path / "lifted.vtu")
    lines = meshio.Mesh([[0, 0, 0], [1, 0, 0]], [("line", [[0, 1]])])
    meshio.vtu.write(tmp_path / "lines.vtu", lines)
    with pytest.raises(FormatError, match="no triangles"):
        read_vtu(tmp_path / "lines.vtu")
    (tmp_path / "junk.vtu").write_text("<VTKFile")
    with pytest.raises(FormatError, match=r"junk\.vtu: not a readable VTU file"):
        read_vtu(tmp_path / "junk.vtu")


def test_registry_entry_is_accepted():
    assert MeshFormat("vtu", (".vtu",), write_vtu, "VTU", read=read_vtu).options == ()
