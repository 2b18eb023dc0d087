"""UGRID netCDF read back by xugrid; VTU read back by meshio."""

from __future__ import annotations

import meshio.vtu
import numpy as np
import pytest
import xarray as xr
import xugrid
from pyproj import CRS

from coastmesh.errors import FormatError, OutputExistsError
from coastmesh.io.ugrid import write_ugrid, write_vtu
from coastmesh.io.writers import MeshFormat
from coastmesh.types import Mesh


def grid_mesh(nx=5, ny=4, dx=100.0, x0=0.0, y0=0.0, crs="EPSG:32630"):
    """A structured grid split into triangles; south edges open (2), rest coast (1)."""
    ii, jj = np.meshgrid(np.arange(nx), np.arange(ny))
    points = np.column_stack([x0 + dx * ii.ravel(), y0 + dx * jj.ravel()])
    idx = (jj * nx + ii)[:-1, :-1].ravel()
    a, b, c, d = idx, idx + 1, idx + nx + 1, idx + nx
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    ring = np.concatenate(
        [
            np.arange(nx - 1),
            (nx - 1) + nx * np.arange(ny - 1),
            (ny - 1) * nx + np.arange(nx - 1, 0, -1),
            nx * np.arange(ny - 1, 0, -1),
        ]
    )
    edges = np.column_stack([ring, np.roll(ring, -1)])
    ids = np.where(np.arange(len(ring)) < nx - 1, 2, 1)
    n = len(points)
    return Mesh(
        points,
        tri,
        edges,
        ids,
        1,
        crs,
        {
            "depth": 10.0 + np.arange(n, dtype=float),
            "size": np.full(n, 100.0),
            "flow": np.arange(2 * n, dtype=float).reshape(n, 2),
        },
        {1: "main coast", 2: "sea"},
        {1: "shoreline", 2: "open"},
    )


def edge_ids(edges, ids):
    """Map each undirected edge to its id."""
    return {
        (min(a, b), max(a, b)): int(i)
        for (a, b), i in zip(np.asarray(edges).tolist(), ids, strict=True)
    }


def same_mesh(a, b):
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.boundary_edges, b.boundary_edges)
    for key in b.point_data:
        np.testing.assert_array_equal(a.point_data[key], b.point_data[key])


def test_xugrid_reads_the_mesh(tmp_path, write_read):
    mesh = grid_mesh()
    uds = write_read(
        tmp_path / "m.nc", write_ugrid, xugrid.open_dataset, mesh, same_mesh
    )
    grid = uds.ugrid.grid
    assert grid.n_node == len(mesh.points) and grid.n_face == len(mesh.triangles)
    np.testing.assert_array_equal(grid.face_node_connectivity, mesh.triangles)
    np.testing.assert_array_equal(grid.node_x, mesh.points[:, 0])
    np.testing.assert_array_equal(grid.node_y, mesh.points[:, 1])
    assert grid.crs == CRS("EPSG:32630")
    np.testing.assert_array_equal(uds["depth"].values, mesh.point_data["depth"])
    assert uds["depth"].attrs["positive"] == "down"
    assert uds["depth"].attrs["units"] == "m"
    np.testing.assert_array_equal(uds["flow"].values, mesh.point_data["flow"])
    # all the triangle edges: xugrid derives faces' edges and the boundary from them
    assert grid.n_edge == 4 * 4 + 5 * 3 + 4 * 3  # horizontal, vertical, diagonal
    found = edge_ids(grid.boundary_node_connectivity, np.zeros(14, dtype=int))
    assert set(found) == set(edge_ids(mesh.boundary_edges, mesh.boundary_ids))
    uds.close()


def test_boundary_ids_sit_on_the_boundary_edges(tmp_path):
    mesh = grid_mesh()
    write_ugrid(tmp_path / "m.nc", mesh)
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        edges = ds["mesh2d_edge_nodes"].values
        ids = ds["boundary_id"].values
        attrs = ds["boundary_id"].attrs
    tagged = ids > 0
    assert edge_ids(edges[tagged], ids[tagged]) == edge_ids(
        mesh.boundary_edges, mesh.boundary_ids
    )
    assert len(np.unique(np.sort(edges, axis=1), axis=0)) == len(edges)
    assert attrs["flag_values"].tolist() == [0, 1, 2]
    assert attrs["flag_meanings"] == "interior main_coast sea"
    assert np.atleast_1d(attrs["open_boundary_ids"]).tolist() == [2]
    assert np.atleast_1d(attrs["shoreline_boundary_ids"]).tolist() == [1]


