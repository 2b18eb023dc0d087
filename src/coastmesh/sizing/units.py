"""Lengths with explicit units: metres, kilometres, and degrees of great-circle arc."""

from __future__ import annotations

import math
import numbers
import re

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS, METRES_PER_DEGREE

__all__ = [
    "EARTH_RADIUS",
    "to_metres",
    "to_metres_per_second",
    "to_seconds",
    "to_square_metres",
]

_UNITS = {"m": 1.0, "km": 1000.0, "deg": METRES_PER_DEGREE}
_PATTERN = re.compile(r"^\s*(\S+?)\s*([a-zA-Z]+[0-9]?)\s*$")


def to_metres(
    value: str | float, unit: str | None = None, *, name: str = "length"
) -> float:
    """Convert a length to metres.

    Parameters
    ----------
    value : str or float
        ``"10 km"``, ``"0.02 deg"``, ``"500 m"``; or a number with ``unit``.
    unit : {"m", "km", "deg"}, optional
        The unit of a numeric ``value``. Degrees are of great-circle arc on a sphere
        of radius :data:`EARTH_RADIUS` (1 deg = 111.195 km), as the paper measures
        mesh sizes.
    name : str
        The parameter's name, for error messages.

    Returns
    -------
    float
        The length in metres.

    Raises
    ------
    ConfigError
        For a missing or unknown unit, or a value that is not a finite number.

    Examples
    --------
    >>> to_metres("10 km")
    10000.0
    >>> round(to_metres(1.5, "deg") / 1000, 3)
    166.793
    """
    if isinstance(value, str):
        return _with_unit(value, _UNITS, name, "'10 km', '500 m' or '0.02 deg'")
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        raise ConfigError(f"{name} = {value!r}: not a length")
    if unit is None:
        raise ConfigError(f"{name} = {value!r}: give a unit (m, km or deg)")
    return _scaled(float(value), unit, _UNITS, name, value)


_AREA_UNITS = {"m2": 1.0, "km2": 1e6, "ha": 1e4}
_TIME_UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0}


def to_square_metres(value: str | float, *, name: str = "area") -> float:
    """Convert an area with its unit (``"0.2 km2"``, ``"5000 m2"``, ``"3 ha"``).

    Parameters
    ----------
    value : str or float
        An area with a unit; a bare number is an error, except 0.
    name : str
        The parameter's name, for error messages.

    Returns
    -------
    float
        The area in square metres.

    Raises
    ------
    ConfigError
        For a missing or unknown unit, or a value that is not a finite number.

    Examples
    --------
    >>> to_square_metres("0.2 km2")
    200000.0
    """
    return _with_unit(value, _AREA_UNITS, name, "'0.2 km2', '5000 m2' or '3 ha'")


def to_seconds(value: str | float, *, name: str = "time") -> float:
    """Convert a duration with its unit (``"12.42 h"``, ``"30 min"``, ``"60 s"``).

    Examples
    --------
    >>> to_seconds("1.5 h")
    5400.0
    """
    return _with_unit(value, _TIME_UNITS, name, "'12.42 h', '30 min' or '60 s'")


_SPEED_UNITS = {"m/s": 1.0, "km/h": 1 / 3.6, "kn": 1852 / 3600}
_SPEED = re.compile(r"^\s*(\S+?)\s*(m/s|km/h|kn)\s*$")


def to_metres_per_second(value: str | float, *, name: str = "speed") -> float:
    """Convert a speed with its unit (``"1.5 m/s"``, ``"3 kn"``, ``"5 km/h"``).

    Examples
    --------
    >>> to_metres_per_second("1.5 m/s"), round(to_metres_per_second("2 kn"), 4)
    (1.5, 1.0289)
    """
    example = "'1 m/s', '2 kn' or '5 km/h'"
    return _with_unit(value, _SPEED_UNITS, name, example, pattern=_SPEED)


def _with_unit(
    value: str | float,
    units: dict[str, float],
    name: str,
    example: str,
    *,
    pattern: re.Pattern[str] = _PATTERN,
) -> float:
    if isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0:
        return 0.0
    match = pattern.match(value) if isinstance(value, str) else None
    if match is None:
        raise ConfigError(
            f"{name} = {value!r}: write a number and a unit, e.g. {example}"
        )
    number_text, unit = match.groups()
    try:
        number = float(number_text)
    except ValueError:
        raise ConfigError(
            f"{name} = {value!r}: {number_text!r} is not a number"
        ) from None
    return _scaled(number, unit, units, name, value)


def _scaled(
    number: float, unit: str, units: dict[str, float], name: str, value: object
) -> float:
    """Return ``number`` in the base unit; ``value`` is what was given, for errors."""
    if unit not in units:
        *first, last = units
        choices = f"{', '.join(first)} or {last}"
        raise ConfigError(f"{name} = {value!r}: unknown unit {unit!r}; use {choices}")
    if not math.isfinite(number):
        raise ConfigError(f"{name} = {value!r}: not a finite number")
    return number * units[unit]
