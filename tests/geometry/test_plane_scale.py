"""The stereographic plane's scale from a point of the plane, against the angle."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from pyproj import Transformer
from reference import plane_scale_from_angle

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import plane_crs, plane_scale, stereographic_scale


@settings(max_examples=200, deadline=None)
@given(
    r=st.one_of(st.just(0.0), st.floats(0.0, 40.0 * EARTH_RADIUS)),
    radius=st.sampled_from([1.0, 6.4e6, EARTH_RADIUS]),
)
def test_plane_scale_is_the_scale_at_the_angle(r, radius):
    r = r * radius / EARTH_RADIUS
    k = plane_scale(r, radius=radius)
    assert isinstance(k, float)
    want = plane_scale_from_angle(r, radius)
    # 1 + cos c loses digits as c nears 180 degrees: about k ulps
    assert abs(k - want) <= 4e-16 * want * max(want, 1.0)
    got = plane_scale(np.array([r, r]), radius=radius)
    assert got.shape == (2,) and (got == k).all()


@settings(max_examples=40, deadline=None)
@given(
    lon=st.floats(-180.0, 180.0),
    lat=st.floats(-70.0, 89.0),
    pole=st.tuples(st.floats(-180.0, 180.0), st.floats(-90.0, -60.0)),
)
def test_plane_scale_is_the_stereographic_scale_in_every_plane(lon, lat, pole):
    x, y = Transformer.from_crs("EPSG:4326", plane_crs(pole), always_xy=True).transform(
        lon, lat
    )
    k = float(stereographic_scale(lon, lat, pole))
    assume(k < 1e3)  # not at the pole, which goes to infinity
    assert plane_scale(float(np.hypot(x, y))) == pytest.approx(k, rel=1e-9)


def test_plane_scale_is_the_former_sum_of_squares_to_a_few_ulps():
    # closing.earth_areas, inlets and time_step_relief wrote the scale as
    # 1 + (x^2 + y^2) / 4R^2; plane_scale(hypot(x, y)) is 1 + (r / 2R)^2: the
    # two round differently, by at most a few ulps (of the same k)
    rng = np.random.default_rng(3)
    xy = rng.normal(0.0, 1.0, (200_000, 2)) * 10.0 ** rng.uniform(0, 8.5, (200_000, 1))
    before = 1.0 + (xy[:, 0] ** 2 + xy[:, 1] ** 2) / (4.0 * EARTH_RADIUS**2)
    now = plane_scale(np.hypot(xy[:, 0], xy[:, 1]))
    assert (np.abs(now - before) <= 8 * np.spacing(before)).all()
    assert (now == before).mean() > 0.5
