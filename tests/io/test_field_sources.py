"""Field sources: model results read as a mesh with values, format by format.

Each format is written here in the layout its model writes (or read from a tiny
real output in ``tests/data/fields``), read, and checked against what was
written.
"""

from __future__ import annotations

from pathlib import Path

import meshio
import netCDF4
import numpy as np
import pytest
import xarray as xr
from io_meshes import strip_mesh

from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io import FieldSource, read_field_source, write_mesh
from coastmesh.io.fields.field_sources import DRY_HEIGHT, TIME_CHUNK

DATA = Path(__file__).parents[1] / "data" / "fields"


def is_lazy(var: xr.DataArray) -> bool:
    """The values are a dask array, not read yet."""
    return var.chunks is not None


# --- ANUGA -------------------------------------------------------------------


def test_anuga_real_file():
    path = DATA / "anuga_tiny.sww"
    with netCDF4.Dataset(path) as ds:
        ds.set_auto_mask(False)
        raw = {key: ds[key][:] for key in ds.variables}
        xll, yll = ds.xllcorner, ds.yllcorner
    source = read_field_source(path)
    assert source.kind == "anuga" and source.path == path
    assert source.crs.to_epsg() == 32630
    expected = np.column_stack(
        [raw["x"].astype(np.float64) + xll, raw["y"].astype(np.float64) + yll]
    )
    assert source.points.dtype == np.float64
    np.testing.assert_array_equal(source.points, expected)
    np.testing.assert_array_equal(source.triangles, raw["volumes"])
    np.testing.assert_array_equal(source.times, raw["time"])
    assert dict(source.roles) == {
        "u": "u",
        "v": "v",
        "elevation": "stage",
        "bed": "elevation",
    }
    assert source.variables["stage"].dims == ("time", "node")
    assert source.variables["elevation"].dims == ("node",)
    assert source.variables["stage_c"].dims == ("time", "triangle")
    assert "elevation_range" not in source.variables  # not on the mesh
    np.testing.assert_array_equal(source.variables["stage"].values, raw["stage"])
    np.testing.assert_array_equal(source.variables["stage_c"].values, raw["stage_c"])
    assert is_lazy(source.variables["stage"]) and is_lazy(source.variables["u"])
    # u, v: momentum / depth where wet, as ANUGA's plot_utils.get_output
    h = raw["stage"] - raw["elevation"]
    wet = h > DRY_HEIGHT
    assert wet.any() and (~wet).any()  # the file has both
    for role, momentum in (("u", "xmomentum"), ("v", "ymomentum")):
        expected = np.where(wet, raw[momentum] / np.where(wet, h, 1.0), 0.0)
        np.testing.assert_allclose(source.variables[role].values, expected, rtol=1e-6)


def write_sww(path, stage, elevation, xmom, ymom, **attrs):
    """An ``.sww`` in ANUGA's layout: 4 points, 2 triangles, relative x and y."""
    with netCDF4.Dataset(path, "w", format="NETCDF3_64BIT_OFFSET") as ds:
        georef = {"xllcorner": 1000.0, "yllcorner": 2000.0, "zone": -1}
        ds.setncatts({"starttime": 0.0, **georef, **attrs})
        ds.createDimension("number_of_volumes", 2)
        ds.createDimension("number_of_vertices", 3)
        ds.createDimension("number_of_points", 4)
        ds.createDimension("number_of_timesteps", len(stage))
        points = ("number_of_points",)
        series = ("number_of_timesteps", "number_of_points")
        ds.createVariable("x", "f4", points)[:] = [0.0, 10.0, 10.0, 0.0]
        ds.createVariable("y", "f4", points)[:] = [0.0, 0.0, 10.0, 10.0]
        volumes = ("number_of_volumes", "number_of_vertices")
        ds.createVariable("volumes", "i4", volumes)[:] = [[0, 1, 2], [0, 2, 3]]
        ds.createVariable("time", "f8", ("number_of_timesteps",))[:] = [0.0, 30.0][
            : len(stage)
        ]
        elevation = np.asarray(elevation)
        ds.createVariable("elevation", "f4", series if elevation.ndim == 2 else points)[
            :
        ] = elevation
        for key, values in (("stage", stage), ("xmomentum", xmom), ("ymomentum", ymom)):
            ds.createVariable(key, "f4", series)[:] = values


