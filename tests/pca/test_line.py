"""simplify_contour against the literal reference, properties and errors."""

from __future__ import annotations

import json
import tracemalloc

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from reference import simplify_contour_dense, simplify_contour_reference

from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.pca import contour_modes, line, simplify_contour


def _walk(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.standard_normal((n, 2)), axis=0) + [5.0, 60.0]


def _well_posed(xy, window, modes, closed) -> bool:
    """The leading-mode projection is unique: a clear gap after mode ``modes``."""
    if modes == window:
        return True
    for dim in range(2):
        lam = contour_modes(xy[:, dim], window, closed=closed)
        if lam[modes - 1] - lam[modes] < 1e-6 * max(lam[0], 1e-300):
            return False
    return True


@pytest.fixture(params=["direct", "fft"])
def path(request, monkeypatch):
    """Run each test through both the strided direct path and the FFT path."""
    if request.param == "fft":
        monkeypatch.setattr(line, "_DIRECT_MAX_VALUES", 0)
    return request.param


# the parametrised fixture runs once per test, not once per example: that is meant
WITH_FIXTURES = settings(
    deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@settings(WITH_FIXTURES, max_examples=60)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(2, 140),
    window=st.integers(2, 60),
    modes_frac=st.floats(0, 1),
    closed=st.booleans(),
)
@example(seed=0, n=60, window=60, modes_frac=0.0, closed=True)  # n == L
@example(seed=1, n=61, window=31, modes_frac=0.0, closed=True)  # n == 2L-1
@example(seed=2, n=45, window=40, modes_frac=0.5, closed=True)  # wraps onto itself
@example(seed=3, n=40, window=40, modes_frac=0.2, closed=False)  # a single partition
def test_matches_reference(path, seed, n, window, modes_frac, closed):
    modes = 1 + int(modes_frac * (window - 1))
    xy = _walk(seed, n)
    expected = simplify_contour_reference(xy, window, modes, closed=closed)
    got = simplify_contour(xy, window, modes, closed=closed)
    if n < window:
        assert got is None and expected is None
        return
    assume(_well_posed(xy, window, modes, closed))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)


@settings(WITH_FIXTURES, max_examples=30)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(8, 120),
    window=st.integers(2, 8),
    closed=st.booleans(),
    dx=st.floats(-1e3, 1e3),
    dy=st.floats(-1e3, 1e3),
)
def test_properties(path, seed, n, window, closed, dx, dy):
    xy = _walk(seed, n)
    before = xy.copy()
    # full rank returns the input
    full = simplify_contour(xy, window, window, closed=closed)
    np.testing.assert_allclose(full, xy, atol=1e-9)
    # shifting the input shifts the output
    a = simplify_contour(xy, window, 1, closed=closed)
    b = simplify_contour(xy + [dx, dy], window, 1, closed=closed)
    np.testing.assert_allclose(b, a + [dx, dy], atol=1e-7)
    # one output vertex per input vertex, input untouched
    assert a.shape == xy.shape and a.dtype == np.float64
    np.testing.assert_array_equal(xy, before)


def test_straight_line_is_kept():
    """A straight, evenly spaced line is its own first mode."""
    xy = np.c_[np.linspace(0, 10, 300), np.linspace(5, -5, 300)]
    for closed in (False,):
        np.testing.assert_allclose(
            simplify_contour(xy, 50, 1, closed=closed), xy, atol=1e-9
        )


def test_smooths_noise_on_a_circle():
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    circle = np.c_[np.cos(t), np.sin(t)]
    noisy = circle + 0.02 * np.random.default_rng(5).standard_normal(circle.shape)
    out = simplify_contour(noisy, 100, 2, closed=True)
    err_in = np.linalg.norm(noisy - circle, axis=1).mean()
    err_out = np.linalg.norm(out - circle, axis=1).mean()
    assert err_out < 0.3 * err_in


def _norway_rings(min_points: int):
    data = json.loads(data_path("norway_west_gshhg_f.geojson").read_text())
    for feature in data["features"]:
        geom = feature["geometry"]
        polygons = (
            [geom["coordinates"]] if geom["type"] == "Polygon" else geom["coordinates"]
        )
        for polygon in polygons:
            for ring in polygon:
                xy = np.asarray(ring, dtype=float)[:-1]
                if len(xy) >= min_points:
                    yield xy


@pytest.mark.parametrize(("window", "modes"), [(100, 1), (100, 5), (500, 1)])
def test_real_shoreline_matches_dense_reference(window, modes):
    """Every Norwegian ring long enough, both kernel paths, at 1e-9 degrees."""
    rings = list(_norway_rings(window))
    assert len(rings) >= 9
    for xy in rings:
        expected = simplify_contour_dense(xy, window, modes, closed=True)
        got = simplify_contour(xy, window, modes, closed=True)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
        got_open = simplify_contour(xy, window, modes, closed=False)
        expected_open = simplify_contour_dense(xy, window, modes, closed=False)
        np.testing.assert_allclose(got_open, expected_open, rtol=0, atol=1e-9)


def test_real_ring_loop_reference():
    """The loop reference itself on a real ring (small enough for its loops)."""
    xy = next(r for r in _norway_rings(300) if len(r) < 1500)
    np.testing.assert_allclose(
        simplify_contour(xy, 100, 1, closed=True),
        simplify_contour_reference(xy, 100, 1, closed=True),
        atol=1e-9,
    )


def test_memory_is_not_n_times_window():
    """O(n + L^2) memory: far below the n x L trajectory matrix (800 MB here)."""
    xy = _walk(11, 200_000)
    simplify_contour(xy[:5000], 500, 1, closed=True)  # warm-up (imports, caches)
    tracemalloc.start()
    simplify_contour(xy, 500, 1, closed=True)
    simplify_contour(xy, 500, 1, closed=False)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 60 * 200_000 * 8 / 2 + 40 * 500**2 * 8  # ~50 MB vs 800 MB


def test_short_contour_is_dropped():
    assert simplify_contour(_walk(0, 99), 100, 1, closed=True) is None
    assert simplify_contour(np.empty((0, 2)), 2, 1, closed=False) is None


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"window": 1, "modes": 1}, "window = 1"),
        ({"window": 2.5, "modes": 1}, "window = 2.5"),
        ({"window": 10, "modes": 0}, "modes = 0"),
        ({"window": 10, "modes": 11}, "modes = 11"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        simplify_contour(_walk(0, 50), closed=True, **kwargs)


def test_bad_coordinates():
    xy = _walk(0, 50)
    xy[17, 1] = np.nan
    with pytest.raises(InputDataError, match="vertex 17"):
        simplify_contour(xy, 10, 1, closed=True)
    with pytest.raises(ValueError, match=r"shape \(n, 2\)"):
        simplify_contour(np.zeros((5, 3)), 2, 1, closed=True)
