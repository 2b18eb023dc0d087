"""The world ocean from world shorelines: dateline joins, the pole, the plane."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from conftest import synthetic_world
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Geod, Proj

from coastmesh.data import path as data_path
from coastmesh.errors import InputDataError
from coastmesh.geometry.earth import EARTH_RADIUS, reproject
from coastmesh.geometry.sphere import plane_crs, stereographic_scale
from coastmesh.geometry.world import (
    close_narrow_water,
    join_dateline,
    polar_ring,
    world_ocean,
)
from coastmesh.io.vectors.vector import read_features

SPHERE = Geod(a=EARTH_RADIUS, b=EARTH_RADIUS)
SPHERE_AREA = 4.0 * math.pi * EARTH_RADIUS**2


@pytest.fixture(scope="module")
def world_low():
    return read_features(data_path("world_gshhg_l.zip"))


def _sphere_area(ring_lonlat: np.ndarray) -> float:
    """Area to the left of a lon/lat ring on the sphere (GeographicLib)."""
    area, _ = SPHERE.polygon_area_perimeter(ring_lonlat[:, 0], ring_lonlat[:, 1])
    return abs(area)


def _land_area(polygons) -> float:
    """Sum of the sphere areas of land polygons (exteriors less their holes)."""
    total = 0.0
    for p in shapely.get_parts(polygons):
        total += _sphere_area(shapely.get_coordinates(p.exterior))
        for hole in p.interiors:
            total -= _sphere_area(shapely.get_coordinates(hole))
    return total


# --- the plane --------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    st.floats(-180, 180),
    st.floats(-80, 80),
    st.floats(-180, 180),
    st.floats(-90, 90),
)
def test_the_scale_factor_is_pyprojs(lon, lat, pole_lon, pole_lat):
    pole = (pole_lon, pole_lat)
    k = float(stereographic_scale(lon, lat, pole))
    # far enough from the pole for the plane to be finite
    if k > 1e3:
        return
    factors = Proj(plane_crs(pole)).get_factors(lon, lat)
    # conformal: one scale in every direction, on the sphere of EARTH_RADIUS
    assert factors.parallel_scale == pytest.approx(k, rel=1e-6)
    assert factors.meridional_scale == pytest.approx(k, rel=1e-6)


def test_the_pole_goes_to_infinity_and_its_antipode_to_the_origin():
    crs = plane_crs((30.0, -60.0))
    x, y = reproject(shapely.Point(-150.0, 60.0), "EPSG:4326", crs).coords[0]
    assert abs(x) < 1e-6 and abs(y) < 1e-6
    assert float(stereographic_scale(-150.0, 60.0, (30.0, -60.0))) == pytest.approx(1.0)
    with pytest.raises(InputDataError, match=r"pole \(0.0, 95.0\) is not on"):
        plane_crs((0.0, 95.0))


# --- joining at the dateline ------------------------------------------------


def test_halves_split_at_the_dateline_are_joined_on_the_real_layer(world_low):
    geoms = world_low.geometry
    ids = world_low.fields["id"]
    out = join_dateline(geoms)
    halves = np.char.endswith(ids.astype(str), ("-E")) | np.char.endswith(
        ids.astype(str), "-W"
    )
    assert halves.sum() == 12  # six polygons in two halves
    assert len(out) == len(geoms) - 6
    # Eurasia: one polygon past 180 whose sphere area is its two halves'
    eurasia = [g for g in out if g.bounds[0] < 0 < 180 < g.bounds[2]]
    assert len(eurasia) == 1
    pieces = geoms[np.isin(ids, ["0-E", "0-W"])]
    assert _land_area(eurasia) == pytest.approx(_land_area(pieces), rel=1e-9)
    # polygons away from the dateline come through untouched, in order
    away = geoms[~halves]
    assert shapely.equals_exact(out[: len(away)], away, tolerance=0).all()


def test_a_layer_that_does_not_touch_the_dateline_is_unchanged():
    boxes = [shapely.box(0, 0, 1, 1), shapely.box(170, 0, 180, 1)]
    out = join_dateline(boxes)
    assert len(out) == 2 and out[1].bounds == (170.0, 0.0, 180.0, 1.0)


# --- the polar ring -----------------------------------------------------------


def test_the_real_antarctic_coast_closes_round_the_pole(world_low):
    ids = world_low.fields["id"]
    halves = world_low.geometry[np.isin(ids, ["4-E", "4-W"])]
    (joined,) = [g for g in join_dateline(halves) if g.bounds[1] <= -90.0]
    ring = polar_ring(joined)
    assert (ring[-1] == ring[0] + [360.0, 0.0]).all() and (ring[:, 1] > -86.0).all()
    # longitudes run on over one turn: no edge jumps across the antimeridian
    assert (np.abs(np.diff(ring[:, 0])) < 10).all()
    # the ring holds Antarctica: the smaller side of it has the halves' area
    inside = min(_sphere_area(ring), SPHERE_AREA - _sphere_area(ring))
    assert inside == pytest.approx(_land_area(halves), rel=1e-6)


def test_a_polygon_that_does_not_reach_the_pole_has_no_polar_ring():
    with pytest.raises(InputDataError, match="does not reach latitude -90"):
        polar_ring(shapely.box(0, -80, 10, -70))
    half = shapely.Polygon([(0, -70), (180, -75), (180, -90), (0, -90)])
    with pytest.raises(InputDataError, match="both halves in the layer"):
        polar_ring(half)


# --- the world ocean ----------------------------------------------------------


def _ocean_area(ocean) -> float:
    """Sphere area of the plane polygon, through its rings in lon/lat."""
    rings = [ocean.polygon.exterior, *ocean.polygon.interiors]
    lonlat = [
        shapely.get_coordinates(reproject(r, ocean.crs, "EPSG:4326")) for r in rings
    ]
    outer = _sphere_area(lonlat[0])
    outer = max(outer, SPHERE_AREA - outer)  # the side away from the pole
    return outer - sum(_sphere_area(r) for r in lonlat[1:])


def test_the_world_ocean_of_the_low_resolution_layer(world_low):
    geoms = world_low.geometry
    ocean = world_ocean(geoms, world_low.crs)
    assert ocean.joined == 6 and ocean.enclosed == 0
    # every land polygon is a hole, but Antarctica, the outside
    assert ocean.islands == len(geoms) - 6 - 1
    assert ocean.polygon.is_valid
    # its area on the sphere is the sphere's less the land's (overlaps between
    # land polygons aside): 361 M km2
    area = _ocean_area(ocean)
    land = _land_area(geoms)
    assert area == pytest.approx(SPHERE_AREA - land, rel=2e-4)
    assert 3.55e14 < area < 3.65e14


def test_another_pole_on_land_gives_the_same_ocean(world_low):
    south = world_ocean(world_low.geometry, world_low.crs)
    siberia = world_ocean(world_low.geometry, world_low.crs, pole=(100.0, 65.0))
    assert siberia.islands == south.islands
    assert _ocean_area(siberia) == pytest.approx(_ocean_area(south), rel=1e-6)


def test_a_pole_in_the_sea_is_refused(world_low):
    with pytest.raises(InputDataError, match=r"pole \(-30.0, 0.0\) is in the sea"):
        world_ocean(world_low.geometry, world_low.crs, pole=(-30.0, 0.0))


def test_a_regional_layer_is_not_a_world_layer():
    orkney = read_features(data_path("orkney_gshhg_f.geojson"))
    with pytest.raises(InputDataError, match="covers both hemispheres"):
        world_ocean(orkney.geometry, orkney.crs)


def test_a_world_without_antarctica_is_refused(world_low):
    level = world_low.fields["level"]
    with pytest.raises(InputDataError, match="0 land polygons reach the South Pole"):
        world_ocean(world_low.geometry[level == 1], world_low.crs)


def test_a_projected_layer_is_refused(world_low):
    with pytest.raises(InputDataError, match="longitude and latitude"):
        world_ocean(world_low.geometry, "EPSG:3857")


# --- closing narrow water -------------------------------------------------------


def _disc(lon: float, lat: float, radius_km: float) -> shapely.Polygon:
    az = np.linspace(0.0, 360.0, 180, endpoint=False)
    x, y, _ = SPHERE.fwd(
        np.full(az.size, lon),
        np.full(az.size, lat),
        az,
        np.full(az.size, radius_km * 1e3),
    )
    return shapely.Polygon(np.column_stack([x, y])[::-1])


def _pair(lon: float, lat: float, gap_km: float) -> list[shapely.Polygon]:
    """Two 100 km discs with ``gap_km`` of sea between them, along a meridian."""
    _, north_lat, _ = SPHERE.fwd(lon, lat, 0.0, (100.0 + gap_km / 2) * 1e3)
    _, south_lat, _ = SPHERE.fwd(lon, lat, 180.0, (100.0 + gap_km / 2) * 1e3)
    return [_disc(lon, north_lat, 100.0), _disc(lon, south_lat, 100.0)]


def test_narrow_water_is_closed_at_its_width_on_the_earth_anywhere():
    # a strait 6 km wide near the plane's centre (k = 1.07) and one far out
    # (60 S: k = 15); a thin spit of land, 4 km wide, on a third island
    spit = shapely.union_all(
        [_disc(-130.0, 10.0, 150.0), shapely.box(-128.6, 9.98, -124.0, 10.02)]
    )
    extra = [*_pair(-140.0, 60.0, 6.0), *_pair(-120.0, -60.0, 6.0), spit]
    land = [*synthetic_world(), *extra]
    kept = world_ocean(land, "EPSG:4326", close=2e3)
    closed = world_ocean(land, "EPSG:4326", close=12e3)
    rings = {
        "north": _pair(-140.0, 60.0, 6.0)[0],
        "south": _pair(-120.0, -60.0, 6.0)[0],
    }

    def holes_near(ocean, polygon) -> int:
        where = reproject(polygon.centroid.buffer(3.0), "EPSG:4326", ocean.crs)
        return sum(
            shapely.Polygon(r).intersects(where) for r in ocean.polygon.interiors
        )

    for name, disc in rings.items():
        assert holes_near(kept, disc) == 2, name  # two islands
        assert holes_near(closed, disc) == 1, name  # one, the strait closed
    # the spit: 4 km wide, gone at 12 km, kept at 2 km
    spit_tip = reproject(shapely.Point(-124.5, 10.0), "EPSG:4326", kept.crs)
    assert not kept.polygon.contains(spit_tip)
    assert closed.polygon.contains(spit_tip)
    assert closed.closed >= 2 and kept.closed == 0  # the two pairs at least


def test_islands_of_keep_area_are_never_opened_away():
    # near the plane's centre (k ~ 1): a bar 3 km x 300 km (900 km2), narrow
    # everywhere; an island of 150 km radius with a spit 4 km wide; and a
    # small bar 3 km x 50 km (150 km2)
    bar = shapely.box(0.0, 0.0, 3e3, 300e3)
    big = shapely.union_all(
        [shapely.Point(500e3, 0).buffer(150e3), shapely.box(640e3, -2e3, 700e3, 2e3)]
    )
    small = shapely.box(-300e3, 0.0, -297e3, 50e3)
    land = np.array([bar, big, small], dtype=object)

    def area_over(closed, polygon) -> float:
        return shapely.union_all(closed).intersection(polygon).area / polygon.area

    opened, _ = close_narrow_water(land, 12e3)
    assert area_over(opened, bar) == 0.0 and area_over(opened, small) == 0.0
    assert area_over(opened, shapely.box(660e3, -2e3, 700e3, 2e3)) == 0.0  # spit
    kept, _ = close_narrow_water(land, 12e3, keep_area=500e6)
    assert area_over(kept, bar) > 0.99  # whole (to the seam clean-up's metre)
    assert area_over(kept, big) > 0.99  # with its spit
    assert area_over(kept, small) == 0.0  # under keep_area: opened away


def test_a_geos_error_on_the_world_layer_names_the_place_in_lonlat():
    import shapely.errors

    from coastmesh.errors import InputDataError
    from coastmesh.geometry.sphere import plane_crs
    from coastmesh.geometry.world import geos_errors_named

    message = (
        "TopologyException: side location conflict at -4803976.18 -3753404.44. "
        "This can occur if the input geometry is invalid."
    )
    with pytest.raises(InputDataError, match=r"world\.gpkg") as caught:
        with geos_errors_named("world.gpkg", plane_crs((0.0, -90.0))):
            raise shapely.errors.GEOSException(message)
    assert "at (128.0009, 38.8625) (lon, lat)" in str(caught.value)
    assert "side location conflict" in str(caught.value)
