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

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.types import Report

__all__ = [
    "RADIUS_STEP",
    "ChannelReport",
    "NarrowChannel",
    "channel_size",
    "local_width",
    "narrow_channels",
    "water_mask",
]

#: Ratio of one radius to the next in :func:`local_width`.
RADIUS_STEP = 1.15
#: A channel is "narrow" if fewer than this many elements of the floor fit across.
NARROW_ELEMENTS = 2


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
    water: NDArray[np.bool_], cell: float, *, max_width: float
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
        radii.append(radii[-1] * RADIUS_STEP)
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
    return ndimage.distance_transform_edt(~centres) <= r


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


@dataclass(frozen=True, slots=True)
class NarrowChannel(Report):
    """A stretch of water too narrow for two elements of the floor size.

    Attributes
    ----------
    x, y : float
        Its widest point, in the size grid's CRS.
    lon, lat : float
        The same point, degrees.
    area_m2 : float
        Its area on the size grid, square metres.
    width_m : float
        Its greatest width, metres (its dead ends are narrower).
    """

    x: float
    y: float
    lon: float
    lat: float
    area_m2: float
    width_m: float

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.width_m:.0f} m wide, {self.area_m2 / 1e6:.3f} km2 at "
            f"{self.lon:.4f}, {self.lat:.4f}"
        )


@dataclass(frozen=True, slots=True)
class ChannelReport(Report):
    """What the channel-width term found.

    Attributes
    ----------
    elements_across : float
        Elements asked for across every channel.
    h_min : float
        The floor of the field, metres.
    narrow : {"keep", "close"}
        What is done with narrow channels.
    limited_km2 : float
        Area of the domain where the term set the size, km2.
    narrow_channels : int
        Stretches of the domain narrower than two elements of ``h_min``: one
        element wide (after closing, with ``narrow = "close"``: what the cut
        left).
    narrow_km2 : float
        Their area, km2.
    worst : tuple of NarrowChannel
        The largest of them (up to 20), largest first.
    closed, closed_km2 : int, float
        Channels closed (taken out of the domain as land) and their area, km2.
    slots : int
        With ``narrow = "keep"``: slots narrower than ``h_min / 2`` closed all
        the same (no element fits in them; with ``"close"`` they are counted in
        ``closed``).
    """

    elements_across: float
    h_min: float
    narrow: str
    limited_km2: float
    narrow_channels: int
    narrow_km2: float
    worst: tuple[NarrowChannel, ...] = ()
    closed: int = 0
    closed_km2: float = 0.0
    slots: int = 0

    def summary(self) -> str:
        """Return a one-line summary."""
        closed = (
            f"{self.closed} closed ({self.closed_km2:,.2f} km2), "
            if self.closed
            else ""
        )
        return (
            f"channels: {self.elements_across:g} elements across sets the size on "
            f"{self.limited_km2:,.1f} km2; {closed}{self.narrow_channels} narrower "
            f"than {NARROW_ELEMENTS} x {self.h_min:g} m kept ({self.narrow_km2:,.2f} "
            "km2)"
        )


def narrow_channels(
    width: NDArray[np.float64],
    inside: NDArray[np.bool_],
    *,
    h_min: float,
    cell: float,
    min_length: float | None = None,
) -> tuple[NDArray[np.int32], list[tuple[float, float, float, float]]]:
    """Label the stretches of water narrower than ``NARROW_ELEMENTS * h_min``.

    Parameters
    ----------
    width : ndarray, shape (ny, nx)
        :func:`local_width`, metres.
    inside : ndarray of bool
        Grid nodes inside the domain (only those count).
    h_min : float
        The floor of the size field, metres.
    cell : float
        Grid spacing, metres.
    min_length : float, optional
        Stretches shorter than this (the diagonal of their bounding box, metres)
        are the tips of corners, not channels, and are left out; default
        ``NARROW_ELEMENTS * h_min``. (The tip of a right-angled corner is about
        ``0.6 h_min`` long; the head of a fjord 20 degrees wide, ``5.7 h_min``.)

    Returns
    -------
    labels : ndarray of int32, shape (ny, nx)
        0 outside any narrow channel, else its number (1, 2, ...), largest first.
    channels : list of (row, col, area_m2, width_m)
        For each: its widest node, its area, and its greatest width (still
        under ``NARROW_ELEMENTS * h_min``; its dead ends are narrower).

    Examples
    --------
    >>> width = np.full((6, 6), 900.0); width[2:4, :] = 150.0; width[2, 0] = 80.0
    >>> labels, found = narrow_channels(width, np.ones((6, 6), bool),
    ...                                 h_min=100.0, cell=50.0)
    >>> int(labels.max()), found[0][2], found[0][3]
    (1, 30000.0, 150.0)
    """
    narrow = inside & (width < NARROW_ELEMENTS * h_min)
    labels, count = ndimage.label(narrow, structure=np.ones((3, 3)))
    if count == 0:
        return labels.astype(np.int32), []
    if min_length is None:
        min_length = NARROW_ELEMENTS * h_min
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    sizes[0] = 0
    boxes = ndimage.find_objects(labels)
    length = np.zeros(count + 1)
    length[1:] = [
        cell * math.hypot(b[0].stop - b[0].start, b[1].stop - b[1].start) for b in boxes
    ]
    keep = np.flatnonzero(length >= min_length)
    keep = keep[np.argsort(-sizes[keep], kind="stable")]
    renumber = np.zeros(count + 1, dtype=np.int32)
    renumber[keep] = np.arange(1, len(keep) + 1, dtype=np.int32)
    labels = renumber[labels]
    found = []
    if len(keep):
        index = np.arange(1, len(keep) + 1)
        lows = ndimage.maximum_position(width, labels, index=index)
        for k, (row, col) in enumerate(lows):
            found.append(
                (
                    int(row),
                    int(col),
                    float(sizes[keep[k]] * cell * cell),
                    float(width[row, col]),
                )
            )
    return labels, found


def channel_polygons(
    labels: NDArray[np.int32], x: NDArray[np.float64], y: NDArray[np.float64]
) -> NDArray[np.object_]:
    """Return the labelled stretches as polygons (union of their grid cells).

    Parameters
    ----------
    labels : ndarray of int, shape (ny, nx)
        As :func:`narrow_channels` returns.
    x, y : ndarray
        Ascending node coordinates of the grid (uniform spacing).

    Returns
    -------
    ndarray of shapely polygons
        One (Multi)Polygon per label, 1 first.
    """
    count = int(labels.max(initial=0))
    if count == 0:
        return np.empty(0, dtype=object)
    dx = float(x[1] - x[0])
    rows, cols = np.nonzero(labels)
    boxes = shapely.box(
        x[cols] - dx / 2, y[rows] - dx / 2, x[cols] + dx / 2, y[rows] + dx / 2
    )
    order = np.argsort(labels[rows, cols], kind="stable")
    starts = np.searchsorted(labels[rows, cols][order], np.arange(1, count + 2))
    # the cells of a label tile it: coverage_union_all merges them exactly
    parts = [
        shapely.coverage_union_all(boxes[order[starts[k] : starts[k + 1]]])
        for k in range(count)
    ]
    return np.array(parts, dtype=object)


def over_land(term: NDArray[np.float64], water: NDArray[np.bool_]) -> NDArray:
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
    nearest = ndimage.distance_transform_edt(
        ~water, return_distances=False, return_indices=True
    )
    return term[tuple(nearest)]
