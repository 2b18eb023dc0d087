"""[[structures]]: land placed in the sea, cut out with a boundary id of its own."""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest
import shapely
from conftest import EXAMPLE, coarse_example_text
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import CRS

import coastmesh
from coastmesh.case import parse_case
from coastmesh.case.pipeline.structures import check_structure_sizes
from coastmesh.errors import ConfigError
from coastmesh.geometry import (
    OpenBoundary,
    build_domain,
    domain_with_land,
    domain_with_structures,
)
from coastmesh.io import read_mesh
from coastmesh.types import SizeGrid
from coastmesh.types.topology import unique_edges

# a bay 10 x 7 (units of the plane): the coast along y = 2, open on the rest
LAND = [shapely.box(0, 0, 10, 2)]
WALLS = [OpenBoundary([(1, 1), (1, 9), (9, 9), (9, 1)], "open", 2)]
SETS = [("coast", 1, None)]
CRS_M = "EPSG:32630"


def _bay():
    return build_domain(LAND, WALLS, crs=CRS_M, shorelines=SETS)


def _cut(*structures, seed=None):
    domain, report = _bay()
    return domain_with_structures(
        domain, list(structures), WALLS, report, shorelines=SETS, seed=seed
    )


def _edges(domain):
    """Every boundary edge as (a, b, name)."""
    out = []
    for s in domain.segments:
        out += [
            (a, b, s.name) for a, b in zip(s.coords[:-1], s.coords[1:], strict=True)
        ]
    return out


def reference_names(domain, structures):
    """Literal: an edge on a structure's outline is the structure's, else not."""
    names = []
    for a, b, _ in _edges(domain):
        mid = shapely.Point((a + b) / 2)
        on = [n for n, _, p in structures if p.boundary.distance(mid) < 1e-9]
        names.append(on[0] if on else None)
    return names


def _check_tags(domain, structures):
    for (_, _, got), want in zip(
        _edges(domain), reference_names(domain, structures), strict=True
    ):
        if want is None:
            assert got in {"coast", "open"}
        else:
            assert got == want


def test_an_island_structure_is_a_hole_with_its_id():
    island = ("island", 7, shapely.box(4, 5, 5, 6))
    domain, report = _cut(island)
    assert domain.polygon.area == pytest.approx(56.0 - 1.0, abs=1e-12)
    assert report.holes == 1 and len(domain.polygon.interiors) == 1
    pier = [s for s in domain.segments if s.name == "island"]
    assert len(pier) == 1 and pier[0].physical_id == 7 and pier[0].kind == "shoreline"
    assert shapely.Polygon(pier[0].coords).equals(island[2])
    _check_tags(domain, [island])


def test_a_pier_from_the_coast_is_a_notch_with_its_id():
    pier = ("pier", 8, shapely.box(4, 1, 4.5, 5))  # from under the coast to y = 5
    domain, report = _cut(pier)
    assert domain.polygon.area == pytest.approx(56.0 - 0.5 * 3, abs=1e-12)
    assert report.holes == 0
    on_pier = [s for s in domain.segments if s.name == "pier"]
    assert sum(shapely.LineString(s.coords).length for s in on_pier) == pytest.approx(
        3 + 0.5 + 3
    )
    _check_tags(domain, [pier])


@settings(deadline=None, max_examples=60)  # a domain built per example
@given(
    st.lists(
        st.tuples(
            st.floats(1.5, 8.0), st.floats(2.5, 8.0), st.floats(0.1, 0.9), st.booleans()
        ),
        min_size=1,
        max_size=4,
    )
)
def test_every_edge_on_an_outline_and_only_those_take_its_id(boxes):
    structures, shapes = [], []
    for k, (x, y, w, to_coast) in enumerate(boxes):
        shape = shapely.box(x, 1.0 if to_coast else y, x + w, y + w)
        if any(shape.buffer(0.05).intersects(s) for s in shapes):
            continue
        shapes.append(shape)
        structures.append((f"s{k}", 10 + k, shape))
    try:
        domain, _ = _cut(*structures)
    except ConfigError as exc:  # piers side by side can close the water between
        assert "cut the sea in" in str(exc)
        return
    _check_tags(domain, structures)
    sea = shapely.difference(_bay()[0].polygon, shapely.union_all(shapes))
    assert domain.polygon.area == pytest.approx(sea.area, rel=1e-12)


