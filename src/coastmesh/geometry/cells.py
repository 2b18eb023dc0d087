"""The land on cells: winding numbers, coast cells, morphology, tracing.

The raster steps of :func:`~coastmesh.geometry.closing.close_narrow_water`,
on batches of square windows (``(tiles, size, size)`` arrays) of a grid in a
plane. They are written here, with numpy, because the core stages may not use
rasterio (its :func:`rasterio.features.rasterize` and ``shapes`` do the first
and last) and scikit-image is not a dependency; :mod:`scipy.ndimage` labels,
and :mod:`contourpy` (marching squares) traces.

* :func:`winding`: which cell centres the land holds, by scan lines; the
  polygons may overlap (a cell is land if any holds it) and have holes;
* :func:`crossed`: the cells an edge crosses;
* :func:`dilate`, :func:`erode`: by a disk of cells, by shifted ORs;
* :func:`bridge`: the water on short straight runs between land (a neck
  between two points of land, which no disk closing fills);
* :func:`joined`: the cells joined to seed cells;
* :func:`trace`: the polygons of True cells;
* :func:`points_inside`: which of many points a polygon holds, on threads;
* :func:`copies`: new GEOS objects of geometries, for another thread.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import contourpy
import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.geometry.dem import _polygons

__all__ = [
    "bridge",
    "copies",
    "crossed",
    "dilate",
    "erode",
    "joined",
    "points_inside",
    "trace",
    "winding",
]

#: Points per thread below which :func:`points_inside` runs on one
_POINTS_PER_THREAD = 50_000


def _same(xy: NDArray) -> NDArray:
    """Return the coordinates as they are: :func:`shapely.transform` copies so."""
    return xy


def copies(geoms: Any) -> Any:
    """Return new GEOS objects of ``geoms``, for a thread of their own.

    GEOS's prepared geometry (which shapely's predicates make and keep) is
    not safe to share between threads, even once built: each thread that asks
    a geometry while another may asks its own copy.

    Examples
    --------
    >>> box = shapely.box(0, 0, 1, 1)
    >>> copy = copies(box)
    >>> copy is box, copy.equals_exact(box, 0.0)
    (False, True)
    """
    return shapely.transform(geoms, _same)


def points_inside(
    polygon: shapely.Geometry, x: NDArray, y: NDArray, threads: int = 1
) -> NDArray[np.bool_]:
    """Return which points ``(x, y)`` (any shape) ``polygon`` holds, on threads.

    :func:`shapely.contains_xy` in ``threads`` chunks: GEOS lets go of
    Python's lock, and a world's coast makes each point slow (a scan line
    there crosses thousands of edges: 1 M size-grid nodes take about a second).

    Examples
    --------
    >>> points_inside(shapely.box(0, 0, 2, 2), np.array([1.0, 3.0]),
    ...               np.array([1.0, 1.0]), threads=2).tolist()
    [True, False]
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    shape, x, y = x.shape, x.ravel(), y.ravel()
    chunks = max(1, min(int(threads), len(x) // _POINTS_PER_THREAD))
    if chunks == 1:
        return shapely.contains_xy(polygon, x, y).reshape(shape)
    # a copy of the polygon per thread: GEOS's prepared polygon (which
    # contains_xy makes of each) is not safe to share between threads, even
    # once its point index is built (GEOS 3.14: heap corruption, every few
    # runs); the caller's own is never asked from a thread
    own = [copies(polygon) for _ in range(chunks)]
    edges = np.linspace(0, len(x), chunks + 1).astype(int)
    with ThreadPoolExecutor(chunks) as pool:
        parts = pool.map(
            lambda i: shapely.contains_xy(
                own[i], x[edges[i] : edges[i + 1]], y[edges[i] : edges[i + 1]]
            ),
            range(chunks),
        )
        return np.concatenate(list(parts)).reshape(shape)


def winding(
    a: NDArray,
    b: NDArray,
    sense: NDArray,
    tile: NDArray,
    origin: NDArray,
    anchor: NDArray,
    cell: float,
    size: int,
) -> NDArray[np.bool_]:
    """Return which cell centres of the tiles the land holds (winding number > 0).

    A scan line per row of cell centres (the edges crossing it, each +1 going
    down and -1 going up, summed from the window's left side), from the
    winding number on the left side itself: ``anchor`` at the first row's
    height, then the edges crossing that side, each +1 going right. Polygons
    that overlap are land where they overlap; holes are water.

    Parameters
    ----------
    a, b : ndarray of shape (n, 2)
        The edges' ends.
    sense : ndarray of int8, shape (n,)
        +1 for edges of exteriors anticlockwise and holes clockwise, else -1.
    tile : ndarray of int, shape (n,)
        The tile of each edge (edges in several tiles come once per tile).
    origin : ndarray of shape (t, 2)
        Each tile window's lower left corner.
    anchor : ndarray of int, shape (t,)
        The polygons that hold the point of each window's left side at its
        first row's height.
    cell : float
        The cells' side; the windows' lower left cell is at ``origin``.
    size : int
        The windows' cells a side.

    Returns
    -------
    ndarray of bool, shape (t, m, m)
        Rows then columns; ``m`` is ``size``.
    """
    count, n = len(origin), size
    x0, y0 = origin[tile, 0], origin[tile, 1]
    lo, hi = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
    v = np.flatnonzero((lo <= x0) & (x0 < hi))
    av, bv = a[v], b[v]
    yv = av[:, 1] + (x0[v] - av[:, 0]) * (bv[:, 1] - av[:, 1]) / (bv[:, 0] - av[:, 0])
    row = np.floor((yv - y0[v]) / cell - 0.5).astype(np.int64) + 1
    ok = (row >= 1) & (row < n)
    left = np.zeros(count * n, dtype=np.int16)
    up = np.where(bv[ok, 0] > av[ok, 0], 1, -1) * sense[v][ok]
    np.add.at(left, tile[v][ok] * n + row[ok], up)
    left = anchor[:, None] + np.cumsum(left.reshape(count, n), axis=1)
    rows = _rows(a, b, sense, tile, origin, cell, size)
    winding = np.cumsum(rows, axis=2, dtype=np.int16)
    winding += left[:, :, None].astype(np.int16)
    return winding > 0


def _rows(
    a: NDArray,
    b: NDArray,
    sense: NDArray,
    tile: NDArray,
    origin: NDArray,
    cell: float,
    size: int,
) -> NDArray[np.int8]:
    """Return each edge's crossings of the rows of cell centres, +1 down, -1 up.

    At the first cell of the row whose centre lies right of the crossing;
    crossings left of the window are in its left side's winding number.
    """
    count, n = len(origin), size
    x0, y0 = origin[tile, 0], origin[tile, 1]
    ylo, yhi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
    j0 = np.clip(np.ceil((ylo - y0) / cell - 0.5), 0, n).astype(np.int64)
    j1 = np.clip(np.ceil((yhi - y0) / cell - 0.5), 0, n).astype(np.int64)
    k = j1 - j0
    e = np.repeat(np.arange(len(a)), k)
    j = j0[e] + np.arange(len(e)) - np.repeat(np.cumsum(k) - k, k)
    ae, be = a[e], b[e]
    yc = y0[e] + (j + 0.5) * cell
    x = ae[:, 0] + (yc - ae[:, 1]) * (be[:, 0] - ae[:, 0]) / (be[:, 1] - ae[:, 1])
    col = np.ceil((x - x0[e]) / cell - 0.5)
    ok = (x >= x0[e]) & (col < n)
    flat = (tile[e][ok] * n + j[ok]) * n + col[ok].astype(np.int64)
    rows = np.zeros(count * n * n, dtype=np.int8)
    down = np.where(be[ok, 1] < ae[ok, 1], 1, -1).astype(np.int8) * sense[e][ok]
    np.add.at(rows, flat, down)
    return rows.reshape(count, n, n)


def crossed(
    a: NDArray, b: NDArray, tile: NDArray, origin: NDArray, cell: float, size: int
) -> NDArray[np.bool_]:
    """Return the cells of the tiles the edges cross (every half cell along each).

    The arguments are :func:`winding`'s.
    """
    count, n = len(origin), size
    steps = np.maximum(np.ceil(np.hypot(*(b - a).T) / (0.5 * cell)), 1).astype(np.int64)
    if steps.max(initial=1) == 1:  # short edges (a full-resolution coast): ends
        e, p = np.arange(len(a)), a
    else:
        e = np.repeat(np.arange(len(a)), steps)
        f = (np.arange(len(e)) - np.repeat(np.cumsum(steps) - steps, steps)) / steps[e]
        p = a[e] + f[:, None] * (b - a)[e]
    i = np.floor((p[:, 0] - origin[tile[e], 0]) / cell).astype(np.int64)
    j = np.floor((p[:, 1] - origin[tile[e], 1]) / cell).astype(np.int64)
    ok = (i >= 0) & (i < n) & (j >= 0) & (j < n)
    coast = np.zeros(count * n * n, dtype=bool)
    coast[(tile[e][ok] * n + j[ok]) * n + i[ok]] = True
    return coast.reshape(count, n, n)


def joined(mask: NDArray[np.bool_], seeds: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Return the cells of ``mask`` joined (8 ways, in one tile) to a seed cell."""
    structure = np.zeros((3, 3, 3), dtype=bool)
    structure[1] = True
    label, count = ndimage.label(mask, structure)
    hit = np.zeros(count + 1, dtype=bool)
    hit[label[seeds & mask]] = True
    hit[0] = False
    return hit[label]


def dilate(mask: NDArray[np.bool_], radius: float) -> NDArray[np.bool_]:
    """Dilate each tile by the disk of cells within ``radius`` (a square for 1).

    By shifted ORs: each row of the disk is a run of ``2w + 1`` cells, so the
    tiles dilated along their rows by each ``w`` are ORed in shifted up and
    down (about 9 ns a cell for 4, against 36 for
    :func:`scipy.ndimage.binary_dilation` with the disk; scikit-image's
    :func:`~skimage.morphology.binary_dilation` does the same decomposition
    only for squares).
    """
    reach = math.floor(radius)
    widths = {
        dy: reach if radius == 1 else math.floor(math.sqrt(radius**2 - dy**2))
        for dy in range(-reach, reach + 1)
    }
    runs, run, done = {}, mask, 0
    for w in sorted(set(widths.values())):
        run = run.copy()
        for s in range(done + 1, w + 1):
            run[..., s:] |= mask[..., :-s]
            run[..., :-s] |= mask[..., s:]
        runs[w], done = run, w
    out = runs[widths[0]].copy()
    for dy, w in widths.items():
        if dy > 0:
            out[:, dy:] |= runs[w][:, :-dy]
        elif dy < 0:
            out[:, :dy] |= runs[w][:, -dy:]
    return out


def erode(mask: NDArray[np.bool_], radius: float) -> NDArray[np.bool_]:
    """Erode each tile by a disk of ``radius`` cells (a square for 1)."""
    return ~dilate(~mask, radius)


def bridge(mask: NDArray[np.bool_], half: int) -> NDArray[np.bool_]:
    """Return ``mask`` with every cell on a short straight run between two of its cells.

    The union, over directions 15 degrees apart, of the closing by a digital
    segment of ``half`` cells each side of its centre (the line to the
    nearest cell of ``half (cos, sin)``; 2 ``half`` to 2.9 ``half`` cells long;
    8 distinct directions for 2 cells, 12 for 3): a cell is added when,
    along one of the directions, the run of cells outside ``mask`` through
    it is no longer than the segment. A
    disk's closing does not join two points of land facing each other over
    a gap narrower than the disk (the disk passes round them); this does.
    Cells beyond a tile's edge count as in ``mask``, as :func:`erode` has
    them.
    """
    pad = ((0, 0), (half, half), (half, half))
    padded = np.pad(mask, pad, constant_values=True)
    out = padded.copy()
    for offsets in _segments(half):
        grown = padded.copy()  # the dilation by the segment (it holds 0, 0)
        for dy, dx in offsets:
            if dy or dx:
                _shifted(padded, dy, dx, grown, np.bitwise_or)
        shrunk = grown.copy()  # then the erosion: past the edge counts as in
        for dy, dx in offsets:
            if dy or dx:
                _shifted(grown, dy, dx, shrunk, np.bitwise_and)
        out |= shrunk
    return out[:, half:-half, half:-half]


def _segments(half: int) -> list[NDArray[np.intp]]:
    """Return the (dy, dx) cells of each direction's segment, centred on 0."""
    found: dict[tuple[int, int], NDArray[np.intp]] = {}
    for angle in np.deg2rad(np.arange(0.0, 180.0, 15.0)):
        end = half * np.array([np.cos(angle), np.sin(angle)])
        # halves away from 0, and sin(30 deg) * 3 is 1.4999...: to the nearest
        a, b = (int(v) for v in np.sign(end) * np.floor(np.abs(end) + 0.5 + 1e-9))
        n = max(abs(a), abs(b))
        t = np.arange(-n, n + 1)
        cells = np.column_stack([np.rint(t * b / n), np.rint(t * a / n)])
        found.setdefault((a, b), np.unique(cells.astype(np.intp), axis=0))
    return list(found.values())


def _shifted(
    src: NDArray[np.bool_],
    dy: int,
    dx: int,
    out: NDArray[np.bool_],
    op: np.ufunc,
) -> None:
    """``out[..., y, x] = op(out[..., y, x], src[..., y - dy, x - dx])`` in the tile."""
    rows, cols = src.shape[-2:]
    to = (
        ...,
        slice(max(dy, 0), rows + min(dy, 0)),
        slice(max(dx, 0), cols + min(dx, 0)),
    )
    frm = (
        ...,
        slice(max(-dy, 0), rows + min(-dy, 0)),
        slice(max(-dx, 0), cols + min(-dx, 0)),
    )
    op(out[to], src[frm], out=out[to])


def trace(
    mask: NDArray[np.bool_], origin: NDArray[np.float64], cell: float, first: int
) -> NDArray[np.object_]:
    """Return the polygons of each tile's True cells (marching squares).

    ``mask[t]`` holds the cells of tile ``t``'s window from ``first`` on in
    both directions; the window's lower left corner is at ``origin[t]``.

    The tiles are traced at once, stacked with a row of False cells between
    them and round them, so every boundary runs half way between a True and a
    False cell's centre: along the cells' sides, with their corners cut.
    """
    tiles = np.flatnonzero(mask.any(axis=(1, 2)))
    if len(tiles) == 0:
        return np.empty(0, dtype=object)
    m = mask.shape[1]
    stack = np.zeros((len(tiles), m + 1, m + 2))
    stack[:, 1:, 1:-1] = mask[tiles]
    z = np.concatenate([stack.reshape(-1, m + 2), np.zeros((1, m + 2))])
    generator = contourpy.contour_generator(
        np.arange(float(m + 2)),
        np.arange(float(len(z))),
        z,
        name="serial",
        corner_mask=False,
        fill_type=contourpy.FillType.OuterOffset,
    )
    polygons = _polygons(*generator.filled(0.5, 1.5))

    def placed(ij: NDArray) -> NDArray:
        """From the stack's rows and columns to the plane."""
        t = (ij[:, 1] // (m + 1)).astype(np.int64)
        local = ij - np.column_stack([np.ones(len(t)), t * (m + 1) + 1.0])
        return origin[tiles[t]] + (local + first + 0.5) * cell

    # a staircase's vertices, one a cell, are mostly on straight runs
    return shapely.simplify(shapely.transform(polygons, placed), 0.5 * cell)
