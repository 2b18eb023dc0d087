"""The case schema: every key of a case file declared once, on its config field.

=============================  ==============================================
:mod:`.convert`                value converters: ``convert(value, key)``,
                               errors naming the key and the value
:mod:`.table`                  :class:`Table`: one TOML table, read key by
                               key, unknown keys an error
:mod:`.keys`                   :func:`key` declares a field's key (name,
                               check, unit, doc); :func:`checked` checks a
                               part by its keys
:mod:`.read`                   :func:`read_part`: a part from its table
:mod:`.dump`                   :func:`dump_part`: a part back to TOML data
:mod:`.reference`              the key tables of ``docs/case-files.md``
=============================  ==============================================

The converters are importable from here too (``schema.length()``,
``schema.point``), as the PCA studies read their tables with them.
"""

from __future__ import annotations

from coastmesh.case.schema.convert import (
    Converter,
    area,
    area_with_unit,
    boolean,
    box,
    choice,
    crs,
    duration,
    duration_with_unit,
    integer,
    length,
    length_with_unit,
    names,
    number,
    path,
    point,
    points,
    positive,
    speed,
    speed_with_unit,
    string,
)
from coastmesh.case.schema.dump import dump_keys, dump_part
from coastmesh.case.schema.keys import (
    REQUIRED,
    Check,
    Key,
    check_part,
    check_parts,
    checked,
    file_key,
    key,
    keys_of,
    layer_key,
    sequence,
)
from coastmesh.case.schema.read import Reading, read_keys, read_part, unchecked_part
from coastmesh.case.schema.table import MISSING, Table, located

__all__ = [
    "MISSING",
    "REQUIRED",
    "Check",
    "Converter",
    "Key",
    "Reading",
    "Table",
    "area",
    "area_with_unit",
    "boolean",
    "box",
    "check_part",
    "check_parts",
    "checked",
    "choice",
    "crs",
    "dump_keys",
    "dump_part",
    "duration",
    "duration_with_unit",
    "file_key",
    "integer",
    "key",
    "keys_of",
    "layer_key",
    "length",
    "length_with_unit",
    "located",
    "names",
    "number",
    "path",
    "point",
    "points",
    "positive",
    "read_keys",
    "read_part",
    "sequence",
    "speed",
    "speed_with_unit",
    "string",
    "unchecked_part",
]
