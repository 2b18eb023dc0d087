"""The figure of a case's parts: where the water was cut, and each part's cost."""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.geometry import reproject_points
from coastmesh.plot.mesh import _fill_water, _frame, _plane_water, _unwrapped

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from coastmesh.meshing.parts.report import PartsReport
    from coastmesh.types import Domain

__all__ = ["parts_figure"]


def parts_figure(
    domain: Domain,
    parts: PartsReport,
    *,
    crs: Any = None,
    title: str | None = None,
) -> Figure:
    """Draw how the water was cut into parts: the cuts, and each part's cost.

    Parameters
    ----------
    domain : coastmesh.types.Domain
        The domain, in the CRS of ``parts``.
    parts : coastmesh.meshing.parts.report.PartsReport
        From :func:`coastmesh.meshing.engine.mesh_in_parts`.
    crs : pyproj.CRS or CRS-like, optional
        The CRS of ``parts`` (the mesh's); default ``domain.crs``.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        The water, the cuts in red, and for each part holding at least 0.5 %
        of the triangles its number, triangles and Gmsh seconds, at a point
        inside it (``parts.centres``) or, where labels would overlap, beside
        it with a line to it, or its number alone (:func:`_place_labels`).
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    crs = domain.crs if crs is None else CRS.from_user_input(crs)
    cuts = list(parts.cuts)
    plane = crs.is_geographic and domain.crs is not None and domain.crs.is_projected
    # a world map is twice as wide as it is high
    figure = Figure(figsize=(10, 6) if plane else (9, 8), layout="constrained")
    ax = figure.add_subplot()
    if plane:
        # meshed in a plane, written in lon/lat (a global case): the water as
        # a mask image, the coast and cuts split where they wrap round
        bounds = _plane_water(ax, domain, crs)
        cuts = [_unwrapped(_on_earth(c, crs, domain.crs)) for c in cuts]
    else:

        def here(xy: Any) -> NDArray[np.float64]:
            return reproject_points(np.asarray(xy, dtype=float), domain.crs, crs)

        _fill_water(ax, domain.polygon, here)
        outline = [here(s.coords) for s in domain.segments]
        ax.add_collection(LineCollection(outline, colors="0.45", linewidths=0.6))
        xy = np.concatenate(outline)
        bounds = (*xy.min(axis=0), *xy.max(axis=0))
    ax.add_collection(LineCollection(cuts, colors="#c0392b", linewidths=1.6, zorder=3))
    total = max(sum(parts.triangles), 1)
    labels = [
        (n, k + 1, xy, f"{k + 1}\n{n:,} tri\n{t:.1f} s")
        for k, (xy, n, t) in enumerate(
            zip(parts.centres, parts.triangles, parts.seconds, strict=False)
        )
        if n >= 0.005 * total  # a sliver of water a cut crosses: no label
    ]
    _frame(ax, bounds, crs)
    ax.set_title("\n".join(textwrap.wrap(title or parts.summary(), 90)), fontsize=9)
    _place_labels(figure, ax, labels)
    return figure


def _on_earth(xy: Any, lonlat: CRS, plane: CRS) -> NDArray[np.float64]:
    """Return a cut (``xy`` in lon/lat, straight in ``plane``) as drawn on the Earth.

    A straight line of the plane is a curve on the Earth: its points every
    1/200th of its length in the plane, moved back to lon/lat.
    """
    import shapely

    line = shapely.LineString(
        reproject_points(np.asarray(xy, dtype=float), lonlat, plane)
    )
    line = shapely.segmentize(line, max(line.length / 200.0, 1.0))
    return reproject_points(shapely.get_coordinates(line), plane, lonlat)


#: Where a part's label may go, in points from its centre: there, then around
#: it at growing distances (with a line to the centre), 8 ways at each.
_OFFSETS = [(0.0, 0.0)] + [
    (r * np.cos(a), r * np.sin(a))
    for r in (32.0, 52.0, 72.0)
    for a in np.radians([45, 135, 225, 315, 90, 270, 0, 180])
]


def _place_labels(figure: Figure, ax: Any, labels: list) -> None:
    """Draw the labels ``(triangles, number, centre, text)`` without overlaps.

    Larger parts first, each where it first fits inside the axes without
    touching a label placed before it: its whole text at its centre or around
    it, then its number alone the same way; a part with no room for either is
    named in a note in the lower left corner.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    renderer = FigureCanvasAgg(figure).get_renderer()
    figure.draw_without_rendering()  # the layout, so the boxes are where drawn
    frame = ax.get_window_extent(renderer)
    placed: list = []
    hidden = []
    for _, number, xy, text in sorted(labels, key=lambda item: (-item[0], item[1])):
        tries = [(text, at) for at in _OFFSETS[:17]]  # whole: not far off
        for words, (dx, dy) in tries + [(str(number), at) for at in _OFFSETS]:
            label = ax.annotate(
                words,
                xy,
                xytext=(dx, dy),
                textcoords="offset points",
                ha="center",
                va="center",
                fontsize=7,
                zorder=4 if dx == dy == 0 else 3.9,  # lines pass under boxes
                bbox={"boxstyle": "round", "fc": "white", "ec": "0.6", "alpha": 0.8},
                arrowprops=(
                    None
                    if dx == dy == 0
                    else {"arrowstyle": "-", "color": "0.3", "lw": 0.6}
                ),
            )
            label.get_window_extent(renderer)  # places it (and its line)
            box = Text.get_window_extent(label, renderer).padded(5)  # with its box
            inside = frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1)
            if inside and not any(box.overlaps(other) for other in placed):
                placed.append(box)
                break
            label.remove()
        else:
            hidden.append(number)
    if hidden:
        ax.text(
            0.01,
            0.01,
            f"not labelled (no room): part{'s' if len(hidden) > 1 else ''} "
            + ", ".join(map(str, sorted(hidden))),
            transform=ax.transAxes,
            fontsize=7,
            bbox={"fc": "white", "ec": "0.6", "alpha": 0.8},
        )
