"""Boundary resampling: polylines to the local target size, before Gmsh sees them.

Resampling makes the meshing work scale with the mesh, not with the raw shoreline:
details below the local size disappear instead of creating tiny elements.
"""

from __future__ import annotations

import itertools
import re
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import CoastmeshWarning, MeshingError

__all__ = [
    "SmallIslandWarning",
    "check_boundary",
    "resample_rings",
    "resample_segment",
]

SizeAt = Callable[[NDArray[np.float64]], NDArray[np.float64]]

# A vertex stays a vertex when the line turns there by more than this angle and
# both edges next to it are at least one local target size long (a real corner,
# such as the corner of a box or a straight breakwater, not shoreline noise).
_CORNER_ANGLE = np.deg2rad(30.0)
# Vertices turning by less than this are straight: their edges form one run.
_STRAIGHT_ANGLE = 1e-3
# Sampling step along each raw edge when integrating 1/h, as a fraction of h.
_SAMPLES_PER_SIZE = 4.0


class SmallIslandWarning(CoastmeshWarning):
    """An island is smaller than the local target size and was dropped."""


def resample_segment(
    coords: ArrayLike,
    size_at: SizeAt,
    *,
    points_per_edge: float = 2.0,
    up: bool = False,
) -> NDArray[np.float64]:
    r"""Resample a polyline so its point spacing follows a target size.

    Parameters
    ----------
    coords : array_like of shape (k, 2), k >= 2
        The polyline, in a projected CRS (metres).
    size_at : callable
        Takes an ndarray of shape (n, 2) of positions and returns the target edge
        length in metres at each, shape (n,), all > 0.
    points_per_edge : float, default 2.0
        Points per target edge length: the spacing is about
        ``size_at(x) / points_per_edge``.
    up : bool, default False
        Round the number of edges between kept vertices up (as Gmsh does when
        it meshes a curve), so no edge is longer than its target; by default
        to the nearest.

    Returns
    -------
    ndarray of shape (m, 2), m >= 2
        The resampled polyline. The end points are the input end points exactly,
        as are the vertices where the line turns by more than 30 degrees between
        two straight runs each at least one local size long (corners).

    Raises
    ------
    ValueError
        If ``coords`` has the wrong shape or non-finite values, ``points_per_edge``
        is not > 0, or ``size_at`` returns a wrong shape or values that are not > 0.

    Notes
    -----
    Vectorised: each edge is split into steps of at most a quarter of the local
    size; the number of target edges along the line, :math:`s = \int ds / h`, is
    accumulated with the trapezoidal rule; between consecutive corners, points are
    put at equal steps of :math:`s` and located by linear interpolation of the
    cumulative arc length.

    Examples
    --------
    >>> line = np.array([[0.0, 0.0], [100.0, 0.0]])
    >>> out = resample_segment(line, lambda xy: np.full(len(xy), 20.0))
    >>> len(out), out[0].tolist(), out[-1].tolist()
    (11, [0.0, 0.0], [100.0, 0.0])
    """
    return _resample(coords, size_at, points_per_edge, up)[0]


