"""ADCIRC outputs as field sources: the netCDF ones and the ASCII ones.

netCDF (``fort.63.nc``, ``fort.64.nc``, ``maxele.63.nc``, ``maxvel.63.nc``):
nodes ``x``, ``y``, triangles ``element`` (1-based), and ``zeta``, ``u-vel``,
``v-vel``, ``zeta_max``, ``time_of_zeta_max``, ``vel_max``,
``time_of_vel_max``, ``depth``... with -99999 for a dry node. Spherical runs
(``ICS = 2``) store lon/lat in degrees; ``x`` of a Cartesian run (``ICS = 1``)
has no longitude standard name.

ASCII (``fort.63``, ``fort.64``, ``maxele.63``, ``maxvel.63``), as ADCIRC's
``globalio.F`` writes them: a header line, ``NDSETS NP DT NSPOOL IRTYPE``, then
per record ``TIME IT`` (sparse: ``TIME IT NNONDEF DEFVAL``) and one line
``node value(s)`` per node. They hold values only: the nodes and triangles come
from the grid the run was made on (its ``fort.14``).
"""

from __future__ import annotations

import os
import warnings
from itertools import islice
from typing import Any, TextIO

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import FormatError, InputDataError
from coastmesh.io.fields.field_sources._netcdf import (
    collect_variables,
    read_mesh_layout,
)
from coastmesh.io.fields.field_sources._source import (
    READS,
    FieldSource,
    bed_elevation,
    build_source,
    roles_of,
)
from coastmesh.io.meshes._registry import read_mesh
from coastmesh.types import Mesh

__all__ = ["adcirc_ascii_header", "read_adcirc_ascii", "read_adcirc_netcdf"]

_DRY = -99999.0  # ADCIRC's missing value (a dry node)
_ROLES = {  # role -> ADCIRC's variable
    "elevation": ("zeta",),
    "u": ("u-vel",),
    "v": ("v-vel",),
    "elevation_max": ("zeta_max",),
    "speed_max": ("vel_max",),
    "bed": ("bed",),
}
_ASCII = {  # end of the file name -> variables of a record, max file?
    "maxele": (("zeta_max",), True),
    "maxvel": (("vel_max",), True),
    "63": (("zeta",), False),
    "64": (("u-vel", "v-vel"), False),
}


