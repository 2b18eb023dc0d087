"""The first stages: the shoreline layer read, and each shoreline set built.

1. read the shoreline file (clip to ``bbox``; fill in a missing CRS), or contour
   the land from a raster (:mod:`~coastmesh.case.pipeline.dem_shorelines`);
2. build each shoreline set: full resolution, or a PCA reconstruction
   (:func:`~coastmesh.geometry.simplify_shorelines`, after
   :func:`~coastmesh.geometry.densify_long_edges`); drop land polygons and fill
   lakes below ``min_area``.

A global case builds its sets in the stereographic plane
(:mod:`~coastmesh.case.pipeline.world`), with the same functions.
"""

from __future__ import annotations

import logging
from typing import TypedDict

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig, ShorelineSetConfig
from coastmesh.case.pipeline.dem_shorelines import read_raster_land
from coastmesh.case.pipeline.state import (
    CaseRun,
    RunContext,
    Shorelines,
    ShorelineSetReport,
)
from coastmesh.errors import InputDataError
from coastmesh.geometry import (
    check_coordinates,
    densify_long_edges,
    land_polygons,
    reproject,
    simplify_shorelines,
    smaller_than,
)
from coastmesh.io import read_features
from coastmesh.types import Features, Progress

__all__ = [
    "build_shoreline_set",
    "fill_lakes",
    "read_shorelines",
    "regional_sets",
    "set_label",
]

logger = logging.getLogger(__name__)


class _PcaCounts(TypedDict, total=False):
    """What a PCA reconstruction adds to :class:`ShorelineSetReport`."""

    contours_in: int
    contours_dropped: int
    features_repaired: int


def read_shorelines(config: CaseConfig) -> tuple[Features, CRS]:
    """Read the land polygons of ``[shorelines]``, in the case CRS.

    With ``raster``, the land is contoured from the raster instead
    (:func:`~coastmesh.case.pipeline.dem_shorelines.read_raster_land`).

    Returns
    -------
    features : Features
        Land polygons, reprojected to the case CRS.
    crs : pyproj.CRS
        The case CRS: ``[case] crs``, else the file's.
    """
    s = config.shorelines
    if s.raster is not None:
        features = read_raster_land(config)
        assert features.crs is not None  # read_raster_land raises without one
        crs = CRS.from_user_input(config.crs) if config.crs else features.crs
        geometry = reproject(features.geometry, features.crs, crs)
        return Features(geometry, crs, {}, features.fids, features.path), crs
    assert s.path is not None  # _validate: a path or a raster
    features = read_features(s.path, layer=s.layer, bbox=s.bbox)
    file_crs = features.crs
    if file_crs is None:
        if s.crs is None:
            raise InputDataError(
                f"{s.path}: the file declares no CRS; set shorelines.crs in "
                f"{config.label}",
                path=str(s.path),
            )
        file_crs = CRS.from_user_input(s.crs)
        features = Features(
            features.geometry,
            file_crs,
            features.fields,
            features.fids,
            features.path,
            features.layer,
        )
    try:
        check_coordinates(features.geometry)
    except InputDataError as exc:
        fid = features.fids[exc.feature] if exc.feature is not None else None
        raise InputDataError(exc.message, path=str(s.path), feature=fid) from None
    features = land_polygons(features, purpose="the shoreline file")
    crs = CRS.from_user_input(config.crs) if config.crs else file_crs
    features = features.with_geometry(reproject(features.geometry, features.crs, crs))
    logger.info("shorelines: %d land polygons from %s", len(features), s.path)
    return features, crs


def build_shoreline_set(
    s: ShorelineSetConfig,
    features: Features,
    crs: CRS,
    min_area: float,
    progress: Progress | None = None,
    densified: NDArray[np.object_] | None = None,
    workers: int = 1,
) -> tuple[NDArray[np.object_], ShorelineSetReport]:
    """Build one shoreline set: full resolution or PCA, small land dropped.

    ``densified`` is ``densify_long_edges(features.geometry)`` if the caller
    has it already (it is the same for every PCA set of a case). The PCA runs
    on ``workers`` threads (the same result on any number).

    Returns
    -------
    land : ndarray of shapely Polygons
        The set's land polygons.
    report : ShorelineSetReport
    """
    points_in = int(shapely.get_num_coordinates(features.geometry).sum())
    pca: _PcaCounts = {}
    if s.window is None or s.modes is None:  # not s.pca
        land = features.geometry
    else:
        if densified is None:
            densified = densify_long_edges(features.geometry)
        land, done = simplify_shorelines(
            densified, s.window, s.modes, progress=progress, workers=workers
        )
        land = land[~shapely.is_missing(land)]
        points_in = done.points_in
        pca = {
            "contours_in": done.contours_in,
            "contours_dropped": done.contours_dropped,
            "features_repaired": done.repaired,
        }
    land = shapely.get_parts(land)
    land = land[shapely.get_type_id(land) == shapely.GeometryType.POLYGON]
    small = smaller_than(land, crs, min_area)
    land, lakes = fill_lakes(land[~small], crs, min_area)
    report = ShorelineSetReport(
        kind=s.label,
        points_in=points_in,
        polygons=int((~small).sum()),
        polygons_below_min_area=int(small.sum()),
        lakes_below_min_area=lakes,
        points_out=int(shapely.get_num_coordinates(land).sum()),
        **pca,
    )
    return land, report


def fill_lakes(
    land: NDArray[np.object_], crs: CRS, min_area: float
) -> tuple[NDArray[np.object_], int]:
    """Fill the holes (lakes) of land polygons that are smaller than ``min_area``.

    Parameters
    ----------
    land : ndarray of shapely Polygons
        In ``crs``.
    crs : pyproj.CRS
        Their CRS (areas are geodesic).
    min_area : float
        Square metres.

    Returns
    -------
    land : ndarray of shapely Polygons
        A new array; the input is unchanged.
    filled : int
        Lakes filled.
    """
    if min_area <= 0 or len(land) == 0:
        return land, 0
    holed = np.flatnonzero(shapely.get_num_interior_rings(land) > 0)
    filled = 0
    land = land.copy()
    for k in holed:
        polygon = land[k]
        lakes = np.array([shapely.Polygon(r) for r in polygon.interiors], dtype=object)
        keep = ~smaller_than(lakes, crs, min_area)
        if not keep.all():
            filled += int((~keep).sum())
            kept = [r for r, k_ in zip(polygon.interiors, keep, strict=True) if k_]
            land[k] = shapely.Polygon(polygon.exterior, kept)
    return land, filled


def set_label(s: ShorelineSetConfig) -> str:
    """Return the label a shoreline set is timed and logged under."""
    return f"shoreline set {s.name!r} ({s.label})"


def regional_sets(run: CaseRun, ctx: RunContext) -> Shorelines:
    """Read the shorelines and build every set, in the case CRS."""
    config = run.config
    with ctx.timed("reading shorelines"):
        features, crs = read_shorelines(config)
    sets, reports = {}, {}
    dense = None  # the coasts with long edges split: the same for every PCA set
    for s in config.sets:
        with ctx.timed(set_label(s)) as progress:
            if dense is None and s.pca:
                dense = densify_long_edges(features.geometry)
            sets[s.name], reports[s.name] = build_shoreline_set(
                s,
                features,
                crs,
                config.shorelines.min_area,
                progress,
                dense,
                workers=ctx.threads,
            )
        logger.info("%s: %s", set_label(s), reports[s.name].summary())
    return Shorelines(features, crs, sets, reports)
