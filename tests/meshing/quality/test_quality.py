"""Mesh quality on the Earth: fast code against a geodesic loop, and as data."""

from __future__ import annotations

import json
import math

import meshio
import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from pyproj import Geod, Transformer
from reference_quality import (
    mesh_quality_reference,
    triangle_quality_reference,
    triangle_reference,
)

from coastmesh.io.meshes.msh import write_msh
from coastmesh.meshing import generate_mesh
from coastmesh.meshing.quality import measure as measure_module
from coastmesh.meshing.quality.mesh_quality import (
    edge_quality,
    mesh_quality,
    triangle_quality,
)
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

GEOD = Geod(ellps="WGS84")
RTOL = 1e-6

# The topology test domain (4 x 3 km, two islands), moved to about 60N 3.4W.
X0, Y0 = 480_000.0, 6_650_000.0


@pytest.fixture(scope="module")
def lonlat_mesh():
    def at(ring):
        return [[x + X0, y + Y0] for x, y in ring]

    outer = at([[0, 0], [4000, 0], [4000, 3000], [0, 3000], [0, 0]])
    holes = [
        at([[1000, 1000], [1000, 1500], [1500, 1500], [1500, 1000], [1000, 1000]]),
        at([[2500, 1000], [2500, 2000], [3000, 2000], [2500, 1000]]),
    ]
    polygon = shapely.Polygon(outer, holes)
    segments = (
        BoundarySegment(outer[:2], "open", "south", 2),
        BoundarySegment(outer[1:], "shoreline", "coast", 1),
        BoundarySegment(polygon.interiors[0].coords, "shoreline", "coast", 1),
        BoundarySegment(polygon.interiors[1].coords, "shoreline", "rock", 3),
    )
    domain = Domain(polygon, segments, crs="EPSG:32630")
    grid = SizeGrid(
        [X0, X0 + 4000.0], [Y0, Y0 + 3000.0], [[150.0, 400.0], [150.0, 400.0]]
    )
    mesh = generate_mesh(domain, grid, output_crs="EPSG:4326")
    assert mesh.crs.is_geographic and 58 < mesh.points[:, 1].mean() < 61
    return mesh


