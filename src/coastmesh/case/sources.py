"""Read ``[[bathymetry.sources]]`` into a :class:`~coastmesh.depth.DepthSources`.

Each raster is read only over the window the mesh (or size grid) needs, widened
by the source's blend; ``bbox`` and ``region`` keep the cells whose centres lie
inside them. Sources with the same explicit ``priority`` must not overlap.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely
from numpy.typing import ArrayLike
from pyproj import CRS

from coastmesh.case.config.sources import DepthSourceConfig
from coastmesh.depth.sources import check_blend, no_crs
from coastmesh.errors import ConfigError, InputDataError
from coastmesh.geometry.earth import METRES_PER_DEGREE, reproject
from coastmesh.io.raster_window import raster_extent, read_raster_around
from coastmesh.types import Progress

__all__ = ["check_rasters", "read_sources"]


def read_sources(
    configs: Sequence[DepthSourceConfig],
    points: ArrayLike,
    crs: CRS | str,
    progress: Progress | None = None,
) -> Any:
    """Read the sources (priority order) over the window ``points`` need."""
    from coastmesh.depth import DepthSource, DepthSources

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


def check_rasters(config: Any) -> None:
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


def _region(path: Any, raster: Any) -> Any:
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


def _keep_inside(raster: Any, area: Any, name: str, key: str) -> Any:
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


def _lonlat_box(c: DepthSourceConfig) -> Any:
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
