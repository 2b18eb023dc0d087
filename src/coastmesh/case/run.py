"""Run a whole case: shorelines to a written mesh, as ``coastmesh run`` does.

The stages, each reported to the ``progress`` factory and the log:

1. read the shoreline file (clip to ``bbox``; fill in a missing CRS);
2. build each shoreline set: full resolution, or a PCA reconstruction
   (:func:`~coastmesh.geometry.simplify_shorelines`, after
   :func:`~coastmesh.geometry.densify_long_edges`); drop land polygons and fill
   lakes below ``min_area``;
3. stitch the sets by region (:func:`~coastmesh.geometry.stitch.stitch_shorelines`),
   draw the open boundaries (loxodromes, blends, great circles, polylines) and
   build the domain (:func:`~coastmesh.geometry.build_domain`);
4. the size field: gradations from named shoreline sets and open boundaries,
   bathymetry terms, a gradation limit, on a grid in the meshing CRS;
5. mesh with Gmsh (:func:`~coastmesh.meshing.generate_mesh`), then clean up
   (:mod:`~coastmesh.meshing.cleanup`), put depths on the nodes
   (:mod:`~coastmesh.meshing.depth`) and measure the quality
   (:mod:`~coastmesh.meshing.quality`);
6. write the mesh formats, the domain GeoPackage, the size field, the reports
   and figures (:mod:`coastmesh.case.outputs`) into ``<output>.partial-XXXX/``,
   renamed to ``<output>`` at the end: a failed run leaves nothing.

A case with ``[case] kind = "shorelines"`` or ``"bathymetry"`` runs one of the
paper's PCA studies (:mod:`coastmesh.case.studies`) instead.
"""

from __future__ import annotations

import contextlib
import logging
import time
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS, Transformer

from coastmesh.case.config import (
    BoundaryConfig,
    CaseConfig,
    RegionConfig,
    StudyCase,
    load_case,
)
from coastmesh.case.outputs import (
    CaseProducts,
    build_report,
    write_case_copy,
    write_outputs,
)
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.domain import polygon_areas
from coastmesh.types import Features

__all__ = ["CaseResult", "run_case"]

logger = logging.getLogger(__name__)

Progress = Callable[[int, int], None]
#: ``stage(label)`` returns a context manager yielding a ``progress(done, total)``
StageFactory = Callable[[str], contextlib.AbstractContextManager[Progress]]

_LONLAT = CRS.from_epsg(4326)


@dataclass(frozen=True, slots=True)
class CaseResult:
    """What :func:`run_case` made."""

    name: str
    output: Path
    files: tuple[str, ...]
    nodes: int
    triangles: int
    boundary_edges: dict[str, int]
    seconds: float
    report: dict[str, Any] = field(default_factory=dict)

    def summary(self) -> str:
        """Return a one-line summary."""
        ids = ", ".join(f"{k} {v}" for k, v in self.boundary_edges.items())
        return (
            f"{self.name}: {self.nodes:,} nodes, {self.triangles:,} triangles, "
            f"boundary edges by id: {ids}; {len(self.files)} files in "
            f"{self.output}/ in {self.seconds:.1f} s"
        )


@contextlib.contextmanager
def _quiet_stage(label: str) -> Iterator[Progress]:
    yield lambda done, total: None


