"""The islands the closing changed, in a global case's shoreline set reports."""

from __future__ import annotations

import dataclasses
import json
import warnings

import numpy as np
import pytest
import shapely

from coastmesh.case import parse_case
from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
from coastmesh.case.pipeline.state import ChangedIsland, ClosingReport
from coastmesh.data import path as data_path
from coastmesh.geometry import EARTH_RADIUS as R
from coastmesh.geometry import reproject
from coastmesh.geometry.closing import earth_areas
from coastmesh.types import quiet_stage, serial_runner

CASE = """
[case]
name = "world_low"

[shorelines]
path = "{world}"
min_area = "2000 km2"

[shoreline_sets.world]
id = 10

[shoreline_sets.shelf]
id = 11

[[regions]]
set = "shelf"
box = [-16.0, 48.0, 26.0, 70.0]

[domain]
kind = "global"
close = "30 km"

[mesh_size]
h_max = "600 km"
cell = "2 deg"

[[mesh_size.gradations]]
lines = ["world"]
h_min = "30 km"
d_grade = "2000 km"
"""


@pytest.fixture(scope="module")
def shorelines(tmp_path_factory):
    """The shoreline stage of a global case on GSHHG's low-resolution world."""
    folder = tmp_path_factory.mktemp("closing_report")
    config = parse_case(
        CASE.format(world=data_path("world_gshhg_l.zip")), folder / "world.toml"
    )
    run = CaseRun(config, strategy_of(config))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = STAGES[0](run, RunContext(1, serial_runner, quiet_stage))
    return run.shorelines


def test_each_set_reports_the_islands_the_closing_changed(shorelines):
    world = shorelines.world
    for name, report in shorelines.reports.items():
        closing = report.closing
        assert closing is not None and closing.width == 30e3, name
        assert 0 < len(closing.changed) <= closing.islands
        assert closing.summary().startswith(f"closing 30 km: {len(closing.changed)} of")
        for change in closing.changed:
            assert -180 <= change.lon <= 180 and -90 <= change.lat <= 90
            assert change.km2_before >= 2000
            if change.polar:
                assert change.km2_after is None
            else:  # changed by more than 10 %
                assert (
                    abs(change.km2_after - change.km2_before) > 0.1 * change.km2_before
                )
        # the point given lies in an island of the area given
        change = next(c for c in closing.changed if not c.polar)
        point = reproject(shapely.Point(change.lon, change.lat), "EPSG:4326", world.crs)
        island = world.islands[shapely.contains(world.islands, point)]
        assert len(island) == 1
        assert earth_areas(island, world.crs)[0] / 1e6 == pytest.approx(
            change.km2_before, rel=1e-3
        )
    # the shelf set is closed near its region only: fewer islands change
    world_set, shelf = shorelines.reports["world"], shorelines.reports["shelf"]
    assert len(shelf.closing.changed) < len(world_set.closing.changed)
    assert all(-30 < c.lon < 40 and 40 < c.lat < 80 for c in shelf.closing.changed)


def test_the_closing_report_goes_to_report_json(shorelines):
    data = shorelines.reports["world"].to_dict()
    assert json.loads(json.dumps(data)) == data
    changed = data["closing"]["changed"]
    assert changed and set(changed[0]) == {
        "lon",
        "lat",
        "km2_before",
        "km2_after",
        "joined",
        "polar",
    }


@pytest.mark.xdist_group("coarse")
def test_summary_txt_counts_the_changed_islands_in_one_line(coarse_case):
    report = coarse_case.report
    assert "the closing changed" not in report.summary()  # a regional case
    changed = (
        ChangedIsland(lon=1.5, lat=60.0, km2_before=900.0, km2_after=1200.0, joined=0),
        ChangedIsland(
            lon=2.0, lat=61.0, km2_before=600.0, km2_after=None, joined=3, polar=True
        ),
    )
    sets = {
        name: dataclasses.replace(
            r, closing=ClosingReport(width=10e3, merged=4, islands=12, changed=changed)
        )
        for name, r in report.shoreline_sets.items()
    }
    text = dataclasses.replace(report, shoreline_sets=sets).summary()
    (line,) = [t for t in text.splitlines() if "the closing changed" in t]
    first = next(iter(sets))
    assert f"{first} 2 of 12" in line
    assert (
        changed[1].summary()
        == "(2.00, 61.00): 600 km2 -> the polar land, joined to 3 more"
    )
    assert np.isclose(changed[0].to_dict()["km2_after"], 1200.0)


def test_without_min_area_land_as_large_as_the_closing_disk_is_kept_whole(tmp_path):
    """With no ``min_area`` (0), a global case keeps the islands of the closing's disk.

    Each island of pi close^2 / 4 or more stays land over 90 % of its area;
    the rocks smaller than that and narrower than ``close``, with no other
    land within 100 km (the closing would join them to it), are gone, not
    grown into islands of the disk's size.
    """
    text = CASE.format(world=data_path("world_gshhg_l.zip"))
    config = parse_case(
        text.replace('min_area = "2000 km2"\n', ""), tmp_path / "w.toml"
    )
    assert config.shorelines.min_area == 0
    run = CaseRun(config, strategy_of(config))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = STAGES[0](run, RunContext(1, serial_runner, quiet_stage))
    world, land = run.shorelines.world, run.shorelines.sets["world"]
    islands = np.asarray(world.islands, dtype=object)
    area = earth_areas(islands, world.crs)  # on WGS84, as min_area is
    disk = np.pi * 15e3**2
    assert run.shorelines.reports["world"].closing.islands == (area >= disk).sum()
    tree, near = shapely.STRtree(land), shapely.STRtree(islands)
    # where the plane's scale is under 2, 100 km there is over 50 km on the Earth
    inner = np.hypot(*shapely.get_coordinates(shapely.centroid(islands)).T) < 2 * R
    kept, rocks = 0, 0
    for i, (island, a) in enumerate(zip(islands, area, strict=True)):
        over = shapely.union_all(land[tree.query(island, "intersects")])
        share = shapely.intersection(island, over).area / island.area
        if a >= disk:
            assert share >= 0.9, (a / 1e6, share)
            kept += 1
        elif (
            inner[i]
            and island.buffer(-7.5e3).is_empty  # narrower than close
            and len(near.query(island, "dwithin", 100e3)) == 1  # itself alone
        ):
            assert share == 0, (a / 1e6, share)
            rocks += 1
    assert kept > 100 and rocks > 10
