"""``coastmesh patch``: a site remeshed into an existing mesh, the rest kept."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from coastmesh.cli._common import translate_errors
from coastmesh.cli.options import CRS_OPTION_TYPE, overwrite_option

if TYPE_CHECKING:
    from pyproj import CRS

__all__ = ["patch"]


def _length(ctx: click.Context, param: click.Parameter, value: str | None):
    if value is None:
        return None
    from coastmesh.case.schema import length
    from coastmesh.errors import ConfigError

    try:
        return length()(_number_or_text(value), "--distance")
    except ConfigError as exc:
        raise click.BadParameter(str(exc), ctx, param) from None


def _number_or_text(value: str) -> float | str:
    """Return a bare number as metres; anything else as a length with a unit."""
    try:
        return float(value)
    except ValueError:
        return value


@click.command("patch")
@click.argument("mesh", metavar="MESH", type=click.Path(dir_okay=False, path_type=Path))
@click.argument(
    "case", metavar="CASE.toml", type=click.Path(dir_okay=False, path_type=Path)
)
@click.option(
    "-o",
    "--output",
    type=click.Path(file_okay=False, path_type=Path),
    required=True,
    help="Output folder: the patched mesh (MESH's name and format), report.json, "
    "summary.txt and figures/patch.png.",
)
@click.option(
    "--polygon",
    type=click.Path(dir_okay=False, path_type=Path),
    metavar="FILE",
    help="A vector file (any CRS) of the region to remesh. Default: the case's "
    "farms, turbines, wakes and lines, grown by --distance.",
)
@click.option(
    "--distance",
    metavar="LENGTH",
    callback=_length,
    help="How far to grow the site, e.g. '3 km'. Default: the distance over which "
    "the site's smallest size grows to the mesh's there at the case's rate, plus "
    "two of the mesh's elements.",
)
@click.option(
    "--format",
    "formats",
    metavar="NAME",
    multiple=True,
    help="Also write the patched mesh in this format ('coastmesh formats' lists "
    "them). Repeat for several.",
)
@click.option(
    "--crs",
    type=CRS_OPTION_TYPE,
    metavar="CRS",
    help="CRS of MESH when the file stores none (msh, VTU, a fort.14 from "
    "another tool), e.g. EPSG:4326.",
)
@click.option(
    "-w",
    "--workers",
    type=click.IntRange(min=1),
    default=1,
    help="Threads for the size field (default 1).",
)
@overwrite_option
@click.pass_context
@translate_errors
def patch(
    ctx: click.Context,
    *,
    mesh: Path,
    case: Path,
    output: Path,
    polygon: Path | None,
    distance: float | None,
    formats: tuple[str, ...],
    crs: CRS | None,
    workers: int,
    overwrite: bool,
) -> None:
    """Remesh a site into an existing mesh; keep everything outside exactly.

    MESH is the mesh you have (fort.14, hgrid.gr3, SELAFIN + .cli, msh, UGRID,
    ...), CASE.toml the site: its [[farms]], [[turbines]], [[wakes]], [[lines]],
    [mesh_size] and [bathymetry] (its shorelines and open boundaries are not
    used). The elements that meet the polygon are cut out and the hole is
    meshed on the kept nodes around it, so every node and element outside
    keeps its number, coordinates, depth and boundary lists; the new nodes and
    elements take the numbers of those cut out, then follow the last. See
    docs/patching.md.
    """
    from coastmesh.commands.patch import patch_files

    result = patch_files(
        mesh,
        case,
        output,
        polygon=polygon,
        distance=distance,
        crs=crs,
        formats=formats,
        overwrite=overwrite,
        threads=workers,
    )
    if not ctx.find_root().obj.get("quiet", False):
        click.echo(result.summary())