@pytest.mark.parametrize("elevation_in_time", [False, True])
def test_anuga_velocity_is_zero_where_dry(tmp_path, elevation_in_time):
    path = tmp_path / "run.sww"
    bed = np.array([0.0, 0.0, 0.0, 0.0])  # depth = stage, exact in float32
    # depths 0, half the threshold, just under it, then just over it, 1 m, 0.5 m
    depths = np.array([[0.0, 5e-4, 9.9e-4, 1.0], [1.1e-3, 1.0, 0.5, 0.0]])
    stage = bed + depths
    xmom = np.array([[0.1, 0.2, 0.3, 0.5], [0.004, 0.25, 1.0, 0.1]])
    ymom = -xmom
    elevation = np.tile(bed, (2, 1)) if elevation_in_time else bed
    write_sww(path, stage, elevation, xmom, ymom)
    source = read_field_source(path)
    assert source.crs is None  # zone -1: not in a UTM zone
    np.testing.assert_array_equal(source.points[:, 0], [1000.0, 1010.0, 1010.0, 1000.0])
    np.testing.assert_array_equal(source.points[:, 1], [2000.0, 2000.0, 2010.0, 2010.0])
    expected = np.array([[0.0, 0.0, 0.0, 0.5], [0.004 / 1.1e-3, 0.25, 2.0, 0.0]])
    np.testing.assert_allclose(source.variables["u"].values, expected, rtol=1e-5)
    np.testing.assert_allclose(source.variables["v"].values, -expected, rtol=1e-5)
    assert source.variables["u"].dims == ("time", "node")
    assert source.variables["elevation"].dims == (
        ("time", "node") if elevation_in_time else ("node",)
    )


@pytest.mark.parametrize(
    ("attrs", "epsg"),
    [
        ({"zone": 55, "hemisphere": "southern"}, 32755),
        ({"zone": 30, "hemisphere": "northern"}, 32630),
        ({"zone": -56}, 32756),  # ANUGA's shorthand for zone 56 south
        ({"zone": 56, "false_northing": 10000000}, 32756),  # no hemisphere
        ({"zone": 30, "false_northing": 0}, 32630),
        ({"zone": 30, "hemisphere": "northern", "epsg": 27700}, 27700),
        ({"zone": 10, "hemisphere": "northern", "datum": "NAD83"}, 26910),
        (
            {"zone": 55, "hemisphere": "southern", "datum": "GDA94"},
            None,
        ),  # no PROJ datum
        ({"zone": -1, "hemisphere": "northern"}, None),
        ({"zone": 30}, None),  # no hemisphere and no false northing
    ],
)
def test_anuga_crs(tmp_path, attrs, epsg):
    path = tmp_path / "run.sww"
    write_sww(
        path, np.zeros((1, 4)), np.zeros(4), np.zeros((1, 4)), np.zeros((1, 4)), **attrs
    )
    crs = read_field_source(path).crs
    assert (None if crs is None else crs.to_epsg()) == epsg


def test_crs_given_replaces_the_files(tmp_path):
    path = tmp_path / "run.sww"
    write_sww(
        path,
        np.zeros((1, 4)),
        np.zeros(4),
        np.zeros((1, 4)),
        np.zeros((1, 4)),
        zone=30,
        hemisphere="northern",
    )
    assert read_field_source(path, crs="EPSG:27700").crs.to_epsg() == 27700
    with pytest.raises(ConfigError, match="not a CRS"):
        read_field_source(path, crs="EPSG:0")


# --- SCHISM ------------------------------------------------------------------


