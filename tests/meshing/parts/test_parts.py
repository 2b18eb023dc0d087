"""Domain decomposition and meshing in parts: balance, conformity, determinism."""

from __future__ import annotations

import itertools
import re
import warnings

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from coastmesh.case.executor import open_runner
from coastmesh.meshing import CleanupOptions, generate_mesh
from coastmesh.meshing.engine import PartsWarning, mesh_in_parts
from coastmesh.meshing.gmsh.boundary_nodes import chunked
from coastmesh.meshing.parts import crossings
from coastmesh.meshing.parts import cuts as parts_module
from coastmesh.meshing.parts.cuts import (
    auto_parts,
    cut_lines,
    expected_triangles,
    plan_cuts,
)
from coastmesh.meshing.parts.faces import face_polygon, merge_small_faces, split_faces
from coastmesh.types import BoundarySegment, Domain, SizeGrid

OUTER = np.array([[0, 0], [12000, 0], [12000, 8000], [0, 8000], [0, 0]], float)
ISLAND = np.array(
    [[5000, 3000], [5000, 5000], [7000, 5000], [7000, 3000], [5000, 3000]], float
)


def _grid(h_min=120.0, slope=0.1, step=200.0):
    x = np.arange(-400.0, 12401.0, step)
    y = np.arange(-400.0, 8401.0, step)
    X, Y = np.meshgrid(x, y)
    return SizeGrid(x, y, h_min + slope * np.hypot(X - 2000, Y - 4000))


def _domain():
    sides = tuple(
        BoundarySegment(
            OUTER[i : i + 2], "open" if i == 1 else "shoreline", f"s{i}", i + 1
        )
        for i in range(4)
    )
    island = BoundarySegment(ISLAND, "shoreline", "island", 9)
    return Domain(shapely.Polygon(OUTER, [ISLAND]), (*sides, island), crs="EPSG:32630")


def _reference_expected(polygon, grid):
    """Literal: every grid node, one at a time."""
    cell = (grid.x[1] - grid.x[0]) * (grid.y[1] - grid.y[0])
    total = 0.0
    for j, y in enumerate(grid.y):
        for i, x in enumerate(grid.x):
            if polygon.contains(shapely.Point(x, y)):
                total += 4.0 / np.sqrt(3.0) * cell / grid.values[j, i] ** 2
    return total


def _faces(water, cuts):
    """The faces of water the cuts make, literally: node, polygonize, keep wet."""
    faces = shapely.get_parts(
        shapely.polygonize(
            shapely.get_parts(shapely.node(shapely.union_all([water.boundary, *cuts])))
        )
    )
    return [f for f in faces if water.contains(f.point_on_surface())]


def test_expected_triangles_matches_the_literal_sum():
    water = shapely.Polygon(OUTER, [ISLAND])
    grid = _grid()
    assert expected_triangles(water, grid) == pytest.approx(
        _reference_expected(water, grid), rel=1e-12
    )


def test_cells_found_once_give_the_same_parts_and_cuts(monkeypatch):
    water, grid = shapely.Polygon(OUTER, [ISLAND]), _grid(8.0, 0.004, step=50.0)
    cells = parts_module.water_cells(water, grid, threads=2)
    assert cells.weight.sum() == pytest.approx(_reference_expected(water, grid))
    wanted = auto_parts(water, grid)
    cuts = plan_cuts(water, grid, 3)

    def again(*args, **kwargs):
        raise AssertionError("the cells were found again")

    monkeypatch.setattr(parts_module, "water_cells", again)
    assert auto_parts(water, grid, cells=cells) == wanted
    given_cells = plan_cuts(water, grid, 3, cells=cells)
    assert [c.wkt for c in given_cells.cuts] == [c.wkt for c in cuts.cuts]
    assert given_cells.missed == cuts.missed


