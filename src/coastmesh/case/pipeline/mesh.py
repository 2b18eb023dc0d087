"""The meshing stage: Gmsh meshes the domain to the size field, in parts."""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import shapely

from coastmesh.case.config import CaseConfig
from coastmesh.case.pipeline.domain import site_area
from coastmesh.case.pipeline.farms import with_site_sizes
from coastmesh.case.pipeline.state import CaseRun, MeshState, RunContext, missing
from coastmesh.case.pipeline.structures import check_structure_sizes
from coastmesh.meshing import CleanupOptions, mesh_in_parts
from coastmesh.meshing.cleanup.peel import open_short_runs, peel_channels
from coastmesh.meshing.gmsh import release_memory

__all__ = ["channel_stage", "cleanup_options", "mesh_stage"]

logger = logging.getLogger(__name__)


def mesh_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Mesh the domain (``[mesh]``), cleaned part by part (``[cleanup]``)."""
    config, state = run.config, run.domain or missing("domain")
    release_memory()  # what the shoreline sets and slots freed, before the workers
    size, inner = run.strategy.size_grid(run), None
    check_structure_sizes(state, size, config.label)
    if run.site:
        size = with_site_sizes(size, run.site, config.size.rate)
        inner = run.site.inner()
    with ctx.timed("meshing") as progress:
        mesh, parts = mesh_in_parts(
            state.domain,
            size,
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
    return replace(run, mesh=MeshState(mesh, parts))


def channel_stage(run: CaseRun, ctx: RunContext) -> CaseRun:
    """Close the dead-end channels the mesh left one element wide.

    With the channel term on and ``narrow = "close"`` (the default): what the
    closing before meshing could not see on its grid, peeled back from the
    channel's end (:func:`~coastmesh.meshing.cleanup.peel.peel_channels`);
    never inside ``[[sites]]``. Then, whatever ``narrow`` says, a run of coast
    between two open boundaries with fewer than three edges becomes part of
    the open boundary (:func:`~coastmesh.meshing.cleanup.peel.open_short_runs`),
    as Telemac would make it.
    """
    config, state = run.config, run.mesh or missing("mesh")
    channels = config.size.channels
    if channels.enabled and channels.narrow == "close":
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


def cleanup_options(config: CaseConfig) -> CleanupOptions | None:
    """``[cleanup]`` as the mesher takes it; None when it is off."""
    c = config.cleanup
    if not c.enabled:
        return None
    return CleanupOptions(c.boundary_triangles, c.max_valence, c.min_angle, c.smooth)
