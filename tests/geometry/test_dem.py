"""Land polygons contoured from a grid (coastmesh.geometry.land_from_grid).

The contour is compared with a literal marching squares written here, quad by
quad (corners classified, crossings interpolated along each edge, saddles
decided by the quad's mean), on random grids; with an analytic surface whose
coast is a circle; and, on real data, with the GSHHG coast of Orkney.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from pyproj import CRS

from coastmesh.data import path as data_path
from coastmesh.geometry import land_from_grid, reproject
from coastmesh.io import read_features, read_raster

# -- the literal reference ---------------------------------------------------


def _quad_land(xy, h, level):
    """The land of one quad: corners (4, 2) counter-clockwise, heights (4,)."""
    land = h > level
    if not land.any() or np.isnan(h).any():
        return []
    if land.all():
        return [shapely.Polygon(xy)]

    def crossing(a, b):
        t = (level - h[a]) / (h[b] - h[a])
        return xy[a] + t * (xy[b] - xy[a])

    saddle = land[0] == land[2] and land[1] == land[3]
    if saddle and h.mean() <= level:  # two separate corners
        pieces = []
        for k in np.flatnonzero(land):
            before, after = (k - 1) % 4, (k + 1) % 4
            ring = [crossing(k, before), xy[k], crossing(k, after)]
            pieces.append(shapely.Polygon(ring))
        return pieces
    ring = []
    for a in range(4):
        b = (a + 1) % 4
        if land[a]:
            ring.append(xy[a])
        if land[a] != land[b]:
            ring.append(crossing(a, b))
    return [shapely.Polygon(ring)]


def reference_land(x, y, heights, level):
    """Literal marching squares: the union of every quad's land."""
    pieces = []
    for i in range(len(y) - 1):
        for j in range(len(x) - 1):
            rows, cols = [i, i, i + 1, i + 1], [j, j + 1, j + 1, j]
            xy = np.column_stack([x[cols], y[rows]])
            pieces += _quad_land(xy, heights[rows, cols], level)
    return shapely.union_all(pieces)


def check_vertices(land, x, y, heights, level):
    """Every vertex is a level crossing on a grid edge, or a land sample on the
    frame or next to a missing sample; the crossing interpolates to the level."""
    xy = shapely.get_coordinates(land)
    scale = max(1.0, float(np.abs(heights[np.isfinite(heights)]).max(initial=0.0)))
    for px, py in xy:
        on_col = np.flatnonzero(np.isclose(x, px, rtol=0, atol=1e-12))
        on_row = np.flatnonzero(np.isclose(y, py, rtol=0, atol=1e-12))
        if len(on_col) and len(on_row):  # a sample
            i, j = on_row[0], on_col[0]
            assert heights[i, j] > level
            frame = i in (0, len(y) - 1) or j in (0, len(x) - 1)
            near = heights[max(i - 1, 0) : i + 2, max(j - 1, 0) : j + 2]
            assert frame or np.isnan(near).any(), (px, py)
            continue
        if len(on_row):  # on a row: between two columns
            i = on_row[0]
            along, line, h = px, x, heights[i, :]
        else:
            assert len(on_col), f"vertex ({px}, {py}) is on no grid line"
            j = on_col[0]
            along, line, h = py, y, heights[:, j]
        order = np.argsort(line)
        k = np.searchsorted(line[order], along) - 1
        a, b = order[k], order[k + 1]
        t = (along - line[a]) / (line[b] - line[a])
        assert (h[a] > level) != (h[b] > level)
        assert abs(h[a] + t * (h[b] - h[a]) - level) < 1e-9 * scale


# -- random grids against the reference --------------------------------------


@st.composite
def grids(draw):
    ny, nx = draw(st.integers(2, 7)), draw(st.integers(2, 7))
    cells = st.integers(-4, 4).map(float) | st.just(np.nan)
    values = np.array(draw(st.lists(cells, min_size=ny * nx, max_size=ny * nx)))
    steps = st.floats(0.25, 3.0)
    x = np.cumsum(draw(st.lists(steps, min_size=nx, max_size=nx))) - 5.0
    y = np.cumsum(draw(st.lists(steps, min_size=ny, max_size=ny))) + 50.0
    if draw(st.booleans()):
        y = y[::-1]  # north-up
    # integer samples and quad means in quarters never equal a level of k + 0.37
    level = draw(st.integers(-3, 3)) + 0.37
    return x, y, values.reshape(ny, nx), level


