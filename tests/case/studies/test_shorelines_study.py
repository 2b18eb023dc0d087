"""The shoreline study (paper figure 2): config, outputs, counts and distances."""

from __future__ import annotations

import contextlib
import csv
import itertools
import json
from pathlib import Path

import numpy as np
import pytest
import shapely
from pyproj import CRS, Transformer
from scipy.spatial import cKDTree

from coastmesh.case import read_case
from coastmesh.case.schema import Table
from coastmesh.case.studies.shorelines import (
    ShorelineStudyConfig,
    _distances,
    parse_study,
    run_study,
)
from coastmesh.errors import ConfigError
from coastmesh.io import read_features, write_features

ROOT = Path(__file__).parents[3]
EXAMPLE = ROOT / "examples" / "norway" / "sognefjorden.toml"
# mouth of Sognefjorden, as tests/conftest.py NORWAY_BBOX (repeated: no package import)
BBOX = [4.8, 60.9, 5.6, 61.3]
DETAIL = [4.9, 61.0, 5.2, 61.15]
RECONSTRUCTIONS = [{"window": 50, "modes": 1}, {"window": 20, "modes": 3}]


@contextlib.contextmanager
def quiet(label):
    yield lambda done, total: None


def parse(data: dict) -> ShorelineStudyConfig:
    return parse_study(Table(data, "study", "test.toml"), lambda v, k: Path(v))


def study(path, **extra) -> ShorelineStudyConfig:
    data = {"path": str(path), "reconstructions": RECONSTRUCTIONS} | extra
    return parse(data)


def distinct(rings) -> np.ndarray:
    """Vertices per ring, the closing vertex not counted (as ShorelineReport)."""
    return shapely.get_num_coordinates(rings) - 1


@pytest.fixture(scope="module")
def clipped_run(tmp_path_factory, norway_geojson):
    """The study on the mouth of Sognefjorden, long edges left as they are."""
    folder = tmp_path_factory.mktemp("shorelines")
    config = study(norway_geojson, bbox=BBOX, detail=DETAIL, densify_long_edges=False)
    labels = []

    @contextlib.contextmanager
    def stage(label):
        labels.append(label)
        yield lambda done, total: None

    return run_study(config, folder, stage), folder, labels


# parse_study


def test_parse_defaults_and_names():
    config = parse(
        {
            "path": "coast.gpkg",
            "detail": [4.6, 60.9, 5.6, 61.3],
            "hausdorff_spacing": "0.1 km",
            "reconstructions": [
                {"window": 500, "modes": 1},
                {"window": 100, "modes": 5, "name": "fine"},
            ],
        }
    )
    assert config.path == Path("coast.gpkg")
    assert config.detail == (4.6, 60.9, 5.6, 61.3)
    assert config.bbox is None and config.layer is None
    assert config.densify_long_edges is True
    assert config.hausdorff_spacing == pytest.approx(100.0)
    assert [r.name for r in config.reconstructions] == ["pca_1_500", "fine"]
    assert [(r.window, r.modes) for r in config.reconstructions] == [(500, 1), (100, 5)]
    assert config.reconstructions[1].label == "PCA 5 modes / 100 points"


@pytest.mark.parametrize(
    ("data", "key"),
    [
        ({"colour": "red"}, "study.colour"),
        ({"reconstructions": [{"window": 1, "modes": 1}]}, "reconstructions[0].window"),
        (
            {"reconstructions": [{"window": 5, "modes": 1}, {"window": 5, "modes": 6}]},
            "reconstructions[1].modes",
        ),
        ({"reconstructions": [{"window": 5, "modes": 0}]}, "reconstructions[0].modes"),
        ({"reconstructions": [{"window": 5, "modes": 1, "m": 1}]}, "[0].m"),
        ({"reconstructions": []}, "study.reconstructions"),
        ({"detail": [5, 61, 4, 62]}, "study.detail"),
        ({"hausdorff_spacing": "-1 m"}, "study.hausdorff_spacing"),
        (
            {"reconstructions": [{"window": 5, "modes": 1, "name": "a/b"}]},
            "reconstructions[0].name",
        ),
        (
            {"reconstructions": [{"window": 5, "modes": 1}, {"window": 5, "modes": 1}]},
            "reconstructions[1].name",
        ),
    ],
)
def test_parse_errors_name_the_key(data, key):
    full = {"path": "coast.gpkg", "reconstructions": [{"window": 5, "modes": 1}]}
    with pytest.raises(ConfigError, match=r"^test\.toml: ") as info:
        parse(full | data)
    assert key in str(info.value)


def test_parse_needs_a_path():
    with pytest.raises(ConfigError, match=r"study\.path: is missing"):
        parse({"reconstructions": RECONSTRUCTIONS})


