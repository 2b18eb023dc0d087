"""Sizes from a field: the mapping, the sampling of a mesh on a grid, gradients."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import (
    node_gradients_loop,
    size_mapping_loop,
    triangles_on_grid_loop,
)
from scipy.spatial import Delaunay

from coastmesh.errors import ConfigError
from coastmesh.sizing.fields import SizeMapping, node_gradients, triangles_on_grid


@st.composite
def meshes(draw):
    """A random Delaunay mesh in a 100 m square, node values, a grid over it."""
    n = draw(st.integers(4, 25))
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 100, (n, 2))
    triangles = Delaunay(points).simplices.astype(np.int64)
    values = rng.normal(size=n)
    step = draw(st.floats(3.0, 30.0))
    x0, y0 = draw(st.floats(-20, 20)), draw(st.floats(-20, 20))
    x = x0 + step * np.arange(int(140 / step))
    y = y0 + step * np.arange(int(140 / step))
    return points, triangles, values, x, y


@given(meshes())
@settings(max_examples=40, deadline=None)
def test_triangles_on_grid_matches_the_loop(case):
    points, triangles, values, x, y = case
    got, inside = triangles_on_grid(points, triangles, x, y, values)
    want, want_inside = triangles_on_grid_loop(points, triangles, x, y, values)
    # a node on an edge may fall either side within rounding: compare the
    # nodes both call inside, and the rest must be few and on an edge
    assert (inside == want_inside).mean() > 0.99
    both = inside & want_inside
    np.testing.assert_allclose(got[both], want[both], rtol=1e-9, atol=1e-9)
    assert np.isnan(got[~inside]).all()


@given(meshes())
@settings(max_examples=20, deadline=None)
def test_triangle_values_are_constant_in_each(case):
    points, triangles, _, x, y = case
    per_triangle = np.arange(len(triangles), dtype=np.float64)
    got, inside = triangles_on_grid(
        points, triangles, x, y, per_triangle, per="triangle"
    )
    _want, want_inside = triangles_on_grid_loop(
        points, triangles, x, y, per_triangle, per="triangle"
    )
    # on a shared edge either triangle's value is right: check the node lies in
    # the triangle named
    from matplotlib.path import Path as MplPath

    for j, i in zip(*np.nonzero(inside & want_inside), strict=False):
        tri = points[triangles[int(got[j, i])]]
        assert MplPath(tri).contains_point((x[i], y[j]), radius=1e-6) or MplPath(
            tri[::-1]
        ).contains_point((x[i], y[j]), radius=1e-6)


def test_linear_data_is_reproduced_exactly():
    rng = np.random.default_rng(3)
    points = rng.uniform(0, 1000, (300, 2))
    triangles = Delaunay(points).simplices
    values = 2.0 * points[:, 0] - 0.5 * points[:, 1] + 7.0
    x = y = np.arange(0.0, 1000.0, 7.0)
    got, inside = triangles_on_grid(points, triangles, x, y, values)
    xx, yy = np.meshgrid(x, y)
    np.testing.assert_allclose(
        got[inside], (2.0 * xx - 0.5 * yy + 7.0)[inside], atol=1e-9
    )
    assert inside.mean() > 0.9  # the hull of 300 random points covers most


def test_many_chunks_give_the_same(monkeypatch):
    import coastmesh.sizing.fields as fields

    rng = np.random.default_rng(4)
    points = rng.uniform(0, 1000, (500, 2))
    triangles = Delaunay(points).simplices
    values = rng.normal(size=500)
    x = y = np.arange(0.0, 1000.0, 5.0)
    whole = triangles_on_grid(points, triangles, x, y, values)
    monkeypatch.setattr(fields, "_PAIRS", 997)
    chunked = triangles_on_grid(points, triangles, x, y, values)
    np.testing.assert_array_equal(whole[1], chunked[1])
    np.testing.assert_allclose(whole[0], chunked[0], equal_nan=True)


@given(meshes())
@settings(max_examples=30, deadline=None)
def test_node_gradients_match_the_loop(case):
    points, triangles, values, _, _ = case
    gx, gy = node_gradients(points, triangles, values)
    wx, wy = node_gradients_loop(points, triangles, values)
    used = np.isfinite(wx)
    np.testing.assert_allclose(gx[used], wx[used], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(gy[used], wy[used], rtol=1e-6, atol=1e-9)


def test_gradients_in_lonlat_are_per_metre():
    # a field rising 1 per km eastward, on a small lon/lat mesh at 60 N
    rng = np.random.default_rng(5)
    lon = rng.uniform(-0.1, 0.1, 200)
    lat = 60 + rng.uniform(-0.05, 0.05, 200)
    points = np.column_stack([lon, lat])
    triangles = Delaunay(points).simplices
    east_m = np.radians(lon) * 6371008.8 * np.cos(np.radians(60.0))
    gx, gy = node_gradients(points, triangles, east_m / 1000.0, lonlat=True)
    assert np.nanmedian(gx) == pytest.approx(1e-3, rel=0.01)
    assert abs(np.nanmedian(gy)) < 2e-5


@given(
    kind=st.sampled_from(["thresholds", "ramp", "power"]),
    v=st.lists(st.floats(-10, 10, allow_nan=False), min_size=1, max_size=30),
    increasing=st.booleans(),
)
def test_mapping_matches_the_loop(kind, v, increasing):
    values = {"thresholds": (-1.0, 0.5, 2.0), "ramp": (0.5, 2.0), "power": (2.0,)}[kind]
    sizes = {
        "thresholds": (300.0, 100.0, 50.0),
        "ramp": (300.0, 50.0),
        "power": (50.0,),
    }[kind]
    if increasing:
        sizes = tuple(reversed(sizes))
    m = SizeMapping(kind, values, sizes, exponent=-1.5)
    got = m.sizes_of(np.array(v))
    want = [size_mapping_loop(kind, values, sizes, -1.5, x) for x in v]
    np.testing.assert_allclose(got, want)


@pytest.mark.parametrize(
    ("kind", "values", "sizes", "message"),
    [
        ("thresholds", (2.0, 3.0), (100.0, -50.0), "not a positive size"),
        ("thresholds", (2.0, 3.0), (100.0, 0.0), "not a positive size"),
        ("thresholds", (3.0, 2.0), (100.0, 50.0), "strictly increasing"),
        ("thresholds", (1.0, 2.0, 3.0), (100.0, 50.0, 80.0), "not ordered"),
        ("thresholds", (1.0, 2.0), (100.0,), "one size per value"),
        ("ramp", (1.0, 2.0, 3.0), (1.0, 2.0, 3.0), "takes 2 value"),
        ("ramp", (2.0, 2.0), (100.0, 50.0), "strictly increasing"),
        ("power", (0.0,), (50.0,), "reference value must be > 0"),
        ("curve", (1.0,), (50.0,), "use one of"),
    ],
)
def test_bad_mappings_are_named(kind, values, sizes, message):
    with pytest.raises(ConfigError, match=message) as err:
        SizeMapping(kind, values, sizes, where="mesh_size.fields[2]")
    assert "mesh_size.fields[2]" in str(err.value)


def _neighbour_min_loop(values, wrap_x=False, cells=1):
    """Literal: each node's smallest value over the nodes within ``cells``."""
    ny, nx = values.shape
    out = np.empty_like(values)
    for j in range(ny):
        for i in range(nx):
            best = np.inf
            for dj in range(-cells, cells + 1):
                for di in range(-cells, cells + 1):
                    jj, ii = j + dj, i + di
                    if not 0 <= jj < ny:
                        continue
                    if wrap_x:  # columns 0 and nx - 1 are one meridian
                        ii %= nx - 1
                    elif not 0 <= ii < nx:
                        continue
                    best = min(best, values[jj, ii])
            out[j, i] = best
    if wrap_x:
        out[:, -1] = out[:, 0]
    return out


@settings(max_examples=40, deadline=None)
@given(
    st.integers(2, 7),
    st.integers(3, 8),
    st.integers(0, 2**31 - 1),
    st.integers(1, 3),
)
def test_neighbour_min_matches_a_loop_on_both_grids(ny, nx, seed, cells):
    from coastmesh.sizing.grid import PlaneGrid, SphereGrid

    rng = np.random.default_rng(seed)
    values = np.where(rng.random((ny, nx)) < 0.3, np.inf, rng.uniform(1, 9, (ny, nx)))
    plane = PlaneGrid(np.arange(nx) * 10.0, np.arange(ny) * 10.0, "EPSG:32630", 10.0)
    np.testing.assert_array_equal(
        plane.neighbour_min(values, cells), _neighbour_min_loop(values, cells=cells)
    )
    # a world grid's last column is its first one's meridian: spread across it
    sphere = SphereGrid(360.0 / (nx - 1))
    world = values.copy()
    world[:, -1] = world[:, 0]
    np.testing.assert_array_equal(
        sphere.neighbour_min(world, cells),
        _neighbour_min_loop(world, wrap_x=True, cells=cells),
    )
