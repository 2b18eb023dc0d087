"""The built-in mesh formats, registered in this order when the registry is used.

===========  ========================  ====  ====================================
name         extensions                read  what a read gives back
===========  ========================  ====  ====================================
``msh2``     ``.msh``                  yes   ids, names and kinds (physical names)
``msh4``     ``.msh`` (by name)        yes   ids
``gpkg``     ``.gpkg``                 yes   ids, names, kinds, depth, CRS
``fort14``   ``.14``, ``.grd``         yes   ids, names, kinds, depth, CRS; region
                                             ids from the ``.13`` beside it
``gr3``      ``.gr3``, ``.ll``         yes   as ``fort14``; region ids, exact,
                                             from the ``.regions.prop`` beside it
``selafin``  ``.slf``, ``.selafin``    yes   depth, CRS (the title); kinds and
                                             ids from the ``.cli`` beside it: land
                                             1, liquid boundary k of Telemac k + 1
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
from coastmesh.io.meshes._mesh_format import MeshFormat
from coastmesh.io.meshes._registry import register_mesh_format
from coastmesh.io.meshes.adcirc import (
    read_fort14_mesh,
    read_gr3_mesh,
    write_fort14,
    write_gr3,
)
from coastmesh.io.meshes.mesh_gpkg import read_mesh_gpkg, write_mesh_gpkg
from coastmesh.io.meshes.mike import read_mike_mesh, write_mike_mesh
from coastmesh.io.meshes.msh import read_msh, write_msh
from coastmesh.io.meshes.telemac import write_selafin
from coastmesh.io.meshes.telemac_read import read_selafin_mesh
from coastmesh.io.meshes.ugrid import read_ugrid, write_ugrid
from coastmesh.io.meshes.vtu import read_vtu, write_vtu
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


_TOPOLOGY = frozenset({"ids", "names", "kinds"})

BUILT_IN = (
    MeshFormat(
        "msh2",
        (".msh",),
        _msh_writer("2.2"),
        "Gmsh msh 2.2: triangles (one physical surface per region: `domain`, "
        "farms, footprints), boundary lines with physical ids, physical names "
        "`open:NAME` / `shoreline:NAME`; default .msh",
        read=read_msh,
        model="Fluidity, Thetis/Firedrake",
        holds=_TOPOLOGY | {"sphere_xyz", "regions", "lines"},
    ),
    MeshFormat(
        "msh4",
        (".msh",),
        _msh_writer("4.1"),
        "Gmsh msh 4.1 with ids, one surface entity per region (meshio cannot "
        "read back names in 4.1, so none are written)",
        read=read_msh,
        model="Gmsh 4",
        holds=frozenset({"ids", "sphere_xyz", "regions", "lines"}),
    ),
    MeshFormat(
        "gpkg",
        (".gpkg",),
        write_mesh_gpkg,
        "GeoPackage: layers `nodes` (id, depth, size), `triangles` (id, region, "
        "region_name) and `boundaries` (physical_id, name, kind)",
        read=read_mesh_gpkg,
        model="QGIS",
        holds=_TOPOLOGY | {"depth", "node_data", "crs", "regions"},
        positive="down",
    ),
    MeshFormat(
        "fort14",
        (".14", ".grd"),
        write_fort14,
        "ADCIRC fort.14: nodes with depth, elements, boundary lists by ADCIRC's "
        "rules: open boundaries that meet as one string (`IBTYPEE 0`, no node "
        "twice), each coast between them one `IBTYPE 0` string, each island one "
        '`IBTYPE 1` string closed by its first node (`land="natural"`: 20 '
        "and 21), the ids along each in its comment; with regions, the nodal "
        "attributes file `.13` (fort.13) beside it: `coastmesh_region_id` per "
        "node, default the surface id",
        read=read_fort14_mesh,
        model="ADCIRC",
        holds=_TOPOLOGY | {"depth", "crs", "node_regions"},
        positive="down",
        region_companions=(".13",),
    ),
    MeshFormat(
        "gr3",
        (".gr3", ".ll"),
        write_gr3,
        "SCHISM hgrid.gr3: the fort.14 layout by SCHISM's rules: one open string "
        "per id (corners shared), each coast between them one string of flag 0, "
        "each island one string of flag 1, not closed; with regions, the element "
        "property file `.regions.prop` beside it: `element_number region_id` per "
        "element",
        read=read_gr3_mesh,
        model="SCHISM",
        holds=_TOPOLOGY | {"depth", "crs", "regions"},
        positive="down",
        region_companions=(".regions.prop",),
    ),
    MeshFormat(
        "selafin",
        (".slf", ".selafin"),
        write_selafin,
        "Telemac SELAFIN geometry with `BOTTOM` (bed elevation) and `IPOBO`, and "
        "the `.cli` boundary file in boundary order: land `2 2 2`, open `5 4 4` "
        "(prescribed elevation)",
        read=read_selafin_mesh,
        model="Telemac-2D",
        holds=frozenset({"ids", "kinds", "depth", "crs"}),
        companions=(".cli",),
        positive="up",
    ),
    MeshFormat(
        "mike",
        (".mesh",),
        write_mike_mesh,
        "DHI MIKE .mesh: node codes 0 inside, 1 land, 2, 3, ... for the open ids "
        "in increasing order; `z`",
        read=read_mike_mesh,
        model="MIKE 21 FM",
        holds=frozenset({"ids", "kinds", "depth", "crs"}),
        positive="up",
    ),
    MeshFormat(
        "ugrid",
        (".nc",),
        write_ugrid,
        "UGRID-1.0 netCDF: `mesh2d`, `depth` and every node field on the nodes, "
        "`boundary_id` on edges, `region_id` on faces, the CRS",
        read=read_ugrid,
        model="xugrid, QGIS, Delft3D FM tools",
        holds=_TOPOLOGY | {"depth", "node_data", "crs", "regions"},
        positive="down",
    ),
    MeshFormat(
        "vtu",
        (".vtu",),
        write_vtu,
        "VTK unstructured grid: triangles (cell data `physical`: the region id) "
        "and boundary lines, every node field",
        read=read_vtu,
        model="ParaView",
        holds=frozenset({"ids", "depth", "node_data", "regions"}),
        positive="down",
    ),
)

for _fmt in BUILT_IN:
    register_mesh_format(_fmt)
del _fmt
