"""Field sources: a model's results (or any mesh with values) read as fields.

:func:`read_field_source` reads the mesh and the values of a first run, for the
size term that sizes a mesh from a field (issue 50). It reads

==========  ===================================================================
``anuga``   ANUGA ``.sww`` (netCDF), as ``anuga/file/sww.py`` writes it
``schism``  SCHISM 2D outputs ``out2d_*.nc`` (v5.10 on) and ``schout_*.nc``
``adcirc``  ADCIRC netCDF outputs (``fort.63.nc``, ``fort.64.nc``,
            ``maxele.63.nc``, ``maxvel.63.nc``) and the ASCII ones (``fort.63``,
            ``fort.64``, ``maxele.63``, ``maxvel.63``) with their grid
``ugrid``   any UGRID-1.0 netCDF file with one 2D mesh (Delft3D FM map files,
            :func:`~coastmesh.io.write_mesh` ``format="ugrid"``, xugrid)
``vtu``     VTK unstructured grids (``.vtu``), through meshio
==========  ===================================================================

and tells them apart by their contents. Every source becomes a
:class:`FieldSource`: nodes, triangles (a quad or polygon split in a fan from its
first node) and variables with the dimensions ``("time", "node")``,
``("node",)``, ``("time", "triangle")`` or ``("triangle",)``. The time series of
the netCDF formats stay on disk, as dask arrays of :data:`TIME_CHUNK` records,
so a reduction over time reads a record block at a time.
"""

from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from itertools import islice
from pathlib import Path
from types import MappingProxyType
from typing import Any, TextIO

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io._cf import crs_from_grid_mapping
from coastmesh.io._inputs import check_input
from coastmesh.io._meshio import read_with_meshio
from coastmesh.io._registry import read_mesh
from coastmesh.types import Mesh

__all__ = [
    "DRY_HEIGHT",
    "KINDS",
    "ROLES",
    "TIME_CHUNK",
    "FieldSource",
    "read_field_source",
]

logger = logging.getLogger(__name__)

#: The kinds of source, as :attr:`FieldSource.kind` names them.
KINDS = ("anuga", "schism", "adcirc", "ugrid", "vtu")
#: The roles a format can give its variables (:attr:`FieldSource.roles`).
ROLES = ("u", "v", "elevation", "bed", "speed_max", "elevation_max")
#: Records per dask chunk of a netCDF time series.
TIME_CHUNK = 24
#: Metres of water below which ANUGA velocities are taken as 0: the
#: ``minimum_allowed_height`` default of ANUGA's own reader of ``.sww`` files
#: (``anuga/utilities/plot_utils.py``, ``get_output``).
DRY_HEIGHT = 1.0e-3
_DIMS = (("time", "node"), ("node",), ("time", "triangle"), ("triangle",))
_ADCIRC_DRY = -99999.0  # ADCIRC's missing value (a dry node)
_SECONDS = {"s": 1.0, "sec": 1.0, "second": 1.0, "seconds": 1.0, "min": 60.0}
_SECONDS |= {"minute": 60.0, "minutes": 60.0, "h": 3600.0, "hour": 3600.0}
_SECONDS |= {"hours": 3600.0, "d": 86400.0, "day": 86400.0, "days": 86400.0}
_COORDINATE_NAMES = frozenset(
    {"longitude", "latitude", "projection_x_coordinate", "projection_y_coordinate"}
)
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
_ADCIRC_ASCII = {  # end of the file name -> variables of a record, max file?
    "maxele": (("zeta_max",), True),
    "maxvel": (("vel_max",), True),
    "63": (("zeta",), False),
    "64": (("u-vel", "v-vel"), False),
}
_READS = (
    "it reads ANUGA .sww, SCHISM out2d_*.nc and schout_*.nc, ADCIRC netCDF and "
    "ASCII outputs (fort.63, fort.64, maxele.63, maxvel.63), UGRID netCDF (one 2D "
    "mesh) and VTU (.vtu)"
)


