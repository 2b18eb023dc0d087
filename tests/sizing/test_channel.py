"""The width of the water and the channel-width term, against a literal reference."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from conftest import bay_with_inlet
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from coastmesh.sizing.channel import (
    RADIUS_STEP,
    channel_size,
    domain_width,
    local_width,
    narrow_width,
    water_mask,
)
from coastmesh.sizing.grid import PlaneGrid
from coastmesh.sizing.narrow import channel_polygons, narrow_channels
from coastmesh.sizing.slots import slots


def reference_width(water: np.ndarray, cell: float, max_width: float) -> np.ndarray:
    """Literal local thickness: for each node, every disk that fits and holds it.

    The same radii as the fast code (half a cell times powers of RADIUS_STEP,
    up to the first at or above max_width / 2); a disk of radius r centred at a
    water node fits if every land node (and every node outside the array) is at
    least r + 1/2 cells from its centre.
    """
    ny, nx = water.shape
    land = [(i, j) for i in range(-1, ny + 1) for j in range(-1, nx + 1)]
    land = [
        (i, j) for i, j in land if not (0 <= i < ny and 0 <= j < nx) or not water[i, j]
    ]
    radii = [0.5]
    while radii[-1] < max_width / (2 * cell):
        radii.append(radii[-1] * RADIUS_STEP)
    depth = {}
    for i in range(ny):
        for j in range(nx):
            if water[i, j]:
                depth[i, j] = min(math.hypot(i - a, j - b) for a, b in land) - 0.5
    out = np.zeros(water.shape)
    for i in range(ny):
        for j in range(nx):
            if not water[i, j]:
                continue
            best = None
            for r in radii:
                if any(
                    d >= r and math.hypot(i - a, j - b) <= r
                    for (a, b), d in depth.items()
                ):
                    best = r
            if best is None:
                out[i, j] = 0.5 * cell
            elif best == radii[-1]:
                out[i, j] = np.inf
            else:
                out[i, j] = 2 * best * cell
    return out


@settings(max_examples=25, deadline=None)
@given(
    arrays(bool, st.tuples(st.integers(1, 9), st.integers(1, 9))),
    st.floats(2.0, 30.0),
)
def test_local_width_matches_the_literal_reference(water, max_cells):
    cell = 10.0
    fast = local_width(water, cell, max_width=max_cells * cell)
    np.testing.assert_array_equal(fast, reference_width(water, cell, max_cells * cell))


def test_local_width_on_a_real_like_mask_matches_the_reference():
    rng = np.random.default_rng(3)
    water = rng.random((14, 16)) > 0.25
    water[5:9, :] = True  # a channel through noise
    fast = local_width(water, 50.0, max_width=800.0)
    np.testing.assert_array_equal(fast, reference_width(water, 50.0, 800.0))


def reference_narrow(water: np.ndarray, cell: float, max_width: float) -> np.ndarray:
    """Literal: a water node is narrow if no disk of diameter max_width that
    fits (centred on a water node at least max_width / 2 + 1/2 cells from all
    land) has its centre within max_width / 2 + 1/2 cells of it; a narrow node
    gets twice its own distance to the edge of the water."""
    ny, nx = water.shape
    land = [
        (i, j)
        for i in range(-1, ny + 1)
        for j in range(-1, nx + 1)
        if not (0 <= i < ny and 0 <= j < nx) or not water[i, j]
    ]
    depth = {
        (i, j): min(math.hypot(i - a, j - b) for a, b in land) - 0.5
        for i in range(ny)
        for j in range(nx)
        if water[i, j]
    }
    radius = max_width / (2 * cell)
    centres = [c for c, d in depth.items() if d >= radius]
    out = np.zeros(water.shape)
    for (i, j), d in depth.items():
        held = any(math.hypot(i - a, j - b) <= radius + 0.5 for a, b in centres)
        out[i, j] = np.inf if held else 2 * d * cell
    return out


@settings(max_examples=25, deadline=None)
@given(
    arrays(bool, st.tuples(st.integers(1, 12), st.integers(1, 12))),
    st.floats(1.0, 8.0),
)
def test_narrow_width_matches_the_literal_reference(water, max_cells):
    cell = 10.0
    fast = narrow_width(water, cell, max_width=max_cells * cell)
    slow = reference_narrow(water, cell, max_cells * cell)
    np.testing.assert_allclose(fast, slow, rtol=1e-12)


@pytest.mark.parametrize("cells", [2, 3, 5, 8])
def test_narrow_width_tells_a_channel_under_max_width_and_a_staircase_coast(cells):
    water = np.zeros((40, cells + 2), bool)
    water[:, 1:-1] = True  # a channel `cells` nodes across: `cells` cells wide
    narrow = narrow_width(water, 100.0, max_width=400.0) < 400.0
    # (4 cells, max_width itself, comes out narrow: disks are centred on nodes)
    assert narrow[10:30, 1:-1].all() == (cells < 4)
    assert not narrow[10:30, 1:-1].any() or cells < 4
    # open water with a diagonal (staircase) coast holds no narrow node
    i, j = np.mgrid[0:60, 0:80]
    sea = j <= i + 20
    away = sea & (i >= 10) & (i < 50)  # 30 cells and more from the frame
    assert not (narrow_width(sea, 100.0, max_width=400.0)[away] < 400.0).any()


@pytest.mark.parametrize("cells", [3, 6, 11, 24])
def test_a_straight_channel_is_measured_within_a_cell_and_a_radius_step(cells):
    water = np.zeros((80, cells + 2), bool)
    water[:, 1:-1] = True
    width = local_width(water, 100.0, max_width=10_000.0)
    across = width[40, 1:-1]
    true = cells * 100.0
    # rounded down by at most a cell (disks are centred on nodes) and a radius
    # step; next to the shore (disks through grid nodes) by one step more
    assert (true - 100.0) / RADIUS_STEP <= across[len(across) // 2] <= true
    assert ((true - 100.0) / RADIUS_STEP**2 <= across).all()
    assert (across <= true).all()


def test_open_water_is_wider_than_max_width_and_land_is_zero():
    water = np.ones((30, 30), bool)
    water[:, :3] = False
    width = local_width(water, 100.0, max_width=1000.0)
    assert np.isinf(width[15, 20]) and np.isinf(width[15, 3])
    assert (width[:, :3] == 0).all()


def test_the_head_of_a_wedge_narrows():
    # a wedge of water opening to the right: narrower towards its head
    y, x = np.mgrid[0:60, 0:120]
    water = np.abs(y - 30) < 2 + x * 0.2
    width = local_width(water, 10.0, max_width=2000.0)
    along = width[30, 5:100:10]
    assert (np.diff(along) >= 0).all() and along[0] < along[-1]


def test_water_goes_on_past_an_open_boundary():
    inside = np.zeros((10, 10), bool)
    inside[:, :5] = True
    shore = np.zeros((10, 10), bool)
    shore[:, 0] = True
    opened = np.zeros((10, 10), bool)
    opened[:, 5] = True
    water = water_mask(inside, shore, opened)
    assert water[:, :10].all()  # beyond the open line: nearer it than the shore
    # no open boundary: the domain is all the water
    assert (water_mask(inside, shore, np.zeros_like(opened)) == inside).all()


def test_channel_size_floors_and_rejects_fewer_than_one_element():
    width = np.array([0.0, 150.0, 3000.0, np.inf])
    np.testing.assert_array_equal(
        channel_size(width, elements_across=3, h_min=100.0), [100, 100, 1000, np.inf]
    )
    with pytest.raises(ValueError, match=r"elements_across = 0\.5"):
        channel_size(width, elements_across=0.5, h_min=100.0)


def test_narrow_channels_are_labelled_largest_first_without_corner_tips():
    width = np.full((20, 20), 5000.0)
    width[2:4, :] = 150.0  # a long narrow channel: 40 nodes
    width[10:13, 5:8] = 120.0  # a short one: 9 nodes
    width[12, 7] = 60.0  # its dead end
    width[17:19, 17:19] = 50.0  # the tip of a corner: 4 nodes, 141 m across
    labels, found = narrow_channels(
        width, np.ones((20, 20), bool), h_min=100.0, cell=50.0
    )
    assert int(labels.max()) == 2
    assert [f[2] for f in found] == [40 * 2500.0, 9 * 2500.0]
    assert found[1][3] == 120.0
    assert labels[18, 18] == 0
    polygons = channel_polygons(labels, np.arange(20) * 50.0, np.arange(20) * 50.0)
    assert shapely.area(polygons).tolist() == [40 * 2500.0, 9 * 2500.0]


def test_domain_width_measures_an_inlet_and_ignores_the_open_boundary():
    domain = bay_with_inlet(600.0)
    x = np.arange(-225.0, 20_226.0, 50.0)  # no node on the inlet walls
    y = np.arange(-200.0, 26_201.0, 50.0)
    grid = PlaneGrid(x, y, domain.crs, 50.0, domain)
    width, inside = domain_width(grid, domain, max_width=9000.0), grid.sea
    row = np.searchsorted(y, 23_000.0)
    in_inlet = width[row][inside[row]]
    assert len(in_inlet) == 12
    assert (in_inlet <= 600.0).all() and (in_inlet >= 550.0 / RADIUS_STEP).all()
    # at the open boundary, the bay is as wide as ever: the sea goes on
    assert np.isinf(width[np.searchsorted(y, 100.0), np.searchsorted(x, 10_000.0)])


def test_slots_thinner_than_the_grid_are_found_and_corners_are_not():
    # a 20 m bay with a 3 m wide, 60 m long slot, and a sharp cape
    bay = shapely.Polygon(
        [
            (0, 0),
            (20, 0),
            (20, 20),
            (11.5, 20),
            (11.5, 80),
            (8.5, 80),
            (8.5, 20),
            (0, 20),
            (-5, 10),
        ]
    )
    found = slots(bay, 6.0)
    assert len(found) == 1
    assert found[0].bounds[1] >= 19.9 and found[0].bounds[3] == 80.0
    assert found[0].area == pytest.approx(3 * 60, rel=0.02)
    # nothing narrower than 2 m: no slot
    assert len(slots(bay, 2.0)) == 0
