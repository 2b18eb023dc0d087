"""The slope, Courant and channel terms of a global case, on the world grid.

A small world ocean in the stereographic plane of a global case (everything
north of 60 S), with two blocks of land that leave a strait across the
antimeridian, sized on a :class:`~coastmesh.sizing.grid.SphereGrid` through
the terms themselves.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import shapely
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.case import (
    BathymetryConfig,
    ChannelConfig,
    CourantConfig,
    NodeDepthConfig,
    SizeConfig,
    parse_case,
)
from coastmesh.case.schema import Check, check_part
from coastmesh.case.terms import Bathymetry, Channels, Courant
from coastmesh.case.terms.base import SizeCase, SizeTables
from coastmesh.case.terms.courant import AUTO_PERCENTILE, AUTO_SHARE, auto_time_step
from coastmesh.errors import CoastmeshWarning
from coastmesh.geometry.earth import EARTH_RADIUS, GRAVITY, reproject
from coastmesh.geometry.sphere import plane_crs
from coastmesh.sizing.combine import Applied
from coastmesh.sizing.courant import round_step
from coastmesh.sizing.grid import SphereGrid
from coastmesh.sizing.sphere_channel import sphere_width
from coastmesh.types import BoundarySegment, Domain

PLANE = plane_crs((0.0, -90.0))
#: the two blocks of land: 160 to 178.5 E and 178.5 to 160 W, 10 S to 10 N
WEST = shapely.box(160.0, -10.0, 178.5, 10.0)
EAST = shapely.box(-178.5, -10.0, -160.0, 10.0)


def _world(*, islands=(WEST, EAST)) -> Domain:
    """The ocean north of 60 S in the plane, the islands cut out of it."""
    south = shapely.LineString([(lon, -60.0) for lon in np.linspace(-180, 180, 721)])
    shell = reproject(south, "EPSG:4326", PLANE)
    holes = [
        reproject(shapely.segmentize(i, 0.25).exterior, "EPSG:4326", PLANE)
        for i in islands
    ]
    polygon = shapely.Polygon(shell.coords, [h.coords for h in holes])
    segments = [BoundarySegment(np.asarray(shell.coords), "shoreline", "coast", 1)]
    segments += [
        BoundarySegment(np.asarray(h.coords), "shoreline", f"island{k}", 1)
        for k, h in enumerate(holes)
    ]
    return Domain(polygon, tuple(segments), PLANE)


def _raster(elevation=None) -> xr.DataArray:
    """A world raster of 1-degree cells, 4 km deep unless ``elevation`` says."""
    lon = np.arange(-179.5, 180.0, 1.0)
    lat = np.arange(89.5, -90.0, -1.0)
    values = np.full((len(lat), len(lon)), -4000.0)
    if elevation is not None:
        values = elevation(lon[None, :], lat[:, None])
    return xr.DataArray(
        values, coords={"y": lat, "x": lon}, dims=("y", "x"), attrs={"crs": "EPSG:4326"}
    )


def _case(domain: Domain, raster: xr.DataArray, **size) -> SizeCase:
    size.setdefault("h_max", 1000e3)
    config = check_part(SizeConfig(**size), SizeConfig, Check("test"), "mesh_size")
    depth = NodeDepthConfig(path="in_memory.tif")
    floor = config.h_min or min([g.h_min for g in config.gradations] or [1e9])
    return SizeCase(
        SizeTables(config, depth), domain, floor, read_depth=lambda part: raster
    )


def _grid(domain: Domain, cell: float = 1.0) -> SphereGrid:
    return SphereGrid(cell, south=-62.0, domain=domain)


def _node(grid: SphereGrid, lon: float, lat: float) -> tuple[int, int]:
    return int(np.argmin(np.abs(grid.y - lat))), int(np.argmin(np.abs(grid.x - lon)))


def test_the_terms_on_by_default_are_on_in_a_global_case_too():
    domain = _world()
    grid, raster = _grid(domain, 2.0), _raster()
    case = _case(domain, raster, h_min=50e3)  # enabled unset: on
    assert Channels().sizes(grid, case) is not None
    assert Courant().sizes(grid, case) is not None
    given_dt = _case(domain, raster, h_min=50e3, courant=CourantConfig(dt=60.0))
    assert Courant().sizes(grid, given_dt) is not None
    off = _case(domain, raster, courant=CourantConfig(dt=60.0, enabled=False))
    assert Courant().sizes(grid, off) is None
    off = _case(domain, raster, channels=ChannelConfig(enabled=False))
    assert Channels().sizes(grid, off) is None


def test_the_channel_term_puts_elements_across_a_strait_over_the_antimeridian():
    domain = _world()
    grid = _grid(domain)
    case = _case(domain, _raster(), h_min=20e3, channels=ChannelConfig(enabled=True))
    sizes = Channels().sizes(grid, case)
    width = sizes.layers["width"]
    np.testing.assert_array_equal(
        width, sphere_width(grid.sea, grid.y, max_width=3 * 1000e3)
    )
    # the strait: 3 degrees (334 km) between the blocks, its nodes at 179 E,
    # 180 and 179 W; 2 r of the largest disk that fits, 3 across
    j, i = _node(grid, 180.0, 0.0)
    assert grid.sea[j, i] and grid.sea[j, 0] and not grid.sea[j, i - 2]
    strait = 3 * math.radians(1.0) * EARTH_RADIUS
    assert strait / 1.15 - 111.2e3 <= width[j, i] <= strait
    assert sizes.upper[j, i] == pytest.approx(width[j, i] / 3)
    assert sizes.upper[j, 0] == sizes.upper[j, -1] == sizes.upper[j, 1]
    # open ocean: wider than elements_across * h_max, no bound
    assert np.isinf(sizes.upper[_node(grid, -100.0, 0.0)])
    # land (the blocks) takes its nearest water's size: the strait's beside it
    assert sizes.upper[_node(grid, 177.0, 0.0)] == sizes.upper[j, i]
    # the report: where the term set the size, on the sphere
    before = np.full(grid.shape, 1000e3)
    report = sizes.report(Applied(before, before))
    limited = grid.km2(grid.sea & (sizes.upper < before))
    assert report.limited_km2 == limited > 0 and report.narrow_channels == 0


def test_a_strait_narrower_than_two_elements_is_named_and_left_to_domain_close():
    domain = _world()
    grid = _grid(domain)
    # widths err narrow by up to a cell (111 km): the strait (296 km on the
    # grid) counts as narrow under 2 x 250 km, not under 2 x 200 km
    ask = ChannelConfig(enabled=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sizes = Channels().sizes(
            grid, _case(domain, _raster(), h_min=200e3, channels=ask)
        )
    before = np.full(grid.shape, 1e9)
    assert sizes.report(Applied(before, before)).narrow_channels == 0
    case = _case(domain, _raster(), h_min=250e3, channels=ask)
    with pytest.warns(CoastmeshWarning, match=r"left by \[domain\] close") as caught:
        sizes = Channels().sizes(grid, case)
    assert "1 channels are narrower than 2 elements of h_min = 250000 m" in str(
        caught[0].message
    )
    report = sizes.report(Applied(before, before))
    assert report.narrow_channels == 1 and report.narrow == "close"
    place = report.worst[0]
    assert abs(abs(place.lon) - 180.0) <= 1.0 and abs(place.lat) <= 10.0
    # its area on the sphere: 3 columns of 1 degree, at most the 21 rows
    # between the blocks (at their ends the water opens out)
    cell = math.radians(1.0) ** 2 * EARTH_RADIUS**2 / 1e6
    assert 3 * 15 * cell < report.narrow_km2 < 3 * 21 * cell


def test_the_slope_term_reads_the_sea_alone():
    # a raster of 4 km and a seamount at 20 W, 20 N; an island at 30 E the
    # case drops (min_area), land in the raster: the sea's slope sizes do
    # not change with the island's heights
    def seamount(lon, lat, island=100.0):
        d = -4000.0 + 3000.0 * np.exp(-((lon + 20.0) ** 2 + (lat - 20.0) ** 2) / 50.0)
        return np.where((np.abs(lon - 30.0) < 3) & (np.abs(lat) < 3), island, d)

    hole = shapely.box(60.0, 20.0, 70.0, 30.0)  # land in the domain too
    domain = _world(islands=(WEST, EAST, hole))
    grid = _grid(domain)
    b = BathymetryConfig(path="in_memory.tif", per_slope=10.0, min_depth=10.0)
    low = Bathymetry().sizes(grid, _case(domain, _raster(seamount), bathymetry=b))
    high = Bathymetry().sizes(
        grid,
        _case(domain, _raster(lambda x, y: seamount(x, y, 5000.0)), bathymetry=b),
    )
    np.testing.assert_array_equal(low.upper[grid.sea], high.upper[grid.sea])
    assert np.isinf(low.upper[~grid.sea]).all()
    # over the dropped island the sea takes the nearest wet depth (4 km,
    # flat): no slope; on the seamount's flank, 2 pi d / (n |grad d|)
    assert np.isinf(low.upper[_node(grid, 30.0, 0.0)])
    j, i = _node(grid, -20.0, 25.0)
    assert 1e3 < low.upper[j, i] < 1e6
    # across the antimeridian the columns -180 and 180 agree
    np.testing.assert_array_equal(low.upper[:, 0], low.upper[:, -1])


def test_the_courant_floor_takes_the_wet_depth_over_raster_land():
    def island(lon, lat):
        return np.where((np.abs(lon - 30.0) < 3) & (np.abs(lat) < 3), 100.0, -4000.0)

    domain = _world()
    grid = _grid(domain)
    co = CourantConfig(dt=60.0, courant_max=0.5, velocity=1.0)
    sizes = Courant().sizes(grid, _case(domain, _raster(island), courant=co))
    want = 60.0 * (math.sqrt(GRAVITY * 4000.0) + 1.0) / 0.5
    assert sizes.lower[_node(grid, 30.0, 0.0)] == pytest.approx(want, rel=1e-9)
    assert sizes.lower[grid.sea] == pytest.approx(want, rel=1e-9)


def reference_auto_time_step(h, speed, sea, areas, courant_max):
    """Loops: sort the sea's nodes by their stable step, add up the elements
    each holds (its area over h^2) until 1 % of all, take that node's step."""
    nodes = [
        (courant_max * h[k] / speed[k], areas[k] / h[k] ** 2)
        for k in np.ndindex(h.shape)
        if sea[k] and math.isfinite(speed[k]) and areas[k] > 0
    ]
    nodes.sort(key=lambda n: n[0])
    total = sum(w for _, w in nodes)
    held = 0.0
    for step, w in nodes:
        held += w
        if held >= AUTO_PERCENTILE / 100.0 * total:
            return round_step(AUTO_SHARE * step)
    return math.inf


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 10_000), st.integers(2, 12), st.integers(4, 12))
def test_auto_time_step_weights_each_node_by_its_area_on_the_sphere(seed, ny, nx):
    rng = np.random.default_rng(seed)
    grid = SphereGrid(180.0 / ny, south=-90.0)
    h = rng.uniform(1e3, 1e5, grid.shape)
    speed = rng.uniform(5.0, 250.0, grid.shape)
    speed[rng.random(grid.shape) < 0.1] = np.nan
    sea = rng.random(grid.shape) < 0.8
    areas = grid.areas
    fast = auto_time_step(h, speed, sea, 0.5, areas=areas)
    assert fast == reference_auto_time_step(h, speed, sea, areas, 0.5)


