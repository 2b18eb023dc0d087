"""Channels too narrow for two elements of the floor: found, described, warned of.

With a channel term, the width of the water (:mod:`coastmesh.sizing.channel`)
says where fewer than :data:`NARROW_ELEMENTS` elements of the floor ``h_min``
fit across: those stretches are one element wide in the mesh. A case keeps them
(and is warned of them, with their places) or closes them as land before
meshing (``[mesh_size.channels] narrow``); :func:`channel_polygons` gives the
cells of each as polygons to close.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.errors import CoastmeshWarning
from coastmesh.geometry.earth import transformer
from coastmesh.types import Report

__all__ = [
    "NARROW_CHOICES",
    "NARROW_ELEMENTS",
    "ChannelReport",
    "NarrowChannel",
    "channel_polygons",
    "narrow_channels",
    "narrow_places",
    "rank_channels",
    "warn_narrow",
]

#: What to do with channels too narrow for two elements of the floor size.
NARROW_CHOICES = ("keep", "close")


#: A channel is "narrow" if fewer than this many elements of the floor fit across.
NARROW_ELEMENTS = 2


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
) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
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
    area = np.bincount(labels.ravel(), minlength=count + 1) * cell * cell
    boxes = ndimage.find_objects(labels)
    length = np.zeros(count + 1)
    length[1:] = [
        cell * math.hypot(b[0].stop - b[0].start, b[1].stop - b[1].start) for b in boxes
    ]
    return rank_channels(labels, width, area, length >= min_length)


def rank_channels(
    labels: NDArray[np.integer],
    width: NDArray[np.float64],
    area: NDArray[np.number],
    kept: NDArray[np.bool_],
) -> tuple[NDArray[np.int32], list[tuple[int, int, float, float]]]:
    """Keep some labelled stretches, number them largest first, find their widest.

    The step :func:`narrow_channels` and
    :func:`~coastmesh.sizing.sphere_channel.sphere_narrow_channels` share; each
    measures its stretches' areas and lengths its own way.

    Parameters
    ----------
    labels : ndarray of int, shape (ny, nx)
        0 outside any stretch, else its label, ``1 .. count``.
    width : ndarray, shape (ny, nx)
        The width of the water at each node, metres.
    area : ndarray, shape (count + 1,)
        Each label's area, m^2 (entry 0, the background, is not read).
    kept : ndarray of bool, shape (count + 1,)
        Which labels to keep (entry 0 is never kept): those long enough.

    Returns
    -------
    labels : ndarray of int32, shape (ny, nx)
        0 outside the kept stretches, else ``1 .. k`` by area, largest first
        (equal areas in the order of their old labels).
    channels : list of (row, col, area_m2, width_m)
        For each, in that order: its widest node (one of them, when several
        are as wide), its area and its width there.

    Examples
    --------
    >>> labels = np.array([[1, 0, 2, 2], [1, 0, 2, 3]])
    >>> width = np.array([[5.0, 0.0, 7.0, 9.0], [6.0, 0.0, 8.0, 4.0]])
    >>> new, found = rank_channels(labels, width, np.array([0.0, 2.0, 3.0, 1.0]),
    ...                            np.array([False, True, True, False]))
    >>> new.tolist(), found
    ([[2, 0, 1, 1], [2, 0, 1, 0]], [(0, 3, 3.0, 9.0), (1, 0, 2.0, 6.0)])
    """
    keep = np.flatnonzero(kept)
    keep = keep[keep > 0]
    keep = keep[np.argsort(-area[keep], kind="stable")]
    renumber = np.zeros(len(kept), dtype=np.int32)
    renumber[keep] = np.arange(1, len(keep) + 1, dtype=np.int32)
    ranked = renumber[labels]
    found = []
    if len(keep):
        index = np.arange(1, len(keep) + 1)
        lows = ndimage.maximum_position(width, ranked, index=index)
        for k, (row, col) in enumerate(lows):
            found.append(
                (int(row), int(col), float(area[keep[k]]), float(width[row, col]))
            )
    return ranked, found


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


def narrow_places(
    found: list[tuple[int, int, float, float]],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    crs: object,
    *,
    most: int = 20,
) -> tuple[NarrowChannel, ...]:
    """Describe the largest narrow channels (:func:`narrow_channels`): where, how big.

    ``x``, ``y`` are the grid's node coordinates in ``crs``; each channel's
    widest point is also given in longitude and latitude.
    """
    to_lonlat = transformer(crs, "EPSG:4326")
    worst = []
    for row, col, area, w in found[:most]:
        lon, lat = to_lonlat.transform(x[col], y[row])
        worst.append(
            NarrowChannel(
                x=float(x[col]),
                y=float(y[row]),
                lon=round(float(lon), 6),
                lat=round(float(lat), 6),
                area_m2=area,
                width_m=w,
            )
        )
    return tuple(worst)


def warn_narrow(
    report: ChannelReport,
    *,
    closed: bool = False,
    after_closing: int = 0,
    closed_by: str | None = None,
) -> None:
    """Warn of narrow channels kept (or closed), where they are, and what to do.

    ``after_closing``: these are left after closing others this many times.
    ``closed_by``: the key that closed the narrower water before (a global
    case's ``[domain] close``).
    """
    where = "; ".join(c.summary() for c in report.worst[:3])
    if closed:
        action = "closed: taken out of the domain as land"
    elif closed_by is not None:
        action = (
            f"left by {closed_by} (which closes narrower water), kept: they are "
            f"one element wide. Lower h_min to resolve them, or raise {closed_by} "
            f"to {NARROW_ELEMENTS} h_min to close them"
        )
    elif after_closing:
        action = (
            f"left after closing narrow channels {after_closing} times (the cuts "
            "made them), kept: they are one element wide. Lower h_min to resolve "
            "them"
        )
    else:
        action = (
            "kept: they are one element wide. Lower h_min to resolve them, or set "
            '[mesh_size.channels] narrow = "close"'
        )
    warnings.warn(
        f"mesh_size: {report.narrow_channels} channels are narrower than "
        f"{NARROW_ELEMENTS} elements of h_min = {report.h_min:g} m ("
        f"{report.narrow_km2:,.2f} km2; the largest: {where}), {action}",
        CoastmeshWarning,
        stacklevel=4,
    )
