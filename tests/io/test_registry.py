"""The mesh format registry (read and write), and its msh and GeoPackage formats."""

from __future__ import annotations

import numpy as np
import pytest
from io_meshes import canonical, jittered_grid, same_mesh, unit_square

import coastmesh.io
from coastmesh.errors import ConfigError, FormatError, OutputExistsError
from coastmesh.io import (
    MeshFormat,
    atomic_write,
    format_for_path,
    mesh_format,
    mesh_formats,
    read_msh,
    register_mesh_format,
    write_mesh,
)
from coastmesh.io.meshes import _registry

square = pytest.fixture(unit_square, name="square")
jittered = pytest.fixture(jittered_grid, name="jittered")


@pytest.fixture
def scratch_registry(monkeypatch):
    """Let a test register formats without changing the registry for the others."""
    monkeypatch.setattr(_registry, "_FORMATS", mesh_formats())


def write_msh2(path, mesh, *, overwrite=False, binary=False):
    write_mesh(path, mesh, format="msh2", overwrite=overwrite, binary=binary)


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
    match = r"'msh2' has no option 'version' for writing.*binary"
    with pytest.raises(ConfigError, match=match):
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
    assert formats["msh2"].options == ("binary", "sphere_xyz", "radius")
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
    assert ".gpkg, .gr3, .grd, .ll, .mesh, .msh" in message
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
    again = MeshFormat("MSH2", (".m2",), write_msh2, "again")
    with pytest.raises(FormatError, match="'msh2' is already registered"):
        register_mesh_format(again)
    assert ".m2" not in {e for f in mesh_formats().values() for e in f.extensions}


def test_shared_extension_keeps_selecting_the_first_format(scratch_registry):
    register_mesh_format(MeshFormat("other", (".MSH",), write_msh2, "o"))
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
        "write": write_msh2,
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
    from coastmesh.io.vectors.domain_gpkg import write_domain

    assert coastmesh.io.write_domain is write_domain
    assert {"write_mesh", "mesh_formats", "write_domain"} <= set(coastmesh.io.__all__)
