"""Domain decomposition: cut the water into parts of about equal meshing cost.

Gmsh meshes separate plane surfaces of one model on separate threads
(``General.NumThreads``), and a curve two surfaces share is meshed once, so
their meshes conform with no stitching. :func:`cut_lines` chooses straight cuts
through the sea; :func:`split_faces` nodes the boundary with them and returns
the faces of water as loops of shared curves, ready for Gmsh.

**How the cuts are chosen.** The cost of a region is its expected triangle
count, the integral over its water of the triangle density ``4 / (sqrt(3)
h^2)`` of an equilateral mesh of size ``h`` (:func:`expected_triangles`). A
region is cut across its longer side, in recursive bisection: ``K`` parts take
``floor(K / 2)`` and ``ceil(K / 2)`` parts on either side, so the cut sits at
that quantile of the cost. Among 9 positions within 3 % of cost of it, the cut
whose water crossing has the fewest target edges (``integral of 1 / h`` along
it) wins: cuts go where the size is coarse and the water narrow, and keep off
the fine coast. A crossing that meets the coast at under 50 degrees, or is
under two target edges long, would make a bad triangle at its end: it counts
as a million edges, so another position wins wherever one can. Nothing is
random: the same water, grid and ``K`` give the same cuts.

The noding (``shapely.node``) and the faces (``shapely.polygonize``) are GEOS;
what is written here is the bookkeeping from faces to loops of signed curves.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.types import SizeGrid

__all__ = [
    "TRIANGLES_PER_PART",
    "Faces",
    "add_faces",
    "auto_parts",
    "chunked",
    "cut_lines",
    "expected_triangles",
    "ring_pieces",
    "split_faces",
]

#: Triangles per unit area of an equilateral mesh of edge h: 4 / (sqrt(3) h^2).
_DENSITY = 4.0 / np.sqrt(3.0)
#: ``parts = "auto"``: the largest power of two at most the expected triangles
#: over this, from 1 to :data:`MAX_AUTO_PARTS`. It depends on the case only,
#: never on the machine, so a case gives the same mesh on any number of cores.
TRIANGLES_PER_PART = 40_000
MAX_AUTO_PARTS = 64
#: The most points of one Gmsh spline (:func:`chunked`).
CURVE_POINTS = 500
#: Candidate cut positions tried around the balanced one, and their spread
#: (a fraction of the region's cost on either side).
_CANDIDATES = 9
_SPREAD = 0.03
#: A cut crossing the coast at a smaller angle (degrees), or crossing water
#: under two target edges wide, is penalised by this many edges.
_MIN_CROSSING = 50.0
_PENALTY = 1e6


def _cells(
    polygon: shapely.Polygon, grid: SizeGrid
) -> tuple[NDArray, NDArray, NDArray]:
    """Grid nodes in the water and the expected triangles each stands for."""
    gx, gy = np.meshgrid(grid.x, grid.y)
    inside = shapely.contains_xy(polygon, gx, gy)
    cell = abs(grid.x[1] - grid.x[0]) * abs(grid.y[1] - grid.y[0])
    weight = _DENSITY * cell / grid.values[inside] ** 2
    return gx[inside], gy[inside], weight


def expected_triangles(polygon: shapely.Polygon, grid: SizeGrid) -> float:
    """Return the expected triangle count of ``polygon`` meshed at ``grid``.

    Parameters
    ----------
    polygon : shapely.Polygon
        The water, in the grid's coordinates (metres).
    grid : SizeGrid
        Target sizes, metres, at least 2 x 2 nodes.

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
    return float(_cells(polygon, grid)[2].sum())


def auto_parts(polygon: shapely.Polygon, grid: SizeGrid) -> int:
    """Return the number of parts ``parts = "auto"`` means for this water.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 100_001, 500), np.arange(0.0, 100_001, 500),
    ...              np.full((201, 201), 200.0))
    >>> auto_parts(shapely.box(0, 0, 100_000, 100_000), g)  # 577,350 triangles
    8
    """
    n = expected_triangles(polygon, grid) / TRIANGLES_PER_PART
    return int(min(2 ** max(int(np.floor(np.log2(max(n, 1.0)))), 0), MAX_AUTO_PARTS))


