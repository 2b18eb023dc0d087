"""Run ADCIRC and SCHISM on coastmesh's meshes: the smoke test of every case.

For each case, the mesh is built (``coastmesh.build_case``) and kept as UGRID
with its time step; then, for each model, the smoke-test folder
(:func:`coastmesh.io.write_model_test`: an M2 tide of 0.5 m on every open
boundary after a 6 h ramp, one M2 cycle; ADCIRC at the case's own ``dt``,
SCHISM at a step of its own rules) is written and the model is run in it.
The table says, for each run, whether it ran to the end, the largest
elevation and speed (from the models' own ``maxele.63`` / ``maxvel.63`` and
``maxelev_*`` / ``maxdahv_*``, every time step), where the largest speed is
(and whether that node is where an open boundary meets the coast), the
elevation warnings, and the model's steps per second.

The models are not built here. Build them from their public sources
(``adcirc/adcirc``: serial ``adcirc``; ``schism-dev/schism``: ``pschism``, any
TVD limiter, with ``OLDIO=OFF``) and pass the binaries::

    python benchmarks/models/run_models.py --adcirc ~/models/bin/adcirc \\
        --schism ~/models/bin/pschism --out runs/models

    # one case, one model, the grid files of an older checkout of coastmesh
    python benchmarks/models/run_models.py --adcirc ~/models/bin/adcirc \\
        --models adcirc --cases examples/orkney/pentland_firth.toml \\
        --writer /path/to/old/checkout/src --label before

``--writer SRC`` writes ``fort.14`` / ``hgrid.gr3`` with the coastmesh found in
``SRC`` (a subprocess with ``PYTHONPATH=SRC``), everything else with today's, and
fits the forcing to that grid's open nodes: the before-and-after of a writer
change on the same mesh. ``--hours H`` stops each run after H model hours
(default: the whole ramp and cycle). ``--adcirc-procs N`` runs ``padcirc`` on
N processes after ``adcprep`` (see :func:`run`). SCHISM runs as ``mpirun -np 2
pschism 1`` (one process computes, one writes; the writer niced, as its busy
wait would take a core from the computing one on a 2-core machine).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
CASES = [  # shortest runs first; the farm's 4.5 m footprints take 0.09 s steps
    "examples/orkney/pentland_firth.toml",
    "examples/nw_european_shelf/coarse.toml",
    "tests/data/coasts/oresund.toml",
    "tests/data/coasts/shetland.toml",
    "tests/data/coasts/vestfjorden.toml",
    "examples/nw_european_shelf/intermediate.toml",
    "examples/norway/fjords_mesh.toml",
    "examples/orkney/inner_sound_farm.toml",
]


def build(case: str, out: Path) -> tuple[Path, float]:
    """Build the case once; keep its mesh (UGRID) and dt. Return both."""
    import coastmesh
    from coastmesh.case.result import model_dt

    mesh_file, info = out / "mesh.nc", out / "mesh.json"
    if mesh_file.exists() and info.exists():
        return mesh_file, json.loads(info.read_text())["dt"]
    out.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = coastmesh.build_case(ROOT / case)
    dt = model_dt(result.report.quality)
    coastmesh.write_mesh(mesh_file, result.mesh, overwrite=True)
    info.write_text(
        json.dumps(
            {
                "case": case,
                "dt": dt,
                "nodes": len(result.mesh.points),
                "triangles": len(result.mesh.triangles),
            }
        )
    )
    return mesh_file, dt


def old_grid(writer_src: Path, mesh_file: Path, target: Path, fmt: str) -> None:
    """Write ``target`` with the coastmesh of ``writer_src`` (an older checkout)."""
    code = (
        "import sys, warnings; warnings.simplefilter('ignore'); import coastmesh; "
        "m = coastmesh.read_mesh(sys.argv[1]); "
        "coastmesh.write_mesh(sys.argv[2], m, format=sys.argv[3], overwrite=True)"
    )
    env = dict(os.environ, PYTHONPATH=str(writer_src))
    subprocess.run(
        [sys.executable, "-c", code, str(mesh_file), str(target), fmt],
        check=True,
        env=env,
    )


def open_counts(grid: Path) -> list[int]:
    """The node count of each open segment of a fort.14 / gr3, as written."""
    lines = grid.read_text().splitlines()
    ne, npt = (int(v) for v in lines[1].split()[:2])
    at = 2 + ne + npt
    nope = int(lines[at].split()[0])
    at += 2
    counts = []
    for _ in range(nope):
        size = int(lines[at].split()[0])
        counts.append(size)
        at += 1 + size
    return counts


def fit_forcing(folder: Path, model: str) -> None:
    """Make the forcing list one line per open node of the grid in ``folder``."""
    if model == "adcirc":
        neta = sum(open_counts(folder / "fort.14"))
        lines = (folder / "fort.15").read_text().splitlines()
        at = next(i for i, s in enumerate(lines) if s.startswith("M2 ! EALPHA")) + 1
        end = next(i for i in range(at, len(lines)) if "ANGINN" in lines[i])
        amp = lines[at]
        lines[at:end] = [amp] * neta
        (folder / "fort.15").write_text("\n".join(lines) + "\n")
    else:
        counts = open_counts(folder / "hgrid.gr3")
        lines = (folder / "bctides.in").read_text().splitlines()
        amp = lines[8]
        head = lines[:5] + [f"{len(counts)} !nope"]
        for size in counts:
            head += [f"{size} 3 0 0 0", "M2"] + [amp] * size
        (folder / "bctides.in").write_text("\n".join(head) + "\n")


def shorten(folder: Path, model: str, hours: float) -> None:
    """Stop the run after ``hours`` of model time."""
    days = f"{hours / 24:.10f}"
    if model == "adcirc":
        text = (folder / "fort.15").read_text()
        text = re.sub(r"^\S+ ! RNDAY$", f"{days} ! RNDAY", text, flags=re.M)
        (folder / "fort.15").write_text(text)
    else:
        text = (folder / "param.nml").read_text()
        text = re.sub(r"rnday = \S+", f"rnday = {days}", text)
        (folder / "param.nml").write_text(text)


def set_params(folder: Path, pairs: list[str]) -> None:
    """Set ``key=value`` pairs in SCHISM's param.nml (a key it lists, or a new one).

    A new key goes into ``&OPT``. For trying other SCHISM settings on the same
    mesh and forcing, e.g. ``ishapiro=1 ihorcon=0``.
    """
    text = (folder / "param.nml").read_text()
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep:
            sys.exit(f"--schism-param {pair!r}: expected key=value")
        pattern = rf"^(\s*){re.escape(key.strip())}\s*=.*$"
        if re.search(pattern, text, flags=re.M):
            text = re.sub(
                pattern, rf"\g<1>{key.strip()} = {value.strip()}", text, flags=re.M
            )
        else:
            text = text.replace(
                "&OPT\n", f"&OPT\n  {key.strip()} = {value.strip()}\n", 1
            )
    (folder / "param.nml").write_text(text)


def run(folder: Path, model: str, binary: str, timeout: float, procs: int = 1) -> float:
    """Run the model in ``folder``; return the wall time, s.

    ADCIRC with ``procs`` > 1 runs ``binary`` (then ``padcirc``) on that many
    MPI processes, after ADCIRC's own decomposition: ``adcprep --np N
    --partmesh`` then ``--prepall``, with the ``adcprep`` beside ``binary``
    (both built with ``-DBUILD_PADCIRC=ON -DBUILD_ADCPREP=ON``). The maxima
    files are written whole by the root process, as in a serial run.
    """
    env = dict(
        os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"
    )
    if model == "adcirc" and procs > 1:
        adcprep = str(Path(binary).with_name("adcprep"))
        with open(folder / "adcprep.log", "wb") as log:
            for step in ("--partmesh", "--prepall"):
                subprocess.run(
                    [adcprep, "--np", str(procs), step],
                    cwd=folder,
                    stdout=log,
                    stderr=subprocess.STDOUT,
                    check=True,
                )
        command = ["mpirun", "--oversubscribe", "-np", str(procs), binary]
    elif model == "adcirc":
        command = [binary]
    else:
        # the scribe (the last process) only writes; niced, its busy wait gives
        # the core to the computing process
        command = [
            "mpirun",
            "--oversubscribe",
            "-np",
            "1",
            binary,
            "1",
            ":",
            "-np",
            "1",
            "nice",
            "-n",
            "19",
            binary,
            "1",
        ]
    start = time.perf_counter()
    with open(folder / "run.log", "wb") as log:
        try:
            subprocess.run(
                command,
                cwd=folder,
                stdout=log,
                stderr=subprocess.STDOUT,
                env=env,
                timeout=timeout,
                check=False,
            )
        except subprocess.TimeoutExpired:
            (folder / "TIMEOUT").write_text(f"{timeout} s\n")
    return time.perf_counter() - start


def _adcirc_max(path: Path, n: int) -> np.ndarray | None:
    """The first dataset of an ASCII maxele.63 / maxvel.63: one value per node.

    NaN where the node was never wet (ADCIRC writes -99999 there).
    """
    if not path.exists():
        return None
    lines = path.read_text().splitlines()
    if len(lines) < 3 + n:
        return None
    values = np.array([float(s.split()[1]) for s in lines[3 : 3 + n]])
    return np.where(values <= -99998.0, np.nan, values)


def _schism_max(folder: Path, prefix: str, n: int) -> np.ndarray | None:
    """Gather SCHISM's per-process maxelev_* / maxdahv_*: one value per node."""
    files = sorted((folder / "outputs").glob(f"{prefix}_*"))
    if not files:
        return None
    out = np.full(n, np.nan)
    for f in files:
        rows = np.loadtxt(f, skiprows=1, ndmin=2)
        if rows.size:
            out[rows[:, 0].astype(int) - 1] = rows[:, 3]
    return out


