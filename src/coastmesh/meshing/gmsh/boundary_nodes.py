"""The boundary nodes, made once by Gmsh's own 1-D mesher.

Gmsh meshes each boundary piece (a spline through the points of
:func:`~coastmesh.meshing.gmsh.resample.resample_rings`, at most
:data:`~coastmesh.meshing.gmsh.boundary_nodes.CURVE_POINTS` points) from the size grid:
equal steps of the integral of 1/h, rounded up, so no boundary edge is longer
than its target (but on a short piece between corners, :func:`fewer_edges`).
That is done here once, for the whole boundary (a long one in batches, on the
workers), before the water is cut; the nodes are then
fixed, and every part (or the whole water) is meshed inside them. So the
boundary nodes, where the worst triangles of a coastal mesh sit, are the same
however the water is cut, and a cut that ends on a boundary curve cannot move
the nodes along it.
"""

from __future__ import annotations

import itertools
from typing import Any, NamedTuple

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.errors import MeshingError
from coastmesh.geometry.projection import sample_size
from coastmesh.meshing.gmsh.model import add_size_view, gmsh_session, set_options
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.types import Runner, SizeGrid, serial_runner

__all__ = [
    "BATCHES",
    "BATCH_CURVES",
    "CURVE_POINTS",
    "NEAREST_BELOW",
    "NEAREST_SLACK",
    "BoundaryBatch",
    "batch_nodes",
    "boundary_nodes",
    "chunked",
    "fewer_edges",
]

#: The most points of one Gmsh spline (:func:`chunked`).
CURVE_POINTS = 500

#: A piece between two corners of one boundary segment (:func:`fewer_edges`) of
#: under this many target sizes gets ``ceil(s - NEAREST_SLACK)`` edges, not
#: Gmsh's ``floor(s + 0.99)``: its edges are 0.65 to 1.3 sizes, not 0.5 to 1.
#: (From three sizes on, Gmsh's edges are at least 0.75 of a size.)
NEAREST_BELOW = 3.0
#: See :data:`NEAREST_BELOW`.
NEAREST_SLACK = 0.3


#: A boundary of more curves than this is meshed in :data:`BATCHES` batches
#: (:func:`boundary_nodes`).
BATCH_CURVES = 500
#: The batches of a long boundary. Each carries the size grid to its worker:
#: on ``world_fine.toml`` (28,072 curves, a grid of 49 MB) 4 batches took
#: 5.5 s on 2 workers, 57 batches of 500 curves 9.5 s (9.8 s in one).
BATCHES = 4


class BoundaryBatch(NamedTuple):
    """Runs of boundary pieces meshed in one Gmsh session (:func:`batch_nodes`).

    ``runs``: per run, consecutive pieces of one ring as ``(points, id)`` and
    whether they are the whole ring (its last piece ends on its first point).
    ``expected`` (the pieces' points) orders the batches for the runner,
    longest first.
    """

    runs: tuple[tuple[tuple[tuple[NDArray[np.float64], int], ...], bool], ...]
    size: Any
    expected: float
    label: str