def cut_lines(
    polygon: shapely.Polygon, grid: SizeGrid, parts: int
) -> list[shapely.LineString]:
    """Return straight cuts that split the water into ``parts`` of equal cost.

    Parameters
    ----------
    polygon : shapely.Polygon
        The water, in the grid's coordinates.
    grid : SizeGrid
        Target sizes there.
    parts : int
        The number of parts wanted, >= 1.

    Returns
    -------
    list of shapely.LineString
        ``parts - 1`` segments, each spanning the region it cuts (a region is
        a box of the recursive bisection); later cuts end on earlier ones. A
        cut may cross the water several times: each crossing is a shared curve.

    Examples
    --------
    >>> g = SizeGrid(np.arange(0.0, 2001, 20), np.arange(0.0, 1001, 20),
    ...              np.full((51, 101), 50.0))
    >>> [c.bounds for c in cut_lines(shapely.box(0, 0, 2000, 1000), g, 2)]
    [(1010.0, 0.0, 1010.0, 1000.0)]
    """
    if isinstance(parts, bool) or not isinstance(parts, int | np.integer) or parts < 1:
        raise ValueError(f"parts is {parts!r}; expected an integer >= 1")
    x, y, w = _cells(polygon, grid)
    cuts: list[shapely.LineString] = []
    _bisect(polygon, grid, shapely.box(*polygon.bounds), x, y, w, int(parts), cuts)
    return cuts


