"""The run state of a case: one frozen class per point of the build.

A case is built by the stages of :data:`coastmesh.case.pipeline.STAGES`, in
order. The run state grows as it goes, and its class says how far it has got:
each class is the one before it plus the part its stage makes, that part never
None, so a stage (or a strategy's step) annotated with the state it reads can
only read what the stages before it made, and mypy checks it::

    CaseRun(config, strategy)                 nothing made yet
    ShorelineRun  + shorelines: Shorelines    shoreline_stage
    DomainRun     + domain: DomainState       domain_stage (closing_stage cuts
                  + site: SiteFeatures | None   it, site_stage sets the site)
    SizedRun      + size: SizeState           size_stage
    MeshedRun     + mesh: MeshState           mesh_stage (channel_stage peels it)
    DepthRun      + depth: DepthState | None  depth_stage (time_step_stage
                                                relieves it); None without
                                                [bathymetry]
    FinishedRun   + quality: QualityReport | None
                                              quality_stage; None without
                                                [output] quality

A stage that makes a part returns the next class, built by the state's own
``with_...`` method (:meth:`CaseRun.with_shorelines`, ...:
:func:`dataclasses.replace` cannot change the class); a stage that changes a
part already made (the closing, the channels, the time-step relief) returns
the same class with :func:`dataclasses.replace`. What is truly optional stays
optional: the site (a case without farms, turbines or lines), the depths
(without ``[bathymetry]``) and the quality (with ``[output] quality = false``).

:data:`~coastmesh.case.pipeline.STAGES` is one list of stages of different
types, so :func:`~coastmesh.case.pipeline.build_run` checks, before it calls a
stage, that the run is the state the stage reads (its ``run`` parameter's
annotation): a stage listed before one that makes what it reads fails before
it runs, naming it and the parts the run lacks. The reports of a case
(:class:`~coastmesh.case.report.CaseReport`) are read from the finished run,
never patched. Where and how the run happens (the workers, the timer, the
figures drawn on the way) is the :class:`RunContext`, not state.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import time
import warnings
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypeVar

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.terms.base import Closing
from coastmesh.depth import DepthReport, DepthSources
from coastmesh.geometry import DomainReport, OpenBoundary, StitchReport
from coastmesh.geometry.world import WorldLand
from coastmesh.meshing import PartsReport, QualityReport, ThrottleReport
from coastmesh.meshing.cleanup.conform import ConformReport
from coastmesh.meshing.cleanup.peel import PeelReport
from coastmesh.sizing.combine import SizeFieldReport
from coastmesh.sizing.courant import CourantReport
from coastmesh.sizing.grid import Grid
from coastmesh.types import (
    Domain,
    Features,
    Mesh,
    Progress,
    Report,
    StageFactory,
)

if TYPE_CHECKING:
    import xarray as xr

    from coastmesh.case.executor import TaskRunner
    from coastmesh.case.figures import FigureJobs
    from coastmesh.case.pipeline.farms import SiteFeatures  # farms imports this
    from coastmesh.case.pipeline.strategy import Strategy

__all__ = [
    "CaseRun",
    "ChangedIsland",
    "ClosingReport",
    "DepthRun",
    "DepthState",
    "DomainRun",
    "DomainState",
    "FinishedRun",
    "MeshState",
    "MeshedRun",
    "RunContext",
    "ShorelineRun",
    "ShorelineSetReport",
    "Shorelines",
    "SizeState",
    "SizedRun",
]

logger = logging.getLogger("coastmesh.case.build")


@dataclass(frozen=True, slots=True)
class ChangedIsland(Report):
    """An island whose area the closing of narrow water changed by over 10 %.

    Attributes
    ----------
    lon, lat : float
        A point inside the island, degrees.
    km2_before : float
        Its area on the Earth before the closing.
    km2_after : float or None
        The area of the land that holds that point after the closing, with
        the land it was joined to; the area left of the island if no land
        holds the point; 0 if it is gone; None if it was joined to the polar
        land (``polar``).
    joined : int
        Other land polygons of the set now part of the same land.
    polar : bool
        Joined to the polar land round the ocean (Antarctica, by default).
    """

    lon: float
    lat: float
    km2_before: float
    km2_after: float | None
    joined: int
    polar: bool = False

    def summary(self) -> str:
        """Return a one-line summary."""
        after = "the polar land" if self.polar else f"{self.km2_after:,.0f} km2"
        return (
            f"({self.lon:.2f}, {self.lat:.2f}): {self.km2_before:,.0f} km2 -> "
            f"{after}" + (f", joined to {self.joined} more" if self.joined else "")
        )


@dataclass(frozen=True, slots=True)
class ClosingReport(Report):
    """What closing narrow water did to a global case's shoreline set.

    Attributes
    ----------
    width : float
        ``[domain] close``, metres.
    merged : int
        Land polygons fewer after the closing (joined, or opened away).
    islands : int
        The set's islands the closing keeps whole: of ``min_area`` or more on
        the Earth (without it, of the closing's disk,
        :func:`~coastmesh.case.pipeline.world.kept_area`).
    changed : tuple of ChangedIsland
        Those whose area changed by more than 10 % of it, the largest change
        first.
    """

    width: float
    merged: int
    islands: int
    changed: tuple[ChangedIsland, ...] = ()

    def summary(self) -> str:
        """Return a one-line summary."""
        joined = sum(c.joined > 0 or c.polar for c in self.changed)
        return (
            f"closing {self.width / 1e3:g} km: {len(self.changed)} of {self.islands} "
            f"islands of min_area changed by more than 10 % of their area ({joined} "
            "joined to other land)"
        )


@dataclass(frozen=True, slots=True)
class ShorelineSetReport(Report):
    """What building one shoreline set did.

    Attributes
    ----------
    kind : str
        ``"full resolution"`` or ``"PCA m modes / L points"``.
    points_in : int
        Vertices of the shoreline layer.
    contours_in, contours_dropped, features_repaired : int or None
        For a PCA set: rings in, rings shorter than the window, and polygons
        repaired after smoothing (:class:`~coastmesh.geometry.ShorelineReport`).
    polygons : int
        Land polygons kept.
    polygons_below_min_area, lakes_below_min_area : int
        Islands dropped and lakes filled for being below ``min_area``.
    points_out : int
        Vertices of the set.
    closing : ClosingReport or None
        A global case's closing of narrow water (``[domain] close``).
    """

    kind: str
    points_in: int
    polygons: int
    polygons_below_min_area: int
    lakes_below_min_area: int
    points_out: int
    contours_in: int | None = None
    contours_dropped: int | None = None
    features_repaired: int | None = None
    closing: ClosingReport | None = None

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.kind}, {self.polygons} polygons ({self.polygons_below_min_area} "
            f"islands and {self.lakes_below_min_area} lakes below min_area dropped), "
            f"{self.points_out:,} points"
        )


@dataclass(frozen=True)
class Shorelines:
    """The shoreline layer read, and each shoreline set built from it.

    Attributes
    ----------
    features : Features
        The land polygons, in :attr:`crs`.
    crs : pyproj.CRS
        The case CRS: ``[case] crs``, else the shoreline file's.
    sets : mapping of str to ndarray of shapely Polygons
        Each set's land, by set name, in the CRS the domain is built in: the
        case CRS of a regional case; the plane of :attr:`world` in a global one.
    reports : mapping of str to ShorelineSetReport
    world : WorldLand or None
        A global case's world land in the stereographic plane (its ``crs``,
        whose singular point is ``[domain] pole``), before the sets were made
        of it; None in a regional case.
    """

    features: Features
    crs: CRS
    sets: Mapping[str, NDArray[np.object_]] = field(default_factory=dict)
    reports: Mapping[str, ShorelineSetReport] = field(default_factory=dict)
    world: WorldLand | None = None


@dataclass(frozen=True)
class DomainState:
    """The domain meshed, what was drawn on the way, and the CRSs of the mesh.

    Attributes
    ----------
    domain : Domain
        The sea polygon and its tagged boundary segments.
    report : DomainReport
    stitch : StitchReport
        Joining the shoreline sets at the region seams.
    regions : tuple of (name, id, geometry or None)
        Where each shoreline set is used.
    open_boundaries : tuple of OpenBoundary
        The open boundaries as drawn, before trimming at the coast.
    land : ndarray of shapely geometries
        The stitched land, before any closed water was added to it.
    mesh_crs, output_crs : pyproj.CRS
        The CRS meshed in, and the CRS of the written nodes.
    closing : Closing
        What was closed as land before the size field.
    structures : tuple of (name, id, polygon)
        The ``[[structures]]`` cut out of the sea, in the domain's CRS (also
        first in ``regions``, so that their edges keep their id).
    seed : (float, float) or None
        ``[domain] seed`` in the domain's CRS; None: the largest sea region.
    """

    domain: Domain
    report: DomainReport
    stitch: StitchReport
    regions: tuple[tuple[str, int, shapely.Geometry | None], ...]
    open_boundaries: tuple[OpenBoundary, ...]
    land: NDArray[np.object_]
    mesh_crs: CRS
    output_crs: CRS
    closing: Closing = field(default_factory=Closing)
    structures: tuple[tuple[str, int, shapely.Polygon], ...] = ()
    seed: tuple[float, float] | None = None


@dataclass(frozen=True)
class SizeState:
    """The size field: its grid, its values, its report, the terms' other grids."""

    grid: Grid
    field: xr.DataArray
    report: SizeFieldReport
    # dataclasses.field: the name field is this class's size field
    layers: Mapping[str, xr.DataArray] = dataclasses.field(default_factory=dict)
    #: the grid's nodes where the elements must take the sizes closely
    #: (:attr:`coastmesh.sizing.combine.Combined.conform`); None: nowhere
    conform: NDArray[np.bool_] | None = None


