"""The meshing stage: Gmsh meshes the domain to the size field, in parts."""

from __future__ import annotations

import logging
import os
from dataclasses import replace

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.domain import site_area
from coastmesh.case.pipeline.farms import with_site_sizes
from coastmesh.case.pipeline.state import MeshedRun, MeshState, RunContext, SizedRun
from coastmesh.case.pipeline.structures import check_structure_sizes
from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import reproject_points
from coastmesh.geometry.grids import interpolate_bilinear
from coastmesh.meshing import CleanupOptions, mesh_in_parts
from coastmesh.meshing.cleanup.conform import conform_sizes
from coastmesh.meshing.cleanup.peel import open_short_runs, peel_channels
from coastmesh.meshing.gmsh import release_memory
from coastmesh.sizing.grid import Grid
from coastmesh.types import Mesh, SizeGrid

__all__ = [
    "channel_stage",
    "check_memory",
    "cleanup_options",
    "conform_stage",
    "expected_triangles",
    "mesh_stage",
]

logger = logging.getLogger(__name__)


#: Peak memory a mesh takes per triangle, bytes, over :data:`BASE_MEMORY`:
#: ``world.toml`` (1.1 M triangles) peaked at 2.0 GB in one part and 1.35 GB
#: in parts, the Python process itself about 0.4 GB of it.
MEMORY_PER_TRIANGLE = 1500
BASE_MEMORY = 500e6


def expected_triangles(run: SizedRun) -> float:
    """Return the triangles the size field asks for over the sea.

    ``4 / (sqrt(3) h^2)`` per unit area (an equilateral mesh of size ``h``),
    summed over the size grid's sea nodes, each standing for its cell's area
    on the Earth.
    """
    size = run.size
    grid, h = size.grid, np.asarray(size.field.values, dtype=np.float64)
    areas = grid.areas
    if areas is None:  # a plane grid: a cell, shrunk by the map's scale
        areas = (grid.cell / grid.scale) ** 2
    sea = grid.sea & np.isfinite(h) & (h > 0)
    return float(4.0 / np.sqrt(3.0) * (areas[sea] / h[sea] ** 2).sum())


def check_memory(run: SizedRun) -> None:
    """Raise before meshing if the mesh asked for will not fit in this machine.

    The need is :data:`BASE_MEMORY` and :data:`MEMORY_PER_TRIANGLE` per
    expected triangle (:func:`expected_triangles`); the machine's is its
    physical memory.
    """
    triangles = expected_triangles(run)
    need = BASE_MEMORY + MEMORY_PER_TRIANGLE * triangles
    have = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    logger.info(
        "expected %.0f triangles, about %.1f GB of %.1f GB",
        triangles,
        need / 1e9,
        have / 1e9,
    )
    if need > have:
        raise ConfigError(
            f"{run.config.label}: the size field asks for about {triangles:,.0f} "
            f"triangles, which need about {need / 1e9:.1f} GB to mesh; this "
            f"machine has {have / 1e9:.1f} GB. Raise h_min or h_max in "
            "[mesh_size] (or narrow the gradations' reach), or run on a machine "
            "with more memory"
        )


def mesh_stage(run: SizedRun, ctx: RunContext) -> MeshedRun:
    """Mesh the domain (``[mesh]``), cleaned part by part (``[cleanup]``).

    First checks that the mesh asked for fits in memory (:func:`check_memory`).
    """
    config, state = run.config, run.domain
    check_memory(run)
    release_memory()  # what the shoreline sets and slots freed, before the workers
    size, inner = run.strategy.size_grid(run), None
    check_structure_sizes(state, size, config.label)
    if run.site:
        assert isinstance(size, SizeGrid)  # a site is in a regional case (checked)
        size = with_site_sizes(size, run.site, config.size.rate, config.label)
        inner = run.site.inner()
    with ctx.timed("meshing") as progress:
        mesh, parts = mesh_in_parts(
            state.domain,
            # a SphereSizeGrid too: the meshing layer types the size field as
            # a SizeGrid (issue 49: one protocol for both is still to come)
            size,  # type: ignore[arg-type]
            mesh_crs=state.mesh_crs,
            output_crs=state.output_crs,
            seed=config.mesh.seed,
            algorithm=config.mesh.algorithm,
            optimize=config.mesh.optimize,
            parts=run.strategy.parts(config),
            threads=ctx.threads,
            runner=ctx.runner,
            cleanup=cleanup_options(config),
            progress=progress,
            inner=inner,
        )
    if parts.parts > 1:
        logger.info("parts: %s", parts.summary())
    return run.with_mesh(MeshState(mesh, parts))


