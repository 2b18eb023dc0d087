"""Dead-end channels one element wide, peeled back until they are two wide.

A triangle whose three nodes all lie on the boundary, with at most one
boundary side, spans a channel one element wide: an ocean model has a single
velocity across it, and the channel neither flows nor drains right. Where such
a channel ends (a dock, the head of a narrow inlet, the wedge where an open
boundary meets the coast at a sharp angle), its last triangle is an *ear*: two
boundary sides. :func:`peel_channels` removes ears whose one inner neighbour
also has all its nodes on the boundary, again and again, so a dead-end strip
one element wide is taken back, from its end, to where the water is two
elements wide. That closes the channel as land, as ``narrow = "close"`` does
before meshing for the channels the size grid can see.

The new boundary side (the ear's inner side) takes the id of the sides it
replaces: an open boundary's if one of them is open (the open boundary is cut
back along the strip), else the shoreline's. Ears whose two boundary sides are
both open, and triangles of ``keep`` (a site's), are left. A strait one
element wide has no end to peel from: its run of all-boundary triangles is
taken out whole where it meets the rest of the mesh through one or two inner
sides (which become coast, or open boundary for a strip along one). Where that
would leave a node with more than two boundary sides (a pinch: one triangle
from a point of one coast to the other, water on both sides of the point),
the smaller fan of triangles around the node goes too. Water cut off from the
largest piece by that goes too, unless it has an open boundary of its own:
then the strait is left. The passes run again while they change something.

No maintained library edits a mesh's boundary this way; the loop is written
here, over plain Python dicts, and touches only the all-boundary triangles.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from coastmesh.types import Mesh, Report

__all__ = ["PeelReport", "peel_channels"]

#: A side of a triangle: its two nodes, the lower first (:func:`_edge`).
_Side = tuple[int, int]
#: The all-boundary triangles of a pass: each one's nodes.
_Alive = dict[int, tuple[int, ...]]


@dataclass(frozen=True, slots=True)
class PeelReport(Report):
    """What :func:`peel_channels` did.

    Attributes
    ----------
    removed : int
        Triangles taken out (dead-end strips one element wide).
    nodes_removed : int
        Nodes left without a triangle, taken out too.
    strips : int
        Dead-end strips peeled.
    left : int
        Triangles still spanning a channel one element wide (in sites, or
        where closing would pinch the boundary).
    straits : int
        Straits one element wide closed whole (their mouths made coast).
    cut_off : int
        Triangles of water the closing cut off from the largest piece (a
        lagoon behind a closed strait), taken out too.
    unpinched : int
        Straits whose closing would have pinched the boundary at a node (the
        water on both sides touching there), closed with the smaller fan of
        triangles around that node.
    """

    removed: int
    nodes_removed: int
    strips: int
    left: int
    straits: int = 0
    cut_off: int = 0
    unpinched: int = 0

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.removed:,} triangles of {self.strips:,} dead-end channels and "
            f"{self.straits:,} straits one element wide closed ({self.unpinched:,} "
            f"at a pinch; {self.cut_off:,} "
            f"cut off behind them; {self.nodes_removed:,} nodes); {self.left:,} "
            "spanning triangles left"
        )


def _edge(a: int, b: int) -> tuple[int, int]:
    return (a, b) if a < b else (b, a)


def peel_channels(
    mesh: Mesh, keep: NDArray[np.bool_] | None = None
) -> tuple[Mesh, PeelReport]:
    """Close the dead-end channels one element wide by peeling their ears.

    Parameters
    ----------
    mesh : Mesh
        The mesh, with ``boundary_kinds`` (``"open"`` or ``"shoreline"`` per
        id; without them every boundary is shoreline).
    keep : ndarray of bool, shape (M,), optional
        Triangles never removed (inside ``[[sites]]``).

    Returns
    -------
    mesh : Mesh
        Without the peeled triangles and the nodes they alone held.
    report : PeelReport

    Examples
    --------
    A square with a node inside, and a strip one element wide (three
    triangles) running east from it: the strip is peeled from its end until
    its last triangle, which now has two boundary sides (a corner, not a
    channel) and a neighbour with a node inside.

    >>> pts = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5],
    ...        [2, 0], [2, 1], [3, 0], [3, 1]]
    >>> tri = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4],
    ...        [1, 5, 2], [5, 6, 2], [5, 7, 6], [7, 8, 6]]
    >>> ring = [[0, 1], [1, 5], [5, 7], [7, 8], [8, 6], [6, 2], [2, 3], [3, 0]]
    >>> m = Mesh(pts, tri, ring, [1] * 8, 1, None)
    >>> peeled, report = peel_channels(m)
    >>> len(peeled.triangles), report.removed, report.nodes_removed, report.left
    (5, 3, 3, 0)
    """
    report = PeelReport(0, 0, 0, 0)
    for _ in range(MAX_PASSES):
        mesh, keep, found = _peel_once(mesh, keep)
        report = _added(report, found)
        if not found.removed:
            return mesh, report
    # the last pass took something out: what it left may hold new strips
    return mesh, _added(report, PeelReport(0, 0, 0, _left(mesh)))


#: Passes of peeling: a pinch closed with its fan can leave a new strip.
MAX_PASSES = 3


def _added(a: PeelReport, b: PeelReport) -> PeelReport:
    """Return the reports of two passes summed (``left``: the last pass's)."""
    return PeelReport(
        removed=a.removed + b.removed,
        nodes_removed=a.nodes_removed + b.nodes_removed,
        strips=a.strips + b.strips,
        left=b.left,
        straits=a.straits + b.straits,
        cut_off=a.cut_off + b.cut_off,
        unpinched=a.unpinched + b.unpinched,
    )


def _peel_once(
    mesh: Mesh, keep: NDArray[np.bool_] | None, blocked: frozenset[int] = frozenset()
) -> tuple[Mesh, NDArray[np.bool_] | None, PeelReport]:
    """One pass of :func:`peel_channels`; returns ``keep`` for the new mesh.

    A strait whose closing would cut off water with an open boundary of its
    own (forced water, not a lagoon) is left: the pass is done again with its
    triangles in ``blocked``.
    """
    tris = mesh.triangles
    n = len(mesh.points)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[mesh.boundary_edges.ravel()] = True
    candidates = np.flatnonzero(on_boundary[tris].all(axis=1))
    if candidates.size == 0:
        return mesh, keep, PeelReport(0, 0, 0, 0)
    kinds = mesh.boundary_kinds
    side_id = {
        _edge(int(a), int(b)): int(i)
        for (a, b), i in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True)
    }
    # the all-boundary triangles and, for their sides, the triangles on each
    alive = {int(t): tuple(int(v) for v in tris[t]) for t in candidates}
    kept = set(np.flatnonzero(keep).tolist()) if keep is not None else set()
    alive_ids = [t for t in alive if t not in kept]
    near = np.isin(tris, np.unique(tris[candidates])).any(axis=1)
    by_side: dict[tuple[int, int], list[int]] = {}
    for t in np.flatnonzero(near).tolist():
        for side in _sides(tuple(int(v) for v in tris[t])):
            by_side.setdefault(side, []).append(t)
    removed: set[int] = set()

    def open_(side: tuple[int, int]) -> bool:
        return kinds.get(side_id.get(side, -1)) == "open"

    def ear(t: int) -> tuple[tuple[int, int], list[tuple[int, int]]] | None:
        """Return the inner side and the boundary sides of an ear, else None."""
        sides = _sides(alive[t])
        outer = [s for s in sides if s in side_id]
        inner = [s for s in sides if s not in side_id]
        if len(outer) != 2 or len(inner) != 1:
            return None
        if all(open_(s) for s in outer):
            return None
        return inner[0], outer

    _peel_ears(alive_ids, alive, kept, removed, side_id, by_side, ear, open_)
    strips = _strips(alive, removed) if removed else 0
    found = _Straits(tris, alive, kept | blocked, removed, side_id, by_side, open_)
    straits, unpinched = found.close()
    if not removed:
        return mesh, keep, PeelReport(0, 0, 0, _spanning(alive, side_id, set()))
    cut_off, forced = _cut_off(mesh, removed)
    if forced:
        nodes = set(tris[sorted(forced)].ravel().tolist())
        more = {
            t
            for run, group in found.closed
            for t in run
            if nodes & set(tris[sorted(group)].ravel().tolist())
        }
        if more - blocked:
            return _peel_once(mesh, keep, blocked | more)
        cut_off -= forced  # (not reached unless a peeled ear cut it off)
    removed |= cut_off
    left = _spanning(alive, side_id, removed)
    report = PeelReport(0, 0, strips, left, straits, len(cut_off), unpinched)
    return _without(mesh, keep, removed, side_id, report)


