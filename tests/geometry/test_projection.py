"""The meshing CRS: sizes are metres on the Earth, converted by the scale factor."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from pyproj import CRS, Geod, Transformer

from coastmesh.geometry import projection
from coastmesh.geometry.projection import default_mesh_crs, scale_factor, to_map_units
from coastmesh.meshing import generate_mesh
from coastmesh.types import BoundarySegment, Domain, SizeGrid

GEOD = Geod(ellps="WGS84")
H = 5000.0  # target edge length, metres on the Earth
# WGS 84: semi-major axis and first eccentricity squared
A = 6378137.0
E2 = 0.00669437999014


def lonlat_box(west, south, east, north):
    ring = np.array(
        [[west, south], [east, south], [east, north], [west, north], [west, south]],
        dtype=float,
    )
    segment = BoundarySegment(ring, "open", "box", 1)
    return Domain(shapely.Polygon(ring), (segment,), crs="EPSG:4326")


def uniform_grid(domain, crs, h=H, n=20):
    """A uniform size grid in ``crs`` covering the domain with a margin."""
    west, south, east, north = domain.polygon.bounds
    lon, lat = np.meshgrid(
        np.linspace(west - 0.5, east + 0.5, 30),
        np.linspace(south - 0.2, north + 0.2, 30),
    )
    x, y = Transformer.from_crs(4326, crs, always_xy=True).transform(lon, lat)
    gx = np.linspace(x.min(), x.max(), n)
    gy = np.linspace(y.min(), y.max(), n)
    return SizeGrid(gx, gy, np.full((n, n), h))


def geodesic_edge_lengths(mesh):
    """Length on the WGS 84 ellipsoid of every edge of a lon/lat mesh, in metres."""
    t = mesh.triangles
    edges = np.unique(
        np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1),
        axis=0,
    )
    (lon1, lat1), (lon2, lat2) = mesh.points[edges[:, 0]].T, mesh.points[edges[:, 1]].T
    return GEOD.inv(lon1, lat1, lon2, lat2)[2]


@pytest.fixture(scope="module")
def box60():
    # 4 x 1 degrees around 60N, where Mercator's scale factor is about 2
    return lonlat_box(-2.0, 59.5, 2.0, 60.5)


@pytest.fixture(scope="module")
def mercator_mesh(box60):
    mercator = CRS.from_epsg(3857)
    return generate_mesh(box60, uniform_grid(box60, mercator), mesh_crs=mercator)


@pytest.fixture(scope="module")
def utm_mesh(box60):
    utm = CRS.from_epsg(32631)
    return generate_mesh(box60, uniform_grid(box60, utm), mesh_crs=utm)


def test_mercator_mesh_edges_are_the_target_length_on_the_earth(mercator_mesh):
    length = geodesic_edge_lengths(mercator_mesh)
    # unconverted, the 5000 "map metres" are about 2500 m on the Earth at 60N
    assert np.median(length) == pytest.approx(H, rel=0.15)
    assert mercator_mesh.crs == CRS.from_epsg(4326)
    # the node data stays the target in metres on the Earth, not map units
    np.testing.assert_allclose(mercator_mesh.point_data["size"], H, rtol=1e-9)


def test_utm_and_mercator_meshes_have_similar_node_counts(mercator_mesh, utm_mesh):
    n_mercator, n_utm = len(mercator_mesh.points), len(utm_mesh.points)
    assert n_mercator == pytest.approx(n_utm, rel=0.15)
    assert np.median(geodesic_edge_lengths(utm_mesh)) == pytest.approx(H, rel=0.15)
    # about sqrt(3) / 2 * H**2 of the Earth per node; four times that unconverted
    area = 4 * 111.2e3 * np.cos(np.radians(60)) * 111.2e3
    assert 0.6 < n_utm * np.sqrt(3) / 2 * H**2 / area < 1.4


def test_mercator_meshing_is_deterministic(box60, mercator_mesh):
    mercator = CRS.from_epsg(3857)
    again = generate_mesh(box60, uniform_grid(box60, mercator), mesh_crs=mercator)
    np.testing.assert_array_equal(again.points, mercator_mesh.points)
    np.testing.assert_array_equal(again.triangles, mercator_mesh.triangles)


def test_grid_conversion_matches_ellipsoidal_mercator_closed_form():
    # EPSG:3395, World Mercator on the WGS 84 ellipsoid, in closed form:
    # y = a ln(tan(pi/4 + phi/2) ((1 - e sin phi) / (1 + e sin phi))^(e/2)),
    # k = sqrt(1 - e^2 sin^2 phi) / cos phi
    lat = np.radians(np.array([-75.0, -40.0, 0.0, 20.0, 45.0, 60.0, 70.0, 84.0]))
    e = np.sqrt(E2)
    esin = e * np.sin(lat)
    y = A * np.log(np.tan(np.pi / 4 + lat / 2) * ((1 - esin) / (1 + esin)) ** (e / 2))
    x = A * np.radians(np.array([-170.0, -30.0, 0.0, 5.0, 100.0]))
    rng = np.random.default_rng(0)
    size = SizeGrid(x, y, rng.uniform(100.0, 20000.0, (y.size, x.size)))
    converted = to_map_units(size, CRS.from_epsg(3395))
    k = np.sqrt(1 - E2 * np.sin(lat) ** 2) / np.cos(lat)
    np.testing.assert_allclose(converted.values / size.values, k[:, None] + 0 * x)
    np.testing.assert_allclose(converted.values, size.values * k[:, None], rtol=1e-7)
    np.testing.assert_array_equal(converted.x, size.x)
    np.testing.assert_array_equal(converted.y, size.y)


def test_default_mesh_crs_is_utm_when_narrow_and_stereographic_when_wide():
    assert default_mesh_crs(lonlat_box(4.0, 60.0, 6.0, 62.0)) == CRS.from_epsg(32631)
    assert default_mesh_crs(lonlat_box(-71.0, -42.0, -65.0, -40.0)).to_epsg() == 32719
    # 2 degrees across the antimeridian is narrow, not 358 degrees wide
    assert default_mesh_crs(lonlat_box(179.0, 50.0, 181.0, 51.0)).to_epsg() == 32601

    wide = lonlat_box(-10.0, 50.0, 10.0, 60.0)
    crs = default_mesh_crs(wide)
    assert crs.is_projected and crs.geodetic_crs == CRS.from_epsg(4326)
    operation = crs.coordinate_operation
    assert operation.method_name == "Oblique Stereographic"  # PROJ's sterea
    params = {p.name: p.value for p in operation.params}
    centroid = wide.polygon.centroid
    assert params["Latitude of natural origin"] == pytest.approx(centroid.y, abs=1e-6)
    assert params["Longitude of natural origin"] == pytest.approx(centroid.x, abs=1e-6)
    assert params["Scale factor at natural origin"] == 1
    assert params["False easting"] == params["False northing"] == 0
    # conformal, with a scale factor close to 1 over the domain
    ring = shapely.get_coordinates(shapely.segmentize(wide.polygon.exterior, 0.5))
    x, y = Transformer.from_crs(4326, crs, always_xy=True).transform(*ring.T)
    k = scale_factor(x, y, crs)
    assert 1.0 <= k.min() and k.max() < 1.01

    # polar, even if narrow
    polar = default_mesh_crs(lonlat_box(10.0, 79.0, 14.0, 81.0))
    assert polar.coordinate_operation.method_name == "Oblique Stereographic"
    assert polar.coordinate_operation.params[0].value == pytest.approx(80.0, abs=0.01)


def test_wide_domain_in_its_default_crs_follows_the_size_on_the_earth():
    shelf = lonlat_box(-15.0, 45.0, 10.0, 70.0)
    crs = default_mesh_crs(shelf)
    mesh = generate_mesh(shelf, uniform_grid(shelf, crs, h=100e3))
    assert np.median(geodesic_edge_lengths(mesh)) == pytest.approx(100e3, rel=0.1)


def test_non_conformal_mesh_crs_is_refused(box60):
    laea = CRS.from_epsg(3035)  # Lambert azimuthal equal area: not conformal
    with pytest.raises(ValueError, match=r"'ETRS89-extended / LAEA Europe'.*conformal"):
        generate_mesh(box60, uniform_grid(box60, laea), mesh_crs=laea)


def test_size_grid_outside_the_projection_is_refused(box60):
    utm = CRS.from_epsg(32631)
    size = SizeGrid([-1e8, 1e8], [6.5e6, 6.8e6], np.full((2, 2), H))
    with pytest.raises(ValueError, match=r"no longitude.*UTM zone 31N"):
        generate_mesh(box60, size, mesh_crs=utm)


def test_scale_factors_in_threads_are_those_of_one(monkeypatch):
    monkeypatch.setattr(projection, "_SCALE_BLOCK", 7)  # 12 blocks, the last short
    crs = CRS.from_epsg(32631)
    rng = np.random.default_rng(3)
    x = rng.uniform(2e5, 8e5, (9, 9))
    y = rng.uniform(6.5e6, 6.8e6, (9, 9))
    one = scale_factor(x, y, crs)
    np.testing.assert_array_equal(scale_factor(x, y, crs, threads=3), one)
    assert one.shape == (9, 9) and 0.9996 <= one.min() < one.max() < 1.001
    # a point with no longitude: the same error, naming the first such node
    x[4, 2], x[7, 1] = 1e8, 2e8
    messages = []
    for threads in (1, 3):
        with pytest.raises(ValueError, match="no longitude") as error:
            scale_factor(x, y, crs, threads=threads)
        messages.append(str(error.value))
    assert messages[0] == messages[1] and "100000000.0" in messages[0]
