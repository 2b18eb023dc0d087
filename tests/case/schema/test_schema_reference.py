"""case/schema/reference.py: the key tables of the docs, from the keys."""

from __future__ import annotations

from dataclasses import dataclass

import pytest
from schema_parts import Leg, Place, Trip

from coastmesh.case import schema
from coastmesh.case.schema import key
from coastmesh.case.schema.reference import (
    key_table,
    markdown,
    renamed_table,
    section,
    update_reference,
)


@dataclass(frozen=True)
class Shape:
    """Defaults of every kind the table writes."""

    box: tuple[float, ...] = key((0.0, 1.5, 2.0, 3.0), check=schema.box, doc="a box")
    kinds: tuple[str, ...] = key(("a", "b"), check=schema.names, doc="kinds")
    on: bool = key(True, check=schema.boolean, doc="on or off")
    step: float = key(2.5, check=schema.positive, doc="a | b")
    floor: float = key(
        1.0, check=schema.length(), unit="length", default_doc="`h_min`", doc="x"
    )


@dataclass(frozen=True)
class Wider(Shape):
    """A class that adds one key to its base's."""

    width: int = key(3, check=schema.integer(1), doc="how wide")


def test_the_table_gives_each_key_its_default_and_doc():
    assert key_table(Leg).splitlines() == [
        "| key | default | meaning |",
        "|---|---|---|",
        "| `name` | required | its name |",
        "| `length` | required | how long |",
        "| `pace` | none | how fast |",
        "| `track` | none | its track |",
        '| `mode` | `"walk"` | how |',
        "| `tags` | none | its tags |",
    ]
    rows = key_table(Shape).splitlines()[2:]
    assert rows == [
        "| `box` | `[0, 1.5, 2, 3]` | a box |",
        '| `kinds` | `["a", "b"]` | kinds |',
        "| `on` | `true` | on or off |",
        "| `step` | `2.5` | a \\| b |",  # a | in a doc is not a column
        "| `floor` | `h_min` | x |",
    ]
    assert (
        key_table(Place).splitlines()[3] == '| `tolerance` | `"10 m"` | a tolerance |'
    )
    assert key_table(Trip).splitlines()[3:5] == [
        "| `stop` | none | the stops |",
        "| `home` | its defaults | where it starts |",
    ]


def test_own_gives_only_the_keys_a_class_adds():
    assert key_table(Wider, own=True).splitlines()[2:] == [
        "| `width` | `3` | how wide |"
    ]
    assert len(key_table(Wider).splitlines()) == 2 + 6


def test_update_reference_writes_every_marked_table_anew():
    text = (
        "intro\n<!-- keys: Leg -->\nstale\n<!-- /keys -->\nmiddle\n"
        "<!-- keys: Wider own -->\n<!-- /keys -->\n<!-- keys: BLOCK -->\nx\n"
        "<!-- /keys -->\nend\n"
    )
    out = update_reference(text, {"Leg": Leg, "Wider": Wider}, {"BLOCK": "block\n"})
    assert out == (
        "intro\n<!-- keys: Leg -->\n"
        + key_table(Leg)
        + "<!-- /keys -->\nmiddle\n<!-- keys: Wider own -->\n"
        + key_table(Wider, own=True)
        + "<!-- /keys -->\n<!-- keys: BLOCK -->\nblock\n<!-- /keys -->\nend\n"
    )
    assert (
        update_reference(out, {"Leg": Leg, "Wider": Wider}, {"BLOCK": "block\n"}) == out
    )
    with pytest.raises(KeyError, match="'keys: Nope' names no config class"):
        update_reference("<!-- keys: Nope -->\n<!-- /keys -->", {"Leg": Leg})


def test_renamed_keys_are_listed_with_their_python_field():
    assert renamed_table([Trip, Leg]).splitlines() == [
        "| case file | Python | in |",
        "|---|---|---|",
        "| `[stop.NAME]` | `stops` | Trip |",  # keyed tables
    ]


def test_markdown_and_section():
    assert markdown("the ``h_min`` of :func:`~coastmesh.case.floor`") == (
        "the `h_min` of `floor`"
    )
    assert markdown(":class:`Trip` and :mod:`coastmesh.case`") == (
        "`Trip` and `coastmesh.case`"
    )
    text = section("The ``legs``.", "Each leg.\n", Leg)
    assert text.startswith("#### The `legs`\n\nEach leg.\n\n| key | default |")
