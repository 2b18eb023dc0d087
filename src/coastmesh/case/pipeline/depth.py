"""The depth stage: depths at the nodes from ``[bathymetry]``, and the time step.

Bathymetry comes from one raster or a stack of them
(:class:`~coastmesh.depth.DepthSources`). Each raster is read only over the window
the mesh (or the size grid) needs, widened by the source's blend; ``bbox`` and
``region`` keep the cells whose centres lie inside them; sources with the same
explicit ``priority`` must not overlap. :func:`check_rasters` opens every raster
before any work, so a bad one fails in a second.

Two stages: :func:`depth_stage` puts the depths on the nodes (PCA-simplified
rasters if asked); :func:`time_step_stage` relieves the few elements that
throttle an explicit model's time step (``[cleanup] time_step``), and reads the
depth again at the nodes it moved.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import ArrayLike
from pyproj import CRS

from coastmesh.case.config import CaseConfig, NodeDepthConfig
from coastmesh.case.pipeline.farms import check_clearance, turbine_nodes
from coastmesh.case.pipeline.state import DepthRun, DepthState, MeshedRun, RunContext
from coastmesh.case.sources import DepthSourceConfig
from coastmesh.depth import DepthReport, DepthSource, DepthSources, depth_at_nodes
from coastmesh.depth.nodes import MAX_LAND_SHARE, node_sources
from coastmesh.depth.sources import check_blend, no_crs
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import METRES_PER_DEGREE, reproject
from coastmesh.io.rasters.raster_window import raster_extent, read_raster_around
from coastmesh.meshing import relieve_time_step
from coastmesh.types import Mesh, Progress

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "check_rasters",
    "depth_stage",
    "node_depths",
    "read_sources",
    "relief_due",
    "time_step_stage",
]

logger = logging.getLogger(__name__)


def depth_stage(run: MeshedRun, ctx: RunContext) -> DepthRun:
    """Put ``[bathymetry]``'s depths on the mesh's nodes (none without it)."""
    b, state = run.config.bathymetry, run.mesh
    if b is None:
        return run.with_depth(None)
    with ctx.timed("depth at the nodes") as progress:
        crs = state.mesh.crs
        assert crs is not None  # the case's meshes carry their CRS
        rasters = read_sources(b.stack, state.mesh.points, crs, progress)
        if b.window is not None and b.modes is not None:  # given together
            rasters = _simplified(rasters, b.window, b.modes)
        # the depth's warnings wait for the relief: they are about the final mesh
        with warnings.catch_warnings(record=relief_due(run.config)) as caught:
            if caught is not None:
                warnings.simplefilter("always", CoastmeshWarning)
            mesh, report = node_depths(b, state.mesh, rasters, progress, ctx.threads)
    if run.site:
        check_clearance(run.site, mesh)
    depth = DepthState(rasters, report, deferred=tuple(caught or ()))
    return replace(run, mesh=replace(state, mesh=mesh)).with_depth(depth)


def time_step_stage(run: DepthRun, ctx: RunContext) -> DepthRun:
    """Relieve the elements that throttle the time step; depth at moved nodes.

    The angles may not fall below Gmsh's own mesh's, the cleanup's bar.
    """
    config, state, depth = run.config, run.mesh, run.depth
    b = config.bathymetry  # not None with depths (and relief_due)
    if b is None or depth is None or not relief_due(config):
        return run
    cleanup = state.parts.cleanup
    assert cleanup is not None  # relief_due: the parts were cleaned
    courant = run.time_step
    with ctx.timed("time step") as progress:
        held = None
        if run.site:
            held = np.zeros(len(state.mesh.points), dtype=bool)
            held[turbine_nodes(run.site, state.mesh)] = True
        relieved, report = relieve_time_step(
            state.mesh,
            velocity=0.0 if courant is None else courant.velocity,
            keep_angles=(cleanup.min_angle_before, cleanup.min_angle_p1_before),
            held=held,
            threads=ctx.threads,
        )
        logger.info("time step: %s", report.summary())
        if not report.accepted:
            _give(depth.deferred)
            return replace(run, depth=replace(depth, relief=report, deferred=()))
        # the merged nodes took their pair's mean depth: read the rasters there
        # (its warnings, about this mesh, replace those held back)
        relieved, depth_report = node_depths(
            b, relieved, depth.rasters, progress, ctx.threads
        )
    return replace(
        run,
        mesh=replace(state, mesh=relieved),
        depth=replace(depth, report=depth_report, relief=report, deferred=()),
    )


def _give(deferred: Sequence[warnings.WarningMessage]) -> None:
    """Give the warnings held back, as they were first raised."""
    for w in deferred:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def relief_due(config: CaseConfig) -> bool:
    """Whether :func:`time_step_stage` relieves a case's mesh (it may move nodes)."""
    c = config.cleanup
    return config.bathymetry is not None and c.enabled and c.time_step


def node_depths(
    b: NodeDepthConfig,
    mesh: Mesh,
    rasters: DepthSources,
    progress: Progress,
    threads: int = 1,
) -> tuple[Mesh, DepthReport]:
    """Return ``mesh`` with ``depth`` at its nodes from ``rasters``, and the report."""
    depth, report = depth_at_nodes(
        mesh,
        rasters,
        positive=b.positive,
        method=b.method,
        min_depth=b.min_depth,
        max_slope=b.max_slope,
        outside=b.outside,
        land="wet" if b.land is None else b.land,
        land_distance=b.land_distance,
        max_land_share=MAX_LAND_SHARE if b.land is None else None,
        threads=threads,
    )
    progress(2, 2)
    logger.info("%s", report.summary())
    if len(rasters) > 1:
        return mesh.with_point_data(
            depth=depth, depth_source=node_sources(mesh, rasters)
        ), report
    return mesh.with_point_data(depth=depth), report


