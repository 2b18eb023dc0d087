"""The report of a whole case: :class:`CaseReport` (``report.json``) and its parts."""

from __future__ import annotations

import sys
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from pyproj import CRS

from coastmesh.case.pipeline.state import FinishedRun, ShorelineSetReport
from coastmesh.depth import DepthReport
from coastmesh.geometry import DomainReport, StitchReport
from coastmesh.meshing import CleanupReport, QualityReport, ThrottleReport
from coastmesh.meshing.cleanup.conform import ConformReport
from coastmesh.meshing.cleanup.peel import PeelReport
from coastmesh.meshing.parts.report import PartsReport
from coastmesh.sizing import SizeFieldReport
from coastmesh.types import Mesh, Report

__all__ = ["CaseReport", "MeshReport", "peak_memory_mb"]


@dataclass(frozen=True, slots=True)
class MeshReport(Report):
    """The mesh a case made.

    Attributes
    ----------
    nodes, triangles : int
    boundary_edges : dict of str to int
        Boundary edges by ``"name (id)"``.
    surface_id : int
        The physical id of the triangles.
    line_edges : dict of str to int
        The edges of each line inside the mesh (``[[lines]]``), by
        ``"name (id)"``.
    """

    nodes: int
    triangles: int
    boundary_edges: dict[str, int]
    surface_id: int
    line_edges: dict[str, int] = field(default_factory=dict)

    @classmethod
    def of(cls, mesh: Mesh) -> MeshReport:
        """Count the nodes, triangles and boundary edges by id of a mesh."""
        ids, counts = np.unique(mesh.boundary_ids, return_counts=True)
        edges = {
            f"{mesh.boundary_names.get(int(i), '?')} ({int(i)})": int(c)
            for i, c in zip(ids, counts, strict=True)
        }
        lines = {f"{ln.name} ({ln.id})": len(ln.xy) - 1 for ln in mesh.lines}
        return cls(len(mesh.points), len(mesh.triangles), edges, mesh.surface_id, lines)

    def summary(self) -> str:
        """Return a one-line summary."""
        ids = ", ".join(f"{k} {v}" for k, v in self.boundary_edges.items())
        lines = ", ".join(f"{k} {v}" for k, v in self.line_edges.items())
        return (
            f"{self.nodes:,} nodes, {self.triangles:,} triangles, boundary edges "
            f"by id: {ids}" + (f"; line edges: {lines}" if lines else "")
        )