@dataclass(frozen=True, eq=False, slots=True)
class FieldSource:
    """A mesh with values on its nodes or triangles, read from a model's results.

    Parameters
    ----------
    path : Path
        The file read.
    kind : str
        Its format, one of :data:`KINDS`.
    points : ndarray of shape (N, 2)
        Node coordinates in ``crs``; float64.
    triangles : ndarray of shape (M, 3)
        0-based node indices; int64. A face of k > 3 nodes is split in a fan from
        its first node, ``(0, j, j + 1)`` for ``j = 1 .. k - 2``, in file order.
    crs : pyproj.CRS or None
        The CRS of ``points``; None when the file stores none and none was given.
    variables : mapping of str to xarray.DataArray
        Values by name, each with the dimensions ``("time", "node")``,
        ``("node",)``, ``("time", "triangle")`` or ``("triangle",)``. A face's
        value is on each of its triangles. Time series carry ``times`` as their
        ``time`` coordinate; those of netCDF files are dask arrays.
    times : ndarray of shape (T,) or None
        Seconds from the file's time origin; None if no variable has a time axis.
    roles : mapping of str to str
        Role (:data:`ROLES`) -> variable name, where the format says what a
        variable is: ``u``, ``v`` (depth-averaged velocity, m/s), ``elevation``
        (free surface, m), ``bed`` (bed elevation, m, positive up),
        ``speed_max`` (a stored peak speed, m/s), ``elevation_max`` (a stored
        peak elevation, m).

    Raises
    ------
    ValueError
        If a shape, a variable's dimensions or sizes, a role or the kind does not
        fit; the message names the field and both sizes.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> source = FieldSource(
    ...     Path("m.vtu"), "vtu", np.array([[0.0, 0], [1, 0], [0, 1]]),
    ...     np.array([[0, 1, 2]]), None,
    ...     {"speed": xr.DataArray([0.5, 1.0, 2.0], dims="node")}, None, {})
    >>> source.variables["speed"].dims, source.triangles.dtype
    (('node',), dtype('int64'))
    """

    path: Path
    kind: str
    points: NDArray[np.float64]
    triangles: NDArray[np.int64]
    crs: CRS | None
    variables: Mapping[str, xr.DataArray]
    times: NDArray[np.float64] | None
    roles: Mapping[str, str]

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "path", Path(self.path))
        set_(self, "points", np.asarray(self.points, dtype=np.float64))
        set_(self, "triangles", np.asarray(self.triangles, dtype=np.int64))
        if self.times is not None:
            set_(self, "times", np.asarray(self.times, dtype=np.float64))
        set_(self, "variables", MappingProxyType(dict(self.variables)))
        set_(self, "roles", MappingProxyType(dict(self.roles)))
        _check_source(self)


def _check_source(source: FieldSource) -> None:
    """Raise ValueError if the parts of a FieldSource do not fit together."""
    if source.kind not in KINDS:
        raise ValueError(f"kind = {source.kind!r}: expected one of {KINDS}")
    points, triangles = source.points, source.triangles
    if points.ndim != 2 or points.shape[1] != 2:
        raise ValueError(f"points has shape {points.shape}; expected (N, 2)")
    if not np.isfinite(points).all():
        raise ValueError("points has a coordinate that is not finite")
    if triangles.ndim != 2 or triangles.shape[1] != 3:
        raise ValueError(f"triangles has shape {triangles.shape}; expected (M, 3)")
    if triangles.size and (triangles.min() < 0 or triangles.max() >= len(points)):
        raise ValueError(
            f"triangles has node indices in [{triangles.min()}, {triangles.max()}]; "
            f"expected 0 .. {len(points) - 1} (N = {len(points)})"
        )
    sizes = {"node": len(points), "triangle": len(triangles)}
    if source.times is not None:
        sizes["time"] = len(source.times)
    for name, var in source.variables.items():
        if var.dims not in _DIMS:
            raise ValueError(f"variable {name!r} has dims {var.dims}; expected {_DIMS}")
        for dim, size in zip(var.dims, var.shape, strict=True):
            if sizes.get(dim, -1) != size:
                raise ValueError(
                    f"variable {name!r} has {size} along {dim!r}; expected "
                    f"{sizes.get(dim, 'none (times is None)')}"
                )
    for role, name in source.roles.items():
        if role not in ROLES or name not in source.variables:
            raise ValueError(
                f"roles[{role!r}] = {name!r}: roles are {ROLES}, each naming a variable"
            )


