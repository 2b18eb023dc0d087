"""The files of a case: model formats, domain, size field, reports, figures.

:func:`write_case` is :meth:`coastmesh.CaseResult.write`: everything goes into
``<folder>.partial-XXXX/``, renamed to ``folder`` when all is written.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from coastmesh.case.config import CaseConfig, OutputConfig
from coastmesh.io import (
    atomic_directory,
    mesh_format,
    write_domain,
    write_mesh,
    write_raster,
    write_report,
)
from coastmesh.types import Features, StageFactory, quiet_stage

if TYPE_CHECKING:
    from coastmesh.case.result import CaseResult

__all__ = ["write_case", "write_case_copy"]


def write_case(
    result: CaseResult,
    folder: Path,
    outputs: OutputConfig,
    *,
    overwrite: bool = False,
    stage: StageFactory | None = None,
) -> list[str]:
    """Write every output of a case into ``folder``, atomically.

    Parameters
    ----------
    result : CaseResult
        What the case made.
    folder : pathlib.Path
        The output folder.
    outputs : OutputConfig
        What to write (formats, domain, size field, quality, figures).
    overwrite : bool, default False
        Whether a non-empty ``folder`` may be replaced.
    stage : callable, optional
        ``stage(label)`` returns a context manager, entered once.

    Returns
    -------
    list of str
        File names relative to ``folder``, in the order written.
    """
    with (
        (stage or quiet_stage)("writing outputs"),
        atomic_directory(folder, overwrite=overwrite) as partial,
    ):
        files = _write_models(result, partial, outputs)
        if outputs.domain:
            _write_domain(partial / "domain.gpkg", result)
            files.append("domain.gpkg")
        if outputs.size_field:
            write_raster(partial / "size.tif", result.size)
            files.append("size.tif")
        quality = result.report.quality
        if quality is not None and outputs.quality:
            write_report(
                partial / "quality.json", quality, summary=partial / "quality.txt"
            )
            files += ["quality.json", "quality.txt"]
        if outputs.figures:
            files += _write_figures(result, partial, outputs)
        write_case_copy(partial, result.config)
        files += ["case.toml", "report.json", "summary.txt"]
        report = dataclasses.replace(result.report, files=tuple(files))
        write_report(partial / "report.json", report, summary=partial / "summary.txt")
    return files


def write_case_copy(folder: Path, config: CaseConfig | Any) -> None:
    """Keep the case as run, as ``case.toml``, saying where it came from.

    A case read from a file is copied as it is (its relative paths stay
    relative to that file); a case built in Python is written with
    :func:`~coastmesh.case.dump_case`, so ``coastmesh run case.toml`` runs it again.
    """
    from coastmesh import __version__
    from coastmesh.case.dump import dump_case

    if config.source is not None:
        header = (
            f"# A copy of {Path(config.source).resolve()}, as run by coastmesh "
            f"{__version__}.\n# Its relative paths are relative to that file, not "
            "to this copy.\n"
        )
        text = config.text
    else:
        header = (
            f"# A case built in Python, as run by coastmesh {__version__}.\n"
            "# Run it again with: coastmesh run case.toml\n"
        )
        text = dump_case(config)
    (folder / "case.toml").write_text(header + text, encoding="utf-8")


def _write_models(result: CaseResult, folder: Path, outputs: OutputConfig) -> list[str]:
    """Write the mesh in each format of ``[output] formats``."""
    name = result.name
    files: list[str] = []
    taken: set[str] = set()
    for fmt_name in outputs.formats:
        fmt = mesh_format(fmt_name)
        suffix = fmt.extensions[0]
        filename = f"{name}{suffix}"
        if filename in taken:
            filename = f"{name}-{fmt_name}{suffix}"
        taken.add(filename)
        options = {}
        if outputs.positive and fmt_name in outputs.positive:
            options["positive"] = outputs.positive[fmt_name]
        write_mesh(folder / filename, result.mesh, format=fmt_name, **options)
        files.append(filename)
        if fmt_name == "selafin":  # the boundary-conditions file written with it
            files.append(f"{Path(filename).stem}.cli")
    return files


def _write_domain(path: Path, result: CaseResult) -> None:
    """Write the domain GeoPackage, with the untrimmed boundaries and the regions."""
    from coastmesh import __version__

    walls, crs = result.open_boundaries, result.crs
    extra = {}
    if walls:
        extra["open_boundaries_untrimmed"] = _layer(
            [shapely.LineString(w.coords) for w in walls],
            crs,
            name=[w.name for w in walls],
            physical_id=[w.physical_id for w in walls],
        )
    used = [(n, i, r) for n, i, r in result.regions if r is not None]
    if used:
        extra["regions"] = _layer(
            [r for _, _, r in used],
            crs,
            shoreline_set=[n for n, _, _ in used],
            physical_id=[i for _, i, _ in used],
        )
    notes = {
        "coastmesh_version": __version__,
        "case": result.name,
        "case_file": result.config.label,
    }
    write_domain(path, result.domain, metadata=notes, extra_layers=extra)


def _layer(geometry: list[Any], crs: Any, **fields: list[Any]) -> Features:
    return Features(
        np.array(geometry, dtype=object),
        crs,
        {
            key: np.array(values, dtype=object if isinstance(values[0], str) else None)
            for key, values in fields.items()
        },
        np.arange(len(geometry)),
        "<memory>",
    )


def _write_figures(
    result: CaseResult, folder: Path, outputs: OutputConfig
) -> list[str]:
    """Draw the domain, mesh, size, quality and depth figures into figures/."""
    from coastmesh import plot

    mesh, name, quality = result.mesh, result.name, result.report.quality
    names = {s.physical_id: s.name for s in result.domain.segments}
    figures: list[tuple[str, Callable[[], Any]]] = [
        ("domain", lambda: plot.domain_figure(result.domain, title=f"{name}: domain")),
        ("mesh", lambda: plot.mesh_figure(mesh, names=names, title=name)),
        ("size", lambda: plot.size_figure(result.size, title=f"{name}: element size")),
    ]
    if quality is not None:
        figures.append(
            (
                "quality",
                lambda: plot.quality_figure(
                    mesh, quality, title=f"{name}: element quality"
                ),
            )
        )
    if "depth" in mesh.point_data:
        figures.append(
            ("depth", lambda: plot.depth_figure(mesh, title=f"{name}: depth"))
        )
    if outputs.detail is not None:
        figures.append(
            (
                "mesh_mercator",
                lambda: plot.mercator_figure(
                    mesh, detail=outputs.detail, names=names, title=name
                ),
            )
        )
    (folder / "figures").mkdir()
    files = []
    for stem, draw in figures:
        plot.save_figure(draw(), folder / "figures" / f"{stem}.png")
        files.append(f"figures/{stem}.png")
    return files
