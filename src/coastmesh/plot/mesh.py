"""Figures of a case: the domain with its boundary ids, the mesh, the size field.

Like :mod:`coastmesh.plot`, these build a :class:`matplotlib.figure.Figure`
without pyplot; save them with :func:`coastmesh.plot.save_figure`. Boundary ids
get the same colour in every figure.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.geometry import reproject_points
from coastmesh.geometry.sphere import is_world_plane
from coastmesh.plot.base import SEA, across_dateline, geographic_axes

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.typing import LegendLocType

    from coastmesh.types import Domain, Mesh

__all__ = [
    "domain_figure",
    "mercator_figure",
    "mesh_figure",
    "size_figure",
]

#: Above this many triangles the mesh figure draws the boundary only.
MAX_DRAWN_TRIANGLES = 400_000


def _palette(ids: Any) -> dict[int, Any]:
    """One distinct colour per boundary id, in increasing id order."""
    from matplotlib import colormaps

    ids = sorted({int(i) for i in ids})
    cmap = colormaps["tab10" if len(ids) <= 10 else "tab20"]
    return {i: cmap(k % cmap.N) for k, i in enumerate(ids)}


def _legend(
    ax: Axes,
    labels: dict[int, str],
    colours: dict[int, Any],
    loc: LegendLocType = "best",
) -> None:
    """Draw the boundary ids' legend at ``loc`` (as matplotlib's).

    Give a fixed ``loc`` on axes that hold a shaded mesh: to find the "best"
    place, matplotlib turns every triangle into a path (5.8 s of the globe of
    the 1.5-million-triangle world mesh).
    """
    from matplotlib.lines import Line2D

    handles = [
        Line2D([], [], color=colours[i], linewidth=2.5, label=f"{i}: {name}")
        for i, name in sorted(labels.items())
    ]
    ax.legend(handles=handles, title="boundary id", loc=loc, fontsize="small")


def domain_figure(domain: Domain, *, title: str | None = None) -> Figure:
    """Draw a domain: its boundary segments coloured by physical id.

    Parameters
    ----------
    domain : coastmesh.meshing.Domain
        The domain.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment, Domain
    >>> ring = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    >>> d = Domain(shapely.Polygon(ring),
    ...            (BoundarySegment(ring, "open", "sea", 2),), crs="EPSG:32630")
    >>> len(domain_figure(d).axes[0].collections)  # the water, the boundary
    2
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure
    from pyproj import CRS

    colours = _palette(s.physical_id for s in domain.segments)
    if domain.crs is not None and is_world_plane(CRS.from_user_input(domain.crs)):
        # a global case's plane: drawn on a lon/lat map, twice as wide as high
        figure = Figure(figsize=(10, 6), layout="constrained")
        ax = figure.add_subplot()
        lonlat = CRS.from_epsg(4326)
        # (a coarser mask than the parts figure's: it is drawn while the
        # water is meshed, on the same cores; the coast lines are exact)
        bounds = _plane_water(ax, domain, lonlat, colours, pixels=(720, 360))
        _frame(ax, bounds, lonlat)
    else:
        figure = Figure(figsize=(9, 8), layout="constrained")
        ax = figure.add_subplot()
        _fill_water(ax, domain.polygon)
        ax.add_collection(
            LineCollection(
                [s.coords for s in domain.segments],
                colors=[colours[s.physical_id] for s in domain.segments],
                linewidths=1.2,
            )
        )
        _frame(ax, domain.polygon.bounds, domain.crs)
    _legend(ax, {s.physical_id: s.name for s in domain.segments}, colours)
    if title:
        ax.set_title(title)
    return figure


