"""case/boundaries: each kind's keys read, checked, written back, named in errors."""

from __future__ import annotations

from pathlib import Path

import pytest
import tomli_w
from boundary_tables import SOURCE, read_boundaries

from coastmesh.case.boundaries import (
    BOUNDARY_KINDS,
    BlendBoundary,
    BoundaryConfig,
    GreatCircleBoundary,
    LoxodromeBoundary,
    LoxodromeConfig,
    PolylineBoundary,
)
from coastmesh.case.schema import dump_part
from coastmesh.errors import ConfigError
from coastmesh.geometry import Loxodrome

LOXODROME = {
    "kind": "loxodrome",
    "name": "north",
    "id": 2,
    "start": [-15.0, 57.0],
    "bearing_west": 20,
    "end_lat": 70.0,
}
BLEND = {
    "kind": "blend",
    "name": "blend",
    "id": 3,
    "first": {"start": [-15.0, 57.0], "bearing": 340, "end_lat": 70},
    "second": {"start": [5.45, 62.0], "bearing": 0, "end_lat": 70},
}
GREAT_CIRCLE = {
    "kind": "great_circle",
    "name": "west",
    "id": 4,
    "start": [-10.0, 50.0],
    "end": [10.0, 50.0],
    "spacing": "2 km",
}
POLYLINE = {
    "kind": "polyline",
    "name": "south",
    "id": 5,
    "points": [[0, 0], [1000, 0], [1000, 500]],
}


def test_the_kinds_are_registered_by_their_kind():
    assert BOUNDARY_KINDS == {
        "loxodrome": LoxodromeBoundary,
        "blend": BlendBoundary,
        "great_circle": GreatCircleBoundary,
        "polyline": PolylineBoundary,
    }
    for kind, cls in BOUNDARY_KINDS.items():
        assert issubclass(cls, BoundaryConfig) and cls.kind == kind


def test_each_kind_is_read_from_its_table():
    lox, blend, great, poly = read_boundaries(
        [LOXODROME, BLEND, GREAT_CIRCLE, POLYLINE]
    )
    assert lox == LoxodromeBoundary(
        "north", 2, start=(-15.0, 57.0), bearing=340.0, end_lat=70.0
    )
    assert lox.spacing is None and lox.end_lon is None  # the defaults
    assert blend == BlendBoundary(
        "blend",
        3,
        first=LoxodromeConfig((-15.0, 57.0), 340.0, 70.0),
        second=LoxodromeConfig((5.45, 62.0), 0.0, 70.0),
    )
    assert great == GreatCircleBoundary(
        "west", 4, 2000.0, start=(-10.0, 50.0), end=(10.0, 50.0)
    )
    assert poly == PolylineBoundary(
        "south", 5, points=((0.0, 0.0), (1000.0, 0.0), (1000.0, 500.0))
    )
    assert poly.path is None and poly.layer is None


def test_bearings_west_of_north_and_two_ends_give_the_same_line():
    (west,) = read_boundaries([LOXODROME])
    table = {k: v for k, v in LOXODROME.items() if k not in ("bearing_west", "end_lat")}
    (north,) = read_boundaries([table | {"bearing": 340, "end_lat": 70.0}])
    assert north == west  # bearing_west = 20 is bearing = 340
    (by_ends,) = read_boundaries([table | {"end": [-4.0, 48.5]}])
    line = Loxodrome.between((-15.0, 57.0), (-4.0, 48.5))
    assert by_ends.bearing == line.azimuth and by_ends.end_lat == 48.5
    (bearing,) = read_boundaries([table | {"bearing": -20, "end_lat": 70.0}])
    assert bearing.bearing == 340.0  # in [0, 360)


def test_a_relative_path_is_taken_from_the_case_files_folder():
    table = {k: v for k, v in POLYLINE.items() if k != "points"}
    (poly,) = read_boundaries([table | {"path": "../lines/south.gpkg", "layer": "l"}])
    assert poly.path == Path("/lines/south.gpkg") and poly.layer == "l"


LOX = "open_boundaries[0]"


