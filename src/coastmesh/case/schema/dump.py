"""Write a config part back as case-file TOML data, as its keys declare.

:func:`dump_part` is :func:`~coastmesh.case.schema.read.read_part` the other way:
lengths, areas, durations and speeds are written in metres, square metres,
seconds and metres per second with their unit, paths absolute (so the text runs
from any folder), sub-tables and arrays of tables as their parts. Keys whose
value is None are left out, so the reader takes their defaults again.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from coastmesh.case.schema.keys import UNITS, Key, keys_of

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = ["dump_keys", "dump_part", "toml_value"]


def dump_part(part: DataclassInstance) -> dict[str, object]:
    """Return a part as the data of its table (for ``tomli_w``).

    A part that leaves keys out where they do not apply (a regional domain's
    pole, say) does so in a ``_dump()`` method, built on :func:`dump_keys`.

    Examples
    --------
    >>> from coastmesh.case.config import DomainConfig
    >>> dump_part(DomainConfig(seed=(-3.1, 58.85), seam_tolerance=50.0))
    {'seed': [-3.1, 58.85], 'seam_tolerance': '50.0 m', 'surface_id': 1}
    """
    own = getattr(part, "_dump", None)
    return own() if own is not None else dump_keys(part)


def dump_keys(part: DataclassInstance) -> dict[str, object]:
    """Return every key of a part that has a value; a ``kind`` (of a boundary) first."""
    kind = getattr(type(part), "kind", None)
    out: dict[str, object] = {"kind": kind} if isinstance(kind, str) else {}
    for f, meta in keys_of(part):
        value = getattr(part, f.name)
        if value is None and meta.dump is None:
            continue
        dumped = _dump_value(value, meta)
        if dumped not in ([], {}, None):
            out[meta.name] = dumped
    return out


def _dump_value(value: object, meta: Key) -> object:  # noqa: PLR0911 (one per kind)
    """Dump a field's value, of the type its key declares (a part, parts, a path...)."""
    if meta.dump is not None:
        return meta.dump(value)
    if meta.part is not None and meta.keyed:
        return {_name(p): dump_part(p) for p in _parts(value)}
    if meta.part is not None and meta.many:
        return [dump_part(p) for p in _parts(value)]
    if meta.part is not None:
        return dump_part(_part(value))
    if meta.path:
        if not isinstance(value, str | os.PathLike):
            raise TypeError(f"expected a path, got {value!r}")
        return os.path.abspath(value)
    if meta.unit is not None:
        return f"{value!r} {UNITS[meta.unit][0]}"
    return toml_value(value)


def _part(value: object) -> DataclassInstance:
    """Return a sub-table's value as the part it is (a config dataclass)."""
    if not dataclasses.is_dataclass(value) or isinstance(value, type):
        raise TypeError(f"expected a config part, got {value!r}")
    return value


def _parts(value: object) -> list[DataclassInstance]:
    """Return an array of tables' value as its parts."""
    if not isinstance(value, Iterable):
        raise TypeError(f"expected config parts, got {value!r}")
    return [_part(p) for p in value]


def _name(part: DataclassInstance) -> str:
    """Return the ``NAME`` of a keyed table's part (``[shoreline_sets.NAME]``)."""
    name = getattr(part, "name", None)
    if not isinstance(name, str):
        raise TypeError(f"expected a named config part, got {part!r}")
    return name


def toml_value(value: object) -> object:
    """Return a value as TOML holds it: tuples as lists, paths as strings."""
    if isinstance(value, tuple | list):
        return [toml_value(v) for v in value]
    if isinstance(value, Path):
        return os.path.abspath(value)
    if hasattr(value, "items"):
        return {k: toml_value(v) for k, v in value.items()}
    return value
