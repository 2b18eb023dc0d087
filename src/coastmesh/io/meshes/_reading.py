"""What the mesh readers share: a Mesh from what a file held, triangles turned.

A reader builds its :class:`~coastmesh.types.Mesh` with :func:`mesh_from_file`, so
that values which do not make a mesh name the file, and turns clockwise
triangles with :func:`counter_clockwise` (on the sphere for lon/lat meshes). The
checks of the input path and the CRS are in :mod:`coastmesh.io._inputs`, beside
the bounding box check the raster and vector readers use.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import InputDataError
from coastmesh.geometry.sphere import lonlat_to_xyz
from coastmesh.io.meshes.sphere import misdrawn_triangles, solid_angles
from coastmesh.types import Mesh

__all__ = ["counter_clockwise", "mesh_from_file"]


def mesh_from_file(path: str | os.PathLike[str], *args: Any, **kwargs: Any) -> Mesh:
    """Build a :class:`~coastmesh.types.Mesh` from what a reader read.

    Parameters
    ----------
    path : str or path-like
        The file read, for messages.
    *args, **kwargs
        The arguments of :class:`~coastmesh.types.Mesh`.

    Returns
    -------
    Mesh

    Raises
    ------
    InputDataError
        If the values do not make a Mesh (such as a node index out of range, or
        a coordinate that is not finite); the message names the file.

    Examples
    --------
    >>> mesh_from_file("bad.14", [[0, 0], [1, 0]], [[0, 1, 2]], [], [], 1, None)
    Traceback (most recent call last):
    ...
    coastmesh.errors.InputDataError: bad.14: not a valid mesh: triangles has ...
    """
    try:
        return Mesh(*args, **kwargs)
    except ValueError as exc:
        raise InputDataError(f"not a valid mesh: {exc}", path=os.fspath(path)) from None


def counter_clockwise(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    *,
    sphere: bool = False,
) -> NDArray[np.int64]:
    """Return the triangles, those that run clockwise turned counter-clockwise.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Node coordinates.
    triangles : ndarray of shape (M, 3)
        Node indices.
    sphere : bool, default False
        The points are longitude, latitude in degrees: a triangle that crosses
        the antimeridian or has a node at a pole
        (:func:`~coastmesh.io.meshes.sphere.misdrawn_triangles`) is turned by which way
        it runs seen from outside the sphere, not in the lon/lat plane (where a
        counter-clockwise one crossing the antimeridian looks clockwise).

    Returns
    -------
    ndarray of shape (M, 3)
        A new array; a clockwise triangle ``(a, b, c)`` becomes ``(a, c, b)``.

    Examples
    --------
    >>> points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> counter_clockwise(points, np.array([[0, 2, 1], [0, 1, 2]])).tolist()
    [[0, 1, 2], [0, 1, 2]]
    >>> points = np.array([[179.0, 0.0], [-179.0, 0.0], [179.5, 1.0]])
    >>> counter_clockwise(points, np.array([[0, 1, 2]]), sphere=True).tolist()
    [[0, 1, 2]]
    """
    a, b, c = (points[triangles[:, k]] for k in range(3))
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (
        b[:, 1] - a[:, 1]
    )
    out = np.array(triangles, dtype=np.int64)
    flip = cross < 0
    if sphere and len(out):
        misdrawn = misdrawn_triangles(points, out)
        xyz = lonlat_to_xyz(points)
        flip[misdrawn] = solid_angles(xyz, out[misdrawn]) < 0
    out[flip] = out[flip][:, [0, 2, 1]]
    return out
