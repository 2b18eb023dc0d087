"""Every island of the whole world layer that ``world.toml`` asks for is kept.

The islands are the bundled intermediate GSHHG layer's, every one of them,
measured on the WGS84 ellipsoid by pyproj, apart from the pipeline's own
areas: the check the global case had measured its islands with the same areas
as the pipeline (on the sphere), and an island of 500.8 km2 at 70.9 N (497.1
km2 on the sphere) was dropped from a case of ``min_area = "500 km2"`` without
either seeing it.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pyogrio.raw
import pytest
import shapely
from pyproj import Geod

from coastmesh.case import read_case
from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
from coastmesh.case.pipeline.world import kept_area
from coastmesh.geometry import reproject
from coastmesh.types import quiet_stage, serial_runner

#: the first stages of the world case (about 20 s): run by `pytest -m slow`
pytestmark = pytest.mark.slow

WORLD = Path(__file__).resolve().parents[2] / "examples" / "global" / "world.toml"
WGS84 = Geod(ellps="WGS84")


def _islands(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return the layer's islands: their parts, the island of each, its area.

    An island GSHHG cuts at the antimeridian (ids ``7-E``, ``7-W``) is one;
    the polar land (reaching -90) is the frame round the ocean, not an island.
    """
    meta, _, wkb, values = pyogrio.raw.read(f"/vsizip/{path}")
    ids = np.asarray(dict(zip(meta["fields"], values, strict=True))["id"]).astype(str)
    parts = shapely.from_wkb(wkb)
    island = shapely.bounds(parts)[:, 1] > -89.99
    parts, ids = parts[island], ids[island]
    _, owner = np.unique([i.split("-")[0] for i in ids], return_inverse=True)
    area = np.array([abs(WGS84.geometry_area_perimeter(p)[0]) for p in parts])
    return parts, owner, np.bincount(owner, area)


@pytest.fixture(scope="module")
def world_domain():
    config = read_case(WORLD)
    run = CaseRun(config, strategy_of(config))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for stage in STAGES[:3]:  # shorelines, domain, closing
            run = stage(run, RunContext(1, serial_runner, quiet_stage))
    return config, run


def test_every_island_of_min_area_in_the_world_layer_is_land(world_domain):
    config, run = world_domain
    parts, owner, area = _islands(Path(config.shorelines.path))
    min_area = kept_area(config)
    sea = run.domain.domain.polygon
    shapely.prepare(sea)
    plane = run.shorelines.world.crs
    lost = []
    asked = np.flatnonzero(area >= min_area)
    for k in asked:
        mine = parts[owner == k]
        projected = shapely.make_valid(reproject(mine, "EPSG:4326", plane))
        wet = shapely.area(shapely.intersection(projected, sea)).sum()
        share = wet / shapely.area(projected).sum()
        if share > 0.1:
            lon, lat = shapely.get_coordinates(shapely.centroid(mine[0]))[0]
            lost.append(f"{area[k] / 1e6:.1f} km2 at {lon:.2f}, {lat:.2f}: {share:.0%}")
    assert len(asked) >= 470  # world.toml's layer and min_area: 478
    assert not lost, f"{len(lost)} islands of min_area under the sea: {lost}"