def resample_rings(
    rings: Sequence[Sequence[ArrayLike]],
    size_at: SizeAt,
    *,
    points_per_edge: float = 2.0,
    up: bool = False,
) -> tuple[list[list[list[NDArray[np.float64]]]], list[int]]:
    """Resample the segments of polygon rings; drop holes that collapse.

    Parameters
    ----------
    rings : sequence of sequence of array_like of shape (k, 2)
        For each ring, its segments in order (each starting where the previous
        ends, the last ending where the first starts). Ring 0 is the exterior;
        the others are holes (islands). Projected CRS, metres.
    size_at : callable
        Target edge length in metres at positions, as in :func:`resample_segment`.
    points_per_edge : float, default 2.0
        Points per target edge length.
    up : bool, default False
        As in :func:`resample_segment`.

    Returns
    -------
    rings : list of list of list of ndarray of shape (m, 2)
        For each kept ring, for each segment, its resampled pieces: the segment
        split at its corners, so each piece is smooth. Consecutive pieces share end
        points.
    dropped : list of int
        Indices (into ``rings``) of holes dropped because their perimeter is less
        than three target edges (fewer than ``3 * points_per_edge`` distinct points
        after resampling): Gmsh would put fewer than three edges around them.

    Raises
    ------
    MeshingError
        If the exterior ring collapses to fewer than 3 points.

    Warns
    -----
    SmallIslandWarning
        Once, naming the number of dropped holes and the first few indices.

    Examples
    --------
    >>> box = [np.array([[0, 0], [100, 0], [100, 100], [0, 100], [0, 0]], float)]
    >>> tiny = [np.array([[50, 50], [51, 50], [51, 51], [50, 50]], float)]
    >>> import warnings
    >>> def size(xy):
    ...     return np.full(len(xy), 50.0)
    >>> with warnings.catch_warnings(record=True):
    ...     warnings.simplefilter("always")
    ...     kept, dropped = resample_rings([box, tiny], size)
    >>> len(kept), dropped
    (1, [1])
    """
    kept: list[list[list[NDArray[np.float64]]]] = []
    dropped: list[int] = []
    for r, ring in enumerate(rings):
        segments = []
        distinct = 0
        for coords in ring:
            points, corners = _resample(coords, size_at, points_per_edge, up)
            segments.append([points[a : b + 1] for a, b in itertools.pairwise(corners)])
            distinct += len(points) - 1
        # A hole needs three mesh edges around it; Gmsh puts about
        # ``distinct / points_per_edge`` edges on it.
        if distinct < (3 if r == 0 else 3 * points_per_edge):
            if r == 0:
                raise MeshingError(
                    f"the domain exterior collapses to {distinct} points at the "
                    "target size; the size field is larger than the domain"
                )
            dropped.append(r)
            continue
        kept.append(segments)
    if dropped:
        shown = ", ".join(str(d) for d in dropped[:5])
        more = ", ..." if len(dropped) > 5 else ""
        warnings.warn(
            f"{len(dropped)} islands smaller than the local target size were "
            f"dropped (ring {shown}{more}); the mesh covers them",
            SmallIslandWarning,
            stacklevel=2,
        )
    return kept, dropped


def check_boundary(
    rings: Sequence[Sequence[Sequence[NDArray[np.float64]]]],
    where: Callable[[float, float], str] | None = None,
) -> None:
    """Check that resampled rings still bound a valid polygon.

    Parameters
    ----------
    rings : sequence of sequence of sequence of ndarray of shape (m, 2)
        As :func:`resample_rings` returns them: for each ring, for each segment,
        its pieces; the exterior first.
    where : callable, optional
        ``where(x, y)`` names a point of the rings for the message (its
        longitude and latitude, say); by default the coordinates as they are.

    Raises
    ------
    MeshingError
        If the rings do not form a valid polygon (a ring crosses itself or
        another after resampling), with GEOS's reason.

    Examples
    --------
    >>> square = [[np.array([[0.0, 0], [1, 0], [1, 1], [0, 1], [0, 0]])]]
    >>> check_boundary([square]) is None
    True
    """
    coords = [
        np.concatenate([p[:-1] for seg in ring for p in seg] + [ring[0][0][:1]])
        for ring in rings
    ]
    polygon = shapely.Polygon(coords[0], coords[1:])
    if not polygon.is_valid:
        reason = shapely.is_valid_reason(polygon)
        found = re.search(r"\[([-\deE.+]+) ([-\deE.+]+)\]", reason)
        place = ""
        if found and where is not None:
            place = f" at {where(float(found[1]), float(found[2]))}"
        raise MeshingError(
            f"the boundary resampled to the target size is not a valid polygon "
            f"({reason}){place}: two coasts there are closer than the size "
            "resolves; close the water there ([domain] close at least the "
            "size), or make the size there smaller"
        )


