"""A global case end to end: the whole ocean from the bundled low-resolution
world layer, coarse (about 20,000 triangles in about 30 s)."""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import pyogrio.raw
import pytest
import shapely
from pyproj import CRS

from coastmesh.case import run_case
from coastmesh.data import path as data_path
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.io import read_mesh

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow

CASE = """
[case]
name = "world_coarse"

[shorelines]
path = "{world}"
min_area = "5000 km2"

[shoreline_sets.world]
id = 10

[shoreline_sets.shelf]
id = 11
window = 50
modes = 2

[[regions]]
set = "shelf"
box = [-16.0, 48.0, 26.0, 70.0]

[domain]
kind = "global"
close = "150 km"

[mesh_size]
h_max = "600 km"
cell = "2 deg"
rate = 0.5

[[mesh_size.gradations]]
lines = ["world"]
h_min = "150 km"
d_grade = "2000 km"

[[mesh_size.gradations]]
lines = ["shelf"]
h_min = "150 km"
d_grade = "1000 km"

[mesh_size.bathymetry]
path = "{etopo}"
per_wavelength = 20
min_depth = "10 m"

[bathymetry]
path = "{etopo}"
min_depth = "10 m"

[output]
formats = ["gr3", "msh2", "ugrid"]
sphere_xyz = true
detail = [-16.0, 48.0, 26.0, 70.0]
"""


def _case(tmp_path, text: str = CASE):
    path = tmp_path / "world.toml"
    path.write_text(
        text.format(
            world=data_path("world_gshhg_l.zip"),
            etopo=data_path("etopo1_0.5deg_world.tif"),
        )
    )
    return path


@pytest.fixture(scope="module")
def world(tmp_path_factory):
    folder = tmp_path_factory.mktemp("global")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(_case(folder), output=folder / "out")
    return result, folder / "out"


def _xyz(lonlat):
    lon, lat = np.radians(lonlat).T
    return np.column_stack(
        [np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)]
    )


