"""The parts of the water as tasks: each meshed alone, merged by shared nodes.

:func:`part_tasks` turns the faces of :func:`~coastmesh.meshing.parts.faces.split_faces`
into :class:`PartTask` objects that hold all one part needs and nothing else:
its own curves, its window of the size grid and the Gmsh options. Each piece of
a cut is discretised once, here, from the size grid (one node per target edge,
:func:`~coastmesh.meshing.gmsh.resample.resample_segment`), and given to both parts
it separates as fixed nodes (a chain of 2-node lines), so the two meshes share
those nodes exactly and :func:`merge_parts` joins them by the nodes' shared
numbers: no stitching, no search by distance.

:func:`mesh_part` is a plain function of its task, so any executor can run it:
a loop in this process, a local process pool, or a Dask cluster. The mesh of a
part does not depend on where or when it was made, so the merged mesh does not
depend on the executor or the worker count.
"""

from __future__ import annotations

import itertools
import os
import socket
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.errors import MeshingError
from coastmesh.geometry.projection import sample_size
from coastmesh.meshing.cleanup.fixes import clean_mesh
from coastmesh.meshing.cleanup.planar import signed_areas
from coastmesh.meshing.cleanup.report import CleanupOptions, PartCleanup
from coastmesh.meshing.cleanup.smoothing import min_angles
from coastmesh.meshing.gmsh.model import (
    add_size_view,
    crop_grid,
    gmsh_session,
    set_options,
)
from coastmesh.meshing.gmsh.resample import resample_segment
from coastmesh.meshing.parts.cuts import auto_parts, expected_triangles
from coastmesh.meshing.parts.faces import Faces
from coastmesh.types import Mesh, MeshLine, Runner, SizeGrid, serial_runner

__all__ = [
    "PartMesh",
    "PartTask",
    "Runner",
    "clean_part",
    "label_point",
    "merge_parts",
    "mesh_arrays",
    "mesh_part",
    "part_tasks",
    "serial_runner",
    "start_workers",
]


@dataclass(frozen=True, slots=True)
class PartTask:
    """All that meshing one part of the water needs.

    Attributes
    ----------
    index, count : int
        This part's number (0-based) and the number of parts.
    curves : tuple of ndarray of shape (k, 2)
        The part's curves in the meshing CRS. A cut's points are its nodes.
    ids : tuple of int or None
        Each curve's physical id; None for a piece of a cut.
    shared : tuple of ndarray of int
        Per curve, the shared number of each point of a cut (empty for others).
    loops : tuple of tuple of int
        The outer loop first, then holes: signed 1-based curve indices.
    size : SizeGrid
        The size grid (map units) over the part's bounds, a few cells wider.
    seed : int
    algorithm : str
    optimize : bool
    expected : float
        The part's expected triangle count.
    centre : (float, float)
        A point inside the part, in the meshing CRS, where the parts figure
        puts its label (:func:`label_point`).
    cleanup : CleanupOptions or None
        Clean the part's mesh, the nodes of its cuts held (:func:`clean_part`).
    embedded, embedded_numbers : ndarray
        Points (k, 2) that must be nodes of the part (turbines), and their
        shared numbers: held as the nodes of cuts are.
    lines : tuple of MeshLine
        Lines inside the part whose edges must be mesh edges (their points
        are their nodes), embedded as curves.
    line_numbers : tuple of ndarray of int
        The shared numbers of each line's nodes: held as the nodes of cuts are.
    """

    index: int
    count: int
    curves: tuple[NDArray[np.float64], ...]
    ids: tuple[int | None, ...]
    shared: tuple[NDArray[np.int64], ...]
    loops: tuple[tuple[int, ...], ...]
    size: SizeGrid
    seed: int
    algorithm: str
    optimize: bool
    expected: float
    centre: tuple[float, float] = (0.0, 0.0)
    cleanup: CleanupOptions | None = None
    embedded: NDArray[np.float64] = field(
        default_factory=lambda: np.empty((0, 2), dtype=np.float64)
    )
    embedded_numbers: NDArray[np.int64] = field(
        default_factory=lambda: np.empty(0, dtype=np.int64)
    )
    lines: tuple[MeshLine, ...] = ()
    line_numbers: tuple[NDArray[np.int64], ...] = ()

    @property
    def label(self) -> str:
        """Name the part in messages: number, size and place."""
        xy = np.concatenate(self.curves)
        cx, cy = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
        return (
            f"part {self.index + 1} of {self.count} ({self.expected:,.0f} expected "
            f"triangles, centred at x={cx:.0f}, y={cy:.0f} in the meshing CRS)"
        )