def read_field_source(
    path: str | os.PathLike[str],
    *,
    mesh: str | os.PathLike[str] | Mesh | None = None,
    crs: Any = None,
) -> FieldSource:
    """Read a model's results (or any mesh with values) as a :class:`FieldSource`.

    Parameters
    ----------
    path : str or path-like
        The file: an ANUGA ``.sww``, a SCHISM ``out2d_*.nc`` or ``schout_*.nc``,
        an ADCIRC netCDF output or ASCII ``fort.63``, ``fort.64``,
        ``maxele.63`` or ``maxvel.63``, a UGRID netCDF file or a ``.vtu``. The
        format is told from the contents (the ASCII outputs also by their name).
    mesh : str, path-like or Mesh, optional
        The grid of an ADCIRC ASCII output (which holds values only), such as the
        ``fort.14`` it was run on, read with :func:`~coastmesh.io.read_mesh`.
        Other sources do not use it.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates; it replaces the one the file declares.

    Returns
    -------
    FieldSource
        See Notes for each format.

    Raises
    ------
    InputDataError
        If the file is missing or cannot be read as its format (the message names
        it, and the variable or record), an ADCIRC ASCII output is read without
        ``mesh``, or its node count differs from the mesh's.
    FormatError
        If the file is none of the formats read; the message lists them.
    ConfigError
        If ``crs`` is not a CRS.

    Notes
    -----
    **ANUGA** ``.sww``: nodes ``x + xllcorner``, ``y + yllcorner`` (float64),
    triangles ``volumes``; times ``time``, seconds after ``starttime``. Every
    variable on the points (``stage``, ``xmomentum``, ``ymomentum``,
    ``elevation``, ``friction``, ...) or on the triangles (the centroid values
    ``stage_c``, ...). Added: ``u = xmomentum / h`` and ``v = ymomentum / h``
    with ``h = stage - elevation`` (or the stored ``height``), and ``u = v = 0``
    where ``h <= DRY_HEIGHT`` (1 mm, as ANUGA's ``plot_utils.get_output``; the
    solver's own ``minimum_allowed_height`` is 1e-5 m). Roles ``u``, ``v``,
    ``elevation = stage``, ``bed = elevation``. CRS: the ``epsg`` attribute
    (ANUGA 4 writes it), else UTM ``zone`` on ``datum`` (WGS84: EPSG 326zz or
    327zz) in the ``hemisphere`` (if undefined, the one its ``false_northing``
    belongs to: 0 north, 10 000 000 south); None for zone -1 (no UTM zone).

    **SCHISM** ``out2d_*.nc``: nodes ``SCHISM_hgrid_node_x/y``, faces
    ``SCHISM_hgrid_face_nodes`` (1-based; -1 or the fill value after the third
    node of a triangle); every variable on the nodes or faces, with a time axis
    or not; ``bed = -depth`` added. Roles ``elevation``, ``u =
    depthAverageVelX``, ``v = depthAverageVelY``, ``bed``. The older
    ``schout_*.nc``: ``elev`` and ``dahv`` (split into ``dahv_x``, ``dahv_y``).
    CRS: SCHISM writes one (global attribute ``crs``, and a grid mapping
    ``crs``) only for lon/lat grids (``ics = 2``: EPSG:4326); else None.

    **ADCIRC** netCDF: nodes ``x``, ``y``, triangles ``element`` (1-based);
    ``zeta``, ``u-vel``, ``v-vel``, ``zeta_max``, ``time_of_zeta_max``,
    ``vel_max``, ``time_of_vel_max``, ``depth``... with -99999 as NaN (dry);
    ``bed = -depth`` added. Roles ``elevation = zeta``, ``u``, ``v``,
    ``elevation_max = zeta_max``, ``speed_max = vel_max``, ``bed``. CRS:
    EPSG:4326, as ADCIRC's spherical runs (``ICS = 2``) store lon/lat in
    degrees; None if ``x`` is marked Cartesian (``ICS = 1``). ASCII: a header
    line, ``NDSETS NP DT NSPOOL IRTYPE``, then per record ``TIME IT`` (sparse:
    ``TIME IT NNONDEF DEFVAL``) and one line ``node value(s)`` per node, as
    ADCIRC's ``globalio.F`` writes them. ``fort.63`` gives ``zeta``,
    ``fort.64`` ``u-vel`` and ``v-vel`` (time, node); ``maxele.63`` gives
    ``zeta_max`` and ``maxvel.63`` ``vel_max`` from the first record, and the
    second record, if there, as ``time_of_zeta_max`` or ``time_of_vel_max``
    (node). The nodes, triangles and CRS are the mesh's (EPSG:4326 if it has
    none and its coordinates are lon/lat), ``depth`` and ``bed`` its depth. The
    ASCII files are read whole, into float64 arrays.

    **UGRID**: the variable with ``cf_role = "mesh_topology"`` and
    ``topology_dimension = 2``, its ``node_coordinates`` and
    ``face_node_connectivity`` (``start_index``, ``_FillValue`` or a negative
    index for faces of fewer nodes); every variable on its node or face
    dimension, with the time axis (the dimension of ``time``) or not. Roles
    from CF standard names, where one variable has that name (on the nodes,
    else anywhere): ``sea_surface_height`` -> ``elevation``,
    ``sea_water_x_velocity`` -> ``u``, ``altitude`` -> ``bed``, ...; a
    ``depth`` with ``positive = "down"`` gives ``bed = -depth``. CRS: the grid
    mapping of the coordinates, topology or variables (its ``epsg`` or
    ``EPSG_code`` first, as Delft3D FM writes them), else None.

    **VTU**: the points (x, y; z is left out); triangle, quad and polygon cells
    (other cells are left out); point data on the nodes, cell data on the
    triangles (a vector's components as ``name_x``, ``name_y``, ``name_z``). No
    time, no roles.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io import write_mesh
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, "EPSG:32630",
    ...          {"depth": [5.0, 6.0, 7.0, 8.0]})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.nc"
    >>> write_mesh(path, m)
    >>> source = read_field_source(path)
    >>> source.kind, source.crs.to_epsg(), source.roles["bed"]
    ('ugrid', 32630, 'bed')
    >>> source.variables["bed"].values.tolist()
    [-5.0, -6.0, -7.0, -8.0]
    """
    name = check_input(path)
    given = _given_crs(crs)
    with open(name, "rb") as file:
        magic = file.read(8)
    if magic[:3] == b"CDF" or magic == b"\x89HDF\r\n\x1a\n":
        source = _read_netcdf(name, given)
    elif name.lower().endswith(".vtu") or magic[:5] in (b"<?xml", b"<VTKF"):
        source = _read_vtu(name, given)
    elif _adcirc_ascii_header(name) is not None:
        source = _read_adcirc_ascii(name, mesh, given)
    else:
        raise FormatError(f"{name}: not a field source coastmesh reads; {_READS}")
    logger.debug(
        "%s: %s, %d nodes, %d triangles, %s records, variables %s",
        name,
        source.kind,
        len(source.points),
        len(source.triangles),
        "no" if source.times is None else len(source.times),
        ", ".join(source.variables),
    )
    return source