@pytest.mark.parametrize(
    ("structures", "seed", "message"),
    [
        ([("far", 7, shapely.box(20, 20, 21, 21))], None, "'far'.*wholly on land"),
        (
            [("a", 7, shapely.box(4, 5, 5, 6)), ("b", 8, shapely.box(5, 5, 6, 6))],
            None,
            "'b': touches structure 'a'",
        ),
        ([("wall", 7, shapely.box(4, 1, 4.5, 9.5))], None, "crosses the open bound"),
        ([("dam", 7, shapely.box(0.5, 5, 9.5, 5.5))], None, "crosses the open"),
        ([("big", 7, shapely.box(4, 5, 5, 6))], (4.5, 5.5), "'big': covers the seed"),
        ([("bad", 7, shapely.Polygon([(4, 4), (5, 5), (5, 4), (4, 5)]))], None, "not"),
    ],
)
def test_bad_structures_are_named(structures, seed, message):
    with pytest.raises(ConfigError, match=message):
        _cut(*structures, seed=seed)


def test_a_structure_that_cuts_the_sea_in_two_is_refused():
    # a wall from the coast that meets an island: the water behind is cut off
    land = [*LAND, shapely.box(3, 6, 7, 7)]
    domain, report = build_domain(land, WALLS, crs=CRS_M, shorelines=SETS)
    wall = ("wall", 7, shapely.box(2, 1, 3.5, 6.5))
    ring = ("ring", 8, shapely.box(6.5, 1, 8, 6.5))
    with pytest.raises(ConfigError, match=r"\['wall', 'ring'\].*cut the sea in 2"):
        domain_with_structures(domain, [wall, ring], WALLS, report, shorelines=SETS)


def test_a_closing_keeps_a_structure_smaller_than_min_area():
    island = ("islet", 7, shapely.box(4, 5, 4.2, 5.2))
    domain, report = _cut(island)
    closed = [shapely.box(8, 2, 8.5, 2.5)]
    kept, _ = domain_with_land(
        domain,
        closed,
        WALLS,
        report,
        min_area=1.0,
        shorelines=[island, *SETS],
        keep=[island[2]],
    )
    assert len(kept.polygon.interiors) == 1
    assert [s.physical_id for s in kept.segments if s.name == "islet"] == [7]
    dropped, _ = domain_with_land(
        domain, closed, WALLS, report, min_area=1.0, shorelines=[island, *SETS]
    )
    assert len(dropped.polygon.interiors) == 0  # what keep= is for


def test_a_structure_too_small_for_its_elements_is_named():
    state = SimpleNamespace(
        structures=(("pier", 7, shapely.box(0, 0, 50, 10)),),
        domain=SimpleNamespace(crs=CRS(CRS_M)),
        mesh_crs=CRS(CRS_M),
    )
    coarse = SizeGrid([-100.0, 200.0], [-100.0, 200.0], np.full((2, 2), 30.0))
    with pytest.raises(ConfigError, match=r"'pier'.*120 m.*4\.0 edges.*h_min <= 15"):
        check_structure_sizes(state, coarse, "case.toml")
    fine = SizeGrid([-100.0, 200.0], [-100.0, 200.0], np.full((2, 2), 15.0))
    check_structure_sizes(state, fine, "case.toml")  # 8 edges: enough