def test_schism_real_excerpt():
    path = DATA / "schism_out2d_excerpt.nc"
    with netCDF4.Dataset(path) as ds:
        ds.set_auto_mask(False)
        raw = {key: ds[key][:] for key in ds.variables}
    source = read_field_source(path)
    assert source.kind == "schism"
    assert source.crs.to_epsg() == 4326  # a lon/lat run (ics = 2) says so
    xy = np.column_stack([raw["SCHISM_hgrid_node_x"], raw["SCHISM_hgrid_node_y"]])
    np.testing.assert_array_equal(source.points, xy)
    np.testing.assert_array_equal(
        source.triangles, raw["SCHISM_hgrid_face_nodes"][:, :3] - 1
    )
    np.testing.assert_array_equal(source.times, raw["time"])
    assert dict(source.roles) == {
        "elevation": "elevation",
        "u": "depthAverageVelX",
        "v": "depthAverageVelY",
        "bed": "bed",
    }
    for key in ("elevation", "depthAverageVelX", "depthAverageVelY"):
        var = source.variables[key]
        assert var.dims == ("time", "node") and is_lazy(var)
        np.testing.assert_array_equal(var.values, raw[key])
    np.testing.assert_array_equal(source.variables["bed"].values, -raw["depth"])
    assert source.variables["dryFlagElement"].dims == ("time", "triangle")
    np.testing.assert_array_equal(source.variables["elevation"]["time"], raw["time"])
    assert "SCHISM_hgrid_node_x" not in source.variables


def write_schism(path, faces, *, old=False, fill=-1, crs=True):
    """An out2d (or schout) file: 5 nodes, ``faces`` 1-based, 2 records."""
    n, nt = 5, 2
    with netCDF4.Dataset(path, "w", format="NETCDF4") as ds:
        ds.createDimension("nSCHISM_hgrid_node", n)
        ds.createDimension("nSCHISM_hgrid_face", len(faces))
        ds.createDimension("nMaxSCHISM_hgrid_face_nodes", 4)
        ds.createDimension("two", 2)
        ds.createDimension("time", None)
        node, face = ("nSCHISM_hgrid_node",), ("nSCHISM_hgrid_face",)
        ds.createVariable("SCHISM_hgrid_node_x", "f8", node)[:] = [0, 1, 1, 0, 2.0]
        ds.createVariable("SCHISM_hgrid_node_y", "f8", node)[:] = [0, 0, 1, 1, 0.5]
        table = ds.createVariable(
            "SCHISM_hgrid_face_nodes",
            "i4",
            face + ("nMaxSCHISM_hgrid_face_nodes",),
            fill_value=fill,
        )
        table.start_index = 1
        table[:] = np.ma.masked_equal(faces, fill)
        time = ds.createVariable("time", "f8", ("time",))
        time.units = "days since 2000-01-01 00:00:00"
        time[:] = [0.0, 0.5]
        ds.createVariable("depth", "f4", node)[:] = [1.0, 2.0, 3.0, 4.0, 5.0]
        series = np.arange(nt * n, dtype=float).reshape(nt, n)
        if old:
            ds.createVariable("elev", "f4", ("time",) + node)[:] = series
            ds.createVariable("dahv", "f4", ("time",) + node + ("two",))[:] = np.stack(
                [series / 10, -series / 10], axis=-1
            )
        else:
            ds.createVariable("elevation", "f4", ("time",) + node)[:] = series
            ds.createVariable("depthAverageVelX", "f4", ("time",) + node)[:] = (
                series / 10
            )
            ds.createVariable("depthAverageVelY", "f4", ("time",) + node)[:] = (
                -series / 10
            )
            dry = ds.createVariable("dryFlagElement", "f4", ("time",) + face)
            dry[:] = np.arange(nt * len(faces)).reshape(nt, len(faces))


def test_schism_quads_are_split_and_face_values_follow(tmp_path):
    path = tmp_path / "out2d_1.nc"
    # a quad 1-2-3-4, then a triangle 2-5-3 (-1 for its 4th node)
    write_schism(path, np.array([[1, 2, 3, 4], [2, 5, 3, -1]]))
    source = read_field_source(path)
    assert source.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    np.testing.assert_array_equal(source.times, [0.0, 43200.0])  # days -> s
    dry = source.variables["dryFlagElement"]
    assert dry.dims == ("time", "triangle") and is_lazy(dry)
    np.testing.assert_array_equal(dry.values, [[0, 0, 1], [2, 2, 3]])
    np.testing.assert_array_equal(source.variables["bed"].values, [-1, -2, -3, -4, -5])
    assert source.crs is None  # a SCHISM file with no crs: not lon/lat
    assert read_field_source(path, crs="EPSG:32630").crs.to_epsg() == 32630


def test_schism_fill_value_other_than_minus_one(tmp_path):
    path = tmp_path / "out2d_1.nc"
    write_schism(path, np.array([[1, 2, 3, -999], [2, 5, 3, -999]]), fill=-999)
    assert read_field_source(path).triangles.tolist() == [[0, 1, 2], [1, 4, 2]]


