"""patch_mesh and ``coastmesh patch`` on a small mesh of the Inner Sound.

The existing mesh is a Gmsh mesh of a 16 km x 11 km box of the Pentland Firth
(UTM 30N) with a coast to the south, open sides and an island, written in
longitude and latitude with depths: a mesh "from elsewhere". The site is a
farm with three turbines, sized and given depths by the bundled ETOPO1 tile.
Every check is measured from the input and the output meshes alone: which
elements kept their nodes at their number, which nodes kept their
coordinates bit for bit, how the edges pair up, how the areas add up.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from conftest import assert_clean_failure
from model_rules import check_adcirc, check_schism, check_telemac
from pyproj import Transformer

import coastmesh
from coastmesh.case import read_case
from coastmesh.case.patch import patch_mesh
from coastmesh.commands.patch import patch_files
from coastmesh.data import path as data_path
from coastmesh.depth.nodes import CoarseRasterWarning
from coastmesh.errors import CoastmeshWarning, InputDataError
from coastmesh.geometry.earth import reproject_points
from coastmesh.types import BoundarySegment, Domain, Mesh, SizeGrid

UTM = "EPSG:32630"
#: the existing mesh's box in UTM 30N: the coast along its south side
BOX = (484_000.0, 6_497_000.0, 500_000.0, 6_508_000.0)
FARM_ID = 20
FARM = [[-3.145, 58.655], [-3.128, 58.655], [-3.128, 58.662], [-3.145, 58.662]]
TURBINES = [[-3.140, 58.6585], [-3.135, 58.6585], [-3.130, 58.6585]]
#: a polygon round the farm, in lon/lat (so an axis-aligned box in EPSG:3857 too)
AROUND = (-3.16, 58.645, -3.11, 58.672)
#: a polygon round the farm reaching across the coast, in UTM 30N
TO_THE_COAST = (490_000.0, 6_496_000.0, 494_000.0, 6_503_500.0)

CASE = f"""
# the site's case: only its farm, turbines, sizes and bathymetry are used by a
# patch; the shorelines, shoreline sets, domain and open boundaries are keys
# every case file has
[case]
name = "site"

[shorelines]
path = "{data_path("orkney_gshhg_f.geojson").as_posix()}"

[shoreline_sets.full]
id = 10

[domain]
seed = [-3.1, 58.85]

[[open_boundaries]]
name = "west"
id = 2
kind = "loxodrome"
start = [-3.6, 58.55]
bearing = 0
end_lat = 59.5

[mesh_size]
h_max = "1 km"
rate = 0.25

[bathymetry]
path = "{data_path("etopo1_0.1deg_orkney_wide.tif").as_posix()}"
"""

SITE = f"""
[[farms]]
name = "array"
id = {FARM_ID}
polygon = {FARM}
h = "60 m"

