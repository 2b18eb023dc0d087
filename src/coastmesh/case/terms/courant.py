"""``[mesh_size.courant]``: sizes a model runs at its time step.

The Courant number is ``C = dt (sqrt(g d) + u) / h``, with ``d`` the depth (from
``[mesh_size.bathymetry]``, else ``[bathymetry]``) and ``h`` the size; the size
is kept between ``dt (sqrt(g d) + u) / courant_max`` and
``dt (sqrt(g d) + u) / courant_min``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from coastmesh.case import schema
from coastmesh.case.schema import Check, key
from coastmesh.case.terms.base import SizeTerm

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
