"""``[shorelines] raster = PATH``: the land contoured from a raster, in a case.

The config keys and their errors, the reading (CRS, window, sign, nodata, no
land), and whole runs of examples/orkney/dem_shoreline.toml: it meshes, and bad
input stops it with a message naming the file or the keys and nothing written.
"""

from __future__ import annotations

import dataclasses
import re
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
import xarray as xr
from conftest import assert_clean_failure
from pyproj import CRS

from coastmesh.case import (
    CaseConfig,
    ShorelinesConfig,
    ShorelineSetConfig,
    SizeConfig,
    parse_case,
    run_case,
)
from coastmesh.case.dump import dump_case
from coastmesh.case.pipeline.dem_shorelines import NoLandWarning
from coastmesh.case.pipeline.shorelines import read_shorelines
from coastmesh.data import path as data_path
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry import land_from_grid
from coastmesh.io import read_raster, write_raster
from coastmesh.io.meshes.msh import read_msh

EXAMPLE = Path(__file__).parents[3] / "examples" / "orkney" / "dem_shoreline.toml"
ETOPO = data_path("etopo1_0.1deg_orkney_wide.tif")
#: the example's shoreline raster line, once its paths are absolute
RASTER = f'raster = "{ETOPO.as_posix()}"'

BASE = """
[case]
name = "dem"
{case}
[shorelines]
{shorelines}
[shoreline_sets.coast]
id = 1
[mesh_size]
h_max = "5 km"
"""


def parse(shorelines: str, case: str = ""):
    return parse_case(BASE.format(shorelines=shorelines, case=case), "/cases/a.toml")


def case_text(tmp_path: Path, **replace: str) -> Path:
    """The example with absolute data paths, one format, no figures."""
    text = EXAMPLE.read_text().replace(
        "../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif", ETOPO.as_posix()
    )
    text = re.sub(r"^output = .*\n", "", text, flags=re.M)
    text = re.sub(
        r"^formats = .*$", 'formats = ["msh2"]\nfigures = false', text, flags=re.M
    )
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


def write_grid(path, values, x, y, crs="EPSG:32630"):
    grid = xr.DataArray(
        np.asarray(values, dtype=np.float64),
        dims=("y", "x"),
        coords={"y": y, "x": x},
        attrs={"crs": crs, "nodata": -9999.0, "dtype": "float32"},
    )
    write_raster(path, grid)
    return path


def bump(tmp_path, crs="EPSG:32630", name="bump.tif"):
    """A hill 10 km across (land r < 5 km at 0 m), UTM 30N metres, 500 m cells."""
    x = 500_000.0 + np.arange(-10_000.0, 10_001.0, 500.0)
    y = 6_500_000.0 + np.arange(10_000.0, -10_001.0, -500.0)
    r = np.hypot(x[None, :] - 500_000.0, y[:, None] - 6_500_000.0)
    return write_grid(tmp_path / name, 50.0 * (1.0 - (r / 5000.0) ** 2), x, y, crs)


def python_case(**shorelines) -> CaseConfig:
    return CaseConfig(
        name="dem",
        shorelines=ShorelinesConfig(**shorelines),
        sets=[ShorelineSetConfig("coast", 1)],
        size=SizeConfig(h_max="5 km"),
    )


# -- the config ---------------------------------------------------------------


def test_raster_keys_are_read():
    case = parse('raster = "dem.tif"\nlevel = "-0.5 m"\npositive = "down"')
    s = case.shorelines
    assert s.path is None and s.raster == Path("/cases/dem.tif")
    assert (s.level, s.positive) == (-0.5, "down")
    default = parse('raster = "dem.tif"\nbbox = [0, 0, 1, 1]').shorelines
    assert (default.level, default.positive, default.bbox) == (0.0, "up", (0, 0, 1, 1))
    assert parse('raster = "dem.tif"\nlevel = 2').shorelines.level == 2.0  # metres
    # written back and read again, equal
    again = parse_case(dump_case(case), "/elsewhere/case.toml")
    assert dataclasses.replace(again, source=None, text="") == dataclasses.replace(
        case, source=None, text=""
    )


@pytest.mark.parametrize(
    "shorelines, match",
    [
        (
            'path = "coast.gpkg"\nraster = "dem.tif"',
            r"a\.toml: shorelines\.path: give exactly one of shorelines\.path .* "
            r"and shorelines\.raster .*; both are given",
        ),
        ('min_area = "1 km2"', r"shorelines\.raster .*; neither is given"),
        ('path = "coast.gpkg"\nlevel = "1 m"', r"shorelines\.level: is for a raster"),
        ('path = "c.gpkg"\npositive = "up"', r"shorelines\.positive: is for a raster"),
        ('raster = "dem.tif"\nlayer = "land"', r"shorelines\.layer = 'land': a raster"),
        ('raster = "d.tif"\nlevel = "1 deg"', r"shorelines\.level = '1 deg': expected"),
        ('raster = "d.tif"\nlevel = "high"', r"shorelines\.level = 'high': expected"),
        ('raster = "d.tif"\npositive = "out"', r"shorelines\.positive = 'out'"),
    ],
)
def test_config_errors_name_the_keys(shorelines, match):
    with pytest.raises(ConfigError, match=match):
        parse(shorelines)


