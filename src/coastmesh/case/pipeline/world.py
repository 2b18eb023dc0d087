"""Global cases: ``[domain] kind = "global"``, the whole world ocean in one mesh.

The stages of a regional case, with these steps done the global way
(:class:`Global`):

1. the world shoreline layer (lon/lat) goes into the stereographic plane whose
   singular point is ``[domain] pole`` (:func:`coastmesh.geometry.world_land`):
   halves split at the antimeridian joined, the polar land (Antarctica) a frame
   round the rest;
2. the shoreline sets (PCA, ``min_area``) are made in that plane, by region as
   in a regional case (region boxes are in lon/lat); the polar coast takes the
   background set's PCA; water and land narrower than ``[domain] close`` are
   closed (:func:`coastmesh.geometry.close_narrow_water`), so the coast can be
   resolved at the gradations' sizes;
3. the size field lives on a world lon/lat grid
   (:class:`~coastmesh.sizing.grid.SphereGrid`): gradations by great-circle
   distance from the sets, the tidal-wavelength term, the gradation limit on
   the sphere; the size terms read their raster whole;
4. Gmsh meshes the ocean in the plane with the sizes scaled by the plane's
   scale factor (:class:`~coastmesh.meshing.gmsh.SphereSizeGrid`), in parts
   as a regional case is (``[mesh] parts``): cuts straight in the plane;
5. the nodes go back to lon/lat; depths, time step and quality follow as in a
   regional case.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import warnings

import numpy as np
import shapely
import xarray as xr
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig, RasterConfig, ShorelineSetConfig
from coastmesh.case.pipeline.domain import Place, build_case_domain, case_region
from coastmesh.case.pipeline.shorelines import (
    build_shoreline_set,
    read_shorelines,
    set_label,
)
from coastmesh.case.pipeline.state import (
    CaseRun,
    ChangedIsland,
    ClosingReport,
    DomainRun,
    DomainState,
    RunContext,
    ShorelineRun,
    Shorelines,
    ShorelineSetReport,
    SizedRun,
)
from coastmesh.case.pipeline.strategy import Strategy
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry import OpenBoundary, simplify_shorelines
from coastmesh.geometry.closing import (
    close_narrow_water,
    earth_areas,
    island_changes,
)
from coastmesh.geometry.earth import (
    EARTH_RADIUS,
    METRES_PER_DEGREE,
    reproject,
    reproject_points,
)
from coastmesh.geometry.sphere import plane_crs, plane_scale
from coastmesh.geometry.world import WorldLand, geos_errors_named, world_land
from coastmesh.io import read_raster
from coastmesh.meshing.gmsh import SphereSizeGrid
from coastmesh.sizing.grid import SphereGrid
from coastmesh.types import Features, SizeGrid

__all__ = ["DEFAULT_CELL_DEG", "Global", "closing_width", "kept_area"]

logger = logging.getLogger(__name__)

#: The world size grid's spacing unless ``[mesh_size] cell`` sets one: 0.25
#: degrees, 1441 x ~680 nodes. Gmsh holds the grid's cells as its background
#: view, 128 bytes a cell: 0.1 degrees would be 800 MB.
DEFAULT_CELL_DEG = 0.25


class Global(Strategy):
    """A global case: the world ocean, meshed in a stereographic plane."""

    on_sphere = True

    def shorelines(self, run: CaseRun, ctx: RunContext) -> Shorelines:
        """Read the world layer, put it in the plane, build the sets there."""
        config = run.config
        with ctx.timed("reading shorelines"):
            features, crs = read_shorelines(config)
        _check_lonlat(config, crs)
        named = geos_errors_named(
            str(config.shorelines.path), plane_crs(config.domain.pole)
        )
        with ctx.timed("the world in the plane"), named:
            world = _world(config, features, crs)
        _check_seed(config, world, crs)
        _warn_near_pole(config, world, crs)
        plane = world.crs
        islands = Features(
            world.islands,
            plane,
            {},
            np.arange(len(world.islands)),
            features.path,
            features.layer,
        )
        sets, reports = {}, {}
        for s in config.sets:
            named = geos_errors_named(str(config.shorelines.path), plane)
            with ctx.timed(set_label(s)) as progress, named:
                land, reports[s.name] = build_shoreline_set(
                    s, islands, plane, kept_area(config), progress, workers=ctx.threads
                )
                sets[s.name], reports[s.name] = _closed(
                    config, s, world, land, reports[s.name], crs, ctx.threads
                )
        return Shorelines(features, crs, sets, reports, world=world)

    def domain(self, run: ShorelineRun, ctx: RunContext) -> DomainState:
        """Build the ocean in the plane; mesh there, write in lon/lat."""
        config, shorelines = run.config, run.shorelines
        plane = plane_crs(config.domain.pole)  # the world land's (world_land)
        lonlat = shorelines.crs
        named = geos_errors_named(str(config.shorelines.path), plane)
        with ctx.timed("building the domain"), named:
            return build_case_domain(
                config,
                shorelines.sets,
                plane,
                mesh_crs=plane,
                output_crs=CRS.from_user_input(config.mesh.output_crs or lonlat),
                place=_from_lonlat(lonlat, plane),
                check_walls=lambda walls, land: _check_cut_ends(
                    config, walls, land, plane, lonlat
                ),
            )

    def grid(self, run: DomainRun, ctx: RunContext) -> SphereGrid:
        """Return the world lon/lat grid, from below the ocean's southernmost point."""
        size, state = run.config.size, run.domain
        cell = DEFAULT_CELL_DEG if size.cell is None else size.cell / METRES_PER_DEGREE
        exterior = state.domain.polygon.exterior
        south = reproject(exterior, state.domain.crs, run.shorelines.crs).bounds[1]
        return SphereGrid(
            cell,
            south=max(math.floor(south - 2 * cell), -90.0),
            domain=state.domain,
            pole=_pole(run.config),
        )

    def read_depth(self, run: DomainRun, part: RasterConfig) -> xr.DataArray:
        """Read the one raster whole (a world grid)."""
        if part.sources:
            raise ConfigError(
                "mesh_size.bathymetry.sources: a global case takes one raster for "
                "its size terms; give path"
            )
        assert part.path is not None  # _validate: path or sources
        return read_raster(part.path)

    def size_grid(self, run: SizedRun) -> SphereSizeGrid:
        """Return the field on the lon/lat grid, scaled to the plane when sampled."""
        xy = shapely.get_coordinates(run.domain.domain.polygon.exterior)
        return SphereSizeGrid(
            SizeGrid.from_dataarray(run.size.field),
            _pole(run.config),
            reach=float(np.hypot(xy[:, 0], xy[:, 1]).max()),
        )