def run_case(
    case: CaseConfig | str | Path,
    *,
    output: str | Path | None = None,
    overwrite: bool = False,
    stage: StageFactory | None = None,
) -> CaseResult:
    """Run a case file end to end and write its outputs.

    Parameters
    ----------
    case : CaseConfig or path
        The case, or its TOML file (read with :func:`coastmesh.case.config.load_case`).
    output : str or path-like, optional
        The output folder; default: the case's ``[case] output``.
    overwrite : bool, default False
        Whether an existing, non-empty output folder may be replaced.
    stage : callable, optional
        ``stage(label)`` returns a context manager yielding a
        ``progress(done, total)`` callback, entered once per stage (the CLI draws
        a progress bar per stage with it).

    Returns
    -------
    CaseResult

    Raises
    ------
    ConfigError
        For a bad case file or a value that does not fit the data (e.g. a seed
        on land).
    InputDataError
        If a data file is missing or holds the wrong kind of geometry.
    MeshingError
        If Gmsh fails.
    OutputExistsError
        If the output folder exists, is not empty, and ``overwrite`` is false.
    """
    from coastmesh.io import atomic_directory, check_directory

    config = case if isinstance(case, CaseConfig | StudyCase) else load_case(case)
    target = Path(output) if output is not None else config.output
    check_directory(target, overwrite=overwrite)  # fail before the work
    stage = stage or _quiet_stage
    if isinstance(config, StudyCase):
        return _run_study(config, target, overwrite, stage)
    started = time.perf_counter()
    timings: dict[str, float] = {}

    @contextlib.contextmanager
    def timed(label: str) -> Iterator[Progress]:
        t0 = time.perf_counter()
        logger.info("stage: %s", label)
        with stage(label) as progress:
            yield progress
        timings[label] = round(time.perf_counter() - t0, 3)

    with timed("reading shorelines"):
        features, crs = _read_shorelines(config)
    sets, set_reports = _build_sets(config, features, crs, timed)
    with timed("building the domain"):
        domain, domain_report, stitch_report, regions, walls = _build_domain(
            config, sets, crs
        )
    with timed("size field") as progress:
        from coastmesh.meshing import SizeGrid, default_mesh_crs

        mesh_crs = (
            CRS.from_user_input(config.mesh.crs)
            if config.mesh.crs
            else default_mesh_crs(domain)
        )
        field_ = _size_field(config, domain, mesh_crs, progress)
    with timed("meshing") as progress:
        from coastmesh.meshing import generate_mesh

        output_crs = CRS.from_user_input(config.mesh.output_crs or crs)
        mesh = generate_mesh(
            domain,
            SizeGrid.from_dataarray(field_),
            mesh_crs=mesh_crs,
            output_crs=output_crs,
            seed=config.mesh.seed,
            algorithm=config.mesh.algorithm,
            optimize=config.mesh.optimize,
            progress=progress,
        )
    mesh, after = _after_meshing(config, mesh, timed)
    names = {s.physical_id: s.name for s in config.sets}
    names |= {b.physical_id: b.name for b in config.boundaries}
    ids, counts = np.unique(mesh.boundary_ids, return_counts=True)
    edges = {
        f"{names.get(int(i), '?')} ({int(i)})": int(c)
        for i, c in zip(ids, counts, strict=True)
    }
    report = build_report(
        config,
        crs=crs,
        mesh_crs=mesh_crs,
        output_crs=output_crs,
        sets=set_reports,
        stitch=stitch_report,
        domain=domain_report,
        size=field_,
        mesh=mesh,
        edges=edges,
        after=after,
        timings=timings,
    )
    with (
        timed("writing outputs"),
        atomic_directory(target, overwrite=overwrite) as folder,
    ):
        files = write_outputs(
            config,
            folder,
            CaseProducts(mesh, domain, field_, regions, walls, crs, after["quality"]),
            report,
        )
    seconds = time.perf_counter() - started
    result = CaseResult(
        name=config.name,
        output=target,
        files=tuple(files),
        nodes=len(mesh.points),
        triangles=len(mesh.triangles),
        boundary_edges=edges,
        seconds=seconds,
        report=report,
    )
    logger.info("%s", result.summary())
    return result


def _run_study(
    config: StudyCase, target: Path, overwrite: bool, stage: StageFactory
) -> Any:
    """Run a PCA study case (``[case] kind``) into ``target``, atomically."""
    import importlib

    from coastmesh.io import atomic_directory

    module = importlib.import_module(f"coastmesh.case.studies.{config.kind}")
    with atomic_directory(target, overwrite=overwrite) as folder:
        result = module.run_study(config.study, folder, stage)
        write_case_copy(folder, config.source, config.text)
        (folder / "summary.txt").write_text(result.summary() + "\n", encoding="utf-8")
    logger.info("%s: %s", config.name, result.summary())
    return result


# stage 1: the shoreline file


