"""Smoke-test run folders for ADCIRC and SCHISM (coastmesh.io.meshes.model_tests).

The files are parsed here line by line, as each model reads them: fort.15's
forcing must list one amplitude and phase per open-boundary node of the fort.14
(``NETA``), bctides.in one block per open segment of the hgrid.gr3 with its node
count, and every file the models need must be there.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from io_meshes import cell_mesh
from model_rules import check_adcirc, check_schism, parse_grid

from coastmesh.errors import ConfigError, OutputExistsError
from coastmesh.io import write_model_test
from coastmesh.io.meshes.model_tests import M2_PERIOD, ModelTest
from coastmesh.types import Mesh


def ids(p, q):
    """South side open (2), east side open (5), the rest coast (1); a rock (3)."""
    if p[1] == q[1] == 0:
        return 2
    if p[0] == q[0] == 4:
        return 5
    if p[0] == q[0] == 0 or p[1] == q[1] == 4:
        return 1
    return 3


KINDS = {1: "shoreline", 2: "open", 3: "shoreline", 5: "open"}


@pytest.fixture(scope="module")
def mesh():
    """4 x 4 cells of 1 km (UTM 30N), a rock, open south and east sides, a farm."""
    m = cell_mesh(4, {(1, 1)}, ids, KINDS, names={1: "coast", 2: "south", 3: "rock",
                                                  5: "east"})  # fmt: skip
    points = m.points * 1000.0 + [500000.0, 6500000.0]
    regions = np.where(np.arange(len(m.triangles)) < 4, 20, 1)
    return Mesh(
        points, m.triangles, m.boundary_edges, m.boundary_ids, 1, "EPSG:32630",
        {"depth": 10.0 + m.points[:, 0]}, m.boundary_names, m.boundary_kinds,
        regions=regions,
    )  # fmt: skip


def _values(path):
    """``value ! comment`` lines of a fort.15, by comment's first word."""
    out = {}
    for line in path.read_text().splitlines():
        if " ! " in line:
            value, what = line.split(" ! ", 1)
            out.setdefault(what.split()[0].rstrip(":"), value.split())
    return out


def _fort13(path, n):
    """A fort.13 as ADCIRC reads it: {name: (default, {node: value})}."""
    lines = path.read_text().splitlines()
    assert int(lines[1]) == n
    count = int(lines[2])
    names, defaults, at = [], {}, 3
    for _ in range(count):
        name = lines[at]
        names.append(name)
        defaults[name] = float(lines[at + 3])
        at += 4
    out = {}
    for _ in range(count):
        name, k = lines[at], int(lines[at + 1])
        rows = [line.split() for line in lines[at + 2 : at + 2 + k]]
        out[name] = (defaults[name], {int(a): float(b) for a, b in rows})
        at += 2 + k
    assert at == len(lines) and set(out) == set(names)
    return out


