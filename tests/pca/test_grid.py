"""simplify_raster against the literal reference, properties and errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from reference import simplify_raster_dense, simplify_raster_reference

from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError
from coastmesh.pca import grid as grid_module
from coastmesh.pca import raster_modes, simplify_raster


@pytest.fixture(params=["whole", "strips"])
def strips(request, monkeypatch):
    """Run each test on the whole grid at once, and in strips of 4 window heights."""
    if request.param == "strips":
        monkeypatch.setattr(grid_module, "_STRIP_CELLS", 1)
    return request.param


def _surface(seed: int, ny: int, nx: int, holes: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    grid = np.cumsum(np.cumsum(rng.standard_normal((ny, nx)), 0), 1) - 50.0
    grid[rng.random((ny, nx)) < holes] = np.nan
    return grid


def _well_posed(grid, window, modes) -> bool:
    wy, wx = (window, window) if np.isscalar(window) else window
    if modes == wy * wx:
        return True
    try:
        lam = raster_modes(grid, window)
    except ValueError:
        return True  # no partition at all
    return lam[modes - 1] - lam[modes] >= 1e-6 * max(lam[0], 1e-300)


# the parametrised fixture runs once per test, not once per example: that is meant
WITH_FIXTURES = settings(
    deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@settings(WITH_FIXTURES, max_examples=60)
@given(
    seed=st.integers(0, 2**32 - 1),
    ny=st.integers(2, 24),
    nx=st.integers(2, 24),
    wy=st.integers(2, 5),
    wx=st.integers(2, 5),
    modes_frac=st.floats(0, 1),
    holes=st.sampled_from([0.0, 0.0, 0.01, 0.05, 0.2]),
)
@example(seed=0, ny=8, nx=8, wy=8, wx=8, modes_frac=0.0, holes=0.0)  # one window
@example(seed=1, ny=9, nx=2, wy=2, wx=2, modes_frac=1.0, holes=0.0)
def test_matches_reference(strips, seed, ny, nx, wy, wx, modes_frac, holes):
    assume(ny >= wy and nx >= wx)
    modes = 1 + int(modes_frac * (wy * wx - 1))
    grid = _surface(seed, ny, nx, holes)
    assume(_well_posed(grid, (wy, wx), modes))
    expected = simplify_raster_reference(grid, (wy, wx), modes)
    got = simplify_raster(grid, (wy, wx), modes)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(grid))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)


@settings(WITH_FIXTURES, max_examples=25)
@given(
    seed=st.integers(0, 2**32 - 1),
    ny=st.integers(4, 20),
    nx=st.integers(4, 20),
    holes=st.sampled_from([0.0, 0.05]),
    shift=st.floats(-1e4, 1e4),
)
def test_properties(strips, seed, ny, nx, holes, shift):
    grid = _surface(seed, ny, nx, holes)
    before = grid.copy()
    np.testing.assert_allclose(simplify_raster(grid, 3, 9), grid, atol=1e-9)
    a = simplify_raster(grid, 3, 1)
    b = simplify_raster(grid + shift, 3, 1)
    np.testing.assert_allclose(b, a + shift, atol=1e-7)
    np.testing.assert_array_equal(grid, before)


def test_uncovered_cells_keep_their_values(strips):
    grid = _surface(3, 12, 12, 0.0)
    grid[5, 5] = np.nan  # isolates nothing, but windows through it are not partitions
    grid[:, 0] = np.nan  # the first column is missing
    grid[0, 1] = 7.0  # the corner cell next to the gap is covered only via row 0
    out = simplify_raster(grid, 4, 1)
    assert np.isnan(out[:, 0]).all() and np.isnan(out[5, 5])
    expected = simplify_raster_reference(grid, 4, 1)
    np.testing.assert_allclose(out, expected, atol=1e-9)
    # a grid with no complete window comes back unchanged
    sparse = _surface(4, 6, 6, 0.0)
    sparse[::2, ::2] = np.nan
    np.testing.assert_array_equal(
        np.isnan(simplify_raster(sparse, 3, 1)), np.isnan(sparse)
    )
    np.testing.assert_allclose(simplify_raster(sparse, 3, 1), sparse)


@pytest.mark.parametrize("modes", [1, 16, 48, 64])
def test_real_orkney_raster(strips, modes):
    rasterio = pytest.importorskip("rasterio")
    with rasterio.open(data_path("etopo1_0.1deg_orkney_wide.tif")) as src:
        grid = src.read(1).astype(float)
    expected = simplify_raster_reference(grid, 8, modes)
    got = simplify_raster(grid, 8, modes)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
    if modes == 64:
        np.testing.assert_allclose(got, grid, atol=1e-9)


def test_real_shelf_raster_with_missing_land(strips):
    """The NW shelf grid with land masked out as missing (a real nodata pattern)."""
    rasterio = pytest.importorskip("rasterio")
    with rasterio.open(data_path("etopo1_0.1deg_nwshelf.tif")) as src:
        grid = src.read(1).astype(float)
    grid[grid > 0] = np.nan
    for modes in (1, 16):
        got = simplify_raster(grid, 8, modes)
        expected = simplify_raster_dense(grid, 8, modes)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)


def test_rectangular_window():
    grid = _surface(9, 15, 20, 0.0)
    np.testing.assert_allclose(
        simplify_raster(grid, (3, 5), 4),
        simplify_raster_reference(grid, (3, 5), 4),
        atol=1e-9,
    )


def test_progress_is_reported(strips):
    calls = []
    simplify_raster(
        _surface(1, 40, 10, 0.0), 3, 1, progress=lambda d, t: calls.append((d, t))
    )
    total = calls[-1][1]
    assert calls == [(d, total) for d in range(1, total + 1)]
    assert total == (2 if strips == "whole" else 2 * 4)  # 40 rows, strips of 12


def test_out_of_core_with_memmaps(tmp_path, monkeypatch):
    """Read from and write to memory-mapped files strip by strip."""
    monkeypatch.setattr(grid_module, "_STRIP_CELLS", 2000)
    grid = _surface(12, 300, 90, 0.01)
    src = np.lib.format.open_memmap(tmp_path / "in.npy", "w+", np.float32, grid.shape)
    src[:] = grid
    dst = np.lib.format.open_memmap(tmp_path / "out.npy", "w+", np.float64, grid.shape)
    result = simplify_raster(src, 8, 16, out=dst)
    assert result is dst
    expected = simplify_raster_dense(np.asarray(src, dtype=float), 8, 16)
    np.testing.assert_allclose(np.asarray(dst), expected, atol=1e-9)


@pytest.mark.parametrize(
    ("args", "error", "match"),
    [
        ((np.zeros((5, 5)), 1, 1), ConfigError, "window = 1"),
        ((np.zeros((5, 5)), 8, 1), ConfigError, r"larger than the raster \(5 x 5"),
        ((np.zeros((9, 9)), 3, 10), ConfigError, r"modes = 10"),
        ((np.zeros((9, 9)), 3, 0), ConfigError, r"modes = 0"),
        ((np.zeros((9, 9)), (3, "a"), 1), ConfigError, "window columns"),
        ((np.zeros(9), 3, 1), ValueError, "2-D"),
        ((np.full((9, 9), np.inf), 3, 1), ValueError, r"values\[0, 0\] is infinite"),
    ],
)
def test_bad_input(args, error, match):
    with pytest.raises(error, match=match):
        simplify_raster(*args)
