"""Land polygons from a gridded elevation model: the coast as a contour.

:func:`land_from_grid` takes a grid of elevations (or depths) and returns the
land above a level as valid polygons, with the coast at sub-cell accuracy:
marching squares (:mod:`contourpy`) places each coast vertex on a grid edge
where the linear interpolation of the two samples equals the level.
"""

from __future__ import annotations

import logging
from typing import cast

import contourpy
import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.geometry.layers import valid_polygons

__all__ = ["land_from_grid"]

logger = logging.getLogger(__name__)

_SIGNS = {"up": 1.0, "down": -1.0}


def land_from_grid(
    x: ArrayLike,
    y: ArrayLike,
    values: ArrayLike,
    level: float = 0.0,
    *,
    positive: str = "up",
) -> NDArray[np.object_]:
    """Return the land of a grid of elevations or depths as valid polygons.

    Parameters
    ----------
    x : array_like of shape (nx,)
        The samples' x coordinates (CRS units), strictly increasing or
        decreasing, ``nx >= 2``.
    y : array_like of shape (ny,)
        The samples' y coordinates, likewise (north-up rasters: decreasing).
    values : array_like of shape (ny, nx)
        Heights (``positive="up"``) or depths (``positive="down"``) in metres,
        at ``(y[i], x[j])``; NaN where there is no data.
    level : float
        The height of the coast above the grid's datum, in metres, positive up
        whatever the sign of ``values``: land is where the height is above it,
        that is ``values > level`` for ``"up"`` and ``values < -level`` for
        ``"down"``.
    positive : {"up", "down"}
        The sign of ``values``.

    Returns
    -------
    ndarray of shapely Polygons, shape (k,)
        The land, in the grid's coordinates; lakes (water enclosed by land) are
        holes. Empty when no sample is above the level.

    Raises
    ------
    ValueError
        If the shapes do not match, a coordinate is not finite or not strictly
        monotonic, a value is infinite, ``level`` is not finite or ``positive``
        is unknown.

    Notes
    -----
    The grid's cells are the quads between four neighbouring samples. A coast
    vertex lies on a quad edge, at the linear interpolation of the level
    between the edge's two samples; within a quad the coast is straight. A
    saddle quad (land at two opposite corners only) joins the two land corners
    when the mean of its four samples is above the level. Land that reaches
    the edge of the grid is closed along its outermost samples. Quads with a
    missing corner are not land: land stops at the last quad with four samples,
    as at the edge of the grid, so nodata is treated as water (a void inside
    land becomes a lake). The polygons are made valid with
    :func:`~coastmesh.geometry.valid_polygons` (a ring that touches itself
    where samples equal the level exactly is split).

    References
    ----------
    W. E. Lorensen and H. E. Cline, "Marching cubes: a high resolution 3D
    surface construction algorithm", SIGGRAPH 1987 (the 2-D case).

    Examples
    --------
    >>> import numpy as np
    >>> x = y = np.linspace(-2.0, 2.0, 5)
    >>> height = 1.0 - np.abs(x)[None, :] - np.abs(y)[:, None]
    >>> land = land_from_grid(x, y, height, 0.0)
    >>> len(land), float(land[0].area)
    (1, 2.0)
    >>> land_from_grid(x, y, -height, 0.0, positive="down")[0].equals(land[0])
    True
    """
    xs, ys, heights = _checked(x, y, values, level, positive)
    above = heights > level
    if not above.any():
        return np.empty(0, dtype=object)
    generator = contourpy.contour_generator(
        xs,
        ys,
        heights,
        name="serial",
        corner_mask=False,
        fill_type=contourpy.FillType.OuterOffset,
    )
    # FillType.OuterOffset: contourpy returns (points, offsets), one per polygon
    points, offsets = cast(
        "tuple[list[NDArray[np.float64]], list[NDArray[np.uint32]]]",
        generator.filled(float(level), np.inf),
    )
    polygons = _polygons(points, offsets)
    invalid = int((~shapely.is_valid(polygons)).sum())
    land = valid_polygons(polygons)
    logger.debug(
        "land above %g m: %d polygons from a %d x %d grid (%d repaired)",
        level,
        len(land),
        *heights.shape,
        invalid,
    )
    return land


def _checked(
    x: ArrayLike, y: ArrayLike, values: ArrayLike, level: float, positive: str
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Check the arguments; return x, y and the heights (positive up)."""
    grid = np.asarray(values, dtype=np.float64)
    if grid.ndim != 2:
        raise ValueError(f"values must be 2-D (ny, nx), got shape {grid.shape}")
    coords = []
    for name, axis, size in (("x", x, grid.shape[1]), ("y", y, grid.shape[0])):
        c = np.asarray(axis, dtype=np.float64)
        if c.ndim != 1 or len(c) != size:
            raise ValueError(
                f"{name} has shape {c.shape}; values has shape {grid.shape}, so "
                f"{name} must have shape ({size},)"
            )
        if size < 2:
            raise ValueError(f"{name} has {size} sample; need at least 2")
        if not np.isfinite(c).all():
            raise ValueError(f"{name} has non-finite coordinates")
        step = np.diff(c)
        if not ((step > 0).all() or (step < 0).all()):
            raise ValueError(f"{name} must be strictly increasing or decreasing")
        coords.append(c)
    if np.isinf(grid).any():
        raise ValueError(
            f"values has {int(np.isinf(grid).sum())} infinite cells; use NaN for "
            "missing data"
        )
    if not np.isfinite(level):
        raise ValueError(f"level = {level!r}: must be a finite number (metres)")
    if positive not in _SIGNS:
        raise ValueError(f"positive = {positive!r}: expected 'up' or 'down'")
    heights = grid if positive == "up" else -grid
    return coords[0], coords[1], heights


def _polygons(
    points: list[NDArray[np.float64]], offsets: list[NDArray[np.uint32]]
) -> NDArray[np.object_]:
    """Build polygons from contourpy's ``OuterOffset`` output (shell, holes...)."""
    if not points:
        return np.empty(0, dtype=object)
    coords = np.concatenate(points)
    starts = np.cumsum([0] + [len(p) for p in points[:-1]])
    rings = np.concatenate(
        [o[:-1].astype(np.int64) + s for o, s in zip(offsets, starts, strict=True)]
        + [np.array([len(coords)])]
    )
    per_polygon = np.cumsum([0] + [len(o) - 1 for o in offsets])
    return shapely.from_ragged_array(
        shapely.GeometryType.POLYGON, coords, (rings, per_polygon)
    )
