"""``coastmesh simplify-raster`` streamed (Dask, strips of rows) against in memory.

Run from the repository root:

    python benchmarks/bench_raster_stream.py          # 6,000, 10,000 and 20,000
    python benchmarks/bench_raster_stream.py --sizes 2000 --workers 2 --folder /tmp/b

For each size it writes a synthetic float32 GeoTIFF into a temporary folder
(tiled, deflate), generated in strips of rows so the generator's own memory
stays bounded: a smooth bathymetry-like field (two spline surfaces of random
control points, 400 and 50 cells apart), 2 m of noise, and land above 0 m set to
nodata (about 11 % of the cells, so there are coasts and islands).

Then it runs, each as its own process, timed from outside (start-up, reading and
writing included):

- ``stream``: ``coastmesh simplify-raster SRC DST --window 8 --modes 16
  --workers N`` (a GeoTIFF output is streamed);
- ``memory``: :func:`coastmesh.commands.simplify_raster_file` with
  ``stream=False``, the whole grid in memory (skipped above ``--memory-max``
  cells a side: it needs about 50 bytes a cell, 20 GB at 20,000 x 20,000).

Peak memory is the largest resident set of the process (``wait4``'s
``ru_maxrss``), and the largest sum over the process tree sampled every 50 ms
(psutil), whichever is larger. The table gives cells per second and the ratio
of the in-memory path's throughput to the streamed one's (same size, same run).
The two outputs are compared cell by cell.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import psutil
import rasterio
from affine import Affine
from scipy.interpolate import RectBivariateSpline

WINDOW, MODES = 8, 16
NODATA = -9999.0


def make_raster(path: Path, ny: int, nx: int, *, seed: int = 0) -> None:
    """Write a synthetic ``ny x nx`` float32 bathymetry GeoTIFF, 256 rows at a time."""
    rng = np.random.default_rng(seed)
    surfaces = []
    for spacing, amplitude in ((400, 1400.0), (50, 200.0)):
        knots_y = np.arange(-2, ny // spacing + 4) * spacing
        knots_x = np.arange(-2, nx // spacing + 4) * spacing
        control = rng.standard_normal((knots_y.size, knots_x.size)) * amplitude
        surfaces.append(RectBivariateSpline(knots_y, knots_x, control))
    profile = {
        "driver": "GTiff",
        "height": ny,
        "width": nx,
        "count": 1,
        "dtype": "float32",
        "crs": "EPSG:32630",
        "transform": Affine(100.0, 0.0, 300000.0, 0.0, -100.0, 7000000.0),
        "nodata": NODATA,
        "tiled": True,
        "blockxsize": 256,
        "blockysize": 256,
        "compress": "deflate",
        "predictor": 3,
        "NUM_THREADS": "ALL_CPUS",
        "BIGTIFF": "IF_SAFER",
    }
    x = np.arange(nx, dtype=np.float64)
    with rasterio.Env(GDAL_CACHEMAX=256), rasterio.open(path, "w", **profile) as dst:
        for r0 in range(0, ny, 256):
            y = np.arange(r0, min(ny, r0 + 256), dtype=np.float64)
            depth = -1500.0 + sum(s(y, x) for s in surfaces)
            noise = np.random.default_rng([seed, r0]).standard_normal(depth.shape)
            depth += 2.0 * noise
            depth[depth > 0] = NODATA
            window = rasterio.windows.Window(0, r0, nx, len(y))
            dst.write(depth.astype(np.float32), 1, window=window)


def run(command: list[str]) -> tuple[float, float]:
    """Run a command; return its wall time (s) and peak memory (MB)."""
    start = time.perf_counter()
    process = subprocess.Popen(command)
    peak = 0
    done = threading.Event()

    def sample() -> None:
        nonlocal peak
        try:
            root = psutil.Process(process.pid)
            while not done.is_set():
                tree = [root, *root.children(recursive=True)]
                total = 0
                for p in tree:
                    try:
                        total += p.memory_info().rss
                    except psutil.Error:
                        pass
                peak = max(peak, total)
                time.sleep(0.05)
        except psutil.Error:
            pass

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    done.set()
    sampler.join()
    if process.returncode != 0:
        raise SystemExit(f"{command} failed with exit code {process.returncode}")
    return wall, max(peak / 2**20, usage.ru_maxrss / 1024)


def stream_command(src: Path, dst: Path, workers: int) -> list[str]:
    """The command line of the streamed path."""
    exe = shutil.which("coastmesh") or "coastmesh"
    return [
        exe,
        "-q",
        "simplify-raster",
        str(src),
        str(dst),
        "--window",
        str(WINDOW),
        "--modes",
        str(MODES),
        "--workers",
        str(workers),
    ]


def memory_command(src: Path, dst: Path) -> list[str]:
    """The in-memory path, as the command ran it before streaming."""
    code = (
        "from coastmesh.commands import simplify_raster_file as f; "
        f"f({str(src)!r}, {str(dst)!r}, window={WINDOW}, modes={MODES}, stream=False)"
    )
    return [sys.executable, "-c", code]


def largest_difference(a: Path, b: Path) -> float:
    """Largest absolute difference of two rasters, 1,024 rows at a time."""
    worst = 0.0
    with rasterio.open(a) as da_, rasterio.open(b) as db_:
        for r0 in range(0, da_.height, 1024):
            window = rasterio.windows.Window(
                0, r0, da_.width, min(1024, da_.height - r0)
            )
            va = da_.read(1, window=window, masked=True)
            vb = db_.read(1, window=window, masked=True)
            if (va.mask != vb.mask).any():
                return float("inf")
            if va.count():
                worst = max(worst, float(np.abs(va - vb).max()))
    return worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[6000, 10000, 20000])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument(
        "--memory-max",
        type=int,
        default=10000,
        help="largest side also run in memory (cells); the in-memory path needs "
        "about 50 bytes a cell: 20 GB at 20,000 x 20,000",
    )
    parser.add_argument("--folder", type=Path, help="keep the files here")
    args = parser.parse_args()
    folder = args.folder or Path(tempfile.mkdtemp(prefix="bench_raster_stream-"))
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    try:
        for n in args.sizes:
            src = folder / f"synthetic_{n}.tif"
            if not src.exists():
                start = time.perf_counter()
                make_raster(src, n, n)
                print(
                    f"made {src.name}: {src.stat().st_size / 2**20:.0f} MB in "
                    f"{time.perf_counter() - start:.0f} s",
                    flush=True,
                )
            outputs = {}
            runs = [("stream", w) for w in args.workers]
            if n <= args.memory_max:
                runs.append(("memory", 1))
            for path, workers in runs:
                dst = folder / f"out_{n}_{path}_{workers}.tif"
                dst.unlink(missing_ok=True)
                command = (
                    stream_command(src, dst, workers)
                    if path == "stream"
                    else memory_command(src, dst)
                )
                wall, peak = run(command)
                outputs[path, workers] = dst
                rows.append((n, path, workers, wall, n * n / wall, peak))
                print(
                    f"{n} x {n} {path} workers={workers}: {wall:.1f} s, {peak:.0f} MB",
                    flush=True,
                )
            if ("memory", 1) in outputs:
                for (path, workers), dst in outputs.items():
                    if path == "stream":
                        worst = largest_difference(dst, outputs["memory", 1])
                        print(f"  stream ({workers}) - memory: max |diff| {worst:.3g}")
            for dst in outputs.values():
                dst.unlink(missing_ok=True)
    finally:
        if args.folder is None:
            shutil.rmtree(folder, ignore_errors=True)
    print()
    print("| rows x cols | path | workers | wall s | cells/s | peak MB | ratio |")
    print("|---|---|---:|---:|---:|---:|---:|")
    memory_speed = {n: speed for n, path, _, _, speed, _ in rows if path == "memory"}
    for n, path, workers, wall, speed, peak in rows:
        ratio = (
            f"{memory_speed[n] / speed:.2f}"
            if n in memory_speed and path == "stream"
            else ""
        )
        print(
            f"| {n:,} x {n:,} | {path} | {workers} | {wall:.1f} | {speed:,.0f} | "
            f"{peak:,.0f} | {ratio} |"
        )
    print(
        "\nratio: in-memory cells/s over streamed cells/s (above 1: streaming slower)"
    )


if __name__ == "__main__":
    main()