[[turbines]]
name = "row"
farm = "array"
diameter = "18 m"
positions = {TURBINES}
h = "30 m"
"""


def _existing_mesh() -> Mesh:
    """The mesh to patch: Gmsh, 300 to 700 m elements, lon/lat, depths."""
    from coastmesh.meshing import generate_mesh

    x0, y0, x1, y1 = BOX
    island = [(487500, 6505000), (488000, 6504600), (488600, 6505100),
              (488000, 6505600), (487500, 6505000)]  # fmt: skip
    polygon = shapely.Polygon(shapely.box(*BOX).exterior.coords, [island])
    domain = Domain(
        polygon,
        (
            BoundarySegment([[x0, y0], [x1, y0]], "shoreline", "coast", 1),
            BoundarySegment([[x1, y0], [x1, y1], [x0, y1], [x0, y0]], "open", "sea", 2),
            BoundarySegment(polygon.interiors[0].coords, "shoreline", "stroma", 3),
        ),
        crs=UTM,
    )
    x, y = np.linspace(x0, x1, 5), np.linspace(y0, y1, 5)
    size = 300.0 + 50.0 * (np.arange(5)[:, None] + np.arange(5)[None, :])
    utm = generate_mesh(domain, SizeGrid(x, y, size))
    return Mesh(
        reproject_points(utm.points, UTM, "EPSG:4326"),
        utm.triangles,
        utm.boundary_edges,
        utm.boundary_ids,
        utm.surface_id,
        "EPSG:4326",
        point_data={"depth": 10.0 + (utm.points[:, 1] - y0) / 200.0},
        boundary_names=utm.boundary_names,
        boundary_kinds=utm.boundary_kinds,
    )


@pytest.fixture(scope="module")
def existing() -> Mesh:
    return _existing_mesh()


@pytest.fixture(scope="module")
def case_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("site") / "site.toml"
    path.write_text(CASE + SITE)
    return path


@pytest.fixture(scope="module")
def no_site_file(tmp_path_factory) -> Path:
    """A case without farms or turbines: coarse sizes, growing fast."""
    path = tmp_path_factory.mktemp("coarse") / "coarse.toml"
    path.write_text(
        CASE.replace('h_max = "1 km"', 'h_max = "3 km"').replace(
            "rate = 0.25", "rate = 0.6"
        )
    )
    return path


def _patch(mesh, case, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)  # ETOPO1 is coarse
        return patch_mesh(mesh, read_case(case), **options)


@pytest.fixture(scope="module")
def patched(existing, case_file):
    return _patch(existing, case_file)


# -- what the checks measure ------------------------------------------------


def _same_bits(a, b) -> bool:
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and bool((a.view(np.uint64) == b.view(np.uint64)).all())


def _doubled_areas(xy, triangles):
    p = xy[triangles]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


def _edges(triangles):
    """Each distinct edge (sorted node pair) and how many triangles have it."""
    pairs = np.sort(triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    return np.unique(pairs, axis=0, return_counts=True)


def _kept(before: Mesh, after: Mesh):
    """What the patch kept, measured: nodes and elements the same at their number.

    Returns the kept elements (bool per input element: the same nodes at its
    number, each where it was) and the kept nodes (bool per input node: in the
    output at its number with its coordinates, bit for bit, and used).
    """
    m, n = len(before.triangles), len(before.points)
    assert len(after.triangles) >= m and len(after.points) >= n
    xy_after = np.ascontiguousarray(after.points[:n]).view(np.uint64)
    xy_before = np.ascontiguousarray(before.points).view(np.uint64)
    nodes = (xy_after == xy_before).all(axis=1)
    nodes &= np.isin(np.arange(n), after.triangles)
    elements = (after.triangles[:m] == before.triangles).all(axis=1)
    # a new element in a slot cut out may have the numbers of the one it
    # replaces, its nodes being new ones in the slots cut out
    elements &= nodes[before.triangles].all(axis=1)
    return elements, nodes


def assert_outside_kept(before: Mesh, after: Mesh, removed=None):
    """Every node and element outside the hole is the input's, and so on."""
    elements, nodes = _kept(before, after)
    if removed is not None:
        # all the patch says it kept; and maybe an element it cut out and made
        # again, the same nodes in the same slot (a corner of the hole)
        assert elements[~removed].all()
        assert (elements & removed).sum() <= 2
    assert elements.mean() > 0.5  # the patch is a small part of the mesh
    used = np.unique(before.triangles[elements])
    assert _same_bits(after.points[used], before.points[used])  # bit for bit
    assert nodes[used].all()
    # every node kept (the kept elements', and the coast's in the hole): its depth
    depth_after = after.point_data["depth"][: len(before.points)]
    assert _same_bits(depth_after[nodes], before.point_data["depth"][nodes])
    np.testing.assert_array_equal(after.boundary_edges, before.boundary_edges)
    np.testing.assert_array_equal(after.boundary_ids, before.boundary_ids)
    assert after.boundary_names == before.boundary_names
    assert after.boundary_kinds == before.boundary_kinds
    assert after.surface_id == before.surface_id
    assert after.crs == before.crs
    assert nodes[np.unique(before.boundary_edges)].all()  # the boundary's nodes
    np.testing.assert_array_equal(
        after.regions[: len(before.triangles)][elements], before.regions[elements]
    )
    return elements, nodes


