"""Sizes on the sphere, and a mesh of a whole (synthetic) world through the plane."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from conftest import synthetic_world
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Geod, Transformer

from coastmesh.geometry.earth import EARTH_RADIUS
from coastmesh.geometry.sphere import plane_crs, stereographic_scale
from coastmesh.geometry.world import world_ocean
from coastmesh.meshing import generate_mesh
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.types import BoundarySegment, Domain, SizeGrid

SPHERE = Geod(a=EARTH_RADIUS, b=EARTH_RADIUS)


def _grid(step: float = 10.0, lat0: float = -80.0, seed: int = 0) -> SizeGrid:
    lon = np.arange(-180.0, 180.0 + step / 2, step)
    lat = np.arange(lat0, 90.0 + step / 2, step)
    rng = np.random.default_rng(seed)
    values = rng.uniform(1e4, 1e5, (len(lat), len(lon)))
    values[:, -1] = values[:, 0]  # one turn: the last column is the first
    return SizeGrid(lon, lat, values)


def _reference_sample(size: SphereSizeGrid, xy) -> list[float]:
    """One point at a time: invert the projection, find the cell, interpolate."""
    inverse = Transformer.from_crs(plane_crs(size.pole), "EPSG:4326", always_xy=True)
    lon_nodes, lat_nodes, v = size.grid.x, size.grid.y, size.grid.values
    out = []
    for x, y in xy:
        lon, lat = inverse.transform(x, y)
        while lon < lon_nodes[0]:
            lon += 360.0
        while lon >= lon_nodes[-1]:
            lon -= 360.0
        lat = min(max(lat, lat_nodes[0]), lat_nodes[-1])
        i = max(k for k in range(len(lon_nodes) - 1) if lon_nodes[k] <= lon)
        j = max([k for k in range(len(lat_nodes) - 1) if lat_nodes[k] <= lat] or [0])
        tx = (lon - lon_nodes[i]) / (lon_nodes[i + 1] - lon_nodes[i])
        ty = (lat - lat_nodes[j]) / (lat_nodes[j + 1] - lat_nodes[j])
        h = (
            (1 - tx) * (1 - ty) * v[j, i]
            + tx * (1 - ty) * v[j, i + 1]
            + (1 - tx) * ty * v[j + 1, i]
            + tx * ty * v[j + 1, i + 1]
        )
        if size.map_units:
            h *= 2.0 / (1.0 + math.sin(math.radians(lat)))  # pole at -90
        out.append(h)
    return out


@settings(max_examples=30, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-180, 179.999), st.floats(-79, 89.9)),
        min_size=1,
        max_size=20,
    ),
    st.integers(0, 5),
    st.booleans(),
)
def test_sampling_matches_the_literal_reference(points, seed, map_units):
    size = SphereSizeGrid(_grid(seed=seed), map_units=map_units)
    forward = Transformer.from_crs("EPSG:4326", plane_crs(), always_xy=True)
    xy = np.array([forward.transform(lon, lat) for lon, lat in points])
    np.testing.assert_allclose(size.sample(xy), _reference_sample(size, xy), rtol=1e-9)


def test_a_longitude_just_past_the_last_column_takes_its_values():
    # a grid may go round to within 1e-9 degrees: a longitude that wraps into
    # the gap before the first column again takes the last (the first) column's
    # values, as the grid's edge, not a linear extrapolation of the last cell
    g = _grid()
    x = g.x.copy()
    x[-1] -= 5e-10
    size = SphereSizeGrid(SizeGrid(x, g.y, g.values))
    lat = np.array([-75.0, 0.0, 42.0, 89.0])
    past = size.at_lonlat(np.full(4, 180.0 - 1e-10), lat)
    np.testing.assert_array_equal(past, size.at_lonlat(np.full(4, x[-1]), lat))
    np.testing.assert_allclose(past, size.at_lonlat(np.full(4, -180.0), lat), rtol=1e-9)


def test_a_grid_must_go_once_round():
    g = _grid()
    with pytest.raises(ValueError, match="spans exactly 360 degrees"):
        SphereSizeGrid(SizeGrid(g.x[:-1], g.y, g.values[:, :-1]))


def test_the_view_covers_the_plane_with_cells_turning_the_right_way():
    size = SphereSizeGrid(_grid()).in_map_units()
    data = size.view_data()
    quads = data["SQ"].reshape(-1, 16)
    tris = data["ST"].reshape(-1, 12)
    nx, ny = len(size.grid.x) - 1, len(size.grid.y) - 1
    assert len(quads) == nx * (ny - 1) and len(tris) == nx  # the top row: a fan
    x, y = quads[:, 0:4], quads[:, 4:8]
    twice = sum(
        x[:, k] * y[:, (k + 1) % 4] - x[:, (k + 1) % 4] * y[:, k] for k in range(4)
    )
    assert (twice > 0).all()  # counter-clockwise in the plane
    # the values are plane lengths: sphere lengths times the scale factor
    lon, lat = np.meshgrid(size.grid.x, size.grid.y)
    k = stereographic_scale(lon, lat)
    assert quads[0, 12] == pytest.approx(size.grid.values[0, 0] * k[0, 0])
    # the fan's apex is the North Pole, the plane's centre
    np.testing.assert_allclose(tris[:, 2], 0.0, atol=1e-6)
    np.testing.assert_allclose(tris[:, 5], 0.0, atol=1e-6)


def _reference_view(size: SphereSizeGrid, bounds, cells=None) -> list[list[float]]:
    """The view's quadrangles one cell at a time, each corner projected alone.

    Rows south to north, then west to east; kept when every corner is finite,
    the cell's extent meets ``bounds`` and it is not wholly beyond the reach;
    and, given ``cells`` (a set of (row, column)), when it is one of them.
    """
    forward = Transformer.from_crs("EPSG:4326", plane_crs(size.pole), always_xy=True)
    lon, lat, v = size.grid.x, size.grid.y, size.grid.values
    rows = len(lat) - 1 - int(lat[-1] >= 90.0)
    out = []
    for j in range(rows):
        for i in range(len(lon) - 1):
            if cells is not None and (j, i) not in cells:
                continue
            at = [(j, i), (j, i + 1), (j + 1, i + 1), (j + 1, i)]
            xy = [forward.transform(lon[c], lat[r]) for r, c in at]
            h = [
                v[r, c]
                * (
                    stereographic_scale(lon[c], lat[r], size.pole)
                    if size.map_units
                    else 1
                )
                for r, c in at
            ]
            x, y = [p[0] for p in xy], [p[1] for p in xy]
            if not np.isfinite(x + y + h).all():
                continue
            if (
                max(x) < bounds[0]
                or min(x) > bounds[2]
                or max(y) < bounds[1]
                or min(y) > bounds[3]
            ):
                continue
            side = max(math.dist(xy[k], xy[k - 1]) for k in range(4))
            if min(math.hypot(*q) for q in xy) - side > size.reach:
                continue
            out.append(x + y + [0.0] * 4 + h)
    return out


#: a plane's pole (lon, lat) and whether the sizes are in map units
_POLE_AND_UNITS = (st.floats(-180.0, 180.0), st.floats(-80.0, 80.0), st.booleans())


@settings(max_examples=8, deadline=None)
@given(
    *_POLE_AND_UNITS,
    st.floats(-1.2e7, 1.2e7),
    st.floats(-1.2e7, 1.2e7),
    st.floats(1e5, 1.2e7),
)
def test_the_view_is_the_literal_one_cell_by_cell(lon0, lat0, map_units, x0, y0, width):
    """Cells chosen, corners projected and values scaled as a loop over cells does."""
    size = SphereSizeGrid(_grid(step=15.0, lat0=-75.0), (lon0, lat0), map_units, 3e7)
    bounds = (x0, y0, x0 + width, y0 + width)
    got = size.view_data(bounds)["SQ"].reshape(-1, 16)
    want = np.array(_reference_view(size, bounds)).reshape(-1, 16)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-6)


def _around(size: SphereSizeGrid, points) -> set[tuple[int, int]]:
    """Literal: the cells holding each point (plane) and the 3 x 3 around it."""
    back = Transformer.from_crs(plane_crs(size.pole), "EPSG:4326", always_xy=True)
    lon, lat = size.grid.x, size.grid.y
    out = set()
    for x, y in points:
        a, b = back.transform(x, y)
        a = (a - lon[0]) % 360.0 + lon[0]
        b = min(max(b, lat[0]), lat[-1])
        i = min(max(int(np.searchsorted(lon, a, side="right")) - 1, 0), len(lon) - 2)
        j = min(max(int(np.searchsorted(lat, b, side="right")) - 1, 0), len(lat) - 2)
        for dj in (-1, 0, 1):
            for di in (-1, 0, 1):
                if 0 <= j + dj <= len(lat) - 2:
                    out.add((j + dj, (i + di) % (len(lon) - 1)))
    return out


@settings(max_examples=8, deadline=None)
@given(*_POLE_AND_UNITS, st.integers(0, 2**32 - 1))
def test_the_view_near_points_is_the_literal_and_the_whole_views_cells(
    lon0, lat0, map_units, seed
):
    """Cells near points (a boundary's samples): their corners projected alone
    give the whole grid's numbers, bit for bit, and the literal loop's cells."""
    size = SphereSizeGrid(_grid(step=15.0, lat0=-75.0), (lon0, lat0), map_units, 3e7)
    rng = np.random.default_rng(seed)
    near = rng.uniform(-1.2e7, 1.2e7, (int(rng.integers(1, 12)), 2))
    bounds = (-1.3e7, -1.3e7, 1.3e7, 1.3e7)
    got = size.view_data(bounds, near)["SQ"].reshape(-1, 16)
    want = np.array(_reference_view(size, bounds, _around(size, near)))
    np.testing.assert_allclose(got, want.reshape(-1, 16), rtol=1e-12, atol=1e-6)
    whole = {tuple(row) for row in size.view_data(bounds)["SQ"].reshape(-1, 16)}
    assert all(tuple(row) in whole for row in got)


def _quads(data) -> list[shapely.Polygon]:
    q = data["SQ"].reshape(-1, 16)
    t = data["ST"].reshape(-1, 12)
    return [shapely.Polygon(np.column_stack([r[0:4], r[4:8]])) for r in q] + [
        shapely.Polygon(np.column_stack([r[0:3], r[3:6]])) for r in t
    ]


@settings(max_examples=10, deadline=None)
@given(st.floats(-1.5e7, 1.0e7), st.floats(-1.5e7, 1.0e7), st.floats(2e5, 5e6))
def test_a_part_gets_the_cells_that_cover_it(x0, y0, width):
    """The cells kept for a part's bounds cover them (every probe in a cell),
    and each meets them: a literal check, cell by cell."""
    size = SphereSizeGrid(_grid(step=10.0, lat0=-80.0)).in_map_units()
    bounds = (x0, y0, x0 + width, y0 + width)
    kept = _quads(size.view_data(bounds))
    every = _quads(size.view_data())
    want = [
        c
        for c in every
        if c.bounds[0] <= bounds[2]
        and c.bounds[2] >= bounds[0]
        and c.bounds[1] <= bounds[3]
        and c.bounds[3] >= bounds[1]
    ]
    assert len(kept) == len(want)
    rng = np.random.default_rng(0)
    probes = rng.uniform(bounds[:2], bounds[2:], (50, 2))
    covered = shapely.union_all(every).buffer(1.0)
    cover = shapely.union_all(kept).buffer(1.0)
    for x, y in probes:
        if covered.contains(shapely.Point(x, y)):  # inside the grid at all
            assert cover.contains(shapely.Point(x, y))


def test_cells_at_the_pole_and_beyond_the_water_are_left_out():
    """A pole on a grid node (103 E, 46 N) puts that node at infinity: no cell
    with it goes to Gmsh, nor any cell wholly beyond the water's reach (a view of
    them took Gmsh over 24 GB)."""
    lon = np.linspace(-180.0, 180.0, 361)
    lat = np.linspace(-90.0, 90.0, 181)
    values = np.full((181, 361), 1e5)
    whole = SphereSizeGrid(SizeGrid(lon, lat, values), pole=(103.0, 46.0))
    data = whole.in_map_units().view_data()
    assert all(np.isfinite(d).all() for d in data.values())
    reach = 3e7
    near = SphereSizeGrid(SizeGrid(lon, lat, values), (103.0, 46.0), reach=reach)
    kept = near.in_map_units().view_data()["SQ"].reshape(-1, 16)
    every = data["SQ"].reshape(-1, 16)
    assert 0 < len(kept) < len(every)
    for cells, inside in ((kept, True), (every, None)):
        r = np.hypot(cells[:, 0:4], cells[:, 4:8])
        side = np.hypot(
            np.diff(cells[:, 0:4], append=cells[:, :1], axis=1),
            np.diff(cells[:, 4:8], append=cells[:, 4:5], axis=1),
        ).max(axis=1)
        nearest = r.min(axis=1) - side
        if inside:
            assert (nearest <= reach).all()
        else:  # those left out were all beyond it
            assert (nearest <= reach).sum() == len(kept)


def test_the_cells_weigh_the_sphere():
    lon = np.linspace(-180.0, 180.0, 361)
    lat = np.linspace(-90.0, 90.0, 181)
    size = SphereSizeGrid(SizeGrid(lon, lat, np.ones((181, 361))), pole=(0.0, -90.0))
    everything = shapely.box(-1e10, -1e10, 1e10, 1e10)
    _, _, weight = size.cells(everything)
    # the South Pole row goes to infinity in the plane: its weight is cos(-90) = 0
    assert weight.sum() == pytest.approx(4 * math.pi * EARTH_RADIUS**2, rel=1e-4)


def test_the_cells_of_a_part_are_its_nodes_on_any_number_of_threads():
    lon = np.linspace(-180.0, 180.0, 721)
    lat = np.linspace(-90.0, 90.0, 361)
    size = SphereSizeGrid(SizeGrid(lon, lat, np.ones((361, 721))), pole=(0.0, -90.0))
    part = shapely.Point(3e6, -2e6).buffer(12e6)  # the nodes in its box are asked
    one, two = size.cells(part), size.cells(part, threads=2)
    assert len(one[0]) > 100_000  # two chunks of over 50,000
    for a, b in zip(one, two, strict=True):
        assert np.array_equal(a, b)
    # every node of the grid asked, on one thread: as many, the same
    glon, glat = np.meshgrid(lon[:-1], lat)
    to_plane = Transformer.from_crs(
        "EPSG:4326", plane_crs((0.0, -90.0)), always_xy=True
    )
    px, py = to_plane.transform(glon, glat)
    literal = shapely.contains_xy(part, px, py)
    assert np.array_equal(one[0], px[literal])


# --- a whole world, meshed --------------------------------------------------


@pytest.fixture(scope="module")
def world_mesh():
    land = synthetic_world()
    ocean = world_ocean(land, "EPSG:4326")
    rings = [ocean.polygon.exterior, *ocean.polygon.interiors]
    segments = tuple(
        BoundarySegment(np.asarray(r.coords), "shoreline", f"coast{i}", 1)
        for i, r in enumerate(rings)
    )
    domain = Domain(ocean.polygon, segments, crs=ocean.crs)
    lon = np.linspace(-180.0, 180.0, 73)
    lat = np.linspace(-80.0, 90.0, 35)
    size = SphereSizeGrid(SizeGrid(lon, lat, np.full((35, 73), 600e3)))
    mesh = generate_mesh(domain, size, mesh_crs=ocean.crs, output_crs="EPSG:4326")
    return land, ocean, mesh


def _xyz(lonlat: np.ndarray) -> np.ndarray:
    lon, lat = np.radians(lonlat).T
    return np.column_stack(
        [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]
    )


def test_the_world_mesh_is_one_surface_on_the_sphere(world_mesh):
    land, ocean, mesh = world_mesh
    assert ocean.joined == 2 and ocean.islands == 3
    lon = mesh.points[:, 0]
    assert (lon >= -180.0).all() and (lon <= 180.0).all()
    p = _xyz(mesh.points)
    a, b, c = (p[mesh.triangles[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    # every triangle turns counter-clockwise seen from outside the sphere
    assert ((normal * (a + b + c)).sum(axis=1) > 0).all()
    # some cross the antimeridian, and are whole on the sphere all the same
    span = np.ptp(mesh.points[mesh.triangles, 0], axis=1)
    assert (span > 180.0).sum() >= 3
    # no duplicate nodes (along the dateline or anywhere)
    assert len(np.unique(np.round(p, 9), axis=0)) == len(p)
    # the mesh's area (flat triangles) is the ocean's on the sphere, less the
    # chords' sag (about h^2 / 12 R^2 of it)
    area = 0.5 * np.linalg.norm(normal, axis=1).sum() * EARTH_RADIUS**2
    land_area = sum(
        abs(SPHERE.geometry_area_perimeter(shapely.Polygon(g.exterior))[0])
        for g in land
    )
    want = 4 * math.pi * EARTH_RADIUS**2 - land_area
    assert area == pytest.approx(want, rel=0.01)
    assert area < want


def test_the_world_mesh_is_well_shaped_on_the_sphere(world_mesh):
    _, _, mesh = world_mesh
    p = _xyz(mesh.points)
    angles = []
    for k in range(3):
        a, b, c = (p[mesh.triangles[:, (k + j) % 3]] for j in range(3))
        u, v = b - a, c - a
        cos = (
            (u * v).sum(axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        )
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    smallest = np.min(angles, axis=0)
    assert np.percentile(smallest, 1) >= 30.0
    # edges follow the 600 km size on the sphere, wherever k is in the plane
    edges = np.linalg.norm(p[mesh.triangles[:, 0]] - p[mesh.triangles[:, 1]], axis=1)
    median = float(np.median(edges)) * EARTH_RADIUS
    assert 450e3 < median < 750e3
