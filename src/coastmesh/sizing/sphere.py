"""What a size field of the whole world needs: its grid wraps round.

A global case's size field lives on the nodes of a longitude/latitude grid whose
last column is its first (longitude -180 and 180):
:class:`~coastmesh.sizing.grid.SphereGrid`, which
:class:`~coastmesh.meshing.gmsh.SphereSizeGrid` hands to the mesher. Every size
is a length on the sphere, in metres:

* gradations from shoreline sets, by great-circle distance
  (:func:`sphere_distance`, from lines in longitude and latitude or in the
  stereographic plane);
* a bathymetry raster is sampled at the nodes wrapped round in longitude when it
  covers the world (:func:`wrapped`);
* the gradation limit, with the true length of each step on the sphere: the
  east-west spacing shrinks with the cosine of the latitude, and the sweeps
  carry the limit across the antimeridian (:func:`limit_gradation_sphere`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS, earth_centred
from coastmesh.sizing.distance import distance_to_lines, nearest_arcs

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "limit_gradation_sphere",
    "sphere_distance",
    "wrapped",
]

_LONLAT = "EPSG:4326"


def sphere_distance(
    lines: NDArray[np.object_],
    crs: CRS | str,
    lon: NDArray[np.float64],
    lat: NDArray[np.float64],
    resolution: float,
    max_distance: float,
) -> NDArray[np.float64]:
    """Great-circle distance from lines in ``crs`` to the lon/lat grid's nodes."""
    crs = CRS.from_user_input(crs)
    if crs.is_geographic:
        return distance_to_lines(
            lines,
            lon,
            lat,
            crs=crs,
            resolution=resolution,
            max_distance=max_distance,
        )
    # a plane: the lines' vertices go onto the Earth, and are densified there
    # (densified in the plane, every step of the far side, where the plane
    # stretches lengths up to 90 times, was that much shorter on the Earth:
    # world.toml's coast took 1.5 million vertices and its k-d tree 23 s)
    geoms = np.asarray(lines, dtype=object).ravel()
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    # a polygon's distance is to its rings; a line's to the line itself (its
    # boundary would be its two end points, and a closed ring's nothing)
    polygonal = np.isin(
        shapely.get_type_id(geoms),
        [shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON],
    )
    geoms[polygonal] = shapely.boundary(geoms[polygonal])
    parts = shapely.get_parts(geoms)
    xy, which = shapely.get_coordinates(parts, return_index=True)
    vertices = _densified(
        earth_centred(xy, crs, name="line vertices"), which, resolution
    )
    glon, glat = np.meshgrid(lon, lat)
    arc = nearest_arcs(
        vertices,
        earth_centred(np.column_stack([glon.ravel(), glat.ravel()]), _LONLAT),
        resolution=resolution,
        max_distance=max_distance,
    )
    return arc.reshape(glon.shape)


def _densified(
    xyz: NDArray[np.float64], line: NDArray[np.intp], step: float
) -> NDArray[np.float64]:
    """Return the vertices of lines (earth-centred) with points every ``step``.

    ``line`` is each vertex's line; a segment joins two vertices of one line.
    Its points are equally spaced along its chord, at most ``step`` apart (a
    chord of the lengths meant here is its arc to within a part in 10^6).
    """
    same = line[1:] == line[:-1]
    a, b = xyz[:-1][same], xyz[1:][same]
    pieces = np.maximum(np.ceil(np.linalg.norm(b - a, axis=1) / step), 1).astype(int)
    start = np.repeat(a, pieces - 1, axis=0)
    delta = np.repeat((b - a) / pieces[:, None], pieces - 1, axis=0)
    # k = 1 .. pieces - 1 along each segment
    k = np.arange(len(start)) - np.repeat(
        np.cumsum(pieces - 1) - (pieces - 1), pieces - 1
    )
    return np.concatenate([xyz, start + (k + 1)[:, None] * delta])


