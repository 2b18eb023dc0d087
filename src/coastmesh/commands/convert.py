"""Convert a mesh file to a model format, optionally with bathymetry on the nodes.

This is ``coastmesh convert``: a Gmsh ``.msh`` (as ``coastmesh run`` writes it, or
any 2D triangle mesh with physical line ids) in, any registered format out.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from pyproj import CRS

from coastmesh.errors import ConfigError, FormatError
from coastmesh.types import Mesh

__all__ = ["ConvertResult", "convert_mesh"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class ConvertResult:
    """What :func:`convert_mesh` wrote."""

    path: str
    format: str
    nodes: int
    triangles: int
    boundary_edges: int
    depth: Any = None

    def summary(self) -> str:
        """Return a one-line summary."""
        text = (
            f"{self.path} ({self.format}): {self.nodes:,} nodes, "
            f"{self.triangles:,} triangles, {self.boundary_edges:,} boundary edges"
        )
        if self.depth is not None:
            text += f"; {self.depth.summary()}"
        return text


def convert_mesh(
    src: str | os.PathLike[str],
    dst: str | os.PathLike[str],
    *,
    format: str | None = None,
    crs: CRS | str = "EPSG:4326",
    open_ids: Sequence[int] | None = None,
    bathymetry: str | os.PathLike[str] | None = None,
    raster_positive: str = "up",
    method: str = "bilinear",
    min_depth: float | None = None,
    max_slope: float | None = None,
    positive: str | None = None,
    overwrite: bool = False,
) -> ConvertResult:
    """Read a ``.msh`` mesh and write it in another format.

    Parameters
    ----------
    src : path
        The mesh (msh 2.2 or 4.1).
    dst : path
        The output; its extension picks the format unless ``format`` is given.
    format : str, optional
        A registered format name (``coastmesh.io.mesh_formats()``).
    crs : CRS-like
        The CRS of the mesh coordinates (msh does not store it).
    open_ids : sequence of int, optional
        The boundary ids that are open (sea) boundaries; the others are land.
        Default: the kinds stored in the file's physical names (``open:NAME``).
    bathymetry : path, optional
        A raster (any GDAL raster) to interpolate onto the nodes.
    raster_positive : {"up", "down"}
        The raster's sign (elevations are ``"up"``).
    method, min_depth, max_slope
        As in :func:`coastmesh.meshing.depth.depth_at_nodes`.
    positive : {"up", "down"}, optional
        The sign written, for formats that take one; default: the format's own.
    overwrite : bool
        Whether ``dst`` may be replaced.

    Returns
    -------
    ConvertResult

    Raises
    ------
    FormatError
        If the extension or format is unknown, or the format cannot hold the mesh.
    ConfigError
        If ``open_ids`` names ids the mesh does not have.
    """
    from coastmesh.io import check_output, read_msh
    from coastmesh.io.writers import format_for_path, mesh_format, write_mesh

    fmt = mesh_format(format) if format else format_for_path(dst)
    check_output(dst, overwrite=overwrite)
    mesh = read_msh(src, crs=crs)
    if open_ids is not None:
        mesh = _with_kinds(mesh, open_ids, os.fspath(src))
    depth_report = None
    if bathymetry is not None:
        from coastmesh.io import read_raster
        from coastmesh.meshing.depth import depth_at_nodes

        depth, depth_report = depth_at_nodes(
            mesh,
            read_raster(bathymetry),
            positive=raster_positive,
            method=method,
            min_depth=min_depth,
            max_slope=max_slope,
        )
        mesh = mesh.with_point_data(depth=depth)
    options: dict[str, Any] = {}
    if positive is not None:
        if fmt.options is not None and "positive" not in fmt.options:
            raise FormatError(
                f"{os.fspath(dst)}: the {fmt.name} format has no depth sign to set"
            )
        options["positive"] = positive
    write_mesh(dst, mesh, format=fmt.name, overwrite=overwrite, **options)
    result = ConvertResult(
        os.fspath(dst),
        fmt.name,
        len(mesh.points),
        len(mesh.triangles),
        len(mesh.boundary_edges),
        depth_report,
    )
    logger.info("%s", result.summary())
    return result


def _with_kinds(mesh: Mesh, open_ids: Sequence[int], source: str) -> Mesh:
    present = {int(i) for i in mesh.boundary_ids}
    unknown = sorted(set(open_ids) - present)
    if unknown:
        raise ConfigError(
            f"--open-ids {unknown}: {source} has no such boundary ids; it has "
            f"{sorted(present)}"
        )
    kinds = {pid: ("open" if pid in set(open_ids) else "shoreline") for pid in present}
    return Mesh(
        mesh.points,
        mesh.triangles,
        mesh.boundary_edges,
        mesh.boundary_ids,
        mesh.surface_id,
        mesh.crs,
        mesh.point_data,
        mesh.boundary_names,
        kinds,
    )
