"""The domain: shoreline sets stitched by region, open boundaries, the sea.

:func:`build_case_domain` stitches the sets by region
(:func:`~coastmesh.geometry.stitch_shorelines`), draws the open boundaries
(each kind draws itself: :mod:`coastmesh.case.boundaries`) and builds the domain
(:func:`~coastmesh.geometry.build_domain`); :func:`with_land` makes water
closed as land (narrow channels, slots) part of it: the sea is cut and tagged
again, as building it again from the same stitched shorelines would give.
"""

from __future__ import annotations

import logging
import warnings
from collections.abc import Callable, Mapping
from dataclasses import replace

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.boundaries import BoundaryConfig
from coastmesh.case.config import CaseConfig, RegionConfig, SiteConfig
from coastmesh.case.config.case import boundary_key
from coastmesh.case.pipeline.places import file_place
from coastmesh.case.pipeline.state import DomainState
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry import (
    DomainReport,
    OpenBoundary,
    ShorelineSet,
    StitchReport,
    build_domain,
    domain_with_land,
    reproject,
    stitch_shorelines,
)
from coastmesh.io import read_features
from coastmesh.types import Domain

__all__ = [
    "CheckWalls",
    "Place",
    "Region",
    "as_given",
    "build_case_domain",
    "case_region",
    "region_geometry",
    "with_land",
]

logger = logging.getLogger(__name__)

#: Where a shoreline set is used: its name, its id and its region (None: the rest).
Region = tuple[str, int, shapely.Geometry | None]
#: Puts a box, polygon or point given in a case file (a region's box or
#: polygon, the seed) into the CRS the domain is built in.
Place = Callable[[shapely.Geometry], shapely.Geometry]
#: Checks the open boundaries as drawn against the stitched land, before the
#: domain is built; raises :class:`~coastmesh.errors.ConfigError`.
CheckWalls = Callable[[tuple[OpenBoundary, ...], NDArray[np.object_]], None]


def as_given(geometry: shapely.Geometry) -> shapely.Geometry:
    """Return ``geometry`` as it is: a case's places given in its domain's CRS."""
    return geometry


def build_case_domain(
    config: CaseConfig,
    sets: Mapping[str, NDArray[np.object_]],
    crs: CRS,
    *,
    mesh_crs: CRS,
    output_crs: CRS,
    place: Place = as_given,
    check_walls: CheckWalls | None = None,
) -> DomainState:
    """Stitch the sets by region, draw the open boundaries, build the domain.

    ``crs`` is the CRS the sets are in and the domain is built in. The case's
    strategy says what differs: ``place`` puts the region boxes, polygons and
    the seed into ``crs`` (a global case gives them in lon/lat and builds in
    the stereographic plane); ``check_walls`` checks the open boundaries
    against the land first (a global case's ``[[cuts]]`` run land to land).
    """
    land, regions, stitch_report = _stitch(config, sets, crs, place)
    spacing = min(1000.0, config.size.h_max / 4)  # a quarter of h_max, <= 1 km
    walls = tuple(
        OpenBoundary(
            _boundary_coords(b, k, crs, spacing, config), b.name, b.physical_id
        )
        for k, b in enumerate(config.boundaries)
    )
    if check_walls is not None:
        check_walls(walls, land)
    seed = _seed(config, place)
    domain, report = _domain(config, land, walls, regions, crs, seed)
    logger.info("domain: %s; %s", report.summary(), stitch_report.summary())
    return DomainState(
        domain,
        report,
        stitch_report,
        tuple(regions),
        walls,
        land,
        mesh_crs,
        output_crs,
        seed=seed,
    )


def with_land(
    state: DomainState, config: CaseConfig, closed: NDArray[np.object_]
) -> DomainState:
    """Return the state with ``closed`` (polygons of water) made land.

    The domain's sea less ``closed``, with its boundary tagged again
    (:func:`~coastmesh.geometry.domain_with_land`, the same as building it again
    from the stitched shorelines with ``closed`` added to their land, without
    the whole coast again): the closed polygons' edges take the shoreline set
    of the region they lie in. ``closed`` need hold only what is new: the
    domain already lacks what was closed before.
    """
    try:
        domain, report = domain_with_land(
            state.domain,
            closed,
            list(state.open_boundaries),
            state.report,
            seed=state.seed,
            min_area=config.shorelines.min_area,
            shorelines=list(state.regions),
            land=state.land,
            keep=[polygon for _, _, polygon in state.structures],
        )
    except (ConfigError, InputDataError) as exc:
        raise type(exc)(f"{config.label}: domain: {exc}") from None
    return replace(state, domain=domain, report=report)


