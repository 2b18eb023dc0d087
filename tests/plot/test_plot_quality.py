"""Figures of mesh quality and of depth on the mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest

from coastmesh.geometry import reproject_points
from coastmesh.meshing import element_time_steps, mesh_quality
from coastmesh.plot import depth_figure, quality_figure, time_step_figure
from coastmesh.types import Mesh


@pytest.fixture(scope="module")
def lonlat_mesh(mesh_with_islands):
    """The islands mesh of conftest, in longitude and latitude."""
    m = mesh_with_islands
    lonlat = reproject_points(m.points, m.crs, "EPSG:4326")
    return Mesh(
        lonlat,
        m.triangles,
        m.boundary_edges,
        m.boundary_ids,
        m.surface_id,
        "EPSG:4326",
        {"size": np.full(len(lonlat), 250.0)},
        m.boundary_names,
        m.boundary_kinds,
    )


def test_quality_figure_builds_and_saves(lonlat_mesh, tmp_path):
    report = mesh_quality(lonlat_mesh)
    figure = quality_figure(lonlat_mesh, report, title="test")
    assert len(figure.axes) == 3
    assert figure.axes[2].get_xscale() == "log"
    bars = figure.axes[0].patches[0]  # the minimum-angle histogram
    assert bars.get_data().values.sum() == len(lonlat_mesh.triangles)
    figure.savefig(tmp_path / "quality.png")
    assert (tmp_path / "quality.png").stat().st_size > 1000
    sizeless = Mesh(
        lonlat_mesh.points,
        lonlat_mesh.triangles,
        lonlat_mesh.boundary_edges,
        lonlat_mesh.boundary_ids,
        1,
        lonlat_mesh.crs,
    )
    assert len(quality_figure(sizeless).axes) == 2  # no size, no edge panel


def test_depth_figure_builds_and_saves(lonlat_mesh, tmp_path):
    lon, lat = lonlat_mesh.points.T
    depth = 10 + 1000 * (lon - lon.min())
    depth[0] = np.nan
    mesh = lonlat_mesh.with_point_data(depth=depth)
    figure = depth_figure(mesh, title="depth")
    assert len(figure.axes) == 2  # the map and its colour bar
    ax, bar = figure.axes
    assert ax.get_xlabel().startswith("longitude")
    assert ax.get_aspect() == pytest.approx(
        1 / math.cos(math.radians(lat.mean())), 1e-2
    )
    assert "positive down" in bar.get_ylabel()
    figure.savefig(tmp_path / "depth.png")
    assert (tmp_path / "depth.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="no 'depth'"):
        depth_figure(lonlat_mesh)


def test_time_step_figure_builds_and_saves(lonlat_mesh, mesh_with_islands, tmp_path):
    lon = lonlat_mesh.points[:, 0]
    # 72 m deep in the east, dry (above 0 m) in the west: blank there
    mesh = lonlat_mesh.with_point_data(depth=2000 * (lon - lon.min()) - 10)
    figure = time_step_figure(mesh, title="test")
    assert len(figure.axes) == 2  # the map and its colour bar
    ax, bar = figure.axes
    assert ax.get_xlabel().startswith("longitude")
    assert "stable time step (s)" in bar.get_ylabel()
    assert bar.yaxis.get_scale() == "log"
    steps = element_time_steps(mesh)["dt"]
    finite = np.isfinite(steps)
    assert 0 < finite.sum() < 0.95 * len(steps)
    assert ax.collections[0].get_array().size == finite.sum()
    marker = ax.lines[0]  # the smallest circled, and labelled
    k = int(np.flatnonzero(finite)[np.argmin(steps[finite])])
    centroid = mesh.points[mesh.triangles[k]].mean(axis=0)
    np.testing.assert_allclose(marker.get_xydata()[0], centroid)
    assert ax.texts[0].get_text() == f"min {steps[k]:.3g}"
    figure.savefig(tmp_path / "time_step.png")
    assert (tmp_path / "time_step.png").stat().st_size > 1000

    both = time_step_figure(mesh_with_islands, dt=20.0, velocity=1.0)
    assert len(both.axes) == 4
    courant = both.axes[1]
    assert "Courant number at dt = 20 s" in both.axes[3].get_ylabel()
    report = mesh_quality(mesh_with_islands, dt=20.0, velocity=1.0).time_step
    assert courant.texts[0].get_text() == f"max {report.courant.max:.3g}"
    assert both.axes[0].texts[0].get_text() == f"min {report.min:.3g}"
    both.savefig(tmp_path / "both.png")
    assert (tmp_path / "both.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="no 'depth'"):
        time_step_figure(lonlat_mesh)


def test_time_step_figure_of_a_large_mesh_shades_each_node_by_its_worst(
    lonlat_mesh, monkeypatch, tmp_path
):
    import coastmesh.plot.quality as quality

    lon = lonlat_mesh.points[:, 0]
    mesh = lonlat_mesh.with_point_data(depth=2000 * (lon - lon.min()) + 5)
    steps = element_time_steps(mesh, dt=2.0)
    monkeypatch.setattr(quality, "FLAT_TRIANGLES", len(mesh.triangles) - 1)
    figure = time_step_figure(mesh, dt=2.0)
    ax, ax2 = (a for a in figure.axes if a.get_xlabel().startswith("longitude"))
    for axes, key, worst in ((ax, "dt", np.minimum), (ax2, "courant", np.maximum)):
        image = axes.collections[0]
        assert (
            image.get_shading() == "gouraud" if hasattr(image, "get_shading") else True
        )
        at_nodes = image.get_array()
        want = np.full(len(mesh.points), np.nan)
        for t, value in zip(mesh.triangles, steps[key], strict=True):
            for node in t:  # the literal reduction, one triangle at a time
                want[node] = value if np.isnan(want[node]) else worst(want[node], value)
        np.testing.assert_array_equal(at_nodes, want)
        assert not image.get_in_layout()
    figure.savefig(tmp_path / "time_step.png")
