"""Size fields on a grid: several gradations combined by minimum, then limited."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import ConfigError
from coastmesh.sizing.bands import graded_sizes
from coastmesh.sizing.gradation import limit_gradation
from coastmesh.types import Runner

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["Gradation", "grid_axes", "size_field"]


@dataclass(frozen=True, slots=True)
class Gradation:
    """The paper's gradation from one set of lines (all lengths in metres).

    Parameters
    ----------
    lines : ndarray of shapely geometries
        The shoreline set (lines or polygons) the size is graded from.
    h_min : float
        Size at the lines.
    d_hold : float
        Distance over which ``h_min`` is kept.
    d_grade : float
        Distance over which the size then grows linearly to the field's ``h_max``.
    name : str
        For reports.
    """

    lines: NDArray[np.object_]
    h_min: float
    d_hold: float
    d_grade: float
    name: str = "gradation"


def size_field(
    bounds: tuple[float, float, float, float],
    gradations: list[Gradation],
    *,
    crs: CRS | str,
    h_max: float,
    cell: float,
    rate: float | None = None,
    runner: Runner | None = None,
) -> xr.DataArray:
    """Target edge length on a regular grid covering ``bounds``.

    Parameters
    ----------
    bounds : (minx, miny, maxx, maxy)
        Extent in a projected ``crs`` (metres); the grid nodes cover it.
    gradations : list of Gradation
        Combined by minimum (each grows to ``h_max``).
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
    >>> import shapely
    >>> coast = shapely.LineString([(500_000, 6_500_000), (510_000, 6_500_000)])
    >>> g = Gradation(np.array([coast]), h_min=100.0, d_hold=1_000.0, d_grade=5_000.0)
    >>> f = size_field((495_000, 6_495_000, 515_000, 6_505_000), [g],
    ...                crs="EPSG:32630", h_max=2_000.0, cell=500.0)
    >>> float(f.sel(x=505_000, y=6_500_000)), float(f.max())
    (100.0, 2000.0)
    """
    crs = CRS.from_user_input(crs)
    if not crs.is_projected:
        raise ConfigError(
            f"size_field: crs {crs.name!r} is not projected; mesh in metres"
        )
    minx, miny, maxx, maxy = (float(v) for v in bounds)
    if not (maxx > minx and maxy > miny):
        raise ConfigError(f"bounds = {bounds}: need minx < maxx and miny < maxy")
    if not cell > 0:
        raise ConfigError(f"cell = {cell}: must be > 0 metres")
    x, y = grid_axes((minx, miny, maxx, maxy), cell)
    for g in gradations:
        if g.h_min > h_max:
            raise ConfigError(
                f"gradation {g.name!r}: h_min = {g.h_min} > h_max = {h_max}"
            )
    size = graded_sizes(
        x, y, gradations, crs=crs, h_max=h_max, resolution=cell / 4, runner=runner
    )
    if rate is not None:
        size = limit_gradation(size, (cell, cell), rate)
    history = f"coastmesh size_field: {len(gradations)} gradations, h_max={h_max} m"
    if rate is not None:
        history += f", rate={rate}"
    import xarray as xr

    return xr.DataArray(
        size,
        dims=("y", "x"),
        coords={"y": y, "x": x},
        name="size",
        attrs={"crs": crs.to_wkt(), "units": "m", "history": history},
    )


def grid_axes(
    bounds: tuple[float, float, float, float], cell: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the node coordinates ``x``, ``y`` of :func:`size_field`'s grid.

    From the lower-left corner of ``bounds`` every ``cell`` metres, until the
    nodes cover them.

    Examples
    --------
    >>> x, y = grid_axes((0.0, 0.0, 250.0, 100.0), 100.0)
    >>> x.tolist(), y.tolist()
    ([0.0, 100.0, 200.0, 300.0], [0.0, 100.0])
    """
    minx, miny, maxx, maxy = (float(v) for v in bounds)
    nx = int(np.ceil((maxx - minx) / cell)) + 1
    ny = int(np.ceil((maxy - miny) / cell)) + 1
    return minx + cell * np.arange(nx), miny + cell * np.arange(ny)
