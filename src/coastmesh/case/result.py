"""What a case makes: :class:`CaseResult`, in memory, and its :class:`CaseReport`."""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.inputs import ShorelineSetReport
from coastmesh.geometry import DomainReport, OpenBoundary, StitchReport
from coastmesh.meshing import CleanupReport, DepthReport, QualityReport
from coastmesh.sizing import SizeFieldReport
from coastmesh.types import Domain, Mesh, Report, SizeGrid, StageFactory

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["CaseReport", "CaseResult", "MeshReport"]


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
    """

    nodes: int
    triangles: int
    boundary_edges: dict[str, int]
    surface_id: int

    @classmethod
    def of(cls, mesh: Mesh) -> MeshReport:
        """Count the nodes, triangles and boundary edges by id of a mesh."""
        ids, counts = np.unique(mesh.boundary_ids, return_counts=True)
        edges = {
            f"{mesh.boundary_names.get(int(i), '?')} ({int(i)})": int(c)
            for i, c in zip(ids, counts, strict=True)
        }
        return cls(len(mesh.points), len(mesh.triangles), edges, mesh.surface_id)

    def summary(self) -> str:
        """Return a one-line summary."""
        ids = ", ".join(f"{k} {v}" for k, v in self.boundary_edges.items())
        return (
            f"{self.nodes:,} nodes, {self.triangles:,} triangles, boundary edges "
            f"by id: {ids}"
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
        :class:`~coastmesh.meshing.cleanup.CleanupReport`,
        :class:`~coastmesh.meshing.depth.DepthReport`,
        :class:`~coastmesh.meshing.quality.QualityReport`, where the case asks.
    seconds : dict of str to float
        Wall time of each stage.
    peak_memory_mb : float or None
        Peak resident memory of the process so far; None where the platform
        does not tell (Windows).
    files : tuple of str
        The files written, relative to the output folder; empty before
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
        d = self.domain
        lines.append(
            f"domain: {d.holes} islands ({d.holes_dropped} dropped), "
            f"{d.land_repaired} land polygons repaired, {d.land_overlaps_merged} "
            "overlaps merged"
        )
        lines.append(f"size field: {self.size_field.summary()}")
        for name in ("cleanup", "depth"):
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
        if self.files:
            lines.append("files: " + ", ".join(self.files))
        return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class CaseResult:
    """A case built in memory by :func:`coastmesh.build_case`.

    Attributes
    ----------
    config : CaseConfig
        The case.
    mesh : Mesh
        Points in the output CRS, triangles, boundary edges with their ids,
        names and kinds, and node data: ``size`` (the target size, metres) and,
        with ``[bathymetry]``, ``depth`` (metres, positive down).
    domain : Domain
        The domain meshed, in the case CRS.
    size : xarray.DataArray
        The size field, metres, on a grid in the mesh CRS (:attr:`size_grid`
        as a :class:`~coastmesh.types.SizeGrid`).
    report : CaseReport
        Every stage's report (shoreline sets, stitching, domain, size, mesh,
        cleanup, depth, quality, times).
    regions : tuple of (name, id, geometry or None)
        Where each shoreline set is used, in the case CRS.
    open_boundaries : tuple of OpenBoundary
        The open boundaries as drawn, before trimming at the coast.
    crs : pyproj.CRS
        The case CRS.
    seconds : float
        Wall time, building (and, after :func:`coastmesh.run_case`, writing).
    output : pathlib.Path or None
        The folder written by :func:`coastmesh.run_case`; None in memory.
    files : tuple of str
        The files written there, relative to it.
    """

    config: CaseConfig
    mesh: Mesh
    domain: Domain
    size: xr.DataArray
    report: CaseReport
    regions: tuple[tuple[str, int, shapely.Geometry | None], ...]
    open_boundaries: tuple[OpenBoundary, ...]
    crs: CRS
    seconds: float
    output: Path | None = None
    files: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        """The case's name."""
        return self.config.name

    @property
    def nodes(self) -> int:
        """Number of mesh nodes."""
        return len(self.mesh.points)

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return len(self.mesh.triangles)

    @property
    def boundary_edges(self) -> dict[str, int]:
        """Boundary edges by ``"name (id)"``."""
        return self.report.mesh.boundary_edges

    @property
    def size_grid(self) -> SizeGrid:
        """The size field as a :class:`~coastmesh.types.SizeGrid` (mesh CRS)."""
        return SizeGrid.from_dataarray(self.size)

    def to_dict(self) -> dict[str, Any]:
        """Return the report as data, with where it was written and the time."""
        return self.report.to_dict() | {
            "output": None if self.output is None else str(self.output),
            "seconds_total": self.seconds,
        }

    def summary(self) -> str:
        """Return a one-line summary."""
        where = (
            ""
            if self.output is None
            else f"; {len(self.files)} files in {self.output}/"
        )
        return (
            f"{self.name}: {self.report.mesh.summary()}{where} in {self.seconds:.1f} s"
        )

    def write(
        self,
        folder: str | os.PathLike[str],
        *,
        formats: tuple[str, ...] | list[str] | None = None,
        overwrite: bool = False,
        stage: StageFactory | None = None,
    ) -> CaseResult:
        """Write the mesh formats, domain, size field, reports and figures.

        This is what ``coastmesh run`` writes: everything goes into
        ``<folder>.partial-XXXX/``, renamed to ``folder`` at the end, so a
        failure leaves nothing.

        Parameters
        ----------
        folder : str or path-like
            The output folder; it must not exist or be empty, unless
            ``overwrite``.
        formats : sequence of str, optional
            Mesh formats by name (:func:`coastmesh.io.mesh_formats`); default
            the case's ``[output] formats``.
        overwrite : bool, default False
            Whether a non-empty ``folder`` may be replaced.
        stage : callable, optional
            ``stage(label)`` returns a context manager (for a progress bar).

        Returns
        -------
        CaseResult
            This result with ``output``, ``files`` and ``report.files`` set.

        Raises
        ------
        ConfigError
            If a format is unknown.
        OutputExistsError
            If ``folder`` exists, is not empty, and ``overwrite`` is false.
        """
        from coastmesh.case.outputs import write_case

        outputs = self.config.outputs
        if formats is not None:
            checked = dataclasses.replace(
                self.config, outputs=dataclasses.replace(outputs, formats=formats)
            )
            outputs = checked.outputs
        files = write_case(
            self, Path(folder), outputs, overwrite=overwrite, stage=stage
        )
        return dataclasses.replace(
            self,
            output=Path(folder),
            files=tuple(files),
            report=dataclasses.replace(self.report, files=tuple(files)),
        )
