"""Run a coastmesh mesh in ANUGA with a tide on the open boundaries; did it blow up?

A stability check of a mesh in a real shallow-water solver, not a test: ANUGA
(finite volumes, CFL-limited explicit time steps) is forced by one sine tide of
amplitude A and period T, in phase on every open boundary, ramped in over 1 h,
with reflective (wall) land boundaries, Manning friction 0.025 and the sea at
rest at t = 0. Every step the water is checked: a NaN or inf, a speed above
``--max-speed`` (20 m/s) or a stage beyond 10 A is a blow-up (time and place
reported); an exception from ANUGA (e.g. a vanishing time step) is one too.

ANUGA gets its own environment. anuga 4.2.0 (a binary wheel, no compiler)
needs Python 3.10-3.15 and numpy >= 2.0 and pulls in meshpy, pymetis,
netCDF4, scipy, matplotlib, xarray; with coastmesh on top it took about 40 s::

    python3.11 -m venv /work/venv-anuga
    /work/venv-anuga/bin/pip install anuga             # anuga 4.2.0, numpy 2.4.6
    /work/venv-anuga/bin/pip install -e /work/main     # for coastmesh.read_mesh

(Its "Could not import mpi4py" warning is harmless: serial runs need no MPI.)

Run from the repository root with that environment::

    /work/venv-anuga/bin/python benchmarks/anuga_run.py MESH --hours 6 \
        [--amplitude 1.0] [--period 44712] [--depth-floor 5] [--json out.json]

MESH is any mesh coastmesh reads with depth (fort.14, gr3, UGRID .nc, mesh
.gpkg, ...; a .msh has no depth). Lon/lat nodes are projected to the UTM zone
of the mesh centre; a projected mesh is used as it is. ANUGA runs in a
temporary folder (its .sww output and logs are deleted; ``--sww`` keeps the
.sww). ``--phase-lag DEG`` delays the tide from west to east: the open boundary
edges are cut into ``--phase-bins`` bins by x, each forced with the phase of
its bin's middle, from 0 at the westmost open edge to DEG at the eastmost (an
idealised tide travelling east, as the M2 Kelvin wave does along the north
of Scotland; not a calibrated forcing). Prints a one-line summary;
``--json`` also writes the numbers. The dt
statistics are ANUGA's CFL-limited steps (as in its timestepping statistics),
before the last step of each yield interval is shortened to land on it.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import shutil
import sys
import tempfile
import time
from pathlib import Path

import anuga
import numpy as np
from pyproj import CRS, Transformer

import coastmesh


class BlowUp(Exception):
    """The solution went non-finite or out of bounds."""


def project(mesh, crs_option):
    """Return node coordinates in metres, the metric CRS, and the mesh's CRS."""
    crs = mesh.crs
    if crs is None and crs_option:
        crs = CRS.from_user_input(crs_option)
    if crs is None:
        x, y = mesh.points.T
        lonlat = (np.abs(x) <= 180).all() and (np.abs(y) <= 90).all()
        crs = CRS.from_epsg(4326) if lonlat else None
        print(f"warning: the mesh has no CRS; assuming {crs or 'metres'} (--crs)")
    if crs is None or crs.is_projected:
        return mesh.points.copy(), crs, crs
    lon, lat = Transformer.from_crs(crs, 4326, always_xy=True).transform(*mesh.points.T)
    lon0, lat0 = (lon.min() + lon.max()) / 2, (lat.min() + lat.max()) / 2
    zone = int((lon0 + 180) // 6) % 60 + 1
    utm = CRS.from_epsg((32600 if lat0 >= 0 else 32700) + zone)
    xy = Transformer.from_crs(crs, utm, always_xy=True).transform(*mesh.points.T)
    return np.column_stack(xy), utm, crs


def boundary_tags(triangles, mesh):
    """Tag every edge of exactly one triangle 'open' or 'land' (ANUGA's dict)."""
    kind = {}
    for (a, b), bid in zip(mesh.boundary_edges, mesh.boundary_ids, strict=True):
        open_ = mesh.boundary_kinds.get(int(bid)) == "open"
        kind[(min(a, b), max(a, b))] = "open" if open_ else "land"
    # ANUGA's edge i of a triangle is the one opposite its vertex i
    edges = np.sort(triangles[:, [1, 2, 2, 0, 0, 1]].reshape(-1, 3, 2), axis=2)
    flat = edges.reshape(-1, 2)
    _, inverse, counts = np.unique(
        flat, axis=0, return_inverse=True, return_counts=True
    )
    boundary, missing = {}, 0
    for k in np.flatnonzero(counts[inverse.ravel()] == 1):
        tag = kind.get((int(flat[k, 0]), int(flat[k, 1])))
        missing += tag is None
        boundary[(int(k // 3), int(k % 3))] = tag or "land"
    return boundary, missing, len(kind) - (len(boundary) - missing)


def phase_bins(boundary, triangles, xy, lag, bins):
    """Tag the open edges by bins of x; return the tags and each bin's phase (deg)."""
    open_edges = [k for k, tag in boundary.items() if tag == "open"]
    if not open_edges:
        return boundary, {}
    if not lag:
        return boundary, {"open": 0.0}
    mid = np.array(
        [xy[triangles[t, [(e + 1) % 3, (e + 2) % 3]], 0].mean() for t, e in open_edges]
    )
    lo, hi = mid.min(), mid.max()
    k = np.minimum(((mid - lo) / max(hi - lo, 1e-9) * bins).astype(int), bins - 1)
    tagged, phases = dict(boundary), {}
    for edge, b in zip(open_edges, k, strict=True):
        tag = f"open{b}"
        tagged[edge] = tag
        phases[tag] = lag * (b + 0.5) / bins
    return tagged, phases


class Monitor(anuga.Operator):
    """A fractional step that records dt and checks the water every step."""

    def __init__(self, domain, amplitude, max_speed):
        super().__init__(domain, description="blow-up monitor")
        self.dts, self.cfl_dts = [], []
        self.stage_limit, self.speed_limit = 10 * amplitude, max_speed
        self.max_speed = self.max_stage = (0.0, -1, 0.0)  # value, triangle, time

    def __call__(self):
        d = self.domain
        self.dts.append(d.timestep)
        self.cfl_dts.append(min(d.CFL * d.flux_timestep, d.evolve_max_timestep))
        stage, xm, ym = self.stage_c, self.xmom_c, self.ymom_c
        if not (np.isfinite(stage).all() and np.isfinite(xm + ym).all()):
            k = int(np.flatnonzero(~np.isfinite(stage + xm + ym))[0])
            raise BlowUp(k, "NaN/inf in stage or momentum")
        h = stage - self.elev_c
        speed = np.where(h > 0.01, np.hypot(xm, ym) / np.maximum(h, 0.01), 0.0)
        k, j = int(speed.argmax()), int(np.abs(stage).argmax())
        if speed[k] > self.max_speed[0]:
            self.max_speed = (float(speed[k]), k, d.get_time())
        if abs(stage[j]) > self.max_stage[0]:
            self.max_stage = (float(abs(stage[j])), j, d.get_time())
        if speed[k] > self.speed_limit:
            raise BlowUp(k, f"speed {speed[k]:.2f} m/s > {self.speed_limit:g} m/s")
        if abs(stage[j]) > self.stage_limit:
            raise BlowUp(j, f"|stage| {abs(stage[j]):.2f} m > {self.stage_limit:g} m")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("mesh", type=Path)
    p.add_argument("--hours", type=float, required=True, help="model time")
    p.add_argument("--amplitude", type=float, default=1.0, help="tide, m")
    p.add_argument("--period", type=float, default=44712.0, help="s (M2)")
    p.add_argument("--depth-floor", type=float, help="min depth, m (else as is)")
    p.add_argument("--yieldstep", type=float, default=600.0, help="s")
    p.add_argument("--manning", type=float, default=0.025)
    p.add_argument("--max-speed", type=float, default=20.0, help="blow-up, m/s")
    p.add_argument("--crs", help="CRS of a mesh file that stores none")
    p.add_argument("--json", type=Path, help="write the results here")
    p.add_argument("--sww", type=Path, help="keep ANUGA's .sww output here")
    p.add_argument(
        "--phase-lag", type=float, default=0.0, help="deg, west to east (default 0)"
    )
    p.add_argument("--phase-bins", type=int, default=12, help="bins of the lag")
    p.add_argument(
        "--hump",
        nargs=4,
        type=float,
        metavar=("LON", "LAT", "RADIUS", "HEIGHT"),
        help="start with a Gaussian hump of the sea surface, HEIGHT m high and "
        "RADIUS m wide (e-folding), at LON, LAT: its waves cross a site at once, "
        "where a tide from far boundaries would take hours",
    )
    args = p.parse_args(argv)

    mesh = coastmesh.read_mesh(args.mesh)
    if "depth" not in mesh.point_data:
        sys.exit(
            f"{args.mesh}: no depth in the mesh (point_data 'depth'); use a "
            "format that stores it (fort.14, gr3, UGRID .nc, .gpkg)"
        )
    depth = np.asarray(mesh.point_data["depth"], dtype=float)
    if args.depth_floor is not None:
        depth = np.maximum(depth, args.depth_floor)
    xy, metric, crs = project(mesh, args.crs)
    origin = xy.min(axis=0)
    tris = mesh.triangles.copy()
    a, b, c = (xy[tris[:, i]] for i in range(3))
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
    area2 -= (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    flipped = int((area2 < 0).sum())
    tris[area2 < 0] = tris[area2 < 0][:, [0, 2, 1]]
    boundary, untagged, unmatched = boundary_tags(tris, mesh)
    notes = []
    if flipped:
        notes.append(f"{flipped} clockwise triangles reordered")
    if "open" not in boundary.values():
        notes.append("no open boundary edges (no boundary kinds in the file?)")
    if untagged or unmatched:
        notes.append(
            f"{untagged} boundary edges not in the file's boundaries "
            f"(tagged land), {unmatched} file boundary edges not on "
            "the mesh boundary"
        )

    amp, period, ramp = args.amplitude, args.period, 3600.0
    boundary, phases = phase_bins(boundary, tris, xy, args.phase_lag, args.phase_bins)

    def tide_at(phase):
        def tide(t):
            r = 0.5 * (1 - math.cos(math.pi * t / ramp)) if t < ramp else 1.0
            return amp * r * math.sin(2 * math.pi * t / period - math.radians(phase))

        return tide

    utm = (metric.utm_zone or "") if metric else ""
    t_wall = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="anuga_run_") as tmp, contextlib.chdir(tmp):
        domain = anuga.Domain(
            xy - origin,
            tris,
            boundary=boundary,
            geo_reference=anuga.Geo_reference(
                int(utm[:-1]) if utm else -1,  # UTM zone; -1: not UTM
                *origin,
                hemisphere={"N": "northern", "S": "southern"}.get(
                    utm[-1:], "undefined"
                ),
            ),
        )
        domain.set_name("run")
        domain.set_datadir(tmp)
        domain.set_quantity("elevation", -depth, location="unique vertices")
        if args.hump is None:
            domain.set_quantity("stage", 0.0)
        else:
            lon, lat, radius, height = args.hump
            to_metric = Transformer.from_crs(4326, metric, always_xy=True)
            hx, hy = np.subtract(to_metric.transform(lon, lat), origin)

            def hump(x, y):
                r2 = ((x - hx) ** 2 + (y - hy) ** 2) / radius**2
                return height * np.exp(-r2)

            domain.set_quantity("stage", hump, location="centroids")
        domain.set_quantity("friction", args.manning)
        bcs = {"land": anuga.Reflective_boundary(domain)}
        for tag, phase in phases.items():
            bcs[tag] = anuga.Transmissive_n_momentum_zero_t_momentum_set_stage_boundary(
                domain, function=tide_at(phase)
            )
        domain.set_boundary({tag: bcs[tag] for tag in set(boundary.values())})
        monitor = Monitor(
            domain, max(amp, args.hump[3] if args.hump else 0.0), args.max_speed
        )
        setup = time.perf_counter() - t_wall
        status, reason, where = "ok", None, None
        try:
            for t in domain.evolve(
                yieldstep=args.yieldstep, finaltime=args.hours * 3600.0
            ):
                print(
                    f"  t = {t / 3600:6.2f} h  steps {len(monitor.dts):7d}  "
                    f"max speed {monitor.max_speed[0]:5.2f} m/s  "
                    f"max |stage| {monitor.max_stage[0]:5.2f} m",
                    flush=True,
                )
        except BlowUp as e:
            status, (where, reason) = "blew up", e.args
        except Exception as e:  # ANUGA's own failures (tiny dt, ...)
            status, reason = "blew up", f"ANUGA: {type(e).__name__}: {e}"
        t_end = domain.get_time()
        cx, cy = (domain.centroid_coordinates + origin).T
        if args.sww and (tmp_sww := Path(tmp) / "run.sww").exists():
            shutil.copy(tmp_sww, args.sww)
    wall = time.perf_counter() - t_wall

    back = Transformer.from_crs(metric, crs, always_xy=True) if crs else None

    def place(k):
        if k is None or k < 0:
            return None
        x, y = float(cx[k]), float(cy[k])
        at = {"triangle": int(k), "x": round(x, 1), "y": round(y, 1)}
        if crs is not None and crs.is_geographic:
            lon, lat = back.transform(x, y)
            at |= {"lon": round(float(lon), 5), "lat": round(float(lat), 5)}
        return at

    def extreme(record):
        value, k, t = record
        return {"value": value, "hours": t / 3600, "at": place(k)}

    dt = np.array(monitor.cfl_dts) if monitor.cfl_dts else np.full(1, np.nan)
    out = {
        "mesh": str(args.mesh),
        "nodes": len(mesh.points),
        "triangles": len(mesh.triangles),
        "boundary_edges": len(boundary),
        "open_edges": sum(v != "land" for v in boundary.values()),
        "phase_lag": args.phase_lag,
        "hump": args.hump,
        "crs": crs.to_string() if crs else None,
        "metric_crs": metric.to_string() if metric else None,
        "depth_range": [float(depth.min()), float(depth.max())],
        "amplitude": amp,
        "period": period,
        "manning": args.manning,
        "hours_requested": args.hours,
        "hours_simulated": t_end / 3600,
        "wall_seconds": wall,
        "setup_seconds": setup,
        "steps": len(monitor.dts),
        "dt_min": float(dt.min()),
        "dt_median": float(np.median(dt)),
        "dt_max": float(dt.max()),
        "max_speed": extreme(monitor.max_speed),
        "max_abs_stage": extreme(monitor.max_stage),
        "status": status,
        "blowup": None
        if status == "ok"
        else {"hours": t_end / 3600, "reason": reason, "at": place(where)},
        "notes": notes,
        "anuga": anuga.__version__,
        "flow_algorithm": domain.get_flow_algorithm(),
        "cfl": domain.CFL,
    }
    line = (
        f"{args.mesh.name}: {status} after {t_end / 3600:.2f} h of "
        f"{args.hours:g} h; {out['nodes']} nodes, {out['triangles']} "
        f"triangles; {out['steps']} steps, dt {out['dt_min']:.3g}/"
        f"{out['dt_median']:.3g}/{out['dt_max']:.3g} s (min/median/max); "
        f"max speed {monitor.max_speed[0]:.2f} m/s, max |stage| "
        f"{monitor.max_stage[0]:.2f} m; {wall:.1f} s wall"
    )
    if reason:
        line += f"; {reason} at {place(where)}"
    print(line)
    for n in notes:
        print("note:", n)
    if args.json:
        args.json.write_text(json.dumps(out, indent=2) + "\n")
    return 0 if status == "ok" else 1


if __name__ == "__main__":
    sys.exit(main())
