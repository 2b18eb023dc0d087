"""Model-ready on default keys: the targets of issue 31, measured case by case.

Builds each case in memory (``coastmesh.build_case``; nothing is written) and
prints one markdown row per case:

- ``triangles``;
- ``p01 angle``: the 1st percentile of the minimum angle (target >= 30 deg);
- ``rr away``: the smallest radius ratio of the triangles that touch no
  boundary corner sharper than 45 deg (target >= 0.25);
- ``spanning``: triangles that span a channel one element wide (target 0);
- ``dt min/p1``: the worst element's stable time step over the 1st
  percentile's (target >= 0.6);
- ``on land``: the share of nodes the rasters put on land (depth <= 0 m);
- ``land values``: sea nodes whose depth holds a land cell's value (target 0),
  as the depth report counts them (``DepthReport.land_values``; ``n/a`` on
  code without it) / as measured here from the raster: nodes with a land cell
  (elevation >= 0 m) of non-zero bilinear weight among their four whose depth
  is the plain bilinear mix, or <= 0 m; ``n/a`` for PCA-approximated or
  stacked sources;
- ``at floor``: nodes at ``[bathymetry] min_depth`` (the examples give 5 m),
  or dry (<= 0 m) when the case gives none, as the coasts do (target < 2 %
  where the raster resolves the coast);
- ``seconds``: wall time of ``build_case`` (best of ``--repeat``);
- ``fails``: the targets missed.

The default cases are the hard coasts of ``tests/data/coasts`` (default keys
only) and four examples. Run from the repository root::

    python benchmarks/bench_model_ready.py                      # all, a table
    python benchmarks/bench_model_ready.py tests/data/coasts/oresund.toml
    python benchmarks/bench_model_ready.py --json               # JSON lines

Today's code against another checkout of it, side by side: each case is built
in a fresh process under each code in turn (old, new, old, new, ...; the best
of ``--repeat``), and the table gains the ratio of the wall times (target
new / old <= 1.25)::

    python benchmarks/bench_model_ready.py --compare /work/snap/src --repeat 2

(about 20 minutes on 2 cores), which is the same as running, for each case,
in turn::

    PYTHONPATH=/work/snap/src python benchmarks/bench_model_ready.py CASE --json
    python benchmarks/bench_model_ready.py CASE --json
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
import traceback
import warnings
from pathlib import Path

import numpy as np

import coastmesh

ROOT = Path(__file__).resolve().parents[1]
COASTS = ROOT / "tests" / "data" / "coasts"
CASES = (
    COASTS / "vestfjorden.toml",
    COASTS / "shetland.toml",
    COASTS / "oresund.toml",
    ROOT / "examples" / "orkney" / "pentland_firth.toml",
    ROOT / "examples" / "nw_european_shelf" / "coarse.toml",
    ROOT / "examples" / "nw_european_shelf" / "intermediate.toml",
    ROOT / "examples" / "norway" / "fjords_mesh.toml",
)
#: the issue's targets, by row key
TARGETS = {
    "min_angle_p1": lambda v: v >= 30.0,
    "radius_ratio_away": lambda v: v >= 0.25,
    "channel_spanning": lambda v: v == 0,
    "time_step_min_over_p1": lambda v: v >= 0.6,
    "land_values": lambda v: v == 0,
    "land_values_measured": lambda v: v == 0,
    "at_floor_share": lambda v: v < 0.02,
}
COST_TARGET = 1.25


def measure(path: str | Path, *, repeat: int = 1, workers: int | None = None) -> dict:
    """Build the case ``repeat`` times; return its figures (best wall time)."""
    seconds, result = np.inf, None
    for _ in range(repeat):
        case = coastmesh.read_case(path)
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = coastmesh.build_case(case, workers=workers)
        seconds = min(seconds, time.perf_counter() - started)
    return {"path": str(path), "seconds": round(seconds, 2)} | figures(result)


def figures(result) -> dict:
    """The row of a built case: quality, time step, depth, targets missed."""
    q, d = result.report.quality, result.report.depth
    away = q.radius_ratio_away_from_corners or q.radius_ratio
    ts = q.time_step
    row = {
        "case": result.report.case,
        "code": str(Path(coastmesh.__file__).parents[1]),
        "nodes": q.nodes,
        "triangles": q.triangles,
        "min_angle_p1": round(q.min_angle.p1, 2),
        "radius_ratio_away": round(away.min, 3),
        "sharp_corners": q.corners.sharp,
        "channel_spanning": len(q.channel_spanning_triangles),
        "time_step_min_over_p1": None if ts is None else round(ts.min_over_p1, 3),
    }
    if d is not None:
        depth = result.mesh.point_data["depth"]
        floor = result.config.bathymetry.min_depth
        at_floor = int((depth <= (floor or 0.0) + 1e-6).sum())
        row |= {
            "land_share": round(d.land / d.nodes, 4),
            "land_values": getattr(d, "land_values", None),
            "land_values_measured": land_valued_nodes(result),
            "min_depth": floor,
            "below_min_depth": d.below_min_depth,
            "at_floor": at_floor,
            "at_floor_share": round(at_floor / d.nodes, 4),
        }
    row["fails"] = [
        key
        for key, ok in TARGETS.items()
        if row.get(key) is not None and not ok(row[key])
    ]
    return row


def land_valued_nodes(result) -> int | None:
    """Sea nodes whose depth is a bilinear mix with a land cell, or <= 0 m.

    Measured from the case's ``[bathymetry]`` raster itself; None where the
    depths do not come from one raster as it is (PCA windows, stacks).
    """
    from pyproj import Transformer

    from coastmesh.io import read_raster

    b = result.config.bathymetry
    if b is None or b.sources or getattr(b, "window", None) is not None:
        return None
    mesh = result.mesh
    z = read_raster(b.path)
    to_raster = Transformer.from_crs(mesh.crs, z.attrs["crs"], always_xy=True)
    px, py = to_raster.transform(mesh.points[:, 0], mesh.points[:, 1])
    z = z.sortby("y").sortby("x")
    elevation = z.values if b.positive == "up" else -z.values
    (i, tx), (j, ty) = _cell(z.x.values, px), _cell(z.y.values, py)
    cells = elevation[j[:, None] + [0, 0, 1, 1], i[:, None] + [0, 1, 0, 1]]
    weights = np.column_stack([1 - ty, 1 - ty, ty, ty]) * np.column_stack(
        [1 - tx, tx, 1 - tx, tx]
    )
    land = ((cells >= 0) & (weights > 0)).any(axis=1)  # depth <= 0 m
    plain = -(weights * cells).sum(axis=1)
    depth = mesh.point_data["depth"]
    mixed = np.isclose(depth, plain, rtol=1e-9, atol=1e-6) | (depth <= 0)
    return int((land & mixed).sum())


def _cell(centres: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lower cell index of each point and its weight along one axis."""
    i = np.clip(np.searchsorted(centres, p) - 1, 0, len(centres) - 2)
    t = np.clip((p - centres[i]) / (centres[i + 1] - centres[i]), 0.0, 1.0)
    return i, t


