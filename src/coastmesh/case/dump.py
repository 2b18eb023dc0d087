"""Write a case as case-file TOML: :func:`dump_case`.

:func:`~coastmesh.case.parse.read_case` reads the text back to an equal case,
so a case built in Python can be saved and run with ``coastmesh run``. Each
table is written by its config class's keys
(:func:`coastmesh.case.schema.dump_part`).
"""

from __future__ import annotations

import os

from coastmesh.case.config import CaseConfig
from coastmesh.case.config.case import boundary_key
from coastmesh.case.schema import dump_keys

__all__ = ["dump_case"]


def dump_case(case: CaseConfig) -> str:
    """Write a case as case-file TOML; :func:`parse_case` reads it back equal.

    Lengths are written in metres, areas in square metres and durations in
    seconds, each with its unit; paths are written absolute, so the text runs
    from any folder.

    Parameters
    ----------
    case : CaseConfig
        The case.

    Returns
    -------
    str
        TOML text.

    Examples
    --------
    >>> from coastmesh.case import (
    ...     CaseConfig, ShorelineSetConfig, ShorelinesConfig, SizeConfig)
    >>> case = CaseConfig(
    ...     name="demo",
    ...     shorelines=ShorelinesConfig("/data/coast.gpkg"),
    ...     sets=[ShorelineSetConfig("coast", 1)],
    ...     size=SizeConfig(h_max="5 km"),
    ... )
    >>> text = dump_case(case)
    >>> 'h_max = "5000.0 m"' in text
    True
    >>> from coastmesh.case.parse import parse_case
    >>> parse_case(text, "/cases/demo.toml").size == case.size
    True
    """
    import tomli_w

    if not isinstance(case, CaseConfig):
        raise TypeError(f"case is a {type(case).__name__}, expected a CaseConfig")
    assert case.output is not None  # __post_init__ sets it (out/NAME by default)
    head = {"name": case.name, "output": os.path.abspath(case.output), "crs": case.crs}
    tables = dump_keys(case)
    if "open_boundaries" in tables:
        tables[boundary_key(case.domain)] = tables.pop("open_boundaries")
    data = {"case": {k: v for k, v in head.items() if v is not None}} | tables
    return tomli_w.dumps(data)
