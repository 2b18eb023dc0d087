"""``coastmesh simplify-shoreline`` end to end, through click."""

from __future__ import annotations

import re

import numpy as np
import pyogrio
import pytest
import shapely
from conftest import ORKNEY_BBOX, assert_clean_failure

from coastmesh import __version__
from coastmesh.errors import InputDataError
from coastmesh.io.vectors.vector import read_features

BBOX = [str(v) for v in ORKNEY_BBOX]


def test_simplify_a_clip(run_cli, orkney_geojson, tmp_path, folder_listing):
    out = tmp_path / "coast.gpkg"
    result = run_cli(
        "simplify-shoreline",
        orkney_geojson,
        out,
        "--window",
        20,
        "--modes",
        2,
        "--bbox",
        *BBOX,
    )
    assert result.exit_code == 0, result.output
    summary = result.stdout.strip().splitlines()
    assert len(summary) == 1
    assert re.search(r"\d+ contours in, \d+ dropped", summary[0])
    assert re.search(r"\d+ -> \d+ points", summary[0])
    assert re.search(r"\d+\.\d s; wrote .*coast\.gpkg", summary[0])
    assert folder_listing(tmp_path) == ["coast.gpkg"]

    source = read_features(orkney_geojson, bbox=ORKNEY_BBOX)
    coast = read_features(out)
    assert coast.crs.to_epsg() == 4326
    assert list(coast.fields) == list(source.fields)
    assert 0 < len(coast) <= len(source)
    assert shapely.is_valid(coast.geometry).all()
    # the attributes travel with their features
    assert set(coast.fields["id"]) <= set(source.fields["id"])
    points_in = shapely.get_num_coordinates(source.geometry).sum()
    assert shapely.get_num_coordinates(coast.geometry).sum() < points_in
    notes = pyogrio.read_info(out)["dataset_metadata"]
    assert notes["coastmesh_version"] == __version__
    assert notes["coastmesh_window"] == "20"
    assert notes["coastmesh_modes"] == "2"
    assert "simplify-shoreline" in notes["history"]


@pytest.mark.parametrize("suffix", [".geojson", ".shp", ".fgb"])
def test_output_formats(run_cli, orkney_geojson, tmp_path, suffix):
    out = tmp_path / f"coast{suffix}"
    result = run_cli(
        "simplify-shoreline", orkney_geojson, out, "--window", 20, "--bbox", *BBOX
    )
    assert result.exit_code == 0, result.output
    coast = read_features(out)
    assert coast.crs.to_epsg() == 4326
    assert len(coast) > 0