def test_topology_attributes(tmp_path):
    write_ugrid(tmp_path / "m.nc", grid_mesh())
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        topo = ds["mesh2d"].attrs
        assert topo["cf_role"] == "mesh_topology"
        assert topo["topology_dimension"] == 2
        assert topo["node_coordinates"] == "mesh2d_node_x mesh2d_node_y"
        for var, role in [
            ("mesh2d_face_nodes", "face_node_connectivity"),
            ("mesh2d_edge_nodes", "edge_node_connectivity"),
        ]:
            assert topo[role] == var
            assert ds[var].attrs["cf_role"] == role
            assert ds[var].attrs["start_index"] == 0
        assert ds["mesh2d_node_x"].attrs["standard_name"] == "projection_x_coordinate"
        assert ds["mesh2d_node_x"].attrs["units"] == "m"
        assert CRS.from_wkt(ds["mesh2d_crs"].attrs["crs_wkt"]) == CRS("EPSG:32630")
        assert ds["depth"].attrs["grid_mapping"] == "mesh2d_crs"
        assert "_FillValue" not in ds["mesh2d_node_x"].encoding
        assert ds.attrs["Conventions"] == "CF-1.8 UGRID-1.0"


def test_geographic_coordinates(tmp_path):
    write_ugrid(tmp_path / "g.nc", grid_mesh(dx=0.01, x0=-3.0, y0=58.0, crs=4326))
    with xr.open_dataset(tmp_path / "g.nc") as ds:
        assert ds["mesh2d_node_x"].attrs["standard_name"] == "longitude"
        assert ds["mesh2d_node_y"].attrs["units"] == "degrees_north"
    uds = xugrid.open_dataset(tmp_path / "g.nc")
    assert uds.ugrid.grid.crs == CRS("EPSG:4326")
    uds.close()


def test_unknown_crs_writes_no_grid_mapping(tmp_path):
    mesh = grid_mesh(crs=None)
    write_ugrid(tmp_path / "m.nc", mesh)
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        assert "mesh2d_crs" not in ds
        assert "standard_name" not in ds["mesh2d_node_x"].attrs


@pytest.mark.parametrize(
    ("point_data", "message"),
    [
        ({"boundary_id": np.zeros(20)}, "name of a mesh variable"),
        ({"label": np.array(["a"] * 20)}, "expected numbers"),
        ({"cube": np.zeros((20, 2, 2))}, "expected numbers of shape"),
    ],
)
def test_bad_point_data_is_refused(tmp_path, point_data, message):
    mesh = grid_mesh().with_point_data(**point_data)
    with pytest.raises(FormatError, match=message):
        write_ugrid(tmp_path / "m.nc", mesh)
    assert list(tmp_path.iterdir()) == []


def test_existing_file_is_kept(tmp_path):
    (tmp_path / "m.nc").write_text("keep")
    with pytest.raises(OutputExistsError, match="already exists"):
        write_ugrid(tmp_path / "m.nc", grid_mesh())
    assert (tmp_path / "m.nc").read_text() == "keep"
    write_ugrid(tmp_path / "m.nc", grid_mesh(), overwrite=True)
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        assert ds.sizes["mesh2d_nFaces"] == 24


def test_failed_write_leaves_nothing(tmp_path, monkeypatch):
    def broken(self, path, **kwargs):
        open(path, "w").close()
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", broken)
    with pytest.raises(OSError, match="disk full"):
        write_ugrid(tmp_path / "m.nc", grid_mesh())
    assert list(tmp_path.iterdir()) == []


def test_vtu_round_trip(tmp_path, write_read):
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


def test_vtu_without_boundary_edges_has_triangles_only(tmp_path):
    mesh = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 3, None)
    write_vtu(tmp_path / "t.vtu", mesh)
    back = meshio.vtu.read(tmp_path / "t.vtu")
    assert [c.type for c in back.cells] == ["triangle"]
    assert back.cell_data["physical"][0].tolist() == [3]


def test_vtu_existing_file_is_kept(tmp_path):
    (tmp_path / "m.vtu").write_text("keep")
    with pytest.raises(OutputExistsError):
        write_vtu(tmp_path / "m.vtu", grid_mesh())
    assert (tmp_path / "m.vtu").read_text() == "keep"


def test_registry_entries_are_accepted():
    assert MeshFormat("ugrid", (".nc",), write_ugrid, "UGRID").options == ()
    assert MeshFormat("vtu", (".vtu",), write_vtu, "VTU").options == ()
