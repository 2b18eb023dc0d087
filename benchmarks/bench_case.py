"""Benchmark the domain-to-mesh stages against literal references, side by side.

Run from the repository root (needs the test extras):

    python benchmarks/bench_case.py [--data ../shared/data]

1. Distance to the shoreline: ``distance_to_lines`` (a k-d tree in earth-centred
   coordinates) against one WGS84 geodesic per node and line vertex
   (``tests/reference.py``), on a grid around the Orkney coast.
2. Gradation limit: ``limit_gradation`` (8-direction sweeps) against the
   all-pairs minimum (``tests/reference.py``).
3. Boundary resampling: the example case meshed as coastmesh does it (every
   boundary curve resampled to the local size) and with every raw shoreline
   vertex handed to Gmsh as a point on straight lines (as qmesh-style
   pipelines do), in the same run: time, nodes, and edges far below the target.
4. Whole cases: ``coastmesh run`` in a fresh process each (time, peak memory):
   the Orkney example, and, with ``--data``, a NW European shelf case on the
   full-resolution GSHHG layer (944k points).

Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from pyproj import Geod, Transformer

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from reference import (  # noqa: E402
    distance_to_points_geodesic,
    limit_gradation_brute,
)
from timing import best_time  # noqa: E402

from coastmesh.data import path as data_path  # noqa: E402
from coastmesh.sizing import distance_to_lines, limit_gradation  # noqa: E402

EXAMPLE = ROOT / "examples" / "orkney" / "pentland_firth.toml"
GEOD = Geod(ellps="WGS84")


def bench_distance() -> None:
    print("\n### Distance to the Orkney coast (GSHHG full), metres\n")
    print("| grid | line vertices | reference s | fast s | ratio | max diff (m) |")
    print("|---|---:|---:|---:|---:|---:|")
    features = json.loads(data_path("orkney_gshhg_f.geojson").read_text())
    land = np.array(
        [shapely.from_geojson(json.dumps(f["geometry"])) for f in features["features"]]
    )
    coast = shapely.boundary(land)
    resolution = 50.0
    for n in (20, 40):
        x, y = np.linspace(-3.8, -2.4, n), np.linspace(58.6, 59.4, n)
        fast_s, fast = best_time(
            lambda x=x, y=y: distance_to_lines(
                coast, x, y, crs="EPSG:4326", resolution=resolution
            )
        )
        # the reference gets the vertices the fast code searches (same densifying)
        step = resolution / 111_320.0
        dense = shapely.get_coordinates(shapely.segmentize(coast, step))
        gx, gy = np.meshgrid(x, y)
        ref_s, ref = best_time(
            lambda gx=gx, gy=gy, dense=dense: distance_to_points_geodesic(
                gx.ravel(), gy.ravel(), dense[:, 0], dense[:, 1]
            ),
            repeat=1,
        )
        diff = np.abs(fast.ravel() - ref).max()
        print(
            f"| {n} x {n} | {len(dense):,} | {ref_s:.3f} | {fast_s:.4f} | "
            f"{ref_s / fast_s:.0f} | {diff:.1f} |"
        )
    print(
        "\nThe fast distances are great-circle arcs on a sphere of radius R through "
        "earth-centred chords, the reference WGS84 geodesics: they differ by up to "
        "0.5 % of the distance (by design; see coastmesh.sizing.distance)."
    )


def bench_gradation() -> None:
    print("\n### Gradation limit (rate 0.2), random sizes with a few fine cells\n")
    print("| grid | reference s | fast s | ratio | slope bound holds | below exact |")
    print("|---|---:|---:|---:|---|---|")
    rng = np.random.default_rng(1)
    for n in (32, 64):
        size = np.full((n, n), 5_000.0)
        size[rng.integers(0, n, 8), rng.integers(0, n, 8)] = 100.0
        cell = (250.0, 250.0)
        fast_s, fast = best_time(lambda s=size, c=cell: limit_gradation(s, c, 0.2))
        ref_s, (d, exact) = best_time(
            lambda s=size, c=cell: limit_gradation_brute(s, c, 0.2), repeat=1
        )
        flat = fast.ravel()
        holds = bool(np.all(flat[:, None] <= flat[None, :] + 0.2 * d + 1e-9))
        below = bool(np.all(fast <= exact + 1e-9))
        print(
            f"| {n} x {n} | {ref_s:.3f} | {fast_s:.4f} | {ref_s / fast_s:.0f} | "
            f"{holds} | {below} |"
        )


@contextlib.contextmanager
def raw_boundary():
    """Hand Gmsh every raw boundary vertex, joined by straight lines."""
    from coastmesh.meshing import engine

    def keep_every_vertex(rings, size_at, **_):
        out = []
        for ring in rings:
            out.append(
                [[np.asarray(c)[k : k + 2] for k in range(len(c) - 1)] for c in ring]
            )
        return out, []

    saved = engine.resample_rings
    engine.resample_rings = keep_every_vertex
    try:
        yield
    finally:
        engine.resample_rings = saved


def bench_resampling() -> None:
    from coastmesh.case import run_case

    print("\n### Boundary resampling on the Orkney example (same run)\n")
    print(
        "| boundary given to Gmsh | mesh s | nodes | triangles | boundary edges | "
        "edges < 0.25 target | shortest edge (m) |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, context in (
        ("resampled to the local size (coastmesh)", contextlib.nullcontext),
        ("every raw vertex, straight lines", raw_boundary),
    ):
        with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with context():
                try:
                    result = run_case(EXAMPLE, output=Path(tmp) / "out")
                except Exception as exc:  # the raw boundary may break Gmsh
                    print(f"| {label} | failed: {exc} | | | | | |")
                    continue
            length, target = _edge_lengths(result)
        tiny = int(np.sum(length < 0.25 * target))
        print(
            f"| {label} | {result.report.seconds['meshing']:.2f} | "
            f"{result.nodes:,} | {result.triangles:,} | "
            f"{sum(result.boundary_edges.values()):,} | {tiny:,} | {length.min():.1f} |"
        )


def _edge_lengths(result):
    """Geodesic length of every mesh edge and the target size at its middle (m)."""
    from coastmesh.io import read_msh, read_raster
    from coastmesh.meshing import sample_size
    from coastmesh.types import SizeGrid

    mesh = read_msh(result.output / f"{result.name}.msh")
    tri = mesh.triangles
    pairs = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    edges = np.unique(np.sort(pairs, axis=1), axis=0)
    a, b = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
    _, _, length = GEOD.inv(a[:, 0], a[:, 1], b[:, 0], b[:, 1])
    field = read_raster(result.output / "size.tif").sortby("y")
    to_grid = Transformer.from_crs("EPSG:4326", field.attrs["crs"], always_xy=True)
    middle = np.column_stack(to_grid.transform(*((a + b) / 2).T))
    return length, sample_size(SizeGrid.from_dataarray(field), middle)


NW_SHELF = """
[case]
name = "nw_shelf"
[shorelines]
path = "{data}/uk_northsea_gshhg_f.gpkg"
min_area = "1 km2"
[shoreline_sets.pca_1_500]
id = 12
window = 500
modes = 1
[shoreline_sets.full]
id = 10
[[regions]]
set = "full"
box = [-3.5, 58.6, -2.3, 59.5]
[domain]
seed = [0.0, 56.0]
[[open_boundaries]]
name = "north"
id = 2
kind = "blend"
first = {{ start = [-15.0, 57.0], bearing_west = 20, end_lat = 70.0 }}
second = {{ start = [5.45, 62.0], bearing = 0, end_lat = 70.0 }}
[[open_boundaries]]
name = "west"
id = 3
kind = "loxodrome"
start = [-15.0, 57.0]
end = [-4.0, 48.5]
[[open_boundaries]]
name = "east"
id = 4
kind = "blend"
first = {{ start = [-4.0, 48.5], bearing = 110, end_lon = 25.0 }}
second = {{ start = [5.45, 62.0], bearing = 175, end_lat = 55.0 }}
[mesh_size]
h_max = "1.5 deg"
[[mesh_size.gradations]]
lines = ["pca_1_500"]
h_min = "0.1 deg"
d_grade = "1 deg"
[[mesh_size.gradations]]
lines = ["full"]
h_min = "0.01 deg"
d_hold = "0.02 deg"
d_grade = "1 deg"
"""


def bench_cases(data: Path | None) -> None:
    print("\n### Whole cases, `coastmesh run` in a fresh process\n")
    print("| case | shoreline points in | nodes | triangles | wall s | peak RSS (MB) |")
    print("|---|---:|---:|---:|---:|---:|")
    cases = [("Orkney example (examples/orkney)", EXAMPLE)]
    with tempfile.TemporaryDirectory() as tmp:
        if data is not None:
            path = Path(tmp) / "nw_shelf.toml"
            path.write_text(NW_SHELF.format(data=data.resolve().as_posix()))
            cases.append(("NW shelf, GSHHG full (PCA 1/500 + Orkney full)", path))
        for label, case in cases:
            out = Path(tmp) / f"out-{case.stem}"
            start = time.perf_counter()
            proc = subprocess.run(
                [
                    "/usr/bin/time",
                    "-v",
                    sys.executable,
                    "-m",
                    "coastmesh",
                    "-q",
                    "run",
                    str(case),
                    "-o",
                    str(out),
                ],
                capture_output=True,
                text=True,
                check=True,
            )
            wall = time.perf_counter() - start
            rss = next(
                int(line.split()[-1]) / 1024
                for line in proc.stderr.splitlines()
                if "Maximum resident" in line
            )
            report = json.loads((out / "report.json").read_text())
            points = max(r["points_in"] for r in report["shoreline_sets"].values())
            print(
                f"| {label} | {points:,} | {report['mesh']['nodes']:,} | "
                f"{report['mesh']['triangles']:,} | {wall:.1f} | {rss:.0f} |"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--data", type=Path, help="folder with uk_northsea_gshhg_f.gpkg"
    )
    args = parser.parse_args()
    bench_distance()
    bench_gradation()
    bench_resampling()
    bench_cases(args.data)


if __name__ == "__main__":
    main()
