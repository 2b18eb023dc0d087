"""Lengths with explicit units: metres, kilometres, and degrees of great-circle arc."""

from __future__ import annotations

import math
import numbers
import re

from coastmesh.errors import ConfigError

__all__ = ["EARTH_RADIUS", "to_metres"]

#: Mean radius of the Earth (IUGG, R1 of WGS84), metres: the length of one radian
#: of great-circle arc, used for lengths the paper gives in degrees.
EARTH_RADIUS = 6_371_008.8

_UNITS = {"m": 1.0, "km": 1000.0, "deg": EARTH_RADIUS * math.pi / 180.0}
_PATTERN = re.compile(r"^\s*(\S+?)\s*([a-zA-Z]+)\s*$")


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
        match = _PATTERN.match(value)
        if match is None:
            raise ConfigError(
                f"{name} = {value!r}: write a number and a unit, e.g. '10 km', "
                "'500 m' or '0.02 deg'"
            )
        number_text, unit = match.groups()
        try:
            number = float(number_text)
        except ValueError:
            raise ConfigError(
                f"{name} = {value!r}: {number_text!r} is not a number"
            ) from None
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        number = float(value)
        if unit is None:
            raise ConfigError(f"{name} = {value!r}: give a unit (m, km or deg)")
    else:
        raise ConfigError(f"{name} = {value!r}: not a length")
    if unit not in _UNITS:
        raise ConfigError(
            f"{name} = {value!r}: unknown unit {unit!r}; use m, km or deg"
        )
    if not math.isfinite(number):
        raise ConfigError(f"{name} = {value!r}: not a finite number")
    return number * _UNITS[unit]
