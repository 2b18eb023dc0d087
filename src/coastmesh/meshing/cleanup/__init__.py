"""Cleanup and relief: what ocean models choke on, fixed without losing quality.

``fixes`` (all-boundary triangles, crowded nodes and slivers, by flips and
splits), ``smoothing`` (interior nodes moved, the worst angles never lowered),
``time_step_relief`` (edges collapsed where elements throttle an explicit
model's time step), ``conform`` (nodes moved so that elements take the size
field's sizes, where a size term asks), ``report`` (what the cleanup did),
``editable`` (a mesh to edit in place), ``planar`` (triangle measures in a
plane, for the local decisions) and ``aside`` (work on a side thread, or at
once).
"""

from __future__ import annotations

from coastmesh.meshing.cleanup.conform import ConformReport, conform_sizes
from coastmesh.meshing.cleanup.fixes import clean_mesh
from coastmesh.meshing.cleanup.report import CleanupOptions, CleanupReport
from coastmesh.meshing.cleanup.smoothing import (
    SmoothingReport,
    smooth_mesh,
    smooth_points,
)
from coastmesh.meshing.cleanup.time_step_relief import (
    THROTTLE_RATIO,
    ThrottleReport,
    relieve_time_step,
)

__all__ = [
    "THROTTLE_RATIO",
    "CleanupOptions",
    "CleanupReport",
    "ConformReport",
    "SmoothingReport",
    "ThrottleReport",
    "clean_mesh",
    "conform_sizes",
    "relieve_time_step",
    "smooth_mesh",
    "smooth_points",
]
