"""Water closed as land before the size field: slots, and narrow channels.

With the channel term on (``[mesh_size.channels]``, on by default):

* ``narrow = "keep"``: slots of water narrower than ``h_min / 2`` (spikes of a
  coastline, thinner than any element) become land
  (:func:`~coastmesh.sizing.slots.domain_slots`);
* ``narrow = "close"`` (the default): the slots and the channels narrower
  than two elements of ``h_min`` outside the ``[[sites]]``, found by the width
  of the water on the size field's grid, become land. A cut can leave new
  narrow water next to it, so this is done up to :data:`CLOSE_PASSES` times,
  and the slivers each cut leaves at the coast close with it; what is narrow
  after the last pass is kept, and the channel term warns of it.

After each pass the sea is cut by what closed and its boundary tagged again
(:func:`~coastmesh.case.pipeline.domain.with_land`): the domain building it
again from the same stitched shorelines would give.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import shapely
from numpy.typing import NDArray
from scipy import ndimage

from coastmesh.case.config import CaseConfig, SizeConfig, floor, terms_smallest
from coastmesh.case.pipeline.domain import site_area, with_land
from coastmesh.case.pipeline.state import DomainRun, DomainState, RunContext
from coastmesh.case.terms.base import Closing
from coastmesh.errors import ConfigError
from coastmesh.geometry import reproject
from coastmesh.geometry.earth import densified
from coastmesh.sizing.channel import window_width
from coastmesh.sizing.grid import PlaneGrid, grid_axes
from coastmesh.sizing.narrow import (
    NARROW_ELEMENTS,
    ChannelReport,
    channel_polygons,
    narrow_channels,
    narrow_places,
    warn_narrow,
)
from coastmesh.sizing.slots import domain_slots, off_open_boundaries, slots_near
from coastmesh.types import Domain

__all__ = ["CLOSE_PASSES", "close_water", "size_grid", "smallest_size"]

logger = logging.getLogger(__name__)

#: The narrow channels :func:`~coastmesh.sizing.narrow.narrow_channels` finds:
#: (row, col, area m2, width m) each: its widest node, its area, its width.
Found = list[tuple[int, int, float, float]]
#: A grid, the channels labelled on it, and what was found there.
Piece = tuple[PlaneGrid, NDArray[np.int32], Found]

#: Most times narrow channels are closed and the domain cut by them.
CLOSE_PASSES = 2


def close_water(run: DomainRun, ctx: RunContext) -> DomainState:
    """Close what the channel term asks: narrow channels and slots, or slots."""
    config, state = run.config, run.domain
    channels = config.size.channels
    if channels is None or not channels.enabled:
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


def size_grid(
    state: DomainState, config: CaseConfig, threads: int = 1, *, floors: bool = False
) -> PlaneGrid:
    """Return the size field's grid for a regional domain (the closing's too).

    Its spacing is ``[mesh_size] cell``, else the extent over 1000 but not
    below the smallest size asked for (with ``floors``, by the terms that set
    the floor alone: the closing's grid does not change with the sizes of
    ``[[mesh_size.fields]]``, nor then does the domain).
    """
    return PlaneGrid.around(
        state.domain,
        state.mesh_crs,
        spacing=config.size.cell,
        smallest=smallest_size(config.size, floors=floors),
        threads=threads,
    )


def smallest_size(size: SizeConfig, *, floors: bool = False) -> float:
    """Return the smallest size ``[mesh_size]`` asks for: the grid is no finer.

    ``floors``: of the terms that set the floor alone (:func:`terms_smallest`).
    """
    given = [v for v in (terms_smallest(size, floors=floors), size.h_min) if v]
    return min(given or [size.h_max])


def _close_channels(state: DomainState, config: CaseConfig) -> DomainState:
    """Make the narrow channels land; return the domain and what closed."""
    closed_count, closed_km2, passes = 0, 0.0, 0
    report = None
    polygons = None
    for _ in range(CLOSE_PASSES):
        # after a cut, new narrow water can only be next to it: look there
        found, polygons = _narrow_water(state, config, near=polygons)
        if not len(polygons):
            break
        _refuse_closing_all(state, config, found)
        report = found
        closed_count += len(polygons)
        closed_km2 += found.narrow_km2
        # a cut can leave slivers where it meets the coast: close them with it
        slivers = _slivers(state, polygons, floor(config.size) / 2)
        state = with_land(state, config, np.concatenate([polygons, slivers]))
        passes += 1
    if report is None:
        return state
    closed = replace(report, narrow_channels=closed_count, narrow_km2=closed_km2)
    warn_narrow(closed, closed=True)
    return replace(state, closing=Closing(channels=closed, passes=passes))


def _slivers(
    state: DomainState, polygons: NDArray[np.object_], width: float
) -> NDArray[np.object_]:
    """Return the slots narrower than ``width`` that closing ``polygons`` leaves.

    Looked for around the polygons only (within ``4 width`` of their boxes),
    in the water less them (:func:`~coastmesh.sizing.slots.slots_near`); as
    land in the domain's CRS, none that touches an open boundary.
    """
    domain, crs = state.domain, state.mesh_crs
    water = densified(domain, [domain.polygon], crs)[0]
    cuts = reproject(np.asarray(polygons, dtype=object), domain.crs, crs)
    reach = 4 * width  # two h_min: the slivers a cut leaves are at its edge
    boxes = shapely.bounds(cuts) + [-reach, -reach, reach, reach]
    thin = slots_near(water, width, boxes, shapely.union_all(cuts))
    if not len(thin):
        return thin
    grown = reproject(shapely.buffer(thin, width / 10), crs, domain.crs)
    return off_open_boundaries(grown, domain)


def _refuse_closing_all(
    state: DomainState, config: CaseConfig, found: ChannelReport
) -> None:
    """Raise if the narrow channels are (nearly) all of the domain's water."""
    sea_km2 = state.domain.polygon.area
    if state.domain.crs.is_geographic:  # degrees squared: measure on the plane
        sea_km2 = reproject(state.domain.polygon, state.domain.crs, state.mesh_crs).area
    sea_km2 /= 1e6
    if found.narrow_km2 < 0.9 * sea_km2:
        return
    raise ConfigError(
        f"{config.label}: mesh_size.channels: {found.narrow_km2:,.1f} of the "
        f"{sea_km2:,.1f} km2 of water are channels narrower than 2 elements of "
        f"h_min = {found.h_min:g} m: closing them (narrow = 'close') would leave no "
        "sea. Lower h_min (or the gradations' h_min), mark the water as a "
        '[[sites]] region to keep it, or set narrow = "keep"'
    )


