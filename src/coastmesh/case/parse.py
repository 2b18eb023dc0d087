"""Case files: read a TOML case into a ``CaseConfig``, and write one back.

The reader takes each table key by key (:class:`~coastmesh.case.schema.Table`):
an unknown key, a missing one, or a value of the wrong form is an error naming
the file and the key's full path (``open_boundaries[2].bearing``). Lengths,
areas and durations must carry their units (``"10 km"``, ``"0.02 deg"``,
``"0.5 km2"``, ``"12.42 h"``); relative paths are relative to the case file.
The values are then checked by :class:`~coastmesh.case.config.CaseConfig`
itself, so a case built in Python gets the same checks and messages. Reading a
case never reads its data files.

:func:`~coastmesh.case.dump.dump_case` writes a case back as TOML.
"""

from __future__ import annotations

import importlib
import os
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config import (
    BOUNDARY_KINDS,
    CASE_KINDS,
    BathymetryConfig,
    BoundaryConfig,
    CaseConfig,
    ChannelConfig,
    CleanupConfig,
    CourantConfig,
    DepthSourceConfig,
    DomainConfig,
    GradationConfig,
    LoxodromeConfig,
    MeshConfig,
    NodeDepthConfig,
    OutputConfig,
    RegionConfig,
    RunConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
    SizeConfig,
    StudyCase,
)
from coastmesh.case.schema import Table
from coastmesh.errors import ConfigError

__all__ = ["parse_case", "read_case"]

PathOf = Callable[[Any, str], Path]
_LENGTH = schema.length_with_unit


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
    base = source.parent

    def path_of(value: Any, key: str) -> Path:
        p = schema.path(value, key)
        # normpath folds "examples/x/../../out" to "out" (it does not resolve links)
        return p if p.is_absolute() else Path(os.path.normpath(base / p))

    root = Table(data, "", label)
    case = root.table("case", required=True)
    name = case.get("name", schema.string)
    output = case.get("output", path_of, Path(os.path.normpath(base / "out" / name)))
    kind = case.get("kind", schema.choice(CASE_KINDS), "mesh")
    crs = case.get("crs", schema.crs, None) if kind == "mesh" else None
    case.done()
    if kind != "mesh":
        table = root.table("study", required=True)
        module = importlib.import_module(f"coastmesh.case.studies.{kind}")
        study = module.parse_study(table, path_of)
        root.done()
        return StudyCase(source, name, kind, output, study, text)

    parts = {
        "shorelines": _shorelines(root.table("shorelines", required=True), path_of),
        "sets": _sets(root.table("shoreline_sets", required=True)),
        "regions": tuple(_region(t, path_of) for t in root.tables("regions")),
        "domain": DomainConfig(**_domain(root.table("domain"))),
        "boundaries": _boundaries(root, path_of, label),
        "size": _size(root.table("mesh_size", required=True), path_of),
        "mesh": MeshConfig(
            **_done(
                root.table("mesh"),
                "crs",
                "output_crs",
                "seed",
                "algorithm",
                "optimize",
                "parts",
            )
        ),
        "outputs": OutputConfig(
            **_done(
                root.table("output"),
                "formats",
                "positive",
                "domain",
                "size_field",
                "figures",
                "quality",
                "detail",
                "sphere_xyz",
            )
        ),
        "bathymetry": _node_depth(root.table("bathymetry"), path_of)
        if root.has("bathymetry")
        else None,
        "cleanup": CleanupConfig(
            **_done(
                root.table("cleanup"),
                "enabled",
                "boundary_triangles",
                "max_valence",
                "min_angle",
                "smooth",
                "time_step",
            )
        ),
        "run": RunConfig(**_done(root.table("run"), "workers", "scheduler")),
    }
    root.taken.add("bathymetry")
    root.done()
    return CaseConfig(
        name=name, output=output, crs=crs, source=source, text=text, **parts
    )


