"""Smoke-test control files: run ADCIRC or SCHISM on a mesh at once.

A **smoke test**, not a calibrated model: it shows that the model reads the mesh
and its boundary lists and runs on it stably, nothing about the tides of the
place. Each model gets a folder with everything it reads:

- an M2 tide of ``amplitude`` (0.5 m) on every open boundary node, with the same
  phase everywhere;
- a ramp of ``ramp`` seconds (6 h), then ``cycles`` M2 cycles (one: 12.42 h);
- ADCIRC at the mesh's own time step ``dt`` (``coastmesh run`` reports it:
  ``quality.time_step.courant.dt``), and SCHISM, implicit, at a step of its
  own rules (:func:`schism_time_step`:
  its advection scheme asks for a Courant number above 0.4, within 100-400 s);
- quadratic bottom friction from a Manning coefficient per node, derived from
  the mesh's region ids (:func:`~coastmesh.io.meshes.adcirc.node_regions`): ``manning``
  (0.025) in the sea and, if asked, other values in the farms and footprints;
  the drag coefficient ``g n^2 / H^(1/3)`` is held at :data:`MIN_DRAG` or more
  (ADCIRC's own rule; SCHISM's ``manning.gr3`` is raised to match);
- wetting and drying; Coriolis from the latitude.

================  ===========================================================
model             files (run in the folder)
================  ===========================================================
``adcirc``        ``fort.14``, ``fort.13`` (``mannings_n_at_sea_floor``),
                  ``fort.15``; run ``adcirc`` (serial)
``schism``        ``hgrid.gr3``, ``hgrid.ll``, ``vgrid.in`` (2-D: one layer),
                  ``bctides.in``, ``manning.gr3``, ``adv.gr3``, ``param.nml``,
                  ``outputs/``; run ``mpirun -np 2 pschism 1`` (one process
                  computes, one writes)
================  ===========================================================

Each folder also holds ``README.txt``, which says how to run the model and what
to look at. The control values, and why each was chosen, are in
:mod:`coastmesh.io.meshes.model_tests._adcirc` and
:mod:`coastmesh.io.meshes.model_tests._schism`.

A mesh on the sphere (a global case) is refused: these sets force a regional
model through its open boundaries, and a global ocean has none (ADCIRC would
also need its poles rotated away, ``fort.rotm``, and SCHISM a global ``ics = 2``
set-up with tidal potential). So is a mesh with no open boundary, or without a
CRS (the sets need the latitude).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS, Transformer

from coastmesh.errors import ConfigError
from coastmesh.io._atomic import atomic_directory
from coastmesh.io.meshes.adcirc import node_regions
from coastmesh.io.meshes.adcirc._segments import DEFAULT_LAND, land_codes
from coastmesh.io.meshes.sphere import on_sphere
from coastmesh.types import Mesh
from coastmesh.types.topology import unique_edges

__all__ = [
    "GRAVITY",
    "M2_FREQUENCY",
    "M2_PERIOD",
    "MIN_DRAG",
    "MODEL_TESTS",
    "ModelTest",
    "model_test_step",
    "near_nodes",
    "schism_time_step",
    "write_model_test",
]

#: M2's angular frequency, rad/s (ADCIRC's and SCHISM's tables: 1.405189e-4)
M2_FREQUENCY = 1.405189e-4
#: M2's period, s (12.42 h)
M2_PERIOD = 2 * math.pi / M2_FREQUENCY
_OMEGA = 7.292115e-5  # the Earth's rotation, rad/s
#: Gravity, m/s2, as both control sets give it.
GRAVITY = 9.81
#: The least quadratic drag coefficient, ``Cd = g n^2 / H^(1/3)`` floored. With a
#: Manning nodal attribute, ADCIRC takes its ``fort.15`` ``CF`` as this floor
#: (``src/nodalattr.F``: "the value from the fort.15 file is used as a floor for
#: the minimum equivalent quadratic friction value"); 0.0025 is the classic
#: shelf-sea value. With n = 0.025 it holds wherever the water is deeper than
#: 15 m. SCHISM has no floor (``schism_step.F90`` takes ``g n^2 / H^(1/3)``
#: as it is), so its ``manning.gr3`` gets the n that meets the floor at each
#: node's still-water depth; both models then have the same friction.
MIN_DRAG = 0.0025


@dataclass(frozen=True)
class ModelTest:
    """What a smoke test asks of the model.

    Attributes
    ----------
    dt : float
        The model's time step, s.
    amplitude : float, default 0.5
        The M2 amplitude on every open boundary node, m.
    ramp : float, default 21600
        The ramp from rest to the full tide, s (6 h).
    cycles : float, default 1
        M2 cycles after the ramp.
    manning : float, default 0.025
        Manning's n in the sea, s m^(-1/3).
    region_manning : mapping of int to float
        Manning's n of the nodes of other regions (farms, footprints), by
        region id; a region not listed takes ``manning``.
    schism_dt : float, optional
        SCHISM's step, s; default its own rule
        (:func:`schism_time_step`).
    """

    dt: float
    amplitude: float = 0.5
    ramp: float = 6 * 3600.0
    cycles: float = 1.0
    manning: float = 0.025
    region_manning: Mapping[int, float] = field(default_factory=dict)
    schism_dt: float | None = None

    def __post_init__(self) -> None:
        for name in ("dt", "amplitude", "cycles", "manning"):
            value = getattr(self, name)
            if not (
                isinstance(value, int | float) and math.isfinite(value) and value > 0
            ):
                raise ConfigError(
                    f"model test: {name} = {value!r}; expected a number > 0"
                )
        if self.schism_dt is not None and not (
            isinstance(self.schism_dt, int | float)
            and math.isfinite(self.schism_dt)
            and self.schism_dt > 0
        ):
            raise ConfigError(
                f"model test: schism_dt = {self.schism_dt!r}; expected a number > 0"
            )
        if not (math.isfinite(self.ramp) and self.ramp >= 0):
            raise ConfigError(
                f"model test: ramp = {self.ramp!r}; expected seconds >= 0"
            )
        for rid, n in self.region_manning.items():
            if not (isinstance(n, int | float) and n > 0):
                raise ConfigError(
                    f"model test: region_manning[{rid}] = {n!r}; expected a number > 0"
                )

    @property
    def duration(self) -> float:
        """The run's length, s: the ramp, then the cycles."""
        return self.ramp + self.cycles * M2_PERIOD

    def node_manning(self, mesh: Mesh) -> NDArray[np.float64]:
        """Manning's n at each node, from the nodes' region ids."""
        n = np.full(len(mesh.points), float(self.manning))
        if self.region_manning:
            ids = node_regions(mesh)
            for rid, value in self.region_manning.items():
                n[ids == rid] = float(value)
        return n