@settings(max_examples=25, deadline=None)
@given(parts=st.integers(2, 7), slope=st.floats(0.0, 0.01), h=st.floats(5, 15))
def test_cuts_balance_the_expected_triangles(parts, slope, h):
    water = shapely.Polygon(OUTER, [ISLAND])
    grid = _grid(h, slope, step=50.0)  # >= 100,000 expected triangles per part
    cuts = cut_lines(water, grid, parts)
    assert len(cuts) == parts - 1  # this water has a clean cut everywhere
    pieces = _faces(water, cuts)
    assert len(pieces) >= parts
    costs = np.array([expected_triangles(p, grid) for p in pieces])
    # the cuts may split the water into more faces than parts (around the
    # island), but no face holds much more than its share
    assert costs.sum() == pytest.approx(expected_triangles(water, grid), rel=1e-9)
    assert costs.max() <= 1.35 * costs.sum() / parts


def test_one_part_has_no_cut_and_auto_grows_in_powers_of_two():
    water = shapely.Polygon(OUTER)
    assert cut_lines(water, _grid(5.0, 0.0), 1) == []
    assert auto_parts(water, _grid(120.0, 0.0)) == 1  # about 7,700 triangles
    fine = SizeGrid(
        np.arange(0.0, 12001, 50), np.arange(0.0, 8001, 50), np.full((161, 241), 10.0)
    )  # 2,194,000 triangles: 11.0 parts
    assert auto_parts(water, fine) == 8

    def at(h: float) -> SizeGrid:
        return SizeGrid(fine.x, fine.y, np.full_like(fine.values, h))

    # the nearest power of two, by ratio: 6.0 parts' worth is 8, 5.0's is 4
    assert expected_triangles(water, at(13.52)) / 200_000 == pytest.approx(6.0, 0.01)
    assert auto_parts(water, at(13.52)) == 8
    assert auto_parts(water, at(14.81)) == 4
    with pytest.raises(ValueError, match="parts is 0"):
        cut_lines(water, _grid(5.0, 0.0), 0)


def test_split_faces_shares_cut_curves_and_keeps_ids():
    ring = OUTER
    island = ISLAND[::-1]
    faces = split_faces(
        [(ring, 1), (island, 9)],
        shapely.Polygon(ring, [island]),
        [shapely.LineString([(6000, -100), (6000, 8100)])],
    )
    assert len(faces.faces) == 2  # the cut crosses the island: two faces
    cut = [k for k, pid in enumerate(faces.ids) if pid is None]
    assert len(cut) == 2  # the two crossings of the water
    uses = np.zeros(len(faces.curves), int)
    for loops in faces.faces:
        for loop in loops:
            for s in loop:
                uses[abs(s) - 1] += 1
    assert (uses[cut] == 2).all()  # shared by both faces
    assert set(uses[[k for k in range(len(uses)) if k not in cut]]) == {1}
    assert sorted({pid for pid in faces.ids if pid is not None}) == [1, 9]


def test_a_sliver_between_two_cuts_joins_a_neighbour_and_fixed_cuts_stay():
    # two cuts 50 m apart across the water (and an island): the sliver
    # between them are parts of a few triangles unless joined to a side
    ring, island = OUTER, ISLAND[::-1]
    water = shapely.Polygon(ring, [island])
    cuts = [shapely.LineString([(x, -100), (x, 8100)]) for x in (6000.0, 6050.0)]
    fixed = shapely.LineString([(2000, -100), (2000, 8100)])
    faces = split_faces([(ring, 1), (island, 9)], water, [*cuts, fixed])
    assert len(faces.faces) == 5  # two slivers: above the island and below
    area = [face_polygon(faces, i).area for i in range(5)]
    assert sum(area) == pytest.approx(water.area)
    joined, dropped = merge_small_faces(
        faces, water, lambda p: p.area, 1e6, fixed=[fixed]
    )
    # each sliver (under 1 km2) joined a side; the fixed cut's faces stay
    assert dropped == 2 and len(joined.faces) == 3
    areas = sorted(face_polygon(joined, i).area for i in range(3))
    assert min(areas) >= 1e6
    assert sum(areas) == pytest.approx(water.area)
    left = shapely.box(-1e4, -1e4, 2000, 1e4).intersection(water).area
    assert any(a == pytest.approx(left) for a in areas)
    # ids of the coast are kept
    assert sorted({i for i in joined.ids if i is not None}) == [1, 9]
    # nothing to join: as it was
    same, none = merge_small_faces(faces, water, lambda p: p.area, 1.0)
    assert none == 0 and same is faces