def test_schism_old_schout(tmp_path):
    path = tmp_path / "schout_1.nc"
    write_schism(path, np.array([[1, 2, 3, -1], [2, 5, 3, -1]]), old=True)
    source = read_field_source(path)
    assert dict(source.roles) == {
        "elevation": "elev",
        "u": "dahv_x",
        "v": "dahv_y",
        "bed": "bed",
    }
    series = np.arange(10.0).reshape(2, 5) / 10
    np.testing.assert_allclose(source.variables["dahv_x"].values, series, rtol=1e-6)
    np.testing.assert_allclose(source.variables["dahv_y"].values, -series, rtol=1e-6)
    assert source.variables["dahv_x"].dims == ("time", "node")


# --- ADCIRC netCDF -----------------------------------------------------------


def write_adcirc_nc(path, variables, *, cartesian=False, times=(0.0, 3600.0)):
    """An ADCIRC netCDF output, as netcdfio.F90 defines it: 4 nodes, 2 elements."""
    with netCDF4.Dataset(path, "w", format="NETCDF4_CLASSIC") as ds:
        ds.createDimension("time", None)
        ds.createDimension("node", 4)
        ds.createDimension("nele", 2)
        ds.createDimension("nvertex", 3)
        time = ds.createVariable("time", "f8", ("time",))
        time.units = "seconds since 2020-01-01 00:00:00"
        time[:] = times
        for key, values in (
            ("x", [-3.0, -2.9, -2.9, -3.0]),
            ("y", [58.6, 58.6, 58.7, 58.7]),
        ):
            var = ds.createVariable(key, "f8", ("node",))
            name = {"x": "longitude", "y": "latitude"}[key]
            var.standard_name = f"{key}_coordinate" if cartesian else name
            var[:] = values
        element = ds.createVariable("element", "i4", ("nele", "nvertex"))
        element.cf_role = "face_node_connectivity"
        element.start_index = 1
        element[:] = [[1, 2, 3], [1, 3, 4]]
        mesh = ds.createVariable("adcirc_mesh", "i4")
        mesh.cf_role = "mesh_topology"
        mesh.topology_dimension = 2
        ds.createVariable("depth", "f8", ("node",))[:] = [10.0, 20.0, 30.0, 40.0]
        for key, (dims, values) in variables.items():
            var = ds.createVariable(key, "f8", dims, fill_value=-99999.0)
            var.location, var.mesh = "node", "adcirc_mesh"
            var[:] = values


def test_adcirc_netcdf_time_series(tmp_path):
    path = tmp_path / "fort.64.nc"
    u = np.array([[0.1, 0.2, -99999.0, 0.4], [0.5, 0.6, 0.7, -99999.0]])
    dry = u == -99999.0
    write_adcirc_nc(
        path,
        {
            "u-vel": (("time", "node"), u),
            "v-vel": (("time", "node"), np.where(dry, u, -u)),
        },
    )
    source = read_field_source(path)
    assert source.kind == "adcirc" and source.crs.to_epsg() == 4326
    assert source.points.tolist() == [
        [-3.0, 58.6],
        [-2.9, 58.6],
        [-2.9, 58.7],
        [-3.0, 58.7],
    ]
    assert source.triangles.tolist() == [[0, 1, 2], [0, 2, 3]]
    np.testing.assert_array_equal(source.times, [0.0, 3600.0])
    expected = np.where(dry, np.nan, u)
    np.testing.assert_array_equal(source.variables["u-vel"].values, expected)
    np.testing.assert_array_equal(source.variables["v-vel"].values, -expected)
    assert is_lazy(source.variables["u-vel"])
    assert dict(source.roles) == {"u": "u-vel", "v": "v-vel", "bed": "bed"}
    np.testing.assert_array_equal(source.variables["bed"].values, [-10, -20, -30, -40])


