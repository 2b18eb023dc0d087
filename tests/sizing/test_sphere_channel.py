"""The width of the water on a world lon/lat grid, against literal references.

The references loop over the grid's nodes with great-circle distances
(haversine) and the spherical midpoint formula; the fast code uses chords of
the unit sphere in k-d trees.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.sizing.channel import RADIUS_STEP
from coastmesh.sizing.narrow import NARROW_ELEMENTS
from coastmesh.sizing.sphere_channel import (
    TOLERANCE,
    sphere_narrow_channels,
    sphere_over_land,
    sphere_water_mask,
    sphere_width,
)


def _arc(lon0: float, lat0: float, lon1: float, lat1: float) -> float:
    """Great-circle distance by the haversine formula, metres."""
    p0, p1 = math.radians(lat0), math.radians(lat1)
    dp, dl = p1 - p0, math.radians(lon1 - lon0)
    a = math.sin(dp / 2) ** 2 + math.cos(p0) * math.cos(p1) * math.sin(dl / 2) ** 2
    return 2 * EARTH_RADIUS * math.asin(min(1.0, math.sqrt(a)))


def _midpoint(lon0: float, lat0: float, lon1: float, lat1: float):
    """The midpoint of the great-circle arc between two points, degrees."""
    p0, p1 = math.radians(lat0), math.radians(lat1)
    dl = math.radians(lon1 - lon0)
    bx, by = math.cos(p1) * math.cos(dl), math.cos(p1) * math.sin(dl)
    lat = math.atan2(math.sin(p0) + math.sin(p1), math.hypot(math.cos(p0) + bx, by))
    lon = math.radians(lon0) + math.atan2(by, math.cos(p0) + bx)
    return math.degrees(lon), math.degrees(lat)


def _lon(nx: int) -> list[float]:
    return [-180.0 + 360.0 * i / nx for i in range(nx)]


def reference_edges(water: np.ndarray, lat: np.ndarray) -> list[tuple[float, float]]:
    """Every step from a water node to a node not in the water, its midpoint;
    half a step past a first or last row that is not a pole."""
    ny, nx = water.shape[0], water.shape[1] - 1
    lon = _lon(nx)
    edges = []
    for j in range(ny):
        for i in range(nx):
            east = (i + 1) % nx
            if water[j, i] != water[j, east]:
                edges.append(_midpoint(lon[i], lat[j], lon[east], lat[j]))
            if j + 1 < ny and water[j, i] != water[j + 1, i]:
                edges.append(_midpoint(lon[i], lat[j], lon[i], lat[j + 1]))
    step = lat[1] - lat[0]
    for i in range(nx):
        if abs(lat[0]) < 90 and water[0, i]:
            edges.append((lon[i], max(lat[0] - step / 2, -90.0)))
        if abs(lat[-1]) < 90 and water[-1, i]:
            edges.append((lon[i], min(lat[-1] + step / 2, 90.0)))
    return edges


def reference_sphere_width(
    water: np.ndarray, lat: np.ndarray, max_width: float
) -> np.ndarray:
    """Literal: for each water node, every disk centred on a water node that
    fits (its distance to the edge at least r) and holds it (within r)."""
    ny, nx = water.shape[0], water.shape[1] - 1
    lon = _lon(nx)
    edges = reference_edges(water, lat)
    depth = {}
    for j in range(ny):
        for i in range(nx):
            if water[j, i]:
                arcs = [_arc(lon[i], lat[j], a, b) for a, b in edges]
                depth[j, i] = min(arcs, default=math.inf)
    radii = [0.5 * EARTH_RADIUS * math.radians(lat[1] - lat[0])]
    while radii[-1] < max_width / 2:
        radii.append(radii[-1] * RADIUS_STEP)
    out = np.zeros((ny, nx + 1))
    for (j, i), d in depth.items():
        best = None
        for r in radii:
            if any(
                dc >= r * (1 - TOLERANCE)
                and _arc(lon[i], lat[j], lon[c], lat[k]) <= r * (1 + TOLERANCE)
                for (k, c), dc in depth.items()
            ):
                best = r
        if best is None:
            out[j, i] = 2 * d
        elif best == radii[-1]:
            out[j, i] = math.inf
        else:
            out[j, i] = 2 * best
    out[:, -1] = out[:, 0]
    return out


@st.composite
def world_grids(draw):
    """A small world grid: rows from ``south`` every ``step`` degrees, a pole
    row or not, and a random sea (one value on a pole row: one point)."""
    nx = draw(st.integers(4, 9))
    ny = draw(st.integers(2, 6))
    step = draw(st.floats(0.5, 25.0))
    where = draw(st.sampled_from(["north_pole", "south_pole", "free"]))
    if where == "north_pole":
        lat = 90.0 - step * np.arange(ny)[::-1]
    elif where == "south_pole":
        lat = -90.0 + step * np.arange(ny)
    else:
        south = draw(st.floats(-89.0, 89.0 - step * (ny - 1)))
        lat = south + step * np.arange(ny)
    seed = draw(st.integers(0, 2**31))
    water = np.random.default_rng(seed).random((ny, nx)) < draw(st.floats(0.2, 0.95))
    for row in np.flatnonzero(np.abs(lat) >= 90.0):
        water[row] = water[row, 0]
    return np.hstack([water, water[:, :1]]), lat


@settings(max_examples=40, deadline=None)
@given(world_grids(), st.floats(1.0, 6.0))
def test_sphere_width_matches_the_literal_reference(grid, cells):
    water, lat = grid
    max_width = cells * EARTH_RADIUS * math.radians(lat[1] - lat[0])
    fast = sphere_width(water, lat, max_width=max_width)
    np.testing.assert_allclose(
        fast, reference_sphere_width(water, lat, max_width), rtol=1e-9
    )
    assert (fast[~water] == 0).all() and (fast[water] > 0).all()


def _strait(nx: int, lat: np.ndarray, columns: list[int]) -> np.ndarray:
    water = np.zeros((len(lat), nx), dtype=bool)
    water[:, columns] = True
    return np.hstack([water, water[:, :1]])


def test_a_strait_across_the_antimeridian_is_as_wide_as_one_in_the_middle():
    lat = np.arange(-30.0, 31.0, 2.0)
    across = _strait(180, lat, [178, 179, 0, 1, 2])  # 168 to 184 degrees east
    middle = _strait(180, lat, [88, 89, 90, 91, 92])  # -4 to 4 degrees east
    w_across = sphere_width(across, lat, max_width=3e6)
    w_middle = sphere_width(middle, lat, max_width=3e6)
    np.testing.assert_allclose(
        np.roll(w_across[:, :-1], 90, axis=1), w_middle[:, :-1], rtol=1e-9
    )
    np.testing.assert_allclose(
        w_across, reference_sphere_width(across, lat, 3e6), rtol=1e-9
    )
    # 5 columns of 2 degrees on the equator: 1,112 km of water, measured
    # within a cell (222 km) and a radius step, as on a plane
    true = 5 * 2 * math.radians(1) * EARTH_RADIUS
    assert (true - 2 * 222e3) / RADIUS_STEP <= w_across[15, 0] <= true
    assert w_across[15, 0] == w_across[15, -1] == w_across[15, 179]


def test_a_polar_sea_is_measured_across_the_pole():
    # water north of 80.5 degrees (the edge between the rows at 80 and 81):
    # a disk round the pole, 19 degrees of arc across
    lat = np.arange(70.0, 90.5, 1.0)
    water = np.zeros((len(lat), 25), dtype=bool)
    water[lat >= 81.0] = True
    w = sphere_width(water, lat, max_width=5e6)
    np.testing.assert_allclose(w, reference_sphere_width(water, lat, 5e6), rtol=1e-9)
    across = 19.0 * math.radians(1) * EARTH_RADIUS
    assert across / RADIUS_STEP - 2 * 111.2e3 <= w[-1, 0] <= across
    # every node of the sea is held by the same disk round the pole: the east-
    # west steps there are tiny, but no sliver is measured narrow
    assert np.ptp(w[water]) == 0.0


def test_sphere_width_refuses_a_grid_without_its_repeated_meridian():
    with pytest.raises(ConfigError, match="nx >= 4"):
        sphere_width(np.ones((3, 4), bool), np.array([0.0, 1.0, 2.0]), max_width=1e5)


def reference_over_land(term, water, lat, reach):
    """For each land node, the values of the water nodes nearest it; inf
    beyond ``reach``."""
    ny, nx = water.shape[0], water.shape[1] - 1
    lon = _lon(nx)
    wet = [(j, i) for j in range(ny) for i in range(nx) if water[j, i]]
    options = {}
    for j in range(ny):
        for i in range(nx):
            if water[j, i]:
                continue
            arcs = [_arc(lon[i], lat[j], lon[c], lat[k]) for k, c in wet]
            near = min(arcs)
            if near > reach * (1 + 1e-9):
                options[j, i] = {math.inf}
                continue
            options[j, i] = {
                term[k, c]
                for (k, c), a in zip(wet, arcs, strict=True)
                if a <= near * (1 + 1e-9) + 1e-6
            }
    return options


@settings(max_examples=30, deadline=None)
@given(world_grids(), st.integers(0, 10_000), st.sampled_from([math.inf, 1.0, 3.0]))
def test_land_takes_the_nearest_water_value_on_the_sphere(grid, seed, cells):
    water, lat = grid
    if not water.any() or water.all():
        return
    term = np.random.default_rng(seed).uniform(1.0, 100.0, water.shape)
    term[:, -1] = term[:, 0]
    reach = cells * EARTH_RADIUS * math.radians(lat[1] - lat[0])
    out = sphere_over_land(term, water, lat, reach=reach)
    for (j, i), values in reference_over_land(term, water, lat, reach).items():
        assert out[j, i] in values
    assert (out[water] == term[water]).all() and (out[:, -1] == out[:, 0]).all()


def test_water_goes_on_past_an_open_boundary_on_the_sphere():
    lat = np.arange(-10.0, 11.0, 5.0)
    inside = np.zeros((5, 37), dtype=bool)
    inside[:, 16:19] = True  # -20 to 0 degrees east
    inside[:, -1] = inside[:, 0]
    shore = np.array([[-25.5, y] for y in range(-15, 16)])  # west of the sea
    opened = np.array([[5.0, y] for y in range(-15, 16)])  # east of it: a cut
    water = sphere_water_mask(inside, lat, shore, opened)
    nodes = np.meshgrid(np.linspace(-180, 180, 37), lat)
    for (j, i), wet in np.ndenumerate(water[:, :-1]):
        lon, y = nodes[0][j, i], nodes[1][j, i]
        to_shore = min(_arc(lon, y, a, b) for a, b in shore)
        to_open = min(_arc(lon, y, a, b) for a, b in opened)
        assert wet == (inside[j, i] or to_open < to_shore)
    assert water[2, 19] and water[2, 20] and not water[2, 15]


def reference_narrow(width, inside, lat, h_min, margin):
    """Stretches narrower than 2 h_min (with ``margin`` added to the widths)
    by flood fill over 8 neighbours, the columns wrapping round; area by
    R^2 dlon dlat cos(lat) per node."""
    ny, nx = inside.shape[0], inside.shape[1] - 1
    narrow = {
        (j, i)
        for j in range(ny)
        for i in range(nx)
        if inside[j, i] and width[j, i] + margin < NARROW_ELEMENTS * h_min
    }
    seen, parts = set(), []
    for start in sorted(narrow):
        if start in seen:
            continue
        part, queue = [], deque([start])
        seen.add(start)
        while queue:
            j, i = queue.popleft()
            part.append((j, i))
            for dj in (-1, 0, 1):
                for di in (-1, 0, 1):
                    n = (j + dj, (i + di) % nx)
                    if n in narrow and n not in seen:
                        seen.add(n)
                        queue.append(n)
        parts.append(part)
    dlon, dlat = 2 * math.pi / nx, math.radians(lat[1] - lat[0])
    out = []
    for part in parts:
        area = sum(
            EARTH_RADIUS**2 * dlon * dlat * math.cos(math.radians(lat[j]))
            for j, _ in part
        )
        rows = [j for j, _ in part]
        cols = sorted({i for _, i in part})
        # the fewest consecutive columns round the world that hold them all
        span = min(max((c - s) % nx for c in cols) + 1 for s in cols)
        wide = math.cos(math.radians(min(abs(lat[j]) for j in rows)))
        length = EARTH_RADIUS * math.hypot(
            (max(rows) - min(rows) + 1) * dlat, span * dlon * wide
        )
        if length >= NARROW_ELEMENTS * h_min:
            out.append((frozenset(part), area, max(width[j, i] for j, i in part)))
    return out


@settings(max_examples=40, deadline=None)
@given(
    world_grids(),
    st.integers(0, 10_000),
    st.floats(0.05, 2.0),
    st.sampled_from([0.0, 0.3, 1.0]),
)
def test_narrow_channels_on_the_sphere_match_the_reference(grid, seed, share, cells):
    inside, lat = grid
    rng = np.random.default_rng(seed)
    step = EARTH_RADIUS * math.radians(lat[1] - lat[0])
    width = np.where(inside, rng.uniform(0.1, 4.0, inside.shape) * step, 0.0)
    width[:, -1] = width[:, 0]
    h_min, margin = share * step, cells * step
    labels, found = sphere_narrow_channels(
        width, inside, lat, h_min=h_min, margin=margin
    )
    want = reference_narrow(width, inside, lat, h_min, margin)
    assert len(found) == len(want) == labels.max()
    got = []
    for k, (row, col, area, w) in enumerate(found, start=1):
        nodes = frozenset(zip(*np.nonzero(labels[:, :-1] == k), strict=True))
        assert labels[row, col] == k and width[row, col] == w
        got.append((nodes, area, w))
    assert [a for _, a, _ in got] == sorted((a for _, a, _ in got), reverse=True)
    assert {n for n, _, _ in got} == {n for n, _, _ in want}
    for nodes, area, w in got:
        match = next(x for x in want if x[0] == nodes)
        assert area == pytest.approx(match[1], rel=1e-9) and w == match[2]
    assert (labels[:, -1] == labels[:, 0]).all()
