"""case/schema/keys.py: keys declared on fields, parts checked by them."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from schema_parts import Leg, Place, Stop, Trip

from coastmesh.case import schema
from coastmesh.case.schema import REQUIRED, Check, check_part, checked, key, keys_of
from coastmesh.errors import ConfigError

C = Check("trip.toml")


def test_keys_of_names_each_key_by_its_field_unless_it_gives_another():
    names = {f.name: meta.name for f, meta in keys_of(Trip)}
    assert names == {"legs": "legs", "stops": "stop", "home": "home", "area": "area"}
    leg = dict(keys_of(Leg)[1:2])
    (meta,) = leg.values()
    assert meta.unit == "length" and meta.doc == "how long"
    assert [f.name for f, _ in keys_of(Stop)] == ["stay"]  # name: no key


def test_defaults_are_the_declared_ones():
    place = Place()
    assert place.seed is None and place.tolerance == 10.0
    leg = Leg("a", 5.0)
    assert (leg.pace, leg.track, leg.mode, leg.tags) == (None, None, "walk", None)
    trip = Trip((leg,))
    assert trip.home == Place() and trip.stops == () and trip.area is None
    with pytest.raises(TypeError):
        Leg("a")  # length is REQUIRED: the dataclass needs it
    assert dataclasses.fields(Leg)[0].default is REQUIRED


def test_key_refuses_an_unknown_unit():
    with pytest.raises(ValueError, match=r"unit 'lightyear': expected one of"):
        key(1.0, doc="x", unit="lightyear")


def test_checked_converts_every_key_and_keeps_other_fields():
    trip = checked(
        Trip(
            [Leg("a", "2 km", pace="2 kn", track="~/a.gpx", tags="x")],
            stops=[Stop("inn", "1 h")],
            home=Place(seed=[1, 2], tolerance="0.5 km"),
            area="1 ha",
        ),
        C,
    )
    (leg,) = trip.legs
    assert leg.length == 2000.0 and leg.pace == pytest.approx(1852 / 1800)
    assert leg.track == Path.home() / "a.gpx" and leg.tags == ("x",)
    assert trip.stops == (Stop("inn", 3600.0),)  # the name is kept as it is
    assert trip.home == Place((1.0, 2.0), 500.0) and trip.area == 1e4
    assert isinstance(trip.legs, tuple)


@pytest.mark.parametrize(
    ("trip", "message"),
    [
        (
            Trip((Leg("a", 1.0), Leg("b", -5))),
            "trip.toml: legs[1].length = -5 m: must be > 0",
        ),
        (
            Trip((Leg("a", 1.0, mode="fly"),)),
            "trip.toml: legs[0].mode = 'fly': expected one of 'walk', 'run'",
        ),
        (
            Trip((Leg("a", 1.0),), home=Place(tolerance=-1)),
            "trip.toml: home.tolerance = -1 m: must be >= 0",
        ),
        (
            Trip((Leg("a", 1.0),), stops=(Stop("inn", 0),)),
            "trip.toml: stop.inn.stay = 0 s: must be > 0",
        ),
        (Trip(()), "trip.toml: legs: define at least one (Leg)"),
        (Trip("ab"), "trip.toml: legs = 'ab': expected a list"),
        (Trip(({"name": "a"},)), "trip.toml: legs[0] = {'name': 'a'}: expected a Leg"),
        (
            Trip((Leg("a", 1.0), Leg("a", 2.0))),
            "trip.toml: legs: a name is used twice: ['a', 'a']",
        ),
    ],
)
def test_errors_name_the_file_the_key_path_and_the_value(trip, message):
    with pytest.raises(ConfigError) as info:
        checked(trip, C)
    assert str(info.value) == message


def test_a_long_value_is_named_by_its_type():
    with pytest.raises(ConfigError) as info:
        check_part(list(range(40)), Place, C, "home")
    assert str(info.value) == "trip.toml: home = list: expected a Place"


def test_check_names_nested_key_paths():
    c = Check("case.toml", "mesh_size").at("courant")
    assert c.key("dt") == "mesh_size.courant.dt"
    assert str(c.error("dt", "= -1 s: must be > 0")) == (
        "case.toml: mesh_size.courant.dt = -1 s: must be > 0"
    )
    assert str(c.error("dt", "needs a depth")) == (
        "case.toml: mesh_size.courant.dt: needs a depth"
    )
    assert c.optional(schema.positive, None, "dt") is None
    with pytest.raises(ConfigError, match=r"^case.toml: mesh_size.courant.dt = 0:"):
        c(schema.positive, 0, "dt")


def test_sequence_takes_lists_and_refuses_strings_and_tables():
    assert schema.sequence([1, 2], C, "legs") == (1, 2)
    assert schema.sequence((x for x in "ab"), C, "legs") == ("a", "b")
    for bad in ("ab", {"a": 1}, 3):
        with pytest.raises(
            ConfigError, match=r"^trip.toml: legs = .*: expected a list"
        ):
            schema.sequence(bad, C, "legs")