def test_dt_auto_on_the_sphere_is_the_area_weighted_percentile():
    domain = _world()
    grid = _grid(domain, 2.0)
    case = _case(domain, _raster(), courant=CourantConfig(enabled=True), h_min=50e3)
    sizes = Courant().sizes(grid, case)
    floored = np.random.default_rng(1).uniform(50e3, 500e3, grid.shape)
    report = sizes.report(Applied(floored, floored))
    speed = np.full(grid.shape, math.sqrt(GRAVITY * 4000.0) + 1.0)
    want = reference_auto_time_step(floored, speed, grid.sea, grid.areas, 0.5)
    assert report.auto and report.dt == want
    # the floor: dt (sqrt(g d) + u) / (0.7 courant_max) in the sea
    lower = sizes.lower_from(floored)
    np.testing.assert_allclose(lower[grid.sea], want * speed[grid.sea] / 0.35)
    # weighted by 1 / h^2 alone (as on a plane), the polar nodes would count
    # as much as the equator's
    flat = auto_time_step(floored, speed, grid.sea, 0.5)
    assert flat != want or np.ptp(grid.areas[:, :-1]) == 0


def test_a_global_case_takes_the_slope_courant_and_channel_terms():
    text = (
        '[case]\nname = "w"\n[shorelines]\npath = "w.gpkg"\n'
        '[shoreline_sets.world]\nid = 1\n[domain]\nkind = "global"\n'
        '[mesh_size]\nh_max = "100 km"\n[mesh_size.bathymetry]\n'
        'path = "etopo.tif"\nper_slope = 10\n'
    )
    case = parse_case(text, "/cases/w.toml")
    assert case.size.bathymetry.per_slope == 10.0
    # unset: on, in a global case as in a regional one
    assert case.size.channels.enabled is True and case.size.courant.enabled is True
    asked = parse_case(
        text
        + '[mesh_size.channels]\nenabled = true\n[mesh_size.courant]\ndt = "2 min"\n',
        "/cases/w.toml",
    )
    assert asked.size.channels.enabled is True and asked.size.courant.dt == 120.0