def _pole(config: CaseConfig) -> tuple[float, float]:
    """Return ``[domain] pole`` (lon, lat), as the world land holds it.

    The plane and its singular point are the case's
    (:func:`~coastmesh.geometry.world_land` makes the plane of this pole), so
    the domain and the grids take them from the config, not from the
    shorelines' world land (None in a regional case).
    """
    lon, lat = config.domain.pole
    return float(lon), float(lat)


def _from_lonlat(lonlat: CRS, plane: CRS) -> Place:
    """Return what puts a box, polygon or point given in lon/lat into the plane.

    Segmentized every 0.1 degrees first, so that its edges bend as the
    plane bends them.
    """

    def place(geometry: shapely.Geometry) -> shapely.Geometry:
        return reproject(shapely.segmentize(geometry, 0.1), lonlat, plane)

    return place


def _check_cut_ends(
    config: CaseConfig,
    walls: tuple[OpenBoundary, ...],
    land: NDArray[np.object_],
    crs: CRS,
    lonlat: CRS,
) -> None:
    """Raise unless both ends of every ``[[cuts]]`` line lie on land.

    A cut takes a sea off the world ocean only if it runs from land to land;
    one that ends in the water would close nothing and be left out.
    """
    if not walls:
        return
    tree = shapely.STRtree(land)
    for k, wall in enumerate(walls):
        ends = shapely.points(wall.coords[[0, -1]])
        for which, end in zip(("start", "end"), ends, strict=True):
            if len(tree.query(end, "within")):
                continue
            lon, lat = reproject(end, crs, lonlat).coords[0]
            raise ConfigError(
                f"{config.label}: cuts[{k}] ({wall.name!r}): its {which} "
                f"({lon:.4f}, {lat:.4f}) is in the water, not on land: a cut must "
                "run from land to land, across the sea it takes off"
            )


