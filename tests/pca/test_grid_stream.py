"""The raster PCA one chunk at a time (pca.chunks) against the in-memory kernel.

The streamed ``simplify-raster`` runs these functions as Dask tasks, each on
the cells it reads from the file; here the chunks are cut from arrays, in
sizes a GeoTIFF's tiles would not allow (1 row, 3 columns, ...).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
from reference import simplify_raster_reference

from coastmesh.data import path as data_path
from coastmesh.pca import (
    chunk_gram,
    chunk_modes,
    chunk_rebuild,
    raster_modes,
    simplify_raster,
)


def _surface(seed: int, ny: int, nx: int, holes: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    grid = np.cumsum(np.cumsum(rng.standard_normal((ny, nx)), 0), 1) - 50.0
    grid[rng.random((ny, nx)) < holes] = np.nan
    return grid


def _edges(n: int, size: int) -> list[int]:
    return [*range(0, n, size), n]


def chunked(grid, window, modes, rows: int, columns: int) -> np.ndarray:
    """The streamed algorithm on an array: chunks of ``rows x columns`` cells."""
    (wy, wx), (ny, nx) = window, grid.shape
    chunks = [
        (r0, r1, c0, c1)
        for r0, r1 in zip(_edges(ny, rows), _edges(ny, rows)[1:], strict=False)
        for c0, c1 in zip(_edges(nx, columns), _edges(nx, columns)[1:], strict=False)
    ]
    gram, count, shift = 0.0, 0, None
    for r0, r1, c0, c1 in chunks:  # pass 1, summed in a fixed order
        block = grid[r0 : r1 + wy - 1, c0 : c1 + wx - 1]
        valid = np.isfinite(block)
        mean = float(block[valid].mean()) if valid.any() else 0.0
        if shift is None and valid.any():
            shift = mean
        g, m = chunk_gram(block, window, shift=mean)
        gram, count = gram + g, count + m
    if count == 0:
        return grid.copy()
    vectors = chunk_modes(gram, count, modes)
    out = np.empty_like(grid)
    for r0, r1, c0, c1 in chunks:  # pass 2
        top, left = max(0, r0 - wy + 1), max(0, c0 - wx + 1)
        block = grid[top : r1 + wy - 1, left : c1 + wx - 1]
        out[r0:r1, c0:c1], cover = chunk_rebuild(
            block,
            window,
            vectors,
            shift=shift,
            rows=slice(r0 - top, r1 - top),
            columns=slice(c0 - left, c1 - left),
        )
        assert cover.shape == (r1 - r0, c1 - c0)
    return out


def _well_posed(grid, window, modes) -> bool:
    if modes == window[0] * window[1]:
        return True
    try:
        lam = raster_modes(grid, window)
    except ValueError:
        return True  # no partition at all
    return lam[modes - 1] - lam[modes] >= 1e-6 * max(lam[0], 1e-300)


@settings(deadline=None, max_examples=60)
@given(
    seed=st.integers(0, 2**32 - 1),
    ny=st.integers(2, 30),
    nx=st.integers(2, 30),
    wy=st.integers(2, 5),
    wx=st.integers(2, 5),
    modes_frac=st.floats(0, 1),
    holes=st.sampled_from([0.0, 0.0, 0.01, 0.05, 0.2]),
    rows=st.integers(1, 31),
    columns=st.integers(1, 31),
)
@example(seed=0, ny=8, nx=8, wy=8, wx=8, modes_frac=0.0, holes=0.0, rows=1, columns=1)
@example(
    seed=5, ny=30, nx=30, wy=4, wx=3, modes_frac=0.3, holes=0.05, rows=1, columns=30
)
def test_chunks_match_the_in_memory_kernel(
    seed, ny, nx, wy, wx, modes_frac, holes, rows, columns
):
    assume(ny >= wy and nx >= wx)
    modes = 1 + int(modes_frac * (wy * wx - 1))
    grid = _surface(seed, ny, nx, holes)
    assume(_well_posed(grid, (wy, wx), modes))
    before = grid.copy()
    got = chunked(grid, (wy, wx), modes, rows, columns)
    np.testing.assert_array_equal(grid, before)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(grid))
    np.testing.assert_allclose(
        got, simplify_raster(grid, (wy, wx), modes), rtol=0, atol=1e-9
    )


def test_chunks_match_the_literal_reference():
    grid = _surface(11, 23, 19, 0.05)
    got = chunked(grid, (3, 4), 5, 7, 5)
    np.testing.assert_allclose(
        got, simplify_raster_reference(grid, (3, 4), 5), rtol=0, atol=1e-9
    )


@pytest.mark.parametrize(("rows", "columns"), [(48, 421), (112, 144)])
def test_real_shelf_raster_in_chunks(rows, columns):
    """The NW shelf grid with land missing, in strips and in rectangles."""
    rasterio = pytest.importorskip("rasterio")
    with rasterio.open(data_path("etopo1_0.1deg_nwshelf.tif")) as src:
        grid = src.read(1).astype(float)
    grid[grid > 0] = np.nan
    got = chunked(grid, (8, 8), 16, rows, columns)
    np.testing.assert_allclose(got, simplify_raster(grid, 8, 16), rtol=0, atol=1e-9)


def test_the_gram_does_not_depend_on_the_shift():
    grid = _surface(2, 20, 20, 0.05)
    a, m = chunk_gram(grid, 4, shift=-50.0)
    b, n = chunk_gram(grid, 4, shift=1e3)
    assert m == n > 0
    np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(a).max())


def test_bad_input_is_named():
    grid = _surface(2, 10, 10, 0.0)
    grid[3, 4] = np.inf
    with pytest.raises(ValueError, match=r"block\[3, 4\] is infinite"):
        chunk_gram(grid, 3, shift=0.0)
    with pytest.raises(ValueError, match="2-D"):
        chunk_gram(np.zeros(5), 3, shift=0.0)
    with pytest.raises(ValueError, match="shift"):
        chunk_gram(np.zeros((5, 5)), 3, shift=np.nan)
    with pytest.raises(ValueError, match="no partition"):
        chunk_modes(np.zeros((9, 9)), 0, 1)
    with pytest.raises(ValueError, match=r"vectors must have shape \(9, modes\)"):
        chunk_rebuild(
            np.zeros((5, 5)), 3, np.zeros((4, 1)), shift=0.0, rows=slice(0, 5)
        )
