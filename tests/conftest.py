"""Shared fixtures: bundled real data, the CLI runner, small clipped inputs."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import settings
from scipy.spatial import Delaunay

from coastmesh.data import path as data_path

# Small real clips of the bundled data (minx, miny, maxx, maxy), EPSG:4326.
ORKNEY_BBOX = (-3.45, 58.85, -2.85, 59.15)  # Mainland Orkney, west half
NORWAY_BBOX = (4.8, 60.9, 5.6, 61.3)  # mouth of Sognefjorden
ORKNEY_RASTER_BBOX = (-4.0, 58.0, -2.0, 60.0)  # 21 x 21 cells

# The property tests draw the same examples on every run (a seed of their own
# per test): a run is reproducible, and a clean clone cannot fail on a rare
# draw another run never saw. HYPOTHESIS_PROFILE=explore draws afresh, to hunt.
settings.register_profile("ci", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture(scope="session")
def orkney_geojson() -> Path:
    return data_path("orkney_gshhg_f.geojson")


@pytest.fixture(scope="session")
def norway_geojson() -> Path:
    return data_path("norway_west_gshhg_f.geojson")


@pytest.fixture(scope="session")
def orkney_tif() -> Path:
    return data_path("etopo1_0.1deg_orkney_wide.tif")


@pytest.fixture(scope="session")
def nwshelf_tif() -> Path:
    return data_path("etopo1_0.1deg_nwshelf.tif")


@pytest.fixture(scope="session")
def nwshelf_nc() -> Path:
    return data_path("etopo1_0.1deg_nwshelf.nc")


EXAMPLE = Path(__file__).parents[1] / "examples" / "orkney" / "pentland_firth.toml"
#: what the example case writes (its [output] formats, and the figures)
MODEL_EXTENSIONS = ("msh", "14", "gr3", "slf", "cli", "mesh", "nc", "vtu", "gpkg")
FIGURES = (
    "domain",
    "mesh",
    "size",
    "channels",
    "quality",
    "depth",
    "depth_rules",
    "time_step",
)


#: the example's gradations made coarser: the same case, meshed in a few seconds
COARSER = {
    'h_min = "150 m"': 'h_min = "600 m"',
    'h_min = "400 m"': 'h_min = "800 m"',
    'h_min = "1 km"': 'h_min = "1.5 km"',
}


def coarse_example_text(**replace: str) -> str:
    """The example case's text with :data:`COARSER` sizes and ``replace`` applied."""
    text = EXAMPLE.read_text()
    for old, new in (COARSER | replace).items():
        assert old in text, old
        text = text.replace(old, new)
    return text


def clustered_delaunay(seed: int, n: int, clusters: int):
    """Delaunay triangles of random points in a square, some in tight clusters."""
    rng = np.random.default_rng(seed)
    points = [[[0, 0], [1, 0], [1, 1], [0, 1]], rng.random((n, 2))]
    for centre in rng.random((clusters, 2)):
        points.append(centre + rng.normal(0, 0.01, (3, 2)))  # slivers around it
    xy = np.vstack(points).clip(0, 1) * 1000
    tri = Delaunay(xy).simplices.astype(np.int64)
    d1, d2 = xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]
    area = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    tri[area < 0] = tri[area < 0][:, [0, 2, 1]]
    return xy, tri[np.abs(area) > 1e-6]


def one_triangle(crs=None):
    """A mesh of one right triangle with one boundary id: for argument checks."""
    from coastmesh.types import Mesh

    return Mesh(
        [[0, 0], [1, 0], [0, 1]],
        [[0, 1, 2]],
        [[0, 1], [1, 2], [2, 0]],
        [1, 1, 1],
        1,
        crs,
    )


@pytest.fixture(scope="session")
def mesh_with_islands():
    """A Gmsh mesh of a 4 x 3 km square with two islands, with depth on its nodes.

    Boundary ids: 2 the open south side, 1 the rest of the coast and the square
    island, 3 the triangular island. UTM 30N, 250 m elements.
    """
    from coastmesh.meshing import generate_mesh
    from coastmesh.types import BoundarySegment, Domain, SizeGrid

    outer = [[0, 0], [4000, 0], [4000, 3000], [0, 3000], [0, 0]]
    holes = [
        [[1000, 1000], [1000, 1500], [1500, 1500], [1500, 1000], [1000, 1000]],
        [[2500, 1000], [2500, 2000], [3000, 2000], [2500, 1000]],
    ]
    polygon = shapely.Polygon(outer, holes)
    segments = (
        BoundarySegment([[0, 0], [4000, 0]], "open", "south", 2),
        BoundarySegment(
            [[4000, 0], [4000, 3000], [0, 3000], [0, 0]], "shoreline", "coast", 1
        ),
        BoundarySegment(polygon.interiors[0].coords, "shoreline", "coast", 1),
        BoundarySegment(polygon.interiors[1].coords, "shoreline", "rock", 3),
    )
    domain = Domain(polygon, segments, crs="EPSG:32630")
    grid = SizeGrid([0.0, 4000.0], [0.0, 3000.0], np.full((2, 2), 250.0))
    mesh = generate_mesh(domain, grid)
    return mesh.with_point_data(depth=5.0 + mesh.points[:, 0] / 100.0)


@pytest.fixture(scope="session")
def coarse_case():
    """The example case with coarser sizes, built in memory once a session.

    Tests that share it are grouped on one worker (``xdist_group("coarse")``),
    so a run on several workers builds it once.
    """
    from coastmesh import CoastmeshWarning
    from coastmesh.case import build_case, parse_case

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)
        return build_case(parse_case(coarse_example_text(), EXAMPLE), workers=1)


