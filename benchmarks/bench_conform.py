"""Sizes held (``conform_sizes``): its sweeps against the literal loops, and its cost.

1. **One sweep** of the springs (``_relax``) and of the settling
   (``_settle``) on Gmsh's lattice of a square of sea at 50 m, against the
   literal loops of ``tests/meshing/cleanup/test_conform.py`` (node by node,
   triangle by triangle, in Python), measured in the same run; the results
   agree to 1e-9 m (checked here too).
2. **The whole pass** on squares of 2, 6 and 12 km (about 3,800, 33,000 and
   133,000 triangles), every node in the zone: its time, and the share of the
   elements within 10 % of the size before and after.

Every time is the minimum, median and maximum of ``--runs`` runs. Run from
the repository root::

    python benchmarks/bench_conform.py [--runs 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "meshing" / "cleanup"))
sys.path.insert(0, str(ROOT / "tests"))

from test_conform import _settle_loop, _square_mesh, _sweep_loop  # noqa: E402

from coastmesh.meshing.cleanup.conform import (  # noqa: E402
    _relax,
    _settle,
    conform_sizes,
)


def timed(fn, runs: int) -> tuple[list[float], object]:
    """Run ``fn`` ``runs`` times; its wall times and last result."""
    times, out = [], None
    for _ in range(runs):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return times, out


def row(label: str, times: list[float]) -> str:
    return (
        f"| {label} | {min(times):.4f} | {statistics.median(times):.4f} | "
        f"{max(times):.4f} |"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=5)
    args = p.parse_args(argv)

    mesh = _square_mesh(side=2000.0)
    xy = np.asarray(mesh.points, dtype=np.float64)
    tri = np.asarray(mesh.triangles, dtype=np.int64)
    goal = np.asarray(mesh.point_data["size"], dtype=np.float64)
    movable = np.ones(len(xy), dtype=bool)
    movable[np.unique(mesh.boundary_edges)] = False
    print(f"## 1. One sweep, {len(tri):,} triangles, {movable.sum():,} nodes moving\n")
    print("| sweep | min s | median s | max s | literal / fast (median) |")
    print("|---|---:|---:|---:|---:|")
    cases = [
        (
            "springs (`_relax`)",
            lambda: _relax(xy, tri, goal, movable, 30.0, 1, 0.2)[0],
            lambda: _sweep_loop(xy, tri, goal, movable, 30.0, 0.2),
        ),
        (
            "settling (`_settle`)",
            lambda: _settle(xy, tri, goal, movable, 30.0, 1, 0.1)[0],
            lambda: _settle_loop(xy, tri, goal, movable, 30.0, 0.1)[0],
        ),
    ]
    for label, fast, slow in cases:
        t_fast, a = timed(fast, args.runs)
        t_slow, b = timed(slow, max(1, args.runs // 2))
        assert np.allclose(a, b, atol=1e-9, rtol=0), label
        ratio = statistics.median(t_slow) / statistics.median(t_fast)
        print(row(f"{label}, numpy", t_fast) + " |")
        print(row(f"{label}, literal loop", t_slow) + f" {ratio:,.0f} |")

    print("\n## 2. The whole pass, every node of a square of sea in the zone\n")
    print(
        "| square | triangles | min s | median s | max s | within 10 % before "
        "-> after | worst before -> after | nodes moved, taken out |"
    )
    print("|---|---:|---:|---:|---:|---|---|---|")
    for side in (2000.0, 6000.0, 12000.0):
        mesh = _square_mesh(side=side)
        zone = np.ones(len(mesh.points), dtype=bool)
        times, (_, report) = timed(
            lambda m=mesh, z=zone: conform_sizes(m, z), args.runs
        )
        print(
            f"| {side / 1000:g} km | {len(mesh.triangles):,} | {min(times):.2f} | "
            f"{statistics.median(times):.2f} | {max(times):.2f} | "
            f"{report.within_before:.2%} -> {report.within_after:.2%} | "
            f"{report.worst_before:.0%} -> {report.worst_after:.0%} | "
            f"{report.nodes_moved:,}, {report.nodes_removed} |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
