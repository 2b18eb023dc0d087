"""Gmsh meshing engine: a Domain and a size grid in, a Mesh out.

This is the only module that imports gmsh, and only inside :func:`_gmsh_session`,
so ``import coastmesh.meshing`` stays light. Gmsh keeps process-global state: one
session at a time holds a lock, and the session is always finalised.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS, Proj, Transformer
from pyproj.crs import ProjectedCRS

from coastmesh.errors import MeshingError
from coastmesh.meshing.boundary import resample_rings
from coastmesh.types import Domain, Mesh, SizeGrid

__all__ = ["ALGORITHMS", "default_mesh_crs", "generate_mesh", "sample_size"]

logger = logging.getLogger(__name__)

#: Gmsh 2D algorithms by name (the ``Mesh.Algorithm`` option).
ALGORITHMS = {"meshadapt": 1, "automatic": 2, "delaunay": 5, "frontal-delaunay": 6}

_LOCK = threading.Lock()
# Geographic segments are densified to this fraction of the domain's extent before
# projection, so straight lines in the domain CRS stay (almost) straight.
_DENSIFY_FRACTION = 1e-3
# Relative precision of Gmsh's integral of 1/h along each curve (boundary nodes).
_INTEGRATION_PRECISION = 1e-4
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
    """Return the CRS :func:`generate_mesh` meshes in when none is given.

    A conformal projection keeps the triangles' shapes on the Earth; its point
    scale factor k (map length per metre on the Earth) then only changes their
    size, and :func:`generate_mesh` corrects for it. The choice keeps k close
    to 1 over the domain:

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
    generate_mesh : converts the target sizes by the scale factor of this CRS.

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
    to_lonlat = Transformer.from_crs(domain.crs, "EPSG:4326", always_xy=True)
    ring = shapely.get_coordinates(domain.polygon.exterior)
    lon, lat = to_lonlat.transform(ring[:, 0], ring[:, 1])
    centroid = domain.polygon.centroid
    c_lon, c_lat = to_lonlat.transform(centroid.x, centroid.y)
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


def sample_size(grid: SizeGrid, xy: NDArray[np.float64]) -> NDArray[np.float64]:
    """Interpolate a size grid bilinearly, clamped to its edge values outside.

    Parameters
    ----------
    grid : SizeGrid
        Target edge lengths in metres on cell centres.
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
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    x = np.clip(xy[:, 0], grid.x[0], grid.x[-1])
    y = np.clip(xy[:, 1], grid.y[0], grid.y[-1])
    i = np.clip(np.searchsorted(grid.x, x, side="right") - 1, 0, grid.x.size - 2)
    j = np.clip(np.searchsorted(grid.y, y, side="right") - 1, 0, grid.y.size - 2)
    tx = (x - grid.x[i]) / (grid.x[i + 1] - grid.x[i])
    ty = (y - grid.y[j]) / (grid.y[j + 1] - grid.y[j])
    v = grid.values
    return (
        (1 - tx) * (1 - ty) * v[j, i]
        + tx * (1 - ty) * v[j, i + 1]
        + (1 - tx) * ty * v[j + 1, i]
        + tx * ty * v[j + 1, i + 1]
    )


def _scale_factor(
    x: NDArray[np.float64], y: NDArray[np.float64], mesh_crs: CRS
) -> NDArray[np.float64]:
    """Return the point scale factor k of a conformal ``mesh_crs`` at points.

    Parameters
    ----------
    x, y : ndarray
        Projected coordinates in ``mesh_crs``, of the same shape.
    mesh_crs : pyproj.CRS
        A projected CRS.

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
    to_lonlat = Transformer.from_crs(mesh_crs, mesh_crs.geodetic_crs, always_xy=True)
    projection = Proj(mesh_crs)
    flat_x, flat_y = x.ravel(), y.ravel()
    k = np.empty(flat_x.size)
    distortion = 0.0
    for start in range(0, flat_x.size, _SCALE_BLOCK):
        block = slice(start, start + _SCALE_BLOCK)
        lon, lat = to_lonlat.transform(flat_x[block], flat_y[block])
        factors = projection.get_factors(lon, lat)
        k[block] = factors.meridional_scale
        bad = ~(np.isfinite(lon) & np.isfinite(lat) & np.isfinite(k[block]))
        bad |= ~(k[block] > 0)
        if bad.any():
            i = start + int(np.argmax(bad))
            raise ValueError(
                f"the size grid node at ({flat_x[i]:.1f}, {flat_y[i]:.1f}) has no "
                f"longitude, latitude or scale factor in mesh_crs {mesh_crs.name!r}; "
                "keep the grid inside the projection's valid area"
            )
        distortion = max(distortion, float(np.max(factors.angular_distortion)))
    if not distortion <= _MAX_ANGULAR_DISTORTION:
        raise ValueError(
            f"mesh_crs {mesh_crs.name!r} is not conformal: its angular distortion "
            f"reaches {distortion:.3g} degrees over the size grid, so triangles "
            "would be distorted on the Earth; mesh_crs must be conformal (UTM, "
            "stereographic, Lambert conformal conic, Mercator; default: "
            "default_mesh_crs)"
        )
    return k.reshape(x.shape)


