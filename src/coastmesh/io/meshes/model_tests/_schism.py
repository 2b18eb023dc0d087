"""SCHISM smoke test: the inputs of a 2-D barotropic tidal run.

From SCHISM's own docs and source (``schism-dev/schism``: ``docs/input-output/``
``hgrid.md``, ``vgrid.md``, ``bctides.md``, ``param.md``;
``src/Hydro/schism_init.F90``, which reads them):

- ``hgrid.gr3``: the grid (:func:`~coastmesh.io.meshes.adcirc.write_gr3`), in the
  mesh's CRS; ``ics = 1`` for a projected mesh, ``ics = 2`` for lon/lat (then
  ``hgrid.gr3`` is in degrees too). ``hgrid.ll``: the same grid in lon/lat, for
  the Coriolis parameter of each node (``ncor = 1``);
- ``vgrid.in``: one layer (``ivcor = 2``, ``nvrt = 2``), which makes SCHISM a 2-D
  depth-averaged model (``vgrid.md``); SCHISM has no compile-time 2-D switch;
- ``bctides.in``: no tidal potential, one constituent (M2, 1.405189e-4 rad/s,
  nodal factor 1, argument 0) and, for each open segment of the grid in turn,
  ``nnodes 3 0 0 0`` (elevation from harmonics; no velocity, temperature or
  salinity condition) and ``amplitude phase`` for each of its nodes;
- ``manning.gr3``: Manning's n at each node, read with ``nchi = -1`` and
  ``hmin_man = 1`` m, raised where ADCIRC's floor on the drag coefficient
  (:data:`~coastmesh.io.meshes.model_tests.MIN_DRAG`) would raise it: ``n =
  max(n, sqrt(MIN_DRAG max(h, hmin_man)^(1/3) / g))`` at the node's
  still-water depth ``h`` (:func:`floored_manning`), so both models have the
  same friction;
- ``param.nml``: ``ibc = 1, ibtp = 0`` (barotropic), ``dramp`` the ramp in days
  (``nramp_elev = 0``), ``thetai = 1`` ("maximum stability for strong
  wet/dry"), ``h0 = 0.01`` m (wetting and drying), ``itur = 0``, ``rmaxvel =
  10`` m/s (SCHISM's cap on the speed; its default 5 would hide a blow-up
  under the 3 m/s a smoke test looks for); elevation and depth-averaged
  velocity in ``outputs/out2d_1.nc`` every 10 min, and none of the 3-D
  outputs SCHISM writes by default (each would need a scribe process of its
  own). ``&CORE`` lists every key, as SCHISM gives it no defaults; ``&OPT``
  only those changed;
- **SCHISM's own time step**, not the mesh's explicit one
  (:func:`schism_time_step`). SCHISM is implicit and tracks momentum
  advection by Eulerian-Lagrangian backtracking (ELM), whose numerical
  diffusion asks for the opposite of an explicit model's limit:
  ``CFL = (|u| + sqrt(g h)) dt / dx > 0.4``, "at least in wet areas", with
  ``dt`` in "100-400 s for barotropic" field applications
  (``docs/getting-started/grid-generation.md``, "Beware of CFL number", and
  ``typical-workflow.md``, mesh generation tips 4, 5 and 9). The step is the
  one at which 95 % of the wet elements meet that criterion, held to that
  range, in whole seconds;
- **momentum advection off** (``nadv = 0`` with ``adv.gr3`` 0 at a node, 1
  elsewhere, ``docs/input-output/optional-inputs.md``) where the elements
  still have ``CFL < 0.4`` at that step (the deep, coarse sea:
  SCHISM's ``case-study.md`` turns advection off in the open ocean as it "is
  negligible there ... this bypasses the inverse CFL criterion"), and within
  two rings of nodes of the open boundaries (an elevation boundary gives
  backtracking no inflow to start from; ADCIRC's set does the same);
- ``indvel = 0, ishapiro = 1, shapiro0 = 0.5, niter_shap = 1, ihorcon = 0``:
  ``sample_inputs/param.nml``'s "easiest option" for non-eddying
  applications (nearshore, estuary, river).

  Measured with SCHISM master 820ac00 on the examples' meshes (one M2 cycle
  of 0.5 m after a 6 h ramp): the demo ran at 0.54 m and 0.64 m/s at this
  step, where the mesh's own 1.8 s gave 0.72 m and 1.00 m/s, and where 100 s
  without the two advection rules and with bi-harmonic viscosity (``ihorcon
  = 2``, the earlier set) reached 10.9 m/s; the NW-shelf intermediate mesh at
  its own 6.6 s reached 305 m;
- ``outputs/``, which SCHISM needs before it starts.

SCHISM is run under MPI with one scribe (``mpirun -np 2 pschism 1``: the last
process writes the outputs). It also writes, per process,
``outputs/maxelev_*`` and ``outputs/maxdahv_*``: the largest elevation and
depth-averaged speed of each node over the run.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.io.meshes._model import require_kinds
from coastmesh.io.meshes._table import put_lines, write_table
from coastmesh.io.meshes.adcirc import write_gr3
from coastmesh.io.meshes.adcirc._segments import grid_segments
from coastmesh.io.meshes.model_tests import (
    GRAVITY,
    M2_FREQUENCY,
    MIN_DRAG,
    ModelTest,
    Place,
    near_nodes,
    readme,
)
from coastmesh.meshing.quality.time_step import element_time_steps
from coastmesh.types import Mesh

__all__ = ["INVERSE_CFL", "STEP_RANGE", "floored_manning", "schism_time_step", "write"]

#: SCHISM's lower bound on the Courant number of its ELM advection ("CFL >
#: 0.4", docs/getting-started/grid-generation.md)
INVERSE_CFL = 0.4
#: SCHISM's operating range of time steps for barotropic field runs, s
#: (docs/getting-started/grid-generation.md; typical-workflow.md, tip 4)
STEP_RANGE = (100.0, 400.0)
#: The share of wet elements that meet INVERSE_CFL at the step chosen; advection
#: is off on the rest (module docstring)
_MET_SHARE = 95.0
#: The velocity scale |u| of SCHISM's CFL, m/s (its docs drop sqrt(g h) in the
#: shallows and take |u| ~ 1 there)
_VELOCITY = 1.0
#: Wet: deeper than this, m (the docs' h < 0.1 m is dry)
_WET = 0.1
#: Rings of nodes inside the open boundaries with advection off
_QUIET_RINGS = 2

_OUTPUT_EVERY = 600.0  # s
_HMIN_MAN = 1.0  # m: the least depth in SCHISM's Manning formula (hmin_man)
_VGRID_2D = """2 !ivcor: SZ
2 1 1.e6 !nvrt = 2 (one layer: 2-D), kz = 1, h_s
Z levels
1 -1.e6
S levels
40. 1. 1.e-4 !h_c theta_b theta_f
1 -1.
2 0.
"""


def write(
    folder: Path, mesh: Mesh, test: ModelTest, where: Place, land: str
) -> list[str]:
    """Write the SCHISM run folder; return its files (``land`` is ADCIRC's)."""
    del land
    if test.schism_dt is None:
        step, slow = schism_time_step(mesh)
    else:
        step, slow = test.schism_dt, _below_inverse_cfl(mesh, test.schism_dt)
    test = dataclasses.replace(test, dt=step)
    write_gr3(folder / "hgrid.gr3", mesh, regions=False)
    lonlat = mesh if where.geographic else _in_lonlat(mesh, where)
    write_gr3(folder / "hgrid.ll", lonlat, regions=False, title="coastmesh hgrid.ll")
    (folder / "vgrid.in").write_text(_VGRID_2D, encoding="ascii")
    kinds = require_kinds(mesh, "hgrid.gr3")
    opened, _ = grid_segments(mesh, "hgrid.gr3", kinds, "gr3")
    (folder / "bctides.in").write_text(
        _bctides(test, [len(s.nodes) for s in opened]), encoding="ascii"
    )
    depth = np.asarray(mesh.point_data["depth"], dtype=np.float64)
    _write_node_file(
        folder / "manning.gr3",
        mesh,
        floored_manning(test.node_manning(mesh), depth),
        f"manning: n, raised to Cd >= {MIN_DRAG:g} at the still-water depth",
        digits=8,
    )
    advection = np.ones(len(mesh.points))
    advection[np.unique(mesh.triangles[slow])] = 0.0
    advection[
        near_nodes(mesh, np.concatenate([s.nodes for s in opened]), _QUIET_RINGS)
    ] = 0.0
    _write_node_file(
        folder / "adv.gr3", mesh, advection, "adv: momentum advection on (1) or off (0)"
    )
    (folder / "param.nml").write_text(_param(test, where), encoding="ascii")
    (folder / "outputs").mkdir()
    run = "mpirun -np 2 pschism 1   (one process computes, one writes outputs/)"
    look = (
        "- the end of outputs/mirror.out: 'Run completed successfully'; no\n"
        "  outputs/fatal.error with a message;\n"
        "- outputs/maxelev_* and outputs/maxdahv_* (node, x, y, largest elevation\n"
        "  or speed, ...), one file per computing process; outputs/out2d_1.nc.\n"
    )
    why = (
        f"the step given, {step:g} s"
        if test.schism_dt is not None
        else f"SCHISM's own step, {step:g} s, not the mesh's explicit one: CFL = "
        f"(|u| + sqrt(g h)) dt / dx > {INVERSE_CFL:g} on {_MET_SHARE:g} % of the "
        f"wet elements, within {STEP_RANGE[0]:g}-{STEP_RANGE[1]:g} s (SCHISM's "
        "docs, 'Beware of CFL number')"
    )
    note = (
        f"It runs at {why}. Momentum advection is off (adv.gr3) where CFL < "
        f"{INVERSE_CFL:g} at that step ({int(slow.sum())} elements) and within two "
        "rings of nodes of the open boundaries.\n\n"
    )
    (folder / "README.txt").write_text(readme("SCHISM", test, run, look, note))
    return [
        "hgrid.gr3",
        "hgrid.ll",
        "vgrid.in",
        "bctides.in",
        "manning.gr3",
        "adv.gr3",
        "param.nml",
        "README.txt",
    ]  # and the empty folder outputs/


def schism_time_step(mesh: Mesh) -> tuple[float, NDArray[np.bool_]]:
    """Return SCHISM's time step for ``mesh``, and the elements still below it.

    The step at which ``CFL = (|u| + sqrt(g h)) dt / dx`` is above
    :data:`INVERSE_CFL` on 95 % of the wet elements (``dx`` the mean side,
    ``h`` the deepest node, ``|u|`` 1 m/s), rounded up to a whole second and
    held to :data:`STEP_RANGE`; and which elements have a CFL under
    :data:`INVERSE_CFL` at that step (the smoke test turns advection off
    there).

    Examples
    --------
    >>> n = 11  # 1 km squares, 20 m deep: sqrt(g h) + 1 = 15 m/s
    >>> pts = np.mgrid[0:n, 0:n].reshape(2, -1).T * 1000.0
    >>> q = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)).ravel()
    >>> tri = np.vstack([np.column_stack([q, q + n, q + n + 1]),
    ...                  np.column_stack([q, q + n + 1, q + 1])])
    >>> m = Mesh(pts, tri, [[0, 1]], [1], 1, "EPSG:32630", {"depth": [20.0] * n * n})
    >>> step, slow = schism_time_step(m)
    >>> step, int(slow.sum())  # 0.4 x 1138 m / 15 m/s = 30.4 s: the range's 100 s
    (100.0, 0)
    """
    need = _needed_steps(mesh)
    wet = np.isfinite(need)
    met = float(np.percentile(need[wet], _MET_SHARE)) if wet.any() else STEP_RANGE[0]
    step = float(np.clip(math.ceil(met), *STEP_RANGE))
    return step, _below_inverse_cfl(mesh, step, need)


def _needed_steps(mesh: Mesh) -> NDArray[np.float64]:
    """Return the shortest step at which each element meets the inverse CFL.

    NaN where the element is dry.
    """
    e = element_time_steps(mesh)
    depth = e["depth"]
    speed = np.sqrt(GRAVITY * np.maximum(depth, 0.0)) + _VELOCITY
    need = INVERSE_CFL * e["mean_edge"] / speed
    return np.where(depth > _WET, need, np.nan)


def _below_inverse_cfl(
    mesh: Mesh, step: float, need: NDArray[np.float64] | None = None
) -> NDArray[np.bool_]:
    """Which wet elements have CFL < :data:`INVERSE_CFL` at ``step``."""
    need = _needed_steps(mesh) if need is None else need
    return np.asarray(np.isfinite(need) & (need > step), dtype=bool)


def _in_lonlat(mesh: Mesh, where: Place) -> Mesh:
    """Return the mesh with its nodes in lon/lat (for ``hgrid.ll``)."""
    return Mesh(
        where.lonlat,
        mesh.triangles,
        mesh.boundary_edges,
        mesh.boundary_ids,
        mesh.surface_id,
        CRS.from_epsg(4326),
        {"depth": mesh.point_data["depth"]},
        mesh.boundary_names,
        mesh.boundary_kinds,
    )


def _bctides(test: ModelTest, sizes: list[int]) -> str:
    """Tidal elevation on every open segment, in the grid's order (``bctides.md``)."""
    lines = [
        "coastmesh smoke test: M2 on every open boundary (start time not used)",
        "0 40. !ntip tip_dp: no tidal potential",
        "1 !nbfr",
        "M2",
        f"{M2_FREQUENCY:.9e} 1.0 0.0 !frequency (rad/s), nodal factor, argument",
        f"{len(sizes)} !nope",
    ]
    for size in sizes:
        lines += [f"{size} 3 0 0 0 !nodes, elevation from harmonics", "M2"]
        lines += [f"{test.amplitude:g} 0.0"] * size
    return "\n".join(lines) + "\n"


def floored_manning(
    manning: NDArray[np.float64], depth: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Return Manning's n raised so that ``g n^2 / H^(1/3) >= MIN_DRAG``.

    ``H`` is the still-water ``depth`` (positive down), at least
    ``hmin_man`` (SCHISM's least depth in the formula). ADCIRC holds its drag
    at the floor as the water level moves; this holds it at mean sea level,
    which differs where the tide is a large part of the depth.

    Examples
    --------
    >>> floored_manning(np.array([0.025, 0.025, 0.04]), np.array([8.0, 64.0, 64.0]))
    array([0.025     , 0.03192754, 0.04      ])
    """
    h = np.maximum(np.asarray(depth, dtype=np.float64), _HMIN_MAN)
    least = np.sqrt(MIN_DRAG * np.cbrt(h) / GRAVITY)
    return np.maximum(np.asarray(manning, dtype=np.float64), least)


def _write_node_file(
    path: Path, mesh: Mesh, values: np.ndarray, title: str, digits: int = 6
) -> None:
    """Write a node-value ``.gr3`` (as ``manning.gr3``): nodes, elements, no lists.

    ``digits`` counts the integer part's too (:func:`write_table`).
    """
    n, m = len(mesh.points), len(mesh.triangles)
    with open(path, "wb") as handle:
        put_lines(handle, title, f"{m} {n}")
        write_table(
            handle,
            [
                (np.arange(1, n + 1), None),
                (mesh.points[:, 0], 15),
                (mesh.points[:, 1], 15),
                (values, digits),
            ],
        )
        write_table(
            handle,
            [(np.arange(1, m + 1), None), (np.full(m, 3), None)]
            + [(mesh.triangles[:, k] + 1, None) for k in range(3)],
        )


def _param(test: ModelTest, where: Place) -> str:
    """``param.nml``: ``&CORE`` whole, ``&OPT`` and ``&SCHOUT`` as changed."""
    dt = test.dt
    spool = max(1, round(_OUTPUT_EVERY / dt))
    steps = math.ceil(test.duration / dt)
    files = max(1, math.ceil(steps / spool))
    core = {
        "ipre": 0,
        "ibc": 1,
        "ibtp": 0,
        "rnday": f"{test.duration / 86400.0:.10f}",
        "dt": f"{dt:g}",
        "msc2": 24,
        "mdc2": 30,
        "ntracer_gen": 2,
        "ntracer_age": 4,
        "sed_class": 5,
        "eco_class": 27,
        "nbins_veg_vert": 2,
        "nmarsh_types": 2,
        "nspool": spool,
        "ihfskip": spool * files,  # one output file for the whole run
    }
    lon, lat = where.centre
    opt = {
        "ics": 2 if where.geographic else 1,
        "ihot": 0,
        "dramp": f"{test.ramp / 86400.0:.10f}",
        "nramp_elev": 0,
        "indvel": 0,
        "ihorcon": 0,
        "ishapiro": 1,
        "shapiro0": 0.5,
        "niter_shap": 1,
        "nadv": 0,
        "thetai": 1.0,
        "slam0": f"{lon:.6f}",
        "sfea0": f"{lat:.6f}",
        "nchi": -1,
        "hmin_man": _HMIN_MAN,
        "ncor": 1,
        "ic_elev": 0,
        "h0": 0.01,
        "itur": 0,
        "dfv0": 0.01,
        "dfh0": 0.0001,
        "nws": 0,
        "ihconsv": 0,
        "if_source": 0,
        "rmaxvel": 10.0,
    }
    schout = {
        "nc_out": 1,
        "iof_ugrid": 0,
        "nhot": 0,
        "iout_sta": 0,
        "iof_hydro(1)": 1,
        "iof_hydro(16)": 1,
        # SCHISM turns these 3-D outputs on by default (schism_init.F90), and
        # each would need a scribe of its own
        "iof_hydro(25)": 0,
        "iof_hydro(26)": 0,
    }
    parts = []
    for name, values in (("CORE", core), ("OPT", opt), ("SCHOUT", schout)):
        parts.append(f"&{name}")
        parts += [f"  {key} = {value}" for key, value in values.items()]
        parts.append("/")
    return "\n".join(parts) + "\n"
