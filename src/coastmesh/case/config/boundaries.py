"""``[[open_boundaries]]``: loxodromes, blends, great circles, polylines."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from coastmesh.case import schema
from coastmesh.case.config._check import Check

__all__ = ["BOUNDARY_KINDS", "BoundaryConfig", "LoxodromeConfig"]

BOUNDARY_KINDS = ("loxodrome", "blend", "great_circle", "polyline")


@dataclass(frozen=True, slots=True)
class LoxodromeConfig:
    """A rhumb line: start, azimuth (degrees clockwise from north) and one end.

    Attributes
    ----------
    start : (lon, lat)
    azimuth : float
        ``bearing`` in the file; the paper's "20 deg W" is 340.
    end_lat, end_lon : float, optional
        Exactly one: where the line ends. :meth:`between` builds one from two
        points.
    """

    start: tuple[float, float]
    azimuth: float
    end_lat: float | None = None
    end_lon: float | None = None

    @classmethod
    def between(
        cls, start: tuple[float, float], end: tuple[float, float]
    ) -> LoxodromeConfig:
        """Return the loxodrome from ``start`` to ``end`` (lon, lat degrees).

        Examples
        --------
        >>> line = LoxodromeConfig.between((-3.0, 58.0), (-3.0, 59.0))
        >>> line.azimuth, line.end_lat
        (0.0, 59.0)
        """
        from coastmesh.geometry import Loxodrome

        line = Loxodrome.between(start, end)
        return cls(tuple(start), line.azimuth, line.end_lat, line.end_lon)

    def _checked(self, c: Check) -> LoxodromeConfig:
        start = c(schema.point, self.start, "start")
        if not -90 < start[1] < 90:
            raise c.error("start", f"= {list(start)}: latitude must be in (-90, 90)")
        if (self.end_lat is None) == (self.end_lon is None):
            raise c.error("end_lat", "give exactly one of end_lat and end_lon")
        return LoxodromeConfig(
            start=start,
            azimuth=c(schema.number, self.azimuth, "bearing") % 360.0,
            end_lat=c.optional(schema.number, self.end_lat, "end_lat"),
            end_lon=c.optional(schema.number, self.end_lon, "end_lon"),
        )


@dataclass(frozen=True, slots=True)
class BoundaryConfig:
    """``[[open_boundaries]]``: one open boundary and its id.

    Attributes
    ----------
    name : str
    physical_id : int
        ``id`` in the file, >= 1, unique among sets and boundaries.
    kind : {"loxodrome", "blend", "great_circle", "polyline"}, optional
        In Python it may be left out: it follows from the fields given
        (``loxodrome``; ``first`` and ``second``; ``start`` and ``end``;
        ``points`` or ``path``).
    spacing : float or str, optional
        Sampling of the line (metres); default a quarter of ``h_max``, <= 1 km.
    loxodrome : LoxodromeConfig
        For ``kind = "loxodrome"`` (its keys sit in the boundary's own table).
    first, second : LoxodromeConfig
        For ``kind = "blend"``: the paper's blended loxodromes.
    start, end : (lon, lat)
        For ``kind = "great_circle"``.
    points : sequence of (x, y), or path (with layer)
        For ``kind = "polyline"``: exactly one, in the case CRS.
    """

    name: str
    physical_id: int
    kind: str | None = None
    spacing: float | None = None
    loxodrome: LoxodromeConfig | None = None
    first: LoxodromeConfig | None = None
    second: LoxodromeConfig | None = None
    start: tuple[float, float] | None = None
    end: tuple[float, float] | None = None
    points: tuple[tuple[float, float], ...] | None = None
    path: Path | None = None
    layer: str | None = None

    def _checked(self, c: Check) -> BoundaryConfig:
        kind = c(schema.choice(BOUNDARY_KINDS), self.kind or self._kind(c), "kind")
        needs = {
            "loxodrome": ("loxodrome",),
            "blend": ("first", "second"),
            "great_circle": ("start", "end"),
            "polyline": (),
        }[kind]
        for name in needs:
            if getattr(self, name) is None:
                raise c.error(name, f"is missing (a {kind} boundary needs it)")
        if kind == "polyline" and (self.points is None) == (self.path is None):
            raise c.error("points", "give exactly one of points and path")
        lox = {
            name: getattr(self, name)._checked(c if name == "loxodrome" else c.at(name))
            for name in ("loxodrome", "first", "second")
            if getattr(self, name) is not None
        }
        return BoundaryConfig(
            name=c(schema.string, self.name, "name"),
            physical_id=c(schema.integer(1), self.physical_id, "id"),
            kind=kind,
            spacing=c.optional(schema.length(), self.spacing, "spacing"),
            start=c.optional(schema.point, self.start, "start"),
            end=c.optional(schema.point, self.end, "end"),
            points=c.optional(schema.points, self.points, "points"),
            path=c.optional(schema.path, self.path, "path"),
            layer=c.optional(schema.string, self.layer, "layer"),
            **lox,
        )

    def _kind(self, c: Check) -> str:
        """Return the kind the given fields make, for a boundary built without one."""
        given = {
            "loxodrome": self.loxodrome is not None,
            "blend": self.first is not None or self.second is not None,
            "great_circle": self.start is not None or self.end is not None,
            "polyline": self.points is not None or self.path is not None,
        }
        kinds = [kind for kind, present in given.items() if present]
        if len(kinds) != 1:
            raise c.error(
                "kind",
                "is missing; give it, or the fields of one kind: loxodrome; first "
                "and second (blend); start and end (great_circle); points or path "
                f"(polyline){f' (given: {kinds})' if kinds else ''}",
            )
        return kinds[0]