def summarise(
    folder: Path, model: str, mesh, duration: float, dt: float, wall: float
) -> dict:
    """What a run did: finished, stop time, maxima, warnings, steps per second."""
    n = len(mesh.points)
    log = (folder / "run.log").read_text(errors="replace")
    if model == "adcirc":
        fort16 = folder / "fort.16"
        text = log + (fort16.read_text(errors="replace") if fort16.exists() else "")
        finished = "ADCIRC terminating normally" in text
        warns = text.count("Elevation.gt.WarnElev")
        errors = text.count("Elevation.gt.ErrorElev")
        elev = _adcirc_max(folder / "maxele.63", n)
        speed = _adcirc_max(folder / "maxvel.63", n)
        steps = re.findall(r"TIME STEP =\s*(\d+)", log)
    else:
        mirror = folder / "outputs" / "mirror.out"
        text = mirror.read_text(errors="replace") if mirror.exists() else ""
        fatal = folder / "outputs" / "fatal.error"
        fatal_text = fatal.read_text(errors="replace").strip() if fatal.exists() else ""
        finished = "Run completed successfully" in text
        warns, errors = 0, int(bool(fatal_text))
        elev = _schism_max(folder, "maxelev", n)
        speed = _schism_max(folder, "maxdahv", n)
        steps = re.findall(r"TIME STEP=\s*(\d+)", text)
    last = int(steps[-1]) if steps else 0
    total = math.ceil(duration / dt)
    done = total if finished else last
    row = {
        "model": model,
        "finished": bool(finished) and not (folder / "TIMEOUT").exists(),
        "model_hours": done * dt / 3600,
        "steps": done,
        "wall_s": round(wall, 1),
        "steps_per_s": round(done / wall, 1) if wall > 0 else None,
        "elevation_warnings": warns,
        "elevation_errors": errors,
    }
    depth = mesh.point_data["depth"]
    for key, values in (("elevation", elev), ("speed", speed)):
        if values is None or not np.isfinite(values).any():
            row[f"max_{key}"] = None
            continue
        k = int(np.nanargmax(np.abs(values)))
        row[f"max_{key}"] = round(float(abs(values[k])), 3)
        row[f"max_{key}_at"] = where(mesh, k, depth)
    return row


