"""Measurement and quality: triangles and edges measured on the Earth.

``measure`` (the kernels: sides, angles, radii and areas on the ellipsoid),
``mesh_quality`` (the quality report of a mesh), ``report`` (what it holds),
``time_step`` (each element's stable time step and Courant number),
``corners`` (the sharp corners the boundary forces) and ``sphere`` (a global
lon/lat mesh checked on the sphere: angles, orientation, overlaps).
"""

from __future__ import annotations

from coastmesh.meshing.quality.corners import CornerStats, SharpCorner, boundary_angles
from coastmesh.meshing.quality.mesh_quality import (
    edge_quality,
    mesh_quality,
    triangle_quality,
)
from coastmesh.meshing.quality.report import QualityReport
from coastmesh.meshing.quality.sphere import SphereQuality, sphere_quality
from coastmesh.meshing.quality.time_step import (
    CourantStats,
    TimeStepStats,
    element_time_steps,
)

__all__ = [
    "CornerStats",
    "CourantStats",
    "QualityReport",
    "SharpCorner",
    "SphereQuality",
    "TimeStepStats",
    "boundary_angles",
    "edge_quality",
    "element_time_steps",
    "mesh_quality",
    "sphere_quality",
    "triangle_quality",
]
