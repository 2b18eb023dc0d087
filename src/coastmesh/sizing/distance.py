"""Distance from a set of lines to the nodes of a grid, in metres on the Earth."""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS
from scipy.spatial import cKDTree

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS, earth_centred, metres_per_unit

__all__ = [
    "chord_bound",
    "distance_to_lines",
    "grid_nodes",
    "line_vertices",
    "nearest_arcs",
]

# A projected CRS's scale error is a few per mille in conformal projections: the
# densifying step allows 2 % more ground per CRS unit than the unit says.
_PROJECTED_MARGIN = 1.02


def distance_to_lines(
    lines: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    *,
    crs: CRS | str,
    resolution: float,
    max_distance: float | None = None,
) -> NDArray[np.float64]:
    """Distance from every node of a grid to the nearest of a set of lines.

    Parameters
    ----------
    lines : array_like of shapely geometries
        Lines or polygons (their rings count) in ``crs``.
    x, y : array_like of shape (nx,), (ny,)
        Node coordinates of the grid in ``crs``.
    crs : pyproj.CRS or str
        CRS of the lines and the grid (geographic or projected).
    resolution : float
        Accuracy wanted, metres (> 0): the lines are densified so that no point of
        a line is farther than ``resolution`` from a vertex, and the distances are
        exact to within ``resolution``.
    max_distance : float, optional
        Nodes farther than this (metres) from every line get ``inf``; the search
        stops there, which is much faster when most nodes are far away.

    Returns
    -------
    ndarray of shape (ny, nx)
        Distances, metres, as great-circle arcs on a sphere of radius
        :data:`~coastmesh.geometry.earth.EARTH_RADIUS` through the WGS84
        earth-centred coordinates (within 0.5 % of the ellipsoidal geodesic).

    Raises
    ------
    ConfigError
        If ``resolution`` is not > 0 or no line is given.
    ValueError
        If a line vertex or a grid node has no position on the Earth in ``crs``.

    Notes
    -----
    Lines and nodes go to WGS84 earth-centred coordinates
    (:func:`~coastmesh.geometry.earth.earth_centred`), where a k-d
    tree (scipy) finds each node's nearest line vertex by chord length; chords
    become arcs with ``2 R asin(c / 2R)``. Never raw degrees of longitude.

    Examples
    --------
    >>> import shapely
    >>> coast = shapely.LineString([(0.0, 60.0), (1.0, 60.0)])
    >>> d = distance_to_lines([coast], [0.5], [60.0, 61.0], crs="EPSG:4326",
    ...                       resolution=100.0)
    >>> round(d[0, 0]), round(d[1, 0] / 1000)
    (0, 111)
    """
    crs = CRS.from_user_input(crs)
    vertices = line_vertices(lines, crs, resolution)
    xs, ys = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    nodes = grid_nodes(xs, ys, crs)
    arc = nearest_arcs(
        vertices, nodes, resolution=resolution, max_distance=max_distance
    )
    return arc.reshape(len(ys), len(xs))


def grid_nodes(x: ArrayLike, y: ArrayLike, crs: CRS) -> NDArray[np.float64]:
    """Return the nodes of the grid ``x`` by ``y`` earth-centred, row by row."""
    gx, gy = np.meshgrid(np.asarray(x, float), np.asarray(y, float))
    return earth_centred(
        np.column_stack([gx.ravel(), gy.ravel()]), crs, name="grid nodes"
    )


def line_vertices(lines: ArrayLike, crs: CRS, resolution: float) -> NDArray[np.float64]:
    """Return the lines' vertices, densified to ``resolution``, earth-centred.

    Polygons count by their rings. See :func:`distance_to_lines`.
    """
    if not resolution > 0:
        raise ConfigError(f"resolution = {resolution}: must be > 0 metres")
    geoms = np.asarray(lines, dtype=object).ravel()
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    if len(geoms) == 0:
        raise ConfigError("distance_to_lines: no lines given")
    boundaries = shapely.boundary(geoms)
    polygonal = np.isin(
        shapely.get_type_id(geoms),
        (shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON),
    )
    geoms = np.where(polygonal, boundaries, geoms)
    # Densify in the lines' own CRS with a step that is safely below the
    # resolution, measured by the widest stretch of one CRS unit on the ground
    # (a degree of latitude for a geographic CRS).
    widest = metres_per_unit(crs)
    if not crs.is_geographic:
        widest *= _PROJECTED_MARGIN
    step = resolution / widest
    vertices = shapely.get_coordinates(shapely.segmentize(geoms, step))
    return earth_centred(vertices, crs, name="line vertices")


