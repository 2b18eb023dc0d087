"""A global mesh checked on the sphere: fast code against a literal loop, and faults.

The reference below measures one triangle, edge or node pair at a time with the
math module: sides from the unit vectors, angles by the spherical law of
cosines, the area by L'Huilier's theorem, orientations as the triple product
the target names, and edges, copies and coincident nodes in dicts and sets.
Random meshes are convex hulls of random points on the sphere (a whole sphere
triangulated), cut, turned, copied and wrapped at random; the hand-made meshes
are a strip of near-equilateral triangles across the antimeridian, correct and
then broken in the ways a global mesh goes wrong.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.io.meshes.sphere import check_on_sphere
from coastmesh.meshing.quality import SphereQuality, mesh_quality, sphere_quality
from coastmesh.meshing.quality.sphere import SAME_NODE, sphere_triangle_measures
from coastmesh.types import Mesh

SPAN = 10.0

# ---------------------------------------------------------------- the reference


def unit_reference(lon, lat):
    lon, lat = math.radians(lon), math.radians(lat)
    return (
        math.cos(lat) * math.cos(lon),
        math.cos(lat) * math.sin(lon),
        math.sin(lat),
    )


def sub(u, v):
    return tuple(a - b for a, b in zip(u, v, strict=True))


def dot(u, v):
    return sum(a * b for a, b in zip(u, v, strict=True))


def cross(u, v):
    return (
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    )


def arc(u, v):
    return math.atan2(math.sqrt(dot(cross(u, v), cross(u, v))), dot(u, v))


def triangle_reference(a, b, c):
    """Orientation, smallest angle (deg), longest side (deg), area (sr)."""
    total = tuple(x + y + z for x, y, z in zip(a, b, c, strict=True))
    orientation = dot(cross(sub(b, a), sub(c, a)), total)
    sa, sb, sc = arc(b, c), arc(c, a), arc(a, b)  # sides opposite a, b, c
    angles = []
    for x, y, z in ((sa, sb, sc), (sb, sc, sa), (sc, sa, sb)):
        cos = (math.cos(x) - math.cos(y) * math.cos(z)) / (math.sin(y) * math.sin(z))
        angles.append(math.degrees(math.acos(max(-1.0, min(1.0, cos)))))
    s = (sa + sb + sc) / 2
    product = (
        math.tan(s / 2)
        * math.tan((s - sa) / 2)
        * math.tan((s - sb) / 2)
        * math.tan((s - sc) / 2)
    )
    area = 4 * math.atan(math.sqrt(max(product, 0.0)))
    return orientation, min(angles), math.degrees(max(sa, sb, sc)), area


def sphere_quality_reference(mesh, span=SPAN):
    """Every count of :class:`SphereQuality`, one thing at a time."""
    xyz = [unit_reference(lon, lat) for lon, lat in mesh.points.tolist()]
    same = list(range(len(xyz)))
    for i in range(len(xyz)):
        for j in range(i):
            if math.dist(xyz[i], xyz[j]) <= SAME_NODE:
                same[i] = same[j]
                break
    per = [triangle_reference(*(xyz[k] for k in t)) for t in mesh.triangles.tolist()]
    positive = sum(1 for o, *_ in per if o > 0)
    negative = sum(1 for o, *_ in per if o < 0)
    majority = 1 if positive >= negative else -1
    inverted = 0
    for (o, *_), t in zip(per, mesh.triangles.tolist(), strict=True):
        two_at_one_place = len({same[k] for k in t}) < 3
        inverted += o * majority <= 0 or two_at_one_place
    seen, duplicated = set(), 0
    edges = {}
    for t in mesh.triangles.tolist():
        nodes = [same[k] for k in t]
        key = tuple(sorted(nodes))
        duplicated += key in seen
        seen.add(key)
        for k in range(3):
            p, q, r = nodes[k], nodes[(k + 1) % 3], nodes[(k + 2) % 3]
            lo, hi = min(p, q), max(p, q)
            side = dot(cross(xyz[lo], xyz[hi]), xyz[r])
            edges.setdefault((lo, hi), []).append(side)
    folded = sum(
        1 for sides in edges.values() if len(sides) == 2 and sides[0] * sides[1] > 0
    )
    return {
        "triangles": len(per),
        "angles": [angle for _, angle, _, _ in per],
        "inverted": inverted,
        "coincident_nodes": sum(1 for i, s in enumerate(same) if s != i),
        "duplicated": duplicated,
        "overused_edges": sum(1 for sides in edges.values() if len(sides) > 2),
        "folded_edges": folded,
        "spanning": sum(1 for *_, longest, _ in per if longest > span),
        "max_arc": max(longest for *_, longest, _ in per),
        "area": sum(area for *_, area in per) * EARTH_RADIUS**2,
    }


# ------------------------------------------------------------------ random meshes


def hull_mesh(seed: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A whole sphere triangulated: the hull of the 6 axes' ends and ``n`` points.

    The axes' ends keep the centre inside the hull (each triangle less than a
    hemisphere) and put nodes at both poles.
    """
    rng = np.random.default_rng(seed)
    xyz = np.vstack([np.eye(3), -np.eye(3), rng.normal(size=(n, 3))])
    xyz /= np.linalg.norm(xyz, axis=1)[:, None]
    triangles = ConvexHull(xyz).simplices.copy()
    a, b, c = (xyz[triangles[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a) < 0
    triangles[inward] = triangles[inward][:, ::-1]
    lon = np.degrees(np.arctan2(xyz[:, 1], xyz[:, 0]))
    lat = np.degrees(np.arcsin(np.clip(xyz[:, 2], -1, 1)))
    return np.column_stack([lon, lat]), triangles


@st.composite
def broken_meshes(draw):
    """A hull, cut, with triangles turned and copied, nodes wrapped and doubled."""
    seed = draw(st.integers(0, 2**31))
    points, triangles = hull_mesh(seed, draw(st.integers(0, 40)))
    rng = np.random.default_rng(seed)
    keep = rng.random(len(triangles)) < draw(st.floats(0.5, 1.0))
    triangles = triangles[keep] if keep.any() else triangles
    turned = rng.random(len(triangles)) < draw(st.sampled_from([0.0, 0.1, 0.6]))
    triangles[turned] = triangles[turned][:, ::-1]
    copies = rng.integers(0, len(triangles), draw(st.integers(0, 3)))
    triangles = np.vstack([triangles, np.roll(triangles[copies], 1, axis=1)])
    wrapped = rng.random(len(points)) < draw(st.floats(0.0, 0.5))
    points[wrapped, 0] += np.where(points[wrapped, 0] < 0, 360.0, -360.0)
    doubled = rng.integers(0, len(points), draw(st.integers(0, 3)))
    copy = points[doubled] + [360.0, 0.0]
    renumber = np.arange(len(points) + len(doubled))
    renumber[doubled] = len(points) + np.arange(len(doubled))
    use = rng.random(triangles.shape) < 0.5
    triangles = np.where(use, renumber[triangles], triangles)
    return Mesh(np.vstack([points, copy]), triangles, [], [], 1, "EPSG:4326")


@settings(max_examples=30, deadline=None)
@given(broken_meshes(), st.sampled_from([5.0, 10.0, 60.0]))
def test_sphere_quality_matches_the_reference(mesh, span):
    fast = sphere_quality(mesh, span_limit=span)
    slow = sphere_quality_reference(mesh, span)
    for key in (
        "triangles",
        "inverted",
        "coincident_nodes",
        "duplicated",
        "overused_edges",
        "folded_edges",
        "spanning",
    ):
        assert getattr(fast, key) == slow[key], key
    angles = sphere_triangle_measures(
        np.array([unit_reference(*p) for p in mesh.points]), mesh.triangles
    )["min_angle"]
    np.testing.assert_allclose(angles, slow["angles"], atol=1e-6)
    assert fast.min_angle == pytest.approx(min(slow["angles"]), abs=1e-6)
    assert fast.min_angle_p1 == pytest.approx(
        np.percentile(slow["angles"], 1), abs=1e-6
    )
    assert fast.max_arc == pytest.approx(slow["max_arc"], abs=1e-9)
    assert fast.area == pytest.approx(slow["area"], rel=1e-9)
    assert fast.area == pytest.approx(check_on_sphere(mesh).area, rel=1e-9)
    assert fast.ok == (
        fast.min_angle_p1 >= 30
        and not any(slow[k] for k in ("inverted", "coincident_nodes", "duplicated"))
        and not any(slow[k] for k in ("overused_edges", "folded_edges", "spanning"))
    )


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**31), st.integers(0, 60))
def test_a_whole_sphere_is_covered_once_whichever_way_its_nodes_wrap(seed, n):
    points, triangles = hull_mesh(seed, n)
    q = sphere_quality(Mesh(points, triangles, [], [], 1, "EPSG:4326"))
    assert q.area == pytest.approx(4 * math.pi * EARTH_RADIUS**2, rel=1e-12)
    faults = (q.inverted, q.duplicated, q.overused_edges, q.folded_edges)
    assert faults == (0, 0, 0, 0)
    shifted = points + [[360.0 * (k % 3 - 1), 0.0] for k in range(len(points))]
    again = sphere_quality(Mesh(shifted, triangles, [], [], 1, None))
    for key in ("triangles", "inverted", "coincident_nodes", "duplicated", "spanning"):
        assert getattr(again, key) == getattr(q, key), key
    for key in ("min_angle", "min_angle_p1", "max_arc", "area"):
        assert getattr(again, key) == pytest.approx(getattr(q, key), rel=1e-12)


