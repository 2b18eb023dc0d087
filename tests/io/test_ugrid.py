"""UGRID netCDF: written and read by xugrid, and read back into a Mesh."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import xugrid
from io_meshes import edge_ids, same_mesh, strip_mesh
from pyproj import CRS

from coastmesh.errors import FormatError, InputDataError, OutputExistsError
from coastmesh.io import MeshFormat
from coastmesh.io.meshes.ugrid import read_ugrid, write_ugrid


def grid_mesh(nx=5, ny=4, dx=100.0, x0=0.0, y0=0.0, crs="EPSG:32630"):
    """A structured grid (:func:`io_meshes.strip_mesh`) with three node variables."""
    n = nx * ny
    return strip_mesh(
        nx,
        ny,
        dx=dx,
        x0=x0,
        y0=y0,
        crs=crs,
        point_data={
            "depth": 10.0 + np.arange(n, dtype=float),
            "size": np.full(n, 100.0),
            "flow": np.arange(2 * n, dtype=float).reshape(n, 2),
        },
        names={1: "main coast", 2: "sea"},
        kinds={1: "shoreline", 2: "open"},
    )


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


def test_registry_entry_is_accepted():
    fmt = MeshFormat("ugrid", (".nc",), write_ugrid, "UGRID", read=read_ugrid)
    assert fmt.options == () and fmt.read_options == ()


def test_reads_a_file_xugrid_wrote(tmp_path):
    """An independent writer: no boundary ids, fill values, xugrid's own names."""
    mesh = grid_mesh()
    grid = xugrid.Ugrid2d(
        mesh.points[:, 0],
        mesh.points[:, 1],
        -1,
        mesh.triangles,
        name="net2d",
        crs="EPSG:32630",
    )
    uds = xugrid.UgridDataset(grids=[grid])
    uds["depth"] = xugrid.UgridDataArray(
        xr.DataArray(
            -mesh.point_data["depth"],
            dims=[grid.node_dimension],
            attrs={"positive": "up"},
        ),
        grid,
    )
    uds.ugrid.to_netcdf(tmp_path / "x.nc")
    back = read_ugrid(tmp_path / "x.nc")
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    np.testing.assert_array_equal(back.point_data["depth"], mesh.point_data["depth"])
    # no boundary_id: the edges of one triangle, all id 1
    outline = edge_ids(mesh.boundary_edges, mesh.boundary_ids)
    assert edge_ids(back.boundary_edges, back.boundary_ids) == dict.fromkeys(outline, 1)
    assert back.boundary_kinds == {} and back.crs == CRS("EPSG:32630")


def test_read_back_keeps_ids_names_kinds_and_node_data(tmp_path):
    mesh = grid_mesh()
    write_ugrid(tmp_path / "m.nc", mesh)
    back = read_ugrid(tmp_path / "m.nc")
    assert edge_ids(back.boundary_edges, back.boundary_ids) == edge_ids(
        mesh.boundary_edges, mesh.boundary_ids
    )
    assert back.boundary_names == {1: "main_coast", 2: "sea"}
    assert back.boundary_kinds == mesh.boundary_kinds
    for key in ("depth", "size", "flow"):
        np.testing.assert_array_equal(back.point_data[key], mesh.point_data[key])
    write_ugrid(tmp_path / "plain.nc", grid_mesh(crs=None))
    assert read_ugrid(tmp_path / "plain.nc").crs is None
    assert read_ugrid(tmp_path / "plain.nc", crs=4326).crs == CRS("EPSG:4326")


def test_reader_errors_name_the_variable(tmp_path):
    write_ugrid(tmp_path / "m.nc", grid_mesh())
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        quads = ds.drop_vars("mesh2d_face_nodes").assign(
            mesh2d_face_nodes=(("mesh2d_nFaces", "four"), np.zeros((24, 4), int))
        )
        quads.to_netcdf(tmp_path / "quads.nc")
        ds.drop_vars("mesh2d").to_netcdf(tmp_path / "none.nc")
    with pytest.raises(InputDataError, match="'mesh2d_face_nodes' has shape"):
        read_ugrid(tmp_path / "quads.nc")
    with pytest.raises(InputDataError, match="has 0 2D mesh topologies"):
        read_ugrid(tmp_path / "none.nc")
    (tmp_path / "junk.nc").write_text("not netCDF")
    with pytest.raises(FormatError, match=r"junk\.nc: not a readable netCDF file"):
        read_ugrid(tmp_path / "junk.nc")