def _narrow_water(
    state: DomainState, config: CaseConfig, near: NDArray[np.object_] | None = None
) -> tuple[ChannelReport, NDArray[np.object_]]:
    """Find the narrow channels and slots of the domain, as polygons to close.

    The channels are found by the width of the water alone (no gradation or
    bathymetry term: the width needs neither). The size field's grid finds the
    candidates; where its cells are coarser than half of ``h_min`` (widths
    there err narrow by up to a cell), each candidate is measured again on a
    grid of ``h_min / 2`` around it (:func:`_confirmed`), so that water two
    elements wide is not closed for the coarse grid's sake. Each channel is
    its cells, one cell wider (into the land, and past its mouth) and
    simplified, so that the cut is clean; none that touches an open boundary
    is closed.

    With ``near`` (the polygons the last pass closed, in the domain's CRS),
    only the water around them is measured (on the fine grid), and the slots
    are left to the slivers' pass: a cut changes the width of nothing further.
    """
    domain, channels, h_min = state.domain, config.size.channels, floor(config.size)
    assert channels is not None  # close_water closes channels only with the term on
    grid = size_grid(state, config, floors=True)
    sites = site_area(config, state.mesh_crs)
    if near is not None:
        # water farther than the widest disk measured from a cut keeps its width
        reach = 1.05 * NARROW_ELEMENTS * h_min
        bounds = shapely.bounds(reproject(near, domain.crs, grid.crs))
        boxes = shapely.box(*(bounds + [-reach, -reach, reach, reach]).T)
        pieces = _confirmed(grid, boxes, domain, h_min, sites)
    else:
        labels, found = _channels(grid, domain, h_min, sites)
        pieces = [(grid, labels, found)]
        if found and grid.cell > h_min / 2:
            pieces = _confirmed(grid, _boxes(grid, labels), domain, h_min, sites)
    found = sorted((f for _, _, fs in pieces for f in fs), key=lambda f: -f[2])
    places = sorted(
        (p for g, _, fs in pieces for p in narrow_places(fs, g.x, g.y, g.crs)),
        key=lambda p: -p.area_m2,
    )
    report = ChannelReport(
        elements_across=float(channels.elements_across),
        h_min=float(h_min),
        narrow="close",
        limited_km2=0.0,
        narrow_channels=len(found),
        narrow_km2=sum(a for _, _, a, _ in found) / 1e6,
        worst=tuple(places[:20]),
    )
    polygons = (
        domain_slots(domain, state.mesh_crs, h_min / 2)
        if near is None
        else np.empty(0, dtype=object)
    )
    lines = [shapely.LineString(s.coords) for s in domain.segments if s.kind == "open"]
    opened = densified(domain, lines, state.mesh_crs) if lines else None
    for g, lab, fs in pieces:
        if not fs:
            continue
        cells = channel_polygons(lab, g.x, g.y)
        grown = shapely.simplify(shapely.buffer(cells, g.cell, quad_segs=2), g.cell)
        grown = shapely.make_valid(grown)
        if opened is not None:  # a cut near an open boundary would leave a
            # run of coast too short between it and the next (Telemac needs 3)
            near = shapely.dwithin(grown[:, None], opened[None, :], h_min).any(1)
            grown = grown[~near]
        polygons = np.concatenate(
            [polygons, reproject(grown, state.mesh_crs, domain.crs)]
        )
    if len(polygons):
        polygons = off_open_boundaries(polygons, domain)
    return report, polygons


