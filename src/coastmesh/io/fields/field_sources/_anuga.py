"""ANUGA ``.sww`` files (netCDF) as field sources.

The layout is the one ANUGA's own writer gives them (``anuga/file/sww.py``):
node coordinates ``x``, ``y`` relative to the georeference's ``xllcorner``,
``yllcorner``; triangles ``volumes`` (0-based); ``time`` in seconds after
``starttime``; the quantities (``stage``, ``xmomentum``, ``ymomentum``,
``elevation``, ...) on the points, and their centroid values (``stage_c``, ...)
on the triangles. The georeference is in the global attributes: ``epsg`` (ANUGA
4), else ``zone``, ``datum``, ``hemisphere`` and ``false_northing``.
Velocities are momentum over depth, taken as 0 on nodes shallower than
:data:`DRY_HEIGHT`, as ANUGA's own reader does (``anuga/utilities/plot_utils.py``,
``get_output``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.io.fields.field_sources._netcdf import (
    collect_variables,
    read_mesh_layout,
)
from coastmesh.io.fields.field_sources._source import (
    FieldSource,
    build_source,
    epsg_crs,
    roles_of,
)

__all__ = ["DRY_HEIGHT", "read_anuga"]

#: Metres of water below which ANUGA velocities are taken as 0: the
#: ``minimum_allowed_height`` default of ANUGA's own reader of ``.sww`` files
#: (``anuga/utilities/plot_utils.py``, ``get_output``).
DRY_HEIGHT = 1.0e-3


def read_anuga(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read an ANUGA ``.sww`` file."""
    attrs = dataset.attrs
    points, triangles, layout, times = read_mesh_layout(
        dataset, name, (dataset["x"], dataset["y"], dataset["volumes"]), 0
    )
    points += [float(attrs.get("xllcorner", 0.0)), float(attrs.get("yllcorner", 0.0))]
    variables = collect_variables(dataset, layout, times)
    roles = roles_of(variables, {"elevation": ("stage",), "bed": ("elevation",)})
    needed = {"stage", "elevation", "xmomentum", "ymomentum"}
    if needed <= set(variables) and "u" not in variables and "v" not in variables:
        height = variables.get("height")
        if height is None:
            height = variables["stage"] - variables["elevation"]
        wet = height > DRY_HEIGHT
        safe = height.where(wet, 1.0)
        for role, momentum in (("u", "xmomentum"), ("v", "ymomentum")):
            velocity = (variables[momentum] / safe).where(wet, 0.0)
            variables[role] = velocity.assign_attrs(
                long_name=f"{momentum} / height, 0 where height <= {DRY_HEIGHT} m",
                units="m/s",
            )
            roles[role] = role
    crs = given if given is not None else _anuga_crs(attrs)
    return build_source(name, "anuga", points, triangles, crs, variables, times, roles)


def _anuga_crs(attrs: Mapping[str, Any]) -> CRS | None:
    """Return the CRS of an ``.sww`` file's georeference, as ANUGA finds it."""
    crs = epsg_crs(attrs)
    if crs is not None:
        return crs
    zone = int(attrs.get("zone", -1))
    hemisphere = str(attrs.get("hemisphere", "undefined")).lower()
    if -60 <= zone <= -2:
        zone, hemisphere = -zone, "southern"
    if hemisphere not in ("northern", "southern"):
        northing = float(attrs.get("false_northing", -1.0))
        hemisphere = {0.0: "northern", 10_000_000.0: "southern"}.get(northing, "")
    if not 1 <= zone <= 60 or not hemisphere:
        return None
    south = hemisphere == "southern"
    datum = str(attrs.get("datum", "wgs84")).upper()
    if datum == "WGS84":
        return CRS.from_epsg((32700 if south else 32600) + zone)
    try:
        return CRS.from_dict(
            {"proj": "utm", "zone": zone, "south": south, "datum": datum}
        )
    except CRSError:
        return None
