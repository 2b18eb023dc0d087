"""Read only the window of a raster that some points need.

GEBCO's world grid is 86,400 x 43,200 cells; a case needs the part under its
mesh. :func:`read_raster_around` reprojects the points' bounding box to the
raster's CRS (densified edges, so a curved box is covered), widens it by a
margin on the Earth, and reads just those cells through GDAL's windowed reads.
"""

from __future__ import annotations

import math
import os

import numpy as np
import rasterio
import xarray as xr
from numpy.typing import ArrayLike
from pyproj import CRS, Transformer

from coastmesh.errors import InputDataError
from coastmesh.geometry.earth import METRES_PER_DEGREE
from coastmesh.io._inputs import check_input
from coastmesh.io.rasters.raster import _open, read_raster

__all__ = ["raster_extent", "read_raster_around"]


def raster_extent(
    path: str | os.PathLike[str],
) -> tuple[tuple[float, float, float, float], str | None, tuple[float, float]]:
    """Return a raster's bounds ``(minx, miny, maxx, maxy)``, CRS (WKT) and cell size.

    Raises
    ------
    InputDataError, FormatError
        As :func:`coastmesh.io.read_raster`.
    """
    source = check_input(path)
    with rasterio.Env():
        dataset = _open(source)
        with dataset:
            crs = None if dataset.crs is None else dataset.crs.to_wkt()
            b = dataset.bounds
            res = (abs(dataset.transform.a), abs(dataset.transform.e))
    bounds = (
        min(b.left, b.right),
        min(b.bottom, b.top),
        max(b.left, b.right),
        max(b.bottom, b.top),
    )
    return bounds, crs, res


def read_raster_around(
    path: str | os.PathLike[str],
    points: ArrayLike,
    crs: CRS | str,
    *,
    margin: float = 0.0,
    name: str | None = None,
) -> xr.DataArray:
    """Read the cells of a raster within ``margin`` metres of the points' box.

    Parameters
    ----------
    path : str or path-like
        Any raster GDAL reads.
    points : array_like of shape (n, 2)
        Where the values are needed (mesh nodes, say), in ``crs``.
    crs : pyproj.CRS or str
        CRS of ``points``.
    margin : float
        Metres to widen the box by (two cells are always added).
    name : str, optional
        How errors name the raster (default: its path).

    Returns
    -------
    xarray.DataArray
        As :func:`coastmesh.io.read_raster`; the whole raster when it has no
        CRS (the caller reports that).

    Raises
    ------
    InputDataError
        If the raster does not overlap the points' box at all.
    """
    label = name or str(path)
    bounds, wkt, res = raster_extent(path)
    if wkt is None:
        return read_raster(path)
    target = CRS.from_wkt(wkt)
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    box = _box_in(pts, CRS.from_user_input(crs), target)
    if box is None:  # the points do not all project: read everything
        return read_raster(path)
    if target.is_geographic:
        lat = max(abs(box[1]), abs(box[3]))
        mx = margin / (
            METRES_PER_DEGREE * max(math.cos(math.radians(min(lat, 89.0))), 0.01)
        )
        my = margin / METRES_PER_DEGREE
    else:
        unit = target.axis_info[0].unit_conversion_factor or 1.0
        mx = my = margin / unit
    mx, my = mx + 2 * res[0], my + 2 * res[1]
    want = (box[0] - mx, box[1] - my, box[2] + mx, box[3] + my)
    clipped = (
        max(want[0], bounds[0]),
        max(want[1], bounds[1]),
        min(want[2], bounds[2]),
        min(want[3], bounds[3]),
    )
    if clipped[0] >= clipped[2] or clipped[1] >= clipped[3]:
        raise InputDataError(
            f"bathymetry raster {label} does not overlap the mesh: it spans "
            f"{_shown(bounds)} and the mesh needs {_shown(box)} (in the raster's "
            "CRS); is it the right region and CRS?"
        )
    return read_raster(path, bbox=clipped)


def _box_in(pts, src: CRS, dst: CRS) -> tuple[float, float, float, float] | None:
    """Return the points' box in ``dst``, edges densified (None: unprojectable)."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    t = Transformer.from_crs(src, dst, always_xy=True)
    with np.errstate(invalid="ignore"):
        box = t.transform_bounds(lo[0], lo[1], hi[0], hi[1], densify_pts=101)
        if dst.is_geographic and box[0] > box[2]:  # crosses the antimeridian
            return None
        # the points themselves too: transform_bounds misses inner extremes
        x, y = t.transform(pts[:, 0], pts[:, 1])
    if not (np.isfinite(box).all() and np.isfinite(x).all() and np.isfinite(y).all()):
        return None
    return (
        min(box[0], float(x.min())),
        min(box[1], float(y.min())),
        max(box[2], float(x.max())),
        max(box[3], float(y.max())),
    )


def _shown(box) -> str:
    return f"x {box[0]:.6g} to {box[2]:.6g}, y {box[1]:.6g} to {box[3]:.6g}"
