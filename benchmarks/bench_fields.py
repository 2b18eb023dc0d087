"""The ``[[mesh_size.fields]]`` term's speed targets (issue 50), measured.

1. **A raster source.** "The term on a 10-million-cell raster adds <= 1.3x the
   time of the bathymetry term on the same raster." The raster is the bundled
   ETOPO1 NW-shelf grid (0.1 deg, 421 x 221 cells) resampled bilinearly
   (``rasterio.warp.reproject``) to about ``--cells`` cells over the same
   extent, in longitude/latitude; the domain is that of
   ``examples/nw_european_shelf/coarse.toml`` (its shoreline, domain and
   closing stages), meshed in the case's oblique stereographic CRS; the size
   grid has about ``--grid`` x ``--grid`` nodes. Timed, on the same
   grid (its sea mask measured once, beforehand, as the size stage shares it
   between the terms), each with a new case so that each reads the raster:

   * ``[mesh_size.bathymetry]`` (``per_wavelength = 100``): ``Bathymetry().sizes``;
   * ``[[mesh_size.fields]]`` with a thresholds mapping of the raster's
     values: ``Fields().sizes``;

   and the whole size field with one term or the other
   (:func:`coastmesh.case.domain_size_field`: the grid, its sea mask, the term,
   the floor, ``h_max`` and the gradation limit; channels and Courant off).
2. **A mesh source.** "Reading a 1-million-node UGRID source adds <= 10 s." A
   Delaunay triangulation of ``--nodes`` random nodes (and the corners) over a
   100 km square in UTM 30N, with a node variable of ``--records`` float32
   records, written as UGRID netCDF by xugrid, and the same mesh as an ANUGA
   ``.sww`` (netCDF-3, ``stage``, ``xmomentum``, ``ymomentum``, ``elevation``,
   as ``anuga/file/sww.py`` lays it out). Timed on a ``--grid`` x ``--grid``
   size grid over the square (100 m):
   :func:`~coastmesh.io.fields.field_values.sample_field` with ``reduce = "max"``
   (the UGRID variable; ANUGA's derived ``speed``), split into the read
   (:func:`~coastmesh.io.fields.field_sources.read_field_source`:
   the nodes, the faces and the metadata; the time series stay on disk), the
   reduction over the records (which reads them; the module's own private
   ``_recipe`` and ``_reduced``, as ``sample_field`` calls them), and the sampling
   on the grid (:func:`~coastmesh.sizing.fields.triangles_on_grid`); and the whole term
   (``Fields().sizes``: sampling, mapping, the land filled).

Every figure is the minimum, median and maximum over ``--runs`` runs after
``--warmup`` runs not counted; the two terms run in turn (A B A B ...) and
their ratio is taken run by run. The inputs are made once and kept under
``--cache``; nothing is written into the repository. ``--profile`` prints
where the field term's time goes (cProfile, the 25 costliest calls).
``--once STEP`` runs one step once and prints its seconds, for a whole-process
timer (``/usr/bin/time -v``: the peak memory of that step and its inputs).

Run from the repository root::

    python benchmarks/bench_fields.py
    python benchmarks/bench_fields.py --runs 7 --cache /tmp/bench_fields
    python benchmarks/bench_fields.py --only mesh --nodes 200000 --profile
    /usr/bin/time -v python benchmarks/bench_fields.py --once ugrid-term
"""

from __future__ import annotations

import argparse
import cProfile
import math
import pstats
import statistics
import time
import warnings
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
ETOPO = ROOT / "src" / "coastmesh" / "data" / "etopo1_0.1deg_nwshelf.tif"
CASE = ROOT / "examples" / "nw_european_shelf" / "coarse.toml"
UTM = "EPSG:32630"
#: The mesh source's square, UTM 30N metres (the Pentland Firth's latitudes).
SQUARE = (450e3, 6.45e6, 550e3, 6.55e6)
#: An M2 tide, seconds: the records span one.
M2 = 44714.0
TARGET_RATIO = 1.3
#: What ``--once`` runs: a raster term or its whole size field, a mesh term.
ONCE = (
    "bathymetry-term", "fields-term", "bathymetry-field", "fields-field",
    "ugrid-term", "sww-term",
)  # fmt: skip
TARGET_SECONDS = 10.0


