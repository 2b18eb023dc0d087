"""Mesh output formats: one registry, one entry per format.

=========  ==========  ===========================================================
name       extensions  what
=========  ==========  ===========================================================
``msh2``   ``.msh``    Gmsh msh 2.2, ASCII (or binary): read by Fluidity and Thetis
``msh4``   ``.msh``    Gmsh msh 4.1, ASCII (or binary); by name only
``gpkg``   ``.gpkg``   GeoPackage: layers ``triangles`` and ``boundaries``, for a GIS
=========  ==========  ===========================================================

:func:`write_mesh` picks the format from ``format=`` or else from the file name.
Formats may share an extension: the file name then selects the one registered
first, so ``.msh`` means msh 2.2 and msh 4.1 is asked for by name.
A model format joins by one :func:`register_mesh_format` call with a
:class:`MeshFormat` whose writer is atomic, as :func:`coastmesh.io.msh.write_msh` is
(meshio's ``register_format`` in ``src/meshio/_helpers.py`` works the same way)::

    register_mesh_format(
        MeshFormat("fort14", (".14", ".grd"), write_fort14, "ADCIRC fort.14")
    )
"""

from __future__ import annotations

import inspect
import logging
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from coastmesh.errors import ConfigError, FormatError
from coastmesh.io._atomic import check_output

# The model writers need only numpy, pyproj and coastmesh itself (their heavy
# readers and writers, meshio and xarray, are imported inside them), so they are
# registered as they are.
from coastmesh.io.adcirc import write_fort14, write_gr3
from coastmesh.io.mike import write_mike_mesh
from coastmesh.io.telemac import write_selafin
from coastmesh.io.ugrid import write_ugrid, write_vtu
from coastmesh.types import Mesh

__all__ = [
    "MeshFormat",
    "format_for_path",
    "mesh_format",
    "mesh_formats",
    "register_mesh_format",
    "write_mesh",
]

logger = logging.getLogger(__name__)

_FORMATS: dict[str, MeshFormat] = {}


@dataclass(frozen=True, slots=True)
class MeshFormat:
    """A mesh output format: its name, file extensions and writer.

    Parameters
    ----------
    name : str
        The name given as ``format=``; stored in lower case, no spaces.
    extensions : sequence of str
        File name endings of this format, at least one, each starting with
        ``"."`` (such as ``".msh"`` or ``".14"``); stored in lower case. The first
        is the one to give new files. A file name selects the format that
        registered its ending first (:func:`format_for_path`).
    write : callable
        ``write(path, mesh, *, overwrite, **options)``: writes ``mesh`` to
        ``path`` atomically and refuses an existing ``path`` unless
        ``overwrite``. Its other keyword parameters are the format's options.
    description : str
        One line for listings.

    Raises
    ------
    ValueError
        If the name or an extension is malformed, or ``write`` is not callable
        or takes no ``overwrite`` keyword.

    Examples
    --------
    >>> fmt = mesh_format("msh4")
    >>> fmt.extensions, fmt.options
    (('.msh',), ('binary',))
    """

    name: str
    extensions: tuple[str, ...]
    write: Callable[..., None]
    description: str

    def __post_init__(self) -> None:
        name = self.name
        if not isinstance(name, str) or not name or name != "".join(name.split()):
            raise ValueError(
                f"mesh format name {name!r}: expected a non-empty string without spaces"
            )
        extensions = (
            (self.extensions,)
            if isinstance(self.extensions, str)
            else tuple(self.extensions)
        )
        if not extensions:
            raise ValueError(
                f"mesh format {name!r}: give at least one extension, such as '.msh'"
            )
        for ext in extensions:
            if not isinstance(ext, str) or len(ext) < 2 or not ext.startswith("."):
                raise ValueError(
                    f"mesh format {name!r}: extension {ext!r} must be a string "
                    "starting with '.', such as '.msh'"
                )
        extensions = tuple(dict.fromkeys(ext.lower() for ext in extensions))
        if not callable(self.write):
            raise ValueError(f"mesh format {name!r}: write is not callable")
        if _options(self.write, name) is None and not _takes_kwargs(self.write):
            raise ValueError(
                f"mesh format {name!r}: write takes no 'overwrite' keyword; "
                "expected write(path, mesh, *, overwrite, ...)"
            )
        object.__setattr__(self, "name", name.lower())
        object.__setattr__(self, "extensions", extensions)
        object.__setattr__(self, "description", str(self.description))

    @property
    def options(self) -> tuple[str, ...] | None:
        """The writer's keyword options besides ``overwrite``; None for ``**kwargs``."""
        if _takes_kwargs(self.write):
            return None
        return _options(self.write, self.name)


