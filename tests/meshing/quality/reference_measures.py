"""Literal, slow references for time steps, Courant numbers and boundary corners.

One triangle, edge or node at a time, with the math module: sides are geodesics
or planar distances (:mod:`reference_quality`), the area is Heron's textbook
formula, angles are the law of cosines, and boundary edges and nodes are counted
with dicts and sets. Also a hypothesis strategy for random planar meshes
(``scipy.spatial.Delaunay`` of random points). Never import these from the
package.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import strategies as st
from reference_quality import distance_reference, lonlat_of
from scipy.spatial import Delaunay

from coastmesh.types import Mesh

G = 9.80665  # standard gravity, as coastmesh.geometry.earth.GRAVITY


def sides_reference(mesh):
    """Per triangle, its sides (a, b, c) opposite nodes 0, 1, 2, in metres."""
    lonlat = lonlat_of(mesh)
    out = []
    for tri in mesh.triangles:
        p, q, r = (int(k) for k in tri)
        out.append(
            (
                distance_reference(mesh, lonlat, q, r),
                distance_reference(mesh, lonlat, r, p),
                distance_reference(mesh, lonlat, p, q),
            )
        )
    return out


def time_step_reference(mesh, velocity=0.0, dt=None):
    """Per triangle: r_in = 2 A / P, c = sqrt(g max(d, 0)) + u with d the deepest
    node, dt_e = r_in / c (inf when c == 0) and C = dt c / (P / 3); as lists."""
    depth = mesh.point_data["depth"]
    out = {"r_in": [], "wave_speed": [], "dt": [], "courant": []}
    for tri, (a, b, c) in zip(mesh.triangles, sides_reference(mesh), strict=True):
        perimeter = a + b + c
        s = perimeter / 2
        area = math.sqrt(max(s * (s - a) * (s - b) * (s - c), 0.0))
        r_in = 2 * area / perimeter
        deepest = max(float(depth[int(k)]) for k in tri)
        speed = math.sqrt(G * max(deepest, 0.0)) + velocity
        out["r_in"].append(r_in)
        out["wave_speed"].append(speed)
        out["dt"].append(r_in / speed if speed > 0 else math.inf)
        if dt is not None:
            out["courant"].append(dt * speed / (perimeter / 3))
    return {key: np.array(values) for key, values in out.items()}


def boundary_reference(mesh):
    """Edges in one triangle: {(i, j): count} with i < j, and the boundary nodes."""
    count = {}
    for tri in mesh.triangles:
        nodes = [int(k) for k in tri]
        for k in range(3):
            i, j = nodes[k], nodes[(k + 1) % 3]
            key = (min(i, j), max(i, j))
            count[key] = count.get(key, 0) + 1
    edges = [key for key, n in count.items() if n == 1]
    nodes = set()
    for i, j in edges:
        nodes.add(i)
        nodes.add(j)
    return edges, nodes


def corner_reference(mesh):
    """{boundary node: interior angle in degrees}, the angles of its triangles
    there (law of cosines) added up."""
    _, boundary = boundary_reference(mesh)
    total = dict.fromkeys(boundary, 0.0)
    for tri, sides in zip(mesh.triangles, sides_reference(mesh), strict=True):
        for k in range(3):
            node = int(tri[k])
            if node not in total:
                continue
            opposite = sides[k]
            x, y = sides[(k + 1) % 3], sides[(k + 2) % 3]
            cos = (x * x + y * y - opposite * opposite) / (2 * x * y)
            total[node] += math.degrees(math.acos(min(1.0, max(-1.0, cos))))
    return total


def channel_reference(mesh):
    """Triangles with three boundary nodes and at most one boundary side."""
    edges, boundary = boundary_reference(mesh)
    edges = set(edges)
    out = []
    for index, tri in enumerate(mesh.triangles):
        nodes = [int(k) for k in tri]
        if not all(node in boundary for node in nodes):
            continue
        sides = 0
        for k in range(3):
            i, j = nodes[k], nodes[(k + 1) % 3]
            sides += (min(i, j), max(i, j)) in edges
        if sides <= 1:
            out.append(index)
    return out


@st.composite
def delaunay_meshes(draw, *, span=10_000.0):
    """A planar mesh (no CRS, metres): the Delaunay triangulation of 4 to 40
    random points in a ``span`` square, its hull edges tagged 1 (shoreline) and
    2 (open), and a random depth (-20 to 200 m) at each node."""
    seed = draw(st.integers(0, 2**32 - 1))
    n = draw(st.integers(4, 40))
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, span, (n, 2))
    tri = Delaunay(points)
    hull = np.sort(tri.convex_hull, axis=1)
    ids = np.where(hull[:, 0] % 2 == 0, 1, 2)
    depth = rng.uniform(-20, 200, n)
    return Mesh(
        points,
        tri.simplices,
        hull,
        ids,
        1,
        None,
        {"depth": depth},
        {1: "coast", 2: "sea"},
        {1: "shoreline", 2: "open"},
    )
