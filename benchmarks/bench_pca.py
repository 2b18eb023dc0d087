"""Benchmark the PCA kernels against the literal reference, side by side.

Run from the repository root (needs the test extras and the developer data set):

    python benchmarks/bench_pca.py [--data ../shared/data] [--quick]

For every shoreline ring of 5,000 points or more, and for rasters with 8 x 8
windows, it times the fast kernel (``coastmesh.pca``) and the literal reference
(``tests/reference.py``: the explicit L x M partition matrix, a dense
eigendecomposition and offset-by-offset averaging), both on the same input in the
same run, checks they agree, and prints a Markdown table of times and ratios.
The 1000 x 1000, 2000 x 2000 and 4000 x 4000 grids are the NW-shelf ETOPO1 grid
resampled with cubic splines (scipy.ndimage.zoom), so real relief at finer spacing;
at 4000 x 4000 the reference needs about 25 GB and is not run.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pyogrio.raw
import rasterio
import scipy.ndimage
import shapely

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from reference import simplify_contour_dense, simplify_raster_dense  # noqa: E402
from timing import best_time  # noqa: E402

from coastmesh.pca import simplify_contour, simplify_raster  # noqa: E402


def rings_of(path: Path, min_points: int):
    _, _, wkb, _ = pyogrio.raw.read(path)
    rings = shapely.get_rings(shapely.get_parts(shapely.from_wkb(wkb)))
    n = shapely.get_num_coordinates(rings) - 1
    return [shapely.get_coordinates(r)[:-1] for r in rings[n >= min_points]]


def bench_shorelines(data: Path, quick: bool):
    print("\n### Shorelines: every ring of 5,000 points or more, closed\n")
    print(
        "| file | ring points | L | r | reference s | fast s | ratio | max diff (deg) |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    totals = {}
    for name in ("norway_west_gshhg_f.geojson", "uk_northsea_gshhg_f.gpkg"):
        rings = rings_of(data / name, 5000)
        if quick:
            rings = rings[:2]
        for window in (100, 500):
            for modes in (1, 5):
                for xy in rings:
                    t_ref, ref = best_time(
                        lambda xy=xy, w=window, r=modes: simplify_contour_dense(
                            xy, w, r, closed=True
                        ),
                        1 if len(xy) > 20000 else 3,
                    )
                    t_fast, fast = best_time(
                        lambda xy=xy, w=window, r=modes: simplify_contour(
                            xy, w, r, closed=True
                        ),
                        5,
                    )
                    diff = np.abs(fast - ref).max()
                    key = (window, modes)
                    a, b = totals.get(key, (0.0, 0.0))
                    totals[key] = (a + t_ref, b + t_fast)
                    print(
                        f"| {name} | {len(xy):,} | {window} | {modes} | {t_ref:.4f} "
                        f"| {t_fast:.4f} | {t_ref / t_fast:.1f} | {diff:.1e} |"
                    )
    print("\n| all rings >= 5,000 points | L | r | reference s | fast s | ratio |")
    print("|---|---:|---:|---:|---:|---:|")
    for (window, modes), (a, b) in sorted(totals.items()):
        print(f"| total | {window} | {modes} | {a:.3f} | {b:.3f} | {a / b:.1f} |")


def bench_rasters(data: Path, quick: bool):
    with rasterio.open(data / "etopo1_0.1deg_nwshelf.tif") as src:
        shelf = src.read(1).astype(float)
    with rasterio.open(data / "etopo1_0.1deg_orkney_wide.tif") as src:
        orkney = src.read(1).astype(float)
    grids = {
        "etopo1 orkney 51x101": orkney,
        "etopo1 nwshelf 221x421": shelf,
        "nwshelf resampled 1000x1000": scipy.ndimage.zoom(
            shelf, (1000 / 221, 1000 / 421), order=3
        ),
    }
    if not quick:
        grids["nwshelf resampled 2000x2000"] = scipy.ndimage.zoom(
            shelf, (2000 / 221, 2000 / 421), order=3
        )
        grids["nwshelf resampled 4000x4000"] = scipy.ndimage.zoom(
            shelf, (4000 / 221, 4000 / 421), order=3
        )
    print("\n### Rasters: 8 x 8 windows\n")
    print("| grid | r | reference s | fast s | ratio | max diff (m) | max rel diff |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, grid in grids.items():
        for modes in (1, 16, 48):
            big = grid.size > 5_000_000
            t_fast, fast = best_time(
                lambda g=grid, r=modes: simplify_raster(g, 8, r), 1 if big else 3
            )
            if grid.size > 10_000_000:
                print(f"| {name} | {modes} | not run (~25 GB) | {t_fast:.3f} | | | |")
                continue
            t_ref, ref = best_time(
                lambda g=grid, r=modes: simplify_raster_dense(g, 8, r), 1 if big else 2
            )
            diff = np.abs(fast - ref).max()
            rel = diff / np.abs(ref).max()
            print(
                f"| {name} | {modes} | {t_ref:.3f} | {t_fast:.4f} "
                f"| {t_ref / t_fast:.1f} | {diff:.1e} | {rel:.1e} |"
            )


def bench_cli(data: Path):
    print("\n### Command line: whole uk_northsea_gshhg_f.gpkg, L = 100, r = 1\n")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.gpkg"
        cmd = [
            sys.executable,
            "-m",
            "coastmesh",
            "simplify-shoreline",
            str(data / "uk_northsea_gshhg_f.gpkg"),
            str(out),
            "--window",
            "100",
            "--modes",
            "1",
        ]
        start = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
        elapsed = time.perf_counter() - start
    print(
        f"`coastmesh simplify-shoreline` wall time: {elapsed:.2f} s "
        f"(exit {done.returncode})\n\n    {done.stdout.strip()}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--quick", action="store_true", help="fewer rings and grids")
    args = parser.parse_args()
    print(f"numpy {np.__version__}, {sys.platform}, data {args.data}")
    bench_shorelines(args.data, args.quick)
    bench_rasters(args.data, args.quick)
    bench_cli(args.data)


if __name__ == "__main__":
    main()
