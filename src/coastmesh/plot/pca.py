"""Figures of the PCA: shorelines over their approximation, rasters side by side.

matplotlib is imported only when a plot is made. The ``plot_*`` functions draw on
an Axes (a new pyplot one when ``ax`` is None, on the Agg backend when there is no
display) and return it; the ``*_figure`` functions build a whole
:class:`matplotlib.figure.Figure` without pyplot, for :func:`save_figure`.
"""

from __future__ import annotations

from collections.abc import Collection
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.plot.base import (
    as_crs,
    contours,
    detail_bounds,
    geographic_axes,
    geometry_array,
    pyplot,
    raster_extent,
    relief_style,
    total_bounds,
    x_stretch,
)
from coastmesh.types import Features

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "plot_raster_comparison",
    "plot_shoreline_overlay",
    "raster_figure",
    "shoreline_figure",
]


def plot_shoreline_overlay(
    original: Features | Collection[Any],
    simplified: Features | Collection[Any],
    ax: Axes | None = None,
    *,
    crs: CRS | str | None = None,
    bounds: tuple[float, float, float, float] | None = None,
    labels: tuple[str, str] = ("input", "PCA approximation"),
) -> Axes:
    """Draw a shoreline and its approximation over each other.

    Parameters
    ----------
    original, simplified : Features or array_like of shapely geometries
        The input and the result; polygons are drawn as their rings.
    ax : matplotlib Axes, optional
        Where to draw; a new figure by default.
    crs : pyproj.CRS or str, optional
        The coordinates' CRS, for the axis labels and, for longitude/latitude, an
        aspect ratio that keeps shapes. Taken from ``original`` if it is Features.
    bounds : tuple of 4 floats, optional
        ``(minx, miny, maxx, maxy)`` to show, in CRS units; everything by default.
    labels : tuple of 2 str
        Legend entries for ``original`` and ``simplified``.

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import shapely
    >>> ring = shapely.Point(0, 0).buffer(1.0)
    >>> ax = plot_shoreline_overlay([ring], [ring.simplify(0.2)])
    >>> len(ax.collections)
    2
    """
    from matplotlib.collections import LineCollection

    if crs is None and isinstance(original, Features):
        crs = original.crs
    if ax is None:
        ax = pyplot().figure(figsize=(7, 7)).add_subplot()
    before, after = geometry_array(original), geometry_array(simplified)
    ax.add_collection(
        LineCollection(contours(before), colors="0.3", linewidths=1.2, label=labels[0])
    )
    ax.add_collection(
        LineCollection(
            contours(after), colors="tab:red", linewidths=0.9, label=labels[1]
        )
    )
    extent = bounds if bounds is not None else total_bounds(before, after)
    if extent is not None:
        ax.set_xlim(extent[0], extent[2])
        ax.set_ylim(extent[1], extent[3])
    geographic_axes(ax, as_crs(crs), extent)
    ax.legend(loc="upper right", fontsize="small")
    return ax


