"""A field's values at the nodes of a size grid: from a raster or a model's results.

:func:`sample_field` reads a source (a raster, or a mesh file with results:
:func:`coastmesh.io.fields.field_sources.read_field_source`), derives and reduces the
variable asked for, and samples it at the grid's nodes. The derived variables
and reductions, per node of the source mesh and record of its time series:

=================  =========================================================
``"speed"``        ``sqrt(u^2 + v^2)``, the depth-averaged velocity's
                   magnitude (m/s); a stored peak speed (ADCIRC ``maxvel``)
                   where the file has no velocity
``"elevation"``    the free surface (m): ANUGA's ``stage``, ADCIRC's
                   ``zeta``, SCHISM's ``elevation``; a stored maximum where the
                   file has no series (ADCIRC ``maxele``)
``"vorticity"``    ``|dv/dx - du/dy|`` (1/s), each triangle's gradient of the
                   linear velocity, area-weighted at the nodes
=================  =========================================================

``reduce``: ``max``, ``min``, ``mean`` (of the records where the value is
defined), ``range`` (``max - min``: ``elevation`` gives the tidal range), or
``at`` (the record nearest ``time``). ``gradient``: ``|grad f|`` of the
reduced field ``f`` on the source mesh, per metre (the same triangle gradients).
Records are read a few at a time, so a long series of a big mesh is never
whole in memory.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import reproject_points
from coastmesh.sizing.fields import node_gradients, triangles_on_grid

if TYPE_CHECKING:
    import xarray as xr

    from coastmesh.io.fields.field_sources import FieldSource
    from coastmesh.sizing.grid import Grid

__all__ = ["DERIVED", "Sampled", "is_mesh_source", "sample_field"]

#: The variables derived from a mesh source's roles.
DERIVED = ("speed", "elevation", "vorticity")
#: File name endings that are always mesh sources.
_MESH_ENDINGS = (".sww", ".63", ".64", ".vtu")
#: Grid nodes this many cells outside a source's cover take its nearest value.
EDGE_CELLS = 2.0
#: Node values of a record read at once: about 200 MB of float64.
_VALUES_AT_ONCE = 25_000_000


@dataclass(frozen=True, eq=False)
class Sampled:
    """A field on a size grid.

    Attributes
    ----------
    values : ndarray of shape (ny, nx)
        The field; NaN outside the source and where it has no value.
    inside : ndarray of bool of shape (ny, nx)
        The nodes the source covers (inside its triangles or its cells).
    what : str
        What the values are (``"speed max"``).
    """

    values: NDArray[np.float64]
    inside: NDArray[np.bool_]
    what: str


def is_mesh_source(path: str | os.PathLike[str]) -> bool:
    """Whether a file is a mesh with results (not a raster).

    By its name (``.sww``, ``.63``, ``.64``, ``.vtu``), or for NetCDF by its
    variables: a UGRID mesh topology, SCHISM's or ADCIRC's node coordinates.
    """
    name = Path(path).name.lower()
    if name.endswith(_MESH_ENDINGS):
        return True
    if not name.endswith((".nc", ".nc4", ".cdf")) or not Path(path).is_file():
        return False
    import netCDF4

    try:
        with netCDF4.Dataset(path) as nc:
            names = set(nc.variables)
            if {"SCHISM_hgrid_node_x", "element", "volumes"} & names:
                return True
            return any(
                getattr(v, "cf_role", None) == "mesh_topology"
                for v in nc.variables.values()
            )
    except OSError:
        return False


def sample_field(
    grid: Grid,
    source: str | os.PathLike[str],
    *,
    variable: str | None = None,
    reduce: str | None = None,
    time: float | None = None,
    gradient: bool = False,
    sample: str = "bilinear",
    mesh: str | os.PathLike[str] | None = None,
    crs: Any = None,
    where: str = "field",
) -> Sampled:
    """Return a source's field at the nodes of ``grid``.

    Parameters
    ----------
    grid : Grid
        The size grid.
    source : path-like
        A raster, or a mesh file with results (:func:`is_mesh_source`).
    variable : str, optional
        A raster: its NetCDF variable (default its only band). A mesh: a
        variable of the file, or ``"speed"``, ``"elevation"``, ``"vorticity"``.
    reduce : {"max", "min", "mean", "range", "at"}, optional
        Over a time series (required for one).
    time : float, optional
        Seconds from the file's time origin, with ``reduce = "at"``.
    gradient : bool
        The magnitude of the reduced field's gradient, per metre (a mesh).
    sample : {"bilinear", "nearest"}
        How a raster is read at the nodes
        (:meth:`~coastmesh.sizing.grid.Grid.sample`); a mesh is read in its
        triangles.
    mesh : path-like, optional
        The grid of an ADCIRC text output.
    crs : CRS-like, optional
        The source's CRS where the file stores none.
    where : str
        How errors and warnings name the entry (``"mesh_size.fields[0]"``).

    Returns
    -------
    Sampled

    Raises
    ------
    ConfigError
        A variable that is not there (the message lists those that are), a
        time series without ``reduce``, ``gradient`` on a raster.
    InputDataError
        A source that does not overlap the domain, or has no CRS.
    """
    if is_mesh_source(source):
        found = _mesh_field(
            grid, source, variable, reduce, time, gradient, mesh, crs, where
        )
    else:
        if gradient:
            raise ConfigError(
                f"{where}: gradient = true needs a mesh source; {source} is a raster"
            )
        found = _raster_field(grid, source, variable, crs, sample, where)
    found = _reach(found, EDGE_CELLS)
    _check_cover(grid, found, source, where)
    return found


def _reach(found: Sampled, cells: float) -> Sampled:
    """Give the nodes within ``cells`` of the source's cover their nearest value.

    A first run's mesh cuts the corners of the coast the domain follows, and a
    raster's coastal cells may have no data: the sea nodes there take the
    nearest covered node's value, so the term reaches the coast.
    """
    from scipy import ndimage

    if found.inside.all() or not found.inside.any():
        return found
    distance, (jj, ii) = ndimage.distance_transform_edt(
        ~found.inside, return_indices=True
    )
    near = ~found.inside & (distance <= cells)
    values = found.values.copy()
    values[near] = found.values[jj[near], ii[near]]
    return Sampled(values, found.inside | near, found.what)


def _check_cover(grid: Grid, found: Sampled, source: Any, where: str) -> None:
    """Refuse a source off the domain; warn of the share it does not cover."""
    sea = grid.sea
    covered = found.inside & sea
    if not covered.any():
        raise InputDataError(
            f"{where}: {source} does not overlap the domain (no node of the size "
            "grid's sea lies inside it); check its CRS and extent"
        )
    share = 1.0 - float(covered.sum()) / float(sea.sum())
    if share > 0.001:
        warnings.warn(
            f"{where}: {source} does not cover {100 * share:.1f} % of the domain; "
            "the term does not apply there",
            CoastmeshWarning,
            stacklevel=3,
        )


def _raster_field(
    grid: Grid, source: Any, variable: str | None, crs: Any, how: str, where: str
) -> Sampled:
    """Read a raster at the grid's nodes, in the raster's CRS (:meth:`Grid.sample`)."""
    from coastmesh.io.rasters.raster_window import raster_extent, read_raster_around

    path = source
    if variable is not None:
        _check_raster_variable(source, variable, where)
        path = f'NETCDF:"{os.fspath(source)}":{variable}'
    _, wkt, _ = raster_extent(path)
    given = CRS.from_user_input(crs) if crs is not None else None
    raster_crs = given or (CRS.from_wkt(wkt) if wkt else None)
    if raster_crs is None:
        raise InputDataError(f"{where}: {source} has no CRS; give the entry's crs")
    # the window the nodes need, found in the raster's CRS (the nodes moved
    # there once: grid.sample reads them again)
    moved = grid.nodes_as(raster_crs)
    raster = read_raster_around(path, moved, raster_crs, name=f"{where}: {source}")
    z = grid.sample(raster.assign_attrs(crs=raster_crs.to_wkt()), how)
    return Sampled(z, np.isfinite(z), variable or "band 1")


def _check_raster_variable(source: Any, variable: str, where: str) -> None:
    """Check a raster's variable: a NetCDF file must have it (the error lists all)."""
    import netCDF4

    try:
        with netCDF4.Dataset(source) as nc:
            names = [n for n, v in nc.variables.items() if len(v.dimensions) >= 2]
    except OSError:
        raise ConfigError(
            f"{where}: variable = {variable!r}, but {source} is not a NetCDF file "
            "with variables; leave variable out to read its first band"
        ) from None
    if variable not in names:
        raise ConfigError(
            f"{where}: variable {variable!r} is not in {source}; it has "
            f"{', '.join(sorted(names)) or 'no gridded variable'}"
        )


