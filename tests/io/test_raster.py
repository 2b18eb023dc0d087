"""Reading and writing rasters: GeoTIFF and GEBCO-style NetCDF."""

from __future__ import annotations

import numpy as np
import pytest
import rasterio
import xarray as xr
from affine import Affine
from conftest import ORKNEY_RASTER_BBOX
from pyproj import CRS

from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.io.rasters.raster import raster_transform, read_raster, write_raster


def assert_same_raster(a: xr.DataArray, b: xr.DataArray) -> None:
    assert a.dims == b.dims == ("y", "x")
    np.testing.assert_array_equal(a.values, b.values)
    np.testing.assert_allclose(a.attrs["transform"], b.attrs["transform"], atol=1e-9)
    np.testing.assert_allclose(a.x, b.x, atol=1e-9)
    np.testing.assert_allclose(a.y, b.y, atol=1e-9)
    assert CRS.from_user_input(a.attrs["crs"]) == CRS.from_user_input(b.attrs["crs"])
    assert a.attrs["dtype"] == b.attrs["dtype"]
    assert a.attrs["nodata"] == b.attrs["nodata"] or (
        np.isnan(a.attrs["nodata"]) and np.isnan(b.attrs["nodata"])
    )


@pytest.fixture(scope="module")
def orkney(orkney_tif):
    return read_raster(orkney_tif)


def test_read_geotiff(orkney):
    assert orkney.shape == (51, 101)
    assert orkney.dims == ("y", "x")
    assert orkney.dtype == np.float64
    assert orkney.name == "elevation"
    assert orkney.attrs["dtype"] == "float32"
    assert orkney.attrs["nodata"] is None
    assert orkney.attrs["units"] == "m"
    assert CRS.from_wkt(orkney.attrs["crs"]).to_epsg() == 4326
    np.testing.assert_allclose(
        orkney.attrs["transform"], (0.1, 0, -8.05, 0, -0.1, 61.05)
    )
    # cell centres on the 0.1 degree grid nodes, north-up
    np.testing.assert_allclose(orkney.x[[0, -1]], [-8.0, 2.0], atol=1e-9)
    np.testing.assert_allclose(orkney.y[[0, -1]], [61.0, 56.0], atol=1e-9)
    assert np.isfinite(orkney.values).all()
    assert orkney.values.min() == pytest.approx(-1406, abs=1)
    assert orkney.values.max() == pytest.approx(1030, abs=1)


def test_netcdf_with_ascending_latitude_matches_the_geotiff(nwshelf_nc, nwshelf_tif):
    from_nc = read_raster(nwshelf_nc)
    from_tif = read_raster(nwshelf_tif)
    assert from_nc.shape == (221, 421)
    assert from_nc.y[0] > from_nc.y[-1]  # north-up although the file is south-up
    # GDAL's default netCDF fill (9.97e36) is not taken as a real nodata
    assert from_nc.attrs["nodata"] is None
    assert_same_raster(from_nc, from_tif)


def test_bbox_cuts_whole_cells(orkney_tif, orkney):
    cut = read_raster(orkney_tif, bbox=ORKNEY_RASTER_BBOX)
    # cells whose area overlaps the box: centres -4.0 .. -2.0 and 58.0 .. 60.0
    assert cut.shape == (21, 21)
    np.testing.assert_allclose(cut.x[[0, -1]], [-4.0, -2.0], atol=1e-9)
    np.testing.assert_allclose(cut.y[[0, -1]], [60.0, 58.0], atol=1e-9)
    np.testing.assert_allclose(cut.attrs["transform"], (0.1, 0, -4.05, 0, -0.1, 60.05))
    expected = orkney.sel(x=cut.x, y=cut.y, method="nearest").values
    np.testing.assert_array_equal(cut.values, expected)


def test_bbox_is_clamped_to_the_raster(orkney_tif):
    cut = read_raster(orkney_tif, bbox=(-20, 59.0, -7.0, 70.0))
    assert cut.shape == (21, 11)


def test_bbox_outside(orkney_tif):
    with pytest.raises(InputDataError, match=r"does not overlap the raster") as info:
        read_raster(orkney_tif, bbox=(20, 10, 21, 11))
    assert str(orkney_tif) in str(info.value)