def _given_crs(crs: Any) -> CRS | None:
    """Return the CRS the caller gave, checked; None if none was."""
    try:
        return None if crs is None else CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"crs={crs!r}: not a CRS pyproj knows ({exc})") from None


def _source(name: str, kind: str, *args: Any) -> FieldSource:
    """Build a FieldSource; a part that does not fit names the file."""
    try:
        return FieldSource(Path(name), kind, *args)
    except ValueError as exc:
        raise InputDataError(f"not a valid {kind} source: {exc}", path=name) from None


def _read_netcdf(name: str, given: CRS | None) -> FieldSource:
    """Read a netCDF source: ANUGA, SCHISM, ADCIRC or any UGRID file."""
    try:
        dataset = xr.open_dataset(
            name,
            engine="netcdf4",
            decode_times=False,
            decode_timedelta=False,
            decode_coords=False,
        )
    except (OSError, ValueError, RuntimeError) as exc:
        raise InputDataError(f"not a readable netCDF file ({exc})", path=name) from None
    names = set(map(str, dataset.variables))
    if "SCHISM_hgrid_node_x" in names:
        reader = _read_schism
    elif {"x", "y", "volumes"} <= names:
        reader = _read_anuga
    elif {"x", "y", "element"} <= names:
        reader = _read_adcirc_netcdf
    elif _topologies(dataset):
        reader = _read_ugrid
    else:
        dataset.close()
        raise FormatError(
            f"{name}: a netCDF file with no mesh coastmesh knows (no ANUGA, SCHISM "
            f"or ADCIRC variables, no UGRID 2D mesh topology); {_READS}"
        )
    try:
        return reader(dataset, name, given)
    except BaseException:
        dataset.close()
        raise


