"""A case with several bathymetry sources, end to end, and its bad inputs.

A 'survey' in UTM at 250 m (depths positive down, no data on land, a smooth
offset from ETOPO so the two differ) over the Pentland Firth sits on top of
ETOPO1 at 0.1 deg (elevations). The case file is the Orkney example with a
``[[bathymetry.sources]]`` stack.
"""

from __future__ import annotations

import json
import warnings

import netCDF4
import numpy as np
import pytest
import rasterio
from conftest import EXAMPLE, coarse_example_text
from rasterio.transform import from_origin
from rasterio.warp import Resampling, reproject

from coastmesh.case import parse_case, run_case
from coastmesh.data import path as data_path
from coastmesh.depth import DepthSource, DepthSources
from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io import read_raster

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow

ETOPO = data_path("etopo1_0.1deg_orkney_wide.tif")
NODE_DEPTH = """[bathymetry]
path = "../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif"
window = 8
modes = 16
min_depth = "5 m"
"""


def _write_survey(path, *, x0=470e3, y0=6.53e6, nx=180, ny=120, crs="EPSG:32630"):
    """ETOPO resampled to 250 m in UTM 30N, as depths (down), NaN on land."""
    etopo = read_raster(ETOPO)
    cells = np.full((ny, nx), np.nan, dtype=np.float32)
    transform = from_origin(x0, y0, 250.0, 250.0)
    reproject(
        etopo.values.astype(np.float32),
        cells,
        src_transform=etopo.attrs["transform"],
        src_crs="EPSG:4326",
        dst_transform=transform,
        dst_crs="EPSG:32630",
        resampling=Resampling.bilinear,
        dst_nodata=np.nan,
    )
    yy, xx = np.mgrid[0:ny, 0:nx]
    depth = -cells + 4.0 * np.sin(xx / 15.0) * np.cos(yy / 11.0) + 3.0
    depth[cells > 0] = np.nan  # a survey has no land
    profile = {
        "driver": "GTiff",
        "width": nx,
        "height": ny,
        "count": 1,
        "dtype": "float32",
        "transform": transform,
        "nodata": np.nan,
    }
    if crs is not None:
        profile["crs"] = crs
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(depth.astype(np.float32), 1)
    return path


SIZE_DEPTH = """[mesh_size.bathymetry]
path = "../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif"
per_wavelength = 200           # elements per M2 tidal wavelength
"""


def _case(tmp_path, sources: str, extra: str = "", size: str | None = None):
    replace = {NODE_DEPTH: f"[bathymetry]\n{extra}\n{sources}"}
    if size is not None:
        replace[SIZE_DEPTH] = f"[mesh_size.bathymetry]\nper_wavelength = 200\n{size}"
    return parse_case(coarse_example_text(**replace), EXAMPLE)


def _stack_text(survey, blend="3 km", second=ETOPO):
    return f"""
[[bathymetry.sources]]
path = "{survey}"
positive = "down"
blend = "{blend}"

[[bathymetry.sources]]
path = "{second}"
positive = "up"
"""


@pytest.fixture(scope="module")
def stacked_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("sources")
    survey = _write_survey(tmp / "survey.tif")
    stack = _stack_text(survey)
    case = _case(
        tmp,
        stack,
        'min_depth = "5 m"\nland = "nearest_sea"',
        size=stack.replace("[[bathymetry.", "[[mesh_size.bathymetry."),
    )
    assert len(case.size.bathymetry.sources) == 2
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(case, output=tmp / "out")
    return result, tmp / "out", survey