def limit_gradation_sphere(
    size: ArrayLike, lat: ArrayLike, rate: float, *, max_sweeps: int = 200
) -> NDArray[np.float64]:
    """Lower a world size field until no step grows faster than ``rate``.

    Parameters
    ----------
    size : array_like of shape (ny, nx + 1)
        Sizes (metres) at the nodes of a longitude/latitude grid of equal steps
        from -180 to 180 (the last column is the first meridian again).
    lat : array_like of shape (ny,)
        The rows' latitudes, degrees, ascending, equally spaced.
    rate : float
        Largest growth per metre along a grid step (> 0).

    Returns
    -------
    ndarray
        The largest field below ``size`` in which a node exceeds each of its 8
        neighbours by at most ``rate`` times the great-circle length of the step
        between them (the last column kept equal to the first).

    Notes
    -----
    The sweeps are :func:`~coastmesh.sizing.gradation.limit_gradation`'s
    (cumulative minima of ``h - ramp`` along rows, columns and both diagonals),
    with each step's ramp its own length on the sphere, and repeated until
    nothing changes; the limit crosses the antimeridian because the two end
    columns, one meridian, take the smaller of their values after each sweep.
    Written here because no maintained library limits a gradient on a periodic
    grid of varying spacing.

    Examples
    --------
    >>> lat = np.array([-10.0, 0.0, 10.0])
    >>> h = np.full((3, 37), 1e6)
    >>> h[1, 0] = h[1, -1] = 1e4  # at longitude -180 = 180, on the equator
    >>> out = limit_gradation_sphere(h, lat, 0.5)
    >>> step = np.radians(10.0) * 6_371_008.8  # 10 degrees of the equator
    >>> bool(abs(out[1, 1] - (1e4 + 0.5 * step)) < 1e-6 * step)
    True
    >>> bool(abs(out[1, -2] - out[1, 1]) < 1e-6)  # across the antimeridian
    True
    """
    h = np.array(size, dtype=np.float64)
    lat = np.radians(np.asarray(lat, dtype=np.float64))
    if h.ndim != 2 or h.shape[0] != lat.size or h.shape[1] < 3:
        raise ConfigError(f"size has shape {h.shape}; lat has {lat.size} rows")
    if not rate > 0:
        raise ConfigError(f"rate = {rate}: must be > 0")
    nx = h.shape[1] - 1
    dlon = 2.0 * math.pi / nx
    # the length of each step on the sphere (haversine)
    east = _arc(lat, lat, dlon)  # along each row, (ny,)
    north = _arc(lat[:-1], lat[1:], 0.0)  # from row j to row j + 1, (ny - 1,)
    diag = _arc(lat[:-1], lat[1:], dlon)
    for _ in range(max_sweeps):
        before = h.copy()
        h = _rows(h, rate * east)
        h = _columns(h, rate * north)
        h = _diagonals(h, rate * diag, flip=False)
        h = _diagonals(h, rate * diag, flip=True)
        seam = np.minimum(h[:, 0], h[:, -1])
        h[:, 0] = h[:, -1] = seam
        if np.max(before - h, initial=0.0) <= 1e-12 * np.max(h, initial=1.0):
            break
    return h


def _arc(
    lat0: NDArray[np.float64], lat1: NDArray[np.float64], dlon: float
) -> NDArray[np.float64]:
    """Great-circle length (metres) between points ``dlon`` apart in longitude."""
    a = (
        np.sin((lat1 - lat0) / 2) ** 2
        + np.cos(lat0) * np.cos(lat1) * math.sin(dlon / 2) ** 2
    )
    arc: NDArray[np.float64] = (
        2.0 * EARTH_RADIUS * np.arcsin(np.sqrt(np.clip(a, 0.0, 1.0)))
    )
    return arc


def _cone(
    values: NDArray[np.float64], ramp: NDArray[np.float64], axis: int
) -> NDArray[np.float64]:
    """``min_j values[j] + |ramp[i] - ramp[j]|`` along ``axis`` (ramp ascending)."""
    forward = np.minimum.accumulate(values - ramp, axis=axis) + ramp
    flipped = np.flip(values + ramp, axis=axis)
    backward = np.flip(np.minimum.accumulate(flipped, axis=axis), axis=axis) - ramp
    cone: NDArray[np.float64] = np.minimum(forward, backward)  # numpy's stub: Any
    return cone


def _rows(h: NDArray[np.float64], step: NDArray[np.float64]) -> NDArray[np.float64]:
    ramp = step[:, None] * np.arange(h.shape[1])[None, :]
    return _cone(h, ramp, 1)


def _columns(h: NDArray[np.float64], step: NDArray[np.float64]) -> NDArray[np.float64]:
    ramp = np.concatenate([[0.0], np.cumsum(step)])[:, None]
    return _cone(h, ramp, 0)


def _diagonals(
    h: NDArray[np.float64], step: NDArray[np.float64], *, flip: bool
) -> NDArray[np.float64]:
    """Sweep the diagonals: shear each into a column, sweep, shear back."""
    ny, nx = h.shape
    grid = h[:, ::-1] if flip else h
    sheared = np.full((ny, nx + ny - 1), np.inf)
    rows = np.arange(ny)[:, None]
    cols = np.arange(nx)[None, :] + (ny - 1 - rows)
    sheared[rows, cols] = grid
    ramp = np.concatenate([[0.0], np.cumsum(step)])[:, None]
    with np.errstate(invalid="ignore"):  # inf - inf where a diagonal is absent
        done = _cone(sheared, ramp, 0)
    out: NDArray[np.float64] = done[rows, cols]
    return out[:, ::-1] if flip else out


def wrapped(raster: xr.DataArray) -> xr.DataArray:
    """Return a world lon/lat raster one column wider on each side.

    The column added on each side is the other side's edge column, so the raster
    interpolates across the antimeridian; any other raster is returned as it is.
    """
    if not hasattr(raster, "attrs"):  # a stack of sources: sampled as it is
        return raster
    import xarray as xr

    crs = raster.attrs.get("crs")
    if crs is None or not CRS.from_user_input(crs).is_geographic:
        return raster
    x = raster["x"].values
    step = float(abs(x[1] - x[0])) if len(x) > 1 else 0.0
    if step == 0.0 or x[-1] - x[0] + step < 360.0 - 1e-6:
        return raster
    left = raster.isel(x=[-1]).assign_coords(x=[x[-1] - 360.0])
    right = raster.isel(x=[0]).assign_coords(x=[x[0] + 360.0])
    out = xr.concat([left, raster, right], dim="x")
    out.attrs = raster.attrs
    return out
