"""A triangle mesh to edit in place: flips, splits, new nodes (for the cleanup).

No maintained Python library edits a triangle mesh in place (flip an edge,
split a triangle, keep the edge map and the triangles at each node up to
date), so :class:`EditableMesh` does it, with plain Python structures built
only where the edits can happen. :mod:`coastmesh.meshing.cleanup.fixes` decides which
edits to make.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.sphere import local_plane
from coastmesh.meshing.cleanup import smoothing
from coastmesh.meshing.cleanup.planar import signed_areas, triangle_angles
from coastmesh.types import Mesh

__all__ = ["EditableMesh"]


class EditableMesh:
    """A triangle mesh being edited: triangles, edge map, boundary nodes, valences.

    The edge map and the triangles at each node are Python structures, built
    only around the nodes that a pass can touch (``watch``, default all): the
    nodes of all-boundary triangles and slivers, and crowded nodes, and their
    neighbours. Every triangle at a watched node is loaded, so an edge with a
    watched end is complete, and every fix joins watched nodes only: the
    result is the same as with the whole mesh loaded (tested), for a few
    thousand triangles instead of millions.
    """

    def __init__(
        self,
        mesh: Mesh,
        fixed: NDArray[np.bool_] | None = None,
        region: tuple[bool, int | None, float] | None = None,
    ) -> None:
        """Load the mesh; ``region``: (boundary fixes, max valence, min angle)."""
        self.mesh = mesh
        self.to_plane = local_plane(mesh)
        self.xy = smoothing.plane_points(mesh.points, self.to_plane)
        self.extra_xy: list[NDArray[np.float64]] = []  # new nodes, and the
        self.extra_from: list[tuple[int, ...]] = []  # neighbours of each
        self.on_boundary = np.zeros(len(mesh.points), dtype=bool)
        self.on_boundary[mesh.boundary_edges.ravel()] = True
        self.fixed = self.on_boundary.copy()  # nodes that never move
        if fixed is not None:
            self.fixed |= np.asarray(fixed, dtype=bool)
        # the edges of the mesh's lines are never flipped or split, and their
        # nodes never move
        line_edges = mesh.line_edges()[0]
        self.fixed[line_edges.ravel()] = True
        self.locked = {(min(u, v), max(u, v)) for u, v in line_edges.tolist()}
        n = len(mesh.points)
        self.angles = smoothing.min_angles(self.xy, mesh.triangles)
        self.valence = np.bincount(mesh.triangles.ravel(), minlength=n)
        self.watch = np.ones(n, bool) if region is None else self._region(*region)
        loaded = np.flatnonzero(self.watch[mesh.triangles].any(axis=1))
        self.count = len(mesh.triangles)  # the next new triangle's number
        self.tri = dict(
            zip(loaded.tolist(), mesh.triangles[loaded].tolist(), strict=True)
        )
        self.edges: dict[tuple[int, int], list[int]] = {}
        self.node_tris: dict[int, set[int]] = {}
        for k, t in self.tri.items():  # in order of k, as the arrays have them
            self._link(k, t)

    def _region(
        self, boundary: bool, limit: int | None, min_angle: float
    ) -> NDArray[np.bool_]:
        """Return the nodes a pass can touch, and their neighbours."""
        tri = self.mesh.triangles
        bad = self.angles < min_angle
        if boundary:
            bad |= self.on_boundary[tri].all(axis=1)
        watch = np.zeros(len(self.xy), dtype=bool)
        watch[tri[bad].ravel()] = True
        if limit is not None:
            watch |= (self.valence > limit) & ~self.fixed
        watch[tri[watch[tri].any(axis=1)].ravel()] = True
        return watch

    def _complete(self, node: int) -> bool:
        return node >= len(self.watch) or bool(self.watch[node])

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
        """Return the edges at node ``p`` (a watched or new node), sorted."""
        if not self._complete(p):
            raise RuntimeError(f"cleanup: node {p} is outside the loaded region")
        keys = set()
        for k in self.node_tris.get(p, ()):
            for w in self.tri[k]:
                if w != p:
                    keys.add((min(p, w), max(p, w)))
        return sorted(keys)

    def point(self, node: int) -> NDArray[np.float64]:
        """Return a node's plane coordinates (new nodes too)."""
        n = len(self.xy)
        return self.xy[node] if node < n else self.extra_xy[node - n]

    def min_angle(self, *triangles: list[int]) -> float:
        """Return the smallest angle of the given triangles, degrees."""
        xy = np.array([[self.point(v) for v in t] for t in triangles])
        return float(triangle_angles(xy).min())

    def area(self, t: list[int]) -> float:
        """Return a triangle's signed area in the plane."""
        return float(signed_areas(np.array([[self.point(v) for v in t]]))[0])

    def all_boundary(self, t: list[int]) -> bool:
        """Whether all three nodes of a triangle are on the boundary."""
        n = len(self.on_boundary)
        return all(v < n and self.on_boundary[v] for v in t)

    def _quad(self, k: int, u: int, v: int) -> tuple[int, ...] | None:
        """Return (k2, u, v, a, b): k2 across edge u -> v of k, a and b opposite."""
        if not (self._complete(u) or self._complete(v)):
            raise RuntimeError(f"cleanup: edge {u}-{v} is outside the loaded region")
        key = (min(u, v), max(u, v))
        pair = self.edges.get(key, [])
        if len(pair) != 2 or key in self.locked:
            return None  # a boundary edge, or an edge of a line
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

    def _new_node(self, point: NDArray[np.float64], neighbours: tuple[int, ...]) -> int:
        self.extra_xy.append(point)
        self.extra_from.append(neighbours)
        return len(self.xy) + len(self.extra_xy) - 1

    def _replace(self, old: list[int], pieces: list[list[int]]) -> None:
        """Put ``pieces`` in place of triangles ``old``, then at the end."""
        for k in old:
            self._unlink(k, self.tri[k])
        for i, piece in enumerate(pieces):
            if i < len(old):
                k = old[i]
            else:
                k, self.count = self.count, self.count + 1
            self.tri[k] = piece
            self._link(k, piece)

    def _split(self, k: int) -> None:
        t = self.tri[k]
        corners = [self.point(v) for v in t]
        node = self._new_node(np.mean(corners, axis=0), tuple(t))
        self._replace([k], [[t[i], t[(i + 1) % 3], node] for i in range(3)])
        np.add.at(self.valence, [w for w in t if w < len(self.valence)], 1)

    def _split_edge(
        self, k: int, k2: int, point: NDArray[np.float64], quad: tuple[int, ...]
    ) -> None:
        u, v, a, b = quad
        node = self._new_node(point, quad)
        pieces = [[u, node, a], [v, node, b], [node, v, a], [node, u, b]]
        self._replace([k, k2], pieces)
        np.add.at(self.valence, [w for w in (a, b) if w < len(self.valence)], 1)

    def held(self) -> NDArray[np.bool_]:
        """Return which of every node (new ones last) may not move."""
        return np.concatenate([self.fixed, np.zeros(len(self.extra_xy), bool)])

    def arrays(
        self,
    ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.bool_]]:
        """Return every node's plane coordinates, the triangles, the boundary."""
        xy = np.concatenate([self.xy, np.array(self.extra_xy).reshape(-1, 2)])
        on_boundary = np.zeros(len(xy), dtype=bool)
        on_boundary[: len(self.xy)] = self.on_boundary
        return xy, self.triangles(), on_boundary

    def triangles(self) -> NDArray[np.int64]:
        """Return every triangle: the mesh's, with the edited ones replaced."""
        tri = np.empty((self.count, 3), dtype=np.int64)
        tri[: len(self.mesh.triangles)] = self.mesh.triangles
        if self.tri:
            tri[np.fromiter(self.tri, np.int64)] = list(self.tri.values())
        return tri

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
            triangles=self.triangles(),
            point_data=point_data,
        )
