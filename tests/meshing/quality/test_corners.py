"""Sharp boundary corners and channels one element wide, against literal loops."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from reference_measures import (
    channel_reference,
    corner_reference,
    delaunay_meshes,
)

from coastmesh.case.pipeline.advice import warn_avoidable_corners
from coastmesh.errors import CoastmeshWarning
from coastmesh.meshing import boundary_angles, generate_mesh, mesh_quality
from coastmesh.meshing.quality.corners import MAX_LISTED_CORNERS, SHARP_ANGLE
from coastmesh.meshing.quality.mesh_quality import triangle_quality
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

X0, Y0 = 500_000.0, 6_500_000.0  # UTM 30N on its central meridian, 58.6N


@pytest.fixture(scope="module")
def wedge_mesh():
    """A triangle of sea with corners of 20 degrees at A (between shorelines 1
    and 3: a fjord head), 40 at B (shoreline 1 meets the open boundary 2) and
    120 at C; A to B is 10 km, 300 m elements."""
    a = (X0, Y0)
    b = (X0 + 10_000.0, Y0)
    ac = 10_000.0 * math.sin(math.radians(40)) / math.sin(math.radians(120))
    c = (X0 + ac * math.cos(math.radians(20)), Y0 + ac * math.sin(math.radians(20)))
    polygon = shapely.Polygon([a, b, c, a])
    segments = (
        BoundarySegment([a, b], "shoreline", "coast", 1),
        BoundarySegment([b, c], "open", "sea", 2),
        BoundarySegment([c, a], "shoreline", "head", 3),
    )
    domain = Domain(polygon, segments, crs="EPSG:32630")
    grid = SizeGrid([X0, X0 + 10_000.0], [Y0, Y0 + 3_000.0], np.full((2, 2), 300.0))
    return generate_mesh(domain, grid), (a, b, c)


# --- against the literal reference -------------------------------------------


@given(delaunay_meshes())
@settings(max_examples=60, deadline=None)
def test_random_planar_meshes_match_the_reference(mesh):
    fast = boundary_angles(mesh)
    slow = corner_reference(mesh)
    assert fast["nodes"].tolist() == sorted(slow)
    want = np.array([slow[k] for k in sorted(slow)])
    np.testing.assert_allclose(fast["angle"], want, atol=1e-6)
    # a convex hull: the interior angles add up to (k - 2) 180 degrees
    assert fast["angle"].sum() == pytest.approx(180 * (len(want) - 2), abs=1e-6)

    report = mesh_quality(mesh)
    sharp = [node for node, angle in slow.items() if angle < SHARP_ANGLE]
    assert report.corners.sharp == len(sharp)
    assert report.corners.boundary_nodes == len(slow)
    assert report.corners.min_angle == pytest.approx(min(slow.values()), abs=1e-6)
    listed = [c.node.index for c in report.corners.sharpest]
    assert len(sharp) <= MAX_LISTED_CORNERS and sorted(listed) == sorted(sharp)
    angles = [c.angle for c in report.corners.sharpest]
    assert angles == sorted(angles)
    assert report.channel_spanning_triangles.tolist() == channel_reference(mesh)
    away = [
        ratio
        for tri, ratio in zip(
            mesh.triangles, triangle_quality(mesh)["radius_ratio"], strict=True
        )
        if not any(int(k) in sharp for k in tri)
    ]
    assert report.corners.triangles == len(mesh.triangles) - len(away)
    if away:
        assert report.radius_ratio_away_from_corners.min == pytest.approx(min(away))
        assert report.radius_ratio_away_from_corners.below_0_25 == sum(
            r < 0.25 for r in away
        )
    else:
        assert report.radius_ratio_away_from_corners is None


def test_real_mesh_matches_the_geodesic_reference(mesh_with_islands):
    """The islands mesh: square corners of 90 degrees, islands' corners reflex."""
    mesh = mesh_with_islands
    fast = boundary_angles(mesh)
    slow = corner_reference(mesh)
    assert fast["nodes"].tolist() == sorted(slow)
    want = np.array([slow[k] for k in sorted(slow)])
    np.testing.assert_allclose(fast["angle"], want, atol=1e-6)
    x, y = mesh.points[fast["nodes"]].T
    corner = np.isin(x, (0, 4000)) & np.isin(y, (0, 3000))
    np.testing.assert_allclose(fast["angle"][corner], 90.0, atol=1e-3)
    assert corner.sum() == 4
    square = np.isin(x, (1000, 1500)) & np.isin(y, (1000, 1500))
    np.testing.assert_allclose(fast["angle"][square], 270.0, atol=1e-3)
    tip = (x == 2500) & (y == 1000)  # the triangular island's 26.6 degree tip
    assert fast["angle"][tip] == pytest.approx(360 - math.degrees(math.atan(0.5)))
    straight = ~corner & ~square & ~np.isin(x, (2500, 3000))
    np.testing.assert_allclose(fast["angle"][straight], 180.0, atol=1e-3)
    report = mesh_quality(mesh)
    assert report.corners.sharp == 0 and report.corners.sharpest == ()
    assert report.corners.min_angle == pytest.approx(90.0, abs=1e-3)
    assert report.radius_ratio_away_from_corners == report.radius_ratio


# --- known shapes --------------------------------------------------------------


