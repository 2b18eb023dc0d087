"""The Gmsh session: options, the size field as a background view, the nodes.

``model`` (one Gmsh model: its options and the size grid as a background view;
the only module that imports gmsh), ``boundary_nodes`` (the boundary meshed once
by Gmsh's 1-D mesher), ``resample`` (boundary polylines resampled to the local
size first) and ``sphere_sizes`` (a world size field on a longitude/latitude
grid, handed to a mesh in the stereographic plane).
"""

from __future__ import annotations

from coastmesh.meshing.gmsh.model import ALGORITHMS, gmsh_session, release_memory
from coastmesh.meshing.gmsh.resample import (
    SmallIslandWarning,
    resample_rings,
    resample_segment,
)
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid

__all__ = [
    "ALGORITHMS",
    "SmallIslandWarning",
    "SphereSizeGrid",
    "gmsh_session",
    "release_memory",
    "resample_rings",
    "resample_segment",
]
