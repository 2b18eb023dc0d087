"""Region ids (farms, turbine footprints) survive every format that holds them."""

from __future__ import annotations

import gmsh
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from io_meshes import jittered_grid, node_map

from coastmesh.io import read_mesh, write_mesh
from coastmesh.meshing.cleanup.smoothing import mesh_with
from coastmesh.types import Mesh

FORMATS = [
    ("m.msh", {"format": "msh2"}),
    ("m.msh", {"format": "msh2", "binary": True}),
    ("m.msh", {"format": "msh4"}),
    ("m.vtu", {}),
    ("m.nc", {}),
    ("m.gpkg", {}),
]


def farm_mesh(regions=None) -> Mesh:
    """The jittered 24-triangle grid (surface 7) with a farm (20) and a
    footprint (100) in it; the domain keeps the most triangles."""
    grid = jittered_grid()
    if regions is None:
        regions = np.full(len(grid.triangles), 7)
        regions[[3, 4, 5, 10, 11]] = 20
        regions[[12]] = 100
    return Mesh(
        grid.points,
        grid.triangles,
        grid.boundary_edges,
        grid.boundary_ids,
        7,
        grid.crs,
        {"depth": np.linspace(5, 50, len(grid.points))},
        {1: "coast"},
        {1: "shoreline"},
        regions,
        {20: "meygen", 100: "T1"},
    )


def _by_triangle(mesh: Mesh, nodes=None):
    tri = mesh.triangles if nodes is None else nodes[mesh.triangles]
    return {
        tuple(sorted(t)): int(r)
        for t, r in zip(tri.tolist(), mesh.regions.tolist(), strict=True)
    }


@pytest.mark.parametrize(("file", "options"), FORMATS)
def test_every_region_id_survives_a_round_trip(tmp_path, file, options):
    mesh = farm_mesh()
    path = tmp_path / file
    write_mesh(path, mesh, **options)
    back = read_mesh(path, crs=mesh.crs)
    nodes = node_map(back, mesh, atol=1e-6)
    assert _by_triangle(back, nodes) == _by_triangle(mesh)
    assert back.surface_id == 7
    assert back.region_ids == [7, 20, 100]
    # VTU holds no names, and meshio reads none from msh 4.1
    if options.get("format") != "msh4" and file != "m.vtu":
        assert back.region_names == {20: "meygen", 100: "T1"}


@pytest.mark.parametrize("binary", [False, True])
def test_gmsh_reads_one_physical_surface_per_region(tmp_path, binary):
    path = tmp_path / "m.msh"
    write_mesh(path, farm_mesh(), format="msh2", binary=binary)
    gmsh.initialize(["-v", "0"])
    try:
        gmsh.open(str(path))
        groups = gmsh.model.getPhysicalGroups(2)
        named = {tag: gmsh.model.getPhysicalName(2, tag) for _, tag in groups}
        counts = {}
        for _, tag in groups:
            for entity in gmsh.model.getEntitiesForPhysicalGroup(2, tag):
                _, elements, _ = gmsh.model.mesh.getElements(2, entity)
                counts[tag] = counts.get(tag, 0) + sum(len(e) for e in elements)
    finally:
        gmsh.finalize()
    assert named == {7: "domain", 20: "meygen", 100: "T1"}
    assert counts == {7: 18, 20: 5, 100: 1}


@settings(max_examples=20, deadline=None)
@given(st.lists(st.sampled_from([7, 20, 21, 100]), min_size=24, max_size=24))
def test_any_split_into_regions_round_trips_through_msh2_and_ugrid(regions):
    import tempfile
    from pathlib import Path

    mesh = farm_mesh(np.array(regions))
    with tempfile.TemporaryDirectory() as tmp:
        for file, options in (("m.msh", {"format": "msh2"}), ("m.nc", {})):
            path = Path(tmp) / file
            write_mesh(path, mesh, **options, overwrite=True)
            back = read_mesh(path, crs=mesh.crs)
            np.testing.assert_array_equal(back.regions, mesh.regions)


def test_regions_are_checked():
    grid = jittered_grid()
    with pytest.raises(ValueError, match="one physical surface id per triangle"):
        farm_mesh(np.ones(3, int))
    with pytest.raises(ValueError, match="ids are >= 1"):
        farm_mesh(np.zeros(len(grid.triangles), int))
    assert (jittered_grid().regions == 7).all()  # default: the surface id


def test_new_triangles_need_new_regions_when_there_are_several():
    one = jittered_grid()
    fewer = mesh_with(one, triangles=one.triangles[:-2])
    assert (fewer.regions == 7).all() and len(fewer.regions) == len(one.triangles) - 2
    with pytest.raises(ValueError, match="give regions"):
        mesh_with(farm_mesh(), triangles=one.triangles[:-2])
