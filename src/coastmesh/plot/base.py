"""Helpers shared by every figure: pyplot, saving, axes, colours, extents.

matplotlib is imported only inside these functions, so importing
:mod:`coastmesh.plot` stays light.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Collection
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.io import atomic_write, plot_format
from coastmesh.types import Features

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "FIGURE_DPI",
    "as_crs",
    "contours",
    "detail_bounds",
    "geographic_axes",
    "geometry_array",
    "pyplot",
    "raster_extent",
    "relief_style",
    "save_figure",
    "total_bounds",
    "x_stretch",
]

_DETAIL_FRACTION = 1 / 8
#: Resolution of raster figures, dots per inch (:func:`save_figure`'s default).
FIGURE_DPI = 150


def across_dateline(
    xy: NDArray[np.float64], cells: NDArray[np.int64], crs: Any
) -> NDArray[np.bool_]:
    """Return which cells (edges or triangles) cross the antimeridian.

    In longitude and latitude such a cell spans over 180 degrees and would be
    drawn across the whole map; the figures leave it out. Never for a
    projected CRS.

    Examples
    --------
    >>> xy = np.array([[179.0, 0.0], [-179.0, 0.0], [170.0, 0.0]])
    >>> across_dateline(xy, np.array([[0, 1], [0, 2]]), "EPSG:4326").tolist()
    [True, False]
    """
    if crs is None or not CRS.from_user_input(crs).is_geographic or len(cells) == 0:
        return np.zeros(len(cells), dtype=bool)
    lon = xy[:, 0][cells]
    return (lon.max(axis=1) - lon.min(axis=1)) > 180.0


def save_figure(
    figure: Figure,
    path: str | os.PathLike[str],
    *,
    overwrite: bool = False,
    dpi: int = FIGURE_DPI,
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
    dpi : int, default :data:`FIGURE_DPI` (150)
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


def pyplot() -> Any:
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


def relief_style(cmap: str | None, low: float, high: float) -> tuple[Any, Any]:
    """Colour map and norm for elevation: sea blues below 0, land above."""
    from matplotlib import colormaps
    from matplotlib.colors import LinearSegmentedColormap, Normalize, TwoSlopeNorm

    if cmap is not None or not low < 0 < high:
        return cmap or "terrain", Normalize(low, high)
    sea = colormaps["Blues_r"](np.linspace(0.0, 0.8, 128))
    land = colormaps["terrain"](np.linspace(0.25, 1.0, 128))
    colours = LinearSegmentedColormap.from_list("relief", np.vstack([sea, land]))
    return colours, TwoSlopeNorm(vmin=low, vcenter=0.0, vmax=high)


def geometry_array(value: Features | Collection[Any]) -> NDArray[np.object_]:
    """Return the geometries of Features, or a sequence of them, as an object array."""
    if isinstance(value, Features):
        return value.geometry
    geometry = np.empty(len(value), dtype=object)
    geometry[:] = list(value)
    return geometry


def contours(geometry: NDArray[np.object_]) -> list[NDArray[np.float64]]:
    """Every ring and line of the geometries, as (n, 2) coordinate arrays."""
    parts = shapely.get_parts(geometry[~shapely.is_missing(geometry)])
    polygons = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    lines = np.concatenate([shapely.get_rings(parts[polygons]), parts[~polygons]])
    coords, index = shapely.get_coordinates(lines, return_index=True)
    if not len(coords):
        return []
    cuts = np.flatnonzero(np.diff(index)) + 1
    return np.split(coords, cuts)


def total_bounds(
    *arrays: NDArray[np.object_],
) -> tuple[float, float, float, float] | None:
    """Return ``(minx, miny, maxx, maxy)`` of all the geometries; None if empty."""
    boxes = np.array([shapely.total_bounds(a) for a in arrays if len(a)])
    if boxes.size == 0 or np.isnan(boxes).all():
        return None
    minx, miny = np.nanmin(boxes[:, :2], axis=0)
    maxx, maxy = np.nanmax(boxes[:, 2:], axis=0)
    return float(minx), float(miny), float(maxx), float(maxy)


def detail_bounds(
    geometry: NDArray[np.object_], crs: CRS | None
) -> tuple[float, float, float, float] | None:
    """Return a box around the middle vertex of the feature with most vertices."""
    extent = total_bounds(geometry)
    if extent is None:
        return None
    counts = shapely.get_num_coordinates(geometry)
    biggest = geometry[int(np.argmax(counts))]
    coords = shapely.get_coordinates(biggest)
    x, y = coords[len(coords) // 2]
    stretch = x_stretch(crs, extent)
    half = _DETAIL_FRACTION * max(
        (extent[2] - extent[0]) / stretch, extent[3] - extent[1]
    )
    half_x = half * stretch
    return float(x - half_x), float(y - half), float(x + half_x), float(y + half)


def x_stretch(
    crs: CRS | None, extent: tuple[float, float, float, float] | None
) -> float:
    """How many x units make one y unit on the map: 1/cos(latitude) for lon/lat."""
    if crs is None or not crs.is_geographic:
        return 1.0
    middle = 0.0 if extent is None else (extent[1] + extent[3]) / 2
    return 1 / max(math.cos(math.radians(middle)), 0.05)


def raster_extent(raster: xr.DataArray) -> tuple[float, float, float, float]:
    """Return ``(left, right, bottom, top)`` for ``imshow``."""
    from coastmesh.io import raster_transform

    t = raster_transform(raster)
    ny, nx = raster.shape
    left, right = t.c, t.c + t.a * nx
    top, bottom = t.f, t.f + t.e * ny
    return float(left), float(right), float(bottom), float(top)


def as_crs(value: CRS | str | None) -> CRS | None:
    """Return ``value`` as a :class:`pyproj.CRS` (None stays None)."""
    if value is None or isinstance(value, CRS):
        return value
    return CRS.from_user_input(value)


def geographic_axes(
    ax: Axes, crs: CRS | None, extent: tuple[float, float, float, float] | None
) -> None:
    """Label the axes and set an aspect ratio that keeps shapes."""
    if crs is not None and crs.is_geographic:
        ax.set_xlabel("longitude (degrees east)")
        ax.set_ylabel("latitude (degrees north)")
        ax.set_aspect(x_stretch(crs, extent))
        return
    unit = ""
    if crs is not None and crs.axis_info:
        unit = f" ({crs.axis_info[0].unit_name})"
    ax.set_xlabel(f"x{unit}")
    ax.set_ylabel(f"y{unit}")
    ax.set_aspect("equal")


#: The sea of the maps: water, behind the mesh or without one.
SEA = "#dbe9f6"


def flat_mesh(
    ax: Axes,
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    values: ArrayLike,
    *,
    chunk: int | None = None,
    **kwargs: Any,
) -> Any:
    """Colour each triangle flat by its value, drawn as Gouraud triangles.

    ``ax.tripcolor(..., facecolors=values)`` draws each triangle as a path of
    its own, built in Python: 4.5 s for the 1.5-million-triangle world mesh.
    Here each triangle gets three corners of its own that share its value,
    shaded (:func:`shaded_mesh`, Agg's triangle loop): the same flat colours in
    1.5 s. Give ``vmin`` and ``vmax``, or ``norm``. Returns the first
    collection (None without triangles); none is in the layout.
    """
    from matplotlib.tri import Triangulation

    if "norm" not in kwargs and ("vmin" not in kwargs or "vmax" not in kwargs):
        raise ValueError("flat_mesh needs vmin and vmax, or norm")
    triangles, values = np.asarray(triangles), np.asarray(values, dtype=float)
    chunk = int(chunk or SHADED_CHUNK)
    first = None
    for start in range(0, len(triangles), chunk):  # none: nothing drawn
        part = triangles[start : start + chunk]
        corners = np.arange(3 * len(part)).reshape(-1, 3)
        image = ax.tripcolor(
            Triangulation(points[part, 0].ravel(), points[part, 1].ravel(), corners),
            np.repeat(values[start : start + chunk], 3),
            shading="gouraud",
            **kwargs,
        )
        image.set_in_layout(False)  # clipped to the axes; measuring it is slow
        first = image if first is None else first
    return first


#: Triangles per collection of a Gouraud-shaded mesh (:func:`shaded_mesh`).
SHADED_CHUNK = 300_000


def shaded_mesh(
    ax: Axes,
    triangulation: Any,
    values: NDArray[np.float64],
    *,
    in_layout: bool = False,
    chunk: int | None = None,
    **kwargs: Any,
) -> Any:
    """Shade a triangulation from values at its nodes (Gouraud), in chunks.

    ``ax.tripcolor(triangulation, values, shading="gouraud", **kwargs)``, drawn
    as one collection per ``chunk`` (default :data:`SHADED_CHUNK`) triangles,
    each with only its own nodes:
    matplotlib builds the vertices and colours of every triangle of a
    collection at once when it draws it, which for the 2.9-million-triangle
    NW-shelf mesh took 560 MB above the figure's data; in chunks of 300,000,
    215 MB. Gouraud triangles are drawn one by one in order, so the image is
    the same byte for byte (tested). Give the colours' range (``vmin`` and
    ``vmax``, or ``norm``): each chunk would scale its own otherwise.

    Returns the first collection, for a colour bar; ``in_layout`` is set on
    every one. Not in the layout by default: a shaded mesh is clipped to its
    axes, and to measure it for the layout matplotlib turns it into one path
    per triangle (the depth map of a 1.1-million-triangle world mesh: 35 of
    its 48 s).
    """
    from matplotlib.tri import Triangulation

    if "norm" not in kwargs and ("vmin" not in kwargs or "vmax" not in kwargs):
        raise ValueError("shaded_mesh needs vmin and vmax, or norm")
    triangles, mask = triangulation.triangles, triangulation.mask
    values = np.asarray(values)
    chunk = int(chunk or SHADED_CHUNK)
    first = None
    for start in range(0, max(len(triangles), 1), chunk):
        part = triangles[start : start + chunk]
        if mask is not None:
            part = part[~mask[start : start + chunk]]
        nodes, local = np.unique(part, return_inverse=True)
        image = ax.tripcolor(
            Triangulation(
                triangulation.x[nodes], triangulation.y[nodes], local.reshape(-1, 3)
            ),
            values[nodes],
            shading="gouraud",
            **kwargs,
        )
        image.set_in_layout(in_layout)
        first = image if first is None else first
    return first
