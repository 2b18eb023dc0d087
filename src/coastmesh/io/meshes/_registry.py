"""Mesh formats: one registry for reading and writing, by name or by extension.

Each format is one :class:`MeshFormat` entry: a name, file extensions, a writer
and a reader (a format may have only one of them). :func:`read_mesh` and
:func:`write_mesh` pick the format from ``format=`` or else from the file name,
as meshio's ``read``/``write`` do (``src/meshio/_helpers.py``); an unknown format
lists the known ones. The built-in formats (:mod:`coastmesh.io.meshes._builtin`) are
registered the first time the registry is used, in a fixed order: formats may
share an extension, and the file name then selects the one registered first, so
``.msh`` means msh 2.2 and msh 4.1 is asked for by name.

Another format joins by one :func:`register_mesh_format` call, with an atomic
writer (as :func:`coastmesh.io.meshes.msh.write_msh` is)::

    register_mesh_format(
        MeshFormat("fort14", (".14", ".grd"), write_fort14, "ADCIRC fort.14",
                   read=read_fort14_mesh)
    )
"""

from __future__ import annotations

import importlib
import logging
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from coastmesh.errors import ConfigError, FormatError
from coastmesh.io._atomic import check_output
from coastmesh.io.meshes._mesh_format import MeshFormat
from coastmesh.io.meshes._model import check_mesh
from coastmesh.types import Mesh

__all__ = [
    "format_for_path",
    "formats_table",
    "mesh_format",
    "mesh_formats",
    "read_mesh",
    "register_mesh_format",
    "write_mesh",
]

logger = logging.getLogger(__name__)

_FORMATS: dict[str, MeshFormat] = {}
# registers the built-in formats when imported
_BUILT_IN = "coastmesh.io.meshes._builtin"


def register_mesh_format(fmt: MeshFormat) -> None:
    """Add a mesh format to the registry.

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
    formats = _registry()
    if fmt.name in formats:
        raise FormatError(f"mesh format {fmt.name!r} is already registered")
    formats[fmt.name] = fmt


def mesh_formats() -> dict[str, MeshFormat]:
    """Return the registered mesh formats.

    Returns
    -------
    dict of str to MeshFormat
        A new dict, by name, in registration order.

    Examples
    --------
    >>> {name: fmt.mode for name, fmt in mesh_formats().items()}
    ... # doctest: +NORMALIZE_WHITESPACE
    {'msh2': 'read and write', 'msh4': 'read and write', 'gpkg': 'read and write',
     'fort14': 'read and write', 'gr3': 'read and write', 'selafin': 'read and write',
     'mike': 'read and write', 'ugrid': 'read and write', 'vtu': 'read and write'}
    """
    return dict(_registry())


def mesh_format(name: str) -> MeshFormat:
    """Return the mesh format called ``name``.

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
    >>> fmt = mesh_format("MSH4")
    >>> fmt.name, fmt.model, sorted(fmt.holds)
    ('msh4', 'Gmsh 4', ['ids', 'lines', 'regions', 'sphere_xyz'])
    """
    formats = _registry()
    key = name.lower() if isinstance(name, str) else name
    if key not in formats:
        raise ConfigError(f"unknown mesh format {name!r}; pick one of {_listing()}")
    return formats[key]


def format_for_path(path: str | os.PathLike[str]) -> MeshFormat:
    """Return the mesh format that a file name selects.

    Parameters
    ----------
    path : str or path-like
        The file. Its name's ending is matched against the formats' extensions,
        ignoring case; the longest match wins, and of formats sharing it, the one
        registered first.

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
    formats = _registry()
    file_name = Path(path).name.lower()
    found = [
        (len(ext), -order, fmt)
        for order, fmt in enumerate(formats.values())
        for ext in fmt.extensions
        if file_name.endswith(ext)
    ]
    if not found:
        suffix = Path(path).suffix
        shown = f"extension {suffix!r}" if suffix else "no extension"
        known = sorted({ext for fmt in formats.values() for ext in fmt.extensions})
        raise FormatError(
            f"{os.fspath(path)}: unknown mesh format ({shown}); pick one of "
            f"{', '.join(known)}, or give the format by name ({_listing()})"
        )
    return max(found, key=lambda item: item[:2])[2]


