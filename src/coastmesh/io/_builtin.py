"""The built-in mesh formats, registered in this order when the registry is used.

===========  ========================  ====  ====================================
name         extensions                read  what a read gives back
===========  ========================  ====  ====================================
``msh2``     ``.msh``                  yes   ids, names and kinds (physical names)
``msh4``     ``.msh`` (by name)        yes   ids
``gpkg``     ``.gpkg``                 yes   ids, names, kinds, depth, CRS
``fort14``   ``.14``, ``.grd``         yes   ids, names, kinds, depth, CRS
``gr3``      ``.gr3``, ``.ll``         yes   as ``fort14``
``selafin``  ``.slf``, ``.selafin``    no    (write only)
``mike``     ``.mesh``                 yes   kinds, open ids (codes), depth, CRS
``ugrid``    ``.nc``                   yes   ids, names, kinds, depth, CRS
``vtu``      ``.vtu``                  yes   ids, depth
===========  ========================  ====  ====================================

The model writers need only numpy, pyproj and coastmesh itself at import (meshio,
xarray and pyogrio are imported inside them), so importing this module stays light.
"""

from __future__ import annotations

import os
from collections.abc import Callable

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.io._mesh_format import MeshFormat
from coastmesh.io._registry import register_mesh_format
from coastmesh.io.adcirc import read_fort14_mesh, write_fort14, write_gr3
from coastmesh.io.mesh_gpkg import read_mesh_gpkg, write_mesh_gpkg
from coastmesh.io.mike import read_mike_mesh, write_mike_mesh
from coastmesh.io.msh import read_msh, write_msh
from coastmesh.io.telemac import write_selafin
from coastmesh.io.ugrid import read_ugrid, write_ugrid
from coastmesh.io.vtu import read_vtu, write_vtu
from coastmesh.types import Mesh

__all__ = ["BUILT_IN"]


def _msh_writer(version: str) -> Callable[..., None]:
    """Return a writer of msh ``version``, with the options the registry shows."""

    def write(
        path: str | os.PathLike[str],
        mesh: Mesh,
        *,
        overwrite: bool = False,
        binary: bool = False,
        sphere_xyz: bool = False,
        radius: float = EARTH_RADIUS,
    ) -> None:
        write_msh(
            path,
            mesh,
            version=version,
            binary=binary,
            overwrite=overwrite,
            sphere_xyz=sphere_xyz,
            radius=radius,
        )

    write.__name__ = write.__qualname__ = f"write_msh{version[0]}"
    return write


BUILT_IN = (
    MeshFormat(
        "msh2",
        (".msh",),
        _msh_writer("2.2"),
        "Gmsh msh 2.2 (Fluidity, Thetis); default .msh",
        read=read_msh,
    ),
    MeshFormat("msh4", (".msh",), _msh_writer("4.1"), "Gmsh msh 4.1", read=read_msh),
    MeshFormat(
        "gpkg",
        (".gpkg",),
        write_mesh_gpkg,
        "GeoPackage: layers 'nodes' (id, depth, size), 'triangles' (id) and "
        "'boundaries' (physical_id, name, kind)",
        read=read_mesh_gpkg,
    ),
    MeshFormat(
        "fort14",
        (".14", ".grd"),
        write_fort14,
        "ADCIRC fort.14: depth positive down, open and land boundary segments",
        read=read_fort14_mesh,
    ),
    MeshFormat(
        "gr3",
        (".gr3", ".ll"),
        write_gr3,
        "SCHISM hgrid.gr3: depth positive down, open and land boundary segments",
        read=read_fort14_mesh,
    ),
    MeshFormat(
        "selafin",
        (".slf", ".selafin"),
        write_selafin,
        "Telemac SELAFIN geometry (BOTTOM = bed elevation) + .cli boundary file",
    ),
    MeshFormat(
        "mike",
        (".mesh",),
        write_mike_mesh,
        "DHI MIKE .mesh: z positive up, node codes 1 land, 2.. open ids in order",
        read=read_mike_mesh,
    ),
    MeshFormat(
        "ugrid",
        (".nc",),
        write_ugrid,
        "UGRID-1.0 netCDF: mesh2d, depth on nodes, boundary_id on edges",
        read=read_ugrid,
    ),
    MeshFormat(
        "vtu",
        (".vtu",),
        write_vtu,
        "VTK unstructured grid: triangles + boundary lines, point data",
        read=read_vtu,
    ),
)

for _fmt in BUILT_IN:
    register_mesh_format(_fmt)
del _fmt
