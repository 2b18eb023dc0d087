"""``[mesh_size.bathymetry]``: size terms from the depth: tidal wavelength, slope.

Sizes from a raster (``path``), or from a stack of them
(``[[mesh_size.bathymetry.sources]]``, the keys of ``[[bathymetry.sources]]``),
read over the domain's box; a global case takes one ``path``, read whole.
``per_wavelength`` asks for ``h = T sqrt(g d) / n``, ``n`` elements per tidal
wavelength; ``per_slope`` for ``h = 2 pi d / (n |grad d|)``, ``n`` elements per
``2 pi`` topographic length scales. At least one of the two. On a global case's
world grid the gradient takes each grid step's true length on the sphere
(``R cos(lat) dlon`` east-west, ``R dlat`` north-south, across the
antimeridian) and the depths of the sea alone: no node of the sea takes a
slope from land.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.sources import RasterConfig
from coastmesh.case.terms.base import SizeCase, SizeTerm
from coastmesh.sizing.bathymetry import M2_PERIOD, wavelength_size
from coastmesh.sizing.combine import TermSizes
from coastmesh.sizing.grid import Grid

__all__ = ["Bathymetry", "BathymetryConfig"]


@dataclass(frozen=True)
class BathymetryConfig(RasterConfig):
    """``[mesh_size.bathymetry]``: at least one of the two terms."""

    per_wavelength: float | None = key(
        None,
        check=schema.positive,
        doc="elements per tidal wavelength, `h = T sqrt(g d) / n`",
    )
    period: float = key(
        M2_PERIOD,
        check=schema.duration,
        unit="duration",
        default_doc='M2 (`"12.4206012 h"`)',
        doc="the wave period",
    )
    per_slope: float | None = key(
        None,
        check=schema.positive,
        doc="elements per `2 pi` topographic length scales, "
        "`h = 2 pi d / (n |grad d|)`",
    )
    min_depth: float = key(
        1.0, check=schema.length(), unit="length", doc="the depth floor of both terms"
    )

    def _validate(self, c: Check) -> BathymetryConfig:
        if self.per_wavelength is None and self.per_slope is None:
            raise c.error("per_wavelength", "give per_wavelength and/or per_slope")
        return super()._validate(c)


class Bathymetry(SizeTerm[BathymetryConfig | None]):
    """The term of ``[mesh_size.bathymetry]``."""

    key = "bathymetry"
    config = BathymetryConfig
    many = False
    default = None
    doc = "size terms from a bathymetry raster: tidal wavelength and slope (below)"

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """Return the smaller of the wavelength and slope terms at the nodes."""
        b = self.settings(case)
        if b is None:
            return None
        depth = grid.depth(case.depth(b), b.positive)
        size = np.full(depth.shape, np.inf)
        if b.per_wavelength is not None:
            wave = wavelength_size(
                depth,
                per_wavelength=b.per_wavelength,
                period=b.period,
                min_depth=b.min_depth,
            )
            size = np.minimum(size, wave)
        if b.per_slope is not None:
            slope = grid.slope_size(depth, per_slope=b.per_slope, min_depth=b.min_depth)
            size = np.minimum(size, slope)
        # a land node (outside the domain) takes its nearest sea node's size:
        # the mesher interpolates between the nodes of a cell, and a land
        # node's size from the raster's land (min_depth: 4.4 km at 100 per
        # wavelength) reached into the sea across every coastal cell (the
        # Chilean coast of world.toml was meshed at 5 km for it, where the sea
        # nodes asked 70)
        if grid.domain is not None and grid.sea.any():
            size = grid.over_land(size, grid.sea)
        return TermSizes(upper=size, history="bathymetry")