def test_the_world_ocean_is_one_mesh_on_the_sphere(world):
    result, _ = world
    mesh = result.mesh
    assert mesh.crs.is_geographic and 5_000 < len(mesh.triangles) < 60_000
    # shorelines only, both sets on the boundary; no open boundary
    assert set(mesh.boundary_kinds.values()) == {"shoreline"}
    assert set(np.unique(mesh.boundary_ids)) == {10, 11}
    p = _xyz(mesh.points)
    a, b, c = (p[mesh.triangles[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    assert ((normal * (a + b + c)).sum(axis=1) > 0).all()  # outward, every one
    crossing = np.ptp(mesh.points[mesh.triangles, 0], axis=1) > 180
    assert crossing.sum() > 10
    # the ocean is about 70 % of the sphere
    area = 0.5 * np.linalg.norm(normal, axis=1).sum()
    assert 0.6 < area / (4 * math.pi) < 0.75
    # the quality report measures on the Earth: no sign of the wrap
    q = result.report.quality
    assert q.min_angle.p1 >= 30.0
    assert q.min_angle.below_20 <= 1e-3 * q.triangles  # at forced corners


def test_the_shelf_is_its_own_set_and_sizes_follow_the_field(world):
    result, _ = world
    mesh = result.mesh
    edges = mesh.boundary_edges[mesh.boundary_ids == 11]
    lon, lat = mesh.points[edges[:, 0]].T
    assert (lon > -17).all() and (lon < 27).all() and (lat > 47).all()
    assert result.report.size_field.min_m == pytest.approx(150e3, rel=1e-6)


def test_the_files_read_back_on_the_sphere(world):
    _, out = world
    for name in ("world_coarse.gr3", "world_coarse.nc", "world_coarse.msh"):
        assert (out / name).stat().st_size > 10_000
    for name in ("globe", "mesh", "mesh_mercator", "depth"):
        assert (out / "figures" / f"{name}.png").stat().st_size > 20_000
    back = read_mesh(out / "world_coarse.msh")  # x, y, z on the sphere
    assert back.crs.to_epsg() == 4326
    assert len(back.triangles) > 5_000
    lines = (out / "world_coarse.msh").read_text().splitlines()
    first = lines.index("$Nodes") + 2
    xyz = np.array(
        [[float(v) for v in line.split()[1:]] for line in lines[first:][:50]]
    )
    assert np.allclose(np.linalg.norm(xyz, axis=1), 6_371_008.8)


CUT = """
[[cuts]]
name = "gulf"
id = 2
kind = "great_circle"
start = [-81.5, 27.5]              # in Florida
end = [-89.0, 20.0]                # in Yucatan
"""


def test_a_cut_takes_a_sea_off_with_an_open_boundary(world, tmp_path):
    """The Gulf of Mexico cut off by a line Florida - Yucatan: the ocean is
    meshed less the Gulf, and the cut is an open boundary with its id. Cuba
    (far above min_area) is kept, fattened by the 150 km closing until the
    line crosses its west end: the coast between the cut's two pieces there is
    under three edges, so it becomes open too (as Telemac would make it)."""
    whole = world[0].mesh
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(_case(tmp_path, CASE + CUT), output=tmp_path / "out")
    mesh = read_mesh(tmp_path / "out" / "world_coarse.gr3")
    assert _nearest_km(whole, -90.0, 25.0) < 200 < _nearest_km(mesh, -90.0, 25.0)
    cut = mesh.boundary_edges[mesh.boundary_ids == 2]
    assert len(cut) >= 2 and mesh.boundary_kinds[2] == "open"
    assert result.report.domain.segments["gulf"] > 100  # the line, before meshing
    # the cut's nodes lie on the line Florida - Yucatan (a geodesic on the
    # ellipsoid: within 130 m of the sphere's great circle)
    ends = _xyz(np.array([[-81.5, 27.5], [-89.0, 20.0]]))
    normal = np.cross(ends[0], ends[1])
    normal /= np.linalg.norm(normal)
    nodes = mesh.points[np.unique(cut)]
    cuba = (nodes[:, 0] > -85.5) & (nodes[:, 0] < -82.0) & (nodes[:, 1] < 24.0)
    assert cuba.sum() <= 5  # short runs of Cuba's coast, made open
    on = _xyz(nodes[~cuba])
    # on the line, but where the channel stage cut the open boundary back: a
    # strip one element wide along it (between the line and Cuba's fattened
    # west end, at 150 km, as the boundary nodes fall) goes, and the open
    # boundary runs along its inner side, one node off the line per strip
    off = np.abs(on @ normal) >= 2e-5
    assert off.sum() <= result.report.channels.strips
    assert (np.abs(on @ normal) < 0.03).all()  # within an element (190 km)
    # the ocean lost the Gulf of Mexico: about 1.6 M km2
    lost = _area(whole) - _area(mesh)
    assert 1.0e12 < lost < 2.0e12
    # domain.gpkg holds the untrimmed cut where the domain is (the plane)
    path = tmp_path / "out" / "domain.gpkg"
    meta, _, wkb, _ = pyogrio.raw.read(path, layer="open_boundaries_untrimmed")
    meta_d, _, wkb_d, _ = pyogrio.raw.read(path, layer="domain")
    assert CRS.from_user_input(meta["crs"]) == CRS.from_user_input(meta_d["crs"])
    assert shapely.from_wkb(wkb)[0].intersects(shapely.from_wkb(wkb_d)[0])


def _nearest_km(mesh, lon0, lat0) -> float:
    """The distance from (lon0, lat0) to the nearest node, km (sphere)."""
    chord = np.linalg.norm(_xyz(mesh.points) - _xyz(np.array([[lon0, lat0]])), axis=1)
    return float(2 * np.arcsin(chord.min() / 2) * 6371.0088)


def _area(mesh) -> float:
    """The mesh's area on the sphere, m2 (spherical triangles, l'Huilier)."""
    xyz = _xyz(mesh.points)[mesh.triangles]
    a, b, c = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    triple = np.abs(np.einsum("ij,ij->i", a, np.cross(b, c)))
    denom = 1 + (a * b).sum(1) + (b * c).sum(1) + (c * a).sum(1)
    return float((2 * np.arctan2(triple, denom)).sum() * 6_371_008.8**2)


def test_open_boundaries_in_a_global_case_say_what_to_do(tmp_path):
    text = CASE + CUT.replace("[[cuts]]", "[[open_boundaries]]")
    with pytest.raises(ConfigError, match=r"give the line as \[\[cuts\]\]"):
        run_case(_case(tmp_path, text), output=tmp_path / "out")
    assert not (tmp_path / "out").exists()
    regional = CASE.replace('kind = "global"\n', "") + CUT
    with pytest.raises(ConfigError, match=r"\[\[cuts\]\] are for global cases"):
        run_case(_case(tmp_path, regional), output=tmp_path / "out")


def test_a_regional_layer_is_refused_with_its_name(tmp_path):
    text = CASE.replace("{world}", str(data_path("orkney_gshhg_f.geojson")))
    with pytest.raises(InputDataError, match=r"orkney_gshhg_f.*both hemispheres"):
        run_case(_case(tmp_path, text), output=tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    ("seed", "message"),
    [
        ("[20.0, 10.0]", r"\[20, 10\] \(lon, lat\): lies on land .*continent"),
        ("[0.0, -85.0]", r"\[0, -85\] \(lon, lat\): lies on the polar land"),
    ],
)
def test_a_seed_on_land_is_found_before_the_sets_in_lonlat(tmp_path, seed, message):
    text = CASE.replace('kind = "global"\n', f'kind = "global"\nseed = {seed}\n')
    started = time.perf_counter()
    with pytest.raises(ConfigError, match=message):
        run_case(_case(tmp_path, text), output=tmp_path / "out")
    assert time.perf_counter() - started < 20  # before any set or meshing
    assert not (tmp_path / "out").exists()


def test_a_cut_that_ends_in_the_water_is_named(tmp_path):
    text = CASE + CUT.replace("[-89.0, 20.0]", "[-88.0, 24.0]")  # in the Gulf
    started = time.perf_counter()
    with pytest.raises(ConfigError, match=r"cuts\[0\] \('gulf'\): its end \(-88.0"):
        run_case(_case(tmp_path, text), output=tmp_path / "out")
    assert time.perf_counter() - started < 60  # before the size field and mesh
    assert not (tmp_path / "out").exists()


def test_a_pole_near_the_coast_is_warned_of(tmp_path):
    # in Cameroon, about 150 km from the Gulf of Guinea
    text = CASE.replace('kind = "global"\n', 'kind = "global"\npole = [12.0, 5.0]\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoastmeshWarning)  # stop at the warning
        with pytest.raises(CoastmeshWarning, match=r"pole = \[12.0, 5.0\]: the coast"):
            run_case(_case(tmp_path, text), output=tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_pole_in_asia_meshes_and_keeps_europe_land(tmp_path):
    """The pole inside Asia (103 E, 46 N): the grid node on it goes to infinity
    in the plane and the cells round it grow without bound; with them in the
    size view Gmsh grew past 24 GB. Europe, where the shelf set's region is, is
    the polar land's coast there: it must stay land in that set too."""
    text = CASE.replace(
        'kind = "global"\n', 'kind = "global"\npole = [103.0, 46.0]\n'
    ).replace('cell = "2 deg"', 'cell = "1 deg"')  # a grid node on the pole
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(_case(tmp_path, text), output=tmp_path / "out")
    mesh = result.mesh
    p = _xyz(mesh.points)
    a, b, c = (p[mesh.triangles[:, k]] for k in range(3))
    assert ((np.cross(b - a, c - a) * (a + b + c)).sum(axis=1) > 0).all()
    centre = mesh.points[mesh.triangles].mean(axis=1)
    inland = [(8.0, 48.0, 14.0, 53.0), (20.0, 48.0, 26.0, 52.0)]  # Germany, Poland
    for x0, y0, x1, y1 in inland:
        inside = (centre[:, 0] > x0) & (centre[:, 0] < x1)
        assert not (inside & (centre[:, 1] > y0) & (centre[:, 1] < y1)).any()
    # and the shelf's coast is there, with the shelf set's id
    edges = mesh.boundary_edges[mesh.boundary_ids == 11]
    assert len(edges) > 20
    assert result.report.quality.min_angle.p1 >= 30.0
