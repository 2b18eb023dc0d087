"""Figures of mesh quality, of depth on the mesh and of the time step it allows.

Like :mod:`coastmesh.plot.mesh`, these build a :class:`matplotlib.figure.Figure`
without pyplot; save them with :func:`coastmesh.plot.save_figure`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from coastmesh.meshing import (
    QualityReport,
    edge_quality,
    element_time_steps,
    mesh_quality,
    triangle_quality,
)
from coastmesh.meshing.quality.report import EDGE_RATIO_RANGE, histograms
from coastmesh.plot.base import (
    across_dateline,
    flat_mesh,
    geographic_axes,
    shaded_mesh,
    x_stretch,
)

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

    from coastmesh.types import Mesh

__all__ = [
    "FLAT_TRIANGLES",
    "depth_figure",
    "depth_source_figure",
    "quality_figure",
    "time_step_figure",
]

#: Up to this many triangles, the time-step map gives each its flat colour.
FLAT_TRIANGLES = 500_000


def quality_figure(
    mesh: Mesh, report: QualityReport | None = None, *, title: str | None = None
) -> Figure:
    """Draw histograms of minimum angle, radius ratio and edge length / size.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        The mesh; the edge panel needs ``point_data["size"]`` (metres).
    report : QualityReport, optional
        :func:`~coastmesh.meshing.quality.mesh_quality` of ``mesh``, for the
        numbers in the panel titles; computed when not given.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels (minimum angle in degrees, radius ratio), or three with the
        edge length over target size on a logarithmic axis. Counts are per
        triangle (per edge in the third panel), on a logarithmic scale.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, None)
    >>> len(quality_figure(m).axes)
    2
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import NullFormatter

    if report is None:
        report = mesh_quality(mesh)
    drawn = report.histograms
    if not {"min_angle", "radius_ratio"} <= drawn.keys():  # a report without them
        drawn = histograms(triangle_quality(mesh), edge_quality(mesh))
    panels = 3 if "edge_ratio" in drawn else 2
    figure = Figure(figsize=(5 * panels, 4), layout="constrained")
    axes = figure.subplots(1, panels, squeeze=False)[0]
    a, r = report.min_angle, report.radius_ratio
    _histogram(axes[0], *drawn["min_angle"], (20, 30))
    axes[0].set_xlabel("minimum angle (degrees)")
    axes[0].set_title(
        f"min {a.min:.1f}, p5 {a.p5:.1f}; {a.below_30:,} below 30", fontsize="medium"
    )
    _histogram(axes[1], *drawn["radius_ratio"], ())
    axes[1].set_xlabel("radius ratio 2 r_in / r_circ")
    axes[1].set_title(f"min {r.min:.3f}, p5 {r.p5:.3f}", fontsize="medium")
    if panels == 3:
        counts, bins = drawn["edge_ratio"]
        low, high = bins[0], bins[-1]
        _histogram(axes[2], counts, bins, EDGE_RATIO_RANGE)
        axes[2].set_xscale("log")
        ticks = [t for t in 2.0 ** np.arange(-4, 5) if low <= t <= high]
        axes[2].set_xticks(ticks, [f"{t:g}" for t in ticks])
        axes[2].xaxis.set_minor_formatter(NullFormatter())
        axes[2].set_xlabel("edge length / target size")
        if report.edge_ratio is not None:
            axes[2].set_title(
                f"{100 * report.edge_ratio.within:.1f}% in [0.5, 2]",
                fontsize="medium",
            )
    axes[0].set_ylabel("count")
    figure.suptitle(
        (title or "mesh quality")
        + f": {report.triangles:,} triangles, {report.nodes:,} nodes"
    )
    return figure