@settings(max_examples=300, deadline=None)
@given(grids(), st.sampled_from(["up", "down"]))
@example(
    (np.arange(3.0), np.arange(3.0), np.array([[1, -1, 1], [-1, 1, -1], [1, -1, 1.0]]),
     0.37),
    "up",
)  # fmt: skip
def test_matches_literal_marching_squares(grid, positive):
    x, y, heights, level = grid
    values = heights if positive == "up" else -heights
    before = values.copy()
    land = land_from_grid(x, y, values, level, positive=positive)
    np.testing.assert_array_equal(values, before)  # input unchanged
    assert shapely.is_valid(land).all()
    assert (shapely.get_type_id(land) == shapely.GeometryType.POLYGON).all()
    expected = reference_land(x, y, heights, level)
    got = shapely.union_all(land)
    total = float(np.ptp(x) * np.ptp(y))
    assert shapely.symmetric_difference(got, expected).area < 1e-9 * total
    assert got.area == pytest.approx(expected.area, rel=1e-9, abs=1e-12)
    check_vertices(land, x, y, heights, level)
    # shifting the grid shifts the land
    moved = land_from_grid(x + 100.0, y - 7.0, values, level, positive=positive)
    shifted = shapely.transform(got, lambda c: c + [100.0, -7.0])
    assert shapely.symmetric_difference(shapely.union_all(moved), shifted).area < (
        1e-9 * total
    )


# -- analytic surfaces --------------------------------------------------------


def _grid(n, half=2.0):
    x = np.linspace(-half, half, n)
    y = np.linspace(half, -half, n)  # north-up
    return x, y, np.hypot(x[None, :], y[:, None])


def test_bump_coast_is_a_circle_converging_with_resolution():
    """A Gaussian bump cut at the height of radius 1: the land is the unit disk."""
    errors = []
    for n in (21, 41, 81, 161):
        x, y, r = _grid(n)
        heights = np.exp(-(r**2)) - np.exp(-1.0)
        land = land_from_grid(x, y, heights, 0.0)
        assert len(land) == 1 and len(land[0].interiors) == 0
        coast = shapely.get_coordinates(land[0].exterior)
        spacing = x[1] - x[0]
        assert np.abs(np.hypot(*coast.T) - 1.0).max() < spacing**2
        errors.append(abs(land[0].area - np.pi) / np.pi)
    # second order: halving the spacing divides the area error by about 4
    assert errors[-1] < 1e-3
    for coarse, fine in itertools.pairwise(errors):
        assert fine < coarse / 3


def test_lakes_are_holes_and_land_is_closed_along_the_frame():
    x, y, r = _grid(81)
    ring = 1.0 - ((r - 1.2) / 0.6) ** 2  # land 0.6 < r < 1.8: a lake inside
    land = land_from_grid(x, y, ring, 0.0)
    assert len(land) == 1 and len(land[0].interiors) == 1
    assert land[0].area == pytest.approx(np.pi * (1.8**2 - 0.6**2), rel=2e-3)
    # everything land: the grid's frame, through its outer samples
    whole = land_from_grid(x, y, 1.0 + r, 0.0)
    assert len(whole) == 1 and whole[0].equals(shapely.box(-2, -2, 2, 2))
    # a hill cut by the frame is closed along it
    cut = land_from_grid(x, y, 1.0 - np.hypot(x[None, :] - 2.0, y[:, None]), 0.0)
    assert len(cut) == 1
    assert cut[0].area == pytest.approx(np.pi / 2, rel=2e-3)
    assert shapely.get_coordinates(cut[0])[:, 0].max() == pytest.approx(2.0)


def test_nodata_is_not_land():
    x, y, _ = _grid(9)  # samples 0.5 apart
    heights = np.ones((9, 9))
    heights[3:6, 3:6] = np.nan  # a void inside land: a lake up to its last quads
    land = land_from_grid(x, y, heights, 0.0)
    assert len(land) == 1 and len(land[0].interiors) == 1
    assert land[0].interiors[0].envelope.equals(shapely.box(-1, -1, 1, 1))
    heights[:, 5:] = np.nan  # the east is nodata (a land-only DEM, say)
    land = land_from_grid(x, y, heights, 0.0)
    assert land[0].bounds[2] == pytest.approx(0.0)
    assert len(land_from_grid(x, y, np.full((9, 9), np.nan), 0.0)) == 0


def test_level_and_sign():
    x, y, r = _grid(41)
    heights = 2.0 - r  # land r < 2 at level 0, r < 1 at level 1
    at_one = land_from_grid(x, y, heights, 1.0)
    assert at_one[0].area == pytest.approx(np.pi, rel=1e-2)
    depths = land_from_grid(x, y, -heights, 1.0, positive="down")
    assert depths[0].equals(at_one[0])
    assert len(land_from_grid(x, y, heights, 5.0)) == 0  # no land
    assert land_from_grid(x, y, heights, 5.0).dtype == object


def _ambiguous_saddle(heights, level):
    """Whether a saddle quad's mean is exactly the level (either way is right)."""
    h = heights
    quads = np.stack([h[:-1, :-1], h[:-1, 1:], h[1:, 1:], h[1:, :-1]])
    land = quads > level
    saddle = (land[0] == land[2]) & (land[1] == land[3]) & (land[0] != land[1])
    return bool((saddle & (quads.mean(axis=0) == level)).any())


