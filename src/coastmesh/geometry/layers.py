"""Shoreline layers as geometry arrays: checks, repairs, and densifying before PCA.

:func:`check_coordinates` and :func:`land_polygons` check a layer as read;
:func:`valid_polygons` turns any polygonal geometries into valid single polygons;
:func:`densify_long_edges` splits the long straight edges that clipping leaves,
before :func:`~coastmesh.geometry.simplify_shorelines` counts vertices.
"""

from __future__ import annotations

import logging

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from coastmesh.errors import InputDataError
from coastmesh.types import Features

__all__ = [
    "LONG_EDGE_FACTOR",
    "check_coordinates",
    "densify_long_edges",
    "land_polygons",
    "valid_polygons",
]

logger = logging.getLogger(__name__)

_POLYGONAL = (shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON)


def check_coordinates(geometries: ArrayLike) -> None:
    """Check that every vertex of every geometry has finite coordinates.

    Parameters
    ----------
    geometries : array_like of shapely geometries, shape (F,)
        The geometries to check; None is allowed.

    Raises
    ------
    InputDataError
        For the first geometry with a NaN or infinite coordinate; ``feature`` is
        its index, and the message names the vertex (counted over the whole
        geometry) and the value.

    Examples
    --------
    >>> import shapely
    >>> check_coordinates([shapely.box(0, 0, 1, 1), None]) is None
    True
    """
    geoms = np.asarray(geometries, dtype=object).ravel()
    coords, index = shapely.get_coordinates(geoms, return_index=True)
    bad = np.flatnonzero(~np.isfinite(coords).all(axis=1))
    if bad.size == 0:
        return
    row = bad[0]
    feature = int(index[row])
    vertex = int(row - np.searchsorted(index, feature))
    x, y = coords[row]
    kind = "NaN" if np.isnan(coords[row]).any() else "infinite"
    others = np.unique(index[bad]).size - 1
    more = f" (and {others} more features)" if others else ""
    raise InputDataError(
        f"vertex {vertex} has a {kind} coordinate ({x}, {y}){more}", feature=feature
    )


def valid_polygons(geometries: ArrayLike) -> NDArray[np.object_]:
    """Return the valid single polygons that make up some geometries.

    Parameters
    ----------
    geometries : array_like of shapely geometries
        Polygons and multipolygons (valid or not); None and empty geometries are
        skipped.

    Returns
    -------
    ndarray of shapely polygons, shape (k,)
        The parts of the geometries, in order, invalid ones first made valid by
        GEOS ``make_valid``; the lines and points a repair can leave are dropped.

    Examples
    --------
    >>> import shapely
    >>> bowtie = shapely.Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    >>> parts = valid_polygons([bowtie, None, shapely.box(5, 5, 6, 6)])
    >>> len(parts), sorted(shapely.area(parts).tolist())
    (3, [1.0, 1.0, 1.0])
    """
    geoms = np.asarray(geometries, dtype=object).ravel()
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    invalid = ~shapely.is_valid(geoms)
    if invalid.any():
        geoms = geoms.copy()
        geoms[invalid] = shapely.make_valid(geoms[invalid])
    parts = shapely.get_parts(geoms)
    if (shapely.get_type_id(parts) >= shapely.GeometryType.MULTIPOINT).any():
        # a repair can give a collection that holds a multipolygon: flatten fully
        parts = np.array([p for g in parts for p in _flat(g)], dtype=object)
    return parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]


def _flat(geometry: shapely.Geometry) -> list[shapely.Geometry]:
    """Return the single parts of a geometry, collections inside collections too."""
    if shapely.get_type_id(geometry) < shapely.GeometryType.MULTIPOINT:
        return [geometry]
    return [p for g in shapely.get_parts(geometry) for p in _flat(g)]


