"""``[[mesh_size.fields]]``: the config, its errors, and the term on a raster."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
import shapely
from affine import Affine

from coastmesh.case import GradationConfig, SizeConfig, dump_case, parse_case
from coastmesh.case.pipeline.size import domain_size_field
from coastmesh.case.terms.fields import FieldConfig, spread_cells, with_result
from coastmesh.errors import CoastmeshWarning, ConfigError, InputDataError
from coastmesh.geometry.earth import reproject_points
from coastmesh.types import BoundarySegment, Domain

BASE = """
[case]
name = "t"

[shorelines]
path = "/data/coast.gpkg"

[shoreline_sets.full]
id = 10

[domain]
seed = [0.5, 0.5]

[mesh_size]
h_max = "1 km"
"""


def parsed(extra: str):
    return parse_case(BASE + extra, "/cases/t.toml")


def test_an_entry_reads_with_units_and_paths_from_the_case_folder():
    case = parsed(
        """
[[mesh_size.fields]]
source = "runs/first.sww"
variable = "speed"
reduce = "max"
values = [1.5, 2.0]
sizes = ["300 m", 50]
mapping = "ramp"
"""
    )
    (entry,) = case.size.fields
    assert entry.source == Path("/cases/runs/first.sww")
    assert entry.sizes == (300.0, 50.0)
    assert entry.values == (1.5, 2.0)
    assert entry.size_mapping().sizes_of(np.array([1.75])).tolist() == [175.0]
    # the case dumps and reads back the same
    again = parse_case(dump_case(case), "/cases/t.toml")
    assert again.size.fields == case.size.fields


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('values = [2.0]\nsizes = ["-50 m"]', "sizes"),
        ("values = [2.0, 1.0]\nsizes = [50, 100]", "strictly increasing"),
        ("values = [1.0, 2.0, 3.0]\nsizes = [100, 50, 80]", "not ordered"),
        ("values = [1.0, 2.0]\nsizes = [100]", "one size per value"),
        ('values = [1.0]\nsizes = [50]\nmapping = "spline"', "mapping"),
        ('values = [1.0]\nsizes = [50]\nreduce = "at"', "time"),
        ('values = [1.0]\nsizes = [50]\ntime = "1 h"', "time"),
        ('values = [1.0]\nsizes = [50]\nreduce = "median"', "reduce"),
        ('values = [1.0]\nsizes = [50]\nsample = "cubic"', "sample"),
        (
            'values = [1.0]\nsizes = [50]\nsource = "r.sww"\nsample = "nearest"',
            r"sample = 'nearest' reads a raster; .*r\.sww is a mesh file",
        ),
    ],
)
def test_bad_entries_name_the_key(table, message):
    with pytest.raises(ConfigError, match=message) as err:
        parsed("[[mesh_size.fields]]\n" + table)
    assert "mesh_size.fields[0]" in str(err.value)


def test_refine_from_fills_the_entries_without_a_source():
    fields = (
        FieldConfig(values=(2.0,), sizes=(50.0,)),
        FieldConfig(values=(1.0,), sizes=(80.0,), source=Path("a.tif")),
    )
    filled = with_result(fields, Path("run.sww"))
    assert [f.source for f in filled] == [Path("run.sww"), Path("a.tif")]
    with pytest.raises(ConfigError, match=r"no \[\[mesh_size\.fields\]\] entry"):
        with_result(fields[1:], Path("run.sww"))


# --- the term on a raster -------------------------------------------------

RING = [[0, 0], [20000, 0], [20000, 20000], [0, 20000], [0, 0]]
UTM = "EPSG:32630"


def _domain():
    x0, y0 = 500000.0, 6500000.0
    ring = [[x0 + x, y0 + y] for x, y in RING]
    return Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south", 2),
            BoundarySegment(ring[1:], "shoreline", "coast", 1),
        ),
        crs=UTM,
    )


def _raster(path: Path, bounds, value, *, crs="EPSG:4326", cells=200) -> Path:
    """A lon/lat raster over ``bounds`` whose value is ``value(lon, lat)``."""
    minx, miny, maxx, maxy = bounds
    dx, dy = (maxx - minx) / cells, (maxy - miny) / cells
    lon = minx + dx * (np.arange(cells) + 0.5)
    lat = maxy - dy * (np.arange(cells) + 0.5)
    data = value(*np.meshgrid(lon, lat)).astype("float32")
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=cells,
        height=cells,
        count=1,
        dtype="float32",
        crs=crs,
        transform=Affine(dx, 0.0, minx, 0.0, -dy, maxy),
        nodata=-9999.0,
    ) as out:
        out.write(data, 1)
    return path


def _lonlat_box(domain, pad=0.05):
    lon, lat = reproject_points(
        np.asarray(domain.polygon.exterior.coords), UTM, "EPSG:4326"
    ).T
    return (lon.min() - pad, lat.min() - pad, lon.max() + pad, lat.max() + pad)


def _size(domain, **fields):
    size = SizeConfig(
        h_max="2 km",
        cell="250 m",
        rate=None,
        gradations=[GradationConfig(["coast"], h_min="400 m", d_grade="5 km")],
        **({"fields": [FieldConfig(**fields)]} if fields else {}),
    )
    return domain_size_field(domain, size, mesh_crs=UTM)


def test_sizes_follow_a_raster_in_another_crs_and_leave_the_rest(tmp_path):
    domain = _domain()
    box = _lonlat_box(domain)
    mid = (box[0] + box[2]) / 2
    # the value is the longitude's distance east of the middle: sizes east of it
    tif = _raster(tmp_path / "f.tif", box, lambda lon, lat: lon - mid)
    without = _size(domain)
    with_term = _size(domain, source=tif, values=(0.0,), sizes=(100.0,))
    grid = with_term.grid
    xx, yy = np.meshgrid(grid.x, grid.y)
    lon, _ = reproject_points(
        np.column_stack([xx.ravel(), yy.ravel()]), UTM, "EPSG:4326"
    ).T
    # a cell is 250 m, 0.0043 degrees of longitude here: the term's zone is
    # one cell wider than the value's contour (neighbour_min)
    east = (lon.reshape(xx.shape) > mid + 0.002) & grid.sea
    west = (lon.reshape(xx.shape) < mid - 0.01) & grid.sea
    # east of the line: the mapping's 100 m, below the gradations' floor of 400 m
    np.testing.assert_array_equal(with_term.field.values[east], 100.0)
    # west of it: the field without the term, exactly (rate = false: no grading)
    np.testing.assert_array_equal(
        with_term.field.values[west], without.field.values[west]
    )
    report = with_term.report.fields.entries[0]
    assert report.uncovered == 0.0
    assert report.size_after_m == 100.0
    assert report.elements_after > report.elements_before > 0


def test_a_raster_of_classes_is_read_as_the_cell_each_node_is_in(tmp_path):
    """``sample = "nearest"``: class 2 (a habitat) sized, classes 1 and 3 not.

    Bilinear reading would make class 2 of the edge between classes 1 and 3.
    """
    domain = _domain()
    box = _lonlat_box(domain)
    west, east = box[0] + (box[2] - box[0]) / 3, box[0] + 2 * (box[2] - box[0]) / 3
    classes = _raster(
        tmp_path / "habitat.tif",
        box,
        lambda lon, lat: np.where(lon < west, 1.0, np.where(lon < east, 3.0, 1.0)),
        cells=60,
    )
    table = {"source": classes, "values": (2.0, 2.5), "sizes": (100.0, 2000.0)}
    bilinear = _size(domain, **table, mapping="thresholds")
    nearest = _size(domain, **table, mapping="thresholds", sample="nearest")
    without = _size(domain)
    # nearest: classes 1 and 3 only, never 2: the mesh is the mesh without it
    np.testing.assert_array_equal(nearest.field.values, without.field.values)
    # bilinear: the cells between classes 1 and 3 read 2 there
    assert (bilinear.field.values == 100.0).sum() > 0


def test_the_size_holds_wherever_the_value_is_reached(tmp_path):
    """Read as Gmsh reads it (bilinear in each cell), not only at the nodes."""
    from scipy.interpolate import RegularGridInterpolator

    domain = _domain()
    box = _lonlat_box(domain)
    mid_lon, mid_lat = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
    # a disc of high values, its edge crossing cells at every angle
    tif = _raster(
        tmp_path / "f.tif",
        box,
        lambda lon, lat: 0.02 - np.hypot((lon - mid_lon) * 0.5, lat - mid_lat),
        cells=400,
    )
    out = _size(domain, source=tif, values=(0.0,), sizes=(100.0,))
    grid = out.grid
    rng = np.random.default_rng(3)
    pts = np.column_stack(
        [
            rng.uniform(grid.x[0], grid.x[-1], 20_000),
            rng.uniform(grid.y[0], grid.y[-1], 20_000),
        ]
    )
    lon, lat = reproject_points(pts, UTM, "EPSG:4326").T
    inside = 0.02 - np.hypot((lon - mid_lon) * 0.5, lat - mid_lat) >= 0
    ok = np.array([domain.polygon.contains(shapely.Point(p)) for p in pts])
    reached = inside & ok
    assert reached.sum() > 500
    gmsh_reads = RegularGridInterpolator((grid.y, grid.x), out.field.values)
    np.testing.assert_allclose(gmsh_reads(pts[reached][:, ::-1]), 100.0)
    # and the zone is no wider than its spread (2 cells for 100 m elements on
    # 250 m cells: the cell Gmsh reads bilinearly, and an element's
    # circumradius, 58 m) and the raster's own cell
    assert spread_cells(100.0, 250.0) == 2
    beyond = ~inside & ok
    fine = gmsh_reads(pts[beyond][:, ::-1]) <= 100.0
    gap = np.hypot((lon[beyond] - mid_lon) * 0.5, lat[beyond] - mid_lat) - 0.02
    assert fine.any()
    assert gap[fine].max() > 250.0 / 111e3  # more than one cell: spread by two
    assert gap[fine].max() < 3 * 250.0 / 111e3


def test_h_min_given_clamps_the_field_with_a_warning(tmp_path):
    domain = _domain()
    tif = _raster(tmp_path / "f.tif", _lonlat_box(domain), lambda lon, lat: lon * 0 + 5)
    size = SizeConfig(
        h_max="2 km",
        h_min="300 m",
        cell="250 m",
        rate=None,
        fields=[FieldConfig(source=tif, values=(1.0,), sizes=(100.0,))],
    )
    with pytest.warns(CoastmeshWarning, match="clamped to h_min"):
        out = domain_size_field(domain, size, mesh_crs=UTM)
    assert float(out.field.values[out.grid.sea].min()) == 300.0


def test_a_raster_off_the_domain_is_refused(tmp_path):
    domain = _domain()
    box = _lonlat_box(domain)
    tif = _raster(
        tmp_path / "far.tif",
        (box[0] + 20, box[1], box[2] + 20, box[3]),
        lambda lon, lat: lon,
    )
    with pytest.raises(InputDataError, match=r"far\.tif"):
        _size(domain, source=tif, values=(0.0,), sizes=(100.0,))


def test_a_partial_raster_warns_of_the_share_it_misses(tmp_path):
    domain = _domain()
    box = _lonlat_box(domain, pad=0.0)
    west_half = (box[0], box[1], (box[0] + box[2]) / 2, box[3])
    tif = _raster(tmp_path / "half.tif", west_half, lambda lon, lat: lon * 0 + 5)
    with pytest.warns(
        CoastmeshWarning, match=r"half.tif does not cover (4[5-9]|5[0-5])\.\d %"
    ):
        out = _size(domain, source=tif, values=(1.0,), sizes=(100.0,))
    share = out.report.fields.entries[0].uncovered
    assert 0.45 < share < 0.55


def test_a_variable_of_a_geotiff_names_the_file(tmp_path):
    domain = _domain()
    tif = _raster(tmp_path / "f.tif", _lonlat_box(domain), lambda lon, lat: lon)
    with pytest.raises(ConfigError, match=r"f\.tif is not a NetCDF file"):
        _size(domain, source=tif, variable="nothere", values=(0.0,), sizes=(100.0,))


def test_a_missing_netcdf_variable_lists_those_there(tmp_path):
    import xarray as xr

    domain = _domain()
    box = _lonlat_box(domain)
    lon = np.linspace(box[0], box[2], 50)
    lat = np.linspace(box[1], box[3], 40)
    ds = xr.Dataset(
        {
            "tidal_range": (("lat", "lon"), np.ones((40, 50))),
            "speed": (("lat", "lon"), np.full((40, 50), 3.0)),
        },
        coords={"lat": lat, "lon": lon},
    )
    ds.lat.attrs = {"units": "degrees_north", "standard_name": "latitude"}
    ds.lon.attrs = {"units": "degrees_east", "standard_name": "longitude"}
    ds.to_netcdf(tmp_path / "atlas.nc")
    with pytest.raises(
        ConfigError, match=r"'power' is not in .*atlas\.nc; it has speed, tidal_range"
    ):
        _size(
            domain,
            source=tmp_path / "atlas.nc",
            variable="power",
            values=(0.0,),
            sizes=(100.0,),
        )
    atlas = {"source": tmp_path / "atlas.nc", "variable": "speed"}
    with pytest.raises(
        InputDataError, match=r"atlas\.nc has no CRS; give the entry's crs"
    ):
        _size(domain, **atlas, values=(2.0,), sizes=(100.0,))
    out = _size(domain, **atlas, values=(2.0,), sizes=(100.0,), crs="EPSG:4326")
    assert float(out.field.values[out.grid.sea].max()) == 100.0


def test_an_entry_without_source_is_off_with_a_warning():
    domain = _domain()
    with pytest.warns(CoastmeshWarning, match="has no source"):
        out = _size(domain, values=(2.0,), sizes=(50.0,))
    without = _size(domain)
    np.testing.assert_array_equal(out.field.values, without.field.values)
    assert out.report.fields is None