def boundary_nodes(
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    size: SizeGrid,
    runner: Runner[BoundaryBatch, list[NDArray[np.float64]]] = serial_runner,
) -> tuple[list[tuple[NDArray[np.float64], int]], shapely.Polygon]:
    """Return the boundary as chains of its mesh nodes, and the water.

    Each curve is meshed alone, so the boundary can be meshed in batches:
    one of more than :data:`BATCH_CURVES` curves is split, at equal shares of
    its points, into :data:`BATCHES`, each meshed in a Gmsh session of its own
    as a task of ``runner`` (``world.toml``: 1,944 curves, 2.6 s in one
    session, 1.6 s on 2 workers; ``world_fine.toml``: 28,072 curves, 9.4 s
    and 5.5 s). The batches depend on the boundary alone, never on the
    workers, so the nodes are the same on any number of them.

    Each batch is meshed on one Gmsh thread, so that its nodes are the same
    bytes every run. On two, Gmsh reads the size view through an octree that
    starts each search from the element it found last, so which thread looked
    last picks, on an element's edge, between two values that differ in the
    last bits, and nodes move by some 1e-15 of the domain's size (seen on
    ``world.toml``: one piece of 1,945 in some runs, and the mesh's nodes near
    it by up to 4e-9 degrees); in turns with two threads it was no slower.
    For the same reason a curve's nodes in a batch can differ from those in the
    whole boundary by such bits (``world.toml``: 3 curves of 1,944, by 2e-9 m).

    Parameters
    ----------
    rings : list of list of list of ndarray of shape (k, 2)
        From :func:`~coastmesh.meshing.gmsh.resample.resample_rings`, in the
        meshing CRS.
    ids : list of list of int
        Each ring's segments' physical ids.
    size : SizeGrid
        Target sizes in map units.
    runner : Runner, default serial_runner
        Runs the batches (:mod:`coastmesh.case.executor`).

    Returns
    -------
    pieces : list of (ndarray of shape (m, 2), int)
        Per piece, in ring order, its nodes from end to end (the ends are the
        piece's own end points) and its physical id.
    water : shapely.Polygon
        The polygon those nodes bound.

    Raises
    ------
    MeshingError
        If Gmsh fails.
    """
    by_ring = _ring_pieces(rings, ids)
    batches = _batches(by_ring, size)
    if len(batches) == 1:
        inner = batch_nodes(batches[0])
    else:
        inner = [nodes for done in runner(batch_nodes, batches) for nodes in done]
    flat = [piece for pieces in by_ring for piece in pieces]
    pieces = [
        (np.vstack([piece[:1], nodes, piece[-1:]]), pid)
        for (piece, pid), nodes in zip(flat, inner, strict=True)
    ]
    pieces = fewer_edges(pieces, [len(r) for r in by_ring], size)
    starts = np.cumsum([0] + [len(r) for r in by_ring])
    coords = [
        np.concatenate([pieces[a][0][:1], *(p[1:] for p, _ in pieces[a:b])])
        for a, b in itertools.pairwise(starts)
    ]
    return pieces, shapely.Polygon(coords[0], coords[1:])


