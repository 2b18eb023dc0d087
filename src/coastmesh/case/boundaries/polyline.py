"""``kind = "polyline"``: a line given point by point, or read from a file.

Exactly one of ``points`` (in the case CRS) and ``path`` (with ``layer``): a
vector file holding one line, in its own CRS. The line keeps its vertices; as
every boundary, it is resampled to the local size before meshing.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import shapely
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.case import schema
from coastmesh.case.boundaries.base import BoundaryConfig
from coastmesh.case.schema import Check, key
from coastmesh.errors import InputDataError
from coastmesh.geometry import reproject
from coastmesh.io import read_features

__all__ = ["PolylineBoundary"]


@dataclass(frozen=True)
class PolylineBoundary(BoundaryConfig):
    """``kind = "polyline"``: ``points`` in the case CRS, or a file's one line."""

    kind: ClassVar[str] = "polyline"

    points: tuple[tuple[float, float], ...] | None = key(
        None,
        check=schema.points,
        doc="`[[x, y], ...]` in the case CRS; or `path`",
        kw_only=True,
    )
    path: Path | None = key(
        None,
        check=schema.path,
        path=True,
        doc="a vector file holding one line (in any CRS)",
        kw_only=True,
    )
    layer: str | None = key(
        None,
        check=schema.string,
        default_doc="the only layer",
        doc="the file's layer",
        kw_only=True,
    )

    def _validate(self, c: Check) -> PolylineBoundary:
        if (self.points is None) == (self.path is None):
            raise c.error("points", "give exactly one of points and path")
        return self

    def line(self, crs: CRS, spacing: float) -> NDArray[np.float64]:
        """Return the points as given (in ``crs``), or the file's line in ``crs``.

        ``spacing`` is not used: the line keeps its own vertices, and is
        resampled to the size field before meshing, as every boundary is.
        """
        if self.points is not None:
            return np.array(self.points, dtype=float)
        assert self.path is not None  # _validate: exactly one of points and path
        features = read_features(self.path, layer=self.layer)
        lines = features.geometry[shapely.get_dimensions(features.geometry) == 1]
        parts = shapely.get_parts(lines)
        if len(parts) != 1:
            raise InputDataError(
                f"{self.path} must hold exactly one line; it has {len(parts)}",
                path=str(self.path),
            )
        line = parts[0]
        if features.crs is not None:
            line = reproject(line, features.crs, crs)
        return np.asarray(shapely.get_coordinates(line), dtype=np.float64)