def _channels(
    grid: PlaneGrid, domain: Domain, h_min: float, sites: shapely.Geometry | None
) -> tuple[NDArray[np.int32], Found]:
    """Label the water narrower than two elements of ``h_min`` on ``grid``.

    Only whether water is narrower than ``NARROW_ELEMENTS h_min`` matters here:
    one opening (:func:`~coastmesh.sizing.channel.narrow_width`); wider water
    comes out inf. Not in ``sites``.
    """
    width = grid.widths(domain, max_width=NARROW_ELEMENTS * h_min, narrow_only=True)
    sea = grid.sea
    if sites is not None:  # channels in a site are kept (and refined)
        shapely.prepare(sites)
        xx, yy = np.meshgrid(grid.x, grid.y)
        sea = sea & ~shapely.contains_xy(sites, xx, yy)
    return narrow_channels(width, sea, h_min=h_min, cell=grid.cell)


def _boxes(grid: PlaneGrid, labels: NDArray[np.int32]) -> list[shapely.Polygon]:
    """Return the box of each labelled candidate, a cell wider all round."""
    boxes = []
    for sl in ndimage.find_objects(labels):
        if sl is None:
            continue
        rows, cols = sl
        boxes.append(
            shapely.box(
                grid.x[cols.start] - grid.cell,
                grid.y[rows.start] - grid.cell,
                grid.x[cols.stop - 1] + grid.cell,
                grid.y[rows.stop - 1] + grid.cell,
            )
        )
    return boxes


def _confirmed(
    grid: PlaneGrid,
    boxes: Sequence[shapely.Polygon] | NDArray[np.object_],
    domain: Domain,
    h_min: float,
    sites: shapely.Geometry | None,
) -> list[Piece]:
    """Measure the water in ``boxes`` (candidates) on a grid of ``h_min / 2``.

    The boxes, merged where their windows overlap, each on its own fine
    grid: the margin (the widest disk measured, and a cell) keeps the
    window's frame from making water look narrow inside the box, since a disk
    that holds a node of the box lies within the margin. The domain's polygon
    and lines are moved to the grid's CRS once, and clipped to each window
    (:func:`~coastmesh.sizing.channel.window_width`). Returns ``(grid, labels,
    found)`` per window.
    """
    max_width = 1.05 * NARROW_ELEMENTS * h_min
    margin = max_width + h_min
    merged = shapely.get_parts(shapely.union_all(shapely.buffer(boxes, margin)))
    water = densified(domain, [domain.polygon], grid.crs)[0]
    lines: dict[str, list[shapely.Geometry]] = {"shoreline": [], "open": []}
    for s in domain.segments:
        lines[s.kind].append(shapely.LineString(s.coords))
    shore = densified(domain, lines["shoreline"], grid.crs)
    opened = densified(domain, lines["open"], grid.crs)
    pieces: list[Piece] = []
    for window in merged:
        core = shapely.buffer(window, -margin, join_style="mitre")
        fine = PlaneGrid(*grid_axes(window.bounds, h_min / 2), grid.crs, h_min / 2)
        width, sea = window_width(
            fine,
            water,
            np.asarray(shore),
            np.asarray(opened),
            max_width=NARROW_ELEMENTS * h_min,
        )
        xx, yy = np.meshgrid(fine.x, fine.y)
        shapely.prepare(core)
        sea &= shapely.contains_xy(core, xx, yy)
        if sites is not None:
            sea &= ~shapely.contains_xy(sites, xx, yy)
        found = narrow_channels(width, sea, h_min=h_min, cell=fine.cell)
        pieces.append((fine, *found))
    return pieces
