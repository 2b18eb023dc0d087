"""Nodes moved so that the elements take the size field's sizes, where a term asks.

Gmsh's frontal-Delaunay algorithm meshes a region of one size as a triangular
lattice, broken where its fronts meet by pairs of nodes of 5 and 7 triangles.
The lattice is squeezed round each pair, and there an element's mean edge is
up to a quarter off the size: on the 50 m zone of the Pentland Firth's
refinement example (``examples/orkney/pentland_refine.toml``), 289 of 29,797
elements were more than 10 % off. Gmsh's own smoothing (``optimize``) and the
cleanup's (:mod:`~coastmesh.meshing.cleanup.smoothing`) improve angles, not
sizes, and Laplacian smoothing barely changes them (99.03 to 99.07 % within
10 % there, measured).

Where a size term asks for its sizes to hold
(:attr:`~coastmesh.sizing.combine.TermSizes.conform`: the field term,
``[[mesh_size.fields]]``), :func:`conform_sizes` relaxes the nodes as a network
of springs, each edge's rest length the mean of its two nodes' sizes (in the
plane: the size times the plane's scale factor there)::

    x_i <- x_i + step * sum_j (L_ij - h_ij) / L_ij * (x_j - x_i)

for every movable node ``i`` at once (Jacobi sweeps), which spreads the squeeze
round each 5-7 pair over the lattice round it (99.94 % there). Boundary nodes,
the nodes of lines and of region outlines do not move. A sweep's move of a
node is undone where one of its triangles would turn over, or get a minimum
angle below both its own before the pass and ``min_angle``; so no triangle's
minimum angle falls below ``min(its own, min_angle)``. Sweeps stop when no node
moves by more than 1e-3 of its size, or after ``sweeps``. The result is kept
only if the share of the zone's elements within ``tolerance`` of their size
does not fall, and their worst is not further off than before (or within
``tolerance``).

No maintained library relaxes a mesh to a size field with its boundary and
lines held and a guard on angles (DistMesh's springs are the same idea inside
a mesh generator; MMG adapts a mesh, but its Python bindings remesh whole
surfaces and spread edge lengths wider than Gmsh's lattice), so this is
written here.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS, Proj, Transformer

from coastmesh.errors import ConfigError
from coastmesh.geometry.sphere import local_plane
from coastmesh.meshing.cleanup import smoothing
from coastmesh.meshing.cleanup.planar import signed_areas
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import region_interfaces, unique_edges

__all__ = ["ConformReport", "conform_sizes", "size_deviation"]

#: The share of its size an element's mean edge may be off by (the targets).
TOLERANCE = 0.1
#: A sweep's step, as a fraction of the springs' pull (stable below 2 / 6).
STEP = 0.2
#: The springs relax the nodes this many rings round the triangles off their
#: size by more than half the tolerance (:func:`_around`).
RELAX_RINGS = 8
#: Sweeps stop when no node moves by more than this fraction of its size.
STILL = 1e-3
#: The share of ``tolerance`` a triangle off by more pulls its nodes at the end.
SETTLE = 0.95
#: That pull's step, as a fraction of the gradient (times the size).
STEP_SETTLE = 0.3
#: Guard rounds a sweep may undo moves in, before it is undone whole.
_GUARD_ROUNDS = 8


@dataclass(frozen=True, slots=True)
class ConformReport(Report):
    """What :func:`conform_sizes` did.

    Attributes
    ----------
    elements : int
        Elements whose three nodes are in the zone (those measured), in the
        mesh returned.
    nodes, nodes_moved, nodes_removed : int
        Nodes that could move (in the zone, not held), those that did, and
        those taken out (of 3 or 4 triangles, too small: :func:`conform_sizes`).
    sweeps : int
        Sweeps made.
    within_before, within_after : float
        Share of the elements whose mean edge is within ``tolerance`` of the
        mean size of their nodes (1.0 for no element).
    worst_before, worst_after : float
        The largest ``|mean edge / size - 1|`` of those elements (0.0 for none).
    tolerance : float
    kept : bool
        Whether the moves were kept (the share within ``tolerance`` did not
        fall, nor the worst rise past ``tolerance`` and its own).
    seconds : float
    """

    elements: int
    nodes: int
    nodes_moved: int
    nodes_removed: int
    sweeps: int
    within_before: float
    within_after: float
    worst_before: float
    worst_after: float
    tolerance: float
    kept: bool
    seconds: float

    def summary(self) -> str:
        """One line: the elements within tolerance before and after."""
        if not self.elements:
            return "no element where the sizes must hold"
        return (
            f"{self.elements:,} elements where the sizes must hold: "
            f"{self.within_before:.2%} -> {self.within_after:.2%} within "
            f"{self.tolerance:.0%} of the size (worst {self.worst_before:.0%} -> "
            f"{self.worst_after:.0%} off); {self.nodes_moved:,} nodes moved and "
            f"{self.nodes_removed:,} taken out in {self.sweeps} sweeps"
        )


def conform_sizes(
    mesh: Mesh,
    zone: NDArray[np.bool_],
    *,
    tolerance: float = TOLERANCE,
    sweeps: int = 200,
    min_angle: float = 30.0,
    step: float = STEP,
) -> tuple[Mesh, ConformReport]:
    """Move the zone's nodes so that its elements take the size field's sizes.

    Parameters
    ----------
    mesh : Mesh
        With ``point_data["size"]``, the target edge length at each node in
        metres on the Earth (as :func:`~coastmesh.meshing.generate_mesh` gives).
    zone : ndarray of bool, shape (N,)
        The nodes where the sizes must hold. Those not on the boundary, a line
        or an outline between regions move.
    tolerance : float, default 0.1
        The share of its size an element's mean edge may be off by, for the
        report and the keep-or-undo test; in (0, 1).
    sweeps : int, default 200
        The most sweeps; >= 1.
    min_angle : float, default 30
        No triangle's minimum angle falls below the smaller of its own and
        this, degrees; in [0, 60).
    step : float, default 0.2
        The fraction of the springs' pull a node moves by each sweep; in (0, 0.3].

    Returns
    -------
    (Mesh, ConformReport)
        The mesh with the nodes moved (nodes that did not move keep their
        coordinates exactly) and the crowded ones taken out (the nodes after
        each renumbered down, their triangles replaced), or ``mesh`` itself
        when nothing changed or the changes were undone.

    Raises
    ------
    ConfigError
        If an option is out of range (the message names it).
    ValueError
        If ``zone`` is not one flag per node, or the mesh has no sizes.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> pts = np.array([[0, 0], [100, 0], [50, 87], [50, 29.0]])
    >>> tris = np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3]])
    >>> edges = np.array([[0, 1], [1, 2], [2, 0]])
    >>> m = Mesh(pts, tris, edges, [1, 1, 1], 1, None,
    ...          point_data={"size": np.full(4, 100.0)})
    >>> out, report = conform_sizes(m, np.ones(4, bool), min_angle=0.0)
    >>> report.nodes_removed, len(out.triangles)  # 3 triangles 28 % too small
    (1, 1)
    >>> report.within_before, report.within_after
    (0.0, 1.0)
    """
    _check_options(tolerance, sweeps, min_angle, step)
    start = time.perf_counter()
    zone = np.asarray(zone, dtype=bool)
    n = len(mesh.points)
    if zone.shape != (n,):
        raise ValueError(f"zone has shape {zone.shape}; the mesh has {n} nodes")
    if "size" not in mesh.point_data:
        raise ValueError("conform_sizes needs the mesh's point_data['size']")
    tri = np.asarray(mesh.triangles, dtype=np.int64)
    measured = np.asarray(zone[tri].all(axis=1), dtype=bool)
    movable = zone & ~_held(mesh)
    if not measured.any() and not movable.any():
        return mesh, _report(
            0, 0, 0, 0, 0, (1.0, 0.0), (1.0, 0.0), tolerance, True, start
        )
    to_plane = local_plane(mesh)
    xy0 = smoothing.plane_points(mesh.points, to_plane)
    goal = np.asarray(mesh.point_data["size"], dtype=np.float64) * _scale(
        mesh, to_plane, zone
    )
    before = _shares(size_deviation(xy0, tri[measured], goal), tolerance)
    nodes, elements = int(movable.sum()), int(measured.sum())
    if not movable[tri].any():
        return mesh, _report(
            elements, 0, 0, 0, 0, before, before, tolerance, True, start
        )
    near, free = _around(xy0, tri, goal, movable, tolerance / 2, RELAX_RINGS)
    xy, done = _on_own(_relax, xy0, near, goal, free, min_angle, sweeps, step)
    tri, gone = _drop_crowded(xy, tri, movable, measured, goal, tolerance, min_angle)
    alive = (tri >= 0).all(axis=1)
    if gone.any():  # the lattice round each node taken out, relaxed again
        movable = movable & ~gone
        measured = np.asarray(zone[tri].all(axis=1) & alive, dtype=bool)
        near, free = _around(xy, tri[alive], goal, movable, tolerance / 2, RELAX_RINGS)
        xy, more = _on_own(_relax, xy, near, goal, free, min_angle, sweeps, step)
        done += more
    near, free = _around(xy, tri[alive], goal, movable, SETTLE * tolerance, 3)
    xy, more = _on_own(_settle, xy, near, goal, free, min_angle, sweeps, tolerance)
    done += more
    after = _shares(size_deviation(xy, tri[measured], goal), tolerance)
    moved = (xy != xy0).any(axis=1) & ~gone
    # the share within tolerance does not fall, nor the worst rise past it
    kept = (
        bool(moved.any() or gone.any())
        and after[0] >= before[0]
        and after[1] <= max(before[1], tolerance)
    )
    report = _report(
        int(measured.sum()) if kept else elements,
        nodes,
        int(moved.sum()) if kept else 0,
        int(gone.sum()) if kept else 0,
        done,
        before,
        after if kept else before,
        tolerance,
        kept,
        start,
    )
    if not kept:
        return mesh, report
    points = smoothing.moved_points(mesh.points, xy0, xy, to_plane)
    return _without(mesh, points, tri, gone), report


def _without(
    mesh: Mesh,
    points: NDArray[np.float64],
    tri: NDArray[np.int64],
    gone: NDArray[np.bool_],
) -> Mesh:
    """Return ``mesh`` at ``points`` with ``tri``; the nodes ``gone`` dropped.

    ``tri``'s ``-1`` rows are dropped too; the others keep their rows'
    regions (a hole's triangles took the rows of its node's own).
    """
    if not gone.any():
        return smoothing.mesh_with(mesh, points=points)
    keep = ~gone
    index = np.cumsum(keep) - 1
    alive = (tri >= 0).all(axis=1)
    return smoothing.mesh_with(
        mesh,
        points=points[keep],
        triangles=index[tri[alive]],
        regions=np.asarray(mesh.regions)[alive],
        boundary_edges=index[np.asarray(mesh.boundary_edges)],
        point_data={k: np.asarray(v)[keep] for k, v in mesh.point_data.items()},
    )


def size_deviation(
    xy: NDArray[np.float64], triangles: NDArray[np.int64], goal: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return each triangle's ``mean edge / mean of its nodes' goal - 1``.

    ``xy`` (N, 2) plane coordinates, ``triangles`` (M, 3), ``goal`` (N,) the
    target edge length at each node in the plane's units.

    Examples
    --------
    >>> xy = np.array([[0, 0], [110, 0], [0, 110.0]])
    >>> size_deviation(xy, np.array([[0, 1, 2]]), np.full(3, 100.0)).round(3)
    array([0.252])
    """
    p = np.asarray(xy, dtype=np.float64)[triangles]
    sides = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=2)
    deviation: NDArray[np.float64] = (
        sides.mean(axis=1) / goal[triangles].mean(axis=1) - 1.0
    )
    return deviation