@dataclass(frozen=True, slots=True)
class _Layout:
    """Where a netCDF file keeps its mesh: the dimension names and the faces."""

    node: str
    face: str
    time: str | None
    face_of: NDArray[np.int64] | None  # the face of each triangle, if split
    skip: frozenset[str]


def _netcdf_source(
    dataset: Any, name: str, mesh: tuple[Any, Any, Any], start: int
) -> tuple[NDArray[np.float64], NDArray[np.int64], _Layout, NDArray[np.float64] | None]:
    """Read the nodes and faces of a netCDF mesh; return them, its layout, times."""
    x, y, faces = mesh
    points = np.column_stack([np.asarray(v.values, dtype=np.float64) for v in (x, y)])
    start = int(faces.attrs.get("start_index", start))
    triangles, face_of = _fan(faces.values, start, len(points), name, faces.name)
    time = _time_variable(dataset)
    layout = _Layout(
        x.dims[0],
        faces.dims[0],
        None if time is None else str(dataset[time].dims[0]),
        face_of,
        frozenset({str(x.name), str(y.name), str(faces.name), str(time)}),
    )
    times = None if time is None else _seconds(dataset[time], name)
    return points, triangles, layout, times


def _fan(
    faces: Any, start: int, n: int, name: str, variable: Any
) -> tuple[NDArray[np.int64], NDArray[np.int64] | None]:
    """Split faces into triangles from their first node; the face of each one.

    A NaN (a fill value xarray masked) or an index below ``start`` (-1, or
    SCHISM's 0 for 1-based faces) ends a face. The face of each triangle is None
    when every face is a triangle (the triangles are the faces).
    """
    values = np.asarray(faces, dtype=np.float64)
    if values.ndim != 2 or values.shape[1] < 3:
        raise InputDataError(
            f"variable {variable!r} has shape {values.shape}; expected (faces, k >= 3)",
            path=name,
        )
    valid = np.isfinite(values) & (values >= start)
    counts = valid.sum(axis=1)
    leading = np.arange(values.shape[1]) < counts[:, None]
    if (counts < 3).any() or (valid != leading).any():
        row = int(np.flatnonzero((counts < 3) | (valid != leading).any(axis=1))[0])
        raise InputDataError(
            f"variable {variable!r}: face {row} has nodes {values[row].tolist()}; "
            "expected at least 3 indices, then only fill values",
            path=name,
        )
    index = np.where(valid, values, start).astype(np.int64) - start
    if index.size and index.max() >= n:
        raise InputDataError(
            f"variable {variable!r} has node index {int(index.max()) + start} "
            f"(start_index {start}); there are {n} nodes",
            path=name,
        )
    if (counts == 3).all():
        return index[:, :3], None
    parts, owners = [], []
    for k in np.unique(counts):
        rows = np.flatnonzero(counts == k)
        for j in range(1, int(k) - 1):
            parts.append(index[rows][:, [0, j, j + 1]])
            owners.append(rows)
    owner = np.concatenate(owners)
    order = np.argsort(owner, kind="stable")
    return np.concatenate(parts)[order], owner[order]


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


