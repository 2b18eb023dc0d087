"""Regions, nodes and lines inside the water: farms, footprints, turbines, cables.

A region (a farm's area, a turbine's footprint) is meshed as a face of its own:
its outline is noded once, every vertex of the polygon kept and each side
split evenly at the local size, and goes to :func:`~.faces.split_faces` as a
closed cut, so the water around it and the region inside share its nodes and
the mesh conforms along it (:mod:`~coastmesh.meshing.parts.tasks` holds the
nodes of cuts in the cleanup of each part, and the seams are smoothed only
at the straight cuts). Its triangles then carry the region's id (the
innermost region that holds a triangle's centroid). A turbine node is a
point embedded in the face that holds it (``gmsh.model.mesh.embed``), at its
exact position in the meshing CRS. A line (a cable route, a weir crest) is
noded once as an outline is, and its 2-node pieces are curves embedded in
the face that holds it: its edges are mesh edges, and its nodes are held by
the part's cleanup (which never flips or splits one of its edges) and every
stage after it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.types import MeshLine

__all__ = ["Inner", "InnerPlane", "label_regions", "node_line", "node_ring"]


@dataclass(frozen=True)
class Inner:
    """What a mesh must hold inside its water, in the domain's CRS.

    Attributes
    ----------
    regions : sequence of (shapely.Polygon, int, str)
        Each region's polygon (no holes: a region inside another is its own
        entry), physical surface id and name. Regions may nest but not cross.
    points : ndarray of shape (k, 2)
        Positions that must be mesh nodes (turbines).
    crs : pyproj.CRS or CRS-like, optional
        The CRS of the regions, points and lines; default the domain's.
    lines : sequence of (ndarray of shape (k, 2), int, str)
        Lines whose edges must be mesh edges (``[[lines]]``), with their id
        and name: inside the water, clear of its boundary, crossing no region
        outline and no other line.
    """

    regions: Sequence[tuple[shapely.Polygon, int, str]] = ()
    points: NDArray[np.float64] = field(
        default_factory=lambda: np.empty((0, 2), dtype=np.float64)
    )
    crs: Any = None
    lines: Sequence[tuple[NDArray[np.float64], int, str]] = ()

    def __bool__(self) -> bool:
        return bool(len(self.regions) or len(self.points) or len(self.lines))


@dataclass(frozen=True)
class InnerPlane:
    """:class:`Inner` in the meshing CRS, its outlines noded.

    ``rings`` are the closed outlines (first point repeated last) as the mesh
    will have them; ``polygons`` the same as polygons; ``ids`` and ``names``
    the regions'; ``points`` the nodes to embed; ``lines`` the lines noded
    (their points are their nodes), ``line_ids`` and ``line_names`` theirs.
    """

    rings: list[NDArray[np.float64]]
    polygons: list[shapely.Polygon]
    ids: list[int]
    names: list[str]
    points: NDArray[np.float64]
    lines: list[NDArray[np.float64]] = field(default_factory=list)
    line_ids: list[int] = field(default_factory=list)
    line_names: list[str] = field(default_factory=list)

    def mesh_lines(self) -> list[MeshLine]:
        """Return the noded lines as :class:`~coastmesh.types.MeshLine`."""
        return [
            MeshLine(pid, name, xy)
            for xy, pid, name in zip(
                self.lines, self.line_ids, self.line_names, strict=True
            )
        ]


def node_ring(
    ring: NDArray[np.float64],
    size_at: Callable[[NDArray[np.float64]], NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Return a closed ring with each side split evenly at the local size.

    Every vertex of ``ring`` is kept; a side of length ``L`` whose size at its
    middle is ``h`` gets ``ceil(L / h)`` edges (the size grid's value there,
    rounded up as Gmsh rounds the edges of a curve).

    Examples
    --------
    >>> sq = np.array([[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]], dtype=float)
    >>> r = node_ring(sq, lambda xy: np.full(len(xy), 4.0))
    >>> len(r) - 1, r[:4].round(3).tolist()
    (12, [[0.0, 0.0], [3.333, 0.0], [6.667, 0.0], [10.0, 0.0]])
    """
    ring = np.asarray(ring, dtype=np.float64)
    if not np.array_equal(ring[0], ring[-1]):
        ring = np.vstack([ring, ring[:1]])
    return node_line(ring, size_at)


def node_line(
    line: NDArray[np.float64],
    size_at: Callable[[NDArray[np.float64]], NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Return an open line with each side split evenly at the local size.

    As :func:`node_ring`, without closing it: every vertex kept, a side of
    length ``L`` and size ``h`` at its middle in ``ceil(L / h)`` edges.

    Examples
    --------
    >>> ab = np.array([[0, 0], [10, 0]], dtype=float)
    >>> node_line(ab, lambda xy: np.full(len(xy), 4.0))[:, 0].round(3).tolist()
    [0.0, 3.333, 6.667, 10.0]
    """
    ring = np.asarray(line, dtype=np.float64)
    a, b = ring[:-1], ring[1:]
    length = np.linalg.norm(b - a, axis=1)
    keep = length > 0
    a, b, length = a[keep], b[keep], length[keep]
    h = np.asarray(size_at(0.5 * (a + b)), dtype=np.float64)
    pieces = np.maximum(np.ceil(length / h - 1e-9), 1).astype(int)
    out = [a[k] + np.outer(np.arange(n) / n, b[k] - a[k]) for k, n in enumerate(pieces)]
    out.append(ring[-1:])
    return np.concatenate(out)


def label_regions(
    centres: NDArray[np.float64], plane: InnerPlane, surface_id: int
) -> NDArray[np.int64]:
    """Return each triangle's region id: the innermost region holding its centre.

    Regions are tried largest first, so a footprint inside a farm wins; a
    centre in none is the domain's (``surface_id``).
    """
    regions = np.full(len(centres), surface_id, dtype=np.int64)
    order = sorted(range(len(plane.polygons)), key=lambda k: -plane.polygons[k].area)
    for k in order:
        polygon = plane.polygons[k]
        shapely.prepare(polygon)
        inside = shapely.contains_xy(polygon, centres[:, 0], centres[:, 1])
        regions[inside] = plane.ids[k]
    return regions


def smallest_side(plane: InnerPlane) -> float:
    """Return the shortest edge of the noded outlines and lines; inf if none."""
    sides = [
        np.linalg.norm(np.diff(r, axis=0), axis=1).min()
        for r in [*plane.rings, *plane.lines]
    ]
    return float(min(sides, default=math.inf))
