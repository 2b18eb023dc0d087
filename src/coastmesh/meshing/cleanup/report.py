"""What the cleanup did: its options, its report, and the report of a mesh in parts.

:func:`~coastmesh.meshing.cleanup.fixes.clean_mesh` cleans one mesh. A mesh meshed
in parts (:func:`~coastmesh.meshing.mesh_in_parts`) is cleaned part by part,
where each part is meshed, with the nodes of the cuts held fixed; :func:`combine`
then makes one report of the parts' as if the whole mesh had been cleaned: the
counts add up, the "before" numbers are those of the merged Gmsh mesh (the
valence at a node of a cut sums both sides'), and the "after" numbers are
measured on the merged mesh.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from coastmesh.errors import ConfigError
from coastmesh.meshing.cleanup import smoothing
from coastmesh.meshing.cleanup.planar import sines_and_ratios
from coastmesh.types import Report

__all__ = [
    "Accepted",
    "CleanupOptions",
    "CleanupReport",
    "PartCleanup",
    "combine",
    "stats",
]

#: Which mesh :func:`~coastmesh.meshing.cleanup.fixes.clean_mesh` returned.
Accepted = Literal["cleaned", "cleaned_partly", "smoothed_only", "input"]

#: the acceptances, from the least done to the most
ACCEPTED = ("input", "smoothed_only", "cleaned_partly", "cleaned")


@dataclass(frozen=True, slots=True)
class CleanupOptions:
    """The options of :func:`~coastmesh.meshing.cleanup.fixes.clean_mesh` (see there).

    Raises
    ------
    ConfigError
        If ``max_valence`` is below 4 or ``min_angle`` is not in (0, 60).
    """

    boundary_triangles: bool = True
    max_valence: int | None = None
    min_angle: float = 20.0
    smooth: bool = True

    def __post_init__(self) -> None:
        if self.max_valence is not None and self.max_valence < 4:
            raise ConfigError(f"max_valence = {self.max_valence}: must be at least 4")
        if not 0 < self.min_angle < 60:
            raise ConfigError(
                f"min_angle = {self.min_angle}: must be between 0 and 60 degrees"
            )


@dataclass(frozen=True, slots=True)
class CleanupReport(Report):
    """What :func:`clean_mesh` changed (the fixes in the mesh it returned).

    Attributes
    ----------
    boundary_triangles_before, boundary_triangles_after : int
        Triangles with all three nodes on the boundary.
    boundary_flips, boundary_splits, boundary_edge_splits : int
        Such triangles fixed by an edge flip, a centroid split, an edge split.
    max_valence_before, max_valence_after : int
        Most triangles at an interior node.
    slivers_before, slivers_after : int
        Triangles with a minimum angle below ``min_angle``.
    valence_flips, sliver_flips, sliver_splits : int
        Flips that lowered crowded nodes' valence; flips and edge splits that
        raised slivers' angles.
    min_angle_before, min_angle_after, min_angle_p1_before, min_angle_p1_after
        Smallest angle, and 1st percentile of minimum angles, degrees (float).
    radius_ratio_before, radius_ratio_after : float
        Smallest radius ratio (twice the inscribed over the circumscribed
        radius; 1 for an equilateral triangle).
    smoothed_nodes : int
        Nodes moved by smoothing.
    accepted : {"cleaned", "cleaned_partly", "smoothed_only", "input"}
        The mesh returned (see the module notes): cleaned and smoothed; the same
        with only the boundary fixes that keep the input's 1st percentile; the
        input smoothed; or the input.
    """

    boundary_triangles_before: int
    boundary_triangles_after: int
    boundary_flips: int
    boundary_splits: int
    max_valence_before: int
    max_valence_after: int
    valence_flips: int
    slivers_before: int
    slivers_after: int
    sliver_flips: int
    min_angle_before: float
    min_angle_after: float
    boundary_edge_splits: int
    smoothed_nodes: int
    min_angle_p1_before: float
    min_angle_p1_after: float
    radius_ratio_before: float
    radius_ratio_after: float
    accepted: Accepted
    sliver_splits: int = 0

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.accepted}: all-boundary triangles "
            f"{self.boundary_triangles_before} -> {self.boundary_triangles_after} "
            f"({self.boundary_flips} flips, {self.boundary_splits} + "
            f"{self.boundary_edge_splits} splits); max valence "
            f"{self.max_valence_before} -> {self.max_valence_after} "
            f"({self.valence_flips} flips); slivers {self.slivers_before} -> "
            f"{self.slivers_after} ({self.sliver_flips} flips, "
            f"{self.sliver_splits} splits); "
            f"{self.smoothed_nodes} nodes smoothed; min angle "
            f"{self.min_angle_before:.1f} -> {self.min_angle_after:.1f} deg, 1st "
            f"percentile {self.min_angle_p1_before:.1f} -> "
            f"{self.min_angle_p1_after:.1f} deg; radius ratio "
            f"{self.radius_ratio_before:.2f} -> {self.radius_ratio_after:.2f}"
        )


def stats(
    xy: NDArray[np.float64],
    tri: NDArray[np.int64],
    on_boundary: NDArray[np.bool_],
    min_angle: float,
    fixed: NDArray[np.bool_] | None = None,
) -> dict[str, Any]:  # ints and floats, by CleanupReport's field
    """Return the numbers the report has before and after.

    ``fixed`` nodes (the nodes of cuts in a part) are left out of the valence.
    """
    sines, ratios = sines_and_ratios(xy, tri)
    angles = np.degrees(np.arcsin(np.clip(sines, -1.0, 1.0)))  # as min_angles
    valence = np.bincount(tri.ravel(), minlength=len(xy))
    inner = ~on_boundary if fixed is None else ~(on_boundary | fixed)
    ratios = ratios if len(tri) else np.ones(1)
    return {
        "boundary_triangles": int(on_boundary[tri].all(axis=1).sum()),
        "max_valence": int(valence[inner].max(initial=0)),
        "slivers": int((angles < min_angle).sum()),
        "min_angle": float(angles.min(initial=90.0)),
        "min_angle_p1": smoothing.percentile(angles, 1),
        "radius_ratio": float(ratios.min()),
    }


#: A worst radius ratio the cleanup may lower to, if the input's is higher: the
#: fan of twelve 30-degree triangles (radius ratio 0.8) needs one near 0.6 to
#: lose four of its edges, and elements above this are no trouble to a model
RADIUS_RATIO_GOOD = 0.5


def no_worse(after: dict[str, float], before: dict[str, float]) -> bool:
    """Whether the worst angle, 1st percentile and radius ratio held up.

    The radius ratio may fall, but not below :data:`RADIUS_RATIO_GOOD`.
    """
    least = min(before["radius_ratio"], RADIUS_RATIO_GOOD)
    return after["radius_ratio"] >= least and all(
        after[k] >= before[k] for k in ("min_angle", "min_angle_p1")
    )


@dataclass(frozen=True, slots=True)
class PartCleanup:
    """One part's cleanup, as :func:`combine` needs it.

    Attributes
    ----------
    report : CleanupReport
        The part's own report.
    angles_before : ndarray of shape (M,)
        The minimum angle of each of the part's Gmsh triangles, degrees.
    cut_nodes, cut_valence : ndarray of int
        The shared numbers of the part's nodes on cuts (not on the boundary),
        and the number of the part's Gmsh triangles at each.
    seconds : float
        The time the part's cleanup took.
    """

    report: CleanupReport
    angles_before: NDArray[np.float64]
    cut_nodes: NDArray[np.int64]
    cut_valence: NDArray[np.int64]
    seconds: float


def combine(
    parts: Sequence[PartCleanup],
    after: dict[str, Any],
    *,
    seam_moved: int = 0,
    seam_fixes: tuple[int, int] = (0, 0),
) -> CleanupReport:
    """Return the report of a mesh cleaned in parts.

    Parameters
    ----------
    parts : sequence of PartCleanup
    after : dict
        :func:`stats` of the merged, cleaned mesh.
    seam_moved : int
        Nodes moved when the cuts were smoothed after the parts were joined
        (:func:`~coastmesh.meshing.parts.seams.smooth_seams`); they count in
        ``smoothed_nodes`` too (a node moved in its part and again there
        counts twice).
    seam_fixes : (int, int)
        Sliver flips and splits made at the cuts after the parts were joined
        (:func:`~coastmesh.meshing.cleanup.fixes.fix_seam_slivers`); they
        count in ``sliver_flips`` and ``sliver_splits`` too.

    Returns
    -------
    CleanupReport
        ``accepted`` is the parts' if they agree; else "smoothed_only" if no
        part was cleaned, "cleaned_partly" if some were.
    """
    reports = [p.report for p in parts]
    cut = np.concatenate([p.cut_nodes for p in parts])
    weights = np.concatenate([p.cut_valence for p in parts])
    at_cuts = np.bincount(cut, weights=weights).max(initial=0) if len(cut) else 0
    before: dict[str, Any] = {  # as stats() gives them
        "boundary_triangles": sum(r.boundary_triangles_before for r in reports),
        "max_valence": int(max(*(r.max_valence_before for r in reports), at_cuts)),
        "slivers": sum(r.slivers_before for r in reports),
        "min_angle": min(r.min_angle_before for r in reports),
        "min_angle_p1": smoothing.percentile(
            np.concatenate([p.angles_before for p in parts]), 1
        ),
        "radius_ratio": min(r.radius_ratio_before for r in reports),
    }
    kinds = {r.accepted for r in reports}
    accepted: Accepted
    if len(kinds) == 1:
        accepted = kinds.pop()
    elif kinds <= {"input", "smoothed_only"}:
        accepted = "smoothed_only"
    else:
        accepted = "cleaned_partly"
    counts = (
        "boundary_flips",
        "boundary_splits",
        "boundary_edge_splits",
        "valence_flips",
        "sliver_flips",
        "sliver_splits",
        "smoothed_nodes",
    )
    return CleanupReport(
        **{f"{name}_before": value for name, value in before.items()},
        **{f"{name}_after": value for name, value in after.items()},
        **{name: sum(getattr(r, name) for r in reports) for name in counts[:-1]}
        | {
            "sliver_flips": sum(r.sliver_flips for r in reports) + seam_fixes[0],
            "sliver_splits": sum(r.sliver_splits for r in reports) + seam_fixes[1],
        },
        smoothed_nodes=sum(r.smoothed_nodes for r in reports) + seam_moved,
        accepted=accepted,
    )
