"""cut_hole against a literal reference (tests/reference.py), and its errors.

The reference takes out, one shapely test per triangle, the triangles that
meet the polygon, then widens the hole by the words of ``cut.py``'s docstring
until nothing changes; the fast code must give the same removed triangles,
the same nodes going with them, the same ring edges and the same seam flags,
or refuse the same polygons.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import shapely
from hypothesis import event, example, given, settings
from hypothesis import strategies as st
from reference import cut_hole_reference
from scipy.spatial import Delaunay

from coastmesh.case.patch.cut import MIN_CORNER, check_elements, cut_hole, grow_hole
from coastmesh.errors import InputDataError

#: what the fast code says for each of the reference's refusals
REFUSALS = {
    "no element": "meets no element",
    "in two": "would cut the mesh in two",
    "holes": "separate holes",
    "touches itself": "the hole would touch itself at node",
}


def _mesh(seed: int, n: int, clusters: int, island: tuple[float, float, float]):
    """Delaunay triangles of a 1 km square, counter-clockwise, maybe with an island.

    ``n`` random points inside, nodes along the sides about as far apart, and
    ``clusters`` tight clusters of three (slivers round them). The island
    (x, y, radius in metres) takes out the triangles whose centroid is within
    it; a radius of 0 keeps them all.
    """
    rng = np.random.default_rng(seed)
    k = max(int(np.sqrt(n)), 2)
    side = np.linspace(0, 1, k + 1)[:-1]
    edge = np.concatenate(
        [np.column_stack(c) for c in (
            (side, 0 * side), (1 + 0 * side, side), (1 - side, 1 + 0 * side),
            (0 * side, 1 - side),
        )]
    )  # fmt: skip
    points = [edge, 0.02 + 0.96 * rng.random((n, 2))]
    for centre in 0.1 + 0.8 * rng.random((clusters, 2)):
        points.append(centre + rng.normal(0, 0.01, (3, 2)))
    xy = np.vstack(points) * 1000
    tri = Delaunay(xy).simplices.astype(np.int64)
    d1, d2 = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    area = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    tri[area < 0] = tri[area < 0][:, [0, 2, 1]]
    tri = tri[np.abs(area) > 1e-6]
    x, y, r = island
    centroid = xy[tri].mean(axis=1)
    return xy, tri[np.hypot(centroid[:, 0] - x, centroid[:, 1] - y) >= r]


def _star(x: float, y: float, radii: list[float], turn: float) -> shapely.Polygon:
    """A star-shaped polygon round (x, y): one radius per vertex, evenly turned."""
    k = len(radii)
    a = turn + 2 * math.pi * np.arange(k) / k
    return shapely.Polygon(
        np.column_stack([x + radii * np.cos(a), y + radii * np.sin(a)])
    )


def _strip(x: float, y: float, width: float, turn: float) -> shapely.Polygon:
    """A strip ``width`` wide and 4 km long through (x, y): across the square."""
    line = shapely.LineString(
        [(x - 2000 * math.cos(turn), y - 2000 * math.sin(turn)),
         (x + 2000 * math.cos(turn), y + 2000 * math.sin(turn))]
    )  # fmt: skip
    return line.buffer(width / 2, cap_style="flat")


def _signed_area(xy: np.ndarray) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1]))


def _compare(points, triangles, polygon, grow=None) -> list[str]:
    """cut_hole (or grow_hole) and the reference agree: the same hole, or the
    same refusal. ``grow``: (a hole, nodes) to grow it at.

    Returns what kind of case it was, for hypothesis' statistics.
    """
    if grow is None:
        want = cut_hole_reference(points, triangles, polygon)

        def fast():
            return cut_hole(points, triangles, polygon, "drawn")
    else:
        start, nodes = grow
        hit = int(start.removed.sum()) - start.widened
        want = cut_hole_reference(
            points, triangles, None, grow=(start.removed, hit, nodes)
        )

        def fast():
            return grow_hole(points, triangles, start, nodes, "drawn")

    if want["error"] is not None:
        with pytest.raises(InputDataError, match=REFUSALS[want["error"]]):
            fast()
        return [f"refused: {want['error']}"]
    hole = fast()
    np.testing.assert_array_equal(hole.removed, want["removed"])
    np.testing.assert_array_equal(np.sort(hole.inner_nodes), want["inner"])
    assert hole.widened == want["widened"]
    got = {}
    for ring, seam in zip(hole.rings, hole.seam, strict=True):
        assert ring[0] == ring[-1]  # closed
        assert len(set(ring[:-1].tolist())) == len(ring) - 1  # simple
        assert len(seam) == len(ring) - 1
        for a, b, s in zip(ring[:-1], ring[1:], seam, strict=True):
            assert (int(a), int(b)) not in got
            got[(int(a), int(b))] = bool(s)
    assert got == want["edges"]
    return [
        f"widened: {hole.widened > 0}",
        f"rings: {len(hole.rings)}",
        f"the mesh's boundary in the hole: {not all(s.all() for s in hole.seam)}",
    ]
    # the outer ring first, counter-clockwise; the islands in it clockwise
    assert _signed_area(points[hole.rings[0]]) > 0
    for ring in hole.rings[1:]:
        assert _signed_area(points[ring]) < 0


@settings(max_examples=100, deadline=None)
@given(
    seed=st.integers(0, 2**16),
    n=st.integers(8, 120),
    clusters=st.integers(0, 3),
    island=st.tuples(
        st.floats(300, 700), st.floats(300, 700), st.sampled_from([0.0, 50.0, 100.0])
    ),
    centre=st.tuples(st.floats(150, 850), st.floats(150, 850)),
    radii=st.lists(st.floats(10, 150), min_size=3, max_size=8),
    turn=st.floats(0, 2 * math.pi),
    other=st.one_of(
        st.none(),
        st.tuples(st.just("strip"), st.floats(5, 80)),
        st.tuples(st.just("and"), st.floats(-500, 500), st.floats(-500, 500)),
    ),
)
# two holes, one each side of an island (refused)
@example(
    seed=1, n=60, clusters=1, island=(500.0, 500.0, 100.0), centre=(300.0, 500.0),
    radii=[60.0] * 3, turn=0.0, other=("and", 400.0, 0.0),
)  # fmt: skip
# a hole round the island: two rings, the island's clockwise
@example(
    seed=1, n=60, clusters=1, island=(500.0, 500.0, 100.0), centre=(500.0, 500.0),
    radii=[230.0] * 6, turn=0.0, other=None,
)  # fmt: skip
def test_cut_hole_is_the_reference(
    seed, n, clusters, island, centre, radii, turn, other
):
    """Drawn meshes (some with an island, some with slivers) and polygons: a
    star, a strip across, or two stars (apart or overlapping)."""
    points, triangles = _mesh(seed, n, clusters, island)
    polygon = _star(*centre, radii, turn)
    if other is not None and other[0] == "strip":
        polygon = _strip(*centre, other[1], turn)
    elif other is not None:
        shifted = (centre[0] + other[1], centre[1] + other[2])
        polygon = shapely.union(polygon, _star(*shifted, radii[::-1], -turn))
    for kind in _compare(points, triangles, polygon):
        event(kind)


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**16),
    n=st.integers(8, 120),
    island=st.tuples(
        st.floats(300, 700), st.floats(300, 700), st.sampled_from([0.0, 100.0])
    ),
    centre=st.tuples(st.floats(150, 850), st.floats(150, 850)),
    radii=st.lists(st.floats(10, 150), min_size=3, max_size=8),
    pick=st.lists(st.integers(0, 10**6), min_size=1, max_size=4),
)
def test_grow_hole_is_the_reference(seed, n, island, centre, radii, pick):
    """A hole grown at some of its ring's nodes (where a patch met its seam
    badly): the hole and the kept triangles at those nodes, widened again."""
    points, triangles = _mesh(seed, n, 1, island)
    try:
        hole = cut_hole(points, triangles, _star(*centre, radii, 0.3), "drawn")
    except InputDataError:
        return event("the first hole refused")
    ring = np.unique(np.concatenate(hole.rings))
    nodes = np.unique(ring[np.array(pick) % len(ring)])
    for kind in _compare(points, triangles, None, grow=(hole, nodes)):
        event(kind)


def test_a_grown_hole_takes_the_kept_triangles_at_the_nodes():
    points, triangles = _rectangle()
    hole = cut_hole(points, triangles, shapely.box(700, 300, 1100, 650), "grid")
    node = int(hole.rings[0][0])
    grown = grow_hole(points, triangles, hole, np.array([node]), "grid")
    at_node = (triangles == node).any(axis=1)
    assert at_node[~hole.removed].any()
    assert grown.removed[at_node].all() and grown.removed[hole.removed].all()
    assert node in grown.inner_nodes  # the seam moved out past it
    assert grown.widened == hole.widened + int((grown.removed & ~hole.removed).sum())


def _rectangle(nx: int = 21, ny: int = 11, seed: int = 0):
    """Delaunay triangles of a jittered grid on a 2 km x 1 km rectangle, CCW."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 2000, nx), np.linspace(0, 1000, ny))
    xy = np.column_stack([x.ravel(), y.ravel()])
    inside = (xy[:, 0] > 0) & (xy[:, 0] < 2000) & (xy[:, 1] > 0) & (xy[:, 1] < 1000)
    xy[inside] += rng.uniform(-20, 20, (inside.sum(), 2))
    tri = Delaunay(xy).simplices.astype(np.int64)
    d1, d2 = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    clockwise = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] < 0
    tri[clockwise] = tri[clockwise][:, [0, 2, 1]]
    return xy, tri


