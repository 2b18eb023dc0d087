"""The case schema, written once: each config field declares its key.

A config dataclass (``[mesh_size.courant]``, ``[[open_boundaries]]``, ...) gives
every field its case-file key with :func:`key`: the key's name, how a value is
checked and converted, its unit, and one line of documentation. From that one
description:

* :func:`checked` checks a part built in Python or read from a file, with errors
  that name the key path (``mesh_size.courant.dt = -1 s: must be > 0``);
* :func:`coastmesh.case.schema.read.read_part` reads the part's table of a case
  file, every unknown key an error;
* :func:`coastmesh.case.schema.dump.dump_part` writes it back as TOML;
* :mod:`coastmesh.case.schema.reference` writes the key tables of
  ``docs/case-files.md``.

A part may define ``_validate(self, c)``, called after its fields are checked,
for what ties its fields together (exactly one of two keys, ``modes <=
window``); it returns the part, or a copy with defaults that depend on other
fields filled in.

Examples
--------
>>> from dataclasses import dataclass
>>> from coastmesh.case.schema.convert import length
>>> @dataclass(frozen=True)
... class Spacing:
...     step: float = key(check=length(), unit="length", doc="the step")
>>> checked(Spacing("2 km"), Check("case.toml", "grid")).step
2000.0
>>> checked(Spacing(-1), Check("case.toml", "grid"))
Traceback (most recent call last):
...
coastmesh.errors.ConfigError: case.toml: grid.step = -1 m: must be > 0
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, TypeGuard, TypeVar

from coastmesh.case.schema.convert import Converter, string
from coastmesh.case.schema.convert import path as to_path
from coastmesh.case.schema.table import located
from coastmesh.errors import ConfigError

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = [
    "REQUIRED",
    "UNITS",
    "Check",
    "Key",
    "check_part",
    "check_parts",
    "check_value",
    "checked",
    "is_required",
    "key",
    "keys_of",
    "sequence",
]

P = TypeVar("P")
#: A config part: a dataclass.
D = TypeVar("D", bound="DataclassInstance")
#: The default of :func:`key` for a key that must be given.
REQUIRED: Final = dataclasses.MISSING
#: The units a case file writes with a value, by kind (the first when dumping).
UNITS = {
    "length": ("m", "km", "deg"),
    "area": ("m2", "km2", "ha"),
    "duration": ("s", "min", "h"),
    "speed": ("m/s", "km/h", "kn"),
}


@dataclasses.dataclass(frozen=True)
class Key:
    """What a config field is in a case file.

    Attributes
    ----------
    name : str
        The key in the file ("" until :func:`keys_of` fills in the field name).
    check : callable or None
        ``check(value, key) -> value``: converts and checks a value; None for a
        table (``part``).
    unit : str or None
        ``"length"``, ``"area"``, ``"duration"`` or ``"speed"``: a case file
        writes the unit with the value (:data:`UNITS`).
    path : bool
        A file's path: relative to the case file's folder.
    part : type or None
        A sub-table's config class; with ``many``, an array of tables
        (``[[...]]``); with ``keyed`` too, tables named by their key
        (``[shoreline_sets.NAME]``).
    kinds : mapping of str to type, optional
        With ``many``: the classes an array's tables may be, by the value of
        their ``kind`` key (the open-boundary kinds).
    read : callable or None
        ``read(value, key) -> value``: how the file's value is read, where it
        differs from ``check`` (``rate = false``).
    dump : callable or None
        ``dump(value) -> TOML value``, where it differs from the value.
    doc : str
        One line for the key reference.
    default_doc : str or None
        How the default reads in the key reference, where the value says too
        little (``"the smallest gradation h_min"``).
    """

    name: str = ""
    check: Converter[object] | None = None
    unit: str | None = None
    path: bool = False
    part: type | None = None
    many: bool = False
    keyed: bool = False
    kinds: Mapping[str, type] | None = None
    read: Converter[object] | None = None
    dump: Callable[[object], object] | None = None
    doc: str = ""
    default_doc: str | None = None


def key(
    default: object = REQUIRED,
    *,
    doc: str,
    name: str = "",
    check: Converter[object] | None = None,
    unit: str | None = None,
    path: bool = False,
    part: type | None = None,
    many: bool = False,
    keyed: bool = False,
    kinds: Mapping[str, type] | None = None,
    read: Converter[object] | None = None,
    dump: Callable[[object], object] | None = None,
    default_doc: str | None = None,
    kw_only: bool | None = None,
) -> Any:  # as dataclasses.field: the field's type, whatever it is
    """Declare a config field and its case-file key (see :class:`Key`).

    ``default`` is the field's default (:data:`REQUIRED`: the key must be
    given); a part's default config is made anew for each instance. Returns a
    :func:`dataclasses.field`; ``kw_only``: as its ``kw_only``, None for its
    default.
    """
    if unit is not None and unit not in UNITS:
        raise ValueError(f"unit {unit!r}: expected one of {sorted(UNITS)}")
    meta = Key(
        name, check, unit, path, part, many, keyed, kinds, read, dump, doc, default_doc
    )
    metadata = {"key": meta}
    only = dataclasses.MISSING if kw_only is None else kw_only
    if default is REQUIRED:
        return dataclasses.field(metadata=metadata, kw_only=only)
    if dataclasses.is_dataclass(default) and not isinstance(default, type):
        return dataclasses.field(
            default_factory=lambda: default, metadata=metadata, kw_only=only
        )
    return dataclasses.field(default=default, metadata=metadata, kw_only=only)


def file_key(doc: str, *, default_doc: str | None = None) -> Path | None:
    """Declare ``path``: a file, relative to the case file's folder, default none."""
    # a field, declared as the value it holds (as with key and dataclasses.field)
    declared: Path | None = key(
        None, check=to_path, path=True, doc=doc, default_doc=default_doc
    )
    return declared


