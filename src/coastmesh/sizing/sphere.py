"""Size fields of the whole world, on a longitude/latitude grid that wraps round.

A global case's size field lives on the nodes of a longitude/latitude grid whose
last column is its first (longitude -180 and 180): the grid
:class:`~coastmesh.meshing.gmsh.sphere_sizes.SphereSizeGrid` hands to the mesher.
Every size is a length on the sphere, in metres:

* gradations from shoreline sets, by great-circle distance
  (:func:`~coastmesh.sizing.distance.distance_to_lines` measures on the Earth);
* the tidal-wavelength term from a bathymetry raster, sampled at the nodes with
  the raster wrapped round in longitude when it covers the world;
* the gradation limit, with the true length of each step on the sphere: the
  east-west spacing shrinks with the cosine of the latitude, and the sweeps
  carry the limit across the antimeridian.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

from coastmesh.depth.grid import depth_on_grid
from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS, earth_centred
from coastmesh.sizing.bathymetry import BathymetrySize, wavelength_size
from coastmesh.sizing.distance import distance_to_lines, nearest_arcs
from coastmesh.sizing.field import Gradation
from coastmesh.sizing.gradation import gradation_size

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["limit_gradation_sphere", "sphere_size_field"]

_LONLAT = "EPSG:4326"


def sphere_size_field(
    gradations: list[Gradation],
    *,
    h_max: float,
    cell: float,
    south: float = -90.0,
    rate: float | None = None,
    bathymetry: BathymetrySize | None = None,
    h_min: float | None = None,
    lines_crs: CRS | str = _LONLAT,
) -> xr.DataArray:
    """Target edge length on a world longitude/latitude grid.

    Parameters
    ----------
    gradations : list of Gradation
        Lines in longitude/latitude (EPSG:4326); combined by minimum.
    h_max : float
        Largest size, metres.
    cell : float
        Grid spacing in degrees (> 0; 360 and 90 - ``south`` are rounded to
        whole numbers of cells).
    south : float
        Southernmost latitude of the grid (degrees): below the ocean's
        southernmost point. The grid runs from there to the North Pole.
    rate : float, optional
        Gradation limit (metres per metre, on the sphere).
    bathymetry : BathymetrySize, optional
        The tidal-wavelength term (the slope term is not available on a world
        grid yet).
    h_min : float, optional
        Floor of the field, metres.
    lines_crs : CRS-like
        The CRS of the gradations' lines: longitude/latitude, or the
        stereographic plane a world is meshed in (lines there, Antarctica's
        coast among them, have no edge across the antimeridian).

    Returns
    -------
    xarray.DataArray
        Sizes in metres, dims ``("y", "x")``: ``x`` longitudes from -180 to 180
        (both ends, the same meridian), ``y`` latitudes; attrs ``crs``,
        ``units`` and ``history``.

    Raises
    ------
    ConfigError
        If a number is out of range, or the bathymetry asks for the slope term.

    Examples
    --------
    >>> coast = shapely.LineString([(-10, 0), (10, 0)])
    >>> g = Gradation(np.array([coast]), h_min=10e3, d_hold=10e3, d_grade=500e3)
    >>> f = sphere_size_field([g], h_max=50e3, cell=2.0, south=-80.0)
    >>> f.shape, float(f.sel(x=0, y=0)), float(f.sel(x=180, y=0))
    ((86, 181), 10000.0, 50000.0)
    """
    if not cell > 0:
        raise ConfigError(f"cell = {cell}: must be > 0 degrees")
    if not -90.0 <= south < 90.0:
        raise ConfigError(f"south = {south}: must be a latitude below 90")
    if bathymetry is not None and bathymetry.per_slope is not None:
        raise ConfigError(
            "mesh_size.bathymetry: the slope term (per_slope) is not available in "
            "a global case; use the wavelength term (per_wavelength) alone"
        )
    nx = max(round(360.0 / cell), 4)
    ny = max(round((90.0 - south) / cell), 2)
    lon = np.linspace(-180.0, 180.0, nx + 1)
    lat = np.linspace(south, 90.0, ny + 1)
    size = np.full((ny + 1, nx + 1), float(h_max))
    resolution = min(math.radians(360.0 / nx) * EARTH_RADIUS / 4, 5_000.0)
    for g in gradations:
        if g.h_min > h_max:
            raise ConfigError(
                f"gradation {g.name!r}: h_min = {g.h_min} > h_max = {h_max}"
            )
        lines = np.asarray(g.lines, dtype=object)
        if len(lines) == 0 or shapely.is_empty(lines).all():
            continue
        distance = _distance(
            lines, lines_crs, lon[:-1], lat, resolution, g.d_hold + g.d_grade
        )  # the last column is the first meridian again
        graded = gradation_size(distance, g.h_min, h_max, g.d_hold, g.d_grade)
        np.minimum(size, np.hstack([graded, graded[:, :1]]), out=size)
    if bathymetry is not None and bathymetry.per_wavelength is not None:
        raster = _wrapped(bathymetry.raster)
        depth = depth_on_grid(
            raster, lon[:-1], lat, crs=_LONLAT, positive=bathymetry.positive
        )
        wave = wavelength_size(
            depth,
            per_wavelength=bathymetry.per_wavelength,
            period=bathymetry.period,
            min_depth=bathymetry.min_depth,
        )
        np.minimum(size, np.hstack([wave, wave[:, :1]]), out=size)
    if h_min is not None:
        size = np.maximum(size, h_min)
    size = np.minimum(size, h_max)
    if rate is not None:
        size = limit_gradation_sphere(size, lat, rate)
    import xarray as xr

    history = f"coastmesh sphere_size_field: {len(gradations)} gradations"
    history += ", wavelength" if bathymetry is not None else ""
    history += f", h_max {h_max:g} m" + (f", rate {rate:g}" if rate else "")
    return xr.DataArray(
        size,
        dims=("y", "x"),
        coords={"y": lat, "x": lon},
        name="size",
        attrs={"crs": CRS(_LONLAT).to_wkt(), "units": "m", "history": history},
    )


def _distance(
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
    # a plane: densified there (its scale is at least 1 where the world is
    # meshed, so a plane step is at most as long on the Earth)
    geoms = np.asarray(lines, dtype=object).ravel()
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    geoms = shapely.boundary(geoms)
    vertices = shapely.get_coordinates(shapely.segmentize(geoms, resolution))
    glon, glat = np.meshgrid(lon, lat)
    arc = nearest_arcs(
        earth_centred(vertices, crs, name="line vertices"),
        earth_centred(np.column_stack([glon.ravel(), glat.ravel()]), _LONLAT),
        resolution=resolution,
        max_distance=max_distance,
    )
    return arc.reshape(glon.shape)


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


def _arc(lat0: NDArray, lat1: NDArray, dlon: float) -> NDArray[np.float64]:
    """Great-circle length (metres) between points ``dlon`` apart in longitude."""
    a = (
        np.sin((lat1 - lat0) / 2) ** 2
        + np.cos(lat0) * np.cos(lat1) * math.sin(dlon / 2) ** 2
    )
    return 2.0 * EARTH_RADIUS * np.arcsin(np.sqrt(np.clip(a, 0.0, 1.0)))


def _cone(values: NDArray, ramp: NDArray, axis: int) -> NDArray[np.float64]:
    """``min_j values[j] + |ramp[i] - ramp[j]|`` along ``axis`` (ramp ascending)."""
    forward = np.minimum.accumulate(values - ramp, axis=axis) + ramp
    flipped = np.flip(values + ramp, axis=axis)
    backward = np.flip(np.minimum.accumulate(flipped, axis=axis), axis=axis) - ramp
    return np.minimum(forward, backward)


def _rows(h: NDArray, step: NDArray) -> NDArray[np.float64]:
    ramp = step[:, None] * np.arange(h.shape[1])[None, :]
    return _cone(h, ramp, 1)


def _columns(h: NDArray, step: NDArray) -> NDArray[np.float64]:
    ramp = np.concatenate([[0.0], np.cumsum(step)])[:, None]
    return _cone(h, ramp, 0)


def _diagonals(h: NDArray, step: NDArray, *, flip: bool) -> NDArray[np.float64]:
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
    out = done[rows, cols]
    return out[:, ::-1] if flip else out


def _wrapped(raster: xr.DataArray) -> xr.DataArray:
    """Return a world lon/lat raster one column wider on each side.

    The column added on each side is the other side's edge column, so the raster
    interpolates across the antimeridian; any other raster is returned as it is.
    """
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