def test_a_hole_inside_and_one_at_the_edge_are_the_reference():
    points, triangles = _rectangle()
    for polygon in (
        shapely.box(700, 300, 1100, 650),  # inside: one seam ring
        shapely.box(-50, 300, 300, 700),  # across the west side
        shapely.Point(1000, 500).buffer(30),  # in one or two triangles
        shapely.Polygon([(900, 450), (1500, 500), (900, 520)]),  # a sharp wedge
    ):
        _compare(points, triangles, polygon)


def test_a_hole_inside_is_one_seam_ring_and_its_inner_nodes_go():
    points, triangles = _rectangle()
    hole = cut_hole(points, triangles, shapely.box(700, 300, 1100, 650), "grid")
    assert len(hole.rings) == 1
    assert hole.seam[0].all()  # no edge of the mesh's own boundary
    inside = shapely.contains_xy(shapely.box(700, 300, 1100, 650), *points.T)
    assert set(np.flatnonzero(inside)) <= set(hole.inner_nodes.tolist())
    assert not set(hole.inner_nodes.tolist()) & set(hole.rings[0].tolist())


def test_a_hole_at_the_edge_has_the_mesh_boundary_in_its_ring():
    points, triangles = _rectangle()
    hole = cut_hole(points, triangles, shapely.box(-50, 300, 300, 700), "grid")
    (ring,), (seam,) = hole.rings, hole.seam
    xy = points[ring]
    west = (xy[:-1, 0] == 0) & (xy[1:, 0] == 0)  # edges on x = 0
    assert west.sum() >= 4
    np.testing.assert_array_equal(seam, ~west)