def test_chunks_share_their_ends():
    piece = np.column_stack([np.arange(1300.0), np.zeros(1300)])
    chunks = chunked([(piece, 4)], most=500)
    assert [len(c) for c, _ in chunks] == [434, 434, 434]
    assert all((a[-1] == b[0]).all() for (a, _), (b, _) in itertools.pairwise(chunks))
    assert np.array_equal(
        np.vstack([chunks[0][0], *(c[1:] for c, _ in chunks[1:])]), piece
    )


def _backwards(fn, items):
    """Run the tasks last first: results must not depend on the order."""
    return [fn(item) for item in items[::-1]][::-1]


@pytest.fixture(scope="module")
def meshes():
    domain, grid = _domain(), _grid()
    with pytest.MonkeyPatch.context() as patch:  # cut even a mesh this small
        patch.setattr(parts_module, "MIN_PART_TRIANGLES", 100)
        out = {(k, "serial"): generate_mesh(domain, grid, parts=k) for k in (1, 3, 4)}
        out[(3, "backwards")] = generate_mesh(domain, grid, parts=3, runner=_backwards)
        clean = CleanupOptions(max_valence=7)
        for k in (1, 3):
            out[(k, "clean")] = mesh_in_parts(domain, grid, parts=k, cleanup=clean)
        out[(3, "clean-backwards")] = generate_mesh(
            domain, grid, parts=3, runner=_backwards, cleanup=clean
        )
        with open_runner(2) as pool:  # spawned workers: the real module constant
            out[(3, "pool")] = generate_mesh(domain, grid, parts=3, runner=pool)
            out[(3, "clean-pool")] = generate_mesh(
                domain, grid, parts=3, runner=pool, cleanup=clean
            )
        return out


def test_small_regions_are_not_cut():
    water = shapely.Polygon(OUTER)
    # 7,700 expected triangles: under twice the least a part may hold
    assert cut_lines(water, _grid(120.0, 0.0), 4) == []


@settings(max_examples=20, deadline=None)
@given(parts=st.integers(2, 6), off=st.floats(0.0, 0.3))
@example(parts=2, off=0.3)  # 0.2 / 0.8 of the water: the 0.8 is cut again
def test_no_part_holds_much_more_than_its_share(parts, off):
    # every cut forced off balance by ``off`` (as where only a cut off balance
    # is clean): a part over OVERSIZE shares is cut again, and again
    water = shapely.Polygon(OUTER)
    grid = SizeGrid(
        np.arange(0.0, 12001, 50), np.arange(0.0, 8001, 50), np.full((161, 241), 10.0)
    )
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(parts_module, "_CANDIDATES", 1)  # only share - _SPREAD
        patch.setattr(parts_module, "_SPREAD", off)
        cuts = cut_lines(water, grid, parts)
    costs = np.array([expected_triangles(f, grid) for f in _faces(water, cuts)])
    total = expected_triangles(water, grid)
    assert costs.sum() == pytest.approx(total, rel=1e-9)
    assert costs.max() <= parts_module.OVERSIZE * total / parts * (1 + 1e-9)
    if off == 0.0:
        assert len(cuts) == parts - 1  # balanced cuts: no part is cut again


