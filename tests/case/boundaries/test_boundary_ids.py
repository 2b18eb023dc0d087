"""Boundary ids in a case: each open boundary's ``id`` is its own."""

from __future__ import annotations

from pathlib import Path

import pytest

from coastmesh.case import parse_case
from coastmesh.errors import ConfigError

CASE = """
[case]
name = "t"

[shorelines]
path = "data/coast.gpkg"

[shoreline_sets.coast]
id = 1

[[open_boundaries]]
name = "north"
id = 2
kind = "great_circle"
start = [-4.0, 59.0]
end = [-2.0, 59.0]

[[open_boundaries]]
name = "east"
id = 3
kind = "polyline"
points = [[-2.0, 59.0], [-2.0, 58.0]]

[mesh_size]
h_max = "5 km"
"""


def parse(text: str = CASE):
    return parse_case(text, Path("/cases/t.toml"))


def test_each_boundary_keeps_the_id_it_is_given():
    case = parse()
    assert [(b.name, b.physical_id) for b in case.boundaries] == [
        ("north", 2),
        ("east", 3),
    ]
    assert [(s.name, s.physical_id) for s in case.sets] == [("coast", 1)]


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "id = 3",
            "id = 2",
            "open_boundaries[1]: id 2 of 'east' is also the id of 'north'; "
            "every boundary needs its own id",
        ),
        (
            "id = 2",
            "id = 1",
            "open_boundaries[0]: id 1 of 'north' is also the id of 'coast'; "
            "every boundary needs its own id",
        ),
        (
            'name = "east"',
            'name = "north"',
            "open_boundaries[1]: the name 'north' is used twice",
        ),
        (
            'name = "north"',
            'name = "coast"',
            "open_boundaries[0]: the name 'coast' is used twice",
        ),
        ("id = 3", "id = -3", "open_boundaries[1].id = -3: expected an integer >= 1"),
        ("id = 3", "id = 3.0", "open_boundaries[1].id = 3.0: expected an integer >= 1"),
    ],
)
def test_an_id_or_name_used_twice_is_an_error_naming_both(old, new, message):
    text = CASE.replace(old, new, 1)
    assert text != CASE
    with pytest.raises(ConfigError) as info:
        parse(text)
    assert str(info.value).startswith("/cases/t.toml")
    assert message in str(info.value)