def test_adcirc_netcdf_max_file(tmp_path):
    path = tmp_path / "maxvel.63.nc"
    peak = np.array([1.5, 2.5, -99999.0, 0.5])
    write_adcirc_nc(
        path,
        {
            "vel_max": (("node",), peak),
            "time_of_vel_max": (("node",), [60, 120, -99999, 180]),
        },
        times=(7200.0,),
    )
    source = read_field_source(path)
    assert source.times is None  # no variable has a time axis
    np.testing.assert_array_equal(
        source.variables["vel_max"].values, [1.5, 2.5, np.nan, 0.5]
    )
    assert source.variables["time_of_vel_max"].dims == ("node",)
    assert source.roles["speed_max"] == "vel_max"


def test_adcirc_netcdf_old_max_file_with_a_time_axis(tmp_path):
    path = tmp_path / "maxele.63.nc"
    write_adcirc_nc(
        path, {"zeta_max": (("time", "node"), [[1.0, 2.0, 3.0, 4.0]])}, times=(0.0,)
    )
    source = read_field_source(path)
    assert source.variables["zeta_max"].dims == ("node",) and source.times is None
    assert source.roles["elevation_max"] == "zeta_max"


def test_adcirc_netcdf_cartesian_has_no_crs(tmp_path):
    path = tmp_path / "fort.63.nc"
    write_adcirc_nc(
        path, {"zeta": (("time", "node"), np.zeros((2, 4)))}, cartesian=True
    )
    source = read_field_source(path)
    assert source.crs is None and source.roles["elevation"] == "zeta"


# --- ADCIRC ASCII ------------------------------------------------------------


def fortran(value: float) -> str:
    """A number as ADCIRC writes it, 1pE20.10E3: ``  -4.8182553168E-001``."""
    mantissa, exponent = f"{value:.10E}".split("E")
    return f"{mantissa}E{int(exponent):+04d}".rjust(20)


def write_ascii(path, records, *, irtype=1, np_=None, sparse=False):
    """An ADCIRC ASCII output as globalio.F writes it: (time, it, values) records."""
    count = len(records[0][2]) if np_ is None else np_
    lines = [
        " coastmesh test                    ! RUNID             coastmesh EPSG:4326",
        f" {len(records):10d} {count:10d} {0.18e4:15.7E} {18:5d} {irtype:5d} "
        "FileFmtVersion:    1050624",
    ]
    for time, step, given in records:
        values = np.asarray(given, dtype=float).reshape(len(given), irtype)
        rows = np.arange(len(values))
        if sparse:
            rows = rows[(values != -99999.0).any(axis=1)]
            dry = fortran(-99999.0)
            lines.append(
                f"  {fortran(time)}     {step:10d}     {len(rows):10d}     {dry}"
            )
        else:
            lines.append(f"  {fortran(time)}     {step:10d}")
        lines += [
            f"  {k + 1:8d}  " + "".join(fortran(v) for v in values[k]) for k in rows
        ]
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture
def grid_file(tmp_path):
    """A fort.14 of 6 lon/lat nodes with a depth, and the mesh in it."""
    mesh = strip_mesh(3, 2, dx=0.01, x0=-3.0, y0=58.6, crs="EPSG:4326")
    path = tmp_path / "fort.14"
    write_mesh(path, mesh)
    return path, mesh


def test_adcirc_ascii_fort63(tmp_path, grid_file):
    grid, mesh = grid_file
    zeta = np.array(
        [[0.1, -0.2, 0.3, -99999.0, 0.5, 0.6], [1.0, 2.0, 3.0, 4.0, 5.0, -99999.0]]
    )
    path = tmp_path / "fort.63"
    write_ascii(path, [(1800.0, 18, zeta[0]), (3600.0, 36, zeta[1])])
    source = read_field_source(path, mesh=grid)
    assert source.kind == "adcirc" and source.crs.to_epsg() == 4326
    np.testing.assert_array_equal(source.points, mesh.points)
    np.testing.assert_array_equal(source.triangles, mesh.triangles)
    np.testing.assert_array_equal(source.times, [1800.0, 3600.0])
    expected = np.where(zeta == -99999.0, np.nan, zeta)
    np.testing.assert_array_equal(source.variables["zeta"].values, expected)
    assert source.variables["zeta"].dims == ("time", "node")
    np.testing.assert_array_equal(
        source.variables["bed"].values, -mesh.point_data["depth"]
    )
    assert dict(source.roles) == {"elevation": "zeta", "bed": "bed"}


