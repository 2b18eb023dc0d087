"""Benchmark the boundary nodes: the size view along the curves against the whole grid.

Run from the repository root:

    python benchmarks/bench_boundary_nodes.py examples/nw_european_shelf/fine.toml

The case is built up to its meshing (shoreline sets, domain, slots, size
field: about 25 s for the NW-shelf fine case); then, in the same process and in
turn, :func:`coastmesh.meshing.gmsh.boundary_nodes.boundary_nodes` makes the
boundary nodes with Gmsh's size view holding only the grid cells along the curves (as
coastmesh does) and with the whole grid (as before), ``--runs`` times each (on
one Gmsh thread, as always). The nodes must be the same, bit for bit. Prints a
Markdown table: min and median seconds, and the ratio of the medians.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np


class _Captured(Exception):
    """Raised to stop the case at its meshing, with what it would mesh."""


def case_boundary(case: Path):
    """Return the case's resampled boundary rings, their ids, and the size grid."""
    from coastmesh.case import build as build_module
    from coastmesh.case.pipeline import mesh as mesh_stage_module
    from coastmesh.geometry.projection import project_rings, sample_size, to_map_units
    from coastmesh.meshing.gmsh.resample import resample_rings

    def capture(domain, size, **kwargs):
        raise _Captured(domain, size, kwargs["mesh_crs"])

    # this process only: stop at the meshing stage's call
    mesh_stage_module.mesh_in_parts = capture
    try:
        build_module.build_case(case, workers=1)
    except _Captured as stop:
        domain, size, mesh_crs = stop.args
    else:
        raise SystemExit(f"{case}: the case did not reach its meshing")
    map_size = to_map_units(size, mesh_crs)
    rings, ids = project_rings(domain, mesh_crs)
    resampled, dropped = resample_rings(rings, lambda xy: sample_size(map_size, xy))
    ids = [ring_ids for r, ring_ids in enumerate(ids) if r not in set(dropped)]
    return resampled, ids, map_size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", type=Path)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    from coastmesh.meshing.gmsh import boundary_nodes as curves
    from coastmesh.meshing.gmsh.model import grid_view_data

    rings, ids, size = case_boundary(args.case)
    along = curves._along
    cells = {}
    seen = curves.add_size_view

    def counted(gmsh, grid, bounds, near=None):
        cells[near is not None] = len(grid_view_data(grid, bounds, near)) // 16
        seen(gmsh, grid, bounds, near)

    curves.add_size_view = counted
    times: dict[str, list[float]] = {}
    nodes = {}
    for _ in range(args.runs):
        for how in ("along the curves", "whole grid"):
            curves._along = along if how == "along the curves" else (lambda *a: None)
            started = time.perf_counter()
            pieces, _ = curves.boundary_nodes(rings, ids, size)
            times.setdefault(how, []).append(time.perf_counter() - started)
            nodes[how] = np.concatenate([p for p, _ in pieces])
    same = np.array_equal(nodes["along the curves"], nodes["whole grid"])
    count = len(nodes["whole grid"])
    print(
        f"{args.case}: {count:,} boundary nodes, the same bit for bit: {same}; "
        f"view cells {cells[True]:,} along the curves, {cells[False]:,} whole"
    )
    print("\n| view | min s | median s | whole / along (medians) |")
    print("|---|---:|---:|---:|")
    whole = statistics.median(times["whole grid"])
    for how in ("along the curves", "whole grid"):
        t = times[how]
        along_curves = how == "along the curves"
        ratio = f"{whole / statistics.median(t):.2f}" if along_curves else ""
        print(f"| {how} | {min(t):.2f} | {statistics.median(t):.2f} | {ratio} |")
    if not same:
        sys.exit("the boundary nodes differ")


if __name__ == "__main__":
    main()
