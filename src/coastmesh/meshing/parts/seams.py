"""Smoothing across the cuts of a mesh made in parts, once the parts are joined.

Each part is cleaned and smoothed on its worker with the nodes of its cuts
held, so that its neighbour's mesh still meets it node for node. A triangle
whose nodes are all on the coast or a cut then cannot be improved by either
part: on the NW-shelf intermediate case in 4 parts, the mesh's worst radius
ratio (0.357, against 0.441 in one part) was such a triangle, where a cut meets
the coast. Once the parts are joined the cuts are plain interior nodes, so the
nodes of the cuts and their neighbours are smoothed again here, with the same
guarded kernel (:func:`~coastmesh.meshing.cleanup.smoothing.smooth_points`) on the
triangles around them only: a few per cent of the mesh.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from coastmesh.meshing.cleanup import smoothing

__all__ = ["smooth_seams"]


def smooth_seams(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    edges: NDArray[np.int64],
    seam: NDArray[np.int64],
    held: NDArray[np.bool_] | None = None,
) -> tuple[NDArray[np.float64], int]:
    """Smooth the nodes ``seam`` and their neighbours; every other node stays.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Nodes in a conformal plane (the meshing CRS).
    triangles : ndarray of shape (M, 3)
        Counter-clockwise.
    edges : ndarray of shape (E, 2)
        The boundary edges: their nodes never move.
    seam : ndarray of int
        The nodes of the cuts.
    held : ndarray of bool, shape (N,), optional
        Nodes that never move either (region outlines, turbines).

    Returns
    -------
    points : ndarray of shape (N, 2)
        A new array; only nodes in ``seam`` or next to one may have moved.
    moved : int
        How many nodes moved.

    Examples
    --------
    >>> xy = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1.6, 1.5]])
    >>> tri = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    >>> ring = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> new, moved = smooth_seams(xy, tri, ring, np.array([4]))
    >>> moved, bool(new[4, 0] < 1.6)
    (1, True)
    """
    points = np.array(points, dtype=np.float64)
    if len(seam) == 0 or len(triangles) == 0:
        return points, 0
    near = np.zeros(len(points), dtype=bool)
    near[seam] = True
    near[np.unique(triangles[near[triangles].any(axis=1)])] = True  # + neighbours
    local = triangles[near[triangles].any(axis=1)]  # every triangle they touch
    nodes, inverse = np.unique(local, return_inverse=True)
    local = inverse.reshape(local.shape)
    fixed = ~near[nodes]
    on_boundary = np.zeros(len(points), dtype=bool)
    on_boundary[edges.ravel()] = True
    fixed |= on_boundary[nodes]
    if held is not None:
        fixed |= held[nodes]
    xy = points[nodes]
    # the nodes of the worst 5% move, as in the parts' own smoothing
    good = max(35.0, smoothing.percentile(smoothing.min_angles(xy, local), 5))
    new = smoothing.smooth_points(xy, local, fixed, good_angle=good)[0]
    changed = (new != xy).any(axis=1)
    points[nodes[changed]] = new[changed]
    return points, int(changed.sum())