def assert_conforming(before: Mesh, after: Mesh):
    """The output is a conforming mesh of the same region, turning the same way."""
    pairs, counts = _edges(after.triangles)
    assert set(counts.tolist()) <= {1, 2}  # no edge in three triangles
    outline = {tuple(e) for e in pairs[counts == 1].tolist()}
    given = {tuple(e) for e in np.sort(before.boundary_edges, axis=1).tolist()}
    before_pairs, before_counts = _edges(before.triangles)
    assert {tuple(e) for e in before_pairs[before_counts == 1].tolist()} == given
    assert outline == given  # no hanging node, no gap: the boundary is the input's
    area_before = _doubled_areas(before.points, before.triangles)
    area_after = _doubled_areas(after.points, after.triangles)
    assert (area_before > 0).all()
    assert (area_after > 0).all()  # counter-clockwise, as the input's
    # all the same way round with the same boundary: the sum is the union's
    # area only if no two triangles overlap
    assert area_after.sum() == pytest.approx(area_before.sum(), rel=1e-11)
    assert np.isin(np.arange(len(after.points)), after.triangles).all()
    assert np.isfinite(after.point_data["depth"]).all()


# -- patch_mesh ----------------------------------------------------------------


def test_everything_outside_is_kept_exactly(existing, patched):
    elements, _ = assert_outside_kept(existing, patched.mesh, patched.hole.removed)
    # what went is what meets the polygon (and the widening round it)
    cells = shapely.polygons(
        reproject_points(existing.points, "EPSG:4326", patched.crs)[existing.triangles]
    )
    meets = shapely.intersects(cells, patched.polygon)
    assert meets.any()
    assert not (elements & meets).any()
    far = shapely.distance(cells, patched.polygon) > 2000.0
    assert elements[far].all()


def test_new_nodes_and_elements_take_the_numbers_cut_out_then_follow(existing, patched):
    before, after = existing, patched.mesh
    elements, nodes = _kept(before, after)
    m, n = len(before.triangles), len(before.points)
    # the nodes only replaced elements used, off the hole's edge (the nodes of
    # kept elements and of the mesh's boundary stay)
    cut_out = np.setdiff1d(
        np.unique(before.triangles[~elements]),
        np.union1d(before.triangles[elements], before.boundary_edges),
    )
    assert len(cut_out) > 0
    np.testing.assert_array_equal(np.flatnonzero(~nodes), cut_out)
    new_nodes = np.union1d(cut_out, np.arange(n, len(after.points)))
    assert len(after.points) - n > 0  # more nodes than cut out: they follow
    new_elements = np.union1d(
        np.flatnonzero(~elements), np.arange(m, len(after.triangles))
    )
    assert len(after.triangles) > m
    np.testing.assert_array_equal(patched.new_elements, new_elements)
    np.testing.assert_array_equal(np.sort(patched.hole.inner_nodes), cut_out)
    # the new nodes are only in new elements, and inside the hole
    in_kept = np.unique(after.triangles[:m][elements])
    assert not np.isin(new_nodes, in_kept).any()
    hole = shapely.union_all(
        shapely.polygons(before.points[before.triangles[~elements]])
    )
    inside = shapely.contains_xy(hole.buffer(1e-9), *after.points[new_nodes].T)
    assert inside.all()
    centroids = after.points[after.triangles[new_elements]].mean(axis=1)
    assert shapely.contains_xy(hole, *centroids.T).all()


def test_the_patched_mesh_is_conforming(existing, patched):
    assert_conforming(existing, patched.mesh)