def test_a_sharp_corner_is_opened():
    """A wedge's tip makes a corner under MIN_CORNER: the triangles round it go."""
    points, triangles = _rectangle()
    wedge = shapely.Polygon([(900, 490), (1500, 500), (900, 510)])
    hole = cut_hole(points, triangles, wedge, "grid")
    assert hole.widened > 0
    meets = shapely.intersects(shapely.polygons(points[triangles]), wedge)
    assert hole.removed.sum() == meets.sum() + hole.widened
    assert (hole.removed >= meets).all()
    # no kept node is left with a hole angle under MIN_CORNER
    p = points[triangles]
    for node in np.unique(np.concatenate(hole.rings)):
        at = np.flatnonzero((triangles == node).any(axis=1) & hole.removed)
        inside = 0.0
        for k in at:
            i = int(np.flatnonzero(triangles[k] == node)[0])
            u = p[k, (i + 1) % 3] - p[k, i]
            v = p[k, (i + 2) % 3] - p[k, i]
            inside += math.degrees(
                math.acos(np.dot(u, v) / np.linalg.norm(u) / np.linalg.norm(v))
            )
        kept = ((triangles == node).any(axis=1) & ~hole.removed).any()
        assert not kept or inside >= MIN_CORNER


def test_a_polygon_off_the_mesh_is_refused():
    points, triangles = _rectangle()
    with pytest.raises(
        InputDataError, match="grid: the patch polygon meets no element"
    ):
        cut_hole(points, triangles, shapely.box(3000, 0, 3500, 500), "grid")