@pytest.fixture(scope="session")
def example_run(tmp_path_factory):
    """The Orkney example case, run once for the whole test session."""
    from coastmesh.case import run_case

    out = tmp_path_factory.mktemp("example") / "pentland_firth"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(EXAMPLE, output=out)
    return result, out


def model_rule_breaks(mesh, folder: Path) -> list:
    """Write ``mesh`` as fort.14, hgrid.gr3 and SELAFIN; every model rule broken.

    The checker (``tests/model_rules.py``) parses the files itself.
    """
    from model_rules import check_adcirc, check_schism, check_telemac

    import coastmesh

    folder.mkdir(parents=True, exist_ok=True)
    for name in ("fort.14", "hgrid.gr3", "mesh.slf"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            coastmesh.write_mesh(folder / name, mesh, overwrite=True)
    return (
        check_adcirc(folder / "fort.14")
        + check_schism(folder / "hgrid.gr3")
        + check_telemac(folder / "mesh.slf", folder / "mesh.cli")
    )


def assert_clean_failure(result, *expected: str, code: int = 1) -> None:
    """A command failed cleanly: exit ``code``, the ``expected`` texts, no traceback.

    ``result`` is what :func:`run_cli` returns (click's ``Result``).
    """
    assert result.exit_code == code, result.output
    assert "Traceback" not in result.output
    for text in expected:
        assert text in result.output, (text, result.output)


@pytest.fixture
def run_cli():
    """Call the ``coastmesh`` group in-process; return click's Result."""
    from click.testing import CliRunner

    from coastmesh.cli.main import cli

    runner = CliRunner()

    def invoke(*args: object):
        return runner.invoke(cli, [str(a) for a in args], catch_exceptions=True)

    return invoke


@pytest.fixture
def folder_listing():
    """Return the sorted names in a folder (hidden staging files included)."""

    def listing(folder: Path) -> list[str]:
        return sorted(p.name for p in Path(folder).iterdir())

    return listing


@pytest.fixture
def make_gpkg():
    """Write geometries (and fields) to a GeoPackage with pyogrio's raw API."""
    import pyogrio.raw

    def write(path: Path, geometries, *, crs: str | None = "EPSG:4326", **fields):
        geometry = np.empty(len(geometries), dtype=object)
        geometry[:] = list(geometries)
        with warnings.catch_warnings(), np.errstate(invalid="ignore"):
            warnings.simplefilter("ignore")
            pyogrio.raw.write(
                path,
                shapely.to_wkb(geometry),
                [np.asarray(v) for v in fields.values()],
                list(fields),
                driver="GPKG",
                geometry_type="Unknown",
                crs=crs,
            )
        return Path(path)

    return write


@pytest.fixture
def write_read():
    """Write ``obj`` to ``path``, read it back, and check ``obj`` was not changed.

    ``assert_same(a, b)`` compares two objects and raises on a difference.
    """
    import copy

    def round_trip(path: Path, writer, reader, obj, assert_same):
        before = copy.deepcopy(obj)
        writer(path, obj)
        assert_same(obj, before)
        return reader(path)

    return round_trip


def bay_with_inlet(inlet: float = 600.0):
    """A 20 km bay in UTM 31N, open to the south, with an inlet ``inlet`` m wide.

    The inlet runs 6 km north from the middle of the bay's north shore.
    """
    import shapely

    from coastmesh.types import BoundarySegment, Domain

    x0, x1 = 10_000 - inlet / 2, 10_000 + inlet / 2
    ring = [
        (0, 0),
        (20_000, 0),
        (20_000, 20_000),
        (x1, 20_000),
        (x1, 26_000),
        (x0, 26_000),
        (x0, 20_000),
        (0, 20_000),
        (0, 0),
    ]
    return Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south", 2),
            BoundarySegment(ring[1:], "shoreline", "coast", 1),
        ),
        crs="EPSG:32631",
    )


def _sphere():
    from pyproj import Geod

    from coastmesh.geometry.earth import EARTH_RADIUS

    return Geod(a=EARTH_RADIUS, b=EARTH_RADIUS)


def _cap(lon: float, lat: float, radius_km: float, n: int = 240) -> np.ndarray:
    """A geodesic circle on the sphere, longitudes continuous round it."""
    az = np.linspace(0.0, 360.0, n, endpoint=False)
    x, y, _ = _sphere().fwd(
        np.full(n, lon), np.full(n, lat), az, np.full(n, radius_km * 1e3)
    )
    x = np.unwrap(np.asarray(x), period=360.0)
    return np.column_stack([x, y])[::-1]  # counter-clockwise


def synthetic_world() -> list[shapely.Polygon]:
    """Antarctica as GSHHG stores it, a continent split at the antimeridian, two
    more continents: a world ocean bounded by 4 land masses, in GSHHG's form."""
    lon = np.linspace(0.0, 180.0, 91)
    coast = np.column_stack([lon, -70.0 + 3.0 * np.sin(np.radians(2 * lon))])
    east = shapely.Polygon([*coast, (180.0, -90.0), (0.0, -90.0)])
    west = shapely.transform(east, lambda xy: xy - [180.0, 0.0])
    pacific = shapely.Polygon(_cap(180.0, 15.0, 2500.0))
    halves = [
        pacific.intersection(shapely.box(0.0, -90.0, 180.0, 90.0)),
        shapely.transform(
            pacific.intersection(shapely.box(180.0, -90.0, 360.0, 90.0)),
            lambda xy: xy - [360.0, 0.0],
        ),
    ]
    return [
        east,
        west,
        *halves,
        shapely.Polygon(_cap(10.0, 45.0, 3000.0)),
        shapely.Polygon(_cap(-80.0, 0.0, 2000.0)),
    ]
