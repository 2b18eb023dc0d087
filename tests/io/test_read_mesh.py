"""Every readable format: a mesh written with write_mesh comes back from read_mesh.

Each format gives back what it can hold (docs/formats.md): the round trips check
nodes, triangles (as node triples where the format renumbers), boundary edges with
their ids, and the names, kinds, depth and CRS where the format stores them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from io_meshes import edge_ids, node_map, same_mesh, signed_areas, triangle_set
from scipy.spatial import Delaunay

from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io import (
    MeshFormat,
    mesh_format,
    mesh_formats,
    read_mesh,
    register_mesh_format,
    write_mesh,
)
from coastmesh.io.meshes import _registry
from coastmesh.types import Mesh
from coastmesh.types.topology import boundary_rings


@dataclass(frozen=True)
class Case:
    """A readable format, and what a mesh read back from it holds."""

    name: str
    file: str
    write: dict = field(default_factory=dict)
    crs: str | None = None  # given to read_mesh: the format stores none
    same_order: bool = True  # nodes and triangles come back in their order
    names: bool = True
    kinds: bool = True
    depth: bool = True
    atol: float = 0.0  # text formats round the coordinates and depths
    mike_ids: bool = False  # land ids become 1, open ids their MIKE codes


CASES = [
    Case("msh2", "mesh.msh", crs="EPSG:32630", depth=False),
    Case("msh2", "binary.msh", {"binary": True}, crs="EPSG:32630", depth=False),
    Case(
        "msh4",
        "mesh.msh",
        crs="EPSG:32630",
        same_order=False,
        names=False,
        kinds=False,
        depth=False,
    ),
    Case(
        "msh4",
        "binary.msh",
        {"binary": True},
        crs="EPSG:32630",
        same_order=False,
        names=False,
        kinds=False,
        depth=False,
    ),
    Case("gpkg", "mesh.gpkg"),
    Case("fort14", "fort.14", atol=1e-9),
    Case("gr3", "hgrid.gr3", atol=1e-9),
    Case("mike", "mesh.mesh", names=False, atol=1e-9, mike_ids=True),
    Case("ugrid", "mesh.nc"),
    Case("vtu", "mesh.vtu", crs="EPSG:32630", names=False, kinds=False),
]


def check_read_back(back: Mesh, mesh: Mesh, case: Case) -> None:
    nodes = node_map(back, mesh, atol=case.atol)
    if case.same_order:
        np.testing.assert_array_equal(nodes, np.arange(len(mesh.points)))
        np.testing.assert_array_equal(back.triangles, mesh.triangles)
    assert triangle_set(back.triangles, nodes) == triangle_set(mesh.triangles)
    assert (signed_areas(back) > 0).all()
    open_codes = {
        pid: 2 + k
        for k, pid in enumerate(
            sorted(p for p, kind in mesh.boundary_kinds.items() if kind == "open")
        )
    }
    expected = {
        edge: (open_codes.get(pid, 1) if case.mike_ids else pid)
        for edge, pid in edge_ids(mesh.boundary_edges, mesh.boundary_ids).items()
    }
    assert edge_ids(back.boundary_edges, back.boundary_ids, nodes) == expected
    if case.names:
        spaced = {i: "_".join(n.split()) for i, n in mesh.boundary_names.items()}
        assert back.boundary_names in (mesh.boundary_names, spaced)
    else:
        assert back.boundary_names == {}
    if case.kinds:
        written = edge_ids(mesh.boundary_edges, mesh.boundary_ids)
        kinds = {expected[e]: mesh.boundary_kinds[pid] for e, pid in written.items()}
        assert back.boundary_kinds == kinds
    else:
        assert back.boundary_kinds == {}
    if case.depth:
        np.testing.assert_allclose(
            back.point_data["depth"], mesh.point_data["depth"][nodes], atol=case.atol
        )
    else:
        assert "depth" not in back.point_data
    assert back.crs == mesh.crs


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c.name}-{c.file}")
def test_round_trip_of_the_islands_mesh(tmp_path, write_read, mesh_with_islands, case):
    back = write_read(
        tmp_path / case.file,
        lambda path, mesh: write_mesh(path, mesh, format=case.name, **case.write),
        lambda path: read_mesh(path, format=case.name, crs=case.crs),
        mesh_with_islands,
        same_mesh,
    )
    check_read_back(back, mesh_with_islands, case)
    assert back.surface_id == 1


def test_every_format_reads():
    modes = {name: fmt.mode for name, fmt in mesh_formats().items()}
    assert set(modes.values()) == {"read and write"}
    # SELAFIN's round trips (ids renumbered as Telemac numbers its liquid
    # boundaries) are in test_telemac_read.py
    assert {case.name for case in CASES} == set(modes) - {"selafin"}


def test_the_extension_picks_the_reader(tmp_path, mesh_with_islands):
    for name in ("mesh.msh", "fort.14", "mesh.grd", "hgrid.gr3", "hgrid.ll", "m.nc"):
        write_mesh(tmp_path / name, mesh_with_islands)
        back = read_mesh(tmp_path / name, crs="EPSG:32630")
        assert len(back.triangles) == len(mesh_with_islands.triangles), name


@st.composite
def random_meshes(draw):
    """A Delaunay mesh of random points, its hull cut into runs of 2+ edges."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    points = rng.uniform(0.0, 1000.0, (draw(st.integers(5, 40)), 2))
    points = np.vstack([points, points.mean(axis=0)])  # one node inside, at least
    triangles = Delaunay(points).simplices
    a, b, c = (points[triangles[:, k]] for k in range(3))
    cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    clockwise = cross < 0
    triangles[clockwise] = triangles[clockwise][:, [0, 2, 1]]
    counted: dict[tuple[int, int], int] = {}
    for tri in triangles.tolist():
        for i, j in zip(tri, tri[1:] + tri[:1], strict=True):
            counted[(min(i, j), max(i, j))] = counted.get((min(i, j), max(i, j)), 0) + 1
    hull = [edge for edge, count in counted.items() if count == 1]
    plain = Mesh(points, triangles, hull, np.ones(len(hull)), 1, None)
    (ring,) = boundary_rings(plain)
    size = len(ring.nodes)
    runs = draw(st.integers(1, max(size // 2, 1)))
    cuts = np.sort(rng.choice(np.arange(1, size // 2), runs - 1, replace=False)) * 2
    run_of = np.searchsorted(cuts, np.arange(size), side="right")
    edges = np.column_stack([ring.nodes, np.roll(ring.nodes, -1)])
    kinds = {k + 1: draw(st.sampled_from(["open", "shoreline"])) for k in range(runs)}
    return Mesh(
        points,
        triangles,
        edges,
        run_of + 1,
        1,
        "EPSG:32631",
        {"depth": rng.uniform(1.0, 100.0, len(points))},
        {k: f"run {k}" for k in kinds},
        kinds,
    )


@settings(max_examples=15, deadline=None)
@given(mesh=random_meshes())
def test_round_trip_of_random_meshes(tmp_path_factory, mesh):
    folder = tmp_path_factory.mktemp("random")
    for case in CASES:
        path = folder / case.file
        write_mesh(path, mesh, format=case.name, overwrite=True, **case.write)
        crs = None if case.crs is None else mesh.crs
        check_read_back(read_mesh(path, format=case.name, crs=crs), mesh, case)


def test_write_only_format_is_refused_for_reading(tmp_path, monkeypatch):
    from coastmesh.io.meshes import _registry
    from coastmesh.io.meshes._mesh_format import MeshFormat

    only = MeshFormat("scratch", (".scratch",), lambda *a, **k: None, "write only")
    monkeypatch.setitem(_registry._registry(), "scratch", only)
    path = tmp_path / "m.scratch"
    path.write_bytes(b"")
    with pytest.raises(
        FormatError, match=r"m\.scratch: the scratch format is write only"
    ):
        read_mesh(path)
    with pytest.raises(FormatError, match="can be read: msh2, msh4, gpkg, fort14"):
        read_mesh(path, format="scratch")


def test_unknown_names_list_the_modes(tmp_path):
    with pytest.raises(ConfigError, match=r"gr3, selafin, mike"):
        mesh_format("fort15")
    with pytest.raises(FormatError, match=r"unknown mesh format.*\.msh"):
        read_mesh(tmp_path / "mesh.xyz")


@pytest.mark.parametrize(
    "name", ["m.msh", "m.gpkg", "fort.14", "h.gr3", "m.mesh", "m.nc", "m.vtu"]
)
def test_missing_file_is_named(tmp_path, name):
    with pytest.raises(InputDataError, match="file not found") as info:
        read_mesh(tmp_path / name)
    assert info.value.path == str(tmp_path / name)


def test_crs_is_for_files_that_store_none(tmp_path, mesh_with_islands):
    write_mesh(tmp_path / "m.nc", mesh_with_islands)
    assert read_mesh(tmp_path / "m.nc", crs="EPSG:32630").crs.to_epsg() == 32630
    with pytest.raises(InputDataError, match="CRS is EPSG:32630, but crs=EPSG:4326"):
        read_mesh(tmp_path / "m.nc", crs="EPSG:4326")
    with pytest.raises(ConfigError, match="crs='nowhere'"):
        read_mesh(tmp_path / "m.nc", crs="nowhere")
    write_mesh(tmp_path / "m.msh", mesh_with_islands)
    assert read_mesh(tmp_path / "m.msh").crs is None


def test_reader_options(tmp_path, mesh_with_islands):
    write_mesh(tmp_path / "fort.14", mesh_with_islands, positive="up")
    back = read_mesh(tmp_path / "fort.14", positive="up")
    np.testing.assert_allclose(
        back.point_data["depth"], mesh_with_islands.point_data["depth"]
    )
    with pytest.raises(ConfigError, match="has no option 'binary' for reading"):
        read_mesh(tmp_path / "fort.14", binary=True)
    assert mesh_format("fort14").read_options == ("positive",)
    assert mesh_format("msh2").read_options == ()


def test_path_comes_first(tmp_path, mesh_with_islands):
    with pytest.raises(TypeError, match="the path comes first"):
        write_mesh(mesh_with_islands, tmp_path / "m.msh")
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def scratch_registry(monkeypatch):
    monkeypatch.setattr(_registry, "_FORMATS", mesh_formats())


def test_read_only_format(tmp_path, mesh_with_islands, scratch_registry):
    seen = {}

    def read_points(path, *, crs=None, scale=1.0):
        seen.update(crs=crs, scale=scale)
        return mesh_with_islands

    register_mesh_format(MeshFormat("pts", (".pts",), None, "points", read=read_points))
    assert mesh_format("pts").mode == "read only"
    assert mesh_format("pts").options == ()
    assert read_mesh(tmp_path / "a.pts", scale=2.0) is mesh_with_islands
    assert seen == {"crs": None, "scale": 2.0}
    with pytest.raises(FormatError, match="pts format is read only; formats that can"):
        write_mesh(tmp_path / "a.pts", mesh_with_islands)
    with pytest.raises(ConfigError, match=r"pts \(read only\)"):
        mesh_format("nothing")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("write", "read", "match"),
    [
        (None, None, "a writer, a reader or both"),
        (None, lambda path: None, "read takes no 'crs' keyword"),
        (None, "read me", "read is not callable"),
    ],
)
def test_mesh_format_checks_its_reader(write, read, match):
    with pytest.raises(ValueError, match=match):
        MeshFormat("x", (".x",), write, "x", read=read)
