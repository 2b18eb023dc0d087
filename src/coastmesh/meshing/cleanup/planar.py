"""Measures of triangles in a plane, for the cleanup's local decisions.

Each takes triangles as (k, 3, 2) coordinates in a conformal plane (where the
cleanup works), or nodes and their (M, 3) indices (:func:`sin_min_angles`, for
the smoothing's sweeps); :mod:`coastmesh.meshing.quality.mesh_quality` measures on
the Earth instead.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "radius_ratios",
    "signed_areas",
    "sin_min_angles",
    "smallest_r_in",
    "triangle_angles",
]


def triangle_angles(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the three angles (degrees) of triangles as (k, 3, 2) coordinates.

    Examples
    --------
    >>> triangle_angles(np.array([[[0, 0], [1, 0], [0, 1.0]]])).round(6).tolist()
    [[90.0, 45.0, 45.0]]
    """
    a = np.linalg.norm(xy[:, 1] - xy[:, 2], axis=1)
    b = np.linalg.norm(xy[:, 2] - xy[:, 0], axis=1)
    c = np.linalg.norm(xy[:, 0] - xy[:, 1], axis=1)

    def angle(
        opposite: NDArray[np.float64], s1: NDArray[np.float64], s2: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        cos = (s1**2 + s2**2 - opposite**2) / np.maximum(2 * s1 * s2, 1e-300)
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))

    return np.column_stack([angle(a, b, c), angle(b, c, a), angle(c, a, b)])


def signed_areas(xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the signed areas of triangles as (k, 3, 2) coordinates.

    Examples
    --------
    >>> signed_areas(np.array([[[0, 0], [2, 0], [0, 1.0]]])).tolist()
    [1.0]
    """
    d1, d2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def smallest_r_in(xy: ArrayLike) -> float:
    """Return the smallest inscribed radius of triangles as (k, 3, 2) coordinates.

    ``r_in = 2 A / perimeter``.

    Examples
    --------
    >>> xy = [[[0, 0], [3, 0], [0, 4.0]], [[0, 0], [2, 0], [0, 2.0]]]
    >>> round(smallest_r_in(xy), 9)
    0.585786438
    """
    xy = np.asarray(xy, dtype=float)
    sides = np.linalg.norm(xy - np.roll(xy, -1, axis=1), axis=2)
    return float((2 * np.abs(signed_areas(xy)) / sides.sum(axis=1)).min())


def radius_ratios(xy: ArrayLike) -> NDArray[np.float64]:
    """Return twice the inscribed over the circumscribed radius of triangles.

    Triangles as (k, 3, 2) coordinates; ``16 A^2 / (P a b c)``, 1 for an
    equilateral triangle, 0 for a flat one.

    Examples
    --------
    >>> radius_ratios([[[0, 0], [2, 0], [1, 3 ** 0.5]], [[0, 0], [4, 0], [0, 3.0]]])
    array([1. , 0.8])
    """
    xy = np.asarray(xy, dtype=float)
    sides = np.linalg.norm(xy - np.roll(xy, -1, axis=1), axis=2)
    area = signed_areas(xy)
    # numpy's stub: Any (np.linalg.norm of an array of unknown dtype)
    ratio: NDArray[np.float64] = (
        16 * area**2 / np.maximum(sides.sum(axis=1) * sides.prod(axis=1), 1e-300)
    )
    return ratio


def sin_min_angles(
    xy: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Return the sine of each triangle's minimum angle, negative if inverted.

    ``2 A c / (a b c)``, with ``c`` the shortest side; ``xy`` (N, 2) nodes,
    ``triangles`` (M, 3) their indices, counter-clockwise.

    Examples
    --------
    >>> xy = np.array([[0, 0], [1, 0], [0, 1.0]])
    >>> sin_min_angles(xy, np.array([[0, 1, 2], [0, 2, 1]])).round(6).tolist()
    [0.707107, -0.707107]
    """
    return _sines(*_sides(xy, triangles))


def sines_and_ratios(
    xy: NDArray[np.float64], triangles: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return :func:`sin_min_angles` and :func:`radius_ratios` at once.

    The same numbers, bit for bit, from one gather of the corners (the
    smoothing's guard needs both, many times over).

    Examples
    --------
    >>> xy = np.array([[0, 0], [4, 0], [0, 3.0]])
    >>> [v.round(6).tolist() for v in sines_and_ratios(xy, np.array([[0, 1, 2]]))]
    [[0.6], [0.8]]
    """
    d1, d2, d3, area2 = _sides(xy, triangles)
    sine = _sines(d1, d2, d3, area2)
    # the sides as radius_ratios measures them (a square root, not hypot)
    s0, s1, s2 = (np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]) for d in (d1, d3, d2))
    area = 0.5 * area2
    ratio = 16 * area**2 / np.maximum((s0 + s1 + s2) * (s0 * s1 * s2), 1e-300)
    return sine, ratio


def _sides(
    xy: NDArray[np.float64], triangles: NDArray[np.int64]
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]
]:
    """Return the side vectors 0->1, 0->2, 1->2 and twice the signed area."""
    p0, p1, p2 = (xy[triangles[:, i]] for i in range(3))
    d1, d2, d3 = p1 - p0, p2 - p0, p2 - p1
    return d1, d2, d3, d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


def _sines(
    d1: NDArray[np.float64],
    d2: NDArray[np.float64],
    d3: NDArray[np.float64],
    area2: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Return ``2 A c / (a b c)``, c the shortest side (0 for a degenerate one)."""
    a, b, c = np.hypot(*d1.T), np.hypot(*d2.T), np.hypot(*d3.T)
    product = a * b * c
    shortest = np.minimum(np.minimum(a, b), c)
    # numpy's stub: Any (np.hypot of unpacked columns)
    sine: NDArray[np.float64] = np.divide(
        area2 * shortest, product, out=np.zeros_like(area2), where=product > 0
    )
    return sine