def channel_stage(run: MeshedRun, ctx: RunContext) -> MeshedRun:
    """Close the dead-end channels the mesh left one element wide.

    With the channel term on and ``narrow = "close"`` (the default): what the
    closing before meshing could not see on its grid, peeled back from the
    channel's end (:func:`~coastmesh.meshing.cleanup.peel.peel_channels`);
    never inside ``[[sites]]``. Then, whatever ``narrow`` says, a run of coast
    between two open boundaries with fewer than three edges becomes part of
    the open boundary (:func:`~coastmesh.meshing.cleanup.peel.open_short_runs`),
    as Telemac would make it.
    """
    config, state = run.config, run.mesh
    channels = config.size.channels
    if (
        channels is not None
        and channels.enabled is not False
        and channels.narrow == "close"
    ):
        with ctx.timed("channels one element wide"):
            mesh = state.mesh
            keep = None
            sites = site_area(config, mesh.crs) if mesh.crs is not None else None
            if sites is not None:
                centres = mesh.points[mesh.triangles].mean(axis=1)
                keep = shapely.contains_xy(sites, centres[:, 0], centres[:, 1])
            if (mesh.regions != mesh.surface_id).any():  # farms, footprints
                keep = (mesh.regions != mesh.surface_id) | (
                    False if keep is None else keep
                )
            if mesh.lines:  # the triangles at a line's nodes stay
                on_line = np.zeros(len(mesh.points), dtype=bool)
                on_line[mesh.line_edges()[0].ravel()] = True
                keep = on_line[mesh.triangles].any(axis=1) | (
                    False if keep is None else keep
                )
            peeled, report = peel_channels(mesh, keep)
        if report.removed:
            logger.info("channels: %s", report.summary())
        state = replace(state, mesh=peeled, channels=report)
    opened, relabelled = open_short_runs(state.mesh)
    if relabelled:
        logger.info("boundary: %d edges of short coast runs made open", relabelled)
        state = replace(state, mesh=opened)
    return replace(run, mesh=state)


def conform_stage(run: MeshedRun, ctx: RunContext) -> MeshedRun:
    """Bring the elements to their sizes where a size term asks (the field term).

    The mesh's nodes where every corner of their size-grid cell is in the
    field's :attr:`~coastmesh.case.pipeline.state.SizeState.conform` are
    relaxed (:func:`~coastmesh.meshing.cleanup.conform.conform_sizes`); with
    ``[cleanup] enabled = false``, or where no term asks, nothing changes.
    """
    conform = run.size.conform
    if conform is None or not conform.any() or not run.config.cleanup.enabled:
        return run
    state = run.mesh
    with ctx.timed("sizes held"):
        zone = grid_flags(run.size.grid, conform, state.mesh)
        mesh, report = conform_sizes(state.mesh, zone)
    logger.info("sizes held: %s", report.summary())
    return replace(run, mesh=replace(state, mesh=mesh, conform=report))


def grid_flags(grid: Grid, flags: NDArray[np.bool_], mesh: Mesh) -> NDArray[np.bool_]:
    """Return, for each mesh node, whether every corner of its grid cell is flagged.

    Nodes outside the grid take its nearest edge cell. The mesh's points are
    moved into the grid's CRS first.
    """
    points = np.asarray(mesh.points, dtype=np.float64)
    if mesh.crs is not None and not CRS.from_user_input(mesh.crs).equals(grid.crs):
        points = reproject_points(points, mesh.crs, grid.crs)
    share = interpolate_bilinear(
        grid.x, grid.y, flags.astype(np.float64), points[:, 0], points[:, 1], clamp=True
    )
    # bilinear weights sum to 1: 1 only where every corner with weight is set
    return np.asarray(share >= 1.0 - 1e-9)


def cleanup_options(config: CaseConfig) -> CleanupOptions | None:
    """``[cleanup]`` as the mesher takes it; None when it is off."""
    c = config.cleanup
    if not c.enabled:
        return None
    return CleanupOptions(c.boundary_triangles, c.max_valence, c.min_angle, c.smooth)
