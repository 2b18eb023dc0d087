"""Convert a mesh file to another format, optionally with bathymetry on the nodes.

This is ``coastmesh convert``: a mesh in any format the registry reads
(:func:`coastmesh.io.read_mesh`: msh, fort.14, gr3, UGRID, VTU, GeoPackage, MIKE)
in, any registered format out (:func:`coastmesh.io.write_mesh`).
"""

from __future__ import annotations

import dataclasses
import logging
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from pyproj import CRS

from coastmesh.errors import ConfigError, FormatError
from coastmesh.types import Mesh, Report

__all__ = ["DEFAULT_CRS", "ConvertResult", "convert_mesh"]

logger = logging.getLogger(__name__)

#: The CRS of a mesh read from a file that stores none (msh, VTU), unless given.
DEFAULT_CRS = "EPSG:4326"


@dataclass(frozen=True, slots=True)
class ConvertResult(Report):
    """What :func:`convert_mesh` wrote.

    Parameters
    ----------
    path : str
        The output file.
    format : str
        The format it was written in.
    nodes, triangles, boundary_edges : int
        The counts of the mesh.
    depth : Report, optional
        The depth interpolation report, if bathymetry was given.
    repaired : tuple of str
        The rules of the output's model that the input's boundary lists broke
        (a ``fort.14`` or ``hgrid.gr3`` from another tool written as a
        ``fort.14`` or ``hgrid.gr3``), which the output follows:
        :func:`~coastmesh.io.meshes.adcirc.rule_breaks`, one line each.

    Examples
    --------
    >>> ConvertResult("fort.14", "fort14", 4, 2, 4).summary()
    'fort.14 (fort14): 4 nodes, 2 triangles, 4 boundary edges'
    """

    path: str
    format: str
    nodes: int
    triangles: int
    boundary_edges: int
    depth: Any = None
    repaired: tuple[str, ...] = ()

    def summary(self) -> str:
        """Return a one-line summary."""
        text = (
            f"{self.path} ({self.format}): {self.nodes:,} nodes, "
            f"{self.triangles:,} triangles, {self.boundary_edges:,} boundary edges"
        )
        if self.depth is not None:
            text += f"; {self.depth.summary()}"
        if self.repaired:
            text += (
                f"; repaired {len(self.repaired)} break(s) of the model's boundary "
                f"rules in the input (first: {self.repaired[0]})"
            )
        return text


def convert_mesh(
    src: str | os.PathLike[str],
    dst: str | os.PathLike[str],
    *,
    format: str | None = None,
    crs: CRS | str | None = None,
    open_ids: Sequence[int] | None = None,
    bathymetry: str | os.PathLike[str] | Sequence[str | os.PathLike[str]] | None = None,
    raster_positive: str | Sequence[str] = "up",
    method: str = "bilinear",
    min_depth: float | None = None,
    max_slope: float | None = None,
    blend: float | Sequence[float] = 0.0,
    outside: str = "error",
    land: str | None = None,
    land_distance: float | None = None,
    positive: str | None = None,
    options: dict[str, Any] | None = None,
    overwrite: bool = False,
) -> ConvertResult:
    """Read a mesh in any readable format and write it in another.

    Parameters
    ----------
    src : path
        The mesh; its extension picks the reader (``coastmesh.io.mesh_formats()``
        lists which formats can be read).
    dst : path
        The output; its extension picks the format unless ``format`` is given.
    format : str, optional
        A registered format name for ``dst``.
    crs : CRS-like, optional
        The CRS of the mesh coordinates, for files that store none (msh, VTU, a
        fort.14 from another tool); default :data:`DEFAULT_CRS`. A file that
        stores a CRS keeps it (and ``crs``, if given, must agree).
    open_ids : sequence of int, optional
        The boundary ids that are open (sea) boundaries; the others are land.
        Default: the kinds the file stores (msh physical names ``open:NAME``,
        fort.14/gr3 open and land lists, UGRID, GeoPackage, MIKE codes).
    bathymetry : path or sequence of paths, optional
        Rasters (any GDAL raster, any CRS) to interpolate onto the nodes, highest
        priority first; each is read only over the mesh's box.
    raster_positive : {"up", "down"} or a sequence of them
        The rasters' sign (elevations are ``"up"``): one for all, or one each.
    blend : float or sequence of float
        Metres over which each raster blends into the next (one for all, or
        one each).
    method, min_depth, max_slope, outside, land, land_distance
        As in :func:`coastmesh.depth.nodes.depth_at_nodes`; ``outside``
        defaults to an error for nodes beyond every raster. ``land`` defaults
        to ``"wet"``, and then more than half the nodes on land in the rasters
        is an error (:data:`~coastmesh.depth.nodes.MAX_LAND_SHARE`).
    positive : {"up", "down"}, optional
        The sign written, for formats that take one; default: the format's own.
    options : dict, optional
        More options of the output format's writer, such as ``{"land":
        "essential"}`` for a fort.14 (:func:`coastmesh.io.write_mesh`).
    overwrite : bool
        Whether ``dst`` may be replaced.

    Returns
    -------
    ConvertResult

    Raises
    ------
    FormatError
        If an extension or format is unknown, ``src``'s format cannot be read, or
        ``dst``'s format cannot hold the mesh.
    InputDataError
        If ``src`` is missing or not a valid mesh.
    ConfigError
        If ``open_ids`` names ids the mesh does not have.
    OutputExistsError
        If ``dst`` exists and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from coastmesh.io import write_mesh
    >>> m = Mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]],
    ...          [[0, 1], [1, 2], [2, 3], [3, 0]], [2, 1, 1, 1], 1, None)
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> write_mesh(folder / "square.msh", m)
    >>> convert_mesh(folder / "square.msh", folder / "square.nc").summary()
    '.../square.nc (ugrid): 4 nodes, 2 triangles, 4 boundary edges'
    >>> convert_mesh(folder / "square.nc", folder / "square.vtu").format
    'vtu'
    """
    from coastmesh.io import (
        check_output,
        format_for_path,
        mesh_format,
        read_mesh,
        write_mesh,
    )

    fmt = mesh_format(format) if format else format_for_path(dst)
    check_output(dst, overwrite=overwrite)
    mesh = read_mesh(src, crs=crs)
    if mesh.crs is None:
        mesh = dataclasses.replace(mesh, crs=CRS.from_user_input(DEFAULT_CRS))
    if open_ids is not None:
        mesh = _with_kinds(mesh, open_ids, os.fspath(src))
    depth_report = None
    if bathymetry is not None:
        from coastmesh.depth.nodes import (
            MAX_LAND_SHARE,
            depth_at_nodes,
            node_sources,
        )

        stack = _stack(bathymetry, raster_positive, blend, mesh)
        depth, depth_report = depth_at_nodes(
            mesh,
            stack,
            method=method,
            min_depth=min_depth,
            max_slope=max_slope,
            outside=outside,
            land="wet" if land is None else land,
            land_distance=land_distance,
            max_land_share=MAX_LAND_SHARE if land is None else None,
        )
        extra = {"depth_source": node_sources(mesh, stack)} if len(stack) > 1 else {}
        mesh = mesh.with_point_data(depth=depth, **extra)
    options = dict(options or {})
    if positive is not None:
        if fmt.options is not None and "positive" not in fmt.options:
            raise FormatError(
                f"{os.fspath(dst)}: the {fmt.name} format has no depth sign to set"
            )
        options["positive"] = positive
    repaired = _repairs(src, mesh, fmt.name)
    write_mesh(dst, mesh, format=fmt.name, overwrite=overwrite, **options)
    result = ConvertResult(
        os.fspath(dst),
        fmt.name,
        len(mesh.points),
        len(mesh.triangles),
        len(mesh.boundary_edges),
        depth_report,
        repaired,
    )
    logger.info("%s", result.summary())
    return result


