"""case/schema/table.py: one TOML table read key by key, leftovers an error."""

from __future__ import annotations

import pytest

from coastmesh.case import schema
from coastmesh.case.schema import MISSING, Table, located
from coastmesh.errors import ConfigError


def test_keys_are_converted_and_missing_ones_take_the_default():
    t = Table({"h_max": "5 km", "rate": 0.2}, "mesh_size", "case.toml")
    assert t.get("h_max", schema.length_with_unit) == 5000.0
    assert t.get("rate", schema.positive) == 0.2
    assert t.get("cell", schema.length_with_unit, None) is None
    assert t.get("modes", schema.integer(1), 3) == 3
    t.done()  # every key taken


def test_a_bad_value_names_the_file_the_key_path_and_the_value():
    t = Table({"rate": -1}, "mesh_size", "case.toml")
    with pytest.raises(ConfigError) as info:
        t.get("rate", schema.positive)
    assert str(info.value) == "case.toml: mesh_size.rate = -1: must be > 0"


def test_a_required_key_that_is_missing_is_named():
    t = Table({}, "open_boundaries[2]", "case.toml")
    with pytest.raises(ConfigError) as info:
        t.get("id", schema.integer(1), MISSING)
    assert str(info.value) == "case.toml: open_boundaries[2].id: is missing"


def test_an_unknown_key_is_an_error_listing_the_keys_allowed():
    t = Table({"rate": 0.1, "rte": 1}, "mesh_size", "case.toml")
    t.get("rate", schema.positive)
    t.get("h_max", schema.length_with_unit, None)
    with pytest.raises(ConfigError) as info:
        t.done()
    assert str(info.value) == (
        "case.toml: unknown key 'mesh_size.rte'; the keys allowed here are: h_max, rate"
    )
    with pytest.raises(ConfigError, match="allowed here are: none"):
        Table({"x": 1}, "", "case.toml").done()


def test_sub_tables_and_arrays_of_tables_carry_their_key_path():
    data = {"domain": {"seed": [0, 0]}, "lines": [{"id": 1}, {"id": 0}]}
    t = Table(data, "", "case.toml")
    assert t.table("domain").where == "domain"
    assert t.table("output").data == {}  # absent: an empty table
    lines = t.tables("lines")
    assert [s.where for s in lines] == ["lines[0]", "lines[1]"]
    with pytest.raises(ConfigError, match=r"^case.toml: lines\[1\].id = 0: "):
        lines[1].get("id", schema.integer(1))
    assert t.tables("farms") == []
    t.done()
    with pytest.raises(
        ConfigError, match=r"^case.toml: mesh: is missing \(a \[table\]\)"
    ):
        Table({}, "", "case.toml").table("mesh", required=True)


def test_tables_that_are_not_tables_are_refused():
    with pytest.raises(ConfigError) as info:
        Table([1, 2], "mesh_size", "case.toml")
    assert str(info.value) == "case.toml: mesh_size must be a table, got list [1, 2]"
    with pytest.raises(ConfigError, match="the file must be a table"):
        Table("text", "", "case.toml")
    t = Table({"lines": {"id": 1}}, "", "case.toml")
    with pytest.raises(ConfigError, match=r"lines: must be an array of tables"):
        t.tables("lines")


def test_pick_takes_the_keys_present_as_they_are():
    t = Table({"end_lat": 70, "other": 1}, "b", "case.toml")
    assert t.pick("end_lat", "end_lon") == {"end_lat": 70}
    with pytest.raises(ConfigError, match=r"unknown key 'b\.other'"):
        t.done()


def test_located_puts_the_file_first_once():
    with pytest.raises(ConfigError) as info:
        located(schema.positive, 0, "rate", "case.toml")
    assert str(info.value) == "case.toml: rate = 0: must be > 0"

    def already(value, key):
        raise ConfigError(f"case.toml: {key} is wrong")

    with pytest.raises(ConfigError) as info:
        located(already, 0, "rate", "case.toml")
    assert str(info.value) == "case.toml: rate is wrong"