def _to_map_units(size: SizeGrid, mesh_crs: CRS) -> SizeGrid:
    """Convert a size grid from metres on the Earth to ``mesh_crs`` map units.

    Parameters
    ----------
    size : SizeGrid
        Target edge lengths in metres on the Earth, at nodes in ``mesh_crs``.
    mesh_crs : pyproj.CRS
        A projected, conformal CRS.

    Returns
    -------
    SizeGrid
        The same nodes with values ``size.values * k``, k the point scale factor
        (:func:`_scale_factor`).
    """
    gx, gy = np.meshgrid(size.x, size.y)
    k = _scale_factor(gx, gy, mesh_crs)
    logger.info(
        "size: scale factor %.4f to %.4f in %s", k.min(), k.max(), mesh_crs.name
    )
    return SizeGrid(size.x, size.y, size.values * k)


def generate_mesh(
    domain: Domain,
    size: SizeGrid,
    *,
    mesh_crs: Any = None,
    output_crs: Any = None,
    seed: int = 0,
    algorithm: str = "frontal-delaunay",
    optimize: bool = True,
    progress: Callable[[int, int], None] | None = None,
) -> Mesh:
    """Mesh a domain with triangles whose edge lengths follow a size grid.

    Parameters
    ----------
    domain : Domain
        The polygon and its tagged boundary segments, in ``domain.crs``.
    size : SizeGrid
        Target edge length in metres on the Earth, on a regular grid in
        ``mesh_crs`` coordinates; clamped to the nearest grid value outside the
        grid. Build it in :func:`default_mesh_crs` when ``mesh_crs`` is not given.
    mesh_crs : pyproj.CRS or CRS-like, optional
        The CRS to mesh in: projected and conformal, so elements keep their shape
        on the Earth. Default :func:`default_mesh_crs`.
    output_crs : pyproj.CRS or CRS-like, optional
        The CRS of the returned points. Default ``domain.crs``.
    seed : int, default 0
        Seed of Gmsh's random number generator (``Mesh.RandomSeed``); >= 0.
    algorithm : {"frontal-delaunay", "delaunay", "meshadapt", "automatic"}
        Gmsh's 2D algorithm.
    optimize : bool, default True
        Improve the triangles' shapes after meshing (Gmsh "Relocate2D").
    progress : callable, optional
        Called as ``progress(done, total)`` after each of the stages.

    Returns
    -------
    Mesh
        Points in ``output_crs``; triangles counter-clockwise; every boundary edge
        oriented with the domain on its left and tagged with the ``physical_id``
        of its segment; ``surface_id`` from the domain. ``point_data["size"]`` is
        the target size at each node in metres on the Earth, from ``size``.

    Raises
    ------
    TypeError
        If ``domain`` or ``size`` has the wrong type.
    ValueError
        If ``algorithm``, ``seed`` or ``mesh_crs`` is invalid: a geographic or
        non-conformal ``mesh_crs`` (angular distortion above 1e-3 degrees on the
        size grid), or one in which a size grid node has no longitude and
        latitude.
    MeshingError
        If the boundary self-intersects after resampling, or Gmsh fails; the
        message carries Gmsh's last error.

    Warns
    -----
    SmallIslandWarning
        If islands smaller than the local size were dropped.

    Notes
    -----
    The sizes are metres on the Earth, and a conformal projection maps a length
    of h metres near a point to h * k map units, k the point scale factor there
    (``pyproj.Proj(mesh_crs).get_factors``, at each grid node's longitude and
    latitude in ``mesh_crs.geodetic_crs``). k is 0.9996 to 1.001 in a UTM zone
    but 2 at 60 degrees latitude in Mercator, so the grid is converted once to
    map units, ``size.values * k``, before the boundary is resampled and Gmsh
    sees it; edge lengths measured on the ellipsoid then follow ``size``.

    Each segment is projected to ``mesh_crs`` and resampled to about two points
    per local target edge (:func:`~coastmesh.meshing.boundary.resample_rings`),
    keeping end points and corners. Every piece between kept points becomes a
    Gmsh spline through the resampled points, so the boundary is smooth at the
    target resolution. The size grid is handed to Gmsh as a list-based
    post-processing view of quadrangles (bilinear interpolation), padded to the
    domain's bounds with the edge values, and used as the background field;
    sizes from points, curvature and the boundary are switched off, and the
    integral of 1/h along curves is computed to a relative precision of 1e-4.
    The run is reproducible: one thread, a fixed seed, fixed options; the same
    input gives the same arrays.

    Examples
    --------
    >>> import shapely
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]]
    >>> d = Domain(shapely.Polygon(ring), (BoundarySegment(ring, "open", "b", 3),),
    ...            crs="EPSG:32630")
    >>> g = SizeGrid([0.0, 1000.0], [0.0, 1000.0], np.full((2, 2), 250.0))
    >>> m = generate_mesh(d, g)
    >>> sorted(set(m.boundary_ids.tolist())), m.surface_id, m.crs.to_epsg()
    ([3], 1, 32630)
    """
    if not isinstance(domain, Domain):
        raise TypeError(f"domain is a {type(domain).__name__}, expected Domain")
    if not isinstance(size, SizeGrid):
        raise TypeError(f"size is a {type(size).__name__}, expected SizeGrid")
    if algorithm not in ALGORITHMS:
        raise ValueError(
            f"algorithm is {algorithm!r}; pick one of {sorted(ALGORITHMS)}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed is {seed!r}, expected an integer >= 0")
    mesh_crs = default_mesh_crs(domain) if mesh_crs is None else CRS(mesh_crs)
    if not mesh_crs.is_projected:
        raise ValueError(
            f"mesh_crs {mesh_crs.name!r} is not projected; give a conformal "
            "projection in metres (default: the UTM zone of the domain)"
        )
    output_crs = domain.crs if output_crs is None else CRS(output_crs)
    total = 4

    def step(done: int) -> None:
        if progress is not None:
            progress(done, total)

    started = time.perf_counter()
    map_size = _to_map_units(size, mesh_crs)
    rings, ids = _project_rings(domain, mesh_crs)
    resampled, dropped = resample_rings(rings, lambda xy: sample_size(map_size, xy))
    ids = [ring_ids for r, ring_ids in enumerate(ids) if r not in set(dropped)]
    _check_boundary(resampled)
    n_boundary = sum(len(p) - 1 for ring in resampled for seg in ring for p in seg)
    logger.info(
        "boundary: %d rings, %d -> %d vertices, %d islands dropped",
        len(rings),
        sum(len(c) for ring in rings for c in ring),
        n_boundary,
        len(dropped),
    )
    step(1)
    with _gmsh_session() as gmsh:
        points, triangles, edges, edge_ids = _run_gmsh(
            gmsh,
            resampled,
            ids,
            map_size,
            domain.surface_id,
            seed,
            algorithm,
            optimize,
            step,
        )
    target = sample_size(size, points)
    points = _transform(points, mesh_crs, output_crs)
    triangles = _orient(points, triangles)
    edges, edge_ids = _check_edges(triangles, edges, edge_ids)
    step(total)
    logger.info(
        "mesh: %d nodes, %d triangles, %d boundary edges in %.1f s",
        len(points),
        len(triangles),
        len(edges),
        time.perf_counter() - started,
    )
    return Mesh(
        points,
        triangles,
        edges,
        edge_ids,
        domain.surface_id,
        output_crs,
        {"size": target},
        {s.physical_id: s.name for s in domain.segments},
        {s.physical_id: s.kind for s in domain.segments},
    )


