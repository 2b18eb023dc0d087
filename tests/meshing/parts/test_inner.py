"""Regions and nodes inside the water: farms and footprints as faces of their own."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.meshing import CleanupOptions, generate_mesh
from coastmesh.meshing.parts.inner import Inner, InnerPlane, label_regions, node_ring
from coastmesh.types import BoundarySegment, Domain, SizeGrid
from coastmesh.types.topology import unique_edges

RING = [[0, 0], [3000, 0], [3000, 2000], [0, 2000], [0, 0]]
FARM = shapely.Polygon([[1300, 900], [1700, 900], [1700, 1100], [1300, 1100]])
TURBINE = (1600.0, 1000.0)


def _disc(cx, cy, diameter, h):
    n = int(np.ceil(np.pi * diameter / h))
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return shapely.Polygon(
        np.column_stack([cx + diameter / 2 * np.cos(t), cy + diameter / 2 * np.sin(t)])
    )


DISC = _disc(1400.0, 1000.0, 18.0, 4.5)


def _case(width=3000.0):
    ring = [[0, 0], [width, 0], [width, 2000], [0, 2000], [0, 0]]
    domain = Domain(
        shapely.Polygon(ring),
        (BoundarySegment(ring, "open", "sea", 3),),
        crs="EPSG:32630",
    )
    x, y = np.arange(0, width + 1, 10.0), np.arange(0, 2001, 10.0)
    xx, yy = np.meshgrid(x, y)
    # 4.5 m at the footprint, 20 m in the farm, growing at 0.2 to 200 m
    near = np.hypot(xx - 1400, yy - 1000)
    in_farm = np.maximum(
        np.maximum(1300 - xx, xx - 1700), np.maximum(900 - yy, yy - 1100)
    ).clip(0)
    h = np.minimum(4.5 + 0.2 * np.maximum(near - 9, 0), 20 + 0.2 * in_farm)
    return domain, SizeGrid(x, y, np.clip(h, 4.5, 200.0))


@pytest.fixture(scope="module")
def meshed():
    domain, size = _case()
    inner = Inner([(FARM, 20, "farm"), (DISC, 100, "T1")], np.array([TURBINE]))
    cleanup = CleanupOptions(True, 8, 30.0, True)
    return generate_mesh(domain, size, inner=inner, cleanup=cleanup), size


def _areas(mesh):
    p = mesh.points[mesh.triangles]
    return 0.5 * np.abs(
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    )


def test_each_region_is_its_polygon_exactly(meshed):
    mesh, _ = meshed
    area = _areas(mesh)
    assert mesh.region_ids == [1, 20, 100]
    assert mesh.region_names == {20: "farm", 100: "T1"}
    assert area[mesh.regions == 100].sum() == pytest.approx(DISC.area, rel=1e-12)
    in_farm = np.isin(mesh.regions, [20, 100])  # the footprint is in the farm
    assert area[in_farm].sum() == pytest.approx(FARM.area, rel=1e-12)


def test_outlines_are_mesh_edges_and_the_mesh_conforms(meshed):
    mesh, _ = meshed
    _, count = unique_edges(mesh.triangles, len(mesh.points))
    assert set(count.tolist()) == {1, 2}  # no edge of three triangles, no gap
    assert sorted(set(mesh.boundary_ids.tolist())) == [3]  # outlines are inside
    # every node of each noded outline is a node of the mesh, exactly
    nodes = {tuple(p) for p in mesh.points.tolist()}
    for polygon in (FARM, DISC):
        ring = node_ring(
            np.asarray(polygon.exterior.coords),
            lambda xy: np.full(len(xy), 1.0e9),  # the vertices alone
        )
        assert all(tuple(p) in nodes for p in ring.tolist())
    # the edges between two regions are exactly the outlines' sides
    regions = mesh.regions
    tri_of_edge = {}
    for t, tri in enumerate(mesh.triangles.tolist()):
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            tri_of_edge.setdefault((min(a, b), max(a, b)), []).append(t)
    between = [e for e, ts in tri_of_edge.items() if len({regions[t] for t in ts}) > 1]
    mids = mesh.points[np.array(between)].mean(axis=1)
    on = shapely.distance(
        shapely.MultiLineString([FARM.exterior, DISC.exterior]), shapely.points(mids)
    )
    assert on.max() < 1e-9


def test_a_turbine_is_a_node_at_its_place(meshed):
    mesh, _ = meshed
    assert np.hypot(*(mesh.points - TURBINE).T).min() == 0.0


def test_elements_inside_follow_the_size_and_keep_their_shape(meshed):
    mesh, _ = meshed
    from coastmesh.meshing.cleanup.smoothing import min_angles

    angles = min_angles(mesh.points, mesh.triangles)
    edge = np.sqrt(_areas(mesh) * 4 / np.sqrt(3))  # equilateral of that area
    for pid, h in ((100, 4.5), (20, 20.0)):
        inside = mesh.regions == pid
        assert np.percentile(angles[inside], 1) >= 30.0
        if pid == 20:  # away from the footprint the farm is at its 20 m
            far = inside & (
                np.hypot(*(mesh.points[mesh.triangles].mean(1) - (1400, 1000)).T) > 150
            )
            assert 0.8 <= np.median(edge[far]) / h <= 1.25
        else:
            assert 0.8 <= np.median(edge[inside]) / h <= 1.25


def test_a_cut_that_would_cross_a_region_means_one_part():
    from coastmesh.meshing.engine import _cut

    ring = np.array([[0, 0], [20000, 0], [20000, 2000], [0, 2000], [0, 0]], float)
    water = shapely.Polygon(ring)
    size = SizeGrid(
        np.arange(0, 20001, 500.0), np.arange(0, 2001, 500.0), np.full((5, 41), 20.0)
    )  # 230,000 triangles: two parts
    farm = shapely.box(10100, 900, 10400, 1100)  # where the one cut goes
    plane = InnerPlane(
        [np.asarray(farm.exterior.coords)], [farm], [20], ["farm"], np.empty((0, 2))
    )
    empty = InnerPlane([], [], [], [], np.empty((0, 2)))
    _, chords, wanted = _cut([(ring, 3)], water, size, 2, empty)
    assert len(chords) == 1 and wanted == 2  # without the farm: cut in two
    assert shapely.intersects(shapely.LineString(chords[0]), farm)
    with pytest.warns(UserWarning, match="a farm, a turbine footprint"):
        _, chords, wanted = _cut([(ring, 3)], water, size, 2, plane)
    assert chords == [] and wanted == 1


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=1, max_size=40)
)
def test_label_regions_is_the_innermost_polygon_holding_each_centre(offsets):
    outer = shapely.box(-40, -40, 40, 40)
    inner = shapely.box(-10, -10, 10, 10)
    plane = InnerPlane(
        [np.asarray(p.exterior.coords) for p in (outer, inner)],
        [outer, inner],
        [20, 100],
        ["farm", "T1"],
        np.empty((0, 2)),
    )
    centres = np.array(offsets)
    got = label_regions(centres, plane, 1)
    for (x, y), r in zip(offsets, got.tolist(), strict=True):
        want = 1
        if outer.contains(shapely.Point(x, y)):
            want = 20
        if inner.contains(shapely.Point(x, y)):
            want = 100
        assert r == want


def test_node_ring_keeps_every_vertex_and_splits_each_side_evenly():
    ring = np.array([[0, 0], [10, 0], [10, 3], [0, 0]], dtype=float)
    out = node_ring(ring, lambda xy: np.full(len(xy), 2.0))
    assert np.array_equal(out[0], out[-1])
    for vertex in ring[:-1]:
        assert any(np.array_equal(vertex, p) for p in out)
    sides = np.linalg.norm(np.diff(out, axis=0), axis=1)
    assert sides.max() <= 2.0 + 1e-12
    assert len(out) - 1 == 5 + 2 + int(np.ceil(np.hypot(10, 3) / 2))
