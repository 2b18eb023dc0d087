"""Whole runs through the Python API (the CLI calls these)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
from conftest import ORKNEY_BBOX, ORKNEY_RASTER_BBOX

from coastmesh.commands import (
    RasterReport,
    simplify_raster_file,
    simplify_shoreline_file,
)
from coastmesh.errors import ConfigError
from coastmesh.io.rasters.raster import read_raster
from coastmesh.io.vectors.vector import read_features


def test_shoreline_report_matches_the_output(orkney_geojson, tmp_path):
    calls = []
    report = simplify_shoreline_file(
        orkney_geojson,
        tmp_path / "coast.gpkg",
        window=20,
        modes=1,
        bbox=ORKNEY_BBOX,
        progress=lambda done, total: calls.append((done, total)),
    )
    source = read_features(orkney_geojson, bbox=ORKNEY_BBOX)
    coast = read_features(tmp_path / "coast.gpkg")
    assert report.features_in == len(source)
    assert len(coast) == report.features_in - report.features_dropped
    assert calls and calls[-1][0] == calls[-1][1]
    assert all(b >= a for (a, _), (b, _) in itertools.pairwise(calls))
    rings = (
        shapely.get_num_interior_rings(coast.geometry).sum()
        + shapely.get_num_geometries(coast.geometry).sum()
    )
    assert rings >= report.contours_in - report.contours_dropped - report.repaired


@pytest.mark.parametrize(
    ("window", "modes", "message"),
    [(1, 1, "window = 1"), (10, 11, "modes = 11"), (10, 0, "modes = 0")],
)
def test_shoreline_parameters_are_checked_first(tmp_path, window, modes, message):
    # the input does not exist: the parameters fail before it is opened
    with pytest.raises(ConfigError, match=message):
        simplify_shoreline_file(
            tmp_path / "missing.gpkg", tmp_path / "c.gpkg", window=window, modes=modes
        )


def test_raster_report(orkney_tif, tmp_path):
    calls = []
    report = simplify_raster_file(
        orkney_tif,
        tmp_path / "d.tif",
        window=(6, 4),
        modes=3,
        bbox=ORKNEY_RASTER_BBOX,
        progress=lambda done, total: calls.append((done, total)),
    )
    assert isinstance(report, RasterReport)
    assert (report.rows, report.columns, report.cells) == (21, 21, 441)
    assert report.cells_missing == 0 and report.cells_covered == 441
    before = read_raster(orkney_tif, bbox=ORKNEY_RASTER_BBOX).values
    after = read_raster(tmp_path / "d.tif").values
    change = np.abs(after - before)
    assert report.max_change == pytest.approx(change.max(), rel=1e-5)
    assert report.rms_change == pytest.approx(np.sqrt((change**2).mean()), rel=1e-5)
    assert report.cells_changed == (change > 0).sum()
    assert calls and calls[-1][0] == calls[-1][1]
    assert "21 x 21 cells" in report.summary()


def test_raster_coverage_with_missing_cells(orkney_tif, tmp_path):
    from coastmesh.io.rasters.raster import write_raster

    holed = read_raster(orkney_tif, bbox=ORKNEY_RASTER_BBOX)
    holed.values[:, 10] = np.nan  # splits the grid into 10 and 10 columns
    holed.attrs["nodata"] = -9999.0
    write_raster(tmp_path / "holed.tif", holed)
    report = simplify_raster_file(
        tmp_path / "holed.tif", tmp_path / "d.tif", window=(4, 11), modes=2
    )
    # no 11-column window avoids the missing column: nothing is covered
    assert report.cells_missing == 21
    assert report.cells_covered == 0 and report.cells_changed == 0
    after = read_raster(tmp_path / "d.tif").values
    np.testing.assert_array_equal(after, holed.values)