@dataclass(frozen=True)
class Place:
    """Where the mesh is: what the control files need of its coordinates."""

    geographic: bool  # lon/lat in degrees, else a projected CRS in metres
    lonlat: NDArray[np.float64]  # every node, degrees
    centre: tuple[float, float]  # lon, lat of the middle of its box

    @property
    def coriolis(self) -> float:
        """2 Omega sin(latitude) at the centre, 1/s."""
        return 2 * _OMEGA * math.sin(math.radians(self.centre[1]))


def place_of(mesh: Mesh) -> Place:
    """Return the nodes in lon/lat and the centre of the mesh's box."""
    crs = CRS.from_user_input(mesh.crs)
    if crs.is_geographic:
        lonlat = np.asarray(mesh.points, dtype=np.float64)
    else:
        to = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
        lonlat = np.column_stack(to.transform(mesh.points[:, 0], mesh.points[:, 1]))
    lo, hi = lonlat.min(axis=0), lonlat.max(axis=0)
    return Place(
        bool(crs.is_geographic),
        lonlat,
        (float(lo[0] + hi[0]) / 2, float(lo[1] + hi[1]) / 2),
    )


Writer = Callable[[Path, Mesh, ModelTest, Place, str], list[str]]


def _writers() -> dict[str, Writer]:
    from coastmesh.io.meshes.model_tests import _adcirc, _schism

    return {"adcirc": _adcirc.write, "schism": _schism.write}


