"""Gmsh engine: a square with a square island, and Mainland Orkney in a box."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from pyproj import CRS, Transformer

from coastmesh.errors import MeshingError
from coastmesh.meshing import default_mesh_crs, generate_mesh, sample_size
from coastmesh.meshing.gmsh.model import gmsh_session
from coastmesh.meshing.gmsh.resample import SmallIslandWarning
from coastmesh.types import BoundarySegment, Domain, SizeGrid

OUTER = np.array([[0, 0], [10000, 0], [10000, 10000], [0, 10000], [0, 0]], float)
ISLAND = np.array(
    [[4000, 4000], [4000, 6000], [6000, 6000], [6000, 4000], [4000, 4000]], float
)
SIDE_IDS = (1, 2, 1, 3)
ISLAND_ID = 5


def square_domain(island=ISLAND, surface_id=7):
    sides = tuple(
        BoundarySegment(OUTER[i : i + 2], "open", f"side {i}", pid)
        for i, pid in enumerate(SIDE_IDS)
    )
    polygon = shapely.Polygon(OUTER, [island])
    segments = sides + (BoundarySegment(island, "shoreline", "island", ISLAND_ID),)
    return Domain(polygon, segments, crs="EPSG:32630", surface_id=surface_id)


def graded(h_min):
    x = np.linspace(-500, 10500, 23)
    X, Y = np.meshgrid(x, x)
    values = h_min + 0.08 * np.hypot(X - 5000, Y - 5000)
    return SizeGrid(x, x, values)


def triangle_edges(mesh):
    t = mesh.triangles
    return np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])


def signed_areas(points, triangles):
    a, b, c = (points[triangles[:, k]] for k in range(3))
    u, v = b - a, c - a
    return 0.5 * (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])


def min_angles(points, triangles):
    p = points[triangles]
    angles = []
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cos = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.min(angles, axis=0)


@pytest.fixture(scope="module")
def square():
    return square_domain()


@pytest.fixture(scope="module")
def coarse(square):
    return generate_mesh(square, graded(300.0))


@pytest.fixture(scope="module")
def fine(square):
    return generate_mesh(square, graded(150.0))


def test_every_boundary_edge_has_the_id_of_its_segment(square, coarse):
    mesh = coarse
    assert len(mesh.boundary_ids) == len(mesh.boundary_edges) > 0
    assert set(mesh.boundary_ids.tolist()) == {*SIDE_IDS, ISLAND_ID}
    mid = shapely.points(mesh.points[mesh.boundary_edges].mean(axis=1))
    for segment in square.segments:
        on = shapely.distance(shapely.LineString(segment.coords), mid) < 1e-6
        assert (mesh.boundary_ids[on] == segment.physical_id).all(), segment.name
    # every edge that only one triangle has is a tagged boundary edge
    edges = np.sort(triangle_edges(mesh), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    once = {tuple(e) for e in unique[count == 1]}
    assert once == {tuple(e) for e in np.sort(mesh.boundary_edges, axis=1)}


def test_triangles_are_counter_clockwise_and_fill_the_polygon(square, coarse):
    area = signed_areas(coarse.points, coarse.triangles)
    assert (area > 0).all()
    assert abs(area.sum() - square.polygon.area) <= 1e-9 * square.polygon.area
    boundary_nodes = coarse.points[np.unique(coarse.boundary_edges)]
    distance = shapely.distance(square.polygon.boundary, shapely.points(boundary_nodes))
    assert distance.max() < 1e-6
    inside = shapely.covers(square.polygon.buffer(1e-6), shapely.points(coarse.points))
    assert inside.all()


def test_boundary_edges_have_the_domain_on_their_left(coarse):
    a, b = (coarse.points[coarse.boundary_edges[:, k]] for k in range(2))
    ids = coarse.boundary_ids
    outer = ids != ISLAND_ID
    # the exterior runs counter-clockwise, the island clockwise
    cross = lambda p, q: p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]  # noqa: E731
    assert cross(a[outer], b[outer]).sum() > 0
    assert cross(a[~outer], b[~outer]).sum() < 0


def test_node_count_grows_as_the_size_shrinks(square):
    grid = graded(300.0)
    counts = [
        len(generate_mesh(square, SizeGrid(grid.x, grid.y, grid.values * f)).points)
        for f in (4.0, 2.0, 1.0)
    ]
    assert counts[0] < counts[1] < counts[2]
    assert counts[2] > 2.5 * counts[1]  # about 4 times per halving


@pytest.mark.parametrize("which", ["coarse", "fine"])
def test_edge_lengths_follow_the_size_field(which, request):
    mesh = request.getfixturevalue(which)
    h_min = 300.0 if which == "coarse" else 150.0
    edges = triangle_edges(mesh)
    p, q = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
    ratio = np.hypot(*(q - p).T) / sample_size(graded(h_min), 0.5 * (p + q))
    assert 0.7 < np.median(ratio) < 1.4
    np.testing.assert_allclose(
        mesh.point_data["size"], sample_size(graded(h_min), mesh.points)
    )


def test_meshing_twice_gives_identical_arrays(square, coarse):
    again = generate_mesh(square, graded(300.0))
    for name in ("points", "triangles", "boundary_edges", "boundary_ids"):
        np.testing.assert_array_equal(getattr(again, name), getattr(coarse, name))


def test_the_boundary_nodes_are_made_on_one_gmsh_thread(square, coarse, monkeypatch):
    # on more, Gmsh's size view octree makes them depend on thread timing in
    # the last bits (world.toml); a mesh asked for on 4 threads is the same
    from coastmesh.meshing.gmsh import boundary_nodes as module

    seen = []
    options = module.set_options

    def spy(gmsh, *, threads, **kwargs):
        seen.append(threads)
        return options(gmsh, threads=threads, **kwargs)

    monkeypatch.setattr(module, "set_options", spy)
    again = generate_mesh(square, graded(300.0), threads=4)
    assert seen == [1]
    np.testing.assert_array_equal(again.points, coarse.points)
    np.testing.assert_array_equal(again.triangles, coarse.triangles)


def test_surface_id_crs_and_progress(square, coarse):
    assert coarse.surface_id == 7
    assert coarse.crs == CRS.from_epsg(32630)
    calls = []
    generate_mesh(square, graded(600.0), progress=lambda d, t: calls.append((d, t)))
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]


@pytest.mark.parametrize("algorithm", ["delaunay", "meshadapt"])
def test_other_algorithms_also_mesh(square, algorithm):
    mesh = generate_mesh(square, graded(600.0), algorithm=algorithm, optimize=False)
    area = signed_areas(mesh.points, mesh.triangles)
    assert (area > 0).all()
    assert abs(area.sum() - square.polygon.area) <= 1e-9 * square.polygon.area


def test_an_island_below_the_local_size_is_dropped():
    tiny = np.array([[5000, 5000], [5000, 5010], [5010, 5010], [5000, 5000]], float)
    domain = square_domain(tiny)
    with pytest.warns(SmallIslandWarning):
        mesh = generate_mesh(domain, graded(600.0))
    assert ISLAND_ID not in mesh.boundary_ids
    area = signed_areas(mesh.points, mesh.triangles).sum()
    assert area == pytest.approx(OUTER_AREA, rel=1e-9)


OUTER_AREA = 1e8


def test_gmsh_failures_become_meshing_errors(square, monkeypatch):
    import gmsh

    def failing_generate(dim):
        gmsh.model.mesh.field.setNumber(999, "NoSuchOption", 1)

    monkeypatch.setattr(gmsh.model.mesh, "generate", failing_generate)
    with pytest.raises(MeshingError, match=r"Gmsh failed.*: .*field"):
        generate_mesh(square, graded(600.0))
    assert not gmsh.isInitialized()


def test_session_finalises_after_an_exception():
    import gmsh

    with pytest.raises(KeyError), gmsh_session():
        assert gmsh.isInitialized()
        raise KeyError("boom")
    assert not gmsh.isInitialized()


def test_bad_arguments_are_refused(square):
    grid = graded(600.0)
    with pytest.raises(ValueError, match="algorithm"):
        generate_mesh(square, grid, algorithm="quad")
    with pytest.raises(ValueError, match="seed"):
        generate_mesh(square, grid, seed=-1)
    with pytest.raises(ValueError, match="mesh_crs"):
        generate_mesh(square, grid, mesh_crs="EPSG:4326")
    with pytest.raises(TypeError, match="SizeGrid"):
        generate_mesh(square, grid.values)


def test_importing_the_meshing_package_does_not_import_gmsh():
    code = "import sys, coastmesh.meshing; print('gmsh' in sys.modules)"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "False"


# --- real data: Mainland Orkney as an island in a box --------------------------

BOX = np.array(
    [[-3.5, 58.68], [-2.55, 58.68], [-2.55, 59.25], [-3.5, 59.25], [-3.5, 58.68]]
)


@pytest.fixture(scope="module")
def orkney(orkney_geojson):
    collection = json.loads(orkney_geojson.read_text())
    feature = next(f for f in collection["features"] if f["properties"]["id"] == "456")
    mainland = np.array(feature["geometry"]["coordinates"][0], dtype=float)
    segments = (
        BoundarySegment(BOX[0:3], "open", "south-east", 2),
        BoundarySegment(BOX[2:5], "open", "north-west", 3),
        BoundarySegment(mainland, "shoreline", "Mainland", 1),
    )
    domain = Domain(shapely.Polygon(BOX, [mainland]), segments, crs="EPSG:4326")
    utm = CRS.from_epsg(32630)
    to_utm = Transformer.from_crs(4326, utm, always_xy=True)
    coast = shapely.LineString(np.column_stack(to_utm.transform(*mainland.T)))
    x0, y0 = to_utm.transform(-3.6, 58.6)
    x1, y1 = to_utm.transform(-2.45, 59.3)
    x, y = np.arange(x0, x1, 1000.0), np.arange(y0, y1, 1000.0)
    X, Y = np.meshgrid(x, y)
    distance = shapely.distance(coast, shapely.points(X, Y))
    grid = SizeGrid(x, y, np.clip(300.0 + 0.2 * distance, 300.0, 3000.0))
    return domain, grid, to_utm, coast


def test_orkney_default_mesh_crs_is_utm_30n(orkney):
    domain, *_ = orkney
    assert default_mesh_crs(domain) == CRS.from_epsg(32630)


def test_orkney_mesh_in_utm_returned_in_lon_lat(orkney):
    domain, grid, to_utm, coast = orkney
    mesh = generate_mesh(domain, grid)
    assert mesh.crs == CRS.from_epsg(4326)
    lon, lat = mesh.points.T
    # the box sides are densified in lon/lat and meshed as UTM splines: 0.1 m
    tol = 1e-6
    assert lon.min() >= -3.5 - tol and lon.max() <= -2.55 + tol
    assert lat.min() >= 58.68 - tol and lat.max() <= 59.25 + tol
    for corner in BOX[:4]:
        assert np.isclose(mesh.points, corner, atol=1e-9, rtol=0).all(axis=1).any()
    assert (signed_areas(mesh.points, mesh.triangles) > 0).all()
    assert set(mesh.boundary_ids.tolist()) == {1, 2, 3}
    metres = np.column_stack(to_utm.transform(lon, lat))
    assert (min_angles(metres, mesh.triangles) > 15.0).mean() >= 0.99
    # shoreline nodes stay on the coast to well within the 300 m target size
    shore = np.unique(mesh.boundary_edges[mesh.boundary_ids == 1])
    off = shapely.distance(coast, shapely.points(metres[shore]))
    assert np.median(off) < 15.0 and off.max() < 150.0
    # edges follow the size field in metres
    edges = triangle_edges(mesh)
    p, q = metres[edges[:, 0]], metres[edges[:, 1]]
    ratio = np.hypot(*(q - p).T) / sample_size(grid, 0.5 * (p + q))
    assert 0.7 < np.median(ratio) < 1.4
    assert 3000 < len(mesh.points) < 8000


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="Linux only")
def test_a_gmsh_session_leaves_broken_pipes_to_python():
    """Gmsh resets SIGPIPE to 'end the process'; the session puts Python's back."""
    from coastmesh.meshing.gmsh.model import gmsh_session

    def ignored() -> bool:
        status = Path("/proc/self/status").read_text().splitlines()
        mask = next(line for line in status if line.startswith("SigIgn"))
        return bool(int(mask.split()[1], 16) >> (signal.SIGPIPE - 1) & 1)

    assert ignored()  # Python ignores it: a write to a closed pipe raises
    with gmsh_session():
        assert ignored()
    assert ignored()
