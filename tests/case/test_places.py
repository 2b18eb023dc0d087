"""Places of a site read from a vector file: one polygon, or one line."""

from __future__ import annotations

import json

import pytest
import shapely
from pyproj import CRS

from coastmesh.case.pipeline.places import file_place
from coastmesh.errors import ConfigError, InputDataError

LONLAT = CRS.from_epsg(4326)


def _geojson(path, geometries):
    features = [
        {"type": "Feature", "properties": {}, "geometry": shapely.geometry.mapping(g)}
        for g in geometries
    ]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    return path


def test_touching_polygons_are_one_area_and_apart_two(tmp_path):
    a, b = shapely.box(0, 0, 1, 1), shapely.box(1, 0, 2, 1)
    one = file_place(
        _geojson(tmp_path / "a.geojson", [a, b]),
        None,
        LONLAT,
        "f",
        dimension=2,
        what="farm",
    )
    assert one.equals(shapely.box(0, 0, 2, 1))
    apart = _geojson(tmp_path / "b.geojson", [a, shapely.box(3, 0, 4, 1)])
    with pytest.raises(
        ConfigError, match="make 2 separate areas; give one farm per area"
    ):
        file_place(apart, None, LONLAT, "f", dimension=2, what="farm")


def test_lines_end_to_end_are_one_line_and_apart_two(tmp_path):
    a = shapely.LineString([(0, 0), (1, 0)])
    b = shapely.LineString([(1, 0), (1, 1)])
    one = file_place(
        _geojson(tmp_path / "a.geojson", [a, b]),
        None,
        LONLAT,
        "l",
        dimension=1,
        what="[[lines]] entry",
    )
    assert one.geom_type == "LineString" and one.length == pytest.approx(2.0)
    apart = _geojson(tmp_path / "b.geojson", [a, shapely.LineString([(3, 0), (4, 0)])])
    with pytest.raises(
        ConfigError, match=r"2 separate lines; give one \[\[lines\]\] en"
    ):
        file_place(apart, None, LONLAT, "l", dimension=1, what="[[lines]] entry")


def test_a_file_without_the_shapes_asked_is_named(tmp_path):
    points = _geojson(tmp_path / "p.geojson", [shapely.Point(0, 0)])
    with pytest.raises(InputDataError, match=r"p\.geojson has no lines"):
        file_place(points, None, LONLAT, "l", dimension=1, what="[[lines]] entry")
    with pytest.raises(InputDataError, match=r"p\.geojson has no polygons"):
        file_place(points, None, LONLAT, "f", dimension=2, what="farm")