def test_adcirc_ascii_sparse_fort64(tmp_path, grid_file):
    grid, _ = grid_file
    u = np.array([0.1, -99999.0, 0.3, 0.4, -99999.0, 0.6])
    uv = np.column_stack([u, np.where(u == -99999.0, u, -2 * u)])
    path = tmp_path / "fort.64"
    write_ascii(path, [(900.0, 9, uv)], irtype=2, sparse=True)
    source = read_field_source(path, mesh=grid)
    expected = np.where(u == -99999.0, np.nan, u)
    np.testing.assert_array_equal(source.variables["u-vel"].values, [expected])
    np.testing.assert_array_equal(source.variables["v-vel"].values, [-2 * expected])
    assert source.roles["u"] == "u-vel" and source.roles["v"] == "v-vel"


@pytest.mark.parametrize(
    ("name", "key", "role"),
    [("maxele.63", "zeta_max", "elevation_max"), ("maxvel.63", "vel_max", "speed_max")],
)
def test_adcirc_ascii_max_files(tmp_path, grid_file, name, key, role):
    grid, _ = grid_file
    peak = np.array([1.0, 2.0, -99999.0, 4.0, 5.0, 6.0])
    when = np.array([60.0, 120.0, -99999.0, 240.0, 300.0, 360.0])
    path = tmp_path / name
    write_ascii(path, [(66300.0, 663, peak), (66300.0, 663, when)])
    source = read_field_source(path, mesh=grid)
    assert source.times is None
    np.testing.assert_array_equal(
        source.variables[key].values, np.where(peak < -9e4, np.nan, peak)
    )
    np.testing.assert_array_equal(
        source.variables[f"time_of_{key}"].values, np.where(when < -9e4, np.nan, when)
    )
    assert source.variables[key].dims == ("node",) and source.roles[role] == key


def test_adcirc_ascii_needs_its_mesh(tmp_path, grid_file):
    grid, _ = grid_file
    path = tmp_path / "maxvel.63"
    write_ascii(path, [(0.0, 0, np.ones(6))])
    with pytest.raises(InputDataError, match=r"maxvel\.63.*mesh="):
        read_field_source(path)
    write_ascii(path, [(0.0, 0, np.ones(5))])
    with pytest.raises(
        InputDataError, match=r"maxvel\.63: NP = 5 nodes, but .*fort\.14 has 6"
    ):
        read_field_source(path, mesh=grid)


def test_adcirc_ascii_short_record(tmp_path, grid_file):
    grid, _ = grid_file
    path = tmp_path / "fort.63"
    write_ascii(path, [(0.0, 0, np.ones(6))])
    path.write_text("\n".join(path.read_text().splitlines()[:-2]) + "\n")
    with pytest.raises(InputDataError, match=r"fort\.63: the record of line 3"):
        read_field_source(path, mesh=grid)


# --- UGRID ---------------------------------------------------------------------


def test_ugrid_written_by_coastmesh(tmp_path):
    mesh = strip_mesh(4, 3, dx=100.0, x0=500000.0, crs="EPSG:32630")
    path = tmp_path / "mesh.nc"
    write_mesh(path, mesh, format="ugrid")
    source = read_field_source(path)
    assert source.kind == "ugrid" and source.crs.to_epsg() == 32630
    np.testing.assert_array_equal(source.points, mesh.points)
    np.testing.assert_array_equal(source.triangles, mesh.triangles)
    assert source.times is None
    np.testing.assert_array_equal(
        source.variables["depth"].values, mesh.point_data["depth"]
    )
    np.testing.assert_array_equal(
        source.variables["bed"].values, -mesh.point_data["depth"]
    )
    assert source.roles["bed"] == "bed"
    assert source.variables["region_id"].dims == ("triangle",)
    assert "boundary_id" not in source.variables  # on the edges