def timed_runs(
    funcs: dict[str, Callable[[], Any]], runs: int, warmup: int
) -> dict[str, list[float]]:
    """Run each function in turn, ``warmup + runs`` times; return the counted times."""
    times: dict[str, list[float]] = {label: [] for label in funcs}
    for k in range(warmup + runs):
        for label, func in funcs.items():
            started = time.perf_counter()
            func()
            if k >= warmup:
                times[label].append(time.perf_counter() - started)
    return times


def spread(values: list[float]) -> str:
    """Return ``min / median / max`` of ``values``."""
    return f"{min(values):.2f} | {statistics.median(values):.2f} | {max(values):.2f}"


def profiled(func: Callable[[], Any], title: str) -> None:
    """Print the 25 calls of ``func`` with the most cumulative time."""
    profile = cProfile.Profile()
    profile.runcall(func)
    print(f"\n#### Profile: {title}\n\n```")
    pstats.Stats(profile).sort_stats("cumulative").print_stats(25)
    print("```")


# -- 1. a raster source ---------------------------------------------------------


def make_raster(cache: Path, cells: int) -> Path:
    """Resample the NW-shelf ETOPO1 grid bilinearly to about ``cells`` cells."""
    import rasterio
    from rasterio.transform import from_bounds
    from rasterio.warp import Resampling, reproject

    with rasterio.open(ETOPO) as src:
        data = src.read(1)
        bounds, crs, transform = src.bounds, src.crs, src.transform
    factor = math.sqrt(cells / data.size)
    nx, ny = math.ceil(data.shape[1] * factor), math.ceil(data.shape[0] * factor)
    path = cache / f"etopo1_nwshelf_{nx}x{ny}.tif"
    if path.exists():
        return path
    out = np.empty((ny, nx), dtype=np.float32)
    fine = from_bounds(*bounds, nx, ny)
    reproject(
        data, out,
        src_transform=transform, src_crs=crs, dst_transform=fine, dst_crs=crs,
        resampling=Resampling.bilinear,
    )  # fmt: skip
    partial = path.with_suffix(".partial.tif")
    profile = {
        "driver": "GTiff", "width": nx, "height": ny, "count": 1,
        "dtype": "float32", "crs": crs, "transform": fine, "nodata": None,
        "tiled": True, "blockxsize": 512, "blockysize": 512,
    }  # fmt: skip
    with rasterio.open(partial, "w", **profile) as dst:
        dst.write(out, 1)
    partial.rename(path)
    return path


def shelf_domain() -> tuple[Any, Any]:
    """Return the coarse NW-shelf case's domain and its mesh CRS."""
    from coastmesh.case import read_case
    from coastmesh.case.pipeline import STAGES, CaseRun, RunContext, strategy_of
    from coastmesh.errors import CoastmeshWarning
    from coastmesh.types import quiet_stage, serial_runner

    config = read_case(CASE)
    ctx = RunContext(1, serial_runner, quiet_stage)
    run = CaseRun(config, strategy_of(config))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoastmeshWarning)  # the channels closed
        for stage in STAGES[:3]:  # shorelines, domain, closing
            run = stage(run, ctx)
    return run.domain.domain, run.domain.mesh_crs


def grid_cell(domain: Any, crs: Any, nodes: int) -> float:
    """Return the spacing (10 m steps) of about ``nodes`` x ``nodes`` grid nodes."""
    import shapely

    from coastmesh.geometry import reproject

    ring = shapely.segmentize(domain.polygon.exterior, 0.05)
    minx, miny, maxx, maxy = reproject(ring, domain.crs, crs).bounds
    return round(math.sqrt((maxx - minx) * (maxy - miny)) / nodes, -1)


def size_configs(raster: Path, cell: float) -> dict[str, Any]:
    """Return the ``[mesh_size]`` of each term: alone, on the same grid."""
    from coastmesh.case import SizeConfig
    from coastmesh.case.terms import (
        BathymetryConfig,
        ChannelConfig,
        CourantConfig,
        FieldConfig,
    )

    common = {
        "h_max": "150 km", "h_min": "2 km", "cell": cell,
        "channels": ChannelConfig(enabled=False),
        "courant": CourantConfig(enabled=False),
    }  # fmt: skip
    # the raster is elevation, up: finer on the shelf, finer still near the coast
    fields = FieldConfig(
        values=(-200.0, -50.0), sizes=("10 km", "5 km"), source=raster, name="etopo"
    )
    return {
        "bathymetry": SizeConfig(
            bathymetry=BathymetryConfig(path=raster, per_wavelength=100), **common
        ),
        "fields": SizeConfig(fields=[fields], **common),
    }


