"""What :func:`~coastmesh.meshing.quality.mesh_quality` reports, as data and text.

:class:`QualityReport` holds the counts and one statistics block per measure
(:class:`AngleStats`, :class:`RatioStats`, :class:`EdgeRatioStats`,
:class:`ValenceStats`), each built from the measured arrays by ``from_values``,
and the blocks for sharp boundary corners
(:class:`~coastmesh.meshing.quality.corners.CornerStats`) and the time step
(:class:`~coastmesh.meshing.quality.time_step.TimeStepStats`). Every block has
``to_dict()`` and ``summary()``; writing them to files is left to
:mod:`coastmesh.io`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from coastmesh.meshing.quality.corners import CornerStats
from coastmesh.meshing.quality.sphere import SphereQuality
from coastmesh.meshing.quality.time_step import TimeStepStats
from coastmesh.types import Report

__all__ = [
    "EDGE_RATIO_RANGE",
    "HISTOGRAM_BINS",
    "RADIUS_RATIO_TARGET",
    "AngleStats",
    "EdgeRatioStats",
    "QualityReport",
    "RatioStats",
    "ValenceStats",
    "histogram",
    "histogram_bins",
    "histograms",
]

#: Edge length / target size counted as on target.
EDGE_RATIO_RANGE = (0.5, 2.0)

#: The smallest radius ratio wanted, except at sharp boundary corners.
RADIUS_RATIO_TARGET = 0.25

_LENGTHS = {
    False: "on the WGS84 ellipsoid (metres)",
    True: "planar: the mesh has no CRS, coordinates taken as metres",
}


@dataclass(frozen=True, slots=True)
class AngleStats(Report):
    """The triangles' minimum angles, in degrees.

    Attributes
    ----------
    min, p1, p5, p50, mean : float
        Smallest value, 1st, 5th and 50th percentiles, and mean (degrees).
    below_20, below_30 : int
        Triangles whose minimum angle is below 20 and 30 degrees.
    """

    min: float
    p1: float
    p5: float
    p50: float
    mean: float
    below_20: int
    below_30: int

    @classmethod
    def from_values(cls, angle: NDArray[np.float64]) -> AngleStats:
        """Return the statistics of the minimum angles (degrees) of the triangles.

        Examples
        --------
        >>> AngleStats.from_values(np.array([10.0, 25.0, 40.0])).below_30
        2
        """
        p1, p5, p50 = np.percentile(angle, [1, 5, 50])
        return cls(
            min=float(angle.min()),
            p1=float(p1),
            p5=float(p5),
            p50=float(p50),
            mean=float(angle.mean()),
            below_20=int((angle < 20).sum()),
            below_30=int((angle < 30).sum()),
        )

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"minimum angle (deg): min {self.min:.2f}, p1 {self.p1:.2f}, "
            f"p5 {self.p5:.2f}, median {self.p50:.2f}, mean {self.mean:.2f}; "
            f"{self.below_20:,} below 20, {self.below_30:,} below 30"
        )


@dataclass(frozen=True, slots=True)
class RatioStats(Report):
    """The triangles' radius ratios ``2 r_in / r_circ`` (1 for equilateral).

    Attributes
    ----------
    min, p1, p5, mean : float
        Smallest value, 1st and 5th percentiles, and mean.
    below_0_25 : int
        Triangles with a ratio below :data:`RADIUS_RATIO_TARGET` (0.25).
    """

    min: float
    p1: float
    p5: float
    mean: float
    below_0_25: int

    @classmethod
    def from_values(cls, ratio: NDArray[np.float64]) -> RatioStats:
        """Return the statistics of the radius ratios of the triangles.

        Examples
        --------
        >>> RatioStats.from_values(np.array([0.5, 1.0])).mean
        0.75
        """
        p1, p5 = np.percentile(ratio, [1, 5])
        return cls(
            min=float(ratio.min()),
            p1=float(p1),
            p5=float(p5),
            mean=float(ratio.mean()),
            below_0_25=int((ratio < RADIUS_RATIO_TARGET).sum()),
        )

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"radius ratio: min {self.min:.3f}, p1 {self.p1:.3f}, p5 {self.p5:.3f}, "
            f"mean {self.mean:.3f}; {self.below_0_25:,} below "
            f"{RADIUS_RATIO_TARGET:g}"
        )


@dataclass(frozen=True, slots=True)
class EdgeRatioStats(Report):
    """Edge length over target size, for every edge of the mesh once.

    Attributes
    ----------
    edges : int
        Number of edges.
    min, p5, p50, p95, max : float
        Smallest value, 5th, 50th and 95th percentiles, largest value.
    within : float
        Fraction of the edges with a ratio in :data:`EDGE_RATIO_RANGE`, [0.5, 2].
    """

    edges: int
    min: float
    p5: float
    p50: float
    p95: float
    max: float
    within: float

    @classmethod
    def from_values(cls, ratio: NDArray[np.float64]) -> EdgeRatioStats:
        """Return the statistics of the edge length over target size of each edge.

        Examples
        --------
        >>> EdgeRatioStats.from_values(np.array([0.4, 1.0, 1.5, 3.0])).within
        0.5
        """
        p5, p50, p95 = np.percentile(ratio, [5, 50, 95])
        low, high = EDGE_RATIO_RANGE
        return cls(
            edges=len(ratio),
            min=float(ratio.min()),
            p5=float(p5),
            p50=float(p50),
            p95=float(p95),
            max=float(ratio.max()),
            within=float(((ratio >= low) & (ratio <= high)).mean()),
        )

    def summary(self) -> str:
        """Return a one-line summary."""
        low, high = EDGE_RATIO_RANGE
        return (
            f"edge length / size: min {self.min:.2f}, p5 {self.p5:.2f}, median "
            f"{self.p50:.2f}, p95 {self.p95:.2f}, max {self.max:.2f}; "
            f"{100 * self.within:.1f}% of {self.edges:,} edges in [{low:g}, {high:g}]"
        )


@dataclass(frozen=True, slots=True)
class ValenceStats(Report):
    """Number of triangles at each node of one group (interior or boundary).

    Attributes
    ----------
    nodes : int
        Nodes in the group.
    histogram : dict of int to int
        Number of nodes by valence, for the valences that occur.
    max : int
        Largest valence (0 if the group is empty).
    above_8 : int
        Nodes in more than 8 triangles.
    """

    nodes: int
    histogram: dict[int, int]
    max: int
    above_8: int

    @classmethod
    def from_values(cls, valence: NDArray[np.int64]) -> ValenceStats:
        """Return the statistics of the valences (triangles per node) of a group.

        Examples
        --------
        >>> ValenceStats.from_values(np.array([6, 6, 9])).histogram
        {6: 2, 9: 1}
        """
        counts = np.bincount(valence)
        return cls(
            nodes=len(valence),
            histogram={int(v): int(c) for v, c in enumerate(counts) if c},
            max=int(valence.max()) if valence.size else 0,
            above_8=int((valence > 8).sum()),
        )

    def summary(self) -> str:
        """Return a one-line summary."""
        return f"{self.nodes:,} nodes, valence max {self.max}, {self.above_8:,} above 8"


#: Bins of each histogram of a quality report (and figure).
HISTOGRAM_BINS = 90


def histogram_bins(key: str, values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the bin edges of ``key``'s histogram of ``values``.

    ``"min_angle"``: 0 to 60 degrees; ``"radius_ratio"``: 0 to 1;
    ``"edge_ratio"``: geometric, from 0.25 or the smallest value below it to 4
    or the largest above it.
    """
    if key == "min_angle":
        return np.linspace(0.0, 60.0, HISTOGRAM_BINS + 1)
    if key == "radius_ratio":
        return np.linspace(0.0, 1.0, HISTOGRAM_BINS + 1)
    low = min(float(values.min()), 0.25)
    high = max(float(values.max()), 4.0)
    return np.geomspace(low, high, HISTOGRAM_BINS + 1)