def _mesh_field(
    grid: Grid,
    source: Any,
    variable: str | None,
    reduce: str | None,
    time: float | None,
    gradient: bool,
    mesh: Any,
    crs: Any,
    where: str,
) -> Sampled:
    """Reduce a mesh source's variable per node, then sample it on the grid."""
    from coastmesh.io.fields.field_sources import read_field_source

    field = read_field_source(source, mesh=mesh, crs=crs)
    if field.crs is None:
        raise InputDataError(
            f"{where}: {source} stores no CRS; give the entry's crs (the CRS of "
            "its node coordinates)"
        )
    if variable is None:
        raise ConfigError(
            f"{where}: give variable, one of {_listing(field)} for {source}"
        )
    record, arrays, per = _recipe(field, variable, where)
    values = _reduced(field, record, arrays, reduce, time, where, variable)
    what = variable + (f" {reduce}" if reduce and field.times is not None else "")
    points = reproject_points(field.points, field.crs, grid.crs)
    if gradient:
        if per != "node":
            raise ConfigError(
                f"{where}: gradient = true needs node values; {variable!r} of "
                f"{source} is on the faces"
            )
        gx, gy = node_gradients(
            field.points, field.triangles, values, lonlat=field.crs.is_geographic
        )
        values, what = np.hypot(gx, gy), what + " gradient"
    triangles = _unwrapped(field.triangles, points, grid)
    z, inside = triangles_on_grid(points, triangles, grid.x, grid.y, values, per=per)
    return Sampled(z, inside, what)


