"""A whole (synthetic) world meshed in parts through the stereographic plane."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from conftest import synthetic_world
from scipy.spatial import cKDTree

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import lonlat_to_xyz
from coastmesh.geometry.world import world_ocean
from coastmesh.meshing import mesh_in_parts
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.meshing.parts.cuts import expected_triangles, plan_cuts
from coastmesh.types import BoundarySegment, Domain, SizeGrid

#: 150 km on the sphere: about 37,000 triangles, room for two parts
H = 150e3


def _world() -> tuple[Domain, SphereSizeGrid]:
    ocean = world_ocean(synthetic_world(), "EPSG:4326")
    rings = [ocean.polygon.exterior, *ocean.polygon.interiors]
    segments = tuple(
        BoundarySegment(np.asarray(r.coords), "shoreline", f"coast{i}", 1)
        for i, r in enumerate(rings)
    )
    domain = Domain(ocean.polygon, segments, crs=ocean.crs)
    lon = np.linspace(-180.0, 180.0, 145)
    lat = np.linspace(-80.0, 90.0, 69)
    size = SphereSizeGrid(SizeGrid(lon, lat, np.full((69, 145), H)))
    return domain, size


@pytest.fixture(scope="module")
def meshes():
    domain, size = _world()
    whole, _ = mesh_in_parts(domain, size, mesh_crs=domain.crs, output_crs="EPSG:4326")
    parted, report = mesh_in_parts(
        domain, size, mesh_crs=domain.crs, output_crs="EPSG:4326", parts=2
    )
    return whole, parted, report


def _area(mesh) -> float:
    p = lonlat_to_xyz(mesh.points)
    a, b, c = (p[mesh.triangles[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    assert ((normal * (a + b + c)).sum(axis=1) > 0).all()  # all outward
    return 0.5 * float(np.linalg.norm(normal, axis=1).sum()) * EARTH_RADIUS**2


def test_the_world_is_cut_in_the_plane_and_meshed_as_one_surface(meshes):
    whole, parted, report = meshes
    assert report.parts >= 2 and len(report.cuts) >= 1
    # one conforming surface: every edge in one triangle (the coast) or two
    n = len(parted.points)
    e = np.sort(parted.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, count = np.unique(e[:, 0] * n + e[:, 1], return_counts=True)
    assert set(count.tolist()) <= {1, 2}
    assert (count == 1).sum() == len(parted.boundary_edges)
    # no node twice (along a cut, or across the antimeridian)
    p = lonlat_to_xyz(parted.points)
    assert len(np.unique(np.round(p, 9), axis=0)) == n
    # the same water as meshed whole, at the same size
    assert _area(parted) == pytest.approx(_area(whole), rel=2e-3)
    assert len(parted.triangles) == pytest.approx(len(whole.triangles), rel=0.05)

    # the coast is noded once for both: the same boundary nodes, but where a
    # cut meets the coast (the nearer node moves onto the meeting point)
    def coast(mesh):
        return lonlat_to_xyz(mesh.points[np.unique(mesh.boundary_edges)])

    a, b = coast(parted), coast(whole)
    assert len(a) == len(b)
    moved = cKDTree(b).query(a)[0] > 1e-9
    ends = 2 * sum(len(shapely.get_parts(c)) for c in _cut_lines(report))
    assert moved.sum() <= ends


def _cut_lines(report) -> list:
    return [shapely.LineString(c) for c in report.cuts]


def test_the_cuts_share_the_world_by_expected_triangles():
    domain, size = _world()
    water = domain.polygon
    plan = plan_cuts(water, size, 2)
    assert len(plan.cuts) == 1 and plan.missed == 0
    # the water on one side of the cut's line (a wide half-plane) against all
    line = plan.cuts[0]
    (x0, y0), (x1, y1) = np.asarray(line.coords)[[0, -1]]
    far = 10 * math.hypot(*np.ptp(shapely.get_coordinates(water), axis=0))
    d = np.array([x1 - x0, y1 - y0]) / math.hypot(x1 - x0, y1 - y0)
    a, b = np.array([x0, y0]) - far * d, np.array([x1, y1]) + far * d
    side = shapely.Polygon(
        [a, b, b + far * d[::-1] * [-1, 1], a + far * d[::-1] * [-1, 1]]
    )
    left = expected_triangles(water.intersection(side), size)
    assert 0.35 < left / expected_triangles(water, size) < 0.65
    # no grid node lies on the cut: each is on one side or the other
    x, y, _ = size.cells(shapely.box(-1e9, -1e9, 1e9, 1e9))
    assert not shapely.intersects_xy(line, x, y).any()


def test_the_parts_figure_of_the_world_is_a_lon_lat_map(meshes):
    """Meshed in the plane, drawn on a lon/lat map: the water as an image, the
    cuts curved as they run on the Earth and broken where they wrap round."""
    from coastmesh import plot

    _, _, report = meshes
    domain, _ = _world()
    figure = plot.parts_figure(domain, report, crs="EPSG:4326")
    ax = figure.axes[0]
    assert len(ax.images) == 1
    assert ax.get_xlim()[0] >= -190.0 and ax.get_xlim()[1] <= 190.0
    cuts = ax.collections[-1].get_segments()
    assert len(cuts) == len(report.cuts)
    for segment in cuts:
        drawn = np.asarray(segment)
        step = np.abs(np.diff(drawn[:, 0]))
        assert np.nanmax(step) < 180.0  # no line across the whole map
        assert len(drawn) > 100  # a curve, not its two ends
    # the coast is drawn too, every ring of it
    assert len(ax.collections[0].get_segments()) == len(domain.segments)


def test_the_domain_figure_of_the_world_is_a_lon_lat_map():
    """A domain in a world plane is drawn on a lon/lat map, its coast by id."""
    from coastmesh import plot

    domain, _ = _world()
    figure = plot.domain_figure(domain)
    ax = figure.axes[0]
    assert len(ax.images) == 1  # the water, as an image
    x0, x1 = ax.get_xlim()
    assert -190.0 <= x0 < -170.0 and 170.0 < x1 <= 190.0
    y0, y1 = ax.get_ylim()
    assert -95.0 <= y0 and y1 <= 95.0
    (coast,) = ax.collections
    assert len(coast.get_paths()) == len(domain.segments)
    broken = 0
    for path in coast.get_paths():
        # no line jumps round the Earth: a NaN vertex breaks it there (what
        # get_segments() leaves out)
        step = np.abs(np.diff(path.vertices[:, 0]))
        assert np.nanmax(step) < 180.0
        broken += int(np.isnan(step).any())
    assert broken >= 1  # the synthetic world's coast crosses the antimeridian
