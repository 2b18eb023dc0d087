"""The boundary nodes: Gmsh's 1-D mesher sized by the grid cells along the curves."""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
import shapely.geometry
from conftest import ORKNEY_BBOX
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer

from coastmesh.case.executor import open_runner
from coastmesh.geometry.projection import sample_size
from coastmesh.meshing.gmsh import boundary_nodes as curves
from coastmesh.meshing.gmsh.boundary_nodes import boundary_nodes
from coastmesh.meshing.gmsh.model import grid_view_data
from coastmesh.meshing.gmsh.resample import resample_rings
from coastmesh.types import SizeGrid


def _literal_whole(size, bounds):
    """Literal: every cell of the grid padded to ``bounds``, in row order."""
    minx, miny, maxx, maxy = bounds
    pad = 0.01 * max(maxx - minx, maxy - miny) + 1.0
    xs, ys = list(size.x), list(size.y)
    v = [list(row) for row in size.values]
    if minx - pad < xs[0]:
        xs.insert(0, minx - pad)
        v = [[row[0], *row] for row in v]
    if maxx + pad > xs[-1]:
        xs.append(maxx + pad)
        v = [[*row, row[-1]] for row in v]
    if miny - pad < ys[0]:
        ys.insert(0, miny - pad)
        v.insert(0, list(v[0]))
    if maxy + pad > ys[-1]:
        ys.append(maxy + pad)
        v.append(list(v[-1]))
    cells = []
    for j in range(len(ys) - 1):
        for i in range(len(xs) - 1):
            corners = [(j, i), (j, i + 1), (j + 1, i + 1), (j + 1, i)]  # ccw
            cells.append(
                [xs[b] for _, b in corners]
                + [ys[a] for a, _ in corners]
                + [0.0] * 4
                + [v[a][b] for a, b in corners]
            )
    return np.array(cells).reshape(-1, 16), xs, ys


def _reference_view(size, bounds, near):
    """Literal: the whole view's cells, kept where a point is in the 3 x 3 around."""
    whole, xs, ys = _literal_whole(size, bounds)
    kept = []
    for cell in whole:
        i, j = xs.index(cell[0]), ys.index(cell[4])  # its lower left corner
        for px, py in near:
            # the cell holding the point; points outside go to the edge cells
            pi = max(min(sum(px >= x for x in xs) - 1, len(xs) - 2), 0)
            pj = max(min(sum(py >= y for y in ys) - 1, len(ys) - 2), 0)
            if abs(pi - i) <= 1 and abs(pj - j) <= 1:
                kept.append(cell)
                break
    return np.array(kept).reshape(-1, 16)


@settings(max_examples=40, deadline=None)
@given(
    nx=st.integers(2, 9),
    ny=st.integers(2, 9),
    count=st.integers(0, 6),
    seed=st.integers(0, 2**32 - 1),
)
def test_the_view_is_the_padded_grid_near_points_or_whole(nx, ny, count, seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(1.0, 10.0, nx))
    y = np.cumsum(rng.uniform(1.0, 10.0, ny))
    size = SizeGrid(x, y, rng.uniform(1.0, 5.0, (ny, nx)))
    # a side of the grid is padded where ``bounds`` come within the pad of it
    a, b, c, d = rng.uniform(-4.0, 4.0, 4)
    bounds = (x[0] + a, y[0] + b, x[-1] - c, y[-1] - d)
    near = np.column_stack(
        [
            rng.uniform(x[0] - 9, x[-1] + 9, count),
            rng.uniform(y[0] - 9, y[-1] + 9, count),
        ]
    )
    got = grid_view_data(size, bounds, near).reshape(-1, 16)
    np.testing.assert_array_equal(got, _reference_view(size, bounds, near))
    whole = grid_view_data(size, bounds).reshape(-1, 16)
    np.testing.assert_array_equal(whole, _literal_whole(size, bounds)[0])


