"""Benchmark the issue-4 stages on a large mesh, against literal references.

Run from the repository root (needs the test extras):

    python benchmarks/bench_formats.py [--triangles 1000000]

The mesh is a jittered structured grid in longitude/latitude near 58 N, split
into triangles, with an open south side and land elsewhere: the size of a
regional tidal model. Timed, each in the same run:

1. depth at the nodes (bilinear, ETOPO1 NW shelf) against a per-node Python loop
   (``tests/reference.py``, on a sample of nodes, scaled);
2. the quality report against the per-triangle geodesic reference
   (``tests/reference_quality.py``, on a sample of triangles, scaled);
3. boundary topology, cleanup, every model writer, and every reader (the file
   just written read back with ``read_mesh``); fort.14 also against a
   line-by-line writer (``tests/reference.py``).

Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from reference import bilinear_loop, write_fort14_loop  # noqa: E402
from reference_quality import triangle_quality_reference  # noqa: E402

from coastmesh.data import path as data_path  # noqa: E402
from coastmesh.depth.nodes import depth_at_nodes  # noqa: E402
from coastmesh.io import mesh_formats, read_mesh, read_raster, write_mesh  # noqa: E402
from coastmesh.meshing.cleanup.fixes import clean_mesh  # noqa: E402
from coastmesh.meshing.quality.mesh_quality import mesh_quality, triangle_quality  # noqa: E402
from coastmesh.types import Mesh  # noqa: E402
from coastmesh.types.topology import boundary_strings  # noqa: E402


def grid_mesh(triangles: int) -> Mesh:
    """A jittered lon/lat grid near 58 N with about ``triangles`` triangles."""
    n = int(np.sqrt(triangles / 2)) + 1
    lon = np.linspace(-2.0, 2.0, n)
    lat = np.linspace(57.0, 59.0, n)
    gx, gy = np.meshgrid(lon, lat)
    rng = np.random.default_rng(0)
    step = (lon[1] - lon[0]) * 0.2
    jitter = rng.uniform(-step, step, (n, n, 2))
    jitter[[0, -1], :, :] = 0
    jitter[:, [0, -1], :] = 0
    points = np.column_stack(
        [(gx + jitter[..., 0]).ravel(), (gy + jitter[..., 1]).ravel()]
    )
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    tri = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(
        -1, 3
    )
    south = np.stack([idx[0, :-1], idx[0, 1:]], 1)
    east = np.stack([idx[:-1, -1], idx[1:, -1]], 1)
    north = np.stack([idx[-1, 1:], idx[-1, :-1]], 1)
    west = np.stack([idx[1:, 0], idx[:-1, 0]], 1)
    edges = np.concatenate([south, east, north, west])
    ids = np.concatenate([np.full(len(south), 2), np.full(len(edges) - len(south), 10)])
    return Mesh(
        points,
        tri,
        edges,
        ids,
        1,
        "EPSG:4326",
        boundary_names={2: "south", 10: "coast"},
        boundary_kinds={2: "open", 10: "shoreline"},
    )


def timed(func):
    start = time.perf_counter()
    result = func()
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=1_000_000)
    args = parser.parse_args()
    mesh = grid_mesh(args.triangles)
    print(f"\nmesh: {len(mesh.points):,} nodes, {len(mesh.triangles):,} triangles\n")
    raster = read_raster(data_path("etopo1_0.1deg_nwshelf.tif"))

    print("| stage | fast s | reference s (scaled from sample) | ratio | agreement |")
    print("|---|---:|---:|---:|---|")
    fast_s, (depth, _) = timed(lambda: depth_at_nodes(mesh, raster))
    sample = np.random.default_rng(1).choice(len(mesh.points), 20_000, replace=False)
    r = raster.sortby("y")
    ref_s, ref = timed(
        lambda: bilinear_loop(r.x.values, r.y.values, r.values, *mesh.points[sample].T)
    )
    ref_s *= len(mesh.points) / len(sample)
    diff = np.nanmax(np.abs(-ref - depth[sample]))
    print(
        f"| depth at nodes (bilinear) | {fast_s:.2f} | {ref_s:.1f} | "
        f"{ref_s / fast_s:.0f} | max diff {diff:.1e} m |"
    )
    fast_s, report = timed(lambda: mesh_quality(mesh.with_point_data(depth=depth)))
    tri_sample = np.random.default_rng(2).choice(
        len(mesh.triangles), 5_000, replace=False
    )
    small = Mesh(
        mesh.points, mesh.triangles[tri_sample], np.empty((0, 2), int), [], 1, mesh.crs
    )
    ref_s, ref = timed(lambda: triangle_quality_reference(small))
    ref_s *= len(mesh.triangles) / len(tri_sample)
    fast_angles = triangle_quality(small)["min_angle"]
    ref_angles = (
        np.array(ref["min_angle"])
        if isinstance(ref, dict)
        else np.array([t[0] for t in ref])
    )
    angle_diff = np.max(np.abs(fast_angles - ref_angles))
    print(
        f"| quality report | {fast_s:.2f} | {ref_s:.1f} | {ref_s / fast_s:.0f} | "
        f"max angle diff {angle_diff:.1e} deg |"
    )
    deep = mesh.with_point_data(depth=depth)
    with tempfile.TemporaryDirectory() as tmp:
        strings = boundary_strings(mesh)
        fast_s, _ = timed(lambda: write_mesh(Path(tmp) / "a.14", deep))
        open_s = [s.nodes for s in strings if s.physical_id == 2]
        land_s = [s.nodes for s in strings if s.physical_id == 10]
        ref_s, _ = timed(
            lambda: write_fort14_loop(Path(tmp) / "b.14", mesh, depth, open_s, land_s)
        )
        print(
            f"| fort.14 writer | {fast_s:.2f} | {ref_s:.1f} | {ref_s / fast_s:.1f} | "
            "same lists (tests) |"
        )

        print("\n| step | seconds |\n|---|---:|")
        print(f"| boundary topology | {timed(lambda: boundary_strings(mesh))[0]:.2f} |")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            seconds, (_, cleanup) = timed(lambda: clean_mesh(deep, max_valence=8))
        print(f"| cleanup ({cleanup.summary()}) | {seconds:.1f} |")
        for name, fmt in mesh_formats().items():
            path = Path(tmp) / f"mesh-{name}{fmt.extensions[0]}"
            seconds, _ = timed(
                lambda path=path, name=name: write_mesh(path, deep, format=name)
            )
            size = sum(p.stat().st_size for p in Path(tmp).glob(f"mesh-{name}*"))
            print(f"| write {name} ({size / 1e6:.0f} MB) | {seconds:.2f} |")
            if fmt.read is not None:
                seconds, back = timed(
                    lambda path=path, name=name: read_mesh(
                        path, format=name, crs=mesh.crs
                    )
                )
                ok = len(back.triangles) == len(mesh.triangles)
                print(
                    f"| read {name} ({'same' if ok else 'DIFFERENT'} size) | "
                    f"{seconds:.2f} |"
                )
    del report


if __name__ == "__main__":
    main()