# --------------------------------------------------------- a strip across 180


def strip(rows: int = 4, columns: int = 8) -> Mesh:
    """Near-equilateral triangles from 177 E to 176 W over the equator, wrapped.

    Counter-clockwise in unwrapped longitude and latitude, so counter-clockwise
    seen from outside the sphere; nodes at 180 E are written as -180.
    """
    step = 1.0
    height = step * math.sqrt(3) / 2
    points = [
        [177.0 + step * (i + 0.5 * (j % 2)), height * (j - rows / 2)]
        for j in range(rows + 1)
        for i in range(columns + 1)
    ]
    triangles = []
    for j in range(rows):
        for i in range(columns):
            a, b = j * (columns + 1) + i, j * (columns + 1) + i + 1
            c, d = a + columns + 1, b + columns + 1
            if j % 2 == 0:
                triangles += [[a, b, c], [b, d, c]]
            else:
                triangles += [[a, d, c], [a, b, d]]
    points = np.array(points)
    points[:, 0] = (points[:, 0] + 180.0) % 360.0 - 180.0
    return Mesh(points, triangles, [], [], 1, "EPSG:4326")


def test_a_strip_wrapped_right_across_the_antimeridian_meets_the_target():
    mesh = strip()
    assert np.ptp(mesh.points[mesh.triangles, 0], axis=1).max() > 180  # it crosses
    q = sphere_quality(mesh)
    assert q.ok, q.summary()
    assert q.min_angle_p1 > 59 and q.max_arc < 1.01 and q.flagged == ()
    area = sphere_quality_reference(mesh)["area"]
    assert q.area == pytest.approx(area, rel=1e-9)


