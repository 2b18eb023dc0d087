"""Mesh cleanup: the fixes happen, and the mesh stays a valid triangulation."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import one_triangle

from coastmesh.errors import ConfigError
from coastmesh.meshing.cleanup import clean_mesh
from coastmesh.meshing.topology import boundary_rings
from coastmesh.types import Mesh


def _check_valid(before: Mesh, after: Mesh) -> None:
    """Positive areas, no edge in 3 triangles, same boundary edges and ids."""
    xy = after.points[after.triangles]
    area = 0.5 * (
        (xy[:, 1, 0] - xy[:, 0, 0]) * (xy[:, 2, 1] - xy[:, 0, 1])
        - (xy[:, 2, 0] - xy[:, 0, 0]) * (xy[:, 1, 1] - xy[:, 0, 1])
    )
    assert (area > 0).all()
    np.testing.assert_array_equal(after.boundary_edges, before.boundary_edges)
    np.testing.assert_array_equal(after.boundary_ids, before.boundary_ids)
    boundary_rings(after)  # the tagged edges are exactly the one-triangle edges
    total = np.abs(area).sum()
    xy0 = before.points[before.triangles]
    total0 = (
        0.5
        * np.abs(
            (xy0[:, 1, 0] - xy0[:, 0, 0]) * (xy0[:, 2, 1] - xy0[:, 0, 1])
            - (xy0[:, 2, 0] - xy0[:, 0, 0]) * (xy0[:, 1, 1] - xy0[:, 0, 1])
        ).sum()
    )
    assert total == pytest.approx(total0, rel=1e-9)  # same region covered


def _all_boundary(mesh: Mesh) -> int:
    boundary = set(mesh.boundary_edges.ravel().tolist())
    return sum(all(v in boundary for v in t) for t in mesh.triangles.tolist())


def test_corner_triangle_is_flipped():
    # a square with an interior node; the corner triangle (0, 1, 3) has all three
    # nodes on the boundary, and flipping its diagonal fixes it
    pts = [[0, 0], [4, 0], [4, 4], [0, 4], [2.6, 2.6]]
    tri = [[0, 1, 3], [1, 4, 3], [1, 2, 4], [2, 3, 4]]
    edges = [[0, 1], [1, 2], [2, 3], [3, 0]]
    m = Mesh(pts, tri, edges, [1, 2, 2, 2], 1, "EPSG:32630")
    assert _all_boundary(m) == 1
    clean, report = clean_mesh(m)
    assert _all_boundary(clean) == 0
    assert report.boundary_triangles_before == 1
    assert report.boundary_flips + report.boundary_splits == 1
    _check_valid(m, clean)
    data = report.to_dict()
    assert data == {f: getattr(report, f) for f in data} and len(data) == 12
    assert "all-boundary triangles 1 -> 0" in report.summary()


def test_high_valence_node_loses_edges():
    # a fan of 12 triangles around node 0 inside a 12-gon, with an inner ring
    n = 12
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    inner = np.column_stack([np.cos(t), np.sin(t)]) * 1000
    outer = np.column_stack([np.cos(t + np.pi / n), np.sin(t + np.pi / n)]) * 2000
    pts = np.vstack([[[0, 0]], inner, outer])
    tri = [[0, 1 + k, 1 + (k + 1) % n] for k in range(n)]
    tri += [[1 + k, 1 + n + k, 1 + (k + 1) % n] for k in range(n)]
    tri += [[1 + (k + 1) % n, 1 + n + k, 1 + n + (k + 1) % n] for k in range(n)]
    edges = [[1 + n + k, 1 + n + (k + 1) % n] for k in range(n)]
    m = Mesh(pts, tri, edges, [3] * n, 1, "EPSG:32630")
    clean, report = clean_mesh(m, max_valence=8, min_angle=5)
    valence = np.bincount(clean.triangles.ravel(), minlength=len(clean.points))
    assert report.max_valence_before == 12
    assert valence[0] <= 8 and report.max_valence_after <= 8
    assert report.valence_flips >= 4
    _check_valid(m, clean)


def test_real_mesh_stays_valid(tmp_path):
    from pathlib import Path

    from coastmesh.case import parse_case, run_case

    example = Path(__file__).parents[2] / "examples" / "orkney" / "pentland_firth.toml"
    text = example.read_text().replace('h_min = "150 m"', 'h_min = "300 m"')
    text = text.replace("[cleanup]", "[cleanup]\nenabled = false")  # raw Gmsh mesh
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(parse_case(text, example), output=tmp_path / "o")
    from coastmesh.io import read_msh

    mesh = read_msh(tmp_path / "o" / "pentland_firth.msh", crs="EPSG:4326")
    clean, report = clean_mesh(mesh, max_valence=7)
    assert report.boundary_triangles_before == _all_boundary(mesh) > 0
    assert report.boundary_triangles_after == _all_boundary(clean)
    assert report.boundary_triangles_after < report.boundary_triangles_before
    # no flip raises a node above the limit
    assert report.max_valence_after <= max(7, report.max_valence_before)
    # flips never go below min(old, min_angle); fixes stop at half of it
    assert report.min_angle_after >= min(report.min_angle_before, 10.0) - 1e-9
    _check_valid(mesh, clean)
    assert result.nodes == len(mesh.points)


def test_bad_options():
    m = one_triangle()
    with pytest.raises(ConfigError, match="max_valence = 2"):
        clean_mesh(m, max_valence=2)
    with pytest.raises(ConfigError, match="min_angle = 70"):
        clean_mesh(m, min_angle=70)
