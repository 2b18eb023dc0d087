"""A raster of depths, or a stack of them: ``path`` or ``[[...sources]]``.

``[bathymetry]`` (depth at the nodes) and ``[mesh_size.bathymetry]`` (size terms)
both take one raster (``path``, ``positive``) or a stack of rasters, highest
priority first (``[[bathymetry.sources]]``): a node takes the first source with
a valid value there, blended into the next across ``blend`` inside the edge of
the source's data (:class:`coastmesh.depth.DepthSources`).

These parts live beside :mod:`coastmesh.case.config` and
:mod:`coastmesh.case.terms`, not in either: both use them, and neither
imports the other's way back (the ``acyclic_siblings`` contract).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Self

from coastmesh.case import schema
from coastmesh.case.schema import Check, key

__all__ = ["UP_DOWN", "DepthSourceConfig", "RasterConfig"]

#: A raster's sign: ``"up"`` for elevations (GEBCO, ETOPO), ``"down"`` for depths.
UP_DOWN = ("up", "down")
_SIGN_DOC = (
    'the raster\'s sign: `"up"` for elevations (GEBCO, ETOPO), `"down"` for depths'
)


@dataclass(frozen=True)
class DepthSourceConfig:
    """One ``[[bathymetry.sources]]`` entry: a raster of a stack, where it counts."""

    path: Path = key(
        check=schema.path, path=True, doc="any raster GDAL reads, with a CRS"
    )
    positive: str = key("up", check=schema.choice(UP_DOWN), doc=_SIGN_DOC)
    bbox: tuple[float, float, float, float] | None = key(
        None,
        check=schema.box,
        doc="`[minx, miny, maxx, maxy]` in the raster's CRS: only cells whose "
        "centres lie inside are used",
    )
    region: Path | None = key(
        None,
        check=schema.path,
        path=True,
        doc="a vector file of polygons (any CRS): only cells whose centres lie "
        "inside are used",
    )
    blend: float = key(
        0.0,
        check=schema.length(positive=False),
        unit="length",
        doc="the width of the ramp inside the edge of this source's data; less "
        "than half the source's extent",
    )
    priority: int | None = key(
        None,
        check=schema.integer(-(10**9)),
        doc="integers, higher first, on every source or on none (then the list "
        "order is the priority); sources with the same priority must not overlap",
    )

    def _validate(self, c: Check) -> DepthSourceConfig:
        if self.bbox is not None and self.region is not None:
            raise c.error("region", "give bbox or region, not both")
        return self


@dataclass(frozen=True)
class RasterConfig:
    """One raster (``path``, ``positive``) or a stack of them (``sources``).

    The base of ``[bathymetry]`` and ``[mesh_size.bathymetry]``: exactly one of
    ``path`` and ``sources``; the sources come out in priority order.
    """

    path: Path | None = key(
        None,
        check=schema.path,
        path=True,
        default_doc="one of `path` and `sources`",
        doc="any raster GDAL reads (GeoTIFF, GEBCO-style NetCDF), in any CRS",
    )
    positive: str = key("up", check=schema.choice(UP_DOWN), doc=_SIGN_DOC)
    sources: tuple[DepthSourceConfig, ...] = key(
        (),
        part=DepthSourceConfig,
        many=True,
        default_doc="none",
        doc="several rasters instead of `path`, highest priority first (below)",
    )

    @property
    def stack(self) -> tuple[DepthSourceConfig, ...]:
        """The sources in priority order: ``path`` makes one."""
        if self.sources:
            return self.sources
        assert self.path is not None  # _validate: exactly one of path and sources
        return (DepthSourceConfig(self.path, self.positive),)

    def _validate(self, c: Check) -> Self:
        """Exactly one of ``path`` and ``sources``; the sources by priority."""
        if self.path is not None and self.sources:
            raise c.error("sources", "give path (one raster) or sources, not both")
        if self.path is None and not self.sources:
            raise c.error("path", "give the raster's path, or [[...sources]]")
        given = [s.priority is not None for s in self.sources]
        if any(given) and not all(given):
            raise c.error(
                "sources",
                "give priority on every source or on none (the list order is then "
                "the priority, highest first)",
            )
        ordered = self.sources
        if ordered and all(given):
            # every source has a priority here (all(given))
            ordered = tuple(sorted(ordered, key=lambda s: -(s.priority or 0)))
        paths = [s.path for s in ordered]
        for k, p in enumerate(paths):
            if p in paths[:k]:
                raise c.error(f"sources[{k}]", f"path = {str(p)!r} is listed twice")
        return replace(self, sources=ordered)
