"""Case files: read a TOML case into a ``CaseConfig`` (:func:`read_case`).

Each table is read by its config class's keys
(:func:`coastmesh.case.schema.read_part`): an unknown key, a missing one, or a
value of the wrong form is an error naming the file and the key's full path
(``open_boundaries[2].bearing``). Lengths, areas, durations and speeds must
carry their units (``"10 km"``, ``"0.02 deg"``, ``"0.5 km2"``, ``"12.42 h"``);
relative paths are relative to the case file. The values are then checked by
:class:`~coastmesh.case.config.CaseConfig` itself, so a case built in Python
gets the same checks and messages. Reading a case never reads its data files.

:func:`~coastmesh.case.dump.dump_case` writes a case back as TOML.
"""

from __future__ import annotations

import importlib
import os
import tomllib
from pathlib import Path

from coastmesh.case.config import CaseConfig, CaseKeys, StudyCase
from coastmesh.case.config.kinds import DOMAIN_KINDS, domain_kind
from coastmesh.case.schema import (
    Check,
    Reading,
    Table,
    checked,
    read_keys,
    unchecked_part,
)
from coastmesh.errors import ConfigError

__all__ = ["parse_case", "read_case"]


def read_case(path: str | os.PathLike[str]) -> CaseConfig | StudyCase:
    """Read and check a case file.

    Parameters
    ----------
    path : str or path-like
        The TOML file.

    Returns
    -------
    CaseConfig or StudyCase
        A study case for ``[case] kind = "shorelines"`` or ``"bathymetry"``.

    Raises
    ------
    ConfigError
        If the file cannot be read or parsed, a key is unknown or missing, or a
        value is bad; the message names the file and the key.
    """
    source = Path(path)
    try:
        text = source.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ConfigError(f"{source}: no such case file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{source}: cannot read it: {exc}") from None
    return parse_case(text, source)


def parse_case(text: str, source: str | os.PathLike[str]) -> CaseConfig | StudyCase:
    """Parse case-file text; relative paths are taken from ``source``'s folder.

    Parameters
    ----------
    text : str
        TOML text.
    source : str or path-like
        The file it came from (names it in errors, anchors relative paths).

    Returns
    -------
    CaseConfig or StudyCase

    Raises
    ------
    ConfigError
        As :func:`read_case`.

    Examples
    --------
    >>> case = parse_case('''
    ... [case]
    ... name = "demo"
    ... [shorelines]
    ... path = "coast.gpkg"
    ... [shoreline_sets.coast]
    ... id = 1
    ... [[open_boundaries]]
    ... name = "sea"
    ... id = 2
    ... kind = "great_circle"
    ... start = [-3.0, 58.0]
    ... end = [-2.0, 59.0]
    ... [mesh_size]
    ... h_max = "5 km"
    ... ''', "/cases/demo.toml")
    >>> case.output.as_posix(), case.boundaries[0].kind, case.size.h_max
    ('/cases/out/demo', 'great_circle', 5000.0)
    """
    source = Path(source)
    label = str(source)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{label}: not valid TOML: {exc}") from None
    reading = Reading(source.parent)
    root = Table(data, "", label)
    head = root.table("case", required=True)
    given = read_keys(CaseKeys, head, reading)
    keys = checked(unchecked_part(CaseKeys, given), Check(label, "case"))
    head.done()
    output = keys.output or Path(os.path.normpath(reading.base / "out" / keys.name))
    if keys.kind != "mesh":
        module = importlib.import_module(f"coastmesh.case.studies.{keys.kind}")
        study = module.parse_study(root.table("study", required=True), reading.path)
        root.done()
        return StudyCase(source, keys.name, keys.kind, output, study, text)
    parts = read_keys(CaseConfig, root, reading, rename=_boundary_table(root, label))
    root.done()
    return unchecked_part(
        CaseConfig,
        parts,
        name=keys.name,
        output=output,
        crs=keys.crs,
        source=source,
        text=text,
    )


def _boundary_table(root: Table, label: str) -> dict[str, str]:
    """``[[open_boundaries]]``, or in a global case ``[[cuts]]`` (the same keys).

    Each kind of case has its table
    (:attr:`~coastmesh.case.config.kinds.DomainKind.boundaries`); another
    kind's is an error.
    """
    domain = root.data.get("domain", {})
    kind = domain_kind(domain.get("kind") if isinstance(domain, dict) else None)
    for table in dict.fromkeys(k.boundaries for k in DOMAIN_KINDS.values()):
        given = root.data.get(table)
        if table != kind.boundaries and given:
            raise ConfigError(f"{label}: {kind.refuse_boundaries(table, given)}")
    return {"boundaries": kind.boundaries}