def test_turbines_are_nodes_and_the_farm_has_its_id(existing, patched):
    after = patched.mesh
    xy = reproject_points(after.points, "EPSG:4326", UTM)
    turbines = reproject_points(np.array(TURBINES), "EPSG:4326", UTM)
    for t in turbines:
        assert np.hypot(*(xy - t).T).min() < 1e-3  # a node there, to a mm
    farm = shapely.Polygon(reproject_points(np.array(FARM), "EPSG:4326", UTM))
    centroids = xy[after.triangles].mean(axis=1)
    inside = shapely.contains_xy(farm.buffer(-1.0), *centroids.T)
    outside = ~shapely.contains_xy(farm.buffer(1.0), *centroids.T)
    assert inside.sum() > 100
    assert (after.regions[inside] == FARM_ID).all()
    assert (after.regions[outside] != FARM_ID).all()
    assert after.region_names[FARM_ID] == "array"
    new = np.zeros(len(after.triangles), dtype=bool)
    new[patched.new_elements] = True
    assert (after.regions[~new] == existing.surface_id).all()
    # the farm is finer than the mesh there; the turbines finer still
    sizes = np.hypot(*(xy[after.triangles[:, 1]] - xy[after.triangles[:, 0]]).T)
    assert np.median(sizes[inside]) < 90.0
    assert np.median(sizes[~new]) > 250.0


def test_the_seam_is_within_its_bounds_and_moved_out_where_it_is_not(
    existing, case_file, patched, monkeypatch
):
    import coastmesh.case.patch.patch as patch_module

    # as it is: every element at the seam over 30 degrees, ratios under 1.5
    assert patched.report.seam_moves == 0
    assert patched.report.angle_min_seam >= patch_module.SEAM_MIN_ANGLE
    assert patched.report.size_ratio_seam_max <= patch_module.SEAM_MAX_RATIO
    # bounds this patch breaks (43 degrees) move the seam out, once per try
    monkeypatch.setattr(patch_module, "SEAM_MIN_ANGLE", 43.0)
    monkeypatch.setattr(patch_module, "SEAM_MOVES", 0)
    first = _patch(existing, case_file)
    monkeypatch.setattr(patch_module, "SEAM_MOVES", 2)
    moved = _patch(existing, case_file)
    assert moved.report.seam_moves >= 1
    grown = moved.hole.removed & ~first.hole.removed
    assert grown.any() and (first.hole.removed <= moved.hole.removed).all()
    assert moved.report.widened_elements == first.report.widened_elements + int(
        grown.sum()
    )
    assert_outside_kept(existing, moved.mesh, moved.hole.removed)
    assert_conforming(existing, moved.mesh)
    # the best try is kept: no worse at the seam than the first
    assert moved.report.angle_p01_seam >= first.report.angle_p01_seam
    assert f"moved out {moved.report.seam_moves} time" in moved.report.summary()


def test_the_report_counts_what_changed(existing, patched):
    before, after, report = existing, patched.mesh, patched.report
    elements, nodes = _kept(before, after)
    assert report.kept_elements == elements.sum()
    assert report.removed_elements == (~elements).sum()
    assert report.added_elements == len(after.triangles) - elements.sum()
    assert report.kept_nodes == nodes.sum()
    assert report.removed_nodes == (~nodes).sum()
    assert report.added_nodes == len(after.points) - nodes.sum()
    # seam: the edges one kept and one new element share
    m = len(before.triangles)
    kept_edges = {tuple(e) for e in _edges(after.triangles[:m][elements])[0].tolist()}
    new_edges = {
        tuple(e) for e in _edges(after.triangles[patched.new_elements])[0].tolist()
    }
    seam = kept_edges & new_edges
    assert report.seam_edges == len(seam) > 10
    assert 0 < report.angle_min_patch <= report.angle_p01_patch <= 60
    assert 0 < report.angle_min_seam <= report.angle_p01_seam <= 60
    assert 1 <= report.size_ratio_seam_p99 <= report.size_ratio_seam_max < 3
    assert report.size_new_m < report.size_removed_m
    assert 0 < report.dt_patch_s < report.dt_input_s
    assert report.dt_output_s == report.dt_patch_s
    assert (
        f"-{report.removed_elements:,} +{report.added_elements:,}" in report.summary()
    )


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3", "mesh.slf", "mesh.nc"])
def test_written_and_read_back_in_each_model_format(patched, tmp_path, name):
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        coastmesh.write_mesh(path, patched.mesh)
    back = coastmesh.read_mesh(path)
    np.testing.assert_array_equal(back.triangles, patched.mesh.triangles)
    atol = 1e-5 if name.endswith(".slf") else 1e-9  # SELAFIN: float32
    np.testing.assert_allclose(back.points, patched.mesh.points, rtol=0, atol=atol)
    np.testing.assert_allclose(
        back.point_data["depth"], patched.mesh.point_data["depth"], atol=1e-3
    )
    assert {tuple(e) for e in np.sort(back.boundary_edges, axis=1).tolist()} == {
        tuple(e) for e in np.sort(patched.mesh.boundary_edges, axis=1).tolist()
    }
    if name == "fort.14":
        assert check_adcirc(path) == []
    elif name == "hgrid.gr3":
        assert check_schism(path) == []
    elif name == "mesh.slf":
        assert check_telemac(path, tmp_path / "mesh.cli") == []