def test_bad_bbox(orkney_tif):
    with pytest.raises(ConfigError, match="minx < maxx"):
        read_raster(orkney_tif, bbox=(0, 0, -1, 1))


@pytest.mark.parametrize("suffix", [".tif", ".nc"])
def test_round_trip(tmp_path, write_read, orkney, suffix):
    back = write_read(
        tmp_path / f"depth{suffix}",
        write_raster,
        read_raster,
        orkney,
        assert_same_raster,
    )
    assert_same_raster(orkney, back)
    assert back.name == "elevation"
    assert back.attrs["units"] == "m"


@pytest.mark.parametrize("suffix", [".tif", ".nc"])
def test_round_trip_with_nodata(tmp_path, write_read, orkney, suffix):
    holed = orkney.copy()
    holed.values[:3, :4] = np.nan
    holed.attrs["nodata"] = -9999.0
    back = write_read(
        tmp_path / f"holed{suffix}",
        write_raster,
        read_raster,
        holed,
        assert_same_raster,
    )
    assert back.attrs["nodata"] == -9999.0
    assert np.isnan(back.values).sum() == 12
    assert_same_raster(holed, back)


def test_nan_without_nodata_is_stored_as_nan(tmp_path, orkney):
    holed = orkney.copy()
    holed.values[0, 0] = np.nan
    write_raster(tmp_path / "holed.tif", holed)
    back = read_raster(tmp_path / "holed.tif")
    assert np.isnan(back.attrs["nodata"])
    assert np.isnan(back.values[0, 0]) and np.isfinite(back.values[0, 1])


def test_integer_rasters_are_rounded(tmp_path, orkney):
    integer = orkney.copy(data=orkney.values + 0.4)
    integer.values[0, 0] = np.nan
    integer.attrs.update(dtype="int16", nodata=-32768.0)
    write_raster(tmp_path / "int.tif", integer)
    back = read_raster(tmp_path / "int.tif")
    assert back.attrs["dtype"] == "int16"
    assert np.isnan(back.values[0, 0])
    np.testing.assert_array_equal(back.values[1:], np.rint(integer.values[1:]))


def test_integer_without_nodata_cannot_hold_nan(tmp_path, orkney):
    integer = orkney.copy()
    integer.values[0, 0] = np.nan
    integer.attrs.update(dtype="int16", nodata=None)
    with pytest.raises(FormatError, match=r"1 cells are missing.*int16"):
        write_raster(tmp_path / "int.tif", integer)
    assert list(tmp_path.iterdir()) == []


def test_netcdf_layout(tmp_path, orkney):
    described = orkney.copy()
    described.attrs["history"] = "made by a test"
    write_raster(tmp_path / "depth.nc", described)
    with xr.open_dataset(tmp_path / "depth.nc") as dataset:
        assert list(dataset["elevation"].dims) == ["lat", "lon"]
        assert (np.diff(dataset["lat"].values) > 0).all()  # ascending, like GEBCO
        assert dataset["lat"].attrs["units"] == "degrees_north"
        assert dataset["lon"].attrs["standard_name"] == "longitude"
        assert dataset["elevation"].attrs["grid_mapping"] == "crs"
        assert CRS.from_wkt(dataset["crs"].attrs["crs_wkt"]).to_epsg() == 4326
        assert dataset.attrs["history"] == "made by a test"
        assert dataset.attrs["Conventions"].startswith("CF-")
        assert dataset["elevation"].dtype == np.float32


def test_geotiff_layout(tmp_path, orkney):
    described = orkney.copy()
    described.attrs["history"] = "made by a test"
    write_raster(tmp_path / "depth.tif", described)
    with rasterio.open(tmp_path / "depth.tif") as dataset:
        assert dataset.compression is not None
        assert dataset.tags()["history"] == "made by a test"
        assert dataset.crs.to_epsg() == 4326
        assert dataset.dtypes == ("float32",)


