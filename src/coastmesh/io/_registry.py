"""File formats by extension.

Readers let GDAL detect the format of an input file; writers pick the GDAL driver
(or the plot format) from the output file's extension through this registry.
"""

from __future__ import annotations

import os
from pathlib import Path

from coastmesh.errors import FormatError

__all__ = [
    "PLOT_FORMATS",
    "RASTER_DRIVERS",
    "VECTOR_DRIVERS",
    "plot_format",
    "raster_driver",
    "vector_driver",
]

VECTOR_DRIVERS: dict[str, str] = {
    ".gpkg": "GPKG",
    ".shp": "ESRI Shapefile",
    ".geojson": "GeoJSON",
    ".json": "GeoJSON",
    ".fgb": "FlatGeobuf",
}
RASTER_DRIVERS: dict[str, str] = {
    ".tif": "GTiff",
    ".tiff": "GTiff",
    ".nc": "netCDF",
}
PLOT_FORMATS: dict[str, str] = {
    ".png": "png",
    ".pdf": "pdf",
    ".svg": "svg",
    ".jpg": "jpeg",
    ".jpeg": "jpeg",
}


def vector_driver(path: str | os.PathLike[str]) -> str:
    """Return the GDAL vector driver for writing ``path``, from its extension.

    Parameters
    ----------
    path : str or path-like
        The output file.

    Returns
    -------
    str
        A GDAL driver name such as ``"GPKG"``.

    Raises
    ------
    FormatError
        If the extension is not a known vector format; the message lists them.

    Examples
    --------
    >>> vector_driver("coast.gpkg")
    'GPKG'
    """
    return _lookup(path, VECTOR_DRIVERS, "vector")


def raster_driver(path: str | os.PathLike[str]) -> str:
    """Return the GDAL raster driver for writing ``path``, from its extension.

    Parameters
    ----------
    path : str or path-like
        The output file.

    Returns
    -------
    str
        ``"GTiff"`` or ``"netCDF"``.

    Raises
    ------
    FormatError
        If the extension is not a known raster format; the message lists them.

    Examples
    --------
    >>> raster_driver("depth.nc")
    'netCDF'
    """
    return _lookup(path, RASTER_DRIVERS, "raster")


def plot_format(path: str | os.PathLike[str]) -> str:
    """Return the matplotlib format for saving a figure to ``path``.

    Parameters
    ----------
    path : str or path-like
        The image file.

    Returns
    -------
    str
        A matplotlib format name such as ``"png"``.

    Raises
    ------
    FormatError
        If the extension is not a known image format; the message lists them.

    Examples
    --------
    >>> plot_format("overlay.PNG")
    'png'
    """
    return _lookup(path, PLOT_FORMATS, "plot")


def _lookup(path: str | os.PathLike[str], table: dict[str, str], kind: str) -> str:
    suffix = Path(path).suffix.lower()
    try:
        return table[suffix]
    except KeyError:
        known = ", ".join(sorted(table))
        shown = f"extension {suffix!r}" if suffix else "no extension"
        raise FormatError(
            f"{os.fspath(path)}: unknown {kind} format ({shown}); pick one of {known}"
        ) from None