def test_example_case_parses():
    case = read_case(EXAMPLE)
    assert case.kind == "shorelines" and case.name == "sognefjorden"
    assert case.output == ROOT / "out" / "examples" / "sognefjorden"
    config = case.study
    assert isinstance(config, ShorelineStudyConfig)
    assert config.path.is_file()
    assert [(r.window, r.modes) for r in config.reconstructions] == [
        (500, 1),
        (100, 1),
        (100, 5),
    ]
    minx, miny, maxx, maxy = config.detail
    assert 4.4 <= minx < 5.0 and 5.2 < maxx <= 5.7
    assert 60.8 <= miny < 61.05 and 61.15 < maxy <= 61.4


# run_study


def test_run_writes_every_file(clipped_run):
    result, folder, labels = clipped_run
    expected = {
        "pca_1_50.gpkg",
        "pca_3_20.gpkg",
        "figures/overlay_whole.png",
        "figures/overlay_detail.png",
        "table.md",
        "table.csv",
        "study.json",
    }
    assert set(result.files) == expected
    for name in expected:
        assert (folder / name).stat().st_size > 0, name
    for name in ("overlay_whole", "overlay_detail"):
        assert (folder / "figures" / f"{name}.png").read_bytes()[:4] == b"\x89PNG"
    assert "pca_1_50: PCA 1 mode / 50 points" in labels
    assert "pca_3_20: distances" in labels
    assert result.seconds > 0
    assert "pca_1_50" in result.summary() and "\n" not in result.summary()


def test_tables_agree(clipped_run):
    result, folder, _ = clipped_run
    with (folder / "table.csv").open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert [r["name"] for r in rows] == ["pca_1_50", "pca_3_20"]
    assert [int(r["points_out"]) for r in rows] == [
        r["points_out"] for r in result.rows
    ]
    report = json.loads((folder / "study.json").read_text())
    assert report["rows"] == [dict(r) for r in result.rows]
    assert report["metric_crs"] == "EPSG:32631"
    markdown = (folder / "table.md").read_text().splitlines()
    assert len(markdown) == 2 + len(result.rows)
    assert "Hausdorff (m)" in markdown[0] and "rings dropped" in markdown[0]
    assert markdown[2].startswith("| PCA 1 mode / 50 points |")


def test_counts_against_the_input(clipped_run, norway_geojson):
    result, folder, _ = clipped_run
    # independent count: GEOS clip of every ring in the box, closing vertex off
    raw = read_features(norway_geojson).geometry
    clipped = shapely.clip_by_rect(raw, *BBOX)
    clipped = clipped[~shapely.is_empty(clipped)]
    rings = shapely.get_rings(shapely.get_parts(clipped))
    points = distinct(rings)
    for row in result.rows:
        assert row["points_in"] == points.sum()
        assert row["points_added"] == 0
        assert row["rings_in"] == len(rings)
        assert row["rings_dropped"] == int((points < row["window"]).sum())
        assert 0 < row["points_out"] < row["points_in"]
        written = read_features(folder / f"{row['name']}.gpkg")
        assert len(written) == row["features_in"] - row["features_dropped"]
        assert written.crs.to_epsg() == 4326
        assert shapely.is_valid(written.geometry).all()
        kept = distinct(shapely.get_rings(shapely.get_parts(written.geometry)))
        assert (kept >= 3).all()
    assert result.rows[0]["rings_dropped"] > result.rows[1]["rings_dropped"] > 0


def test_distances_shrink_with_more_detail(clipped_run):
    result, _, _ = clipped_run
    coarse, fine = result.rows
    assert fine["hausdorff_m"] < coarse["hausdorff_m"]
    assert fine["mean_distance_m"] < coarse["mean_distance_m"]
    for row in result.rows:
        assert 0 < row["mean_distance_m"] < row["hausdorff_m"] < 20_000
        assert BBOX[0] <= row["hausdorff_lon"] <= BBOX[2]
        assert BBOX[1] <= row["hausdorff_lat"] <= BBOX[3]


def test_long_edges_are_densified_but_not_counted_as_input(tmp_path, norway_geojson):
    config = study(norway_geojson, bbox=BBOX, reconstructions=[RECONSTRUCTIONS[0]])
    (row,) = run_study(config, tmp_path, quiet).rows
    raw = read_features(norway_geojson, bbox=BBOX).geometry
    assert row["points_in"] == distinct(shapely.get_rings(shapely.get_parts(raw))).sum()
    assert row["points_added"] > 100  # the box cuts the mainland: edges of ~40 km


def _densify(ring: np.ndarray, step: float) -> np.ndarray:
    """Points along a closed (n, 2) ring, at most ``step`` apart (slow, obvious)."""
    out = []
    for a, b in itertools.pairwise(ring):
        count = max(int(np.ceil(np.hypot(*(b - a)) / step)), 1)
        out += [a + (b - a) * t for t in np.arange(count) / count]
    return np.array(out)


