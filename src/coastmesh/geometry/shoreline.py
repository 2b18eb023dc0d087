"""PCA approximation of whole shoreline layers (shapely geometry arrays).

Flatten, compute, rebuild (the pattern of ``shapely.transform``): every polygon
ring (exterior and holes) and every line becomes one contour, and all of them go
to :func:`coastmesh.pca.simplify_packed` at once (small contours in batches, the
work spread over threads; each contour comes out as
:func:`coastmesh.pca.simplify_contour` computes it, to rounding); contours
shorter than the window are dropped (the paper's small-island filter); the
survivors are put back into geometries of the input's type, and polygons that
the smoothing made invalid are repaired with GEOS ``make_valid``.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import InputDataError
from coastmesh.geometry.layers import check_coordinates
from coastmesh.pca import check_modes, check_window, check_workers, simplify_packed
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
    workers: int | None = None,
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
        Called as ``progress(points_done, points_total)`` while contours are done
        (from the calling thread).
    workers : int, optional
        Threads for the PCA and the repairs; every core by default. The result
        does not depend on it.

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
    workers = check_workers(workers)
    geoms = np.asarray(geometries, dtype=object).ravel()
    present, types, polygonal = _check_types(geoms)

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
    coords = shapely.get_coordinates(contours)
    if not np.isfinite(coords).all():
        check_coordinates(geoms)  # names the feature and its vertex
    stored = shapely.get_num_coordinates(contours).astype(np.int64)
    starts = np.cumsum(stored) - stored
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

    # Compute: the short contours in batches, the long ones one by one, on threads.
    out = simplify_packed(
        coords,
        starts,
        distinct,
        window,
        modes,
        closed=is_ring,
        workers=workers,
        progress=progress,
        out=coords,  # in place: the input coordinates are not needed after
    )
    closing = keep & is_ring
    out[starts[closing] + distinct[closing]] = out[starts[closing]]

    alive = _surviving(contour_part, len(rings), keep, len(parts))
    result = _rebuild(geoms, part_feature, contour_part, len(rings), alive, out, stored)
    result, repaired = _repair(result, polygonal, types, workers)
    # points out: the surviving contours, except in repaired features (recounted)
    counted = alive & ~repaired[part_feature[contour_part]]
    closed_out = stored >= 4  # and first == last: the closing vertex is no point
    last = (starts + stored - 1)[closed_out]
    closed_out[closed_out] = np.all(out[starts[closed_out]] == out[last], axis=1)
    closed_out[: len(rings)] = True
    report = ShorelineReport(
        features_in=int(present.sum()),
        features_dropped=int((present & shapely.is_missing(result)).sum()),
        contours_in=len(contours),
        contours_dropped=int((~keep).sum()),
        points_in=int(distinct.sum()),
        points_out=int((stored - closed_out)[counted].sum())
        + _count_points(result[repaired]),
        repaired=int(repaired.sum()),
    )
    return result, report


def _check_types(
    geoms: NDArray[np.object_],
) -> tuple[NDArray[np.bool_], NDArray[np.int64], NDArray[np.bool_]]:
    """Return which features are present, their type ids, and which are polygonal.

    Raises
    ------
    InputDataError
        If a present feature is neither polygonal nor linear (after naming any
        non-finite coordinate first); ``feature`` is its index.
    """
    present = ~(shapely.is_missing(geoms) | shapely.is_empty(geoms))
    types = shapely.get_type_id(geoms)
    polygonal = present & np.isin(types, _POLYGONAL)
    linear = present & np.isin(types, _LINEAR)
    other = present & ~(polygonal | linear)
    if other.any():
        check_coordinates(geoms)  # a bad coordinate is named first
        bad = int(np.flatnonzero(other)[0])
        raise InputDataError(
            f"geometry type {shapely.get_type_id(geoms[bad])} "
            f"({geoms[bad].geom_type}) is not a polygon or a line",
            feature=bad,
        )
    return present, types, polygonal


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


def _surviving(contour_part, n_rings, keep, n_parts):
    """Contours in the output: kept lines, kept rings of polygons whose shell is kept.

    A polygon's exterior is its first ring; contours are rings first, then lines.
    """
    ring_part = contour_part[:n_rings]
    ring_kept = keep[:n_rings]
    is_shell = np.r_[True, ring_part[1:] != ring_part[:-1]]
    shell_kept = np.zeros(n_parts, dtype=bool)
    shell_kept[ring_part[is_shell & ring_kept]] = True
    return np.r_[ring_kept & shell_kept[ring_part], keep[n_rings:]]


def _rebuild(geoms, part_feature, contour_part, n_rings, alive, coords, stored):
    """Put the surviving contours back into geometries of the input's types.

    ``coords`` holds the new vertices of the contours (closing vertices included)
    back to back, ``stored`` the rows of each contour. Contours are rings first,
    then lines.
    """
    result = np.full(len(geoms), None, dtype=object)
    feature_type = shapely.get_type_id(geoms)
    ring_part = contour_part[:n_rings]
    use = alive[:n_rings]
    ring_rows = int(stored[:n_rings].sum())
    in_multi = (
        feature_type[part_feature[ring_part]] == shapely.GeometryType.MULTIPOLYGON
    )
    for multi in (False, True):
        chosen = use & (in_multi == multi)
        rings = np.flatnonzero(chosen)
        if len(rings) == 0:
            continue
        # from the flat coordinates in one pass: GEOS copies them once
        xy = coords[:ring_rows][np.repeat(chosen, stored[:n_rings])]
        parts, first_ring = np.unique(ring_part[rings], return_index=True)
        offsets = [_offsets(stored[rings]), np.r_[first_ring, len(rings)]]
        features, first_part = np.unique(part_feature[parts], return_index=True)
        if multi:
            offsets.append(np.r_[first_part, len(parts)])
            kind = shapely.GeometryType.MULTIPOLYGON
        else:
            kind = shapely.GeometryType.POLYGON
        result[features] = shapely.from_ragged_array(kind, xy, tuple(offsets))
    # lines, as few as there usually are
    line_kept = alive[n_rings:]
    if not line_kept.any():
        return result
    rows = np.repeat(line_kept, stored[n_rings:])
    sizes = stored[n_rings:][line_kept]
    new = shapely.linestrings(
        coords[ring_rows:][rows], indices=np.repeat(np.arange(len(sizes)), sizes)
    )
    line_part = contour_part[n_rings:][line_kept]
    single = np.isin(feature_type[part_feature[line_part]], _SINGLE)
    result[part_feature[line_part[single]]] = new[single]
    many = ~single
    if many.any():
        owners = part_feature[line_part[many]]
        result[np.unique(owners)] = shapely.multilinestrings(
            new[many], indices=_dense(owners)
        )
    return result


def _offsets(sizes: NDArray[np.int64]) -> NDArray[np.int64]:
    return np.r_[0, np.cumsum(sizes)]


def _dense(ids: NDArray[np.int64]) -> NDArray[np.int64]:
    """Map sorted ids onto 0 .. k-1 (shapely's ``indices`` convention)."""
    return np.searchsorted(np.unique(ids), ids)


def _repair(result, polygonal, types, workers=1):
    """Make invalid polygonal features valid; return them and which changed.

    GEOS ``make_valid`` with the "structure" method rebuilds each polygon from its
    rings (outer rings unioned, holes subtracted), so a smoothed ring that crosses
    itself or a hole that pokes out of its shell becomes valid polygons; collapsed
    slivers (lines, points) are dropped. A polygon stays a polygon if it is still
    one piece; a multipolygon stays a multipolygon.
    """
    check = polygonal & ~shapely.is_missing(result)
    invalid = np.zeros(len(result), dtype=bool)
    invalid[check] = ~shapely.is_valid(result[check])
    if not invalid.any():
        return result, invalid
    fixed = _make_valid(result[invalid], workers)
    kind = shapely.get_type_id(fixed)
    was_polygon = types[invalid] == shapely.GeometryType.POLYGON
    out = np.full(len(fixed), None, dtype=object)
    # the usual cases need no copy: the type is already the one to return
    same = (kind == shapely.GeometryType.POLYGON) & was_polygon
    same |= (kind == shapely.GeometryType.MULTIPOLYGON) & ~was_polygon
    same &= ~shapely.is_empty(fixed)
    out[same] = fixed[same]
    rest = np.flatnonzero(~same)
    parts, owner = shapely.get_parts(fixed[rest], return_index=True)
    polys = shapely.get_type_id(parts) == shapely.GeometryType.POLYGON
    if polys.any():
        rebuilt = np.full(len(rest), None, dtype=object)
        rebuilt[np.unique(owner[polys])] = shapely.multipolygons(
            parts[polys], indices=_dense(owner[polys])
        )
        single = was_polygon[rest] & (shapely.get_num_geometries(rebuilt) == 1)
        rebuilt[single] = shapely.get_geometry(rebuilt[single], 0)
        out[rest] = rebuilt
    result = result.copy()
    result[invalid] = out
    return result, invalid


def _make_valid(geoms, workers):
    """GEOS ``make_valid`` ("structure") of each geometry, over ``workers`` threads.

    The geometries are dealt out by size (largest first, to the least loaded
    thread); each is repaired on its own, so the split does not change the result.
    """

    def repair(part):
        return shapely.make_valid(part, method="structure", keep_collapsed=False)

    if workers == 1 or len(geoms) < 2:
        return repair(geoms)
    sizes = shapely.get_num_coordinates(geoms)
    shares: list[list[int]] = [[] for _ in range(workers)]
    loads = np.zeros(workers)
    for k in np.argsort(-sizes, kind="stable").tolist():
        least = int(np.argmin(loads))
        shares[least].append(k)
        loads[least] += sizes[k]
    out = np.empty(len(geoms), dtype=object)
    with ThreadPoolExecutor(max_workers=workers) as pool:
        for share, done in zip(
            shares, pool.map(lambda k: repair(geoms[k]), shares), strict=True
        ):
            out[share] = done
    return out