def depth_figure(mesh: Mesh, *, title: str | None = None) -> Figure:
    """Draw the depth at the nodes on the mesh, in metres, positive down.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        With ``point_data["depth"]`` (metres, positive down), one value per node;
        triangles with a non-finite depth at a node are left blank.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        One map (with lon/lat axes and an aspect ratio that keeps shapes for a
        geographic CRS) and its colour bar.

    Raises
    ------
    ValueError
        If ``mesh.point_data`` has no ``"depth"``, or it is not one value per node.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, "EPSG:4326", {"depth": [5.0, 10.0, 20.0]})
    >>> len(depth_figure(m).axes)
    2
    """
    from matplotlib.figure import Figure
    from matplotlib.tri import Triangulation

    if "depth" not in mesh.point_data:
        raise ValueError(
            f"mesh.point_data has no 'depth' (it has {sorted(mesh.point_data)}); "
            "add one with mesh.with_point_data(depth=...)"
        )
    depth = np.asarray(mesh.point_data["depth"], dtype=np.float64)
    if depth.shape != (len(mesh.points),):
        raise ValueError(
            f"mesh.point_data['depth'] has shape {depth.shape}, expected "
            f"({len(mesh.points)},): one depth (metres) per node"
        )
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    finite = np.isfinite(depth)
    mask = ~finite[mesh.triangles].all(axis=1)
    mask |= across_dateline(mesh.points, mesh.triangles, mesh.crs)
    triangulation = Triangulation(
        x, y, mesh.triangles, mask=mask if mask.any() else None
    )
    figure = Figure(figsize=_map_size(mesh), layout="constrained")
    ax = figure.add_subplot()
    low, high = (
        (float(depth[finite].min()), float(depth[finite].max()))
        if finite.any()
        else (0.0, 1.0)
    )
    image = shaded_mesh(
        ax,
        triangulation,
        np.where(finite, depth, low),
        cmap="viridis_r",
        vmin=low,
        vmax=high,
    )
    figure.colorbar(image, ax=ax, label="depth (m, positive down)")
    _frame(ax, mesh.points)
    geographic_axes(ax, mesh.crs, _bounds(mesh.points))
    ax.ticklabel_format(useOffset=False)
    span = f"{low:,.1f} to {high:,.1f} m" if finite.any() else "no finite values"
    ax.set_title(f"{title or 'depth'}: {span}")
    return figure


def depth_source_figure(
    mesh: Mesh, names: Sequence[str], *, title: str | None = None
) -> Figure:
    """Draw which bathymetry source each node took its depth from.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        With ``point_data["depth_source"]``: the index of each node's source in
        ``names`` (-1 for none).
    names : sequence of str
        The sources, in priority order (``report.sources``).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        One map; each triangle coloured by the source of its first node's
        highest-priority source, with a legend of node counts.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, "EPSG:4326", {"depth_source": [0, 1, 1]})
    >>> len(depth_source_figure(m, ["survey", "gebco"]).axes)
    1
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    source = np.asarray(mesh.point_data.get("depth_source", ()), dtype=np.int64)
    if source.shape != (len(mesh.points),):
        raise ValueError(
            "mesh.point_data['depth_source'] must hold one source index per node "
            f"(it has {sorted(mesh.point_data)})"
        )
    # a triangle shows the best (lowest-index) source among its nodes
    shown = np.where(source < 0, len(names), source)[mesh.triangles].min(axis=1)
    figure = Figure(figsize=_map_size(mesh), layout="constrained")
    ax = figure.add_subplot()
    colours = [f"C{k % 10}" for k in range(len(names))] + ["0.6"]
    _by_category(ax, mesh, shown, colours)
    labels = [*(str(n).replace("\\", "/").rsplit("/", 1)[-1] for n in names)]
    labels.append("none (nearest cell)")
    handles = [
        Patch(color=colours[k], label=f"{labels[k]}: {int((source == k).sum()):,}")
        for k in range(len(names))
    ]
    if (source < 0).any():
        handles.append(Patch(color=colours[-1], label=labels[-1]))
    ax.legend(handles=handles, loc="upper left", fontsize="small", title="nodes")
    _frame(ax, mesh.points)
    geographic_axes(ax, mesh.crs, _bounds(mesh.points))
    ax.ticklabel_format(useOffset=False)
    ax.set_title(title or "bathymetry source of each node")
    return figure


def depth_rule_figure(
    mesh: Mesh, rules: NDArray[np.int8], *, title: str | None = None
) -> Figure:
    """Draw what each node's depth is: the raster's, wet cells, nearest, floored.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
    rules : ndarray of int, shape (N,)
        Each node's code in :data:`coastmesh.depth.nodes.RULES`
        (``DepthReport.rules``).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        One map; each triangle coloured by the highest code among its nodes
        (the raster's own depths in grey), with a legend of node counts and
        shares.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2], [2, 0]],
    ...          [1, 1, 1], 1, "EPSG:4326")
    >>> len(depth_rule_figure(m, np.array([0, 1, 2])).axes)
    1
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    from coastmesh.depth.nodes import RULES

    rules = np.asarray(rules, dtype=np.int64)
    if rules.shape != (len(mesh.points),):
        raise ValueError(
            f"rules has shape {rules.shape}: one code per node ({len(mesh.points)})"
        )
    shown = rules[mesh.triangles].max(axis=1)
    figure = Figure(figsize=_map_size(mesh), layout="constrained")
    ax = figure.add_subplot()
    colours = ["0.85", "C0", "C2", "C8", "C1", "C3", "C4"][: len(RULES)]
    _by_category(ax, mesh, shown, colours)
    n = max(len(rules), 1)
    handles = [
        Patch(
            color=colours[k],
            label=f"{RULES[k]}: {int((rules == k).sum()):,} "
            f"({(rules == k).sum() / n:.1%})",
        )
        for k in range(len(RULES))
        if (rules == k).any() or k == 0
    ]
    ax.legend(handles=handles, loc="upper left", fontsize="small", title="nodes")
    _frame(ax, mesh.points)
    geographic_axes(ax, mesh.crs, _bounds(mesh.points))
    ax.ticklabel_format(useOffset=False)
    ax.set_title(title or "what each node's depth is")
    return figure


