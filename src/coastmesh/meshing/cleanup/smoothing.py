"""Smoothing interior nodes, never lowering the worst angles or radius ratio.

Boundary nodes stay. Each sweep moves the interior nodes that have a triangle with
an angle below ``good_angle``, all at once (Jacobi), each by the largest of a few
steps that passes a guard: none of its triangles turns over, and none gets a
smaller minimum angle unless it stays at or above both the node's worst one and
the 1st percentile of the mesh's, and none gets a smaller radius ratio (twice
the inscribed over the circumscribed radius) unless it stays at or above the
mesh's worst one (all from before the sweep). Nodes that fail take smaller steps
until every step passes with the final positions. Then no count of triangles
below an angle up to the 1st percentile grows, so neither the minimum angle nor
the 1st percentile falls, and the worst radius ratio does not fall either: a
bound on angles alone let a triangle keep its smallest angle while its second
fell, and the worst radius ratio of meshes made in parts fell by 0.02-0.07.

Steps go up the gradients of the smallest angles of the node's worst triangles
(``"angle"``, optimization-based smoothing after Freitag and Ollivier-Gooch) or
to the mean of its neighbours (``"laplacian"``). Picked by measurement on Gmsh's
NW European shelf meshes (``examples/nw_european_shelf``): six sweeps raise the
1st percentile of the minimum angle from 23.0 to 25.3 degrees (coarse) and 25.9
to 31.1 (intermediate) with ``"angle"``, to 23.0 and 26.5 with ``"laplacian"``.
The star's area-weighted centroid and circumcentres (optimal Delaunay) did no
better than ``"laplacian"``, nor did trying them before the ``"angle"`` steps;
moving only nodes with an angle below 35 degrees gives the same percentiles as
moving all, moves a third of the nodes and changes edge lengths less.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from pyproj import Transformer
from scipy import sparse

from coastmesh.errors import ConfigError
from coastmesh.geometry.sphere import local_plane
from coastmesh.meshing.cleanup.planar import sin_min_angles, sines_and_ratios
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import unique_edges

__all__ = [
    "SmoothingReport",
    "boundary_nodes",
    "min_angles",
    "smooth_mesh",
    "smooth_points",
]

#: The steps tried, as fractions of the first (the last, no step, is implied).
_FRACTIONS = (1.0, 0.5, 0.25, 0.125)
#: The first ``"angle"`` step, as a fraction of the node's mean edge length.
_ASCENT = 0.1
#: Triangles this close (degrees) to a node's worst one steer its step too.
_ACTIVE = 1.0
#: A sum of unit gradients shorter than this per gradient has no direction.
_CANCELLED = 1e-9


@dataclass(frozen=True, slots=True)
class SmoothingReport(Report):
    """What :func:`smooth_mesh` changed.

    Attributes
    ----------
    nodes_moved, sweeps : int
        Nodes at a new position; sweeps made (fewer when one moved nothing).
    min_angle_before, min_angle_after, min_angle_p1_before, min_angle_p1_after
        Smallest angle of the mesh, and 1st percentile of the triangles'
        minimum angles, degrees (float).
    seconds : float
        Time taken.
    """

    nodes_moved: int
    sweeps: int
    min_angle_before: float
    min_angle_after: float
    min_angle_p1_before: float
    min_angle_p1_after: float
    seconds: float

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.nodes_moved} nodes moved in {self.sweeps} sweeps; min angle "
            f"{self.min_angle_before:.1f} -> {self.min_angle_after:.1f} deg, 1st "
            f"percentile {self.min_angle_p1_before:.1f} -> "
            f"{self.min_angle_p1_after:.1f} deg ({self.seconds:.2f} s)"
        )


def smooth_mesh(
    mesh: Mesh,
    *,
    iterations: int = 6,
    method: Literal["angle", "laplacian"] = "angle",
    good_angle: float = 35.0,
) -> tuple[Mesh, SmoothingReport]:
    """Move interior nodes, never lowering the minimum angle or its 1st percentile.

    Parameters
    ----------
    mesh : Mesh
        The mesh (triangles counter-clockwise).
    iterations, method, good_angle
        As for :func:`smooth_points`.

    Returns
    -------
    mesh : Mesh
        The same triangles, boundary and point data; interior nodes moved.
    report : SmoothingReport

    Raises
    ------
    ConfigError
        If ``iterations``, ``method`` or ``good_angle`` is out of range.

    Notes
    -----
    Boundary nodes are the nodes of ``mesh.boundary_edges`` and of every edge
    not shared by exactly two triangles. Angles are measured in a conformal
    plane centred on the mesh (an oblique stereographic for longitude and
    latitude), so they are angles on the Earth; moved nodes go back to the CRS.

    Examples
    --------
    >>> pts = [[0, 0], [2, 0], [2, 2], [0, 2], [1.7, 1.6]]
    >>> tri = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> m = Mesh(pts, tri, [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None)
    >>> smooth, report = smooth_mesh(m)
    >>> report.nodes_moved, report.min_angle_before < report.min_angle_after
    (1, True)
    >>> smooth.points[:4].tolist() == m.points[:4].tolist()  # the boundary stays
    True
    """
    start = time.perf_counter()
    to_plane = local_plane(mesh)
    xy = plane_points(mesh.points, to_plane)
    fixed = boundary_nodes(mesh.triangles, len(xy))
    fixed[mesh.boundary_edges.ravel()] = True
    fixed[mesh.line_edges()[0].ravel()] = True  # a line's nodes stay on it
    new_xy, sweeps = smooth_points(
        xy,
        mesh.triangles,
        fixed,
        iterations=iterations,
        method=method,
        good_angle=good_angle,
    )
    before = min_angles(xy, mesh.triangles)
    after = min_angles(new_xy, mesh.triangles)
    report = SmoothingReport(
        nodes_moved=int((new_xy != xy).any(axis=1).sum()),
        sweeps=sweeps,
        min_angle_before=float(before.min(initial=90.0)),
        min_angle_after=float(after.min(initial=90.0)),
        min_angle_p1_before=percentile(before, 1),
        min_angle_p1_after=percentile(after, 1),
        seconds=time.perf_counter() - start,
    )
    points = moved_points(mesh.points, xy, new_xy, to_plane)
    return mesh_with(mesh, points=points), report


def smooth_points(
    xy: NDArray[np.float64],
    triangles: NDArray[np.int64],
    fixed: NDArray[np.bool_],
    *,
    iterations: int = 6,
    method: Literal["angle", "laplacian"] = "angle",
    good_angle: float = 35.0,
) -> tuple[NDArray[np.float64], int]:
    """Smooth planar nodes under a minimum-angle guard (the kernel of smoothing).

    Parameters
    ----------
    xy : ndarray of shape (N, 2)
        Node coordinates in a conformal plane (any length unit).
    triangles : ndarray of shape (M, 3)
        Node indices, counter-clockwise.
    fixed : ndarray of bool, shape (N,)
        Nodes that never move (at least the boundary); nodes of no triangle
        never move either.
    iterations : int
        Most sweeps; > 0. Sweeps stop early when one moves no node (moves under
        a millionth of the node's mean edge length are not made).
    method : {"angle", "laplacian"}
        A node's first step: along the sum of the unit gradients of the
        smallest angles of its triangles within 1 degree of its worst, 0.1
        times its mean edge length (its triangles' perimeters over three times
        their number); or to the mean of its neighbours. Then a half, a
        quarter, an eighth of it.
    good_angle : float
        Only nodes with a triangle whose minimum angle is below this (degrees)
        at the start of a sweep move in it; in (0, 90].

    Returns
    -------
    xy : ndarray of shape (N, 2)
        New coordinates; nodes that did not move keep their input values.
    sweeps : int
        Sweeps made (none if no node may move).

    Raises
    ------
    ConfigError
        If ``iterations``, ``method`` or ``good_angle`` is out of range.
    ValueError
        If an array has the wrong shape.

    Notes
    -----
    Each sweep puts every moving node at its first step, then repeats: a node
    with a triangle of no positive area, or whose minimum angle fell below both
    its value and the node's floor, or whose radius ratio fell below both its
    value and the mesh's smallest radius ratio, takes its next step (the
    last is none); until no node fails. The floor is the larger of the
    smallest angle at the node and the value just above the 1st percentile of
    the triangles' minimum angles; it and the radius ratios are from the start
    of the sweep. Steps only shrink, so this ends;
    only nodes next to one that changed are checked again. Angles are compared
    by their sines, ``2 A c / (a b c)`` with c the shortest side. The mean of
    an interior node's neighbours is the mean of the other corners of its
    triangles (every edge there has two). A node whose unit gradients cancel
    (a sum under 1e-9 per gradient: a symmetric star) does not move.

    Examples
    --------
    >>> xy = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1.6, 1.5]])
    >>> tri = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    >>> fixed = np.array([True, True, True, True, False])
    >>> new, sweeps = smooth_points(xy, tri, fixed, method="laplacian")
    >>> new[4].round(12).tolist(), sweeps
    ([1.0, 1.0], 2)
    """
    xy = np.asarray(xy, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    fixed = np.asarray(fixed, dtype=bool)
    if xy.ndim != 2 or xy.shape[1:] != (2,):
        raise ValueError(f"xy has shape {xy.shape}, expected (N, 2)")
    if triangles.ndim != 2 or triangles.shape[1:] != (3,):
        raise ValueError(f"triangles has shape {triangles.shape}, expected (M, 3)")
    if fixed.shape != (len(xy),):
        raise ValueError(f"fixed has shape {fixed.shape}, expected ({len(xy)},)")
    if isinstance(iterations, bool) or not (
        isinstance(iterations, int | np.integer) and iterations > 0
    ):
        raise ConfigError(f"iterations = {iterations!r}: must be an integer > 0")
    if method not in ("angle", "laplacian"):
        raise ConfigError(f"method = {method!r}: must be 'angle' or 'laplacian'")
    if not 0 < good_angle <= 90:
        raise ConfigError(f"good_angle = {good_angle}: must be in (0, 90] degrees")
    stars = _Stars(triangles, len(xy))
    free = ~fixed & (stars.count > 0)
    limit = np.sin(np.radians(good_angle))
    xy = xy.copy()
    sweeps = 0
    quality, ratio = sines_and_ratios(xy, triangles)
    while free.any() and sweeps < iterations:
        sweeps += 1
        # the free nodes of a triangle below the limit, in increasing order
        bad = np.zeros(len(xy), dtype=bool)
        bad[triangles[quality < limit].ravel()] = True
        nodes = np.flatnonzero(bad & free)
        if not len(nodes):
            break
        tri, starts = stars.gather(nodes)
        worst = np.minimum.reduceat(quality[tri], starts)
        step = _first_steps(xy, triangles, stars, nodes, quality, method)
        # floors: the star's minimum, and the value just above the 1st percentile
        upper = min(int(np.ceil(0.01 * (len(quality) - 1))) + 1, len(quality) - 1)
        floor = np.maximum(worst, np.partition(quality, upper)[upper])
        trial, moved = _guarded(
            xy, triangles, stars, nodes, step, (quality, ratio), (floor, ratio.min())
        )
        if not moved.any():
            break
        xy = trial
        # only the triangles at a node that moved change
        touched = np.zeros(len(triangles), dtype=bool)
        touched[stars.gather(nodes[moved])[0]] = True
        quality[touched], ratio[touched] = sines_and_ratios(xy, triangles[touched])
    return xy, sweeps


def min_angles(
    xy: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Return the minimum angle of each triangle, degrees (negative if inverted).

    ``xy`` (N, 2) are plane coordinates, ``triangles`` (M, 3) counter-clockwise
    node indices; the angles have shape (M,).

    Examples
    --------
    >>> min_angles(np.array([[0, 0], [1, 0], [0, 1.0]]), np.array([[0, 1, 2]]))
    array([45.])
    """
    sine = sin_min_angles(np.asarray(xy, dtype=np.float64), np.asarray(triangles))
    return np.degrees(np.arcsin(np.clip(sine, -1.0, 1.0)))


