"""The model writers against the models' own rules (tests/model_rules.py).

The checker parses the written files itself. It runs on domains hypothesis
draws (islands made of several shoreline sets, open boundaries that meet,
structures cut into the coast, a farm), on files written before the rules were
followed (where it must fail), and on files broken by hand, one rule each.
"""

from __future__ import annotations

import collections
import itertools
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from model_rules import (
    check_adcirc,
    check_schism,
    check_telemac,
    liquid_boundaries,
    parse_grid,
)

import coastmesh
from coastmesh.errors import CoastmeshWarning

DATA = Path(__file__).parents[1] / "data" / "models"
OPEN_IDS = (2, 5, 6)
SHORE_IDS = (1, 7)
ISLAND_IDS = (3, 4, 1)
STRUCTURE = 9
KINDS = dict.fromkeys(OPEN_IDS, "open") | dict.fromkeys(
    (*SHORE_IDS, *ISLAND_IDS, STRUCTURE), "shoreline"
)
NAMES = {1: "coast", 2: "south", 3: "rock", 4: "reef", 5: "east", 6: "west",
         7: "cliffs", 9: "pier"}  # fmt: skip


def _segments(ring, ids, prefix):
    """BoundarySegments of a ring of vertices, one per run of one id."""
    from coastmesh.types import BoundarySegment

    ring = np.asarray(ring, dtype=float)
    k = len(ring)
    ids = list(ids)
    # start at a change of id, so that each run is one segment
    changes = [i for i in range(k) if ids[i] != ids[i - 1]] or [0]
    start = changes[0]
    order = [(start + i) % k for i in range(k)]
    out, run = [], [order[0]]
    for i in order[1:] + [None]:
        if i is not None and ids[i] == ids[run[0]]:
            run.append(i)
            continue
        coords = np.vstack([ring[run], ring[(run[-1] + 1) % k]])
        pid = ids[run[0]]
        out.append(BoundarySegment(coords, KINDS[pid], f"{prefix}{NAMES[pid]}", pid))
        if i is not None:
            run = [i]
    return out


@st.composite
def domains(draw):
    """A rectangle of sea with open and land sides, islands, a pier, a farm."""
    from coastmesh.types import Domain

    w = draw(st.floats(3000, 8000))
    h = draw(st.floats(3000, 8000))
    side = st.sampled_from(OPEN_IDS + SHORE_IDS)
    sides = [draw(st.lists(side, min_size=1, max_size=2)) for _ in range(4)]
    corners = [(0, 0), (w, 0), (w, h), (0, h)]
    ring, ids = [], []
    for k, pieces in enumerate(sides):
        a, b = np.array(corners[k]), np.array(corners[(k + 1) % 4])
        for j, pid in enumerate(pieces):
            ring.append(a + (b - a) * j / len(pieces))
            ids.append(pid)
        if k == 0 and draw(st.booleans()):  # a pier cut into the south side
            x0 = draw(st.floats(0.55, 0.75)) * w
            ring += [(x0, 0), (x0, 0.15 * h), (x0 + 0.1 * w, 0.15 * h),
                     (x0 + 0.1 * w, 0)]  # fmt: skip
            ids += [STRUCTURE] * 3 + [ids[-1]]
    ring = [tuple(p) for p in ring]
    segments = _segments(ring, ids, "")
    holes = []
    for cell in range(draw(st.integers(0, 3))):
        cx = (0.3 + 0.2 * cell) * w
        cy = draw(st.floats(0.5, 0.75)) * h
        r = 0.07 * min(w, h)
        if draw(st.booleans()):
            hole = [
                (cx - r, cy - r),
                (cx + r, cy - r),
                (cx + r, cy + r),
                (cx - r, cy + r),
            ]
        else:
            hole = [(cx - r, cy - r), (cx + r, cy - r), (cx, cy + r)]
        hole_ids = draw(st.lists(st.sampled_from(ISLAND_IDS), min_size=len(hole),
                                 max_size=len(hole)))  # fmt: skip
        holes.append(hole)
        segments += _segments(hole, hole_ids, f"island {cell} ")
    polygon = shapely.Polygon(ring, holes)
    assert polygon.is_valid, shapely.is_valid_reason(polygon)
    farm = None
    if draw(st.booleans()):
        farm = shapely.box(0.2 * w, 0.2 * h, 0.4 * w, 0.35 * h)
    return Domain(polygon, tuple(segments), crs="EPSG:32630"), farm, min(w, h) / 9


