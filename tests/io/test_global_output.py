"""Global meshes on the sphere: every format written, read back, rebuilt on the sphere.

The fixture is a synthetic global ocean built without Gmsh: Fibonacci points on
the unit sphere, their convex hull (the Delaunay triangulation of the sphere),
minus four spherical caps of land. Each cap's rim is a ring of nodes, so the
hull's facet across the cap is exactly the land, and the rim the shoreline.
"Pacifica" straddles the antimeridian with a node on it, "Antarctica" holds the
South Pole, and the North Pole is in the sea (inside a triangle, or a node).
"""

from __future__ import annotations

import itertools
import warnings

import meshio
import netCDF4
import numpy as np
import pyogrio.raw
import pytest
import shapely
import xarray as xr
from pyproj import CRS
from scipy.spatial import ConvexHull, cKDTree

import coastmesh
from coastmesh.errors import CoastmeshWarning, ConfigError, FormatError
from coastmesh.geometry import EARTH_RADIUS, reproject_points
from coastmesh.geometry.sphere import lonlat_to_xyz, xyz_to_lonlat
from coastmesh.io import check_on_sphere
from coastmesh.io.meshes.adcirc import read_fort14
from coastmesh.io.meshes.sphere import (
    crossing_triangles,
    on_sphere,
    pole_triangles,
    solid_angles,
)
from coastmesh.types import Mesh
from coastmesh.types.topology import boundary_rings

CAPS = (  # centre lon, lat, radius (degrees), name; id = position + 1
    (180.0, 10.0, 22.0, "pacifica"),
    (0.0, -90.0, 25.0, "antarctica"),
    (20.0, 5.0, 30.0, "africa"),
    (-150.0, -30.0, 6.0, "isle"),
)
AFRICA = 3  # the largest land: the exterior ring on the sphere


def global_mesh(n=1500, *, pole_node=False):
    """The synthetic global ocean (see the module docstring), EPSG:4326."""
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    phi = np.pi * (1 + 5**0.5) * i
    xyz = np.column_stack(
        [np.sqrt(1 - z**2) * np.cos(phi), np.sqrt(1 - z**2) * np.sin(phi), z]
    )
    spacing = np.sqrt(4 * np.pi / n)
    sea = np.ones(n, dtype=bool)
    rims = []
    for lon, lat, radius, _ in CAPS:
        centre = lonlat_to_xyz([[lon, lat]])[0]
        angle = np.radians(radius)
        sea &= xyz @ centre < np.cos(angle + 0.4 * spacing)
        count = max(8, round(2 * np.pi * np.sin(angle) / spacing)) | 1
        north = np.array([0.0, 0.0, 1.0]) - centre[2] * centre
        if np.linalg.norm(north) < 1e-9:  # a polar cap: start towards lon 180
            north = lonlat_to_xyz([[180.0, 0.0]])[0]
        north /= np.linalg.norm(north)
        east = np.cross(north, centre)
        # Pacifica's rim has a node on the antimeridian (its northernmost one, t = 0);
        # Antarctica's rim crosses it between two nodes
        t = 2 * np.pi * (np.arange(count) + (0.5 if lat == -90 else 0.0)) / count
        rims.append(
            np.cos(angle) * centre
            + np.sin(angle) * (np.outer(np.cos(t), north) + np.outer(np.sin(t), east))
        )
    parts = [xyz[sea], *rims] + ([[[0.0, 0.0, 1.0]]] if pole_node else [])
    lonlat = xyz_to_lonlat(np.concatenate(parts))
    lonlat[np.abs(np.abs(lonlat[:, 0]) - 180) < 1e-9, 0] = -180.0
    if pole_node:
        lonlat[-1] = [0.0, 90.0]
    xyz = lonlat_to_xyz(lonlat)
    triangles = ConvexHull(xyz).simplices.astype(np.int64)
    backwards = solid_angles(xyz, triangles) < 0
    triangles[backwards] = triangles[backwards][:, ::-1]
    owner = np.full(len(xyz), -1)
    start = int(sea.sum())
    for k, rim in enumerate(rims):
        owner[start : start + len(rim)] = k
        start += len(rim)
    on_rim = owner[triangles]
    land = (on_rim[:, 0] >= 0) & (on_rim == on_rim[:, :1]).all(axis=1)
    triangles = triangles[~land]
    # the first triangle crosses the antimeridian: planar code reads it backwards
    first = int(np.flatnonzero(crossing_triangles(lonlat, triangles))[0])
    triangles[[0, first]] = triangles[[first, 0]]
    sides = np.sort(
        np.concatenate(
            [triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]
        ),
        axis=1,
    )
    unique, count = np.unique(sides, axis=0, return_counts=True)
    edges = unique[count == 1]
    ids = owner[edges[:, 0]] + 1
    assert (owner[edges[:, 1]] + 1 == ids).all() and (ids > 0).all()
    return Mesh(
        lonlat,
        triangles,
        edges,
        ids,
        1,
        "EPSG:4326",
        {"depth": 1000.0 + np.arange(len(lonlat))},
        {k + 1: cap[3] for k, cap in enumerate(CAPS)},
        {k + 1: "shoreline" for k in range(len(CAPS))},
    )