@pytest.mark.parametrize("name", ["fort.14", "hgrid.gr3", "mesh.slf"])
def test_an_input_read_from_a_model_file_gives_the_same_patch(
    existing, patched, case_file, tmp_path, name
):
    coastmesh.write_mesh(tmp_path / name, existing)
    source = coastmesh.read_mesh(tmp_path / name)
    again = _patch(source, case_file)
    np.testing.assert_array_equal(again.hole.removed, patched.hole.removed)
    assert again.report.seam_edges == patched.report.seam_edges
    assert_outside_kept(source, again.mesh, again.hole.removed)
    assert_conforming(source, again.mesh)


def test_a_polygon_file_in_another_crs(existing, case_file, tmp_path, make_gpkg):
    """A GeoPackage in web Mercator cuts what the same box in lon/lat cuts."""
    coastmesh.write_mesh(tmp_path / "fort.14", existing)
    to_3857 = Transformer.from_crs("EPSG:4326", "EPSG:3857", always_xy=True)
    x0, y0 = to_3857.transform(*AROUND[:2])
    x1, y1 = to_3857.transform(*AROUND[2:])
    make_gpkg(tmp_path / "site.gpkg", [shapely.box(x0, y0, x1, y1)], crs="EPSG:3857")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        run = patch_files(
            tmp_path / "fort.14",
            case_file,
            tmp_path / "out",
            polygon=tmp_path / "site.gpkg",
        )
    out = coastmesh.read_mesh(tmp_path / "out" / "fort.14")
    source = coastmesh.read_mesh(tmp_path / "fort.14")
    lonlat = _patch(source, case_file, polygon=shapely.box(*AROUND))
    np.testing.assert_array_equal(out.triangles, lonlat.mesh.triangles)
    np.testing.assert_allclose(out.points, lonlat.mesh.points, rtol=0, atol=1e-9)
    assert run.patch.removed_elements == lonlat.report.removed_elements
    elements, _ = assert_outside_kept(source, out, lonlat.hole.removed)
    # what went is what the box meets, and the widening round it
    cells = shapely.polygons(source.points[source.triangles])
    assert not (elements & shapely.intersects(cells, shapely.box(*AROUND))).any()
    assert_conforming(source, out)


def test_a_polygon_across_the_coast_keeps_the_coast(existing, case_file, tmp_path):
    across = _patch(
        existing, case_file, polygon=shapely.box(*TO_THE_COAST), polygon_crs=UTM
    )
    after = across.mesh
    assert_outside_kept(existing, after, across.hole.removed)
    assert_conforming(existing, after)
    # the coast's edges in the hole: still boundary edges with their id, now
    # edges of the patch's elements
    xy = reproject_points(existing.points, "EPSG:4326", UTM)
    coast = existing.boundary_edges[existing.boundary_ids == 1]
    inside = shapely.contains_xy(shapely.box(*TO_THE_COAST), *xy[coast].mean(axis=1).T)
    assert inside.sum() >= 5
    new_edges = {
        tuple(e) for e in _edges(after.triangles[across.new_elements])[0].tolist()
    }
    for a, b in coast[inside]:
        assert (min(a, b), max(a, b)) in new_edges
    assert not all(s.all() for s in across.hole.seam)  # the ring has coast edges
    assert check_adcirc(_written(after, tmp_path / "fort.14")) == []
    assert check_schism(_written(after, tmp_path / "hgrid.gr3")) == []


