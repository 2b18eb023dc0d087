"""Loxodromes against independent calculations: Mercator, geodesics, the sphere."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from pyproj import Geod, Transformer

from coastmesh.errors import ConfigError
from coastmesh.geometry.rhumb import (
    Loxodrome,
    blend_loxodromes,
    great_circle,
    paper_bearing,
)

GEOD = Geod(ellps="WGS84")
TO_MERCATOR = Transformer.from_crs("EPSG:4326", "EPSG:3395", always_xy=True)


def _azimuth_in_mercator(points):
    x, y = TO_MERCATOR.transform(points[:, 0], points[:, 1])
    return np.degrees(np.arctan2(np.diff(x), np.diff(y))) % 360, x, y


@settings(max_examples=60, deadline=None)
@given(
    lon=st.floats(-30, 30),
    lat=st.floats(-75, 75),
    azimuth=st.floats(0, 360).filter(lambda a: abs(np.cos(np.radians(a))) > 0.05),
    dlat=st.floats(0.5, 10),
)
@example(lon=0.0, lat=0.0, azimuth=267.0, dlat=10.0)  # crosses 180: skipped
def test_straight_in_ellipsoidal_mercator(lon, lat, azimuth, dlat):
    """A rhumb line is the straight line at its azimuth on EPSG:3395."""
    north = np.cos(np.radians(azimuth)) > 0
    end = min(lat + dlat, 85) if north else max(lat - dlat, -85)
    if end == lat:
        return
    line = Loxodrome((lon, lat), azimuth, end_lat=end)
    # stay within one turn of longitude: EPSG:3395 wraps x at the antimeridian
    assume(abs(line.end[0] - lon) < 170)
    points = line.sample(5_000)
    az, x, y = _azimuth_in_mercator(points)
    off = (az - azimuth + 180.0) % 360.0 - 180.0  # each step's Mercator heading
    assert np.abs(off).max() < 1e-6
    # every point lies on the straight Mercator line through the ends
    t = (y - y[0]) / (y[-1] - y[0])
    np.testing.assert_allclose(x, x[0] + t * (x[-1] - x[0]), atol=1e-3)  # metres
    assert points[-1, 1] == end


def test_length_matches_summed_geodesics():
    line = Loxodrome((-4.0, 48.5), 250.0, end_lat=40.0)
    points = line.sample(1_000)
    summed = GEOD.line_length(points[:, 0], points[:, 1])
    assert abs(summed - line.length) < 1e-6 * line.length
    steps = GEOD.inv(points[:-1, 0], points[:-1, 1], points[1:, 0], points[1:, 1])[2]
    assert steps.max() <= 1_000 and np.ptp(steps) < 1.0  # equal arc-length steps


def test_end_longitude_and_parallel():
    # due east along a parallel: the length is N cos(phi) dlambda
    line = Loxodrome((0.0, 60.0), 90.0, end_lon=10.0)
    phi = np.radians(60.0)
    n = GEOD.a / np.sqrt(1 - GEOD.es * np.sin(phi) ** 2)
    assert line.length == pytest.approx(n * np.cos(phi) * np.radians(10), rel=1e-12)
    pts = line.sample(10_000)
    assert np.all(pts[:, 1] == 60.0) and pts[-1, 0] == 10.0
    # an oblique line ending at a longitude: it ends on that meridian, straight in
    # Mercator
    oblique = Loxodrome((8.0, 58 + 5 / 60), paper_bearing(30), end_lon=7.0)
    pts = oblique.sample(2_000)
    assert pts[-1, 0] == 7.0
    _, x, y = _azimuth_in_mercator(pts)
    t = (x - x[0]) / (x[-1] - x[0])
    np.testing.assert_allclose(y, y[0] + t * (y[-1] - y[0]), atol=1e-3)


def test_spherical_limit_is_close():
    """On the sphere, dlambda = tan(alpha) * dpsi; the ellipsoid differs by < 1 %."""
    line = Loxodrome((-15.0, 57.0), 340.0, end_lat=70.0)
    psi = lambda p: np.log(np.tan(np.pi / 4 + np.radians(p) / 2))  # noqa: E731
    sphere = -15.0 + np.degrees(np.tan(np.radians(340)) * (psi(70) - psi(57)))
    assert abs(line.end[0] - sphere) < 0.01 * abs(sphere + 15)


def test_blend_runs_between_the_starts_and_is_dense():
    a = Loxodrome((-15.0, 57.0), paper_bearing(20), end_lat=70.0)
    b = Loxodrome((5.45, 62.0), 0.0, end_lat=70.0)
    curve = blend_loxodromes(a, b, spacing=5_000)
    np.testing.assert_allclose(curve[0], a.start)
    np.testing.assert_allclose(curve[-1], b.start)
    steps = GEOD.inv(curve[:-1, 0], curve[:-1, 1], curve[1:, 0], curve[1:, 1])[2]
    assert steps.max() <= 5_000
    # the midpoint is the mean of the two lines' midpoints
    mid = len(curve) // 2
    s = mid / (len(curve) - 1)
    expected = (1 - s) * a.points(np.array([s]))[:, 0] + s * b.points(
        np.array([1 - s])
    )[:, 0]
    np.testing.assert_allclose(curve[mid], expected, atol=1e-12)


def test_paper_bearings():
    assert paper_bearing(20) == 340.0
    assert paper_bearing(110) == 250.0
    assert paper_bearing(185) == 175.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"start": (0, 60), "azimuth": 0}, "exactly one of end_lat and end_lon"),
        ({"start": (0, 60), "azimuth": 0, "end_lat": 50}, "heads north"),
        ({"start": (0, 60), "azimuth": 90, "end_lat": 70}, "due east or west"),
        ({"start": (0, 60), "azimuth": 180, "end_lon": 5}, "due north or south"),
        ({"start": (0, 60), "azimuth": 270, "end_lon": 5}, "heads west"),
        ({"start": (0, 95), "azimuth": 0, "end_lat": 70}, "latitude strictly"),
    ],
)
def test_bad_definitions(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        Loxodrome(**kwargs)


def test_bad_spacing():
    with pytest.raises(ConfigError, match="spacing = 0"):
        Loxodrome((0, 60), 0, end_lat=61).sample(0)


@settings(max_examples=40, deadline=None)
@given(
    lon0=st.floats(-30, 30),
    lat0=st.floats(-70, 70),
    lon1=st.floats(-30, 30),
    lat1=st.floats(-70, 70),
)
def test_great_circle_follows_the_geodesic(lon0, lat0, lon1, lat1):
    _, _, length = GEOD.inv(lon0, lat0, lon1, lat1)
    assume(length > 1_000.0)
    p = great_circle((lon0, lat0), (lon1, lat1), spacing=length / 7.3)
    assert p[0].tolist() == [lon0, lat0] and p[-1].tolist() == [lon1, lat1]
    _, _, steps = GEOD.inv(p[:-1, 0], p[:-1, 1], p[1:, 0], p[1:, 1])
    # on the geodesic, the steps add up to its length, and are equal
    assert steps.sum() == pytest.approx(length, rel=1e-9)
    assert steps.max() <= length / 7.3 * (1 + 1e-9)
    np.testing.assert_allclose(steps, steps.mean(), rtol=1e-6)


def test_great_circle_errors():
    with pytest.raises(ConfigError, match="coincide"):
        great_circle((1.0, 2.0), (1.0, 2.0), spacing=10.0)
    with pytest.raises(ConfigError, match="latitude = 95"):
        great_circle((1.0, 95.0), (1.0, 2.0), spacing=10.0)