def test_plot(run_cli, orkney_geojson, tmp_path, folder_listing):
    result = run_cli(
        "simplify-shoreline",
        orkney_geojson,
        tmp_path / "coast.gpkg",
        "--window",
        20,
        "--bbox",
        *BBOX,
        "--plot",
        tmp_path / "coast.png",
    )
    assert result.exit_code == 0, result.output
    assert folder_listing(tmp_path) == ["coast.gpkg", "coast.png"]
    assert (tmp_path / "coast.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_lines_and_holes(run_cli, tmp_path, make_gpkg):
    circle = shapely.Point(0, 0).buffer(10.0, quad_segs=64)  # 256 points
    hole = shapely.Point(0, 0).buffer(4.0, quad_segs=32)  # 128 points
    holed = shapely.Polygon(circle.exterior, [hole.exterior])
    angle = np.linspace(0, np.pi, 200)
    line = shapely.LineString(np.c_[30 + 10 * np.cos(angle), 10 * np.sin(angle)])
    source = make_gpkg(
        tmp_path / "shapes.gpkg",
        [holed, line],
        crs="EPSG:32630",
        name=["lake", "river"],
    )
    out = tmp_path / "out.gpkg"
    result = run_cli("simplify-shoreline", source, out, "--window", 50, "--modes", 1)
    assert result.exit_code == 0, result.output
    shapes = read_features(out)
    assert shapes.crs.to_epsg() == 32630
    assert shapes.fields["name"].tolist() == ["lake", "river"]
    lake, river = shapes.geometry
    assert lake.geom_type == "Polygon" and len(lake.interiors) == 1
    assert river.geom_type == "LineString"
    assert lake.area == pytest.approx(holed.area, rel=0.05)


def test_everything_dropped_warns(run_cli, tmp_path, make_gpkg):
    source = make_gpkg(tmp_path / "islets.gpkg", [shapely.box(0, 0, 1, 1)])
    result = run_cli(
        "simplify-shoreline", source, tmp_path / "out.gpkg", "--window", 10
    )
    assert result.exit_code == 0, result.output
    assert "WARNING: every feature of" in result.stderr
    assert "fewer than window = 10 points" in result.stderr
    assert pyogrio.read_info(tmp_path / "out.gpkg")["features"] == 0


def test_layer_option(run_cli, orkney_geojson, tmp_path):
    result = run_cli(
        "simplify-shoreline",
        orkney_geojson,
        tmp_path / "c.gpkg",
        "--window",
        20,
        "--layer",
        "orkney_gshhg_f",
        "--bbox",
        *BBOX,
    )
    assert result.exit_code == 0, result.output
    result = run_cli(
        "simplify-shoreline", orkney_geojson, tmp_path / "d.gpkg", "--layer", "land"
    )
    assert_clean_failure(result, "no layer 'land'", "'orkney_gshhg_f'")
    assert not (tmp_path / "d.gpkg").exists()


def test_existing_output_needs_overwrite(run_cli, orkney_geojson, tmp_path):
    out = tmp_path / "coast.gpkg"
    out.write_bytes(b"precious")
    args = ("simplify-shoreline", orkney_geojson, out, "--window", 20, "--bbox", *BBOX)
    result = run_cli(*args)
    assert_clean_failure(result, str(out), "--overwrite")
    assert out.read_bytes() == b"precious"
    result = run_cli(*args, "--overwrite")
    assert result.exit_code == 0, result.output
    assert len(read_features(out)) > 0


def test_existing_plot_needs_overwrite(run_cli, orkney_geojson, tmp_path):
    (tmp_path / "coast.png").write_bytes(b"precious")
    result = run_cli(
        "simplify-shoreline",
        orkney_geojson,
        tmp_path / "coast.gpkg",
        "--plot",
        tmp_path / "coast.png",
    )
    assert_clean_failure(result, "coast.png", "--overwrite")
    assert not (tmp_path / "coast.gpkg").exists()
    assert (tmp_path / "coast.png").read_bytes() == b"precious"


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        (("--window", "1"), ["'--window'", "1 is not in the range"]),
        (("--window", "ten"), ["'--window'", "'ten'"]),
        (("--modes", "0"), ["'--modes'", "0 is not in the range"]),
        (("--window", "10", "--modes", "11"), ["'--modes'", "11", "--window (10)"]),
        (("--bbox", "1", "2", "3"), ["'--bbox' requires 4 arguments"]),
        (("--bbox", "-2", "59", "-3", "60"), ["'--bbox'", "minx < maxx"]),
        (("--bbox", "-2", "59", "nan", "60"), ["'--bbox'", "finite"]),
        (("--crs", "EPSG:99999"), ["'--crs'", "'EPSG:99999'"]),
    ],
)
def test_bad_options(run_cli, orkney_geojson, tmp_path, options, expected):
    result = run_cli(
        "simplify-shoreline", orkney_geojson, tmp_path / "c.gpkg", *options
    )
    assert_clean_failure(result, *expected, code=2)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("source", "out", "options", "expected"),
    [
        ("nothing.shp", "c.gpkg", (), ("nothing.shp", "file not found")),
        ("orkney_tif", "c.gpkg", (), ("{source}", "not a vector file")),
        ("orkney_geojson", "c.kml", (), ("c.kml", "unknown vector format", ".gpkg")),
        ("orkney_geojson", "c.png", (), ("c.png", "unknown vector format", ".shp")),
        ("orkney_geojson", "c", (), ("unknown vector format",)),
        (
            "orkney_geojson",
            "c.gpkg",
            ("--plot", "{tmp}/c.bmp"),
            ("c.bmp", "unknown plot format", ".png"),
        ),
        (
            "orkney_geojson",
            "c.gpkg",
            ("--bbox", "10", "10", "11", "11"),
            ("{source}", "no features in bbox"),
        ),
    ],
)
def test_bad_inputs_fail_cleanly(
    run_cli, request, tmp_path, source, out, options, expected
):
    """A clear message naming the file or option, exit 1, and nothing written."""
    path = (
        request.getfixturevalue(source)
        if source.startswith("orkney")
        else tmp_path / source
    )
    fill = {"source": str(path), "tmp": str(tmp_path)}
    options = [o.format(**fill) for o in options]
    result = run_cli("simplify-shoreline", path, tmp_path / out, *options)
    assert_clean_failure(result, *(e.format(**fill) for e in expected))
    assert list(tmp_path.iterdir()) == []


def test_empty_layer(run_cli, tmp_path):
    empty = tmp_path / "empty.gpkg"
    pyogrio.raw.write(
        empty,
        np.array([], dtype=object),
        [],
        [],
        driver="GPKG",
        geometry_type="Polygon",
        crs="EPSG:4326",
    )
    result = run_cli("simplify-shoreline", empty, tmp_path / "c.gpkg")
    assert_clean_failure(result, "empty.gpkg", "layer 'empty'", "no features")
    assert not (tmp_path / "c.gpkg").exists()


