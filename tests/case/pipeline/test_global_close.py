"""A region set's closing runs only near its regions; elsewhere its land is kept."""

from __future__ import annotations

import numpy as np
import shapely

from coastmesh.case.pipeline.world import _close


def test_closing_only_near_the_zone():
    # two pairs of squares 2 km apart (in a plane near its centre, k ~ 1): one
    # pair in the zone, one 3000 km away
    near = [shapely.box(0, 0, 100e3, 100e3), shapely.box(102e3, 0, 200e3, 100e3)]
    far = [shapely.box(3e6, 0, 3.1e6, 1e5), shapely.box(3.102e6, 0, 3.2e6, 1e5)]
    land = np.array(near + far, dtype=object)
    zone = shapely.box(-50e3, -50e3, 250e3, 150e3)
    closed, merged = _close(land, 5e3, 1e8, zone)
    union = shapely.union_all(closed)
    assert union.contains(shapely.Point(101e3, 50e3))  # the gap in the zone closed
    assert not union.contains(shapely.Point(3.101e6, 5e4))  # the far gap kept
    assert merged >= 1
    # the far land is exactly as it was (100 x 100 km and 98 x 100 km)
    outside = shapely.difference(union, zone.buffer(50e3))
    assert np.isclose(outside.area, 1.98e10, rtol=1e-12)
    everywhere, _ = _close(land, 5e3, 1e8, None)
    assert shapely.union_all(everywhere).contains(shapely.Point(3.101e6, 5e4))
