"""``[mesh]``, ``[cleanup]``, ``[bathymetry]`` and ``[output]``."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from coastmesh.case import schema
from coastmesh.case.config._check import Check
from coastmesh.case.config.sources import DepthSourceConfig, check_sources
from coastmesh.errors import ConfigError

__all__ = [
    "CleanupConfig",
    "MeshConfig",
    "NodeDepthConfig",
    "OutputConfig",
    "RunConfig",
]

_UP_DOWN = ("up", "down")


@dataclass(frozen=True, slots=True)
class NodeDepthConfig:
    """``[bathymetry]``: the depth written at the mesh nodes.

    Attributes
    ----------
    path : path, optional
        One raster GDAL reads; or ``sources``.
    positive : {"up", "down"}
        The raster's sign (with ``path``).
    sources : tuple of DepthSourceConfig
        ``[[bathymetry.sources]]``: several rasters, highest priority first;
        with ``path``, the one source it makes.
    outside : {"error", "nearest"}
        Nodes more than a cell diagonal beyond every source's data: an error,
        or the nearest valid cell and a warning.
    land : {"min_depth", "nearest_sea", "smooth"}
        Nodes where the rasters say land (depth <= 0 m); see
        :data:`coastmesh.depth.nodes.LAND_TREATMENTS`.
    land_distance : float or str, optional
        Width of the coastal taper of ``land = "smooth"`` (metres).
    method : {"bilinear", "mean"}
        See :func:`coastmesh.depth.nodes.depth_at_nodes`.
    min_depth : float or str, optional
        Depths below this are raised to it (metres, may be negative).
    max_slope : float, optional
        Largest depth difference per edge length.
    window, modes : int, optional
        PCA of the raster first (both or neither).
    """

    path: Path | None = None
    positive: str = "up"
    method: str = "bilinear"
    min_depth: float | None = None
    max_slope: float | None = None
    window: int | None = None
    modes: int | None = None
    sources: tuple[DepthSourceConfig, ...] = ()
    outside: str = "error"
    land: str = "min_depth"
    land_distance: float | None = None

    def _checked(self, c: Check) -> NodeDepthConfig:
        from coastmesh.depth.nodes import (
            DEPTH_METHODS,
            LAND_TREATMENTS,
            OUTSIDE_RULES,
        )

        window = c.optional(schema.integer(2), self.window, "window")
        modes = c.optional(schema.integer(1), self.modes, "modes")
        if (window is None) != (modes is None):
            raise c.error(
                "window", "give window and modes together (PCA of the raster)"
            )
        if window is not None and modes > window**2:
            raise c.error("modes", f"= {modes} is more than window**2")
        positive = c(schema.choice(_UP_DOWN), self.positive, "positive")
        path, sources = check_sources(c, self.path, positive, self.sources)
        land = c(schema.choice(LAND_TREATMENTS), self.land, "land")
        min_depth = c.optional(schema.length(signed=True), self.min_depth, "min_depth")
        land_distance = c.optional(schema.length(), self.land_distance, "land_distance")
        if land == "smooth" and (min_depth is None or land_distance is None):
            raise c.error(
                "land",
                "= 'smooth' tapers the depth to min_depth at the coast over "
                "land_distance: give both",
            )
        return NodeDepthConfig(
            path=path,
            positive=positive,
            sources=sources,
            outside=c(schema.choice(OUTSIDE_RULES), self.outside, "outside"),
            land=land,
            land_distance=land_distance,
            method=c(schema.choice(DEPTH_METHODS), self.method, "method"),
            min_depth=min_depth,
            max_slope=c.optional(schema.positive, self.max_slope, "max_slope"),
            window=window,
            modes=modes,
        )


@dataclass(frozen=True, slots=True)
class CleanupConfig:
    """``[cleanup]``: fixes after meshing (see :mod:`coastmesh.meshing.cleanup.fixes`).

    ``smooth``: move interior nodes to raise the smallest angles (boundary nodes
    stay); the result is kept only if its minimum angle and 1st percentile are
    no worse than Gmsh's mesh. ``time_step``: with ``[bathymetry]``, collapse
    an edge of each of the few elements whose stable time step is under 0.65 of
    the 1st percentile's (:func:`coastmesh.meshing.relieve_time_step`).
    """

    enabled: bool = True
    boundary_triangles: bool = True
    max_valence: int | None = None
    min_angle: float = 20.0
    smooth: bool = True
    time_step: bool = True

    def _checked(self, c: Check) -> CleanupConfig:
        min_angle = c(schema.number, self.min_angle, "min_angle")
        if not 0 < min_angle < 60:
            raise c.error(
                "min_angle", f"= {self.min_angle!r}: degrees between 0 and 60"
            )
        return CleanupConfig(
            enabled=c(schema.boolean, self.enabled, "enabled"),
            boundary_triangles=c(
                schema.boolean, self.boundary_triangles, "boundary_triangles"
            ),
            max_valence=c.optional(schema.integer(4), self.max_valence, "max_valence"),
            min_angle=min_angle,
            smooth=c(schema.boolean, self.smooth, "smooth"),
            time_step=c(schema.boolean, self.time_step, "time_step"),
        )


@dataclass(frozen=True, slots=True)
class MeshConfig:
    """``[mesh]``: Gmsh options and CRSs.

    Attributes
    ----------
    crs : str, optional
        The conformal CRS to mesh in; default UTM or an oblique stereographic.
    output_crs : str, optional
        The CRS of the written nodes; default the case CRS.
    seed : int
        Gmsh's random seed.
    algorithm : {"frontal-delaunay", "delaunay", "meshadapt", "automatic"}
    optimize : bool
    parts : int or "auto", default "auto"
        Parts of the water meshed alone, at once on as many processes as the
        run has workers, or on a Dask cluster (:mod:`coastmesh.meshing.parts.cuts`,
        :mod:`coastmesh.meshing.parts.tasks`); ``"auto"``: one per 200,000 expected
        triangles, rounded down to a power of two (1 to 64). It depends on the
        case only, so the mesh is the same on any number of cores or machines.
        1 is one part. The boundary nodes are the same either way, and so,
        measured on the NW-shelf meshes, is the quality (docs/meshing.md).
    """

    crs: str | None = None
    output_crs: str | None = None
    seed: int = 0
    algorithm: str = "frontal-delaunay"
    optimize: bool = True
    parts: int | str = "auto"

    def _checked(self, c: Check) -> MeshConfig:
        from coastmesh.meshing.engine import ALGORITHMS

        return MeshConfig(
            crs=c.optional(schema.crs, self.crs, "crs"),
            output_crs=c.optional(schema.crs, self.output_crs, "output_crs"),
            seed=c(schema.integer(0), self.seed, "seed"),
            algorithm=c(schema.choice(tuple(ALGORITHMS)), self.algorithm, "algorithm"),
            optimize=c(schema.boolean, self.optimize, "optimize"),
            parts=self.parts
            if self.parts == "auto"
            else c(_parts, self.parts, "parts"),
        )


@dataclass(frozen=True, slots=True)
class RunConfig:
    """``[run]``: where the parts are meshed (never what the mesh is).

    Attributes
    ----------
    workers : int, optional
        Local worker processes; default every core this process may use.
        ``coastmesh run --workers`` overrides it.
    scheduler : str, optional
        The address of a Dask distributed scheduler (``"tcp://host:8786"``):
        the parts are meshed as tasks on its workers. ``coastmesh run
        --scheduler`` overrides it.
    """

    workers: int | None = None
    scheduler: str | None = None

    def _checked(self, c: Check) -> RunConfig:
        return RunConfig(
            workers=c.optional(schema.integer(1), self.workers, "workers"),
            scheduler=c.optional(_address, self.scheduler, "scheduler"),
        )


def _address(value: Any, key: str) -> str:
    """``[run] scheduler``: a Dask address such as "tcp://host:8786"."""
    text = schema.string(value, key)
    if "://" not in text and ":" not in text:
        raise ConfigError(
            f"{key} = {value!r}: expected a Dask scheduler address such as "
            '"tcp://10.0.0.5:8786"'
        )
    return text


def _parts(value: Any, key: str) -> int:
    """``[mesh] parts``: "auto" or an integer >= 1."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ConfigError(f'{key} = {value!r}: expected "auto" or an integer >= 1')
    return value