@contextmanager
def _gmsh_session() -> Iterator[Any]:
    """Initialise Gmsh, route its messages to our logger, and always finalise.

    Yields
    ------
    module
        The ``gmsh`` module, initialised with an empty model.
    """
    import gmsh

    with _LOCK:
        if gmsh.isInitialized():
            raise MeshingError(
                "Gmsh is already initialised in this process by other code; "
                "coastmesh needs it to itself"
            )
        gmsh.initialize(readConfigFiles=False, run=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.logger.start()
            gmsh.model.add("coastmesh")
            yield gmsh
        finally:
            _forward_log(gmsh)
            gmsh.logger.stop()
            gmsh.finalize()


def _forward_log(gmsh: Any) -> None:
    for line in gmsh.logger.get():
        if line.startswith(("Warning", "Error")):
            logger.warning("gmsh: %s", line)
        else:
            logger.debug("gmsh: %s", line)


def _project_rings(
    domain: Domain, mesh_crs: CRS
) -> tuple[list[list[NDArray[np.float64]]], list[list[int]]]:
    """Segment coordinates by ring, in the meshing CRS; and their physical ids."""
    same = domain.crs == mesh_crs
    transformer = (
        None if same else Transformer.from_crs(domain.crs, mesh_crs, always_xy=True)
    )
    minx, miny, maxx, maxy = domain.polygon.bounds
    step = _DENSIFY_FRACTION * max(maxx - minx, maxy - miny)
    rings, ids = [], []
    for ring in domain.rings():
        coords = []
        for segment in ring:
            xy = segment.coords
            if transformer is not None:
                xy = shapely.get_coordinates(
                    shapely.segmentize(shapely.LineString(xy), step)
                )
                xy = np.column_stack(transformer.transform(xy[:, 0], xy[:, 1]))
                if not np.isfinite(xy).all():
                    raise MeshingError(
                        f"segment {segment.name!r} cannot be projected to "
                        f"{mesh_crs.name!r}: infinite coordinates"
                    )
            coords.append(xy)
        rings.append(coords)
        ids.append([segment.physical_id for segment in ring])
    return rings, ids


def _check_boundary(rings: list[list[list[NDArray[np.float64]]]]) -> None:
    """Raise MeshingError if the resampled rings do not form a valid polygon."""
    coords = [
        np.concatenate([p[:-1] for seg in ring for p in seg] + [ring[0][0][:1]])
        for ring in rings
    ]
    polygon = shapely.Polygon(coords[0], coords[1:])
    if not polygon.is_valid:
        raise MeshingError(
            "the boundary resampled to the target size is not a valid polygon ("
            f"{shapely.is_valid_reason(polygon)}); reduce the size there or "
            "simplify the shoreline"
        )


def _grid_view_data(size: SizeGrid, bounds: tuple[float, ...]) -> NDArray[np.float64]:
    """Quadrangles of the size grid, padded to ``bounds``, in Gmsh list format."""
    minx, miny, maxx, maxy = bounds
    pad = 0.01 * max(maxx - minx, maxy - miny) + 1.0
    x, y, v = size.x, size.y, size.values
    if minx - pad < x[0]:
        x, v = np.concatenate([[minx - pad], x]), np.hstack([v[:, :1], v])
    if maxx + pad > x[-1]:
        x, v = np.concatenate([x, [maxx + pad]]), np.hstack([v, v[:, -1:]])
    if miny - pad < y[0]:
        y, v = np.concatenate([[miny - pad], y]), np.vstack([v[:1], v])
    if maxy + pad > y[-1]:
        y, v = np.concatenate([y, [maxy + pad]]), np.vstack([v, v[-1:]])
    gx, gy = np.meshgrid(x, y)
    corners = [(0, 0), (0, 1), (1, 1), (1, 0)]  # (dj, di), counter-clockwise

    def at(a: NDArray[np.float64], dj: int, di: int) -> NDArray[np.float64]:
        return a[dj : a.shape[0] - 1 + dj, di : a.shape[1] - 1 + di].ravel()

    columns = (
        [at(gx, dj, di) for dj, di in corners]
        + [at(gy, dj, di) for dj, di in corners]
        + [np.zeros(gx[:-1, :-1].size)] * 4
        + [at(v, dj, di) for dj, di in corners]
    )
    # gmsh's Python API takes a contiguous float64 array as it is (no list copy)
    return np.column_stack(columns).ravel()


def _run_gmsh(
    gmsh: Any,
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    size: SizeGrid,
    surface_id: int,
    seed: int,
    algorithm: str,
    optimize: bool,
    step: Callable[[int], None],
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Build the model, mesh it, and return nodes, triangles and tagged edges."""
    try:
        for name, value in (
            ("General.NumThreads", 1),
            ("Mesh.MaxNumThreads1D", 1),
            ("Mesh.MaxNumThreads2D", 1),
            ("Mesh.RandomSeed", int(seed)),
            ("Mesh.Algorithm", ALGORITHMS[algorithm]),
            ("Mesh.MeshSizeFromPoints", 0),
            ("Mesh.MeshSizeFromCurvature", 0),
            ("Mesh.MeshSizeExtendFromBoundary", 0),
            # 1e-9 (the default) makes 1D meshing of long splines 100 times slower
            ("Mesh.LcIntegrationPrecision", _INTEGRATION_PRECISION),
        ):
            gmsh.option.setNumber(name, value)
        curve_ids = _build_model(gmsh, rings, ids, surface_id)
        bounds = shapely.MultiPoint(
            np.concatenate([p for ring in rings for seg in ring for p in seg])
        ).bounds
        view = gmsh.view.add("size")
        data = _grid_view_data(size, bounds)
        gmsh.view.addListData(view, "SQ", len(data) // 16, data)
        field = gmsh.model.mesh.field.add("PostView")
        gmsh.model.mesh.field.setNumber(field, "ViewTag", view)
        gmsh.model.mesh.field.setAsBackgroundMesh(field)

        gmsh.model.mesh.generate(1)
        step(2)
        gmsh.model.mesh.generate(2)
        if optimize:
            gmsh.model.mesh.optimize("Relocate2D")
        step(3)
        node_tags, node_xyz, _ = gmsh.model.mesh.getNodes()
        _, tri_nodes = gmsh.model.mesh.getElementsByType(2)
        lines = [
            (gmsh.model.mesh.getElementsByType(1, curve)[1], pid)
            for curve, pid in curve_ids.items()
        ]
    except Exception as exc:  # gmsh raises bare Exception with its last error
        raise MeshingError(f"Gmsh failed: {exc}") from exc
    if len(tri_nodes) == 0:
        raise MeshingError(
            f"Gmsh made no triangles: {gmsh.logger.getLastError() or 'no message'}"
        )
    return _extract(node_tags, node_xyz, tri_nodes, lines)


def _build_model(
    gmsh: Any,
    rings: list[list[list[NDArray[np.float64]]]],
    ids: list[list[int]],
    surface_id: int,
) -> dict[int, int]:
    """Add points, curves, the surface and physical groups; return curve -> id."""
    geo = gmsh.model.geo
    curve_ids: dict[int, int] = {}
    loops = []
    for ring, ring_ids in zip(rings, ids, strict=True):
        pieces = [
            (p, pid) for seg, pid in zip(ring, ring_ids, strict=True) for p in seg
        ]
        first = geo.addPoint(*pieces[0][0][0], 0.0)
        start = first
        curves = []
        for k, (piece, pid) in enumerate(pieces):
            inner = [geo.addPoint(x, y, 0.0) for x, y in piece[1:-1]]
            end = first if k == len(pieces) - 1 else geo.addPoint(*piece[-1], 0.0)
            tags = [start, *inner, end]
            curve = geo.addLine(*tags) if len(tags) == 2 else geo.addSpline(tags)
            curve_ids[curve] = pid
            curves.append(curve)
            start = end
        loops.append(geo.addCurveLoop(curves))
    surface = geo.addPlaneSurface(loops)
    geo.synchronize()
    for pid in sorted(set(curve_ids.values())):
        curves = [c for c, p in curve_ids.items() if p == pid]
        gmsh.model.addPhysicalGroup(1, curves, tag=pid)
    gmsh.model.addPhysicalGroup(2, [surface], tag=surface_id)
    return curve_ids


def _extract(
    node_tags: NDArray,
    node_xyz: NDArray,
    tri_nodes: NDArray,
    lines: list[tuple[NDArray, int]],
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Gmsh node tags to indices; keep only the nodes triangles use."""
    index = np.full(int(node_tags.max()) + 1, -1, dtype=np.int64)
    index[node_tags.astype(np.int64)] = np.arange(len(node_tags))
    triangles = index[tri_nodes.astype(np.int64)].reshape(-1, 3)
    edges = index[np.concatenate([n for n, _ in lines]).astype(np.int64)].reshape(-1, 2)
    edge_ids = np.concatenate([np.full(len(n) // 2, pid) for n, pid in lines])
    used, renumber = np.unique(triangles, return_inverse=True)
    lookup = np.full(len(node_tags), -1, dtype=np.int64)
    lookup[used] = np.arange(len(used))
    points = node_xyz.reshape(-1, 3)[used, :2].copy()
    edges = lookup[edges]
    if (edges < 0).any():
        raise MeshingError("Gmsh made boundary edges whose nodes no triangle uses")
    return points, renumber.reshape(-1, 3), edges, edge_ids


def _transform(points: NDArray[np.float64], src: CRS, dst: CRS) -> NDArray[np.float64]:
    if src == dst:
        return points
    transformer = Transformer.from_crs(src, dst, always_xy=True)
    out = np.column_stack(transformer.transform(points[:, 0], points[:, 1]))
    if not np.isfinite(out).all():
        raise MeshingError(f"mesh nodes cannot be transformed to {dst.name!r}")
    return out


def _signed_areas(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray:
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return 0.5 * (
        (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    )


def _orient(points: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray:
    """Make every triangle counter-clockwise; raise on degenerate ones."""
    area = _signed_areas(points, triangles)
    if (area == 0).any():
        raise MeshingError(f"Gmsh made {(area == 0).sum()} triangles of zero area")
    triangles = triangles.copy()
    flip = area < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    return triangles


def _check_edges(
    triangles: NDArray[np.int64], edges: NDArray[np.int64], ids: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Orient tagged edges along triangles, check they are the boundary, sort."""
    n = int(triangles.max()) + 1
    directed = np.concatenate(
        [triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]
    )
    key = directed[:, 0] * n + directed[:, 1]
    reverse = directed[:, 1] * n + directed[:, 0]
    boundary = key[~np.isin(key, reverse)]
    forward = edges[:, 0] * n + edges[:, 1]
    flip = ~np.isin(forward, boundary)
    edges = edges.copy()
    edges[flip] = edges[flip][:, ::-1]
    tagged = edges[:, 0] * n + edges[:, 1]
    if len(tagged) != len(boundary) or not np.isin(boundary, tagged).all():
        raise MeshingError(
            f"the mesh has {len(boundary)} boundary edges but {len(tagged)} tagged "
            "edges match them; Gmsh did not conform to the boundary"
        )
    order = np.argsort(ids, kind="stable")
    return edges[order], ids[order].astype(np.int64)
