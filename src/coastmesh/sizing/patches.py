"""Fine patches of a size grid: metre-scale sizes at a site in a coarse field.

A tidal site asks for sizes of a few metres (a quarter of a rotor diameter)
where the field around it is hundreds of metres, on a grid whose cells are
the field's. :func:`site_patch` makes a finer grid over the site's cells
alone (:attr:`~coastmesh.types.SizeGrid.patches`): the smaller of the coarse
field and the site's sizes, graded at ``rate`` (the field's own gradation
limit, :func:`~coastmesh.sizing.gradation.limit_gradation`), over a margin
wide enough that the site's sizes have grown to the field's at its edge.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry.projection import sample_size
from coastmesh.sizing.gradation import limit_gradation
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
) -> SizeGrid:
    """Return a patch of ``base`` over ``box`` and a margin, with a site's sizes.

    Parameters
    ----------
    base : SizeGrid
        The field (no patches of its own over ``box``).
    box : (minx, miny, maxx, maxy)
        The site, in the grid's coordinates.
    sizes : callable
        ``sizes(x, y)``: the site's sizes at arrays of points (``inf`` where it
        asks for none).
    smallest : float
        The smallest size the site asks for: the patch's cells are half of it.
    rate : float
        The gradation limit (``|grad h| <= rate``).

    Returns
    -------
    SizeGrid
        From base nodes to base nodes, each base cell split evenly; ``min(base,
        sizes)`` limited at ``rate``. The margin around ``box`` is where the
        site's sizes have grown at ``rate`` to the largest base size over the
        box, so the patch meets the field without a step.

    Examples
    --------
    >>> base = SizeGrid(np.arange(0.0, 1001, 100), np.arange(0.0, 1001, 100),
    ...                 np.full((11, 11), 100.0))
    >>> spot = lambda x, y: np.where(np.hypot(x - 500, y - 500) < 10, 5.0, np.inf)
    >>> p = site_patch(base, (490, 490, 510, 510), spot, smallest=5.0, rate=0.2)
    >>> [round(float(v), 6) for v in (p.values.min(), p.values.max(), p.x[0], p.x[-1])]
    [5.0, 100.0, 0.0, 1000.0]
    """
    x0, y0, x1, y1 = box
    sample = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [(x0 + x1) / 2, y0]])
    top = float(np.max(sample_size(base, sample)))
    margin = max(top - smallest, 0.0) / rate + 2 * top
    lo = _snap(base.x, x0 - margin, base.y, y0 - margin, low=True)
    hi = _snap(base.x, x1 + margin, base.y, y1 + margin, low=False)
    xs = _split(base.x[lo[0] : hi[0] + 1], smallest / 2)
    ys = _split(base.y[lo[1] : hi[1] + 1], smallest / 2)
    xx, yy = np.meshgrid(xs, ys)
    coarse = sample_size(base, np.column_stack([xx.ravel(), yy.ravel()]))
    values = np.minimum(coarse.reshape(xx.shape), sizes(xx, yy))
    dx, dy = float(np.diff(xs).min()), float(np.diff(ys).min())
    values = limit_gradation(values, (dx, dy), rate)
    return SizeGrid(xs, ys, values)


def with_patches(base: SizeGrid, patches: list[SizeGrid]) -> SizeGrid:
    """Return ``base`` with ``patches`` (merged where two would overlap)."""
    return SizeGrid(base.x, base.y, base.values, base.scale, tuple(patches))


def _snap(x, at_x, y, at_y, *, low: bool) -> tuple[int, int]:
    """Return the base node indices at or beyond ``(at_x, at_y)``, clamped."""
    if low:
        i = int(np.clip(np.searchsorted(x, at_x, side="right") - 1, 0, len(x) - 2))
        j = int(np.clip(np.searchsorted(y, at_y, side="right") - 1, 0, len(y) - 2))
    else:
        i = int(np.clip(np.searchsorted(x, at_x, side="left"), 1, len(x) - 1))
        j = int(np.clip(np.searchsorted(y, at_y, side="left"), 1, len(y) - 1))
    return i, j


def _split(nodes: NDArray[np.float64], step: float) -> NDArray[np.float64]:
    """Split each interval of ``nodes`` into equal steps of at most ``step``."""
    out = [nodes[:1]]
    for a, b in itertools.pairwise(nodes):
        n = max(math.ceil((b - a) / step - 1e-9), 1)
        out.append(a + (b - a) * np.arange(1, n + 1) / n)
    out[-1][-1] = nodes[-1]
    return np.concatenate(out)
