"""The width of the water at every point, and the channel-width size term.

The width at a point is the diameter of the largest disk that holds the point and
lies in the water: in a channel of width ``w`` it is ``w`` everywhere across the
channel, on open water it is large, and at the head of a fjord it falls to the
width that is left. It is the local feature size of OceanMesh2D's ``R`` term and
the "local thickness" of image analysis, and unlike the distance to the medial
axis it does not drop next to every bump of a noisy shoreline (the medial axis
sends a branch to each of them).

How it is computed, on the size grid (regular, in the meshing CRS):

1. *Water*: the grid nodes inside the domain, plus the nodes outside it that are
   nearer an open boundary than a shoreline (the sea goes on past an open
   boundary; it is not a wall).
2. The union of the disks of radius ``r`` that fit in the water is the
   morphological opening of the water by a disk of radius ``r``. It is two
   Euclidean distance transforms (:func:`scipy.ndimage.distance_transform_edt`):
   the centres that fit are where the distance to land exceeds ``r``, and the
   points covered are those within ``r`` of a centre.
3. The width at a node is twice the largest ``r`` whose opening holds it, over
   radii in geometric steps of ``RADIUS_STEP`` from half a cell up to the widest
   channel that can matter (``elements_across * h_max``). Widths are thus
   rounded down, by at most one cell (disks are centred on grid nodes) and a
   factor ``RADIUS_STEP``: the term errs fine. The cost is
   one distance transform of the grid per radius: about 30 for a grid of 1000 x
   1000 nodes (a few seconds). A coarser grid for the large radii was tried and
   dropped: it cannot tell whether a node next to the shore is held by a large
   disk, which is exactly where the width matters.

No maintained library computes a local thickness for a 2-D mask of this size (the
scikit-image medial axis needs pruning for this use), so the loop over radii is
written here; every transform in it is scipy's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.types import Domain

if TYPE_CHECKING:
    from coastmesh.sizing.grid import PlaneGrid

__all__ = [
    "RADIUS_STEP",
    "channel_size",
    "domain_width",
    "local_width",
    "narrow_width",
    "over_land",
    "water_mask",
    "window_width",
]

#: Ratio of one radius to the next in :func:`local_width`.
RADIUS_STEP = 1.15


def water_mask(
    inside: NDArray[np.bool_],
    shore: NDArray[np.bool_],
    open_lines: NDArray[np.bool_],
) -> NDArray[np.bool_]:
    """Return the water: inside the domain, or outside but nearer open than shore.

    Parameters
    ----------
    inside : ndarray of bool, shape (ny, nx)
        Grid nodes inside the domain.
    shore, open_lines : ndarray of bool, shape (ny, nx)
        Grid nodes on (touched by) the shorelines and the open boundaries.

    Examples
    --------
    >>> inside = np.zeros((3, 5), bool); inside[:, :2] = True
    >>> shore = np.zeros((3, 5), bool); shore[:, 0] = True
    >>> opened = np.zeros((3, 5), bool); opened[:, 2] = True
    >>> water_mask(inside, shore, opened).astype(int).tolist()[0]
    [1, 1, 1, 1, 1]
    """
    water = inside.copy()
    if open_lines.any():
        if shore.any():
            to_shore = ndimage.distance_transform_edt(~shore)
            to_open = ndimage.distance_transform_edt(~open_lines)
            water |= ~inside & (to_open < to_shore)
        else:
            water[:] = True
    return water


def local_width(
    water: NDArray[np.bool_],
    cell: float,
    *,
    max_width: float,
    step: float = RADIUS_STEP,
) -> NDArray[np.float64]:
    """Return the width of the water at each grid node (metres).

    Parameters
    ----------
    water : ndarray of bool, shape (ny, nx)
        The water (see :func:`water_mask`); outside the array is land.
    cell : float
        Grid spacing, metres.
    max_width : float
        Widths at or above this are not resolved: they come out as ``inf``.
    step : float
        The ratio of successive radii (> 1): a larger step is quicker, and
        rounds widths down further.

    Returns
    -------
    ndarray of float64, shape (ny, nx)
        Diameter of the largest disk in the water that holds the node, rounded
        down by at most one cell and a factor :data:`RADIUS_STEP`; 0 on land;
        ``inf`` where it is at least ``max_width``.

    Examples
    --------
    A channel nine cells (900 m) wide, in a grid of 100 m cells:

    >>> water = np.zeros((40, 11), bool); water[:, 1:10] = True
    >>> w = local_width(water, 100.0, max_width=5000.0)
    >>> round(float(w[20, 1]), 1), round(float(w[20, 5]), 1), float(w[0, 0])
    (813.7, 813.7, 0.0)
    """
    water = np.asarray(water, dtype=bool)
    # distance (cells) from each water node to the edge of the water: half a
    # cell less than the distance to the nearest land node
    depth = ndimage.distance_transform_edt(np.pad(water, 1))[1:-1, 1:-1] - 0.5
    width = np.where(water, np.inf, 0.0)
    top = max_width / (2 * cell)
    radii = [0.5]
    while radii[-1] < top:
        radii.append(radii[-1] * step)
    # from the widest down: a node takes the largest radius whose opening holds
    # it; those held by the widest (at least max_width across) stay inf
    done = _opening(depth, radii[-1])
    for r in reversed(radii[:-1]):
        new = _opening(depth, r) & ~done & water
        width[new] = 2 * r * cell
        done |= new
    # a water node no disk of half a cell holds: narrower than one cell
    width[water & ~done] = 0.5 * cell
    return width


def _opening(depth: NDArray[np.float64], r: float) -> NDArray[np.bool_]:
    """Nodes within ``r`` of a centre where a disk of radius ``r`` fits (cells)."""
    centres = depth >= r
    if not centres.any():
        return centres
    # scipy is untyped here (no stubs among the dependencies)
    distance: NDArray[np.float64] = ndimage.distance_transform_edt(~centres)
    return distance <= r


def narrow_width(
    water: NDArray[np.bool_], cell: float, *, max_width: float
) -> NDArray[np.float64]:
    """Return where the water is narrower than ``max_width``, and how narrow.

    The one question the closing asks, in one opening (two distance
    transforms) instead of :func:`local_width`'s dozen: a water node that no
    disk of diameter ``max_width`` in the water holds gets the diameter of
    the largest disk centred on it (twice its distance to the edge of the
    water, below ``max_width``); the others ``inf``; land 0.

    Examples
    --------
    A channel nine cells (900 m) wide, in a grid of 100 m cells:

    >>> water = np.zeros((40, 11), bool); water[:, 1:10] = True
    >>> w = narrow_width(water, 100.0, max_width=1000.0)
    >>> float(w[20, 1]), float(w[20, 5]), float(w[0, 0])
    (100.0, 900.0, 0.0)
    >>> bool(np.isinf(narrow_width(water, 100.0, max_width=800.0)[20, 1:10]).all())
    True
    """
    water = np.asarray(water, dtype=bool)
    depth = ndimage.distance_transform_edt(np.pad(water, 1))[1:-1, 1:-1] - 0.5
    radius = max_width / (2 * cell)
    centres = depth >= radius
    if not centres.any():  # no disk fits: all the water is narrow
        return np.where(water, 2 * depth * cell, 0.0)
    # a disk reaches half a cell past its radius, as the edge of the water is
    # half a cell past its last node: a staircase coast is not narrow water
    # (no centre fits in water narrower than max_width, whatever the reach)
    held = ndimage.distance_transform_edt(~centres) <= radius + 0.5
    width = np.where(water, np.inf, 0.0)
    narrow = water & ~held
    width[narrow] = 2 * depth[narrow] * cell
    return width


def channel_size(
    width: NDArray[np.float64], *, elements_across: float, h_min: float
) -> NDArray[np.float64]:
    """Return the channel-width size term: ``width / elements_across``, floored.

    Examples
    --------
    >>> channel_size(np.array([3000.0, 300.0, np.inf]), elements_across=3, h_min=200)
    array([1000.,  200.,   inf])
    """
    if not elements_across >= 1:
        raise ValueError(f"elements_across = {elements_across!r}: must be >= 1")
    return np.maximum(width / elements_across, h_min)


def over_land(
    term: NDArray[np.float64], water: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """Return ``term`` with each land node given its nearest water node's value.

    The width is 0 on land, which would put ``h_min`` on every land node: Gmsh
    interpolates the grid along the coast between land and water nodes, so
    every coast would be meshed near ``h_min`` whatever its gradation asked
    for (the NW-shelf intermediate case's 0.1-degree coasts came out with
    0.9 km edges). A land node takes the channel's size where the water next
    to it is narrow, and the open water's where it is wide.

    Examples
    --------
    >>> term = np.array([[1.0, 5.0, 9.0, 0.2]])
    >>> over_land(term, np.array([[True, False, True, False]])).tolist()
    [[1.0, 1.0, 9.0, 9.0]]
    """
    if water.all() or not water.any():
        return term
    # scipy is untyped here (no stubs among the dependencies)
    nearest: NDArray[np.intp] = ndimage.distance_transform_edt(
        ~water, return_distances=False, return_indices=True
    )
    near: NDArray[np.float64] = term[tuple(nearest)]
    return near


def domain_width(
    grid: PlaneGrid,
    domain: Domain,
    *,
    max_width: float,
    step: float = RADIUS_STEP,
    narrow_only: bool = False,
) -> NDArray[np.float64]:
    """Return the width of the domain's water at the grid's nodes (metres).

    The domain's shoreline segments are walls; its open boundaries are not (the
    sea goes on past them). 0 on land; ``inf`` where wider than ``max_width``
    (see :func:`local_width`; with ``narrow_only``, :func:`narrow_width`).
    """
    from coastmesh.geometry.earth import densified

    lines: dict[str, list[shapely.Geometry]] = {"shoreline": [], "open": []}
    for s in domain.segments:
        lines[s.kind].append(shapely.LineString(s.coords))
    shore = _touched(densified(domain, lines["shoreline"], grid.crs), grid)
    opened = _touched(densified(domain, lines["open"], grid.crs), grid)
    water = water_mask(grid.sea, shore, opened)
    if narrow_only:
        return narrow_width(water, grid.cell, max_width=max_width)
    return local_width(water, grid.cell, max_width=max_width, step=step)


def window_width(
    grid: PlaneGrid,
    water: shapely.Geometry,
    shore: NDArray[np.object_],
    opened: NDArray[np.object_],
    *,
    max_width: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Return the width of the water on a small grid, and its sea mask.

    As :func:`domain_width` with ``narrow_only`` (the closing's question),
    from geometries already in the grid's CRS (the domain's polygon, its
    shoreline and open-boundary lines), clipped to the grid first: the cost
    follows the window, not the whole coast.
    """
    pad = 2 * grid.cell
    box = (grid.x[0] - pad, grid.y[0] - pad, grid.x[-1] + pad, grid.y[-1] + pad)
    xx, yy = np.meshgrid(grid.x, grid.y)
    local = shapely.clip_by_rect(water, *box)
    shapely.prepare(local)
    sea = shapely.contains_xy(local, xx, yy)
    inside = shapely.box(*box)
    shore = shapely.clip_by_rect(shore[shapely.intersects(shore, inside)], *box)
    opened = shapely.clip_by_rect(opened[shapely.intersects(opened, inside)], *box)
    touched_shore = _touched(shore[~shapely.is_empty(shore)], grid)
    touched_open = _touched(opened[~shapely.is_empty(opened)], grid)
    mask = water_mask(sea, touched_shore, touched_open)
    return narrow_width(mask, grid.cell, max_width=max_width), sea


def _touched(lines: NDArray[np.object_], grid: PlaneGrid) -> NDArray[np.bool_]:
    """Grid nodes next to the lines: the nearest node of every point of them.

    Each line is sampled at a third of the grid spacing, so every cell it
    crosses has a sample (a line burnt into the grid; rasterio is kept out of
    the core stages).
    """
    x, y, cell = grid.x, grid.y, grid.cell
    mask = np.zeros(grid.shape, dtype=bool)
    if not len(lines):
        return mask
    points = shapely.get_coordinates(shapely.segmentize(lines, cell / 3))
    col = np.clip(np.rint((points[:, 0] - x[0]) / cell).astype(np.int64), 0, len(x) - 1)
    row = np.clip(np.rint((points[:, 1] - y[0]) / cell).astype(np.int64), 0, len(y) - 1)
    mask[row, col] = True
    return mask