def test_python_config_has_the_same_checks():
    assert python_case(raster="dem.tif", level="-2 m").shorelines.level == -2.0
    with pytest.raises(ConfigError, match=r"shorelines\.path: .*neither is given"):
        python_case()
    with pytest.raises(ConfigError, match=r"shorelines\.path: .*both are given"):
        python_case(path="coast.gpkg", raster="dem.tif")


# -- reading ------------------------------------------------------------------


def test_etopo_land_in_the_case_crs():
    box = (-4.5, 58.0, -1.5, 60.0)
    case = parse(f'raster = "{ETOPO.as_posix()}"\nbbox = {list(box)}')
    features, crs = read_shorelines(case)
    assert crs.equals(CRS.from_epsg(4326)) and features.crs.equals(crs)
    assert features.path == str(ETOPO) and len(features) == 4
    assert shapely.is_valid(features.geometry).all()
    assert shapely.covers(shapely.box(*box).buffer(1e-9), features.geometry).all()
    raster = read_raster(ETOPO, bbox=box)
    direct = land_from_grid(raster.x, raster.y, raster.values, 0.0)
    assert shapely.union_all(features.geometry).equals(shapely.union_all(direct))
    # [case] crs: reprojected, the same land
    utm, utm_crs = read_shorelines(
        parse(
            f'raster = "{ETOPO.as_posix()}"\nbbox = {list(box)}', 'crs = "EPSG:32630"'
        )
    )
    assert utm_crs.to_epsg() == 32630 and utm.crs.to_epsg() == 32630
    assert shapely.get_coordinates(utm.geometry)[:, 1].min() > 6e6  # metres


def test_depths_give_the_same_land(tmp_path):
    raster = read_raster(ETOPO)
    depths = write_grid(
        tmp_path / "depth.tif", -raster.values, raster.x, raster.y, "EPSG:4326"
    )
    up, _ = read_shorelines(parse(f'raster = "{ETOPO.as_posix()}"\nlevel = "-20 m"'))
    down, _ = read_shorelines(
        parse(f'raster = "{depths.as_posix()}"\nlevel = "-20 m"\npositive = "down"')
    )
    assert shapely.union_all(up.geometry).equals(shapely.union_all(down.geometry))
    at_zero, _ = read_shorelines(parse(f'raster = "{ETOPO.as_posix()}"'))
    # land at -20 m (shallows above it count as land) is more than at 0 m
    assert (
        shapely.union_all(up.geometry).area > shapely.union_all(at_zero.geometry).area
    )


def test_projected_raster_and_sub_cell_coast(tmp_path):
    features, crs = read_shorelines(parse(f'raster = "{bump(tmp_path).as_posix()}"'))
    assert crs.to_epsg() == 32630 and len(features) == 1
    # the coast is the circle r = 5 km to well within a cell (500 m)
    xy = shapely.get_coordinates(features.geometry[0].exterior)
    r = np.hypot(xy[:, 0] - 500_000.0, xy[:, 1] - 6_500_000.0)
    assert np.abs(r - 5000.0).max() < 20.0
    assert features.geometry[0].area == pytest.approx(np.pi * 5000.0**2, rel=5e-3)


def test_nodata_stops_the_land(tmp_path):
    x = np.arange(0.0, 10_001.0, 1000.0) + 400_000.0
    y = np.arange(10_000.0, -1.0, -1000.0) + 6_400_000.0
    values = np.full((len(y), len(x)), 10.0)
    values[:, 6:] = np.nan  # a land-only DEM: the sea is nodata
    path = write_grid(tmp_path / "land_only.tif", values, x, y)
    features, _ = read_shorelines(parse(f'raster = "{path.as_posix()}"'))
    assert len(features) == 1
    assert features.geometry[0].bounds == pytest.approx(
        (x[0], y[-1], x[5], y[0])  # up to the last quad with four samples
    )


def test_no_crs_is_an_error_naming_the_file_unless_crs_is_given(tmp_path):
    path = bump(tmp_path, crs=None, name="nocrs.tif")
    with pytest.raises(InputDataError, match=r"nocrs\.tif: the raster declares no CRS"):
        read_shorelines(parse(f'raster = "{path.as_posix()}"'))
    features, crs = read_shorelines(
        parse(f'raster = "{path.as_posix()}"\ncrs = "EPSG:32630"')
    )
    assert crs.to_epsg() == 32630 and len(features) == 1