#: the models a smoke test can be written for
MODEL_TESTS = ("adcirc", "schism")


def write_model_test(
    folder: str | os.PathLike[str],
    mesh: Mesh,
    model: str,
    *,
    dt: float,
    amplitude: float = 0.5,
    ramp: float = 6 * 3600.0,
    cycles: float = 1.0,
    manning: float = 0.025,
    region_manning: Mapping[int, float] | None = None,
    land: str | None = None,
    schism_dt: float | None = None,
    overwrite: bool = False,
) -> list[str]:
    """Write a smoke test of ``model`` on ``mesh`` into ``folder``, atomically.

    Parameters
    ----------
    folder : str or path-like
        The run folder to make; it must not exist, or be empty, unless
        ``overwrite``.
    mesh : Mesh
        A regional mesh with depth (``point_data["depth"]``, m, positive down),
        a CRS, open boundaries, and a kind for every boundary id.
    model : {"adcirc", "schism"}
        The model.
    dt : float
        ADCIRC's time step, s: the mesh's own (``coastmesh run`` reports it as
        ``quality.time_step.courant.dt``). SCHISM takes a step of its own rules
        unless ``schism_dt`` is given.
    amplitude, ramp, cycles, manning, region_manning, schism_dt
        As :class:`ModelTest`.
    land : {"essential", "natural"}, optional
        ADCIRC's land types in the ``fort.14``
        (:func:`~coastmesh.io.meshes.adcirc.write_fort14`); default essential. SCHISM
        has no such choice.
    overwrite : bool, default False
        Whether a non-empty ``folder`` may be replaced.

    Returns
    -------
    list of str
        The files written, relative to ``folder`` (SCHISM also gets the empty
        folder ``outputs/`` it writes into).

    Raises
    ------
    ConfigError
        If ``model`` is unknown, a value is out of range, or the mesh is on the
        sphere (a global case), has no open boundary or no CRS; the message
        says why.
    FormatError
        As the grid writers (:func:`~coastmesh.io.meshes.adcirc.write_fort14`,
        :func:`~coastmesh.io.meshes.adcirc.write_gr3`).
    OutputExistsError
        If ``folder`` is not empty and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1000, 0], [1000, 1000], [0, 1000]],
    ...          [[0, 1, 2], [0, 2, 3]], [[0, 1], [1, 2], [2, 3], [3, 0]],
    ...          [2, 1, 1, 1], 1, "EPSG:32630", {"depth": [10.0] * 4},
    ...          boundary_kinds={1: "shoreline", 2: "open"})
    >>> folder = pathlib.Path(tempfile.mkdtemp()) / "adcirc"
    >>> write_model_test(folder, m, "adcirc", dt=5.0)
    ['fort.14', 'fort.13', 'fort.15', 'README.txt']
    """
    writers = _writers()
    if model not in writers:
        raise ConfigError(
            f"model test {model!r}: unknown model; expected one of "
            f"{', '.join(MODEL_TESTS)}"
        )
    test = ModelTest(
        dt, amplitude, ramp, cycles, manning, dict(region_manning or {}), schism_dt
    )
    check_regional(mesh, model)
    land = land or DEFAULT_LAND
    land_codes(land)
    where = place_of(mesh)
    with atomic_directory(folder, overwrite=overwrite) as partial:
        files = writers[model](partial, mesh, test, where, land)
    return files


