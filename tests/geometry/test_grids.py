"""Bilinear interpolation on a regular grid, against the literal loop."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import bilinear_loop, nearest_loop

from coastmesh.geometry.grids import cell_of, interpolate_bilinear, interpolate_nearest
from coastmesh.geometry.projection import sample_size
from coastmesh.types import SizeGrid


def _points(rng, x, y, n):
    """Points in and round the grid, many of them on its lines and corners."""
    px = rng.uniform(x[0] - 1.0, x[-1] + 1.0, n)
    py = rng.uniform(y[0] - 1.0, y[-1] + 1.0, n)
    q = n // 6
    px[:q] = rng.choice(x, q)  # on a column of nodes
    py[q : 2 * q] = rng.choice(y, q)  # on a row of nodes
    px[2 * q : 3 * q], py[2 * q : 3 * q] = rng.choice(x, q), rng.choice(y, q)  # nodes
    px[3 * q : 4 * q] = x[-1]  # the last column, and the last row
    py[4 * q : 5 * q] = y[-1]
    px[-4:], py[-4:] = x[[0, -1, 0, -1]], y[[0, 0, -1, -1]]  # the grid's corners
    return px, py


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    nx=st.integers(2, 8),
    ny=st.integers(2, 8),
    missing=st.sampled_from([0.0, 0.1, 0.4]),
    clamp=st.booleans(),
)
def test_bilinear_matches_the_loop_bit_for_bit(seed, nx, ny, missing, clamp):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.1, 2.0, nx)) - rng.uniform(0, 5)
    y = np.cumsum(rng.uniform(0.1, 2.0, ny)) - rng.uniform(0, 5)
    values = rng.normal(0.0, 10.0, (ny, nx))
    values[rng.random(values.shape) < missing] = np.nan
    px, py = _points(rng, x, y, 120)
    before = values.copy()
    got = interpolate_bilinear(x, y, values, px, py, clamp=clamp)
    expected = bilinear_loop(x, y, values, px, py, clamp=clamp)
    np.testing.assert_array_equal(got, expected)  # NaN where it is NaN, else equal
    np.testing.assert_array_equal(values, before)
    # the shape of the points is kept
    shaped = interpolate_bilinear(
        x, y, values, px[:-4].reshape(4, -1), py[:-4].reshape(4, -1), clamp=clamp
    )
    np.testing.assert_array_equal(shaped, expected[:-4].reshape(4, -1))


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    nx=st.integers(1, 8),
    ny=st.integers(1, 8),
    missing=st.sampled_from([0.0, 0.2]),
)
def test_nearest_matches_the_loop(seed, nx, ny, missing):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.1, 2.0, nx)) - rng.uniform(0, 5)
    y = np.cumsum(rng.uniform(0.1, 2.0, ny)) - rng.uniform(0, 5)
    values = rng.integers(0, 9, (ny, nx)).astype(float)
    values[rng.random(values.shape) < missing] = np.nan
    px, py = _points(rng, x, y, 120)
    # half-way between nodes, and half a cell beyond the outer ones
    if nx > 1:
        px[5:8] = [
            (x[0] + x[1]) / 2,
            x[0] - (x[1] - x[0]) / 2,
            x[-1] + 0.6 * (x[-1] - x[-2]),
        ]
    got = interpolate_nearest(x, y, values, px, py)
    np.testing.assert_array_equal(got, nearest_loop(x, y, values, px, py))
    assert set(np.unique(got[np.isfinite(got)])) <= set(np.unique(values))


def test_bilinear_matches_the_loop_with_nodata_and_outside_points():
    rng = np.random.default_rng(4)
    x = np.cumsum(rng.uniform(0.5, 1.5, 15))
    y = np.cumsum(rng.uniform(0.5, 1.5, 11))
    values = rng.normal(0, 10, (11, 15))
    values[rng.random(values.shape) < 0.05] = np.nan
    px = rng.uniform(x[0] - 2, x[-1] + 2, 2000)
    py = rng.uniform(y[0] - 2, y[-1] + 2, 2000)
    got = interpolate_bilinear(x, y, values, px, py)
    expected = bilinear_loop(x, y, values, px, py)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    assert np.isnan(got).sum() > 100 and (~np.isnan(got)).sum() > 1000
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
    # cell centres give the cells (without nodata); the shape of the points is kept
    gx, gy = np.meshgrid(x, y)
    full = np.nan_to_num(values)
    np.testing.assert_allclose(interpolate_bilinear(x, y, full, gx, gy), full)


def test_a_missing_node_without_a_weight_does_not_count():
    holed = np.array([[0.0, 10.0], [20.0, np.nan]])
    axis = np.array([0.0, 1.0])
    got = interpolate_bilinear(
        axis, axis, holed, [0.5, 0.0, 1.0, 0.5], [0.0, 0.5, 0.0, 1.0]
    )
    np.testing.assert_array_equal(got, [5.0, 10.0, 10.0, np.nan])


def test_bilinear_on_a_grid_one_cell_wide_is_nan():
    out = interpolate_bilinear(
        np.array([0.0]), np.array([0.0, 1.0]), np.ones((2, 1)), [0.0], [0.5]
    )
    assert np.isnan(out).all() and out.shape == (1,)


def test_cell_of_puts_the_last_column_in_the_last_cell():
    x = np.array([0.0, 1.0, 3.0])
    y = np.array([-1.0, 1.0])
    i, j = cell_of(x, y, np.array([-5.0, 0.0, 0.999, 1.0, 3.0, 9.0]), np.full(6, 1.0))
    assert i.tolist() == [0, 0, 0, 1, 1, 1] and j.tolist() == [0] * 6


def test_a_size_grid_is_sampled_by_the_shared_interpolation_clamped():
    rng = np.random.default_rng(7)
    x, y = np.cumsum(rng.uniform(1, 3, 9)), np.cumsum(rng.uniform(1, 3, 6))
    grid = SizeGrid(x, y, rng.uniform(10.0, 100.0, (6, 9)))
    px, py = _points(rng, x, y, 300)
    got = sample_size(grid, np.column_stack([px, py]))
    np.testing.assert_array_equal(
        got, bilinear_loop(x, y, grid.values, px, py, clamp=True)
    )
    assert np.isfinite(got).all()
