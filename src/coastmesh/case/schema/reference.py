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
``scripts/doc_tables.py`` updates the docs; a test checks that they are current.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Mapping

from coastmesh.case.schema.keys import UNITS, Key, is_required, keys_of

__all__ = [
    "MARKER",
    "key_table",
    "markdown",
    "renamed_table",
    "section",
    "update_reference",
]

#: The markers around a generated table: the class's name is the group.
MARKER = re.compile(r"(<!-- keys: (\w+)( own)? -->\n)(.*?)(<!-- /keys -->)", re.DOTALL)


def key_table(kind: type, *, own: bool = False) -> str:
    """Return the Markdown table of a config class's keys.

    ``own``: only the keys it adds to those of its base classes.

    Examples
    --------
    >>> from coastmesh.case.config import RunConfig
    >>> print(key_table(RunConfig).splitlines()[2])  # doctest: +ELLIPSIS
    | `workers` | every core | the cores the run may use: local worker processes ...
    """
    inherited = _inherited(kind)
    rows = ["| key | default | meaning |", "|---|---|---|"]
    for f, meta in keys_of(kind):
        if own and f.name in inherited:
            continue
        doc = meta.doc.replace("|", "\\|")  # a | of a formula is not a column
        rows.append(f"| `{meta.name}` | {_default(f, meta)} | {doc} |")
    return "\n".join(rows) + "\n"


def update_reference(
    text: str, classes: Mapping[str, type], blocks: Mapping[str, str] | None = None
) -> str:
    """Return ``text`` with every marked key table written anew.

    ``classes`` gives the config class of each marker's name, ``blocks`` the
    text of markers that stand for more than one table (the size terms); a
    marker naming neither is an error.
    """
    blocks = blocks or {}

    def table(match: re.Match[str]) -> str:
        name = match.group(2)
        if name == "renamed":
            body = renamed_table(classes.values())
        elif name in blocks:
            body = blocks[name]
        elif name in classes:
            body = key_table(classes[name], own=bool(match.group(3)))
        else:
            raise KeyError(f"docs marker 'keys: {name}' names no config class")
        return match.group(1) + body + match.group(5)

    return MARKER.sub(table, text)


def markdown(doc: str) -> str:
    """Return a docstring's text as Markdown: roles and double backticks as code.

    Examples
    --------
    >>> markdown("the ``h_min`` of :func:`~coastmesh.case.config.floor`")
    'the `h_min` of `floor`'
    """
    text = re.sub(r":\w+:`~[\w.]*?\.?(\w+)`", r"`\1`", doc)
    text = re.sub(r":\w+:`([^`]+)`", r"`\1`", text)
    return text.replace("``", "`")


def section(title: str, doc: str, kind: type, *, own: bool = False) -> str:
    """Return a Markdown section: a title, a docstring's text, a key table."""
    parts = [f"#### {markdown(title).rstrip('.')}", markdown(doc).strip()]
    return "\n\n".join([p for p in parts if p] + [key_table(kind, own=own)])


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


def _default(f: dataclasses.Field[object], meta: Key) -> str:  # noqa: PLR0911
    if meta.default_doc is not None:
        return meta.default_doc
    if is_required(f):
        return "required"
    factory = f.default_factory  # a field has a default or a factory, not both
    value = f.default if factory is dataclasses.MISSING else factory()
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
