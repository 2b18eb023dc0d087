"""CF conventions for the netCDF writers: the grid mapping and coordinate attributes.

The raster writer (:mod:`coastmesh.io.rasters.raster`) and the UGRID mesh writer
(:mod:`coastmesh.io.meshes.ugrid`) describe their CRS the same way: a CF grid mapping
variable from :meth:`pyproj.CRS.to_cf`, with the WKT again as ``spatial_ref`` for
GDAL, and coordinates with CF standard names and units. The UGRID reader turns
such a grid mapping back into a CRS.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from pyproj import CRS
from pyproj.exceptions import CRSError

from coastmesh.errors import InputDataError

__all__ = ["axis_attrs", "crs_from_grid_mapping", "grid_mapping_attrs"]

_GEOGRAPHIC = {
    "X": {"standard_name": "longitude", "units": "degrees_east"},
    "Y": {"standard_name": "latitude", "units": "degrees_north"},
}


def grid_mapping_attrs(crs: CRS) -> dict[str, Any]:
    """Return the attributes of a CF grid mapping variable for ``crs``.

    Parameters
    ----------
    crs : pyproj.CRS
        The CRS.

    Returns
    -------
    dict
        :meth:`pyproj.CRS.to_cf` (with ``crs_wkt``), ``spatial_ref`` (the same
        WKT, which GDAL reads) and ``epsg`` when the CRS has an EPSG code.

    Examples
    --------
    >>> attrs = grid_mapping_attrs(CRS.from_epsg(32630))
    >>> attrs["grid_mapping_name"], int(attrs["epsg"])
    ('transverse_mercator', 32630)
    """
    attrs = dict(crs.to_cf())
    attrs["spatial_ref"] = attrs["crs_wkt"]
    epsg = crs.to_epsg()
    if epsg is not None:
        attrs["epsg"] = np.int32(epsg)
    return attrs


def axis_attrs(crs: CRS | None, axis: str) -> dict[str, str]:
    """Return the CF standard name and units of the x or y coordinate in ``crs``.

    Parameters
    ----------
    crs : pyproj.CRS or None
        The CRS of the coordinates; None gives no attributes.
    axis : {"X", "Y"}
        The coordinate.

    Returns
    -------
    dict of str to str
        ``longitude``/``latitude`` in degrees for a geographic CRS, else
        ``projection_x_coordinate``/``projection_y_coordinate`` with the CRS's
        unit (``m`` for metres).

    Examples
    --------
    >>> axis_attrs(CRS.from_epsg(4326), "Y")
    {'standard_name': 'latitude', 'units': 'degrees_north'}
    >>> axis_attrs(CRS.from_epsg(32630), "X")
    {'standard_name': 'projection_x_coordinate', 'units': 'm'}
    """
    if crs is None:
        return {}
    if crs.is_geographic:
        return dict(_GEOGRAPHIC[axis])
    attrs = {"standard_name": f"projection_{axis.lower()}_coordinate"}
    unit = crs.axis_info[0].unit_name if crs.axis_info else ""
    if unit:
        attrs["units"] = "m" if unit in ("metre", "meter") else unit
    return attrs


def crs_from_grid_mapping(attrs: Mapping[str, Any], path: str, variable: str) -> CRS:
    """Return the CRS a CF grid mapping variable describes.

    Parameters
    ----------
    attrs : mapping
        The grid mapping variable's attributes (``crs_wkt``, ``spatial_ref`` or
        the CF projection parameters).
    path : str
        The file, for messages.
    variable : str
        The grid mapping variable's name, for messages.

    Returns
    -------
    pyproj.CRS

    Raises
    ------
    InputDataError
        If pyproj cannot make a CRS of the attributes.

    Examples
    --------
    >>> crs_from_grid_mapping(grid_mapping_attrs(CRS.from_epsg(4326)), "m.nc",
    ...                       "crs").to_epsg()
    4326
    """
    try:
        return CRS.from_cf(dict(attrs))
    except CRSError:
        pass
    wkt = attrs.get("crs_wkt") or attrs.get("spatial_ref")
    try:
        return CRS.from_user_input(str(wkt))
    except CRSError as exc:
        raise InputDataError(
            f"grid mapping variable {variable!r} describes no CRS pyproj knows ({exc})",
            path=path,
        ) from None