def _unwrapped(
    triangles: NDArray[np.int64], points: NDArray[np.float64], grid: Grid
) -> NDArray[np.int64]:
    """Drop triangles across the antimeridian of a longitude/latitude grid."""
    if not grid.crs.is_geographic:
        return triangles
    lon = points[triangles, 0]
    return triangles[(lon.max(axis=1) - lon.min(axis=1)) < 180.0]


def _listing(field: FieldSource) -> str:
    """Return the variables of a source, and the derived ones it has roles for."""
    derived = [d for d in DERIVED if _derivable(field, d)]
    return ", ".join(sorted(field.variables) + [f"{d!r} (derived)" for d in derived])


def _derivable(field: FieldSource, name: str) -> bool:
    roles = field.roles
    if name == "elevation":
        return "elevation" in roles or "elevation_max" in roles
    if name == "speed":
        return {"u", "v"} <= set(roles) or "speed_max" in roles
    return {"u", "v"} <= set(roles)


Record = Callable[[list[NDArray[np.float64]]], NDArray[np.float64]]


def _recipe(
    field: FieldSource, variable: str, where: str
) -> tuple[Record, list[xr.DataArray], str]:
    """How a record's values come from the file's arrays: (function, arrays, per)."""
    if variable in field.variables:
        array = field.variables[variable]
        per = "triangle" if "triangle" in array.dims else "node"
        return (lambda a: a[0]), [array], per
    roles, v = field.roles, field.variables
    if variable not in DERIVED or not _derivable(field, variable):
        raise ConfigError(
            f"{where}: variable {variable!r} is not in {field.path}; it has "
            f"{_listing(field)}"
        )
    if variable == "elevation":
        name = roles.get("elevation", roles.get("elevation_max"))
        return (lambda a: a[0]), [v[str(name)]], "node"
    if variable == "speed" and not {"u", "v"} <= set(roles):
        return (lambda a: a[0]), [v[roles["speed_max"]]], "node"
    u, w = v[roles["u"]], v[roles["v"]]
    if variable == "speed":
        return (lambda a: np.hypot(a[0], a[1])), [u, w], "node"
    lonlat = field.crs is not None and field.crs.is_geographic

    def vorticity(a: list[NDArray[np.float64]]) -> NDArray[np.float64]:
        if a[0].ndim == 1:
            return _vorticity(field, a[0], a[1], lonlat)
        return np.stack(
            [_vorticity(field, x, y, lonlat) for x, y in zip(*a, strict=True)]
        )

    return vorticity, [u, w], "node"


