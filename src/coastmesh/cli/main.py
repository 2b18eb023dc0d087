"""The ``coastmesh`` click group: logging, ``--version``, ``--show-versions``.

Subcommands import their heavy dependencies inside their bodies, so
``coastmesh --help`` stays fast.
"""

from __future__ import annotations

import logging
import os
import platform
import sys
import warnings
from collections.abc import Callable, Sequence
from importlib import metadata
from typing import Any

import click

from coastmesh.cli.convert import convert
from coastmesh.cli.demo import demo
from coastmesh.cli.formats import formats
from coastmesh.cli.patch import patch
from coastmesh.cli.run import run
from coastmesh.cli.simplify_raster import simplify_raster
from coastmesh.cli.simplify_shoreline import simplify_shoreline
from coastmesh.version import __version__

__all__ = ["cli", "main"]

logger = logging.getLogger("coastmesh")

_DEPENDENCIES = (
    "numpy",
    "scipy",
    "shapely",
    "pyproj",
    "pyogrio",
    "rasterio",
    "xarray",
    "netCDF4",
    "click",
    "matplotlib",
)


class _ClickHandler(logging.Handler):
    """Write log records to the current stderr (works under click's CliRunner)."""

    def emit(self, record: logging.LogRecord) -> None:
        click.echo(self.format(record), err=True)


def configure_logging(verbosity: int) -> Callable[[], None]:
    """Send coastmesh's log records to stderr at a level set by ``-v``/``-q``.

    Parameters
    ----------
    verbosity : int
        ``-v`` count minus ``-q`` count: 0 shows warnings, 1 info, 2 debug,
        -1 errors only.

    Returns
    -------
    callable
        Call it to put the ``coastmesh`` logger back as it was.
    """
    level = max(logging.DEBUG, min(logging.CRITICAL, logging.WARNING - 10 * verbosity))
    handler = _ClickHandler()
    handler.setFormatter(logging.Formatter("coastmesh: %(levelname)s: %(message)s"))
    previous_level = logger.level
    logger.addHandler(handler)
    logger.setLevel(level)

    def restore() -> None:
        logger.removeHandler(handler)
        logger.setLevel(previous_level)

    return restore


def _log_warning(message: Warning | str, *_: object, **__: object) -> None:
    """Show a Python warning as one log line (``warnings.showwarning``)."""
    logger.warning("%s", message)


def _show_versions(ctx: click.Context, param: click.Parameter, value: bool) -> None:
    if not value or ctx.resilient_parsing:
        return
    click.echo(f"coastmesh {__version__}")
    click.echo(f"python {platform.python_version()} ({sys.executable})")
    click.echo(f"platform {platform.platform()}")
    for name in _DEPENDENCIES:
        try:
            version = metadata.version(name)
        except metadata.PackageNotFoundError:
            version = "not installed"
        click.echo(f"{name} {version}")
    libraries = []
    try:
        import shapely

        libraries.append(f"GEOS {shapely.geos_version_string}")
        import pyproj

        libraries.append(f"PROJ {pyproj.proj_version_str}")
        import pyogrio

        libraries.append(f"GDAL (pyogrio) {pyogrio.__gdal_version_string__}")
        import rasterio

        libraries.append(f"GDAL (rasterio) {rasterio.__gdal_version__}")
    except ImportError as exc:
        libraries.append(f"({exc})")
    for line in libraries:
        click.echo(line)
    ctx.exit(0)


class _Group(click.Group):
    """The group, showing Python warnings as one log line instead of source lines."""

    def invoke(self, ctx: click.Context) -> Any:
        with warnings.catch_warnings():
            warnings.showwarning = _log_warning
            return super().invoke(ctx)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="coastmesh")
@click.option(
    "--show-versions",
    is_flag=True,
    is_eager=True,
    expose_value=False,
    callback=_show_versions,
    help="Show the versions of coastmesh, Python, its dependencies, GDAL, GEOS "
    "and PROJ, and exit.",
)
@click.option("-v", "--verbose", count=True, help="More messages (-v info, -vv debug).")
@click.option(
    "-q", "--quiet", count=True, help="Only errors; no progress bar or summary."
)
@click.pass_context
def cli(ctx: click.Context, verbose: int, quiet: int) -> None:
    """Shorelines and bathymetry to meshes for tidal ocean models.

    Approximate shorelines and bathymetry by principal component analysis (PCA)
    of overlapping windows (Avdis et al. 2015), close model domains with
    loxodrome open boundaries, and mesh them with Gmsh. Start with 'coastmesh demo';
    run a whole case with 'coastmesh run CASE.toml'.
    """
    ctx.call_on_close(configure_logging(verbose - quiet))
    ctx.ensure_object(dict)
    ctx.obj["quiet"] = quiet > 0


cli.add_command(simplify_shoreline)
cli.add_command(simplify_raster)
cli.add_command(demo)
cli.add_command(run)
cli.add_command(convert)
cli.add_command(patch)
cli.add_command(formats)


def small_pages() -> None:
    """Ask numpy for ordinary memory pages, unless the user chose (environment).

    numpy asks the kernel for transparent huge pages (``madvise``) for every
    array of 4 MB or more. Where the kernel must compact memory to find them
    (``/sys/kernel/mm/transparent_hugepage/defrag`` set to ``madvise``, as on
    the 2-core VMs coastmesh is benchmarked on), the run's many short-lived
    arrays of 10-100 MB stall on it: ``world.toml`` on 2 workers spent 26 s
    of 164 CPU seconds in the kernel with huge pages and 8.5 s of 141
    without, 96 s against 81 s end to end. numpy reads
    ``NUMPY_MADVISE_HUGEPAGE`` when it is first imported, here and in every
    worker process (they inherit the environment); ``NUMPY_MADVISE_HUGEPAGE=1``
    in the environment keeps numpy's default.
    """
    if "numpy" not in sys.modules:
        os.environ.setdefault("NUMPY_MADVISE_HUGEPAGE", "0")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line and return its exit code.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name; ``sys.argv[1:]`` by default.

    Returns
    -------
    int
        0 on success, 1 for bad input data or outputs, 2 for bad options.
    """
    small_pages()
    try:
        cli.main(args=list(argv) if argv is not None else None, prog_name="coastmesh")
    except SystemExit as exc:
        code = exc.code
        return code if isinstance(code, int) else (0 if code is None else 1)
    return 0
