"""seamsh beside coastmesh: the same domain, the same size field, one core.

Run with coastmesh's Python; seamsh runs in a venv of its own
(``--seamsh-python``, default ``/work/venv-seamsh/bin/python``: seamsh, GDAL's
Python bindings, the same ``gmsh`` as coastmesh's, scipy, psutil)::

    python benchmarks/bench_seamsh.py examples/nw_european_shelf/intermediate.toml
    python benchmarks/bench_seamsh.py examples/nw_european_shelf/fine.toml \\
        --coarsen --isolated
    python benchmarks/bench_seamsh.py examples/nw_european_shelf/fine.toml \\
        --coarsen --parts auto

What is compared, and how:

- **coastmesh** builds the case with ``coastmesh.build_case(case, workers=1)``,
  its ``[mesh] parts`` set to 1 and its ``[cleanup]`` off, so that its
  "meshing" stage is exactly ``generate_mesh(domain, size_grid, mesh_crs=...,
  parts=1, threads=1)``: the boundary nodes (Gmsh 1-D), Gmsh's 2-D mesher on
  one surface with the case's algorithm (Frontal-Delaunay), Relocate2D, and
  the arrays put in order. The domain and size field do not depend on the
  two settings changed. That stage is timed from inside, through a ``stage``
  hook of ``build_case``: its wall time, the resident memory of this process
  at its start and its peak during it (psutil, every 0.2 s). The mesh is made
  once. Its peak includes what the case holds before meshing (shorelines,
  size field), so ``--isolated`` meshes the same domain and size grid again
  with ``generate_mesh`` in a child process of its own, measured as seamsh is
  (a second row, ``coastmesh (child)``).
- **seamsh** gets the same domain: each boundary segment of the coastmesh
  domain, in the mesh CRS (``rings.npz``; the islands coastmesh drops as
  smaller than three target edges are left out), added as a tagged
  ``POLYLINE`` boundary curve with ``Domain.add_boundary_curve``; and the same
  size field: the coastmesh grid in the mesh CRS's map units (metres times
  the projection's scale factor, which is what Gmsh sees in coastmesh;
  ``size.npz``), interpolated bilinearly by ``scipy``'s
  ``RegularGridInterpolator``, clamped to the edge values outside the grid as
  coastmesh clamps. Only the water needs the same values: seamsh samples the
  field over the whole bounding box into a quadtree whose cells are split
  down to twice the smallest size at their corners, and the coastmesh grid
  holds its smallest size over land (55.6 m on the fine case: seamsh then
  refined all the land to 110 m cells and ran out of memory at 21 GB). So
  each grid node that is a corner of no cell meeting the water gets instead
  the kept nodes' sizes grown with distance at coastmesh's default gradation
  rate (``coastmesh.sizing.DEFAULT_RATE``); in every cell that meets the
  water the bilinear field is the one coastmesh meshes with. seamsh then
  holds it as its quadtree (bilinear in each leaf, leaves merged where that
  is within 10 %), so Gmsh sees it within about 10 % there. The edge/target
  check uses the unchanged grid. ``seamsh.gmsh.mesh`` is called with
  gradation limiting off (``--smoothness``, default 1e9: the coastmesh field
  is already graded) and binary .msh output, in a child process, after Gmsh
  is set to one thread and algorithm 6 (Frontal-Delaunay, which seamsh 0.6.2
  keeps on a Gmsh without its "optimized" mesher). Its wall time is that call less
  the ``gmsh.write`` of the file (reported apart); its peak memory is the
  child's ``VmHWM`` (its own peak since ``exec``: ``ru_maxrss`` would keep
  this process's memory at the fork), and its memory at the start is its
  resident memory just before the call.
- **coastmesh in parts** (``--parts auto``): the water cut into parts as
  coastmesh cuts it by default, the parts meshed one after the other in this
  process (``workers=1``), still without cleanup: coastmesh's own way of
  meshing, on one core. The "meshing" stage then also holds the cutting and
  the joining of the parts, and Gmsh's times are summed over the parts.
- **seamsh + coarsen** (``--coarsen``): seamsh's own workflow, the same
  domain first passed through ``seamsh.geometry.coarsen_boundaries`` (its
  boundaries resampled to the size field, as coastmesh resamples its rings
  before Gmsh sees them; timed within the wall time, and apart as
  ``coarsen_s``). Without it, Gmsh's curves are polylines through every
  vertex of the rings.
- **Both**: CPU seconds of the same call beside its wall time (the machine
  may be shared); Gmsh's own wall and CPU times are read from its log
  ("Done meshing 1D/2D", "Done optimizing mesh"); a child past ``--max-mb``
  resident (sampled every 0.2 s) is stopped and its row says so; the
  quality is measured by the same numpy function on the planar mesh-CRS
  coordinates (minimum angle per triangle, its 1st percentile, the worst
  radius ratio ``2 r_in / r_circ``), with each edge's length over the target
  size at its middle as a check that both followed the same field.

Prints one JSON line per tool, then a markdown table.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import io
import json
import logging
import os
import pickle
import re
import subprocess
import sys
import tempfile
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import psutil
import shapely
from pyproj import CRS, Transformer

import coastmesh
from coastmesh.geometry.projection import project_rings, sample_size, to_map_units
from coastmesh.meshing.engine import ALGORITHMS
from coastmesh.meshing.gmsh.resample import resample_rings
from coastmesh.sizing import DEFAULT_RATE
from coastmesh.types import SizeGrid

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_parallel import TreeMemory

SEAMSH_PYTHON = "/work/venv-seamsh/bin/python"
MB = 2**20
_GMSH_DONE = re.compile(
    r"Done (meshing 1D|meshing 2D|optimizing mesh) "
    r"\(Wall ([0-9.eE+-]+)s, CPU ([0-9.eE+-]+)s"
)

# The seamsh side, run in seamsh's venv: argv[1] is the work folder.
# Both child scripts read their own peak memory this way.
PEAK_RSS = r"""
def peak_rss():
    # VmHWM: this process's own peak since exec (ru_maxrss would keep the
    # parent's resident memory at the fork)
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no VmHWM in /proc/self/status")
"""

SEAMSH_SCRIPT = (
    r"""
