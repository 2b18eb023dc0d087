"""A small case schema of its own, to test case/schema apart from the case's."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from coastmesh.case import schema
from coastmesh.case.schema import Check, key


@dataclass(frozen=True)
class Place:
    """A table with defaults only."""

    seed: tuple[float, float] | None = key(None, check=schema.point, doc="a point")
    tolerance: float = key(
        10.0,
        check=schema.length(positive=False),
        unit="length",
        doc="a tolerance",
    )


@dataclass(frozen=True)
class Leg:
    """An array of tables (``[[legs]]``)."""

    name: str = key(check=schema.string, doc="its name")
    length: float = key(check=schema.length(), unit="length", doc="how long")
    pace: float | None = key(None, check=schema.speed, unit="speed", doc="how fast")
    track: Path | None = key(None, check=schema.path, path=True, doc="its track")
    mode: str = key("walk", check=schema.choice(("walk", "run")), doc="how")
    tags: tuple[str, ...] | None = key(None, check=schema.names, doc="its tags")


@dataclass(frozen=True)
class Stop:
    """Tables keyed by name (``[stop.NAME]``); ``name`` is not a key."""

    name: str
    stay: float = key(check=schema.duration, unit="duration", doc="how long")


@dataclass(frozen=True)
class Trip:
    """The file: a required array, keyed tables, a sub-table, a renamed key."""

    legs: tuple[Leg, ...] = key(part=Leg, many=True, doc="the legs")
    stops: tuple[Stop, ...] = key(
        (), name="stop", part=Stop, many=True, keyed=True, doc="the stops"
    )
    home: Place = key(Place(), part=Place, doc="where it starts")
    area: float | None = key(None, check=schema.area, unit="area", doc="an area")

    def _validate(self, c: Check) -> Trip:
        names = [leg.name for leg in self.legs]
        if len(set(names)) != len(names):
            raise c.error("legs", f"a name is used twice: {names}")
        return self
