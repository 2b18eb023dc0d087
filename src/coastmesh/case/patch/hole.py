"""The hole as a domain to mesh, and its size field graded from the seam.

:func:`hole_domain` makes the hole (:class:`~coastmesh.case.patch.cut.Hole`) a
:class:`~coastmesh.types.Domain` in the meshing CRS whose segments are runs of
the existing mesh's nodes: the seam (``"seam"``, open, so the channel term
does not take it for a wall) and the pieces of the mesh's own boundary, with
their ids. :func:`seam_sizes` is the size the seam asks for: the length of
its nearest edge, growing at ``rate`` away from it (and, at least, a little
less than it, shrinking at ``rate``), so the new elements beside the seam are
about the size of the kept ones across it.
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS
from scipy.spatial import cKDTree

from coastmesh.case.patch.cut import Hole
from coastmesh.types import BoundarySegment, Domain, Mesh

__all__ = ["SEAM", "SEAM_SLACK", "hole_domain", "seam_edges", "seam_sizes"]

#: The name of the seam's segments in the hole's domain.
SEAM = "seam"
#: The size beside the seam is at least its edges' length over this.
SEAM_SLACK = 1.25


def hole_domain(
    hole: Hole,
    points: NDArray[np.float64],
    mesh: Mesh,
    crs: CRS,
    boundary_ids: dict[tuple[int, int], int],
) -> tuple[Domain, int]:
    """Return the hole as a domain in ``crs`` (``points`` are there), and the seam id.

    ``boundary_ids`` maps each boundary edge of the mesh (sorted node pair)
    to its id.
    """
    seam_id = max([*mesh.boundary_kinds, *mesh.boundary_names, 0]) + 1
    seam_id = max(seam_id, int(mesh.boundary_ids.max(initial=0)) + 1)
    segments = []
    for ring, seam in zip(hole.rings, hole.seam, strict=True):
        ids = np.array(
            [
                seam_id if s else boundary_ids.get((min(a, b), max(a, b)), 0)
                for a, b, s in zip(ring[:-1], ring[1:], seam, strict=True)
            ]
        )
        segments += _runs(ring, ids, points, mesh, seam_id)
    shell, *holes = (points[r] for r in hole.rings)
    polygon = shapely.Polygon(shell, holes)
    return Domain(polygon, tuple(segments), crs), seam_id


def _runs(
    ring: NDArray[np.int64],
    ids: NDArray[np.int64],
    points: NDArray[np.float64],
    mesh: Mesh,
    seam_id: int,
) -> list[BoundarySegment]:
    """Split a ring into segments of one id each, starting where the id changes."""
    change = np.flatnonzero(ids != np.roll(ids, 1))
    start = int(change[0]) if change.size else 0
    order = np.roll(np.arange(len(ids)), -start)
    ids = ids[order]
    nodes = np.concatenate([ring[:-1][order], ring[:-1][order][:1]])
    cuts = np.flatnonzero(np.diff(ids)) + 1
    out = []
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(ids)], strict=True):
        pid = int(ids[a])
        xy = points[nodes[a : b + 1]]
        if pid == seam_id:
            out.append(BoundarySegment(xy, "open", SEAM, pid))
            continue
        name = mesh.boundary_names.get(pid, f"id {pid}")
        if mesh.boundary_kinds.get(pid) == "open":
            out.append(BoundarySegment(xy, "open", name, max(pid, 1)))
        else:
            out.append(BoundarySegment(xy, "shoreline", name, max(pid, 1)))
    return out


def seam_edges(hole: Hole) -> NDArray[np.int64]:
    """Return the seam's edges as node pairs of the mesh, (k, 2)."""
    pairs = [
        np.column_stack([r[:-1], r[1:]])[s]
        for r, s in zip(hole.rings, hole.seam, strict=True)
    ]
    return np.concatenate(pairs) if pairs else np.empty((0, 2), dtype=np.int64)


def seam_sizes(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    points: NDArray[np.float64],
    edges: NDArray[np.int64],
    rate: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the seam's upper and lower size bounds on the grid ``x``, ``y``.

    ``L`` is the length of the seam's edge whose midpoint is nearest, ``d``
    the distance to it: the size is at most ``L + rate d`` and at least
    ``L / SEAM_SLACK - rate d``. So beside the seam the new elements are no
    larger than the kept ones across it, nor much smaller. The lower bound is
    slack: at ``L`` itself it kept large elements round a reflex corner of the
    seam between long edges (angles of 27 degrees on the NW-shelf mesh, 32
    with the slack).
    """
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    length = np.hypot(*(b - a).T)
    mid = (a + b) / 2
    xx, yy = np.meshgrid(x, y)
    d, k = cKDTree(mid).query(np.column_stack([xx.ravel(), yy.ravel()]))
    d, h = d.reshape(xx.shape), length[k].reshape(xx.shape)
    return h + rate * d, h / SEAM_SLACK - rate * d
