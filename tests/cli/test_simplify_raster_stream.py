"""``coastmesh simplify-raster`` streamed: chunks as Dask tasks, the in-memory result.

A GeoTIFF output is computed chunk by chunk (coastmesh.commands.raster_stream),
each task reading its own cells from the file. These tests check it against the
in-memory kernel (1e-9 on float64 files), against the in-memory command (the
same file but for rounding to float32), and its failure modes.
"""

from __future__ import annotations

import re
import time
import warnings

import numpy as np
import pytest
import rasterio
from affine import Affine
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from coastmesh.case import executor
from coastmesh.commands import raster_stream, simplify_raster_file
from coastmesh.commands.raster_chunks import plan_chunks
from coastmesh.commands.raster_stream import open_client, stream_raster
from coastmesh.errors import FormatError
from coastmesh.io.rasters.raster import read_raster
from coastmesh.io.rasters.raster_stream import (
    RasterWriter,
    open_raster_source,
    read_cells,
    read_decimated,
)
from coastmesh.pca import simplify_raster

TRANSFORM = Affine(100.0, 0.0, 500000.0, 0.0, -100.0, 6500000.0)


@pytest.fixture(scope="module")
def client():
    """Two threads in this process, as the command runs by default."""
    with open_client(2) as dask_client:
        yield dask_client


def write_grid(path, grid, *, nodata=None, dtype="float64", transform=TRANSFORM):
    """A plain GeoTIFF of ``grid`` (NaN written as ``nodata`` if given)."""
    values = grid if nodata is None else np.where(np.isnan(grid), nodata, grid)
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        height=grid.shape[0],
        width=grid.shape[1],
        count=1,
        dtype=dtype,
        crs="EPSG:32630",
        transform=transform,
        nodata=nodata,
    ) as dataset:
        dataset.write(values.astype(dtype), 1)
    return path


def surface(seed, ny, nx, holes):
    rng = np.random.default_rng(seed)
    grid = np.cumsum(np.cumsum(rng.standard_normal((ny, nx)), 0), 1) - 50.0
    grid[rng.random((ny, nx)) < holes] = np.nan
    return grid


def stream(client, src, dst, window, modes, *, rows=None, columns=None):
    source = open_raster_source(src)
    plan = plan_chunks(source.shape, window, rows=rows, columns=columns)
    totals = stream_raster(
        source,
        dst,
        window=window,
        modes=modes,
        client=client,
        crs=source.crs,
        notes={"history": "test"},
        plan=plan,
    )
    return totals, plan


def _well_posed(grid, window, modes) -> bool:
    from coastmesh.pca import raster_modes

    if modes == window[0] * window[1]:
        return True
    try:
        lam = raster_modes(grid, window)
    except ValueError:
        return True
    return lam[modes - 1] - lam[modes] >= 1e-6 * max(lam[0], 1e-300)


@settings(
    deadline=None,
    max_examples=20,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    seed=st.integers(0, 2**32 - 1),
    ny=st.integers(8, 56),
    nx=st.integers(8, 56),
    w=st.sampled_from([(2, 2), (3, 3), (4, 3), (5, 5)]),
    modes=st.integers(1, 6),
    holes=st.sampled_from([0.0, 0.02, 0.1]),
    nodata=st.sampled_from([None, -9999.0]),
    rows=st.sampled_from([16, 32, None]),
    columns=st.sampled_from([16, 48, None]),
)
def test_streamed_equals_in_memory(
    client, tmp_path_factory, seed, ny, nx, w, modes, holes, nodata, rows, columns
):
    grid = surface(seed, ny, nx, holes)
    modes = min(modes, w[0] * w[1])
    if not _well_posed(grid, w, modes):
        return
    folder = tmp_path_factory.mktemp("grid")
    src = write_grid(folder / "in.tif", grid, nodata=nodata)
    totals, plan = stream(
        client, src, folder / "out.tif", w, modes, rows=rows, columns=columns
    )
    got = read_raster(folder / "out.tif")
    expected = simplify_raster(grid, w, modes)
    np.testing.assert_array_equal(np.isnan(got.values), np.isnan(grid))
    np.testing.assert_allclose(got.values, expected, rtol=0, atol=1e-9)
    assert got.attrs["dtype"] == "float64"
    assert got.attrs["transform"] == tuple(TRANSFORM)[:6]
    assert totals.cells_missing == int(np.isnan(grid).sum())
    assert totals.chunks == len(plan.chunks)
    if nodata is not None:
        assert got.attrs["nodata"] == nodata