def test_adcirc_folder_has_what_adcirc_reads(tmp_path, mesh):
    folder = tmp_path / "adcirc"
    files = write_model_test(folder, mesh, "adcirc", dt=2.5,
                             region_manning={20: 0.04})  # fmt: skip
    assert files == ["fort.14", "fort.13", "fort.15", "README.txt"]
    assert sorted(p.name for p in folder.iterdir()) == sorted(files)
    assert check_adcirc(folder / "fort.14") == []
    grid = parse_grid(folder / "fort.14")
    neta = sum(len(n) for n, _, _ in grid.open)
    lines = (folder / "fort.15").read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("M2 ! EALPHA"))
    forcing = lines[at + 1 : at + 1 + neta]
    assert forcing == ["0.5 0.0"] * neta
    assert lines[at + 1 + neta].endswith("! ANGINN")
    values = _values(folder / "fort.15")
    assert values["DTDP"] == ["2.5"]
    assert values["ICS"] == ["1"] and values["NCOR"] == ["0"]  # projected
    assert float(values["RNDAY"][0]) * 86400 == pytest.approx(6 * 3600 + M2_PERIOD)
    assert float(values["DRAMP"][0]) == pytest.approx(0.25)
    lat = 58.64  # 6500 km north in UTM 30N
    cori = float(values["CORI"][0])
    assert cori == pytest.approx(
        2 * 7.292115e-5 * math.sin(math.radians(lat)), rel=1e-2
    )
    # fort.13: Manning's n (0.04 at the farm's nodes) and advection_state (off
    # within two rings of nodes of the open boundary: nodes on the south and
    # east sides, and the two columns and rows inside them)
    assert values["NWP"] == ["2"]
    attrs = _fort13(folder / "fort.13", len(mesh.points))
    default, listed = attrs["mannings_n_at_sea_floor"]
    farm = np.unique(mesh.triangles[mesh.regions == 20]) + 1
    assert default == 0.025 and listed == dict.fromkeys(farm.tolist(), 0.04)
    default, listed = attrs["advection_state"]
    xy = mesh.points - mesh.points.min(axis=0)
    near = np.flatnonzero((xy[:, 1] <= 2000.0) | (xy[:, 0] >= 2000.0)) + 1
    assert default == -999.0 and listed == dict.fromkeys(near.tolist(), 10000.0)
    assert "NOT a calibrated model" in (folder / "README.txt").read_text()


def test_schism_folder_has_what_schism_reads(tmp_path, mesh):
    folder = tmp_path / "schism"
    write_model_test(folder, mesh, "schism", dt=2.5)
    assert (folder / "outputs").is_dir()
    assert check_schism(folder / "hgrid.gr3") == []
    grid = parse_grid(folder / "hgrid.gr3")
    lines = (folder / "bctides.in").read_text().splitlines()
    assert lines[1].split()[0] == "0" and lines[2].split()[0] == "1"  # ntip, nbfr
    nope = int(lines[5].split()[0])
    assert nope == len(grid.open) == 2  # south and east: one segment each
    at = 6
    for nodes, _, _ in grid.open:
        head = lines[at].split()
        assert [int(v) for v in head[:5]] == [len(nodes), 3, 0, 0, 0]
        assert lines[at + 1] == "M2"
        assert lines[at + 2 : at + 2 + len(nodes)] == ["0.5 0.0"] * len(nodes)
        at += 2 + len(nodes)
    assert at == len(lines)
    # hgrid.ll: the same grid in lon/lat
    ll = parse_grid(folder / "hgrid.ll")
    np.testing.assert_array_equal(ll.elements, grid.elements)
    assert (abs(ll.xy[:, 0] + 3.0) < 0.2).all() and (
        abs(ll.xy[:, 1] - 58.6) < 0.2
    ).all()
    param = (folder / "param.nml").read_text()
    # SCHISM's own step (the mesh's explicit 2.5 s is ADCIRC's), its stabilizer
    # and advection rules
    step = _schism_step_loop(mesh)
    assert step == 100.0  # CFL > 0.4 everywhere from 37 s: the range's lowest
    for setting in (f"dt = {step:g}\n", "ics = 1", "ncor = 1", "nchi = -1",
                    "ibc = 1", "iof_hydro(25) = 0", "dramp = 0.25", "nadv = 0",
                    "ishapiro = 1", "shapiro0 = 0.5", "ihorcon = 0"):  # fmt: skip
        assert setting in param
    readme = (folder / "README.txt").read_text()
    assert f"It runs at SCHISM's own step, {step:g} s, not the mesh's" in readme
    # advection off within two rings of nodes of the open sides, on elsewhere
    xy = mesh.points - mesh.points.min(axis=0)
    near = (xy[:, 1] <= 2000.0) | (xy[:, 0] >= 2000.0)
    np.testing.assert_array_equal(_node_values(folder / "adv.gr3", mesh), ~near)
    manning = (folder / "manning.gr3").read_text().splitlines()
    assert manning[1].split() == [str(len(mesh.triangles)), str(len(mesh.points))]
    values = {float(line.split()[3]) for line in manning[2 : 2 + len(mesh.points)]}
    assert values == {0.025}
    assert (folder / "vgrid.in").read_text().splitlines()[1].split()[0] == "2"


