"""A DEM coast at every level, closed by open boundaries that cross in the sea.

Issue 48 (item 3): a case whose three open boundaries cross one another in the
open sea (a meridian and two parallels, every end 0.1 deg past a crossing)
must be closed at 0.5, 1, 2 and 10 m by the same rule as at 0 m. Here: the
west coast of Ireland from the bundled ETOPO1 0.1 deg grid, the meridian
12 W from 51.5 to 54.3 N, and the parallels 51.6 and 54.2 N from 12.1 W east
onto the land at 9 W. Each level's domain is compared with one built
without coastmesh's domain code: the box between the crossings and the
raster's east edge less the land above the level, the part that holds the
seed (loxodromes along a meridian or a parallel are straight in lon/lat).
The sea grows as the coast rises, each level's sea holds the one below, and
the open boundaries end at the crossings.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from pyproj import Geod

from coastmesh.case import parse_case
from coastmesh.case.pipeline import (
    CaseRun,
    RunContext,
    domain_stage,
    shoreline_stage,
    strategy_of,
)
from coastmesh.data import path as data_path
from coastmesh.geometry import land_from_grid
from coastmesh.io import read_raster
from coastmesh.types import quiet_stage

ETOPO = data_path("etopo1_0.1deg_nwshelf.tif")
BOX = (-13.0, 51.0, -8.0, 55.0)
LEVELS = (0.0, 0.5, 1.0, 2.0, 10.0)
WEST, SOUTH, NORTH, EAST = -12.0, 51.6, 54.2, -9.0
SEED = (-11.0, 53.0)
GEOD = Geod(ellps="WGS84")

CASE = f"""
[case]
name = "west_ireland"

[shorelines]
raster = "{ETOPO}"
level = "LEVEL m"
bbox = {list(BOX)}

[shoreline_sets.contour]
id = 10

[domain]
seed = {list(SEED)}

[[open_boundaries]]
name = "west"
id = 2
kind = "loxodrome"
start = [{WEST}, {SOUTH - 0.1}]
bearing = 0
end_lat = {NORTH + 0.1}

[[open_boundaries]]
name = "south"
id = 3
kind = "loxodrome"
start = [{WEST - 0.1}, {SOUTH}]
bearing = 90
end_lon = {EAST}

[[open_boundaries]]
name = "north"
id = 4
kind = "loxodrome"
start = [{WEST - 0.1}, {NORTH}]
bearing = 90
end_lon = {EAST}

[mesh_size]
h_max = "10 km"
"""


def domain_at(level: float):
    """Run the case's shoreline and domain stages; return the domain."""
    text = CASE.replace("LEVEL", f"{level:g}")
    config = parse_case(text, Path(__file__))
    run = CaseRun(config, strategy_of(config))
    ctx = RunContext(1, None, quiet_stage)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # every boundary reaches the domain
        run = domain_stage(shoreline_stage(run, ctx), ctx)
    return run.domain.domain


def expected_sea(level: float) -> shapely.Polygon:
    """The sea between the crossings at ``level``, without the domain code."""
    raster = read_raster(ETOPO, bbox=BOX)
    land = shapely.union_all(
        land_from_grid(raster.x.values, raster.y.values, raster.values, level)
    )
    box = shapely.box(WEST, SOUTH, BOX[2], NORTH)  # Galway Bay runs past 9 W
    (sea,) = [p for p in shapely.get_parts(box - land) if p.covers(shapely.Point(SEED))]
    return sea


def km2(geometry) -> float:
    """Geodesic area in km2 (edges split to 0.01 degree)."""
    area = GEOD.geometry_area_perimeter(shapely.segmentize(geometry, 0.01))[0]
    return abs(area) / 1e6


def test_crossing_boundaries_close_the_sea_at_every_level():
    areas, below = [], None
    for level in LEVELS:
        domain = domain_at(level)
        sea = domain.polygon
        expected = expected_sea(level)
        assert km2(sea) == pytest.approx(km2(expected), rel=1e-8), level
        assert km2(shapely.symmetric_difference(sea, expected)) < 0.01, level
        # the open boundaries end at the crossings: nothing of the 0.1 deg past
        assert shapely.bounds(sea)[[0, 1, 3]] == pytest.approx([WEST, SOUTH, NORTH])
        opened = {s.name: s.coords for s in domain.segments if s.kind == "open"}
        assert set(opened) == {"west", "south", "north"}, level
        west = opened["west"]
        assert np.allclose(west[:, 0], WEST)
        assert sorted(west[[0, -1], 1]) == pytest.approx([SOUTH, NORTH])
        for name, lat in (("south", SOUTH), ("north", NORTH)):
            assert np.allclose(opened[name][:, 1], lat)
            assert opened[name][:, 0].min() == pytest.approx(WEST)
        if below is not None:  # the sea at a level holds the sea below it
            assert km2(shapely.difference(below, sea)) < 1e-6, level
        below = sea
        areas.append(km2(sea))
    # measured: 39,862, 39,924, 39,987, 40,092 and 40,956 km2 (0 to 10 m)
    assert np.all(np.diff(areas) > 50.0), areas
    assert areas[-1] - areas[0] == pytest.approx(1094, abs=5)
