"""Patch a site into an existing mesh: remesh inside a polygon, keep the rest exactly.

:func:`patch_mesh` cuts out the elements that meet a polygon (given, or grown
round the case's farms, turbines, wakes and lines), meshes the hole with the
case's site tables and size terms, its boundary the existing mesh's nodes as
they are (the seam, and any coast or open boundary the hole reaches), and puts
the new elements in:

* every node and element outside the hole keeps its number, coordinates,
  depth and boundary lists: the new nodes and elements take the numbers of
  those cut out first, then follow the last;
* the size inside grows from the seam's own edge lengths (the new elements
  beside it have the size of the kept ones across it) to the site's sizes;
* depths inside come from the case's ``[bathymetry]``, or without one from
  the existing mesh, linear on its elements; the seam's nodes keep theirs.
"""

from __future__ import annotations

import logging
import math
import warnings
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case.config import CaseConfig, floor
from coastmesh.case.patch.cut import Hole, check_elements, cut_hole, grow_hole
from coastmesh.case.patch.hole import hole_domain, seam_edges, seam_sizes
from coastmesh.case.patch.report import PatchReport, patch_report, seam_faults
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import reproject_points
from coastmesh.geometry.projection import default_mesh_crs
from coastmesh.sizing.grid import PlaneGrid
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

if TYPE_CHECKING:
    from coastmesh.case.config import RasterConfig
    from coastmesh.case.pipeline.farms import SiteFeatures
    from coastmesh.depth import DepthSources

__all__ = ["Patched", "patch_mesh", "site_polygon"]

logger = logging.getLogger(__name__)

#: The polygon grown round the site by default: the distance over which the
#: site's smallest size grows to the mesh's there, at the case's rate, plus
#: this many of the mesh's elements there.
MARGIN_ELEMENTS = 2.0
#: The seam's bounds: an element with a node on it has no angle under
#: SEAM_MIN_ANGLE degrees, and the size ratio across it is at most
#: SEAM_MAX_RATIO. Where the patch breaks them, the seam is moved out past
#: those nodes (the kept elements at them are cut out too) and the hole meshed
#: again, at most SEAM_MOVES times; the best of the tries is kept.
SEAM_MIN_ANGLE = 30.0
SEAM_MAX_RATIO = 1.5
SEAM_MOVES = 3


@dataclass(frozen=True, eq=False)
class Patched:
    """The patched mesh, what changed, and where.

    Attributes
    ----------
    mesh : Mesh
        The patched mesh, in the input's CRS.
    report : PatchReport
    polygon : shapely.Polygon
        The polygon cut, in ``crs``.
    hole : Hole
        The elements cut out and the hole's rings (node numbers of the input).
    crs : pyproj.CRS
        The CRS meshed in.
    new_elements : ndarray of int
        The numbers (0-based) of the patch's elements in :attr:`mesh`.
    """

    mesh: Mesh
    report: PatchReport
    polygon: shapely.Polygon
    hole: Hole
    crs: CRS
    new_elements: NDArray[np.int64]


