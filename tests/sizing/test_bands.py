"""The size field's gradations in bands of rows: the same field, bit for bit."""

from __future__ import annotations

import itertools
import os

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import CRS, Transformer
from reference import distance_to_points_geodesic

from coastmesh.sizing import gradation_size, size_field
from coastmesh.sizing.bands import BandTask, band_count, graded_sizes
from coastmesh.sizing.gradation import Gradation
from coastmesh.types import runner_workers

UTM = CRS.from_epsg(32630)


class Recording:
    """A runner that runs its tasks here, says it has ``workers``, and keeps them."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self.tasks: list[BandTask] = []

    def __call__(self, fn, items):
        self.tasks.extend(items)
        return [fn(item) for item in reversed(items)][::-1]  # any order


def _lines(rng: np.random.Generator, count: int) -> np.ndarray:
    lines = []
    for _ in range(count):
        start = rng.uniform([400_000, 6_300_000], [600_000, 6_500_000])
        steps = rng.normal(0, 8_000, size=(int(rng.integers(2, 6)), 2))
        lines.append(shapely.LineString(start + np.cumsum(steps, axis=0)))
    return np.array(lines, dtype=object)


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    workers=st.integers(2, 5),
    reach=st.floats(5_000, 120_000),
)
def test_bands_equal_the_whole_grid(seed, workers, reach):
    rng = np.random.default_rng(seed)
    gradations = [
        Gradation(_lines(rng, int(rng.integers(1, 4))), 200.0, reach / 4, reach),
        Gradation(_lines(rng, 1), 500.0, 0.0, reach / 2),
    ]
    x = np.arange(380_000, 620_001, 4_000.0)
    y = np.arange(6_280_000, 6_520_001, 3_000.0)
    whole = graded_sizes(x, y, gradations, crs=UTM, h_max=9_000.0, resolution=250.0)
    runner = Recording(workers)
    banded = graded_sizes(
        x, y, gradations, crs=UTM, h_max=9_000.0, resolution=250.0, runner=runner,
        bands=2 * workers,
    )  # fmt: skip
    assert np.array_equal(whole, banded)
    assert len(runner.tasks) == min(2 * workers, len(y) // 16)
    # the bands cover the rows once, in order, and carry fewer vertices than all
    rows = [t.rows for t in runner.tasks]
    assert rows[0][0] == 0 and rows[-1][1] == len(y)
    assert all(a[1] == b[0] for a, b in itertools.pairwise(rows))


def test_a_band_gets_only_the_vertices_within_reach():
    far = shapely.LineString([(500_000, 6_300_000), (520_000, 6_300_000)])
    near = shapely.LineString([(500_000, 6_700_000), (520_000, 6_700_000)])
    g = Gradation(np.array([far, near], dtype=object), 100.0, 1_000.0, 20_000.0)
    x = np.arange(480_000, 540_001, 1_000.0)
    y = np.arange(6_280_000, 6_720_001, 1_000.0)
    runner = Recording(2)
    banded = graded_sizes(x, y, [g], crs=UTM, h_max=5_000.0, resolution=250.0,
                          runner=runner, bands=4)  # fmt: skip
    counts = [len(t.vertices[0]) for t in runner.tasks]
    assert 0 in counts  # the middle bands are beyond reach of both lines
    assert max(counts) < 2 * sum(counts) / 3  # no band holds both lines
    # against geodesics to the densified vertices (the reference's own)
    gx, gy = np.meshgrid(x[::6], y[::40])
    vertices = shapely.get_coordinates(shapely.segmentize([far, near], 100.0))
    lonlat = Transformer.from_crs(UTM, 4326, always_xy=True)
    d = distance_to_points_geodesic(
        *lonlat.transform(gx.ravel(), gy.ravel()), *lonlat.transform(*vertices.T)
    )
    want = gradation_size(d, 100.0, 5_000.0, 1_000.0, 20_000.0).reshape(gx.shape)
    np.testing.assert_allclose(banded[::40, ::6], want, rtol=0, atol=0.02 * 5_000)


def test_size_field_is_the_same_on_any_runner():
    rng = np.random.default_rng(7)
    g = [Gradation(_lines(rng, 3), 150.0, 2_000.0, 40_000.0)]
    bounds = (380_000, 6_280_000, 620_000, 6_520_000)
    one = size_field(bounds, g, crs=UTM, h_max=6_000.0, cell=2_000.0, rate=0.2)
    cluster = Recording(4 * (os.cpu_count() or 1))  # more workers than cores
    assert band_count(cluster) == 2 * cluster.workers
    many = size_field(bounds, g, crs=UTM, h_max=6_000.0, cell=2_000.0, rate=0.2,
                      runner=cluster)  # fmt: skip
    assert np.array_equal(one.values, many.values)
    assert len(cluster.tasks) == len(one.y) // 16
    assert float(one.min()) == 150.0


def test_runner_workers_and_default_bands():
    assert runner_workers(print) == 1
    assert runner_workers(Recording(4)) == 4
    assert band_count(print) == 1
    assert band_count(Recording(1)) == 1  # one machine: the threads do it
