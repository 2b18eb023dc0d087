"""Bathymetry on the mesh nodes: sources, coverage, land, depth floor, slope limit.

The depth comes from a stack of rasters (:class:`~coastmesh.depth.DepthSources`,
highest priority first, blended at their seams). Every node must lie within the
sources' cover (up to one cell diagonal); ``outside="nearest"`` gives the rest
the nearest valid cell on the Earth instead, with a warning. Nodes the rasters
put on land (depth <= 0 m) get the ``land`` treatment. Depths are metres,
positive down.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from coastmesh.depth.sources import DepthSource, DepthSources, SourceSample
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import mesh_earth_centred, reproject_points
from coastmesh.types import Mesh, Report
from coastmesh.types.topology import unique_edges

if TYPE_CHECKING:
    import xarray as xr
    from pyproj import CRS

_R = TypeVar("_R")

__all__ = [
    "DEPTH_METHODS",
    "FLOOR_CAUSES",
    "LAND_TREATMENTS",
    "MAX_LAND_SHARE",
    "OUTSIDE_RULES",
    "RULES",
    "CoarseRasterWarning",
    "DepthReport",
    "depth_at_nodes",
    "limit_slope",
]

#: ``"bilinear"``: bilinear interpolation; ``"mean"``: the mean of the cells over
#: each node's surrounding area where the mesh is coarser than the raster
#: (bilinear elsewhere).
DEPTH_METHODS = ("bilinear", "mean")
#: What a node in the mesh's sea gets where the rasters say land (depth <= 0):
#: ``"wet"`` (the default) reads the wet cells alone: a node with a wet cell
#: among its four takes their renormalised bilinear mean; one with none takes
#: the nearest wet cell, tapered to ``min_depth`` at the coast (only across
#: the strip the raster calls land); ``"min_depth"`` the depth floor;
#: ``"nearest_sea"`` the nearest wet cell; ``"smooth"`` the nearest wet cell,
#: then a taper of every depth within ``land_distance`` of the coast to
#: ``min_depth`` at the coast; ``"keep"`` the land heights as negative depths
#: (for models that wet and dry).
LAND_TREATMENTS = ("wet", "min_depth", "nearest_sea", "smooth", "keep")
#: What a node's depth is, in ``DepthReport.rules`` (later codes win): the
#: raster's own; the wet cells around it alone; the nearest wet cell (the
#: raster calls the place land); that, tapered to the coast; raised to
#: ``min_depth``; a land cell's value (``"keep"``, ``"min_depth"`` without it);
#: beyond every source (``outside = "nearest"``).
RULES = (
    "raster",
    "wet cells around",
    "nearest wet cell",
    "tapered",
    "min_depth",
    "land value",
    "outside the rasters",
)
#: Why a node's depth ends at ``min_depth`` (``DepthReport.at_min_depth_causes``),
#: each with the words of the summary.
FLOOR_CAUSES = {
    "raised": "raised from shallower sea depths",
    "raised_on_land": "raised on land in the rasters",
    "tapered": "tapered to it at the coast",
    "rasters": "the rasters' own depth",
}
#: Above this share of the nodes on land in the rasters, a raster is too
#: coarse for the coast: an error unless ``land`` is given (the case decides).
MAX_LAND_SHARE = 0.5
#: A node reads a raster "coarser than the mesh" where its elements are
#: smaller than the raster's cells by this factor or more.
COARSE_RATIO = 1.0
#: Nodes beyond every source's cover: ``"error"`` or ``"nearest"`` valid cell.
OUTSIDE_RULES = ("error", "nearest")


@dataclass(frozen=True, slots=True)
class DepthReport(Report):
    """What :func:`depth_at_nodes` did.

    Attributes
    ----------
    nodes : int
        Mesh nodes given a depth.
    method : str
        ``"bilinear"`` or ``"mean"`` (:data:`DEPTH_METHODS`).
    averaged : int
        Nodes whose depth is the mean of the cells around them (``"mean"``).
    nearest : int
        Nodes beyond every source's cover that took the nearest valid cell on
        the Earth (``outside="nearest"``).
    below_min_depth : int
        Nodes raised to the minimum depth from shallower (sea or land): one of
        the causes of ``at_min_depth``, not the share at the floor.
    slope_limited : int
        Nodes made shallower by the slope limit.
    min, max : float
        Smallest and largest depth, metres, positive down.
    sources : tuple of str
        The sources' names, in priority order.
    per_source : tuple of int
        Nodes whose depth came from each source.
    blended : int
        Nodes in a blend zone (a source mixed with the ones below).
    snapped : int
        Nodes within a cell diagonal outside a source's data, given its
        nearest cell.
    land : int
        Nodes the rasters put on land (depth <= 0 m).
    land_treatment : str
        What those got (:data:`LAND_TREATMENTS`).
    tapered : int
        Nodes made shallower by a coastal taper (``"wet"``, ``"smooth"``).
    coast_cells : int
        Nodes with land and sea cells around them: with ``"wet"`` their depth
        is the mean of the wet cells alone; otherwise it mixes in land.
    took_wet : int
        Nodes on land in the rasters given the nearest wet cell's depth.
    land_values : int
        Sea nodes whose depth holds a land cell's value (0 with ``"wet"``,
        ``"nearest_sea"`` and ``"smooth"`` wherever a wet cell exists; the
        land and coast nodes with ``"min_depth"`` before the floor, and
        ``"keep"``).
    coarse : int
        Nodes at the coast (land cells around them) whose elements are
        smaller than their raster's cells: the raster cannot tell their
        depths apart.
    min_depth : float, optional
        The depth floor, metres; None for none.
    at_min_depth : int
        Nodes whose depth ends at exactly ``min_depth``, whatever the cause.
    at_min_depth_causes : dict of str to int
        Those nodes by cause (:data:`FLOOR_CAUSES`), adding up to
        ``at_min_depth``: ``"raised"`` sea nodes raised from shallower depths;
        ``"raised_on_land"`` nodes on land in the rasters (as ``land`` counts
        them) that the floor raised; ``"tapered"`` nodes tapered to it at the
        coast; ``"rasters"`` nodes whose depth from the rasters (or the slope
        limit) is ``min_depth`` itself. Empty without ``min_depth``.
    rules : ndarray of int8, shape (N,), optional
        What each node got, by :data:`RULES` (not in ``to_dict``): for
        ``figures/depth_rules.png``.
    """

    nodes: int
    method: str
    averaged: int
    nearest: int
    below_min_depth: int
    slope_limited: int
    min: float
    max: float
    sources: tuple[str, ...] = ()
    per_source: tuple[int, ...] = ()
    blended: int = 0
    snapped: int = 0
    land: int = 0
    land_treatment: str = "wet"
    tapered: int = 0
    coast_cells: int = 0
    took_wet: int = 0
    land_values: int = 0
    coarse: int = 0
    min_depth: float | None = None
    at_min_depth: int = 0
    at_min_depth_causes: dict[str, int] = field(default_factory=dict)
    rules: NDArray[np.int8] | None = field(
        default=None, repr=False, compare=False, metadata={"to_dict": False}
    )

    def summary(self) -> str:
        """Return a one-line summary, with the shares of the nodes."""
        shares = ", ".join(
            f"{name} {count:,}"
            for name, count in zip(self.sources, self.per_source, strict=True)
        )

        def share(count: int) -> str:
            return f"{count:,} ({count / max(self.nodes, 1):.1%})"

        return (
            f"depth at {self.nodes:,} nodes ({self.method}; {self.averaged:,} by cell "
            f"means): {self.min:.1f} to {self.max:.1f} m; by source: {shares}; "
            f"{self.blended:,} blended, {share(self.snapped)} within a cell of the "
            f"data, {self.nearest:,} outside every source took the nearest cell; "
            f"{share(self.land)} on land in the rasters ({self.land_treatment}: "
            f"{share(self.took_wet)} took the nearest wet cell, {self.tapered:,} "
            f"tapered), {share(self.coast_cells)} beside land cells; "
            f"{share(self.land_values)} hold land values; "
            f"{self._floor_summary(share)}; "
            f"{share(self.coarse)} at a coast finer than the raster; "
            f"{self.slope_limited:,} changed by the slope limit"
        )

    def _floor_summary(self, share: Callable[[int], str]) -> str:
        """Return the nodes at ``min_depth`` in all, then by cause."""
        if self.min_depth is None:
            return "no min_depth"
        causes = ", ".join(
            f"{share(self.at_min_depth_causes.get(cause, 0))} {label}"
            for cause, label in FLOOR_CAUSES.items()
        )
        return (
            f"{share(self.at_min_depth)} at min_depth {self.min_depth:g} m, "
            f"by cause: {causes}"
        )


def depth_at_nodes(
    mesh: Mesh,
    raster: xr.DataArray | DepthSources,
    *,
    positive: str = "up",
    method: str = "bilinear",
    min_depth: float | None = None,
    max_slope: float | None = None,
    outside: str = "error",
    land: str = "wet",
    land_distance: float | None = None,
    max_land_share: float | None = None,
    threads: int = 1,
) -> tuple[NDArray[np.float64], DepthReport]:
    """Interpolate bathymetry onto the nodes of a mesh.

    Parameters
    ----------
    mesh : Mesh
        The mesh; ``mesh.crs`` must be known.
    raster : xarray.DataArray or DepthSources
        One raster (dims ``("y", "x")``, 1-D cell-centre coordinates, a ``crs``
        attr, NaN for nodata, as :func:`coastmesh.io.read_raster` returns), or a
        stack of them in priority order.
    positive : {"up", "down"}
        A single raster's sign: ``"up"`` for elevations (GEBCO, ETOPO),
        ``"down"`` for depths. A stack carries its own.
    method : {"bilinear", "mean"}
        ``"mean"`` averages the valid cells within half the mean length of each
        node's edges where that covers more than one cell, and interpolates
        bilinearly elsewhere.
    min_depth : float, optional
        Depths below this (metres; e.g. 5 for a model without wetting and drying)
        are raised to it.
    max_slope : float, optional
        Largest ``|depth difference| / edge length`` along any mesh edge; deeper
        nodes are made shallower until it holds (:func:`limit_slope`).
    outside : {"error", "nearest"}
        Nodes beyond every source's cover (more than a cell diagonal from its
        data): an error, or the nearest valid cell on the Earth and a warning.
    land : {"wet", "min_depth", "nearest_sea", "smooth", "keep"}
        Nodes where the rasters say land, and nodes beside land cells
        (:data:`LAND_TREATMENTS`). ``"wet"``: a node reads the wet cells
        alone; a node with no wet cell around takes the nearest wet cell's
        depth ``d_w`` (at ``r`` metres), tapered to ``min_depth`` (if given) at
        the coast: ``min_depth + (d_w - min_depth) s / (s + r)``, with ``s``
        the distance to the nearest coast node. So the taper runs only across
        the strip the raster calls land, from the coast to the first wet cell,
        and every depth off that strip is the raster's own.
    land_distance : float, optional
        Metres; the width of the coastal taper of ``land="smooth"``.
    max_land_share : float, optional
        If more than this share of the nodes lies on land in the rasters (no
        wet cell around them), the rasters are too coarse for the coast: an
        :class:`InputDataError` that names them and gives the share. None for
        no limit (the caller chose ``land`` knowingly).
    threads : int, default 1
        With 2 or more, the nodes' element sizes (for the warning of a coarse
        raster) are measured on a side thread while the rasters are sampled.
        The result is the same.

    Returns
    -------
    depth : ndarray of shape (N,)
        Metres, positive down.
    report : DepthReport

    Raises
    ------
    ConfigError
        For a bad ``positive``, ``method``, ``min_depth``, ``max_slope``,
        ``outside``, ``land`` or ``land_distance``, or a mesh without a CRS.
    InputDataError
        If a source has no valid cell or covers no node, or nodes lie beyond
        every source with ``outside="error"``; the message names the sources,
        the share each covers and where the gap is. If more than
        ``max_land_share`` of the nodes lie on land in the rasters.

    Warns
    -----
    CoarseRasterWarning
        Where a raster's cells are larger than the elements at the coast
        (nodes with land cells around them): it names the raster, the share of
        nodes and where they are, and suggests a finer source.

    Examples
    --------
    >>> import xarray as xr
    >>> r = xr.DataArray([[-10.0, -20.0], [-30.0, -40.0]], dims=("y", "x"),
    ...                  coords={"y": [0.0, 1.0], "x": [0.0, 1.0]},
    ...                  attrs={"crs": "EPSG:4326"})
    >>> m = Mesh([[0.5, 0.5], [0.0, 0.0], [3.0, 0.0]], [[1, 2, 0]],
    ...          [[1, 2], [2, 0], [0, 1]], [1, 1, 1], 1, "EPSG:4326")
    >>> depth, report = depth_at_nodes(m, r, outside="nearest")
    >>> depth.tolist(), report.nearest
    ([25.0, 10.0, 20.0], 1)

    A cell of land (``5 m`` up) beside the sea: plain bilinear interpolation
    would pull the node up by the land's height, to ``(-5 + 10 + 20 + 30) / 4
    = 13.75`` m; the wet cells alone give it ``(10 + 20 + 30) / 3 = 20`` m.

    >>> r2 = r.copy(data=[[5.0, -10.0], [-20.0, -30.0]])
    >>> depth_at_nodes(m, r2, outside="nearest")[0].tolist()[0]
    20.0
    """
    _check_args(mesh, method, min_depth, outside, land, land_distance)
    sources = _stack(raster, positive)
    radius = _node_radius(mesh) if method == "mean" else None
    # else measured for the check of the coast, on a side thread if it can
    later = _aside(_node_radius, mesh) if radius is None and threads > 1 else None
    sample, plain, source = _sample(sources, mesh, radius, outside)
    gap = sample.uncovered
    wet = sources.sample(mesh.points, _crs(mesh), radius=radius, wet=True).depth
    wet[gap] = plain[gap]
    with np.errstate(invalid="ignore"):
        coast = (wet > 0) & (wet != plain)
    land_nodes = plain <= 0
    depth = np.where(np.isfinite(wet), wet, plain) if land == "wet" else plain
    dry = depth <= 0
    _check_land_share(sources, dry, max_land_share)
    depth, took_wet, tapered_nodes = _treat_land(
        mesh, sources, depth, dry, land, min_depth, land_distance
    )
    held = (dry & ~took_wet) | (coast if land != "wet" else False)
    if land == "min_depth" and min_depth is not None:
        held &= ~dry  # the floor replaced them
    depth, raised, limited = _floor_and_slope(mesh, depth, min_depth, max_slope)
    if later is not None:
        radius = later.result()
    coarse, radius = _coarse_at_coast(sources, mesh, source, coast | land_nodes, radius)
    rules = np.zeros(len(depth), dtype=np.int8)
    for code, where in enumerate(
        (coast & (land == "wet"), took_wet, tapered_nodes, raised, held, gap),
        start=1,
    ):
        rules[where] = code
    causes = _floor_causes(depth, min_depth, raised, land_nodes, tapered_nodes)
    report = DepthReport(
        nodes=len(depth),
        method=method,
        averaged=int(sample.averaged.sum()),
        nearest=int(gap.sum()),
        below_min_depth=int(raised.sum()),
        slope_limited=limited,
        min=float(depth.min()),
        max=float(depth.max()),
        sources=sources.names,
        per_source=tuple(int((source == k).sum()) for k in range(len(sources))),
        blended=int(sample.blended.sum()),
        snapped=int(sample.snapped.sum()),
        land=int(land_nodes.sum()),
        land_treatment=land,
        tapered=int(tapered_nodes.sum()),
        coast_cells=int(coast.sum()),
        took_wet=int(took_wet.sum()),
        land_values=int(held.sum()),
        coarse=int(coarse.sum()),
        min_depth=min_depth,
        at_min_depth=sum(causes.values()),
        at_min_depth_causes=causes,
        rules=rules,
    )
    if report.coarse:
        assert radius is not None  # measured: coarse nodes are at the coast
        warnings.warn(
            _coarse_message(sources, mesh, source, coarse, radius),
            CoarseRasterWarning,
            stacklevel=2,
        )
    return depth, report


def _floor_and_slope(
    mesh: Mesh,
    depth: NDArray[np.float64],
    min_depth: float | None,
    max_slope: float | None,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], int]:
    """Raise depths to ``min_depth``, then limit the slope.

    Returns the depths, the nodes raised, and the number of nodes the slope
    limit changed.
    """
    raised = np.zeros(len(depth), dtype=bool)
    if min_depth is not None:
        raised = depth < min_depth
        depth = np.maximum(depth, min_depth)
    limited = 0
    if max_slope is not None:
        limited_depth = limit_slope(mesh, depth, max_slope)
        limited = int((limited_depth != depth).sum())
        depth = limited_depth
    return depth, raised, limited


def _floor_causes(
    depth: NDArray[np.float64],
    min_depth: float | None,
    raised: NDArray[np.bool_],
    land: NDArray[np.bool_],
    tapered: NDArray[np.bool_],
) -> dict[str, int]:
    """Count the nodes that end at exactly ``min_depth``, by cause.

    The causes (:data:`FLOOR_CAUSES`) do not overlap: raised from a shallower
    sea depth, raised on land in the rasters (``land``), tapered to the floor,
    and the rest (the rasters' own depth, or the slope limit). Empty without a
    floor.
    """
    if min_depth is None:
        return {}
    at = depth == min_depth
    groups = {
        "raised": at & raised & ~land,
        "raised_on_land": at & raised & land,
        "tapered": at & ~raised & tapered,
        "rasters": at & ~raised & ~tapered,
    }
    return {cause: int(where.sum()) for cause, where in groups.items()}


def _sample(
    sources: DepthSources,
    mesh: Mesh,
    radius: NDArray[np.float64] | None,
    outside: str,
) -> tuple[SourceSample, NDArray[np.float64], NDArray[np.int64]]:
    """Sample the stack at the nodes; uncovered nodes by ``outside``.

    Returns the sample, the depths (plain bilinear, or cell means) and the
    source of each node.
    """
    crs = _crs(mesh)
    sample = sources.sample(mesh.points, crs, radius=radius)
    for name, hit, k in zip(
        sources.names, sample.hits, range(len(sources)), strict=True
    ):
        if hit == 0 and not (sample.source == k).any():
            raise InputDataError(
                f"bathymetry source {name} does not overlap the mesh: no node lies "
                "within its data (is it the right region and CRS?)"
            )
    plain, source = sample.depth.copy(), sample.source.copy()
    gap = sample.uncovered
    if gap.any():
        if outside == "error":
            raise InputDataError(
                sources.uncovered_message(sample, mesh.points, crs)
                + "; add a source that covers them, or set outside = 'nearest'"
            )
        plain[gap], source[gap], _ = sources.nearest(mesh.points[gap], crs)
        warnings.warn(
            sources.uncovered_message(sample, mesh.points, crs)
            + ": they took the nearest valid cell (outside = 'nearest')",
            CoastmeshWarning,
            stacklevel=3,
        )
    return sample, plain, source


def _treat_land(
    mesh: Mesh,
    sources: DepthSources,
    depth: NDArray[np.float64],
    dry: NDArray[np.bool_],
    land: str,
    min_depth: float | None,
    land_distance: float | None,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """Give the ``dry`` nodes their depth by the ``land`` rule.

    Returns the depths, the nodes that took the nearest wet cell, and the
    nodes tapered.
    """
    tapered = np.zeros(len(depth), dtype=bool)
    took_wet = np.zeros(len(depth), dtype=bool)
    if dry.any() and land in ("wet", "nearest_sea", "smooth"):
        value, _, distance = sources.nearest(mesh.points[dry], _crs(mesh), kind="wet")
        found = np.isfinite(value)
        took_wet[np.flatnonzero(dry)[found]] = True
        if land == "wet" and min_depth is not None:
            value, less = _taper_across(mesh, dry, value, distance, min_depth)
            tapered[np.flatnonzero(dry)] = less
        depth = depth.copy()
        depth[dry] = np.where(found, value, depth[dry])
    if land == "smooth":
        # _check_args refuses "smooth" without both
        assert min_depth is not None and land_distance is not None
        depth, tapered = _taper(mesh, depth, min_depth, land_distance)
    return depth, took_wet, tapered


class CoarseRasterWarning(CoastmeshWarning):
    """A bathymetry raster's cells are larger than the mesh's elements at the coast."""


def _check_land_share(
    sources: DepthSources, dry: NDArray[np.bool_], limit: float | None
) -> None:
    """Refuse rasters that put more than ``limit`` of the nodes on land."""
    share = float(dry.mean()) if len(dry) else 0.0
    if limit is None or share <= limit:
        return
    cells = ", ".join(
        f"{name} (cells of {cell / 1e3:.3g} km)"
        for name, cell in zip(sources.names, sources.cells_m, strict=True)
    )
    raise InputDataError(
        f"bathymetry: {dry.sum():,} of {len(dry):,} mesh nodes ({share:.0%}) lie on "
        f"land in {cells}, with no wet cell around them: the raster is too coarse "
        "for this coast. Add a finer source above it ([[bathymetry.sources]]: a "
        "survey, EMODnet or GEBCO), or set [bathymetry] land to say what those "
        "nodes get ('wet': the nearest wet cell)"
    )


def _taper_across(
    mesh: Mesh,
    dry: NDArray[np.bool_],
    value: NDArray[np.float64],
    distance: NDArray[np.float64],
    min_depth: float,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Taper the nearest wet depths of the ``dry`` nodes to ``min_depth`` at the coast.

    ``min_depth + (value - min_depth) * s / (s + r)``: ``s`` the distance to
    the nearest coast node, ``r`` (``distance``) to the wet cell. Only makes
    depths shallower, and only across the strip the raster calls land.
    """
    s = _coast_distance(mesh, np.flatnonzero(dry))
    if s is None:
        return value, np.zeros(len(value), dtype=bool)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(s + distance > 0, s / (s + distance), 1.0)
        deeper = np.isfinite(value) & (value > min_depth) & (t < 1.0)
    out = value.copy()
    out[deeper] = min_depth + (value[deeper] - min_depth) * t[deeper]
    return out, deeper


def _coast_nodes(mesh: Mesh) -> NDArray[np.int64]:
    """Return the nodes of the shoreline boundary edges (all, if no kinds)."""
    coast_ids = [k for k, kind in mesh.boundary_kinds.items() if kind == "shoreline"]
    on_coast = np.isin(mesh.boundary_ids, coast_ids)
    if not mesh.boundary_kinds:  # no kinds known: every boundary is coast
        on_coast[:] = True
    return np.unique(mesh.boundary_edges[on_coast])


def _coast_distance(mesh: Mesh, nodes: NDArray[np.int64]) -> NDArray[np.float64] | None:
    """Return the distances (metres, chords) from ``nodes`` to the coast."""
    coast = _coast_nodes(mesh)
    if coast.size == 0:
        return None
    xyz, _ = mesh_earth_centred(mesh)
    d: NDArray[np.float64]  # scipy is untyped here (no stubs among the dependencies)
    d, _ = cKDTree(xyz[coast]).query(xyz[nodes])
    return d


def _aside(fn: Callable[..., _R], *args: Any) -> Future[_R]:
    """Return the future of ``fn(*args)``, called on a thread of its own."""
    pool = ThreadPoolExecutor(1)
    future = pool.submit(fn, *args)
    pool.shutdown(wait=False)  # the call runs on; the thread ends after it
    return future


def _coarse_at_coast(
    sources: DepthSources,
    mesh: Mesh,
    source: NDArray[np.int64],
    at_coast: NDArray[np.bool_],
    radius: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.bool_], NDArray[np.float64] | None]:
    """Return the nodes beside land cells with elements finer than their cells.

    And each node's :func:`_node_radius` (``radius``, or measured here if it
    is needed and None), for :func:`_coarse_message`.
    """
    if not at_coast.any():
        return at_coast, radius
    radius = _node_radius(mesh) if radius is None else radius
    cells = np.asarray(sources.cells_m)[np.maximum(source, 0)]
    return at_coast & (source >= 0) & (COARSE_RATIO * (2.0 * radius) < cells), radius