def where(mesh, k: int, depth) -> dict:
    """Node ``k``: lon, lat, depth and what boundaries it is on."""
    from pyproj import Transformer

    x, y = mesh.points[k]
    if mesh.crs is not None and not mesh.crs.is_geographic:
        x, y = Transformer.from_crs(mesh.crs, "EPSG:4326", always_xy=True).transform(
            x, y
        )
    on = sorted(
        {int(i) for i in mesh.boundary_ids[(mesh.boundary_edges == k).any(axis=1)]}
    )
    kinds = sorted({mesh.boundary_kinds.get(i, "?") for i in on})
    return {
        "node": k + 1,
        "lon": round(float(x), 5),
        "lat": round(float(y), 5),
        "depth": round(float(depth[k]), 2),
        "boundary_ids": on,
        "corner": kinds == ["open", "shoreline"],
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--adcirc", help="the adcirc binary (padcirc with --adcirc-procs)")
    p.add_argument(
        "--adcirc-procs",
        type=int,
        default=1,
        help="run --adcirc (then padcirc, with adcprep beside it) on N MPI processes",
    )
    p.add_argument("--schism", help="the pschism binary")
    p.add_argument("--models", nargs="+", default=["adcirc", "schism"])
    p.add_argument("--cases", nargs="+", default=CASES)
    p.add_argument("--out", type=Path, default=Path("runs/models"))
    p.add_argument("--writer", type=Path, help="src/ of another coastmesh checkout")
    p.add_argument("--label", default="now", help="a name for this set of runs")
    p.add_argument("--land", default="essential", choices=["essential", "natural"])
    p.add_argument("--hours", type=float, help="stop each run after H model hours")
    p.add_argument("--timeout", type=float, default=6 * 3600, help="s per run")
    p.add_argument(
        "--schism-dt",
        type=float,
        help="SCHISM's time step, s (default SCHISM's own rule, as the smoke test "
        "writes it: CFL > 0.4 on 95 %% of the wet elements, within 100-400 s)",
    )
    p.add_argument(
        "--schism-param",
        nargs="+",
        default=[],
        metavar="KEY=VALUE",
        help="set these in SCHISM's param.nml (e.g. ishapiro=1 ihorcon=0)",
    )
    args = p.parse_args()
    import coastmesh
    from coastmesh.io.meshes.model_tests import ModelTest

    rows = []
    for case in args.cases:
        name = Path(case).stem
        mesh_file, case_dt = build(case, args.out / name)
        mesh = coastmesh.read_mesh(mesh_file)
        for model in args.models:
            dt = case_dt
            binary = getattr(args, model)
            if not binary:
                sys.exit(f"--{model}: give the path of the {model} binary")
            folder = args.out / name / f"{model}-{args.label}"
            if folder.exists():
                shutil.rmtree(folder)
            coastmesh.io.write_model_test(
                folder, mesh, model, dt=dt, schism_dt=args.schism_dt
            )
            if model == "schism":  # its own step (or --schism-dt), as written
                dt = float(
                    re.search(
                        r"^\s*dt = (\S+)$", (folder / "param.nml").read_text(), re.M
                    )[1]
                )
            if model == "adcirc" and args.land != "essential":
                coastmesh.write_mesh(
                    folder / "fort.14",
                    mesh,
                    format="fort14",
                    overwrite=True,
                    regions=False,
                    land=args.land,
                )
            if args.writer is not None:
                grid = "fort.14" if model == "adcirc" else "hgrid.gr3"
                fmt = "fort14" if model == "adcirc" else "gr3"
                old_grid(args.writer, mesh_file, folder / grid, fmt)
                fit_forcing(folder, model)
            if model == "schism" and args.schism_param:
                set_params(folder, args.schism_param)
            duration = ModelTest(dt).duration
            if args.hours is not None:
                duration = min(duration, args.hours * 3600)
                shorten(folder, model, duration / 3600)
            wall = run(folder, model, binary, args.timeout, args.adcirc_procs)
            row = {
                "case": name,
                "label": args.label,
                "nodes": len(mesh.points),
                "dt": dt,
            }
            if model == "schism" and args.schism_param:
                row["schism_param"] = args.schism_param
            if model == "adcirc" and args.adcirc_procs > 1:
                row["procs"] = args.adcirc_procs
            row |= summarise(folder, model, mesh, duration, dt, wall)
            rows.append(row)
            print(json.dumps(row), flush=True)
            with open(args.out / "runs.jsonl", "a") as f:
                f.write(json.dumps(row) + "\n")
    print()
    print(
        "| case | model | label | nodes | dt (s) | ran to the end | model h "
        "| max elev (m) | max speed (m/s) | at | warnings | steps/s |"
    )
    print("|---|---|---|---:|---:|---|---:|---:|---:|---|---:|---:|")
    for r in rows:
        at = r.get("max_speed_at") or {}
        spot = f"{at.get('lon')}, {at.get('lat')} ({at.get('depth')} m)" if at else ""
        if at.get("corner"):
            spot += ", open/coast corner"
        print(
            f"| {r['case']} | {r['model']} | {r['label']} | {r['nodes']:,} "
            f"| {r['dt']:g} | "
            f"{'yes' if r['finished'] else 'no'} | {r['model_hours']:.2f} | "
            f"{r['max_elevation']} | {r['max_speed']} | {spot} | "
            f"{r['elevation_warnings']} | {r['steps_per_s']} |"
        )


if __name__ == "__main__":
    main()