def _read_shorelines(config: CaseConfig) -> tuple[Features, CRS]:
    from coastmesh.geometry import check_coordinates, land_polygons
    from coastmesh.io import read_features

    s = config.shorelines
    features = read_features(s.path, layer=s.layer, bbox=s.bbox)
    if features.crs is None:
        if s.crs is None:
            raise InputDataError(
                f"{s.path}: the file declares no CRS; set shorelines.crs in "
                f"{config.source}",
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
    if crs != features.crs:
        to_case = Transformer.from_crs(features.crs, crs, always_xy=True)
        features = features.with_geometry(
            shapely.transform(
                features.geometry, lambda xy: np.column_stack(to_case.transform(*xy.T))
            )
        )
    logger.info("shorelines: %d land polygons from %s", len(features), s.path)
    return features, crs


# stage 2: shoreline sets


def _build_sets(
    config: CaseConfig, features: Features, crs: CRS, timed: StageFactory
) -> tuple[dict[str, NDArray[np.object_]], dict[str, dict[str, Any]]]:
    from coastmesh.geometry import densify_long_edges, simplify_shorelines

    sets: dict[str, NDArray[np.object_]] = {}
    reports: dict[str, dict[str, Any]] = {}
    points_in = int(shapely.get_num_coordinates(features.geometry).sum())
    for s in config.sets:
        label = f"shoreline set {s.name!r} ({s.label})"
        with timed(label) as progress:
            if s.window is None or s.modes is None:
                land = features.geometry
                report: dict[str, Any] = {"kind": s.label, "points_in": points_in}
            else:
                land, pca = simplify_shorelines(
                    densify_long_edges(features.geometry),
                    s.window,
                    s.modes,
                    progress=progress,
                )
                land = land[~shapely.is_missing(land)]
                report = {
                    "kind": s.label,
                    "points_in": pca.points_in,
                    "contours_in": pca.contours_in,
                    "contours_dropped": pca.contours_dropped,
                    "features_repaired": pca.repaired,
                }
            land = shapely.get_parts(land)
            land = land[shapely.get_type_id(land) == shapely.GeometryType.POLYGON]
            small = polygon_areas(land, crs) < config.shorelines.min_area
            land, lakes = _fill_lakes(land[~small], crs, config.shorelines.min_area)
            sets[s.name] = land
            report |= {
                "polygons": int((~small).sum()),
                "polygons_below_min_area": int(small.sum()),
                "lakes_below_min_area": lakes,
                "points_out": int(shapely.get_num_coordinates(land).sum()),
            }
            reports[s.name] = report
            logger.info("%s: %s", label, report)
    return sets, reports


def _fill_lakes(
    land: NDArray[np.object_], crs: CRS, min_area: float
) -> tuple[NDArray[np.object_], int]:
    """Fill the holes (lakes) of land polygons that are smaller than ``min_area``."""
    if min_area <= 0 or len(land) == 0:
        return land, 0
    holed = np.flatnonzero(shapely.get_num_interior_rings(land) > 0)
    filled = 0
    land = land.copy()
    for k in holed:
        polygon = land[k]
        lakes = np.array([shapely.Polygon(r) for r in polygon.interiors], dtype=object)
        keep = polygon_areas(lakes, crs) >= min_area
        if not keep.all():
            filled += int((~keep).sum())
            kept = [r for r, k_ in zip(polygon.interiors, keep, strict=True) if k_]
            land[k] = shapely.Polygon(polygon.exterior, kept)
    return land, filled


# stage 3: the domain


def _build_domain(
    config: CaseConfig, sets: dict[str, NDArray[np.object_]], crs: CRS
) -> tuple[Any, Any, Any, list[Any], list[Any]]:
    from coastmesh.geometry import OpenBoundary, build_domain
    from coastmesh.geometry.stitch import ShorelineSet, stitch_shorelines

    regions: dict[str, list[shapely.Geometry]] = {}
    for k, r in enumerate(config.regions):
        regions.setdefault(r.set, []).append(_region_geometry(r, k, crs, config))
    order = [r.set for r in config.regions]
    ordered = list(dict.fromkeys(order)) + [config.background_set.name]
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
    spacing = _boundary_spacing(config)
    walls = [
        OpenBoundary(
            _boundary_coords(b, k, crs, spacing, config), b.name, b.physical_id
        )
        for k, b in enumerate(config.boundaries)
    ]
    try:
        domain, report = build_domain(
            land,
            walls,
            crs=crs,
            seed=config.domain.seed,
            min_area=config.shorelines.min_area,
            surface_id=config.domain.surface_id,
            shorelines=tagged,
        )
    except ConfigError as exc:
        raise ConfigError(f"{config.source}: domain: {exc}") from None
    missing = [b.name for b in walls if b.name not in report.segments]
    if missing:
        warnings.warn(
            f"{config.source}: open boundaries {missing} do not reach the domain "
            "(they do not close the sea region that holds the seed)",
            CoastmeshWarning,
            stacklevel=3,
        )
    logger.info("domain: %s; %s", report.summary(), stitch_report.summary())
    return domain, report, stitch_report, tagged, walls


def _region_geometry(
    r: RegionConfig, k: int, crs: CRS, config: CaseConfig
) -> shapely.Geometry:
    if r.box is not None:
        return shapely.box(*r.box)
    if r.polygon is not None:
        polygon = shapely.Polygon(r.polygon)
        if not polygon.is_valid:
            raise ConfigError(
                f"{config.source}: regions[{k}].polygon is not a valid polygon "
                f"({shapely.is_valid_reason(polygon)})"
            )
        return polygon
    from coastmesh.io import read_features

    features = read_features(r.path, layer=r.layer)
    geometry = features.geometry[~shapely.is_missing(features.geometry)]
    polygonal = shapely.get_dimensions(geometry) == 2
    if not polygonal.any():
        raise InputDataError(
            f"{r.path}: regions[{k}] needs polygons; the file has none",
            path=str(r.path),
        )
    region = shapely.union_all(shapely.make_valid(geometry[polygonal]))
    if features.crs is not None and features.crs != crs:
        to_case = Transformer.from_crs(features.crs, crs, always_xy=True)
        region = shapely.transform(
            region, lambda xy: np.column_stack(to_case.transform(*xy.T))
        )
    return region


def _boundary_spacing(config: CaseConfig) -> float:
    """Default sampling of open boundaries: a quarter of the coarsest size, <= 1 km."""
    return min(1000.0, config.size.h_max / 4)


def _boundary_coords(
    b: BoundaryConfig, k: int, crs: CRS, spacing: float, config: CaseConfig
) -> NDArray[np.float64]:
    from coastmesh.geometry import blend_loxodromes, great_circle

    step = b.spacing or spacing
    where = f"{config.source}: open_boundaries[{k}] ({b.name!r})"
    try:
        if b.kind == "loxodrome":
            lonlat = _loxodrome(b.loxodrome).sample(step)
        elif b.kind == "blend":
            lonlat = blend_loxodromes(
                _loxodrome(b.first), _loxodrome(b.second), spacing=step
            )
        elif b.kind == "great_circle":
            lonlat = great_circle(b.start, b.end, spacing=step)
        else:
            return _polyline(b, where, crs)
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    if crs.is_geographic and crs.to_epsg() == 4326:
        return lonlat
    to_case = Transformer.from_crs(_LONLAT, crs, always_xy=True)
    return np.column_stack(to_case.transform(lonlat[:, 0], lonlat[:, 1]))


def _loxodrome(c: Any) -> Any:
    from coastmesh.geometry import Loxodrome

    return Loxodrome(c.start, c.azimuth, end_lat=c.end_lat, end_lon=c.end_lon)


def _polyline(b: BoundaryConfig, where: str, crs: CRS) -> NDArray[np.float64]:
    if b.points is not None:
        return np.array(b.points, dtype=float)
    from coastmesh.io import read_features

    features = read_features(b.path, layer=b.layer)
    lines = features.geometry[shapely.get_dimensions(features.geometry) == 1]
    parts = shapely.get_parts(lines)
    if len(parts) != 1:
        raise InputDataError(
            f"{where}: {b.path} must hold exactly one line; it has {len(parts)}",
            path=str(b.path),
        )
    line = parts[0]
    if features.crs is not None and features.crs != crs:
        to_case = Transformer.from_crs(features.crs, crs, always_xy=True)
        line = shapely.transform(
            line, lambda xy: np.column_stack(to_case.transform(*xy.T))
        )
    return shapely.get_coordinates(line)


# stage 4: size field


def _size_field(
    config: CaseConfig, domain: Any, mesh_crs: CRS, progress: Progress
) -> Any:
    from coastmesh.sizing import Gradation, size_field
    from coastmesh.sizing.gradation import limit_gradation

    size = config.size
    to_mesh = Transformer.from_crs(domain.crs, mesh_crs, always_xy=True)

    def project(geom: Any) -> Any:
        return shapely.transform(
            geom, lambda xy: np.column_stack(to_mesh.transform(*xy.T))
        )

    outline = project(shapely.segmentize(domain.polygon.exterior, _densify(domain)))
    minx, miny, maxx, maxy = outline.bounds
    extent = max(maxx - minx, maxy - miny)
    smallest = min(
        [g.h_min for g in size.gradations] + ([size.h_min] if size.h_min else [])
        or [size.h_max]
    )
    cell = size.cell or max(extent / 1000.0, smallest)
    pad = 2 * cell
    bounds = (minx - pad, miny - pad, maxx + pad, maxy + pad)
    gradations = []
    for k, g in enumerate(size.gradations):
        lines = [
            shapely.LineString(s.coords) for s in domain.segments if s.name in g.lines
        ]
        if not lines:
            warnings.warn(
                f"{config.source}: mesh_size.gradations[{k}]: {list(g.lines)} have no "
                "edges on the domain boundary; the gradation is skipped",
                CoastmeshWarning,
                stacklevel=3,
            )
            continue
        gradations.append(
            Gradation(
                project(np.array(lines, dtype=object)),
                h_min=g.h_min,
                d_hold=g.d_hold,
                d_grade=g.d_grade,
                name=",".join(g.lines),
            )
        )
    progress(0, 3)
    field_ = size_field(bounds, gradations, crs=mesh_crs, h_max=size.h_max, cell=cell)
    progress(1, 3)
    values = field_.values
    if size.bathymetry is not None:
        values = np.minimum(values, _bathymetry_size(size.bathymetry, field_, mesh_crs))
    if size.h_min is not None:
        values = np.maximum(values, size.h_min)
    values = np.minimum(values, size.h_max)
    if size.rate is not None:
        values = limit_gradation(values, (cell, cell), size.rate)
    progress(2, 3)
    field_ = field_.copy(data=values)
    field_.attrs["history"] = (
        f"coastmesh run {config.source.name}: {len(gradations)} gradations"
        + (", bathymetry" if size.bathymetry else "")
        + (f", rate {size.rate}" if size.rate else "")
    )
    progress(3, 3)
    logger.info(
        "size field: %d x %d cells of %.0f m, %.0f to %.0f m",
        field_.shape[1],
        field_.shape[0],
        cell,
        float(values.min()),
        float(values.max()),
    )
    return field_


def _densify(domain: Any) -> float:
    minx, miny, maxx, maxy = domain.polygon.bounds
    return max(maxx - minx, maxy - miny) / 1000.0


def _bathymetry_size(b: Any, field_: Any, mesh_crs: CRS) -> NDArray[np.float64]:
    from coastmesh.io import read_raster
    from coastmesh.sizing.bathymetry import depth_on_grid, slope_size, wavelength_size

    raster = read_raster(b.path)
    depth = depth_on_grid(
        raster, field_.x.values, field_.y.values, crs=mesh_crs, positive=b.positive
    )
    size = np.full(depth.shape, np.inf)
    if b.per_wavelength is not None:
        size = np.minimum(
            size,
            wavelength_size(
                depth,
                per_wavelength=b.per_wavelength,
                period=b.period,
                min_depth=b.min_depth,
            ),
        )
    if b.per_slope is not None:
        cell = float(field_.x[1] - field_.x[0])
        size = np.minimum(
            size,
            slope_size(
                depth, (cell, cell), per_slope=b.per_slope, min_depth=b.min_depth
            ),
        )
    return size


# stage 5b: cleanup, depth at the nodes, quality


def _after_meshing(
    config: CaseConfig, mesh: Any, timed: StageFactory
) -> tuple[Any, dict[str, Any]]:
    after: dict[str, Any] = {"cleanup": None, "depth": None, "quality": None}
    if config.cleanup.enabled:
        with timed("cleanup"):
            from coastmesh.meshing.cleanup import clean_mesh

            mesh, after["cleanup"] = clean_mesh(
                mesh,
                boundary_triangles=config.cleanup.boundary_triangles,
                max_valence=config.cleanup.max_valence,
                min_angle=config.cleanup.min_angle,
            )
            logger.info("cleanup: %s", after["cleanup"].summary())
    if config.bathymetry is not None:
        with timed("depth at the nodes") as progress:
            mesh, after["depth"] = _node_depths(config, mesh, progress)
    if config.outputs.quality:
        with timed("mesh quality"):
            from coastmesh.meshing.quality import mesh_quality

            after["quality"] = mesh_quality(mesh)
    return mesh, after


def _node_depths(config: CaseConfig, mesh: Any, progress: Progress) -> tuple[Any, Any]:
    from coastmesh.io import read_raster
    from coastmesh.meshing.depth import depth_at_nodes

    b = config.bathymetry
    raster = read_raster(b.path)
    progress(0, 2)
    if b.window is not None:
        from coastmesh.pca import simplify_raster

        raster = raster.copy(data=simplify_raster(raster.values, b.window, b.modes))
    progress(1, 2)
    depth, report = depth_at_nodes(
        mesh,
        raster,
        positive=b.positive,
        method=b.method,
        min_depth=b.min_depth,
        max_slope=b.max_slope,
    )
    progress(2, 2)
    logger.info("%s", report.summary())
    return mesh.with_point_data(depth=depth), report
