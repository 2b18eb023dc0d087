"""``coastmesh run`` end to end on the bundled real data (GSHHG Orkney, ETOPO1).

The example case in examples/orkney is run once; its outputs are checked against
independent calculations: msh read back by meshio, geodesic areas and lengths by
pyproj, the domain by shapely.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyogrio.raw
import pytest
import shapely
from conftest import EXAMPLE, FIGURES, MODEL_EXTENSIONS, coarse_example_text
from pyproj import Geod

from coastmesh.case import parse_case, read_case, run_case
from coastmesh.errors import ConfigError, InputDataError, OutputExistsError
from coastmesh.io.meshes.msh import read_msh

#: a whole case, end to end: run by `pytest -m slow` (and .ci/run)
pytestmark = pytest.mark.slow

GEOD = Geod(ellps="WGS84")


def _coarse(**replace: str):
    """The example with coarser sizes (a few seconds), read from memory."""
    # relative paths still from examples/orkney
    return parse_case(coarse_example_text(**replace), EXAMPLE)


def test_example_writes_every_output(example_run):
    result, out = example_run
    expected = {f"pentland_firth.{ext}" for ext in MODEL_EXTENSIONS} | {
        "domain.gpkg",
        "size.tif",
        "case.toml",
        "report.json",
        "summary.txt",
        "quality.json",
        "quality.txt",
    }
    expected |= {f"figures/{name}.png" for name in FIGURES}
    runs = {
        "adcirc": ["fort.14", "fort.13", "fort.15", "README.txt"],
        "schism": ["hgrid.gr3", "hgrid.ll", "vgrid.in", "bctides.in", "manning.gr3",
                   "adv.gr3", "param.nml", "README.txt"],
    }  # fmt: skip
    expected |= {
        f"model_test/{m}/{name}" for m, names in runs.items() for name in names
    }
    written = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()}
    assert written == expected == set(result.files)
    assert (out / "model_test" / "schism" / "outputs").is_dir()
    assert not list(out.parent.glob("*.partial-*"))
    report = json.loads((out / "report.json").read_text())
    assert report["mesh"]["nodes"] == result.nodes > 5_000
    assert result.seconds < 60


def test_the_models_rules_hold_in_its_files(example_run):
    """The example's own fort.14, gr3 and SELAFIN files, by the models' rules."""
    from model_rules import check_adcirc, check_schism, check_telemac

    _, out = example_run
    assert check_adcirc(out / "pentland_firth.14") == []
    assert check_schism(out / "pentland_firth.gr3") == []
    assert check_telemac(out / "pentland_firth.slf", out / "pentland_firth.cli") == []


def test_msh_round_trip_and_boundary_ids(example_run):
    result, out = example_run
    case = read_case(EXAMPLE)
    mesh2 = read_msh(out / "pentland_firth.msh")
    assert len(mesh2.points) == result.nodes
    assert len(mesh2.triangles) == result.triangles
    ids = {s.physical_id for s in case.sets} | {b.physical_id for b in case.boundaries}
    assert set(np.unique(mesh2.boundary_ids)) == ids  # every set and boundary
    # every edge used by one triangle only is a boundary edge, and carries an id
    unique, count = _edges(mesh2.triangles)
    outer = {tuple(e) for e in unique[count == 1]}
    tagged = {tuple(e) for e in np.sort(mesh2.boundary_edges, axis=1)}
    assert outer == tagged
    assert mesh2.surface_id == 1


def test_mesh_covers_the_domain(example_run):
    """The triangles' geodesic area equals the domain's, and nodes lie in it."""
    _, out = example_run
    mesh = read_msh(out / "pentland_firth.msh")
    wkb, _ = _layer(out / "domain.gpkg", "domain")
    domain = shapely.from_wkb(wkb[0])
    tri = mesh.points[mesh.triangles]
    area = sum(abs(GEOD.polygon_area_perimeter(t[:, 0], t[:, 1])[0]) for t in tri[::1])
    expected = abs(GEOD.geometry_area_perimeter(domain)[0])
    # boundary curves are resampled to the local size: a small area change
    assert area == pytest.approx(expected, rel=0.01)
    inside = shapely.dwithin(domain, shapely.points(mesh.points), 0.003)
    assert inside.all()


def test_mesh_follows_the_size_field(example_run):
    _, out = example_run
    mesh = read_msh(out / "pentland_firth.msh")
    from coastmesh.io import read_raster
    from coastmesh.meshing import sample_size
    from coastmesh.types import SizeGrid

    field = read_raster(out / "size.tif")
    edges, _ = _edges(mesh.triangles)
    a, b = mesh.points[edges[:, 0]], mesh.points[edges[:, 1]]
    _, _, length = GEOD.inv(a[:, 0], a[:, 1], b[:, 0], b[:, 1])
    from pyproj import Transformer

    to_grid = Transformer.from_crs("EPSG:4326", field.attrs["crs"], always_xy=True)
    mid = np.column_stack(to_grid.transform(*((a + b) / 2).T))
    grid = SizeGrid.from_dataarray(field.sortby("y"))
    ratio = length / sample_size(grid, mid)
    assert 0.75 < np.median(ratio) < 1.25
    assert np.percentile(ratio, 5) > 0.4 and np.percentile(ratio, 95) < 1.8


def test_domain_geopackage_boundaries(example_run):
    _, out = example_run
    case = read_case(EXAMPLE)
    wkb, fields = _layer(out / "domain.gpkg", "boundaries")
    lines = shapely.from_wkb(wkb)
    names = set(fields["name"])
    assert names == {s.name for s in case.sets} | {b.name for b in case.boundaries}
    untrimmed, ufields = _layer(out / "domain.gpkg", "open_boundaries_untrimmed")
    walls = dict(zip(ufields["name"], shapely.from_wkb(untrimmed), strict=True))
    for line, name, kind in zip(lines, fields["name"], fields["kind"], strict=True):
        if kind == "open":  # trimmed, but still on its untrimmed line
            assert (
                shapely.hausdorff_distance(
                    line, shapely.intersection(walls[name], line.buffer(1e-9))
                )
                < 1e-6
            )
    # the full-resolution coast lies within its region (plus the seam tolerance)
    region = shapely.box(-3.45, 58.55, -2.85, 58.76).buffer(0.002)
    full = lines[fields["name"] == "full"]
    assert len(full) and shapely.within(full, region).all()


@pytest.mark.filterwarnings("ignore::coastmesh.meshing.SmallIslandWarning")
def test_same_input_same_mesh(tmp_path):
    case = _coarse()
    first = run_case(case, output=tmp_path / "a")
    second = run_case(case, output=tmp_path / "b")
    assert first.nodes == second.nodes
    assert (tmp_path / "a" / "pentland_firth.msh").read_bytes() == (
        tmp_path / "b" / "pentland_firth.msh"
    ).read_bytes()


def test_failures_leave_nothing(tmp_path):
    out = tmp_path / "out"
    bad_seed = _coarse(**{"seed = [-3.1, 58.85]": "seed = [-3.2, 58.98]"})
    with pytest.raises(ConfigError, match=r"seed = \(-3.2, 58.98\): lies on land"):
        run_case(bad_seed, output=out)
    assert not out.exists() and not list(tmp_path.glob("out.partial*"))
    missing = parse_case(
        EXAMPLE.read_text().replace("orkney_gshhg_f.geojson", "nope.geojson"),
        EXAMPLE,
    )
    with pytest.raises(InputDataError, match=r"nope\.geojson"):
        run_case(missing, output=out)
    assert not out.exists()
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    with pytest.raises(OutputExistsError, match="not empty"):
        run_case(EXAMPLE, output=out)
    assert [p.name for p in out.iterdir()] == ["keep.txt"]


def _edges(triangles):
    """Unique undirected edges of a triangulation, and how many triangles use each."""
    pairs = np.concatenate([triangles[:, [a, b]] for a, b in ((0, 1), (1, 2), (2, 0))])
    return np.unique(np.sort(pairs, axis=1), axis=0, return_counts=True)


def _layer(path: Path, layer: str):
    meta, _, geometry, values = pyogrio.raw.read(path, layer=layer)
    return geometry, dict(zip(meta["fields"], values, strict=True))


def test_small_lakes_are_filled_and_counted():
    from pyproj import CRS

    from coastmesh.case.pipeline.shorelines import fill_lakes

    land = shapely.Polygon(
        [(0, 0), (10_000, 0), (10_000, 10_000), (0, 10_000)],
        [
            [(1_000, 1_000), (1_100, 1_000), (1_100, 1_100), (1_000, 1_100)],  # 1 ha
            [(5_000, 5_000), (8_000, 5_000), (8_000, 8_000), (5_000, 8_000)],  # 9 km2
        ],
    )
    out, filled = fill_lakes(np.array([land]), CRS("EPSG:32630"), 1e6)
    assert filled == 1 and len(out[0].interiors) == 1
    assert out[0].area == pytest.approx(1e8 - 9e6)


def test_shoreline_lines_are_refused_naming_the_feature(tmp_path):
    lines = tmp_path / "lines.geojson"
    lines.write_text(
        '{"type": "FeatureCollection", "features": [{"type": "Feature", '
        '"properties": {}, "geometry": {"type": "LineString", '
        '"coordinates": [[-3, 58], [-2, 59]]}}]}'
    )
    text = EXAMPLE.read_text().replace(
        "../../src/coastmesh/data/orkney_gshhg_f.geojson", lines.as_posix()
    )
    with pytest.raises(InputDataError, match=r"feature 0 is a LineString.*polygons"):
        run_case(parse_case(text, EXAMPLE), output=tmp_path / "out")
    assert not (tmp_path / "out").exists()


@pytest.mark.filterwarnings("ignore::coastmesh.meshing.SmallIslandWarning")
def test_polyline_boundary_and_region_from_files(tmp_path):
    """A polyline open boundary and a region polygon, each read from a file."""
    line = tmp_path / "north.geojson"
    line.write_text(
        '{"type": "FeatureCollection", "features": [{"type": "Feature", '
        '"properties": {}, "geometry": {"type": "LineString", '
        '"coordinates": [[-3.7, 59.45], [-2.9, 59.47], [-2.0, 59.45]]}}]}'
    )
    region = tmp_path / "firth.geojson"
    region.write_text(
        '{"type": "FeatureCollection", "features": [{"type": "Feature", '
        '"properties": {}, "geometry": {"type": "Polygon", "coordinates": '
        "[[[-3.45, 58.55], [-2.85, 58.55], [-2.85, 58.76], [-3.45, 58.76], "
        "[-3.45, 58.55]]]}}]}"
    )
    case = _coarse(
        **{
            'kind = "great_circle"\nstart = [-3.7, 59.45]\nend = [-2.0, 59.45]': (
                f'kind = "polyline"\npath = "{line.as_posix()}"'
            ),
            "box = [-3.45, 58.55, -2.85, 58.76]": f'path = "{region.as_posix()}"',
        }
    )
    result = run_case(case, output=tmp_path / "out")
    wkb, fields = _layer(tmp_path / "out" / "domain.gpkg", "boundaries")
    north = shapely.from_wkb(wkb)[fields["name"] == "north"]
    assert len(north) == 1
    # the trimmed boundary runs on the polyline, through its middle vertex
    assert shapely.dwithin(north[0], shapely.Point(-2.9, 59.47), 1e-9)
    assert result.boundary_edges["north (3)"] > 0
    assert result.boundary_edges["full (10)"] > 0


def test_the_default_channel_term_closes_narrow_channels(example_run):
    result, _ = example_run
    channels = result.report.size_field.channels
    # narrow = "close" by default: closed before meshing, then peeled after
    assert channels.narrow == "close" and channels.closed >= 1
    assert channels.closed_km2 > 0 and channels.limited_km2 > 10.0
    quality = result.report.quality
    assert len(quality.channel_spanning_triangles) <= 1e-4 * quality.triangles
    assert result.report.channels is not None
    assert quality.min_angle.p1 >= 30.0 and quality.radius_ratio.below_0_25 == 0
