"""Options shared by several subcommands, defined once.

Parameter types parse and check values when click reads them, so a bad value
is reported with the option's name before any file is opened.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

F = TypeVar("F", bound=Callable[..., Any])

__all__ = [
    "CRS_OPTION_TYPE",
    "RASTER_WINDOW",
    "bbox_option",
    "crs_option",
    "in_out_arguments",
    "overwrite_option",
    "plot_option",
]


class CRSType(click.ParamType):
    """Anything pyproj understands: ``EPSG:4326``, a PROJ string, WKT."""

    name = "crs"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> Any:
        from pyproj import CRS
        from pyproj.exceptions import CRSError

        if isinstance(value, CRS):
            return value
        try:
            return CRS.from_user_input(value)
        except CRSError:
            self.fail(
                f"{value!r} is not a CRS pyproj knows (try EPSG:4326)", param, ctx
            )


class RasterWindowType(click.ParamType):
    """A window in cells: ``8`` (8 x 8) or ``8x6`` (rows x columns)."""

    name = "cells"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> int | tuple[int, int]:
        if isinstance(value, int | tuple):
            return value
        match = re.fullmatch(r"\s*(-?\d+)\s*(?:[x,]\s*(-?\d+)\s*)?", str(value))
        if match is None:
            self.fail(
                f"{value!r}: expected a number of cells such as 8 or 8x6", param, ctx
            )
        rows = int(match.group(1))
        columns = int(match.group(2)) if match.group(2) is not None else rows
        if rows < 2 or columns < 2:
            self.fail(f"{value!r}: each side must be at least 2 cells", param, ctx)
        return rows if match.group(2) is None else (rows, columns)


CRS_OPTION_TYPE = CRSType()
RASTER_WINDOW = RasterWindowType()

overwrite_option = click.option(
    "--overwrite",
    is_flag=True,
    help="Replace existing outputs (a file, or a non-empty output folder). Without "
    "it an existing output is an error and nothing is written.",
)


def _check_bbox(
    ctx: click.Context, param: click.Parameter, value: tuple[float, ...] | None
) -> tuple[float, float, float, float] | None:
    if value is None:
        return None
    from coastmesh.errors import ConfigError
    from coastmesh.io import check_bbox

    try:
        return check_bbox(value)
    except ConfigError as exc:
        raise click.BadParameter(str(exc).removeprefix("bbox = "), ctx, param) from None


bbox_option = click.option(
    "--bbox",
    nargs=4,
    type=float,
    default=None,
    metavar="MINX MINY MAXX MAXY",
    callback=_check_bbox,
    help="Only use this box, in the CRS units of IN (degrees for EPSG:4326), e.g. "
    "--bbox -3.5 58.7 -2.4 59.4.",
)
crs_option = click.option(
    "--crs",
    type=CRS_OPTION_TYPE,
    metavar="CRS",
    help="CRS of IN when the file declares none, e.g. EPSG:4326 or EPSG:32630.",
)


def in_out_arguments(command: F) -> F:
    """Add the arguments IN (any file) and OUT (a file to write) to a command."""
    command = click.argument(
        "dst", metavar="OUT", type=click.Path(dir_okay=False, path_type=Path)
    )(command)
    return click.argument("src", metavar="IN", type=click.Path(path_type=Path))(command)


plot_option = click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path),
    metavar="FILE.png",
    help="Also draw the input and the result to this image (.png, .pdf, .svg, .jpg).",
)
