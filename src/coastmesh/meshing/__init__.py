"""Meshing: domains, size grids and Gmsh meshes.

========================  =====================================================
:class:`Domain`           polygon + tagged boundary segments + CRS
:class:`SizeGrid`         target edge length (metres) on a regular grid
:class:`Mesh`             triangles, tagged boundary edges, CRS
:func:`generate_mesh`     Domain + SizeGrid -> Mesh, with Gmsh
:func:`resample_segment`  a polyline resampled to a target size
========================  =====================================================

Gmsh is imported only when :func:`generate_mesh` runs.
"""

from __future__ import annotations

from coastmesh.meshing.boundary import (
    SmallIslandWarning,
    resample_rings,
    resample_segment,
)
from coastmesh.meshing.engine import default_mesh_crs, generate_mesh, sample_size
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

__all__ = [
    "BoundarySegment",
    "Domain",
    "Mesh",
    "SizeGrid",
    "SmallIslandWarning",
    "default_mesh_crs",
    "generate_mesh",
    "resample_rings",
    "resample_segment",
    "sample_size",
]