def test_a_part_cut_again_for_its_size_does_not_hide_a_cut_not_made():
    # the first cut is forced to 0.2 / 0.8; the 0.2 side (2 parts wanted) has
    # no clean cut; the 0.8 side's larger part is cut again, and again, for
    # its size: more cuts than asked, and still one asked for is missed
    water = shapely.Polygon(OUTER)
    grid = SizeGrid(
        np.arange(0.0, 12001, 50), np.arange(0.0, 8001, 50), np.full((161, 241), 10.0)
    )
    total = expected_triangles(water, grid)
    best, partial = parts_module._best_cut, parts_module._partial_cut

    def refuse_small(polygon, grid, coast, region, x, y, w, *rest):
        if w.sum() < 0.3 * total:  # no clean cut in a region under 30 %
            return (np.inf, shapely.LineString(), [], 0.0)
        return best(polygon, grid, coast, region, x, y, w, *rest)

    def refuse_small_partial(face, grid, coast, cells, *rest):
        if cells[2].sum() < 0.3 * total:  # nor one clean in part
            return []
        return partial(face, grid, coast, cells, *rest)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(parts_module, "_CANDIDATES", 1)  # only share - _SPREAD
        patch.setattr(parts_module, "_SPREAD", 0.3)
        patch.setattr(parts_module, "_best_cut", refuse_small)
        patch.setattr(parts_module, "_partial_cut", refuse_small_partial)
        plan = plan_cuts(water, grid, 4)
        assert cut_lines(water, grid, 4) == plan.cuts
    assert len(plan.cuts) > 3 and plan.missed == 1
    costs = np.array([expected_triangles(f, grid) for f in _faces(water, plan.cuts)])
    assert costs.max() <= parts_module.OVERSIZE * total / 4 * (1 + 1e-9)
    assert np.isclose(costs, 0.2 * total, rtol=0.02).sum() == 1  # the uncut side


@pytest.mark.parametrize("key", [(3, "serial"), (4, "serial"), (3, "clean")])
def test_parts_give_one_conforming_mesh_with_the_same_boundary(meshes, key):
    one, many = meshes[(1, "serial")], meshes[key]
    many = many[0] if isinstance(many, tuple) else many
    assert_one_conforming_mesh(one, many, shapely.Polygon(OUTER, [ISLAND]))


def assert_one_conforming_mesh(one, many, water):
    """``many`` (meshed in parts) is one mesh of ``water``, as ``one`` is."""
    _, counts = np.unique(many.points, axis=0, return_counts=True)
    assert (counts == 1).all()  # no duplicate node
    t = many.triangles
    edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    edges, uses = np.unique(edges, axis=0, return_counts=True)
    assert uses.max() == 2
    boundary = edges[uses == 1]
    # every edge used once is a tagged boundary edge: the cuts left no seam
    tagged = {tuple(e) for e in np.sort(many.boundary_edges, axis=1)}
    assert {tuple(e) for e in boundary} == tagged
    assert set(many.boundary_ids.tolist()) == set(one.boundary_ids.tolist())
    # boundary edges lie on the domain's boundary, none on a cut
    mid = many.points[many.boundary_edges].mean(axis=1)
    assert shapely.distance(water.boundary, shapely.points(mid)).max() < 1e-6
    # a cut adds about its length in edges: a few % on a mesh this small
    assert abs(len(many.triangles) - len(one.triangles)) < 0.05 * len(one.triangles)
    a = np.asarray(many.triangles)
    p = many.points[a]
    area = 0.5 * (
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    )
    assert (area > 0).all() and area.sum() == pytest.approx(water.area, rel=1e-9)


@pytest.mark.parametrize("how", ["backwards", "pool", "clean-backwards", "clean-pool"])
def test_the_mesh_does_not_depend_on_the_executor_or_order(meshes, how):
    a = meshes[(3, "clean")][0] if how.startswith("clean") else meshes[(3, "serial")]
    b = meshes[(3, how)]
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.triangles, b.triangles)
    np.testing.assert_array_equal(a.boundary_edges, b.boundary_edges)
    np.testing.assert_array_equal(a.boundary_ids, b.boundary_ids)


def test_too_many_parts_warns_and_meshes_fewer():
    # 7,700 expected triangles: not one cut leaves two parts of 10,000
    with pytest.warns(
        PartsWarning, match="at only 0 of the 3 places asked; meshing 1 parts"
    ):
        _, report = mesh_in_parts(_domain(), _grid(), parts=4)
    assert report.parts == 1 and report.wanted == 4 and report.cuts == ()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # "auto" asks for what it can have
        mesh_in_parts(_domain(), _grid(), parts="auto")


def test_bad_parts_and_threads_are_refused():
    with pytest.raises(ValueError, match="parts is 0"):
        generate_mesh(_domain(), _grid(), parts=0)
    with pytest.raises(ValueError, match=r"parts is 1\.5"):
        generate_mesh(_domain(), _grid(), parts=1.5)


