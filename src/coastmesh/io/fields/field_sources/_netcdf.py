"""What the netCDF field sources share: the file opened lazily, its mesh and times.

ANUGA, SCHISM, ADCIRC and UGRID files all keep a mesh as node coordinate
variables and a face-node connectivity variable, times in a 1D variable with CF
``units`` (``seconds since ...``), and values on the node and face dimensions.
The format modules name their variables; this module reads them: the nodes and
the faces (split in a fan,
:func:`~coastmesh.io.fields.field_sources._source.split_faces`), the times in
seconds, and every numeric variable on the nodes or faces, its time series as dask
arrays of :data:`TIME_CHUNK` records, so a reduction over time reads a record
block at a time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from coastmesh.errors import InputDataError
from coastmesh.io.fields.field_sources._source import DIMS, split_faces

__all__ = [
    "TIME_CHUNK",
    "Layout",
    "as_variable",
    "collect_variables",
    "need",
    "open_netcdf",
    "read_mesh_layout",
]

#: Records per dask chunk of a netCDF time series.
TIME_CHUNK = 24
_SECONDS = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "min": 60.0}
_SECONDS |= {"minute": 60.0, "minutes": 60.0, "h": 3600.0, "hour": 3600.0}
_SECONDS |= {"hours": 3600.0, "d": 86400.0, "day": 86400.0, "days": 86400.0}
_COORDINATE_NAMES = frozenset(
    {"longitude", "latitude", "projection_x_coordinate", "projection_y_coordinate"}
)


@dataclass(frozen=True, slots=True)
class Layout:
    """Where a netCDF file keeps its mesh: the dimension names and the faces."""

    node: str
    face: str
    time: str | None
    face_of: NDArray[np.int64] | None  # the face of each triangle, if split
    skip: frozenset[str]


def open_netcdf(name: str) -> Any:
    """Open a netCDF file as a dataset, nothing read but its header."""
    try:
        return xr.open_dataset(
            name,
            engine="netcdf4",
            decode_times=False,
            decode_timedelta=False,
            decode_coords=False,
        )
    except (OSError, ValueError, RuntimeError) as exc:
        raise InputDataError(f"not a readable netCDF file ({exc})", path=name) from None


def need(dataset: Any, name: str, *keys: str) -> None:
    """Raise if the file lacks a variable its format must have."""
    for key in keys:
        if key not in dataset.variables:
            raise InputDataError(
                f"has no variable {key!r}; it has "
                f"{', '.join(map(str, dataset.variables))}",
                path=name,
            )


def read_mesh_layout(
    dataset: Any, name: str, mesh: tuple[Any, Any, Any], start: int
) -> tuple[NDArray[np.float64], NDArray[np.int64], Layout, NDArray[np.float64] | None]:
    """Read the nodes and faces of a netCDF mesh; return them, its layout, times."""
    x, y, faces = mesh
    points = np.column_stack([np.asarray(v.values, dtype=np.float64) for v in (x, y)])
    start = int(faces.attrs.get("start_index", start))
    triangles, face_of = split_faces(faces.values, start, len(points), name, faces.name)
    time = _time_variable(dataset)
    layout = Layout(
        x.dims[0],
        faces.dims[0],
        None if time is None else str(dataset[time].dims[0]),
        face_of,
        frozenset({str(x.name), str(y.name), str(faces.name), str(time)}),
    )
    times = None if time is None else _seconds(dataset[time], name)
    return points, triangles, layout, times


def _time_variable(dataset: Any) -> str | None:
    """Return the name of the times: ``time``, else a CF time variable; or None."""
    candidates = ["time"] if "time" in dataset.variables else []
    candidates += [
        str(key)
        for key, var in dataset.variables.items()
        if var.attrs.get("standard_name") == "time" or var.attrs.get("axis") == "T"
    ]
    return next((key for key in candidates if dataset[key].ndim == 1), None)


def _seconds(var: Any, name: str) -> NDArray[np.float64]:
    """Return a time variable in seconds from its origin (``units``, CF style)."""
    units = str(var.attrs.get("units", "seconds"))
    word = units.split(" since ", maxsplit=1)[0].strip().lower()
    if word not in _SECONDS:
        raise InputDataError(
            f"variable {var.name!r} has units {units!r}; expected seconds, minutes, "
            "hours or days (since a date)",
            path=name,
        )
    return np.asarray(var.values, dtype=np.float64) * _SECONDS[word]


def collect_variables(
    dataset: Any, layout: Layout, times: NDArray[np.float64] | None
) -> dict[str, xr.DataArray]:
    """Return every numeric variable on the nodes or faces, time series lazy."""
    rename = {layout.node: "node", layout.face: "triangle"}
    if layout.time is not None:
        rename[layout.time] = "time"
    out = {}
    for key, var in dataset.variables.items():
        dims = tuple(rename.get(d, "") for d in var.dims)
        coordinate = var.attrs.get("axis") in ("X", "Y") or (
            var.attrs.get("standard_name") in _COORDINATE_NAMES
        )
        if (
            key in layout.skip
            or dims not in DIMS
            or var.dtype.kind not in "iuf"
            or coordinate
        ):
            continue
        out[str(key)] = as_variable(var, dims, layout, times)
    return out


def as_variable(
    var: Any, dims: tuple[str, ...], layout: Layout, times: Any
) -> xr.DataArray:
    """One variable as a DataArray of our dims; a time series as a dask array."""
    if "time" in dims:
        variable = var.variable if isinstance(var, xr.DataArray) else var
        data = variable.chunk({layout.time: TIME_CHUNK}).data
    else:
        data = np.asarray(var.values)
    if dims[-1] == "triangle" and layout.face_of is not None:
        data = data[:, layout.face_of] if data.ndim == 2 else data[layout.face_of]
    coords = {"time": times} if "time" in dims else None
    return xr.DataArray(data, dims=dims, coords=coords, attrs=dict(var.attrs))
