"""One TOML table of a case file, read key by key: :class:`Table`."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Final, TypeVar, overload

from coastmesh.case.schema.convert import Converter
from coastmesh.errors import ConfigError

__all__ = ["MISSING", "Table", "located"]

T = TypeVar("T")
D = TypeVar("D")
#: The default of :meth:`Table.get` that makes a key required.
MISSING: Final = object()


class Table:
    """One TOML table being read: each key is taken once; leftovers are errors.

    Parameters
    ----------
    data : mapping
        The table's keys and values.
    where : str
        Its key path in the file (``"mesh_size"``, ``"open_boundaries[2]"``);
        ``""`` for the file itself.
    source : str
        The file, named at the start of every message.

    Raises
    ------
    ConfigError
        If ``data`` is not a mapping.

    Examples
    --------
    >>> from coastmesh.case.schema.convert import length_with_unit, positive
    >>> t = Table({"h_max": "5 km", "rate": 0.2}, "mesh_size", "case.toml")
    >>> t.get("h_max", length_with_unit), t.get("rate", positive)
    (5000.0, 0.2)
    >>> t.get("cell", length_with_unit, None) is None
    True
    >>> t.done()
    >>> Table({"rte": 1}, "mesh_size", "case.toml").done()
    Traceback (most recent call last):
    ...
    coastmesh.errors.ConfigError: case.toml: unknown key 'mesh_size.rte'; ...
    """

    def __init__(self, data: object, where: str, source: str) -> None:
        if not isinstance(data, Mapping):
            raise ConfigError(
                f"{source}: {where or 'the file'} must be a table, got "
                f"{type(data).__name__} {data!r}"
            )
        self.data: dict[str, object] = dict(data)
        self.where = where
        self.source = source
        self.taken: set[str] = set()

    def key(self, name: str) -> str:
        """Return the full key path of ``name`` in this table."""
        return f"{self.where}.{name}" if self.where else name

    def error(self, name: str, message: str) -> ConfigError:
        """Return a ConfigError about key ``name``, naming the file and the key."""
        sep = " " if message.startswith("=") else ": "
        return ConfigError(f"{self.source}: {self.key(name)}{sep}{message}")

    def has(self, name: str) -> bool:
        """Whether the table has key ``name``."""
        return name in self.data

    @overload
    def get(self, name: str, convert: Converter[T]) -> T: ...
    @overload
    def get(self, name: str, convert: Converter[T], default: D) -> T | D: ...

    def get(
        self, name: str, convert: Converter[T], default: object = MISSING
    ) -> object:
        """Take key ``name`` and convert it; ``default`` if absent (else an error)."""
        self.taken.add(name)
        if name not in self.data:
            if default is MISSING:
                raise self.error(name, "is missing")
            return default
        return located(convert, self.data[name], self.key(name), self.source)

    def pick(self, *names: str) -> dict[str, object]:
        """Take the keys that are present, as they are: ``{key: value}``."""
        self.taken.update(names)
        return {name: self.data[name] for name in names if name in self.data}

    def table(self, name: str, *, required: bool = False) -> Table:
        """Take key ``name`` as a sub-table (empty if absent and not required)."""
        self.taken.add(name)
        if name not in self.data:
            if required:
                raise self.error(name, "is missing (a [table])")
            return Table({}, self.key(name), self.source)
        return Table(self.data[name], self.key(name), self.source)

    def tables(self, name: str) -> list[Table]:
        """Take key ``name`` as an array of tables (``[[name]]``)."""
        self.taken.add(name)
        items = self.data.get(name, [])
        if not isinstance(items, list):
            raise self.error(name, "must be an array of tables ([[...]])")
        return [
            Table(item, f"{self.key(name)}[{k}]", self.source)
            for k, item in enumerate(items)
        ]

    def done(self) -> None:
        """Raise if a key of the table was not taken."""
        unknown = sorted(set(self.data) - self.taken)
        if unknown:
            known = ", ".join(sorted(self.taken)) or "none"
            raise ConfigError(
                f"{self.source}: unknown key {self.key(unknown[0])!r}; the keys "
                f"allowed here are: {known}"
            )


def located(convert: Converter[T], value: object, key: str, source: str) -> T:
    """Run a converter; put ``source`` at the start of its error message."""
    try:
        return convert(value, key)
    except ConfigError as exc:
        message = str(exc)
        if not message.startswith(source):
            message = f"{source}: {message}"
        raise ConfigError(message) from None
