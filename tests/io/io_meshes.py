"""Small meshes built by hand for the format tests, and ways to compare meshes.

Imported by the tests of this folder (``from io_meshes import ...``): pytest puts
the folder of a test module on ``sys.path``.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from coastmesh.types import Mesh


def cell_mesh(n, holes, edge_id, kinds, *, depth=True, crs="EPSG:32630", names=None):
    """An n x n square of unit cells, two ccw triangles each, minus ``holes``.

    Node (i, j) has index j * (n + 1) + i and coordinates (i, j); each boundary
    edge gets ``edge_id((x0, y0), (x1, y1))``.
    """
    xs, ys = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
    points = np.column_stack([xs.ravel(), ys.ravel()])
    triangles = []
    for j in range(n):
        for i in range(n):
            if (i, j) not in holes:
                a = j * (n + 1) + i
                triangles += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    triangles = np.array(triangles)
    count = {}
    for tri in triangles:
        for a, b in zip(tri, np.roll(tri, -1), strict=True):
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    edges = np.array(sorted(k for k, c in count.items() if c == 1))
    ids = [edge_id(tuple(points[a]), tuple(points[b])) for a, b in edges]
    point_data = {"depth": 10.0 + points[:, 0] + 2.5 * points[:, 1]} if depth else {}
    if names is None:
        names = {1: "coast", 2: "south", 3: "rock", 4: "reef"}
    return Mesh(points, triangles, edges, ids, 1, crs, point_data, names, kinds)


def strip_mesh(
    nx,
    ny,
    *,
    dx=100.0,
    dy=None,
    x0=0.0,
    y0=0.0,
    ids=None,
    jitter=0.0,
    crs="EPSG:32630",
    point_data=None,
    names=None,
    kinds=None,
    surface_id=1,
):
    """A structured grid split into ccw triangles; south edges open (2), rest coast (1).

    Nodes are ``dx`` apart in x and ``dy`` (default ``dx``) in y. ``ids``
    overrides the id of each boundary edge, counter-clockwise from (x0, y0);
    ``jitter`` moves the interior nodes by up to that much (seed 20240611);
    ``point_data`` defaults to a depth of 10 + the node index.
    """
    ii, jj = np.meshgrid(np.arange(nx), np.arange(ny))
    dy = dx if dy is None else dy
    points = np.column_stack([x0 + dx * ii.ravel(), y0 + dy * jj.ravel()])
    if jitter:
        inside = ((ii > 0) & (ii < nx - 1) & (jj > 0) & (jj < ny - 1)).ravel()
        rng = np.random.default_rng(20240611)
        points[inside] += rng.uniform(-jitter, jitter, (inside.sum(), 2))
    idx = (jj * nx + ii)[:-1, :-1].ravel()
    a, b, c, d = idx, idx + 1, idx + nx + 1, idx + nx
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    ring = np.concatenate(
        [
            np.arange(nx - 1),
            (nx - 1) + nx * np.arange(ny - 1),
            (ny - 1) * nx + np.arange(nx - 1, 0, -1),
            nx * np.arange(ny - 1, 0, -1),
        ]
    )
    edges = np.column_stack([ring, np.roll(ring, -1)])
    if ids is None:
        ids = np.where(np.arange(len(ring)) < nx - 1, 2, 1)
    if point_data is None:
        point_data = {"depth": 10.0 + np.arange(len(points), dtype=float)}
    return Mesh(
        points,
        tri,
        edges,
        ids,
        surface_id,
        crs,
        point_data,
        {1: "coast", 2: "sea", 3: "rock"} if names is None else names,
        {1: "shoreline", 2: "open", 3: "shoreline"} if kinds is None else kinds,
    )


def jittered_grid() -> Mesh:
    """A 5 x 4 node grid in UTM metres, interior nodes moved, 24 triangles.

    At most 57 m per node: no triangle (altitudes >= 156 m) can fold over.
    """
    return strip_mesh(
        5,
        4,
        dx=250.0,
        dy=200.0,
        x0=500000.0,
        jitter=40.0,
        point_data={},
        names={},
        kinds={},
        surface_id=7,
    )


def unit_square() -> Mesh:
    """The unit square as 2 triangles; bottom and right edges id 1, the rest id 2."""
    return Mesh(
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        [[0, 1, 2], [0, 2, 3]],
        [[0, 1], [1, 2], [2, 3], [3, 0]],
        [1, 1, 2, 2],
        3,
        "EPSG:32630",
    )


def canonical(m: Mesh):
    """Renumber nodes by coordinates, sort triangles and edges: order-free form."""
    order = np.lexsort(m.points.T[::-1])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    tri = np.sort(rank[m.triangles], axis=1)
    edges = np.column_stack([np.sort(rank[m.boundary_edges], axis=1), m.boundary_ids])
    return (
        m.points[order],
        tri[np.lexsort(tri.T[::-1])],
        edges[np.lexsort(edges.T[::-1])],
        m.surface_id,
    )


def same_topology(a: Mesh, b: Mesh) -> None:
    """Assert two meshes have the same nodes, triangles, boundary edges and ids."""
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.boundary_edges, b.boundary_edges)
    np.testing.assert_array_equal(a.boundary_ids, b.boundary_ids)
    assert a.surface_id == b.surface_id


def same_mesh(a: Mesh, b: Mesh) -> None:
    """Assert two meshes are the same, field for field (the input-unchanged check)."""
    same_topology(a, b)
    assert a.crs == b.crs
    assert a.point_data.keys() == b.point_data.keys()
    for key in a.point_data:
        np.testing.assert_array_equal(a.point_data[key], b.point_data[key])
    assert a.boundary_names == b.boundary_names
    assert a.boundary_kinds == b.boundary_kinds


def node_map(read: Mesh, written: Mesh, atol: float = 0.0) -> np.ndarray:
    """The written node of each read node, matched by coordinates (within ``atol``)."""
    scale = max(float(np.abs(written.points).max(initial=1.0)), 1.0)
    distance, index = cKDTree(written.points).query(read.points)
    assert distance.max(initial=0.0) <= atol + 1e-12 * scale, distance.max()
    assert len(np.unique(index)) == len(index)
    return index


def edge_ids(edges, ids, nodes=None):
    """Each undirected edge, by its written node numbers, mapped to its id."""
    edges = np.asarray(edges)
    if nodes is not None:
        edges = nodes[edges]
    return {
        (min(a, b), max(a, b)): int(i)
        for (a, b), i in zip(edges.tolist(), np.asarray(ids).tolist(), strict=True)
    }


def triangle_set(triangles, nodes=None):
    """The triangles as a set of sorted node triples, by written node numbers."""
    triangles = np.asarray(triangles)
    if nodes is not None:
        triangles = nodes[triangles]
    return {tuple(sorted(t)) for t in triangles.tolist()}


def signed_areas(mesh: Mesh) -> np.ndarray:
    """Twice the signed area of each triangle: > 0 counter-clockwise."""
    p = mesh.points[mesh.triangles]
    return (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (
        p[:, 2, 0] - p[:, 0, 0]
    ) * (p[:, 1, 1] - p[:, 0, 1])