def _simplified(rasters: DepthSources, window: int, modes: int) -> DepthSources:
    """Each raster of the window read, approximated by PCA (the paper's section II)."""
    from coastmesh.pca import simplify_raster

    return DepthSources(
        [
            DepthSource(
                s.raster.copy(data=simplify_raster(s.raster.values, window, modes)),
                s.positive,
                s.blend,
                s.name,
            )
            for s in rasters.sources
        ]
    )


def read_sources(
    configs: Sequence[DepthSourceConfig],
    points: ArrayLike,
    crs: CRS | str,
    progress: Progress | None = None,
) -> DepthSources:
    """Read the sources (priority order) over the window ``points`` need."""
    _check_priorities(configs)
    sources = []
    for k, c in enumerate(configs):
        name = str(c.path)
        # widen by the blend and a little: the window's own frame must stay
        # farther than the blend from every point, or it would look like an edge
        raster = read_raster_around(
            c.path, points, crs, margin=2.0 * c.blend + 1e3, name=name
        )
        if c.bbox is not None:
            raster = _keep_inside(raster, shapely.box(*c.bbox), name, "bbox")
        if c.region is not None:
            raster = _keep_inside(raster, _region(c.region, raster), name, "region")
        sources.append(DepthSource(raster, c.positive, c.blend, name))
        if progress is not None:
            progress(k + 1, len(configs) + 1)
    return DepthSources(sources)


def check_rasters(config: CaseConfig) -> None:
    """Open every bathymetry raster of a case: readable, with a CRS, blend fits.

    Runs before the meshing, so that a bad raster fails in a second.
    """
    parts = [config.bathymetry, config.size.bathymetry]
    for part in (p for p in parts if p is not None):
        stack = part.stack
        _check_priorities(stack)
        for c in stack:
            _, wkt, _ = raster_extent(c.path)
            if wkt is None:
                raise no_crs(str(c.path))
            if c.blend > 0:
                box = _lonlat_box(c)
                lon0, lat0, lon1, lat1 = box.bounds
                mid = np.radians(0.5 * (lat0 + lat1))
                width = (lon1 - lon0) * METRES_PER_DEGREE * np.cos(mid)
                height = (lat1 - lat0) * METRES_PER_DEGREE
                check_blend(str(c.path), c.blend, width, height)


def _region(path: Path, raster: xr.DataArray) -> shapely.Geometry:
    """Return the union of the polygons of a vector file, in the raster's CRS."""
    from coastmesh.io import read_features

    features = read_features(path)
    polygons = [
        g
        for g in features.geometry
        if g is not None and g.geom_type in ("Polygon", "MultiPolygon")
    ]
    if not polygons:
        raise InputDataError(f"region {path}: holds no polygon")
    if features.crs is None or raster.attrs.get("crs") is None:
        raise InputDataError(f"region {path}: has no CRS")
    union = shapely.union_all(polygons)
    return reproject(union, features.crs, CRS.from_user_input(raster.attrs["crs"]))


def _keep_inside(
    raster: xr.DataArray, area: shapely.Geometry, name: str, key: str
) -> xr.DataArray:
    """NaN the cells whose centres lie outside ``area``; crop to its box."""
    x, y = raster.x.values, raster.y.values
    minx, miny, maxx, maxy = area.bounds
    cols = (x >= minx) & (x <= maxx)
    rows = (y >= miny) & (y <= maxy)
    if not cols.any() or not rows.any():
        raise InputDataError(
            f"bathymetry source {name}: its {key} holds none of the cells read "
            "(is it in the raster's CRS, and over the mesh?)"
        )
    cropped = raster.isel(x=np.flatnonzero(cols), y=np.flatnonzero(rows))
    gx, gy = np.meshgrid(cropped.x.values, cropped.y.values)
    shapely.prepare(area)
    inside = shapely.contains_xy(area, gx, gy)
    return cropped.where(inside)


def _check_priorities(configs: Sequence[DepthSourceConfig]) -> None:
    """Refuse overlapping sources of the same explicit priority (which wins?)."""
    by_priority: dict[int, list[DepthSourceConfig]] = {}
    for c in configs:
        if c.priority is not None:
            by_priority.setdefault(c.priority, []).append(c)
    for priority, same in by_priority.items():
        boxes = [_lonlat_box(c) for c in same]
        for i in range(len(same)):
            for j in range(i + 1, len(same)):
                if boxes[i].intersects(boxes[j]):
                    raise ConfigError(
                        f"bathymetry sources {same[i].path} and {same[j].path} have "
                        f"the same priority ({priority}) and overlap: give them "
                        "different priorities"
                    )


def _lonlat_box(c: DepthSourceConfig) -> shapely.Geometry:
    bounds, wkt, _ = raster_extent(c.path)
    if c.bbox is not None:
        b = c.bbox
        bounds = (
            max(bounds[0], b[0]),
            max(bounds[1], b[1]),
            min(bounds[2], b[2]),
            min(bounds[3], b[3]),
        )
    box = shapely.box(*bounds)
    if wkt is None:
        raise no_crs(str(c.path))
    return reproject(box.segmentize(box.length / 400), CRS.from_wkt(wkt), "EPSG:4326")