def _full_and_near(monkeypatch, rings, ids, size):
    """The boundary nodes with the view along the curves, then with the whole grid."""
    cells = []
    seen = curves.add_size_view

    def spy(gmsh, grid, bounds, near=None):
        cells.append(len(grid_view_data(grid, bounds, near)) // 16)
        seen(gmsh, grid, bounds, near)

    monkeypatch.setattr(curves, "add_size_view", spy)
    near = boundary_nodes(rings, ids, size)
    monkeypatch.setattr(curves, "_along", lambda *a: None)
    whole = boundary_nodes(rings, ids, size)
    return near, whole, cells


def _assert_same(near, whole):
    assert len(near[0]) == len(whole[0])
    for (a, pid_a), (b, pid_b) in zip(near[0], whole[0], strict=True):
        assert pid_a == pid_b
        np.testing.assert_array_equal(a, b)
    assert near[1].equals_exact(whole[1], 0.0)


@settings(max_examples=15, deadline=None)
@given(sides=st.integers(5, 40), seed=st.integers(0, 2**32 - 1))
def test_boundary_nodes_are_those_of_the_whole_view(sides, seed):
    rng = np.random.default_rng(seed)
    # a star-shaped ring of long spans, in a grid of sizes that change fast
    angle = np.sort(rng.uniform(0, 2 * np.pi, sides))
    radius = rng.uniform(3000, 9000, sides)
    ring = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    ring = np.vstack([ring, ring[:1]])
    half = len(ring) // 2
    x = np.arange(-10000.0, 10001, 400)
    y = np.arange(-10000.0, 10001, 500)
    size = SizeGrid(x, y, rng.uniform(80.0, 900.0, (len(y), len(x))))
    with pytest.MonkeyPatch.context() as mp:
        near, whole, cells = _full_and_near(
            mp, [[[ring[: half + 1], ring[half:]]]], [[7]], size
        )
    _assert_same(near, whole)
    assert cells[0] < cells[1]


def _orkney(orkney_geojson):
    """Orkney's water in UTM, resampled, sized 60 m at the coast to 1 km offshore."""
    to_utm = Transformer.from_crs(4326, 32630, always_xy=True)
    features = json.loads(orkney_geojson.read_text())["features"]
    land = [shapely.geometry.shape(f["geometry"]) for f in features]
    box = shapely.box(*ORKNEY_BBOX).buffer(-0.02)
    water = shapely.difference(box, shapely.union_all(land))
    water = max(getattr(water, "geoms", [water]), key=lambda p: p.area)
    water = shapely.transform(
        water, lambda xy: np.column_stack(to_utm.transform(*xy.T))
    )
    x0, y0, x1, y1 = water.bounds
    x = np.arange(x0 - 1000, x1 + 1000, 300.0)
    y = np.arange(y0 - 1000, y1 + 1000, 300.0)
    gx, gy = np.meshgrid(x, y)
    # 60 m at the coast to 1 km offshore, as a gradation gives
    coast = shapely.MultiLineString([r.coords for r in water.interiors])
    distance = shapely.distance(coast, shapely.points(gx, gy))
    size = SizeGrid(x, y, np.clip(60.0 + 0.2 * distance, 60.0, 1000.0))
    rings = [np.asarray(r.coords) for r in [water.exterior, *water.interiors]]
    resampled, _ = resample_rings(
        [[r] for r in rings], lambda xy: sample_size(size, xy)
    )
    return resampled, [[3]] * len(resampled), size


def test_boundary_nodes_of_orkney_are_those_of_the_whole_view(
    monkeypatch, orkney_geojson
):
    resampled, ids, size = _orkney(orkney_geojson)
    near, whole, cells = _full_and_near(monkeypatch, resampled, ids, size)
    _assert_same(near, whole)
    assert sum(len(p) for p, _ in near[0]) > 500
    assert cells[0] < 0.8 * cells[1]


def _ends(piece):
    return tuple(piece[0]), tuple(piece[-1])


def test_a_long_boundary_is_meshed_in_batches_the_same_on_any_runner(
    monkeypatch, orkney_geojson
):
    resampled, ids, size = _orkney(orkney_geojson)
    alone = boundary_nodes(resampled, ids, size)  # under BATCH_CURVES: one batch
    count = len(alone[0])
    monkeypatch.setattr(curves, "BATCH_CURVES", count - 1)
    monkeypatch.setattr(curves, "BATCHES", 5)
    seen = []

    def runner(fn, items):
        seen.append(list(items))
        return [fn(item) for item in items]

    batched = boundary_nodes(resampled, ids, size, runner)
    (batches,) = seen
    # cut at equal shares of points: a share inside one long piece is no cut
    assert 1 < len(batches) <= 5
    # every piece once, in order, and a ring cut between batches is no whole run
    pieces = [p for b in batches for run, _ in b.runs for p in run]
    assert len(pieces) == count
    assert sum(b.expected for b in batches) == sum(len(p) for p, _ in pieces)
    by_ring = curves._ring_pieces(resampled, ids)
    ring_of = {_ends(p): r for r, ring in enumerate(by_ring) for p, _ in ring}
    for batch in batches:
        for run, whole in batch.runs:
            rings = {ring_of[_ends(p)] for p, _ in run}
            assert len(rings) == 1
            assert whole == (len(run) == len(by_ring[rings.pop()]))
    assert not all(whole for b in batches for _, whole in b.runs)  # a ring was cut
    # the same nodes but for the last bits of the size view's search
    for (a, pid_a), (b, pid_b) in zip(alone[0], batched[0], strict=True):
        assert pid_a == pid_b and a.shape == b.shape
        np.testing.assert_array_equal(a[[0, -1]], b[[0, -1]])
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-6)
    with open_runner(2) as pool:
        on_workers = boundary_nodes(resampled, ids, size, pool)
    _assert_same(on_workers, batched)  # the same bytes on 2 workers


