"""Reading and writing vector files with pyogrio's raw (vectorised) interface."""

from __future__ import annotations

import numpy as np
import pyogrio
import pytest
import shapely
from conftest import ORKNEY_BBOX

from coastmesh.commands import simplify_shoreline_file
from coastmesh.errors import ConfigError, FormatError, InputDataError
from coastmesh.geometry import check_coordinates
from coastmesh.io.vectors.vector import read_features, write_features
from coastmesh.types import Features

ORKNEY_FIELDS = [
    "id",
    "part",
    "level",
    "npoints",
    "clipped",
    "area_km2",
    "riverlake",
    "npoints_orig",
]


@pytest.fixture(scope="module")
def orkney_clip(orkney_geojson):
    return read_features(orkney_geojson, bbox=ORKNEY_BBOX)


def assert_same_features(
    a: Features, b: Features, *, exact: bool = True, name_length: int | None = None
) -> None:
    assert len(a) == len(b)
    if exact:
        assert shapely.equals_exact(a.geometry, b.geometry, tolerance=1e-9).all()
    else:  # ring orientation or single/multi may differ, the shapes may not
        assert shapely.equals(a.geometry, b.geometry).all()
    assert a.crs == b.crs
    assert [n[:name_length] for n in a.fields] == list(b.fields)
    for mine, theirs in zip(a.fields.values(), b.fields.values(), strict=True):
        np.testing.assert_array_equal(_blank(mine), _blank(theirs))


def _blank(values: np.ndarray) -> np.ndarray:
    """Empty strings as None: shapefiles (dBase) cannot tell them apart."""
    if values.dtype != object:
        return values
    return np.array([None if v == "" else v for v in values], dtype=object)


def test_read_whole_file(orkney_geojson):
    coast = read_features(orkney_geojson)
    assert len(coast) == 84
    assert coast.crs.to_epsg() == 4326
    assert list(coast.fields) == ORKNEY_FIELDS
    assert coast.layer == "orkney_gshhg_f"
    assert coast.path == str(orkney_geojson)
    np.testing.assert_array_equal(coast.fids, np.arange(84))
    # the npoints attribute counts the stored vertices of each feature
    np.testing.assert_array_equal(
        coast.fields["npoints"], shapely.get_num_coordinates(coast.geometry)
    )
    assert shapely.get_num_coordinates(coast.geometry).sum() == 5907


def test_bbox_clips_and_keeps_the_real_fids(orkney_geojson, orkney_clip):
    whole = read_features(orkney_geojson)
    assert 0 < len(orkney_clip) < len(whole)
    minx, miny, maxx, maxy = shapely.total_bounds(orkney_clip.geometry)
    box = ORKNEY_BBOX
    assert box[0] - 1e-9 <= minx and maxx <= box[2] + 1e-9
    assert box[1] - 1e-9 <= miny and maxy <= box[3] + 1e-9
    assert set(orkney_clip.fids) <= set(whole.fids)
    # fields stay aligned with the geometries: the ids match the source features
    by_fid = dict(zip(whole.fids, whole.fields["id"], strict=True))
    assert [by_fid[f] for f in orkney_clip.fids] == list(orkney_clip.fields["id"])
    assert shapely.is_valid(orkney_clip.geometry).all()


