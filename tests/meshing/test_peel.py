"""Dead-end channels one element wide: peeled, against a literal loop."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from conftest import bay_with_inlet

from coastmesh.meshing import generate_mesh, mesh_quality
from coastmesh.meshing.cleanup.peel import peel_channels
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid


def _uniform(domain: Domain, h: float) -> SizeGrid:
    minx, miny, maxx, maxy = domain.polygon.bounds
    x = np.arange(minx - h, maxx + 2 * h, h)
    y = np.arange(miny - h, maxy + 2 * h, h)
    return SizeGrid(x, y, np.full((len(y), len(x)), h))


def _boundary_sides(triangles) -> dict[tuple[int, int], int]:
    """Sides used by one triangle (literally: count every side of every one)."""
    count: dict[tuple[int, int], int] = {}
    for a, b, c in triangles:
        for u, v in ((a, b), (b, c), (c, a)):
            key = (min(u, v), max(u, v))
            count[key] = count.get(key, 0) + 1
    return {k: n for k, n in count.items() if n == 1}


def peel_loop(mesh: Mesh) -> set[tuple[int, int, int]]:
    """Peel by brute force: one ear at a time, rescanning the whole mesh."""
    kinds = mesh.boundary_kinds
    ids = {
        (min(a, b), max(a, b)): int(i)
        for (a, b), i in zip(
            mesh.boundary_edges.tolist(), mesh.boundary_ids, strict=True
        )
    }
    tris = [tuple(t) for t in mesh.triangles.tolist()]
    while True:
        sides = _boundary_sides(tris)
        nodes = {v for s in sides for v in s}
        for t in tris:
            a, b, c = t
            tsides = [(min(u, v), max(u, v)) for u, v in ((a, b), (b, c), (c, a))]
            outer = [s for s in tsides if s in sides]
            if len(outer) != 2 or not all(v in nodes for v in t):
                continue
            if all(kinds.get(ids[s]) == "open" for s in outer):
                continue
            inner = next(s for s in tsides if s not in sides)
            other = [u for u in tris if u != t and set(inner) <= set(u)]
            if len(other) != 1 or not all(v in nodes for v in other[0]):
                continue
            opened = [s for s in outer if kinds.get(ids[s]) == "open"]
            ids[inner] = ids[opened[0]] if opened else ids[outer[0]]
            tris.remove(t)
            break
        else:
            return {tuple(sorted(mesh.points[list(t)].round(6).ravel())) for t in tris}


@pytest.fixture(scope="module")
def inlet_mesh() -> Mesh:
    # a 100 m inlet meshed at 300 m: one element wide, 6 km long, a dead end
    return generate_mesh(bay_with_inlet(100.0), _uniform(bay_with_inlet(100.0), 300.0))


def test_a_dead_end_inlet_one_element_wide_is_peeled_like_the_loop(inlet_mesh):
    peeled, report = peel_channels(inlet_mesh)
    assert report.removed > 20 and report.strips >= 1 and report.left == 0
    got = {
        tuple(sorted(peeled.points[t].round(6).ravel()))
        for t in peeled.triangles.tolist()
    }
    assert got == peel_loop(inlet_mesh)
    # the inlet is gone: no triangle north of the bay's shore but its mouth
    north = peeled.points[peeled.triangles].mean(axis=1)[:, 1]
    assert north.max() < 20_400
    # a valid mesh: every boundary side on one triangle, every node used,
    # the boundary ids kept (the coast's), the area less by the triangles gone
    sides = _boundary_sides(peeled.triangles.tolist())
    assert set(sides) == {tuple(sorted(e)) for e in peeled.boundary_edges.tolist()}
    assert np.bincount(peeled.triangles.ravel()).min() > 0
    assert set(peeled.boundary_ids.tolist()) == {1, 2}

    def area(m):
        p = m.points[m.triangles]
        return shapely.area(shapely.polygons(np.concatenate([p, p[:, :1]], 1))).sum()

    assert area(peeled) < area(inlet_mesh) - 0.5 * 100 * 5_000


def test_a_wide_inlet_and_the_open_corners_are_left_alone():
    wide = bay_with_inlet(1_000.0)
    mesh = generate_mesh(wide, _uniform(wide, 200.0))
    peeled, report = peel_channels(mesh)
    assert report.removed == 0 and peeled is mesh


def test_sites_keep_their_channels(inlet_mesh):
    centres = inlet_mesh.points[inlet_mesh.triangles].mean(axis=1)
    keep = centres[:, 1] > 20_000  # the inlet is a site
    peeled, report = peel_channels(inlet_mesh, keep)
    assert report.removed == 0 and report.left > 10
    assert len(peeled.triangles) == len(inlet_mesh.triangles)


def test_a_strip_along_an_open_boundary_cuts_the_open_boundary_back():
    # a wedge: the open boundary (south) meets the coast at 10 degrees
    ring = [(0, 0), (10_000, 0), (10_000, 1_763), (0, 0)]
    d = Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south", 2),
            BoundarySegment(ring[1:], "shoreline", "coast", 1),
        ),
        crs="EPSG:32631",
    )
    mesh = generate_mesh(d, _uniform(d, 400.0))
    before = len(mesh_quality(mesh).channel_spanning_triangles)
    peeled, report = peel_channels(mesh)
    assert before > 0 and report.removed > 0
    # the end is peeled (like the loop); the rest of the strip, one element
    # wide again past a node inside, is a run with one mouth: closed whole
    assert report.left == len(mesh_quality(peeled).channel_spanning_triangles) == 0
    assert _rings_ok(peeled)
    got = {
        tuple(sorted(peeled.points[t].round(6).ravel()))
        for t in peeled.triangles.tolist()
    }
    assert got <= peel_loop(mesh)
    # the open boundary is cut back along the strip: the new sides are open
    west = peeled.points[peeled.boundary_edges].mean(axis=1)[:, 0].argmin()
    assert peeled.boundary_ids[west] == 2
    assert peeled.points[:, 0].min() > 300.0


def _rings_ok(mesh: Mesh) -> bool:
    """Every boundary side on one triangle; every boundary node on two sides."""
    sides = _boundary_sides(mesh.triangles.tolist())
    listed = {tuple(sorted(e)) for e in mesh.boundary_edges.tolist()}
    degree = np.bincount(mesh.boundary_edges.ravel(), minlength=len(mesh.points))
    return set(sides) == listed and set(degree[degree > 0].tolist()) == {2}


def test_a_strait_one_element_wide_between_an_island_and_the_coast_is_closed():
    # a 10 km square open to the north; an island 80 m off the south coast
    outer = [(0, 0), (10_000, 0), (10_000, 10_000), (0, 10_000), (0, 0)]
    island = [(3_000, 80), (3_000, 1_000), (5_000, 1_000), (5_000, 80), (3_000, 80)]
    d = Domain(
        shapely.Polygon(outer, [island]),
        (
            BoundarySegment(outer[:3], "shoreline", "coast", 1),
            BoundarySegment(outer[2:4], "open", "north", 2),
            BoundarySegment(outer[3:], "shoreline", "coast", 1),
            BoundarySegment(island, "shoreline", "coast", 1),
        ),
        crs="EPSG:32631",
    )
    mesh = generate_mesh(d, _uniform(d, 300.0))
    before = len(mesh_quality(mesh).channel_spanning_triangles)
    assert before > 3  # the strait is one element wide
    peeled, report = peel_channels(mesh)
    assert report.straits == 1 and report.left == 0
    assert len(mesh_quality(peeled).channel_spanning_triangles) == 0
    assert _rings_ok(peeled)
    # the strait's water is gone, the island now joined to the coast: one ring
    centres = peeled.points[peeled.triangles].mean(axis=1)
    strait = (centres[:, 0] > 3_000) & (centres[:, 0] < 5_000) & (centres[:, 1] < 80)
    assert not strait.any()
    assert set(peeled.boundary_ids.tolist()) == {1, 2}


def _island_with_a_spike(tip: float) -> Domain:
    """A 10 km bay open to the north, an island whose spike reaches ``tip`` m
    from the south coast: water on both sides of the spike, joined around."""
    outer = [(0, 0), (10_000, 0), (10_000, 10_000), (0, 10_000), (0, 0)]
    island = [(3_000, 1_500), (4_000, tip), (5_000, 1_500), (5_000, 3_000)]
    island += [(3_000, 3_000), (3_000, 1_500)]
    return Domain(
        shapely.Polygon(outer, [island]),
        (
            BoundarySegment(outer[:3], "shoreline", "coast", 1),
            BoundarySegment(outer[2:4], "open", "north", 2),
            BoundarySegment(outer[3:], "shoreline", "coast", 1),
            BoundarySegment(island, "shoreline", "coast", 1),
        ),
        crs="EPSG:32631",
    )


@pytest.mark.parametrize("tip", [100.0, 200.0])
def test_a_strait_at_a_pinch_is_closed_with_the_smaller_fan(tip):
    # the spike's tip and the coast below it: one triangle with one boundary
    # side, whose closing alone would leave the tip with four boundary sides
    d = _island_with_a_spike(tip)
    mesh = generate_mesh(d, _uniform(d, 300.0))
    spans = mesh_quality(mesh).channel_spanning_triangles
    assert len(spans) >= 1
    peeled, report = peel_channels(mesh)
    assert report.unpinched >= 1 and report.left == 0
    assert len(mesh_quality(peeled).channel_spanning_triangles) == 0
    assert _rings_ok(peeled)
    # only the strait and a fan of the tip go: a few triangles, all near it
    gone = len(mesh.triangles) - len(peeled.triangles)
    assert 2 <= gone <= 12
    kept = {
        tuple(sorted(peeled.points[t].round(6).ravel()))
        for t in peeled.triangles.tolist()
    }
    centres = mesh.points[mesh.triangles].mean(axis=1)
    lost = [
        i
        for i, t in enumerate(mesh.triangles.tolist())
        if tuple(sorted(mesh.points[t].round(6).ravel())) not in kept
    ]
    assert np.hypot(centres[lost, 0] - 4_000, centres[lost, 1] - tip / 2).max() < 900
    # the island is now joined to the coast: one ring of boundary less
    assert set(peeled.boundary_ids.tolist()) == {1, 2}


def test_a_pinch_whose_fan_is_a_site_is_left_and_reported():
    d = _island_with_a_spike(150.0)
    mesh = generate_mesh(d, _uniform(d, 300.0))
    centres = mesh.points[mesh.triangles].mean(axis=1)
    keep = np.hypot(centres[:, 0] - 4_000, centres[:, 1]) < 1_000  # the site
    peeled, report = peel_channels(mesh, keep)
    assert report.removed == 0 and report.left >= 1
    assert peeled is mesh


def test_a_strait_that_is_the_only_way_to_a_sea_of_its_own_is_left():
    # two basins, each with its own open boundary, joined only where a spike
    # of the north coast comes within 150 m of the south coast: closing it
    # would cut the west basin off (and drop it), so it stays, reported
    ring = [(0, 0), (10_000, 0), (10_000, 4_000), (5_400, 4_000), (5_000, 150)]
    ring += [(4_600, 4_000), (0, 4_000), (0, 0)]
    d = Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "shoreline", "coast", 1),
            BoundarySegment(ring[1:3], "open", "east", 2),
            BoundarySegment(ring[2:7], "shoreline", "coast", 1),
            BoundarySegment(ring[6:], "open", "west", 3),
        ),
        crs="EPSG:32631",
    )
    mesh = generate_mesh(d, _uniform(d, 300.0))
    assert len(mesh_quality(mesh).channel_spanning_triangles) >= 1
    peeled, report = peel_channels(mesh)
    assert report.left == len(mesh_quality(peeled).channel_spanning_triangles) >= 1
    assert report.cut_off == 0 and set(peeled.boundary_ids.tolist()) == {1, 2, 3}
    assert _rings_ok(peeled)