def test_the_parts_figure_draws_every_cut_and_labels_every_part(monkeypatch):
    from coastmesh import plot

    monkeypatch.setattr(parts_module, "MIN_PART_TRIANGLES", 100)
    _, report = mesh_in_parts(_domain(), _grid(), parts=3)
    assert report.parts >= 3 and len(report.centres) == report.parts
    water = shapely.Polygon(OUTER, [ISLAND])
    assert all(water.contains(shapely.Point(c)) for c in report.centres)
    figure = plot.parts_figure(_domain(), report)
    ax = figure.axes[0]
    cuts = ax.collections[-1]
    assert len(cuts.get_segments()) == len(report.cuts) > 0
    labels = {int(t.get_text().split("\n")[0]): t.get_text() for t in ax.texts}
    total = sum(report.triangles)
    big = {k + 1: n for k, n in enumerate(report.triangles) if n >= 0.005 * total}
    assert set(labels) == set(big) and len(big) >= 3
    assert all(f"{n:,} tri" in labels[k] for k, n in big.items())


def _drawn_labels(centres, triangles):
    """The parts figure of these parts, drawn: its labels by part, and its note."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from coastmesh import plot
    from coastmesh.meshing.parts.report import PartsReport

    k = len(centres)
    report = PartsReport(
        k, k, (), (1.0,) * k, triangles, (1.0,) * k, ("w",) * k, centres
    )
    ax = plot.parts_figure(_domain(), report).axes[0]
    FigureCanvasAgg(ax.figure).draw()
    labels = {
        int(t.get_text().split("\n")[0]): t
        for t in ax.texts
        if t.get_text()[0].isdigit()
    }
    notes = [t.get_text() for t in ax.texts if t.get_text().startswith("not labelled")]
    boxes = [t.get_bbox_patch().get_window_extent() for t in labels.values()]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[:i])
    for t in labels.values():  # a label off its part's centre has a line to it
        assert (tuple(t.xyann) != (0.0, 0.0)) == (t.arrow_patch is not None)
    return labels, notes


def test_the_parts_figure_keeps_its_labels_apart():
    # parts 1-4 labelled at nearly one point, part 5 far from them
    centres = ((2000, 2000), (2100, 2050), (2200, 1950), (2050, 2150), (10000, 6000))
    labels, notes = _drawn_labels(centres, (5000, 4000, 3000, 2000, 6000))
    assert set(labels) == {1, 2, 3, 4, 5} and not notes  # room for all
    # the largest of the four and the lone one whole, at their centres
    for k, n in ((1, "5,000"), (5, "6,000")):
        assert f"{n} tri" in labels[k].get_text() and tuple(labels[k].xyann) == (0, 0)
    assert all(tuple(labels[k].xyann) != (0, 0) for k in (2, 3, 4))
    # forty parts at one point: those with no room are named in a note
    many = [(6000 + 10.0 * k, 1500.0) for k in range(40)]
    labels, notes = _drawn_labels(many, tuple(range(5000, 5040)))
    named = re.search(r"parts? ([\d, ]+)$", notes[0]) if notes else None
    hidden = {int(k) for k in named.group(1).split(", ")} if named else set()
    assert (
        hidden
        and not hidden & set(labels)
        and hidden | set(labels) == set(range(1, 41))
    )
    assert max(labels) == 40 and "5,039 tri" in labels[40].get_text()  # the largest


def _literal_stats(mesh, min_angle):
    """Literal: each triangle's angles by the law of cosines, one at a time."""
    boundary = set(mesh.boundary_edges.ravel().tolist())
    valence, angles, ratios, all_boundary = {}, [], [], 0
    for t in mesh.triangles.tolist():
        p = [mesh.points[v] for v in t]
        sides = [float(np.hypot(*(p[(i + 1) % 3] - p[(i + 2) % 3]))) for i in range(3)]
        a, b, c = sides
        corner = [
            np.degrees(np.arccos((b * b + c * c - a * a) / (2 * b * c))),
            np.degrees(np.arccos((c * c + a * a - b * b) / (2 * c * a))),
            np.degrees(np.arccos((a * a + b * b - c * c) / (2 * a * b))),
        ]
        angles.append(min(corner))
        s = (a + b + c) / 2
        area = np.sqrt(s * (s - a) * (s - b) * (s - c))
        ratios.append(2 * (area / s) / (a * b * c / (4 * area)))
        all_boundary += all(v in boundary for v in t)
        for v in t:
            valence[v] = valence.get(v, 0) + 1
    return {
        "boundary_triangles": all_boundary,
        "max_valence": max(n for v, n in valence.items() if v not in boundary),
        "slivers": sum(x < min_angle for x in angles),
        "min_angle": min(angles),
        "min_angle_p1": float(np.percentile(angles, 1)),
        "radius_ratio": min(ratios),
    }


