"""The figure of a patch: the mesh before and after, around the hole."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from coastmesh.plot.base import geographic_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from coastmesh.types import Mesh

__all__ = ["patch_figure"]


def patch_figure(
    before: Mesh,
    after: Mesh,
    removed: NDArray[np.bool_],
    added: NDArray[np.int64],
    outline: NDArray[np.float64],
    *,
    title: str | None = None,
) -> Figure:
    """Draw a mesh before and after a patch, around the hole.

    Parameters
    ----------
    before, after : Mesh
        The input and the patched mesh, in one CRS.
    removed : ndarray of bool of shape (M_before,)
        The input's elements cut out (drawn red on the left).
    added : ndarray of int
        The patched mesh's new elements (drawn blue on the right).
    outline : ndarray of shape (k, 2)
        The polygon cut, in the meshes' CRS (dashed).
    title : str, optional
        Figure title.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(13, 6), layout="constrained")
    left, right = figure.subplots(1, 2)
    corners = before.points[before.triangles[removed]].reshape(-1, 2)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    pad = 0.4 * np.maximum(hi - lo, 1e-9)
    window = (*(lo - pad), *(hi + pad))
    mark = np.zeros(len(after.triangles), dtype=bool)
    mark[added] = True
    _draw(left, before, removed, "tab:red", window, outline)
    left.set_title(f"before: {int(removed.sum()):,} elements cut out (red)")
    _draw(right, after, mark, "tab:blue", window, outline)
    right.set_title(f"after: {len(added):,} new elements (blue)")
    figure.suptitle(title or "patch")
    return figure


def _draw(
    ax: Axes,
    mesh: Mesh,
    marked: NDArray[np.bool_],
    colour: str,
    window: tuple[float, ...],
    outline: NDArray[np.float64],
) -> None:
    """Draw the triangles in ``window``, the marked ones in ``colour``."""
    from matplotlib.collections import PolyCollection

    x0, y0, x1, y1 = window
    p = mesh.points[mesh.triangles]
    inside = (
        (p[:, :, 0].max(axis=1) >= x0)
        & (p[:, :, 0].min(axis=1) <= x1)
        & (p[:, :, 1].max(axis=1) >= y0)
        & (p[:, :, 1].min(axis=1) <= y1)
    )
    kept = inside & ~marked
    ax.add_collection(
        PolyCollection(p[kept], facecolors="0.95", edgecolors="0.45", linewidths=0.3)
    )
    ax.add_collection(
        PolyCollection(
            p[inside & marked], facecolors="none", edgecolors=colour, linewidths=0.2
        )
    )
    ax.plot(outline[:, 0], outline[:, 1], "--", color="k", lw=1.0)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    geographic_axes(ax, mesh.crs, (x0, y0, x1, y1))