def test_a_land_node_takes_its_nearest_sea_node_s_wavelength_size():
    """The mesher interpolates between a cell's nodes: a land node's size from the
    raster's land (min_depth) would reach into the sea along every coast. Land
    nodes take the nearest sea node's size; the sea nodes' sizes are the land's
    business of no one."""

    def land_blocks(lon, lat):  # the blocks are land (100 m up), the rest 4 km deep
        inside = ((lon > 160) | (lon < -160)) & (np.abs(lat) < 10)
        return np.where(inside, 100.0, -4000.0) + 0.0 * lat

    domain = _world()
    grid = _grid(domain)
    b = BathymetryConfig(path="in_memory.tif", per_wavelength=100.0, min_depth=10.0)
    upper = Bathymetry().sizes(grid, _case(domain, _raster(land_blocks), bathymetry=b))
    upper = upper.upper
    sea = grid.sea
    assert (~sea).any() and sea.any()
    deep = upper[sea].min()
    # no land node is finer than the sea around it (min_depth would be 4.4 km)
    assert (upper[~sea & (grid.y[:, None] > -60)] >= deep).all()
    # a land node near the coast holds its nearest sea node's value; one far
    # inland, where no mesh is made, no bound
    j, i = _node(grid, 177.0, 0.0)  # 1.5 cells inside the west block
    assert not sea[j, i] and upper[j, i] == deep
    j, i = _node(grid, 169.0, 0.0)  # its middle
    assert not sea[j, i] and np.isinf(upper[j, i])


