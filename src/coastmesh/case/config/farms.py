"""``[[farms]]``, ``[[turbines]]``, ``[[wakes]]``, ``[[lines]]``, ``[[structures]]``.

The parts of a tidal site: farm areas (a region of elements with an id of
their own), turbines (a node each, or a footprint of elements), their wakes
(a refinement along the tidal axis), lines the mesh follows (embedded edges
with an id) and structures (land in the sea, cut out with a boundary id of
their own). Places are lon/lat, as the seed and the open
boundaries, or read from a vector file (any CRS GDAL reads) or, for turbines,
a CSV.

Lengths at turbines may be given in rotor diameters: ``"D/4"``, ``"0.25 D"``,
``"20 D"`` (:class:`RotorLength`).
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass
from pathlib import Path

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.errors import ConfigError

__all__ = [
    "FOOTPRINTS",
    "WAKE_SIDES",
    "FarmConfig",
    "LineConfig",
    "RotorLength",
    "StructureConfig",
    "TurbinesConfig",
    "WakeConfig",
]

#: ``[[turbines]] footprint``: a node at each turbine, or a resolved footprint.
FOOTPRINTS = ("node", "disc", "square")
#: ``[[wakes]] sides``: both ways along the axis, or the flood or ebb side only.
WAKE_SIDES = ("both", "flood", "ebb")

_PER_D = re.compile(
    r"^\s*(?:(?P<a>[0-9.eE+-]+)\s*\*?\s*D|D\s*/\s*(?P<b>[0-9.eE+-]+)|D)\s*$"
)


@dataclass(frozen=True)
class RotorLength:
    """A length in metres, or a multiple of a turbine's rotor diameter ``D``.

    Examples
    --------
    >>> RotorLength.parse("D/4", "h").metres(18.0), str(RotorLength.parse("20 D", "x"))
    (4.5, '20 D')
    >>> RotorLength.parse("2 km", "length").metres(18.0)
    2000.0
    """

    value: float
    per_d: bool = False

    @classmethod
    def parse(cls, value: object, key: str) -> RotorLength:
        """Read ``"D/4"``, ``"0.25 D"``, ``"20 D"``, ``"D"``, or a length."""
        if isinstance(value, RotorLength):
            return value
        if isinstance(value, str):
            m = _PER_D.match(value)
            if m is not None:
                try:
                    if m["a"] is not None:
                        share = float(m["a"])
                    elif m["b"] is not None:
                        share = 1.0 / float(m["b"])
                    else:
                        share = 1.0
                except (ValueError, ZeroDivisionError):
                    share = math.nan
                if not (math.isfinite(share) and share > 0):
                    raise ConfigError(
                        f"{key} = {value!r}: expected a positive multiple of the "
                        "rotor diameter, e.g. 'D/4', '0.25 D' or '20 D'"
                    )
                return cls(share, True)
        return cls(schema.length()(value, key))

    def metres(self, diameter: float) -> float:
        """Return the length in metres for a rotor of ``diameter`` metres."""
        return self.value * diameter if self.per_d else self.value

    def __str__(self) -> str:
        return f"{self.value:g} D" if self.per_d else f"{self.value:g} m"


def _rotor_length(value: object, key: str) -> RotorLength:
    return RotorLength.parse(value, key)


def _bearing(value: object, key: str) -> float:
    """Convert a bearing in degrees clockwise from north, to [0, 360)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ConfigError(f"{key} = {value!r}: expected a bearing in degrees")
    if not math.isfinite(value):
        raise ConfigError(f"{key} = {value!r}: expected a finite bearing in degrees")
    return float(value) % 360.0


def _ids(value: object, key: str) -> tuple[int, ...]:
    """Convert a list of physical ids (integers >= 1)."""
    if isinstance(value, str | bytes) or not hasattr(value, "__iter__"):
        raise ConfigError(f"{key} = {value!r}: expected a list of integer ids")
    return tuple(schema.integer(1)(x, f"{key}[{i}]") for i, x in enumerate(value))