@settings(max_examples=200, deadline=None)
@given(
    st.integers(2, 7).flatmap(
        lambda ny: st.integers(2, 7).flatmap(
            lambda nx: st.lists(
                st.integers(-2, 2), min_size=ny * nx, max_size=ny * nx
            ).map(lambda v: np.array(v, dtype=float).reshape(ny, nx))
        )
    )
)
def test_samples_at_the_level_match_the_reference(heights):
    """Integer samples cut at 0: many samples sit exactly on the coast."""
    if _ambiguous_saddle(heights, 0.0):
        return
    ny, nx = heights.shape
    x, y = np.arange(nx, dtype=float), np.arange(ny, dtype=float)
    land = land_from_grid(x, y, heights, 0.0)
    assert shapely.is_valid(land).all()
    expected = reference_land(x, y, heights, 0.0)
    assert shapely.symmetric_difference(shapely.union_all(land), expected).area < 1e-9


def test_samples_exactly_at_the_level_give_valid_polygons():
    """A DEM whose sea is exactly 0 (common): land is above it, rings are valid."""
    heights = np.zeros((6, 7))
    heights[1:3, 1:3] = 5.0
    heights[3:5, 3:6] = 2.0  # touches the first block at a corner sample
    x, y = np.arange(7.0), np.arange(6.0)
    land = land_from_grid(x, y, heights, 0.0)
    assert shapely.is_valid(land).all()
    assert shapely.union_all(land).area == pytest.approx(
        reference_land(x, y, heights, 0.0).area
    )


@pytest.mark.parametrize(
    "args, match",
    [
        (([0.0, 1.0], [0.0, 1.0], np.zeros(4)), "values must be 2-D"),
        (([0.0, 1.0, 2.0], [0.0, 1.0], np.zeros((2, 2))), r"x must have shape \(2,\)"),
        (([0.0], [0.0, 1.0], np.zeros((2, 1))), "x has 1 sample"),
        (([0.0, 0.0], [0.0, 1.0], np.zeros((2, 2))), "x must be strictly"),
        (([0.0, 1.0], [0.0, np.nan], np.zeros((2, 2))), "y has non-finite"),
        (([0.0, 1.0], [0.0, 1.0], [[0.0, np.inf], [0, 0]]), "1 infinite cells"),
    ],
)
def test_bad_arguments_name_the_parameter(args, match):
    with pytest.raises(ValueError, match=match):
        land_from_grid(*args)


def test_bad_level_and_sign():
    with pytest.raises(ValueError, match="level = nan"):
        land_from_grid([0, 1], [0, 1], np.zeros((2, 2)), float("nan"))
    with pytest.raises(ValueError, match="positive = 'sideways'"):
        land_from_grid([0, 1], [0, 1], np.zeros((2, 2)), 0.0, positive="sideways")


# -- real data ----------------------------------------------------------------

#: the bundled GSHHG clip's box (its Great Britain is cut along it)
GSHHG_BOX = (-3.8, 58.5, -2.3708, 59.3988)
UTM30 = CRS.from_epsg(32630)


def _iou(a, b):
    return shapely.intersection(a, b).area / shapely.union(a, b).area


def test_etopo1_coast_against_gshhg():
    """ETOPO1 at 0.1 degree, cut at 0 m, against the GSHHG full-resolution coast.

    Measured: intersection over union 0.58 over the GSHHG box (the Orkney
    islands are a few cells across at 0.1 degree) and 0.82 on the Caithness
    coast south of 58.7 N.
    """
    raster = read_raster(data_path("etopo1_0.1deg_orkney_wide.tif"))
    land = land_from_grid(raster.x, raster.y, raster.values, 0.0)
    assert shapely.is_valid(land).all()
    gshhg = read_features(data_path("orkney_gshhg_f.geojson")).geometry
    lonlat = CRS.from_epsg(4326)

    def clipped(geoms, box):
        region = shapely.intersection(shapely.union_all(geoms), shapely.box(*box))
        return reproject(shapely.segmentize(region, 0.01), lonlat, UTM30)

    whole = _iou(clipped(land, GSHHG_BOX), clipped(gshhg, GSHHG_BOX))
    south = (-3.8, 58.5, -2.3708, 58.7)
    caithness = _iou(clipped(land, south), clipped(gshhg, south))
    assert 0.55 < whole < 0.65
    assert 0.78 < caithness < 0.88
    # ETOPO1's land is about 11 % larger (its coast is smoothed over 0.1 degree)
    area = clipped(land, GSHHG_BOX).area / clipped(gshhg, GSHHG_BOX).area
    assert 0.95 < area < 1.2
