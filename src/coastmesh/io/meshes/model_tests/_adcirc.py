"""ADCIRC smoke test: ``fort.14``, ``fort.13`` and ``fort.15`` for a 2-D tidal run.

The ``fort.15`` follows ADCIRC's input description
(``docs/technical_reference/input_files/fort15.rst`` and
``parameter_definitions/index.rst`` in ``adcirc/adcirc``), line by line:

- ``IM = 0``: 2-D depth-integrated, barotropic;
- ``ICS = 2`` for a mesh in lon/lat (CPP projection about the middle of its box,
  ``SLAM0 SFEA0``) with ``NCOR = 1`` (Coriolis from each node's latitude);
  ``ICS = 1`` for a projected mesh, with ``NCOR = 0`` and ``CORI`` at the
  middle's latitude;
- ``NOLIBF = 1`` quadratic friction with ``NWP = 1``:
  ``mannings_n_at_sea_floor`` from the ``fort.13``, and ``CF`` =
  :data:`~coastmesh.io.meshes.model_tests.MIN_DRAG`, which ADCIRC then takes as
  the floor on ``g n^2 / H^(1/3)`` (``src/nodalattr.F``); ``NOLIFA = 2``
  wetting and drying (``H0 = 0.1`` m), ``NOLICA = NOLICAT = 1`` advection;
- ``TAU0 = -1``: the GWCE weight from the depth, 0.005 at 10 m and deeper,
  0.02 shallower (ADCIRC's own depth rule; the docs' typical range is 0.005 to
  0.1); ``ESLM = 5`` m2/s lateral viscosity; ``A00 B00 C00 = 0.35 0.30 0.35``;
- ``NRAMP = 1``, ``DRAMP`` the ramp in days; one constituent, M2
  (``AMIG = 1.405189e-4`` rad/s, nodal factor 1, equilibrium argument 0), with
  ``EMO EFA`` on each open boundary node in the order of the ``fort.14``;
- global elevation and velocity (``fort.63``, ``fort.64``, ASCII) every 30 min
  of the cycles after the ramp, so ADCIRC also writes ``maxele.63`` and
  ``maxvel.63`` (the largest elevation and speed at each node);
- ``&WarnElevControl``: ``WarnElev`` at 10 times the amplitude and
  ``ErrorElev`` at 50 times, so a warning means something for a tide of this
  size (the defaults are 20 m and 1000 m; ``src/read_input.F``) while a basin
  that resonates is not taken for a blow-up: on the NW shelf, the Severn
  estuary raises the 0.5 m of the shelf edge to 2.8 m;
- the advective terms off on the elements within three elements of an open
  boundary: ``advection_state`` (a nodal attribute, ``fort13.rst``; advection
  is off on an element when a node's depth is under the node's value) is
  10,000 m at the open boundary nodes and the two rings of nodes inside them,
  -999 m elsewhere. ADCIRC has no inflow condition for the advective terms at
  an elevation boundary, and they grow there where flow runs along a coast into
  the boundary: on ``examples/orkney/pentland_firth.toml`` the speed at the
  node where the south boundary meets a straight north-south coast doubled
  every 30 min until ADCIRC stopped at 14.2 h (43 m/s); the same with
  essential land types (16.5 h), with ``TAU0 = 0.03`` or ADCIRC's ``tau0_gen``
  rule (14.2 h), and with the coast's depth tapered to 5 m (4.5 h, on the
  open boundary nodes in the shallower water); advection off on the elements
  at the boundary alone moved it one element in (12.7 m/s, 160 warnings); off
  within three elements, or everywhere, the run ended cleanly (0.80 and 0.77
  m/s). The corner's triangles have angles of 45 to 72 degrees and meet at 90
  degrees, so it is not the mesh's shape.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from coastmesh.io.meshes._model import require_kinds
from coastmesh.io.meshes.adcirc import write_fort14
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
from coastmesh.types import Mesh

_OUTPUT_EVERY = 1800.0  # s: global output during the cycles
_H0 = 0.1  # m: ADCIRC's minimum depth for wetting and drying
_TAU0 = -1  # the GWCE weight from the depth (module docstring)
_ESLM = 5.0  # m2/s, lateral viscosity
_QUIET_RINGS = 2  # rings of nodes inside the open boundary with advection off
_ADVECTION_OFF, _ADVECTION_ON = 10_000.0, -999.0  # advection_state values, m


def write(
    folder: Path, mesh: Mesh, test: ModelTest, where: Place, land: str
) -> list[str]:
    """Write the ADCIRC run folder; return its files."""
    write_fort14(folder / "fort.14", mesh, regions=False, land=land)
    kinds = require_kinds(mesh, "fort.14")
    opened, _ = grid_segments(mesh, "fort.14", kinds, "fort14", land=land)
    neta = sum(len(s.nodes) for s in opened)
    quiet = near_nodes(mesh, np.concatenate([s.nodes for s in opened]), _QUIET_RINGS)
    _write_fort13(folder / "fort.13", test.node_manning(mesh), test.manning, quiet)
    (folder / "fort.15").write_text(_fort15(test, where, neta), encoding="ascii")
    run = "adcirc          (serial; reads fort.14, fort.13 and fort.15)"
    look = (
        "- the end of fort.16 and the screen: 'ADCIRC terminating normally'; no\n"
        "  'WARNING: Elevation.gt.WarnElev' (set at 10 x the amplitude) and no\n"
        "  'Elevation.gt.ErrorElev' (50 x), which stops the run;\n"
        "- maxele.63 and maxvel.63: the largest elevation and speed at each node.\n"
    )
    (folder / "README.txt").write_text(readme("ADCIRC", test, run, look))
    return ["fort.14", "fort.13", "fort.15", "README.txt"]


def _write_fort13(path: Path, n: np.ndarray, default: float, quiet: np.ndarray) -> None:
    """Write the nodal attributes (``fort13.rst``, ``nodalattr.F``).

    ``mannings_n_at_sea_floor`` from the region ids, and ``advection_state``:
    advection off at the ``quiet`` nodes (module docstring).
    """
    other = np.flatnonzero(n != default)
    lines = [
        "coastmesh smoke test: Manning's n from the region ids, advection_state",
        str(len(n)),
        "2",
        "mannings_n_at_sea_floor",
        "s/m^(1/3)",
        "1",
        f"{default:g}",
        "advection_state",
        "m",
        "1",
        f"{_ADVECTION_ON:g}",
        "mannings_n_at_sea_floor",
        str(len(other)),
    ]
    lines += [f"{k + 1} {n[k]:g}" for k in other]
    lines += ["advection_state", str(len(quiet))]
    lines += [f"{k + 1} {_ADVECTION_OFF:g}" for k in quiet]
    path.write_text("\n".join(lines) + "\n", encoding="ascii")


def _fort15(test: ModelTest, where: Place, neta: int) -> str:
    """Return the model parameter and periodic boundary condition file."""
    dt = test.dt
    rnday = test.duration / 86400.0
    steps = math.ceil(test.duration / dt)
    spool = max(1, round(_OUTPUT_EVERY / dt))
    start = test.ramp / 86400.0
    ics, ncor = (2, 1) if where.geographic else (1, 0)
    lon, lat = where.centre
    a = test.amplitude
    forcing = "\n".join([f"{a:g} 0.0"] * neta)
    rows = [
        ("coastmesh smoke test: M2 on the open boundaries", "RUNDES"),
        ("smoke", "RUNID"),
        ("1", "NFOVER"),
        ("1", "NABOUT"),
        (str(max(1, steps // 50)), "NSCREEN"),
        ("0", "IHOT"),
        (str(ics), "ICS"),
        ("0", "IM: 2-D barotropic"),
        ("1", "NOLIBF: quadratic friction"),
        ("2", "NOLIFA: wetting and drying"),
        ("1", "NOLICA"),
        ("1", "NOLICAT"),
        ("2", "NWP"),
        ("mannings_n_at_sea_floor", "from fort.13"),
        ("advection_state", "from fort.13: advection off near the open boundaries"),
        (str(ncor), "NCOR"),
        ("0", "NTIP"),
        ("0", "NWS"),
        ("1", "NRAMP"),
        (f"{GRAVITY:g}", "G"),
        (str(_TAU0), "TAU0"),
        (f"{dt:g}", "DTDP"),
        ("0.0", "STATIM"),
        ("0.0", "REFTIM"),
        (f"{rnday:.10f}", "RNDAY"),
        (f"{test.ramp / 86400.0:.10f}", "DRAMP"),
        ("0.35 0.30 0.35", "A00 B00 C00"),
        (f"{_H0:g} 0 0 0.01", "H0 NODEDRYMIN NODEWETMIN VELMIN"),
        (f"{lon:.6f} {lat:.6f}", "SLAM0 SFEA0"),
        (f"{MIN_DRAG:g}", "CF: with Manning's n, the floor on g n^2 / H^(1/3)"),
        (f"{_ESLM:g}", "ESLM"),
        (f"{where.coriolis:.9e}", "CORI"),
        ("0", "NTIF"),
        ("1", "NBFR"),
        ("M2", "BOUNTAG"),
        (f"{M2_FREQUENCY:.9e} 1.0 0.0", "AMIG FF FACE"),
        ("M2", "EALPHA"),
    ]
    text = "".join(f"{value} ! {what}\n" for value, what in rows)
    text += forcing + "\n"
    more = [
        ("110.0", "ANGINN"),
        ("0 0.0 0.0 0", "NOUTE TOUTSE TOUTFE NSPOOLE"),
        ("0", "NSTAE"),
        ("0 0.0 0.0 0", "NOUTV TOUTSV TOUTFV NSPOOLV"),
        ("0", "NSTAV"),
        (f"1 {start:.10f} {rnday:.10f} {spool}", "NOUTGE TOUTSGE TOUTFGE NSPOOLGE"),
        (f"1 {start:.10f} {rnday:.10f} {spool}", "NOUTGV TOUTSGV TOUTFGV NSPOOLGV"),
        ("0", "NFREQ"),
        ("0.0 0.0 0 0.0", "THAS THAF NHAINC FMV"),
        ("0 0 0 0", "NHASE NHASV NHAGE NHAGV"),
        ("0 0", "NHSTAR NHSINC"),
        ("1 0 1.0e-8 25", "ITITER ISLDIA CONVCR ITMAX"),
    ]
    text += "".join(f"{value} ! {what}\n" for value, what in more)
    text += f"&WarnElevControl WarnElev = {10 * a:g}, ErrorElev = {50 * a:g} /\n"
    return text
