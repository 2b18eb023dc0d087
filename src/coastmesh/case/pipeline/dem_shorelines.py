"""``[shorelines] raster = PATH``: the land polygons contoured from a raster.

The raster (or its ``bbox`` window) is read with
:func:`~coastmesh.io.read_raster`, and the land above ``level`` is contoured by
:func:`~coastmesh.geometry.land_from_grid`. The polygons keep the raster's CRS,
and then go through the shoreline sets, PCA and stitching as a vector
shoreline layer does
(:func:`~coastmesh.case.pipeline.shorelines.read_shorelines`).
"""

from __future__ import annotations

import logging
import warnings

import numpy as np
import shapely
from pyproj import CRS

from coastmesh.case.config import CaseConfig
from coastmesh.errors import CoastmeshWarning, InputDataError
from coastmesh.geometry import land_from_grid
from coastmesh.io import read_raster
from coastmesh.types import Features

__all__ = ["NoLandWarning", "read_raster_land"]

logger = logging.getLogger(__name__)


class NoLandWarning(CoastmeshWarning):
    """A shoreline raster has no cell above the level: the case has no land."""


def read_raster_land(config: CaseConfig) -> Features:
    """Contour the land of ``[shorelines] raster`` at ``level``.

    Parameters
    ----------
    config : CaseConfig
        A case whose ``shorelines.raster`` is set.

    Returns
    -------
    Features
        Land polygons in the raster's CRS (or ``shorelines.crs`` if the raster
        declares none), one feature each; none if no cell is above the level.

    Raises
    ------
    InputDataError
        If the raster is missing or unreadable, declares no CRS and
        ``shorelines.crs`` is not set, or its window is less than 2 x 2 cells.

    Warns
    -----
    NoLandWarning
        If no cell is above the level: the case goes on with no shoreline, so
        its domain must be closed by open boundaries alone.
    """
    s = config.shorelines
    if s.raster is None:
        raise ValueError("shorelines.raster is not set")
    source = str(s.raster)
    raster = read_raster(s.raster, bbox=s.bbox)
    wkt = raster.attrs.get("crs")
    if not wkt and s.crs is None:
        raise InputDataError(
            f"the raster declares no CRS; set shorelines.crs in {config.label}",
            path=source,
        )
    crs = CRS.from_user_input(wkt or s.crs)
    if min(raster.shape) < 2:
        raise InputDataError(
            f"{raster.shape[0]} x {raster.shape[1]} cells (rows x columns) read"
            f"{'' if s.bbox is None else f' in bbox {s.bbox}'}; contouring the "
            "coast needs at least 2 x 2",
            path=source,
        )
    land = land_from_grid(
        raster["x"].values,
        raster["y"].values,
        raster.values,
        s.level,
        positive=s.positive,
    )
    if len(land) == 0:
        message = _no_land(raster.values, s.level, s.positive, source)
        warnings.warn(message, NoLandWarning, stacklevel=3)
    logger.info(
        "shorelines: %d land polygons (%d points) contoured at %g m from %s "
        "(%d x %d cells)",
        len(land),
        int(shapely.get_num_coordinates(land).sum()),
        s.level,
        source,
        *raster.shape,
    )
    return Features(land, crs, {}, np.arange(len(land)), source, None)


def _no_land(values: np.ndarray, level: float, positive: str, source: str) -> str:
    valid = values[np.isfinite(values)]
    if valid.size == 0:
        found = "every cell is nodata"
    else:
        found = (
            f"its values are {valid.min():g} to {valid.max():g} (positive {positive})"
        )
    return (
        f"{source}: no land above level = {level:g} m: {found}. The case goes on "
        "with no shoreline, so the open boundaries alone must close the domain"
    )