def _written(mesh, path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        coastmesh.write_mesh(path, mesh)
    return path


def test_sizes_coarser_than_the_mesh_warn(existing, no_site_file):
    """A big box, a case of coarse sizes: fewer nodes than cut out. The nodes
    after the gaps move down (in order); the report's seam is the output's."""
    big = shapely.box(486_000, 6_499_000, 498_000, 6_506_000)
    with (
        pytest.warns(CoastmeshWarning, match="coarser than those they replace"),
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", CoarseRasterWarning)  # ETOPO1 is coarse
        coarse = patch_mesh(
            existing, read_case(no_site_file), polygon=big, polygon_crs=UTM
        )
    before, after, report = existing, coarse.mesh, coarse.report
    assert report.added_nodes < report.removed_nodes
    assert report.added_elements < report.removed_elements
    assert (
        len(after.points)
        == len(before.points) - report.removed_nodes + report.added_nodes
    )
    # the kept nodes: all there, bit for bit, in their order
    at = {p.tobytes(): i for i, p in enumerate(after.points)}
    kept = ~coarse.hole.removed
    used = np.union1d(before.triangles[kept], before.boundary_edges)
    numbers = np.array([at[before.points[k].tobytes()] for k in used])
    assert (np.diff(numbers) > 0).all()
    assert (numbers <= used).all()
    assert _same_bits(
        after.point_data["depth"][numbers], before.point_data["depth"][used]
    )
    old_to_new = np.full(len(before.points), -1)
    old_to_new[used] = numbers
    remapped = old_to_new[before.triangles[kept]]
    new = np.zeros(len(after.triangles), dtype=bool)
    new[coarse.new_elements] = True
    np.testing.assert_array_equal(after.triangles[~new], remapped)
    np.testing.assert_array_equal(
        after.boundary_edges, old_to_new[before.boundary_edges]
    )
    # conforming, the same area
    pairs, counts = _edges(after.triangles)
    assert set(counts.tolist()) <= {1, 2}
    assert {tuple(e) for e in pairs[counts == 1].tolist()} == {
        tuple(e) for e in np.sort(after.boundary_edges, axis=1).tolist()
    }
    areas = _doubled_areas(after.points, after.triangles)
    assert (areas > 0).all()
    assert areas.sum() == pytest.approx(
        _doubled_areas(before.points, before.triangles).sum(), rel=1e-11
    )
    kept_edges = {tuple(e) for e in _edges(after.triangles[~new])[0].tolist()}
    new_edges = {tuple(e) for e in _edges(after.triangles[new])[0].tolist()}
    assert report.seam_edges == len(kept_edges & new_edges)


def test_a_case_without_a_site_needs_a_polygon(existing, no_site_file):
    with pytest.raises(InputDataError, match=r"no \[\[farms\]\].*\(--polygon\)"):
        patch_mesh(existing, read_case(no_site_file), name="the mesh")


def test_a_polygon_off_the_mesh_is_refused(existing, case_file):
    with pytest.raises(
        InputDataError, match="the mesh: the patch polygon meets no element"
    ):
        patch_mesh(
            existing, read_case(case_file), polygon=shapely.box(-5, 50, -4.9, 50.1),
            name="the mesh",
        )  # fmt: skip


def test_inverted_elements_are_refused(existing, case_file):
    triangles = existing.triangles.copy()
    triangles[11] = triangles[11, [0, 2, 1]]
    broken = Mesh(
        existing.points, triangles, existing.boundary_edges, existing.boundary_ids,
        existing.surface_id, existing.crs,
    )  # fmt: skip
    with pytest.raises(InputDataError, match=r"fort\.14: element 12 .* is inverted"):
        patch_mesh(broken, read_case(case_file), name="fort.14")


# -- coastmesh patch -------------------------------------------------------------


@pytest.fixture(scope="module")
def mesh_file(existing, tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("mesh") / "fort.14"
    coastmesh.write_mesh(path, existing)
    return path


def test_the_command_writes_the_folder(
    mesh_file, case_file, patched, tmp_path, run_cli
):
    out = tmp_path / "patched"
    result = run_cli("patch", mesh_file, case_file, "-o", out, "--format", "gr3")
    assert result.exit_code == 0, result.output
    assert "patch: -" in result.output
    names = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert {"fort.14", "fort_patched.gr3", "report.json", "summary.txt",
            "figures/patch.png"} <= names  # fmt: skip
    assert (out / "figures" / "patch.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    source = coastmesh.read_mesh(mesh_file)
    written = coastmesh.read_mesh(out / "fort.14")
    assert_outside_kept(source, written)
    assert_conforming(source, written)
    assert len(written.triangles) == len(patched.mesh.triangles)
    report = json.loads((out / "report.json").read_text())
    for key in ("kept_nodes", "kept_elements", "removed_nodes", "removed_elements",
                "added_nodes", "added_elements", "seam_edges"):  # fmt: skip
        assert report[key] == getattr(patched.report, key), key
    assert "patch: -" in (out / "summary.txt").read_text()
    assert check_adcirc(out / "fort.14") == []
    assert check_schism(out / "fort_patched.gr3") == []
    # an output that exists is kept, unless --overwrite
    before = sorted(p.name for p in out.iterdir())
    again = run_cli("patch", mesh_file, case_file, "-o", out)
    assert again.exit_code != 0
    assert "--overwrite" in again.output or "exists" in again.output, again.output
    assert "Traceback" not in again.output
    assert sorted(p.name for p in out.iterdir()) == before
    assert (out / "fort_patched.gr3").exists()
    again = run_cli("patch", mesh_file, case_file, "-o", out, "--overwrite")
    assert again.exit_code == 0, again.output
    assert not (out / "fort_patched.gr3").exists()


def test_the_command_takes_a_polygon_file(
    mesh_file, case_file, tmp_path, run_cli, make_gpkg
):
    make_gpkg(tmp_path / "box.gpkg", [shapely.box(*TO_THE_COAST)], crs=UTM)
    out = tmp_path / "patched"
    result = run_cli(
        "patch", mesh_file, case_file, "-o", out, "--polygon", tmp_path / "box.gpkg"
    )
    assert result.exit_code == 0, result.output
    source = coastmesh.read_mesh(mesh_file)
    written = coastmesh.read_mesh(out / "fort.14")
    assert_outside_kept(source, written)
    assert_conforming(source, written)


def _no_output(folder: Path, out: Path) -> None:
    assert not out.exists()
    assert not [p for p in folder.iterdir() if p.name.startswith(out.name)]


def test_the_command_refuses_a_missing_mesh(case_file, tmp_path, run_cli):
    out = tmp_path / "patched"
    result = run_cli("patch", tmp_path / "nothing.14", case_file, "-o", out)
    assert_clean_failure(result, "nothing.14")
    _no_output(tmp_path, out)


def test_the_command_refuses_a_case_without_a_site(
    mesh_file, no_site_file, tmp_path, run_cli
):
    out = tmp_path / "patched"
    result = run_cli("patch", mesh_file, no_site_file, "-o", out)
    assert_clean_failure(result, str(mesh_file), "[[farms]]", "--polygon")
    _no_output(tmp_path, out)


def test_the_command_refuses_a_polygon_off_the_mesh(
    mesh_file, case_file, tmp_path, run_cli, make_gpkg
):
    make_gpkg(tmp_path / "far.gpkg", [shapely.box(-5, 50, -4.9, 50.1)])
    out = tmp_path / "patched"
    result = run_cli(
        "patch", mesh_file, case_file, "-o", out, "--polygon", tmp_path / "far.gpkg"
    )
    assert_clean_failure(result, str(mesh_file), "meets no element")
    _no_output(tmp_path, out)


def test_the_command_refuses_a_polygon_cutting_two_holes(
    mesh_file, case_file, tmp_path, run_cli, make_gpkg
):
    """Two boxes apart (here: each side of the island)."""
    two = [shapely.box(487_000, 6_504_900, 487_400, 6_505_100),
           shapely.box(488_700, 6_504_900, 489_100, 6_505_100)]  # fmt: skip
    make_gpkg(tmp_path / "two.gpkg", two, crs=UTM)
    out = tmp_path / "patched"
    result = run_cli(
        "patch", mesh_file, case_file, "-o", out, "--polygon", tmp_path / "two.gpkg"
    )
    assert_clean_failure(result, "cuts 2 separate holes")
    _no_output(tmp_path, out)


def _field_case(no_site_file, tmp_path, extra=""):
    """The coarse case with a [[mesh_size.fields]] entry: 100 m over the box."""
    import rasterio
    from rasterio.transform import from_bounds

    tif = tmp_path / "one.tif"
    with rasterio.open(
        tif, "w", driver="GTiff", height=40, width=60, count=1, dtype="float32",
        crs="EPSG:4326", transform=from_bounds(-3.35, 58.58, -2.95, 58.75, 60, 40),
    ) as out:  # fmt: skip
        out.write(np.ones((1, 40, 60), dtype="float32"))
    case = tmp_path / "field.toml"
    case.write_text(
        no_site_file.read_text()
        + f'\n[[mesh_size.fields]]\nsource = "{tif.as_posix()}"\n'
        + 'values = [0.5]\nsizes = ["100 m"]\n'
        + extra
    )
    return read_case(case)


#: a disc of 3.5 km in the middle of the box, clear of the coast and island
DISC = shapely.Point(492_000, 6_503_000).buffer(3_500)


def test_a_field_s_sizes_hold_in_the_patch_and_nothing_outside_moves(
    existing, no_site_file, tmp_path
):
    """Measured from the meshes: every new element more than 1 km inside the
    seam (whose sizes, 300 m and up, grade down to the field's 100 m within
    400 m at rate 0.6) is within 10 % of 100 m; outside nothing changed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        config = _field_case(no_site_file, tmp_path)
        result = patch_mesh(existing, config, polygon=DISC, polygon_crs=UTM)
    after = result.mesh
    assert_outside_kept(existing, after, result.hole.removed)
    assert_conforming(existing, after)
    xy = reproject_points(after.points, "EPSG:4326", UTM)
    p = xy[after.triangles[result.new_elements]]
    mean_edge = np.mean(
        [np.hypot(*(p[:, (i + 1) % 3] - p[:, i]).T) for i in range(3)], axis=0
    )
    inside = shapely.Point(492_000, 6_503_000).buffer(2_500)
    deep = shapely.contains_xy(inside, *p.reshape(-1, 2).T).reshape(-1, 3).all(axis=1)
    assert deep.sum() > 3000
    assert np.abs(mean_edge[deep] / 100.0 - 1).max() <= 0.10


@pytest.mark.parametrize("enabled", [True, False])
def test_a_patch_holds_a_field_s_sizes_where_it_sets_them(
    existing, no_site_file, tmp_path, monkeypatch, enabled
):
    """The hole's mesh goes through conform_sizes with the field's zone (the
    nodes at its 100 m), unless the cleanup is off."""
    from coastmesh.meshing.cleanup import conform

    calls = []
    real = conform.conform_sizes

    def spy(mesh, zone, **options):
        calls.append((mesh, np.asarray(zone)))
        return real(mesh, zone, **options)

    monkeypatch.setattr(conform, "conform_sizes", spy)
    extra = "" if enabled else "\n[cleanup]\nenabled = false\n"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        config = _field_case(no_site_file, tmp_path, extra)
        patch_mesh(existing, config, polygon=DISC, polygon_crs=UTM)
    if not enabled:
        assert not calls
        return
    assert calls  # once for each hole tried (the seam moves out past faults)
    mesh, zone = calls[-1]
    assert zone.sum() > 1000
    # the field's own size there (not the seam's grading), with UTM's scale
    np.testing.assert_allclose(mesh.point_data["size"][zone], 100.0, rtol=1e-3)