def _one_place(part: object, c: Check, keys: tuple[str, ...]) -> None:
    """Raise unless exactly one of ``keys`` is given."""
    given = [k for k in keys if getattr(part, k) is not None]
    if len(given) != 1:
        raise c.error(keys[0], f"give exactly one of {', '.join(keys)}")


def _dump_length(value: object) -> str | None:  # a RotorLength or None
    return None if value is None else str(value)


@dataclass(frozen=True)
class FarmConfig:
    """``[[farms]]``: a farm area, meshed as a region of its own.

    Its outline is made of mesh edges, its elements carry ``id`` (a physical
    surface: Thetis ``tidal_turbine_farms[id]``), and ``h`` is the size inside.
    Exactly one of ``polygon`` (lon/lat) and ``path`` (a vector file of
    polygons in its own CRS, unioned; ``layer``).
    """

    name: str = key(check=schema.string, doc="names the farm in reports and lines")
    id: int = key(
        check=schema.integer(1),
        doc="the physical surface id of its elements (not the domain's surface id)",
    )
    polygon: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[lon, lat]` points"
    )
    path: Path | None = schema.file_key("a vector file of polygons")
    layer: str | None = schema.layer_key()
    h: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="the size field's",
        doc="the element size inside the farm",
    )

    def _validate(self, c: Check) -> FarmConfig:
        _one_place(self, c, ("polygon", "path"))
        if self.polygon is not None and len(self.polygon) < 3:
            raise c.error("polygon", "needs at least three points")
        return self


@dataclass(frozen=True)
class TurbinesConfig:
    """``[[turbines]]``: a group of turbines of one rotor diameter.

    Exactly one of ``positions`` (lon/lat) and ``path``: a CSV with columns
    ``name``, ``x``, ``y`` and optionally ``diameter`` (in ``crs``, lon/lat by
    default), or a vector file of points (a ``name`` and ``diameter`` field if
    it has them). Each turbine is a mesh node at its position
    (``footprint = "node"``), or a disc or square of size ``D`` resolved by mesh
    edges, a physical surface numbered from ``id``.
    """

    name: str = key(check=schema.string, doc="names the group in reports and wakes")
    diameter: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="the file's `diameter` column",
        doc="the rotor diameter `D`",
    )
    positions: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[lon, lat]` points"
    )
    path: Path | None = schema.file_key(
        "a CSV (`name, x, y[, diameter]`) or a vector file of points"
    )
    layer: str | None = schema.layer_key()
    crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="`EPSG:4326` (a vector file: its own)",
        doc="the CRS of a CSV's `x` and `y`",
    )
    farm: str | None = key(
        None,
        check=schema.string,
        default_doc="none: standing alone",
        doc="the farm the turbines stand in (each must be inside it)",
    )
    footprint: str = key(
        "node",
        check=schema.choice(FOOTPRINTS),
        doc='`"node"`: a mesh node at each turbine; `"disc"` or `"square"`: a '
        "footprint of size `D`, a region of its own",
    )
    bearing: float = key(
        0.0,
        check=_bearing,
        doc="a square footprint's side across the flow, degrees clockwise from north",
    )
    id: int | None = key(
        None,
        check=schema.integer(1),
        default_doc="needed for footprints",
        doc="the first footprint's physical surface id; the others follow in order",
    )
    ids: tuple[int, ...] | None = key(
        None,
        check=_ids,
        default_doc="numbered from `id`",
        doc="each footprint's id, in the turbines' order",
    )
    h: RotorLength = key(
        RotorLength(0.25, True),
        check=_rotor_length,
        dump=_dump_length,
        default_doc='`"D/4"`',
        doc='the element size at the turbine: a length or a share of `D` (`"D/4"`)',
    )
    spacing: RotorLength = key(
        RotorLength(1.0, True),
        check=_rotor_length,
        dump=_dump_length,
        default_doc='`"D"`',
        doc="turbines closer than this to each other are an error",
    )
    clearance: RotorLength = key(
        RotorLength(1.0, True),
        check=_rotor_length,
        dump=_dump_length,
        default_doc='`"D"`',
        doc="a turbine in water shallower than this (at its node) is an error",
    )

    def _validate(self, c: Check) -> TurbinesConfig:
        _one_place(self, c, ("positions", "path"))
        if self.positions is not None and self.diameter is None:
            raise c.error("diameter", "give the rotor diameter of inline positions")
        if self.footprint != "node" and self.id is None and self.ids is None:
            raise c.error(
                "id",
                f'footprint = "{self.footprint}" needs the footprints\' ids: give '
                "id (the first; the others follow) or ids",
            )
        if self.ids is not None and self.positions is not None:
            if len(self.ids) != len(self.positions):
                raise c.error(
                    "ids",
                    f"has {len(self.ids)} ids for {len(self.positions)} positions",
                )
        return self