def _check_seed(config: CaseConfig, world: WorldLand, lonlat: CRS) -> None:
    """Raise now, not after the sets and the closing, if the seed is on land.

    Land is the polar land and every island of :func:`kept_area` or more (the
    smaller ones are dropped, so a seed on one is in the sea).
    """
    seed = config.domain.seed
    if seed is None:
        return
    point = reproject(shapely.Point(seed), lonlat, world.crs)
    where = f"{config.label}: domain.seed = [{seed[0]:g}, {seed[1]:g}] (lon, lat)"
    if not world.shell.contains(point):
        raise ConfigError(
            f"{where}: lies on the polar land of {config.shorelines.path} (the "
            "land round the projection's pole); give a point in the ocean"
        )
    hit = shapely.STRtree(world.islands).query(point, "within")
    if len(hit):
        area = earth_areas(world.islands[hit], world.crs).max()
        if area >= kept_area(config):
            raise ConfigError(
                f"{where}: lies on land in {config.shorelines.path} (an island or "
                "continent the case keeps); give a point in the ocean"
            )


#: The plane's scale past which the coast is too near the pole: lengths there
#: are this many times longer in the plane (about 5 degrees from the pole),
#: and the closing's rings and the size field's scale become unreliable.
POLE_SCALE = 500.0


def _warn_near_pole(config: CaseConfig, world: WorldLand, lonlat: CRS) -> None:
    """Warn if the coast comes so near the pole that the plane's scale blows up."""
    xy = shapely.get_coordinates(world.shell.exterior)
    r = np.hypot(xy[:, 0], xy[:, 1])
    i = int(np.argmax(r))
    k = plane_scale(float(r[i]))
    if k <= POLE_SCALE:
        return
    away = (math.pi - 2.0 * math.atan(r[i] / (2.0 * EARTH_RADIUS))) * EARTH_RADIUS
    lon, lat = reproject(shapely.Point(xy[i]), world.crs, lonlat).coords[0]
    warnings.warn(
        f"{config.label}: domain.pole = {list(world.pole)}: the coast comes within "
        f"{away / 1000:,.0f} km of it (at {lon:.2f}, {lat:.2f}), where the plane "
        f"stretches lengths {k:,.0f} times: the closing of narrow water and the "
        "sizes there are unreliable; put the pole deeper inside its land (the "
        "middle of Antarctica, [0, -90], for the world ocean)",
        CoastmeshWarning,
        stacklevel=2,
    )


def _check_lonlat(config: CaseConfig, crs: CRS) -> None:
    """Check that a global case reads and writes longitude and latitude."""
    if not crs.is_geographic:
        raise ConfigError(
            f"{config.label}: a global case takes its shorelines in longitude and "
            f"latitude; [case] crs or the file gives {crs.name!r}"
        )
    output_crs = CRS.from_user_input(config.mesh.output_crs or crs)
    if not output_crs.is_geographic:
        raise ConfigError(
            f"{config.label}: mesh.output_crs = {output_crs.name!r}: a global mesh is "
            "written in longitude and latitude"
        )


def _world(config: CaseConfig, features: Features, crs: CRS) -> WorldLand:
    try:
        return world_land(features.geometry, crs, pole=config.domain.pole)
    except InputDataError as exc:
        raise InputDataError(
            f"{config.shorelines.path}: {exc.message}",
            path=str(config.shorelines.path),
        ) from None


