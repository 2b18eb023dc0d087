"""Does a real solver see the farm? ANUGA on the Inner Sound mesh, with and without.

A check run by hand, not a test. It builds (or reuses) the example case
``examples/orkney/inner_sound_farm.toml``, reads its UGRID file (per triangle
``region_id``: the farm 20, the turbine footprints 100-103, the sea 1; per
node ``depth``; per edge ``boundary_id`` and the file's ``open_boundary_ids``)
and runs ANUGA twice: base (Manning n = 0.025 everywhere) and farm (the same,
with drag on the farm's triangles only, picked by their region ids). It prints
the depth-averaged speeds inside, upstream, in the lee of and far from the
farm, saves ``OUT/speed_difference.png`` and ``OUT/results.json``, and exits 1
unless the mean lee deficit is at least ``--min-deficit`` (5 %) and larger
than the change at the far points.

The set-up (every number an option):

- Nodes projected from lon/lat to UTM 30N (EPSG:32630); the mesh cropped to
  the Pentland Firth (``--box`` -3.35 58.60 -2.95 58.76: the triangles whose
  centroids lie in it, the largest connected piece; 23,354 of the 50,648
  triangles). ANUGA takes one global time step, set by the 4.5 m footprints
  (about 0.037 s): the whole Orkney mesh cost about 35 ms a step, the window
  15 ms (CPU, one core).
- Land edges Reflective. Open edges (the file's open ids and the crop's cut
  edges) take a head difference ramped in over ``--ramp`` (5 min) and then
  held, the flood-like flow through the Inner Sound: stage falls linearly with
  x from +head/2 at the window's west end to -head/2 at its east end
  (``--head`` 3 m), with the normal momentum from inside and no tangential
  momentum (ANUGA's Transmissive_n_momentum_zero_t_momentum_set_stage_boundary
  with a stage per edge). Sea at rest at t = 0; elevation = -depth; ANUGA's
  default DE0 scheme. 30 min of model time (``--minutes``); speeds are means
  over the last 5 min (``--average``), area-weighted over the triangles within
  50 m of each point. The flow is still speeding up then (about 2.3 m/s at
  the farm in the base run), not steady, but it has had time to cross the
  farm (1.8 km long) and the wake to form.
- Farm run: n = 0.1 on region 20 (``--farm-manning``): at 35 m of water a drag
  coefficient g n^2 / h^(1/3) = 0.030, against 0.0019 for n = 0.025; that
  is the thrust of a dense array (one 18 m rotor with thrust coefficient 0.8
  per about 60 m x 60 m), not of the four Phase 1A turbines, which spread over
  the 1.6 km2 box would add only about 2.5e-4. Each footprint (a disc of the
  rotor's diameter, so of the rotor's area) carries its own turbine's thrust:
  C_d = C_T / 2 (``--thrust`` 0.8), n = sqrt(C_T h^(1/3) / (2 g)), about 0.37.
- Points: the lee and upstream ones on the axis of the base run's mean flow
  over the farm (bearing 101 deg), through the farm's centre, at the distances
  given beyond its downstream and upstream edges; the far ones fixed (the
  Outer Sound north of Stroma, the west entrance of the Firth).

Measured (2 shared cores, the two runs side by side): each run 48,400-48,900
steps, about 1,190 s wall and 750 s CPU. Deficit inside the farm 33-35 %, lee
28 % at 100 m, 17 % at 250 m, 8 % at 500 m, 5 % at 1 km, 4 % at 2 km (mean
12.4 %); upstream 4-6 % (blockage); far points -1.0 % and 0.7 %.

ANUGA's environment (anuga 4.2.0 is a binary wheel; its "Could not import
mpi4py" warning is harmless; coastmesh is not needed in it, the mesh is built
with the project's own coastmesh)::

    python3.11 -m venv /work/venv-anuga
    /work/venv-anuga/bin/pip install anuga pyproj netCDF4 scipy matplotlib

Run from the repository root (about 30 s for the mesh, once)::

    /work/venv-anuga/bin/python benchmarks/anuga_farm.py \\
        --coastmesh /work/venv/bin/coastmesh --out benchmarks/out/anuga_farm

``OUT/mesh/`` is built once and reused (``--rebuild`` to build it again;
``--mesh FILE.nc`` to use another coastmesh UGRID file). ``--jobs 1`` runs the
two one after the other.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
CASE = REPO / "examples" / "orkney" / "inner_sound_farm.toml"
UTM30N = "EPSG:32630"
GRAVITY = 9.81
# Fixed far-field points (lon, lat): little change is expected there.
FAR_POINTS = {
    "far: Outer Sound": (-3.10, 58.715),
    "far: west entrance": (-3.28, 58.70),
}


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=REPO / "benchmarks/out/anuga_farm")
    p.add_argument("--mesh", type=Path, help="a coastmesh UGRID .nc (else build)")
    p.add_argument("--coastmesh", default=shutil.which("coastmesh") or "coastmesh")
    p.add_argument("--rebuild", action="store_true", help="rebuild OUT/mesh")
    p.add_argument(
        "--box",
        type=float,
        nargs=4,
        default=[-3.35, 58.60, -2.95, 58.76],
        metavar=("W", "S", "E", "N"),
        help="crop window, lon/lat",
    )
    p.add_argument("--farm-id", type=int, default=20)
    p.add_argument("--manning", type=float, default=0.025)
    p.add_argument("--farm-manning", type=float, default=0.1)
    p.add_argument("--thrust", type=float, default=0.8, help="C_T; 0: farm n")
    p.add_argument("--head", type=float, default=3.0, help="west - east, m")
    p.add_argument("--ramp", type=float, default=5.0, help="minutes")
    p.add_argument("--minutes", type=float, default=30.0, help="model time")
    p.add_argument("--average", type=float, default=5.0, help="minutes")
    p.add_argument("--min-deficit", type=float, default=5.0, help="%% in the lee")
    p.add_argument("--jobs", type=int, default=2, choices=(1, 2))
    return p.parse_args(argv)


# -- the mesh -----------------------------------------------------------------


def mesh_file(args):
    """The UGRID file: --mesh, else OUT/mesh/ (built with coastmesh if absent)."""
    if args.mesh:
        return args.mesh, 0.0
    folder = args.out / "mesh"
    path = folder / f"{CASE.stem}.nc"
    if path.exists() and not args.rebuild:
        print(f"mesh: reusing {path}")
        return path, 0.0
    cmd = [args.coastmesh, "-q", "run", str(CASE), "-o", str(folder)]
    if args.rebuild:
        cmd.append("--overwrite")
    print("mesh:", " ".join(cmd), flush=True)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    build_s = time.perf_counter() - t0
    print(f"mesh: built in {build_s:.0f} s")
    return path, build_s


def read_ugrid(path):
    """Nodes (UTM 30N), triangles, depth, region and boundary ids of a UGRID file."""
    import netCDF4
    from pyproj import CRS, Transformer

    with netCDF4.Dataset(path) as d:
        x, y = d["mesh2d_node_x"][:].data, d["mesh2d_node_y"][:].data
        tris = d["mesh2d_face_nodes"][:].data.astype(np.int64)
        tris -= int(getattr(d["mesh2d_face_nodes"], "start_index", 0))
        edges = d["mesh2d_edge_nodes"][:].data.astype(np.int64)
        edges -= int(getattr(d["mesh2d_edge_nodes"], "start_index", 0))
        bid = d["boundary_id"]
        region = d["region_id"]
        crs = CRS.from_wkt(d["mesh2d_crs"].crs_wkt)
        mesh = {
            "depth": d["depth"][:].data.astype(float),
            "region": region[:].data.astype(np.int64),
            "domain_id": int(region.domain_surface_id),
            "region_names": dict(
                zip(
                    region.flag_values.tolist(),
                    region.flag_meanings.split(),
                    strict=True,
                )
            ),
            "open_ids": set(np.atleast_1d(bid.open_boundary_ids).tolist()),
            "tris": tris,
        }
        ids = bid[:].data
    on = ids != 0
    mesh["edge_id"] = {
        (int(min(a, b)), int(max(a, b))): int(i)
        for (a, b), i in zip(edges[on], ids[on], strict=True)
    }
    lon, lat = Transformer.from_crs(crs, 4326, always_xy=True).transform(x, y)
    mesh["lonlat"] = np.column_stack([lon, lat])
    xy = Transformer.from_crs(crs, UTM30N, always_xy=True).transform(x, y)
    mesh["xy"] = np.column_stack(xy)
    return mesh


def edge_table(tris):
    """Each triangle's edges (edge k opposite vertex k, ANUGA's order), sorted."""
    e = np.sort(tris[:, [1, 2, 2, 0, 0, 1]].reshape(-1, 2), axis=1)
    _, inverse, counts = np.unique(e, axis=0, return_inverse=True, return_counts=True)
    return e, inverse.ravel(), counts


def largest_piece(tris):
    """Mask of the triangles in the largest edge-connected piece."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    _, inverse, counts = edge_table(tris)
    owner = np.repeat(np.arange(len(tris)), 3)
    shared = counts[inverse] == 2
    order = np.argsort(inverse[shared], kind="stable")
    pairs = owner[shared][order].reshape(-1, 2)
    n = len(tris)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (n, n))
    _, label = connected_components(graph, directed=False)
    return label == np.bincount(label).argmax()


