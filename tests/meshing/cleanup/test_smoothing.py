"""Guarded smoothing: the fast kernel against a literal loop, and its guarantees."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import clustered_delaunay
from hypothesis import example, given, settings
from hypothesis import strategies as st

from coastmesh.errors import ConfigError
from coastmesh.meshing import SmoothingReport, mesh_quality, smooth_mesh
from coastmesh.meshing.cleanup.planar import radius_ratios
from coastmesh.meshing.cleanup.smoothing import (
    _angle_gradient,
    boundary_nodes,
    min_angles,
    smooth_points,
)
from coastmesh.types import Mesh

FRACTIONS = (1.0, 0.5, 0.25, 0.125)  # the steps tried, then none


def _angle(p, q, r):
    """The angle at p of triangle p, q, r (radians), negative if clockwise."""
    u, v = (q[0] - p[0], q[1] - p[1]), (r[0] - p[0], r[1] - p[1])
    return math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])


def _min_angle(xy, t):
    """The smallest angle (degrees) of triangle t; negative if it turned over."""
    a, b, c = (xy[v] for v in t)
    angles = (_angle(a, b, c), _angle(b, c, a), _angle(c, a, b))
    if min(angles) <= 0:
        return -1.0
    return math.degrees(min(angles))


def _radius_ratio(xy, t):
    """Twice the inscribed over the circumscribed radius of triangle t."""
    a, b, c = (xy[v] for v in t)
    sides = math.dist(a, b), math.dist(b, c), math.dist(c, a)
    area = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2
    if area == 0:
        return 0.0
    r_in = area / (sum(sides) / 2)
    r_circ = sides[0] * sides[1] * sides[2] / (4 * area)
    return 2 * r_in / r_circ


def _gradient_at(xy, t, v):
    """The gradient of triangle t's smallest angle as node v moves."""
    angles = [
        _angle(xy[t[i]], xy[t[(i + 1) % 3]], xy[t[(i + 2) % 3]]) for i in range(3)
    ]
    i = angles.index(min(angles))
    a, b, c = (xy[t[(i + j) % 3]] for j in range(3))
    ab, ac = (b[0] - a[0], b[1] - a[1]), (c[0] - a[0], c[1] - a[1])
    # moving b by d changes the angle at a by (d . (ab_y, -ab_x)) / |ab|^2
    gb = (ab[1] / (ab[0] ** 2 + ab[1] ** 2), -ab[0] / (ab[0] ** 2 + ab[1] ** 2))
    gc = (-ac[1] / (ac[0] ** 2 + ac[1] ** 2), ac[0] / (ac[0] ** 2 + ac[1] ** 2))
    gradient = {t[i]: (-gb[0] - gc[0], -gb[1] - gc[1]), t[(i + 1) % 3]: gb}
    gradient[t[(i + 2) % 3]] = gc
    return gradient[v]


def _first_step(xy, tris, star, v, method):
    """The node's first step, literally as smooth_points documents it."""
    x, y = xy[v]
    length = sum(
        math.dist(xy[tris[k][j]], xy[tris[k][(j + 1) % 3]])
        for k in star[v]
        for j in range(3)
    ) / (3 * len(star[v]))  # the mean edge length of its triangles
    if method == "laplacian":
        neighbours = sorted({w for k in star[v] for w in tris[k] if w != v})
        mx = sum(xy[w][0] for w in neighbours) / len(neighbours)
        my = sum(xy[w][1] for w in neighbours) / len(neighbours)
        step = (mx - x, my - y)
        return step if math.hypot(*step) > 1e-6 * length else (0.0, 0.0)
    # the unit gradients of the triangles within 1 degree of the worst, summed
    angles = {k: _min_angle(xy, tris[k]) for k in star[v]}
    gx = gy = 0.0
    summed = 0
    for k in star[v]:
        if angles[k] > min(angles.values()) + 1.0:
            continue
        g = _gradient_at(xy, tris[k], v)
        gx, gy = gx + g[0] / math.hypot(*g), gy + g[1] / math.hypot(*g)
        summed += 1
    norm = math.hypot(gx, gy)
    if norm <= 1e-9 * summed:  # gradients that cancel: rounding noise
        return (0.0, 0.0)
    step = (gx / norm * 0.1 * length, gy / norm * 0.1 * length)
    return step if math.hypot(*step) > 1e-6 * length else (0.0, 0.0)


