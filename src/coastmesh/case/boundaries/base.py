"""What every open boundary has: a name, a boundary id, a sampling step.

Each kind of open boundary (``[[open_boundaries]] kind = ...``) is a subclass of
:class:`BoundaryConfig` in a module of its own, with its keys and its geometry:
:meth:`BoundaryConfig.line` samples it in the case CRS. The kinds are listed
once, in :data:`coastmesh.case.boundaries.BOUNDARY_KINDS`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case import schema
from coastmesh.case.schema import key
from coastmesh.geometry import reproject_points

__all__ = ["LONLAT", "BoundaryConfig"]

#: Loxodromes and great circles are given in longitude and latitude on WGS84.
LONLAT = CRS.from_epsg(4326)


@dataclass(frozen=True)
class BoundaryConfig:
    """One ``[[open_boundaries]]`` entry (or ``[[cuts]]`` in a global case).

    A base class: a boundary is one of the kinds in
    :data:`~coastmesh.case.boundaries.BOUNDARY_KINDS`, each with its own keys.
    ``physical_id`` is ``id`` in the file.
    """

    #: the value of ``kind`` that selects the class in a case file
    kind: ClassVar[str] = ""

    name: str = key(check=schema.string, doc="the boundary's name")
    physical_id: int = key(
        name="id",
        check=schema.integer(1),
        doc="its boundary id, unique among shoreline sets and boundaries",
    )
    spacing: float | None = key(
        None,
        check=schema.length(),
        unit="length",
        default_doc="`min(1 km, h_max / 4)`",
        doc="the sampling step of the line before meshing",
    )

    def line(self, crs: CRS, spacing: float) -> NDArray[np.float64]:
        """Return the boundary's points in ``crs``, about ``spacing`` metres apart.

        Raises
        ------
        ConfigError
            If the line cannot be drawn (its end is never reached, say).
        InputDataError
            If a file the boundary names cannot be read.
        """
        return reproject_points(self.lonlat(spacing), LONLAT, crs)

    def lonlat(self, spacing: float) -> NDArray[np.float64]:
        """Return the boundary's points in longitude and latitude on WGS84."""
        raise NotImplementedError(f"{type(self).__name__} draws no line")