@pytest.mark.parametrize(("rows", "columns"), [(None, None), (48, 128)])
def test_real_shelf_raster(client, nwshelf_tif, tmp_path, rows, columns):
    """ETOPO1 of the NW shelf, land as nodata, in float64: 1e-9 of in memory."""
    grid = read_raster(nwshelf_tif).values
    grid[grid > 0] = np.nan
    src = write_grid(tmp_path / "shelf.tif", grid, nodata=-32768.0)
    _, plan = stream(
        client, src, tmp_path / "out.tif", (8, 8), 16, rows=rows, columns=columns
    )
    assert len(plan.chunks) == (1 if rows is None else 5 * 4)
    got = read_raster(tmp_path / "out.tif").values
    np.testing.assert_allclose(
        got, simplify_raster(grid, 8, 16), rtol=0, atol=1e-9, equal_nan=True
    )


def _same_file_but_rounding(streamed, in_memory):
    a, b = read_raster(streamed), read_raster(in_memory)
    for key in ("transform", "crs", "nodata", "dtype", "units"):
        assert a.attrs.get(key) == b.attrs.get(key), key
    assert a.name == b.name
    np.testing.assert_array_equal(np.isnan(a.values), np.isnan(b.values))
    valid = np.isfinite(a.values)
    if a.attrs["dtype"] == "float32":  # both round the same float64s, to 1e-9
        np.testing.assert_array_max_ulp(
            a.values[valid].astype("float32"), b.values[valid].astype("float32"), 1
        )
    else:
        np.testing.assert_array_equal(a.values, b.values)
    with rasterio.open(streamed) as x, rasterio.open(in_memory) as y:
        tags_x, tags_y = x.tags(), y.tags()
        assert x.profile["compress"] == "deflate" and x.profile["tiled"]
    assert sorted(tags_x) == sorted(tags_y)
    for key in tags_x:
        if key != "history":  # the time stamp differs
            assert tags_x[key] == tags_y[key], key


def test_command_streams_what_it_computed_in_memory(run_cli, nwshelf_tif, tmp_path):
    out = tmp_path / "stream.tif"
    result = run_cli(
        "simplify-raster", nwshelf_tif, out, "--workers", 2, "--memory", 16
    )
    assert result.exit_code == 0, result.output
    reference = simplify_raster_file(
        nwshelf_tif, tmp_path / "memory.tif", window=8, modes=16, stream=False
    )
    _same_file_but_rounding(out, tmp_path / "memory.tif")
    summary = result.stdout.split("; wrote")[0]
    assert re.sub(r"[\d.]+ s$", "", summary) == re.sub(
        r"[\d.]+ s$", "", reference.summary()
    )


def test_integer_raster_with_nodata_and_a_south_up_grid(run_cli, tmp_path):
    grid = np.round(surface(4, 300, 280, 0.03) * 10)
    south_up = Affine(100.0, 0.0, 500000.0, 0.0, 100.0, 6400000.0)
    src = write_grid(
        tmp_path / "in.tif",
        grid[::-1],
        nodata=-32768,
        dtype="int16",
        transform=south_up,
    )
    out = tmp_path / "stream.tif"
    result = run_cli("simplify-raster", src, out, "--modes", 10, "--memory", 16)
    assert result.exit_code == 0, result.output
    simplify_raster_file(src, tmp_path / "memory.tif", window=8, modes=10, stream=False)
    _same_file_but_rounding(out, tmp_path / "memory.tif")
    assert read_raster(out).attrs["transform"][4] == -100.0  # written north-up
    np.testing.assert_array_equal(np.isnan(read_raster(out).values), np.isnan(grid))


