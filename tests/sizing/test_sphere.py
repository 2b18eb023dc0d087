"""World size fields on a longitude/latitude grid, against literal references."""

from __future__ import annotations

import heapq
import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.data import path as data_path
from coastmesh.geometry.earth import EARTH_RADIUS, GRAVITY
from coastmesh.io import read_raster
from coastmesh.sizing.bathymetry import M2_PERIOD, wavelength_size
from coastmesh.sizing.combine import TermSizes, combine
from coastmesh.sizing.gradation import Gradation
from coastmesh.sizing.grid import SphereGrid
from coastmesh.sizing.sphere import limit_gradation_sphere


def _arc(lon0, lat0, lon1, lat1) -> float:
    """Great-circle distance by the spherical law of cosines (metres)."""
    p0, p1 = math.radians(lat0), math.radians(lat1)
    c = math.sin(p0) * math.sin(p1) + math.cos(p0) * math.cos(p1) * math.cos(
        math.radians(lon1 - lon0)
    )
    return EARTH_RADIUS * math.acos(max(-1.0, min(1.0, c)))


def reference_limit(size: np.ndarray, lat: np.ndarray, rate: float) -> np.ndarray:
    """Dijkstra from every node over the 8-neighbour graph of the periodic grid,
    edges ``rate`` times their great-circle length; the two end columns (one
    meridian) are one node."""
    ny, nxp = size.shape
    nx = nxp - 1
    lon = np.linspace(-180.0, 180.0, nxp)
    best = {
        (j, i): float(min(size[j, i], size[j, i + nx if i == 0 else i]))
        for j in range(ny)
        for i in range(nx)
    }
    best = {
        (j, i): min(size[j, i], size[j, -1] if i == 0 else size[j, i])
        for j in range(ny)
        for i in range(nx)
    }
    heap = [(v, k) for k, v in best.items()]
    heapq.heapify(heap)
    done = set()
    while heap:
        v, (j, i) = heapq.heappop(heap)
        if (j, i) in done:
            continue
        done.add((j, i))
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1):
                if (dj, di) == (0, 0) or not 0 <= j + dj < ny:
                    continue
                n = (j + dj, (i + di) % nx)
                w = v + rate * _arc(lon[i], lat[j], lon[i] + di * 360 / nx, lat[j + dj])
                if w < best[n]:
                    best[n] = w
                    heapq.heappush(heap, (w, n))
    out = np.array([[best[j, i % nx] for i in range(nxp)] for j in range(ny)])
    return out


@settings(max_examples=40, deadline=None)
@given(
    st.integers(3, 7),
    st.integers(4, 10),
    st.floats(-80.0, 0.0),
    st.floats(0.1, 2.0),
    st.integers(0, 10_000),
)
def test_the_limit_is_the_shortest_paths_on_the_sphere(ny, nx, south, rate, seed):
    lat = np.linspace(south, south + (ny - 1) * 10.0, ny)
    lat = lat[lat <= 90.0] if lat[-1] > 90 else lat
    rng = np.random.default_rng(seed)
    size = rng.uniform(1e3, 2e6, (len(lat), nx + 1))
    size[:, -1] = size[:, 0]
    fast = limit_gradation_sphere(size, lat, rate)
    np.testing.assert_allclose(fast, reference_limit(size, lat, rate), rtol=1e-9)
    assert (fast <= size + 1e-6).all() and (fast[:, 0] == fast[:, -1]).all()


def test_a_coast_grades_to_h_max_by_true_distance():
    coast = shapely.LineString([(170.0, 0.0), (190.0, 0.0)])  # across 180
    g = Gradation(np.array([coast]), h_min=10e3, d_hold=0.0, d_grade=1000e3)
    grid = SphereGrid(1.0, south=-60.0)
    f = grid.field(grid.graded([g], lines_crs="EPSG:4326", h_max=60e3), "coast")
    # on the line (to the densifying's 2.5 km), the meridian 180 = -180 alike
    assert float(f.sel(x=180.0, y=0.0)) == float(f.sel(x=-180.0, y=0.0))
    assert float(f.sel(x=180.0, y=0.0)) == pytest.approx(10e3, abs=130.0)
    assert float(f.sel(x=-175.0, y=0.0)) == pytest.approx(10e3, abs=130.0)
    # 5 degrees of latitude north: 556 km of great circle
    want = 10e3 + 50e3 * 5 * math.radians(1) * EARTH_RADIUS / 1000e3
    assert float(f.sel(x=175.0, y=5.0)) == pytest.approx(want, rel=5e-3)  # WGS84
    assert float(f.sel(x=0.0, y=0.0)) == 60e3


