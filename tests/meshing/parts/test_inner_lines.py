"""Lines inside the water (``[[lines]]``): embedded as mesh edges, held after."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from coastmesh.io import read_mesh, write_mesh
from coastmesh.meshing import generate_mesh
from coastmesh.meshing.cleanup.fixes import clean_mesh
from coastmesh.meshing.cleanup.report import CleanupOptions
from coastmesh.meshing.cleanup.time_step_relief import _held
from coastmesh.meshing.parts.inner import Inner, node_line
from coastmesh.types import BoundarySegment, Domain, Mesh, MeshLine, SizeGrid
from coastmesh.types.topology import unique_edges

RING = [[0, 0], [20000, 0], [20000, 10000], [0, 10000], [0, 0]]
DOMAIN = Domain(
    shapely.Polygon(RING),
    (BoundarySegment(RING, "shoreline", "coast", 1),),
    "EPSG:32630",
)
X, Y = np.linspace(-500, 20500, 43), np.linspace(-500, 10500, 23)
SIZE = SizeGrid(X, Y, np.full((len(Y), len(X)), 400.0))
CABLE = np.array([[2000, 2000], [6000, 5000], [12000, 5200], [13000, 8000]], float)
FARM = shapely.box(3000, 6000, 5000, 8000)
ARRAY = np.array([[3500.0, 6500.0], [4500.0, 7500.0]])
CLEAN = CleanupOptions(True, 8, 20.0, True)


def reference_follows(mesh: Mesh, given: np.ndarray, pid: int) -> None:
    """Literal: the line's edges are interior mesh edges that trace the line."""
    edges, ids = mesh.line_edges()
    mine = edges[ids == pid]
    inner, count = unique_edges(mesh.triangles, len(mesh.points))
    interior = {tuple(e) for e in inner[count == 2].tolist()}
    for a, b in mine.tolist():
        assert (min(a, b), max(a, b)) in interior
    traced = shapely.union_all(shapely.linestrings(mesh.points[mine]))
    line = shapely.LineString(given)
    assert traced.length == pytest.approx(line.length, rel=1e-12)
    assert shapely.hausdorff_distance(traced, line) < 1e-6
    corners = {tuple(p) for p in mesh.points[mine].reshape(-1, 2).tolist()}
    assert all(tuple(v) in corners for v in given.tolist())  # every vertex a node


@pytest.fixture(scope="module")
def meshed():
    inner = Inner(
        regions=[(FARM, 20, "farm")],
        lines=[(CABLE, 40, "cable"), (ARRAY, 41, "array")],
    )
    return generate_mesh(DOMAIN, SIZE, inner=inner, cleanup=CLEAN)


def test_a_line_is_a_chain_of_interior_mesh_edges(meshed):
    reference_follows(meshed, CABLE, 40)
    reference_follows(meshed, ARRAY, 41)  # inside the farm's region
    assert [(ln.id, ln.name) for ln in meshed.lines] == [(40, "cable"), (41, "array")]
    edges, _ids = meshed.line_edges()
    lengths = np.linalg.norm(np.diff(meshed.points[edges], axis=1)[:, 0], axis=1)
    assert 0.7 * 400 < np.median(lengths) <= 400 * (1 + 1e-9)  # the local size
    centres = meshed.points[meshed.triangles].mean(axis=1)
    farm = shapely.contains_xy(FARM, *centres.T)
    assert (meshed.regions[farm] == 20).all() and (meshed.regions[~farm] == 1).all()


@settings(deadline=None, max_examples=12)
@given(
    st.lists(
        st.tuples(st.floats(1000, 19000), st.floats(1000, 9000)),
        min_size=2,
        max_size=5,
        unique=True,
    ),
    st.floats(150.0, 800.0),
)
def test_any_simple_line_is_followed(points, h):
    line = np.array(points)
    assume(shapely.LineString(line).is_simple)
    assume(shapely.LineString(line).length >= h)
    size = SizeGrid(X, Y, np.full((len(Y), len(X)), h))
    mesh = generate_mesh(DOMAIN, size, inner=Inner(lines=[(line, 9, "l")]))
    reference_follows(mesh, line, 9)


