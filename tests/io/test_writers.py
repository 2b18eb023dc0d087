"""The mesh output format registry and its built-in formats: msh 2.2, msh 4.1, gpkg."""

from __future__ import annotations

import numpy as np
import pyogrio
import pyogrio.raw
import pytest
import shapely
from pyogrio.errors import DataLayerError
from pyproj import CRS

import coastmesh.io
from coastmesh.errors import ConfigError, FormatError, OutputExistsError
from coastmesh.io import writers
from coastmesh.io._atomic import atomic_write
from coastmesh.io.msh import read_msh
from coastmesh.io.writers import (
    MeshFormat,
    format_for_path,
    mesh_format,
    mesh_formats,
    register_mesh_format,
    write_mesh,
)
from coastmesh.types import Mesh


@pytest.fixture
def square() -> Mesh:
    """The unit square as 2 triangles; bottom and right edges id 1, the rest id 2."""
    return Mesh(
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        [[0, 1, 2], [0, 2, 3]],
        [[0, 1], [1, 2], [2, 3], [3, 0]],
        [1, 1, 2, 2],
        3,
        "EPSG:32630",
    )


@pytest.fixture
def jittered() -> Mesh:
    """A 5 x 4 node grid in UTM metres, interior nodes moved, 24 triangles."""
    rng = np.random.default_rng(20240611)
    nx, ny = 5, 4
    x, y = np.meshgrid(np.arange(nx) * 250.0 + 500000.0, np.arange(ny) * 200.0)
    points = np.column_stack([x.ravel(), y.ravel()])
    xs, ys = x.ravel(), y.ravel()
    interior = (xs > xs.min()) & (xs < xs.max()) & (ys > ys.min()) & (ys < ys.max())
    # at most 57 m per node: no triangle (altitudes >= 156 m) can fold over
    points[interior] += rng.uniform(-40.0, 40.0, (interior.sum(), 2))
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1))
    a = (j * nx + i).ravel()
    b, c, d = a + 1, a + nx, a + nx + 1
    triangles = np.concatenate([np.column_stack([a, b, d]), np.column_stack([a, d, c])])
    ring = np.concatenate(
        [
            np.arange(nx - 1),  # bottom, left to right
            np.arange(ny - 1) * nx + nx - 1,  # right, upwards
            (ny - 1) * nx + np.arange(nx - 1, 0, -1),  # top, right to left
            np.arange(ny - 1, 0, -1) * nx,  # left, downwards
        ]
    )
    edges = np.column_stack([ring, np.roll(ring, -1)])
    ids = np.where(np.arange(len(edges)) < nx - 1, 2, 1)
    return Mesh(points, triangles, edges, ids, 7, "EPSG:32630")


def triangle_areas(mesh: Mesh) -> np.ndarray:
    """Shoelace area of each triangle, with plain numpy."""
    p = mesh.points[mesh.triangles]
    return 0.5 * np.abs(
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    )


def canonical(m: Mesh):
    """Renumber nodes by coordinates, sort triangles and edges: order-free form."""
    order = np.lexsort(m.points.T[::-1])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    tri = np.sort(rank[m.triangles], axis=1)
    edges = np.column_stack([np.sort(rank[m.boundary_edges], axis=1), m.boundary_ids])
    return (
        m.points[order],
        tri[np.lexsort(tri.T[::-1])],
        edges[np.lexsort(edges.T[::-1])],
        m.surface_id,
    )


def same_mesh(a: Mesh, b: Mesh) -> None:
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.boundary_edges, b.boundary_edges)
    np.testing.assert_array_equal(a.boundary_ids, b.boundary_ids)
    assert a.surface_id == b.surface_id
    assert a.crs == b.crs


def read_layer(path, layer):
    meta, _, wkb, columns = pyogrio.raw.read(path, layer=layer)
    return meta, shapely.from_wkb(wkb), dict(zip(meta["fields"], columns, strict=True))


@pytest.fixture
def scratch_registry(monkeypatch):
    """Let a test register formats without changing the registry for the others."""
    monkeypatch.setattr(writers, "_FORMATS", dict(writers._FORMATS))


# --- msh --------------------------------------------------------------------


