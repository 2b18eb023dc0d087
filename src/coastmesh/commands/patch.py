"""Patch a site into an existing mesh, from files to an output folder.

This is ``coastmesh patch``: the mesh (any format :func:`coastmesh.io.read_mesh`
reads), the site's case file, and optionally the polygon to remesh (a vector
file, any CRS) in; the patched mesh in the input's format (and any others
asked for), ``report.json``, ``summary.txt`` and ``figures/patch.png`` out,
written atomically (:func:`coastmesh.io.atomic_directory`).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.errors import ConfigError
from coastmesh.types import Report

__all__ = ["PatchRun", "patch_files"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class PatchRun(Report):
    """What ``coastmesh patch`` wrote, and the patch's report."""

    output: str
    files: tuple[str, ...]
    patch: Any

    def summary(self) -> str:
        """Return one line: the patch's, and where it went."""
        return f"{self.patch.summary()}; {len(self.files)} files in {self.output}/"


def patch_files(
    mesh_path: str | os.PathLike[str],
    case_path: str | os.PathLike[str],
    output: str | os.PathLike[str],
    *,
    polygon: str | os.PathLike[str] | None = None,
    distance: float | None = None,
    crs: Any = None,
    formats: Sequence[str] = (),
    overwrite: bool = False,
    threads: int = 1,
) -> PatchRun:
    """Read a mesh and a case, patch the case's site in, write the results.

    Parameters
    ----------
    mesh_path : path
        The existing mesh: fort.14, hgrid.gr3, SELAFIN, msh, UGRID, ...
    case_path : path
        The site's case file (``[[farms]]``, ``[[turbines]]``, ``[mesh_size]``,
        ``[bathymetry]``, ...).
    output : path
        The output folder (must not exist or be empty, unless ``overwrite``).
    polygon : path, optional
        A vector file of the polygon(s) to remesh, in any CRS; default: the
        site grown (``distance``, :func:`coastmesh.case.patch.site_polygon`).
    distance : float, optional
        Metres to grow the site by.
    crs : CRS-like, optional
        The mesh's CRS, for a file that stores none.
    formats : sequence of str
        More formats to write the patched mesh in, by name.
    overwrite : bool
        Whether ``output`` may be replaced.
    threads : int
        Threads for the size field.

    Raises
    ------
    ConfigError, InputDataError, FormatError, MeshingError
        As reading, patching and writing raise them; nothing is left written.
    """
    import shapely

    from coastmesh.case import CaseConfig, read_case
    from coastmesh.case.patch import patch_mesh
    from coastmesh.io import (
        atomic_directory,
        check_directory,
        format_for_path,
        read_features,
        read_mesh,
        write_mesh,
        write_report,
    )

    check_directory(output, overwrite=overwrite)
    source = Path(mesh_path)
    mesh = read_mesh(source, crs=crs) if crs is not None else read_mesh(source)
    config = read_case(case_path)
    if not isinstance(config, CaseConfig):
        raise ConfigError(f"{case_path}: a {config.kind} study has no site to patch in")
    shape: Any = None
    shape_crs: Any = "EPSG:4326"
    if polygon is not None:
        features = read_features(polygon)
        shape = shapely.union_all(features.geometry)
        shape_crs = features.crs or "EPSG:4326"
    patched = patch_mesh(
        mesh,
        config,
        polygon=shape,
        polygon_crs=shape_crs,
        distance=distance,
        name=str(source),
        threads=threads,
    )
    written = []
    with atomic_directory(output, overwrite=overwrite) as folder:
        own = format_for_path(source).name
        write_mesh(folder / source.name, patched.mesh, format=own)
        written.append(source.name)
        for name in formats:
            if name == own:
                continue
            target = folder / f"{source.stem}_patched.{_extension(name)}"
            write_mesh(target, patched.mesh, format=name)
            written.append(target.name)
        write_report(
            folder / "report.json", patched.report, summary=folder / "summary.txt"
        )
        written += ["report.json", "summary.txt"]
        written.append(_figure(folder, mesh, patched))
    return PatchRun(os.fspath(output), tuple(written), patched.report)


def _extension(name: str) -> str:
    from coastmesh.io import mesh_format

    return mesh_format(name).extensions[0].lstrip(".")


def _figure(folder: Path, before: Any, patched: Any) -> str:
    """Draw the mesh before and after, around the hole: ``figures/patch.png``."""
    import numpy as np

    from coastmesh.geometry import reproject
    from coastmesh.plot import patch_figure, save_figure

    outline = reproject(patched.polygon, patched.crs, before.crs)
    ring = (
        outline.exterior if hasattr(outline, "exterior") else outline.geoms[0].exterior
    )
    figure = patch_figure(
        before,
        patched.mesh,
        patched.hole.removed,
        patched.new_elements,
        np.asarray(ring.coords),
        title=patched.report.summary().split(";")[0],
    )
    (folder / "figures").mkdir()
    save_figure(figure, folder / "figures" / "patch.png")
    return "figures/patch.png"