def test_the_wavelength_term_wraps_round_the_world():
    raster = read_raster(data_path("etopo1_0.5deg_world.tif"))
    grid = SphereGrid(0.5, south=-80.0)
    depth = grid.depth(raster, "up")
    wave = TermSizes(wavelength_size(depth, per_wavelength=30.0, min_depth=10.0))
    f = combine(grid, [("wave", wave)], h_min=None, h_max=1e9, rate=None).field
    # mid-Pacific, 5,000 m or so: T sqrt(g d) / 30
    depth = -float(raster.sel(x=-150.0, y=0.0, method="nearest"))
    want = M2_PERIOD * math.sqrt(GRAVITY * depth) / 30.0
    assert float(f.sel(x=-150.0, y=0.0)) == pytest.approx(want, rel=0.05)
    # no seam at the antimeridian: the columns each side of it are alike
    row = f.sel(y=-30.0).values
    assert abs(row[0] - row[-1]) == 0.0
    assert abs(row[1] - row[0]) < 0.2 * row[0] and abs(row[-2] - row[-1]) < 0.2 * row[0]


def test_the_grid_wraps_round_and_measures_areas_on_the_sphere():
    grid = SphereGrid(10.0, south=-90.0)
    assert grid.shape == (19, 37) and grid.x[0] == -180.0 and grid.x[-1] == 180.0
    # every node but the repeated meridian: the whole sphere, to the cells' rule
    total = grid.km2(np.ones(grid.shape, dtype=bool))
    assert total == pytest.approx(4 * math.pi * EARTH_RADIUS**2 / 1e6, rel=0.02)


def test_a_sea_node_over_raster_land_takes_the_nearest_wet_depth():
    # a world ocean 4 km deep with a block of land 30 x 30 deg that the
    # domain does not have (an island the case dropped): its nodes are sea
    import xarray as xr

    from coastmesh.geometry.sphere import plane_crs
    from coastmesh.types import BoundarySegment, Domain

    lon = np.arange(-175.0, 180.0, 10.0)
    lat = np.arange(85.0, -90.0, -10.0)
    elevation = np.full((len(lat), len(lon)), -4000.0)
    block = (np.abs(lat[:, None] - 5.0) < 15) & (np.abs(lon[None, :] - 5.0) < 15)
    elevation[block] = 100.0
    raster = xr.DataArray(
        elevation,
        coords={"y": lat, "x": lon},
        dims=("y", "x"),
        attrs={"crs": "EPSG:4326"},
    )
    ring = shapely.Point(0, 0).buffer(3 * EARTH_RADIUS, 64).exterior  # to ~ -73 deg
    crs = plane_crs((0.0, -90.0))
    domain = Domain(
        shapely.Polygon(ring),
        (BoundarySegment(np.asarray(ring.coords), "shoreline", "coast", 1),),
        crs,
    )
    grid = SphereGrid(10.0, south=-80.0, domain=domain)
    depth = grid.depth(raster, "up")
    at = (grid.y[:, None] == 10.0) & (grid.x[None, :] == 10.0)
    assert grid.sea[at].all()
    assert depth[at][0] == pytest.approx(4000.0)  # the nearest wet cell's
    # read without the sea, the node takes the land's height: what it was
    from coastmesh.depth.grid import depth_on_grid

    land = depth_on_grid(raster, grid.x[:-1], grid.y, crs="EPSG:4326", positive="up")
    assert land[at[:, :-1]][0] == pytest.approx(-100.0)
