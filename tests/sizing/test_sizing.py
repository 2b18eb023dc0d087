"""Size fields against brute-force and independent geodesic calculations."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer
from reference import distance_to_points_geodesic, limit_gradation_brute

from coastmesh.errors import ConfigError
from coastmesh.sizing import (
    EARTH_RADIUS,
    distance_to_lines,
    gradation_size,
    limit_gradation,
    to_metres,
)


def test_units():
    assert to_metres("10 km") == 10_000.0
    assert to_metres("500 m") == 500.0
    assert to_metres(0.02, "deg") == pytest.approx(0.02 * np.pi / 180 * EARTH_RADIUS)
    assert to_metres("1 deg") == pytest.approx(111_195.08, abs=0.01)
    for bad, match in [
        ("10", "a number and a unit"),
        ("3 miles", "unknown unit"),
        (5.0, "give a unit"),
        ("nan m", "finite"),
        ("ten m", "not a number"),
    ]:
        with pytest.raises(ConfigError, match=match):
            to_metres(bad, name="h_min")


def test_area_and_time_units():
    from coastmesh.sizing.units import to_seconds, to_square_metres

    assert to_square_metres("0.2 km2") == 200_000.0
    assert to_square_metres("5000 m2") == 5000.0
    assert to_square_metres("3 ha") == 30_000.0
    assert to_square_metres(0) == 0.0
    assert to_seconds("12.42 h") == pytest.approx(44_712.0)
    assert to_seconds("30 min") == 1800.0
    for bad, match in [("2 km", "unknown unit 'km'"), (5, "a number and a unit")]:
        with pytest.raises(ConfigError, match=match):
            to_square_metres(bad, name="min_area")
    with pytest.raises(ConfigError, match="period = '3 days'"):
        to_seconds("3 days", name="period")


@settings(max_examples=50, deadline=None)
@given(
    h=st.tuples(st.floats(1, 1e4), st.floats(1, 1e4)).map(sorted),
    d_hold=st.floats(0, 1e5),
    d_grade=st.floats(1, 1e5),
    d=st.lists(st.floats(0, 1e6), min_size=2, max_size=50),
)
def test_gradation_is_bounded_and_monotone(h, d_hold, d_grade, d):
    h_min, h_max = h
    d = np.sort(np.asarray(d))
    size = gradation_size(d, h_min, h_max, d_hold, d_grade)
    assert np.all((size >= h_min) & (size <= h_max))
    assert np.all(np.diff(size) >= -1e-9)
    assert np.all(size[d <= d_hold] == h_min)
    assert np.all(size[d >= d_hold + d_grade] == pytest.approx(h_max))


def test_gradation_errors():
    with pytest.raises(ConfigError, match="h_min = 5"):
        gradation_size([0.0], 5.0, 1.0, 0.0, 1.0)
    with pytest.raises(ConfigError, match="d_grade = 0"):
        gradation_size([0.0], 1.0, 5.0, 0.0, 0.0)


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    ny=st.integers(1, 14),
    nx=st.integers(1, 14),
    rate=st.floats(0.05, 2.0),
    dx=st.floats(0.5, 3.0),
)
def test_limit_gradation_against_brute_force(seed, ny, nx, rate, dx):
    rng = np.random.default_rng(seed)
    size = rng.uniform(1, 50, (ny, nx)) * rng.choice([1, 10], (ny, nx))
    spacing = (1.0, dx)
    h = limit_gradation(size, spacing, rate)
    d, exact = limit_gradation_brute(size, spacing, rate)
    flat = h.ravel()
    # below the input, and the slope bound holds between every pair of cells
    assert np.all(h <= size + 1e-12)
    assert np.all(flat[:, None] <= flat[None, :] + rate * d + 1e-9)
    # close to the largest such field: between the exact one and the octagonal one
    assert np.all(h <= exact + 1e-9)
    widest = max(np.arctan2(1.0, dx), np.arctan2(dx, 1.0))  # between step directions
    _, tight = limit_gradation_brute(size, spacing, rate * np.cos(widest / 2))
    assert np.all(h >= tight - 1e-9)


def test_limit_gradation_errors():
    with pytest.raises(ConfigError, match="rate = 0"):
        limit_gradation(np.ones((3, 3)), (1.0, 1.0), 0)
    with pytest.raises(ConfigError, match="spacing"):
        limit_gradation(np.ones((3, 3)), (0.0, 1.0), 0.1)


@pytest.mark.parametrize("crs", ["EPSG:4326", "EPSG:32630"])
def test_distance_against_geodesics(crs):
    """Distances agree with WGS84 geodesics to the nearest point of the line."""
    coast = shapely.LineString(
        [(-3.4, 58.9), (-3.0, 59.1), (-2.6, 58.95), (-2.4, 59.3)]
    )
    lon = np.linspace(-4.0, -2.0, 9)
    lat = np.linspace(58.5, 59.6, 7)
    if crs == "EPSG:4326":
        lines, x, y = [coast], lon, lat
    else:
        to = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
        lines = [
            shapely.transform(coast, lambda c: np.column_stack(to.transform(*c.T)))
        ]
        x0, y0 = to.transform(-4.0, 58.5)
        x1, y1 = to.transform(-2.0, 59.6)
        x, y = np.linspace(x0, x1, 9), np.linspace(y0, y1, 7)
    d = distance_to_lines(lines, x, y, crs=crs, resolution=50.0)
    gx, gy = np.meshgrid(x, y)
    if crs != "EPSG:4326":
        back = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
        glon, glat = back.transform(gx.ravel(), gy.ravel())
    else:
        glon, glat = gx.ravel(), gy.ravel()
    dense = shapely.get_coordinates(shapely.segmentize(coast, 0.0002))  # ~20 m
    expected = distance_to_points_geodesic(
        glon, glat, dense[:, 0], dense[:, 1]
    ).reshape(d.shape)
    assert np.all(np.abs(d - expected) <= 50.0 + 0.005 * expected)


def test_polygons_use_their_rings():
    island = shapely.Point(0.0, 60.0).buffer(0.1)
    d = distance_to_lines([island], [0.0], [60.0], crs="EPSG:4326", resolution=10.0)
    # the centre is about 0.1 deg of latitude from the ring (north/south side)
    assert 5_000 < d[0, 0] < 11_200


def test_size_field_combines_by_minimum_and_limits():
    from coastmesh.sizing import Gradation, size_field

    coast = shapely.LineString([(500_000, 6_500_000), (520_000, 6_500_000)])
    site = shapely.Point(510_000, 6_503_000).buffer(300.0)
    coarse = Gradation(np.array([coast]), h_min=1_000.0, d_hold=0.0, d_grade=20_000.0)
    fine = Gradation(np.array([site]), h_min=50.0, d_hold=500.0, d_grade=5_000.0)
    bounds = (495_000, 6_490_000, 525_000, 6_510_000)
    args = {"crs": "EPSG:32630", "h_max": 5_000.0, "cell": 250.0}
    both = size_field(bounds, [coarse, fine], **args)
    only_coarse = size_field(bounds, [coarse], **args)
    only_fine = size_field(bounds, [fine], **args)
    np.testing.assert_array_equal(
        both.values, np.minimum(only_coarse, only_fine).values
    )
    assert float(both.min()) == 50.0 and float(both.max()) <= 5_000.0
    assert both.dims == ("y", "x") and both.attrs["units"] == "m"
    limited = size_field(bounds, [coarse, fine], rate=0.1, **args)
    assert np.all(limited.values <= both.values)
    h = limited.values  # neighbours along rows, columns and diagonals
    assert np.abs(np.diff(h, axis=0)).max() <= 0.1 * 250.0 + 1e-9
    assert np.abs(np.diff(h, axis=1)).max() <= 0.1 * 250.0 + 1e-9
    assert np.abs(h[1:, 1:] - h[:-1, :-1]).max() <= 0.1 * 250.0 * np.sqrt(2) + 1e-9
    with pytest.raises(ConfigError, match="not projected"):
        size_field(bounds, [coarse], crs="EPSG:4326", h_max=5_000.0, cell=250.0)


def test_max_distance_only_cuts_the_far_nodes():
    coast = shapely.LineString([(-3.4, 58.9), (-3.0, 59.1), (-2.6, 58.95)])
    x, y = np.linspace(-4.5, -1.5, 31), np.linspace(58.0, 60.0, 21)
    full = distance_to_lines([coast], x, y, crs="EPSG:4326", resolution=50.0)
    cut = distance_to_lines(
        [coast], x, y, crs="EPSG:4326", resolution=50.0, max_distance=30_000.0
    )
    near = full <= 30_000.0
    assert near.any() and (~near).any()
    np.testing.assert_array_equal(cut[near], full[near])
    far = full > 30_000.0 + 100.0
    assert np.isinf(cut[far]).all()
