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
  angle is flipped when that raises the smaller minimum angle of the pair.
- **Smoothing** (:func:`~coastmesh.meshing.smoothing.smooth_points`) of the nodes
  of the worst 5% of triangles and any with an angle below 35 degrees, then
  **acceptance**: the minimum angle, and the 1st percentile of the triangles'
  minimum angles, must be no lower than the input's; if not, the passes run
  again with only the boundary fixes that keep the input's 1st percentile; then
  the input is smoothed only; then it is returned as it is.

Boundary edges and their ids never change. Angles are measured in a conformal
projection centred on the mesh, so they are angles on the Earth. Fixes are a few
per thousand triangles: plain loops over the candidates (no maintained Python
library edits triangle meshes in place).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import ConfigError
from coastmesh.meshing import smoothing
from coastmesh.meshing.planar import signed_areas, smallest_r_in, triangle_angles
from coastmesh.types import Mesh, Report

__all__ = ["CleanupReport", "clean_mesh"]

logger = logging.getLogger(__name__)
#: where an edge split may put its node: weighted means of the edge's ends and
#: the opposite corners, weights in tenths, at least two of them nonzero
_SPLIT_WEIGHTS = np.array(
    [(i, j, k, 10 - i - j - k) for i in range(11) for j in range(11 - i)
     for k in range(11 - i - j) if sorted((i, j, k, 10 - i - j - k))[2]]
) / 10.0  # fmt: skip


@dataclass(frozen=True, slots=True)
class CleanupReport(Report):
    """What :func:`clean_mesh` changed (the fixes in the mesh it returned).

    Attributes
    ----------
    boundary_triangles_before, boundary_triangles_after : int
        Triangles with all three nodes on the boundary.
    boundary_flips, boundary_splits, boundary_edge_splits : int
        Such triangles fixed by an edge flip, a centroid split, an edge split.
    max_valence_before, max_valence_after : int
        Most triangles at an interior node.
    slivers_before, slivers_after : int
        Triangles with a minimum angle below ``min_angle``.
    valence_flips, sliver_flips : int
        Flips that lowered crowded nodes' valence; that raised slivers' angles.
    min_angle_before, min_angle_after, min_angle_p1_before, min_angle_p1_after
        Smallest angle, and 1st percentile of minimum angles, degrees (float).
    smoothed_nodes : int
        Nodes moved by smoothing.
    accepted : {"cleaned", "cleaned_partly", "smoothed_only", "input"}
        The mesh returned (see the module notes): cleaned and smoothed; the same
        with only the boundary fixes that keep the input's 1st percentile; the
        input smoothed; or the input.
    """

    boundary_triangles_before: int
    boundary_triangles_after: int
    boundary_flips: int
    boundary_splits: int
    max_valence_before: int
    max_valence_after: int
    valence_flips: int
    slivers_before: int
    slivers_after: int
    sliver_flips: int
    min_angle_before: float
    min_angle_after: float
    boundary_edge_splits: int
    smoothed_nodes: int
    min_angle_p1_before: float
    min_angle_p1_after: float
    accepted: Literal["cleaned", "cleaned_partly", "smoothed_only", "input"]

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.accepted}: all-boundary triangles "
            f"{self.boundary_triangles_before} -> {self.boundary_triangles_after} "
            f"({self.boundary_flips} flips, {self.boundary_splits} + "
            f"{self.boundary_edge_splits} splits); max valence "
            f"{self.max_valence_before} -> {self.max_valence_after} "
            f"({self.valence_flips} flips); slivers {self.slivers_before} -> "
            f"{self.slivers_after} ({self.sliver_flips} flips); "
            f"{self.smoothed_nodes} nodes smoothed; min angle "
            f"{self.min_angle_before:.1f} -> {self.min_angle_after:.1f} deg, 1st "
            f"percentile {self.min_angle_p1_before:.1f} -> "
            f"{self.min_angle_p1_after:.1f} deg"
        )


