"""Edge collapses and node moves that lift the few elements capping the time step.

An explicit shallow-water model runs at the smallest element time step ``dt_e =
r_in / (sqrt(g d) + u)`` (:mod:`~coastmesh.meshing.quality.time_step`). Gmsh
makes a few elements 0.6 of the requested size; in deep water they cap the
whole model's time step: the smallest ``dt_e`` over their 1st percentile is 0.4
to 0.55 on the NW European shelf meshes, where 0.6 means that no element
throttles. :func:`relieve_time_step` collapses an edge of each, or moves a
node, in the conformal plane the cleanup works in (angles there are angles on
the Earth).

Each pass takes the triangles below ``ratio`` times the 1st percentile of the
time steps, smallest first, and collapses the shortest of their edges that
passes: into its boundary node, else at the midpoint, with the deeper depth. A
collapse never moves a boundary node; one goes only by a *coast collapse*: a
boundary edge collapsed into its other end, where the node has two boundary
edges and lies within :data:`COAST_TOLERANCE` times the new edge's length of it
(the boundary moves by at most that: 15 m for a 100 m edge). Along a shoreline
the new edge keeps its id; where ids change (a short piece of an open boundary
between two pieces of coast, left where the open boundary was trimmed at a
spit) the piece goes, and the new edge takes the id of the edge beyond, but
never the last edge of an id. A collapse passes if the mesh stays valid (link
condition, positive areas, no new edge between boundary nodes, no node left
bare), no angle falls below both ``min_angle`` and the smallest it replaces,
and the smallest time step around rises. After the collapses of a pass, each
triangle still below ``ratio`` times the 1st percentile has a node moved: of
its nodes, the one whose move lifts the smallest time step of its own triangles
most, while the triangle throttles. A node inside goes where that time step is
largest (a compass search, under the same angle rule, no triangle turned over);
a shoreline node between two edges of one id slides along one of them, once,
where its first place stays within :data:`COAST_TOLERANCE` times the new edges'
length of the new coast (open boundaries never move). If a triangle is still
under :data:`~coastmesh.meshing.quality.time_step.MIN_OVER_P1_TARGET` (0.6)
times the 1st percentile after the passes, a second round of passes runs for
those alone, in which each coast node may slide or go once more, within the
same tolerance of where the round found it (on ``world_fine.toml`` the tip of
a spike of Christmas Island's coast, under the local size, where Gmsh's spline
puts two nodes 0.4 of a size apart, needed two slides: 0.53 -> 0.61). The
result is kept only if, on the Earth, the smallest time step over its 1st
percentile rose and neither the minimum angle nor its 1st percentile fell
(below ``keep_angles``, when given: a case gives Gmsh's own mesh's, as the
cleanup does). The steps
are first allowed :data:`ANGLE_SLACK` degrees under that bar on the way (a
collapse in a notch of the coast leaves an angle that the next move lifts
again); if that result falls under the bar, the passes are run again with every
step at the bar.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pyproj import Transformer
from scipy import sparse

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import is_world_plane, local_plane, plane_scale
from coastmesh.meshing.cleanup import smoothing
from coastmesh.meshing.cleanup.aside import done_now
from coastmesh.meshing.cleanup.planar import signed_areas, triangle_angles
from coastmesh.meshing.quality.time_step import (
    MIN_OVER_P1_TARGET,
    element_time_steps,
    node_depth,
)
from coastmesh.sizing.courant import wave_speed
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import region_interfaces

__all__ = [
    "ANGLE_SLACK",
    "COAST_TOLERANCE",
    "THROTTLE_RATIO",
    "ThrottleReport",
    "relieve_time_step",
]

logger = logging.getLogger(__name__)
#: Goal: no element's time step below this fraction of the 1st percentile of
#: them (the target :data:`~coastmesh.meshing.quality.time_step.MIN_OVER_P1_TARGET` is
#: 0.6: a margin for the re-sampled depth).
THROTTLE_RATIO = 0.65
#: A coast collapse removes a shoreline node only if it lies within this share
#: of the new boundary edge's length of it: the coast's shape changes by less.
COAST_TOLERANCE = 0.15
#: How far under the angle bar (degrees) a single step may go on the way, first
#: with the slack, then without: a collapse can leave an angle that the next
#: move of its neighbour lifts again (on the Sognefjord example min / p1 0.57
#: at the bar, 0.65 with 2 deg, the result's minimum angle unchanged). A result
#: under the bar is never kept.
ANGLE_SLACK = (2.0, 0.0)
#: A run of coast between two open boundaries keeps more edges than this
#: (Telemac turns a shorter one open, or stops).
MIN_RUN = 3


@dataclass(frozen=True, slots=True)
class ThrottleReport(Report):
    """What :func:`relieve_time_step` changed (in the mesh it returned).

    Attributes
    ----------
    throttling_before, throttling_after, collapses : int
        Triangles with a time step below ``ratio`` times the 1st percentile;
        edges collapsed.
    min_over_p1_before, min_over_p1_after : float
        Smallest time step over its 1st percentile, measured on the Earth.
    min_angle_before, min_angle_after, min_angle_p1_before, min_angle_p1_after
        Smallest angle, and 1st percentile of minimum angles, degrees (float).
    accepted : bool
        Whether the mesh returned differs from the input; False when nothing
        throttles, no collapse passes, or their result is rejected.
    coast_collapses : int
        Of the collapses, those that took a boundary node along the boundary.
    moves : int
        Nodes inside the mesh moved (a node of a throttling triangle, where
        the smallest time step of its triangles rose).
    """

    throttling_before: int
    throttling_after: int
    collapses: int
    min_over_p1_before: float
    min_over_p1_after: float
    min_angle_before: float
    min_angle_after: float
    min_angle_p1_before: float
    min_angle_p1_after: float
    accepted: bool
    coast_collapses: int = 0
    moves: int = 0

    def summary(self) -> str:
        """Return a one-line summary.

        Examples
        --------
        >>> print(ThrottleReport(3, 0, 2, 0.45, 0.7, 20, 21, 30, 30, True).summary())
        ... # doctest: +NORMALIZE_WHITESPACE
        time step relieved: min / p1 0.45 -> 0.70 (target >= 0.6), throttling 3 -> 0
        (2 collapses, 0 along the boundary, 0 nodes moved); min angle 20.0 -> 21.0
        deg, 1st percentile 30.0 -> 30.0 deg
        """
        return (
            f"time step {'relieved' if self.accepted else 'unchanged'}: min / p1 "
            f"{self.min_over_p1_before:.2f} -> {self.min_over_p1_after:.2f} "
            f"(target >= {MIN_OVER_P1_TARGET:g}), throttling "
            f"{self.throttling_before} -> {self.throttling_after} "
            f"({self.collapses} collapses, {self.coast_collapses} along the "
            f"boundary, {self.moves} nodes moved); min angle "
            f"{self.min_angle_before:.1f} -> {self.min_angle_after:.1f} deg, 1st "
            f"percentile {self.min_angle_p1_before:.1f} -> "
            f"{self.min_angle_p1_after:.1f} deg"
        )


def relieve_time_step(
    mesh: Mesh,
    *,
    velocity: float = 0.0,
    ratio: float = THROTTLE_RATIO,
    min_angle: float = 30.0,
    passes: int = 3,
    keep_angles: tuple[float, float] | None = None,
    held: NDArray[np.bool_] | None = None,
    threads: int = 1,
    target: float = MIN_OVER_P1_TARGET,
) -> tuple[Mesh, ThrottleReport]:
    """Collapse an edge of each element whose time step is far below the others'.

    Parameters
    ----------
    mesh : Mesh
        With ``point_data["depth"]`` (metres, positive down); triangles
        counter-clockwise.
    velocity : float, default 0
        Velocity scale ``u`` added to the wave speed, m/s (>= 0).
    ratio : float, default :data:`THROTTLE_RATIO`
        Triangles below ``ratio`` times the 1st percentile throttle (0 to 1).
    min_angle : float, default 30
        A collapse may leave a smaller angle (degrees, 0 to 60) only if no
        smaller than the smallest it replaces.
    passes : int, default 3
        Most sweeps over the throttling triangles (>= 1).
    keep_angles : (float, float), optional
        The minimum angle and 1st percentile of minimum angles (degrees) the
        result must keep; default the input's. A case passes Gmsh's own mesh's,
        the bar the cleanup keeps to.
    held : ndarray of bool, shape (N,), optional
        Nodes that neither move nor go (turbines, the outlines of farms and
        footprints): as boundary nodes are, but never along a coast. The
        nodes on the outline between two regions of ``mesh.regions`` are
        held whether given or not.
    threads : int, default 1
        With 2 or more, the mesh is measured on one thread while the
        collapses are prepared on another (numpy lets go of Python's lock);
        the result is the same.
    target : float, default 0.6
        Triangles still below ``min(ratio, target)`` times the 1st percentile
        after the passes get a second round (0 to 1; 0: none). The default is
        :data:`~coastmesh.meshing.quality.time_step.MIN_OVER_P1_TARGET`.

    Returns
    -------
    mesh : Mesh
        The same boundary edges, ids and boundary nodes; fewer nodes and
        triangles. A merged node's point data are the mean of the two nodes'
        (re-sample the depth). The input itself unless ``report.accepted``.
    report : ThrottleReport

    Raises
    ------
    ConfigError
        If ``velocity``, ``ratio``, ``min_angle`` or ``passes`` is out of range.
    ValueError
        If the mesh has no ``"depth"`` point data.

    Notes
    -----
    See the module notes; ``velocity``, ``ratio`` and the depth are as for
    :func:`~coastmesh.meshing.quality.time_step.element_time_steps`.

    Examples
    --------
    >>> from coastmesh.types.topology import unique_edges
    >>> n = 12  # 100 m squares cut in two, 50 m deep; one node moved 75 m east
    >>> pts = np.mgrid[0:n, 0:n].reshape(2, -1).T[:, ::-1] * 100.0
    >>> pts[5 * n + 5, 0] += 75
    >>> q = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)).ravel()
    >>> tri = np.vstack([np.column_stack([q, q + 1, q + n + 1]),
    ...                  np.column_stack([q, q + n + 1, q + n])])
    >>> edges, count = unique_edges(tri, n * n)
    >>> m = Mesh(pts, tri, edges[count == 1], [1] * (4 * n - 4), 1, None,
    ...          {"depth": np.full(n * n, 50.0)})
    >>> relieved, report = relieve_time_step(m)
    >>> report.accepted, report.collapses, len(relieved.triangles) - len(tri)
    (True, 1, -2)
    >>> round(report.min_over_p1_before, 2), round(report.min_over_p1_after, 2)
    (0.33, 0.77)
    """
    _check_options(velocity, ratio, min_angle, passes, target)
    depth = node_depth(mesh)
    if depth is None:
        raise ValueError(
            f"mesh.point_data has no 'depth' (it has {sorted(mesh.point_data)}); "
            "add one with mesh.with_point_data(depth=...)"
        )
    to_plane = local_plane(mesh)
    xy = smoothing.plane_points(mesh.points, to_plane)
    held = _held(mesh, held)
    plane = mesh.crs if to_plane is None else to_plane.target_crs
    radius = EARTH_RADIUS if plane is not None and is_world_plane(plane) else None
    with ThreadPoolExecutor(1) as side:
        aside = side.submit if threads > 1 else done_now
        first = aside(_prepare, mesh, xy, velocity, held, radius)
        before = _measures(mesh, xy, velocity, ratio)  # while _prepare runs aside
        # the bar: the given angles, or the input's where it is already under
        # them (measured here to rounding, it may be by 1e-6 deg)
        own = (before["min_angle"], before["min_angle_p1"])
        keep = tuple(map(min, keep_angles, own)) if keep_angles else own
        # no result may go under the bar; a step may, by the slack, on the way
        bar = max(min_angle, keep[0])
        accepted = False
        for k, slack in enumerate(ANGLE_SLACK):
            work = (
                first.result() if k == 0 else _prepare(mesh, xy, velocity, held, radius)
            )
            collapses, moves = _passes(work, ratio, bar - slack, passes, target)
            if not collapses and not moves:
                break
            new = work.result(mesh, to_plane)
            after = _measures(new, work.xy[~work.removed], velocity, ratio, aside)
            logger.debug("throttle: %d collapses, %s -> %s", collapses, before, after)
            if after["min_over_p1"] > before["min_over_p1"] and (
                after["min_angle"] >= keep[0] and after["min_angle_p1"] >= keep[1]
            ):
                accepted = True
                break
    if not accepted:
        new, after, collapses, moves = mesh, before, 0, 0
    report = ThrottleReport(
        **{f"{name}_before": value for name, value in before.items()},
        **{f"{name}_after": value for name, value in after.items()},
        collapses=collapses,
        accepted=accepted,
        coast_collapses=work.coast_collapses if accepted else 0,
        moves=moves,
    )
    return new, report


def _held(mesh: Mesh, held: NDArray[np.bool_] | None) -> NDArray[np.bool_]:
    """Return ``held`` (or none) with the nodes between two regions added.

    The nodes of the mesh's lines are held too: none of them moves or goes,
    so their edges stay (a collapse keeps every other edge of the node kept).
    """
    out = np.zeros(len(mesh.points), dtype=bool)
    if held is not None:
        out |= np.asarray(held, dtype=bool)
    if len(np.unique(mesh.regions)) > 1:
        out[region_interfaces(mesh).ravel()] = True
    out[mesh.line_edges()[0].ravel()] = True
    return out


def _prepare(
    mesh: Mesh,
    xy: NDArray[np.float64],
    velocity: float,
    held: NDArray[np.bool_],
    radius: float | None = None,
) -> _Collapser:
    """Return a fresh :class:`_Collapser` of ``mesh``, ready for the passes.

    ``radius``: the sphere's, when ``xy`` is a world plane (its lengths are
    the sphere's times the plane's scale).
    """
    fixed = smoothing.boundary_nodes(mesh.triangles, len(xy)) | held
    fixed[mesh.boundary_edges.ravel()] = True
    depth = node_depth(mesh)
    work = _Collapser(xy, mesh.triangles, fixed, depth, velocity, radius)
    work.coast = _coast_links(mesh)
    ids, counts = np.unique(mesh.boundary_ids, return_counts=True)
    work.edges_of = dict(zip(ids.tolist(), counts.tolist(), strict=True))
    work.open_ids = {k for k, kind in mesh.boundary_kinds.items() if kind == "open"}
    return work


def _passes(
    work: _Collapser, ratio: float, floor: float, passes: int, target: float
) -> tuple[int, int]:
    """Run the passes on ``work``; return the collapses and moves made.

    Then, if a triangle is below ``min(ratio, target)`` times the 1st
    percentile, a second round of passes for those.
    """
    collapses, moves = _round(work, ratio, floor, passes)
    last = min(ratio, target)
    if work.throttling(last)[0]:  # a second round, for those under the target
        work.since = work.xy.copy()
        more = _round(work, last, floor, passes)
        collapses, moves = collapses + more[0], moves + more[1]
    return collapses, moves


def _round(
    work: _Collapser, ratio: float, floor: float, passes: int
) -> tuple[int, int]:
    """Run up to ``passes`` passes of collapses, then moves; return how many."""
    collapses = moves = 0
    for _ in range(passes):
        made = work.run_pass(ratio, floor)
        moved = work.move_pass(ratio, floor)
        collapses, moves = collapses + made, moves + moved
        if not made and not moved:
            break
    return collapses, moves


def _coast_links(mesh: Mesh) -> dict[int, dict[int, int]]:
    """Map each boundary node to its neighbours along the boundary and the ids.

    Nodes with other than two boundary edges (pinched) are left out: they
    never go.
    """
    links: dict[int, dict[int, int]] = {}
    for (a, b), sid in zip(
        mesh.boundary_edges.tolist(), mesh.boundary_ids.tolist(), strict=True
    ):
        links.setdefault(a, {})[b] = sid
        links.setdefault(b, {})[a] = sid
    return {n: nb for n, nb in links.items() if len(nb) == 2}


def _check_options(
    velocity: float, ratio: float, min_angle: float, passes: int, target: float
) -> None:
    """Raise ConfigError naming the first option out of range."""
    integer = isinstance(passes, int | np.integer) and not isinstance(passes, bool)
    speed = math.isfinite(velocity) and velocity >= 0
    for name, value, ok, rule in (
        ("velocity", velocity, speed, "finite and >= 0 m/s"),
        ("ratio", ratio, 0 < ratio <= 1, "> 0 and <= 1"),
        ("min_angle", min_angle, 0 < min_angle < 60, "between 0 and 60 degrees"),
        ("passes", passes, integer and passes >= 1, "an integer >= 1"),
        ("target", target, 0 <= target <= 1, ">= 0 and <= 1"),
    ):
        if not ok:
            raise ConfigError(f"{name} = {value!r}: must be {rule}")


def _measures(
    mesh: Mesh,
    xy: NDArray[np.float64],
    velocity: float,
    ratio: float,
    aside: Callable[..., Future[Any]] | None = None,
) -> dict[str, Any]:  # ints and floats, by ThrottleReport's field
    """Return the report's numbers: time steps on the Earth, angles in the plane.

    ``aside(fn, *args)`` returns a future: the angles are measured there
    while the time steps are measured here.
    """
    angles_of = (aside or done_now)(smoothing.min_angles, xy, mesh.triangles)
    step = element_time_steps(mesh, velocity=velocity)["dt"]
    step = step[np.isfinite(step)]  # no NaN (no depth) nor inf (dry)
    p1 = float(np.percentile(step, 1)) if step.size else math.inf
    angles = angles_of.result()
    return {
        "throttling": int((step < ratio * p1).sum()),
        "min_over_p1": float(step.min()) / p1 if step.size and p1 > 0 else math.nan,
        "min_angle": float(angles.min(initial=90.0)),
        "min_angle_p1": smoothing.percentile(angles, 1),
    }


def _plane_time_steps(
    pts: NDArray[np.float64],
    corner_depth: NDArray[np.float64],
    velocity: float,
    radius: float | None = None,
) -> NDArray[np.float64]:
    """Return the time steps of triangles as (k, 3, 2) coordinates (inf: dry).

    ``r_in / (sqrt(g max(d, 0)) + u)``, ``d`` the deepest of ``corner_depth``.
    With ``radius``, the plane is a stereographic one of a sphere of that
    radius, scale 1 at its origin: ``r_in`` is divided by the scale at the
    triangle's centroid, ``1 + r^2 / 4 R^2``
    (:func:`~coastmesh.geometry.sphere.plane_scale`), to be a length on the
    sphere (a global mesh's plane stretches lengths up to some 90 times).
    """
    sides = np.linalg.norm(pts - np.roll(pts, -1, axis=1), axis=2).sum(axis=1)
    r_in = 2 * signed_areas(pts) / np.maximum(sides, 1e-300)
    if radius is not None:
        centre = pts.mean(axis=1)
        r_in = r_in / plane_scale(
            np.hypot(centre[..., 0], centre[..., 1]), radius=radius
        )
    deepest = np.fmax.reduce(corner_depth, axis=1)  # NaN only if all three are
    speed = wave_speed(deepest, velocity)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(speed > 0, r_in / speed, np.inf)


#: Steps of the compass search that moves a node (:meth:`_Collapser.try_move`).
MOVE_STEPS = 8
_COMPASS = np.array(
    [[np.cos(a), np.sin(a)] for a in np.arange(8) * np.pi / 4], dtype=np.float64
)


#: Where a shoreline node may slide, as shares of one of its edges.
_SLIDES = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4)


def _to_segment(
    p: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64]
) -> float:
    """Return the distance from point ``p`` to the segment ``a``-``b``."""
    ab = b - a
    t = np.clip(np.dot(p - a, ab) / max(float(np.dot(ab, ab)), 1e-300), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * ab)))


#: A collapse (:meth:`_Collapser.try_edge`): kept node, removed node, the kept
#: node's place and depth, the deleted triangles, the changed ones, their new
#: nodes and time steps.
_Collapse = tuple[
    int,
    int,
    NDArray[np.float64],
    float,
    set[int],
    NDArray[np.int64],
    NDArray[np.int64],
    NDArray[np.float64],
]

#: What :meth:`_Collapser._relinked` finds: kept node, removed node, the
#: deleted triangles, the changed ones, their new nodes, all affected.
_Relinked = tuple[
    int, int, set[int], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]
]


# Edge collapse is hand-written: no maintained Python library among our
# dependencies (numpy, scipy, shapely, gmsh, meshio) does constrained edge
# collapse on a numpy triangle mesh.
class _Collapser:
    """The mesh being collapsed: triangles, the triangles at each node, time steps.

    No triangle is added: a collapse deletes the two at the edge and renames
    the removed node in the others, so the indices stay.
    """

    def __init__(
        self,
        xy: NDArray[np.float64],
        triangles: NDArray[np.int64],
        fixed: NDArray[np.bool_],
        # node_depth's (None never comes: relieve_time_step checks first)
        depth: NDArray[np.float64] | None,
        velocity: float,
        radius: float | None = None,
    ) -> None:
        self.xy0, self.xy = xy, np.array(xy, dtype=np.float64)  # at first, now
        self.fixed, self.velocity = fixed, velocity
        #: the sphere's radius when ``xy`` is a world plane (lengths scaled)
        self.radius = radius
        self.tri = np.array(triangles, dtype=np.int64)
        self.depth = np.array(depth, dtype=np.float64)
        self.alive = np.ones(len(self.tri), dtype=bool)
        self.removed = np.zeros(len(xy), dtype=bool)
        self.merges: list[tuple[int, int]] = []  # (kept, removed), in order
        #: boundary node -> {neighbour along the boundary: edge id}, for the
        #: coast collapses; the edges of each id; the open boundaries' ids
        self.coast: dict[int, dict[int, int]] = {}
        self.edges_of: dict[int, int] = {}
        self.open_ids: set[int] = set()
        self.coast_collapses = 0
        #: where the nodes were when this round of passes began: a coast
        #: node slides, or goes, once a round
        self.since = self.xy0
        m = len(self.tri)
        csr = sparse.csr_array(
            (np.ones(3 * m, np.int8), (self.tri.ravel(), np.repeat(np.arange(m), 3))),
            shape=(len(xy), m),
        )
        self._ptr, self._at = csr.indptr, csr.indices
        self._stars: dict[int, set[int]] = {}
        self.dt = self._steps(self.xy[self.tri], self.depth[self.tri])

    def _steps(
        self, pts: NDArray[np.float64], corner_depth: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Return the time steps of triangles, on the Earth (`_plane_time_steps`)."""
        return _plane_time_steps(pts, corner_depth, self.velocity, self.radius)

    def star(self, node: int) -> set[int]:
        """Return the set of live triangles at ``node``."""
        if node not in self._stars:
            at = self._at[self._ptr[node] : self._ptr[node + 1]]
            self._stars[node] = set(at.tolist())
        return self._stars[node]

    def _nodes(self, tris: set[int]) -> set[int]:  # of the triangles
        return set(self.tri[list(tris)].ravel().tolist())

    def throttling(self, ratio: float) -> tuple[list[int], float]:
        """Return the live triangles below ``ratio`` x p1, smallest first; the limit."""
        live = np.flatnonzero(self.alive & np.isfinite(self.dt))
        if not live.size:
            return [], 0.0
        limit = ratio * np.percentile(self.dt[live], 1)
        worst = live[self.dt[live] < limit]
        return worst[np.argsort(self.dt[worst], kind="stable")].tolist(), limit

    def run_pass(self, ratio: float, min_angle: float) -> int:
        """Collapse an edge of each triangle below ``ratio`` x p1; return how many."""
        worst, limit = self.throttling(ratio)
        made = 0
        for t in worst:
            if self.alive[t] and self.dt[t] < limit:
                collapse = self.best_collapse(t, min_angle)
                if collapse is not None:
                    self.apply(*collapse)
                    made += 1
        return made

    def move_pass(self, ratio: float, min_angle: float) -> int:
        """Move the nodes of each triangle below ``ratio`` x p1; return how many.

        Of a triangle's nodes, the one whose move lifts the smallest time step
        of its own triangles most goes first, and so on while the triangle
        throttles: a node inside where that time step is largest
        (:meth:`place_inside`), a node of a shoreline along it
        (:meth:`place_on_coast`). The worst triangles first.
        """
        worst, limit = self.throttling(ratio)
        moved = 0
        for t in worst:
            for _ in range(3):
                if not self.alive[t] or self.dt[t] >= limit:
                    break
                options = [self._place(node, min_angle) for node in self.tri[t]]
                best = max((o for o in options if o is not None), default=None)
                if best is None:
                    break
                _, node, place = best
                moved += self._move(node, place)
        return moved

    def _place(
        self, node: int, min_angle: float
    ) -> tuple[float, int, NDArray[np.float64]] | None:
        """Return (time step, node, place) of ``node``'s best move; None if none."""
        node = int(node)
        if self.removed[node]:
            return None
        if not self.fixed[node]:
            found = self.place_inside(node, min_angle)
        elif node in self.coast:
            found = self.place_on_coast(node, min_angle)
        else:
            return None
        return None if found is None else (found[0], node, found[1])

    def _star(self, node: int) -> NDArray[np.int64]:
        return np.fromiter(self.star(node), dtype=np.int64)

    def place_inside(
        self, node: int, min_angle: float
    ) -> tuple[float, NDArray[np.float64]] | None:
        """Return ``node``'s best place inside and its star's smallest time step.

        None if no place beats where it is.

        A compass search (eight directions, the step halved when none is
        better; the neighbours' mean tried first) among the places where every
        triangle of the star keeps a positive area and no angle falls below
        both ``min_angle`` and the star's smallest.
        """
        here = self.xy[node].copy()
        star = self._star(node)
        near = np.unique(self.tri[star].ravel())
        near = near[near != node]
        step = 0.2 * np.linalg.norm(self.xy[near] - here, axis=1).min()
        start = best = self.dt[star].min()
        tries = [self.xy[near].mean(axis=0)[None, :]]
        for _ in range(MOVE_STEPS):
            places = np.concatenate([*tries, here + step * _COMPASS])
            tries = []
            score, k = self._best_place(node, star, places, min_angle)
            if score > best * (1 + 1e-6):
                best, here = score, places[k]
            else:
                step /= 2
        return None if best == start else (best, here)

    def place_on_coast(
        self, node: int, min_angle: float
    ) -> tuple[float, NDArray[np.float64]] | None:
        """Return a shoreline node's best place along its coast, and time step.

        None if none helps.

        Only a node not yet moved, between two shoreline edges of one id whose
        other ends have not moved either; the place is on one of the edges,
        where the node's first place lies within :data:`COAST_TOLERANCE` times
        the new edges' length of the new coast (as for a coast collapse). A
        node's first place is where it was when the round of passes began
        (``since``).
        """
        links = self.coast[node]
        ends = list(links)
        sids = set(links.values())
        moved = [n for n in (node, *ends) if (self.xy[n] != self.since[n]).any()]
        if len(ends) != 2 or len(sids) != 1 or sids & self.open_ids or moved:
            return None
        b = self.xy[node]
        tried, off = [], []
        for end, other in ((ends[0], ends[1]), (ends[1], ends[0])):
            for f in _SLIDES:
                p = b + f * (self.xy[end] - b)
                c = self.xy[other]
                shortest = min(np.linalg.norm(self.xy[end] - p), np.linalg.norm(c - p))
                off.append(_to_segment(b, p, c) <= COAST_TOLERANCE * shortest)
                tried.append(p)
        places = np.asarray(tried)[np.asarray(off)]
        if not len(places):
            return None
        star = self._star(node)
        score, k = self._best_place(node, star, places, min_angle)
        if score <= self.dt[star].min() * (1 + 1e-6):
            return None
        return score, places[k]

    def _best_place(
        self,
        node: int,
        star: NDArray[np.int64],
        places: NDArray[np.float64],
        min_angle: float,
    ) -> tuple[float, int]:
        """Return the best smallest time step of ``star`` over ``node``'s places.

        Places where a triangle of the star would turn over, or an angle fall
        below both ``min_angle`` and the star's smallest, score -inf.
        """
        tris = self.tri[star]
        pts, at = self.xy[tris], tris == node
        floor = min(min_angle, triangle_angles(pts).min())
        moved = np.repeat(pts[None], len(places), axis=0)
        moved[:, at] = places[:, None, :]
        flat = moved.reshape(-1, 3, 2)
        depth = np.tile(self.depth[tris], (len(places), 1))
        dt = self._steps(flat, depth).reshape(len(places), -1)
        ok = (signed_areas(flat) > 0) & (triangle_angles(flat).min(axis=1) >= floor)
        score = np.where(
            ok.reshape(len(places), -1).all(axis=1), dt.min(axis=1), -np.inf
        )
        k = int(np.argmax(score))
        return float(score[k]), k

    def _move(self, node: int, place: NDArray[np.float64]) -> bool:
        """Put ``node`` at ``place``; update the time steps of its triangles."""
        self.xy[node] = place
        star = self._star(node)
        tris = self.tri[star]
        self.dt[star] = self._steps(self.xy[tris], self.depth[tris])
        return True

    def best_collapse(self, t: int, min_angle: float) -> _Collapse | None:
        """Return the first collapse of an edge of ``t`` that passes, shortest first.

        As (kept, removed, position, depth, deleted, changed, new triangles,
        their time steps); None if none passes.
        """
        nodes = self.tri[t].tolist()
        p = self.xy[nodes]
        length = np.linalg.norm(p - np.roll(p, -1, axis=0), axis=1)
        for e in np.argsort(length, kind="stable").tolist():
            collapse = self.try_edge(nodes[e], nodes[(e + 1) % 3], min_angle)
            if collapse is not None:
                return collapse
        return None

    def try_edge(self, a: int, b: int, min_angle: float) -> _Collapse | None:
        """Return the collapse of edge ``(a, b)`` if it passes, else None."""
        found = self._relinked(a, b)
        if found is None:
            return None
        kept, gone, deleted, ids, new, old = found
        position = self.xy[kept] if self.fixed[kept] else (self.xy[a] + self.xy[b]) / 2
        pts = self.xy[new]
        pts[new == kept] = position
        merged = np.fmax(self.depth[a], self.depth[b])
        corner_depth = self.depth[new]
        corner_depth[new == kept] = merged
        dt = self._steps(pts, corner_depth)
        floor = min(min_angle, triangle_angles(self.xy[self.tri[old]]).min())
        if (
            (signed_areas(pts) > 0).all()
            and triangle_angles(pts).min() >= floor
            and dt.min() > self.dt[old].min()
        ):
            return kept, gone, position, merged, deleted, ids, new, dt
        return None

    def _coast_pair(self, a: int, b: int) -> tuple[int, int, int] | None:
        """Return (kept, gone, next) if shoreline edge ``(a, b)`` may collapse.

        ``gone`` has two shoreline edges of one id (to ``kept`` and to
        ``next``) and lies within :data:`COAST_TOLERANCE` of edge
        ``(kept, next)``'s length from it; none of the three has slid.
        """
        for kept, gone in ((a, b), (b, a)):
            links = self.coast.get(gone)
            if links is None or kept not in links or len(links) != 2:
                continue
            after = next(n for n in links if n != kept)
            own = links[kept]
            if own != links[after] and self.edges_of[own] < 2:
                continue  # the last edge of a boundary id
            if own == links[after] and own in self.open_ids:
                continue  # an open boundary keeps its nodes
            if (self.xy[[kept, gone, after]] != self.since[[kept, gone, after]]).any():
                continue  # slid along the coast already: the shape moves once
            p, q, r = self.xy[kept], self.xy[after], self.xy[gone]
            span = float(np.linalg.norm(q - p))
            if span == 0 or after == kept:
                continue
            cross = abs((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))
            if cross / span <= COAST_TOLERANCE * span:
                return kept, gone, after
        return None

    def _short_run(self, node: int, sid: int) -> bool:
        """Whether ``node``'s run of id ``sid`` is short, between open boundaries.

        :data:`MIN_RUN` edges or fewer (Telemac needs three).
        """
        edges = 0
        ends: list[int | None] = []  # the ids beyond the run's ends (None: none)
        for first in self.coast[node]:
            prev, at = node, first
            while True:
                edges += 1
                links = self.coast.get(at)
                if links is None or len(links) != 2:
                    ends.append(None)
                    break
                nxt = next(n for n in links if n != prev)
                if links[nxt] != sid:
                    ends.append(links[nxt])
                    break
                if nxt == node or edges > MIN_RUN + 1:  # a ring, or long enough
                    return False
                prev, at = at, nxt
        return edges <= MIN_RUN and all(e in self.open_ids for e in ends)

    def _relinked(self, a: int, b: int) -> _Relinked | None:
        """Return the new triangles if collapsing ``(a, b)`` leaves a valid mesh.

        As (kept, removed, deleted, changed, their nodes, all affected).
        """
        along = None
        if self.fixed[a] and self.fixed[b]:
            along = self._coast_pair(a, b)
            if along is None:
                return None
            kept, gone, after = along
        else:
            fixed_b = self.fixed[b] or (not self.fixed[a] and b < a)
            kept, gone = (b, a) if fixed_b else (a, b)
        own, other = self.star(kept), self.star(gone)
        deleted = own & other
        near_kept, near_gone = self._nodes(own) - {kept}, self._nodes(other) - {gone}
        opposite = self._nodes(deleted) - {a, b}
        if (
            not deleted
            or near_kept & near_gone != opposite  # the link condition
            or any(self.star(c) <= deleted for c in opposite)  # a node left bare
            or (  # a new edge between two boundary nodes (but the coast's)
                self.fixed[kept]
                and self.fixed[
                    list(near_gone - near_kept - {kept} - ({after} if along else set()))
                ].any()
            )
        ):
            return None
        changed = sorted(other - deleted)
        ids = np.array(sorted(own - deleted) + changed, dtype=np.int64)
        new = self.tri[ids]
        new[new == gone] = kept
        repeated = len(np.unique(np.sort(new, axis=1), axis=0)) < len(new)
        if repeated or self.fixed[new[len(ids) - len(changed) :]].all(axis=1).any():
            return None  # a repeated triangle, or a new all-boundary one
        if along is not None and len(deleted) != 1:
            return None  # a shoreline edge has one triangle
        return kept, gone, deleted, ids, new, np.array(sorted(own | other))

    def apply(
        self,
        kept: int,
        gone: int,
        position: NDArray[np.float64],
        merged: float,
        deleted: set[int],
        ids: NDArray[np.int64],
        new: NDArray[np.int64],
        dt: NDArray[np.float64],
    ) -> None:
        """Make a collapse returned by :meth:`try_edge`."""
        for t in deleted:
            for node in self.tri[t].tolist():
                self.star(node).discard(t)
        self._stars[kept] = self.star(kept) | self.star(gone)
        self._stars[gone] = set()
        dead = list(deleted)
        self.alive[dead], self.dt[dead] = False, np.nan
        self.tri[ids], self.dt[ids] = new, dt
        self.xy[kept], self.depth[kept] = position, merged
        self.removed[gone] = True
        self.merges.append((kept, gone))
        links = self.coast.pop(gone, None)
        if links is not None:  # a coast collapse: kept and next now meet
            self.coast_collapses += 1
            after = next(n for n in links if n != kept)
            sid = links[after]
            self.edges_of[links[kept]] -= 1
            for node, other in ((kept, after), (after, kept)):
                if node in self.coast:
                    self.coast[node].pop(gone, None)
                    self.coast[node][other] = sid

    def result(self, mesh: Mesh, to_plane: Transformer | None) -> Mesh:
        """Return ``mesh`` with the collapses: removed nodes dropped, renumbered."""
        keep = ~self.removed
        index = np.cumsum(keep) - 1
        point_data = {}
        for name, values in mesh.point_data.items():
            full = np.array(values, dtype=np.result_type(values, 1.0))
            for kept, gone in self.merges:
                full[kept] = (full[kept] + full[gone]) / 2
            point_data[name] = full[keep]
        points = smoothing.moved_points(mesh.points, self.xy0, self.xy, to_plane)
        into = np.arange(len(keep))
        for kept, gone in self.merges:
            into[gone] = kept
        while (into[into] != into).any():  # a node merged into one merged later
            into = into[into]
        edges = into[mesh.boundary_edges]
        whole = edges[:, 0] != edges[:, 1]  # a coast collapse's edge is gone
        return smoothing.mesh_with(
            mesh,
            points=points[keep],
            triangles=index[self.tri[self.alive]],
            regions=mesh.regions[self.alive],
            boundary_edges=index[edges[whole]],
            boundary_ids=mesh.boundary_ids[whole],
            point_data=point_data,
        )