@pytest.mark.parametrize("k", [1, 3])
def test_cleaning_in_parts_reports_as_if_the_whole_mesh_was_cleaned(meshes, k):
    # before: the merged Gmsh mesh (the same parts, uncleaned); after: the result
    gmsh_mesh = meshes[(k, "serial")]
    cleaned, report = meshes[(k, "clean")]
    if k > 1:
        assert report.parts == k and len(report.cleanup_seconds) == k
    c = report.cleanup
    for when, mesh in (("before", gmsh_mesh), ("after", cleaned)):
        literal = _literal_stats(mesh, 20.0)
        for name, value in literal.items():
            assert getattr(c, f"{name}_{when}") == pytest.approx(value, abs=1e-6), name
    assert c.smoothed_nodes > 0 and c.accepted in ("cleaned", "cleaned_partly")
    assert c.min_angle_after >= c.min_angle_before
    assert len(cleaned.points) - len(gmsh_mesh.points) == (
        c.boundary_splits + c.boundary_edge_splits
    )
    # the coast's nodes never move; the cuts' were held in the parts and are
    # smoothed once the parts are joined, so some of them move
    kept = {tuple(xy) for xy in cleaned.points.tolist()}
    coast = gmsh_mesh.points[np.unique(gmsh_mesh.boundary_edges)]
    assert all(tuple(xy) in kept for xy in coast.tolist())
    if report.cuts:
        on_cut = (
            shapely.distance(
                shapely.MultiLineString(list(report.cuts)),
                shapely.points(gmsh_mesh.points),
            )
            < 1e-6
        )
        stayed = [tuple(xy) in kept for xy in gmsh_mesh.points[on_cut].tolist()]
        assert on_cut.sum() > 10 and not all(stayed)


@settings(deadline=None, max_examples=40)
@given(
    frac=st.floats(0.01, 0.99),
    across_x=st.booleans(),
    seed=st.integers(0, 2**16),
)
def test_the_clipped_crossing_is_the_whole_polygons(frac, across_x, seed):
    # a jagged coast with islands: the line's wet part, clipped first or not
    water = jagged_water(seed)
    x0, y0, x1, y1 = water.bounds
    if across_x:
        at = x0 + frac * (x1 - x0)
        line = shapely.LineString([(at, y0), (at, y1)])
    else:
        at = y0 + frac * (y1 - y0)
        line = shapely.LineString([(x0, at), (x1, at)])
    fast, literal = crossings.wet(water, line), shapely.intersection(water, line)
    assert shapely.get_num_geometries(fast) == shapely.get_num_geometries(literal)
    assert fast.length == pytest.approx(literal.length, abs=1e-6)
    assert shapely.hausdorff_distance(fast, literal) < 1e-6


def jagged_water(seed):
    """A jagged coast with five islands, as GEOS makes it valid."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    r = 5000 * (1 + 0.3 * rng.random(len(t)))
    shell = np.column_stack([r * np.cos(t), r * np.sin(t)])
    holes = [
        c + 300 * np.column_stack([np.cos(t[::20]), np.sin(t[::20])])
        for c in rng.uniform(-2500, 2500, (5, 2))
    ]
    return shapely.make_valid(shapely.Polygon(shell, holes))