def patch_mesh(
    mesh: Mesh,
    config: CaseConfig,
    *,
    polygon: shapely.Geometry | None = None,
    polygon_crs: CRS | str = "EPSG:4326",
    distance: float | None = None,
    name: str = "mesh",
    threads: int = 1,
) -> Patched:
    """Remesh a site into an existing mesh; keep everything outside it exactly.

    Parameters
    ----------
    mesh : Mesh
        The existing mesh (:func:`coastmesh.io.read_mesh`), with its CRS.
    config : CaseConfig
        The site's case: its ``[[farms]]``, ``[[turbines]]``, ``[[wakes]]``,
        ``[[lines]]``, ``[mesh_size]`` terms, ``[bathymetry]``, ``[mesh]`` and
        ``[cleanup]``. Its shorelines and open boundaries are not used.
    polygon : shapely geometry, optional
        The region to remesh, in ``polygon_crs``. Default: the site's features
        grown by ``distance`` (:func:`site_polygon`).
    distance : float, optional
        Metres to grow the site by; default the distance the site's smallest
        size needs to grow to the mesh's at the case's ``rate``, plus two of
        the mesh's elements.
    name : str
        How messages name the mesh (its file).
    threads : int
        Threads for the size field and the cleanup.

    Raises
    ------
    InputDataError
        The mesh has no CRS, or inverted or duplicate elements; the polygon
        meets no element, or would cut the mesh in two.
    MeshingError
        The hole could not be meshed on the seam's nodes.

    Warns
    -----
    CoastmeshWarning
        The sizes inside are coarser than the elements they replace.
    """
    if mesh.crs is None:
        raise InputDataError(f"{name}: the mesh stores no CRS; give its CRS (--crs)")
    crs = _meshing_crs(mesh, config)
    points = reproject_points(mesh.points, mesh.crs, crs)
    clockwise = check_elements(points, mesh.triangles, name)
    triangles = mesh.triangles[:, [0, 2, 1]] if clockwise else mesh.triangles
    if polygon is None:
        polygon = site_polygon(config, mesh, points, crs, distance, name)
    else:
        polygon = shapely.make_valid(_reproject(polygon, polygon_crs, crs))
    at_site = _site_crs(mesh, config, polygon, crs)
    if at_site != crs:  # a geographic mesh: UTM at the site, not the mesh's middle
        polygon = _reproject(polygon, crs, at_site)
        crs, points = at_site, reproject_points(mesh.points, mesh.crs, at_site)
    hole = cut_hole(points, triangles, polygon, name)
    best: Patched | None = None
    for moves in range(SEAM_MOVES + 1):
        patched, faults = _fill(
            mesh, config, points, hole, polygon, crs, threads, name, clockwise, moves
        )
        if best is None or _score(patched.report) > _score(best.report):
            best = patched
        if not faults.size or moves == SEAM_MOVES:
            break
        try:  # move the seam out past the nodes where the patch met it badly
            hole = grow_hole(points, triangles, hole, faults, name)
        except InputDataError as exc:
            logger.info("the seam stays: %s", exc)
            break
    assert best is not None
    _warn_if_coarser(best.report, name)
    return best


def _fill(
    mesh: Mesh,
    config: CaseConfig,
    points: NDArray[np.float64],
    hole: Hole,
    polygon: shapely.Geometry,
    crs: CRS,
    threads: int,
    name: str,
    clockwise: bool,
    moves: int,
) -> tuple[Patched, NDArray[np.int64]]:
    """Mesh the hole and merge it; return the result and the seam's faults.

    The faults are the seam's nodes (the input's numbers) where an element
    with a node on the seam has an angle under :data:`SEAM_MIN_ANGLE`, or the
    size ratio across a seam edge is over :data:`SEAM_MAX_RATIO`.
    """
    from coastmesh.case.patch.merge import merge

    domain, _ = hole_domain(hole, points, mesh, crs, _boundary_ids(mesh))
    size, site, held = _sizes(config, domain, hole, points, crs, threads)
    new = _mesh_hole(config, domain, size, site, crs, threads)
    if held is not None and config.cleanup.enabled:
        # a [[mesh_size.fields]] entry's sizes hold inside, as in a whole run;
        # the seam's nodes are the hole's boundary: they stay
        from coastmesh.case.pipeline.mesh import grid_flags
        from coastmesh.meshing.cleanup.conform import conform_sizes

        new, _ = conform_sizes(new, grid_flags(held[0], held[1], new))
    merged, new_elements, numbers = merge(
        mesh, points, hole, new, crs, config, name, clockwise=clockwise
    )
    # the seam in the output's numbers: a coarser patch closes the gaps it leaves
    seam = numbers[seam_edges(hole)]
    report = patch_report(mesh, merged, hole, new_elements, crs, seam, moves)
    faults = seam_faults(
        merged, crs, seam, min_angle=SEAM_MIN_ANGLE, max_ratio=SEAM_MAX_RATIO
    )
    ring = np.unique(np.concatenate(hole.rings))
    patched = Patched(merged, report, polygon, hole, crs, new_elements)
    return patched, ring[np.isin(numbers[ring], faults)]


def _score(report: PatchReport) -> tuple[float, float]:
    """How near the seam is to its bounds (1 and 1: within them); larger is better."""
    return (
        min(
            report.angle_p01_seam / SEAM_MIN_ANGLE,
            SEAM_MAX_RATIO / report.size_ratio_seam_max,
            1.0,
        ),
        min(report.angle_min_seam / SEAM_MIN_ANGLE, 1.0),
    )


