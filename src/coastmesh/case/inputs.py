"""The first stages of a case: shorelines, shoreline sets, open boundaries, domain.

1. read the shoreline file (clip to ``bbox``; fill in a missing CRS), or contour
   the land from a raster (:mod:`~coastmesh.case.dem_shorelines`);
2. build each shoreline set: full resolution, or a PCA reconstruction
   (:func:`~coastmesh.geometry.simplify_shorelines`, after
   :func:`~coastmesh.geometry.densify_long_edges`); drop land polygons and fill
   lakes below ``min_area``;
3. stitch the sets by region (:func:`~coastmesh.geometry.stitch_shorelines`),
   draw the open boundaries (loxodromes, blends, great circles, polylines) and
   build the domain (:func:`~coastmesh.geometry.build_domain`).
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.boundaries import BoundaryConfig
from coastmesh.case.config import CaseConfig, RegionConfig, ShorelineSetConfig
from coastmesh.case.config.case import boundary_key
from coastmesh.case.dem_shorelines import read_raster_land
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry import (
    DomainReport,
    OpenBoundary,
    ShorelineSet,
    StitchReport,
    build_domain,
    check_coordinates,
    densify_long_edges,
    land_polygons,
    reproject,
    simplify_shorelines,
    smaller_than,
    stitch_shorelines,
)
from coastmesh.io import read_features
from coastmesh.types import Domain, Features, Progress, Report

__all__ = [
    "DomainInputs",
    "ShorelineSetReport",
    "bathymetry_terms",
    "build_case_domain",
    "build_shoreline_set",
    "depth_stack",
    "fill_lakes",
    "read_shorelines",
    "region_geometry",
]

logger = logging.getLogger(__name__)

_LONLAT = CRS.from_epsg(4326)


@dataclass(frozen=True, slots=True)
class ShorelineSetReport(Report):
    """What building one shoreline set did.

    Attributes
    ----------
    kind : str
        ``"full resolution"`` or ``"PCA m modes / L points"``.
    points_in : int
        Vertices of the shoreline layer.
    contours_in, contours_dropped, features_repaired : int or None
        For a PCA set: rings in, rings shorter than the window, and polygons
        repaired after smoothing (:class:`~coastmesh.geometry.ShorelineReport`).
    polygons : int
        Land polygons kept.
    polygons_below_min_area, lakes_below_min_area : int
        Islands dropped and lakes filled for being below ``min_area``.
    points_out : int
        Vertices of the set.
    """

    kind: str
    points_in: int
    polygons: int
    polygons_below_min_area: int
    lakes_below_min_area: int
    points_out: int
    contours_in: int | None = None
    contours_dropped: int | None = None
    features_repaired: int | None = None

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.kind}, {self.polygons} polygons ({self.polygons_below_min_area} "
            f"islands and {self.lakes_below_min_area} lakes below min_area dropped), "
            f"{self.points_out:,} points"
        )


@dataclass(frozen=True, slots=True)
class DomainInputs:
    """What stage 3 made: the domain and what was drawn on the way."""

    domain: Domain
    domain_report: DomainReport
    stitch_report: StitchReport
    regions: list[tuple[str, int, shapely.Geometry | None]]
    open_boundaries: list[OpenBoundary]
    #: the stitched land, before any closed water was added to it
    land: Any = None


def read_shorelines(config: CaseConfig) -> tuple[Features, CRS]:
    """Read the land polygons of ``[shorelines]``, in the case CRS.

    With ``raster``, the land is contoured from the raster instead
    (:func:`~coastmesh.case.dem_shorelines.read_raster_land`).

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
        crs = CRS.from_user_input(config.crs) if config.crs else features.crs
        geometry = reproject(features.geometry, features.crs, crs)
        return Features(geometry, crs, {}, features.fids, features.path), crs
    features = read_features(s.path, layer=s.layer, bbox=s.bbox)
    if features.crs is None:
        if s.crs is None:
            raise InputDataError(
                f"{s.path}: the file declares no CRS; set shorelines.crs in "
                f"{config.label}",
                path=str(s.path),
            )
        features = Features(
            features.geometry,
            CRS.from_user_input(s.crs),
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
    crs = CRS.from_user_input(config.crs) if config.crs else features.crs
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
) -> tuple[NDArray[np.object_], ShorelineSetReport]:
    """Build one shoreline set: full resolution or PCA, small land dropped.

    ``densified`` is ``densify_long_edges(features.geometry)`` if the caller
    has it already (it is the same for every PCA set of a case).

    Returns
    -------
    land : ndarray of shapely Polygons
        The set's land polygons.
    report : ShorelineSetReport
    """
    points_in = int(shapely.get_num_coordinates(features.geometry).sum())
    pca: dict[str, Any] = {}
    if not s.pca:
        land = features.geometry
    else:
        if densified is None:
            densified = densify_long_edges(features.geometry)
        land, done = simplify_shorelines(
            densified, s.window, s.modes, progress=progress
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


def build_case_domain(
    config: CaseConfig,
    sets: dict[str, NDArray[np.object_]],
    crs: CRS,
    *,
    closed: NDArray[np.object_] | None = None,
    lonlat: CRS | None = None,
    stitched: DomainInputs | None = None,
) -> DomainInputs:
    """Stitch the sets by region, draw the open boundaries, build the domain.

    ``closed``: polygons of water to take out of the domain as land (narrow
    channels closed by the channel term); their edges take the shoreline set
    of the region they lie in. ``lonlat``: the CRS the case's region boxes,
    polygons and seed are given in, when it is not ``crs`` (a global case,
    built in the stereographic plane). ``stitched``: what an earlier call with
    the same case, sets and CRSs returned; its stitched shorelines are used
    again instead of stitched anew (2 s of the NW-shelf fine case's 4 s).
    """
    if stitched is not None:
        land, tagged, stitch_report = (
            stitched.land, stitched.regions, stitched.stitch_report
        )  # fmt: skip
    else:
        land, tagged, stitch_report = _stitch(config, sets, crs, lonlat)
    spacing = min(1000.0, config.size.h_max / 4)  # a quarter of h_max, <= 1 km
    walls = [
        OpenBoundary(
            _boundary_coords(b, k, crs, spacing, config), b.name, b.physical_id
        )
        for k, b in enumerate(config.boundaries)
    ]
    stitched_land = land
    if closed is not None and len(closed):
        land = np.concatenate([np.asarray(land, dtype=object), closed])
    try:
        domain, report = build_domain(
            land,
            walls,
            crs=crs,
            seed=_seed(config, crs, lonlat),
            min_area=config.shorelines.min_area,
            surface_id=config.domain.surface_id,
            shorelines=tagged,
        )
    except ConfigError as exc:
        raise ConfigError(f"{config.label}: domain: {exc}") from None
    missing = [b.name for b in walls if b.name not in report.segments]
    if missing:
        warnings.warn(
            f"{config.label}: open boundaries {missing} do not reach the domain "
            "(they do not close the sea region that holds the seed)",
            CoastmeshWarning,
            stacklevel=3,
        )
    logger.info("domain: %s; %s", report.summary(), stitch_report.summary())
    return DomainInputs(domain, report, stitch_report, tagged, walls, stitched_land)


def _stitch(
    config: CaseConfig,
    sets: dict[str, NDArray[np.object_]],
    crs: CRS,
    lonlat: CRS | None,
) -> tuple[Any, list[tuple[str, int, shapely.Geometry | None]], StitchReport]:
    """Stitch the shoreline sets by region: land, regions by set, report."""
    regions: dict[str, list[shapely.Geometry]] = {}
    for k, r in enumerate(config.regions):
        region = region_geometry(r, k, crs, config)
        if lonlat is not None and r.path is None:  # a box or polygon in lon/lat
            region = reproject(shapely.segmentize(region, 0.1), lonlat, crs)
        regions.setdefault(r.set, []).append(region)
    ordered = list(dict.fromkeys(r.set for r in config.regions))
    ordered.append(config.background_set.name)
    ids = {s.name: s.physical_id for s in config.sets}
    shoreline_sets = [
        ShorelineSet(
            name,
            sets[name],
            ids[name],
            shapely.union_all(regions[name]) if name in regions else None,
        )
        for name in ordered
    ]
    land, tagged, stitch_report = stitch_shorelines(
        shoreline_sets, crs=crs, tolerance=config.domain.seam_tolerance
    )
    return land, tagged, stitch_report


def bathymetry_terms(b: Any, domain: Any = None) -> Any:
    """``[mesh_size.bathymetry]`` as :class:`~coastmesh.sizing.BathymetrySize`.

    With ``domain``, the sources are read over its box only (a stack); without
    (the world grid), the one raster whole.
    """
    from coastmesh.sizing import BathymetrySize

    return BathymetrySize(
        depth_stack(b, domain),
        positive=b.positive,
        per_wavelength=b.per_wavelength,
        period=b.period,
        per_slope=b.per_slope,
        min_depth=b.min_depth,
    )


def depth_stack(b: Any, domain: Any = None) -> Any:
    """Read the rasters of a ``[bathymetry]``-like part over ``domain``'s box.

    Without ``domain`` (the world), the single raster is read whole.
    """
    from coastmesh.case.sources import read_sources
    from coastmesh.io import read_raster

    if domain is None:
        if b.sources:
            raise ConfigError(
                "mesh_size.bathymetry.sources: a global case takes one raster for "
                "its size terms; give path"
            )
        return read_raster(b.path)
    ring = shapely.segmentize(domain.polygon.exterior, domain.polygon.length / 400)
    return read_sources(b.stack, shapely.get_coordinates(ring), domain.crs)


def _seed(config: CaseConfig, crs: CRS, lonlat: CRS | None) -> Any:
    seed = config.domain.seed
    if seed is None or lonlat is None:
        return seed
    point = reproject(shapely.Point(seed), lonlat, crs)
    return (point.x, point.y)


def region_geometry(
    r: RegionConfig, k: int, crs: CRS, config: CaseConfig
) -> shapely.Geometry:
    """Return ``[[regions]]`` entry ``k`` as a geometry (a file's in ``crs``)."""
    if r.box is not None:
        return shapely.box(*r.box)
    if r.polygon is not None:
        polygon = shapely.Polygon(r.polygon)
        if not polygon.is_valid:
            raise ConfigError(
                f"{config.label}: regions[{k}].polygon is not a valid polygon "
                f"({shapely.is_valid_reason(polygon)})"
            )
        return polygon
    features = read_features(r.path, layer=r.layer)
    geometry = features.geometry[~shapely.is_missing(features.geometry)]
    polygonal = shapely.get_dimensions(geometry) == 2
    if not polygonal.any():
        raise InputDataError(
            f"{r.path}: regions[{k}] needs polygons; the file has none",
            path=str(r.path),
        )
    region = shapely.union_all(shapely.make_valid(geometry[polygonal]))
    return region if features.crs is None else reproject(region, features.crs, crs)


def _boundary_coords(
    b: BoundaryConfig, k: int, crs: CRS, spacing: float, config: CaseConfig
) -> NDArray[np.float64]:
    where = f"{config.label}: {boundary_key(config.domain)}[{k}] ({b.name!r})"
    try:
        return b.line(crs, b.spacing or spacing)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    except InputDataError as exc:
        raise InputDataError(f"{where}: {exc.message}", path=exc.path) from None