def _coarse_message(
    sources: DepthSources,
    mesh: Mesh,
    source: NDArray[np.int64],
    coarse: NDArray[np.bool_],
    radius: NDArray[np.float64],
) -> str:
    """Name the coarse rasters, the share of nodes, where, and a finer source."""
    n = len(coarse)
    parts = []
    for k, (name, cell) in enumerate(zip(sources.names, sources.cells_m, strict=True)):
        mine = coarse & (source == k)
        if not mine.any():
            continue
        lon, lat = reproject_points(mesh.points[mine], mesh.crs, "EPSG:4326").T
        edge = 2.0 * float(np.median(radius[mine]))
        parts.append(
            f"bathymetry raster {name} (cells of {cell / 1e3:.3g} km) is coarser than "
            f"the mesh at the coast: {mine.sum():,} of {n:,} nodes ({mine.mean():.1%}) "
            f"with land cells around them have elements of {edge:,.0f} m (median), "
            f"at lon {lon.min():.3f} to {lon.max():.3f}, lat {lat.min():.3f} to "
            f"{lat.max():.3f}"
        )
    return (
        "; ".join(parts) + ". Their depths come from the wet cells near them, which "
        "cannot see channels and bays narrower than a cell: add a finer source "
        "above it as [[bathymetry.sources]] (a survey, EMODnet 1/16' ~ 115 m, GEBCO "
        '15" ~ 460 m) for true depths there'
    )