def _meshing_crs(mesh: Mesh, config: CaseConfig) -> CRS:
    """Return the mesh's CRS if projected, else ``[mesh] crs``, else UTM there."""
    assert mesh.crs is not None
    if mesh.crs.is_projected:
        return mesh.crs
    if config.mesh.crs is not None:
        return CRS.from_user_input(config.mesh.crs)
    hull = shapely.convex_hull(shapely.multipoints(mesh.points))
    return _utm_at(np.asarray(hull.centroid.coords), mesh.crs)


def _site_crs(
    mesh: Mesh, config: CaseConfig, polygon: shapely.Geometry, crs: CRS
) -> CRS:
    """Return the meshing CRS at the site: UTM at the polygon, for a lon/lat mesh."""
    assert mesh.crs is not None
    if mesh.crs.is_projected or config.mesh.crs is not None:
        return crs
    return _utm_at(np.asarray(shapely.centroid(polygon).coords), crs)


def _utm_at(point: NDArray[np.float64], crs: CRS) -> CRS:
    """Return the CRS a small domain at ``point`` (in ``crs``) is meshed in: its UTM."""
    lon, lat = reproject_points(point, crs, "EPSG:4326")[0]
    box = shapely.box(lon - 0.01, lat - 0.01, lon + 0.01, lat + 0.01)
    return default_mesh_crs(Domain(box, _box_segments(box), CRS.from_epsg(4326)))


def _box_segments(box: shapely.Polygon) -> tuple[BoundarySegment, ...]:
    return (BoundarySegment(np.asarray(box.exterior.coords), "open", "box", 1),)


def _reproject(
    geometry: shapely.Geometry, src: CRS | str, dst: CRS
) -> shapely.Geometry:
    from coastmesh.geometry import reproject

    minx, miny, maxx, maxy = geometry.bounds
    step = max(maxx - minx, maxy - miny) / 200 or 1.0  # straight in src stays so
    return reproject(shapely.segmentize(geometry, step), src, dst)


def _boundary_ids(mesh: Mesh) -> dict[tuple[int, int], int]:
    edges = np.sort(mesh.boundary_edges, axis=1)
    return {
        (int(a), int(b)): int(i)
        for (a, b), i in zip(edges, mesh.boundary_ids, strict=True)
    }


def site_polygon(
    config: CaseConfig,
    mesh: Mesh,
    points: NDArray[np.float64],
    crs: CRS,
    distance: float | None,
    name: str,
) -> shapely.Geometry:
    """Return the site's farms, turbines, wakes and lines grown by ``distance``.

    Without ``distance``: the distance over which the site's smallest size
    grows, at the case's ``rate``, to the size of the mesh's elements there,
    plus :data:`MARGIN_ELEMENTS` of them.
    """
    from coastmesh.case.pipeline.farms import site_features_in

    bounds = (*points.min(axis=0), *points.max(axis=0))
    box = shapely.box(*bounds)
    everywhere = Domain(box, _box_segments(box), crs)
    site = site_features_in(config, everywhere, crs)
    shapes = [p for _, _, p, _ in site.farms]
    shapes += [shapely.Point(t.xy).buffer(t.diameter) for t in site.turbines]
    shapes += [band for _, band, _ in site.wakes] + [line for *_, line, _ in site.lines]
    if not shapes:
        raise InputDataError(
            f"{name}: the case has no [[farms]], [[turbines]], [[wakes]] or "
            "[[lines]] to patch in; give the polygon to remesh (--polygon)"
        )
    union = shapely.union_all(shapes)
    if distance is None:
        smallest = site.smallest()
        if not math.isfinite(smallest):
            smallest = floor(config.size)
        distance = _grading_distance(config, points, mesh.triangles, union, smallest)
    return shapely.buffer(union, distance)


def _grading_distance(
    config: CaseConfig,
    points: NDArray[np.float64],
    triangles: NDArray[np.int64],
    site: shapely.Geometry,
    smallest: float,
) -> float:
    """Return the distance the site's sizes need to grow to the mesh's there."""
    centroid = points[triangles].mean(axis=1)
    near = shapely.contains_xy(site.buffer(max(site.length, 1000.0)), *centroid.T)
    if not near.any():
        near = np.ones(len(triangles), dtype=bool)
    p = points[triangles[near]]
    there = float(np.median(np.hypot(*(p[:, 1] - p[:, 0]).T)))
    rate = config.size.rate or 0.25
    return max(there - smallest, 0.0) / rate + MARGIN_ELEMENTS * there


