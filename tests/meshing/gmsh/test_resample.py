"""Boundary resampling: end points, spacing against an analytic reference, islands."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import MeshingError
from coastmesh.meshing.gmsh.resample import (
    SmallIslandWarning,
    check_boundary,
    resample_rings,
    resample_segment,
)


def constant(h):
    return lambda xy: np.full(len(xy), float(h))


def linear_in_x(a, b):
    return lambda xy: a + b * xy[:, 0]


def test_straight_line_with_constant_size():
    out = resample_segment(np.array([[0.0, 0.0], [100.0, 0.0]]), constant(10.0))
    np.testing.assert_allclose(out[:, 0], np.arange(0, 101, 5.0))
    np.testing.assert_array_equal(out[:, 1], 0.0)


def test_spacing_follows_a_linear_size_against_the_exact_integral():
    # h(x) = a + b x on [0, L]: s(x) = ln(1 + b x / a) / b target edges, so with
    # n intervals the points sit at x_j = a (exp(b s_j) - 1) / b, s_j = j s(L) / n.
    a, b, length = 10.0, 0.05, 1000.0
    line = np.column_stack([np.linspace(0, length, 7), np.zeros(7)])
    out = resample_segment(line, linear_in_x(a, b), points_per_edge=2.0)
    total = np.log1p(b * length / a) / b
    n = round(total * 2.0)
    s = np.arange(n + 1) * total / n
    expected = a * np.expm1(b * s) / b
    assert len(out) == n + 1
    # the trapezoidal rule on quarter-size steps is good to 1e-3 of the local size
    assert (np.abs(out[:, 0] - expected) <= 1e-3 * (a + b * expected)).all()
    np.testing.assert_array_equal(out[:, 1], 0.0)
    spacing = np.diff(out[:, 0])
    local = a + b * 0.5 * (out[1:, 0] + out[:-1, 0])
    np.testing.assert_allclose(spacing / local, 0.5, rtol=0.05)


def test_spacing_along_a_curve_follows_the_size():
    t = np.linspace(0, np.pi, 400)
    arc = np.column_stack([1000 * np.cos(t), 1000 * np.sin(t)])
    size = lambda xy: 20.0 + 0.02 * (xy[:, 0] + 1000)  # noqa: E731
    out = resample_segment(arc, size, points_per_edge=1.0)
    steps = np.hypot(*np.diff(out, axis=0).T)
    mid = 0.5 * (out[1:] + out[:-1])
    np.testing.assert_allclose(steps / size(mid), 1.0, rtol=0.05)
    radius = np.hypot(out[:, 0], out[:, 1])
    np.testing.assert_allclose(radius, 1000.0, rtol=1e-3)


@settings(max_examples=50, deadline=None)
@given(
    coords=st.lists(
        st.tuples(
            st.floats(-1e4, 1e4, allow_nan=False), st.floats(-1e4, 1e4, allow_nan=False)
        ),
        min_size=2,
        max_size=30,
    ),
    h=st.floats(1.0, 5e3),
    points_per_edge=st.floats(0.5, 4.0),
)
def test_end_points_are_kept_exactly(coords, h, points_per_edge):
    xy = np.array(coords, dtype=np.float64)
    before = xy.copy()
    out = resample_segment(xy, constant(h), points_per_edge=points_per_edge)
    np.testing.assert_array_equal(xy, before)
    assert out.shape[1] == 2 and len(out) >= 2
    np.testing.assert_array_equal(out[0], xy[0])
    np.testing.assert_array_equal(out[-1], xy[-1])


def test_long_corners_stay_and_short_details_go():
    square = np.array([[0, 0], [100, 0], [100, 100], [0, 100], [0, 0]], float)
    out = resample_segment(square, constant(10.0))
    for corner in square:
        assert (out == corner).all(axis=1).any()
    zigzag = np.column_stack([np.arange(0, 1000, 1.0), np.tile([0.0, 1.0], 500)])
    smooth = resample_segment(zigzag, constant(100.0))
    arc = np.hypot(*np.diff(zigzag, axis=0).T).sum()
    # 50 m of arc between points: each step spans tens of 1 m teeth
    assert len(smooth) == round(arc / 50.0) + 1
    assert (np.diff(smooth[:, 0]) > 30.0).all()


def test_rings_split_at_corners_share_end_points():
    square = np.array([[0, 0], [100, 0], [100, 100], [0, 100], [0, 0]], float)
    kept, dropped = resample_rings([[square]], constant(10.0))
    pieces = kept[0][0]
    assert dropped == [] and len(pieces) == 4
    for first, second in itertools.pairwise(pieces):
        np.testing.assert_array_equal(first[-1], second[0])
    np.testing.assert_array_equal(pieces[-1][-1], pieces[0][0])


def test_tiny_island_is_dropped_with_a_warning():
    box = np.array([[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]], float)
    tiny = np.array([[500, 500], [503, 500], [503, 503], [500, 500]], float)
    big = np.array([[100, 100], [100, 300], [300, 300], [300, 100], [100, 100]], float)
    with pytest.warns(SmallIslandWarning, match="1 islands"):
        kept, dropped = resample_rings([[box], [tiny], [big]], constant(50.0))
    assert dropped == [1] and len(kept) == 2


def test_no_warning_when_nothing_is_dropped():
    box = np.array([[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]], float)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept, dropped = resample_rings([[box]], constant(50.0))
    assert dropped == [] and len(kept) == 1


def test_collapsing_exterior_is_an_error():
    box = np.array([[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]], float)
    with pytest.raises(MeshingError, match="exterior collapses"):
        resample_rings([[box]], constant(1e4))


@pytest.mark.parametrize(
    ("coords", "size", "ppe", "match"),
    [
        (np.zeros((1, 2)), constant(1.0), 2.0, "shape"),
        (np.array([[0, 0], [np.nan, 1]]), constant(1.0), 2.0, "non-finite"),
        (np.array([[0, 0], [1, 1]]), constant(1.0), 0.0, "points_per_edge"),
        (np.array([[0, 0], [1, 1]]), constant(-1.0), 2.0, "size_at"),
        (np.array([[0, 0], [1, 1]]), lambda xy: np.ones(1), 2.0, "size_at"),
    ],
)
def test_bad_input_is_refused(coords, size, ppe, match):
    with pytest.raises(ValueError, match=match):
        resample_segment(coords, size, points_per_edge=ppe)


@pytest.mark.parametrize(("radius", "kept"), [(0.3, False), (0.7, True)])
def test_islands_need_three_edges_around_them(radius, kept):
    """A hole whose perimeter is under three target edges would mesh degenerate."""
    box = [np.array([[0, 0], [20, 0], [20, 20], [0, 20], [0, 0]], float)]
    t = np.linspace(0, 2 * np.pi, 65)
    island = [np.column_stack([10 + radius * np.cos(t), 10 + radius * np.sin(t)])]
    island[0][-1] = island[0][0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SmallIslandWarning)
        rings, dropped = resample_rings([box, island], lambda xy: np.ones(len(xy)))
    # perimeter / size: 1.9 (dropped), 4.4 (kept)
    assert (len(rings) == 2) == kept and (dropped == []) == kept


def test_self_intersecting_resampled_boundary_is_a_meshing_error():
    # an island resampled so coarsely that it crosses the exterior
    square = np.array([[0, 0], [10000, 0], [10000, 10000], [0, 10000], [0, 0]], float)
    island = np.array([[50, 50], [50, 9000], [-10, 5000], [50, 50]], float)
    with pytest.raises(MeshingError, match="not a valid polygon"):
        check_boundary([[[square]], [[island]]])
    assert check_boundary([[[square]]]) is None
    # the place named as the caller says (lon/lat in a case), with what to do
    with pytest.raises(MeshingError, match=r"at <0, \d+>: two coasts .* close"):
        check_boundary([[[square]], [[island]]], lambda x, y: f"<{x:g}, {y:g}>")
