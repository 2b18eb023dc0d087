"""The core types of meshing: BoundarySegment, Domain, SizeGrid, Mesh."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

OUTER = np.array([[0, 0], [10000, 0], [10000, 10000], [0, 10000], [0, 0]], float)
ISLAND = np.array(
    [[4000, 4000], [4000, 6000], [6000, 6000], [6000, 4000], [4000, 4000]], float
)


def test_domain_refuses_segments_that_do_not_cover_the_rings():
    polygon = shapely.Polygon(OUTER, [ISLAND])
    sides = tuple(BoundarySegment(OUTER[i : i + 2], "open", "s", 1) for i in range(4))
    with pytest.raises(ValueError, match=r"[12] closed rings"):
        Domain(polygon, sides, crs="EPSG:32630")
    with pytest.raises(ValueError, match="does not close"):
        Domain(polygon, sides[:2] + sides[3:], crs="EPSG:32630")
    shifted = BoundarySegment(ISLAND + 100, "shoreline", "i", 5)
    with pytest.raises(ValueError, match="differ"):
        Domain(polygon, sides + (shifted,), crs="EPSG:32630")


def test_domain_takes_segments_that_cover_the_rings_with_other_vertices():
    # the same rings, the island traced the other way from another corner,
    # and the sea's south side with an extra vertex midway: the same polygon
    # (topologically), though not vertex for vertex
    polygon = shapely.Polygon(OUTER, [ISLAND])
    south = np.array([[0, 0], [5000, 0], [10000, 0]], float)
    sides = (BoundarySegment(south, "open", "s", 1),) + tuple(
        BoundarySegment(OUTER[i : i + 2], "open", f"s{i}", 2) for i in range(1, 4)
    )
    island = BoundarySegment(np.roll(ISLAND[:-1], 2, axis=0)[::-1], "shoreline", "i", 5)
    island = BoundarySegment(
        np.vstack([island.coords, island.coords[:1]]), "shoreline", "i", 5
    )
    domain = Domain(polygon, sides + (island,), crs="EPSG:32630")
    assert len(domain.rings()) == 2
    # and vertex for vertex (the fast check) too
    exact = tuple(
        BoundarySegment(OUTER[i : i + 2], "open", f"s{i}", 2) for i in range(4)
    ) + (BoundarySegment(ISLAND, "shoreline", "i", 5),)
    assert len(Domain(polygon, exact, crs="EPSG:32630").rings()) == 2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"coords": [[0, 0]]}, "shape"),
        ({"kind": "river"}, "kind"),
        ({"physical_id": 0}, "physical_id"),
    ],
)
def test_boundary_segment_checks(kwargs, match):
    args = {"coords": [[0, 0], [1, 1]], "kind": "open", "name": "s", "physical_id": 1}
    with pytest.raises(ValueError, match=match):
        BoundarySegment(**(args | kwargs))


def test_mesh_and_size_grid_checks():
    with pytest.raises(ValueError, match=r"indices in \[0, 3\]"):
        Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 3]], [[0, 1]], [1], 1, None)
    with pytest.raises(ValueError, match="boundary_ids has 2 values"):
        Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [[0, 1]], [1, 1], 1, None)
    with pytest.raises(ValueError, match="point_data"):
        Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, None, {"d": [1.0]})
    with pytest.raises(ValueError, match="values has shape"):
        SizeGrid([0, 1], [0, 1, 2], np.ones((2, 2)))
    with pytest.raises(ValueError, match="ascending"):
        SizeGrid([1, 0], [0, 1], np.ones((2, 2)))
    with pytest.raises(ValueError, match="> 0"):
        SizeGrid([0, 1], [0, 1], np.zeros((2, 2)))


def test_mesh_converts_and_keeps_its_inputs():
    points = [[0, 0], [1, 0], [0, 1]]
    mesh = Mesh(
        points,
        [[0, 1, 2]],
        [[0, 1]],
        [3],
        1,
        "EPSG:32630",
        {"depth": [1, 2, 3]},
        {3: "sea"},
        {3: "open"},
    )
    assert mesh.points.dtype == np.float64 and mesh.triangles.dtype == np.int64
    assert mesh.crs.to_epsg() == 32630 and mesh.boundary_names == {3: "sea"}
    with pytest.raises(ValueError, match="boundary_kinds"):
        Mesh(points, [[0, 1, 2]], [[0, 1]], [3], 1, None, boundary_kinds={3: "river"})
    with pytest.raises(ValueError, match="surface_id"):
        Mesh(points, [[0, 1, 2]], [], [], 0, None)
    richer = mesh.with_point_data(size=[5.0, 5.0, 5.0])
    assert (
        sorted(richer.point_data) == ["depth", "size"] and "size" not in mesh.point_data
    )


def test_size_grid_from_a_dataarray():
    import xarray as xr

    field = xr.DataArray(
        np.ones((2, 3)), dims=("y", "x"), coords={"y": [0.0, 1.0], "x": [0.0, 1.0, 2.0]}
    )
    assert SizeGrid.from_dataarray(field).values.shape == (2, 3)
    with pytest.raises(ValueError, match="dims"):
        SizeGrid.from_dataarray(field.transpose())
