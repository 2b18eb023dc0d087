"""Parts as tasks: merging by shared nodes, against a literal merge by place."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import MeshingError
from coastmesh.meshing.gmsh.boundary_nodes import boundary_nodes
from coastmesh.meshing.parts.cuts import auto_parts
from coastmesh.meshing.parts.faces import split_faces
from coastmesh.meshing.parts.report import PartsReport
from coastmesh.meshing.parts.tasks import (
    PartMesh,
    merge_parts,
    mesh_part,
    part_tasks,
    ready,
    start_workers,
)
from coastmesh.types import SizeGrid


def _reference_merge(parts):
    """Literal: one node per distinct place, triangles as sets of places."""
    places: dict[tuple[float, float], int] = {}
    triangles = set()
    for p in parts:
        for xy in p.points.tolist():
            places.setdefault(tuple(xy), len(places))
        for t in p.triangles:
            triangles.add(frozenset(tuple(p.points[k]) for k in t))
    return len(places), triangles


def _random_parts(seed: int, count: int):
    """A unit-square strip split into ``count`` columns that share cut nodes."""
    rng = np.random.default_rng(seed)
    parts, shared_xy = [], {}
    xs = np.linspace(0.0, float(count), count + 1)
    cut_y = [np.sort(np.r_[0.0, rng.uniform(0.05, 0.95, 3), 1.0]) for _ in xs]
    for k in range(count):
        left = np.column_stack([np.full(5, xs[k]), cut_y[k]])
        right = np.column_stack([np.full(5, xs[k + 1]), cut_y[k + 1]])
        inner = np.column_stack(
            [rng.uniform(xs[k] + 0.1, xs[k + 1] - 0.1, 4), rng.uniform(0.1, 0.9, 4)]
        )
        pts = np.vstack([left, right, inner])
        shared = np.full(len(pts), -1)
        for i, xy in enumerate(pts[:10]):
            shared[i] = shared_xy.setdefault(tuple(xy), len(shared_xy))
        from scipy.spatial import Delaunay

        tri = Delaunay(pts).simplices.astype(np.int64)
        parts.append(
            PartMesh(
                k,
                pts,
                tri,
                np.empty((0, 2), np.int64),
                np.empty(0, np.int64),
                shared.astype(np.int64),
                0.0,
                "test",
            )
        )
    return parts


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), count=st.integers(1, 5), flip=st.booleans())
def test_merge_matches_the_literal_merge_by_place(seed, count, flip):
    parts = _random_parts(seed, count)
    points, triangles, _, _ = merge_parts(parts[::-1] if flip else parts)
    n, reference = _reference_merge(parts)
    assert len(points) == n  # each shared node once
    merged = {frozenset(tuple(points[k]) for k in t) for t in triangles}
    assert merged == reference


def test_a_shared_node_in_two_places_is_refused():
    parts = _random_parts(1, 2)
    moved = parts[1].points.copy()
    moved[0, 1] += 1e-9  # a node of the shared cut, moved on one side only
    parts[1] = PartMesh(
        *(
            moved if f == "points" else getattr(parts[1], f)
            for f in PartMesh.__dataclass_fields__
        )
    )
    with pytest.raises(MeshingError, match="part 2 put a node of a cut"):
        merge_parts(parts)


def test_each_part_alone_keeps_the_cut_nodes_it_was_given():
    outer = np.array([[0, 0], [4000, 0], [4000, 2000], [0, 2000], [0, 0]], float)
    grid = SizeGrid(
        np.arange(-100.0, 4101, 100),
        np.arange(-100.0, 2101, 100),
        np.full((23, 43), 60.0),
    )
    # one segment, a straight piece per side (corners end Gmsh's splines),
    # its nodes placed once by Gmsh's 1-D mesher: about 60 m apart
    sides = [[[outer[i : i + 2] for i in range(4)]]]
    pieces, water = boundary_nodes(sides, [[5]], grid)
    steps = np.hypot(*np.diff(np.concatenate([p for p, _ in pieces]), axis=0).T)
    assert 40 < steps[steps > 0].min() and steps.max() <= 60 * 1.01
    faces = split_faces(pieces, water, [shapely.LineString([(2010, -5), (2010, 2005)])])
    tasks = part_tasks(faces, grid, seed=0, algorithm="frontal-delaunay", optimize=True)
    assert len(tasks) == 2 and "part 1 of 2" in tasks[0].label
    meshes = [mesh_part(t) for t in tasks]
    cut = next(
        c for c, pid in zip(tasks[0].curves, tasks[0].ids, strict=True) if pid is None
    )
    for m in meshes:
        on_cut = m.points[m.shared >= 0]
        assert {tuple(p) for p in on_cut} == {tuple(p) for p in cut}
        assert set(m.edge_ids.tolist()) == {5}  # the cut is no boundary
    points, triangles, _, _ = merge_parts(meshes)
    assert len(points) == sum(len(m.points) for m in meshes) - len(cut)
    area = shapely.MultiPolygon([shapely.Polygon(points[t]) for t in triangles]).area
    assert area == pytest.approx(water.area, rel=1e-9)


def test_projected_speedup_schedules_the_longest_first():
    report = PartsReport(8, 8, (), (1.0,) * 5, (10,) * 5, (4.0, 3.0, 3.0, 2.0, 2.0), ())
    assert report.projected_speedup(1) == pytest.approx(1.0)
    # longest first onto the least loaded: 4 | 3, 3 | +2 -> 6 | 6 | +2 -> 8;
    # a pool is greedy, so the best split ({4, 3} / {3, 2, 2}: 7) is not it
    assert report.projected_speedup(2) == pytest.approx(14 / 8)
    assert report.projected_speedup(32) == pytest.approx(14 / 4)  # the largest part
    assert PartsReport(1, 1, (), (), (), (), ()).projected_speedup(8) == 1.0
    assert report.to_dict()["projected_speedup"]["32"] == 3.5


class _Warm:
    """A runner that records what it was asked to start."""

    def __init__(self) -> None:
        self.calls: list[tuple[int, object]] = []

    def warm(self, count: int, fn: object) -> None:
        self.calls.append((count, fn))


@pytest.mark.parametrize("h", [500.0, 100.0, 20.0])
def test_workers_are_started_for_the_parts_auto_will_cut(h):
    x = np.arange(0.0, 100_001, 1_000)
    grid = SizeGrid(x, x, np.full((len(x), len(x)), h))
    # the water as the engine has it: rings of segments, the exterior first
    outer = [
        np.array([[0, 0], [9e4, 0], [9e4, 9e4]]),
        np.array([[9e4, 9e4], [0, 9e4], [0, 0]]),
    ]
    island = [np.array([[4e4, 4e4], [4e4, 5e4], [5e4, 5e4], [5e4, 4e4], [4e4, 4e4]])]
    water = shapely.Polygon(np.concatenate(outer), [np.concatenate(island)])
    runner = _Warm()
    start_workers(runner, "auto", [outer, island], grid)
    want = auto_parts(water, grid)
    assert runner.calls == ([(want, ready)] if want > 1 else [])
    assert want > 1 or h == 500.0  # the three cover both
    start_workers(runner, 3, [outer, island], grid)
    start_workers(runner, 1, [outer, island], grid)  # one part: none started
    assert runner.calls[-1] == (3, ready) and len(runner.calls) == (
        2 if want > 1 else 1
    )
    start_workers(object(), 3, [outer, island], grid)  # no warm: left be
