"""PCA approximation of whole shoreline layers (shapely geometry arrays).

Flatten, compute, rebuild (the pattern of ``shapely.transform``): every polygon
ring (exterior and holes) and every line becomes one contour for
:func:`coastmesh.pca.simplify_contour`; contours shorter than the window are
dropped (the paper's small-island filter); the survivors are put back into
geometries of the input's type, and polygons that the smoothing made invalid are
repaired with GEOS ``make_valid``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import InputDataError
from coastmesh.geometry.layers import check_coordinates
from coastmesh.pca import (
    check_modes,
    check_window,
    simplify_contour,
    single_threaded_blas,
)
from coastmesh.types import Progress, Report

__all__ = ["ShorelineReport", "simplify_shorelines"]

_POLYGONAL = (shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON)
_SINGLE = (
    shapely.GeometryType.POLYGON,
    shapely.GeometryType.LINESTRING,
    shapely.GeometryType.LINEARRING,
)
_LINEAR = (
    shapely.GeometryType.LINESTRING,
    shapely.GeometryType.LINEARRING,
    shapely.GeometryType.MULTILINESTRING,
)


@dataclass(frozen=True, slots=True)
class ShorelineReport(Report):
    """What :func:`simplify_shorelines` did.

    Attributes
    ----------
    features_in, features_dropped : int
        Non-empty input features, and those whose every contour was dropped.
    contours_in, contours_dropped : int
        Rings and lines in, and those shorter than the window.
    points_in, points_out : int
        Distinct vertices in and out (closing vertices of rings not counted); the
        output counts the vertices that repairs add where rings crossed.
    repaired : int
        Polygon features that were invalid after smoothing and were repaired.
    """

    features_in: int
    features_dropped: int
    contours_in: int
    contours_dropped: int
    points_in: int
    points_out: int
    repaired: int

    def summary(self) -> str:
        """Return a one-line summary."""
        return (
            f"{self.contours_in} contours in, {self.contours_dropped} dropped "
            f"(shorter than the window); {self.points_in} -> {self.points_out} points; "
            f"{self.features_in} features, {self.features_dropped} dropped, "
            f"{self.repaired} repaired"
        )


def simplify_shorelines(
    geometries: ArrayLike,
    window: int,
    modes: int,
    *,
    progress: Progress | None = None,
) -> tuple[NDArray[np.object_], ShorelineReport]:
    """Approximate every ring and line of a shoreline layer by PCA.

    Parameters
    ----------
    geometries : array_like of shapely geometries, shape (F,)
        Polygons, multipolygons, lines, multilines or linear rings; None and empty
        geometries pass through as None. A line whose first and last vertices are
        equal is a closed ring.
    window : int
        Partition size in points (the paper's segment size), ``>= 2``.
    modes : int
        Leading modes kept, ``1 <= modes <= window``.
    progress : callable, optional
        Called as ``progress(points_done, points_total)`` while contours are done.

    Returns
    -------
    geometries : ndarray of object, shape (F,)
        The approximated geometries, None where every contour of the feature was
        dropped. A polygon whose exterior is dropped is dropped with its holes.
        Polygons are valid; a polygon that smoothing split becomes a multipolygon.
    report : ShorelineReport
        Counts of contours, points, dropped and repaired features.

    Raises
    ------
    InputDataError
        If a geometry is not polygonal or linear, or has a non-finite coordinate;
        ``feature`` is the index into ``geometries``.
    ConfigError
        If ``window`` or ``modes`` is out of range.

    Examples
    --------
    >>> import shapely
    >>> ring = shapely.Point(0, 0).buffer(1.0, quad_segs=64)  # 256-point circle
    >>> island = shapely.box(3, 3, 3.1, 3.1)                  # 4 points
    >>> out, report = simplify_shorelines([ring, island], 50, 1)
    >>> out[1] is None, report.contours_dropped
    (True, 1)
    >>> bool(abs(out[0].area - ring.area) < 0.05)
    True
    """
    window = check_window(window)
    modes = check_modes(modes, window)
    geoms = np.asarray(geometries, dtype=object).ravel()
    check_coordinates(geoms)
    present = ~(shapely.is_missing(geoms) | shapely.is_empty(geoms))
    types = shapely.get_type_id(geoms)
    polygonal = present & np.isin(types, _POLYGONAL)
    linear = present & np.isin(types, _LINEAR)
    other = present & ~(polygonal | linear)
    if other.any():
        bad = int(np.flatnonzero(other)[0])
        raise InputDataError(
            f"geometry type {shapely.get_type_id(geoms[bad])} "
            f"({geoms[bad].geom_type}) is not a polygon or a line",
            feature=bad,
        )

    # Flatten: parts, then rings (polygons) or lines, then coordinates.
    parts, part_feature = shapely.get_parts(geoms, return_index=True)
    part_is_polygon = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    rings, ring_part = shapely.get_rings(parts[part_is_polygon], return_index=True)
    polygon_parts = np.flatnonzero(part_is_polygon)
    ring_part = polygon_parts[ring_part]
    lines = parts[~part_is_polygon]
    line_part = np.flatnonzero(~part_is_polygon)
    contours = np.concatenate([rings, lines])
    contour_part = np.concatenate([ring_part, line_part]).astype(np.int64)
    coords, contour_of = shapely.get_coordinates(contours, return_index=True)
    stored = np.bincount(contour_of, minlength=len(contours))
    starts = np.concatenate([[0], np.cumsum(stored)[:-1]])
    is_ring = np.zeros(len(contours), dtype=bool)
    is_ring[: len(rings)] = True
    closes = stored >= 4
    closes[closes] = np.all(
        coords[starts[closes]] == coords[starts[closes] + stored[closes] - 1], axis=1
    )
    is_ring |= closes & np.isin(
        shapely.get_type_id(contours),
        (shapely.GeometryType.LINESTRING, shapely.GeometryType.LINEARRING),
    )
    distinct = stored - is_ring  # a ring's closing vertex is not a point of its own
    keep = distinct >= window

    # Compute: one kernel call per contour that is long enough.
    total_points = int(distinct[keep].sum())
    done = 0
    new_coords: list[NDArray[np.float64]] = []
    with single_threaded_blas():
        for c in np.flatnonzero(keep):
            xy = coords[starts[c] : starts[c] + distinct[c]]
            out = simplify_contour(xy, window, modes, closed=bool(is_ring[c]))
            new_coords.append(np.vstack([out, out[:1]]) if is_ring[c] else out)
            done += len(xy)
            if progress is not None:
                progress(done, total_points)

    result = _rebuild(
        geoms, part_feature, part_is_polygon, contour_part, len(rings), keep, new_coords
    )
    result, repaired = _repair(result, polygonal, types)
    dropped_features = int((present & shapely.is_missing(result)).sum())
    report = ShorelineReport(
        features_in=int(present.sum()),
        features_dropped=dropped_features,
        contours_in=len(contours),
        contours_dropped=int((~keep).sum()),
        points_in=int(distinct.sum()),
        points_out=_count_points(result),
        repaired=repaired,
    )
    return result, report


def _count_points(geoms) -> int:
    """Distinct vertices of polygons and lines (a ring's closing vertex not counted)."""
    parts = shapely.get_parts(geoms[~shapely.is_missing(geoms)])
    polygon = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    rings = shapely.get_rings(parts[polygon])
    lines = parts[~polygon]
    closed = shapely.is_closed(lines) & (shapely.get_num_coordinates(lines) >= 4)
    return int(
        shapely.get_num_coordinates(rings).sum()
        - len(rings)
        + shapely.get_num_coordinates(lines).sum()
        - closed.sum()
    )


def _rebuild(
    geoms, part_feature, part_is_polygon, contour_part, n_rings, keep, new_coords
):
    """Put the approximated contours back into geometries of the input's types."""
    # contours: rings first, then lines, in input order
    new = np.full(len(keep), None, dtype=object)
    kept = np.flatnonzero(keep)
    result = np.full(len(geoms), None, dtype=object)
    if len(kept) == 0:
        return result
    flat = np.concatenate(new_coords)
    which = np.repeat(np.arange(len(kept)), [len(c) for c in new_coords])
    kept_is_ring = kept < n_rings
    for mask, make in (
        (kept_is_ring, shapely.linearrings),
        (~kept_is_ring, shapely.linestrings),
    ):
        if mask.any():
            rows = mask[which]
            new[kept[mask]] = make(flat[rows], indices=_dense(which[rows]))
    # parts: a polygon survives when its exterior (its first ring) survives
    new_parts = np.full(len(part_feature), None, dtype=object)
    ring_part = contour_part[:n_rings]
    ring_kept = keep[:n_rings]
    is_shell = np.r_[True, ring_part[1:] != ring_part[:-1]]
    shell_kept = np.zeros(len(part_feature), dtype=bool)
    shell_kept[ring_part[is_shell & ring_kept]] = True
    use = ring_kept & shell_kept[ring_part]
    if use.any():
        new_parts[np.unique(ring_part[use])] = shapely.polygons(
            new[:n_rings][use], indices=_dense(ring_part[use])
        )
    line_kept = keep[n_rings:]
    new_parts[contour_part[n_rings:][line_kept]] = new[n_rings:][line_kept]
    # features: single geometries stay single, multi-geometries stay multi
    alive = ~shapely.is_missing(new_parts)
    single = np.isin(shapely.get_type_id(geoms), _SINGLE)[part_feature]
    one = alive & single
    result[part_feature[one]] = new_parts[one]
    for mask, make in (
        (part_is_polygon, shapely.multipolygons),
        (~part_is_polygon, shapely.multilinestrings),
    ):
        many = alive & ~single & mask
        if many.any():
            result[np.unique(part_feature[many])] = make(
                new_parts[many], indices=_dense(part_feature[many])
            )
    return result


def _dense(ids: NDArray[np.int64]) -> NDArray[np.int64]:
    """Map sorted ids onto 0 .. k-1 (shapely's ``indices`` convention)."""
    return np.searchsorted(np.unique(ids), ids)


def _repair(result, polygonal, types):
    """Make invalid polygonal features valid; return them and how many changed.

    GEOS ``make_valid`` with the "structure" method rebuilds each polygon from its
    rings (outer rings unioned, holes subtracted), so a smoothed ring that crosses
    itself or a hole that pokes out of its shell becomes valid polygons; collapsed
    slivers (lines, points) are dropped.
    """
    check = polygonal & ~shapely.is_missing(result)
    invalid = np.zeros(len(result), dtype=bool)
    invalid[check] = ~shapely.is_valid(result[check])
    if not invalid.any():
        return result, 0
    fixed = shapely.make_valid(
        result[invalid], method="structure", keep_collapsed=False
    )
    parts, owner = shapely.get_parts(fixed, return_index=True)
    polys = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    out = np.full(len(fixed), None, dtype=object)
    if polys.any():
        out[np.unique(owner[polys])] = shapely.multipolygons(
            parts[polys], indices=_dense(owner[polys])
        )
        single = (types[invalid] == shapely.GeometryType.POLYGON) & (
            shapely.get_num_geometries(out) == 1
        )
        out[single] = shapely.get_geometry(out[single], 0)
    result = result.copy()
    result[invalid] = out
    return result, int(invalid.sum())