def read_mesh(
    path: str | os.PathLike[str],
    *,
    format: str | None = None,
    crs: Any = None,
    **options: Any,
) -> Mesh:
    """Read a mesh file of any registered format that has a reader.

    Parameters
    ----------
    path : str or path-like
        The file.
    format : str, optional
        A format name (:func:`mesh_formats`); by default the file name picks it
        (:func:`format_for_path`).
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the coordinates, for formats and files that store none (msh,
        VTU, a fort.14 from another tool); where the file stores one, they must
        agree.
    **options
        Options of the format's reader, such as ``positive`` (the sign of the
        file's depth) for ``fort14``, ``gr3`` and ``mike``.

    Returns
    -------
    Mesh
        What the format holds: see each reader (the table in
        ``docs/formats.md``). Depth, where the format has it, is
        ``point_data["depth"]`` in metres, positive down.

    Raises
    ------
    ConfigError
        If ``format`` is unknown, or its reader takes no such option.
    FormatError
        If the file name selects no format, the format is write only, or the file
        cannot be read as that format.
    InputDataError
        If the file is missing or its contents are not a valid mesh; the message
        names the file, and the line or variable.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, "EPSG:32630", {"depth": [3.0, 4.0, 5.0]},
    ...          {2: "sea"}, {1: "shoreline", 2: "open"})
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.nc"
    >>> write_mesh(path, m)
    >>> back = read_mesh(path)
    >>> back.boundary_names, back.crs.to_epsg(), back.point_data["depth"].tolist()
    ({2: 'sea'}, 32630, [3.0, 4.0, 5.0])
    """
    fmt = format_for_path(path) if format is None else mesh_format(format)
    if fmt.read is None:
        raise FormatError(
            f"{os.fspath(path)}: the {fmt.name} format is write only; formats "
            f"that can be read: {_listing('read')}"
        )
    _check_options(fmt, "read", options, path)
    mesh = fmt.read(path, crs=crs, **options)
    logger.debug(
        "read %s as %s: %d nodes, %d triangles, %d boundary edges",
        path,
        fmt.name,
        len(mesh.points),
        len(mesh.triangles),
        len(mesh.boundary_edges),
    )
    return mesh


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
        The output file; it comes first, as in every writer of coastmesh (and
        ``meshio.write(filename, mesh)``).
    mesh : Mesh
        The mesh; it is not changed.
    format : str, optional
        A format name (:func:`mesh_formats`); by default the file name picks it
        (:func:`format_for_path`): ``.msh`` is msh 2.2, ``.gpkg`` a GeoPackage.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    **options
        Options of the format's writer: ``binary``, ``sphere_xyz`` and
        ``radius`` for ``msh2`` and ``msh4``, ``metadata`` (mapping of str to
        str) for ``gpkg``, ``positive`` for the model formats, ...

    Raises
    ------
    ConfigError
        If ``format`` is unknown, or the format takes no such option.
    FormatError
        If ``format`` is not given and the file name selects no format, the
        format is read only, or it cannot hold the mesh.
    TypeError
        If ``mesh`` is not a :class:`~coastmesh.types.Mesh`, or a Mesh is given
        first (the path comes first).
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, None)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "tri.msh"
    >>> write_mesh(path, m)
    >>> read_mesh(path).boundary_ids.tolist()
    [1, 1, 2]
    >>> write_mesh(m, path)
    Traceback (most recent call last):
    ...
    TypeError: write_mesh(path, mesh): the path comes first, then the mesh ...
    """
    if isinstance(path, Mesh):
        raise TypeError(
            "write_mesh(path, mesh): the path comes first, then the mesh (as in "
            f"meshio.write(filename, mesh)); got a Mesh, then {type(mesh).__name__}"
        )
    fmt = format_for_path(path) if format is None else mesh_format(format)
    if fmt.write is None:
        raise FormatError(
            f"{os.fspath(path)}: the {fmt.name} format is read only; formats that "
            f"can be written: {_listing('write')}"
        )
    check_mesh(mesh)
    _check_options(fmt, "write", options, path)
    check_output(path, overwrite=overwrite)
    fmt.write(path, mesh, overwrite=overwrite, **options)
    logger.debug(
        "wrote %s as %s: %d nodes, %d triangles",
        path,
        fmt.name,
        len(mesh.points),
        len(mesh.triangles),
    )


def formats_table() -> str:
    """Return the registered mesh formats as a Markdown table.

    One row per format: its name, extensions, the models that read it, what its
    files hold, the sign of its depths and whether it is read back. It is the
    table of ``docs/formats.md`` and what ``coastmesh formats`` prints.

    Examples
    --------
    >>> print(formats_table().splitlines()[2])  # doctest: +ELLIPSIS
    | `msh2` | `.msh` | Fluidity, Thetis/Firedrake | Gmsh msh 2.2: ...
    """
    rows = [
        "| name | extensions | model | the file | holds | depth sign | read |",
        "|---|---|---|---|---|---|---|",
    ]
    for fmt in _registry().values():
        extensions = ", ".join(f"`{e}`" for e in fmt.extensions)
        extensions += "".join(f" (+ `{e}`)" for e in fmt.companions)
        extensions += "".join(f" (+ `{e}` with regions)" for e in fmt.region_companions)
        holds = ", ".join(sorted(fmt.holds)) or "-"
        sign = {"down": "down", "up": "up (elevation)", None: "(no depth)"}
        read = "yes" if fmt.read is not None else "no (write only)"
        rows.append(
            f"| `{fmt.name}` | {extensions} | {fmt.model} | {fmt.description} | "
            f"{holds} | {sign[fmt.positive]} | {read} |"
        )
    return "\n".join(rows) + "\n"


def _check_options(
    fmt: MeshFormat, role: str, options: Mapping[str, Any], path: Any
) -> None:
    accepted = fmt.options if role == "write" else fmt.read_options
    unknown = sorted(set(options) - set(accepted)) if accepted is not None else []
    if unknown:
        takes = ", ".join(accepted or ()) or "none"
        doing = "writing" if role == "write" else "reading"
        raise ConfigError(
            f"{os.fspath(path)}: mesh format {fmt.name!r} has no option "
            f"{unknown[0]!r} for {doing}; its options: {takes}"
        )


def _listing(role: str | None = None) -> str:
    """List the format names (with ``role``), each with its mode if it lacks one."""
    return ", ".join(
        name if fmt.mode == "read and write" or role else f"{name} ({fmt.mode})"
        for name, fmt in _registry().items()
        if role is None or getattr(fmt, role) is not None
    )


def _registry() -> dict[str, MeshFormat]:
    """Return the registry, the built-in formats registered on first use."""
    importlib.import_module(_BUILT_IN)  # once: then it is in sys.modules
    return _FORMATS
