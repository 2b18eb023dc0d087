"""Literal, slow references for mesh quality: one triangle and one edge at a time.

Side lengths are WGS84 geodesics from ``pyproj.Geod.inv`` (not chords) for
longitude/latitude, or plain distances for planar metres; angles come from the law
of cosines, the radii from the classic formulas; valence, edges and boundary
nodes are counted with dicts and sets. Never import these from the package.
"""

from __future__ import annotations

import math

import numpy as np
from pyproj import Geod, Transformer

_GEOD = Geod(ellps="WGS84")


def lonlat_of(mesh):
    """The nodes as (lon, lat) on WGS84, or None for a planar mesh (no CRS)."""
    if mesh.crs is None:
        return None
    if mesh.crs.is_geographic:
        return [tuple(p) for p in mesh.points]
    to_lonlat = Transformer.from_crs(mesh.crs, "EPSG:4326", always_xy=True)
    return [to_lonlat.transform(x, y) for x, y in mesh.points]


def distance_reference(mesh, lonlat, i, j):
    """Geodesic (or planar) distance in metres between nodes i and j."""
    if lonlat is None:
        (x1, y1), (x2, y2) = mesh.points[i], mesh.points[j]
        return math.hypot(x2 - x1, y2 - y1)
    (lon1, lat1), (lon2, lat2) = lonlat[i], lonlat[j]
    _, _, distance = _GEOD.inv(lon1, lat1, lon2, lat2)
    return distance


def triangle_reference(a, b, c):
    """Minimum angle (degrees), 2 r_in / r_circ and area of a triangle with sides
    a, b, c, by the textbook formulas."""
    angles = []
    for opposite, x, y in ((a, b, c), (b, c, a), (c, a, b)):
        cos = (x * x + y * y - opposite * opposite) / (2 * x * y)
        cos = min(1.0, max(-1.0, cos))
        angles.append(math.degrees(math.acos(cos)))
    s = (a + b + c) / 2
    area = math.sqrt(max(s * (s - a) * (s - b) * (s - c), 0.0))
    r_in = area / s
    r_circ = a * b * c / (4 * area)
    return min(angles), 2 * r_in / r_circ, area


def triangle_quality_reference(mesh):
    """Per triangle: lists of minimum angle, radius ratio and area (m^2)."""
    lonlat = lonlat_of(mesh)
    out = {"min_angle": [], "radius_ratio": [], "area": [], "sides": []}
    for tri in mesh.triangles:
        p, q, r = (int(k) for k in tri)
        a = distance_reference(mesh, lonlat, q, r)
        b = distance_reference(mesh, lonlat, r, p)
        c = distance_reference(mesh, lonlat, p, q)
        angle, ratio, area = triangle_reference(a, b, c)
        out["min_angle"].append(angle)
        out["radius_ratio"].append(ratio)
        out["area"].append(area)
        out["sides"].append((a, b, c))
    return {key: np.array(values) for key, values in out.items()}


def mesh_quality_reference(mesh, size=None):
    """Edges, valence, boundary nodes and all-boundary triangles, counted by hand.

    Returns a dict: ``edges`` {(i, j): [triangles, length, ratio or None]} with
    i < j, ``boundary_nodes`` (set), ``interior_valence`` and ``boundary_valence``
    ({valence: nodes}), ``unused`` (int), ``all_boundary`` (list of triangle
    indices).
    """
    if size is None and "size" in mesh.point_data:
        size = mesh.point_data["size"]
    lonlat = lonlat_of(mesh)
    edges = {}
    valence = {}
    for tri in mesh.triangles:
        nodes = [int(k) for k in tri]
        for node in nodes:
            valence[node] = valence.get(node, 0) + 1
        for k in range(3):
            i, j = nodes[k], nodes[(k + 1) % 3]
            key = (min(i, j), max(i, j))
            if key in edges:
                edges[key][0] += 1
            else:
                edges[key] = [1, None, None]
    for (i, j), record in edges.items():
        record[1] = distance_reference(mesh, lonlat, i, j)
        if size is not None:
            target = (float(size[i]) + float(size[j])) / 2
            record[2] = record[1] / target
    boundary_nodes = set()
    for (i, j), record in edges.items():
        if record[0] == 1:
            boundary_nodes.add(i)
            boundary_nodes.add(j)
    interior_valence, boundary_valence = {}, {}
    unused = 0
    for node in range(len(mesh.points)):
        v = valence.get(node, 0)
        if v == 0:
            unused += 1
        elif node in boundary_nodes:
            boundary_valence[v] = boundary_valence.get(v, 0) + 1
        else:
            interior_valence[v] = interior_valence.get(v, 0) + 1
    all_boundary = []
    for index, tri in enumerate(mesh.triangles):
        if all(int(k) in boundary_nodes for k in tri):
            all_boundary.append(index)
    return {
        "edges": edges,
        "boundary_nodes": boundary_nodes,
        "interior_valence": interior_valence,
        "boundary_valence": boundary_valence,
        "unused": unused,
        "all_boundary": all_boundary,
    }