def _peel_ears(
    queue: Iterable[int],
    alive: _Alive,
    kept: set[int],
    removed: set[int],
    side_id: dict[_Side, int],
    by_side: dict[_Side, list[int]],
    ear: Callable[[int], tuple[_Side, list[_Side]] | None],
    open_: Callable[[_Side], bool],
) -> None:
    """Remove ears whose inner neighbour is all-boundary, until none is left."""
    queue = list(queue)
    while queue:
        t = queue.pop()
        if t in removed or t in kept:
            continue
        found = ear(t)
        if found is None:
            continue
        inner, outer = found
        others = [u for u in by_side[inner] if u != t and u not in removed]
        if len(others) != 1 or others[0] not in alive or others[0] in kept:
            continue  # the neighbour has a node inside: the water is wider
        removed.add(t)
        opened = [s for s in outer if open_(s)]
        side_id[inner] = side_id[opened[0]] if opened else side_id[outer[0]]
        for s in outer:
            del side_id[s]
        queue.append(others[0])


class _Straits:
    """The straits one element wide of one pass, and their closing.

    A run (all-boundary triangles joined by inner sides) that spans a channel
    and meets the rest of the mesh through one or two inner sides (its mouths)
    is taken out whole; its mouths take the run's commonest id (of its open
    sides, if any: a strip along an open boundary cuts it back). Where that
    would leave a node with more than two boundary sides (the water on both
    sides of the run touching at one node: the boundary must stay a set of
    rings), the smaller fan of triangles around that node goes too, for at
    most :data:`MAX_FANS` nodes a run.
    """

    def __init__(
        self,
        tris: NDArray[np.int64],
        alive: _Alive,
        kept: set[int],
        removed: set[int],
        side_id: dict[_Side, int],
        by_side: dict[_Side, list[int]],
        open_: Callable[[_Side], bool],
    ) -> None:
        self.tris, self.alive, self.kept = tris, alive, kept
        self.removed, self.side_id, self.by_side = removed, side_id, by_side
        self.open_ = open_
        #: (run, triangles taken out) of each strait closed
        self.closed: list[tuple[set[int], set[int]]] = []
        #: the triangles at each node (CSR: order, starts) and each node's
        #: boundary sides, made on the first strait: a strait's closing then
        #: touches only the triangles round it, not the whole mesh
        self._at: tuple[NDArray[np.int64], NDArray[np.int64]] | None = None
        self._degree: dict[int, int] = {}

    def close(self) -> tuple[int, int]:
        """Close what can be; return the runs closed and those at a pinch."""
        alive, side_id = self.alive, self.side_id
        rest = {t for t in alive if t not in self.removed and t not in self.kept}
        spanning = {t for t in rest if sum(s in side_id for s in _sides(alive[t])) <= 1}
        seen: set[int] = set()
        closed = unpinched = 0
        for start in sorted(spanning):
            if start in seen:
                continue
            run = _run(start, alive, rest, side_id, self.by_side)
            seen |= run
            outer = [s for t in run for s in _sides(alive[t]) if s in side_id]
            mouths = [
                s
                for t in run
                for s in _sides(alive[t])
                if s not in side_id
                and any(
                    u not in run and u not in self.removed
                    for u in self.by_side.get(s, ())
                )
            ]
            if not 1 <= len(mouths) <= 2:
                continue
            # a strip along an open boundary: the open boundary is cut back
            like = [side_id[s] for s in ([s for s in outer if self.open_(s)] or outer)]
            grown = self._closed(run, max(set(like), key=like.count))
            if grown is None:
                continue
            group, (gone, added) = grown
            for side in gone:
                del side_id[side]
            side_id.update(added)
            for side, step in [(g, -1) for g in gone] + [(a, 1) for a in added]:
                for v in side:
                    self._degree[v] = self._degree.get(v, 0) + step
            self.removed |= group
            self.closed.append((run, group))
            closed += 1
            unpinched += len(group) > len(run)
        return closed, unpinched

    def _closed(
        self, run: set[int], like: int
    ) -> tuple[set[int], tuple[set[_Side], dict[_Side, int]]] | None:
        """Return the triangles to take out for ``run`` and the change of sides.

        The change is (the boundary sides that go, the new ones with their id).
        None if the boundary cannot be kept a set of rings, or a fan it would
        need holds a site's triangle.
        """
        group = set(run)
        for _ in range(MAX_FANS + 1):
            gone, added, around = self._side_ids(group, like)
            pinched = self._pinched(
                gone, added, {v for t in group for v in self._tri(t)}
            )
            if not pinched:
                return group, (gone, added)
            fan = self._smaller_fan(pinched[0], group, gone, added, around)
            if fan is None:
                return None
            group |= fan
        return None

    def _tri(self, t: int) -> tuple[int, int, int]:
        a, b, c = (int(v) for v in self.tris[t])
        return a, b, c

    def _index(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Return the triangles at each node; on the first call, make them.

        And the boundary degree of every node, from the sides as they are
        then (before any strait is closed; :meth:`close` keeps it in step).
        """
        if self._at is None:
            flat = self.tris.ravel()
            order = np.argsort(flat, kind="stable")
            starts = np.searchsorted(flat[order], np.arange(int(flat.max()) + 2))
            self._at = (order // 3, starts)
            for side in self.side_id:
                for v in side:
                    self._degree[v] = self._degree.get(v, 0) + 1
        return self._at

    def _near(self, nodes: NDArray[np.int64]) -> NDArray[np.int64]:
        """Return the triangles with a node in ``nodes`` (sorted, unique)."""
        order, starts = self._index()
        lo, hi = starts[nodes], starts[nodes + 1]
        at = np.repeat(lo - np.cumsum(np.r_[0, (hi - lo)[:-1]]), hi - lo)
        return np.unique(order[np.arange(at.size) + at])

    def _side_ids(
        self, group: set[int], like: int
    ) -> tuple[set[_Side], dict[_Side, int], dict[_Side, list[int]]]:
        """Return how the boundary sides change once ``group`` is out.

        Returns the boundary sides that go, the new ones with their id, and
        the sides near the group with their triangles. A side of the group's
        that was boundary goes; one with water on its other side becomes
        boundary with the id ``like``.
        """
        nodes = np.unique(self.tris[sorted(group)])
        around: dict[tuple[int, int], list[int]] = {}
        for t in self._near(nodes).tolist():
            if t in self.removed:
                continue
            for side in _sides(self._tri(t)):
                around.setdefault(side, []).append(t)
        gone: set[tuple[int, int]] = set()
        added: dict[tuple[int, int], int] = {}
        for t in group:
            for side in _sides(self._tri(t)):
                if side in self.side_id:
                    gone.add(side)
                elif any(u not in group for u in around[side]):
                    added[side] = like
        return gone, added, around

    def _pinched(
        self, gone: set[_Side], added: dict[_Side, int], nodes: set[int]
    ) -> list[int]:
        """Return the ``nodes`` with boundary sides other than none or two.

        Those are pinches, once the sides ``gone`` go and those ``added`` come.
        """
        degree = {v: self._degree.get(v, 0) for v in nodes}
        for sides, step in ((gone, -1), (added, 1)):
            for side in sides:
                for v in side:
                    if v in degree:
                        degree[v] += step
        return sorted(v for v, d in degree.items() if d not in (0, 2))

    def _smaller_fan(
        self,
        node: int,
        group: set[int],
        gone: set[_Side],
        added: dict[_Side, int],
        around: dict[_Side, list[int]],
    ) -> set[int] | None:
        """Return the smaller fan of water around ``node`` (fans part at the boundary).

        None if it holds a triangle of a site.
        """

        def boundary(side: tuple[int, int]) -> bool:
            return side in added or (side in self.side_id and side not in gone)

        fans: list[set[int]] = []
        left = {u for s, ts in around.items() if node in s for u in ts} - group
        while left:
            fan, stack = set(), [left.pop()]
            while stack:
                t = stack.pop()
                fan.add(t)
                for side in _sides(self._tri(t)):
                    if node in side and not boundary(side):
                        for u in around[side]:
                            if u in left:
                                left.discard(u)
                                stack.append(u)
            fans.append(fan)
        fans.sort(key=len)
        if len(fans) < 2 or fans[0] & self.kept:
            return None
        return fans[0]


#: Pinched nodes a run may free by taking out a fan of triangles.
MAX_FANS = 2


def _run(
    start: int,
    alive: _Alive,
    rest: set[int],
    side_id: dict[_Side, int],
    by_side: dict[_Side, list[int]],
) -> set[int]:
    """Return the all-boundary triangles joined to ``start`` by inner sides."""
    run, stack = {start}, [start]
    while stack:
        t = stack.pop()
        for side in _sides(alive[t]):
            if side in side_id:
                continue
            for u in by_side.get(side, ()):
                if u in rest and u not in run:
                    run.add(u)
                    stack.append(u)
    return run


def _sides(tri: tuple[int, ...]) -> tuple[tuple[int, int], ...]:
    a, b, c = tri
    return (_edge(a, b), _edge(b, c), _edge(c, a))


#: Open boundary sides that make water cut off by a closing a sea of its own.
FORCED_SIDES = 10


def _cut_off(mesh: Mesh, removed: set[int]) -> tuple[set[int], set[int]]:
    """Return the triangles no longer joined to the largest piece of water.

    And, of those, the ones in pieces with an open boundary of their own (at
    least :data:`FORCED_SIDES` sides of it: fewer are a corner of an open
    boundary trimmed at the coast, not a sea).
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    alive = np.ones(len(mesh.triangles), dtype=bool)
    alive[list(removed)] = False
    index = np.flatnonzero(alive)
    tris = mesh.triangles[index]
    m, n = len(tris), len(mesh.points)
    # the sides, triangle by triangle for each of the three (side k of
    # triangle t at k * m + t), as keys; a side two triangles share joins them
    after = np.roll(tris, -1, axis=1)
    key = (np.minimum(tris, after) * n + np.maximum(tris, after)).T.ravel()
    del after
    order = np.argsort(key)
    at = np.flatnonzero(key[order][1:] == key[order][:-1])
    a, b = order[at] % m, order[at + 1] % m
    del order, at
    graph = csr_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(m, m))
    count, labels = connected_components(graph, directed=False)
    if count <= 1:
        return set(), set()
    largest = np.bincount(labels).argmax()
    cut = labels != largest
    kinds = mesh.boundary_kinds
    opened = np.isin(mesh.boundary_ids, [i for i, k in kinds.items() if k == "open"])
    edges = np.sort(mesh.boundary_edges[opened], axis=1)
    # the open sides of each piece cut off (the largest's are not needed)
    sides = np.flatnonzero(np.tile(cut, 3))
    open_ = np.isin(key[sides], edges[:, 0] * n + edges[:, 1])
    open_sides = np.bincount(labels[sides[open_] % m], minlength=count)
    forced_pieces = np.flatnonzero(open_sides >= FORCED_SIDES)
    forced = cut & np.isin(labels, forced_pieces)
    return set(index[cut].tolist()), set(index[forced].tolist())


