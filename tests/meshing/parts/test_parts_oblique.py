"""Oblique cuts: where no cut across x or y is clean, cuts at other angles.

The fast pieces are checked against literal ones: the crossings of a line
found in the turned water against GEOS's intersection with the water as it
is, the R-tree ``dwithin`` check against a distance per point, and the halves
of a region against the region.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from test_parts import (
    ISLAND,
    OUTER,
    _domain,
    _faces,
    assert_one_conforming_mesh,
    jagged_water,
)

from coastmesh.meshing import generate_mesh
from coastmesh.meshing.parts import crossings
from coastmesh.meshing.parts import cuts as parts_module
from coastmesh.meshing.parts.cuts import cut_lines, expected_triangles
from coastmesh.types import SizeGrid

ANGLES = st.sampled_from(parts_module._OBLIQUE)


def _grid(h=10.0, slope=0.005, step=50.0):
    x = np.arange(-400.0, 12401.0, step)
    y = np.arange(-400.0, 8401.0, step)
    X, Y = np.meshgrid(x, y)
    return SizeGrid(x, y, h + slope * np.hypot(X - 2000, Y - 4000))


def _direction(degrees):
    return (np.cos(np.radians(degrees)), np.sin(np.radians(degrees)))


@settings(deadline=None, max_examples=40)
@given(
    frac=st.floats(0.02, 0.98),
    angle=ANGLES,
    seed=st.integers(0, 2**16),
    utm=st.booleans(),
)
def test_crossings_in_the_turned_water_are_the_water_crossings(frac, angle, seed, utm):
    water = jagged_water(seed)
    if utm:  # far from the origin for its size, as a UTM domain is
        water = shapely.transform(water, lambda xy: xy + [500_000.0, 6_200_000.0])
    direction = _direction(angle)
    region = shapely.box(*water.bounds)
    along = shapely.get_coordinates(region) @ np.array(direction)
    at = along.min() + frac * np.ptp(along)
    line = parts_module._line(region, direction, at)
    assert line.geom_type == "LineString" and not line.is_empty
    fast = crossings.Turned(water, direction).chords(line)
    literal = [
        g
        for g in shapely.get_parts(shapely.intersection(water, line))
        if g.geom_type == "LineString" and not g.is_empty
    ]
    assert len(fast) == len(literal)
    if literal:  # a line near a corner of the box may miss the water
        both = shapely.MultiLineString(fast), shapely.MultiLineString(literal)
        assert both[0].length == pytest.approx(both[1].length, abs=1e-6)
        assert shapely.hausdorff_distance(*both) < 1e-6


@settings(deadline=None, max_examples=40)
@given(
    frac=st.floats(0.05, 0.95),
    angle=st.sampled_from((0.0, 90.0, *parts_module._OBLIQUE)),
    cut=st.floats(0.2, 0.8),
    utm=st.booleans(),
)
def test_the_halves_of_a_region_are_the_region(frac, angle, cut, utm):
    # a box, or a box already cut obliquely (a convex polygon); near the
    # origin, or at UTM-like coordinates (far from the origin for its size)
    x, y = (500_000.0, 6_200_000.0) if utm else (0.0, 0.0)
    box = shapely.box(x, y, x + 12000, y + 8000)
    along = np.array([x, y]) @ np.array(_direction(135.0))
    first = parts_module._half(
        box, _direction(135.0), along + 12000 * cut / np.sqrt(2), True
    )
    for region in (box, first):
        direction = _direction(angle)
        if angle in (0.0, 90.0):  # the axes, exactly
            direction = (1.0, 0.0) if angle == 0.0 else (0.0, 1.0)
        along = shapely.get_coordinates(region) @ np.array(direction)
        at = along.min() + frac * np.ptp(along)
        low = parts_module._half(region, direction, at, True)
        high = parts_module._half(region, direction, at, False)
        assert low.area + high.area == pytest.approx(region.area, rel=1e-12)
        assert shapely.intersection(low, high).area < 1e-6 * region.area
        line = parts_module._line(region, direction, at)
        assert line.length > 0
        # the line is the halves' common side
        assert (
            shapely.hausdorff_distance(
                line, shapely.intersection(low.boundary, high.boundary)
            )
            < 1e-6
        )


def _literal_tight(polygon, earlier, xy, h, t, length):
    """The rule of ``_tight``, one point at a time with GEOS distances."""
    boundary = polygon.boundary
    for k in range(1, len(xy) - 1):
        s = length * min(t[k], 1 - t[k])
        if s < 2 * h[k]:
            continue
        limit = 0.999 * np.sin(np.radians(35.0)) * min(s, 2 * h[k])
        point = shapely.Point(xy[k])
        if boundary.distance(point) <= limit:
            return True
        if earlier and shapely.MultiLineString(earlier).distance(point) <= limit:
            return True
    return False


@settings(deadline=None, max_examples=60)
@given(
    seed=st.integers(0, 2**16),
    angle=st.floats(0, 180),
    offset=st.floats(-3000, 3000),
    h=st.floats(20, 400),
    with_cut=st.booleans(),
)
def test_the_tight_check_is_the_literal_one(seed, angle, offset, h, with_cut):
    water = jagged_water(seed)
    c, s = np.cos(np.radians(angle)), np.sin(np.radians(angle))
    a = np.array([c, s]) * offset + np.array([-s, c]) * 2500
    b = np.array([c, s]) * offset - np.array([-s, c]) * 2500
    length = float(np.hypot(*(b - a)))
    t = np.linspace(0, 1, 129)
    xy = a + t[:, None] * (b - a)
    hs = h * (1 + 0.5 * np.sin(7 * t))
    earlier = [shapely.LineString([(-6000, offset), (6000, offset + 500)])]
    coast = (crossings.coast_tree(water), None, [], earlier if with_cut else [])
    fast = crossings.tight(coast, xy, hs, t, length)
    assert fast == _literal_tight(water, coast[3], xy, hs, t, length)


def _oblique_only(monkeypatch, angles=(45.0, 135.0)):
    monkeypatch.setattr(
        parts_module,
        "_directions",
        lambda longer_x: [_direction(a) for a in angles],
    )


@settings(deadline=None, max_examples=10)
@given(parts=st.integers(2, 5))
def test_oblique_cuts_balance_the_expected_triangles(parts):
    water = shapely.Polygon(OUTER, [ISLAND])
    grid = _grid()
    with pytest.MonkeyPatch.context() as patch:
        _oblique_only(patch)
        cuts = cut_lines(water, grid, parts)
    assert len(cuts) == parts - 1
    for cut in cuts:  # every cut at 45 or 135 degrees
        (x0, y0), (x1, y1) = np.asarray(cut.coords)[[0, -1]]
        assert abs(abs(x1 - x0) - abs(y1 - y0)) < 1e-6 * cut.length
    faces = _faces(water, cuts)
    costs = np.array([expected_triangles(f, grid) for f in faces])
    assert costs.sum() == pytest.approx(expected_triangles(water, grid), rel=1e-9)
    assert costs.max() <= 1.35 * costs.sum() / parts


def test_axis_cuts_come_first():
    # this water has clean cuts across x: the oblique ones are never tried
    assert parts_module._directions(True)[:2] == [(1.0, 0.0), (0.0, 1.0)]
    assert parts_module._directions(False)[:2] == [(0.0, 1.0), (1.0, 0.0)]
    cuts = cut_lines(shapely.Polygon(OUTER, [ISLAND]), _grid(), 4)
    for cut in cuts:
        (x0, y0), (x1, y1) = np.asarray(cut.coords)[[0, -1]]
        assert x0 == x1 or y0 == y1


def test_oblique_parts_make_one_conforming_mesh(monkeypatch):
    domain = _domain()
    grid = _grid(120.0, 0.1, 200.0)
    monkeypatch.setattr(parts_module, "MIN_PART_TRIANGLES", 100)
    one = generate_mesh(domain, grid, parts=1)
    _oblique_only(monkeypatch)
    many = generate_mesh(domain, grid, parts=4)
    again = generate_mesh(domain, grid, parts=4)
    np.testing.assert_array_equal(many.points, again.points)  # deterministic
    np.testing.assert_array_equal(many.triangles, again.triangles)
    assert_one_conforming_mesh(one, many, domain.polygon)
    # the cuts were oblique: interior nodes on a 45-degree line through the water
    cuts = cut_lines(domain.polygon, grid, 4)
    assert cuts
    for cut in cuts:
        dx, dy = np.ptp(np.asarray(cut.coords), axis=0)
        assert abs(dx - dy) < 1e-6 * cut.length
    on_cut = shapely.distance(
        shapely.MultiLineString(cuts), shapely.points(many.points)
    )
    assert (on_cut < 1e-6).sum() > 20
