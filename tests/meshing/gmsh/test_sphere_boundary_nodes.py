"""Boundary nodes of a global case: the sphere view along the curves, or whole."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

import coastmesh.meshing.gmsh.boundary_nodes as curves
from coastmesh.geometry.earth import reproject
from coastmesh.geometry.sphere import plane_crs
from coastmesh.meshing.gmsh import SphereSizeGrid
from coastmesh.meshing.gmsh.boundary_nodes import boundary_nodes
from coastmesh.types import SizeGrid


def _world_sizes(rng, cell):
    """A world grid of ``cell`` degrees with sizes (metres) that change fast."""
    lon = np.arange(-180.0, 180.0 + cell / 2, cell)
    lat = np.arange(-90.0, 90.0 + cell / 2, cell)
    values = rng.uniform(60e3, 400e3, (len(lat), len(lon)))
    values[:, -1] = values[:, 0]  # the wrapped column
    return SphereSizeGrid(SizeGrid(lon, lat, values), map_units=True)


def _literal_cells_near(grid, xy):
    """Cells (row, column) holding a point of ``xy``, or next to one, by loops."""
    x, y = grid.grid.x, grid.grid.y
    out = np.zeros((len(y) - 1, len(x) - 1), dtype=bool)
    for raw, lat in grid.lonlat(xy):
        lon = (raw + 180.0) % 360.0 - 180.0
        i = min(max(int(np.searchsorted(x, lon, side="right")) - 1, 0), len(x) - 2)
        j = min(max(int(np.searchsorted(y, lat, side="right")) - 1, 0), len(y) - 2)
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1):
                if 0 <= j + dj < len(y) - 1:
                    out[j + dj, (i + di) % (len(x) - 1)] = True
    return out


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count=st.integers(1, 30))
def test_the_cells_near_points_are_the_literal_ones(seed, count):
    rng = np.random.default_rng(seed)
    grid = _world_sizes(rng, 10.0)
    lonlat = np.column_stack(
        [rng.uniform(-180.0, 180.0, count), rng.uniform(-80.0, 89.0, count)]
    )
    lonlat[0, 0] = 179.9  # one next to the antimeridian
    xy = reproject(shapely.points(lonlat), "EPSG:4326", plane_crs())
    xy = shapely.get_coordinates(xy)
    np.testing.assert_array_equal(grid._cells_near(xy), _literal_cells_near(grid, xy))


def _island(lon, lat, radius, sides, rng):
    """A star-shaped island about (lon, lat), ``radius`` degrees, in the plane."""
    angle = np.sort(rng.uniform(0, 2 * np.pi, sides))
    r = radius * rng.uniform(0.5, 1.0, sides)
    ring = np.column_stack([lon + r * np.cos(angle), lat + r * np.sin(angle)])
    ring = np.vstack([ring, ring[:1]])
    plane = reproject(shapely.LineString(ring), "EPSG:4326", plane_crs())
    return shapely.get_coordinates(plane)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_sphere_boundary_nodes_are_those_of_the_whole_view(monkeypatch, seed):
    rng = np.random.default_rng(seed)
    grid = _world_sizes(rng, 5.0)
    # an ocean (a big ring round the plane's centre) and islands, one on the
    # antimeridian and one far north
    theta = np.linspace(0, 2 * np.pi, 41)
    r = 1.2e7
    ocean = np.column_stack([r * np.cos(theta), r * np.sin(theta)])
    islands = [
        _island(179.0, -10.0, 4.0, 12, rng),
        _island(20.0, 70.0, 3.0, 9, rng),
        _island(-60.0, 0.0, 6.0, 15, rng),
    ]
    rings = [[[ocean]]] + [[[isle[::-1]]] for isle in islands]
    ids = [[1]] + [[2]] * len(islands)
    cells = []
    seen = curves.add_size_view

    def spy(gmsh, size, bounds, near=None):
        data = size.view_data(bounds, near)
        cells.append(sum(len(v) for v in data.values()))
        seen(gmsh, size, bounds, near)

    monkeypatch.setattr(curves, "add_size_view", spy)
    near = boundary_nodes(rings, ids, grid)
    monkeypatch.setattr(curves, "_along", lambda *a: None)
    whole = boundary_nodes(rings, ids, grid)
    assert len(near[0]) == len(whole[0])
    for (a, pid_a), (b, pid_b) in zip(near[0], whole[0], strict=True):
        assert pid_a == pid_b
        # the same nodes; Gmsh's search over fewer cells rounds the last bit
        np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-6)
    assert cells[0] < cells[1]  # the view along the curves is smaller