@pytest.mark.parametrize("binary", [False, True])
def test_msh2_round_trip_keeps_order(tmp_path, write_read, jittered, binary):
    path = tmp_path / "mesh.msh"
    back = write_read(
        path,
        lambda p, m: write_mesh(p, m, binary=binary),
        read_msh,
        jittered,
        same_mesh,
    )
    np.testing.assert_array_equal(back.points, jittered.points)
    np.testing.assert_array_equal(back.triangles, jittered.triangles)
    grouped = np.argsort(jittered.boundary_ids, kind="stable")  # msh groups by id
    np.testing.assert_array_equal(back.boundary_edges, jittered.boundary_edges[grouped])
    np.testing.assert_array_equal(back.boundary_ids, jittered.boundary_ids[grouped])
    assert back.surface_id == 7
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.msh"]


@pytest.mark.parametrize("binary", [False, True])
def test_msh4_round_trip(tmp_path, write_read, jittered, binary):
    path = tmp_path / "mesh.msh"
    back = write_read(
        path,
        lambda p, m: write_mesh(p, m, format="msh4", binary=binary),
        read_msh,
        jittered,
        same_mesh,
    )
    for got, want in zip(canonical(back), canonical(jittered), strict=True):
        np.testing.assert_array_equal(got, want)


def test_msh_extension_is_version_2_2_and_msh4_is_4_1(tmp_path, square):
    write_mesh(tmp_path / "a.msh", square)
    write_mesh(tmp_path / "b.msh", square, format="msh4")
    assert (tmp_path / "a.msh").read_text().splitlines()[1] == "2.2 0 8"
    assert (tmp_path / "b.msh").read_text().splitlines()[1] == "4.1 0 8"
    assert read_msh(tmp_path / "a.msh").boundary_ids.tolist() == [1, 1, 2, 2]


# --- gpkg -------------------------------------------------------------------


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


# --- outputs ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("file_name", "fmt"),
    [("m.msh", None), ("m.msh", "msh4"), ("m.gpkg", None)],
)
def test_existing_output_is_kept_unless_overwrite(tmp_path, square, file_name, fmt):
    path = tmp_path / file_name
    path.write_bytes(b"previous")
    with pytest.raises(OutputExistsError, match=file_name):
        write_mesh(path, square, format=fmt)
    assert path.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == [file_name]
    write_mesh(path, square, format=fmt, overwrite=True)
    assert path.read_bytes() != b"previous"
    assert [p.name for p in tmp_path.iterdir()] == [file_name]


def test_failing_registered_writer_leaves_nothing(tmp_path, square, scratch_registry):
    def broken(path, mesh, *, overwrite):
        with atomic_write(path, overwrite=overwrite) as tmp:
            tmp.write_text("half a mesh")
            raise RuntimeError("writer crashed")

    register_mesh_format(MeshFormat("broken", (".brk",), broken, "fails"))
    with pytest.raises(RuntimeError, match="writer crashed"):
        write_mesh(tmp_path / "m.brk", square)
    assert list(tmp_path.iterdir()) == []


def test_unknown_option_is_refused_before_writing(tmp_path, square):
    with pytest.raises(ConfigError, match=r"'msh2' has no option 'version'.*binary"):
        write_mesh(tmp_path / "m.msh", square, version="4.1")
    with pytest.raises(ConfigError, match=r"'gpkg' has no option 'binary'.*metadata"):
        write_mesh(tmp_path / "m.gpkg", square, binary=True)
    assert list(tmp_path.iterdir()) == []


def test_write_mesh_refuses_other_types(tmp_path):
    with pytest.raises(TypeError, match="mesh is a dict"):
        write_mesh(tmp_path / "m.msh", {"points": []})
    assert list(tmp_path.iterdir()) == []


# --- registry ---------------------------------------------------------------


def test_built_in_formats():
    formats = mesh_formats()
    assert list(formats)[:3] == ["msh2", "msh4", "gpkg"]
    assert formats["msh2"].extensions == (".msh",)
    assert formats["msh4"].extensions == (".msh",)
    assert formats["gpkg"].extensions == (".gpkg",)
    assert formats["msh2"].options == ("binary",)
    assert formats["gpkg"].options == ("metadata",)
    formats.clear()  # a copy: the registry keeps its entries
    assert "msh2" in mesh_formats()


def test_unknown_format_name(tmp_path, square):
    with pytest.raises(ConfigError, match=r"'fort15'.*msh2, msh4, gpkg"):
        mesh_format("fort15")
    with pytest.raises(ConfigError, match="'fort15'"):
        write_mesh(tmp_path / "m.msh", square, format="fort15")
    assert list(tmp_path.iterdir()) == []


