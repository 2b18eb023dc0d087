"""Slots opened in tiles on threads, against one opening of the whole water."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from coastmesh.sizing.slots import SLIVER, slots, slots_near, tiles


def reference_slots(polygon: shapely.Polygon, width: float) -> list[shapely.Polygon]:
    """Literal: the water the opening by a disk of diameter ``width`` misses.

    One opening of the whole polygon (GEOS buffers in and out, the second
    grown by ``SLIVER`` of the radius, as documented), its pieces, each kept
    if its bounding box's diagonal is at least twice ``width``.
    """
    r = width / 2
    opened = shapely.Polygon(polygon).buffer(-r).buffer(r * (1 + SLIVER))
    missed = polygon.difference(opened)
    kept = []
    for piece in getattr(missed, "geoms", [missed]):
        if isinstance(piece, shapely.Polygon) and not piece.is_empty:
            x0, y0, x1, y1 = piece.bounds
            if np.hypot(x1 - x0, y1 - y0) >= 2 * width:
                kept.append(piece)
    return kept


@st.composite
def combs(draw: st.DrawFn) -> shapely.Polygon:
    """A 1 km square of water with inlets of random width along its north side.

    Its edges are split every 5 m, so that small tiles cut through it.
    """
    count = draw(st.integers(1, 8))
    x = sorted(draw(st.lists(st.floats(20, 980), min_size=count, max_size=count)))
    water = [shapely.box(0, 0, 1000, 1000)]
    for k, left in enumerate(x):
        w = draw(st.floats(1.0, 40.0))
        length = draw(st.floats(30.0, 400.0))
        x0 = min(left, 990 - w) if k == 0 else max(min(left, 990 - w), x[k - 1] + 45)
        if x0 + w <= 995:
            water.append(shapely.box(x0, 999, x0 + w, 1000 + length))
    polygon = shapely.union_all(water).segmentize(5.0)
    return shapely.normalize(polygon)


@settings(max_examples=40, deadline=None)
@given(water=combs(), width=st.floats(4.0, 30.0), most=st.integers(60, 400))
def test_slots_in_tiles_are_the_water_one_opening_misses(water, width, most):
    ref = reference_slots(water, width)
    got = slots(water, width, tile_vertices=most, threads=2)
    assert len(tiles(water, most)) > 1  # the tiles are in play
    missed = shapely.union_all(ref) if ref else shapely.Polygon()
    found = shapely.union_all(got) if len(got) else shapely.Polygon()
    # the same water, to GEOS's arcs: 8 chords a quarter circle, up to 0.5 %
    # of the radius inside it, placed from the vertices near them (a tile's
    # clip moves them); where an inlet is as wide as the disk, the offsets in
    # and out meet at a glancing angle and the chords' 0.5 % grows 5 times
    tol = 0.05 * width
    apart = shapely.symmetric_difference(missed, found).area
    assert apart <= tol * (missed.length + found.length) + 1e-9 * water.area
    # each slot whole in one piece (a tile's edge split none), none extra
    for piece in got:
        assert any(p.buffer(tol).covers(piece) for p in ref)
    for piece in ref:
        assert any(p.buffer(tol).covers(piece) for p in got)


@settings(max_examples=15, deadline=None)
@given(water=combs(), width=st.floats(4.0, 30.0))
def test_slots_do_not_depend_on_the_threads(water, width):
    one = slots(water, width, tile_vertices=100, threads=1)
    three = slots(water, width, tile_vertices=100, threads=3)
    assert len(one) == len(three)
    assert shapely.equals_exact(one, three, 0.0).all()


@settings(max_examples=30, deadline=None)
@given(water=combs(), most=st.integers(20, 500))
def test_tiles_cover_the_bounds_with_at_most_so_many_vertices(water, most):
    boxes = tiles(water, most)
    xy = shapely.get_coordinates(water)
    bounds = shapely.box(*water.bounds)
    # they tile the bounds: no overlap, no gap
    assert np.isclose(shapely.area(boxes).sum(), bounds.area)
    assert shapely.union_all(boxes).equals(bounds)
    top = xy.max(axis=0)
    for box in boxes:
        x0, y0, x1, y1 = box.bounds
        # a vertex on a cut belongs to the box above it
        x = (xy[:, 0] >= x0) & ((xy[:, 0] < x1) | (x1 == top[0]))
        y = (xy[:, 1] >= y0) & ((xy[:, 1] < y1) | (y1 == top[1]))
        inside = xy[x & y]
        if len(inside) > most:  # only if no median splits it
            mx, my = np.median(inside, axis=0)
            assert not (x0 < mx < x1) and not (y0 < my < y1)


@settings(max_examples=40, deadline=None)
@given(
    radii=st.lists(st.floats(20e3, 40e3), min_size=5, max_size=15),
    turn=st.floats(0.0, 1.0),
    width=st.floats(5.0, 60.0),
)
def test_no_slivers_along_straight_coasts_far_from_the_origin(radii, turn, width):
    # star-shaped water at UTM-like coordinates, its edges split every 500 m:
    # one opening used to leave thousands of slivers a few micrometres wide
    # along such straight coasts (4,723 on the NW-shelf fine domain), each
    # long enough to pass for a slot, and closing them moved the coast
    t = 2 * np.pi * (np.arange(len(radii)) + turn) / len(radii)
    ring = np.c_[np.cos(t), np.sin(t)] * np.array(radii)[:, None]
    water = shapely.Polygon(ring + [500_000.0, 6_500_000.0]).segmentize(500.0)
    for piece in slots(water, width):
        x0, y0, x1, y1 = piece.bounds
        assert piece.area / np.hypot(x1 - x0, y1 - y0) > 0.01 * width


@settings(max_examples=30, deadline=None)
@given(
    water=combs(),
    width=st.floats(4.0, 30.0),
    box=st.tuples(st.floats(0, 900), st.floats(0, 1200), st.floats(50, 600)),
)
def test_slots_near_a_box_are_the_slots_there(water, width, box):
    # land: a block across the comb's north side, as a closing would add
    x0, y0, size = box
    land = shapely.box(x0, 900, x0 + 60, 1000)
    less = water.difference(land)
    ref = [q for part in shapely.get_parts(less) for q in reference_slots(part, width)]
    boxes = np.array([[x0, y0, x0 + size, y0 + size]])
    got = slots_near(water, width, boxes, land)
    core = shapely.box(*boxes[0])
    tol = 0.05 * width
    # what it finds is slot water of the whole, in the box ...
    missed = shapely.union_all(ref) if ref else shapely.Polygon()
    for piece in got:
        assert core.buffer(1e-6).covers(piece)
        assert missed.buffer(tol).covers(piece)
    # ... and every slot wholly in the box is found
    for piece in ref:
        if core.buffer(-tol).covers(piece):
            assert any(p.buffer(tol).covers(piece) for p in got)
    # a box over everything is the whole
    every = slots_near(water, width, np.array([[-10, -10, 1010, 1500]]), land)
    assert len(every) == len(ref)