def test_missing_raster_and_tiny_window(tmp_path):
    with pytest.raises(InputDataError, match=r"gone\.tif: file not found"):
        read_shorelines(parse(f'raster = "{(tmp_path / "gone.tif").as_posix()}"'))
    tiny = f'raster = "{ETOPO.as_posix()}"\nbbox = [-3.01, 58.99, -2.99, 59.01]'
    with pytest.raises(InputDataError, match=r"1 x 1 cells .*at least 2 x 2"):
        read_shorelines(parse(tiny))


def test_no_land_warns_and_gives_no_shoreline():
    with pytest.warns(NoLandWarning, match=r"no land above level = 2000 m.*1030"):
        features, _ = read_shorelines(
            parse(f'raster = "{ETOPO.as_posix()}"\nlevel = "2 km"')
        )
    assert len(features) == 0


# -- whole runs -----------------------------------------------------------------


def test_example_meshes_with_the_contoured_coast(tmp_path):
    started = time.perf_counter()
    result = run_case(case_text(tmp_path), output=tmp_path / "out")
    seconds = time.perf_counter() - started
    assert seconds < 20
    mesh = read_msh(tmp_path / "out" / "dem_shoreline.msh")
    assert len(mesh.triangles) == result.triangles > 5000
    assert set(np.unique(mesh.boundary_ids)) == {2, 3, 4, 5, 10}
    # the coast of the mesh is the contour: its nodes lie on the land's edge
    raster = read_raster(ETOPO, bbox=(-4.5, 58.0, -1.5, 60.0))
    land = shapely.union_all(land_from_grid(raster.x, raster.y, raster.values, 0.0))
    coast = np.unique(mesh.boundary_edges[mesh.boundary_ids == 10])
    gap = shapely.distance(land.boundary, shapely.points(mesh.points[coast]))
    # (resampling the boundary to the local size cuts the contour's corners)
    assert np.mean(gap < 1e-6) > 0.9 and gap.max() < 5e-4  # degrees
    inland = land.buffer(-5e-4)
    assert not shapely.contains_properly(inland, shapely.points(mesh.points)).any()


def test_pca_of_the_contour_and_regions(tmp_path):
    """The contour goes through the shoreline sets as a vector layer does."""
    sets = (
        '[shoreline_sets.contour]\nid = 10\n\n[shoreline_sets.smooth]\nid = 11\n'
        'window = 20\nmodes = 3\n\n[[regions]]\nset = "contour"\n'
        "box = [-5.0, 57.5, -1.0, 58.7]\n"
    )  # fmt: skip
    # (the box's edges are kept off the raster's frame, where the land is cut
    # straight: a seam along it lost every land polygon in the stitch)
    path = case_text(
        tmp_path,
        **{
            "[shoreline_sets.contour]\nid = 10\n": sets,
            'lines = ["west", "north"': 'lines = ["smooth", "west", "north"',
        },
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(path, output=tmp_path / "out")
    report = result.report.shoreline_sets
    # 4 coasts and a lake; the lake and the two islands have under 20 points
    assert (report["smooth"].contours_in, report["smooth"].contours_dropped) == (5, 3)
    assert report["smooth"].polygons == 2 and report["contour"].polygons == 4
    assert result.report.stitch.polygons == {"contour": 1, "smooth": 1}
    assert {"contour (10)", "smooth (11)"} <= set(result.boundary_edges)


@pytest.mark.filterwarnings("ignore:.*have no edges on the domain boundary")
def test_a_level_above_all_land_meshes_the_sea_alone(tmp_path):
    path = case_text(tmp_path, **{'level = "0 m"': 'level = "2 km"'})
    with pytest.warns(NoLandWarning):
        result = run_case(path, output=tmp_path / "out")
    assert "contour (10)" not in result.boundary_edges
    assert set(result.boundary_edges) == {
        "west (2)",
        "north (3)",
        "east (4)",
        "south (5)",
    }


def test_bad_input_stops_the_run_with_nothing_written(run_cli, tmp_path):
    out = tmp_path / "out"
    nocrs = bump(tmp_path, crs=None, name="nocrs.tif")
    cases = {
        "nocrs": (
            {
                RASTER: f'raster = "{nocrs.as_posix()}"',
                "bbox = [-4.5, 58.0, -1.5, 60.0]\n": "",
            },
            ["nocrs.tif", "declares no CRS", "shorelines.crs"],
            1,
        ),
        "both": (
            {"[shorelines]\n": '[shorelines]\npath = "coast.gpkg"\n'},
            ["shorelines.path", "shorelines.raster", "both are given"],
            2,
        ),
        "missing": (
            {RASTER: f'raster = "{(tmp_path / "gone.tif").as_posix()}"'},
            ["gone.tif", "file not found"],
            1,
        ),
    }
    for name, (replace, expected, code) in cases.items():
        case = case_text(tmp_path, **replace)
        result = run_cli("run", case, "--output", out)
        assert_clean_failure(result, *expected, code=code)
        assert not out.exists() and not list(tmp_path.glob("out.partial*")), name
