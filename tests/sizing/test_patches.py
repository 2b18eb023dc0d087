"""Fine patches of a size grid: sampling, the view Gmsh gets, cropping, meshing."""

from __future__ import annotations

import itertools

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


def _cone(cx=1000.0, cy=1000.0, radius=10.0, h=5.0, rate=0.2):
    def sizes(x, y):
        return h + rate * np.maximum(np.hypot(x - cx, y - cy) - radius, 0.0)

    return sizes


@pytest.fixture(scope="module")
def patched():
    base = _base()
    levels = site_patch(base, (990, 990, 1010, 1010), _cone(), smallest=5.0, rate=0.2)
    return base, levels, with_patches(base, levels)


def test_levels_halve_their_cells_and_nest(patched):
    base, levels, _ = patched
    steps = [float(p.x[1] - p.x[0]) for p in levels]
    assert steps == [50.0, 25.0, 12.5, 6.25, 3.125, 1.5625]
    parent = base
    for level in levels:  # each on its parent's nodes, inside it
        assert set(level.x[[0, -1]]).issubset(parent.x)
        assert set(level.y[[0, -1]]).issubset(parent.y)
        parent = level


def test_the_levels_meet_the_field_and_keep_the_gradation(patched):
    _, levels, _ = patched
    assert levels[-1].values.min() == pytest.approx(5.0)
    outer = levels[0].values
    frame = np.concatenate([outer[0], outer[-1], outer[:, 0], outer[:, -1]])
    assert np.allclose(frame, 100.0)  # on its frame the outer level is the field
    for level in levels:
        dx = float(np.diff(level.x).min())
        assert np.abs(np.diff(level.values, axis=1)).max() <= 0.2 * dx * (1 + 1e-9)
    # each level holds where its parent's cells are too coarse for the sizes
    for parent, child in itertools.pairwise(levels):
        step = float(parent.x[1] - parent.x[0])
        xx, yy = np.meshgrid(parent.x, parent.y)
        fine = parent.values < 2 * step
        inside = (
            (xx >= child.x[0])
            & (xx <= child.x[-1])
            & (yy >= child.y[0])
            & (yy <= child.y[-1])
        )
        assert inside[fine].all()


def test_sampling_takes_the_finest_level_holding_a_point(patched):
    _, levels, size = patched
    xy = np.array([[1000.0, 1000.0], [1030.0, 1000.0], [50.0, 50.0]])
    got = sample_size(size, xy)
    assert got[0] == pytest.approx(5.0)
    holding = [p for p in levels if p.x[0] <= 1030 <= p.x[-1]]
    assert got[1] == pytest.approx(sample_size(holding[-1], xy[1:2])[0])
    assert got[2] == pytest.approx(100.0)


def test_the_view_tiles_the_plane_once(patched):
    base, levels, size = patched
    bounds = (0.0, 0.0, 2000.0, 2000.0)
    cells = grid_view_data(size, bounds).reshape(-1, 16)
    area = ((cells[:, 1] - cells[:, 0]) * (cells[:, 7] - cells[:, 4])).sum()
    plain = grid_view_data(base, bounds).reshape(-1, 16)
    plain_area = ((plain[:, 1] - plain[:, 0]) * (plain[:, 7] - plain[:, 4])).sum()
    assert area == pytest.approx(plain_area)  # no gap and no overlap
    # a quadtree: far fewer cells than one grid at the finest step
    finest = levels[-1]
    assert len(cells) < 0.1 * (2000 / float(finest.x[1] - finest.x[0])) ** 2
    for level in levels:  # no cell of a level lies inside a finer level
        step = float(level.x[1] - level.x[0])
        mine = cells[np.isclose(cells[:, 1] - cells[:, 0], step)]
        for finer in levels:
            if float(finer.x[1] - finer.x[0]) < step:
                inside = (
                    (mine[:, 0] >= finer.x[0])
                    & (mine[:, 1] <= finer.x[-1])
                    & (mine[:, 4] >= finer.y[0])
                    & (mine[:, 6] <= finer.y[-1])
                )
                assert not inside.any()


def test_a_crop_cuts_the_levels_to_it_and_samples_the_same(patched):
    _, levels, size = patched
    across = crop_grid(size, (1000, 1000, 1900, 1900), margin=0)
    assert len(across.patches) == len(levels)
    for cut, level in zip(across.patches, levels, strict=True):
        assert cut.x[0] >= across.x[0] and cut.x[-1] <= across.x[-1]
        assert set(cut.x).issubset(level.x) and set(cut.y).issubset(level.y)
    rng = np.random.default_rng(0)
    xy = rng.uniform(across.x[0], across.x[-1], (500, 2))
    np.testing.assert_allclose(sample_size(across, xy), sample_size(size, xy))
    away = crop_grid(size, (1500, 1500, 1900, 1900), margin=0)
    assert len(away.patches) < len(levels)  # the finest levels are not there


def test_map_units_scale_the_levels_too(patched):
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