def percentile(values: NDArray[np.float64], q: float) -> float:
    """Return the ``q``-th percentile of ``values`` (90 for none): angle statistics."""
    return float(np.percentile(values, q)) if len(values) else 90.0


def boundary_nodes(triangles: NDArray[np.int64], n_points: int) -> NDArray[np.bool_]:
    """Return which nodes lie on an edge not shared by exactly two triangles.

    ``triangles`` (M, 3) are node indices below ``n_points``; the mask has shape
    (n_points,).

    Examples
    --------
    >>> boundary_nodes(np.array([[0, 1, 2], [0, 2, 3]]), 5).tolist()
    [True, True, True, True, False]
    """
    edges, count = unique_edges(np.asarray(triangles, dtype=np.int64), n_points)
    mask = np.zeros(n_points, dtype=bool)
    mask[edges[count != 2].ravel()] = True
    return mask


def mesh_with(mesh: Mesh, **fields: object) -> Mesh:
    """Return a copy of ``mesh`` with ``fields`` changed (and checked again).

    New ``triangles`` without new ``regions`` keep the one region of a mesh
    that has one; a mesh of several regions needs its new ``regions`` given.
    """
    values = {f.name: getattr(mesh, f.name) for f in dataclasses.fields(mesh)}
    if "triangles" in fields and "regions" not in fields:
        ids = np.unique(mesh.regions)
        if len(ids) > 1:
            raise ValueError(
                f"the triangles of a mesh of {len(ids)} regions changed without "
                "their regions: give regions"
            )
        count = len(np.asarray(fields["triangles"]).reshape(-1, 3))
        values["regions"] = np.full(count, ids[0]) if len(ids) else None
    return Mesh(**(values | fields))


