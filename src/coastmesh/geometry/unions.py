"""Unions of many polygons that overlay only those that meet.

A world layer's thousands of islands are almost all apart. GEOS's
``union_all`` of them overlays every one (a cascaded union, level by level of
its tree, the continents at every level): 0.7 s for a world's 300 polygons
that meet nowhere. :func:`meeting_pairs` finds the pairs that do meet with a
spatial index; :func:`groups_of` puts them in connected groups; and
:func:`union_meeting` unions each group alone and leaves the rest as they
are.
"""

from __future__ import annotations

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

__all__ = ["group_labels", "groups_of", "meeting_pairs", "union_meeting"]

Pairs = tuple[NDArray[np.intp], NDArray[np.intp]]


def meeting_pairs(
    geoms: NDArray[np.object_], among: NDArray[np.object_] | None = None
) -> Pairs:
    """Return the pairs ``i < j`` of ``geoms`` that intersect (``among`` them).

    With ``among``, the indices of its geometries follow those of ``geoms``,
    and only pairs with one of them are found. Each pair is tested with the
    one with more vertices prepared, so a continent is tested against a small
    patch in the patch's time, not its own (:meth:`shapely.STRtree.query` with
    a predicate would prepare the patch).

    Examples
    --------
    >>> boxes = np.array([shapely.box(0, 0, 1, 1), shapely.box(1, 0, 2, 1),
    ...                   shapely.box(5, 5, 6, 6)])
    >>> [pair.tolist() for pair in meeting_pairs(boxes)]
    [[0], [1]]
    """
    everything = geoms if among is None else np.concatenate([geoms, among])
    if among is None:
        i, j = shapely.STRtree(geoms).query(geoms)
        i, j = i[i < j], j[i < j]
    else:
        j, i = shapely.STRtree(everything).query(among)
        j = j + len(geoms)
        i, j = np.minimum(i, j), np.maximum(i, j)
        i, j = i[i < j], j[i < j]
    size = shapely.get_num_coordinates(everything)
    swap = size[i] < size[j]
    first, second = np.where(swap, j, i), np.where(swap, i, j)
    shapely.prepare(everything[np.unique(first)])
    hit = shapely.intersects(everything[first], everything[second])
    return i[hit], j[hit]


def group_labels(n: int, pairs: Pairs) -> NDArray[np.int32]:
    """Return the group of each of ``n`` geometries that ``pairs`` of them join."""
    i, j = pairs
    graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(n, n))
    return connected_components(graph, directed=False)[1]


def groups_of(n: int, pairs: Pairs) -> list[NDArray[np.intp]]:
    """Return the groups of ``n`` geometries that ``pairs`` of them join.

    In the order of each group's first member; each group in index order.
    """
    label = group_labels(n, pairs)
    order = np.argsort(label, kind="stable")
    starts = np.flatnonzero(np.r_[True, label[order][1:] != label[order][:-1]])
    return np.split(order, starts[1:])


def union_meeting(polygons: ArrayLike) -> NDArray[np.object_]:
    """Return the union of ``polygons`` as single polygons, overlaying only what meets.

    The same land as ``shapely.get_parts(shapely.union_all(polygons))``
    (valid polygons, or multipolygons, in): each group of polygons that meet
    (:func:`meeting_pairs`) is unioned alone, and a polygon that meets no
    other is returned as it is. No two polygons returned overlap, so
    :func:`shapely.multipolygons` of them is valid.

    Examples
    --------
    >>> boxes = [shapely.box(0, 0, 2, 1), shapely.box(1, 0, 3, 1),
    ...          shapely.box(5, 5, 6, 6)]
    >>> [float(p.area) for p in union_meeting(boxes)]
    [3.0, 1.0]
    """
    geoms = shapely.get_parts(np.asarray(polygons, dtype=object).ravel())
    geoms = geoms[~(shapely.is_missing(geoms) | shapely.is_empty(geoms))]
    out = []
    for group in groups_of(len(geoms), meeting_pairs(geoms)):
        if len(group) == 1:
            out.append(geoms[group])
        else:
            parts = shapely.get_parts(shapely.union_all(geoms[group]))
            out.append(
                parts[shapely.get_type_id(parts) == shapely.GeometryType.POLYGON]
            )
    return np.concatenate(out) if out else np.empty(0, dtype=object)
