"""The Earth helpers against per-point pyproj calls, closed forms and geodesics."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import CRS, Geod, Transformer

from coastmesh.geometry.earth import (
    EARTH_RADIUS,
    METRES_PER_DEGREE,
    arc_lengths,
    earth_centred,
    metres_per_unit,
    reproject,
    reproject_points,
    transformer,
)

GEOD = Geod(ellps="WGS84")
A, F = 6_378_137.0, 1 / 298.257223563
E2 = F * (2 - F)


def per_point(xy, src, dst):
    """The literal reference: a new transformer, one point at a time."""
    t = Transformer.from_crs(CRS(src), CRS(dst), always_xy=True)
    return np.array([t.transform(x, y) for x, y in xy], dtype=float).reshape(-1, 2)


def geodetic_to_ecef(lon, lat):
    """WGS84 lon/lat (degrees) at height 0 to earth-centred metres, in closed form."""
    lam, phi = np.radians(lon), np.radians(lat)
    n = A / np.sqrt(1 - E2 * np.sin(phi) ** 2)
    return np.column_stack(
        [
            n * np.cos(phi) * np.cos(lam),
            n * np.cos(phi) * np.sin(lam),
            n * (1 - E2) * np.sin(phi),
        ]
    )


def test_transformer_is_cached_and_x_first():
    t = transformer("EPSG:4326", 32630)
    assert t is transformer(CRS("EPSG:4326"), "EPSG:32630")
    x, y = t.transform(-3.0, 58.0)  # longitude first, not EPSG:4326's latitude
    assert 450_000 < x < 550_000 and 6_400_000 < y < 6_500_000
    assert transformer("EPSG:32630", "EPSG:4326") is not t


def test_reproject_matches_the_per_point_transform():
    rng = np.random.default_rng(7)
    shell = np.column_stack([rng.uniform(-4, -2, 12), rng.uniform(57, 59, 12)])
    polygon = shapely.Polygon(shapely.convex_hull(shapely.MultiPoint(shell)).exterior)
    hole = shapely.Point(-3, 58).buffer(0.1)
    geoms = np.array(
        [
            shapely.Polygon(polygon.exterior, [hole.exterior]),
            shapely.MultiLineString([[(-3, 58), (-2.5, 58.5)], [(-4, 57), (-3, 57)]]),
            None,
            shapely.Point(-3.2, 58.1),
        ],
        dtype=object,
    )
    out = reproject(geoms, "EPSG:4326", "EPSG:32630")
    assert out[2] is None
    assert [g.geom_type for g in out[[0, 1, 3]]] == [
        "Polygon",
        "MultiLineString",
        "Point",
    ]
    for before, after in zip(geoms[[0, 1, 3]], out[[0, 1, 3]], strict=True):
        expected = per_point(shapely.get_coordinates(before), 4326, 32630)
        np.testing.assert_allclose(
            shapely.get_coordinates(after), expected, rtol=0, atol=1e-6
        )
    assert len(out[0].interiors) == 1
    one = reproject(geoms[3], "EPSG:4326", "EPSG:32630")
    assert one.equals_exact(out[3], 1e-9)


def test_reproject_is_the_identity_for_equal_crs():
    line = shapely.LineString([(0, 0), (1, 1)])
    assert reproject(line, "EPSG:4326", CRS.from_epsg(4326)) is line
    geoms = np.array([line], dtype=object)
    assert reproject(geoms, 32630, "EPSG:32630") is geoms


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(0, 30),
    dst=st.sampled_from([32630, 3857, 27700, 3035]),
)
def test_reproject_points_matches_the_per_point_transform(seed, n, dst):
    rng = np.random.default_rng(seed)
    xy = np.column_stack([rng.uniform(-6, 1, n), rng.uniform(50, 60, n)])
    before = xy.copy()
    out = reproject_points(xy, "EPSG:4326", dst)
    assert out.shape == (n, 2) and out.dtype == np.float64
    np.testing.assert_allclose(out, per_point(xy, 4326, dst), rtol=0, atol=1e-6)
    back = reproject_points(out, dst, 4326)  # OSGB36's Helmert shift: 1e-8 deg
    np.testing.assert_allclose(back, xy, rtol=0, atol=1e-7)
    np.testing.assert_array_equal(xy, before)


def test_reproject_points_identity_is_a_copy_and_shapes_are_checked():
    xy = np.array([[1.0, 2.0], [3.0, 4.0]])
    same = reproject_points(xy, 4326, "EPSG:4326")
    np.testing.assert_array_equal(same, xy)
    assert same is not xy
    assert np.isinf(reproject_points([[0.0, 100.0]], 4326, 3395)).any()
    with pytest.raises(ValueError, match=r"xy must have shape \(n, 2\); got shape"):
        reproject_points([1.0, 2.0], 4326, 3857)


def test_earth_centred_geographic_matches_the_closed_form():
    rng = np.random.default_rng(1)
    lon, lat = rng.uniform(-180, 180, 500), rng.uniform(-90, 90, 500)
    xyz = earth_centred(np.column_stack([lon, lat]), "EPSG:4326")
    np.testing.assert_allclose(xyz, geodetic_to_ecef(lon, lat), rtol=0, atol=1e-6)


@pytest.mark.parametrize("crs", [32630, 3857, "EPSG:32630+5773"])
def test_earth_centred_projected_and_compound_go_through_lon_lat(crs):
    rng = np.random.default_rng(2)
    lonlat = np.column_stack([rng.uniform(-6, 0, 200), rng.uniform(54, 61, 200)])
    horizontal = CRS(crs).sub_crs_list[0] if CRS(crs).is_compound else CRS(crs)
    xy = per_point(lonlat, 4326, horizontal)
    xyz = earth_centred(xy, crs)
    expected = geodetic_to_ecef(*lonlat.T)
    # at height 0 on the ellipsoid, whatever the vertical part says
    np.testing.assert_allclose(xyz, expected, rtol=0, atol=1e-5)


def test_earth_centred_errors_name_the_point_and_the_crs():
    with pytest.raises(ValueError, match="expected a geographic or projected CRS"):
        earth_centred([[0.0, 0.0]], "EPSG:4978")
    bad = [[0.0, 10.0], [5.0, 100.0], [1.0, np.nan]]
    with pytest.raises(
        ValueError, match=r"nodes\[1\] = \(5.0, 100.0\) .*'WGS 84'; 2 such points"
    ):
        earth_centred(bad, 4326, name="nodes")
    with pytest.raises(ValueError, match=r"points must have shape \(n, 2\)"):
        earth_centred(np.zeros((3, 3)), 4326)
    assert earth_centred(np.empty((0, 2)), 4326).shape == (0, 3)


@settings(max_examples=60, deadline=None)
@given(
    lon=st.floats(-180, 180),
    lat=st.floats(-89.9, 89.9),
    azimuth=st.floats(0, 360),
    distance=st.floats(1_000, 100_000),
)
def test_arc_lengths_match_the_geodesic(lon, lat, azimuth, distance):
    lon2, lat2, _ = GEOD.fwd(lon, lat, azimuth, distance)
    ends = earth_centred([[lon, lat], [lon2, lat2]], 4326)
    arc = arc_lengths(ends[:1], ends[1:])
    assert arc.shape == (1,)
    assert arc[0] == pytest.approx(distance, rel=1e-11)


def test_arc_lengths_many_at_once_and_at_the_poles():
    rng = np.random.default_rng(3)
    lon, lat = rng.uniform(-180, 180, 300), rng.uniform(-89, 89, 300)
    distance = rng.uniform(100.0, 200_000.0, 300)
    lon2, lat2, _ = GEOD.fwd(lon, lat, rng.uniform(0, 360, 300), distance)
    p = earth_centred(np.column_stack([lon, lat]), 4326)
    q = earth_centred(np.column_stack([lon2, lat2]), 4326)
    geodesic = GEOD.inv(lon, lat, lon2, lat2)[2]
    np.testing.assert_allclose(arc_lengths(p, q), geodesic, rtol=1e-10, atol=1e-8)
    np.testing.assert_allclose(arc_lengths(q, p), arc_lengths(p, q), rtol=1e-14)
    assert arc_lengths(p, p).tolist() == [0.0] * 300
    # across the north pole: the midpoint's radius of curvature is the polar one
    pole = earth_centred([[0.0, 89.9], [180.0, 89.9]], 4326)
    expected = GEOD.inv(0.0, 89.9, 180.0, 89.9)[2]
    assert arc_lengths(pole[:1], pole[1:])[0] == pytest.approx(expected, rel=1e-11)


def test_metres_per_unit():
    assert metres_per_unit("EPSG:32630") == 1.0
    assert metres_per_unit(CRS("EPSG:2227")) == pytest.approx(1200 / 3937)  # US ft
    assert metres_per_unit(4326) == METRES_PER_DEGREE
    assert METRES_PER_DEGREE == EARTH_RADIUS * np.pi / 180.0
    assert metres_per_unit("EPSG:4326+5773") == METRES_PER_DEGREE
