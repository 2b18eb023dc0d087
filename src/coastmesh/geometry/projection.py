"""The meshing CRS and target sizes in it.

Gmsh meshes in a plane. :func:`default_mesh_crs` picks a conformal projection
that keeps the scale factor k near 1 over the domain; :func:`to_map_units` turns
a size grid in metres on the Earth into map units with k (:func:`scale_factor`),
and :func:`sample_size` interpolates it as Gmsh does. :func:`project_rings`
puts the domain's boundary into the meshing CRS.
"""

from __future__ import annotations

import logging
from concurrent.futures import ThreadPoolExecutor
from typing import Protocol

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS, Proj
from pyproj.crs import ProjectedCRS

from coastmesh.errors import MeshingError
from coastmesh.geometry.earth import reproject_points, transformer
from coastmesh.geometry.grids import interpolate_bilinear
from coastmesh.types import Domain, SizeGrid

__all__ = [
    "PlaneSizes",
    "default_mesh_crs",
    "project_points",
    "project_rings",
    "sample_size",
    "scale_factor",
    "to_map_units",
]

logger = logging.getLogger(__name__)


class PlaneSizes(Protocol):
    """A size field that samples itself in the plane (a ``SphereSizeGrid``).

    The meshing layer's lon/lat grid, named here by what it does, since this
    layer cannot import it.
    """

    def sample(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the target edge lengths at points ``xy`` of the plane."""


# Geographic segments are densified to this fraction of the domain's extent before
# projection, so straight lines in the domain CRS stay (almost) straight.
_DENSIFY_FRACTION = 1e-3
# default_mesh_crs: UTM for domains at most this many degrees of longitude wide ...
_UTM_MAX_WIDTH = 6.0
# ... and within this many degrees of latitude of the equator.
_UTM_MAX_LAT = 80.0
# A mesh CRS whose angular distortion (degrees) exceeds this anywhere on the size
# grid is not conformal; conformal ones give ~1e-6 from PROJ's numerical derivatives.
_MAX_ANGULAR_DISTORTION = 1e-3
# Size grid nodes per block when computing scale factors (bounds the memory used).
_SCALE_BLOCK = 1 << 18


def default_mesh_crs(domain: Domain) -> CRS:
    """Return the CRS meshes are made in when none is given.

    A conformal projection keeps the triangles' shapes on the Earth; its point
    scale factor k (map length per metre on the Earth) then only changes their
    size, and :func:`~coastmesh.meshing.generate_mesh` corrects for it. The
    choice keeps k close to 1 over the domain:

    - a projected ``domain.crs`` is used as it is;
    - a geographic domain at most 6 degrees of longitude wide and within
      80 degrees of latitude of the equator gets the WGS 84 UTM zone (north or
      south) of its centroid, where k stays within about 1 % of 1;
    - a wider or polar geographic domain gets an oblique stereographic
      projection on WGS 84 centred on its centroid (``+proj=sterea +lat_0=..
      +lon_0=.. +k=1 +x_0=0 +y_0=0 +datum=WGS84 +units=m``). Its k is 1 at the
      centroid and grows alike in every direction with the angular distance c
      from it, k = 2 / (1 + cos c) (1.017 at 15 degrees), half as fast as a
      transverse Mercator's grows away from its central meridian; and unlike
      UTM it is defined at the poles.

    Parameters
    ----------
    domain : Domain
        The domain.

    Returns
    -------
    pyproj.CRS
        A projected, conformal CRS in metres: ``domain.crs``, a UTM zone, or an
        oblique stereographic projection as above.

    See Also
    --------
    coastmesh.meshing.generate_mesh : meshes in this CRS, the sizes scaled by k.

    Examples
    --------
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[-3, 58], [-2, 58], [-2, 59], [-3, 59], [-3, 58]]
    >>> d = Domain(shapely.Polygon(ring), (BoundarySegment(ring, "open", "b", 1),),
    ...            crs="EPSG:4326")
    >>> default_mesh_crs(d).to_epsg()
    32630

    The north-west European shelf is too wide for one UTM zone:

    >>> ring = [[-15, 45], [10, 45], [10, 70], [-15, 70], [-15, 45]]
    >>> d = Domain(shapely.Polygon(ring), (BoundarySegment(ring, "open", "b", 1),),
    ...            crs="EPSG:4326")
    >>> default_mesh_crs(d).name
    'WGS 84 / oblique stereographic 57.5N 2.5W'
    """
    if domain.crs.is_projected:
        return domain.crs
    ring = shapely.get_coordinates(domain.polygon.exterior)
    lon, lat = reproject_points(ring, domain.crs, "EPSG:4326").T
    centroid = domain.polygon.centroid
    ((c_lon, c_lat),) = reproject_points(
        [[centroid.x, centroid.y]], domain.crs, "EPSG:4326"
    )
    c_lon = (c_lon + 180.0) % 360.0 - 180.0
    if _lon_extent(lon) <= _UTM_MAX_WIDTH and np.abs(lat).max() <= _UTM_MAX_LAT:
        zone = int(np.clip(np.floor((c_lon + 180.0) / 6.0) + 1, 1, 60))
        return CRS.from_epsg((32600 if c_lat >= 0 else 32700) + zone)
    return _oblique_stereographic(float(c_lat), float(c_lon))


def _lon_extent(lon: NDArray[np.float64]) -> float:
    """Return the degrees of longitude spanned: 360 minus the widest empty arc."""
    lon = np.sort(np.mod(np.asarray(lon, dtype=np.float64), 360.0))
    gaps = np.diff(np.concatenate([lon, lon[:1] + 360.0]))
    return float(360.0 - gaps.max())


def _oblique_stereographic(lat: float, lon: float) -> CRS:
    """Return a named oblique stereographic CRS on WGS 84 centred on (lat, lon)."""
    lat, lon = round(lat, 6), round(lon, 6)
    proj = (
        f"+proj=sterea +lat_0={lat} +lon_0={lon} +k=1 +x_0=0 +y_0=0 "
        "+datum=WGS84 +units=m +no_defs"
    )
    name = (
        f"WGS 84 / oblique stereographic {abs(lat):g}{'N' if lat >= 0 else 'S'} "
        f"{abs(lon):g}{'E' if lon >= 0 else 'W'}"
    )
    return ProjectedCRS(
        CRS.from_proj4(proj).coordinate_operation,
        name=name,
        geodetic_crs=CRS.from_epsg(4326),
    )


def sample_size(
    grid: SizeGrid | PlaneSizes, xy: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Interpolate a size grid bilinearly, clamped to its edge values outside.

    Parameters
    ----------
    grid : SizeGrid or PlaneSizes
        Target edge lengths in metres on cell centres; or a field that samples
        itself (a ``SphereSizeGrid``).
    xy : ndarray of shape (n, 2)
        Positions in the grid's CRS.

    Returns
    -------
    ndarray of shape (n,)
        Target edge lengths in metres; the same interpolation Gmsh applies.

    Examples
    --------
    >>> g = SizeGrid([0.0, 10.0], [0.0, 10.0], [[1.0, 3.0], [1.0, 3.0]])
    >>> sample_size(g, np.array([[5.0, 5.0], [50.0, -5.0]])).tolist()
    [2.0, 3.0]
    """
    if not isinstance(grid, SizeGrid):  # a SphereSizeGrid: lon/lat, wraps round
        return grid.sample(xy)
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    if grid.patches:
        out = _bilinear(grid, xy)
        for patch in sorted(grid.patches, key=lambda p: -(p.x[1] - p.x[0])):
            inside = (
                (xy[:, 0] >= patch.x[0])
                & (xy[:, 0] <= patch.x[-1])
                & (xy[:, 1] >= patch.y[0])
                & (xy[:, 1] <= patch.y[-1])
            )
            out[inside] = _bilinear(patch, xy[inside])
        return out
    return _bilinear(grid, xy)


