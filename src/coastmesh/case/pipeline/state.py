"""The run state of a case: :class:`CaseRun`, one typed part per stage.

A case is built by the stages of :data:`coastmesh.case.pipeline.STAGES`, in
order. Each stage takes the run as the stages before it left it and returns it
with its own part filled in (:func:`dataclasses.replace`): the shorelines, the
domain, the size field, the mesh, the depths and the quality, each with its
report. The reports of a case (:class:`~coastmesh.case.report.CaseReport`) are
read from the finished run, never patched. Where and how the run happens (the
workers, the timer, the figures drawn on the way) is the :class:`RunContext`,
not state.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import time
import warnings
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple, NoReturn

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
    Runner,
    StageFactory,
)

if TYPE_CHECKING:
    import xarray as xr

    from coastmesh.case.figures import FigureJobs
    from coastmesh.case.pipeline.farms import SiteFeatures  # farms imports this
    from coastmesh.case.pipeline.strategy import Strategy

__all__ = [
    "Built",
    "CaseRun",
    "ChangedIsland",
    "ClosingReport",
    "DepthState",
    "DomainState",
    "MeshState",
    "RunContext",
    "ShorelineSetReport",
    "Shorelines",
    "SizeState",
    "missing",
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
        A global case's world land in the stereographic plane (its ``crs``),
        what :class:`~coastmesh.case.pipeline.world.Global` takes on to the
        domain and the size grid; None in a regional case.
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


@dataclass(frozen=True)
class MeshState:
    """The mesh (in the output CRS), how the water was cut, and the cleanup.

    ``channels``: the dead-end channels one element wide closed after
    meshing (:func:`~coastmesh.meshing.cleanup.peel.peel_channels`).
    """

    mesh: Mesh
    parts: PartsReport
    channels: PeelReport | None = None


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
    """A case being built: its config, its strategy, and what each stage made.

    Each part is None until its stage has run (:data:`STAGES`).
    """

    config: CaseConfig
    strategy: Strategy
    shorelines: Shorelines | None = None
    domain: DomainState | None = None
    size: SizeState | None = None
    mesh: MeshState | None = None
    depth: DepthState | None = None
    quality: QualityReport | None = None
    #: the farms and turbines, checked; None in a case without them
    site: SiteFeatures | None = None

    @property
    def time_step(self) -> CourantReport | None:
        """The model's time step and Courant window, once the size field has one.

        The Courant term's report (``dt`` as given, or worked out with
        ``dt = "auto"``); None without the term or before the size stage.
        """
        if self.size is None:
            return None
        report = self.size.report.terms.get("courant")
        return report if isinstance(report, CourantReport) else None

    def built(self) -> Built:
        """Return the parts every built case has; raise if a stage has not run."""
        return Built(
            self.shorelines or missing("shorelines"),
            self.domain or missing("domain"),
            self.size or missing("size field"),
            self.mesh or missing("mesh"),
        )


class Built(NamedTuple):
    """The parts of a run that every built case has (:meth:`CaseRun.built`)."""

    shorelines: Shorelines
    domain: DomainState
    size: SizeState
    mesh: MeshState


def missing(part: str) -> NoReturn:
    """Raise for a stage run before the stage that makes ``part``."""
    raise RuntimeError(f"the case has no {part} yet: its stage has not run")


@dataclass(eq=False)
class RunContext:
    """Where and how a case runs: never what it makes.

    Attributes
    ----------
    threads : int
        Local workers: processes for the parts and figures; threads for the
        PCA, the closing and the size terms.
    runner : Runner
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
    runner: Runner
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


#: A stage: the run so far and its context in, the run with the stage's part out.
Stage = Callable[[CaseRun, RunContext], CaseRun]