def fewer_edges(
    pieces: list[tuple[NDArray[np.float64], int]], counts: list[int], size: Any
) -> list[tuple[NDArray[np.float64], int]]:
    """Give short pieces between corners the nearest count of edges, not more.

    Gmsh cuts a curve of ``s`` target sizes (the integral of 1/h along it) into
    ``floor(s + 0.99)`` edges, so that none is longer than its size: a piece
    of 1.05 sizes gets two edges of 0.53. Where the piece is the coast between
    two corners (:mod:`~coastmesh.meshing.gmsh.resample` keeps a vertex that
    turns by more than 30 degrees between straight runs of a size or more) the
    triangle on such an edge is half the size around it, and in deep water it
    caps an explicit model's time step (``world_fine.toml``'s coast had 540
    pieces of under 3 sizes with an edge under 0.6 of a size, the time-step
    relief's work afterwards). So a piece whose neighbours on both sides have
    its id (it ends at corners, or where an island's ring starts: never at an
    open boundary or a change of shoreline set, whose runs keep Gmsh's count)
    and of under :data:`NEAREST_BELOW` sizes gets ``max(1, ceil(s -
    NEAREST_SLACK))`` edges if that is fewer than Gmsh's. The new nodes are
    Gmsh's own polyline's points at equal steps of ``s``.

    Parameters
    ----------
    pieces : list of (ndarray of shape (m, 2), int)
        Each piece's nodes from end to end, and its id, ring by ring; each
        ring's pieces close on its first point.
    counts : list of int
        The pieces of each ring.
    size : SizeGrid or SphereSizeGrid
        Target sizes in map units, as Gmsh saw them.

    Returns
    -------
    list of (ndarray, int)
        The pieces, some with fewer inner nodes; the ends never move.

    Examples
    --------
    Two corners 1.1 sizes apart, in a ring of one id: Gmsh's two edges become
    one; a piece whose neighbour has another id keeps its two.

    >>> g = SizeGrid([0.0, 100.0], [0.0, 100.0], np.full((2, 2), 10.0))
    >>> def piece(a, b, n):
    ...     return np.linspace(a, b, n + 1)
    >>> ring = [(piece([0, 0], [11, 0], 2), 1), (piece([11, 0], [11, 30], 3), 1),
    ...         (piece([11, 30], [0, 0], 4), 1)]
    >>> [len(p) - 1 for p, _ in fewer_edges(ring, [3], g)]
    [1, 3, 4]
    >>> ring[1] = (ring[1][0], 2)
    >>> [len(p) - 1 for p, _ in fewer_edges(ring, [3], g)]
    [2, 3, 4]
    """
    out = list(pieces)
    if not pieces:
        return out
    # every edge's length in sizes at once (one search of the size grid)
    nodes_of = [nodes for nodes, _ in pieces]
    edges = np.array([len(nodes) - 1 for nodes in nodes_of])
    a = np.concatenate([nodes[:-1] for nodes in nodes_of])
    b = np.concatenate([nodes[1:] for nodes in nodes_of])
    sizes = np.hypot(*(b - a).T) / sample_size(size, 0.5 * (a + b))
    first = np.cumsum(edges) - edges
    s_of = np.add.reduceat(sizes, first)  # every piece has an edge
    ids = np.array([pid for _, pid in pieces])
    # each piece's neighbours in its ring, the ring closing on its first piece
    count = np.repeat(counts, counts)
    ring_start = np.repeat(np.cumsum(counts) - counts, counts)
    at_ring = np.arange(len(pieces)) - ring_start
    before = ids[ring_start + (at_ring - 1) % count]
    after = ids[ring_start + (at_ring + 1) % count]
    wanted = np.maximum(1, np.ceil(s_of - NEAREST_SLACK)).astype(np.intp)
    closed = np.array([(nodes[0] == nodes[-1]).all() for nodes in nodes_of])
    fewer = (  # wanted < edges: at least two edges
        (before == ids)
        & (after == ids)
        & ~closed
        & (s_of < NEAREST_BELOW)
        & (wanted < edges)
    )
    for k in np.flatnonzero(fewer).tolist():
        nodes, n = nodes_of[k], int(wanted[k])
        steps = np.concatenate(
            [[0.0], np.cumsum(sizes[first[k] : first[k] + edges[k]])]
        )
        at = np.interp(s_of[k] * np.arange(1, n) / n, steps, np.arange(len(nodes)))
        below = np.minimum(at.astype(np.intp), edges[k] - 1)
        t = (at - below)[:, None]
        inner = (1 - t) * nodes[below] + t * nodes[below + 1]
        out[k] = (np.vstack([nodes[:1], inner, nodes[-1:]]), pieces[k][1])
    return out


def batch_nodes(batch: BoundaryBatch) -> list[NDArray[np.float64]]:
    """Mesh a batch's curves in a Gmsh session; return each one's inner nodes.

    In piece order, each ``(m, 2)``, from the piece's first point to its last
    (neither included).

    Raises
    ------
    MeshingError
        If Gmsh fails.
    """
    with gmsh_session() as gmsh:
        try:
            set_options(gmsh, threads=1, seed=0, algorithm="frontal-delaunay")
            curves = _add_curves(gmsh, batch.runs)
            xy = np.concatenate([p for p, _, _ in curves])
            bounds = (*xy.min(axis=0), *xy.max(axis=0))
            add_size_view(gmsh, batch.size, bounds, _along(gmsh, curves, batch.size))
            gmsh.model.mesh.generate(1)
            inner = []
            for _, _, tag in curves:
                _, coords, params = gmsh.model.mesh.getNodes(1, tag)
                inner.append(coords.reshape(-1, 3)[np.argsort(params), :2])
        except Exception as exc:  # gmsh raises bare Exception with its last error
            raise MeshingError(
                f"Gmsh failed on the boundary ({batch.label}): {exc}"
            ) from exc
    return inner