def register_mesh_format(fmt: MeshFormat) -> None:
    """Add a mesh output format to the registry.

    Parameters
    ----------
    fmt : MeshFormat
        The format; its name must be new. An extension that another format
        has already keeps selecting that one.

    Raises
    ------
    TypeError
        If ``fmt`` is not a :class:`MeshFormat`.
    FormatError
        If a format of that name is registered.

    Examples
    --------
    >>> register_mesh_format(mesh_format("msh2"))
    Traceback (most recent call last):
    ...
    coastmesh.errors.FormatError: mesh format 'msh2' is already registered
    """
    if not isinstance(fmt, MeshFormat):
        raise TypeError(f"expected a MeshFormat, got {type(fmt).__name__}")
    if fmt.name in _FORMATS:
        raise FormatError(f"mesh format {fmt.name!r} is already registered")
    _FORMATS[fmt.name] = fmt


def mesh_formats() -> dict[str, MeshFormat]:
    """Return the registered mesh output formats.

    Returns
    -------
    dict of str to MeshFormat
        A new dict, by name, in registration order.

    Examples
    --------
    >>> list(mesh_formats())[:3]
    ['msh2', 'msh4', 'gpkg']
    """
    return dict(_FORMATS)


def mesh_format(name: str) -> MeshFormat:
    """Return the mesh output format called ``name``.

    Parameters
    ----------
    name : str
        A registered name, in any case.

    Returns
    -------
    MeshFormat

    Raises
    ------
    ConfigError
        If no format has that name; the message lists the known ones.

    Examples
    --------
    >>> mesh_format("MSH4").description
    'Gmsh msh 4.1'
    """
    key = name.lower() if isinstance(name, str) else name
    if key not in _FORMATS:
        raise ConfigError(
            f"unknown mesh format {name!r}; pick one of {', '.join(_FORMATS)}"
        )
    return _FORMATS[key]


def format_for_path(path: str | os.PathLike[str]) -> MeshFormat:
    """Return the mesh output format that a file name selects.

    Parameters
    ----------
    path : str or path-like
        The output file. Its name's ending is matched against the formats'
        extensions, ignoring case; the longest match wins, and of formats sharing
        it, the one registered first.

    Returns
    -------
    MeshFormat

    Raises
    ------
    FormatError
        If no format claims the ending; the message names the path and lists the
        known extensions.

    Examples
    --------
    >>> format_for_path("run/mesh.MSH").name
    'msh2'
    """
    file_name = Path(path).name.lower()
    found = [
        (len(ext), -order, fmt)
        for order, fmt in enumerate(_FORMATS.values())
        for ext in fmt.extensions
        if file_name.endswith(ext)
    ]
    if not found:
        suffix = Path(path).suffix
        shown = f"extension {suffix!r}" if suffix else "no extension"
        known = sorted({ext for fmt in _FORMATS.values() for ext in fmt.extensions})
        raise FormatError(
            f"{os.fspath(path)}: unknown mesh format ({shown}); pick one of "
            f"{', '.join(known)}, or give the format by name "
            f"({', '.join(_FORMATS)})"
        )
    return max(found, key=lambda item: item[:2])[2]


def write_mesh(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    format: str | None = None,
    overwrite: bool = False,
    **options: Any,
) -> None:
    """Write a mesh in one of the registered formats, atomically.

    Parameters
    ----------
    path : str or path-like
        The output file.
    mesh : Mesh
        The mesh; it is not changed.
    format : str, optional
        A format name (:func:`mesh_formats`); by default the file name picks it
        (:func:`format_for_path`): ``.msh`` is msh 2.2, ``.gpkg`` a GeoPackage.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    **options
        Options of the format's writer: ``binary`` for ``msh2`` and ``msh4``,
        ``metadata`` (mapping of str to str) for ``gpkg``.

    Raises
    ------
    ConfigError
        If ``format`` is unknown, or the format takes no such option.
    FormatError
        If ``format`` is not given and the file name selects no format.
    TypeError
        If ``mesh`` is not a :class:`~coastmesh.types.Mesh`.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Notes
    -----
    The GeoPackage holds layer ``triangles``, one polygon per triangle with field
    ``id`` (its row in ``mesh.triangles``, from 0), and layer ``boundaries``, one
    2-point LineString per boundary edge, in order, with field ``physical_id``;
    both in ``mesh.crs``. ``mesh.point_data`` is not written.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io.msh import read_msh
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, None)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.msh"
    >>> write_mesh(path, m)
    >>> read_msh(path).boundary_ids.tolist()
    [1, 1, 2]
    """
    fmt = format_for_path(path) if format is None else mesh_format(format)
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    accepted = fmt.options
    if accepted is not None:
        unknown = sorted(set(options) - set(accepted))
        if unknown:
            takes = ", ".join(accepted) if accepted else "none"
            raise ConfigError(
                f"{os.fspath(path)}: mesh format {fmt.name!r} has no option "
                f"{unknown[0]!r}; its options: {takes}"
            )
    check_output(path, overwrite=overwrite)
    fmt.write(path, mesh, overwrite=overwrite, **options)
    logger.debug(
        "wrote %s as %s: %d nodes, %d triangles",
        path,
        fmt.name,
        len(mesh.points),
        len(mesh.triangles),
    )