def smooth_reference(xy, triangles, fixed, iterations, method, good_angle):
    """Guarded Jacobi smoothing with plain loops over nodes and triangles."""
    xy = [tuple(map(float, p)) for p in xy]
    tris = [tuple(map(int, t)) for t in triangles]
    star = [[] for _ in xy]
    for k, t in enumerate(tris):
        for v in t:
            star[v].append(k)
    free = [v for v in range(len(xy)) if not fixed[v] and star[v]]
    sweeps = 0
    while free and sweeps < iterations:
        sweeps += 1
        old = [_min_angle(xy, t) for t in tris]
        old_ratio = [_radius_ratio(xy, t) for t in tris]
        least_ratio = min(old_ratio)  # the mesh's worst, a floor for every move
        worst = {v: min(old[k] for k in star[v]) for v in free}
        nodes = [v for v in free if worst[v] < good_angle]
        if not nodes:
            break
        # the value just above the 1st percentile of the minimum angles
        ordered = sorted(old)
        upper = min(math.ceil(0.01 * (len(old) - 1)) + 1, len(old) - 1)
        floor = {v: max(worst[v], ordered[upper]) for v in nodes}
        step = {v: _first_step(xy, tris, star, v, method) for v in nodes}
        level = {v: 0 if step[v] != (0.0, 0.0) else len(FRACTIONS) for v in nodes}
        trial = list(xy)

        def place(v, xy=xy, trial=trial, step=step, level=level):
            f = ([*FRACTIONS, 0.0])[level[v]]
            trial[v] = (xy[v][0] + f * step[v][0], xy[v][1] + f * step[v][1])

        for v in nodes:
            place(v)
        while True:  # every move checked with every other move made
            failed = [
                v
                for v in nodes
                if level[v] < len(FRACTIONS)
                and any(
                    _min_angle(trial, tris[k]) <= 0
                    or _min_angle(trial, tris[k]) < min(old[k], floor[v])
                    or _radius_ratio(trial, tris[k]) < min(old_ratio[k], least_ratio)
                    for k in star[v]
                )
            ]
            if not failed:
                break
            for v in failed:
                level[v] += 1
                place(v)
        if all(level[v] == len(FRACTIONS) for v in nodes):
            break
        xy = trial
    return np.array(xy), sweeps


def _unchanged_or_better(before, after, ratios=None):
    """Minimum angle, 1st percentile and worst radius ratio did not fall."""
    assert after.min() > 0
    assert after.min() >= before.min() - 1e-9
    assert np.percentile(after, 1) >= np.percentile(before, 1) - 1e-9
    if ratios is not None:
        assert ratios[1].min() >= ratios[0].min() - 1e-12


@settings(deadline=None, max_examples=60)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(3, 60),
    clusters=st.integers(0, 4),
    method=st.sampled_from(["angle", "laplacian"]),
    good_angle=st.sampled_from([25.0, 35.0, 60.0, 90.0]),
    iterations=st.integers(1, 5),
)
@example(seed=0, n=40, clusters=3, method="angle", good_angle=35.0, iterations=5)
# a node at the centre of a symmetric star: its gradients cancel to rounding
@example(seed=1382, n=32, clusters=1, method="angle", good_angle=25.0, iterations=1)
@example(seed=1, n=40, clusters=3, method="laplacian", good_angle=90.0, iterations=5)
def test_matches_reference(seed, n, clusters, method, good_angle, iterations):
    xy, tri = clustered_delaunay(seed, n, clusters)
    fixed = boundary_nodes(tri, len(xy))
    options = {"iterations": iterations, "method": method, "good_angle": good_angle}
    got, sweeps = smooth_points(xy, tri, fixed, **options)
    expected, expected_sweeps = smooth_reference(xy, tri, fixed, **options)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
    assert sweeps == expected_sweeps
    np.testing.assert_array_equal(got[fixed], xy[fixed])  # exactly
    ratios = (radius_ratios(xy[tri]), radius_ratios(got[tri]))
    _unchanged_or_better(min_angles(xy, tri), min_angles(got, tri), ratios)


@settings(deadline=None, max_examples=40)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(10, 300),
    clusters=st.integers(0, 10),
    extra_fixed=st.floats(0, 0.5),
    method=st.sampled_from(["angle", "laplacian"]),
)
def test_guarantees(seed, n, clusters, extra_fixed, method):
    """Fixed nodes stay; no triangle turns over; min and 1st percentile hold."""
    xy, tri = clustered_delaunay(seed, n, clusters)
    fixed = boundary_nodes(tri, len(xy))
    fixed |= np.random.default_rng(seed).random(len(xy)) < extra_fixed
    before = xy.copy()
    got, sweeps = smooth_points(xy, tri, fixed, method=method)
    np.testing.assert_array_equal(xy, before)  # the input is not changed
    np.testing.assert_array_equal(got[fixed], xy[fixed])
    assert 0 <= sweeps <= 6
    ratios = (radius_ratios(xy[tri]), radius_ratios(got[tri]))
    _unchanged_or_better(min_angles(xy, tri), min_angles(got, tri), ratios)