@pytest.fixture(
    scope="module", params=[False, True], ids=["pole-in-triangle", "pole-node"]
)
def world(request):
    return global_mesh(pole_node=request.param)


def test_the_fixture_is_a_global_ocean(world):
    check = check_on_sphere(world)
    land = sum(2 * np.pi * (1 - np.cos(np.radians(cap[2]))) for cap in CAPS)
    assert check.ok and on_sphere(world)
    # the rims are polygons inscribed in the caps: a little more sea than 4 pi - land
    sea = 4 * np.pi * EARTH_RADIUS**2 - land * EARTH_RADIUS**2
    assert 1 < check.area / sea < 1.01
    assert check.crossing > 20
    assert check.polar == (0 if (world.points[:, 1] == 90).any() else 1)
    assert (world.points[:, 0] == -180).sum() == 1  # Pacifica's northernmost node
    assert crossing_triangles(world.points, world.triangles[:1]).all()
    sides = (3 * len(world.triangles) + len(world.boundary_edges)) // 2
    euler = len(world.points) - sides + len(world.triangles)
    assert euler == 2 - len(CAPS)  # a sphere with a hole per cap


# --- rebuilding what was read, on the sphere -------------------------------------


def rebuilt(world, points, triangles, *, reference=None):
    """Map the nodes read onto the fixture's; check the triangles on the sphere.

    ``reference`` is the fixture's points as the format stores them (float32 for
    SELAFIN); the nodes read must be those, and the triangles the same set, each
    counter-clockwise seen from outside, with the same total and largest area.
    """
    reference = world.points if reference is None else reference
    distance, index = cKDTree(lonlat_to_xyz(reference)).query(lonlat_to_xyz(points))
    assert distance.max() < 1e-12
    assert np.array_equal(np.sort(index), np.arange(len(reference)))  # same node set
    mapped = index[np.asarray(triangles)]
    assert {tuple(sorted(t)) for t in mapped.tolist()} == {
        tuple(sorted(t)) for t in world.triangles.tolist()
    }
    xyz = lonlat_to_xyz(reference)
    area = solid_angles(xyz, mapped)
    expected = solid_angles(xyz, world.triangles)
    assert (area > 0).all(), f"{int((area <= 0).sum())} triangles run clockwise"
    np.testing.assert_allclose(area.sum(), expected.sum(), rtol=1e-9)
    assert area.max() <= expected.max() * (
        1 + 1e-9
    )  # no triangle wrapped the wrong way
    return index


def test_a_planar_reading_is_caught(world):
    """The check fails if crossing triangles are turned counter-clockwise in lon/lat."""
    from coastmesh.io.meshes._reading import counter_clockwise

    planar = counter_clockwise(world.points, world.triangles)
    assert check_on_sphere(Mesh(world.points, planar, [], [], 1, None)).clockwise > 20
    with pytest.raises(AssertionError, match="run clockwise"):
        rebuilt(world, world.points, planar)
    spherical = counter_clockwise(world.points, world.triangles, sphere=True)
    np.testing.assert_array_equal(spherical, world.triangles)


@pytest.mark.parametrize(
    ("name", "options"), [("g.msh", {"format": "msh2"}), ("g4.msh", {"format": "msh4"})]
)
def test_msh_sphere_xyz_round_trip(tmp_path, world, name, options):
    path = tmp_path / name
    coastmesh.write_mesh(path, world, sphere_xyz=True, **options)
    data = meshio.read(path)  # an independent reader: x, y, z in metres
    radius = np.linalg.norm(data.points, axis=1)
    np.testing.assert_allclose(radius, EARTH_RADIUS, rtol=1e-12)
    triangles = data.cells_dict["triangle"]
    assert (solid_angles(data.points / radius[:, None], triangles) > 0).all()  # outward
    rebuilt(world, xyz_to_lonlat(data.points), triangles)
    back = coastmesh.read_mesh(path, format=options["format"])
    assert back.crs == CRS.from_epsg(4326)
    index = rebuilt(world, back.points, back.triangles)
    np.testing.assert_allclose(back.points, world.points[index], atol=1e-9)
    written = {
        tuple(sorted(e)): i
        for e, i in zip(world.boundary_edges.tolist(), world.boundary_ids, strict=True)
    }
    read = {
        tuple(sorted(e)): i
        for e, i in zip(
            index[back.boundary_edges].tolist(), back.boundary_ids, strict=True
        )
    }
    assert read == written  # the same physical ids
    assert back.surface_id == world.surface_id


