"""The quality stage: the mesh measured, and advice to the case's author.

The quality report (:func:`~coastmesh.meshing.quality.mesh_quality`) counts what
the geometry or the case forces (sharp corners, channels one element wide);
the warnings here turn the counts into advice, with places.
"""

from __future__ import annotations

import warnings
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

import numpy as np

from coastmesh.case.pipeline.state import DepthRun, FinishedRun, RunContext
from coastmesh.errors import CoastmeshWarning
from coastmesh.meshing import QualityReport, mesh_quality
from coastmesh.meshing.cleanup.aside import done_now
from coastmesh.meshing.quality import sphere_quality
from coastmesh.meshing.quality.measure import places
from coastmesh.meshing.quality.time_step import element_time_steps
from coastmesh.sizing.courant import CourantReport, round_step
from coastmesh.types import Mesh

__all__ = ["quality_stage", "warn_avoidable_corners", "warn_spanning"]

#: Places given in a warning.
_SHOWN = 5


def quality_stage(run: DepthRun, ctx: RunContext) -> FinishedRun:
    """Measure the mesh (``[output] quality``); warn of what its author can change."""
    config, state = run.config, run.mesh
    if not config.outputs.quality:
        return run.with_quality(None)
    courant = run.time_step
    with ctx.timed("mesh quality"), ThreadPoolExecutor(1) as side:
        # a global mesh (lon/lat) is checked on the sphere too: on a side
        # thread, with 2 or more (numpy lets go of Python's lock)
        aside = side.submit if ctx.threads > 1 else done_now
        sphere = None
        if run.strategy.on_sphere:
            sphere = aside(sphere_quality, state.mesh)
        quality = mesh_quality(
            state.mesh,
            dt=None if courant is None else model_time_step(state.mesh, courant),
            velocity=0.0 if courant is None else courant.velocity,
            courant_max=None if courant is None else courant.courant_max,
            courant_min=None if courant is None else courant.courant_min,
        )
        if sphere is not None:
            quality = replace(quality, sphere=sphere.result())
    warn_avoidable_corners(quality, state.mesh)
    size = run.size
    channels = config.size.channels
    warn_spanning(
        quality,
        state.mesh,
        cell=size.grid.cell_m,
        h_min=size.report.h_min_m,
        narrow=None if channels is None else channels.narrow,
    )
    return run.with_quality(quality)


def model_time_step(mesh: Mesh, courant: CourantReport) -> float:
    """Return the time step the mesh is checked at: ``dt``, or for ``"auto"`` less.

    A given ``dt`` is the user's. With ``dt = "auto"`` the size field's step is
    lowered, if need be, until no element of the mesh made has a Courant number
    above ``courant_max`` (an element smaller than its target size), and rounded
    down to two figures: the step the model can run this mesh at.
    """
    dt = courant.dt
    if (
        not courant.auto
        or courant.courant_max is None
        or "depth" not in (mesh.point_data)
    ):
        return dt
    numbers = element_time_steps(mesh, velocity=courant.velocity, dt=dt)["courant"]
    worst = float(np.nanmax(numbers)) if np.isfinite(numbers).any() else 0.0
    if worst <= courant.courant_max:
        return dt
    return round_step(dt * courant.courant_max / worst)


def warn_avoidable_corners(quality: QualityReport, mesh: Mesh) -> None:
    """Warn of open boundaries that meet the coast at a sharp angle."""
    avoidable = [c for c in quality.corners.sharpest if c.avoidable]
    if not avoidable:
        return
    names = dict(mesh.boundary_names)
    where = "; ".join(
        f"{'/'.join(str(i if i is None else names.get(i, i)) for i in c.boundary_ids)}"
        " at "
        f"{c.angle:.1f} deg ({c.node.lon:.4f}, {c.node.lat:.4f})"
        for c in avoidable[:_SHOWN]
        if c.node.lon is not None
    )
    warnings.warn(
        f"open boundaries meet the coast at under {quality.corners.threshold:g} deg "
        f"at {quality.corners.avoidable} places ({where}): the triangle there cannot "
        "be well shaped; move the end of the open boundary so that it meets the "
        "coast closer to a right angle",
        CoastmeshWarning,
        stacklevel=4,
    )


def warn_spanning(
    quality: QualityReport,
    mesh: Mesh,
    *,
    cell: float,
    h_min: float | None,
    narrow: str | None,
) -> None:
    """Warn of triangles one element across a channel, with what to change.

    The channel term sees channels a few grid cells wide; narrower ones, and
    strips of water between an open boundary and the coast, can still end up
    one element wide. ``cell`` is the size grid's spacing and ``h_min`` the
    field's floor (metres).
    """
    spanning = quality.channel_spanning_triangles
    if len(spanning) == 0:
        return
    shown = places(mesh, spanning[:_SHOWN], triangles=True)
    where = ", ".join(p.summary() for p in shown)
    advice = []
    if h_min is not None and cell > h_min:
        advice.append(
            f"the size grid ({cell:,.0f} m) is coarser than h_min ({h_min:,.0f} m) "
            f"and cannot see channels narrower than about {2 * cell:,.0f} m: set "
            "[mesh_size] cell nearer h_min"
        )
    if narrow != "close":
        advice.append('set [mesh_size.channels] narrow = "close" to make them land')
    at_open = _at_open_boundaries(mesh, spanning)
    if at_open:
        advice.append(
            f"{sum(at_open.values()):,} of them lie between an open boundary and the "
            "coast ("
            + ", ".join(f"{name}: {n:,}" for name, n in at_open.items())
            + "), where the channel term sees open sea: move the open boundary "
            "off the coast"
        )
    if not advice:
        advice.append(
            "they lie in stretches still narrower than 2 h_min after closing "
            "(report.json lists the largest): lower h_min to resolve them"
        )
    warnings.warn(
        f"{len(spanning):,} triangles span a channel one element wide (three "
        f"boundary nodes, at most one boundary edge), at {where}: " + "; ".join(advice),
        CoastmeshWarning,
        stacklevel=4,
    )


def _at_open_boundaries(mesh: Mesh, triangles: np.ndarray) -> dict[str, int]:
    """Count ``triangles`` with a node on each open boundary, by its name."""
    kinds, names = dict(mesh.boundary_kinds), dict(mesh.boundary_names)
    ids = np.asarray(mesh.boundary_ids)
    nodes = mesh.triangles[triangles]
    counts = {}
    for pid in sorted(i for i, kind in kinds.items() if kind == "open"):
        on = np.zeros(len(mesh.points), dtype=bool)
        on[mesh.boundary_edges[ids == pid].ravel()] = True
        n = int(on[nodes].any(axis=1).sum())
        if n:
            counts[str(names.get(pid, pid))] = n
    return counts
