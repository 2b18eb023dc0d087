"""``coastmesh convert``: a mesh from any readable format to any other, with depth."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from coastmesh.cli._common import translate_errors
from coastmesh.cli.options import crs_option, overwrite_option

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["convert"]


def _ids(ctx: click.Context, param: click.Parameter, value: str | None):
    if value is None:
        return None
    try:
        return [int(v) for v in value.split(",") if v.strip()]
    except ValueError:
        raise click.BadParameter(
            f"{value!r}: give boundary ids separated by commas, e.g. 2,3,4"
        ) from None


def _write_options(
    ctx: click.Context, param: click.Parameter, values: tuple[str, ...]
) -> dict[str, object]:
    """``NAME=VALUE`` pairs; true/false become booleans, numbers numbers."""
    out: dict[str, object] = {}
    for text in values:
        name, sep, raw = text.partition("=")
        if not sep or not name.strip():
            raise click.BadParameter(f"{text!r}: expected NAME=VALUE", ctx, param)
        value: object = raw
        if raw.lower() in ("true", "false"):
            value = raw.lower() == "true"
        else:
            for kind in (int, float):
                try:
                    value = kind(raw)
                    break
                except ValueError:
                    pass
        out[name.strip()] = value
    return out


@click.command("convert")
@click.argument("src", metavar="MESH", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("dst", metavar="OUT", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--format",
    "fmt",
    metavar="NAME",
    help="Output format by name ('coastmesh formats' lists them); by default "
    "OUT's extension decides.",
)
@click.option(
    "--bathymetry",
    type=click.Path(dir_okay=False, path_type=Path),
    metavar="RASTER",
    multiple=True,
    help="Interpolate this raster (any GDAL raster, any CRS) onto the nodes as "
    "depth. Repeat for several, highest priority first.",
)
@click.option(
    "--raster-positive",
    type=click.Choice(["up", "down"]),
    multiple=True,
    help="Sign of the raster: up (default) for elevations (GEBCO, ETOPO), down "
    "for depths. Once for all rasters, or once per --bathymetry.",
)
@click.option(
    "--blend",
    type=click.FloatRange(min=0),
    multiple=True,
    metavar="M",
    help="Metres inside a raster's data edge over which it blends into the next "
    "(default 0). Once for all, or once per --bathymetry.",
)
@click.option(
    "--outside",
    type=click.Choice(["error", "nearest"]),
    default="error",
    show_default=True,
    help="Nodes beyond every raster: an error, or the nearest valid cell.",
)
@click.option(
    "--land",
    type=click.Choice(["wet", "min_depth", "nearest_sea", "smooth", "keep"]),
    default=None,
    help="Nodes beside or on land in the rasters. Default wet: read the wet cells "
    "alone, and give nodes with none around the nearest wet cell, tapered to "
    "--min-depth at the coast; with it, more than half the nodes on land is an "
    "error. min_depth: the depth floor; nearest_sea: the nearest wet cell; "
    "smooth: that and a taper to --min-depth over --land-distance; keep: land "
    "heights as negative depths (wetting and drying).",
)
@click.option(
    "--land-distance",
    type=click.FloatRange(min=0, min_open=True),
    metavar="M",
    help="Width of the coastal taper of --land smooth, metres.",
)
@click.option(
    "--method",
    type=click.Choice(["bilinear", "mean"]),
    default="bilinear",
    show_default=True,
    help="mean: average the cells around each node where the mesh is coarser.",
)
@click.option("--min-depth", type=float, metavar="M", help="Raise depths to this.")
@click.option(
    "--max-slope",
    type=click.FloatRange(min=0, min_open=True),
    metavar="S",
    help="Limit |depth difference| / edge length along every edge.",
)
@click.option(
    "--positive",
    type=click.Choice(["up", "down"]),
    help="Sign written (default: the format's own: down for fort.14/gr3, "
    "up for Telemac BOTTOM and MIKE).",
)
@click.option(
    "--open-ids",
    callback=_ids,
    metavar="IDS",
    help="Boundary ids that are open boundaries, e.g. 2,3,4 (default: the kinds "
    "MESH stores: msh physical names open:NAME, fort.14/gr3 open and land lists, "
    "UGRID, GeoPackage, MIKE codes).",
)
@click.option(
    "--write-option",
    "write_options",
    multiple=True,
    callback=_write_options,
    metavar="NAME=VALUE",
    help="An option of OUT's writer (repeat for more), e.g. land=natural for a "
    "fort.14 with ADCIRC's natural land types (IBTYPE 20/21, not 0/1); "
    "`coastmesh formats` lists each writer's options.",
)
@crs_option
@overwrite_option
@click.pass_context
@translate_errors
def convert(
    ctx: click.Context,
    *,
    src: Path,
    dst: Path,
    fmt: str | None,
    bathymetry: tuple[Path, ...],
    raster_positive: tuple[str, ...],
    blend: tuple[float, ...],
    outside: str,
    land: str | None,
    land_distance: float | None,
    method: str,
    min_depth: float | None,
    max_slope: float | None,
    positive: str | None,
    open_ids: list[int] | None,
    write_options: dict[str, object],
    crs: CRS | None,
    overwrite: bool,
) -> None:
    """Read the mesh MESH and write it in the format of OUT's extension.

    \b
    MESH can be read from: .msh (msh 2.2 or 4.1), .14 / .grd (ADCIRC fort.14),
    .gr3 / .ll (SCHISM), .nc (UGRID), .vtu, .gpkg (coastmesh's mesh layers),
    .mesh (MIKE); the boundary ids, kinds and depth come along where the file
    has them. --crs is for files that store no CRS (msh, vtu; default
    EPSG:4326).
    \b
    OUT extensions: .msh (msh 2.2), .14 / .grd (ADCIRC fort.14), .gr3 (SCHISM),
    .slf (Telemac SELAFIN + .cli), .mesh (MIKE), .vtu, .nc (UGRID), .gpkg.

    \b
    Example:
      coastmesh convert out/case/case.msh fort.14 --bathymetry gebco.nc --min-depth 5
      coastmesh convert case.msh case.nc --bathymetry survey.tif --raster-positive \\
        down --blend 2000 --bathymetry gebco.nc --raster-positive up --min-depth 5
    """  # noqa: D301 (\b keeps click from rewrapping the lists)
    from coastmesh.commands.convert import convert_mesh

    result = convert_mesh(
        src,
        dst,
        format=fmt,
        crs=crs,
        open_ids=open_ids,
        bathymetry=bathymetry or None,
        raster_positive=raster_positive or "up",
        blend=blend or 0.0,
        outside=outside,
        land=land,
        land_distance=land_distance,
        method=method,
        min_depth=min_depth,
        max_slope=max_slope,
        positive=positive,
        options=write_options,
        overwrite=overwrite,
    )
    for line in result.repaired:
        click.echo(f"{src}: repaired: {line}", err=True)
    if not ctx.find_root().obj.get("quiet", False):
        click.echo(result.summary())
