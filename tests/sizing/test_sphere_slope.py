"""The bathymetric slope term on a world lon/lat grid, against a literal reference."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.sizing.bathymetry import slope_size, slope_size_sphere


def reference_slope_sphere(depth, lat, sea, per_slope, min_depth):
    """Loops over the nodes: each difference from the neighbours with a depth
    in the sea (central, one-sided or none), east-west steps R cos(lat) dlon
    round the world, north-south steps R dlat; 0 east-west at a pole."""
    ny, nx = depth.shape[0], depth.shape[1] - 1
    dlon = math.radians(360.0 / nx)
    dy = EARTH_RADIUS * math.radians(lat[1] - lat[0])

    def known(j, i):
        return bool(sea[j, i]) and math.isfinite(depth[j, i])

    def d(j, i):
        return max(depth[j, i], min_depth)

    def derivative(here, after, before, step):
        if after is not None and before is not None:
            return (d(*after) - d(*before)) / (2 * step)
        if after is not None:
            return (d(*after) - d(*here)) / step
        if before is not None:
            return (d(*here) - d(*before)) / step
        return 0.0

    out = np.full(depth.shape, math.inf)
    for j in range(ny):
        for i in range(nx):
            if not known(j, i):
                continue
            east, west = (j, (i + 1) % nx), (j, (i - 1) % nx)
            north, south = (j + 1, i), (j - 1, i)
            gx = 0.0
            if abs(lat[j]) < 90.0:
                gx = derivative(
                    (j, i),
                    east if known(*east) else None,
                    west if known(*west) else None,
                    EARTH_RADIUS * math.cos(math.radians(lat[j])) * dlon,
                )
            gy = derivative(
                (j, i),
                north if j + 1 < ny and known(*north) else None,
                south if j > 0 and known(*south) else None,
                dy,
            )
            steep = math.hypot(gx, gy)
            if steep > 0:
                out[j, i] = 2 * math.pi * d(j, i) / (per_slope * steep)
    out[:, -1] = out[:, 0]
    return out


@st.composite
def world_depths(draw):
    """A small world grid (rows to a pole or not), random depths with NaN and
    shallow cells, and a random sea."""
    nx = draw(st.integers(4, 9))
    ny = draw(st.integers(2, 6))
    step = draw(st.floats(0.2, 25.0))
    where = draw(st.sampled_from(["north_pole", "south_pole", "free"]))
    if where == "north_pole":
        lat = 90.0 - step * np.arange(ny)[::-1]
    elif where == "south_pole":
        lat = -90.0 + step * np.arange(ny)
    else:
        lat = draw(st.floats(-89.0, 89.0 - step * (ny - 1))) + step * np.arange(ny)
    rng = np.random.default_rng(draw(st.integers(0, 2**31)))
    depth = rng.uniform(-50.0, 6000.0, (ny, nx))
    depth[rng.random((ny, nx)) < 0.1] = np.nan
    sea = rng.random((ny, nx)) < draw(st.floats(0.3, 1.0))
    return np.hstack([depth, depth[:, :1]]), lat, np.hstack([sea, sea[:, :1]])


@settings(max_examples=60, deadline=None)
@given(world_depths(), st.floats(1.0, 50.0), st.floats(0.5, 20.0))
def test_slope_on_the_sphere_matches_the_literal_reference(grid, n, min_depth):
    depth, lat, sea = grid
    fast = slope_size_sphere(depth, lat, per_slope=n, min_depth=min_depth, sea=sea)
    want = reference_slope_sphere(depth, lat, sea, n, min_depth)
    np.testing.assert_allclose(fast, want, rtol=1e-9)


@settings(max_examples=40, deadline=None)
@given(world_depths(), st.integers(0, 10_000))
def test_no_sea_node_takes_a_slope_from_land(grid, seed):
    depth, lat, sea = grid
    before = slope_size_sphere(depth, lat, per_slope=10.0, sea=sea)
    other = depth.copy()  # land heights anything at all: the sea's sizes hold
    land = ~sea
    other[land] = np.random.default_rng(seed).uniform(-9000.0, 9000.0, land.sum())
    other[:, -1] = other[:, 0]
    after = slope_size_sphere(other, lat, per_slope=10.0, sea=sea)
    np.testing.assert_array_equal(after, before)
    assert np.isinf(after[land]).all()


def test_the_gradient_takes_each_step_at_its_true_length():
    # depth 1 m deeper per km east at every latitude: d = 2000 + x / 1000,
    # x the distance east along the parallel (on a half world, then back)
    lat = np.array([0.0, 30.0, 60.0, 80.0])
    lon = np.linspace(-180.0, 180.0, 721)
    x = EARTH_RADIUS * np.cos(np.radians(lat))[:, None] * np.radians(lon)[None, :]
    depth = 4000.0 + x / 1000.0
    h = slope_size_sphere(depth, lat, per_slope=10.0)
    # away from the seam (where x jumps), |grad d| = 1e-3 at every latitude
    for j in range(len(lat)):
        d = depth[j, 360]
        assert h[j, 360] == pytest.approx(2 * math.pi * d / (10.0 * 1e-3), rel=1e-4)


def test_a_ridge_across_the_antimeridian_is_the_same_as_one_in_the_middle():
    lat = np.linspace(-60.0, 60.0, 25)
    lon = np.linspace(-180.0, 180.0, 73)[:-1]
    ridge = 4000.0 - 3000.0 * np.exp(
        -((np.minimum(lon + 180.0, 180.0 - lon) / 10) ** 2)
    )
    depth = np.repeat(ridge[None, :], len(lat), axis=0) + lat[:, None]
    middle = np.roll(depth, 36, axis=1)  # the ridge on the meridian 0
    wrap = slope_size_sphere(np.hstack([depth, depth[:, :1]]), lat, per_slope=5.0)
    mid = slope_size_sphere(np.hstack([middle, middle[:, :1]]), lat, per_slope=5.0)
    np.testing.assert_allclose(np.roll(wrap[:, :-1], 36, axis=1), mid[:, :-1])
    assert wrap[12, 0] == wrap[12, -1]
    assert wrap[12, 1] < 0.01 * wrap[12, 36]  # steep by the seam, flat away


def test_the_pole_takes_the_slope_along_the_meridians():
    lat = np.array([80.0, 85.0, 90.0])
    depth = np.array([[3000.0] * 9, [2000.0] * 9, [1000.0] * 9])
    h = slope_size_sphere(depth, lat, per_slope=10.0)
    dy = EARTH_RADIUS * math.radians(5.0)
    assert h[2, 0] == pytest.approx(2 * math.pi * 1000.0 / (10.0 * 1000.0 / dy))
    assert np.ptp(h[2]) == 0.0 and np.isfinite(h).all()


def test_on_a_flat_plane_world_it_agrees_with_the_plane_term_at_the_equator():
    # near the equator, a degree east is a degree north: the plane's kernel
    # with that spacing gives the same sizes in the middle of the grid
    lat = np.linspace(-0.5, 0.5, 11)
    rng = np.random.default_rng(4)
    depth = rng.uniform(100.0, 200.0, (11, 3601))
    depth[:, -1] = depth[:, 0]
    step = EARTH_RADIUS * math.radians(0.1)
    sphere = slope_size_sphere(depth, lat, per_slope=10.0)
    plane = slope_size(depth, (step, step), per_slope=10.0)
    np.testing.assert_allclose(sphere[5, 1:-2], plane[5, 1:-2], rtol=1e-4)


def test_bad_slope_inputs_are_refused():
    with pytest.raises(ConfigError, match="per_slope = 0"):
        slope_size_sphere(np.ones((3, 9)), np.arange(3.0), per_slope=0.0)
    with pytest.raises(ConfigError, match=r"depth has shape \(3, 9\); lat has 2"):
        slope_size_sphere(np.ones((3, 9)), np.arange(2.0), per_slope=1.0)
