"""A mesh as a GeoPackage: nodes, triangles and boundary edges, and read back."""

from __future__ import annotations

import numpy as np
import pyogrio
import pyogrio.raw
import pytest
import shapely
from io_meshes import jittered_grid, same_mesh, unit_square
from pyogrio.errors import DataLayerError
from pyproj import CRS

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io import read_mesh, write_mesh
from coastmesh.io.meshes.mesh_gpkg import _mesh_layers, read_mesh_gpkg
from coastmesh.io.vectors.domain_gpkg import write_layers
from coastmesh.types import Features, Mesh

square = pytest.fixture(unit_square, name="square")
jittered = pytest.fixture(jittered_grid, name="jittered")


def read_layer(path, layer):
    meta, _, wkb, columns = pyogrio.raw.read(path, layer=layer)
    return meta, shapely.from_wkb(wkb), dict(zip(meta["fields"], columns, strict=True))


def triangle_areas(mesh: Mesh) -> np.ndarray:
    """Shoelace area of each triangle, with plain numpy."""
    p = mesh.points[mesh.triangles]
    return 0.5 * np.abs(
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    )


@pytest.mark.parametrize("name", ["square", "jittered"])
def test_gpkg_round_trip(tmp_path, write_read, request, name):
    mesh = request.getfixturevalue(name)
    path = tmp_path / "mesh.gpkg"
    write_read(path, write_mesh, lambda p: None, mesh, same_mesh)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.gpkg"]
    layers = pyogrio.list_layers(path)[:, 0].tolist()
    assert layers == ["nodes", "triangles", "boundaries"]
    meta, points, fields = read_layer(path, "nodes")
    np.testing.assert_array_equal(shapely.get_coordinates(points), mesh.points)
    assert fields["id"].tolist() == list(range(len(mesh.points)))

    meta, polygons, fields = read_layer(path, "triangles")
    assert CRS.from_user_input(meta["crs"]) == CRS.from_epsg(32630)
    assert meta["geometry_type"] == "Polygon"
    assert len(polygons) == len(mesh.triangles)
    assert fields["id"].tolist() == list(range(len(mesh.triangles)))
    areas = triangle_areas(mesh)
    np.testing.assert_allclose(shapely.area(polygons), areas, rtol=1e-12)
    union = shapely.union_all(polygons)
    assert union.area == pytest.approx(areas.sum(), rel=1e-9)
    assert shapely.get_num_coordinates(polygons).tolist() == [4] * len(polygons)
    corners = shapely.get_coordinates(polygons).reshape(-1, 4, 2)[:, :3]
    np.testing.assert_array_equal(corners, mesh.points[mesh.triangles])

    meta, lines, fields = read_layer(path, "boundaries")
    assert meta["geometry_type"] == "LineString"
    assert len(lines) == len(mesh.boundary_edges)
    assert fields["physical_id"].tolist() == mesh.boundary_ids.tolist()
    ends = shapely.get_coordinates(lines).reshape(-1, 2, 2)
    np.testing.assert_array_equal(ends, mesh.points[mesh.boundary_edges])


def test_gpkg_metadata_and_no_crs(tmp_path, square):
    mesh = Mesh(
        square.points, square.triangles, square.boundary_edges, [1, 1, 2, 2], 3, None
    )
    path = tmp_path / "m.gpkg"
    write_mesh(path, mesh, metadata={"coastmesh": "test"})
    info = pyogrio.read_info(path, layer="triangles")
    assert info["dataset_metadata"] == {"coastmesh": "test"}
    assert info["crs"] is None
    assert info["features"] == 2


def test_gpkg_without_boundary_edges(tmp_path, square):
    mesh = Mesh(square.points, square.triangles, [], [], 1, "EPSG:4326")
    path = tmp_path / "m.gpkg"
    write_mesh(path, mesh)
    _, lines, fields = read_layer(path, "boundaries")
    assert len(lines) == 0
    assert fields["physical_id"].size == 0