def _options(write: Callable[..., None], name: str) -> tuple[str, ...] | None:
    """Keyword options of ``write`` besides ``overwrite``; None if no overwrite."""
    try:
        parameters = list(inspect.signature(write).parameters.values())
    except (TypeError, ValueError):
        raise ValueError(
            f"mesh format {name!r}: the signature of write cannot be inspected"
        ) from None
    keyword = [
        p.name
        for p in parameters[2:]
        if p.kind in {p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY}
    ]
    if "overwrite" not in keyword:
        return None
    return tuple(k for k in keyword if k != "overwrite")


def _takes_kwargs(write: Callable[..., None]) -> bool:
    parameters = inspect.signature(write).parameters.values()
    return any(p.kind is p.VAR_KEYWORD for p in parameters)


def _write_msh2(
    path: str | os.PathLike[str], mesh: Mesh, *, overwrite: bool, binary: bool = False
) -> None:
    from coastmesh.io.msh import write_msh

    write_msh(path, mesh, version="2.2", binary=binary, overwrite=overwrite)


def _write_msh4(
    path: str | os.PathLike[str], mesh: Mesh, *, overwrite: bool, binary: bool = False
) -> None:
    from coastmesh.io.msh import write_msh

    write_msh(path, mesh, version="4.1", binary=binary, overwrite=overwrite)


def _write_gpkg(
    path: str | os.PathLike[str],
    mesh: Mesh,
    *,
    overwrite: bool,
    metadata: Mapping[str, str] | None = None,
) -> None:
    from coastmesh.io.domain_gpkg import write_layers

    write_layers(path, _mesh_layers(mesh), overwrite=overwrite, metadata=metadata)


def _mesh_layers(mesh: Mesh) -> dict[str, Any]:
    """Build the GeoPackage layers of a mesh: nodes, triangles, boundary edges."""
    from coastmesh.types import Features

    triangles = mesh.triangles
    edges = mesh.boundary_edges
    if len(triangles):
        corners = mesh.points[triangles]  # (M, 3, 2)
        polygons = shapely.polygons(np.concatenate([corners, corners[:, :1]], axis=1))
    else:
        polygons = np.empty(0, dtype=object)
    lines = (
        shapely.linestrings(mesh.points[edges])
        if len(edges)
        else np.empty(0, dtype=object)
    )
    triangle_ids = np.arange(len(triangles), dtype=np.int64)
    edge_ids = np.arange(len(edges), dtype=np.int64)
    node_ids = np.arange(len(mesh.points), dtype=np.int64)
    names = np.array(
        [mesh.boundary_names.get(int(i), "") for i in mesh.boundary_ids], dtype=object
    )
    kinds = np.array(
        [mesh.boundary_kinds.get(int(i), "") for i in mesh.boundary_ids], dtype=object
    )
    node_fields: dict[str, Any] = {"id": node_ids}
    for key, raw in mesh.point_data.items():
        values = np.asarray(raw)
        if values.ndim == 1 and np.issubdtype(values.dtype, np.number):
            node_fields[key] = values.astype(np.float64)
    return {
        "nodes": Features(
            geometry=shapely.points(mesh.points),
            crs=mesh.crs,
            fields=node_fields,
            fids=node_ids,
            path="<memory>",
            layer="nodes",
        ),
        "triangles": Features(
            geometry=polygons,
            crs=mesh.crs,
            fields={"id": triangle_ids},
            fids=triangle_ids,
            path="<memory>",
            layer="triangles",
        ),
        "boundaries": Features(
            geometry=lines,
            crs=mesh.crs,
            fields={"physical_id": mesh.boundary_ids, "name": names, "kind": kinds},
            fids=edge_ids,
            path="<memory>",
            layer="boundaries",
        ),
    }


for _fmt in (
    MeshFormat(
        "msh2", (".msh",), _write_msh2, "Gmsh msh 2.2 (Fluidity, Thetis); default .msh"
    ),
    MeshFormat("msh4", (".msh",), _write_msh4, "Gmsh msh 4.1"),
    MeshFormat(
        "gpkg",
        (".gpkg",),
        _write_gpkg,
        "GeoPackage: layers 'nodes' (id, depth, size), 'triangles' (id) and "
        "'boundaries' (physical_id, name, kind)",
    ),
    MeshFormat(
        "fort14",
        (".14", ".grd"),
        write_fort14,
        "ADCIRC fort.14: depth positive down, open and land boundary segments",
    ),
    MeshFormat(
        "gr3",
        (".gr3",),
        write_gr3,
        "SCHISM hgrid.gr3: depth positive down, open and land boundary segments",
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
    ),
    MeshFormat(
        "ugrid",
        (".nc",),
        write_ugrid,
        "UGRID-1.0 netCDF: mesh2d, depth on nodes, boundary_id on edges",
    ),
    MeshFormat(
        "vtu",
        (".vtu",),
        write_vtu,
        "VTK unstructured grid: triangles + boundary lines, point data",
    ),
):
    register_mesh_format(_fmt)
del _fmt
