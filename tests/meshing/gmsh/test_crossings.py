"""Resampled boundaries that cross themselves: found, and resampled finer there."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import MeshingError
from coastmesh.meshing.gmsh.crossings import (
    FinerCoastWarning,
    boundary_crossings,
    resample_valid,
)
from coastmesh.meshing.gmsh.resample import check_boundary, resample_rings


def _crossings_reference(rings) -> list[tuple[float, float, int]]:
    """Every edge that meets a later one but for its neighbours: pair by pair."""
    closed = [
        np.concatenate([p[:-1] for seg in ring for p in seg] + [ring[0][0][:1]])
        for ring in rings
    ]
    edges = []  # (ring, index in ring, edges in ring, a, b)
    for r, c in enumerate(closed):
        for k in range(len(c) - 1):
            edges.append((r, k, len(c) - 1, c[k], c[k + 1]))
    found = []
    for i, (ri, ki, ni, ai, bi) in enumerate(edges):
        for rj, kj, _, aj, bj in edges[i + 1 :]:
            if ri == rj and (kj == ki + 1 or (ki == 0 and kj == ni - 1)):
                continue
            if shapely.LineString([ai, bi]).intersects(shapely.LineString([aj, bj])):
                found.append((*(0.5 * (ai + bi)), ri))
                break
    return found


def _star(rng, centre, radius, n):
    angle = np.sort(rng.uniform(0, 2 * np.pi, n))
    r = radius * rng.uniform(0.3, 1.0, n)
    xy = np.column_stack([centre[0] + r * np.cos(angle), centre[1] + r * np.sin(angle)])
    return np.vstack([xy, xy[:1]])


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 4))
def test_crossings_are_the_edges_that_meet_another(seed, islands):
    # star-shaped rings (simple each) that may cross one another
    rng = np.random.default_rng(seed)
    rings = [[[_star(rng, (0.0, 0.0), 100.0, 12)]]]
    for _ in range(islands):
        rings.append([[_star(rng, rng.uniform(-60, 60, 2), 30.0, 7)]])
    got = boundary_crossings(rings)
    expected = np.reshape(_crossings_reference(rings), (-1, 3))
    np.testing.assert_array_equal(got, expected)
    holes = [shapely.Polygon(r[0][0]) for r in rings[1:]]
    simple = all(shapely.LinearRing(r[0][0]).is_simple for r in rings)
    meet = shapely.intersects(shapely.LinearRing(rings[0][0][0]), holes).any() or any(
        a.boundary.intersects(b.boundary)
        for k, a in enumerate(holes)
        for b in holes[:k]
    )
    assert (len(got) > 0) == (bool(meet) or not simple)


def _spit_and_notch():
    """A coastal spit reaching into an island's notch (the module's example)."""
    shore = [[0, 0], [2480, 0], [2480, 1500], [2520, 1500], [2520, 0]]
    shore += [[40e3, 0], [40e3, 40e3], [0, 40e3], [0, 0]]
    island = [[1500, 1000], [2450, 1000], [2450, 1800], [2550, 1800], [2550, 1000]]
    island += [[3500, 1000], [3500, 3000], [1500, 3000], [1500, 1000]]
    return [[np.array(shore, float)], [np.array(island, float)]]


@pytest.mark.parametrize("size", [1500.0, 2000.0, 2500.0])
def test_a_boundary_that_would_cross_is_resampled_finer_only_there(size):
    rings = _spit_and_notch()

    def at(xy):
        return np.full(len(xy), size)

    coarse, _ = resample_rings(rings, at)
    with pytest.raises(MeshingError, match="not a valid polygon"):
        check_boundary(coarse)
    with pytest.warns(FinerCoastWarning, match=r"crossed itself at \d+ places"):
        fine, dropped = resample_valid(rings, at, lambda x, y: f"<{x:.0f}, {y:.0f}>")
    assert dropped == [] and check_boundary(fine) is None
    assert len(boundary_crossings(fine)) == 0
    # the far side of the shore (x = 40 km) is resampled as before
    far = np.concatenate([p for seg in coarse[0] for p in seg])
    far_fine = np.concatenate([p for seg in fine[0] for p in seg])
    side = far[far[:, 0] == 40e3]
    assert len(side) > 20
    np.testing.assert_allclose(far_fine[far_fine[:, 0] == 40e3], side, atol=1e-6)
    # and more points near the spit than before
    near = np.hypot(*(far_fine - [2500, 1000]).T) < 1000
    assert near.sum() > (np.hypot(*(far - [2500, 1000]).T) < 1000).sum()


def test_a_valid_boundary_is_resampled_as_it_was_without_a_warning():
    square = np.array([[0, 0], [10e3, 0], [10e3, 10e3], [0, 10e3], [0, 0]], float)
    island = np.array([[4e3, 4e3], [6e3, 4e3], [6e3, 6e3], [4e3, 6e3], [4e3, 4e3]])
    rings = [[square], [island]]

    def at(xy):
        return np.full(len(xy), 500.0)

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got, _ = resample_valid(rings, at)
    expected, _ = resample_rings(rings, at)
    assert all(
        np.array_equal(p, q)
        for a, b in zip(got, expected, strict=True)
        for s, t in zip(a, b, strict=True)
        for p, q in zip(s, t, strict=True)
    )


def test_a_ring_outside_the_exterior_is_still_an_error_with_the_place():
    square = np.array([[0, 0], [1e3, 0], [1e3, 1e3], [0, 1e3], [0, 0]], float)
    outside = np.array([[5e3, 5e3], [6e3, 5e3], [6e3, 6e3], [5e3, 5e3]], float)

    def at(xy):
        return np.full(len(xy), 100.0)

    with pytest.raises(MeshingError, match="not a valid polygon"):
        resample_valid([[square], [outside]], at)


def test_a_hole_inside_another_is_still_an_error():
    square = np.array([[0, 0], [1e4, 0], [1e4, 1e4], [0, 1e4], [0, 0]], float)
    big = np.array([[2e3, 2e3], [8e3, 2e3], [8e3, 8e3], [2e3, 8e3], [2e3, 2e3]])
    small = np.array([[4e3, 4e3], [5e3, 4e3], [5e3, 5e3], [4e3, 5e3], [4e3, 4e3]])

    def at(xy):
        return np.full(len(xy), 400.0)

    assert (
        len(boundary_crossings(resample_rings([[square], [big], [small]], at)[0])) == 0
    )
    with pytest.raises(MeshingError, match="not a valid polygon"):
        resample_valid([[square], [big], [small]], at)


def test_boundary_nodes_that_cross_are_named_in_lonlat():
    from pyproj import CRS

    from coastmesh.meshing.engine import _check_nodes

    utm = CRS("EPSG:32630")
    bow = shapely.Polygon(
        [(5e5, 6.5e6), (5.1e5, 6.51e6), (5.1e5, 6.5e6), (5e5, 6.51e6)]
    )
    where = r"cross at 1 places, the first at \(-2\.91\d+, 58\.68\d+\)"
    with pytest.raises(MeshingError, match=where):
        _check_nodes(bow, utm)
    assert _check_nodes(shapely.box(5e5, 6.5e6, 5.1e5, 6.51e6), utm) is None
