"""The canonical numbering of a mesh: nodes by (x, y), triangles by their nodes."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

from coastmesh.meshing.parts.faces import _row_order, canonical_order


@settings(deadline=None, max_examples=60)
@given(
    seed=st.integers(0, 2**32 - 1),
    m=st.integers(0, 300),
    n=st.integers(3, 40),
)
def test_the_row_order_is_the_lexsort_with_or_without_repeated_keys(seed, m, n):
    rows = np.random.default_rng(seed).integers(0, n, (m, 3))  # keys repeat
    expected = rows[np.lexsort(rows.T[::-1])]
    np.testing.assert_array_equal(rows[_row_order(rows, n)], expected)


@settings(deadline=None, max_examples=40)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(4, 200))
def test_canonical_order_of_a_delaunay_mesh_does_not_depend_on_numbering(seed, n):
    rng = np.random.default_rng(seed)
    xy = rng.random((n, 2))
    tri = Delaunay(xy).simplices.astype(np.int64)
    d1, d2 = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    ccw = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0
    tri[~ccw] = tri[~ccw][:, [0, 2, 1]]
    edges = np.zeros((0, 2), dtype=np.int64)
    ids = np.zeros(0, dtype=np.int64)
    first = canonical_order(xy, tri, edges, ids)
    # the same mesh renumbered, its triangles shuffled and turned
    perm = rng.permutation(n)
    rank = np.argsort(perm)
    turned = np.roll(rank[tri], rng.integers(0, 3), axis=1)[rng.permutation(len(tri))]
    second = canonical_order(xy[perm], turned, edges, ids)
    for a, b in zip(first, second, strict=True):
        np.testing.assert_array_equal(a, b)
    # literal: each triangle starts at its lowest node, rows in ascending order
    t = first[1]
    assert (t[:, 0] == t.min(axis=1)).all()
    assert [tuple(r) for r in t.tolist()] == sorted(tuple(r) for r in t.tolist())


@settings(deadline=None, max_examples=60)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 300), spread=st.integers(1, 6))
def test_nodes_are_in_xy_order_and_triangles_start_at_their_lowest_node(
    seed, n, spread
):
    rng = np.random.default_rng(seed)
    # few distinct x (and y): ties, signed zeros and repeated places
    xy = rng.integers(-spread, spread + 1, (n, 2)).astype(float) * rng.choice(
        [1.0, 0.5]
    )
    xy[rng.random(n) < 0.2] *= -1.0
    tri = rng.integers(0, n, (2 * n, 3))
    edges = rng.integers(0, n, (n, 2))
    ids = rng.integers(0, 9, n)
    points, triangles, out_edges, out_ids = canonical_order(xy, tri, edges, ids)
    # literal: numpy's lexsort by x then y (stable), triangles turned one by one
    order = np.lexsort((xy[:, 1], xy[:, 0]))
    np.testing.assert_array_equal(points, xy[order])
    rank = np.argsort(order)
    turned = []
    for t in rank[tri].tolist():
        k = t.index(min(t))  # the first of equal lowest nodes, as argmin
        turned.append(t[k:] + t[:k])
    assert [tuple(t) for t in triangles.tolist()] == sorted(map(tuple, turned))
    np.testing.assert_array_equal(
        out_edges, rank[edges][np.lexsort(rank[edges].T[::-1])]
    )
    np.testing.assert_array_equal(out_ids, ids[np.lexsort(rank[edges].T[::-1])])
