"""case/boundaries: each kind draws its line, checked against pyproj."""

from __future__ import annotations

import json

import numpy as np
import pytest
from pyproj import CRS, Geod, Transformer

from coastmesh.case.boundaries import (
    BlendBoundary,
    GreatCircleBoundary,
    LoxodromeBoundary,
    LoxodromeConfig,
    PolylineBoundary,
)
from coastmesh.errors import InputDataError

GEOD = Geod(ellps="WGS84")
UTM = CRS.from_epsg(32630)


def _steps(lonlat):
    _, _, d = GEOD.inv(lonlat[:-1, 0], lonlat[:-1, 1], lonlat[1:, 0], lonlat[1:, 1])
    return d


def test_a_loxodrome_runs_from_its_start_at_one_bearing_to_its_end():
    b = LoxodromeBoundary("n", 2, start=(-5.0, 57.0), bearing=340.0, end_lat=59.0)
    pts = b.lonlat(5_000.0)
    np.testing.assert_allclose(pts[0], (-5.0, 57.0))
    assert pts[-1, 1] == pytest.approx(59.0, abs=1e-9)
    steps = _steps(pts)
    assert steps.max() <= 5_000.0 * (1 + 1e-9) and len(pts) > 40
    # a rhumb line: equal steps in isometric latitude and in longitude
    psi = np.arctanh(np.sin(np.radians(pts[:, 1])))  # sphere: enough for the ratio
    ratio = np.diff(np.radians(pts[:, 0])) / np.diff(psi)
    assert ratio.std() < 1e-2 * abs(ratio.mean())
    assert ratio.mean() < 0  # west of north


def test_line_puts_the_points_in_the_case_crs():
    b = LoxodromeBoundary("n", 2, start=(-5.0, 57.0), bearing=10.0, end_lat=58.0)
    to_utm = Transformer.from_crs(4326, UTM, always_xy=True)
    expected = np.column_stack(to_utm.transform(*b.lonlat(2_000.0).T))
    np.testing.assert_allclose(b.line(UTM, 2_000.0), expected, atol=1e-6)


def test_a_great_circle_follows_the_geodesic():
    b = GreatCircleBoundary("w", 4, start=(-10.0, 50.0), end=(10.0, 50.0))
    pts = b.lonlat(20_000.0)
    np.testing.assert_allclose(pts[[0, -1]], [(-10.0, 50.0), (10.0, 50.0)])
    _, _, total = GEOD.inv(-10.0, 50.0, 10.0, 50.0)
    _, _, to_start = GEOD.inv(np.full(len(pts), -10.0), np.full(len(pts), 50.0), *pts.T)
    _, _, to_end = GEOD.inv(*pts.T, np.full(len(pts), 10.0), np.full(len(pts), 50.0))
    np.testing.assert_allclose(to_start + to_end, total, rtol=1e-9)  # on it
    assert _steps(pts).max() <= 20_000.0 and pts[:, 1].max() > 50.4  # bulges north


def test_a_blend_runs_from_the_first_start_to_the_second_start():
    b = BlendBoundary(
        "b",
        3,
        first=LoxodromeConfig((-15.0, 57.0), 340.0, 70.0),
        second=LoxodromeConfig((5.45, 62.0), 0.0, 70.0),
    )
    pts = b.lonlat(10_000.0)
    np.testing.assert_allclose(pts[0], (-15.0, 57.0))
    np.testing.assert_allclose(pts[-1], (5.45, 62.0), atol=1e-9)
    assert _steps(pts).max() <= 10_000.0


def test_a_polyline_keeps_its_points_whatever_the_spacing():
    points = ((0.0, 0.0), (1000.0, 0.0), (1000.0, 500.0))
    b = PolylineBoundary("s", 5, points=points)
    np.testing.assert_array_equal(b.line(UTM, 10.0), np.array(points))
    np.testing.assert_array_equal(b.line(UTM, 1e6), np.array(points))


def _geojson(path, lines):
    features = [
        {
            "type": "Feature",
            "properties": {},
            "geometry": {"type": "LineString", "coordinates": line},
        }
        for line in lines
    ]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    return path


def test_a_polyline_from_a_file_is_its_one_line_in_the_case_crs(tmp_path):
    line = [[-3.0, 58.0], [-2.9, 58.05], [-2.8, 58.0]]
    path = _geojson(tmp_path / "south.geojson", [line])
    got = PolylineBoundary("s", 5, path=path).line(UTM, 1000.0)
    to_utm = Transformer.from_crs(4326, UTM, always_xy=True)
    expected = np.column_stack(to_utm.transform(*np.array(line).T))
    np.testing.assert_allclose(got, expected, atol=1e-6)


def test_a_file_with_two_lines_is_refused_with_its_name(tmp_path):
    path = _geojson(
        tmp_path / "two.geojson",
        [[[-3.0, 58.0], [-2.9, 58.0]], [[-2.0, 58.0], [-1.9, 58.0]]],
    )
    with pytest.raises(InputDataError, match=r"two\.geojson must hold exactly one"):
        PolylineBoundary("s", 5, path=path).line(UTM, 1000.0)
