"""Boundary rings and strings: every tagged edge once, in order, domain on the left."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from coastmesh.errors import FormatError
from coastmesh.types import Mesh
from coastmesh.types.topology import boundary_rings, boundary_strings


def test_rings_cover_every_boundary_edge_once(mesh_with_islands):
    mesh = mesh_with_islands
    rings = boundary_rings(mesh)
    assert len(rings) == 3 and rings[0].exterior and not rings[1].exterior
    got = {}
    for ring in rings:
        for a, b, pid in zip(
            ring.nodes, np.roll(ring.nodes, -1), ring.ids, strict=True
        ):
            got[(min(a, b), max(a, b))] = pid
    want = {
        (min(a, b), max(a, b)): pid
        for (a, b), pid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True)
    }
    assert got == want


def test_domain_is_on_the_left(mesh_with_islands):
    rings = boundary_rings(mesh_with_islands)
    for ring in rings:
        area = shapely.Polygon(mesh_with_islands.points[ring.nodes]).area
        signed = shapely.LinearRing(mesh_with_islands.points[ring.nodes]).is_ccw
        assert area > 0
        assert signed == ring.exterior  # exterior ccw, islands cw


def test_strings_split_where_the_id_changes(mesh_with_islands):
    strings = boundary_strings(mesh_with_islands)
    ids = sorted(s.physical_id for s in strings)
    assert ids == [1, 1, 2, 3]
    south = next(s for s in strings if s.physical_id == 2)
    xy = mesh_with_islands.points[south.nodes]
    assert not south.closed and south.exterior
    np.testing.assert_allclose(xy[:, 1], 0.0, atol=1e-6)
    assert np.all(np.diff(xy[:, 0]) > 0)  # west to east: domain (north) on the left
    rock = next(s for s in strings if s.physical_id == 3)
    assert rock.closed and not rock.exterior
    exterior = [s for s in strings if s.exterior]
    assert exterior[0].nodes[-1] == exterior[1].nodes[0]  # they share end nodes


def test_untagged_boundary_is_refused():
    m = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1], [1, 2]], [1, 1], 1, None)
    with pytest.raises(FormatError, match="not its 3 boundary edges"):
        boundary_rings(m)
