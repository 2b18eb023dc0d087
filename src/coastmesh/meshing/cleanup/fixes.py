"""Mesh cleanup for what ocean models choke on, then smoothing, never for the worse.

- **Triangles with all three nodes on the boundary** (they make SCHISM, ADCIRC and
  SWAN unstable near the coast): the best of flipping an interior edge, splitting
  one (a new node joined to both opposite corners, at the best of a grid of
  points) or a centroid split, if its minimum angle is at least half of
  ``min_angle`` and no new triangle has an inscribed radius below 0.6 of the
  fixed one's. Across a channel one element wide every fix makes such a
  triangle, which would set the stable time step of the whole mesh: those stay,
  counted (close the channel, or lower ``h_min`` so that it is resolved).
- **Nodes shared by too many triangles** (``max_valence``): interior edges at the
  node are flipped away when that lowers its valence without raising a neighbour
  above the limit or lowering the local minimum angle below ``min_angle``.
- **Slivers** (minimum angle below ``min_angle``): the edge opposite the widest
  angle is flipped when that raises the smaller minimum angle of the pair;
  else split (a new node on it, at the best of the same grid of points, joined
  to both opposite corners) when that does, and no new triangle has an
  inscribed radius below 0.6 of the sliver's.
- **Smoothing** (:func:`~coastmesh.meshing.cleanup.smoothing.smooth_points`) of the
  nodes of the worst 5% of triangles and any with an angle below 35 degrees, then
  **acceptance**: the minimum angle, and the 1st percentile of the triangles'
  minimum angles, must be no lower than the input's, nor the worst radius ratio
  lower than the input's or 0.5 (on the Pentland Firth, the full pass fixed one
  more all-boundary triangle than the next attempt, but left a radius ratio of
  0.17 for Gmsh's 0.29 and two more slivers); if not, the passes run
  again with only the boundary fixes and valence flips that keep the input's
  smallest angle and smallest radius ratio, then with only the fixes that keep
  its 1st percentile; then the input is smoothed
  only; then it is returned as it is.

Boundary edges and their ids never change. Angles are measured in a conformal
projection centred on the mesh, so they are angles on the Earth. Fixes are a few
per thousand triangles: plain loops over the candidates (no maintained Python
library edits triangle meshes in place).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.meshing.cleanup import smoothing
from coastmesh.meshing.cleanup.editable import EditableMesh
from coastmesh.meshing.cleanup.planar import (
    radius_ratios,
    signed_areas,
    smallest_r_in,
    triangle_angles,
)
from coastmesh.meshing.cleanup.report import (
    Accepted,
    CleanupOptions,
    CleanupReport,
    no_worse,
    stats,
)
from coastmesh.types import Mesh
from coastmesh.types.topology import unique_edges

__all__ = ["CleanupOptions", "CleanupReport", "clean_mesh", "fix_seam_slivers"]

logger = logging.getLogger(__name__)
#: where an edge split may put its node: weighted means of the edge's ends and
#: the opposite corners, weights in tenths, at least two of them nonzero
_SPLIT_WEIGHTS = np.array(
    [(i, j, k, 10 - i - j - k) for i in range(11) for j in range(11 - i)
     for k in range(11 - i - j) if sorted((i, j, k, 10 - i - j - k))[2]]
) / 10.0  # fmt: skip


def clean_mesh(
    mesh: Mesh,
    *,
    boundary_triangles: bool = True,
    max_valence: int | None = None,
    min_angle: float = 20.0,
    smooth: bool = True,
    fixed: NDArray[np.bool_] | None = None,
) -> tuple[Mesh, CleanupReport]:
    """Fix all-boundary triangles, over-connected nodes and slivers; smooth.

    Parameters
    ----------
    mesh : Mesh
        The mesh (triangles counter-clockwise).
    boundary_triangles : bool
        Remove triangles whose three nodes are all on the boundary.
    max_valence : int, optional
        Largest number of triangles at an interior node (e.g. 8); none by default.
    min_angle : float
        Triangles with a smaller minimum angle (degrees) are slivers.
    smooth : bool
        Smooth interior nodes after the flips and splits.
    fixed : ndarray of bool, shape (N,), optional
        Nodes that are not on the boundary but must not move or count in the
        valence either: the nodes of the cuts of a mesh made in parts.

    Returns
    -------
    mesh : Mesh
        The same boundary edges and ids; new nodes (from splits) appended, with
        point data averaged from their neighbours; moved nodes keep theirs. Its
        minimum angle and 1st percentile of minimum angles are no lower than
        the input's, its worst radius ratio no lower than the input's or 0.5.
    report : CleanupReport

    Examples
    --------
    >>> pts = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1.0]]
    >>> tri = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> m = Mesh(pts, tri, [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None)
    >>> clean, report = clean_mesh(m)
    >>> report.boundary_triangles_before, len(clean.triangles), report.accepted
    (0, 4, 'cleaned')
    """
    CleanupOptions(boundary_triangles, max_valence, min_angle, smooth)  # checks
    region = (boundary_triangles, max_valence, min_angle)
    work = _Work(mesh, fixed, region)
    before = stats(work.xy, mesh.triangles, work.on_boundary, min_angle, fixed)
    good = max(35.0, smoothing.percentile(work.angles, 5))  # the worst 5% move
    # (accepted, least angle and radius ratio a boundary fix leaves, least
    # angle and radius ratio a valence flip leaves)
    rr = before["radius_ratio"]
    floors: list[tuple[Accepted, float, float, float, float]] = [
        ("cleaned", min_angle / 2, 0.0, 0.0, 0.0)
    ]
    if (boundary_triangles and before["boundary_triangles"]) or max_valence:
        # only the fixes and flips that keep the input's smallest angle and
        # radius ratio, then the fixes that keep its 1st percentile: one fix
        # that smoothing cannot make up for then no longer undoes the pass
        least = before["min_angle"]
        floors.append(("cleaned_partly", max(min_angle / 2, least), rr, least, rr))
        if boundary_triangles and before["min_angle_p1"] > floors[-1][1]:
            floors.append(("cleaned_partly", before["min_angle_p1"], rr, least, rr))
    for attempt, (accepted, *floor) in enumerate(floors):
        work = work if attempt == 0 else _Work(mesh, fixed, region)
        counts = work.clean(floor, boundary_triangles, max_valence, min_angle)
        if attempt and not any(counts.values()):
            continue  # the input again: "smoothed only", below, covers it
        xy, tri, on_boundary = work.arrays()
        held = smoothing.boundary_nodes(tri, len(xy)) | work.held()
        if _cannot_pass(xy, tri, held, before):
            logger.debug("cleanup: %s %s fails before smoothing", accepted, counts)
            continue  # smoothing (the costly step) could not save it
        xy, moved = _smoothed(xy, tri, held, good) if smooth else (xy, 0)
        after = stats(xy, tri, on_boundary, min_angle, work.held())
        logger.debug("cleanup: %s %s, min angle and p1 %s", accepted, counts, after)
        if no_worse(after, before):
            break
    else:
        counts = dict.fromkeys(counts, 0)
        xy, moved, after, accepted = work.xy, 0, before, "input"
        if smooth:
            held = smoothing.boundary_nodes(mesh.triangles, len(work.xy)) | work.fixed
            smoothed, n = _smoothed(work.xy, mesh.triangles, held, good)
            kept = stats(smoothed, mesh.triangles, work.on_boundary, min_angle, fixed)
            if n and no_worse(kept, before):
                xy, moved, after, accepted = smoothed, n, kept, "smoothed_only"
    report = CleanupReport(
        **{f"{name}_before": value for name, value in before.items()},
        **{f"{name}_after": value for name, value in after.items()},
        smoothed_nodes=moved,
        accepted=accepted,
        **counts,
    )
    if accepted == "input":
        return mesh, report
    if accepted.startswith("cleaned"):
        return work.result(xy), report
    points = smoothing.moved_points(mesh.points, work.xy, xy, work.to_plane)
    return smoothing.mesh_with(mesh, points=points), report


def fix_seam_slivers(
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    edges: NDArray[np.int64],
    seam: NDArray[np.int64],
    held: NDArray[np.bool_],
    min_angle: float,
) -> tuple[NDArray[np.float64], NDArray[np.int64], tuple[int, int]]:
    """Flip, else split, the slivers at the seams of a mesh joined from parts.

    A part's cleanup cannot reach a sliver whose widest angle faces the cut:
    the edge there has its other triangle in the next part (a cut ending at
    a cape's tip leaves one, flat, at the coast). Joined, the edge is inside:
    the slivers with a node in ``seam`` get the pass of :func:`clean_mesh`
    (flip, else split; each raises its pair's smaller angle). ``points`` are
    plane coordinates (a conformal plane); the ``held`` nodes (lines,
    outlines, turbines) neither move nor lose an edge.

    Returns the points (new nodes last), the triangles, and the flips and
    splits made.
    """
    xy = np.asarray(points, dtype=np.float64)[:, :2]
    at_seam = np.zeros(len(xy), dtype=bool)
    at_seam[seam] = True
    near = np.flatnonzero(at_seam[triangles].any(axis=1))
    slivers = near[smoothing.min_angles(xy, triangles[near]) < min_angle]
    if not len(slivers):
        return points, triangles, (0, 0)
    # the triangles within two of the slivers' nodes, as a mesh of their own:
    # its edges with one triangle are its boundary (never flipped or split),
    # so a fix there is one in the whole mesh
    around = np.zeros(len(xy), dtype=bool)
    around[triangles[slivers].ravel()] = True
    for _ in range(2):
        around[triangles[around[triangles].any(axis=1)].ravel()] = True
    local = np.flatnonzero(around[triangles].all(axis=1))
    nodes, sub = np.unique(triangles[local], return_inverse=True)
    sub = sub.reshape(-1, 3)
    pairs, count = unique_edges(sub, len(nodes))
    edges = pairs[count == 1]
    probe = Mesh(xy[nodes], sub, edges, np.ones(len(edges), dtype=np.int64), 1, None)
    work = _Work(probe, np.asarray(held, dtype=bool)[nodes], (False, None, min_angle))
    # no edge between held nodes is flipped or split (a line's, an outline's)
    for t in work.tri.values():
        for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if held[nodes[u]] and held[nodes[v]]:
                work.locked.add((min(u, v), max(u, v)))
    # only the seam's slivers: the parts' own cleanups tried the rest
    where = np.searchsorted(local, slivers)
    flips, splits = work.flip_slivers(min_angle, None, where)
    if not flips + splits:
        return points, triangles, (0, 0)
    new_xy, new_tri, _ = work.arrays()
    extra = new_xy[len(nodes) :]
    number = np.concatenate([nodes, len(xy) + np.arange(len(extra))])
    out = np.delete(triangles, local, axis=0)
    out = np.concatenate([out, number[new_tri]])
    return np.concatenate([xy, extra]), out, (flips, splits)


def _smoothed(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    held: NDArray[np.bool_],
    good: float,
) -> tuple[NDArray[np.float64], int]:
    """Return ``xy`` smoothed with the ``held`` nodes fixed, and the nodes moved."""
    new = smoothing.smooth_points(xy, tri, held, good_angle=good)[0]
    return new, int((new != xy).any(axis=1).sum())


def _cannot_pass(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    held: NDArray[np.bool_],
    before: dict[str, float],
) -> bool:
    """Whether a triangle smoothing cannot touch already fails the acceptance.

    Smoothing moves no ``held`` node, so a triangle of three held nodes keeps
    its angles and radius ratio: if one is below the input's smallest angle, or
    its worst radius ratio (or 0.5), the pass fails whatever smoothing does, and
    is not smoothed (the costly step of a pass).
    """
    stuck = tri[held[tri].all(axis=1)]
    if not len(stuck):
        return False
    after = {
        "min_angle": float(smoothing.min_angles(xy, stuck).min()),
        "min_angle_p1": np.inf,  # the 1st percentile cannot be told here
        "radius_ratio": float(radius_ratios(xy[stuck]).min()),
    }
    return not no_worse(after, before)


#: Least inscribed radius a fix may leave, over the fixed triangle's (module notes)
_R_IN_KEPT = 0.6


class _Work(EditableMesh):
    """The mesh being cleaned: the passes over an :class:`EditableMesh`."""

    def _edge_split(
        self, k: int, u: int, v: int
    ) -> (
        tuple[
            float, int, NDArray[np.float64], tuple[int, ...], float, NDArray[np.float64]
        ]
        | None
    ):
        """Return the best split of edge (u, v) of triangle k, or None.

        (quality, k2, point, (u, v, a, b), r_in, pieces): a new node joined to
        a and b; r_in the smallest inscribed radius of the four triangles.
        """
        quad = self._quad(k, u, v)
        if quad is None:
            return None
        k2, u, v, a, b = quad
        corners = np.array([self.point(w) for w in (u, v, a, b)])
        w = _SPLIT_WEIGHTS @ corners
        pu, pv, pa, pb = (np.broadcast_to(c, w.shape) for c in corners)
        pieces = np.stack([[pu, w, pa], [w, pv, pa], [pv, w, pb], [w, pu, pb]])
        pieces = pieces.transpose(2, 0, 1, 3).reshape(-1, 3, 2)  # (4 K, 3, 2)
        quality = triangle_angles(pieces).min(axis=1).reshape(-1, 4).min(axis=1)
        quality[(signed_areas(pieces) <= 0).reshape(-1, 4).any(axis=1)] = -1.0
        best = int(np.argmax(quality))
        if quality[best] < 0:
            return None
        best_pieces = pieces.reshape(-1, 4, 3, 2)[best]
        r_in = smallest_r_in(best_pieces)
        return float(quality[best]), k2, w[best], (u, v, a, b), r_in, best_pieces

    def clean(
        self,
        floor: list[float],
        boundary: bool,
        max_valence: int | None,
        min_angle: float,
    ) -> dict[str, int]:
        """Make every pass; return the report's counts of fixes.

        ``floor``: the least minimum angle and radius ratio a boundary fix
        leaves, and the least angle and radius ratio a valence flip leaves.
        """
        fixes = self.fix_boundary_triangles(*floor[:2]) if boundary else (0, 0, 0)
        names = ("boundary_flips", "boundary_splits", "boundary_edge_splits")
        counts = dict(zip(names, fixes, strict=True))
        counts["valence_flips"] = (
            0
            if max_valence is None
            else self.reduce_valence(max_valence, min_angle, floor[2], floor[3])
        )
        flips, splits = self.flip_slivers(min_angle, max_valence)
        counts["sliver_flips"], counts["sliver_splits"] = flips, splits
        return counts

    def fix_boundary_triangles(
        self, floor: float, rr_floor: float = 0.0
    ) -> tuple[int, int, int]:
        done = [0, 0, 0]  # flips, centroid splits, edge splits
        fixes: tuple[Callable[..., None], ...] = (
            self._apply,
            self._split,
            self._split_edge,
        )
        # candidates found at once with numpy; the loop visits only those
        candidates = np.flatnonzero(self.on_boundary[self.mesh.triangles].all(axis=1))
        for k in candidates.tolist():
            t = self.tri[k]
            if not self.all_boundary(t):
                continue
            corners = [self.point(v) for v in t]
            centre = np.mean(corners, axis=0)
            pieces = [[corners[i], corners[(i + 1) % 3], centre] for i in range(3)]
            # (quality, preference on a tie, kind, arguments, smallest r_in,
            # new triangles)
            options: list[tuple[float, int, int, tuple[Any, ...], float, Any]] = [
                (
                    triangle_angles(np.array(pieces)).min(),
                    1,
                    1,
                    (),
                    smallest_r_in(pieces),
                    pieces,
                )
            ]
            for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                flip = self._flipped(k, u, v)
                if flip and not any(map(self.all_boundary, flip[1:])):
                    xy = [[self.point(w) for w in f] for f in flip[1:]]
                    options.append(
                        (self.min_angle(*flip[1:]), 2, 0, flip, smallest_r_in(xy), xy)
                    )
                split = self._edge_split(k, u, v)
                if split is not None:
                    options.append((split[0], 0, 2, split[1:4], split[4], split[5]))
            # no fix may leave a far smaller element (across a channel one
            # element wide all do): it would set the whole mesh's time step
            least = _R_IN_KEPT * smallest_r_in([corners])
            options = [
                o
                for o in options
                if o[4] >= least
                and o[0] >= floor
                and (not rr_floor or radius_ratios(o[5]).min() >= rr_floor)
            ]
            if options:
                _, _, kind, arguments, *_ = max(options, key=lambda o: o[:2])
                fixes[kind](k, *arguments)
                done[kind] += 1
        return done[0], done[1], done[2]

    def reduce_valence(
        self, limit: int, min_angle: float, floor: float = 0.0, rr_floor: float = 0.0
    ) -> int:
        flips, n = 0, len(self.valence)
        for _ in range(3):
            crowded = np.flatnonzero(self.valence > limit)
            crowded = crowded[~self.fixed[crowded]]
            if len(crowded) == 0:
                break
            for p in crowded:
                for key in self.incident_edges(int(p)):
                    if self.valence[p] <= limit:
                        break
                    pair = self.edges.get(key, [])
                    flipped = self._flipped(pair[0], *key) if len(pair) == 2 else None
                    if flipped is None:
                        continue
                    k2, new1, new2 = flipped  # new1[1:]: the nodes that gain
                    if any(w < n and self.valence[w] + 1 > limit for w in new1[1:]):
                        continue
                    old = self.min_angle(self.tri[pair[0]], self.tri[k2])
                    new = self.min_angle(new1, new2)
                    worse = new < min(old, min_angle) or new < floor
                    if rr_floor and not worse:
                        xy = [[self.point(w) for w in t] for t in (new1, new2)]
                        worse = radius_ratios(xy).min() < rr_floor
                    if worse or any(map(self.all_boundary, flipped[1:])):
                        continue
                    self._apply(pair[0], k2, new1, new2)
                    flips += 1
        return flips

    def flip_slivers(
        self, min_angle: float, limit: int | None, only: NDArray[np.int64] | None = None
    ) -> tuple[int, int]:
        """Flip, else split, the edge opposite each sliver's widest angle.

        ``only``: the triangles to try (default: every sliver).

        Returns the flips and the splits. A split (a new node on the edge,
        joined to both opposite corners) lifts a cap whose flip cannot: a
        coast node at a cape, its angle of water shared by two triangles, one
        of them flat, where the flip would make a triangle of three coast
        nodes.
        """
        done, n = [0, 0], len(self.valence)
        if only is None:
            xy, tri, _ = self.arrays()
            only = np.flatnonzero(triangle_angles(xy[tri]).min(axis=1) < min_angle)
        for k in only.tolist():
            t = self.tri[k]
            angles = triangle_angles(np.array([[self.point(v) for v in t]]))[0]
            if angles.min() >= min_angle:
                continue
            widest = int(np.argmax(angles))
            u, v = t[(widest + 1) % 3], t[(widest + 2) % 3]  # the opposite edge
            quad = self._quad(k, u, v)
            if quad is None:
                continue
            k2, *_, a, b = quad
            if limit is not None and any(
                w < n and not self.fixed[w] and self.valence[w] + 1 > limit
                for w in (a, b)
            ):
                continue
            old = self.min_angle(t, self.tri[k2])
            flipped = self._flipped(k, u, v)
            if flipped is not None:
                _, new1, new2 = flipped
                if self.min_angle(new1, new2) > old and not any(
                    map(self.all_boundary, flipped[1:])
                ):
                    self._apply(k, k2, new1, new2)
                    done[0] += 1
                    continue
            split = self._edge_split(k, u, v)
            least = _R_IN_KEPT * smallest_r_in([[self.point(w) for w in t]])
            if split is not None and split[0] > old and split[4] >= least:
                self._split_edge(k, *split[1:4])
                done[1] += 1
        return done[0], done[1]
