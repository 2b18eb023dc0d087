"""What a patch changed: counts, the seam's quality, the time step.

Angles and sizes are measured in the meshing CRS (conformal: the shapes are
the Earth's); an element's size is its mean edge length. Across each seam edge
the size ratio is the larger over the smaller of the kept element's and the
new element's sizes. The time steps are each element's stable step
``r_in / sqrt(g d)`` (:func:`coastmesh.meshing.element_time_steps`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.patch.cut import Hole
from coastmesh.geometry.earth import reproject_points
from coastmesh.meshing.cleanup.smoothing import min_angles
from coastmesh.types import Mesh, Report

__all__ = ["PatchReport", "patch_report", "seam_faults"]


@dataclass(frozen=True, slots=True)
class PatchReport(Report):
    """What :func:`~coastmesh.case.patch.patch_mesh` did.

    Attributes
    ----------
    kept_nodes, kept_elements : int
        Of the input, kept as they were.
    removed_nodes, removed_elements : int
        Cut out (nodes: those only the elements cut out used).
    widened_elements : int
        Of those, the elements that do not meet the polygon, cut out where
        the hole would touch itself or make a corner sharper than 45 degrees,
        or where the seam was moved out (``seam_moves``).
    added_nodes, added_elements : int
        The patch's.
    seam_edges : int
        Edges the patch shares with the kept mesh.
    angle_p01_patch, angle_min_patch : float
        The 1st percentile and the smallest of the patch's elements' smallest
        angles, degrees.
    angle_p01_seam, angle_min_seam : float
        The same over the elements, kept and new, with a node on the seam.
    size_ratio_seam_max, size_ratio_seam_p99 : float
        Of the size ratios across the seam's edges.
    size_removed_m, size_new_m : float
        The median size of the elements cut out and of the patch's.
    dt_input_s, dt_patch_s, dt_output_s : float or None
        The smallest stable step of the input, of the patch, and of the
        output (None without depths).
    seam_moves : int
        How many times the seam was moved out, past the nodes where the patch
        met it with an angle under 30 degrees or a size ratio over 1.5 (the
        kept elements there are cut out too, and counted as widened).
    """

    kept_nodes: int
    kept_elements: int
    removed_nodes: int
    removed_elements: int
    widened_elements: int
    added_nodes: int
    added_elements: int
    seam_edges: int
    angle_p01_patch: float
    angle_min_patch: float
    angle_p01_seam: float
    angle_min_seam: float
    size_ratio_seam_max: float
    size_ratio_seam_p99: float
    size_removed_m: float
    size_new_m: float
    dt_input_s: float | None
    dt_patch_s: float | None
    dt_output_s: float | None
    seam_moves: int = 0

    def summary(self) -> str:
        """Return one line."""
        dt = ""
        if self.dt_input_s is not None and self.dt_output_s is not None:
            dt = f"; slowest step {self.dt_input_s:.2f} -> {self.dt_output_s:.2f} s"
        moved = ""
        if self.seam_moves:
            moved = f" (moved out {self.seam_moves} time{'s' * (self.seam_moves > 1)})"
        return (
            f"patch: -{self.removed_elements:,} +{self.added_elements:,} elements "
            f"(-{self.removed_nodes:,} +{self.added_nodes:,} nodes), "
            f"{self.kept_elements:,} kept as they were; seam of {self.seam_edges} "
            f"edges{moved}, size ratio across it <= {self.size_ratio_seam_max:.2f}; "
            f"min angle p01 {self.angle_p01_patch:.1f} deg in the patch, "
            f"{self.angle_p01_seam:.1f} at the seam{dt}"
        )


def patch_report(
    before: Mesh,
    after: Mesh,
    hole: Hole,
    new_elements: NDArray[np.int64],
    crs: CRS,
    seam: NDArray[np.int64],
    seam_moves: int = 0,
) -> PatchReport:
    """Measure a patch: ``before`` and ``after`` in their CRS, measured in ``crs``."""
    assert after.crs is not None and before.crs is not None
    xy = reproject_points(after.points, after.crs, crs)
    # either way round, as the input turns: the angles' size
    angles = np.abs(min_angles(xy, after.triangles))
    sizes = _sizes(xy, after.triangles)
    old_xy = reproject_points(before.points, before.crs, crs)
    removed_size = _sizes(old_xy, before.triangles[hole.removed])
    seam_nodes = np.zeros(len(after.points), dtype=bool)
    seam_nodes[np.unique(seam)] = True  # the seam's nodes keep their numbers
    at_seam = seam_nodes[after.triangles].any(axis=1)
    ratio = _seam_ratios(after.triangles, sizes, seam)
    ratio = ratio[np.isfinite(ratio)]
    dts = [_dt(m) for m in (before, after)]
    is_new = np.zeros(len(after.triangles), dtype=bool)
    is_new[new_elements] = True
    dt_patch = None
    if dts[1] is not None:
        dt_patch = float(np.nanmin(dts[1][is_new]))
    return PatchReport(
        kept_nodes=len(before.points) - len(hole.inner_nodes),
        kept_elements=int((~hole.removed).sum()),
        removed_nodes=len(hole.inner_nodes),
        removed_elements=int(hole.removed.sum()),
        widened_elements=hole.widened,
        added_nodes=len(after.points) - len(before.points) + len(hole.inner_nodes),
        added_elements=len(new_elements),
        seam_edges=len(seam),
        angle_p01_patch=float(np.percentile(angles[is_new], 1)),
        angle_min_patch=float(angles[is_new].min()),
        angle_p01_seam=float(np.percentile(angles[at_seam], 1)),
        angle_min_seam=float(angles[at_seam].min()),
        size_ratio_seam_max=float(ratio.max()) if ratio.size else 1.0,
        size_ratio_seam_p99=float(np.percentile(ratio, 99)) if ratio.size else 1.0,
        size_removed_m=float(np.median(removed_size)),
        size_new_m=float(np.median(sizes[is_new])),
        dt_input_s=None if dts[0] is None else float(np.nanmin(dts[0])),
        dt_patch_s=dt_patch,
        dt_output_s=None if dts[1] is None else float(np.nanmin(dts[1])),
        seam_moves=seam_moves,
    )


def seam_faults(
    after: Mesh,
    crs: CRS,
    seam: NDArray[np.int64],
    *,
    min_angle: float,
    max_ratio: float,
) -> NDArray[np.int64]:
    """Return the seam's nodes (numbers in ``after``) where the patch meets it badly.

    Those of each element with a node on the seam and a smallest angle under
    ``min_angle`` (degrees, in ``crs``), and both ends of each seam edge across
    which the size ratio is over ``max_ratio``.
    """
    assert after.crs is not None
    xy = reproject_points(after.points, after.crs, crs)
    on_seam = np.zeros(len(after.points), dtype=bool)
    on_seam[seam.ravel()] = True
    tris = after.triangles
    sharp = on_seam[tris].any(axis=1) & (np.abs(min_angles(xy, tris)) < min_angle)
    at_sharp = tris[sharp][on_seam[tris[sharp]]]
    ratio = _seam_ratios(tris, _sizes(xy, tris), seam)
    return np.union1d(at_sharp, seam[ratio > max_ratio].ravel())


def _sizes(xy: NDArray[np.float64], tris: NDArray[np.int64]) -> NDArray[np.float64]:
    p = xy[tris]
    sides = [np.hypot(*(p[:, (i + 1) % 3] - p[:, i]).T) for i in range(3)]
    return np.asarray(np.mean(sides, axis=0), dtype=np.float64)


def _seam_ratios(
    tris: NDArray[np.int64],
    sizes: NDArray[np.float64],
    seam: NDArray[np.int64],
) -> NDArray[np.float64]:
    """Return the size ratio across each seam edge (larger over smaller; NaN: none)."""
    edges = np.sort(tris[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    owner = np.repeat(np.arange(len(tris)), 3)
    key = edges[:, 0] * (int(edges.max()) + 1) + edges[:, 1]
    s = np.sort(seam, axis=1)
    wanted = s[:, 0] * (int(edges.max()) + 1) + s[:, 1]
    order = np.argsort(key, kind="stable")
    lo = np.searchsorted(key[order], wanted, side="left")
    hi = np.searchsorted(key[order], wanted, side="right")
    ratios = np.full(len(seam), np.nan)
    for k, (a, b) in enumerate(zip(lo, hi, strict=True)):
        pair = owner[order[a:b]]
        if len(pair) == 2:
            h = sizes[pair]
            ratios[k] = h.max() / h.min()
    return ratios


def _dt(mesh: Mesh) -> NDArray[np.float64] | None:
    """Each element's stable step, or None without depths."""
    if "depth" not in mesh.point_data:
        return None
    from coastmesh.meshing import element_time_steps

    return element_time_steps(mesh)["dt"]