import json, re, sys, time, warnings
from importlib.metadata import version
from pathlib import Path

import numpy as np
import psutil
from osgeo import osr
from scipy.interpolate import RegularGridInterpolator

import gmsh
import seamsh
import seamsh.gmsh

work = Path(sys.argv[1])
"""
    + PEAK_RSS
    + r"""

inputs = json.loads((work / "inputs.json").read_text())
grid = np.load(work / "size.npz")
gx, gy, gv = grid["x"], grid["y"], grid["values"]
interp = RegularGridInterpolator((gy, gx), gv, method="linear")
lo, hi = np.array([gx[0], gy[0]]), np.array([gx[-1], gy[-1]])


def mesh_size(xy, projection):
    xy = np.clip(np.asarray(xy)[:, :2], lo, hi)  # clamped, as coastmesh clamps
    return interp(xy[:, ::-1])


srs = osr.SpatialReference()
srs.ImportFromWkt(inputs["wkt"])
srs.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
domain = seamsh.geometry.Domain(srs)
curves = np.load(work / "rings.npz")
for k, tag in enumerate(inputs["tags"]):
    domain.add_boundary_curve(
        curves[f"c{k}"], tag, srs, seamsh.geometry.CurveType.POLYLINE
    )

for name, value in (
    ("General.Terminal", 0),
    ("General.Verbosity", 5),  # the "Done meshing" lines, to the logger only
    ("General.NumThreads", 1),
    ("Mesh.MaxNumThreads1D", 1),
    ("Mesh.MaxNumThreads2D", 1),
    ("Mesh.Algorithm", inputs["algorithm"]),
):
    gmsh.option.setNumber(name, value)
gmsh.logger.start()
writes = []
write = gmsh.write


def timed_write(*args, **kwargs):
    t0, c0 = time.perf_counter(), time.process_time()
    write(*args, **kwargs)
    writes.append((time.perf_counter() - t0, time.process_time() - c0))


