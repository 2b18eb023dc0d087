"""End-to-end ``coastmesh simplify-shoreline`` on a world-sized full-resolution proxy.

Run from the repository root (needs the developer data set, ``../shared/data``):

    python benchmarks/bench_world_pca.py [--data ../shared/data] [--runs 3]

The target (issue 12) is GSHHG full resolution, world, level 1: 9.45 M points in
179,833 rings, ``--window 100 --modes 1``. That file is not here, so the script
builds a proxy of the same size from real data (written once to
``/tmp/coastmesh_world_proxy.gpkg``; ``--rebuild`` makes it again):

1. *Continents*: the rings of 10,000 points or more of the intermediate world
   layer (``world_gshhg_i.gpkg``: Eurasia and Africa), resampled evenly along
   their length to 20 times their vertex count. Full resolution has about 27
   times the vertices of intermediate; only their size matters here (one long
   ring each, FFT path).
2. *Small rings*: whole copies of the full-resolution UK / North Sea layer
   (``uk_northsea_gshhg_f``, 39,107 rings, 98.6 % of them under 100 points),
   shifted in lon/lat so that no two copies overlap, until the layer has
   about 179,833 rings; the last copy is a regular subsample of the features.
3. *Medium rings*: extra shifted copies of the features of the UK, West Norway
   and Orkney full-resolution layers whose rings have 100 to 9,999 points, until
   about 5,800 rings have at least 100 points (the issue's count of rings that
   the PCA keeps).
4. *Large rings*: extra shifted copies of the UK features with a ring of 10,000
   points or more (Scandinavia, Great Britain, ...) until the layer has about
   9.45 M points.

The script prints the proxy's ring-size histogram, then times the command run
as a subprocess (read and write included), old against new, alternating runs:

* *new*: this work tree (``python -m coastmesh``);
* *old*: ``git archive OLD_REF src`` unpacked into a temporary folder and put
  first on ``PYTHONPATH``, so that code runs unchanged (no git state changes).
  ``--old-ref`` is by default the last commit with the per-contour loop.

It reports min and median wall seconds, the largest peak RSS of the runs
(``os.wait4``, so Linux or macOS), and the largest coordinate difference between
the two outputs, vertex by vertex. The new code uses every core (``workers``
defaults to all of them); the old one runs on one. Run it on a quiet machine:
another busy process takes a core from the new code only.
"""

from __future__ import annotations

import argparse
import itertools
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pyogrio.raw
import shapely

ROOT = Path(__file__).resolve().parents[1]
TARGET_POINTS = 9_450_000
TARGET_RINGS = 179_833
TARGET_KEPT = 5_800  # rings of at least `window` points (issue 12)
WINDOW, MODES = 100, 1
PROXY = Path(tempfile.gettempdir()) / "coastmesh_world_proxy.gpkg"
#: the last commit where simplify_shorelines called simplify_contour ring by ring
PER_CONTOUR_LOOP = "6b25f66f61988c546d3c9f30792757c1f4b0675f"


def _read(path: Path):
    _, _, wkb, _ = pyogrio.raw.read(path)
    return shapely.from_wkb(wkb)


def _ring_sizes(geoms) -> np.ndarray:
    rings = shapely.get_rings(shapely.get_parts(geoms))
    return shapely.get_num_coordinates(rings) - 1


def _largest_ring(geoms) -> np.ndarray:
    """Largest ring of each feature, in distinct points."""
    rings, owner = shapely.get_rings(shapely.get_parts(geoms), return_index=True)
    _, feature = shapely.get_parts(geoms, return_index=True)
    out = np.zeros(len(geoms), dtype=np.int64)
    np.maximum.at(out, feature[owner], shapely.get_num_coordinates(rings) - 1)
    return out


def _resample(ring, factor: int):
    """The ring with ``factor`` times its vertices, evenly along its length."""
    xy = shapely.get_coordinates(ring)
    step = np.hypot(*np.diff(xy, axis=0).T)
    s = np.r_[0.0, np.cumsum(step)]
    t = np.linspace(0.0, s[-1], factor * (len(xy) - 1), endpoint=False)
    out = np.c_[np.interp(t, s, xy[:, 0]), np.interp(t, s, xy[:, 1])]
    return shapely.Polygon(np.vstack([out, out[:1]]))


