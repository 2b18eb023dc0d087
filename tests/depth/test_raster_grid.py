"""Rasters as arrays: axes, flips and errors, and wet sampling against a loop."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import bilinear_wet_loop

from coastmesh.depth.raster import interpolate_wet, raster_grid
from coastmesh.errors import ConfigError


def raster(values, y, x, crs="EPSG:4326"):
    attrs = {} if crs is None else {"crs": crs}
    return xr.DataArray(values, dims=("y", "x"), coords={"y": y, "x": x}, attrs=attrs)


@pytest.mark.parametrize("flip_y", [False, True])
@pytest.mark.parametrize("flip_x", [False, True])
def test_raster_grid_returns_ascending_axes(flip_x, flip_y):
    values = np.arange(12, dtype=np.float32).reshape(3, 4)
    x, y = np.array([0.0, 1.0, 2.0, 3.0]), np.array([10.0, 20.0, 30.0])
    r = raster(values, y, x)
    if flip_x:
        r = r.isel(x=slice(None, None, -1))
    if flip_y:
        r = r.isel(y=slice(None, None, -1))
    before = r.values.copy()
    gx, gy, grid, crs = raster_grid(r)
    np.testing.assert_array_equal(gx, x)
    np.testing.assert_array_equal(gy, y)
    np.testing.assert_array_equal(grid, values)  # the unflipped order
    assert grid.dtype == gx.dtype == gy.dtype == np.float64
    assert crs.to_epsg() == 4326
    np.testing.assert_array_equal(r.values, before)  # the raster is not changed


def test_raster_grid_errors_name_the_problem():
    values = np.zeros((2, 3))
    with pytest.raises(ConfigError, match=r"raster dims \('x', 'y'\)"):
        raster_grid(raster(values, [0.0, 1.0], [0.0, 1.0, 2.0]).transpose())
    with pytest.raises(ConfigError, match="no 'crs' attribute"):
        raster_grid(raster(values, [0.0, 1.0], [0.0, 1.0, 2.0], crs=None))
    with pytest.raises(ConfigError, match="raster x coordinates are not strictly"):
        raster_grid(raster(values, [0.0, 1.0], [0.0, 2.0, 1.0]))
    with pytest.raises(ConfigError, match="raster y coordinates are not strictly"):
        raster_grid(raster(values, [1.0, 1.0], [0.0, 1.0, 2.0]))


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    land=st.floats(0.0, 1.0),
    nodata=st.floats(0.0, 0.2),
)
def test_wet_interpolation_matches_the_loop(seed, land, nodata):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.5, 1.5, 9))
    y = np.cumsum(rng.uniform(0.5, 1.5, 7))
    depth = rng.uniform(0.5, 100.0, (7, 9))
    depth[rng.random(depth.shape) < land] *= -1  # land heights
    depth[rng.random(depth.shape) < nodata] = np.nan
    px = rng.uniform(x[0] - 1, x[-1] + 1, 300)
    py = rng.uniform(y[0] - 1, y[-1] + 1, 300)
    px[:20], py[:20] = x[rng.integers(0, 9, 20)], y[rng.integers(0, 7, 20)]
    got = interpolate_wet(x, y, depth, px, py)
    expected = bilinear_wet_loop(x, y, depth, px, py)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
    # never a land value: every finite result is a wet depth or exactly 0
    ok = np.isfinite(got)
    assert ((got[ok] > 0) | (got[ok] == 0)).all()
    wet = depth[np.isfinite(depth) & (depth > 0)]
    if wet.size:
        assert (got[ok & (got > 0)] >= wet.min() - 1e-9).all()
        assert (got[ok] <= wet.max() + 1e-9).all()