gmsh.write = timed_write  # seamsh.gmsh calls gmsh.write on this module
name = sys.argv[2]
rss_before = psutil.Process().memory_info().rss
t0, c0 = time.perf_counter(), time.process_time()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    if name.endswith("coarsen"):  # seamsh's own boundary preparation
        domain = seamsh.geometry.coarsen_boundaries(
            domain, inputs["inside"], srs, mesh_size
        )
    coarsen = time.perf_counter() - t0
    seamsh.gmsh.mesh(
        domain,
        str(work / f"{name}.msh"),
        mesh_size,
        smoothness=inputs["smoothness"],
        binary=True,
    )
total, cpu = time.perf_counter() - t0, time.process_time() - c0
out = {
    "version": version("seamsh"),
    "gmsh": gmsh.option.getString("General.Version"),
    "algorithm": gmsh.option.getNumber("Mesh.Algorithm"),
    "threads": gmsh.option.getNumber("General.NumThreads"),
    "call_s": total,
    "cpu_s": cpu - sum(c for _, c in writes),
    "coarsen_s": coarsen,
    "write_s": sum(w for w, _ in writes),
    "rss_before": rss_before,
    "peak": peak_rss(),
    "gmsh_log": [l for l in gmsh.logger.get() if "Done " in l],
    "warnings": sorted({str(w.message).splitlines()[0] for w in caught}),
}
(work / f"{name}.json").write_text(json.dumps(out))
"""
)

# coastmesh again, alone in a child process (--isolated): argv[1] is the work
# folder, with the domain and size grid pickled by the parent.
COASTMESH_SCRIPT = (
    r"""
import json, logging, pickle, sys, time, warnings
from pathlib import Path

import numpy as np
import psutil

from coastmesh.meshing import generate_mesh

work = Path(sys.argv[1])
"""
    + PEAK_RSS
    + r"""

args = pickle.loads((work / "coastmesh.pkl").read_bytes())
lines = []


class Keep(logging.Handler):
    def emit(self, record):
        text = record.getMessage()
        if "Done " in text:
            lines.append(text)


log = logging.getLogger("coastmesh.meshing.engine")
log.setLevel(logging.DEBUG)
log.addHandler(Keep())
rss_before = psutil.Process().memory_info().rss
t0, c0 = time.perf_counter(), time.process_time()
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    mesh = generate_mesh(
        args["domain"],
        args["size"],
        mesh_crs=args["mesh_crs"],
        output_crs=args["mesh_crs"],
        seed=args["seed"],
        algorithm=args["algorithm"],
        optimize=args["optimize"],
        parts=1,
        threads=1,
    )
total, cpu = time.perf_counter() - t0, time.process_time() - c0
np.savez(work / "coastmesh.npz", points=mesh.points, triangles=mesh.triangles)
out = {
    "call_s": total,
    "cpu_s": cpu,
    "rss_before": rss_before,
    "peak": peak_rss(),
    "gmsh_log": lines,
}
(work / "coastmesh.json").write_text(json.dumps(out))
"""
)


def triangle_shapes(
    points: np.ndarray, triangles: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum angle (degrees) and radius ratio ``2 r_in / r_circ`` per triangle.

    Planar: ``points`` are (x, y) in a projected CRS.
    """
    p = points[:, :2][triangles]
    a = np.hypot(*(p[:, 1] - p[:, 2]).T)
    b = np.hypot(*(p[:, 2] - p[:, 0]).T)
    c = np.hypot(*(p[:, 0] - p[:, 1]).T)
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area = 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    angles = [
        np.arccos(np.clip((y * y + z * z - x * x) / (2 * y * z), -1.0, 1.0))
        for x, y, z in ((a, b, c), (b, c, a), (c, a, b))
    ]
    min_angle = np.degrees(np.minimum.reduce(angles))
    # r_in = area / s, r_circ = abc / (4 area): 2 r_in / r_circ = 8 area^2 / (s abc)
    s = 0.5 * (a + b + c)
    ratio = 8.0 * area**2 / (s * a * b * c)
    return min_angle, ratio


def edge_over_target(
    points: np.ndarray, triangles: np.ndarray, grid: SizeGrid
) -> float:
    """Median of edge length over the target size at its middle (map units).

    Every side of every triangle counts (an inner edge twice).
    """
    p = points[:, :2]
    ratios = []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        pa, pb = p[triangles[:, i]], p[triangles[:, j]]
        length = np.hypot(*(pb - pa).T)
        ratios.append(length / sample_size(grid, 0.5 * (pa + pb)))
    return float(np.median(np.concatenate(ratios)))


