"""The field source type, and the helpers every format's reader shares.

:class:`FieldSource` is what
:func:`~coastmesh.io.fields.field_sources.read_field_source` returns whatever the
format (the formats are listed in :mod:`coastmesh.io.fields.field_sources`): nodes,
triangles, a CRS, variables on the
nodes or triangles and their roles. Beside it are the parts the format modules
share: the CRS the caller gives or the file names, a FieldSource built so that
a part that does not fit names the file, the fan split of faces into triangles,
the roles a format's variable names give, and a bed elevation from a depth.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import ConfigError, InputDataError

__all__ = [
    "DIMS",
    "KINDS",
    "READS",
    "ROLES",
    "FieldSource",
    "bed_elevation",
    "build_source",
    "crs_of",
    "epsg_crs",
    "given_crs",
    "roles_of",
    "split_faces",
]

#: The kinds of source, as :attr:`FieldSource.kind` names them.
KINDS = ("anuga", "schism", "adcirc", "ugrid", "vtu")
#: The roles a format can give its variables (:attr:`FieldSource.roles`).
ROLES = ("u", "v", "elevation", "bed", "speed_max", "elevation_max")
#: The dimensions a variable can have.
DIMS = (("time", "node"), ("node",), ("time", "triangle"), ("triangle",))
#: What :func:`~coastmesh.io.fields.field_sources.read_field_source` reads, for
#: messages.
READS = (
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
        if var.dims not in DIMS:
            raise ValueError(f"variable {name!r} has dims {var.dims}; expected {DIMS}")
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


def build_source(name: str, kind: str, *args: Any) -> FieldSource:
    """Build a FieldSource; a part that does not fit names the file."""
    try:
        return FieldSource(Path(name), kind, *args)
    except ValueError as exc:
        raise InputDataError(f"not a valid {kind} source: {exc}", path=name) from None


def given_crs(crs: Any) -> CRS | None:
    """Return the CRS the caller gave, checked; None if none was."""
    try:
        return None if crs is None else CRS.from_user_input(crs)
    except CRSError as exc:
        raise ConfigError(f"crs={crs!r}: not a CRS pyproj knows ({exc})") from None


def crs_of(text: str, name: str, where: str) -> CRS:
    """Return the CRS a file's text names (``EPSG:4326``)."""
    try:
        return CRS.from_user_input(text)
    except CRSError as exc:
        raise InputDataError(
            f"{where} = {text!r} is not a CRS pyproj knows ({exc}); give crs=",
            path=name,
        ) from None


def epsg_crs(attrs: Mapping[str, Any]) -> CRS | None:
    """Return the CRS of an ``epsg`` attribute; None if there is none, or 0."""
    epsg = int(attrs.get("epsg", 0) or 0)
    return CRS.from_epsg(epsg) if epsg > 0 else None


def split_faces(
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


def roles_of(
    variables: Mapping[str, Any], wanted: Mapping[str, tuple[str, ...]]
) -> dict[str, str]:
    """Role -> the first of its names the variables have; roles with none left out."""
    roles = {}
    for role, keys in wanted.items():
        found = next((key for key in keys if key in variables), None)
        if found is not None:
            roles[role] = found
    return roles


def bed_elevation(depth: xr.DataArray, key: str = "depth") -> xr.DataArray:
    """Return minus a depth (positive down): a bed elevation, positive up."""
    return (-depth).assign_attrs(
        long_name=f"bed elevation (-{key})", units="m", positive="up"
    )
