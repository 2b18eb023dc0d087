"""The batched kernel against the per-contour kernel and the literal reference."""

from __future__ import annotations

import threading

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from reference import simplify_contour_dense, simplify_contour_reference
from test_line import _well_posed

from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io import read_features
from coastmesh.pca import (
    batch,
    line,
    simplify_contour,
    simplify_contours,
    simplify_packed,
)


def _walk(rng, n: int) -> np.ndarray:
    return np.cumsum(rng.standard_normal((n, 2)), axis=0) + [5.0, 60.0]


@pytest.fixture(params=["batches", "small batches and long contours"])
def split(request, monkeypatch):
    """Run with the default split, and with many small batches plus some contours
    sent one by one to the per-contour kernel (and its FFT path)."""
    if request.param != "batches":
        monkeypatch.setattr(batch, "_BATCH_VALUES", 2000)
        monkeypatch.setattr(line, "_DIRECT_MAX_VALUES", 3000)
    return request.param


WITH_FIXTURES = settings(
    deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@settings(WITH_FIXTURES, max_examples=40)
@given(
    seed=st.integers(0, 2**32 - 1),
    sizes=st.lists(st.integers(2, 140), min_size=1, max_size=7),
    window=st.integers(2, 40),
    modes_frac=st.floats(0, 1),
    closed=st.lists(st.booleans(), min_size=7, max_size=7),
)
@example(seed=0, sizes=[40, 41, 79, 40], window=40, modes_frac=0.0, closed=[1] * 7)
@example(seed=1, sizes=[9, 12, 30], window=9, modes_frac=1.0, closed=[0, 1] * 4)
@example(seed=2, sizes=[3, 5, 2], window=2, modes_frac=0.0, closed=[1, 0] * 4)
def test_matches_per_contour_kernel_and_reference(
    split, seed, sizes, window, modes_frac, closed
):
    modes = 1 + int(modes_frac * (window - 1))
    rng = np.random.default_rng(seed)
    contours = [_walk(rng, n) for n in sizes]
    flags = closed[: len(sizes)]
    got = simplify_contours(contours, window, modes, closed=flags, workers=2)
    for xy, is_ring, out in zip(contours, flags, got, strict=True):
        one = simplify_contour(xy, window, modes, closed=is_ring)
        if one is None:
            assert out is None
            continue
        assert out.shape == xy.shape
        if not _well_posed(xy, window, modes, is_ring):
            continue  # a tie at the cut: any two implementations may differ
        np.testing.assert_allclose(out, one, rtol=0, atol=1e-9)
        expected = simplify_contour_reference(xy, window, modes, closed=is_ring)
        np.testing.assert_allclose(out, expected, rtol=0, atol=1e-9)
    assume(any(out is not None for out in got))


@pytest.mark.parametrize("window", [2, 3, 10, 11])
def test_centrosymmetric_modes_span_the_leading_eigenvectors(window):
    """The two half-size problems give the projector of the full eigenproblem."""
    rng = np.random.default_rng(window)
    z = rng.standard_normal(3 * window)
    lags = np.array([z @ np.roll(z, -d) for d in range(window)])
    count = np.full(2, len(z))
    even, odd = batch._halves(np.stack([lags, lags]), count)
    toeplitz = lags[np.abs(np.subtract.outer(np.arange(window), np.arange(window)))]
    q = np.eye(window) - 1.0 / window
    cov = q @ toeplitz @ q / len(z)
    values, vectors = np.linalg.eigh(cov)
    for modes in range(1, window + 1):
        if modes < window and values[-modes] - values[-modes - 1] < 1e-9:
            continue
        u = batch._centrosymmetric_modes(even.copy(), odd.copy(), window, modes)[0]
        expected = vectors[:, -modes:] @ vectors[:, -modes:].T
        np.testing.assert_allclose(u @ u.T, expected, atol=1e-12)
        np.testing.assert_allclose(u.T @ u, np.eye(modes), atol=1e-12)


@pytest.fixture(scope="module")
def orkney_rings():
    coast = read_features(data_path("orkney_gshhg_f.geojson"))
    rings = shapely.get_rings(shapely.get_parts(coast.geometry))
    return [shapely.get_coordinates(r)[:-1] for r in rings]


@pytest.mark.parametrize(("window", "modes"), [(20, 1), (50, 3), (100, 1)])
def test_real_shoreline_matches_dense_reference(orkney_rings, window, modes):
    """Every Orkney ring (84 polygons), as rings and as open lines, at 1e-9 deg."""
    kept = [xy for xy in orkney_rings if len(xy) >= window]
    assert len(kept) >= 5
    for closed in (True, False):
        got = simplify_contours(orkney_rings, window, modes, closed=closed)
        assert sum(out is not None for out in got) == len(kept)
        for xy, out in zip(orkney_rings, got, strict=True):
            if out is None:
                assert len(xy) < window
                continue
            one = simplify_contour(xy, window, modes, closed=closed)
            np.testing.assert_allclose(out, one, rtol=0, atol=1e-9)
            dense = simplify_contour_dense(xy, window, modes, closed=closed)
            np.testing.assert_allclose(out, dense, rtol=0, atol=1e-9)


def test_thread_count_does_not_change_the_result(orkney_rings, monkeypatch):
    """Bit for bit, with several batches and long contours to share out."""
    monkeypatch.setattr(batch, "_BATCH_VALUES", 20_000)
    monkeypatch.setattr(line, "_DIRECT_MAX_VALUES", 20_000)
    flags = np.arange(len(orkney_rings)) % 3 > 0
    results = [
        simplify_contours(orkney_rings, 30, 2, closed=flags, workers=w)
        for w in (1, 2, 3)
    ]
    for other in results[1:]:
        for a, b in zip(results[0], other, strict=True):
            assert (a is None) == (b is None)
            if a is not None:
                np.testing.assert_array_equal(a, b)


def test_packed_rows_progress_and_out(orkney_rings):
    counts = np.array([len(xy) for xy in orkney_rings])
    starts = np.r_[0, np.cumsum(counts + 1)[:-1]]  # one spare row between contours
    coords = np.full((counts.sum() + len(counts), 2), 7.0)
    for s, xy in zip(starts, orkney_rings, strict=True):
        coords[s : s + len(xy)] = xy
    calls = []

    def progress(done, total):
        calls.append((done, total, threading.get_ident()))

    out = simplify_packed(
        coords, starts, counts, 50, 1, closed=True, workers=2, progress=progress
    )
    kept = counts >= 50
    assert calls[-1][:2] == (counts[kept].sum(), counts[kept].sum())
    assert [c[0] for c in calls] == sorted(c[0] for c in calls)
    assert {c[2] for c in calls} == {threading.get_ident()}
    for s, n, xy in zip(starts, counts, orkney_rings, strict=True):
        if n >= 50:
            one = simplify_contour(xy, 50, 1, closed=True)
            np.testing.assert_allclose(out[s : s + n], one, atol=1e-9)
        else:
            assert np.isnan(out[s : s + n]).all()
    assert np.isnan(out[starts + counts]).all()  # rows outside every contour
    in_place = simplify_packed(coords, starts, counts, 50, 1, closed=True, out=coords)
    assert in_place is coords
    np.testing.assert_array_equal(coords[starts + counts], 7.0)
    np.testing.assert_array_equal(
        in_place[~np.isnan(out[:, 0])], out[~np.isnan(out[:, 0])]
    )


def test_full_rank_returns_the_input():
    rng = np.random.default_rng(3)
    contours = [_walk(rng, n) for n in (12, 17, 30)]
    for closed in (True, False):
        for xy, out in zip(
            contours, simplify_contours(contours, 12, 12, closed=closed), strict=True
        ):
            np.testing.assert_allclose(out, xy, atol=1e-9)


def test_bad_input():
    rng = np.random.default_rng(0)
    good = _walk(rng, 30)
    bad = good.copy()
    bad[4, 0] = np.inf
    with pytest.raises(InputDataError, match="contour 1, vertex 4"):
        simplify_contours([good, bad], 10, 1, closed=True)
    with pytest.raises(
        ValueError, match=r"contour 1: coords must have shape \(n, 2\); \(5, 3\)"
    ):
        simplify_contours([good, np.zeros((5, 3))], 10, 1, closed=True)
    with pytest.raises(ValueError, match="2 flags, 3 contours"):
        simplify_contours([good] * 3, 10, 1, closed=[True, False])
    with pytest.raises(ConfigError, match="workers = 0"):
        simplify_contours([good], 10, 1, closed=True, workers=0)
    with pytest.raises(ConfigError, match="modes = 11"):
        simplify_contours([good], 10, 11, closed=True)
    with pytest.raises(ValueError, match="out must be float64"):
        simplify_packed(good, [0], [30], 10, 1, closed=True, out=np.zeros((3, 2)))
    assert simplify_contours([], 10, 1, closed=True) == []


def test_lapack_without_the_c_pointer_gives_the_same(orkney_rings, monkeypatch):
    """scipy exports dsyevr's C pointer (called without the GIL); without it the
    Python wrapper of the same routine is used."""
    assert batch._dsyevr() is not None
    rings = [xy for xy in orkney_rings if len(xy) >= 21]
    fast = simplify_contours(rings, 21, 2, closed=True)
    slow_lines = simplify_contours(rings, 21, 2, closed=False)
    monkeypatch.setattr(batch, "_dsyevr", lambda: None)
    for a, b in zip(fast, simplify_contours(rings, 21, 2, closed=True), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    for a, b in zip(
        slow_lines, simplify_contours(rings, 21, 2, closed=False), strict=True
    ):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_one_mode_solves_only_the_half_that_holds_it(monkeypatch):
    """On a smooth ring the leading mode (a ramp) is skew: the symmetric half is
    not solved, and the result is still the per-contour kernel's."""
    sizes = []
    solve = batch._Leading.__call__

    def counted(self, matrix):
        sizes.append(self.size)
        return solve(self, matrix)

    monkeypatch.setattr(batch._Leading, "__call__", counted)
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    rng = np.random.default_rng(4)
    ring = 10 * np.c_[np.cos(t), np.sin(t)] + 0.01 * rng.standard_normal((400, 2))
    out = simplify_contours([ring], 40, 1, closed=True)[0]
    assert sizes == [20, 20]  # one half of 20 per coordinate, not two
    one = simplify_contour(ring, 40, 1, closed=True)
    np.testing.assert_allclose(out, one, rtol=0, atol=1e-9)
    sizes.clear()
    simplify_contours([ring], 40, 2, closed=True)  # two modes: both halves
    assert sizes == [20, 20, 20, 20]
