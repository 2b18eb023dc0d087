"""Mesh cleanup for what ocean models choke on, by local edge flips and splits.

- **Triangles with all three nodes on the boundary** (they make SCHISM, ADCIRC and
  SWAN unstable near the coast): either an interior edge of such a triangle is
  flipped (when the quadrilateral it spans is convex and the flip leaves no such
  triangle) or the triangle is split at its centroid (one new interior node),
  whichever leaves the larger minimum angle, if that is at least half of
  ``min_angle``; otherwise the triangle stays (and is counted).
- **Nodes shared by too many triangles** (``max_valence``): interior edges at the
  node are flipped away when that lowers its valence without raising a neighbour
  above the limit or lowering the local minimum angle below ``min_angle``.
- **Slivers** (minimum angle below ``min_angle``): the edge opposite the widest
  angle is flipped when that raises the smaller minimum angle of the pair.

Boundary edges and their ids never change, so the boundary lists of every format
stay as they were. Angles are measured in a conformal projection centred on the
mesh (an oblique stereographic for longitude/latitude), so they are angles on the
Earth. Flips and splits are a few per thousand triangles: written here as plain
loops over the candidates, since no maintained Python library edits triangle
meshes in place.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS, Transformer

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import transformer
from coastmesh.types import Mesh, Report

__all__ = ["CleanupReport", "clean_mesh"]


@dataclass(frozen=True, slots=True)
class CleanupReport(Report):
    """What :func:`clean_mesh` changed.

    Attributes
    ----------
    boundary_triangles_before, boundary_triangles_after : int
        Triangles with all three nodes on the boundary, before and after.
    boundary_flips, boundary_splits : int
        Such triangles fixed by flipping an interior edge, and by splitting the
        triangle at its centroid.
    max_valence_before, max_valence_after : int
        Most triangles at an interior node, before and after.
    valence_flips : int
        Edge flips that lowered the valence of crowded nodes.
    slivers_before, slivers_after : int
        Triangles with a minimum angle below ``min_angle``, before and after.
    sliver_flips : int
        Edge flips that raised the minimum angle of a sliver pair.
    min_angle_before, min_angle_after : float
        Smallest angle of the mesh, degrees, before and after.
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

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"all-boundary triangles {self.boundary_triangles_before} -> "
            f"{self.boundary_triangles_after} ({self.boundary_flips} flips, "
            f"{self.boundary_splits} splits); max valence {self.max_valence_before} "
            f"-> {self.max_valence_after} ({self.valence_flips} flips); slivers "
            f"{self.slivers_before} -> {self.slivers_after} ({self.sliver_flips} "
            f"flips); min angle {self.min_angle_before:.1f} -> "
            f"{self.min_angle_after:.1f} deg"
        )


def clean_mesh(
    mesh: Mesh,
    *,
    boundary_triangles: bool = True,
    max_valence: int | None = None,
    min_angle: float = 20.0,
) -> tuple[Mesh, CleanupReport]:
    """Fix all-boundary triangles, over-connected nodes and slivers.

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

    Returns
    -------
    mesh : Mesh
        The cleaned mesh: the same boundary edges and ids; new nodes (from
        splits) are appended, with point data averaged from their triangle.
    report : CleanupReport

    Examples
    --------
    >>> pts = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1.0]]
    >>> tri = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> m = Mesh(pts, tri, [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 1, 1, 1], 1, None)
    >>> clean, report = clean_mesh(m)
    >>> report.boundary_triangles_before, len(clean.triangles)
    (0, 4)
    """
    if max_valence is not None and max_valence < 4:
        raise ConfigError(f"max_valence = {max_valence}: must be at least 4")
    if not 0 < min_angle < 60:
        raise ConfigError(f"min_angle = {min_angle}: must be between 0 and 60 degrees")
    work = _Work(mesh)
    before = work.stats(min_angle)
    flips = splits = valence_flips = sliver_flips = 0
    if boundary_triangles:
        flips, splits = work.fix_boundary_triangles(min_angle / 2)
    if max_valence is not None:
        valence_flips = work.reduce_valence(max_valence, min_angle)
    sliver_flips = work.flip_slivers(min_angle, max_valence)
    after = work.stats(min_angle)
    report = CleanupReport(
        boundary_triangles_before=before[0],
        boundary_triangles_after=after[0],
        boundary_flips=flips,
        boundary_splits=splits,
        max_valence_before=before[1],
        max_valence_after=after[1],
        valence_flips=valence_flips,
        slivers_before=before[2],
        slivers_after=after[2],
        sliver_flips=sliver_flips,
        min_angle_before=before[3],
        min_angle_after=after[3],
    )
    return work.result(), report


