"""Faces cut alone, and along a line at its clean crossings only."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from test_parts import _faces, assert_one_conforming_mesh

from coastmesh.meshing import generate_mesh
from coastmesh.meshing.engine import mesh_in_parts
from coastmesh.meshing.parts import cuts as parts_module
from coastmesh.meshing.parts.crossings import PENALTY, Turned, chord_edges, coast_tree
from coastmesh.meshing.parts.cuts import expected_triangles, plan_cuts, water_cells
from coastmesh.meshing.parts.partial import cells_of, faces_of, split_costs
from coastmesh.meshing.parts.report import PartsReport, oversize_parts
from coastmesh.types import BoundarySegment, Domain, SizeGrid


def moat(side=6000.0, moat=80.0, land=400.0, gap=400.0):
    """A square sea whose coast is a moat ``moat`` wide all round it.

    The land between the moat and the inner sea is a C, open at the middle of
    its south side: every straight line across the water crosses the moat,
    under two target edges of 100 m wide (at 30 degrees or more to it), so
    no line across the water is clean.
    """
    a, b, m, g = moat, land, side / 2, gap / 2
    land_c = np.array(
        [
            [m + g, a], [side - a, a], [side - a, side - a], [a, side - a], [a, a],
            [m - g, a], [m - g, b], [b, b], [b, side - b], [side - b, side - b],
            [side - b, b], [m + g, b], [m + g, a],
        ]
    )  # fmt: skip
    outer = np.array([[0, 0], [side, 0], [side, side], [0, side], [0, 0]], float)
    return outer, land_c


def _moat_water():
    outer, land = moat()
    return shapely.Polygon(outer, [land])


def _grid(h=100.0, step=50.0, side=6000.0):
    x = np.arange(-200.0, side + 201.0, step)
    return SizeGrid(x, x, np.full((len(x), len(x)), h))


def test_no_line_across_the_moat_is_clean():
    # the water the tests below cut: the planner's lines across it all fail
    water, grid = _moat_water(), _grid()
    x, y, w = water_cells(water, grid)
    coast = (coast_tree(water), None, [], [])
    region = shapely.box(*water.bounds)
    for direction in parts_module._directions(True):
        score, *_ = parts_module._best_cut(
            water, grid, coast, region, x, y, w, 0.5, direction
        )
        assert score >= PENALTY, direction


def test_a_face_no_line_crosses_cleanly_is_cut_where_lines_cross_it_cleanly(
    monkeypatch,
):
    water, grid = _moat_water(), _grid()
    monkeypatch.setattr(parts_module, "MIN_PART_TRIANGLES", 1000)
    total = expected_triangles(water, grid)  # 6,426
    plan = plan_cuts(water, grid, 2)
    assert plan.missed == 0 and plan.cuts
    costs = np.array([expected_triangles(f, grid) for f in _faces(water, plan.cuts)])
    assert costs.sum() == pytest.approx(total, rel=1e-9)
    assert costs.max() <= parts_module.OVERSIZE * total / 2
    # no cut crosses the moat: each is clean against the coast
    coast = (coast_tree(water), None, [], [])
    assert all(chord_edges(grid, coast, c)[1] for c in plan.cuts)
    # without cuts along a line's clean crossings, the water was one part
    monkeypatch.setattr(parts_module, "_partial_cut", lambda *args: [])
    before = plan_cuts(water, grid, 2)
    assert before.cuts == [] and before.missed == 1


def test_parts_cut_where_lines_cross_cleanly_make_one_conforming_mesh(monkeypatch):
    outer, land = moat()
    sides = tuple(
        BoundarySegment(outer[i : i + 2], "shoreline", f"s{i}", i + 1) for i in range(4)
    )
    domain = Domain(
        shapely.Polygon(outer, [land]),
        (*sides, BoundarySegment(land, "shoreline", "land", 9)),
        crs="EPSG:32630",
    )
    grid = _grid()
    monkeypatch.setattr(parts_module, "MIN_PART_TRIANGLES", 1000)
    one = generate_mesh(domain, grid, parts=1)
    many, report = mesh_in_parts(domain, grid, parts=4)
    again = generate_mesh(domain, grid, parts=4)
    np.testing.assert_array_equal(many.points, again.points)  # deterministic
    np.testing.assert_array_equal(many.triangles, again.triangles)
    assert_one_conforming_mesh(one, many, domain.polygon)
    assert report.parts >= 4 and report.oversize == ()
    share = sum(report.expected) / 4
    assert max(report.expected) <= parts_module.OVERSIZE * share


def hook():
    """A sea and, past a spit of land, a bay of it that a line x = 60 cuts off."""
    return shapely.Polygon(
        [(0, 0), (100, 0), (100, 100), (50, 100), (50, 92), (90, 92), (90, 50),
         (0, 50), (0, 0)]
    )  # fmt: skip


def test_a_piece_too_small_to_mesh_alone_is_not_cut_off():
    sea = hook()
    g = np.arange(0.5, 100, 1.0)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    inside = shapely.contains_xy(sea, x, y)
    cells = (x[inside], y[inside], np.ones(inside.sum()))
    turned = Turned(sea, (1.0, 0.0))
    chords = turned.chords(shapely.LineString([(60, 0), (60, 100)]))
    assert len(chords) == 2  # the sea below, the bay's arm above
    # west of the line: the sea's 3,000 cells, the bay's 80; east: 2,740
    low = min(range(2), key=lambda k: chords[k].bounds[1])
    # under 100 cells, the bay stays joined to the water east of it
    split = split_costs(sea, turned, 60.0, cells, chords, [True, True], 100.0)
    assert split.kept == [low] and split.costs == [3_000.0, 2_820.0]
    # counted alone, it is a face of its own
    split = split_costs(sea, turned, 60.0, cells, chords, [True, True], 10.0)
    assert sorted(split.kept) == [0, 1] and split.costs == [3_000.0, 2_740.0, 80.0]
    # a crossing that is not clean is not cut: the water stays joined there
    clean = [k != low for k in range(2)]
    split = split_costs(sea, turned, 60.0, cells, chords, clean, 10.0)
    assert split.kept == [1 - low] and split.costs == [5_740.0, 80.0]


def test_the_faces_of_a_cut_and_their_cells():
    sea = hook()
    chord = shapely.LineString([(60, 0), (60, 50)])
    faces = faces_of(sea, [chord])
    assert len(faces) == 2
    assert sum(f.area for f in faces) == pytest.approx(sea.area)
    labels = cells_of(faces, np.array([30.0, 80.0, 70.0]), np.array([25.0, 25.0, 96.0]))
    west = next(k for k, f in enumerate(faces) if f.bounds[0] == 0)
    assert labels.tolist() == [west, 1 - west, 1 - west]


def test_the_summary_names_a_part_left_over_its_limit_and_why():
    why = oversize_parts((30_000.0, 5_000.0, 5_000.0), 4, ((1.5, 2.0),) * 3)
    assert len(why) == 1 and why[0].startswith("part 1 holds 3.00 shares")
    report = PartsReport(
        4, 4, (), (30_000.0, 5_000.0, 5_000.0), (30, 5, 5), (3.0, 0.5, 0.5),
        ("a", "a", "b"), oversize=why,
    )  # fmt: skip
    assert report.summary().endswith("; " + why[0])
    assert report.to_dict()["oversize"] == list(why)
    assert oversize_parts((10_000.0, 10_000.0), 2) == ()
