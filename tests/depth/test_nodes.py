"""Depth at mesh nodes against independent interpolation and brute force."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from conftest import one_triangle
from pyproj import Geod
from scipy.interpolate import RegularGridInterpolator

from coastmesh.data import path as data_path
from coastmesh.depth.nodes import CoarseRasterWarning, depth_at_nodes, limit_slope
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io import read_raster
from coastmesh.meshing import generate_mesh
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

GEOD = Geod(ellps="WGS84")


@pytest.fixture(scope="module")
def orkney_mesh():
    """A lon/lat mesh of a box west of Orkney, partly outside the ETOPO grid."""
    ring = [[-8.3, 58.0], [-5.0, 58.0], [-5.0, 59.5], [-8.3, 59.5], [-8.3, 58.0]]
    import shapely

    domain = Domain(
        shapely.Polygon(ring), (BoundarySegment(ring, "open", "b", 2),), "EPSG:4326"
    )
    grid = SizeGrid(
        np.linspace(-300e3, 300e3, 3),
        np.linspace(6.3e6, 6.7e6, 3),
        np.full((3, 3), 8e3),
    )
    return generate_mesh(domain, grid, mesh_crs="EPSG:32629")


@pytest.fixture(scope="module")
def etopo():
    return read_raster(data_path("etopo1_0.1deg_orkney_wide.tif"))


def test_bilinear_matches_scipy(orkney_mesh, etopo):
    # land = "keep": plain bilinear interpolation, land heights and all
    depth, report = depth_at_nodes(orkney_mesh, etopo, outside="nearest", land="keep")
    r = etopo.sortby("y")
    interp = RegularGridInterpolator(
        (r.y.values, r.x.values), r.values, bounds_error=False, fill_value=np.nan
    )
    lon, lat = orkney_mesh.points.T
    expected = -interp(np.column_stack([lat, lon]))
    inside = np.isfinite(expected)
    assert inside.sum() > 100 and (~inside).sum() > 10  # some nodes lie west of -8.05
    np.testing.assert_allclose(depth[inside], expected[inside], atol=1e-9)
    assert report.nearest + report.snapped == int((~inside).sum())
    assert report.snapped > 0 and report.nearest > 0  # within a cell, and beyond
    data = report.to_dict()
    assert data["nodes"] == len(depth) and data["method"] == "bilinear"
    assert data["min"] == depth.min() and data["max"] == depth.max()
    assert f"{report.nearest:,} outside every source" in report.summary()


def test_outside_nodes_take_the_nearest_valid_cell(orkney_mesh, etopo):
    depth, _ = depth_at_nodes(orkney_mesh, etopo, outside="nearest")
    r = etopo.sortby("y")
    lon, lat = orkney_mesh.points.T
    outside = lon < r.x.values[0]
    gx, gy = np.meshgrid(r.x.values, r.y.values)
    for k in np.flatnonzero(outside)[:20]:  # brute force: geodesic to every cell
        _, _, d = GEOD.inv(
            np.full(gx.size, lon[k]), np.full(gx.size, lat[k]), gx.ravel(), gy.ravel()
        )
        assert depth[k] == pytest.approx(-r.values.ravel()[np.argmin(d)])


def test_nodata_cells_are_avoided(orkney_mesh, etopo):
    holed = etopo.copy()
    holed.values[20:30, 10:25] = np.nan
    depth, report = depth_at_nodes(orkney_mesh, holed, outside="nearest")
    assert np.isfinite(depth).all()
    _, clean_report = depth_at_nodes(orkney_mesh, etopo, outside="nearest")
    assert report.nearest + report.snapped > clean_report.nearest + clean_report.snapped


def test_mean_method_averages_cells_like_a_loop(orkney_mesh):
    # a fine raster (0.01 deg) under an ~8 km mesh: means over several cells
    x = np.arange(-8.5, -4.8, 0.01)
    y = np.arange(57.8, 59.7, 0.01)
    rng = np.random.default_rng(3)
    values = -50 - 30 * np.sin(x)[None, :] * np.cos(3 * y)[:, None]
    values = values + rng.normal(0, 5, values.shape)
    raster = xr.DataArray(
        values, dims=("y", "x"), coords={"y": y, "x": x}, attrs={"crs": "EPSG:4326"}
    )
    depth, report = depth_at_nodes(orkney_mesh, raster, method="mean")
    assert report.averaged == len(depth)
    from coastmesh.depth.nodes import _node_radius

    radius = _node_radius(orkney_mesh)
    for k in range(0, len(depth), max(1, len(depth) // 25)):
        lon, lat = orkney_mesh.points[k]
        half_y = radius[k] / 111_195.08
        half_x = half_y / np.cos(np.radians(lat))
        ci, cj = np.argmin(abs(x - lon)), np.argmin(abs(y - lat))
        kx, ky = int(half_x // 0.01), int(half_y // 0.01)
        cells = [
            values[j, i]
            for j in range(max(cj - ky, 0), min(cj + ky + 1, len(y)))
            for i in range(max(ci - kx, 0), min(ci + kx + 1, len(x)))
        ]
        assert depth[k] == pytest.approx(-np.mean(cells), abs=1e-6)


def test_min_depth_and_sign(orkney_mesh, etopo):
    depth, _ = depth_at_nodes(orkney_mesh, etopo, outside="nearest")
    floored, report = depth_at_nodes(
        orkney_mesh, etopo, min_depth=150.0, outside="nearest"
    )
    assert floored.min() == 150.0
    assert report.below_min_depth == int((depth < 150).sum()) > 0
    down, _ = depth_at_nodes(
        orkney_mesh,
        -etopo.assign_attrs(etopo.attrs),
        positive="down",
        outside="nearest",
    )
    np.testing.assert_allclose(down, depth)


def test_slope_limit_against_all_pairs_shortest_paths():
    from scipy.sparse.csgraph import shortest_path

    rng = np.random.default_rng(0)
    n = 7
    xs, ys = np.meshgrid(np.arange(n) * 1000.0, np.arange(n) * 1000.0)
    pts = np.column_stack([xs.ravel(), ys.ravel()]) + rng.normal(0, 100, (n * n, 2))
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    tri = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(
        -1, 3
    )
    edges = np.concatenate(
        [
            np.stack([idx[0, :-1], idx[0, 1:]], 1),
            np.stack([idx[:-1, -1], idx[1:, -1]], 1),
            np.stack([idx[-1, 1:], idx[-1, :-1]], 1),
            np.stack([idx[1:, 0], idx[:-1, 0]], 1),
        ]
    )
    mesh = Mesh(pts, tri, edges, np.ones(len(edges), int), 1, "EPSG:32630")
    depth = rng.uniform(0, 400, n * n)
    limited = limit_slope(mesh, depth, 0.05)
    # reference: min over all nodes q of depth(q) + s * graph distance(q, p)
    from scipy.sparse import coo_matrix

    from coastmesh.depth.nodes import _edges_on_earth

    e, length = _edges_on_earth(mesh)
    graph = coo_matrix((length, (e[:, 0], e[:, 1])), shape=(n * n, n * n))
    dist = shortest_path(graph, directed=False)
    expected = (depth[:, None] + 0.05 * dist).min(axis=0)
    np.testing.assert_allclose(limited, expected, rtol=1e-12)
    assert np.all(np.abs(limited[e[:, 0]] - limited[e[:, 1]]) <= 0.05 * length + 1e-9)


def test_errors():
    m = one_triangle()
    r = xr.DataArray(
        np.zeros((2, 2)),
        dims=("y", "x"),
        coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
        attrs={"crs": "EPSG:4326"},
    )
    with pytest.raises(ConfigError, match="no CRS"):
        depth_at_nodes(m, r)
    with pytest.raises(ConfigError, match="method = 'cubic'"):
        depth_at_nodes(m, r, method="cubic")
    with pytest.raises(ConfigError, match="outside = 'far'"):
        depth_at_nodes(m, r, outside="far")
    with pytest.raises(ConfigError, match="land = 'dry'"):
        depth_at_nodes(m, r, land="dry")
    with pytest.raises(ConfigError, match="give min_depth"):
        depth_at_nodes(m, r, land="smooth", land_distance=100.0)
    with pytest.raises(ConfigError, match="land_distance = None"):
        depth_at_nodes(m, r, land="smooth", min_depth=2.0)
    with pytest.raises(ConfigError, match="max_slope = -1"):
        limit_slope(m, np.zeros(3), -1)


def _grid_mesh(lon0, lon1, lat0, lat1, n=40):
    """A triangulated lon/lat box: its west side is coast (id 1), the rest sea."""
    from scipy.spatial import Delaunay

    gx, gy = np.meshgrid(np.linspace(lon0, lon1, n), np.linspace(lat0, lat1, n))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    tri = Delaunay(pts).simplices
    idx = np.arange(n * n).reshape(n, n)
    west = np.stack([idx[1:, 0], idx[:-1, 0]], 1)
    rest = np.concatenate(
        [
            np.stack([idx[0, :-1], idx[0, 1:]], 1),
            np.stack([idx[:-1, -1], idx[1:, -1]], 1),
            np.stack([idx[-1, 1:], idx[-1, :-1]], 1),
        ]
    )
    edges = np.concatenate([west, rest])
    ids = np.r_[np.ones(len(west), int), np.full(len(rest), 2)]
    return Mesh(
        pts, tri, edges, ids, 1, "EPSG:4326",
        boundary_kinds={1: "shoreline", 2: "open"},
    )  # fmt: skip


def test_land_nodes_take_the_nearest_wet_cell(etopo):
    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)  # over mainland Orkney
    plain, report = depth_at_nodes(mesh, etopo, land="keep")
    land = plain <= 0
    assert report.land == int(land.sum()) > 20
    sea, report = depth_at_nodes(mesh, etopo, land="nearest_sea")
    assert report.land_treatment == "nearest_sea"
    np.testing.assert_array_equal(sea[~land], plain[~land])
    r = etopo.sortby("y")
    gx, gy = np.meshgrid(r.x.values, r.y.values)
    wet = r.values.ravel() < 0
    lon, lat = mesh.points.T
    for k in np.flatnonzero(land)[:15]:  # brute force: geodesic to every wet cell
        _, _, d = GEOD.inv(
            np.full(wet.sum(), lon[k]),
            np.full(wet.sum(), lat[k]),
            gx.ravel()[wet],
            gy.ravel()[wet],
        )
        assert sea[k] == pytest.approx(-r.values.ravel()[wet][np.argmin(d)])
    assert (sea > 0).all()


def test_smooth_land_tapers_to_min_depth_at_the_coast(etopo):
    from coastmesh.geometry.earth import earth_centred

    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)
    sea, _ = depth_at_nodes(mesh, etopo, land="nearest_sea")
    width = 10e3
    smooth, report = depth_at_nodes(
        mesh, etopo, land="smooth", land_distance=width, min_depth=2.0
    )
    xyz = earth_centred(mesh.points, mesh.crs)
    coast = np.unique(mesh.boundary_edges[mesh.boundary_ids == 1])
    d = np.linalg.norm(xyz[:, None, :] - xyz[None, coast, :], axis=2).min(axis=1)
    expected = np.where(
        (d < width) & (sea > 2.0), 2.0 + (sea - 2.0) * d / width, np.maximum(sea, 2.0)
    )
    np.testing.assert_allclose(smooth, expected, rtol=1e-12)
    assert smooth[coast].max() == 2.0
    assert report.tapered == int(((d < width) & (sea > 2.0)).sum()) > 50


def test_the_summary_gives_the_share_at_min_depth_then_its_causes(etopo):
    # "smooth" tapers the coast nodes to min_depth exactly: more nodes end at
    # the floor than were raised to it, and the summary gives the former
    from coastmesh.geometry.earth import earth_centred

    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)
    plain, _ = depth_at_nodes(mesh, etopo, land="keep")
    sea, _ = depth_at_nodes(mesh, etopo, land="nearest_sea")
    depth, report = depth_at_nodes(
        mesh, etopo, land="smooth", land_distance=10e3, min_depth=2.0
    )
    at_floor = depth == 2.0
    n = len(depth)
    assert report.min_depth == 2.0
    assert report.at_min_depth == int(at_floor.sum())
    assert report.at_min_depth > report.below_min_depth > 0  # the counts differ
    causes = report.at_min_depth_causes
    assert sum(causes.values()) == report.at_min_depth
    assert causes["raised"] + causes["raised_on_land"] == report.below_min_depth
    # tapered to the floor: the coast nodes whose nearest wet cell is deeper
    xyz = earth_centred(mesh.points, mesh.crs)
    coast = np.unique(mesh.boundary_edges[mesh.boundary_ids == 1])
    d = np.linalg.norm(xyz[:, None, :] - xyz[None, coast, :], axis=2).min(axis=1)
    assert causes["tapered"] == int(((d == 0) & (sea > 2.0)).sum()) > 0
    raised = at_floor & ~((d < 10e3) & (sea > 2.0))
    assert causes["raised_on_land"] == int((raised & (plain <= 0)).sum()) > 0
    assert causes["raised"] == int((raised & (plain > 0)).sum()) > 0
    assert causes["rasters"] == 0
    text = report.summary()
    share = f"{report.at_min_depth:,} ({report.at_min_depth / n:.1%})"
    assert f"; {share} at min_depth 2 m, by cause: " in text
    raised_share = f"{causes['raised']:,} ({causes['raised'] / n:.1%})"
    assert f"by cause: {raised_share} raised from shallower sea depths, " in text
    assert f"{causes['tapered']:,} (" in text and "tapered to it at the coast" in text
    assert "raised to the minimum depth" not in text
    data = report.to_dict()
    assert data["at_min_depth"] == report.at_min_depth and data["min_depth"] == 2.0
    assert data["at_min_depth_causes"] == causes
    # without a floor, the summary says so and counts nothing
    _, bare = depth_at_nodes(mesh, etopo, land="nearest_sea")
    assert bare.at_min_depth == 0 and bare.at_min_depth_causes == {}
    assert "; no min_depth; " in bare.summary()


def test_wet_rule_never_gives_a_sea_node_a_land_value(etopo):
    # the default: nodes beside land cells read the wet cells alone; nodes with
    # no wet cell around take the nearest wet cell (brute force below)
    from reference import bilinear_wet_loop

    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)  # over mainland Orkney
    plain, _ = depth_at_nodes(mesh, etopo, land="keep")
    depth, report = depth_at_nodes(mesh, etopo)
    assert report.land_treatment == "wet" and report.land_values == 0
    r = etopo.sortby("y")
    lon, lat = mesh.points.T
    expected = bilinear_wet_loop(r.x.values, r.y.values, -r.values, lon, lat)
    around = expected > 0
    np.testing.assert_allclose(depth[around], expected[around], rtol=1e-12)
    assert report.coast_cells == int((around & (expected != plain)).sum()) > 10
    none = expected == 0
    assert report.took_wet == int(none.sum()) > 5
    gx, gy = np.meshgrid(r.x.values, r.y.values)
    wet = r.values.ravel() < 0
    for k in np.flatnonzero(none)[:10]:
        _, _, d = GEOD.inv(
            np.full(wet.sum(), lon[k]), np.full(wet.sum(), lat[k]),
            gx.ravel()[wet], gy.ravel()[wet],
        )  # fmt: skip
        assert depth[k] == pytest.approx(-r.values.ravel()[wet][np.argmin(d)])
    assert (depth > 0).all()
    # the old default kept land heights where no min_depth was given
    _, old = depth_at_nodes(mesh, etopo, land="min_depth")
    beside = (plain <= 0) | (around & (expected != plain))
    assert old.land_values == int(beside.sum()) > report.coast_cells


def test_wet_rule_tapers_to_min_depth_across_the_land_strip_only(etopo):
    from coastmesh.geometry.earth import earth_centred

    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)
    untapered, _ = depth_at_nodes(mesh, etopo)
    depth, report = depth_at_nodes(mesh, etopo, min_depth=2.0)
    r = etopo.sortby("y")
    lon, lat = mesh.points.T
    from reference import bilinear_wet_loop

    strip = bilinear_wet_loop(r.x.values, r.y.values, -r.values, lon, lat) == 0
    # off the strip: the raster's own (wet) depths, floored
    np.testing.assert_array_equal(depth[~strip], np.maximum(untapered[~strip], 2.0))
    xyz = earth_centred(mesh.points, mesh.crs)
    coast = np.unique(mesh.boundary_edges[mesh.boundary_ids == 1])
    gx, gy = np.meshgrid(r.x.values, r.y.values)
    wet = r.values.ravel() < 0
    cells = earth_centred(np.column_stack([gx.ravel()[wet], gy.ravel()[wet]]), 4326)
    for k in np.flatnonzero(strip)[:12]:
        s = np.linalg.norm(xyz[coast] - xyz[k], axis=1).min()
        to_cells = np.linalg.norm(cells - xyz[k], axis=1)
        d_w, rr = -r.values.ravel()[wet][np.argmin(to_cells)], to_cells.min()
        want = 2.0 + (d_w - 2.0) * s / (s + rr) if d_w > 2.0 else max(d_w, 2.0)
        assert depth[k] == pytest.approx(max(want, 2.0), rel=1e-9)
    assert report.tapered > 0 and depth[coast].min() >= 2.0


def test_a_raster_that_puts_most_nodes_on_land_is_an_error_unless_land_is_given(
    etopo,
):
    mesh = _grid_mesh(-4.6, -4.0, 58.2, 58.5)  # Caithness and Sutherland: all land
    _, report = depth_at_nodes(mesh, etopo)
    share = report.took_wet / report.nodes
    assert share == 1.0
    with pytest.raises(InputDataError, match=r"lie on land in .*orkney_wide.tif") as e:
        depth_at_nodes(mesh, etopo, max_land_share=0.5)
    assert f"({share:.0%})" in str(e.value) and "[bathymetry] land" in str(e.value)
    # a third of the Orkney grid's nodes on land: under the limit, fine
    depth_at_nodes(_grid_mesh(-3.4, -2.6, 58.7, 59.2), etopo, max_land_share=0.5)


def test_keep_with_min_depth_is_refused_and_coarse_rasters_warn(etopo):
    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)
    with pytest.raises(ConfigError, match="land = 'keep' keeps the land heights"):
        depth_at_nodes(mesh, etopo, land="keep", min_depth=5.0)
    with pytest.warns(
        CoarseRasterWarning, match=r"orkney_wide.tif \(cells of 11.1 km\)"
    ):
        _, report = depth_at_nodes(mesh, etopo)
    # this grid mesh's elements (~1.4 to 2.4 km) are finer than 0.1 deg cells
    plain, _ = depth_at_nodes(mesh, etopo, land="keep")
    r = etopo.sortby("y")
    from reference import bilinear_wet_loop

    lon, lat = mesh.points.T
    wet = bilinear_wet_loop(r.x.values, r.y.values, -r.values, lon, lat)
    with np.errstate(invalid="ignore"):
        beside = (plain <= 0) | ((wet > 0) & (wet != plain))
    assert report.coarse == int(beside.sum()) > 0
    assert f"{report.coarse:,} (" in report.summary()


def test_the_depths_and_warning_are_the_same_on_two_threads(etopo):
    # the element sizes of the coast's check are measured on a side thread
    mesh = _grid_mesh(-3.4, -2.6, 58.7, 59.2)
    found = []
    for threads in (1, 2):
        with pytest.warns(CoarseRasterWarning) as caught:
            depth, report = depth_at_nodes(mesh, etopo, threads=threads)
        found.append((depth, report, [str(w.message) for w in caught]))
    (one, r1, w1), (two, r2, w2) = found
    assert np.array_equal(one, two)
    assert r1.summary() == r2.summary() and np.array_equal(r1.rules, r2.rules)
    assert w1 == w2
