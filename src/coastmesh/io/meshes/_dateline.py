"""Triangles and boundary edges of a global mesh cut at the antimeridian, for a GIS.

RFC 7946 (GeoJSON), section 3.1.9, asks that a geometry crossing the
antimeridian be cut in two, so that no part crosses it; GDAL's
``-wrapdateline`` and QGIS's "Geodesic line split at antimeridian" do the same,
and give multi-part geometries. The mesh GeoPackage of a mesh on the sphere
(:func:`coastmesh.io.meshes.sphere.on_sphere`) follows them: every triangle is a
MultiPolygon and every boundary edge a MultiLineString, of one part, or of two
for those that cross the antimeridian, cut where the straight line between their
nodes in the lon/lat plane (longitude unwrapped) meets longitude 180. A triangle
around a pole becomes the cap between its edges and the pole (latitude +-90),
and a node at a pole becomes a stretch of latitude +-90, as a GIS draws them.

Reading back, the corners that are nodes (exactly, or with longitude 180 taken
as -180 and latitude +-90 as the node at that pole) give each feature its nodes;
the cut points are not nodes.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.errors import InputDataError
from coastmesh.geometry.sphere import lonlat_to_xyz, wrap_longitude
from coastmesh.io.meshes.sphere import crossing_triangles, solid_angles

__all__ = ["cut_edges", "cut_triangles", "edge_nodes", "triangle_nodes"]

_WINDOWS = (-1, 0, 1)  # unwrapped longitudes lie within [-540, 540]


def cut_triangles(
    points: NDArray[np.float64], triangles: NDArray[np.int64]
) -> NDArray[np.object_]:
    """Return one MultiPolygon per triangle, cut at the antimeridian.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
        Longitude in [-180, 180), latitude, degrees.
    triangles : ndarray of shape (M, 3)
        Node indices, counter-clockwise on the sphere.

    Returns
    -------
    ndarray of shapely MultiPolygon, shape (M,)
        Counter-clockwise parts (RFC 7946), all within [-180, 180].

    Examples
    --------
    >>> points = np.array([[179.0, 0.0], [-179.0, 0.0], [179.5, 1.0]])
    >>> cut = cut_triangles(points, np.array([[0, 1, 2]]))[0]
    >>> [round(part.area, 6) for part in cut.geoms]
    [0.666667, 0.333333]
    """
    special = crossing_triangles(points, triangles) | (np.abs(points[:, 1]) == 90)[
        triangles
    ].any(axis=1)
    corners = points[triangles]
    parts = list(shapely.polygons(np.concatenate([corners, corners[:, :1]], axis=1)))
    owners = list(range(len(triangles)))
    for k in np.flatnonzero(special):
        pieces = _cut(corners[k])
        parts[k] = pieces[0]
        parts += pieces[1:]
        owners += [int(k)] * (len(pieces) - 1)
    order = np.argsort(owners, kind="stable")
    parts = shapely.orient_polygons(np.array(parts, dtype=object)[order])
    return shapely.multipolygons(parts, indices=np.asarray(owners)[order])


def cut_edges(
    points: NDArray[np.float64], edges: NDArray[np.int64]
) -> NDArray[np.object_]:
    """Return one MultiLineString per edge, cut at the antimeridian.

    Examples
    --------
    >>> points = np.array([[179.0, 0.0], [-179.0, 2.0]])
    >>> print(cut_edges(points, np.array([[0, 1]]))[0])
    MULTILINESTRING ((179 0, 180 1), (-180 1, -179 2))
    """
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    special = (np.abs(b[:, 0] - a[:, 0]) > 180) | (np.abs(a[:, 1]) == 90)
    special |= np.abs(b[:, 1]) == 90
    parts = list(shapely.linestrings(np.stack([a, b], axis=1)))
    owners = list(range(len(edges)))
    for k in np.flatnonzero(special):
        pieces = _cut_line(a[k], b[k])
        parts[k] = pieces[0]
        parts += pieces[1:]
        owners += [int(k)] * (len(pieces) - 1)
    order = np.argsort(owners, kind="stable")
    return shapely.multilinestrings(
        np.array(parts, dtype=object)[order], indices=np.asarray(owners)[order]
    )


def triangle_nodes(
    nodes: NDArray[np.float64],
    geometry: NDArray[np.object_],
    path: str,
    layer: str,
    *,
    sphere: bool,
) -> NDArray[np.int64]:
    """Return the three nodes of each (multi-)polygon, in order.

    The corners that are nodes, in the order they first appear; with ``sphere``
    (lon/lat nodes), each triangle is then turned to run counter-clockwise on
    the sphere (a cut one may list its nodes in either order).

    Raises
    ------
    InputDataError
        If a feature's corners name other than three nodes.
    """
    parts, owner = shapely.get_parts(geometry, return_index=True)
    coords, index = shapely.get_coordinates(
        shapely.get_exterior_ring(parts), return_index=True
    )
    closing = np.r_[index[1:] != index[:-1], True]  # each ring repeats its start
    coords, feature = coords[~closing], owner[index[~closing]]
    found = _match(nodes, coords)
    hit = found >= 0
    feature, found = feature[hit], found[hit]
    n = max(len(nodes), 1)
    _, first = np.unique(feature * n + found, return_index=True)
    first = np.sort(first)
    counts = np.bincount(feature[first], minlength=len(geometry))
    if (counts != 3).any():
        k = int(np.flatnonzero(counts != 3)[0])
        raise InputDataError(
            f"its corners are {counts[k]} nodes, expected 3",
            path=path,
            layer=layer,
            feature=k,
        )
    triangles = found[first].reshape(-1, 3)
    if sphere:
        turn = solid_angles(lonlat_to_xyz(nodes), triangles) < 0
        triangles[turn] = triangles[turn][:, [0, 2, 1]]
    return triangles


def edge_nodes(
    nodes: NDArray[np.float64], geometry: NDArray[np.object_], path: str, layer: str
) -> NDArray[np.int64]:
    """Return the nodes at the two ends of each (multi-)line.

    Raises
    ------
    InputDataError
        If an end is not a node.
    """
    coords, index = shapely.get_coordinates(geometry, return_index=True)
    if len(geometry) == 0:
        return np.empty((0, 2), dtype=np.int64)
    starts = np.searchsorted(index, np.arange(len(geometry)))
    ends = np.searchsorted(index, np.arange(len(geometry)), side="right") - 1
    found = _match(nodes, coords[np.column_stack([starts, ends]).ravel()])
    if (found < 0).any():
        k = int(np.flatnonzero(found < 0)[0])
        raise InputDataError(
            "an end of the line is not a node", path=path, layer=layer, feature=k // 2
        )
    return found.reshape(-1, 2)


def _cut(corners: NDArray[np.float64]) -> list[shapely.Polygon]:
    """Cut one triangle (3 lon/lat corners, counter-clockwise) into parts."""
    pole = np.abs(corners[:, 1]) == 90
    start = int(np.argmin(pole))  # a corner away from the poles
    ring = [(corners[start, 0], corners[start, 1])]
    lon = corners[start, 0]
    for step in (1, 2, 3):
        here, before = (start + step) % 3, (start + step - 1) % 3
        if pole[here]:  # up the meridian, along the pole, down the next one
            ring.append((lon, corners[here, 1]))
            lon += wrap_longitude(corners[(here + 1) % 3, 0] - corners[before, 0])
            ring.append((lon, corners[here, 1]))
            continue
        if not pole[before]:
            lon += wrap_longitude(corners[here, 0] - corners[before, 0])
        if step < 3:
            ring.append((lon, corners[here, 1]))
    turns = round((lon - ring[0][0]) / 360)
    if turns:  # around a pole: on to the start again, and back along the pole
        cap = 90.0 if turns > 0 else -90.0
        ring += [(lon, ring[0][1]), (lon, cap), (ring[0][0], cap)]
    return _windows(shapely.Polygon(ring), corners, shapely.Polygon, _WINDOWS)


def _cut_line(a: NDArray[np.float64], b: NDArray[np.float64]) -> list[Any]:
    """Cut one edge from lon/lat ``a`` to ``b`` into parts."""
    ends = np.array([a, b], dtype=np.float64)
    if abs(a[1]) == 90:  # an edge to a pole runs along its other node's meridian
        ends[0, 0] = b[0]
    if abs(b[1]) == 90:
        ends[1, 0] = a[0]
    ends[1, 0] = ends[0, 0] + wrap_longitude(ends[1, 0] - ends[0, 0])
    line = shapely.LineString(ends)
    westwards = ends[1, 0] < ends[0, 0]  # the parts in order along the edge
    return _windows(
        line, np.array([a, b]), shapely.LineString, _WINDOWS[:: -1 if westwards else 1]
    )


def _windows(
    geometry: Any, nodes: NDArray[np.float64], kind: type, windows: tuple[int, ...]
) -> list[Any]:
    """Return the parts of ``geometry`` (longitudes unwrapped) in [-180, 180].

    Each vertex within 1e-9 degrees of a node (other than a pole) gets the
    node's exact coordinates, so that a reader finds it; a node at longitude
    -180 on the eastern edge of a part is written at 180.
    """
    pieces = []
    for k in windows:
        clipped = shapely.clip_by_rect(geometry, 360 * k - 180, -90, 360 * k + 180, 90)
        for part in shapely.get_parts(clipped):
            size = part.area if kind is shapely.Polygon else part.length
            if isinstance(part, kind) and size > 0:
                moved = shapely.transform(part, lambda xy, k=k: xy - [360 * k, 0])
                pieces.append(shapely.transform(moved, lambda xy: _snap(xy, nodes)))
    return pieces


def _snap(xy: NDArray[np.float64], nodes: NDArray[np.float64]) -> NDArray[np.float64]:
    xy = xy.copy()
    for lon, lat in nodes:
        if abs(lat) == 90:
            continue
        near = np.abs(xy[:, 1] - lat) < 1e-9
        near &= np.abs(wrap_longitude(xy[:, 0] - lon)) < 1e-9
        east = (lon == -180) & (xy[:, 0] > 0)
        xy[near, 0] = np.where(east[near], 180.0, lon)
        xy[near, 1] = lat
    return xy


def _match(
    nodes: NDArray[np.float64], coords: NDArray[np.float64]
) -> NDArray[np.int64]:
    """Return the node at each lon/lat coordinate, or -1 (a cut point).

    Exact matches first; then longitude moved into [-180, 180) (180 is -180);
    then latitude +-90 as the node at that pole, if there is one.
    """
    keys = nodes[:, 0] + 1j * nodes[:, 1]
    order = np.argsort(keys)
    ordered = keys[order]

    def lookup(wanted: NDArray[np.complex128]) -> NDArray[np.int64]:
        if len(ordered) == 0:
            return np.full(len(wanted), -1, dtype=np.int64)
        where = np.minimum(np.searchsorted(ordered, wanted), len(ordered) - 1)
        return np.where(ordered[where] == wanted, order[where], -1)

    found = lookup(coords[:, 0] + 1j * coords[:, 1])
    missing = found < 0
    found[missing] = lookup(
        wrap_longitude(coords[missing, 0]) + 1j * coords[missing, 1]
    )
    for lat in (90.0, -90.0):
        at_pole = np.flatnonzero(nodes[:, 1] == lat)
        if len(at_pole) == 1:
            found[(found < 0) & (coords[:, 1] == lat)] = at_pole[0]
    return found