def in_process(path: str | Path, src: str | None, repeat: int, workers) -> dict:
    """Measure one case in a fresh process under the code at ``src``."""
    src = src or str(Path(coastmesh.__file__).parents[1])
    command = [sys.executable, __file__, str(path), "--json", "--repeat", str(repeat)]
    if workers is not None:
        command += ["--workers", str(workers)]
    run = subprocess.run(
        command,
        env=os.environ | {"PYTHONPATH": src},
        capture_output=True,
        text=True,
        check=False,
    )
    lines = run.stdout.strip().splitlines()
    if run.returncode or not lines:
        return {"path": str(path), "code": src, "error": run.stderr.strip()[-2000:]}
    return json.loads(lines[-1])


def compare(paths, old: str, repeat: int, workers) -> list[dict]:
    """Each case under ``old`` and today's code in turn; the best of ``repeat``."""
    rows = []
    for path in paths:
        best: dict[str, dict] = {}
        for _ in range(repeat):
            for side, src in (("old", old), ("new", None)):
                row = in_process(path, src, 1, workers)
                if side not in best or row.get("seconds", np.inf) < best[side].get(
                    "seconds", np.inf
                ):
                    best[side] = row
        ratio = None
        if "seconds" in best["old"] and "seconds" in best["new"]:
            ratio = round(best["new"]["seconds"] / best["old"]["seconds"], 2)
        rows += [
            best["old"] | {"side": "old"},
            best["new"] | {"side": "new", "ratio": ratio},
        ]
    return rows


def table(rows: list[dict]) -> str:
    """The rows as a markdown table."""
    head = (
        "| case | code | triangles | p01 angle | rr away | spanning | dt min/p1 | "
        "on land | land values (report / measured) | at floor | seconds | fails |"
    )
    lines = [head, "|---" * head.count(" | ") + "|---|"]
    for r in rows:
        code = r.get("side", Path(r.get("code", "?")).parent.name)
        if "error" in r:
            lines.append(
                f"| {'/'.join(Path(r['path']).parts[-2:])} | {code} | error: "
                f"{r['error'].splitlines()[-1] if r['error'] else '?'} |"
            )
            continue
        seconds = f"{r['seconds']:.1f}"
        if r.get("ratio") is not None:
            ok = "" if r["ratio"] <= COST_TARGET else " (over 1.25)"
            seconds += f" ({r['ratio']:.2f}x old{ok})"
        lines.append(
            f"| {r['case']} | {code} | {r['triangles']:,} | {r['min_angle_p1']:.1f} | "
            f"{r['radius_ratio_away']:.3f} | {r['channel_spanning']} | "
            f"{_text(r['time_step_min_over_p1'])} | {_share(r.get('land_share'))} | "
            f"{_text(r.get('land_values'))} / {_text(r.get('land_values_measured'))} | "
            f"{r.get('at_floor', 'n/a')} ({_share(r.get('at_floor_share'))}) | "
            f"{seconds} | {', '.join(r['fails']) or '-'} |"
        )
    lines.append(
        "| target | | | >= 30 | >= 0.25 | 0 | >= 0.6 | | 0 / 0 | < 2 % | "
        f"<= {COST_TARGET}x old | |"
    )
    return "\n".join(lines)


def _text(value) -> str:
    return "n/a" if value is None else f"{value:g}"


def _share(value) -> str:
    return "n/a" if value is None else f"{100 * value:.1f} %"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", default=[str(p) for p in CASES])
    parser.add_argument("--json", action="store_true", help="one JSON line a case")
    parser.add_argument("--repeat", type=int, default=1, help="best of N builds")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument(
        "--compare", metavar="OLD_SRC", help="also time the code at OLD_SRC, in turn"
    )
    args = parser.parse_args()
    if args.compare:
        rows = compare(args.cases, args.compare, args.repeat, args.workers)
    else:
        rows = []
        for path in args.cases:
            try:
                row = measure(path, repeat=args.repeat, workers=args.workers)
            except Exception:  # a case that fails is a row, not the end
                row = {"path": str(path), "error": traceback.format_exc()}
            rows.append(row)
            if args.json:
                print(json.dumps(row), flush=True)
    if args.compare and args.json:
        for row in rows:
            print(json.dumps(row))
    elif not args.json:
        print(table(rows))


if __name__ == "__main__":
    main()
