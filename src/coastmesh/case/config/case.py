"""A whole case: :class:`CaseConfig`, checked when built, and :class:`StudyCase`."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config._check import Check, check_part, check_parts
from coastmesh.case.config.boundaries import BoundaryConfig
from coastmesh.case.config.mesh import (
    CleanupConfig,
    MeshConfig,
    NodeDepthConfig,
    OutputConfig,
    RunConfig,
)
from coastmesh.case.config.shorelines import (
    DomainConfig,
    RegionConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
)
from coastmesh.case.config.sizes import SizeConfig
from coastmesh.errors import ConfigError

__all__ = ["CASE_KINDS", "PYTHON_SOURCE", "CaseConfig", "StudyCase"]

#: ``[case] kind``: a mesh (default), or one of the paper's PCA studies
CASE_KINDS = ("mesh", "shorelines", "bathymetry")
#: How a hand-built case is named in messages, where a case file is named.
PYTHON_SOURCE = "CaseConfig"


@dataclass(frozen=True, slots=True, kw_only=True)
class CaseConfig:
    """A whole mesh case, checked when built (see the module docstring).

    Attributes
    ----------
    name : str
        Names the case and its output files.
    shorelines : ShorelinesConfig
    sets : sequence of ShorelineSetConfig
        At least one; exactly one has no region (it is used everywhere else).
    size : SizeConfig
    regions : sequence of RegionConfig
        The first region that holds a place picks its set.
    domain : DomainConfig
    boundaries : sequence of BoundaryConfig
        ``[[open_boundaries]]``; in a global case, ``[[cuts]]``: open
        boundaries that cut seas off the world ocean.
    mesh : MeshConfig
    outputs : OutputConfig
    bathymetry : NodeDepthConfig, optional
        Depth at the nodes.
    cleanup : CleanupConfig
    run : RunConfig
        Where the parts are meshed (workers, a Dask scheduler); it never
        changes the mesh.
    crs : str, optional
        The CRS the case works in; default the shoreline file's.
    output : path, optional
        The output folder; default ``out/NAME`` (next to the case file when
        read from one).
    source : path, optional
        The case file; None for a case built in Python.
    text : str
        The case file's text ("" for a case built in Python).

    Raises
    ------
    ConfigError
        For any bad value or combination; the message names the file (or
        ``CaseConfig``) and the key path.

    Examples
    --------
    >>> case = CaseConfig(
    ...     name="demo",
    ...     shorelines=ShorelinesConfig("coast.gpkg"),
    ...     sets=[ShorelineSetConfig("coast", 1)],
    ...     size=SizeConfig(h_max="5 km"),
    ... )
    >>> case.size.h_max, case.output.as_posix()
    (5000.0, 'out/demo')
    >>> CaseConfig(name="bad", shorelines=ShorelinesConfig("coast.gpkg"),
    ...            sets=[ShorelineSetConfig("coast", 1)], size=SizeConfig(h_max=-1))
    Traceback (most recent call last):
    ...
    coastmesh.errors.ConfigError: CaseConfig: mesh_size.h_max = -1 m: must be > 0
    """

    name: str
    shorelines: ShorelinesConfig
    sets: tuple[ShorelineSetConfig, ...]
    size: SizeConfig
    regions: tuple[RegionConfig, ...] = ()
    domain: DomainConfig = field(default_factory=DomainConfig)
    boundaries: tuple[BoundaryConfig, ...] = ()
    mesh: MeshConfig = field(default_factory=MeshConfig)
    outputs: OutputConfig = field(default_factory=OutputConfig)
    bathymetry: NodeDepthConfig | None = None
    cleanup: CleanupConfig = field(default_factory=CleanupConfig)
    run: RunConfig = field(default_factory=RunConfig)
    crs: str | None = None
    output: Path | None = None
    source: Path | None = None
    text: str = ""

    def __post_init__(self) -> None:
        source = None if self.source is None else Path(self.source)
        c = Check(PYTHON_SOURCE if source is None else str(source))
        name = c(schema.string, self.name, "case.name")
        checked = {
            "name": name,
            "source": source,
            "output": c(schema.path, self.output, "case.output")
            if self.output is not None
            else Path("out") / name,
            "crs": c.optional(schema.crs, self.crs, "case.crs"),
            "shorelines": check_part(
                self.shorelines, ShorelinesConfig, c, "shorelines"
            ),
            "sets": check_parts(
                self.sets,
                ShorelineSetConfig,
                c,
                "shoreline_sets",
                required=True,
                keyed=True,
            ),
            "regions": check_parts(self.regions, RegionConfig, c, "regions"),
            "domain": check_part(self.domain, DomainConfig, c, "domain"),
            "boundaries": check_parts(
                self.boundaries, BoundaryConfig, c, _boundary_key(self.domain)
            ),
            "size": check_part(self.size, SizeConfig, c, "mesh_size"),
            "mesh": check_part(self.mesh, MeshConfig, c, "mesh"),
            "outputs": check_part(self.outputs, OutputConfig, c, "output"),
            "bathymetry": None
            if self.bathymetry is None
            else check_part(self.bathymetry, NodeDepthConfig, c, "bathymetry"),
            "cleanup": check_part(self.cleanup, CleanupConfig, c, "cleanup"),
            "run": check_part(self.run, RunConfig, c, "run"),
            "text": c(_text, self.text, "text"),
        }
        _cross_check(checked, c.source)
        for name, value in checked.items():
            object.__setattr__(self, name, value)

    @property
    def background_set(self) -> ShorelineSetConfig:
        """The shoreline set used wherever no region picks another one."""
        used = {r.set for r in self.regions}
        return next(s for s in self.sets if s.name not in used)

    @property
    def label(self) -> str:
        """The case file, or ``CaseConfig`` for a case built in Python."""
        return PYTHON_SOURCE if self.source is None else str(self.source)


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


def _text(value: Any, key: str) -> str:
    if not isinstance(value, str):
        raise ConfigError(f"{key} = {value!r}: expected the case file's text")
    return value


def _boundary_key(domain: Any) -> str:
    """Return the table of open boundaries: ``cuts`` in a global case."""
    return "cuts" if getattr(domain, "kind", None) == "global" else "open_boundaries"


def _check_global(case: dict[str, Any], label: str) -> None:
    """Refuse what a global case cannot take: some size terms.

    Its ``boundaries`` are the ``[[cuts]]``: lines that cut seas off the ocean.
    """
    size = case["size"]
    if size.courant is not None:
        raise ConfigError(
            f"{label}: [mesh_size.courant] is not available in a global case yet"
        )
    if size.bathymetry is not None and size.bathymetry.per_slope is not None:
        raise ConfigError(
            f"{label}: mesh_size.bathymetry.per_slope: the slope term is not "
            "available in a global case; use per_wavelength"
        )


def _cross_check(case: dict[str, Any], label: str) -> None:
    """Names and ids across tables: sets, regions, boundaries, gradations."""
    sets, regions, boundaries = case["sets"], case["regions"], case["boundaries"]
    if case["domain"].kind == "global":
        _check_global(case, label)
    set_names = [s.name for s in sets]
    for k, r in enumerate(regions):
        if r.set not in set_names:
            raise ConfigError(
                f"{label}: regions[{k}].set = {r.set!r}: no such shoreline set; "
                f"the sets are {sorted(set_names)}"
            )
    used = {r.set for r in regions}
    background = [name for name in set_names if name not in used]
    if len(background) != 1:
        raise ConfigError(
            f"{label}: exactly one shoreline set must have no [[regions]] (it is used "
            f"everywhere else); sets without a region: {background or 'none'}"
        )
    owners: dict[int, str] = {}
    names: set[str] = set()
    items = [("shoreline_sets", s.name, s.physical_id) for s in sets]
    items += [
        (f"{_boundary_key(case['domain'])}[{k}]", b.name, b.physical_id)
        for k, b in enumerate(boundaries)
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
    courant = case["size"].courant
    if (
        courant is not None
        and case["size"].bathymetry is None
        and case.get("bathymetry") is None
    ):
        raise ConfigError(
            f"{label}: mesh_size.courant.dt = {courant.dt:g} s: the Courant term "
            "needs the depth; add [mesh_size.bathymetry] or [bathymetry]"
        )
    for k, g in enumerate(case["size"].gradations):
        for n in g.lines:
            if n not in names:
                raise ConfigError(
                    f"{label}: mesh_size.gradations[{k}].lines: {n!r} is neither a "
                    f"shoreline set nor an open boundary; known: {sorted(names)}"
                )