def _batches(
    by_ring: list[list[tuple[NDArray[np.float64], int]]], size: Any
) -> list[BoundaryBatch]:
    """Split the rings' pieces into :data:`BATCHES` batches, or one if few.

    One batch for at most :data:`BATCH_CURVES` pieces. The pieces in order,
    cut where their running count of points passes each equal share; a ring
    cut between batches is a run in each.
    """
    where = [(r, k) for r, pieces in enumerate(by_ring) for k in range(len(pieces))]
    count = BATCHES if len(where) > BATCH_CURVES else 1
    points = np.cumsum([len(by_ring[r][k][0]) for r, k in where])
    cuts = np.searchsorted(points, points[-1] * np.arange(1, count) / count)
    edges = np.unique(np.concatenate([[0], cuts, [len(where)]]))
    batches = []
    for a, b in itertools.pairwise(edges):
        runs: list[tuple[int, list[tuple[NDArray[np.float64], int]]]] = []
        for r, k in where[a:b]:
            if runs and runs[-1][0] == r:
                runs[-1][1].append(by_ring[r][k])
            else:
                runs.append((r, [by_ring[r][k]]))
        batches.append(
            BoundaryBatch(
                runs=tuple(
                    (tuple(pieces), len(pieces) == len(by_ring[r]))
                    for r, pieces in runs
                ),
                size=size,
                expected=float(points[b - 1] - (points[a - 1] if a else 0)),
                label=f"curves {a + 1} to {b} of {len(where)}",
            )
        )
    return batches


def _along(
    gmsh: Any, curves: list[tuple[NDArray[np.float64], int, int]], size: Any
) -> NDArray[np.float64] | None:
    """Points along the curves, a quarter of a size-grid cell apart; or None.

    Gmsh's 1-D mesher asks for sizes on the curves only, so the size view
    needs only the grid cells along them (:func:`add_size_view` with these
    points): on the NW-shelf fine case 34,920 cells of its 839,004, and the
    same boundary nodes. A spline through ``n`` points takes them at
    the parameters ``k / (n - 1)``; each span is sampled at steps of at most a
    quarter cell along its chord (on the sphere, of the cell's shorter side
    in the plane at the span's ends; a span is shorter than a cell there).
    None (the whole grid) if that takes more points than the grid has
    cells, or if Gmsh's spline does not pass its points at those parameters.
    """
    spans = np.array([len(piece) - 1 for piece, _, _ in curves])
    ends = np.cumsum(spans)
    # every span of every curve at once: its chord, its samples, their parameters
    points = np.concatenate([piece for piece, _, _ in curves])
    at = np.delete(np.arange(len(points) - 1), np.cumsum(spans + 1)[:-1] - 1)
    step: float | NDArray[np.float64]  # one for the plane, one per span on the sphere
    if isinstance(size, SizeGrid) and min(len(size.x), len(size.y)) >= 2:
        step = 0.25 * min(np.min(np.diff(size.x)), np.min(np.diff(size.y)))
    elif isinstance(size, SphereSizeGrid):
        cell = size.plane_cell(points)
        step = 0.25 * np.minimum(cell[at], cell[at + 1])
    else:
        return None
    chords = np.hypot(*(points[at + 1] - points[at]).T)
    steps = np.maximum(np.ceil(chords / step), 1).astype(np.int64)
    if steps.sum() > _size_cells(size):  # more samples than cells: nothing saved
        return None
    first = np.cumsum(steps) - steps  # each span's first sample
    owner = np.searchsorted(ends, np.arange(len(at)), side="right")  # its curve
    span = np.repeat(np.arange(len(at)), steps)
    within = np.arange(len(span)) - first[span]
    local = span - (ends - spans)[owner[span]]  # the span's number in its curve
    t = (local + within / steps[span]) / spans[owner[span]]
    cut = np.cumsum(steps)[ends - 1]
    out = []
    for (_, _, tag), params in zip(curves, np.split(t, cut[:-1]), strict=True):
        xy = np.asarray(gmsh.model.getValue(1, tag, np.append(params, 1.0)))
        out.append(xy.reshape(-1, 3)[:, :2])
    along = np.concatenate(out)
    # each span's first sample and each curve's last must be its points
    # (each curve ends with one sample more: its parameter 1)
    knots = along[np.concatenate([first + owner, cut + np.arange(len(cut))])]
    expected = points[np.concatenate([at, np.cumsum(spans + 1) - 1])]
    if not np.allclose(knots, expected, rtol=0.0, atol=1e-3 * np.min(step)):
        return None
    return along