PIER = (
    "[[-3.1372, 58.6415], [-3.1362, 58.6415], [-3.1362, 58.6445], [-3.1372, 58.6445]]"
)
ISLAND = "[[-3.160, 58.657], [-3.156, 58.657], [-3.156, 58.659], [-3.160, 58.659]]"
STRUCTURES = f"""
[[structures]]
name = "pier"
id = 30
polygon = {PIER}

[[structures]]
name = "island"
id = 31
polygon = {ISLAND}

[[lines]]
name = "cable"
id = 40
points = [[-3.150, 58.657], [-3.140, 58.660], [-3.125, 58.660]]
h = "30 m"

[[mesh_size.gradations]]
lines = ["pier", "island"]
h_min = "25 m"
d_hold = "0 m"
d_grade = "4 km"
"""


def _case(extra: str = STRUCTURES):
    return parse_case(coarse_example_text() + extra, EXAMPLE)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("id = 30", "id = 10", r"structures\[0\]: id 10 is also the id of"),
        ('name = "island"', 'name = "pier"', "the name 'pier' is used twice"),
        ('lines = ["pier", "island"]', 'lines = ["peir"]', "'peir' is not a shoreline"),
        (PIER, "[[-3.1372, 58.6415], [-3.1362, 58.6415]]", "at least three points"),
    ],
)
def test_bad_structure_keys_are_named(old, new, message):
    with pytest.raises(ConfigError, match=message):
        _case(STRUCTURES.replace(old, new, 1))


@pytest.fixture(scope="module")
def built():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", coastmesh.CoastmeshWarning)
        return coastmesh.build_case(_case(), workers=1)


@pytest.mark.slow  # a whole case, built once
def test_structures_are_cut_out_with_their_ids(built, tmp_path):
    mesh = built.mesh
    names = {30: "pier", 31: "island"}
    for pid, polygon in ((30, PIER), (31, ISLAND)):
        shape = shapely.Polygon(eval(polygon))
        edges = mesh.boundary_edges[mesh.boundary_ids == pid]
        assert len(edges) >= 8, names[pid]
        segments = shapely.linestrings(mesh.points[edges])
        # every edge lies on the structure's outline (1e-7 deg ~ 1 cm: its
        # sides are straight in lon/lat, the edges in UTM)
        assert shapely.distance(shape.boundary, segments).max() < 1e-7
        assert mesh.boundary_names[pid] == names[pid]
        centres = mesh.points[mesh.triangles].mean(axis=1)
        assert not shapely.contains_xy(shape, *centres.T).any()  # nothing inside
    # the island's edges close a ring around it
    island = mesh.boundary_edges[mesh.boundary_ids == 31]
    assert np.all(np.bincount(island.ravel())[np.unique(island)] == 2)
    path = tmp_path / "s.msh"
    coastmesh.write_mesh(path, mesh)
    back = read_mesh(path)
    assert set(back.boundary_ids.tolist()) >= {30, 31}


@pytest.mark.slow  # a whole case, built once
def test_a_line_is_embedded_in_the_case_mesh(built, tmp_path):
    mesh = built.mesh
    (line,) = mesh.lines
    assert (line.id, line.name) == (40, "cable")
    edges, _ = mesh.line_edges()
    inner, count = unique_edges(mesh.triangles, len(mesh.points))
    interior = {tuple(e) for e in inner[count == 2].tolist()}
    assert all((min(a, b), max(a, b)) in interior for a, b in edges.tolist())
    given = shapely.LineString([(-3.150, 58.657), (-3.140, 58.660), (-3.125, 58.660)])
    traced = shapely.LineString(line.xy)
    # straight in UTM between its vertices, not in lon/lat: 1e-6 deg ~ 10 cm
    assert shapely.hausdorff_distance(traced, given) < 1e-6
    assert "line edges: cable (40)" in built.report.mesh.summary()
    path = tmp_path / "l.msh"
    coastmesh.write_mesh(path, mesh)
    assert [ln.id for ln in read_mesh(path).lines] == [40]
