"""A whole case: :class:`CaseConfig`, checked when built, and :class:`StudyCase`."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

from coastmesh.case import schema
from coastmesh.case.boundaries import BOUNDARY_KINDS, BoundaryConfig
from coastmesh.case.config.farms import (
    FarmConfig,
    LineConfig,
    StructureConfig,
    TurbinesConfig,
    WakeConfig,
)
from coastmesh.case.config.kinds import domain_kind
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
    SiteConfig,
)
from coastmesh.case.config.sizes import TERMS, SizeConfig
from coastmesh.case.schema import Check, key, keys_of
from coastmesh.case.schema.keys import Key, check_value
from coastmesh.errors import ConfigError

__all__ = ["CASE_KINDS", "PYTHON_SOURCE", "CaseConfig", "CaseKeys", "StudyCase"]

#: ``[case] kind``: a mesh (default), or one of the paper's PCA studies
CASE_KINDS = ("mesh", "shorelines", "bathymetry")
#: How a hand-built case is named in messages, where a case file is named.
PYTHON_SOURCE = "CaseConfig"


@dataclass(frozen=True)
class CaseKeys:
    """``[case]``: the case's name, its output folder, its CRS and its kind."""

    name: str = key(check=schema.string, doc="names the output files (`NAME.msh`, ...)")
    output: Path | None = key(
        None,
        check=schema.path,
        path=True,
        default_doc="`out/NAME`",
        doc="the output folder; `--output` overrides it",
    )
    crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="the shoreline file's",
        doc="the CRS of the domain and of the points in this file",
    )
    kind: str = key(
        "mesh",
        check=schema.choice(CASE_KINDS),
        doc='`"mesh"`, or one of the paper\'s PCA studies: `"shorelines"`, '
        '`"bathymetry"` (below)',
    )


