"""``coastmesh formats``: the mesh formats coastmesh reads and writes."""

from __future__ import annotations

import click

__all__ = ["formats"]


@click.command("formats")
@click.option(
    "--markdown", is_flag=True, help="Print the table as Markdown (docs/formats.md)."
)
def formats(markdown: bool) -> None:
    """List the mesh formats: names, extensions, models, what each file holds.

    The names are those of '[output] formats' in a case file and of 'coastmesh
    convert --format'; a file's extension picks its format otherwise.
    """
    from coastmesh.io import formats_table, mesh_formats

    if markdown:
        click.echo(formats_table(), nl=False)
        return
    for fmt in mesh_formats().values():
        extra = tuple(f"+{e}" for e in fmt.companions)
        extra += tuple(f"(+{e} with regions)" for e in fmt.region_companions)
        extensions = " ".join(fmt.extensions + extra)
        click.echo(f"{fmt.name:9} {extensions:38} {fmt.mode:15} {fmt.model}")
        holds = ", ".join(sorted(fmt.holds)) or "nodes and triangles only"
        sign = f"; depth positive {fmt.positive}" if fmt.positive else ""
        click.echo(f"{'':9} holds: {holds}{sign}")