def read_adcirc_netcdf(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read an ADCIRC netCDF output (``fort.63.nc``, ``maxvel.63.nc``, ...)."""
    mesh = (dataset["x"], dataset["y"], dataset["element"])
    points, triangles, layout, times = read_mesh_layout(dataset, name, mesh, 1)
    variables = {}
    for key, found in collect_variables(dataset, layout, times).items():
        var = found
        peak = key.endswith("_max") or key.startswith("time_of_")
        if peak and var.dims[0] == "time" and var.sizes["time"] == 1:
            var = var.isel(time=0, drop=True)  # older ADCIRC: a time axis of one
        variables[key] = var.where(var != _DRY) if var.dtype.kind == "f" else var
    if not any("time" in var.dims for var in variables.values()):
        times = None
    if "depth" in variables:
        variables["bed"] = bed_elevation(variables["depth"])
    crs = given
    x = dataset["x"].attrs
    cartesian = "longitude" not in str(x.get("standard_name", "longitude"))
    if crs is None and not cartesian:
        crs = CRS.from_epsg(4326)
    roles = roles_of(variables, _ROLES)
    return build_source(name, "adcirc", points, triangles, crs, variables, times, roles)


def adcirc_ascii_header(name: str) -> tuple[int, int] | None:
    """``(NP, IRTYPE)`` of an ADCIRC ASCII output's 2nd line; None if not one."""
    try:
        with open(name, encoding="ascii", errors="replace") as file:
            file.readline(4096)
            tokens = file.readline(4096).split()
        int(tokens[0]), float(tokens[2]), int(tokens[3])
        return int(tokens[1]), int(tokens[4])
    except (ValueError, IndexError):
        return None


def read_adcirc_ascii(
    name: str, mesh: str | os.PathLike[str] | Mesh | None, given: CRS | None
) -> FieldSource:
    """Read an ADCIRC ASCII output on the nodes of its grid."""
    count, irtype = adcirc_ascii_header(name) or (0, 0)
    keys, peak = _ascii_kind(name, irtype)
    if mesh is None:
        raise InputDataError(
            "an ADCIRC ASCII output holds no node coordinates; give the grid it "
            "was run on as mesh= (its fort.14)",
            path=name,
        )
    grid = mesh if isinstance(mesh, Mesh) else read_mesh(mesh)
    if count != len(grid.points):
        where = "the mesh given" if isinstance(mesh, Mesh) else os.fspath(mesh)
        raise InputDataError(
            f"NP = {count} nodes, but {where} has {len(grid.points)}; give the grid "
            "this run was made on",
            path=name,
        )
    with open(name, encoding="ascii", errors="replace") as file:
        stamps, records = _ascii_records(file, name, count, irtype)
    if not records:
        raise InputDataError("holds no record after its header", path=name)
    values = np.stack(records)
    values[values == _DRY] = np.nan
    variables: dict[str, xr.DataArray] = {}
    times: NDArray[np.float64] | None = None
    if peak:
        variables[keys[0]] = xr.DataArray(values[0, :, 0], dims=("node",))
        if len(records) > 1:
            variables[f"time_of_{keys[0]}"] = xr.DataArray(
                values[1, :, 0], dims=("node",)
            )
    else:
        times = np.asarray(stamps, dtype=np.float64)
        for k, key in enumerate(keys):
            variables[key] = xr.DataArray(
                values[:, :, k], dims=("time", "node"), coords={"time": times}
            )
    if "depth" in grid.point_data:
        variables["depth"] = xr.DataArray(grid.point_data["depth"], dims=("node",))
        variables["bed"] = bed_elevation(variables["depth"])
    roles = roles_of(variables, _ROLES)
    crs = given if given is not None else grid.crs
    lonlat = (np.abs(grid.points) <= [360.0, 90.0]).all()
    if crs is None and lonlat:
        crs = CRS.from_epsg(4326)
    return build_source(
        name, "adcirc", grid.points, grid.triangles, crs, variables, times, roles
    )


def _ascii_kind(name: str, irtype: int) -> tuple[tuple[str, ...], bool]:
    """Return the variables of a record, and whether it is a max file."""
    base = os.path.basename(name).lower()
    key = next((k for k in ("maxele", "maxvel") if k in base), base[-2:])
    found = _ASCII.get(key)
    if found is None or len(found[0]) != irtype:
        raise FormatError(
            f"{name}: an ADCIRC ASCII output with IRTYPE = {irtype}, but not one "
            "read (by name: fort.63 and maxele.63, maxvel.63 with one value a node, "
            f"fort.64 with two); {READS}"
        )
    return found


def _ascii_records(
    file: TextIO, name: str, count: int, irtype: int
) -> tuple[list[float], list[NDArray[np.float64]]]:
    """Read the records after the header: their times and (NP, IRTYPE) values."""
    file.readline()
    file.readline()
    number = 2
    stamps, records = [], []
    for line in iter(file.readline, ""):
        number += 1
        tokens = line.split()
        if not tokens:
            continue
        sparse = len(tokens) >= 4
        try:
            stamp = float(tokens[0])
            rows = int(tokens[2]) if sparse else count
            default = float(tokens[3]) if sparse else _DRY
        except (ValueError, IndexError):
            raise InputDataError(
                f"line {number}: {line.strip()[:60]!r} is not a record's "
                "'TIME IT' line",
                path=name,
            ) from None
        block = _ascii_block(file, rows, irtype + 1, name, number)
        labels = block[:, 0].astype(np.int64)
        if labels.size and (labels.min() < 1 or labels.max() > count):
            raise InputDataError(
                f"the record of line {number} has node numbers in "
                f"[{labels.min()}, {labels.max()}]; expected 1..NP = 1..{count}",
                path=name,
            )
        record = np.full((count, irtype), default)
        record[labels - 1] = block[:, 1:]
        stamps.append(stamp)
        records.append(record)
        number += rows
    return stamps, records


def _ascii_block(
    file: TextIO, rows: int, width: int, name: str, number: int
) -> NDArray[np.float64]:
    """Return the next ``rows`` lines of ``width`` numbers each, as an array."""
    text = "".join(islice(file, rows))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", DeprecationWarning)
            values = np.fromstring(text, sep=" ")
    except (ValueError, DeprecationWarning):
        values = np.empty(0)
    if values.size != rows * width:
        raise InputDataError(
            f"the record of line {number}: expected {rows} lines of {width} numbers "
            "(node, value...); the file ends early or a value is not a number",
            path=name,
        )
    return values.reshape(rows, width)