def _around(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    goal: NDArray[np.float64],
    movable: NDArray[np.bool_],
    off: float,
    rings: int,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Return the work round the triangles off their size by more than ``off``.

    The movable nodes within ``rings`` rings of triangles of those, and every
    triangle at one of them: elsewhere the lattice is already at its size
    and a sweep would move nothing (on a large zone, most of it).
    """
    tri = tri[movable[tri].any(axis=1)]  # only these can change
    near = np.zeros(len(xy), dtype=bool)
    near[tri[np.abs(size_deviation(xy, tri, goal)) > off].ravel()] = True
    for _ in range(rings):
        near[tri[near[tri].any(axis=1)].ravel()] = True
    free = near & movable
    return tri[free[tri].any(axis=1)], free


def _on_own(
    work: Callable[..., tuple[NDArray[np.float64], int]],
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    goal: NDArray[np.float64],
    movable: NDArray[np.bool_],
    *args: Any,
) -> tuple[NDArray[np.float64], int]:
    """Run ``work`` on the nodes of ``tri`` alone, numbered afresh; put them back.

    A sweep's cost is then that of the triangles worked on, not of the mesh.
    """
    if not len(tri):
        return xy, 0
    nodes, local = np.unique(tri, return_inverse=True)
    moved, done = work(
        xy[nodes], local.reshape(tri.shape), goal[nodes], movable[nodes], *args
    )
    out = xy.copy()
    out[nodes] = moved
    return out, done


def _relax(
    xy0: NDArray[np.float64],
    tri: NDArray[np.int64],
    goal: NDArray[np.float64],
    movable: NDArray[np.bool_],
    min_angle: float,
    sweeps: int,
    step: float,
) -> tuple[NDArray[np.float64], int]:
    """Jacobi sweeps of the springs on the triangles ``tri``; the nodes, sweeps."""
    n = len(xy0)
    edges = unique_edges(tri, n)[0]
    a, b = edges[:, 0], edges[:, 1]
    rest = 0.5 * (goal[a] + goal[b])
    bar = np.minimum(smoothing.min_angles(xy0, tri), min_angle)
    nodes = np.flatnonzero(movable)
    xy = xy0.copy()
    done = 0
    for sweep in range(1, sweeps + 1):
        done = sweep
        d = xy[b] - xy[a]
        length = np.hypot(d[:, 0], d[:, 1])
        pull = ((length - rest) / np.maximum(length, 1e-300))[:, None] * d
        force = np.stack(
            [
                np.bincount(a, pull[:, k], n) - np.bincount(b, pull[:, k], n)
                for k in range(2)
            ],
            axis=1,
        )
        new = xy.copy()
        new[nodes] += step * force[nodes]
        new = _guarded(xy, new, tri, bar, movable)
        shift = np.hypot(*(new[nodes] - xy[nodes]).T)
        xy = new
        if not (shift > STILL * goal[nodes]).any():
            break
    return xy, done


def _settle(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    goal: NDArray[np.float64],
    movable: NDArray[np.bool_],
    min_angle: float,
    sweeps: int,
    tolerance: float,
) -> tuple[NDArray[np.float64], int]:
    """Let the triangles still off by near ``tolerance`` pull their own nodes.

    Gradient descent of ``sum r_t^2`` over those triangles alone, ``r_t`` a
    triangle's :func:`size_deviation`: where the lattice meets a boundary of
    edges shorter than the size, the springs leave the row of triangles on
    it squeezed, and only their own nodes (inside) moving away from the
    boundary bring their mean edge to the size. ``SETTLE`` of ``tolerance``
    is the mark, so that a triangle brought just inside it is not left on
    its edge. Guarded as :func:`_relax`; stops when no triangle is off.
    """
    n = len(xy)
    bar = np.minimum(smoothing.min_angles(xy, tri), min_angle)
    target = goal[tri].mean(axis=1)
    done = 0
    for sweep in range(1, sweeps + 1):
        p = xy[tri]
        sides = p[:, [1, 2, 0]] - p  # side k from node k to node k + 1
        length = np.linalg.norm(sides, axis=2)
        off = length.mean(axis=1) / target - 1.0
        pulling = np.abs(off) > SETTLE * tolerance
        active = np.zeros(n, dtype=bool)
        active[tri[pulling].ravel()] = True
        active &= movable
        if not active.any():
            break
        done = sweep
        # d(mean side)/d(node k) = (unit side k-1 - unit side k) / 3
        unit = sides / np.maximum(length, 1e-300)[..., None]
        weight = np.where(pulling, off, 0.0) * target / 3.0
        push = np.zeros_like(xy)
        for k in range(3):
            pull = weight[:, None] * (unit[:, k - 1] - unit[:, k])
            for axis in range(2):
                push[:, axis] -= np.bincount(tri[:, k], pull[:, axis], n)
        new = xy.copy()
        new[active] += STEP_SETTLE * push[active]
        xy = _guarded(xy, new, tri, bar, movable)
    return xy, done


def _drop_crowded(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    movable: NDArray[np.bool_],
    measured: NDArray[np.bool_],
    goal: NDArray[np.float64],
    tolerance: float,
    min_angle: float,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Take out movable nodes of 3 to 5 triangles that are squeezed.

    Such a node is one too many where two of Gmsh's fronts met: a lattice's
    nodes have 6 triangles, and no move of a node of 3 or 4 brings them to the
    size (nor of 5 whose triangles are on average more than half
    ``tolerance`` too small). Each, with an element of it more than
    ``tolerance`` too small, is taken out with its triangles, and the hole
    it leaves filled by the fan from one of its corners whose smallest angle
    is largest, if that is ``min_angle`` or more. A node next to one taken
    out stays. (The pass keeps all this only if the share within
    ``tolerance`` does not fall: :func:`conform_sizes`.)

    Returns the triangles, those of the holes in place of the first ones
    taken out and ``-1`` rows for the others (so rows keep their regions),
    and the nodes taken out.
    """
    n = len(xy)
    tri = tri.copy()
    gone = np.zeros(n, dtype=bool)
    valence = np.bincount(tri.ravel(), minlength=n)
    deviation = size_deviation(xy, tri, goal)
    small = np.zeros(n, dtype=bool)
    small[tri[measured & (deviation < -tolerance)].ravel()] = True
    mean = np.bincount(tri.ravel(), np.repeat(deviation, 3), n) / np.maximum(valence, 1)
    crowded = ((valence >= 3) & (valence <= 4)) | (
        (valence == 5) & (mean < -tolerance / 2)
    )
    candidates = np.flatnonzero(movable & small & crowded)
    if not len(candidates):
        return tri, gone
    star: dict[int, list[int]] = {int(v): [] for v in candidates}
    near = np.flatnonzero(np.isin(tri, candidates).any(axis=1))
    for k, t in zip(near.tolist(), tri[near].tolist(), strict=True):
        for v in t:
            if v in star:
                star[v].append(k)
    touched = np.zeros(n, dtype=bool)
    for v, rows in star.items():
        if touched[v]:  # next to a node taken out: its triangles changed
            continue
        ring = _ring(tri[rows], v)
        if ring is None or touched[ring].any():
            continue
        best = _best_fill(xy, ring, min_angle)
        if best is None:
            continue
        rows_sorted = sorted(rows)
        tri[rows_sorted[: len(best)]] = best
        tri[rows_sorted[len(best) :]] = -1
        gone[v] = True
        touched[ring] = True
        touched[v] = True
    return tri, gone


def _best_fill(
    xy: NDArray[np.float64], ring: list[int], min_angle: float
) -> NDArray[np.int64] | None:
    """Return the fan over ``ring`` of the largest smallest angle, >= ``min_angle``."""
    m = len(ring)
    best, score = None, -np.inf
    for i in range(m if m > 3 else 1):  # the fan from each corner of the hole
        fan = np.array(
            [
                [ring[i], ring[(i + j) % m], ring[(i + j + 1) % m]]
                for j in range(1, m - 1)
            ],
            dtype=np.int64,
        )
        if (signed_areas(xy[fan]) <= 0).any():
            continue
        angle = float(smoothing.min_angles(xy, fan).min())
        if angle >= min_angle and angle > score:
            best, score = fan, angle
    return best


def _ring(star: NDArray[np.int64], v: int) -> list[int] | None:
    """Return the neighbours of ``v`` in counter-clockwise order; None if open."""
    after = {}
    for t in star.tolist():
        i = t.index(v)
        after[t[(i + 1) % 3]] = t[(i + 2) % 3]
    if len(after) != len(star):
        return None
    ring = [next(iter(after))]
    while len(ring) < len(after):
        nxt = after.get(ring[-1])
        if nxt is None or nxt in ring:
            return None
        ring.append(nxt)
    return ring if after.get(ring[-1]) == ring[0] else None


def _guarded(
    old: NDArray[np.float64],
    new: NDArray[np.float64],
    tri: NDArray[np.int64],
    bar: NDArray[np.float64],
    movable: NDArray[np.bool_],
) -> NDArray[np.float64]:
    """Undo the moves of the nodes of triangles that turn over or pass ``bar``.

    A triangle whose nodes are all back where they were is as it was, so the
    rounds end; after :data:`_GUARD_ROUNDS` the whole sweep is undone.

    The first round looks at every triangle. A later one looks only at the
    triangles at a node put back and at those still bad: no other triangle
    changed since it was found good, and each triangle's test reads its own
    corners alone, so the flags (and the result) are those of testing all.
    """
    check = np.arange(len(tri))
    for _ in range(_GUARD_ROUNDS):
        corners = tri[check]
        bad = (signed_areas(new[corners]) <= 0) | (
            smoothing.min_angles(new, corners) < bar[check]
        )
        if not bad.any():
            return new
        back = np.unique(corners[bad].ravel())
        back = back[movable[back]]
        new[back] = old[back]
        put_back = np.zeros(len(new), dtype=bool)
        put_back[back] = True
        again: NDArray[np.bool_] = np.asarray(put_back[tri].any(axis=1))
        again[check[bad]] = True
        check = np.flatnonzero(again)
    return old.copy()


def _held(mesh: Mesh) -> NDArray[np.bool_]:
    """Nodes that never move: on the boundary, a line, or between regions."""
    held = smoothing.boundary_nodes(mesh.triangles, len(mesh.points))
    if mesh.lines:
        held[mesh.line_edges()[0].ravel()] = True
    if len(np.unique(mesh.regions)) > 1:
        held[region_interfaces(mesh).ravel()] = True
    return held


def _scale(
    mesh: Mesh, to_plane: Transformer | None, zone: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """Return the plane's scale factor at each node of ``zone`` (1 elsewhere).

    Sizes are metres on the Earth; a length of ``h`` there is ``h k`` in a
    conformal plane of scale factor ``k`` (as the mesher converts the grid).
    A mesh without a CRS is its own plane (1).
    """
    k = np.ones(len(mesh.points))
    if mesh.crs is None or not zone.any():
        return k
    plane = mesh.crs if to_plane is None else CRS.from_user_input(to_plane.target_crs)
    # from the mesh's own points, not the plane's (geometry.projection's
    # scale_factor): its k differs by 1e-10, and that moves the result
    geodetic = Transformer.from_crs(mesh.crs, mesh.crs.geodetic_crs, always_xy=True)
    lon, lat = geodetic.transform(*np.asarray(mesh.points)[zone].T)
    factors = Proj(plane).get_factors(lon, lat)
    k[zone] = np.asarray(factors.meridional_scale, dtype=np.float64)
    return k


def _shares(deviation: NDArray[np.float64], tolerance: float) -> tuple[float, float]:
    """Return the share within ``tolerance`` and the worst ``|deviation|``."""
    if not len(deviation):
        return 1.0, 0.0
    off = np.abs(deviation)
    return float(np.mean(off <= tolerance)), float(off.max())


def _report(
    elements: int,
    nodes: int,
    moved: int,
    removed: int,
    sweeps: int,
    before: tuple[float, float],
    after: tuple[float, float],
    tolerance: float,
    kept: bool,
    start: float,
) -> ConformReport:
    return ConformReport(
        elements=elements,
        nodes=nodes,
        nodes_moved=moved,
        nodes_removed=removed,
        sweeps=sweeps,
        within_before=before[0],
        within_after=after[0],
        worst_before=before[1],
        worst_after=after[1],
        tolerance=tolerance,
        kept=kept,
        seconds=time.perf_counter() - start,
    )


def _check_options(
    tolerance: float, sweeps: int, min_angle: float, step: float
) -> None:
    for name, value, ok, want in (
        ("tolerance", tolerance, 0.0 < tolerance < 1.0, "in (0, 1)"),
        ("sweeps", sweeps, isinstance(sweeps, int) and sweeps >= 1, ">= 1"),
        ("min_angle", min_angle, 0.0 <= min_angle < 60.0, "in [0, 60) degrees"),
        ("step", step, 0.0 < step <= 0.3, "in (0, 0.3]"),
    ):
        if not ok:
            raise ConfigError(f"conform_sizes: {name} = {value!r}; it must be {want}")
