"""case/schema/read.py and dump.py: a part read from its table, and written back."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
import tomli_w
from schema_parts import Leg, Place, Stop, Trip

from coastmesh.case.config import CleanupConfig, DomainConfig, MeshConfig, RunConfig
from coastmesh.case.schema import (
    Check,
    Reading,
    Table,
    checked,
    dump_part,
    read_keys,
    read_part,
)
from coastmesh.case.schema.dump import toml_value
from coastmesh.errors import ConfigError

SOURCE = "/cases/trip.toml"
READING = Reading(Path("/cases"))

TEXT = """
area = "2 ha"

[[legs]]
name = "out"
length = "1.5 km"
pace = "4 km/h"
track = "../tracks/out.gpx"
tags = ["coast", "hill"]

[[legs]]
name = "back"
length = "0.02 deg"
mode = "run"

[stop.inn]
stay = "30 min"

[stop.pier]
stay = "45 s"

[home]
seed = [-3.1, 58.9]
"""


def read(text: str) -> Trip:
    """Read and check a trip as a case file is: read_part, then checked."""
    trip = read_part(Trip, Table(tomllib.loads(text), "", SOURCE), READING)
    return checked(trip, Check(SOURCE))


def test_a_table_is_read_with_units_paths_parts_and_defaults():
    trip = read(TEXT)
    out, back = trip.legs
    assert out == Leg(
        "out",
        1500.0,
        pace=pytest.approx(4 / 3.6),
        track=Path("/tracks/out.gpx"),  # from the file's folder
        tags=("coast", "hill"),
    )
    assert back.length == pytest.approx(0.02 * 111_194.9, rel=1e-5)
    assert (back.pace, back.track, back.mode, back.tags) == (None, None, "run", None)
    assert trip.stops == (Stop("inn", 1800.0), Stop("pier", 45.0))
    assert trip.home == Place((-3.1, 58.9), 10.0)  # tolerance: its default
    assert trip.area == 2e4


def test_an_absent_sub_table_keeps_its_default():
    trip = read('[[legs]]\nname = "a"\nlength = "1 m"\n')
    assert trip.home == Place() and trip.stops == () and trip.area is None


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ('length = "1.5 km"', "length = 1500", "legs[0].length = 1500: give a unit"),
        (
            'stay = "45 s"',
            "stay = 45",
            "stop.pier.stay = 45: write a number and a unit",
        ),
        ('area = "2 ha"', 'area = "2 acres"', "area = '2 acres': unknown unit"),
        ('mode = "run"', 'mode = "run"\nspeed = 3', "unknown key 'legs[1].speed'"),
        ("[home]", "[home]\nradius = 1", "unknown key 'home.radius'"),
        ('area = "2 ha"', 'area = "2 ha"\nlegz = 1', "unknown key 'legz'"),
        ('[stop.inn]\nstay = "30 min"', "[stop.inn]", "stop.inn.stay: is missing"),
        (
            'length = "0.02 deg"',
            'length = "-1 m"',
            "legs[1].length = -1 m: must be > 0",
        ),
        ('tags = ["coast", "hill"]', "tags = []", "legs[0].tags = []: expected a name"),
        ('name = "back"', 'name = "out"', "legs: a name is used twice"),
    ],
)
def test_errors_name_the_file_and_the_key(old, new, message):
    text = TEXT.replace(old, new, 1)
    assert text != TEXT
    with pytest.raises(ConfigError) as info:
        read(text)
    assert str(info.value).startswith(f"{SOURCE}: ")
    assert message in str(info.value)


def test_a_required_array_that_is_missing_is_an_error():
    with pytest.raises(ConfigError) as info:
        read('area = "1 ha"\n')
    assert str(info.value) == f"{SOURCE}: legs: define at least one (Leg)"


def test_read_keys_takes_only_the_parts_keys_and_can_rename_them():
    t = Table({"name": "a", "distance": "2 m", "extra": 1}, "legs[0]", SOURCE)
    values = read_keys(Leg, t, READING, rename={"length": "distance"})
    assert values == {"name": "a", "length": 2.0}
    with pytest.raises(ConfigError, match=r"unknown key 'legs\[0\]\.extra'"):
        t.done()


def test_dump_writes_units_and_absolute_paths_and_leaves_none_out():
    trip = read(TEXT)
    data = dump_part(trip)
    assert data["area"] == "20000.0 m2"
    assert data["legs"][0]["length"] == "1500.0 m"
    assert data["legs"][0]["pace"].endswith(" m/s")
    assert data["legs"][0]["track"] == str(Path("/tracks/out.gpx").resolve())
    assert data["stop"] == {"inn": {"stay": "1800.0 s"}, "pier": {"stay": "45.0 s"}}
    assert "pace" not in data["legs"][1] and "tags" not in data["legs"][1]
    assert data["home"] == {"seed": [-3.1, 58.9], "tolerance": "10.0 m"}


def test_a_dumped_part_reads_back_equal():
    trip = read(TEXT)
    text = tomli_w.dumps(dump_part(trip))
    assert read(text) == trip
    # and writing it again gives the same text
    assert tomli_w.dumps(dump_part(read(text))) == text


@pytest.mark.parametrize(
    "part",
    [
        DomainConfig(seed=(-3.1, 58.85), seam_tolerance=50.0),
        MeshConfig(),
        CleanupConfig(),
        RunConfig(),
    ],
    ids=lambda p: type(p).__name__,
)
def test_the_case_parts_read_back_equal(part):
    c = Check("case.toml", "part")
    part = checked(part, c)
    data = tomllib.loads(tomli_w.dumps(dump_part(part)))
    again = read_part(type(part), Table(data, "part", "case.toml"), READING)
    assert checked(again, c) == part


def test_toml_value_turns_tuples_paths_and_mappings_into_toml():
    assert toml_value((1, (2, 3))) == [1, [2, 3]]
    assert toml_value({"a": (1,)}) == {"a": [1]}
    assert toml_value(Path("/x/y")) == str(Path("/x/y").resolve())
    assert toml_value("text") == "text"


def test_reading_takes_relative_paths_from_the_files_folder():
    assert READING.path("data/c.gpkg", "p") == Path("/cases/data/c.gpkg")
    assert READING.path("/abs/c.gpkg", "p") == Path("/abs/c.gpkg")
    with pytest.raises(ConfigError, match=r"^p = '': expected a non-empty string"):
        READING.path("", "p")
