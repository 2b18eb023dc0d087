"""Stable time steps and Courant numbers: fast code against a literal loop."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer
from reference_measures import delaunay_meshes, time_step_reference

from coastmesh.geometry.earth import GRAVITY
from coastmesh.meshing import (
    QualityReport,
    TimeStepStats,
    element_time_steps,
    mesh_quality,
)
from coastmesh.types import Mesh

RTOL = 1e-6


def triangle_mesh(points, depth, crs=None):
    return Mesh(
        points,
        [[0, 1, 2]],
        [[0, 1], [1, 2], [2, 0]],
        [1, 1, 1],
        1,
        crs,
        {"depth": depth},
    )


def square_grid(n):
    """An n x n grid of 500 m squares, each cut in two: its nodes and triangles."""
    points = [(i * 500.0, j * 500.0) for j in range(n + 1) for i in range(n + 1)]
    triangles = []
    for j in range(n):
        for i in range(n):
            a = (n + 1) * j + i
            triangles += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return points, triangles


def strip(depth):
    """Four planar triangles in a row, 1 km squares cut in two: nodes 0-2 below,
    3-5 above."""
    points = [(0, 0), (1000, 0), (2000, 0), (0, 1000), (1000, 1000), (2000, 1000)]
    triangles = [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]
    ring = [0, 1, 2, 5, 4, 3]
    edges = [[ring[k], ring[(k + 1) % 6]] for k in range(6)]
    return Mesh(points, triangles, edges, [1] * 6, 1, None, {"depth": depth})


# --- against the literal reference -------------------------------------------


@given(delaunay_meshes(), st.floats(0, 3), st.floats(1, 600))
@settings(max_examples=60, deadline=None)
def test_random_planar_meshes_match_the_reference(mesh, velocity, dt):
    fast = element_time_steps(mesh, velocity=velocity, dt=dt)
    slow = time_step_reference(mesh, velocity, dt)
    scale = 1e-9 * 10_000.0  # metres: slivers on the hull lose digits in Heron
    np.testing.assert_allclose(fast["r_in"], slow["r_in"], rtol=RTOL, atol=scale)
    np.testing.assert_allclose(fast["wave_speed"], slow["wave_speed"], rtol=1e-12)
    np.testing.assert_allclose(fast["courant"], slow["courant"], rtol=RTOL)
    finite = np.isfinite(slow["dt"])
    assert np.array_equal(np.isfinite(fast["dt"]), finite)
    np.testing.assert_allclose(
        fast["dt"][finite], slow["dt"][finite], rtol=RTOL, atol=scale
    )

    report = mesh_quality(mesh, dt=dt, velocity=velocity).time_step
    if finite.any():
        assert report.min == pytest.approx(slow["dt"][finite].min(), rel=RTOL, abs=1e-8)
        assert report.p1 == pytest.approx(
            np.percentile(slow["dt"][finite], 1), rel=RTOL, abs=1e-8
        )
    assert report.dry == int((~finite).sum())
    assert report.courant.max == pytest.approx(slow["courant"].max(), rel=RTOL)


def test_real_mesh_matches_the_geodesic_reference(mesh_with_islands):
    """The islands mesh (UTM 30N, 250 m, depth 5 to 45 m) against geodesic sides."""
    mesh = mesh_with_islands
    fast = element_time_steps(mesh, velocity=1.5, dt=20.0)
    slow = time_step_reference(mesh, 1.5, 20.0)
    for key in ("r_in", "wave_speed", "dt", "courant"):
        np.testing.assert_allclose(fast[key], slow[key], rtol=RTOL, err_msg=key)

    report = mesh_quality(
        mesh, dt=20.0, velocity=1.5, courant_max=1.5, courant_min=1.0
    ).time_step
    first = int(np.argmin(slow["dt"]))
    assert report.min == pytest.approx(slow["dt"][first], rel=RTOL)
    assert report.at.index == first
    centroid = mesh.points[mesh.triangles[first]].mean(axis=0)
    assert (report.at.x, report.at.y) == pytest.approx(tuple(centroid))
    to_lonlat = Transformer.from_crs(mesh.crs, "EPSG:4326", always_xy=True)
    assert (report.at.lon, report.at.lat) == pytest.approx(
        to_lonlat.transform(*centroid), abs=1e-9
    )
    p1 = np.percentile(slow["dt"], 1)
    assert report.p1 == pytest.approx(p1, rel=RTOL)
    assert report.min_over_p1 == pytest.approx(slow["dt"][first] / p1, rel=RTOL)
    assert report.p50 == pytest.approx(np.median(slow["dt"]), rel=RTOL)
    c = report.courant
    assert c.dt == 20.0 and c.courant_max == 1.5 and c.courant_min == 1.0
    assert c.max == pytest.approx(slow["courant"].max(), rel=RTOL)
    assert c.at.index == int(np.argmax(slow["courant"]))
    assert c.p99 == pytest.approx(np.percentile(slow["courant"], 99), rel=RTOL)
    assert c.p50 == pytest.approx(np.median(slow["courant"]), rel=RTOL)
    assert c.above == int((slow["courant"] > 1.5).sum()) > 0
    assert c.below == int((slow["courant"] < 1.0).sum()) > 0
    # the wave is fastest in the east (depth 5 + x / 100 m): the limit is there;
    # Gmsh's even 250 m triangles: no single one throttles the model
    assert centroid[0] > 2000
    assert 1 < report.min < 5 and 0.6 < report.min_over_p1 <= 1


# --- known values --------------------------------------------------------------


@pytest.mark.parametrize("side", [10.0, 1000.0, 25_000.0])
def test_equilateral_inscribed_radius(side):
    h = side * math.sqrt(3) / 2
    mesh = triangle_mesh([(0, 0), (side, 0), (side / 2, h)], [4.0, 9.0, 16.0])
    q = element_time_steps(mesh, dt=2.0)
    r_in = side / (2 * math.sqrt(3))
    assert q["r_in"][0] == pytest.approx(r_in, rel=1e-12)
    assert q["mean_edge"][0] == pytest.approx(side, rel=1e-12)
    speed = math.sqrt(GRAVITY * 16.0)  # the deepest node
    assert q["wave_speed"][0] == pytest.approx(speed, rel=1e-12)
    assert q["dt"][0] == pytest.approx(r_in / speed, rel=1e-12)
    assert q["courant"][0] == pytest.approx(2.0 * speed / side, rel=1e-12)
    # at its own stable step, an equilateral triangle's Courant number is 0.29
    at_limit = element_time_steps(mesh, dt=float(q["dt"][0]))["courant"][0]
    assert at_limit == pytest.approx(1 / (2 * math.sqrt(3)), rel=1e-12)


def test_equilateral_on_the_ellipsoid():
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    lon, lat = -3.0, 59.0
    tips = [geod.fwd(lon, lat, az, 5000.0)[:2] for az in (30.0, 90.0)]
    mesh = triangle_mesh([(lon, lat), *tips], [50.0, 50.0, 50.0], "EPSG:4326")
    q = element_time_steps(mesh)
    assert q["r_in"][0] == pytest.approx(5000.0 / (2 * math.sqrt(3)), rel=2e-5)
    assert "courant" not in q


def test_dry_and_missing_depths():
    # triangles 0, 1 and 3 dry (no node below 0 m), 2 without any depth
    mesh = strip(np.array([-1.0, np.nan, np.nan, -3.0, -2.0, np.nan]))
    still = element_time_steps(mesh, dt=10.0)
    assert np.isinf(still["dt"][[0, 1]]).all()
    assert (still["wave_speed"][[0, 1]] == 0).all()
    assert np.isnan(still["dt"][2]) and np.isnan(still["courant"][2])
    assert still["depth"][3] == -2.0  # nodes 1, 5, 4: the NaNs are skipped
    report = mesh_quality(mesh, dt=10.0).time_step
    assert report.dry == 3 and report.no_depth == 1
    assert report.min == math.inf and report.at is None
    data = report.to_dict()
    assert data["min"] is None and json.loads(json.dumps(data)) == data
    moving = mesh_quality(mesh, velocity=2.0).time_step
    assert moving.dry == 0 and moving.no_depth == 1
    q = element_time_steps(mesh, velocity=2.0)
    assert moving.min == pytest.approx(np.nanmin(q["dt"]))
    assert q["wave_speed"][0] == 2.0


def test_one_element_throttles_the_model():
    """A 20 x 20 grid of 800 triangles, 30 m deep but for one 3000 m hole at the
    corner node (20, 0), which is in a single triangle: ten times as fast."""
    n = 20
    points, triangles = square_grid(n)
    depth = np.full(len(points), 30.0)
    depth[n] = 3000.0
    mesh = Mesh(points, triangles, [[0, 1]], [1], 1, None, {"depth": depth})
    report = mesh_quality(mesh).time_step
    assert report.at.index == 2 * (n - 1)  # the one triangle at node (20, 0)
    assert report.min_over_p1 == pytest.approx(0.1, rel=1e-9)
    assert "min / p1 0.10 (target >= 0.6)" in report.summary()
    even = mesh_quality(mesh.with_point_data(depth=np.full(len(points), 30.0)))
    assert even.time_step.min_over_p1 == pytest.approx(1.0)


def test_the_slowest_elements_are_the_smallest_steps():
    """The listed elements are the ten smallest time steps, smallest first, with
    their depth and radius as element_time_steps gives them."""
    rng = np.random.default_rng(3)
    n = 12
    points, triangles = square_grid(n)
    depth = rng.uniform(5.0, 4000.0, len(points))
    mesh = Mesh(points, triangles, [[0, 1]], [1], 1, None, {"depth": depth})
    report = mesh_quality(mesh).time_step
    q = element_time_steps(mesh)
    order = np.argsort(q["dt"], kind="stable")[:10]
    assert [e.at.index for e in report.slowest] == order.tolist()
    assert [e.dt for e in report.slowest] == pytest.approx(q["dt"][order])
    assert report.slowest[0].dt == report.min
    assert report.slowest[0].over_p1 == pytest.approx(report.min_over_p1)
    assert [e.depth for e in report.slowest] == pytest.approx(q["depth"][order])
    assert [e.r_in for e in report.slowest] == pytest.approx(q["r_in"][order])
    few = mesh_quality(triangle_mesh([(0, 0), (1, 0), (0, 1)], [5.0] * 3))
    assert len(few.time_step.slowest) == 1


def test_a_place_across_the_antimeridian_is_on_the_sphere():
    """A lon/lat triangle across the antimeridian is placed at its centre there,
    not at the mean of its longitudes (near 0)."""
    mesh = triangle_mesh(
        [(179.5, -16.0), (-179.5, -16.0), (179.8, -15.5)], [100.0] * 3, "EPSG:4326"
    )
    at = mesh_quality(mesh).time_step.at
    assert abs(abs(at.lon) - 179.93) < 0.05 and at.lat == pytest.approx(
        -15.83, abs=0.02
    )


# --- in the quality report -----------------------------------------------------


def test_quality_report_has_the_time_step(mesh_with_islands):
    report = mesh_quality(mesh_with_islands, dt=15.0, courant_max=0.5)
    assert isinstance(report, QualityReport)
    assert isinstance(report.time_step, TimeStepStats)
    data = report.to_dict()
    assert json.loads(json.dumps(data)) == data
    ts = data["time_step"]
    assert ts["min"] == float(f"{report.time_step.min:.6g}")
    assert ts["at"]["index"] == report.time_step.at.index
    assert ts["courant"]["dt"] == 15.0 and ts["courant"]["courant_min"] is None
    assert ts["courant"]["above"] == report.time_step.courant.above
    lines = report.summary().splitlines()
    k = lines.index(f"  {report.time_step.summary()}")
    assert lines[k + 1].strip() == report.time_step.courant.summary()
    assert "Courant number at dt = 15 s" in lines[k + 1] and "above 0.5" in lines[k + 1]
    # then the ten slowest elements, smallest first, each at its place
    assert lines[k + 2] == "  slowest elements (smallest stable time step):"
    listed = [e.summary() for e in report.time_step.slowest]
    assert [line.strip() for line in lines[k + 3 : k + 13]] == listed
    assert len(ts["slowest"]) == 10
    assert ts["slowest"][0]["at"]["index"] == report.time_step.at.index
    # no dt: no Courant block; no depth: no time-step block
    assert mesh_quality(mesh_with_islands).time_step.courant is None
    bare = Mesh(
        mesh_with_islands.points,
        mesh_with_islands.triangles,
        mesh_with_islands.boundary_edges,
        mesh_with_islands.boundary_ids,
        1,
        mesh_with_islands.crs,
    )
    assert mesh_quality(bare, dt=15.0).time_step is None
    assert mesh_quality(bare).to_dict()["time_step"] is None


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"velocity": -1.0}, r"velocity = -1.0: must be a finite speed >= 0"),
        ({"velocity": math.nan}, r"velocity = nan"),
        ({"dt": 0.0}, r"dt = 0.0: must be finite and > 0"),
        ({"dt": 5.0, "courant_max": -1.0}, r"courant_max = -1.0"),
        ({"courant_max": 1.0}, r"need a model time step dt"),
        (
            {"dt": 5.0, "courant_max": 0.5, "courant_min": 0.5},
            r"courant_min = 0.5 must be below courant_max = 0.5",
        ),
    ],
)
def test_bad_options_are_named(options, message):
    mesh = strip(np.full(6, 10.0))
    with pytest.raises(ValueError, match=message):
        mesh_quality(mesh, **options)


def test_bad_depth_is_named():
    mesh = strip(np.full(6, 10.0))
    bare = Mesh(mesh.points, mesh.triangles, mesh.boundary_edges, [1] * 6, 1, None)
    with pytest.raises(ValueError, match="has no 'depth'"):
        element_time_steps(bare)
    with pytest.raises(TypeError, match="mesh is a dict"):
        element_time_steps({})
    wide = bare.with_point_data(depth=np.ones((6, 2)))
    with pytest.raises(ValueError, match=r"depth'\] has shape \(6, 2\)"):
        mesh_quality(wide)


def test_inputs_are_not_changed(mesh_with_islands):
    depth = mesh_with_islands.point_data["depth"].copy()
    points = mesh_with_islands.points.copy()
    element_time_steps(mesh_with_islands, velocity=1.0, dt=5.0)
    np.testing.assert_array_equal(mesh_with_islands.point_data["depth"], depth)
    np.testing.assert_array_equal(mesh_with_islands.points, points)