def _domain(
    config: CaseConfig,
    land: NDArray[np.object_],
    walls: tuple[OpenBoundary, ...],
    regions: list[Region],
    crs: CRS,
    seed: tuple[float, float] | None,
) -> tuple[Domain, DomainReport]:
    """Build the domain; warn of open boundaries that do not reach it."""
    try:
        domain, report = build_domain(
            land,
            list(walls),
            crs=crs,
            seed=seed,
            min_area=config.shorelines.min_area,
            surface_id=config.domain.surface_id,
            shorelines=regions,
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
    return domain, report


def _stitch(
    config: CaseConfig,
    sets: Mapping[str, NDArray[np.object_]],
    crs: CRS,
    place: Place,
) -> tuple[NDArray[np.object_], list[Region], StitchReport]:
    """Stitch the shoreline sets by region: land, regions by set, report."""
    regions: dict[str, list[shapely.Geometry]] = {}
    for k, r in enumerate(config.regions):
        regions.setdefault(r.set, []).append(case_region(r, k, crs, config, place))
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


def _seed(config: CaseConfig, place: Place) -> tuple[float, float] | None:
    """Return ``[domain] seed`` in the domain's CRS; None without one."""
    seed = config.domain.seed
    if seed is None:
        return None
    point = place(shapely.Point(seed))
    return (point.x, point.y)


def site_area(config: CaseConfig, crs: CRS) -> shapely.Geometry | None:
    """Return the union of the ``[[sites]]`` and farms in ``crs``; None without.

    Boxes and polygons are lon/lat; a file's polygons are in the file's CRS.
    A farm is meshed finely on purpose, as a site is: the closing keeps the
    water it lies in, and the Courant floor does not apply inside it.
    """
    if not (config.sites or config.farms):
        return None
    lonlat = CRS.from_epsg(4326)
    parts = []
    for k, site in enumerate(config.sites):
        area = region_geometry(site, k, crs, config, table="sites")
        if site.path is None:
            area = reproject(shapely.segmentize(area, 0.01), lonlat, crs)
        parts.append(area)
    for k, farm in enumerate(config.farms):
        if farm.polygon is not None:
            parts.append(reproject(shapely.Polygon(farm.polygon), lonlat, crs))
        else:
            where = f"{config.label}: farms[{k}] ({farm.name!r})"
            assert farm.path is not None  # _validate: a polygon or a path
            parts.append(
                file_place(farm.path, farm.layer, crs, where, dimension=2, what="farm")
            )
    return shapely.union_all(parts)


def case_region(
    r: RegionConfig, k: int, crs: CRS, config: CaseConfig, place: Place
) -> shapely.Geometry:
    """Return ``[[regions]]`` entry ``k`` in ``crs``: a box or polygon placed.

    A box or polygon is given as ``place`` takes it; a file's polygons are
    read into ``crs`` (:func:`region_geometry`).
    """
    region = region_geometry(r, k, crs, config)
    return region if r.path is not None else place(region)


def region_geometry(
    r: RegionConfig | SiteConfig,
    k: int,
    crs: CRS,
    config: CaseConfig,
    table: str = "regions",
) -> shapely.Geometry:
    """Return ``[[regions]]`` (or ``[[sites]]``) entry ``k`` as a geometry.

    A box or polygon as given; a file's polygons in ``crs``.
    """
    if r.box is not None:
        return shapely.box(*r.box)
    if r.polygon is not None:
        polygon = shapely.Polygon(r.polygon)
        if not polygon.is_valid:
            raise ConfigError(
                f"{config.label}: {table}[{k}].polygon is not a valid polygon "
                f"({shapely.is_valid_reason(polygon)})"
            )
        return polygon
    assert r.path is not None  # _validate: one of box, polygon and path
    features = read_features(r.path, layer=r.layer)
    geometry = features.geometry[~shapely.is_missing(features.geometry)]
    polygonal = shapely.get_dimensions(geometry) == 2
    if not polygonal.any():
        raise InputDataError(
            f"{r.path}: {table}[{k}] needs polygons; the file has none",
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