def test_a_spline_that_misses_its_points_gets_the_whole_view():
    piece = np.array([[0.0, 0.0], [50.0, 10.0], [100.0, 0.0]])
    x, y = np.arange(-100.0, 201, 10), np.arange(-20.0, 21, 10)
    size = SizeGrid(x, y, np.ones((len(y), len(x))))  # 155 cells

    class Model:
        def __init__(self, shift):
            self.shift = shift

        def getValue(self, dim, tag, t):  # Gmsh's name
            # the control polygon at parameters k / (n - 1), moved by shift
            xy = np.column_stack(
                [np.interp(t * 2, [0, 1, 2], piece[:, k]) for k in (0, 1)]
            )
            return np.column_stack([xy + self.shift, np.zeros(len(t))]).ravel()

    class Gmsh:
        def __init__(self, shift):
            self.model = Model(shift)

    along = curves._along(Gmsh(0.0), [(piece, 1, 1)], size)
    assert len(along) == 2 * 21 + 1  # two 51 m spans in 2.5 m steps, and the end
    assert np.hypot(*np.diff(along, axis=0).T).max() <= 2.5
    assert curves._along(Gmsh(0.5), [(piece, 1, 1)], size) is None
    # more samples than the grid has cells: the whole grid costs less
    small = SizeGrid(x[:8], y, np.ones((len(y), 8)))  # 35 cells
    assert curves._along(Gmsh(0.0), [(piece, 1, 1)], small) is None


def _fewer_edges_loop(pieces, counts, h):
    """A literal fewer_edges for a constant size h: piece by piece, edge by edge."""
    out, start = [], 0
    for count in counts:
        ring = pieces[start : start + count]
        for k, (nodes, pid) in enumerate(ring):
            before, after = ring[k - 1][1], ring[(k + 1) % count][1]
            lengths = [
                float(np.hypot(*(nodes[i + 1] - nodes[i])))
                for i in range(len(nodes) - 1)
            ]
            s = sum(lengths) / h
            n = max(1, int(np.ceil(s - curves.NEAREST_SLACK)))
            closed = tuple(nodes[0]) == tuple(nodes[-1])
            if before != pid or after != pid or closed or s >= curves.NEAREST_BELOW:
                out.append((nodes, pid))
                continue
            if n >= len(lengths) or len(lengths) < 2:
                out.append((nodes, pid))
                continue
            new = [nodes[0]]
            for j in range(1, n):
                want, walked = s * j / n * h, 0.0
                for i, length in enumerate(lengths):  # walk Gmsh's edges
                    if walked + length >= want:
                        t = (want - walked) / length
                        new.append(nodes[i] + t * (nodes[i + 1] - nodes[i]))
                        break
                    walked += length
            new.append(nodes[-1])
            out.append((np.array(new), pid))
        start += count
    return out