def term_case(size: Any, domain: Any) -> Any:
    """Return a new case of ``size`` on ``domain`` (it reads its rasters anew)."""
    import shapely

    from coastmesh.case.config import floor
    from coastmesh.case.pipeline.depth import read_sources
    from coastmesh.case.terms.base import SizeCase, SizeTables

    ring = shapely.segmentize(domain.polygon.exterior, domain.polygon.length / 400)

    def read(part: Any) -> Any:
        return read_sources(part.stack, shapely.get_coordinates(ring), domain.crs)

    return SizeCase(SizeTables(size), domain, floor(size), read_depth=read)


def raster_runs(args: argparse.Namespace) -> tuple[str, dict[str, Callable[[], Any]]]:
    """Make the raster, the domain and the grid; return a note and what to time."""
    import rasterio

    from coastmesh.case import domain_size_field
    from coastmesh.case.config import PYTHON_SOURCE, SizeConfig
    from coastmesh.case.schema import Check, check_part
    from coastmesh.case.terms import Bathymetry, Fields
    from coastmesh.sizing.grid import PlaneGrid

    raster = make_raster(args.cache, args.cells)
    domain, crs = shelf_domain()
    cell = grid_cell(domain, crs, args.grid)
    sizes = {
        label: check_part(size, SizeConfig, Check(PYTHON_SOURCE), "mesh_size")
        for label, size in size_configs(raster, cell).items()
    }
    grid = PlaneGrid.around(domain, crs, spacing=cell, smallest=cell)
    sea = grid.sea  # measured once: the size stage shares it between the terms
    terms = {"bathymetry": Bathymetry(), "fields": Fields()}

    def term(label: str) -> Callable[[], Any]:
        def run() -> Any:
            # each run moves the nodes into the raster's CRS anew, as a new
            # case's grid does (the grid keeps them once moved: Grid.nodes_as)
            for key in [k for k in vars(grid) if k.startswith("nodes in ")]:
                del vars(grid)[key]
            return terms[label].sizes(grid, term_case(sizes[label], domain))

        return run

    def whole(label: str) -> Callable[[], Any]:
        return lambda: domain_size_field(domain, sizes[label], mesh_crs=crs)

    runs = {f"{label} term": term(label) for label in terms}
    runs |= {f"{label} field": whole(label) for label in terms}
    if args.once:
        return "", runs
    with rasterio.open(raster) as r:
        nx, ny, res = r.width, r.height, r.res[0]
    check = {label: runs[f"{label} term"]().upper for label in terms}
    note = (
        f"\n### 1. A raster: {nx:,} x {ny:,} = {nx * ny:,} cells ({res:.5f} deg, "
        f"lon/lat), {raster.name}\n\nDomain: {CASE.relative_to(ROOT)} (shorelines, "
        f"domain, closing); mesh CRS {crs.name}; size grid {grid.shape[1]} x "
        f"{grid.shape[0]} nodes, cell {cell:.0f} m, {int(sea.sum()):,} sea nodes. "
        "Sizes set at the sea nodes: "
        + ", ".join(
            f"{label} {np.isfinite(v[sea]).mean():.0%} (median "
            f"{np.median(v[sea & np.isfinite(v)]) / 1e3:.1f} km)"
            for label, v in check.items()
        )
        + f". {args.runs} runs after {args.warmup}, the four in turn.\n"
    )
    return note, runs


def bench_raster(args: argparse.Namespace) -> None:
    """Time the bathymetry and the field term on the same raster and grid."""
    note, runs = raster_runs(args)
    print(note)
    times = timed_runs(runs, args.runs, args.warmup)
    parts = (("the term's sizes", "term"), ("whole size field", "field"))
    print("| what | term | min s | median s | max s |")
    print("|---|---|---:|---:|---:|")
    for what, kind in parts:
        for label in ("bathymetry", "fields"):
            print(f"| {what} | {label} | {spread(times[f'{label} {kind}'])} |")
    print("\n| ratio fields / bathymetry, run by run | min | median | max | target |")
    print("|---|---:|---:|---:|---:|")
    for what, kind in parts:
        pairs = zip(times[f"fields {kind}"], times[f"bathymetry {kind}"], strict=True)
        ratio = [f / b for f, b in pairs]
        print(f"| {what} | {spread(ratio)} | <= {TARGET_RATIO} |")
    if args.profile:
        profiled(runs["fields term"], "the fields term's sizes on the raster")
        profiled(runs["bathymetry term"], "the bathymetry term's sizes on the raster")