def test_node_line_keeps_every_vertex_and_splits_at_the_size():
    out = node_line(CABLE, lambda xy: np.full(len(xy), 1000.0))
    assert {tuple(v) for v in CABLE.tolist()} <= {tuple(v) for v in out.tolist()}
    sides = np.linalg.norm(np.diff(out, axis=0), axis=1)
    assert sides.max() <= 1000.0 + 1e-9
    assert shapely.LineString(out).length == pytest.approx(
        shapely.LineString(CABLE).length
    )


def _kite(with_line: bool) -> Mesh:
    """Two triangles whose shared edge a flip would make better: a sliver pair."""
    points = [[0, 0], [10, 0], [5, 0.6], [5, -0.6], [-5, 5], [15, 5], [5, -6]]
    triangles = [
        [0, 3, 1],
        [0, 1, 2],
        [0, 2, 4],
        [2, 1, 5],
        [2, 5, 4],
        [3, 6, 1],
        [0, 6, 3],
    ]
    edges, count = unique_edges(np.array(triangles), len(points))
    boundary = edges[count == 1]
    lines = [MeshLine(9, "weir", [[0, 0], [10, 0]])] if with_line else []
    return Mesh(points, triangles, boundary, [1] * len(boundary), 1, None, lines=lines)


def test_the_cleanup_never_flips_or_moves_a_line():
    free, _ = clean_mesh(_kite(False), min_angle=20.0)
    edges, _ = unique_edges(free.triangles, len(free.points))
    assert [0, 1] not in edges.tolist()  # flipped away without the line
    held, _ = clean_mesh(_kite(True), min_angle=20.0)
    edges, _ = unique_edges(held.triangles, len(held.points))
    assert [0, 1] in edges.tolist()
    assert held.line_edges()[0].tolist() == [[0, 1]]


def test_the_relief_holds_the_nodes_of_lines(meshed):
    edges, _ = meshed.line_edges()
    held = _held(meshed, None)
    assert held[edges.ravel()].all()


def test_a_line_node_that_is_not_a_mesh_node_is_named():
    mesh = _kite(False)
    moved = Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        mesh.boundary_ids,
        1,
        None,
        lines=[MeshLine(9, "weir", [[0, 0], [10, 0.5]])],
    )
    with pytest.raises(ValueError, match=r"line 'weir' \(id 9\): its node at"):
        moved.line_edges()


@pytest.mark.parametrize("fmt", ["msh2", "msh4"])
def test_lines_survive_the_msh_files(meshed, tmp_path, fmt):
    path = tmp_path / f"m.{fmt}.msh"
    write_mesh(path, meshed, format=fmt)
    back = read_mesh(path)
    assert sorted(ln.id for ln in back.lines) == [40, 41]
    for ln in meshed.lines:
        again = next(b for b in back.lines if b.id == ln.id)
        assert np.array_equal(again.xy, ln.xy) or np.array_equal(again.xy[::-1], ln.xy)
        if fmt == "msh2":  # msh 4.1 files carry ids only
            assert again.name == ln.name
    assert len(back.boundary_edges) == len(meshed.boundary_edges)
    assert 40 not in back.boundary_names


def test_gmsh_reads_the_lines_as_1d_physical_groups(meshed, tmp_path):
    gmsh = pytest.importorskip("gmsh")
    path = tmp_path / "m.msh"
    write_mesh(path, meshed)
    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        groups = {
            (dim, tag): gmsh.model.getPhysicalName(dim, tag)
            for dim, tag in gmsh.model.getPhysicalGroups(1)
        }
        assert groups[(1, 40)] == "line:cable" and groups[(1, 41)] == "line:array"
        count = 0
        for entity in gmsh.model.getEntitiesForPhysicalGroup(1, 40):
            _types, tags, _ = gmsh.model.mesh.getElements(1, entity)
            count += sum(len(t) for t in tags)
        assert count == len(meshed.lines[0].xy) - 1
    finally:
        gmsh.finalize()