def test_netcdf_in_with_bbox(run_cli, nwshelf_nc, tmp_path):
    bbox = ("-10", "50", "5", "62")
    out = tmp_path / "stream.tif"
    result = run_cli(
        "simplify-raster", nwshelf_nc, out, "--window", "6x8", "--bbox", *bbox
    )
    assert result.exit_code == 0, result.output
    simplify_raster_file(
        nwshelf_nc,
        tmp_path / "memory.tif",
        window=(6, 8),
        modes=16,
        bbox=[float(v) for v in bbox],
        stream=False,
    )
    _same_file_but_rounding(out, tmp_path / "memory.tif")


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    """600 x 700 cells with holes: 12 chunks at --memory 16."""
    grid = surface(8, 600, 700, 0.01)
    grid[100:160, 200:420] = np.nan  # an island
    return write_grid(
        tmp_path_factory.mktemp("synthetic") / "in.tif",
        grid,
        nodata=-9999.0,
        dtype="float32",
    )


def test_workers_do_not_change_the_output(run_cli, synthetic, tmp_path):
    values = []
    for workers in (1, 2):
        out = tmp_path / f"w{workers}.tif"
        result = run_cli(
            "simplify-raster", synthetic, out, "--workers", workers, "--memory", 16
        )
        assert result.exit_code == 0, result.output
        values.append(read_raster(out).values)
    assert plan_chunks((600, 700), (8, 8), memory_mb=16).chunks[1:] != []
    np.testing.assert_array_equal(values[0], values[1])  # bit for bit


def test_a_failing_task_leaves_nothing(
    run_cli, synthetic, tmp_path, monkeypatch, folder_listing
):
    rebuild = raster_stream.rebuild_task

    def flaky(source, rows, columns, *args):  # pass 2: after others were written
        if (rows, columns) == ((256, 512), (256, 512)):  # the middle one of 9
            raise RuntimeError("worker lost its disk")
        return rebuild(source, rows, columns, *args)

    monkeypatch.setattr(raster_stream, "rebuild_task", flaky)
    out = tmp_path / "out" / "d.tif"
    result = run_cli(
        "simplify-raster",
        synthetic,
        out,
        "--memory",
        16,
        "--plot",
        tmp_path / "out" / "d.png",
    )
    assert result.exit_code != 0
    assert "worker lost its disk" in str(result.exception)
    assert folder_listing(tmp_path) == []  # no output, no staging, no folder


def test_an_unreachable_scheduler_fails_fast_and_writes_nothing(
    run_cli, orkney_tif, tmp_path, monkeypatch
):
    monkeypatch.setattr(executor, "SCHEDULER_TIMEOUT", 2.0)
    start = time.perf_counter()
    result = run_cli(
        "simplify-raster",
        orkney_tif,
        tmp_path / "d.tif",
        "--scheduler",
        "tcp://127.0.0.1:9",
    )
    assert time.perf_counter() - start < 15
    assert result.exit_code == 2
    assert "scheduler = 'tcp://127.0.0.1:9': no Dask scheduler" in result.output
    assert "dask scheduler" in result.output
    assert list(tmp_path.iterdir()) == []