def _bilinear(grid: SizeGrid, xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Bilinear interpolation of one grid, clamped to its edges."""
    return interpolate_bilinear(
        grid.x, grid.y, grid.values, xy[:, 0], xy[:, 1], clamp=True
    )


def scale_factor(
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    mesh_crs: CRS,
    *,
    threads: int = 1,
) -> NDArray[np.float64]:
    """Return the point scale factor k of a conformal ``mesh_crs`` at points.

    Parameters
    ----------
    x, y : ndarray
        Projected coordinates in ``mesh_crs``, of the same shape.
    mesh_crs : pyproj.CRS
        A projected CRS.
    threads : int, default 1
        Blocks of points computed at once (PROJ lets go of the GIL): the
        same numbers for any number.

    Returns
    -------
    ndarray
        k at each point, the same shape as ``x``: map units per metre on the
        Earth (PROJ's meridional scale, equal to the parallel scale).

    Raises
    ------
    ValueError
        If a point has no longitude and latitude or no scale factor, or if
        ``mesh_crs`` is not conformal there (angular distortion above 1e-3
        degrees).
    """
    x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
    to_lonlat = transformer(mesh_crs, mesh_crs.geodetic_crs)
    projection = Proj(mesh_crs)
    flat_x, flat_y = x.ravel(), y.ravel()
    k = np.empty(flat_x.size)

    def block(start: int) -> float:
        part = slice(start, start + _SCALE_BLOCK)
        lon, lat = to_lonlat.transform(flat_x[part], flat_y[part])
        factors = projection.get_factors(lon, lat)
        k[part] = factors.meridional_scale
        bad = ~(np.isfinite(lon) & np.isfinite(lat) & np.isfinite(k[part]))
        bad |= ~(k[part] > 0)
        if bad.any():
            i = start + int(np.argmax(bad))
            raise ValueError(
                f"the size grid node at ({flat_x[i]:.1f}, {flat_y[i]:.1f}) has no "
                f"longitude, latitude or scale factor in mesh_crs {mesh_crs.name!r}; "
                "keep the grid inside the projection's valid area"
            )
        # a NaN (PROJ has no derivative there) is skipped, not taken as the max
        return float(np.fmax.reduce(factors.angular_distortion, initial=0.0))

    starts = range(0, flat_x.size, _SCALE_BLOCK)
    if threads > 1 and len(starts) > 1:
        with ThreadPoolExecutor(min(threads, len(starts))) as pool:
            distortion = max(pool.map(block, starts))  # the first error raises
    else:
        distortion = max(map(block, starts), default=0.0)
    if not distortion <= _MAX_ANGULAR_DISTORTION:
        raise ValueError(
            f"mesh_crs {mesh_crs.name!r} is not conformal: its angular distortion "
            f"reaches {distortion:.3g} degrees over the size grid, so triangles "
            "would be distorted on the Earth; mesh_crs must be conformal (UTM, "
            "stereographic, Lambert conformal conic, Mercator; default: "
            "default_mesh_crs)"
        )
    return k.reshape(x.shape)


def to_map_units(size: SizeGrid, mesh_crs: CRS, *, threads: int = 1) -> SizeGrid:
    """Convert a size grid from metres on the Earth to ``mesh_crs`` map units.

    Parameters
    ----------
    size : SizeGrid
        Target edge lengths in metres on the Earth, at nodes in ``mesh_crs``.
    mesh_crs : pyproj.CRS
        A projected, conformal CRS.
    threads : int, default 1
        Threads for the scale factors (:func:`scale_factor`).

    Returns
    -------
    SizeGrid
        The same nodes with values ``size.values * k``, k the point scale factor
        (:func:`scale_factor`; ``size.scale`` where the grid has it).
    """
    if not isinstance(size, SizeGrid):  # a SphereSizeGrid scales as it samples
        return size.in_map_units()
    if size.scale is not None:  # measured with the grid
        k = size.scale
    else:
        gx, gy = np.meshgrid(size.x, size.y)
        k = scale_factor(gx, gy, mesh_crs, threads=threads)
    logger.info(
        "size: scale factor %.4f to %.4f in %s", k.min(), k.max(), mesh_crs.name
    )
    patches = tuple(to_map_units(p, mesh_crs, threads=threads) for p in size.patches)
    return SizeGrid(size.x, size.y, size.values * k, patches=patches)


def project_rings(
    domain: Domain, mesh_crs: CRS
) -> tuple[list[list[NDArray[np.float64]]], list[list[int]]]:
    """Return the segments of a domain by ring, in the meshing CRS, and their ids.

    Parameters
    ----------
    domain : Domain
        The domain.
    mesh_crs : pyproj.CRS
        The CRS to mesh in.

    Returns
    -------
    rings : list of list of ndarray of shape (k, 2)
        For each ring (the exterior first), its segments' coordinates in
        ``mesh_crs``. Outside ``domain.crs`` they are densified first to a
        thousandth of the domain's extent, so lines straight in the domain CRS
        stay (almost) straight.
    ids : list of list of int
        The segments' physical ids, alike.

    Raises
    ------
    MeshingError
        If a segment has points with no position in ``mesh_crs``.
    """
    same = domain.crs == mesh_crs
    minx, miny, maxx, maxy = domain.polygon.bounds
    step = _DENSIFY_FRACTION * max(maxx - minx, maxy - miny)
    rings, ids = [], []
    for ring in domain.rings():
        coords = []
        for segment in ring:
            xy = segment.coords
            if not same:
                xy = shapely.get_coordinates(
                    shapely.segmentize(shapely.LineString(xy), step)
                )
                xy = project_points(
                    xy, domain.crs, mesh_crs, what=f"segment {segment.name!r}"
                )
            coords.append(xy)
        rings.append(coords)
        ids.append([segment.physical_id for segment in ring])
    return rings, ids


def project_points(
    xy: ArrayLike, src: CRS, dst: CRS, *, what: str
) -> NDArray[np.float64]:
    """Return points in another CRS, refusing points that have no position there.

    Parameters
    ----------
    xy : array_like of shape (n, 2)
        Points in ``src``.
    src, dst : pyproj.CRS
        From and to.
    what : str
        What the points are, for the error message (``"mesh nodes"``).

    Returns
    -------
    ndarray of shape (n, 2)
        The points in ``dst`` (:func:`~coastmesh.geometry.earth.reproject_points`).

    Raises
    ------
    MeshingError
        If a point comes out infinite or NaN.

    Examples
    --------
    >>> project_points([[-3.0, 0.0]], CRS(4326), CRS(32630), what="nodes").round()
    array([[500000.,      0.]])
    """
    out = reproject_points(xy, src, dst)
    if not np.isfinite(out).all():
        raise MeshingError(
            f"{what} cannot be projected to {dst.name!r}: infinite coordinates"
        )
    return out
