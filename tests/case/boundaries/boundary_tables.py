"""Read ``[[open_boundaries]]`` tables as a case file does, apart from a case."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.case.boundaries import BOUNDARY_KINDS, BoundaryConfig
from coastmesh.case.schema import Check, Reading, Table, checked, key, read_part

SOURCE = "/cases/t.toml"
READING = Reading(Path("/cases"))


@dataclass(frozen=True)
class Boundaries:
    """The ``[[open_boundaries]]`` key, declared as the case declares it."""

    boundaries: tuple[BoundaryConfig, ...] = key(
        (),
        name="open_boundaries",
        part=BoundaryConfig,
        many=True,
        kinds=BOUNDARY_KINDS,
        doc="the open boundaries",
    )


def read_boundaries(text_or_tables: str | list[dict[str, Any]]) -> tuple[Any, ...]:
    """Read and check ``[[open_boundaries]]`` from TOML text or from tables."""
    if isinstance(text_or_tables, str):
        data = tomllib.loads(text_or_tables)
    else:
        data = {"open_boundaries": text_or_tables}
    part = read_part(Boundaries, Table(data, "", SOURCE), READING)
    return checked(part, Check(SOURCE)).boundaries