def test_a_scheduler_needs_a_geotiff(run_cli, orkney_tif, tmp_path):
    result = run_cli(
        "simplify-raster",
        orkney_tif,
        tmp_path / "d.nc",
        "--scheduler",
        "tcp://127.0.0.1:9",
    )
    assert result.exit_code == 2
    assert "only a GeoTIFF output is streamed" in result.output
    assert list(tmp_path.iterdir()) == []


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_a_cluster_of_processes_gives_the_local_output(run_cli, synthetic, tmp_path):
    from distributed import LocalCluster

    with (
        warnings.catch_warnings(),
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
    ):
        out = tmp_path / "cluster.tif"
        result = run_cli(
            "simplify-raster",
            synthetic,
            out,
            "--memory",
            16,
            "--scheduler",
            cluster.scheduler_address,
        )
    assert result.exit_code == 0, result.output
    local = tmp_path / "local.tif"
    assert run_cli("simplify-raster", synthetic, local, "--memory", 16).exit_code == 0
    np.testing.assert_array_equal(read_raster(out).values, read_raster(local).values)


def test_the_figure_comes_from_a_decimated_read(
    run_cli, synthetic, tmp_path, monkeypatch
):
    from coastmesh.io.rasters import raster as raster_io
    from coastmesh.io.rasters import raster_stream as stream_io

    def whole_grid(*args, **kwargs):
        raise AssertionError("the whole grid was read")

    monkeypatch.setattr(raster_io, "read_raster", whole_grid)
    monkeypatch.setattr(
        stream_io, "read_decimated", _spy(stream_io.read_decimated, seen := [])
    )
    monkeypatch.setattr(stream_io, "_DECIMATED_CELLS", 5000)
    result = run_cli(
        "simplify-raster", synthetic, tmp_path / "d.tif", "--plot", tmp_path / "d.png"
    )
    assert result.exit_code == 0, result.output
    assert (tmp_path / "d.png").read_bytes()[:4] == b"\x89PNG"
    assert len(seen) == 2


def _spy(function, calls):
    def spy(*args, **kwargs):
        calls.append(args)
        return function(*args, **kwargs)

    return spy


def test_decimated_reads_sample_the_same_cells(tmp_path):
    grid = surface(3, 50, 70, 0.1)
    south_up = Affine(1.0, 0.0, 10.0, 0.0, 1.0, 20.0)
    north = open_raster_source(write_grid(tmp_path / "n.tif", grid, nodata=-1.0))
    south = open_raster_source(
        write_grid(tmp_path / "s.tif", grid[::-1], nodata=-1.0, transform=south_up)
    )
    assert south.flipped and not north.flipped
    for source in (north, south):
        np.testing.assert_array_equal(
            read_cells(source, (3, 9), (5, 40)), grid[3:9, 5:40]
        )
        small = read_decimated(source, max_size=20)
        np.testing.assert_array_equal(small.values, grid[::4, ::4])
        assert small.attrs["transform"][0] == 4 * source.transform[0]
    with pytest.raises(ValueError, match=r"rows \[40, 60\) are outside"):
        read_cells(north, (40, 60))


def test_progress_reaches_the_end(synthetic, tmp_path):
    calls = []
    simplify_raster_file(
        synthetic,
        tmp_path / "d.tif",
        window=8,
        modes=4,
        memory_mb=16,
        workers=2,
        progress=lambda done, total: calls.append((done, total)),
    )
    total = calls[0][1]
    assert [done for done, _ in calls] == list(range(1, total + 1))
    assert total == 2 * len(plan_chunks((600, 700), (8, 8), memory_mb=16).chunks)


def test_the_writer_refuses_bad_tiles_and_cells(tmp_path):
    with pytest.raises(FormatError, match="multiples of 16"):
        RasterWriter(
            tmp_path / "a.tif",
            shape=(10, 10),
            transform=tuple(TRANSFORM),
            crs=None,
            dtype="float32",
            nodata=None,
            tile=(10, 16),
        )
    with RasterWriter(
        tmp_path / "b.tif",
        shape=(10, 10),
        transform=tuple(TRANSFORM),
        crs=None,
        dtype="float32",
        nodata=None,
    ) as writer:
        with pytest.raises(ValueError, match="do not fit"):
            writer.write(np.zeros((4, 4), "float32"), row=8)
        with pytest.raises(ValueError, match="the file holds float32"):
            writer.write(np.zeros((4, 4)))
