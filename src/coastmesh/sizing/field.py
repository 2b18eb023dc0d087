"""A size field of gradations alone: combined by minimum, then limited."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pyproj import CRS

from coastmesh.sizing.bands import BandRunner
from coastmesh.sizing.gradation import Gradation
from coastmesh.sizing.grid import PlaneGrid

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["size_field"]


def size_field(
    bounds: tuple[float, float, float, float],
    gradations: list[Gradation],
    *,
    crs: CRS | str,
    h_max: float,
    cell: float,
    rate: float | None = None,
    runner: BandRunner | None = None,
) -> xr.DataArray:
    """Target edge length on a regular grid covering ``bounds``.

    The gradations alone, combined by minimum, then limited: the size field of
    a chain built in Python. A case's size field has more terms
    (:mod:`coastmesh.case.terms`).

    Parameters
    ----------
    bounds : (minx, miny, maxx, maxy)
        Extent in a projected ``crs`` (metres); the grid nodes cover it.
    gradations : list of Gradation
        Combined by minimum (each grows to ``h_max``), the lines in ``crs``.
    crs : pyproj.CRS or str
        A projected CRS in metres (mesh in a conformal projection).
    h_max : float
        Largest size, metres.
    cell : float
        Grid spacing, metres (> 0).
    rate : float, optional
        Gradation limit: the size grows by at most ``rate`` metres per metre.
    runner : Runner, optional
        Where the distance terms run, in bands of rows
        (:mod:`coastmesh.sizing.bands`); default here. The field is the same.

    Returns
    -------
    xarray.DataArray
        Sizes in metres, dims ``("y", "x")``, 1-D node coordinates, attrs ``crs``
        (WKT), ``units`` and ``history``.

    Examples
    --------
    >>> import numpy as np, shapely
    >>> coast = shapely.LineString([(500_000, 6_500_000), (510_000, 6_500_000)])
    >>> g = Gradation(np.array([coast]), h_min=100.0, d_hold=1_000.0, d_grade=5_000.0)
    >>> f = size_field((495_000, 6_495_000, 515_000, 6_505_000), [g],
    ...                crs="EPSG:32630", h_max=2_000.0, cell=500.0)
    >>> float(f.sel(x=505_000, y=6_500_000)), float(f.max())
    (100.0, 2000.0)
    """
    grid = PlaneGrid.from_bounds(bounds, cell, crs)
    size = grid.graded(gradations, lines_crs=grid.crs, h_max=h_max, runner=runner)
    if rate is not None:
        size = grid.limit(size, rate)
    history = f"coastmesh size_field: {len(gradations)} gradations, h_max={h_max} m"
    if rate is not None:
        history += f", rate={rate}"
    return grid.field(size, history)
