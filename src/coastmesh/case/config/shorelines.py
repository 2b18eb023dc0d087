"""``[shorelines]``, ``[shoreline_sets]``, ``[[regions]]`` and ``[domain]``."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config._check import Check
from coastmesh.errors import ConfigError

__all__ = ["DomainConfig", "RegionConfig", "ShorelineSetConfig", "ShorelinesConfig"]


@dataclass(frozen=True, slots=True)
class ShorelinesConfig:
    """``[shorelines]``: the land, from a vector file or an elevation raster.

    Attributes
    ----------
    path : path, optional
        Any vector file GDAL reads, of land polygons (e.g. GSHHG level 1).
    layer : str, optional
        The layer, if the file has several (vector files only).
    bbox : (minx, miny, maxx, maxy), optional
        Clip to this box first (read only this window of a raster), in the
        file's CRS.
    crs : str, optional
        The file's CRS, if it declares none.
    min_area : float or str
        Islands and lakes smaller than this (m², or e.g. ``"0.5 km2"``) are dropped.
    raster : path, optional
        Instead of ``path`` (exactly one of the two): any raster GDAL reads, of
        elevations or depths; the land is where the height is above ``level``
        (:func:`~coastmesh.geometry.land_from_grid`).
    level : float or str
        Rasters: the height of the coast above the raster's datum, positive up
        whatever ``positive`` is (metres, or e.g. ``"-0.5 m"``); default 0.
    positive : {"up", "down"}
        Rasters: the raster's sign, ``"up"`` for elevations (GEBCO, ETOPO),
        ``"down"`` for depths.
    """

    path: Path | None = None
    layer: str | None = None
    bbox: tuple[float, float, float, float] | None = None
    crs: str | None = None
    min_area: float = 0.0
    raster: Path | None = None
    level: float = 0.0
    positive: str = "up"

    def _checked(self, c: Check) -> ShorelinesConfig:
        if (self.path is None) == (self.raster is None):
            given = "both are given" if self.path is not None else "neither is given"
            raise c.error(
                "path",
                f"give exactly one of {c.key('path')} (a vector file of land "
                f"polygons) and {c.key('raster')} (an elevation raster); {given}",
            )
        if self.raster is not None and self.layer is not None:
            raise c.error(
                "layer", f"= {self.layer!r}: a raster has no layers (layer is for path)"
            )
        return ShorelinesConfig(
            path=c.optional(schema.path, self.path, "path"),
            layer=c.optional(schema.string, self.layer, "layer"),
            bbox=c.optional(schema.box, self.bbox, "bbox"),
            crs=c.optional(schema.crs, self.crs, "crs"),
            min_area=c(schema.area, self.min_area, "min_area"),
            raster=c.optional(schema.path, self.raster, "raster"),
            level=c(_height, self.level, "level"),
            positive=c(schema.choice(("up", "down")), self.positive, "positive"),
        )


def _height(value: Any, key: str) -> float:
    """Convert a height (metres, or a string in m or km), of either sign."""
    if not (isinstance(value, str) and value.strip().endswith("deg")):
        try:
            return schema.length(signed=True)(value, key)
        except ConfigError:
            pass
    raise ConfigError(
        f"{key} = {value!r}: expected a height in metres, e.g. 0, -1.5 or '-1.5 m'"
    )


@dataclass(frozen=True, slots=True)
class ShorelineSetConfig:
    """``[shoreline_sets.NAME]``: full resolution, or a PCA reconstruction.

    Attributes
    ----------
    name : str
        The set's name (the ``NAME`` of its table).
    physical_id : int
        The boundary id of its shoreline edges (``id`` in the file), >= 1.
    window, modes : int, optional
        PCA partition length (points) and leading modes kept; both or neither
        (full resolution).
    """

    name: str
    physical_id: int
    window: int | None = None
    modes: int | None = None

    @property
    def pca(self) -> bool:
        """Whether the set is a PCA reconstruction (window and modes given)."""
        return self.window is not None and self.modes is not None

    @property
    def label(self) -> str:
        """Describe the set, e.g. ``"PCA 1 mode / 500 points"``."""
        if self.window is None:
            return "full resolution"
        modes = "1 mode" if self.modes == 1 else f"{self.modes} modes"
        return f"PCA {modes} / {self.window} points"

    def _checked(self, c: Check) -> ShorelineSetConfig:
        window = c.optional(schema.integer(2), self.window, "window")
        modes = c.optional(schema.integer(1), self.modes, "modes")
        if (window is None) != (modes is None):
            raise c.error("window", "give window and modes together (or neither)")
        if window is not None and modes > window:
            raise c.error("modes", f"= {modes} is more than window = {window}")
        return ShorelineSetConfig(
            name=c(schema.string, self.name, "name"),
            physical_id=c(schema.integer(1), self.physical_id, "id"),
            window=window,
            modes=modes,
        )


@dataclass(frozen=True, slots=True)
class RegionConfig:
    """``[[regions]]``: where a shoreline set is used.

    Attributes
    ----------
    set : str
        The shoreline set used inside the region.
    box : (minx, miny, maxx, maxy), optional
    polygon : sequence of (x, y), optional
    path : path, optional
        Exactly one of ``box``, ``polygon`` and ``path`` (a vector file of
        polygons, with ``layer``), in the case CRS (a file may have its own).
    layer : str, optional
    """

    set: str
    box: tuple[float, float, float, float] | None = None
    polygon: tuple[tuple[float, float], ...] | None = None
    path: Path | None = None
    layer: str | None = None

    def _checked(self, c: Check) -> RegionConfig:
        given = [k for k in ("box", "polygon", "path") if getattr(self, k) is not None]
        if len(given) != 1:
            raise c.error("box", "give exactly one of box, polygon and path")
        polygon = c.optional(schema.points, self.polygon, "polygon")
        if polygon is not None and len(polygon) < 3:
            raise c.error("polygon", "needs at least three points")
        return RegionConfig(
            set=c(schema.string, self.set, "set"),
            box=c.optional(schema.box, self.box, "box"),
            polygon=polygon,
            path=c.optional(schema.path, self.path, "path"),
            layer=c.optional(schema.string, self.layer, "layer"),
        )


@dataclass(frozen=True, slots=True)
class DomainConfig:
    """``[domain]``: which sea region, seams, the surface id.

    Attributes
    ----------
    seed : (x, y), optional
        A point in the sea to mesh; default the largest sea region.
    seam_tolerance : float or str
        Slivers narrower than twice this at region seams are closed (metres).
    surface_id : int
        The physical id of the triangles.
    kind : {"regional", "global"}
        ``"global"``: the whole world ocean bounded by a world shoreline layer,
        with no open boundary, meshed through the stereographic plane whose
        singular point is ``pole``.
    pole : (lon, lat)
        Global cases: the projection's singular point, on land (default the
        South Pole).
    close : float or str, optional
        Global cases: water narrower than this between or within land, and land
        narrower than it, is closed (metres on the Earth); default the smallest
        gradation ``h_min``, so the coast can be resolved.
    """

    seed: tuple[float, float] | None = None
    seam_tolerance: float = 50.0
    surface_id: int = 1
    kind: str = "regional"
    pole: tuple[float, float] = (0.0, -90.0)
    close: float | None = None

    def _checked(self, c: Check) -> DomainConfig:
        return DomainConfig(
            seed=c.optional(schema.point, self.seed, "seed"),
            seam_tolerance=c(
                schema.length(positive=False), self.seam_tolerance, "seam_tolerance"
            ),
            surface_id=c(schema.integer(1), self.surface_id, "surface_id"),
            kind=c(schema.choice(("regional", "global")), self.kind, "kind"),
            pole=c(schema.point, self.pole, "pole"),
            close=c.optional(schema.length(), self.close, "close"),
        )
