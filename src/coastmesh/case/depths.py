"""Depth at the mesh nodes, from ``[bathymetry]``, and the time-step relief.

The sources are read (and PCA-simplified, if asked) once, over the mesh's box;
after the relief the nodes are sampled again from the same sources.
"""

from __future__ import annotations

import logging
from typing import Any

from coastmesh.case.config import CaseConfig
from coastmesh.case.sources import read_sources
from coastmesh.depth import depth_at_nodes
from coastmesh.depth.nodes import node_sources
from coastmesh.meshing import relieve_time_step
from coastmesh.types import Mesh, Progress

__all__ = ["depth_raster", "node_depths", "relieve"]

logger = logging.getLogger(__name__)


def relieve(
    config: CaseConfig, mesh: Mesh, raster: Any, cleanup: Any, progress: Progress
) -> tuple:
    """Relieve the elements that throttle the time step; depth at moved nodes.

    The angles may not fall below Gmsh's own mesh's, the cleanup's bar.
    """
    courant = config.size.courant
    velocity = 0.0 if courant is None else courant.velocity
    keep = (cleanup.min_angle_before, cleanup.min_angle_p1_before)
    relieved, report = relieve_time_step(mesh, velocity=velocity, keep_angles=keep)
    logger.info("time step: %s", report.summary())
    if not report.accepted:
        return mesh, report, None
    # the merged nodes took their pair's mean depth: read the raster there
    relieved, depth = node_depths(config, relieved, raster, progress)
    return relieved, report, depth


def depth_raster(config: CaseConfig, mesh: Mesh, progress: Progress) -> Any:
    """Return the ``[bathymetry]`` sources around ``mesh`` as a DepthSources stack.

    Each raster is read only over the mesh's box (widened by its blend), and
    PCA-simplified there if asked.
    """
    b = config.bathymetry
    sources = read_sources(b.stack, mesh.points, mesh.crs, progress)
    if b.window is not None:
        from coastmesh.depth import DepthSource, DepthSources
        from coastmesh.pca import simplify_raster

        sources = DepthSources(
            [
                DepthSource(
                    s.raster.copy(
                        data=simplify_raster(s.raster.values, b.window, b.modes)
                    ),
                    s.positive,
                    s.blend,
                    s.name,
                )
                for s in sources.sources
            ]
        )
    return sources


def node_depths(
    config: CaseConfig, mesh: Mesh, raster: Any, progress: Progress
) -> tuple[Mesh, Any]:
    """Return ``mesh`` with ``depth`` at its nodes from ``raster``, and the report."""
    b = config.bathymetry
    depth, report = depth_at_nodes(
        mesh,
        raster,
        positive=b.positive,
        method=b.method,
        min_depth=b.min_depth,
        max_slope=b.max_slope,
        outside=b.outside,
        land=b.land,
        land_distance=b.land_distance,
    )
    progress(2, 2)
    logger.info("%s", report.summary())
    source = node_sources(mesh, raster) if len(raster) > 1 else None
    extra = {} if source is None else {"depth_source": source}
    return mesh.with_point_data(depth=depth, **extra), report