@dataclass(frozen=True, slots=True)
class OutputConfig:
    """``[output]``: what :meth:`coastmesh.CaseResult.write` writes.

    Attributes
    ----------
    formats : sequence of str
        Mesh formats by name (:func:`coastmesh.io.mesh_formats`).
    positive : mapping of str to {"up", "down"}, optional
        The depth sign per format, where a format takes one.
    domain, size_field, figures, quality : bool
        Also write ``domain.gpkg``, ``size.tif``, ``figures/`` and the quality
        report.
    detail : (minx, miny, maxx, maxy), optional
        A detail box for a Mercator mesh figure.
    sphere_xyz : bool
        Write ``msh2``/``msh4`` nodes as Cartesian x, y, z on the sphere (for
        Fluidity and Thetis meshes of the globe), with the same physical ids.
    """

    formats: tuple[str, ...] = ("msh2",)
    positive: Mapping[str, str] | None = None
    domain: bool = True
    size_field: bool = True
    figures: bool = True
    quality: bool = True
    detail: tuple[float, float, float, float] | None = None
    sphere_xyz: bool = False

    def _checked(self, c: Check) -> OutputConfig:
        return OutputConfig(
            formats=c(_formats, self.formats, "formats"),
            positive=c.optional(_signs, self.positive, "positive"),
            domain=c(schema.boolean, self.domain, "domain"),
            size_field=c(schema.boolean, self.size_field, "size_field"),
            figures=c(schema.boolean, self.figures, "figures"),
            quality=c(schema.boolean, self.quality, "quality"),
            detail=c.optional(schema.box, self.detail, "detail"),
            sphere_xyz=c(schema.boolean, self.sphere_xyz, "sphere_xyz"),
        )


def _formats(value: Any, key: str) -> tuple[str, ...]:
    from coastmesh.io import mesh_formats

    names = schema.names(value, key)
    known = mesh_formats()
    for k, n in enumerate(names):
        if n not in known:
            raise ConfigError(
                f"{key}[{k}] = {n!r}: unknown format; known: {', '.join(known)}"
            )
    if len(set(names)) != len(names):
        raise ConfigError(f"{key} = {list(names)}: a format is listed twice")
    return names


def _signs(value: Any, key: str) -> dict[str, str]:
    from coastmesh.io import mesh_formats

    if not isinstance(value, Mapping):
        raise ConfigError(
            f"{key} = {value!r}: expected a table, e.g. {{ mike = 'up' }}"
        )
    known = mesh_formats()
    for name, sign in value.items():
        if name not in known:
            raise ConfigError(
                f"{key}.{name}: unknown format; known: {', '.join(known)}"
            )
        schema.choice(_UP_DOWN)(sign, f"{key}.{name}")
    return dict(value)
