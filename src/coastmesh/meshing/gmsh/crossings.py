"""A resampled boundary that crosses itself: found, and resampled finer there.

Resampling a coast at the local size ``h`` (:func:`~coastmesh.meshing.gmsh.
resample.resample_rings`) cuts across whatever is narrower than ``h``. Where two
coasts come closer than that (a strait the closing left, within its 20 %, or
the skerries of a full-resolution world layer), the chords of one can cross the
other, and Gmsh cannot mesh the polygon. :func:`resample_valid` finds every
place where the resampled rings cross or touch, halves the size the coast is
resampled at within two sizes of each, and resamples the rings again, up to
:data:`TRIES` times (a 256th of the size); the rest of the boundary is as it
was. The curves through those points then follow both coasts there. Gmsh
still places the boundary's nodes along them at the size field's size, so
nodes that cross after all are an error named in lon/lat
(``coastmesh.meshing.engine``), before the parts' overlays would fail on them.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import CoastmeshWarning
from coastmesh.meshing.gmsh.resample import SizeAt, check_boundary, resample_rings

__all__ = ["FinerCoastWarning", "boundary_crossings", "resample_valid"]

logger = logging.getLogger(__name__)

#: halvings of the size at a crossing before the boundary is given up on
TRIES = 8
#: a crossing's disk of finer resampling, in local sizes
_REACH = 2.0

Rings = list[list[list[NDArray[np.float64]]]]


class FinerCoastWarning(CoastmeshWarning):
    """The coast was resampled finer than the size where it crossed itself."""


def boundary_crossings(
    rings: Sequence[Sequence[Sequence[NDArray[np.float64]]]],
) -> NDArray[np.float64]:
    """Return where the rings' edges cross or touch, other than at their joints.

    Parameters
    ----------
    rings : sequence of sequence of sequence of ndarray of shape (m, 2)
        As :func:`~coastmesh.meshing.gmsh.resample.resample_rings` returns
        them: for each ring, for each segment, its pieces.

    Returns
    -------
    ndarray of shape (k, 3)
        For each pair of edges that meet, the middle of the first edge and
        the index of its ring; the pairs are those of a ring with itself or
        with another, not two edges that follow each other in a ring.

    Examples
    --------
    >>> bow = [[np.array([[0.0, 0], [2, 2], [2, 0], [0, 2], [0, 0]])]]
    >>> boundary_crossings([bow]).tolist()
    [[1.0, 1.0, 0.0]]
    """
    closed = [
        np.concatenate([p[:-1] for seg in ring for p in seg] + [ring[0][0][:1]])
        for ring in rings
    ]
    a = np.concatenate([c[:-1] for c in closed])
    b = np.concatenate([c[1:] for c in closed])
    count = np.array([len(c) - 1 for c in closed])
    ring = np.repeat(np.arange(len(closed)), count)
    first = np.repeat(np.cumsum(count) - count, count)
    last = first + np.repeat(count, count) - 1
    lines = shapely.linestrings(np.stack([a, b], axis=1))
    i, j = shapely.STRtree(lines).query(lines, predicate="intersects")
    keep = i < j
    i, j = i[keep], j[keep]
    joint = (ring[i] == ring[j]) & ((j == i + 1) | ((i == first[i]) & (j == last[i])))
    i = np.unique(i[~joint])
    return np.column_stack([0.5 * (a[i] + b[i]), ring[i]])


def resample_valid(
    rings: Sequence[Sequence[ArrayLike]],
    size_at: SizeAt,
    where: Callable[[float, float], str] | None = None,
) -> tuple[Rings, list[int]]:
    """Resample the rings to the size, finer where they would cross.

    Parameters
    ----------
    rings : sequence of sequence of array_like of shape (k, 2)
        For each ring, its segments, as
        :func:`~coastmesh.meshing.gmsh.resample.resample_rings` takes them.
    size_at : callable
        The target size at positions.
    where : callable, optional
        ``where(x, y)`` names a point in messages (lon/lat).

    Returns
    -------
    rings, dropped
        As :func:`~coastmesh.meshing.gmsh.resample.resample_rings` returns
        them; the rings bound a valid polygon.

    Raises
    ------
    MeshingError
        If the rings still cross after :data:`TRIES` halvings, or bound no
        valid polygon for another reason (a ring outside the exterior).

    Warns
    -----
    FinerCoastWarning
        Where the coast was resampled finer, with how many places and the
        first one.

    Examples
    --------
    A spit of the coast 1.5 km long reaches into a notch of an island:
    resampled at 2 km, the island's chord across the notch crosses the spit.

    >>> shore = [[0, 0], [2480, 0], [2480, 1500], [2520, 1500], [2520, 0],
    ...          [5000, 0], [5000, 5000], [0, 5000], [0, 0]]
    >>> island = [[1500, 1000], [2450, 1000], [2450, 1800], [2550, 1800],
    ...           [2550, 1000], [3500, 1000], [3500, 3000], [1500, 3000],
    ...           [1500, 1000]]
    >>> rings = [[np.array(shore, float)], [np.array(island, float)]]
    >>> def size(xy):
    ...     return np.full(len(xy), 2e3)
    >>> coarse, _ = resample_rings(rings, size)
    >>> len(boundary_crossings(coarse))
    2
    >>> with warnings.catch_warnings(record=True) as seen:
    ...     warnings.simplefilter("always")
    ...     out, _ = resample_valid(rings, size)
    >>> len(boundary_crossings(out)), check_boundary(out), len(seen)
    (0, None, 1)
    """
    disks = np.zeros((0, 3))  # x, y, radius: each halves the size inside it

    def finer(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        h = np.asarray(size_at(xy), dtype=np.float64)
        if len(disks) == 0 or len(xy) == 0:
            return h
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        near = disks[
            (disks[:, 0] + disks[:, 2] >= lo[0])
            & (disks[:, 0] - disks[:, 2] <= hi[0])
            & (disks[:, 1] + disks[:, 2] >= lo[1])
            & (disks[:, 1] - disks[:, 2] <= hi[1])
        ]
        if len(near) == 0:
            return h
        inside = np.zeros(len(xy), dtype=np.int64)
        for x, y, r in near:
            inside += (xy[:, 0] - x) ** 2 + (xy[:, 1] - y) ** 2 <= r * r
        return h * 0.5 ** np.minimum(inside, TRIES)

    out, dropped = resample_rings(rings, finer)
    places, first = 0, np.zeros(3)
    for rounds in range(TRIES + 1):
        crossing = boundary_crossings(out)
        if len(crossing) == 0 or rounds == TRIES:
            break
        if not rounds:
            places, first = len(crossing), crossing[0]
        h = np.asarray(size_at(crossing[:, :2]), dtype=np.float64)
        disks = np.vstack([disks, np.column_stack([crossing[:, :2], _REACH * h])])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CoastmeshWarning)
            out, dropped = resample_rings(rings, finer)
    if places:
        name = (
            where(*first[:2]) if where is not None else f"({first[0]:g}, {first[1]:g})"
        )
        warnings.warn(
            f"the coast resampled at the target size crossed itself at {places} "
            f"places where two coasts are closer than the size (the first at "
            f"{name}); it is resampled finer there, in {rounds} rounds of "
            "halving the size",
            FinerCoastWarning,
            stacklevel=2,
        )
    if len(crossing) or not _nested_right(out):
        check_boundary(out, where)  # raises, with GEOS's reason and the place
    return out, dropped


def _nested_right(rings: Rings) -> bool:
    """Return whether, with no two edges meeting, the rings bound one polygon.

    Each hole inside the exterior and outside every other hole: a vertex of
    each tells, as their rings do not meet. (GEOS's own validity check took
    13 s on 20,000 holes of 600,000 vertices where this takes under 1 s.)
    """
    first = np.array([ring[0][0][0] for ring in rings])
    if len(rings) < 2:
        return True
    shell = shapely.Polygon(np.concatenate([p[:-1] for seg in rings[0] for p in seg]))
    if not shapely.contains_xy(shell, first[1:, 0], first[1:, 1]).all():
        return False
    holes = [
        shapely.Polygon(np.concatenate([p[:-1] for seg in ring for p in seg]))
        for ring in rings[1:]
    ]
    inside, _ = shapely.STRtree(holes).query(
        shapely.points(first[1:]), predicate="within"
    )
    return len(inside) == 0
