"""Where the parts figure labels a part: the widest place of its water."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.meshing.parts.tasks import label_point


def _widest_by_grid(polygon: shapely.Polygon, n: int = 120) -> float:
    """The literal search: the largest distance to the edges over a fine grid."""
    x0, y0, x1, y1 = polygon.bounds
    xs, ys = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    inside = shapely.contains_xy(polygon, xs.ravel(), ys.ravel())
    points = shapely.points(xs.ravel()[inside], ys.ravel()[inside])
    return float(shapely.distance(polygon.boundary, points).max())


@st.composite
def waters(draw):
    """A star-shaped polygon with up to two islands cut out of it."""
    k = draw(st.integers(5, 14))
    radii = draw(st.lists(st.floats(20, 100), min_size=k, max_size=k))
    # whole degrees: angles a few ulps apart made slivers of no area (the
    # label of a polygon with no interior is another test's)
    degrees = draw(st.lists(st.integers(0, 359), min_size=k, max_size=k, unique=True))
    angles = np.radians(np.sort(np.array(degrees, dtype=float)))
    shell = shapely.Polygon(np.column_stack([np.cos(angles), np.sin(angles)]) *
                            np.array(radii)[:, None])  # fmt: skip
    holes = [
        shapely.Point(draw(st.floats(-30, 30)), draw(st.floats(-30, 30))).buffer(
            draw(st.floats(2, 8))
        )
        for _ in range(draw(st.integers(0, 2)))
    ]
    shell = shapely.make_valid(shell)  # near-equal angles can cross
    water = shapely.difference(shell, shapely.union_all(holes)) if holes else shell
    parts = shapely.get_parts(water)
    parts = parts[shapely.get_type_id(parts) == 3]
    return max(parts, key=lambda p: p.area) if len(parts) else shapely.box(0, 0, 1, 1)


@settings(max_examples=40, deadline=None)
@given(waters())
def test_the_label_is_inside_at_the_widest_place(water):
    x, y = label_point(water)
    assert water.contains(shapely.Point(x, y))
    widest = _widest_by_grid(water)
    cell = max(water.bounds[2] - water.bounds[0], water.bounds[3] - water.bounds[1])
    # GEOS's tolerance (1 % of the square root of the area) and the grid's
    # spacing both bound how far from the true widest place each search ends
    slack = 0.01 * np.sqrt(water.area) + cell / 119
    assert water.boundary.distance(shapely.Point(x, y)) >= widest - slack


def test_a_point_on_the_surface_when_there_is_no_area():
    line_like = shapely.Polygon([(0, 0), (1, 0), (2, 0)])  # no area
    assert label_point(line_like) == tuple(line_like.point_on_surface().coords[0])
