"""``coastmesh simplify-shoreline``: PCA approximation of a vector shoreline."""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING

import click

from coastmesh.cli._common import ProgressBar, translate_errors
from coastmesh.cli.options import (
    bbox_option,
    crs_option,
    in_out_arguments,
    overwrite_option,
    plot_option,
)

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["simplify_shoreline"]


@click.command("simplify-shoreline")
@in_out_arguments
@click.option(
    "--window",
    type=click.IntRange(min=2),
    default=100,
    show_default=True,
    metavar="POINTS",
    help="Partition size, in points (vertices) along each ring or line. Rings and "
    "lines with fewer points are dropped.",
)
@click.option(
    "--modes",
    type=click.IntRange(min=1),
    default=1,
    show_default=True,
    metavar="N",
    help="Leading PCA modes kept, from 1 (smoothest) to the window size (no change).",
)
@click.option("--layer", help="Layer of IN to read; needed if IN has several.")
@bbox_option
@crs_option
@plot_option
@overwrite_option
@click.pass_context
@translate_errors
def simplify_shoreline(
    ctx: click.Context,
    *,
    src: Path,
    dst: Path,
    window: int,
    modes: int,
    layer: str | None,
    bbox: tuple[float, float, float, float] | None,
    crs: CRS | None,
    plot: Path | None,
    overwrite: bool,
) -> None:
    """Approximate the shoreline IN by PCA; write OUT.

    IN is any vector file GDAL reads (GSHHG shapefile, GeoPackage, GeoJSON, ...)
    holding polygons (outer rings and holes) or lines. Every ring and line is
    approximated from the leading modes of its overlapping windows of --window
    points. OUT (.gpkg, .shp, .geojson, .fgb) keeps the CRS and the attributes;
    polygons that the smoothing made self-intersect are repaired.

    \b
    Example:
      coastmesh simplify-shoreline coast.shp coast_L100.gpkg --window 100
    """  # noqa: D301 (\b keeps click from rewrapping the example)
    if modes > window:
        raise click.BadParameter(
            f"{modes} is more than --window ({window}); use 1 to {window}",
            param_hint="'--modes'",
        )
    from coastmesh.commands.simplify_shoreline import simplify_shoreline_file

    quiet = ctx.find_root().obj.get("quiet", False)
    start = time.perf_counter()
    with ProgressBar("shoreline points", enabled=not quiet) as progress:
        report = simplify_shoreline_file(
            src,
            dst,
            window=window,
            modes=modes,
            layer=layer,
            bbox=bbox,
            crs=crs,
            overwrite=overwrite,
            plot=plot,
            progress=progress,
        )
    seconds = time.perf_counter() - start
    if not quiet:
        written = f"{dst}" + (f" and {plot}" if plot is not None else "")
        click.echo(f"{report.summary()}; {seconds:.1f} s; wrote {written}")
