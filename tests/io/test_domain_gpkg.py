"""Writing a domain (polygon, tagged segments, extra layers) to a GeoPackage."""

from __future__ import annotations

import numpy as np
import pyogrio
import pyogrio.raw
import pytest
import shapely
from pyogrio.errors import DataLayerError
from pyproj import CRS

from coastmesh.errors import ConfigError, FormatError, OutputExistsError
from coastmesh.io.vectors.domain_gpkg import segment_lengths, write_domain, write_layers
from coastmesh.types import BoundarySegment, Domain, Features

# Integer corners, axis-aligned sides and one 3-4-5 diagonal: every length is exact.
OUTER = np.array(
    [[0, 0], [4000, 0], [4000, 2000], [3400, 2800], [0, 2800], [0, 0]], float
)
ISLAND = np.array(
    [[1000, 1000], [1000, 2000], [2000, 2000], [2000, 1000], [1000, 1000]], float
)


@pytest.fixture
def domain() -> Domain:
    segments = (
        BoundarySegment(OUTER[0:4], "open", "sea", 2),
        BoundarySegment(OUTER[3:6], "shoreline", "coast", 1),
        BoundarySegment(ISLAND, "shoreline", "island", 4),
    )
    return Domain(
        shapely.Polygon(OUTER, [ISLAND]), segments, crs="EPSG:32630", surface_id=5
    )


@pytest.fixture
def lonlat_square() -> Domain:
    """One degree square at the equator, one segment per side."""
    ring = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)
    names = ["equator", "east", "north", "west"]
    segments = tuple(
        BoundarySegment(ring[i : i + 2], "open" if i == 0 else "shoreline", n, i + 1)
        for i, n in enumerate(names)
    )
    return Domain(shapely.Polygon(ring), segments, crs="EPSG:4326")


def read_layer(path, layer):
    meta, _, wkb, columns = pyogrio.raw.read(path, layer=layer)
    return meta, shapely.from_wkb(wkb), dict(zip(meta["fields"], columns, strict=True))


def test_layers_read_back(tmp_path, domain):
    path = tmp_path / "domain.gpkg"
    write_domain(path, domain)
    assert [p.name for p in tmp_path.iterdir()] == ["domain.gpkg"]
    assert pyogrio.list_layers(path)[:, 0].tolist() == ["domain", "boundaries"]

    meta, polygons, fields = read_layer(path, "domain")
    assert CRS.from_user_input(meta["crs"]) == CRS.from_epsg(32630)
    assert len(polygons) == 1
    assert shapely.equals(polygons[0], domain.polygon)
    assert fields["surface_id"].tolist() == [5]

    meta, lines, fields = read_layer(path, "boundaries")
    assert CRS.from_user_input(meta["crs"]) == CRS.from_epsg(32630)
    assert meta["geometry_type"] == "LineString"
    assert fields["name"].tolist() == ["sea", "coast", "island"]
    assert fields["kind"].tolist() == ["open", "shoreline", "shoreline"]
    assert fields["physical_id"].tolist() == [2, 1, 4]
    for line, segment in zip(lines, domain.segments, strict=True):
        np.testing.assert_array_equal(shapely.get_coordinates(line), segment.coords)


def test_planar_lengths_add_up_to_the_polygon_boundary(tmp_path, domain):
    path = tmp_path / "domain.gpkg"
    write_domain(path, domain)
    _, lines, fields = read_layer(path, "boundaries")
    lengths = fields["length_m"]
    assert lengths.tolist() == [4000.0 + 2000.0 + 1000.0, 3400.0 + 2800.0, 4000.0]
    assert lengths.sum() == domain.polygon.boundary.length == 7000 + 6200 + 4000
    np.testing.assert_array_equal(lengths, shapely.length(lines))


def test_geodesic_lengths_on_wgs84(tmp_path, lonlat_square):
    path = tmp_path / "square.gpkg"
    write_domain(path, lonlat_square)
    _, _, fields = read_layer(path, "boundaries")
    equator, east, north, west = fields["length_m"]
    assert west == pytest.approx(110574.0, abs=1.0)  # 1 degree of meridian
    assert east == pytest.approx(west, abs=1e-6)
    assert equator == pytest.approx(2 * np.pi * 6378137.0 / 360, abs=1e-3)
    assert 0 < equator - north < 20  # the parallel at 1 degree N is a bit shorter


def test_lengths_in_a_feet_crs_are_metres():
    ring = np.array([[0, 0], [1000, 0], [1000, 1000], [0, 1000], [0, 0]], float)
    domain = Domain(
        shapely.Polygon(ring),
        (BoundarySegment(ring, "shoreline", "all", 1),),
        crs="EPSG:2277",  # Texas Central, US survey feet
    )
    assert segment_lengths(domain)[0] == pytest.approx(4000 * 1200 / 3937, rel=1e-12)


