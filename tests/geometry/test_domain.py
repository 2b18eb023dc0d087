"""build_domain against independent shapely constructions and on real shorelines."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import CRS, Transformer

from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.domain import (
    OpenBoundary,
    build_domain,
    domain_with_land,
    polygon_areas,
    smaller_than,
)
from coastmesh.geometry.rhumb import Loxodrome


def _bay():
    """A U-shaped coast (land on three sides) closed by one open line."""
    land = shapely.box(0, 0, 10, 10).difference(shapely.box(2, 2, 8, 12))
    island = shapely.box(4, 5, 5, 6)
    mouth = OpenBoundary(np.array([(1.0, 9.0), (9.0, 9.0)]), "mouth", 3)
    return [land, island], [mouth]


def test_bay_against_shapely():
    land, walls = _bay()
    domain, report = build_domain(land, walls, crs="EPSG:32630")
    expected = shapely.box(2, 2, 8, 9).difference(shapely.box(4, 5, 5, 6))
    assert domain.polygon.is_valid
    assert shapely.equals(domain.polygon, expected)
    assert report.holes == 1 and report.sea_faces == 1
    # the domain.segments cover every ring, in order, and carry the right ids
    kinds = {(s.kind, s.name, s.physical_id) for s in domain.segments}
    assert kinds == {("open", "mouth", 3), ("shoreline", "shoreline", 1)}
    for seg in domain.segments:
        line = shapely.LineString(seg.coords)
        if seg.kind == "open":
            assert line.length == pytest.approx(6.0)
            assert np.allclose(seg.coords[:, 1], 9.0)
        else:
            assert line.distance(shapely.boundary(shapely.union_all(land))) < 1e-12
    total = sum(shapely.LineString(s.coords).length for s in domain.segments)
    assert total == pytest.approx(domain.polygon.length)
    # the report as data: its fields, JSON as they are
    data = report.to_dict()
    assert json.loads(json.dumps(data)) == data
    assert data["holes"] == 1 and data["land_in"] == 2
    assert data["segments"] == report.segments and sum(data["segments"].values()) == 8
    assert "1 islands" in report.summary()


def test_seed_chooses_the_face_and_errors():
    land, walls = _bay()
    outer = OpenBoundary(
        np.array(
            [(-5.0, -5.0), (15.0, -5.0), (15.0, 15.0), (-5.0, 15.0), (-5.0, -5.0)]
        ),
        "outer",
        4,
    )
    domain, report = build_domain(
        land, [*walls, outer], crs="EPSG:32630", seed=(12.0, 0.0)
    )
    assert report.sea_faces == 2
    assert shapely.contains(domain.polygon, shapely.Point(12, 0))
    assert not shapely.contains(domain.polygon, shapely.Point(3, 3))
    with pytest.raises(ConfigError, match=r"seed = \(1.0, 1.0\): lies on land"):
        build_domain(land, walls, crs="EPSG:32630", seed=(1.0, 1.0))
    with pytest.raises(ConfigError, match="in no sea region"):
        build_domain(land, walls, crs="EPSG:32630", seed=(50.0, 50.0))
    with pytest.raises(InputDataError, match="enclose no sea"):
        build_domain(land, [], crs="EPSG:32630")


def test_a_seed_in_open_water_is_told_where_the_water_runs_out():
    # a bay closed by its mouth (one sea face) and, east of it, a strait that
    # runs off the data at its east end, with a side channel off its north
    # edge (metres, UTM 30N)
    bay = shapely.box(0, 0, 10_000, 10_000).difference(
        shapely.box(2000, 2000, 8000, 12_000)
    )
    land = [
        bay,
        shapely.box(10_000, 6000, 25_000, 10_000),
        shapely.box(27_000, 6000, 40_000, 10_000),
        shapely.box(10_000, 0, 40_000, 4000),
    ]
    mouth = OpenBoundary(np.array([(1000.0, 9000.0), (9000.0, 9000.0)]), "mouth", 3)
    with pytest.raises(ConfigError) as error:
        build_domain(land, [mouth], crs="EPSG:32630", seed=(12_000.0, 5000.0))
    message = str(error.value)
    assert "in no sea region closed by the shorelines and open boundaries" in message
    assert "runs out of the shoreline data at 2 places, the nearest at " in message
    # the side channel's mouth on the data's edge is nearer the seed than the
    # strait's east end; both are named, nearest first
    to_lonlat = Transformer.from_crs(32630, 4326, always_xy=True).transform
    first, second = (to_lonlat(26_000, 10_000), to_lonlat(40_000, 5000))
    named = [f"({lon:.4f}, {lat:.4f})" for lon, lat in (first, second)]
    assert f"nearest at {named[0]}, {named[1]} (lon, lat)" in message
    # a boundary with a loose end is named instead: the water runs round it
    gate = OpenBoundary(np.array([(30_000.0, 4000.0), (30_000.0, 5000.0)]), "gate", 4)
    with pytest.raises(ConfigError) as error:
        build_domain(land, [mouth, gate], crs="EPSG:32630", seed=(12_000.0, 5000.0))
    message = str(error.value)
    assert "open boundary 'gate' (id 4) ends at (" in message
    assert "the water runs round it" in message
    assert "runs out of the shoreline data" not in message


def test_no_sea_says_which_open_boundary_ends_short_and_where():
    bay = shapely.box(0, 0, 10_000, 10_000).difference(
        shapely.box(2000, 2000, 8000, 12_000)
    )
    short = OpenBoundary(np.array([(1000.0, 9000.0), (6000.0, 9000.0)]), "mouth", 3)
    with pytest.raises(InputDataError) as error:
        build_domain([bay], [short], crs="EPSG:32630")
    message = str(error.value)
    assert "enclose no sea: open boundary 'mouth' (id 3) ends at (" in message
    assert "(lon, lat), 2 km from land and the other open boundaries" in message
    assert message.count("ends at") == 1  # its west end is on land
    lon, lat = Transformer.from_crs(32630, 4326, always_xy=True).transform(6000, 9000)
    assert f"ends at ({lon:.4f}, {lat:.4f}) (lon, lat)" in message
    inland = OpenBoundary(np.array([(100.0, 100.0), (500.0, 100.0)]), "dyke", 4)
    with pytest.raises(InputDataError, match=r"'dyke' \(id 4\) lies wholly on land"):
        build_domain([bay], [inland], crs="EPSG:32630")
    with pytest.raises(InputDataError, match="there are no open boundaries"):
        build_domain([bay], [], crs="EPSG:32630")
    # both ends on the coast, or on another open boundary: nothing named
    mouth = OpenBoundary(np.array([(1000.0, 9000.0), (4000.0, 9000.0)]), "a", 3)
    rest = OpenBoundary(np.array([(4000.0, 9000.0), (4000.0, 9500.0)]), "b", 5)
    with pytest.raises(InputDataError) as error:
        build_domain([bay], [mouth, rest], crs="EPSG:32630")
    assert "'a'" not in str(error.value) and "'b' (id 5) ends at" in str(error.value)


def test_repairs_and_merges_dirty_land():
    land, walls = _bay()
    bowtie = shapely.Polygon([(3, 3), (3.5, 3.5), (3, 3.5), (3.5, 3)])  # invalid
    overlap = shapely.box(4.5, 5.5, 5.5, 6.5)  # overlaps the island
    domain, report = build_domain([*land, bowtie, overlap], walls, crs="EPSG:32630")
    assert domain.polygon.is_valid
    assert report.land_repaired == 1 and report.land_overlaps_merged >= 1
    assert report.holes == 3  # the merged island and the bow-tie's two triangles


def test_small_islands_dropped_by_area():
    land, walls = _bay()
    domain, report = build_domain(land, walls, crs="EPSG:32630", min_area=2.0)
    assert report.holes == 0 and report.holes_dropped == 1
    assert domain.polygon.area == pytest.approx(42.0)  # 6 x 7, the island filled


def test_real_orkney_closed_by_loxodromes():
    """Scapa Flow region: Orkney shorelines closed by rhumb lines on two sides."""
    features = json.loads(data_path("orkney_gshhg_f.geojson").read_text())["features"]
    land = [shapely.from_geojson(json.dumps(f["geometry"])) for f in features]
    west = Loxodrome((-3.5, 58.6), 0.0, end_lat=59.5).sample(2_000)
    north = Loxodrome((-3.6, 59.45), 90.0, end_lon=-2.3).sample(2_000)
    east = Loxodrome((-2.35, 59.5), 180.0, end_lat=58.55).sample(2_000)
    south = Loxodrome((-2.3, 58.62), 270.0, end_lon=-3.6).sample(2_000)
    walls = [
        OpenBoundary(c, n, i)
        for c, n, i in [
            (west, "west", 2),
            (north, "north", 3),
            (east, "east", 4),
            (south, "south", 5),
        ]
    ]
    domain, report = build_domain(
        land, walls, crs="EPSG:4326", seed=(-3.1, 58.85), min_area=1e5
    )
    assert domain.polygon.is_valid
    assert report.holes >= 5  # Hoy, Flotta, South Ronaldsay, ... as islands
    names = {s.name for s in domain.segments}
    assert "shoreline" in names and len(names & {"west", "north", "east", "south"}) >= 3
    # every ring is covered by its domain.segments, which join end to start
    assert sum(len(s.coords) - 1 for s in domain.segments) == sum(
        len(r.coords) - 1 for r in [domain.polygon.exterior, *domain.polygon.interiors]
    )


def _orkney():
    features = json.loads(data_path("orkney_gshhg_f.geojson").read_text())["features"]
    land = [shapely.from_geojson(json.dumps(f["geometry"])) for f in features]
    box = [(-3.5, 58.6), (-3.5, 59.45), (-2.35, 59.45), (-2.35, 58.62), (-3.5, 58.62)]
    walls = [OpenBoundary(np.array(box), "open", 2)]
    shorelines = [("far", 10, None), ("near", 11, shapely.box(-3.3, 58.7, -3.0, 59.0))]
    return land, walls, shorelines


@settings(deadline=None, max_examples=15)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12))
def test_closing_water_is_building_the_domain_again(seed, count):
    # small boxes of water made land, some across the coast, some joining
    # islands, some cutting water off: the same domain, boundary and report
    # as building it again from the land with them added
    land, walls, shorelines = _orkney()
    options = {"seed": (-3.1, 58.85), "min_area": 1e5, "shorelines": shorelines}
    domain, report = build_domain(land, walls, crs="EPSG:4326", **options)
    rng = np.random.default_rng(seed)
    centres = rng.uniform([-3.45, 58.65], [-2.4, 59.4], (count, 2))
    sizes = rng.uniform(0.002, 0.03, (count, 2))
    closed = shapely.box(*(centres - sizes).T, *(centres + sizes).T)
    if shapely.intersects(closed, shapely.Point(options["seed"])).any():
        with pytest.raises(ConfigError, match=r"seed .* lies in water closed"):
            domain_with_land(domain, closed, walls, report, land=land, **options)
        return
    again, again_report = build_domain(
        [*land, *closed], walls, crs="EPSG:4326", **options
    )
    fast, fast_report = domain_with_land(
        domain, closed, walls, report, land=land, **options
    )
    assert shapely.equals(fast.polygon, again.polygon)
    if shapely.intersects(closed, domain.polygon).any():  # not vacuous
        assert fast.polygon.area < domain.polygon.area
    assert fast_report.holes == again_report.holes
    assert fast_report.segments == again_report.segments
    tagged = {(g.name, g.kind, g.physical_id, len(g.coords)) for g in fast.segments}
    assert tagged == {
        (g.name, g.kind, g.physical_id, len(g.coords)) for g in again.segments
    }


@settings(deadline=None, max_examples=30)
@given(
    seed=st.integers(0, 2**32 - 1),
    lat=st.floats(-85, 85),
    limit=st.sampled_from([1e4, 1e6, 1e8]),
    crs=st.sampled_from(["EPSG:4326", "EPSG:4258", "EPSG:32630"]),
)
def test_smaller_than_is_the_one_by_one_comparison(seed, lat, limit, crs):
    """Many islands near the limit, some wide ones: the same answer as areas."""
    rng = np.random.default_rng(seed)
    n = 200
    lon0 = rng.uniform(-180, 170, n)
    lat0 = np.clip(lat + rng.normal(0, 2, n), -89, 88)
    side = np.sqrt(limit) * rng.uniform(0.7, 1.4, n) / 111e3  # degrees, near it
    side[:5] = rng.uniform(5, 20, 5)  # and some wider than 10 degrees
    width = side * rng.uniform(0.5, 2, n)
    if crs == "EPSG:32630":  # planar areas in metres: the same sides in metres
        lon0, lat0 = 5e5 + lon0 * 1e3, 5e6 + lat0 * 1e3
        side, width = side * 111e3, width * 111e3
    boxes = shapely.box(lon0, lat0, lon0 + width, lat0 + side)
    expected = polygon_areas(boxes, CRS(crs)) < limit
    got = smaller_than(boxes, CRS(crs), limit)
    np.testing.assert_array_equal(got, expected)
    assert 0 < expected.sum() < n


def test_geodesic_areas_are_pyprojs_bit_for_bit():
    # the rings read with shapely.get_coordinates, not pyproj's ring.xy: the
    # same sums, on real coasts (the Orkney GSHHG layer) and odd shapes
    from pyproj import Geod

    features = json.loads(data_path("orkney_gshhg_f.geojson").read_text())["features"]
    real = [shapely.geometry.shape(f["geometry"]) for f in features]
    box = shapely.box(-3, 58, -2, 59)
    odd = [
        box.difference(shapely.box(-2.8, 58.2, -2.5, 58.5)),  # a hole
        shapely.MultiPolygon([box, shapely.box(0, 0, 1, 1)]),
        shapely.Polygon(),
        shapely.box(-179, -89, 179, 89),
    ]
    polygons = np.array([*real, *odd], dtype=object)
    geod = Geod(ellps="WGS84")
    literal = [abs(geod.geometry_area_perimeter(p)[0]) for p in polygons]
    got = polygon_areas(polygons, CRS("EPSG:4326"))
    assert len(real) > 50
    assert got.tolist() == literal


@settings(max_examples=20, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    pole=st.sampled_from([(0.0, -90.0), (103.0, 46.0), (-40.0, 75.0)]),
)
def test_areas_in_a_world_plane_are_areas_on_the_earth(seed, pole):
    # islands of 50 to 2000 km2 anywhere but round the pole, in the plane of a
    # global case: their areas (and min_area's test) are those on the WGS84
    # ellipsoid, as in lon/lat, not the plane's (k^2 larger) nor the sphere's
    from pyproj import Geod

    from coastmesh.geometry.earth import reproject
    from coastmesh.geometry.sphere import plane_crs, stereographic_scale

    rng = np.random.default_rng(seed)
    n = 40
    lon, lat = rng.uniform(-180, 180, n), rng.uniform(-70, 70, n)
    far = stereographic_scale(lon, lat, pole) < 20  # not beside the pole
    lon, lat = lon[far], lat[far]
    side = np.sqrt(rng.uniform(50e6, 2000e6, len(lon))) / 111e3
    boxes = shapely.segmentize(
        shapely.box(lon, lat, lon + side / np.cos(np.radians(lat)), lat + side), 0.01
    )
    wgs84 = Geod(ellps="WGS84")
    literal = np.array([abs(wgs84.geometry_area_perimeter(b)[0]) for b in boxes])
    lonlat = CRS("EPSG:4326")
    np.testing.assert_allclose(polygon_areas(boxes, lonlat), literal, rtol=1e-9)
    crs = plane_crs(pole)
    plane = reproject(boxes, "EPSG:4326", crs)
    got = polygon_areas(plane, crs)
    np.testing.assert_allclose(got, literal, rtol=1e-4)
    assert not np.allclose(shapely.area(plane), literal, rtol=0.01)
    # a limit between two of the areas, in the widest gap of the middle half
    ranked = np.sort(literal)
    q = len(ranked) // 4
    i = q + int(np.argmax(ranked[q + 1 : 3 * q + 1] / ranked[q : 3 * q]))
    limit = float(np.sqrt(ranked[i] * ranked[i + 1]))
    np.testing.assert_array_equal(smaller_than(plane, crs, limit), literal < limit)