def test_both_models_get_the_same_friction_floor(tmp_path, mesh):
    """ADCIRC's CF is its floor on g n^2 / H^(1/3) (src/nodalattr.F); SCHISM
    has none, so its manning.gr3 carries the n that meets that floor."""
    # land, shallows (the floor does not bite) and deep sea (it does)
    depth = np.resize([-2.0, 5.0, 14.0, 16.0, 60.0, 400.0], len(mesh.points))
    deep = Mesh(
        mesh.points, mesh.triangles, mesh.boundary_edges, mesh.boundary_ids, 1,
        mesh.crs, {"depth": depth}, mesh.boundary_names, mesh.boundary_kinds,
        regions=mesh.regions,
    )  # fmt: skip
    write_model_test(tmp_path / "a", deep, "adcirc", dt=2.5, region_manning={20: 0.04})
    write_model_test(tmp_path / "s", deep, "schism", dt=2.5, region_manning={20: 0.04})
    assert _values(tmp_path / "a" / "fort.15")["CF"] == ["0.0025"]
    farm = set(mesh.triangles[mesh.regions == 20].ravel().tolist())
    got = _node_values(tmp_path / "s" / "manning.gr3", mesh)
    for k, still in enumerate(depth):  # the floor, node by node
        n = 0.04 if k in farm else 0.025
        h = max(still, 1.0)  # SCHISM's hmin_man
        drag = max(9.81 * n * n / h ** (1 / 3), 0.0025)
        assert got[k] == pytest.approx(math.sqrt(drag * h ** (1 / 3) / 9.81), abs=1e-7)
    sea = np.array([k not in farm for k in range(len(depth))])
    assert set(got[sea & (depth < 15)]) == {0.025}  # not raised in the shallows
    assert (got[sea & (depth > 15)] > 0.025).all()  # raised in deeper water


def test_schism_at_a_step_given_turns_advection_off_below_its_cfl(tmp_path, mesh):
    write_model_test(tmp_path / "s", mesh, "schism", dt=2.5, schism_dt=20.0)
    assert "  dt = 20\n" in (tmp_path / "s" / "param.nml").read_text()
    # every element needs 36 s or more for CFL > 0.4: advection off everywhere
    assert (_node_values(tmp_path / "s" / "adv.gr3", mesh) == 0).all()
    readme = (tmp_path / "s" / "README.txt").read_text()
    assert "It runs at the step given, 20 s. Momentum advection is off" in readme
    assert f"at that step ({len(mesh.triangles)} elements)" in readme


def _schism_step_loop(mesh):
    """SCHISM's step, one element at a time (the module's rule, written out).

    The least ``dt`` with ``(1 + sqrt(g h)) dt / dx > 0.4`` on 95 % of the
    wet elements (h the deepest node, over 0.1 m; dx the mean side), rounded
    up to a second, within 100 .. 400 s.
    """
    need = []
    for tri in mesh.triangles:
        p = mesh.points[tri]
        dx = sum(math.dist(p[k], p[(k + 1) % 3]) for k in range(3)) / 3
        h = max(mesh.point_data["depth"][k] for k in tri)
        if h > 0.1:
            need.append(0.4 * dx / (math.sqrt(9.81 * h) + 1.0))
    return float(min(max(math.ceil(np.percentile(need, 95)), 100.0), 400.0))


def _node_values(path, mesh):
    """The value column of a node ``.gr3`` (manning.gr3, adv.gr3)."""
    lines = path.read_text().splitlines()[2 : 2 + len(mesh.points)]
    return np.array([float(line.split()[3]) for line in lines])


