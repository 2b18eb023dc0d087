"""``kind = "great_circle"``: the geodesic from ``start`` to ``end`` on WGS84.

The shortest line on the Earth between two points given in longitude and
latitude, sampled every ``spacing``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from coastmesh.case import schema
from coastmesh.case.boundaries.base import BoundaryConfig
from coastmesh.case.schema import key
from coastmesh.geometry import great_circle

__all__ = ["GreatCircleBoundary"]


@dataclass(frozen=True)
class GreatCircleBoundary(BoundaryConfig):
    """``kind = "great_circle"``: the shortest line on the Earth between two points."""

    kind: ClassVar[str] = "great_circle"

    start: tuple[float, float] = key(
        check=schema.point, doc="`[lon, lat]` where it starts", kw_only=True
    )
    end: tuple[float, float] = key(
        check=schema.point, doc="`[lon, lat]` where it ends", kw_only=True
    )

    def lonlat(self, spacing: float) -> NDArray[np.float64]:
        """Sample the geodesic every ``spacing`` metres at most."""
        return great_circle(self.start, self.end, spacing=spacing)