def test_hausdorff_against_brute_force(tmp_path, norway_geojson):
    coast = read_features(norway_geojson, bbox=BBOX)
    (k,) = np.flatnonzero(coast.fields["id"] == "3745")  # GSHHG id: 208 points
    (islet,) = np.flatnonzero(coast.fields["id"] == "69214")  # 21 points, ~2 km off
    island = coast.take([k])
    source = tmp_path / "island.geojson"
    write_features(source, coast.take([k, islet]))
    folder = tmp_path / "out"
    folder.mkdir()
    config = study(
        source,
        reconstructions=[{"window": 40, "modes": 1}],
        hausdorff_spacing="5 m",
        densify_long_edges=False,
    )
    (row,) = run_study(config, folder, quiet).rows
    rebuilt = read_features(folder / "pca_1_40.gpkg").geometry
    # the islet is shorter than the window: dropped, and left out of the distances
    assert (row["rings_in"], row["rings_dropped"], len(rebuilt)) == (2, 1, 1)

    # the island is at 5 E: UTM zone 31 north
    assert 0 < shapely.centroid(island.geometry[0]).x < 6
    to_utm = Transformer.from_crs("EPSG:4326", "EPSG:32631", always_xy=True)

    def ring_metres(polygon) -> np.ndarray:
        xy = shapely.get_coordinates(polygon.exterior)
        return np.column_stack(to_utm.transform(xy[:, 0], xy[:, 1]))

    a = ring_metres(island.geometry[0])
    b = ring_metres(rebuilt[0])
    dense_a, dense_b = _densify(a, 0.5), _densify(b, 0.5)
    ab = cKDTree(dense_b).query(dense_a)[0].max()
    ba = cKDTree(dense_a).query(dense_b)[0].max()
    brute = max(ab, ba)
    assert brute > 50  # a real departure, not a rounding error
    # the study's points are 5 m apart: exact to 2.5 m, plus 0.5 m here, plus rounding
    assert row["hausdorff_m"] == pytest.approx(brute, abs=3.2)
    geos = shapely.hausdorff_distance(
        shapely.linestrings(a), shapely.linestrings(b), densify=0.02
    )
    assert row["hausdorff_m"] == pytest.approx(geos, abs=3.2)
    mean = cKDTree(dense_a).query(b[:-1])[0].mean()
    assert row["mean_distance_m"] == pytest.approx(mean, abs=0.5)


UTM31 = CRS.from_epsg(32631)


def rings(*coords):
    return np.array([shapely.linestrings(c + c[:1]) for c in coords], dtype=object)


def test_hausdorff_is_symmetric():
    """A narrow spike 300 m out of a square: one direction sees it, the other not."""
    square = [(0, 0), (1000, 0), (1000, 1000), (0, 1000)]
    spiked = [(0, 0), (1000, 0), (1000, 1000), (510, 1000), (500, 1300), (490, 1000)]
    spiked.append((0, 1000))
    for a, b in ((square, spiked), (spiked, square)):
        d = _distances(rings(a), rings(b), 5.0, UTM31, UTM31)
        assert d["hausdorff_m"] == pytest.approx(300.0, abs=0.1)
        assert (d["hausdorff_lon"], d["hausdorff_lat"]) == pytest.approx((500, 1300))
    # mean over the spiked ring's 7 vertices: the tip is 300 m off, the rest on
    d = _distances(rings(square), rings(spiked), 5.0, UTM31, UTM31)
    assert d["mean_distance_m"] == pytest.approx(300 / 7, abs=0.1)


def test_hausdorff_sees_between_vertices():
    """A quadrilateral and a bow-tie on its corners: every vertex lies on the other.

    Vertices alone give 0 m; the distance is reached inside the bow-tie's edges.
    """
    quad = [(0, 0), (1000, 0), (1000, 1000), (0, 400)]
    bowtie = [(0, 0), (1000, 1000), (1000, 0), (0, 400)]
    a, b = rings(quad), rings(bowtie)
    assert shapely.hausdorff_distance(a[0], b[0]) == 0.0
    dense_a = _densify(shapely.get_coordinates(a[0]), 0.25)
    dense_b = _densify(shapely.get_coordinates(b[0]), 0.25)
    brute = max(
        cKDTree(dense_b).query(dense_a)[0].max(),
        cKDTree(dense_a).query(dense_b)[0].max(),
    )
    assert brute > 200
    for original, rebuilt in ((a, b), (b, a)):
        d = _distances(original, rebuilt, 5.0, UTM31, UTM31)
        assert d["hausdorff_m"] == pytest.approx(brute, abs=2.5 + 0.25 + 0.05)
        assert d["mean_distance_m"] == 0.0


def test_detail_box_outside_the_data_is_an_error(tmp_path, norway_geojson):
    config = study(norway_geojson, bbox=BBOX, detail=[10.0, 50.0, 11.0, 51.0])
    with pytest.raises(ConfigError, match=r"study\.detail"):
        run_study(config, tmp_path, quiet)
    assert not any(tmp_path.iterdir())
