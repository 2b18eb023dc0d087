"""UGRID-1.0 netCDF files with one 2D mesh as field sources.

Any file that follows the UGRID conventions for a 2D mesh: Delft3D FM map
files, :func:`~coastmesh.io.write_mesh` ``format="ugrid"``, xugrid. The mesh is
the variable with ``cf_role = "mesh_topology"`` and ``topology_dimension = 2``;
its ``node_coordinates`` and ``face_node_connectivity`` name the node and face
variables (``start_index``, ``_FillValue`` or a negative index for faces of
fewer nodes), its ``face_dimension`` the order of the connectivity's
dimensions, and a variable's ``mesh`` attribute the mesh it lies on. What a
variable is comes from its CF standard name; the CRS from a CF grid mapping
(with the ``epsg`` or ``EPSG_code`` attribute Delft3D FM writes).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import xarray as xr
from pyproj import CRS

from coastmesh.errors import InputDataError
from coastmesh.io._cf import crs_from_grid_mapping
from coastmesh.io.fields.field_sources._netcdf import (
    collect_variables,
    need,
    read_mesh_layout,
)
from coastmesh.io.fields.field_sources._source import (
    FieldSource,
    bed_elevation,
    build_source,
    crs_of,
    epsg_crs,
)

__all__ = ["read_ugrid", "topologies"]

_STANDARD_ROLES = {  # CF standard names of UGRID variables -> roles
    "sea_surface_height": "elevation",
    "sea_surface_height_above_geoid": "elevation",
    "sea_surface_elevation": "elevation",
    "sea_water_x_velocity": "u",
    "eastward_sea_water_velocity": "u",
    "sea_water_y_velocity": "v",
    "northward_sea_water_velocity": "v",
    "altitude": "bed",
    "bedrock_altitude": "bed",
}


def topologies(dataset: Any) -> list[str]:
    """Return the names of the file's 2D UGRID mesh topology variables."""
    return [
        str(key)
        for key, var in dataset.variables.items()
        if var.attrs.get("cf_role") == "mesh_topology"
        and int(var.attrs.get("topology_dimension", 0)) == 2
    ]


def read_ugrid(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read any UGRID file with one 2D mesh."""
    found = topologies(dataset)
    if len(found) != 1:
        raise InputDataError(
            f"has {len(found)} 2D mesh topologies ({', '.join(found)}); expected one",
            path=name,
        )
    topology = found[0]
    attrs = dataset[topology].attrs
    coords = str(attrs.get("node_coordinates", "")).split()[:2]
    faces = str(attrs.get("face_node_connectivity", ""))
    need(dataset, name, *coords, faces)
    if len(coords) != 2:
        raise InputDataError(
            f"the mesh topology {topology!r} has node_coordinates = "
            f"{attrs.get('node_coordinates')!r}; expected two variable names",
            path=name,
        )
    connectivity = dataset[faces]
    face_dim = attrs.get("face_dimension")
    if face_dim is not None and connectivity.dims[-1] == face_dim:
        connectivity = connectivity.transpose()
    mesh = (dataset[coords[0]], dataset[coords[1]], connectivity)
    points, triangles, layout, times = read_mesh_layout(dataset, name, mesh, 0)
    others = {
        k
        for k, v in dataset.variables.items()
        if v.attrs.get("mesh") not in (None, topology)
    }
    layout = replace(layout, skip=layout.skip | {topology} | {str(k) for k in others})
    variables = collect_variables(dataset, layout, times)
    roles = _ugrid_roles(variables)
    crs = (
        given
        if given is not None
        else _ugrid_crs(dataset, [*coords, topology, *variables], name)
    )
    return build_source(name, "ugrid", points, triangles, crs, variables, times, roles)


def _ugrid_roles(variables: dict[str, xr.DataArray]) -> dict[str, str]:
    """Return the roles CF standard names give; add ``bed = -depth`` if it fits."""
    roles = {}
    for role in dict.fromkeys(_STANDARD_ROLES.values()):
        keys = [
            key
            for key, var in variables.items()
            if _STANDARD_ROLES.get(str(var.attrs.get("standard_name"))) == role
        ]
        on_nodes = [key for key in keys if variables[key].dims[-1] == "node"]
        for choice in (on_nodes, keys):
            if len(choice) == 1:
                roles[role] = choice[0]
                break
    if "bed" not in roles and "bed" not in variables:
        for key, var in list(variables.items()):
            depth = key == "depth" or "depth" in str(var.attrs.get("standard_name", ""))
            if depth and var.attrs.get("positive") == "down" and var.dims == ("node",):
                variables["bed"] = bed_elevation(var, key)
                roles["bed"] = "bed"
                break
    return roles


def _ugrid_crs(dataset: Any, holders: list[str], name: str) -> CRS | None:
    """Return the CRS of the grid mapping the variables name; None if none."""
    for holder in holders:
        mapping = (
            dataset[holder].attrs.get("grid_mapping")
            if holder in dataset.variables
            else None
        )
        if not mapping or mapping not in dataset.variables:
            continue
        attrs = dataset[mapping].attrs
        crs = epsg_crs(attrs)
        if crs is not None:
            return crs
        if "EPSG_code" in attrs and str(attrs["EPSG_code"]).upper() not in (
            "EPSG:0",
            "",
        ):
            return crs_of(str(attrs["EPSG_code"]), name, f"{mapping}:EPSG_code")
        return crs_from_grid_mapping(attrs, name, mapping)
    for mapping in ("projected_coordinate_system", "wgs84"):
        crs = epsg_crs(dataset[mapping].attrs) if mapping in dataset.variables else None
        if crs is not None:
            return crs
    return None