def _by_category(
    ax: Axes, mesh: Mesh, shown: NDArray[np.int64], colours: list[str]
) -> None:
    """Colour each triangle flat by its category ``shown`` (an index of ``colours``).

    Triangles across the antimeridian are left out.
    """
    from matplotlib.colors import ListedColormap

    keep = ~across_dateline(mesh.points, mesh.triangles, mesh.crs)
    flat_mesh(
        ax,
        mesh.points,
        mesh.triangles[keep],
        shown[keep],
        cmap=ListedColormap(colours),
        vmin=-0.5,
        vmax=len(colours) - 0.5,
    )


def time_step_figure(
    mesh: Mesh,
    *,
    dt: float | None = None,
    velocity: float = 0.0,
    title: str | None = None,
) -> Figure:
    """Map each triangle's stable time step and, at ``dt``, its Courant number.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        With ``point_data["depth"]`` (metres, positive down).
    dt : float, optional
        A model time step, seconds: adds a map of the Courant numbers at it.
    velocity : float, default 0
        Velocity scale added to the wave speed, m/s.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        One map of ``r_in / (sqrt(g d) + u)`` per triangle, seconds, on a
        logarithmic colour scale, with the smallest (the step the whole mesh
        runs at) circled and labelled; with ``dt`` a second map of
        ``dt (sqrt(g d) + u) / h`` with the largest circled. Each map has its
        colour bar. Triangles that limit nothing (dry, or no depth) are blank.
        See :func:`~coastmesh.meshing.quality.time_step.element_time_steps`. A mesh of
        more than :data:`FLAT_TRIANGLES` triangles (most smaller than a pixel)
        is shaded from its nodes, each the worst value of its triangles:
        matplotlib draws a flat colour per triangle as one polygon each, 16 s
        of a 2.9-million-triangle mesh, against about 3 s.

    Raises
    ------
    ValueError
        As for :func:`~coastmesh.meshing.quality.time_step.element_time_steps`.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [100, 0], [0, 100]], [[0, 1, 2]],
    ...          [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, None,
    ...          {"depth": [5.0, 10.0, 20.0]})
    >>> len(time_step_figure(m, dt=1.0).axes)
    4
    """
    from matplotlib.figure import Figure

    values = element_time_steps(mesh, velocity=velocity, dt=dt)
    panels = [("dt", "stable time step (s)", "min", "viridis")]
    if dt is not None:
        panels.append(("courant", f"Courant number at dt = {dt:g} s", "max", "magma"))
    figure = Figure(figsize=_map_size(mesh, len(panels)), layout="constrained")
    for ax, (key, label, pick, cmap) in zip(
        figure.subplots(1, len(panels), squeeze=False)[0], panels, strict=True
    ):
        _element_map(ax, mesh, values[key], label=label, pick=pick, cmap=cmap)
    speed = f", velocity {velocity:g} m/s" if velocity else ""
    figure.suptitle(f"{title or 'time step'}: r_in / (sqrt(g d) + u){speed}")
    return figure


