"""Sharp corners of the mesh boundary: where the domain forces thin triangles.

A boundary node's interior angle is the sum of the angles its triangles have
there, measured on the Earth (:func:`boundary_angles`). Below
:data:`SHARP_ANGLE` (45 degrees) no triangle at that node can be well shaped,
so quality targets leave those triangles out. :class:`CornerStats` counts the
sharp corners and lists the sharpest, with the boundary ids that meet there: an
open boundary meeting the coast at a sharp angle can be moved (*avoidable*); two
shoreline edges meeting sharply are a fjord head or a spit the coast forces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypedDict

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.earth import mesh_earth_centred
from coastmesh.meshing.quality.measure import Place, places, triangle_measures
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import unique_edges

__all__ = [
    "MAX_LISTED_CORNERS",
    "SHARP_ANGLE",
    "BoundaryAngles",
    "CornerStats",
    "SharpCorner",
    "boundary_angles",
    "corner_stats",
    "interior_angles",
]

#: Interior angle (degrees) below which a boundary corner is sharp.
SHARP_ANGLE = 45.0

#: The sharpest corners listed in :class:`CornerStats`; the rest are counted.
MAX_LISTED_CORNERS = 50


@dataclass(frozen=True, slots=True)
class SharpCorner(Report):
    """A boundary node whose interior angle is below :data:`SHARP_ANGLE`.

    Attributes
    ----------
    node : Place
        The node (index and position).
    angle : float
        The domain's interior angle there, degrees.
    boundary_ids : tuple of int or None
        Physical ids of the boundary edges that meet there (two, or four where
        the boundary touches itself); None for an edge without a tag.
    kinds : tuple of str or None
        ``"open"`` or ``"shoreline"`` for each, where known.
    avoidable : bool
        True when an open boundary is one of them: moving it removes the corner.
    """

    node: Place
    angle: float
    boundary_ids: tuple[int | None, ...]
    kinds: tuple[str | None, ...]
    avoidable: bool

    def summary(self) -> str:
        """Return a one-line summary.

        Examples
        --------
        >>> SharpCorner(Place(7, 0.0, 0.0, -3.0, 59.0), 12.5, (1, 2),
        ...             ("shoreline", "open"), True).summary()
        '12.5 deg at node 7 (-3.0000, 59.0000), ids 1/2 (shoreline/open), avoidable'
        """
        ids = "/".join("?" if i is None else str(i) for i in self.boundary_ids)
        kinds = "/".join(k or "?" for k in self.kinds)
        return (
            f"{self.angle:.1f} deg at node {self.node.index} {self.node.summary()}, "
            f"ids {ids} ({kinds}), {'avoidable' if self.avoidable else 'forced'}"
        )


@dataclass(frozen=True, slots=True)
class CornerStats(Report):
    """The boundary nodes' interior angles and the sharp corners among them.

    Attributes
    ----------
    threshold : float
        Interior angle below which a corner is sharp, degrees (:data:`SHARP_ANGLE`).
    boundary_nodes : int
        Nodes on the boundary (of edges in a single triangle).
    min_angle : float
        Smallest interior angle of any boundary node, degrees (nan without one).
    sharp : int
        Sharp corners.
    avoidable : int
        Sharp corners where an open boundary meets (see :class:`SharpCorner`).
    triangles : int
        Triangles with a node at a sharp corner.
    sharpest : tuple of SharpCorner
        The sharpest (up to :data:`MAX_LISTED_CORNERS`), sharpest first.
    """

    threshold: float
    boundary_nodes: int
    min_angle: float
    sharp: int
    avoidable: int
    triangles: int
    sharpest: tuple[SharpCorner, ...]

    def summary(self) -> str:
        """Return a one-line summary.

        Examples
        --------
        >>> CornerStats(45.0, 100, 60.0, 0, 0, 0, ()).summary()
        'boundary corners sharper than 45 deg: 0 (sharpest 60.0 deg)'
        """
        text = f"boundary corners sharper than {self.threshold:g} deg: {self.sharp:,}"
        if not self.sharpest:
            return text + f" (sharpest {self.min_angle:.1f} deg)"
        return (
            f"{text} ({self.avoidable:,} avoidable, where an open boundary meets; "
            f"{self.triangles:,} triangles touch them); sharpest "
            f"{self.sharpest[0].summary()}"
        )


class BoundaryAngles(TypedDict):
    """What :func:`boundary_angles` returns."""

    nodes: NDArray[np.int64]
    angle: NDArray[np.float64]


def boundary_angles(mesh: Mesh) -> BoundaryAngles:
    """Return the domain's interior angle at each boundary node, on the Earth.

    Parameters
    ----------
    mesh : Mesh
        Points in a geographic or projected CRS, or planar metres when
        ``mesh.crs`` is None.

    Returns
    -------
    dict of str to ndarray of shape (k,)
        ``"nodes"`` the boundary nodes (of edges in a single triangle), in
        increasing order, and ``"angle"`` the sum of the angles of their
        triangles at them, degrees: 180 on a straight boundary, below 180 at a
        headland of the sea (a fjord head), above at a cape.

    Raises
    ------
    TypeError
        If ``mesh`` is not a :class:`Mesh`.
    ValueError
        As for :func:`~coastmesh.meshing.quality.mesh_quality.triangle_quality`.

    Notes
    -----
    Triangle angles come from the three side lengths
    (:func:`~coastmesh.meshing.quality.measure.triangle_measures`). Where the boundary
    passes twice through a node, its angle is the sum over both wedges.

    Examples
    --------
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None)
    >>> q = boundary_angles(m)
    >>> q["nodes"].tolist(), np.round(q["angle"], 9).tolist()
    ([0, 1, 2, 3], [90.0, 90.0, 90.0, 90.0])
    """
    if not isinstance(mesh, Mesh):
        raise TypeError(f"mesh is a {type(mesh).__name__}, expected a Mesh")
    xyz, planar = mesh_earth_centred(mesh)
    edges, shared = unique_edges(mesh.triangles, len(mesh.points))
    nodes, angle = interior_angles(xyz, planar, mesh.triangles, edges[shared == 1])
    return {"nodes": nodes, "angle": angle}


def interior_angles(
    xyz: NDArray[np.float64],
    planar: bool,
    triangles: NDArray[np.int64],
    boundary: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Return the nodes of ``boundary`` edges (k, 2) and their interior angles."""
    n = len(xyz)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[boundary.ravel()] = True
    touching = triangles[on_boundary[triangles].any(axis=1)]
    angles = triangle_measures(xyz, touching, planar, ("angles",))["angles"]
    total = np.bincount(touching.ravel(), weights=angles.ravel(), minlength=n)
    nodes = np.flatnonzero(on_boundary).astype(np.int64, copy=False)
    return nodes, total[nodes].astype(np.float64, copy=False)


