"""Figures of the paper's PCA studies."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from coastmesh.data import path as data_path
from coastmesh.io import read_raster
from coastmesh.plot.studies import (
    overlay_figure,
    relief_maps_figure,
    relief_surfaces_figure,
    rms_figure,
    spectrum_figure,
)


@pytest.fixture(scope="module")
def raster():
    return read_raster(
        data_path("etopo1_0.1deg_orkney_wide.tif"), bbox=(-4.0, 58.0, -2.0, 60.0)
    )


def test_maps_share_one_colour_scale(raster):
    panels = [("1 mode", raster.values - 100.0), ("input", raster.values)]
    figure = relief_maps_figure(raster, panels)
    images = [ax.images[0] for ax in figure.axes if ax.images]
    assert len(images) == 2
    assert len({(im.norm.vmin, im.norm.vmax) for im in images}) == 1
    assert images[0].norm.vmin == pytest.approx(float(raster.min()) - 100.0)
    assert images[0].get_extent() == pytest.approx([-4.05, -1.95, 57.95, 60.05])
    assert figure.axes[0].get_xlabel().startswith("longitude")


def test_surfaces_are_3d_with_the_exaggeration_noted(raster):
    figure = relief_surfaces_figure(
        raster, [("a", raster.values), ("b", raster.values)]
    )
    assert [ax.name for ax in figure.axes] == ["3d", "3d"]
    assert all(len(ax.collections) == 1 for ax in figure.axes)
    assert "vertical exaggeration x" in figure.get_suptitle()


def test_spectrum_and_rms_mark_the_chosen_modes():
    spectrum = np.array([100.0, 10.0, 1.0, 1e-20])
    figure = spectrum_figure(spectrum, (1, 3))
    left, right = figure.axes
    assert len(left.lines[0].get_xdata()) == 3  # the ~0 mode is not drawn
    assert list(right.lines[1].get_xdata()) == [1, 3]
    curve = [
        {"modes": m, "rms_m": 10.0 / m, "max_abs_diff_m": 30.0 / m} for m in (1, 2, 3)
    ]
    figure = rms_figure(curve, (2,))
    assert [list(ax.lines[1].get_xdata()) for ax in figure.axes] == [[2], [2]]


@pytest.mark.parametrize("view", ["whole", "detail"])
def test_overlay_draws_every_layer(view):
    ring = np.array([shapely.Point(0, 0).buffer(1.0)], dtype=object)
    smooth = np.array([ring[0].simplify(0.2)], dtype=object)
    detail = (0.5, -0.5, 1.2, 0.5)
    figure = overlay_figure(
        ring, [("pca", smooth)], crs="EPSG:4326", detail=detail, view=view
    )
    (ax,) = figure.axes
    assert len(ax.collections) == 2
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["original", "pca"]
    box = (-1.0, -1.0, 1.0, 1.0) if view == "whole" else detail
    assert ax.get_xlim() == pytest.approx((box[0], box[2]))
    assert len(ax.patches) == (1 if view == "whole" else 0)