class _Tiles:
    """Shifted copies of the UK box (lon -16..26, lat 48..70) over the globe."""

    def __init__(self) -> None:
        self.slot = 0

    def place(self, geoms):
        i, j = self.slot % 8, (self.slot // 8) % 8
        self.slot += 1
        dx, dy = (
            -180.0 + 42.0 * i + 16.0,
            -90.0 + 22.0 * j - 48.0 + 0.01 * (self.slot // 64),
        )
        return shapely.transform(geoms, lambda xy: xy + [dx, dy])


def make_proxy(data: Path, out: Path) -> None:
    """Build the proxy layer described in the module docstring."""
    package = ROOT / "src" / "coastmesh" / "data"
    uk = _read(data / "uk_northsea_gshhg_f.gpkg")
    regional = np.concatenate(
        [
            uk,
            _read(package / "norway_west_gshhg_f.geojson"),
            _read(package / "orkney_gshhg_f.geojson"),
        ]
    )
    world = _read(data / "world_gshhg_i.gpkg")
    world_rings = shapely.get_rings(shapely.get_parts(world))
    big = world_rings[shapely.get_num_coordinates(world_rings) > 10_000]
    pieces = [np.array([_resample(r, 20) for r in big], dtype=object)]
    tiles = _Tiles()

    def sizes():
        return _ring_sizes(np.concatenate(pieces))

    uk_sizes = _ring_sizes(uk)
    small_per_copy = int((uk_sizes < WINDOW).sum())
    copies = (TARGET_RINGS - TARGET_KEPT) / small_per_copy
    for _ in range(int(copies)):
        pieces.append(tiles.place(uk))
    fraction = copies - int(copies)
    if fraction > 0:
        stride = max(1, round(1 / fraction))
        pieces.append(tiles.place(uk[::stride]))
    largest = _largest_ring(regional)
    medium = regional[(largest >= WINDOW) & (largest < 10_000)]
    while (sizes() >= WINDOW).sum() < TARGET_KEPT:
        have = int((sizes() >= WINDOW).sum())
        need = TARGET_KEPT - have
        per_copy = int((_ring_sizes(medium) >= WINDOW).sum())
        take = medium if need >= per_copy else medium[: max(1, need)]
        pieces.append(tiles.place(take))
    large = uk[_largest_ring(uk) >= 10_000]
    for geom in np.resize(large, 100):
        if sizes().sum() >= TARGET_POINTS:
            break
        pieces.append(tiles.place(np.array([geom], dtype=object)))
    geoms = np.concatenate(pieces)
    parts, owner = shapely.get_parts(geoms, return_index=True)
    geoms = shapely.multipolygons(parts, indices=owner)
    print(f"proxy: {len(geoms):,} features", flush=True)
    pyogrio.raw.write(
        out,
        shapely.to_wkb(geoms),
        geometry_type="MultiPolygon",
        field_data=[np.arange(len(geoms), dtype=np.int64)],
        fields=["id"],
        crs="EPSG:4326",
        driver="GPKG",
        layer="world_proxy",
    )


def old_tree(ref: str, where: Path) -> Path:
    """Unpack ``src`` of commit ``ref`` into ``where`` (git state is not touched)."""
    archive = subprocess.run(
        ["git", "archive", ref, "src"], cwd=ROOT, check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(where)], input=archive, check=True)
    return where / "src"


def run_once(src_path: Path | None, source: Path, out: Path) -> tuple[float, float]:
    """Run the CLI once; return wall seconds and peak RSS (MB) of the process."""
    env = dict(os.environ)
    if src_path is not None:
        env["PYTHONPATH"] = str(src_path)
    out.unlink(missing_ok=True)
    command = [sys.executable, "-m", "coastmesh", "--quiet", "simplify-shoreline"]
    command += [str(source), str(out), "--window", str(WINDOW), "--modes", str(MODES)]
    start = time.perf_counter()
    proc = subprocess.Popen(command, env=env, cwd=tempfile.gettempdir())
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({proc.returncode})")
    return seconds, usage.ru_maxrss / 1024


def compare(old: Path, new: Path) -> str:
    """Largest vertex difference between two outputs, feature by feature."""
    a, b = _read(old), _read(new)
    if len(a) != len(b):
        return f"{len(a)} vs {len(b)} features"
    na, nb = shapely.get_num_coordinates(a), shapely.get_num_coordinates(b)
    same = na == nb
    xa = shapely.get_coordinates(a[same])
    xb = shapely.get_coordinates(b[same])
    diff = np.abs(xa - xb).max() if len(xa) else 0.0
    note = f"{diff:.1e} deg over {same.sum():,} features"
    if not same.all():
        note += f"; {(~same).sum()} features differ in vertex count (repairs)"
    return note


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT.parent / "shared" / "data")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--old-ref", default=PER_CONTOUR_LOOP)
    parser.add_argument("--rebuild", action="store_true")
    args = parser.parse_args()
    if args.rebuild or not PROXY.exists():
        make_proxy(args.data, PROXY)
    sizes = _ring_sizes(_read(PROXY))
    print(f"proxy {PROXY}: {len(sizes):,} rings, {sizes.sum():,} points")
    print("| ring points | rings | points |\n|---|---:|---:|")
    edges = [0, WINDOW, 200, 500, 1310, 10_000, 100_000, 10**9]
    for lo, hi in itertools.pairwise(edges):
        inside = (sizes >= lo) & (sizes < hi)
        print(f"| {lo:,} - {hi - 1:,} | {inside.sum():,} | {sizes[inside].sum():,} |")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        old_src = old_tree(args.old_ref, folder)
        times = {"old": [], "new": []}
        peaks = {"old": [], "new": []}
        for _ in range(args.runs):
            for name, src in (("old", old_src), ("new", None)):
                seconds, peak = run_once(src, PROXY, folder / f"{name}.gpkg")
                times[name].append(seconds)
                peaks[name].append(peak)
                print(f"{name}: {seconds:.2f} s, {peak:,.0f} MB", flush=True)
        print(f"\n`simplify-shoreline --window {WINDOW} --modes {MODES}`, ", end="")
        print(f"{args.runs} runs each, alternating\n")
        print("| code | min s | median s | peak RSS MB |\n|---|---:|---:|---:|")
        for name, seconds in times.items():
            t = np.array(seconds)
            print(
                f"| {name} | {t.min():.2f} | {np.median(t):.2f} "
                f"| {max(peaks[name]):,.0f} |"
            )
        ratio = np.median(times["old"]) / np.median(times["new"])
        print(f"\nmedian old / new: {ratio:.2f}")
        print("max |old - new|:", compare(folder / "old.gpkg", folder / "new.gpkg"))


if __name__ == "__main__":
    main()