def _mesh(domain, farm, h):
    from coastmesh.meshing import generate_mesh
    from coastmesh.meshing.parts.inner import Inner
    from coastmesh.types import SizeGrid

    x0, y0, x1, y1 = domain.polygon.bounds
    grid = SizeGrid([x0, x1], [y0, y1], np.full((2, 2), h))
    inner = Inner(regions=[(farm, 20, "farm")]) if farm is not None else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        mesh = generate_mesh(domain, grid, inner=inner)
    mesh = mesh.with_point_data(depth=10.0 + mesh.points[:, 0] / 1000.0)
    return coastmesh.types.Mesh(
        mesh.points, mesh.triangles, mesh.boundary_edges, mesh.boundary_ids,
        mesh.surface_id, mesh.crs, mesh.point_data, NAMES | mesh.boundary_names,
        KINDS, regions=mesh.regions,
    )  # fmt: skip


def _edge_ids(mesh):
    return {
        (min(a, b), max(a, b)): int(i)
        for (a, b), i in zip(mesh.boundary_edges.tolist(), mesh.boundary_ids.tolist(),
                             strict=True)
    }  # fmt: skip


def _open_runs(mesh):
    """Maximal runs of open edges along each boundary ring (Telemac's count)."""
    from coastmesh.types.topology import boundary_rings

    count = 0
    for ring in boundary_rings(mesh):
        is_open = np.array([KINDS[int(i)] == "open" for i in ring.ids])
        if is_open.all():
            count += 1
        else:
            count += int(np.count_nonzero(is_open & ~np.roll(is_open, 1)))
    return count


@settings(
    max_examples=40,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture,
                           HealthCheck.too_slow],
)  # fmt: skip
@given(drawn=domains())
def test_every_writer_follows_its_models_rules(tmp_path_factory, drawn):
    domain, farm, h = drawn
    mesh = _mesh(domain, farm, h)
    folder = tmp_path_factory.mktemp("rules")
    for name in ("fort.14", "hgrid.gr3", "mesh.slf"):
        coastmesh.write_mesh(folder / name, mesh)
    assert check_adcirc(folder / "fort.14") == []
    assert check_schism(folder / "hgrid.gr3") == []
    assert check_telemac(folder / "mesh.slf", folder / "mesh.cli") == []
    assert liquid_boundaries(folder / "mesh.slf", folder / "mesh.cli") == _open_runs(
        mesh
    )
    want = _edge_ids(mesh)
    for name in ("fort.14", "hgrid.gr3"):
        back = coastmesh.read_mesh(folder / name)
        assert _edge_ids(back) == want, name
        assert back.boundary_kinds == {i: KINDS[i] for i in set(want.values())}
    # ADCIRC: each island one closed segment, whatever sets make it up
    grid = parse_grid(folder / "fort.14")
    islands = [s for s in grid.land if s[1] == 1]
    assert len(islands) == len(domain.polygon.interiors)


def test_the_checker_fails_on_the_writers_before_the_rules():
    """Files written at bc770b9: an island of two sets, open sides that meet."""
    adcirc = check_adcirc(DATA / "before_bc770b9.14")
    rules = collections.Counter(b.rule for b in adcirc)
    assert rules == {"A3": 4, "A5": 1}
    (corner,) = (b for b in adcirc if b.rule == "A5")
    assert (corner.node, corner.segment) == (7, "open segment 2")
    assert {b.segment for b in adcirc if b.rule == "A3"} == {
        "land segment 2",
        "land segment 3",
    }
    schism = check_schism(DATA / "before_bc770b9.gr3")
    assert [(b.rule, b.node, b.segment) for b in schism] == [
        ("S4", 19, "land segment 2"),
        ("S4", 31, "land segment 3"),
    ]
    # the same mesh, read back and written by today's writers, follows them
    mesh = coastmesh.read_mesh(DATA / "before_bc770b9.14")
    assert len(set(mesh.boundary_ids.tolist())) == 5