def _resample(
    coords: ArrayLike, size_at: SizeAt, points_per_edge: float, up: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """Resample one polyline; also return the output indices of kept vertices."""
    xy = np.array(coords, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2 or xy.shape[0] < 2:
        raise ValueError(f"coords has shape {xy.shape}, expected (k, 2) with k >= 2")
    if not np.isfinite(xy).all():
        raise ValueError("coords has non-finite values")
    if not (np.isfinite(points_per_edge) and points_per_edge > 0):
        raise ValueError(f"points_per_edge is {points_per_edge}, expected > 0")
    # drop repeated consecutive vertices (keep the last one, an end point)
    keep = np.ones(len(xy), dtype=bool)
    keep[:-1] = (np.diff(xy, axis=0) != 0).any(axis=1)
    xy = xy[keep] if keep.sum() >= 2 else xy[[0, -1]]
    if len(xy) == 2 and (xy[0] == xy[1]).all():
        return xy, np.array([0, 1])

    h_vertex = _sizes(size_at, xy)
    edge = np.diff(xy, axis=0)
    length = np.hypot(edge[:, 0], edge[:, 1])
    corner = _corners(edge, length, h_vertex)

    # split each edge into steps of at most h / _SAMPLES_PER_SIZE
    h_edge = np.minimum(h_vertex[:-1], h_vertex[1:])
    steps = np.maximum(1, np.ceil(length * _SAMPLES_PER_SIZE / h_edge)).astype(np.intp)
    start = np.repeat(np.arange(len(edge)), steps)
    offset = np.arange(steps.sum()) - np.repeat(np.cumsum(steps) - steps, steps)
    t = offset / np.repeat(steps, steps)
    fine = np.vstack([xy[start] + t[:, None] * edge[start], xy[-1:]])
    vertex_at = np.append(np.cumsum(steps) - steps, len(fine) - 1)
    h_fine = _sizes(size_at, fine)
    h_fine[vertex_at] = h_vertex
    ds = np.hypot(*np.diff(fine, axis=0).T)
    arc = np.concatenate([[0.0], np.cumsum(ds)])
    s = np.concatenate(
        [[0.0], np.cumsum(0.5 * ds * (1 / h_fine[:-1] + 1 / h_fine[1:]))]
    )

    # equal steps of s between kept vertices
    kept = np.flatnonzero(corner)
    s_kept = s[vertex_at[kept]]
    edges = np.diff(s_kept) * points_per_edge
    # up: Gmsh's own rule for a curve, floor(s + 0.99) edges
    n = np.maximum(1, np.floor(edges + 0.99) if up else np.rint(edges)).astype(np.intp)
    piece = np.repeat(np.arange(len(n)), n)
    step = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    targets = s_kept[piece] + np.diff(s_kept)[piece] * step / n[piece]
    out_arc = np.interp(targets, s, arc)
    out = np.column_stack(
        [np.interp(out_arc, arc, fine[:, 0]), np.interp(out_arc, arc, fine[:, 1])]
    )
    out = np.vstack([out, xy[-1:]])
    out_kept = np.append(np.cumsum(n) - n, len(out) - 1)
    out[out_kept] = xy[kept]
    return out, out_kept


def _sizes(size_at: SizeAt, xy: NDArray[np.float64]) -> NDArray[np.float64]:
    h = np.asarray(size_at(xy), dtype=np.float64)
    if h.shape != (len(xy),):
        raise ValueError(
            f"size_at returned shape {h.shape}, expected ({len(xy)},): one size "
            "per position"
        )
    if not (np.isfinite(h).all() and (h > 0).all()):
        raise ValueError("size_at returned sizes that are not finite and > 0")
    return h


def _corners(
    edge: NDArray[np.float64], length: NDArray[np.float64], h: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Mark the end points and the vertices to keep as corners.

    Edges joined at (nearly) straight vertices count as one run, so a densified
    straight side still has a corner at its end.
    """
    corner = np.zeros(len(edge) + 1, dtype=bool)
    corner[[0, -1]] = True
    if len(edge) > 1:
        before, after = edge[:-1], edge[1:]
        cross = before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]
        dot = (before * after).sum(axis=1)
        turn = np.abs(np.arctan2(cross, dot))
        run = np.concatenate([[0], np.cumsum(turn >= _STRAIGHT_ANGLE)])
        run_length = np.bincount(run, weights=length)[run]
        long_enough = np.minimum(run_length[:-1], run_length[1:]) >= h[1:-1]
        corner[1:-1] = (turn > _CORNER_ANGLE) & long_enough
    return corner