def test_format_name_ignores_case():
    assert mesh_format("GPKG") is mesh_format("gpkg")


@pytest.mark.parametrize(
    "path", ["mesh.vtk", "run/out/mesh.txt", "mesh", "mesh.msh.bak"]
)
def test_unknown_extension(tmp_path, square, path):
    with pytest.raises(FormatError) as info:
        format_for_path(path)
    message = str(info.value)
    assert message.startswith(f"{path}:")
    assert ".gpkg, .gr3, .grd, .mesh, .msh" in message
    with pytest.raises(FormatError, match="unknown mesh format"):
        write_mesh(tmp_path / "x.vtk", square)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("path", "name"),
    [("m.msh", "msh2"), ("M.MSH", "msh2"), ("a/b.Msh", "msh2"), ("x.GPKG", "gpkg")],
)
def test_format_for_path_ignores_case(path, name):
    assert format_for_path(path).name == name


def test_write_by_upper_case_extension(tmp_path, square):
    write_mesh(tmp_path / "MESH.MSH", square)
    assert read_msh(tmp_path / "MESH.MSH").boundary_ids.tolist() == [1, 1, 2, 2]


def test_duplicate_name_is_refused(scratch_registry):
    again = MeshFormat("MSH2", (".m2",), writers._write_msh2, "again")
    with pytest.raises(FormatError, match="'msh2' is already registered"):
        register_mesh_format(again)
    assert ".m2" not in {e for f in mesh_formats().values() for e in f.extensions}


def test_shared_extension_keeps_selecting_the_first_format(scratch_registry):
    register_mesh_format(MeshFormat("other", (".MSH",), writers._write_msh2, "o"))
    assert mesh_format("other").extensions == (".msh",)
    assert format_for_path("m.msh").name == "msh2"


def test_registered_format_is_used(tmp_path, square, scratch_registry):
    def write_nodes(path, mesh, *, overwrite, precision=3):
        with atomic_write(path, overwrite=overwrite) as tmp:
            np.savetxt(tmp, mesh.points, fmt=f"%.{precision}f")

    register_mesh_format(MeshFormat("nodes", (".nodes.txt",), write_nodes, "nodes"))
    register_mesh_format(MeshFormat("text", (".txt",), write_nodes, "text"))
    assert format_for_path("a.NODES.txt").name == "nodes"  # longest ending wins
    assert format_for_path("a.txt").name == "text"
    write_mesh(tmp_path / "m.nodes.txt", square, precision=1)
    assert (tmp_path / "m.nodes.txt").read_text().splitlines()[2] == "1.0 1.0"


def test_scratch_registry_does_not_leak():
    assert set(mesh_formats()) >= {"msh2", "msh4", "gpkg"}
    assert not {"nodes", "text", "broken", "other"} & set(mesh_formats())


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"name": ""}, "name ''"),
        ({"name": "two words"}, "name 'two words'"),
        ({"extensions": ()}, "at least one extension"),
        ({"extensions": ("msh",)}, "extension 'msh'"),
        ({"extensions": (".",)}, "extension '.'"),
        ({"write": "not a function"}, "not callable"),
        ({"write": lambda path, mesh: None}, "no 'overwrite' keyword"),
    ],
)
def test_mesh_format_checks_its_fields(kwargs, match):
    fields = {
        "name": "ok",
        "extensions": (".ok",),
        "write": writers._write_msh2,
        "description": "ok",
    }
    with pytest.raises(ValueError, match=match):
        MeshFormat(**{**fields, **kwargs})


def test_writer_with_kwargs_takes_any_option(tmp_path, square, scratch_registry):
    seen = {}

    def write_any(path, mesh, **options):
        seen.update(options)

    register_mesh_format(MeshFormat("any", (".any",), write_any, "any"))
    assert mesh_format("any").options is None
    write_mesh(tmp_path / "m.any", square, level=3)
    assert seen == {"overwrite": False, "level": 3}


def test_lazy_exports():
    assert coastmesh.io.write_mesh is write_mesh
    assert coastmesh.io.mesh_formats is mesh_formats
    from coastmesh.io.domain_gpkg import write_domain

    assert coastmesh.io.write_domain is write_domain
    assert {"write_mesh", "mesh_formats", "write_domain"} <= set(coastmesh.io.__all__)


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