def quality(points: np.ndarray, triangles: np.ndarray, grid: SizeGrid) -> dict:
    """The same figures for either mesh, on mesh-CRS coordinates."""
    min_angle, ratio = triangle_shapes(points, triangles)
    return {
        "min_angle_p1": round(float(np.percentile(min_angle, 1)), 2),
        "min_angle_min": round(float(min_angle.min()), 2),
        "radius_ratio_min": round(float(ratio.min()), 3),
        "edge_over_target_median": round(edge_over_target(points, triangles, grid), 3),
    }


def gmsh_seconds(lines: list[str]) -> dict[str, float]:
    """Sum Gmsh's "Done ... (Wall X s, CPU Y s" times by kind."""
    out = {"gmsh_1d_s": 0.0, "gmsh_2d_s": 0.0, "gmsh_optimize_s": 0.0}
    out |= {k.replace("_s", "_cpu_s"): 0.0 for k in out}
    keys = {
        "meshing 1D": "gmsh_1d_s",
        "meshing 2D": "gmsh_2d_s",
        "optimizing mesh": "gmsh_optimize_s",
    }
    for line in lines:
        m = _GMSH_DONE.search(line)
        if m:
            key = keys[m.group(1)]
            out[key] += float(m.group(2))
            out[key.replace("_s", "_cpu_s")] += float(m.group(3))
    return {k: round(v, 2) for k, v in out.items()}


class GmshLog(logging.Handler):
    """Keep coastmesh's Gmsh log lines that give a stage's wall time."""

    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.lines: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        text = record.getMessage()
        if "Done " in text:
            self.lines.append(text)


class MeshingStage:
    """A ``build_case`` stage factory watching the "meshing" stage."""

    def __init__(self) -> None:
        self.seconds = 0.0
        self.cpu = 0.0
        self.rss_before = 0
        self.peak = 0

    @contextlib.contextmanager
    def __call__(self, label: str) -> Iterator[Any]:
        if label != "meshing":
            yield lambda done, total: None
            return
        self.rss_before = psutil.Process().memory_info().rss
        started, cpu = time.perf_counter(), time.process_time()
        with TreeMemory() as tree:
            yield lambda done, total: None
        self.seconds = time.perf_counter() - started
        self.cpu = time.process_time() - cpu  # with the sampler's thread
        self.peak = tree.peak


def row(tool: str, version: str, case: str, **fields: Any) -> dict:
    """One tool's figures, with the derived rates and memory."""
    wall, tri = fields["wall_s"], fields["triangles"]
    out = {"tool": tool, "version": version, "case": case, **fields}
    out["wall_s"] = round(wall, 2)
    out["triangles_per_s"] = round(tri / wall)
    if out.get("gmsh_2d_s"):
        out["gmsh_2d_triangles_per_s"] = round(tri / out["gmsh_2d_s"])
    out["peak_mb"] = round(fields["peak_mb"])
    out["rss_before_mb"] = round(fields["rss_before_mb"])
    out["meshing_mb"] = out["peak_mb"] - out["rss_before_mb"]
    out["load"] = [round(x, 2) for x in os.getloadavg()]
    return out


class ChildFailed(Exception):
    """A child process failed or was stopped; ``peak`` is its sampled peak RSS."""

    def __init__(self, message: str, peak: int) -> None:
        super().__init__(message)
        self.peak = peak


def failed(tool: str, case: str, exc: ChildFailed) -> dict:
    """The row of a tool that did not finish."""
    return {
        "tool": tool,
        "case": case,
        "error": str(exc),
        "peak_mb": round(exc.peak / MB),
        "load": [round(x, 2) for x in os.getloadavg()],
    }