def _size_cells(size: Any) -> int:
    """Return how many cells a size grid (in the plane or on the sphere) has."""
    grid = size if isinstance(size, SizeGrid) else size.grid
    return int(grid.values.size)


def _ring_pieces(
    rings: list[list[list[NDArray[np.float64]]]], ids: list[list[int]]
) -> list[list[tuple[NDArray[np.float64], int]]]:
    """Return each ring's pieces, chunked, with their ids."""
    return [
        chunked(
            [(p, pid) for seg, pid in zip(ring, ring_ids, strict=True) for p in seg]
        )
        for ring, ring_ids in zip(rings, ids, strict=True)
    ]


def _add_curves(
    gmsh: Any,
    runs: tuple[tuple[tuple[tuple[NDArray[np.float64], int], ...], bool], ...],
) -> list[tuple[NDArray[np.float64], int, int]]:
    """Add each run's pieces as Gmsh splines; return (piece, id, curve tag).

    The pieces of a run share their end points; those of a whole ring close
    on its first point.
    """
    geo = gmsh.model.geo
    out = []
    for pieces, whole in runs:
        first = geo.addPoint(*pieces[0][0][0], 0.0)
        start = first
        for k, (piece, pid) in enumerate(pieces):
            inner = [geo.addPoint(x, y, 0.0) for x, y in piece[1:-1]]
            last = whole and k == len(pieces) - 1
            end = first if last else geo.addPoint(*piece[-1], 0.0)
            tags = [start, *inner, end]
            curve = geo.addLine(*tags) if len(tags) == 2 else geo.addSpline(tags)
            out.append((np.asarray(piece, dtype=np.float64), pid, curve))
            start = end
    geo.synchronize()
    return out


def chunked(
    pieces: list[tuple[NDArray[np.float64], int]], most: int = CURVE_POINTS
) -> list[tuple[NDArray[np.float64], int]]:
    """Split (piece, id) pairs of more than ``most`` points; ends are shared.

    Made for Gmsh's threads (one spline through thousands of points is one
    long serial job: in chunks, the NW-shelf intermediate boundary took 1.1 s
    on 2 threads instead of 2.8 s on one). The boundary is meshed on one
    thread now (:func:`boundary_nodes`); the chunks stay, as the splines they
    make decide where the nodes go.

    Examples
    --------
    >>> [len(p) for p, _ in chunked([(np.zeros((1201, 2)), 3)], most=500)]
    [401, 401, 401]
    """
    out = []
    for piece, pid in pieces:
        n = int(np.ceil((len(piece) - 1) / (most - 1)))
        if n <= 1:
            out.append((piece, pid))
            continue
        cuts = np.linspace(0, len(piece) - 1, n + 1).round().astype(int)
        out += [(piece[a : b + 1], pid) for a, b in itertools.pairwise(cuts)]
    return out
