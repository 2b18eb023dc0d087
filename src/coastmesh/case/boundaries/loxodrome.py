"""``kind = "loxodrome"``: a rhumb line, and the loxodrome keys of a blend.

A loxodrome takes ``start = [lon, lat]`` and either ``bearing`` (degrees
clockwise from true north) or ``bearing_west`` (degrees west of north, as the
paper writes them), and ends at ``end_lat`` or ``end_lon``; or it is given by
its two ends (``start`` and ``end``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar, Protocol

import numpy as np
from numpy.typing import NDArray

from coastmesh.case import schema
from coastmesh.case.boundaries.base import BoundaryConfig
from coastmesh.case.schema import Check, Table, key
from coastmesh.errors import ConfigError
from coastmesh.geometry import Loxodrome

__all__ = ["LoxodromeBoundary", "LoxodromeConfig"]

_START_DOC = "`[lon, lat]` where the line starts"
_END_LAT_DOC = "the latitude where it ends: exactly one of `end_lat` and `end_lon`"
_END_LON_DOC = "the longitude where it ends"
_BEARING_DOC = (
    "degrees clockwise from true north; or `bearing_west`: degrees west of north, "
    'as the paper writes them ("20 deg W" is `bearing_west = 20`, the same as '
    "`bearing = 340`); or `end = [lon, lat]` instead of a bearing and an end"
)


def _read_loxodrome(t: Table) -> dict[str, object]:  # not yet checked (_validate)
    """Read the loxodrome keys of a table: a bearing and an end, or two ends."""
    if t.has("end"):
        others = [
            k for k in ("bearing", "bearing_west", "end_lat", "end_lon") if t.has(k)
        ]
        if others:
            raise t.error("end", f"give either end or {' and '.join(others)}, not both")
        start, end = t.get("start", schema.point), t.get("end", schema.point)
        try:
            line = Loxodrome.between(start, end)
        except ConfigError as exc:
            raise t.error("end", str(exc)) from None
        return {
            "start": start,
            "bearing": line.azimuth,
            "end_lat": line.end_lat,
            "end_lon": line.end_lon,
        }
    if t.has("bearing") == t.has("bearing_west"):
        raise t.error(
            "bearing",
            "give exactly one of bearing (degrees clockwise from north) and "
            "bearing_west (degrees west of north, as the paper writes them), or "
            "the end point as end = [lon, lat]",
        )
    if t.has("bearing"):
        bearing = t.get("bearing", schema.number)
    else:
        bearing = -t.get("bearing_west", schema.number)
    return {"start": t.get("start", _as_is), "bearing": bearing} | t.pick(
        "end_lat", "end_lon"
    )


def _as_is(value: object, key: str) -> object:
    return value


class _Line(Protocol):
    """The loxodrome keys, of a :class:`LoxodromeConfig` or a boundary."""

    @property
    def start(self) -> tuple[float, float]: ...
    @property
    def bearing(self) -> float: ...
    @property
    def end_lat(self) -> float | None: ...
    @property
    def end_lon(self) -> float | None: ...


def _check_loxodrome(line: _Line, c: Check) -> float:
    """Check the loxodrome keys; return the bearing in [0, 360)."""
    if not -90 < line.start[1] < 90:
        start = list(line.start)
        raise c.error("start", f"= {start}: latitude must be in (-90, 90)")
    if (line.end_lat is None) == (line.end_lon is None):
        raise c.error("end_lat", "give exactly one of end_lat and end_lon")
    return line.bearing % 360.0


def _loxodrome(line: _Line) -> Loxodrome:
    return Loxodrome(
        line.start, line.bearing, end_lat=line.end_lat, end_lon=line.end_lon
    )


@dataclass(frozen=True)
class LoxodromeConfig:
    """The loxodrome keys, as a table of their own: ``first`` and ``second`` of a blend.

    Examples
    --------
    >>> line = LoxodromeConfig.between((-3.0, 58.0), (-3.0, 59.0))
    >>> line.bearing, line.end_lat
    (0.0, 59.0)
    """

    start: tuple[float, float] = key(check=schema.point, doc=_START_DOC)
    bearing: float = key(check=schema.number, doc=_BEARING_DOC)
    end_lat: float | None = key(None, check=schema.number, doc=_END_LAT_DOC)
    end_lon: float | None = key(None, check=schema.number, doc=_END_LON_DOC)

    @classmethod
    def between(
        cls, start: tuple[float, float], end: tuple[float, float]
    ) -> LoxodromeConfig:
        """Return the loxodrome from ``start`` to ``end`` (lon, lat degrees)."""
        line = Loxodrome.between(start, end)
        return cls((start[0], start[1]), line.azimuth, line.end_lat, line.end_lon)

    @classmethod
    def _read(
        cls, t: Table, reading: schema.Reading, **given: object
    ) -> LoxodromeConfig:
        values = _read_loxodrome(t)
        t.done()
        return schema.unchecked_part(cls, values)

    def _validate(self, c: Check) -> LoxodromeConfig:
        return replace(self, bearing=_check_loxodrome(self, c))

    @property
    def loxodrome(self) -> Loxodrome:
        """The line on WGS84."""
        return _loxodrome(self)


@dataclass(frozen=True)
class LoxodromeBoundary(BoundaryConfig):
    """``kind = "loxodrome"``: a rhumb line on WGS84, its keys in its own table."""

    kind: ClassVar[str] = "loxodrome"

    start: tuple[float, float] = key(check=schema.point, doc=_START_DOC, kw_only=True)
    bearing: float = key(check=schema.number, doc=_BEARING_DOC, kw_only=True)
    end_lat: float | None = key(
        None, check=schema.number, doc=_END_LAT_DOC, kw_only=True
    )
    end_lon: float | None = key(
        None, check=schema.number, doc=_END_LON_DOC, kw_only=True
    )

    @classmethod
    def _read(
        cls, t: Table, reading: schema.Reading, **given: object
    ) -> LoxodromeBoundary:
        base = schema.read_keys(BoundaryConfig, t, reading)
        values = _read_loxodrome(t)
        t.done()
        return schema.unchecked_part(cls, values, **base)

    def _validate(self, c: Check) -> LoxodromeBoundary:
        return replace(self, bearing=_check_loxodrome(self, c))

    def lonlat(self, spacing: float) -> NDArray[np.float64]:
        """Sample the rhumb line every ``spacing`` metres at most."""
        return _loxodrome(self).sample(spacing)