def test_a_field_on_the_world_grid_across_the_antimeridian(tmp_path):
    """A lon/lat mesh source across 180: sizes where it is fast, on the sphere."""
    import xarray as xr

    from coastmesh.case.terms import FieldConfig, Fields

    domain = _world(islands=())
    # a UGRID source of lon/lat nodes every 2 degrees from 170 E to 170 W, over
    # the antimeridian (longitudes -180..180: its triangles there are split by
    # the grid's seam), with a peak speed of 3 m/s north of the equator
    lon = np.concatenate([np.arange(170.0, 180.1, 2.0), np.arange(-178.0, -169.9, 2.0)])
    lat = np.arange(-20.0, 20.1, 2.0)
    glon, glat = np.meshgrid(lon, lat)
    nx = len(lon)
    rows = [
        [j * nx + i, j * nx + i + 1, (j + 1) * nx + i + 1]
        for j in range(len(lat) - 1)
        for i in range(nx - 1)
    ] + [
        [j * nx + i, (j + 1) * nx + i + 1, (j + 1) * nx + i]
        for j in range(len(lat) - 1)
        for i in range(nx - 1)
    ]
    speed = np.where(glat.ravel() > 0, 3.0, 1.0)
    xr.Dataset(
        {
            "mesh2d": (
                (),
                0,
                {
                    "cf_role": "mesh_topology",
                    "topology_dimension": 2,
                    "node_coordinates": "lon lat",
                    "face_node_connectivity": "faces",
                },
            ),
            "wgs84": ((), 0, {"epsg": 4326}),
            "lon": ("node", glon.ravel(), {"standard_name": "longitude"}),
            "lat": ("node", glat.ravel(), {"standard_name": "latitude"}),
            "faces": (("face", "three"), np.array(rows), {"start_index": 0}),
            "vel_peak": ("node", speed, {"mesh": "mesh2d", "location": "node"}),
        }
    ).to_netcdf(tmp_path / "pacific.nc")
    field = FieldConfig(
        source=tmp_path / "pacific.nc", variable="vel_peak", values=(2.0,), sizes=(5e3,)
    )
    case = _case(domain, _raster(), h_min=50e3, fields=(field,))
    grid = _grid(domain)
    with pytest.warns(CoastmeshWarning, match="does not cover"):
        sizes = Fields().sizes(grid, case)
    fast = sizes.upper < np.inf
    assert np.isfinite(sizes.upper[_node(grid, 175.0, 10.0)])
    assert np.isfinite(sizes.upper[_node(grid, -175.0, 10.0)])
    assert sizes.upper[_node(grid, 180.0, 10.0)] == 5e3  # across the seam
    assert np.isinf(sizes.upper[_node(grid, 175.0, -10.0)])  # slow: no bound
    assert np.isinf(sizes.upper[_node(grid, 0.0, 10.0)])  # off the source
    # the floor is lowered there alone (h_min given: clamped, with a warning)
    assert sizes.floor is None
    report = sizes.report(
        Applied(np.full(grid.shape, 1000e3), np.where(fast, 5e3, 50e3))
    )
    (entry,) = report.entries
    # the fast band, 0 to 20 N by 20 degrees of longitude, on the sphere: about
    # 28 by 24 degrees with the two cells the term reaches past its cover and
    # the two cells its sizes are spread by (neighbour_min, spread_cells: a
    # cell, and the 5 km elements' circumradius rounded up to one)
    band = (
        (EARTH_RADIUS**2)
        * math.radians(28.0)
        * (math.sin(math.radians(22.0)) + math.sin(math.radians(2.0)))
        / 1e6
    )
    assert entry.km2 == pytest.approx(band, rel=0.2)
    assert entry.elements_after > entry.elements_before
