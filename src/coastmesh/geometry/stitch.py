"""Stitching shoreline sets: each region of the model takes its own shoreline.

The paper builds one domain from several versions of the same coast: full
resolution near the sites of interest and PCA reconstructions further away. Here
each :class:`ShorelineSet` owns a region; regions are made disjoint in the order
given (an earlier set wins where regions overlap) and the one set without a region
takes everything else. Each set's land is clipped to its region and the pieces are
unioned; the pieces that meet along a seam are unioned on a fixed precision grid
(GEOS snap-rounding), so they share the seam's vertices exactly: no gaps and no
overlaps between them.

Where two versions of the coast meet at a seam they differ by the PCA error, so the
seam can leave thin sea channels or thin land strips along the region boundary.
With ``tolerance > 0``, sea and land narrower than ``2 * tolerance`` that touch a
seam are found by a morphological opening (buffer in, buffer out) within a band of
``2 * tolerance`` around the seams: sea slivers are filled and land slivers
removed. Nothing away from the seams changes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError
from coastmesh.geometry.earth import metres_per_unit
from coastmesh.geometry.layers import valid_polygons
from coastmesh.geometry.unions import union_meeting
from coastmesh.types import Report

__all__ = ["ShorelineSet", "StitchReport", "stitch_shorelines"]

# A degree of latitude, near enough for a sliver width. Rounded: METRES_PER_DEGREE
# (7e-7 shorter) would move the seams' sliver cleanup, and the meshes, a little.
_METRES_PER_DEGREE = 111_195.0


@dataclass(frozen=True, slots=True)
class ShorelineSet:
    """One version of the coastline and the region where it is used.

    Parameters
    ----------
    name : str
        The set's name (it names the boundary segments it produces).
    land : array_like of shapely polygons
        Land polygons, in the CRS of the stitch.
    physical_id : int
        Boundary id of the shoreline edges from this set, ``> 0``.
    region : shapely geometry, optional
        Where this set is used (polygonal). ``None`` for the background set, which
        is used everywhere no other set's region reaches.
    """

    name: str
    land: NDArray[np.object_]
    physical_id: int
    region: shapely.Geometry | None = None

    def __post_init__(self) -> None:
        land = np.asarray(self.land, dtype=object).ravel()
        object.__setattr__(self, "land", land)
        if isinstance(self.physical_id, bool) or int(self.physical_id) <= 0:
            raise ConfigError(
                f"shoreline set {self.name!r}: physical_id = {self.physical_id!r} "
                "must be an integer > 0"
            )
        if self.region is not None:
            if shapely.get_dimensions(self.region) != 2 or self.region.is_empty:
                raise ConfigError(
                    f"shoreline set {self.name!r}: its region must be a non-empty "
                    f"polygon, got {self.region.geom_type}"
                )
            if not self.region.is_valid:
                object.__setattr__(self, "region", shapely.make_valid(self.region))


@dataclass(frozen=True, slots=True)
class StitchReport(Report):
    """What :func:`stitch_shorelines` did.

    Attributes
    ----------
    polygons : dict of str to int
        Land polygons of each set after clipping to its region, by set name.
    seam_length : float
        Length of the seams between the regions, in CRS units (0 with one set).
    sea_slivers_filled : int
        Thin sea channels along the seams that were filled with land.
    land_slivers_removed : int
        Thin land strips along the seams that were removed.
    """

    polygons: dict[str, int] = field(default_factory=dict)
    seam_length: float = 0.0
    sea_slivers_filled: int = 0
    land_slivers_removed: int = 0

    def summary(self) -> str:
        """Return a one-line summary."""
        sets = ", ".join(f"{k}: {v}" for k, v in self.polygons.items())
        return (
            f"land polygons per set after clipping ({sets}); "
            f"{self.sea_slivers_filled} sea slivers filled and "
            f"{self.land_slivers_removed} land slivers removed at the seams"
        )


def stitch_shorelines(
    sets: Sequence[ShorelineSet],
    *,
    crs: CRS | str,
    tolerance: float = 0.0,
) -> tuple[
    NDArray[np.object_], list[tuple[str, int, shapely.Geometry | None]], StitchReport
]:
    """Join shoreline sets, each within its region, into one land geometry.

    Parameters
    ----------
    sets : sequence of ShorelineSet
        Earlier sets win where regions overlap; exactly one set has no region.
    crs : pyproj.CRS or str
        CRS of the land and regions.
    tolerance : float
        Sliver width, metres (see the module notes); 0 turns the cleanup off.

    Returns
    -------
    land : ndarray of shapely polygons
        The stitched land, valid and non-overlapping.
    regions : list of (name, physical_id, region)
        The disjoint regions actually used, in priority order, for tagging the
        domain boundary (``region`` is None for the background set); pass it to
        :func:`~coastmesh.geometry.build_domain` as ``shorelines``.
    report : StitchReport

    Raises
    ------
    ConfigError
        If no set or more than one set lacks a region, or names repeat.

    Examples
    --------
    >>> import shapely
    >>> coarse = ShorelineSet("coarse", [shapely.box(0, 0, 10, 1)], 11)
    >>> fine = ShorelineSet("fine", [shapely.box(0, 0, 10, 1.2)], 10,
    ...                     region=shapely.box(4, -5, 6, 5))
    >>> land, regions, report = stitch_shorelines([fine, coarse], crs="EPSG:3857")
    >>> round(float(shapely.area(land).sum()), 6), [r[0] for r in regions]
    (10.4, ['fine', 'coarse'])
    """
    crs = CRS.from_user_input(crs)
    names = [s.name for s in sets]
    if len(set(names)) != len(names):
        raise ConfigError(f"shoreline sets: names repeat in {names}")
    background = [s for s in sets if s.region is None]
    if len(background) != 1:
        raise ConfigError(
            "shoreline sets: exactly one set must have no region (it is used "
            f"everywhere else); got {len(background)}: "
            f"{[s.name for s in background] or 'none'}"
        )
    if not tolerance >= 0:
        raise ConfigError(f"seam tolerance = {tolerance}: must be >= 0 metres")
    grid = _grid_size(sets)
    claimed: shapely.Geometry = shapely.Polygon()
    regions: list[tuple[str, int, shapely.Geometry | None]] = []
    pieces: list[NDArray[np.object_]] = []
    counts: dict[str, int] = {}
    for s in [*[s for s in sets if s.region is not None], background[0]]:
        land = valid_polygons(s.land)
        if s.region is None:
            mine = None
            clipped = shapely.difference(land, claimed) if len(land) else land
        else:
            mine = shapely.difference(s.region, claimed)
            if mine.is_empty:
                continue
            claimed = shapely.union(claimed, mine)
            tree = shapely.STRtree(land)
            land = land[tree.query(mine, predicate="intersects")]
            clipped = shapely.intersection(land, mine)
        clipped = valid_polygons(clipped)
        counts[s.name] = len(clipped)
        pieces.append(clipped)
        regions.append((s.name, int(s.physical_id), mine))
    everything = np.concatenate(pieces) if pieces else np.empty(0, dtype=object)
    seams = shapely.boundary(claimed) if not claimed.is_empty else None
    land_union = _union(everything, seams, grid)
    filled = removed = 0
    if tolerance > 0 and seams is not None and not land_union.is_empty:
        land_union, filled, removed = _clean_seams(land_union, seams, tolerance, crs)
    return (
        valid_polygons(np.array([land_union], dtype=object)),
        regions,
        StitchReport(
            polygons=counts,
            seam_length=0.0 if seams is None else float(seams.length),
            sea_slivers_filled=filled,
            land_slivers_removed=removed,
        ),
    )


def _union(
    pieces: NDArray[np.object_], seams: shapely.Geometry | None, grid: float
) -> shapely.Geometry:
    """Union the pieces; those that meet at a seam on the precision grid.

    Snap-rounding costs about 20 times a floating overlay, and only pieces that
    touch a seam share near-coincident edges, so only they are snapped. Of
    the rest, only those that meet are overlaid (:func:`union_meeting`).
    """
    if seams is None or len(pieces) == 0:
        return shapely.multipolygons(union_meeting(pieces))
    touch = shapely.dwithin(pieces, seams, 2 * grid)
    seamed = shapely.union_all(pieces[touch], grid_size=grid)
    return shapely.multipolygons(union_meeting([seamed, *pieces[~touch]]))


def _grid_size(sets: Sequence[ShorelineSet]) -> float:
    """Return a precision grid far below any coastline detail: ~1e-9 of the extent."""
    bounds = [shapely.total_bounds(s.land) for s in sets if len(s.land)]
    bounds = [b for b in bounds if np.isfinite(b).all()]
    if not bounds:
        return 0.0
    b = np.array(bounds)
    extent = max(b[:, 2].max() - b[:, 0].min(), b[:, 3].max() - b[:, 1].min(), 1e-12)
    return 10.0 ** math.floor(math.log10(extent * 1e-9))


def _clean_seams(
    land: shapely.Geometry, seams: shapely.Geometry, tolerance: float, crs: CRS
) -> tuple[shapely.Geometry, int, int]:
    """Fill sea and remove land narrower than 2 tolerance where it meets a seam."""
    scale_x = 1.0
    if crs.is_geographic:
        # work in a local frame where a degree of longitude is as long as one of
        # latitude, so the buffers are round on the ground
        lat = shapely.centroid(seams).y
        scale_x = max(math.cos(math.radians(lat)), 1e-3)
        tolerance /= _METRES_PER_DEGREE
    else:
        tolerance /= metres_per_unit(crs)

    def local(g: shapely.Geometry, inverse: bool = False) -> shapely.Geometry:
        factor = 1.0 / scale_x if inverse else scale_x
        return shapely.transform(g, lambda xy: xy * [factor, 1.0])

    land_l, seams_l = local(land), local(seams)
    band = shapely.buffer(seams_l, 2 * tolerance)
    touch = shapely.buffer(seams_l, 1e-6 * tolerance)

    def thin(area: shapely.Geometry) -> NDArray[np.object_]:
        opened = shapely.buffer(shapely.buffer(area, -tolerance), tolerance)
        rest = valid_polygons([shapely.difference(area, opened)])
        # drop the rounding residue buffers leave along straight edges
        rest = rest[shapely.area(rest) > 1e-6 * tolerance**2]
        return rest[shapely.intersects(rest, touch)]

    sea_slivers = thin(shapely.difference(band, land_l))
    if len(sea_slivers):
        land_l = shapely.union_all([land_l, *sea_slivers])
    land_slivers = thin(shapely.intersection(band, land_l))
    if len(land_slivers):
        land_l = shapely.difference(land_l, shapely.union_all(land_slivers))
    return local(land_l, inverse=True), len(sea_slivers), len(land_slivers)
