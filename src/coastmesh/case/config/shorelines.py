"""``[shorelines]``, ``[shoreline_sets]``, ``[[regions]]`` and ``[domain]``."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Protocol, TypeVar

from coastmesh.case import schema
from coastmesh.case.config.kinds import DEFAULT_KIND, DOMAIN_KINDS, domain_kind
from coastmesh.case.schema import Check, key
from coastmesh.errors import ConfigError

__all__ = ["DomainConfig", "RegionConfig", "ShorelineSetConfig", "ShorelinesConfig"]

_UP_DOWN = ("up", "down")


def _height(value: object, key: str) -> float:
    """Convert a height (metres, or a string in m or km), of either sign."""
    if not (isinstance(value, str) and value.strip().endswith("deg")):
        try:
            return schema.length(signed=True)(value, key)
        except ConfigError:
            pass
    raise ConfigError(
        f"{key} = {value!r}: expected a height in metres, e.g. 0, -1.5 or '-1.5 m'"
    )


@dataclass(frozen=True)
class ShorelinesConfig:
    """``[shorelines]``: the land, from a vector file or an elevation raster.

    Exactly one of ``path`` and ``raster``; ``level`` and ``positive`` are for
    a raster. The keys and their defaults are listed in ``docs/case-files.md``.
    """

    path: Path | None = key(
        None,
        check=schema.path,
        path=True,
        default_doc="`path` or `raster`",
        doc="any vector file GDAL reads (GeoPackage, shapefile, GeoJSON) of land "
        "polygons, e.g. GSHHG level 1",
    )
    layer: str | None = key(
        None,
        check=schema.string,
        default_doc="the only layer",
        doc="the layer name (`path` only)",
    )
    bbox: tuple[float, float, float, float] | None = key(
        None,
        check=schema.box,
        doc="`[minx, miny, maxx, maxy]`: read only this box (of a raster, only "
        "this window), in the file's CRS",
    )
    crs: str | None = key(
        None,
        check=schema.crs,
        default_doc="the file's",
        doc="the CRS to assume if the file declares none",
    )
    min_area: float = key(
        0.0,
        check=schema.area,
        unit="area",
        default_doc="`0`; global cases: a disk of `[domain] close`",
        doc="islands and lakes smaller than this are dropped (geodesic area); a "
        "global case keeps every island of this area or more whole",
    )
    raster: Path | None = key(
        None,
        check=schema.path,
        path=True,
        default_doc="`path` or `raster`",
        doc="instead of `path`: a raster of elevations or depths; the land is "
        "contoured from it (below)",
    )
    level: float = key(
        0.0,
        check=_height,
        read=_height,
        dump=lambda v: f"{v!r} m",
        default_doc='`"0 m"`',
        doc="`raster` only: the height of the coast above the raster's datum, "
        'positive up whatever `positive` is: the land is above it (`"2 m"`, '
        '`"-0.5 m"`, or a number of metres)',
    )
    positive: str = key(
        "up",
        check=schema.choice(_UP_DOWN),
        doc='`raster` only: the raster\'s sign, `"up"` for elevations (GEBCO, '
        'ETOPO), `"down"` for depths',
    )

    @classmethod
    def _read(
        cls, t: schema.Table, reading: schema.Reading, **given: object
    ) -> ShorelinesConfig:
        """``level`` and ``positive`` are for a raster: refused with ``path``."""
        contour = [k for k in ("level", "positive") if t.has(k)]
        if contour and not t.has("raster"):
            raise t.error(contour[0], "is for a raster shoreline (raster = PATH)")
        values = schema.read_keys(cls, t, reading)
        t.done()
        return schema.unchecked_part(cls, values)

    def _validate(self, c: Check) -> ShorelinesConfig:
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
        return self

    def _dump(self) -> dict[str, object]:
        """Return the keys; the raster's keys only with a raster."""
        out = schema.dump_keys(self)
        if self.raster is None:
            out.pop("level", None)
            out.pop("positive", None)
        return out


@dataclass(frozen=True)
class ShorelineSetConfig:
    """``[shoreline_sets.NAME]``: full resolution, or a PCA reconstruction.

    ``name`` is the ``NAME`` of its table; ``physical_id`` is ``id`` in the file.
    ``window`` and ``modes``: both (a PCA reconstruction) or neither (full
    resolution).
    """

    name: str
    physical_id: int = key(
        name="id",
        check=schema.integer(1),
        doc="the boundary id of the shoreline edges from this set",
    )
    window: int | None = key(
        None,
        check=schema.integer(2),
        default_doc="full resolution",
        doc="PCA partition size, in points",
    )
    modes: int | None = key(
        None,
        check=schema.integer(1),
        default_doc="full resolution",
        doc="leading modes kept (`1 <= modes <= window`)",
    )

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

    def _validate(self, c: Check) -> ShorelineSetConfig:
        if (self.window is None) != (self.modes is None):
            raise c.error("window", "give window and modes together (or neither)")
        if (
            self.modes is not None
            and self.window is not None
            and self.modes > self.window
        ):
            raise c.error(
                "modes", f"= {self.modes} is more than window = {self.window}"
            )
        return replace(self, name=c(schema.string, self.name, "name"))


