"""Islands a global case keeps: issue 33's "no island lost" target, measured.

Runs a global case's first stages (shorelines, domain, closing) and checks
every island of the input layer of at least ``[shorelines] min_area`` (its
area on the WGS84 ellipsoid, by pyproj; without one, the closing's disk,
``pi close^2 / 4``: see
:func:`coastmesh.case.pipeline.world.kept_area`): it is kept if the sea
covers at most 10 % of it (a hole of the domain with at least 90 % of its
area). Prints the islands lost, the
counts, and the stages' times.

Run from the repository root::

    python benchmarks/bench_islands.py                               # world.toml
    python benchmarks/bench_islands.py path/to/global_case.toml
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "global" / "world.toml"


def _domain(config):
    """Run the stages up to the closing; return the run and their times."""
    from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
    from coastmesh.types import quiet_stage, serial_runner

    ctx = RunContext(1, serial_runner, quiet_stage)
    run = CaseRun(config, strategy_of(config))
    for stage in STAGES[:3]:  # shorelines, domain, closing
        run = stage(run, ctx)
    return run, ctx.seconds


def islands_kept(run, config, min_area: float) -> tuple[list, list]:
    """Return the (area km2, lon, lat, share under sea) of the islands, kept, lost.

    The islands are the input layer's polygons, measured on the WGS84
    ellipsoid by pyproj (not by the pipeline's own areas: an island measured
    on the sphere at 70.9 N came out under ``min_area`` and was dropped, and
    this check, which used the same areas, did not see it).
    """
    import pyogrio.raw
    from pyproj import Geod

    from coastmesh.geometry import reproject

    path = str(config.shorelines.path)
    meta, _, wkb, values = pyogrio.raw.read(
        f"/vsizip/{path}" if path.endswith(".zip") else path
    )
    ids = np.asarray(dict(zip(meta["fields"], values, strict=True))["id"]).astype(str)
    polygons = shapely.from_wkb(wkb)
    polar = shapely.bounds(polygons)[:, 1] <= -89.99  # Antarctica: the frame
    polygons, ids = polygons[~polar], ids[~polar]
    # an island GSHHG cuts at the antimeridian is one island: ids "7-E", "7-W"
    island = np.array([i.split("-")[0] for i in ids])
    geod = Geod(ellps="WGS84")
    area = np.array([abs(geod.geometry_area_perimeter(p)[0]) for p in polygons])
    _, of = np.unique(island, return_inverse=True)
    total = np.bincount(of, area)
    crs = run.shorelines.world.crs
    sea = run.domain.domain.polygon
    shapely.prepare(sea)
    kept, lost = [], []
    for k in np.flatnonzero(total >= min_area):
        parts = np.flatnonzero(of == k)
        plane = shapely.make_valid(reproject(polygons[parts], "EPSG:4326", crs))
        wet = shapely.area(shapely.intersection(plane, sea)) / shapely.area(plane)
        share = float(np.average(wet, weights=area[parts]))
        lon, lat = shapely.get_coordinates(shapely.centroid(polygons[parts[0]]))[0]
        row = (total[k] / 1e6, lon, lat, share)
        (kept if share <= 0.1 else lost).append(row)
    return kept, lost


def main(argv: list[str] | None = None) -> int:
    """Run the stages, check the islands, print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", nargs="?", default=str(CASE))
    args = parser.parse_args(argv)
    import coastmesh

    config = coastmesh.read_case(args.case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        started = time.perf_counter()
        run, seconds = _domain(config)
        wall = time.perf_counter() - started
    from coastmesh.case.pipeline.world import kept_area

    min_area = kept_area(config)
    kept, lost = islands_kept(run, config, min_area)
    print(
        f"{args.case}: {len(kept) + len(lost)} islands of >= "
        f"{min_area / 1e6:g} km2; kept {len(kept)}, lost "
        f"{len(lost)} ({sum(r[0] for r in lost):,.0f} km2); stages {wall:.1f} s: "
        + ", ".join(f"{k} {v:.1f} s" for k, v in seconds.items())
    )
    if lost:
        print("| area (km2) | lon | lat | share under the sea |")
        print("|---|---|---|---|")
        for area, lon, lat, wet in sorted(lost, reverse=True):
            print(f"| {area:,.0f} | {lon:.2f} | {lat:.2f} | {wet:.0%} |")
    return 1 if lost else 0


if __name__ == "__main__":
    sys.exit(main())
