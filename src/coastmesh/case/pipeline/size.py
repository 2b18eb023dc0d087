"""The size stage: every size term on the strategy's grid, combined.

Each size term of the case (:func:`~coastmesh.case.config.terms_of`) computes its
sizes on the grid (:meth:`~coastmesh.case.terms.SizeTerm.sizes`), all at once on
threads (the distance queries, the distance transforms of the channel term and
the raster reads let go of the GIL; a term that reads another's sizes waits for
them); :func:`~coastmesh.sizing.combine.combine` then
combines them in the one order its docs give, with the floor
(:func:`~coastmesh.case.config.floor`), ``h_max`` and the gradation limit.
"""

from __future__ import annotations

import logging
import warnings
from concurrent.futures import Future, ThreadPoolExecutor
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import (
    PYTHON_SOURCE,
    NodeDepthConfig,
    RasterConfig,
    SizeConfig,
    floor,
    terms_of,
    terms_smallest,
)
from coastmesh.case.pipeline.closing import smallest_size
from coastmesh.case.pipeline.depth import read_sources
from coastmesh.case.pipeline.domain import site_area
from coastmesh.case.pipeline.farms import SiteFeatures
from coastmesh.case.pipeline.state import DomainRun, RunContext, SizedRun, SizeState
from coastmesh.case.schema import Check, check_part
from coastmesh.case.terms.base import SizeCase, SizeTables
from coastmesh.depth import DepthSources
from coastmesh.errors import CoastmeshWarning
from coastmesh.geometry import reproject
from coastmesh.geometry.projection import default_mesh_crs
from coastmesh.sizing.bands import BandRunner
from coastmesh.sizing.combine import TermSizes, combine
from coastmesh.sizing.grid import Grid, PlaneGrid
from coastmesh.types import Domain, Progress

__all__ = ["domain_size_field", "size_field", "size_stage"]

if TYPE_CHECKING:
    import xarray as xr

logger = logging.getLogger(__name__)


def size_stage(run: DomainRun, ctx: RunContext) -> SizedRun:
    """Make the size field of the domain (``[mesh_size]``)."""
    config, state = run.config, run.domain
    with ctx.timed("size field") as progress:
        case = SizeCase(
            config,
            state.domain,
            floor(config.size),
            read_depth=partial(run.strategy.read_depth, run),
            runner=ctx.runner,
            closing=state.closing,
            site_area=site_area(config, state.mesh_crs),
            lines=_farm_outlines(run.site, state.domain.crs),
        )
        size = size_field(run.strategy.grid(run, ctx), case, progress, ctx.threads)
    return run.with_size(size)


def _farm_outlines(site: SiteFeatures | None, crs: CRS) -> dict[str, shapely.Geometry]:
    """Return each farm's outline by name, in ``crs``: gradations may name it."""
    if site is None:
        return {}
    return {
        name: reproject(polygon.exterior, site.crs, crs)
        for name, _, polygon, _ in site.farms
    }


def size_field(
    grid: Grid, case: SizeCase, progress: Progress | None = None, threads: int = 1
) -> SizeState:
    """Compute every size term of ``case`` on ``grid`` and combine them.

    Parameters
    ----------
    grid : Grid
        Where the field lives (:class:`~coastmesh.sizing.grid.PlaneGrid` or
        :class:`~coastmesh.sizing.grid.SphereGrid`).
    case : SizeCase
        The case as the terms see it.
    progress : callable, optional
        Called as ``progress(done, total)`` as the terms finish.
    threads : int, default 1
        The terms run on this many threads at once (numpy, GEOS and scikit-image
        let go of Python's lock); the field does not depend on it.

    Returns
    -------
    SizeState
        The grid, the field (metres), its report, and the terms' other grids.
    """
    size = case.config.size
    terms = terms_of(size)
    total = len(terms) + 1
    # first in, first out: a term that waits for the sizes of terms before it
    # (its reads) holds a thread only once they have all started, so the pool
    # cannot deadlock at any size
    with ThreadPoolExecutor(max(1, min(int(threads), len(terms)))) as pool:
        running: dict[str, Future[TermSizes | None]] = {}
        for term in terms:
            running[term.key] = pool.submit(
                term.sizes, grid, case.reading(term, running)
            )
        done = []
        for k, (key, future) in enumerate(running.items()):
            done.append((key, future.result()))
            if progress is not None:
                progress(k + 1, total)
    _warn_if_floored_away(size, done)
    combined = combine(
        grid,
        done,
        h_min=case.floor,
        h_max=size.h_max,
        rate=size.rate,
        reporting=[term.key for term in terms if term.reports],
    )
    if progress is not None:
        progress(total, total)
    logger.info("size field: %s", combined.report.summary())
    return SizeState(
        grid, combined.field, combined.report, combined.layers, combined.conform
    )


