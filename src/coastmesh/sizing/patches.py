"""Fine patches of a size grid: metre-scale sizes at a site in a coarse field.

A tidal site asks for sizes of a few metres (a quarter of a rotor diameter)
where the field around it is hundreds of metres, on a grid whose cells are
the field's. :func:`site_patch` makes nested finer grids around the site
alone (:attr:`~coastmesh.types.SizeGrid.patches`), each level's cells half
its parent's, each over the water where the sizes need its cells: the
smaller of the coarse field and the site's sizes, which grow at the field's
``rate`` (so the patches meet the field without a step).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.projection import sample_size
from coastmesh.types import SizeGrid

__all__ = ["site_patch", "with_patches"]

Sizes = Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]


def site_patch(
    base: SizeGrid,
    box: tuple[float, float, float, float],
    sizes: Sizes,
    *,
    smallest: float,
    rate: float,
) -> list[SizeGrid]:
    """Return nested patches of ``base`` around ``box`` with a site's sizes.

    Parameters
    ----------
    base : SizeGrid
        The field.
    box : (minx, miny, maxx, maxy)
        The site, in the grid's coordinates.
    sizes : callable
        ``sizes(x, y)``: the site's sizes at arrays of points, graded already
        (``inf`` where it asks for none): at most ``rate`` of growth per metre.
    smallest : float
        The smallest size the site asks for.
    rate : float
        The gradation limit the sizes keep (``|grad h| <= rate``).

    Returns
    -------
    list of SizeGrid
        Levels of cells half as large as the last, from half the base's cell
        down to half of ``smallest``: each covers the box of its parent's
        cells where the sizes are under two of its parent's cells (one cell
        more all round), on whole cells of its parent. Their values are
        ``min(base, sizes)``. A quadtree of levels, so the cells
        follow the sizes: a turbine of metres in a field of hundreds of metres
        takes tens of thousands of cells, not millions.

    Examples
    --------
    >>> base = SizeGrid(np.arange(0.0, 1001, 100), np.arange(0.0, 1001, 100),
    ...                 np.full((11, 11), 100.0))
    >>> cone = lambda x, y: 5.0 + 0.2 * np.maximum(np.hypot(x - 500, y - 500) - 10, 0)
    >>> levels = site_patch(base, (490, 490, 510, 510), cone, smallest=5.0, rate=0.2)
    >>> [float(p.x[1] - p.x[0]) for p in levels]
    [50.0, 25.0, 12.5, 6.25, 3.125, 1.5625]
    >>> round(float(levels[-1].values.min()), 6), float(levels[0].values.max())
    (5.0, 100.0)
    """
    step = float(np.min(np.diff(base.x)))
    # the base's nodes near the site, and the sizes there
    reach = max(2 * step - smallest, 0.0) / rate + 2 * step
    x0, y0, x1, y1 = box
    i0, i1 = _snap(base.x, x0 - reach, x1 + reach)
    j0, j1 = _snap(base.y, y0 - reach, y1 + reach)
    xs, ys = base.x[i0 : i1 + 1], base.y[j0 : j1 + 1]
    xx, yy = np.meshgrid(xs, ys)
    values = np.minimum(base.values[j0 : j1 + 1, i0 : i1 + 1], sizes(xx, yy))
    levels = []
    while step > smallest / 2:
        # the parent's cells too coarse for the sizes at a corner, one more
        # cell all round: the next level covers them (one box)
        rows, cols = np.nonzero(values < 2 * step)
        if not len(rows):
            break
        a, b = max(cols.min() - 1, 0), min(cols.max() + 1, len(xs) - 1)
        c, d = max(rows.min() - 1, 0), min(rows.max() + 1, len(ys) - 1)
        b, d = max(b, a + 1), max(d, c + 1)
        step /= 2
        xs, ys = _split(xs[a : b + 1], step), _split(ys[c : d + 1], step)
        xx, yy = np.meshgrid(xs, ys)
        coarse = sample_size(base, np.column_stack([xx.ravel(), yy.ravel()]))
        values = np.minimum(coarse.reshape(xx.shape), sizes(xx, yy))
        levels.append(SizeGrid(xs, ys, values))
    return levels


def with_patches(base: SizeGrid, patches: list[SizeGrid]) -> SizeGrid:
    """Return ``base`` with ``patches`` (and those it had)."""
    return SizeGrid(base.x, base.y, base.values, base.scale, (*base.patches, *patches))


def _snap(axis: NDArray[np.float64], low: float, high: float) -> tuple[int, int]:
    """Return the node indices of ``axis`` at or beyond ``low`` and ``high``."""
    i0 = int(np.clip(np.searchsorted(axis, low, side="right") - 1, 0, len(axis) - 2))
    i1 = int(np.clip(np.searchsorted(axis, high, side="left"), i0 + 1, len(axis) - 1))
    return i0, i1


def _split(nodes: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Split each interval of ``nodes`` into equal steps of at most ``step``.

    Every node of ``nodes`` is kept exactly (a crop of the base grid then
    falls on nodes of every level).
    """
    out = [nodes[:1]]
    for a, b in itertools.pairwise(nodes):
        n = max(math.ceil((b - a) / step - 1e-9), 1)
        seg = a + (b - a) * np.arange(1, n + 1) / n
        seg[-1] = b
        out.append(seg)
    return np.concatenate(out)