def _bisect(
    polygon: shapely.Polygon,
    grid: SizeGrid,
    region: shapely.Polygon,
    x: NDArray,
    y: NDArray,
    w: NDArray,
    parts: int,
    cuts: list[shapely.LineString],
) -> None:
    """Cut ``region`` (a box) and recurse into its two sides."""
    if parts < 2 or len(w) < 2:
        return
    x0, y0, x1, y1 = region.bounds
    across_x = (x1 - x0) >= (y1 - y0)  # cut across the longer side
    along = x if across_x else y
    spacing = abs(float(np.diff(grid.x if across_x else grid.y)[0]))
    order = np.argsort(along, kind="stable")
    cum = np.cumsum(w[order]) / w.sum()
    share = (parts // 2) / parts
    best = None
    tried = np.linspace(share - _SPREAD, share + _SPREAD, _CANDIDATES)
    for q in sorted(tried, key=lambda q: abs(q - share)):  # ties: the balanced
        k = min(int(np.searchsorted(cum, q)), len(order) - 1)
        # half a cell past a grid node: no node lies on the cut
        at = float(along[order[k]]) + 0.5 * spacing
        if across_x:
            line = shapely.LineString([(at, y0), (at, y1)])
        else:
            line = shapely.LineString([(x0, at), (x1, at)])
        score = _edges_across(polygon, grid, line)
        if best is None or score < best[0]:
            best = (score, at, line)
    _, at, line = best
    cuts.append(line)
    low = along < at
    if across_x:
        boxes = shapely.box(x0, y0, at, y1), shapely.box(at, y0, x1, y1)
    else:
        boxes = shapely.box(x0, y0, x1, at), shapely.box(x0, at, x1, y1)
    for box, side, n in (
        (boxes[0], low, parts // 2),
        (boxes[1], ~low, parts - parts // 2),
    ):
        _bisect(polygon, grid, box, x[side], y[side], w[side], n, cuts)


def _edges_across(
    polygon: shapely.Polygon, grid: SizeGrid, line: shapely.LineString
) -> float:
    """Return the target edges along ``line`` in the water, plus penalties.

    Each crossing (chord) shorter than two target edges, or meeting the coast
    at under :data:`_MIN_CROSSING` degrees, adds :data:`_PENALTY`: its end
    would make a bad triangle.
    """
    wet = shapely.intersection(polygon, line)
    chords = [g for g in shapely.get_parts(wet) if g.geom_type == "LineString"]
    if not chords:
        return np.inf  # cuts nothing: never the best
    from coastmesh.meshing.projection import sample_size

    score = 0.0
    boundary = polygon.boundary
    for chord in chords:
        a, b = np.asarray(chord.coords)[[0, -1]]
        length = float(np.hypot(*(b - a)))
        xy = a + np.linspace(0.0, 1.0, 17)[:, None] * (b - a)
        h = sample_size(grid, xy)
        edges = float(length * np.mean(1.0 / h))
        score += edges
        if edges < 2.0 or _crossing_angle(boundary, a, b) < _MIN_CROSSING:
            score += _PENALTY
    return score


def _crossing_angle(boundary: object, a: NDArray, b: NDArray) -> float:
    """Return the smaller angle (degrees) between chord ``a b`` and the coast."""
    u = (b - a) / np.hypot(*(b - a))
    worst = 90.0
    for end in (a, b):
        at = shapely.line_locate_point(boundary, shapely.Point(end))
        span = 1e-6 * max(shapely.length(boundary), 1.0)
        p, q = shapely.line_interpolate_point(boundary, [at - span, at + span])
        v = np.asarray(q.coords[0]) - np.asarray(p.coords[0])
        norm = np.hypot(*v)
        if norm == 0:
            continue
        cos = abs(float(u @ v)) / norm
        worst = min(worst, float(np.degrees(np.arccos(min(cos, 1.0)))))
    return worst


@dataclass(frozen=True, slots=True)
class Faces:
    """The boundary noded with the cuts, and the faces of water.

    Attributes
    ----------
    curves : list of ndarray of shape (k, 2)
        Pieces of the boundary (split where a cut meets them) and of the cuts.
    ids : list of int or None
        Each curve's physical id; None for a piece of a cut.
    faces : list of list of list of int
        Per face of water, its loops (the outer one first), each a list of
        signed 1-based curve indices: ``-i`` runs curve ``i - 1`` backwards.
    """

    curves: list[NDArray[np.float64]]
    ids: list[int | None]
    faces: list[list[list[int]]]


def split_faces(
    pieces: list[tuple[NDArray[np.float64], int]],
    polygon: shapely.Polygon,
    cuts: list[shapely.LineString],
) -> Faces:
    """Node the boundary pieces with the cuts and return the faces of water.

    Parameters
    ----------
    pieces : list of (ndarray of shape (k, 2), int)
        The boundary as curves with their physical ids; consecutive pieces of a
        ring share end points exactly.
    polygon : shapely.Polygon
        The water the pieces bound.
    cuts : list of shapely.LineString
        From :func:`cut_lines`.

    Returns
    -------
    Faces
        Every face of water bounded by the pieces and the cuts.

    Examples
    --------
    >>> ring = np.array([[0, 0], [4, 0], [4, 2], [0, 2], [0, 0]], dtype=float)
    >>> f = split_faces([(ring, 7)], shapely.Polygon(ring),
    ...                 [shapely.LineString([(2, -1), (2, 3)])])
    >>> len(f.faces), sorted(i for i in f.ids if i is not None), f.ids.count(None)
    (2, [7, 7, 7], 1)
    """
    lines = [shapely.LineString(p) for p, _ in pieces] + list(cuts)
    noded = shapely.node(shapely.GeometryCollection(lines))
    curves = [np.asarray(g.coords) for g in noded.geoms]
    # the id of each curve: the piece its first edge's midpoint lies on
    tree = shapely.STRtree([shapely.LineString(p) for p, _ in pieces])
    mids = shapely.points([0.5 * (c[0] + c[1]) for c in curves])
    near, dist = tree.query_nearest(mids, return_distance=True, all_matches=False)
    on_piece = np.full(len(curves), -1)
    on_piece[near[0]] = near[1]
    scale = max(np.ptp(shapely.get_coordinates(polygon), axis=0).max(), 1.0)
    ids = [
        pieces[int(on_piece[k])][1] if dist[k] <= 1e-9 * scale else None
        for k in range(len(curves))
    ]
    first_edge: dict[tuple, int] = {}
    for k, c in enumerate(curves):
        first_edge[(tuple(c[0]), tuple(c[1]))] = k + 1
        first_edge[(tuple(c[-1]), tuple(c[-2]))] = -(k + 1)
    ends = {tuple(c[0]) for c in curves} | {tuple(c[-1]) for c in curves}
    faces = []
    for face in shapely.polygonize(list(noded.geoms)).geoms:
        if not polygon.contains(face.point_on_surface()):
            continue  # an island, or outside
        loops = [
            _loop(ring, first_edge, ends, curves)
            for ring in [face.exterior, *face.interiors]
        ]
        faces.append(loops)
    # keep the curves the faces use (not the cuts' ends outside the water)
    used = sorted({abs(i) - 1 for loops in faces for loop in loops for i in loop})
    new = {old: k + 1 for k, old in enumerate(used)}
    faces = [
        [[int(np.sign(i)) * new[abs(i) - 1] for i in loop] for loop in loops]
        for loops in faces
    ]
    return Faces([curves[k] for k in used], [ids[k] for k in used], faces)


def _loop(ring, first_edge: dict, ends: set, curves: list) -> list[int]:
    """Return a face's ring as signed curve indices, from a curve end."""
    xy = np.asarray(ring.coords)[:-1]
    start = next(k for k in range(len(xy)) if tuple(xy[k]) in ends)
    xy = np.vstack([np.roll(xy, -start, axis=0), xy[start : start + 1]])
    loop, k = [], 0
    while k < len(xy) - 1:
        signed = first_edge[(tuple(xy[k]), tuple(xy[k + 1]))]
        loop.append(signed)
        k += len(curves[abs(signed) - 1]) - 1
    return loop


def add_faces(gmsh: object, faces: Faces, surface_id: int) -> dict[int, int]:
    """Add the faces to the Gmsh model (geo kernel) as plane surfaces.

    A curve two faces share is one Gmsh curve, so its nodes are shared. Curves
    with an id get a physical group of that id; pieces of cuts get none. Every
    surface is in the physical group ``surface_id``.

    Returns
    -------
    dict of int to int
        Gmsh curve tag -> physical id, for the tagged curves.
    """
    geo = gmsh.model.geo
    point: dict[tuple[float, float], int] = {}

    def tag(xy: NDArray) -> int:
        key = (float(xy[0]), float(xy[1]))
        if key not in point:
            point[key] = geo.addPoint(key[0], key[1], 0.0)
        return point[key]

    curve_of: dict[int, int] = {}
    surfaces = []
    for loops in faces.faces:
        loop_tags = []
        for loop in loops:
            signed = []
            for s in loop:
                i = abs(s) - 1
                if i not in curve_of:
                    c = faces.curves[i]
                    ends = [tag(c[0]), *(geo.addPoint(x, y, 0.0) for x, y in c[1:-1])]
                    ends.append(tag(c[-1]))
                    curve_of[i] = (
                        geo.addLine(*ends) if len(ends) == 2 else geo.addSpline(ends)
                    )
                signed.append(curve_of[i] if s > 0 else -curve_of[i])
            loop_tags.append(geo.addCurveLoop(signed))
        surfaces.append(geo.addPlaneSurface(loop_tags))
    geo.synchronize()
    curve_ids = {
        curve_of[i]: pid
        for i, pid in enumerate(faces.ids)
        if pid is not None and i in curve_of
    }
    for pid in sorted(set(curve_ids.values())):
        gmsh.model.addPhysicalGroup(
            1, [c for c, p in curve_ids.items() if p == pid], tag=pid
        )
    gmsh.model.addPhysicalGroup(2, surfaces, tag=surface_id)
    return curve_ids


def chunked(pieces: list[tuple[NDArray, int]], most: int = CURVE_POINTS) -> list:
    """Split (piece, id) pairs of more than ``most`` points; ends are shared.

    Gmsh meshes curves on separate threads, and one spline through thousands of
    points is one long serial job: in chunks, the 1-D meshing of the NW-shelf
    intermediate boundary takes 1.1 s on 2 threads instead of 2.8 s on one.

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


def ring_pieces(rings: list, ids: list) -> tuple[list, shapely.Polygon]:
    """Return the resampled rings as (piece, id) pairs, and the water."""
    pieces = chunked(
        [
            (np.asarray(p, dtype=np.float64), pid)
            for ring, ring_ids in zip(rings, ids, strict=True)
            for seg, pid in zip(ring, ring_ids, strict=True)
            for p in seg
        ]
    )
    coords = [
        np.concatenate([ring[0][0][:1], *(p[1:] for seg in ring for p in seg)])
        for ring in rings
    ]
    return pieces, shapely.Polygon(coords[0], coords[1:])