def histograms(
    shape: dict[str, NDArray[np.float64]], edges: dict[str, Any]
) -> dict[str, tuple[NDArray[np.int64], NDArray[np.float64]]]:
    """Return :attr:`QualityReport.histograms` of measured triangles and edges.

    ``shape`` holds ``"min_angle"`` and ``"radius_ratio"`` per triangle,
    ``edges`` maybe ``"ratio"`` per edge (as
    :func:`~coastmesh.meshing.quality.mesh_quality.triangle_quality` and
    :func:`~coastmesh.meshing.quality.mesh_quality.edge_quality` return them).
    """
    return {
        key: histogram(key, values)
        for key, values in (
            ("min_angle", shape["min_angle"]),
            ("radius_ratio", shape["radius_ratio"]),
            ("edge_ratio", edges.get("ratio")),
        )
        if values is not None
    }


def histogram(
    key: str, values: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Return ``(counts, edges)`` of ``values`` in :func:`histogram_bins`.

    Values outside the bins are counted in the end bins.
    """
    bins = histogram_bins(key, values)
    counts, edges = np.histogram(np.clip(values, bins[0], bins[-1]), bins=bins)
    return counts, edges


@dataclass(frozen=True, slots=True)
class QualityReport(Report):
    """What :func:`~coastmesh.meshing.quality.mesh_quality.mesh_quality` measured.

    Attributes
    ----------
    nodes, triangles : int
        Counts.
    unused_nodes : int
        Nodes in no triangle; neither interior nor boundary.
    boundary_edges : dict of int to int
        Number of tagged boundary edges (``mesh.boundary_edges``) by id.
    boundary_names, boundary_kinds : dict of int to str
        From the mesh, where known.
    crs : str or None
        Name of the mesh CRS; None when unknown.
    planar : bool
        True when the mesh has no CRS and lengths were taken as planar metres.
    min_angle : AngleStats
        Minimum angle of each triangle, degrees.
    radius_ratio : RatioStats
        ``2 r_in / r_circ`` of each triangle.
    edge_ratio : EdgeRatioStats or None
        Edge length over target size; None without a size.
    interior_valence, boundary_valence : ValenceStats
        Triangles per node, for interior nodes and for nodes on the boundary
        (nodes of edges that belong to a single triangle).
    corners : CornerStats
        Boundary nodes with an interior angle below 45 degrees.
    radius_ratio_away_from_corners : RatioStats or None
        The radius ratios of the triangles that touch no sharp corner (the
        target, at least 0.25, applies to them); None if every triangle does.
    time_step : TimeStepStats or None
        Stable time step and Courant numbers; None without a depth on the nodes.
    all_boundary_triangles : ndarray of int64, shape (k,)
        Indices of the triangles whose three nodes are all on the boundary; only
        their number goes into :meth:`to_dict` and :meth:`summary`.
    channel_spanning_triangles : ndarray of int64, shape (k,)
        Those of them with at most one side on the boundary: they span a
        channel one element wide. Only their number is reported.
    histograms : dict of str to (counts, bin edges)
        ``"min_angle"``, ``"radius_ratio"`` and, with a size,
        ``"edge_ratio"`` (:func:`histogram_bins`), values outside the bins
        counted in the end bins: what the quality figure draws, so that it
        need not measure the mesh again. Not in :meth:`to_dict`.
    sphere : SphereQuality or None
        A global mesh checked on the sphere
        (:func:`~coastmesh.meshing.quality.sphere.sphere_quality`); None otherwise.
    """

    nodes: int
    triangles: int
    unused_nodes: int
    boundary_edges: dict[int, int]
    boundary_names: dict[int, str]
    boundary_kinds: dict[int, str]
    crs: str | None
    planar: bool
    min_angle: AngleStats
    radius_ratio: RatioStats
    edge_ratio: EdgeRatioStats | None
    interior_valence: ValenceStats
    boundary_valence: ValenceStats
    corners: CornerStats
    radius_ratio_away_from_corners: RatioStats | None
    time_step: TimeStepStats | None
    all_boundary_triangles: NDArray[np.int64] = field(repr=False, compare=False)
    channel_spanning_triangles: NDArray[np.int64] = field(repr=False, compare=False)
    histograms: dict[str, tuple[NDArray[np.int64], NDArray[np.float64]]] = field(
        default_factory=dict, repr=False, compare=False
    )
    sphere: SphereQuality | None = None

    def to_dict(self) -> dict[str, Any]:
        """Return the report as JSON-ready data, floats to 6 significant digits.

        Returns
        -------
        dict
            ``coastmesh_version``, ``crs``, ``lengths`` (how lengths were
            measured), the counts, ``boundary_edges`` by id (with name, kind and
            number of edges), ``min_angle_deg``, ``radius_ratio``,
            ``edge_length_over_size`` (None without a size) and ``valence``
            (``interior`` and ``boundary``), ``corners``,
            ``radius_ratio_away_from_corners`` and ``time_step`` (None without
            depths). Integer keys (boundary ids, valences) become strings, as
            JSON needs; ``all_boundary_triangles`` and
            ``channel_spanning_triangles`` are their numbers.
        """
        from coastmesh.version import __version__

        boundary = {
            str(pid): {
                "name": self.boundary_names.get(pid),
                "kind": self.boundary_kinds.get(pid),
                "edges": count,
            }
            for pid, count in sorted(self.boundary_edges.items())
        }
        valence = {
            group: {
                **_rounded(stats.to_dict()),
                "histogram": {str(k): v for k, v in sorted(stats.histogram.items())},
            }
            for group, stats in (
                ("interior", self.interior_valence),
                ("boundary", self.boundary_valence),
            )
        }
        return {
            "coastmesh_version": __version__,
            "crs": self.crs,
            "lengths": _LENGTHS[self.planar],
            "nodes": self.nodes,
            "triangles": self.triangles,
            "unused_nodes": self.unused_nodes,
            "boundary_edges": boundary,
            "min_angle_deg": _rounded(self.min_angle.to_dict()),
            "radius_ratio": _rounded(self.radius_ratio.to_dict()),
            "edge_length_over_size": (
                None if self.edge_ratio is None else _rounded(self.edge_ratio.to_dict())
            ),
            "valence": valence,
            "corners": _rounded(self.corners.to_dict()),
            "radius_ratio_away_from_corners": (
                None
                if self.radius_ratio_away_from_corners is None
                else _rounded(self.radius_ratio_away_from_corners.to_dict())
            ),
            "time_step": (
                None if self.time_step is None else _rounded(self.time_step.to_dict())
            ),
            "all_boundary_triangles": len(self.all_boundary_triangles),
            "channel_spanning_triangles": len(self.channel_spanning_triangles),
            "sphere": None if self.sphere is None else _rounded(self.sphere.to_dict()),
        }

    def summary(self) -> str:
        """Return a short multi-line text summary.

        Returns
        -------
        str
            About ten lines, without a trailing newline.
        """
        iv, bv = self.interior_valence, self.boundary_valence
        ids = "; ".join(
            f"{_label(pid, self.boundary_names, self.boundary_kinds)}: {n:,}"
            for pid, n in sorted(self.boundary_edges.items())
        )
        lines = [
            f"mesh quality, lengths {_LENGTHS[self.planar]}",
            f"  {self.nodes:,} nodes ({iv.nodes:,} interior, {bv.nodes:,} boundary, "
            f"{self.unused_nodes:,} unused), {self.triangles:,} triangles",
            f"  boundary edges by id: {ids or 'none'}",
            f"  {self.min_angle.summary()}",
            f"  {self.radius_ratio.summary()}",
        ]
        if self.edge_ratio is not None:
            lines.append(f"  {self.edge_ratio.summary()}")
        lines += [
            f"  valence: interior max {iv.max}, {iv.above_8:,} above 8; "
            f"boundary max {bv.max}",
            "  triangles with all nodes on the boundary: "
            f"{len(self.all_boundary_triangles):,}, spanning a channel: "
            f"{len(self.channel_spanning_triangles):,}",
            f"  {self.corners.summary()}",
        ]
        away = self.radius_ratio_away_from_corners
        if self.corners.sharp and away is not None:
            lines.append(f"  away from sharp corners, {away.summary()}")
        if self.time_step is not None:
            lines.append(f"  {self.time_step.summary()}")
            if self.time_step.courant is not None:
                lines.append(f"  {self.time_step.courant.summary()}")
            if self.time_step.slowest:
                lines.append("  slowest elements (smallest stable time step):")
                lines.extend(f"    {e.summary()}" for e in self.time_step.slowest)
        if self.sphere is not None:
            lines.append(f"  {self.sphere.summary()}")
        return "\n".join(lines)


def _label(pid: int, names: dict[int, str], kinds: dict[int, str]) -> str:
    """``"2 south (open)"``: the id, with its name and kind where known."""
    name = f" {names[pid]}" if pid in names else ""
    kind = f" ({kinds[pid]})" if pid in kinds else ""
    return f"{pid}{name}{kind}"


def _rounded(value: Any) -> Any:
    """Floats to 6 significant digits, in dicts and lists too; the rest unchanged."""
    if isinstance(value, float):
        return float(f"{value:.6g}")
    if isinstance(value, dict):
        return {key: _rounded(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_rounded(item) for item in value]
    return value