def write_ugrid_file(path, *, transposed=False, start=0, fill=-1, crs_attrs=None):
    """A Delft3D FM style map file: 5 nodes, a quad and a triangle, 3 records."""
    faces = np.array([[0, 1, 2, 3], [1, 4, 2, fill - start]]) + start
    with netCDF4.Dataset(path, "w", format="NETCDF4") as ds:
        ds.createDimension("nmesh2d_node", 5)
        ds.createDimension("nmesh2d_face", 2)
        ds.createDimension("max_nmesh2d_face_nodes", 4)
        ds.createDimension("time", None)
        topology = ds.createVariable("mesh2d", "i4")
        topology.setncatts(
            {
                "cf_role": "mesh_topology",
                "topology_dimension": 2,
                "node_coordinates": "mesh2d_node_x mesh2d_node_y",
                "face_node_connectivity": "mesh2d_face_nodes",
                "face_dimension": "nmesh2d_face",
            }
        )
        node, face = ("nmesh2d_node",), ("nmesh2d_face",)
        for key, values in (("x", [0, 10, 10, 0, 20.0]), ("y", [0, 0, 10, 10, 5.0])):
            var = ds.createVariable(f"mesh2d_node_{key}", "f8", node)
            var.standard_name = f"projection_{key}_coordinate"
            var[:] = values
        dims = (
            ("max_nmesh2d_face_nodes",) + face
            if transposed
            else face + ("max_nmesh2d_face_nodes",)
        )
        table = ds.createVariable("mesh2d_face_nodes", "i4", dims, fill_value=fill)
        table.start_index = start
        table[:] = np.ma.masked_equal(faces.T if transposed else faces, fill)
        time = ds.createVariable("time", "f8", ("time",))
        time.units = "minutes since 2001-01-01"
        time[:] = [0.0, 10.0, 20.0]
        if crs_attrs is not None:
            ds.createVariable("projected_coordinate_system", "i4").setncatts(crs_attrs)
        s1 = ds.createVariable("mesh2d_s1", "f8", ("time",) + face)
        s1.setncatts(
            {
                "mesh": "mesh2d",
                "location": "face",
                "standard_name": "sea_surface_height",
            }
        )
        s1[:] = [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]
        if crs_attrs is not None:
            s1.grid_mapping = "projected_coordinate_system"
        ucx = ds.createVariable("mesh2d_ucx", "f8", ("time",) + face)
        ucx.setncatts(
            {
                "mesh": "mesh2d",
                "location": "face",
                "standard_name": "sea_water_x_velocity",
            }
        )
        ucx[:] = np.ones((3, 2))
        z = ds.createVariable("mesh2d_node_z", "f8", node)
        z.setncatts({"mesh": "mesh2d", "location": "node", "standard_name": "altitude"})
        z[:] = [-1.0, -2.0, -3.0, -4.0, -5.0]
        ds.createVariable(
            "mesh2d_layer", "f8", ("time",) + face + ("max_nmesh2d_face_nodes",)
        )


@pytest.mark.parametrize(
    ("transposed", "start", "fill"), [(False, 0, -1), (True, 1, -999), (False, 1, -1)]
)
def test_ugrid_mixed_faces(tmp_path, transposed, start, fill):
    path = tmp_path / "map.nc"
    write_ugrid_file(path, transposed=transposed, start=start, fill=fill)
    source = read_field_source(path)
    assert source.kind == "ugrid" and source.crs is None
    assert source.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    np.testing.assert_array_equal(source.times, [0.0, 600.0, 1200.0])
    s1 = source.variables["mesh2d_s1"]
    assert s1.dims == ("time", "triangle") and is_lazy(s1)
    np.testing.assert_array_equal(s1.values, [[1, 1, 2], [3, 3, 4], [5, 5, 6]])
    assert dict(source.roles) == {
        "elevation": "mesh2d_s1",
        "u": "mesh2d_ucx",
        "bed": "mesh2d_node_z",
    }
    assert "mesh2d_layer" not in source.variables  # 3D: not read


def test_ugrid_delft3d_crs(tmp_path):
    path = tmp_path / "map.nc"
    attrs = {
        "name": "Amersfoort / RD New",
        "epsg": 28992,
        "grid_mapping_name": "Unknown projected",
    }
    write_ugrid_file(path, crs_attrs=attrs)
    assert read_field_source(path).crs.to_epsg() == 28992