def _warn_if_floored_away(
    size: SizeConfig, done: list[tuple[str, TermSizes | None]]
) -> None:
    """Warn when the default floor, ``h_max``, takes away a term's refinement."""
    if size.h_min is not None or terms_smallest(size, floors=True) is not None:
        return
    finer = [
        key
        for key, sizes in done
        if sizes is not None
        and sizes.upper is not None
        and sizes.floor is None  # a term with a floor of its own is not floored
        and float(np.nanmin(sizes.upper)) < size.h_max
    ]
    if finer:
        warnings.warn(
            "mesh_size: no h_min and no gradations, so the floor is "
            f"h_max = {size.h_max:g} m and the {', '.join(finer)} term(s) cannot "
            "make the mesh finer anywhere; give mesh_size.h_min",
            CoastmeshWarning,
            stacklevel=3,
        )


def domain_size_field(
    domain: Domain,
    size: SizeConfig,
    *,
    mesh_crs: CRS | str | None = None,
    bathymetry: NodeDepthConfig | None = None,
    depth: xr.DataArray | DepthSources | None = None,
    runner: BandRunner | None = None,
    sites: shapely.Geometry | None = None,
) -> SizeState:
    """Make the size field of a domain built in Python: the size stage alone.

    Parameters
    ----------
    domain : Domain
        The domain; gradations name its boundary segments.
    size : SizeConfig
        ``[mesh_size]``: ``h_max``, the floor, the grid, the gradation limit,
        and a table per size term (checked here, as a case checks it).
    mesh_crs : pyproj.CRS or CRS-like, optional
        The projected, conformal CRS the mesh is made in; default
        :func:`~coastmesh.geometry.projection.default_mesh_crs` of the domain.
        The grid is regular there.
    bathymetry : NodeDepthConfig, optional
        ``[bathymetry]``: the depth of the Courant term when ``size`` has no
        bathymetry table.
    depth : xarray.DataArray or DepthSources, optional
        The raster (or stack) the terms take their depth from, in memory,
        instead of the files their tables name.
    runner : Runner, optional
        Where the gradations' distances run, in bands of rows.
    sites : shapely geometry, optional
        Regions meshed finely on purpose (``[[sites]]``), in ``mesh_crs``:
        channels there get two elements across or more, below the floor if
        need be, and the Courant floor does not apply.

    Returns
    -------
    SizeState
        ``grid``, ``field`` (metres, an xarray DataArray), ``report`` (each
        term's report by its key) and ``layers`` (the channel term's width).

    Examples
    --------
    >>> from coastmesh.case import GradationConfig, SizeConfig
    >>> from coastmesh.types import BoundarySegment
    >>> ring = [[0, 0], [20000, 0], [20000, 20000], [0, 20000], [0, 0]]
    >>> d = Domain(shapely.Polygon(ring),
    ...            (BoundarySegment(ring[:2], "open", "south", 2),
    ...             BoundarySegment(ring[1:], "shoreline", "coast", 1)),
    ...            crs="EPSG:32630")
    >>> size = SizeConfig(h_max="2 km", cell="500 m", gradations=[
    ...     GradationConfig(["coast"], h_min="200 m", d_grade="5 km")])
    >>> out = domain_size_field(d, size, mesh_crs="EPSG:32630")
    >>> float(out.field.min()), float(out.field.max()), out.field.shape
    (200.0, 2000.0, (45, 45))
    """
    size = check_part(size, SizeConfig, Check(PYTHON_SOURCE), "mesh_size")
    crs = default_mesh_crs(domain) if mesh_crs is None else CRS(mesh_crs)
    grid = PlaneGrid.around(
        domain, crs, spacing=size.cell, smallest=smallest_size(size)
    )

    def read(part: RasterConfig) -> xr.DataArray | DepthSources:
        if depth is not None:
            return depth
        ring = shapely.segmentize(domain.polygon.exterior, domain.polygon.length / 400)
        return read_sources(part.stack, shapely.get_coordinates(ring), domain.crs)

    tables = SizeTables(size, bathymetry)
    case = SizeCase(
        tables, domain, floor(size), read_depth=read, runner=runner, site_area=sites
    )
    return size_field(grid, case)