def test_gpkg_failing_second_layer_leaves_nothing(tmp_path, square, monkeypatch):
    real = pyogrio.raw.write

    def fail_on_boundaries(path, *args, layer=None, **kwargs):
        if layer == "boundaries":
            raise DataLayerError("disk full")
        return real(path, *args, layer=layer, **kwargs)

    monkeypatch.setattr(pyogrio.raw, "write", fail_on_boundaries)
    with pytest.raises(FormatError, match=r"mesh.gpkg, layer 'boundaries'.*disk full"):
        write_mesh(tmp_path / "mesh.gpkg", square)
    assert list(tmp_path.iterdir()) == []

    old = tmp_path / "old.gpkg"
    old.write_bytes(b"previous")
    with pytest.raises(FormatError):
        write_mesh(old, square, overwrite=True)
    assert old.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == ["old.gpkg"]


def test_gpkg_nodes_carry_point_data_and_boundary_names(tmp_path, square):
    mesh = Mesh(
        square.points,
        square.triangles,
        square.boundary_edges,
        [1, 1, 2, 2],
        3,
        "EPSG:32630",
        {"depth": np.arange(len(square.points), dtype=float) * 2.5},
        {1: "coast", 2: "north"},
        {1: "shoreline", 2: "open"},
    )
    path = tmp_path / "m.gpkg"
    write_mesh(path, mesh)
    _, _, fields = read_layer(path, "nodes")
    np.testing.assert_array_equal(fields["depth"], mesh.point_data["depth"])
    _, _, fields = read_layer(path, "boundaries")
    assert fields["name"].tolist() == ["coast", "coast", "north", "north"]
    assert fields["kind"].tolist() == ["shoreline", "shoreline", "open", "open"]


@pytest.mark.parametrize("name", ["square", "jittered"])
def test_read_back_is_the_mesh(tmp_path, write_read, request, name):
    mesh = request.getfixturevalue(name)
    back = write_read(tmp_path / "m.gpkg", write_mesh, read_mesh, mesh, same_mesh)
    np.testing.assert_array_equal(back.points, mesh.points)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    np.testing.assert_array_equal(back.boundary_edges, mesh.boundary_edges)
    np.testing.assert_array_equal(back.boundary_ids, mesh.boundary_ids)
    assert back.crs == mesh.crs and back.surface_id == mesh.surface_id


def test_read_back_without_boundary_edges_or_crs(tmp_path, square):
    mesh = Mesh(square.points, square.triangles, [], [], 1, None)
    write_mesh(tmp_path / "m.gpkg", mesh)
    back = read_mesh_gpkg(tmp_path / "m.gpkg", crs="EPSG:4326")
    assert len(back.boundary_edges) == 0 and back.crs == CRS("EPSG:4326")


def test_reader_errors_name_the_layer(tmp_path, square):
    layers = _mesh_layers(square)
    write_layers(tmp_path / "two.gpkg", {k: layers[k] for k in ("nodes", "triangles")})
    with pytest.raises(InputDataError, match="no layer 'boundaries'"):
        read_mesh_gpkg(tmp_path / "two.gpkg")
    triangles = layers["triangles"]
    first, second = triangles.geometry
    moved = np.array([first, shapely.affinity.translate(second, 0.5)])
    layers["triangles"] = Features(
        moved, triangles.crs, triangles.fields, triangles.fids, "<memory>"
    )
    write_layers(tmp_path / "moved.gpkg", layers)
    with pytest.raises(InputDataError, match="layer 'triangles', feature 1: vertex"):
        read_mesh_gpkg(tmp_path / "moved.gpkg")
    (tmp_path / "junk.gpkg").write_text("junk")
    with pytest.raises(FormatError, match="not a vector file"):
        read_mesh_gpkg(tmp_path / "junk.gpkg")
