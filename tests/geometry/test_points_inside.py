"""Which of many points a polygon holds, on threads, against one by one."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.geometry import cells
from coastmesh.geometry.cells import points_inside


def _wiggly(n: int, seed: int, holes: bool = True) -> shapely.Polygon:
    """A star-shaped polygon of ``n`` vertices round the origin, with holes."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    r = 1.0 + 0.3 * np.sin(17 * t) + 0.1 * rng.random(n)
    shell = np.column_stack([r * np.cos(t), r * np.sin(t)])
    inner = [shapely.Point(x, 0.0).buffer(0.1).exterior.coords for x in (-0.3, 0.3)]
    return shapely.Polygon(shell, inner if holes else [])


@settings(max_examples=30, deadline=None)
@given(
    n=st.integers(3, 400),
    seed=st.integers(0, 2**16),
    points=st.integers(0, 300),
    threads=st.integers(1, 4),
)
def test_points_inside_is_contains_point_by_point(n, seed, points, threads):
    polygon = _wiggly(n, seed)
    rng = np.random.default_rng(seed + 1)
    x, y = rng.uniform(-1.5, 1.5, (2, points))
    literal = [polygon.contains(shapely.Point(a, b)) for a, b in zip(x, y, strict=True)]
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(cells, "_POINTS_PER_THREAD", 10)  # threads on few points
        assert points_inside(polygon, x, y, threads).tolist() == literal


def test_a_grid_keeps_its_shape_and_threads_agree_on_a_fresh_polygon():
    # many points on threads, on one polygon: GEOS's prepared polygon is not
    # safe to share between threads, even once asked (shared, this aborted
    # the process in one run of five; the world's size grid did too)
    x, y = np.meshgrid(np.linspace(-1.4, 1.4, 500), np.linspace(-1.4, 1.4, 400))
    one = shapely.contains_xy(_wiggly(20_000, 7), x, y)
    for _ in range(3):
        found = points_inside(_wiggly(20_000, 7), x, y, threads=4)
        assert found.shape == x.shape
        assert (found == one).all()
