"""``coastmesh run``: a whole case from its TOML file."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import click

from coastmesh.cli._common import ProgressBar, translate_errors
from coastmesh.cli.options import overwrite_option

__all__ = ["run"]


@click.command("run")
@click.argument(
    "case",
    metavar="CASE.toml",
    type=click.Path(dir_okay=False, path_type=Path),
)
@click.option(
    "-o",
    "--output",
    type=click.Path(file_okay=False, path_type=Path),
    help="Output folder; overrides [case] output in the case file.",
)
@click.option(
    "--check",
    is_flag=True,
    help="Only read and check the case file (keys, values, names, ids); run nothing.",
)
@click.option(
    "-w",
    "--workers",
    type=click.IntRange(min=1),
    default=None,
    help="Cores the run may use: processes to mesh and clean the parts of the "
    "water on and to draw the figures on, threads for the PCA, the closing and "
    "the size terms (default: [run] workers, else all cores). The outputs are "
    "the same for any number: [mesh] parts in the case sets how the water is cut.",
)
@click.option(
    "--scheduler",
    metavar="ADDRESS",
    default=None,
    help="Mesh the parts as tasks on this Dask cluster (e.g. tcp://10.0.0.5:8786; "
    "default: [run] scheduler, else this machine). Start one with `dask "
    "scheduler` and `dask worker ADDRESS --nthreads 1`.",
)
@click.option(
    "--refine-from",
    "refine_from",
    metavar="RESULT",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="A first run's results (ANUGA .sww, SCHISM out2d_*.nc, ADCIRC fort.63/"
    "fort.64/maxvel.63, UGRID .nc, .vtu): the source of every [[mesh_size.fields]] "
    "entry that gives none, to mesh again finer where that run asks. Give -o too, "
    "so the first mesh is kept.",
)
@overwrite_option
@click.pass_context
@translate_errors
def run(
    ctx: click.Context,
    *,
    case: Path,
    output: Path | None,
    check: bool,
    overwrite: bool,
    workers: int | None,
    scheduler: str | None,
    refine_from: Path | None,
) -> None:
    """Build a mesh from a case file: shorelines, open boundaries, sizes, Gmsh.

    CASE.toml names the shoreline file, the shoreline sets (full resolution or PCA
    reconstructions) and the regions that use them, the open boundaries
    (loxodromes, blended loxodromes, great circles, polylines) with their boundary
    ids, the size gradations and the outputs. Relative paths are relative to
    CASE.toml. With [case] kind = "shorelines" or "bathymetry" it runs one of the
    paper's PCA studies instead. See docs/case-files.md and examples/.

    Everything is written into OUTPUT.partial-XXXX/ and renamed to OUTPUT at the
    end, so a failed run leaves nothing. OUTPUT must not exist or be empty, unless
    --overwrite is given.
    """
    from coastmesh.case import StudyCase, read_case

    config = read_case(case)
    if refine_from is not None:
        config = _refined(config, refine_from, case)
    quiet = ctx.find_root().obj.get("quiet", False)
    if check:
        if quiet:
            return
        if isinstance(config, StudyCase):
            click.echo(
                f"{case}: OK: a {config.kind} study; output {output or config.output}"
            )
        else:
            from coastmesh.case.site_check import site_counts, site_lines

            site = "".join(f", {count}" for count in site_counts(config))
            click.echo(
                f"{case}: OK: {len(config.sets)} shoreline sets, "
                f"{len(config.regions)} regions, {len(config.boundaries)} open "
                f"boundaries, {len(config.size.gradations)} gradations"
                f"{_fields(config)}{site}; "
                f"output {output or config.output}"
            )
            for line in site_lines(config):
                click.echo(f"  {line}")
        return
    from coastmesh.case import CaseResult, run_case

    result = run_case(
        config,
        output=output,
        overwrite=overwrite,
        stage=_stages(quiet),
        workers=workers,
        scheduler=scheduler,
    )
    if quiet:
        return
    if isinstance(config, StudyCase):
        folder = output or config.output
        click.echo(f"{config.name}: {result.summary()}")
        click.echo(f"Look at {folder / 'figures'}/ and {folder / 'table.md'}")
        return
    if not quiet:
        assert isinstance(result, CaseResult)  # a mesh case, not a study
        written = result.output
        assert written is not None  # run_case wrote the case there
        click.echo(result.summary())
        click.echo(
            f"Look at {written / 'summary.txt'} and the figures in "
            f"{written / 'figures'}/"
            if (written / "figures").is_dir()
            else f"Look at {written / 'summary.txt'}"
        )


def _fields(config: Any) -> str:
    """``, N fields`` (and how many wait for ``--refine-from``), or nothing."""
    fields = config.size.fields
    waiting = sum(f.source is None for f in fields)
    if not fields:
        return ""
    return f", {len(fields)} fields" + (
        f" ({waiting} without a source: off until --refine-from)" if waiting else ""
    )


def _refined(config: Any, result: Path, case: Path) -> Any:
    """Give ``result`` to the case's ``[[mesh_size.fields]]`` without a source."""
    from dataclasses import replace

    from coastmesh.case import StudyCase
    from coastmesh.case.terms.fields import with_result
    from coastmesh.errors import ConfigError

    if isinstance(config, StudyCase):
        raise ConfigError(f"{case}: --refine-from: a {config.kind} study has no sizes")
    if not result.is_file():
        raise ConfigError(f"--refine-from {result}: no such file")
    fields = with_result(config.size.fields, result.resolve())
    return replace(config, size=replace(config.size, fields=fields))


def _stages(quiet: bool) -> Callable[[str], contextlib.AbstractContextManager]:
    @contextlib.contextmanager
    def stage(label: str) -> Iterator[ProgressBar]:
        started = time.perf_counter()
        with ProgressBar(label, enabled=not quiet) as bar:
            yield bar
        if not quiet:
            seconds = time.perf_counter() - started
            click.echo(f"  {label}: {seconds:.1f} s", err=True)

    return stage