def test_nan_coordinate(run_cli, tmp_path, make_gpkg):
    with np.errstate(invalid="ignore"):
        bad = shapely.polygons([(0, 0), (1, 0), (np.nan, 1), (0, 0)])
    source = make_gpkg(tmp_path / "coast.gpkg", [shapely.box(0, 0, 1, 1), bad])
    result = run_cli("simplify-shoreline", source, tmp_path / "out.gpkg", "--window", 2)
    assert_clean_failure(
        result, "coast.gpkg, layer 'coast', feature 2: vertex 2 has a NaN coordinate"
    )
    assert not (tmp_path / "out.gpkg").exists()


def test_points_are_refused(run_cli, tmp_path, make_gpkg):
    source = make_gpkg(
        tmp_path / "pts.gpkg", [shapely.box(0, 0, 1, 1), shapely.Point(0, 0)]
    )
    result = run_cli("simplify-shoreline", source, tmp_path / "out.gpkg", "--window", 2)
    assert_clean_failure(result, "pts.gpkg, layer 'pts', feature 2: Point")
    assert not (tmp_path / "out.gpkg").exists()


def test_missing_crs_needs_the_crs_option(run_cli, tmp_path, make_gpkg):
    ring = shapely.Point(0, 0).buffer(1.0)
    source = make_gpkg(tmp_path / "nocrs.gpkg", [ring], crs=None)
    out = tmp_path / "out.gpkg"
    result = run_cli("simplify-shoreline", source, out, "--window", 10)
    assert_clean_failure(result, "nocrs.gpkg", "no CRS", "--crs")
    assert not out.exists()
    result = run_cli(
        "simplify-shoreline", source, out, "--window", 10, "--crs", "EPSG:32631"
    )
    assert result.exit_code == 0, result.output
    assert read_features(out).crs.to_epsg() == 32631


def test_crs_option_cannot_contradict_the_file(run_cli, orkney_geojson, tmp_path):
    result = run_cli(
        "simplify-shoreline", orkney_geojson, tmp_path / "c.gpkg", "--crs", "EPSG:32630"
    )
    assert_clean_failure(result, "EPSG:32630", "EPSG:4326", code=2)
    assert list(tmp_path.iterdir()) == []


def test_feature_errors_name_the_real_fid(
    run_cli, orkney_geojson, tmp_path, monkeypatch
):
    import coastmesh.commands.simplify_shoreline

    def broken(geometries, window, modes, *, progress=None):
        raise InputDataError("vertex 3 has a non-finite coordinate", feature=1)

    monkeypatch.setattr(
        coastmesh.commands.simplify_shoreline, "simplify_shorelines", broken
    )
    result = run_cli(
        "simplify-shoreline", orkney_geojson, tmp_path / "c.gpkg", "--bbox", *BBOX
    )
    second_fid = read_features(orkney_geojson, bbox=ORKNEY_BBOX).fids[1]
    assert_clean_failure(
        result,
        f"layer 'orkney_gshhg_f', feature {second_fid}: vertex 3 has a non-finite",
    )
    assert list(tmp_path.iterdir()) == []


def test_a_failing_plot_leaves_no_output(
    run_cli, orkney_geojson, tmp_path, monkeypatch
):
    import coastmesh.plot

    def full_disk(figure, path, **options):
        path.write_bytes(b"half a png")
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(coastmesh.plot, "save_figure", full_disk)
    result = run_cli(
        "simplify-shoreline",
        orkney_geojson,
        tmp_path / "c.gpkg",
        "--window",
        20,
        "--bbox",
        *BBOX,
        "--plot",
        tmp_path / "c.png",
    )
    assert_clean_failure(result, "c.png", "No space left on device")
    assert list(tmp_path.iterdir()) == []


def test_help_names_the_units(run_cli):
    result = run_cli("simplify-shoreline", "--help")
    assert result.exit_code == 0
    text = " ".join(result.output.split())
    assert "in points (vertices)" in text
    assert "--overwrite" in text and "--bbox MINX MINY MAXX MAXY" in text
    assert "--window POINTS" in text and "[default: 100; x>=2]" in text


def test_quiet_and_verbose(run_cli, orkney_geojson, tmp_path):
    args = ("simplify-shoreline", orkney_geojson)
    quiet = run_cli("-q", *args, tmp_path / "q.gpkg", "--window", 20, "--bbox", *BBOX)
    assert quiet.exit_code == 0 and quiet.output == ""
    loud = run_cli("-v", *args, tmp_path / "v.gpkg", "--window", 20, "--bbox", *BBOX)
    assert loud.exit_code == 0
    assert "coastmesh: INFO: read" in loud.stderr
    assert f"INFO: wrote {tmp_path / 'v.gpkg'}" in loud.stderr
    assert "contours in" in loud.stdout


def test_logging_is_restored_after_a_command(run_cli, orkney_geojson, tmp_path):
    import logging

    logger = logging.getLogger("coastmesh")
    before = (logger.level, list(logger.handlers), logger.propagate)
    run_cli("-vv", "simplify-shoreline", orkney_geojson, tmp_path / "nothing" / "x.kml")
    assert (logger.level, list(logger.handlers), logger.propagate) == before