@pytest.mark.filterwarnings("ignore:Normalized/laundered field name")
@pytest.mark.parametrize("suffix", [".gpkg", ".geojson", ".shp", ".fgb"])
def test_round_trip(tmp_path, write_read, orkney_clip, suffix):
    path = tmp_path / f"coast{suffix}"
    back = write_read(
        path, write_features, read_features, orkney_clip, assert_same_features
    )
    # GeoPackages declare MultiPolygon here (a clipped island may split), and
    # shapefiles store outer rings clockwise and cut field names to 10 characters
    assert_same_features(
        orkney_clip,
        back,
        exact=suffix not in {".gpkg", ".shp"},
        name_length=10 if suffix == ".shp" else None,
    )
    assert back.crs.to_epsg() == 4326
    hidden = [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert hidden == []


def test_round_trip_lines_and_holes(tmp_path, write_read):
    ring = shapely.Point(0, 0).buffer(10.0)
    holed = ring.difference(shapely.box(-2, -2, 2, 2))
    lines = shapely.MultiLineString([[(0, 0), (1, 1), (2, 0)], [(5, 5), (6, 6)]])
    features = Features(
        geometry=[holed, shapely.LineString([(0, 0), (3, 4)]), lines],
        crs="EPSG:32630",
        fields={"name": ["holed", "line", "lines"]},
        fids=[10, 11, 12],
        path="<memory>",
    )
    back = write_read(
        tmp_path / "mixed.gpkg",
        write_features,
        read_features,
        features,
        assert_same_features,
    )
    assert back.crs.to_epsg() == 32630
    assert len(back.geometry[0].interiors) == 1
    assert shapely.equals(back.geometry, features.geometry).all()


def test_mixed_polygons_become_multipolygons_in_a_geopackage(tmp_path):
    features = Features(
        geometry=[
            shapely.box(0, 0, 1, 1),
            shapely.MultiPolygon([shapely.box(2, 2, 3, 3)]),
        ],
        crs="EPSG:4326",
        fields={},
        fids=[0, 1],
        path="<memory>",
    )
    write_features(tmp_path / "m.gpkg", features)
    assert pyogrio.read_info(tmp_path / "m.gpkg")["geometry_type"] == "MultiPolygon"
    assert shapely.equals(
        read_features(tmp_path / "m.gpkg").geometry, features.geometry
    ).all()


def test_metadata_and_layer_name_are_stored(tmp_path, orkney_clip):
    path = tmp_path / "coast.gpkg"
    write_features(path, orkney_clip, metadata={"coastmesh_window": "100"})
    info = pyogrio.read_info(path)
    assert info["layer_name"] == "coast"
    assert info["dataset_metadata"] == {"coastmesh_window": "100"}


def test_write_refuses_existing_file(tmp_path, orkney_clip):
    path = tmp_path / "coast.gpkg"
    write_features(path, orkney_clip)
    stamp = path.stat().st_mtime_ns
    with pytest.raises(FileExistsError, match="--overwrite"):
        write_features(path, orkney_clip)
    assert path.stat().st_mtime_ns == stamp
    write_features(path, orkney_clip.take([0]), overwrite=True)
    assert len(read_features(path)) == 1


def test_write_unknown_extension_lists_the_known_ones(tmp_path, orkney_clip):
    with pytest.raises(FormatError, match=r"'\.kml'.*\.gpkg.*\.shp"):
        write_features(tmp_path / "coast.kml", orkney_clip)
    assert list(tmp_path.iterdir()) == []


def test_write_what_the_driver_cannot_hold(tmp_path):
    features = Features(
        geometry=[shapely.box(0, 0, 1, 1), shapely.LineString([(0, 0), (1, 1)])],
        crs="EPSG:4326",
        fields={},
        fids=[0, 1],
        path="<memory>",
    )
    with pytest.raises(FormatError, match="ESRI Shapefile"):
        write_features(tmp_path / "mixed.shp", features)
    assert list(tmp_path.iterdir()) == []


def test_missing_file(tmp_path):
    with pytest.raises(InputDataError, match="file not found") as info:
        read_features(tmp_path / "nothing.gpkg")
    assert info.value.path == str(tmp_path / "nothing.gpkg")


@pytest.mark.parametrize("name", ["etopo1_0.1deg_orkney_wide.tif", "README.md"])
def test_not_a_vector_file(tmp_path, name):
    from coastmesh.data import path as data_path

    path = data_path(name) if name.endswith(".tif") else tmp_path / name
    if not path.exists():
        path.write_text("# not vector data\n")
    with pytest.raises(FormatError, match="not a vector file") as info:
        read_features(path)
    assert str(path) in str(info.value)


def test_unknown_layer_lists_the_layers(orkney_geojson):
    with pytest.raises(InputDataError, match=r"no layer 'land'.*'orkney_gshhg_f'"):
        read_features(orkney_geojson, layer="land")


def test_several_layers_need_a_choice(tmp_path, orkney_clip):
    path = tmp_path / "two.gpkg"
    write_features(path, orkney_clip, layer="land")
    wkb = shapely.to_wkb(orkney_clip.geometry[:1])
    pyogrio.raw.write(
        path,
        wkb,
        [],
        [],
        layer="sea",
        driver="GPKG",
        geometry_type="Polygon",
        crs="EPSG:4326",
        append=True,
    )
    with pytest.raises(InputDataError, match=r"2 layers.*--layer"):
        read_features(path)
    assert len(read_features(path, layer="sea")) == 1
    assert read_features(path, layer="land").layer == "land"


def test_empty_layer(tmp_path):
    path = tmp_path / "empty.gpkg"
    pyogrio.raw.write(
        path,
        np.array([], dtype=object),
        [],
        [],
        driver="GPKG",
        geometry_type="Polygon",
        crs="EPSG:4326",
    )
    with pytest.raises(InputDataError, match="layer 'empty': no features"):
        read_features(path)


def test_layer_without_geometry(tmp_path):
    table = tmp_path / "table.csv"
    table.write_text("name,depth\nA,10\n")
    with pytest.raises(
        InputDataError, match=r"layer 'table': the layer has no geometry"
    ):
        read_features(table)


def test_nothing_in_bbox(orkney_geojson):
    with pytest.raises(InputDataError, match=r"no features in bbox \(10\.0, 10\.0"):
        read_features(orkney_geojson, bbox=(10, 10, 11, 11))


@pytest.mark.parametrize(
    "bbox", [(1, 2, 3), (0, 0, -1, 1), (0, 1, 1, 0), (0, 0, np.nan, 1), ("a", 0, 1, 1)]
)
def test_bad_bbox(orkney_geojson, bbox):
    with pytest.raises(ConfigError, match="bbox"):
        read_features(orkney_geojson, bbox=bbox)


def test_file_without_crs(tmp_path, make_gpkg):
    path = make_gpkg(tmp_path / "nocrs.gpkg", [shapely.box(0, 0, 1, 1)], crs=None)
    assert read_features(path).crs is None


def test_nan_vertex_is_named(tmp_path, make_gpkg):
    with np.errstate(invalid="ignore"):
        bad = shapely.polygons([(0, 0), (1, 0), (np.nan, 1), (0, 0)])
    path = make_gpkg(
        tmp_path / "coast.gpkg",
        [shapely.box(0, 0, 1, 1), shapely.box(2, 2, 3, 3), bad],
        crs="EPSG:4326",
    )
    with pytest.raises(InputDataError) as info:
        simplify_shoreline_file(path, tmp_path / "out.gpkg", window=2, modes=1)
    assert not (tmp_path / "out.gpkg").exists()
    message = str(info.value)
    assert message.startswith(f"{path}, layer 'coast', feature 3: vertex 2 has a NaN")
    assert info.value.feature == 3  # GeoPackage fids start at 1


def test_finite_features_pass(orkney_clip):
    assert check_coordinates(orkney_clip.geometry) is None
