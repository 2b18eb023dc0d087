"""The nodes whose sizes are held: every corner of their size-grid cell flagged."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer

from coastmesh.case.pipeline.mesh import grid_flags
from coastmesh.sizing.grid import PlaneGrid
from coastmesh.types import Mesh


def _flags_loop(x, y, flags, points):
    """Literal: a point's cell (clamped to the grid); its weighted corners all set."""
    out = []
    for qx, qy in points.tolist():
        px = min(max(qx, x[0]), x[-1])
        py = min(max(qy, y[0]), y[-1])
        i = min(int(np.searchsorted(x, px, side="right")) - 1, len(x) - 2)
        j = min(int(np.searchsorted(y, py, side="right")) - 1, len(y) - 2)
        # the corners with a bilinear weight (none across a grid line)
        tx = (px - x[i]) / (x[i + 1] - x[i])
        ty = (py - y[j]) / (y[j + 1] - y[j])
        weights = {
            (j, i): (1 - tx) * (1 - ty),
            (j, i + 1): tx * (1 - ty),
            (j + 1, i): (1 - tx) * ty,
            (j + 1, i + 1): tx * ty,
        }
        corners = [c for c, w in weights.items() if w > 0]
        out.append(all(flags[c] for c in corners))
    return np.array(out)


def _mesh(points, crs):
    tri = np.array([[0, 1, 2]])
    return Mesh(points, tri, [[0, 1], [1, 2], [2, 0]], [1, 1, 1], 1, crs)


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(0.1, 0.9))
def test_grid_flags_is_the_literal_cell_test(seed, share):
    rng = np.random.default_rng(seed)
    x = 500_000.0 + np.arange(7) * 100.0
    y = 6_500_000.0 + np.arange(6) * 100.0
    grid = PlaneGrid(x, y, "EPSG:32630", 100.0)
    flags = rng.random(grid.shape) < share
    points = np.column_stack(
        [rng.uniform(x[0] - 50, x[-1] + 50, 60), rng.uniform(y[0] - 50, y[-1] + 50, 60)]
    )
    # the mesh in lon/lat: its points are moved into the grid's CRS first
    lonlat = np.column_stack(
        Transformer.from_crs("EPSG:32630", "EPSG:4326", always_xy=True).transform(
            *points.T
        )
    )
    got = grid_flags(grid, flags, _mesh(lonlat, "EPSG:4326"))
    back = np.column_stack(
        Transformer.from_crs("EPSG:4326", "EPSG:32630", always_xy=True).transform(
            *lonlat.T
        )
    )
    np.testing.assert_array_equal(got, _flags_loop(x, y, flags, back))
