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
  ``mannings_n_at_sea_floor`` from the ``fort.13`` (its ``CF`` line is then
  read and not used); ``NOLIFA = 2`` wetting and drying (``H0 = 0.1`` m),
  ``NOLICA = NOLICAT = 1`` advection;
- ``TAU0 = -1``: the GWCE weight from the depth, 0.005 at 10 m and deeper,
  0.02 shallower (ADCIRC's own depth rule; the docs' typical range is 0.005 to
  0.1); ``ESLM = 5`` m2/s lateral viscosity; ``A00 B00 C00 = 0.35 0.30 0.35``;
- ``NRAMP = 1``, ``DRAMP`` the ramp in days; one constituent, M2
  (``AMIG = 1.405189e-4`` rad/s, nodal factor 1, equilibrium argument 0), with
  ``EMO EFA`` on each open boundary node in the order of the ``fort.14``;
- global elevation and velocity (``fort.63``, ``fort.64``, ASCII) every 30 min
  of the cycles after the ramp, so ADCIRC also writes ``maxele.63`` and
  ``maxvel.63`` (the largest elevation and speed at each node);
- ``&WarnElevControl``: ``WarnElev`` at 5 times the amplitude and ``ErrorElev``
  at 20 times, so a warning means something for a tide of this size (the
  defaults are 20 m and 1000 m; ``src/read_input.F``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from coastmesh.io._model import require_kinds
from coastmesh.io.adcirc import write_fort14
from coastmesh.io.adcirc._segments import grid_segments
from coastmesh.io.model_tests import M2_FREQUENCY, ModelTest, Place, readme
from coastmesh.types import Mesh

_OUTPUT_EVERY = 1800.0  # s: global output during the cycles
_H0 = 0.1  # m: ADCIRC's minimum depth for wetting and drying
_TAU0 = -1  # the GWCE weight from the depth (module docstring)
_ESLM = 5.0  # m2/s, lateral viscosity


def write(
    folder: Path, mesh: Mesh, test: ModelTest, where: Place, land: str
) -> list[str]:
    """Write the ADCIRC run folder; return its files."""
    write_fort14(folder / "fort.14", mesh, regions=False, land=land)
    _write_fort13(folder / "fort.13", test.node_manning(mesh), test.manning)
    kinds = require_kinds(mesh, "fort.14")
    opened, _ = grid_segments(mesh, "fort.14", kinds, "fort14", land=land)
    neta = sum(len(s.nodes) for s in opened)
    (folder / "fort.15").write_text(_fort15(test, where, neta), encoding="ascii")
    run = "adcirc          (serial; reads fort.14, fort.13 and fort.15)"
    look = (
        "- the end of fort.16 and the screen: 'ADCIRC terminating normally'; no\n"
        "  'WARNING: Elevation.gt.WarnElev' (set at 5 x the amplitude) and no\n"
        "  'Elevation.gt.ErrorElev' (20 x), which stops the run;\n"
        "- maxele.63 and maxvel.63: the largest elevation and speed at each node.\n"
    )
    (folder / "README.txt").write_text(readme("ADCIRC", test, run, look))
    return ["fort.14", "fort.13", "fort.15", "README.txt"]


def _write_fort13(path: Path, n: np.ndarray, default: float) -> None:
    """Write the nodal attributes: ``mannings_n_at_sea_floor`` (``nodalattr.F``)."""
    other = np.flatnonzero(n != default)
    lines = [
        "coastmesh smoke test: Manning's n from the region ids",
        str(len(n)),
        "1",
        "mannings_n_at_sea_floor",
        "s/m^(1/3)",
        "1",
        f"{default:g}",
        "mannings_n_at_sea_floor",
        str(len(other)),
    ] + [f"{k + 1} {n[k]:g}" for k in other]
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
        ("1", "NWP"),
        ("mannings_n_at_sea_floor", "from fort.13"),
        (str(ncor), "NCOR"),
        ("0", "NTIP"),
        ("0", "NWS"),
        ("1", "NRAMP"),
        ("9.81", "G"),
        (str(_TAU0), "TAU0"),
        (f"{dt:g}", "DTDP"),
        ("0.0", "STATIM"),
        ("0.0", "REFTIM"),
        (f"{rnday:.10f}", "RNDAY"),
        (f"{test.ramp / 86400.0:.10f}", "DRAMP"),
        ("0.35 0.30 0.35", "A00 B00 C00"),
        (f"{_H0:g} 0 0 0.01", "H0 NODEDRYMIN NODEWETMIN VELMIN"),
        (f"{lon:.6f} {lat:.6f}", "SLAM0 SFEA0"),
        ("0.0025", "CF (not used: Manning's n from fort.13)"),
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
    text += f"&WarnElevControl WarnElev = {5 * a:g}, ErrorElev = {20 * a:g} /\n"
    return text
