"""``coastmesh demo``: the paper's examples on the bundled data."""

from __future__ import annotations

from pathlib import Path

import click

from coastmesh.cli._common import ProgressBar, translate_errors
from coastmesh.cli.options import overwrite_option

__all__ = ["demo"]


@click.command("demo")
@click.argument(
    "outdir",
    metavar="OUTDIR",
    default="out",
    type=click.Path(file_okay=False, path_type=Path),
)
@overwrite_option
@click.pass_context
@translate_errors
def demo(ctx: click.Context, *, outdir: Path, overwrite: bool) -> None:
    """Run the examples on the bundled data; write them to OUTDIR.

    OUTDIR is out/ by default.

    The West Norway GSHHG shoreline is approximated with windows of 100 and 500
    points (1 mode) and 100 points with 5 modes; the ETOPO1 Orkney bathymetry with
    8 x 8 cell windows and 1, 16 and 48 modes. Each result comes with a PNG that
    draws the input and the result together. Then the bundled Orkney case runs
    the whole chain into OUTDIR/pentland_firth/: shoreline PCA by region,
    loxodrome open boundaries, a graded Gmsh mesh, depths from the PCA of ETOPO1,
    eight model formats, the quality report and figures. OUTDIR must not exist or
    be empty, unless --overwrite is given.
    """
    from coastmesh.commands.demo import run_demo

    quiet = ctx.find_root().obj.get("quiet", False)
    with ProgressBar("demo steps", enabled=not quiet) as progress:
        steps = run_demo(outdir, overwrite=overwrite, progress=progress)
    if quiet:
        return
    for step in steps:
        click.echo(f"{step.title}: {step.report.summary()}")
        click.echo(f"    {outdir / step.outputs[0]}, {outdir / step.outputs[1]}")
    click.echo(
        f"Done: {len(steps)} results in {outdir}/ (see {outdir / 'README.txt'}); "
        f"look at the .png files first, e.g. {outdir / steps[-1].outputs[1]}"
    )