@pytest.mark.parametrize(
    ("table", "message"),
    [
        (
            LOXODROME | {"kind": "spline"},
            f"{LOX}.kind = 'spline': expected one of 'loxodrome', 'blend', "
            "'great_circle', 'polyline'",
        ),
        (LOXODROME | {"id": 0}, f"{LOX}.id = 0: expected an integer >= 1"),
        (LOXODROME | {"id": "2"}, f"{LOX}.id = '2': expected an integer >= 1"),
        (LOXODROME | {"name": ""}, f"{LOX}.name = '': expected a non-empty string"),
        (LOXODROME | {"spacing": 100}, f"{LOX}.spacing = 100: give a unit"),
        (LOXODROME | {"spacing": "-1 km"}, f"{LOX}.spacing = -1000 m: must be > 0"),
        (LOXODROME | {"bearing": 3}, f"{LOX}.bearing: give exactly one of bearing"),
        (
            LOXODROME | {"end": [1, 2]},
            f"{LOX}.end: give either end or bearing_west and end_lat, not both",
        ),
        (
            LOXODROME | {"start": [-15.0, 97.0]},
            f"{LOX}.start = [-15.0, 97.0]: latitude must be in (-90, 90)",
        ),
        (
            LOXODROME | {"end_lon": 3.0},
            f"{LOX}.end_lat: give exactly one of end_lat and end_lon",
        ),
        (LOXODROME | {"colour": "red"}, f"unknown key '{LOX}.colour'"),
        (
            BLEND | {"first": {"start": [-15.0, 57.0], "bearing": 340}},
            f"{LOX}.first.end_lat: give exactly one of end_lat and end_lon",
        ),
        (
            BLEND | {"second": BLEND["second"] | {"tilt": 1}},
            f"unknown key '{LOX}.second.tilt'",
        ),
        (
            {k: v for k, v in BLEND.items() if k != "second"},
            f"{LOX}.second: is missing (a [table])",
        ),
        (
            GREAT_CIRCLE | {"start": [1]},
            f"{LOX}.start = [1]: expected [x, y] (longitude, latitude)",
        ),
        (
            {k: v for k, v in GREAT_CIRCLE.items() if k != "end"},
            f"{LOX}.end: is missing",
        ),
        (
            POLYLINE | {"path": "south.gpkg"},
            f"{LOX}.points: give exactly one of points and path",
        ),
        (
            {k: v for k, v in POLYLINE.items() if k != "points"},
            f"{LOX}.points: give exactly one of points and path",
        ),
        (
            POLYLINE | {"points": [[0, 0]]},
            f"{LOX}.points: expected a list of at least two [x, y] points",
        ),
    ],
)
def test_bad_tables_name_the_file_the_key_and_the_value(table, message):
    with pytest.raises(ConfigError) as info:
        read_boundaries([table])
    text = str(info.value)
    assert text.startswith(f"{SOURCE}: "), text
    assert message in text, text


def test_a_missing_id_or_name_is_named():
    no_id = {k: v for k, v in LOXODROME.items() if k != "id"}
    with pytest.raises(ConfigError, match=r"open_boundaries\[1\]\.id: is missing"):
        read_boundaries([POLYLINE, no_id])
    no_name = {k: v for k, v in POLYLINE.items() if k != "name"}
    with pytest.raises(ConfigError, match=r"open_boundaries\[0\]\.name: is missing"):
        read_boundaries([no_name])


@pytest.mark.parametrize(
    "table", [LOXODROME, BLEND, GREAT_CIRCLE, POLYLINE], ids=lambda t: t["kind"]
)
def test_each_kind_is_written_back_and_reads_back_equal(table):
    (boundary,) = read_boundaries([table])
    data = dump_part(boundary)
    assert next(iter(data)) == "kind" and data["kind"] == table["kind"]
    assert data["id"] == table["id"] and data["name"] == table["name"]
    text = tomli_w.dumps({"open_boundaries": [data]})
    assert read_boundaries(text) == (boundary,)


def test_the_base_class_draws_no_line():
    with pytest.raises(NotImplementedError, match="BoundaryConfig draws no line"):
        BoundaryConfig("b", 1).lonlat(1000.0)
