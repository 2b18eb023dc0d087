"""Case files: one TOML file describes a whole run of ``coastmesh run``.

The file is read into frozen dataclasses. Every key is checked: an unknown key, a
missing one or a bad value raises :class:`~coastmesh.errors.ConfigError` naming
the file and the key's full path (``open_boundaries[2].bearing``). Lengths, areas
and durations carry their units (``"10 km"``, ``"0.02 deg"``, ``"0.5 km2"``,
``"12.42 h"``). Relative paths are relative to the case file. Reading a case never
reads its data files: :func:`coastmesh.case.run_case` does.

The keys, with their defaults, are listed in ``docs/case-files.md``; the examples
in ``examples/`` use most of them.
"""

from __future__ import annotations

import math
import numbers
import os
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from coastmesh.errors import ConfigError
from coastmesh.sizing.units import to_metres, to_seconds, to_square_metres

__all__ = [
    "BathymetryConfig",
    "BoundaryConfig",
    "CaseConfig",
    "CleanupConfig",
    "DomainConfig",
    "GradationConfig",
    "LoxodromeConfig",
    "MeshConfig",
    "NodeDepthConfig",
    "OutputConfig",
    "RegionConfig",
    "ShorelineSetConfig",
    "ShorelinesConfig",
    "SizeConfig",
    "StudyCase",
    "load_case",
    "parse_case",
]

T = TypeVar("T")
_MISSING: Any = object()

BOUNDARY_KINDS = ("loxodrome", "blend", "great_circle", "polyline")
#: ``[case] kind``: a mesh (default), or one of the paper's PCA studies
CASE_KINDS = ("mesh", "shorelines", "bathymetry")
ALGORITHMS = ("frontal-delaunay", "delaunay", "meshadapt", "automatic")


class _Table:
    """One TOML table being read: each key is taken once; leftovers are errors."""

    def __init__(self, data: object, where: str, source: str) -> None:
        if not isinstance(data, Mapping):
            raise ConfigError(
                f"{source}: {where or 'the file'} must be a table, got "
                f"{type(data).__name__} {data!r}"
            )
        self.data = dict(data)
        self.where = where
        self.source = source
        self.taken: set[str] = set()

    def key(self, name: str) -> str:
        return f"{self.where}.{name}" if self.where else name

    def error(self, name: str, message: str) -> ConfigError:
        sep = " " if message.startswith("=") else ": "
        return ConfigError(f"{self.source}: {self.key(name)}{sep}{message}")

    def has(self, name: str) -> bool:
        return name in self.data

    def get(
        self,
        name: str,
        convert: Callable[[Any, str], T],
        default: Any = _MISSING,
    ) -> T:
        self.taken.add(name)
        if name not in self.data:
            if default is _MISSING:
                raise self.error(name, "is missing")
            return default
        try:
            return convert(self.data[name], self.key(name))
        except ConfigError as exc:
            message = str(exc)
            if not message.startswith(self.source):
                message = f"{self.source}: {message}"
            raise ConfigError(message) from None

    def table(self, name: str, *, required: bool = False) -> _Table:
        self.taken.add(name)
        if name not in self.data:
            if required:
                raise self.error(name, "is missing (a [table])")
            return _Table({}, self.key(name), self.source)
        return _Table(self.data[name], self.key(name), self.source)

    def tables(self, name: str) -> list[_Table]:
        self.taken.add(name)
        items = self.data.get(name, [])
        if not isinstance(items, list):
            raise self.error(name, "must be an array of tables ([[...]])")
        return [
            _Table(item, f"{self.key(name)}[{k}]", self.source)
            for k, item in enumerate(items)
        ]

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.taken)
        if unknown:
            known = ", ".join(sorted(self.taken)) or "none"
            raise ConfigError(
                f"{self.source}: unknown key {self.key(unknown[0])!r}; the keys "
                f"allowed here are: {known}"
            )


