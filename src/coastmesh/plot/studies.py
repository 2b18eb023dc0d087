"""Figures of the paper's PCA studies (``coastmesh run`` with ``[case] kind``).

The shoreline study draws every reconstruction over the original
(:func:`overlay_figure`); the bathymetry study draws the approximations as maps
and as surfaces, the eigenvalue spectrum, and the error against the number of
modes. Each builds a :class:`matplotlib.figure.Figure` without pyplot.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.plot.base import (
    as_crs,
    contours,
    geographic_axes,
    raster_extent,
    relief_style,
    total_bounds,
    x_stretch,
)

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = [
    "overlay_figure",
    "relief_maps_figure",
    "relief_surfaces_figure",
    "rms_figure",
    "spectrum_figure",
]

_COLOURS = ("tab:purple", "tab:red", "tab:blue", "tab:green", "tab:orange", "tab:cyan")
_KM_PER_DEGREE = 111.32  # one degree of latitude (and of longitude at the equator)


def overlay_figure(
    original: NDArray[np.object_],
    layers: list[tuple[str, NDArray[np.object_]]],
    *,
    crs: CRS | str,
    detail: tuple[float, float, float, float],
    view: str = "whole",
    label: str = "original",
) -> Figure:
    """Draw reconstructions of a shoreline over the original, whole or in detail.

    Parameters
    ----------
    original : ndarray of shapely geometries
        The shoreline.
    layers : list of (str, ndarray of shapely geometries)
        Each reconstruction and its legend entry.
    crs : pyproj.CRS or str
        The coordinates' CRS (axis labels and aspect).
    detail : (minx, miny, maxx, maxy)
        The detail box: drawn dashed on the whole view, the extent of the
        detail view.
    view : {"whole", "detail"}
    label : str
        Legend entry of the original.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    pyproj_crs = as_crs(crs)
    box, width = (total_bounds(original), 0.5) if view == "whole" else (detail, 1.2)
    assert box is not None  # the study's shorelines hold land polygons
    ratio = (box[2] - box[0]) / x_stretch(pyproj_crs, box) / (box[3] - box[1])
    figure = Figure(figsize=(min(max(9 * ratio, 5), 16) + 2, 9), layout="constrained")
    ax = figure.add_subplot()
    ax.add_collection(
        LineCollection(
            contours(original), colors="0.15", linewidths=width * 1.4, label=label
        )
    )
    for k, (name, out) in enumerate(layers):
        ax.add_collection(
            LineCollection(
                contours(out),
                colors=_COLOURS[k % len(_COLOURS)],
                linewidths=width,
                label=name,
            )
        )
    ax.set_xlim(box[0], box[2])
    ax.set_ylim(box[1], box[3])
    geographic_axes(ax, pyproj_crs, box)
    if view == "whole":
        ax.add_patch(
            Rectangle(
                detail[:2],
                detail[2] - detail[0],
                detail[3] - detail[1],
                fill=False,
                edgecolor="black",
                linestyle="--",
                linewidth=1.0,
            )
        )
        ax.set_title("whole layer (dashed: the detail box)")
    else:
        ax.set_title(f"detail {list(detail)}")
    ax.legend(loc="lower right", fontsize="small")
    return figure


def _grid(count: int) -> tuple[int, int]:
    columns = min(count, 3)
    return math.ceil(count / columns), columns


def _relief(panels) -> tuple[Any, Any]:
    """Colour map and norm shared by every panel: the range of all of them."""
    low = min(float(np.nanmin(v)) for _, v in panels)
    high = max(float(np.nanmax(v)) for _, v in panels)
    return relief_style(None, low, high)


def relief_maps_figure(raster: xr.DataArray, panels) -> Figure:
    """Each approximation and the input as a map, on one colour scale."""
    from matplotlib.figure import Figure

    rows, columns = _grid(len(panels))
    figure = Figure(figsize=(5.2 * columns, 3.6 * rows), layout="constrained")
    axes = np.asarray(figure.subplots(rows, columns, squeeze=False)).ravel()
    cmap, norm = _relief(panels)
    extent = raster_extent(raster)
    crs = as_crs(raster.attrs.get("crs"))
    for k, (ax, (title, values)) in enumerate(zip(axes, panels, strict=False)):
        image = ax.imshow(values, extent=extent, origin="upper", cmap=cmap, norm=norm)
        ax.set_title(f"({chr(ord('a') + k)}) {title}")
        geographic_axes(ax, crs, (extent[0], extent[2], extent[1], extent[3]))
    for ax in axes[len(panels) :]:
        ax.set_axis_off()
    bar = figure.colorbar(image, ax=axes[: len(panels)].tolist(), shrink=0.8)
    bar.set_label(f"elevation ({raster.attrs.get('units') or 'm'})")
    figure.suptitle("PCA approximations of the bathymetry and topography")
    return figure