def crop(mesh, box):
    """The triangles with centroids in the lon/lat box, nodes renumbered, tagged."""
    west, south, east, north = box
    c = mesh["lonlat"][mesh["tris"]].mean(axis=1)
    keep = (c[:, 0] > west) & (c[:, 0] < east) & (c[:, 1] > south) & (c[:, 1] < north)
    keep[keep] = largest_piece(mesh["tris"][keep])
    tris = mesh["tris"][keep]
    xy = mesh["xy"]
    a, b, cc = (xy[tris[:, k]] for k in range(3))
    cw = (b[:, 0] - a[:, 0]) * (cc[:, 1] - a[:, 1]) < (b[:, 1] - a[:, 1]) * (
        cc[:, 0] - a[:, 0]
    )
    tris[cw] = tris[cw][:, [0, 2, 1]]
    edges, inverse, counts = edge_table(tris)
    boundary, tally = {}, {"land": 0, "open": 0, "cut": 0}
    for k in np.flatnonzero(counts[inverse] == 1):
        bid = mesh["edge_id"].get((int(edges[k, 0]), int(edges[k, 1])))
        tag = "cut" if bid is None else "open" if bid in mesh["open_ids"] else "land"
        boundary[(int(k // 3), int(k % 3))] = tag
        tally[tag] += 1
    used, local = np.unique(tris, return_inverse=True)
    return {
        "xy": xy[used],
        "lonlat": mesh["lonlat"][used],
        "depth": mesh["depth"][used],
        "tris": local.reshape(-1, 3),
        "region": mesh["region"][keep],
        "boundary": boundary,
        "tally": tally,
    }


def friction(win, mesh, args, farm):
    """Manning n per triangle: the base value; with farm, the farm's drag too."""
    n = np.full(len(win["tris"]), args.manning)
    if not farm:
        return n
    region = win["region"]
    n[region == args.farm_id] = args.farm_manning
    footprint = (region != args.farm_id) & (region != mesh["domain_id"])
    if args.thrust > 0:
        h = win["depth"][win["tris"][footprint]].mean(axis=1)
        n[footprint] = np.sqrt(0.5 * args.thrust * np.cbrt(h) / GRAVITY)
    else:
        n[footprint] = args.farm_manning
    return n


# -- the runs ----------------------------------------------------------------


def head_boundary(domain, head, ramp, x_west, x_east):
    """A set-stage boundary: the stage falls linearly in x, west to east."""
    from anuga.abstract_2d_finite_volumes.generic_boundary_conditions import (
        Boundary,
    )

    class HeadBoundary(Boundary):
        def __init__(self):
            super().__init__()
            self.domain = domain

        def evaluate_segment(self, domain, segment_edges):
            ids = np.asarray(segment_edges)
            q = domain.quantities
            vol, edge = domain.boundary_cells[ids], domain.boundary_edges[ids]
            x = domain.edge_coordinates[3 * vol + edge, 0]
            t = domain.get_time()
            level = 0.5 * (1 - np.cos(np.pi * min(t / ramp, 1.0)))
            stage = level * head * (0.5 - (x - x_west) / (x_east - x_west))
            q["stage"].boundary_values[ids] = stage
            inside = np.maximum(q["height"].edge_values[vol, edge], 0.0)
            outside = np.maximum(stage - q["elevation"].edge_values[vol, edge], 0.0)
            scale = np.where(outside >= inside, 1.0, outside / np.maximum(inside, 1e-9))
            n1 = domain.normals[vol, 2 * edge]
            n2 = domain.normals[vol, 2 * edge + 1]
            qx = q["xmomentum"].edge_values[vol, edge]
            qy = q["ymomentum"].edge_values[vol, edge]
            normal = (n1 * qx + n2 * qy) * scale
            q["xmomentum"].boundary_values[ids] = normal * n1
            q["ymomentum"].boundary_values[ids] = normal * n2

    return HeadBoundary()


def velocities(domain):
    """Depth-averaged velocity at the centroids (0 where dry)."""
    q = domain.quantities
    h = q["stage"].centroid_values - q["elevation"].centroid_values
    wet = h > 0.01
    hs = np.where(wet, h, 1.0)
    u = np.where(wet, q["xmomentum"].centroid_values / hs, 0.0)
    v = np.where(wet, q["ymomentum"].centroid_values / hs, 0.0)
    return u, v


def simulate(job):
    """One ANUGA run; time means of the centroid velocities at the end."""
    import tempfile

    import anuga

    xy, tris = job["xy"], job["tris"]
    origin = xy.min(axis=0)
    t0, cpu0 = time.perf_counter(), time.process_time()
    with tempfile.TemporaryDirectory(prefix="anuga_farm_") as tmp:
        domain = anuga.Domain(
            xy - origin,
            tris,
            boundary=job["boundary"],
            geo_reference=anuga.Geo_reference(30, *origin, hemisphere="northern"),
        )
        domain.set_compute_mode("legacy")
        domain.set_name(job["name"])
        domain.set_datadir(tmp)
        domain.set_store(False)
        domain.set_quantity("elevation", -job["depth"], location="unique vertices")
        domain.set_quantity("stage", 0.0)
        domain.set_quantity("friction", job["manning"], location="centroids")
        west, east = xy[:, 0].min() - origin[0], xy[:, 0].max() - origin[0]
        head = head_boundary(domain, job["head"], job["ramp"], west, east)
        bcs = {"land": anuga.Reflective_boundary(domain), "open": head, "cut": head}
        domain.set_boundary({tag: bcs[tag] for tag in set(job["boundary"].values())})
        setup = time.perf_counter() - t0
        end, start_mean = job["seconds"], job["seconds"] - job["average"]
        steps, sums, samples, max_speed = 0, 0.0, 0, 0.0
        for t in domain.evolve(yieldstep=60.0, finaltime=end):
            steps += domain.number_of_steps
            u, v = velocities(domain)
            speed = np.hypot(u, v)
            if not np.isfinite(speed).all():
                raise FloatingPointError(f"{job['name']}: NaN at t = {t:.0f} s")
            max_speed = max(max_speed, float(speed.max()))
            if t >= start_mean - 1e-6:
                sums = sums + np.column_stack([speed, u, v])
                samples += 1
            if int(t) % 600 == 0:
                print(
                    f"  {job['name']}: t = {t / 60:4.0f} min, {steps} steps, "
                    f"max speed {speed.max():.2f} m/s, "
                    f"{time.perf_counter() - t0:.0f} s",
                    flush=True,
                )
    mean = sums / samples
    return {
        "name": job["name"],
        "wall_s": time.perf_counter() - t0,
        "cpu_s": time.process_time() - cpu0,
        "setup_s": setup,
        "steps": steps,
        "mean_dt_s": end / steps,
        "max_speed": max_speed,
        "speed": mean[:, 0],
        "u": mean[:, 1],
        "v": mean[:, 2],
    }


def run_both(win, mesh, args):
    """The base and the farm run, side by side (--jobs 2, one core each)."""
    jobs = [
        {
            "name": name,
            "xy": win["xy"],
            "tris": win["tris"],
            "depth": win["depth"],
            "boundary": win["boundary"],
            "manning": friction(win, mesh, args, farm=name == "farm"),
            "head": args.head,
            "ramp": 60.0 * args.ramp,
            "seconds": 60.0 * args.minutes,
            "average": 60.0 * args.average,
        }
        for name in ("base", "farm")
    ]
    if args.jobs == 1:
        return [simulate(j) for j in jobs]
    os.environ["OMP_NUM_THREADS"] = "1"
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        return list(pool.map(simulate, jobs))


# -- the sample points and the check ------------------------------------------


def triangle_geometry(win):
    """Centroids and areas of the window's triangles (UTM)."""
    a, b, c = (win["xy"][win["tris"][:, k]] for k in range(3))
    area = 0.5 * np.abs(
        (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    )
    return (a + b + c) / 3, area


def sample_points(win, mesh, args, base):
    """Points inside, upstream and in the lee of the farm, and far away (UTM)."""
    from pyproj import Transformer

    centroid, area = triangle_geometry(win)
    farm = win["region"] != mesh["domain_id"]
    w = area[farm]
    centre = (centroid[farm] * w[:, None]).sum(axis=0) / w.sum()
    flow = np.array([(base["u"][farm] * w).sum(), (base["v"][farm] * w).sum()])
    axis = flow / np.hypot(*flow)
    along = (win["xy"][np.unique(win["tris"][farm])] - centre) @ axis
    down, up = along.max(), -along.min()
    points = {
        "farm centre": centre,
        "farm, downstream half": centre + 0.5 * down * axis,
    }
    for s in (100, 250, 500, 1000, 2000):
        points[f"lee {s} m"] = centre + (down + s) * axis
    for s in (500, 1000):
        points[f"upstream {s} m"] = centre - (up + s) * axis
    to_utm = Transformer.from_crs(4326, UTM30N, always_xy=True)
    for name, (lon, lat) in FAR_POINTS.items():
        points[name] = np.array(to_utm.transform(lon, lat))
    bearing = float(np.degrees(np.arctan2(axis[0], axis[1])) % 360)
    return points, bearing, centre


def speed_at(points, win, speeds, radius=50.0):
    """Area-weighted mean speed of the triangles within radius of each point.

    Where no centroid is that close (large triangles), the triangle that holds
    the point; None if none does (land, or outside the window).
    """
    from matplotlib.tri import Triangulation
    from scipy.spatial import cKDTree

    centroid, area = triangle_geometry(win)
    tree = cKDTree(centroid)
    finder = Triangulation(*win["xy"].T, win["tris"]).get_trifinder()
    out = {}
    for name, p in points.items():
        near = tree.query_ball_point(p, radius)
        if not near:
            k = int(finder(*p))
            near = [k] if k >= 0 else []
        out[name] = [
            float((s[near] * area[near]).sum() / area[near].sum()) if near else None
            for s in speeds
        ]
    return out


def table(points, at, centre, bearing):
    """Print the table; return its rows."""
    from pyproj import Transformer

    back = Transformer.from_crs(UTM30N, 4326, always_xy=True)
    print(f"\nflow axis over the farm (base run): bearing {bearing:.0f} deg")
    head = f"{'point':24s} {'lon':>8s} {'lat':>8s} {'dist m':>7s}"
    print(f"{head} {'base m/s':>9s} {'farm m/s':>9s} {'deficit %':>9s}")
    rows = []
    for name, p in points.items():
        lon, lat = back.transform(*p)
        base, farm = at[name]
        moving = base is not None and base > 1e-3
        deficit = 100.0 * (base - farm) / base if moving else None
        dist = float(np.hypot(*(p - centre)))
        rows.append(
            {"point": name, "lon": lon, "lat": lat, "from_centre_m": dist}
            | {"base": base, "farm": farm, "deficit_pct": deficit}
        )
        cells = (
            "  (dry / outside the window)"
            if base is None
            else f" {base:9.3f} {farm:9.3f} "
            + ("(no flow)" if deficit is None else f"{deficit:9.1f}")
        )
        print(f"{name:24s} {lon:8.4f} {lat:8.4f} {dist:7.0f}{cells}")
    return rows


def verdict(rows, min_deficit):
    """0 if the lee shows the deficit and far away shows less; else 1."""
    lee = [r["deficit_pct"] for r in rows if r["point"].startswith("lee")]
    far = [r["deficit_pct"] for r in rows if r["point"].startswith("far:")]
    lee = [d for d in lee if d is not None]
    far = [abs(d) for d in far if d is not None]
    lee_mean = float(np.mean(lee)) if lee else float("nan")
    far_max = max(far) if far else 0.0
    ok = bool(lee) and lee_mean >= min_deficit and far_max < lee_mean
    print(
        f"\nlee deficit, mean of {len(lee)} points: {lee_mean:.1f} % "
        f"(needed >= {min_deficit:g} %); far away, largest change "
        f"{far_max:.1f} %: {'OK' if ok else 'FAILED'}"
    )
    return ok, lee_mean, far_max


# -- the figure ---------------------------------------------------------------


def figure(path, win, mesh, base, farm, points, centre, half=(4.0, 3.0)):
    """Base speed and speed difference (farm - base) near the farm, farm outlined."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xy = (win["xy"] - centre) / 1000.0
    tris = win["tris"]
    centroid, _ = triangle_geometry(win)
    near = np.all(np.abs(centroid - centre) < 1500.0 * np.array(half), axis=1)
    in_farm = win["region"] != mesh["domain_id"]
    edges, inverse, counts = edge_table(tris)
    owner = np.repeat(np.arange(len(tris)), 3)
    order = np.argsort(inverse, kind="stable")
    shared = counts[inverse[order]] == 2
    pairs = owner[order][shared].reshape(-1, 2)
    keys = edges[order][shared][::2]
    outline = keys[in_farm[pairs[:, 0]] != in_farm[pairs[:, 1]]]
    diff = farm["speed"] - base["speed"]
    lim = float(np.percentile(np.abs(diff[near]), 99.5)) or 1.0
    fig, axes = plt.subplots(2, 1, figsize=(10, 12), layout="constrained")
    panels = [
        (base["speed"], "viridis", None, "base run: speed (m/s)"),
        (diff, "RdBu_r", (-lim, lim), "farm - base: speed (m/s)"),
    ]
    for ax, (values, cmap, clim, title) in zip(axes, panels, strict=True):
        kw = {"vmin": clim[0], "vmax": clim[1]} if clim else {}
        art = ax.tripcolor(*xy.T, tris[near], facecolors=values[near], cmap=cmap, **kw)
        fig.colorbar(art, ax=ax, shrink=0.8)
        for a, b in outline:
            ax.plot(*xy[[a, b]].T, "k", lw=0.8)
        for name, p in points.items():
            q = (p - centre) / 1000.0
            ax.plot(*q, "k^" if name.startswith("lee") else "ko", ms=3)
        ax.set(xlim=(-half[0], half[0]), ylim=(-half[1], half[1]))
        ax.set(aspect="equal", title=title, xlabel="km east of the farm centre")
        ax.set_ylabel("km north of the farm centre")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    args = parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    path, build_s = mesh_file(args)
    mesh = read_ugrid(path)
    win = crop(mesh, args.box)
    counts = {
        mesh["region_names"].get(int(r), str(r)): int(n)
        for r, n in zip(*np.unique(win["region"], return_counts=True), strict=True)
    }
    print(
        f"mesh {path}: {len(mesh['xy'])} nodes, {len(mesh['tris'])} triangles; "
        f"window {args.box}: {len(win['xy'])} nodes, {len(win['tris'])} "
        f"triangles, boundary edges {win['tally']}, triangles by region {counts}; "
        f"read and cropped in {time.perf_counter() - t0 - build_s:.1f} s"
    )
    base, farm = run_both(win, mesh, args)
    for r in (base, farm):
        print(
            f"{r['name']}: {r['wall_s']:.0f} s wall, {r['cpu_s']:.0f} s CPU "
            f"({r['setup_s']:.1f} s setup), "
            f"{r['steps']} steps, mean dt {r['mean_dt_s']:.4f} s, "
            f"max speed {r['max_speed']:.2f} m/s"
        )
    points, bearing, centre = sample_points(win, mesh, args, base)
    at = speed_at(points, win, (base["speed"], farm["speed"]))
    rows = table(points, at, centre, bearing)
    ok, lee_mean, far_max = verdict(rows, args.min_deficit)
    figure(args.out / "speed_difference.png", win, mesh, base, farm, points, centre)
    summary = {
        "mesh": str(path),
        "mesh_nodes": len(mesh["xy"]),
        "mesh_triangles": len(mesh["tris"]),
        "window": args.box,
        "window_nodes": len(win["xy"]),
        "window_triangles": len(win["tris"]),
        "boundary_edges": win["tally"],
        "triangles_by_region": counts,
        "options": {k: v for k, v in vars(args).items() if k not in ("out", "mesh")},
        "build_s": build_s,
        "runs": {
            r["name"]: {k: v for k, v in r.items() if not isinstance(v, np.ndarray)}
            for r in (base, farm)
        },
        "flow_bearing_deg": bearing,
        "points": rows,
        "lee_mean_deficit_pct": lee_mean,
        "far_max_change_pct": far_max,
        "ok": ok,
        "total_s": time.perf_counter() - t0,
    }
    (args.out / "results.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"total {summary['total_s']:.0f} s; results.json, figure: {args.out}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