def one_triangle(points, crs="EPSG:4326"):
    return Mesh(points, [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, crs)


def fan(lon, lat, azimuths, distances):
    """A triangle: a node at (lon, lat) and two at given azimuths and distances."""
    tips = [
        GEOD.fwd(lon, lat, az, d)[:2] for az, d in zip(azimuths, distances, strict=True)
    ]
    return [(lon, lat), *tips]


def grid_mesh(crs=None, scale=1.0, origin=(0.0, 0.0)):
    """3 x 3 nodes, 8 triangles, diagonals from (i, j) to (i + 1, j + 1).

    Node 4 is the only interior node; triangles 2 (1, 2, 5) and 5 (3, 7, 6) have
    all three nodes on the boundary.
    """
    points = [
        (origin[0] + i * scale, origin[1] + j * scale)
        for j in range(3)
        for i in range(3)
    ]
    triangles = []
    for j in range(2):
        for i in range(2):
            a = 3 * j + i
            triangles += [[a, a + 1, a + 4], [a, a + 4, a + 3]]
    ring = [0, 1, 2, 5, 8, 7, 6, 3]
    edges = [[ring[k], ring[(k + 1) % 8]] for k in range(8)]
    return Mesh(points, triangles, edges, [1] * 4 + [2] * 4, 1, crs)


# --- against the literal reference -------------------------------------------


def test_generated_lonlat_mesh_matches_the_geodesic_reference(lonlat_mesh):
    mesh = lonlat_mesh
    fast = triangle_quality(mesh)
    slow = triangle_quality_reference(mesh)
    for key in ("min_angle", "radius_ratio", "area"):
        np.testing.assert_allclose(fast[key], slow[key], rtol=RTOL, err_msg=key)
    assert 100 < len(mesh.triangles) < 5000
    assert fast["min_angle"].min() > 20  # Gmsh makes decent triangles

    report = mesh_quality(mesh)
    ref = mesh_quality_reference(mesh)
    edges = edge_quality(mesh)
    assert len(edges["edges"]) == len(ref["edges"])
    for (i, j), shared, length, ratio in zip(
        edges["edges"], edges["triangles"], edges["length"], edges["ratio"], strict=True
    ):
        want_shared, want_length, want_ratio = ref["edges"][(int(i), int(j))]
        assert shared == want_shared
        assert length == pytest.approx(want_length, rel=RTOL)
        assert ratio == pytest.approx(want_ratio, rel=RTOL)
    assert report.interior_valence.histogram == ref["interior_valence"]
    assert report.boundary_valence.histogram == ref["boundary_valence"]
    assert report.unused_nodes == ref["unused"]
    assert report.all_boundary_triangles.tolist() == ref["all_boundary"]
    assert report.min_angle.min == pytest.approx(slow["min_angle"].min(), rel=RTOL)
    assert report.min_angle.p5 == pytest.approx(
        np.percentile(slow["min_angle"], 5), rel=RTOL
    )
    assert report.radius_ratio.mean == pytest.approx(
        slow["radius_ratio"].mean(), rel=RTOL
    )
    ratios = np.array([r[2] for r in ref["edges"].values()])
    assert report.edge_ratio.edges == len(ratios)
    assert report.edge_ratio.p50 == pytest.approx(np.median(ratios), rel=RTOL)
    assert report.edge_ratio.within == np.mean((ratios >= 0.5) & (ratios <= 2))
    # the boundary edges Gmsh tagged are the edges in one triangle
    tagged = {tuple(sorted(map(int, e))) for e in mesh.boundary_edges}
    assert tagged == {k for k, r in ref["edges"].items() if r[0] == 1}
    assert report.boundary_edges == {
        pid: int((mesh.boundary_ids == pid).sum()) for pid in (1, 2, 3)
    }
    assert not report.planar and report.crs == "WGS 84"


def test_projected_mesh_is_measured_like_its_lonlat_copy(lonlat_mesh):
    to_utm = Transformer.from_crs("EPSG:4326", "EPSG:32630", always_xy=True)
    x, y = to_utm.transform(*lonlat_mesh.points.T)
    utm = Mesh(
        np.column_stack([x, y]),
        lonlat_mesh.triangles,
        lonlat_mesh.boundary_edges,
        lonlat_mesh.boundary_ids,
        1,
        "EPSG:32630",
    )
    a, b = triangle_quality(utm), triangle_quality(lonlat_mesh)
    for key in a:
        np.testing.assert_allclose(a[key], b[key], rtol=1e-9, err_msg=key)
    slow = triangle_quality_reference(utm)
    np.testing.assert_allclose(a["min_angle"], slow["min_angle"], rtol=RTOL)


def test_blocks_give_the_same_answer(lonlat_mesh, monkeypatch):
    whole = triangle_quality(lonlat_mesh)
    whole_edges = edge_quality(lonlat_mesh)
    monkeypatch.setattr(measure_module, "_BLOCK", 7)
    blocked = triangle_quality(lonlat_mesh)
    blocked_edges = edge_quality(lonlat_mesh)
    for key in whole:
        np.testing.assert_array_equal(blocked[key], whole[key])
    for key in whole_edges:
        np.testing.assert_array_equal(blocked_edges[key], whole_edges[key])


def _planar_shape(xy):
    """Smallest angle (degrees) and side of a planar triangle."""
    xy = np.asarray(xy)
    angle, side = 180.0, math.inf
    for k in range(3):
        u, v = xy[(k + 1) % 3] - xy[k], xy[(k + 2) % 3] - xy[k]
        norms = np.linalg.norm(u) * np.linalg.norm(v)
        if norms == 0:
            return 0.0, 0.0
        angle = min(angle, math.degrees(math.acos(np.clip(u @ v / norms, -1, 1))))
        side = min(side, np.linalg.norm(u))
    return angle, side


@st.composite
def lonlat_triangles(draw):
    """Non-degenerate triangles in a box of 0.001 to 0.5 degrees (100 m to 55 km):
    no angle under 3 degrees, no side under 1/40 of the box."""
    lon = draw(st.floats(-180, 180))
    lat = draw(st.floats(-75, 75))
    span = draw(st.floats(1e-3, 0.5))
    stretch = math.cos(math.radians(lat))

    def fair(offsets):
        angle, side = _planar_shape([(dx * stretch, dy) for dx, dy in offsets])
        return angle > 3 and side > 0.05

    corner = st.tuples(st.floats(-1, 1), st.floats(-1, 1))
    offsets = draw(st.lists(corner, min_size=3, max_size=3).filter(fair))
    return [(lon + span * dx, lat + span * dy) for dx, dy in offsets]


@given(lonlat_triangles())
@example([(10.0, 60.0), (10.4, 60.0), (10.0, 60.45)])
@example([(179.9, -75.0), (-179.8, -75.1), (179.95, -74.7)])  # across 180
@settings(max_examples=200, deadline=None)
def test_random_lonlat_triangles_match_geodesics(points):
    mesh = one_triangle(points)
    slow = triangle_quality_reference(mesh)
    sides = slow["sides"][0]
    angle, ratio, _ = triangle_reference(*sides)
    assert angle > 2 and min(sides) > 1  # the strategy keeps them non-degenerate
    fast = triangle_quality(mesh)
    assert fast["min_angle"][0] == pytest.approx(angle, rel=RTOL)
    assert fast["radius_ratio"][0] == pytest.approx(ratio, rel=RTOL)
    assert fast["area"][0] == pytest.approx(slow["area"][0], rel=RTOL)
    lengths = edge_quality(mesh)["length"]  # edges (0, 1), (0, 2), (1, 2)
    a, b, c = sides  # opposite nodes 0, 1, 2
    np.testing.assert_allclose(lengths, [c, b, a], rtol=RTOL)


# --- known shapes --------------------------------------------------------------


def test_equilateral_triangle_on_the_ellipsoid():
    # 5 km sides at 60N: azimuths 60 degrees apart from the first node
    mesh = one_triangle(fan(-3.0, 60.0, (30.0, 90.0), (5000.0, 5000.0)))
    q = triangle_quality(mesh)
    assert q["min_angle"][0] == pytest.approx(60.0, abs=1e-3)
    assert q["radius_ratio"][0] == pytest.approx(1.0, abs=1e-6)
    assert q["area"][0] == pytest.approx(math.sqrt(3) / 4 * 5000.0**2, rel=1e-5)
    lengths = edge_quality(mesh)["length"]
    np.testing.assert_allclose(lengths, 5000.0, rtol=2e-5)


@pytest.mark.parametrize("apex", [0.5, 2.0, 10.0])
def test_sliver_has_the_right_small_angle(apex):
    theta = math.radians(apex)
    ratio = math.sin(theta) ** 2 / ((1 + math.sin(theta / 2)) * math.sin(theta / 2))
    # planar: an isosceles triangle with its apex at the origin
    planar = one_triangle(
        [(0, 0), (1000, 0), (1000 * math.cos(theta), 1000 * math.sin(theta))],
        crs=None,
    )
    q = triangle_quality(planar)
    assert q["min_angle"][0] == pytest.approx(apex, rel=1e-9)
    assert q["radius_ratio"][0] == pytest.approx(ratio, rel=1e-9)
    assert mesh_quality(planar).planar
    # on the Earth: two 3 km geodesics leaving one node `apex` degrees apart
    earth = one_triangle(fan(20.0, 58.0, (40.0, 40.0 + apex), (3000.0, 3000.0)))
    q = triangle_quality(earth)
    assert q["min_angle"][0] == pytest.approx(apex, rel=1e-5)
    assert q["radius_ratio"][0] == pytest.approx(ratio, rel=1e-4)


def test_degenerate_triangle_has_zero_angle_ratio_and_area():
    mesh = one_triangle([(0, 0), (1, 0), (2, 0)], crs=None)
    q = triangle_quality(mesh)
    assert q["min_angle"][0] == 0 and q["radius_ratio"][0] == 0 and q["area"][0] == 0


# --- valence and boundary ------------------------------------------------------


@pytest.mark.parametrize(
    ("crs", "scale", "origin"), [(None, 100.0, (0, 0)), ("EPSG:4326", 0.01, (5, 60))]
)
def test_triangles_with_all_nodes_on_the_boundary_are_counted(crs, scale, origin):
    mesh = grid_mesh(crs, scale, origin)
    report = mesh_quality(mesh)
    assert report.all_boundary_triangles.tolist() == [2, 5]
    assert report.to_dict()["all_boundary_triangles"] == 2
    assert "all nodes on the boundary: 2" in report.summary()
    ref = mesh_quality_reference(mesh)
    assert ref["all_boundary"] == [2, 5]
    assert report.interior_valence.histogram == {6: 1} == ref["interior_valence"]
    assert report.boundary_valence.histogram == {1: 2, 2: 2, 3: 4}
    assert report.boundary_valence.histogram == ref["boundary_valence"]
    assert report.interior_valence.max == 6 and report.interior_valence.above_8 == 0
    assert report.boundary_edges == {1: 4, 2: 4}


def test_high_valence_node_is_counted():
    # a hub with 10 triangles around it
    angles = np.linspace(0, 2 * np.pi, 11)[:-1]
    points = np.vstack([[0, 0], np.column_stack([np.cos(angles), np.sin(angles)])])
    triangles = [[0, 1 + k, 1 + (k + 1) % 10] for k in range(10)]
    edges = [[1 + k, 1 + (k + 1) % 10] for k in range(10)]
    mesh = Mesh(points * 1000, triangles, edges, [1] * 10, 1, None)
    report = mesh_quality(mesh)
    assert report.interior_valence.histogram == {10: 1}
    assert report.interior_valence.above_8 == 1
    assert report.boundary_valence.histogram == {2: 10}
    assert len(report.all_boundary_triangles) == 0


# --- size ------------------------------------------------------------------------


def test_size_argument_overrides_point_data(lonlat_mesh):
    default = mesh_quality(lonlat_mesh)
    doubled = mesh_quality(lonlat_mesh, size=2 * lonlat_mesh.point_data["size"])
    assert doubled.edge_ratio.p50 == pytest.approx(default.edge_ratio.p50 / 2)
    bare = Mesh(
        lonlat_mesh.points,
        lonlat_mesh.triangles,
        lonlat_mesh.boundary_edges,
        lonlat_mesh.boundary_ids,
        1,
        lonlat_mesh.crs,
    )
    assert mesh_quality(bare).edge_ratio is None
    assert mesh_quality(bare).to_dict()["edge_length_over_size"] is None
    assert "edge length" not in mesh_quality(bare).summary()


def test_generated_edges_are_near_their_target(lonlat_mesh):
    e = mesh_quality(lonlat_mesh).edge_ratio
    assert 0.7 < e.p50 < 1.3  # Gmsh follows the size field
    assert e.within > 0.95


def test_bad_size_is_named():
    mesh = grid_mesh()
    with pytest.raises(ValueError, match=r"size has shape \(4,\), expected \(9,\)"):
        mesh_quality(mesh, size=np.ones(4))
    bad = np.ones(9)
    bad[3] = -2.0
    with pytest.raises(ValueError, match=r"size\[3\] is -2.0"):
        mesh_quality(mesh, size=bad)
    bad[3] = np.nan
    with pytest.raises(ValueError, match=r"point_data\['size'\]\[3\] is nan"):
        mesh_quality(mesh.with_point_data(size=bad))


def test_bad_mesh_is_refused():
    with pytest.raises(TypeError, match="mesh is a dict"):
        mesh_quality({})
    empty = Mesh(np.zeros((3, 2)), np.zeros((0, 3), int), [], [], 1, None)
    with pytest.raises(ValueError, match="no triangles"):
        mesh_quality(empty)
    with pytest.raises(ValueError, match="expected a geographic or projected CRS"):
        triangle_quality(grid_mesh("EPSG:4978"))
    far = grid_mesh("EPSG:4326", 100.0, (0, 0))  # latitudes 0, 100, 200
    with pytest.raises(ValueError, match=r"points\[3\] = \(0.0, 100.0\).*6 such"):
        triangle_quality(far)


def test_inputs_are_not_changed(lonlat_mesh):
    points = lonlat_mesh.points.copy()
    triangles = lonlat_mesh.triangles.copy()
    size = lonlat_mesh.point_data["size"].copy()
    mesh_quality(lonlat_mesh)
    np.testing.assert_array_equal(lonlat_mesh.points, points)
    np.testing.assert_array_equal(lonlat_mesh.triangles, triangles)
    np.testing.assert_array_equal(lonlat_mesh.point_data["size"], size)


# --- outputs ---------------------------------------------------------------------


def test_report_as_data_and_text(lonlat_mesh):
    """to_dict() is JSON as it is; summary() is its text (files: tests/io)."""
    report = mesh_quality(lonlat_mesh)
    data = report.to_dict()
    assert json.loads(json.dumps(data)) == data
    assert data["boundary_edges"]["3"] == {
        "name": "rock",
        "kind": "shoreline",
        "edges": int((lonlat_mesh.boundary_ids == 3).sum()),
    }
    assert data["lengths"].startswith("on the WGS84 ellipsoid")
    assert data["nodes"] == len(lonlat_mesh.points)
    assert data["triangles"] == len(lonlat_mesh.triangles)
    assert data["all_boundary_triangles"] == len(report.all_boundary_triangles)
    assert data["min_angle_deg"]["min"] == pytest.approx(report.min_angle.min, 1e-6)
    assert data["edge_length_over_size"]["edges"] == report.edge_ratio.edges
    histogram = data["valence"]["interior"]["histogram"]
    assert list(histogram) == sorted(histogram, key=int)
    assert sum(histogram.values()) == report.interior_valence.nodes
    text = report.summary()
    assert "south (open)" in text and "rock (shoreline)" in text
    assert f"{report.triangles:,} triangles" in text
    assert "edges in [0.5, 2]" in text
    assert not text.endswith("\n") and len(text.splitlines()) == 9
    for stats in (report.min_angle, report.radius_ratio, report.edge_ratio):
        assert stats.summary() in text
    assert report.interior_valence.to_dict()["nodes"] == report.interior_valence.nodes
    without_size = mesh_quality(grid_mesh("EPSG:4326", 0.01, (5, 60)))
    assert without_size.to_dict()["edge_length_over_size"] is None
    assert len(without_size.summary().splitlines()) == 8


@pytest.mark.parametrize("which", ["generated", "grid"])
def test_report_agrees_with_the_msh_file_read_by_meshio(which, request, tmp_path):
    if which == "generated":
        mesh = request.getfixturevalue("lonlat_mesh")
    else:  # two triangles with all nodes on the boundary
        mesh = grid_mesh("EPSG:4326", 0.01, (5, 60))
    path = tmp_path / "mesh.msh"
    write_msh(path, mesh)
    data = meshio.read(path)
    points = data.points[:, :2]
    triangles = np.concatenate([c.data for c in data.cells if c.type == "triangle"])
    lines = np.concatenate([c.data for c in data.cells if c.type == "line"])
    # minimum angle from geodesic sides, vectorised the other way round
    p = points[triangles]
    sides = np.column_stack(
        [
            GEOD.inv(p[:, j, 0], p[:, j, 1], p[:, k, 0], p[:, k, 1])[2]
            for j, k in ((1, 2), (2, 0), (0, 1))
        ]
    )
    a2 = sides**2
    cosines = [
        (a2[:, (k + 1) % 3] + a2[:, (k + 2) % 3] - a2[:, k])
        / (2 * sides[:, (k + 1) % 3] * sides[:, (k + 2) % 3])
        for k in range(3)
    ]
    min_angle = np.degrees(np.arccos(np.clip(np.max(cosines, axis=0), -1, 1))).min()
    on_line = np.isin(triangles, np.unique(lines))
    report = mesh_quality(mesh)
    assert report.nodes == len(points)
    assert report.triangles == len(triangles)
    assert sum(report.boundary_edges.values()) == len(lines)
    assert report.min_angle.min == pytest.approx(min_angle, rel=RTOL)
    all_boundary = int(on_line.all(axis=1).sum())
    assert len(report.all_boundary_triangles) == all_boundary
    if which == "grid":
        assert all_boundary == 2
