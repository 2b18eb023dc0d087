"""Checks of the case dataclasses: converters applied with the key path."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from coastmesh.case.schema import located
from coastmesh.errors import ConfigError

__all__ = ["Check", "check_part", "check_parts", "sequence"]


class Check:
    """Converters applied to values, errors naming the file and the key path."""

    def __init__(self, source: str, where: str = "") -> None:
        self.source = source
        self.where = where

    def key(self, name: str) -> str:
        return f"{self.where}.{name}" if self.where else name

    def __call__(self, convert: Callable[[Any, str], Any], value: Any, name: str):
        return located(convert, value, self.key(name), self.source)

    def optional(self, convert: Callable[[Any, str], Any], value: Any, name: str):
        return None if value is None else self(convert, value, name)

    def error(self, name: str, message: str) -> ConfigError:
        sep = " " if message.startswith("=") else ": "
        return ConfigError(f"{self.source}: {self.key(name)}{sep}{message}")

    def at(self, where: str) -> Check:
        return Check(self.source, self.key(where))


def check_part(value: Any, kind: type, c: Check, where: str) -> Any:
    """Check one part (a config dataclass) at key path ``where``."""
    if not isinstance(value, kind):
        shown = repr(value) if len(repr(value)) < 60 else type(value).__name__
        raise c.error(where, f"= {shown}: expected a {kind.__name__}")
    return value._checked(c.at(where))


def check_parts(
    values: Any,
    kind: type,
    c: Check,
    where: str,
    *,
    required: bool = False,
    keyed: bool = False,
) -> tuple[Any, ...]:
    """Check a list of parts; ``keyed``: name each by its ``name`` in the path."""
    items = sequence(values, c, where)
    if required and not items:
        raise c.error(where, f"define at least one ({kind.__name__})")
    if keyed:  # [shoreline_sets.NAME]: keyed by name
        return tuple(
            check_part(v, kind, c, f"{where}.{getattr(v, 'name', k)}")
            for k, v in enumerate(items)
        )
    return tuple(check_part(v, kind, c, f"{where}[{k}]") for k, v in enumerate(items))


def sequence(values: Any, c: Check, where: str) -> tuple[Any, ...]:
    """Return a list-like value as a tuple; a string or mapping is an error."""
    if isinstance(values, str | bytes | Mapping) or not hasattr(values, "__iter__"):
        raise c.error(where, f"= {values!r}: expected a list")
    return tuple(values)
