"""What ``coastmesh run --check`` lists of a case's site.

:func:`site_counts` counts the ``[[farms]]``, ``[[turbines]]``, ``[[wakes]]``,
``[[lines]]`` and ``[[structures]]`` of a case for the check's summary line, and
:func:`site_lines` gives a line for each: its name and id, and what it is
checked against (a farm's region id, size and area; each turbine's position,
diameter and footprint id; a wake's axis, length and size; a line's id and
length; a structure's id and area). A kind the case does not have gets nothing.
Reading a case never reads its data files, so an entry read from a file names
the file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.config.farms import (
    FarmConfig,
    LineConfig,
    RotorLength,
    StructureConfig,
    TurbinesConfig,
    WakeConfig,
)
from coastmesh.geometry import arc_lengths, earth_centred, polygon_areas

__all__ = ["site_counts", "site_lines"]

_LONLAT = CRS.from_epsg(4326)

#: ``[[wakes]] sides`` in words
_SIDES = {"both": "both ways", "flood": "flood side", "ebb": "ebb side"}


def site_counts(config: CaseConfig) -> list[str]:
    """Return the count of each kind of site entry the case has, in words.

    Turbines given inline are counted one by one; a group read from a file
    counts as that file.

    Examples
    --------
    >>> from coastmesh.case import parse_case
    >>> from coastmesh.data import path
    >>> case = parse_case(path("pentland_firth.toml").read_text() + '''
    ... [[turbines]]
    ... name = "row"
    ... diameter = "18 m"
    ... positions = [[-3.145, 58.659], [-3.140, 58.659]]
    ... ''', path("pentland_firth.toml"))
    >>> site_counts(case)
    ['2 turbines']
    """
    inline = sum(len(t.positions) for t in config.turbines if t.positions)
    files = sum(t.path is not None for t in config.turbines)
    turbines = _count(inline, "turbine") if inline else ""
    if files:
        turbines += f"{' and ' if inline else ''}{_count(files, 'file')} of turbines"
    counts = [
        _count(len(config.farms), "farm"),
        turbines,
        _count(len(config.wakes), "wake"),
        _count(len(config.lines), "line"),
        _count(len(config.structures), "structure"),
    ]
    return [c for c in counts if c and not c.startswith("0 ")]


def site_lines(config: CaseConfig) -> list[str]:
    """Return a line per farm, turbine group and turbine, wake, line and structure.

    Places given inline are lon/lat; lengths and areas are on the WGS84
    ellipsoid. Lengths given in rotor diameters are also given in metres
    where the diameter is known from the case file.

    Examples
    --------
    >>> from coastmesh.case import parse_case
    >>> from coastmesh.data import path
    >>> case = parse_case(path("pentland_firth.toml").read_text() + '''
    ... [[lines]]
    ... name = "cable"
    ... id = 40
    ... points = [[-3.147, 58.6586], [-3.128, 58.6586]]
    ... ''', path("pentland_firth.toml"))
    >>> site_lines(case)
    ["line 'cable': id 40; 2 points, 1,103 m long; h the size field's"]
    """
    out = [_farm(f) for f in config.farms]
    for group in config.turbines:
        out += _turbines(group)
    out += [_wake(config, w) for w in config.wakes]
    out += [_line(ln) for ln in config.lines]
    out += [_structure(s) for s in config.structures]
    return out


def _farm(farm: FarmConfig) -> str:
    h = "the size field's" if farm.h is None else _metres(farm.h)
    return (
        f"farm {farm.name!r}: region {farm.id}, h {h}; "
        f"{_polygon(farm.polygon, farm.path, farm.layer)}"
    )


def _turbines(group: TurbinesConfig) -> list[str]:
    d = group.diameter if group.positions is not None else None  # else per row
    if group.footprint == "node":
        kind = "a node each"
    elif group.positions is not None:
        ids = _footprint_ids(group)
        kind = f"{group.footprint} footprints, regions {ids[0]} to {ids[-1]}"
    elif group.ids is not None:
        kind = f"{group.footprint} footprints, regions {', '.join(map(str, group.ids))}"
    else:
        kind = f"{group.footprint} footprints, regions from {group.id}"
    where = "standing alone" if group.farm is None else f"in farm {group.farm!r}"
    head = (
        f"turbines {group.name!r}: {kind}, h {_rotor(group.h, d)}, spacing "
        f"{_rotor(group.spacing, d)}, clearance {_rotor(group.clearance, d)}, {where}"
    )
    if group.positions is None:
        crs = f"x, y in {group.crs}" if group.crs else "its own CRS or lon/lat"
        layer = f" layer {group.layer!r}" if group.layer else ""
        size = (
            f"D {_metres(group.diameter)} unless the file gives it"
            if group.diameter
            else "D from the file"
        )
        return [f"{head}; from {group.path}{layer} ({crs}), {size}"]
    assert d is not None  # _validate: inline positions give the diameter
    regions = _footprint_ids(group) if group.footprint != "node" else None
    lines = [head]
    for n, (lon, lat) in enumerate(group.positions):
        region = "" if regions is None else f", region {regions[n]}"
        name = f"{group.name}_{n + 1}"
        lines.append(f"  turbine {name!r} at {lon!r}, {lat!r}, D {_metres(d)}{region}")
    return lines


def _footprint_ids(group: TurbinesConfig) -> list[int]:
    if group.ids is not None:
        return list(group.ids)
    return [(group.id or 0) + n for n in range(len(group.positions or ()))]


def _wake(config: CaseConfig, wake: WakeConfig) -> str:
    farms = {f.name: f for f in config.farms}
    if wake.of in farms:
        groups = [t for t in config.turbines if t.farm == wake.of]
        what = "farm"
    else:
        groups = [t for t in config.turbines if t.name == wake.of]
        what = "turbines"
    sizes = [
        t.diameter
        for t in groups
        if t.positions is not None and t.diameter is not None  # inline: given
    ]
    d = max(sizes) if sizes and len(sizes) == len(groups) else None
    if wake.h is not None:
        h = _rotor(wake.h, d)
    elif wake.of in farms:
        farm_h = farms[wake.of].h
        h = "the farm's" + ("" if farm_h is None else f" ({_metres(farm_h)})")
    else:
        h = _rotor(RotorLength(0.5, True), d)
    return (
        f"wake of {what} {wake.of!r}: bearing {wake.bearing:g} deg, length "
        f"{_rotor(wake.length, d)} {_SIDES[wake.sides]}, h {h}"
    )


def _line(line: LineConfig) -> str:
    if line.points is not None:
        ends = earth_centred(np.asarray(line.points, dtype=np.float64), _LONLAT)
        length = float(arc_lengths(ends[:-1], ends[1:]).sum())
        place = f"{len(line.points)} points, {_metres(length)} long"
    else:
        place = _from(line.path, line.layer)
    h = "the size field's" if line.h is None else _metres(line.h)
    return f"line {line.name!r}: id {line.id}; {place}; h {h}"


def _structure(structure: StructureConfig) -> str:
    place = _polygon(structure.polygon, structure.path, structure.layer)
    return f"structure {structure.name!r}: boundary id {structure.id}; {place}"


def _polygon(
    points: tuple[tuple[float, float], ...] | None, path: Path | None, layer: str | None
) -> str:
    if points is None:
        return _from(path, layer)
    area = float(polygon_areas([shapely.Polygon(points)], _LONLAT)[0])
    return f"a polygon of {len(points)} points, {_area(area)}"


def _from(path: Path | None, layer: str | None) -> str:
    return f"from {path}" + (f" layer {layer!r}" if layer else "")


def _rotor(value: RotorLength, diameter: float | None) -> str:
    """``"20 D (360 m)"`` with the diameter known, ``"20 D"`` or ``"9 m"``."""
    if not value.per_d:
        return _metres(value.value)
    if diameter is None:
        return str(value)
    return f"{value} ({_metres(value.metres(diameter))})"


def _metres(value: float) -> str:
    return f"{value:,.0f} m" if value >= 100 else f"{value:.3g} m"


def _area(value: float) -> str:
    return f"{value:,.0f} m2" if value < 1e6 else f"{value / 1e6:,.3g} km2"


def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"