@dataclass(frozen=True, kw_only=True)
class CaseConfig:
    """A whole mesh case, checked when built: one field per table of a case file.

    Every value is checked and converted when a ``CaseConfig`` is made (by the
    case-file reader, by hand, or by :func:`dataclasses.replace`), with the
    messages of the case-file reader, naming the key path
    (``open_boundaries[2].spacing``). ``name``, ``crs`` and ``output`` are the
    keys of ``[case]``; ``source`` and ``text`` are the case file and its text
    (None and "" for a case built in Python). In Python, lengths are numbers of
    metres or strings with a unit (``"10 km"``), areas square metres or
    ``"0.5 km2"``, durations seconds or ``"12.42 h"``; paths are relative to
    the working folder. ``docs/case-files.md`` lists every key.

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
    shorelines: ShorelinesConfig = key(
        part=ShorelinesConfig, doc="the land polygons, or a raster to contour"
    )
    sets: tuple[ShorelineSetConfig, ...] = key(
        name="shoreline_sets",
        part=ShorelineSetConfig,
        many=True,
        keyed=True,
        doc="versions of the coast: full resolution or PCA reconstructions",
    )
    size: SizeConfig = key(name="mesh_size", part=SizeConfig, doc="the size field")
    regions: tuple[RegionConfig, ...] = key(
        (), part=RegionConfig, many=True, doc="where each set is used"
    )
    sites: tuple[SiteConfig, ...] = key(
        (),
        part=SiteConfig,
        many=True,
        doc="regions meshed finely on purpose: channels kept, no Courant floor",
    )
    farms: tuple[FarmConfig, ...] = key(
        (), part=FarmConfig, many=True, doc="farm areas: regions of their own id"
    )
    turbines: tuple[TurbinesConfig, ...] = key(
        (),
        part=TurbinesConfig,
        many=True,
        doc="turbines: mesh nodes, or footprints of their own ids",
    )
    wakes: tuple[WakeConfig, ...] = key(
        (), part=WakeConfig, many=True, doc="refinement along the tidal axis"
    )
    lines: tuple[LineConfig, ...] = key(
        (),
        part=LineConfig,
        many=True,
        doc="lines in the sea the mesh follows, with an id of their own",
    )
    structures: tuple[StructureConfig, ...] = key(
        (),
        part=StructureConfig,
        many=True,
        doc="land in the sea, cut out with a boundary id of its own",
    )
    domain: DomainConfig = key(
        DomainConfig(), part=DomainConfig, doc="the sea region meshed"
    )
    boundaries: tuple[BoundaryConfig, ...] = key(
        (),
        name="open_boundaries",
        part=BoundaryConfig,
        many=True,
        kinds=BOUNDARY_KINDS,
        doc="the open boundaries; `[[cuts]]` in a global case",
    )
    mesh: MeshConfig = key(MeshConfig(), part=MeshConfig, doc="Gmsh and the CRSs")
    outputs: OutputConfig = key(
        OutputConfig(), name="output", part=OutputConfig, doc="what is written"
    )
    bathymetry: NodeDepthConfig | None = key(
        None, part=NodeDepthConfig, doc="the depth at the nodes"
    )
    cleanup: CleanupConfig = key(
        CleanupConfig(), part=CleanupConfig, doc="fixes after meshing"
    )
    run: RunConfig = key(RunConfig(), part=RunConfig, doc="where the work runs")
    crs: str | None = None
    output: Path | None = None
    source: Path | None = None
    text: str = ""

    def __post_init__(self) -> None:
        source = None if self.source is None else Path(self.source)
        c = Check(PYTHON_SOURCE if source is None else str(source))
        name = c(schema.string, self.name, "case.name")
        checked: dict[str, object] = {
            "name": name,
            "source": source,
            "output": Path("out") / name
            if self.output is None
            else c(schema.path, self.output, "case.output"),
            "crs": c.optional(schema.crs, self.crs, "case.crs"),
            "text": c(_text, self.text, "text"),
        }
        domain = check_value(self.domain, *_key(self, "domain"), c)
        assert isinstance(domain, DomainConfig)  # the part's check makes one
        for f, meta in keys_of(self):
            if f.name == "domain":
                checked[f.name] = domain
                continue
            named = meta
            if f.name == "boundaries":
                named = dataclasses.replace(meta, name=boundary_key(domain))
            checked[f.name] = check_value(getattr(self, f.name), f, named, c)
        for name, value in checked.items():
            object.__setattr__(self, name, value)
        _cross_check(self, c.source)

    @property
    def background_set(self) -> ShorelineSetConfig:
        """The shoreline set used wherever no region picks another one."""
        used = {r.set for r in self.regions}
        return next(s for s in self.sets if s.name not in used)

    @property
    def label(self) -> str:
        """The case file, or ``CaseConfig`` for a case built in Python."""
        return PYTHON_SOURCE if self.source is None else str(self.source)


def _key(case: CaseConfig, name: str) -> tuple[dataclasses.Field[object], Key]:
    return next((f, meta) for f, meta in keys_of(case) if f.name == name)


@dataclass(frozen=True)
class StudyCase:
    """A case of another kind than a mesh: one of the paper's PCA studies.

    ``study`` is the parsed ``[study]`` table of ``coastmesh.case.studies.<kind>``.
    """

    source: Path
    name: str
    kind: str
    output: Path
    study: object
    text: str = ""


def _text(value: object, key: str) -> str:
    if not isinstance(value, str):
        raise ConfigError(f"{key} = {value!r}: expected the case file's text")
    return value


def boundary_key(domain: DomainConfig) -> str:
    """Return the table of open boundaries: ``cuts`` in a global case."""
    return domain_kind(domain.kind).boundaries


def _term_defaults(case: CaseConfig) -> None:
    """Switch the terms on by default on, unless the case says otherwise.

    :attr:`~coastmesh.case.terms.base.SizeTerm.on_by_default` (channels and
    Courant: a model's mesh needs its time step and its narrow water wherever
    it is), in regional and global cases alike
    (:func:`~coastmesh.case.terms.base.switched_on`).
    """
    size = case.size
    terms = {
        term.key: dataclasses.replace(part, enabled=True)
        for term in TERMS
        if term.on_by_default
        and (part := term.of(size)) is not None
        and part.enabled is None
    }
    if terms:  # in the case being made (CaseConfig.__post_init__)
        object.__setattr__(case, "size", dataclasses.replace(size, **terms))


def _cross_check(case: CaseConfig, label: str) -> None:
    """Names and ids across tables: sets, regions, boundaries, gradations."""
    sets, regions, boundaries = case.sets, case.regions, case.boundaries
    _term_defaults(case)
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
        (f"{boundary_key(case.domain)}[{k}]", b.name, b.physical_id)
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
    _check_sites(case, label, names, owners)
    _check_model_tests(case, label)
    for term in TERMS:  # each term's own cross-checks (SizeTerm.check)
        term.check(term.of(case.size), case, label=label, lines=names)


def _check_model_tests(case: CaseConfig, label: str) -> None:
    """``[output] model_test``: a case whose kind takes them, depths, open boundaries.

    The kind of case may refuse them
    (:attr:`~coastmesh.case.config.kinds.DomainKind.refuses_model_tests`).
    """
    tests = case.outputs.model_test
    if not tests:
        return
    what = f"{label}: output.model_test = {list(tests)}"
    refused = domain_kind(case.domain.kind).refuses_model_tests
    if refused is not None:
        raise ConfigError(f"{what}: {refused}")
    if case.bathymetry is None:
        raise ConfigError(
            f"{what}: a model needs depths at the nodes; add [bathymetry]"
        )
    if not case.boundaries:
        raise ConfigError(
            f"{what}: the case has no open boundary to force the tide through"
        )


def _check_sites(
    case: CaseConfig, label: str, names: set[str], owners: dict[int, str]
) -> None:
    """Names and ids of farms, turbines and structures.

    Every name is new and every id too (none of a shoreline set, an open
    boundary, the domain's surface or another farm, footprint or structure);
    turbines name a farm that exists. A structure's name joins ``names``: its
    edges are boundary edges that gradations may name. The kind of case may
    refuse them all (:attr:`~coastmesh.case.config.kinds.DomainKind.refuses_sites`).
    """
    refused = domain_kind(case.domain.kind).refuses_sites
    if refused is not None and (
        case.farms or case.turbines or case.wakes or case.structures or case.lines
    ):
        raise ConfigError(f"{label}: {refused}")
    taken = dict(owners)
    surface = case.domain.surface_id
    taken.setdefault(surface, "the domain's surface (domain.surface_id)")
    seen = set(names)

    def claim(where: str, name: str | None, ids: list[int]) -> None:
        if name is not None:
            if name in seen:
                raise ConfigError(f"{label}: {where}: the name {name!r} is used twice")
            seen.add(name)
        for pid in ids:
            if pid in taken:
                raise ConfigError(
                    f"{label}: {where}: id {pid} is also the id of {taken[pid]}; "
                    "every farm, footprint, line and structure needs its own id"
                )
            taken[pid] = repr(name) if name is not None else where

    for k, f in enumerate(case.farms):
        claim(f"farms[{k}]", f.name, [f.id])
        names.add(f.name)  # gradations may name its outline
    for k, ln in enumerate(case.lines):
        claim(f"lines[{k}]", ln.name, [ln.id])
    for k, st in enumerate(case.structures):
        claim(f"structures[{k}]", st.name, [st.id])
        names.add(st.name)  # gradations may name it: it is boundary edges
    farms = {f.name for f in case.farms}
    for k, t in enumerate(case.turbines):
        if t.farm is not None and t.farm not in farms:
            raise ConfigError(
                f"{label}: turbines[{k}].farm = {t.farm!r}: no such farm; the farms "
                f"are {sorted(farms)}"
            )
        ids = list(t.ids or ())
        if t.id is not None and t.ids is None and t.positions is not None:
            ids = list(range(t.id, t.id + len(t.positions)))
        claim(f"turbines[{k}]", t.name, ids)
    groups = farms | {t.name for t in case.turbines}
    for k, w in enumerate(case.wakes):
        if w.of not in groups:
            raise ConfigError(
                f"{label}: wakes[{k}].of = {w.of!r}: no such farm or turbine group; "
                f"known: {sorted(groups)}"
            )
