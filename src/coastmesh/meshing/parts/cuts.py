"""Domain decomposition: cut the water into parts of about equal meshing cost.

:func:`cut_lines` chooses straight cuts through the sea;
:func:`~coastmesh.meshing.parts.faces.split_faces` nodes the boundary with them
and returns the faces of water as loops of shared curves, and
:mod:`~coastmesh.meshing.parts.tasks` meshes each face alone, with the cuts'
nodes fixed once for both sides, so the meshes conform with no stitching.

**How the cuts are chosen.** The cost of a region is its expected triangle
count, the integral over its water of the triangle density ``4 / (sqrt(3)
h^2)`` of an equilateral mesh of size ``h`` (:func:`expected_triangles`). A
region is cut across its longer side, in recursive bisection: ``K`` parts take
``floor(K / 2)`` and ``ceil(K / 2)`` parts on either side, so the cut sits at
that quantile of the cost. Among 9 positions within 3 % of cost of it, the cut
whose water crossing has the fewest target edges (``integral of 1 / h`` along
it) wins: cuts go where the size is coarse and the water narrow, and keep off
the fine coast. A cut must be clean where it crosses the water, every time
it does: if none of the 9 is, 41 positions within 15 % are tried, then the
same across the shorter side, then the same at the oblique angles of
:data:`_OBLIQUE` (the diagonals first). The first direction with a clean cut
wins, so a region cut across x or y is cut as before oblique cuts were
tried. A region is convex: a box, or a box cut by oblique cuts, and its
halves are its parts on either side of the cut. A crossing makes thin
triangles when it is under two target edges long, comes nearer the coast or
an earlier cut than ``sin(35 deg) min(s, 2 h)`` at a distance ``s >= 2 h``
from its end (it meets the coast at under 35 degrees, or runs along it; nearer
its end, the coast's roughness below the size is noise), or ends
within half an edge of the end of a boundary curve or within an edge of
another cut's end. A region holding under twice :data:`MIN_PART_TRIANGLES` is
not cut. A part left holding over :data:`OVERSIZE` times its share (the
water's cost over ``K``), where only a cut off balance was clean, is cut in
two as a region would be, until it is not. Nothing is random: the same
water, grid and ``K`` give the same cuts.

**Where no line across a region is clean**, its faces of water are cut one
by one (:func:`_cut_face`), each by a line that need be clean only where it
crosses that face (its crossings of other faces are not cut), tried as
above; and where no line is clean even there, along the first line that
splits the face at its clean crossings only, leaving the water joined at the
others (:mod:`~coastmesh.meshing.parts.partial`): its largest face may hold
at most :data:`_WIDER` more than the larger side of a balanced cut. The
faces a cut makes share the face's parts by their expected triangles
(largest remainders), and are cut alone in turn, down to :data:`OVERSIZE`.
In a face, a crossing that would cut off a piece of under
:data:`MIN_PART_TRIANGLES` is not cut, so it makes no face of a few
triangles. (``world_fine.toml``, 32 parts wanted: a line across the world
ocean crosses it 10 to 60 times, and none of the 400 tried is clean at every
one, so the world was one part; now 46, the largest 1.32 shares, planned in
about 25 s.) A region is cut by lines spanning it as before wherever one is
clean, so such cases cut as before (``world.toml``, the NW-shelf fine case).
A part left over :data:`OVERSIZE` shares all the same is named, with why,
in the parts report (:func:`~coastmesh.meshing.parts.report.oversize_parts`).
"""

from __future__ import annotations

from typing import Any, NamedTuple, cast

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.geometry.cells import points_inside
from coastmesh.meshing.parts.crossings import (
    PENALTY,
    Coast,
    Turned,
    chord_edges,
    coast_tree,
    edges_across,
)
from coastmesh.meshing.parts.partial import cells_of, faces_of, split_costs
from coastmesh.types import SizeGrid

__all__ = [
    "MIN_PART_TRIANGLES",
    "OVERSIZE",
    "TRIANGLES_PER_PART",
    "CutPlan",
    "WaterCells",
    "auto_parts",
    "cut_lines",
    "expected_triangles",
    "plan_cuts",
    "water_cells",
]