@dataclass(frozen=True)
class MeshState:
    """The mesh (in the output CRS), how the water was cut, and the cleanup.

    ``channels``: the dead-end channels one element wide closed after
    meshing (:func:`~coastmesh.meshing.cleanup.peel.peel_channels`).
    ``conform``: the elements brought to their sizes where a size term asks
    (:func:`~coastmesh.meshing.cleanup.conform.conform_sizes`).
    """

    mesh: Mesh
    parts: PartsReport
    channels: PeelReport | None = None
    conform: ConformReport | None = None


@dataclass(frozen=True)
class DepthState:
    """The rasters the depths came from, their report, and the time-step relief."""

    rasters: DepthSources
    report: DepthReport
    relief: ThrottleReport | None = None
    #: the depth warnings held back until the time-step relief has run: its
    #: mesh is the one they are about (given then, once)
    deferred: tuple[warnings.WarningMessage, ...] = ()


@dataclass(frozen=True)
class CaseRun:
    """A case about to be built: its config and its strategy, nothing made yet.

    The first of the run states (the module's docstring has them all): each
    stage of :data:`~coastmesh.case.pipeline.STAGES` reads one of them and
    returns it, or the next, with its part made.
    """

    config: CaseConfig
    strategy: Strategy

    def with_shorelines(self, shorelines: Shorelines) -> ShorelineRun:
        """Return the run with its shoreline layer and sets made."""
        return _next(self, ShorelineRun, shorelines=shorelines)