def node_sources(mesh: Mesh, raster: xr.DataArray | DepthSources) -> NDArray[np.int64]:
    """Return the index of the source each node's depth came from (-1: none)."""
    sources = _stack(raster, "up")
    crs = _crs(mesh)
    sample = sources.sample(mesh.points, crs)
    source = sample.source.copy()
    gap = sample.uncovered
    if gap.any():
        _, source[gap], _ = sources.nearest(mesh.points[gap], crs)
    return source


def _stack(raster: xr.DataArray | DepthSources, positive: str) -> DepthSources:
    if isinstance(raster, DepthSources):
        return raster
    if positive not in ("up", "down"):
        raise ConfigError(f"positive = {positive!r}: use 'up' or 'down'")
    return DepthSources([DepthSource(raster, positive)])


def _check_args(
    mesh: Mesh,
    method: str,
    min_depth: float | None,
    outside: str,
    land: str,
    land_distance: float | None,
) -> None:
    if method not in DEPTH_METHODS:
        raise ConfigError(f"method = {method!r}: use one of {DEPTH_METHODS}")
    if min_depth is not None and not np.isfinite(min_depth):
        raise ConfigError(f"min_depth = {min_depth}: not a finite number of metres")
    if outside not in OUTSIDE_RULES:
        raise ConfigError(f"outside = {outside!r}: use one of {OUTSIDE_RULES}")
    if land not in LAND_TREATMENTS:
        raise ConfigError(f"land = {land!r}: use one of {LAND_TREATMENTS}")
    if land == "keep" and min_depth is not None:
        raise ConfigError(
            f"land = 'keep' keeps the land heights as negative depths (for a model "
            f"that wets and dries); min_depth = {min_depth:g} would raise them: give "
            "one of the two"
        )
    if land == "smooth":
        if min_depth is None:
            raise ConfigError("land = 'smooth' tapers to min_depth: give min_depth")
        if land_distance is None or not (land_distance > 0):
            raise ConfigError(
                f"land_distance = {land_distance}: land = 'smooth' needs the width "
                "of the coastal taper, a distance > 0 m"
            )
    _crs(mesh)