def test_the_same_mesh_written_now_follows_the_rules(tmp_path):
    mesh = coastmesh.read_mesh(DATA / "before_bc770b9.14")
    coastmesh.write_mesh(tmp_path / "fort.14", mesh)
    coastmesh.write_mesh(tmp_path / "hgrid.gr3", mesh)
    assert check_adcirc(tmp_path / "fort.14") == []
    assert check_schism(tmp_path / "hgrid.gr3") == []
    grid = parse_grid(tmp_path / "fort.14")
    assert len(grid.open) == 1  # the south and east sides meet: one segment
    assert [len(n) for n, _, _ in grid.open] == [13]  # node 7 once
    assert [code for _, code, _ in grid.land] == [0, 1]


# the checker catches each rule, on files broken by hand ---------------------------


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """The bc770b9 mesh written now: fort.14, gr3, slf + cli, and their text."""
    folder = tmp_path_factory.mktemp("good")
    mesh = coastmesh.read_mesh(DATA / "before_bc770b9.14")
    for name in ("fort.14", "hgrid.gr3", "mesh.slf"):
        coastmesh.write_mesh(folder / name, mesh)
    return folder


def _package_rules(path: Path, model: str) -> list[tuple[str, str]]:
    """What coastmesh's own audit (``rule_breaks``, used by convert) finds."""
    from coastmesh.io.meshes.adcirc import read_fort14, read_fort14_mesh, rule_breaks

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        mesh = read_fort14_mesh(path, crs="EPSG:32630")
    return [(b.rule, b.segment) for b in rule_breaks(read_fort14(path), mesh, model)]


def _edit(src: Path, dst: Path, old: str, new: str) -> Path:
    text = src.read_text()
    assert old in text, old
    dst.write_text(text.replace(old, new, 1))
    return dst


def _segment_text(path: Path, which: str, k: int) -> str:
    """The header and node lines of one segment, as written."""
    grid = parse_grid(path)
    nodes = getattr(grid, which)[k][0]
    lines = path.read_text().splitlines()
    for i, line in enumerate(lines):
        if f"Number of nodes for {which} boundary {k + 1}:" in line:
            return "\n".join(lines[i : i + 1 + len(nodes)]) + "\n"
    raise AssertionError("segment not found")


def test_adcirc_rules_catch_a_corner_listed_twice(good, tmp_path):
    text = (good / "fort.14").read_text()
    seg = _segment_text(good / "fort.14", "open", 0)
    _, *body = seg.splitlines()
    # split the open segment in two at its 7th node, listed in both
    first = ["7 0 = Number of nodes for open boundary 1: id 2"] + body[:7]
    second = [f"{len(body) - 6} 0 = Number of nodes for open boundary 2: id 5"]
    second += body[6:]
    text = text.replace(seg, "\n".join(first + second) + "\n")
    text = text.replace(
        "1 = Number of open boundaries", "2 = Number of open boundaries"
    )
    total = len(body) + 1
    text = text.replace(
        f"{len(body)} = Total number of open", f"{total} = Total number of open"
    )
    (tmp_path / "fort.14").write_text(text)
    breaks = check_adcirc(tmp_path / "fort.14")
    assert [(b.rule, b.segment) for b in breaks] == [("A5", "open segment 2")]
    assert _package_rules(tmp_path / "fort.14", "adcirc") == [("A5", "open segment 2")]


def test_adcirc_rules_catch_an_unclosed_island_and_a_wrong_type(good, tmp_path):
    seg = _segment_text(good / "fort.14", "land", 1)
    head, *body = seg.splitlines()
    broken = "\n".join([head.replace(" 1 = ", " 0 = ", 1)] + body) + "\n"
    path = _edit(good / "fort.14", tmp_path / "fort.14", seg, broken)
    assert {b.rule for b in check_adcirc(path)} == {"A3"}
    assert _package_rules(path, "adcirc") == [("A3", "land segment 2")]


def test_adcirc_rules_catch_a_reversed_segment(good, tmp_path):
    seg = _segment_text(good / "fort.14", "land", 0)
    head, *body = seg.splitlines()
    path = _edit(good / "fort.14", tmp_path / "fort.14", seg,
                 "\n".join([head] + body[::-1]) + "\n")  # fmt: skip
    rules = {b.rule for b in check_adcirc(path)}
    assert "cover" in rules