# converters: (value, key) -> parsed value, raising ConfigError naming the key


def _string(value: Any, key: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(f"{key} = {value!r}: expected a non-empty string")
    return value


def _boolean(value: Any, key: str) -> bool:
    if not isinstance(value, bool):
        raise ConfigError(f"{key} = {value!r}: expected true or false")
    return value


def _number(value: Any, key: str) -> float:
    if (
        isinstance(value, bool)
        or not isinstance(value, numbers.Real)
        or not math.isfinite(value)
    ):
        raise ConfigError(f"{key} = {value!r}: expected a finite number")
    return float(value)


def _positive(value: Any, key: str) -> float:
    number = _number(value, key)
    if number <= 0:
        raise ConfigError(f"{key} = {value!r}: must be > 0")
    return number


def _integer(minimum: int) -> Callable[[Any, str], int]:
    def convert(value: Any, key: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise ConfigError(f"{key} = {value!r}: expected an integer >= {minimum}")
        return value

    return convert


def _length(*, positive: bool = True) -> Callable[[Any, str], float]:
    def convert(value: Any, key: str) -> float:
        metres = to_metres(value, name=key)
        if metres < 0 or (positive and metres == 0):
            raise ConfigError(
                f"{key} = {value!r}: must be {'>' if positive else '>='} 0"
            )
        return metres

    return convert


def _area(value: Any, key: str) -> float:
    area = to_square_metres(value, name=key)
    if area < 0:
        raise ConfigError(f"{key} = {value!r}: must be >= 0")
    return area


def _duration(value: Any, key: str) -> float:
    seconds = to_seconds(value, name=key)
    if seconds <= 0:
        raise ConfigError(f"{key} = {value!r}: must be > 0")
    return seconds


def _point(value: Any, key: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise ConfigError(f"{key} = {value!r}: expected [x, y] (longitude, latitude)")
    return (_number(value[0], f"{key}[0]"), _number(value[1], f"{key}[1]"))


def _points(value: Any, key: str) -> tuple[tuple[float, float], ...]:
    if not isinstance(value, list) or len(value) < 2:
        raise ConfigError(f"{key}: expected a list of at least two [x, y] points")
    return tuple(_point(p, f"{key}[{k}]") for k, p in enumerate(value))


def _box(value: Any, key: str) -> tuple[float, float, float, float]:
    if not isinstance(value, list) or len(value) != 4:
        raise ConfigError(f"{key} = {value!r}: expected [minx, miny, maxx, maxy]")
    box = tuple(_number(v, f"{key}[{k}]") for k, v in enumerate(value))
    if not (box[0] < box[2] and box[1] < box[3]):
        raise ConfigError(f"{key} = {value!r}: need minx < maxx and miny < maxy")
    return box  # type: ignore[return-value]


def _names(value: Any, key: str) -> tuple[str, ...]:
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value:
        raise ConfigError(f"{key} = {value!r}: expected a name or a list of names")
    return tuple(_string(v, f"{key}[{k}]") for k, v in enumerate(value))


def _choice(options: tuple[str, ...]) -> Callable[[Any, str], str]:
    def convert(value: Any, key: str) -> str:
        if value not in options:
            raise ConfigError(
                f"{key} = {value!r}: expected one of {', '.join(map(repr, options))}"
            )
        return value

    return convert


def _crs(value: Any, key: str) -> str:
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    text = _string(value, key)
    try:
        CRS.from_user_input(text)
    except CRSError:
        raise ConfigError(f"{key} = {value!r}: not a CRS pyproj knows") from None
    return text


# the case


@dataclass(frozen=True, slots=True)
class ShorelinesConfig:
    """``[shorelines]``: the shoreline file (land polygons, e.g. GSHHG)."""

    path: Path
    layer: str | None = None
    bbox: tuple[float, float, float, float] | None = None
    crs: str | None = None
    min_area: float = 0.0


@dataclass(frozen=True, slots=True)
class ShorelineSetConfig:
    """``[shoreline_sets.NAME]``: full resolution, or a PCA reconstruction."""

    name: str
    physical_id: int
    window: int | None = None
    modes: int | None = None

    @property
    def label(self) -> str:
        """Describe the set, e.g. ``"PCA 1 mode / 500 points"``."""
        if self.window is None:
            return "full resolution"
        modes = "1 mode" if self.modes == 1 else f"{self.modes} modes"
        return f"PCA {modes} / {self.window} points"


@dataclass(frozen=True, slots=True)
class RegionConfig:
    """``[[regions]]``: where a shoreline set is used (a box, polygon or file)."""

    set: str
    box: tuple[float, float, float, float] | None = None
    polygon: tuple[tuple[float, float], ...] | None = None
    path: Path | None = None
    layer: str | None = None


@dataclass(frozen=True, slots=True)
class LoxodromeConfig:
    """A rhumb line: start, azimuth (clockwise from north) and one end."""

    start: tuple[float, float]
    azimuth: float
    end_lat: float | None = None
    end_lon: float | None = None


@dataclass(frozen=True, slots=True)
class BoundaryConfig:
    """``[[open_boundaries]]``: one open boundary and its id."""

    name: str
    physical_id: int
    kind: str
    spacing: float | None = None
    loxodrome: LoxodromeConfig | None = None
    first: LoxodromeConfig | None = None
    second: LoxodromeConfig | None = None
    start: tuple[float, float] | None = None
    end: tuple[float, float] | None = None
    points: tuple[tuple[float, float], ...] | None = None
    path: Path | None = None
    layer: str | None = None


@dataclass(frozen=True, slots=True)
class DomainConfig:
    """``[domain]``: which sea region, seams, the surface id."""

    seed: tuple[float, float] | None = None
    seam_tolerance: float = 50.0
    surface_id: int = 1


@dataclass(frozen=True, slots=True)
class GradationConfig:
    """``[[mesh_size.gradations]]``: the paper's gradation from named lines."""

    lines: tuple[str, ...]
    h_min: float
    d_hold: float
    d_grade: float


@dataclass(frozen=True, slots=True)
class BathymetryConfig:
    """``[mesh_size.bathymetry]``: size terms from a bathymetry raster."""

    path: Path
    positive: str = "up"
    per_wavelength: float | None = None
    period: float = 12.4206012 * 3600.0
    per_slope: float | None = None
    min_depth: float = 1.0


@dataclass(frozen=True, slots=True)
class SizeConfig:
    """``[mesh_size]``: the element size field."""

    h_max: float
    gradations: tuple[GradationConfig, ...] = ()
    h_min: float | None = None
    cell: float | None = None
    rate: float | None = None
    bathymetry: BathymetryConfig | None = None


@dataclass(frozen=True, slots=True)
class NodeDepthConfig:
    """``[bathymetry]``: the depth written at the mesh nodes."""

    path: Path
    positive: str = "up"
    method: str = "bilinear"
    min_depth: float | None = None
    max_slope: float | None = None
    window: int | None = None
    modes: int | None = None


@dataclass(frozen=True, slots=True)
class CleanupConfig:
    """``[cleanup]``: fixes after meshing (see :mod:`coastmesh.meshing.cleanup`)."""

    enabled: bool = True
    boundary_triangles: bool = True
    max_valence: int | None = None
    min_angle: float = 20.0


@dataclass(frozen=True, slots=True)
class MeshConfig:
    """``[mesh]``: Gmsh options and CRSs."""

    crs: str | None = None
    output_crs: str | None = None
    seed: int = 0
    algorithm: str = "frontal-delaunay"
    optimize: bool = True


@dataclass(frozen=True, slots=True)
class OutputConfig:
    """``[output]``: what to write."""

    formats: tuple[str, ...] = ("msh2",)
    positive: dict[str, str] | None = None
    domain: bool = True
    size_field: bool = True
    figures: bool = True
    quality: bool = True
    detail: tuple[float, float, float, float] | None = None


@dataclass(frozen=True, slots=True)
class CaseConfig:
    """A whole case, as read from a TOML file by :func:`load_case`."""

    source: Path
    name: str
    output: Path
    crs: str | None
    shorelines: ShorelinesConfig
    sets: tuple[ShorelineSetConfig, ...]
    regions: tuple[RegionConfig, ...]
    domain: DomainConfig
    boundaries: tuple[BoundaryConfig, ...]
    size: SizeConfig
    mesh: MeshConfig
    outputs: OutputConfig
    bathymetry: NodeDepthConfig | None = None
    cleanup: CleanupConfig = CleanupConfig()
    text: str = ""

    @property
    def background_set(self) -> ShorelineSetConfig:
        """The shoreline set used wherever no region picks another one."""
        used = {r.set for r in self.regions}
        return next(s for s in self.sets if s.name not in used)


@dataclass(frozen=True, slots=True)
class StudyCase:
    """A case of another kind than a mesh: one of the paper's PCA studies.

    ``study`` is the parsed ``[study]`` table of ``coastmesh.case.studies.<kind>``.
    """

    source: Path
    name: str
    kind: str
    output: Path
    study: Any
    text: str = ""


def load_case(path: str | Path) -> CaseConfig | StudyCase:
    """Read and check a case file.

    Parameters
    ----------
    path : str or path-like
        The TOML file.

    Returns
    -------
    CaseConfig

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


def parse_case(text: str, source: str | Path) -> CaseConfig | StudyCase:
    """Parse case-file text; relative paths are taken from ``source``'s folder.

    Parameters
    ----------
    text : str
        TOML text.
    source : str or path-like
        The file it came from (names it in errors, anchors relative paths).

    Returns
    -------
    CaseConfig

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
        p = Path(_string(value, key)).expanduser()
        # normpath folds "examples/x/../../out" to "out" (it does not resolve links)
        return p if p.is_absolute() else Path(os.path.normpath(base / p))

    root = _Table(data, "", label)
    case = root.table("case", required=True)
    name = case.get("name", _string)
    output = case.get("output", path_of, Path(os.path.normpath(base / "out" / name)))
    kind = case.get("kind", _choice(CASE_KINDS), "mesh")
    crs = case.get("crs", _crs, None) if kind == "mesh" else None
    case.done()
    if kind != "mesh":
        import importlib

        table = root.table("study", required=True)
        module = importlib.import_module(f"coastmesh.case.studies.{kind}")
        study = module.parse_study(table, path_of)
        root.done()
        return StudyCase(source, name, kind, output, study, text)

    shorelines = _shorelines(root.table("shorelines", required=True), path_of)
    sets = _sets(root.table("shoreline_sets", required=True))
    regions = tuple(_region(t, path_of) for t in root.tables("regions"))
    domain = _domain(root.table("domain"))
    boundaries = tuple(_boundary(t, path_of) for t in root.tables("open_boundaries"))
    size = _size(root.table("mesh_size", required=True), path_of)
    mesh = _mesh(root.table("mesh"))
    outputs = _outputs(root.table("output"))
    bathymetry = (
        _node_depth(root.table("bathymetry"), path_of)
        if root.has("bathymetry")
        else None
    )
    root.taken.add("bathymetry")
    cleanup = _cleanup(root.table("cleanup"))
    root.done()
    config = CaseConfig(
        source=source,
        name=name,
        output=output,
        crs=crs,
        shorelines=shorelines,
        sets=sets,
        regions=regions,
        domain=domain,
        boundaries=boundaries,
        size=size,
        mesh=mesh,
        outputs=outputs,
        bathymetry=bathymetry,
        cleanup=cleanup,
        text=text,
    )
    _cross_check(config, label)
    return config


def _shorelines(t: _Table, path_of: Callable[[Any, str], Path]) -> ShorelinesConfig:
    config = ShorelinesConfig(
        path=t.get("path", path_of),
        layer=t.get("layer", _string, None),
        bbox=t.get("bbox", _box, None),
        crs=t.get("crs", _crs, None),
        min_area=t.get("min_area", _area, 0.0),
    )
    t.done()
    return config


def _sets(t: _Table) -> tuple[ShorelineSetConfig, ...]:
    if not t.data:
        raise t.error("", "define at least one [shoreline_sets.NAME] table")
    sets = []
    for name in t.data:
        s = t.table(name)
        window = s.get("window", _integer(2), None)
        modes = s.get("modes", _integer(1), None)
        if (window is None) != (modes is None):
            raise s.error("window", "give window and modes together (or neither)")
        if window is not None and modes is not None and modes > window:
            raise s.error("modes", f"= {modes} is more than window = {window}")
        sets.append(ShorelineSetConfig(name, s.get("id", _integer(1)), window, modes))
        s.done()
    t.done()
    return tuple(sets)


def _region(t: _Table, path_of: Callable[[Any, str], Path]) -> RegionConfig:
    config = RegionConfig(
        set=t.get("set", _string),
        box=t.get("box", _box, None),
        polygon=t.get("polygon", _points, None),
        path=t.get("path", path_of, None),
        layer=t.get("layer", _string, None),
    )
    given = [k for k in ("box", "polygon", "path") if t.has(k)]
    if len(given) != 1:
        raise t.error("box", "give exactly one of box, polygon and path")
    if config.polygon is not None and len(config.polygon) < 3:
        raise t.error("polygon", "needs at least three points")
    t.done()
    return config


def _loxodrome(t: _Table) -> LoxodromeConfig:
    start = t.get("start", _point)
    if not -90 < start[1] < 90:
        raise t.error("start", f"= {list(start)}: latitude must be in (-90, 90)")
    if t.has("end"):
        others = [
            k for k in ("bearing", "bearing_west", "end_lat", "end_lon") if t.has(k)
        ]
        if others:
            raise t.error("end", f"give either end or {' and '.join(others)}, not both")
        from coastmesh.geometry.rhumb import Loxodrome

        end = t.get("end", _point)
        try:
            line = Loxodrome.between(start, end)
        except ConfigError as exc:
            raise t.error("end", str(exc)) from None
        t.done()
        return LoxodromeConfig(start, line.azimuth, line.end_lat, line.end_lon)
    if t.has("bearing") == t.has("bearing_west"):
        raise t.error(
            "bearing",
            "give exactly one of bearing (degrees clockwise from north) and "
            "bearing_west (degrees west of north, as the paper writes them), or "
            "the end point as end = [lon, lat]",
        )
    if t.has("bearing"):
        azimuth = t.get("bearing", _number) % 360.0
    else:
        azimuth = (-t.get("bearing_west", _number)) % 360.0
    end_lat = t.get("end_lat", _number, None)
    end_lon = t.get("end_lon", _number, None)
    if (end_lat is None) == (end_lon is None):
        raise t.error("end_lat", "give exactly one of end_lat and end_lon")
    t.done()
    return LoxodromeConfig(start, azimuth, end_lat, end_lon)


def _boundary(t: _Table, path_of: Callable[[Any, str], Path]) -> BoundaryConfig:
    name = t.get("name", _string)
    physical_id = t.get("id", _integer(1))
    kind = t.get("kind", _choice(BOUNDARY_KINDS))
    spacing = t.get("spacing", _length(), None)
    fields: dict[str, Any] = {}
    if kind == "loxodrome":
        lox = _Table(
            {
                k: t.data[k]
                for k in t.data
                if k not in ("name", "id", "kind", "spacing")
            },
            t.where,
            t.source,
        )
        fields["loxodrome"] = _loxodrome(lox)
        t.taken |= lox.taken
    elif kind == "blend":
        fields["first"] = _loxodrome(t.table("first", required=True))
        fields["second"] = _loxodrome(t.table("second", required=True))
    elif kind == "great_circle":
        fields["start"] = t.get("start", _point)
        fields["end"] = t.get("end", _point)
    else:  # polyline
        if t.has("points") == t.has("path"):
            raise t.error("points", "give exactly one of points and path")
        fields["points"] = t.get("points", _points, None)
        fields["path"] = t.get("path", path_of, None)
        fields["layer"] = t.get("layer", _string, None)
    t.done()
    return BoundaryConfig(name, physical_id, kind, spacing, **fields)


def _domain(t: _Table) -> DomainConfig:
    config = DomainConfig(
        seed=t.get("seed", _point, None),
        seam_tolerance=t.get("seam_tolerance", _length(positive=False), 50.0),
        surface_id=t.get("surface_id", _integer(1), 1),
    )
    t.done()
    return config


def _size(t: _Table, path_of: Callable[[Any, str], Path]) -> SizeConfig:
    gradations = []
    for g in t.tables("gradations"):
        gradations.append(
            GradationConfig(
                lines=g.get("lines", _names),
                h_min=g.get("h_min", _length()),
                d_hold=g.get("d_hold", _length(positive=False), 0.0),
                d_grade=g.get("d_grade", _length()),
            )
        )
        g.done()
    bathymetry = None
    if t.has("bathymetry"):
        b = t.table("bathymetry")
        bathymetry = BathymetryConfig(
            path=b.get("path", path_of),
            positive=b.get("positive", _choice(("up", "down")), "up"),
            per_wavelength=b.get("per_wavelength", _positive, None),
            period=b.get("period", _duration, 12.4206012 * 3600.0),
            per_slope=b.get("per_slope", _positive, None),
            min_depth=b.get("min_depth", _length(), 1.0),
        )
        if bathymetry.per_wavelength is None and bathymetry.per_slope is None:
            raise b.error("per_wavelength", "give per_wavelength and/or per_slope")
        b.done()
    else:
        t.taken.add("bathymetry")
    config = SizeConfig(
        h_max=t.get("h_max", _length()),
        gradations=tuple(gradations),
        h_min=t.get("h_min", _length(), None),
        cell=t.get("cell", _length(), None),
        rate=t.get("rate", _positive, None),
        bathymetry=bathymetry,
    )
    for k, g in enumerate(config.gradations):
        if g.h_min > config.h_max:
            raise t.error(
                f"gradations[{k}].h_min",
                f"= {g.h_min:g} m is larger than h_max = {config.h_max:g} m",
            )
    t.done()
    return config


def _node_depth(t: _Table, path_of: Callable[[Any, str], Path]) -> NodeDepthConfig:
    from coastmesh.meshing.depth import DEPTH_METHODS

    config = NodeDepthConfig(
        path=t.get("path", path_of),
        positive=t.get("positive", _choice(("up", "down")), "up"),
        method=t.get("method", _choice(DEPTH_METHODS), "bilinear"),
        min_depth=t.get("min_depth", _signed_length, None),
        max_slope=t.get("max_slope", _positive, None),
        window=t.get("window", _integer(2), None),
        modes=t.get("modes", _integer(1), None),
    )
    if (config.window is None) != (config.modes is None):
        raise t.error("window", "give window and modes together (PCA of the raster)")
    if config.window is not None and config.modes > config.window**2:
        raise t.error("modes", f"= {config.modes} is more than window**2")
    t.done()
    return config


def _cleanup(t: _Table) -> CleanupConfig:
    def angle(value: Any, key: str) -> float:
        number = _number(value, key)
        if not 0 < number < 60:
            raise ConfigError(f"{key} = {value!r}: degrees between 0 and 60")
        return number

    config = CleanupConfig(
        enabled=t.get("enabled", _boolean, True),
        boundary_triangles=t.get("boundary_triangles", _boolean, True),
        max_valence=t.get("max_valence", _integer(4), None),
        min_angle=t.get("min_angle", angle, 20.0),
    )
    t.done()
    return config


def _signed_length(value: Any, key: str) -> float:
    return to_metres(value, name=key)


def _mesh(t: _Table) -> MeshConfig:
    config = MeshConfig(
        crs=t.get("crs", _crs, None),
        output_crs=t.get("output_crs", _crs, None),
        seed=t.get("seed", _integer(0), 0),
        algorithm=t.get("algorithm", _choice(ALGORITHMS), "frontal-delaunay"),
        optimize=t.get("optimize", _boolean, True),
    )
    t.done()
    return config


def _outputs(t: _Table) -> OutputConfig:
    def formats(value: Any, key: str) -> tuple[str, ...]:
        from coastmesh.io.writers import mesh_formats

        names = _names(value, key)
        known = mesh_formats()
        for k, n in enumerate(names):
            if n not in known:
                raise ConfigError(
                    f"{key}[{k}] = {n!r}: unknown format; known: {', '.join(known)}"
                )
        if len(set(names)) != len(names):
            raise ConfigError(f"{key} = {list(names)}: a format is listed twice")
        return names

    def signs(value: Any, key: str) -> dict[str, str]:
        from coastmesh.io.writers import mesh_formats

        if not isinstance(value, Mapping):
            raise ConfigError(
                f"{key} = {value!r}: expected a table, e.g. {{ mike = 'up' }}"
            )
        known = mesh_formats()
        for name, sign in value.items():
            if name not in known:
                raise ConfigError(
                    f"{key}.{name}: unknown format; known: {', '.join(known)}"
                )
            _choice(("up", "down"))(sign, f"{key}.{name}")
        return dict(value)

    config = OutputConfig(
        formats=t.get("formats", formats, ("msh2",)),
        positive=t.get("positive", signs, None),
        domain=t.get("domain", _boolean, True),
        size_field=t.get("size_field", _boolean, True),
        figures=t.get("figures", _boolean, True),
        quality=t.get("quality", _boolean, True),
        detail=t.get("detail", _box, None),
    )
    t.done()
    return config


def _cross_check(config: CaseConfig, label: str) -> None:
    set_names = {s.name for s in config.sets}
    for k, r in enumerate(config.regions):
        if r.set not in set_names:
            raise ConfigError(
                f"{label}: regions[{k}].set = {r.set!r}: no such shoreline set; "
                f"the sets are {sorted(set_names)}"
            )
    used = {r.set for r in config.regions}
    background = [s.name for s in config.sets if s.name not in used]
    if len(background) != 1:
        raise ConfigError(
            f"{label}: exactly one shoreline set must have no [[regions]] (it is used "
            f"everywhere else); sets without a region: {background or 'none'}"
        )
    owners: dict[int, str] = {}
    names: set[str] = set()
    items = [("shoreline_sets", s.name, s.physical_id) for s in config.sets]
    items += [
        (f"open_boundaries[{k}]", b.name, b.physical_id)
        for k, b in enumerate(config.boundaries)
    ]
    for where, name, physical_id in items:
        if name in names:
            raise ConfigError(f"{label}: {where}: the name {name!r} is used twice")
        names.add(name)
        if physical_id in owners:
            raise ConfigError(
                f"{label}: {where}: id {physical_id} of {name!r} is also the id of "
                f"{owners[physical_id]!r}; every boundary needs its own id"
            )
        owners[physical_id] = name
    for k, g in enumerate(config.size.gradations):
        for n in g.lines:
            if n not in names:
                raise ConfigError(
                    f"{label}: mesh_size.gradations[{k}].lines: {n!r} is neither a "
                    f"shoreline set nor an open boundary; known: {sorted(names)}"
                )
