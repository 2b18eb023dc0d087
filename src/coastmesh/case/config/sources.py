"""``[[bathymetry.sources]]`` and ``[[mesh_size.bathymetry.sources]]``.

A stack of bathymetry rasters, highest priority first: a node takes the first
source with a valid value there, blended into the next across ``blend`` inside
the edge of the source's data (:class:`coastmesh.depth.DepthSources`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config._check import Check, check_parts

__all__ = ["DepthSourceConfig", "check_sources", "stack_of"]

_UP_DOWN = ("up", "down")


@dataclass(frozen=True, slots=True)
class DepthSourceConfig:
    """One ``[[bathymetry.sources]]`` entry.

    Attributes
    ----------
    path : path
        Any raster GDAL reads, in any CRS (the nodes are reprojected to it).
    positive : {"up", "down"}
        The raster's sign: ``"up"`` for elevations (GEBCO, ETOPO).
    bbox : (minx, miny, maxx, maxy), optional
        Use only the cells whose centres lie in this box, in the raster's CRS.
    region : path, optional
        Use only the cells whose centres lie in these polygons (any vector file
        with a CRS; reprojected to the raster's).
    blend : float or str
        Distance inside the edge of the source's valid data over which it
        blends into the sources below (metres; ``"2 km"``); 0 for a hard seam.
    priority : int, optional
        Higher first. Without it the list order is the priority; with it on
        every source, sources with equal priority must not overlap.
    """

    path: Path
    positive: str = "up"
    bbox: tuple[float, float, float, float] | None = None
    region: Path | None = None
    blend: float = 0.0
    priority: int | None = None

    def _checked(self, c: Check) -> DepthSourceConfig:
        if self.bbox is not None and self.region is not None:
            raise c.error("region", "give bbox or region, not both")
        return DepthSourceConfig(
            path=c(schema.path, self.path, "path"),
            positive=c(schema.choice(_UP_DOWN), self.positive, "positive"),
            bbox=c.optional(schema.box, self.bbox, "bbox"),
            region=c.optional(schema.path, self.region, "region"),
            blend=c(schema.length(positive=False), self.blend, "blend"),
            priority=c.optional(schema.integer(-(10**9)), self.priority, "priority"),
        )


def check_sources(
    c: Check, path: Any, positive: str, sources: Any
) -> tuple[Path | None, tuple[DepthSourceConfig, ...]]:
    """Check ``path`` (one raster) or ``sources`` (a stack): exactly one of them.

    Returns the path (None with sources) and the sources in priority order
    (none when ``path`` is given: :func:`stack_of` makes its one source).
    """
    if path is not None and sources:
        raise c.error("sources", "give path (one raster) or sources, not both")
    if path is None and not sources:
        raise c.error("path", "give the raster's path, or [[...sources]]")
    if path is not None:
        return DepthSourceConfig(path, positive)._checked(c).path, ()
    checked = check_parts(sources, DepthSourceConfig, c, "sources")
    given = [s.priority is not None for s in checked]
    if any(given) and not all(given):
        raise c.error(
            "sources",
            "give priority on every source or on none (the list order is then "
            "the priority, highest first)",
        )
    if all(given):
        order = sorted(range(len(checked)), key=lambda k: -checked[k].priority)
        checked = tuple(checked[k] for k in order)
    paths = [s.path for s in checked]
    for k, p in enumerate(paths):
        if p in paths[:k]:
            raise c.error(f"sources[{k}]", f"path = {str(p)!r} is listed twice")
    return None, checked


def stack_of(part: Any) -> tuple[DepthSourceConfig, ...]:
    """Return the sources of a checked ``[bathymetry]``-like part, in priority order."""
    if part.sources:
        return part.sources
    return (DepthSourceConfig(part.path, part.positive),)
