"""Unions that overlay only polygons that meet, against GEOS's union of them all."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.geometry.unions import groups_of, meeting_pairs, union_meeting


def _reference_pairs(geoms):
    """Every pair i < j, tested with shapely's own predicate: the literal search."""
    n = len(geoms)
    return {
        (i, j)
        for i in range(n)
        for j in range(i + 1, n)
        if shapely.intersects(geoms[i], geoms[j])
    }


_box = st.tuples(
    st.integers(0, 20), st.integers(0, 20), st.integers(1, 6), st.integers(1, 6)
).map(lambda b: shapely.box(b[0], b[1], b[0] + b[2], b[1] + b[3]))
_disk = st.tuples(st.integers(0, 20), st.integers(0, 20), st.integers(1, 4)).map(
    lambda d: shapely.Point(d[0], d[1]).buffer(d[2], quad_segs=4)
)
_polygons = st.lists(st.one_of(_box, _disk), min_size=0, max_size=14)


@settings(deadline=None, max_examples=60)
@given(_polygons)
def test_pairs_are_every_pair_that_meets(polygons):
    geoms = np.array(polygons, dtype=object)
    i, j = meeting_pairs(geoms) if len(geoms) else ([], [])
    assert set(zip(np.asarray(i).tolist(), np.asarray(j).tolist(), strict=True)) == (
        _reference_pairs(geoms)
    )


@settings(deadline=None, max_examples=60)
@given(_polygons)
def test_union_is_union_all(polygons):
    parts = union_meeting(polygons)
    expected = shapely.union_all(polygons)
    got = shapely.multipolygons(parts)
    assert shapely.is_valid(got)
    assert all(p.geom_type == "Polygon" for p in parts)
    assert shapely.equals(got, expected) or (got.is_empty and expected.is_empty)
    # as many pieces as GEOS makes: nothing left overlapping or split
    assert len(parts) == len(shapely.get_parts(expected))


def test_polygons_apart_are_not_overlaid():
    apart = [shapely.box(i * 10, 0, i * 10 + 1, 1) for i in range(5)]
    assert [p.wkb for p in union_meeting(apart)] == [p.wkb for p in apart]


def test_groups_join_chains():
    # 0-1 and 1-2 meet: one group; 3 alone
    groups = groups_of(4, (np.array([0, 1]), np.array([1, 2])))
    assert [g.tolist() for g in groups] == [[0, 1, 2], [3]]


def test_pairs_among_others_only():
    land = np.array([shapely.box(0, 0, 2, 2), shapely.box(1, 1, 3, 3)], dtype=object)
    patch = np.array([shapely.box(2.5, 2.5, 4, 4)], dtype=object)
    i, j = meeting_pairs(land, patch)
    # land 0-1 meet too, but only pairs with the patch (index 2) are asked for
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == [(1, 2)]