def test_msh_sphere_xyz_keeps_physical_names_and_radius(tmp_path, world):
    path = tmp_path / "unit.msh"
    coastmesh.write_mesh(path, world, sphere_xyz=True, radius=1.0)
    data = meshio.read(path)
    np.testing.assert_allclose(np.linalg.norm(data.points, axis=1), 1.0, rtol=1e-14)
    back = coastmesh.read_mesh(path)
    assert back.boundary_names == world.boundary_names
    assert back.boundary_kinds == world.boundary_kinds
    lines = np.concatenate([c.data for c in data.cells if c.type == "line"])
    assert len(lines) == len(world.boundary_edges)


def test_flat_msh_of_a_global_mesh_warns(tmp_path, world):
    with pytest.warns(
        CoastmeshWarning, match=r"\d+ triangles cross the antimeridian.*sphere_xyz"
    ):
        coastmesh.write_mesh(tmp_path / "flat.msh", world)
    back = coastmesh.read_mesh(tmp_path / "flat.msh", crs="EPSG:4326")
    rebuilt(world, back.points, back.triangles)


def test_msh_sphere_xyz_refusals_and_projected_meshes(tmp_path, world):
    bare = Mesh(
        world.points, world.triangles, world.boundary_edges, world.boundary_ids, 1, None
    )
    with pytest.raises(FormatError, match="sphere_xyz needs the mesh's CRS"):
        coastmesh.write_mesh(tmp_path / "a.msh", bare, sphere_xyz=True)
    for radius in (0.0, -1.0, float("nan"), "6371 km"):
        with pytest.raises(ConfigError, match="radius="):
            coastmesh.write_mesh(
                tmp_path / "b.msh", world, sphere_xyz=True, radius=radius
            )
    assert list(tmp_path.iterdir()) == []
    # a projected regional mesh goes to lon/lat first
    square = Mesh(
        [[5e5, 6.5e6], [5.1e5, 6.5e6], [5e5, 6.51e6]],
        [[0, 1, 2]],
        [[0, 1], [1, 2], [2, 0]],
        [1, 1, 2],
        1,
        "EPSG:32630",
    )
    coastmesh.write_mesh(tmp_path / "utm.msh", square, sphere_xyz=True)
    back = coastmesh.read_mesh(tmp_path / "utm.msh")
    expected = reproject_points(square.points, "EPSG:32630", "EPSG:4326")
    np.testing.assert_allclose(back.points, expected, atol=1e-9)
    assert check_on_sphere(back).ok
    with pytest.raises(ConfigError, match="not a geographic CRS"):
        coastmesh.read_mesh(tmp_path / "utm.msh", crs="EPSG:32630")


def test_msh_reader_refuses_3d_nodes_off_a_sphere(tmp_path):
    path = tmp_path / "bumpy.msh"
    mesh = meshio.Mesh(
        [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.5]],
        [("triangle", [[0, 1, 2]])],
        cell_data={"gmsh:physical": [[1]], "gmsh:geometrical": [[1]]},
    )
    meshio.gmsh.write(path, mesh, fmt_version="2.2", binary=False)
    with pytest.raises(FormatError, match="not on a sphere centred at 0"):
        coastmesh.read_mesh(path)


