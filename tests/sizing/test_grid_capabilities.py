"""What a grid says of itself, so that size terms never ask which kind it is."""

from __future__ import annotations

import numpy as np
import shapely

from coastmesh.sizing.grid import Grid, PlaneGrid, SphereGrid


def test_a_plane_grid_places_an_area_node_by_node():
    grid = PlaneGrid.from_bounds((0.0, 0.0, 1000.0, 500.0), 100.0, "EPSG:32630")
    area = shapely.Polygon([(150, 50), (750, 50), (450, 460)])
    inside = grid.nodes_in(area)
    assert inside is not None and inside.shape == grid.shape
    expected = [
        [area.contains(shapely.Point(x, y)) for x in grid.x] for y in grid.y
    ]  # one node at a time
    np.testing.assert_array_equal(inside, expected)
    assert 0 < inside.sum() < inside.size


def test_a_sphere_grid_places_no_area():
    grid = SphereGrid(10.0)
    assert grid.nodes_in(shapely.box(-20.0, -20.0, 20.0, 20.0)) is None
    assert Grid.nodes_in(grid, shapely.box(0.0, 0.0, 1.0, 1.0)) is None


def test_who_closes_water_narrower_than_the_grid():
    assert Grid.narrow_closed_by is None
    assert PlaneGrid.narrow_closed_by is None
    assert SphereGrid.narrow_closed_by == "[domain] close"
