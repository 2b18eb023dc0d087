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
:func:`conform_sizes`     nodes moved so elements take the sizes (a zone)
:func:`mesh_quality`      angles, radius ratios, edge sizes, valence, corners
:func:`boundary_angles`   the domain's interior angle at each boundary node
========================  =====================================================

:func:`element_time_steps` gives each triangle's stable time step and, at a model
time step, its Courant number. Depth at the nodes is
:func:`coastmesh.depth.depth_at_nodes`.

The types they take and return (:class:`~coastmesh.types.Domain`,
:class:`~coastmesh.types.SizeGrid`, :class:`~coastmesh.types.Mesh`) live in
:mod:`coastmesh.types`.

Subpackages, by what they do (each may use those after it):

* ``engine`` (:func:`generate_mesh`, :func:`mesh_in_parts`): the entry points;
* :mod:`~coastmesh.meshing.parts`: the water cut into parts, each meshed alone
  as a task on any executor, the parts merged by their shared nodes;
* :mod:`~coastmesh.meshing.gmsh`: one Gmsh session, its options and size
  view, the boundary nodes made once, boundary resampling;
* :mod:`~coastmesh.meshing.cleanup`: fixes, smoothing and the time-step
  relief, never for the worse;
* :mod:`~coastmesh.meshing.quality`: triangles and edges measured on the
  Earth, the quality report, time steps and sharp corners;

The meshing CRS and sizes in its map units are in
:mod:`coastmesh.geometry.projection` (:func:`default_mesh_crs` and
:func:`sample_size` are here too).

They compute and never write. Gmsh is imported only when :func:`generate_mesh`
runs.
"""

from __future__ import annotations

from coastmesh.geometry.projection import default_mesh_crs, sample_size
from coastmesh.meshing.cleanup import (
    THROTTLE_RATIO,
    CleanupOptions,
    CleanupReport,
    ConformReport,
    SmoothingReport,
    ThrottleReport,
    clean_mesh,
    conform_sizes,
    relieve_time_step,
    smooth_mesh,
    smooth_points,
)
from coastmesh.meshing.engine import PartsWarning, generate_mesh, mesh_in_parts
from coastmesh.meshing.gmsh import SmallIslandWarning, resample_rings, resample_segment
from coastmesh.meshing.parts import PartsReport
from coastmesh.meshing.quality import (
    CornerStats,
    CourantStats,
    QualityReport,
    SharpCorner,
    TimeStepStats,
    boundary_angles,
    edge_quality,
    element_time_steps,
    mesh_quality,
    triangle_quality,
)

__all__ = [
    "THROTTLE_RATIO",
    "CleanupOptions",
    "CleanupReport",
    "ConformReport",
    "CornerStats",
    "CourantStats",
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
    "conform_sizes",
    "default_mesh_crs",
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