def directed_sides(triangles):
    return set(
        map(
            tuple,
            np.concatenate(
                [triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]
            ).tolist(),
        )
    )


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_adcirc_and_schism_keep_lonlat_and_sphere_orientation(tmp_path, world, name):
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)  # the North Pole (fort.14)
        coastmesh.write_mesh(path, world)
    grid = read_fort14(path)  # the file as written, nothing turned
    np.testing.assert_allclose(grid["xy"], world.points, rtol=0, atol=1e-12)
    assert grid["xy"][:, 0].min() >= -180 and grid["xy"][:, 0].max() < 180
    elements = grid["elements"] - 1
    rebuilt(world, grid["xy"], elements)
    np.testing.assert_array_equal(elements, world.triangles)
    # ADCIRC finds crossing elements by their negative Jacobian in lon/lat
    crossing = crossing_triangles(grid["xy"], elements) & (
        pole_triangles(grid["xy"], elements) == 0
    )
    a, b, c = (grid["xy"][elements[crossing, k]] for k in range(3))
    jacobian = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (
        b[:, 1] - a[:, 1]
    )
    assert crossing.sum() > 20 and (jacobian < 0).all()
    back = coastmesh.read_mesh(path)  # coastmesh's reader keeps them as they are
    np.testing.assert_array_equal(back.triangles, world.triangles)
    rebuilt(world, back.points, back.triangles)


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3"])
def test_land_boundaries_have_the_sea_on_the_left_on_the_sphere(tmp_path, world, name):
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        coastmesh.write_mesh(path, world)
    grid = read_fort14(path)
    sides = directed_sides(world.triangles)
    land = grid["land_boundaries"]
    for segment in land:
        nodes = segment["nodes"] - 1
        assert all((a, b) in sides for a, b in itertools.pairwise(nodes))
    # the exterior is Africa, the largest land (two linked segments in SCHISM)
    exterior = [s for s in land if s["ibtype"] == 0]
    assert len(exterior) == (1 if name == "fort.14" else 2)
    africa = set(np.unique(world.boundary_edges[world.boundary_ids == AFRICA]).tolist())
    assert set(np.concatenate([s["nodes"] for s in exterior]) - 1) == africa
    assert sum(s["ibtype"] == 1 for s in land) == len(CAPS) - 1
    back = coastmesh.read_mesh(path)
    assert sorted(map(tuple, np.sort(back.boundary_edges, axis=1).tolist())) == sorted(
        map(tuple, np.sort(world.boundary_edges, axis=1).tolist())
    )


def test_planar_rings_would_run_backwards(world):
    """Why the rings are ordered on the sphere: in the plane they run backwards."""
    sides = directed_sides(world.triangles)
    ring = boundary_rings(world)[0]
    pairs = zip(ring.nodes, np.roll(ring.nodes, -1), strict=True)
    assert not any((int(a), int(b)) in sides for a, b in pairs)


def test_fort14_warns_when_the_pole_is_inside_a_triangle(tmp_path, world):
    inside = (pole_triangles(world.points, world.triangles) != 0).any()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        coastmesh.write_mesh(tmp_path / "fort.14", world)
        coastmesh.write_mesh(tmp_path / "hgrid.gr3", world)
    messages = [
        str(w.message) for w in caught if issubclass(w.category, CoastmeshWarning)
    ]
    assert len(messages) == int(inside)
    if inside:
        assert "fort.14: the North Pole lies inside the mesh" in messages[0]
        assert "fort.rotm" in messages[0]


def test_ugrid_faces_counter_clockwise_on_the_sphere(tmp_path, world):
    path = tmp_path / "g.nc"
    coastmesh.write_mesh(path, world)
    with netCDF4.Dataset(path) as ds:  # an independent reader
        x = ds["mesh2d_node_x"][:].data
        y = ds["mesh2d_node_y"][:].data
        faces = ds["mesh2d_face_nodes"][:].data - ds["mesh2d_face_nodes"].start_index
        assert ds["mesh2d_node_x"].standard_name == "longitude"
    points = np.column_stack([x, y])
    np.testing.assert_array_equal(points, world.points)
    rebuilt(world, points, faces)
    back = coastmesh.read_mesh(path)
    rebuilt(world, back.points, back.triangles)
    np.testing.assert_array_equal(back.triangles, world.triangles)