def test_projected_netcdf_uses_x_and_y(tmp_path):
    grid = xr.DataArray(
        np.arange(12.0).reshape(3, 4),
        dims=("y", "x"),
        coords={"y": [250.0, 150.0, 50.0], "x": [50.0, 150.0, 250.0, 350.0]},
        name="depth",
        attrs={"crs": CRS.from_epsg(32630).to_wkt(), "dtype": "float64"},
    )
    write_raster(tmp_path / "utm.nc", grid)
    with xr.open_dataset(tmp_path / "utm.nc") as dataset:
        assert list(dataset["depth"].dims) == ["y", "x"]
        assert dataset["x"].attrs["units"] == "m"
    back = read_raster(tmp_path / "utm.nc")
    np.testing.assert_array_equal(back.values, grid.values)
    np.testing.assert_allclose(back.attrs["transform"], (100, 0, 0, 0, -100, 300))
    assert CRS.from_wkt(back.attrs["crs"]).to_epsg() == 32630


def test_transform_from_coordinates():
    grid = xr.DataArray(
        np.zeros((2, 3)),
        dims=("y", "x"),
        coords={"y": [1.5, 0.5], "x": [0.5, 1.5, 2.5]},
    )
    assert tuple(raster_transform(grid))[:6] == (1.0, 0.0, 0.0, 0.0, -1.0, 2.0)
    uneven = grid.assign_coords(x=[0.0, 1.0, 5.0])
    with pytest.raises(ValueError, match="'x' is not evenly spaced"):
        raster_transform(uneven)


def test_raster_without_crs(tmp_path):
    with rasterio.open(
        tmp_path / "nocrs.tif",
        "w",
        driver="GTiff",
        width=4,
        height=3,
        count=1,
        dtype="float32",
        transform=Affine(1, 0, 0, 0, -1, 3),
    ) as dataset:
        dataset.write(np.ones((3, 4), dtype="float32"), 1)
    assert read_raster(tmp_path / "nocrs.tif").attrs["crs"] is None


@pytest.mark.filterwarnings("ignore::rasterio.errors.NotGeoreferencedWarning")
def test_raster_without_georeferencing(tmp_path):
    with rasterio.open(
        tmp_path / "plain.tif",
        "w",
        driver="GTiff",
        width=4,
        height=3,
        count=1,
        dtype="uint8",
    ) as dataset:
        dataset.write(np.ones((3, 4), dtype="uint8"), 1)
    with pytest.raises(InputDataError, match=r"plain\.tif: has no georeferencing"):
        read_raster(tmp_path / "plain.tif")


def test_several_netcdf_variables(tmp_path, orkney):
    two = xr.Dataset(
        {
            "elevation": (("lat", "lon"), orkney.values[::-1]),
            "tid": (("lat", "lon"), np.zeros(orkney.shape, dtype=np.int8)),
        },
        coords={"lat": orkney.y.values[::-1], "lon": orkney.x.values},
    )
    path = tmp_path / "gebco.nc"
    two.to_netcdf(path)
    with pytest.raises(InputDataError, match=r"2 variables \(elevation, tid\)"):
        read_raster(path)
    chosen = read_raster(f'NETCDF:"{path}":elevation')
    np.testing.assert_array_equal(chosen.values, orkney.values)


def test_missing_file(tmp_path):
    with pytest.raises(InputDataError, match="file not found") as info:
        read_raster(tmp_path / "nothing.tif")
    assert info.value.path == str(tmp_path / "nothing.tif")


def test_not_a_raster(orkney_geojson):
    with pytest.raises(FormatError, match="not a raster file") as info:
        read_raster(orkney_geojson)
    assert str(orkney_geojson) in str(info.value)


def test_unknown_output_extension(tmp_path, orkney):
    with pytest.raises(FormatError, match=r"'\.png'.*\.nc.*\.tif"):
        write_raster(tmp_path / "depth.png", orkney)
    assert list(tmp_path.iterdir()) == []


def test_existing_output_is_kept(tmp_path, orkney):
    path = tmp_path / "depth.tif"
    path.write_bytes(b"old")
    with pytest.raises(FileExistsError, match="--overwrite"):
        write_raster(path, orkney)
    assert path.read_bytes() == b"old"
    write_raster(path, orkney, overwrite=True)
    assert read_raster(path).shape == orkney.shape