def _collect(
    dataset: Any, layout: _Layout, times: NDArray[np.float64] | None
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
            or dims not in _DIMS
            or var.dtype.kind not in "iuf"
            or coordinate
        ):
            continue
        out[str(key)] = _variable(var, dims, layout, times)
    return out


def _variable(
    var: Any, dims: tuple[str, ...], layout: _Layout, times: Any
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


def _negated(var: xr.DataArray, long_name: str) -> xr.DataArray:
    """Return minus a depth (positive down): a bed elevation, positive up."""
    return (-var).assign_attrs(long_name=long_name, units="m", positive="up")


def _read_anuga(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read an ANUGA ``.sww`` file."""
    attrs = dataset.attrs
    points, triangles, layout, times = _netcdf_source(
        dataset, name, (dataset["x"], dataset["y"], dataset["volumes"]), 0
    )
    points += [float(attrs.get("xllcorner", 0.0)), float(attrs.get("yllcorner", 0.0))]
    variables = _collect(dataset, layout, times)
    roles = {"elevation": "stage", "bed": "elevation"}
    roles = {role: key for role, key in roles.items() if key in variables}
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
    return _source(name, "anuga", points, triangles, crs, variables, times, roles)


def _anuga_crs(attrs: Mapping[str, Any]) -> CRS | None:
    """Return the CRS of an ``.sww`` file's georeference, as ANUGA finds it."""
    if int(attrs.get("epsg", 0) or 0) > 0:
        return CRS.from_epsg(int(attrs["epsg"]))
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


def _read_schism(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read a SCHISM 2D output (``out2d_*.nc``, or the older ``schout_*.nc``)."""
    for key in ("SCHISM_hgrid_node_y", "SCHISM_hgrid_face_nodes"):
        _need(dataset, key, name)
    mesh = tuple(
        dataset[f"SCHISM_hgrid_{v}"] for v in ("node_x", "node_y", "face_nodes")
    )
    points, triangles, layout, times = _netcdf_source(dataset, name, mesh, 1)
    variables = _collect(dataset, layout, times)
    if "dahv" in dataset.variables and layout.time is not None:
        dahv = dataset["dahv"]
        if dahv.dims[:2] == (layout.time, layout.node) and dahv.shape[2:] == (2,):
            for k, axis in enumerate("xy"):
                variables[f"dahv_{axis}"] = _variable(
                    dahv[..., k], ("time", "node"), layout, times
                )
    if "depth" in variables:
        variables["bed"] = _negated(variables["depth"], "bed elevation (-depth)")
    wanted = {
        "elevation": ("elevation", "elev"),
        "u": ("depthAverageVelX", "dahv_x"),
        "v": ("depthAverageVelY", "dahv_y"),
        "bed": ("bed",),
    }
    roles = {
        role: next(key for key in keys if key in variables)
        for role, keys in wanted.items()
        if any(key in variables for key in keys)
    }
    crs = given
    if crs is None and "crs" in dataset.attrs:
        crs = _crs_of(str(dataset.attrs["crs"]), name, "global attribute 'crs'")
    if crs is None and "crs" in dataset.variables:
        crs = crs_from_grid_mapping(dataset["crs"].attrs, name, "crs")
    return _source(name, "schism", points, triangles, crs, variables, times, roles)


def _crs_of(text: str, name: str, where: str) -> CRS:
    """Return the CRS a file's text names (``EPSG:4326``)."""
    try:
        return CRS.from_user_input(text)
    except CRSError as exc:
        raise InputDataError(
            f"{where} = {text!r} is not a CRS pyproj knows ({exc}); give crs=",
            path=name,
        ) from None


def _need(dataset: Any, key: str, name: str) -> None:
    """Raise if the file lacks a variable its format must have."""
    if key not in dataset.variables:
        raise InputDataError(
            f"has no variable {key!r}; it has {', '.join(map(str, dataset.variables))}",
            path=name,
        )


def _read_adcirc_netcdf(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read an ADCIRC netCDF output (``fort.63.nc``, ``maxvel.63.nc``, ...)."""
    mesh = (dataset["x"], dataset["y"], dataset["element"])
    points, triangles, layout, times = _netcdf_source(dataset, name, mesh, 1)
    variables = {}
    for key, found in _collect(dataset, layout, times).items():
        var = found
        peak = key.endswith("_max") or key.startswith("time_of_")
        if peak and var.dims[0] == "time" and var.sizes["time"] == 1:
            var = var.isel(time=0, drop=True)  # older ADCIRC: a time axis of one
        variables[key] = var.where(var != _ADCIRC_DRY) if var.dtype.kind == "f" else var
    if not any("time" in var.dims for var in variables.values()):
        times = None
    if "depth" in variables:
        variables["bed"] = _negated(variables["depth"], "bed elevation (-depth)")
    crs = given
    x = dataset["x"].attrs
    cartesian = "longitude" not in str(x.get("standard_name", "longitude"))
    if crs is None and not cartesian:
        crs = CRS.from_epsg(4326)
    roles = _adcirc_roles(variables)
    return _source(name, "adcirc", points, triangles, crs, variables, times, roles)


def _adcirc_roles(variables: Mapping[str, Any]) -> dict[str, str]:
    """Return the roles of ADCIRC's variables, of those the file has."""
    names = {
        "elevation": "zeta",
        "u": "u-vel",
        "v": "v-vel",
        "elevation_max": "zeta_max",
        "speed_max": "vel_max",
        "bed": "bed",
    }
    return {role: key for role, key in names.items() if key in variables}


def _topologies(dataset: Any) -> list[str]:
    """Return the names of the file's 2D UGRID mesh topology variables."""
    return [
        str(key)
        for key, var in dataset.variables.items()
        if var.attrs.get("cf_role") == "mesh_topology"
        and int(var.attrs.get("topology_dimension", 0)) == 2
    ]


def _read_ugrid(dataset: Any, name: str, given: CRS | None) -> FieldSource:
    """Read any UGRID file with one 2D mesh."""
    found = _topologies(dataset)
    if len(found) != 1:
        raise InputDataError(
            f"has {len(found)} 2D mesh topologies ({', '.join(found)}); expected one",
            path=name,
        )
    topology = found[0]
    attrs = dataset[topology].attrs
    coords = str(attrs.get("node_coordinates", "")).split()[:2]
    faces = str(attrs.get("face_node_connectivity", ""))
    for key in [*coords, faces]:
        _need(dataset, key, name)
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
    points, triangles, layout, times = _netcdf_source(dataset, name, mesh, 0)
    others = {
        k
        for k, v in dataset.variables.items()
        if v.attrs.get("mesh") not in (None, topology)
    }
    layout = replace(layout, skip=layout.skip | {topology} | {str(k) for k in others})
    variables = _collect(dataset, layout, times)
    roles = _ugrid_roles(variables)
    crs = (
        given
        if given is not None
        else _ugrid_crs(dataset, [*coords, topology, *variables], name)
    )
    return _source(name, "ugrid", points, triangles, crs, variables, times, roles)


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
                variables["bed"] = _negated(var, f"bed elevation (-{key})")
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
        epsg = int(attrs.get("epsg", 0) or 0)
        if epsg > 0:
            return CRS.from_epsg(epsg)
        if "EPSG_code" in attrs and str(attrs["EPSG_code"]).upper() not in (
            "EPSG:0",
            "",
        ):
            return _crs_of(str(attrs["EPSG_code"]), name, f"{mapping}:EPSG_code")
        return crs_from_grid_mapping(attrs, name, mapping)
    for mapping in ("projected_coordinate_system", "wgs84"):
        if mapping in dataset.variables:
            attrs = dataset[mapping].attrs
            if int(attrs.get("epsg", 0) or 0) > 0:
                return CRS.from_epsg(int(attrs["epsg"]))
    return None


def _read_vtu(name: str, given: CRS | None) -> FieldSource:
    """Read a ``.vtu`` file: its surface cells, point data and cell data."""
    import meshio.vtu

    data = read_with_meshio(meshio.vtu.read, name, "VTU")
    points = np.asarray(data.points, dtype=np.float64)[:, :2]
    parts, owners, blocks, offset = [], [], [], 0
    for k, block in enumerate(data.cells):
        if block.type not in ("triangle", "quad", "polygon"):
            continue
        triangles, face_of = _fan(block.data, 0, len(points), name, f"cells[{k}]")
        count = len(block.data)
        parts.append(triangles)
        owners.append(offset + (np.arange(count) if face_of is None else face_of))
        blocks.append(k)
        offset += count
    if not parts:
        raise FormatError(
            f"{name}: no triangle, quad or polygon cells; cell types: "
            f"{', '.join(block.type for block in data.cells) or 'none'}"
        )
    face_of = np.concatenate(owners)
    variables: dict[str, xr.DataArray] = {}
    for key, values in data.point_data.items():
        variables |= _components(str(key), np.asarray(values), "node")
    for key, arrays in data.cell_data.items():
        values = np.concatenate([np.asarray(arrays[k]) for k in blocks])
        variables |= _components(str(key), values[face_of], "triangle")
    triangles = np.concatenate(parts)
    return _source(name, "vtu", points, triangles, given, variables, None, {})


def _components(key: str, values: NDArray[Any], dim: str) -> dict[str, xr.DataArray]:
    """One DataArray of numbers, or one per component (``key_x``, ``key_y``...)."""
    if values.dtype.kind not in "iuf" or values.ndim not in (1, 2):
        return {}
    if values.ndim == 1:
        return {key: xr.DataArray(values, dims=(dim,))}
    width = values.shape[1]
    names = "xyz" if width <= 3 else [str(k) for k in range(width)]
    return {
        f"{key}_{names[k]}": xr.DataArray(values[:, k], dims=(dim,))
        for k in range(width)
    }


def _adcirc_ascii_header(name: str) -> tuple[int, int] | None:
    """``(NP, IRTYPE)`` of an ADCIRC ASCII output's 2nd line; None if not one."""
    try:
        with open(name, encoding="ascii", errors="replace") as file:
            file.readline(4096)
            tokens = file.readline(4096).split()
        int(tokens[0]), float(tokens[2]), int(tokens[3])
        return int(tokens[1]), int(tokens[4])
    except (ValueError, IndexError):
        return None


def _read_adcirc_ascii(
    name: str, mesh: str | os.PathLike[str] | Mesh | None, given: CRS | None
) -> FieldSource:
    """Read an ADCIRC ASCII output on the nodes of its grid."""
    count, irtype = _adcirc_ascii_header(name) or (0, 0)
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
    values[values == _ADCIRC_DRY] = np.nan
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
        variables["bed"] = _negated(variables["depth"], "bed elevation (-depth)")
    roles = _adcirc_roles(variables)
    crs = given if given is not None else grid.crs
    lonlat = (np.abs(grid.points) <= [360.0, 90.0]).all()
    if crs is None and lonlat:
        crs = CRS.from_epsg(4326)
    return _source(
        name, "adcirc", grid.points, grid.triangles, crs, variables, times, roles
    )


def _ascii_kind(name: str, irtype: int) -> tuple[tuple[str, ...], bool]:
    """Return the variables of a record, and whether it is a max file."""
    base = os.path.basename(name).lower()
    key = next((k for k in ("maxele", "maxvel") if k in base), base[-2:])
    found = _ADCIRC_ASCII.get(key)
    if found is None or len(found[0]) != irtype:
        raise FormatError(
            f"{name}: an ADCIRC ASCII output with IRTYPE = {irtype}, but not one "
            "read (by name: fort.63 and maxele.63, maxvel.63 with one value a node, "
            f"fort.64 with two); {_READS}"
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
            default = float(tokens[3]) if sparse else _ADCIRC_DRY
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