def layer_key() -> str | None:
    """Declare ``layer``: the layer of ``path``'s vector file, default its only one."""
    declared: str | None = key(
        None, check=string, default_doc="the only layer", doc="its layer"
    )
    return declared


def keys_of(
    part: DataclassInstance | type[DataclassInstance],
) -> list[tuple[dataclasses.Field[object], Key]]:
    """Return the fields of a config class (or part) that are keys, with their keys.

    Each key's ``name`` is its field's name unless it gives another.
    """
    found = []
    for f in dataclasses.fields(part):
        meta = f.metadata.get("key")
        if meta is not None:
            named = meta if meta.name else dataclasses.replace(meta, name=f.name)
            found.append((f, named))
    return found


def is_required(f: dataclasses.Field[object]) -> bool:
    """Whether a field has no default: its key must be given."""
    return f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING


class Check:
    """Converters applied to values, errors naming the file and the key path.

    ``Check(source, where)``: ``source`` names the file (or ``CaseConfig``),
    ``where`` the table's key path (``"mesh_size.courant"``).
    """

    def __init__(self, source: str, where: str = "") -> None:
        self.source = source
        self.where = where

    def key(self, name: str) -> str:
        """Return the full key path of ``name``."""
        return f"{self.where}.{name}" if self.where else name

    def __call__(self, convert: Converter[P], value: object, name: str) -> P:
        """Convert ``value`` of key ``name``; errors name the file and the key."""
        return located(convert, value, self.key(name), self.source)

    def optional(self, convert: Converter[P], value: object, name: str) -> P | None:
        """As calling it, but None stays None."""
        return None if value is None else self(convert, value, name)

    def error(self, name: str, message: str) -> ConfigError:
        """Return a ConfigError about key ``name``."""
        sep = " " if message.startswith("=") else ": "
        return ConfigError(f"{self.source}: {self.key(name)}{sep}{message}")

    def at(self, where: str) -> Check:
        """Return the checks of the sub-table ``where``."""
        return Check(self.source, self.key(where))


def checked(part: D, c: Check) -> D:
    """Check and convert every key of a config part; then its ``_validate``.

    Returns a new part of the same class with the converted values.
    """
    values = {}
    for f, meta in keys_of(part):
        values[f.name] = check_value(getattr(part, f.name), f, meta, c)
    plain = {
        f.name: getattr(part, f.name)
        for f in dataclasses.fields(part)
        if "key" not in f.metadata and f.init
    }
    result = type(part)(**values, **plain)
    validate = getattr(result, "_validate", None)
    return validate(c) if validate is not None else result


def check_value(
    value: object, f: dataclasses.Field[object], meta: Key, c: Check
) -> object:
    """Check one field's value by its key (a part's fields are checked too)."""
    if meta.part is not None and meta.many:
        return check_parts(
            value, meta.part, c, meta.name, required=is_required(f), keyed=meta.keyed
        )
    if value is None and not is_required(f):
        return None
    if meta.part is not None:
        return check_part(value, meta.part, c, meta.name)
    if meta.check is None:
        return value
    return c(meta.check, value, meta.name)


def check_part(value: object, kind: type[D], c: Check, where: str) -> D:
    """Check one part (a config dataclass) at key path ``where``."""
    if not isinstance(value, kind):
        shown = repr(value) if len(repr(value)) < 60 else type(value).__name__
        raise c.error(where, f"= {shown}: expected a {kind.__name__}")
    return checked(value, c.at(where))


def check_parts(
    values: object,
    kind: type[D],
    c: Check,
    where: str,
    *,
    required: bool = False,
    keyed: bool = False,
) -> tuple[D, ...]:
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


def sequence(values: object, c: Check, where: str) -> tuple[object, ...]:
    """Return a list-like value as a tuple; a string or mapping is an error."""
    if isinstance(values, str | bytes | Mapping) or not _iterable(values):
        raise c.error(where, f"= {values!r}: expected a list")
    return tuple(values)


def _iterable(value: object) -> TypeGuard[Iterable[object]]:
    return hasattr(value, "__iter__")