@dataclass(frozen=True, slots=True)
class CaseReport(Report):
    """Every number of a case run: ``report.json`` is its :meth:`to_dict`.

    Attributes
    ----------
    case : str
        The case's name.
    source : str or None
        The case file; None for a case built in Python.
    coastmesh_version : str
    crs, mesh_crs, output_crs : str
        The case CRS, the CRS meshed in, and the CRS of the written nodes.
    shoreline_sets : dict of str to ShorelineSetReport
        By set name.
    stitch : StitchReport
        Joining the sets at the region seams.
    domain : DomainReport
        The domain: land repaired, islands, boundary vertices per segment name.
    size_field : SizeFieldReport
    mesh : MeshReport
    cleanup, depth, quality : report or None
        :class:`~coastmesh.meshing.cleanup.fixes.CleanupReport`,
        :class:`~coastmesh.depth.nodes.DepthReport`,
        :class:`~coastmesh.meshing.quality.QualityReport`, where the case asks.
    parts : PartsReport or None
        How the water was cut into parts and what each cost
        (:class:`~coastmesh.meshing.parts.report.PartsReport`).
    channels : PeelReport or None
        The dead-end channels one element wide closed after meshing
        (:func:`~coastmesh.meshing.cleanup.peel.peel_channels`).
    conform : ConformReport or None
        The elements brought to their sizes where a size term asks it (the
        field term, ``[[mesh_size.fields]]``:
        :func:`~coastmesh.meshing.cleanup.conform.conform_sizes`).
    time_step : ThrottleReport or None
        The elements that throttled the time step, relieved
        (:func:`~coastmesh.meshing.relieve_time_step`); with ``[bathymetry]``
        and ``[cleanup] time_step``.
    seconds : dict of str to float
        Wall time of each stage.
    peak_memory_mb : float or None
        Peak resident memory of the process so far; None where the platform
        does not tell (Windows).
    files : tuple of str
        The files written, relative to the output folder; empty before
        :meth:`CaseResult.write`.
    model_tests : dict of str to float
        The time step, s, of each smoke test written (``[output] model_test``),
        by model: ADCIRC at the mesh's own, SCHISM at a step of its own rules
        (:func:`~coastmesh.io.meshes.model_tests.model_test_step`); empty before
        :meth:`CaseResult.write`.
    """

    case: str
    source: str | None
    coastmesh_version: str
    crs: str
    mesh_crs: str
    output_crs: str
    shoreline_sets: dict[str, ShorelineSetReport]
    stitch: StitchReport
    domain: DomainReport
    size_field: SizeFieldReport
    mesh: MeshReport
    cleanup: CleanupReport | None
    depth: DepthReport | None
    quality: QualityReport | None
    seconds: dict[str, float]
    peak_memory_mb: float | None
    files: tuple[str, ...] = ()
    time_step: ThrottleReport | None = None
    parts: PartsReport | None = None
    channels: PeelReport | None = None
    conform: ConformReport | None = None
    model_tests: dict[str, float] = field(default_factory=dict)

    @classmethod
    def of(
        cls,
        run: FinishedRun,
        seconds: Mapping[str, float],
        files: tuple[str, ...] = (),
    ) -> CaseReport:
        """Read the report of a finished run: every stage's part, as it left it."""
        from coastmesh.version import __version__

        config, domain, mesh = run.config, run.domain, run.mesh
        return cls(
            case=config.name,
            source=None if config.source is None else str(config.source),
            coastmesh_version=__version__,
            crs=run.shorelines.crs.to_string(),
            mesh_crs=_crs_text(domain.mesh_crs),
            output_crs=domain.output_crs.to_string(),
            shoreline_sets=dict(run.shorelines.reports),
            stitch=domain.stitch,
            domain=domain.report,
            size_field=run.size.report,
            mesh=MeshReport.of(mesh.mesh),
            cleanup=mesh.parts.cleanup,
            depth=None if run.depth is None else run.depth.report,
            quality=run.quality,
            seconds=dict(seconds),
            peak_memory_mb=peak_memory_mb(),
            files=files,
            time_step=None if run.depth is None else run.depth.relief,
            parts=mesh.parts,
            channels=mesh.channels,
            conform=mesh.conform,
        )

    def summary(self) -> str:
        """Return the report as a few lines of text (``summary.txt``)."""
        lines = [
            f"coastmesh case {self.case} ({self.source or 'built in Python'})",
            f"mesh: {self.mesh.nodes:,} nodes, {self.mesh.triangles:,} triangles",
            "boundary edges by name (id): "
            + ", ".join(f"{k} {v}" for k, v in self.mesh.boundary_edges.items()),
            f"surface id: {self.mesh.surface_id}",
            "shoreline sets:",
        ]
        lines += [f"  {n}: {r.summary()}" for n, r in self.shoreline_sets.items()]
        closings = {n: r.closing for n, r in self.shoreline_sets.items() if r.closing}
        if closings:
            lines.append(
                "islands the closing changed by more than 10 % of their area: "
                + ", ".join(
                    f"{n} {len(c.changed)} of {c.islands}" for n, c in closings.items()
                )
                + " (report.json: shoreline_sets.<set>.closing.changed)"
            )
        d = self.domain
        lines.append(
            f"domain: {d.holes} islands ({d.holes_dropped} dropped), "
            f"{d.land_repaired} land polygons repaired, {d.land_overlaps_merged} "
            "overlaps merged"
        )
        lines.append(f"size field: {self.size_field.summary()}")
        if self.parts is not None and self.parts.parts > 1:
            lines.append(f"parts: {self.parts.summary()}")
        for name in ("cleanup", "channels", "conform", "time_step", "depth"):
            part = getattr(self, name)
            if part is not None:
                lines.append(f"{name}: {part.summary()}")
        lines.append(
            "time (s): " + ", ".join(f"{k} {v}" for k, v in self.seconds.items())
        )
        lines.append(
            "peak memory: not measured on this platform"
            if self.peak_memory_mb is None
            else f"peak memory: {self.peak_memory_mb:,.0f} MB"
        )
        if self.model_tests:
            lines.append(
                "model tests, time step (s): "
                + ", ".join(f"{m} {dt:g}" for m, dt in self.model_tests.items())
                + " (SCHISM at a step of its own rules: model_test/schism/README.txt)"
                * ("schism" in self.model_tests)
            )
        if self.files:
            lines.append("files: " + ", ".join(self.files))
        return "\n".join(lines)


def _crs_text(crs: CRS) -> str:
    """Return a CRS as its code (``EPSG:32630``), or as WKT where it has none."""
    return crs.to_wkt() if crs.to_epsg() is None else crs.to_string()


def peak_memory_mb() -> float | None:
    """Return the peak resident memory of this process, MB; None if unknown.

    The ``resource`` module is Unix-only: on Windows the peak is not measured.
    """
    try:
        import resource
    except ImportError:
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # Linux reports KiB, macOS bytes
    return round(peak / (1024 * 1024 if sys.platform == "darwin" else 1024), 1)
