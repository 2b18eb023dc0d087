"""``[shorelines] level`` in a case: the coast at a height above the datum.

Issue 31 (intertidal coasts): examples/orkney/dem_shoreline.toml with the coast
at -1, 0, 0.5, 1, 2 and 10 m. Its domain is compared with one built here
without coastmesh's domain code: the quadrilateral closed by the example's four
open boundaries (two meridians, a parallel and a great circle drawn with
pyproj) less the land above the level, the part that holds the seed. The sea
grows as the coast rises; a raster of depths with ``positive = "down"`` and the
same level gives the same domain; and the whole case meshes at ``"2 m"``.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
import xarray as xr
from conftest import model_rule_breaks
from pyproj import Geod

from coastmesh.case import parse_case, run_case
from coastmesh.case.pipeline import (
    CaseRun,
    RunContext,
    domain_stage,
    shoreline_stage,
    strategy_of,
)
from coastmesh.data import path as data_path
from coastmesh.geometry import land_from_grid
from coastmesh.io import read_raster, write_raster
from coastmesh.io.meshes.msh import read_msh
from coastmesh.types import quiet_stage

EXAMPLE = Path(__file__).parents[2] / "examples" / "orkney" / "dem_shoreline.toml"
ETOPO = data_path("etopo1_0.1deg_orkney_wide.tif")
BOX = (-4.5, 58.0, -1.5, 60.0)  # the example's bbox
LEVELS = (-1.0, 0.0, 0.5, 1.0, 2.0, 10.0)
GEOD = Geod(ellps="WGS84")
SEED = shapely.Point(-2.4, 58.7)


def case_text(level: str, raster: Path = ETOPO, positive: str = "up") -> str:
    """The example with absolute paths, the coast at ``level``, one format."""
    text = EXAMPLE.read_text()
    text = text.replace(
        '../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif"', f'{ETOPO}"'
    )
    text = re.sub(r"^output = .*\n", "", text, flags=re.M)
    text = re.sub(r'^raster = ".*"', f'raster = "{raster}"', text, flags=re.M)
    for key, value in (("level", level), ("positive", positive)):
        text, n = re.subn(rf"^{key} = .*$", f'{key} = "{value}"', text, flags=re.M)
        assert n == 1, key
    return re.sub(
        r"^formats = .*$", 'formats = ["msh2"]\nfigures = false', text, flags=re.M
    )


def domain_of(text: str) -> shapely.Polygon:
    """Run the case's shoreline and domain stages; return the sea polygon."""
    config = parse_case(text, EXAMPLE)
    run = CaseRun(config, strategy_of(config))
    ctx = RunContext(1, None, quiet_stage)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = domain_stage(shoreline_stage(run, ctx), ctx)
    return run.domain.domain.polygon


def km2(geometry) -> float:
    """Geodesic area in km2 (edges split to 0.01 degree)."""
    area = GEOD.geometry_area_perimeter(shapely.segmentize(geometry, 0.01))[0]
    return abs(area) / 1e6


def expected_sea(level: float) -> shapely.Polygon:
    """The example's sea at ``level``, built without coastmesh's domain code.

    The open boundaries: west the meridian -3.6, east -2.1, south the parallel
    58.55 and north the great circle from (-3.7, 59.5) to (-2.0, 59.5).
    """
    west, east, south = -3.6, -2.1, 58.55
    north = np.array(GEOD.npts(-3.7, 59.5, -2.0, 59.5, 2000))
    inside = north[(north[:, 0] > west) & (north[:, 0] < east)]
    ends = [[lon, np.interp(lon, north[:, 0], north[:, 1])] for lon in (west, east)]
    top = np.vstack([ends[0], inside, ends[1]])
    quad = shapely.Polygon([(west, south), (east, south), *top[::-1]])
    raster = read_raster(ETOPO, bbox=BOX)
    land = shapely.union_all(
        land_from_grid(raster.x.values, raster.y.values, raster.values, level)
    )
    (sea,) = [p for p in shapely.get_parts(quad - land) if p.covers(SEED)]
    return sea