def run_child(python: str, script: str, name: str, work: Path, max_mb: float) -> dict:
    """Run ``script`` with ``python`` on ``work``; return the JSON it wrote.

    The child's resident memory is sampled every 0.2 s; past ``max_mb`` it is
    stopped (the machine is shared: better than the kernel's OOM killer).
    """
    path = work / f"{name}_run.py"
    path.write_text(script)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    peak, stopped = 0, False
    with open(work / f"{name}.log", "w") as log:
        child = psutil.Popen(
            [python, str(path), str(work), name],
            stdout=log,
            stderr=subprocess.STDOUT,
            env=env,
        )
        while child.poll() is None:
            with contextlib.suppress(psutil.Error):
                peak = max(peak, child.memory_info().rss)
            if peak > max_mb * MB:
                child.kill()
                child.wait()
                stopped = True
                break
            time.sleep(0.2)
    if stopped or child.returncode != 0:
        tail = (work / f"{name}.log").read_text()[-1500:]
        why = (
            f"stopped at {peak / MB:,.0f} MB resident (--max-mb {max_mb:,.0f})"
            if stopped
            else f"exit status {child.returncode}"
        )
        print(f"{name}: {why}; its log ends:\n{tail}", file=sys.stderr)
        raise ChildFailed(why, peak)
    return json.loads((work / f"{name}.json").read_text())


def build(case_path: str, parts: int | str = 1) -> tuple[Any, MeshingStage, GmshLog]:
    """Build the case on one core, in ``parts``, no cleanup; watch its meshing."""
    case = coastmesh.read_case(case_path)
    case = dataclasses.replace(
        case,
        mesh=dataclasses.replace(case.mesh, parts=parts),
        cleanup=dataclasses.replace(case.cleanup, enabled=False),
    )
    stage, log = MeshingStage(), GmshLog()
    engine = logging.getLogger("coastmesh.meshing.engine")
    engine.setLevel(logging.DEBUG)
    engine.addHandler(log)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = coastmesh.build_case(case, workers=1, stage=stage)
    finally:
        engine.removeHandler(log)
    return result, stage, log


def water_nodes(
    grid: SizeGrid, rings: list[list[np.ndarray]], dropped: list[int]
) -> np.ndarray:
    """Which grid nodes are corners of a cell that meets the water."""

    def closed(ring: list[np.ndarray]) -> np.ndarray:
        return np.concatenate([np.asarray(c)[:-1] for c in ring] + [ring[0][:1]])

    kept = [closed(r) for k, r in enumerate(rings) if k not in set(dropped)]
    water = shapely.Polygon(kept[0], kept[1:])
    shapely.prepare(water)
    x0, y0 = np.meshgrid(grid.x[:-1], grid.y[:-1])
    x1, y1 = np.meshgrid(grid.x[1:], grid.y[1:])
    cells = shapely.box(x0.ravel(), y0.ravel(), x1.ravel(), y1.ravel())
    wet = shapely.intersects(water, cells).reshape(x0.shape)
    keep = np.zeros(grid.values.shape, dtype=bool)
    for dj in (0, 1):
        for di in (0, 1):
            keep[dj : keep.shape[0] - 1 + dj, di : keep.shape[1] - 1 + di] |= wet
    return keep


def over_land(grid: SizeGrid, keep: np.ndarray, rate: float) -> np.ndarray:
    """The grid's values where ``keep``; elsewhere grown from them at ``rate``.

    ``min(h_max, min over kept nodes of value + rate * distance)``, by sweeps
    over the 8 neighbours of each node (a chamfer distance).
    """
    values = grid.values.astype(np.float64)
    out = np.where(keep, values, values[keep].max())
    dx, dy = float(np.diff(grid.x).mean()), float(np.diff(grid.y).mean())
    ny, nx = out.shape
    steps = [
        (dj, di, rate * float(np.hypot(dj * dy, di * dx)))
        for dj in (-1, 0, 1)
        for di in (-1, 0, 1)
        if dj or di
    ]
    while True:
        best = out.copy()
        for dj, di, cost in steps:  # best[j, i] vs out[j - dj, i - di]
            src = out[max(-dj, 0) : ny - max(dj, 0), max(-di, 0) : nx - max(di, 0)]
            dst = best[max(dj, 0) : ny - max(-dj, 0), max(di, 0) : nx - max(-di, 0)]
            np.minimum(dst, src + cost, out=dst)
        best[keep] = values[keep]
        if np.array_equal(best, out):
            return out
        out = best