@dataclass(frozen=True, slots=True)
class PartMesh:
    """One part's mesh, in the meshing CRS.

    ``shared[i]`` is the shared number of node ``i`` if it lies on a cut (or
    is a turbine's or a line's node), else -1; ``lines`` are the task's.
    ``seconds`` is the Gmsh time of the part and ``worker`` the host and
    process that made it; ``cleanup`` is what cleaning it did, if it was.
    """

    index: int
    points: NDArray[np.float64]
    triangles: NDArray[np.int64]
    edges: NDArray[np.int64]
    edge_ids: NDArray[np.int64]
    shared: NDArray[np.int64]
    seconds: float
    worker: str
    cleanup: PartCleanup | None = None
    lines: tuple[MeshLine, ...] = ()


def part_tasks(
    faces: Faces,
    size: SizeGrid,
    *,
    seed: int,
    algorithm: str,
    optimize: bool,
    cleanup: CleanupOptions | None = None,
    exact: Sequence[NDArray[np.float64]] = (),
    points: NDArray[np.float64] | None = None,
    lines: Sequence[MeshLine] = (),
) -> list[PartTask]:
    """Return one task per face of water, its cuts discretised once.

    Parameters
    ----------
    faces : Faces
        From :func:`~coastmesh.meshing.parts.faces.split_faces`.
    size : SizeGrid
        Target sizes in map units.
    seed, algorithm, optimize
        As :func:`~coastmesh.meshing.generate_mesh` takes them.
    cleanup : CleanupOptions, optional
        Clean each part where it is meshed.
    exact : sequence of ndarray of shape (k, 2)
        Closed cuts already noded (the outlines of regions,
        :func:`~coastmesh.meshing.parts.inner.node_ring`): their points are
        their nodes, not resampled.
    points : ndarray of shape (k, 2), optional
        Points that must be nodes, each embedded in the face that holds it.
    lines : sequence of MeshLine
        Lines already noded whose edges must be mesh edges, each embedded in
        the face that holds it (a line crosses no cut and no region outline).

    Returns
    -------
    list of PartTask
        In the order of ``faces.faces``.
    """

    def size_at(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        return sample_size(size, xy)

    numbers: dict[tuple[float, float], int] = {}
    chains: dict[int, tuple[NDArray[np.float64], NDArray[np.int64]]] = {}
    noded = {(float(x), float(y)) for ring in exact for x, y in ring}
    for i, pid in enumerate(faces.ids):
        if pid is not None:
            continue
        chain = faces.curves[i]
        if not all((float(x), float(y)) in noded for x, y in chain):
            chain = resample_segment(chain, size_at, points_per_edge=1.0, up=True)
        keys = [(float(x), float(y)) for x, y in chain]
        chains[i] = chain, np.array([numbers.setdefault(k, len(numbers)) for k in keys])
    tasks = []
    for index, loops in enumerate(faces.faces):
        used = sorted({abs(s) - 1 for loop in loops for s in loop})
        local = {g: k + 1 for k, g in enumerate(used)}
        curves = tuple(chains[g][0] if g in chains else faces.curves[g] for g in used)
        signed = tuple(
            tuple(int(np.sign(s)) * local[abs(s) - 1] for s in loop) for loop in loops
        )
        xy = np.concatenate(curves)
        bounds = (*xy.min(axis=0), *xy.max(axis=0))
        polygon = shapely.Polygon(
            _ring(signed[0], curves), [_ring(h, curves) for h in signed[1:]]
        )
        window = crop_grid(size, bounds)  # the same cells, over the part only
        inside = np.empty((0, 2))
        shapely.prepare(polygon)
        if points is not None and len(points):
            inside = points[shapely.contains_xy(polygon, points[:, 0], points[:, 1])]
        held = tuple(ln for ln in lines if polygon.contains(shapely.LineString(ln.xy)))
        tasks.append(
            PartTask(
                index=index,
                count=len(faces.faces),
                curves=curves,
                ids=tuple(faces.ids[g] for g in used),
                shared=tuple(
                    chains[g][1] if g in chains else np.empty(0, np.int64) for g in used
                ),
                loops=signed,
                size=window,
                seed=seed,
                algorithm=algorithm,
                optimize=optimize,
                expected=expected_triangles(polygon, window),
                centre=label_point(polygon),
                cleanup=cleanup,
                embedded=inside,
                embedded_numbers=np.array(
                    [
                        numbers.setdefault((float(x), float(y)), len(numbers))
                        for x, y in inside
                    ],
                    dtype=np.int64,
                ),
                lines=held,
                line_numbers=tuple(_numbered(ln.xy, numbers) for ln in held),
            )
        )
    return tasks


def _numbered(
    xy: NDArray[np.float64], numbers: dict[tuple[float, float], int]
) -> NDArray[np.int64]:
    """Return the shared numbers of points, numbering the new ones next."""
    keys = [(float(x), float(y)) for x, y in xy]
    return np.array([numbers.setdefault(k, len(numbers)) for k in keys], np.int64)


def start_workers(
    runner: Any,
    parts: int | str,
    rings: list[list[NDArray[np.float64]]],
    size: SizeGrid,
) -> None:
    """Have ``runner`` start the workers for the parts now, if it can.

    Called while the boundary nodes are made, seconds before the parts are
    ready, so that a local pool's worker processes have started and imported
    Python, numpy, shapely and Gmsh (about 2 s each) when the parts come.
    ``parts = "auto"`` is estimated from the projected ``rings`` (exterior
    first); the water the parts are cut from can differ at a power of two,
    and then a worker starts for nothing, or when its part comes. A runner
    without a ``warm(count, ready)`` method (this process, Dask) is left be.
    """
    warm = getattr(runner, "warm", None)
    if warm is None or parts == 1:
        return
    if parts == "auto":
        shells = [np.concatenate([np.asarray(s) for s in ring]) for ring in rings]
        water = shapely.Polygon(shells[0], shells[1:])
        # an estimate only, so on a coast simplified to the smallest size (on a
        # world, 126,000 vertices to 12,000: the grid's nodes found in it in
        # 0.2 s, not 1.3, while the workers start)
        smallest = np.nanmin(getattr(size, "grid", size).values)
        parts = auto_parts(shapely.simplify(water, float(smallest)), size)
    if int(parts) > 1:
        warm(int(parts), ready)


def ready() -> None:
    """Import Gmsh: the first task of a worker started ahead of its parts."""
    import gmsh  # noqa: F401  (this module brought the rest mesh_part needs)


def _ring(
    loop: Sequence[int], curves: tuple[NDArray[np.float64], ...]
) -> NDArray[np.float64]:
    """Return a loop of signed 1-based curve indices as one ring's points."""
    pieces = [curves[abs(s) - 1][:: 1 if s > 0 else -1] for s in loop]
    return np.concatenate([p[:-1] for p in pieces])


def mesh_part(task: PartTask) -> PartMesh:
    """Mesh one part alone, in a Gmsh session of its own; clean it if asked.

    Every curve is a chain of straight 2-node lines through its points: the
    points are the boundary's nodes, and Gmsh meshes only the inside.

    Raises
    ------
    MeshingError
        If Gmsh fails or makes no triangles; the message names the part.
    """
    started = time.perf_counter()
    with gmsh_session() as gmsh:
        try:
            set_options(gmsh, threads=1, seed=task.seed, algorithm=task.algorithm)
            surface = _build_part(gmsh, task)
            _embed(gmsh, task, surface)
            xy = np.concatenate(task.curves)
            add_size_view(gmsh, task.size, (*xy.min(axis=0), *xy.max(axis=0)))
            gmsh.model.mesh.generate(2)
            if task.optimize:
                gmsh.model.mesh.optimize("Relocate2D")
            points, triangles = mesh_arrays(gmsh)
        except MeshingError as exc:
            raise MeshingError(f"{task.label}: {exc}") from exc
        except Exception as exc:  # gmsh raises bare Exception with its last error
            raise MeshingError(f"{task.label}: Gmsh failed: {exc}") from exc
    find = _Finder(points)
    shared = np.full(len(points), -1, dtype=np.int64)
    edges, edge_ids = [], []
    for c, pid, numbers in zip(task.curves, task.ids, task.shared, strict=True):
        nodes = find(c, task)
        if pid is None:
            shared[nodes] = numbers
        else:
            edges.append(np.column_stack([nodes[:-1], nodes[1:]]))
            edge_ids.append(np.full(len(nodes) - 1, pid, dtype=np.int64))
    if len(task.embedded):
        shared[find(task.embedded, task)] = task.embedded_numbers
    for line, numbers in zip(task.lines, task.line_numbers, strict=True):
        shared[find(line.xy, task)] = numbers
    part = PartMesh(
        task.index,
        points,
        triangles,
        np.concatenate(edges) if edges else np.empty((0, 2), np.int64),
        np.concatenate(edge_ids) if edge_ids else np.empty(0, np.int64),
        shared,
        round(time.perf_counter() - started, 3),
        f"{socket.gethostname()}:{os.getpid()}",
        lines=task.lines,
    )
    return part if task.cleanup is None else clean_part(part, task.cleanup)


def _embed(gmsh: Any, task: PartTask, surface: int) -> None:
    """Embed the task's turbine points and lines (2-node curves) in its surface."""
    geo = gmsh.model.geo
    points = [geo.addPoint(x, y, 0.0) for x, y in task.embedded]
    curves = []
    for line in task.lines:
        tags = [geo.addPoint(x, y, 0.0) for x, y in line.xy]
        for a, b in itertools.pairwise(tags):
            curves.append(geo.addLine(a, b))
            geo.mesh.setTransfiniteCurve(curves[-1], 2)  # its two ends only
    if not (points or curves):
        return
    geo.synchronize()
    if points:
        gmsh.model.mesh.embed(0, points, 2, surface)
    if curves:
        gmsh.model.mesh.embed(1, curves, 2, surface)


def clean_part(part: PartMesh, options: CleanupOptions) -> PartMesh:
    """Return ``part`` cleaned (:func:`~coastmesh.meshing.clean_mesh`), its cuts held.

    The nodes of the cuts neither move nor count as boundary or in the valence,
    and an edge of a cut is never flipped or split (it has one triangle here),
    so the neighbour's mesh still meets this one node for node. New nodes come
    last; the meshing CRS is conformal, so angles are measured in it.
    """
    started = time.perf_counter()
    on_cut = part.shared >= 0
    on_cut[part.edges.ravel()] = False  # a cut's ends on the boundary are boundary
    mesh = Mesh(
        part.points,
        part.triangles,
        part.edges,
        part.edge_ids,
        1,
        None,
        lines=part.lines,
    )
    clean, report = clean_mesh(
        mesh,
        boundary_triangles=options.boundary_triangles,
        max_valence=options.max_valence,
        min_angle=options.min_angle,
        smooth=options.smooth,
        fixed=on_cut,
    )
    valence = np.bincount(part.triangles.ravel(), minlength=len(part.points))
    shared = np.full(len(clean.points), -1, dtype=np.int64)
    shared[: len(part.shared)] = part.shared
    return PartMesh(
        part.index,
        clean.points,
        clean.triangles,
        part.edges,
        part.edge_ids,
        shared,
        part.seconds,
        part.worker,
        PartCleanup(
            report,
            min_angles(part.points, part.triangles),
            part.shared[on_cut],
            valence[on_cut],
            round(time.perf_counter() - started, 3),
        ),
        part.lines,
    )


class _Finder:
    """Find given points among the mesh nodes, exactly.

    A boundary node is a Gmsh point, at the very coordinates it was given.
    """

    def __init__(self, points: NDArray[np.float64]) -> None:
        # complex numbers sort by real part, then imaginary: (x, y) order
        self.keys = points[:, 0] + 1j * points[:, 1]
        self.order = np.argsort(self.keys, kind="stable")
        self.sorted = self.keys[self.order]

    def __call__(self, xy: NDArray[np.float64], task: PartTask) -> NDArray[np.int64]:
        want = xy[:, 0] + 1j * xy[:, 1]
        at = np.clip(np.searchsorted(self.sorted, want), 0, len(self.sorted) - 1)
        found = self.order[at]
        if not np.array_equal(self.keys[found], want):
            raise MeshingError(f"{task.label}: Gmsh left out nodes of its boundary")
        return found.astype(np.int64)


def _build_part(gmsh: Any, task: PartTask) -> int:
    """Add the part's points, its curves as 2-node lines, and its surface (tag)."""
    geo = gmsh.model.geo
    point: dict[tuple[float, float], int] = {}

    def tag(xy: NDArray[np.float64]) -> int:
        key = (float(xy[0]), float(xy[1]))
        if key not in point:
            point[key] = geo.addPoint(key[0], key[1], 0.0)
        return point[key]

    made = [
        [geo.addLine(a, b) for a, b in itertools.pairwise([tag(p) for p in c])]
        for c in task.curves
    ]
    loops = []
    for loop in task.loops:
        signed = []
        for s in loop:
            lines = made[abs(s) - 1]
            signed += lines if s > 0 else [-t for t in reversed(lines)]
        loops.append(geo.addCurveLoop(signed))
    surface: int = geo.addPlaneSurface(loops)  # gmsh is untyped: Any
    for line in itertools.chain.from_iterable(made):
        geo.mesh.setTransfiniteCurve(line, 2)  # its two end nodes, nothing between
    geo.synchronize()
    return surface


def mesh_arrays(gmsh: Any) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Return the meshed model's nodes that triangles use, and the triangles.

    The triangles are counter-clockwise in the model's plane.

    Raises
    ------
    MeshingError
        If Gmsh made no triangles.
    """
    node_tags, node_xyz, _ = gmsh.model.mesh.getNodes()
    _, tri_nodes = gmsh.model.mesh.getElementsByType(2)
    if len(tri_nodes) == 0:
        raise MeshingError(
            f"Gmsh made no triangles: {gmsh.logger.getLastError() or 'no message'}"
        )
    node_tags = node_tags.astype(np.int64)
    index = np.full(int(node_tags.max()) + 1, -1, dtype=np.int64)
    index[node_tags] = np.arange(len(node_tags))
    triangles = index[tri_nodes.astype(np.int64)].reshape(-1, 3)
    used, renumber = np.unique(triangles, return_inverse=True)
    points = node_xyz.reshape(-1, 3)[used, :2].copy()
    triangles = renumber.reshape(-1, 3).astype(np.int64)
    clockwise = signed_areas(points[triangles]) < 0  # Gmsh's follow the surface's
    triangles[clockwise] = triangles[clockwise][:, [0, 2, 1]]  # normal
    return points, triangles


def merge_parts(
    parts: Sequence[PartMesh],
) -> tuple[
    NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64]
]:
    """Join the parts' meshes into one: each shared node once.

    Returns
    -------
    points, triangles, edges, edge_ids
        The nodes on cuts first, in order of their shared numbers, then each
        part's other nodes in part order.

    Raises
    ------
    MeshingError
        If two parts put a shared node at different places.
    """
    parts = sorted(parts, key=lambda p: p.index)
    n_shared = max((int(p.shared.max()) + 1 for p in parts), default=0)
    shared_xy = np.full((n_shared, 2), np.nan)
    offsets, points = [], [shared_xy]
    start = n_shared
    for p in parts:
        on_cut = p.shared >= 0
        here = shared_xy[p.shared[on_cut]]
        seen = ~np.isnan(here[:, 0])
        if not np.array_equal(here[seen], p.points[on_cut][seen]):
            raise MeshingError(
                f"part {p.index + 1} put a node of a cut at another place than "
                "its neighbour did; the parts do not conform"
            )
        shared_xy[p.shared[on_cut]] = p.points[on_cut]
        number = np.empty(len(p.points), dtype=np.int64)
        number[on_cut] = p.shared[on_cut]
        number[~on_cut] = start + np.arange(int((~on_cut).sum()))
        start += int((~on_cut).sum())
        points.append(p.points[~on_cut])
        offsets.append(number)
    if np.isnan(shared_xy).any():
        raise MeshingError("a node of a cut is in no part's mesh")
    return (
        np.concatenate(points),
        np.concatenate([n[p.triangles] for n, p in zip(offsets, parts, strict=True)]),
        np.concatenate([n[p.edges] for n, p in zip(offsets, parts, strict=True)]),
        np.concatenate([p.edge_ids for p in parts]),
    )


def label_point(polygon: shapely.Polygon) -> tuple[float, float]:
    """Return a point inside ``polygon`` far from its edges, for a label.

    The centre of the largest circle inside it (GEOS, to 1 % of the square
    root of its area), so that a label sits in the open water of a part
    rather than next to a coast; a point on its surface if that fails.

    Examples
    --------
    An L of arms 10 wide: the widest place is at the elbow, 5.86 from the
    edges (a point on its surface lies 5 from them, in an arm).

    >>> ell = shapely.Polygon([(0, 0), (30, 0), (30, 10), (10, 10), (10, 30), (0, 30)])
    >>> round(ell.exterior.distance(shapely.Point(label_point(ell))), 2)
    5.86
    """
    tolerance = 0.01 * float(np.sqrt(polygon.area))
    if tolerance > 0:
        with np.errstate(divide="ignore", invalid="ignore"):  # a degenerate one
            circle = shapely.maximum_inscribed_circle(polygon, tolerance)
        if not circle.is_empty:
            x, y = circle.coords[0]
            if polygon.contains(shapely.Point(x, y)):
                return float(x), float(y)
    x, y = polygon.point_on_surface().coords[0]
    return float(x), float(y)