def test_an_inverted_triangle_is_found_where_it_is():
    mesh = strip()
    triangles = mesh.triangles.copy()
    triangles[5] = triangles[5][::-1]
    q = sphere_quality(replace(mesh, triangles=triangles))
    assert (q.inverted, q.folded_edges, q.duplicated) == (1, 0, 0)
    assert not q.ok
    assert [p.index for p in q.flagged] == [5]
    centre = mesh.points[mesh.triangles[5]]
    assert abs(q.flagged[0].lat - centre[:, 1].mean()) < 1e-3


def test_a_duplicated_triangle_is_found():
    mesh = strip()
    triangles = np.vstack([mesh.triangles, mesh.triangles[9][[1, 2, 0]]])
    q = sphere_quality(Mesh(mesh.points, triangles, [], [], 1, "EPSG:4326"))
    assert q.duplicated == 1 and q.overused_edges + q.folded_edges >= 3
    assert not q.ok
    assert {9, len(triangles) - 1} <= {p.index for p in q.flagged}


def test_a_triangle_doubled_across_the_antimeridian_on_copied_nodes_is_found():
    mesh = strip()
    seam = np.flatnonzero(mesh.points[:, 0] == -180.0)
    assert seam.size  # the strip has nodes on the antimeridian
    copies = mesh.points[seam] + [360.0, 0.0]  # the same places, at +180
    renumber = np.arange(len(mesh.points))
    renumber[seam] = len(mesh.points) + np.arange(seam.size)
    at_seam = np.flatnonzero(np.isin(mesh.triangles, seam).any(axis=1))
    doubled = renumber[mesh.triangles[at_seam[:2]]]
    points = np.vstack([mesh.points, copies])
    q = sphere_quality(
        Mesh(points, np.vstack([mesh.triangles, doubled]), [], [], 1, "EPSG:4326")
    )
    assert (q.coincident_nodes, q.duplicated) == (seam.size, 2)
    assert q.inverted == 0 and not q.ok
    # torn at the seam: the triangles east of 180 on the copies, none doubled
    unwrapped = np.where(mesh.points[:, 0] < 0, mesh.points[:, 0] + 360, 0)
    unwrapped += np.where(mesh.points[:, 0] >= 0, mesh.points[:, 0], 0)
    east = unwrapped[mesh.triangles].mean(axis=1) > 180
    assert 0 < east.sum() < len(east)
    torn = np.where(east[:, None], renumber[mesh.triangles], mesh.triangles)
    q = sphere_quality(Mesh(points, torn, [], [], 1, "EPSG:4326"))
    assert (q.coincident_nodes, q.duplicated, q.folded_edges) == (seam.size, 0, 0)
    assert not q.ok


