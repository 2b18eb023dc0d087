"""A model's results on the size grid: derived variables, reductions, sampling."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy.spatial import Delaunay

from coastmesh.errors import ConfigError, InputDataError
from coastmesh.io.fields import field_values
from coastmesh.io.fields.field_values import is_mesh_source, sample_field
from coastmesh.sizing.grid import PlaneGrid

UTM = "EPSG:32630"
X0, Y0 = 500000.0, 6500000.0
TIMES = np.arange(0.0, 12 * 3600.0 + 1, 1800.0)  # 25 records, half-hourly


def _mesh(n=400, seed=1):
    rng = np.random.default_rng(seed)
    inner = rng.uniform(0, 10000, (n, 2))
    corners = np.array([[0, 0], [10000, 0], [10000, 10000], [0, 10000]], float)
    points = np.vstack([corners, inner])
    return points, Delaunay(points).simplices.astype(np.int64)


def _ugrid(path, points, triangles, variables, times=TIMES):
    """A UGRID-1.0 file: ``variables`` maps names to (location, values, attrs)."""
    ds = xr.Dataset(
        {
            "mesh2d": (
                (),
                0,
                {
                    "cf_role": "mesh_topology",
                    "topology_dimension": 2,
                    "node_coordinates": "node_x node_y",
                    "face_node_connectivity": "face_nodes",
                },
            ),
            "node_x": (
                "node",
                X0 + points[:, 0],
                {"standard_name": "projection_x_coordinate"},
            ),
            "node_y": (
                "node",
                Y0 + points[:, 1],
                {"standard_name": "projection_y_coordinate"},
            ),
            "face_nodes": (
                ("face", "three"),
                triangles,
                {
                    "cf_role": "face_node_connectivity",
                    "start_index": 0,
                },
            ),
        },
        coords={
            "time": (
                "time",
                times,
                {"units": "seconds since 2026-01-01", "standard_name": "time"},
            )
        },
    )
    for name, (location, values, attrs) in variables.items():
        dim = "node" if location == "node" else "face"
        dims = ("time", dim) if np.ndim(values) == 2 else (dim,)
        ds[name] = (dims, values, {"mesh": "mesh2d", "location": location, **attrs})
    ds.to_netcdf(path)
    return path


def _grid(cell=250.0):
    return PlaneGrid.from_bounds((X0, Y0, X0 + 10000, Y0 + 10000), cell, UTM)


def _on_grid(grid, f):
    xx, yy = np.meshgrid(grid.x - X0, grid.y - Y0)
    return f(xx, yy)


def test_a_ugrid_file_is_a_mesh_source_and_a_geotiff_is_not(tmp_path, orkney_tif):
    points, triangles = _mesh()
    path = _ugrid(tmp_path / "r.nc", points, triangles, {})
    assert is_mesh_source(path)
    assert not is_mesh_source(orkney_tif)


def test_peak_speed_is_the_max_of_the_records_speed(tmp_path):
    points, triangles = _mesh()
    x, y = points.T
    w = 2 * np.pi * TIMES / 44712.0
    a, b = 1 + x / 5000, 0.5 + y / 10000  # linear amplitudes: exact on the grid
    u = np.outer(np.cos(w), a)
    v = np.outer(np.cos(w), b)
    path = _ugrid(
        tmp_path / "r.nc",
        points,
        triangles,
        {
            "ucx": ("node", u, {"standard_name": "sea_water_x_velocity"}),
            "ucy": ("node", v, {"standard_name": "sea_water_y_velocity"}),
        },
    )
    grid = _grid()
    got = sample_field(grid, path, variable="speed", reduce="max", crs=UTM)
    # the peak of |cos w t| (a, b) over the records at the nodes, linear between
    peak = np.abs(np.cos(w)).max()
    want = peak * np.hypot(a, b)
    # the grid samples the node values linearly: compare at the grid from the
    # nodes by the same interpolation, and on the nodes themselves
    from coastmesh.sizing.fields import triangles_on_grid

    ref, inside = triangles_on_grid(points + [X0, Y0], triangles, grid.x, grid.y, want)
    assert inside.all() and got.inside.all()
    np.testing.assert_allclose(got.values, ref, rtol=1e-6)
    assert got.what == "speed max"


def test_tidal_range_and_the_record_at_a_time(tmp_path):
    points, triangles = _mesh()
    x, _ = points.T
    amp = 1.0 + x / 10000  # 1 to 2 m: linear
    w = 2 * np.pi * TIMES / 44712.0
    eta = np.outer(np.sin(w), amp)
    path = _ugrid(
        tmp_path / "r.nc",
        points,
        triangles,
        {
            "s1": ("node", eta, {"standard_name": "sea_surface_height"}),
        },
    )
    grid = _grid()
    rng = sample_field(grid, path, variable="elevation", reduce="range", crs=UTM)
    expected = (np.sin(w).max() - np.sin(w).min()) * (1.0 + (grid.x - X0) / 10000)
    np.testing.assert_allclose(
        rng.values, np.broadcast_to(expected, grid.shape), rtol=1e-6
    )
    at = sample_field(
        grid, path, variable="s1", reduce="at", time=3 * 3600.0 + 600, crs=UTM
    )
    k = 6  # 3 h is the nearest record to 3 h 10 min
    np.testing.assert_allclose(
        at.values,
        np.broadcast_to(np.sin(w[k]) * (1.0 + (grid.x - X0) / 10000), grid.shape),
        rtol=1e-6,
        atol=1e-12,
    )


def test_vorticity_of_a_solid_rotation_and_a_gradient(tmp_path):
    points, triangles = _mesh()
    x, y = points.T
    c = 1e-4  # u = -c y, v = c x: vorticity 2c everywhere
    ramp = np.linspace(0.5, 1.0, len(TIMES))[:, None]
    path = _ugrid(
        tmp_path / "r.nc",
        points,
        triangles,
        {
            "u": ("node", -c * y * ramp, {"standard_name": "sea_water_x_velocity"}),
            "v": ("node", c * x * ramp, {"standard_name": "sea_water_y_velocity"}),
            "bedlevel": ("node", -10 - x / 100, {}),
        },
    )
    grid = _grid()
    vort = sample_field(grid, path, variable="vorticity", reduce="max", crs=UTM)
    np.testing.assert_allclose(vort.values, 2 * c, rtol=1e-6)
    slope = sample_field(grid, path, variable="bedlevel", gradient=True, crs=UTM)
    np.testing.assert_allclose(slope.values, 0.01, rtol=1e-6)
    assert slope.what == "bedlevel gradient"


def test_face_values_are_constant_in_each_triangle(tmp_path):
    from matplotlib.path import Path as MplPath

    points, triangles = _mesh()
    path = _ugrid(
        tmp_path / "r.nc",
        points,
        triangles,
        {
            "index": ("face", np.arange(len(triangles), dtype=float), {}),
        },
    )
    grid = _grid(cell=100.0)
    got = sample_field(grid, path, variable="index", crs=UTM)
    assert got.inside.all()
    rng = np.random.default_rng(0)
    for j, i in zip(
        rng.integers(0, grid.shape[0], 300),
        rng.integers(0, grid.shape[1], 300),
        strict=True,
    ):
        corners = points[triangles[int(got.values[j, i])]]
        node = (grid.x[i] - X0, grid.y[j] - Y0)
        # the node lies in (or on the edge of) the triangle whose value it has
        assert MplPath(corners).contains_point(node, radius=1e-6) or MplPath(
            corners[::-1]
        ).contains_point(node, radius=1e-6)


def test_streaming_in_small_blocks_gives_the_same(tmp_path, monkeypatch):
    points, triangles = _mesh()
    rng = np.random.default_rng(2)
    series = rng.normal(size=(len(TIMES), len(points)))
    series[3, :50] = np.nan  # dry at one record: left out of the mean
    path = _ugrid(tmp_path / "r.nc", points, triangles, {"z": ("node", series, {})})
    grid = _grid()
    whole = {
        r: sample_field(grid, path, variable="z", reduce=r, crs=UTM).values
        for r in ("max", "min", "mean", "range")
    }
    monkeypatch.setattr(field_values, "_VALUES_AT_ONCE", 3 * len(points))
    for r, values in whole.items():
        again = sample_field(grid, path, variable="z", reduce=r, crs=UTM).values
        np.testing.assert_allclose(again, values, rtol=1e-12)
    # the mean leaves the NaN record out at the nodes it is NaN at
    mean = np.nanmean(series, axis=0)
    from coastmesh.sizing.fields import triangles_on_grid

    ref, _ = triangles_on_grid(points + [X0, Y0], triangles, grid.x, grid.y, mean)
    np.testing.assert_allclose(whole["mean"], ref, rtol=1e-9)


def test_a_series_without_reduce_names_the_file_and_variable(tmp_path):
    points, triangles = _mesh()
    path = _ugrid(
        tmp_path / "run.nc",
        points,
        triangles,
        {
            "z": ("node", np.zeros((len(TIMES), len(points))), {}),
        },
    )
    with pytest.raises(
        ConfigError,
        match=r"'z' of .*run\.nc is a time series of 25 records; give reduce",
    ):
        sample_field(_grid(), path, variable="z", crs=UTM, where="mesh_size.fields[1]")


def test_a_missing_variable_lists_those_there(tmp_path):
    points, triangles = _mesh()
    path = _ugrid(
        tmp_path / "run.nc",
        points,
        triangles,
        {
            "ucx": (
                "node",
                np.zeros((len(TIMES), len(points))),
                {"standard_name": "sea_water_x_velocity"},
            ),
            "ucy": (
                "node",
                np.zeros((len(TIMES), len(points))),
                {"standard_name": "sea_water_y_velocity"},
            ),
        },
    )
    with pytest.raises(ConfigError) as err:
        sample_field(_grid(), path, variable="power", reduce="max", crs=UTM)
    text = str(err.value)
    assert "'power' is not in" in text and "run.nc" in text
    assert "ucx" in text and "ucy" in text and "'speed' (derived)" in text
    assert "'elevation' (derived)" not in text  # no free surface in the file


def test_a_source_off_the_domain_and_one_without_crs(tmp_path):
    points, triangles = _mesh()
    path = _ugrid(
        tmp_path / "run.nc", points, triangles, {"z": ("node", points[:, 0], {})}
    )
    far = PlaneGrid.from_bounds((X0 + 50000, Y0, X0 + 60000, Y0 + 10000), 250.0, UTM)
    with pytest.raises(InputDataError, match=r"run\.nc does not overlap the domain"):
        sample_field(far, path, variable="z", crs=UTM)
    with pytest.raises(
        InputDataError, match=r"run\.nc stores no CRS; give the entry's crs"
    ):
        sample_field(_grid(), path, variable="z")
