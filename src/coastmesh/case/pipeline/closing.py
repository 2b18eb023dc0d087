"""Water closed as land before the size field: slots, and narrow channels.

With the channel term on (``[mesh_size.channels]``, on by default):

* ``narrow = "keep"``: slots of water narrower than ``h_min / 2`` (spikes of a
  coastline, thinner than any element) become land
  (:func:`~coastmesh.sizing.slots.domain_slots`);
* ``narrow = "close"`` (the default): the slots and the channels narrower
  than two elements of ``h_min`` outside the ``[[sites]]``, found by the width
  of the water on the size field's grid, become land. A cut can leave new
  narrow water next to it, so this is done up to :data:`CLOSE_PASSES` times,
  and the slivers the last cut leaves at the coast close too; what is narrow
  after the last pass is kept, and the channel term warns of it.

The domain is then built again from the same stitched shorelines
(:func:`~coastmesh.case.pipeline.domain.with_land`).
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np
import shapely
from numpy.typing import NDArray

from coastmesh.case.config import CaseConfig, SizeConfig, floor
from coastmesh.case.pipeline.domain import site_area, with_land
from coastmesh.case.pipeline.state import CaseRun, DomainState, RunContext, missing
from coastmesh.case.terms.base import Closing
from coastmesh.geometry import reproject
from coastmesh.sizing.grid import PlaneGrid
from coastmesh.sizing.narrow import (
    NARROW_ELEMENTS,
    ChannelReport,
    channel_polygons,
    narrow_channels,
    narrow_places,
    warn_narrow,
)
from coastmesh.sizing.slots import domain_slots, off_open_boundaries

__all__ = ["CLOSE_PASSES", "close_water", "size_grid", "smallest_size"]

logger = logging.getLogger(__name__)

#: Most times narrow channels are closed and the domain built again.
CLOSE_PASSES = 3


def close_water(run: CaseRun, ctx: RunContext) -> DomainState:
    """Close what the channel term asks: narrow channels and slots, or slots."""
    config, state = run.config, run.domain or missing("domain")
    channels = config.size.channels
    if not channels.enabled:
        return state
    if channels.narrow == "close":
        with ctx.timed("closing narrow channels"):
            return _close_channels(state, config)
    with ctx.timed("closing slots"):
        thin = domain_slots(
            state.domain, state.mesh_crs, floor(config.size) / 2, threads=ctx.threads
        )
        if len(thin):
            state = with_land(state, config, thin)
            logger.info("closed %d slots narrower than h_min / 2", len(thin))
    return replace(state, closing=Closing(slots=len(thin)))


def size_grid(state: DomainState, config: CaseConfig, threads: int = 1) -> PlaneGrid:
    """Return the size field's grid for a regional domain (the closing's too).

    Its spacing is ``[mesh_size] cell``, else the extent over 1000 but not
    below the smallest size asked for.
    """
    return PlaneGrid.around(
        state.domain,
        state.mesh_crs,
        spacing=config.size.cell,
        smallest=smallest_size(config.size),
        threads=threads,
    )


def smallest_size(size: SizeConfig) -> float:
    """Return the smallest size ``[mesh_size]`` asks for: the grid is no finer."""
    given = [g.h_min for g in size.gradations] + ([size.h_min] if size.h_min else [])
    return min(given or [size.h_max])


def _close_channels(state: DomainState, config: CaseConfig) -> DomainState:
    """Make the narrow channels land; return the domain and what closed."""
    closed_count, closed_km2, passes = 0, 0.0, 0
    land: list[shapely.Geometry] = []
    report = None
    for _ in range(CLOSE_PASSES):
        found, polygons = _narrow_water(state, config)
        if not len(polygons):
            break
        report = found
        closed_count += len(polygons)
        closed_km2 += found.narrow_km2
        land.extend(polygons)
        state = with_land(state, config, np.array(land, dtype=object))
        passes += 1
    if report is None:
        return state
    # the last cut can leave slivers where it meets the coast: close those too
    slivers = domain_slots(state.domain, state.mesh_crs, floor(config.size) / 2)
    if len(slivers):
        land.extend(slivers)
        state = with_land(state, config, np.array(land, dtype=object))
    closed = replace(report, narrow_channels=closed_count, narrow_km2=closed_km2)
    warn_narrow(closed, closed=True)
    return replace(state, closing=Closing(channels=closed, passes=passes))


def _narrow_water(
    state: DomainState, config: CaseConfig
) -> tuple[ChannelReport, NDArray[np.object_]]:
    """Find the narrow channels and slots of the domain, as polygons to close.

    The channels are found by the width of the water alone (no gradation or
    bathymetry term: the width needs neither), on the size field's grid. Each
    channel is its cells, one cell wider (into the land, and past its mouth)
    and simplified, so that the cut is clean; none that touches an open
    boundary is closed.
    """
    domain, channels, h_min = state.domain, config.size.channels, floor(config.size)
    grid = size_grid(state, config)
    if grid.cell > h_min / 2:  # widths to half a floor element, or 2 h_min is a guess
        grid = PlaneGrid.around(
            domain,
            state.mesh_crs,
            spacing=max(h_min, grid.cell) / 2,
            smallest=smallest_size(config.size),
        )
    # only whether water is narrower than NARROW_ELEMENTS h_min matters here:
    # wider water comes out inf, and the few radii are quick
    width = grid.widths(domain, max_width=1.05 * NARROW_ELEMENTS * h_min)
    sea = grid.sea
    sites = site_area(config, state.mesh_crs)
    if sites is not None:  # channels in a site are kept (and refined)
        shapely.prepare(sites)
        xx, yy = np.meshgrid(grid.x, grid.y)
        sea = sea & ~shapely.contains_xy(sites, xx, yy)
    labels, found = narrow_channels(width, sea, h_min=h_min, cell=grid.cell)
    report = ChannelReport(
        elements_across=float(channels.elements_across),
        h_min=float(h_min),
        narrow="close",
        limited_km2=0.0,
        narrow_channels=len(found),
        narrow_km2=sum(a for _, _, a, _ in found) / 1e6,
        worst=narrow_places(found, grid.x, grid.y, grid.crs),
    )
    polygons = domain_slots(domain, state.mesh_crs, h_min / 2)
    if found:
        cells = channel_polygons(labels, grid.x, grid.y)
        grown = shapely.simplify(
            shapely.buffer(cells, grid.cell, quad_segs=2), grid.cell
        )
        grown = shapely.make_valid(grown)
        polygons = np.concatenate(
            [polygons, reproject(grown, state.mesh_crs, domain.crs)]
        )
    if len(polygons):
        polygons = off_open_boundaries(polygons, domain)
    return report, polygons