def _closed(
    config: CaseConfig,
    s: ShorelineSetConfig,
    world: WorldLand,
    land: NDArray[np.object_],
    report: ShorelineSetReport,
    lonlat: CRS,
    threads: int = 1,
) -> tuple[NDArray[np.object_], ShorelineSetReport]:
    """Return the set's land, framed, narrow water closed (on ``threads``); report.

    Every set has the polar land (the frame round the plane), with its own
    PCA: a region set is used inside its regions, and those may hold the
    polar land's coast (Europe's, with the pole in Asia); without it, the
    region's land there would be sea. The report gets the islands the closing
    keeps whole (:func:`kept_area`) that it changed by more than 10 % of
    their area.
    """
    islands = land
    land = np.concatenate([[world.frame(_shell(world.shell, s, threads))], land])
    close = closing_width(config)
    if not close:
        return land, report
    min_area = kept_area(config)
    land, merged = _close(
        land,
        close,
        1.05 * world.reach,
        _zone(config, s, world.crs, lonlat),
        keep_area=min_area,
        threads=threads,
        crs=world.crs,
    )
    logger.info("%s: %d polygons joined across water under %g m", s.name, merged, close)
    looked, changed = island_changes(
        islands, land, min_area=min_area, framed=True, crs=world.crs
    )
    where = np.reshape([c.point for c in changed], (-1, 2))
    points = reproject_points(where, world.crs, lonlat)
    closing = ClosingReport(
        width=float(close),
        merged=merged,
        islands=looked,
        changed=tuple(
            ChangedIsland(
                lon=round(float(lon), 4),
                lat=round(float(lat), 4),
                km2_before=round(c.before / 1e6, 1),
                km2_after=None if math.isnan(c.after) else round(c.after / 1e6, 1),
                joined=c.joined,
                polar=math.isnan(c.after),
            )
            for c, (lon, lat) in zip(changed, points, strict=True)
        ),
    )
    logger.info("%s: %s", s.name, closing.summary())
    return land, dataclasses.replace(report, closing=closing)


def closing_width(config: CaseConfig) -> float | None:
    """Return the width of water a global case closes: ``[domain] close``.

    By default the smallest gradation's ``h_min``; None (no closing) without
    gradations.
    """
    if config.domain.close is not None:
        return config.domain.close
    return min((g.h_min for g in config.size.gradations), default=None)


def kept_area(config: CaseConfig) -> float:
    """Return the area on the Earth of the smallest island a global case keeps.

    ``[shorelines] min_area``; without it (0, the default), the disk of the
    closing's width, ``pi close^2 / 4`` (:func:`closing_width`; 0 without a
    closing). Smaller islands are dropped from the shoreline sets: the mesh
    cannot hold them (and kept, the closing would join them to the coast in
    tangles). Islands of that area or more are never opened away; their thin
    parts are thickened to ``close``.
    """
    close = closing_width(config)
    if config.shorelines.min_area or not close:
        return config.shorelines.min_area
    return math.pi * close**2 / 4


def _zone(
    config: CaseConfig, s: ShorelineSetConfig, plane: CRS, lonlat: CRS
) -> shapely.Geometry | None:
    """Return where a set is used (its regions, in the plane); None: everywhere."""
    if s.name == config.background_set.name:
        return None
    place = _from_lonlat(lonlat, plane)
    zones = [
        case_region(r, k, plane, config, place)
        for k, r in enumerate(config.regions)
        if r.set == s.name
    ]
    return shapely.union_all(zones) if zones else None


def _close(
    land: NDArray[np.object_],
    width: float,
    reach: float,
    zone: shapely.Geometry | None,
    *,
    keep_area: float = 0.0,
    threads: int = 1,
    crs: CRS | None = None,
) -> tuple[NDArray[np.object_], int]:
    """Close narrow water, only near ``zone`` (a region set's regions) if given.

    A set made for regions is used only there: its land farther than a margin
    of a few closing widths (at the plane's scale there) is kept as it is.
    Islands of ``keep_area`` or more are never removed, only thickened.
    """
    near = None
    if zone is not None:
        far = float(np.hypot(*np.abs(np.reshape(zone.bounds, (2, 2))).max(axis=0)))
        scale = plane_scale(far)  # the plane's k there
        near = zone.buffer(4.0 * width * scale)
    return close_narrow_water(
        land,
        width,
        within=reach,
        keep_area=keep_area,
        zone=near,
        threads=threads,
        crs=crs,
    )


def _shell(
    shell: shapely.Polygon, s: ShorelineSetConfig, threads: int = 1
) -> shapely.Polygon:
    """Return the polar coast, with the set's PCA when it has one."""
    if s.window is None or s.modes is None:  # not s.pca
        return shell
    out, _ = simplify_shorelines([shell], s.window, s.modes, workers=threads)
    parts = shapely.get_parts(out[0]) if out[0] is not None else []
    return max(parts, key=lambda p: p.area) if len(parts) else shell
