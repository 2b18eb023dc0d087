"""Value converters: a case file's values checked and turned into Python values.

A converter is ``convert(value, key) -> parsed`` and raises
:class:`~coastmesh.errors.ConfigError` whose message starts with the key and the
bad value (``mesh_size.rate = -1: must be > 0``). The case-file reader, the
checks of every config dataclass and the PCA studies all use these, so a value
gets the same message wherever it is checked.

Converters are lenient about Python types (a tuple or an array where TOML has a
list) and strict about meaning. Lengths, areas, durations and speeds are numbers
in metres, square metres, seconds and metres per second, or strings with a unit
(``"10 km"``); in a case file the unit is required (:func:`length_with_unit`,
:func:`area_with_unit`, :func:`duration_with_unit`, :func:`speed_with_unit`).
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Protocol, TypeGuard, TypeVar, cast

import numpy as np

from coastmesh.errors import ConfigError
from coastmesh.sizing.units import (
    to_metres,
    to_metres_per_second,
    to_seconds,
    to_square_metres,
)

__all__ = [
    "Converter",
    "area",
    "area_with_unit",
    "boolean",
    "box",
    "choice",
    "crs",
    "duration",
    "duration_with_unit",
    "integer",
    "length",
    "length_with_unit",
    "names",
    "number",
    "path",
    "point",
    "points",
    "positive",
    "speed",
    "speed_with_unit",
    "string",
]

T = TypeVar("T")
Converter = Callable[[object, str], T]


def string(value: object, key: str) -> str:
    """Check for a non-empty string."""
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(f"{key} = {value!r}: expected a non-empty string")
    return value


def boolean(value: object, key: str) -> bool:
    """Check for ``true`` or ``false``."""
    if not isinstance(value, bool | np.bool_):
        raise ConfigError(f"{key} = {value!r}: expected true or false")
    return bool(value)


def number(value: object, key: str) -> float:
    """Check for a finite number; return it as a float."""
    if (
        isinstance(value, bool | np.bool_)
        or not isinstance(value, numbers.Real)
        or not math.isfinite(value)
    ):
        raise ConfigError(f"{key} = {value!r}: expected a finite number")
    return float(value)


def positive(value: object, key: str) -> float:
    """Check for a finite number > 0."""
    result = number(value, key)
    if result <= 0:
        raise ConfigError(f"{key} = {value!r}: must be > 0")
    return result


def integer(minimum: int) -> Converter[int]:
    """Return a converter to integers >= ``minimum``."""

    def convert(value: object, key: str) -> int:
        if (
            isinstance(value, bool | np.bool_)
            or not isinstance(value, numbers.Integral)
            or value < minimum
        ):
            raise ConfigError(f"{key} = {value!r}: expected an integer >= {minimum}")
        return int(value)

    return convert


def length_with_unit(value: object, key: str) -> float:
    """Convert a length with its unit (``"10 km"``) to metres; 0 may be bare."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0:
        return 0.0
    return to_metres(_unit_text(value), name=key)


def area_with_unit(value: object, key: str) -> float:
    """Convert an area with its unit (``"0.5 km2"``) to square metres; 0 may be bare."""
    return to_square_metres(_unit_text(value), name=key)


def duration_with_unit(value: object, key: str) -> float:
    """Convert a duration with its unit (``"12.42 h"``) to seconds."""
    return to_seconds(_unit_text(value), name=key)


def speed_with_unit(value: object, key: str) -> float:
    """Convert a speed with its unit (``"1 m/s"``, ``"2 kn"``) to m/s; 0 may be bare."""
    return to_metres_per_second(_unit_text(value), name=key)


def speed(value: object, key: str) -> float:
    """Convert a speed >= 0 (m/s, or a string with a unit)."""
    result = speed_with_unit(value, key) if isinstance(value, str) else None
    if result is None:
        result = number(value, key)
    if result < 0:
        raise ConfigError(f"{key} = {value!r}: must be >= 0")
    return result


def length(*, positive: bool = True, signed: bool = False) -> Converter[float]:
    """Return a converter of lengths (numbers of metres, or strings with a unit).

    ``positive``: must be > 0, else >= 0; ``signed``: any finite length.
    """

    def convert(value: object, key: str) -> float:
        if isinstance(value, str):
            metres = to_metres(value, name=key)
        else:
            metres = number(value, key)
        if signed or metres > 0 or (metres == 0 and not positive):
            return metres
        shown = repr(value) if isinstance(value, str) else f"{metres:g} m"
        raise ConfigError(f"{key} = {shown}: must be {'>' if positive else '>='} 0")

    return convert