def test_schism_rules_catch_a_looped_open_segment_and_a_missing_node(good, tmp_path):
    seg = _segment_text(good / "hgrid.gr3", "land", 1)  # the island
    head, *body = seg.splitlines()
    fewer = "\n".join([head.replace(f"{len(body)} 1", f"{len(body) - 1} 1", 1)])
    fewer += "\n" + "\n".join(body[:-1]) + "\n"
    text = (good / "hgrid.gr3").read_text().replace(seg, fewer)
    total = sum(len(n) for n, _, _ in parse_grid(good / "hgrid.gr3").land)
    text = text.replace(
        f"{total} = Total number of land", f"{total - 1} = Total number of land"
    )
    (tmp_path / "hgrid.gr3").write_text(text)
    rules = collections.Counter(b.rule for b in check_schism(tmp_path / "hgrid.gr3"))
    assert rules["S3"] == 1 and rules["S4"] == 1
    assert {r for r, _ in _package_rules(tmp_path / "hgrid.gr3", "schism")} == {
        "S3",
        "S4",
    }


def test_telemac_rules_catch_a_solid_node_between_liquid_ones(good, tmp_path):
    lines = (good / "mesh.cli").read_text().splitlines()
    # the open boundary's 3rd node made solid: a solid point between liquid ones
    k = next(i for i, line in enumerate(lines) if line.startswith("5 4 4")) + 2
    lines[k] = "2 2 2" + lines[k][5:]
    (tmp_path / "mesh.cli").write_text("\n".join(lines) + "\n")
    breaks = check_telemac(good / "mesh.slf", tmp_path / "mesh.cli")
    assert [b.rule for b in breaks] == ["T3"]


def test_telemac_rules_catch_lines_out_of_order(good, tmp_path):
    lines = (good / "mesh.cli").read_text().splitlines()
    a, b = lines[3].split(), lines[4].split()
    a[11], b[11] = b[11], a[11]  # swap two nodes, keep K
    lines[3], lines[4] = " ".join(a), " ".join(b)
    (tmp_path / "mesh.cli").write_text("\n".join(lines) + "\n")
    rules = {b.rule for b in check_telemac(good / "mesh.slf", tmp_path / "mesh.cli")}
    assert rules == {"T2"}  # IPOBO no longer fits; T4 is checked once it does


def test_the_ids_of_a_segment_of_several_sets_read_back(tmp_path):
    mesh = coastmesh.read_mesh(DATA / "before_bc770b9.14")
    coastmesh.write_mesh(tmp_path / "fort.14", mesh)
    text = (tmp_path / "fort.14").read_text()
    assert ": id 2 south; id 5 @7 east" in text
    back = coastmesh.read_mesh(tmp_path / "fort.14")
    assert _edge_ids(back) == _edge_ids(mesh)
    assert back.boundary_names == mesh.boundary_names


def test_a_lake_and_a_ring_open_all_round(tmp_path):
    """A ring of one kind all round: ADCIRC closes land, lists open nodes once."""
    from io_meshes import cell_mesh

    for kind, pid in (("shoreline", 1), ("open", 2)):
        mesh = cell_mesh(3, set(), lambda p, q, pid=pid: pid, {pid: kind})
        coastmesh.write_mesh(tmp_path / "fort.14", mesh, overwrite=True)
        coastmesh.write_mesh(tmp_path / "hgrid.gr3", mesh, overwrite=True)
        assert check_adcirc(tmp_path / "fort.14") == []
        assert check_schism(tmp_path / "hgrid.gr3") == []
        grid = parse_grid(tmp_path / "fort.14")
        segments = grid.open if kind == "open" else grid.land
        ((nodes, _, _),) = segments
        if kind == "open":
            assert len(nodes) == len(set(nodes.tolist())) == 12  # once, not closed
        else:
            assert nodes[0] == nodes[-1] and len(nodes) == 13
        for name in ("fort.14", "hgrid.gr3"):
            assert _edge_ids(coastmesh.read_mesh(tmp_path / name)) == _edge_ids(mesh)


def test_pairs_of_every_segment_are_boundary_edges(good):
    """The checker's own parse: each segment walks the boundary."""
    grid = parse_grid(good / "fort.14")
    for nodes, _, _ in grid.open + grid.land:
        assert all(a != b for a, b in itertools.pairwise(nodes.tolist()))