def _strips(alive: _Alive, removed: set[int]) -> int:
    """Count the strips peeled: the removed triangles joined by a side."""
    parent = {t: t for t in removed}

    def root(t: int) -> int:
        while parent[t] != t:
            parent[t] = parent[parent[t]]
            t = parent[t]
        return t

    owner: dict[tuple[int, int], int] = {}
    for t in removed:
        a, b, c = alive[t]
        for side in (_edge(a, b), _edge(b, c), _edge(c, a)):
            if side in owner:
                parent[root(t)] = root(owner[side])
            else:
                owner[side] = t
    return len({root(t) for t in removed})


def _left(mesh: Mesh) -> int:
    """Count the triangles of ``mesh`` that span a channel.

    Those with all their nodes on the boundary and at most one boundary side.
    """
    n = len(mesh.points)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[mesh.boundary_edges.ravel()] = True
    tris = mesh.triangles[on_boundary[mesh.triangles].all(axis=1)]
    edges = np.sort(mesh.boundary_edges, axis=1)
    keys = edges[:, 0] * n + edges[:, 1]
    sides = np.zeros(len(tris), dtype=np.int64)
    for k in range(3):
        i, j = tris[:, k], tris[:, (k + 1) % 3]
        sides += np.isin(np.minimum(i, j) * n + np.maximum(i, j), keys)
    return int((sides <= 1).sum())