@settings(max_examples=40, deadline=None)
@given(
    edges=st.lists(st.integers(1, 5), min_size=3, max_size=6),
    ids=st.lists(st.sampled_from([1, 1, 1, 2]), min_size=6, max_size=6),
    jitter=st.lists(st.floats(0.0, 0.3), min_size=30, max_size=30),
)
def test_fewer_edges_is_the_literal_walk(edges, ids, jitter):
    h = 10.0
    rng = iter(jitter)
    pieces, corner = [], np.zeros(2)
    angles = np.linspace(0, 2 * np.pi, len(edges), endpoint=False)
    for k, n in enumerate(edges):
        end = (
            np.array(
                [
                    np.cos(angles[(k + 1) % len(edges)]),
                    np.sin(angles[(k + 1) % len(edges)]),
                ]
            )
            * 15.0
            if k < len(edges) - 1
            else pieces[0][0][0]
        )
        if k == 0:
            corner = np.array([15.0, 0.0])
        t = np.sort(
            np.concatenate(
                [[0.0, 1.0], np.cumsum([next(rng) + 0.5] * (n - 1)) / (n + 1)]
            )
        )
        pieces.append((corner + t[:, None] * (end - corner), ids[k]))
        corner = end
    fast = curves.fewer_edges(
        pieces, [len(pieces)], SizeGrid([0.0, 1.0], [0.0, 1.0], np.full((2, 2), h))
    )
    slow = _fewer_edges_loop(pieces, [len(pieces)], h)
    for (a, pid_a), (b, pid_b) in zip(fast, slow, strict=True):
        assert pid_a == pid_b
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)


@settings(max_examples=20, deadline=None)
@given(
    a=st.floats(1.01, 6.0),
    b=st.floats(1.01, 6.0),
    turn=st.floats(0.0, np.pi / 2),
)
def test_sides_between_corners_get_edges_of_0_65_to_1_3_sizes(a, b, turn):
    # a rectangle of one id: every vertex a corner, every side a piece
    h = 100.0
    c, s = np.cos(turn), np.sin(turn)
    box = np.array([[0, 0], [a, 0], [a, b], [0, b], [0, 0]]) * h @ [[c, s], [-s, c]]
    size = SizeGrid([-1000.0, 1000.0], [-1000.0, 1000.0], np.full((2, 2), h))
    rings, _ = resample_rings([[box]], lambda xy: sample_size(size, xy))
    pieces, _ = boundary_nodes(rings, [[4]], size)
    assert len(pieces) == 4
    length = np.concatenate([np.hypot(*np.diff(p, axis=0).T) for p, _ in pieces])
    # a side of just over 1.3 sizes takes two edges: the shortest there are
    assert length.min() >= (1 + curves.NEAREST_SLACK) / 2 * h * (1 - 1e-3)
    assert length.max() <= (1 + curves.NEAREST_SLACK) * h * (1 + 1e-3)


def test_a_side_by_an_open_boundary_keeps_gmsh_s_count():
    # the side of 1.05 sizes: one edge between two coast corners, two where
    # one of its ends is an open boundary's
    h = 100.0
    box = np.array([[0, 0], [105, 0], [105, 400], [0, 400], [0, 0]], float)
    size = SizeGrid([-1000.0, 1000.0], [-1000.0, 1000.0], np.full((2, 2), h))
    rings, _ = resample_rings([[box]], lambda xy: sample_size(size, xy))
    alone, _ = boundary_nodes(rings, [[4]], size)
    assert [len(p) - 1 for p, _ in alone] == [1, 4, 1, 4]
    sides = [box[:2], box[1:]]
    rings, _ = resample_rings([sides], lambda xy: sample_size(size, xy))
    beside, _ = boundary_nodes(rings, [[2, 4]], size)
    assert [len(p) - 1 for p, _ in beside] == [2, 4, 1, 4]
