"""Read a config part from its case-file table, as its keys declare.

:func:`read_part` takes each key of a part's table (:class:`~.table.Table`):
values with a unit must carry it (``"10 km"``), paths are taken from the case
file's folder, sub-tables and arrays of tables are read as their parts, and a key
left over is an error that lists the keys allowed there. The values are checked
when the :class:`~coastmesh.case.config.CaseConfig` that holds the part is made,
so a case built in Python gets the same checks and messages.

A part reads itself where its table is more than its keys (a loxodrome given by
its two ends, say) with a ``_read(table, reading)`` class method.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from coastmesh.case.schema import convert
from coastmesh.case.schema.convert import Converter
from coastmesh.case.schema.keys import Key, is_required, keys_of
from coastmesh.case.schema.table import Table

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = ["Reading", "read_keys", "read_part", "unchecked_part"]

D = TypeVar("D", bound="DataclassInstance")
#: A sub-table that is not there: the field keeps its default.
_ABSENT = object()

#: How a case file's value of each unit is read: the unit is required.
_UNIT_READERS: dict[str, Converter[float]] = {
    "length": convert.length_with_unit,
    "area": convert.area_with_unit,
    "duration": convert.duration_with_unit,
    "speed": convert.speed_with_unit,
}


@dataclasses.dataclass(frozen=True)
class Reading:
    """What reading a case file needs besides its tables: the file's folder.

    Examples
    --------
    >>> Reading(Path("/cases")).path("../data/coast.gpkg", "shorelines.path")
    PosixPath('/data/coast.gpkg')
    """

    base: Path

    def path(self, value: object, key: str) -> Path:
        """Return a path of the file: relative paths from the file's folder."""
        p = convert.path(value, key)
        # normpath folds "examples/x/../../out" to "out" (it does not resolve links)
        return p if p.is_absolute() else Path(os.path.normpath(self.base / p))


def read_part(kind: type[D], t: Table, reading: Reading, **given: object) -> D:
    """Read a part of class ``kind`` from its table; ``given``: fields known already.

    Unknown keys are an error. The values are converted (units, paths), not yet
    checked.
    """
    # a part's own reader: a class method, ``_read(t, reading, **given) -> part``
    own: Callable[..., D] | None = getattr(kind, "_read", None)
    if own is not None:
        return own(t, reading, **given)
    values = read_keys(kind, t, reading)
    t.done()
    return unchecked_part(kind, values, **given)


def unchecked_part(kind: type[D], values: Mapping[str, object], **given: object) -> D:
    """Make a part of class ``kind`` of values read from a file, not yet checked.

    The part's fields are declared as what its checks make of them (a length
    given as ``"2 km"`` is a float once checked): :func:`~.keys.checked`
    converts and checks them, when the case that holds the part is made.
    """
    return kind(**given, **values)


def read_keys(
    kind: type[DataclassInstance],
    t: Table,
    reading: Reading,
    *,
    rename: dict[str, str] | None = None,
) -> dict[str, object]:  # not yet checked: the part's class checks them
    """Take the keys of ``kind`` that are in ``t``; return them by field name.

    ``rename`` gives other keys for some fields, by field name (the open
    boundaries of a global case are ``[[cuts]]``).
    """
    values: dict[str, object] = {}
    for f, declared in keys_of(kind):
        meta = declared
        if rename and f.name in rename:
            meta = dataclasses.replace(declared, name=rename[f.name])
        if meta.part is not None:
            found = _read_parts(meta, meta.part, t, reading, required=is_required(f))
        elif t.has(meta.name) or is_required(f):
            found = t.get(meta.name, _reader(meta, reading))
        else:
            t.taken.add(meta.name)
            continue
        if found is not _ABSENT:
            values[f.name] = found
    return values


def _reader(meta: Key, reading: Reading) -> Converter[object]:
    if meta.read is not None:
        return meta.read
    if meta.path:
        return reading.path
    if meta.unit is not None:
        return _UNIT_READERS[meta.unit]
    return _as_is


def _as_is(value: object, key: str) -> object:
    """Take a value as it is: the part's checks convert it."""
    return value


def _read_parts(
    meta: Key,
    part: type[DataclassInstance],
    t: Table,
    reading: Reading,
    *,
    required: bool,
) -> object:
    """Read a sub-table, an array of tables, or tables keyed by name."""
    if meta.keyed:
        tables = t.table(meta.name, required=required)
        if required and not tables.data:
            raise tables.error("", f"define at least one [{meta.name}.NAME] table")
        parts = tuple(
            read_part(part, tables.table(name), reading, name=name)
            for name in tables.data
        )
        tables.done()
        return parts
    if meta.many:
        return tuple(
            read_part(_kind_of(meta, part, sub), sub, reading)
            for sub in t.tables(meta.name)
        )
    if not t.has(meta.name):
        if required:
            t.table(meta.name, required=True)
        t.taken.add(meta.name)
        return _ABSENT
    return read_part(part, t.table(meta.name), reading)


def _kind_of(
    meta: Key, part: type[DataclassInstance], t: Table
) -> type[DataclassInstance]:
    """Return the class of one table of an array: by its ``kind``, if it has kinds."""
    if meta.kinds is None:
        return part
    return meta.kinds[t.get("kind", convert.choice(tuple(meta.kinds)))]