def model_test_step(
    mesh: Mesh, model: str, *, dt: float, schism_dt: float | None = None
) -> float:
    """Return the time step, s, that :func:`write_model_test` writes for ``model``.

    ADCIRC runs at ``dt``, the mesh's own; SCHISM at ``schism_dt`` if given,
    else at :func:`schism_time_step`.

    Examples
    --------
    >>> from coastmesh.types import Mesh
    >>> m = Mesh([[0, 0], [1000, 0], [1000, 1000], [0, 1000]],
    ...          [[0, 1, 2], [0, 2, 3]], [[0, 1], [1, 2], [2, 3], [3, 0]],
    ...          [2, 1, 1, 1], 1, "EPSG:32630", {"depth": [10.0] * 4})
    >>> model_test_step(m, "adcirc", dt=5.0), model_test_step(m, "schism", dt=5.0)
    (5.0, 100.0)
    """
    if model not in MODEL_TESTS:
        raise ConfigError(
            f"model test {model!r}: unknown model; expected one of "
            f"{', '.join(MODEL_TESTS)}"
        )
    if model != "schism":
        return float(dt)
    return float(schism_dt) if schism_dt is not None else schism_time_step(mesh)[0]


def check_regional(mesh: Mesh, model: str) -> None:
    """Raise ConfigError if a smoke test of ``model`` cannot describe ``mesh``."""
    what = f"model test {model!r}"
    if on_sphere(mesh):
        raise ConfigError(
            f"{what}: the mesh is on the sphere (a global case), which this smoke "
            "test cannot describe: it forces a regional model through its open "
            "boundaries, and a global ocean has none. Run a global model with "
            "tidal potential instead (ADCIRC: NTIP, with a fort.rotm that turns "
            "the poles onto land; SCHISM: ics = 2 and ntip > 0)"
        )
    if mesh.crs is None:
        raise ConfigError(f"{what}: the mesh has no CRS; the test needs its latitude")
    kinds = mesh.boundary_kinds
    if not any(kinds.get(int(i)) == "open" for i in np.unique(mesh.boundary_ids)):
        raise ConfigError(
            f"{what}: the mesh has no open boundary, so there is nowhere to force "
            "the tide; give a boundary id the kind 'open'"
        )


def near_nodes(mesh: Mesh, nodes: NDArray[np.int64], rings: int) -> NDArray[np.intp]:
    """Return the nodes ``nodes`` and those within ``rings`` edges of them."""
    edges, _ = unique_edges(mesh.triangles, len(mesh.points))
    mark = np.zeros(len(mesh.points), dtype=bool)
    mark[nodes] = True
    for _ in range(rings):
        reached = mark[edges[:, 0]] | mark[edges[:, 1]]
        mark[edges[reached].ravel()] = True
    return np.flatnonzero(mark)


def readme(model: str, test: ModelTest, run: str, look: str, note: str = "") -> str:
    """Return the README of a smoke-test folder (``note``: after the forcing)."""
    steps = math.ceil(test.duration / test.dt)
    return (
        f"coastmesh smoke test for {model}: NOT a calibrated model.\n\n"
        f"It shows that {model} reads this mesh and its boundary lists and runs "
        "stably on it. The forcing is an M2 tide of "
        f"{test.amplitude:g} m on every open boundary node, with the same phase "
        f"everywhere, ramped up over {test.ramp / 3600:g} h, then "
        f"{test.cycles:g} M2 cycle(s) ({test.duration / 3600:.2f} h in all, "
        f"{steps} steps of {test.dt:g} s); Manning's n {test.manning:g} "
        f"(quadratic friction, the drag g n^2 / H^(1/3) held at {MIN_DRAG:g} or "
        "more), wetting and drying, Coriolis from the latitude.\n\n"
        f"{note}Run, in this folder:\n    {run}\n\nLook at:\n{look}\n"
        "A tide of this amplitude gives speeds of a few tenths of m/s in most "
        "seas; elevations or speeds far above it, or a stop, point at the mesh "
        "(or at a time step too long for it).\n"
    )


# SCHISM's own step rule, public here; its module imports the names above
from coastmesh.io.meshes.model_tests._schism import schism_time_step  # noqa: E402