def plane_points(
    points: NDArray[np.float64], to_plane: Transformer | None
) -> NDArray[np.float64]:
    """Return ``points`` (N, 2) in the plane of :func:`local_plane`, as a copy."""
    if to_plane is None:
        return np.array(points, dtype=np.float64).reshape(-1, 2)
    return np.column_stack(to_plane.transform(*np.asarray(points).T)).reshape(-1, 2)


def moved_points(
    points: NDArray[np.float64],
    before: NDArray[np.float64],
    after: NDArray[np.float64],
    to_plane: Transformer | None,
) -> NDArray[np.float64]:
    """Return ``points`` with the nodes that moved in the plane moved too.

    ``before`` and ``after`` are the plane coordinates; nodes that did not move
    keep their coordinates exactly.
    """
    points = np.array(points, dtype=np.float64)
    moved = (after != before).any(axis=1)
    if to_plane is None:
        points[moved] = after[moved]
    elif moved.any():
        x, y = after[moved].T
        back = to_plane.transform(x, y, direction="INVERSE")
        points[moved] = np.column_stack(back)
    return points


class _Stars:
    """The triangles at each node (its star)."""

    def __init__(self, triangles: NDArray[np.int64], n: int) -> None:
        m = len(triangles)
        # scipy's COO to CSR is a counting sort: corners grouped by node, each
        # node's triangles in increasing order
        incidence = sparse.csr_array(
            (np.ones(3 * m, np.int8), (triangles.ravel(), np.repeat(np.arange(m), 3))),
            shape=(n, m),
        )
        self.indptr = incidence.indptr.astype(np.int64)
        self.tri = incidence.indices.astype(np.int64)
        self.count = np.diff(self.indptr)

    def gather(
        self, nodes: NDArray[np.int64]
    ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Return the triangles of ``nodes`` (each has some), and run starts."""
        count = self.count[nodes]
        starts = np.cumsum(count) - count
        offsets = np.repeat(self.indptr[nodes] - starts, count)
        return self.tri[offsets + np.arange(len(offsets))], starts


def _first_steps(
    xy: NDArray[np.float64],
    triangles: NDArray[np.int64],
    stars: _Stars,
    nodes: NDArray[np.int64],
    quality: NDArray[np.float64],
    method: str,
) -> NDArray[np.float64]:
    """Return the first step (k, 2) of each node (see :func:`smooth_points`)."""
    tri, starts = stars.gather(nodes)
    count = stars.count[nodes][:, None]
    p = xy[triangles[tri]]  # (K, 3, 2)
    sides = np.hypot(*(np.roll(p, -1, axis=1) - p).transpose(2, 0, 1))
    scale = np.add.reduceat(sides.sum(axis=1), starts) / (3 * count[:, 0])
    step: NDArray[np.float64]  # numpy's stub: np.add.reduceat returns Any
    if method == "laplacian":
        # the other two corners of each triangle: all three minus the node
        total = np.add.reduceat(p.sum(axis=1), starts)
        step = (total - count * xy[nodes]) / (2 * count) - xy[nodes]
    else:  # the triangles within _ACTIVE of the star's worst, and the node in each
        angle = np.degrees(np.arcsin(np.clip(quality[tri], -1.0, 1.0)))
        row = np.repeat(np.arange(len(nodes)), count[:, 0])
        near = np.flatnonzero(
            angle <= np.minimum.reduceat(angle, starts)[row] + _ACTIVE
        )
        corner = np.argmax(triangles[tri[near]] == nodes[row[near], None], axis=1)
        unit = _angle_gradient(p[near], corner)
        ascent = np.zeros((len(tri), 2))
        ascent[near] = unit / np.maximum(np.hypot(*unit.T), 1e-300)[:, None]
        step = np.add.reduceat(ascent, starts)
        steering = np.zeros(len(tri))
        steering[near] = 1.0
        norm = np.hypot(*step.T)
        step *= (_ASCENT * scale / np.maximum(norm, 1e-300))[:, None]
        # unit gradients that cancel leave rounding noise, not a direction
        step[norm <= _CANCELLED * np.add.reduceat(steering, starts)] = 0.0
    step[np.hypot(*step.T) <= 1e-6 * scale] = 0.0  # too short to count
    return step


def _angle_gradient(
    p: NDArray[np.float64], corner: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Return the gradient of each triangle's smallest angle at one corner.

    ``p`` (k, 3, 2) are counter-clockwise triangles, ``corner`` (k,) the corner
    (0, 1 or 2) that moves. At the smallest angle's corner A, with B and C
    next: the angle grows by ``-rot(AB) / |AB|**2`` per unit move of B,
    ``rot(AC) / |AC|**2`` of C, and minus their sum of A (``rot`` turns
    90 degrees counter-clockwise).
    """
    k = len(p)
    ahead, behind = np.roll(p, -1, axis=1) - p, np.roll(p, 1, axis=1) - p
    cross = ahead[..., 0] * behind[..., 1] - ahead[..., 1] * behind[..., 0]
    angle = np.arctan2(cross, (ahead * behind).sum(axis=2))
    a = np.argmin(angle, axis=1)
    rows = np.arange(k)
    ab, ac = ahead[rows, a], behind[rows, a]
    d_b = np.column_stack([ab[:, 1], -ab[:, 0]]) / (ab**2).sum(axis=1)[:, None]
    d_c = np.column_stack([-ac[:, 1], ac[:, 0]]) / (ac**2).sum(axis=1)[:, None]
    options = np.stack([-(d_b + d_c), d_b, d_c])  # (3, k, 2): A, B, C move
    gradient: NDArray[np.float64] = options[(corner - a) % 3, rows]  # stub: Any
    return gradient


def _guarded(
    xy: NDArray[np.float64],
    triangles: NDArray[np.int64],
    stars: _Stars,
    nodes: NDArray[np.int64],
    step: NDArray[np.float64],
    before: tuple[NDArray[np.float64], NDArray[np.float64]],
    floor: tuple[NDArray[np.float64], float],
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return the positions after the guarded steps, and which nodes moved.

    ``before`` is the sine of each triangle's smallest angle and its radius
    ratio, (M,) each; a node's move may lower the first only to the node's
    ``floor[0]`` (k,), the second only to the mesh's worst, ``floor[1]``.
    """
    last = len(_FRACTIONS)
    fractions = np.array([*_FRACTIONS, 0.0])
    level = np.where((step != 0).any(axis=1), 0, last)
    trial = xy.copy()
    trial[nodes] += fractions[level, None] * step
    row = np.full(len(xy), -1)
    row[nodes] = np.arange(len(nodes))
    check = np.arange(len(nodes))
    position = np.empty(len(triangles), dtype=np.int64)  # in the triangles checked
    while True:
        check = check[level[check] < last]
        if len(check) == 0:
            break
        tri, starts = stars.gather(nodes[check])
        count = stars.count[nodes[check]]
        # each triangle once (most are in the stars of two or three nodes)
        seen = np.zeros(len(triangles), dtype=bool)
        seen[tri] = True
        once = np.flatnonzero(seen)
        position[once] = np.arange(len(once))
        at = position[tri]
        after, ratio = (v[at] for v in sines_and_ratios(trial, triangles[once]))
        bound = np.minimum(before[0][tri], np.repeat(floor[0][check], count))
        ok = (after >= bound) & (after > 0)
        ok &= ratio >= np.minimum(before[1][tri], floor[1])
        failed = check[~np.logical_and.reduceat(ok, starts)]
        if len(failed) == 0:
            break
        level[failed] += 1
        changed = nodes[failed]
        trial[changed] = xy[changed] + fractions[level[failed], None] * step[failed]
        # the moving nodes that share a triangle with one that changed, in order
        near = row[triangles[stars.gather(changed)[0]].ravel()]
        again = np.zeros(len(nodes), dtype=bool)
        again[near[near >= 0]] = True
        check = np.flatnonzero(again)
    return trial, level < last