@dataclass(frozen=True)
class WakeConfig:
    """``[[wakes]]``: a refinement along the flow through a farm or turbines.

    A band as wide as the source across ``bearing`` (the principal tidal axis,
    degrees clockwise from north, the flood's direction), ``length`` long, at
    size ``h``, both ways unless ``sides`` says the flood or ebb side only. It
    grades into the field at the field's ``rate``.
    """

    of: str = key(check=schema.string, doc="the farm or turbine group it trails")
    bearing: float = key(
        check=_bearing, doc="the tidal axis: the flood's direction, degrees from north"
    )
    length: RotorLength = key(
        check=_rotor_length,
        dump=_dump_length,
        doc='how far it reaches past the source: `"20 D"` or `"2 km"`',
    )
    h: RotorLength | None = key(
        None,
        check=_rotor_length,
        dump=_dump_length,
        default_doc='a farm\'s `h`; `"D/2"` for turbines',
        doc="the element size in the wake",
    )
    sides: str = key(
        "both",
        check=schema.choice(WAKE_SIDES),
        doc='`"both"`, or only the `"flood"` (along `bearing`) or `"ebb"` side',
    )


@dataclass(frozen=True)
class StructureConfig:
    """``[[structures]]``: land in the sea (a pier, an artificial island, a wall).

    Cut out of the domain as a hole, or a notch where it touches the coast;
    the boundary edges it makes carry ``id`` (a land boundary, as a shoreline
    set's), and gradations may name it in ``lines``. Exactly one of
    ``polygon`` (lon/lat) and ``path`` (a vector file of polygons in its own
    CRS, unioned; ``layer``).
    """

    name: str = key(
        check=schema.string, doc="names the structure in reports and gradations"
    )
    id: int = key(check=schema.integer(1), doc="the boundary id of its edges")
    polygon: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[lon, lat]` points"
    )
    path: Path | None = schema.file_key("a vector file of polygons")
    layer: str | None = schema.layer_key()

    def _validate(self, c: Check) -> StructureConfig:
        _one_place(self, c, ("polygon", "path"))
        if self.polygon is not None and len(self.polygon) < 3:
            raise c.error("polygon", "needs at least three points")
        return self


@dataclass(frozen=True)
class LineConfig:
    """``[[lines]]``: a line inside the sea that the mesh follows, with an id.

    A cable route, a weir crest, a thalweg, a breakwater's centre line: its
    edges are mesh edges (a 1-D physical group ``id`` in msh files). Exactly
    one of ``points`` (lon/lat) and ``path`` (a vector file of lines in its
    own CRS; ``layer``; its lines are joined end to end where they meet).
    """

    name: str = key(check=schema.string, doc="names the line in reports")
    id: int = key(check=schema.integer(1), doc="the physical id of its edges")
    points: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[lon, lat]` points"
    )
    path: Path | None = schema.file_key("a vector file of lines")
    layer: str | None = schema.layer_key()
    h: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="the size field's",
        doc="the element size along it, growing at `rate` away from it",
    )

    def _validate(self, c: Check) -> LineConfig:
        _one_place(self, c, ("points", "path"))
        if self.points is not None and len(self.points) < 2:
            raise c.error("points", "needs at least two points")
        return self