class _Area(Protocol):
    """A place given as a box, a polygon or a file: a region or a site."""

    @property
    def box(self) -> tuple[float, float, float, float] | None: ...
    @property
    def polygon(self) -> tuple[tuple[float, float], ...] | None: ...
    @property
    def path(self) -> Path | None: ...


_A = TypeVar("_A", bound=_Area)


def _one_area(part: _A, c: Check) -> _A:
    """Exactly one of ``box``, ``polygon`` (three points or more) and ``path``."""
    given = [k for k in ("box", "polygon", "path") if getattr(part, k) is not None]
    if len(given) != 1:
        raise c.error("box", "give exactly one of box, polygon and path")
    if part.polygon is not None and len(part.polygon) < 3:
        raise c.error("polygon", "needs at least three points")
    return part


@dataclass(frozen=True)
class RegionConfig:
    """``[[regions]]``: where a shoreline set is used.

    Exactly one of ``box``, ``polygon`` and ``path`` (a vector file of polygons,
    with ``layer``), in the case CRS (a file may have its own).
    """

    set: str = key(check=schema.string, doc="the shoreline set's name")
    box: tuple[float, float, float, float] | None = key(
        None, check=schema.box, doc="`[minx, miny, maxx, maxy]`"
    )
    polygon: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[x, y]` points"
    )
    path: Path | None = schema.file_key("a vector file of polygons")
    layer: str | None = schema.layer_key()

    def _validate(self, c: Check) -> RegionConfig:
        return _one_area(self, c)


@dataclass(frozen=True)
class SiteConfig:
    """``[[sites]]``: a region the user meshes finely on purpose (a tidal site).

    Inside a site, narrow channels are kept (with at least two elements across,
    below the floor ``h_min`` if need be) rather than closed, and the Courant
    floor of ``dt = "auto"`` does not apply: the user's sizes win, and the
    quality report names the elements that then set the time step. Exactly one
    of ``box`` and ``polygon`` (lon/lat, as the seed and open boundaries) and
    ``path`` (a vector file of polygons in its own CRS, with ``layer``).
    """

    name: str = key(check=schema.string, doc="names the site in reports")
    box: tuple[float, float, float, float] | None = key(
        None, check=schema.box, doc="`[lon_min, lat_min, lon_max, lat_max]`"
    )
    polygon: tuple[tuple[float, float], ...] | None = key(
        None, check=schema.points, doc="a list of `[lon, lat]` points"
    )
    path: Path | None = schema.file_key("a vector file of polygons")
    layer: str | None = schema.layer_key()

    def _validate(self, c: Check) -> SiteConfig:
        return _one_area(self, c)


@dataclass(frozen=True)
class DomainConfig:
    """``[domain]``: which sea region, seams, the surface id; a global case.

    ``kind = "global"`` meshes the whole world ocean bounded by a world
    shoreline layer, through the stereographic plane whose singular point is
    ``pole`` (docs/global.md).
    """

    seed: tuple[float, float] | None = key(
        None,
        check=schema.point,
        default_doc="the largest sea region",
        doc="`[x, y]` of a point in the wanted sea region",
    )
    seam_tolerance: float = key(
        50.0,
        check=schema.length(positive=False),
        unit="length",
        doc='half the width of the slivers removed at seams; `"0 m"` turns it off',
    )
    surface_id: int = key(
        1, check=schema.integer(1), doc="the physical id of the triangles"
    )
    kind: str = key(
        DEFAULT_KIND,
        check=schema.choice(tuple(DOMAIN_KINDS)),
        doc='`"global"`: the whole world ocean, no open boundary ([global.md]'
        "(global.md))",
    )
    pole: tuple[float, float] = key(
        (0.0, -90.0),
        check=schema.point,
        doc="global cases: the stereographic plane's singular point, on land",
    )
    close: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="the smallest gradation `h_min`",
        doc="global cases: water, and land smaller than `[shorelines] min_area`, "
        "narrower than this on the Earth are closed; larger land's thin parts "
        "are thickened to it",
    )

    def _dump(self) -> dict[str, object]:
        """Return the keys, less those only another kind of case writes.

        A regional domain's are without ``kind``, ``pole`` and ``close``
        (:attr:`~coastmesh.case.config.kinds.DomainKind.keys`).
        """
        out = schema.dump_keys(self)
        own = domain_kind(self.kind).keys
        for kind in DOMAIN_KINDS.values():
            for name in kind.keys:
                if name not in own:
                    out.pop(name, None)
        return out