def test_gpkg_cuts_crossing_features_at_the_antimeridian(tmp_path, world):
    path = tmp_path / "g.gpkg"
    coastmesh.write_mesh(path, world)
    meta, _, wkb, _ = pyogrio.raw.read(path, layer="triangles")
    assert meta["geometry_type"] == "MultiPolygon"
    polygons = shapely.from_wkb(wkb)
    parts, owner = shapely.get_parts(polygons, return_index=True)
    bounds = shapely.bounds(parts)
    assert bounds[:, 0].min() >= -180 and bounds[:, 2].max() <= 180
    polar = pole_triangles(world.points, world.triangles) != 0
    wide = bounds[:, 2] - bounds[:, 0] > 180  # only caps around a pole
    assert set(owner[wide].tolist()) <= set(np.flatnonzero(polar).tolist())
    cut = np.bincount(owner, minlength=len(polygons)) > 1
    crossing = crossing_triangles(world.points, world.triangles)
    assert cut.sum() > 20 and not (cut & ~crossing).any()
    # the parts of each triangle cover it: planar area of the unwrapped triangle
    area = np.bincount(owner, shapely.area(parts), minlength=len(polygons))
    plain = ~polar & ~(np.abs(world.points[:, 1]) == 90)[world.triangles].any(axis=1)
    corners = world.points[world.triangles[plain]]
    corners[..., 0] = (
        corners[:, :1, 0] + (corners[..., 0] - corners[:, :1, 0] + 180) % 360 - 180
    )
    u, v = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    flat = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    np.testing.assert_allclose(area[plain], flat, rtol=1e-9, atol=1e-12)
    meta, _, wkb, _ = pyogrio.raw.read(path, layer="boundaries")
    lines = shapely.from_wkb(wkb)
    parts, owner = shapely.get_parts(lines, return_index=True)
    assert (shapely.bounds(parts)[:, 2] - shapely.bounds(parts)[:, 0]).max() < 180
    assert (np.bincount(owner) == 2).sum() >= 2  # Antarctica's and Pacifica's rims
    back = coastmesh.read_mesh(path)
    np.testing.assert_array_equal(back.points, world.points)
    rebuilt(world, back.points, back.triangles)
    np.testing.assert_array_equal(back.boundary_edges, world.boundary_edges)
    np.testing.assert_array_equal(back.boundary_ids, world.boundary_ids)
    np.testing.assert_array_equal(back.point_data["depth"], world.point_data["depth"])


def test_vtu_writes_the_mesh_as_it_is(tmp_path, world):
    path = tmp_path / "g.vtu"
    coastmesh.write_mesh(path, world)
    data = meshio.read(path)
    rebuilt(world, data.points[:, :2], data.cells_dict["triangle"])


def test_selafin_keeps_lonlat_and_warns(tmp_path, world):
    path = tmp_path / "g.slf"
    with pytest.warns(
        CoastmeshWarning, match=r"\d+ triangles cross the antimeridian.*Telemac"
    ):
        coastmesh.write_mesh(path, world)
    with xr.open_dataset(path, engine="selafin") as ds:
        points = np.column_stack([ds["x"].values, ds["y"].values]).astype(np.float64)
        triangles = ds.attrs["ikle2"] - 1
    single = world.points.astype(np.float32).astype(np.float64)
    rebuilt(world, points, triangles, reference=single)


def test_selafin_cli_rings_have_the_sea_on_the_left(tmp_path, world):
    path = tmp_path / "g.slf"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        coastmesh.write_mesh(path, world)
    rows = [line.split() for line in path.with_suffix(".cli").read_text().splitlines()]
    nodes = np.array([int(r[11]) for r in rows]) - 1
    assert sorted(nodes.tolist()) == np.unique(world.boundary_edges).tolist()
    sides = directed_sides(world.triangles)
    follows = sum((int(a), int(b)) in sides for a, b in itertools.pairwise(nodes))
    assert follows == len(nodes) - len(CAPS)  # every step but the jumps between rings


def test_mike_refuses_a_global_mesh(tmp_path, world):
    count = int(crossing_triangles(world.points, world.triangles).sum())
    with pytest.raises(
        FormatError, match=rf"{count} triangles cross the antimeridian.*MIKE"
    ):
        coastmesh.write_mesh(tmp_path / "g.mesh", world)
    assert list(tmp_path.iterdir()) == []


def test_regional_lonlat_meshes_are_not_on_the_sphere(tmp_path):
    """A lon/lat mesh with no crossing triangle is written as before, in the plane."""
    square = Mesh(
        [[178.0, 0.0], [179.5, 0.0], [179.5, 1.0], [178.0, 1.0]],
        [[0, 1, 2], [0, 2, 3]],
        [[0, 1], [1, 2], [2, 3], [3, 0]],
        [1, 1, 1, 1],
        1,
        "EPSG:4326",
        {"depth": [5.0, 5.0, 5.0, 5.0]},
        boundary_kinds={1: "shoreline"},
    )
    assert not on_sphere(square)
    coastmesh.write_mesh(tmp_path / "r.gpkg", square)
    for layer, kind in (("triangles", "Polygon"), ("boundaries", "LineString")):
        assert (
            pyogrio.raw.read(tmp_path / "r.gpkg", layer=layer)[0]["geometry_type"]
            == kind
        )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coastmesh.write_mesh(tmp_path / "r.msh", square)
        coastmesh.write_mesh(tmp_path / "r.mesh", square)


def test_check_on_sphere_needs_lonlat():
    utm = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], [], [], 1, "EPSG:32630")
    with pytest.raises(FormatError, match="not geographic"):
        check_on_sphere(utm)
