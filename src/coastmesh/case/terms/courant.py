"""``[mesh_size.courant]``: sizes a model runs at its time step.

The Courant number is ``C = dt (sqrt(g d) + u) / h``, with ``d`` the depth (from
``[mesh_size.bathymetry]``, else ``[bathymetry]``; one of them is required) and
``h`` the size. The size is kept between ``dt (sqrt(g d) + u) / courant_max`` (a
floor, which beats ``h_min``) and ``dt (sqrt(g d) + u) / courant_min`` (a cap).
Where no size in ``[h_min, h_max]`` meets the window, a warning gives the area.
Not in global cases yet.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeCase, SizeTerm
from coastmesh.errors import CoastmeshWarning
from coastmesh.sizing.combine import Applied, TermSizes
from coastmesh.sizing.courant import CourantReport, courant_bounds
from coastmesh.sizing.grid import Grid

__all__ = ["DEFAULT_COURANT_MAX", "Courant", "CourantConfig"]

#: ``courant_max`` when neither bound is given (explicit models).
DEFAULT_COURANT_MAX = 0.5


@dataclass(frozen=True)
class CourantConfig:
    """``[mesh_size.courant]``."""

    dt: float = key(
        check=schema.duration,
        unit="duration",
        doc='the model\'s time step (`"30 s"`, `"1 min"`)',
    )
    courant_max: float | None = key(
        None,
        check=schema.positive,
        default_doc="`0.5` if neither bound is given, else none",
        doc="the largest Courant number (explicit models: ADCIRC about 0.5 to 0.9)",
    )
    courant_min: float | None = key(
        None,
        check=schema.positive,
        doc="the smallest (SCHISM asks for 0.4 or more)",
    )
    velocity: float = key(
        1.0,
        check=schema.speed,
        unit="speed",
        doc='the flow speed `u` added to the wave speed (`"m/s"`, `"kn"`, `"km/h"`)',
    )

    def _validate(self, c: Check) -> CourantConfig:
        high, low = self.courant_max, self.courant_min
        if high is None and low is None:
            high = DEFAULT_COURANT_MAX
        if high is not None and low is not None and low >= high:
            raise c.error(
                "courant_min",
                f"= {low:g} is not below courant_max = {high:g}: no Courant number "
                "fits between them",
            )
        return replace(self, courant_max=high)


class Courant(SizeTerm):
    """The term of ``[mesh_size.courant]``."""

    key = "courant"
    config = CourantConfig
    many = False
    default = None
    doc = "sizes a model runs at its time step (below)"
    reports = True

    def sizes(self, grid: Grid, case: SizeCase) -> TermSizes | None:
        """Cap and floor the size so the Courant number stays in its window.

        The depth is ``[mesh_size.bathymetry]``'s, else ``[bathymetry]``'s.
        Warns of the area where no size in ``[h_min, h_max]`` meets the window.
        """
        co = case.config.size.courant
        if co is None:
            return None
        source = case.config.size.bathymetry or case.config.bathymetry
        min_depth = source.min_depth
        depth = grid.depth(case.depth(source), source.positive)
        floor, cap = courant_bounds(
            depth,
            dt=co.dt,
            courant_max=co.courant_max,
            courant_min=co.courant_min,
            velocity=co.velocity,
            min_depth=min_depth if min_depth is not None and min_depth > 0 else 1.0,
        )
        h_min, h_max = case.floor, case.config.size.h_max
        unmet = grid.km2(grid.sea & ((floor > h_max) | (cap < h_min)))
        if unmet > 0:
            warnings.warn(
                f"mesh_size.courant: no size in [h_min, h_max] = [{h_min:g}, "
                f"{h_max:g}] m keeps the Courant number in its window at dt = "
                f"{co.dt:g} s on {unmet:,.1f} km2 of the domain; the Courant number "
                "leaves the window there (h_max wins over the floor, h_min over the "
                "cap)",
                CoastmeshWarning,
                stacklevel=2,
            )

        def report(applied: Applied) -> CourantReport:
            return CourantReport(
                dt=co.dt,
                velocity=co.velocity,
                courant_min=co.courant_min,
                courant_max=co.courant_max,
                raised_km2=grid.km2(grid.sea & (floor > applied.floored)),
                lowered_km2=grid.km2(grid.sea & (cap < applied.before)),
                unmet_km2=unmet,
            )

        return TermSizes(
            upper=cap, lower=floor, report=report, history=f"Courant at dt {co.dt:g} s"
        )