def mesh_figure(
    mesh: Mesh,
    *,
    names: dict[int, str] | None = None,
    title: str | None = None,
) -> Figure:
    """Draw a mesh: its triangles, and its boundary edges coloured by id.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        The mesh.
    names : dict of int to str, optional
        Names of the boundary ids for the legend; default
        ``mesh.boundary_names``.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Meshes with more than :data:`MAX_DRAWN_TRIANGLES` triangles are drawn by
        their boundary only (the title says so).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(9, 8), layout="constrained")
    ax = figure.add_subplot()
    points = mesh.points
    note = ""
    if len(mesh.triangles) > MAX_DRAWN_TRIANGLES:
        note = f" (boundary only: {len(mesh.triangles):,} triangles)"
    ids = np.unique(mesh.boundary_ids)
    colours = _palette(ids)
    _draw_mesh(ax, points, mesh, mesh.triangles, colours, linewidth=1.2)
    bounds = (*points.min(axis=0), *points.max(axis=0))
    _frame(ax, bounds, mesh.crs)
    labels = {**mesh.boundary_names, **(names or {})}
    _legend(ax, {int(i): labels.get(int(i), "") for i in ids}, colours)
    ax.set_title(
        (title or "mesh")
        + f": {len(points):,} nodes, {len(mesh.triangles):,} triangles{note}"
    )
    return figure


def size_figure(field: xr.DataArray, *, title: str | None = None) -> Figure:
    """Draw a size field (metres) on a logarithmic colour scale.

    Parameters
    ----------
    field : xarray.DataArray
        Dims ``("y", "x")``, values in metres, a ``crs`` attr.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, ax, x, y, values = _grid_axes(field, (9, 8))
    low, high = float(np.nanmin(values)), float(np.nanmax(values))
    image = _log_image(ax, x, y, values, (low, high), "viridis")
    figure.colorbar(image, ax=ax, label="target element size (m)")
    _grid_frame(ax, field, x, y)
    if title:
        ax.set_title(title)
    return figure


def channel_figure(
    width: xr.DataArray,
    *,
    report: Any = None,
    title: str | None = None,
) -> Figure:
    """Draw the width of the water, with the narrow channels marked.

    Parameters
    ----------
    width : xarray.DataArray
        The channel term's width of the water (metres; NaN off the domain,
        inf where wide).
    report : coastmesh.sizing.ChannelReport, optional
        Its narrow channels are circled and its floor drawn as a contour
        (``2 h_min``: narrower water cannot take two elements).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, ax, x, y, values = _grid_axes(width, (10, 6))
    finite = values[np.isfinite(values) & (values > 0)]
    wide = np.where(np.isinf(values), 1.0, np.nan)
    ax.pcolormesh(x, y, wide, shading="nearest", cmap="Greys", vmin=0, vmax=4)
    if len(finite):
        low, high = float(finite.min()), float(finite.max())
        shown = np.where(np.isfinite(values), values, np.nan)
        image = _log_image(ax, x, y, shown, (low, high), "magma")
        figure.colorbar(image, ax=ax, label="width of the water (m); grey: wider")
    if report is not None:
        floor = 2 * report.h_min
        ax.contour(
            x,
            y,
            np.nan_to_num(values, nan=np.inf),
            levels=[floor],
            colors="cyan",
            linewidths=0.6,
        )
        for c in report.worst:
            ax.plot(c.x, c.y, "o", mfc="none", mec="red", ms=9)
        note = (
            f"{report.narrow_channels} narrower than 2 x {report.h_min:g} m (cyan "
            f"contour; largest circled), {report.closed} closed\n"
            f"{report.elements_across:g} elements across set the size on "
            f"{report.limited_km2:,.0f} km2"
        )
        title = f"{title}\n{note}" if title else note
    _grid_frame(ax, width, x, y)
    if title:
        ax.set_title(title, fontsize=10)
    return figure


def _grid_axes(field: xr.DataArray, size: tuple[float, float]) -> tuple:
    """Return a figure of ``size`` inches, its axes, and a grid's x, y, values."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=size, layout="constrained")
    x, y = field["x"].values, field["y"].values
    return figure, figure.add_subplot(), x, y, np.asarray(field.values, dtype=float)


def _log_image(
    ax: Axes,
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    values: NDArray[np.float64],
    span: tuple[float, float],
    cmap: str,
) -> Any:
    """Draw a grid's cells, coloured on a log scale over ``span`` where it is > 0."""
    from matplotlib.colors import LogNorm

    low, high = span
    norm = LogNorm(low, high) if high > low > 0 else None
    return ax.pcolormesh(x, y, values, shading="nearest", cmap=cmap, norm=norm)


def _grid_frame(
    ax: Axes, field: xr.DataArray, x: NDArray[np.float64], y: NDArray[np.float64]
) -> None:
    """Frame the axes on a grid, with its CRS's graticule where it has one."""
    from pyproj import CRS

    crs = CRS.from_user_input(field.attrs["crs"]) if "crs" in field.attrs else None
    _frame(ax, (x.min(), y.min(), x.max(), y.max()), crs)