def test_the_sea_grows_as_the_coast_rises():
    areas = []
    for level in LEVELS:
        domain = domain_of(case_text(f"{level:g} m"))
        expected = expected_sea(level)
        assert km2(domain) == pytest.approx(km2(expected), abs=0.05), level
        assert km2(shapely.symmetric_difference(domain, expected)) < 0.05, level
        assert len(domain.interiors) == len(expected.interiors), level
        areas.append(km2(domain))
    # measured: 7490, 7525, 7543, 7560, 7765, 8126 km2
    assert all(np.diff(areas) > 10.0), areas
    assert 230.0 < areas[LEVELS.index(2.0)] - areas[LEVELS.index(0.0)] < 250.0


def test_depths_with_the_same_level_give_the_same_domain(tmp_path):
    raster = read_raster(ETOPO)
    depths = xr.DataArray(
        -np.asarray(raster.values, dtype=np.float64),
        dims=("y", "x"),
        coords={"y": raster.y, "x": raster.x},
        attrs={"crs": raster.attrs["crs"], "nodata": -9999.0, "dtype": "float32"},
    )
    path = tmp_path / "depths.tif"
    write_raster(path, depths)
    up = domain_of(case_text("2 m"))
    down = domain_of(case_text("2 m", raster=path, positive="down"))
    assert down.equals(up)
    assert not down.equals(domain_of(case_text("-2 m")))


def test_the_case_meshes_with_the_coast_at_2_m(tmp_path):
    """The issue's case: it stopped with "enclose no sea"; it meshes the flats."""
    path = tmp_path / "case.toml"
    path.write_text(case_text("2 m"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(path, output=tmp_path / "out")
    mesh = read_msh(tmp_path / "out" / "dem_shoreline.msh")
    assert len(mesh.triangles) == result.triangles > 3000
    assert model_rule_breaks(result.mesh, tmp_path / "rules") == []
    assert set(np.unique(mesh.boundary_ids)) == {2, 3, 4, 5, 10}
    # the mesh covers the sea at 2 m, not the sea at 0 m (240 km2 less)
    corners = mesh.points[mesh.triangles]
    area = (
        sum(abs(GEOD.polygon_area_perimeter(c[:, 0], c[:, 1])[0]) for c in corners)
        / 1e6
    )
    assert area == pytest.approx(km2(expected_sea(2.0)), rel=0.005)  # 0.006 %
    assert abs(area - km2(expected_sea(2.0))) < abs(area - km2(expected_sea(0.0)))
    # no node inside the land above 2 m (a node may cut a corner of the coast)
    raster = read_raster(ETOPO, bbox=BOX)
    land = shapely.union_all(land_from_grid(raster.x, raster.y, raster.values, 2.0))
    inland = land.buffer(-5e-4)
    assert not shapely.contains_properly(inland, shapely.points(mesh.points)).any()
    # the raster's samples inside the open boundaries, without the contour:
    # those below 2 m are meshed, those above are not
    lon, lat = np.meshgrid(raster.x.values, raster.y.values)
    inside = (lon > -3.59) & (lon < -2.11) & (lat > 58.56) & (lat < 59.49)
    heights = raster.values[inside]
    samples = shapely.points(lon[inside], lat[inside])
    tree = shapely.STRtree(shapely.polygons(mesh.points[mesh.triangles]))
    meshed = np.zeros(len(samples), dtype=bool)
    meshed[np.unique(tree.query(samples, predicate="intersects")[0])] = True
    assert (heights > 2.0).sum() > 20 and (heights < 2.0).sum() > 100
    np.testing.assert_array_equal(meshed, heights < 2.0)
    # among them a flat: 1 m above the datum, land at 0 m, sea at 2 m
    flat = np.isclose(lon[inside], -2.9) & np.isclose(lat[inside], 59.3)
    assert heights[flat].tolist() == [1.0] and meshed[flat].all()
