"""case/schema/convert.py: each converter's values, and errors that name the key."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from pyproj import CRS

from coastmesh.case import schema
from coastmesh.errors import ConfigError

KEY = "mesh_size.x"


@pytest.mark.parametrize(
    ("convert", "value", "expected"),
    [
        (schema.string, "north", "north"),
        (schema.boolean, np.bool_(True), True),
        (schema.number, 3, 3.0),
        (schema.number, np.float32(0.5), 0.5),
        (schema.positive, 1e-9, 1e-9),
        (schema.integer(1), np.int64(4), 4),
        (schema.integer(0), 0, 0),
        (schema.length(), "2 km", 2000.0),
        (schema.length(), 150, 150.0),
        (schema.length(positive=False), 0, 0.0),
        (schema.length(signed=True), "-3 m", -3.0),
        (schema.length_with_unit, 0, 0.0),
        (schema.length_with_unit, "0.5 km", 500.0),
        (schema.area, "1 km2", 1e6),
        (schema.area, "2 ha", 2e4),
        (schema.area, 0, 0.0),
        (schema.area_with_unit, "5000 m2", 5000.0),
        (schema.duration, "1.5 h", 5400.0),
        (schema.duration, 30, 30.0),
        (schema.duration_with_unit, "30 min", 1800.0),
        (schema.speed, "3.6 km/h", 1.0),
        (schema.speed, 0, 0.0),
        (schema.speed_with_unit, "2 kn", 2 * 1852 / 3600),
        (schema.point, [1, 2.5], (1.0, 2.5)),
        (schema.point, (np.float64(-3.0), 58), (-3.0, 58.0)),
        (schema.points, [[0, 0], [1, 1]], ((0.0, 0.0), (1.0, 1.0))),
        (schema.box, [0, -1, 2, 3], (0.0, -1.0, 2.0, 3.0)),
        (schema.names, "full", ("full",)),
        (schema.names, ["a", "b"], ("a", "b")),
        (schema.choice(("wet", "keep")), "keep", "keep"),
        (schema.crs, "EPSG:32630", "EPSG:32630"),
        (schema.crs, CRS.from_epsg(4326), "EPSG:4326"),
        (schema.path, Path("data/coast.gpkg"), Path("data/coast.gpkg")),
    ],
)
def test_good_values_convert(convert, value, expected):
    result = convert(value, KEY)
    assert result == expected
    assert type(result) is type(expected)


@pytest.mark.parametrize(
    ("convert", "value", "message"),
    [
        (schema.string, "  ", "= '  ': expected a non-empty string"),
        (schema.string, 3, "= 3: expected a non-empty string"),
        (schema.boolean, 1, "= 1: expected true or false"),
        (schema.boolean, "true", "= 'true': expected true or false"),
        (schema.number, True, "= True: expected a finite number"),
        (schema.number, "3", "= '3': expected a finite number"),
        (schema.number, math.inf, "= inf: expected a finite number"),
        (schema.number, math.nan, "= nan: expected a finite number"),
        (schema.positive, 0, "= 0: must be > 0"),
        (schema.positive, -0.1, "= -0.1: must be > 0"),
        (schema.integer(1), 0, "= 0: expected an integer >= 1"),
        (schema.integer(1), 2.0, "= 2.0: expected an integer >= 1"),
        (schema.integer(1), True, "= True: expected an integer >= 1"),
        (schema.length(), -5, "= -5 m: must be > 0"),
        (schema.length(), 0, "= 0 m: must be > 0"),
        (schema.length(), "-2 km", "= '-2 km': must be > 0"),
        (schema.length(positive=False), -1, "= -1 m: must be >= 0"),
        (schema.length(), "2 miles", "= '2 miles': unknown unit 'miles'"),
        (schema.length(), "10", "= '10': write a number and a unit"),
        (schema.length_with_unit, 5, "= 5: give a unit (m, km or deg)"),
        (schema.area, -1, "= -1: must be >= 0"),
        (schema.area, "1 acre", "unknown unit 'acre'"),
        (schema.area_with_unit, 5, "= 5: write a number and a unit"),
        (schema.duration, 0, "= 0 s: must be > 0"),
        (schema.duration, "-1 h", "= '-1 h': must be > 0"),
        (schema.duration_with_unit, "1 day", "unknown unit 'day'"),
        (schema.speed, -1, "= -1: must be >= 0"),
        (schema.speed, "fast", "= 'fast': write a number and a unit"),
        (schema.point, [1, 2, 3], "= [1, 2, 3]: expected [x, y] (longitude, latitude)"),
        (schema.point, "1, 2", "= '1, 2': expected [x, y]"),
        (schema.points, [[0, 0]], ": expected a list of at least two [x, y] points"),
        (schema.box, [0, 0, 1], "= [0, 0, 1]: expected [minx, miny, maxx, maxy]"),
        (schema.box, [1, 0, 0, 1], "= [1, 0, 0, 1]: need minx < maxx and miny < maxy"),
        (schema.box, [0, 1, 1, 1], "need minx < maxx and miny < maxy"),
        (schema.names, [], "= []: expected a name or a list of names"),
        (
            schema.choice(("wet", "keep")),
            "dry",
            "= 'dry': expected one of 'wet', 'keep'",
        ),
        (schema.crs, "EPSG:99999999", "= 'EPSG:99999999': not a CRS pyproj knows"),
        (schema.path, "", "= '': expected a non-empty string"),
    ],
)
def test_bad_values_name_the_key_and_the_value(convert, value, message):
    with pytest.raises(ConfigError) as info:
        convert(value, KEY)
    text = str(info.value)
    assert text.startswith(KEY), text
    assert message in text, text


@pytest.mark.parametrize(
    ("convert", "value", "where"),
    [
        (schema.point, [1, "x"], f"{KEY}[1] = 'x'"),
        (schema.points, [[0, 0], [1, None]], f"{KEY}[1][1] = None"),
        (schema.box, [0, 0, math.nan, 1], f"{KEY}[2] = nan"),
        (schema.names, ["a", ""], f"{KEY}[1] = ''"),
    ],
)
def test_an_item_of_a_list_is_named_by_its_place(convert, value, where):
    with pytest.raises(ConfigError, match=r"^" + re.escape(where)):
        convert(value, KEY)


def test_paths_expand_the_home_folder():
    assert schema.path("~/coast.gpkg", KEY) == Path.home() / "coast.gpkg"


def test_a_crs_without_an_epsg_code_is_kept_as_wkt():
    custom = CRS.from_proj4("+proj=stere +lat_0=90 +lon_0=0 +R=6371000")
    text = schema.crs(custom, KEY)
    assert CRS.from_user_input(text) == custom
    assert not text.startswith("EPSG:")
