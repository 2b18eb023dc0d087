"""Run every example case with one version of coastmesh, or compare two such runs.

A refactoring must not change what a case writes. This runs each example (all
but the NW-shelf ``fine`` and ``fine_10M`` cases, which take minutes each) and
the demo with the coastmesh found on ``--src`` (a ``src`` folder of any
checkout, e.g. a ``git worktree`` of the commit before the change), then
compares two output trees file by file::

    git worktree add /tmp/before HEAD~5
    python scripts/same_outputs.py run --src /tmp/before/src --out /tmp/a
    python scripts/same_outputs.py run --src src --out /tmp/b
    python scripts/same_outputs.py compare /tmp/a /tmp/b

Files must be the same byte for byte, except what records when, where and how
long a run took: JSON files are compared without their timings, memory and list
of files; text files and tables without timings and the run's own folder; the
GeoPackages by their layers' contents and GeoTIFFs by their values, grid and CRS
(GDAL stamps both with the time written); the figures are not compared. A text
mesh file whose bytes differ is compared number by number, and reported apart
if only the last digits of some coordinates differ: the global example's nodes
do so between two runs of the same code. ``compare`` exits 1 if anything else
differs, and lists every difference.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = (
    "orkney/pentland_firth",
    "orkney/dem_shoreline",
    "orkney_bathymetry/orkney",
    "norway/sognefjorden",
    "norway/fjords_mesh",
    "nw_european_shelf/coarse",
    "nw_european_shelf/intermediate",
    "global/world",
)
#: keys of report.json that say how long a run took, or where its files went: the
#: parts' workers are process names, their projected speed-up is worked out from
#: the parts' times
TIMING_KEYS = {
    "seconds",
    "seconds_total",
    "cleanup_seconds",
    "peak_memory_mb",
    "files",
    "output",
    "workers",
    "projected_speedup",
}
#: text mesh formats: compared number by number where the bytes differ
TEXT_MESHES = (".msh", ".14", ".gr3", ".mesh", ".cli")


def run(src: Path, out: Path, workers: int) -> int:
    """Run each example and the demo with the coastmesh of ``src``."""
    out.mkdir(parents=True, exist_ok=True)
    env = os.environ | {"PYTHONPATH": str(src.resolve())}
    failed = 0
    jobs = [
        (case.replace("/", "_"), ["run", str(ROOT / "examples" / f"{case}.toml")])
        for case in EXAMPLES
    ] + [("demo", ["demo"])]
    for name, args in jobs:
        target = out / name
        command = [sys.executable, "-m", "coastmesh", *args]
        command += ["--output", str(target)] if args[0] == "run" else [str(target)]
        if args[0] == "run":
            command += ["--workers", str(workers)]
        started = time.perf_counter()
        log = (out / f"{name}.log").open("w")
        done = subprocess.run(command, env=env, stdout=log, stderr=log, check=False)
        seconds = time.perf_counter() - started
        print(f"{name}: exit {done.returncode} in {seconds:.0f} s", flush=True)
        failed += done.returncode != 0
    return int(failed > 0)


def _without_timings(value: object) -> object:
    if isinstance(value, dict):
        return {
            k: _without_timings(v) for k, v in value.items() if k not in TIMING_KEYS
        }
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


#: the parts' projected speed-up in a summary, worked out from the parts' times
SPEEDUP = re.compile(r"projected speed-up .*$")
#: the bundled data's folder, which differs from one source tree to the next
SRC = re.compile(r"[^\s\"']*/src/coastmesh/")


def _text(path: Path, root: Path) -> list[str]:
    """Return a text file's lines without timings, memory and its run's folder."""
    skip = ("time (s):", "peak memory:", "files:")
    text = path.read_text(encoding="utf-8").replace(str(root), "<out>")
    text = SRC.sub("<src>/coastmesh/", text)
    return [
        SPEEDUP.sub(
            "projected speed-up <t>", re.sub(r"\b\d+(\.\d+)? s\b", "<t> s", line)
        )
        for line in text.splitlines()
        if not line.startswith(skip)
    ]


def _table(path: Path) -> list[list[str]]:
    """Return a CSV or Markdown table without its columns of seconds."""
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        sep = "," if path.suffix == ".csv" else "|"
        rows.append([cell.strip() for cell in line.split(sep)])
    timed = [k for k, cell in enumerate(rows[0]) if "second" in cell or "(s)" in cell]
    return [[c for k, c in enumerate(row) if k not in timed] for row in rows]


def _gpkg_layers(path: Path) -> dict[str, str]:
    """Each layer's contents, hashed: its geometry as WKB and its fields."""
    import pyogrio
    import pyogrio.raw

    layers = {}
    for name, _ in pyogrio.list_layers(path):
        meta, _, geometry, fields = pyogrio.raw.read(path, layer=name)
        digest = hashlib.sha256(str(meta["crs"]).encode())
        digest.update(b"".join(g or b"" for g in geometry))
        for column, values in zip(meta["fields"], fields, strict=True):
            digest.update(column.encode())
            digest.update(repr(values.tolist()).encode())
        layers[name] = digest.hexdigest()
    return layers


