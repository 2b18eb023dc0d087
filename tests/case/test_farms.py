"""[[farms]] and [[turbines]]: regions and nodes of a tidal site in a case's mesh."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
import shapely
from conftest import EXAMPLE, coarse_example_text
from pyproj import CRS

import coastmesh
from coastmesh.case import parse_case
from coastmesh.case.pipeline.farms import site_features
from coastmesh.errors import ConfigError
from coastmesh.geometry import reproject

FARM = "[[-3.150, 58.655], [-3.125, 58.655], [-3.125, 58.662], [-3.150, 58.662]]"
SITE = f"""
[[farms]]
name = "meygen"
id = 20
polygon = {FARM}
h = "60 m"

[[turbines]]
name = "discs"
farm = "meygen"
diameter = "18 m"
positions = [[-3.145, 58.6585], [-3.140, 58.6585]]
footprint = "disc"
id = 100
h = "D/2"

[[turbines]]
name = "nodes"
farm = "meygen"
diameter = "18 m"
positions = [[-3.132, 58.6575], [-3.128, 58.6595]]
"""


def _case(extra: str = SITE, **replace: str):
    return parse_case(coarse_example_text(**replace) + extra, EXAMPLE)


@pytest.fixture(scope="module")
def built():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        return coastmesh.build_case(_case(), workers=1)


def _utm_areas(mesh):
    utm = CRS.from_epsg(32630)
    p = reproject(shapely.polygons(mesh.points[mesh.triangles]), mesh.crs, utm)
    return shapely.area(p)


@pytest.mark.slow  # a whole case, built once
def test_the_farm_and_footprints_are_regions_of_their_own(built):
    mesh = built.mesh
    assert mesh.region_ids == [1, 20, 100, 101]
    assert mesh.region_names == {20: "meygen", 100: "discs_1", 101: "discs_2"}
    area = _utm_areas(mesh)
    utm = CRS.from_epsg(32630)
    farm = reproject(shapely.Polygon(eval(FARM)), CRS.from_epsg(4326), utm)
    in_farm = np.isin(mesh.regions, [20, 100, 101])
    # the outline's vertices are nodes, its sides straight in the meshing CRS
    assert area[in_farm].sum() == pytest.approx(farm.area, rel=1e-6)
    disc = area[mesh.regions == 100].sum()
    sides = max(8, math.ceil(math.pi * 18 / 9))  # h = D/2: 7 sides, at least 8
    inscribed = sides / 2 * 9.0**2 * math.sin(2 * math.pi / sides)
    assert disc == pytest.approx(inscribed, rel=1e-6)


@pytest.mark.slow  # a whole case, built once
def test_node_turbines_are_mesh_nodes_at_their_place(built):
    mesh = built.mesh
    for lon, lat in ((-3.132, 58.6575), (-3.128, 58.6595)):
        gap = np.hypot(mesh.points[:, 0] - lon, mesh.points[:, 1] - lat)
        k = int(np.argmin(gap))
        utm = CRS.from_epsg(32630)
        a = reproject(shapely.Point(mesh.points[k]), mesh.crs, utm)
        b = reproject(shapely.Point(lon, lat), CRS.from_epsg(4326), utm)
        assert a.distance(b) < 1e-3


@pytest.mark.slow  # a whole case, built once
def test_the_regions_survive_the_written_msh(built, tmp_path):
    path = tmp_path / "m.msh"
    coastmesh.write_mesh(path, built.mesh, format="msh2")
    back = coastmesh.read_mesh(path, crs=built.mesh.crs)
    assert back.region_ids == built.mesh.region_ids
    assert back.region_names == built.mesh.region_names
    assert (
        np.bincount(back.regions).tolist() == np.bincount(built.mesh.regions).tolist()
    )


@pytest.mark.slow  # a whole case, built once
def test_elements_in_the_farm_follow_its_size(built):
    mesh = built.mesh
    edges = np.sqrt(_utm_areas(mesh) * 4 / np.sqrt(3))
    # away from the turbines, whose sizes grow at rate 0.25 to the farm's 60 m
    turbines = np.array(
        [[-3.145, 58.6585], [-3.140, 58.6585], [-3.132, 58.6575], [-3.128, 58.6595]]
    )
    centres = mesh.points[mesh.triangles].mean(axis=1)
    metres = np.array([math.cos(math.radians(58.66)) * 111_320, 111_320])
    gap = np.min(
        np.hypot(*((centres[:, None, :] - turbines[None]) * metres).transpose(2, 0, 1)),
        axis=1,
    )
    farm = (mesh.regions == 20) & (gap > 300)
    assert farm.sum() > 50
    assert 0.8 <= np.median(edges[farm]) / 60.0 <= 1.25
    assert 0.6 <= np.median(edges[mesh.regions == 100]) / 9.0 <= 1.25


# --- bad input ---------------------------------------------------------------


def test_a_turbine_naming_no_farm_is_refused():
    with pytest.raises(ConfigError, match=r"turbines\[0\].farm = 'nowhere'"):
        _case(SITE.replace('farm = "meygen"', 'farm = "nowhere"', 1))


def test_an_id_used_twice_is_refused():
    with pytest.raises(ConfigError, match="id 10 is also the id of"):
        _case(SITE.replace("id = 20", "id = 10"))  # the example's 'full' set
    with pytest.raises(ConfigError, match="id 20 is also the id of"):
        _case(SITE.replace("id = 100", "id = 19"))  # 19, 20 (the farm)


def test_a_footprint_needs_ids():
    with pytest.raises(ConfigError, match="needs the footprints' ids"):
        _case(SITE.replace("id = 100\n", ""))


@pytest.mark.parametrize("text", ["D/0", "-2 D", "D/x"])
def test_a_bad_share_of_the_diameter_is_named(text):
    with pytest.raises(ConfigError, match=r"turbines\[0\]\.h"):
        _case(SITE.replace('h = "D/2"', f'h = "{text}"'))


def _state(case):
    """A stand-in for the domain stage: the sea is the box the farm lies in."""
    sea = shapely.box(-3.30, 58.60, -3.00, 58.72)
    domain = SimpleNamespace(polygon=sea, crs=CRS.from_epsg(4326))
    return SimpleNamespace(domain=domain, mesh_crs=CRS.from_epsg(32630))


def test_site_features_read_the_farm_and_turbines():
    site = site_features(_case(), _state(None))
    assert [f[0] for f in site.farms] == ["meygen"]
    assert [t.name for t in site.turbines] == [
        "discs_1",
        "discs_2",
        "nodes_1",
        "nodes_2",
    ]
    assert [f[1] for f in site.footprints] == [100, 101]
    assert site.smallest() == pytest.approx(4.5)  # the nodes: D/4 by default


def test_site_sizes_without_a_gradation_limit_are_refused():
    from coastmesh.case.pipeline.farms import with_site_sizes
    from coastmesh.types import SizeGrid

    site = site_features(_case(), _state(None))
    size = SizeGrid([0.0, 1.0], [0.0, 1.0], [[1.0, 1.0], [1.0, 1.0]])
    with pytest.raises(ConfigError, match=r"case.toml: mesh_size.rate = false: "):
        with_site_sizes(size, site, None, "case.toml")


def test_a_farm_on_land_is_refused():
    case = _case()
    state = _state(case)
    state.domain.polygon = shapely.box(-3.30, 58.60, -3.14, 58.72)  # cuts the farm
    with pytest.raises(ConfigError, match=r"farms\[0\] \('meygen'\): .* lies on land"):
        site_features(case, state)


def test_turbines_too_close_are_refused_by_name():
    close = SITE.replace("[-3.140, 58.6585]", "[-3.1452, 58.6585]")
    with pytest.raises(ConfigError, match=r"'discs_1' and 'discs_2' are .* apart"):
        site_features(_case(close), _state(None))


def test_a_footprint_across_the_farm_outline_is_refused():
    across = SITE.replace("[-3.145, 58.6585]", "[-3.150, 58.6585]").replace(
        'farm = "meygen"\ndiameter', "diameter", 1
    )
    with pytest.raises(ConfigError, match="crosses the outline of farm 'meygen'"):
        site_features(_case(across), _state(None))


def test_a_turbine_outside_its_farm_is_refused():
    outside = SITE.replace("[-3.132, 58.6575]", "[-3.110, 58.6575]")
    with pytest.raises(ConfigError, match="'nodes_1' is not inside its farm"):
        site_features(_case(outside), _state(None))


@pytest.mark.slow  # a whole case, built once
def test_turbines_csv_says_where_each_turbine_is(built, tmp_path):
    import csv

    from coastmesh.case.pipeline.farms import TURBINE_COLUMNS, write_turbines

    path = tmp_path / "turbines.csv"
    write_turbines(path, built.site, built.mesh)
    rows = list(csv.DictReader(path.open()))
    assert [r["name"] for r in rows] == ["discs_1", "discs_2", "nodes_1", "nodes_2"]
    assert tuple(rows[0]) == TURBINE_COLUMNS
    assert [int(r["region"]) for r in rows] == [100, 101, 20, 20]
    mesh = built.mesh
    assert mesh.crs.is_geographic  # the example's output CRS: x, y are lon, lat
    given = [p for group in built.config.turbines for p in group.positions]
    assert len(given) == len(rows) == 4
    for r, (lon, lat) in zip(rows, given, strict=True):
        # the turbine: its place as the case gives it, in lon/lat and the mesh CRS
        assert float(r["lon"]) == pytest.approx(lon, abs=1e-8)
        assert float(r["lat"]) == pytest.approx(lat, abs=1e-8)
        assert (float(r["x"]), float(r["y"])) == (lon, lat)  # as given, exactly
        # its node: a mesh node, the nearest to the turbine
        node = int(r["node"])
        assert (float(r["node_x"]), float(r["node_y"])) == tuple(mesh.points[node])
        gap = np.hypot(mesh.points[:, 0] - lon, mesh.points[:, 1] - lat)
        assert gap[node] == gap.min()
        assert float(r["depth_m"]) == pytest.approx(
            mesh.point_data["depth"][node], abs=1e-3
        )
    utm = CRS.from_epsg(32630)
    for r in rows:
        turbine = reproject(shapely.Point(float(r["x"]), float(r["y"])), mesh.crs, utm)
        node = reproject(
            shapely.Point(float(r["node_x"]), float(r["node_y"])), mesh.crs, utm
        )
        if r["group"] == "discs":  # the nearest node of the footprint, not its centre
            assert 1e-3 < turbine.distance(node) <= 9.0  # D/2
        else:  # a node turbine: its node is its place, to 1 mm
            assert turbine.distance(node) < 1e-3
            assert float(r["element_size_m"]) == pytest.approx(4.5, rel=0.35)


def test_footprint_ids_from_a_file_are_checked_too(tmp_path):
    table = tmp_path / "turbines.csv"
    table.write_text("name,x,y\nA,-3.145,58.6585\nB,-3.140,58.6585\n")
    text = SITE.replace(
        "positions = [[-3.145, 58.6585], [-3.140, 58.6585]]",
        f'path = "{table}"',
    ).replace("id = 100", "id = 19")  # A: 19, B: 20, the farm's id
    with pytest.raises(ConfigError, match="'B' has id 20, which is the id of farm"):
        site_features(_case(text), _state(None))


def test_a_farm_touching_the_coast_is_refused():
    case = _case()
    state = _state(case)
    # the sea ends at the farm's east side
    farm = shapely.Polygon(eval(FARM))
    state.domain.polygon = shapely.box(-3.30, 58.60, -3.15, 58.72).union(farm)
    with pytest.raises(ConfigError, match="touches the domain's boundary"):
        site_features(case, state)


@pytest.mark.parametrize("bearing", [0.0, 30.0, 100.0])
def test_a_square_footprint_has_side_d_turned_to_its_bearing(bearing):
    from coastmesh.case.pipeline.farms import _footprint

    square = _footprint("square", (100.0, 200.0), 18.0, 4.5, bearing)
    assert square.area == pytest.approx(18.0**2)
    assert square.centroid.distance(shapely.Point(100, 200)) < 1e-9
    # one side's direction: the bearing turns it clockwise from east-west
    a, b = np.asarray(square.exterior.coords)[:2]
    angle = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))
    assert (angle + bearing) % 90 == pytest.approx(0, abs=1e-9) or (
        (angle + bearing) % 90 == pytest.approx(90, abs=1e-9)
    )


def test_a_disc_footprint_has_ceil_pi_d_over_h_sides_at_least_8():
    from coastmesh.case.pipeline.farms import _footprint

    assert len(_footprint("disc", (0, 0), 18.0, 4.5, 0).exterior.coords) - 1 == 13
    assert len(_footprint("disc", (0, 0), 18.0, 18.0, 0).exterior.coords) - 1 == 8


WAKE = """
[[wakes]]
of = "discs"
bearing = 90
length = "10 D"
h = "D/2"
"""


def test_a_wake_is_the_source_swept_along_the_axis():
    site = site_features(_case(SITE + WAKE), _state(None))
    ((source, band, h),) = site.wakes
    assert source == "discs" and h == pytest.approx(9.0)
    discs = [t for t in site.turbines if t.group == "discs"]
    xs = [t.xy[0] for t in discs]
    x0, y0, x1, y1 = band.bounds
    assert x0 == pytest.approx(min(xs) - 9 - 180, abs=0.5)  # both ways, 10 D
    assert x1 == pytest.approx(max(xs) + 9 + 180, abs=0.5)
    assert y1 - y0 == pytest.approx(18.0, abs=1.0)  # a rotor (UTM turns a parallel)
    flood = site_features(_case(SITE + WAKE + 'sides = "flood"\n'), _state(None)).wakes[
        0
    ][1]
    assert flood.bounds[0] == pytest.approx(min(xs) - 9, abs=0.5)  # east only
    # the site's sizes: h in the band, growing at rate away from it
    x = np.array([min(xs) - 100.0, max(xs) + 5000.0])
    y = np.array([discs[0].xy[1], discs[0].xy[1]])
    got = site.sizes(x, y, 0.25)
    assert got[0] == pytest.approx(9.0)
    assert got[1] > 500.0


def test_a_wake_of_nothing_known_is_refused():
    with pytest.raises(ConfigError, match=r"wakes\[0\]\.of = 'nowhere'"):
        _case(SITE + WAKE.replace('of = "discs"', 'of = "nowhere"'))


def test_a_share_of_d_without_turbines_is_refused():
    lone = SITE.split("[[turbines]]", maxsplit=1)[0]
    text = lone + WAKE.replace('of = "discs"', 'of = "meygen"')
    with pytest.raises(ConfigError, match="a share of D, but the source has no"):
        site_features(_case(text), _state(None))


def test_turbines_from_a_vector_file_take_its_names_and_diameters(tmp_path):
    import json

    points = [(-3.145, 58.6585, "T1", 18.0), (-3.140, 58.6585, "T2", 20.0)]
    path = tmp_path / "turbines.geojson"
    path.write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    {
                        "type": "Feature",
                        "properties": {"name": name, "diameter": d},
                        "geometry": {"type": "Point", "coordinates": [x, y]},
                    }
                    for x, y, name, d in points
                ],
            }
        )
    )
    text = SITE.replace(
        'diameter = "18 m"\npositions = [[-3.145, 58.6585], [-3.140, 58.6585]]',
        f'path = "{path}"',
    )
    site = site_features(_case(text), _state(None))
    read = [t for t in site.turbines if t.group == "discs"]
    assert [(t.name, t.diameter) for t in read] == [("T1", 18.0), ("T2", 20.0)]


def test_a_gradation_may_name_a_farm_outline():
    from coastmesh.case import GradationConfig, SizeConfig
    from coastmesh.case.config import PYTHON_SOURCE
    from coastmesh.case.schema import Check, check_part
    from coastmesh.case.terms.base import SizeCase, SizeTables
    from coastmesh.case.terms.gradations import Gradations
    from coastmesh.sizing.grid import PlaneGrid
    from coastmesh.types import BoundarySegment, Domain

    ring = [[0, 0], [20000, 0], [20000, 20000], [0, 20000], [0, 0]]
    domain = Domain(
        shapely.Polygon(ring),
        (BoundarySegment(ring, "shoreline", "coast", 1),),
        crs="EPSG:32630",
    )
    farm = shapely.box(9000, 9000, 11000, 11000).exterior
    size = SizeConfig(
        h_max="2 km",
        cell="250 m",
        gradations=[GradationConfig(["meygen"], h_min="100 m", d_grade="5 km")],
    )
    size = check_part(size, SizeConfig, Check(PYTHON_SOURCE), "mesh_size")
    grid = PlaneGrid.around(domain, CRS(32630), spacing=250.0, smallest=100.0)
    case = SizeCase(SizeTables(size), domain, 100.0, read_depth=None)
    with pytest.warns(coastmesh.CoastmeshWarning, match="have no edges"):
        Gradations().sizes(grid, case)  # without the farm's outline: skipped
    named = SizeCase(SizeTables(size), domain, 100.0, None, lines={"meygen": farm})
    upper = np.asarray(Gradations().sizes(grid, named).upper)
    xx, yy = np.meshgrid(grid.x, grid.y)
    d = shapely.distance(farm, shapely.points(xx, yy))
    want = np.minimum(100.0 + (2000.0 - 100.0) * d / 5000.0, 2000.0)
    # the lines' vertices are a cell apart: distances within half a cell
    assert np.abs(upper - want).max() <= 1900.0 / 5000.0 * 125.0


def test_a_footprint_smaller_than_gmsh_can_place_is_refused():
    tiny = SITE.replace('diameter = "18 m"', 'diameter = "0.001 m"', 1)
    with pytest.raises(ConfigError, match=r"'discs_1'.*smaller than the smallest elem"):
        site_features(_case(tiny), _state(None))


def test_a_farm_is_a_site_for_the_closing_and_the_courant_floor():
    from coastmesh.case.pipeline.domain import site_area

    utm = CRS.from_epsg(32630)
    area = site_area(_case(), utm)
    farm = reproject(shapely.Polygon(eval(FARM)), CRS.from_epsg(4326), utm)
    assert area is not None and area.buffer(1e-6).covers(farm)