def chord_bound(max_distance: float | None, resolution: float) -> float:
    """Return the chord beyond which :func:`nearest_arcs` stops searching.

    The chord of an arc of length ``s`` is ``2 R sin(s / 2R) <= s``; ``inf``
    without ``max_distance``.
    """
    if max_distance is None:
        return np.inf
    half = min(max_distance / (2 * EARTH_RADIUS), np.pi / 2)
    chord: float = 2 * EARTH_RADIUS * np.sin(half) * (1 + 1e-9) + resolution
    return chord


#: The coarse pass of :func:`nearest_arcs` keeps a vertex per cube of this
#: many ``resolution``s a side.
_COARSE = 20.0
#: ... and searches each group of nodes, of nearly equal coarse distance,
#: within that group's bound: this many groups.
_GROUPS = 24


def nearest_arcs(
    vertices: NDArray[np.float64],
    nodes: NDArray[np.float64],
    *,
    resolution: float,
    max_distance: float | None = None,
) -> NDArray[np.float64]:
    """Arc length (metres) from each earth-centred node to its nearest vertex.

    ``inf`` beyond ``max_distance`` (the k-d tree stops searching there).

    The vertices are thinned to one per cube of half ``resolution`` (the
    arcs stay within it); then in two passes: a k-d tree of a vertex per cube
    of :data:`_COARSE` resolutions gives each node a chord ``d0`` to some
    vertex, so its nearest vertex is within ``d0`` and no nearer than ``d0``
    less the cube's diagonal; then the nodes, in groups of nearly equal
    ``d0``, search the whole tree each within its group's largest ``d0``.
    One search to ``max_distance`` for every node explored the whole of that
    radius for nodes far from a coast: 23 s on the world grid (1 million
    nodes, 1.2 million coast vertices), where the two passes take a few.
    """
    bound = chord_bound(max_distance, resolution)
    # a vertex per cube of half the resolution: the distances stay within it
    # (a cube's diagonal is 0.87 of it), and the tree holds no crowd of
    # vertices centimetres apart, which slows every search through them
    vertices = _thinned(vertices, 0.5 * resolution)
    cube = _COARSE * resolution
    coarse, _ = cKDTree(_thinned(vertices, cube)).query(
        nodes, workers=-1, distance_upper_bound=bound + 2.0 * cube
    )
    chord = np.full(len(nodes), np.inf)
    reach = coarse - np.sqrt(3.0) * cube  # no vertex is nearer than this
    near = np.flatnonzero(reach <= bound)  # so coarse is finite there
    if len(near):
        tree = cKDTree(vertices)
        order = near[np.argsort(coarse[near], kind="stable")]
        for group in np.array_split(order, min(_GROUPS, len(order))):
            chord[group], _ = tree.query(
                nodes[group],
                workers=-1,
                distance_upper_bound=min(
                    float(coarse[group].max()) * (1 + 1e-9), bound
                ),
            )
    arc = 2 * EARTH_RADIUS * np.arcsin(np.minimum(chord / (2 * EARTH_RADIUS), 1.0))
    arc[np.isinf(chord)] = np.inf
    return arc


def _thinned(points: NDArray[np.float64], cube: float) -> NDArray[np.float64]:
    """Return the first of ``points`` in each cube of side ``cube`` (metres)."""
    if not len(points):
        return points
    cells = np.floor(points / cube).astype(np.int64)
    cells -= cells.min(axis=0)
    span = cells.max(axis=0) + 1
    # one integer per cube (np.unique over rows sorts them as records, 5x slower)
    key = (cells[:, 0] * span[1] + cells[:, 1]) * span[2] + cells[:, 2]
    _, first = np.unique(key, return_index=True)
    return points[np.sort(first)]