def test_extra_layers_and_metadata(tmp_path, domain):
    lines = Features(
        geometry=[shapely.LineString([(-1, 50), (1, 50)]), None],
        crs="EPSG:4326",
        fields={"name": np.array(["north", "south"]), "rank": [1, 2]},
        fids=[0, 1],
        path="<memory>",
    )
    regions = Features(
        geometry=[shapely.box(0, 0, 100, 100)],
        crs="EPSG:32630",
        fields={"h_max": [250.0]},
        fids=[0],
        path="<memory>",
    )
    path = tmp_path / "domain.gpkg"
    write_domain(
        path,
        domain,
        metadata={"coastmesh_version": "test"},
        extra_layers={"open_lines": lines, "regions": regions},
    )
    names = pyogrio.list_layers(path)[:, 0].tolist()
    assert names == ["domain", "boundaries", "open_lines", "regions"]
    meta, geometry, fields = read_layer(path, "open_lines")
    assert CRS.from_user_input(meta["crs"]) == CRS.from_epsg(4326)
    assert fields["name"].tolist() == ["north", "south"]
    assert fields["rank"].tolist() == [1, 2]
    assert shapely.equals(geometry[0], lines.geometry[0])
    assert geometry[1] is None
    _, geometry, fields = read_layer(path, "regions")
    assert shapely.equals(geometry[0], shapely.box(0, 0, 100, 100))
    assert fields["h_max"].tolist() == [250.0]
    info = pyogrio.read_info(path, layer="domain")
    assert info["dataset_metadata"] == {"coastmesh_version": "test"}


@pytest.mark.parametrize("name", ["domain", "Boundaries", "", "   "])
def test_extra_layer_names_must_be_free(tmp_path, domain, name):
    extra = Features([shapely.Point(0, 0)], "EPSG:32630", {}, [0], "<memory>")
    with pytest.raises(ConfigError, match=repr(name)):
        write_domain(tmp_path / "d.gpkg", domain, extra_layers={name: extra})
    assert list(tmp_path.iterdir()) == []


def test_only_geopackage(tmp_path, domain):
    with pytest.raises(FormatError, match=r"d\.shp: .*\.gpkg"):
        write_domain(tmp_path / "d.shp", domain)
    assert list(tmp_path.iterdir()) == []


def test_existing_output_is_kept_unless_overwrite(tmp_path, domain):
    path = tmp_path / "d.gpkg"
    path.write_bytes(b"previous")
    with pytest.raises(OutputExistsError, match=r"d\.gpkg"):
        write_domain(path, domain)
    assert path.read_bytes() == b"previous"
    write_domain(path, domain, overwrite=True)
    assert pyogrio.list_layers(path)[:, 0].tolist() == ["domain", "boundaries"]
    assert [p.name for p in tmp_path.iterdir()] == ["d.gpkg"]


def test_failure_in_a_later_layer_leaves_the_target_as_it_was(
    tmp_path, domain, monkeypatch
):
    real = pyogrio.raw.write
    written = []

    def fail_on_extra(path, *args, layer=None, **kwargs):
        if layer == "extra":
            raise DataLayerError("no space left")
        real(path, *args, layer=layer, **kwargs)
        written.append(layer)

    monkeypatch.setattr(pyogrio.raw, "write", fail_on_extra)
    extra = Features([shapely.Point(0, 0)], "EPSG:32630", {}, [0], "<memory>")
    path = tmp_path / "d.gpkg"
    with pytest.raises(FormatError, match=r"d\.gpkg, layer 'extra'.*no space left"):
        write_domain(path, domain, extra_layers={"extra": extra})
    assert written == ["domain", "boundaries"]
    assert list(tmp_path.iterdir()) == []

    path.write_bytes(b"previous")
    with pytest.raises(FormatError):
        write_domain(path, domain, overwrite=True, extra_layers={"extra": extra})
    assert path.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == ["d.gpkg"]


def test_write_layers_needs_a_layer(tmp_path):
    with pytest.raises(ConfigError, match="no layers"):
        write_layers(tmp_path / "x.gpkg", {})
    assert list(tmp_path.iterdir()) == []


def test_domain_is_unchanged(tmp_path, domain, write_read):
    def same(a: Domain, b: Domain) -> None:
        assert shapely.equals_exact(a.polygon, b.polygon, tolerance=0)
        assert a.crs == b.crs and a.surface_id == b.surface_id
        for s, t in zip(a.segments, b.segments, strict=True):
            np.testing.assert_array_equal(s.coords, t.coords)
            assert (s.kind, s.name, s.physical_id) == (t.kind, t.name, t.physical_id)

    write_read(tmp_path / "d.gpkg", write_domain, lambda p: None, domain, same)