def _boundaries(root: Table, path_of: PathOf, label: str) -> tuple[BoundaryConfig, ...]:
    """``[[open_boundaries]]``, or in a global case ``[[cuts]]`` (the same keys)."""
    domain = root.data.get("domain", {})
    is_global = isinstance(domain, dict) and domain.get("kind") == "global"
    walls, cuts = root.tables("open_boundaries"), root.tables("cuts")
    if is_global and walls:
        names = [t.data.get("name") for t in walls]
        raise ConfigError(
            f"{label}: [[open_boundaries]] {names}: a global case meshes the whole "
            "ocean, which has no open boundary. To cut a sea off the ocean with an "
            "open boundary (the Mediterranean at Gibraltar, say), give the line as "
            "[[cuts]], with the keys of [[open_boundaries]], and put [domain] seed "
            "in the ocean you keep"
        )
    if cuts and not is_global:
        raise ConfigError(
            f'{label}: [[cuts]] are for global cases ([domain] kind = "global"); '
            "a regional case gives its open boundaries as [[open_boundaries]]"
        )
    return tuple(_boundary(t, path_of) for t in (cuts if is_global else walls))


def _done(t: Table, *names: str) -> dict[str, Any]:
    """Take the keys that are there, as they are, then refuse any other key."""
    picked = t.pick(*names)
    t.done()
    return picked


def _shorelines(t: Table, path_of: PathOf) -> ShorelinesConfig:
    contour = [k for k in ("level", "positive") if t.has(k)]
    if contour and not t.has("raster"):
        raise t.error(contour[0], "is for a raster shoreline (raster = PATH)")
    config = ShorelinesConfig(
        path=t.get("path", path_of, None),
        min_area=t.get("min_area", schema.area_with_unit, 0.0),
        raster=t.get("raster", path_of, None),
        **t.pick("layer", "bbox", "crs", "level", "positive"),
    )
    t.done()
    return config


def _sets(t: Table) -> tuple[ShorelineSetConfig, ...]:
    if not t.data:
        raise t.error("", "define at least one [shoreline_sets.NAME] table")
    sets = []
    for name in t.data:
        s = t.table(name)
        sets.append(
            ShorelineSetConfig(name, s.get("id", _as_is), **_done(s, "window", "modes"))
        )
    t.done()
    return tuple(sets)


def _as_is(value: Any, key: str) -> Any:
    """Take a value as it is: :class:`CaseConfig` checks it."""
    return value


def _region(t: Table, path_of: PathOf) -> RegionConfig:
    config = RegionConfig(
        set=t.get("set", _as_is),
        path=t.get("path", path_of, None),
        **t.pick("box", "polygon", "layer"),
    )
    t.done()
    return config


def _loxodrome(t: Table) -> LoxodromeConfig:
    if t.has("end"):
        others = [
            k for k in ("bearing", "bearing_west", "end_lat", "end_lon") if t.has(k)
        ]
        if others:
            raise t.error("end", f"give either end or {' and '.join(others)}, not both")
        start, end = t.get("start", schema.point), t.get("end", schema.point)
        t.done()
        try:
            return LoxodromeConfig.between(start, end)
        except ConfigError as exc:
            raise t.error("end", str(exc)) from None
    if t.has("bearing") == t.has("bearing_west"):
        raise t.error(
            "bearing",
            "give exactly one of bearing (degrees clockwise from north) and "
            "bearing_west (degrees west of north, as the paper writes them), or "
            "the end point as end = [lon, lat]",
        )
    if t.has("bearing"):
        azimuth = t.get("bearing", schema.number)
    else:
        azimuth = -t.get("bearing_west", schema.number)
    return LoxodromeConfig(
        t.get("start", _as_is), azimuth, **_done(t, "end_lat", "end_lon")
    )


