"""The key reference of ``docs/case-files.md``, written from the config classes.

Each table of keys in the docs sits between two markers naming its config
class (``own``: only the keys the class adds to its base's)::

    <!-- keys: CourantConfig -->
    | key | default | meaning |
    ...
    <!-- /keys -->

:func:`update_reference` writes every such table again from the class's keys
(their names, defaults and docs), :func:`key_table` writes one, and
:func:`renamed_table` the table of ``docs/python-api.md`` that gives the Python
field of each key named otherwise (marker ``<!-- keys: renamed -->``).
``scripts/case_keys.py`` updates the docs; a test checks that they are current.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Mapping
from typing import Any

from coastmesh.case.schema.keys import UNITS, Key, is_required, keys_of

__all__ = ["MARKER", "key_table", "renamed_table", "update_reference"]

#: The markers around a generated table: the class's name is the group.
MARKER = re.compile(r"(<!-- keys: (\w+)( own)? -->\n)(.*?)(<!-- /keys -->)", re.DOTALL)


def key_table(kind: type, *, own: bool = False) -> str:
    """Return the Markdown table of a config class's keys.

    ``own``: only the keys it adds to those of its base classes.

    Examples
    --------
    >>> from coastmesh.case.config import RunConfig
    >>> print(key_table(RunConfig).splitlines()[2])  # doctest: +ELLIPSIS
    | `workers` | every core | local worker processes ...
    """
    inherited = _inherited(kind)
    rows = ["| key | default | meaning |", "|---|---|---|"]
    for f, meta in keys_of(kind):
        if own and f.name in inherited:
            continue
        doc = meta.doc.replace("|", "\\|")  # a | of a formula is not a column
        rows.append(f"| `{meta.name}` | {_default(f, meta)} | {doc} |")
    return "\n".join(rows) + "\n"


def update_reference(text: str, classes: Mapping[str, type]) -> str:
    """Return ``text`` with every marked key table written anew.

    ``classes`` gives the config class of each marker's name; a marker naming
    no class is an error.
    """

    def table(match: re.Match[str]) -> str:
        name = match.group(2)
        if name == "renamed":
            body = renamed_table(classes.values())
        elif name in classes:
            body = key_table(classes[name], own=bool(match.group(3)))
        else:
            raise KeyError(f"docs marker 'keys: {name}' names no config class")
        return match.group(1) + body + match.group(5)

    return MARKER.sub(table, text)


def renamed_table(classes: Iterable[type]) -> str:
    """Return the table of the keys whose Python field has another name.

    One row per key and field, naming the classes where the key is renamed.
    """
    rows: dict[tuple[str, str], list[str]] = {}
    for kind in classes:
        inherited = _inherited(kind)
        for f, meta in keys_of(kind):
            if meta.name != f.name and f.name not in inherited:
                shown = f"[{meta.name}.NAME]" if meta.keyed else meta.name
                rows.setdefault((shown, f.name), []).append(kind.__name__)
    lines = ["| case file | Python | in |", "|---|---|---|"]
    for (name, field), owners in rows.items():
        lines.append(f"| `{name}` | `{field}` | {', '.join(sorted(set(owners)))} |")
    return "\n".join(lines) + "\n"


def _inherited(kind: type) -> set[str]:
    """Return the fields a class has from its dataclass bases."""
    return {
        f.name
        for base in kind.__mro__[1:]
        if dataclasses.is_dataclass(base)
        for f in dataclasses.fields(base)
    }


def _default(f: dataclasses.Field[Any], meta: Key) -> str:  # noqa: PLR0911
    if meta.default_doc is not None:
        return meta.default_doc
    if is_required(f):
        return "required"
    value = f.default_factory() if f.default is dataclasses.MISSING else f.default
    if value is None or value == ():
        return "none"
    if meta.part is not None:
        return "its defaults"
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, str):
        return f'`"{value}"`'
    if meta.unit is not None:
        return f'`"{value:g} {UNITS[meta.unit][0]}"`'
    if isinstance(value, tuple):
        return (
            "`["
            + ", ".join(f'"{v}"' if isinstance(v, str) else f"{v:g}" for v in value)
            + "]`"
        )
    return f"`{value:g}`" if isinstance(value, float | int) else f"`{value}`"
