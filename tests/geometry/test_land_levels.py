"""The coast's level in land_from_grid: a height above the raster's datum.

Issue 31: a coast contoured at a positive level (the highest astronomical
tide, say) leaves the intertidal flats in the sea, for models that wet and dry.
The land is where the height is above the level, so as the level rises the land
shrinks (each level's land inside the one below) and the sea grows. Checked on
the Orkney ETOPO1 window against the raster itself: every coast vertex lies
where a literal bilinear interpolation of the samples equals the level, every
sample above the level is land and every sample below it is not. A raster of
depths (``positive="down"``) with the same level gives the same land, and on
a plane the coast is exactly where the plane crosses the level.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
from pyproj import Geod

from coastmesh.data import path as data_path
from coastmesh.geometry import land_from_grid
from coastmesh.io import read_raster

#: the levels of the issue, metres above the raster's datum
LEVELS = (-1.0, 0.0, 0.5, 1.0, 2.0, 10.0)
#: examples/orkney/dem_shoreline.toml's window (21 x 31 samples)
BOX = (-4.5, 58.0, -1.5, 60.0)
GEOD = Geod(ellps="WGS84")


@pytest.fixture(scope="module")
def orkney():
    raster = read_raster(data_path("etopo1_0.1deg_orkney_wide.tif"), bbox=BOX)
    values = np.asarray(raster.values, dtype=np.float64)
    assert values.shape == (21, 31) and np.isfinite(values).all()
    return raster.x.values, raster.y.values, values


def km2(geometry):
    """Geodesic area in km2 (edges split to 0.01 degree)."""
    area = GEOD.geometry_area_perimeter(shapely.segmentize(geometry, 0.01))[0]
    return abs(area) / 1e6


def cell_of(coords, p):
    """The index k and fraction t of p between coords[k] and coords[k + 1]."""
    for k in range(len(coords) - 1):
        a, b = coords[k], coords[k + 1]
        if min(a, b) - 1e-12 <= p <= max(a, b) + 1e-12:
            return k, (p - a) / (b - a)
    raise AssertionError(f"{p} is outside the grid {coords[0]} .. {coords[-1]}")


def bilinear(x, y, values, px, py):
    """The raster's bilinear interpolation at (px, py), one point, by hand."""
    j, t = cell_of(x, px)
    i, u = cell_of(y, py)
    return (
        (1 - t) * (1 - u) * values[i, j]
        + t * (1 - u) * values[i, j + 1]
        + (1 - t) * u * values[i + 1, j]
        + t * u * values[i + 1, j + 1]
    )


def check_on_the_level(land, x, y, values, level):
    """Every vertex interpolates to the level, or is a land sample on the frame."""
    vertices = shapely.get_coordinates(land)
    assert len(vertices) > 0
    frame = 0
    for px, py in vertices:
        height = bilinear(x, y, values, px, py)
        if abs(height - level) < 1e-9 * np.abs(values).max():
            continue
        # not on the level: the land closed along the grid's outermost samples
        assert px in (x[0], x[-1]) or py in (y[0], y[-1]), (px, py, height)
        assert px in x and py in y and height > level, (px, py, height)
        frame += 1
    return frame


@pytest.mark.parametrize("level", LEVELS)
def test_the_coast_is_where_the_raster_crosses_the_level(orkney, level):
    x, y, values = orkney
    land = land_from_grid(x, y, values, level)
    assert shapely.is_valid(land).all()
    # a slow literal reference: each vertex, interpolated in the raster
    check_on_the_level(land, x, y, values, level)
    # and each sample on its side of the coast
    union = shapely.union_all(land)
    samples = shapely.points(*np.meshgrid(x, y))
    assert shapely.covers(union, samples[values > level]).all()
    assert not shapely.intersects(union, samples[values < level]).any()


def test_the_sea_grows_as_the_coast_rises(orkney):
    """-1, 0, 0.5, 1, 2, 10 m: each land inside the last, the sea larger."""
    x, y, values = orkney
    frame = shapely.box(x.min(), y.min(), x.max(), y.max())
    lands = [shapely.union_all(land_from_grid(x, y, values, v)) for v in LEVELS]
    sea = [km2(frame) - km2(land) for land in lands]
    for (low, high), (sea_low, sea_high) in zip(
        itertools.pairwise(lands), itertools.pairwise(sea), strict=True
    ):
        assert shapely.difference(high, low).area < 1e-12  # nested
        assert sea_high > sea_low + 1.0  # km2: each step moves the coast
    # the samples above each level say the same, independently of the contour
    above = [int((values > v).sum()) for v in LEVELS]
    assert above == sorted(above, reverse=True) and above[0] > above[-1]
    # a level above every sample: no land, all sea
    assert len(land_from_grid(x, y, values, values.max() + 1.0)) == 0


@pytest.mark.parametrize("level", LEVELS)
def test_depths_with_the_same_level_give_the_same_land(orkney, level):
    x, y, values = orkney
    up = shapely.union_all(land_from_grid(x, y, values, level))
    down = shapely.union_all(land_from_grid(x, y, -values, level, positive="down"))
    assert down.equals(up)
    if level != 0.0:  # not the land at the opposite level
        opposite = shapely.union_all(land_from_grid(x, y, values, -level))
        assert not down.equals(opposite)


@pytest.mark.parametrize("level", [-1.0, 0.0, 0.5, 2.0, 5.25])
@pytest.mark.parametrize("positive", ["up", "down"])
def test_on_a_plane_the_coast_is_at_the_level(level, positive):
    """Height x - 3 m over 0 <= x <= 10: the land is exactly x > 3 + level."""
    x = np.arange(0.0, 11.0)
    y = np.arange(4.0, -1.0, -1.0)  # north-up
    height = np.broadcast_to(x - 3.0, (len(y), len(x)))
    values = height if positive == "up" else -height
    land = land_from_grid(x, y, values, level, positive=positive)
    assert len(land) == 1
    expected = shapely.box(3.0 + level, 0.0, 10.0, 4.0)
    assert shapely.symmetric_difference(land[0], expected).area < 1e-12
    # the same as the land above 0 m of the plane lowered by the level
    lowered = land_from_grid(x, y, height - level, 0.0)
    assert shapely.symmetric_difference(land[0], lowered[0]).area < 1e-12