def _spanning(alive: _Alive, side_id: dict[_Side, int], removed: set[int]) -> int:
    """Count the all-boundary triangles with at most one boundary side."""
    count = 0
    for t, (a, b, c) in alive.items():
        if t in removed:
            continue
        sides = (_edge(a, b), _edge(b, c), _edge(c, a))
        if sum(s in side_id for s in sides) <= 1:
            count += 1
    return count


def _without(
    mesh: Mesh,
    sites: NDArray[np.bool_] | None,
    removed: set[int],
    side_id: dict[_Side, int],
    report: PeelReport,
) -> tuple[Mesh, NDArray[np.bool_] | None, PeelReport]:
    """Return the mesh without the ``removed`` triangles; boundary from ``side_id``.

    With ``sites`` (a flag per triangle), the flags of the triangles left.
    """
    keep = np.ones(len(mesh.triangles), dtype=bool)
    keep[list(removed)] = False
    tris = mesh.triangles[keep]
    used = np.zeros(len(mesh.points), dtype=bool)
    used[tris.ravel()] = True
    new_index = np.cumsum(used) - 1
    # each boundary side oriented as in its triangle (as the mesh has them); a
    # side of water cut off has no triangle left and goes with it
    n = len(mesh.points)
    sides = np.array(list(side_id), dtype=np.int64).reshape(-1, 2)
    sids = np.fromiter(side_id.values(), dtype=np.int64, count=len(side_id))
    key = sides[:, 0] * n + sides[:, 1]
    rank = np.argsort(key)
    on = np.zeros(n, dtype=bool)
    on[sides.ravel()] = True
    directed = np.concatenate(  # the triangles' sides with both nodes on one
        [
            tris[on[tris[:, k]] & on[tris[:, (k + 1) % 3]]][:, [k, (k + 1) % 3]]
            for k in range(3)
        ]
    )
    wanted = directed.min(axis=1) * n + directed.max(axis=1)
    at = np.minimum(np.searchsorted(key, wanted, sorter=rank), max(len(key) - 1, 0))
    hit = (key[rank[at]] == wanted) if len(key) else np.zeros(len(wanted), bool)
    found = rank[at[hit]]
    edges = np.empty((len(key), 2), dtype=np.int64)
    edges[found] = directed[hit]  # (a side of two triangles: either)
    held = np.zeros(len(key), dtype=bool)
    held[found] = True
    edges, ids = edges[held], sids[held]
    if _flipped(mesh):
        edges = edges[:, ::-1]
    order = np.lexsort(edges.T[::-1])
    edges_arr = new_index[edges[order]]
    point_data = {k: np.asarray(v)[used] for k, v in mesh.point_data.items()}
    peeled = Mesh(
        mesh.points[used],
        new_index[tris],
        edges_arr,
        ids[order],
        mesh.surface_id,
        mesh.crs,
        point_data,
        dict(mesh.boundary_names),
        dict(mesh.boundary_kinds),
        mesh.regions[keep],
        dict(mesh.region_names),
        mesh.lines,
    )
    report = PeelReport(
        removed=len(removed),
        nodes_removed=int((~used).sum()),
        strips=report.strips,
        left=report.left,
        straits=report.straits,
        cut_off=report.cut_off,
        unpinched=report.unpinched,
    )
    return peeled, None if sites is None else sites[keep], report


