"""``coastmesh simplify-raster`` end to end, through click."""

from __future__ import annotations

import re

import numpy as np
import pytest
import rasterio
import xarray as xr
from affine import Affine
from conftest import ORKNEY_RASTER_BBOX, assert_clean_failure

from coastmesh import __version__
from coastmesh.io.rasters.raster import read_raster

BBOX = [str(v) for v in ORKNEY_RASTER_BBOX]


def test_simplify_geotiff(run_cli, orkney_tif, tmp_path, folder_listing):
    out = tmp_path / "depth.tif"
    result = run_cli("simplify-raster", orkney_tif, out, "--window", 8, "--modes", 16)
    assert result.exit_code == 0, result.output
    summary = result.stdout.strip().splitlines()
    assert len(summary) == 1
    assert "51 x 101 cells, 0 missing; 5151 covered by a full window" in summary[0]
    assert re.search(r"change rms [\d.]+, max [\d.]+; \d+\.\d s; wrote", summary[0])
    assert folder_listing(tmp_path) == ["depth.tif"]

    source = read_raster(orkney_tif)
    depth = read_raster(out)
    assert depth.shape == source.shape
    assert depth.attrs["transform"] == source.attrs["transform"]
    assert depth.attrs["crs"] == source.attrs["crs"]
    assert depth.attrs["dtype"] == "float32"
    assert depth.attrs["nodata"] is None
    change = np.abs(depth.values - source.values)
    assert change.max() > 1.0  # 16 of 64 modes smooth the relief
    assert change.mean() < 0.1 * np.abs(source.values).mean()
    with rasterio.open(out) as dataset:
        tags = dataset.tags()
    assert tags["coastmesh_version"] == __version__
    assert tags["coastmesh_window"] == "8x8"
    assert tags["coastmesh_modes"] == "16"
    assert "simplify-raster" in tags["history"]


def test_all_modes_give_back_the_input(run_cli, orkney_tif, tmp_path):
    out = tmp_path / "same.tif"
    result = run_cli(
        "simplify-raster",
        orkney_tif,
        out,
        "--window",
        4,
        "--modes",
        16,
        "--bbox",
        *BBOX,
    )
    assert result.exit_code == 0, result.output
    source = read_raster(orkney_tif, bbox=ORKNEY_RASTER_BBOX)
    np.testing.assert_allclose(read_raster(out).values, source.values, atol=1e-2)


def test_netcdf_in_and_out_with_bbox_and_plot(
    run_cli, nwshelf_nc, tmp_path, folder_listing
):
    out = tmp_path / "depth.nc"
    result = run_cli(
        "simplify-raster",
        nwshelf_nc,
        out,
        "--window",
        "8x6",
        "--modes",
        10,
        "--bbox",
        *BBOX,
        "--plot",
        tmp_path / "depth.png",
    )
    assert result.exit_code == 0, result.output
    assert folder_listing(tmp_path) == ["depth.nc", "depth.png"]
    assert (tmp_path / "depth.png").read_bytes()[:4] == b"\x89PNG"
    depth = read_raster(out)
    assert depth.shape == (21, 21)
    np.testing.assert_allclose(
        depth.attrs["transform"], (0.1, 0, -4.05, 0, -0.1, 60.05)
    )
    with xr.open_dataset(out) as dataset:
        assert (np.diff(dataset["lat"].values) > 0).all()
        assert dataset.attrs["coastmesh_window"] == "8x6"


def test_missing_cells_stay_missing(run_cli, orkney_tif, tmp_path):
    source = read_raster(orkney_tif)
    holed = source.copy()
    holed.values[10:14, 20:30] = np.nan
    holed.attrs["nodata"] = -9999.0
    from coastmesh.io.rasters.raster import write_raster

    write_raster(tmp_path / "holed.tif", holed)
    out = tmp_path / "out.tif"
    result = run_cli("simplify-raster", tmp_path / "holed.tif", out, "--modes", 8)
    assert result.exit_code == 0, result.output
    assert "40 missing" in result.stdout
    depth = read_raster(out)
    assert depth.attrs["nodata"] == -9999.0
    np.testing.assert_array_equal(np.isnan(depth.values), np.isnan(holed.values))


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        (("--window", "1"), ["'--window'", "'1'", "at least 2"]),
        (("--window", "8x1"), ["'--window'", "'8x1'"]),
        (("--window", "abc"), ["'--window'", "'abc'"]),
        (("--modes", "0"), ["'--modes'", "0 is not in the range"]),
        (("--window", "8", "--modes", "65"), ["'--modes'", "65", "64 cells"]),
        (("--window", "4x3", "--modes", "13"), ["'--modes'", "13", "12 cells"]),
        (("--bbox", "a", "b", "c", "d"), ["'--bbox'", "'a' is not a valid float"]),
        (("--crs", "nonsense"), ["'--crs'", "'nonsense'"]),
    ],
)
def test_bad_options(run_cli, orkney_tif, tmp_path, options, expected):
    result = run_cli("simplify-raster", orkney_tif, tmp_path / "d.tif", *options)
    assert_clean_failure(result, *expected, code=2)
    assert list(tmp_path.iterdir()) == []