def plot_raster_comparison(
    original: xr.DataArray,
    simplified: xr.DataArray,
    axes: ArrayLike | None = None,
    *,
    cmap: str | None = None,
) -> NDArray[np.object_]:
    """Draw a raster, its approximation and their difference side by side.

    Parameters
    ----------
    original, simplified : xarray.DataArray of shape (ny, nx)
        As returned by :func:`coastmesh.io.read_raster`, on the same grid.
    axes : sequence of 3 matplotlib Axes, optional
        Where to draw; a new figure with three panels by default.
    cmap : str, optional
        Colour map of the two maps. By default blues below 0 and land colours
        above, split at 0 (sea level for elevation). The difference uses a
        diverging map centred on 0.

    Returns
    -------
    ndarray of 3 matplotlib Axes
        Input, approximation, and approximation minus input.

    Raises
    ------
    ValueError
        If the rasters differ in shape or ``axes`` does not hold 3 Axes.
    """
    if original.shape != simplified.shape:
        raise ValueError(
            f"rasters differ in shape: {original.shape} and {simplified.shape}"
        )
    if axes is None:
        figure = pyplot().figure(figsize=(15, 4.5), layout="constrained")
        axes = figure.subplots(1, 3)
    axes = np.asarray(axes, dtype=object).ravel()
    if axes.size != 3:
        raise ValueError(f"axes must hold 3 Axes, got {axes.size}")
    before = np.asarray(original.values, dtype=np.float64)
    after = np.asarray(simplified.values, dtype=np.float64)
    extent = raster_extent(original)
    units = original.attrs.get("units", "")
    finite = before[np.isfinite(before)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0, 1)
    difference = after - before
    spread = np.nanmax(np.abs(difference)) if np.isfinite(difference).any() else 0.0
    spread = float(spread) or 1.0
    from matplotlib.colors import Normalize

    relief, relief_norm = relief_style(cmap, low, high)
    panels = (
        (before, "input", relief, relief_norm),
        (after, "PCA approximation", relief, relief_norm),
        (difference, "approximation - input", "RdBu_r", Normalize(-spread, spread)),
    )
    crs = as_crs(original.attrs.get("crs"))
    bounds = (extent[0], extent[2], extent[1], extent[3])
    for ax, (values, title, colours, norm) in zip(axes, panels, strict=True):
        image = ax.imshow(
            values,
            extent=extent,
            origin="upper",
            cmap=colours,
            norm=norm,
            interpolation="nearest",
        )
        ax.set_title(title)
        geographic_axes(ax, crs, bounds)
        bar = ax.figure.colorbar(image, ax=ax, shrink=0.85)
        if units:
            bar.set_label(units)
    return axes


def shoreline_figure(
    original: Features | Collection[Any],
    simplified: Features | Collection[Any],
    *,
    crs: CRS | str | None = None,
    title: str | None = None,
) -> Figure:
    """Build a figure: the whole shoreline overlay, and a detail of it.

    Parameters
    ----------
    original, simplified : Features or array_like of shapely geometries
        The input and the result.
    crs : pyproj.CRS or str, optional
        The coordinates' CRS (see :func:`plot_shoreline_overlay`).
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels; the detail is centred on a vertex of the feature with the
        most vertices and spans 1/8 of the layer's extent.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    if crs is None and isinstance(original, Features):
        crs = original.crs
    before = geometry_array(original)
    extent = total_bounds(before)
    width = 13.0
    if extent is not None and extent[3] > extent[1]:
        ratio = (
            (extent[2] - extent[0])
            / x_stretch(as_crs(crs), extent)
            / (extent[3] - extent[1])
        )
        width = min(max(2 * 6.0 * ratio, 6.0), 13.0) + 1.5
    figure = Figure(figsize=(width, 7.0), layout="constrained")
    whole, detail = figure.subplots(1, 2)
    plot_shoreline_overlay(original, simplified, whole, crs=crs)
    box = detail_bounds(geometry_array(original), as_crs(crs))
    if box is not None:
        plot_shoreline_overlay(original, simplified, detail, crs=crs, bounds=box)
        whole.add_patch(
            Rectangle(
                (box[0], box[1]),
                box[2] - box[0],
                box[3] - box[1],
                fill=False,
                edgecolor="tab:blue",
                linewidth=1.5,
            )
        )
        detail.set_title("detail (blue box)")
    whole.set_title("whole layer")
    if title:
        figure.suptitle(title)
    return figure


def raster_figure(
    original: xr.DataArray, simplified: xr.DataArray, *, title: str | None = None
) -> Figure:
    """Build a figure with :func:`plot_raster_comparison`'s three panels.

    Parameters
    ----------
    original, simplified : xarray.DataArray of shape (ny, nx)
        The input and the result.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(16, 4.8), layout="constrained")
    plot_raster_comparison(original, simplified, figure.subplots(1, 3))
    if title:
        figure.suptitle(title)
    return figure