def test_angle_gradient_matches_finite_differences():
    rng = np.random.default_rng(5)
    p = rng.random((200, 3, 2))
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    p = p[d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0.05]  # counter-clockwise
    corner = rng.integers(0, 3, len(p))
    got = _angle_gradient(p, corner)
    h = 1e-7
    rows = np.arange(len(p))
    for axis in (0, 1):
        up, down = p.copy(), p.copy()
        up[rows, corner, axis] += h
        down[rows, corner, axis] -= h
        smallest = [
            np.radians(
                min_angles(q.reshape(-1, 2), np.arange(3 * len(p)).reshape(-1, 3))
            )
            for q in (up, down)
        ]
        numeric = (smallest[0] - smallest[1]) / (2 * h)
        np.testing.assert_allclose(got[:, axis], numeric, rtol=1e-4, atol=1e-4)


def test_a_node_moves_to_the_centre_of_a_square():
    xy = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [1.6, 1.5]])
    tri = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    fixed = np.array([True, True, True, True, False])
    got, _ = smooth_points(xy, tri, fixed, method="laplacian")
    np.testing.assert_allclose(got[4], [1.0, 1.0], atol=1e-12)
    got, _ = smooth_points(xy, tri, fixed)  # up the worst angles
    assert min_angles(got, tri).min() > min_angles(xy, tri).min() + 5
    # every node fixed, or no triangles: nothing moves, no sweep is made
    assert smooth_points(xy, tri, np.ones(5, bool))[1] == 0
    assert smooth_points(xy, np.zeros((0, 3), int), np.zeros(5, bool))[1] == 0


def test_smooth_mesh_keeps_boundary_and_data_on_the_earth(mesh_with_islands):
    mesh = mesh_with_islands
    for crs in ("EPSG:32630", "EPSG:4326"):
        from coastmesh.geometry.earth import transformer

        points = np.column_stack(transformer(mesh.crs, crs).transform(*mesh.points.T))
        m = Mesh(
            points,
            mesh.triangles,
            mesh.boundary_edges,
            mesh.boundary_ids,
            mesh.surface_id,
            crs,
            mesh.point_data,
        )
        smooth, report = smooth_mesh(m, good_angle=60)  # Gmsh's mesh is good
        boundary = np.unique(m.boundary_edges)
        np.testing.assert_array_equal(smooth.points[boundary], m.points[boundary])
        np.testing.assert_array_equal(smooth.triangles, m.triangles)
        np.testing.assert_array_equal(smooth.point_data["depth"], m.point_data["depth"])
        assert report.nodes_moved == int((smooth.points != m.points).any(axis=1).sum())
        assert report.nodes_moved > 0
        assert report.min_angle_after >= report.min_angle_before
        assert report.min_angle_p1_after >= report.min_angle_p1_before
        # measured on the Earth (the guard works in a conformal plane)
        before, after = mesh_quality(m).min_angle, mesh_quality(smooth).min_angle
        assert after.min >= before.min - 1e-6 and after.p1 >= before.p1 - 1e-6
        assert isinstance(report, SmoothingReport)
        assert report.to_dict()["sweeps"] == report.sweeps
        assert "nodes moved" in report.summary()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"iterations": 0}, "iterations = 0"),
        ({"iterations": 2.5}, "iterations = 2.5"),
        ({"iterations": True}, "iterations = True"),
        ({"method": "odt"}, "method = 'odt'"),
        ({"good_angle": 0}, "good_angle = 0"),
        ({"good_angle": 91}, "good_angle = 91"),
    ],
)
def test_bad_options(options, message):
    xy = np.array([[0, 0], [1, 0], [0, 1.0]])
    with pytest.raises(ConfigError, match=message):
        smooth_points(xy, [[0, 1, 2]], [True, True, True], **options)


def test_bad_shapes():
    xy = np.array([[0, 0], [1, 0], [0, 1.0]])
    with pytest.raises(ValueError, match="xy has shape"):
        smooth_points(xy.ravel(), [[0, 1, 2]], [True] * 3)
    with pytest.raises(ValueError, match="triangles has shape"):
        smooth_points(xy, [0, 1, 2], [True] * 3)
    with pytest.raises(ValueError, match="fixed has shape"):
        smooth_points(xy, [[0, 1, 2]], [True] * 2)


@settings(max_examples=50, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), scale=st.floats(1e-3, 1e6))
def test_sines_and_ratios_are_both_measures_bit_for_bit(seed, scale):
    from coastmesh.meshing.cleanup.planar import (
        radius_ratios,
        sin_min_angles,
        sines_and_ratios,
    )

    rng = np.random.default_rng(seed)
    xy = rng.normal(size=(40, 2)) * scale
    xy[5] = xy[4]  # a degenerate triangle or two
    tri = rng.integers(0, 40, size=(200, 3))
    sine, ratio = sines_and_ratios(xy, tri)
    assert np.array_equal(sine, sin_min_angles(xy, tri))
    assert np.array_equal(ratio, radius_ratios(xy[tri]))
