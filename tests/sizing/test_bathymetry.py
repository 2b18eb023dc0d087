"""Bathymetry size terms against independent calculations on real ETOPO1 data."""

from __future__ import annotations

import numpy as np
import pytest
from pyproj import Transformer
from reference import bilinear_loop

from coastmesh.data import path as data_path
from coastmesh.depth import depth_on_grid
from coastmesh.errors import ConfigError
from coastmesh.io import read_raster
from coastmesh.sizing import M2_PERIOD, slope_size, wavelength_size


def _bilinear(raster, lon, lat):
    """Textbook bilinear interpolation on the cell centres, one point at a time."""
    xs, ys, z = raster["x"].values, raster["y"].values, raster.values
    if ys[0] > ys[-1]:
        ys, z = ys[::-1], z[::-1]
    return bilinear_loop(xs, ys, z, lon, lat)


def test_depth_on_a_utm_grid_matches_bilinear():
    raster = read_raster(data_path("etopo1_0.1deg_orkney_wide.tif"))
    to_utm = Transformer.from_crs("EPSG:4326", "EPSG:32630", always_xy=True)
    x0, y0 = to_utm.transform(-4.0, 58.0)
    x = x0 + 7_000.0 * np.arange(12)
    y = y0 + 9_000.0 * np.arange(10)
    depth = depth_on_grid(raster, x, y, crs="EPSG:32630")
    back = Transformer.from_crs("EPSG:32630", "EPSG:4326", always_xy=True)
    gx, gy = np.meshgrid(x, y)
    lon, lat = back.transform(gx.ravel(), gy.ravel())
    expected = -_bilinear(raster, lon, lat)
    np.testing.assert_allclose(depth.ravel(), expected, rtol=1e-12, atol=1e-9)
    up = depth_on_grid(raster, x, y, crs="EPSG:32630", positive="down")
    np.testing.assert_allclose(up, -depth)
    outside = depth_on_grid(raster, [0.0], [0.0], crs="EPSG:32630")
    assert np.isnan(outside).all()


def test_wavelength_size():
    d = np.array([np.nan, -5.0, 0.5, 100.0, 4000.0])
    h = wavelength_size(d, per_wavelength=50.0)
    expected = M2_PERIOD * np.sqrt(9.80665 * np.array([1, 1, 1, 100, 4000.0])) / 50
    np.testing.assert_allclose(h, expected)
    assert np.all(np.diff(h[2:]) > 0)  # deeper, longer wave, larger elements
    with pytest.raises(ConfigError, match="per_wavelength = 0"):
        wavelength_size(d, per_wavelength=0)


def test_slope_size():
    # a plane sloping 1:20 in x: h = 2 pi d / (n * 0.05)
    x = np.arange(0, 5_000.0, 100.0)
    d = np.tile(20.0 + 0.05 * x, (4, 1))
    h = slope_size(d, (100.0, 100.0), per_slope=8)
    np.testing.assert_allclose(h, 2 * np.pi * d / (8 * 0.05))
    flat = slope_size(np.full((3, 3), 50.0), (10.0, 10.0), per_slope=8)
    assert np.isinf(flat).all()
    with pytest.raises(ConfigError, match="per_slope = -1"):
        slope_size(d, (100.0, 100.0), per_slope=-1)