def test_a_strip_across_is_refused():
    points, triangles = _rectangle()
    with pytest.raises(
        InputDataError, match=r"cut the mesh in two \(2 pieces left of 1\)"
    ):
        cut_hole(points, triangles, shapely.box(950, -100, 1050, 1100), "grid")


def test_two_separate_holes_are_refused():
    points, triangles = _rectangle()
    two = shapely.MultiPolygon(
        [shapely.box(300, 300, 500, 600), shapely.box(1400, 300, 1600, 600)]
    )
    with pytest.raises(InputDataError, match="cuts 2 separate holes"):
        cut_hole(points, triangles, two, "grid")


def test_check_elements_passes_a_good_mesh_either_way_round():
    points, triangles = _rectangle()
    check_elements(points, triangles, "grid")
    check_elements(points, triangles[:, [0, 2, 1]], "grid")  # all clockwise


def test_an_inverted_element_is_named():
    points, triangles = _rectangle()
    bad = triangles.copy()
    bad[7] = bad[7, [0, 2, 1]]
    nodes = re.escape(str((bad[7] + 1).tolist()))
    with pytest.raises(
        InputDataError,
        match=rf"grid: element 8 \(nodes {nodes}\) is inverted.*; 1 such",
    ):
        check_elements(points, bad, "grid")


def test_an_element_without_area_is_named():
    points, triangles = _rectangle()
    # nodes 0, 1, 2 lie on y = 0: a flat element, the 41st
    bad = np.insert(triangles, 40, [0, 1, 2], axis=0)
    with pytest.raises(
        InputDataError, match=r"grid: element 41 \(nodes \[1, 2, 3\]\) has no area"
    ):
        check_elements(points, bad, "grid")
    # a node twice
    bad = np.insert(triangles, 5, [9, 9, 30], axis=0)
    with pytest.raises(InputDataError, match=r"element 6 \(nodes \[10, 10, 31\]\)"):
        check_elements(points, bad, "grid")


def test_duplicate_elements_are_named():
    points, triangles = _rectangle()
    m = len(triangles)
    # the 4th element again at the end, turned round its corners (same nodes,
    # same way round)
    bad = np.vstack([triangles, triangles[3, [1, 2, 0]]])
    with pytest.raises(
        InputDataError, match=rf"grid: elements 4 and {m + 1} have the same nodes"
    ):
        check_elements(points, bad, "grid")


def test_a_hole_through_a_pinch_of_the_mesh_boundary_is_refused():
    """Two islands meeting at a node: the hole cannot be opened there.

    (Before it was refused, the rings were chained through the node and a
    KeyError came out.)
    """
    points, triangles = _rectangle()
    v = int(np.argmin(np.hypot(*(points - [1000, 500]).T)))  # an inner node
    fan = np.flatnonzero((triangles == v).any(axis=1))
    assert len(fan) >= 5
    # keep two triangles of the fan that share no edge: the rest is water no more
    a = fan[0]
    b = next(k for k in fan[2:] if len(set(triangles[a]) & set(triangles[k])) == 1)
    drop = np.setdiff1d(fan, [a, b])
    mesh = np.delete(triangles, drop, axis=0)
    around = shapely.Point(points[v]).buffer(250)
    assert cut_hole_reference(points, mesh, around)["error"] == "touches itself"
    with pytest.raises(
        InputDataError,
        match=rf"grid: the hole would touch itself at node {v + 1}, where the mesh's "
        "own boundary meets itself",
    ):
        cut_hole(points, mesh, around, "grid")
    # away from the node, a hole is cut as ever
    _compare(points, mesh, shapely.Point(points[v] + [-450, 0]).buffer(100))