# -- 2. a mesh source -------------------------------------------------------------


def make_mesh(
    cache: Path, nodes: int, records: int
) -> tuple[Path, Path, tuple[int, int]]:
    """Write the random mesh as UGRID and as ``.sww``; return both and its size."""
    ugrid = cache / f"ugrid_{nodes}_{records}.nc"
    sww = cache / f"anuga_{nodes}_{records}.sww"
    if ugrid.exists() and sww.exists():
        import netCDF4

        with netCDF4.Dataset(sww) as nc:
            size = (len(nc.dimensions["number_of_points"]),)
            size += (len(nc.dimensions["number_of_volumes"]),)
        return ugrid, sww, size
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(50)
    x0, y0, x1, y1 = SQUARE
    corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
    inner = rng.uniform((x0, y0), (x1, y1), size=(nodes - 4, 2))
    points = np.vstack([corners, inner])
    triangles = Delaunay(points).simplices.astype(np.int32)
    t = np.linspace(0.0, M2, records)
    # a tidal stream: strongest through a channel across the square's middle
    gx, gy = (points[:, 0] - x0) / (x1 - x0), (points[:, 1] - y0) / (y1 - y0)
    peak = 0.5 + 3.0 * np.exp(-(((gy - 0.5) / 0.15) ** 2)) * (1 + 0.2 * np.sin(9 * gx))
    phase = np.cos(2 * np.pi * t / M2)[:, None]
    u = (peak * phase).astype(np.float32)
    v = (0.1 * peak * np.sin(2 * np.pi * t / M2)[:, None]).astype(np.float32)
    _write_ugrid(ugrid, points, triangles, t, np.hypot(u, v))
    _write_sww(sww, points, triangles, t, u, v)
    return ugrid, sww, (len(points), len(triangles))


def _write_ugrid(path: Path, points: Any, triangles: Any, t: Any, speed: Any) -> None:
    """Write a UGRID netCDF file with xugrid: the node variable ``current_speed``."""
    import xarray as xr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numba is not installed: no matter here
        import xugrid as xu

    grid = xu.Ugrid2d(points[:, 0], points[:, 1], -1, triangles, crs=UTM)
    data = xr.DataArray(
        speed, dims=("time", grid.node_dimension),
        attrs={"long_name": "depth-averaged current speed", "units": "m s-1"},
    )  # fmt: skip
    dataset = xu.UgridDataset(grids=[grid])
    dataset["current_speed"] = xu.UgridDataArray(data, grid)
    dataset["time"] = ("time", t, {"units": "seconds since 2000-01-01 00:00:00"})
    partial = path.with_suffix(".partial.nc")
    dataset.ugrid.to_netcdf(partial)
    partial.rename(path)


def _write_sww(path: Path, points: Any, triangles: Any, t: Any, u: Any, v: Any) -> None:
    """Write an ANUGA ``.sww``: the layout of ``anuga/file/sww.py`` (netCDF-3)."""
    import netCDF4

    x0, y0 = SQUARE[:2]
    bed = -(20.0 + 40.0 * (points[:, 0] - x0) / (SQUARE[2] - x0))
    stage = (0.5 * np.sin(2 * np.pi * t / M2))[:, None] + np.zeros(len(points))
    height = stage - bed
    partial = path.with_suffix(".partial.sww")
    with netCDF4.Dataset(partial, "w", format="NETCDF3_64BIT_OFFSET") as nc:
        nc.setncatts({
            "institution": "Geosciences Australia", "smoothing": "Yes",
            "vertices_are_stored_uniquely": "False", "order": 2,
            "starttime": 0, "timezone": "UTC", "xllcorner": x0, "yllcorner": y0,
            "zone": 30, "hemisphere": "northern", "false_easting": 500000,
            "false_northing": 0, "datum": "wgs84", "projection": "UTM",
            "units": "m", "epsg": 32630,
        })  # fmt: skip
        nc.createDimension("number_of_volumes", len(triangles))
        nc.createDimension("number_of_vertices", 3)
        nc.createDimension("number_of_points", len(points))
        nc.createDimension("number_of_timesteps", len(t))
        on_points = ("number_of_points",)
        series = ("number_of_timesteps", "number_of_points")
        nc.createVariable("x", "f4", on_points)[:] = points[:, 0] - x0
        nc.createVariable("y", "f4", on_points)[:] = points[:, 1] - y0
        volumes = ("number_of_volumes", "number_of_vertices")
        nc.createVariable("volumes", "i4", volumes)[:] = triangles
        nc.createVariable("elevation", "f4", on_points)[:] = bed
        nc.createVariable("time", "f8", ("number_of_timesteps",))[:] = t
        for name, values in (
            ("stage", stage), ("xmomentum", u * height), ("ymomentum", v * height),
        ):  # fmt: skip
            nc.createVariable(name, "f4", series)[:] = values.astype(np.float32)
    partial.rename(path)


