"""``SizeCase.sites``: the grid's nodes in the ``[[sites]]``, as the grid says."""

from __future__ import annotations

import numpy as np
import shapely

from coastmesh.case.terms.base import SizeCase, SizeTables
from coastmesh.sizing.grid import PlaneGrid, SphereGrid
from coastmesh.types import BoundarySegment, Domain


def test_sites_are_the_grid_s_nodes_in_them():
    ring = [(0, 0), (20000, 0), (20000, 20000), (0, 20000)]
    coast = BoundarySegment([*ring, ring[0]], "shoreline", "coast", 1)
    domain = Domain(shapely.Polygon(ring), (coast,), crs="EPSG:32630")
    site = shapely.box(5000.0, 5000.0, 9000.0, 12000.0)
    case = SizeCase(
        SizeTables(None), domain, 100.0, read_depth=lambda part: None, site_area=site
    )
    plane = PlaneGrid.from_bounds(domain.polygon.bounds, 1000.0, "EPSG:32630")
    np.testing.assert_array_equal(case.sites(plane), plane.nodes_in(site))
    assert case.sites(plane).sum() == 3 * 6  # nodes strictly inside the box
    assert case.sites(SphereGrid(10.0)) is None
    no_sites = SizeCase(SizeTables(None), domain, 100.0, read_depth=lambda part: None)
    assert no_sites.sites(plane) is None
