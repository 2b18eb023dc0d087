"""Every model format the example case writes, read back by an independent reader.

The issue's 'done' check: the same node and element counts in every format, the
same boundary ids where the format can hold them, and the same depths.
"""

from __future__ import annotations

import numpy as np
import pytest

from coastmesh.io.meshes.msh import read_msh

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def reference(example_run):
    result, out = example_run
    mesh = read_msh(out / "pentland_firth.msh", crs="EPSG:4326")
    return result, out, mesh


def test_msh_by_meshio(reference):
    import meshio

    result, out, _ = reference
    m = meshio.read(out / "pentland_firth.msh")
    assert len(m.points) == result.nodes
    assert len(m.get_cells_type("triangle")) == result.triangles
    ids = np.concatenate(
        [
            d
            for c, d in zip(m.cells, m.cell_data["gmsh:physical"], strict=True)
            if c.type == "line"
        ]
    )
    assert set(ids.tolist()) == {2, 3, 4, 5, 10, 11, 12}


def test_vtu_by_meshio(reference):
    import meshio

    result, out, mesh = reference
    m = meshio.read(out / "pentland_firth.vtu")
    assert len(m.points) == result.nodes
    assert len(m.get_cells_type("triangle")) == result.triangles
    np.testing.assert_allclose(m.points[:, :2], mesh.points)
    lines = [k for k, c in enumerate(m.cells) if c.type == "line"]
    ids = np.concatenate([m.cell_data["boundary_id"][k] for k in lines])
    assert sorted(ids.tolist()) == sorted(mesh.boundary_ids.tolist())
    assert np.all(m.point_data["depth"] >= 5.0)  # min_depth in the case


def test_ugrid_by_xugrid(reference):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import xugrid

    result, out, _ = reference
    ds = xugrid.open_dataset(out / "pentland_firth.nc")
    grid = ds.ugrid.grid
    assert grid.n_node == result.nodes and grid.n_face == result.triangles
    ids = ds["boundary_id"].values
    assert set(ids[ids > 0].tolist()) == {2, 3, 4, 5, 10, 11, 12}
    depth = ds["depth"].values
    assert depth.min() >= 5.0


def test_selafin_by_xarray_selafin(reference):
    import xarray as xr

    result, out, _ = reference
    ds = xr.open_dataset(out / "pentland_firth.slf", engine="selafin")
    assert ds.sizes["node"] == result.nodes
    assert ds.attrs["ikle2"].shape == (result.triangles, 3)
    bottom = ds["B"].values.ravel()
    assert bottom.max() <= -5.0 + 1e-4  # BOTTOM is elevation: -depth
    lines = (out / "pentland_firth.cli").read_text().splitlines()
    boundary_nodes = {int(line.split()[11]) for line in lines}
    mesh = read_msh(out / "pentland_firth.msh")
    assert len(boundary_nodes) == len(np.unique(mesh.boundary_edges)) == len(lines)


def test_mike_by_mikeio(reference):
    import mikeio

    result, out, _ = reference
    geometry = mikeio.Mesh(out / "pentland_firth.mesh").geometry
    assert geometry.n_nodes == result.nodes and geometry.n_elements == result.triangles
    codes = np.asarray(geometry.codes)
    # 0 inside, 1 on land, 2.. one code per open boundary (ids 2, 3, 4, 5)
    assert set(codes.tolist()) == {0, 1, 2, 3, 4, 5}
    assert np.asarray(geometry.node_coordinates)[:, 2].max() <= -5.0 + 1e-9


def test_fort14_and_gr3_against_the_format_description(reference):
    from coastmesh.io.meshes.adcirc import read_fort14
    from coastmesh.types.topology import boundary_strings

    result, out, mesh = reference
    strings = boundary_strings(mesh)
    open_strings = [s for s in strings if mesh.boundary_kinds[s.physical_id] == "open"]
    # west, north, east, and south, which the mainland cuts in two
    assert len(open_strings) == 5
    want = {tuple((s.nodes + 1).tolist()) for s in open_strings}
    for suffix in ("14", "gr3"):
        grid = read_fort14(out / f"pentland_firth.{suffix}")
        assert grid["np"] == result.nodes and grid["ne"] == result.triangles
        written = [tuple(b["nodes"].tolist()) for b in grid["open_boundaries"]]
        if suffix == "gr3":  # SCHISM: one segment per open boundary
            assert set(written) == want
        else:  # ADCIRC: the open boundaries that meet are one segment, each node once
            assert len(written) == 2
            joined = [n for w in written for n in w]
            assert len(joined) == len(set(joined))
            assert set(joined) == {n for w in want for n in w}
        assert grid["neta"] == sum(len(b["nodes"]) for b in grid["open_boundaries"])
        assert grid["depth"].min() >= 5.0
        # every boundary node is on an open or a land list
        listed = set()
        for b in grid["open_boundaries"] + grid["land_boundaries"]:
            listed |= set(np.asarray(b["nodes"]).tolist())
        assert listed == set((np.unique(mesh.boundary_edges) + 1).tolist())


def test_gpkg_by_pyogrio(reference):
    import pyogrio.raw

    result, out, mesh = reference
    _, _, geometry, _ = pyogrio.raw.read(out / "pentland_firth.gpkg", layer="triangles")
    assert len(geometry) == result.triangles
    meta, _, geometry, values = pyogrio.raw.read(
        out / "pentland_firth.gpkg", layer="boundaries"
    )
    ids = values[list(meta["fields"]).index("physical_id")]
    assert sorted(ids.tolist()) == sorted(mesh.boundary_ids.tolist())


def test_same_depth_in_every_format(reference):
    import meshio

    from coastmesh.io.meshes.adcirc import read_fort14

    _, out, _ = reference
    vtu = meshio.read(out / "pentland_firth.vtu")
    fort = read_fort14(out / "pentland_firth.14")
    np.testing.assert_allclose(fort["depth"], vtu.point_data["depth"], atol=1e-6)


@pytest.mark.parametrize("suffix", ["14", "gr3", "mesh", "nc", "vtu", "gpkg", "msh"])
def test_read_mesh_gives_back_the_case_mesh(reference, suffix):
    """coastmesh's own readers: every readable format the case wrote, one mesh."""
    import meshio

    from coastmesh.io import read_mesh

    _, out, mesh = reference
    back = read_mesh(out / f"pentland_firth.{suffix}", crs="EPSG:4326")
    assert back.crs == mesh.crs
    np.testing.assert_allclose(back.points, mesh.points, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)

    def ids(m):
        return {
            (min(a, b), max(a, b)): int(i)
            for (a, b), i in zip(m.boundary_edges.tolist(), m.boundary_ids, strict=True)
        }

    want = ids(mesh)
    if suffix == "mesh":  # MIKE: one land code, open ids as codes 2, 3, ...
        codes = {
            pid: code
            for code, pid in enumerate(
                sorted(p for p, k in mesh.boundary_kinds.items() if k == "open"), 2
            )
        }
        want = {edge: codes.get(pid, 1) for edge, pid in want.items()}
    assert ids(back) == want
    if suffix != "msh":
        depth = meshio.read(out / "pentland_firth.vtu").point_data["depth"]
        np.testing.assert_allclose(back.point_data["depth"], depth, atol=1e-9)