def clean_mesh(
    mesh: Mesh,
    *,
    boundary_triangles: bool = True,
    max_valence: int | None = None,
    min_angle: float = 20.0,
    smooth: bool = True,
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

    Returns
    -------
    mesh : Mesh
        The same boundary edges and ids; new nodes (from splits) appended, with
        point data averaged from their neighbours; moved nodes keep theirs. Its
        minimum angle and 1st percentile of minimum angles are no lower than
        the input's.
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
    if max_valence is not None and max_valence < 4:
        raise ConfigError(f"max_valence = {max_valence}: must be at least 4")
    if not 0 < min_angle < 60:
        raise ConfigError(f"min_angle = {min_angle}: must be between 0 and 60 degrees")
    work = _Work(mesh)
    before = _stats(work.xy, mesh.triangles, work.on_boundary, min_angle)
    angles = smoothing.min_angles(work.xy, mesh.triangles)
    good = max(35.0, smoothing.percentile(angles, 5))  # the worst 5% move, at least
    floors = {"cleaned": min_angle / 2}
    p1 = before["min_angle_p1"]
    if boundary_triangles and before["boundary_triangles"] and p1 > min_angle / 2:
        floors["cleaned_partly"] = p1  # only the fixes that keep the 1st percentile
    for accepted, floor in floors.items():
        work = work if accepted == "cleaned" else _Work(mesh)
        counts = work.clean(floor, boundary_triangles, max_valence, min_angle)
        xy, tri, on_boundary = work.arrays()
        xy, moved = _smoothed(xy, tri, on_boundary, good) if smooth else (xy, 0)
        after = _stats(xy, tri, on_boundary, min_angle)
        logger.debug("cleanup: %s %s, min angle and p1 %s", accepted, counts, after)
        changed = moved or any(counts.values()) or accepted == "cleaned"
        if changed and _no_worse(after, before):
            break
    else:
        counts = dict.fromkeys(counts, 0)
        xy, moved, after, accepted = work.xy, 0, before, "input"
        if smooth:
            smoothed, n = _smoothed(work.xy, mesh.triangles, work.on_boundary, good)
            stats = _stats(smoothed, mesh.triangles, work.on_boundary, min_angle)
            if n and _no_worse(stats, before):
                xy, moved, after, accepted = smoothed, n, stats, "smoothed_only"
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


def _smoothed(xy: NDArray, tri: NDArray, fixed: NDArray, good: float) -> tuple:
    """Return ``xy`` smoothed with every boundary node fixed, and the nodes moved."""
    fixed = smoothing.boundary_nodes(tri, len(xy)) | fixed
    new = smoothing.smooth_points(xy, tri, fixed, good_angle=good)[0]
    return new, int((new != xy).any(axis=1).sum())


def _stats(xy: NDArray, tri: NDArray, on_boundary: NDArray, min_angle: float) -> dict:
    """Return the numbers the report has before and after."""
    angles = smoothing.min_angles(xy, tri)
    valence = np.bincount(tri.ravel(), minlength=len(xy))
    return {
        "boundary_triangles": int(on_boundary[tri].all(axis=1).sum()),
        "max_valence": int(valence[~on_boundary].max(initial=0)),
        "slivers": int((angles < min_angle).sum()),
        "min_angle": float(angles.min(initial=90.0)),
        "min_angle_p1": smoothing.percentile(angles, 1),
    }


def _no_worse(after: dict[str, float], before: dict[str, float]) -> bool:
    """Whether the minimum angle and its 1st percentile did not fall."""
    return all(after[k] >= before[k] for k in ("min_angle", "min_angle_p1"))


#: Least inscribed radius a fix may leave, over the fixed triangle's (module notes)
_R_IN_KEPT = 0.6


class _Work:
    """The mesh being edited: triangles, edge map, boundary nodes, valences."""

    def __init__(self, mesh: Mesh) -> None:
        self.mesh = mesh
        self.to_plane = smoothing.local_plane(mesh)
        self.xy = smoothing.plane_points(mesh.points, self.to_plane)
        self.extra_xy: list[NDArray[np.float64]] = []  # new nodes, and the
        self.extra_from: list[tuple[int, ...]] = []  # neighbours of each
        self.tri = [list(map(int, t)) for t in mesh.triangles]
        self.on_boundary = np.zeros(len(mesh.points), dtype=bool)
        self.on_boundary[mesh.boundary_edges.ravel()] = True
        self.edges: dict[tuple[int, int], list[int]] = {}
        self.node_tris: dict[int, set[int]] = {}
        for k, t in enumerate(self.tri):
            self._link(k, t)
        self.valence = np.bincount(mesh.triangles.ravel(), minlength=len(mesh.points))

    def _link(self, k: int, t: list[int]) -> None:
        for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            self.edges.setdefault((min(u, v), max(u, v)), []).append(k)
        for w in t:
            self.node_tris.setdefault(w, set()).add(k)

    def _unlink(self, k: int, t: list[int]) -> None:
        for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = (min(u, v), max(u, v))
            self.edges[key].remove(k)
            if not self.edges[key]:
                del self.edges[key]
        for w in t:
            self.node_tris[w].discard(k)

    def incident_edges(self, p: int) -> list[tuple[int, int]]:
        keys = set()
        for k in self.node_tris.get(p, ()):
            for w in self.tri[k]:
                if w != p:
                    keys.add((min(p, w), max(p, w)))
        return sorted(keys)

    def point(self, node: int) -> NDArray[np.float64]:
        n = len(self.xy)
        return self.xy[node] if node < n else self.extra_xy[node - n]

    def min_angle(self, *triangles: list[int]) -> float:
        xy = np.array([[self.point(v) for v in t] for t in triangles])
        return float(triangle_angles(xy).min())

    def area(self, t: list[int]) -> float:
        return float(signed_areas(np.array([[self.point(v) for v in t]]))[0])

    def all_boundary(self, t: list[int]) -> bool:
        n = len(self.on_boundary)
        return all(v < n and self.on_boundary[v] for v in t)

    def _quad(self, k: int, u: int, v: int) -> tuple[int, ...] | None:
        """Return (k2, u, v, a, b): k2 across edge u -> v of k, a and b opposite."""
        pair = self.edges.get((min(u, v), max(u, v)), [])
        if len(pair) != 2:
            return None  # a boundary edge
        k2 = pair[0] if pair[1] == k else pair[1]
        t = self.tri[k]
        if t[(t.index(u) + 1) % 3] != v:
            u, v = v, u
        a = t[(t.index(u) + 2) % 3]
        return k2, u, v, a, next(w for w in self.tri[k2] if w not in (u, v))

    def _flipped(
        self, k1: int, u: int, v: int
    ) -> tuple[int, list[int], list[int]] | None:
        """Return the flip of edge (u, v) of triangle k1: (k2, new t1, new t2)."""
        quad = self._quad(k1, u, v)
        if quad is None:
            return None
        k2, u, v, a, b = quad
        new1, new2 = [u, b, a], [b, v, a]
        if self.area(new1) <= 0 or self.area(new2) <= 0:
            return None  # the quadrilateral is not convex
        return k2, new1, new2

    def _apply(self, k1: int, k2: int, new1: list[int], new2: list[int]) -> None:
        n = len(self.valence)
        for t, change in ((self.tri[k1], -1), (self.tri[k2], -1), (new1, 1), (new2, 1)):
            np.add.at(self.valence, [w for w in t if w < n], change)
        self._replace([k1, k2], [new1, new2])

    def _new_node(self, point: NDArray[np.float64], neighbours: tuple) -> int:
        self.extra_xy.append(point)
        self.extra_from.append(neighbours)
        return len(self.xy) + len(self.extra_xy) - 1

    def _replace(self, old: list[int], pieces: list[list[int]]) -> None:
        """Put ``pieces`` in place of triangles ``old``, then at the end."""
        for k in old:
            self._unlink(k, self.tri[k])
        for i, piece in enumerate(pieces):
            k = old[i] if i < len(old) else len(self.tri)
            self.tri[k : k + 1] = [piece]
            self._link(k, piece)

    def _split(self, k: int) -> None:
        t = self.tri[k]
        corners = [self.point(v) for v in t]
        node = self._new_node(np.mean(corners, axis=0), tuple(t))
        self._replace([k], [[t[i], t[(i + 1) % 3], node] for i in range(3)])
        np.add.at(self.valence, [w for w in t if w < len(self.valence)], 1)

    def _edge_split(
        self, k: int, u: int, v: int
    ) -> tuple[float, int, NDArray[np.float64], tuple[int, ...], float] | None:
        """Return the best split of edge (u, v) of triangle k, or None.

        (quality, k2, point, (u, v, a, b), r_in): a new node joined to a and b;
        r_in the smallest inscribed radius of the four triangles.
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
        r_in = smallest_r_in(pieces.reshape(-1, 4, 3, 2)[best])
        return float(quality[best]), k2, w[best], (u, v, a, b), r_in

    def _split_edge(self, k: int, k2: int, point: NDArray, quad: tuple) -> None:
        u, v, a, b = quad
        node = self._new_node(point, quad)
        pieces = [[u, node, a], [v, node, b], [node, v, a], [node, u, b]]
        self._replace([k, k2], pieces)
        np.add.at(self.valence, [w for w in (a, b) if w < len(self.valence)], 1)

    def clean(
        self, floor: float, boundary: bool, max_valence: int | None, min_angle: float
    ) -> dict[str, int]:
        """Make every pass; return the report's counts of fixes."""
        fixes = self.fix_boundary_triangles(floor) if boundary else (0, 0, 0)
        names = ("boundary_flips", "boundary_splits", "boundary_edge_splits")
        counts = dict(zip(names, fixes, strict=True))
        counts["valence_flips"] = (
            0 if max_valence is None else self.reduce_valence(max_valence, min_angle)
        )
        counts["sliver_flips"] = self.flip_slivers(min_angle, max_valence)
        return counts

    def fix_boundary_triangles(self, floor: float) -> tuple[int, int, int]:
        done = [0, 0, 0]  # flips, centroid splits, edge splits
        # candidates found at once with numpy; the loop visits only those
        candidates = np.flatnonzero(self.on_boundary[self.mesh.triangles].all(axis=1))
        for k in candidates:
            t = self.tri[k]
            if not self.all_boundary(t):
                continue
            corners = [self.point(v) for v in t]
            centre = np.mean(corners, axis=0)
            pieces = [[corners[i], corners[(i + 1) % 3], centre] for i in range(3)]
            # (quality, preference on a tie, kind, arguments, smallest r_in)
            options = [
                (
                    triangle_angles(np.array(pieces)).min(),
                    1,
                    1,
                    (),
                    smallest_r_in(pieces),
                )
            ]
            for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                flip = self._flipped(k, u, v)
                if flip and not any(map(self.all_boundary, flip[1:])):
                    xy = [[self.point(w) for w in f] for f in flip[1:]]
                    options.append(
                        (self.min_angle(*flip[1:]), 2, 0, flip, smallest_r_in(xy))
                    )
                split = self._edge_split(k, u, v)
                if split is not None:
                    options.append((split[0], 0, 2, split[1:4], split[4]))
            # no fix may leave a far smaller element (across a channel one
            # element wide all do): it would set the whole mesh's time step
            least = _R_IN_KEPT * smallest_r_in([corners])
            options = [o for o in options if o[4] >= least and o[0] >= floor]
            if options:
                _, _, kind, arguments, _ = max(options, key=lambda o: o[:2])
                (self._apply, self._split, self._split_edge)[kind](k, *arguments)
                done[kind] += 1
        return done[0], done[1], done[2]

    def reduce_valence(self, limit: int, min_angle: float) -> int:
        flips, n = 0, len(self.valence)
        for _ in range(3):
            crowded = np.flatnonzero(self.valence > limit)
            crowded = crowded[~self.on_boundary[crowded]]
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
                    worse = self.min_angle(new1, new2) < min(old, min_angle)
                    if worse or any(map(self.all_boundary, flipped[1:])):
                        continue
                    self._apply(pair[0], k2, new1, new2)
                    flips += 1
        return flips

    def flip_slivers(self, min_angle: float, limit: int | None) -> int:
        flips, n = 0, len(self.valence)
        xy, tri, _ = self.arrays()
        for k in np.flatnonzero(triangle_angles(xy[tri]).min(axis=1) < min_angle):
            t = self.tri[k]
            angles = triangle_angles(np.array([[self.point(v) for v in t]]))[0]
            if angles.min() >= min_angle:
                continue
            widest = int(np.argmax(angles))
            u, v = t[(widest + 1) % 3], t[(widest + 2) % 3]  # the opposite edge
            flipped = self._flipped(k, u, v)
            if flipped is None:
                continue
            k2, new1, new2 = flipped
            if limit is not None and any(
                w < n and not self.on_boundary[w] and self.valence[w] + 1 > limit
                for w in new1[1:]
            ):
                continue
            better = self.min_angle(new1, new2) > self.min_angle(t, self.tri[k2])
            if better and not any(map(self.all_boundary, flipped[1:])):
                self._apply(k, k2, new1, new2)
                flips += 1
        return flips

    def arrays(self) -> tuple[NDArray, NDArray, NDArray]:
        """Return every node's plane coordinates, the triangles, the boundary."""
        xy = np.concatenate([self.xy, np.array(self.extra_xy).reshape(-1, 2)])
        on_boundary = np.zeros(len(xy), dtype=bool)
        on_boundary[: len(self.xy)] = self.on_boundary
        return xy, np.array(self.tri, dtype=np.int64), on_boundary

    def result(self, xy: NDArray[np.float64]) -> Mesh:
        """Return the edited mesh with its nodes at ``xy`` (plane coordinates)."""
        mesh, n = self.mesh, len(self.xy)
        points = np.full_like(xy, np.nan)  # new nodes: all moved, from nowhere
        points[:n] = mesh.points
        before = np.vstack([self.xy, points[n:]])
        point_data = dict(mesh.point_data)
        for name, values in point_data.items():
            full = np.zeros((len(xy), *values.shape[1:]), np.result_type(values, 1.0))
            full[:n] = values
            for i, neighbours in enumerate(self.extra_from, start=n):
                full[i] = full[list(neighbours)].mean(axis=0)  # in order: may use
            point_data[name] = full  # earlier new nodes
        return smoothing.mesh_with(
            mesh,
            points=smoothing.moved_points(points, before, xy, self.to_plane),
            triangles=np.array(self.tri, dtype=np.int64),
            point_data=point_data,
        )