def test_a_geographic_mesh_runs_in_lonlat(tmp_path, mesh):
    from pyproj import Transformer

    to = Transformer.from_crs("EPSG:32630", "EPSG:4326", always_xy=True)
    lonlat = np.column_stack(to.transform(*mesh.points.T))
    m = Mesh(lonlat, mesh.triangles, mesh.boundary_edges, mesh.boundary_ids, 1,
             "EPSG:4326", mesh.point_data, mesh.boundary_names,
             mesh.boundary_kinds)  # fmt: skip
    write_model_test(tmp_path / "a", m, "adcirc", dt=3.0)
    values = _values(tmp_path / "a" / "fort.15")
    assert values["ICS"] == ["2"] and values["NCOR"] == ["1"]
    lon, _ = (float(v) for v in values["SLAM0"])
    assert lon == pytest.approx(lonlat[:, 0].min() / 2 + lonlat[:, 0].max() / 2)
    write_model_test(tmp_path / "s", m, "schism", dt=3.0)
    assert "ics = 2" in (tmp_path / "s" / "param.nml").read_text()


@pytest.mark.parametrize("model", ["adcirc", "schism"])
def test_what_a_smoke_test_cannot_describe_is_refused(tmp_path, mesh, model):
    land = Mesh(mesh.points, mesh.triangles, mesh.boundary_edges,
                np.ones(len(mesh.boundary_ids), int), 1, "EPSG:32630",
                mesh.point_data, boundary_kinds={1: "shoreline"})  # fmt: skip
    with pytest.raises(ConfigError, match="no open boundary"):
        write_model_test(tmp_path / "x", land, model, dt=1.0)
    bare = Mesh(mesh.points, mesh.triangles, mesh.boundary_edges, mesh.boundary_ids, 1,
                None, mesh.point_data, boundary_kinds=mesh.boundary_kinds)  # fmt: skip
    with pytest.raises(ConfigError, match="no CRS"):
        write_model_test(tmp_path / "x", bare, model, dt=1.0)
    with pytest.raises(ConfigError, match="dt = -1"):
        write_model_test(tmp_path / "x", mesh, model, dt=-1)
    with pytest.raises(ConfigError, match="unknown model"):
        write_model_test(tmp_path / "x", mesh, "fvcom", dt=1.0)
    assert not (tmp_path / "x").exists()


def test_a_global_mesh_is_refused_with_why(tmp_path):
    # a band round the equator: triangles across the antimeridian
    lon = np.arange(-180, 180, 30.0)
    pts = np.array([(x, y) for y in (-10.0, 10.0) for x in lon])
    k = len(lon)
    tri = []
    for i in range(k):
        a, b, c, d = i, (i + 1) % k, k + (i + 1) % k, k + i
        tri += [[a, b, c], [a, c, d]]
    edges = [[i, (i + 1) % k] for i in range(k)] + [
        [k + (i + 1) % k, k + i] for i in range(k)
    ]
    m = Mesh(pts, tri, edges, [2] * k + [1] * k, 1, "EPSG:4326",
             {"depth": np.full(2 * k, 4000.0)},
             boundary_kinds={1: "shoreline", 2: "open"})  # fmt: skip
    with pytest.raises(ConfigError, match="on the sphere"):
        write_model_test(tmp_path / "g", m, "adcirc", dt=60.0)


def test_an_existing_folder_is_kept_unless_overwrite(tmp_path, mesh):
    folder = tmp_path / "adcirc"
    folder.mkdir()
    (folder / "mine.txt").write_text("keep")
    with pytest.raises(OutputExistsError):
        write_model_test(folder, mesh, "adcirc", dt=1.0)
    assert [p.name for p in folder.iterdir()] == ["mine.txt"]
    write_model_test(folder, mesh, "adcirc", dt=1.0, overwrite=True)
    assert not (folder / "mine.txt").exists()


def test_model_test_values_are_checked():
    with pytest.raises(ConfigError, match="amplitude"):
        ModelTest(1.0, amplitude=0)
    with pytest.raises(ConfigError, match="region_manning"):
        ModelTest(1.0, region_manning={20: -1})
    with pytest.raises(ConfigError, match=r"schism_dt = -5; expected a number > 0"):
        ModelTest(1.0, schism_dt=-5)
    assert ModelTest(2.0).duration == pytest.approx(21600 + M2_PERIOD)