def test_raster_smaller_than_the_window(run_cli, orkney_tif, tmp_path):
    result = run_cli(
        "simplify-raster",
        orkney_tif,
        tmp_path / "d.tif",
        "--window",
        8,
        "--bbox",
        -3.0,
        58.0,
        -2.8,
        58.2,
        "--plot",
        tmp_path / "d.png",
    )
    assert_clean_failure(
        result, "window = 8 x 8 cells", str(orkney_tif), "3 x 3 cells", code=2
    )
    assert list(tmp_path.iterdir()) == []


def test_bbox_outside_the_raster(run_cli, orkney_tif, tmp_path):
    result = run_cli(
        "simplify-raster", orkney_tif, tmp_path / "d.tif", "--bbox", 20, 10, 21, 11
    )
    assert_clean_failure(result, str(orkney_tif), "does not overlap")
    assert list(tmp_path.iterdir()) == []


def test_missing_input(run_cli, tmp_path):
    result = run_cli("simplify-raster", tmp_path / "gebco.nc", tmp_path / "d.tif")
    assert_clean_failure(result, "gebco.nc", "file not found")
    assert list(tmp_path.iterdir()) == []


def test_input_is_not_a_raster(run_cli, orkney_geojson, tmp_path):
    result = run_cli("simplify-raster", orkney_geojson, tmp_path / "d.tif")
    assert_clean_failure(result, str(orkney_geojson), "not a raster file")
    assert list(tmp_path.iterdir()) == []


def test_unknown_output_format(run_cli, orkney_tif, tmp_path):
    result = run_cli("simplify-raster", orkney_tif, tmp_path / "d.grd")
    assert_clean_failure(result, "d.grd", "unknown raster format", ".nc", ".tif")
    assert list(tmp_path.iterdir()) == []


def test_existing_output_needs_overwrite(run_cli, orkney_tif, tmp_path):
    out = tmp_path / "d.tif"
    out.write_bytes(b"precious")
    result = run_cli("simplify-raster", orkney_tif, out, "--bbox", *BBOX)
    assert_clean_failure(result, str(out), "--overwrite")
    assert out.read_bytes() == b"precious"
    result = run_cli("simplify-raster", orkney_tif, out, "--bbox", *BBOX, "--overwrite")
    assert result.exit_code == 0, result.output
    assert read_raster(out).shape == (21, 21)


def test_missing_crs_needs_the_crs_option(run_cli, tmp_path):
    source = tmp_path / "nocrs.tif"
    values = np.random.default_rng(7).normal(size=(20, 30)).astype("float32")
    with rasterio.open(
        source,
        "w",
        driver="GTiff",
        width=30,
        height=20,
        count=1,
        dtype="float32",
        transform=Affine(100, 0, 500000, 0, -100, 6500000),
    ) as dataset:
        dataset.write(values, 1)
    out = tmp_path / "out.tif"
    result = run_cli("simplify-raster", source, out, "--window", 4, "--modes", 2)
    assert_clean_failure(result, "nocrs.tif", "no CRS", "--crs")
    assert not out.exists()
    result = run_cli(
        "simplify-raster",
        source,
        out,
        "--window",
        4,
        "--modes",
        2,
        "--crs",
        "EPSG:32630",
    )
    assert result.exit_code == 0, result.output
    with rasterio.open(out) as dataset:
        assert dataset.crs.to_epsg() == 32630
        assert dataset.transform == Affine(100, 0, 500000, 0, -100, 6500000)


def test_infinite_cells_are_refused(run_cli, orkney_tif, tmp_path):
    source = read_raster(orkney_tif)
    bad = source.copy()
    bad.values[5, 7] = np.inf
    from coastmesh.io.rasters.raster import write_raster

    write_raster(tmp_path / "inf.tif", bad)
    result = run_cli("simplify-raster", tmp_path / "inf.tif", tmp_path / "out.tif")
    assert_clean_failure(result, "inf.tif", "row 5, column 7", "inf")
    assert not (tmp_path / "out.tif").exists()


def test_help_names_the_units(run_cli):
    result = run_cli("simplify-raster", "--help")
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    assert "--window CELLS Window size in cells" in text
    assert "[default: 8]" in text and "[default: 16; x>=1]" in text