def _vorticity(
    field: FieldSource, u: NDArray[np.float64], v: NDArray[np.float64], lonlat: bool
) -> NDArray[np.float64]:
    """``|dv/dx - du/dy|`` at the nodes."""
    _, du_dy = node_gradients(field.points, field.triangles, u, lonlat=lonlat)
    dv_dx, _ = node_gradients(field.points, field.triangles, v, lonlat=lonlat)
    return np.abs(dv_dx - du_dy)


def _reduced(
    field: FieldSource,
    record: Record,
    arrays: list[xr.DataArray],
    reduce: str | None,
    time: float | None,
    where: str,
    variable: str,
) -> NDArray[np.float64]:
    """Reduce a variable over its records, a few records at a time."""
    if "time" not in arrays[0].dims:
        if reduce is not None:
            warnings.warn(
                f"{where}: {variable!r} of {field.path} has no time axis; reduce = "
                f"{reduce!r} does nothing",
                CoastmeshWarning,
                stacklevel=4,
            )
        return np.asarray(record([np.asarray(a.values, np.float64) for a in arrays]))
    times = (
        field.times if field.times is not None else np.arange(arrays[0].sizes["time"])
    )
    if reduce is None:
        raise ConfigError(
            f"{where}: {variable!r} of {field.path} is a time series of "
            f"{len(times)} records; give reduce = 'max', 'min', 'mean', 'range' "
            "or 'at' (with time)"
        )
    if reduce == "at":
        assert time is not None  # FieldConfig: time with reduce = "at"
        k = int(np.argmin(np.abs(np.asarray(times) - time)))
        return record([np.asarray(a.isel(time=k).values, np.float64) for a in arrays])
    return _streamed(record, arrays, reduce)


def _streamed(
    record: Record, arrays: list[xr.DataArray], reduce: str
) -> NDArray[np.float64]:
    """Max, min, mean or range over the records, read in blocks.

    Only what ``reduce`` needs is kept: the highs (max, range), the lows (min,
    range), or the sums and counts of the defined values (mean).
    """
    count = arrays[0].sizes["time"]
    size = max(1, arrays[0].size // count)
    step = max(1, _VALUES_AT_ONCE // (size * len(arrays)))
    high = low = total = seen = None
    for start in range(0, count, step):
        block = [
            np.asarray(a.isel(time=slice(start, start + step)).values, np.float64)
            for a in arrays
        ]
        values = record(block)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN nodes
            if reduce in ("max", "range"):
                bmax = np.nanmax(values, axis=0)
                high = bmax if high is None else np.fmax(high, bmax)
            if reduce in ("min", "range"):
                bmin = np.nanmin(values, axis=0)
                low = bmin if low is None else np.fmin(low, bmin)
        if reduce == "mean":
            finite = np.isfinite(values)
            part = np.where(finite, values, 0.0).sum(axis=0)
            total = part if total is None else total + part
            seen = finite.sum(axis=0) if seen is None else seen + finite.sum(axis=0)
    if reduce == "max":
        assert high is not None
        return high
    if reduce == "min":
        assert low is not None
        return low
    if reduce == "range":
        assert high is not None and low is not None
        return high - low
    assert total is not None and seen is not None
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / seen
