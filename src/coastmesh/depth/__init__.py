"""Depth: bathymetry rasters, one or several, sampled on grids and mesh nodes.

=================================  ===========================================
:class:`DepthSources`              several rasters in priority order, blended
                                   across their seams; each node records its
                                   source
:class:`DepthSource`               one raster of such a stack
:func:`depth_on_grid`              a raster's (or a stack's) depth on the
                                   nodes of a regular grid
:func:`raster_on_grid`             any raster's values on the nodes of a
                                   regular grid, bilinear or nearest
:func:`raster_at`                  the same at any points
:func:`depth_at_nodes`             depth on the nodes of a mesh: coverage,
                                   land, the depth floor, the slope limit
:func:`raster_grid`                a raster's axes (ascending) and values
=================================  ===========================================

Every depth here is in metres, positive down; each raster says its own sign
(``"up"`` for elevations such as GEBCO and ETOPO). Files are read in
:mod:`coastmesh.io` (:func:`coastmesh.io.read_raster`, and only the window a
mesh needs with :func:`coastmesh.io.rasters.raster_window.read_raster_around`); a case
reads its ``[bathymetry]`` and ``[mesh_size.bathymetry]`` rasters in its depth
stage.
"""

from __future__ import annotations

from coastmesh.depth.grid import READINGS, depth_on_grid, raster_at, raster_on_grid
from coastmesh.depth.nodes import (
    DEPTH_METHODS,
    LAND_TREATMENTS,
    OUTSIDE_RULES,
    DepthReport,
    depth_at_nodes,
    node_sources,
)
from coastmesh.depth.raster import raster_crs, raster_grid
from coastmesh.depth.sources import DepthSource, DepthSources, SourceSample

__all__ = [
    "DEPTH_METHODS",
    "LAND_TREATMENTS",
    "OUTSIDE_RULES",
    "READINGS",
    "DepthReport",
    "DepthSource",
    "DepthSources",
    "SourceSample",
    "depth_at_nodes",
    "depth_on_grid",
    "node_sources",
    "raster_at",
    "raster_crs",
    "raster_grid",
    "raster_on_grid",
]