def _draw_mesh(
    ax: Axes,
    xy: NDArray[np.float64],
    mesh: Mesh,
    triangles: NDArray[np.int64],
    colours: dict[int, Any],
    *,
    linewidth: float,
) -> None:
    """Draw triangles (up to MAX_DRAWN_TRIANGLES) and boundary edges by id."""
    from matplotlib.collections import LineCollection

    # which cross the antimeridian is asked of the mesh's own coordinates
    # (``xy`` may be Mercator kilometres)
    if 0 < len(triangles) <= MAX_DRAWN_TRIANGLES:
        shown = triangles[~across_dateline(mesh.points, triangles, mesh.crs)]
        if len(shown):
            ax.triplot(xy[:, 0], xy[:, 1], shown, color="0.55", lw=0.2)
    keep = ~across_dateline(mesh.points, mesh.boundary_edges, mesh.crs)
    ax.add_collection(
        LineCollection(
            list(xy[mesh.boundary_edges[keep]]),
            colors=[colours[int(i)] for i in mesh.boundary_ids[keep]],
            linewidths=linewidth,
        )
    )


def _fill_water(ax: Axes, polygon: Any, here: Any = None) -> None:
    """Fill a polygon, its holes left out, as one path (the caller sets limits).

    One compound path, its holes turning the other way (non-zero winding):
    ``ax.fill`` per ring measured every vertex for the axis limits, 9 s of the
    NW-shelf fine domain's 185,000 vertices.
    """
    import shapely
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    polygon = shapely.orient_polygons(polygon)
    rings = [polygon.exterior, *polygon.interiors]
    paths = [
        Path(np.asarray(r.coords) if here is None else here(r.coords), closed=True)
        for r in rings
    ]
    patch = PathPatch(Path.make_compound_path(*paths))
    fill = PatchCollection([patch], facecolors=SEA, edgecolors="none", zorder=0)
    ax.add_collection(fill, autolim=False)


def _frame(ax: Axes, bounds: tuple[float, ...], crs: Any) -> None:
    minx, miny, maxx, maxy = (float(v) for v in bounds)
    padx, pady = 0.02 * (maxx - minx), 0.02 * (maxy - miny)
    ax.set_xlim(minx - padx, maxx + padx)
    ax.set_ylim(miny - pady, maxy + pady)
    geographic_axes(ax, crs, (minx, miny, maxx, maxy))


#: The latitude the Mercator map stops at, north and south.
MERCATOR_LAT = 85.0


