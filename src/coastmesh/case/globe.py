"""Global cases: ``[domain] kind = "global"``, the whole world ocean in one mesh.

The steps of a regional case, on the sphere:

1. the world shoreline layer (lon/lat) goes into the stereographic plane whose
   singular point is ``[domain] pole`` (:func:`coastmesh.geometry.world_land`):
   halves split at the antimeridian joined, the polar land (Antarctica) a frame
   round the rest;
2. the shoreline sets (PCA, ``min_area``) are made in that plane, by region as
   in a regional case (region boxes are in lon/lat); the polar coast takes the
   background set's PCA;
3. water and land narrower than ``[domain] close`` are closed
   (:func:`coastmesh.geometry.close_narrow_water`), so the coast can be
   resolved at the gradations' sizes;
4. the size field is made on a world lon/lat grid
   (:func:`coastmesh.sizing.sphere_size_field`): gradations by great-circle
   distance from the sets, the tidal-wavelength term, the gradation limit;
5. Gmsh meshes the ocean in the plane with the sizes scaled by the plane's
   scale factor (:class:`coastmesh.meshing.gmsh.SphereSizeGrid`), in one part;
6. the nodes go back to lon/lat; depths, time step and quality follow as in a
   regional case.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.case.figures import FigureJobs
from coastmesh.case.finish import finish_case, measure_mesh
from coastmesh.case.inputs import (
    bathymetry_terms,
    build_case_domain,
    build_shoreline_set,
    read_shorelines,
    region_geometry,
)
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry import simplify_shorelines
from coastmesh.geometry.earth import EARTH_RADIUS, METRES_PER_DEGREE, reproject
from coastmesh.geometry.world import close_narrow_water, world_land
from coastmesh.meshing.engine import mesh_in_parts
from coastmesh.meshing.gmsh.model import release_memory
from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid
from coastmesh.sizing.domain import SizeField, SizeFieldReport
from coastmesh.sizing.field import Gradation
from coastmesh.sizing.sphere import sphere_size_field
from coastmesh.types import Features, SizeGrid

__all__ = ["DEFAULT_CELL_DEG", "build_global"]

logger = logging.getLogger(__name__)

#: The world size grid's spacing unless ``[mesh_size] cell`` sets one: 0.25
#: degrees, 1441 x ~680 nodes. Gmsh holds the grid's cells as its background
#: view, 128 bytes a cell: 0.1 degrees would be 800 MB.
DEFAULT_CELL_DEG = 0.25


def build_global(
    config: CaseConfig,
    timed: Callable[[str], Any],
    timings: dict[str, float],
    threads: int,
    runner: Any,
    *,
    figures: FigureJobs | None,
    cleanup: Any,
) -> Any:
    """Build a global case (see the module docstring); return its CaseResult.

    ``timed`` times a stage into ``timings``; the mesh's figures start on
    ``figures`` (:func:`~coastmesh.case.finish.measure_mesh`).
    """
    started = time.perf_counter()
    with timed("reading shorelines"):
        features, crs = read_shorelines(config)
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
    with timed("the world in the plane"):
        try:
            world = world_land(features.geometry, crs, pole=config.domain.pole)
        except InputDataError as exc:
            raise InputDataError(
                f"{config.shorelines.path}: {exc.message}",
                path=str(config.shorelines.path),
            ) from None
    plane = world.crs
    islands = Features(
        world.islands,
        plane,
        {},
        np.arange(len(world.islands)),
        features.path,
        features.layer,
    )
    close = config.domain.close
    if close is None:
        close = min((g.h_min for g in config.size.gradations), default=None)
    background = config.background_set.name
    sets, set_reports = {}, {}
    for s in config.sets:
        label = f"shoreline set {s.name!r} ({s.label})"
        with timed(label) as progress:
            land, report = build_shoreline_set(
                s, islands, plane, config.shorelines.min_area, progress
            )
            if s.name == background:
                land = np.concatenate([[world.frame(_shell(world.shell, s))], land])
            if close:
                land, merged = _close(
                    land, close, 1.05 * world.reach, _zone(config, s, plane, crs)
                )
                logger.info("%s: %d polygons joined across water under %g m",
                            s.name, merged, close)  # fmt: skip
            sets[s.name], set_reports[s.name] = land, report
    with timed("building the domain"):
        inputs = build_case_domain(config, sets, plane, lonlat=crs)
    domain = inputs.domain
    with timed("size field"):
        sized = _size_field(config, domain, plane, crs)
    release_memory()
    with timed("meshing") as progress:
        mesh, parts = mesh_in_parts(
            domain,
            SphereSizeGrid(SizeGrid.from_dataarray(sized.field), world.pole),
            mesh_crs=plane,
            output_crs=output_crs,
            seed=config.mesh.seed,
            algorithm=config.mesh.algorithm,
            optimize=config.mesh.optimize,
            parts=1,
            threads=threads,
            runner=runner,
            cleanup=cleanup,
            progress=progress,
        )
    mesh, measured = measure_mesh(
        config, mesh, timed, sized, parts.cleanup, figures=figures, domain=inputs.domain
    )
    return finish_case(
        config, mesh, inputs, sized, parts, measured, timings, started,
        crs=crs, mesh_crs=plane, output_crs=output_crs, set_reports=set_reports,
    )  # fmt: skip


def _zone(config: CaseConfig, s: Any, plane: CRS, lonlat: CRS) -> Any:
    """Return where a set is used (its regions, in the plane); None: everywhere."""
    if s.name == config.background_set.name:
        return None
    zones = []
    for k, r in enumerate(config.regions):
        if r.set == s.name:
            region = region_geometry(r, k, plane, config)
            if r.path is None:  # a box or polygon in lon/lat
                region = reproject(shapely.segmentize(region, 0.1), lonlat, plane)
            zones.append(region)
    return shapely.union_all(zones) if zones else None


def _close(land: Any, width: float, reach: float, zone: Any) -> tuple[Any, int]:
    """Close narrow water, only near ``zone`` (a region set's regions) if given.

    A set made for regions is used only there: its land farther than a margin
    of a few closing widths (at the plane's scale there) is kept as it is.
    """
    if zone is None:
        return close_narrow_water(land, width, within=reach)
    far = float(np.hypot(*np.abs(np.reshape(zone.bounds, (2, 2))).max(axis=0)))
    scale = 1.0 + (far / (2.0 * EARTH_RADIUS)) ** 2  # the plane's k there
    near = zone.buffer(4.0 * width * scale)
    inside = shapely.intersection(land, near)
    inside = inside[~shapely.is_empty(inside)]
    outside = shapely.difference(land, near)
    closed, merged = close_narrow_water(inside, width, within=reach)
    return np.concatenate([closed, outside[~shapely.is_empty(outside)]]), merged


def _shell(shell: shapely.Polygon, s: Any) -> shapely.Polygon:
    """Return the polar coast, with the set's PCA when it has one."""
    if not s.pca:
        return shell
    out, _ = simplify_shorelines([shell], s.window, s.modes)
    parts = shapely.get_parts(out[0]) if out[0] is not None else []
    return max(parts, key=lambda p: p.area) if len(parts) else shell


def _size_field(config: CaseConfig, domain: Any, plane: CRS, lonlat: CRS) -> SizeField:
    """``[mesh_size]`` on the world lon/lat grid."""
    size = config.size
    gradations = []
    for k, g in enumerate(size.gradations):
        lines = [
            shapely.LineString(s.coords) for s in domain.segments if s.name in g.lines
        ]
        if not lines:
            raise ConfigError(
                f"{config.label}: mesh_size.gradations[{k}].lines = {list(g.lines)}: "
                "none of these shoreline sets is on the domain's boundary"
            )
        gradations.append(
            Gradation(np.array(lines, dtype=object), g.h_min, g.d_hold, g.d_grade)
        )
    bathymetry = None if size.bathymetry is None else bathymetry_terms(size.bathymetry)
    cell = DEFAULT_CELL_DEG if size.cell is None else size.cell / METRES_PER_DEGREE
    south = reproject(domain.polygon.exterior, plane, lonlat).bounds[1]
    h_min = size.h_min
    if h_min is None:
        h_min = min((g.h_min for g in size.gradations), default=None)
    field = sphere_size_field(
        gradations,
        h_max=size.h_max,
        cell=cell,
        south=max(math.floor(south - 2 * cell), -90.0),
        rate=size.rate,
        bathymetry=bathymetry,
        h_min=h_min,
        lines_crs=plane,
    )
    report = SizeFieldReport.of(field, h_min=h_min)
    report = type(report)(**{**_fields(report), "cell_m": cell * METRES_PER_DEGREE})
    logger.info("size field: %s", report.summary())
    return SizeField(field, report, np.empty(0, dtype=object), None)


def _fields(report: Any) -> dict[str, Any]:
    import dataclasses

    return {f.name: getattr(report, f.name) for f in dataclasses.fields(report)}
