"""Figures of mesh quality and of depth on the mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest

from coastmesh.geometry import reproject_points
from coastmesh.meshing import mesh_quality
from coastmesh.plot import depth_figure, quality_figure
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
