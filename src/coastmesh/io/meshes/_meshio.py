"""Meshes read through meshio (msh, VTU): the steps both readers share.

meshio's format readers are called directly (``meshio.read`` prints and exits on a
bad file). What they return is checked the same way: the file must be readable, a
flat 2D mesh (z = 0), with triangles of one surface id and, optionally, lines.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any
from xml.etree.ElementTree import ParseError

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import FormatError

__all__ = ["flat_points", "read_with_meshio", "split_cells", "surface_of"]


def read_with_meshio(read: Callable[[str], Any], name: str, what: str) -> Any:
    """Return ``read(name)``: a meshio Mesh; a file meshio cannot read raises.

    Parameters
    ----------
    read : callable
        A meshio format reader, such as ``meshio.gmsh.read``.
    name : str
        The file.
    what : str
        The format, for the message (``"msh"``).

    Returns
    -------
    meshio.Mesh

    Raises
    ------
    FormatError
        If meshio cannot read the file; the message names it.

    Examples
    --------
    >>> import meshio.gmsh, tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "junk.msh"
    >>> _ = path.write_text("not a mesh")
    >>> read_with_meshio(meshio.gmsh.read, str(path), "msh")
    Traceback (most recent call last):
    ...
    coastmesh.errors.FormatError: .../junk.msh: not a readable msh file (...)
    """
    import meshio

    try:
        return read(name)
    except (
        meshio.ReadError,
        ParseError,
        ValueError,
        KeyError,
        IndexError,
        EOFError,
    ) as exc:
        raise FormatError(f"{name}: not a readable {what} file ({exc})") from exc


def flat_points(data: Any, name: str) -> NDArray[np.float64]:
    """Return the (N, 2) points of a meshio Mesh; raise if a node has z != 0.

    Parameters
    ----------
    data : meshio.Mesh
        What a reader returned.
    name : str
        The file, for messages.

    Returns
    -------
    ndarray of shape (N, 2)

    Raises
    ------
    FormatError
        If a node has z != 0.

    Examples
    --------
    >>> import meshio
    >>> flat_points(meshio.Mesh([[0, 0, 0], [1, 0, 0]], []), "m.vtu").tolist()
    [[0.0, 0.0], [1.0, 0.0]]
    """
    points = np.asarray(data.points, dtype=np.float64)
    if points.shape[1] == 3 and np.any(points[:, 2] != 0):
        raise FormatError(f"{name}: nodes have z != 0; expected a flat 2D mesh")
    return points[:, :2]


def split_cells(
    data: Any, name: str, tags: Callable[[int], tuple[Any, Any]]
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]]:
    """Return the triangles, the lines, the lines' ids and the triangles' ids.

    Parameters
    ----------
    data : meshio.Mesh
        What a reader returned; cell blocks other than triangles and lines are
        left out.
    name : str
        The file, for messages.
    tags : callable
        ``tags(k)``: the (triangle ids, line ids) of the cells of block ``k``;
        only the one that fits the block's type is used.

    Returns
    -------
    triangles : ndarray of shape (M, 3)
    lines : ndarray of shape (E, 2)
    ids : ndarray of shape (E,)
    regions : ndarray of shape (M,)
        Each triangle's physical id (:func:`surface_of` picks the domain's).

    Raises
    ------
    FormatError
        If there are no triangles.

    Examples
    --------
    >>> import meshio
    >>> data = meshio.Mesh([[0, 0], [1, 0], [0, 1]],
    ...                    [("triangle", [[0, 1, 2]]), ("line", [[0, 1]])])
    >>> tri, lines, ids, regions = split_cells(data, "m", lambda k: ([7], [3]))
    >>> tri.tolist(), lines.tolist(), ids.tolist(), regions.tolist()
    ([[0, 1, 2]], [[0, 1]], [3], [7])
    """
    found: dict[str, tuple[list[Any], list[Any]]] = {
        "triangle": ([], []),
        "line": ([], []),
    }
    for k, block in enumerate(data.cells):
        if block.type in found:
            cells, ids = found[block.type]
            cells.append(np.asarray(block.data, dtype=np.int64))
            ids.append(np.asarray(tags(k)[block.type == "line"]).reshape(-1))
    triangles, surface = found["triangle"]
    if not triangles:
        raise FormatError(f"{name}: no triangles")
    lines, ids = found["line"]
    return (
        np.concatenate(triangles),
        np.concatenate(lines) if lines else np.empty((0, 2), dtype=np.int64),
        np.concatenate(ids).astype(np.int64) if ids else np.empty(0, dtype=np.int64),
        np.concatenate(surface).astype(np.int64),
    )


def surface_of(regions: NDArray[np.int64], named: int | None = None) -> int:
    """Return the domain's surface id among the triangles' ids.

    ``named``: the id the file names the domain (msh ``"domain"``), if that is
    one of them; else the id of the most triangles (the sea's), the smallest
    of a tie.

    Examples
    --------
    >>> surface_of(np.array([20, 1, 1, 100])), surface_of(np.array([20, 1]), 20)
    (1, 20)
    """
    ids, counts = np.unique(regions, return_counts=True)
    if named is not None and named in set(ids.tolist()):
        return int(named)
    return int(ids[np.argmax(counts)])