@dataclass(frozen=True)
class ShorelineRun(CaseRun):
    """A run with its shorelines made (``shoreline_stage``)."""

    shorelines: Shorelines

    def with_domain(self, domain: DomainState) -> DomainRun:
        """Return the run with its domain made."""
        return _next(self, DomainRun, domain=domain)


@dataclass(frozen=True)
class DomainRun(ShorelineRun):
    """A run with its domain made (``domain_stage``).

    The closing stage cuts the domain, and the site stage sets the site (read
    and checked), each returning a :class:`DomainRun` still.
    """

    domain: DomainState
    #: the farms and turbines, checked; None in a case without them
    site: SiteFeatures | None = field(default=None, kw_only=True)

    def with_size(self, size: SizeState) -> SizedRun:
        """Return the run with its size field made."""
        return _next(self, SizedRun, size=size)


@dataclass(frozen=True)
class SizedRun(DomainRun):
    """A run with its size field made (``size_stage``)."""

    size: SizeState

    @property
    def time_step(self) -> CourantReport | None:
        """The model's time step and Courant window, if the size field has one.

        The Courant term's report (``dt`` as given, or worked out with
        ``dt = "auto"``); None without the term.
        """
        report = self.size.report.terms.get("courant")
        return report if isinstance(report, CourantReport) else None

    def with_mesh(self, mesh: MeshState) -> MeshedRun:
        """Return the run with its mesh made."""
        return _next(self, MeshedRun, mesh=mesh)