def test_stack_gives_each_node_its_source(stacked_run):
    result, out, survey = stacked_run
    report = json.loads((out / "report.json").read_text())["depth"]
    assert report["sources"] == [str(survey), str(ETOPO)]
    survey_nodes, etopo_nodes = report["per_source"]
    assert survey_nodes > 500 and etopo_nodes > 500
    assert survey_nodes + etopo_nodes == report["nodes"] == result.nodes
    assert report["blended"] > 50 and report["nearest"] == 0
    assert (out / "figures" / "depth_sources.png").stat().st_size > 10_000
    with netCDF4.Dataset(out / "pentland_firth.nc") as nc:
        names = {v.name: v for v in nc.variables.values()}
        source = next(v for k, v in names.items() if k.endswith("depth_source"))[:]
        assert sorted(np.unique(source)) == [0, 1]
        assert int((source == 0).sum()) == survey_nodes


def test_nodes_deep_inside_the_survey_take_its_own_value(stacked_run, tmp_path):
    from coastmesh.io.meshes.ugrid import read_ugrid

    _, out, survey = stacked_run
    mesh = read_ugrid(out / "pentland_firth.nc")
    alone = DepthSources([DepthSource(read_raster(survey), "down")])
    own = alone.sample(mesh.points, mesh.crs)
    edge = alone._prepared[0].tree("valid")
    from coastmesh.geometry.earth import earth_centred

    d, _ = edge[0].query(earth_centred(mesh.points, mesh.crs))
    deep = (d > 3e3 + 200) & np.isfinite(own.depth) & (own.depth > 5)
    assert deep.sum() > 200
    depth = mesh.point_data["depth"]
    np.testing.assert_allclose(depth[deep], own.depth[deep], atol=1e-4)


def test_a_raster_of_the_wrong_region_is_an_error(tmp_path):
    far = _write_survey(tmp_path / "far.tif", x0=170e3, y0=5.6e6)
    case = _case(tmp_path, f'path = "{far}"\npositive = "down"')
    out = tmp_path / "out"
    with pytest.raises(InputDataError, match=r"far\.tif does not overlap the mesh"):
        run_case(case, output=out)
    assert not out.exists()


def test_partial_cover_is_an_error_unless_outside_nearest(tmp_path):
    survey = _write_survey(tmp_path / "survey.tif")
    case = _case(tmp_path, f'path = "{survey}"\npositive = "down"')
    out = tmp_path / "out"
    with pytest.raises(InputDataError, match=r"survey\.tif leaves .* without a depth"):
        run_case(case, output=out)
    assert not out.exists()
    case = _case(
        tmp_path, f'path = "{survey}"\npositive = "down"', 'outside = "nearest"'
    )
    with pytest.warns(Warning, match="took the nearest valid cell"):
        result = run_case(case, output=out)
    assert result.nodes > 0 and (out / "report.json").exists()


def test_bad_sources_name_the_source(tmp_path):
    survey = _write_survey(tmp_path / "survey.tif")
    bare = _write_survey(tmp_path / "bare.tif", crs=None)
    (tmp_path / "text.tif").write_text("not a raster")
    cases = {
        "has no CRS": _stack_text(bare),
        "blend = 30 km is at least half": _stack_text(survey, blend="30 km"),
        r"missing\.tif: file not found": _stack_text(tmp_path / "missing.tif"),
        r"text\.tif: not a raster file GDAL can read": _stack_text(
            survey, second=tmp_path / "text.tif"
        ),
    }
    for message, sources in cases.items():
        with pytest.raises((InputDataError, ConfigError, FormatError), match=message):
            run_case(_case(tmp_path, sources), output=tmp_path / "out")
        assert not (tmp_path / "out").exists()
    same = (
        _stack_text(survey)
        .replace('blend = "3 km"', 'blend = "3 km"\npriority = 1')
        .replace('positive = "up"', 'positive = "up"\npriority = 1')
    )
    with pytest.raises(ConfigError, match=r"the same priority \(1\) and overlap"):
        run_case(_case(tmp_path, same), output=tmp_path / "out")
    with pytest.raises(ConfigError, match=r"give path \(one raster\) or sources"):
        _case(tmp_path, f'path = "{survey}"\n' + _stack_text(survey))
