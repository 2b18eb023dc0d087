"""Smoothing at the cuts once the parts are joined: which nodes move, and how."""

from __future__ import annotations

import numpy as np
from conftest import clustered_delaunay
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.meshing.cleanup.planar import radius_ratios
from coastmesh.meshing.cleanup.smoothing import (
    boundary_nodes,
    min_angles,
    smooth_points,
)
from coastmesh.meshing.parts.seams import smooth_seams


def seams_reference(xy, tri, seam):
    """The region chosen with plain loops, then the same guarded kernel."""
    seam = {int(v) for v in seam}
    near = set(seam)
    for t in tri.tolist():
        if seam & set(t):
            near |= set(t)
    local = [t for t in tri.tolist() if near & set(t)]
    if not local:
        return xy.copy()
    nodes = sorted({v for t in local for v in t})
    index = {v: i for i, v in enumerate(nodes)}
    sub = np.array([[index[v] for v in t] for t in local], dtype=np.int64)
    on_boundary = boundary_nodes(tri, len(xy))  # edges of one triangle
    fixed = np.array([v not in near or on_boundary[v] for v in nodes])
    angles = min_angles(xy[nodes], sub)
    good = max(35.0, float(np.percentile(angles, 5)))
    new = smooth_points(xy[nodes], sub, fixed, good_angle=good)[0]
    out = xy.copy()
    out[nodes] = new
    return out


def _boundary_edges(tri, n):
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), 1)
    keys, count = np.unique(edges[:, 0] * n + edges[:, 1], return_counts=True)
    single = keys[count == 1]
    return np.column_stack([single // n, single % n])


@settings(deadline=None, max_examples=40)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(10, 200),
    clusters=st.integers(0, 6),
    share=st.floats(0.0, 0.5),
)
def test_matches_reference_and_moves_only_the_seam(seed, n, clusters, share):
    xy, tri = clustered_delaunay(seed, n, clusters)
    edges = _boundary_edges(tri, len(xy))
    rng = np.random.default_rng(seed)
    seam = np.flatnonzero(rng.random(len(xy)) < share)
    got, moved = smooth_seams(xy, tri, edges, seam)
    np.testing.assert_allclose(got, seams_reference(xy, tri, seam), rtol=0, atol=0)
    changed = (got != xy).any(axis=1)
    assert moved == changed.sum()
    near = np.zeros(len(xy), bool)
    near[seam] = True
    near[np.unique(tri[near[tri].any(axis=1)])] = True
    assert not changed[~near].any()  # nothing else moves
    assert not changed[edges.ravel()].any()  # nor the boundary
    before, after = min_angles(xy, tri), min_angles(got, tri)
    assert after.min() > 0 and after.min() >= before.min() - 1e-9
    assert radius_ratios(got[tri]).min() >= radius_ratios(xy[tri]).min() - 1e-12


def test_no_seam_moves_nothing():
    xy, tri = clustered_delaunay(3, 30, 2)
    got, moved = smooth_seams(xy, tri, _boundary_edges(tri, len(xy)), np.array([], int))
    assert moved == 0
    np.testing.assert_array_equal(got, xy)