def _flipped(mesh: Mesh) -> bool:
    """Whether the mesh's boundary sides run against their triangles' order."""
    a, b = (int(v) for v in mesh.boundary_edges[0])
    for t in mesh.triangles[(mesh.triangles == a).any(axis=1)].tolist():
        for u, v in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if (u, v) == (a, b):
                return False
            if (u, v) == (b, a):
                return True
    return False


#: The fewest edges of a run of coast between two open boundaries (Telemac
#: turns a shorter run open, or stops: BIEF front2.f).
MIN_RUN_EDGES = 3


def open_short_runs(mesh: Mesh, min_edges: int = MIN_RUN_EDGES) -> tuple[Mesh, int]:
    """Make runs of coast too short between two open boundaries open boundary.

    A run (consecutive boundary edges of one shoreline id) with open boundaries
    at both ends and fewer than ``min_edges`` edges (a spit of coast one or two
    elements long where two open boundaries were trimmed) takes the id of the
    open boundary at one of its ends, as Telemac would make it open: every
    format then has the same boundaries, and no element is made smaller.
    Returns the mesh and the number of edges relabelled.

    Examples
    --------
    A unit square, its south side coast between open boundaries, one edge:

    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [1, 2, 2, 2], 1, None,
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> out, relabelled = open_short_runs(m)
    >>> relabelled, out.boundary_ids.tolist()
    (1, [2, 2, 2, 2])
    """
    kinds = mesh.boundary_kinds
    if not any(k == "open" for k in kinds.values()):
        return mesh, 0
    edges = [tuple(e) for e in mesh.boundary_edges.tolist()]
    ids = mesh.boundary_ids.tolist()
    runs = _short_runs(edges, ids, kinds, min_edges)
    if not runs:
        return mesh, 0
    new = np.asarray(ids).copy()
    for run, ends in runs:
        new[run] = ends[0]
    out = Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        new,
        mesh.surface_id,
        mesh.crs,
        dict(mesh.point_data),
        dict(mesh.boundary_names),
        dict(kinds),
        mesh.regions,
        dict(mesh.region_names),
        mesh.lines,
    )
    return out, sum(len(run) for run, _ in runs)