def _raster(path: Path) -> tuple[object, ...]:
    """Return a raster's values, grid and CRS (its tags hold times and paths)."""
    import rasterio

    with rasterio.open(path) as r:
        return (r.read().tobytes(), tuple(r.transform), str(r.crs), r.nodata)


def _numbers_apart(a: Path, b: Path) -> str | None:
    """How far two text files of numbers differ, if only in their last digits."""
    ta, tb = a.read_text().split(), b.read_text().split()
    if len(ta) != len(tb):
        return None
    worst, count = 0.0, 0
    for x, y in zip(ta, tb, strict=True):
        if x == y:
            continue
        try:
            fx, fy = float(x), float(y)
        except ValueError:
            return None
        if "." not in x + y and "e" not in (x + y).lower():
            return None  # integers (ids, counts) must be equal
        worst, count = max(worst, abs(fx - fy) / max(abs(fx), abs(fy), 1.0)), count + 1
    return f"{count} numbers differ, by at most {worst:.1e} (relative)"


def _netcdf_apart(a: Path, b: Path) -> str | None:
    """How far two netCDF files differ, if only in the last digits of floats."""
    import numpy as np
    import xarray as xr

    with xr.open_dataset(a) as da, xr.open_dataset(b) as db:
        if set(da.variables) != set(db.variables) or repr(da.attrs) != repr(db.attrs):
            return None
        worst, count = 0.0, 0
        for name in da.variables:
            x, y = da[name].values, db[name].values
            if x.shape != y.shape or repr(da[name].attrs) != repr(db[name].attrs):
                return None
            if x.dtype.kind != "f":
                if not np.array_equal(x, y):
                    return None
                continue
            diff = np.abs(x - y) / np.maximum(np.maximum(abs(x), abs(y)), 1.0)
            worst = max(worst, float(np.nanmax(diff, initial=0.0)))
            count += int((diff > 0).sum())
    return f"{count} numbers differ, by at most {worst:.1e} (relative)"


def _apart(a: Path, b: Path) -> str | None:
    if a.suffix in TEXT_MESHES:
        return _numbers_apart(a, b)
    return _netcdf_apart(a, b) if a.suffix == ".nc" else None


def _same(a: Path, b: Path, roots: tuple[Path, Path]) -> bool:
    if a.suffix == ".json":

        def load(path: Path) -> object:
            return json.loads(SRC.sub("<src>/coastmesh/", path.read_text()))

        return _without_timings(load(a)) == _without_timings(load(b))
    if a.suffix in (".txt", ".toml"):
        return _text(a, roots[0]) == _text(b, roots[1])
    if a.suffix in (".csv", ".md"):
        return _table(a) == _table(b)
    if a.suffix == ".gpkg":
        return _gpkg_layers(a) == _gpkg_layers(b)
    if a.suffix == ".tif":
        return _raster(a) == _raster(b)
    return a.read_bytes() == b.read_bytes()


IGNORED = (".log", ".png", ".xml")


def compare(a: Path, b: Path) -> int:
    """Compare two output trees of :func:`run`; print what differs."""
    differ, compared = [], 0
    files_a = {p.relative_to(a) for p in a.rglob("*") if p.is_file()}
    files_b = {p.relative_to(b) for p in b.rglob("*") if p.is_file()}
    ignored = {p for p in files_a | files_b if p.suffix in IGNORED}
    ignored |= {p for p in files_a | files_b if p.parent == Path(".")}  # run logs
    for missing in sorted((files_a ^ files_b) - ignored):
        where = "the first" if missing in files_a else "the second"
        differ.append(f"only in {where}: {missing}")
    rounding = []
    for rel in sorted((files_a & files_b) - ignored):
        compared += 1
        if _same(a / rel, b / rel, (a, b)):
            continue
        apart = _apart(a / rel, b / rel)
        if apart is None:
            differ.append(f"differs: {rel}")
        else:
            rounding.append(f"same but for rounding: {rel}: {apart}")
    for line in differ + rounding:
        print(line)
    print(
        f"{compared} files compared: {len(differ)} differ, {len(rounding)} differ "
        "only in the last digits of some coordinates"
    )
    return int(bool(differ))


def main() -> int:
    """Run the command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run every example with one coastmesh")
    r.add_argument("--src", type=Path, required=True, help="the src folder to use")
    r.add_argument("--out", type=Path, required=True, help="where the runs go")
    r.add_argument("--workers", type=int, default=2)
    c = sub.add_parser("compare", help="compare two output trees")
    c.add_argument("first", type=Path)
    c.add_argument("second", type=Path)
    args = parser.parse_args()
    if args.command == "run":
        return run(args.src, args.out, args.workers)
    return compare(args.first, args.second)


if __name__ == "__main__":
    sys.exit(main())
