"""Write a case as case-file TOML: :func:`dump_case`.

:func:`~coastmesh.case.parse.read_case` reads the text back to an equal case,
so a case built in Python can be saved and run with ``coastmesh run``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from coastmesh.case.config import (
    BoundaryConfig,
    CaseConfig,
    ChannelConfig,
    LoxodromeConfig,
    SizeConfig,
)

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
    data: dict[str, Any] = {
        "case": _clean(
            {"name": case.name, "output": _path(case.output), "crs": case.crs}
        ),
        "shorelines": _clean(
            {
                "path": _path(case.shorelines.path),
                "layer": case.shorelines.layer,
                "bbox": case.shorelines.bbox,
                "crs": case.shorelines.crs,
                "min_area": f"{case.shorelines.min_area!r} m2",
                **(
                    {
                        "raster": _path(case.shorelines.raster),
                        "level": _metres(case.shorelines.level),
                        "positive": case.shorelines.positive,
                    }
                    if case.shorelines.raster is not None
                    else {}
                ),
            }
        ),
        "shoreline_sets": {
            s.name: _clean({"id": s.physical_id, "window": s.window, "modes": s.modes})
            for s in case.sets
        },
        "regions": [
            _clean(
                {
                    "set": r.set,
                    "box": r.box,
                    "polygon": r.polygon,
                    "path": _path(r.path),
                    "layer": r.layer,
                }
            )
            for r in case.regions
        ],
        "domain": _clean(
            {
                "seed": case.domain.seed,
                "seam_tolerance": _metres(case.domain.seam_tolerance),
                "surface_id": case.domain.surface_id,
                **(
                    {
                        "kind": "global",
                        "pole": case.domain.pole,
                        "close": _metres(case.domain.close),
                    }
                    if case.domain.kind == "global"
                    else {}
                ),
            }
        ),
        "cuts" if case.domain.kind == "global" else "open_boundaries": [
            _dump_boundary(b) for b in case.boundaries
        ],
        "mesh_size": _dump_size(case.size),
        "mesh": _clean(_fields(case.mesh)),
        "output": _clean(_fields(case.outputs)),
        "cleanup": _clean(_fields(case.cleanup)),
        "run": _clean(_fields(case.run)),
    }
    if case.bathymetry is not None:
        b = case.bathymetry
        data["bathymetry"] = _clean(
            _fields(b)
            | {
                "path": _path(b.path),
                "min_depth": _metres(b.min_depth),
                "land_distance": _metres(b.land_distance),
                "sources": [_dump_source(s) for s in b.sources],
            }
        )
    data = {key: value for key, value in data.items() if value not in ([], {})}
    return tomli_w.dumps(data)


def _dump_boundary(b: BoundaryConfig) -> dict[str, Any]:
    out: dict[str, Any] = {
        "name": b.name,
        "id": b.physical_id,
        "kind": b.kind,
        "spacing": _metres(b.spacing),
    }
    if b.loxodrome is not None:
        out |= _dump_loxodrome(b.loxodrome)
    for name in ("first", "second"):
        if getattr(b, name) is not None:
            out[name] = _dump_loxodrome(getattr(b, name))
    given = {
        "start": b.start,
        "end": b.end,
        "points": b.points,
        "path": _path(b.path),
        "layer": b.layer,
    }
    out |= {key: value for key, value in given.items() if value is not None}
    return _clean(out)


def _dump_loxodrome(lox: LoxodromeConfig) -> dict[str, Any]:
    return _clean(
        {
            "start": lox.start,
            "bearing": lox.azimuth,
            "end_lat": lox.end_lat,
            "end_lon": lox.end_lon,
        }
    )


def _dump_size(size: SizeConfig) -> dict[str, Any]:
    out: dict[str, Any] = {
        "h_max": _metres(size.h_max),
        "h_min": _metres(size.h_min),
        "cell": _metres(size.cell),
        "rate": False if size.rate is None else size.rate,  # no limit
        "gradations": [
            {
                "lines": g.lines,
                "h_min": _metres(g.h_min),
                "d_hold": _metres(g.d_hold),
                "d_grade": _metres(g.d_grade),
            }
            for g in size.gradations
        ],
    }
    if size.bathymetry is not None:
        b = size.bathymetry
        out["bathymetry"] = _clean(
            _fields(b)
            | {
                "path": _path(b.path),
                "sources": [_dump_source(s) for s in b.sources],
                "period": f"{b.period!r} s",
                "min_depth": _metres(b.min_depth),
            }
        )
    if size.channels != ChannelConfig():
        out["channels"] = _clean(_fields(size.channels))
    if size.courant is not None:
        co = size.courant
        out["courant"] = _clean(
            _fields(co) | {"dt": f"{co.dt!r} s", "velocity": f"{co.velocity!r} m/s"}
        )
    return _clean(out)


def _dump_source(s: Any) -> dict[str, Any]:
    return _clean(
        _fields(s)
        | {"path": _path(s.path), "region": _path(s.region), "blend": _metres(s.blend)}
    )


def _fields(part: Any) -> dict[str, Any]:
    return {name: getattr(part, name) for name in part.__dataclass_fields__}


def _clean(table: dict[str, Any]) -> dict[str, Any]:
    """Drop None and empty lists; tuples to lists, mappings to dicts."""
    return {
        key: _toml_value(value)
        for key, value in table.items()
        if value is not None and value != []
    }


def _toml_value(value: Any) -> Any:
    if isinstance(value, tuple | list):
        return [_toml_value(v) for v in value]
    if isinstance(value, Path):
        return _path(value)
    if hasattr(value, "items"):
        return dict(value)
    return value


def _metres(value: float | None) -> str | None:
    return None if value is None else f"{value!r} m"


def _path(value: Path | None) -> str | None:
    return None if value is None else os.path.abspath(value)
