"""What a grid says of itself, so that size terms never ask which kind it is."""

from __future__ import annotations

import numpy as np
import shapely

from coastmesh.sizing.grid import Grid, PlaneGrid, SphereGrid


def test_a_plane_grid_places_an_area_node_by_node():
    grid = PlaneGrid.from_bounds((0.0, 0.0, 1000.0, 500.0), 100.0, "EPSG:32630")
    area = shapely.Polygon([(150, 50), (750, 50), (450, 460)])
    inside = grid.nodes_in(area)
    assert inside is not None and inside.shape == grid.shape
    expected = [
        [area.contains(shapely.Point(x, y)) for x in grid.x] for y in grid.y
    ]  # one node at a time
    np.testing.assert_array_equal(inside, expected)
    assert 0 < inside.sum() < inside.size


def test_a_sphere_grid_places_no_area():
    grid = SphereGrid(10.0)
    assert grid.nodes_in(shapely.box(-20.0, -20.0, 20.0, 20.0)) is None
    assert Grid.nodes_in(grid, shapely.box(0.0, 0.0, 1.0, 1.0)) is None


def test_who_closes_water_narrower_than_the_grid():
    assert Grid.narrow_closed_by is None
    assert PlaneGrid.narrow_closed_by is None
    assert SphereGrid.narrow_closed_by == "[domain] close"


def _lonlat_raster(rng, lon, lat, classes=False):
    import xarray as xr

    values = rng.integers(0, 5, (len(lat), len(lon))).astype(float)
    if not classes:
        values = rng.normal(-40.0, 10.0, (len(lat), len(lon)))
    return xr.DataArray(
        values,
        dims=("y", "x"),
        coords={"y": lat, "x": lon},
        attrs={"crs": "EPSG:4326"},
    )


def test_a_plane_grid_samples_a_raster_of_another_crs_as_the_loops_do():
    """Bilinear and nearest, node by node: moved into the raster's CRS, then read."""
    from pyproj import Transformer
    from reference import bilinear_loop, nearest_loop

    rng = np.random.default_rng(7)
    raster = _lonlat_raster(
        rng, np.arange(-3.5, -2.0, 0.05), np.arange(58.4, 59.0, 0.04)
    )
    grid = PlaneGrid.from_bounds(
        (480_000, 6_480_000, 540_000, 6_520_000), 2000.0, "EPSG:32630"
    )
    to_lonlat = Transformer.from_crs("EPSG:32630", "EPSG:4326", always_xy=True)
    gx, gy = np.meshgrid(grid.x, grid.y)
    lon, lat = to_lonlat.transform(gx.ravel(), gy.ravel())
    rx, ry, v = raster.x.values, raster.y.values, raster.values
    bilinear = grid.sample(raster)
    np.testing.assert_allclose(
        bilinear.ravel(), bilinear_loop(rx, ry, v, lon, lat), rtol=1e-12, atol=1e-9
    )
    assert np.isfinite(bilinear).mean() > 0.5
    classes = _lonlat_raster(rng, raster.x.values, raster.y.values, classes=True)
    nearest = grid.sample(classes, "nearest")
    np.testing.assert_array_equal(
        nearest.ravel(), nearest_loop(rx, ry, classes.values, lon, lat)
    )
    # the depth is one reading: positive down, as the depth of the mesh's nodes
    np.testing.assert_array_equal(grid.sample(raster, "depth"), grid.depth(raster))


def test_a_sphere_grid_samples_a_world_raster_round_the_antimeridian():
    rng = np.random.default_rng(3)
    raster = _lonlat_raster(
        rng, np.arange(-179.5, 180.0, 1.0), np.arange(-89.5, 90.0, 1.0)
    )
    grid = SphereGrid(2.0, south=-80.0)
    got = grid.sample(raster)
    # -180 and 180 lie between the edge columns; the pole beyond the last row
    assert np.isfinite(got[:-1]).all() and np.isnan(got[-1]).all()
    np.testing.assert_array_equal(got[:, 0], got[:, -1])
    row = np.searchsorted(grid.y, 10.0)
    lat = grid.y[row]
    j = np.searchsorted(raster.y.values, lat) - 1
    ty = (lat - raster.y.values[j]) / 1.0
    # at 180: half the last column (179.5) and half the first (-179.5)
    edge = raster.values[:, [0, -1]].mean(axis=1)
    np.testing.assert_allclose(got[row, -1], (1 - ty) * edge[j] + ty * edge[j + 1])
    nearest = grid.sample(raster, "nearest")
    assert set(np.unique(nearest)) <= set(np.unique(raster.values))


def test_a_grid_refuses_an_unknown_reading():
    import pytest

    from coastmesh.errors import ConfigError

    grid = PlaneGrid.from_bounds((0.0, 0.0, 1000.0, 500.0), 250.0, "EPSG:32630")
    raster = _lonlat_raster(np.random.default_rng(0), np.arange(3), np.arange(3))
    with pytest.raises(ConfigError, match="how = 'cubic': use one of bilinear, "):
        grid.sample(raster, "cubic")


def test_the_nodes_are_moved_into_a_crs_once_row_by_row():
    from pyproj import CRS, Transformer

    grid = PlaneGrid.from_bounds(
        (480_000, 6_480_000, 500_000, 6_490_000), 2500.0, "EPSG:32630"
    )
    lonlat = CRS.from_epsg(4326)
    moved = grid.nodes_as(lonlat)
    assert grid.nodes_as(CRS.from_wkt(lonlat.to_wkt())) is moved  # the same CRS: once
    gx, gy = np.meshgrid(grid.x, grid.y)
    lon, lat = Transformer.from_crs(grid.crs, lonlat, always_xy=True).transform(
        gx.ravel(), gy.ravel()
    )
    np.testing.assert_allclose(moved, np.column_stack([lon, lat]), rtol=0, atol=1e-9)