def relief_surfaces_figure(raster: xr.DataArray, panels) -> Figure:
    """Each approximation and the input as a semi-transparent 3-D surface."""
    import mpl_toolkits.mplot3d  # noqa: F401  (registers the 3d projection)
    from matplotlib.figure import Figure

    x, y = np.meshgrid(raster["x"].values, raster["y"].values)
    crs = as_crs(raster.attrs.get("crs"))
    low = min(float(np.nanmin(v)) for _, v in panels)
    high = max(float(np.nanmax(v)) for _, v in panels)
    width, depth = float(np.ptp(x)), float(np.ptp(y))
    if crs is not None and crs.is_geographic:  # to km on the ground
        middle = math.radians(float(np.mean(y)))
        width *= _KM_PER_DEGREE * math.cos(middle)
        depth *= _KM_PER_DEGREE
    else:
        width, depth = width / 1000, depth / 1000
    relief_km = max(high - low, 1e-9) / 1000
    exaggeration = _nice(0.3 * max(width, depth) / relief_km)
    cmap, norm = _relief(panels)
    rows, columns = _grid(len(panels))
    figure = Figure(figsize=(6.0 * columns, 4.6 * rows), layout="constrained")
    for k, (title, values) in enumerate(panels):
        ax = figure.add_subplot(rows, columns, k + 1, projection="3d")
        ax.plot_surface(
            x, y, values, cmap=cmap, norm=norm, rstride=1, cstride=1,
            linewidth=0, antialiased=False, alpha=0.85,
        )  # fmt: skip
        ax.set_zlim(low, high)
        ax.set_box_aspect((width, depth, relief_km * exaggeration), zoom=1.1)
        ax.view_init(elev=30, azim=110)
        ax.set_title(f"({chr(ord('a') + k)}) {title}")
        ax.set_xlabel("longitude" if crs is not None and crs.is_geographic else "x")
        ax.set_ylabel("latitude" if crs is not None and crs.is_geographic else "y")
        ax.set_zlabel(f"elevation ({raster.attrs.get('units') or 'm'})")
    figure.suptitle(
        f"PCA approximations as surfaces, vertical exaggeration x{exaggeration:g}, "
        "seen from the north-north-west"
    )
    return figure


def _nice(value: float) -> float:
    """Round down to 1, 2 or 5 times a power of ten (at least 1)."""
    if value <= 1:
        return 1.0
    power = 10 ** math.floor(math.log10(value))
    return max(step * power for step in (1, 2, 5) if step * power <= value)


def spectrum_figure(spectrum: NDArray[np.float64], modes: tuple[int, ...]) -> Figure:
    """Eigenvalue per mode (log scale) and the cumulative energy fraction."""
    from matplotlib.figure import Figure

    index = np.arange(1, len(spectrum) + 1)
    energy = np.cumsum(np.clip(spectrum, 0.0, None))
    energy /= energy[-1]
    positive = spectrum > spectrum[0] * 1e-12
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    left, right = figure.subplots(1, 2)
    left.semilogy(index[positive], spectrum[positive], "o-", markersize=3)
    left.set_xlabel("mode")
    left.set_ylabel("eigenvalue (m$^2$): energy of the mode")
    left.set_title("eigenvalue spectrum")
    if not positive.all():
        first = int(index[~positive].min())
        which = f"mode {first}" if first == index[-1] else f"modes {first}..{index[-1]}"
        left.annotate(
            f"{which}: ~0, not drawn (each window loses its mean)",
            xy=(0.97, 0.95), xycoords="axes fraction", ha="right", va="top",
        )  # fmt: skip
    right.plot(index, 100 * energy, "-", color="tab:gray")
    picks = np.asarray(modes) - 1
    right.plot(index[picks], 100 * energy[picks], "o", color="tab:red")
    for k in picks:
        right.annotate(
            f"{index[k]}: {100 * energy[k]:.1f} %", (index[k], 100 * energy[k]),
            textcoords="offset points", xytext=(6, -4), va="top",
        )  # fmt: skip
    right.set_ylim(100 * energy[0] - 8, 101)
    right.set_xlabel("modes kept")
    right.set_ylabel("energy kept (%)")
    right.set_title("cumulative energy")
    right.grid(True, alpha=0.3)
    return figure


def rms_figure(curve: list[dict[str, Any]], modes: tuple[int, ...]) -> Figure:
    """RMS and largest difference from the input against the number of modes."""
    from matplotlib.figure import Figure

    index = np.array([c["modes"] for c in curve])
    rms = np.array([c["rms_m"] for c in curve])
    worst = np.array([c["max_abs_diff_m"] for c in curve])
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    picks = np.asarray(modes) - 1
    for ax, values, title in zip(
        figure.subplots(1, 2),
        (rms, worst),
        ("RMS difference from the input", "largest |difference| from the input"),
        strict=True,
    ):
        ax.plot(index, values, "o-", markersize=3)
        ax.plot(index[picks], values[picks], "o", color="tab:red")
        for k in picks:
            ax.annotate(
                f"{index[k]}: {values[k]:.1f} m", (index[k], values[k]),
                textcoords="offset points", xytext=(5, 5),
            )  # fmt: skip
        ax.set_xlabel("modes kept")
        ax.set_ylabel("metres")
        ax.set_title(title)
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
    return figure
