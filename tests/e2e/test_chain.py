"""The issue-3 chain on real data: shorelines + loxodromes -> domain -> size -> mesh.

Orkney (GSHHG full resolution, bundled) closed by four rhumb lines; the size is
graded from the coast in metres; the mesh is made in UTM and written as msh 2.2.
"""

from __future__ import annotations

import json

import numpy as np
import shapely
from pyproj import Transformer

from coastmesh.data import path as data_path
from coastmesh.geometry import Loxodrome, OpenBoundary, build_domain
from coastmesh.io.meshes.msh import read_msh, write_msh
from coastmesh.meshing import default_mesh_crs, generate_mesh
from coastmesh.sizing import Gradation, size_field, to_metres
from coastmesh.types import SizeGrid


def test_orkney_chain(tmp_path):
    features = json.loads((data_path("orkney_gshhg_f.geojson")).read_text())["features"]
    land = np.array([shapely.from_geojson(json.dumps(f["geometry"])) for f in features])
    sides = [
        ("west", 2, Loxodrome((-3.5, 58.6), 0.0, end_lat=59.5)),
        ("north", 3, Loxodrome((-3.6, 59.45), 90.0, end_lon=-2.3)),
        ("east", 4, Loxodrome((-2.35, 59.5), 180.0, end_lat=58.55)),
        ("south", 5, Loxodrome((-2.3, 58.62), 270.0, end_lon=-3.6)),
    ]
    walls = [OpenBoundary(line.sample(1_000), name, i) for name, i, line in sides]
    domain, report = build_domain(
        land, walls, crs="EPSG:4326", seed=(-3.1, 58.85), min_area=2e5
    )
    assert report.holes >= 5

    utm = default_mesh_crs(domain)
    to_utm = Transformer.from_crs("EPSG:4326", utm, always_xy=True)
    coast = shapely.transform(
        shapely.boundary(land), lambda c: np.column_stack(to_utm.transform(*c.T))
    )
    minx, miny, maxx, maxy = shapely.bounds(
        shapely.transform(
            domain.polygon, lambda c: np.column_stack(to_utm.transform(*c.T))
        )
    )
    h_max = to_metres("0.05 deg")
    field = size_field(
        (minx - 5e3, miny - 5e3, maxx + 5e3, maxy + 5e3),
        [Gradation(coast, h_min=600.0, d_hold=1_000.0, d_grade=to_metres("0.2 deg"))],
        crs=utm,
        h_max=h_max,
        cell=500.0,
        rate=0.3,
    )
    mesh = generate_mesh(
        domain,
        SizeGrid.from_dataarray(field),
        mesh_crs=utm,
    )
    # every boundary edge carries an id, from the shoreline or one of the sides
    assert set(np.unique(mesh.boundary_ids)) <= {1, 2, 3, 4, 5}
    assert 1 in mesh.boundary_ids and len(set(mesh.boundary_ids)) >= 4
    # mesh nodes lie in the domain (lon/lat out), to within a boundary smoothing
    inside = shapely.dwithin(domain.polygon, shapely.points(mesh.points), 0.01)
    assert inside.all()
    path = tmp_path / "orkney.msh"
    write_msh(path, mesh, version="2.2")
    back = read_msh(path)
    assert len(back.points) == len(mesh.points)
    np.testing.assert_array_equal(
        np.sort(back.boundary_ids), np.sort(mesh.boundary_ids)
    )


def test_size_grid_from_dataarray_checks_dims():
    import pytest
    import xarray as xr

    from coastmesh.types import SizeGrid

    field = xr.DataArray(
        np.full((2, 3), 5.0),
        dims=("y", "x"),
        coords={"y": [0.0, 1.0], "x": [0.0, 1.0, 2.0]},
    )
    grid = SizeGrid.from_dataarray(field)
    assert grid.values.shape == (2, 3) and grid.x.tolist() == [0.0, 1.0, 2.0]
    with pytest.raises(ValueError, match=r"dims \('x', 'y'\)"):
        SizeGrid.from_dataarray(field.transpose())
