"""Meshing: domains, size grids and Gmsh meshes.

========================  =====================================================
:func:`generate_mesh`     Domain + SizeGrid -> Mesh, with Gmsh
:func:`mesh_in_parts`     the same, in parts, with a :class:`PartsReport`
:func:`default_mesh_crs`  the conformal CRS meshes are made in by default
:func:`sample_size`       a size grid interpolated as Gmsh does
:func:`resample_segment`  a polyline resampled to a target size
:func:`clean_mesh`        all-boundary triangles, valence, slivers fixed
:func:`smooth_mesh`       interior nodes moved, minimum angle never lowered
:func:`relieve_time_step` edges of time-step-throttling elements collapsed
:func:`depth_at_nodes`    a bathymetry raster on the nodes
:func:`mesh_quality`      angles, radius ratios, edge sizes, valence, corners
:func:`boundary_angles`   the domain's interior angle at each boundary node
========================  =====================================================

:func:`element_time_steps` gives each triangle's stable time step and, at a model
time step, its Courant number.

The types they take and return (:class:`~coastmesh.types.Domain`,
:class:`~coastmesh.types.SizeGrid`, :class:`~coastmesh.types.Mesh`) live in
:mod:`coastmesh.types`.

Modules: ``engine`` (Gmsh), ``session`` (one Gmsh session and its options),
``curves`` (the boundary nodes, made once), ``parts``, ``junctions`` and
``surfaces`` (the water cut into parts), ``tasks`` (each part meshed alone,
on any executor, and the parts merged by their shared nodes),
``projection`` (the meshing CRS and sizes in it), ``boundary`` (resampling),
``topology`` (boundary rings and strings),
``cleanup``, ``smoothing``, ``throttle``, ``depth``, ``quality``,
``quality_report``, ``measure``, ``timestep`` and ``corners`` (measure, never
write).

Gmsh is imported only when :func:`generate_mesh` runs.
"""

from __future__ import annotations

from coastmesh.meshing.boundary import (
    SmallIslandWarning,
    resample_rings,
    resample_segment,
)
from coastmesh.meshing.cleanup import CleanupOptions, CleanupReport, clean_mesh
from coastmesh.meshing.corners import CornerStats, SharpCorner, boundary_angles
from coastmesh.meshing.depth import DEPTH_METHODS, DepthReport, depth_at_nodes
from coastmesh.meshing.engine import PartsWarning, generate_mesh, mesh_in_parts
from coastmesh.meshing.parts_report import PartsReport
from coastmesh.meshing.projection import default_mesh_crs, sample_size
from coastmesh.meshing.quality import edge_quality, mesh_quality, triangle_quality
from coastmesh.meshing.quality_report import QualityReport
from coastmesh.meshing.smoothing import SmoothingReport, smooth_mesh, smooth_points
from coastmesh.meshing.throttle import (
    THROTTLE_RATIO,
    ThrottleReport,
    relieve_time_step,
)
from coastmesh.meshing.timestep import CourantStats, TimeStepStats, element_time_steps

__all__ = [
    "DEPTH_METHODS",
    "THROTTLE_RATIO",
    "CleanupOptions",
    "CleanupReport",
    "CornerStats",
    "CourantStats",
    "DepthReport",
    "PartsReport",
    "PartsWarning",
    "QualityReport",
    "SharpCorner",
    "SmallIslandWarning",
    "SmoothingReport",
    "ThrottleReport",
    "TimeStepStats",
    "boundary_angles",
    "clean_mesh",
    "default_mesh_crs",
    "depth_at_nodes",
    "edge_quality",
    "element_time_steps",
    "generate_mesh",
    "mesh_in_parts",
    "mesh_quality",
    "relieve_time_step",
    "resample_rings",
    "resample_segment",
    "sample_size",
    "smooth_mesh",
    "smooth_points",
    "triangle_quality",
]
