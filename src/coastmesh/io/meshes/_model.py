"""What the model-format writers take from a mesh, checked once for all of them.

The ADCIRC/SCHISM, MIKE, Telemac, UGRID and VTU writers all need some of: the depth
at each node with the sign the format wants, a kind (open or shoreline) for every
boundary id, the boundary edges ordered into rings or node strings, and node data
as plain numeric arrays. Each check names the output file in its message, so an
error says which of several outputs it is about.
"""

from __future__ import annotations

import os
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import CoastmeshWarning, ConfigError, FormatError
from coastmesh.io.meshes.sphere import (
    on_sphere,
    sphere_boundary_rings,
    sphere_boundary_strings,
)
from coastmesh.types import Mesh
from coastmesh.types.topology import (
    BoundaryRing,
    BoundaryString,
    boundary_rings,
    boundary_strings,
)

__all__ = [
    "POSITIVE",
    "check_mesh",
    "index_dtype",
    "mesh_boundary_rings",
    "mesh_boundary_strings",
    "node_depth",
    "point_values",
    "require_kinds",
]

POSITIVE = ("down", "up")


def check_mesh(mesh: object) -> Mesh:
    """Return ``mesh`` if it is a :class:`~coastmesh.types.Mesh`; raise otherwise.

    Parameters
    ----------
    mesh : object
        What a writer was given.

    Returns
    -------
    Mesh

    Raises
    ------
    TypeError
        If ``mesh`` is not a Mesh.

    Examples
    --------
    >>> check_mesh({"points": []})
    Traceback (most recent call last):
    ...
    TypeError: mesh is a dict, expected a Mesh
    """
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    return mesh


def node_depth(
    mesh: Mesh,
    name: str,
    *,
    positive: str,
    label: str = "depth",
    stacklevel: int = 2,
) -> NDArray[np.float64]:
    """Return the value to write at each node: the depth, with the sign asked for.

    Parameters
    ----------
    mesh : Mesh
        Its ``point_data["depth"]`` (metres, positive down), if any.
    name : str
        The output file, for messages.
    positive : {"down", "up"}
        ``"down"`` returns the depth, ``"up"`` its negative (the bed elevation).
    label : str, default "depth"
        What the format calls the value (``BOTTOM``, ``z``), for the warning.
    stacklevel : int, default 2
        Passed to :func:`warnings.warn`: make it point at the public writer's caller.

    Returns
    -------
    ndarray of shape (N,)
        float64; zeros (with a warning) if the mesh has no depth.

    Raises
    ------
    ConfigError
        If ``positive`` is not ``"down"`` or ``"up"``.
    FormatError
        If the depth is not one finite number per node.

    Warns
    -----
    CoastmeshWarning
        If the mesh has no ``depth`` point data.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, None,
    ...          point_data={"depth": [5.0, 6.0, 7.0]})
    >>> node_depth(m, "fort.14", positive="up").tolist()
    [-5.0, -6.0, -7.0]
    """
    if positive not in POSITIVE:
        raise ConfigError(
            f"{name}: positive={positive!r}; expected one of {', '.join(POSITIVE)}"
        )
    n = len(mesh.points)
    if "depth" not in mesh.point_data:
        warnings.warn(
            f"{name}: the mesh has no point_data['depth']; writing {label} 0 at all "
            f"{n} nodes",
            CoastmeshWarning,
            stacklevel=stacklevel,
        )
        return np.zeros(n)
    depth = np.asarray(mesh.point_data["depth"])
    if depth.shape != (n,) or depth.dtype.kind not in "biuf":
        raise FormatError(
            f"{name}: point_data['depth'] has shape {depth.shape} and dtype "
            f"{depth.dtype}; expected ({n},) numbers, metres positive down"
        )
    depth = depth.astype(np.float64)
    bad = ~np.isfinite(depth)
    if bad.any():
        node = int(np.flatnonzero(bad)[0])
        raise FormatError(
            f"{name}: point_data['depth'] is {depth[node]} at node {node} "
            f"({int(bad.sum())} nodes are not finite); fill the depth first"
        )
    return depth if positive == "down" else -depth