def _crs(mesh: Mesh) -> CRS:
    """Return the mesh's CRS, which the depths are sampled in; raise without one."""
    if mesh.crs is None:
        raise ConfigError("the mesh has no CRS: give the CRS of its coordinates")
    return mesh.crs


def _taper(
    mesh: Mesh, depth: NDArray[np.float64], min_depth: float, width: float
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Taper depths within ``width`` of the coast to ``min_depth`` at the coast.

    ``depth = min_depth + (depth - min_depth) * d / width`` where ``d`` (metres,
    on the Earth) is the distance to the nearest coast node (the nodes of the
    boundary edges of kind ``"shoreline"``). Only makes depths shallower.
    """
    coast = _coast_nodes(mesh)
    if coast.size == 0:
        return depth, np.zeros(len(depth), dtype=bool)
    xyz, _ = mesh_earth_centred(mesh)
    d: NDArray[np.float64]  # scipy is untyped here (no stubs among the dependencies)
    d, _ = cKDTree(xyz[coast]).query(xyz, distance_upper_bound=width)
    near = np.isfinite(d) & (depth > min_depth)
    s = d[near] / width
    depth = depth.copy()
    depth[near] = min_depth + (depth[near] - min_depth) * s
    return depth, near


def limit_slope(
    mesh: Mesh, depth: NDArray[np.float64], max_slope: float
) -> NDArray[np.float64]:
    """Make deep nodes shallower until no mesh edge is steeper than ``max_slope``.

    The result is the largest field below ``depth`` with
    ``h(p) <= h(q) + max_slope * L(p, q)`` along every edge: the min-plus
    convolution over the mesh graph, ``h(p) = min_q depth(q) + s * dist(q, p)``,
    computed by one multi-source Dijkstra (scipy). Shallow water and the coast
    keep their depths; steep flanks are eased from the deep side.

    Parameters
    ----------
    mesh : Mesh
        The mesh (edge lengths are measured on the Earth).
    depth : ndarray of shape (N,)
        Depths, metres.
    max_slope : float
        Largest slope (dimensionless, > 0), e.g. 0.1.

    Returns
    -------
    ndarray of shape (N,)
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    if not (max_slope > 0 and np.isfinite(max_slope)):
        raise ConfigError(f"max_slope = {max_slope}: must be a number > 0")
    depth = np.asarray(depth, dtype=np.float64)
    edges, lengths = _edges_on_earth(mesh)
    n = len(depth)
    base = depth.min()
    # node n is a source joined to every node by its (shifted) depth
    rows = np.concatenate([edges[:, 0], edges[:, 1], np.full(n, n)])
    cols = np.concatenate([edges[:, 1], edges[:, 0], np.arange(n)])
    weights = np.concatenate(
        [max_slope * lengths, max_slope * lengths, depth - base + 1e-300]
    )
    graph = coo_matrix((weights, (rows, cols)), shape=(n + 1, n + 1)).tocsr()
    # scipy is untyped here (no stubs among the dependencies)
    limited: NDArray[np.float64] = dijkstra(graph, directed=True, indices=n)[:n] + base
    return np.minimum(limited, depth)


def _edges_on_earth(mesh: Mesh) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Return the unique edges and their lengths, metres (earth-centred chords)."""
    edges, _ = unique_edges(mesh.triangles, len(mesh.points))
    xyz, _ = mesh_earth_centred(mesh)
    return edges, np.linalg.norm(xyz[edges[:, 0]] - xyz[edges[:, 1]], axis=1)


def _node_radius(mesh: Mesh) -> NDArray[np.float64]:
    """Half the mean length of each node's edges, metres: its surrounding area."""
    edges, lengths = _edges_on_earth(mesh)
    n = len(mesh.points)
    total = np.bincount(edges.ravel(), np.repeat(lengths, 2), minlength=n)
    count = np.bincount(edges.ravel(), minlength=n)
    return 0.5 * total / np.maximum(count, 1)