# the model whose boundary rules each grid format follows
_RULES = {"fort14": "adcirc", "gr3": "schism"}


def _repairs(
    src: str | os.PathLike[str], mesh: Mesh, out_format: str
) -> tuple[str, ...]:
    """Return the rules of the output's model that the input grid's lists break.

    Only for a ``fort.14`` or ``hgrid.gr3`` written as one of them: the writers
    lay the lists out by the model's rules from the mesh's boundary edges, so
    each break found in the input is repaired in the output.
    """
    from coastmesh.io import format_for_path
    from coastmesh.io.meshes.adcirc import read_fort14, rule_breaks

    model = _RULES.get(out_format)
    try:
        source_format = format_for_path(src).name
    except FormatError:
        return ()
    if model is None or source_format not in _RULES:
        return ()
    breaks = rule_breaks(read_fort14(src), mesh, model)
    return tuple(f"{b}; written by the rules" for b in breaks)


def _stack(paths: Any, positive: Any, blend: Any, mesh: Mesh) -> Any:
    """Read the rasters over the mesh's box as a DepthSources stack."""
    from coastmesh.case.pipeline.depth import read_sources
    from coastmesh.case.sources import DepthSourceConfig

    paths = [paths] if isinstance(paths, str | os.PathLike) else list(paths)
    signs = _each(positive, len(paths), "raster_positive")
    blends = _each(blend, len(paths), "blend")
    configs = [
        DepthSourceConfig(os.fspath(p), s, blend=float(b))
        for p, s, b in zip(paths, signs, blends, strict=True)
    ]
    assert mesh.crs is not None  # convert_mesh gives the mesh one (DEFAULT_CRS)
    return read_sources(configs, mesh.points, mesh.crs)


def _each(value: Any, n: int, name: str) -> list[Any]:
    """One value for all rasters, or one each."""
    if isinstance(value, str) or not isinstance(value, Sequence):
        return [value] * n
    if len(value) == 1:
        return list(value) * n
    if len(value) != n:
        raise ConfigError(
            f"{name}: {len(value)} values for {n} bathymetry rasters; give one "
            "for all or one each"
        )
    return list(value)


def _with_kinds(mesh: Mesh, open_ids: Sequence[int], source: str) -> Mesh:
    present = {int(i) for i in mesh.boundary_ids}
    unknown = sorted(set(open_ids) - present)
    if unknown:
        raise ConfigError(
            f"--open-ids {unknown}: {source} has no such boundary ids; it has "
            f"{sorted(present)}"
        )
    kinds = {pid: ("open" if pid in set(open_ids) else "shoreline") for pid in present}
    return dataclasses.replace(mesh, boundary_kinds=kinds)