@dataclass(frozen=True)
class MeshedRun(SizedRun):
    """A run with its mesh made (``mesh_stage``).

    The channel stage peels the mesh, returning a :class:`MeshedRun` still.
    """

    mesh: MeshState

    def with_depth(self, depth: DepthState | None) -> DepthRun:
        """Return the run with its depth stage done (``depth`` None: no depths)."""
        return _next(self, DepthRun, depth=depth)


@dataclass(frozen=True)
class DepthRun(MeshedRun):
    """A run whose depth stage is done (``depth_stage``).

    ``depth`` is None in a case without ``[bathymetry]``. The time-step stage
    relieves the mesh and reads the depths again, returning a
    :class:`DepthRun` still.
    """

    depth: DepthState | None

    def with_quality(self, quality: QualityReport | None) -> FinishedRun:
        """Return the run with its quality stage done (``quality`` None: not asked)."""
        return _next(self, FinishedRun, quality=quality)


@dataclass(frozen=True)
class FinishedRun(DepthRun):
    """A run every stage has run on: what a case result is read from.

    ``quality`` is None with ``[output] quality = false``.
    """

    quality: QualityReport | None


#: A run state, in :func:`_next`.
_Run = TypeVar("_Run", bound=CaseRun)


def _next(run: CaseRun, to: type[_Run], **part: object) -> _Run:
    """Return the run as the state ``to``: the parts of ``run`` it has, and ``part``.

    The one place a run changes class (:func:`dataclasses.replace` keeps it);
    the ``with_...`` methods give it its types. A part of ``run`` that ``to``
    does not have is left behind (made from what ``part`` replaces).
    """
    have = {f.name for f in dataclasses.fields(run)}
    values = {
        f.name: getattr(run, f.name) for f in dataclasses.fields(to) if f.name in have
    }
    values.update(part)
    return to(**values)


@dataclass(eq=False)
class RunContext:
    """Where and how a case runs: never what it makes.

    Attributes
    ----------
    threads : int
        Local workers: processes for the parts and figures; threads for the
        PCA, the closing and the size terms.
    runner : TaskRunner
        Where the parts are meshed (here, a process pool, or Dask).
    stage : StageFactory
        ``stage(label)`` gives a progress callback per stage (the command
        line's progress bars).
    figures : FigureJobs or None
        Draws the figures as soon as what they show is made.
    seconds : dict of str to float
        The wall time of each timed step, by its label.
    """

    threads: int
    runner: TaskRunner
    stage: StageFactory
    figures: FigureJobs | None = None
    seconds: dict[str, float] = field(default_factory=dict)
    started: float = field(default_factory=time.perf_counter)

    @contextlib.contextmanager
    def timed(self, label: str) -> Iterator[Progress]:
        """Time one step under ``label``, with its progress callback."""
        t0 = time.perf_counter()
        logger.info("stage: %s", label)
        with self.stage(label) as progress:
            yield progress
        self.seconds[label] = round(time.perf_counter() - t0, 3)


#: A stage: the run state it reads (its ``run`` parameter says which) and the
#: context in, the run with the stage's part out. The stages read different
#: states, so their list cannot say which each reads: ``build_run`` checks it
#: before each call (:func:`~coastmesh.case.pipeline.stage_input`).
Stage = Callable[..., CaseRun]