def corner_stats(
    mesh: Mesh,
    nodes: NDArray[np.int64],
    angle: NDArray[np.float64],
    boundary: NDArray[np.int64],
) -> tuple[CornerStats, NDArray[np.bool_]]:
    """Find the sharp corners among the boundary ``nodes`` with interior ``angle``.

    Parameters
    ----------
    mesh : Mesh
        The mesh, for its boundary ids, kinds and positions.
    nodes, angle : ndarray of shape (k,)
        From :func:`interior_angles`.
    boundary : ndarray of shape (K, 2)
        The mesh's boundary edges (in a single triangle), lower node first.

    Returns
    -------
    stats : CornerStats
    touching : ndarray of bool of shape (M,)
        The triangles with a node at a sharp corner.
    """
    sharp = np.flatnonzero(angle < SHARP_ANGLE)
    sharp = sharp[np.argsort(angle[sharp], kind="stable")]
    is_sharp = np.zeros(len(mesh.points), dtype=bool)
    is_sharp[nodes[sharp]] = True
    touching = np.any(is_sharp[mesh.triangles], axis=1)
    ids = _edge_ids(mesh, boundary)
    is_open = np.isin(ids, [i for i, k in mesh.boundary_kinds.items() if k == "open"])
    open_at = np.zeros(len(mesh.points), dtype=bool)
    open_at[boundary[is_open].ravel()] = True
    ends = boundary.ravel()
    order = np.argsort(ends, kind="stable")
    ends = ends[order]
    listed = nodes[sharp[:MAX_LISTED_CORNERS]]
    corners = []
    for where, index in zip(places(mesh, listed, triangles=False), sharp, strict=False):
        lo, hi = np.searchsorted(ends, [where.index, where.index + 1])
        meet = tuple(None if i < 0 else int(i) for i in ids[order[lo:hi] // 2])
        kinds = tuple(None if i is None else mesh.boundary_kinds.get(i) for i in meet)
        corners.append(
            SharpCorner(where, float(angle[index]), meet, kinds, "open" in kinds)
        )
    stats = CornerStats(
        threshold=SHARP_ANGLE,
        boundary_nodes=len(nodes),
        min_angle=float(angle.min()) if angle.size else float("nan"),
        sharp=len(sharp),
        avoidable=int(open_at[nodes[sharp]].sum()),
        triangles=int(touching.sum()),
        sharpest=tuple(corners),
    )
    return stats, touching


def _edge_ids(mesh: Mesh, boundary: NDArray[np.int64]) -> NDArray[np.int64]:
    """Return the tagged id of each boundary edge (lower node first), or -1."""
    if not len(mesh.boundary_edges):
        return np.full(len(boundary), -1, dtype=np.int64)
    n = len(mesh.points)
    tagged = np.sort(mesh.boundary_edges, axis=1)
    keys = tagged[:, 0] * n + tagged[:, 1]
    order = np.argsort(keys, kind="stable")
    keys = keys[order]
    wanted = boundary[:, 0] * n + boundary[:, 1]
    pos = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
    return np.where(keys[pos] == wanted, mesh.boundary_ids[order[pos]], -1)