def area(value: object, key: str) -> float:
    """Convert an area >= 0 (square metres, or a string with a unit)."""
    if isinstance(value, str):
        result = to_square_metres(value, name=key)
    else:
        result = number(value, key)
    if result < 0:
        raise ConfigError(f"{key} = {value!r}: must be >= 0")
    return result


def duration(value: object, key: str) -> float:
    """Convert a duration > 0 (seconds, or a string with a unit)."""
    seconds = to_seconds(value, name=key) if isinstance(value, str) else None
    if seconds is None:
        seconds = number(value, key)
    if seconds <= 0:
        shown = repr(value) if isinstance(value, str) else f"{seconds:g} s"
        raise ConfigError(f"{key} = {shown}: must be > 0")
    return seconds


def point(value: object, key: str) -> tuple[float, float]:
    """Convert ``[x, y]`` (longitude, latitude) to a tuple of two floats."""
    if isinstance(value, str) or not _sized(value) or len(value) != 2:
        raise ConfigError(f"{key} = {value!r}: expected [x, y] (longitude, latitude)")
    return (number(value[0], f"{key}[0]"), number(value[1], f"{key}[1]"))


def points(value: object, key: str) -> tuple[tuple[float, float], ...]:
    """Convert a list of at least two ``[x, y]`` points to tuples."""
    if isinstance(value, str) or not _sized(value) or len(value) < 2:
        raise ConfigError(f"{key}: expected a list of at least two [x, y] points")
    return tuple(point(p, f"{key}[{k}]") for k, p in enumerate(value))


def box(value: object, key: str) -> tuple[float, float, float, float]:
    """Convert ``[minx, miny, maxx, maxy]`` (``minx < maxx``, ``miny < maxy``)."""
    if isinstance(value, str) or not _sized(value) or len(value) != 4:
        raise ConfigError(f"{key} = {value!r}: expected [minx, miny, maxx, maxy]")
    result = tuple(number(v, f"{key}[{k}]") for k, v in enumerate(value))
    if not (result[0] < result[2] and result[1] < result[3]):
        raise ConfigError(f"{key} = {value!r}: need minx < maxx and miny < maxy")
    return result  # type: ignore[return-value]


def names(value: object, key: str) -> tuple[str, ...]:
    """Convert a name or a non-empty list of names to a tuple."""
    if isinstance(value, str):
        value = [value]
    if not _sized(value) or len(value) == 0:
        raise ConfigError(f"{key} = {value!r}: expected a name or a list of names")
    return tuple(string(v, f"{key}[{k}]") for k, v in enumerate(value))


def choice(options: tuple[str, ...]) -> Converter[str]:
    """Return a converter accepting one of ``options``."""

    def convert(value: object, key: str) -> str:
        if not isinstance(value, str) or value not in options:
            raise ConfigError(
                f"{key} = {value!r}: expected one of {', '.join(map(repr, options))}"
            )
        return value

    return convert


def crs(value: object, key: str) -> str:
    """Check a CRS (anything :meth:`pyproj.CRS.from_user_input` takes); keep text."""
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    if isinstance(value, CRS):
        return value.to_string() if value.to_epsg() is not None else value.to_wkt()
    text = string(value, key)
    try:
        CRS.from_user_input(text)
    except CRSError:
        raise ConfigError(f"{key} = {value!r}: not a CRS pyproj knows") from None
    return text


def path(value: object, key: str) -> Path:
    """Convert a non-empty string or a path-like object to a Path."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    return Path(string(value, key)).expanduser()


class _Sized(Protocol):
    """What :func:`_sized` finds: a list, tuple or array (``len`` and indexing)."""

    def __len__(self) -> int: ...
    def __getitem__(self, index: int, /) -> object: ...
    def __iter__(self) -> Iterator[object]: ...  # by index, if not defined


def _sized(value: object) -> TypeGuard[_Sized]:
    return hasattr(value, "__len__") and hasattr(value, "__getitem__")


def _unit_text(value: object) -> str | float:
    """``value`` as :mod:`coastmesh.sizing.units` takes it: it checks the type."""
    return cast("str | float", value)