def require_kinds(mesh: Mesh, name: str, *, hint: str = "") -> dict[int, str]:
    """Return the kind of every boundary id of ``mesh``; raise if one has none.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    name : str
        The output file, for messages.
    hint : str, optional
        More advice for the message, such as another option of the writer.

    Returns
    -------
    dict of int to str
        ``"open"`` or ``"shoreline"`` for each id in ``mesh.boundary_ids``.

    Raises
    ------
    FormatError
        If an id has no kind; the message names the ids and their names.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, None, boundary_names={2: "sea"})
    >>> require_kinds(m, "fort.14")
    Traceback (most recent call last):
    ...
    coastmesh.errors.FormatError: fort.14: boundary id(s) 1, 2 ('sea') have no kind; ...
    """
    ids = sorted({int(i) for i in np.unique(mesh.boundary_ids)})
    missing = [i for i in ids if i not in mesh.boundary_kinds]
    if missing:
        named = ", ".join(
            f"{i} ({mesh.boundary_names[i]!r})" if i in mesh.boundary_names else str(i)
            for i in missing
        )
        raise FormatError(
            f"{name}: boundary id(s) {named} have no kind; this format separates open "
            "from land boundaries, so give every id a kind, such as "
            f"boundary_kinds={{{missing[0]}: 'open'}} (or 'shoreline'){hint}"
        )
    return {i: mesh.boundary_kinds[i] for i in ids}


def mesh_boundary_rings(mesh: Mesh, name: str) -> list[BoundaryRing]:
    """Return the mesh's boundary rings; errors name the output file ``name``.

    The rings of :func:`~coastmesh.types.topology.boundary_rings`, with the
    parameters and errors of :func:`mesh_boundary_strings`; for a mesh on the
    sphere (:func:`~coastmesh.io.meshes.sphere.on_sphere`), those of
    :func:`~coastmesh.io.meshes.sphere.sphere_boundary_rings`.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, None)
    >>> [ring.nodes.tolist() for ring in mesh_boundary_rings(m, "m.slf")]
    [[0, 1, 2]]
    """
    order = sphere_boundary_rings if on_sphere(mesh) else boundary_rings
    return _named(order, mesh, name)


def mesh_boundary_strings(mesh: Mesh, name: str) -> list[BoundaryString]:
    """Return the mesh's boundary node strings; errors name the output file.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    name : str
        The output file, for messages.

    Returns
    -------
    list of BoundaryString
        As :func:`~coastmesh.types.topology.boundary_strings` splits them; for
        a mesh on the sphere (:func:`~coastmesh.io.meshes.sphere.on_sphere`), as
        :func:`~coastmesh.io.meshes.sphere.sphere_boundary_strings` does.

    Raises
    ------
    FormatError
        If the boundary edges do not form simple rings.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 2], 1, None)
    >>> [s.nodes.tolist() for s in mesh_boundary_strings(m, "fort.14")]
    [[0, 1, 2], [2, 0]]
    """
    order = sphere_boundary_strings if on_sphere(mesh) else boundary_strings
    return _named(order, mesh, name)


def point_values(key: str, values: Any, n: int, name: str) -> NDArray[Any]:
    """Return one ``point_data`` entry as numbers of shape (N,) or (N, k).

    Parameters
    ----------
    key : str
        The entry's name, for messages.
    values : array_like
        Its values; booleans become uint8.
    n : int
        The number of nodes.
    name : str
        The output file, for messages.

    Returns
    -------
    ndarray of shape (N,) or (N, k)

    Raises
    ------
    FormatError
        If the values are not numbers of that shape.

    Examples
    --------
    >>> point_values("wet", [True, False], 2, "m.nc").tolist()
    [1, 0]
    """
    array = np.asarray(values)
    if array.dtype.kind == "b":
        array = array.astype(np.uint8)
    if array.dtype.kind not in "iuf" or array.ndim not in (1, 2) or len(array) != n:
        raise FormatError(
            f"{name}: point_data[{key!r}] has shape {array.shape} and dtype "
            f"{array.dtype}; expected numbers of shape ({n},) or ({n}, k)"
        )
    return array


def index_dtype(n: int) -> type[np.integer]:
    """Return the integer type for node indices: int32 while they fit, else int64.

    Parameters
    ----------
    n : int
        The number of nodes.

    Returns
    -------
    numpy integer type

    Examples
    --------
    >>> index_dtype(10).__name__, index_dtype(2**31).__name__
    ('int32', 'int64')
    """
    return np.int32 if n <= np.iinfo(np.int32).max else np.int64


def _named(order: Any, mesh: Mesh, name: str | os.PathLike[str]) -> Any:
    try:
        return order(mesh)
    except FormatError as exc:
        raise FormatError(f"{os.fspath(name)}: {exc}") from exc