def land_polygons(features: Features, *, purpose: str = "land") -> Features:
    """Return the non-empty features of a layer that must hold land polygons.

    Parameters
    ----------
    features : coastmesh.types.Features
        The layer as read.
    purpose : str
        What the polygons are for, for the error message.

    Returns
    -------
    Features
        The features with a polygon or multipolygon (empty ones left out).

    Raises
    ------
    InputDataError
        If a feature holds another geometry type, or none holds a polygon; the
        message names the file and the feature id.
    """
    geometry = features.geometry
    present = ~(shapely.is_missing(geometry) | shapely.is_empty(geometry))
    polygonal = np.isin(shapely.get_type_id(geometry), _POLYGONAL)
    bad = np.flatnonzero(present & ~polygonal)
    if len(bad):
        k = int(bad[0])
        raise InputDataError(
            f"{features.path}: feature {features.fids[k]} is a "
            f"{geometry[k].geom_type}; {purpose} needs land polygons (e.g. GSHHG "
            "level 1)",
            path=features.path,
            feature=int(features.fids[k]),
        )
    if not present.any():
        raise InputDataError(f"{features.path}: no land polygons", path=features.path)
    return features.take(present)


#: Edges longer than this many times the median edge are split before PCA.
LONG_EDGE_FACTOR = 50.0


def densify_long_edges(geoms: NDArray[np.object_]) -> NDArray[np.object_]:
    """Split edges far longer than the data's typical spacing before PCA.

    PCA partitions count vertices, not distance. A shoreline clipped to a data box
    (GSHHG's Eurasia, say) has cut edges hundreds of kilometres long between two
    vertices; a window spanning one averages points far apart and pulls the
    reconstruction across land. Such edges (longer than ``LONG_EDGE_FACTOR``
    times the layer's median edge; in GSHHG full resolution the longest real
    edges are about 20 times the median) get vertices at the median spacing;
    every other edge and vertex stays as it is.

    Parameters
    ----------
    geoms : ndarray of shapely polygons (None allowed)
        The shoreline layer.

    Returns
    -------
    ndarray
        ``geoms`` itself when no edge is that long, else a copy with the long edges
        split.
    """
    # every edge of every ring at once: (x, y) with the ring of each vertex
    present = np.flatnonzero(~shapely.is_missing(geoms))
    parts, part_geom = shapely.get_parts(geoms[present], return_index=True)
    rings, ring_part = shapely.get_rings(parts, return_index=True)
    if len(rings) == 0:
        return geoms
    xy, ring_of = shapely.get_coordinates(rings, return_index=True)
    inside = ring_of[1:] == ring_of[:-1]  # the two ends in one ring
    every = np.hypot(*np.diff(xy, axis=0).T)[inside]
    steps = every[every > 0]
    if len(steps) == 0:
        return geoms
    spacing = float(np.median(steps))
    limit = LONG_EDGE_FACTOR * spacing
    if steps.max() <= limit:
        return geoms

    def densify(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        length = np.hypot(*np.diff(xy, axis=0).T)
        pieces = [xy[:1]]
        for k in range(len(length)):
            if length[k] > limit:
                count = int(np.ceil(length[k] / spacing))
                t = np.linspace(0.0, 1.0, count + 1)[1:, None]
                pieces.append(xy[k] + t * (xy[k + 1] - xy[k]))
            else:
                pieces.append(xy[k + 1 : k + 2])
        return np.concatenate(pieces)

    edge_geom = present[part_geom[ring_part[ring_of[1:][inside]]]]
    long = np.unique(edge_geom[every > limit])  # the features to rebuild
    out = geoms.copy()
    for index in long.tolist():
        rebuilt = []
        for part in shapely.get_parts(geoms[index]):
            shell = densify(shapely.get_coordinates(part.exterior))
            holes = [densify(shapely.get_coordinates(r)) for r in part.interiors]
            rebuilt.append(shapely.Polygon(shell, holes))
        out[index] = rebuilt[0] if len(rebuilt) == 1 else shapely.MultiPolygon(rebuilt)
    split = len(long)
    logger.info(
        "%d shoreline features have edges over %g x the median spacing (clipped "
        "data boxes); those edges get vertices at the median spacing before PCA",
        split,
        LONG_EDGE_FACTOR,
    )
    return out