def _local_plane(mesh: Mesh) -> Transformer | None:
    """Return the map to a conformal plane (angles there are angles on the Earth).

    None for a projected (or planar) mesh: its own plane is used.
    """
    if mesh.crs is None or mesh.crs.is_projected:
        return None
    lon, lat = np.median(mesh.points, axis=0)
    plane = CRS.from_proj4(
        f"+proj=sterea +lat_0={lat} +lon_0={lon} +k=1 +datum=WGS84 +units=m"
    )
    return transformer(mesh.crs, plane)


def _angles(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the three angles (degrees) of triangles as (k, 3, 2) coordinates."""
    a = np.linalg.norm(xy[:, 1] - xy[:, 2], axis=1)
    b = np.linalg.norm(xy[:, 2] - xy[:, 0], axis=1)
    c = np.linalg.norm(xy[:, 0] - xy[:, 1], axis=1)

    def angle(opposite, s1, s2):
        cos = (s1**2 + s2**2 - opposite**2) / np.maximum(2 * s1 * s2, 1e-300)
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))

    return np.column_stack([angle(a, b, c), angle(b, c, a), angle(c, a, b)])


class _Work:
    """The mesh being edited: triangles, edge map, boundary nodes, valences."""

    def __init__(self, mesh: Mesh) -> None:
        self.mesh = mesh
        self.to_plane = _local_plane(mesh)
        self.xy = (
            mesh.points.copy()
            if self.to_plane is None
            else np.column_stack(self.to_plane.transform(*mesh.points.T))
        )
        self.extra_xy: list[NDArray[np.float64]] = []
        self.extra_from: list[tuple[int, int, int]] = []
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

    # geometry

    def point(self, node: int) -> NDArray[np.float64]:
        n = len(self.xy)
        return self.xy[node] if node < n else self.extra_xy[node - n]

    def min_angle(self, t: list[int]) -> float:
        xy = np.array([[self.point(v) for v in t]])
        return float(_angles(xy).min())

    def area(self, t: list[int]) -> float:
        (x0, y0), (x1, y1), (x2, y2) = (self.point(v) for v in t)
        return 0.5 * ((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0))

    def all_boundary(self, t: list[int]) -> bool:
        return all(self.is_boundary_node(v) for v in t)

    def is_boundary_node(self, v: int) -> bool:
        return v < len(self.on_boundary) and bool(self.on_boundary[v])

    # edits

    def _flipped(
        self, k1: int, u: int, v: int
    ) -> tuple[int, list[int], list[int]] | None:
        """Return the flip of edge (u, v) of triangle k1: (k2, new t1, new t2)."""
        key = (min(u, v), max(u, v))
        pair = self.edges.get(key, [])
        if len(pair) != 2:
            return None  # a boundary edge
        k2 = pair[0] if pair[1] == k1 else pair[1]
        t1, t2 = self.tri[k1], self.tri[k2]
        i = t1.index(u)
        if t1[(i + 1) % 3] != v:
            u, v = v, u
            i = t1.index(u)
        a = t1[(i + 2) % 3]
        b = next(w for w in t2 if w not in (u, v))
        new1, new2 = [u, b, a], [b, v, a]
        if self.area(new1) <= 0 or self.area(new2) <= 0:
            return None  # the quadrilateral is not convex
        return k2, new1, new2

    def _apply(self, k1: int, k2: int, new1: list[int], new2: list[int]) -> None:
        for k in (k1, k2):
            t = self.tri[k]
            self._unlink(k, t)
            np.subtract.at(self.valence, [w for w in t if w < len(self.valence)], 1)
        for k, t in ((k1, new1), (k2, new2)):
            self.tri[k] = t
            self._link(k, t)
            np.add.at(self.valence, [w for w in t if w < len(self.valence)], 1)

    def _split(self, k: int) -> None:
        t = self.tri[k]
        node = len(self.xy) + len(self.extra_xy)
        self.extra_xy.append(np.mean([self.point(v) for v in t], axis=0))
        self.extra_from.append(tuple(t))
        self._unlink(k, t)
        pieces = [[t[0], t[1], node], [t[1], t[2], node], [t[2], t[0], node]]
        self.tri[k] = pieces[0]
        self.tri.extend(pieces[1:])
        indices = (k, len(self.tri) - 2, len(self.tri) - 1)
        for index, piece in zip(indices, pieces, strict=True):
            self._link(index, piece)
        np.add.at(self.valence, [w for w in t if w < len(self.valence)], 1)

    # passes

    def fix_boundary_triangles(self, floor: float) -> tuple[int, int]:
        flips = splits = 0
        # candidates found at once with numpy; the loop visits only those
        candidates = np.flatnonzero(self.on_boundary[self.mesh.triangles].all(axis=1))
        for k in candidates:
            t = self.tri[k]
            if not self.all_boundary(t):
                continue
            best = None
            for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                flipped = self._flipped(k, u, v)
                if flipped is None:
                    continue
                k2, new1, new2 = flipped
                if self.all_boundary(new1) or self.all_boundary(new2):
                    continue
                quality = min(self.min_angle(new1), self.min_angle(new2))
                if best is None or quality > best[0]:
                    best = (quality, k2, new1, new2)
            centre = np.mean([self.point(v) for v in t], axis=0)
            corners = [self.point(v) for v in t]
            pieces = np.array(
                [[corners[i], corners[(i + 1) % 3], centre] for i in range(3)]
            )
            split_quality = float(_angles(pieces).min())
            if best is not None and best[0] >= max(split_quality, floor):
                self._apply(k, best[1], best[2], best[3])
                flips += 1
            elif split_quality >= floor:
                self._split(k)
                splits += 1
        return flips, splits

    def reduce_valence(self, limit: int, min_angle: float) -> int:
        flips = 0
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
                    if len(pair) != 2:
                        continue
                    u, v = key
                    flipped = self._flipped(pair[0], u, v)
                    if flipped is None:
                        continue
                    k2, new1, new2 = flipped
                    gain = [w for w in set(new1) & set(new2) if w not in (u, v)]
                    if any(
                        w < len(self.valence) and self.valence[w] + 1 > limit
                        for w in gain
                    ):
                        continue
                    old = min(
                        self.min_angle(self.tri[pair[0]]), self.min_angle(self.tri[k2])
                    )
                    new = min(self.min_angle(new1), self.min_angle(new2))
                    if (
                        new < min(old, min_angle)
                        or self.all_boundary(new1)
                        or self.all_boundary(new2)
                    ):
                        continue
                    self._apply(pair[0], k2, new1, new2)
                    flips += 1
        return flips

    def flip_slivers(self, min_angle: float, limit: int | None) -> int:
        flips = 0
        tri = np.array(self.tri)
        xy = np.concatenate([self.xy, np.array(self.extra_xy).reshape(-1, 2)])
        candidates = np.flatnonzero(_angles(xy[tri]).min(axis=1) < min_angle)
        for k in candidates:
            t = self.tri[k]
            angles = _angles(np.array([[self.point(v) for v in t]]))[0]
            if angles.min() >= min_angle:
                continue
            widest = int(np.argmax(angles))
            u, v = t[(widest + 1) % 3], t[(widest + 2) % 3]  # the opposite edge
            flipped = self._flipped(k, u, v)
            if flipped is None:
                continue
            k2, new1, new2 = flipped
            old = min(angles.min(), self.min_angle(self.tri[k2]))
            new = min(self.min_angle(new1), self.min_angle(new2))
            gain = [w for w in set(new1) & set(new2) if w not in (u, v)]
            if limit is not None and any(
                w < len(self.valence)
                and not self.on_boundary[w]
                and self.valence[w] + 1 > limit
                for w in gain
            ):
                continue
            if new > old and not (self.all_boundary(new1) or self.all_boundary(new2)):
                self._apply(k, k2, new1, new2)
                flips += 1
        return flips

    # results

    def stats(self, min_angle: float) -> tuple[int, int, int, float]:
        tri = np.array(self.tri)
        xy = np.concatenate([self.xy, np.array(self.extra_xy).reshape(-1, 2)])
        angles = _angles(xy[tri]).min(axis=1)
        boundary = np.concatenate(
            [self.on_boundary, np.zeros(len(self.extra_xy), dtype=bool)]
        )
        interior = ~boundary
        valence = np.bincount(tri.ravel(), minlength=len(xy))
        return (
            int(boundary[tri].all(axis=1).sum()),
            int(valence[interior].max(initial=0)),
            int((angles < min_angle).sum()),
            float(angles.min()),
        )

    def result(self) -> Mesh:
        mesh = self.mesh
        points = mesh.points
        point_data = dict(mesh.point_data)
        if self.extra_from:
            sources = np.array(self.extra_from)
            # the triangles' centroids in the plane, back in the mesh's CRS
            centres = np.array(self.extra_xy)
            if self.to_plane is not None:
                centres = np.column_stack(
                    self.to_plane.transform(*centres.T, direction="INVERSE")
                )
            points = np.vstack([points, centres])
            for name, values in point_data.items():
                point_data[name] = np.concatenate(
                    [values, np.asarray(values)[sources].mean(axis=1)]
                )
        return Mesh(
            points,
            np.array(self.tri, dtype=np.int64),
            mesh.boundary_edges,
            mesh.boundary_ids,
            mesh.surface_id,
            mesh.crs,
            point_data,
            mesh.boundary_names,
            mesh.boundary_kinds,
        )
