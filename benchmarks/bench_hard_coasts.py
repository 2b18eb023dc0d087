"""Hard coasts: what the channel and Courant terms and the smoothing cost and buy.

Builds a case in memory (nothing is written) in one of two variants and prints
its quality figures as one JSON line:

- ``after``: the case as it is (channel term on, its Courant term if it has
  one, cleanup with smoothing);
- ``before``: the same case without them (``[mesh_size.channels] enabled =
  false``, no ``[mesh_size.courant]``, no default gradation limit, cleanup
  without smoothing or time-step relief): coastmesh as it was before these
  were added.

Time the two side by side, in turn, as whole processes (wall seconds and
peak memory from ``/usr/bin/time``; the ratio is after / before)::

    C=examples/norway/fjords_mesh.toml
    for run in 1 2 3; do
        for v in before after; do
            /usr/bin/time -f "$v %e s %M KB" \\
                python benchmarks/bench_hard_coasts.py $C $v > /dev/null
        done
    done

and print the quality table of both with ``--table``::

    python benchmarks/bench_hard_coasts.py examples/norway/fjords_mesh.toml --table
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
import warnings

import coastmesh
from coastmesh.case.terms import ChannelConfig
from coastmesh.sizing import DEFAULT_RATE

# the targets
TARGETS = {
    "min_angle_p1": ">= 30",
    "radius_ratio_min_away_from_corners": ">= 0.25",
    "channel_spanning_triangles": "0",
    "time_step_min_over_p1": ">= 0.6",
}


def variant(path: str, which: str) -> coastmesh.CaseConfig:
    """The case, ``after`` as it is or ``before`` without the new terms."""
    case = coastmesh.read_case(path)
    if which == "after":
        return case
    # a case that sets no rate gets the default limit, new with this work
    rate = None if case.size.rate == DEFAULT_RATE else case.size.rate
    size = dataclasses.replace(
        case.size, channels=ChannelConfig(enabled=False), courant=None, rate=rate
    )
    cleanup = dataclasses.replace(case.cleanup, smooth=False, time_step=False)
    return dataclasses.replace(case, size=size, cleanup=cleanup)


def measure(path: str, which: str) -> dict:
    """Build the variant and return its figures."""
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = coastmesh.build_case(variant(path, which))
    seconds = time.perf_counter() - started
    r = result.report
    q = r.quality
    away = q.radius_ratio_away_from_corners or q.radius_ratio
    row = {
        "case": result.name,
        "variant": which,
        "seconds": round(seconds, 2),
        "stage_seconds": r.seconds,
        "triangles": q.triangles,
        "min_angle_min": round(q.min_angle.min, 2),
        "min_angle_p1": round(q.min_angle.p1, 2),
        "radius_ratio_min": round(q.radius_ratio.min, 3),
        "radius_ratio_min_away_from_corners": round(away.min, 3),
        "radius_ratio_below_0_25_away_from_corners": away.below_0_25,
        "sharp_corners": q.corners.sharp,
        "all_boundary_triangles": len(q.all_boundary_triangles),
        "channel_spanning_triangles": len(q.channel_spanning_triangles),
    }
    if q.time_step is not None:
        row["time_step_min_s"] = round(q.time_step.min, 3)
        row["time_step_p1_s"] = round(q.time_step.p1, 3)
        row["time_step_min_over_p1"] = round(q.time_step.min_over_p1, 3)
    if r.cleanup is not None:
        row["cleanup"] = r.cleanup.summary()
    if r.time_step is not None:
        row["time_step_relief"] = r.time_step.summary()
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case")
    parser.add_argument("variant", nargs="?", choices=("before", "after"))
    parser.add_argument("--table", action="store_true", help="both, as a table")
    args = parser.parse_args()
    if not args.table:
        print(json.dumps(measure(args.case, args.variant or "after")))
        return
    rows = [measure(args.case, v) for v in ("before", "after")]
    keys = [k for k in rows[1] if k not in ("case", "variant", "stage_seconds")]
    print(f"| {rows[0]['case']} | before | after | target |")
    print("|---|---|---|---|")
    for k in keys:
        values = [str(row.get(k, "")) for row in rows]
        print(f"| {k} | {values[0]} | {values[1]} | {TARGETS.get(k, '')} |")


if __name__ == "__main__":
    main()