#: Triangles per unit area of an equilateral mesh of edge h: 4 / (sqrt(3) h^2).
_DENSITY = 4.0 / np.sqrt(3.0)
#: ``parts = "auto"``: the power of two nearest (by ratio) the expected
#: triangles over this, from 1 to :data:`MAX_AUTO_PARTS`: a part is planned
#: to hold 141,000 to 283,000. It depends on the case only, never on the
#: machine, so a case gives the same mesh on any number of cores. Every cut
#: leaves a band a few elements wide where Gmsh's triangles are a little
#: worse; the NW-shelf fine case (3.1 M expected triangles, oblique cuts) had
#: a 1st-percentile angle of 44.92 deg in one part, 44.41 in 8 wanted parts
#: (14 faces), 44.03 in 16 (32) and 43.70 in 64 (93), so a part holds about
#: 200,000 (the issue's bound is 1 deg below one part). Rounded down instead,
#: a part held up to 400,000, which Gmsh meshes slower per triangle, and the
#: largest was left alone at the end: world.toml (1.40 M expected) in 4
#: wanted parts took 124.8 s on 1 worker and 73.7 on 2, in 8 117.6 and 68.4,
#: 1st-percentile angle 44.77 and 44.74 deg.
TRIANGLES_PER_PART = 200_000
MAX_AUTO_PARTS = 64
#: A region is not cut into parts of fewer expected triangles than this, so
#: fewer than ``parts`` parts may be made. (Forced to 64 parts, the NW-shelf
#: intermediate mesh, 141,000 triangles, got faces a few elements wide in the
#: coarse North Sea, and triangles with a radius ratio of 0.16.)
MIN_PART_TRIANGLES = 10_000
#: A part still holding more than this many times its share (the water's
#: expected triangles over ``parts``) when the bisection gives it no more cuts
#: is cut in two, again and again while it can be. A cut off balance (no clean
#: cut near the balanced one) leaves one side large: on the NW-shelf fine case
#: (8 wanted) the region meant for two parts around the Pentland Firth, 1.05 M
#: expected triangles, was cut 39 / 61 % and its larger side of 640,000 (1.63
#: shares) meshed alone for a quarter of the Gmsh time: no number of cores
#: could mesh the case in under that part's time. Gmsh's time per triangle
#: grows with the part, too (48 us at 79,000 triangles, 78 at 635,000).
OVERSIZE = 1.5
#: Candidate cut positions tried around the balanced one, and their spread
#: (a fraction of the region's cost on either side).
_CANDIDATES = 9
_SPREAD = 0.03
#: Where every one of those would make thin triangles, positions this far off
#: are tried too (a less even split beats a bad triangle).
_WIDER_CANDIDATES = 41
_WIDER = 0.15
#: Where no cut across x or y is clean, cuts whose normals make these angles
#: (degrees) with the x axis are tried, in this order: the diagonals first.
#: (On the NW-shelf fine case no cut of either half across x or y is clean,
#: and 8 wanted parts were 2; with these, 14 faces; 16 with :data:`OVERSIZE`.)
_OBLIQUE = (45.0, 135.0, 30.0, 60.0, 120.0, 150.0)


