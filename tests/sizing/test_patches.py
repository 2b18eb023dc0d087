"""Fine patches of a size grid: sampling, the view Gmsh gets, cropping, meshing."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from pyproj import CRS

from coastmesh.geometry.projection import sample_size, to_map_units
from coastmesh.meshing import generate_mesh
from coastmesh.meshing.gmsh.model import crop_grid, grid_view_data
from coastmesh.sizing.patches import site_patch, with_patches
from coastmesh.types import BoundarySegment, Domain, SizeGrid


def _base(step=100.0, size=2000.0, h=100.0):
    axis = np.arange(0.0, size + 1, step)
    return SizeGrid(axis, axis, np.full((len(axis), len(axis)), h))


def _spot(cx=1000.0, cy=1000.0, radius=10.0, h=5.0):
    def sizes(x, y):
        return np.where(np.hypot(x - cx, y - cy) <= radius, h, np.inf)

    return sizes


@pytest.fixture(scope="module")
def patched():
    base = _base()
    patch = site_patch(base, (990, 990, 1010, 1010), _spot(), smallest=5.0, rate=0.2)
    return base, patch, with_patches(base, [patch])


def test_a_patch_meets_the_field_and_keeps_the_gradation(patched):
    base, patch, _ = patched
    assert patch.values.min() == pytest.approx(5.0)
    # on its frame the patch is the field's
    frame = np.concatenate(
        [patch.values[0], patch.values[-1], patch.values[:, 0], patch.values[:, -1]]
    )
    assert np.allclose(frame, 100.0)
    # the gradation limit holds across the patch
    dx = np.diff(patch.x).min()
    assert np.abs(np.diff(patch.values, axis=1)).max() <= 0.2 * dx * (1 + 1e-9)
    assert set(patch.x[[0, -1]]).issubset(base.x)  # on the base's nodes


def test_sampling_takes_the_patch_inside_it_and_the_field_outside(patched):
    _, patch, size = patched
    xy = np.array([[1000.0, 1000.0], [1030.0, 1000.0], [50.0, 50.0]])
    got = sample_size(size, xy)
    assert got[0] == pytest.approx(5.0)
    assert got[1] == pytest.approx(sample_size(patch, xy[1:2])[0])
    assert got[2] == pytest.approx(100.0)


def test_the_view_tiles_the_plane_once(patched):
    base, patch, size = patched
    bounds = (0.0, 0.0, 2000.0, 2000.0)
    cells = grid_view_data(size, bounds).reshape(-1, 16)
    area = ((cells[:, 1] - cells[:, 0]) * (cells[:, 7] - cells[:, 4])).sum()
    plain = grid_view_data(base, bounds).reshape(-1, 16)
    plain_area = ((plain[:, 1] - plain[:, 0]) * (plain[:, 7] - plain[:, 4])).sum()
    assert area == pytest.approx(plain_area)  # no gap and no overlap
    assert len(cells) > len(plain)  # finer where the patch is
    # the coarse cells left are those outside the patch's frame, all of them
    fine = (cells[:, 1] - cells[:, 0]) < 5  # the patch: 2.5 m
    coarse = cells[~fine]
    inside = (
        (coarse[:, 0] >= patch.x[0])
        & (coarse[:, 1] <= patch.x[-1])
        & (coarse[:, 4] >= patch.y[0])
        & (coarse[:, 7] <= patch.y[-1])
    )
    assert not inside.any()
    assert fine.sum() == (len(patch.x) - 1) * (len(patch.y) - 1)


def test_a_crop_keeps_a_patch_whole(patched):
    _, patch, size = patched
    inside = crop_grid(size, (1200, 1200, 1900, 1900))
    assert inside.patches == () or inside.patches[0] is patch
    across = crop_grid(size, (1000, 1000, 1900, 1900), margin=0)
    assert across.patches == (patch,)
    assert across.x[0] <= patch.x[0] and across.x[-1] >= patch.x[-1]


def test_map_units_scale_the_patches_too(patched):
    _, _, size = patched
    utm = CRS.from_epsg(32630)
    shifted = SizeGrid(
        size.x + 400000,
        size.y + 6000000,
        size.values,
        patches=tuple(
            SizeGrid(p.x + 400000, p.y + 6000000, p.values) for p in size.patches
        ),
    )
    mapped = to_map_units(shifted, utm)
    k = mapped.values / shifted.values
    kp = mapped.patches[0].values / shifted.patches[0].values
    assert k.min() == pytest.approx(kp.min(), rel=1e-4)


def test_bad_patches_are_refused():
    base = _base()
    off = SizeGrid([5.0, 150.0], [0.0, 100.0], np.ones((2, 2)))
    with pytest.raises(ValueError, match="nodes of the grid"):
        with_patches(base, [off])
    a = SizeGrid([0.0, 200.0], [0.0, 200.0], np.ones((2, 2)))
    b = SizeGrid([100.0, 300.0], [100.0, 300.0], np.ones((2, 2)))
    with pytest.raises(ValueError, match="overlaps"):
        with_patches(base, [a, b])


def test_gmsh_meshes_a_spot_of_a_patch_at_its_size(patched):
    _, _, size = patched
    ring = [[0, 0], [2000, 0], [2000, 2000], [0, 2000], [0, 0]]
    domain = Domain(
        shapely.Polygon(ring),
        (BoundarySegment(ring, "open", "sea", 3),),
        crs="EPSG:32630",
    )
    mesh = generate_mesh(domain, size)
    p = mesh.points[mesh.triangles]
    edges = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).mean(axis=1)
    centre = np.hypot(*(p.mean(axis=1) - 1000.0).T)
    assert 3.5 <= np.median(edges[centre < 8]) <= 6.5  # the spot: 5 m
    assert 70 <= np.median(edges[centre > 800]) <= 125  # the field: 100 m