def test_ugrid_written_by_xugrid(tmp_path):
    xugrid = pytest.importorskip("xugrid")
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]])
    faces = np.array([[0, 1, 2, 3], [1, 4, 2, -1]])
    grid = xugrid.Ugrid2d(nodes[:, 0], nodes[:, 1], -1, faces, crs="EPSG:32631")
    values = xr.DataArray(
        np.array([[1.0, 2.0]] * TIME_CHUNK * 2), dims=("time", grid.face_dimension)
    )
    uds = xugrid.UgridDataset(grids=[grid])
    uds["speed"] = xugrid.UgridDataArray(values, grid)
    uds = uds.assign_coords(time=np.arange(TIME_CHUNK * 2) * 60.0)
    path = tmp_path / "xugrid.nc"
    uds.ugrid.to_netcdf(path)
    source = read_field_source(path)
    assert source.crs.to_epsg() == 32631
    assert source.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    speed = source.variables["speed"]
    assert speed.chunks[0] == (TIME_CHUNK, TIME_CHUNK)
    np.testing.assert_array_equal(speed.isel(time=0).values, [1, 1, 2])


# --- VTU -----------------------------------------------------------------------


def test_vtu(tmp_path):
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0.0]])
    cells = [("quad", [[0, 1, 2, 3]]), ("line", [[0, 1]]), ("triangle", [[1, 4, 2]])]
    data = meshio.Mesh(
        points,
        cells,
        point_data={"speed": [1.0, 2, 3, 4, 5], "flow": np.arange(10.0).reshape(5, 2)},
        cell_data={"region": [[7], [8], [9]], "h": [[0.5], [0.0], [1.5]]},
    )
    path = tmp_path / "result.vtu"
    meshio.write(path, data)
    source = read_field_source(path, crs="EPSG:32630")
    assert (
        source.kind == "vtu" and source.crs.to_epsg() == 32630 and source.times is None
    )
    np.testing.assert_array_equal(source.points, points[:, :2])
    assert source.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    np.testing.assert_array_equal(source.variables["speed"].values, [1, 2, 3, 4, 5])
    np.testing.assert_array_equal(source.variables["flow_y"].values, [1, 3, 5, 7, 9])
    np.testing.assert_array_equal(source.variables["region"].values, [7, 7, 9])
    assert source.variables["h"].dims == ("triangle",)
    assert read_field_source(path).crs is None and not source.roles


# --- errors --------------------------------------------------------------------


def test_unknown_files_name_the_file(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("a line\nanother line\n")
    with pytest.raises(FormatError, match=r"notes\.txt: not a field source .*ANUGA"):
        read_field_source(text)
    plain = tmp_path / "plain.nc"
    xr.Dataset({"a": ("x", [1.0, 2.0])}).to_netcdf(plain)
    with pytest.raises(FormatError, match=r"plain\.nc: a netCDF file with no mesh"):
        read_field_source(plain)
    broken = tmp_path / "broken.nc"
    broken.write_bytes(b"CDF\x01" + b"\xff" * 10)
    with pytest.raises(InputDataError, match=r"broken\.nc: not a readable netCDF"):
        read_field_source(broken)
    other = tmp_path / "fort.73"
    write_ascii(other, [(0.0, 0, np.ones(3))])
    with pytest.raises(FormatError, match=r"fort\.73: an ADCIRC ASCII output"):
        read_field_source(other, mesh=tmp_path / "fort.14")


def test_missing_file(tmp_path):
    with pytest.raises(InputDataError, match=r"nothing\.nc: file not found"):
        read_field_source(tmp_path / "nothing.nc")


def test_field_source_checks_its_parts():
    points, triangles = np.zeros((3, 2)), np.array([[0, 1, 2]])
    good = xr.DataArray(np.zeros(3), dims="node")
    FieldSource(Path("a"), "vtu", points, triangles, None, {"a": good}, None, {})
    with pytest.raises(ValueError, match=r"'a' has dims \('x',\)"):
        FieldSource(
            Path("a"),
            "vtu",
            points,
            triangles,
            None,
            {"a": good.rename(node="x")},
            None,
            {},
        )
    with pytest.raises(ValueError, match="'a' has 3 along 'triangle'; expected 1"):
        FieldSource(
            Path("a"),
            "vtu",
            points,
            triangles,
            None,
            {"a": good.rename(node="triangle")},
            None,
            {},
        )
    with pytest.raises(ValueError, match=r"roles\['u'\] = 'b'"):
        FieldSource(
            Path("a"), "vtu", points, triangles, None, {"a": good}, None, {"u": "b"}
        )
    with pytest.raises(ValueError, match=r"node indices in \[0, 3\]"):
        FieldSource(Path("a"), "vtu", points, [[0, 1, 3]], None, {}, None, {})
