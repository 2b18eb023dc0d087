"""Benchmark the boundary nodes: the size view along the curves against the whole grid.

Run from the repository root:

    python benchmarks/bench_boundary_nodes.py examples/nw_european_shelf/fine.toml

The case is built up to its meshing (shoreline sets, domain, slots, size
field: about 25 s for the NW-shelf fine case); then, in the same process and in
turn, :func:`coastmesh.meshing.gmsh.boundary_nodes.boundary_nodes` makes the
boundary nodes with Gmsh's size view holding only the grid cells along the curves (as
coastmesh does) and with the whole grid (as before), ``--runs`` times each (on
one Gmsh thread, as always). On a plane grid the nodes must be the same, bit
for bit; on a global case's grid on the sphere, whose view Gmsh searches
through an octree from the element it found last, two views of different cells
can give a node on a cell's edge two values that differ in the last bits, so
there they must be within 1e-6 m (``world.toml``: 4.7e-10 m). Prints a
Markdown table: min and median seconds, and the ratio of the medians.

With ``--workers N`` (N > 1) it then times, in turn, a boundary of more than
``BATCH_CURVES`` curves made in one Gmsh session, in its ``BATCHES`` batches
one after the other, and in those batches on a local pool of N workers (as
``coastmesh run -w N`` makes it); the batches must give the same nodes, bit
for bit, in turn and on the workers::

    python benchmarks/bench_boundary_nodes.py examples/global/world.toml --workers 2
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
    parser.add_argument("--workers", type=int, default=1)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    from coastmesh.meshing.gmsh import boundary_nodes as curves
    from coastmesh.meshing.gmsh.model import grid_view_data

    rings, ids, size = case_boundary(args.case)
    along = curves._along
    cells = {}
    seen = curves.add_size_view

    def counted(gmsh, grid, bounds, near=None):
        if hasattr(grid, "view_data"):  # a SphereSizeGrid: quadrangles, triangles
            data = grid.view_data(bounds, near)
            count = len(data["SQ"]) // 16 + len(data["ST"]) // 12
        else:
            count = len(grid_view_data(grid, bounds, near)) // 16
        cells[near is not None] = cells.get(near is not None, 0) + count
        seen(gmsh, grid, bounds, near)

    curves.add_size_view = counted
    times: dict[str, list[float]] = {}
    nodes = {}
    for _ in range(args.runs):
        cells.clear()  # summed over a run's batches
        for how in ("along the curves", "whole grid"):
            curves._along = along if how == "along the curves" else (lambda *a: None)
            started = time.perf_counter()
            pieces, _ = curves.boundary_nodes(rings, ids, size)
            times.setdefault(how, []).append(time.perf_counter() - started)
            nodes[how] = np.concatenate([p for p, _ in pieces])
    same = np.array_equal(nodes["along the curves"], nodes["whole grid"])
    count = len(nodes["whole grid"])
    apart = _apart(nodes["along the curves"], nodes["whole grid"])
    print(
        f"{args.case}: {count:,} boundary nodes, the same bit for bit: {same}"
        f"{apart}; view cells {cells[True]:,} along the curves, "
        f"{cells[False]:,} whole"
    )
    print("\n| view | min s | median s | whole / along (medians) |")
    print("|---|---:|---:|---:|")
    whole = statistics.median(times["whole grid"])
    for how in ("along the curves", "whole grid"):
        t = times[how]
        along_curves = how == "along the curves"
        ratio = f"{whole / statistics.median(t):.2f}" if along_curves else ""
        print(f"| {how} | {min(t):.2f} | {statistics.median(t):.2f} | {ratio} |")
    close = len(nodes["along the curves"]) == count and np.allclose(
        nodes["along the curves"], nodes["whole grid"], rtol=0.0, atol=1e-6
    )
    if not (same or (close and hasattr(size, "view_data"))):
        sys.exit("the boundary nodes differ")
    curves._along = along
    if args.workers > 1:
        on_workers(rings, ids, size, args.workers, args.runs)


def _apart(a, b) -> str:
    """Return how far apart two node arrays are, for the report; '' if equal."""
    if np.array_equal(a, b):
        return ""
    if a.shape != b.shape:
        return f" ({len(a):,} nodes against {len(b):,})"
    return f" (at most {np.abs(a - b).max():.1e} apart, in the plane's metres)"


def on_workers(rings, ids, size, workers: int, runs: int) -> None:
    """Time the boundary in one session, in batches in turn, and on workers."""
    from coastmesh.case.executor import open_runner
    from coastmesh.case.processes import start_server
    from coastmesh.meshing.gmsh import boundary_nodes as curves
    from coastmesh.types import serial_runner

    start_server()
    count = sum(len(ring) for ring in curves._ring_pieces(rings, ids))
    limit = curves.BATCH_CURVES
    times: dict[str, list[float]] = {}
    nodes = {}
    with open_runner(workers) as pool:
        for _ in range(runs):
            for how, most, runner in (
                ("one session", 10**9, serial_runner),
                ("batches in turn", limit, serial_runner),
                (f"batches on {workers} workers", limit, pool),
            ):
                curves.BATCH_CURVES = most
                started = time.perf_counter()
                pieces, _ = curves.boundary_nodes(rings, ids, size, runner)
                times.setdefault(how, []).append(time.perf_counter() - started)
                nodes[how] = np.concatenate([p for p, _ in pieces])
    curves.BATCH_CURVES = limit
    batched = len(curves._batches(curves._ring_pieces(rings, ids), size))
    same = np.array_equal(
        nodes["batches in turn"], nodes[f"batches on {workers} workers"]
    )
    print(
        f"\n{count:,} curves, {batched} batches; the batches' nodes the same bit "
        f"for bit in turn and on the workers: {same}"
    )
    print("\n| boundary nodes | min s | median s | one session / this (medians) |")
    print("|---|---:|---:|---:|")
    one = statistics.median(times["one session"])
    for how, t in times.items():
        print(
            f"| {how} | {min(t):.2f} | {statistics.median(t):.2f} | "
            f"{one / statistics.median(t):.2f} |"
        )
    if not same:
        sys.exit("the batches' nodes differ on the workers")


if __name__ == "__main__":
    main()
