"""What a strategy hands ``build_case_domain``: where the case's places go, a check.

A regional case gives its region boxes and seed in the CRS its domain is built
in (``as_given``); a global case gives them in lon/lat and builds in the
stereographic plane, and checks that its ``[[cuts]]`` run land to land.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from pyproj import CRS

from coastmesh.case import (
    CaseConfig,
    PolylineBoundary,
    RegionConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
    SizeConfig,
)
from coastmesh.case.config import DomainConfig
from coastmesh.case.pipeline.domain import as_given, build_case_domain, with_land
from coastmesh.case.pipeline.world import _check_cut_ends, _from_lonlat
from coastmesh.errors import ConfigError
from coastmesh.geometry import OpenBoundary, reproject
from coastmesh.geometry.sphere import plane_crs

UTM = CRS.from_epsg(32630)
#: land round two lakes: the west one (10-45 km) and the east one (55-90 km)
LAND = np.array(
    [
        shapely.box(0, 0, 100e3, 50e3)
        .difference(shapely.box(10e3, 10e3, 45e3, 40e3))
        .difference(shapely.box(55e3, 10e3, 90e3, 40e3))
    ],
    dtype=object,
)
SETS = {"coast": LAND, "fine": LAND}


def _config(**kw) -> CaseConfig:
    return CaseConfig(
        name="t",
        shorelines=ShorelinesConfig("coast.gpkg"),
        sets=[ShorelineSetConfig("coast", 1), ShorelineSetConfig("fine", 2)],
        regions=[RegionConfig("fine", box=(0.0, 0.0, 30e3, 50e3))],
        size=SizeConfig(h_max="5 km"),
        domain=DomainConfig(seed=(20e3, 20e3)),
        **kw,
    )


def _east(geometry: shapely.Geometry) -> shapely.Geometry:
    """A stand-in for a strategy's ``place``: 50 km east."""
    return shapely.affinity.translate(geometry, 50e3)


def test_a_regional_case_s_places_are_as_given():
    state = build_case_domain(_config(), SETS, UTM, mesh_crs=UTM, output_crs=UTM)
    assert state.domain.polygon.bounds == (10e3, 10e3, 45e3, 40e3)  # the seed's lake
    assert state.seed == (20e3, 20e3)
    assert state.regions[0][2].bounds == (0.0, 0.0, 30e3, 50e3)
    assert as_given(LAND[0]) is LAND[0]
    # the domain with land added keeps the seed in the domain's CRS
    closed = np.array([shapely.box(10e3, 30e3, 45e3, 40e3)], dtype=object)
    assert with_land(state, _config(), closed).seed == state.seed


def test_place_puts_the_region_boxes_and_the_seed_in_the_domain_s_crs():
    state = build_case_domain(
        _config(), SETS, UTM, mesh_crs=UTM, output_crs=UTM, place=_east
    )
    assert state.seed == (70e3, 20e3)
    assert state.domain.polygon.bounds == (55e3, 10e3, 90e3, 40e3)  # the east lake
    assert state.regions[0][2].bounds == (50e3, 0.0, 80e3, 50e3)


def test_check_walls_sees_the_walls_and_land_before_the_domain_is_built():
    seen = []

    def check(walls, land):
        seen.append((walls, land))
        raise ConfigError("refused")

    line = PolylineBoundary("cut", 3, points=((20e3, 20e3), (30e3, 20e3)))
    with pytest.raises(ConfigError, match=r"^refused$"):
        build_case_domain(
            _config(boundaries=[line]),
            SETS,
            UTM,
            mesh_crs=UTM,
            output_crs=UTM,
            check_walls=check,
        )
    ((walls, land),) = seen
    assert [w.name for w in walls] == ["cut"]
    stitched = shapely.union_all(land)  # the sets stitched, seams widened 50 m
    assert stitched.symmetric_difference(LAND[0]).area < 0.01 * LAND[0].area


def test_a_global_case_places_lon_lat_in_the_plane():
    lonlat, plane = CRS.from_epsg(4326), plane_crs((0.0, -90.0))
    place = _from_lonlat(lonlat, plane)
    box = shapely.box(-16.0, 48.0, 26.0, 70.0)
    expected = reproject(shapely.segmentize(box, 0.1), lonlat, plane)
    assert place(box).equals_exact(expected, 0.0)
    point = place(shapely.Point(-5.0, 36.0))
    assert point.equals_exact(reproject(shapely.Point(-5.0, 36.0), lonlat, plane), 0)


def test_a_global_case_s_cuts_run_land_to_land():
    lonlat, plane = CRS.from_epsg(4326), plane_crs((0.0, -90.0))
    land = np.array(
        [reproject(shapely.box(-10.0, 30.0, 0.0, 40.0), lonlat, plane)], dtype=object
    )
    inside = reproject(shapely.LineString([(-6.0, 35.0), (-4.0, 35.0)]), lonlat, plane)
    wet = reproject(shapely.LineString([(-6.0, 35.0), (5.0, 35.0)]), lonlat, plane)
    config = _config()
    walls = (OpenBoundary(np.asarray(inside.coords), "ok", 3),)
    _check_cut_ends(config, walls, land, plane, lonlat)
    walls += (OpenBoundary(np.asarray(wet.coords), "gibraltar", 4),)
    with pytest.raises(ConfigError) as info:
        _check_cut_ends(config, walls, land, plane, lonlat)
    assert str(info.value) == (
        "CaseConfig: cuts[1] ('gibraltar'): its end (5.0000, 35.0000) is in the "
        "water, not on land: a cut must run from land to land, across the sea it "
        "takes off"
    )
