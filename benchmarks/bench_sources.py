"""Bathymetry at GEBCO size, and several sources: memory and time.

1. Makes a GEBCO-size raster: 86,400 x 43,200 float32 cells (15 arc-seconds,
   the whole world; 14.9 GB as a tiled BigTIFF), from the bundled ETOPO1 0.5 deg
   world grid interpolated bilinearly, written strip by strip. And the same
   cells clipped to the Orkney case's window (as a user would clip by hand).
2. Runs an example (``--case``: the Orkney one, or the NW shelf intermediate
   one; ``coastmesh run``, one worker) with each as its ``[bathymetry]`` (and
   ``[mesh_size.bathymetry]``) raster, under
   ``/usr/bin/time -v``: wall time and peak memory side by side.
3. Times depth sampling on N random nodes over the NW shelf: one source, and a
   UTM 'survey' on top of it with a 2 km blend.

Run from the repository root::

    python benchmarks/bench_sources.py --workdir /tmp/gebco
    python benchmarks/bench_sources.py --workdir /tmp/gebco --case nwshelf
    python benchmarks/bench_sources.py --workdir /tmp/gebco_small --scale 8

``--scale 8`` makes the world raster 8 times coarser per axis (a quick check).
The world file is kept in ``--workdir`` and reused.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import rasterio
from rasterio.transform import from_origin
from rasterio.windows import Window
from scipy.ndimage import map_coordinates

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "src" / "coastmesh" / "data"
CASES = {
    # case file, the raster path it names, the box a user would clip to
    "orkney": (
        ROOT / "examples" / "orkney" / "pentland_firth.toml",
        "../../src/coastmesh/data/etopo1_0.1deg_orkney_wide.tif",
        (-8.05, 55.95, 2.05, 61.05),
    ),
    "nwshelf": (
        ROOT / "examples" / "nw_european_shelf" / "intermediate.toml",
        "../../src/coastmesh/data/etopo1_0.1deg_nwshelf.tif",
        (-16.05, 47.95, 26.05, 70.05),
    ),
}


def make_world(path: Path, scale: int) -> Path:
    """The world at 1/240 deg (or ``scale`` times coarser), strip by strip."""
    if path.exists():
        return path
    step = scale / 240.0
    nx, ny = round(360 / step), round(180 / step)
    with rasterio.open(DATA / "etopo1_0.5deg_world.tif") as src:
        world = src.read(1).astype(np.float64)
        t = src.transform
    partial = path.with_suffix(".partial.tif")
    profile = {
        "driver": "GTiff", "width": nx, "height": ny, "count": 1,
        "dtype": "float32", "crs": "EPSG:4326", "nodata": None,
        "transform": from_origin(-180.0, 90.0, step, step),
        "tiled": True, "blockxsize": 512, "blockysize": 512, "BIGTIFF": "YES",
    }  # fmt: skip
    rows = 512
    started = time.perf_counter()
    with rasterio.open(partial, "w", **profile) as dst:
        lon = -180.0 + step * (np.arange(nx) + 0.5)
        for r0 in range(0, ny, rows):
            r1 = min(r0 + rows, ny)
            lat = 90.0 - step * (np.arange(r0, r1) + 0.5)
            # fractional (row, col) in the 0.5 deg grid, cell centres at +0.5
            fr = (lat - t.f) / t.e - 0.5
            fc = (lon - t.c) / t.a - 0.5
            rr, cc = np.meshgrid(fr, fc, indexing="ij")
            strip = map_coordinates(world, [rr, cc], order=1, mode="nearest")
            dst.write(strip.astype(np.float32), 1, window=Window(0, r0, nx, r1 - r0))
    partial.rename(path)
    print(f"made {path.name}: {nx} x {ny} in {time.perf_counter() - started:.0f} s")
    return path


def clip(world: Path, path: Path, box: tuple[float, ...]) -> Path:
    """The cells of ``world`` inside ``box``: what a user would clip by hand."""
    if path.exists():
        return path
    with rasterio.open(world) as src:
        window = rasterio.windows.from_bounds(*box, transform=src.transform)
        window = window.round_offsets().round_lengths()
        data = src.read(1, window=window)
        profile = src.profile | {
            "width": window.width, "height": window.height, "BIGTIFF": "NO",
            "transform": src.window_transform(window),
        }  # fmt: skip
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(data, 1)
    return path


def run_case(case: str, raster: Path, out: Path) -> tuple[float, float, int]:
    """Run an example with ``raster``; return wall s, peak MB, nodes."""
    example, named, _ = CASES[case]
    text = example.read_text().replace(named, str(raster))
    assert str(raster) in text
    text = text.replace("../../src/coastmesh/data/", f"{DATA}/")
    case = out.parent / f"{out.name}.toml"
    case.write_text(text)
    command = [
        "/usr/bin/time", "-v", sys.executable, "-m", "coastmesh", "--quiet", "run",
        str(case), "--output", str(out), "--workers", "1", "--overwrite",
    ]  # fmt: skip
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - started
    if done.returncode:
        raise SystemExit(done.stderr[-3000:])
    peak = int(
        re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)[1]
    )
    nodes = int(re.search(r'"nodes": (\d+)', (out / "report.json").read_text())[1])
    return wall, peak / 1024, nodes


def sampling(n: int) -> list[tuple[str, float, float]]:
    """Time one source, and a UTM survey blended on top, at ``n`` nodes."""
    import xarray as xr
    from rasterio.warp import Resampling, reproject

    from coastmesh.depth import DepthSource, DepthSources
    from coastmesh.io import read_raster

    etopo = read_raster(DATA / "etopo1_0.1deg_nwshelf.tif")
    x = np.arange(300e3, 700e3, 200.0)
    y = np.arange(6.7e6, 6.3e6, -200.0)
    utm = np.full((len(y), len(x)), np.nan, dtype=np.float32)
    reproject(
        etopo.values.astype(np.float32), utm,
        src_transform=etopo.attrs["transform"], src_crs="EPSG:4326",
        dst_transform=[200.0, 0, x[0] - 100, 0, -200.0, y[0] + 100],
        dst_crs="EPSG:32630", resampling=Resampling.bilinear, dst_nodata=np.nan,
    )  # fmt: skip
    utm[utm > 0] = np.nan
    survey = xr.DataArray(
        utm.astype(np.float64), dims=("y", "x"), coords={"y": y, "x": x},
        attrs={"crs": "EPSG:32630"},
    )  # fmt: skip
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.uniform(-8, 2, n), rng.uniform(56, 61, n)])
    rows = []
    for label, stack in (
        ("1 source (ETOPO, lon/lat)", [DepthSource(etopo)]),
        (
            "2 sources (UTM survey 200 m, blend 2 km, on ETOPO)",
            [DepthSource(survey, blend=2e3), DepthSource(etopo)],
        ),
    ):
        best = np.inf
        for _ in range(3):
            started = time.perf_counter()
            DepthSources(stack).sample(pts, "EPSG:4326")
            best = min(best, time.perf_counter() - started)
        rows.append((label, best, n / best))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()))
    parser.add_argument("--scale", type=int, default=1)
    parser.add_argument("--nodes", type=int, default=2_000_000)
    parser.add_argument("--case", choices=sorted(CASES), default="orkney")
    parser.add_argument("--skip-case", action="store_true")
    args = parser.parse_args()
    args.workdir.mkdir(parents=True, exist_ok=True)
    if not args.skip_case:
        world = make_world(args.workdir / f"world_{args.scale}.tif", args.scale)
        box = CASES[args.case][2]
        clipped = clip(world, args.workdir / f"{args.case}_{args.scale}.tif", box)
        with rasterio.open(world) as w, rasterio.open(clipped) as c:
            sizes = {"world": (w.width, w.height), "clipped": (c.width, c.height)}
        print("| bathymetry raster | cells | wall s | peak MB | nodes |")
        print("|---|---:|---:|---:|---:|")
        peaks = {}
        for label, raster in (("clipped", clipped), ("world", world)):
            out = args.workdir / f"run_{args.case}_{label}"
            wall, peak, nodes = run_case(args.case, raster, out)
            peaks[label] = peak
            nx, ny = sizes[label]
            print(
                f"| {label} | {nx:,} x {ny:,} | {wall:.1f} | {peak:,.0f} | {nodes:,} |"
            )
        print(
            f"peak memory, world - clipped: {peaks['world'] - peaks['clipped']:+.0f} MB"
        )
    print(f"\n| depth sampling, {args.nodes:,} nodes | best of 3 s | nodes/s |")
    print("|---|---:|---:|")
    rows = sampling(args.nodes)
    for label, seconds, rate in rows:
        print(f"| {label} | {seconds:.2f} | {rate:,.0f} |")
    print(f"ratio 2 sources / 1 source: {rows[1][1] / rows[0][1]:.2f}")


if __name__ == "__main__":
    main()
