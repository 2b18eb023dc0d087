"""A global mesh seen from space: an orthographic view of the sphere."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from coastmesh.geometry import EARTH_RADIUS, reproject_points, transformer
from coastmesh.plot.base import SEA, shaded_mesh
from coastmesh.plot.mesh import _legend, _palette
from coastmesh.types.topology import unique_edges

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from coastmesh.types import Mesh

__all__ = ["globe_figure"]

#: Above this many visible triangles the globe figure draws the boundary only.
MAX_VISIBLE_TRIANGLES = 600_000


def globe_figure(
    mesh: Mesh,
    *,
    centre: tuple[float, float] = (0.0, 30.0),
    names: dict[int, str] | None = None,
    title: str | None = None,
) -> Figure:
    """Draw a lon/lat mesh of the globe in an orthographic view from ``centre``.

    The half of the sphere that faces the viewer is drawn: the sea (the
    triangles) on grey land, triangle edges (up to
    :data:`MAX_VISIBLE_TRIANGLES` triangles) and boundary edges by id, with the
    rim of the sphere. Triangles across the antimeridian are drawn as they are
    on the sphere.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[170, 0], [-170, 0], [180, 10]], [[0, 1, 2]],
    ...          [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, "EPSG:4326")
    >>> len(globe_figure(m, centre=(180.0, 0.0)).axes)
    1
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    lon0, lat0 = (float(v) for v in centre)
    view = (
        f"+proj=ortho +lat_0={lat0} +lon_0={lon0} +R={EARTH_RADIUS} +units=m +no_defs"
    )
    lonlat = reproject_points(mesh.points, mesh.crs, "EPSG:4326")
    x, y = transformer("EPSG:4326", view).transform(lonlat[:, 0], lonlat[:, 1])
    xy = np.column_stack([x, y]) / 1e3
    seen = np.all(np.isfinite(xy), axis=1)
    figure = Figure(figsize=(8, 8.4), layout="constrained")
    ax = figure.add_subplot()
    radius = EARTH_RADIUS / 1e3
    ax.add_patch(Circle((0, 0), radius, facecolor="0.85", edgecolor="0.3", lw=0.8))
    visible = mesh.triangles[seen[mesh.triangles].all(axis=1)]
    # the sea: the mesh's triangles, filled; land is what they leave grey
    _fill(ax, xy, visible, radius)
    if 0 < len(visible) <= MAX_VISIBLE_TRIANGLES:
        pairs, _ = unique_edges(visible, len(xy))
        ax.add_collection(
            LineCollection(list(xy[pairs]), colors="0.45", linewidths=0.08)
        )
    keep = seen[mesh.boundary_edges].all(axis=1)
    colours = _palette(np.unique(mesh.boundary_ids))
    ax.add_collection(
        LineCollection(
            list(xy[mesh.boundary_edges[keep]]),
            colors=[colours[int(i)] for i in mesh.boundary_ids[keep]],
            linewidths=0.7,
        )
    )
    labels = dict(mesh.boundary_names) if names is None else dict(names)
    # in a corner, outside the sphere's rim: nothing is drawn there
    _legend(ax, {i: labels.get(i, str(i)) for i in colours}, colours, "lower left")
    ax.set_xlim(-1.02 * radius, 1.02 * radius)
    ax.set_ylim(-1.02 * radius, 1.02 * radius)
    ax.set_aspect("equal")
    ax.set_axis_off()
    shown = f"{len(mesh.triangles):,} triangles, seen from ({lon0:g}, {lat0:g})"
    ax.set_title(f"{title}: {shown}" if title else shown, fontsize=10)
    return figure


def _fill(ax: Any, xy: np.ndarray, triangles: np.ndarray, radius: float) -> None:
    """Fill the triangles: as polygons when few, else as one shaded mesh.

    Half a million polygons take matplotlib a minute to draw (a path each);
    a Gouraud-shaded mesh of one colour is drawn by Agg's own triangle loop,
    out of the layout (:func:`~coastmesh.plot.base.shaded_mesh`): 1.1 million
    triangles in about 2 s, where a mask image through matplotlib's
    trapezoid map took 20.
    """
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import ListedColormap
    from matplotlib.tri import Triangulation

    sea = SEA
    if len(triangles) <= 50_000:
        ax.add_collection(PolyCollection(xy[triangles], facecolors=sea, lw=0))
        return
    used = np.unique(triangles)
    local = np.full(len(xy), -1)
    local[used] = np.arange(len(used))
    shaded_mesh(
        ax,
        Triangulation(xy[used, 0], xy[used, 1], local[triangles]),
        np.zeros(len(used)),
        cmap=ListedColormap([sea]),
        vmin=0.0,
        vmax=1.0,
        zorder=1,
    )
