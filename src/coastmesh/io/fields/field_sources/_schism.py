"""SCHISM 2D outputs as field sources: ``out2d_*.nc`` (v5.10 on) and ``schout_*.nc``.

``out2d_*.nc`` is what SCHISM's scribes write (``schism-dev/schism``:
``src/Core/scribe_io.F90``, ``nc_writeout2D``): nodes
``SCHISM_hgrid_node_x``, ``SCHISM_hgrid_node_y``, faces
``SCHISM_hgrid_face_nodes`` (1-based, -1 or the fill value after the third
node of a triangle), ``depth``, and the 2D outputs (``elevation``,
``depthAverageVelX``, ``depthAverageVelY``, ...) on the nodes or faces. The
older ``schout_*.nc`` has the same mesh variables, with ``elev`` and the
velocity ``dahv`` (time, node, 2). SCHISM writes a CRS (global attribute
``crs``, and a grid mapping variable ``crs``) only for lon/lat grids
(``ics = 2``).
"""

from __future__ import annotations

from typing import Any

from pyproj import CRS

from coastmesh.io._cf import crs_from_grid_mapping
from coastmesh.io.fields.field_sources._netcdf import (
    as_variable,
    collect_variables,
    need,
    read_mesh_layout,
)
from coastmesh.io.fields.field_sources._source import (
    FieldSource,
    bed_elevation,
    build_source,
    crs_of,
    roles_of,
)

__all__ = ["read_schism"]

_ROLES = {  # role -> the variable that plays it, out2d's name first
    "elevation": ("elevation", "elev"),
    "u": ("depthAverageVelX", "dahv_x"),
    "v": ("depthAverageVelY", "dahv_y"),
    "bed": ("bed",),
}


def read_schism(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read a SCHISM 2D output (``out2d_*.nc``, or the older ``schout_*.nc``)."""
    need(dataset, name, "SCHISM_hgrid_node_y", "SCHISM_hgrid_face_nodes")
    mesh = tuple(
        dataset[f"SCHISM_hgrid_{v}"] for v in ("node_x", "node_y", "face_nodes")
    )
    points, triangles, layout, times = read_mesh_layout(dataset, name, mesh, 1)
    variables = collect_variables(dataset, layout, times)
    if "dahv" in dataset.variables and layout.time is not None:
        dahv = dataset["dahv"]
        if dahv.dims[:2] == (layout.time, layout.node) and dahv.shape[2:] == (2,):
            for k, axis in enumerate("xy"):
                variables[f"dahv_{axis}"] = as_variable(
                    dahv[..., k], ("time", "node"), layout, times
                )
    if "depth" in variables:
        variables["bed"] = bed_elevation(variables["depth"])
    roles = roles_of(variables, _ROLES)
    crs = given
    if crs is None and "crs" in dataset.attrs:
        crs = crs_of(str(dataset.attrs["crs"]), name, "global attribute 'crs'")
    if crs is None and "crs" in dataset.variables:
        crs = crs_from_grid_mapping(dataset["crs"].attrs, name, "crs")
    return build_source(name, "schism", points, triangles, crs, variables, times, roles)