def _short_runs(
    edges: list[tuple[int, ...]], ids: list[int], kinds: dict[int, str], min_edges: int
) -> list[tuple[list[int], list[int | None]]]:
    """Return the runs of coast too short between open ends: (edges, end ids)."""
    at: dict[int, list[int]] = {}
    for k, (u, v) in enumerate(edges):
        at.setdefault(u, []).append(k)
        at.setdefault(v, []).append(k)
    seen: set[int] = set()
    runs = []
    for start, sid in enumerate(ids):
        if start in seen or kinds.get(sid) != "shoreline":
            continue
        run, stack = {start}, [start]
        ends: list[int | None] = []  # the ids beyond the run's ends (None: none)
        while stack:  # the edges of this id joined end to end
            k = stack.pop()
            for node in edges[k]:
                nxt = [j for j in at[node] if j != k]
                if len(nxt) != 1:
                    ends.append(None)
                    continue
                j = nxt[0]
                if ids[j] == sid:
                    if j not in run:
                        run.add(j)
                        stack.append(j)
                else:
                    ends.append(ids[j])
        seen |= run
        if (
            len(run) < min_edges
            and len(ends) == 2
            and all(e is not None and kinds.get(e) == "open" for e in ends)
        ):
            runs.append((sorted(run), ends))
    return runs
