"""The water cut into parts, each meshed alone as a task, joined by shared nodes.

``cuts`` (where to cut: parts of equal expected triangle count),
``crossings`` (whether a cut crosses the water cleanly), ``junctions`` (cuts
meet the boundary on its nodes), ``faces`` (the boundary noded with the cuts, as
loops of curves), ``tasks`` (each part meshed and cleaned where it runs, then
the parts merged by their shared nodes), ``seams`` (smoothing across the cuts)
and ``report`` (what each part cost).
"""

from __future__ import annotations

from coastmesh.meshing.parts.cuts import (
    WaterCells,
    auto_parts,
    expected_triangles,
    plan_cuts,
    water_cells,
)
from coastmesh.meshing.parts.report import PartsReport
from coastmesh.meshing.parts.tasks import Runner, serial_runner

__all__ = [
    "PartsReport",
    "Runner",
    "WaterCells",
    "auto_parts",
    "expected_triangles",
    "plan_cuts",
    "serial_runner",
    "water_cells",
]
