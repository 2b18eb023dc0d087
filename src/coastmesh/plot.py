"""Figures: shorelines drawn over their approximation, rasters side by side.

matplotlib is imported only when a plot is made. The ``plot_*`` functions draw on
an Axes (a new pyplot one when ``ax`` is None, on the Agg backend when there is no
display) and return it; the ``*_figure`` functions build a whole
:class:`matplotlib.figure.Figure` without pyplot, for :func:`save_figure`.
"""

from __future__ import annotations

import math
import os
import sys
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.io._atomic import atomic_write
from coastmesh.io._registry import plot_format
from coastmesh.types import Features

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "plot_raster_comparison",
    "plot_shoreline_overlay",
    "raster_figure",
    "save_figure",
    "shoreline_figure",
]

_DETAIL_FRACTION = 1 / 8


def plot_shoreline_overlay(
    original: Features | ArrayLike,
    simplified: Features | ArrayLike,
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
        ax = _pyplot().figure(figsize=(7, 7)).add_subplot()
    before, after = _geometries(original), _geometries(simplified)
    ax.add_collection(
        LineCollection(_contours(before), colors="0.3", linewidths=1.2, label=labels[0])
    )
    ax.add_collection(
        LineCollection(
            _contours(after), colors="tab:red", linewidths=0.9, label=labels[1]
        )
    )
    extent = bounds if bounds is not None else _total_bounds(before, after)
    if extent is not None:
        ax.set_xlim(extent[0], extent[2])
        ax.set_ylim(extent[1], extent[3])
    _geographic_axes(ax, _crs(crs), extent)
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
        figure = _pyplot().figure(figsize=(15, 4.5), layout="constrained")
        axes = figure.subplots(1, 3)
    axes = np.asarray(axes, dtype=object).ravel()
    if axes.size != 3:
        raise ValueError(f"axes must hold 3 Axes, got {axes.size}")
    before = np.asarray(original.values, dtype=np.float64)
    after = np.asarray(simplified.values, dtype=np.float64)
    extent = _raster_extent(original)
    units = original.attrs.get("units", "")
    finite = before[np.isfinite(before)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0, 1)
    difference = after - before
    spread = np.nanmax(np.abs(difference)) if np.isfinite(difference).any() else 0.0
    spread = float(spread) or 1.0
    from matplotlib.colors import Normalize

    relief, relief_norm = _relief_style(cmap, low, high)
    panels = (
        (before, "input", relief, relief_norm),
        (after, "PCA approximation", relief, relief_norm),
        (difference, "approximation - input", "RdBu_r", Normalize(-spread, spread)),
    )
    crs = _crs(original.attrs.get("crs"))
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
        _geographic_axes(ax, crs, bounds)
        bar = ax.figure.colorbar(image, ax=ax, shrink=0.85)
        if units:
            bar.set_label(units)
    return axes


def shoreline_figure(
    original: Features | ArrayLike,
    simplified: Features | ArrayLike,
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
    before = _geometries(original)
    extent = _total_bounds(before)
    width = 13.0
    if extent is not None and extent[3] > extent[1]:
        ratio = (
            (extent[2] - extent[0])
            / _x_stretch(_crs(crs), extent)
            / (extent[3] - extent[1])
        )
        width = min(max(2 * 6.0 * ratio, 6.0), 13.0) + 1.5
    figure = Figure(figsize=(width, 7.0), layout="constrained")
    whole, detail = figure.subplots(1, 2)
    plot_shoreline_overlay(original, simplified, whole, crs=crs)
    box = _detail_bounds(_geometries(original), _crs(crs))
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


def save_figure(
    figure: Figure,
    path: str | os.PathLike[str],
    *,
    overwrite: bool = False,
    dpi: int = 150,
) -> None:
    """Save a figure atomically; the format comes from the extension.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        What to save.
    path : str or path-like
        ``.png``, ``.pdf``, ``.svg``, ``.jpg`` or ``.jpeg``.
    overwrite : bool, default False
        Whether an existing file may be replaced.
    dpi : int, default 150
        Resolution of raster formats, in dots per inch.

    Raises
    ------
    FormatError
        If the extension is not a known image format.
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.
    """
    kind = plot_format(path)
    with atomic_write(path, overwrite=overwrite) as staged:
        figure.savefig(staged, format=kind, dpi=dpi)


def _pyplot() -> Any:
    """Import pyplot, on the Agg backend when there is no display."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError(
            "coastmesh's plots need matplotlib; install it with "
            "'pip install matplotlib'"
        ) from None
    headless = sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    )
    if (
        headless
        and "MPLBACKEND" not in os.environ
        and "matplotlib.pyplot" not in sys.modules
    ):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _relief_style(cmap: str | None, low: float, high: float) -> tuple[Any, Any]:
    """Colour map and norm for elevation: sea blues below 0, land above."""
    from matplotlib import colormaps
    from matplotlib.colors import LinearSegmentedColormap, Normalize, TwoSlopeNorm

    if cmap is not None or not low < 0 < high:
        return cmap or "terrain", Normalize(low, high)
    sea = colormaps["Blues_r"](np.linspace(0.0, 0.8, 128))
    land = colormaps["terrain"](np.linspace(0.25, 1.0, 128))
    colours = LinearSegmentedColormap.from_list("relief", np.vstack([sea, land]))
    return colours, TwoSlopeNorm(vmin=low, vcenter=0.0, vmax=high)


def _geometries(value: Features | ArrayLike) -> NDArray[np.object_]:
    if isinstance(value, Features):
        return value.geometry
    geometry = np.empty(len(value), dtype=object)  # type: ignore[arg-type]
    geometry[:] = list(value)  # type: ignore[call-overload]
    return geometry


def _contours(geometry: NDArray[np.object_]) -> list[NDArray[np.float64]]:
    """Every ring and line of the geometries, as (n, 2) coordinate arrays."""
    parts = shapely.get_parts(geometry[~shapely.is_missing(geometry)])
    polygons = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    lines = np.concatenate([shapely.get_rings(parts[polygons]), parts[~polygons]])
    coords, index = shapely.get_coordinates(lines, return_index=True)
    if not len(coords):
        return []
    cuts = np.flatnonzero(np.diff(index)) + 1
    return np.split(coords, cuts)


def _total_bounds(
    *arrays: NDArray[np.object_],
) -> tuple[float, float, float, float] | None:
    boxes = np.array([shapely.total_bounds(a) for a in arrays if len(a)])
    if boxes.size == 0 or np.isnan(boxes).all():
        return None
    minx, miny = np.nanmin(boxes[:, :2], axis=0)
    maxx, maxy = np.nanmax(boxes[:, 2:], axis=0)
    return float(minx), float(miny), float(maxx), float(maxy)


def _detail_bounds(
    geometry: NDArray[np.object_], crs: CRS | None
) -> tuple[float, float, float, float] | None:
    """Return a box around the middle vertex of the feature with most vertices."""
    extent = _total_bounds(geometry)
    if extent is None:
        return None
    counts = shapely.get_num_coordinates(geometry)
    biggest = geometry[int(np.argmax(counts))]
    coords = shapely.get_coordinates(biggest)
    x, y = coords[len(coords) // 2]
    stretch = _x_stretch(crs, extent)
    half = _DETAIL_FRACTION * max(
        (extent[2] - extent[0]) / stretch, extent[3] - extent[1]
    )
    half_x = half * stretch
    return float(x - half_x), float(y - half), float(x + half_x), float(y + half)


def _x_stretch(
    crs: CRS | None, extent: tuple[float, float, float, float] | None
) -> float:
    """How many x units make one y unit on the map: 1/cos(latitude) for lon/lat."""
    if crs is None or not crs.is_geographic:
        return 1.0
    middle = 0.0 if extent is None else (extent[1] + extent[3]) / 2
    return 1 / max(math.cos(math.radians(middle)), 0.05)


def _raster_extent(raster: xr.DataArray) -> tuple[float, float, float, float]:
    """Return ``(left, right, bottom, top)`` for ``imshow``."""
    from coastmesh.io.raster import raster_transform

    t = raster_transform(raster)
    ny, nx = raster.shape
    left, right = t.c, t.c + t.a * nx
    top, bottom = t.f, t.f + t.e * ny
    return float(left), float(right), float(bottom), float(top)


def _crs(value: CRS | str | None) -> CRS | None:
    if value is None or isinstance(value, CRS):
        return value
    return CRS.from_user_input(value)


def _geographic_axes(
    ax: Axes, crs: CRS | None, extent: tuple[float, float, float, float] | None
) -> None:
    """Label the axes and set an aspect ratio that keeps shapes."""
    if crs is not None and crs.is_geographic:
        ax.set_xlabel("longitude (degrees east)")
        ax.set_ylabel("latitude (degrees north)")
        ax.set_aspect(_x_stretch(crs, extent))
        return
    unit = ""
    if crs is not None and crs.axis_info:
        unit = f" ({crs.axis_info[0].unit_name})"
    ax.set_xlabel(f"x{unit}")
    ax.set_ylabel(f"y{unit}")
    ax.set_aspect("equal")