def test_sharp_corners_of_a_wedge(wedge_mesh):
    mesh, (a, b, _) = wedge_mesh
    report = mesh_quality(mesh)
    corners = report.corners
    assert corners.sharp == 2 and corners.avoidable == 1
    head, meet = corners.sharpest  # sharpest first
    assert head.angle == pytest.approx(20.0, abs=1e-3)
    assert (head.node.x, head.node.y) == pytest.approx(a)
    assert head.node.lat == pytest.approx(58.6, abs=0.05)
    assert head.node.lon == pytest.approx(-3.0, abs=1e-6)
    assert sorted(head.boundary_ids) == [1, 3]
    assert head.kinds == ("shoreline", "shoreline") and not head.avoidable
    assert meet.angle == pytest.approx(40.0, abs=1e-3)
    assert (meet.node.x, meet.node.y) == pytest.approx(b)
    assert sorted(meet.boundary_ids) == [1, 2]
    assert sorted(meet.kinds) == ["open", "shoreline"] and meet.avoidable
    # the triangles at the two corners are left out of the radius-ratio target
    at_corner = np.isin(mesh.triangles, [head.node.index, meet.node.index]).any(axis=1)
    assert corners.triangles == int(at_corner.sum()) >= 2
    ratio = triangle_quality(mesh)["radius_ratio"]
    assert report.radius_ratio_away_from_corners.min == pytest.approx(
        ratio[~at_corner].min()
    )
    assert report.radius_ratio_away_from_corners.below_0_25 == 0
    text = report.summary()
    assert "boundary corners sharper than 45 deg: 2 (1 avoidable" in text
    assert (
        "sharpest 20.0 deg at node" in text and "(shoreline/shoreline), forced" in text
    )
    assert "away from sharp corners, radius ratio: min" in text
    data = report.to_dict()
    assert json.loads(json.dumps(data)) == data
    assert data["corners"]["sharp"] == 2
    assert data["corners"]["sharpest"][0]["kinds"] == ["shoreline", "shoreline"]
    assert data["corners"]["sharpest"][1]["avoidable"] is True
    assert data["radius_ratio_away_from_corners"]["below_0_25"] == 0


def test_the_avoidable_corner_is_warned_of_with_its_place(wedge_mesh):
    mesh, _ = wedge_mesh
    quality = mesh_quality(mesh)
    with pytest.warns(CoastmeshWarning) as caught:
        warn_avoidable_corners(quality, mesh)
    message = str(caught[0].message)
    assert "open boundaries meet the coast at under 45 deg at 1 places" in message
    assert "(coast/sea at 40.0 deg (-2.8277, 58.6402))" in message  # 20 deg: forced
    assert "move the end of the open boundary" in message


def test_wedge_tip_in_a_fan():
    """Five triangles fanning out from node 0 over 30 degrees: one sharp corner."""
    angles = np.radians(np.linspace(0, 30, 6))
    points = np.vstack(
        [[0, 0], 1000 * np.column_stack([np.cos(angles), np.sin(angles)])]
    )
    triangles = [[0, k, k + 1] for k in range(1, 6)]
    edges = [[0, 1], *([k, k + 1] for k in range(1, 6)), [6, 0]]
    mesh = Mesh(
        points,
        triangles,
        edges,
        [1] + [2] * 5 + [1],
        1,
        None,
        boundary_kinds={1: "shoreline", 2: "open"},
    )
    q = boundary_angles(mesh)
    assert q["nodes"].tolist() == list(range(7))
    assert q["angle"][0] == pytest.approx(30.0, rel=1e-12)
    report = mesh_quality(mesh).corners
    assert report.sharp == 1 and report.avoidable == 0
    assert report.sharpest[0].boundary_ids == (1, 1)
    assert report.sharpest[0].node.lon is None
    assert report.sharpest[0].summary().startswith("30.0 deg at node 0 (0, 0), ids 1/1")


def test_channel_one_element_wide():
    """A strip of triangles between two banks: all nodes on the boundary; the
    triangles at the ends (1 and 6) have two boundary sides, the six others one."""
    n = 5
    points = [(i * 100.0, 0.0) for i in range(n)] + [
        (i * 100.0, 80.0) for i in range(n)
    ]
    triangles = []
    for i in range(n - 1):
        triangles += [[i, i + 1, n + i + 1], [i, n + i + 1, n + i]]
    ring = [*range(n), *range(2 * n - 1, n - 1, -1)]
    edges = [[ring[k], ring[(k + 1) % len(ring)]] for k in range(len(ring))]
    mesh = Mesh(points, triangles, edges, [1] * len(edges), 1, None)
    report = mesh_quality(mesh)
    assert len(report.all_boundary_triangles) == 8
    assert report.channel_spanning_triangles.tolist() == channel_reference(mesh)
    assert report.channel_spanning_triangles.tolist() == [0, 2, 3, 4, 5, 7]
    assert report.to_dict()["channel_spanning_triangles"] == 6
    assert "spanning a channel: 6" in report.summary()


def test_untagged_boundary_edges_have_no_id():
    mesh = Mesh([[0, 0], [1000, 0], [1000, 200]], [[0, 1, 2]], [[0, 1]], [4], 1, None)
    corners = mesh_quality(mesh).corners
    assert corners.sharp == 1  # 11.3 degrees at node 0; 90 and 78.7 elsewhere
    tip = corners.sharpest[0]
    assert tip.node.index == 0 and sorted(tip.boundary_ids, key=str) == [4, None]
    assert tip.kinds == (None, None) and not tip.avoidable
