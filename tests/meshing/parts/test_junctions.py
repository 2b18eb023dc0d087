"""Cuts end on boundary nodes: join_cuts against the properties it promises."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.meshing.gmsh.boundary_nodes import chunked
from coastmesh.meshing.parts.faces import split_faces
from coastmesh.meshing.parts.junctions import join_cuts


def _ring(seed: int, n: int) -> np.ndarray:
    """A star-shaped ring of n nodes around the origin, closed."""
    rng = np.random.default_rng(seed)
    angle = np.sort(rng.uniform(0, 2 * np.pi, n))
    radius = rng.uniform(800, 1200, n)
    xy = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    return np.vstack([xy, xy[:1]])


def _on_polyline(point, lines) -> bool:
    return (
        min(
            shapely.distance(shapely.LineString(c), shapely.Point(point)) for c in lines
        )
        < 1e-6
    )


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(12, 80),
    at=st.floats(-600, 600),
    t=st.floats(-600, 600),
)
def test_cuts_end_on_nodes_and_the_rest_of_the_boundary_stays(seed, n, at, t):
    ring = _ring(seed, n)
    water = shapely.Polygon(ring)
    pieces = chunked([(ring, 7)], most=max(4, n // 3))
    first = shapely.LineString([(at, -2000), (at, 2000)])
    second = shapely.LineString([(-2000, t), (at, t)])  # a T on the first
    new, chords = join_cuts(pieces, water, [first, second])
    old_nodes = np.concatenate([p for p, _ in pieces])
    new_nodes = np.concatenate([p for p, _ in new])
    nodes = {tuple(p) for p in new_nodes}
    for chord in chords:
        for end in chord[[0, -1]]:
            # on a boundary node, or a node of another chord (a T)
            inner = [tuple(p) for c in chords if c is not chord for p in c]
            assert tuple(end) in nodes or tuple(end) in inner
    # the ends of pieces never move; other nodes move only onto the old boundary
    for (p, _), (q, _) in zip(pieces, new, strict=True):
        assert (p[0] == q[0]).all() and (p[-1] == q[-1]).all()
    old = {tuple(o) for o in old_nodes}
    moved = [tuple(p) for p in new_nodes if tuple(p) not in old]
    assert len(moved) <= 2 * len(chords)
    assert all(_on_polyline(p, [ring]) for p in moved)
    # a node moves at most half of its edge: the boundary keeps its shape
    edge = np.hypot(*np.diff(ring, axis=0).T).max()
    for o in (tuple(o) for o in old_nodes if tuple(o) not in nodes):
        assert min(np.hypot(*(np.array(m) - o)) for m in moved) <= 0.5 * edge + 1e-9
    # the linework bounds faces of water that split_faces can read
    joined = [(q, pid) for q, pid in new]
    coords = np.concatenate([joined[0][0][:1], *(q[1:] for q, _ in joined)])
    polygon = shapely.Polygon(coords)
    if polygon.is_valid:
        faces = split_faces(joined, polygon, [shapely.LineString(c) for c in chords])
        assert len(faces.faces) >= 1


def test_a_node_moves_onto_the_cut_and_a_t_becomes_a_node():
    ring = np.array(
        [[0, 0], [2, 0], [4, 0], [4, 2], [2, 2], [0, 2], [0, 0]], dtype=float
    )
    # pieces end at the corners, as resample_rings makes them
    pieces = [(ring[0:3], 1), (ring[2:4], 1), (ring[3:6], 1), (ring[5:7], 1)]
    cuts = [
        shapely.LineString([(2.4, -1), (2.4, 3)]),
        shapely.LineString([(-1, 1.2), (2.4, 1.2)]),
    ]
    new, chords = join_cuts(pieces, shapely.Polygon(ring), cuts)
    assert new[0][0].tolist() == [[0, 0], [2.4, 0], [4, 0]]  # (2, 0) moved
    assert new[2][0].tolist() == [[4, 2], [2.4, 2], [0, 2]]  # (2, 2) moved
    assert new[3][0].tolist() == [[0, 2], [0, 1.2], [0, 0]]  # one edge: added
    assert new[1][0].tolist() == [[4, 0], [4, 2]]  # untouched
    assert chords[0].tolist() == [[2.4, 0.0], [2.4, 1.2], [2.4, 2.0]]  # the T
    assert chords[1].tolist() == [[0.0, 1.2], [2.4, 1.2]]