def _boundary(t: Table, path_of: PathOf) -> BoundaryConfig:
    kind = t.get("kind", schema.choice(BOUNDARY_KINDS))
    fields = {
        "name": t.get("name", _as_is),
        "physical_id": t.get("id", _as_is),
        "kind": kind,
        "spacing": t.get("spacing", _LENGTH, None),
    }
    if kind == "loxodrome":
        inline = {k: v for k, v in t.data.items() if k not in t.taken}
        lox = Table(inline, t.where, t.source)
        fields["loxodrome"] = _loxodrome(lox)
        t.taken |= lox.taken
    elif kind == "blend":
        fields["first"] = _loxodrome(t.table("first", required=True))
        fields["second"] = _loxodrome(t.table("second", required=True))
    elif kind == "great_circle":
        fields |= {"start": t.get("start", _as_is), "end": t.get("end", _as_is)}
    elif kind == "polyline":
        fields["path"] = t.get("path", path_of, None)
        fields |= t.pick("points", "layer")
    t.done()
    return BoundaryConfig(**fields)


def _domain(t: Table) -> dict[str, Any]:
    fields = t.pick("seed", "surface_id", "kind", "pole")
    for name in ("seam_tolerance", "close"):
        if t.has(name):
            fields[name] = t.get(name, _LENGTH)
    t.done()
    return fields


def _size(t: Table, path_of: PathOf) -> SizeConfig:
    gradations = []
    for g in t.tables("gradations"):
        gradations.append(
            GradationConfig(
                lines=g.get("lines", _as_is),
                h_min=g.get("h_min", _LENGTH),
                d_grade=g.get("d_grade", _LENGTH),
                d_hold=g.get("d_hold", _LENGTH, 0.0),
            )
        )
        g.done()
    bathymetry = None
    if t.has("bathymetry"):
        b = t.table("bathymetry")
        extra = {k: b.get(k, _LENGTH) for k in ("min_depth",) if b.has(k)}
        if b.has("period"):
            extra["period"] = b.get("period", schema.duration_with_unit)
        bathymetry = BathymetryConfig(
            path=b.get("path", path_of, None),
            sources=_sources(b, path_of),
            **extra,
            **_done(b, "positive", "per_wavelength", "per_slope"),
        )
    t.taken.add("bathymetry")
    extra: dict[str, Any] = {}
    if t.has("channels"):
        ch = t.table("channels")
        extra["channels"] = ChannelConfig(
            **_done(ch, "enabled", "elements_across", "narrow")
        )
    t.taken.add("channels")
    if t.has("courant"):
        co = t.table("courant")
        fields = {"dt": co.get("dt", schema.duration_with_unit)}
        if co.has("velocity"):
            fields["velocity"] = co.get("velocity", schema.speed_with_unit)
        extra["courant"] = CourantConfig(
            **fields, **_done(co, "courant_max", "courant_min")
        )
    t.taken.add("courant")
    return SizeConfig(
        h_max=t.get("h_max", _LENGTH),
        h_min=t.get("h_min", _LENGTH, None),
        cell=t.get("cell", _LENGTH, None),
        gradations=tuple(gradations),
        bathymetry=bathymetry,
        **extra,
        **_done(t, "rate"),
    )


def _node_depth(t: Table, path_of: PathOf) -> NodeDepthConfig:
    extra = {k: t.get(k, _LENGTH) for k in ("min_depth", "land_distance") if t.has(k)}
    return NodeDepthConfig(
        path=t.get("path", path_of, None),
        sources=_sources(t, path_of),
        **extra,
        **_done(
            t, "positive", "method", "max_slope", "window", "modes", "outside", "land"
        ),
    )


def _sources(t: Table, path_of: PathOf) -> tuple[DepthSourceConfig, ...]:
    """Return ``[[...sources]]``: a stack of rasters, in the file's order."""
    sources = []
    for s in t.tables("sources"):
        extra = {"blend": s.get("blend", _LENGTH)} if s.has("blend") else {}
        if s.has("region"):
            extra["region"] = s.get("region", path_of)
        sources.append(
            DepthSourceConfig(
                path=s.get("path", path_of),
                **extra,
                **_done(s, "positive", "bbox", "priority"),
            )
        )
        s.done()
    return tuple(sources)
