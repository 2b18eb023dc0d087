"""What a kind of case does its own way: :class:`Strategy`, and the regional one.

The stages of :data:`coastmesh.case.pipeline.STAGES` are the same for every
case. Where a regional and a global case differ (the shorelines and the plane
the domain is built in, the size grid, the rasters the size terms read, the
grid the mesher is handed), a stage asks the run's strategy:
:class:`Regional` here, :class:`~coastmesh.case.pipeline.world.Global` for
``[domain] kind = "global"``.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, ClassVar

import shapely
import xarray as xr
from pyproj import CRS

from coastmesh.case.config import CaseConfig, RasterConfig
from coastmesh.case.pipeline.closing import close_water, size_grid
from coastmesh.case.pipeline.depth import read_sources
from coastmesh.case.pipeline.domain import build_case_domain
from coastmesh.case.pipeline.shorelines import regional_sets
from coastmesh.case.pipeline.state import (
    CaseRun,
    DomainRun,
    DomainState,
    RunContext,
    ShorelineRun,
    Shorelines,
    SizedRun,
)
from coastmesh.depth import DepthSources
from coastmesh.geometry.projection import default_mesh_crs
from coastmesh.sizing.grid import Grid
from coastmesh.types import SizeGrid

if TYPE_CHECKING:
    from coastmesh.meshing.gmsh.sphere_sizes import SphereSizeGrid

__all__ = ["Regional", "Strategy"]


class Strategy:
    """The steps a kind of case does its own way (a base class).

    Attributes
    ----------
    on_sphere : bool
        The mesh covers the sphere, in longitude and latitude: its quality is
        measured on the sphere too, and it is drawn on a globe.
    """

    on_sphere: ClassVar[bool] = False

    def shorelines(self, run: CaseRun, ctx: RunContext) -> Shorelines:
        """Read the shoreline layer and build the shoreline sets."""
        raise NotImplementedError

    def domain(self, run: ShorelineRun, ctx: RunContext) -> DomainState:
        """Build the domain from the sets; choose the CRSs of the mesh."""
        raise NotImplementedError

    def close_water(self, run: DomainRun, ctx: RunContext) -> DomainState:
        """Close water too narrow to mesh, as land; the domain cut by it."""
        return run.domain

    def grid(self, run: DomainRun, ctx: RunContext) -> Grid:
        """Return the grid of the size field."""
        raise NotImplementedError

    def read_depth(
        self, run: DomainRun, part: RasterConfig
    ) -> xr.DataArray | DepthSources:
        """Read a ``[bathymetry]``-like part's rasters for the size terms."""
        raise NotImplementedError

    def size_grid(self, run: SizedRun) -> SizeGrid | SphereSizeGrid:
        """Return the size field as the mesher takes it."""
        raise NotImplementedError

    def parts(self, config: CaseConfig) -> int | str:
        """Return the parts the water is cut into."""
        return config.mesh.parts


class Regional(Strategy):
    """A regional case: meshed in a conformal projection, in parts."""

    def shorelines(self, run: CaseRun, ctx: RunContext) -> Shorelines:
        """Read the shorelines; build each set in the case CRS."""
        return regional_sets(run, ctx)

    def domain(self, run: ShorelineRun, ctx: RunContext) -> DomainState:
        """Build the domain in the case CRS; mesh in ``[mesh] crs`` or UTM."""
        config, shorelines = run.config, run.shorelines
        crs = shorelines.crs
        with ctx.timed("building the domain"):
            state = build_case_domain(
                config,
                shorelines.sets,
                crs,
                mesh_crs=CRS.from_user_input(config.mesh.crs or crs),
                output_crs=CRS.from_user_input(config.mesh.output_crs or crs),
            )
        if config.mesh.crs is None:
            state = _with_mesh_crs(state, default_mesh_crs(state.domain))
        return state

    def close_water(self, run: DomainRun, ctx: RunContext) -> DomainState:
        """Close slots, and narrow channels with ``narrow = "close"``."""
        return close_water(run, ctx)

    def grid(self, run: DomainRun, ctx: RunContext) -> Grid:
        """Return a grid regular in the meshing CRS, two cells beyond the domain."""
        return size_grid(run.domain, run.config, ctx.threads)

    def read_depth(self, run: DomainRun, part: RasterConfig) -> DepthSources:
        """Read the part's rasters over the domain's box only."""
        domain = run.domain.domain
        polygon = domain.polygon
        ring = shapely.segmentize(polygon.exterior, polygon.length / 400)
        return read_sources(part.stack, shapely.get_coordinates(ring), domain.crs)

    def size_grid(self, run: SizedRun) -> SizeGrid:
        """Return the size field in metres, with the grid's scale factors."""
        size = run.size
        return SizeGrid(
            size.grid.x, size.grid.y, size.field.values, scale=size.grid.scale
        )


def _with_mesh_crs(state: DomainState, crs: CRS) -> DomainState:
    return replace(state, mesh_crs=crs)