def _element_map(
    ax: Axes,
    mesh: Mesh,
    values: NDArray[np.float64],
    *,
    label: str,
    pick: str,
    cmap: str,
) -> None:
    """One value per triangle, log colours, the smallest or largest circled."""
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import FuncFormatter, NullFormatter
    from matplotlib.tri import Triangulation

    shown = np.isfinite(values) & (values > 0)
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    hidden = ~shown | across_dateline(mesh.points, mesh.triangles, mesh.crs)
    triangulation = Triangulation(
        x, y, mesh.triangles, mask=hidden if hidden.any() else None
    )
    low, high = (
        (float(values[shown].min()), float(values[shown].max()))
        if shown.any()
        else (1.0, 10.0)
    )
    norm = LogNorm(low, high if high > low else low * 10)
    # not in the layout: its extent is the axes', and matplotlib would turn a
    # shaded mesh into one path per triangle to measure it (38 s at 2.9 M)
    if len(mesh.triangles) <= FLAT_TRIANGLES:
        image = ax.tripcolor(
            triangulation, facecolors=np.where(shown, values, low), cmap=cmap, norm=norm
        )
        image.set_in_layout(False)
    else:  # each node the worst of its triangles (see time_step_figure)
        at_nodes = np.full(len(x), np.inf if pick == "min" else -np.inf)
        worst = np.minimum if pick == "min" else np.maximum
        worst.at(at_nodes, mesh.triangles[shown].ravel(), np.repeat(values[shown], 3))
        at_nodes[~np.isfinite(at_nodes)] = low
        image = shaded_mesh(
            ax, triangulation, at_nodes, in_layout=False, cmap=cmap, norm=norm
        )
    bar = ax.figure.colorbar(image, ax=ax, label=label)
    plain = FuncFormatter(lambda value, _: f"{value:g}")
    bar.ax.yaxis.set_major_formatter(plain)  # 0.5, 2, 10, not 5e-01, 2x10^0
    bar.ax.yaxis.set_minor_formatter(plain if high < 20 * low else NullFormatter())
    _frame(ax, mesh.points)
    geographic_axes(ax, mesh.crs, _bounds(mesh.points))
    ax.ticklabel_format(useOffset=False)
    if not shown.any():
        ax.set_title(f"{label}: no finite values")
        return
    index = np.flatnonzero(shown)
    best = np.argmin if pick == "min" else np.argmax
    k = int(index[best(values[index])])
    cx, cy = mesh.points[mesh.triangles[k]].mean(axis=0)
    ax.plot(
        cx,
        cy,
        marker="o",
        markersize=16,
        markerfacecolor="none",
        markeredgecolor="#c44e52",
        markeredgewidth=2,
    )
    text = f"{pick} {values[k]:.3g}"
    # the label towards the map's middle: never over the title or off the map
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    on_right = cx > x0 + 0.7 * (x1 - x0)
    on_top = cy > y0 + 0.7 * (y1 - y0)
    ax.annotate(
        text,
        (cx, cy),
        xytext=(-12 if on_right else 12, -12 if on_top else 12),
        ha="right" if on_right else "left",
        va="top" if on_top else "bottom",
        textcoords="offset points",
        color="#c44e52",
        fontweight="bold",
        bbox={"boxstyle": "round", "facecolor": "white", "alpha": 0.8},
    )
    ax.set_title(f"{label}: {text} (triangle {k}), range {low:.3g} to {high:.3g}")


def _histogram(
    ax: Axes,
    counts: NDArray[np.int64],
    bins: NDArray[np.float64],
    marks: tuple[float, ...],
) -> None:
    ax.stairs(counts, bins, fill=True, color="#4c72b0")
    ax.set_yscale("log")
    for mark in marks:
        ax.axvline(mark, color="#c44e52", linestyle="--", linewidth=1)


def _bounds(points: NDArray[np.float64]) -> tuple[float, float, float, float]:
    minx, miny = points.min(axis=0)
    maxx, maxy = points.max(axis=0)
    return float(minx), float(miny), float(maxx), float(maxy)


def _map_size(mesh: Mesh, panels: int = 1) -> tuple[float, float]:
    """Return a figure size that fits the mesh's map, ``panels`` side by side.

    The map's own shape (a world map is twice as wide as it is high), not a
    square with empty bands and a colour bar twice the map's height.
    """
    minx, miny, maxx, maxy = _bounds(mesh.points)
    shape = (maxy - miny) * x_stretch(mesh.crs, (minx, miny, maxx, maxy))
    shape = min(max(shape / max(maxx - minx, 1e-12), 0.35), 1.4)
    return (9.0 * panels, max(4.5, 7.0 * shape + 1.6))


def _frame(ax: Axes, points: NDArray[np.float64]) -> None:
    minx, miny, maxx, maxy = _bounds(points)
    padx, pady = 0.02 * (maxx - minx), 0.02 * (maxy - miny)
    ax.set_xlim(minx - padx, maxx + padx)
    ax.set_ylim(miny - pady, maxy + pady)