def _sizes(
    config: CaseConfig,
    domain: Domain,
    hole: Hole,
    points: NDArray[np.float64],
    crs: CRS,
    threads: int,
) -> tuple[SizeGrid, SiteFeatures, tuple[PlaneGrid, NDArray[np.bool_]] | None]:
    """Return the size field over the hole: the case's terms, the seam's, the site's.

    And the grid and its nodes where a term asks its sizes to hold (the field
    term's), or None.
    """
    from coastmesh.case.pipeline.closing import smallest_size
    from coastmesh.case.pipeline.depth import read_sources
    from coastmesh.case.pipeline.domain import site_area
    from coastmesh.case.pipeline.farms import site_features_in, with_site_sizes
    from coastmesh.case.pipeline.size import size_field
    from coastmesh.case.terms.base import SizeCase

    try:
        site = site_features_in(config, domain, crs)
    except ConfigError as exc:
        raise ConfigError(
            f"{exc} (in a patch the domain is the hole cut out: every farm, "
            "turbine and line must lie inside the polygon remeshed; grow "
            "--distance or the --polygon)"
        ) from None
    grid = PlaneGrid.around(
        domain,
        crs,
        spacing=config.size.cell,
        smallest=smallest_size(config.size),
        threads=threads,
    )
    ring = shapely.get_coordinates(domain.polygon.exterior)

    def read(part: RasterConfig) -> DepthSources:
        return read_sources(part.stack, ring, crs)

    case = SizeCase(
        config,
        domain,
        floor(config.size),
        read_depth=read,
        site_area=site_area(config, crs),
        lines={n: p.exterior for n, _, p, _ in site.farms},
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        state = size_field(grid, case, threads=threads)
    _pass_on(caught)
    rate = config.size.rate or 0.25
    upper, lower = seam_sizes(grid.x, grid.y, points, seam_edges(hole), rate)
    values = np.maximum(np.minimum(state.field.values, upper), lower)
    values = grid.limit(np.minimum(values, config.size.h_max), rate)
    size = SizeGrid(grid.x, grid.y, values, scale=grid.scale)
    held = None
    if state.conform is not None:  # where the seam left the case's sizes alone
        held = (grid, state.conform & (values == state.field.values))
    return with_site_sizes(size, site, config.size.rate, config.label), site, held


def _pass_on(caught: list[warnings.WarningMessage]) -> None:
    """Warn again what the size terms warned, the skipped gradations as one."""
    skipped = [
        w for w in caught if "have no edges on the domain boundary" in str(w.message)
    ]
    if skipped:
        logger.info(
            "patch: %d gradations name lines the patch does not have (the case's "
            "shorelines and open boundaries): skipped",
            len(skipped),
        )
    for w in caught:
        if w not in skipped:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def _mesh_hole(
    config: CaseConfig,
    domain: Domain,
    size: SizeGrid,
    site: SiteFeatures,
    crs: CRS,
    threads: int,
) -> Mesh:
    """Mesh the hole on its boundary's nodes as they are."""
    from coastmesh.case.pipeline.mesh import cleanup_options
    from coastmesh.meshing.engine import mesh_in_parts

    options = cleanup_options(config)
    if options is not None:
        # no triangle with three boundary nodes is split or flipped away: the
        # seam's nodes and edges are the kept mesh's
        options = replace(options, boundary_triangles=False)
    new, _ = mesh_in_parts(
        domain,
        size,
        mesh_crs=crs,
        output_crs=crs,
        seed=config.mesh.seed,
        algorithm=config.mesh.algorithm,
        optimize=config.mesh.optimize,
        parts=1,
        threads=threads,
        cleanup=options,
        inner=site.inner() if site else None,
        fixed_boundary=True,
    )
    return new


def _warn_if_coarser(report: PatchReport, name: str) -> None:
    if report.size_new_m > 1.05 * report.size_removed_m and math.isfinite(
        report.size_removed_m
    ):
        warnings.warn(
            f"{name}: the patch's elements (median {report.size_new_m:.0f} m) are "
            f"coarser than those they replace ({report.size_removed_m:.0f} m): the "
            "case's sizes inside are coarser than the mesh there",
            CoastmeshWarning,
            stacklevel=3,
        )