def mercator_figure(
    mesh: Mesh,
    *,
    detail: tuple[float, float, float, float] | None = None,
    names: dict[int, str] | None = None,
    title: str | None = None,
) -> Figure:
    """Draw a mesh in Mercator (EPSG:3395), whole and around a detail box.

    The paper's figure 5 style: the whole mesh, and a detail (e.g. Orkney) with
    its triangles, both in the ellipsoidal Mercator projection, so shapes are kept
    and north is up.

    Parameters
    ----------
    mesh : coastmesh.meshing.Mesh
        The mesh; its CRS must be known.
    detail : (lon_min, lat_min, lon_max, lat_max), optional
        The detail box in longitude/latitude; none: the whole mesh only.
    names : dict of int to str, optional
        Names of the boundary ids for the legend; default
        ``mesh.boundary_names``.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    if mesh.crs is None:
        raise ValueError("the mesh has no CRS; Mercator needs one")
    xy = reproject_points(mesh.points, mesh.crs, "EPSG:3395") / 1000.0  # km
    panels = 2 if detail is not None else 1
    figure = Figure(figsize=(8 * panels, 8), layout="constrained")
    axes = np.atleast_1d(figure.subplots(1, panels))
    ids = np.unique(mesh.boundary_ids)
    colours = _palette(ids)

    def draw(ax: Axes, triangles: NDArray[np.int64]) -> None:
        _draw_mesh(ax, xy, mesh, triangles, colours, linewidth=1.0)
        ax.set_aspect("equal")
        ax.set_xlabel("Mercator x (km)")
        ax.set_ylabel("Mercator y (km)")

    draw(axes[0], mesh.triangles)
    finite = np.isfinite(xy).all(axis=1)
    lo, hi = xy[finite].min(axis=0), xy[finite].max(axis=0)
    # Mercator's y runs to infinity at the poles: the map stops at 85 degrees
    edge = reproject_points([[0.0, MERCATOR_LAT]], "EPSG:4326", "EPSG:3395")[0, 1]
    y0, y1 = max(lo[1], -edge / 1000.0), min(hi[1], edge / 1000.0)
    axes[0].set_xlim(lo[0], hi[0])
    axes[0].set_ylim(y0, y1)
    clipped = " (to 85 deg of latitude)" if (y0, y1) != (lo[1], hi[1]) else ""
    axes[0].set_title(
        f"{len(mesh.points):,} nodes, {len(mesh.triangles):,} triangles{clipped}"
    )
    if detail is not None:
        corners = [detail[:2], detail[2:]]
        (x0, y0), (x1, y1) = reproject_points(corners, mesh.crs, "EPSG:3395") / 1000
        centre = xy[mesh.triangles].mean(axis=1)
        inside = (
            (centre[:, 0] >= x0)
            & (centre[:, 0] <= x1)
            & (centre[:, 1] >= y0)
            & (centre[:, 1] <= y1)
        )
        draw(axes[1], mesh.triangles[inside])
        axes[1].set_xlim(x0, x1)
        axes[1].set_ylim(y0, y1)
        axes[1].set_title(f"detail: {int(inside.sum()):,} triangles")
        axes[0].add_patch(
            Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor="k", lw=1.2)
        )
    labels = {**mesh.boundary_names, **(names or {})}
    _legend(axes[0], {int(i): labels.get(int(i), "") for i in ids}, colours)
    if title:
        figure.suptitle(title)
    return figure


#: Pixels of the water mask of a domain meshed in a plane, across and up.
_MASK = (1440, 720)


def _plane_water(
    ax: Any,
    domain: Domain,
    crs: Any,
    colours: dict[int, Any] | None = None,
    pixels: tuple[int, int] = _MASK,
) -> tuple[float, ...]:
    """Draw a plane's water (a global case's) on a lon/lat map; its bounds.

    The water as a mask image of ``pixels`` (each pixel's centre tested in
    the plane, so nothing wraps) and the coast as lines, cut where they
    cross the antimeridian: grey, or coloured by physical id.
    """
    import shapely
    from matplotlib.collections import LineCollection

    lon = np.linspace(-180.0, 180.0, pixels[0] + 1)
    lat = np.linspace(-90.0, 90.0, pixels[1] + 1)
    glon, glat = np.meshgrid(0.5 * (lon[1:] + lon[:-1]), 0.5 * (lat[1:] + lat[:-1]))
    pxy = reproject_points(
        np.column_stack([glon.ravel(), glat.ravel()]), crs, domain.crs
    )
    wet = shapely.contains_xy(domain.polygon, pxy[:, 0], pxy[:, 1]).reshape(glon.shape)
    image = np.where(wet, 1.0, np.nan)
    ax.imshow(
        image,
        extent=(-180.0, 180.0, -90.0, 90.0),
        origin="lower",
        cmap=_one_colour(),
        interpolation="nearest",
        zorder=0,
    )
    outline = [
        _unwrapped(reproject_points(np.asarray(s.coords), domain.crs, crs))
        for s in domain.segments
    ]
    colors = (
        "0.45" if colours is None else [colours[s.physical_id] for s in domain.segments]
    )
    ax.add_collection(LineCollection(outline, colors=colors, linewidths=0.6))
    rows = np.flatnonzero(wet.any(axis=1))
    south = float(lat[rows[0]]) if len(rows) else -90.0
    north = float(lat[rows[-1] + 1]) if len(rows) else 90.0
    return (-180.0, south, 180.0, north)


def _one_colour() -> Any:
    from matplotlib.colors import ListedColormap

    return ListedColormap([SEA])


def _unwrapped(lonlat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return a lon/lat line with a gap (NaN) wherever it jumps round the Earth."""
    jump = np.flatnonzero(np.abs(np.diff(lonlat[:, 0])) > 180.0)
    return np.insert(lonlat, jump + 1, np.nan, axis=0)