def test_flat_triangles_count_as_inverted_and_their_copies_as_duplicated():
    mesh = strip()
    points = np.vstack([mesh.points, [[170.0, 0.0], [171.0, 0.0], [172.0, 0.0]]])
    points = np.vstack([points, mesh.points[:1] + [360.0, 0.0]])  # node 0 again
    n, n_old = len(mesh.points), len(mesh.triangles)
    flat = [[n, n + 1, n + 2], [n + 1, n + 2, n], [0, n + 3, 1]]
    triangles = np.vstack([mesh.triangles, flat])
    q = sphere_quality(Mesh(points, triangles, [], [], 1, "EPSG:4326"))
    slow = sphere_quality_reference(Mesh(points, triangles, [], [], 1, None))
    assert (q.inverted, q.duplicated, q.coincident_nodes) == (3, 1, 1)
    assert (slow["inverted"], slow["duplicated"], slow["coincident_nodes"]) == (3, 1, 1)
    # and triangle 0, whose edge 0-1 the collapsed one uses twice over
    assert {p.index for p in q.flagged} == {0, *range(n_old, len(triangles))}


@pytest.mark.parametrize(
    ("wrong", "what"),
    [
        (lambda lon: lon + 180.0, "wrapped by 180 degrees, not 360"),
        (lambda lon: -lon, "its sign dropped"),
    ],
)
def test_a_triangle_wrapped_wrong_across_the_antimeridian_is_found(wrong, what):
    mesh = strip()
    node = int(np.flatnonzero(mesh.points[:, 0] < -178.0)[3])  # west of 180
    points = mesh.points.copy()
    points[node, 0] = wrong(points[node, 0])
    q = sphere_quality(replace(mesh, points=points))
    reference = sphere_quality_reference(replace(mesh, points=points))
    assert not q.ok, what
    assert q.inverted + q.folded_edges + q.spanning > 0, what
    assert (q.inverted, q.folded_edges, q.spanning) == (
        reference["inverted"],
        reference["folded_edges"],
        reference["spanning"],
    )
    at_node = set(np.flatnonzero((mesh.triangles == node).any(axis=1)).tolist())
    assert {p.index for p in q.flagged} & at_node


def test_a_sliver_misses_the_angle_target_alone():
    mesh = strip()
    points = mesh.points.copy()
    points[:, 1] *= 0.3  # every triangle flattened: angles of about 19 degrees
    q = sphere_quality(replace(mesh, points=points))
    assert q.min_angle_p1 < 30 and q.below_30 == len(mesh.triangles)
    assert q.inverted == q.duplicated == q.folded_edges == q.spanning == 0
    assert not q.ok


def test_the_quality_report_carries_the_sphere_block():
    mesh = strip()
    sphere = sphere_quality(mesh)
    report = replace(mesh_quality(mesh), sphere=sphere)
    data = json.loads(json.dumps(report.to_dict()))
    assert data["sphere"]["inverted"] == 0
    assert data["sphere"]["min_angle_p1"] == pytest.approx(sphere.min_angle_p1)
    assert report.summary().splitlines()[-1].strip() == sphere.summary()
    assert mesh_quality(mesh).to_dict()["sphere"] is None


def test_bad_input_is_refused_with_the_value():
    mesh = strip()
    with pytest.raises(ValueError, match="not geographic"):
        sphere_quality(replace(mesh, crs="EPSG:32630"))
    points = mesh.points.copy()
    points[2, 1] = 91.0
    with pytest.raises(ValueError, match=r"mesh.points\[2\] has latitude 91"):
        sphere_quality(replace(mesh, points=points))
    with pytest.raises(ValueError, match="span_limit = 0"):
        sphere_quality(mesh, span_limit=0)
    with pytest.raises(TypeError, match="expected a Mesh"):
        sphere_quality(mesh.points)
    assert isinstance(sphere_quality(mesh), SphereQuality)
