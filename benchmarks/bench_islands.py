"""Islands a global case keeps: issue 33's "no island lost" target, measured.

Runs a global case's first stages (shorelines, domain, closing) and checks
every island of the input layer of at least ``[shorelines] min_area`` (its
area on the Earth; without one, the closing's disk, ``pi close^2 / 4``: see
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
EARTH_RADIUS = 6_371_008.8


def _domain(config):
    """Run the stages up to the closing; return the run and their times."""
    from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
    from coastmesh.types import quiet_stage, serial_runner

    ctx = RunContext(1, serial_runner, quiet_stage)
    run = CaseRun(config, strategy_of(config))
    for stage in STAGES[:3]:  # shorelines, domain, closing
        run = stage(run, ctx)
    return run, ctx.seconds


def islands_kept(run, min_area: float) -> tuple[list, list]:
    """Return the (area km2, lon, lat, share under sea) of the islands, kept, lost."""
    from coastmesh.geometry import reproject_points

    world = run.shorelines.world
    sea = run.domain.domain.polygon
    shapely.prepare(sea)
    islands = np.asarray(world.islands, dtype=object)
    centres = shapely.get_coordinates(shapely.centroid(islands))
    k = 1.0 + (np.hypot(*centres.T) / (2 * EARTH_RADIUS)) ** 2
    earth = shapely.area(islands) / k**2  # the plane's areas are k^2 larger
    lonlat = reproject_points(centres, world.crs, "EPSG:4326")
    kept, lost = [], []
    for i in np.flatnonzero(earth >= min_area):
        wet = shapely.intersection(islands[i], sea).area / islands[i].area
        row = (earth[i] / 1e6, *lonlat[i], wet)
        (kept if wet <= 0.1 else lost).append(row)
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
    kept, lost = islands_kept(run, min_area)
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
