"""The figure of a tidal site: farms, turbine footprints and the mesh around them."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from coastmesh.plot.base import geographic_axes
from coastmesh.types.topology import region_interfaces

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from coastmesh.types import Mesh

__all__ = ["site_figure"]


def site_figure(
    mesh: Mesh,
    turbines: list[tuple[str, float, float]],
    *,
    wakes: list[np.ndarray] | None = None,
    title: str | None = None,
) -> Figure:
    """Draw a site: its regions, outlines, turbines and lines, and one up close.

    Parameters
    ----------
    mesh : Mesh
        With ``regions`` (farms and footprints: ids other than its
        ``surface_id``).
    turbines : list of (name, x, y)
        The turbines, in ``mesh.crs``.
    wakes : list of ndarray of shape (k, 2), optional
        The wakes' outlines, in ``mesh.crs`` (drawn dashed).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Left: the site and 30 % around it, triangles coloured by region, the
        outlines between regions in black, the turbines as red crosses, the
        wakes dashed, the lines (``mesh.lines``) in blue. Right:
        the first turbine and three rotor diameters around it.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(13, 6), layout="constrained")
    left, right = figure.subplots(1, 2)
    site = mesh.regions != mesh.surface_id
    xy = mesh.points
    corners = np.array([[x, y] for _, x, y in turbines]).reshape(-1, 2)
    if site.any():
        corners = xy[mesh.triangles[site]].reshape(-1, 2)
    corners = np.concatenate([corners, *(line.xy for line in mesh.lines)])
    if wakes:
        corners = np.concatenate([corners, *wakes])
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    pad = 0.3 * np.maximum(hi - lo, 1e-9)
    _draw(left, mesh, turbines, (*(lo - pad), *(hi + pad)))
    for ring in wakes or []:
        left.plot(ring[:, 0], ring[:, 1], "--", color="tab:red", lw=1.0)
    left.set_title("the site: elements by region")
    if turbines:
        name, x, y = turbines[0]
        span = _turbine_span(mesh, x, y)
        _draw(right, mesh, turbines, (x - span, y - span, x + span, y + span))
        right.set_title(f"turbine {name}")
    else:
        right.set_axis_off()
    figure.suptitle(title or "site")
    return figure


def _turbine_span(mesh: Mesh, x: float, y: float) -> float:
    """Half the side of the close-up: a few of the nearest elements' sizes."""
    centres = mesh.points[mesh.triangles].mean(axis=1)
    near = np.argsort(np.hypot(centres[:, 0] - x, centres[:, 1] - y))[:60]
    p = mesh.points[mesh.triangles[near]]
    return float(4 * np.hypot(*(p.max(axis=1) - p.min(axis=1)).T).max())


def _draw(ax: Axes, mesh: Mesh, turbines, window: tuple[float, ...]) -> None:
    """Draw the triangles in ``window`` coloured by region, outlines, turbines."""
    from matplotlib.collections import LineCollection, PolyCollection

    x0, y0, x1, y1 = window
    p = mesh.points[mesh.triangles]
    inside = (
        (p[:, :, 0].max(axis=1) >= x0)
        & (p[:, :, 0].min(axis=1) <= x1)
        & (p[:, :, 1].max(axis=1) >= y0)
        & (p[:, :, 1].min(axis=1) <= y1)
    )
    ids = mesh.region_ids
    colours = _colours(ids, mesh.surface_id)
    faces = [colours[int(r)] for r in mesh.regions[inside]]
    ax.add_collection(
        PolyCollection(p[inside], facecolors=faces, edgecolors="0.35", linewidths=0.2)
    )
    outlines = mesh.points[region_interfaces(mesh)]
    ax.add_collection(LineCollection(list(outlines), colors="k", linewidths=1.0))
    for line in mesh.lines:
        ax.plot(*line.xy.T, "-", color="tab:blue", lw=1.6)
        ax.annotate(line.name, line.xy[len(line.xy) // 2], color="tab:blue", fontsize=8)
    for _, tx, ty in turbines:
        ax.plot(tx, ty, "r+", markersize=8, mew=1.5)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    geographic_axes(ax, mesh.crs, (x0, y0, x1, y1))
    from matplotlib.ticker import MaxNLocator

    ax.ticklabel_format(useOffset=False)
    ax.xaxis.set_major_locator(MaxNLocator(4))
    from matplotlib.patches import Patch

    names = {mesh.surface_id: "domain", **mesh.region_names}
    shown = [i for i in ids if i in set(mesh.regions[inside].tolist())][:8]
    ax.legend(
        handles=[
            Patch(color=colours[i], label=f"{i}: {names.get(i, '')}") for i in shown
        ],
        loc="upper right",
        fontsize=8,
    )


def _colours(ids: list[int], surface_id: int) -> dict[int, Any]:
    """Return a colour per region: the domain white, each other its own."""
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    out: dict[int, Any] = {surface_id: (1.0, 1.0, 1.0, 1.0)}
    for k, i in enumerate(i for i in ids if i != surface_id):
        r, g, b, _ = cmap(k % 10)
        out[i] = (r, g, b, 0.35)  # light enough to see the mesh through
    return out