def write_inputs(
    result: Any, mesh_crs: CRS, work: Path, smoothness: float, algorithm: int
) -> SizeGrid:
    """Write the domain's segments and the size grid in map units for seamsh."""
    grid = to_map_units(result.size_grid, mesh_crs)
    rings, ids = project_rings(result.domain, mesh_crs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # SmallIslandWarning
        _, dropped = resample_rings(rings, lambda xy: sample_size(grid, xy))
    keep = water_nodes(grid, rings, dropped)
    land = over_land(grid, keep, DEFAULT_RATE)
    names = {s.physical_id: s.name for s in result.domain.segments}
    inside = result.domain.polygon.representative_point()
    to_mesh = Transformer.from_crs(result.domain.crs, mesh_crs, always_xy=True)
    curves, tags = [], []
    for r, (ring, ring_ids) in enumerate(zip(rings, ids, strict=True)):
        if r in set(dropped):
            continue
        for segment, pid in zip(ring, ring_ids, strict=True):
            curves.append(np.asarray(segment, dtype=np.float64))
            tags.append(names.get(pid, str(pid)))
    np.savez(work / "rings.npz", **{f"c{k}": c for k, c in enumerate(curves)})
    np.savez(work / "size.npz", x=grid.x, y=grid.y, values=land)
    (work / "inputs.json").write_text(
        json.dumps(
            {
                "wkt": mesh_crs.to_wkt(),
                "tags": tags,
                "smoothness": smoothness,
                "algorithm": algorithm,
                "rings_dropped": len(dropped),
                "grid_nodes_kept": int(keep.sum()),
                "grid_nodes": int(keep.size),
                "inside": list(to_mesh.transform(inside.x, inside.y)),
            }
        )
    )
    return grid


def table(rows: list[dict]) -> str:
    """A markdown table of the rows."""
    head = (
        "| tool | case | wall s | CPU s | Gmsh 1-D s | Gmsh 2-D s | Gmsh opt. s "
        "| triangles | tri/s "
        "| Gmsh 2-D tri/s "
        "| peak MB | meshing MB | p1 angle | min angle | worst radius ratio "
        "| edge/target |"
    )
    lines = [head, "|" + " --- |" * 16]
    for r in rows:
        if "error" in r:
            lines.append(
                f"| {r['tool']} | {r['case']} | failed: {r['error']} |" + " |" * 13
            )
            continue
        lines.append(
            f"| {r['tool']} {r['version']} | {r['case']} | {r['wall_s']:.1f} "
            f"| {r['cpu_s']:.1f} "
            f"| {r['gmsh_1d_s']:.1f} | {r['gmsh_2d_s']:.1f} "
            f"| {r['gmsh_optimize_s']:.1f} | {r['triangles']:,} "
            f"| {r['triangles_per_s']:,} | {r.get('gmsh_2d_triangles_per_s', 0):,} "
            f"| {r['peak_mb']:,} | {r['meshing_mb']:,} | {r['min_angle_p1']:.2f} "
            f"| {r['min_angle_min']:.2f} | {r['radius_ratio_min']:.3f} "
            f"| {r['edge_over_target_median']:.3f} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case")
    parser.add_argument("--work", default=None, help="keep the files here")
    parser.add_argument("--seamsh-python", default=SEAMSH_PYTHON)
    parser.add_argument(
        "--smoothness",
        type=float,
        default=1e9,
        help="seamsh's gradation limit (default 1e9: off)",
    )
    parser.add_argument(
        "--max-mb",
        type=float,
        default=12000,
        help="stop a child past this resident memory (default 12000)",
    )
    parser.add_argument(
        "--coarsen",
        action="store_true",
        help="also mesh with seamsh after its coarsen_boundaries",
    )
    parser.add_argument(
        "--parts",
        default="1",
        help="coastmesh's [mesh] parts: 1 (default: one surface, as seamsh "
        'meshes) or "auto" or a count (the water cut into parts, meshed one '
        "after the other on this one core)",
    )
    parser.add_argument(
        "--isolated",
        action="store_true",
        help="also mesh with coastmesh in a child process, measured as seamsh",
    )
    args = parser.parse_args()
    with contextlib.ExitStack() as stack:
        if args.work is None:
            work = Path(stack.enter_context(tempfile.TemporaryDirectory()))
        else:
            work = Path(args.work)
            work.mkdir(parents=True, exist_ok=True)
        rows = []
        for r in compare(args, work):
            print(json.dumps(r), flush=True)
            rows.append(r)
    print()
    print(table(rows))


def seamsh_row(
    args: argparse.Namespace, work: Path, variant: str, case: str, grid: SizeGrid
) -> dict:
    """Mesh with seamsh in its venv (``variant``: with coarsening or not)."""
    import meshio

    try:
        seamsh = run_child(
            args.seamsh_python, SEAMSH_SCRIPT, variant, work, args.max_mb
        )
    except ChildFailed as exc:
        return failed(variant.replace("_", " + "), case, exc)
    with contextlib.redirect_stdout(io.StringIO()):  # meshio prints a blank line
        msh = meshio.read(work / f"{variant}.msh")
    triangles = msh.cells_dict["triangle"]
    return row(
        variant.replace("_", " + "),
        seamsh["version"],
        case,
        wall_s=seamsh["call_s"] - seamsh["write_s"],
        cpu_s=round(seamsh["cpu_s"], 2),
        coarsen_s=round(seamsh["coarsen_s"], 2),
        write_s=round(seamsh["write_s"], 2),
        **gmsh_seconds(seamsh["gmsh_log"]),
        triangles=len(triangles),
        nodes=len(np.unique(triangles)),
        peak_mb=seamsh["peak"] / MB,
        rss_before_mb=seamsh["rss_before"] / MB,
        **quality(msh.points, triangles, grid),
        where="child process",
        gmsh=seamsh["gmsh"],
        algorithm=seamsh["algorithm"],
        threads=seamsh["threads"],
        warnings=seamsh["warnings"],
    )


def compare(args: argparse.Namespace, work: Path) -> Iterator[dict]:
    """Mesh with coastmesh, then seamsh (and coastmesh alone); measure all."""
    parts = args.parts if args.parts == "auto" else int(args.parts)
    result, stage, log = build(args.case, parts)
    mesh_crs = CRS.from_user_input(result.report.mesh_crs)
    config = result.config.mesh
    algorithm = ALGORITHMS[config.algorithm]
    grid = write_inputs(result, mesh_crs, work, args.smoothness, algorithm)
    if args.isolated:
        (work / "coastmesh.pkl").write_bytes(
            pickle.dumps(
                {
                    "domain": result.domain,
                    "size": result.size_grid,
                    "mesh_crs": mesh_crs,
                    "seed": config.seed,
                    "algorithm": config.algorithm,
                    "optimize": config.optimize,
                }
            )
        )
    to_plane = Transformer.from_crs(result.mesh.crs, mesh_crs, always_xy=True)
    points = np.column_stack(to_plane.transform(*result.mesh.points[:, :2].T))
    name = result.name
    count = result.report.parts.parts
    yield row(
        "coastmesh" if count <= 1 else f"coastmesh ({count} parts, 1 core)",
        coastmesh.__version__,
        name,
        wall_s=stage.seconds,
        cpu_s=round(stage.cpu, 2),
        **gmsh_seconds(log.lines),
        triangles=len(result.mesh.triangles),
        nodes=len(result.mesh.points),
        peak_mb=stage.peak / MB,
        rss_before_mb=stage.rss_before / MB,
        **quality(points, result.mesh.triangles, grid),
        where="in build_case (stage hook)",
    )
    del result, points
    for variant in ["seamsh", "seamsh_coarsen"] if args.coarsen else ["seamsh"]:
        yield seamsh_row(args, work, variant, name, grid)
    if args.isolated:
        try:
            alone = run_child(
                sys.executable, COASTMESH_SCRIPT, "coastmesh", work, args.max_mb
            )
        except ChildFailed as exc:
            yield failed("coastmesh (child)", name, exc)
            return
        arrays = np.load(work / "coastmesh.npz")
        yield (
            row(
                "coastmesh (child)",
                coastmesh.__version__,
                name,
                wall_s=alone["call_s"],
                cpu_s=round(alone["cpu_s"], 2),
                **gmsh_seconds(alone["gmsh_log"]),
                triangles=len(arrays["triangles"]),
                nodes=len(arrays["points"]),
                peak_mb=alone["peak"] / MB,
                rss_before_mb=alone["rss_before"] / MB,
                **quality(arrays["points"], arrays["triangles"], grid),
                where="child process",
            )
        )


if __name__ == "__main__":
    main()
