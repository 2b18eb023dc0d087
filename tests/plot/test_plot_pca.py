"""Plots: drawn on the Agg backend, checked through their Axes."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from conftest import ORKNEY_BBOX, ORKNEY_RASTER_BBOX
from matplotlib.figure import Figure

from coastmesh.errors import FormatError, OutputExistsError
from coastmesh.io.rasters.raster import read_raster
from coastmesh.io.vectors.vector import read_features
from coastmesh.plot import (
    plot_raster_comparison,
    plot_shoreline_overlay,
    raster_figure,
    save_figure,
    shoreline_figure,
)


@pytest.fixture(autouse=True, scope="module")
def agg_backend():
    import matplotlib

    matplotlib.use("Agg")


@pytest.fixture(scope="module")
def coast(orkney_geojson):
    return read_features(orkney_geojson, bbox=ORKNEY_BBOX)


@pytest.fixture(scope="module")
def depth(orkney_tif):
    return read_raster(orkney_tif, bbox=ORKNEY_RASTER_BBOX)


def test_shoreline_overlay_draws_every_ring(coast):
    ax = Figure().add_subplot()
    simplified = shapely.simplify(coast.geometry, 0.01)
    assert plot_shoreline_overlay(coast, simplified, ax) is ax
    before, after = ax.collections
    assert after.get_label() == "PCA approximation"
    rings = shapely.get_num_interior_rings(coast.geometry).sum() + len(coast)
    assert len(before.get_segments()) == rings
    assert before.get_label() == "input"
    # the view holds the data, and lon/lat keeps shapes (1 / cos 59 degrees)
    minx, miny, maxx, maxy = shapely.total_bounds(coast.geometry)
    assert ax.get_xlim() == pytest.approx((minx, maxx))
    assert ax.get_aspect() == pytest.approx(1 / np.cos(np.radians((miny + maxy) / 2)))
    assert "longitude" in ax.get_xlabel()


def test_shoreline_overlay_on_a_new_figure_skips_missing():
    ring = shapely.Point(0, 0).buffer(1.0)
    ax = plot_shoreline_overlay([ring, None], [None, None], bounds=(-2, -2, 2, 2))
    assert ax.get_xlim() == (-2, 2)
    assert len(ax.collections[0].get_segments()) == 1
    assert len(ax.collections[1].get_segments()) == 0
    assert ax.get_aspect() == 1.0  # no CRS: equal axes


def test_raster_comparison(depth):
    axes = Figure().subplots(1, 3)
    changed = depth.copy(data=depth.values + 5.0)
    drawn = plot_raster_comparison(depth, changed, axes)
    assert [ax.get_title() for ax in drawn] == [
        "input",
        "PCA approximation",
        "approximation - input",
    ]
    image = drawn[2].images[0]
    np.testing.assert_allclose(image.get_array(), 5.0)
    left, right, bottom, top = drawn[0].images[0].get_extent()
    assert (left, right, bottom, top) == pytest.approx((-4.05, -1.95, 57.95, 60.05))


def test_raster_comparison_checks_its_input(depth):
    with pytest.raises(ValueError, match="differ in shape"):
        plot_raster_comparison(depth, depth[:-1], Figure().subplots(1, 3))
    with pytest.raises(ValueError, match="3 Axes"):
        plot_raster_comparison(depth, depth, Figure().subplots(1, 2))


def test_figures_save_atomically(tmp_path, coast, depth):
    figure = shoreline_figure(coast, shapely.simplify(coast.geometry, 0.01), title="t")
    assert len(figure.axes) == 2
    save_figure(figure, tmp_path / "coast.png")
    assert (tmp_path / "coast.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(OutputExistsError, match="--overwrite"):
        save_figure(figure, tmp_path / "coast.png")
    save_figure(raster_figure(depth, depth), tmp_path / "depth.svg")
    assert b"<svg" in (tmp_path / "depth.svg").read_bytes()[:500]
    with pytest.raises(FormatError, match="unknown plot format"):
        save_figure(figure, tmp_path / "coast.bmp")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["coast.png", "depth.svg"]