class WaterCells(NamedTuple):
    """The size grid's nodes in the water, and the expected triangles of each.

    What :func:`water_cells` returns; :func:`auto_parts` and :func:`plan_cuts`
    take it so that the engine finds the nodes once (0.4 s on world.toml).
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    weight: NDArray[np.float64]


def water_cells(
    polygon: shapely.Polygon, grid: SizeGrid, threads: int = 1
) -> WaterCells:
    """Return the grid nodes inside ``polygon`` and the triangles each stands for.

    Parameters
    ----------
    polygon : shapely.Polygon
        The water, in the grid's coordinates (metres).
    grid : SizeGrid or SphereSizeGrid
        Target sizes; on a sphere grid each node's area is measured on the sphere.
    threads : int, default 1
        Threads that find the nodes in the water.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 1001, 10), np.arange(0.0, 1001, 10),
    ...              np.full((101, 101), 100.0))
    >>> cells = water_cells(shapely.box(0, 0, 1000, 1000), g)
    >>> len(cells.x), round(float(cells.weight.sum()))  # 99 x 99 inside
    (9801, 226)
    """
    if not isinstance(grid, SizeGrid):  # a SphereSizeGrid: areas on the sphere
        x, y, weight = grid.cells(polygon, threads)
        return WaterCells(x, y, _DENSITY * weight)
    gx, gy = np.meshgrid(grid.x, grid.y)
    inside = points_inside(polygon, gx, gy, threads)
    cell = abs(grid.x[1] - grid.x[0]) * abs(grid.y[1] - grid.y[0])
    weight = _DENSITY * cell / grid.values[inside] ** 2
    return WaterCells(gx[inside], gy[inside], weight)


def expected_triangles(
    polygon: shapely.Polygon, grid: SizeGrid, threads: int = 1
) -> float:
    """Return the expected triangle count of ``polygon`` meshed at ``grid``.

    Parameters
    ----------
    polygon : shapely.Polygon
        The water, in the grid's coordinates (metres).
    grid : SizeGrid
        Target sizes, metres, at least 2 x 2 nodes.
    threads : int, default 1
        Threads that find the grid nodes in the water.

    Returns
    -------
    float
        The integral of ``4 / (sqrt(3) h^2)`` over the grid nodes inside.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 1001, 10), np.arange(0.0, 1001, 10),
    ...              np.full((101, 101), 100.0))
    >>> round(expected_triangles(shapely.box(0, 0, 1000, 1000), g))  # 99 x 99 inside
    226
    """
    return float(water_cells(polygon, grid, threads).weight.sum())


def auto_parts(
    polygon: shapely.Polygon,
    grid: SizeGrid,
    threads: int = 1,
    *,
    cells: WaterCells | None = None,
) -> int:
    """Return the number of parts ``parts = "auto"`` means for this water.

    ``cells``, if given, are :func:`water_cells` of ``polygon`` and ``grid``,
    found already.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 100_001, 500), np.arange(0.0, 100_001, 500),
    ...              np.full((201, 201), 100.0))
    >>> auto_parts(shapely.box(0, 0, 100_000, 100_000), g)  # 2,286,365 triangles
    16
    """
    if cells is None:
        cells = water_cells(polygon, grid, threads)
    n = float(cells.weight.sum()) / TRIANGLES_PER_PART
    power = int(np.floor(np.log2(max(n, 1.0)) + 0.5))  # the nearest, by ratio
    return int(min(2**power, MAX_AUTO_PARTS))


class CutPlan(NamedTuple):
    """The cuts of :func:`plan_cuts`, and how many cuts asked for were not made."""

    cuts: list[shapely.LineString]
    missed: int


def plan_cuts(
    polygon: shapely.Polygon,
    grid: SizeGrid,
    parts: int,
    *,
    ends: NDArray[np.float64] | None = None,
    threads: int = 1,
    cells: WaterCells | None = None,
) -> CutPlan:
    """Return straight cuts that split the water into ``parts`` of equal cost.

    :func:`cut_lines` returns the same cuts; this also counts the cuts asked
    for that were not made.

    Parameters
    ----------
    polygon : shapely.Polygon
        The water, in the grid's coordinates.
    grid : SizeGrid
        Target sizes there.
    parts : int
        The number of parts wanted, >= 1.
    ends : ndarray of shape (k, 2), optional
        Points of the boundary a cut should not end within half a target edge
        of: the ends of its curves (a cut there leaves a sliver of curve).
    threads : int, default 1
        Threads that find the grid nodes in the water (the cuts are the same).
    cells : WaterCells, optional
        :func:`water_cells` of ``polygon`` and ``grid``, if found already.

    Returns
    -------
    CutPlan
        ``cuts``: ``parts - 1`` segments (fewer where a region holds under twice
        :data:`MIN_PART_TRIANGLES` expected triangles or has no cut;
        more where a part would hold over :data:`OVERSIZE` shares),
        each spanning the region it cuts (a convex region of the recursive
        bisection), or, where a face of water is cut alone, one of its
        crossings of that face;
        later cuts end on earlier ones. A cut may cross the water several
        times: each crossing is a shared curve. ``missed``: how many of the
        ``parts - 1`` cuts asked for were not made (a cut made again to split
        a part over :data:`OVERSIZE` shares does not stand in for one).

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 2001, 20), np.arange(0.0, 1001, 20),
    ...              np.full((51, 101), 5.0))  # 180,000 triangles
    >>> plan = plan_cuts(shapely.box(0, 0, 2000, 1000), g, 2)
    >>> [c.bounds for c in plan.cuts], plan.missed
    ([(1010.0, 0.0, 1010.0, 1000.0)], 0)
    >>> plan = plan_cuts(shapely.box(0, 0, 2000, 1000), g, 40)  # 4,500 each
    >>> len(plan.cuts), plan.missed  # 16 parts of 11,250: each over 10,000
    (15, 24)
    """
    if isinstance(parts, bool) or not isinstance(parts, int | np.integer) or parts < 1:
        raise ValueError(f"parts is {parts!r}; expected an integer >= 1")
    x, y, w = water_cells(polygon, grid, threads) if cells is None else cells
    cuts: list[shapely.LineString] = []
    coast: Coast = (
        coast_tree(polygon),
        (
            None
            if ends is None or not len(ends)
            else shapely.STRtree(shapely.points(ends))
        ),
        [],  # the ends of the cuts chosen so far
        [],  # and their crossings of the water
    )
    limit = OVERSIZE * float(w.sum()) / int(parts)
    region = shapely.box(*polygon.bounds)
    missed: list[int] = []
    _bisect(polygon, grid, coast, region, (x, y, w), (int(parts), limit), cuts, missed)
    return CutPlan(cuts, sum(missed))


def cut_lines(
    polygon: shapely.Polygon,
    grid: SizeGrid,
    parts: int,
    *,
    ends: NDArray[np.float64] | None = None,
) -> list[shapely.LineString]:
    """Return straight cuts that split the water into ``parts`` of equal cost.

    The cuts of :func:`plan_cuts`, which documents the arguments.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 2001, 20), np.arange(0.0, 1001, 20),
    ...              np.full((51, 101), 5.0))  # 180,000 triangles
    >>> [c.bounds for c in cut_lines(shapely.box(0, 0, 2000, 1000), g, 2)]
    [(1010.0, 0.0, 1010.0, 1000.0)]
    """
    return plan_cuts(polygon, grid, parts, ends=ends).cuts


def _bisect(
    polygon: shapely.Polygon,
    grid: SizeGrid,
    coast: Coast,
    region: shapely.Polygon,
    cells: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    aim: tuple[int, float],
    cuts: list[shapely.LineString],
    missed: list[int],
) -> None:
    """Cut ``region`` (convex: a box, or a box cut by oblique cuts) and recurse.

    ``cells`` are the grid nodes in its water and their expected triangles;
    ``aim`` the parts wanted of it and the :data:`OVERSIZE` limit of a part.
    The cuts are appended to ``cuts``; the number of the region's wanted
    cuts not made, if it is not cut, to ``missed``. A region with no clean
    cut has its faces cut one by one (:func:`_cut_face`).
    """
    x, y, w = cells
    parts, limit = aim
    asked = max(parts - 1, 0)  # cuts wanted here; not the one more for OVERSIZE
    if not _worth_cutting(parts, w, limit):
        missed.append(asked)  # a part must be many elements across, or its
        return  # cuts make slivers
    parts = max(parts, 2)  # one part, too large: cut once more
    x0, y0, x1, y1 = region.bounds
    # the water in the region only: each level works on less geometry
    clipped = shapely.clip_by_rect(polygon, x0, y0, x1, y1)
    if not _is_box(region):
        clipped = shapely.intersection(clipped, region)
    pieces = [g for g in shapely.get_parts(clipped) if g.geom_type == "Polygon"]
    if not pieces:
        missed.append(asked)
        return
    polygon = pieces[0] if len(pieces) == 1 else shapely.MultiPolygon(pieces)
    share = (parts // 2) / parts
    longer_x = (x1 - x0) >= (y1 - y0)  # cut across the longer side first
    for direction in _directions(longer_x):
        score, line, chosen, at = _best_cut(
            polygon, grid, coast, region, x, y, w, share, direction
        )
        if score < PENALTY:
            break
    else:  # no clean cut across the region: its faces one by one
        _cut_faces(pieces, grid, coast, cells, aim, cuts, missed, tried=True)
        return
    cuts.append(line)
    coast[2].extend(c for g in chosen for c in np.asarray(g.coords)[[0, -1]])
    coast[3].extend(chosen)
    low = _along(x, y, direction) < at
    for below, side, n in ((True, low, parts // 2), (False, ~low, parts - parts // 2)):
        half = _half(region, direction, at, below=below)
        cells = (x[side], y[side], w[side])
        _bisect(polygon, grid, coast, half, cells, (n, limit), cuts, missed)


def _worth_cutting(parts: int, w: NDArray[np.float64], limit: float) -> bool:
    """Whether water of these expected triangles is cut (in two, if one part)."""
    if parts < 2 and w.sum() <= limit:
        return False  # one part, not too large
    return len(w) >= 2 and w.sum() >= 2 * MIN_PART_TRIANGLES


def _cut_faces(
    faces: list[shapely.Polygon],
    grid: SizeGrid,
    coast: Coast,
    cells: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    aim: tuple[int, float],
    cuts: list[shapely.LineString],
    missed: list[int],
    *,
    tried: bool = False,
    labels: NDArray[np.int64] | None = None,
) -> None:
    """Cut each face alone (:func:`_cut_face`), the parts wanted shared by cost.

    ``tried``: the faces are a region's water that no line across the
    region cuts cleanly, so one face alone has no clean cut either.
    ``labels``: each cell's face, if found already.
    """
    parts, limit = aim
    x, y, w = cells
    if labels is None:
        labels = cells_of(faces, x, y)
    # weighted, bincount gives float64 (numpy's stub says intp either way)
    costs = cast("NDArray[np.float64]", np.bincount(labels, w, minlength=len(faces)))
    shares = _allocate(parts, costs)
    for k, face in enumerate(faces):
        side = labels == k
        _cut_face(
            face,
            grid,
            coast,
            (x[side], y[side], w[side]),
            (shares[k], limit),
            cuts,
            missed,
            tried=tried and len(faces) == 1,
        )


def _cut_face(
    face: shapely.Polygon,
    grid: SizeGrid,
    coast: Coast,
    cells: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    aim: tuple[int, float],
    cuts: list[shapely.LineString],
    missed: list[int],
    tried: bool = False,
) -> None:
    """Cut one face of water by a line, where it crosses that face only; recurse.

    The line is the first clean cut :func:`_best_cut` finds across the face
    (in :func:`_directions`' order), else the first that splits it at its
    clean crossings only (:func:`_partial_cut`). A crossing that cuts off a
    piece of under :data:`MIN_PART_TRIANGLES` is not cut
    (:func:`~coastmesh.meshing.parts.partial.split_costs`). The faces it
    makes share the parts wanted by their expected triangles, and are cut
    alone in turn. ``tried``: no clean cut across it exists.
    """
    x, y, w = cells
    parts, limit = aim
    asked = max(parts - 1, 0)
    if not _worth_cutting(parts, w, limit):
        missed.append(asked)
        return
    split = max(parts, 2)
    share = (split // 2) / split
    most = (1.0 - share + _WIDER) * float(w.sum())
    region = shapely.box(*face.bounds)
    x0, y0, x1, y1 = face.bounds
    kept: list[shapely.LineString] = []
    for direction in [] if tried else _directions((x1 - x0) >= (y1 - y0)):
        score, _, chosen, at = _best_cut(
            face, grid, coast, region, x, y, w, share, direction
        )
        if score < PENALTY:
            costs = split_costs(
                face,
                Turned(face, direction),
                at,
                cells,
                chosen,
                [True] * len(chosen),
                MIN_PART_TRIANGLES,
            )
            if costs.kept and len(costs.costs) > 1 and costs.costs[0] <= most:
                kept = [chosen[k] for k in costs.kept]
                break
    if not kept:
        kept = _partial_cut(face, grid, coast, cells, share, most)
    faces = faces_of(face, kept) if kept else []
    labels = cells_of(faces, x, y)
    if len(faces) < 2 or np.bincount(labels, w).max() >= w.sum():
        missed.append(asked)  # no cut, or none that splits it
        return
    cuts.extend(kept)
    coast[2].extend(c for g in kept for c in np.asarray(g.coords)[[0, -1]])
    coast[3].extend(kept)
    _cut_faces(faces, grid, coast, cells, aim, cuts, missed, labels=labels)


def _allocate(parts: int, costs: NDArray[np.float64]) -> list[int]:
    """Share ``parts`` among faces by their ``costs``: largest remainders.

    Examples
    --------
    >>> _allocate(32, np.array([49.8, 45.0, 5.2]))
    [16, 14, 2]
    """
    exact = parts * costs / max(float(costs.sum()), 1e-300)
    whole = np.floor(exact).astype(int)
    rest = parts - int(whole.sum())
    order = np.argsort(-(exact - whole), kind="stable")
    whole[order[:rest]] += 1
    return [int(n) for n in whole]


def _partial_cut(
    face: shapely.Polygon,
    grid: SizeGrid,
    coast: Coast,
    cells: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    share: float,
    most: float,
) -> list[shapely.LineString]:
    """Return the clean crossings of the first line that splits ``face`` well.

    The lines are those :func:`_best_cut` tries, in its order; each is cut
    where it crosses the face cleanly and left uncut elsewhere
    (:func:`~coastmesh.meshing.parts.partial.split_costs`). The first whose
    largest face holds at most ``most`` expected triangles wins. None
    splits it: an empty list.
    """
    x, y, w = cells
    region = shapely.box(*face.bounds)
    x0, y0, x1, y1 = face.bounds
    for direction in _directions((x1 - x0) >= (y1 - y0)):
        turned = Turned(face, direction)
        places = _places(grid, x, y, w, share, direction)
        for at in places(_SPREAD, _CANDIDATES) + places(_WIDER, _WIDER_CANDIDATES):
            line = _line(region, direction, at)
            if line.is_empty:
                continue
            chords = turned.chords(line)
            clean = [chord_edges(grid, coast, c)[1] for c in chords]
            split = split_costs(
                face, turned, at, cells, chords, clean, MIN_PART_TRIANGLES
            )
            if split.kept and len(split.costs) > 1 and split.costs[0] <= most:
                return [chords[k] for k in split.kept]
    return []


def _directions(longer_x: bool) -> list[tuple[float, float]]:
    """Return the normals ``(cos, sin)`` of the cuts to try, in order.

    Across the longer side, then the shorter (exact axes: such a cut of a box
    leaves boxes), then the oblique :data:`_OBLIQUE` directions.
    """
    axes = [(1.0, 0.0), (0.0, 1.0)]
    oblique = [(np.cos(np.radians(a)), np.sin(np.radians(a))) for a in _OBLIQUE]
    return (axes if longer_x else axes[::-1]) + oblique


def _along(
    x: NDArray[np.float64], y: NDArray[np.float64], direction: tuple[float, float]
) -> NDArray[np.float64]:
    """Coordinates along the normal ``direction``: exactly x or y on the axes."""
    c, s = direction
    if s == 0.0:
        return x
    if c == 0.0:
        return y
    return x * c + y * s


def _is_box(region: shapely.Polygon) -> bool:
    x0, y0, x1, y1 = region.bounds
    return bool(region.area >= (1 - 1e-12) * (x1 - x0) * (y1 - y0))


def _half(
    region: shapely.Polygon, direction: tuple[float, float], at: float, below: bool
) -> shapely.Polygon:
    """Return the part of ``region`` below ``at`` along ``direction`` (or above).

    A box cut along an axis gives the exact box.
    """
    c, s = direction
    x0, y0, x1, y1 = region.bounds
    if (s == 0.0 or c == 0.0) and _is_box(region):
        if s == 0.0:
            return shapely.box(x0, y0, at, y1) if below else shapely.box(at, y0, x1, y1)
        return shapely.box(x0, y0, x1, at) if below else shapely.box(x0, at, x1, y1)
    normal, tangent, base, far = _frame(region, direction, at)
    toward = -normal if below else normal
    plane = shapely.Polygon(
        [base - far * tangent, base + far * tangent,
         base + far * tangent + far * toward, base - far * tangent + far * toward]
    )  # fmt: skip
    return shapely.intersection(region, plane)


def _line(
    region: shapely.Polygon, direction: tuple[float, float], at: float
) -> shapely.LineString:
    """Return the chord of the convex ``region`` at ``at`` along ``direction``."""
    c, s = direction
    x0, y0, x1, y1 = region.bounds
    if (s == 0.0 or c == 0.0) and _is_box(region):
        if s == 0.0:
            return shapely.LineString([(at, y0), (at, y1)])
        return shapely.LineString([(x0, at), (x1, at)])
    _, tangent, base, far = _frame(region, direction, at)
    long = shapely.LineString([base - far * tangent, base + far * tangent])
    chord = shapely.intersection(region, long)
    return chord if chord.geom_type == "LineString" else shapely.LineString()


def _frame(
    region: shapely.Polygon, direction: tuple[float, float], at: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float]:
    """Return a cut's normal, tangent, base point and reach across ``region``.

    The base is the point of the line nearest the region's centre, and the
    reach takes a segment from it past the region. The base is not
    ``normal * at``: in a projected CRS far from its origin (a UTM northing of
    6,000 km) that point may lie farther from the region than any multiple of
    its size.
    """
    c, s = direction
    normal, tangent = np.array([c, s]), np.array([-s, c])
    x0, y0, x1, y1 = region.bounds
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    base = centre + (at - float(centre @ normal)) * normal
    far = (
        2.0 * float(np.hypot(x1 - x0, y1 - y0))
        + 2.0 * abs(at - float(centre @ normal))
        + 1.0
    )
    return normal, tangent, base, far


def _past_node(
    grid: SizeGrid, direction: tuple[float, float], along: NDArray[np.float64]
) -> Any:
    """Return ``k -> place`` of a cut just past the ``k``-th node along ``direction``.

    On a plane grid: half a cell past the node. On the world grid
    (:class:`~coastmesh.meshing.gmsh.SphereSizeGrid`) the nodes are not
    evenly spaced in the plane: half-way to the next node along the
    direction (``along`` sorted), or past the last by the last gap.
    """
    if isinstance(grid, SizeGrid):
        c, s = direction
        dx, dy = (abs(float(np.diff(g)[0])) for g in (grid.x, grid.y))
        spacing = dx if s == 0.0 else dy if c == 0.0 else min(dx, dy)
        return lambda k: float(along[k]) + 0.5 * spacing
    gaps = np.diff(along)
    step = np.append(gaps, gaps[-1] if len(gaps) else 1.0)

    def place(k: int) -> float:
        # the next node farther along (nodes may share a place along)
        j = int(np.searchsorted(along, along[k], side="right"))
        if j < len(along):
            return 0.5 * float(along[k] + along[j])
        return float(along[k]) + 0.5 * float(max(step[k], 1.0))

    return place


def _places(
    grid: SizeGrid,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    w: NDArray[np.float64],
    share: float,
    direction: tuple[float, float],
) -> Any:
    """Return ``(spread, count) -> places``: cuts normal to ``direction``.

    ``count`` places at the cost quantiles within ``spread`` of ``share``,
    the most balanced first; no grid node lies on one.
    """
    along = _along(x, y, direction)
    order = np.argsort(along, kind="stable")
    past = _past_node(grid, direction, along[order])
    cum = np.cumsum(w[order]) / w.sum()

    def places(spread: float, count: int) -> list[float]:
        tried = np.linspace(share - spread, share + spread, count)
        return [
            past(min(int(np.searchsorted(cum, q)), len(order) - 1))
            for q in sorted(tried, key=lambda q: abs(q - share))  # ties: balanced
        ]

    return places


def _best_cut(
    polygon: shapely.Polygon | shapely.MultiPolygon,
    grid: SizeGrid,
    coast: Coast,
    region: shapely.Polygon,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    w: NDArray[np.float64],
    share: float,
    direction: tuple[float, float],
) -> tuple[float, shapely.LineString, list[shapely.LineString], float]:
    """Return the best cut normal to ``direction``: score, line, crossings, place."""
    places = _places(grid, x, y, w, share, direction)
    turned = Turned(polygon, direction)
    best: tuple[float, shapely.LineString, list[shapely.LineString], float] = (
        np.inf,
        shapely.LineString(),
        [],
        0.0,
    )
    for spread, count in ((_SPREAD, _CANDIDATES), (_WIDER, _WIDER_CANDIDATES)):
        if best[0] < PENALTY:
            break  # a clean cut within the first spread: no need to look wider
        for at in places(spread, count):
            line = _line(region, direction, at)
            if line.is_empty:
                continue
            score, chords = edges_across(grid, coast, turned.chords(line))
            if score < best[0]:
                best = (score, line, chords, at)
    return best