#: The steps of a mesh source timed, in order; the last is the whole term.
STEPS = ("read", "reduce", "sample", "sample_field", "term")


def mesh_runs(
    args: argparse.Namespace,
) -> tuple[str, dict[str, dict[str, Callable[[], Any]]]]:
    """Make the mesh sources and the grid; return a note and each one's steps."""
    import shapely

    from coastmesh.case import SizeConfig
    from coastmesh.case.config import PYTHON_SOURCE
    from coastmesh.case.schema import Check, check_part
    from coastmesh.case.terms import ChannelConfig, CourantConfig, FieldConfig, Fields
    from coastmesh.io.fields.field_sources import read_field_source
    from coastmesh.io.fields.field_values import _recipe, _reduced, sample_field
    from coastmesh.sizing.fields import triangles_on_grid
    from coastmesh.sizing.grid import PlaneGrid, grid_axes
    from coastmesh.types import BoundarySegment, Domain

    started = time.perf_counter()
    ugrid, sww, (n_nodes, n_triangles) = make_mesh(args.cache, args.nodes, args.records)
    made = time.perf_counter() - started
    x0, y0, x1, y1 = SQUARE
    ring = [[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]
    domain = Domain(
        shapely.Polygon(ring),
        (
            BoundarySegment(ring[:2], "open", "south", 2),
            BoundarySegment(ring[1:], "shoreline", "coast", 1),
        ),
        crs=UTM,
    )
    cell = (x1 - x0) / (args.grid - 1)
    grid = PlaneGrid(*grid_axes(SQUARE, cell), UTM, cell, domain)
    sea = grid.sea
    common = {
        "h_max": "10 km", "h_min": "50 m", "cell": cell,
        "channels": ChannelConfig(enabled=False),
        "courant": CourantConfig(enabled=False),
    }  # fmt: skip
    runs = {}
    for label, path, variable in (
        ("ugrid", ugrid, "current_speed"),
        ("sww", sww, "speed"),
    ):
        # refine where the peak speed is 1 m/s and more, more so from 2 m/s
        entry = FieldConfig(
            values=(1.0, 2.0), sizes=("200 m", "50 m"), source=path,
            variable=variable, reduce="max",
        )  # fmt: skip
        size = check_part(
            SizeConfig(fields=[entry], **common),
            SizeConfig,
            Check(PYTHON_SOURCE),
            "mesh_size",
        )
        term = partial(_term_sizes, Fields(), grid, size, domain)
        if args.once:
            runs[label] = {"term": term}
            continue
        # the steps of sample_field (coastmesh.io.fields.field_values), one by one
        source = read_field_source(path)
        record, arrays, per = _recipe(source, variable, "bench")
        values = _reduced(source, record, arrays, "max", None, "bench", variable)
        runs[label] = {
            "read": partial(read_field_source, path),
            "reduce": partial(
                _reduced, source, record, arrays, "max", None, "bench", variable
            ),
            "sample": partial(
                triangles_on_grid,
                source.points,
                source.triangles,
                grid.x,
                grid.y,
                values,
                per=per,
            ),
            "sample_field": partial(
                sample_field, grid, path, variable=variable, reduce="max"
            ),
            "term": term,
        }
    note = (
        f"\n### 2. A mesh source: {n_nodes:,} nodes, {n_triangles:,} triangles, "
        f"{args.records} float32 records (a 100 km square, UTM 30N)\n\n"
        f"Size grid {grid.shape[1]} x {grid.shape[0]} nodes, cell {cell:.0f} m, "
        f"{int(sea.sum()):,} sea nodes; inputs made in {made:.1f} s (or cached). "
        f"{args.runs} runs after {args.warmup}, the steps in turn.\n"
    )
    return note, runs


def bench_mesh(args: argparse.Namespace) -> None:
    """Time a 1-million-node mesh source: read, reduce, sample; and the term."""
    note, runs = mesh_runs(args)
    print(note)
    names = {
        "read": "read (`read_field_source`: nodes, faces, metadata)",
        "reduce": f"reduce (max over {args.records} records: reads them)",
        "sample": "sample (`triangles_on_grid`)",
        "sample_field": "`sample_field`, all (read, reduce, sample, edges)",
        "term": "the term's sizes (`Fields().sizes`)",
    }
    sources = {"ugrid": "UGRID `current_speed`", "sww": "ANUGA .sww `speed`"}
    print("| source | step | min s | median s | max s |")
    print("|---|---|---:|---:|---:|")
    medians = {}
    for label, steps in runs.items():
        times = timed_runs(steps, args.runs, args.warmup)
        for step in STEPS:
            print(f"| {sources[label]} | {names[step]} | {spread(times[step])} |")
        medians[label] = statistics.median(times["term"])
    print(
        f"\nTarget: the term on a 1-million-node UGRID source <= {TARGET_SECONDS:g} s;"
        " its median here: "
        + ", ".join(f"{sources[k]} {v:.2f} s" for k, v in medians.items())
    )
    if args.profile:
        for label, steps in runs.items():
            profiled(steps["term"], f"the fields term's sizes from {sources[label]}")


def _term_sizes(term: Any, grid: Any, size: Any, domain: Any) -> Any:
    """Return ``term``'s sizes on ``grid`` in a new case of ``size``."""
    return term.sizes(grid, _mesh_case(size, domain))


def _mesh_case(size: Any, domain: Any) -> Any:
    """Return a case of ``size`` (the fields term reads no raster through it)."""
    from coastmesh.case.config import floor
    from coastmesh.case.terms.base import SizeCase, SizeTables

    def read(part: Any) -> Any:
        raise AssertionError(f"no raster part is read here: {part}")

    return SizeCase(SizeTables(size), domain, floor(size), read_depth=read)


def main(argv: list[str] | None = None) -> None:
    """Make the inputs (once), time both targets, print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cache",
        type=Path,
        default=Path("~/.cache/coastmesh/bench_fields"),
        help="where the big inputs are made and kept",
    )
    parser.add_argument("--only", choices=("raster", "mesh"), default=None)
    parser.add_argument("--runs", type=int, default=5, help="counted runs")
    parser.add_argument("--warmup", type=int, default=1, help="runs not counted")
    parser.add_argument("--cells", type=int, default=10_000_000, help="raster cells")
    parser.add_argument(
        "--grid", type=int, default=1000, help="about GRID x GRID size grid nodes"
    )
    parser.add_argument("--nodes", type=int, default=1_000_000, help="mesh nodes")
    parser.add_argument("--records", type=int, default=24, help="time records")
    parser.add_argument(
        "--profile", action="store_true", help="cProfile the field term's runs"
    )
    parser.add_argument(
        "--once",
        choices=ONCE,
        help="make the inputs, run this once and print its seconds, nothing else "
        "(for a whole-process timer, /usr/bin/time -v: the peak memory)",
    )
    args = parser.parse_args(argv)
    if args.runs < 1 or args.warmup < 0:
        parser.error("--runs must be >= 1 and --warmup >= 0")
    args.cache = args.cache.expanduser()
    if args.cache.resolve().is_relative_to(ROOT):
        parser.error(f"--cache {args.cache}: keep the inputs outside the repository")
    args.cache.mkdir(parents=True, exist_ok=True)
    if args.once:
        what, step = args.once.rsplit("-", 1)
        if what in ("ugrid", "sww"):
            func = mesh_runs(args)[1][what][step]
        else:
            func = raster_runs(args)[1][f"{what} {step}"]
        started = time.perf_counter()
        func()
        print(f"{args.once}: {time.perf_counter() - started:.2f} s")
        return
    if args.only in (None, "raster"):
        bench_raster(args)
    if args.only in (None, "mesh"):
        bench_mesh(args)


if __name__ == "__main__":
    main()
