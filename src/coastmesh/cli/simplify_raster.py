"""``coastmesh simplify-raster``: PCA approximation of a bathymetry raster."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from coastmesh.cli._common import ProgressBar, translate_errors
from coastmesh.cli.options import (
    RASTER_WINDOW,
    bbox_option,
    crs_option,
    in_out_arguments,
    overwrite_option,
    plot_option,
)

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["simplify_raster"]


@click.command("simplify-raster")
@in_out_arguments
@click.option(
    "--window",
    type=RASTER_WINDOW,
    default="8",
    show_default=True,
    metavar="CELLS",
    help="Window size in cells: 8 for 8 x 8, or ROWSxCOLUMNS such as 8x6.",
)
@click.option(
    "--modes",
    type=click.IntRange(min=1),
    default=16,
    show_default=True,
    metavar="N",
    help="Leading PCA modes kept, from 1 (smoothest) to the cells in a window "
    "(64 for 8 x 8: no change).",
)
@bbox_option
@crs_option
@plot_option
@click.option(
    "-w",
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    metavar="N",
    help="Threads to compute the chunks of a GeoTIFF output on (default: all "
    "cores). The output is the same for any number.",
)
@click.option(
    "--scheduler",
    metavar="ADDRESS",
    default=None,
    help="Compute the chunks as tasks on this Dask cluster (e.g. "
    "tcp://10.0.0.5:8786), whose workers read IN at the same path. Start one "
    "with `dask scheduler` and `dask worker ADDRESS`.",
)
@click.option(
    "--memory",
    "memory_mb",
    type=click.FloatRange(min=16),
    default=768,
    show_default=True,
    metavar="MB",
    help="Working memory of each worker thread, in megabytes: sets the size of "
    "the chunks a GeoTIFF output is streamed in.",
)
@overwrite_option
@click.pass_context
@translate_errors
def simplify_raster(
    ctx: click.Context,
    *,
    src: Path,
    dst: Path,
    window: int | tuple[int, int],
    modes: int,
    bbox: tuple[float, float, float, float] | None,
    crs: CRS | None,
    plot: Path | None,
    workers: int | None,
    scheduler: str | None,
    memory_mb: float,
    overwrite: bool,
) -> None:
    """Approximate the raster IN by PCA; write OUT.

    IN is any raster GDAL reads (GeoTIFF, GEBCO-style NetCDF with lat/lon, ...);
    band 1 is used. Each cell becomes the mean of its PCA reconstructions over the
    overlapping windows of --window cells holding it; cells that no full window
    of valid cells covers keep their value, and nodata stays nodata. OUT (.tif or
    .nc) keeps the georeferencing, CRS, data type and nodata value.

    A GeoTIFF OUT is streamed: IN is read, computed and written in chunks, on
    all cores or a Dask cluster, in bounded memory (about --memory per worker),
    so a raster of any size works. A NetCDF OUT is computed in memory.

    \b
    Example:
      coastmesh simplify-raster gebco.nc gebco_8x8_r16.tif --window 8 --modes 16
    """  # noqa: D301 (\b keeps click from rewrapping the example)
    rows, columns = window if isinstance(window, tuple) else (window, window)
    if modes > rows * columns:
        raise click.BadParameter(
            f"{modes} is more than the {rows * columns} cells of a {rows} x {columns} "
            f"window; use 1 to {rows * columns}",
            param_hint="'--modes'",
        )
    from coastmesh.commands.simplify_raster import simplify_raster_file

    quiet = ctx.find_root().obj.get("quiet", False)
    with ProgressBar("raster stages", enabled=not quiet) as progress:
        report = simplify_raster_file(
            src,
            dst,
            window=window,
            modes=modes,
            bbox=bbox,
            crs=crs,
            overwrite=overwrite,
            plot=plot,
            progress=progress,
            workers=workers,
            scheduler=scheduler,
            memory_mb=memory_mb,
        )
    if not quiet:
        written = f"{dst}" + (f" and {plot}" if plot is not None else "")
        click.echo(f"{report.summary()}; wrote {written}")
